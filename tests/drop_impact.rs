//! Acceptance tests of the WCSPH drop impact (issue 2), at resolutions that keep the suite fast.
//! Fang 2006 section 4: D = 2 cm, V = 1 m/s, nu = 0.004 m2/s (Re = 5), c = 12.5 m/s; Oldroyd-B with
//! lambda1 = 0.02 s, lambda2 = 0.002 s (We = 1, beta = 0.1).

mod common;

use common::{
    assert_impulse_matches, assert_outputs_finite, assert_spreads_monotonically, i,
    integrate_wall_force, r, s, series, series_bits,
};
use viscosph::config::Value;
use viscosph::scene::SceneConfig;
use viscosph::simulation::{SimError, Simulation};
use viscosph::Vec2;

/// Fang's drop on his fixed plate: `max_plate_speed = 0`, so the automatic sound speed is his
/// (12.60 m/s against 12.5; the default 1 m/s of plate motion would raise it to 22.60 m/s).
fn cfg(pairs: &[(&str, Value)]) -> SceneConfig {
    let mut c = SceneConfig::default();
    c.set("max_plate_speed", r(0.0)).unwrap();
    for (k, v) in pairs {
        c.set(k, v.clone()).unwrap();
    }
    c.validate().unwrap();
    c
}

const D: f64 = 0.02;
const T_STAR: f64 = 0.02; // D / V

#[test]
fn newtonian_drop_spreads_monotonically_without_fracture() {
    let c = cfg(&[
        ("rheology", s("newtonian")),
        ("artificial_stress_epsilon", r(0.2)),
    ]);
    let (ser, err, sim) = series(&c, 8.0 * T_STAR, 0.1 * T_STAR);
    assert!(err.is_none(), "{err:?}");
    // Fang's walls hold the fluid by themselves here: the impenetrability condition never acts.
    assert_eq!(sim.state().wall_reflections, 0);
    assert_spreads_monotonically(&ser, D, T_STAR);
    let last = ser.last().unwrap().1;
    assert!(
        last.shared.drop_width / D > 1.8,
        "spread to W* = {}",
        last.shared.drop_width / D
    );
    for (t, o) in &ser {
        assert!(
            o.shared.volume_error.abs() < 0.04,
            "volume error {} at t = {t}",
            o.shared.volume_error
        );
        assert_eq!(o.shared.void_fraction, 0.0, "holes at t = {t}");
    }
}

#[test]
fn oldroyd_b_drop_spreads_retracts_and_stays_stable() {
    let c = cfg(&[("particles_per_diameter", i(30))]);
    let (ser, err, sim) = series(&c, 8.0 * T_STAR, 0.05 * T_STAR);
    assert!(err.is_none(), "{err:?}");
    assert_eq!(sim.state().wall_reflections, 0);
    let w: Vec<(f64, f64)> = ser
        .iter()
        .map(|(t, o)| (t / T_STAR, o.shared.drop_width / D))
        .collect();
    // The first maximum of W* after impact, then a minimum, both before t* = 6.
    let (imax, wmax) = w
        .iter()
        .enumerate()
        .filter(|(_, p)| p.0 < 6.0)
        .fold((0, 0.0), |m, (k, p)| if p.1 > m.1 { (k, p.1) } else { m });
    let (imin, wmin) = w[imax..]
        .iter()
        .enumerate()
        .filter(|(_, p)| p.0 < 6.0)
        .fold(
            (0, f64::MAX),
            |m, (k, p)| if p.1 < m.1 { (k + imax, p.1) } else { m },
        );
    assert!(wmax > 1.8, "spreads: max W* = {wmax}");
    assert!(
        wmax - wmin > 0.05 * wmax && imin > imax && w[imin].0 < 6.0,
        "retracts: max W* {wmax} at t* {} then min {wmin} at t* {}",
        w[imax].0,
        w[imin].0
    );
    let last = ser.last().unwrap().1;
    assert!(
        last.shared.max_conformation_trace.is_finite() && last.shared.min_conformation_det > 0.0
    );
    assert!(ser.iter().all(|(_, o)| o.shared.void_fraction == 0.0));
}

#[test]
fn oldroyd_b_without_artificial_stress_reports_fracture() {
    let c = cfg(&[
        ("particles_per_diameter", i(30)),
        ("artificial_stress_epsilon", r(0.0)),
    ]);
    let (ser, err, sim) = series(&c, 8.0 * T_STAR, 0.05 * T_STAR);
    let err = err.expect("the tensile instability must be reported");
    let msg = err.to_string();
    assert!(
        msg.contains("tensile instability") && msg.contains("t = "),
        "{msg}"
    );
    match err {
        SimError::Breakdown { time, step, .. } => {
            assert!(time > 0.0 && step > 0);
            // The state is left at the last good step, with finite outputs.
            assert!(sim.time() <= time + 1e-12);
        }
        other => panic!("{other:?}"),
    }
    assert_outputs_finite(&ser);
}

#[test]
fn momentum_balance_on_an_inclined_plate() {
    let c = cfg(&[
        ("plate_inclination", r(30.0)),
        ("rheology", s("newtonian")),
        ("artificial_stress_epsilon", r(0.2)),
    ]);
    let dt = 0.025 * T_STAR;
    let mut sim = Simulation::new(c.clone()).unwrap();
    let p0 = sim.fluid_momentum();
    let mass = sim.fluid_mass();
    let plate = sim.state().plate().cloned().unwrap();
    let n = (6.0 * T_STAR / dt).round() as usize;
    let (int_n, int_t) = integrate_wall_force(&mut sim, dt, n);
    // The particles are at the solver's own time (at or just past the communication time).
    let t = sim.state().time;
    // Impulse of the plate on the fluid: change of momentum minus the gravity impulse.
    let j = sim.fluid_momentum() - p0 - Vec2::new(0.0, -c.fluid.gravity) * mass * t;
    // Force of the fluid on the plate is -j.
    assert_impulse_matches((int_n, int_t), j, &plate, 0.03);
    // The exact accumulated impulse matches to round-off.
    let acc = sim.state().wall_impulse;
    assert!((acc + j).norm() < 1e-9 * j.norm(), "{acc} vs {}", -j);
}

#[test]
fn drop_at_rest_weighs_on_the_plate() {
    // A viscous drop set down gently comes to rest; the plate then carries its weight.
    let c = cfg(&[
        ("rheology", s("newtonian")),
        ("viscosity", r(40.0)),
        ("impact_velocity", r(0.0)),
        ("initial_drop_height", r(0.5 * D + 2.0 * D / 20.0)),
        ("artificial_stress_epsilon", r(0.2)),
    ]);
    let mut sim = Simulation::new(c.clone()).unwrap();
    sim.advance_to(0.3).unwrap();
    let weight = sim.fluid_mass() * c.fluid.gravity;
    let o = sim.outputs();
    // Quasi-static: a viscous drop keeps creeping outward at mm/s, but its kinetic energy is
    // negligible against its potential energy scale M g D.
    assert!(
        o.shared.kinetic_energy < 1e-3 * weight * D,
        "not at rest: KE = {}",
        o.shared.kinetic_energy
    );
    let err = (o.shared.wall_force_normal - weight) / weight;
    assert!(
        err.abs() < 0.02,
        "normal force {} vs weight {weight} ({err:+.4})",
        o.shared.wall_force_normal
    );
    assert!(o.shared.wall_force_tangential.abs() < 1e-3 * weight);
}

#[test]
fn level_plate_spreads_symmetrically() {
    let c = cfg(&[]);
    let (ser, err, _) = series(&c, 4.0 * T_STAR, 0.1 * T_STAR);
    assert!(err.is_none(), "{err:?}");
    for (t, o) in &ser {
        assert!(
            (o.shared.spread_front - o.shared.spread_back).abs() <= c.dx(),
            "front {} back {} at t = {t}",
            o.shared.spread_front,
            o.shared.spread_back
        );
        assert!(
            o.shared.wall_force_tangential.abs() < 1e-6 * o.shared.wall_force_normal.abs().max(1.0)
        );
    }
}

#[test]
fn inclined_plate_spreads_downhill() {
    let c = cfg(&[("plate_inclination", r(45.0))]);
    let (ser, err, _) = series(&c, 4.0 * T_STAR, 0.5 * T_STAR);
    assert!(err.is_none(), "{err:?}");
    let o = ser.last().unwrap().1;
    assert!(
        o.shared.spread_front > o.shared.spread_back + 2.0 * c.dx(),
        "{} vs {}",
        o.shared.spread_front,
        o.shared.spread_back
    );
    assert!(
        o.shared.wall_force_tangential > 0.0,
        "the fluid drags the plate downhill"
    );
}

#[test]
fn outputs_are_bitwise_identical_on_one_and_two_threads() {
    let c = cfg(&[("plate_inclination", r(20.0))]);
    // Each simulation runs in its own pool of `threads` workers.
    let run = |threads: i64| {
        let mut c = c.clone();
        c.numerics.threads = threads;
        let (ser, err, sim) = series(&c, 2.5 * T_STAR, 0.25 * T_STAR);
        assert!(err.is_none());
        assert_eq!(sim.threads(), threads as usize);
        (series_bits(&ser), sim.state().clone())
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn too_slow_sound_speed_stops_with_a_message() {
    let c = cfg(&[("sound_speed", r(0.5)), ("impact_velocity", r(3.0))]);
    let (_, err, _) = series(&c, 4.0 * T_STAR, 0.1 * T_STAR);
    let msg = err.expect("breakdown").to_string();
    assert!(msg.contains("step") && msg.contains("t = "), "{msg}");
}

#[test]
fn save_and_restore_continue_identically() {
    let c = cfg(&[("plate_inclination", r(10.0))]);
    let mut a = Simulation::new(c.clone()).unwrap();
    a.advance_to(0.035).unwrap();
    let saved = a.save_state();
    a.advance_to(0.05).unwrap();
    let mut b = Simulation::new(c).unwrap();
    b.restore_state(&saved).unwrap();
    assert_eq!(b.time(), 0.035);
    b.advance_to(0.05).unwrap();
    assert_eq!(a.outputs(), b.outputs());
    assert_eq!(a.save_state(), b.save_state());
}
