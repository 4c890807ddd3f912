//! FENE-CR (King & Lind 2021 Table I): f_S = f_R = (A - I) / (1 - tr(A)/L^2), with the
//! extensibility L^2 (`fene_L2`). As L^2 -> infinity it becomes Oldroyd-B.

use super::logconf::fene_relaxation;
use super::Rheology;
use crate::Mat2;

#[derive(Debug, Clone)]
pub struct FeneCr {
    /// Solvent viscosity beta eta0 [Pa s].
    pub eta_s: f64,
    /// Polymer viscosity (1 - beta) eta0 [Pa s].
    pub eta_p: f64,
    /// Relaxation time [s].
    pub lambda: f64,
    /// Extensibility L^2.
    pub l2: f64,
}

impl FeneCr {
    pub fn new(eta0: f64, beta: f64, lambda: f64, l2: f64) -> Self {
        Self {
            eta_s: beta * eta0,
            eta_p: (1.0 - beta) * eta0,
            lambda,
            l2,
        }
    }

    /// Spring factor 1 / (1 - tr(A)/L^2).
    #[inline]
    pub fn spring(&self, a: &Mat2) -> f64 {
        1.0 / (1.0 - a.trace() / self.l2)
    }
}

impl Rheology for FeneCr {
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
        (a - Mat2::identity()) * self.spring(a)
    }
    #[inline]
    fn relax(&self, a: &Mat2) -> Mat2 {
        (a - Mat2::identity()) * self.spring(a)
    }
    /// Eq. (32) with alpha_R = 1/(1 - tr(A)/L^2) frozen at `a_coef`, beta_R = 1, safeguarded to
    /// stay below tr(A) = L^2 ([`super::logconf::fene_relaxation`]).
    #[inline]
    fn relaxation_step(&self, a: &Mat2, a_coef: &Mat2, dt: f64) -> Mat2 {
        fene_relaxation(a, a_coef, self.l2, dt / self.lambda, |f| (f, 1.0))
    }
}
