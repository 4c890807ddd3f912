//! Giesekus (King & Lind 2021 Table I): f_S = A - I,
//! f_R = alpha A^2 + (1 - 2 alpha) A - (1 - alpha) I, with the mobility `giesekus_alpha` = alpha,
//! 0 <= alpha <= 1/2 (King & Lind section II). alpha = 0 is Oldroyd-B.
//!
//! f_R is not of the form alpha_R (beta_R A - I), so eq. (32) does not apply; King & Lind use the
//! explicit step (33). We solve the relaxation sub-problem exactly instead
//! ([`super::logconf::giesekus_relaxation`]), which keeps A positive definite for any step.

use super::logconf::giesekus_relaxation;
use super::{Polymer, Rheology};
use crate::dim::{Const, Dim, Tensor};

#[derive(Debug, Clone)]
pub struct Giesekus {
    /// Solvent and polymer viscosities and relaxation time.
    pub p: Polymer,
    /// Mobility parameter alpha.
    pub alpha: f64,
}

impl Giesekus {
    pub fn new(eta0: f64, beta: f64, lambda: f64, alpha: f64) -> Self {
        Self {
            p: Polymer::new(eta0, beta, lambda),
            alpha,
        }
    }
}

impl Rheology for Giesekus {
    polymer_common!();
    #[inline]
    fn strain<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        a - Tensor::<N>::identity()
    }
    #[inline]
    fn relax<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        let al = self.alpha;
        a * a * al + a * (1.0 - 2.0 * al) - Tensor::<N>::identity() * (1.0 - al)
    }
    /// Exact solution of eq. (29b) (no frozen coefficients: `a_coef` is unused).
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
        giesekus_relaxation(a, self.alpha, dt / self.p.lambda)
    }
}
