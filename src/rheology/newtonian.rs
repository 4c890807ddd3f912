//! Newtonian fluid: constant viscosity, no polymer stress, no conformation tensor.

use super::Rheology;
use crate::Mat2;

#[derive(Debug, Clone)]
pub struct Newtonian {
    /// Dynamic viscosity [Pa s].
    pub viscosity: f64,
}

impl Newtonian {
    pub fn new(viscosity: f64) -> Self {
        Self { viscosity }
    }
}

impl Rheology for Newtonian {
    const ELASTIC: bool = false;
    #[inline]
    fn solvent_viscosity(&self, _kappa: &Mat2) -> f64 {
        self.viscosity
    }
    fn max_viscosity(&self) -> f64 {
        self.viscosity
    }
    fn modulus(&self) -> f64 {
        0.0
    }
    fn relaxation_time(&self) -> f64 {
        f64::INFINITY
    }
    #[inline]
    fn strain(&self, _a: &Mat2) -> Mat2 {
        Mat2::zeros()
    }
    #[inline]
    fn relax(&self, _a: &Mat2) -> Mat2 {
        Mat2::zeros()
    }
    #[inline]
    fn relaxation_step(&self, a: &Mat2, _a_coef: &Mat2, _dt: f64) -> Mat2 {
        *a
    }
}
