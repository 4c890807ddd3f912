//! The jet's nozzle and container: where the inflow particles are held, how rows of them are
//! emitted, and the side walls (see the module documentation of [`super`], "Inflow").

use super::SceneConfig;
use crate::boundary::plate::{Motion, Plate};
use crate::dim::{Tensor, Vector};
use crate::particles::Fluid;
use crate::state::{Inflow, SceneState, State};
use crate::Vec2;
use serde::{Deserialize, Serialize};

/// Rows of particles the nozzle holds: enough to fill the kernel support of a particle at the
/// exit whatever the phase of the inflow, plus one (the scheme tells its support:
/// `SchemeKind::kernel_support`).
pub fn buffer_rows(cfg: &SceneConfig) -> i64 {
    let support = cfg.scheme.kernel_support(cfg.numerics.smoothing_ratio);
    support.ceil() as i64 + 2
}

/// The nozzle: where particles are held at the inflow state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nozzle {
    /// Height of the exit above the impact point \[m\].
    pub exit: f64,
    /// Half the jet width \[m\].
    pub half_width: f64,
    /// Particle spacing \[m\].
    pub dx: f64,
    /// Particles across the jet.
    pub columns: i64,
    /// Rows held (see [`buffer_rows`]).
    pub rows: i64,
}

/// The round nozzle's lattice of the disc of radius `radius` (the 3D jet's rows): rings at the
/// radii r_k = radius - (k + 1/2) dx, k = 0, 1, ... (the last at the centre, a single point,
/// when radius / dx is a half-integer), each holding particles in proportion to its annulus
/// (r_k +/- dx/2), so that every particle stands for about dx^2 of the disc, the outermost ring
/// half a spacing inside the nozzle's wall (a ring at the centre is one point). The counts are rounded by largest remainders so
/// that their sum is the nearest integer to pi radius^2 / dx^2 (the row is then the disc's
/// area to within half a particle); successive rings are turned by half a spacing. A square
/// lattice cut to the disc would miss its area by 13 % at 6 across (32 points for 28.3).
pub fn disc_lattice(radius: f64, dx: f64) -> Vec<[f64; 2]> {
    use std::f64::consts::PI;
    let rings = (radius / dx + 0.5).floor().max(1.0) as usize;
    let r = |k: usize| (radius - (k as f64 + 0.5) * dx).max(0.0);
    // The annulus of each ring, in particles (dx^2 each).
    let share: Vec<f64> = (0..rings)
        .map(|k| {
            let (lo, hi) = ((r(k) - 0.5 * dx).max(0.0), r(k) + 0.5 * dx);
            PI * (hi * hi - lo * lo) / (dx * dx)
        })
        .collect();
    let total = (PI * radius * radius / (dx * dx)).round().max(rings as f64) as usize;
    let mut count: Vec<usize> = share.iter().map(|a| (a.floor() as usize).max(1)).collect();
    // A ring at the centre is a single point; the others share the rest.
    let centre = r(rings - 1) == 0.0;
    let mut order: Vec<usize> = (0..rings).filter(|&k| !(centre && k == rings - 1)).collect();
    // Largest remainder first; ties to the outer ring (lower k): a fixed order.
    order.sort_by(|&a, &b| {
        let (fa, fb) = (share[a] - share[a].floor(), share[b] - share[b].floor());
        fb.total_cmp(&fa).then(a.cmp(&b))
    });
    let mut k = 0;
    while count.iter().sum::<usize>() < total && !order.is_empty() {
        count[order[k % order.len()]] += 1;
        k += 1;
    }
    let mut points = Vec::with_capacity(total);
    for (k, &c) in count.iter().enumerate() {
        let turn = if k % 2 == 1 { 0.5 } else { 0.0 };
        for j in 0..c {
            let a = 2.0 * PI * (j as f64 + turn) / c as f64;
            points.push([r(k) * a.cos(), r(k) * a.sin()]);
        }
    }
    points
}

impl Nozzle {
    /// The nozzle of an effective jet configuration.
    pub fn from_config(cfg: &SceneConfig) -> Self {
        Self {
            exit: cfg.jet.nozzle_height,
            half_width: 0.5 * cfg.jet.jet_width,
            dx: cfg.dx(),
            columns: cfg.numerics.particles_per_diameter,
            rows: buffer_rows(cfg),
        }
    }

    /// Whether a particle at `x` is inside the nozzle (above the exit line, within the jet
    /// width): such a particle is held at the inflow state. The state's copy of this test,
    /// [`Inflow::holds`], is what the schemes read.
    #[inline]
    pub fn contains<const N: usize>(&self, x: &Vector<N>) -> bool {
        self.inflow::<N>().holds(x)
    }

    /// The inlet of this nozzle at t = 0.
    pub fn inflow<const N: usize>(&self) -> Inflow<N> {
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

    /// The positions of one row at height y: the columns across the slot in 2D, the
    /// [`disc_lattice`] of the round nozzle in 3D (the vertical the last axis).
    pub fn row<const N: usize>(&self, y: f64) -> Vec<Vector<N>> {
        if N == 2 {
            (0..self.columns)
                .map(|i| Vector::<N>::from_fn(|d, _| if d == 0 { self.column_x(i) } else { y }))
                .collect()
        } else {
            disc_lattice(self.half_width, self.dx)
                .into_iter()
                .map(|p| Vector::<N>::from_fn(|d, _| if d < 2 { p[d] } else { y }))
                .collect()
        }
    }

    /// Particles in a row: `columns` in 2D, the disc lattice's count in 3D.
    pub fn row_len<const N: usize>(&self) -> u64 {
        if N == 2 {
            self.columns as u64
        } else {
            disc_lattice(self.half_width, self.dx).len() as u64
        }
    }

    /// The mass of each particle: rho0 dx^2 in 2D (per unit depth); in 3D the nozzle's area
    /// pi D^2 / 4 times dx, shared by the row's particles, so that the mass flux is
    /// rho0 (pi D^2 / 4) U0 whatever the lattice (the row holds the area to within half a
    /// particle: the particle's volume is dx^3 within 1 % from 8 across, 1.0 % at 6, 1.3 % at 7).
    pub fn particle_mass<const N: usize>(&self, rho0: f64) -> f64 {
        if N == 2 {
            rho0 * self.dx * self.dx
        } else {
            let area = std::f64::consts::PI * self.half_width * self.half_width;
            rho0 * area * self.dx / self.row_len::<N>() as f64
        }
    }

    /// Append one row of inflow particles at height y.
    fn emit_row<const N: usize>(
        &self,
        fl: &mut Fluid<N>,
        y: f64,
        v: Vector<N>,
        rho0: f64,
        conf: &Tensor<N>,
    ) {
        // A model with a conformation tensor enters at rest, which is never the zero tensor.
        let elastic = *conf != Tensor::<N>::zeros();
        for x in self.row::<N>(y) {
            fl.x.push(x);
            fl.v.push(v);
            fl.rho.push(rho0);
            if elastic {
                fl.conf.push(*conf);
            }
        }
    }
}

/// What has entered through the nozzle, in a form that makes the mass exact to the lattice: the
/// jet's own part of the state ([`State::scene`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct InflowLog<const N: usize = 2> {
    /// Inflow velocity in force since the last update [m/s] (the `jet_velocity` input).
    pub velocity: f64,
    /// Length of fluid that has entered since the last row was emitted, in [0, dx) \[m\].
    pub phase: f64,
    /// Time of the last update \[s\].
    pub updated: f64,
    /// Rows emitted since t = 0.
    pub rows: u64,
    /// Particles emitted since t = 0.
    pub particles: u64,
    /// Conformation tensor of the fluid entering (the model's at rest; unused without one).
    pub conformation: Tensor<N>,
    /// The round jet's coil (followed in 3D only).
    pub coil: super::Coil,
}

impl<const N: usize> Default for InflowLog<N> {
    fn default() -> Self {
        Self {
            velocity: 0.0,
            phase: 0.0,
            updated: 0.0,
            rows: 0,
            particles: 0,
            conformation: Tensor::zeros(),
            coil: super::Coil::default(),
        }
    }
}

/// The jet's inflow bookkeeping in a state (the default for a state that has none).
pub fn inflow_log<const N: usize>(st: &State<N>) -> InflowLog<N> {
    st.scene.decode().unwrap_or_default()
}

/// Lateral velocity of the inflow over its speed while the first jet width of fluid leaves the
/// nozzle (t < D / U0): the seed of the buckling instability. A perfectly symmetric jet would
/// draw it from round-off alone (measured: a deflection of 1e-12 m when the jet reaches the
/// plate), so when it buckles and how large it is at a given time would depend on the last bits
/// of the arithmetic. 1e-3 is a nozzle misaligned by a milliradian.
pub const SEED: f64 = 1e-3;

/// The inflow velocity at time t for the exit speed u0: vertically down, with the lateral
/// [`SEED`] (along x) while the first jet width of fluid leaves.
pub fn inflow_velocity<const N: usize>(cfg: &SceneConfig, u0: f64, t: f64) -> Vector<N> {
    let lateral = if u0 * t < cfg.jet.jet_width {
        SEED * u0
    } else {
        0.0
    };
    let mut v = Vector::<N>::zeros();
    v[0] = lateral;
    v[N - 1] = -u0;
    v
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
        motion: Motion::Fixed,
    };
    vec![wall(-0.5 * width, -plate.n), wall(0.5 * width, plate.n)]
}

/// The inlet and its bookkeeping at t = 0, for a state whose fluid is the full nozzle.
pub fn start<const N: usize>(cfg: &SceneConfig, st: &mut State<N>) {
    st.inflow = Some(Nozzle::from_config(cfg).inflow());
    st.scene = SceneState::encode(&InflowLog::<N> {
        velocity: cfg.jet.jet_velocity,
        conformation: st.fluid.conf.first().copied().unwrap_or_else(Tensor::zeros),
        ..Default::default()
    });
}

/// The inflow before a step (see the module documentation): advance the inflow length by the
/// velocity in force over the last step, emit the rows it has completed, and put every particle
/// in the nozzle back at the inflow state. The input `jet_velocity` in force from now on is
/// `cfg`'s.
pub fn advance<const N: usize>(cfg: &SceneConfig, st: &mut State<N>) {
    let Some(mut inlet) = st.inflow else {
        return;
    };
    let mut log = inflow_log(st);
    let nz = Nozzle::from_config(cfg);
    let dx = nz.dx;
    log.phase += log.velocity * (st.time - log.updated);
    log.updated = st.time;
    log.velocity = cfg.jet.jet_velocity;
    let v_in = inflow_velocity(cfg, log.velocity, st.time);
    let rho0 = cfg.fluid.density;
    let fl = &mut st.fluid;
    let m = fl.mass;
    let elastic = !fl.conf.is_empty();
    let mut reset = Vector::<N>::zeros();
    for i in 0..fl.len() {
        if nz.contains(&fl.x[i]) {
            reset += (v_in - fl.v[i]) * m;
            fl.v[i] = v_in;
            fl.rho[i] = rho0;
            if elastic {
                fl.conf[i] = log.conformation;
            }
        }
    }
    while log.phase >= dx {
        log.phase -= dx;
        let y = nz.exit + (nz.rows as f64 - 0.5) * dx - log.phase;
        nz.emit_row(fl, y, v_in, rho0, &log.conformation);
        log.rows += 1;
        let row = nz.row_len::<N>();
        log.particles += row;
        reset += v_in * (m * row as f64);
    }
    inlet.momentum += reset;
    st.inflow = Some(inlet);
    st.scene = SceneState::encode(&log);
}
