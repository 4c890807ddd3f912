//! Cross shear-thinning generalized Newtonian fluid (Ren, Lu & Jiang 2015 eqs. 4-7):
//! tau = 2 mu(gamma_dot) d (eq. 4), d = (kappa + kappa^T)/2 (eq. 5),
//! mu = eta_inf + (eta0 - eta_inf) / (1 + (K gamma_dot)^m) (eq. 6, written with dynamic
//! viscosities mu = rho nu), gamma_dot = [2 tr(d^2)]^{1/2} (eq. 7).
//!
//! `viscosity` is the zero-shear viscosity eta0, `cross_viscosity_inf` eta_inf, `cross_K` K [s],
//! `cross_m` m. There is no polymer and no conformation tensor (`ELASTIC = false`): the whole
//! viscous stress goes through [`Rheology::solvent_viscosity`].

use super::Rheology;
use crate::dim::{Const, Dim, Tensor};

/// Local shear rate gamma_dot = [2 tr(d^2)]^{1/2} with d = (kappa + kappa^T)/2 (Ren 2015 eq. 7).
/// In simple shear v_x = g y it is |g|.
#[inline]
pub fn shear_rate<const N: usize>(kappa: &Tensor<N>) -> f64 {
    // tr(d^2) = sum_k d_kk^2 + 2 sum_{k < l} d_kl^2
    let (mut diagonal, mut off) = (0.0, 0.0);
    for k in 0..N {
        diagonal += kappa[(k, k)] * kappa[(k, k)];
        for l in k + 1..N {
            let d = 0.5 * (kappa[(k, l)] + kappa[(l, k)]);
            off += d * d;
        }
    }
    (2.0 * (diagonal + 2.0 * off)).sqrt()
}

#[derive(Debug, Clone)]
pub struct Cross {
    /// Zero-shear viscosity eta0 [Pa s].
    pub eta0: f64,
    /// Infinite-shear viscosity eta_inf [Pa s].
    pub eta_inf: f64,
    /// Time constant K \[s\].
    pub k: f64,
    /// Exponent m.
    pub m: f64,
}

impl Cross {
    pub fn new(eta0: f64, eta_inf: f64, k: f64, m: f64) -> Self {
        Self {
            eta0,
            eta_inf,
            k,
            m,
        }
    }

    /// mu(gamma_dot), Ren 2015 eq. (6).
    #[inline]
    pub fn viscosity_at(&self, gamma_dot: f64) -> f64 {
        self.eta_inf + (self.eta0 - self.eta_inf) / (1.0 + (self.k * gamma_dot).powf(self.m))
    }
}

impl Rheology for Cross {
    inelastic_common!();
    #[inline]
    fn solvent_viscosity<const N: usize>(&self, kappa: &Tensor<N>) -> f64 {
        self.viscosity_at(shear_rate(kappa))
    }
    /// mu lies between eta_inf and eta0 (eq. 6 is monotone in gamma_dot).
    fn max_viscosity(&self) -> f64 {
        self.eta0.max(self.eta_inf)
    }
}
