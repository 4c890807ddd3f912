//! Scenes: the initial state of a flow and what to measure in it.

pub mod drop;
pub mod elliptical_drop;

use crate::config::{Scene, SceneConfig};

/// The configuration the solver runs for a scene: the scene's own physics over the user's
/// numerics. The drop takes the configuration as it is; the elliptical drop defines its own
/// (see [`elliptical_drop::effective_config`]).
pub fn effective_config(cfg: &SceneConfig) -> SceneConfig {
    match cfg.scene {
        Scene::EllipticalDrop => elliptical_drop::effective_config(cfg),
        Scene::Drop | Scene::Jet => cfg.clone(),
    }
}

/// Velocity scale U of a scene \[m/s\], for dimensionless measures such as the pressure roughness
/// (normalised by rho0 U^2): the impact velocity of a drop (sqrt(g D) if it is released at rest),
/// A0 R for the elliptical drop.
pub fn velocity_scale(cfg: &SceneConfig) -> f64 {
    match cfg.scene {
        Scene::EllipticalDrop => elliptical_drop::VELOCITY_SCALE,
        Scene::Drop | Scene::Jet => {
            if cfg.impact_velocity > 0.0 {
                cfg.impact_velocity
            } else {
                (cfg.gravity * cfg.drop_diameter).sqrt().max(1e-12)
            }
        }
    }
}
