//! Particle storage: structure of arrays, one typed array per field.

use crate::dim::{Tensor, Vector};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Elements per parallel task of a copy (a copy is a few instructions per element).
const COPY_CHUNK: usize = 4096;

/// `dst.copy_from_slice(src)` on all threads (a copy does not depend on the order it runs in).
pub fn copy_par<T: Copy + Send + Sync>(dst: &mut [T], src: &[T]) {
    // One task's worth: a plain copy, without handing it to the pool.
    if src.len() <= COPY_CHUNK {
        dst.copy_from_slice(src);
        return;
    }
    dst.par_chunks_mut(COPY_CHUNK)
        .zip(src.par_chunks(COPY_CHUNK))
        .for_each(|(d, s)| d.copy_from_slice(s));
}

/// `dst` becomes a copy of `src` on all threads, its allocation kept (no new vector per step).
pub fn assign_par<T: Copy + Send + Sync>(dst: &mut Vec<T>, src: &[T]) {
    dst.clear();
    if src.len() <= COPY_CHUNK {
        dst.extend_from_slice(src);
    } else {
        dst.par_extend(src.par_iter().with_min_len(COPY_CHUNK).copied());
    }
}

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

    /// `self` becomes a copy of `src`, array by array on all threads into the kept
    /// allocations: `clone_from` without the single-thread copies.
    pub fn assign_par(&mut self, src: &Self) {
        assign_par(&mut self.x, &src.x);
        assign_par(&mut self.v, &src.v);
        assign_par(&mut self.rho, &src.rho);
        assign_par(&mut self.conf, &src.conf);
        self.mass = src.mass;
    }
}
