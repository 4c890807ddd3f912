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

/// `$body` with `$r` the running [`Run`], of either dimension.
macro_rules! on_run {
    ($run:expr, $r:ident => $body:expr) => {
        match $run {
            Runs::D2($r) => $body,
            Runs::D3($r) => $body,
        }
    };
}

mod run;
mod view;

pub use view::Particles;

use crate::boundary::plate::Motion;
use crate::budget::Budget;
use crate::config::{ConfigError, PlateCoupling};
use crate::scene::{Inputs, Outputs, Scene, SceneConfig};
use crate::state::State;
use run::{apply_plate_input, Drive, Run, Runs, Saved};
use std::sync::atomic::AtomicBool;
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

/// A running simulation.
pub struct Simulation {
    cfg: SceneConfig,
    /// The configuration the solver runs: the scene's own physics over `cfg`'s numerics
    /// ([`Scene::effective_config`]; equal to `cfg` for the drop), with the inputs in force.
    eff: SceneConfig,
    scene: &'static dyn Scene,
    /// The state, the scheme and what dense output keeps, in the run's dimension.
    run: Runs,
    elastic: bool,
    pool: Arc<rayon::ThreadPool>,
    /// The communication time: where the caller asked to be. In dense-output mode the solver's
    /// own state (its `time`) is at or just past it.
    t_comm: f64,
    /// Whether steps land exactly on communication points (once an input has changed).
    exact: bool,
    /// Checked before every step: when it is set, `advance_to` stops there (see
    /// [`Simulation::set_stop_flag`]).
    stop: Option<Arc<AtomicBool>>,
    /// When the inputs in force were set (the communication time then): under
    /// `plate_coupling = position` the plate's target `plate_position + plate_velocity (t -
    /// inputs_time)` is extrapolated from it.
    inputs_time: f64,
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
        let run = if eff.numerics.dimension == 3 {
            Runs::D3(Run::new(scene, &eff)?)
        } else {
            Runs::D2(Run::new(scene, &eff)?)
        };
        let elastic = crate::scheme::rest_conformation(&eff.fluid).is_some();
        // A plate steered to a position moves at a velocity that depends on the length of the
        // communication step: the steps land on every communication point.
        let steered =
            scene.has_moving_plate() && eff.plate.plate_coupling == PlateCoupling::Position;
        Ok(Self {
            cfg,
            eff,
            scene,
            run,
            elastic,
            pool,
            t_comm: 0.0,
            exact: steered,
            stop: None,
            inputs_time: 0.0,
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
    /// The state of a 2D run (see [`Simulation::state_3d`]).
    ///
    /// # Panics
    /// In a 3D run (`dimension = 3`): its state is a `State<3>`.
    pub fn state(&self) -> &State {
        match &self.run {
            Runs::D2(r) => &r.state,
            Runs::D3(_) => {
                panic!("state(): a 3D run (dimension = 3) has a State<3>: use state_3d()")
            }
        }
    }
    /// The state of a 3D run (None in 2D).
    pub fn state_3d(&self) -> Option<&State<3>> {
        match &self.run {
            Runs::D2(_) => None,
            Runs::D3(r) => Some(&r.state),
        }
    }
    /// The space dimension of the run (2 or 3).
    pub fn dimension(&self) -> usize {
        on_run!(&self.run, r => r.state.fluid.x.first().map_or(
            self.eff.numerics.dimension as usize, |x| x.len()))
    }
    /// The solver's own time (in dense-output mode at or just past [`Simulation::time`]).
    pub fn state_time(&self) -> f64 {
        on_run!(&self.run, r => r.state.time)
    }
    /// Steps taken since t = 0.
    pub fn steps(&self) -> u64 {
        on_run!(&self.run, r => r.state.step)
    }
    /// Number of fluid particles.
    pub fn particle_count(&self) -> usize {
        on_run!(&self.run, r => r.state.fluid.len())
    }
    /// The stable time step at the last step \[s\] (0 before the first).
    pub fn last_dt(&self) -> f64 {
        on_run!(&self.run, r => r.state.last_dt)
    }
    /// How many times the impenetrability condition put a particle back above a plate.
    pub fn wall_reflections(&self) -> u64 {
        on_run!(&self.run, r => r.state.wall_reflections)
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
        if !self.exact && self.state_time() > self.t_comm {
            // The last internal step went past t_comm with the old inputs: go back to the state
            // before it and land exactly on t_comm.
            let eff = &self.eff;
            on_run!(&mut self.run, r => {
                if let Some(before) = r.rewind.take() {
                    r.state = before;
                    // The scheme's neighbour lists and wall particles belong to the state after
                    // the step (walls grow as the fluid spreads): start them afresh.
                    r.refresh_scheme(eff)?;
                }
            });
            self.exact = true;
            let t = self.t_comm;
            self.advance_to(t)?;
        }
        self.exact = true;
        self.eff = next;
        self.inputs_time = self.t_comm;
        on_run!(&mut self.run, r => apply_plate_input(&self.eff, &mut r.state));
        Ok(())
    }

    /// Give wall `wall` (an index into `state().walls`) the motion `motion` from the
    /// communication time on; a prescribed motion takes its velocity at that time. The input
    /// `plate_velocity` then moves the wall only if `motion` is [`Motion::Input`] and the wall
    /// is the scene's plate.
    pub fn set_wall_motion(&mut self, wall: usize, motion: Motion) -> Result<(), SimError> {
        let t = self.t_comm;
        on_run!(&mut self.run, r => {
            let n = r.state.walls.len();
            let w = r
                .state
                .walls
                .get_mut(wall)
                .ok_or_else(|| {
                    SimError::Request(format!("no wall {wall} (this scene has {n} walls)"))
                })?
                .plate_mut()
                .ok_or_else(|| {
                    SimError::Request(format!("wall {wall} is not straight: it is fixed"))
                })?;
            w.motion = motion;
            if let Motion::Prescribed(p) = motion {
                w.velocity = p.at(t);
            }
            apply_plate_input(&self.eff, &mut r.state);
        });
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
        let h = t_end - self.state_time();
        let Some(displacement) = on_run!(&self.run, r => r
            .state
            .plate()
            .filter(|w| w.motion == Motion::Input)
            .map(|w| w.displacement))
        else {
            return Ok(None);
        };
        if p.plate_coupling != PlateCoupling::Position || !self.scene.has_moving_plate() || h <= 0.0
        {
            return Ok(None);
        }
        let target = p.plate_position + p.plate_velocity * (t_end - self.inputs_time);
        let max = self.cfg.plate.max_plate_speed;
        let u = (target - displacement) / h;
        if u.abs() <= max {
            return Ok(Some(u));
        }
        Err(SimError::InputOutOfRange(plate_speed_refusal(
            &format!(
                "plate_position = {} m with plate_velocity = {} m/s (plate_coupling = position) \
                 asks the plate, now at {} m, to move at {u} m/s until t = {t_end} s, which",
                p.plate_position, p.plate_velocity, displacement
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
            on_run!(&mut self.run, r => {
                if let Some(plate) = r.state.plate_mut() {
                    plate.velocity = u;
                }
            });
        }
        Ok(())
    }

    fn advance_in_pool(&mut self, t_end: f64, budget: &Budget) -> Result<(), SimError> {
        let d = Drive {
            scene: self.scene,
            eff: &self.eff,
            exact: self.exact,
            stop: self.stop.as_ref(),
        };
        let t_comm = &mut self.t_comm;
        on_run!(&mut self.run, r => r.advance(&d, t_end, budget, t_comm))
    }

    /// What the stepping loop and the outputs read of this simulation.
    fn drive(&self) -> Drive<'_> {
        Drive {
            scene: self.scene,
            eff: &self.eff,
            exact: self.exact,
            stop: self.stop.as_ref(),
        }
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
        let d = self.drive();
        on_run!(&self.run, r => r.outputs_at(&d, self.t_comm))
    }

    /// The state as bytes (bincode): configuration and state, no pointers.
    pub fn save_state(&self) -> Vec<u8> {
        on_run!(&self.run, r => {
            let saved = Saved {
                state: r.state.clone(),
                t_comm: self.t_comm,
                prev: r.prev,
                exact: self.exact,
                rewind: r.rewind.clone(),
                inputs: self.inputs(),
                inputs_time: self.inputs_time,
            };
            bincode::serialize(&(&self.cfg, &saved)).expect("state serialises")
        })
    }

    /// Restore a state saved by [`Simulation::save_state`], possibly in another process. The
    /// thread pool is kept unless the saved configuration asks for another size.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SimError> {
        let bad = |e: bincode::Error| SimError::State(e.to_string());
        // The configuration comes first and says the dimension of the rest.
        let cfg: SceneConfig = bincode::deserialize(bytes).map_err(bad)?;
        let pool = if cfg.numerics.threads == self.cfg.numerics.threads {
            Arc::clone(&self.pool)
        } else {
            thread_pool(&cfg)?
        };
        let dimension = cfg.numerics.dimension;
        let mut sim = Self::with_pool(cfg, pool)?;
        let (inputs, t_comm, exact, inputs_time) = match (&mut sim.run, dimension) {
            (Runs::D2(r), 2) => {
                let (_, saved): (SceneConfig, Saved<2>) =
                    bincode::deserialize(bytes).map_err(bad)?;
                (r.state, r.prev, r.rewind) = (saved.state, saved.prev, saved.rewind);
                r.refresh_scheme(&sim.eff)?;
                (saved.inputs, saved.t_comm, saved.exact, saved.inputs_time)
            }
            (Runs::D3(r), 3) => {
                let (_, saved): (SceneConfig, Saved<3>) =
                    bincode::deserialize(bytes).map_err(bad)?;
                (r.state, r.prev, r.rewind) = (saved.state, saved.prev, saved.rewind);
                r.refresh_scheme(&sim.eff)?;
                (saved.inputs, saved.t_comm, saved.exact, saved.inputs_time)
            }
            _ => return Err(SimError::State(format!("no {dimension}D run to restore"))),
        };
        sim.eff
            .apply_inputs(&inputs)
            .map_err(|e| SimError::State(e.to_string()))?;
        sim.t_comm = t_comm;
        sim.exact = exact;
        sim.inputs_time = inputs_time;
        sim.stop = self.stop.take();
        *self = sim;
        Ok(())
    }

    /// Back to the initial state of the same configuration (same thread pool).
    pub fn reset(&mut self) -> Result<(), SimError> {
        let stop = self.stop.take();
        *self = Self::with_pool(self.cfg.clone(), Arc::clone(&self.pool))?;
        self.stop = stop;
        Ok(())
    }
}
