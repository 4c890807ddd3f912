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
//!Determinism: the matrix-vector product is row-parallel (each row a sequential sum in column
//! order); every dot product and norm is summed in fixed chunks of [`DOT_CHUNK`] entries whose
//! partial sums are added sequentially (chunk size independent of the thread count); the
//! assembly gathers each row by itself, in parallel, and [`CsrMatrix::from_rows`] sorts and
//! merges each row by itself (the coupled viscous system is assembled a particle's block row at
//! a time, its neighbours sorted once by column and each block summed in neighbour order: the
//! same entries, bit for bit, without sorting its ~750-entry 3D rows); SSOR's and ILU(0)'s
//! triangular solves are sequential; the multigrid cycle ([`Amg`]) is row-parallel throughout.
//! BiCGStab fuses each vector update with the dot products that follow it into one pass over
//! the same fixed chunks (fewer parallel regions per iteration, the same bits as separate
//! passes). Results are bitwise identical whatever the rayon thread count.
//!
//! The pressure takes [`Preconditioner::for_pressure`]: ILU(0) below [`AMG_MIN_ROWS`] = 5,000
//! rows, smoothed-aggregation AMG from there (its iterations stay at 5-9 where ILU(0)'s grow
//! from 8 to 58 between 1,300 and 80,000 rows in cold solves, and 5.7 / 5.8 per solve at 10^4 /
//! 10^5 particles in the ISPH drop; [`Amg`]'s documentation has the measurements). The viscous
//! systems take [`Preconditioner::for_viscous`]: block Jacobi (one `N x N` block per particle
//! of the coupled system, nothing sequential) in 3D and from [`BLOCK_JACOBI_MIN_ROWS`] rows in
//! 2D, ILU(0) below (its factorisation and triangular solves run on one thread; in 3D its
//! factorisation of the ~750-entry rows was most of a step), and in 2D from
//! [`VISCOUS_AMG_MIN_ROWS`] rows plain-aggregation multigrid aggregated by particle
//! ([`Preconditioner::AmgNodal`]), whose iterations stay at 4-5 where block Jacobi's grow
//! like the inverse spacing.
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

use crate::dim::{Tensor, Vector};
use crate::kernel::Kernel;
use crate::neighbors::{Domain, NeighborList};
use rayon::prelude::*;
use thiserror::Error;

mod amg;
mod csr;
mod krylov;
mod viscous;

pub use amg::*;
pub use csr::*;
pub use krylov::*;
pub use viscous::*;

pub use crate::operators::sums::{dot, fixed_sum, DOT_CHUNK};
/// Rows per parallel task in the matrix-vector product.
const ROW_CHUNK: usize = 256;

/// Morris, Fox & Zhu 1997 Laplacian coefficients (King & Lind 2021 eq. (21)) for every stored
/// pair of `nl` (aligned with its flat pair arrays): `c_ij = 2 V_j (x_ij . g_ij) / r^2`, with
/// `g_ij = grad_i W_ij` or, when `correction` is given, the Bonet & Lok 1999 corrected
/// `L_i grad_i W_ij` (eq. (22)). `c_ij <= 0` (uncorrected); the self pair gives 0.
///
/// `x` and `vol` cover every point the lists refer to (fluid then ghosts); the lists' query
/// points are the first `nl.len()` entries of `x`. Pair vectors go through `domain`.
pub fn morris_coefficients<const N: usize, K: Kernel<N>>(
    x: &[Vector<N>],
    vol: &[f64],
    nl: &NeighborList,
    kernel: &K,
    domain: &Domain,
    correction: Option<&[Tensor<N>]>,
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
    assemble_poisson_surface(n_fluid, nl, coef, ghosts, dirichlet, &[], b)
}

/// [`assemble_poisson`] with surface rows that keep their continuity equation:
/// `surface[i] = (c_i, p_s)` adds `c_i (p_i - p_s)` to row i of `-lap p = -b`. Empty: none.
pub fn assemble_poisson_surface(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    ghosts: &GhostLink,
    dirichlet: &[Option<f64>],
    surface: &[(f64, f64)],
    b: &[f64],
) -> LinearSystem {
    assert!(surface.is_empty() || surface.len() == n_fluid);
    let neg_b: Vec<f64> = b.iter().map(|v| -v).collect();
    let (mut rows, mut rhs) = assemble(n_fluid, nl, coef, 0.0, -1.0, ghosts, dirichlet, &neg_b);
    let mut coupled = false;
    for (i, &(c, ps)) in surface.iter().enumerate() {
        if c > 0.0 && dirichlet.get(i).copied().flatten().is_none() {
            if let Some(d) = rows[i].iter_mut().rev().find(|e| e.0 as usize == i) {
                d.1 += c;
                rhs[i] += c * ps;
                coupled = true;
            }
        }
    }
    let closed = n_fluid > 0 && !coupled && dirichlet.iter().all(|d| d.is_none());
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
        rows.par_iter_mut()
            .with_min_len(ROW_CHUNK)
            .for_each(|r| r.retain(|e| e.0 as usize != a));
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

/// The right-hand side [`assemble`] gives a system without Dirichlet rows, without building its
/// matrix: `b_i + sum_j a_ij shift_j` over the same pairs in the same order (fluid neighbours
/// add `a * 0.0`, as there), so it is bitwise the assembled one.
fn helmholtz_rhs(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    lap_scale: f64,
    ghosts: &GhostLink,
    b: &[f64],
) -> Vec<f64> {
    (0..n_fluid)
        .into_par_iter()
        .map(|i| {
            let off = nl.offset(i);
            let mut rhs = b[i];
            for (k, &j) in nl.of(i).iter().enumerate() {
                let j = j as usize;
                let a = lap_scale * coef[off + k];
                if j == i || a == 0.0 {
                    continue;
                }
                let shift = if j < n_fluid {
                    0.0
                } else {
                    ghosts.link(j - n_fluid).2
                };
                rhs += a * shift;
            }
            rhs
        })
        .collect()
}

#[cfg(test)]
#[path = "tests.rs"]
mod tests;
