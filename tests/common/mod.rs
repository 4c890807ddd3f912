//! Helpers shared by the integration tests: parameter values and a recorded run.
#![allow(dead_code)]

use viscosph::config::Value;
use viscosph::scene::Outputs;
use viscosph::scene::SceneConfig;
use viscosph::simulation::{SimError, Simulation};

pub fn r(x: f64) -> Value {
    Value::Real(x)
}
pub fn i(x: i64) -> Value {
    Value::Integer(x)
}
pub fn s(x: &str) -> Value {
    Value::Text(x.into())
}

/// Outputs every `dt` up to `t_end`, or the breakdown, and the simulation where it stopped.
pub fn series(
    c: &SceneConfig,
    t_end: f64,
    dt: f64,
) -> (Vec<(f64, Outputs)>, Option<SimError>, Simulation) {
    let mut sim = Simulation::new(c.clone()).unwrap();
    let (out, err) = sim.record(t_end, dt);
    (out, err, sim)
}

/// Every bit of a recorded series (times and outputs), for bitwise comparisons.
pub fn series_bits(ser: &[(f64, Outputs)]) -> Vec<u64> {
    ser.iter()
        .flat_map(|(t, o)| std::iter::once(*t).chain(o.values()))
        .map(f64::to_bits)
        .collect()
}

/// Advance `sim` by `n` communication steps of `dt` and integrate the wall-force outputs over
/// them by the trapezoidal rule: (normal, tangential) impulse [N s/m].
pub fn integrate_wall_force(sim: &mut Simulation, dt: f64, n: usize) -> (f64, f64) {
    let t0 = sim.time();
    let mut prev = sim.outputs();
    let (mut int_n, mut int_t) = (0.0, 0.0);
    for k in 1..=n {
        sim.advance_to(t0 + k as f64 * dt).unwrap();
        let o = sim.outputs();
        int_n += 0.5 * dt * (o.shared.wall_force_normal + prev.shared.wall_force_normal);
        int_t += 0.5 * dt * (o.shared.wall_force_tangential + prev.shared.wall_force_tangential);
        prev = o;
    }
    (int_n, int_t)
}

/// From the first output with a force on the plate on, the drop width never decreases; the
/// message gives W / `scale` and t / `t_scale` where it does.
pub fn assert_spreads_monotonically(ser: &[(f64, Outputs)], scale: f64, t_scale: f64) {
    let impact = ser
        .iter()
        .position(|(_, o)| o.shared.wall_force_normal > 0.0)
        .expect("the drop reaches the plate");
    for w in ser[impact..].windows(2) {
        assert!(
            w[1].1.shared.drop_width >= w[0].1.shared.drop_width,
            "W* fell from {} to {} at t* = {}",
            w[0].1.shared.drop_width / scale,
            w[1].1.shared.drop_width / scale,
            w[1].0 / t_scale
        );
    }
}

/// The time integral of the wall-force outputs `(int_n, int_t)` equals the impulse of the fluid
/// on `plate`, minus `j` (the impulse of the plate on the fluid), within `tol` relative, in the
/// outputs' frame: normal into the plate (-n), tangential along t.
pub fn assert_impulse_matches(
    (int_n, int_t): (f64, f64),
    j: viscosph::Vec2,
    plate: &viscosph::boundary::plate::Plate,
    tol: f64,
) {
    let (want_n, want_t) = (j.dot(&plate.n), -j.dot(&plate.t));
    assert!(
        want_n.abs() > 1e-3 && want_t.abs() > 1e-4,
        "the plate took too little impulse to compare: {want_n} {want_t}"
    );
    let (en, et) = ((int_n - want_n) / want_n, (int_t - want_t) / want_t);
    assert!(
        en.abs() < tol && et.abs() < tol,
        "normal {int_n} vs {want_n} ({en:+.4}), tangential {int_t} vs {want_t} ({et:+.4})"
    );
}

/// Every output of every recorded row is finite.
pub fn assert_outputs_finite(ser: &[(f64, Outputs)]) {
    for (t, o) in ser {
        assert!(
            o.values().iter().all(|v| v.is_finite()),
            "non-finite output at t = {t}: {o:?}"
        );
    }
}
