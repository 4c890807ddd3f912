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
//! was emitted ([`crate::state::Inflow`]). Before every step ([`Scene::before_step`]) phi grows by
//! U0 times the time since the last step (U0 in force over that step: `jet_velocity` is an input,
//! [`crate::state::Inputs`], which a co-simulation master may change at any communication
//! point); each time it passes dx a new row is emitted at the top
//! (so the mass entering per unit time is rho U0 D exactly, to within one row of rho D dx); and
//! every particle inside the nozzle gets the prescribed state back: velocity (0, -U0), density
//! rho0 (zero pressure in the weakly compressible schemes, the free jet's pressure at the exit)
//! and the model's conformation at rest (zero polymer stress). A particle is in the nozzle by
//! its position alone ([`Nozzle::contains`]): particles carry no flag, so nothing depends on
//! their order. A row leaves the nozzle when it crosses the exit line and is free fluid from
//! then on. The momentum of every reset and of every emitted particle is summed in
//! `Inflow::momentum`, so the fluid's momentum balance closes: the wall impulse equals the
//! inflow's momentum plus the gravity impulse on all particles minus the momentum held.
//! A scheme that needs a pressure condition at the inlet (ISPH: Neumann, King & Lind's moving
//! ghosts) finds the inlet particles the same way, through [`Inflow::holds`] on the state.
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
//!
//! [`buckling`] turns a record of `jet_deflection` into the onset time, frequency and amplitude
//! of the buckling.

use super::Scene;
use crate::boundary::plate::Plate;
use crate::config::{ConfigError, SceneConfig, SchemeKind};
use crate::diagnostics::Outputs;
use crate::particles::Fluid;
use crate::state::{Inflow, State};
use crate::{Mat2, Vec2};

/// The jet scene.
pub struct Jet;

/// Rows of particles the nozzle holds: enough to fill the kernel support of a particle at the
/// exit whatever the phase of the inflow, plus one: 2h with the weakly compressible schemes'
/// cubic spline, 3h = 3.9 dx with ISPH's quintic spline (whose h = 1.3 dx ignores
/// `smoothing_ratio`).
pub fn buffer_rows(cfg: &SceneConfig) -> i64 {
    let support = match cfg.scheme {
        SchemeKind::Isph => 3.0 * crate::scheme::isph::H_OVER_DX,
        _ => 2.0 * cfg.smoothing_ratio,
    };
    support.ceil() as i64 + 2
}

/// What a jet gets for the keys a scene file leaves out: King & Lind's case (the text and the
/// reasons are in [`crate::config::JET_DEFAULTS`], next to the parameter table they are read
/// through, so that the configuration does not depend on the scenes).
pub use crate::config::JET_DEFAULTS as DEFAULTS;

/// The nozzle: where particles are held at the inflow state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nozzle {
    /// Height of the exit above the impact point [m].
    pub exit: f64,
    /// Half the jet width [m].
    pub half_width: f64,
    /// Particle spacing [m].
    pub dx: f64,
    /// Particles across the jet.
    pub columns: i64,
    /// Rows held (see [`buffer_rows`]).
    pub rows: i64,
}

impl Nozzle {
    /// The nozzle of an effective jet configuration.
    pub fn from_config(cfg: &SceneConfig) -> Self {
        Self {
            exit: cfg.nozzle_height,
            half_width: 0.5 * cfg.jet_width,
            dx: cfg.dx(),
            columns: cfg.particles_per_diameter,
            rows: buffer_rows(cfg),
        }
    }

    /// Whether a particle at `x` is inside the nozzle (above the exit line, within the jet
    /// width): such a particle is held at the inflow state. The state's copy of this test,
    /// [`Inflow::holds`], is what the schemes read.
    #[inline]
    pub fn contains(&self, x: &Vec2) -> bool {
        self.inflow().holds(x)
    }

    /// The inflow bookkeeping of this nozzle at t = 0.
    pub fn inflow(&self) -> Inflow {
        Inflow {
            exit: self.exit,
            half_width: self.half_width,
            ..Default::default()
        }
    }

    /// x of inflow column i.
    #[inline]
    pub fn column_x(&self, i: i64) -> f64 {
        (i as f64 + 0.5) * self.dx - self.half_width
    }

    /// Append one row of inflow particles at height y.
    fn emit_row(&self, fl: &mut Fluid, y: f64, v: Vec2, rho0: f64, conf: &Mat2) {
        // A model with a conformation tensor enters at rest, which is never the zero tensor.
        let elastic = *conf != Mat2::zeros();
        for i in 0..self.columns {
            fl.x.push(Vec2::new(self.column_x(i), y));
            fl.v.push(v);
            fl.rho.push(rho0);
            if elastic {
                fl.conf.push(*conf);
            }
        }
    }
}

/// Lateral velocity of the inflow over its speed while the first jet width of fluid leaves the
/// nozzle (t < D / U0): the seed of the buckling instability. A perfectly symmetric jet would
/// draw it from round-off alone (measured: a deflection of 1e-12 m when the jet reaches the
/// plate), so when it buckles and how large it is at a given time would depend on the last bits
/// of the arithmetic. 1e-3 is a nozzle misaligned by a milliradian.
pub const SEED: f64 = 1e-3;

/// The inflow velocity at time t for the exit speed u0: vertically down, with the lateral
/// [`SEED`] while the first jet width of fluid leaves.
pub fn inflow_velocity(cfg: &SceneConfig, u0: f64, t: f64) -> Vec2 {
    let lateral = if u0 * t < cfg.jet_width {
        SEED * u0
    } else {
        0.0
    };
    Vec2::new(lateral, -u0)
}

/// The side walls of the container, if any: perpendicular to the plate at s = -W/2 (facing
/// downhill) and s = +W/2 (facing uphill), growing along their length where fluid comes near.
pub fn side_walls(plate: &Plate, width: f64) -> Vec<Plate> {
    if width <= 0.0 {
        return Vec::new();
    }
    // A plate's normal into the fluid is its tangent turned a quarter turn anticlockwise.
    let wall = |s: f64, t: Vec2| Plate {
        origin: plate.point(s, 0.0),
        velocity: 0.0,
        displacement: 0.0,
        t,
        n: Vec2::new(-t.y, t.x),
        dx: plate.dx,
        k_min: 0,
        k_max: -1,
        fixed: false,
    };
    vec![wall(-0.5 * width, -plate.n), wall(0.5 * width, plate.n)]
}

impl Scene for Jet {
    fn validate(&self, cfg: &SceneConfig) -> Result<(), ConfigError> {
        let dx = cfg.dx();
        let theta = cfg.plate_inclination.to_radians();
        // Lowest point of the exit above the plate, along the plate's normal.
        let gap = cfg.nozzle_height * theta.cos() - 0.5 * cfg.jet_width * theta.sin();
        if gap < 2.0 * dx {
            return Err(ConfigError::Inconsistent(format!(
                "nozzle_height = {} m puts the nozzle exit (width {} m) within two particle \
                 spacings ({:.3e} m) of the plate inclined at {} deg",
                cfg.nozzle_height, cfg.jet_width, dx, cfg.plate_inclination
            )));
        }
        if cfg.container_width > 0.0 && cfg.container_width < cfg.jet_width + 4.0 * dx {
            return Err(ConfigError::Inconsistent(format!(
                "container_width = {} m leaves less than two particle spacings between the jet \
                 (width {} m) and each side wall: use 0 (no walls) or at least {:.4e} m",
                cfg.container_width,
                cfg.jet_width,
                cfg.jet_width + 4.0 * dx
            )));
        }
        let plate = Plate::new(cfg.plate_inclination, dx);
        let top = cfg.nozzle_height + buffer_rows(cfg) as f64 * dx;
        for wall in side_walls(&plate, cfg.container_width) {
            let inside = [-0.5, 0.5].iter().all(|&f| {
                [cfg.nozzle_height, top]
                    .iter()
                    .all(|&y| wall.d(&Vec2::new(f * cfg.jet_width, y)) > 2.0 * dx)
            });
            if !inside {
                return Err(ConfigError::Inconsistent(format!(
                    "container_width = {} m: the side walls stand perpendicular to the plate \
                     inclined at {} deg, and at the nozzle's height ({} m) one of them cuts \
                     through the nozzle or passes within two particle spacings of it; widen \
                     the container or lower the nozzle",
                    cfg.container_width, cfg.plate_inclination, cfg.nozzle_height
                )));
            }
        }
        Ok(())
    }

    /// The jet width sets the lattice (dx = jet_width / particles_per_diameter); the drop's
    /// diameter, height and velocity mirror the jet's so that what reads them (the automatic
    /// sound speed, the domain size) sees the jet. No fracture check
    /// (`fracture_void_fraction` = 0): a jet folding onto its heap traps air between the folds,
    /// which the void fraction would count as holes torn into the fluid.
    fn effective_config(&self, cfg: &SceneConfig) -> SceneConfig {
        let mut e = cfg.clone();
        e.drop_diameter = cfg.jet_width;
        e.initial_drop_height = cfg.nozzle_height;
        e.impact_velocity = cfg.jet_velocity;
        e.fracture_void_fraction = 0.0;
        e
    }

    /// The plate, the side walls if any, and a full nozzle: [`buffer_rows`] rows of particles at
    /// the inflow state above the exit.
    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Plate>) {
        let dx = cfg.dx();
        let plate = Plate::new(cfg.plate_inclination, dx);
        let nz = Nozzle::from_config(cfg);
        let mut fluid = Fluid {
            mass: cfg.density * dx * dx,
            ..Default::default()
        };
        let conf = rest.unwrap_or_else(Mat2::zeros);
        let v = inflow_velocity(cfg, cfg.jet_velocity, 0.0);
        for k in 0..nz.rows {
            let y = nz.exit + (k as f64 + 0.5) * dx;
            for i in 0..nz.columns {
                fluid.x.push(Vec2::new(nz.column_x(i), y));
                fluid.v.push(v);
                fluid.rho.push(cfg.density);
                if rest.is_some() {
                    fluid.conf.push(conf);
                }
            }
        }
        let mut walls = vec![plate.clone()];
        walls.extend(side_walls(&plate, cfg.container_width));
        (fluid, walls)
    }

    fn init_state(&self, cfg: &SceneConfig, st: &mut State) {
        st.inflow = Some(Inflow {
            velocity: cfg.inputs().jet_velocity,
            conformation: st.fluid.conf.first().copied().unwrap_or_else(Mat2::zeros),
            ..Nozzle::from_config(cfg).inflow()
        });
    }

    /// The inflow (see the module documentation): advance the inflow length by the velocity in
    /// force over the last step, emit the rows it has completed, and put every particle in the
    /// nozzle back at the inflow state.
    fn before_step(&self, cfg: &SceneConfig, st: &mut State) {
        let Some(mut inl) = st.inflow else {
            return;
        };
        let nz = Nozzle::from_config(cfg);
        let dx = nz.dx;
        inl.phase += inl.velocity * (st.time - inl.updated);
        inl.updated = st.time;
        inl.velocity = st.inputs.jet_velocity;
        let v_in = inflow_velocity(cfg, inl.velocity, st.time);
        let rho0 = cfg.density;
        let fl = &mut st.fluid;
        let m = fl.mass;
        let elastic = !fl.conf.is_empty();
        let mut reset = Vec2::zeros();
        for i in 0..fl.len() {
            if nz.contains(&fl.x[i]) {
                reset += (v_in - fl.v[i]) * m;
                fl.v[i] = v_in;
                fl.rho[i] = rho0;
                if elastic {
                    fl.conf[i] = inl.conformation;
                }
            }
        }
        while inl.phase >= dx {
            inl.phase -= dx;
            let y = nz.exit + (nz.rows as f64 - 0.5) * dx - inl.phase;
            nz.emit_row(fl, y, v_in, rho0, &inl.conformation);
            inl.rows += 1;
            inl.particles += nz.columns as u64;
            reset += v_in * (m * nz.columns as f64);
        }
        inl.momentum += reset;
        st.inflow = Some(inl);
    }

    /// The exit speed U0.
    fn velocity_scale(&self, cfg: &SceneConfig) -> f64 {
        cfg.jet_velocity.max(1e-12)
    }

    /// The free-fall time from the nozzle, sqrt(2 H / g) (D / U0 without gravity): the jet
    /// reaches the plate after about one unit (later when viscosity holds it back), and a run
    /// to t* = 8 shows several buckling periods (King & Lind's figures go to 0.7 s = 5.8 units).
    fn time_scale(&self, cfg: &SceneConfig) -> f64 {
        if cfg.gravity > 0.0 {
            (2.0 * cfg.nozzle_height / cfg.gravity).sqrt()
        } else {
            cfg.jet_width / self.velocity_scale(cfg)
        }
    }

    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        let mut o = Outputs::compute(st, cfg.dx(), cfg.density);
        let fl = &st.fluid;
        let nz = Nozzle::from_config(cfg);
        let dx = nz.dx;
        let u0 = st.inflow.map_or(cfg.jet_velocity, |i| i.velocity);
        o.injected_mass = st.inflow.map_or(0.0, |i| i.particles as f64 * fl.mass);
        let Some(plate) = st.plate() else {
            return o;
        };
        let v_heap = 0.5 * u0 * plate.n.y;
        let (mut s_lo, mut s_hi, mut d_hi, mut y_hi) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        );
        let is_heap = |i: usize| -fl.v[i].dot(&plate.n) < v_heap && !nz.contains(&fl.x[i]);
        for i in (0..fl.len()).filter(|&i| is_heap(i)) {
            let (s, d) = (plate.s(&fl.x[i]), plate.d(&fl.x[i]));
            s_lo = s_lo.min(s);
            s_hi = s_hi.max(s);
            d_hi = d_hi.max(d);
            y_hi = y_hi.max(fl.x[i].y);
        }
        let y_heap = if s_lo.is_finite() {
            o.drop_width = s_hi - s_lo + dx;
            o.drop_height = d_hi + 0.5 * dx;
            o.spread_front = s_hi + 0.5 * dx;
            o.spread_back = -(s_lo - 0.5 * dx);
            y_hi + 0.5 * dx
        } else {
            o.drop_width = 0.0;
            o.drop_height = 0.0;
            o.spread_front = 0.0;
            o.spread_back = 0.0;
            0.0
        };
        let y_m = (y_heap + cfg.jet_width).min(nz.exit - 0.5 * cfg.jet_width);
        // A hat weight over +/- 2 dx, so that particles enter and leave the band smoothly and the
        // measure carries no lattice noise.
        let (mut sum, mut weight) = (0.0, 0.0);
        for i in 0..fl.len() {
            let w = 1.0 - (fl.x[i].y - y_m).abs() / (2.0 * dx);
            if w > 0.0 && fl.x[i].x.abs() < 2.0 * cfg.jet_width && !nz.contains(&fl.x[i]) {
                sum += w * fl.x[i].x;
                weight += w;
            }
        }
        o.jet_deflection = if weight > 0.0 { sum / weight } else { 0.0 };
        o
    }
}

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

/// [`ISPH_WARNING`] when `cfg` runs the jet under ISPH with p = 0 on its free surface.
pub fn isph_warning(cfg: &SceneConfig) -> Option<&'static str> {
    (cfg.scene == crate::config::Scene::Jet
        && cfg.scheme == SchemeKind::Isph
        && cfg.isph_free_surface == crate::config::IsphFreeSurface::ZeroPressure)
        .then_some(ISPH_WARNING)
}

/// What a record of `jet_deflection` says about buckling (see [`buckling`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Buckling {
    /// When the jet first reached the plate (the heap first had a height) [s]; None if never.
    pub impact: Option<f64>,
    /// First time after impact that |jet_deflection| exceeded [`ONSET_FRACTION`] D [s].
    pub onset: Option<f64>,
    /// Half the peak-to-peak range of `jet_deflection` over the second half of the record after
    /// impact [m].
    pub amplitude: f64,
    /// Frequency of the oscillation after onset: mean-crossings of the deflection over twice
    /// the time they span [Hz]; 0 with fewer than three crossings. Onset, amplitude and
    /// frequency leave out the outputs at which no fluid was in the band (`jet_deflection`
    /// exactly 0, a gap of a torn column).
    pub frequency: f64,
}

/// Deflection, as a fraction of the jet width, beyond which the jet counts as buckled.
pub const ONSET_FRACTION: f64 = 0.1;

/// Onset, amplitude and frequency of buckling from a record of outputs of a jet of width `d`.
pub fn buckling(series: &[(f64, Outputs)], d: f64) -> Buckling {
    let Some(k0) = series.iter().position(|(_, o)| o.drop_height > 0.0) else {
        return Buckling::default();
    };
    // Outputs at which no fluid was in the measuring band (`jet_deflection` exactly 0: a torn
    // column's gap passing the band) say nothing about the column's position: left out, as
    // each would otherwise count as two mean crossings (measured: ISPH's torn Oldroyd-B
    // columns at 6 across read 40-50 Hz with them).
    let impact = Some(series[k0].0);
    let after: Vec<&(f64, Outputs)> = series[k0..]
        .iter()
        .filter(|(_, o)| o.jet_deflection != 0.0)
        .collect();
    if after.is_empty() {
        return Buckling {
            impact,
            ..Buckling::default()
        };
    }
    let onset = after
        .iter()
        .find(|(_, o)| o.jet_deflection.abs() > ONSET_FRACTION * d)
        .map(|(t, _)| *t);
    let late = &after[after.len() / 2..];
    let (lo, hi) = late
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, o)| {
            (lo.min(o.jet_deflection), hi.max(o.jet_deflection))
        });
    let amplitude = if lo.is_finite() { 0.5 * (hi - lo) } else { 0.0 };
    let mut frequency = 0.0;
    if let Some(t_on) = onset {
        let tail: Vec<(f64, f64)> = after
            .iter()
            .filter(|(t, _)| *t >= t_on)
            .map(|(t, o)| (*t, o.jet_deflection))
            .collect();
        let mean = tail.iter().map(|p| p.1).sum::<f64>() / tail.len() as f64;
        let crossings: Vec<f64> = tail
            .windows(2)
            .filter(|w| (w[0].1 - mean) * (w[1].1 - mean) < 0.0)
            .map(|w| {
                let (a, b) = (w[0].1 - mean, w[1].1 - mean);
                w[0].0 + (w[1].0 - w[0].0) * a / (a - b)
            })
            .collect();
        if crossings.len() >= 3 {
            let span = crossings[crossings.len() - 1] - crossings[0];
            frequency = (crossings.len() - 1) as f64 / (2.0 * span);
        }
    }
    Buckling {
        impact,
        onset,
        amplitude,
        frequency,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(n: i64) -> SceneConfig {
        let c = SceneConfig {
            scene: crate::config::Scene::Jet,
            particles_per_diameter: n,
            ..Default::default()
        };
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
        c.nozzle_height = 0.0015;
        assert!(Jet
            .validate(&c)
            .unwrap_err()
            .to_string()
            .contains("nozzle_height"));
        let mut c = cfg(6);
        c.container_width = 0.008;
        assert!(Jet
            .validate(&c)
            .unwrap_err()
            .to_string()
            .contains("container_width"));
        c.container_width = 0.0;
        assert!(Jet.validate(&c).is_ok());
        // Walls perpendicular to a 30 degree plate, 6 cm apart, lean downhill: at the nozzle's
        // height (72 mm) the uphill wall is at x = +6.9 mm, the nozzle outside the container.
        c.plate_inclination = 30.0;
        c.container_width = 0.06;
        let e = Jet.validate(&c).unwrap_err().to_string();
        assert!(e.contains("container_width") && e.contains("nozzle"), "{e}");
        c.container_width = 0.2;
        assert!(Jet.validate(&c).is_ok());
    }

    #[test]
    fn buckling_of_a_sine_after_impact() {
        // Impact at t = 0.1 s, then a 5 Hz oscillation of amplitude 2 mm growing in within
        // 0.05 s: onset when it passes 0.6 mm, frequency 5 Hz, amplitude 2 mm.
        let d = 0.006;
        let series: Vec<(f64, Outputs)> = (0..=1000)
            .map(|k| {
                let t = k as f64 * 1e-3;
                let mut o = Outputs::default();
                if t >= 0.1 {
                    o.drop_height = 0.001;
                    let ramp = ((t - 0.1) / 0.05).min(1.0);
                    o.jet_deflection =
                        0.002 * ramp * (2.0 * std::f64::consts::PI * 5.0 * (t - 0.1)).sin();
                }
                (t, o)
            })
            .collect();
        let b = buckling(&series, d);
        assert_eq!(b.impact, Some(0.1));
        let onset = b.onset.unwrap();
        assert!(onset > 0.1 && onset < 0.15, "{onset}");
        assert!((b.amplitude - 0.002).abs() < 1e-5, "{}", b.amplitude);
        assert!((b.frequency - 5.0).abs() < 0.05, "{}", b.frequency);
        // A straight jet: no onset, no frequency.
        let straight: Vec<(f64, Outputs)> = series
            .iter()
            .map(|(t, o)| {
                (
                    *t,
                    Outputs {
                        jet_deflection: 1e-5,
                        ..*o
                    },
                )
            })
            .collect();
        let b = buckling(&straight, d);
        assert_eq!((b.onset, b.frequency, b.amplitude), (None, 0.0, 0.0));
    }

    #[test]
    fn outputs_without_fluid_in_the_band_do_not_count_as_crossings() {
        // A column buckling about an offset of 1 mm (the heap's side) at 5 Hz, torn: every
        // seventh output finds no fluid in the band (jet_deflection exactly 0). With those
        // outputs read as positions, each would be two crossings of the mean.
        let d = 0.006;
        let record = |gaps: bool| -> Vec<(f64, Outputs)> {
            (0..=1000)
                .map(|k| {
                    let t = k as f64 * 1e-3;
                    let mut o = Outputs::default();
                    if t >= 0.1 {
                        o.drop_height = 0.001;
                        o.jet_deflection = if gaps && k % 7 == 0 {
                            0.0
                        } else {
                            0.001 + 0.002 * (2.0 * std::f64::consts::PI * 5.0 * (t - 0.1)).sin()
                        };
                    }
                    (t, o)
                })
                .collect()
        };
        let whole = buckling(&record(false), d);
        let torn = buckling(&record(true), d);
        println!("{whole:?}\n{torn:?}");
        assert!((whole.frequency - 5.0).abs() < 0.05, "{whole:?}");
        assert!((torn.frequency - 5.0).abs() < 0.05, "{torn:?}");
        assert_eq!(torn.impact, Some(0.1));
        assert!((torn.amplitude - 0.002).abs() < 1e-4, "{torn:?}");
    }
}
