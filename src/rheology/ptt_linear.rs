//! Linear Phan-Thien-Tanner (King & Lind 2021 Table I): f_S = A - I,
//! f_R = [1 + eps tr(A - I)](A - I), with `ptt_epsilon` = eps. eps = 0 is Oldroyd-B.

use super::{Polymer, Rheology};
use crate::dim::{Const, Dim, Tensor};

#[derive(Debug, Clone)]
pub struct PttLinear {
    /// Solvent and polymer viscosities and relaxation time.
    pub p: Polymer,
    /// Extensibility parameter eps.
    pub eps: f64,
}

impl PttLinear {
    pub fn new(eta0: f64, beta: f64, lambda: f64, eps: f64) -> Self {
        Self {
            p: Polymer::new(eta0, beta, lambda),
            eps,
        }
    }

    /// Relaxation factor 1 + eps tr(A - I).
    #[inline]
    pub fn factor<const N: usize>(&self, a: &Tensor<N>) -> f64 {
        1.0 + self.eps * (a.trace() - N as f64)
    }
}

impl Rheology for PttLinear {
    polymer_common!();
    ptt_common!();
}
