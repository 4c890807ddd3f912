//! Oldroyd-B: f_S = f_R = A - I (King & Lind Table I); Fang 2006 eqs. (5)-(9) with
//! lambda1 = lambda, lambda2 = beta lambda. UCM is the case beta = 0.

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
}
