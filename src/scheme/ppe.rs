//! The pressure Poisson equation of incompressible SPH (King & Lind 2021 eq. (25)) and the
//! implicit viscous step, as sparse linear systems, and their solver.
//!
//! # The systems
//! Both are built from the Morris, Fox & Zhu 1997 Laplacian (King & Lind 2021 eq. (21)),
//! `<lap phi>_i = sum_j c_ij (phi_i - phi_j)` with per-pair coefficients
//! `c_ij = 2 V_j (x_ij . grad W_ij) / |x_ij|^2` ([`morris_coefficients`]). The *uncorrected*
//! kernel gradient is King's code's choice: it keeps `c_ij = c_ji` for equal volumes, so the
//! matrix is symmetric (the Bonet & Lok 1999 corrected gradient of eq. (22) can be passed
//! instead). King's code, like Morris et al., regularises the denominator as r^2 + 0.01 h^2; we
//! do not: `x_ij . grad W_ij / r^2 = (1/r) dW/dr` is finite for the quintic, and the
//! regularisation biases the operator. Measured on a lattice channel (h = 1.3 dr, the
//! relative error of lap cos(kx)cos(ly) as in test `morris_laplacian_is_second_order_with_mirror_walls`): with it the relative error stalls at 0.8 % (1.3e-2,
//! 9.2e-3, 7.8e-3 at 20, 40, 80 particles per unit); without it, 7.1e-3, 1.8e-3, 2.1e-5.
//! * PPE: `lap p = b` with `b_i = (rho / dt) div u*_i`, stored as `-lap p = -b` so the diagonal
//!   is positive ([`assemble_poisson`]).
//! * Implicit viscosity: `(I - dt nu lap) u = rhs` ([`assemble_helmholtz`]), one velocity component
//!   per solve, sharing the matrix and its preconditioner ([`solve_viscous`]).
//!
//! Rows belong to fluid particles `0..n_fluid`. Neighbours with index >= `n_fluid` are ghosts
//! (King & Lind's mirror particles, section III.C) whose value follows their fluid parent
//! affinely, `phi_m = sign phi_parent + offset_m` ([`GhostLink`]): Neumann pressure
//! (sign +1, offset the optional hydrostatic correction) or no-slip velocity (sign -1, offset
//! 2 u_wall). A fluid particle on the free surface gets a Dirichlet row `phi_i = g_i` (the value of
//! eq. (35a), or 0) and its column is moved to the right-hand side of its neighbours' rows, so a
//! symmetric Laplacian stays symmetric. A system without any Dirichlet row (a closed or periodic
//! domain) has the constant null space of the pure-Neumann Laplacian: as King's code does, the
//! mean of the right-hand side is subtracted (the compatibility condition for a symmetric matrix);
//! the null space is then fixed by pinning one row (`p_anchor = 0`), and the solution is shifted
//! to zero mean afterwards. No noise is added to the diagonal.
//!
//! # The solver
//! Preconditioned BiCGStab (van der Vorst 1992; the method King & Lind use) with a choice of
//! preconditioner ([`Preconditioner`]) and an optional warm start. Convergence is declared when
//! the *true* residual `|b - A x|` is at most `rel_tol |b|` (= `rel_tol` times the initial
//! residual of a cold start, King's code's test; the same absolute target with a warm start); if
//! the recursive residual says converged but the true one does not, the iteration restarts from
//! the current iterate. Anything else is an error naming its cause ([`SolveError`]): the
//! iteration cap, a breakdown of rho or omega, a zero pivot, a non-finite value. A wrong pressure
//! is never returned silently.
//!
//! Determinism: the matrix-vector product is row-parallel (each row a sequential sum in column
//! order); every dot product and norm is summed in fixed chunks of [`DOT_CHUNK`] entries whose
//! partial sums are added sequentially; the preconditioners' triangular solves are sequential.
//! Results are bitwise identical whatever the rayon thread count.
//!
//! # Measured (`cargo run --release --example ppe_bench`, 2-core VM, 2 threads)
//! Disc of particles on a square lattice (and the same lattice displaced by up to +/-0.15 dr),
//! quintic kernel h = 1.3 dr, outer ring Dirichlet; "channel": periodic in x, mirror walls, no
//! Dirichlet row (null space pinned). Warm start: the solution of the previous step (positions
//! moved by 0.01 dr, right-hand side changed by ~1 %). Tolerance 1e-8. BiCGStab iterations /
//! ms per solve (assembly from given coefficients and preconditioner set-up included; the
//! machine had a load average of ~14 from other builds, so times are indicative, iterations
//! exact):
//!
//! | case | N | Jacobi | Jacobi warm | SSOR | ILU(0) | ILU(0) warm |
//! |---|---|---|---|---|---|---|
//! | disc lattice | 1288 | 45 / 3.5 | 38 / 7.3 | 24 / 6.0 | 9 / 3.0 | 8 / 6.8 |
//! | disc disordered | 1288 | 48 / 5.6 | 41 / 8.6 | 24 / 9.8 | 8 / 3.3 | 7 / 2.7 |
//! | disc lattice | 5008 | 85 / 74 | 72 / 64 | 41 / 111 | 17 / 56 | 12 / 49 |
//! | disc disordered | 5008 | 87 / 92 | 80 / 77 | 42 / 126 | 15 / 58 | 12 / 45 |
//! | disc lattice | 20008 | 171 / 571 | 143 / 506 | 78 / 755 | 34 / 393 | 26 / 369 |
//! | disc disordered | 20008 | 163 / 925 | 149 / 440 | 76 / 709 | 30 / 305 | 26 / 289 |
//! | channel lattice | 5000 | 151 / 88 | 119 / 71 | 62 / 96 | 24 / 41 | 20 / 47 |
//! | channel disordered | 5000 | 165 / 106 | 171 / 108 | 76 / 144 | 26 / 48 | 29 / 50 |
//!
//! The same systems through `faer` 0.24 (sparse Cholesky, sequential so deterministic; factor +
//! solve, residual ~1e-15): 8-10 ms (1288), 51-57 ms (5008), 470-530 ms (20008), 54 ms for the
//! lattice channel; the disordered channel is not exactly symmetric (mirror pairs), and faer's
//! sparse LU took 670 ms there (540-3700 ms elsewhere). So a direct Cholesky is competitive with
//! ILU(0)-BiCGStab but not faster, needs exact symmetry (which the Bonet-Lok corrected Laplacian
//! or disordered mirrors break) and a heavy dependency (22 min to build on this machine);
//! SSOR halves Jacobi's iterations but its sweeps cost more than they save. Choice: BiCGStab
//! with ILU(0), 4-6x fewer iterations than Jacobi and 1.5-3x faster, warm started from the last
//! pressure (10-25 % fewer iterations).

use crate::kernel::Kernel;
use crate::neighbors::{Domain, NeighborList};
use crate::{Mat2, Vec2};
use rayon::prelude::*;
use thiserror::Error;

/// Chunk length of the fixed-order reductions (dot products, norms).
pub const DOT_CHUNK: usize = 2048;
/// Rows per parallel task in the matrix-vector product.
const ROW_CHUNK: usize = 256;

/// Morris, Fox & Zhu 1997 Laplacian coefficients (King & Lind 2021 eq. (21)) for every stored
/// pair of `nl` (aligned with its flat pair arrays): `c_ij = 2 V_j (x_ij . g_ij) / r^2`, with
/// `g_ij = grad_i W_ij` or, when `correction` is given, the Bonet & Lok 1999 corrected
/// `L_i grad_i W_ij` (eq. (22)). `c_ij <= 0` (uncorrected); the self pair gives 0.
///
/// `x` and `vol` cover every point the lists refer to (fluid then ghosts); the lists' query
/// points are the first `nl.len()` entries of `x`. Pair vectors go through `domain`.
pub fn morris_coefficients<K: Kernel>(
    x: &[Vec2],
    vol: &[f64],
    nl: &NeighborList,
    kernel: &K,
    domain: &Domain,
    correction: Option<&[Mat2]>,
) -> Vec<f64> {
    let mut c = vec![0.0; nl.pairs()];
    nl.split_mut(&mut c)
        .into_par_iter()
        .enumerate()
        .for_each(|(i, out)| {
            for (o, &j) in out.iter_mut().zip(nl.of(i)) {
                let j = j as usize;
                let xij = domain.delta(&x[i], &x[j]);
                let r2 = xij.norm_squared();
                if j == i || r2 == 0.0 {
                    *o = 0.0;
                    continue;
                }
                // x_ij . grad W_ij / r^2 = (1/r) dW/dr: finite for a smooth kernel, so no
                // regularisation of the denominator is needed.
                let mut f = kernel.dw_over_r(r2.sqrt());
                if let Some(l) = correction {
                    f *= xij.dot(&(l[i] * xij)) / r2;
                }
                *o = 2.0 * vol[j] * f;
            }
        });
    c
}

/// A sparse matrix in compressed-row form, columns ascending within a row, the diagonal always
/// stored.
#[derive(Debug, Clone, PartialEq)]
pub struct CsrMatrix {
    /// `row_ptr[i]..row_ptr[i+1]` indexes `col` and `val` for row i.
    pub row_ptr: Vec<usize>,
    pub col: Vec<u32>,
    pub val: Vec<f64>,
    /// Position of the diagonal entry of each row in `col`/`val`.
    pub diag: Vec<usize>,
}

impl CsrMatrix {
    /// Build from per-row (column, value) lists; duplicate columns are summed in list order and
    /// a zero diagonal is inserted where missing.
    pub fn from_rows(rows: Vec<Vec<(u32, f64)>>) -> Self {
        let n = rows.len();
        let mut row_ptr = Vec::with_capacity(n + 1);
        let mut col = Vec::new();
        let mut val = Vec::new();
        let mut diag = Vec::with_capacity(n);
        row_ptr.push(0);
        for (i, mut r) in rows.into_iter().enumerate() {
            r.push((i as u32, 0.0));
            // Stable: duplicates keep their order, so their sum is in a fixed order.
            r.sort_by_key(|e| e.0);
            let mut d = usize::MAX;
            for (c, v) in r {
                if col.len() > *row_ptr.last().expect("non-empty")
                    && *col.last().expect("non-empty") == c
                {
                    *val.last_mut().expect("non-empty") += v;
                } else {
                    if c as usize == i {
                        d = col.len();
                    }
                    col.push(c);
                    val.push(v);
                }
            }
            diag.push(d);
            row_ptr.push(col.len());
        }
        Self {
            row_ptr,
            col,
            val,
            diag,
        }
    }

    /// Number of rows (= columns).
    pub fn n(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.col.len()
    }

    /// Entries of row i: (columns, values).
    #[inline]
    pub fn row(&self, i: usize) -> (&[u32], &[f64]) {
        let (a, b) = (self.row_ptr[i], self.row_ptr[i + 1]);
        (&self.col[a..b], &self.val[a..b])
    }

    /// y = A x, row-parallel, each row summed in column order.
    pub fn matvec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.n());
        assert_eq!(y.len(), self.n());
        y.par_chunks_mut(ROW_CHUNK)
            .enumerate()
            .for_each(|(c, out)| {
                for (k, yi) in out.iter_mut().enumerate() {
                    let (cols, vals) = self.row(c * ROW_CHUNK + k);
                    let mut s = 0.0;
                    for (&j, &a) in cols.iter().zip(vals) {
                        s += a * x[j as usize];
                    }
                    *yi = s;
                }
            });
    }

    /// Diagonal entries.
    pub fn diagonal(&self) -> Vec<f64> {
        self.diag.iter().map(|&d| self.val[d]).collect()
    }
}

/// How the value at a ghost point (index >= `n_fluid` in the neighbour lists) follows from its
/// fluid parent: `phi_m = sign_m * phi[parent[m - n_fluid]] + offset[m - n_fluid]`.
#[derive(Debug, Clone, Copy)]
pub struct GhostLink<'a> {
    /// Fluid parent of each ghost.
    pub parent: &'a [u32],
    /// Per-ghost sign: +1 for a Neumann (mirrored) value such as the pressure, or a periodic
    /// image; -1 for a no-slip velocity across a wall. Empty = all +1.
    pub sign: &'a [f64],
    /// Per-ghost additive term (hydrostatic correction; 2 u_wall for no slip). Empty = zeros.
    pub offset: &'a [f64],
}

impl GhostLink<'_> {
    /// No ghost points.
    pub const NONE: GhostLink<'static> = GhostLink {
        parent: &[],
        sign: &[],
        offset: &[],
    };

    /// (parent, sign, offset) of ghost m (counted from the first ghost).
    #[inline]
    fn link(&self, m: usize) -> (usize, f64, f64) {
        (
            self.parent[m] as usize,
            self.sign.get(m).copied().unwrap_or(1.0),
            self.offset.get(m).copied().unwrap_or(0.0),
        )
    }
}

/// A linear system ready to solve, with what is needed to recover the physical solution.
#[derive(Debug, Clone)]
pub struct LinearSystem {
    pub matrix: CsrMatrix,
    pub rhs: Vec<f64>,
    /// Some(row) when the system had the constant null space and `row` was pinned to 0; the
    /// solution is then shifted to zero mean.
    pub anchor: Option<usize>,
    /// Identity rows (Dirichlet values and the anchor), set exactly after the solve.
    pub fixed: Vec<usize>,
}

/// Assemble `diag_shift phi_i + lap_scale sum_j c_ij (phi_i - phi_j) = b_i` for the fluid rows,
/// with ghosts eliminated through `ghosts` and Dirichlet rows where `dirichlet[i]` is `Some`.
#[allow(clippy::too_many_arguments)]
fn assemble(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    diag_shift: f64,
    lap_scale: f64,
    ghosts: &GhostLink,
    dirichlet: &[Option<f64>],
    b: &[f64],
) -> (Vec<Vec<(u32, f64)>>, Vec<f64>) {
    assert!(nl.len() >= n_fluid, "one neighbour list per fluid particle");
    assert_eq!(coef.len(), nl.pairs());
    assert_eq!(b.len(), n_fluid);
    assert!(dirichlet.is_empty() || dirichlet.len() == n_fluid);
    assert!(ghosts.offset.is_empty() || ghosts.offset.len() == ghosts.parent.len());
    assert!(ghosts.sign.is_empty() || ghosts.sign.len() == ghosts.parent.len());
    let fixed = |k: usize| dirichlet.get(k).copied().flatten();
    (0..n_fluid)
        .into_par_iter()
        .map(|i| {
            if let Some(g) = fixed(i) {
                return (vec![(i as u32, 1.0)], g);
            }
            let off = nl.offset(i);
            let mut row = Vec::with_capacity(nl.of(i).len() + 1);
            let mut diag = diag_shift;
            let mut rhs = b[i];
            for (k, &j) in nl.of(i).iter().enumerate() {
                let j = j as usize;
                let a = lap_scale * coef[off + k];
                if j == i || a == 0.0 {
                    continue;
                }
                // Row: diag_shift phi_i + sum_j a (phi_i - phi_j).
                diag += a;
                let (col, s, shift) = if j < n_fluid {
                    (j, 1.0, 0.0)
                } else {
                    ghosts.link(j - n_fluid)
                };
                // -a phi_j = -a (s phi_col + shift)
                rhs += a * shift;
                if let Some(g) = fixed(col) {
                    rhs += a * s * g;
                } else if col == i {
                    diag -= a * s;
                } else {
                    row.push((col as u32, -a * s));
                }
            }
            row.push((i as u32, diag));
            (row, rhs)
        })
        .unzip()
}

/// The PPE `lap p = b` (King & Lind 2021 eq. (25), `b_i = (rho/dt) div u*_i`), stored as
/// `-lap p = -b` (positive diagonal). `dirichlet[i] = Some(p_s)` for a free-surface particle
/// (eq. (35a)'s value, or 0); empty or all `None` means a closed domain, handled as the module
/// documentation says. Ghost pressures: `ghosts.sign = 1` (Neumann), offset = hydrostatic
/// correction rho g . (r_m - r_i) or empty.
pub fn assemble_poisson(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    ghosts: &GhostLink,
    dirichlet: &[Option<f64>],
    b: &[f64],
) -> LinearSystem {
    let neg_b: Vec<f64> = b.iter().map(|v| -v).collect();
    let (mut rows, mut rhs) = assemble(n_fluid, nl, coef, 0.0, -1.0, ghosts, dirichlet, &neg_b);
    let closed = n_fluid > 0 && dirichlet.iter().all(|d| d.is_none());
    let mut anchor = None;
    if closed {
        // Compatibility: the constant vector spans the null space of the (symmetric) matrix, so
        // the right-hand side must have zero sum. Summed in fixed chunks.
        let mean = fixed_sum(&rhs) / n_fluid as f64;
        rhs.iter_mut().for_each(|v| *v -= mean);
        // Pin the row with the largest diagonal (best connected; lowest index on ties).
        let a = (0..n_fluid)
            .max_by(|&p, &q| {
                let dp = rows[p]
                    .iter()
                    .find(|e| e.0 as usize == p)
                    .map_or(0.0, |e| e.1);
                let dq = rows[q]
                    .iter()
                    .find(|e| e.0 as usize == q)
                    .map_or(0.0, |e| e.1);
                dp.total_cmp(&dq).then(q.cmp(&p))
            })
            .expect("n_fluid > 0");
        // p_a = 0: its column drops out of the other rows (times 0), keeping the symmetry.
        for r in rows.iter_mut() {
            r.retain(|e| e.0 as usize != a);
        }
        rows[a] = vec![(a as u32, 1.0)];
        rhs[a] = 0.0;
        anchor = Some(a);
    }
    let fixed = (0..n_fluid)
        .filter(|&i| {
            rows[i].len() == 1
                && rows[i][0] == (i as u32, 1.0)
                && (dirichlet.get(i).copied().flatten().is_some() || anchor == Some(i))
        })
        .collect();
    LinearSystem {
        matrix: CsrMatrix::from_rows(rows),
        rhs,
        anchor,
        fixed,
    }
}

/// The implicit viscous system `(I - dt nu lap) u = rhs` for one velocity component (the
/// solvent viscosity step that lifts the explicit limit rho h^2 / eta0 of King & Lind 2021
/// eq. (28)). Ghost velocities: no slip across a wall, sign -1 and offset 2 u_wall (this
/// component).
/// No Dirichlet rows: free-surface particles keep their truncated stencil, as in the explicit
/// predictor (24).
pub fn assemble_helmholtz(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    dt_nu: f64,
    ghosts: &GhostLink,
    rhs: &[f64],
) -> LinearSystem {
    let (rows, rhs) = assemble(n_fluid, nl, coef, 1.0, -dt_nu, ghosts, &[], rhs);
    LinearSystem {
        matrix: CsrMatrix::from_rows(rows),
        rhs,
        anchor: None,
        fixed: Vec::new(),
    }
}

/// Preconditioners for BiCGStab.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preconditioner {
    /// Diagonal scaling (King & Lind's choice).
    Jacobi,
    /// Symmetric successive over-relaxation with omega = 1 (symmetric Gauss-Seidel).
    Ssor,
    /// Incomplete LU factorisation with the matrix's own sparsity pattern.
    Ilu0,
}

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

/// Sum of a slice in fixed chunks, the partial sums added in order (thread-count independent).
pub fn fixed_sum(a: &[f64]) -> f64 {
    let parts: Vec<f64> = a
        .par_chunks(DOT_CHUNK)
        .map(|c| c.iter().sum::<f64>())
        .collect();
    parts.iter().sum()
}

/// Dot product in fixed chunks (thread-count independent).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    let parts: Vec<f64> = a
        .par_chunks(DOT_CHUNK)
        .zip(b.par_chunks(DOT_CHUNK))
        .map(|(x, y)| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>())
        .collect();
    parts.iter().sum()
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
}

impl Factor {
    /// Set up the preconditioner of `a`.
    pub fn new(a: &CsrMatrix, kind: Preconditioner) -> Result<Self, SolveError> {
        let n = a.n();
        let inv_diag = |a: &CsrMatrix| -> Result<Vec<f64>, SolveError> {
            (0..n)
                .map(|i| {
                    let d = a.val[a.diag[i]];
                    if d == 0.0 || !d.is_finite() {
                        Err(SolveError::ZeroPivot { row: i })
                    } else {
                        Ok(1.0 / d)
                    }
                })
                .collect()
        };
        match kind {
            Preconditioner::Jacobi => Ok(Factor::Jacobi(inv_diag(a)?)),
            Preconditioner::Ssor => Ok(Factor::Ssor(inv_diag(a)?)),
            Preconditioner::Ilu0 => {
                // IKJ variant (Saad 2003, Algorithm 10.4), sequential in row order.
                let mut lu = a.val.clone();
                let mut pos = vec![usize::MAX; n];
                for i in 0..n {
                    let (s, e) = (a.row_ptr[i], a.row_ptr[i + 1]);
                    for p in s..e {
                        pos[a.col[p] as usize] = p;
                    }
                    for p in s..a.diag[i] {
                        let k = a.col[p] as usize;
                        let ukk = lu[a.diag[k]];
                        if ukk == 0.0 || !ukk.is_finite() {
                            return Err(SolveError::ZeroPivot { row: k });
                        }
                        let lik = lu[p] / ukk;
                        lu[p] = lik;
                        for q in a.diag[k] + 1..a.row_ptr[k + 1] {
                            let t = pos[a.col[q] as usize];
                            if t != usize::MAX {
                                lu[t] -= lik * lu[q];
                            }
                        }
                    }
                    for p in s..e {
                        pos[a.col[p] as usize] = usize::MAX;
                    }
                    let d = lu[a.diag[i]];
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
            Factor::Ilu0(lu) => {
                for i in 0..n {
                    let mut s = r[i];
                    for p in a.row_ptr[i]..a.diag[i] {
                        s -= lu[p] * z[a.col[p] as usize];
                    }
                    z[i] = s;
                }
                for i in (0..n).rev() {
                    let mut s = z[i];
                    for p in a.diag[i] + 1..a.row_ptr[i + 1] {
                        s -= lu[p] * z[a.col[p] as usize];
                    }
                    z[i] = s / lu[a.diag[i]];
                }
            }
        }
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
        loop {
            if it >= opts.max_iter {
                return Err(SolveError::NotConverged {
                    iterations: it,
                    rel_residual: rnorm / bnorm,
                });
            }
            it += 1;
            let rho_new = dot(&rhat, &r);
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
            s.par_iter_mut()
                .zip(r.par_iter().zip(v.par_iter()))
                .with_min_len(ROW_CHUNK)
                .for_each(|(s, (r, v))| *s = r - alpha * v);
            let snorm = dot(&s, &s).sqrt();
            if snorm <= target {
                x.par_iter_mut()
                    .zip(y.par_iter())
                    .with_min_len(ROW_CHUNK)
                    .for_each(|(x, y)| *x += alpha * y);
                break;
            }
            m.apply(a, &s, &mut z);
            a.matvec(&z, &mut t);
            let tt = dot(&t, &t);
            omega = if tt > 0.0 { dot(&t, &s) / tt } else { 0.0 };
            if omega == 0.0 || !omega.is_finite() {
                return Err(breakdown("omega", it, omega, snorm / bnorm));
            }
            x.par_iter_mut()
                .zip(y.par_iter().zip(z.par_iter()))
                .with_min_len(ROW_CHUNK)
                .for_each(|(x, (y, z))| *x += alpha * y + omega * z);
            r.par_iter_mut()
                .zip(s.par_iter().zip(t.par_iter()))
                .with_min_len(ROW_CHUNK)
                .for_each(|(r, (s, t))| *r = s - omega * t);
            rnorm = dot(&r, &r).sqrt();
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

/// Solve an assembled system from the start `x` (warm start; zeros for a cold one). A pinned
/// system (closed domain) gets its start shifted so the anchor is 0 and its solution shifted to
/// zero mean.
pub fn solve(
    sys: &LinearSystem,
    x: &mut [f64],
    opts: &SolverOptions,
) -> Result<SolveStats, SolveError> {
    let m = Factor::new(&sys.matrix, opts.preconditioner)?;
    solve_with(sys, &m, x, opts)
}

/// [`solve`] with a preconditioner already set up for `sys.matrix`.
pub fn solve_with(
    sys: &LinearSystem,
    m: &Factor,
    x: &mut [f64],
    opts: &SolverOptions,
) -> Result<SolveStats, SolveError> {
    if let Some(a) = sys.anchor {
        let s = x[a];
        x.iter_mut().for_each(|v| *v -= s);
    }
    let stats = bicgstab(&sys.matrix, m, &sys.rhs, x, opts)?;
    // Dirichlet rows are identity rows: give them their value exactly, not to the tolerance.
    for &i in &sys.fixed {
        x[i] = sys.rhs[i];
    }
    if sys.anchor.is_some() {
        let mean = fixed_sum(x) / x.len() as f64;
        x.iter_mut().for_each(|v| *v -= mean);
    }
    Ok(stats)
}

/// Implicit viscous step for both velocity components: `(I - dt nu lap) u = rhs`, one matrix
/// and one preconditioner, two solves. `u` holds the start (e.g. the explicit prediction) on
/// entry. Ghost m's velocity is `ghost_sign[m] u_parent + ghost_offset[m]`: a no-slip mirror
/// has sign -1 and offset 2 u_wall, a periodic image sign +1 and offset 0 (empty = all +1 / 0).
#[allow(clippy::too_many_arguments)]
pub fn solve_viscous(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    dt_nu: f64,
    ghost_parent: &[u32],
    ghost_sign: &[f64],
    ghost_offset: &[Vec2],
    rhs: &[Vec2],
    u: &mut [Vec2],
    opts: &SolverOptions,
) -> Result<[SolveStats; 2], SolveError> {
    let mut stats = [SolveStats {
        iterations: 0,
        rel_residual: 0.0,
    }; 2];
    let mut factor: Option<(LinearSystem, Factor)> = None;
    for (c, st) in stats.iter_mut().enumerate() {
        let off: Vec<f64> = ghost_offset.iter().map(|w| w[c]).collect();
        let b: Vec<f64> = rhs.iter().map(|r| r[c]).collect();
        let ghosts = GhostLink {
            parent: ghost_parent,
            sign: ghost_sign,
            offset: &off,
        };
        let sys = assemble_helmholtz(n_fluid, nl, coef, dt_nu, &ghosts, &b);
        let m = match factor.take() {
            Some((_, m)) => m,
            None => Factor::new(&sys.matrix, opts.preconditioner)?,
        };
        let mut x: Vec<f64> = u.iter().map(|v| v[c]).collect();
        *st = solve_with(&sys, &m, &mut x, opts)?;
        for (ui, xi) in u.iter_mut().zip(&x) {
            ui[c] = *xi;
        }
        factor = Some((sys, m));
    }
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::QuinticSpline;
    use crate::operators::fixtures::{channel, disc, ParticleSet};
    use std::f64::consts::PI;

    fn kernel(dr: f64) -> QuinticSpline {
        QuinticSpline::new(1.3 * dr)
    }

    fn coefs(set: &ParticleSet) -> (NeighborList, Vec<f64>) {
        let k = kernel(set.dr);
        let nl = set.neighbours(k.radius());
        let vol = vec![set.dr * set.dr; set.x.len()];
        let c = morris_coefficients(&set.x, &vol, &nl, &k, &Domain::OPEN, None);
        (nl, c)
    }

    /// sum_j c_ij (phi_i - phi_j) evaluated directly from the pair coefficients.
    fn laplacian(nl: &NeighborList, c: &[f64], phi: &dyn Fn(usize) -> f64, i: usize) -> f64 {
        let off = nl.offset(i);
        nl.of(i)
            .iter()
            .enumerate()
            .map(|(k, &j)| c[off + k] * (phi(i) - phi(j as usize)))
            .sum()
    }

    fn all_options() -> [SolverOptions; 3] {
        [
            Preconditioner::Jacobi,
            Preconditioner::Ssor,
            Preconditioner::Ilu0,
        ]
        .map(|p| SolverOptions {
            preconditioner: p,
            ..Default::default()
        })
    }

    /// Disc with the outer ring Dirichlet, p = x^2 + y^2 (lap p = 4): the solve reaches the
    /// tolerance with every preconditioner, the solution satisfies the SPH equations row by row,
    /// and it is the exact field to within the Morris Laplacian's discretisation error.
    #[test]
    fn dirichlet_disc_recovers_a_quadratic_pressure() {
        let dr = 0.05;
        let radius = 20.0 * dr;
        let set = disc(radius, dr, 0.1, 1);
        let (nl, c) = coefs(&set);
        let exact = |x: &Vec2| x.norm_squared();
        let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
            .iter()
            .map(|x| (x.norm() > radius - 3.0 * dr).then(|| exact(x)))
            .collect();
        let b = vec![4.0; set.n_fluid];
        let sys = assemble_poisson(set.n_fluid, &nl, &c, &GhostLink::NONE, &dir, &b);
        assert!(sys.anchor.is_none());
        for opts in all_options() {
            let mut p = vec![0.0; set.n_fluid];
            let st = solve(&sys, &mut p, &opts).unwrap();
            assert!(st.rel_residual <= 1e-8, "{st:?}");
            assert!(st.iterations > 1 && st.iterations < 200, "{st:?}");
            let mut worst = 0.0f64;
            for i in 0..set.n_fluid {
                if let Some(g) = dir[i] {
                    assert_eq!(p[i], g);
                    continue;
                }
                let full = |j: usize| p[j];
                let lap = laplacian(&nl, &c, &full, i);
                assert!((lap - 4.0).abs() < 1e-5, "row {i}: lap = {lap}");
                worst = worst.max((p[i] - exact(&set.x[i])).abs());
            }
            // Range of p is radius^2 = 1; the jittered lattice's Laplacian error is a few %.
            assert!(worst < 0.03 * radius * radius, "{worst}");
        }
    }

    /// With equal volumes and the uncorrected gradient, the assembled PPE matrix is symmetric
    /// with a positive diagonal (Dirichlet columns moved to the right-hand side).
    #[test]
    fn poisson_matrix_is_symmetric() {
        let dr = 0.1;
        let set = disc(8.0 * dr, dr, 0.15, 2);
        let (nl, c) = coefs(&set);
        let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
            .iter()
            .map(|x| (x.norm() > 7.0 * dr).then_some(0.0))
            .collect();
        let sys = assemble_poisson(
            set.n_fluid,
            &nl,
            &c,
            &GhostLink::NONE,
            &dir,
            &vec![1.0; set.n_fluid],
        );
        let a = &sys.matrix;
        let get = |i: usize, j: usize| {
            let (cols, vals) = a.row(i);
            cols.iter()
                .position(|&c| c as usize == j)
                .map_or(0.0, |p| vals[p])
        };
        for i in 0..a.n() {
            assert!(a.val[a.diag[i]] > 0.0);
            let (cols, vals) = a.row(i);
            assert!(cols.windows(2).all(|w| w[0] < w[1]));
            for (&j, &v) in cols.iter().zip(vals) {
                let t = get(j as usize, i);
                assert!(
                    (v - t).abs() <= 1e-12 * v.abs(),
                    "A[{i},{j}] = {v}, A[{j},{i}] = {t}"
                );
            }
        }
    }

    /// Closed domain (periodic channel, Neumann walls through mirrors): p = cos(2 pi x / L)
    /// cos(pi y / H) has zero normal derivative at the walls and lap p = -k^2 p. A constant is
    /// added to the right-hand side (which an incompatible solve would turn into garbage): the
    /// mean is removed, the null space pinned, the zero-mean solution matches the exact one.
    #[test]
    fn closed_channel_solution_is_the_exact_one_up_to_discretisation() {
        let error = |n: usize, opts: &SolverOptions| {
            let dr = 1.0 / n as f64;
            let (nx, ny) = (2 * n, n);
            let (l, h) = (nx as f64 * dr, ny as f64 * dr);
            let set = channel(nx, ny, dr, 0.0, 3.0 * 1.3 * dr, 3);
            let (nl, c) = coefs(&set);
            let k2 = (2.0 * PI / l).powi(2) + (PI / h).powi(2);
            let exact = |x: &Vec2| (2.0 * PI * x.x / l).cos() * (PI * x.y / h).cos();
            let b: Vec<f64> = set.x[..set.n_fluid]
                .iter()
                .map(|x| -k2 * exact(x) + 0.7)
                .collect();
            let ghosts = GhostLink {
                parent: &set.parent,
                sign: &[],
                offset: &[],
            };
            let sys = assemble_poisson(set.n_fluid, &nl, &c, &ghosts, &[], &b);
            assert!(sys.anchor.is_some());
            let mut p = vec![0.0; set.n_fluid];
            solve(&sys, &mut p, opts).unwrap();
            assert!(fixed_sum(&p).abs() < 1e-10 * set.n_fluid as f64);
            (0..set.n_fluid)
                .map(|i| (p[i] - exact(&set.x[i])).abs())
                .fold(0.0, f64::max)
        };
        for opts in all_options() {
            let (coarse, fine) = (error(20, &opts), error(40, &opts));
            // Second order: the Morris Laplacian's lattice error is O((k h)^2).
            assert!(coarse < 0.01 && fine < 0.3 * coarse, "{coarse} {fine}");
        }
    }

    /// Implicit viscosity with no-slip mirrors: a very large dt nu gives the steady Couette
    /// profile u = U y / H (bottom wall at rest, top wall moving at U), which the mirrored Morris
    /// Laplacian holds exactly on a lattice; dt nu -> 0 returns the right-hand side.
    #[test]
    fn implicit_viscous_step_reaches_couette_and_keeps_wall_velocity() {
        let dr = 0.1;
        let (nx, ny) = (12, 10);
        let h = ny as f64 * dr;
        let set = channel(nx, ny, dr, 0.0, 3.0 * 1.3 * dr, 4);
        let (nl, c) = coefs(&set);
        let u_top = Vec2::new(2.0, 0.0);
        let offset: Vec<Vec2> = (0..set.parent.len())
            .map(|m| {
                let y = set.x[set.n_fluid + m].y;
                if set.reflected[m] && y > h {
                    2.0 * u_top
                } else {
                    Vec2::zeros()
                }
            })
            .collect();
        let sign = set.signs_no_slip();
        let n = set.n_fluid;
        let rhs = vec![Vec2::new(0.3, -0.1); n];
        let opts = SolverOptions::default();
        // Steady limit: dt nu = 1e8 h^2.
        let mut u = vec![Vec2::zeros(); n];
        let st = solve_viscous(
            n,
            &nl,
            &c,
            1e8 * dr * dr,
            &set.parent,
            &sign,
            &offset,
            &rhs,
            &mut u,
            &opts,
        )
        .unwrap();
        assert!(
            st[0].rel_residual <= 1e-8 && st[1].rel_residual <= 1e-8,
            "{st:?}"
        );
        for (x, u) in set.x[..n].iter().zip(&u) {
            let exact = u_top.x * x.y / h;
            assert!((u.x - exact).abs() < 1e-5 * u_top.x, "{} vs {exact}", u.x);
            assert!(u.y.abs() < 1e-5 * u_top.x, "{}", u.y);
        }
        // dt nu = 0: the identity.
        let mut u = vec![Vec2::zeros(); n];
        solve_viscous(
            n,
            &nl,
            &c,
            0.0,
            &set.parent,
            &sign,
            &offset,
            &rhs,
            &mut u,
            &opts,
        )
        .unwrap();
        assert!(u.iter().zip(&rhs).all(|(a, b)| (a - b).norm() < 1e-12));
    }

    #[test]
    fn results_are_bitwise_independent_of_thread_count() {
        let dr = 0.05;
        let set = disc(40.0 * dr, dr, 0.15, 5);
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    let (nl, c) = coefs(&set);
                    let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
                        .iter()
                        .map(|x| (x.norm() > 39.0 * dr).then_some(0.0))
                        .collect();
                    let b: Vec<f64> = set.x[..set.n_fluid]
                        .iter()
                        .map(|x| (7.0 * x.x).sin() + x.y)
                        .collect();
                    let sys = assemble_poisson(set.n_fluid, &nl, &c, &GhostLink::NONE, &dir, &b);
                    all_options()
                        .iter()
                        .map(|o| {
                            let mut p = vec![0.0; set.n_fluid];
                            let st = solve(&sys, &mut p, o).unwrap();
                            (
                                st.iterations,
                                p.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                            )
                        })
                        .collect::<Vec<_>>()
                })
        };
        assert!(set.n_fluid > 2 * DOT_CHUNK, "several reduction chunks");
        assert_eq!(run(1), run(2));
    }

    #[test]
    fn failures_are_errors_with_their_cause() {
        let dr = 0.05;
        let set = disc(20.0 * dr, dr, 0.1, 6);
        let (nl, c) = coefs(&set);
        let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
            .iter()
            .map(|x| (x.norm() > 19.0 * dr).then_some(0.0))
            .collect();
        let sys = assemble_poisson(
            set.n_fluid,
            &nl,
            &c,
            &GhostLink::NONE,
            &dir,
            &vec![1.0; set.n_fluid],
        );
        let opts = SolverOptions {
            max_iter: 3,
            preconditioner: Preconditioner::Jacobi,
            ..Default::default()
        };
        let mut p = vec![0.0; set.n_fluid];
        match solve(&sys, &mut p, &opts) {
            Err(SolveError::NotConverged {
                iterations,
                rel_residual,
            }) => {
                assert_eq!(iterations, 3);
                assert!(rel_residual > 1e-8 && rel_residual.is_finite());
            }
            other => panic!("{other:?}"),
        }
        // [[1, -1], [-1, 1]] with b = (1, 1): rhat . A r = 0 at the first iteration.
        let a = CsrMatrix::from_rows(vec![vec![(0, 1.0), (1, -1.0)], vec![(0, -1.0), (1, 1.0)]]);
        let m = Factor::new(&a, Preconditioner::Jacobi).unwrap();
        let mut x = vec![0.0; 2];
        let e = bicgstab(&a, &m, &[1.0, 1.0], &mut x, &SolverOptions::default()).unwrap_err();
        assert!(
            matches!(
                e,
                SolveError::Breakdown {
                    quantity: "rho",
                    iteration: 1,
                    ..
                }
            ),
            "{e}"
        );
        // A zero diagonal cannot be Jacobi-preconditioned; a NaN right-hand side is refused.
        let z = CsrMatrix::from_rows(vec![vec![(1, 1.0)], vec![(0, 1.0)]]);
        assert_eq!(
            Factor::new(&z, Preconditioner::Jacobi).unwrap_err(),
            SolveError::ZeroPivot { row: 0 }
        );
        let e = bicgstab(&a, &m, &[f64::NAN, 1.0], &mut x, &SolverOptions::default()).unwrap_err();
        assert_eq!(e, SolveError::NonFinite { iteration: 0 });
    }

    /// A warm start from the solution of a nearby system needs fewer iterations for the same
    /// absolute accuracy.
    #[test]
    fn warm_start_saves_iterations() {
        let dr = 0.05;
        let set = disc(20.0 * dr, dr, 0.1, 7);
        let (nl, c) = coefs(&set);
        let dir: Vec<Option<f64>> = set.x[..set.n_fluid]
            .iter()
            .map(|x| (x.norm() > 19.0 * dr).then_some(0.0))
            .collect();
        let b1: Vec<f64> = set.x[..set.n_fluid].iter().map(|x| 1.0 + x.x).collect();
        let b2: Vec<f64> = b1.iter().zip(&set.x).map(|(b, x)| b + 0.01 * x.y).collect();
        let s1 = assemble_poisson(set.n_fluid, &nl, &c, &GhostLink::NONE, &dir, &b1);
        let s2 = assemble_poisson(set.n_fluid, &nl, &c, &GhostLink::NONE, &dir, &b2);
        for o in all_options() {
            let mut p = vec![0.0; set.n_fluid];
            solve(&s1, &mut p, &o).unwrap();
            let warm = solve(&s2, &mut p, &o).unwrap();
            let mut q = vec![0.0; set.n_fluid];
            let cold = solve(&s2, &mut q, &o).unwrap();
            assert!(warm.iterations < cold.iterations, "{warm:?} {cold:?}");
        }
    }

    /// The Morris Laplacian through mirror ghosts (Neumann walls) converges at second order on a
    /// lattice: relative error of lap cos(2 pi x / L) cos(pi y / H) at 20 and 40 particles per H.
    #[test]
    fn morris_laplacian_is_second_order_with_mirror_walls() {
        let err = |n: usize| {
            let dr = 1.0 / n as f64;
            let (l, h) = (2.0, 1.0);
            let set = channel(2 * n, n, dr, 0.0, 3.0 * 1.3 * dr, 3);
            let (nl, c) = coefs(&set);
            let k2 = (2.0 * PI / l).powi(2) + (PI / h).powi(2);
            let f = |x: &Vec2| (2.0 * PI * x.x / l).cos() * (PI * x.y / h).cos();
            let phi = |j: usize| {
                let k = if j < set.n_fluid {
                    j
                } else {
                    set.parent[j - set.n_fluid] as usize
                };
                f(&set.x[k])
            };
            (0..set.n_fluid)
                .map(|i| (laplacian(&nl, &c, &phi, i) + k2 * f(&set.x[i])).abs() / k2)
                .fold(0.0, f64::max)
        };
        let (coarse, fine) = (err(20), err(40));
        assert!(
            coarse < 1e-2 && fine < 0.3 * coarse,
            "{coarse:.3e} {fine:.3e}"
        );
    }

    /// The implicit viscous step damps a Fourier mode by the backward-Euler factor
    /// 1 / (1 + dt nu k^2) at any step size: the mode cos(2 pi x / L), uniform across a periodic
    /// channel with Neumann (sign +1) mirrors, at dt nu k^2 = 0.05, 0.5 and 50 (1000 times the
    /// explicit limit dt nu <= h^2 / 4 or so): amplitude within 0.5 % of the factor, no
    /// overshoot, the y component untouched.
    #[test]
    fn implicit_viscous_step_damps_a_mode_by_the_backward_euler_factor() {
        let dr = 0.02;
        let (nx, ny) = (50, 10);
        let l = nx as f64 * dr;
        let set = channel(nx, ny, dr, 0.0, 3.0 * 1.3 * dr, 8);
        let (nl, c) = coefs(&set);
        let n = set.n_fluid;
        let k = 2.0 * PI / l;
        let rhs: Vec<Vec2> = set.x[..n]
            .iter()
            .map(|x| Vec2::new((k * x.x).cos(), 0.25))
            .collect();
        for a in [0.05, 0.5, 50.0] {
            let dt_nu = a / (k * k);
            let mut u = rhs.clone();
            solve_viscous(
                n,
                &nl,
                &c,
                dt_nu,
                &set.parent,
                &[],
                &[],
                &rhs,
                &mut u,
                &SolverOptions::default(),
            )
            .unwrap();
            let factor = 1.0 / (1.0 + a);
            for (ui, ri) in u.iter().zip(&rhs) {
                assert!(
                    (ui.x - factor * ri.x).abs() < 5e-3 * factor,
                    "a = {a}: {} vs {}",
                    ui.x,
                    factor * ri.x
                );
                assert!((ui.y - 0.25).abs() < 1e-9);
            }
        }
    }
}
