//! Log-conformation integration of the conformation tensor (King & Lind 2021 eqs. 12-19 and
//! 29-33, after Fattal & Kupferman).
//!
//! The conformation tensor A is symmetric positive definite (SPD); its logarithm
//! Psi = R ln(Lambda) R^T (eqs. 12-13) is merely symmetric, so any update of Psi maps back, through
//! A = exp(Psi), to an SPD tensor. The upper-convected equation is split (eqs. 29-30) into
//!
//! * the **convective** part dPsi/dt = (Omega Psi - Psi Omega) + 2 B (eq. 30a), with the velocity
//!   gradient decomposed as kappa = Omega + B + N A^{-1} (eqs. 14, 16-19), integrated explicitly in
//!   Psi (eq. 31), and
//! * the **relaxation** part dA/dt = -f_R(A)/lambda (eq. 29b), integrated in A by each model's
//!   [`Rheology::relaxation_step`]: quasi-analytically (eq. 32) for f_R = alpha_R (beta_R A - I)
//!   (Oldroyd-B, UCM, FENE-P, FENE-CR, linear and exponential PTT), exactly for Giesekus.
//!
//! Differences from the paper, all deliberate:
//! * Eq. (31) prints `- 2 B^n`; eq. (30a) and Fattal & Kupferman have `+ 2 B`, which is what the
//!   upper-convected derivative gives (at A = I, dA/dt = kappa + kappa^T = 2 D). We use `+ 2 B`;
//!   the start-up shear test against the exact Oldroyd-B solution would fail with the other sign.
//! * Equal eigenvalues (A = I at rest): eq. (19) divides by Lambda_2 - Lambda_1. Only the product
//!   omega (psi_2 - psi_1), which is what enters Omega Psi - Psi Omega, is needed, and
//!   `omega (psi_2 - psi_1) = (Lambda_2 m_12 + Lambda_1 m_21) [ln Lambda_2 - ln Lambda_1] / (Lambda_2 - Lambda_1)`
//!   has the bounded divided difference of ln, which tends to 1/Lambda as the eigenvalues merge.
//!   We evaluate it with `ln_1p`, so nothing divides by zero and the limit is exact: at A = l I the
//!   rate is kappa + kappa^T in any frame.
//! * B carries the trace of kappa: a weakly compressible scheme's velocity gradient is not
//!   traceless, and the diagonal of R^T kappa R is what makes ln(det A) follow 2 tr(kappa).
//! * Stability: positive definiteness is guaranteed, stability is not. Like the direct update,
//!   the explicit step (31) amplifies a rigidly rotating anisotropic Psi by about
//!   1 + (2 w dt)^4/8 per step (w the vorticity), which relaxation outweighs only while the
//!   rotation per step 2 w dt stays below about 2 (dt/lambda)^{1/2} (w dt < 0.1 at
//!   dt = lambda/100). Integrating the vorticity part of
//!   Omega exactly (a rotation) was tried and rejected: it cures rigid rotation but breaks the
//!   cancellation between vorticity and strain-induced turning of the eigenvectors that makes (31)
//!   accurate in shear (tr A off by 7 % instead of < 0.1 % at Wi = 10, gamma_dot dt = 0.1).
//! * Time accuracy: the paper pairs one first-order splitting with its half-step stress storage. To
//!   fit a predictor-corrector (our [`super::advance`] signature) at second order we use Strang
//!   splitting: relax dt/2, convect dt, relax dt/2, with the convective rate (30a) and any frozen
//!   relaxation coefficients (alpha_R, beta_R of eq. 32, "neglecting the change in tr(A)")
//!   evaluated at `a_eval`. A predictor-corrector passes a_eval = A^n for its half step and
//!   a_eval = A^{n+1/2} for its full step, which makes the full step a midpoint rule: second order.
//! * Giesekus: eq. (33) is explicit Euler for (29b) and loses positive definiteness once
//!   dt/lambda * alpha * Lambda_max is of order one. Since f_R is a polynomial in A, (29b) keeps
//!   the eigenvectors of A and each eigenvalue obeys the Riccati equation
//!   dl/dt = -(l - 1)(alpha l + 1 - alpha)/lambda, which we solve exactly
//!   ([`giesekus_relaxation`]); eq. (33) agrees with it to O(dt^2) per step and is kept as
//!   [`explicit_relaxation`].
//! * FENE: eq. (32) with tr(A) frozen cannot see the singularity at tr(A) = L^2, so a large
//!   convective step can carry A past full extension, after which the spring factor changes sign.
//!   [`fene_relaxation`] keeps eq. (32) whenever it lands below L^2 and otherwise evaluates the
//!   spring factor at the relaxed state (implicitly in tr(A)), which always lies below L^2.
//! * The paper stores tau_p and tr(A) and recovers A by inverting f_S (step 1); we store A itself,
//!   so step 1 and step 8 are not needed. The entries of a stored A resolve its smaller eigenvalue
//!   down to about 1e-16 of the larger one; beyond that stretch [`log_spd`] floors it there.
//! * The ALE term u_ps . grad Psi of eqs. (30a)-(31) belongs to a scheme with shifting: it needs
//!   neighbours. [`advance_log`] is the Lagrangian update; a shifting scheme adds
//!   dt u_ps . grad Psi using [`log_spd`] / [`exp_sym`].

use super::Rheology;
use crate::dim::{Const, Dim, Tensor};

pub use crate::dim::SymEigen;

/// Eigen-decomposition of the symmetric part of `a` (King & Lind eq. 12) through the
/// dimension's [`Dim::sym_eigen`], eigenvalues descending; in 2D the closed form
/// [`SymEigen`].
#[inline]
pub fn sym_eigen<const N: usize>(a: &Tensor<N>) -> <Const<N> as Dim>::SymEigen
where
    Const<N>: Dim,
{
    Const::<N>::sym_eigen(a)
}

/// [`sym_eigen`] of a tensor known to be SPD. Unless it is diagonal, its entries resolve the
/// smaller eigenvalues only down to about eps * l1 (l1 the largest): a conformation stretched
/// beyond l1/l ~ 1e16 can round to a singular or indefinite tensor. An eigenvalue that rounded to
/// zero or below is replaced by that resolution, eps * l1, so that the logarithm stays finite.
#[inline]
fn spd_eigen<const N: usize>(a: &Tensor<N>) -> <Const<N> as Dim>::SymEigen
where
    Const<N>: Dim,
{
    let e = Const::<N>::sym_eigen(a);
    let mut l = Const::<N>::eigenvalues(&e);
    let mut floored = false;
    for k in 1..N {
        if l[k].is_nan() || l[k] <= 0.0 {
            l[k] = l[0] * f64::EPSILON;
            floored = true;
        }
    }
    if floored {
        Const::<N>::with_eigenvalues(&e, &l)
    } else {
        e
    }
}

/// Psi = log A = R ln(Lambda) R^T for SPD `a` (King & Lind eq. 13).
#[inline]
pub fn log_spd<const N: usize>(a: &Tensor<N>) -> Tensor<N>
where
    Const<N>: Dim,
{
    let e = spd_eigen(a);
    Const::<N>::compose(&e, &Const::<N>::eigenvalues(&e).map(f64::ln))
}

/// A = exp(Psi) = R exp(ln Lambda) R^T for symmetric `psi` (King & Lind step 6): SPD by
/// construction.
#[inline]
pub fn exp_sym<const N: usize>(psi: &Tensor<N>) -> Tensor<N>
where
    Const<N>: Dim,
{
    let e = Const::<N>::sym_eigen(psi);
    Const::<N>::compose(&e, &Const::<N>::eigenvalues(&e).map(f64::exp))
}

/// (ln l2 - ln l1) / (l2 - l1), the divided difference of ln, for l1 >= l2 > 0; 1/l1 when they
/// are equal.
#[inline]
fn ln_divided_difference(l1: f64, l2: f64) -> f64 {
    let x = (l2 - l1) / l1;
    if x == 0.0 {
        1.0 / l1
    } else {
        x.ln_1p() / (x * l1)
    }
}

/// The convective rate of the log-conformation, (Omega Psi - Psi Omega) + 2 B (King & Lind
/// eq. 30a without the ALE term), at the SPD conformation `a` and velocity gradient
/// kappa_ab = d v_a / d x_b. Eqs. (16)-(19) give, in the eigenframe of A (M = R^T kappa R),
/// 2B = diag(2 m_kk) and (Omega Psi - Psi Omega)_kl = omega_kl (psi_l - psi_k)
/// = (l_l m_kl + l_k m_lk) (ln l_l - ln l_k) / (l_l - l_k); the latter is evaluated as a divided
/// difference so that equal eigenvalues are handled exactly.
#[inline]
pub fn log_convection_rate<const N: usize>(a: &Tensor<N>, kappa: &Tensor<N>) -> Tensor<N>
where
    Const<N>: Dim,
{
    let e = spd_eigen(a);
    let l = Const::<N>::eigenvalues(&e);
    let r = Const::<N>::eigenvectors(&e);
    // M = R^T kappa R, eq. (16). In the eigenframe: 2B from eq. (17) on the diagonal, the
    // commutator (eqs. 18-19) off it (upper triangle: entry (k, j), k < j, l_k >= l_j).
    let m = r.transpose() * kappa * r;
    let mut frame = Tensor::<N>::zeros();
    for k in 0..N {
        frame[(k, k)] = 2.0 * m[(k, k)];
        for j in k + 1..N {
            frame[(k, j)] =
                (l[j] * m[(k, j)] + l[k] * m[(j, k)]) * ln_divided_difference(l[k], l[j]);
        }
    }
    Const::<N>::from_eigenframe(&e, &frame)
}

/// Quasi-analytic relaxation, King & Lind eq. (32): the exact solution over `dt` of
/// dA/dt = -(alpha_R / lambda)(beta_R A - I) with alpha_R, beta_R frozen,
/// A(dt) = A e^{-alpha_R beta_R dt/lambda} + (1 - e^{-alpha_R beta_R dt/lambda}) I / beta_R.
/// SPD in, SPD out whenever alpha_R beta_R >= 0 and beta_R > 0.
#[inline]
pub fn quasi_analytic_relaxation<const N: usize>(
    a: &Tensor<N>,
    alpha_r: f64,
    beta_r: f64,
    dt_over_lambda: f64,
) -> Tensor<N> {
    let x = -alpha_r * beta_r * dt_over_lambda;
    let decay = x.exp();
    let grow = -x.exp_m1() / beta_r;
    let mut out = a * decay;
    for k in 0..N {
        out[(k, k)] += grow;
    }
    out
}

/// Eq. (32) for a FENE model, whose coefficients depend on A through the spring factor
/// f = 1/(1 - tr(A)/L^2): `coef(f)` gives (alpha_R, beta_R). The factor is frozen at `a_coef` as
/// long as that is below full extension and the relaxed state is too. Otherwise (a large
/// convective step carried A to or past tr(A) = L^2) f is taken at the relaxed state itself: the
/// trace T of the result solves
/// T = tr(A) e^{-alpha_R beta_R h} + N (1 - e^{-alpha_R beta_R h})/beta_R (tr I = N) with
/// f = f(T), which has a root below L^2 for both FENE-P (the right side tends to 0 as
/// T -> L^2) and FENE-CR (it tends to N < L^2). So tr(A) < L^2 after every log-conformation step.
#[inline]
pub fn fene_relaxation<const N: usize>(
    a: &Tensor<N>,
    a_coef: &Tensor<N>,
    l2: f64,
    dt_over_lambda: f64,
    coef: impl Fn(f64) -> (f64, f64),
) -> Tensor<N> {
    let spring = |trace: f64| 1.0 / (1.0 - trace / l2);
    let f = spring(a_coef.trace());
    if f > 0.0 && f.is_finite() {
        let (alpha_r, beta_r) = coef(f);
        let out = quasi_analytic_relaxation(a, alpha_r, beta_r, dt_over_lambda);
        if out.trace() < l2 {
            return out;
        }
    }
    let t0 = a.trace();
    let relaxed_trace = |t: f64| {
        let (alpha_r, beta_r) = coef(spring(t));
        let x = -alpha_r * beta_r * dt_over_lambda;
        t0 * x.exp() - N as f64 * x.exp_m1() / beta_r
    };
    // Bisection on [0, L^2): relaxed_trace(t) - t is positive at 0 and tends to a negative limit.
    let (mut lo, mut hi) = (0.0, l2);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if relaxed_trace(mid) > mid {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (alpha_r, beta_r) = coef(spring(lo));
    quasi_analytic_relaxation(a, alpha_r, beta_r, dt_over_lambda)
}

/// Explicit relaxation step, King & Lind eq. (33): A - (dt/lambda) f_R(A). Not used by
/// [`advance_log`] (it is not positive-definiteness preserving); kept for comparison.
#[inline]
pub fn explicit_relaxation<const N: usize, R: Rheology>(
    model: &R,
    a: &Tensor<N>,
    dt: f64,
) -> Tensor<N> {
    a - model.relax(a) * (dt / model.relaxation_time())
}

/// Exact solution of the Giesekus relaxation sub-problem (King & Lind eq. 29b with the Table I
/// f_R = alpha A^2 + (1 - 2 alpha) A - (1 - alpha) I) over `dt_over_lambda` relaxation times.
/// f_R is a polynomial in A, so the eigenvectors stay and each eigenvalue l solves
/// dl/dt = -(l - 1)(alpha l + 1 - alpha)/lambda, whose solution is
/// l(t) = (1 + (1 - alpha) q) / (1 - alpha q), q = (l0 - 1) e^{-t/lambda} / (alpha l0 + 1 - alpha).
/// For 0 <= alpha <= 1/2 and l0 > 0 both numerator and denominator stay positive: SPD is kept for
/// any step; alpha = 0 gives the Oldroyd-B relaxation 1 + (l0 - 1) e^{-t/lambda}.
#[inline]
pub fn giesekus_relaxation<const N: usize>(
    a: &Tensor<N>,
    alpha: f64,
    dt_over_lambda: f64,
) -> Tensor<N>
where
    Const<N>: Dim,
{
    let e = spd_eigen(a);
    let decay = (-dt_over_lambda).exp();
    let relax = |l0: f64| {
        let q = (l0 - 1.0) * decay / (alpha * l0 + 1.0 - alpha);
        (1.0 + (1.0 - alpha) * q) / (1.0 - alpha * q)
    };
    Const::<N>::compose(&e, &Const::<N>::eigenvalues(&e).map(relax))
}

/// One log-conformation step of length `dt` from `a_base`, with the convective rate and frozen
/// relaxation coefficients taken at `a_eval` (see the module documentation):
/// relax dt/2 (eq. 32 or the exact Giesekus solution),
/// Psi* = log A + dt [(Omega Psi - Psi Omega) + 2B] (eqs. 13, 16-19, 31), A* = exp(Psi*)
/// (step 6), relax dt/2. Returns an SPD tensor for any SPD `a_base` and `a_eval`.
#[inline]
pub fn advance_log<const N: usize, R: Rheology>(
    model: &R,
    a_base: &Tensor<N>,
    a_eval: &Tensor<N>,
    kappa: &Tensor<N>,
    dt: f64,
) -> Tensor<N>
where
    Const<N>: Dim,
{
    let half = 0.5 * dt;
    let a1 = model.relaxation_step(a_base, a_eval, half);
    let psi = log_spd(&a1) + log_convection_rate(a_eval, kappa) * dt;
    let a2 = exp_sym(&psi);
    model.relaxation_step(&a2, a_eval, half)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mat2;

    fn close(a: &Mat2, b: &Mat2, tol: f64) -> bool {
        (a - b).abs().max() <= tol * (1.0 + b.abs().max())
    }

    #[test]
    fn eigen_round_trip_and_isotropic() {
        let a = Mat2::new(3.0, 1.2, 1.2, 0.7);
        let e = sym_eigen(&a);
        assert!(close(&e.compose(e.l1, e.l2), &a, 1e-14));
        assert!(e.l1 >= e.l2);
        let i = sym_eigen(&(Mat2::identity() * 2.0));
        assert_eq!((i.c, i.s, i.l1, i.l2), (1.0, 0.0, 2.0, 2.0));
        assert!(close(&exp_sym(&log_spd(&a)), &a, 1e-14));
    }

    #[test]
    fn isotropic_rate_is_twice_the_strain_rate() {
        let k = Mat2::new(0.3, 2.0, -0.5, 0.1);
        for l in [1.0, 0.25, 7.0] {
            let r = log_convection_rate(&(Mat2::identity() * l), &k);
            assert!(close(&r, &(k + k.transpose()), 1e-15), "{r}");
        }
    }

    #[test]
    fn fene_relaxation_falls_back_below_full_extension() {
        let l2 = 10.0;
        let past = Mat2::new(12.0, 3.0, 3.0, 1.0); // tr = 13 > L^2
        for coef in [|f: f64| (1.0, f), |f: f64| (f, 1.0)] {
            // Frozen factor invalid (a_coef past L^2) and valid but overshooting (h tiny).
            for (a_coef, h) in [(past, 0.01), (Mat2::identity(), 1e-6)] {
                let out = fene_relaxation(&past, &a_coef, l2, h, coef);
                assert!(out.trace() < l2 && out.determinant() > 0.0, "{out}");
            }
            // Below full extension the frozen factor of eq. (32) is used as is.
            let a = Mat2::new(3.0, 0.5, 0.5, 2.0);
            let f = 1.0 / (1.0 - a.trace() / l2);
            let (ar, br) = coef(f);
            assert_eq!(
                fene_relaxation(&a, &a, l2, 0.1, coef),
                quasi_analytic_relaxation(&a, ar, br, 0.1)
            );
        }
    }

    #[test]
    fn rate_matches_frechet_derivative_of_log() {
        // d/dt log(A) along dA/dt = kappa A + A kappa^T, by central differences.
        let a = Mat2::new(2.0, 0.6, 0.6, 0.9);
        let k = Mat2::new(0.2, 1.3, -0.4, -0.1);
        let da = k * a + a * k.transpose();
        let h = 1e-6;
        let fd = (log_spd(&(a + da * h)) - log_spd(&(a - da * h))) / (2.0 * h);
        assert!(close(&log_convection_rate(&a, &k), &fd, 1e-8));
        // Nearly equal eigenvalues: the divided difference stays finite and correct.
        let a = Mat2::new(1.0 + 1e-13, 0.0, 0.0, 1.0);
        let fd = k + k.transpose();
        assert!(close(&log_convection_rate(&a, &k), &fd, 1e-12));
    }
}
