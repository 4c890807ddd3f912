//! Acceptance tests of the incompressible SPH of King & Lind 2021 (`scheme = isph`, issue 11) at
//! resolutions that keep the suite fast. The drop is King & Lind's section IV.C: W = 2 cm, centre
//! W above the plate, U = 1 m/s, eta0 = 5 Pa s, rho = 1000 kg/m3 (Re = 4), t* = t U / W.

mod common;

use common::{
    assert_impulse_matches, assert_outputs_finite, assert_spreads_monotonically, i,
    integrate_wall_force, r, s, series, series_bits,
};
use viscosph::config::Value;
use viscosph::scene::{Outputs, SceneConfig};
use viscosph::simulation::Simulation;
use viscosph::Vec2;

const W: f64 = 0.02;
const T_STAR: f64 = 0.02;

fn cfg(pairs: &[(&str, Value)]) -> SceneConfig {
    let mut c = SceneConfig::default();
    for (k, v) in [
        ("scheme", s("isph")),
        ("viscosity", r(5.0)),
        ("initial_drop_height", r(W)),
        ("particles_per_diameter", i(20)),
    ] {
        c.set(k, v).unwrap();
    }
    for (k, v) in pairs {
        c.set(k, v.clone()).unwrap();
    }
    c.validate().unwrap();
    c
}

/// The Newtonian Re = 4 drop spreads monotonically from impact on; at t* = 8 it is between the
/// published curves' range (King & Lind Fig. 12: W* about 2.2-2.4 at W/dr >= 40).
#[test]
fn newtonian_drop_spreads_monotonically() {
    let c = cfg(&[("rheology", s("newtonian"))]);
    let (ser, err, _) = series(&c, 8.0 * T_STAR, 0.2 * T_STAR);
    assert!(err.is_none(), "{err:?}");
    assert_spreads_monotonically(&ser, W, T_STAR);
    let last = ser.last().unwrap().1;
    let w_end = last.shared.drop_width / W;
    assert!((1.9..2.6).contains(&w_end), "W*(8) = {w_end}");
    assert_outputs_finite(&ser);
}

/// Largest |volume_error| (covered raster area, geometric) of the Newtonian drop over t* <= 8.
fn largest_volume_error(ppd: i64, threads: i64) -> f64 {
    let c = cfg(&[
        ("rheology", s("newtonian")),
        ("particles_per_diameter", i(ppd)),
        ("threads", i(threads)),
    ]);
    let (ser, err, _) = series(&c, 8.0 * T_STAR, 0.2 * T_STAR);
    assert!(err.is_none(), "{err:?}");
    ser.iter()
        .map(|(_, o)| o.shared.volume_error.abs())
        .fold(0.0, f64::max)
}

/// The free-surface pressure (p = 0 on the surface of the layer the surface particles stand
/// for, not on their centres), the surface rows' continuity equation and the density-invariant
/// PPE source (interior, near-surface band and surface rows) hold the drop's covered area at
/// W/dr = 40 within issue 11's 0.5 %: largest |error| over t* <= 8 (outputs every 0.2 t*)
/// measured 0.451 % (0.633 % before the surface rows' continuity and the near-surface sources;
/// 1.7 % with p = 0 on the surface particles, 3.4 % without any source; docs/isph.md,
/// "Volume").
#[test]
fn free_surface_pressure_and_density_source_hold_the_volume() {
    let worst = largest_volume_error(40, 2);
    assert!(worst < 0.005, "largest |volume_error| {worst}");
}

/// At W/dr = 20 the surface row is a large share of the particles, and with p = 0 on the
/// surface particles it crowded tangentially: the drop lost 5.3 % of its covered area by t* = 8.
/// With the surface pressure the largest |error| was 2.7 % (just after impact), with the
/// solvent's surface traction 1.77 %, with the surface rows' continuity and the near-surface
/// sources 0.850 %.
#[test]
fn surface_row_does_not_crowd_at_coarse_resolution() {
    let worst = largest_volume_error(20, 1);
    assert!(worst < 0.01, "largest |volume_error| {worst}");
}

/// Oldroyd-B, De = 1, beta = 0.1 (lambda = 0.02 s): the drop spreads, then retracts (King & Lind
/// Fig. 12: a maximum of W* near t* = 2, a minimum near t* = 3.5).
#[test]
fn oldroyd_b_drop_spreads_and_retracts() {
    let c = cfg(&[
        ("rheology", s("oldroyd_b")),
        ("viscosity_ratio", r(0.1)),
        ("relaxation_time", r(0.02)),
    ]);
    let (ser, err, _) = series(&c, 5.0 * T_STAR, 0.2 * T_STAR);
    assert!(err.is_none(), "{err:?}");
    let (k_max, w_max) = ser
        .iter()
        .enumerate()
        .map(|(k, (_, o))| (k, o.shared.drop_width / W))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    let w_after = ser[k_max..]
        .iter()
        .map(|(_, o)| o.shared.drop_width / W)
        .fold(f64::INFINITY, f64::min);
    assert!(w_max > 1.8, "spread only to W* = {w_max}");
    assert!(
        w_after < w_max - 0.15,
        "no retraction: max {w_max}, later min {w_after}"
    );
    assert!(ser.iter().all(|(_, o)| o.shared.min_conformation_det > 0.0));
}

/// The UCM drop (W/dr = 20, relaxation time `lambda`) to t* = 3, outputs every 0.2 t*: it runs,
/// every output is finite, and min det A >= 1 to round-off at every output (the traceless
/// velocity gradient and the bounded ALE term of free-surface scenes leave only relaxation to
/// change det A, which raises it towards 1).
fn ucm_drop_keeping_det_a_at_least_one(lambda: f64) -> Vec<(f64, Outputs)> {
    let c = cfg(&[("rheology", s("ucm")), ("relaxation_time", r(lambda))]);
    let (ser, err, _) = series(&c, 3.0 * T_STAR, 0.2 * T_STAR);
    assert!(err.is_none(), "{err:?}");
    assert_outputs_finite(&ser);
    for (t, o) in &ser {
        let det = o.shared.min_conformation_det;
        assert!(det > 1.0 - 1e-6, "det A {det} at t* {}", t / T_STAR);
    }
    ser
}

/// UCM (beta = 0, EVSS at the floor's 0.05 eta0), De = 1 (lambda = 0.02 s), W/dr = 20. In free
/// flight the drop translates rigidly and, for UCM in an incompressible flow, det A stays 1
/// (ln det A follows 2 tr(kappa)); the conformation step takes the traceless part of the
/// corrected velocity gradient, so flight keeps det A at 1 to round-off (measured 1.0000 at
/// t* = 0.4; with the full gradient it fell to 0.78 at W/dr = 40). Through impact and the first
/// retraction (t* <= 3) the bounded ALE term keeps det A >= 1 (measured 1.000; 0.653 with the
/// central difference), and the drop spreads to W* 2.30 before retracting.
#[test]
fn ucm_drop_keeps_det_a_at_one_in_flight() {
    let ser = ucm_drop_keeping_det_a_at_least_one(0.02);
    for (t, o) in &ser {
        let det = o.shared.min_conformation_det;
        if *t <= 0.4 * T_STAR {
            assert!(
                (det - 1.0).abs() < 1e-3,
                "det A {det} in flight at t* {}",
                t / T_STAR
            );
        }
    }
    let w: Vec<f64> = ser.iter().map(|(_, o)| o.shared.drop_width / W).collect();
    let w_max = w.iter().cloned().fold(0.0, f64::max);
    assert!(w_max > 2.0, "spread only to W* = {w_max}");
    assert!(*w.last().unwrap() < w_max - 0.3, "no retraction: {w:?}");
}

/// UCM (beta = 0, EVSS at the floor's 0.05 eta0), De = 10 (lambda = 0.2 s), W/dr = 20, t* <= 3:
/// past the breakdown of the central-difference ALE term (W/dr = 20: t* = 2.8; W/dr = 40:
/// t* = 1.03, tr A above 1e3 in the wall row at the contact line, det A down to 0.3). With the
/// bounded (convex, one-sided) ALE term of free-surface scenes and the traceless velocity
/// gradient, nothing lowers det A below 1 (UCM relaxation only raises it towards 1): measured
/// min det A 1.000 and at most 1.17 to t* = 3; the drop spreads to W* = 4.70 at t* = 2.8 at
/// both W/dr = 20 and 40 (an elastic drop with nothing but the slow relaxation to dissipate its
/// impact; Oldroyd-B at beta = 0.05 reaches 3.3, its solvent dissipating the rest).
#[test]
fn ucm_drop_at_de_10_stays_bounded_through_impact() {
    let ser = ucm_drop_keeping_det_a_at_least_one(0.2);
    let w_max = ser
        .iter()
        .map(|(_, o)| o.shared.drop_width / W)
        .fold(0.0, f64::max);
    assert!((4.4..5.0).contains(&w_max), "W* max {w_max}");
}

/// The wall force is what the mirrors exert, and the momentum balance is exact: impulse of the
/// wall + gravity + the ALE remapping term = change of the fluid's momentum, to round-off; the
/// force output integrated over time agrees with it to the sampling error.
#[test]
fn momentum_balance_on_an_inclined_plate() {
    let c = cfg(&[
        ("rheology", s("newtonian")),
        ("plate_inclination", r(30.0)),
        ("particles_per_diameter", i(16)),
    ]);
    let dt = 0.025 * T_STAR;
    let mut sim = Simulation::new(c.clone()).unwrap();
    let p0 = sim.fluid_momentum();
    let mass = sim.fluid_mass();
    let plate = sim.state().plate().cloned().unwrap();
    let n = (4.0 * T_STAR / dt).round() as usize;
    let (int_n, int_t) = integrate_wall_force(&mut sim, dt, n);
    let st = sim.state();
    let t = st.time;
    let j =
        sim.fluid_momentum() - p0 - Vec2::new(0.0, -c.fluid.gravity) * mass * t - st.remap_impulse;
    let acc = st.wall_impulse;
    assert!(j.norm() > 1e-4, "{j}");
    assert!((acc + j).norm() < 1e-9 * j.norm(), "{acc} vs {}", -j);
    // The remapping is a small part of the balance.
    assert!(
        st.remap_impulse.norm() < 0.05 * j.norm(),
        "{}",
        st.remap_impulse
    );
    assert_impulse_matches((int_n, int_t), j, &plate, 0.05);
}

/// A viscous drop set down gently comes to rest; the plate then carries its weight. The implicit
/// viscous step at the default factor takes steps of 2 ms here (the viscous limit would be 8 us),
/// over which the incompressible wall force of one step is noisy: the force is averaged over the
/// last 50 ms, at a third of the default step.
#[test]
fn drop_at_rest_weighs_on_the_plate() {
    let c = cfg(&[
        ("rheology", s("newtonian")),
        ("viscosity", r(40.0)),
        ("impact_velocity", r(0.0)),
        ("initial_drop_height", r(0.5 * W + 2.0 * W / 20.0)),
        ("time_step_factor", r(0.1)),
    ]);
    let mut sim = Simulation::new(c.clone()).unwrap();
    sim.advance_to(0.25).unwrap();
    let weight = sim.fluid_mass() * c.fluid.gravity;
    let (mut fn_sum, mut ft_sum, mut ke_max) = (0.0, 0.0, 0.0f64);
    let k_max = 50;
    for k in 1..=k_max {
        sim.advance_to(0.25 + 0.001 * k as f64).unwrap();
        let o = sim.outputs();
        fn_sum += o.shared.wall_force_normal;
        ft_sum += o.shared.wall_force_tangential;
        ke_max = ke_max.max(o.shared.kinetic_energy);
    }
    assert!(ke_max < 2e-3 * weight * W, "not at rest: KE = {ke_max}");
    let (f_n, f_t) = (fn_sum / k_max as f64, ft_sum / k_max as f64);
    let err = (f_n - weight) / weight;
    assert!(
        err.abs() < 0.02,
        "normal force {f_n} vs weight {weight} ({err:+.4})"
    );
    assert!(f_t.abs() < 1e-3 * weight, "{f_t}");
}

#[test]
fn outputs_are_bitwise_identical_on_one_and_two_threads() {
    let c = cfg(&[
        ("plate_inclination", r(20.0)),
        ("particles_per_diameter", i(16)),
    ]);
    let run = |threads: i64| {
        let mut c = c.clone();
        c.numerics.threads = threads;
        let (ser, err, sim) = series(&c, 1.5 * T_STAR, 0.25 * T_STAR);
        assert!(err.is_none(), "{err:?}");
        (series_bits(&ser), sim.state().clone())
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn save_and_restore_continue_identically() {
    let c = cfg(&[
        ("plate_inclination", r(10.0)),
        ("particles_per_diameter", i(16)),
    ]);
    let mut a = Simulation::new(c.clone()).unwrap();
    a.advance_to(0.015).unwrap();
    let saved = a.save_state();
    a.advance_to(0.025).unwrap();
    let mut b = Simulation::new(c).unwrap();
    b.restore_state(&saved).unwrap();
    b.advance_to(0.025).unwrap();
    assert_eq!(a.outputs(), b.outputs());
    assert_eq!(a.save_state(), b.save_state());
}

/// The Eulerian frame needs a domain without a free surface: refused on a drop, with the reason.
#[test]
fn eulerian_frame_is_refused_on_a_drop() {
    let mut c = SceneConfig::default();
    c.set("scheme", s("isph")).unwrap();
    c.set("isph_frame", s("eulerian")).unwrap();
    let e = Simulation::new(c).err().expect("refused").to_string();
    assert!(
        e.contains("isph_frame") && e.contains("free surface"),
        "{e}"
    );
}

/// The implicit solvent viscosity converges to the paper's explicit step as the time step
/// shrinks: at each time_step_factor both runs are made, and the largest difference of their
/// kinetic energies over the impact shrinks with the factor (the explicit run is limited by
/// rho h^2 / eta0 and takes far more steps at the default).
#[test]
fn implicit_viscosity_converges_to_explicit() {
    let run = |step: &str, f: f64| {
        let c = cfg(&[
            ("rheology", s("newtonian")),
            ("particles_per_diameter", i(12)),
            ("isph_viscous_step", s(step)),
            ("time_step_factor", r(f)),
        ]);
        let (ser, err, sim) = series(&c, 2.0 * T_STAR, 0.1 * T_STAR);
        assert!(err.is_none(), "{err:?}");
        let ke: Vec<f64> = ser.iter().map(|(_, o)| o.shared.kinetic_energy).collect();
        (ke, sim.state().step)
    };
    let mut rows = Vec::new();
    for f in [0.3, 0.1, 0.03] {
        let (a, na) = run("implicit", f);
        let (b, nb) = run("explicit", f);
        let ke0 = b[0];
        let d = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs() / ke0)
            .fold(0.0, f64::max);
        rows.push((f, d, na, nb));
    }
    eprintln!("(factor, max |dKE| / KE0, implicit steps, explicit steps): {rows:?}");
    assert!(rows[0].2 * 3 < rows[0].3, "{rows:?}");
    assert!(rows[1].1 < rows[0].1 && rows[2].1 < rows[1].1, "{rows:?}");
}

/// Every rheology runs under ISPH through the project's rheology code: the K&L drop (De = 1,
/// beta = 0.1 for the polymer models) spreads past its diameter by t* = 2.5 with finite outputs
/// and, for the models with a conformation tensor, a positive-definite one. UCM (no solvent)
/// takes EVSS, as King & Lind need it for beta = 0 (section IV.A.2).
#[test]
fn every_rheology_spreads_the_drop() {
    for (name, _) in viscosph::config::RHEOLOGIES {
        let evss = if *name == "ucm" { 0.1 } else { 0.0 };
        let c = cfg(&[
            ("evss_alpha", r(evss)),
            ("rheology", s(name)),
            ("relaxation_time", r(0.02)),
            ("viscosity_ratio", r(0.1)),
            ("cross_viscosity_inf", r(0.5)),
            ("particles_per_diameter", i(12)),
        ]);
        let (ser, err, _) = series(&c, 2.5 * T_STAR, 0.25 * T_STAR);
        assert!(err.is_none(), "{name}: {err:?}");
        let last = ser.last().unwrap().1;
        assert!(
            last.shared.drop_width / W > 1.3,
            "{name}: W* = {}",
            last.shared.drop_width / W
        );
        assert!(
            ser.iter()
                .all(|(_, o)| o.values().iter().all(|v| v.is_finite())
                    && o.shared.min_conformation_det > 0.0),
            "{name}"
        );
    }
}

/// At low De the polymer relaxes faster than the flow deforms it, so Oldroyd-B (beta = 0.1) and
/// UCM (beta = 0) at De = 0.1 (lambda = 2 ms) must both run through the impact and behave like
/// a viscous liquid of viscosity eta0. UCM broke at impact before ISPH raised alpha_V so that
/// the compact Laplacian carries 0.05 eta0 (`MIN_COMPACT_VISCOSITY_RATIO`) and limited the step
/// by EVSS's explicit part. Tolerances, measured at W/dr = 20 over t* <= 4: UCM against
/// Oldroyd-B 0.4 % (2 % allowed: the two differ by beta = 0.1 of the viscosity, in the
/// Laplacian either way); each against the Newtonian drop of the same eta0 at a comparable step
/// (time_step_factor 0.1) 6.4 % and 6.8 % (7.5 % allowed), the largest at impact (t* = 0.8);
/// at t* = 4 they are within 1.5 %. Before the solvent's surface traction entered the implicit
/// viscous step the gap was 8.4 % and 9.4 % and the Newtonian drop the wider at the end: the
/// polymer's viscous stress goes through the positive-form divergence of the corrected
/// gradients, which carries the free surface's traction, the Newtonian one through Morris'
/// Laplacian, which did not (docs/isph.md, "The solvent's free-surface traction").
#[test]
fn low_deborah_drops_spread_like_the_viscous_drop() {
    let t_end = 4.0 * T_STAR;
    let width = |pairs: &[(&str, Value)]| {
        let (ser, err, _) = series(&cfg(pairs), t_end, 0.4 * T_STAR);
        assert!(err.is_none(), "{pairs:?}: {err:?}");
        assert_outputs_finite(&ser);
        assert!(
            ser.iter().all(|(_, o)| o.shared.min_conformation_det > 0.0),
            "{pairs:?}"
        );
        ser.iter()
            .map(|(_, o)| o.shared.drop_width / W)
            .collect::<Vec<_>>()
    };
    let newt = width(&[("rheology", s("newtonian")), ("time_step_factor", r(0.1))]);
    let ob = width(&[
        ("rheology", s("oldroyd_b")),
        ("viscosity_ratio", r(0.1)),
        ("relaxation_time", r(0.002)),
    ]);
    let ucm = width(&[("rheology", s("ucm")), ("relaxation_time", r(0.002))]);
    let rel = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs() / y)
            .fold(0.0, f64::max)
    };
    eprintln!(
        "W*: newtonian {newt:?}\noldroyd_b {ob:?}\nucm {ucm:?}\nmax rel: ucm-ob {}, ob-newt {}, ucm-newt {}",
        rel(&ucm, &ob),
        rel(&ob, &newt),
        rel(&ucm, &newt)
    );
    // Both spread past 1.5 W (no splash: a splashing drop is wider than 3 W by t* = 4).
    for w in [&ob, &ucm] {
        let last = *w.last().unwrap();
        assert!((1.5..2.0).contains(&last), "W*(4) = {last}");
    }
    assert!(rel(&ucm, &ob) < 0.02, "UCM vs Oldroyd-B {}", rel(&ucm, &ob));
    assert!(
        rel(&ob, &newt) < 0.075,
        "Oldroyd-B vs Newtonian {}",
        rel(&ob, &newt)
    );
    assert!(
        rel(&ucm, &newt) < 0.075,
        "UCM vs Newtonian {}",
        rel(&ucm, &newt)
    );
}

/// ISPH's EVSS scale: unchanged where the solvent carries 0.05 eta0 or more (so the default
/// Oldroyd-B drop, beta = 0.1, and King & Lind's lowest beta, 0.05, are bitwise what they were),
/// raised to make up 0.05 eta0 below.
#[test]
fn evss_is_raised_only_below_a_twentieth_of_the_viscosity() {
    use viscosph::rheology::{OldroydB, Rheology};
    use viscosph::scheme::isph::isph_evss_alpha;
    for beta in [0.05, 0.1, 0.5] {
        assert_eq!(isph_evss_alpha(&OldroydB::new(5.0, beta, 0.02), 0.0), 0.0);
    }
    let ucm = OldroydB::new(5.0, 0.0, 0.02);
    let a = isph_evss_alpha(&ucm, 0.0);
    assert!((a * ucm.polymer_viscosity() - 0.25).abs() < 1e-12, "{a}");
    assert_eq!(isph_evss_alpha(&ucm, 0.3), 0.3);
    let b = OldroydB::new(5.0, 0.02, 0.02);
    let a = isph_evss_alpha(&b, 0.0);
    assert!((a * b.polymer_viscosity() - 0.15).abs() < 1e-12, "{a}");
}

/// Decay rate of the extensional mode u = U sin(kx) of a free Newtonian sheet, periodic in x
/// (100 dx long, 10 rows thick: kH = pi/10), no gravity, at step `dt`: the slope of the log of
/// the mode's amplitude `2/N sum u_i sin(k x_i)` between `t0` and `t1`, in units of nu k^2.
fn sheet_decay_rate(dt: f64, t0: f64, t1: f64) -> f64 {
    use viscosph::neighbors::Domain;
    use viscosph::particles::Fluid;
    use viscosph::rheology::Newtonian;
    use viscosph::scheme::isph::Isph;
    use viscosph::scheme::params::Params;
    use viscosph::scheme::Scheme;
    use viscosph::State;
    let (dx, nx, ny) = (1e-3, 100usize, 10usize);
    let (rho, eta, u0) = (1000.0, 5.0, 1e-3);
    let l = nx as f64 * dx;
    let k = 2.0 * std::f64::consts::PI / l;
    let mut fl = Fluid {
        mass: rho * dx * dx,
        ..Default::default()
    };
    for j in 0..ny {
        for i in 0..nx {
            let x = Vec2::new(
                (i as f64 + 0.5) * dx,
                (j as f64 + 0.5 - 0.5 * ny as f64) * dx,
            );
            fl.x.push(x);
            // Divergence-free: v = -U k y cos(kx).
            fl.v.push(Vec2::new(
                u0 * (k * x.x).sin(),
                -u0 * k * x.y * (k * x.x).cos(),
            ));
            fl.rho.push(rho);
        }
    }
    let c = cfg(&[("rheology", s("newtonian")), ("viscosity", r(eta))]);
    let mut p = Params::new(&c.fluid, &c.numerics, c.dx(), c.resolved_sound_speed());
    p.gravity = Vec2::zeros();
    p.domain = Domain::periodic_x(l);
    p.dx = dx;
    p.eos.rho0 = rho;
    let mut scheme = Isph::new(Newtonian::new(eta), p, &c.numerics, &[]);
    let mut st = State::new(fl, Vec::new(), None);
    let amplitude = |st: &State| {
        let n = st.fluid.len() as f64;
        st.fluid
            .x
            .iter()
            .zip(&st.fluid.v)
            .map(|(x, v)| v.x * (k * x.x).sin())
            .sum::<f64>()
            * 2.0
            / n
    };
    let mut a0 = None;
    while st.time < t1 - 1e-12 {
        if a0.is_none() && st.time >= t0 - 1e-12 {
            a0 = Some((st.time, amplitude(&st)));
        }
        let max_dt = dt.min(t1 - st.time);
        let h = scheme.step(&mut st, max_dt).unwrap();
        st.time += h;
        st.step += 1;
    }
    let (ta, aa) = a0.unwrap();
    let a1 = amplitude(&st);
    assert!(a1 > 0.0 && aa > 0.0, "{aa} -> {a1}");
    let nu = eta / rho;
    -(a1 / aa).ln() / (st.time - ta) / (nu * k * k)
}

/// A diverging ISPH run stops with a breakdown that names the blow-up, instead of crawling
/// on at a vanishing step: (28) follows a diverging speed down without ever reaching zero, and
/// an incompressible state has no density to watch. The same sheet as below, one particle given
/// a speed no flow of this scene can have (1e9 m/s: a stable step (28) near 1e-13 s against the
/// viscous time rho h^2 / eta of 3.4e-4 s); the unharmed sheet steps on.
#[test]
fn a_blown_up_flow_stops_with_a_breakdown() {
    use viscosph::neighbors::Domain;
    use viscosph::particles::Fluid;
    use viscosph::rheology::Newtonian;
    use viscosph::scheme::isph::Isph;
    use viscosph::scheme::params::Params;
    use viscosph::scheme::Scheme;
    use viscosph::State;
    let (dx, nx, ny, rho, eta) = (1e-3, 40usize, 10usize, 1000.0, 5.0);
    let mut fl = Fluid {
        mass: rho * dx * dx,
        ..Default::default()
    };
    for j in 0..ny {
        for i in 0..nx {
            fl.x.push(Vec2::new((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx));
            fl.v.push(Vec2::zeros());
            fl.rho.push(rho);
        }
    }
    let c = cfg(&[("rheology", s("newtonian")), ("viscosity", r(eta))]);
    let mut p = Params::new(&c.fluid, &c.numerics, c.dx(), c.resolved_sound_speed());
    p.gravity = Vec2::zeros();
    p.domain = Domain::periodic_x(nx as f64 * dx);
    p.dx = dx;
    p.eos.rho0 = rho;
    let mut healthy = State::new(fl.clone(), Vec::new(), None);
    let mut scheme = Isph::new(Newtonian::new(eta), p, &c.numerics, &[]);
    let h = scheme
        .step(&mut healthy, 1e-4)
        .expect("a sheet at rest steps");
    assert!(h > 0.0);
    fl.v[205] = Vec2::new(1e9, 0.0);
    let mut blown = State::new(fl, Vec::new(), None);
    let e = scheme
        .step(&mut blown, 1e-4)
        .expect_err("a blown-up flow must stop");
    assert!(e.contains("blown up") && e.contains("1.000e9"), "{e}");
}

/// The blow-up guard measures the step against the scene's speed scale, not the fluid's
/// viscous time: the near-inviscid elliptical drop (eta = 1e-3 Pa s, R = 1 m, no gravity),
/// whose viscous time over one smoothing length at 10 per diameter is 6.8e4 s, stopped at its
/// first step (5e-4 s) as "blown up". It now runs to t = 0.004 s (9 steps) and its semi-major
/// axis is within 5 % of the exact solution (Monaghan 1994; measured -3.1 %).
#[test]
fn a_near_inviscid_drop_is_not_a_blow_up() {
    use viscosph::scene::elliptical_drop::semi_axes;
    let mut c = SceneConfig::default();
    for (k, v) in [
        ("scene", s("elliptical_drop")),
        ("scheme", s("isph")),
        ("particles_per_diameter", i(10)),
    ] {
        c.set(k, v).unwrap();
    }
    c.validate().unwrap();
    let mut sim = Simulation::new(c).unwrap();
    sim.advance_to(0.004).expect("the elliptical drop runs");
    let ax = semi_axes(&sim.state().fluid, sim.state().time);
    assert!(sim.state().step > 3, "steps {}", sim.state().step);
    assert!(ax.major_error.abs() < 0.05, "{ax:?}");
}

/// The solvent's free-surface traction (King & Lind 2021 eq. (35a)'s viscous part, made
/// implicit in the viscous solve): a free Newtonian sheet resists extension with the planar
/// Trouton viscosity 4 eta. The long-wave extensional mode u = U sin(kx) of a sheet of
/// thickness 2H without surface tension decays at s = -nu (k^2 + mu^2), mu the smallest
/// positive root of (k^2 - mu^2)^2 cosh(kH) sin(mu H) = 4 k^3 mu sinh(kH) cos(mu H) (linear
/// Stokes modes of a free viscous sheet with traction-free faces): 3.87 nu k^2 at kH = pi/10,
/// 4 nu k^2 as kH -> 0. Measured at dt = 0.2 ms: 2.68 nu k^2 with the traction term, 1.74 with
/// Morris' Laplacian alone (main before this term, where the free surface only imposes p = 0:
/// an extensional viscosity of about 1.8 eta). What is still missing at this step is the
/// splitting of the viscous step from the projection: 3.02 at dt = 0.05 ms, 1.97 at 1 ms.
#[test]
fn free_sheet_resists_extension_with_the_surface_traction() {
    let rate = sheet_decay_rate(2e-4, 0.005, 0.025);
    eprintln!("sheet rate {rate}");
    assert!(
        (2.5..3.9).contains(&rate),
        "extensional mode decays at {rate} nu k^2 (exact 3.87)"
    );
}

/// A Newtonian drop (eta = 5 Pa s) set down on the plate from rest at W/dr = 40, the default
/// step: once it is down (t = 0.04-0.12 s) the plate carries its weight smoothly and the step
/// stays steady. Without the positive-form pressure wave limit (`Isph::pressure_wave_dt`) the
/// step sat at the gravity limit, where the projection's `(p_i + p_j)` spring under the
/// hydrostatic pressure has a Courant number of about 0.9 here (1.5 at W/dr = 120, where the
/// Re = 4 drop blew up): the plate force jumped between 0.51 and 2.19 times the weight and the
/// step between 4.4e-4 and 1.6e-3 s (ratio 3.7); with it, 1.01-1.19 and ratio 1.24
/// (docs/isph.md, "The positive-form pressure wave").
#[test]
fn drop_settling_on_the_plate_keeps_a_smooth_wall_force_and_step() {
    let c = cfg(&[
        ("rheology", s("newtonian")),
        ("impact_velocity", r(0.0)),
        ("initial_drop_height", r(0.5 * W + 0.0005)),
        ("particles_per_diameter", i(40)),
    ]);
    let mut sim = Simulation::new(c.clone()).unwrap();
    sim.advance_to(0.04).unwrap();
    let weight = sim.fluid_mass() * c.fluid.gravity;
    let (mut f_lo, mut f_hi) = (f64::INFINITY, 0.0f64);
    let (mut dt_lo, mut dt_hi) = (f64::INFINITY, 0.0f64);
    for k in 1..=40 {
        sim.advance_to(0.04 + 0.002 * k as f64).unwrap();
        let o = sim.outputs();
        let f = o.shared.wall_force_normal / weight;
        f_lo = f_lo.min(f);
        f_hi = f_hi.max(f);
        dt_lo = dt_lo.min(o.shared.time_step);
        dt_hi = dt_hi.max(o.shared.time_step);
    }
    assert!(
        f_lo > 0.85 && f_hi < 1.35,
        "plate force / weight between {f_lo:.3} and {f_hi:.3}"
    );
    assert!(
        dt_hi / dt_lo < 2.0,
        "step between {dt_lo:.3e} and {dt_hi:.3e} s"
    );
}
