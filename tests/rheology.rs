//! Homogeneous-flow tests of the rheology module alone: a fixed velocity gradient
//! kappa_ab = d v_a / d x_b, no particles. Every integration goes through `rheology::advance`
//! exactly as a predictor-corrector scheme calls it (Fang 2006 eqs. 49-50, `scheme/wcsph.rs`):
//! a half step with a_eval = A^n, then a full step from A^n with a_eval = A^{n+1/2}.
//!
//! References are independent of the module: exact Oldroyd-B solutions, the published closed form
//! of Giesekus steady shear, and the steady-state algebra of PTT and FENE solved by bisection here.

use viscosph::config::{ConformationMethod, RheologyKind, Value, RHEOLOGIES};
use viscosph::dispatch_rheology;
use viscosph::rheology::{
    self, logconf, shear_rate, AnyRheology, Cross, Evss, FeneCr, FeneP, Giesekus, Newtonian,
    OldroydB, PttExponential, PttLinear, Rheology,
};
use viscosph::scene::SceneConfig;
use viscosph::Mat2;

const DIRECT: ConformationMethod = ConformationMethod::Direct;
const LOG: ConformationMethod = ConformationMethod::Log;
const METHODS: [ConformationMethod; 2] = [DIRECT, LOG];

// Material of most tests: eta0 = 2 Pa s, beta = 0.1, lambda = 0.5 s, so G = eta_p/lambda = 3.6 Pa.
const ETA0: f64 = 2.0;
const BETA: f64 = 0.1;
const LAMBDA: f64 = 0.5;

fn eta_p() -> f64 {
    (1.0 - BETA) * ETA0
}
fn modulus() -> f64 {
    eta_p() / LAMBDA
}

/// Simple shear v_x = rate y.
fn shear(rate: f64) -> Mat2 {
    Mat2::new(0.0, rate, 0.0, 0.0)
}
/// Planar extension v = rate (x, -y).
fn extension(rate: f64) -> Mat2 {
    Mat2::new(rate, 0.0, 0.0, -rate)
}
/// Rigid rotation with vorticity 2 w: kappa = [[0, w], [-w, 0]].
fn rotation(w: f64) -> Mat2 {
    Mat2::new(0.0, w, -w, 0.0)
}

/// One predictor-corrector step, as a scheme takes it.
fn pc_step<R: Rheology>(
    method: ConformationMethod,
    model: &R,
    a: &Mat2,
    kappa: &Mat2,
    dt: f64,
) -> Mat2 {
    let half = rheology::advance(method, model, a, a, kappa, 0.5 * dt);
    rheology::advance(method, model, a, &half, kappa, dt)
}

/// `n` steps of `dt` from `a0` in the fixed flow `kappa`; `observe(t, A)` after each step.
fn integrate<R: Rheology>(
    method: ConformationMethod,
    model: &R,
    a0: Mat2,
    kappa: &Mat2,
    dt: f64,
    n: usize,
    mut observe: impl FnMut(f64, &Mat2),
) -> Mat2 {
    let mut a = a0;
    for i in 1..=n {
        a = pc_step(method, model, &a, kappa, dt);
        observe(i as f64 * dt, &a);
    }
    a
}

/// Root of an increasing function on [lo, hi] by bisection.
fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    assert!(f(lo) <= 0.0 && f(hi) >= 0.0, "root not bracketed");
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Oldroyd-B start-up of simple shear at Wi = lambda gamma_dot: max over time of
/// |tau_xy - exact| / max |exact|, the same for N1, and max |tau_yy| / max |tau_xy| (exact 0).
fn oldroyd_b_startup_errors(method: ConformationMethod, wi: f64, dt: f64) -> (f64, f64, f64) {
    let model = OldroydB::new(ETA0, BETA, LAMBDA);
    let g = wi / LAMBDA;
    let (mut e_tau, mut e_n1, mut e_yy) = (0.0f64, 0.0f64, 0.0f64);
    let (mut max_tau, mut max_n1) = (0.0f64, 0.0f64);
    let n = (8.0 * LAMBDA / dt).round() as usize;
    integrate(
        method,
        &model,
        Mat2::identity(),
        &shear(g),
        dt,
        n,
        |t, a| {
            let s = t / LAMBDA;
            let tau = model.polymer_stress(a);
            // Exact: tau_xy = eta_p g (1 - e^-s), N1 = 2 eta_p lambda g^2 (1 - e^-s - s e^-s).
            let tau_xy = eta_p() * g * (1.0 - (-s).exp());
            let n1 = 2.0 * eta_p() * LAMBDA * g * g * (1.0 - (-s).exp() - s * (-s).exp());
            e_tau = e_tau.max((tau[(0, 1)] - tau_xy).abs());
            e_n1 = e_n1.max((tau[(0, 0)] - tau[(1, 1)] - n1).abs());
            max_tau = max_tau.max(tau_xy.abs());
            max_n1 = max_n1.max(n1.abs());
            // Exact A_yy = 1: tau_yy = 0.
            e_yy = e_yy.max(tau[(1, 1)].abs());
            assert_eq!(tau[(0, 1)], tau[(1, 0)]);
        },
    );
    (e_tau / max_tau, e_n1 / max_n1, e_yy / max_tau)
}

#[test]
fn oldroyd_b_shear_startup_matches_exact_solution() {
    // dt = lambda/100: the WCSPH drop takes dt/lambda ~ 0.005, so this is a practical step.
    let dt = LAMBDA / 100.0;
    for method in METHODS {
        for wi in [1.0, 5.0] {
            let (e_tau, e_n1, e_yy) = oldroyd_b_startup_errors(method, wi, dt);
            println!(
                "Oldroyd-B start-up {method:?} Wi = {wi}: tau_xy error {e_tau:.2e}, N1 error {e_n1:.2e}, \
                 tau_yy error {e_yy:.2e}"
            );
            assert!(
                e_tau < 1e-3 && e_n1 < 1e-3 && e_yy < 1e-3,
                "{method:?} Wi = {wi}: {e_tau:e} {e_n1:e} {e_yy:e}"
            );
        }
    }
}

#[test]
fn both_integrators_are_second_order() {
    for method in METHODS {
        let coarse = oldroyd_b_startup_errors(method, 5.0, LAMBDA / 25.0);
        let fine = oldroyd_b_startup_errors(method, 5.0, LAMBDA / 50.0);
        let (r_tau, r_n1) = (coarse.0 / fine.0, coarse.1 / fine.1);
        println!("{method:?}: error ratio on halving dt: tau_xy {r_tau:.2}, N1 {r_n1:.2}");
        assert!(r_tau > 3.5 && r_n1 > 3.5, "{method:?}: {r_tau} {r_n1}");
    }
}

#[test]
fn oldroyd_b_planar_extension_bounded_below_half_unbounded_above() {
    let model = OldroydB::new(ETA0, BETA, LAMBDA);
    let dt = LAMBDA / 100.0;
    for method in METHODS {
        for wi in [0.1, 0.3, 0.45, 0.55, 1.0] {
            let rate = wi / LAMBDA;
            // Exact: A_xx = c + (1 - c) e^{-(1 - 2 Wi) s}, c = 1/(1 - 2 Wi); A_yy likewise with
            // 1 + 2 Wi.
            let (cx, cy) = (1.0 / (1.0 - 2.0 * wi), 1.0 / (1.0 + 2.0 * wi));
            let exact = |s: f64| {
                (
                    cx + (1.0 - cx) * (-(1.0 - 2.0 * wi) * s).exp(),
                    cy + (1.0 - cy) * (-(1.0 + 2.0 * wi) * s).exp(),
                )
            };
            let t_end = if wi < 0.5 { 150.0 } else { 20.0 } * LAMBDA;
            let n = (t_end / dt).round() as usize;
            let mut err = 0.0f64;
            let a = integrate(
                method,
                &model,
                Mat2::identity(),
                &extension(rate),
                dt,
                n,
                |t, a| {
                    let (xx, yy) = exact(t / LAMBDA);
                    err = err.max(rel(a[(0, 0)], xx)).max(rel(a[(1, 1)], yy));
                    assert_eq!(a[(0, 1)], 0.0);
                },
            );
            println!(
                "Oldroyd-B extension {method:?} Wi = {wi}: A_xx(end) = {:.6e}, max rel error {err:.2e}",
                a[(0, 0)]
            );
            assert!(err < 1e-3, "{method:?} Wi = {wi}: {err:e}");
            if wi < 0.5 {
                // The bounded steady state 1/(1 - 2 Wi).
                assert!(
                    rel(a[(0, 0)], cx) < 1e-4,
                    "{method:?} Wi = {wi}: {}",
                    a[(0, 0)]
                );
                assert!(
                    rel(a[(1, 1)], cy) < 1e-4,
                    "{method:?} Wi = {wi}: {}",
                    a[(1, 1)]
                );
            } else {
                // Unbounded: exponential growth at rate (2 Wi - 1)/lambda, past any steady value.
                let grown = ((2.0 * wi - 1.0) * t_end / LAMBDA).exp();
                assert!(
                    a[(0, 0)] > 0.5 * grown,
                    "{method:?} Wi = {wi}: {}",
                    a[(0, 0)]
                );
            }
        }
    }
}

/// Steady planar extension of FENE-P: A_xx = 1/(f - 2 Wi), A_yy = 1/(f + 2 Wi),
/// f = 1/(1 - (A_xx + A_yy)/L^2).
fn fene_p_extension_steady(wi: f64, l2: f64) -> (f64, f64) {
    let trace = |f: f64| 1.0 / (f - 2.0 * wi) + 1.0 / (f + 2.0 * wi);
    let f = bisect(|f| l2 * (1.0 - 1.0 / f) - trace(f), 2.0 * wi + 1e-12, 1e9);
    (1.0 / (f - 2.0 * wi), 1.0 / (f + 2.0 * wi))
}

/// Steady planar extension of FENE-CR: A_xx = f/(f - 2 Wi), A_yy = f/(f + 2 Wi).
fn fene_cr_extension_steady(wi: f64, l2: f64) -> (f64, f64) {
    let trace = |f: f64| f / (f - 2.0 * wi) + f / (f + 2.0 * wi);
    let lo = (2.0 * wi).max(1.0) + 1e-12;
    let f = bisect(|f| l2 * (1.0 - 1.0 / f) - trace(f), lo, 1e9);
    (f / (f - 2.0 * wi), f / (f + 2.0 * wi))
}

#[test]
fn fene_models_stay_below_full_extension() {
    let l2 = 100.0;
    for method in METHODS {
        for wi in [1.0f64, 5.0, 50.0] {
            // Near full extension (spring factor f ~ 2 Wi) the trace relaxes at the rate
            // f^2 tr(A)/(L^2 lambda) ~ (2 Wi)^2/lambda: the step resolves that by a factor of 10.
            let dt = LAMBDA / (10.0 * (1.0 + 2.0 * wi).powi(2));
            let kappa = extension(wi / LAMBDA);
            let n = (10.0 * LAMBDA / dt) as usize;
            let fp = FeneP::new(ETA0, BETA, LAMBDA, l2);
            let mut max_tr = 0.0f64;
            let a = integrate(
                method,
                &fp,
                fp.rest_conformation(),
                &kappa,
                dt,
                n,
                |_, a| {
                    max_tr = max_tr.max(a.trace());
                },
            );
            let (xx, yy) = fene_p_extension_steady(wi, l2);
            println!(
                "FENE-P extension {method:?} Wi = {wi}: max tr A = {max_tr:.4} (L2 = {l2}), \
                 steady A_xx error {:.2e}, A_yy error {:.2e}",
                rel(a[(0, 0)], xx),
                rel(a[(1, 1)], yy)
            );
            assert!(max_tr < l2, "{method:?} Wi = {wi}: {max_tr}");
            assert!(rel(a[(0, 0)], xx) < 1e-3 && rel(a[(1, 1)], yy) < 1e-3);

            let fc = FeneCr::new(ETA0, BETA, LAMBDA, l2);
            let mut max_tr = 0.0f64;
            let a = integrate(method, &fc, Mat2::identity(), &kappa, dt, n, |_, a| {
                max_tr = max_tr.max(a.trace());
            });
            let (xx, yy) = fene_cr_extension_steady(wi, l2);
            println!(
                "FENE-CR extension {method:?} Wi = {wi}: max tr A = {max_tr:.4} (L2 = {l2}), \
                 steady A_xx error {:.2e}, A_yy error {:.2e}",
                rel(a[(0, 0)], xx),
                rel(a[(1, 1)], yy)
            );
            assert!(max_tr < l2, "{method:?} Wi = {wi}: {max_tr}");
            assert!(rel(a[(0, 0)], xx) < 1e-3 && rel(a[(1, 1)], yy) < 1e-3);
        }
    }
}

#[test]
fn log_conformation_keeps_fene_below_full_extension_at_any_step() {
    // Wi = 50 planar extension with steps of 0.5 and 2.5 Hencky strain: the direct update
    // overshoots tr A = L^2 and diverges; the log-conformation's relaxation falls back to the
    // spring factor of the relaxed state (logconf::fene_relaxation) and stays below L^2.
    let l2 = 100.0;
    let wi = 50.0;
    let kappa = extension(wi / LAMBDA);
    for dt in [LAMBDA / 100.0, LAMBDA / 20.0] {
        let n = (20.0 * LAMBDA / dt) as usize;
        let fp = FeneP::new(ETA0, BETA, LAMBDA, l2);
        let fc = FeneCr::new(ETA0, BETA, LAMBDA, l2);
        for (name, max_log, max_direct) in [
            (
                "FENE-P",
                max_trace(LOG, &fp, &kappa, dt, n),
                max_trace(DIRECT, &fp, &kappa, dt, n),
            ),
            (
                "FENE-CR",
                max_trace(LOG, &fc, &kappa, dt, n),
                max_trace(DIRECT, &fc, &kappa, dt, n),
            ),
        ] {
            println!(
                "{name} Wi = {wi}, dt = {:.3} lambda: max tr A log {max_log:.4}, \
                 direct {max_direct:.3e} (L2 = {l2})",
                dt / LAMBDA
            );
            assert!(max_log < l2 && max_log > 0.9 * l2, "{name}: {max_log}");
            assert!(
                max_direct.is_nan() || max_direct >= l2,
                "{name}: direct stayed below L2: {max_direct}"
            );
        }
    }
}

fn max_trace<R: Rheology>(
    method: ConformationMethod,
    model: &R,
    kappa: &Mat2,
    dt: f64,
    n: usize,
) -> f64 {
    let mut max_tr = 0.0f64;
    integrate(
        method,
        model,
        model.rest_conformation(),
        kappa,
        dt,
        n,
        |_, a| {
            max_tr = if a.trace().is_nan() {
                f64::NAN
            } else {
                max_tr.max(a.trace())
            };
        },
    );
    max_tr
}

/// Steady simple shear: (tau_xy, N1, tau_yy) at t = 40 lambda.
fn steady_shear<R: Rheology>(method: ConformationMethod, model: &R, wi: f64) -> (f64, f64, f64) {
    let dt = LAMBDA / 100.0;
    let n = (40.0 * LAMBDA / dt) as usize;
    let a = integrate(
        method,
        model,
        model.rest_conformation(),
        &shear(wi / LAMBDA),
        dt,
        n,
        |_, _| {},
    );
    let tau = model.polymer_stress(&a);
    (tau[(0, 1)], tau[(0, 0)] - tau[(1, 1)], tau[(1, 1)])
}

fn check_steady(
    name: &str,
    method: ConformationMethod,
    got: (f64, f64, f64),
    want: (f64, f64, f64),
) {
    let (e_tau, e_n1) = (rel(got.0, want.0), rel(got.1, want.1));
    let e_yy = (got.2 - want.2).abs() / want.0.abs();
    println!(
        "{name} {method:?}: tau_xy error {e_tau:.2e}, N1 error {e_n1:.2e}, tau_yy error {e_yy:.2e}"
    );
    assert!(
        e_tau < 1e-3 && e_n1 < 1e-3 && e_yy < 1e-3,
        "{name} {method:?}: {got:?} vs {want:?}"
    );
}

#[test]
fn giesekus_steady_shear_matches_closed_form() {
    // Giesekus 1982; Bird, Armstrong & Hassager, Dynamics of Polymeric Liquids vol. 1 (1987):
    // eta_p(g)/eta_p = (1 - f)^2 / (1 + (1 - 2a) f),
    // Psi1 / (2 eta_p lambda) = f (1 - a f) / (Wi^2 a (1 - f)),
    // f = (1 - chi)/(1 + (1 - 2a) chi),
    // chi^2 = (sqrt(1 + 16 a (1 - a) Wi^2) - 1) / (8 a (1 - a) Wi^2).
    // tau_yy follows from the yy component: tau_yy + (a/G)(tau_xy^2 + tau_yy^2) = 0.
    let g_mod = modulus();
    for alpha in [0.1, 0.3, 0.5] {
        for wi in [0.5, 2.0, 8.0] {
            let k: f64 = 8.0 * alpha * (1.0 - alpha) * wi * wi;
            let chi = (((1.0 + 2.0 * k).sqrt() - 1.0) / k).sqrt();
            let f = (1.0 - chi) / (1.0 + (1.0 - 2.0 * alpha) * chi);
            let g = wi / LAMBDA;
            let tau_xy = eta_p() * g * (1.0 - f).powi(2) / (1.0 + (1.0 - 2.0 * alpha) * f);
            let n1 = 2.0 * eta_p() * LAMBDA * g * g * f * (1.0 - alpha * f)
                / (wi * wi * alpha * (1.0 - f));
            let x = tau_xy / g_mod;
            let tau_yy = g_mod * ((1.0 - 4.0 * alpha * alpha * x * x).sqrt() - 1.0) / (2.0 * alpha);
            let model = Giesekus::new(ETA0, BETA, LAMBDA, alpha);
            for method in METHODS {
                check_steady(
                    &format!("Giesekus alpha = {alpha} Wi = {wi}"),
                    method,
                    steady_shear(method, &model, wi),
                    (tau_xy, n1, tau_yy),
                );
            }
        }
    }
}

#[test]
fn ptt_steady_shear_matches_steady_state_algebra() {
    // f_S = A - I and A_yy = 1: A_xy = Wi/h, A_xx - 1 = 2 Wi^2/h^2 with the relaxation factor
    // h = 1 + eps tr(A - I) = 1 + 2 eps Wi^2/h^2 (linear) or exp(2 eps Wi^2/h^2) (exponential).
    let g_mod = modulus();
    for eps in [0.05, 0.25] {
        for wi in [1.0, 5.0] {
            let s = 2.0 * eps * wi * wi;
            let h_lin = bisect(|h| h - 1.0 - s / (h * h), 1.0, 1.0 + s);
            let h_exp = bisect(|h| h - (s / (h * h)).exp(), 1.0, 1.0 + s.exp());
            for method in METHODS {
                for (name, h, got) in [
                    (
                        "linear PTT",
                        h_lin,
                        steady_shear(method, &PttLinear::new(ETA0, BETA, LAMBDA, eps), wi),
                    ),
                    (
                        "exponential PTT",
                        h_exp,
                        steady_shear(method, &PttExponential::new(ETA0, BETA, LAMBDA, eps), wi),
                    ),
                ] {
                    let want = (g_mod * wi / h, g_mod * 2.0 * wi * wi / (h * h), 0.0);
                    check_steady(&format!("{name} eps = {eps} Wi = {wi}"), method, got, want);
                }
            }
        }
    }
}

#[test]
fn fene_p_steady_shear_matches_cubic() {
    // A_yy = 1/f, A_xy = Wi/f^2, A_xx = 1/f + 2 Wi^2/f^3, f = 1/(1 - tr A/L^2), so
    // L^2 f^3 - (L^2 + 2) f^2 - 2 Wi^2 = 0; tau_xy = G Wi/f, N1 = 2 G Wi^2/f^2, tau_yy = 0.
    let g_mod = modulus();
    for l2 in [20.0, 100.0] {
        for wi in [1.0, 5.0] {
            let f = bisect(
                |f| l2 * f.powi(3) - (l2 + 2.0) * f * f - 2.0 * wi * wi,
                1.0,
                1e3,
            );
            let want = (g_mod * wi / f, 2.0 * g_mod * wi * wi / (f * f), 0.0);
            let model = FeneP::new(ETA0, BETA, LAMBDA, l2);
            for method in METHODS {
                check_steady(
                    &format!("FENE-P L2 = {l2} Wi = {wi}"),
                    method,
                    steady_shear(method, &model, wi),
                    want,
                );
            }
        }
    }
}

/// Largest difference of two models' conformation histories, relative to the largest entry.
fn history_difference<R: Rheology, S: Rheology>(method: ConformationMethod, r: &R, s: &S) -> f64 {
    let dt = LAMBDA / 50.0;
    let mut worst = 0.0f64;
    for kappa in [
        shear(3.0 / LAMBDA),
        extension(0.3 / LAMBDA),
        Mat2::new(0.2, 1.5, -0.4, -0.2) / LAMBDA,
    ] {
        let (mut a, mut b) = (Mat2::identity(), Mat2::identity());
        for _ in 0..200 {
            a = pc_step(method, r, &a, &kappa, dt);
            b = pc_step(method, s, &b, &kappa, dt);
            worst = worst.max((a - b).abs().max() / a.abs().max());
        }
    }
    worst
}

#[test]
fn limits_reproduce_oldroyd_b_and_newtonian() {
    let ob = OldroydB::new(ETA0, BETA, LAMBDA);
    for method in METHODS {
        let d_cr = history_difference(method, &ob, &FeneCr::new(ETA0, BETA, LAMBDA, 1e12));
        let d_lin = history_difference(method, &ob, &PttLinear::new(ETA0, BETA, LAMBDA, 0.0));
        let d_exp = history_difference(method, &ob, &PttExponential::new(ETA0, BETA, LAMBDA, 0.0));
        let d_gk = history_difference(method, &ob, &Giesekus::new(ETA0, BETA, LAMBDA, 0.0));
        println!(
            "{method:?}: difference to Oldroyd-B: FENE-CR L2 = 1e12 {d_cr:.1e}, linear PTT eps = 0 {d_lin:.1e}, \
             exponential PTT eps = 0 {d_exp:.1e}, Giesekus alpha = 0 {d_gk:.1e}"
        );
        assert!(d_cr < 1e-9, "{d_cr:e}");
        assert!(
            d_lin < 1e-12 && d_exp < 1e-12 && d_gk < 1e-12,
            "{d_lin:e} {d_exp:e} {d_gk:e}"
        );
    }
    // Cross with eta_inf = eta0 is Newtonian whatever the shear rate.
    let cross = Cross::new(4.0, 4.0, 1.0, 1.0);
    let newt = Newtonian::new(4.0);
    for kappa in [
        Mat2::zeros(),
        shear(0.3),
        shear(1e4),
        Mat2::new(5.0, -2.0, 7.0, -5.0),
    ] {
        assert_eq!(
            cross.solvent_viscosity(&kappa),
            newt.solvent_viscosity(&kappa)
        );
    }
    assert_eq!(cross.max_viscosity(), newt.max_viscosity());
    assert_eq!(
        (cross.polymer_viscosity(), newt.polymer_viscosity()),
        (0.0, 0.0)
    );
    const { assert!(!Cross::ELASTIC && !Newtonian::ELASTIC) };
}

#[test]
fn cross_viscosity_follows_ren_eqs_6_7() {
    // Ren 2015 section 4.2: nu0 = 4e-3, nu_inf = 4e-4 m^2/s, rho = 1000, K = m = 1.
    let cross = Cross::new(4.0, 0.4, 1.0, 1.0);
    // Eq. (7): simple shear v_x = g y has gamma_dot = |g|; planar extension rate e has 2|e|.
    assert!((shear_rate(&shear(-3.0)) - 3.0).abs() < 1e-15);
    assert!((shear_rate(&extension(1.5)) - 3.0).abs() < 1e-15);
    assert_eq!(shear_rate(&rotation(2.0)), 0.0);
    assert_eq!(cross.solvent_viscosity(&Mat2::zeros()), 4.0);
    assert_eq!(cross.solvent_viscosity(&rotation(5.0)), 4.0);
    // K gamma_dot = 1: halfway between eta0 and eta_inf.
    assert!((cross.solvent_viscosity(&shear(1.0)) - 2.2).abs() < 1e-14);
    // K gamma_dot = 9, m = 1: eta_inf + (eta0 - eta_inf)/10.
    assert!((cross.solvent_viscosity(&shear(9.0)) - 0.76).abs() < 1e-14);
    let cross_m2 = Cross::new(4.0, 0.4, 0.5, 2.0);
    assert!((cross_m2.solvent_viscosity(&shear(4.0)) - (0.4 + 3.6 / 5.0)).abs() < 1e-14);
    assert!((cross.solvent_viscosity(&shear(1e12)) - 0.4).abs() < 1e-11);
    assert_eq!(cross.max_viscosity(), 4.0);
}

#[test]
fn log_conformation_stays_positive_definite_where_direct_fails() {
    // A conformation stretched by planar extension at Wi = 2 for 4 lambda (A_xx ~ 2e5,
    // A_yy ~ 0.2), then turned by a rigid rotation kappa = [[0, w], [-w, 0]] with lambda w = 10,
    // both at dt = lambda/100. The exact solution of the second phase is the relaxed tensor turned
    // by the rotation (Oldroyd-B relaxation is isotropic and commutes with it): the eigenvalues obey
    // l(t) = 1 + (l0 - 1) e^{-t/lambda} and det A stays positive. The direct update loses positive
    // definiteness on the second step of the rotation.
    let model = OldroydB::new(ETA0, 0.0, LAMBDA);
    let dt = LAMBDA / 100.0;
    let w = 10.0 / LAMBDA;
    let mut min_det = [f64::INFINITY; 2];
    let mut eig_err = [0.0f64; 2];
    for (m, method) in METHODS.into_iter().enumerate() {
        let stretch = extension(2.0 / LAMBDA);
        let stretched = integrate(
            method,
            &model,
            Mat2::identity(),
            &stretch,
            dt,
            400,
            |_, a| {
                assert!(a.determinant() > 0.0);
            },
        );
        let e0 = logconf::sym_eigen(&stretched);
        assert!(e0.l1 > 1e5 && e0.l2 < 0.25, "{e0:?}");
        integrate(method, &model, stretched, &rotation(w), dt, 25, |t, a| {
            min_det[m] = min_det[m].min(a.determinant());
            let e = logconf::sym_eigen(a);
            let decay = (-t / LAMBDA).exp();
            let (l1, l2) = (1.0 + (e0.l1 - 1.0) * decay, 1.0 + (e0.l2 - 1.0) * decay);
            eig_err[m] = eig_err[m].max(rel(e.l1, l1)).max(rel(e.l2, l2));
        });
    }
    println!(
        "pre-stretched rotation over lambda/4: min det A direct {:.3e}, log {:.3e}; \
         eigenvalue error direct {:.2e}, log {:.2e}",
        min_det[0], min_det[1], eig_err[0], eig_err[1]
    );
    assert!(
        min_det[0] < 0.0,
        "direct integration kept det A > 0: {}",
        min_det[0]
    );
    assert!(
        min_det[1] > 0.0,
        "log-conformation lost det A > 0: {}",
        min_det[1]
    );
    // The log-conformation's error is that of the explicit rotation step (31), 0.2 rad a step.
    assert!(eig_err[1] < 0.05, "{}", eig_err[1]);
}

#[test]
fn log_conformation_determinant_follows_compressible_velocity_gradient() {
    // Without relaxation (lambda huge), d ln det A / dt = 2 tr(kappa) for any kappa; the split
    // keeps this exactly because B carries the trace of kappa (weakly compressible schemes).
    let model = OldroydB::new(ETA0, BETA, 1e12);
    let kappa = Mat2::new(0.3, 1.0, 0.2, 0.1);
    let dt = 0.01;
    let a = integrate(LOG, &model, Mat2::identity(), &kappa, dt, 300, |_, _| {});
    let want = (2.0 * kappa.trace() * 3.0).exp();
    assert!(
        rel(a.determinant(), want) < 1e-9,
        "{} vs {want}",
        a.determinant()
    );
}

#[test]
fn giesekus_exact_relaxation_against_eq_33() {
    // The explicit step of King & Lind eq. (33) loses positive definiteness for a stretched
    // conformation at dt/lambda = 0.3; the exact solution of (29b) does not, and (33) agrees with
    // it to O(dt^2) per step.
    let model = Giesekus::new(ETA0, BETA, LAMBDA, 0.3);
    let a0 = Mat2::new(50.0, 0.0, 0.0, 0.02);
    let explicit = logconf::explicit_relaxation(&model, &a0, 0.3 * LAMBDA);
    let exact = model.relaxation_step(&a0, &a0, 0.3 * LAMBDA);
    assert!(explicit.determinant() < 0.0);
    assert!(exact[(0, 0)] > 0.0 && exact[(1, 1)] > 0.0 && exact[(0, 1)] == 0.0);
    let diff = |dt: f64| {
        (logconf::explicit_relaxation(&model, &a0, dt) - model.relaxation_step(&a0, &a0, dt))
            .abs()
            .max()
    };
    let ratio = diff(2e-4 * LAMBDA) / diff(1e-4 * LAMBDA);
    assert!((ratio - 4.0).abs() < 0.05, "{ratio}");
    // Exact means exact: two half steps equal one full step.
    let half = model.relaxation_step(&model.relaxation_step(&a0, &a0, 0.5), &a0, 0.5);
    assert!((half - model.relaxation_step(&a0, &a0, 1.0)).abs().max() < 1e-12);
}

#[test]
fn rest_state_is_kept() {
    fn check<R: Rheology>(model: &R) {
        let rest = model.rest_conformation::<2>();
        assert!(model.relax(&rest).abs().max() < 1e-14, "{model:?}");
        assert!(model.strain(&rest).abs().max() < 1e-14, "{model:?}");
        for method in METHODS {
            let a = integrate(method, model, rest, &Mat2::zeros(), 0.1, 20, |_, _| {});
            assert!((a - rest).abs().max() < 1e-14, "{model:?} {method:?}");
        }
    }
    check(&OldroydB::new(ETA0, BETA, LAMBDA));
    check(&FeneP::new(ETA0, BETA, LAMBDA, 10.0));
    check(&FeneCr::new(ETA0, BETA, LAMBDA, 10.0));
    check(&PttLinear::new(ETA0, BETA, LAMBDA, 0.25));
    check(&PttExponential::new(ETA0, BETA, LAMBDA, 0.25));
    check(&Giesekus::new(ETA0, BETA, LAMBDA, 0.4));
    assert_eq!(
        FeneP::new(ETA0, BETA, LAMBDA, 10.0).rest_conformation::<2>(),
        Mat2::identity() * (10.0 / 12.0)
    );
}

#[test]
fn evss_split_leaves_total_stress_unchanged() {
    // King & Lind eqs. (6)-(7): Phi + (beta + alpha_V) eta0 2D = tau_p + beta eta0 2D, with
    // alpha_V = evss_alpha (1 - beta).
    let model = OldroydB::new(ETA0, BETA, LAMBDA);
    let evss = Evss::new(&model, 1.0);
    assert!(evss.is_on());
    assert!((evss.added_viscosity() - (1.0 - BETA) * ETA0).abs() < 1e-15);
    let kappa = Mat2::new(0.3, 1.2, -0.7, -0.1);
    let tau_p = model.polymer_stress(&Mat2::new(2.0, 0.5, 0.5, 1.1));
    let two_d = kappa + kappa.transpose();
    let eta_s = model.solvent_viscosity(&kappa);
    let total = evss.phi(&tau_p, &kappa) + two_d * evss.viscous_viscosity(eta_s);
    assert!((total - (tau_p + two_d * eta_s)).abs().max() < 1e-14);
    let half = Evss::new(&model, 0.5);
    assert!((half.viscous_viscosity(eta_s) - (BETA + 0.5 * (1.0 - BETA)) * ETA0).abs() < 1e-15);
    assert!(!Evss::new(&model, 0.0).is_on());
    assert!(!Evss::new(&Cross::new(4.0, 0.4, 1.0, 1.0), 1.0).is_on());
    assert!(!Evss::new(&Newtonian::new(4.0), 1.0).is_on());
    assert_eq!(Evss::off().phi(&tau_p, &kappa), tau_p);
}

fn elastic<R: Rheology>(_: &R) -> bool {
    R::ELASTIC
}

#[test]
fn every_rheology_builds_from_the_configuration() {
    for (name, _) in RHEOLOGIES {
        let mut cfg = SceneConfig::default();
        cfg.set("rheology", Value::Text(name.to_string())).unwrap();
        cfg.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        let kind = RheologyKind::parse(name).unwrap();
        let model = AnyRheology::from_config(&cfg).unwrap();
        let is_elastic = dispatch_rheology!(&model, m => elastic(m));
        assert_eq!(
            is_elastic,
            !matches!(kind, RheologyKind::Newtonian | RheologyKind::Cross),
            "{name}"
        );
        let eta0 = cfg.fluid.viscosity;
        let eta_s = cfg.fluid.viscosity_ratio * eta0;
        match (kind, &model) {
            (RheologyKind::Newtonian, AnyRheology::Newtonian(m)) => assert_eq!(m.viscosity, eta0),
            (RheologyKind::OldroydB, AnyRheology::OldroydB(m)) => assert_eq!(m.p.eta_s, eta_s),
            (RheologyKind::Ucm, AnyRheology::OldroydB(m)) => {
                assert_eq!((m.p.eta_s, m.p.eta_p), (0.0, eta0))
            }
            (RheologyKind::FeneP, AnyRheology::FeneP(m)) => assert_eq!(m.l2, cfg.fluid.fene_L2),
            (RheologyKind::FeneCr, AnyRheology::FeneCr(m)) => assert_eq!(m.l2, cfg.fluid.fene_L2),
            (RheologyKind::PttLinear, AnyRheology::PttLinear(m)) => {
                assert_eq!(m.eps, cfg.fluid.ptt_epsilon)
            }
            (RheologyKind::PttExponential, AnyRheology::PttExponential(m)) => {
                assert_eq!(m.eps, cfg.fluid.ptt_epsilon)
            }
            (RheologyKind::Giesekus, AnyRheology::Giesekus(m)) => {
                assert_eq!(m.alpha, cfg.fluid.giesekus_alpha)
            }
            (RheologyKind::Cross, AnyRheology::Cross(m)) => assert_eq!(
                (m.eta0, m.eta_inf, m.k, m.m),
                (
                    eta0,
                    cfg.fluid.cross_viscosity_inf,
                    cfg.fluid.cross_K,
                    cfg.fluid.cross_m
                )
            ),
            (k, m) => panic!("{k} built {m:?}"),
        }
        dispatch_rheology!(&model, m => {
            if elastic(m) {
                assert_eq!(m.relaxation_time(), cfg.fluid.relaxation_time);
                let eta = m.polymer_viscosity() + m.solvent_viscosity(&Mat2::zeros());
                assert!((eta - eta0).abs() < 1e-12);
            }
            assert!(m.max_viscosity() >= m.solvent_viscosity(&shear(10.0)));
        });
    }
}

#[test]
fn meaningless_rheology_parameters_are_refused_by_name() {
    for (name, value) in [
        ("fene_L2", 2.0),
        ("fene_L2", 1.0),
        ("giesekus_alpha", 0.6),
        ("giesekus_alpha", -0.1),
        ("relaxation_time", 0.0),
        ("relaxation_time", -1.0),
        ("viscosity", -1.0),
        ("viscosity_ratio", 1.5),
        ("ptt_epsilon", -0.1),
        ("cross_viscosity_inf", -0.1),
        ("cross_K", -1.0),
        ("cross_m", -1.0),
        ("evss_alpha", -0.5),
    ] {
        let mut cfg = SceneConfig::default();
        let e = cfg
            .set(name, Value::Real(value))
            .expect_err(name)
            .to_string();
        assert!(e.contains(name), "{e}");
    }
}
