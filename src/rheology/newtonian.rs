//! Newtonian fluid: constant viscosity, no polymer stress, no conformation tensor.

use super::Rheology;
use crate::dim::{Const, Dim, Tensor};

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
    inelastic_common!();
    #[inline]
    fn solvent_viscosity<const N: usize>(&self, _kappa: &Tensor<N>) -> f64 {
        self.viscosity
    }
    fn max_viscosity(&self) -> f64 {
        self.viscosity
    }
}
