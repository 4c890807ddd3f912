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

use super::{time_text, Outputs, Predictions, Scene, SceneConfig, SceneType};
use super::{TimePlot, TimePlotPanel};
use crate::boundary::plate::Plate;
use crate::boundary::wall::Wall;
use crate::config::{real, real_pos, ConfigError};
use crate::diagnostics::SharedOutputs;
use crate::neighbors::Domain;
use crate::particles::Fluid;
use crate::dim::{Tensor, Vector};
use crate::state::State;
use crate::{Mat2, Vec2};
use nalgebra::{Matrix3, Vector3};

crate::params! {
    /// The channel: its width, its period and the force that drives it.
    pub struct ChannelParams {
        channel_width: f64 = real_pos(0.02, 100.0), vr 41, unit "m";
            "Channel scene: distance H between the two walls; particles_per_diameter counts particles across it",
        channel_length: f64 = real(0.0, 0.0, 1000.0), vr 42, unit "m";
            "Channel scene: period along the flow (rounded to whole particle spacings); 0 = channel_width",
        body_force: f64 = real(80.0, 0.0, 1.0e6), vr 43, unit "m/s2";
            "Channel scene: body force per unit mass along the channel, switched on at t = 0 (gravity is off in the channel)",
    }
}

crate::outputs! {
    /// The channel's own outputs (see the module documentation).
    pub struct ChannelOutputs {
        centreline_velocity: vr 114, unit "m/s"; "Channel: flow velocity on the centre line (0 in other scenes)",
        flow_rate: vr 115, unit "m2/s"; "Channel and cylinder array: volume flow rate per unit depth through a cross-section (0 in other scenes)",
        wall_shear_stress: vr 116, unit "Pa"; "Channel: shear stress of the fluid on the walls, mean of both, positive along the flow (0 in other scenes)",
    }
}

/// Fewest particle spacings along the period: the nearest-image neighbour search needs the
/// period to exceed twice the search radius (3.4 dx for the cubic spline at h = 1.5 dx).
pub const MIN_COLUMNS: i64 = 8;

/// The channel scene.
pub struct Channel;

/// The fewest particle spacings a periodic axis of the channel takes: [`MIN_COLUMNS`], or more
/// where a larger smoothing length reaches further.
pub fn least_columns(cfg: &SceneConfig) -> i64 {
    MIN_COLUMNS.max((4.5 * cfg.numerics.smoothing_ratio).ceil() as i64 + 1)
}

/// Number of particle spacings across the flow in 3D (along y, periodic): the fewest the
/// periodic neighbour search allows ([`least_columns`]). Plane Poiseuille flow does not vary
/// across, so a wider period would only cost particles.
pub fn columns_across(cfg: &SceneConfig) -> i64 {
    least_columns(cfg)
}

/// The period across the flow in 3D (along y) \[m\].
pub fn period_across(cfg: &SceneConfig) -> f64 {
    columns_across(cfg) as f64 * cfg.dx()
}

/// Number of particle spacings along the period.
pub fn columns(cfg: &SceneConfig) -> i64 {
    let ch = &cfg.channel;
    let l = if ch.channel_length > 0.0 {
        ch.channel_length
    } else {
        ch.channel_width
    };
    (l / cfg.dx()).round() as i64
}

/// The period along x \[m\] (whole particle spacings).
pub fn period(cfg: &SceneConfig) -> f64 {
    columns(cfg) as f64 * cfg.dx()
}

/// The steady Newtonian centre-line velocity U = rho g H^2 / (8 eta0) [m/s].
pub fn steady_velocity(cfg: &SceneConfig) -> f64 {
    cfg.fluid.density * cfg.channel.body_force * cfg.channel.channel_width.powi(2)
        / (8.0 * cfg.fluid.viscosity)
}

/// The steady wall shear stress rho g H / 2 \[Pa\].
pub fn steady_wall_shear_stress(cfg: &SceneConfig) -> f64 {
    0.5 * cfg.fluid.density * cfg.channel.body_force * cfg.channel.channel_width
}

impl SceneType for Channel {
    const NAME: &'static str = "channel";
    const DESCRIPTION: &'static str = "start-up of plane Poiseuille flow between two walls, periodic along the flow (Waters & King 1970)";
    type Params = ChannelParams;
    type Outputs = ChannelOutputs;
}

impl Scene for Channel {
    /// The bottom wall: the frame of the shared outputs (its force is the shear force on it).
    /// It stays fixed: no input moves a channel wall.
    fn plate_wall(&self) -> Option<usize> {
        Some(0)
    }

    /// The width H.
    fn reference_length(&self, cfg: &SceneConfig) -> f64 {
        cfg.channel.channel_width
    }

    /// The steady Newtonian centre-line speed U = rho g H^2 / (8 eta0); an elastic start-up
    /// overshoots it (Waters & King 1970: 2.85 U at Re = Wi = 1, more when Wi/Re is large), so
    /// elastic models get 3 U. Strongly elastic channels (Wi/Re well above 1) should set
    /// sound_speed themselves.
    fn max_expected_speed(&self, cfg: &SceneConfig) -> f64 {
        let u = steady_velocity(cfg);
        let elastic = !cfg.fluid.is_inelastic();
        (if elastic { 3.0 * u } else { u }).max(1e-3)
    }

    /// The fluid and the two walls' particles (in 3D: times the columns across, three dummy
    /// layers per wall).
    fn estimated_particles(&self, cfg: &SceneConfig) -> f64 {
        let ch = &cfg.channel;
        let ppd = cfg.numerics.particles_per_diameter as f64;
        let along = (ch.channel_length.max(ch.channel_width) / ch.channel_width) * ppd;
        if cfg.numerics.dimension == 3 {
            (ppd + 6.0) * along * columns_across(cfg) as f64
        } else {
            ppd * along + 10.0 * along
        }
    }

    fn validate(&self, cfg: &SceneConfig) -> Result<(), ConfigError> {
        let n = columns(cfg);
        let least = least_columns(cfg);
        if n < least {
            return Err(ConfigError::Inconsistent(format!(
                "channel_length = {} m is {n} particle spacings: the periodic channel needs at \
                 least {least} (raise channel_length or particles_per_diameter)",
                cfg.channel.channel_length,
            )));
        }
        Ok(())
    }

    /// Gravity is off (the body force drives the flow), and so is Monaghan's artificial
    /// viscosity: there are no shocks to capture, and it acts on the approaching pairs of any
    /// shear flow (Fang 2006 eq. 31), adding a viscosity of order alpha h c / 8, a quarter of
    /// the physical one at Fang's alpha = 1 and c = 12.5 m/s (measured: the Newtonian centre
    /// line at 0.80 U).
    fn effective_config(&self, cfg: &SceneConfig) -> SceneConfig {
        body_force_driven(cfg)
    }

    /// Closed by its walls and periodic along the flow.
    fn has_free_surface(&self) -> bool {
        false
    }

    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Wall>) {
        let dx = cfg.dx();
        let (n, m) = (cfg.numerics.particles_per_diameter, columns(cfg));
        let mut fluid = Fluid {
            mass: cfg.fluid.density * dx * dx,
            ..Default::default()
        };
        let (bottom, top, offset) = walls_and_offset(cfg, cfg.channel.channel_width, m, dx);
        // Wall particles (Fang's, Ren's: wcsph, pdri by default) sit on the wall lines, so the
        // fluid rows are at j dx, j = 1 .. n-1. Mirrors (isph) reflect the fluid itself and
        // dummy particles lie at -(k + 1/2) dx: rows at (j + 1/2) dx, j = 0 .. n-1, put the
        // first virtual row dx below the first fluid row, as in the bulk. (Rows at j dx left a
        // gap of 2 dx at each mirror wall: measured, the Newtonian Lagrangian centre line
        // settled 10 % high at 30 across.) The wall model says which
        // (`boundary::Model::lattice_offset`).
        let rows = (n as f64 + 1.0 - 2.0 * offset).round() as i64;
        for j in 0..rows {
            let y = (j as f64 + offset) * dx;
            for i in 0..m {
                fluid.x.push(Vec2::new((i as f64 + 0.5) * dx, y));
            }
        }
        let count = fluid.x.len();
        fluid.v = vec![Vec2::zeros(); count];
        fluid.rho = vec![cfg.fluid.density; count];
        if let Some(a0) = rest {
            fluid.conf = vec![a0; count];
        }
        (fluid, vec![bottom.into(), top.into()])
    }

    /// Fang's nested viscous operator lets the rows next to a wall zigzag (see
    /// [`crate::operators::stress`]); the channel's shear layers need Morris' Laplacian.
    fn viscous_laplacian(&self) -> bool {
        true
    }

    /// Periodic along the flow; in 3D across it (y) too.
    fn domain(&self, cfg: &SceneConfig) -> Domain {
        let d = Domain::periodic_x(period(cfg));
        if cfg.numerics.dimension == 3 {
            d.with_period(1, period_across(cfg))
        } else {
            d
        }
    }

    /// Plane Poiseuille flow between the walls z = 0 and z = H, periodic along x and y
    /// ([`build_3d`]).
    fn three_dimensional(&self) -> bool {
        true
    }

    fn initial_state_3d(&self, cfg: &SceneConfig, rest: Option<Tensor<3>>) -> Option<State<3>> {
        let (fluid, walls) = build_3d(cfg, rest);
        Some(State::new(fluid, walls, self.plate_wall()))
    }

    /// The 2D outputs' definitions over the 3D box: the flow rate per unit depth across
    /// (sum V u_x / (L L_y)), the wall shear stress over both walls' area 2 L L_y.
    fn outputs_3d(&self, st: &State<3>, cfg: &SceneConfig) -> Outputs {
        channel_outputs(st, cfg, period(cfg) * period_across(cfg))
    }

    fn domain_radius(&self, cfg: &SceneConfig) -> f64 {
        1000.0 * (cfg.channel.channel_width + period(cfg))
    }

    fn body_force(&self, cfg: &SceneConfig) -> Vec2 {
        Vec2::new(cfg.channel.body_force, 0.0)
    }

    /// The steady Newtonian centre-line velocity rho g H^2 / (8 eta0).
    fn velocity_scale(&self, cfg: &SceneConfig) -> f64 {
        steady_velocity(cfg).max(1e-12)
    }

    /// H / U (King & Lind's time unit, with H = U = 1).
    fn time_scale(&self, cfg: &SceneConfig) -> f64 {
        cfg.channel.channel_width / self.velocity_scale(cfg)
    }

    /// The health figures of the shared outputs (not the drop's extents, nor the plate's: both
    /// walls carry the force) and the channel's own three. The volume error is sum(m / rho)'s
    /// under every scheme: the closed channel keeps it.
    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        channel_outputs(st, cfg, period(cfg))
    }

    /// The centre-line velocity over the steady Newtonian one, U = rho g H^2 / (8 eta0), and
    /// the wall shear stress over rho g H / 2, against t U / H.
    fn time_plot(&self, cfg: &SceneConfig) -> TimePlot {
        let u = steady_velocity(cfg);
        let tau = steady_wall_shear_stress(cfg);
        let ts = cfg.channel.channel_width / u;
        TimePlot {
            time_unit: ts,
            x_label: format!("t U / H [-]   (H/U = {})", time_text(ts)),
            panels: vec![
                TimePlotPanel {
                    title: format!("centre-line velocity / U (U = {u:.3} m/s)"),
                    y_label: "u_c / U [-]".to_string(),
                    value: Box::new(move |o| o.channel.centreline_velocity / u),
                },
                TimePlotPanel {
                    title: format!("wall shear stress / (rho g H / 2) ({tau:.1} Pa)"),
                    y_label: "tau_w / (rho g H / 2) [-]".to_string(),
                    value: Box::new(move |o| o.channel.wall_shear_stress / tau),
                },
            ],
        }
    }

    /// Where the start-up got to: the centre-line velocity and the wall shear stress at the
    /// end, against their steady Newtonian values.
    fn summary(
        &self,
        cfg: &SceneConfig,
        _st: &State,
        series: &[(f64, Outputs)],
        _predictions: &dyn Predictions,
    ) -> Vec<String> {
        let Some((t, o)) = series.last() else {
            return Vec::new();
        };
        let (u, tau) = (steady_velocity(cfg), steady_wall_shear_stress(cfg));
        let c = &o.channel;
        vec![format!(
            "channel at t = {t:.6} s: centre-line velocity {:.4e} m/s = {:.4} U (U = rho g H^2 / \
             (8 eta0) = {u:.4e} m/s), wall shear stress {:.4e} Pa = {:.4} rho g H / 2",
            c.centreline_velocity,
            c.centreline_velocity / u,
            c.wall_shear_stress,
            c.wall_shear_stress / tau
        )]
    }

    fn snapshot_title(&self, cfg: &SceneConfig, field: &str) -> String {
        format!(
            "{} channel, H = {} mm, g = {} m/s2 ({}, {} across): coloured by {field}",
            cfg.fluid.rheology,
            1e3 * cfg.channel.channel_width,
            cfg.channel.body_force,
            cfg.scheme,
            cfg.numerics.particles_per_diameter
        )
    }
}

/// The 3D channel: the fluid fills the cubic lattice (i dx, j dx, (k + 1/2) dx), i < L / dx,
/// j < [`columns_across`], k < n, between the plane walls z = 0 (normal +z, columns along +x)
/// and z = H (normal -z, columns along -x), each spanning one period along x (fixed columns)
/// and, through the periodic domain, one across. Every 3D wall model puts its particles half a
/// spacing or more beyond the wall plane (dummy layers at -(k + 1/2) dx, mirrors of the fluid),
/// so the fluid fills the whole width, as the 2D mirror lattice does; the fluid's columns line
/// up with the dummy particles' (x = i dx, y = j dx), so the lattice runs on into the walls.
pub fn build_3d(cfg: &SceneConfig, rest: Option<Tensor<3>>) -> (Fluid<3>, Vec<Wall<3>>) {
    let dx = cfg.dx();
    let (n, m, w) = (
        cfg.numerics.particles_per_diameter,
        columns(cfg),
        columns_across(cfg),
    );
    let mut fluid = Fluid::<3> {
        mass: cfg.fluid.density * dx.powi(3),
        ..Default::default()
    };
    for k in 0..n {
        for j in 0..w {
            for i in 0..m {
                fluid.x.push(Vector::<3>::new(
                    i as f64 * dx,
                    j as f64 * dx,
                    (k as f64 + 0.5) * dx,
                ));
            }
        }
    }
    let count = fluid.x.len();
    fluid.v = vec![Vector::<3>::zeros(); count];
    fluid.rho = vec![cfg.fluid.density; count];
    if let Some(a0) = rest {
        fluid.conf = vec![a0; count];
    }
    let h = cfg.channel.channel_width;
    let wall = |z: f64, up: f64, k_min: i64, k_max: i64| {
        let mut p = Plate::<3>::through(
            Vector::<3>::new(0.0, 0.0, z),
            Vector::<3>::new(0.0, 0.0, up),
            Vector::<3>::new(up, 0.0, 0.0),
            dx,
        );
        (p.k_min, p.k_max, p.fixed) = (k_min, k_max, true);
        Wall::from(p)
    };
    // As in 2D, the upper wall's tangent is -x: its columns at s = -k dx sit at x = k dx.
    (fluid, vec![wall(0.0, 1.0, 0, m - 1), wall(h, -1.0, 1 - m, 0)])
}

/// The walls of a 2D channel `h` high with `m` columns of spacing `dx` (the channel's and the
/// cylinder cell's): the bottom wall along +x, the upper one facing down (tangent -x, normal
/// -y; its columns at s = -k dx sit at x = k dx, k = 0 .. m-1), and the distance in spacings
/// from their lines to the first fluid row that their model leaves the fluid
/// (`boundary::Model::lattice_offset`).
pub fn walls_and_offset(cfg: &SceneConfig, h: f64, m: i64, dx: f64) -> (Plate, Plate, f64) {
    let bottom = Plate::spanning(Vec2::zeros(), Vec2::new(1.0, 0.0), dx, 0, m - 1);
    let top = Plate::spanning(Vec2::new(0.0, h), Vec2::new(-1.0, 0.0), dx, 1 - m, 0);
    let offset = cfg.wall_model(&Wall::from(bottom.clone())).lattice_offset();
    (bottom, top, offset)
}

/// A closed cell driven by a body force (the channel, the cylinder array): gravity off, and so
/// is Monaghan's artificial viscosity (see [`Channel`]'s `effective_config`).
pub fn body_force_driven(cfg: &SceneConfig) -> SceneConfig {
    let mut e = cfg.clone();
    e.fluid.gravity = 0.0;
    e.numerics.artificial_viscosity_alpha = 0.0;
    e.numerics.artificial_viscosity_beta = 0.0;
    e
}

/// The channel's outputs in N dimensions over a wall of `area` (2D: the period L, per unit
/// depth; 3D: L times the period across): the flow rate sum V u_x / area, the wall shear stress
/// over both walls, 2 area, and the centre-line velocity.
fn channel_outputs<const N: usize>(st: &State<N>, cfg: &SceneConfig, area: f64) -> Outputs
where
    nalgebra::Const<N>: nalgebra::DimMin<nalgebra::Const<N>, Output = nalgebra::Const<N>>,
{
    let fl = &st.fluid;
    let flow: f64 =
        fl.v.iter()
            .zip(&fl.rho)
            .map(|(v, r)| fl.mass / r * v[0])
            .sum::<f64>()
            / area;
    Outputs {
        shared: health_outputs(st, cfg),
        channel: ChannelOutputs {
            centreline_velocity: centreline_velocity(fl, cfg.channel.channel_width, cfg.dx()),
            flow_rate: flow,
            wall_shear_stress: st.wall_force[0] / (2.0 * area),
        },
        ..Default::default()
    }
}

/// The health figures of the shared outputs only (a closed cell has no drop extents, and no
/// one plate carries its force): kinetic energy, volume error (sum(m / rho)'s under every
/// scheme: a closed cell keeps it), conformation extremes, time step, particle count, voids.
pub fn health_outputs<const N: usize>(st: &State<N>, cfg: &SceneConfig) -> SharedOutputs
where
    nalgebra::Const<N>: nalgebra::DimMin<nalgebra::Const<N>, Output = nalgebra::Const<N>>,
{
    let full = SharedOutputs::compute(st, cfg.dx(), cfg.fluid.density);
    SharedOutputs {
        kinetic_energy: full.kinetic_energy,
        volume_error: full.volume_error,
        max_conformation_trace: full.max_conformation_trace,
        min_conformation_det: full.min_conformation_det,
        time_step: full.time_step,
        particle_count: full.particle_count,
        void_fraction: full.void_fraction,
        ..Default::default()
    }
}

/// u at y = H/2 from a least-squares parabola u = c0 + c1 y' + c2 y'^2 (y' = y - H/2) through
/// the particles within 2 dx of the centre line (0 if there are fewer than three). In 3D the
/// coordinate across the walls is z (the last axis), the flow along x.
pub fn centreline_velocity<const N: usize>(fl: &Fluid<N>, h: f64, dx: f64) -> f64 {
    let mut a = Matrix3::<f64>::zeros();
    let mut b = Vector3::<f64>::zeros();
    let mut count = 0;
    for (x, v) in fl.x.iter().zip(&fl.v) {
        let y = (x[N - 1] - 0.5 * h) / dx;
        if y.abs() <= 2.0 {
            let phi = Vector3::new(1.0, y, y * y);
            a += phi * phi.transpose();
            b += phi * v[0];
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
            scene: crate::scene::SceneKind::Channel,
            ..Default::default()
        };
        c.numerics.particles_per_diameter = 10;
        c.channel.channel_length = 0.0152; // 7.6 spacings of 2 mm: rounds to 8
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
        let walls: Vec<&Plate> = walls.iter().map(|w| w.plate().unwrap()).collect();
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
        c.channel.channel_length = 0.01;
        assert!(Channel.validate(&Channel.effective_config(&c)).is_err());
    }

    #[test]
    fn isph_lattice_fills_the_width_for_the_mirror_walls() {
        // Mirrors reflect the fluid across y = 0 and y = H: the first fluid row half a spacing
        // from the wall puts the first mirror row one spacing below it, as in the bulk.
        let mut c = SceneConfig {
            scene: crate::scene::SceneKind::Channel,
            scheme: crate::scene::SchemeKind::Isph,
            ..Default::default()
        };
        c.numerics.particles_per_diameter = 10;
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
