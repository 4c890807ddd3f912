//! The channel scene (start-up of plane Poiseuille flow) under the weakly compressible schemes:
//! steady state against the exact Newtonian profile, periodic determinism.
//!
//! H = 2 cm, rho = 1000, eta0 = 4 Pa s, g = 80 m/s^2: U = rho g H^2 / (8 eta0) = 1 m/s, Re = 5,
//! viscous time t_v = rho H^2 / eta0 = 0.1 s. The scene's defaults: no artificial viscosity (no
//! shocks to capture) and Morris' viscous Laplacian (`viscous_operator = auto`).

mod common;

use common::{i, r, s};
use viscosph::config::SceneConfig;
use viscosph::simulation::Simulation;

fn channel(scheme: &str, rheology: &str, across: i64) -> SceneConfig {
    let mut c = SceneConfig::default();
    for (k, v) in [
        ("scene", s("channel")),
        ("scheme", s(scheme)),
        ("rheology", s(rheology)),
        ("particles_per_diameter", i(across)),
        ("channel_width", r(0.02)),
        ("body_force", r(80.0)),
        ("viscosity", r(4.0)),
        ("density", r(1000.0)),
        ("sound_speed", r(12.5)),
    ] {
        c.set(k, v).unwrap();
    }
    c
}

#[test]
fn newtonian_channel_reaches_the_poiseuille_profile_under_both_schemes() {
    for scheme in ["wcsph", "pdri"] {
        let mut sim = Simulation::new(channel(scheme, "newtonian", 20)).unwrap();
        // Three viscous times: the slowest mode has decayed by exp(-3 pi^2).
        sim.advance_to(0.3)
            .unwrap_or_else(|e| panic!("{scheme}: {e}"));
        let o = sim.outputs();
        let u = 1000.0 * 80.0 * 0.02f64.powi(2) / (8.0 * 4.0);
        let err = (o.centreline_velocity - u) / u;
        assert!(
            err.abs() < 0.01,
            "{scheme}: centre line {} vs {u}",
            o.centreline_velocity
        );
        // Flow rate 2 U H / 3; the walls carry the body force on the fluid between the wall
        // rows, rho g H (n - 1) / (2 n).
        let q = 2.0 * u * 0.02 / 3.0;
        assert!(
            ((o.flow_rate - q) / q).abs() < 0.01,
            "{scheme}: flow rate {}",
            o.flow_rate
        );
        let tau = 1000.0 * 80.0 * 0.02 / 2.0 * 19.0 / 20.0;
        assert!(
            ((o.wall_shear_stress - tau) / tau).abs() < 0.02,
            "{scheme}: wall shear stress {} vs {tau}",
            o.wall_shear_stress
        );
        // The drop's outputs do not apply and hold 0, never NaN.
        assert_eq!(
            (o.drop_width, o.spread_front, o.wall_force_normal),
            (0.0, 0.0, 0.0)
        );
        assert!(o.values().iter().all(|v| v.is_finite()));
        // Nothing leaves the channel.
        assert!(sim
            .state()
            .fluid
            .x
            .iter()
            .all(|x| x.y > 0.0 && x.y < 0.02 && x.x >= 0.0 && x.x < 0.02));
        // Fang's nested viscous operator, chosen explicitly, cannot hold the wall layers.
        let mut c = channel(scheme, "newtonian", 20);
        c.set("viscous_operator", s("nested")).unwrap();
        let mut nested = Simulation::new(c).unwrap();
        let broke = nested.advance_to(0.3).is_err();
        let o = nested.outputs();
        assert!(
            broke || (o.centreline_velocity - u).abs() > 0.05 * u,
            "{scheme}: nested held"
        );
    }
}

#[test]
fn periodic_channel_is_bitwise_identical_on_one_and_two_threads() {
    for scheme in ["wcsph", "pdri"] {
        let run = |threads: i64| {
            let mut c = channel(scheme, "oldroyd_b", 12);
            c.threads = threads;
            let mut sim = Simulation::new(c).unwrap();
            sim.advance_to(0.02).unwrap();
            assert_eq!(sim.threads(), threads as usize);
            // The flow has crossed the periodic boundary by now.
            assert!(sim.outputs().centreline_velocity > 0.05);
            sim.state().clone()
        };
        assert_eq!(run(1), run(2), "{scheme}");
    }
}

#[test]
fn fene_cr_channel_settles_on_the_oldroyd_b_flow() {
    // In steady shear FENE-CR's shear stress is Oldroyd-B's (Chilcott & Rallison 1988; King &
    // Lind 2021 section IV.A): the factor f(tr A) multiplies both the stress and the relaxation,
    // so the same velocity profile carries different normal stresses. Wi = lambda U / H = 0.5
    // (Re = 5, beta = 0.1): every Waters & King mode decays by exp(-11) by t = 0.2 s. At the
    // wall shear rate 4 U/H Oldroyd-B's tr A = 2 + 2 (4 Wi)^2 = 10, close to L^2 = 12, so
    // FENE-CR's f(tr A) is far from 1 there.
    use viscosph::analytic::SteadyChannel;
    let steady = |rheology: &str| {
        let mut c = channel("wcsph", rheology, 20);
        c.set("relaxation_time", r(0.01)).unwrap();
        c.set("viscosity_ratio", r(0.1)).unwrap();
        c.set("fene_L2", r(12.0)).unwrap();
        // No artificial stress: Fang's term shifts the steady flow (measured at this Wi: centre
        // line 1.028 U with epsilon = 0.1, 1.007 U without); the wall layers stay stable to
        // t = 0.2 s = 10 H/U here.
        c.set("artificial_stress_epsilon", r(0.0)).unwrap();
        let exact = SteadyChannel::from_config(&c, 0.02, 80.0).unwrap();
        let mut sim = Simulation::new(c).unwrap();
        sim.advance_to(0.2)
            .unwrap_or_else(|e| panic!("{rheology}: {e}"));
        let f = &sim.state().fluid;
        // The largest trace of A in the wall rows.
        let tr = f.conf.iter().map(|a| a.trace()).fold(0.0, f64::max);
        (sim.outputs(), exact, tr)
    };
    let (ob, ob_exact, ob_tr) = steady("oldroyd_b");
    let (fc, fc_exact, fc_tr) = steady("fene_cr");
    // The analytic profiles agree (same velocity), the conformations do not.
    assert!((fc_exact.centreline_velocity() - ob_exact.centreline_velocity()).abs() < 1e-12);
    let rel = (fc.centreline_velocity - ob.centreline_velocity) / ob.centreline_velocity;
    assert!(
        rel.abs() < 0.01,
        "centre line FENE-CR {} vs Oldroyd-B {}",
        fc.centreline_velocity,
        ob.centreline_velocity
    );
    let rel_q = (fc.flow_rate - ob.flow_rate) / ob.flow_rate;
    assert!(
        rel_q.abs() < 0.01,
        "flow rate FENE-CR {} vs Oldroyd-B {}",
        fc.flow_rate,
        ob.flow_rate
    );
    for (name, o) in [("oldroyd_b", &ob), ("fene_cr", &fc)] {
        assert!(
            (o.centreline_velocity - 1.0).abs() < 0.01,
            "{name}: steady centre line {} vs U = 1",
            o.centreline_velocity
        );
    }
    // FENE-CR's finite extensibility shows in the normal stress (tr A < L^2), not in the flow.
    assert!(
        fc_tr < 12.0 && fc_tr < ob_tr - 0.5,
        "tr A: FENE-CR {fc_tr}, Oldroyd-B {ob_tr}"
    );
}

#[test]
fn oldroyd_b_start_up_follows_waters_and_king_under_wcsph() {
    // Re = rho U H / eta0 = 5, Wi = lambda U / H = 1, beta = 0.1: the centre line overshoots to
    // 1.58 U at t = 1.4 H/U, undershoots to 0.87 U and settles at U (Waters & King 1970).
    // Fang's artificial stress is lowered to epsilon = 0.1: its rotated principal-stress term has
    // a shear component that slows the flow (measured: steady centre line 1.13 U at the default
    // 0.5; without it the wall layers become unstable after 11 H/U).
    use viscosph::analytic::waters_king::WatersKing;
    let mut c = channel("wcsph", "oldroyd_b", 20);
    c.set("relaxation_time", r(0.02)).unwrap();
    c.set("viscosity_ratio", r(0.1)).unwrap();
    c.set("artificial_stress_epsilon", r(0.1)).unwrap();
    let wk = WatersKing::from_config(&c, 0.02, 80.0).unwrap();
    let mut sim = Simulation::new(c).unwrap();
    let mut worst = 0.0f64;
    let mut peak = 0.0f64;
    for k in 1..=40 {
        let t = 0.005 * k as f64;
        sim.advance_to(t).unwrap();
        let u = sim.outputs().centreline_velocity;
        worst = worst.max((u - wk.centreline_velocity(t)).abs());
        peak = peak.max(u);
    }
    // Measured: 0.050 U at 20 across (the first overshoot slightly high).
    assert!(
        worst < 0.06,
        "largest deviation from Waters & King {worst} U"
    );
    assert!((peak - 1.584).abs() < 0.06, "first peak {peak} U");
}
