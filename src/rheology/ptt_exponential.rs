//! Exponential Phan-Thien-Tanner (King & Lind 2021 Table I): f_S = A - I,
//! f_R = exp[eps tr(A - I)](A - I), with `ptt_epsilon` = eps. eps = 0 is Oldroyd-B.

use super::logconf::quasi_analytic_relaxation;
use super::{Polymer, Rheology};
use crate::Mat2;

#[derive(Debug, Clone)]
pub struct PttExponential {
    /// Solvent and polymer viscosities and relaxation time.
    pub p: Polymer,
    /// Extensibility parameter eps.
    pub eps: f64,
}

impl PttExponential {
    pub fn new(eta0: f64, beta: f64, lambda: f64, eps: f64) -> Self {
        Self {
            p: Polymer::new(eta0, beta, lambda),
            eps,
        }
    }

    /// Relaxation factor exp[eps tr(A - I)].
    #[inline]
    pub fn factor(&self, a: &Mat2) -> f64 {
        (self.eps * (a.trace() - 2.0)).exp()
    }
}

impl Rheology for PttExponential {
    polymer_common!();
    #[inline]
    fn strain(&self, a: &Mat2) -> Mat2 {
        a - Mat2::identity()
    }
    #[inline]
    fn relax(&self, a: &Mat2) -> Mat2 {
        (a - Mat2::identity()) * self.factor(a)
    }
    /// Eq. (32) with alpha_R = exp[eps tr(A - I)] frozen at `a_coef`, beta_R = 1.
    #[inline]
    fn relaxation_step(&self, a: &Mat2, a_coef: &Mat2, dt: f64) -> Mat2 {
        quasi_analytic_relaxation(a, self.factor(a_coef), 1.0, dt / self.p.lambda)
    }
}
