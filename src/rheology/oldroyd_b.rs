//! Oldroyd-B: f_S = f_R = A - I (King & Lind Table I); Fang 2006 eqs. (5)-(9) with
//! lambda1 = lambda, lambda2 = beta lambda. UCM is the case beta = 0 (King & Lind section II):
//! same strain and relaxation functions, so it is this type built with beta = 0 rather than a
//! copy of it.

use super::logconf::quasi_analytic_relaxation;
use super::{Polymer, Rheology};
use crate::dim::{Const, Dim, Tensor};

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
    fn strain<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        a - Tensor::<N>::identity()
    }
    #[inline]
    fn relax<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        a - Tensor::<N>::identity()
    }
    /// Eq. (32) with alpha_R = beta_R = 1: the exact solution of the relaxation sub-problem.
    #[inline]
    fn relaxation_step<const N: usize>(
        &self,
        a: &Tensor<N>,
        _a_coef: &Tensor<N>,
        dt: f64,
    ) -> Tensor<N>
    where
        Const<N>: Dim,
    {
        quasi_analytic_relaxation(a, 1.0, 1.0, dt / self.p.lambda)
    }
}
