//! Start-up of plane Poiseuille flow (King & Lind 2021 section IV.A; Fang 2006 names the
//! start-up flow between parallel plates too): fluid at rest between two no-slip walls at y = 0
//! and y = H, periodic along x with period L, driven from t = 0 by a body force g along x
//! (gravity off). Its exact solution for an Oldroyd-B fluid is Waters & King 1970's.
//!
//! The lattice has `particles_per_diameter` = n spacings across the width H (dx = H / n): rows
//! at y = j dx, j = 1 .. n-1, for the schemes with wall particles on the wall lines (wcsph,
//! pdri), n rows at y = (j + 1/2) dx for isph's mirror walls; columns at x = (i + 1/2) dx,
//! L / dx of them (rounded, at least [`MIN_COLUMNS`]) along the period;
//! the walls' columns sit at whole multiples of dx and span exactly one period, and the
//! neighbour search wraps x (no particle is stored twice).
//!
//! Outputs (the drop's hold 0): `centreline_velocity`, the value at y = H/2 of a least-squares
//! parabola through the velocities of the particles within 2 dx of the centre line (exact for
//! the parabolic steady profile, where a plain average of the two middle rows would read
//! 1 - (dx/H)^2 low); `flow_rate`, sum_i V_i u_i / L per unit depth; `wall_shear_stress`, the
//! force of the fluid on both walls along the flow over 2 L. At steady state the walls carry the
//! body force on the fluid between the wall rows, rho g H (n - 1) / (2 n): the half cells next to
//! the wall lines belong to the wall particles (isph: rho g H / 2, the fluid fills the width).

use super::Scene;
use crate::boundary::plate::Plate;
use crate::config::{ConfigError, SceneConfig, SchemeKind};
use crate::diagnostics::Outputs;
use crate::neighbors::Domain;
use crate::particles::Fluid;
use crate::state::State;
use crate::{Mat2, Vec2};
use nalgebra::{Matrix3, Vector3};

/// Fewest particle spacings along the period: the nearest-image neighbour search needs the
/// period to exceed twice the search radius (3.4 dx for the cubic spline at h = 1.5 dx).
pub const MIN_COLUMNS: i64 = 8;

/// The channel scene.
pub struct Channel;

/// Number of particle spacings along the period.
pub fn columns(cfg: &SceneConfig) -> i64 {
    let l = if cfg.channel_length > 0.0 {
        cfg.channel_length
    } else {
        cfg.channel_width
    };
    (l / cfg.dx()).round() as i64
}

/// The period along x [m] (whole particle spacings).
pub fn period(cfg: &SceneConfig) -> f64 {
    columns(cfg) as f64 * cfg.dx()
}

impl Scene for Channel {
    fn validate(&self, cfg: &SceneConfig) -> Result<(), ConfigError> {
        let n = columns(cfg);
        if n < MIN_COLUMNS.max((4.5 * cfg.smoothing_ratio).ceil() as i64 + 1) {
            return Err(ConfigError::Inconsistent(format!(
                "channel_length = {} m is {n} particle spacings: the periodic channel needs at \
                 least {} (raise channel_length or particles_per_diameter)",
                cfg.channel_length,
                MIN_COLUMNS.max((4.5 * cfg.smoothing_ratio).ceil() as i64 + 1)
            )));
        }
        Ok(())
    }

    /// The width sets the lattice (dx = channel_width / particles_per_diameter); gravity, the
    /// impact velocity and the plate inclination do not apply.
    fn effective_config(&self, cfg: &SceneConfig) -> SceneConfig {
        let mut e = cfg.clone();
        e.drop_diameter = cfg.channel_width;
        e.initial_drop_height = cfg.channel_width;
        e.gravity = 0.0;
        e.impact_velocity = 0.0;
        e.plate_inclination = 0.0;
        // No shocks to capture: Monaghan's artificial viscosity (Fang 2006 eq. 31) acts on the
        // approaching pairs of any shear flow and would add a viscosity of order alpha h c / 8,
        // a quarter of the physical one at Fang's alpha = 1 and c = 12.5 m/s (measured: the
        // Newtonian centre line at 0.80 U).
        e.artificial_viscosity_alpha = 0.0;
        e.artificial_viscosity_beta = 0.0;
        e
    }

    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Plate>) {
        let dx = cfg.dx();
        let (n, m) = (cfg.particles_per_diameter, columns(cfg));
        let mut fluid = Fluid {
            mass: cfg.density * dx * dx,
            ..Default::default()
        };
        // Wall particles (wcsph, pdri) sit on the wall lines, so the fluid rows are at j dx,
        // j = 1 .. n-1. Mirrors (isph) reflect the fluid itself: rows at (j + 1/2) dx,
        // j = 0 .. n-1, put the first mirror row dx below the first fluid row, as in the bulk.
        // (Rows at j dx left a gap of 2 dx at each wall: measured, the Newtonian Lagrangian
        // centre line settled 10 % high at 30 across.)
        let rows: Vec<f64> = if cfg.scheme == SchemeKind::Isph {
            (0..n).map(|j| (j as f64 + 0.5) * dx).collect()
        } else {
            (1..n).map(|j| j as f64 * dx).collect()
        };
        for y in rows {
            for i in 0..m {
                fluid.x.push(Vec2::new((i as f64 + 0.5) * dx, y));
            }
        }
        let count = fluid.x.len();
        fluid.v = vec![Vec2::zeros(); count];
        fluid.rho = vec![cfg.density; count];
        if let Some(a0) = rest {
            fluid.conf = vec![a0; count];
        }
        let h = cfg.channel_width;
        let bottom = Plate::spanning(Vec2::zeros(), Vec2::new(1.0, 0.0), dx, 0, m - 1);
        // The upper wall faces down: tangent -x, normal -y; its columns at s = -k dx sit at
        // x = k dx, k = 0 .. m-1.
        let top = Plate::spanning(Vec2::new(0.0, h), Vec2::new(-1.0, 0.0), dx, 1 - m, 0);
        (fluid, vec![bottom, top])
    }

    /// Fang's nested viscous operator lets the rows next to a wall zigzag (see
    /// [`crate::operators::stress`]); the channel's shear layers need Morris' Laplacian.
    fn viscous_laplacian(&self) -> bool {
        true
    }

    fn domain(&self, cfg: &SceneConfig) -> Domain {
        Domain::periodic_x(period(cfg))
    }

    fn domain_radius(&self, cfg: &SceneConfig) -> f64 {
        1000.0 * (cfg.channel_width + period(cfg))
    }

    fn body_force(&self, cfg: &SceneConfig) -> Vec2 {
        Vec2::new(cfg.body_force, 0.0)
    }

    /// The steady Newtonian centre-line velocity rho g H^2 / (8 eta0).
    fn velocity_scale(&self, cfg: &SceneConfig) -> f64 {
        (cfg.density * cfg.body_force * cfg.channel_width.powi(2) / (8.0 * cfg.viscosity))
            .max(1e-12)
    }

    /// H / U (King & Lind's time unit, with H = U = 1).
    fn time_scale(&self, cfg: &SceneConfig) -> f64 {
        cfg.channel_width / self.velocity_scale(cfg)
    }

    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        let full = Outputs::compute(st, cfg.dx(), cfg.density);
        let fl = &st.fluid;
        let (h, l, dx) = (cfg.channel_width, period(cfg), cfg.dx());
        let flow: f64 =
            fl.v.iter()
                .zip(&fl.rho)
                .map(|(v, r)| fl.mass / r * v.x)
                .sum::<f64>()
                / l;
        Outputs {
            kinetic_energy: full.kinetic_energy,
            volume_error: full.volume_error,
            max_conformation_trace: full.max_conformation_trace,
            min_conformation_det: full.min_conformation_det,
            time_step: full.time_step,
            particle_count: full.particle_count,
            void_fraction: full.void_fraction,
            centreline_velocity: centreline_velocity(fl, h, dx),
            flow_rate: flow,
            wall_shear_stress: st.wall_force.x / (2.0 * l),
            ..Default::default()
        }
    }
}

/// u at y = H/2 from a least-squares parabola u = c0 + c1 y' + c2 y'^2 (y' = y - H/2) through
/// the particles within 2 dx of the centre line (0 if there are fewer than three).
pub fn centreline_velocity(fl: &Fluid, h: f64, dx: f64) -> f64 {
    let mut a = Matrix3::<f64>::zeros();
    let mut b = Vector3::<f64>::zeros();
    let mut count = 0;
    for (x, v) in fl.x.iter().zip(&fl.v) {
        let y = (x.y - 0.5 * h) / dx;
        if y.abs() <= 2.0 {
            let phi = Vector3::new(1.0, y, y * y);
            a += phi * phi.transpose();
            b += phi * v.x;
            count += 1;
        }
    }
    if count < 3 {
        return 0.0;
    }
    a.lu().solve(&b).map_or(0.0, |c| c[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_and_walls_span_one_period() {
        let mut c = SceneConfig {
            scene: crate::config::Scene::Channel,
            particles_per_diameter: 10,
            channel_length: 0.0152, // 7.6 spacings of 2 mm: rounds to 8
            ..Default::default()
        };
        let e = Channel.effective_config(&c);
        assert_eq!(columns(&e), 8);
        assert!((period(&e) - 0.016).abs() < 1e-15);
        let (f, walls) = Channel.build(&e, None);
        // Nine fluid rows between the wall rows at y = 0 and y = H.
        assert_eq!(f.len(), 72);
        assert!(f
            .x
            .iter()
            .all(|x| x.x > 0.0 && x.x < 0.016 && x.y > 0.001 && x.y < 0.019));
        // Both walls: normals into the fluid, eight columns at x = 0, dx, ... 7 dx.
        assert_eq!(walls[0].n, Vec2::new(0.0, 1.0));
        assert_eq!(walls[1].n, Vec2::new(0.0, -1.0));
        for w in &walls {
            assert_eq!(w.columns(), 8);
            let mut xs: Vec<f64> = (0..8).map(|c| w.point(w.column_s(c), 0.0).x).collect();
            xs.sort_by(f64::total_cmp);
            for (k, x) in xs.iter().enumerate() {
                assert!((x - k as f64 * 0.002).abs() < 1e-15, "{x}");
            }
        }
        assert!((walls[1].d(&Vec2::new(0.3, 0.015)) - 0.005).abs() < 1e-15);
        c.channel_length = 0.01;
        assert!(Channel.validate(&Channel.effective_config(&c)).is_err());
    }

    #[test]
    fn isph_lattice_fills_the_width_for_the_mirror_walls() {
        // Mirrors reflect the fluid across y = 0 and y = H: the first fluid row half a spacing
        // from the wall puts the first mirror row one spacing below it, as in the bulk.
        let c = SceneConfig {
            scene: crate::config::Scene::Channel,
            scheme: SchemeKind::Isph,
            particles_per_diameter: 10,
            ..Default::default()
        };
        let e = Channel.effective_config(&c);
        let dx = e.dx();
        let (f, _) = Channel.build(&e, None);
        assert_eq!(f.len() as i64, 10 * columns(&e));
        let mut ys: Vec<f64> = f.x.iter().map(|x| x.y).collect();
        ys.sort_by(f64::total_cmp);
        ys.dedup();
        assert_eq!(ys.len(), 10);
        for (j, y) in ys.iter().enumerate() {
            assert!((y - (j as f64 + 0.5) * dx).abs() < 1e-15, "{y}");
        }
    }

    #[test]
    fn centreline_fit_is_exact_for_a_parabola() {
        let (h, dx) = (1.0, 0.05);
        let mut f = Fluid::default();
        for j in 1..20 {
            let y = j as f64 * dx;
            f.x.push(Vec2::new(0.1, y));
            f.v.push(Vec2::new(4.0 * y * (1.0 - y), 0.0));
        }
        assert!((centreline_velocity(&f, h, dx) - 1.0).abs() < 1e-12);
    }
}
