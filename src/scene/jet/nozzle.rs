//! The jet's nozzle and container: where the inflow particles are held, how rows of them are
//! emitted, and the side walls (see the module documentation of [`super`], "Inflow").

use super::SceneConfig;
use crate::boundary::plate::{Motion, Plate};
use crate::particles::Fluid;
use crate::state::{Inflow, SceneState, State};
use crate::{Mat2, Vec2};
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
    pub fn contains(&self, x: &Vec2) -> bool {
        self.inflow().holds(x)
    }

    /// The inlet of this nozzle at t = 0.
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

/// What has entered through the nozzle, in a form that makes the mass exact to the lattice: the
/// jet's own part of the state ([`State::scene`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct InflowLog {
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
    pub conformation: Mat2,
}

/// The jet's inflow bookkeeping in a state (the default for a state that has none).
pub fn inflow_log(st: &State) -> InflowLog {
    st.scene.decode().unwrap_or_default()
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
    let lateral = if u0 * t < cfg.jet.jet_width {
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
        motion: Motion::Fixed,
    };
    vec![wall(-0.5 * width, -plate.n), wall(0.5 * width, plate.n)]
}

/// The inlet and its bookkeeping at t = 0, for a state whose fluid is the full nozzle.
pub fn start(cfg: &SceneConfig, st: &mut State) {
    st.inflow = Some(Nozzle::from_config(cfg).inflow());
    st.scene = SceneState::encode(&InflowLog {
        velocity: cfg.jet.jet_velocity,
        conformation: st.fluid.conf.first().copied().unwrap_or_else(Mat2::zeros),
        ..Default::default()
    });
}

/// The inflow before a step (see the module documentation): advance the inflow length by the
/// velocity in force over the last step, emit the rows it has completed, and put every particle
/// in the nozzle back at the inflow state. The input `jet_velocity` in force from now on is
/// `cfg`'s.
pub fn advance(cfg: &SceneConfig, st: &mut State) {
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
    let mut reset = Vec2::zeros();
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
        log.particles += nz.columns as u64;
        reset += v_in * (m * nz.columns as f64);
    }
    inlet.momentum += reset;
    st.inflow = Some(inlet);
    st.scene = SceneState::encode(&log);
}
