//! The implicit viscous step's systems (King & Lind 2021's predictor (24) with the solvent
//! viscosity solved for the new velocity): both velocity components with one matrix
//! ([`solve_viscous`]), or coupled through the solvent's free-surface traction
//! ([`solve_viscous_coupled`], [`SurfaceTraction`]).

use super::{
    assemble_helmholtz, helmholtz_rhs, solve, solve_with, CsrMatrix, Factor, GhostLink,
    LinearSystem, SolveError, SolveStats, SolverOptions,
};
use crate::dim::{Tensor, Vector};
use crate::neighbors::NeighborList;
use rayon::prelude::*;

/// Implicit viscous step for both velocity components: `(I - dt nu lap) u = rhs`, one matrix
/// and one preconditioner, two solves. `u` holds the start (e.g. the explicit prediction) on
/// entry. Ghost m's velocity is `ghost_sign[m] u_parent + ghost_offset[m]`: a no-slip mirror
/// has sign -1 and offset 2 u_wall, a periodic image sign +1 and offset 0 (empty = all +1 / 0).
#[allow(clippy::too_many_arguments)]
pub fn solve_viscous<const N: usize>(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    dt_nu: f64,
    ghost_parent: &[u32],
    ghost_sign: &[f64],
    ghost_offset: &[Vector<N>],
    rhs: &[Vector<N>],
    u: &mut [Vector<N>],
    opts: &SolverOptions,
) -> Result<[SolveStats; N], SolveError> {
    let mut stats = [SolveStats {
        iterations: 0,
        rel_residual: 0.0,
    }; N];
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
pub struct SurfaceTraction<'a, const N: usize = 2> {
    /// Per fluid particle: `k_i = 2 eta_i dt s_i / rho` (zero: no surface term in its rows).
    pub k: &'a [Vector<N>],
    /// Per stored pair (aligned with the neighbour list): `V_j L_i grad_i W_ij`, the weights of
    /// the corrected velocity gradient `G_i = sum_j (u_j - u_i) w_ij^T`.
    pub w: &'a [Vector<N>],
    /// Weight of `G_i s_i` (the normal derivative, which Morris' Laplacian already carries).
    pub along: f64,
    /// Weight of `G_i^T s_i` (the part of the traction Morris' Laplacian misses).
    pub transposed: f64,
}

impl<const N: usize> SurfaceTraction<'_, N> {
    /// The coefficient matrix of `u_j - u_i` in the rows of particle i for its stored pair
    /// `p`: `E_ij = along (w_ij . k_i) I + transposed w_ij k_i^T`.
    pub fn pair(&self, i: usize, p: usize) -> Tensor<N> {
        let (w, k) = (self.w[p], self.k[i]);
        Tensor::<N>::identity() * (self.along * w.dot(&k)) + w * k.transpose() * self.transposed
    }
}

/// The two rows (x and y components) of one particle, as (column, value) lists.
type Rows<const N: usize> = [Vec<(u32, f64)>; N];

/// The implicit viscous step with the surface traction: `(I - dt nu lap) u - dt T(u) / rho =
/// rhs` for both components at once, unknowns interleaved (`2 i + c`), one BiCGStab + ILU(0)
/// solve. Ghosts as in [`solve_viscous`] (the same sign for both components). Rows without a
/// surface term are those of [`assemble_helmholtz`] for each component.
#[allow(clippy::too_many_arguments)]
pub fn solve_viscous_coupled<const N: usize>(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    dt_nu: f64,
    ghost_parent: &[u32],
    ghost_sign: &[f64],
    ghost_offset: &[Vector<N>],
    rhs: &[Vector<N>],
    u: &mut [Vector<N>],
    surf: &SurfaceTraction<N>,
    opts: &SolverOptions,
) -> Result<SolveStats, SolveError> {
    assert!(nl.len() >= n_fluid);
    assert_eq!(coef.len(), nl.pairs());
    assert_eq!(surf.w.len(), nl.pairs());
    assert_eq!(surf.k.len(), n_fluid);
    assert_eq!(rhs.len(), n_fluid);
    let link = |m: usize| -> (usize, f64, Vector<N>) {
        (
            ghost_parent[m] as usize,
            ghost_sign.get(m).copied().unwrap_or(1.0),
            ghost_offset
                .get(m)
                .copied()
                .unwrap_or_else(Vector::<N>::zeros),
        )
    };
    let per_particle: Vec<(Rows<N>, Vector<N>)> = (0..n_fluid)
        .into_par_iter()
        .map(|i| {
            let off = nl.offset(i);
            let mut rows: Rows<N> =
                std::array::from_fn(|_| Vec::with_capacity(N * nl.of(i).len() + N));
            let mut b = rhs[i];
            let mut diag = 1.0;
            let with_surface = surf.k[i] != Vector::<N>::zeros();
            // e_cd: the surface term's coefficient of (u_j - u_i)_d in row (i, c).
            let mut e_ii = Tensor::<N>::zeros();
            for (kk, &j) in nl.of(i).iter().enumerate() {
                let j = j as usize;
                if j == i {
                    continue;
                }
                let a = -dt_nu * coef[off + kk];
                let e = if with_surface {
                    surf.pair(i, off + kk)
                } else {
                    Tensor::<N>::zeros()
                };
                let (col, s, shift) = if j < n_fluid {
                    (j, 1.0, Vector::<N>::zeros())
                } else {
                    link(j - n_fluid)
                };
                // Row (i, c): a (u_ic - u_jc) - sum_d e_cd (u_jd - u_id), u_j = s u_col + shift.
                diag += a;
                e_ii += e;
                b += shift * a + e * shift;
                for (c, row) in rows.iter_mut().enumerate() {
                    if col == i {
                        // A ghost of the particle itself (a mirror across a wall).
                        row.push(((N * i + c) as u32, -a * s));
                    } else if a != 0.0 {
                        row.push(((N * col + c) as u32, -a * s));
                    }
                    if with_surface {
                        for d in 0..N {
                            if e[(c, d)] != 0.0 {
                                row.push(((N * col + d) as u32, -e[(c, d)] * s));
                            }
                        }
                    }
                }
            }
            for (c, row) in rows.iter_mut().enumerate() {
                row.push(((N * i + c) as u32, diag));
                if with_surface {
                    for d in 0..N {
                        row.push(((N * i + d) as u32, e_ii[(c, d)]));
                    }
                }
            }
            (rows, b)
        })
        .collect();
    let mut rows = Vec::with_capacity(N * n_fluid);
    let mut b = Vec::with_capacity(N * n_fluid);
    for (r, bi) in per_particle {
        rows.extend(r);
        b.extend(bi.iter());
    }
    let sys = LinearSystem {
        matrix: CsrMatrix::from_rows(rows),
        rhs: b,
        anchor: None,
        fixed: Vec::new(),
    };
    let mut x: Vec<f64> = u.iter().flat_map(|v| v.iter().copied()).collect();
    let stats = solve(&sys, &mut x, opts)?;
    for (ui, xi) in u.iter_mut().zip(x.chunks_exact(N)) {
        ui.copy_from_slice(xi);
    }
    Ok(stats)
}
