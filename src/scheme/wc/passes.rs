//! The two gather passes of a weakly compressible rate evaluation (see the parent module), one
//! code for every dimension N.
//!
//! **How the hot loops are laid out** (the profile and the gain of each step are in
//! docs/benchmarks.md). A neighbour's data is read from packed records rather than from six
//! arrays of nalgebra structs: pass 1 from a [`Rec`] (48 bytes in 2D, one 64-byte line in 3D),
//! pass 2 from a [`Rec2`] (one line in 2D, three in 3D; prefetched a few pairs ahead, since the
//! cached indices say which one comes next). Each particle's sigma/rho^2 is computed once, when
//! its record is packed, not once per pair. The
//! per-pair branches whose outcome is data-dependent (inside the support or in the skin; an
//! approaching or receding pair in the artificial viscosity; a zero artificial stress; a fluid
//! or a virtual neighbour) are gone: pass 1 compacts the candidates inside the support without a
//! branch and then runs the kernel over the compacted slots; pass 2 takes the pairs with fluid
//! neighbours and those with virtual ones as two runs (a list is ascending and virtual particles
//! come after the fluid, so the split is one binary search); the artificial viscosity selects
//! its value by a mask. Loop-invariant choices (periodic domain, Morris' Laplacian, artificial
//! stress, Hessian sums) are const generic parameters, so each variant is its own straight loop.
//! Every operation and every sum is the same as in the plain pair-by-pair form over nalgebra's
//! types, in the same order: the results are bitwise those of that form (in 2D the goldens, in
//! 3D runs compared output file by output file).

use super::*;
use crate::neighbors::Domain;

/// What pass 1 reads of a neighbour: position, velocity, density and volume m/rho; 48 bytes in
/// 2D, 64 in 3D. Kept apart from what pass 2 reads ([`Rec2`]): a particle's neighbours are
/// mostly runs of consecutive indices (lattice rows), so with 48-byte records four neighbours
/// share three cache lines, where one record of both passes' values (128 bytes in 2D) took a
/// line per neighbour and doubled the footprint each pass walks through.
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub(crate) struct Rec<const N: usize> {
    pub x: Vector<N>,
    pub v: Vector<N>,
    pub rho: f64,
    pub vol: f64,
}

impl<const N: usize> Default for Rec<N> {
    fn default() -> Self {
        Self {
            x: Vector::zeros(),
            v: Vector::zeros(),
            rho: 0.0,
            vol: 0.0,
        }
    }
}

/// What pass 2 reads of a neighbour: sigma/rho^2 (Fang 2006 eq. 27) and the artificial stress
/// R: one 64-byte line in 2D, three in 3D. (Morris' term also reads the neighbour's [`Rec`] and
/// its viscosity.)
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct Rec2<const N: usize> {
    pub s: Tensor<N>,
    pub r: Tensor<N>,
}

impl<const N: usize> Default for Rec2<N> {
    fn default() -> Self {
        Self {
            s: Tensor::zeros(),
            r: Tensor::zeros(),
        }
    }
}

/// x_a - x_b: the plain difference, or with `PERIODIC` at the nearest image
/// ([`Domain::delta`], the same operations).
#[inline(always)]
fn delta<const N: usize, const PERIODIC: bool>(
    a: &Vector<N>,
    b: &Vector<N>,
    dom: &Domain,
) -> Vector<N> {
    if PERIODIC {
        dom.delta(a, b)
    } else {
        a - b
    }
}

/// |d|^2 summed axis by axis from x (nalgebra's `norm_squared` for N = 2 and 3, in the same
/// order).
#[inline(always)]
fn norm2<const N: usize>(d: &Vector<N>) -> f64 {
    let mut r2 = d[0] * d[0];
    for a in 1..N {
        r2 += d[a] * d[a];
    }
    r2
}

/// How many pairs ahead pass 2 prefetches a neighbour's record (x86_64 only: the prefetch
/// intrinsic is that architecture's).
#[cfg(target_arch = "x86_64")]
const PREFETCH: usize = 8;

/// The loop-invariant numbers of the pair terms.
struct PairConst {
    alpha: f64,
    beta: f64,
    c: f64,
    h: f64,
    eta2: f64,
    dom: Domain,
}

/// The pass-2 pair term of particle i (record `ri`) with neighbour j (`rj`), kernel gradient
/// `grad`, artificial viscosity `pi` and artificial stress factor `f` (both from pass 1): exactly
/// the operations of Fang eq. (27) with eqs. (30)-(38) (and Morris' term) as the operators write
/// them over nalgebra's types, component by component. Pi_ij enters the diagonal only (the
/// plain form's `- I Pi_ij` subtracts exact zeros elsewhere: Pi_ij >= +0). Without Morris' term
/// it reads only j's [`Rec2`].
#[inline(always)]
fn pair_term<const N: usize, const PERIODIC: bool, const MORRIS: bool, const ART: bool>(
    (ri, si, mui): (&Rec<N>, &Rec2<N>, f64),
    (rj, sj, muj): (&Rec<N>, &Rec2<N>, f64),
    grad: &Vector<N>,
    pi: f64,
    f: f64,
    k: &PairConst,
) -> Vector<N> {
    let mut t = si.s + sj.s;
    for a in 0..N {
        t[(a, a)] -= pi;
    }
    if ART {
        // A zero R_i + R_j adds exact zeros: no branch needed.
        t += (si.r + sj.r) * f;
    }
    // t * grad in the order of nalgebra's matrix-vector product (column by column).
    let mut c = t.column(0) * grad[0];
    for b in 1..N {
        c += t.column(b) * grad[b];
    }
    if MORRIS {
        let xij = delta::<N, PERIODIC>(&ri.x, &rj.x, &k.dom);
        let vij = ri.v - rj.v;
        let r2 = xij.norm_squared();
        c += stress::morris_pair(&vij, &xij, grad, mui + muj, ri.rho, rj.rho, r2, k.eta2);
    }
    c
}

/// Pass 1's per-slot arithmetic over one particle's compacted pairs: on entry `g` holds x_ij,
/// `pi` v_ij . x_ij and `f` the mean density; on exit grad_i W_ij, Pi_ij (Fang 2006 eqs. 31-33)
/// and f_ij^n = `factor(W_ij, r^2)` (eq. 39; r^2 itself without artificial stress). r^2 is
/// recomputed from x_ij by the compaction's own expression, so W needs no array of its own
/// (nothing after this loop reads it): one stream fewer per pair in the pair cache. Element by
/// element the operations of the kernel and of [`artificial::viscosity`], so the values are
/// bitwise those computed pair by pair.
#[inline(always)]
fn pair_kernels<const N: usize, K: Kernel<N>, F: Fn(f64, f64) -> f64>(
    kernel: &K,
    factor: F,
    k: &PairConst,
    (g, pi, f): (&mut [Vector<N>], &mut [f64], &mut [f64]),
) {
    let n = g.len().min(pi.len()).min(f.len());
    let (g, pi, f) = (&mut g[..n], &mut pi[..n], &mut f[..n]);
    for s in 0..n {
        let r2 = norm2(&g[s]);
        let (wv, dw_r) = kernel.w_and_dw_over_r(r2.sqrt());
        g[s] *= dw_r;
        pi[s] = artificial::viscosity_of_dot(k.alpha, k.beta, k.h, k.c, f[s], pi[s], r2);
        f[s] = factor(wv, r2);
    }
}

/// [`pair_kernels`] compiled for AVX2 (4 lanes of f64: the divisions and square roots of the
/// loop, which bound it, run 4 at a time). AVX2 changes no result: IEEE division and square
/// root are correctly rounded in every lane, and Rust never fuses a multiply and an add, so
/// the values are bitwise those of the portable build.
///
/// # Safety
/// Only on a CPU with AVX2 (checked once per pass by the caller).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn pair_kernels_avx2<const N: usize, K: Kernel<N>, F: Fn(f64, f64) -> f64>(
    kernel: &K,
    factor: F,
    k: &PairConst,
    slots: (&mut [Vector<N>], &mut [f64], &mut [f64]),
) {
    pair_kernels(kernel, factor, k, slots)
}

/// [`pair_kernels`] with the artificial stress factor of `art` (None: off), in the AVX2 build
/// when `avx2` (the CPU has it), else the portable one. The choices are made here, once per
/// particle, so that each loop is straight.
#[inline(always)]
fn pair_kernels_dispatch<const N: usize, K: Kernel<N>>(
    kernel: &K,
    art: Option<&ArtificialStress>,
    k: &PairConst,
    slots: (&mut [Vector<N>], &mut [f64], &mut [f64]),
    avx2: bool,
) {
    macro_rules! run {
        ($factor:expr) => {{
            #[cfg(target_arch = "x86_64")]
            if avx2 {
                // SAFETY: the caller checked that the CPU has AVX2 (`has_avx2`).
                unsafe { pair_kernels_avx2(kernel, $factor, k, slots) }
            } else {
                pair_kernels(kernel, $factor, k, slots)
            }
            #[cfg(not(target_arch = "x86_64"))]
            {
                let _ = avx2;
                pair_kernels(kernel, $factor, k, slots)
            }
        }};
    }
    match art {
        None => run!(|_w: f64, r2: f64| r2),
        Some(a) if a.is_fang() => run!(|w: f64, _r2: f64| a.fang_pair_factor(w)),
        Some(a) => run!(|_w: f64, r2: f64| a.ren_pair_factor(r2)),
    }
}

/// Whether this CPU runs the AVX2 build of the pair loops.
fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The passes of every dimension: packed records and the AVX2 build of the pair loops.
impl<K: Kernel<N>, R: Rheology, const N: usize> WcCore<K, R, N>
where
    Const<N>: Dim + WcSpace<N>,
{
    /// Records of every particle (fluid and virtual): positions, velocities, densities and
    /// volumes, for pass 1. The walls' velocities must be in `all_v`.
    pub(super) fn pack_kinematics(&mut self) {
        let n = self.all_x.len();
        self.rec.resize(n, Rec::default());
        let (ax, av, arho, avol) = (&self.all_x, &self.all_v, &self.all_rho, &self.all_vol);
        self.rec
            .par_iter_mut()
            .with_min_len(MIN_TASK_LIGHT)
            .enumerate()
            .for_each(|(i, r)| {
                r.x = ax[i];
                r.v = av[i];
                r.rho = arho[i];
                r.vol = avol[i];
            });
    }

    /// Records of pass 2: sigma/rho^2 and the artificial stress, once pass 1 and the walls have
    /// filled them.
    pub(super) fn pack_stresses(&mut self) {
        let n = self.all_x.len();
        self.rec2.resize(n, Rec2::default());
        let (asig, aart, arho) = (&self.all_sigma, &self.all_art, &self.all_rho);
        self.rec2
            .par_iter_mut()
            .with_min_len(MIN_TASK_LIGHT)
            .enumerate()
            .for_each(|(i, r)| {
                let rho = arho[i];
                r.s = asig[i] / (rho * rho);
                r.r = aart[i];
            });
    }

    /// Pass 1 (a gather): velocity gradient (Fang eq. 23), continuity (eq. 26), stresses, and
    /// the kernel values of every pair inside the support, cached for pass 2.
    pub(super) fn pass1_packed(&mut self, fl: &Fluid<N>) {
        match (self.p.domain.is_periodic(), self.art.needs_hessian()) {
            (false, false) => self.pass1_impl::<false, false>(fl),
            (false, true) => self.pass1_impl::<false, true>(fl),
            (true, false) => self.pass1_impl::<true, false>(fl),
            (true, true) => self.pass1_impl::<true, true>(fl),
        }
    }

    fn pass1_impl<const PERIODIC: bool, const HESS: bool>(&mut self, fl: &Fluid<N>) {
        let nf = fl.len();
        let mass = fl.mass;
        self.pairs.resize_for(&self.nlist);
        self.kappa.resize(nf, Tensor::zeros());
        self.drho.resize(nf, 0.0);
        let (kernel, model, p, art, evss) =
            (&self.kernel, &self.model, &self.p, &self.art, self.evss);
        let (rec, tau_p, cont_v) = (&self.rec, &self.tau_p, &self.cont_v);
        let nlist = &self.nlist;
        let h = kernel.h();
        let cst = PairConst {
            alpha: p.alpha,
            beta: p.beta,
            c: p.eos.c,
            h,
            eta2: MORRIS_ETA2 * h * h,
            dom: self.p.domain,
        };
        let dom = cst.dom;
        let r2max = kernel.radius().powi(2);
        let laplacian = self.laplacian();
        let art_on = art.is_on();
        let avx2 = has_avx2();
        // Every index in the lists is below the number of points they were built over, which is
        // the number of records: the hot loops below read records unchecked.
        assert!(nlist.points() <= rec.len() && rec.len() == self.all_x.len());
        // One parallel task per run of TASK particles, a plain loop over its particles inside:
        // the per-particle work is then one loop body the compiler inlines, not a closure called
        // per particle through rayon's iterator adapters (callgrind: 50 instructions of calls
        // and spills per particle and pass), and the pair arrays are split per run, not per
        // particle. Every particle still writes only its own slots: the result is the same for
        // any thread count and any task size.
        const TASK: usize = MIN_TASK;
        let js = nlist.split_chunks_mut(&mut self.pairs.j, TASK);
        let gs = nlist.split_chunks_mut(&mut self.pairs.grad, TASK);
        let ps = nlist.split_chunks_mut(&mut self.pairs.pi, TASK);
        let fs = nlist.split_chunks_mut(&mut self.pairs.f, TASK);
        (
            (js, gs, ps, fs),
            self.pairs.len.par_chunks_mut(TASK),
            self.kappa.par_chunks_mut(TASK),
            self.drho.par_chunks_mut(TASK),
            self.all_sigma[..nf].par_chunks_mut(TASK),
            self.all_art[..nf].par_chunks_mut(TASK),
            self.all_hess[..nf].par_chunks_mut(TASK),
            self.all_mu[..nf].par_chunks_mut(TASK),
        )
            .into_par_iter()
            .enumerate()
            .for_each(
                |(c, ((js, gs, ps, fs), lens, kappa, drho, sigma, arts, hesss, mus))| {
                    let first = c * TASK;
                    let base = nlist.offset(first);
                    for at in 0..lens.len() {
                        let i = first + at;
                        let ri = &rec[i];
                        let (xi, vi) = (ri.x, ri.v);
                        // Locals, not loads through the closure's captures: the loop's stores might
                        // alias them as far as the compiler knows, and it reloaded both every
                        // candidate.
                        let (rhoi, r2max) = (ri.rho, r2max);
                        // Compact the candidates inside the support (other than i) to the front of
                        // i's slots, without a branch per candidate (a fifth of the list is skin):
                        // x_ij, r^2, v_ij . x_ij and the mean density, all that the artificial
                        // viscosity needs.
                        let list = nlist.of(i);
                        let n = list.len();
                        let slots = nlist.offset(i) - base..nlist.offset(i + 1) - base;
                        let (js, gs, ps, fs) = (
                            &mut js[slots.clone()],
                            &mut gs[slots.clone()],
                            &mut ps[slots.clone()],
                            &mut fs[slots],
                        );
                        assert!(js.len() >= n && gs.len() >= n && ps.len() >= n && fs.len() >= n);
                        let mut k = 0;
                        for &j in list {
                            // SAFETY: j < nlist.points() <= rec.len() (asserted before the pass)
                            // and k <= the number of candidates seen so far < n <= each slot
                            // array's length (asserted above). Unchecked, the loop has no bounds
                            // tests between a neighbour's load and its stores.
                            let rj = unsafe { rec.get_unchecked(j as usize) };
                            let xij = delta::<N, PERIODIC>(&xi, &rj.x, &dom);
                            let r2 = norm2(&xij);
                            unsafe {
                                *js.get_unchecked_mut(k) = j;
                                *gs.get_unchecked_mut(k) = xij;
                                *ps.get_unchecked_mut(k) = (vi - rj.v).dot(&xij);
                                *fs.get_unchecked_mut(k) = 0.5 * (rhoi + rj.rho);
                            }
                            k += ((r2 < r2max) & (j as usize != i)) as usize;
                        }
                        // Then, slot by slot with no neighbour data and no branch (a loop the
                        // compiler vectorises in the AVX2 build): the kernel, the artificial
                        // viscosity and the artificial stress factor.
                        let slots = (&mut gs[..k], &mut ps[..k], &mut fs[..k]);
                        pair_kernels_dispatch(kernel, art_on.then_some(art), &cst, slots, avx2);
                        let mut kin = Kinematics::default();
                        let mut hess = Tensor::zeros();
                        for (j, grad) in js[..k].iter().zip(&gs[..k]) {
                            let ju = *j as usize;
                            // SAFETY: every j is from i's list (see above).
                            let rj = unsafe { rec.get_unchecked(ju) };
                            let vij = vi - rj.v;
                            // A virtual neighbour's continuity term takes its own velocity
                            // (`cont_v`). The branch flips once per particle at most: a list
                            // is ascending and the virtual particles come after the fluid.
                            if ju < nf {
                                kin.add_pair(&vij, grad, rj.vol);
                            } else {
                                let cij = vi - cont_v[ju - nf];
                                kin.add_pair_split(&vij, &cij, grad, rj.vol);
                            }
                            if HESS {
                                let xij = delta::<N, PERIODIC>(&xi, &rj.x, &dom);
                                let r2 = norm2(&xij);
                                hess += artificial::kernel_hessian(kernel, &xij, r2);
                            }
                        }
                        lens[at] = k as u32;
                        kappa[at] = kin.kappa;
                        drho[at] = kin.continuity * mass;
                        hesss[at] = hess;
                        let tau = R::ELASTIC.then(|| &tau_p[i]);
                        (mus[at], sigma[at], arts[at]) = particle_stress(
                            model, p, art, &evss, laplacian, &kin.kappa, tau, fl.rho[i], &hess,
                        );
                    }
                },
            );
    }

    /// Pass 2 (a gather over the cached pairs): momentum (Fang eq. 27, Ren eq. 21) with
    /// artificial viscosity (Fang eqs. 30-37, Ren eq. 19) and artificial stress (Fang eq. 38,
    /// Ren eq. 20a); with EVSS, Morris' viscous Laplacian.
    pub(super) fn pass2_packed(&mut self, fl: &Fluid<N>) {
        let periodic = self.p.domain.is_periodic();
        match (periodic, self.laplacian(), self.art.is_on()) {
            (false, false, false) => self.pass2_impl::<false, false, false>(fl),
            (false, false, true) => self.pass2_impl::<false, false, true>(fl),
            (false, true, false) => self.pass2_impl::<false, true, false>(fl),
            (false, true, true) => self.pass2_impl::<false, true, true>(fl),
            (true, false, false) => self.pass2_impl::<true, false, false>(fl),
            (true, false, true) => self.pass2_impl::<true, false, true>(fl),
            (true, true, false) => self.pass2_impl::<true, true, false>(fl),
            (true, true, true) => self.pass2_impl::<true, true, true>(fl),
        }
    }

    fn pass2_impl<const PERIODIC: bool, const MORRIS: bool, const ART: bool>(
        &mut self,
        fl: &Fluid<N>,
    ) {
        let nf = fl.len();
        let mass = fl.mass;
        self.acc.resize(nf, Vector::zeros());
        self.wall_acc.resize(nf, Vector::zeros());
        // Each wall's virtual particles end at these indices (ascending, wall by wall).
        let wall_ends: Vec<u32> = self.wall_ranges.iter().map(|r| r.end as u32).collect();
        let nw = wall_ends.len();
        self.wall_split
            .resize(if nw > 1 { nf * nw } else { nf }, Vector::zeros());
        {
            let p = &self.p;
            let (rec, rec2, amu) = (&self.rec, &self.rec2, &self.all_mu);
            let (pairs, nlist) = (&self.pairs, &self.nlist);
            // The cached indices are entries of the lists (pass 1 copies them), all below the
            // number of points the lists were built over: the loop reads records unchecked.
            assert!(nlist.points() <= rec2.len());
            assert!(rec.len() == rec2.len() && amu.len() == rec2.len());
            let h = self.kernel.h();
            let eta2 = MORRIS_ETA2 * h * h;
            let cst = PairConst {
                alpha: p.alpha,
                beta: p.beta,
                c: p.eos.c,
                h,
                eta2,
                dom: p.domain,
            };
            // One task per run of TASK particles, a plain loop inside (as in pass 1).
            const TASK: usize = MIN_TASK;
            let per = if nw > 1 { nw } else { 1 };
            (
                self.acc.par_chunks_mut(TASK),
                self.wall_acc.par_chunks_mut(TASK),
                self.wall_split.par_chunks_mut(TASK * per),
            )
                .into_par_iter()
                .enumerate()
                .for_each(|(c, (accs, walls, splits))| {
                    for (at, (acc_i, wall_i)) in accs.iter_mut().zip(walls.iter_mut()).enumerate() {
                        let i = c * TASK + at;
                        let split_i = &mut splits[at * per..(at + 1) * per];
                        let ri = (&rec[i], &rec2[i], amu[i]);
                        let range = pairs.range(nlist, i);
                        let (jj, gg, pp, ff) = (
                            &pairs.j[range.clone()],
                            &pairs.grad[range.clone()],
                            &pairs.pi[range.clone()],
                            &pairs.f[range],
                        );
                        // Ascending lists: fluid neighbours first, then virtual ones.
                        let split = jj.partition_point(|&j| (j as usize) < nf);
                        let n = jj.len();
                        assert!(gg.len() == n && pp.len() == n && ff.len() == n);
                        let sum = |from: usize, to: usize| {
                            let mut a = Vector::<N>::zeros();
                            for k in from..to {
                                // Ask for the record PREFETCH pairs ahead: the cached indices say
                                // which, the hardware prefetchers cannot guess it, and the profile
                                // put pass 2's time on the load of the neighbour's record.
                                #[cfg(target_arch = "x86_64")]
                                if k + PREFETCH < to {
                                    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
                                    // SAFETY: k + PREFETCH < to <= n and the index < the records'
                                    // length, as below; a prefetch never faults anyway. Every
                                    // line of the record (one in 2D, three in 3D).
                                    #[allow(unused_unsafe)]
                                    unsafe {
                                        let j = *jj.get_unchecked(k + PREFETCH) as usize;
                                        let at = rec2.as_ptr().add(j) as *const i8;
                                        for line in 0..std::mem::size_of::<Rec2<N>>() / 64 {
                                            _mm_prefetch::<_MM_HINT_T0>(at.add(64 * line));
                                        }
                                    }
                                }
                                // SAFETY: k < n, the length of every slot array (asserted above),
                                // and every cached index < the records' length (asserted before
                                // the pass).
                                let (rj, g, pi, f) = unsafe {
                                    let j = *jj.get_unchecked(k) as usize;
                                    (
                                        (
                                            rec.get_unchecked(j),
                                            rec2.get_unchecked(j),
                                            *amu.get_unchecked(j),
                                        ),
                                        *gg.get_unchecked(k),
                                        *pp.get_unchecked(k),
                                        *ff.get_unchecked(k),
                                    )
                                };
                                a += pair_term::<N, PERIODIC, MORRIS, ART>(ri, rj, &g, pi, f, &cst);
                            }
                            a
                        };
                        book_particle(
                            sum,
                            jj,
                            split,
                            &wall_ends,
                            mass,
                            p.gravity,
                            (acc_i, wall_i, split_i),
                        );
                    }
                });
        }
    }
}

#[cfg(test)]
#[path = "passes_tests.rs"]
mod tests;
