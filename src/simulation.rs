//! A simulation: the state, the scheme chosen for it, and `advance_to` with adaptive sub-steps.

use crate::config::{ConfigError, Scene, SceneConfig, SchemeKind};
use crate::diagnostics::Outputs;
use crate::kernel::CubicSpline;
use crate::particles::Fluid;
use crate::rheology::{AnyRheology, Rheology};
use crate::scene::elliptical_drop::{self, SemiAxes};
use crate::scheme::common::{pressure_roughness, Params};
use crate::scheme::pdri::Pdri;
use crate::scheme::wcsph::Wcsph;
use crate::scheme::Scheme;
use crate::{dispatch_rheology, Vec2};
use serde::{Deserialize, Serialize};
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
}

/// Everything that evolves: serialisable, holds no pointers, so a saved state restores in another
/// process (FMI get/set/serialize FMU state).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State {
    pub time: f64,
    pub step: u64,
    pub fluid: Fluid,
    pub plate: Option<crate::boundary::plate::Plate>,
    /// Force of the fluid on the plate at the last step's corrector stage [N/m], global frame.
    pub wall_force: Vec2,
    /// Time integral of that force since t = 0 [N s/m], global frame.
    pub wall_impulse: Vec2,
    /// Stable time step at the last step [s] (the step actually taken may be shorter, to land
    /// on a communication point).
    pub last_dt: f64,
    /// Void fraction after the last step (see [`crate::health`]).
    pub void_fraction: f64,
    /// How many times a fluid particle was put back above the plate by the impenetrability
    /// condition of Fang's walls (see [`crate::scheme::wcsph`]).
    pub wall_reflections: u64,
}

/// A running simulation.
pub struct Simulation {
    cfg: SceneConfig,
    /// The configuration the solver runs: the scene's own physics over `cfg`'s numerics
    /// ([`crate::scene::effective_config`]); equal to `cfg` for the drop.
    eff: SceneConfig,
    state: State,
    scheme: Box<dyn Scheme>,
    elastic: bool,
    /// The communication time: where the caller asked to be. The solver's own state
    /// (`state.time`) is at or just past it, because internal steps are never shortened.
    t_comm: f64,
    /// Time and outputs of the internal state before the last step, for interpolating the
    /// outputs at `t_comm` (None before the first step).
    prev: Option<(f64, Outputs)>,
}

/// Build the scheme for an (effective) configuration, resolving scheme, kernel and rheology once
/// into a concrete type.
fn build_scheme(
    cfg: &SceneConfig,
    plate: Option<crate::boundary::plate::Plate>,
) -> Result<(Box<dyn Scheme>, bool), SimError> {
    let model = AnyRheology::from_config(cfg)?;
    let kernel = CubicSpline::new(cfg.h());
    let params = Params::from_config(cfg);
    let kind = cfg.scheme;
    if kind == SchemeKind::Isph {
        return Err(SimError::Config(ConfigError::Inconsistent(
            "scheme 'isph' is not implemented yet".into(),
        )));
    }
    Ok(dispatch_rheology!(model, m => {
        let elastic = elastic_of(&m);
        let scheme: Box<dyn Scheme> = if kind == SchemeKind::Pdri {
            Box::new(Pdri::new(kernel, m, params, plate))
        } else {
            Box::new(Wcsph::new(kernel, m, params, plate))
        };
        (scheme, elastic)
    }))
}

fn elastic_of<R: Rheology>(_: &R) -> bool {
    R::ELASTIC
}

impl Simulation {
    /// Validate the configuration and build the initial state.
    pub fn new(cfg: SceneConfig) -> Result<Self, SimError> {
        cfg.validate()?;
        let eff = crate::scene::effective_config(&cfg);
        let (_, elastic) = build_scheme(&eff, None)?;
        let (fluid, plate) = match cfg.scene {
            Scene::Drop => {
                let rest = dispatch_rheology!(AnyRheology::from_config(&eff)?, m => {
                    elastic_of(&m).then(|| m.rest_conformation())
                });
                let (f, p) = crate::scene::drop::build(&eff, rest);
                (f, Some(p))
            }
            Scene::EllipticalDrop => (elliptical_drop::build(&eff), None),
            other => {
                return Err(SimError::Config(ConfigError::Inconsistent(format!(
                    "scene '{other}' is not implemented yet"
                ))))
            }
        };
        let (scheme, _) = build_scheme(&eff, plate.clone())?;
        let state = State {
            time: 0.0,
            step: 0,
            fluid,
            plate,
            wall_force: Vec2::zeros(),
            wall_impulse: Vec2::zeros(),
            last_dt: 0.0,
            void_fraction: 0.0,
            wall_reflections: 0,
        };
        Ok(Self {
            cfg,
            eff,
            state,
            scheme,
            elastic,
            t_comm: 0.0,
            prev: None,
        })
    }

    /// The configuration as given.
    pub fn config(&self) -> &SceneConfig {
        &self.cfg
    }
    /// The configuration the solver runs: for the elliptical drop, the scene's own physics
    /// (radius, density, viscosity, sound speed...) over the given numerics.
    pub fn effective_config(&self) -> &SceneConfig {
        &self.eff
    }
    pub fn state(&self) -> &State {
        &self.state
    }
    /// The communication time: the `t_end` of the last successful [`Simulation::advance_to`]
    /// (or, after a breakdown, the time of the last good state). The particles themselves are at
    /// `state().time`, which may be up to one internal step later.
    pub fn time(&self) -> f64 {
        self.t_comm
    }
    /// Whether the model carries a conformation tensor.
    pub fn is_elastic(&self) -> bool {
        self.elastic
    }

    /// Advance to exactly `t_end` with the scheme's adaptive steps; the last one is shortened to
    /// land on `t_end`. On a breakdown the state is left at the last good step... and the error
    /// names the time, the step and the cause.
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), SimError> {
        if !t_end.is_finite() || t_end < self.t_comm {
            return Err(SimError::Request(format!(
                "cannot advance from t = {} s to t = {t_end} s",
                self.t_comm
            )));
        }
        // Internal steps are the scheme's own, never shortened to land on t_end: the trajectory
        // is then the same whatever the communication steps, and outputs at a communication point
        // are interpolated between the two internal states around it (dense output). So the
        // outputs at a given time agree to round-off for any communication step size.
        let mut last_before: Option<State> = None;
        while self.state.time < t_end {
            let before = self.state.clone();
            match self.scheme.step(&mut self.state, f64::INFINITY) {
                Ok(dt) => {
                    self.state.step += 1;
                    self.state.time += dt;
                    last_before = Some(before);
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
                    return Err(err);
                }
            }
        }
        if let Some(b) = last_before {
            self.prev = Some((
                b.time,
                Outputs::compute(&b, self.eff.dx(), self.eff.density),
            ));
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

    /// The outputs at the current time.
    /// The outputs at the communication time: linear interpolation between the internal states
    /// just before and at or after it (`time_step` and `particle_count` are the current ones).
    pub fn outputs(&self) -> Outputs {
        let now = Outputs::compute(&self.state, self.eff.dx(), self.eff.density);
        match self.prev {
            Some((tp, before)) if self.state.time > self.t_comm && tp <= self.t_comm => {
                let w = (self.t_comm - tp) / (self.state.time - tp);
                let (a, b) = (before.values(), now.values());
                let mut mixed = now;
                mixed.set_values(std::array::from_fn(|k| a[k] + w * (b[k] - a[k])));
                mixed.time_step = now.time_step;
                mixed.particle_count = now.particle_count;
                mixed
            }
            _ => now,
        }
    }

    /// For the elliptical drop, the semi-axes of the fluid now against the exact ones (relative
    /// error of the semi-major axis, product of the semi-axes); `None` for other scenes.
    pub fn elliptical_semi_axes(&self) -> Option<SemiAxes> {
        (self.cfg.scene == Scene::EllipticalDrop)
            .then(|| elliptical_drop::semi_axes(&self.state.fluid, self.state.time))
    }

    /// Pressure roughness of the fluid now: RMS of p_i minus its SPH-smoothed value, over the
    /// dynamic pressure rho0 U^2 of the scene (see
    /// [`pressure_roughness`] and
    /// [`crate::scene::velocity_scale`]).
    pub fn pressure_roughness(&self) -> f64 {
        let u = crate::scene::velocity_scale(&self.eff);
        pressure_roughness(
            &self.state.fluid,
            &Params::from_config(&self.eff),
            &CubicSpline::new(self.eff.h()),
            self.eff.density * u * u,
        )
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

    /// Positions of the wall particles currently built.
    pub fn wall_positions(&self) -> Vec<Vec2> {
        self.scheme.wall_positions()
    }

    /// The state as bytes (bincode): configuration and state, no pointers.
    pub fn save_state(&self) -> Vec<u8> {
        bincode::serialize(&(&self.cfg, &self.state, self.t_comm, &self.prev))
            .expect("state serialises")
    }

    /// Restore a state saved by [`Simulation::save_state`], possibly in another process.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SimError> {
        let (cfg, state, t_comm, prev): (SceneConfig, State, f64, Option<(f64, Outputs)>) =
            bincode::deserialize(bytes).map_err(|e| SimError::State(e.to_string()))?;
        cfg.validate()?;
        let eff = crate::scene::effective_config(&cfg);
        let (scheme, elastic) = build_scheme(&eff, state.plate.clone())?;
        *self = Self {
            cfg,
            eff,
            state,
            scheme,
            elastic,
            t_comm,
            prev,
        };
        Ok(())
    }

    /// Back to the initial state of the same configuration.
    pub fn reset(&mut self) -> Result<(), SimError> {
        *self = Simulation::new(self.cfg.clone())?;
        Ok(())
    }
}
