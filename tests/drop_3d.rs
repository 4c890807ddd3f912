//! The drop in three dimensions through the whole product (`dimension = 3`): a sphere on a
//! plane plate of any inclination, under the weakly compressible schemes with dummy wall
//! particles and under King & Lind's incompressible scheme with mirror particles, measured by
//! the outputs an FMU user reads. Short runs at 10 particles per diameter keep these in the
//! suite; the resolution study is `viscosph bench`'s.

mod common;

use common::{i, r, s};
use viscosph::config::Value;
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

const D: f64 = 0.02;
const T_STAR: f64 = 0.02; // D / V
/// Largest relative change of the ISPH sphere's second-moment volume in free fall (10 per D).
const FREE_FALL_BOUND: f64 = 0.02;
/// Largest |volume_error| of the ISPH sphere on the plate, t* = 1..2 (10 per D; before, the
/// particles keep much of their lattice, which the covered volume reads high).
const PLATE_BOUND: f64 = 0.02;
/// Fang's Oldroyd-B sphere under ISPH at t* = 1.5 (10 per D): least width / D and tr A.
const FANG_MIN_WIDTH: f64 = 1.6;
const FANG_MIN_TRACE: f64 = 4.0;

/// A 3D drop (D = 2 cm, V = 1 m/s, the table's Oldroyd-B fluid unless `pairs` say otherwise),
/// 10 particles per diameter, released just above the plate.
fn cfg(pairs: &[(&str, Value)]) -> SceneConfig {
    let mut c = SceneConfig::default();
    c.set("dimension", i(3)).unwrap();
    c.set("particles_per_diameter", i(10)).unwrap();
    c.set("initial_drop_height", r(0.6 * D)).unwrap();
    for (k, v) in pairs {
        c.set(k, v.clone()).unwrap();
    }
    c.validate().unwrap();
    c
}

/// The drop released just above the plate at the given inclination: the normal impact on a
/// level plate (spread equal along and across) and the transverse symmetry on an incline.
fn spread_after(c: SceneConfig, t_end: f64) -> (Simulation, viscosph::Outputs) {
    let mut sim = Simulation::new(c).unwrap();
    sim.advance_to(t_end).unwrap();
    let o = sim.outputs();
    (sim, o)
}

/// W*(t* = 1.5) of the Newtonian sphere over the slab's (the disc extended across), both
/// released 0.6 D above a level plate at 10 per diameter, under King & Lind's incompressible
/// scheme with mirror walls (another scheme and wall model than the test's): 1.478 / 1.746 =
/// 0.846 (at 20 per diameter 1.416 / 1.702 = 0.832). A sphere spreads less than a disc: its
/// fluid leaves the axis in every direction along the plate.
const SPHERE_OVER_SLAB: f64 = 0.846;

/// A normal impact on a level plate spreads equally along and across within 1 %, and as far,
/// relative to the same flow in 2D (the slab), as the incompressible scheme's sphere does.
/// The weakly compressible schemes at 10 per diameter spread much less than at high
/// resolution (the 2D disc under WCSPH with Fang's walls: W*(1.5) = 1.392, 1.522, 1.649, 1.690
/// at 10, 20, 40, 80 per diameter; ISPH's 1.714, 1.694, 1.659, 1.650), so W* alone has no
/// reference at this resolution; the ratio to the slab at the same resolution has.
#[test]
fn a_normal_impact_on_a_level_plate_spreads_equally_along_and_across() {
    for scheme in ["wcsph", "pdri"] {
        let c = cfg(&[("scheme", s(scheme)), ("rheology", s("newtonian"))]);
        let mut slab = c.clone();
        slab.set("drop_shape", s("slab")).unwrap();
        let (sim, o) = spread_after(c, 1.5 * T_STAR);
        let sh = o.shared;
        let w_slab = spread_after(slab, 1.5 * T_STAR).1.shared.drop_width;
        let ratio = sh.drop_width / w_slab;
        eprintln!(
            "{scheme}: {} particles, W = {:.5} D along, {:.5} D across (slab {:.5} D, ratio \
             {ratio:.4}), H = {:.4} D, F_n = {:.4e} N",
            sim.particle_count(),
            sh.drop_width / D,
            sh.drop_width_transverse / D,
            w_slab / D,
            sh.drop_height / D,
            sh.wall_force_normal_total
        );
        assert_eq!(sim.dimension(), 3);
        // Measured: W* = 1.265 (WCSPH) and 1.315 (PDRI), the slab 1.426 and 1.542: ratios
        // 0.887 and 0.853, 4.8 % and 0.8 % above the incompressible scheme's. With the dummy
        // particles' extrapolated no-slip velocity in the continuity equation instead of the
        // wall's (`Boundary::continuity_at_wall_velocity`), their false compression of the
        // first rows held the sphere higher and wider: W* 1.312 and 1.425, ratios 0.924 and
        // 0.866 (+9.2 % and +2.3 %).
        assert!(
            (ratio / SPHERE_OVER_SLAB - 1.0).abs() < 0.06,
            "{scheme}: sphere over slab {ratio}, the incompressible scheme's {SPHERE_OVER_SLAB}"
        );
        // It spread: the reference's ratio times the slab's W* is 1.21 (WCSPH) and 1.30
        // (PDRI); the bound leaves 5 % below the smaller.
        spread_round(&sh, 1.15);
        // Per-depth outputs mean nothing in 3D: they hold 0 and the totals carry the values.
        assert_eq!(sh.wall_force_normal, 0.0);
        assert_eq!(sh.kinetic_energy, 0.0);
        assert!(sh.kinetic_energy_total > 0.0);
    }
}

#[test]
fn on_an_inclined_plate_the_transverse_spread_is_symmetric_about_the_downhill_line() {
    let c = cfg(&[
        ("plate_inclination", r(30.0)),
        ("initial_drop_height", r(0.7 * D)),
        ("rheology", s("oldroyd_b")),
    ]);
    let (sim, o) = spread_after(c, 1.5 * T_STAR);
    let st = sim.state_3d().unwrap();
    let plate = st.plate().unwrap();
    let across = plate.n.cross(&plate.t);
    let b: Vec<f64> = st
        .fluid
        .x
        .iter()
        .map(|x| (x - plate.origin).dot(&across))
        .collect();
    let (lo, hi) = b
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
    let mean = b.iter().sum::<f64>() / b.len() as f64;
    let front = o.shared.spread_front;
    eprintln!(
        "30 deg: across {lo:.6} .. {hi:.6} m (mean {mean:.3e}), downhill front {front:.5} m, back {:.5} m",
        o.shared.spread_back
    );
    assert!(hi - lo > 1.1 * D, "the drop spread across: {}", hi - lo);
    assert!(
        (hi + lo).abs() < 0.01 * (hi - lo),
        "spread {lo} .. {hi} about the downhill line"
    );
    assert!(
        mean.abs() < 1e-3 * D,
        "centroid {mean} m off the downhill line"
    );
    // Downhill: the drop runs further down than up the incline.
    assert!(o.shared.spread_front > o.shared.spread_back);
}

/// The plate's normal impulse against the drop's momentum (Newton's second law over the run):
/// the time integral of `wall_force_normal_total` [N] equals the fluid's loss of momentum into
/// the plate plus its weight's impulse into the plate, within 2 %.
fn impulse_balance(c: SceneConfig, n: usize, t_end: f64) -> (f64, f64) {
    let depth = c.depth();
    let mut sim = Simulation::new(c).unwrap();
    let momentum = |sim: &Simulation| match sim.state_3d() {
        Some(st) => {
            let p = sim.fluid_momentum_3d().unwrap();
            p.dot(&st.plate().unwrap().n)
        }
        None => sim.fluid_momentum().dot(&sim.state().plate().unwrap().n) * depth,
    };
    let weight = |sim: &Simulation| match sim.state_3d() {
        Some(st) => sim.fluid_mass() * 9.81 * st.plate().unwrap().n.z,
        None => sim.fluid_mass() * 9.81 * sim.state().plate().unwrap().n.y * depth,
    };
    let p0 = momentum(&sim);
    let dt = t_end / n as f64;
    let mut prev = sim.outputs().shared.wall_force_normal_total;
    let mut integral = 0.0;
    for k in 1..=n {
        sim.advance_to(k as f64 * dt).unwrap();
        let f = sim.outputs().shared.wall_force_normal_total;
        integral += 0.5 * dt * (f + prev);
        prev = f;
    }
    // Along n: dP/dt = F_n - M g n_z (the plate pushes the fluid along n as hard as the fluid
    // pushes it along -n), so int F_n dt = (P1 - P0) + M g n_z t.
    let want = (momentum(&sim) - p0) + weight(&sim) * sim.time();
    (integral, want)
}

#[test]
fn the_normal_impulse_on_the_plate_balances_the_momentum_in_3d_and_in_2d_with_depth() {
    for (dimension, ppd, depth) in [(3, 10, 0.0), (2, 20, 0.0), (2, 20, 0.05)] {
        let c = cfg(&[
            ("dimension", i(dimension)),
            ("particles_per_diameter", i(ppd)),
            ("plate_inclination", r(20.0)),
            ("initial_drop_height", r(0.7 * D)),
            ("rheology", s("newtonian")),
            ("depth", r(depth)),
        ]);
        let (got, want) = impulse_balance(c, 600, 1.5 * T_STAR);
        eprintln!("{dimension}D, depth {depth}: int F_n dt = {got:.6e} N s, momentum balance {want:.6e} N s");
        assert!(want > 1e-5, "the plate took an impulse: {want}");
        assert!((got - want).abs() < 0.02 * want, "{got} vs {want}");
    }
}

#[test]
fn a_3d_run_is_bitwise_the_same_on_one_and_two_threads() {
    let run = |threads: i64| {
        let c = cfg(&[
            ("threads", i(threads)),
            ("scheme", s("pdri")),
            ("plate_inclination", r(10.0)),
            ("initial_drop_height", r(0.7 * D)),
        ]);
        let mut sim = Simulation::new(c).unwrap();
        sim.advance_to(0.5 * T_STAR).unwrap();
        assert_eq!(sim.threads(), threads as usize);
        let bits: Vec<u64> = sim.outputs().values().iter().map(|v| v.to_bits()).collect();
        (sim.state_3d().unwrap().clone(), bits)
    };
    let (a, b) = (run(1), run(2));
    assert!(a.0.step > 10);
    assert!(a.0 == b.0, "the 3D states differ between 1 and 2 threads");
    assert_eq!(a.1, b.1);
}

#[test]
fn a_3d_run_follows_the_plate_input_and_restores_bitwise() {
    let c = cfg(&[("rheology", s("giesekus")), ("plate_velocity", r(0.0))]);
    let mut sim = Simulation::new(c).unwrap();
    sim.advance_to(0.2 * T_STAR).unwrap();
    // The plate driven into the drop at 0.5 m/s from here on.
    let inputs = sim.inputs().with("plate_velocity", -0.5);
    sim.set_inputs(inputs).unwrap();
    sim.advance_to(0.4 * T_STAR).unwrap();
    let saved = sim.save_state();
    sim.advance_to(0.8 * T_STAR).unwrap();
    let (o1, st1) = (sim.outputs(), sim.state_3d().unwrap().clone());
    let moved = o1.shared.plate_displacement;
    assert!(
        (moved - (-0.5) * 0.6 * T_STAR).abs() < 1e-9,
        "the plate moved {moved} m along -n"
    );
    let mut other = Simulation::new(cfg(&[])).unwrap();
    other.restore_state(&saved).unwrap();
    other.advance_to(0.8 * T_STAR).unwrap();
    let st2 = other.state_3d().unwrap();
    eprintln!(
        "restored: time {} vs {}, step {} vs {}, x {}, v {}, rho {}, conf {}, walls {}, force {}",
        st2.time,
        st1.time,
        st2.step,
        st1.step,
        st2.fluid.x == st1.fluid.x,
        st2.fluid.v == st1.fluid.v,
        st2.fluid.rho == st1.fluid.rho,
        st2.fluid.conf == st1.fluid.conf,
        st2.walls == st1.walls,
        st2.wall_force == st1.wall_force
    );
    assert!(st2 == &st1, "restored run differs");
    assert_eq!(
        other
            .outputs()
            .values()
            .iter()
            .map(|v| v.to_bits())
            .collect::<Vec<_>>(),
        o1.values().iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
}

#[test]
fn dimension_3_refuses_what_has_no_3d_form_by_name() {
    let refusal = |pairs: &[(&str, Value)]| {
        let mut c = SceneConfig::default();
        c.set("dimension", i(3)).unwrap();
        for (k, v) in pairs {
            c.set(k, v.clone()).unwrap();
        }
        Simulation::validate(&c).unwrap_err().to_string()
    };
    // The cylinder array has no 3D form; the message lists the scenes that have one.
    let e = refusal(&[("scene", s("cylinder_array"))]);
    assert!(
        e.contains("'cylinder_array'")
            && e.contains("'drop'")
            && e.contains("'channel'")
            && e.contains("'jet'"),
        "{e}"
    );
    let e = refusal(&[("wall_boundary", s("image"))]);
    assert!(
        e.contains("wall_boundary = image") && e.contains("dummy"),
        "{e}"
    );
    let e = refusal(&[("wall_boundary", s("ghost"))]);
    assert!(e.contains("wall_boundary = ghost"), "{e}");
    let mut c = SceneConfig::default();
    c.set("dimension", i(3)).unwrap();
    c.set("wall_boundary", s("dummy")).unwrap();
    Simulation::validate(&c).unwrap();
    assert!(SceneConfig::default().set("dimension", i(4)).is_err());
}

/// King & Lind's Re = 4 drop as a sphere (W = 2 cm, centre W above the plate, U = 1 m/s,
/// eta0 = 5 Pa s) under the incompressible scheme at `ppd` particles per diameter.
fn isph_sphere(pairs: &[(&str, Value)]) -> SceneConfig {
    let mut all: Vec<(&str, Value)> = vec![
        ("scheme", s("isph")),
        ("rheology", s("newtonian")),
        ("viscosity", r(5.0)),
        ("initial_drop_height", r(D)),
    ];
    all.extend(pairs.iter().cloned());
    cfg(&all)
}

/// The volume of a uniform ball with the particles' second moment about their centre (each
/// particle a dx^3 cube: `<|x - c|^2> + dx^2 / 4 = 3 R^2 / 5`). A sphere in free fall moves as
/// a rigid body, so this stays; a compressed surface layer lowers it.
fn gyration_volume(x: &[viscosph::dim::Vector<3>], dx: f64) -> f64 {
    let n = x.len() as f64;
    let c = x
        .iter()
        .fold(viscosph::dim::Vector::<3>::zeros(), |a, p| a + p)
        / n;
    let m2 = x.iter().map(|p| (p - c).norm_squared()).sum::<f64>() / n + 0.25 * dx * dx;
    let r = (5.0 / 3.0 * m2).sqrt();
    4.0 / 3.0 * std::f64::consts::PI * r * r * r
}

/// The Re = 4 sphere released 5 D above the plate falls freely for t* = 0.5 (no contact): it
/// keeps its volume, measured by its second moment (the covered volume reads the cut lattice's
/// staircase, which free fall keeps). The density-invariant sources near the surface take a
/// reference that follows the surface's curvature: against the flat references the sphere's
/// second-moment volume fell by 3.7 % in this fall.
#[test]
fn a_free_falling_isph_sphere_keeps_its_volume() {
    let c = isph_sphere(&[("initial_drop_height", r(5.0 * D))]);
    let dx = D / 10.0;
    let mut sim = Simulation::new(c).unwrap();
    let v0 = gyration_volume(&sim.state_3d().unwrap().fluid.x, dx);
    let mut worst = 0.0f64;
    for k in 1..=4 {
        sim.advance_to(k as f64 * 0.125 * T_STAR).unwrap();
        let v = gyration_volume(&sim.state_3d().unwrap().fluid.x, dx);
        eprintln!(
            "t* = {:.3}: second-moment volume {:+.3} %, volume_error {:+.3} %",
            k as f64 * 0.125,
            100.0 * (v / v0 - 1.0),
            100.0 * sim.outputs().shared.volume_error
        );
        worst = worst.max((v / v0 - 1.0).abs());
    }
    assert!(worst < FREE_FALL_BOUND, "free fall: {:.3} %", 100.0 * worst);
}

/// The Re = 4 sphere on a level plate under ISPH at 10 particles per diameter to t* = 2: it
/// spreads equally along and across the plate (within 1 %) and keeps its volume
/// (`volume_error`, the covered volume over N dx^3, from t* = 1 on: the cut lattice, which the
/// particles keep in part until the impact has disordered them, reads high); it reports the pressure Poisson equation's iterations per step.
#[test]
fn an_isph_sphere_on_a_level_plate_spreads_equally_along_and_across() {
    let c = isph_sphere(&[]);
    let mut sim = Simulation::new(c).unwrap();
    let mut worst = 0.0f64;
    let mut o = sim.outputs();
    for k in 1..=8 {
        sim.advance_to(k as f64 * 0.25 * T_STAR).unwrap();
        o = sim.outputs();
        eprintln!(
            "t* = {:.2}: W along {:.5} D, across {:.5} D, H {:.4} D, volume_error {:+.3} %",
            k as f64 * 0.25,
            o.shared.drop_width / D,
            o.shared.drop_width_transverse / D,
            o.shared.drop_height / D,
            100.0 * o.shared.volume_error
        );
        if k >= 4 {
            worst = worst.max(o.shared.volume_error.abs());
        }
    }
    let st = sim.state_3d().unwrap();
    eprintln!(
        "{} particles, {} steps: {:.1} PPE and {:.1} viscous iterations per step",
        st.fluid.len(),
        st.step,
        st.solver_iterations[0] as f64 / st.step as f64,
        st.solver_iterations[1] as f64 / st.step as f64
    );
    let sh = o.shared;
    spread_round(&sh, 1.3);
    assert!(
        worst < PLATE_BOUND,
        "largest |volume_error| {:.3} %",
        100.0 * worst
    );
    assert!(st.solver_iterations[0] > 0);
}

/// The Re = 4 sphere on a 20 degree incline under ISPH: the walls' impulse the scheme books is
/// exactly the fluid's momentum change less gravity's and the ALE remapping's impulses (every
/// fluid pair force cancels; the mirrors' pair forces and the implicit viscous solve's change
/// are the wall's), and the time integral of `wall_force_normal_total` matches it within 5 %.
#[test]
fn an_isph_sphere_on_an_incline_balances_its_impulse() {
    let c = isph_sphere(&[
        ("plate_inclination", r(20.0)),
        ("initial_drop_height", r(0.7 * D)),
    ]);
    let g = c.fluid.gravity;
    let mut sim = Simulation::new(c).unwrap();
    let p0 = sim.fluid_momentum_3d().unwrap();
    let mass = sim.fluid_mass();
    let n_steps = 300;
    let dt = 1.5 * T_STAR / n_steps as f64;
    let mut prev = sim.outputs().shared.wall_force_normal_total;
    let mut integral = 0.0;
    for k in 1..=n_steps {
        sim.advance_to(k as f64 * dt).unwrap();
        let f = sim.outputs().shared.wall_force_normal_total;
        integral += 0.5 * dt * (f + prev);
        prev = f;
    }
    let st = sim.state_3d().unwrap();
    let gravity = viscosph::dim::Vector::<3>::new(0.0, 0.0, -g);
    let j = sim.fluid_momentum_3d().unwrap() - p0 - gravity * mass * st.time - st.remap_impulse;
    let n = st.plate().unwrap().n;
    eprintln!(
        "wall impulse {:.6e}, momentum balance {:.6e}, remap {:.3e} N s; int F_n dt = {integral:.6e}          vs {:.6e} N s",
        st.wall_impulse.norm(),
        j.norm(),
        st.remap_impulse.norm(),
        -st.wall_impulse.dot(&n)
    );
    assert!(j.norm() > 1e-5, "{j}");
    assert!((st.wall_impulse + j).norm() < 1e-9 * j.norm());
    let want = j.dot(&n);
    assert!(
        (integral - want).abs() < 0.05 * want,
        "{integral} vs {want}"
    );
}

#[test]
fn a_3d_isph_run_is_bitwise_the_same_on_one_and_two_threads() {
    let run = |threads: i64| {
        let c = isph_sphere(&[
            ("threads", i(threads)),
            ("plate_inclination", r(10.0)),
            ("initial_drop_height", r(0.7 * D)),
        ]);
        let mut sim = Simulation::new(c).unwrap();
        sim.advance_to(0.5 * T_STAR).unwrap();
        let bits: Vec<u64> = sim.outputs().values().iter().map(|v| v.to_bits()).collect();
        (sim.state_3d().unwrap().clone(), bits)
    };
    let (a, b) = (run(1), run(2));
    assert!(a.0.step > 5);
    assert!(
        a.0 == b.0,
        "the 3D ISPH states differ between 1 and 2 threads"
    );
    assert_eq!(a.1, b.1);
}

/// The slab (`drop_shape = slab`): the 2D disc extended across, periodic across, spreads as
/// the 2D drop does, so the 3D code reproduces the 2D one. Newtonian and Oldroyd-B under WCSPH
/// and PDRI at 10 per diameter to t* = 1.5, against the 2D drop with the same wall model
/// (dummy particles) and with the scheme's own 2D walls; the table at 20 per diameter to
/// t* = 4 is on the drop's page of the book.
#[test]
fn a_3d_slab_spreads_as_the_2d_drop() {
    for scheme in ["wcsph", "pdri"] {
        for rheology in ["newtonian", "oldroyd_b"] {
            let slab = cfg(&[
                ("scheme", s(scheme)),
                ("rheology", s(rheology)),
                ("drop_shape", s("slab")),
            ]);
            let flat = |walls: &str| {
                let mut c = slab.clone();
                c.set("dimension", i(2)).unwrap();
                c.set("wall_boundary", s(walls)).unwrap();
                let mut sim = Simulation::new(c).unwrap();
                let n = sim.particle_count();
                sim.advance_to(1.5 * T_STAR).unwrap();
                (n, sim.outputs().shared.drop_width / D)
            };
            let (n2, w_dummy) = flat("dummy");
            let (_, w_paper) = flat("auto");
            let mut sim = Simulation::new(slab).unwrap();
            sim.advance_to(1.5 * T_STAR).unwrap();
            let st = sim.state_3d().unwrap();
            let w3 = sim.outputs().shared.drop_width / D;
            let cross = st.fluid.v.iter().map(|v| v.y.abs()).fold(0.0, f64::max);
            eprintln!(
                "{scheme} {rheology}: W* slab {w3:.4}, 2D dummy {w_dummy:.4}, 2D paper walls \
                 {w_paper:.4}; |v_y| <= {cross:.2e} m/s"
            );
            // Eight layers of the disc's lattice across.
            assert_eq!(st.fluid.len(), 8 * n2, "{scheme} {rheology}");
            assert!(w3 > 1.3, "{scheme} {rheology}: the slab spread, W* = {w3}");
            // The flow stays plane: the layers move alike.
            assert!(cross < 1e-9, "{scheme} {rheology}: |v_y| {cross} m/s");
            // Measured at 10 per diameter: the slab 3.1 % (PDRI Newtonian) to 7.3 % (WCSPH
            // Oldroyd-B) wider than the 2D drop with dummy walls, 0.1-7.3 % than with the
            // scheme's own walls (the 3D kernel on the cubic lattice is another
            // discretisation of the same flow; 2-8 % at 20 per diameter, the book's table).
            assert!(
                (w3 - w_dummy).abs() < 0.10 * w_dummy,
                "{scheme} {rheology}: slab {w3} vs 2D {w_dummy}"
            );
            assert!(
                (w3 - w_paper).abs() < 0.10 * w_paper,
                "{scheme} {rheology}: slab {w3} vs 2D paper walls {w_paper}"
            );
        }
    }
}

/// The drop spread wider than `w` D and equally along and across the plate (within 1 %).
fn spread_round(sh: &viscosph::diagnostics::SharedOutputs, w: f64) {
    assert!(
        sh.drop_width > w * D,
        "the drop spread: W* = {}",
        sh.drop_width / D
    );
    assert!(
        (sh.drop_width / sh.drop_width_transverse - 1.0).abs() < 0.01,
        "along {} vs across {}",
        sh.drop_width,
        sh.drop_width_transverse
    );
}

/// Fang's Oldroyd-B drop (the table's fluid: eta0 = 4 Pa s, beta = 0.1, lambda = 0.02 s) as a
/// sphere under ISPH, released 0.6 D above a level plate, to t* = 1.5: it spreads equally along
/// and across, and the impact stretches the polymer (tr A above its rest value 3, the
/// log-conformation keeping det A positive).
#[test]
fn fangs_oldroyd_b_sphere_under_isph_spreads_symmetrically_and_stretches_its_polymer() {
    let c = cfg(&[("scheme", s("isph"))]);
    let (sim, o) = spread_after(c, 1.5 * T_STAR);
    let sh = o.shared;
    eprintln!(
        "{} particles: W = {:.5} D along, {:.5} D across, max tr A {:.4}, min det A {:.4}, \
         volume_error {:+.3} %",
        sim.particle_count(),
        sh.drop_width / D,
        sh.drop_width_transverse / D,
        sh.max_conformation_trace,
        sh.min_conformation_det,
        100.0 * sh.volume_error
    );
    spread_round(&sh, FANG_MIN_WIDTH);
    assert!(
        sh.max_conformation_trace > FANG_MIN_TRACE && sh.max_conformation_trace.is_finite(),
        "tr A = {}",
        sh.max_conformation_trace
    );
    assert!(sh.min_conformation_det > 0.0);
}

/// A sphere of fluid one spacing above a level plate and a film beside it: of the plate's whole
/// dummy layout (the fluid's extent with three search radii to spare) exactly the particles
/// within the search radius plus one kernel radius of some fluid particle are kept, in the
/// layout's order. Those are all a fluid particle can reach before the next placement (it moves
/// less than half the skin) and all a kept particle's own sums reach (its Shepard sums over the
/// fluid within the search radius, Ren's wall Hessian over the virtual particles within one
/// kernel radius), so the runs are bitwise those with the whole layout; most of the square
/// layout is gone.
#[test]
fn a_plate_keeps_only_the_dummy_particles_the_fluid_can_reach() {
    use viscosph::boundary::dummy::DummyWall;
    use viscosph::boundary::plate::Plate;
    use viscosph::boundary::wall::Wall;
    use viscosph::boundary::Boundary;
    use viscosph::dim::Vector;
    use viscosph::kernel::{CubicSplineKernel, Kernel};
    use viscosph::neighbors::{Domain, Grid};
    let dx = 0.001;
    let kernel = CubicSplineKernel::<3>::new(1.5 * dx);
    let radius = kernel.radius() + 0.25 * kernel.h();
    let mut fluid = Vec::new();
    for a in -12..=12 {
        for b in -12..=12 {
            for c in -12..=12 {
                let p = Vector::<3>::new(a as f64, b as f64, c as f64) * dx;
                if p.norm() <= 10.0 * dx {
                    fluid.push(p + Vector::<3>::new(0.0, 0.0, 11.5 * dx));
                }
            }
            for c in 0..2 {
                let q = Vector::<3>::new((30 + a) as f64, b as f64 * 0.3, c as f64 + 0.5);
                fluid.push(q * dx);
            }
        }
    }
    let dom = Domain::OPEN;
    let mut wall = Wall::from(Plate::through(
        Vector::<3>::zeros(),
        Vector::<3>::z(),
        Vector::<3>::x(),
        dx,
    ));
    let mut dummy = DummyWall::new(kernel, dom, dx, Vector::<3>::new(0.0, 0.0, -9.81));
    let grid = Grid::build(&fluid, radius, &dom);
    let mut out = Vec::new();
    dummy.place(&mut wall, &fluid, &grid, radius, &mut out);
    let all = dummy.layout(&wall);
    let reach = radius + kernel.radius();
    let expected: Vec<Vector<3>> = all
        .iter()
        .filter(|w| fluid.iter().any(|f| (*w - f).norm() < reach))
        .copied()
        .collect();
    assert_eq!(out, expected);
    assert_eq!(dummy.positions(&wall), expected);
    assert!(
        2 * out.len() < all.len(),
        "{} of {} kept",
        out.len(),
        all.len()
    );
}
