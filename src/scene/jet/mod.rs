//! The buckling jet of King & Lind 2021 section IV.D: a planar jet of width D leaves a nozzle
//! whose exit is H above the impact point at the speed U0, falls under gravity onto the plate
//! (any inclination) and, above a critical fall height, buckles and folds on the heap it builds.
//! Optional side walls of a container stand perpendicular to the plate at s = +/- W/2.
//!
//! **Geometry.** The nozzle axis is the vertical through the impact point (the plate's origin);
//! the exit is the horizontal segment |x| < D/2 at y = H. `particles_per_diameter` counts
//! particles across D (dx = D / n), and the columns of the inflow sit at x = (i + 1/2) dx - D/2.
//!
//! **Inflow (a buffer of prescribed-velocity particles).** King & Lind cite moving ghost
//! particles for their inflow and give no details; ours is the buffer such inlets share: the
//! nozzle holds [`buffer_rows`] rows of fluid particles above the exit (enough to fill the
//! kernel support of a particle just below it), on the lattice y_k = H + (k + 1/2) dx - phi,
//! k = 0, 1, ..., where phi in [0, dx) is the length of fluid that has entered since the last row
//! was emitted ([`InflowLog`]). Before every step ([`Scene::before_step`]) phi grows by
//! U0 times the time since the last step (U0 in force over that step: `jet_velocity` is an input,
//! which a co-simulation master may change at any communication point); each time it passes dx a new row is emitted at the top
//! (so the mass entering per unit time is rho U0 D exactly, to within one row of rho D dx); and
//! every particle inside the nozzle gets the prescribed state back: velocity (0, -U0), density
//! rho0 (zero pressure in the weakly compressible schemes, the free jet's pressure at the exit)
//! and the model's conformation at rest (zero polymer stress). A particle is in the nozzle by
//! its position alone ([`Nozzle::contains`]): particles carry no flag, so nothing depends on
//! their order. A row leaves the nozzle when it crosses the exit line and is free fluid from
//! then on. The momentum of every reset and of every emitted particle is summed in
//! `Inflow::momentum` (the state's inlet), so the fluid's momentum balance closes: the wall impulse equals the
//! inflow's momentum plus the gravity impulse on all particles minus the momentum held.
//! A scheme that needs a pressure condition at the inlet (ISPH: Neumann, King & Lind's moving
//! ghosts) finds the inlet particles the same way, through [`Inflow::holds`](crate::state::Inflow::holds) on the state.
//!
//! **Outputs** (besides the health figures, the wall forces and `particle_count`):
//!
//! | output | definition |
//! |---|---|
//! | `injected_mass` | mass emitted by the inlet since t = 0 [kg/m]: rows emitted x n x rho0 dx^2 |
//! | heap | the free particles (not in the nozzle) that are *not falling*: their velocity towards the plate -v.n is below U0 cos(theta) / 2. The falling column leaves the nozzle at U0 and gravity only speeds it up, so it is told apart from the heap by its speed, not by a height; where the column folds over on the heap it slows down and counts as heap |
//! | `drop_width` | along-plate extent of the heap + dx (0 before impact) |
//! | `drop_height` | largest distance of heap particles from the plate + dx/2 (0 before impact) |
//! | `spread_front`, `spread_back` | downhill and uphill reach of the heap along the plate, as for the drop |
//! | `jet_deflection` | horizontal offset from the nozzle axis of the centre of the free particles near the height (their mean x, weighted by 1 - |y - y_m| / 2dx over |y - y_m| < 2 dx, so that particles enter and leave the band smoothly, and within 2D of the axis, the column's reach: beyond it at that height is heap spreading sideways) y_m = min(y_heap + D, H - D/2), where y_heap is the vertical height above the impact point of the heap's top (its highest particle + dx/2; 0 before impact): one jet width above the heap, where only the falling column is, unless the heap comes within 3D/2 of the nozzle (low nozzles), when the band is half a jet width below the exit and cuts the column where it enters the heap. 0 while no particle is there. It stays near 0 while the jet falls straight and oscillates when it buckles |
//! | `jet_tip_height` | height above the plate of the fluid's lowest point: the lowest particle's distance from the plate less dx/2 (the nozzle's height H at the start, about 0 once the jet has landed) |
//! | `jet_coil_radius`, `jet_coil_frequency` | the round jet's coil (3D only, 0 in 2D): the distance from the axis of the column's centre in `jet_deflection`'s band, and the turns per second of that centre about the axis ([`Coil`]) |
//!
//! [`buckling`] turns a record of `jet_deflection` into the onset time, frequency and amplitude
//! of the buckling; [`arrival`] reads from `jet_tip_height` when the fluid's lowest point came
//! within a height of the plate, the way the slender models define their arrival (their free
//! end's fall): within D/2, where the plate is not yet felt, and within half a spacing (contact).
//!
//! **The round jet (`dimension = 3`).** The nozzle is the disc of diameter D = `jet_width` about
//! the vertical (z) axis through the impact point, its exit at z = H; the plate the drop's
//! ([`super::drop::plate_3d`], inclined about y, downhill towards +x). Each row is the
//! [`disc_lattice`] (concentric rings, each particle standing for dx^2 of the disc) and every
//! particle has the mass rho0 (pi D^2 / 4) dx / (particles per row), so that a row is
//! rho0 pi D^2 / 4 dx and the inlet's mass flux rho0 (pi D^2 / 4) U0 whatever the lattice; the
//! inflow is the 2D one otherwise (the same [`InflowLog`], phase and resets, the seed along x),
//! and a particle is in the nozzle when it is above the exit within D/2 of the axis
//! ([`Inflow::holds`](crate::state::Inflow::holds)). `injected_mass` is then in kg;
//! `jet_deflection` is the mean x of the free particles in the band (within 2 D of the axis in
//! any direction): along the seed's direction; `jet_coil_radius` that centre's distance from
//! the axis and `jet_coil_frequency` its turns per second about it ([`Coil`], followed before
//! every step). No container (side walls are refused by name).
//! The reference for the fall is the slender-thread model (`viscosph_reference`'s
//! `falling_thread`, Matovich & Pearson 1969's axisymmetric thread).

use super::{Outputs, Predictions, Scene, SceneConfig, SceneType};
use crate::boundary::plate::Plate;
use crate::boundary::wall::Wall;
use crate::config::{real, real_pos, ConfigError, IsphFreeSurface};
use crate::diagnostics::SharedOutputs;
use crate::particles::Fluid;
use crate::dim::{Tensor, Vector};
use crate::state::State;
use crate::{Mat2, Vec2};

mod buckling;
mod coil;
mod column;
mod nozzle;

pub use buckling::{arrival, buckling, summary, summary_3d, Buckling, ONSET_FRACTION};
pub use coil::Coil;
pub use column::{column, Column};
pub use nozzle::{
    buffer_rows, disc_lattice, inflow_log, inflow_velocity, side_walls, InflowLog, Nozzle, SEED,
};

crate::params! {
    /// The jet: its width, its nozzle, its speed and its container.
    pub struct JetParams {
        jet_width: f64 = real_pos(0.006, 10.0), vr 45, unit "m";
            "Jet scene: width D of the planar jet at the nozzle exit (King & Lind 2021: 6 mm); particles_per_diameter counts particles across it",
        nozzle_height: f64 = real_pos(0.072, 100.0), vr 46, unit "m";
            "Jet scene: height of the nozzle exit above the impact point, measured vertically (King & Lind 2021: 12 D)",
        jet_velocity: f64 = real(0.2, 0.0, 100.0), vr 47, unit "m/s", input;
            "Input: jet scene: speed of the fluid leaving the nozzle, vertically down (King & Lind 2021: 0.2 m/s). A co-simulation master (a pump or valve model) may change it at every communication point; this is its start value, which also sets the automatic sound speed",
        max_jet_velocity: f64 = real(0.0, 0.0, 100.0), vr 67, unit "m/s";
            "Jet scene: largest jet_velocity the input may drive in this run, which the automatic sound speed covers; 0 = jet_velocity's start value. An input asking for more is refused by name (the FMU: fmi2Discard)",
        container_width: f64 = real(0.0, 0.0, 100.0), vr 48, unit "m";
            "Jet scene: distance between the container's side walls, centred on the impact point and perpendicular to the plate; 0 = no side walls",
    }
}

crate::outputs! {
    /// The jet's own outputs (see the module documentation).
    pub struct JetOutputs {
        injected_mass: vr 118, unit "kg/m"; "Jet: mass that has entered through the nozzle since t = 0: in 2D per unit depth [kg/m], in 3D the round jet's mass in kg (0 in other scenes)",
        jet_deflection: vr 119, unit "m"; "Jet: horizontal offset of the falling column from the nozzle axis, one jet width above the heap (0 in other scenes)",
        jet_coil_radius: vr 209, unit "m"; "Jet, round (dimension = 3): distance from the nozzle axis of the centre of the column's lowest part (the band one jet width above the heap where jet_deflection is measured): 0 while the jet falls straight, the coil's radius once it coils (0 in 2D and in other scenes)",
        jet_coil_frequency: vr 210, unit "Hz"; "Jet, round (dimension = 3): turns per second of the column's lowest part about the nozzle axis (the azimuth of the centre that jet_coil_radius measures, followed at every step while it is more than 0.1 jet widths off the axis): the inverse of the last full turn's period, the mean rate since the column left the axis before the first turn; 0 while it is within 0.1 jet widths of the axis, where the count starts again (0 in 2D and in other scenes)",
        jet_tip_height: vr 211, unit "m"; "Jet: height above the plate of the fluid's lowest point (the lowest particle's distance from the plate less half a spacing): the nozzle's height at the start, falling to about 0 when the jet lands (0 in other scenes)",
    }
}

/// The jet scene.
pub struct Jet;

/// The largest inflow speed of a run set up with `cfg` (its start values): `max_jet_velocity`,
/// or the start value of `jet_velocity` if that is larger (so 0 means the start value).
pub fn max_jet_velocity(cfg: &SceneConfig) -> f64 {
    cfg.jet.max_jet_velocity.max(cfg.jet.jet_velocity)
}

/// What a jet gets for the keys a scene file leaves out, over the parameter table's defaults
/// (which are Fang's drop): King & Lind 2021 section IV.D's Oldroyd-B jet, D = 6 mm,
/// U0 = 0.2 m/s, nozzle 12 D above the plate, eta0 = 8.8 Pa s, rho = 1023 kg/m3 (Re = 0.14),
/// beta = 0.2, lambda = 0.05 s (Wi = lambda U0 / D = 5/3), at 6 particles across (King & Lind:
/// 20), about a minute to t* = 8 (0.97 s). Under WCSPH, which buckles from 12 D, reproduces
/// both of King & Lind's arrival trends and reaches the plate within -2 to +8 % of the
/// slender-sheet model (`reference/src/analytic/falling_sheet.rs`). King & Lind's ISPH buckles too
/// (`isph_free_surface = auto`) and at this resolution reaches the plate within 3 % of the
/// slender-sheet model (Newtonian -2.8 %, Oldroyd-B within 0.4 % at Wi = 1/3 ... 20/3), but
/// not at 4 across, and its column thins to two particles and tears
/// (docs/methods.md, "Why WCSPH and not King & Lind's ISPH").
/// Written as a scene file and read through the table (`SceneConfig::for_scene`), so every
/// value is checked against its row's range.
pub const DEFAULTS: &str = "\
scheme = \"wcsph\"
rheology = \"oldroyd_b\"
density = 1023.0
viscosity = 8.8
viscosity_ratio = 0.2
relaxation_time = 0.05
gravity = 9.81
jet_width = 0.006
jet_velocity = 0.2
nozzle_height = 0.072
particles_per_diameter = 6
";

/// What a user who runs the jet under ISPH with `isph_free_surface = zero_pressure` is told
/// once (the CLI's `viscosph run` on stderr, the FMU's log under `logStatusWarning` when it
/// leaves initialization mode): with p = 0 on the free surface the compressed column carries its
/// load with 2 eta instead of 4 eta and does not buckle (docs/methods.md, "Why ISPH's jet does
/// not fold"). The jet's default, `auto`, takes King & Lind 2021 eq. (35a)'s normal stress.
pub const ISPH_WARNING: &str = "the jet under scheme = isph with isph_free_surface = \
     zero_pressure is not King & Lind's: with p = 0 on the free surface its column lands early \
     (Newtonian, H = 12 D, 6 across: 0.165 s against 0.200 s with the normal stress and WCSPH's \
     0.227 s) and does not buckle; isph_free_surface = auto or normal_stress buckles. See \
     docs/methods.md, \"The buckling jet\"";

impl SceneType for Jet {
    const NAME: &'static str = "jet";
    const DESCRIPTION: &'static str = "buckling jet from a nozzle onto a plate";
    type Params = JetParams;
    type Outputs = JetOutputs;
}

impl Scene for Jet {
    /// The plate the jet falls on (the container's sides, if any, come after it).
    fn plate_wall(&self) -> Option<usize> {
        Some(0)
    }

    /// King & Lind's jet ([`DEFAULTS`]).
    fn defaults(&self) -> &'static str {
        DEFAULTS
    }

    /// The jet width D.
    fn reference_length(&self, cfg: &SceneConfig) -> f64 {
        cfg.jet.jet_width
    }

    /// The free-fall speed at the plate, sqrt(U0^2 + 2 g H), with U0 the largest inflow speed
    /// of the run ([`max_jet_velocity`]) and H = `nozzle_height`.
    fn max_expected_speed(&self, cfg: &SceneConfig) -> f64 {
        let u0 = max_jet_velocity(cfg);
        (u0 * u0 + 2.0 * cfg.fluid.gravity * cfg.jet.nozzle_height)
            .sqrt()
            .max(1e-3)
    }

    fn domain_radius(&self, cfg: &SceneConfig) -> f64 {
        1000.0 * cfg.jet.jet_width + 10.0 * cfg.jet.nozzle_height
    }

    /// `jet_velocity` up to [`max_jet_velocity`] of the setup.
    fn check_input_range(&self, setup: &SceneConfig, now: &SceneConfig) -> Result<(), String> {
        let (u, max) = (now.jet.jet_velocity, max_jet_velocity(setup));
        if u > max {
            return Err(format!(
                "jet_velocity = {u} m/s is beyond {max} m/s, the largest inflow speed this run was set up \
                 for (max_jet_velocity, 0 = the start value of jet_velocity; the automatic sound speed \
                 covers it): set max_jet_velocity to at least {u} m/s before initialization"
            ));
        }
        Ok(())
    }

    /// King & Lind 2021 eq. (35a)'s normal stress: with p = 0 the column does not buckle.
    fn auto_free_surface(&self) -> IsphFreeSurface {
        IsphFreeSurface::NormalStress
    }

    fn validate(&self, cfg: &SceneConfig) -> Result<(), ConfigError> {
        let (jet, dx) = (&cfg.jet, cfg.dx());
        let inclination = cfg.plate.plate_inclination;
        let theta = inclination.to_radians();
        // Lowest point of the exit above the plate, along the plate's normal.
        let gap = jet.nozzle_height * theta.cos() - 0.5 * jet.jet_width * theta.sin();
        if gap < 2.0 * dx {
            return Err(ConfigError::Inconsistent(format!(
                "nozzle_height = {} m puts the nozzle exit (width {} m) within two particle \
                 spacings ({:.3e} m) of the plate inclined at {} deg",
                jet.nozzle_height, jet.jet_width, dx, inclination
            )));
        }
        if cfg.numerics.dimension == 3 && jet.container_width > 0.0 {
            return Err(ConfigError::Inconsistent(format!(
                "container_width = {} m: the round jet (dimension = 3) has no container (side \
                 walls are planar in 2D only); use container_width = 0",
                jet.container_width
            )));
        }
        if jet.container_width > 0.0 && jet.container_width < jet.jet_width + 4.0 * dx {
            return Err(ConfigError::Inconsistent(format!(
                "container_width = {} m leaves less than two particle spacings between the jet \
                 (width {} m) and each side wall: use 0 (no walls) or at least {:.4e} m",
                jet.container_width,
                jet.jet_width,
                jet.jet_width + 4.0 * dx
            )));
        }
        let plate = Plate::new(inclination, dx);
        let top = jet.nozzle_height + buffer_rows(cfg) as f64 * dx;
        for wall in side_walls(&plate, jet.container_width) {
            let inside = [-0.5, 0.5].iter().all(|&f| {
                [jet.nozzle_height, top]
                    .iter()
                    .all(|&y| wall.d(&Vec2::new(f * jet.jet_width, y)) > 2.0 * dx)
            });
            if !inside {
                return Err(ConfigError::Inconsistent(format!(
                    "container_width = {} m: the side walls stand perpendicular to the plate \
                     inclined at {} deg, and at the nozzle's height ({} m) one of them cuts \
                     through the nozzle or passes within two particle spacings of it; widen \
                     the container or lower the nozzle",
                    jet.container_width, inclination, jet.nozzle_height
                )));
            }
        }
        Ok(())
    }

    /// No fracture check (`fracture_void_fraction` = 0): a jet folding onto its heap traps air
    /// between the folds, which the void fraction would count as holes torn into the fluid.
    fn effective_config(&self, cfg: &SceneConfig) -> SceneConfig {
        let mut e = cfg.clone();
        e.numerics.fracture_void_fraction = 0.0;
        e
    }

    /// The plate, the side walls if any, and a full nozzle: [`buffer_rows`] rows of particles at
    /// the inflow state above the exit.
    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Wall>) {
        let plate = Plate::new(cfg.plate.plate_inclination, cfg.dx());
        let fluid = full_nozzle(cfg, rest);
        let mut walls: Vec<Wall> = vec![plate.clone().into()];
        walls.extend(side_walls(&plate, cfg.jet.container_width).into_iter().map(Wall::from));
        (fluid, walls)
    }

    /// [`Scene::build`]'s fluid and walls, the inlet and its bookkeeping.
    fn initial_state(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> State {
        let (fluid, walls) = self.build(cfg, rest);
        let mut st = State::new(fluid, walls, self.plate_wall());
        nozzle::start(cfg, &mut st);
        st
    }

    /// The inflow (see the module documentation and `nozzle::advance`).
    fn before_step(&self, cfg: &SceneConfig, st: &mut State) {
        nozzle::advance(cfg, st);
    }

    /// The exit speed U0.
    fn velocity_scale(&self, cfg: &SceneConfig) -> f64 {
        cfg.jet.jet_velocity.max(1e-12)
    }

    /// The free-fall time from the nozzle, sqrt(2 H / g) (D / U0 without gravity): the jet
    /// reaches the plate after about one unit (later when viscosity holds it back), and a run
    /// to t* = 8 shows several buckling periods (King & Lind's figures go to 0.7 s = 5.8 units).
    fn time_scale(&self, cfg: &SceneConfig) -> f64 {
        if cfg.fluid.gravity > 0.0 {
            (2.0 * cfg.jet.nozzle_height / cfg.fluid.gravity).sqrt()
        } else {
            cfg.jet.jet_width / self.velocity_scale(cfg)
        }
    }

    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        jet_outputs(st, cfg)
    }

    /// The round jet: the plate under a round nozzle ([`Jet::initial_state_3d`]).
    fn three_dimensional(&self) -> bool {
        true
    }

    /// The plate (`drop::plate_3d`: the plane through the impact point, inclined about y) and
    /// a full round nozzle: [`buffer_rows`] rows of the [`disc_lattice`] at the inflow state,
    /// each particle of mass [`Nozzle::particle_mass`].
    fn initial_state_3d(&self, cfg: &SceneConfig, rest: Option<Tensor<3>>) -> Option<State<3>> {
        let plate = super::drop::plate_3d(cfg.plate.plate_inclination, cfg.dx());
        let fluid = full_nozzle(cfg, rest);
        let mut st = State::new(fluid, vec![plate.into()], self.plate_wall());
        nozzle::start(cfg, &mut st);
        Some(st)
    }

    /// The inflow, as in 2D, and the coil's azimuth (`coil::follow`).
    fn before_step_3d(&self, cfg: &SceneConfig, st: &mut State<3>) {
        nozzle::advance(cfg, st);
        coil::follow(cfg, st);
    }

    /// The shared outputs and the jet's ([`jet_outputs`]; `injected_mass` in kg).
    fn outputs_3d(&self, st: &State<3>, cfg: &SceneConfig) -> Outputs {
        jet_outputs(st, cfg)
    }

    /// [`ISPH_WARNING`] when the scheme's free-surface condition is p = 0.
    fn warning(&self, cfg: &SceneConfig) -> Option<&'static str> {
        let condition = cfg
            .scheme
            .free_surface_condition(&cfg.numerics, self.auto_free_surface());
        (condition == Some(IsphFreeSurface::ZeroPressure)).then_some(ISPH_WARNING)
    }

    /// The buckling line ([`summary`]).
    fn summary(
        &self,
        cfg: &SceneConfig,
        _st: &State,
        series: &[(f64, Outputs)],
        predictions: &dyn Predictions,
    ) -> Vec<String> {
        vec![summary(cfg, series, predictions)]
    }

    /// The round jet's line ([`summary_3d`]: arrival, lean, coil).
    fn summary_3d(
        &self,
        cfg: &SceneConfig,
        _st: &State<3>,
        series: &[(f64, Outputs)],
        predictions: &dyn Predictions,
    ) -> Vec<String> {
        vec![summary_3d(cfg, series, predictions)]
    }

    /// A jet is tall and narrow: one row of tall panels.
    fn snapshot_columns(&self, panels: usize) -> usize {
        panels.clamp(1, 6)
    }

    fn inlet_mark(&self, cfg: &SceneConfig) -> Option<(f64, f64, f64)> {
        let w = 0.5 * cfg.jet.jet_width;
        Some((-w, w, cfg.jet.nozzle_height))
    }

    fn snapshot_title(&self, cfg: &SceneConfig, field: &str) -> String {
        let jet = &cfg.jet;
        format!(
            "{} jet, D = {} mm, U0 = {} m/s, nozzle {:.1} D above a plate at {} deg ({}, {} \
             across): coloured by {field}",
            cfg.fluid.rheology,
            1e3 * jet.jet_width,
            jet.jet_velocity,
            jet.nozzle_height / jet.jet_width,
            cfg.plate.plate_inclination,
            cfg.scheme,
            cfg.numerics.particles_per_diameter
        )
    }
}

/// A full nozzle in N dimensions: [`buffer_rows`] rows ([`Nozzle::row`]) at the inflow state,
/// each particle of mass [`Nozzle::particle_mass`]; `rest` the model's rest conformation, if
/// it has one.
fn full_nozzle<const N: usize>(cfg: &SceneConfig, rest: Option<Tensor<N>>) -> Fluid<N> {
    let nz = Nozzle::from_config(cfg);
    let mut fluid = Fluid::<N> {
        mass: nz.particle_mass::<N>(cfg.fluid.density),
        ..Default::default()
    };
    let v = inflow_velocity::<N>(cfg, cfg.jet.jet_velocity, 0.0);
    for k in 0..nz.rows {
        for x in nz.row::<N>(nz.exit + (k as f64 + 0.5) * nz.dx) {
            fluid.x.push(x);
            fluid.v.push(v);
            fluid.rho.push(cfg.fluid.density);
            if let Some(a) = rest {
                fluid.conf.push(a);
            }
        }
    }
    fluid
}

/// What the outputs measure in a jet state (see the module documentation).
struct Measures {
    /// The heap's along-plate extent (s_lo, s_hi), its largest distance from the plate and the
    /// height of its top above the impact point; None before impact.
    heap: Option<([f64; 2], f64, f64)>,
    /// The horizontal centre [x, y] (y = 0 in 2D) of the free particles in the band one jet
    /// width above the heap; None while no particle is there.
    band: Option<[f64; 2]>,
    /// The fluid's lowest point above the plate: the lowest particle's distance less dx/2.
    tip: f64,
}

/// The heap, the column's band and the lowest fluid of a jet state in N dimensions; None
/// without a plate.
fn measure<const N: usize>(st: &State<N>, cfg: &SceneConfig) -> Option<Measures> {
    let plate = st.plate()?;
    let fl = &st.fluid;
    let nz = Nozzle::from_config(cfg);
    let dx = nz.dx;
    let u0 = st
        .inflow
        .map_or(cfg.jet.jet_velocity, |_| inflow_log(st).velocity);
    let up = N - 1;
    // Horizontal distance from the nozzle's axis.
    let off_axis = |x: &Vector<N>| {
        if N == 2 {
            x[0].abs()
        } else {
            x.rows(0, N - 1).norm()
        }
    };
    let v_heap = 0.5 * u0 * plate.n[up];
    let (mut s_lo, mut s_hi, mut d_hi, mut y_hi) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    );
    let mut lowest = f64::INFINITY;
    for i in 0..fl.len() {
        let d = plate.d(&fl.x[i]);
        lowest = lowest.min(d);
        if -fl.v[i].dot(&plate.n) < v_heap && !nz.contains(&fl.x[i]) {
            let s = plate.s(&fl.x[i]);
            s_lo = s_lo.min(s);
            s_hi = s_hi.max(s);
            d_hi = d_hi.max(d);
            y_hi = y_hi.max(fl.x[i][up]);
        }
    }
    let heap = s_lo
        .is_finite()
        .then_some(([s_lo, s_hi], d_hi, y_hi + 0.5 * dx));
    let y_heap = heap.map_or(0.0, |h| h.2);
    let d = cfg.jet.jet_width;
    let y_m = (y_heap + d).min(nz.exit - 0.5 * d);
    // A hat weight over +/- 2 dx, so that particles enter and leave the band smoothly and the
    // measure carries no lattice noise.
    let (mut sum, mut weight) = ([0.0; 2], 0.0);
    for i in 0..fl.len() {
        let w = 1.0 - (fl.x[i][up] - y_m).abs() / (2.0 * dx);
        if w > 0.0 && off_axis(&fl.x[i]) < 2.0 * d && !nz.contains(&fl.x[i]) {
            sum[0] += w * fl.x[i][0];
            if N == 3 {
                sum[1] += w * fl.x[i][1];
            }
            weight += w;
        }
    }
    Some(Measures {
        heap,
        band: (weight > 0.0).then(|| [sum[0] / weight, sum[1] / weight]),
        tip: if lowest.is_finite() {
            lowest - 0.5 * dx
        } else {
            0.0
        },
    })
}

/// The horizontal centre [x, y] of the round jet's column one jet width above the heap (what
/// `jet_deflection` and `jet_coil_radius` measure); None while no free particle is there.
pub fn band_centre<const N: usize>(st: &State<N>, cfg: &SceneConfig) -> Option<[f64; 2]> {
    measure(st, cfg).and_then(|m| m.band)
}

/// The outputs of a jet state in N dimensions (see the module documentation): the heap's
/// measures replace the shared drop measures; `jet_deflection` is the x offset of the column
/// (in 3D: along the seed's direction, the column's centre within 2 D of the axis, any
/// direction around it); in 3D `jet_coil_radius` is that centre's distance from the axis and
/// `jet_coil_frequency` the turns it has made ([`Coil`], followed at every step).
pub fn jet_outputs<const N: usize>(st: &State<N>, cfg: &SceneConfig) -> Outputs
where
    nalgebra::Const<N>: nalgebra::DimMin<nalgebra::Const<N>, Output = nalgebra::Const<N>>,
{
    let mut o = SharedOutputs::compute(st, cfg.dx(), cfg.fluid.density);
    let dx = cfg.dx();
    let log = st.inflow.map(|_| inflow_log(st));
    let mut own = JetOutputs {
        injected_mass: log.map_or(0.0, |l| l.particles as f64 * st.fluid.mass),
        ..Default::default()
    };
    let Some(m) = measure(st, cfg) else {
        return Outputs {
            shared: o,
            jet: own,
            ..Default::default()
        };
    };
    if let Some(([s_lo, s_hi], d_hi, _)) = m.heap {
        o.drop_width = s_hi - s_lo + dx;
        o.drop_height = d_hi + 0.5 * dx;
        o.spread_front = s_hi + 0.5 * dx;
        o.spread_back = -(s_lo - 0.5 * dx);
    } else {
        o.drop_width = 0.0;
        o.drop_height = 0.0;
        o.spread_front = 0.0;
        o.spread_back = 0.0;
    }
    let [cx, cy] = m.band.unwrap_or([0.0; 2]);
    own.jet_deflection = cx;
    own.jet_tip_height = m.tip;
    if N == 3 {
        own.jet_coil_radius = cx.hypot(cy);
        own.jet_coil_frequency = log.map_or(0.0, |l| l.coil.frequency());
    }
    Outputs {
        shared: o,
        jet: own,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(n: i64) -> SceneConfig {
        let mut c = SceneConfig {
            scene: super::super::SceneKind::Jet,
            ..Default::default()
        };
        c.numerics.particles_per_diameter = n;
        Jet.effective_config(&c)
    }

    #[test]
    fn the_nozzle_is_full_and_its_columns_span_the_jet() {
        let c = cfg(6);
        let (f, walls) = Jet.build(&c, Some(Mat2::identity()));
        let nz = Nozzle::from_config(&c);
        assert_eq!(nz.rows, 5, "h = 1.5 dx: support 3 dx, plus two rows");
        assert_eq!(f.len(), 30);
        assert_eq!(f.conf.len(), 30);
        assert!(f.x.iter().all(|x| nz.contains(x)));
        assert!((f.x[0].x + 0.0025).abs() < 1e-15 && (f.x[5].x - 0.0025).abs() < 1e-15);
        assert!((f.x[0].y - 0.0725).abs() < 1e-15);
        assert_eq!(walls.len(), 1);
    }

    #[test]
    fn side_walls_face_the_jet() {
        let p = Plate::new(30.0, 0.001);
        let w = side_walls(&p, 0.04);
        assert_eq!(w.len(), 2);
        // The impact point is on the fluid side of both walls, 2 cm from each.
        for wall in &w {
            assert!((wall.d(&Vec2::zeros()) - 0.02).abs() < 1e-15);
            assert!(wall.t.dot(&p.t).abs() < 1e-15, "perpendicular to the plate");
        }
        assert!(side_walls(&p, 0.0).is_empty());
    }

    #[test]
    fn a_nozzle_too_close_to_the_plate_or_walls_too_close_to_the_jet_are_refused() {
        let mut c = cfg(6);
        c.jet.nozzle_height = 0.0015;
        assert!(Jet
            .validate(&c)
            .unwrap_err()
            .to_string()
            .contains("nozzle_height"));
        let mut c = cfg(6);
        c.jet.container_width = 0.008;
        assert!(Jet
            .validate(&c)
            .unwrap_err()
            .to_string()
            .contains("container_width"));
        c.jet.container_width = 0.0;
        assert!(Jet.validate(&c).is_ok());
        // Walls perpendicular to a 30 degree plate, 6 cm apart, lean downhill: at the nozzle's
        // height (72 mm) the uphill wall is at x = +6.9 mm, the nozzle outside the container.
        c.plate.plate_inclination = 30.0;
        c.jet.container_width = 0.06;
        let e = Jet.validate(&c).unwrap_err().to_string();
        assert!(e.contains("container_width") && e.contains("nozzle"), "{e}");
        c.jet.container_width = 0.2;
        assert!(Jet.validate(&c).is_ok());
    }

}
