//! The drop impact of Fang 2006 section 4: a disc cut from a Cartesian lattice, moving
//! vertically down at the impact velocity towards a rigid plate.

use super::Scene;
use crate::boundary::plate::Plate;
use crate::config::{ConfigError, SceneConfig};
use crate::particles::Fluid;
use crate::{Mat2, Vec2};

/// Build the fluid of a drop: lattice points (i + 1/2) dx, (j + 1/2) dx about the drop centre in
/// the plate's frame (so the lattice lines up with the wall particles at any inclination, and the
/// drop is symmetric about its centre) kept where they fall inside the disc.
///
/// `rest` is the model's conformation at rest (`Rheology::rest_conformation`), or None for models
/// without a conformation tensor: the drop starts stress-free, as Fang's does.
pub fn build(cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Plate) {
    let dx = cfg.dx();
    let plate = Plate::new(cfg.plate_inclination, dx);
    let centre = Vec2::new(0.0, cfg.initial_drop_height);
    let (sc, dc) = (plate.s(&centre), plate.d(&centre));
    let r = 0.5 * cfg.drop_diameter;
    let n = cfg.particles_per_diameter;
    let mut fluid = Fluid {
        mass: cfg.density * dx * dx,
        ..Default::default()
    };
    for j in -n..n {
        for i in -n..n {
            let (ls, ld) = ((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx);
            if ls * ls + ld * ld < r * r {
                fluid.x.push(plate.point(sc + ls, dc + ld));
            }
        }
    }
    let v0 = Vec2::new(0.0, -cfg.impact_velocity);
    fluid.v = vec![v0; fluid.x.len()];
    fluid.rho = vec![cfg.density; fluid.x.len()];
    if let Some(a0) = rest {
        fluid.conf = vec![a0; fluid.x.len()];
    }
    (fluid, plate)
}

/// The drop impact scene (see the module documentation).
pub struct Drop;

impl Scene for Drop {
    fn has_moving_plate(&self) -> bool {
        true
    }

    fn validate(&self, cfg: &SceneConfig) -> Result<(), ConfigError> {
        let theta = cfg.plate_inclination.to_radians();
        let normal_gap = cfg.initial_drop_height * theta.cos() - 0.5 * cfg.drop_diameter;
        if normal_gap < cfg.dx() {
            return Err(ConfigError::Inconsistent(format!(
                "initial_drop_height = {} m puts the drop (diameter {} m) within one particle spacing of \
                 the plate inclined at {} deg: its centre must be at least {:.6} m above the impact point",
                cfg.initial_drop_height,
                cfg.drop_diameter,
                cfg.plate_inclination,
                (0.5 * cfg.drop_diameter + cfg.dx()) / theta.cos()
            )));
        }
        Ok(())
    }

    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Plate>) {
        let (fluid, plate) = build(cfg, rest);
        (fluid, vec![plate])
    }

    /// The impact velocity (sqrt(g D) if the drop is released at rest).
    fn velocity_scale(&self, cfg: &SceneConfig) -> f64 {
        if cfg.impact_velocity > 0.0 {
            cfg.impact_velocity
        } else {
            (cfg.gravity * cfg.drop_diameter).sqrt().max(1e-12)
        }
    }

    /// D / V, Fang 2006's t*.
    fn time_scale(&self, cfg: &SceneConfig) -> f64 {
        cfg.drop_diameter / self.velocity_scale(cfg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drop_inside_plate_is_refused() {
        let c = SceneConfig {
            initial_drop_height: 0.01,
            ..Default::default()
        };
        let e = Drop.validate(&c).unwrap_err().to_string();
        assert!(e.contains("drop_height"), "{e}");
        assert!(Drop.validate(&SceneConfig::default()).is_ok());
    }
}
