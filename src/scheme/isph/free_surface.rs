//! The free-surface conditions of King & Lind 2021's ISPH (section III.D, eq. (35a)): the
//! pressure of the free-surface rows of the PPE (step 5: Dirichlet or Robin rows), the
//! surface pressure the projection continues beyond a truncated support (step 6), and the
//! weights of the solvent's surface traction in the predictor (step 4). The surface itself and
//! its normals (36)-(39) are [`crate::operators::surface`]'s.
//!
//! **Free-surface pressure** (`isph_free_surface`): p = 0 (`zero_pressure`, every scene but
//! the jet) or (35a)'s solvent normal stress (`normal_stress`, the jet's `auto`). The
//! normal-stress form takes `p_s = 2 mu n.D.n = -2 mu t.G(u*).t` (continuity; G the velocity
//! gradient of the predicted velocity) as the surface value of the surface rows (the Robin
//! rows' target, added to the Dirichlet value) and projects with the positive form of
//! `p - p_s`: `sum_j (p_i + p_j) grad W_ij V_j - 2 p_s s_i`, `s_i = sum_j V_j grad W_ij`,
//! p_s a surface row's own value or its surface neighbours' kernel-weighted mean. King &
//! Lind's positive form on a truncated support acts as if p were -p_i beyond the surface,
//! i.e. p = 0 there whatever the surface value; with p_s it continues as 2 p_s - p_i, so a
//! compressive surface value no longer pushes its row out (the dilation that made (35a)
//! unusable before). The `G s` part of the solvent's surface traction is then the pressure's
//! (`along` = 0), and the `-2 p_s s_i` term, not a pair force, has its mean over the free
//! particles removed (a free surface exerts no net force; the jet's wall impulse balance
//! holds to round-off). Measured (Newtonian, `viscosph run`): the jet (H = 12 D, 6 / 10
//! across) buckles, 0.47 / 0.55 D, heap at 0.200 / 0.205 s (p = 0: 0.019 / 0.034 D, 0.165 /
//! 0.175 s; WCSPH 0.227 s), and not from H = 2 D (0.035 D); the Re = 4 drop at W/dr = 20 /
//! 40 gives W*(8) 1.997 / 1.910, largest |volume_error| 0.93 / 0.52 % (p = 0: 2.127 / 1.962,
//! 0.85 / 0.45 %), hence p = 0 for drops (docs/methods.md, "The ISPH jet with (35a)").
//!
//! **The surface value's gradient.** G in `-2 mu t.G(u*).t` is the Bonet & Lok 1999 corrected
//! gradient with the surface particle's own correction matrix, not the identity the rest of the
//! step gives the free surface ([`super::neighbours`]): the uncorrected gradient of a truncated
//! support reads the stretching along the surface short (0.73-0.80 of the column's dv/dy on
//! the surface rows of King & Lind's Newtonian jet at 6 across, 4 particles wide), and the
//! tension (35a) puts on the column's sides with it. Only this value takes it, so the
//! conformation and the stresses keep the uncorrected gradient whose stability the drops need.
//! Measured (Newtonian jet, H = 12 D, 6 across, lowest point D/2 above the plate against the
//! slender-sheet model): -10.8 % -> -6.9 % at the default step, the explicit viscous step
//! -1.7 % -> +1.3 %; with the splitting limit of [`super::step_size`] -2.2 %.
//!
//! **The polymer's normal stress** (an elastic fluid under `normal_stress`): the surface value
//! is (35a)'s with the total extra stress, `p_s = -2 mu t.G(u*).t + n.Phi.n`, Phi the polymer
//! stress of step 3 (with EVSS's part, whose viscosity is in `mu`), while div Phi keeps the
//! positive form's stress-free part `2 Phi_i s_i` ([`super::predictor`]). In the continuum
//! limit that counts the polymer's normal stress at the surface twice (the positive form's
//! Phi continues as -Phi_i beyond the surface, i.e. vanishes on it, and p_s adds n.Phi.n); on
//! King & Lind's jet at 6 across it is what carries the column's tension: the lateral polymer
//! stress n.Phi.n is negative on the column's sides, so the interior pressure it sets is a
//! suction that pulls the column together along its length, as (35a)'s solvent value does.
//! Measured (Oldroyd-B jet, H = 12 D, 6 across, first contact against the slender-sheet model,
//! with the corrected div Phi of [`super::predictor`] and the surface rows' own gradient in the
//! conformation): Wi = 1/3 ... 20/3 -0.4 / -0.2 / -0.0 / +0.3 % (without the polymer's part
//! -6.8 / -6.6 / -3.6 % at Wi = 1/3, 5/3, 20/3). The consistent pairing, div Phi as the corrected difference
//! form without the stress-free part and n.Phi.n in p_s, tore the Wi = 1/3 column before
//! impact (first contact at 0.134 s against the model's 0.2189 s): the positive form's
//! stress-free part is what keeps the surface rows of a stretched column together.
//!
//! **p = 0**, King's public code's choice, was first taken instead of the normal-stress value
//! of (35a) because, measured on the drop of King & Lind IV.C at W/dr = 20: with the solvent's
//! 2 eta_s n.D.n in the Dirichlet value, the Newtonian drop splashes at impact (W* = 4.5 at
//! t* = 2.4, holes) with the explicit viscous step of (24)-(28), and a drop at rest blows up with
//! the implicit one (the value is explicit in the velocity, so it is a viscous term with the
//! explicit limit rho h^2 / eta_s); with only the polymer's n.tau_p.n the Oldroyd-B drop
//! (De = 1, beta = 0.1) spreads without bound (W* = 23 at t* = 8). With p = 0 the Newtonian
//! drop spreads to W* = 2.16 at t* = 8 under both viscous steps, and the Oldroyd-B drop spreads
//! to 2.1 and retracts. The positive form of div Phi still carries the stress-free condition
//! approximately (King & Lind section III.A).
//!
//! **Where p = 0 is imposed.** The surface lies half a layer outside the surface particles'
//! centres, so a surface particle takes the pressure that far inside the surface,
//! `depth (-dp/dn)` (`surface_pressure`, from the last step's pressures of its interior
//! neighbours), with `depth = dx/2` times the surface row's line density
//! ([`surface::row_density`]: a crowded row stands for a thicker layer). With p = 0 on the
//! centres the surface row crowded tangentially as the free perimeter shrank (0.81 dx apart at
//! W/dr = 20), and nothing returned its particles to the bulk: largest |volume_error| of the
//! Newtonian drop 5.32 %, 1.76 %, 0.62 % at W/dr = 20, 40, 80; now 2.73 %, 1.02 %, 0.39 %
//! (docs/isph.md, "Volume").
//!
//! **Free-surface traction** of the solvent, implicit (King & Lind 2021 eq. (35a)'s viscous part in
//! a stable form; [`super::ppe::SurfaceTraction`]): Morris et al. 1997's Laplacian (21) sees a
//! missing neighbour as one with the particle's own velocity, i.e. the normal derivative, not the
//! traction; the positive form of the divergence of 2 eta D differs from the difference form by `2
//! sigma_i s_i`, `s_i = sum_j V grad W_ij`. Every row of the implicit viscous step takes `(2 eta_i
//! / rho) (G_i + G_i^T) s_i` with the Bonet & Lok 1999 corrected gradient G_i of the new velocity,
//! both components solved together. Measured on the extensional mode of a free sheet (exact decay
//! 3.87 nu k^2): 1.74 without, 2.68 with, at 0.2 ms; the Newtonian Re = 4 drop's W*(8) at W/dr = 40
//! and a third of the step 1.987 -> 1.858 (Oldroyd-B at De = 0.1: 1.80), largest |volume_error| at
//! the default step 1.02 % -> 0.64 % (docs/isph.md). The term is not a pair force; a free surface
//! exerts no net force, so the term's mean velocity change is removed after the solve (without
//! that, a slowly settling drop felt 3 % of its weight from it).

use super::{Context, Isph, MIN_TASK};
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::kernel::{Kernel, QuinticSplineKernel};
use crate::neighbors::{Domain, NeighborList};
use crate::operators::surface;
use crate::rheology::Rheology;
use crate::state::State;
use rayon::prelude::*;

/// Weights of the solvent's free-surface traction in the implicit viscous step
/// ([`super::ppe::SurfaceTraction`]): `(2 eta / rho) (along G + transposed G^T) s_i` on every row,
/// the difference between the positive form of div(2 eta D) and the difference form, with G the
/// Bonet & Lok 1999 corrected velocity gradient (module documentation, "Free-surface traction").
/// Measured on the extensional mode of a free Newtonian sheet (kH = pi/10, exact decay rate 3.87 nu
/// k^2, test `free_sheet_resists_extension_with_the_surface_traction`), at dt = 5e-5 / 2e-4 / 1e-3
/// s: Morris' Laplacian alone 1.84 / 1.74 / 1.47 nu k^2; G^T s only (along = 0) 2.79 / 2.54 / 1.92;
/// both 3.02 / 2.68 / 1.97 (kept).
pub(super) const SURFACE_TRACTION_ALONG: f64 = 1.0;
pub(super) const SURFACE_TRACTION_TRANSPOSED: f64 = 1.0;

/// The free-surface rows of the PPE of one step (all empty without a free surface).
pub(super) struct SurfaceRows {
    /// Dirichlet value of each fluid row (None: an interior or Robin row).
    pub dirichlet: Vec<Option<f64>>,
    /// Robin rows `(c_i, p_s)` (`c_i = 0`: none).
    pub robin: Vec<(f64, f64)>,
    /// The surface value p_s of (35a)'s normal stress on each surface row (zeros with p = 0).
    pub p_fs: Vec<f64>,
}

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// The weight of `G s` in the solvent's surface traction: with the normal-stress surface
    /// pressure that part is the pressure's (module documentation, "Free-surface pressure").
    pub(super) fn along(&self) -> f64 {
        if self.normal_stress {
            0.0
        } else {
            SURFACE_TRACTION_ALONG
        }
    }

    /// The free-surface rows of the PPE: surface particles (but the inlet's Neumann ones,
    /// `neumann`) take the pressure that puts p = 0 on the surface of the layer they stand for
    /// (from the last step's pressures of `st` and the virtual particles' `offsets`), plus with
    /// the normal-stress condition (35a)'s value from the predicted velocity's gradient
    /// `kappa_star`, the viscosity `mu` and the stress Phi `phi` (empty for an inelastic
    /// model); then every such row where Morris' Laplacian misses neighbours beyond the surface
    /// keeps its continuity equation as a Robin row.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn surface_rows(
        &self,
        st: &State<N>,
        ctx: &Context<N>,
        offsets: &[f64],
        kappa_star: &[Tensor<N>],
        mu: &[f64],
        phi: &[Tensor<N>],
        neumann: impl Fn(usize) -> bool,
    ) -> SurfaceRows {
        let n = ctx.n;
        let Some(s) = &ctx.surf else {
            return SurfaceRows {
                dirichlet: Vec::new(),
                robin: Vec::new(),
                p_fs: vec![0.0; n],
            };
        };
        let (h, dx, dom) = (self.kernel.h(), self.p.dx, self.p.domain);
        let (nl, all_x, xs) = (&ctx.nl, &self.all_x, &ctx.xs);
        let depth = surface::row_density(all_x, nl, &dom, &s.is_surface, h, dx);
        // Free-surface particles: Dirichlet rows whose value puts p = 0 on the surface of the
        // layer they stand for, not on their centres (module documentation).
        let p_prev: &[f64] = if st.pressure.len() == n {
            &st.pressure
        } else {
            &[]
        };
        let mut dirichlet: Vec<Option<f64>> = (0..n)
            .map(|i| {
                (s.is_surface[i] && !neumann(i)).then(|| {
                    surface_pressure(
                        i,
                        n,
                        p_prev,
                        &s.is_surface,
                        &ctx.virt.parent,
                        offsets,
                        nl,
                        &self.kernel,
                        all_x,
                        &dom,
                        s.normal[i],
                        0.5 * dx * depth[i],
                    )
                })
            })
            .collect();
        // King & Lind (35a)'s normal stress as the surface pressure (normal_stress): the
        // solvent's 2 mu n.D.n = -2 mu t.G(u*).t by continuity, from the velocity the projection
        // is about to correct, plus an elastic fluid's n.Phi.n (module documentation,
        // "Free-surface pressure", "The polymer's normal stress"). Zero elsewhere.
        let p_fs: Vec<f64> = if self.normal_stress {
            (0..n)
                .map(|i| {
                    if !s.is_surface[i] || ctx.held.holds(i) {
                        return 0.0;
                    }
                    let solvent =
                        -2.0 * mu[i] * Const::<N>::tangential_trace(&s.normal[i], &kappa_star[i]);
                    match phi.get(i) {
                        Some(phi_i) => solvent + s.normal[i].dot(&(phi_i * s.normal[i])),
                        None => solvent,
                    }
                })
                .collect()
        } else {
            vec![0.0; n]
        };
        for (i, d) in dirichlet.iter_mut().enumerate() {
            if let Some(v) = d {
                *v += p_fs[i];
            }
        }
        // Free-surface rows keep their continuity equation ([`super::pressure`], "Volume"):
        // row i of `-lap p = -b` takes `c_i p_i`, the part of Morris' Laplacian that the
        // neighbours missing beyond the surface would give if p fell linearly to 0 at `depth`
        // outside the particle, `c_i = -n . sum_j c_ij x_ji / depth` (the first moment of a full
        // support vanishes, so the missing neighbours' moment is minus the present ones');
        // Dirichlet where that is not positive.
        let robin: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                if dirichlet[i].is_none() {
                    return (0.0, 0.0);
                }
                let off = nl.offset(i);
                let mut m1 = Vector::<N>::zeros();
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let j = j as usize;
                    if j != i {
                        m1 -= dom.delta(&all_x[j], &xs[i]) * self.pairs.morris[off + kk];
                    }
                }
                let d = 0.5 * dx * depth[i];
                let c = (-s.normal[i].dot(&m1)).max(0.0) / d;
                if c > 0.0 && d > 0.0 {
                    dirichlet[i] = None;
                    (c, p_fs[i])
                } else {
                    (0.0, 0.0)
                }
            })
            .collect();
        SurfaceRows {
            dirichlet,
            robin,
            p_fs,
        }
    }

    /// The surface pressure each particle's truncated support sees (normal_stress; empty
    /// otherwise): its own `p_fs` on a surface row, the kernel-weighted mean of its surface
    /// neighbours' elsewhere (zero where the support is full, where it would not matter:
    /// sum_j V grad W_ij = 0 there).
    pub(super) fn ghost_surface_pressure(&self, ctx: &Context<N>, p_fs: &[f64]) -> Vec<f64> {
        let (n, dom) = (ctx.n, self.p.domain);
        let (nl, all_x, xs) = (&ctx.nl, &self.all_x, &ctx.xs);
        match &ctx.surf {
            Some(s) if self.normal_stress => (0..n)
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .map(|i| {
                    if s.is_surface[i] {
                        return p_fs[i];
                    }
                    let (mut num, mut den) = (0.0, 0.0);
                    for &j in nl.of(i) {
                        let j = j as usize;
                        if j < n && s.is_surface[j] {
                            let w = self.kernel.w(dom.delta(&all_x[j], &xs[i]).norm());
                            num += w * p_fs[j];
                            den += w;
                        }
                    }
                    if den > 0.0 {
                        num / den
                    } else {
                        0.0
                    }
                })
                .collect(),
            _ => Vec::new(),
        }
    }
}

/// The free-surface pressure of particle `i`: p = 0 on the surface, which lies `depth` outside
/// the particle along its outward normal `normal`, not on the particle's centre. The pressure
/// along n is fitted to the last step's pressures `p_prev` of the particle's interior neighbours
/// (mirrors included, free-surface ones excluded) as the line through p = 0 at s = depth,
/// weighted by the kernel: `p(s) = b (s - depth)`, `b = sum W p_j (s_j - depth) / sum W
/// (s_j - depth)^2` with `s_j = n . x_ji`; the particle takes `p(0) = -b depth`. The fit uses
/// neither the particle's own value nor its surface neighbours', so the value does not feed on
/// itself from step to step (an extrapolation that did, with the slope taken relative to p_i,
/// amplified by depth / spacing and blew up at W/dr = 80). Limited to [0, max_j p_j]: no tension
/// at the surface, no new extremum. `p_prev` empty (first step): 0.
#[allow(clippy::too_many_arguments)]
fn surface_pressure<const N: usize>(
    i: usize,
    n: usize,
    p_prev: &[f64],
    is_surface: &[bool],
    parent: &[u32],
    offsets: &[f64],
    nl: &NeighborList,
    kernel: &QuinticSplineKernel<N>,
    x: &[Vector<N>],
    dom: &Domain,
    normal: Vector<N>,
    depth: f64,
) -> f64 {
    if p_prev.len() != n || depth <= 0.0 {
        return 0.0;
    }
    let (mut num, mut den, mut p_max) = (0.0, 0.0, 0.0f64);
    for &j in nl.of(i) {
        let j = j as usize;
        let (pj, fs) = if j < n {
            (p_prev[j], is_surface[j])
        } else {
            let k = parent[j - n] as usize;
            (p_prev[k] + offsets[j - n], is_surface[k])
        };
        if j == i || fs {
            continue;
        }
        let xji = dom.delta(&x[j], &x[i]);
        let w = kernel.w(xji.norm());
        let sj = xji.dot(&normal) - depth;
        num += w * pj * sj;
        den += w * sj * sj;
        p_max = p_max.max(pj);
    }
    if den <= 0.0 {
        return 0.0;
    }
    (-num / den * depth).clamp(0.0, p_max)
}
