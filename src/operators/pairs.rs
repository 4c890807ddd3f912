//! Kernel values of the pairs of a CSR neighbour list, computed once per rate evaluation (or
//! step) and read by the later passes (SPHinXsys's habit of caching W and grad W once per stage).
//! Particle i's slots start at the list's offset of i; `len[i]` of them are used. Two layouts:
//! * compact (the weakly compressible schemes, [`PairCache::resize_for`]): the pairs inside the
//!   support other than the self pair, moved to the front of i's slots with their indices in
//!   `j` (the rest of i's list lies in the skin); `grad`, `pi` and `f` are filled;
//! * full (the incompressible scheme, [`PairCache::size_full`]): slot k of i is the list's
//!   k-th entry, the self pair included with zeros, so data aligned with the list (the linear
//!   systems' coefficients) share its indexing; `grad` and `morris` are filled, `j` is unused
//!   (the list holds the indices).

use crate::dim::Vector;
use crate::neighbors::NeighborList;

/// The cache for pairs in N dimensions (`PairCache` alone: two).
#[derive(Debug, Clone)]
pub struct PairCache<const N: usize = 2> {
    /// Neighbour index of each used slot (compact layout).
    pub j: Vec<u32>,
    /// grad_i W_ij (zero for the self pair in the full layout).
    pub grad: Vec<Vector<N>>,
    /// The artificial viscosity Pi_ij (Fang 2006 eqs. 31-33): it depends only on positions,
    /// velocities and densities, all known in the first pass.
    pub pi: Vec<f64>,
    /// The artificial stress factor f_ij^n (Fang 2006 eq. 39, Ren 2015 eq. 20a), when on.
    pub f: Vec<f64>,
    /// Morris et al. 1997's Laplacian coefficient `2 V_j (1/r) dW/dr` (King & Lind 2021 eq.
    /// (21), uncorrected kernel gradient; zero for the self pair), full layout.
    pub morris: Vec<f64>,
    pub len: Vec<u32>,
}

impl<const N: usize> Default for PairCache<N> {
    fn default() -> Self {
        Self {
            j: Vec::new(),
            grad: Vec::new(),
            pi: Vec::new(),
            f: Vec::new(),
            morris: Vec::new(),
            len: Vec::new(),
        }
    }
}

impl<const N: usize> PairCache<N> {
    /// Size the arrays for `list` in the compact layout (one slot per stored pair, one length
    /// per query particle).
    pub fn resize_for(&mut self, list: &NeighborList) {
        let n = list.pairs();
        self.j.resize(n, 0);
        self.grad.resize(n, Vector::zeros());
        self.pi.resize(n, 0.0);
        self.f.resize(n, 0.0);
        self.len.resize(list.len(), 0);
    }

    /// Zero `grad` and `morris` for every pair of `list` in the full layout, every slot of a
    /// particle used.
    pub fn reset_full(&mut self, list: &NeighborList) {
        self.grad.clear();
        self.morris.clear();
        self.size_full(list);
    }

    /// Size `grad` and `morris` for every pair of `list` in the full layout, every slot of a
    /// particle used, keeping what the slots held (only slots beyond the old length are
    /// zeroed): for a caller that writes every slot, the self pair's zeros included. Clearing
    /// and refilling the arrays ([`PairCache::reset_full`]) writes them all on one thread, 24
    /// bytes a pair in 2D (about 12 MB a step at 10^4 ISPH particles), before the parallel pass
    /// writes them again.
    pub fn size_full(&mut self, list: &NeighborList) {
        let n = list.pairs();
        self.grad.resize(n, Vector::zeros());
        self.morris.resize(n, 0.0);
        self.len.clear();
        self.len
            .extend((0..list.len()).map(|i| list.of(i).len() as u32));
    }

    /// The cached slots of particle i: `start..start + len[i]`.
    #[inline]
    pub fn range(&self, list: &NeighborList, i: usize) -> std::ops::Range<usize> {
        let start = list.offset(i);
        start..start + self.len[i] as usize
    }

    /// `s_i = sum_j V grad_i W_ij` over particle i's slots for a uniform volume `vol`, summed in
    /// slot order: zero in a full lattice support, about `-n / delta` where a free surface
    /// truncates it (the weight of the free-surface terms of King & Lind 2021's scheme).
    #[inline]
    pub fn gradient_sum(&self, list: &NeighborList, i: usize, vol: f64) -> Vector<N> {
        self.grad[self.range(list, i)]
            .iter()
            .fold(Vector::zeros(), |a, g| a + g * vol)
    }
}
