//! A simulation: the state, the scene and the scheme chosen for it, its own thread pool, and
//! `advance_to` with adaptive sub-steps.
//!
//! **Thread pool.** Every step runs inside a rayon pool the simulation owns (`threads`, 0 = the
//! `RAYON_NUM_THREADS` environment variable or one thread per core). A step has about 25 parallel
//! regions; entered from a thread outside the pool (a CLI's main thread, an FMU importer's
//! thread) each of them is handed over to the pool and waited for, which cost 14-26 % of a
//! profile. Inside `install` the calling thread is a pool worker and joins the work. Results do
//! not depend on the number of threads (every sum is a gather in a fixed order).
//!
//! **Communication points.** Without inputs, internal steps are the scheme's own and never
//! shortened: the outputs at a communication point are interpolated between the two internal
//! states around it (dense output), so they agree to round-off for any communication step. Once an
//! input has changed, the steps land exactly on every communication point instead (the last one
//! shortened), so that an input set at a communication point acts from exactly that time; if the
//! solver had already stepped past it, it goes back to the state before that step first.

use crate::boundary::plate::Motion;
use crate::budget::Budget;
use crate::config::{ConfigError, PlateCoupling};
use crate::diagnostics::pressure_roughness;
use crate::kernel::CubicSpline;
use crate::profile::Profile;
use crate::scene::{Inputs, Outputs, Scene, SceneConfig};
use crate::scheme::params::Params;
use crate::scheme::{Scheme, Timings};
use crate::state::State;
use crate::Vec2;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use thiserror::Error;

/// Why a simulation could not be built or could not go on.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum SimError {
    #[error(transparent)]
    Config(#[from] ConfigError),
    #[error("numerical breakdown at t = {time:.6e} s (step {step}): {cause}")]
    Breakdown { time: f64, step: u64, cause: String },
    #[error("invalid request: {0}")]
    Request(String),
    #[error("saved state could not be restored: {0}")]
    State(String),
    #[error("interrupted at t = {time:.6e} s (step {step})")]
    Interrupted { time: f64, step: u64 },
    /// [`Simulation::advance_within`] stopped before a step that would have gone over its
    /// [`Budget`]; the state is the last step's, as after an interruption.
    #[error("stopped at t = {time:.6e} s (step {step}) after {spent}, the budget of one call")]
    OverBudget { time: f64, step: u64, spent: String },
    /// An input outside the range the run was set up for (`max_plate_speed`,
    /// `max_jet_velocity`): refused before any work, nothing changed. The message names the
    /// input, its value and the parameter to raise.
    #[error("{0}")]
    InputOutOfRange(String),
}

/// What a saved state holds besides the configuration (see [`Simulation::save_state`]).
#[derive(serde::Serialize, serde::Deserialize)]
struct Saved {
    state: State,
    t_comm: f64,
    prev: Option<(f64, Outputs)>,
    exact: bool,
    rewind: Option<State>,
    /// The inputs in force (the configuration holds their start values).
    inputs: Inputs,
    inputs_time: f64,
}

/// A running simulation.
pub struct Simulation {
    cfg: SceneConfig,
    /// The configuration the solver runs: the scene's own physics over `cfg`'s numerics
    /// ([`Scene::effective_config`]; equal to `cfg` for the drop), with the inputs in force.
    eff: SceneConfig,
    scene: &'static dyn Scene,
    state: State,
    /// The scheme's constants, resolved once from the effective configuration with the
    /// inputs' start values (the automatic sound speed of the jet follows its start speed).
    params: Params,
    scheme: Box<dyn Scheme>,
    elastic: bool,
    pool: Arc<rayon::ThreadPool>,
    /// The communication time: where the caller asked to be. In dense-output mode the solver's
    /// own state (`state.time`) is at or just past it.
    t_comm: f64,
    /// Time and outputs of the internal state before the last step, for interpolating the
    /// outputs at `t_comm` (None before the first step).
    prev: Option<(f64, Outputs)>,
    /// Whether steps land exactly on communication points (once an input has changed).
    exact: bool,
    /// In dense-output mode, the state before the last internal step (at or before `t_comm`),
    /// to go back to when an input changes at `t_comm`.
    rewind: Option<State>,
    /// Checked before every step: when it is set, `advance_to` stops there (see
    /// [`Simulation::set_stop_flag`]).
    stop: Option<Arc<AtomicBool>>,
    /// When the inputs in force were set (the communication time then): under
    /// `plate_coupling = position` the plate's target `plate_position + plate_velocity (t -
    /// inputs_time)` is extrapolated from it.
    inputs_time: f64,
    /// Timers of the work around the scheme's steps (off unless [`Simulation::set_profiling`]).
    profile: Profile,
}

/// Inputs a scene can take: a plate velocity only where there is a plate to move.
fn check_inputs(scene: &dyn Scene, cfg: &SceneConfig) -> Result<(), ConfigError> {
    let v = cfg.plate.plate_velocity;
    if v != 0.0 && !scene.has_moving_plate() {
        return Err(ConfigError::Inconsistent(format!(
            "plate_velocity = {v} m/s: this scene has no free-standing plate to move (only {} \
             has)",
            crate::scene::moving_plate_scenes()
        )));
    }
    Ok(())
}

/// Whether the inputs of `now` lie within the range a run set up with `setup` (the
/// configuration it was built from, whose limits and start values resolved the sound speed) can
/// take: the plate's speed within `max_plate_speed`, and the scene's own
/// ([`Scene::check_input_range`]). The message names the input, its value and the parameter to
/// raise.
fn check_input_range(
    scene: &dyn Scene,
    setup: &SceneConfig,
    now: &SceneConfig,
) -> Result<(), String> {
    let (v, max) = (now.plate.plate_velocity, setup.plate.max_plate_speed);
    if scene.has_moving_plate() && v.abs() > max {
        return Err(plate_speed_refusal(
            &format!("plate_velocity = {v} m/s"),
            v,
            max,
        ));
    }
    scene.check_input_range(setup, now)
}

/// "plate_velocity = -5 m/s is beyond max_plate_speed = 1 m/s ...".
fn plate_speed_refusal(what: &str, speed: f64, max: f64) -> String {
    format!(
        "{what} is beyond max_plate_speed = {max} m/s, the largest plate speed this run was set up for \
         (its automatic sound speed covers a plate driven into the fluid that fast): set max_plate_speed \
         to at least {} m/s before initialization",
        speed.abs()
    )
}

/// Put the inputs of `cfg` in force in `st`: a plate whose motion is the input moves at
/// `plate_velocity`; the scene reads its own inputs from the configuration.
fn apply_plate_input(cfg: &SceneConfig, st: &mut State) {
    if let Some(plate) = st.plate_mut() {
        if plate.motion == Motion::Input {
            plate.velocity = cfg.plate.plate_velocity;
        }
    }
}

/// Whether every wall of the initial state takes the wall model `wall_boundary` asks for under
/// `scheme` ([`crate::boundary::resolve`]).
fn check_wall_models(
    scheme: crate::scheme::SchemeKind,
    choice: crate::config::WallBoundary,
    st: &State,
) -> Result<(), ConfigError> {
    let paper = scheme.paper_wall_model();
    for w in &st.walls {
        crate::boundary::resolve(choice, paper, w).map_err(ConfigError::Inconsistent)?;
    }
    Ok(())
}

fn thread_pool(cfg: &SceneConfig) -> Result<Arc<rayon::ThreadPool>, SimError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(cfg.numerics.threads as usize)
        .thread_name(|i| format!("viscosph-{i}"))
        .build()
        .map(Arc::new)
        .map_err(|e| {
            SimError::Request(format!(
                "cannot start {} threads: {e}",
                cfg.numerics.threads
            ))
        })
}

impl Simulation {
    /// Check a configuration: the parameter table's rules and the scene's own.
    pub fn validate(cfg: &SceneConfig) -> Result<(), SimError> {
        cfg.validate()?;
        let scene = cfg.scene_def();
        scene.validate(&scene.effective_config(cfg))?;
        check_inputs(scene, cfg)?;
        check_input_range(scene, cfg, cfg).map_err(ConfigError::Inconsistent)?;
        Ok(())
    }

    /// Validate the configuration and build the initial state.
    pub fn new(cfg: SceneConfig) -> Result<Self, SimError> {
        let pool = thread_pool(&cfg)?;
        Self::with_pool(cfg, pool)
    }

    fn with_pool(cfg: SceneConfig, pool: Arc<rayon::ThreadPool>) -> Result<Self, SimError> {
        Self::validate(&cfg)?;
        // One way down: the scene makes the configuration the solver runs and its initial
        // state, the configuration resolves the scheme's constants, the scheme is built on them.
        let scene = cfg.scene_def();
        let eff = scene.effective_config(&cfg);
        let rest = crate::scheme::rest_conformation(&eff.fluid);
        let mut state = scene.initial_state(&eff, rest);
        apply_plate_input(&eff, &mut state);
        let params = eff.scheme_params();
        check_wall_models(eff.scheme, params.wall_boundary, &state)?;
        let scheme = crate::scheme::build(
            eff.scheme,
            &eff.fluid,
            &eff.numerics,
            params.clone(),
            &state.walls,
        );
        // A plate steered to a position moves at a velocity that depends on the length of the
        // communication step: the steps land on every communication point.
        let steered =
            scene.has_moving_plate() && eff.plate.plate_coupling == PlateCoupling::Position;
        Ok(Self {
            cfg,
            eff,
            scene,
            state,
            params,
            scheme,
            elastic: rest.is_some(),
            pool,
            t_comm: 0.0,
            prev: None,
            exact: steered,
            rewind: None,
            stop: None,
            inputs_time: 0.0,
            profile: Profile::default(),
        })
    }

    /// The configuration as given (its inputs are their start values).
    pub fn config(&self) -> &SceneConfig {
        &self.cfg
    }
    /// The configuration the solver runs: for the elliptical drop, the scene's own physics
    /// (radius, density, viscosity, sound speed...) over the given numerics; its inputs are
    /// those in force.
    pub fn effective_config(&self) -> &SceneConfig {
        &self.eff
    }
    /// The scene being simulated.
    pub fn scene(&self) -> &'static dyn Scene {
        self.scene
    }
    pub fn state(&self) -> &State {
        &self.state
    }
    /// The communication time: the `t_end` of the last successful [`Simulation::advance_to`]
    /// (or, after a breakdown, the time of the last good state). In dense-output mode the
    /// particles themselves are at `state().time`, which may be up to one internal step later.
    pub fn time(&self) -> f64 {
        self.t_comm
    }
    /// Whether the model carries a conformation tensor.
    pub fn is_elastic(&self) -> bool {
        self.elastic
    }
    /// Number of threads of the simulation's own pool.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }
    /// The inputs in force.
    pub fn inputs(&self) -> Inputs {
        self.eff.inputs()
    }

    /// A flag (set by a signal handler, say) that stops [`Simulation::advance_to`] before its
    /// next step with [`SimError::Interrupted`]; the state is then the last step's, and the
    /// communication time moves to it.
    pub fn set_stop_flag(&mut self, flag: Option<Arc<AtomicBool>>) {
        self.stop = flag;
    }

    /// Set the inputs from the communication time on. A change switches to exact landing on
    /// communication points (see the module documentation).
    pub fn set_inputs(&mut self, inputs: Inputs) -> Result<(), SimError> {
        let request = |e: ConfigError| SimError::Request(e.to_string());
        let mut next = self.eff.clone();
        next.apply_inputs(&inputs).map_err(request)?;
        check_inputs(self.scene, &next).map_err(request)?;
        check_input_range(self.scene, &self.cfg, &next).map_err(SimError::InputOutOfRange)?;
        if next.inputs() == self.eff.inputs() {
            return Ok(());
        }
        if !self.exact && self.state.time > self.t_comm {
            // The last internal step went past t_comm with the old inputs: go back to the state
            // before it and land exactly on t_comm.
            if let Some(before) = self.rewind.take() {
                self.state = before;
                // The scheme's neighbour lists and wall particles belong to the state after
                // the step (walls grow as the fluid spreads): start them afresh.
                self.scheme = self.fresh_scheme();
            }
            self.exact = true;
            let t = self.t_comm;
            self.advance_to(t)?;
        }
        self.exact = true;
        self.eff = next;
        self.inputs_time = self.t_comm;
        apply_plate_input(&self.eff, &mut self.state);
        Ok(())
    }

    /// Give wall `wall` (an index into `state().walls`) the motion `motion` from the
    /// communication time on; a prescribed motion takes its velocity at that time. The input
    /// `plate_velocity` then moves the wall only if `motion` is [`Motion::Input`] and the wall
    /// is the scene's plate.
    pub fn set_wall_motion(&mut self, wall: usize, motion: Motion) -> Result<(), SimError> {
        let n = self.state.walls.len();
        let t = self.t_comm;
        let w = self
            .state
            .walls
            .get_mut(wall)
            .ok_or_else(|| SimError::Request(format!("no wall {wall} (this scene has {n} walls)")))?
            .plate_mut()
            .ok_or_else(|| {
                SimError::Request(format!("wall {wall} is not straight: it is fixed"))
            })?;
        w.motion = motion;
        if let Motion::Prescribed(p) = motion {
            w.velocity = p.at(t);
        }
        apply_plate_input(&self.eff, &mut self.state);
        Ok(())
    }

    /// Advance to `t_end`. On a breakdown the state is left at the last good step and the error
    /// names the time, the step and the cause.
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), SimError> {
        self.advance_within(t_end, &Budget::UNLIMITED)
    }

    /// [`Simulation::advance_to`] within `budget`: before a step that would go over it, stop
    /// with [`SimError::OverBudget`], the state at the last step taken and the communication
    /// time moved to it (as after an interruption), so a later call goes on from there.
    pub fn advance_within(&mut self, t_end: f64, budget: &Budget) -> Result<(), SimError> {
        if !t_end.is_finite() || t_end < self.t_comm {
            return Err(SimError::Request(format!(
                "cannot advance from t = {} s to t = {t_end} s",
                self.t_comm
            )));
        }
        self.steer_plate(t_end)?;
        let pool = Arc::clone(&self.pool);
        pool.install(|| self.advance_in_pool(t_end, budget))
    }

    /// Under `plate_coupling = position`: the plate's velocity until `t_end`, constant, that
    /// brings it to `plate_position + plate_velocity (t_end - t_set)` at `t_end`, t_set the time
    /// the inputs were set: a master's position and velocity at a communication point,
    /// extrapolated over its step. The plate's displacement then follows the master's position
    /// to within the extrapolation's error over one step, which does not accumulate as a
    /// velocity held over each step (a Jacobi master) does. None under `velocity` coupling;
    /// refused if that velocity is beyond `max_plate_speed`.
    fn plate_steering(&self, t_end: f64) -> Result<Option<f64>, SimError> {
        let p = &self.eff.plate;
        let h = t_end - self.state.time;
        let Some(plate) = self.state.plate().filter(|w| w.motion == Motion::Input) else {
            return Ok(None);
        };
        if p.plate_coupling != PlateCoupling::Position || !self.scene.has_moving_plate() || h <= 0.0
        {
            return Ok(None);
        }
        let target = p.plate_position + p.plate_velocity * (t_end - self.inputs_time);
        let max = self.cfg.plate.max_plate_speed;
        let u = (target - plate.displacement) / h;
        if u.abs() <= max {
            return Ok(Some(u));
        }
        Err(SimError::InputOutOfRange(plate_speed_refusal(
            &format!(
                "plate_position = {} m with plate_velocity = {} m/s (plate_coupling = position) \
                 asks the plate, now at {} m, to move at {u} m/s until t = {t_end} s, which",
                p.plate_position, p.plate_velocity, plate.displacement
            ),
            u,
            max,
        )))
    }

    /// Whether [`Simulation::advance_to`]`(t_end)` would be refused before any work because an
    /// input asks for more than the run was set up for ([`SimError::InputOutOfRange`]).
    pub fn check_step(&self, t_end: f64) -> Result<(), SimError> {
        self.plate_steering(t_end).map(|_| ())
    }

    /// Put [`Simulation::plate_steering`] in force until `t_end`.
    fn steer_plate(&mut self, t_end: f64) -> Result<(), SimError> {
        if let Some(u) = self.plate_steering(t_end)? {
            if let Some(plate) = self.state.plate_mut() {
                plate.velocity = u;
            }
        }
        Ok(())
    }

    fn advance_in_pool(&mut self, t_end: f64, budget: &Budget) -> Result<(), SimError> {
        let mut last_before: Option<State> = None;
        let (started, mut taken) = (std::time::Instant::now(), 0u64);
        while self.state.time < t_end {
            let (time, step) = (self.state.time, self.state.step);
            let stop = if self
                .stop
                .as_ref()
                .is_some_and(|f| f.load(Ordering::Relaxed))
            {
                Some(SimError::Interrupted { time, step })
            } else {
                budget
                    .exceeded(taken, started)
                    .map(|spent| SimError::OverBudget { time, step, spent })
            };
            if let Some(err) = stop {
                self.t_comm = self.t_comm.max(self.state.time);
                if let Some(b) = last_before {
                    self.prev = Some((b.time, self.scene.outputs(&b, &self.eff)));
                }
                self.rewind = None;
                return Err(err);
            }
            taken += 1;
            let t_begin = self.profile.start();
            let before = self.state.clone();
            let max_dt = if self.exact {
                t_end - self.state.time
            } else {
                f64::INFINITY
            };
            self.scene.before_step(&self.eff, &mut self.state);
            let t = self.profile.lap(t_begin, "state copy, scene hook", true);
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
                    self.t_comm = self.t_comm.max(self.state.time);
                    self.prev = None;
                    self.rewind = None;
                    return Err(err);
                }
            }
        }
        if let Some(b) = last_before {
            self.prev = Some((b.time, self.scene.outputs(&b, &self.eff)));
            self.rewind = (!self.exact).then_some(b);
        }
        self.t_comm = t_end;
        Ok(())
    }

    /// Advance to `t_end` recording the outputs now and every `dt` after: the record as far as it
    /// got, and the breakdown that ended it early, if any.
    pub fn record(&mut self, t_end: f64, dt: f64) -> (Vec<(f64, Outputs)>, Option<SimError>) {
        let mut out = vec![(self.time(), self.outputs())];
        let (t0, n) = (self.time(), ((t_end - self.time()) / dt).round() as usize);
        for k in 1..=n {
            if let Err(e) = self.advance_to((t0 + k as f64 * dt).min(t_end)) {
                return (out, Some(e));
            }
            out.push((self.time(), self.outputs()));
        }
        (out, None)
    }

    /// The outputs at the communication time: linear interpolation between the internal states
    /// just before and at or after it (`time_step` and `particle_count` are the current ones).
    pub fn outputs(&self) -> Outputs {
        let now = self.scene.outputs(&self.state, &self.eff);
        match self.prev {
            Some((tp, before)) if self.state.time > self.t_comm && tp <= self.t_comm => {
                let w = (self.t_comm - tp) / (self.state.time - tp);
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

    /// Pressure roughness of the fluid now: RMS of p_i minus its SPH-smoothed value, over the
    /// dynamic pressure rho0 U^2 of the scene (see [`pressure_roughness`] and
    /// [`Scene::velocity_scale`]).
    pub fn pressure_roughness(&self) -> f64 {
        let u = self.scene.velocity_scale(&self.eff);
        let p = &self.params;
        let (fluid, kernel) = (&self.state.fluid, CubicSpline::new(self.eff.h()));
        let scale = self.eff.fluid.density * u * u;
        self.pool
            .install(|| pressure_roughness(fluid, &p.eos, &kernel, &p.domain, scale))
    }

    /// Total momentum of the fluid [kg m/s per m depth].
    pub fn fluid_momentum(&self) -> Vec2 {
        let f = &self.state.fluid;
        f.v.iter().fold(Vec2::zeros(), |s, v| s + v) * f.mass
    }

    /// Total fluid mass [kg per m depth].
    pub fn fluid_mass(&self) -> f64 {
        self.state.fluid.mass * self.state.fluid.len() as f64
    }

    /// Where the scheme's time went since the simulation was built or restored (empty for
    /// schemes that time nothing).
    pub fn scheme_timings(&self) -> Timings {
        self.scheme.timings()
    }

    /// Turn the per-pass timers of the steps on or off (see [`crate::profile`]); off by
    /// default, and nothing is timed while off.
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
        // What the scheme's own parts leave of its steps (ISPH times only its solves), counted
        // as serial: unaccounted time is not known to spread over the threads.
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

    /// Positions of the wall particles currently built.
    pub fn wall_positions(&self) -> Vec<Vec2> {
        self.scheme.wall_positions(&self.state)
    }

    /// The state as bytes (bincode): configuration and state, no pointers.
    pub fn save_state(&self) -> Vec<u8> {
        let saved = Saved {
            state: self.state.clone(),
            t_comm: self.t_comm,
            prev: self.prev,
            exact: self.exact,
            rewind: self.rewind.clone(),
            inputs: self.inputs(),
            inputs_time: self.inputs_time,
        };
        bincode::serialize(&(&self.cfg, &saved)).expect("state serialises")
    }

    /// Restore a state saved by [`Simulation::save_state`], possibly in another process. The
    /// thread pool is kept unless the saved configuration asks for another size.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SimError> {
        let (cfg, saved): (SceneConfig, Saved) =
            bincode::deserialize(bytes).map_err(|e| SimError::State(e.to_string()))?;
        let pool = if cfg.numerics.threads == self.cfg.numerics.threads {
            Arc::clone(&self.pool)
        } else {
            thread_pool(&cfg)?
        };
        let mut sim = Self::with_pool(cfg, pool)?;
        sim.state = saved.state;
        sim.scheme = sim.fresh_scheme();
        sim.eff
            .apply_inputs(&saved.inputs)
            .map_err(|e| SimError::State(e.to_string()))?;
        sim.t_comm = saved.t_comm;
        sim.prev = saved.prev;
        sim.exact = saved.exact;
        sim.rewind = saved.rewind;
        sim.inputs_time = saved.inputs_time;
        sim.stop = self.stop.take();
        *self = sim;
        Ok(())
    }

    /// A scheme built for the current state's walls, with no caches: for a state that replaced
    /// the one the scheme stepped (restored, or rewound by an input change).
    fn fresh_scheme(&self) -> Box<dyn Scheme> {
        let mut scheme = crate::scheme::build(
            self.eff.scheme,
            &self.eff.fluid,
            &self.eff.numerics,
            self.params.clone(),
            &self.state.walls,
        );
        scheme.set_profiling(self.profile.start().is_some());
        scheme
    }

    /// Back to the initial state of the same configuration (same thread pool).
    pub fn reset(&mut self) -> Result<(), SimError> {
        let stop = self.stop.take();
        *self = Self::with_pool(self.cfg.clone(), Arc::clone(&self.pool))?;
        self.stop = stop;
        Ok(())
    }
}
