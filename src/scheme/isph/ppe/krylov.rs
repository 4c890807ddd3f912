//! BiCGStab with Jacobi, SSOR, ILU(0) or algebraic multigrid preconditioning, with sums in a
//! fixed order.

use super::*;

/// Preconditioners for BiCGStab.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preconditioner {
    /// Diagonal scaling (King & Lind's choice).
    Jacobi,
    /// Symmetric successive over-relaxation with omega = 1 (symmetric Gauss-Seidel).
    Ssor,
    /// Incomplete LU factorisation with the matrix's own sparsity pattern.
    Ilu0,
    /// One W-cycle of smoothed-aggregation algebraic multigrid ([`Amg`]).
    Amg,
    /// Block Jacobi: the inverse of each `k x k` diagonal block (rows and columns `k b ..
    /// k b + k`), for systems with `k` unknowns per particle interleaved (the coupled viscous
    /// step); `BlockJacobi(1)` is [`Preconditioner::Jacobi`]. No sequential part: set-up and
    /// application are per block, so it costs nothing serial and scales with the threads.
    BlockJacobi(usize),
    /// One W-cycle of plain-aggregation algebraic multigrid (the tentative prolongation, not
    /// smoothed) for systems with `k` unknowns per particle interleaved (the coupled viscous
    /// step), aggregated by particle ([`Amg::with_options`]): the implicit viscous system's
    /// preconditioner from [`VISCOUS_AMG_MIN_ROWS`] rows in 2D.
    AmgNodal(usize),
}

impl Preconditioner {
    /// The preconditioner of a pressure Poisson system of `rows` rows: [`Preconditioner::Amg`]
    /// from [`AMG_MIN_ROWS`] rows, ILU(0) below.
    ///
    /// AMG's iterations stay flat as the resolution grows and its cycle is row-parallel;
    /// ILU(0)'s grow like the inverse spacing and its factorisation and triangular solves run
    /// on one thread. Measured on the scaling bench's drop (King & Lind's Re = 4 from just
    /// above the plate, warm started, one thread; `viscosph bench scaling`'s case): PPE iterations
    /// per solve 5.2 / 5.7 / 5.8 with AMG at 10^3 / 10^4 / 10^5 particles, 8.4 / 23.5 with
    /// ILU(0) at 10^3 / 10^4 (47 at 10^5 in `examples/isph_speed.rs`); CPU of the pressure
    /// solve at 10^4 1.27 s (AMG) against 1.44 s (ILU(0)) over 28 steps, at 10^3 0.227 s against
    /// 0.129 s over 51 steps (AMG's set-up does not pay on so few rows). The switch lies between
    /// the two, where `ppe_bench`'s cold solves at 5,008 rows cost about the same
    /// (docs/isph.md).
    ///
    /// 3D keeps the same switch. King & Lind's Re = 4 drop as a sphere (one thread, AMD EPYC
    /// under load, CPU of the pressure solve, each preconditioner forced in turn): 2,176
    /// particles, 20 steps of the fall, ILU(0) 0.50 s against AMG 0.86 s; 4,224 particles, 25
    /// steps of the fall 1.66 against 2.59 s, 58 steps through the impact (t* = 0.7) 3.73
    /// against 6.21 s; 9,328 particles, 32 steps of the fall 6.04 against 9.73 s. ILU(0) takes
    /// about 0.6 of AMG's CPU up to 10^4 particles, but on one thread: on two, AMG's halved
    /// wall time about equals it at 5,000-10,000 rows, and on more cores AMG wins, so the switch
    /// stays at [`AMG_MIN_ROWS`] for both dimensions.
    pub fn for_pressure(rows: usize) -> Self {
        if rows >= AMG_MIN_ROWS {
            Preconditioner::Amg
        } else {
            Preconditioner::Ilu0
        }
    }

    /// The preconditioner of the implicit viscous system of `rows` rows in `dim` dimensions
    /// with `block` velocity components per particle interleaved (`dim` for the coupled system
    /// with the surface traction, 1 per component without it): in 2D
    /// [`Preconditioner::AmgNodal`] from [`VISCOUS_AMG_MIN_ROWS`] rows, block Jacobi from
    /// [`BLOCK_JACOBI_MIN_ROWS`] rows, ILU(0) below; in 3D [`Preconditioner::BlockJacobi`].
    /// Neither block Jacobi nor the multigrid cycle has a sequential part.
    ///
    /// 3D: with ~250 neighbours per particle (quintic kernel, h = 1.3 dr) and, with the surface
    /// traction, a full 3 x 3 block per pair, the coupled rows hold ~750 entries and ILU(0)'s
    /// factorisation costs ~(entries / 2)^2 per row, about 60 mat-vecs, every step, on one
    /// thread; block Jacobi needs ~6x the iterations but has no set-up beyond the blocks.
    /// Measured on King & Lind's Re = 4 drop as a sphere at 20 per diameter (4,224 particles,
    /// one thread, to t* = 0.15): the run took 17.4 s of CPU with ILU(0) and 6.1 s with block
    /// Jacobi.
    ///
    /// 2D (~50 neighbours): ILU(0) needs fewer iterations, but its factorisation and triangular
    /// solves run on one thread (more than a third of a step at 10^4 particles), and block
    /// Jacobi costs less CPU even on one thread. The scaling bench's drop, one thread,
    /// iterations per step and the viscous solve's CPU: 10^3 particles (2,040 rows, 51 steps)
    /// 14.6 and 0.46 s against ILU(0)'s 2.4 and 0.53 s; 10^4 (28 steps) 19.7 and 3.07 s against
    /// 3.0 and 3.58 s; 10^5 (4 steps) 33.8 and 7.00 s against 5.5 and 7.34 s. ILU(0) of fixed
    /// blocks of consecutive rows (parallel, the same bits on any thread count) lost too much
    /// of the coupling: 7.7 / 9.1 / 12.8 iterations at 10^4 with blocks of 2048 / 1024 / 512
    /// rows.
    ///
    /// Block Jacobi's iterations grow with the resolution (the step falls like the spacing, so
    /// the Laplacian's weight against the identity grows like its inverse): 17.2 / 19.7 / 34.0
    /// per step at 10^3 / 10^4 / 10^5 particles. Plain-aggregation multigrid keeps them at
    /// 4-5 but costs a set-up and a dearer cycle (about 15 mat-vecs an iteration against 2);
    /// with it from [`VISCOUS_AMG_MIN_ROWS`] the counts are 17.2 / 19.7 / 5.0. Measured on the
    /// scaling bench's drop (one thread, AMD EPYC under load, iterations per step and the
    /// viscous solve's CPU, assembly included): 10^4 particles (38 steps) block Jacobi 20.3 and
    /// 3.18 s, plain aggregation 4.18 and 4.48 s (smoothed: 3.89 and 5.66 s); 10^5 (4 steps,
    /// two runs each, alternated) block Jacobi 34.0 and 5.80 / 5.92 s, plain aggregation 5.0
    /// and 6.08 / 6.43 s (smoothed: 5.0 and 7.47 s).
    pub fn for_viscous(rows: usize, dim: usize, block: usize) -> Self {
        if dim == 2 && rows >= VISCOUS_AMG_MIN_ROWS {
            return Preconditioner::AmgNodal(block);
        }
        if dim == 3 || rows >= BLOCK_JACOBI_MIN_ROWS {
            Preconditioner::BlockJacobi(block)
        } else {
            Preconditioner::Ilu0
        }
    }
}

/// Smallest pressure system preconditioned by AMG ([`Preconditioner::for_pressure`]).
pub const AMG_MIN_ROWS: usize = 5_000;
/// Smallest 2D viscous system preconditioned by block Jacobi
/// ([`Preconditioner::for_viscous`]): the 10^3-particle drop's coupled system (2,040 rows)
/// was measured to gain; smaller systems keep ILU(0), whose one-thread part is then a few
/// hundred microseconds a step.
pub const BLOCK_JACOBI_MIN_ROWS: usize = 2_000;
/// Smallest 2D viscous system preconditioned by plain-aggregation multigrid
/// ([`Preconditioner::for_viscous`]): about 5 x 10^4 particles' coupled system. At 10^4
/// particles (20,000 rows) block Jacobi cost 30 % less; at 10^5 (200,160 rows) the multigrid's
/// 5.0 iterations against 34.0 cost 4-8 % more of the viscous solve's CPU, and block Jacobi's
/// count keeps growing with the resolution while the multigrid's stays.
pub const VISCOUS_AMG_MIN_ROWS: usize = 100_000;

impl Default for Preconditioner {
    /// ILU(0): measured the fastest robust option (module documentation).
    fn default() -> Self {
        Preconditioner::Ilu0
    }
}

/// Options of [`bicgstab`].
#[derive(Debug, Clone, Copy)]
pub struct SolverOptions {
    /// Converged when |b - A x| <= rel_tol |b|.
    pub rel_tol: f64,
    /// Iteration cap (King's code: 1000).
    pub max_iter: usize,
    pub preconditioner: Preconditioner,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            rel_tol: 1e-8,
            max_iter: 1000,
            preconditioner: Preconditioner::default(),
        }
    }
}

/// What a successful solve did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveStats {
    /// BiCGStab iterations (each two matrix-vector products).
    pub iterations: usize,
    /// Final true residual |b - A x| / |b|.
    pub rel_residual: f64,
}

/// Why a solve failed.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum SolveError {
    #[error("linear solve did not converge in {iterations} iterations (relative residual {rel_residual:.3e})")]
    NotConverged {
        iterations: usize,
        rel_residual: f64,
    },
    #[error("BiCGStab breakdown: {quantity} = 0 at iteration {iteration} (relative residual {rel_residual:.3e})")]
    Breakdown {
        quantity: &'static str,
        iteration: usize,
        rel_residual: f64,
    },
    #[error("preconditioner: zero pivot in row {row}")]
    ZeroPivot { row: usize },
    #[error("linear solve: non-finite value at iteration {iteration}")]
    NonFinite { iteration: usize },
}

/// A preconditioner ready to apply: z = M^-1 r.
#[derive(Debug, Clone)]
pub enum Factor {
    Jacobi(Vec<f64>),
    /// The matrix itself (SSOR sweeps read it) and its inverse diagonal.
    Ssor(Vec<f64>),
    /// ILU(0) factors in the matrix's pattern: strict lower part holds L (unit diagonal), the
    /// rest U.
    Ilu0(Vec<f64>),
    /// The multigrid hierarchy.
    Amg(Box<Amg>),
    /// Block size k and the inverse blocks, row-major, `k * k` values per block.
    BlockJacobi(usize, Vec<f64>),
}

impl Factor {
    /// Set up the preconditioner of `a`.
    pub fn new(a: &CsrMatrix, kind: Preconditioner) -> Result<Self, SolveError> {
        let n = a.n();
        let inv_diag = inverse_diagonal;
        match kind {
            Preconditioner::Jacobi => Ok(Factor::Jacobi(inv_diag(a)?)),
            Preconditioner::Ssor => Ok(Factor::Ssor(inv_diag(a)?)),
            Preconditioner::Amg => Ok(Factor::Amg(Box::new(Amg::new(a)?))),
            Preconditioner::AmgNodal(k) => Ok(Factor::Amg(Box::new(Amg::with_options(
                a,
                CYCLE_VISITS,
                k,
                false,
            )?))),
            Preconditioner::BlockJacobi(1) => Ok(Factor::Jacobi(inv_diag(a)?)),
            Preconditioner::BlockJacobi(k) => Ok(Factor::BlockJacobi(k, block_inverses(a, k)?)),
            Preconditioner::Ilu0 => {
                // IKJ variant (Saad 2003, Algorithm 10.4), sequential in row order, with the
                // current row scattered into a dense work row `w` indexed by column. The updates
                // from row k go to every column of k's upper part without asking whether row i
                // stores it: a column outside row i's pattern (a fill-in ILU(0) drops) collects
                // a value that is never read, since `w` is read only at row i's own columns,
                // each written afresh by the scatter before its updates. Every stored entry
                // receives the same updates in the same order as in the textbook loop (which
                // looks each column up and branches), so the factors are bitwise the same.
                // Measured (examples/ppe_kernels.rs, 1e4 and 1e5 rows): 1.4-1.7x faster.
                let mut lu = a.val.clone();
                let mut w = vec![0.0f64; n];
                for i in 0..n {
                    let (s, d, e) = (a.row_ptr[i], a.diag[i], a.row_ptr[i + 1]);
                    for (&c, &v) in a.col[s..e].iter().zip(&a.val[s..e]) {
                        w[c as usize] = v;
                    }
                    for &k in &a.col[s..d] {
                        let k = k as usize;
                        let ukk = lu[a.diag[k]];
                        if ukk == 0.0 || !ukk.is_finite() {
                            return Err(SolveError::ZeroPivot { row: k });
                        }
                        let lik = w[k] / ukk;
                        w[k] = lik;
                        let (u0, u1) = (a.diag[k] + 1, a.row_ptr[k + 1]);
                        for (&c, &ukc) in a.col[u0..u1].iter().zip(&lu[u0..u1]) {
                            w[c as usize] -= lik * ukc;
                        }
                    }
                    for (&c, v) in a.col[s..e].iter().zip(&mut lu[s..e]) {
                        *v = w[c as usize];
                    }
                    let d = lu[d];
                    if d == 0.0 || !d.is_finite() {
                        return Err(SolveError::ZeroPivot { row: i });
                    }
                }
                Ok(Factor::Ilu0(lu))
            }
        }
    }

    /// z = M^-1 r.
    pub fn apply(&self, a: &CsrMatrix, r: &[f64], z: &mut [f64]) {
        let n = a.n();
        match self {
            Factor::Jacobi(d) => {
                z.par_iter_mut()
                    .zip(r.par_iter().zip(d.par_iter()))
                    .with_min_len(ROW_CHUNK)
                    .for_each(|(z, (r, d))| *z = r * d);
            }
            Factor::Ssor(dinv) => {
                // M = (D + L) D^-1 (D + U): forward sweep then backward sweep.
                for i in 0..n {
                    let (cols, vals) = a.row(i);
                    let mut s = r[i];
                    for (&j, &v) in cols.iter().zip(vals) {
                        if (j as usize) < i {
                            s -= v * z[j as usize];
                        }
                    }
                    z[i] = s * dinv[i];
                }
                for i in (0..n).rev() {
                    let (cols, vals) = a.row(i);
                    let mut s = 0.0;
                    for (&j, &v) in cols.iter().zip(vals) {
                        if (j as usize) > i {
                            s += v * z[j as usize];
                        }
                    }
                    z[i] -= s * dinv[i];
                }
            }
            Factor::Amg(m) => m.apply(a, r, z),
            Factor::BlockJacobi(k, inv) => {
                let k = *k;
                z.par_chunks_mut(k)
                    .zip(r.par_chunks(k).zip(inv.par_chunks(k * k)))
                    .with_min_len(ROW_CHUNK / k)
                    .for_each(|(z, (r, b))| {
                        for (zi, bi) in z.iter_mut().zip(b.chunks_exact(k)) {
                            *zi = bi.iter().zip(r).map(|(m, v)| m * v).sum();
                        }
                    });
            }
            Factor::Ilu0(lu) => {
                // L z' = r then U z = z', each row a sequential sum in column order; slices per
                // row so the inner loops index only `z`.
                let (rp, col, dg) = (&a.row_ptr, &a.col, &a.diag);
                for i in 0..n {
                    let (s0, d) = (rp[i], dg[i]);
                    let mut s = r[i];
                    for (&c, &l) in col[s0..d].iter().zip(&lu[s0..d]) {
                        s -= l * z[c as usize];
                    }
                    z[i] = s;
                }
                for i in (0..n).rev() {
                    let (d, e) = (dg[i], rp[i + 1]);
                    let mut s = z[i];
                    for (&c, &u) in col[d + 1..e].iter().zip(&lu[d + 1..e]) {
                        s -= u * z[c as usize];
                    }
                    z[i] = s / lu[d];
                }
            }
        }
    }
}

/// The inverses of the `k x k` diagonal blocks of `a` (rows and columns `k b .. k b + k`),
/// row-major, in parallel per block (Gauss-Jordan with partial pivoting; each block by itself,
/// so the result does not depend on the thread count). A singular block is a zero pivot.
fn block_inverses(a: &CsrMatrix, k: usize) -> Result<Vec<f64>, SolveError> {
    let n = a.n();
    assert!(
        k > 0 && n.is_multiple_of(k),
        "{n} rows are not blocks of {k}"
    );
    let mut inv = vec![0.0; n * k];
    let bad: Option<usize> = inv
        .par_chunks_mut(k * k)
        .enumerate()
        .with_min_len(ROW_CHUNK / k)
        .map(|(b, out)| {
            // [block | I] reduced to [I | block^-1].
            let mut m = vec![0.0; 2 * k * k];
            for r in 0..k {
                // The block's columns, found by bisection in the ascending row (a coupled 3D
                // row holds ~750 entries, the block 3).
                let (cols, vals) = a.row(k * b + r);
                let lo = cols.partition_point(|&c| (c as usize) < k * b);
                let hi = cols.partition_point(|&c| (c as usize) < k * b + k);
                for (&c, &v) in cols[lo..hi].iter().zip(&vals[lo..hi]) {
                    m[2 * k * r + c as usize - k * b] = v;
                }
                m[2 * k * r + k + r] = 1.0;
            }
            for p in 0..k {
                let piv = (p..k)
                    .max_by(|&x, &y| {
                        m[2 * k * x + p]
                            .abs()
                            .total_cmp(&m[2 * k * y + p].abs())
                            .then(y.cmp(&x))
                    })
                    .expect("k > 0");
                let d = m[2 * k * piv + p];
                if d == 0.0 || !d.is_finite() {
                    return Some(k * b + p);
                }
                for c in 0..2 * k {
                    m.swap(2 * k * p + c, 2 * k * piv + c);
                }
                for c in 0..2 * k {
                    m[2 * k * p + c] /= d;
                }
                for r in (0..k).filter(|&r| r != p) {
                    let f = m[2 * k * r + p];
                    if f != 0.0 {
                        for c in 0..2 * k {
                            m[2 * k * r + c] -= f * m[2 * k * p + c];
                        }
                    }
                }
            }
            for r in 0..k {
                out[k * r..k * r + k].copy_from_slice(&m[2 * k * r + k..2 * k * r + 2 * k]);
            }
            None
        })
        .find_first(|b| b.is_some())
        .flatten();
    match bad {
        Some(row) => Err(SolveError::ZeroPivot { row }),
        None => Ok(inv),
    }
}

/// Preconditioned BiCGStab (van der Vorst 1992) for `A x = b`; `x` is the start (warm start)
/// on entry and the solution on success. See the module documentation for the stopping test.
pub fn bicgstab(
    a: &CsrMatrix,
    m: &Factor,
    b: &[f64],
    x: &mut [f64],
    opts: &SolverOptions,
) -> Result<SolveStats, SolveError> {
    let n = a.n();
    assert_eq!(b.len(), n);
    assert_eq!(x.len(), n);
    let bnorm = dot(b, b).sqrt();
    if !bnorm.is_finite() || x.iter().any(|v| !v.is_finite()) {
        return Err(SolveError::NonFinite { iteration: 0 });
    }
    if bnorm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        return Ok(SolveStats {
            iterations: 0,
            rel_residual: 0.0,
        });
    }
    let target = opts.rel_tol * bnorm;
    let (mut r, mut rhat, mut p, mut v, mut y, mut s, mut z, mut t) = (
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
    );
    let true_residual = |x: &[f64], r: &mut [f64]| -> f64 {
        a.matvec(x, r);
        r.par_iter_mut()
            .zip(b.par_iter())
            .with_min_len(ROW_CHUNK)
            .for_each(|(r, b)| *r = b - *r);
        dot(r, r).sqrt()
    };
    let mut it = 0usize;
    let mut rnorm = true_residual(x, &mut r);
    // Restart loop: entered again when the recursive residual drifted from the true one.
    loop {
        if rnorm <= target {
            return Ok(SolveStats {
                iterations: it,
                rel_residual: rnorm / bnorm,
            });
        }
        rhat.copy_from_slice(&r);
        let (mut rho, mut alpha, mut omega) = (1.0f64, 1.0f64, 1.0f64);
        p.iter_mut().for_each(|e| *e = 0.0);
        v.iter_mut().for_each(|e| *e = 0.0);
        // rhat . r of the coming iteration (the last one's update computes it with |r|).
        let mut rho_next = dot(&rhat, &r);
        loop {
            if it >= opts.max_iter {
                return Err(SolveError::NotConverged {
                    iterations: it,
                    rel_residual: rnorm / bnorm,
                });
            }
            it += 1;
            let rho_new = rho_next;
            if rho_new == 0.0 || !rho_new.is_finite() {
                return Err(breakdown("rho", it, rho_new, rnorm / bnorm));
            }
            let beta = (rho_new / rho) * (alpha / omega);
            rho = rho_new;
            p.par_iter_mut()
                .zip(r.par_iter().zip(v.par_iter()))
                .with_min_len(ROW_CHUNK)
                .for_each(|(p, (r, v))| *p = r + beta * (*p - omega * v));
            m.apply(a, &p, &mut y);
            a.matvec(&y, &mut v);
            let rv = dot(&rhat, &v);
            if rv == 0.0 || !rv.is_finite() {
                return Err(breakdown("rho", it, rv, rnorm / bnorm));
            }
            alpha = rho / rv;
            // s = r - alpha v and |s|^2, one pass.
            let [ss] = chunked_sums(&mut s, |c, s| {
                for (k, si) in s.iter_mut().enumerate() {
                    *si = r[c + k] - alpha * v[c + k];
                }
                [chunk_dot(s, s)]
            });
            let snorm = ss.sqrt();
            if snorm <= target {
                x.par_iter_mut()
                    .zip(y.par_iter())
                    .with_min_len(ROW_CHUNK)
                    .for_each(|(x, y)| *x += alpha * y);
                break;
            }
            m.apply(a, &s, &mut z);
            a.matvec(&z, &mut t);
            // t . t and t . s, one pass.
            let parts: Vec<[f64; 2]> = t
                .par_chunks(DOT_CHUNK)
                .zip(s.par_chunks(DOT_CHUNK))
                .map(|(t, s)| [chunk_dot(t, t), chunk_dot(t, s)])
                .collect();
            let tt: f64 = parts.iter().map(|q| q[0]).sum();
            omega = if tt > 0.0 {
                parts.iter().map(|q| q[1]).sum::<f64>() / tt
            } else {
                0.0
            };
            if omega == 0.0 || !omega.is_finite() {
                return Err(breakdown("omega", it, omega, snorm / bnorm));
            }
            // x += alpha y + omega z, r = s - omega t, |r|^2 and the next rhat . r, one pass.
            let parts: Vec<[f64; 2]> = x
                .par_chunks_mut(DOT_CHUNK)
                .zip(r.par_chunks_mut(DOT_CHUNK))
                .enumerate()
                .map(|(c, (xc, rc))| {
                    let c = c * DOT_CHUNK;
                    for (k, (xi, ri)) in xc.iter_mut().zip(rc.iter_mut()).enumerate() {
                        *xi += alpha * y[c + k] + omega * z[c + k];
                        *ri = s[c + k] - omega * t[c + k];
                    }
                    [chunk_dot(rc, rc), chunk_dot(&rhat[c..c + rc.len()], rc)]
                })
                .collect();
            rnorm = parts.iter().map(|q| q[0]).sum::<f64>().sqrt();
            rho_next = parts.iter().map(|q| q[1]).sum();
            if !rnorm.is_finite() {
                return Err(SolveError::NonFinite { iteration: it });
            }
            if rnorm <= target {
                break;
            }
        }
        rnorm = true_residual(x, &mut r);
        if !rnorm.is_finite() {
            return Err(SolveError::NonFinite { iteration: it });
        }
    }
}

/// The sum of `x_i y_i` over one chunk, in order: a chunk's partial sum of [`dot`], so that
/// sums fused with a vector update give the same bits as [`dot`] after it.
#[inline]
fn chunk_dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>()
}

/// Run `f(start, chunk)` on `out` in the fixed chunks of [`DOT_CHUNK`] entries in parallel and
/// add its `K` partial sums in chunk order (as [`dot`] does).
fn chunked_sums<const K: usize>(
    out: &mut [f64],
    f: impl Fn(usize, &mut [f64]) -> [f64; K] + Sync,
) -> [f64; K] {
    let parts: Vec<[f64; K]> = out
        .par_chunks_mut(DOT_CHUNK)
        .enumerate()
        .map(|(c, o)| f(c * DOT_CHUNK, o))
        .collect();
    let mut sums = [0.0; K];
    for (k, sum) in sums.iter_mut().enumerate() {
        *sum = parts.iter().map(|q| q[k]).sum();
    }
    sums
}

fn breakdown(quantity: &'static str, iteration: usize, value: f64, rel: f64) -> SolveError {
    if value.is_finite() {
        SolveError::Breakdown {
            quantity,
            iteration,
            rel_residual: rel,
        }
    } else {
        SolveError::NonFinite { iteration }
    }
}
