//! Particle storage: structure of arrays, one typed array per field.

use crate::dim::{Tensor, Vector};
use serde::{Deserialize, Serialize};

/// The fluid particles in N space dimensions: everything the time integration evolves. `Fluid`
/// alone is the two-dimensional one; a saved two-dimensional state reads the same bytes whatever
/// N means elsewhere (serde sees the same field types).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fluid<const N: usize = 2> {
    /// Positions \[m\].
    pub x: Vec<Vector<N>>,
    /// Velocities [m/s].
    pub v: Vec<Vector<N>>,
    /// Densities [kg/m3].
    pub rho: Vec<f64>,
    /// Conformation tensors A (symmetric). Empty for models without one (Newtonian, Cross):
    /// a Newtonian scene allocates no tensor arrays.
    pub conf: Vec<Tensor<N>>,
    /// Mass of every particle [kg per m depth] in 2D (uniform lattice: rho0 dx^2), \[kg\] in
    /// 3D (rho0 dx^3).
    pub mass: f64,
}

impl<const N: usize> Default for Fluid<N> {
    fn default() -> Self {
        Self {
            x: Vec::new(),
            v: Vec::new(),
            rho: Vec::new(),
            conf: Vec::new(),
            mass: 0.0,
        }
    }
}

impl<const N: usize> Fluid<N> {
    pub fn len(&self) -> usize {
        self.x.len()
    }
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}
