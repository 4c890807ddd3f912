//! Step 2 of King & Lind 2021's ISPH (section III.A): the walls' virtual particles
//! ([`super::walls`]), the neighbour lists, and in one pass over them the pair cache (kernel
//! gradients and Morris' coefficients of (21)), the Bonet & Lok correction matrices (22), the
//! sums of the free-surface detection (36)-(38) and of the shifting's concentration gradient
//! (42).
//!
//! **Uncorrected gradients on the free surface.** There the Bonet & Lok moment matrix (22) is
//! nearly singular along the normal, and L_i amplified the velocity gradient that drives the
//! stress: the Oldroyd-B drop above blew up at impact (tr A = 5000 at t* = 0.8) with L_i on
//! every particle, and ran with L = I on the free-surface set (as the positive form of (20)
//! has it).

use super::walls::Virtual;
use super::{Isph, MIN_TASK};
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::kernel::{Kernel, QuinticSplineKernel};
use crate::neighbors::{Domain, Grid, NeighborList};
use crate::operators::pairs::PairCache;
use crate::operators::{correction, shifting, surface};
use crate::rheology::Rheology;
use crate::state::State;
use rayon::prelude::*;

/// What step 2 gives the later steps.
pub(super) struct Neighbourhood<const N: usize> {
    /// Fluid positions r*.
    pub xs: Vec<Vector<N>>,
    pub virt: Virtual<N>,
    pub nl: NeighborList,
    /// Correction matrices L_i, the identity on the free surface.
    pub l: Vec<Tensor<N>>,
    /// With the normal-stress surface condition, every particle's own L_i, the free surface's
    /// included (empty otherwise): (35a)'s surface value reads the tangential strain through it.
    pub l_own: Vec<Tensor<N>>,
    pub surf: Option<surface::Surface<N>>,
    /// Corrections to the virtual no-slip velocities (zeros with a free surface).
    pub u_curv: Vec<Vector<N>>,
    /// Concentration gradient of eq. (42) without and with the repulsion Q (Lagrangian frame;
    /// empty otherwise).
    pub grad_c: Vec<Vector<N>>,
    pub grad_c_q: Vec<Vector<N>>,
}

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// Step 2 for the fluid at r* = `xs` (particle volume `vol`): place the walls' virtual
    /// particles, build the lists and the pair cache (`self.pairs`), the correction matrices
    /// (uncorrected on the free surface), the free surface and, in the Lagrangian frame, the
    /// shifting's sums.
    pub(super) fn neighbourhood(
        &mut self,
        st: &mut State<N>,
        xs: Vec<Vector<N>>,
        vol: f64,
        lagrangian: bool,
    ) -> Result<Neighbourhood<N>, String> {
        let t = self.clock();
        let n = xs.len();
        let dom = self.p.domain;
        let radius = self.kernel.radius();
        self.all_x.clear();
        self.all_x.extend_from_slice(&xs);
        let virt = Virtual::place(
            &mut self.walls,
            &mut st.walls,
            &xs,
            radius,
            &dom,
            &mut self.all_x,
        )?;
        let t = self.lap(t, "neighbours: virtual particles", true);
        let all_x = &self.all_x;
        let grid = Grid::<N>::build(all_x, radius, &dom);
        let nl = NeighborList::build(&grid, all_x, &xs, radius, &dom);
        let t = self.lap(t, "neighbours: grid, lists", false);
        // Virtual particles carry their parent's volume times the reflection's Jacobian
        // (`Virtual::volume`).
        let vols: Vec<f64> = std::iter::repeat_n(vol, n)
            .chain(virt.volume.iter().map(|r| vol * r))
            .collect();
        let sums = neighbour_sums(
            &mut self.pairs,
            all_x,
            &vols,
            &nl,
            &self.kernel,
            &dom,
            n,
            self.free_surface,
            lagrangian.then_some(self.p.dx),
        );
        let (mut l, surf) = (sums.l, sums.surface);
        let l_own = if self.normal_stress {
            l.clone()
        } else {
            Vec::new()
        };
        // Free-surface particles take the uncorrected gradient (module documentation).
        if let Some(s) = &surf {
            for (li, &fs) in l.iter_mut().zip(&s.is_surface) {
                if fs {
                    *li = Tensor::<N>::identity();
                }
            }
        }
        // Closed channel: the wall curvature of u^n the odd continuation misses, added to every
        // virtual velocity of this step.
        let t = self.lap(t, "neighbours: pair cache, correction, surface", false);
        let u_curv = if self.free_surface {
            vec![Vector::<N>::zeros(); virt.len()]
        } else {
            virt.velocity_curvature(&st.walls, &xs, &st.fluid.v, radius)
        };
        self.lap(t, "neighbours: wall curvature", true);
        Ok(Neighbourhood {
            xs,
            virt,
            nl,
            l,
            l_own,
            surf,
            u_curv,
            grad_c: sums.grad_c,
            grad_c_q: sums.grad_c_q,
        })
    }
}

/// Per fluid particle: the moment matrix, the surface sums (div r, C, grad C / h) and the
/// shifting gradients without and with the repulsion.
type Row<const N: usize> = (Tensor<N>, (f64, f64, Vector<N>), (Vector<N>, Vector<N>));

/// What one fused pass over the neighbour lists gives besides the pair cache (module
/// documentation).
struct NeighbourSums<const N: usize> {
    /// Bonet & Lok correction matrices L_i (King & Lind eq. (22)).
    l: Vec<Tensor<N>>,
    /// Free surface and normals (eqs. (36)-(39)), with a free surface.
    surface: Option<surface::Surface<N>>,
    /// Concentration gradient of eq. (42) without and with the repulsion Q (Lagrangian frame;
    /// empty otherwise): which one a particle takes is known only once the surface is.
    grad_c: Vec<Vector<N>>,
    grad_c_q: Vec<Vector<N>>,
}

/// The pair cache `pairs` (gradients and Morris coefficients, full layout, every slot written),
/// the moment matrices, the sums of the free-surface detection and the shifting's concentration gradient
/// of every fluid particle, in one pass over its neighbour list that evaluates the kernel once
/// per pair instead of once per sum. Every sum keeps the order and expression of its operator
/// (`correction::moment_matrices`, `surface::detect`, `shifting::concentration_gradient`, by
/// their per-pair helpers), so the results are bitwise those of the separate operators.
/// `shift_dr` = Some(dr) computes the shifting sums.
#[allow(clippy::too_many_arguments)]
fn neighbour_sums<const N: usize>(
    pairs: &mut PairCache<N>,
    x: &[Vector<N>],
    vols: &[f64],
    nl: &NeighborList,
    k: &QuinticSplineKernel<N>,
    dom: &Domain,
    n: usize,
    free_surface: bool,
    shift_dr: Option<f64>,
) -> NeighbourSums<N>
where
    Const<N>: Dim,
{
    // Every slot is written below (the self pair's zeros too): no zeroing pass first.
    pairs.size_full(nl);
    let gs = nl.split_mut(&mut pairs.grad);
    let ms = nl.split_mut(&mut pairs.morris);
    let inv_h = 1.0 / k.h();
    let (w_dr, alpha, dr) = match shift_dr {
        Some(dr) => (k.w(dr), shifting::cohesion_alpha(k.h()), dr),
        None => (1.0, 0.0, 1.0),
    };
    let rows: Vec<Row<N>> = (gs, ms)
        .into_par_iter()
        .with_min_len(MIN_TASK)
        .enumerate()
        .map(|(i, (g, m))| {
            let mut mom = Tensor::<N>::zeros();
            let (mut div, mut c, mut cg) = (0.0, 0.0, Vector::<N>::zeros());
            let (mut sh, mut sh_q) = (Vector::<N>::zeros(), Vector::<N>::zeros());
            for (kk, &j) in nl.of(i).iter().enumerate() {
                let j = j as usize;
                let xij = dom.delta(&x[i], &x[j]);
                let r2 = xij.norm_squared();
                let r = r2.sqrt();
                let (w, f) = (k.w(r), k.dw_over_r(r));
                let gij = xij * f;
                // Pair data: zero for the self pair.
                if j != i && r2 != 0.0 {
                    // The cache's readers multiply by the fluid volume: a virtual particle's
                    // own volume (`Virtual::volume`) enters through the ratio (exactly 1 for
                    // fluid neighbours and across straight walls).
                    g[kk] = gij * (vols[j] / vols[i]);
                    m[kk] = 2.0 * vols[j] * f;
                } else {
                    g[kk] = Vector::<N>::zeros();
                    m[kk] = 0.0;
                }
                // Moment matrix M_i: x_ji (x) grad W_ij = -x_ij g^T.
                mom -= vols[j] * xij * gij.transpose();
                if free_surface {
                    div -= vols[j] * xij.dot(&gij);
                    c += vols[j] * w;
                    cg += vols[j] * gij;
                }
                if shift_dr.is_some() && j != i && r != 0.0 {
                    let t = shifting::gradient_term(w, f, w_dr, vols[j], xij);
                    sh += t;
                    sh_q += t;
                    sh_q -= shifting::cohesion_term(alpha, r, dr, xij);
                }
            }
            (mom, (div, c, cg * inv_h), (sh, sh_q))
        })
        .collect();
    let l = rows
        .par_iter()
        .with_min_len(MIN_TASK)
        .map(|r| correction::invert_or_identity(&r.0))
        .collect();
    let surface = free_surface.then(|| {
        let div_r = rows.iter().map(|r| r.1 .0).collect();
        let conc = rows.iter().map(|r| r.1 .1).collect();
        let n_star = rows.iter().map(|r| r.1 .2).collect();
        surface::detect_from_sums(div_r, conc, n_star, x, vols, nl, k, dom, n)
    });
    let (grad_c, grad_c_q) = if shift_dr.is_some() {
        rows.iter().map(|r| r.2).unzip()
    } else {
        (Vec::new(), Vec::new())
    };
    NeighbourSums {
        l,
        surface,
        grad_c,
        grad_c_q,
    }
}
