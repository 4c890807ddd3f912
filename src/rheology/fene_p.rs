//! FENE-P (King & Lind 2021 Table I): f_S = f_R = A / (1 - tr(A)/L^2) - I, with the
//! extensibility L^2 (`fene_L2`, > N = tr I so that the rest state exists). tr(A) < L^2 always
//! holds for the exact dynamics: the spring factor 1/(1 - tr(A)/L^2) diverges as the chains
//! approach full extension.
//!
//! This is the unnormalised form of the table, whose rest state (f_R = 0) is
//! A = L^2/(L^2 + N) I in N dimensions, not I; see [`Rheology::rest_conformation`].

use super::logconf::fene_relaxation;
use super::{Polymer, Rheology};
use crate::dim::{Const, Dim, Tensor};

#[derive(Debug, Clone)]
pub struct FeneP {
    /// Solvent and polymer viscosities and relaxation time.
    pub p: Polymer,
    /// Extensibility L^2.
    pub l2: f64,
}

impl FeneP {
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

impl Rheology for FeneP {
    polymer_common!();
    #[inline]
    fn strain<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        a * self.spring(a) - Tensor::<N>::identity()
    }
    #[inline]
    fn relax<const N: usize>(&self, a: &Tensor<N>) -> Tensor<N> {
        a * self.spring(a) - Tensor::<N>::identity()
    }
    /// Eq. (32) with alpha_R = 1, beta_R = 1/(1 - tr(A)/L^2) frozen at `a_coef`, safeguarded to
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
        fene_relaxation(a, a_coef, self.l2, dt / self.p.lambda, |f| (1.0, f))
    }
    fn rest_conformation<const N: usize>(&self) -> Tensor<N>
    where
        Const<N>: Dim,
    {
        Tensor::<N>::identity() * (self.l2 / (self.l2 + N as f64))
    }
}
