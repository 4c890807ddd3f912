//! Constitutive models as strain and relaxation functions (King & Lind 2021, Table I), plus
//! generalized-Newtonian viscosity (the Cross model of Ren 2015).
//!
//! The polymer stress is tau_p = (eta_p / lambda) f_S(A) (King & Lind eq. 9) and the conformation
//! tensor obeys the upper-convected equation dA/dt = kappa A + A kappa^T - f_R(A) / lambda
//! (eqs. 10-11), with kappa_ab = d v_a / d x_b (Fang 2006 eq. 23). A scheme only calls this trait,
//! [`advance`] and (optionally) [`Evss`], so adding a model is adding a file: the scheme never
//! changes.
//!
//! Fang 2006 evolves the elastic stress S directly (eq. 28); for Oldroyd-B, S = (eta_p/lambda)(A - I)
//! turns eq. (28) into exactly the conformation equation above, so one formulation serves both
//! papers.
//!
//! | model | file | f_S, f_R (King & Lind Table I) |
//! |---|---|---|
//! | Newtonian | `newtonian.rs` | none (inelastic) |
//! | Oldroyd-B, UCM (beta = 0) | `oldroyd_b.rs` | A - I |
//! | FENE-P | `fene_p.rs` | A / (1 - tr A / L^2) - I |
//! | FENE-CR | `fene_cr.rs` | (A - I) / (1 - tr A / L^2) |
//! | linear PTT | `ptt_linear.rs` | A - I; [1 + eps tr(A - I)](A - I) |
//! | exponential PTT | `ptt_exponential.rs` | A - I; exp[eps tr(A - I)](A - I) |
//! | Giesekus | `giesekus.rs` | A - I; alpha A^2 + (1 - 2 alpha) A - (1 - alpha) I |
//! | Cross | `cross.rs` | none; shear-thinning viscosity (Ren 2015 eqs. 4-7) |
//!
//! Conformation integration: [`advance`] with [`ConformationMethod::Direct`] (explicit update of
//! A) or [`ConformationMethod::Log`] (log-conformation, [`logconf`]).

/// The trait methods every polymer model with a [`Polymer`] field `p` answers the same way:
/// constant solvent viscosity beta eta0, modulus eta_p / lambda (King & Lind eqs. 3-9).
macro_rules! polymer_common {
    () => {
        const ELASTIC: bool = true;
        #[inline]
        fn solvent_viscosity<const N: usize>(&self, _kappa: &Tensor<N>) -> f64 {
            self.p.eta_s
        }
        fn max_viscosity(&self) -> f64 {
            self.p.eta_s + self.p.eta_p
        }
        #[inline]
        fn modulus(&self) -> f64 {
            self.p.eta_p / self.p.lambda
        }
        fn relaxation_time(&self) -> f64 {
            self.p.lambda
        }
    };
}

/// The constitutive functions of the Phan-Thien-Tanner family (King & Lind 2021 Table I):
/// f_S = A - I, f_R = F(A) (A - I) with the model's scalar `factor` F, and the quasi-analytic
/// relaxation step of eq. (32) with alpha_R = F frozen at `a_coef`, beta_R = 1.
macro_rules! ptt_common {
    () => {
        #[inline]
        fn strain<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
            a - Tensor::<N>::identity()
        }
        #[inline]
        fn relax<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
            (a - Tensor::<N>::identity()) * self.factor(a)
        }
        #[inline]
        fn relaxation_step<const N: usize>(
            &self,
            a: &Tensor<N>,
            a_coef: &Tensor<N>,
            dt: f64,
        ) -> Tensor<N>
        where
            Const<N>: Dim,
        {
            $crate::rheology::logconf::quasi_analytic_relaxation(
                a,
                self.factor(a_coef),
                1.0,
                dt / self.p.lambda,
            )
        }
    };
}

/// The trait methods of a model without a polymer (no conformation tensor, no stress from it).
macro_rules! inelastic_common {
    () => {
        const ELASTIC: bool = false;
        fn modulus(&self) -> f64 {
            0.0
        }
        fn relaxation_time(&self) -> f64 {
            f64::INFINITY
        }
        #[inline]
        fn strain<const N: usize>(&self, _a: &Tensor<N>) -> Tensor<N> {
            Tensor::<N>::zeros()
        }
        #[inline]
        fn relax<const N: usize>(&self, _a: &Tensor<N>) -> Tensor<N> {
            Tensor::<N>::zeros()
        }
        #[inline]
        fn relaxation_step<const N: usize>(
            &self,
            a: &Tensor<N>,
            _a_coef: &Tensor<N>,
            _dt: f64,
        ) -> Tensor<N>
        where
            Const<N>: Dim,
        {
            *a
        }
    };
}

mod cross;
mod evss;
mod fene_cr;
mod fene_p;
mod giesekus;
pub mod logconf;
mod newtonian;
mod oldroyd_b;
mod ptt_exponential;
mod ptt_linear;

pub use cross::{shear_rate, Cross};
pub use evss::Evss;
pub use fene_cr::FeneCr;
pub use fene_p::FeneP;
pub use giesekus::Giesekus;
pub use newtonian::Newtonian;
pub use oldroyd_b::OldroydB;
pub use ptt_exponential::PttExponential;
pub use ptt_linear::PttLinear;

use crate::dim::{Const, Dim, Tensor};

pub const CONFORMATION_METHODS: &[(&str, &str)] = &[
    (
        "direct",
        "direct upper-convected update of the conformation tensor",
    ),
    ("log", "log-conformation (King & Lind eqs. 12-19, 29-33)"),
    (
        "auto",
        "the scheme's own: direct for wcsph and pdri (as Fang 2006 and Ren 2015), log for isph (as King & Lind 2021)",
    ),
];

crate::choice_enum!(
    /// How the conformation tensor is advanced in time.
    ConformationMethod, CONFORMATION_METHODS, Direct = "direct", Log = "log", Auto = "auto");

/// Viscosities and relaxation time shared by every polymer model (King & Lind eqs. 3-9):
/// solvent eta_s = beta eta0, polymer eta_p = (1 - beta) eta0, relaxation time lambda.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Polymer {
    /// Solvent viscosity beta eta0 \[Pa s\].
    pub eta_s: f64,
    /// Polymer viscosity (1 - beta) eta0 \[Pa s\].
    pub eta_p: f64,
    /// Relaxation time \[s\].
    pub lambda: f64,
}

impl Polymer {
    pub fn new(eta0: f64, beta: f64, lambda: f64) -> Self {
        Self {
            eta_s: beta * eta0,
            eta_p: (1.0 - beta) * eta0,
            lambda,
        }
    }
}

/// A constitutive model. `ELASTIC = false` models (Newtonian, Cross) carry no conformation
/// tensor: schemes test the constant, so the tensor work compiles away for them.
///
/// The tensor functions take N x N tensors, N inferred from the argument, with tr I = N wherever
/// the identity's trace enters (FENE-P's rest state, the PTT factors, the FENE relaxation). Two
/// ask for a dimension the solver has (`Const<N>: Dim`): `relaxation_step`, which may go through
/// the dimension's eigen-decomposition, and `rest_conformation`, which has no argument to infer
/// N from.
pub trait Rheology: Send + Sync + Clone + std::fmt::Debug + 'static {
    /// Whether the model has a conformation tensor (a polymer stress).
    const ELASTIC: bool;
    /// Viscosity of the Newtonian (solvent) part [Pa s] given the velocity gradient
    /// kappa_ab = d v_a / d x_b. Constant for most models; shear-rate dependent for Cross.
    fn solvent_viscosity<const N: usize>(&self, kappa: &Tensor<N>) -> f64;
    /// Largest value `solvent_viscosity` can take plus the polymer viscosity [Pa s]: what the
    /// viscous time-step limit (Fang 2006 eq. 53) must respect.
    fn max_viscosity(&self) -> f64;
    /// Polymer modulus eta_p / lambda \[Pa\] (0 for inelastic models).
    fn modulus(&self) -> f64;
    /// Relaxation time lambda \[s\] (infinite for inelastic models).
    fn relaxation_time(&self) -> f64;
    /// Strain function f_S(A) (King & Lind Table I).
    fn strain<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N>;
    /// Relaxation function f_R(A) (King & Lind Table I).
    fn relax<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N>;

    /// The relaxation sub-problem dA/dt = -f_R(A)/lambda (King & Lind eq. 29b) advanced by `dt`
    /// from `a`, as the log-conformation integration needs it: quasi-analytically (eq. 32) with
    /// the coefficients alpha_R, beta_R frozen at `a_coef` for models with
    /// f_R = alpha_R (beta_R A - I), exactly for Giesekus. Must map SPD to SPD; the FENE models
    /// also keep tr(A) < L^2 ([`logconf::fene_relaxation`]).
    fn relaxation_step<const N: usize>(
        &self,
        a: &Tensor<N>,
        a_coef: &Tensor<N>,
        dt: f64,
    ) -> Tensor<N>
    where
        Const<N>: Dim;

    /// Conformation of the fluid at rest, where f_R vanishes: I for every model except the
    /// (unnormalised, King & Lind Table I) FENE-P, whose rest state is L^2/(L^2 + N) I.
    fn rest_conformation<const N: usize>(&self) -> Tensor<N>
    where
        Const<N>: Dim,
    {
        Tensor::<N>::identity()
    }

    /// Polymer viscosity eta_p = (1 - beta) eta0 [Pa s] (0 for inelastic models).
    fn polymer_viscosity(&self) -> f64 {
        if Self::ELASTIC {
            self.modulus() * self.relaxation_time()
        } else {
            0.0
        }
    }

    /// Polymer stress tau_p = (eta_p / lambda) f_S(A) (King & Lind eq. 9).
    #[inline]
    fn polymer_stress<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        self.strain(a) * self.modulus()
    }
}

/// Right-hand side of the conformation equation: kappa A + A kappa^T - f_R(A) / lambda
/// (King & Lind eqs. 10-11 in the Lagrangian frame).
#[inline]
pub fn conformation_rate<const N: usize, R: Rheology>(
    model: &R,
    a: &Tensor<N>,
    kappa: &Tensor<N>,
) -> Tensor<N> {
    kappa * a + a * kappa.transpose() - model.relax(a) / model.relaxation_time()
}

/// Advance the conformation tensor by `dt`: from `a_base`, with rates evaluated at `a_eval` and
/// the velocity gradient `kappa`. A predictor-corrector (Fang 2006 eqs. 49-50) calls this with
/// a_eval = a_base for the half step, then with a_eval = A^{n+1/2} for the full step:
///
/// ```text
/// half = advance(method, model, &a_n, &a_n, &kappa_n, dt / 2);
/// a_np1 = advance(method, model, &a_n, &half, &kappa_half, dt);
/// ```
///
/// * `Direct`: A = a_base + dt [kappa A + A kappa^T - f_R(A)/lambda] at A = a_eval (eqs. 10-11):
///   the predictor-corrector is then the explicit midpoint rule, second order, but nothing keeps A
///   positive definite.
/// * `Log`: [`logconf::advance_log`], Strang splitting of King & Lind eqs. (29)-(33): relaxation
///   dt/2, convection of Psi = log A over dt with the rate at a_eval, relaxation dt/2. Second order
///   in the same predictor-corrector, SPD by construction for any step, and for FENE-P/FENE-CR
///   tr(A) < L^2 after every step.
///
/// A single-stage scheme (King & Lind's ISPH integrates the stress once per step) calls
/// `advance(method, model, &a_n, &a_n, &kappa_n, dt)`: first order in time, as in the paper.
/// The ALE term u_ps . grad(Psi) of a shifting scheme is not included (see [`logconf`]).
#[inline]
pub fn advance<const N: usize, R: Rheology>(
    method: ConformationMethod,
    model: &R,
    a_base: &Tensor<N>,
    a_eval: &Tensor<N>,
    kappa: &Tensor<N>,
    dt: f64,
) -> Tensor<N>
where
    Const<N>: Dim,
{
    match method {
        // A scheme resolves `Auto` before it gets here; unresolved it means the direct update.
        ConformationMethod::Direct | ConformationMethod::Auto => {
            let mut a = a_base + conformation_rate(model, a_eval, kappa) * dt;
            // Keep exact symmetry against round-off.
            for k in 0..N {
                for l in k + 1..N {
                    let off = 0.5 * (a[(k, l)] + a[(l, k)]);
                    a[(k, l)] = off;
                    a[(l, k)] = off;
                }
            }
            a
        }
        ConformationMethod::Log => logconf::advance_log(model, a_base, a_eval, kappa, dt),
    }
}

/// Every model, resolved once from the configuration. Schemes are instantiated per variant
/// through [`dispatch_rheology!`](crate::dispatch_rheology), so hot loops see a concrete type. UCM has no variant of its
/// own: it is Oldroyd-B with beta = 0 (King & Lind section II), same f_S and f_R.
#[derive(Debug, Clone)]
pub enum AnyRheology {
    Newtonian(Newtonian),
    OldroydB(OldroydB),
    FeneP(FeneP),
    FeneCr(FeneCr),
    PttLinear(PttLinear),
    PttExponential(PttExponential),
    Giesekus(Giesekus),
    Cross(Cross),
}

/// Run `$body` with `$m` bound to the concrete model inside an [`AnyRheology`].
#[macro_export]
macro_rules! dispatch_rheology {
    ($any:expr, $m:ident => $body:expr) => {
        match $any {
            $crate::rheology::AnyRheology::Newtonian($m) => $body,
            $crate::rheology::AnyRheology::OldroydB($m) => $body,
            $crate::rheology::AnyRheology::FeneP($m) => $body,
            $crate::rheology::AnyRheology::FeneCr($m) => $body,
            $crate::rheology::AnyRheology::PttLinear($m) => $body,
            $crate::rheology::AnyRheology::PttExponential($m) => $body,
            $crate::rheology::AnyRheology::Giesekus($m) => $body,
            $crate::rheology::AnyRheology::Cross($m) => $body,
        }
    };
}
