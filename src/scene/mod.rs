//! Scenes: the initial state of a flow, its walls, what happens at every step (inflow, for the
//! jet) and what is measured in it. A scene is a [`Scene`]; [`for_config`] is the one place that
//! maps the `scene` parameter to it, so a new scene is a new file and one line there.

pub mod channel;
pub mod drop;
pub mod elliptical_drop;
pub mod jet;

use crate::boundary::plate::Plate;
use crate::config::{self, ConfigError, SceneConfig};
use crate::diagnostics::Outputs;
use crate::neighbors::Domain;
use crate::particles::Fluid;
use crate::state::State;
use crate::{Mat2, Vec2};

/// One kind of flow.
pub trait Scene: Send + Sync {
    /// Checks of the configuration that belong to this scene (beyond the parameter table's).
    fn validate(&self, _cfg: &SceneConfig) -> Result<(), ConfigError> {
        Ok(())
    }

    /// The configuration the solver runs: the scene's own physics over the user's numerics.
    fn effective_config(&self, cfg: &SceneConfig) -> SceneConfig {
        cfg.clone()
    }

    /// The initial fluid and walls for the effective configuration. `rest` is the model's
    /// conformation at rest, or None for models without a conformation tensor.
    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Plate>);

    /// The domain the pairs see (open unless the scene is periodic).
    fn domain(&self, _cfg: &SceneConfig) -> Domain {
        Domain::OPEN
    }

    /// Body force per unit mass [m/s2]: gravity, vertically down, unless the scene drives the
    /// flow otherwise.
    fn body_force(&self, cfg: &SceneConfig) -> Vec2 {
        Vec2::new(0.0, -cfg.gravity)
    }

    /// Whether the `auto` viscous operator means Morris' Laplacian (see
    /// [`crate::operators::stress`]) rather than Fang's nested form.
    fn viscous_laplacian(&self) -> bool {
        false
    }

    /// Largest distance from the origin a particle may reach before the run stops [m].
    fn domain_radius(&self, cfg: &SceneConfig) -> f64 {
        1000.0 * cfg.drop_diameter + 10.0 * cfg.initial_drop_height
    }

    /// Completes the initial state made of [`Scene::build`]'s fluid and walls (the jet's inflow
    /// bookkeeping).
    fn init_state(&self, _cfg: &SceneConfig, _st: &mut State) {}

    /// Called before every step (inflow).
    fn before_step(&self, _cfg: &SceneConfig, _st: &mut State) {}

    /// Whether the input `plate_velocity` may move this scene's first wall. Only a scene with
    /// one free-standing plate can: a channel wall moved along its normal would squeeze the
    /// channel, and the elliptical drop has no wall.
    fn has_moving_plate(&self) -> bool {
        false
    }

    /// Velocity scale U \[m/s\], for dimensionless measures such as the pressure roughness
    /// (normalised by rho0 U^2).
    fn velocity_scale(&self, cfg: &SceneConfig) -> f64;

    /// Time scale \[s\] for dimensionless plots (t* = t / time scale).
    fn time_scale(&self, cfg: &SceneConfig) -> f64;

    /// The outputs of a state (see [`crate::diagnostics`]).
    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        Outputs::compute_for(st, cfg)
    }
}

/// The scene of a configuration, or why it cannot run.
pub fn for_config(cfg: &SceneConfig) -> Result<&'static dyn Scene, ConfigError> {
    match cfg.scene {
        config::Scene::Drop => Ok(&drop::Drop),
        config::Scene::EllipticalDrop => Ok(&elliptical_drop::EllipticalDrop),
        config::Scene::Channel => Ok(&channel::Channel),
        config::Scene::Jet => Ok(&jet::Jet),
    }
}

/// The configuration the solver runs for `cfg` (see [`Scene::effective_config`]); `cfg` itself
/// for a scene that cannot run.
pub fn effective_config(cfg: &SceneConfig) -> SceneConfig {
    match for_config(cfg) {
        Ok(s) => s.effective_config(cfg),
        Err(_) => cfg.clone(),
    }
}

/// Velocity scale of the scene of `cfg` (see [`Scene::velocity_scale`]).
pub fn velocity_scale(cfg: &SceneConfig) -> f64 {
    for_config(cfg).map_or(1.0, |s| s.velocity_scale(cfg))
}

/// Time scale of the scene of `cfg` (see [`Scene::time_scale`]).
pub fn time_scale(cfg: &SceneConfig) -> f64 {
    for_config(cfg).map_or(1.0, |s| s.time_scale(&s.effective_config(cfg)))
}
