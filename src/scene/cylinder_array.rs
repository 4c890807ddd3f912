//! A periodic array of cylinders between two walls (King & Lind 2021 section IV.B): a cell of
//! length L = 6R and height H = 4R, periodic along x, no-slip walls at y = 0 and y = H, a
//! cylinder of radius R at the centre of the cell, the fluid at rest at t = 0 and driven from
//! then on by a uniform body force g along x (gravity off). The reference for it is the finite
//! element solution in `validation/cylinder_array/`.
//!
//! Walls: the two straight walls (wall 0 at the bottom, wall 1 at the top) and the circle
//! (wall 2). Under `wall_boundary = auto` ISPH puts mirror particles on all three; the weakly
//! compressible schemes put their paper's particles on the straight walls (Fang's image
//! particles, Ren's ghost particles) and dummy particles (Adami et al. 2012) on the cylinder;
//! `wall_boundary = dummy` puts dummy particles on all three.
//!
//! The lattice: `particles_per_diameter` spacings across the cylinder's diameter 2R (dx =
//! 2R / n), rows as in the channel (on the wall lines' side at the scheme's
//! `wall_lattice_offset`), without the particles closer to the cylinder's axis than R plus the
//! same offset.
//!
//! Outputs: `cylinder_drag` and `cylinder_lift`, the force of the fluid on the cylinder alone
//! along and across the flow per unit depth (0 where the scheme does not split the walls'
//! force; see `State::wall_forces`).

use super::{Outputs, Scene, SceneConfig, SceneType};
use crate::boundary::plate::Plate;
use crate::boundary::wall::Wall;
use crate::config::{real_pos, ConfigError};
use crate::geometry::{Ball, Shape};
use crate::neighbors::Domain;
use crate::particles::Fluid;
use crate::state::State;
use crate::{Mat2, Vec2};

crate::params! {
    /// The cell: the cylinder's radius (the cell is 6R by 4R) and the force that drives it.
    pub struct CylinderArrayParams {
        cylinder_radius: f64 = real_pos(1.0, 1000.0), vr 62, unit "m";
            "Cylinder array scene: radius R of the cylinder; the periodic cell is 6 R long and 4 R high, particles_per_diameter counts particles across 2 R",
        cylinder_body_force: f64 = real_pos(300.0, 1.0e6), vr 63, unit "m/s2";
            "Cylinder array scene: body force per unit mass along the cell, switched on at t = 0 (gravity is off)",
    }
}

crate::outputs! {
    /// The cylinder array's own outputs (see the module documentation).
    pub struct CylinderArrayOutputs {
        cylinder_drag: vr 120, unit "N/m"; "Cylinder array: force of the fluid on the cylinder along the flow, per unit depth (0 in other scenes)",
        cylinder_lift: vr 121, unit "N/m"; "Cylinder array: force of the fluid on the cylinder across the flow, per unit depth (0 in other scenes)",
    }
}

/// Cell length and height over R.
const LENGTH: f64 = 6.0;
const HEIGHT: f64 = 4.0;
/// The cylinder's place among the walls.
const CYLINDER: usize = 2;

/// The scene.
pub struct CylinderArray;

/// Particle spacings along the period.
fn columns(cfg: &SceneConfig) -> i64 {
    (LENGTH * cfg.cylinder_array.cylinder_radius / cfg.dx()).round() as i64
}

/// The period (whole particle spacings) [m].
fn period(cfg: &SceneConfig) -> f64 {
    columns(cfg) as f64 * cfg.dx()
}

/// The cell's height H = 4R [m].
fn height(cfg: &SceneConfig) -> f64 {
    HEIGHT * cfg.cylinder_array.cylinder_radius
}

/// The channel's Newtonian centre-line speed rho g H^2 / (8 eta0) without the cylinder, an upper
/// bound of the flow's speed [m/s].
fn speed_bound(cfg: &SceneConfig) -> f64 {
    cfg.fluid.density * cfg.cylinder_array.cylinder_body_force * height(cfg).powi(2)
        / (8.0 * cfg.fluid.viscosity)
}

impl SceneType for CylinderArray {
    const NAME: &'static str = "cylinder_array";
    const DESCRIPTION: &'static str = "flow through a periodic array of cylinders between two walls, driven by a body force (King & Lind 2021 section IV.B)";
    type Params = CylinderArrayParams;
    type Outputs = CylinderArrayOutputs;
}

impl Scene for CylinderArray {
    /// The cylinder's diameter 2R.
    fn reference_length(&self, cfg: &SceneConfig) -> f64 {
        2.0 * cfg.cylinder_array.cylinder_radius
    }

    fn max_expected_speed(&self, cfg: &SceneConfig) -> f64 {
        speed_bound(cfg).max(1e-3)
    }

    fn velocity_scale(&self, cfg: &SceneConfig) -> f64 {
        speed_bound(cfg).max(1e-12)
    }

    /// 2R / U.
    fn time_scale(&self, cfg: &SceneConfig) -> f64 {
        self.reference_length(cfg) / self.velocity_scale(cfg)
    }

    /// The fluid (the cell less the cylinder) and the wall particles.
    fn estimated_particles(&self, cfg: &SceneConfig) -> f64 {
        let n = cfg.numerics.particles_per_diameter as f64;
        let cells = 0.25 * (LENGTH * HEIGHT - std::f64::consts::PI) * n * n;
        cells + 10.0 * n * LENGTH
    }

    fn validate(&self, cfg: &SceneConfig) -> Result<(), ConfigError> {
        let least = super::channel::MIN_COLUMNS;
        if columns(cfg) < least {
            return Err(ConfigError::Inconsistent(format!(
                "particles_per_diameter = {}: the periodic cell needs at least {least} particle \
                 spacings along its period",
                cfg.numerics.particles_per_diameter
            )));
        }
        Ok(())
    }

    /// Gravity and Monaghan's artificial viscosity off, as in the channel.
    fn effective_config(&self, cfg: &SceneConfig) -> SceneConfig {
        super::channel::body_force_driven(cfg)
    }

    fn has_free_surface(&self) -> bool {
        false
    }

    fn viscous_laplacian(&self) -> bool {
        true
    }

    fn domain(&self, cfg: &SceneConfig) -> Domain {
        Domain::periodic_x(period(cfg))
    }

    fn domain_radius(&self, cfg: &SceneConfig) -> f64 {
        1000.0 * (height(cfg) + period(cfg))
    }

    fn body_force(&self, cfg: &SceneConfig) -> Vec2 {
        Vec2::new(cfg.cylinder_array.cylinder_body_force, 0.0)
    }

    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Wall>) {
        let dx = cfg.dx();
        let (m, h) = (columns(cfg), height(cfg));
        let radius = cfg.cylinder_array.cylinder_radius;
        let cylinder = Ball::obstacle(Vec2::new(0.5 * period(cfg), 0.5 * h), radius);
        let offset = cfg.scheme.wall_lattice_offset();
        let rows = (h / dx + 1.0 - 2.0 * offset).round() as i64;
        let mut fluid = Fluid {
            mass: cfg.fluid.density * dx * dx,
            ..Default::default()
        };
        for j in 0..rows {
            for i in 0..m {
                let x = Vec2::new((i as f64 + 0.5) * dx, (j as f64 + offset) * dx);
                if cylinder.signed_distance(&x) >= offset * dx - 1e-12 * dx {
                    fluid.x.push(x);
                }
            }
        }
        let count = fluid.x.len();
        fluid.v = vec![Vec2::zeros(); count];
        fluid.rho = vec![cfg.fluid.density; count];
        if let Some(a0) = rest {
            fluid.conf = vec![a0; count];
        }
        // As the channel's: the bottom wall along +x, the top one facing down.
        let bottom = Plate::spanning(Vec2::zeros(), Vec2::new(1.0, 0.0), dx, 0, m - 1);
        let top = Plate::spanning(Vec2::new(0.0, h), Vec2::new(-1.0, 0.0), dx, 1 - m, 0);
        (fluid, vec![bottom.into(), top.into(), cylinder.into()])
    }

    /// The health figures of the shared outputs and the cylinder's force.
    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        let f = st.wall_forces.get(CYLINDER).copied().unwrap_or_default();
        Outputs {
            shared: super::channel::health_outputs(st, cfg),
            cylinder_array: CylinderArrayOutputs {
                cylinder_drag: f.x,
                cylinder_lift: f.y,
            },
            ..Default::default()
        }
    }

    fn snapshot_title(&self, cfg: &SceneConfig, field: &str) -> String {
        format!(
            "{} cylinder array, R = {} m, g = {} m/s2 ({}, {} across 2R): coloured by {field}",
            cfg.fluid.rheology,
            cfg.cylinder_array.cylinder_radius,
            cfg.cylinder_array.cylinder_body_force,
            cfg.scheme,
            cfg.numerics.particles_per_diameter
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Value;
    use crate::simulation::Simulation;

    /// The cell builds and steps under every scheme: three walls (two straight, one circle),
    /// no particle inside the cylinder, and the first steps move the fluid along the flow.
    #[test]
    fn the_cell_builds_and_steps_under_every_scheme() {
        for scheme in ["wcsph", "pdri", "isph"] {
            let mut cfg = SceneConfig::default();
            for (k, v) in [
                ("scene", Value::Text("cylinder_array".into())),
                ("scheme", Value::Text(scheme.into())),
                ("rheology", Value::Text("newtonian".into())),
                ("density", Value::Real(1.0)),
                ("viscosity", Value::Real(41.66)),
                ("sound_speed", Value::Real(20.0)),
                ("particles_per_diameter", Value::Integer(8)),
            ] {
                cfg.set(k, v).unwrap();
            }
            let mut sim = Simulation::new(cfg).unwrap();
            let st = sim.state();
            assert_eq!(st.walls.len(), 3);
            assert!(st.walls[0].is_straight() && st.walls[1].is_straight());
            assert!(!st.walls[CYLINDER].is_straight());
            let cyl = &st.walls[CYLINDER];
            assert!(st.fluid.x.iter().all(|x| cyl.signed_distance(x) > 0.0));
            for _ in 0..5 {
                let t = sim.time() + 1e-4;
                sim.advance_to(t).unwrap_or_else(|e| panic!("{scheme}: {e}"));
            }
            let st = sim.state();
            let momentum: f64 = st.fluid.v.iter().map(|v| v.x).sum();
            assert!(momentum > 0.0, "{scheme}: the body force drives the flow");
            if scheme != "isph" {
                // The cylinder's force alone, along the flow.
                assert!(sim.outputs().cylinder_array.cylinder_drag > 0.0, "{scheme}");
            }
        }
    }
}
