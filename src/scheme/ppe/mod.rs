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

mod csr;
mod krylov;

pub use csr::*;
pub use krylov::*;

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
    // One matrix and one preconditioner: the components differ only in their right-hand
    // sides, so the second one is not assembled again (measured: the second assembly was 14 %
    // of the ISPH drop's step, docs/benchmarks.md).
    let mut shared: Option<(LinearSystem, Factor)> = None;
    for (c, st) in stats.iter_mut().enumerate() {
        let off: Vec<f64> = ghost_offset.iter().map(|w| w[c]).collect();
        let b: Vec<f64> = rhs.iter().map(|r| r[c]).collect();
        let ghosts = GhostLink {
            parent: ghost_parent,
            sign: ghost_sign,
            offset: &off,
        };
        let (sys, m) = match shared.take() {
            Some((mut sys, m)) => {
                sys.rhs = helmholtz_rhs(n_fluid, nl, coef, -dt_nu, &ghosts, &b);
                (sys, m)
            }
            None => {
                let sys = assemble_helmholtz(n_fluid, nl, coef, dt_nu, &ghosts, &b);
                let m = Factor::new(&sys.matrix, opts.preconditioner)?;
                (sys, m)
            }
        };
        let mut x: Vec<f64> = u.iter().map(|v| v[c]).collect();
        *st = solve_with(&sys, &m, &mut x, opts)?;
        for (ui, xi) in u.iter_mut().zip(&x) {
            ui[c] = *xi;
        }
        shared = Some((sys, m));
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

/// The solvent's free-surface traction in the implicit viscous step (King & Lind 2021 eq.
/// (35a)'s viscous part, made implicit). Morris et al. 1997's Laplacian (King & Lind eq. (21))
/// counts a missing neighbour as one with the particle's own velocity, so on a linear field it
/// gives `2 G_i s_i` with `s_i = sum_j V_j grad_i W_ij` (about -n / delta at a surface, 0 in a
/// full support): the flux `eta G n` of the velocity's normal derivative, not the traction
/// `eta (G + G^T) n`. The positive form of the divergence of `2 eta D` (the polymer's, Bonet &
/// Lok 1999 gradients) gives `2 eta (G + G^T) s_i` on the same field. This term adds
/// `(2 eta_i / rho) (along G_i + transposed G_i^T) s_i` to the rows it acts on, with `G_i` the
/// corrected velocity gradient of the unknown velocity (one hop), so both velocity components
/// are solved together.
#[derive(Debug, Clone, Copy)]
pub struct SurfaceTraction<'a> {
    /// Per fluid particle: `k_i = 2 eta_i dt s_i / rho` (zero: no surface term in its rows).
    pub k: &'a [Vec2],
    /// Per stored pair (aligned with the neighbour list): `V_j L_i grad_i W_ij`, the weights of
    /// the corrected velocity gradient `G_i = sum_j (u_j - u_i) w_ij^T`.
    pub w: &'a [Vec2],
    /// Weight of `G_i s_i` (the normal derivative, which Morris' Laplacian already carries).
    pub along: f64,
    /// Weight of `G_i^T s_i` (the part of the traction Morris' Laplacian misses).
    pub transposed: f64,
}

impl SurfaceTraction<'_> {
    /// The coefficient matrix of `u_j - u_i` in the rows of particle i for its stored pair
    /// `p`: `E_ij = along (w_ij . k_i) I + transposed w_ij k_i^T`.
    pub fn pair(&self, i: usize, p: usize) -> Mat2 {
        let (w, k) = (self.w[p], self.k[i]);
        Mat2::identity() * (self.along * w.dot(&k)) + w * k.transpose() * self.transposed
    }
}

/// The two rows (x and y components) of one particle, as (column, value) lists.
type RowPair = [Vec<(u32, f64)>; 2];

/// The implicit viscous step with the surface traction: `(I - dt nu lap) u - dt T(u) / rho =
/// rhs` for both components at once, unknowns interleaved (`2 i + c`), one BiCGStab + ILU(0)
/// solve. Ghosts as in [`solve_viscous`] (the same sign for both components). Rows without a
/// surface term are those of [`assemble_helmholtz`] for each component.
#[allow(clippy::too_many_arguments)]
pub fn solve_viscous_coupled(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    dt_nu: f64,
    ghost_parent: &[u32],
    ghost_sign: &[f64],
    ghost_offset: &[Vec2],
    rhs: &[Vec2],
    u: &mut [Vec2],
    surf: &SurfaceTraction,
    opts: &SolverOptions,
) -> Result<SolveStats, SolveError> {
    assert!(nl.len() >= n_fluid);
    assert_eq!(coef.len(), nl.pairs());
    assert_eq!(surf.w.len(), nl.pairs());
    assert_eq!(surf.k.len(), n_fluid);
    assert_eq!(rhs.len(), n_fluid);
    let link = |m: usize| -> (usize, f64, Vec2) {
        (
            ghost_parent[m] as usize,
            ghost_sign.get(m).copied().unwrap_or(1.0),
            ghost_offset.get(m).copied().unwrap_or_else(Vec2::zeros),
        )
    };
    let per_particle: Vec<(RowPair, Vec2)> = (0..n_fluid)
        .into_par_iter()
        .map(|i| {
            let off = nl.offset(i);
            let mut rows: [Vec<(u32, f64)>; 2] = [
                Vec::with_capacity(2 * nl.of(i).len() + 2),
                Vec::with_capacity(2 * nl.of(i).len() + 2),
            ];
            let mut b = rhs[i];
            let mut diag = 1.0;
            let with_surface = surf.k[i] != Vec2::zeros();
            // e_cd: the surface term's coefficient of (u_j - u_i)_d in row (i, c).
            let mut e_ii = Mat2::zeros();
            for (kk, &j) in nl.of(i).iter().enumerate() {
                let j = j as usize;
                if j == i {
                    continue;
                }
                let a = -dt_nu * coef[off + kk];
                let e = if with_surface {
                    surf.pair(i, off + kk)
                } else {
                    Mat2::zeros()
                };
                let (col, s, shift) = if j < n_fluid {
                    (j, 1.0, Vec2::zeros())
                } else {
                    link(j - n_fluid)
                };
                // Row (i, c): a (u_ic - u_jc) - sum_d e_cd (u_jd - u_id), u_j = s u_col + shift.
                diag += a;
                e_ii += e;
                b += shift * a + e * shift;
                for c in 0..2 {
                    if col == i {
                        // A ghost of the particle itself (a mirror across a wall).
                        rows[c].push(((2 * i + c) as u32, -a * s));
                    } else if a != 0.0 {
                        rows[c].push(((2 * col + c) as u32, -a * s));
                    }
                    if with_surface {
                        for d in 0..2 {
                            if e[(c, d)] != 0.0 {
                                rows[c].push(((2 * col + d) as u32, -e[(c, d)] * s));
                            }
                        }
                    }
                }
            }
            for (c, row) in rows.iter_mut().enumerate() {
                row.push(((2 * i + c) as u32, diag));
                if with_surface {
                    for d in 0..2 {
                        row.push(((2 * i + d) as u32, e_ii[(c, d)]));
                    }
                }
            }
            (rows, b)
        })
        .collect();
    let mut rows = Vec::with_capacity(2 * n_fluid);
    let mut b = Vec::with_capacity(2 * n_fluid);
    for ([r0, r1], bi) in per_particle {
        rows.push(r0);
        rows.push(r1);
        b.push(bi[0]);
        b.push(bi[1]);
    }
    let sys = LinearSystem {
        matrix: CsrMatrix::from_rows(rows),
        rhs: b,
        anchor: None,
        fixed: Vec::new(),
    };
    let mut x: Vec<f64> = u.iter().flat_map(|v| [v[0], v[1]]).collect();
    let stats = solve(&sys, &mut x, opts)?;
    for (i, ui) in u.iter_mut().enumerate() {
        *ui = Vec2::new(x[2 * i], x[2 * i + 1]);
    }
    Ok(stats)
}

#[cfg(test)]
#[path = "tests.rs"]
mod tests;
