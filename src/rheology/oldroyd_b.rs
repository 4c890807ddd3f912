//! Oldroyd-B: f_S = f_R = A - I (King & Lind Table I); Fang 2006 eqs. (5)-(9) with
//! lambda1 = lambda, lambda2 = beta lambda. UCM is the case beta = 0 (King & Lind section II):
//! same strain and relaxation functions, so it is this type built with beta = 0 rather than a
//! copy of it.

use super::logconf::quasi_analytic_relaxation;
use super::Rheology;
use crate::Mat2;

#[derive(Debug, Clone)]
pub struct OldroydB {
    /// Solvent viscosity beta eta0 [Pa s].
    pub eta_s: f64,
    /// Polymer viscosity (1 - beta) eta0 [Pa s].
    pub eta_p: f64,
    /// Relaxation time [s].
    pub lambda: f64,
}

impl OldroydB {
    pub fn new(eta0: f64, beta: f64, lambda: f64) -> Self {
        Self {
            eta_s: beta * eta0,
            eta_p: (1.0 - beta) * eta0,
            lambda,
        }
    }
}

impl Rheology for OldroydB {
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
        a - Mat2::identity()
    }
    /// Eq. (32) with alpha_R = beta_R = 1: the exact solution of the relaxation sub-problem.
    #[inline]
    fn relaxation_step(&self, a: &Mat2, _a_coef: &Mat2, dt: f64) -> Mat2 {
        quasi_analytic_relaxation(a, 1.0, 1.0, dt / self.lambda)
    }
}
