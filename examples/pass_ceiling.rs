//! The measured ceiling of Fang's two-evaluation WCSPH step on this core (issue 16): the pair
//! arithmetic of pass 1 and pass 2 in the most favourable form this machine offers, timed over
//! the real pairs of a scene, side by side with the solver stepping the same scene.
//!
//! Ideal means: every neighbour's operands already sit in contiguous structure-of-arrays f64
//! slots (no gather, no index, no compaction: as if the pair data had been laid out for free),
//! padded per particle to whole 4-lane vectors, and the arithmetic runs in explicit AVX2 + FMA
//! (`std::arch`, 4 lanes of f64) with the fewest divisions the terms allow: per pair one square
//! root (r, for the cubic spline of Fang 2006 eq. 22) and ONE division, from which 1/r (the
//! kernel's outer piece, grad W = x_ij W'/r, eq. 21) and 1/((r^2 + 0.01 h^2)^2 rho_ij) (the
//! artificial viscosity, eqs. 31-33, its two divisions folded) are both recovered by products.
//! Sums run in 4 lane-wise partial sums. Pass 1 per pair: r^2, the support mask, sqrt, both
//! kernel pieces and their select, grad W, Pi_ij with its approach mask, f_ij^4 (eq. 39), the
//! velocity gradient (eq. 23, four sums) and continuity (eq. 26); it stores grad W, Pi and f for
//! pass 2. Pass 2 per pair: Fang eq. (27) with eqs. (30) and (38): (sigma_i/rho_i^2 +
//! sigma_j/rho_j^2 - Pi I + f (R_i + R_j)) grad W, two sums. Nothing else of a step is counted
//! (the per-particle stress and artificial stress, the equation of state, the wall particles,
//! the predictor-corrector updates, the neighbour lists, the health check): so the figure is a
//! floor that no implementation of the two-evaluation step can beat here, not an estimate.
//!
//! Variants, each over the pairs of the scene's state (its fluid particles only):
//! * `exact`: pass 1 and pass 2 over the pairs inside the support (r < 2h), the least work;
//! * `skin`: pass 1 over the list with the solver's skin (r < 2.25h, masked lanes), pass 2 over
//!   the pairs inside the support (what a list reused across steps implies);
//! * `resident`: `exact` repeated over the first 16 particles' pairs, which stay in L1/L2: the
//!   arithmetic alone, without the memory stream of the pre-gathered operands;
//! * `scalar`: `exact` in plain f64 Rust with the same operations (portable build, no FMA):
//!   what the vector units add;
//! * `gather`: `exact` (and `gather skin`: the skin list in pass 1) with the neighbours'
//!   operands loaded by index from per-particle arrays with AVX2's `vgatherdpd`, 4 lanes (6
//!   gathers per 4 pairs in pass 1, 8 in pass 2): what a vectorised pass over today's lists with
//!   today's memory order could reach;
//! * `runs`: both passes over each particle's neighbours taken as runs of consecutive indices
//!   (a row of the lattice, or of a grid-sorted order, is one run), read with plain unaligned
//!   4-lane loads and no gather; the lanes past a run's end are masked by the distance test:
//!   the structural "reorder along the grid, load candidates as contiguous runs" step, ideal;
//! * `f32`: the gathered passes in f32 (8 lanes, `vgatherdps`), the sums in f64;
//!
//! and `solver`: the library's own step of the same scene on one thread, CPU ns per
//! particle-step. Rounds alternate; each figure is the minimum CPU time over the rounds.
//!
//! `cargo run --release --example pass_ceiling -- SCENE.toml [ROUNDS] [SOLVER_STEPS]`
//! (x86-64 with AVX2 and FMA only; elsewhere it says so and exits). Results and what they mean:
//! docs/benchmarks.md, issue 16's fifth session.

// Particle and component indices run over several parallel arrays at once: plain index loops
// read more clearly here than zips of five iterators.
#![allow(clippy::needless_range_loop)]

#[cfg(target_arch = "x86_64")]
mod ceiling {
    use std::time::Instant;
    use viscosph::neighbors::{CellGrid, Domain, NeighborList};
    use viscosph::scene::SceneConfig;
    use viscosph::simulation::Simulation;
    use viscosph::Vec2;

    fn cpu_seconds() -> f64 {
        let stat = std::fs::read_to_string("/proc/self/stat").expect("/proc/self/stat");
        let rest = &stat[stat.rfind(')').expect("stat format") + 2..];
        let f: Vec<&str> = rest.split_whitespace().collect();
        (f[11].parse::<u64>().expect("utime") + f[12].parse::<u64>().expect("stime")) as f64 / 100.0
    }

    /// The numbers the pair terms need (cubic spline, artificial viscosity and stress).
    #[derive(Clone, Copy)]
    struct Consts {
        h: f64,
        inv_h: f64,
        w0: f64,
        r2max: f64,
        eta: f64,
        alpha_c: f64,
        beta_h: f64,
        inv_w_d0: f64,
    }

    /// Pass-1 operands per slot (x_ij, v_ij, rho_j, V_j) and pass-1 results, per particle padded to
    /// a multiple of 4 slots; pass-2 operands per slot (sigma_j/rho_j^2 and R_j, 4 components each).
    struct Pairs {
        off: Vec<usize>,
        dx: Vec<f64>,
        dy: Vec<f64>,
        dvx: Vec<f64>,
        dvy: Vec<f64>,
        rhoj: Vec<f64>,
        volj: Vec<f64>,
        sj: [Vec<f64>; 4],
        rj: [Vec<f64>; 4],
        /// Neighbour index per slot (padding: the far dummy particle n), for the gather variants.
        idx: Vec<i32>,
        /// Real (unpadded) pairs.
        real: usize,
    }

    impl Pairs {
        fn slots(&self) -> usize {
            self.dx.len()
        }
    }

    /// Per-particle operands as structure-of-arrays, with a far dummy particle at index n (the
    /// padding slots' index): what the gather variants load by the neighbour's index.
    struct Soa {
        x: Vec<f64>,
        y: Vec<f64>,
        vx: Vec<f64>,
        vy: Vec<f64>,
        rho: Vec<f64>,
        vol: Vec<f64>,
        s: [Vec<f64>; 4],
        r: [Vec<f64>; 4],
    }

    impl Soa {
        fn new(x: &[Vec2], v: &[Vec2], rho: &[f64], mass: f64) -> Self {
            let mut q = Soa {
                x: x.iter().map(|p| p.x).chain([1e6; 4]).collect(),
                y: x.iter().map(|p| p.y).chain([0.0; 4]).collect(),
                vx: v.iter().map(|p| p.x).chain([0.0; 4]).collect(),
                vy: v.iter().map(|p| p.y).chain([0.0; 4]).collect(),
                rho: rho.iter().copied().chain([1000.0; 4]).collect(),
                vol: rho.iter().map(|r| mass / r).chain([0.0; 4]).collect(),
                s: Default::default(),
                r: Default::default(),
            };
            for (k, p) in x.iter().enumerate() {
                let st = stress_of(p.y);
                let r2 = rho[k] * rho[k];
                for c in 0..4 {
                    q.s[c].push(st[c] / r2);
                    q.r[c].push(if c == 1 || c == 2 { 1e-3 * st[c] } else { 0.0 });
                }
            }
            for c in 0..4 {
                q.s[c].extend([0.0; 4]);
                q.r[c].extend([0.0; 4]);
            }
            q
        }
    }

    /// A made-up but physical stress at height y: hydrostatic plus a shear.
    fn stress_of(y: f64) -> [f64; 4] {
        [-1000.0 * y, 3.0 * y, 3.0 * y, -1000.0 * y + 1.0]
    }

    /// A particle's neighbours as runs of consecutive indices (the scene's lattice order makes a
    /// row of neighbours one run), each rounded up to whole 4-lane vectors: what a layout sorted
    /// along the grid lets the passes read with plain vector loads. The lanes past a run's end
    /// hold particles outside the list (else the run would go on), hence outside the support:
    /// the distance mask drops them.
    struct Runs {
        /// Runs of particle i: `runs[roff[i]..roff[i + 1]]`, each (first index, lanes).
        roff: Vec<usize>,
        runs: Vec<(usize, usize)>,
        /// Particle i's slots (sum of its runs' lanes) start at `soff[i]`.
        soff: Vec<usize>,
    }

    impl Runs {
        fn new(p: &Pairs, n: usize) -> Self {
            let mut r = Runs {
                roff: vec![0],
                runs: Vec::new(),
                soff: vec![0],
            };
            let mut slots = 0;
            for i in 0..n {
                let list: Vec<usize> = p.idx[p.off[i]..p.off[i + 1]]
                    .iter()
                    .map(|&j| j as usize)
                    .filter(|&j| j < n)
                    .chain([i])
                    .collect::<std::collections::BTreeSet<_>>()
                    .into_iter()
                    .collect();
                let mut k = 0;
                while k < list.len() {
                    let mut e = k + 1;
                    while e < list.len() && list[e] == list[e - 1] + 1 {
                        e += 1;
                    }
                    // Whole vectors; runs of up to 8 take two, so the inner loop trip count is
                    // nearly always 2 (a predictable branch: variable counts cost more).
                    let lanes = (e - k).div_ceil(4).max(2) * 4;
                    r.runs.push((list[k], lanes));
                    slots += lanes;
                    k = e;
                }
                r.roff.push(r.runs.len());
                r.soff.push(slots);
            }
            r
        }
        fn slots(&self) -> usize {
            *self.soff.last().expect("non-empty")
        }
    }

    /// The ideal passes over [`Runs`]: pass 1 loads the neighbours' operands from `q` with plain
    /// 4-lane loads (no gather), as [`pass1_avx2`] otherwise; pass 2 likewise for sigma_j/rho_j^2
    /// and R_j.
    ///
    /// # Safety
    /// As [`pass1_avx2`]; `q`'s arrays extend 3 dummies past the last particle.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn runs_avx2(rn: &Runs, q: &Soa, c: &Consts, w: &Parts, o: &mut Out, parts: usize) {
        use std::arch::x86_64::*;
        let set = |v: f64| _mm256_set1_pd(v);
        let (zero, one, two, half) = (set(0.0), set(1.0), set(2.0), set(0.5));
        let (r2max, inv_h, eta) = (set(c.r2max), set(c.inv_h), set(c.eta));
        let (w0, c23, c15) = (set(c.w0), set(2.0 / 3.0), set(1.5));
        let d_in_k = set(c.w0 * c.inv_h * c.inv_h);
        let w_out_k = set(c.w0 / 6.0);
        let d_out_k = set(-0.5 * c.w0 * c.inv_h);
        let (hh, alpha_c, beta_h, inv_w_d0) =
            (set(c.h), set(c.alpha_c), set(c.beta_h), set(c.inv_w_d0));
        let hsum = |v: __m256d| {
            let mut a = [0.0; 4];
            _mm256_storeu_pd(a.as_mut_ptr(), v);
            (a[0] + a[1]) + (a[2] + a[3])
        };
        for i in 0..parts {
            let rhoi = set(q.rho[i]);
            let (xi, yi, vxi, vyi) = (set(q.x[i]), set(q.y[i]), set(q.vx[i]), set(q.vy[i]));
            let (mut k00, mut k01, mut k10, mut k11, mut cont) = (zero, zero, zero, zero, zero);
            let mut s = rn.soff[i];
            for &(start, lanes) in &rn.runs[rn.roff[i]..rn.roff[i + 1]] {
                let mut j = start;
                while j < start + lanes {
                    let ld = |v: &Vec<f64>| _mm256_loadu_pd(v.as_ptr().add(j));
                    let dx = _mm256_sub_pd(xi, ld(&q.x));
                    let dy = _mm256_sub_pd(yi, ld(&q.y));
                    let dvx = _mm256_sub_pd(vxi, ld(&q.vx));
                    let dvy = _mm256_sub_pd(vyi, ld(&q.vy));
                    let (rhoj, volj) = (ld(&q.rho), ld(&q.vol));
                    let r2 = _mm256_fmadd_pd(dx, dx, _mm256_mul_pd(dy, dy));
                    let m = _mm256_and_pd(
                        _mm256_cmp_pd::<_CMP_LT_OQ>(r2, r2max),
                        _mm256_cmp_pd::<_CMP_GT_OQ>(r2, zero),
                    );
                    let r = _mm256_sqrt_pd(r2);
                    let qq = _mm256_mul_pd(r, inv_h);
                    let t = _mm256_sub_pd(two, qq);
                    let q2 = _mm256_mul_pd(qq, qq);
                    let w_in =
                        _mm256_mul_pd(w0, _mm256_fmadd_pd(q2, _mm256_fmsub_pd(half, qq, one), c23));
                    let d_in = _mm256_mul_pd(d_in_k, _mm256_fmsub_pd(c15, qq, two));
                    let t2 = _mm256_mul_pd(t, t);
                    let w_out = _mm256_mul_pd(w_out_k, _mm256_mul_pd(t2, t));
                    let rhom = _mm256_mul_pd(half, _mm256_add_pd(rhoi, rhoj));
                    let vx = _mm256_fmadd_pd(dvx, dx, _mm256_mul_pd(dvy, dy));
                    let d = _mm256_add_pd(r2, eta);
                    let dd = _mm256_mul_pd(_mm256_mul_pd(d, d), rhom);
                    let inv = _mm256_div_pd(one, _mm256_mul_pd(r, dd));
                    let inv_r = _mm256_mul_pd(inv, dd);
                    let inv_dd = _mm256_mul_pd(inv, r);
                    let d_out = _mm256_mul_pd(d_out_k, _mm256_mul_pd(t2, inv_r));
                    let pi = _mm256_mul_pd(
                        _mm256_mul_pd(hh, vx),
                        _mm256_mul_pd(
                            _mm256_fmsub_pd(beta_h, vx, _mm256_mul_pd(alpha_c, d)),
                            inv_dd,
                        ),
                    );
                    let pi =
                        _mm256_and_pd(pi, _mm256_and_pd(m, _mm256_cmp_pd::<_CMP_LT_OQ>(vx, zero)));
                    let inner = _mm256_cmp_pd::<_CMP_LT_OQ>(qq, one);
                    let w = _mm256_and_pd(_mm256_blendv_pd(w_out, w_in, inner), m);
                    let dwr = _mm256_and_pd(_mm256_blendv_pd(d_out, d_in, inner), m);
                    let gx = _mm256_mul_pd(dx, dwr);
                    let gy = _mm256_mul_pd(dy, dwr);
                    let f = _mm256_mul_pd(w, inv_w_d0);
                    let f2 = _mm256_mul_pd(f, f);
                    _mm256_storeu_pd(o.gx.as_mut_ptr().add(s), gx);
                    _mm256_storeu_pd(o.gy.as_mut_ptr().add(s), gy);
                    _mm256_storeu_pd(o.pi.as_mut_ptr().add(s), pi);
                    _mm256_storeu_pd(o.f.as_mut_ptr().add(s), _mm256_mul_pd(f2, f2));
                    let (ux, uy) = (_mm256_mul_pd(dvx, volj), _mm256_mul_pd(dvy, volj));
                    k00 = _mm256_fnmadd_pd(ux, gx, k00);
                    k01 = _mm256_fnmadd_pd(ux, gy, k01);
                    k10 = _mm256_fnmadd_pd(uy, gx, k10);
                    k11 = _mm256_fnmadd_pd(uy, gy, k11);
                    cont = _mm256_fmadd_pd(dvx, gx, _mm256_fmadd_pd(dvy, gy, cont));
                    j += 4;
                    s += 4;
                }
            }
            o.kin[i] = [hsum(k00), hsum(k01), hsum(k10), hsum(k11), hsum(cont)];
        }
        // Pass 2 (after every particle's pass 1, as the scheme needs sigma_j).
        for i in 0..parts {
            let si = w.s[i].map(|v| _mm256_set1_pd(v));
            let ri = w.r[i].map(|v| _mm256_set1_pd(v));
            let (mut ax, mut ay) = (zero, zero);
            let mut s = rn.soff[i];
            for &(start, lanes) in &rn.runs[rn.roff[i]..rn.roff[i + 1]] {
                let mut j = start;
                while j < start + lanes {
                    let lo = |v: &Vec<f64>| _mm256_loadu_pd(v.as_ptr().add(s));
                    let ld = |v: &Vec<f64>| _mm256_loadu_pd(v.as_ptr().add(j));
                    let (gx, gy, pi, f) = (lo(&o.gx), lo(&o.gy), lo(&o.pi), lo(&o.f));
                    let t = |c: usize| {
                        let base = _mm256_add_pd(si[c], ld(&q.s[c]));
                        let base = if c == 0 || c == 3 {
                            _mm256_sub_pd(base, pi)
                        } else {
                            base
                        };
                        _mm256_fmadd_pd(_mm256_add_pd(ri[c], ld(&q.r[c])), f, base)
                    };
                    let (t0, t1, t2, t3) = (t(0), t(1), t(2), t(3));
                    ax = _mm256_fmadd_pd(t0, gx, _mm256_fmadd_pd(t2, gy, ax));
                    ay = _mm256_fmadd_pd(t1, gx, _mm256_fmadd_pd(t3, gy, ay));
                    j += 4;
                    s += 4;
                }
            }
            o.acc[i] = [hsum(ax), hsum(ay)];
        }
    }

    /// [`Soa`] in f32, for the f32 variant.
    struct Soa32 {
        x: Vec<f32>,
        y: Vec<f32>,
        vx: Vec<f32>,
        vy: Vec<f32>,
        rho: Vec<f32>,
        vol: Vec<f32>,
        s: [Vec<f32>; 4],
        r: [Vec<f32>; 4],
    }

    impl Soa32 {
        fn new(q: &Soa) -> Self {
            let f = |v: &Vec<f64>| v.iter().map(|&a| a as f32).collect::<Vec<f32>>();
            Soa32 {
                x: f(&q.x),
                y: f(&q.y),
                vx: f(&q.vx),
                vy: f(&q.vy),
                rho: f(&q.rho),
                vol: f(&q.vol),
                s: [f(&q.s[0]), f(&q.s[1]), f(&q.s[2]), f(&q.s[3])],
                r: [f(&q.r[0]), f(&q.r[1]), f(&q.r[2]), f(&q.r[3])],
            }
        }
    }

    /// Pass-1 results of the f32 variant.
    struct Out32 {
        gx: Vec<f32>,
        gy: Vec<f32>,
        pi: Vec<f32>,
        f: Vec<f32>,
        kin: Vec<[f64; 5]>,
        acc: Vec<[f64; 2]>,
    }

    impl Out32 {
        fn new(slots: usize, n: usize) -> Self {
            Self {
                gx: vec![0.0; slots],
                gy: vec![0.0; slots],
                pi: vec![0.0; slots],
                f: vec![0.0; slots],
                kin: vec![[0.0; 5]; n],
                acc: vec![[0.0; 2]; n],
            }
        }
    }

    /// Add the 8 f32 lanes of `v` to the 4 f64 lanes of `acc` (f64 sums of f32 pair terms).
    #[inline(always)]
    unsafe fn add_wide(
        acc: std::arch::x86_64::__m256d,
        v: std::arch::x86_64::__m256,
    ) -> std::arch::x86_64::__m256d {
        use std::arch::x86_64::*;
        let lo = _mm256_cvtps_pd(_mm256_castps256_ps128(v));
        let hi = _mm256_cvtps_pd(_mm256_extractf128_ps::<1>(v));
        _mm256_add_pd(acc, _mm256_add_pd(lo, hi))
    }

    #[inline(always)]
    unsafe fn hsum_pd(v: std::arch::x86_64::__m256d) -> f64 {
        let mut a = [0.0; 4];
        std::arch::x86_64::_mm256_storeu_pd(a.as_mut_ptr(), v);
        (a[0] + a[1]) + (a[2] + a[3])
    }

    /// Pass 1 with f32 pair geometry and arithmetic, 8 lanes, operands gathered by index
    /// (`vgatherdps`), the sums in f64; otherwise as [`pass1_avx2`].
    ///
    /// # Safety
    /// As [`pass1_avx2`], slots in multiples of 8.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn pass1_f32(p: &Pairs, q: &Soa32, c: &Consts, o: &mut Out32, parts: usize) {
        use std::arch::x86_64::*;
        let set = |v: f64| _mm256_set1_ps(v as f32);
        let (zero, one, two, half) = (set(0.0), set(1.0), set(2.0), set(0.5));
        let (r2max, inv_h, eta) = (set(c.r2max), set(c.inv_h), set(c.eta));
        let (w0, c23, c15) = (set(c.w0), set(2.0 / 3.0), set(1.5));
        let d_in_k = set(c.w0 * c.inv_h * c.inv_h);
        let w_out_k = set(c.w0 / 6.0);
        let d_out_k = set(-0.5 * c.w0 * c.inv_h);
        let (hh, alpha_c, beta_h, inv_w_d0) =
            (set(c.h), set(c.alpha_c), set(c.beta_h), set(c.inv_w_d0));
        let zd = _mm256_setzero_pd();
        for i in 0..parts {
            let rhoi = _mm256_set1_ps(q.rho[i]);
            let (xi, yi) = (_mm256_set1_ps(q.x[i]), _mm256_set1_ps(q.y[i]));
            let (vxi, vyi) = (_mm256_set1_ps(q.vx[i]), _mm256_set1_ps(q.vy[i]));
            let (mut k00, mut k01, mut k10, mut k11, mut cont) = (zd, zd, zd, zd, zd);
            let mut s = p.off[i];
            while s < p.off[i + 1] {
                let vi = _mm256_loadu_si256(p.idx.as_ptr().add(s) as *const __m256i);
                let g = |v: &Vec<f32>| _mm256_i32gather_ps::<4>(v.as_ptr(), vi);
                let dx = _mm256_sub_ps(xi, g(&q.x));
                let dy = _mm256_sub_ps(yi, g(&q.y));
                let dvx = _mm256_sub_ps(vxi, g(&q.vx));
                let dvy = _mm256_sub_ps(vyi, g(&q.vy));
                let (rhoj, volj) = (g(&q.rho), g(&q.vol));
                let r2 = _mm256_fmadd_ps(dx, dx, _mm256_mul_ps(dy, dy));
                let m = _mm256_and_ps(
                    _mm256_cmp_ps::<_CMP_LT_OQ>(r2, r2max),
                    _mm256_cmp_ps::<_CMP_GT_OQ>(r2, zero),
                );
                let r = _mm256_sqrt_ps(r2);
                let qq = _mm256_mul_ps(r, inv_h);
                let t = _mm256_sub_ps(two, qq);
                let q2 = _mm256_mul_ps(qq, qq);
                let w_in =
                    _mm256_mul_ps(w0, _mm256_fmadd_ps(q2, _mm256_fmsub_ps(half, qq, one), c23));
                let d_in = _mm256_mul_ps(d_in_k, _mm256_fmsub_ps(c15, qq, two));
                let t2 = _mm256_mul_ps(t, t);
                let w_out = _mm256_mul_ps(w_out_k, _mm256_mul_ps(t2, t));
                let rhom = _mm256_mul_ps(half, _mm256_add_ps(rhoi, rhoj));
                let vx = _mm256_fmadd_ps(dvx, dx, _mm256_mul_ps(dvy, dy));
                let d = _mm256_add_ps(r2, eta);
                let dd = _mm256_mul_ps(_mm256_mul_ps(d, d), rhom);
                let inv = _mm256_div_ps(one, _mm256_mul_ps(r, dd));
                let inv_r = _mm256_mul_ps(inv, dd);
                let inv_dd = _mm256_mul_ps(inv, r);
                let d_out = _mm256_mul_ps(d_out_k, _mm256_mul_ps(t2, inv_r));
                let pi = _mm256_mul_ps(
                    _mm256_mul_ps(hh, vx),
                    _mm256_mul_ps(
                        _mm256_fmsub_ps(beta_h, vx, _mm256_mul_ps(alpha_c, d)),
                        inv_dd,
                    ),
                );
                let pi = _mm256_and_ps(pi, _mm256_and_ps(m, _mm256_cmp_ps::<_CMP_LT_OQ>(vx, zero)));
                let inner = _mm256_cmp_ps::<_CMP_LT_OQ>(qq, one);
                let w = _mm256_and_ps(_mm256_blendv_ps(w_out, w_in, inner), m);
                let dwr = _mm256_and_ps(_mm256_blendv_ps(d_out, d_in, inner), m);
                let gx = _mm256_mul_ps(dx, dwr);
                let gy = _mm256_mul_ps(dy, dwr);
                let f = _mm256_mul_ps(w, inv_w_d0);
                let f2 = _mm256_mul_ps(f, f);
                _mm256_storeu_ps(o.gx.as_mut_ptr().add(s), gx);
                _mm256_storeu_ps(o.gy.as_mut_ptr().add(s), gy);
                _mm256_storeu_ps(o.pi.as_mut_ptr().add(s), pi);
                _mm256_storeu_ps(o.f.as_mut_ptr().add(s), _mm256_mul_ps(f2, f2));
                let (ux, uy) = (_mm256_mul_ps(dvx, volj), _mm256_mul_ps(dvy, volj));
                k00 = add_wide(k00, _mm256_mul_ps(ux, gx));
                k01 = add_wide(k01, _mm256_mul_ps(ux, gy));
                k10 = add_wide(k10, _mm256_mul_ps(uy, gx));
                k11 = add_wide(k11, _mm256_mul_ps(uy, gy));
                cont = add_wide(cont, _mm256_fmadd_ps(dvx, gx, _mm256_mul_ps(dvy, gy)));
                s += 8;
            }
            o.kin[i] = [
                -hsum_pd(k00),
                -hsum_pd(k01),
                -hsum_pd(k10),
                -hsum_pd(k11),
                hsum_pd(cont),
            ];
        }
    }

    /// Pass 2 with f32 pair terms, 8 lanes, the neighbours' stresses gathered by index, the sums
    /// in f64; otherwise as [`pass2_avx2`].
    ///
    /// # Safety
    /// As [`pass1_f32`].
    #[target_feature(enable = "avx2,fma")]
    unsafe fn pass2_f32(p: &Pairs, q: &Soa32, w: &Parts, o: &mut Out32, parts: usize) {
        use std::arch::x86_64::*;
        for i in 0..parts {
            let si = w.s[i].map(|v| _mm256_set1_ps(v as f32));
            let ri = w.r[i].map(|v| _mm256_set1_ps(v as f32));
            let (mut ax, mut ay) = (_mm256_setzero_pd(), _mm256_setzero_pd());
            let mut s = p.off[i];
            while s < p.off[i + 1] {
                let ld = |v: &Vec<f32>| _mm256_loadu_ps(v.as_ptr().add(s));
                let (gx, gy, pi, f) = (ld(&o.gx), ld(&o.gy), ld(&o.pi), ld(&o.f));
                let vi = _mm256_loadu_si256(p.idx.as_ptr().add(s) as *const __m256i);
                let g = |v: &Vec<f32>| _mm256_i32gather_ps::<4>(v.as_ptr(), vi);
                let t = |c: usize| {
                    let base = _mm256_add_ps(si[c], g(&q.s[c]));
                    let base = if c == 0 || c == 3 {
                        _mm256_sub_ps(base, pi)
                    } else {
                        base
                    };
                    _mm256_fmadd_ps(_mm256_add_ps(ri[c], g(&q.r[c])), f, base)
                };
                let (t0, t1, t2, t3) = (t(0), t(1), t(2), t(3));
                ax = add_wide(ax, _mm256_fmadd_ps(t0, gx, _mm256_mul_ps(t2, gy)));
                ay = add_wide(ay, _mm256_fmadd_ps(t1, gx, _mm256_mul_ps(t3, gy)));
                s += 8;
            }
            o.acc[i] = [hsum_pd(ax), hsum_pd(ay)];
        }
    }

    /// Per-particle values: rho_i, sigma_i/rho_i^2, R_i.
    struct Parts {
        rho: Vec<f64>,
        s: Vec<[f64; 4]>,
        r: Vec<[f64; 4]>,
    }

    /// Pass-1 results per slot and per particle.
    struct Out {
        gx: Vec<f64>,
        gy: Vec<f64>,
        pi: Vec<f64>,
        f: Vec<f64>,
        kin: Vec<[f64; 5]>,
        acc: Vec<[f64; 2]>,
    }

    impl Out {
        fn new(slots: usize, n: usize) -> Self {
            Self {
                gx: vec![0.0; slots],
                gy: vec![0.0; slots],
                pi: vec![0.0; slots],
                f: vec![0.0; slots],
                kin: vec![[0.0; 5]; n],
                acc: vec![[0.0; 2]; n],
            }
        }
    }

    /// Lay out the pairs of `x` within `radius` (other than i itself) as contiguous slots, with
    /// made-up but physical stresses (a hydrostatic part and a shear) for pass 2.
    #[allow(clippy::too_many_arguments)]
    fn layout(
        x: &[Vec2],
        v: &[Vec2],
        rho: &[f64],
        mass: f64,
        radius: f64,
        cell: f64,
        pad: usize,
    ) -> Pairs {
        let dom = Domain::OPEN;
        let grid = CellGrid::build(x, cell, &dom);
        let list = NeighborList::build(&grid, x, x, radius, &dom);
        let mut p = Pairs {
            off: vec![0],
            dx: Vec::new(),
            dy: Vec::new(),
            dvx: Vec::new(),
            dvy: Vec::new(),
            rhoj: Vec::new(),
            volj: Vec::new(),
            sj: Default::default(),
            rj: Default::default(),
            idx: Vec::new(),
            real: 0,
        };
        let stress = |j: usize| stress_of(x[j].y);
        for i in 0..x.len() {
            let mut push = |dx: f64, dy: f64, j: Option<usize>| {
                p.idx.push(j.map_or(x.len() as i32, |j| j as i32));
                p.dx.push(dx);
                p.dy.push(dy);
                let (dv, rj) = j.map_or((Vec2::zeros(), 1000.0), |j| (v[i] - v[j], rho[j]));
                p.dvx.push(dv.x);
                p.dvy.push(dv.y);
                p.rhoj.push(rj);
                p.volj.push(j.map_or(0.0, |_| mass / rj));
                let s = j.map_or([0.0; 4], stress);
                for c in 0..4 {
                    p.sj[c].push(s[c] / (rj * rj));
                    p.rj[c].push(if c == 1 || c == 2 { 1e-3 * s[c] } else { 0.0 });
                }
            };
            let mut k = 0;
            for &j in list.of(i) {
                let j = j as usize;
                if j == i {
                    continue;
                }
                let d = x[i] - x[j];
                push(d.x, d.y, Some(j));
                k += 1;
            }
            p.real += k;
            while k % pad != 0 {
                // Padding: far outside the support, masked off.
                push(1e3, 0.0, None);
                k += 1;
            }
            p.off.push(p.dx.len());
        }
        p
    }

    /// The ideal pass 1 in AVX2 + FMA over particles `parts` (see the module doc); with `GATHER`
    /// the neighbour operands are gathered by index from `q` (`vgatherdpd`, 4 lanes) instead of read
    /// from pre-gathered slots.
    ///
    /// # Safety
    /// Only on a CPU with AVX2 and FMA; `p.off` splits the slots into multiples of 4.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn pass1_avx2<const GATHER: bool>(
        p: &Pairs,
        q: &Soa,
        c: &Consts,
        rho: &[f64],
        o: &mut Out,
        parts: usize,
    ) {
        use std::arch::x86_64::*;
        let set = |v: f64| _mm256_set1_pd(v);
        let (zero, one, two, half) = (set(0.0), set(1.0), set(2.0), set(0.5));
        let (r2max, inv_h, eta) = (set(c.r2max), set(c.inv_h), set(c.eta));
        let (w0, c23, c15) = (set(c.w0), set(2.0 / 3.0), set(1.5));
        let d_in_k = set(c.w0 * c.inv_h * c.inv_h);
        let w_out_k = set(c.w0 / 6.0);
        let d_out_k = set(-0.5 * c.w0 * c.inv_h);
        let (hh, alpha_c, beta_h, inv_w_d0) =
            (set(c.h), set(c.alpha_c), set(c.beta_h), set(c.inv_w_d0));
        for i in 0..parts {
            let rhoi = set(rho[i]);
            let (xi, yi, vxi, vyi) = (set(q.x[i]), set(q.y[i]), set(q.vx[i]), set(q.vy[i]));
            let (mut k00, mut k01, mut k10, mut k11, mut cont) = (zero, zero, zero, zero, zero);
            let mut s = p.off[i];
            while s < p.off[i + 1] {
                let (dx, dy, dvx, dvy, rhoj, volj) = if GATHER {
                    let vi = _mm_loadu_si128(p.idx.as_ptr().add(s) as *const __m128i);
                    let g = |v: &Vec<f64>| _mm256_i32gather_pd::<8>(v.as_ptr(), vi);
                    (
                        _mm256_sub_pd(xi, g(&q.x)),
                        _mm256_sub_pd(yi, g(&q.y)),
                        _mm256_sub_pd(vxi, g(&q.vx)),
                        _mm256_sub_pd(vyi, g(&q.vy)),
                        g(&q.rho),
                        g(&q.vol),
                    )
                } else {
                    let ld = |v: &Vec<f64>| _mm256_loadu_pd(v.as_ptr().add(s));
                    (
                        ld(&p.dx),
                        ld(&p.dy),
                        ld(&p.dvx),
                        ld(&p.dvy),
                        ld(&p.rhoj),
                        ld(&p.volj),
                    )
                };
                let r2 = _mm256_fmadd_pd(dx, dx, _mm256_mul_pd(dy, dy));
                let m = _mm256_and_pd(
                    _mm256_cmp_pd::<_CMP_LT_OQ>(r2, r2max),
                    _mm256_cmp_pd::<_CMP_GT_OQ>(r2, zero),
                );
                let r = _mm256_sqrt_pd(r2);
                let q = _mm256_mul_pd(r, inv_h);
                let t = _mm256_sub_pd(two, q);
                let q2 = _mm256_mul_pd(q, q);
                // W inner: w0 (2/3 - q^2 + q^3/2); dW/dr / r inner: w0/h^2 (-2 + 1.5 q).
                let w_in =
                    _mm256_mul_pd(w0, _mm256_fmadd_pd(q2, _mm256_fmsub_pd(half, q, one), c23));
                let d_in = _mm256_mul_pd(d_in_k, _mm256_fmsub_pd(c15, q, two));
                let t2 = _mm256_mul_pd(t, t);
                let w_out = _mm256_mul_pd(w_out_k, _mm256_mul_pd(t2, t));
                let rhom = _mm256_mul_pd(half, _mm256_add_pd(rhoi, rhoj));
                let vx = _mm256_fmadd_pd(dvx, dx, _mm256_mul_pd(dvy, dy));
                let d = _mm256_add_pd(r2, eta);
                let dd = _mm256_mul_pd(_mm256_mul_pd(d, d), rhom);
                // The one division: 1/(r d^2 rho_ij); then 1/r and 1/(d^2 rho_ij) by products.
                let inv = _mm256_div_pd(one, _mm256_mul_pd(r, dd));
                let inv_r = _mm256_mul_pd(inv, dd);
                let inv_dd = _mm256_mul_pd(inv, r);
                let d_out = _mm256_mul_pd(d_out_k, _mm256_mul_pd(t2, inv_r));
                // Pi = h v.x (-alpha c d + beta h v.x) / (d^2 rho_ij), approaching pairs only.
                let pi = _mm256_mul_pd(
                    _mm256_mul_pd(hh, vx),
                    _mm256_mul_pd(
                        _mm256_fmsub_pd(beta_h, vx, _mm256_mul_pd(alpha_c, d)),
                        inv_dd,
                    ),
                );
                let pi = _mm256_and_pd(pi, _mm256_and_pd(m, _mm256_cmp_pd::<_CMP_LT_OQ>(vx, zero)));
                let inner = _mm256_cmp_pd::<_CMP_LT_OQ>(q, one);
                let w = _mm256_and_pd(_mm256_blendv_pd(w_out, w_in, inner), m);
                let dwr = _mm256_and_pd(_mm256_blendv_pd(d_out, d_in, inner), m);
                let gx = _mm256_mul_pd(dx, dwr);
                let gy = _mm256_mul_pd(dy, dwr);
                let f = _mm256_mul_pd(w, inv_w_d0);
                let f2 = _mm256_mul_pd(f, f);
                _mm256_storeu_pd(o.gx.as_mut_ptr().add(s), gx);
                _mm256_storeu_pd(o.gy.as_mut_ptr().add(s), gy);
                _mm256_storeu_pd(o.pi.as_mut_ptr().add(s), pi);
                _mm256_storeu_pd(o.f.as_mut_ptr().add(s), _mm256_mul_pd(f2, f2));
                // kappa -= V_j v_ij (x) grad W; continuity += v_ij . grad W.
                let (ux, uy) = (_mm256_mul_pd(dvx, volj), _mm256_mul_pd(dvy, volj));
                k00 = _mm256_fnmadd_pd(ux, gx, k00);
                k01 = _mm256_fnmadd_pd(ux, gy, k01);
                k10 = _mm256_fnmadd_pd(uy, gx, k10);
                k11 = _mm256_fnmadd_pd(uy, gy, k11);
                cont = _mm256_fmadd_pd(dvx, gx, _mm256_fmadd_pd(dvy, gy, cont));
                s += 4;
            }
            let hsum = |v: __m256d| {
                let mut a = [0.0; 4];
                _mm256_storeu_pd(a.as_mut_ptr(), v);
                (a[0] + a[1]) + (a[2] + a[3])
            };
            o.kin[i] = [hsum(k00), hsum(k01), hsum(k10), hsum(k11), hsum(cont)];
        }
    }

    /// The ideal pass 2 in AVX2 + FMA over particles `parts`, over slots `p2` (the pairs inside the
    /// support), reading pass 1's results `o` aligned with `p2`.
    ///
    /// # Safety
    /// As [`pass1_avx2`].
    #[target_feature(enable = "avx2,fma")]
    unsafe fn pass2_avx2<const GATHER: bool>(
        p: &Pairs,
        q: &Soa,
        w: &Parts,
        o: &mut Out,
        parts: usize,
    ) {
        use std::arch::x86_64::*;
        for i in 0..parts {
            let si = w.s[i].map(|v| _mm256_set1_pd(v));
            let ri = w.r[i].map(|v| _mm256_set1_pd(v));
            let (mut ax, mut ay) = (_mm256_setzero_pd(), _mm256_setzero_pd());
            let mut s = p.off[i];
            while s < p.off[i + 1] {
                let ld = |v: &Vec<f64>| _mm256_loadu_pd(v.as_ptr().add(s));
                let (gx, gy, pi, f) = (ld(&o.gx), ld(&o.gy), ld(&o.pi), ld(&o.f));
                let vi = _mm_loadu_si128(p.idx.as_ptr().add(s) as *const __m128i);
                let nb = |slot: &Vec<f64>, own: &Vec<f64>| {
                    if GATHER {
                        _mm256_i32gather_pd::<8>(own.as_ptr(), vi)
                    } else {
                        ld(slot)
                    }
                };
                let t = |c: usize| {
                    let base = _mm256_add_pd(si[c], nb(&p.sj[c], &q.s[c]));
                    let base = if c == 0 || c == 3 {
                        _mm256_sub_pd(base, pi)
                    } else {
                        base
                    };
                    _mm256_fmadd_pd(_mm256_add_pd(ri[c], nb(&p.rj[c], &q.r[c])), f, base)
                };
                let (t0, t1, t2, t3) = (t(0), t(1), t(2), t(3));
                // t column-major: (t0 gx + t2 gy, t1 gx + t3 gy).
                ax = _mm256_fmadd_pd(t0, gx, _mm256_fmadd_pd(t2, gy, ax));
                ay = _mm256_fmadd_pd(t1, gx, _mm256_fmadd_pd(t3, gy, ay));
                s += 4;
            }
            let hsum = |v: __m256d| {
                let mut a = [0.0; 4];
                _mm256_storeu_pd(a.as_mut_ptr(), v);
                (a[0] + a[1]) + (a[2] + a[3])
            };
            o.acc[i] = [hsum(ax), hsum(ay)];
        }
    }

    /// `exact` in plain portable f64 (no FMA, no explicit SIMD): the same operations per slot.
    fn pass1_scalar(p: &Pairs, c: &Consts, rho: &[f64], o: &mut Out) {
        for i in 0..rho.len() {
            let mut k = [0.0; 5];
            for s in p.off[i]..p.off[i + 1] {
                let (dx, dy, dvx, dvy) = (p.dx[s], p.dy[s], p.dvx[s], p.dvy[s]);
                let r2 = dx * dx + dy * dy;
                let m = r2 < c.r2max && r2 > 0.0;
                let r = r2.sqrt();
                let q = r * c.inv_h;
                let t = 2.0 - q;
                let w_in = c.w0 * (2.0 / 3.0 + q * q * (0.5 * q - 1.0));
                let d_in = c.w0 * c.inv_h * c.inv_h * (1.5 * q - 2.0);
                let w_out = c.w0 / 6.0 * t * t * t;
                let rhom = 0.5 * (rho[i] + p.rhoj[s]);
                let vx = dvx * dx + dvy * dy;
                let d = r2 + c.eta;
                let dd = d * d * rhom;
                let inv = 1.0 / (r * dd);
                let d_out = -0.5 * c.w0 * c.inv_h * t * t * (inv * dd);
                let pi = c.h * vx * (c.beta_h * vx - c.alpha_c * d) * (inv * r);
                let pi = if m && vx < 0.0 { pi } else { 0.0 };
                let inner = q < 1.0;
                let w = if !m {
                    0.0
                } else if inner {
                    w_in
                } else {
                    w_out
                };
                let dwr = if !m {
                    0.0
                } else if inner {
                    d_in
                } else {
                    d_out
                };
                let (gx, gy) = (dx * dwr, dy * dwr);
                let f = w * c.inv_w_d0;
                o.gx[s] = gx;
                o.gy[s] = gy;
                o.pi[s] = pi;
                o.f[s] = (f * f) * (f * f);
                let (ux, uy) = (dvx * p.volj[s], dvy * p.volj[s]);
                k[0] -= ux * gx;
                k[1] -= ux * gy;
                k[2] -= uy * gx;
                k[3] -= uy * gy;
                k[4] += dvx * gx + dvy * gy;
            }
            o.kin[i] = k;
        }
    }

    fn pass2_scalar(p: &Pairs, w: &Parts, o: &mut Out) {
        for i in 0..w.rho.len() {
            let (si, ri) = (w.s[i], w.r[i]);
            let (mut ax, mut ay) = (0.0, 0.0);
            for s in p.off[i]..p.off[i + 1] {
                let f = o.f[s];
                let t = |c: usize| (si[c] + p.sj[c][s]) + (ri[c] + p.rj[c][s]) * f;
                let (t0, t1, t2, t3) = (t(0) - o.pi[s], t(1), t(2), t(3) - o.pi[s]);
                ax += t0 * o.gx[s] + t2 * o.gy[s];
                ay += t1 * o.gx[s] + t3 * o.gy[s];
            }
            o.acc[i] = [ax, ay];
        }
    }

    /// CPU seconds of `reps` calls of `f`, repeated until at least 0.3 s have passed.
    fn timed(mut f: impl FnMut()) -> (f64, usize) {
        let c0 = cpu_seconds();
        let mut reps = 0;
        while cpu_seconds() - c0 < 0.3 || reps < 3 {
            f();
            reps += 1;
        }
        (cpu_seconds() - c0, reps)
    }

    pub fn main() {
        assert!(
            std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma"),
            "this ceiling needs AVX2 and FMA"
        );
        let args: Vec<String> = std::env::args().collect();
        let path = args
            .get(1)
            .expect("usage: pass_ceiling SCENE.toml [ROUNDS] [SOLVER_STEPS]");
        let rounds: usize = args.get(2).map_or(3, |s| s.parse().expect("ROUNDS"));
        let steps: u64 = args.get(3).map_or(20, |s| s.parse().expect("SOLVER_STEPS"));
        let text = std::fs::read_to_string(path).expect("scene file");
        let mut cfg = SceneConfig::from_toml_str(&text).expect("scene");
        cfg.numerics.threads = 1;
        let mut sim = Simulation::new(cfg).expect("simulation");
        // A few steps in, so velocities and densities are those of a running drop.
        sim.advance_to(1e-12).expect("first step");
        let eff = sim.effective_config().clone();
        let dx = eff.dx();
        let h = eff.numerics.smoothing_ratio * dx;
        let st = sim.state();
        let (x, v, rho, mass) = (
            st.fluid.x.clone(),
            st.fluid.v.clone(),
            st.fluid.rho.clone(),
            st.fluid.mass,
        );
        let n = x.len();
        let w0 = 15.0 / (7.0 * std::f64::consts::PI * h * h);
        let q0 = dx / h;
        let w_d0 = w0 * (2.0 / 3.0 - q0 * q0 + 0.5 * q0 * q0 * q0);
        let c = Consts {
            h,
            inv_h: 1.0 / h,
            w0,
            r2max: (2.0 * h) * (2.0 * h),
            eta: 0.01 * h * h,
            alpha_c: 0.3 * eff.resolved_sound_speed(),
            beta_h: 0.6 * h,
            inv_w_d0: 1.0 / w_d0,
        };
        let exact = layout(&x, &v, &rho, mass, 2.0 * h, 2.25 * h, 4);
        let skin = layout(&x, &v, &rho, mass, 2.25 * h, 2.25 * h, 4);
        let exact8 = layout(&x, &v, &rho, mass, 2.0 * h, 2.25 * h, 8);
        let parts = Parts {
            rho: rho.clone(),
            s: x.iter()
                .zip(&rho)
                .map(|(p, r)| [-1000.0 * p.y / (r * r), 0.0, 0.0, -1000.0 * p.y / (r * r)])
                .collect(),
            r: vec![[0.0, 1e-4, 1e-4, 0.0]; n],
        };
        println!(
        "{n} fluid particles, h = {:.3} dx: {:.2} pairs per particle inside the support ({:.2} slots \
         padded to 4), {:.2} with the skin 0.25 h ({:.2} padded)",
        h / dx,
        exact.real as f64 / n as f64,
        exact.slots() as f64 / n as f64,
        skin.real as f64 / n as f64,
        skin.slots() as f64 / n as f64
    );
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("model name"))
                    .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
            })
            .unwrap_or_default();
        println!("CPU: {cpu}");
        let soa = Soa::new(&x, &v, &rho, mass);
        let runs = Runs::new(&skin, n);
        println!(
        "runs of consecutive indices in the skin lists: {:.2} per particle, {:.2} lanes (4-lane \
         vectors) per particle",
        runs.runs.len() as f64 / n as f64,
        runs.slots() as f64 / n as f64
    );
        let mut orn = Out::new(runs.slots(), n);
        let soa32 = Soa32::new(&soa);
        let mut o32 = Out32::new(exact8.slots(), n);
        let mut oe = Out::new(exact.slots(), n);
        let mut os = Out::new(skin.slots(), n);
        let resident = 16usize;
        let names = [
            "exact pass 1",
            "exact pass 2",
            "skin pass 1",
            "resident pass 1",
            "resident pass 2",
            "scalar pass 1",
            "scalar pass 2",
            "gather pass 1",
            "gather pass 2",
            "gather skin p1",
            "runs, both",
            "f32 gather p1",
            "f32 gather p2",
        ];
        let mut best = [f64::INFINITY; 13];
        let mut solver_best = f64::INFINITY;
        for round in 0..rounds {
            // ns per particle per call of each variant.
            let per = |(t, reps): (f64, usize), m: usize| 1e9 * t / (reps as f64 * m as f64);
            // SAFETY: AVX2 and FMA checked at the start; the layouts pad to multiples of 4.
            let got = unsafe {
                [
                    per(
                        timed(|| pass1_avx2::<false>(&exact, &soa, &c, &rho, &mut oe, n)),
                        n,
                    ),
                    per(
                        timed(|| pass2_avx2::<false>(&exact, &soa, &parts, &mut oe, n)),
                        n,
                    ),
                    per(
                        timed(|| pass1_avx2::<false>(&skin, &soa, &c, &rho, &mut os, n)),
                        n,
                    ),
                    per(
                        timed(|| {
                            for _ in 0..1000 {
                                pass1_avx2::<false>(&exact, &soa, &c, &rho, &mut oe, resident)
                            }
                        }),
                        1000 * resident,
                    ),
                    per(
                        timed(|| {
                            for _ in 0..1000 {
                                pass2_avx2::<false>(&exact, &soa, &parts, &mut oe, resident)
                            }
                        }),
                        1000 * resident,
                    ),
                    per(timed(|| pass1_scalar(&exact, &c, &rho, &mut oe)), n),
                    per(timed(|| pass2_scalar(&exact, &parts, &mut oe)), n),
                    per(
                        timed(|| pass1_avx2::<true>(&exact, &soa, &c, &rho, &mut oe, n)),
                        n,
                    ),
                    per(
                        timed(|| pass2_avx2::<true>(&exact, &soa, &parts, &mut oe, n)),
                        n,
                    ),
                    per(
                        timed(|| pass1_avx2::<true>(&skin, &soa, &c, &rho, &mut os, n)),
                        n,
                    ),
                    per(timed(|| runs_avx2(&runs, &soa, &c, &parts, &mut orn, n)), n),
                    per(timed(|| pass1_f32(&exact8, &soa32, &c, &mut o32, n)), n),
                    per(timed(|| pass2_f32(&exact8, &soa32, &parts, &mut o32, n)), n),
                ]
            };
            for (b, g) in best.iter_mut().zip(got) {
                *b = b.min(g);
            }
            // The solver itself, same scene, one thread.
            let (s0, t0) = (sim.state().step, sim.time());
            let dt = sim.state().last_dt;
            let c0 = cpu_seconds();
            let w = Instant::now();
            sim.advance_to(t0 + dt * steps as f64 * 0.999)
                .expect("solver steps");
            let done = sim.state().step - s0;
            let ns = 1e9 * (cpu_seconds() - c0) / (n as f64 * done as f64);
            solver_best = solver_best.min(ns);
            eprintln!(
            "round {round}: solver {ns:.0} CPU ns/particle-step ({done} steps, wall {:.2} s); {}",
            w.elapsed().as_secs_f64(),
            names
                .iter()
                .zip(got)
                .map(|(k, g)| format!("{k} {g:.1}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        }
        // The variants compute the same sums (in other orders): check the runs against the exact
        // lists, so that the timings are of the same work.
        // SAFETY: as above.
        unsafe {
            pass1_avx2::<false>(&exact, &soa, &c, &rho, &mut oe, n);
            pass2_avx2::<false>(&exact, &soa, &parts, &mut oe, n);
        }
        let scale_k = oe.kin.iter().map(|k| k[4].abs()).fold(0.0, f64::max);
        let scale_a = oe
            .acc
            .iter()
            .map(|a| a[0].abs().max(a[1].abs()))
            .fold(0.0, f64::max);
        for i in 0..n {
            for m in 0..5 {
                assert!(
                    (oe.kin[i][m] - orn.kin[i][m]).abs() <= 1e-10 * scale_k,
                    "kinematics differ at {i}"
                );
            }
            for m in 0..2 {
                assert!(
                    (oe.acc[i][m] - orn.acc[i][m]).abs() <= 1e-10 * scale_a,
                    "accelerations differ at {i}: {:?} vs {:?}",
                    oe.acc[i],
                    orn.acc[i]
                );
            }
        }
        // The f32 variant: the same sums to f32 accuracy (positions in f32 lose digits of x_ij).
        // SAFETY: as above.
        unsafe {
            pass1_f32(&exact8, &soa32, &c, &mut o32, n);
            pass2_f32(&exact8, &soa32, &parts, &mut o32, n);
        }
        let worst = (0..n)
            .map(|i| {
                (oe.acc[i][0] - o32.acc[i][0])
                    .abs()
                    .max((oe.acc[i][1] - o32.acc[i][1]).abs())
            })
            .fold(0.0, f64::max)
            / scale_a;
        println!(
            "f32 variant: largest acceleration difference {worst:.1e} of the largest acceleration"
        );
        // Keep the results alive (and check them finite).
        let check: f64 = oe.kin.iter().map(|k| k[4]).sum::<f64>()
            + oe.acc.iter().map(|a| a[0] + a[1]).sum::<f64>()
            + os.kin.iter().map(|k| k[0]).sum::<f64>()
            + orn.acc.iter().map(|a| a[0] + a[1]).sum::<f64>()
            + o32.acc.iter().map(|a| a[0] + a[1]).sum::<f64>();
        assert!(check.is_finite(), "non-finite sums");
        println!("min CPU ns per particle and evaluation over {rounds} rounds:");
        for (k, b) in names.iter().zip(best) {
            println!("  {k:16} {b:7.1}");
        }
        let step = |p1: f64, p2: f64| 2.0 * (p1 + p2);
        println!("ceiling per particle-step (two evaluations, pair arithmetic only):");
        println!(
            "  AVX2+FMA, exact lists, streamed     {:7.1} ns",
            step(best[0], best[1])
        );
        println!(
            "  AVX2+FMA, skin list in pass 1       {:7.1} ns",
            step(best[2], best[1])
        );
        println!(
            "  AVX2+FMA, operands in L1/L2         {:7.1} ns",
            step(best[3], best[4])
        );
        println!(
            "  portable scalar f64, exact lists    {:7.1} ns",
            step(best[5], best[6])
        );
        println!(
            "  AVX2+FMA gathers by index, exact    {:7.1} ns",
            step(best[7], best[8])
        );
        println!(
            "  AVX2+FMA gathers, skin list pass 1  {:7.1} ns",
            step(best[9], best[8])
        );
        println!(
            "  AVX2+FMA vector loads of index runs {:7.1} ns",
            2.0 * best[10]
        );
        println!(
            "  f32 pairs (8 lanes), f64 sums, gathers {:4.1} ns",
            step(best[11], best[12])
        );
        println!("solver (this library, whole step):   {solver_best:7.1} CPU ns per particle-step");
    }
}

#[cfg(target_arch = "x86_64")]
fn main() {
    ceiling::main()
}

#[cfg(not(target_arch = "x86_64"))]
fn main() {
    eprintln!("pass_ceiling measures AVX2 + FMA code: x86-64 only");
}
