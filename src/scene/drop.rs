//! The drop impact of Fang 2006 section 4: a disc cut from a Cartesian lattice, moving
//! vertically down at the impact velocity towards a rigid plate. Under `dimension = 3` the drop
//! is a sphere cut from the cubic lattice and the plate a plane tilted about the y axis
//! ([`build_3d`], [`plate_3d`]); its outputs are the shared ones (the load bins along the plate,
//! per unit depth, hold 0 there). `drop_shape = slab` makes the 3D drop the 2D disc extended
//! across: a cylinder of fluid along y, periodic across with the fewest spacings the periodic
//! neighbour search allows ([`slab_layers`]): the 2D flow computed by the 3D code, which checks
//! the one against the other.

use super::{Outputs, Scene, SceneConfig, SceneType};
use crate::boundary::plate::{Motion, Plate};
use crate::boundary::wall::Wall;
use crate::config::{enumeration, real, real_pos, ConfigError};
use crate::neighbors::Domain;
use crate::state::State;
use crate::particles::Fluid;
use crate::dim::{Tensor, Vector};
use crate::{Mat2, Vec2};

/// The shapes of the 3D drop (`drop_shape`).
pub const DROP_SHAPES: &[(&str, &str)] = &[
    ("sphere", "a sphere of diameter drop_diameter"),
    (
        "slab",
        "the 2D disc extended across the plane of the flow: a cylinder of fluid of diameter drop_diameter along y, periodic across with the fewest particle spacings the neighbour search allows (8 at the default smoothing ratio)",
    ),
];

crate::choice_enum!(
    /// The shape of the 3D drop.
    DropShape, DROP_SHAPES, Sphere = "sphere", Slab = "slab");

crate::params! {
    /// The drop: its size, where it starts and how fast.
    pub struct DropParams {
        impact_velocity: f64 = real(1.0, 0.0, 100.0), vr 5, unit "m/s";
            "Initial speed of the drop, vertically down",
        drop_diameter: f64 = real_pos(0.02, 10.0), vr 6, unit "m";
            "Diameter of the initial (circular) drop",
        initial_drop_height: f64 = real_pos(0.04, 100.0), vr 7, unit "m", alias "drop_height";
            "Height of the drop centre above the impact point at t = 0, measured vertically (scene files may also call it drop_height)",
        drop_shape: DropShape = enumeration::<DropShape>("DropShape", "sphere"), vr 76, unit "";
            "3D only: sphere, or slab = the 2D disc extended across the plane of the flow (a cylinder of fluid periodic across, for checking the 3D code against the 2D one); not read in 2D",
    }
}

/// Number of bins of the load along the plate (`wall_pressure_001..`, `wall_shear_001..`; the
/// FMI 3.0 arrays `wall_pressure`, `wall_shear`).
pub const WALL_BINS: usize = 24;

/// The bins cover the plate from `-WALL_BIN_SPAN / 2` to `+WALL_BIN_SPAN / 2` drop diameters
/// about the impact point, in the plate's frame: 6 D, bins D / 4 long, wider than a drop ever
/// spreads on a level plate (Fang 2006: W* < 3).
pub const WALL_BIN_SPAN: f64 = 6.0;

crate::outputs! {
    /// The drop's own outputs: the load along the plate (see [`load_outputs`]).
    pub struct DropOutputs {
        wall_pressure: vr 122, unit "Pa"; "Drop: normal load on bin {k} of 24 along the plate (see WALL_BINS), force into the plate per bin length per unit depth (2D; 0 in 3D and in other scenes)";
            array [WALL_BINS] vr 180; "Drop: normal load along the plate in 24 bins (see WALL_BINS), the elements wall_pressure_001..024: force into the plate per bin length per unit depth (2D; 0 in 3D and in other scenes)",
        wall_shear: vr 146, unit "Pa"; "Drop: tangential load on bin {k} of 24 along the plate, force downhill per bin length per unit depth (2D; 0 in 3D and in other scenes)";
            array [WALL_BINS] vr 181; "Drop: tangential load along the plate in 24 bins, the elements wall_shear_001..024: force downhill per bin length per unit depth (2D; 0 in 3D and in other scenes)",
        wall_moment: vr 170, unit "N.m/m"; "Drop: moment about the impact point of the fluid's normal force on the plate per unit depth [N m/m], sum of s F_n: positive when the load downhill of the impact point (s > 0) dominates (2D; 0 in 3D and in other scenes)",
        wall_centre_of_pressure: vr 171, unit "m"; "Drop: where along the plate the normal force acts, wall_moment / wall_force_normal, from the impact point, positive downhill; 0 while the normal force is 0 (2D; 0 in 3D and in other scenes)",
    }
}

/// The load along the plate from the plate's force by fluid particle (`State::plate_load`):
/// each particle's share goes to the bin of its along-plate coordinate s, the normal part
/// (into the plate) to `wall_pressure_k`, the tangential part (downhill) to `wall_shear_k`,
/// each divided by the bin length, so the bins integrate (sum times bin length) to
/// `wall_force_normal` and `wall_force_tangential` when the wetted plate lies within the span.
/// In 2D a force per unit depth over a length is a pressure \[Pa\]. The moment about the impact
/// point is sum s F_n over every particle (the tangential forces act on the plate line through
/// it), and the centre of pressure is the moment over the normal force. Zero when the state has
/// no load by particle.
pub fn load_outputs(st: &State, cfg: &SceneConfig) -> DropOutputs {
    let mut out = DropOutputs::default();
    let Some(plate) = st.plate() else {
        return out;
    };
    if st.plate_load.len() != st.fluid.len() {
        return out;
    }
    let width = WALL_BIN_SPAN * cfg.drop.drop_diameter / WALL_BINS as f64;
    let s0 = -0.5 * WALL_BIN_SPAN * cfg.drop.drop_diameter;
    let (mut normal, mut tangential) = ([0.0; WALL_BINS], [0.0; WALL_BINS]);
    let (mut moment, mut total) = (0.0, 0.0);
    for (x, f) in st.fluid.x.iter().zip(&st.plate_load) {
        let s = plate.s(x);
        let f_n = -f.dot(&plate.n);
        moment += s * f_n;
        total += f_n;
        let k = ((s - s0) / width).floor();
        if k >= 0.0 && k < WALL_BINS as f64 {
            normal[k as usize] += f_n;
            tangential[k as usize] += f.dot(&plate.t);
        }
    }
    let centre = if total != 0.0 { moment / total } else { 0.0 };
    for k in 0..WALL_BINS {
        out.wall_pressure[k] = normal[k] / width;
        out.wall_shear[k] = tangential[k] / width;
    }
    out.wall_moment = moment;
    out.wall_centre_of_pressure = if centre.is_finite() { centre } else { 0.0 };
    out
}

/// Build the fluid of a drop: lattice points (i + 1/2) dx, (j + 1/2) dx about the drop centre in
/// the plate's frame (so the lattice lines up with the wall particles at any inclination, and the
/// drop is symmetric about its centre) kept where they fall inside the disc.
///
/// `rest` is the model's conformation at rest (`Rheology::rest_conformation`), or None for models
/// without a conformation tensor: the drop starts stress-free, as Fang's does.
pub fn build(cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Plate) {
    let dx = cfg.dx();
    let plate = Plate::new(cfg.plate.plate_inclination, dx);
    let centre = Vec2::new(0.0, cfg.drop.initial_drop_height);
    let (sc, dc) = (plate.s(&centre), plate.d(&centre));
    let r = 0.5 * cfg.drop.drop_diameter;
    let n = cfg.numerics.particles_per_diameter;
    let mut fluid = Fluid {
        mass: cfg.fluid.density * dx * dx,
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
    let v0 = Vec2::new(0.0, -cfg.drop.impact_velocity);
    fluid.v = vec![v0; fluid.x.len()];
    fluid.rho = vec![cfg.fluid.density; fluid.x.len()];
    if let Some(a0) = rest {
        fluid.conf = vec![a0; fluid.x.len()];
    }
    (fluid, plate)
}

/// The plate of a 3D drop: the plane through the origin inclined at `inclination_deg` about
/// the y axis (across the downhill direction), downhill towards +x: t = (cos a, 0, -sin a),
/// n = (sin a, 0, cos a), so the 2D plate's frame is its section y = 0 and n x t = +y.
pub fn plate_3d(inclination_deg: f64, dx: f64) -> Plate<3> {
    let a = inclination_deg.to_radians();
    Plate::through(
        Vector::<3>::zeros(),
        Vector::<3>::new(a.sin(), 0.0, a.cos()),
        Vector::<3>::new(a.cos(), 0.0, -a.sin()),
        dx,
    )
}

/// Layers of particles across the slab (`drop_shape = slab`): the fewest the periodic
/// neighbour search allows, as across the 3D channel.
pub fn slab_layers(cfg: &SceneConfig) -> i64 {
    super::channel::least_columns(cfg)
}

/// Whether the drop is the 3D slab.
fn is_slab(cfg: &SceneConfig) -> bool {
    cfg.numerics.dimension == 3 && cfg.drop.drop_shape == DropShape::Slab
}

/// Build the fluid of a 3D drop: a sphere cut from the cubic lattice (i + 1/2, j + 1/2,
/// k + 1/2) dx about the drop centre in the plate's frame (along t, n x t and n), as the 2D
/// drop's disc, moving vertically down (-z) at the impact velocity; each particle of mass
/// rho0 dx^3. The slab (`drop_shape = slab`) is the 2D disc's lattice points repeated at
/// y = j dx, j < [`slab_layers`], on the rows of the plate's dummy particles.
pub fn build_3d(cfg: &SceneConfig, rest: Option<Tensor<3>>) -> (Fluid<3>, Plate<3>) {
    let dx = cfg.dx();
    let plate = plate_3d(cfg.plate.plate_inclination, dx);
    let centre = Vector::<3>::new(0.0, 0.0, cfg.drop.initial_drop_height);
    let (sc, dc) = (plate.s(&centre), plate.d(&centre));
    let across = plate.n.cross(&plate.t);
    let r = 0.5 * cfg.drop.drop_diameter;
    let n = cfg.numerics.particles_per_diameter;
    let mut fluid = Fluid::<3> {
        mass: cfg.fluid.density * dx.powi(3),
        ..Default::default()
    };
    let slab = is_slab(cfg);
    let (j_lo, j_hi, j_off) = if slab {
        (0, slab_layers(cfg), 0.0)
    } else {
        (-n, n, 0.5)
    };
    for k in -n..n {
        for j in j_lo..j_hi {
            for i in -n..n {
                let l = Vector::<3>::new(i as f64 + 0.5, j as f64 + j_off, k as f64 + 0.5) * dx;
                let r2 = if slab {
                    l.x * l.x + l.z * l.z
                } else {
                    l.norm_squared()
                };
                if r2 < r * r {
                    fluid.x.push(plate.point(sc + l.x, dc + l.z) + across * l.y);
                }
            }
        }
    }
    let v0 = Vector::<3>::new(0.0, 0.0, -cfg.drop.impact_velocity);
    fluid.v = vec![v0; fluid.x.len()];
    fluid.rho = vec![cfg.fluid.density; fluid.x.len()];
    if let Some(a0) = rest {
        fluid.conf = vec![a0; fluid.x.len()];
    }
    (fluid, plate)
}

/// The drop impact scene (see the module documentation).
pub struct Drop;

impl SceneType for Drop {
    const NAME: &'static str = "drop";
    const DESCRIPTION: &'static str = "Drop falling onto a rigid plate: a disc on a straight plate in 2D, a sphere on a plane plate in 3D";
    type Params = DropParams;
    type Outputs = DropOutputs;
}

impl Scene for Drop {
    fn has_moving_plate(&self) -> bool {
        true
    }

    /// The shared outputs and the load along the plate ([`load_outputs`]).
    fn outputs(&self, st: &State, cfg: &SceneConfig) -> Outputs {
        Outputs {
            shared: cfg.shared_outputs(st),
            drop: load_outputs(st, cfg),
            ..Default::default()
        }
    }

    /// The plate under the drop, moved by the input `plate_velocity`.
    fn plate_wall(&self) -> Option<usize> {
        Some(0)
    }

    /// The drop's diameter D.
    fn reference_length(&self, cfg: &SceneConfig) -> f64 {
        cfg.drop.drop_diameter
    }

    /// The impact speed plus the free fall from the initial height until the drop's lowest
    /// point touches the plate, sqrt(V^2 + 2 g h_fall), plus `max_plate_speed`: the fluid
    /// meets the plate at the sum of the two speeds when the plate inputs drive the plate into
    /// the drop as fast as the run allows. A drop that spreads or slides afterwards does not
    /// speed up much beyond it (viscosity and the plate take energy out).
    fn max_expected_speed(&self, cfg: &SceneConfig) -> f64 {
        let d = &cfg.drop;
        let theta = cfg.plate.plate_inclination.to_radians();
        let fall = (d.initial_drop_height - 0.5 * d.drop_diameter / theta.cos()).max(0.0);
        let v = d.impact_velocity;
        let drop = (v * v + 2.0 * cfg.fluid.gravity * fall).sqrt();
        (drop + cfg.plate.max_plate_speed).max(1e-3)
    }

    /// The fluid and the plate's wall particles: in 2D four rows, twenty diameters long; in
    /// 3D a sphere and three layers under a plate four diameters square (the slab: the disc
    /// and three layers under a plate four diameters long, times the layers across).
    fn estimated_particles(&self, cfg: &SceneConfig) -> f64 {
        let ppd = cfg.numerics.particles_per_diameter as f64;
        if is_slab(cfg) {
            (std::f64::consts::FRAC_PI_4 * ppd * ppd + 3.0 * 4.0 * ppd) * slab_layers(cfg) as f64
        } else if cfg.numerics.dimension == 3 {
            std::f64::consts::FRAC_PI_6 * ppd.powi(3) + 3.0 * 16.0 * ppd * ppd
        } else {
            std::f64::consts::FRAC_PI_4 * ppd * ppd + 4.0 * ppd * 20.0
        }
    }

    fn domain_radius(&self, cfg: &SceneConfig) -> f64 {
        1000.0 * cfg.drop.drop_diameter + 10.0 * cfg.drop.initial_drop_height
    }

    /// Open; the slab is periodic across (y), one period [`slab_layers`] spacings.
    fn domain(&self, cfg: &SceneConfig) -> Domain {
        if is_slab(cfg) {
            Domain::OPEN.with_period(1, slab_layers(cfg) as f64 * cfg.dx())
        } else {
            Domain::OPEN
        }
    }

    fn validate(&self, cfg: &SceneConfig) -> Result<(), ConfigError> {
        let (d, plate) = (&cfg.drop, &cfg.plate);
        let theta = plate.plate_inclination.to_radians();
        let normal_gap = d.initial_drop_height * theta.cos() - 0.5 * d.drop_diameter;
        if normal_gap < cfg.dx() {
            return Err(ConfigError::Inconsistent(format!(
                "initial_drop_height = {} m puts the drop (diameter {} m) within one particle spacing of \
                 the plate inclined at {} deg: its centre must be at least {:.6} m above the impact point",
                d.initial_drop_height,
                d.drop_diameter,
                plate.plate_inclination,
                (0.5 * d.drop_diameter + cfg.dx()) / theta.cos()
            )));
        }
        Ok(())
    }

    /// A sphere on a plane plate ([`build_3d`]), the plate moved by the inputs as in 2D.
    fn three_dimensional(&self) -> bool {
        true
    }

    fn initial_state_3d(&self, cfg: &SceneConfig, rest: Option<Tensor<3>>) -> Option<State<3>> {
        let (fluid, plate) = build_3d(cfg, rest);
        let walls = vec![plate.with_motion(Motion::Input).into()];
        Some(State::new(fluid, walls, self.plate_wall()))
    }

    fn build(&self, cfg: &SceneConfig, rest: Option<Mat2>) -> (Fluid, Vec<Wall>) {
        let (fluid, plate) = build(cfg, rest);
        (fluid, vec![plate.with_motion(Motion::Input).into()])
    }

    /// The impact velocity (sqrt(g D) if the drop is released at rest).
    fn velocity_scale(&self, cfg: &SceneConfig) -> f64 {
        if cfg.drop.impact_velocity > 0.0 {
            cfg.drop.impact_velocity
        } else {
            (cfg.fluid.gravity * cfg.drop.drop_diameter).sqrt().max(1e-12)
        }
    }

    /// D / V, Fang 2006's t*.
    fn time_scale(&self, cfg: &SceneConfig) -> f64 {
        cfg.drop.drop_diameter / self.velocity_scale(cfg)
    }

    fn snapshot_title(&self, cfg: &SceneConfig, field: &str) -> String {
        format!(
            "{} drop, D = {} mm, V = {} m/s, plate at {} deg ({}): coloured by {field}",
            cfg.fluid.rheology,
            1e3 * cfg.drop.drop_diameter,
            cfg.drop.impact_velocity,
            cfg.plate.plate_inclination,
            cfg.scheme
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drop_inside_plate_is_refused() {
        let mut c = SceneConfig::default();
        c.drop.initial_drop_height = 0.01;
        let e = Drop.validate(&c).unwrap_err().to_string();
        assert!(e.contains("drop_height"), "{e}");
        assert!(Drop.validate(&SceneConfig::default()).is_ok());
    }
}
