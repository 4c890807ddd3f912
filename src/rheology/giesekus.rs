//! Giesekus (King & Lind 2021 Table I): f_S = A - I,
//! f_R = alpha A^2 + (1 - 2 alpha) A - (1 - alpha) I, with the mobility `giesekus_alpha` = alpha,
//! 0 <= alpha <= 1/2 (King & Lind section II). alpha = 0 is Oldroyd-B.
//!
//! f_R is not of the form alpha_R (beta_R A - I), so eq. (32) does not apply; King & Lind use the
//! explicit step (33). We solve the relaxation sub-problem exactly instead
//! ([`super::logconf::giesekus_relaxation`]), which keeps A positive definite for any step.

use super::logconf::giesekus_relaxation;
use super::Rheology;
use crate::Mat2;

#[derive(Debug, Clone)]
pub struct Giesekus {
    /// Solvent viscosity beta eta0 [Pa s].
    pub eta_s: f64,
    /// Polymer viscosity (1 - beta) eta0 [Pa s].
    pub eta_p: f64,
    /// Relaxation time [s].
    pub lambda: f64,
    /// Mobility parameter alpha.
    pub alpha: f64,
}

impl Giesekus {
    pub fn new(eta0: f64, beta: f64, lambda: f64, alpha: f64) -> Self {
        Self {
            eta_s: beta * eta0,
            eta_p: (1.0 - beta) * eta0,
            lambda,
            alpha,
        }
    }
}

impl Rheology for Giesekus {
    const ELASTIC: bool = true;
    #[inline]
    fn solvent_viscosity(&self, _kappa: &Mat2) -> f64 {
        self.eta_s
    }
    fn max_viscosity(&self) -> f64 {
        self.eta_s + self.eta_p
    }
    #[inline]
    fn modulus(&self) -> f64 {
        self.eta_p / self.lambda
    }
    fn relaxation_time(&self) -> f64 {
        self.lambda
    }
    #[inline]
    fn strain(&self, a: &Mat2) -> Mat2 {
        a - Mat2::identity()
    }
    #[inline]
    fn relax(&self, a: &Mat2) -> Mat2 {
        let al = self.alpha;
        a * a * al + a * (1.0 - 2.0 * al) - Mat2::identity() * (1.0 - al)
    }
    /// Exact solution of eq. (29b) (no frozen coefficients: `a_coef` is unused).
    #[inline]
    fn relaxation_step(&self, a: &Mat2, _a_coef: &Mat2, dt: f64) -> Mat2 {
        giesekus_relaxation(a, self.alpha, dt / self.lambda)
    }
}
