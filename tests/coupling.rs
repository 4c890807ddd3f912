//! Two-way coupling through the `plate_velocity` input: a drop on a plate that is a rigid body
//! on a spring and a damper, integrated by a small co-simulation master written here (the same
//! scheme as `examples/spring_plate.py`, which drives the FMU).
//!
//! The master is a Gauss-Seidel coupling: at a communication point it reads the wall force,
//! advances the plate over the communication step with that force held constant, and gives the
//! solver the plate's mean velocity over the step, so that the solver's plate (which moves at the
//! input velocity) lands exactly where the master's plate is.

mod common;

use common::{r, s};
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;
use viscosph::Vec2;

/// A rigid plate of mass `m` [kg/m] on a spring `k` [N/m/m] and a damper `c` [N s/m/m], moving
/// along its normal; `x` is the displacement away from the fluid.
struct SpringPlate {
    m: f64,
    k: f64,
    c: f64,
    x: f64,
    v: f64,
}

impl SpringPlate {
    /// Advance over `h` with the fluid's force `f` (positive into the plate) held constant:
    /// semi-implicit Euler in sub-steps short against the spring's period. Returns the mean
    /// velocity over `h`.
    fn step(&mut self, f: f64, h: f64) -> f64 {
        let x0 = self.x;
        let omega = (self.k / self.m).sqrt() + self.c / self.m;
        let n = ((h * omega / 0.05).ceil() as usize).max(1);
        let dt = h / n as f64;
        for _ in 0..n {
            self.v += dt * (f - self.k * self.x - self.c * self.v) / self.m;
            self.x += dt * self.v;
        }
        (self.x - x0) / h
    }
}

fn drop_cfg() -> SceneConfig {
    let mut c = SceneConfig::default();
    c.set("rheology", s("newtonian")).unwrap();
    c.set("sound_speed", r(12.5)).unwrap();
    c.set("initial_drop_height", r(0.0115)).unwrap();
    c.set("threads", common::i(2)).unwrap();
    c
}

fn fluid_momentum(sim: &Simulation) -> Vec2 {
    let f = &sim.state().fluid;
    f.v.iter().fold(Vec2::zeros(), |p, u| p + u) * f.mass
}

fn fluid_mass(sim: &Simulation) -> f64 {
    let f = &sim.state().fluid;
    f.mass * f.len() as f64
}

/// Run the coupled system to `t_end` with communication step `h`; returns the simulation and
/// the plate, and the wall force normal to the plate at each communication point.
fn coupled(plate: &mut SpringPlate, h: f64, t_end: f64) -> (Simulation, Vec<f64>) {
    let mut sim = Simulation::new(drop_cfg()).unwrap();
    let mut forces = Vec::new();
    let n = (t_end / h).round() as usize;
    for k in 0..n {
        let f = sim.outputs().shared.wall_force_normal;
        forces.push(f);
        let u = plate.step(f, h);
        sim.set_inputs(sim.inputs().with("plate_velocity", u))
            .unwrap();
        sim.advance_to((k + 1) as f64 * h).unwrap();
        // The solver's plate is where the master's is.
        let d = sim.outputs().shared.plate_displacement;
        assert!((d - plate.x).abs() < 1e-12, "{d} vs {}", plate.x);
    }
    (sim, forces)
}

/// A free plate (no spring, no damper) takes up the drop's momentum: the momentum of drop and
/// plate along the normal changes only by the weight of the fluid, within 1 % of the drop's
/// impact momentum.
#[test]
fn a_free_plate_conserves_the_momentum_of_drop_and_plate() {
    let sim0 = Simulation::new(drop_cfg()).unwrap();
    let m_fluid = fluid_mass(&sim0);
    let p0 = fluid_momentum(&sim0);
    let mut plate = SpringPlate {
        m: m_fluid,
        k: 0.0,
        c: 0.0,
        x: 0.0,
        v: 0.0,
    };
    let t_end = 0.03;
    let (sim, _) = coupled(&mut plate, 2.0e-4, t_end);
    let n = sim.state().plate().unwrap().n;
    let g = Vec2::new(0.0, -9.81);
    // Momentum along the plate normal (into the fluid); the plate moves along -n.
    let total = fluid_momentum(&sim).dot(&n) - plate.m * plate.v;
    let expected = p0.dot(&n) + m_fluid * g.dot(&n) * t_end;
    let scale = p0.norm();
    let err = (total - expected).abs() / scale;
    eprintln!(
        "free plate: momentum error {err:.3e} of m U = {scale:.4} kg m/s/m; plate holds {:.3}, plate x = {:.3e} m",
        plate.m * plate.v / scale,
        plate.x
    );
    // The plate really took part: it carries a good part of the drop's momentum.
    assert!(
        plate.m * plate.v > 0.2 * scale,
        "plate momentum {} of {scale}",
        plate.m * plate.v
    );
    assert!(
        err < 0.01,
        "momentum error {err:.3e} of the impact momentum"
    );
}

/// With a very stiff spring and strong damping the plate hardly moves and the wall force is the
/// fixed plate's.
#[test]
fn a_stiff_spring_gives_the_fixed_plate_force() {
    let h = 2.0e-4;
    let t_end = 0.02;
    let sim0 = Simulation::new(drop_cfg()).unwrap();
    let m = 10.0 * fluid_mass(&sim0);
    let k = 1.0e7;
    let mut plate = SpringPlate {
        m,
        k,
        c: 2.0 * (k * m).sqrt(),
        x: 0.0,
        v: 0.0,
    };
    let (_, coupled_forces) = coupled(&mut plate, h, t_end);
    let mut fixed = Simulation::new(drop_cfg()).unwrap();
    let mut fixed_forces = Vec::new();
    for k in 0..coupled_forces.len() {
        fixed_forces.push(fixed.outputs().shared.wall_force_normal);
        fixed.advance_to((k + 1) as f64 * h).unwrap();
    }
    let peak = fixed_forces.iter().cloned().fold(0.0, f64::max);
    let max_diff = coupled_forces
        .iter()
        .zip(&fixed_forces)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "stiff spring: max |F - F_fixed| = {max_diff:.3} N/m of peak {peak:.2} N/m; plate x = {:.3e} m",
        plate.x
    );
    assert!(peak > 1.0, "the drop hit the plate: peak {peak} N/m");
    assert!(
        max_diff < 0.05 * peak,
        "wall force differs by {max_diff} N/m of a peak {peak} N/m"
    );
    assert!(plate.x.abs() < 1e-5, "plate moved {} m", plate.x);
}

/// How a master couples the plate (see [`run_master`]).
#[derive(Clone, Copy, PartialEq)]
enum Master {
    /// Gauss-Seidel: the plate first, then its mean velocity over the step to the solver.
    GaussSeidel,
    /// Jacobi: both advance from the values at t_k; the solver gets the plate's velocity at t_k.
    JacobiVelocity,
    /// Jacobi with `plate_coupling = position`: the solver gets the plate's position and
    /// velocity at t_k.
    JacobiPosition,
}

/// The plate's displacement at each communication point of a coupled run (the master's x) and
/// the largest gap between it and the solver's `plate_displacement`.
fn run_master(master: Master, h: f64, t_end: f64) -> (Vec<f64>, f64) {
    let mut c = drop_cfg();
    if master == Master::JacobiPosition {
        c.set("plate_coupling", s("position")).unwrap();
    }
    let mut sim = Simulation::new(c).unwrap();
    let mut plate = SpringPlate {
        m: 0.314,
        k: 3.1e4,
        c: 20.0,
        x: 0.0,
        v: 0.0,
    };
    let (mut xs, mut gap) = (vec![0.0], 0.0f64);
    let n = (t_end / h).round() as usize;
    for k in 0..n {
        let f = sim.outputs().shared.wall_force_normal;
        let inputs = match master {
            Master::GaussSeidel => sim.inputs().with("plate_velocity", plate.step(f, h)),
            Master::JacobiVelocity => {
                let i = sim.inputs().with("plate_velocity", plate.v);
                plate.step(f, h);
                i
            }
            Master::JacobiPosition => {
                let i = sim
                    .inputs()
                    .with("plate_position", plate.x)
                    .with("plate_velocity", plate.v);
                plate.step(f, h);
                i
            }
        };
        sim.set_inputs(inputs).unwrap();
        sim.advance_to((k + 1) as f64 * h).unwrap();
        xs.push(plate.x);
        gap = gap.max((sim.outputs().shared.plate_displacement - plate.x).abs());
    }
    (xs, gap)
}

/// A Jacobi master (fmpy's SSP runner, libcosim) that gives the solver the plate's velocity at
/// the communication point drifts from the Gauss-Seidel run; giving it the plate's position
/// too (`plate_coupling = position`) keeps the plate displacement within 0.5 % of the
/// Gauss-Seidel run's largest.
#[test]
fn a_position_input_keeps_a_jacobi_master_from_drifting() {
    let (h, t_end) = (2.0e-4, 0.025);
    let (gs, _) = run_master(Master::GaussSeidel, h, t_end);
    let (vel, vel_gap) = run_master(Master::JacobiVelocity, h, t_end);
    let (pos, pos_gap) = run_master(Master::JacobiPosition, h, t_end);
    let scale = gs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let drift = |xs: &[f64]| {
        xs.iter()
            .zip(&gs)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / scale
    };
    let (d_vel, d_pos) = (drift(&vel), drift(&pos));
    eprintln!(
        "largest plate displacement {scale:.4e} m; drift against Gauss-Seidel: Jacobi velocity {:.3} %, \
         Jacobi position {:.3} %; solver's plate off the master's by {vel_gap:.3e} m and {pos_gap:.3e} m",
        100.0 * d_vel,
        100.0 * d_pos
    );
    assert!(scale > 1e-5, "the plate moved: {scale}");
    assert!(d_pos < 0.005, "position coupling drifts {d_pos}");
    assert!(d_pos < d_vel, "{d_pos} vs {d_vel}");
    assert!(pos_gap < vel_gap, "{pos_gap} vs {vel_gap}");
}
