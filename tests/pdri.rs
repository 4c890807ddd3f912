//! PDRI-SPH (Ren, Lu & Jiang 2015) acceptance tests: the Cross drop of Ren section 4.3 on inclined
//! plates, the artificial stress against fracture, the pressure field with and without density
//! reinitialisation, and the solver contracts (threads, momentum, save/restore, every rheology).
//!
//! Ren 4.2-4.3: D = 2 cm, V = 1 m/s, rho0 = 1000, c = 12 m/s, g = 9.81, drop centre 4 cm above the
//! impact point, h = 1.5 d0, artificial viscosity alpha = 1, beta = 2, artificial stress b = 0.8,
//! reinitialisation every 20 steps; Cross fluid nu0 = 4e-3, nu_inf = 4e-4 m2/s (eta0 = 4,
//! eta_inf = 0.4 Pa s), K = 1 s, m = 1. Ren runs 1961 and 7845 particles; the suite runs 316
//! (particles_per_diameter = 20), where every assertion below holds with a margin, except the
//! fracture without artificial stress, run at Ren's 1961; the example `ren_fig14` runs finer.

mod common;

use common::{i, r, s, series};
use viscosph::config::Value;
use viscosph::scene::Outputs;
use viscosph::scene::SceneConfig;
use viscosph::simulation::{SimError, Simulation};
use viscosph::Vec2;

const D: f64 = 0.02;
const T_STAR: f64 = 0.02; // D / V

/// Ren's drop under PDRI-SPH, Cross fluid, with `pairs` on top.
fn ren(pairs: &[(&str, Value)]) -> SceneConfig {
    let mut c = SceneConfig::default();
    for (k, v) in [
        ("scheme", s("pdri")),
        ("rheology", s("cross")),
        ("viscosity", r(4.0)),
        ("cross_viscosity_inf", r(0.4)),
        ("cross_K", r(1.0)),
        ("cross_m", r(1.0)),
        ("sound_speed", r(12.0)),
        ("artificial_stress_kind", s("ren")),
        ("artificial_stress_b", r(0.8)),
        ("density_reinit_interval", i(20)),
        ("particles_per_diameter", i(20)),
    ]
    .iter()
    .chain(pairs)
    {
        c.set(k, v.clone()).unwrap();
    }
    c.validate().unwrap();
    c
}

#[test]
fn cross_drop_spreads_downhill_more_the_steeper_the_plate() {
    // Ren Figs. 13-14: stable to t* = 8 with b = 0.8; the front runs downhill, further on a
    // steeper plate, and the asymmetry between front and back grows with the angle.
    let mut last = Vec::new();
    for angle in [15.0, 30.0, 45.0] {
        let c = ren(&[("plate_inclination", r(angle))]);
        let (ser, err, _) = series(&c, 8.0 * T_STAR, 0.5 * T_STAR);
        assert!(err.is_none(), "{angle} deg: {err:?}");
        assert!(
            ser.iter().all(|(_, o)| o.shared.void_fraction == 0.0),
            "{angle} deg: holes"
        );
        let o = ser.last().unwrap().1;
        println!(
            "{angle} deg: X_front = {:.3} D, X_back = {:.3} D",
            o.shared.spread_front / D,
            o.shared.spread_back / D
        );
        assert!(
            o.shared.spread_front > o.shared.spread_back + 2.0 * c.dx(),
            "{angle} deg: front {} back {}",
            o.shared.spread_front,
            o.shared.spread_back
        );
        last.push(o);
    }
    for w in last.windows(2) {
        assert!(
            w[1].shared.spread_front > w[0].shared.spread_front + D / 20.0,
            "{} then {}",
            w[0].shared.spread_front,
            w[1].shared.spread_front
        );
        let asym = |o: &Outputs| o.shared.spread_front - o.shared.spread_back;
        assert!(
            asym(&w[1]) > asym(&w[0]),
            "{} then {}",
            asym(&w[0]),
            asym(&w[1])
        );
    }
}

#[test]
fn cross_drop_without_artificial_stress_fractures() {
    // Ren Figs. 7-8: with b = 0 the Cross drop tears apart on inclined plates. Run at Ren's
    // resolution of section 4.2 (particles_per_diameter = 50, 1976 particles here against Ren's
    // 1961): measured, the holes pass 2 % of the area at t* = 2.7 (15 deg), 2.9 (30 deg) and 3.5
    // (45 deg), while with b = 0.8 all three run to t* = 8 without a hole. (Coarser drops hold
    // together on the steeper plates: at 40 per diameter the 45 deg drop does not tear.)
    for angle in [15.0, 30.0, 45.0] {
        let c = ren(&[
            ("plate_inclination", r(angle)),
            ("artificial_stress_b", r(0.0)),
            ("particles_per_diameter", i(50)),
        ]);
        let (_, err, sim) = series(&c, 8.0 * T_STAR, 0.5 * T_STAR);
        let Some(SimError::Breakdown { time, step, cause }) = err else {
            panic!("{angle} deg: the tensile instability must be reported, got {err:?}");
        };
        println!("{angle} deg: {cause} at t* = {:.2}", time / T_STAR);
        assert!(
            cause.contains("tensile instability") && cause.contains("artificial_stress_b"),
            "{angle} deg: {cause}"
        );
        // After the impact; the simulation is left at its last good step, with finite outputs.
        assert!(
            time > T_STAR && step > 0 && sim.time() <= time,
            "{angle} deg: {time} {step}"
        );
        assert!(sim.outputs().values().iter().all(|v| v.is_finite()));
    }
}

#[test]
fn reinitialisation_smooths_the_pressure_on_a_level_plate() {
    // Ren Fig. 9: without reinitialisation the pressure field grows oscillations near the plate;
    // with it, it stays smooth. Measured as the pressure roughness (RMS of p_i minus its
    // SPH-smoothed value, over rho0 V^2) at t* = 2, 3, 4, for a Newtonian drop (eta = 4 Pa s).
    let rough = |interval| {
        let c = ren(&[
            ("rheology", s("newtonian")),
            ("density_reinit_interval", i(interval)),
        ]);
        let mut sim = Simulation::new(c).unwrap();
        [2.0, 3.0, 4.0]
            .iter()
            .map(|t| {
                sim.advance_to(t * T_STAR).unwrap();
                sim.pressure_roughness()
            })
            .collect::<Vec<_>>()
    };
    let (with, without) = (rough(20), rough(0));
    println!("roughness with reinitialisation {with:?}, without {without:?}");
    for (a, b) in with.iter().zip(&without) {
        assert!(a.is_finite() && *a < 0.25 * b, "{a} vs {b}");
    }
}

#[test]
fn pdri_is_bitwise_identical_on_one_and_two_threads() {
    // Through the impact and several reinitialisations, every output and the saved state.
    let c = ren(&[("plate_inclination", r(30.0))]);
    // Each simulation runs in its own pool of `threads` workers.
    let on = |threads: i64| {
        let mut c = c.clone();
        c.numerics.threads = threads;
        let (ser, err, sim) = series(&c, 2.5 * T_STAR, 0.25 * T_STAR);
        assert!(err.is_none());
        assert_eq!(sim.threads(), threads as usize);
        let values = ser
            .iter()
            .flat_map(|(t, o)| std::iter::once(*t).chain(o.values()));
        (
            values.map(f64::to_bits).collect::<Vec<_>>(),
            sim.state().clone(),
        )
    };
    assert_eq!(on(1), on(2));
}

#[test]
fn wall_force_balances_the_fluid_momentum() {
    // The wall force is what moves the fluid in the corrector (eq. 25b), so its time integral is
    // the momentum change minus the gravity impulse, to round-off, reinitialisations included.
    let c = ren(&[("plate_inclination", r(30.0))]);
    let mut sim = Simulation::new(c.clone()).unwrap();
    let p0 = sim.fluid_momentum();
    let mass = sim.fluid_mass();
    sim.advance_to(4.0 * T_STAR).unwrap();
    // The particles are at the solver's own time, at or just past the communication time.
    let j = sim.fluid_momentum() - p0 - Vec2::new(0.0, -c.fluid.gravity) * mass * sim.state().time;
    let acc = sim.state().wall_impulse;
    assert!(j.norm() > 1e-4, "the plate stopped the drop: {j}");
    assert!((acc + j).norm() < 1e-9 * j.norm(), "{acc} vs {}", -j);
    let o = sim.outputs();
    assert!(
        o.shared.wall_force_normal > 0.0 && o.shared.wall_force_tangential > 0.0,
        "{o:?}"
    );
}

#[test]
fn save_and_restore_continue_identically() {
    // Across reinitialisations: the schedule follows the step count, which the state carries.
    let c = ren(&[("plate_inclination", r(15.0))]);
    let mut a = Simulation::new(c.clone()).unwrap();
    a.advance_to(1.5 * T_STAR).unwrap();
    let saved = a.save_state();
    a.advance_to(2.5 * T_STAR).unwrap();
    let mut b = Simulation::new(c).unwrap();
    b.restore_state(&saved).unwrap();
    b.advance_to(2.5 * T_STAR).unwrap();
    assert_eq!(a.save_state(), b.save_state());
}

#[test]
fn every_rheology_and_equation_of_state_runs_under_pdri() {
    // Through the impact (t* = 2) at a coarse lattice: Fang's Oldroyd-B defaults for the
    // elastic models, each with its own parameter at the table default.
    for (rheology, eos, method) in [
        ("newtonian", "tait", "direct"),
        ("oldroyd_b", "linear", "direct"),
        ("ucm", "linear", "log"),
        ("fene_p", "linear", "log"),
        ("fene_cr", "tait", "direct"),
        ("ptt_linear", "linear", "log"),
        ("ptt_exponential", "linear", "direct"),
        ("giesekus", "tait", "log"),
        ("cross", "tait", "direct"),
    ] {
        let mut c = SceneConfig::default();
        for (k, v) in [
            ("scheme", s("pdri")),
            ("rheology", s(rheology)),
            ("equation_of_state", s(eos)),
            ("conformation_method", s(method)),
            ("particles_per_diameter", i(14)),
        ] {
            c.set(k, v).unwrap();
        }
        let (ser, err, sim) = series(&c, 2.0 * T_STAR, T_STAR);
        assert!(err.is_none(), "{rheology}: {err:?}");
        let o = ser.last().unwrap().1;
        assert!(
            o.shared.drop_width > 1.5 * D && o.shared.wall_force_normal > 0.0,
            "{rheology}: {o:?}"
        );
        assert_eq!(sim.is_elastic(), !matches!(rheology, "newtonian" | "cross"));
        if sim.is_elastic() {
            assert!(o.shared.min_conformation_det > 0.0 && o.shared.max_conformation_trace > 2.0);
        }
    }
}
