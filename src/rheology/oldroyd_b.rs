//! Oldroyd-B: f_S = f_R = A - I (King & Lind Table I); Fang 2006 eqs. (5)-(9) with
//! lambda1 = lambda, lambda2 = beta lambda. UCM is the case beta = 0 (King & Lind section II):
//! same strain and relaxation functions, so it is this type built with beta = 0 rather than a
//! copy of it.

use super::logconf::quasi_analytic_relaxation;
use super::{Polymer, Rheology};
use crate::Mat2;

#[derive(Debug, Clone)]
pub struct OldroydB {
    /// Solvent and polymer viscosities and relaxation time.
    pub p: Polymer,
}

impl OldroydB {
    pub fn new(eta0: f64, beta: f64, lambda: f64) -> Self {
        Self {
            p: Polymer::new(eta0, beta, lambda),
        }
    }
}

impl Rheology for OldroydB {
    polymer_common!();
    #[inline]
    fn strain(&self, a: &Mat2) -> Mat2 {
        a - Mat2::identity()
    }
    #[inline]
    fn relax(&self, a: &Mat2) -> Mat2 {
        a - Mat2::identity()
    }
    /// Eq. (32) with alpha_R = beta_R = 1: the exact solution of the relaxation sub-problem.
    #[inline]
    fn relaxation_step(&self, a: &Mat2, _a_coef: &Mat2, dt: f64) -> Mat2 {
        quasi_analytic_relaxation(a, 1.0, 1.0, dt / self.p.lambda)
    }
}
