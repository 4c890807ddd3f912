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

/// The implicit viscous step with the surface traction: `(I - dt nu lap) u - dt T(u) / rho =
/// rhs` for all components at once, unknowns interleaved (`N i + c`), one BiCGStab solve.
/// Ghosts as in [`solve_viscous`] (the same sign for every component). Rows without a surface
/// term are those of [`assemble_helmholtz`] for each component.
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
    let sys = assemble_coupled(
        n_fluid,
        nl,
        coef,
        dt_nu,
        ghost_parent,
        ghost_sign,
        ghost_offset,
        rhs,
        surf,
    );
    let mut x: Vec<f64> = u.iter().flat_map(|v| v.iter().copied()).collect();
    let stats = solve(&sys, &mut x, opts)?;
    for (ui, xi) in u.iter_mut().zip(x.chunks_exact(N)) {
        ui.copy_from_slice(xi);
    }
    Ok(stats)
}

/// One particle's `N` rows of the coupled system: the columns and values of each row (columns
/// ascending), their lengths and the diagonal's position in each.
struct ParticleRows {
    col: Vec<u32>,
    val: Vec<f64>,
    len: Vec<usize>,
    diag: Vec<usize>,
}

/// An `N x N` block of the coupled matrix being summed: each entry's value and whether any
/// term has reached it (an entry no term reaches is not stored, as in [`CsrMatrix::from_rows`]).
struct BlockSum<const N: usize> {
    val: [[f64; N]; N],
    set: [[bool; N]; N],
}

impl<const N: usize> BlockSum<N> {
    fn new() -> Self {
        Self {
            val: [[0.0; N]; N],
            set: [[false; N]; N],
        }
    }

    /// Add one term to entry (c, d): the first term is stored as is and later ones are summed in
    /// the order they come, exactly as `from_rows` merges a column's duplicates.
    #[inline]
    fn add(&mut self, c: usize, d: usize, v: f64) {
        if self.set[c][d] {
            self.val[c][d] += v;
        } else {
            self.val[c][d] = v;
            self.set[c][d] = true;
        }
    }
}

/// The matrix and right-hand side of [`solve_viscous_coupled`], assembled one particle (one
/// `N x N` block row) at a time. The rows are those that per-entry lists merged by
/// [`CsrMatrix::from_rows`] give, bit for bit (same stored entries, each summed in the same
/// order), without sorting the `N` rows of `N x` (neighbours) entries each: only the
/// particle's neighbours are sorted once, by the column their value lands in (a ghost's lands
/// in its parent's), and each block is summed in neighbour order. In 3D with the surface
/// traction a row holds ~750 entries: sorting them was most of the assembly.
#[allow(clippy::too_many_arguments)]
pub(super) fn assemble_coupled<const N: usize>(
    n_fluid: usize,
    nl: &NeighborList,
    coef: &[f64],
    dt_nu: f64,
    ghost_parent: &[u32],
    ghost_sign: &[f64],
    ghost_offset: &[Vector<N>],
    rhs: &[Vector<N>],
    surf: &SurfaceTraction<N>,
) -> LinearSystem {
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
    // Where neighbour j's value lands: (column particle, sign, shift), u_j = s u_col + shift.
    let target = |j: usize| -> (usize, f64, Vector<N>) {
        if j < n_fluid {
            (j, 1.0, Vector::<N>::zeros())
        } else {
            link(j - n_fluid)
        }
    };
    // The self entry's marker in the sorted neighbour keys: after every neighbour of the same
    // column, as the diagonal terms come after the neighbour loop.
    const SELF: u64 = u32::MAX as u64;
    let per_particle: Vec<(ParticleRows, Vector<N>)> = (0..n_fluid)
        .into_par_iter()
        .map(|i| {
            let off = nl.offset(i);
            let with_surface = surf.k[i] != Vector::<N>::zeros();
            let pair = |kk: usize| -> Tensor<N> {
                if with_surface {
                    surf.pair(i, off + kk)
                } else {
                    Tensor::<N>::zeros()
                }
            };
            // Row (i, c): a (u_ic - u_jc) - sum_d e_cd (u_jd - u_id), e_cd the surface term's
            // coefficient of (u_j - u_i)_d. The diagonal, e_ii and b sum in neighbour order.
            let mut b = rhs[i];
            let mut diag = 1.0;
            let mut e_ii = Tensor::<N>::zeros();
            let mut keys: Vec<u64> = Vec::with_capacity(nl.of(i).len() + 1);
            for (kk, &j) in nl.of(i).iter().enumerate() {
                let j = j as usize;
                if j == i {
                    continue;
                }
                let a = -dt_nu * coef[off + kk];
                let e = pair(kk);
                let (col, _, shift) = target(j);
                diag += a;
                e_ii += e;
                b += shift * a + e * shift;
                keys.push(((col as u64) << 32) | kk as u64);
            }
            keys.push(((i as u64) << 32) | SELF);
            keys.sort_unstable();
            // Blocks in ascending column, each summed over its neighbours in list order.
            let mut blocks: Vec<(usize, BlockSum<N>)> = Vec::with_capacity(keys.len());
            for &key in &keys {
                let col = (key >> 32) as usize;
                if blocks.last().is_none_or(|(c, _)| *c != col) {
                    blocks.push((col, BlockSum::new()));
                }
                let blk = &mut blocks.last_mut().expect("pushed").1;
                if key & SELF == SELF {
                    for c in 0..N {
                        blk.add(c, c, diag);
                        if with_surface {
                            for d in 0..N {
                                blk.add(c, d, e_ii[(c, d)]);
                            }
                        }
                        // from_rows' inserted diagonal.
                        blk.add(c, c, 0.0);
                    }
                    continue;
                }
                let kk = (key & SELF) as usize;
                let a = -dt_nu * coef[off + kk];
                let e = pair(kk);
                let s = target(nl.of(i)[kk] as usize).1;
                for c in 0..N {
                    if col == i || a != 0.0 {
                        blk.add(c, c, -a * s);
                    }
                    if with_surface {
                        for d in 0..N {
                            if e[(c, d)] != 0.0 {
                                blk.add(c, d, -e[(c, d)] * s);
                            }
                        }
                    }
                }
            }
            let mut out = ParticleRows {
                col: Vec::with_capacity(N * N * blocks.len()),
                val: Vec::with_capacity(N * N * blocks.len()),
                len: Vec::with_capacity(N),
                diag: Vec::with_capacity(N),
            };
            for c in 0..N {
                let start = out.col.len();
                for (col, blk) in &blocks {
                    for d in 0..N {
                        if blk.set[c][d] {
                            if *col == i && d == c {
                                out.diag.push(out.col.len() - start);
                            }
                            out.col.push((N * col + d) as u32);
                            out.val.push(blk.val[c][d]);
                        }
                    }
                }
                out.len.push(out.col.len() - start);
            }
            (out, b)
        })
        .collect();
    let mut row_ptr = Vec::with_capacity(N * n_fluid + 1);
    let mut diag = Vec::with_capacity(N * n_fluid);
    row_ptr.push(0);
    for (p, _) in &per_particle {
        for (len, d) in p.len.iter().zip(&p.diag) {
            let start = *row_ptr.last().expect("non-empty");
            diag.push(start + d);
            row_ptr.push(start + len);
        }
    }
    // A particle's N rows are contiguous: each run of particles fills its own slice.
    let (col, val) = super::fill_rows(&row_ptr, N * 64, |row, c, v| {
        let (p, k) = (&per_particle[row / N].0, row % N);
        let start: usize = p.len[..k].iter().sum();
        c.copy_from_slice(&p.col[start..start + p.len[k]]);
        v.copy_from_slice(&p.val[start..start + p.len[k]]);
    });
    let b = per_particle
        .iter()
        .flat_map(|(_, bi)| bi.iter().copied())
        .collect();
    super::drop_in_parallel(per_particle);
    LinearSystem {
        matrix: CsrMatrix {
            row_ptr,
            col,
            val,
            diag,
        },
        rhs: b,
        anchor: None,
        fixed: Vec::new(),
    }
}
