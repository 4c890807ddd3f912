//! Kernel values of the pairs inside the support, aligned with a CSR neighbour list: neighbour
//! index, grad_i W_ij, the artificial viscosity and the artificial stress factor, computed once per rate evaluation and read by the later passes
//! (SPHinXsys's habit of caching W and grad W once per stage). Particle i's slots start at the
//! list's offset of i; `len[i]` of them are used (the rest of i's list lies in the skin).

use crate::neighbors::NeighborList;
use crate::Vec2;

#[derive(Debug, Clone, Default)]
pub struct PairCache {
    pub j: Vec<u32>,
    pub grad: Vec<Vec2>,
    /// The artificial viscosity Pi_ij (Fang 2006 eqs. 31-33): it depends only on positions,
    /// velocities and densities, all known in the first pass.
    pub pi: Vec<f64>,
    /// The artificial stress factor f_ij^n (Fang 2006 eq. 39, Ren 2015 eq. 20a), when on.
    pub f: Vec<f64>,
    pub len: Vec<u32>,
}

impl PairCache {
    /// Size the arrays for `list` (one slot per stored pair, one length per query particle).
    pub fn resize_for(&mut self, list: &NeighborList) {
        let n = list.pairs();
        self.j.resize(n, 0);
        self.grad.resize(n, Vec2::zeros());
        self.pi.resize(n, 0.0);
        self.f.resize(n, 0.0);
        self.len.resize(list.len(), 0);
    }

    /// The cached slots of particle i: `start..start + len[i]`.
    #[inline]
    pub fn range(&self, list: &NeighborList, i: usize) -> std::ops::Range<usize> {
        let start = list.offset(i);
        start..start + self.len[i] as usize
    }
}
