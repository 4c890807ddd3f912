//! Particle storage: structure of arrays, one typed array per field.

use crate::{Mat2, Vec2};
use serde::{Deserialize, Serialize};

/// The fluid particles: everything the time integration evolves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Fluid {
    /// Positions \[m\].
    pub x: Vec<Vec2>,
    /// Velocities [m/s].
    pub v: Vec<Vec2>,
    /// Densities [kg/m3].
    pub rho: Vec<f64>,
    /// Conformation tensors A (symmetric). Empty for models without one (Newtonian, Cross):
    /// a Newtonian scene allocates no tensor arrays.
    pub conf: Vec<Mat2>,
    /// Mass of every particle [kg per m depth] (uniform lattice: rho0 dx^2).
    pub mass: f64,
}

impl Fluid {
    pub fn len(&self) -> usize {
        self.x.len()
    }
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}
