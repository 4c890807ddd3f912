//! One run in N space dimensions: the state, the scheme stepping it, and what dense output and
//! a rewind keep of the steps around the communication time. [`Simulation`](super::Simulation)
//! holds a 2D or a 3D run ([`Runs`]) and drives either through the same code: what differs
//! between the dimensions is the [`Space`] of `Const<N>` (the scene's state and outputs, the
//! scheme built for them), one impl per dimension, resolved at compile time, so the 2D steps
//! are the same machine code as before the dimension became a parameter.

use super::SimError;
use crate::boundary::plate::Motion;
use crate::boundary::wall::Wall;
use crate::budget::Budget;
use crate::config::ConfigError;
use crate::dim::{Const, Vector};
use crate::profile::Profile;
use crate::scene::{Inputs, Outputs, Scene, SceneConfig};
use crate::scheme::params::Params;
use crate::scheme::{Scheme, Timings};
use crate::state::State;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// What a dimension supplies to a run: the scene's initial state and outputs in it, the
/// scheme's constants and the scheme itself.
pub trait Space<const N: usize> {
    /// The scene's initial state in N dimensions with the model's rest conformation, or why
    /// the scene has none.
    fn initial_state(scene: &dyn Scene, eff: &SceneConfig) -> Result<State<N>, SimError>;
    /// The scheme's constants for the effective configuration.
    fn params(eff: &SceneConfig) -> Params<N>;
    /// The scheme for the walls `walls`.
    fn scheme(
        eff: &SceneConfig,
        params: &Params<N>,
        walls: &[Wall<N>],
    ) -> Result<Box<dyn Scheme<N>>, SimError>;
    /// The outputs of a state.
    fn outputs(scene: &dyn Scene, st: &State<N>, eff: &SceneConfig) -> Outputs;
    /// The scene's hook before every step (the jet's inflow).
    fn before_step(scene: &dyn Scene, eff: &SceneConfig, st: &mut State<N>);
    /// The wall model `auto` means on a straight wall in this dimension.
    fn paper_wall_model(eff: &SceneConfig) -> crate::boundary::Model;
}

impl Space<2> for Const<2> {
    fn initial_state(scene: &dyn Scene, eff: &SceneConfig) -> Result<State, SimError> {
        let rest = crate::scheme::rest_conformation(&eff.fluid);
        Ok(scene.initial_state(eff, rest))
    }
    fn params(eff: &SceneConfig) -> Params {
        eff.scheme_params()
    }
    fn scheme(
        eff: &SceneConfig,
        params: &Params,
        walls: &[Wall],
    ) -> Result<Box<dyn Scheme>, SimError> {
        Ok(crate::scheme::build(
            eff.scheme,
            &eff.fluid,
            &eff.numerics,
            params.clone(),
            walls,
        ))
    }
    fn outputs(_: &dyn Scene, st: &State, eff: &SceneConfig) -> Outputs {
        eff.outputs_2d(st)
    }
    fn before_step(scene: &dyn Scene, eff: &SceneConfig, st: &mut State) {
        scene.before_step(eff, st)
    }
    fn paper_wall_model(eff: &SceneConfig) -> crate::boundary::Model {
        eff.scheme.paper_wall_model()
    }
}

impl Space<3> for Const<3> {
    fn initial_state(scene: &dyn Scene, eff: &SceneConfig) -> Result<State<3>, SimError> {
        let rest = crate::scheme::rest_conformation_in::<3>(&eff.fluid);
        scene.initial_state_3d(eff, rest).ok_or_else(|| {
            SimError::Config(ConfigError::Inconsistent(format!(
                "dimension = 3: the scene '{}' has no 3D form",
                eff.scene
            )))
        })
    }
    fn params(eff: &SceneConfig) -> Params<3> {
        eff.scheme_params_in::<3>()
    }
    fn scheme(
        eff: &SceneConfig,
        params: &Params<3>,
        walls: &[Wall<3>],
    ) -> Result<Box<dyn Scheme<3>>, SimError> {
        crate::scheme::build_3d(eff.scheme, &eff.fluid, &eff.numerics, params.clone(), walls)
            .map_err(|e| SimError::Config(ConfigError::Inconsistent(format!("dimension = 3: {e}"))))
    }
    fn outputs(scene: &dyn Scene, st: &State<3>, eff: &SceneConfig) -> Outputs {
        scene.outputs_3d(st, eff)
    }
    fn before_step(scene: &dyn Scene, eff: &SceneConfig, st: &mut State<3>) {
        scene.before_step_3d(eff, st)
    }
    /// Dummy particles, the one model of the weakly compressible schemes built for a plane;
    /// the incompressible scheme's own mirror particles (a reflection across any plane).
    fn paper_wall_model(eff: &SceneConfig) -> crate::boundary::Model {
        if eff.scheme.is_incompressible() {
            eff.scheme.paper_wall_model()
        } else {
            crate::boundary::Model::Dummy
        }
    }
}

/// A run in N dimensions (see the module documentation).
pub struct Run<const N: usize> {
    pub state: State<N>,
    /// The scheme's constants, resolved once from the effective configuration with the
    /// inputs' start values (the automatic sound speed of the jet follows its start speed).
    pub params: Params<N>,
    pub scheme: Box<dyn Scheme<N>>,
    /// Time and outputs of the internal state before the last step, for interpolating the
    /// outputs at the communication time (None before the first step).
    pub prev: Option<(f64, Outputs)>,
    /// In dense-output mode, the state before the last internal step (at or before the
    /// communication time), to go back to when an input changes there.
    pub rewind: Option<State<N>>,
    /// Timers of the work around the scheme's steps (off unless `Simulation::set_profiling`).
    pub profile: Profile,
}

/// A 2D or a 3D run.
pub enum Runs {
    D2(Run<2>),
    D3(Run<3>),
}

/// What the stepping loop reads of the simulation around it.
pub struct Drive<'a> {
    pub scene: &'static dyn Scene,
    pub eff: &'a SceneConfig,
    /// Whether steps land exactly on communication points.
    pub exact: bool,
    pub stop: Option<&'a Arc<AtomicBool>>,
}

/// What a saved state holds besides the configuration (see `Simulation::save_state`).
#[derive(Serialize, Deserialize)]
pub struct Saved<const N: usize> {
    pub state: State<N>,
    pub t_comm: f64,
    pub prev: Option<(f64, Outputs)>,
    pub exact: bool,
    pub rewind: Option<State<N>>,
    /// The inputs in force (the configuration holds their start values).
    pub inputs: Inputs,
    pub inputs_time: f64,
}

/// Put the inputs of `cfg` in force in `st`: a plate whose motion is the input moves at
/// `plate_velocity`; the scene reads its own inputs from the configuration.
pub fn apply_plate_input<const N: usize>(cfg: &SceneConfig, st: &mut State<N>) {
    if let Some(plate) = st.plate_mut() {
        if plate.motion == Motion::Input {
            plate.velocity = cfg.plate.plate_velocity;
        }
    }
}

impl<const N: usize> Run<N>
where
    Const<N>: Space<N>,
{
    /// The initial run of the effective configuration `eff`, every wall checked against the
    /// wall model `wall_boundary` asks for ([`crate::boundary::resolve`]).
    pub fn new(scene: &'static dyn Scene, eff: &SceneConfig) -> Result<Self, SimError> {
        let mut state = <Const<N> as Space<N>>::initial_state(scene, eff)?;
        apply_plate_input(eff, &mut state);
        let params = <Const<N> as Space<N>>::params(eff);
        let paper = <Const<N> as Space<N>>::paper_wall_model(eff);
        for w in &state.walls {
            crate::boundary::resolve(params.wall_boundary, paper, w)
                .map_err(ConfigError::Inconsistent)?;
        }
        let scheme = <Const<N> as Space<N>>::scheme(eff, &params, &state.walls)?;
        Ok(Self {
            state,
            params,
            scheme,
            prev: None,
            rewind: None,
            profile: Profile::default(),
        })
    }

    /// A scheme built for the current state's walls, with no caches: for a state that replaced
    /// the one the scheme stepped (restored, or rewound by an input change).
    pub fn refresh_scheme(&mut self, eff: &SceneConfig) -> Result<(), SimError> {
        self.scheme = <Const<N> as Space<N>>::scheme(eff, &self.params, &self.state.walls)?;
        self.scheme.set_profiling(self.profile.start().is_some());
        Ok(())
    }

    /// The outputs of the current state.
    pub fn outputs_now(&self, d: &Drive) -> Outputs {
        <Const<N> as Space<N>>::outputs(d.scene, &self.state, d.eff)
    }

    /// The outputs at the communication time `t_comm`: linear interpolation between the
    /// internal states just before and at or after it (`time_step` and `particle_count` are
    /// the current ones).
    pub fn outputs_at(&self, d: &Drive, t_comm: f64) -> Outputs {
        let now = self.outputs_now(d);
        match self.prev {
            Some((tp, before)) if self.state.time > t_comm && tp <= t_comm => {
                let w = (t_comm - tp) / (self.state.time - tp);
                let (a, b) = (before.values(), now.values());
                let mixed_values: Vec<f64> =
                    a.iter().zip(&b).map(|(a, b)| a + w * (b - a)).collect();
                let mut mixed = now;
                mixed.set_values(&mixed_values);
                mixed.shared.time_step = now.shared.time_step;
                mixed.shared.particle_count = now.shared.particle_count;
                mixed
            }
            _ => now,
        }
    }

    /// Step to `t_end` (see `Simulation::advance_within`), moving `t_comm` as the simulation's
    /// communication time moves.
    pub fn advance(
        &mut self,
        d: &Drive,
        t_end: f64,
        budget: &Budget,
        t_comm: &mut f64,
    ) -> Result<(), SimError> {
        let mut last_before: Option<State<N>> = None;
        let (started, mut taken) = (std::time::Instant::now(), 0u64);
        while self.state.time < t_end {
            let (time, step) = (self.state.time, self.state.step);
            let stop = if d.stop.is_some_and(|f| f.load(Ordering::Relaxed)) {
                Some(SimError::Interrupted { time, step })
            } else {
                budget
                    .exceeded(taken, started)
                    .map(|spent| SimError::OverBudget { time, step, spent })
            };
            if let Some(err) = stop {
                *t_comm = t_comm.max(self.state.time);
                if let Some(b) = last_before {
                    self.prev = Some((b.time, <Const<N> as Space<N>>::outputs(d.scene, &b, d.eff)));
                }
                self.rewind = None;
                return Err(err);
            }
            taken += 1;
            let t_begin = self.profile.start();
            // The state before the step, into the last step's copy's allocations.
            let mut before = last_before
                .take()
                .unwrap_or_else(|| State::new(Default::default(), Vec::new(), None));
            copy_state(&mut self.state, &mut before);
            let max_dt = if d.exact {
                t_end - self.state.time
            } else {
                f64::INFINITY
            };
            <Const<N> as Space<N>>::before_step(d.scene, d.eff, &mut self.state);
            let t = self.profile.lap(t_begin, "state copy, scene hook", false);
            match self.scheme.step(&mut self.state, max_dt) {
                Ok(dt) => {
                    self.profile.lap(t, "scheme step", false);
                    self.state.step += 1;
                    self.state.time = if dt >= max_dt {
                        t_end
                    } else {
                        self.state.time + dt
                    };
                    let t = self.state.time;
                    for wall in &mut self.state.walls {
                        wall.advance(t, dt);
                    }
                    last_before = Some(before);
                    self.profile.step(t_begin);
                }
                Err(cause) => {
                    let err = SimError::Breakdown {
                        time: before.time,
                        step: before.step + 1,
                        cause,
                    };
                    self.state = before;
                    *t_comm = t_comm.max(self.state.time);
                    self.prev = None;
                    self.rewind = None;
                    return Err(err);
                }
            }
        }
        if let Some(b) = last_before {
            self.prev = Some((b.time, <Const<N> as Space<N>>::outputs(d.scene, &b, d.eff)));
            self.rewind = (!d.exact).then_some(b);
        }
        *t_comm = t_end;
        Ok(())
    }

    /// Turn the per-pass timers of the steps on or off (see [`crate::profile`]).
    pub fn set_profiling(&mut self, on: bool) {
        self.profile.enable(on);
        self.scheme.set_profiling(on);
    }

    /// Where the time of the steps went since profiling was turned on: the scheme's passes and
    /// the work around them (the copy of the state kept for interpolation, the scene's hook),
    /// the whole steps as the total. Empty while profiling is off.
    pub fn timings(&self) -> Timings {
        let around = self.profile.timings();
        let mut t = self.scheme.timings();
        // What the scheme's own parts leave of its steps (the bookkeeping between its timed
        // parts), counted as serial: unaccounted time is not known to spread over the threads.
        if let Some(step) = around.parts.iter().find(|p| p.name == "scheme step") {
            let wall = step.wall - t.parts.iter().map(|p| p.wall).sum::<f64>();
            let cpu = step.cpu - t.parts.iter().map(|p| p.cpu).sum::<f64>();
            t.add("scheme step, not timed", true, wall.max(0.0), cpu.max(0.0));
        }
        for p in around.parts.iter().filter(|p| p.name != "scheme step") {
            t.add(p.name, p.serial, p.wall, p.cpu);
        }
        t.total = around.total;
        t.total_cpu = around.total_cpu;
        t.steps = around.steps;
        t
    }

    /// Total momentum of the fluid [kg m/s, per m depth in 2D].
    pub fn fluid_momentum(&self) -> Vector<N> {
        let f = &self.state.fluid;
        f.v.iter().fold(Vector::zeros(), |s, v| s + v) * f.mass
    }
}

/// `dst` becomes a copy of `src` (which is left as it was): the per-particle arrays (fluid,
/// plate load, pressure) copied on all threads into `dst`'s kept allocations, the rest (walls,
/// scene data: a few hundred bytes) cloned.
fn copy_state<const N: usize>(src: &mut State<N>, dst: &mut State<N>) {
    use crate::particles::assign_par;
    use std::mem::take;
    let (fluid, load, pressure) = (
        take(&mut src.fluid),
        take(&mut src.plate_load),
        take(&mut src.pressure),
    );
    let (mut f, mut l, mut p) = (
        take(&mut dst.fluid),
        take(&mut dst.plate_load),
        take(&mut dst.pressure),
    );
    dst.clone_from(src);
    f.assign_par(&fluid);
    assign_par(&mut l, &load);
    assign_par(&mut p, &pressure);
    (src.fluid, src.plate_load, src.pressure) = (fluid, load, pressure);
    (dst.fluid, dst.plate_load, dst.pressure) = (f, l, p);
}
