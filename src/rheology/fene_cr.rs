//! FENE-CR (King & Lind 2021 Table I): f_S = f_R = (A - I) / (1 - tr(A)/L^2), with the
//! extensibility L^2 (`fene_L2`). As L^2 -> infinity it becomes Oldroyd-B.

use super::logconf::fene_relaxation;
use super::{Polymer, Rheology};
use crate::dim::{Const, Dim, Tensor};

#[derive(Debug, Clone)]
pub struct FeneCr {
    /// Solvent and polymer viscosities and relaxation time.
    pub p: Polymer,
    /// Extensibility L^2.
    pub l2: f64,
}

impl FeneCr {
    pub fn new(eta0: f64, beta: f64, lambda: f64, l2: f64) -> Self {
        Self {
            p: Polymer::new(eta0, beta, lambda),
            l2,
        }
    }

    /// Spring factor 1 / (1 - tr(A)/L^2).
    #[inline]
    pub fn spring<const N: usize>(&self, a: &Tensor<N>) -> f64 {
        1.0 / (1.0 - a.trace() / self.l2)
    }
}

impl Rheology for FeneCr {
    polymer_common!();
    #[inline]
    fn strain<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        (a - Tensor::<N>::identity()) * self.spring(a)
    }
    #[inline]
    fn relax<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        (a - Tensor::<N>::identity()) * self.spring(a)
    }
    /// Eq. (32) with alpha_R = 1/(1 - tr(A)/L^2) frozen at `a_coef`, beta_R = 1, safeguarded to
    /// stay below tr(A) = L^2 ([`super::logconf::fene_relaxation`]).
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
        fene_relaxation(a, a_coef, self.l2, dt / self.p.lambda, |f| (f, 1.0))
    }
}
