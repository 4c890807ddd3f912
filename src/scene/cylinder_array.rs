//! A periodic array of cylinders between two walls (King & Lind 2021 section IV.B): a cell of
//! length L = 6R and height H = 4R (`cylinder_cell_length`, `cylinder_cell_height`; a cylinder
//! that does not fit the cell is refused), periodic along x, no-slip walls at y = 0 and y = H, a
//! cylinder of radius R at the centre of the cell, the fluid at rest at t = 0 and driven from
//! then on by a uniform body force g along x (gravity off). The reference for it is the finite
//! element solution in `validation/cylinder_array/`.
//!
//! Walls: the two straight walls (wall 0 at the bottom, wall 1 at the top) and the circle
//! (wall 2). Under `wall_boundary = auto` ISPH puts mirror particles on all three and the
//! weakly compressible schemes dummy particles (Adami et al. 2012) on all three; with
//! `cylinder_background_pressure = 0` auto keeps their paper's particles (WCSPH's image, PDRI's
//! ghost) on the straight walls and dummy particles on the cylinder (`image` and `ghost` asked
//! for by name are refused: they cannot be built along the circle). The papers' particles
//! let particles through the walls downstream of the gaps between cylinder and walls: at 8
//! across, Newtonian, WCSPH broke down at t = 3.48 s (a particle at -30 % density next to the
//! wall) and PDRI at t = 2.65 s (a particle through the wall; 2.05 s with the background
//! pressure below), while on dummy walls both ran to t = 6 s.
//!
//! **Background pressure** (WCSPH, PDRI): the closed cell's pressure is fixed only up to a
//! constant, and the weakly compressible schemes add `cylinder_background_pressure` times
//! rho g L H / (2R) to their equation of state, so that the low pressure behind the cylinder
//! stays positive; in tension SPH's particles clump (the tensile instability). On dummy walls
//! at 8 across PDRI without it broke down at t = 0.045 s (holes in the fluid).
//!
//! **Lattice.** `particles_per_diameter` spacings across the cylinder's diameter 2R (dx =
//! 2R / n), rows as in the channel (from the wall lines at the straight walls' model's
//! `boundary::Model::lattice_offset`: one spacing with the papers' wall particles on the
//! line, half a spacing with dummy particles or mirrors, whose rows lie at -(k + 1/2) dx).
//! Next to the cylinder the fluid is laid in rings at R + (k + 1/2) dx, up to six of them
//! (beyond the mirrors' reach 3h = 3.9 dx and the dummy particles' 2h = 3 dx; fewer where the
//! gap to a channel wall holds fewer spacings), and the square lattice starts where they end: the
//! cylinder's virtual particles, mirrors or dummy particles, lie in rings at R -+ (k + 1/2) dx,
//! so the lattice runs on into them. The square lattice cut by a circle leaves gaps of up to
//! 1.5 dx between the first particles and the wall, which mirroring doubles: the kernel sums of
//! the near-wall particles fell to 0.70 of the lattice's, and Morris' Laplacian of the exact
//! Couette field between concentric circles (zero) came out at 0.3 times the wall's shear rate
//! over dx there, at 8, 16 and 32 across alike (an O(1/dx) error that never converges: the
//! wall slipped); on the rings it is 0.04, 0.03, 0.01 (test
//! `mirrors_on_the_ring_lattice_hold_the_couette_field`). Under the weakly compressible
//! schemes the gaps are a volume: the fluid fills them by expanding, and in the closed cell
//! that is a tension of rho0 c^2 times the gaps' share of the area. The old lattice (rows
//! from one spacing, the square lattice cut one spacing from the cylinder) held 15.5 % less
//! than the fluid's area at 8 across and 7.3 % at 16 (the rings and half-spacing rows: 2.3 %
//! and 0.07 %), while the background pressure below covers 1 % (it is 1 % of rho0 c^2).
//! Fluid particles that kept their distance from the dummy particles hid it while the
//! continuity equation read the dummy particles' extrapolated velocity: that doubled the
//! compression rate of a particle approaching a wall, a cushion. With the wall's velocity
//! there (Adami et al. 2012), WCSPH filled the gaps and tore at t = 0.04 s (8 across).
//!
//! Outputs: `cylinder_drag` and `cylinder_lift`, the force of the fluid on the cylinder alone
//! along and across the flow per unit depth, and `wall_shear_force`, the force of the fluid on
//! the two channel walls along the flow (see `State::wall_forces`); `mean_velocity` ⟨u⟩ = sum V u_x
//! / sum V over the fluid (the velocity of King & Lind's Wi = ⟨u⟩ lambda / R and
//! Re = rho ⟨u⟩ R / eta0, which the CLI's summary prints), and the channel's `flow_rate`,
//! sum V u_x / L, the flux through a cross-section.
//!
//! **Momentum balance.** The walls' forces are booked as the momentum each wall gives the fluid
//! in a step, so `sum m u` changes by exactly the body force on the fluid `N m g` less the
//! walls' impulses (ISPH also books the ALE remapping, `State::remap_impulse`): at steady
//! state the body force equals drag plus wall shear (the continuum's `rho g A_fluid = F_cyl +
//! F_walls`; test `the_momentum_balance_closes_at_steady_state`).

use super::{Outputs, Predictions, Scene, SceneConfig, SceneType, SteadyWindow};
use crate::boundary::wall::Wall;
use crate::config::{integer, real, real_pos, ConfigError, WallBoundary};
use crate::geometry::{Ball, Shape};
use crate::neighbors::Domain;
use crate::particles::Fluid;
use crate::state::State;
use crate::{Mat2, Vec2};

crate::params! {
    /// The cell: the cylinder's radius (the cell is 6R by 4R) and the force that drives it.
    pub struct CylinderArrayParams {
        cylinder_radius: f64 = real_pos(1.0, 1000.0), vr 62, unit "m";
            "Cylinder array scene: radius R of the cylinder; the periodic cell is 6 R long and 4 R high unless cylinder_cell_length and cylinder_cell_height say otherwise, particles_per_diameter counts particles across 2 R",
        cylinder_body_force: f64 = real_pos(300.0, 1.0e6), vr 63, unit "m/s2";
            "Cylinder array scene: body force per unit mass along the cell, switched on at t = 0 (gravity is off)",
        cylinder_cell_length: f64 = real(0.0, 0.0, 1.0e4), vr 68, unit "m";
            "Cylinder array scene: length L of the periodic cell, the distance between neighbouring cylinders (rounded to whole particle spacings); 0 = 6 R",
        cylinder_cell_height: f64 = real(0.0, 0.0, 1.0e4), vr 69, unit "m";
            "Cylinder array scene: height H of the cell, the distance between its two walls; 0 = 4 R",
        cylinder_background_pressure: f64 = real(1.0, 0.0, 100.0), vr 99, unit "1";
            "Cylinder array scene, wcsph and pdri: background pressure added to the equation of state, in units of the pressure scale rho g L H / (2 R) (the body force on the cell over the cylinder's diameter, about the pressure difference across the cylinder); it keeps the fluid behind the cylinder out of tension, where the particles clumped and crossed the walls. 0 = none. Ignored under isph",
        stop_at_steady_state: i64 = integer(0, 0, 1), vr 75, unit "";
            "Cylinder array scene: 1 = viscosph run and the benchmarks end the run three time units R/⟨u⟩ after King & Lind's steady state (the flow rate changes by less than 2 % over one time unit), when the averages over those three units are complete; 0 = run to the end time. In the FMU the importer owns time: there it changes nothing, the output steady_state_reached says when the flow is steady",
    }
}

crate::outputs! {
    /// The cylinder array's own outputs (see the module documentation).
    pub struct CylinderArrayOutputs {
        cylinder_drag: vr 120, unit "N/m"; "Cylinder array: force of the fluid on the cylinder along the flow, per unit depth (0 in other scenes)",
        cylinder_lift: vr 121, unit "N/m"; "Cylinder array: force of the fluid on the cylinder across the flow, per unit depth (0 in other scenes)",
        wall_shear_force: vr 172, unit "N/m"; "Cylinder array: force of the fluid on the two channel walls together along the flow, per unit depth (0 in other scenes)",
        mean_velocity: vr 173, unit "m/s"; "Cylinder array: mean flow velocity ⟨u⟩ over the fluid, sum V u / sum V (0 in other scenes)",
        steady_state_reached: vr 174, unit ""; "Cylinder array: 1 from King & Lind's steady state on (the flow rate changed by less than 2 % over the last time unit R/⟨u⟩, checked before every step), 0 before (0 in other scenes)",
        steady_state_time: vr 175, unit "s"; "Cylinder array: the time at which King & Lind's steady state was reached; 0 before (0 in other scenes)",
    }
}

/// King & Lind's cell length and height over R (the defaults).
const LENGTH: f64 = 6.0;
const HEIGHT: f64 = 4.0;
/// The cylinder's place among the walls (the channel walls are 0 and 1).
const CYLINDER: usize = 2;

/// The scene.
pub struct CylinderArray;

/// The cell's length as configured (before rounding to whole spacings) [m].
fn length(cfg: &SceneConfig) -> f64 {
    let c = &cfg.cylinder_array;
    if c.cylinder_cell_length > 0.0 {
        c.cylinder_cell_length
    } else {
        LENGTH * c.cylinder_radius
    }
}

/// Particle spacings along the period.
fn columns(cfg: &SceneConfig) -> i64 {
    (length(cfg) / cfg.dx()).round() as i64
}

/// The period (whole particle spacings) [m].
fn period(cfg: &SceneConfig) -> f64 {
    columns(cfg) as f64 * cfg.dx()
}

/// The cell's height H (4R by default) [m].
fn height(cfg: &SceneConfig) -> f64 {
    let c = &cfg.cylinder_array;
    if c.cylinder_cell_height > 0.0 {
        c.cylinder_cell_height
    } else {
        HEIGHT * c.cylinder_radius
    }
}

/// The mean velocity over the fluid, sum V u_x / sum V (the reference's `u_mean_fluid`), and
/// the flow rate sum V u_x / L [m2/s]: the flux through a cross-section, equal for every
/// section of a divergence-free periodic flow.
fn mean_velocity_and_flow_rate(fl: &Fluid, period: f64) -> (f64, f64) {
    let (mut vol, mut flux) = (0.0, 0.0);
    for (v, r) in fl.v.iter().zip(&fl.rho) {
        let vi = fl.mass / r;
        vol += vi;
        flux += vi * v.x;
    }
    let mean = if vol > 0.0 { flux / vol } else { 0.0 };
    (mean, flux / period)
}

/// King & Lind's steady state in a record of outputs (section IV.B): the first recorded time
/// `time` at which the flow rate differs by less than 2 % from its value one time unit
/// `unit` = R / ⟨u⟩ earlier (linear between records), and the means of the cylinder's outputs
/// and the flow rate over the next three time units (trapezoidal rule over the records), if
/// the record reaches that far.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyState {
    pub time: f64,
    pub unit: f64,
    /// Means of drag, lift, wall shear force, mean velocity and flow rate over
    /// `[time, time + 3 unit]`.
    pub means: Option<[f64; 5]>,
}

/// The flow rate at time `t` of samples (time, flow rate) sorted by time (linear between
/// them).
fn flow_rate_at(samples: &[(f64, f64)], t: f64) -> f64 {
    let k = samples.partition_point(|(s, _)| *s < t).clamp(1, samples.len() - 1);
    let ((t0, a), (t1, b)) = (samples[k - 1], samples[k]);
    let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 };
    a + w * (b - a)
}

/// King & Lind's criterion at the last of `samples` (time, flow rate, sorted by time) with
/// the time unit `unit` = R / ⟨u⟩ there: the flow rate differs by less than 2 % from its value
/// one time unit earlier, which the samples must reach back to. The one test of steadiness,
/// of a record of outputs ([`steady_state`]) and of the run itself ([`SteadyTracker`]).
fn settled(samples: &[(f64, f64)], unit: f64) -> bool {
    let (Some(&(t, q)), Some(&(t_first, _))) = (samples.last(), samples.first()) else {
        return false;
    };
    let earlier = t - unit;
    samples.len() > 1
        && earlier >= t_first
        && (q - flow_rate_at(samples, earlier)).abs() < 0.02 * q.abs()
}

/// The time unit R / ⟨u⟩ of a flow with mean velocity `u`, None while the flow is at rest or
/// runs backwards.
fn time_unit(radius: f64, u: f64) -> Option<f64> {
    (u > 0.0).then(|| radius / u)
}

/// The cylinder's averaged quantities of one output row.
fn averaged(o: &Outputs) -> [f64; 5] {
    let c = &o.cylinder_array;
    [
        c.cylinder_drag,
        c.cylinder_lift,
        c.wall_shear_force,
        c.mean_velocity,
        o.channel.flow_rate,
    ]
}

/// King & Lind's steady state of a record (see [`SteadyState`]) for a cylinder of radius
/// `radius`, not before `earliest` ([`earliest_steady_time`]); None if the flow rate never
/// settled to 2 % over a time unit.
pub fn steady_state(
    series: &[(f64, Outputs)],
    radius: f64,
    earliest: f64,
) -> Option<SteadyState> {
    let samples: Vec<(f64, f64)> = series.iter().map(|(t, o)| (*t, o.channel.flow_rate)).collect();
    let (time, unit) = series.iter().enumerate().find_map(|(k, (t, o))| {
        let unit = time_unit(radius, o.cylinder_array.mean_velocity)?;
        (*t >= earliest && settled(&samples[..=k], unit)).then_some((*t, unit))
    })?;
    Some(steady_means(series, time, unit))
}

/// The means of a record over the three time units from a steady state reached at `time` with
/// the time unit `unit` (trapezoidal rule over the records in the window, divided by the span
/// they cover), if the record reaches that far. The run's own criterion holds before a step,
/// between two records, so the window's first record can come up to an output interval after
/// `time`: divided by the span from `time`, every mean came out low by that interval over three
/// units (King & Lind's cell, outputs every 0.05 s, 16 across: drag + wall shear 0.984 of the
/// body force in the means where every record holds 1.00000).
pub fn steady_means(series: &[(f64, Outputs)], time: f64, unit: f64) -> SteadyState {
    let end = time + 3.0 * unit;
    let last = series.last().map_or(time, |(t, _)| *t);
    // (Rounding: `end` recomputed from a window's ends may differ from theirs in the last bit.)
    let means = (last >= end - 1e-9 * unit).then(|| {
        let mut sum = [0.0; 5];
        let rows: Vec<_> = series
            .iter()
            .filter(|(t, _)| *t >= time && *t <= end)
            .collect();
        for w in rows.windows(2) {
            let (a, b) = (averaged(&w[0].1), averaged(&w[1].1));
            let dt = w[1].0 - w[0].0;
            for (s, (x, y)) in sum.iter_mut().zip(a.iter().zip(&b)) {
                *s += 0.5 * (x + y) * dt;
            }
        }
        let span = match (rows.first(), rows.last()) {
            (Some(a), Some(b)) => b.0 - a.0,
            _ => 0.0,
        };
        sum.map(|s| if span > 0.0 { s / span } else { 0.0 })
    });
    SteadyState { time, unit, means }
}

/// Samples of the flow rate kept per time unit by [`SteadyTracker`].
const SAMPLES_PER_UNIT: f64 = 64.0;

/// Relaxation times an elastic start-up lasts before King & Lind's criterion is tested: the
/// polymer stress builds up as 1 - e^{-t/lambda}, still 2 % short of its steady value at
/// t = 3.9 lambda. Before that the flow rate can pause for a time unit while the stress grows:
/// at Wi = 0.8 (16 across, ISPH) the criterion held at t = 0.79 s = 1.0 lambda, with ⟨u⟩ 1.127
/// m/s there against 0.96-1.06 m/s at the neighbouring Wi's steady states.
pub const START_UP_RELAXATION_TIMES: f64 = 4.0;

/// The earliest time King & Lind's criterion may hold for the fluid of `cfg`: 0 for a fluid
/// without memory, [`START_UP_RELAXATION_TIMES`] relaxation times for an elastic one.
pub fn earliest_steady_time(cfg: &SceneConfig) -> f64 {
    use crate::config::RheologyKind;
    match cfg.fluid.rheology {
        RheologyKind::Newtonian | RheologyKind::Cross => 0.0,
        _ => START_UP_RELAXATION_TIMES * cfg.fluid.relaxation_time,
    }
}

/// King & Lind's criterion followed during the run, before every step (the scene's data in
/// the state, [`crate::state::SceneState`], so a saved FMU state carries it): the flow rate
/// sampled at least a 64th of a time unit apart over the last two time units, and once the
/// criterion holds (not before `earliest`), when (it is not tested again). What the output
/// `steady_state_reached` reports and what ends a run under `stop_at_steady_state`. Between
/// samples a step costs one look at the tracker ([`SteadyTracker::due`]), not a sum over the
/// fluid.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SteadyTracker {
    /// (time, flow rate), sorted by time.
    samples: Vec<(f64, f64)>,
    /// The time unit R / ⟨u⟩ at the last sample: the next one is due a 64th of it later.
    unit: f64,
    /// The time the criterion first held and the time unit R / ⟨u⟩ then.
    pub reached: Option<(f64, f64)>,
}

impl SteadyTracker {
    /// The tracker of a state (a fresh one if the state holds none).
    pub fn of(st: &State) -> Self {
        st.scene.decode().unwrap_or_default()
    }

    /// Whether a sample is due at time `t`: not steady yet, and a 64th of the last sample's
    /// time unit since it (at once if there is none).
    pub fn due(&self, t: f64) -> bool {
        self.reached.is_none()
            && self
                .samples
                .last()
                .is_none_or(|(s, _)| t - s >= self.unit / SAMPLES_PER_UNIT)
    }

    /// Take the flow at time `t` (flow rate `q`, mean velocity `u`) into account, the
    /// criterion tested from `earliest` on.
    fn observe(&mut self, t: f64, q: f64, u: f64, radius: f64, earliest: f64) {
        if !self.due(t) {
            return;
        }
        let Some(unit) = time_unit(radius, u) else {
            return;
        };
        self.unit = unit;
        self.samples.push((t, q));
        if t >= earliest && settled(&self.samples, unit) {
            self.reached = Some((t, unit));
            self.samples.clear();
            return;
        }
        // Keep two time units, the first sample before them included.
        let keep = self.samples.partition_point(|(s, _)| *s < t - 2.0 * unit);
        self.samples.drain(..keep.saturating_sub(1));
    }
}

/// Where a run stands against King & Lind's steady state (see [`Scene::steady_window`]).
pub fn steady_window(cfg: &SceneConfig, st: &State) -> Option<SteadyWindow> {
    let (start, unit) = SteadyTracker::of(st).reached?;
    Some(SteadyWindow {
        start,
        end: start + 3.0 * unit,
        stop: cfg.cylinder_array.stop_at_steady_state == 1,
        lower: Vec2::zeros(),
        upper: Vec2::new(period(cfg), height(cfg)),
        centre_line: 0.5 * height(cfg),
        periodic_x: true,
    })
}

/// The drag coefficient K = F / (eta0 ⟨u⟩) of King & Lind's cell for a Newtonian fluid, from
/// the finite-element solution in `validation/cylinder_array/` (Taylor-Hood, extrapolated,
/// uncertainty 2.4e-6).
pub const REFERENCE_DRAG_COEFFICIENT: f64 = 92.82999;

/// The channel's Newtonian centre-line speed rho g H^2 / (8 eta0) without the cylinder, an upper
/// bound of the flow's speed [m/s].
fn speed_bound(cfg: &SceneConfig) -> f64 {
    cfg.fluid.density * cfg.cylinder_array.cylinder_body_force * height(cfg).powi(2)
        / (8.0 * cfg.fluid.viscosity)
}

/// The pressure scale of the cell, rho g L H / (2R): the body force on the cell carried by a
/// pressure difference across the cylinder's diameter (3600 Pa in King & Lind's cell; the FEM's
/// drag 3938 N/m is 2R times 1969 Pa) [Pa].
fn pressure_scale(cfg: &SceneConfig) -> f64 {
    let c = &cfg.cylinder_array;
    cfg.fluid.density * c.cylinder_body_force * period(cfg) * height(cfg) / (2.0 * c.cylinder_radius)
}

/// The most rings of fluid particles round the cylinder: beyond the mirrors' reach (3h = 3.9
/// dx) and the dummy particles' (2h = 3 dx at the default smoothing ratio), so the seam with
/// the square lattice sees none.
const MAX_RINGS: usize = 6;

/// Rings round the cylinder for the scene `cfg`: [`MAX_RINGS`], fewer where the gap to the
/// next cylinder holds fewer whole spacings, or the gap to a channel wall fewer rings whose
/// last stays `offset` spacings from the wall line (the straight walls' first fluid row,
/// `boundary::Model::lattice_offset`: a ring half a spacing from Fang's or Ren's wall
/// particles on the line would sit inside their half cell).
fn ring_count(cfg: &SceneConfig, offset: f64) -> usize {
    let (dx, r) = (cfg.dx(), cfg.cylinder_array.cylinder_radius);
    let to_wall = (0.5 * height(cfg) - r) / dx - offset + 0.5;
    let to_next = (0.5 * period(cfg) - r) / dx;
    ((to_wall.min(to_next) + 1e-9).floor().max(0.0) as usize).min(MAX_RINGS)
}

/// `rings` rings of particles round `cylinder` at the distances (k + 1/2) dx, each divided
/// into the even number of arcs nearest dx (as the dummy particles' rings inside a cylinder,
/// `boundary::dummy`; even, so the lattice is fore-aft symmetric like the square one), every
/// other ring turned by half an arc.
pub(crate) fn ring_lattice(cylinder: &Ball<2>, rings: usize, dx: f64) -> Vec<Vec2> {
    let mut out = Vec::new();
    for k in 0..rings {
        let r = cylinder.radius + (k as f64 + 0.5) * dx;
        let arcs = 2 * (std::f64::consts::PI * r / dx).round().max(1.0) as usize;
        let turn = if k % 2 == 1 { 0.5 } else { 0.0 };
        for q in 0..arcs {
            let a = 2.0 * std::f64::consts::PI * (q as f64 + turn) / arcs as f64;
            out.push(cylinder.centre + r * Vec2::new(a.cos(), a.sin()));
        }
    }
    out
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

    /// The larger of the flow's speed bound and the speed whose dynamic pressure is the
    /// pressure difference across the cylinder, sqrt(g L H / (2R)): the automatic sound speed
    /// (ten times this) then keeps the density within about 1 % of rho. In creeping flow the
    /// pressure scales with the viscous stresses, not with rho U^2: the body force on the cell,
    /// rho g L H, is carried mostly by the pressure on the cylinder's diameter 2R (at King &
    /// Lind's Re = 0.024, 3600 Pa against rho U^2 = 1 Pa). Measured at 8 across with
    /// `sound_speed = 20` (rho c^2 = 400 Pa): WCSPH broke up behind the cylinder at t = 0.03 s.
    fn max_expected_speed(&self, cfg: &SceneConfig) -> f64 {
        let pressure = (pressure_scale(cfg) / cfg.fluid.density).sqrt();
        speed_bound(cfg).max(pressure).max(1e-3)
    }

    fn velocity_scale(&self, cfg: &SceneConfig) -> f64 {
        speed_bound(cfg).max(1e-12)
    }

    /// `cylinder_background_pressure` times the pressure scale rho g L H / (2R), the pressure
    /// difference the body force sets up across the cylinder.
    fn background_pressure(&self, cfg: &SceneConfig) -> f64 {
        cfg.cylinder_array.cylinder_background_pressure * pressure_scale(cfg)
    }

    /// 2R / U.
    fn time_scale(&self, cfg: &SceneConfig) -> f64 {
        self.reference_length(cfg) / self.velocity_scale(cfg)
    }

    /// The fluid (the cell less the cylinder) and the wall particles.
    fn estimated_particles(&self, cfg: &SceneConfig) -> f64 {
        let (r, dx) = (cfg.cylinder_array.cylinder_radius, cfg.dx());
        let area = length(cfg) * height(cfg) - std::f64::consts::PI * r * r;
        area / (dx * dx) + 10.0 * length(cfg) / dx
    }

    fn validate(&self, cfg: &SceneConfig) -> Result<(), ConfigError> {
        let d = 2.0 * cfg.cylinder_array.cylinder_radius;
        for (name, size) in [
            ("cylinder_cell_height", height(cfg)),
            ("cylinder_cell_length", length(cfg)),
        ] {
            if d >= size {
                return Err(ConfigError::Inconsistent(format!(
                    "{name} = {size} m: the cylinder (cylinder_radius = {} m) does not fit the \
                     cell, whose {name} must exceed the diameter {d} m",
                    cfg.cylinder_array.cylinder_radius
                )));
            }
        }
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

    /// Gravity and Monaghan's artificial viscosity off, as in the channel; under the weakly
    /// compressible schemes with the background pressure on (the default) `wall_boundary =
    /// auto` means dummy particles on all three walls (module documentation, "Walls"). With
    /// `cylinder_background_pressure = 0` auto keeps the papers' particles on the straight walls
    /// and dummy particles on the cylinder: the cell is then steady by t = 0.6 s at 8 across but
    /// breaks down later (WCSPH at 3.5 s, PDRI at 2.7 s), while dummy walls without the
    /// background pressure tear PDRI's fluid at once (holes at t = 0.045 s).
    fn effective_config(&self, cfg: &SceneConfig) -> SceneConfig {
        let mut e = super::channel::body_force_driven(cfg);
        if e.numerics.wall_boundary == WallBoundary::Auto
            && !e.scheme.is_incompressible()
            && e.cylinder_array.cylinder_background_pressure > 0.0
        {
            e.numerics.wall_boundary = WallBoundary::Dummy;
        }
        e
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
        // The channel's walls; the rows start where their model leaves the fluid room.
        let (bottom, top, offset) = super::channel::walls_and_offset(cfg, h, m, dx);
        let rows = (h / dx + 1.0 - 2.0 * offset).round() as i64;
        let mut fluid = Fluid {
            mass: cfg.fluid.density * dx * dx,
            ..Default::default()
        };
        // Rings round the cylinder (module documentation, "Lattice"), the square lattice from
        // `rings` spacings on: the cylinder's mirrors or dummy particles (the two models a
        // circle takes) lie in rings at R -+ (k + 1/2) dx.
        let rings = ring_count(cfg, offset);
        fluid.x.extend(ring_lattice(&cylinder, rings, dx));
        let cut = if rings > 0 { rings as f64 } else { 0.5 };
        for j in 0..rows {
            for i in 0..m {
                let x = Vec2::new((i as f64 + 0.5) * dx, (j as f64 + offset) * dx);
                if cylinder.signed_distance(&x) >= cut * dx - 1e-12 * dx {
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
        (fluid, vec![bottom.into(), top.into(), cylinder.into()])
    }

    /// King & Lind's criterion, on the state the step starts from ([`SteadyTracker`]).
    fn before_step(&self, cfg: &SceneConfig, st: &mut State) {
        let mut tracker = SteadyTracker::of(st);
        if !tracker.due(st.time) {
            return;
        }
        let (u, q) = mean_velocity_and_flow_rate(&st.fluid, period(cfg));
        let r = cfg.cylinder_array.cylinder_radius;
        tracker.observe(st.time, q, u, r, earliest_steady_time(cfg));
        st.scene = crate::state::SceneState::encode(&tracker);
    }

    fn steady_window(&self, cfg: &SceneConfig, st: &State) -> Option<SteadyWindow> {
        steady_window(cfg, st)
    }

    /// The health figures of the shared outputs and the cylinder's force.
    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        let steady = SteadyTracker::of(st).reached;
        let f = st.wall_forces.get(CYLINDER).copied().unwrap_or_default();
        let shear = st.wall_forces.iter().take(CYLINDER).map(|f| f.x).sum();
        let (mean, flow) = mean_velocity_and_flow_rate(&st.fluid, period(cfg));
        Outputs {
            shared: super::channel::health_outputs(st, cfg),
            channel: super::channel::ChannelOutputs {
                flow_rate: flow,
                ..Default::default()
            },
            cylinder_array: CylinderArrayOutputs {
                cylinder_drag: f.x,
                cylinder_lift: f.y,
                wall_shear_force: shear,
                mean_velocity: mean,
                steady_state_reached: if steady.is_some() { 1.0 } else { 0.0 },
                steady_state_time: steady.map_or(0.0, |(t, _)| t),
            },
            ..Default::default()
        }
    }

    /// The flow at the end: ⟨u⟩, Q, the drag and its coefficient K = F / (eta0 ⟨u⟩) (against
    /// the finite-element value of King & Lind's Newtonian cell), the momentum balance, and
    /// King & Lind's Wi = ⟨u⟩ lambda / R and Re = rho ⟨u⟩ R / eta0.
    fn summary(
        &self,
        cfg: &SceneConfig,
        st: &State,
        series: &[(f64, Outputs)],
        _predictions: &dyn Predictions,
    ) -> Vec<String> {
        let Some((t, o)) = series.last() else {
            return Vec::new();
        };
        let c = &o.cylinder_array;
        let (r, eta0, rho) = (
            cfg.cylinder_array.cylinder_radius,
            cfg.fluid.viscosity,
            cfg.fluid.density,
        );
        let u = c.mean_velocity;
        let body = st.fluid.len() as f64 * st.fluid.mass * cfg.cylinder_array.cylinder_body_force;
        let mut lines = vec![format!(
            "cylinder array at t = {t:.6} s: ⟨u⟩ = {u:.6e} m/s, flow rate {:.6e} m2/s, \
             Wi = ⟨u⟩ lambda / R = {:.4}, Re = rho ⟨u⟩ R / eta0 = {:.4e}",
            o.channel.flow_rate,
            u * cfg.fluid.relaxation_time / r,
            rho * u * r / eta0
        )];
        if st.wall_forces.is_empty() {
            lines.push(format!(
                "cylinder array: the scheme does not split the walls' force (all walls: {:.6e} \
                 N/m along the flow; body force on the fluid {body:.6e} N/m)",
                st.wall_force.x
            ));
        } else {
            lines.push(format!(
                "cylinder array: drag {:.6e} N/m, lift {:.3e} N/m, K = F / (eta0 ⟨u⟩) = {:.5} \
                 (finite elements, King & Lind's Newtonian cell: {REFERENCE_DRAG_COEFFICIENT}); \
                 wall shear force {:.6e} N/m; drag + wall shear = {:.5} of the body force on \
                 the fluid ({body:.6e} N/m)",
                c.cylinder_drag,
                c.cylinder_lift,
                c.cylinder_drag / (eta0 * u),
                c.wall_shear_force,
                (c.cylinder_drag + c.wall_shear_force) / body
            ));
        }
        // The run's own verdict (checked before every step) if it has one, else the record's.
        let steady = match SteadyTracker::of(st).reached {
            Some((time, unit)) => Some(steady_means(series, time, unit)),
            None => steady_state(series, r, earliest_steady_time(cfg)),
        };
        let Some(steady) = steady else {
            lines.push(
                "cylinder array: not steady (King & Lind's criterion: the flow rate changes by \
                 less than 2 % over one time unit R / ⟨u⟩)"
                    .to_string(),
            );
            return lines;
        };
        lines.push(match steady.means {
            Some([drag, lift, shear, u, q]) => format!(
                "cylinder array: steady at t = {:.6} s (time unit R / ⟨u⟩ = {:.4e} s); means \
                 over the next 3 time units: drag {drag:.6e} N/m, lift {lift:.3e} N/m, wall \
                 shear force {shear:.6e} N/m, ⟨u⟩ = {u:.6e} m/s, flow rate {q:.6e} m2/s, \
                 K = {:.5}, drag + wall shear = {:.5} of the body force",
                steady.time,
                steady.unit,
                drag / (eta0 * u),
                (drag + shear) / body
            ),
            None => format!(
                "cylinder array: steady at t = {:.6} s (time unit R / ⟨u⟩ = {:.4e} s); the run \
                 ends before 3 more time units, no means",
                steady.time, steady.unit
            ),
        });
        lines
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
#[path = "cylinder_array_tests.rs"]
mod tests;
