//! The implicit solvent viscosity of King & Lind 2021's ISPH predictor (24) (step 4): Morris'
//! Laplacian (21) of the solvent (and EVSS) viscosity solved for the new velocity
//! ([`super::ppe::solve_viscous`], or with the free-surface traction both components together,
//! [`super::ppe::solve_viscous_coupled`]); and the viscosity the Laplacian carries.
//!
//! **Implicit solvent viscosity** (`isph_viscous_step = implicit`, the default):
//! `(I - dt nu lap) u* = u^n + dt [u_ps . grad u + div Phi / rho]` with the same Laplacian and
//! mirrors (no-slip ghosts) as the explicit term. The step is then (28) without its viscous part,
//! plus the polymer's limit: `h / c_e` with the elastic wave speed `c_e = sqrt(G / rho)` while
//! that is shorter than lambda, otherwise `max(lambda, rho h^2 / eta_p)` (a fast-relaxing
//! polymer is an explicit viscosity). The implicit viscous force on the wall is the momentum
//! the solve changed, which by the symmetry of the fluid-fluid coefficients is the mirrors'
//! part exactly. `explicit` is the paper's (24) with (28) as printed (with eta0 = the total
//! viscosity, plus EVSS's alpha_V eta0).
//!
//! **Low solvent viscosity: an EVSS floor.** With a free surface the compact (Morris)
//! Laplacian carries at least [`MIN_COMPACT_VISCOSITY_RATIO`] = 0.05 of eta0: when
//! beta eta0 + alpha_V eta0 is less, alpha_V is raised ([`isph_evss_alpha`]; the closed
//! channel keeps the configured alpha_V). EVSS (King & Lind eqs. (6)-(8)) is an identity of
//! the continuous equations, so this changes the discretisation, not the fluid. Cause,
//! measured on the UCM drop (beta = 0, De = 0.1, Re = 4): with no solvent, every viscous
//! stress goes through the positive-form divergence of the corrected gradients, a wide stencil
//! that does not see grid-scale modes, and the impact's velocity jump excites them unchecked:
//! the conformation blew up at t* = 1.5 (W/dr = 40), and a third of the step did not help
//! (W/dr = 20), so it is not a time-step limit. King & Lind need EVSS for beta = 0 (alpha_V =
//! 0.01 in the channel) and report beta = 0.05 as the drop's lowest stable value. alpha_V eta0
//! = 0.01 eta0 still splashed at impact (W/dr = 20 and 40); 0.05 eta0 spreads like the
//! Oldroyd-B drop at beta = 0.1 (W*(8) = 1.94 and 1.95 at W/dr = 20 and 40, eta0 = 4), and
//! so does 0.1 eta0 (1.95 at W/dr = 40); but a floor of 0.1 made the Oldroyd-B drop at
//! beta = 0.05 (De = 1, W/dr = 40) splash (W* = 5.3 at t* = 8, against a spread to 2.14 and
//! a retraction to 1.64 without EVSS), so the floor is King & Lind's 0.05. Larger alpha_V is
//! worse: EVSS's explicit part, the wide operator on alpha_V eta0 2D, is not cancelled by
//! the implicit compact one near the free surface and in a disordered set, and with
//! alpha_V = (1 - beta) the UCM drop (De = 1, W/dr = 40) blew up in flight, before impact
//! (t* = 0.42 with the step limit below, 0.62 without; tr A should stay 2 in flight), at
//! De = 0.1 and W/dr = 20 it ran; 0.2 and 0.3 broke at impact like 0.1 (De = 1,
//! W/dr = 40). UCM at De = 1 is beyond this floor at W/dr = 40 (the stability map in
//! docs/benchmarks.md).

use super::free_surface::SURFACE_TRACTION_TRANSPOSED;
use super::ppe;
use super::{Books, Context, Isph, MIN_TASK};
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::rheology::Rheology;
use rayon::prelude::*;
use std::time::Instant;

/// Smallest share of eta0 the compact (Morris) viscous operator carries under ISPH: when the
/// solvent's beta eta0 plus `evss_alpha`'s alpha_V eta0 is less, alpha_V is raised to make up
/// the difference (module documentation, "Low solvent viscosity"). EVSS is an identity of the
/// continuous equations (King & Lind eqs. (6)-(8)), so this changes the discretisation, not the
/// model. 0.05 is King & Lind's lowest stable beta for the drop (section IV.C). Measured on the
/// UCM drop (De = 0.1): 0.01 of eta0 still splashed at impact (W/dr = 20 and 40), 0.05 and 0.1
/// spread like the Oldroyd-B drop at beta = 0.1; on the Oldroyd-B drop at beta = 0.05 (De = 1,
/// W/dr = 40) a floor of 0.1 made it splash, 0.05 leaves it as it was (spreads and retracts).
pub const MIN_COMPACT_VISCOSITY_RATIO: f64 = 0.05;
/// Implicitness of the solvent viscous step in the closed channel: Crank-Nicolson (second order
/// in time). Measured on the Newtonian start-up (Re = 1, 30 across, Eulerian, default step):
/// largest centre-line error 0.2 % against 2.7 % with backward Euler (theta = 1). Free-surface
/// scenes keep backward Euler (`Isph::new`).
pub(super) const VISCOUS_THETA_CLOSED: f64 = 0.5;

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// The implicit part of the predictor: `(I - theta dt/rho lap_mu) u* = rhs` with the pair
    /// coefficients carrying the pair's mean viscosity `mu`, the virtual particles as no-slip
    /// ghosts (with the corrections `visc_curv`), and with a free surface the solvent's
    /// surface traction, its net removed. The virtual particles' viscous force on the fluid is
    /// the momentum the solve changed (`Books::wall_on_fluid`).
    pub(super) fn viscous_step(
        &self,
        ctx: &Context<N>,
        mu: &[f64],
        visc_curv: &[Vector<N>],
        theta: f64,
        rhs: Vec<Vector<N>>,
        books: &mut Books<N>,
    ) -> Result<Vec<Vector<N>>, String> {
        let t0 = Instant::now();
        let mut t = self.clock();
        let (n, dt, vol, mass, rho) = (ctx.n, ctx.dt, ctx.vol, ctx.mass, self.rho);
        let (nl, l, pairs, held) = (&ctx.nl, &ctx.l, &self.pairs, &ctx.held);
        let parent = &ctx.virt.parent;
        // (I - dt/rho lap_mu) u* = rhs; pair coefficients carry the pair's mean viscosity.
        // Written in parallel into zeroed (untouched) pages, not cloned then scaled (a clone
        // copies on one thread).
        let mut coef = vec![0.0; pairs.morris.len()];
        nl.split_mut(&mut coef)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, c)| {
                // The inlet's held particles are Dirichlet rows (module documentation,
                // "Inlet"): no coefficients, so the row reads u_i = rhs_i, their velocity.
                if held.holds(i) {
                    return;
                }
                let off = nl.offset(i);
                for (k, (ck, &j)) in c.iter_mut().zip(nl.of(i)).enumerate() {
                    let pj = ctx.source(j as usize);
                    *ck = pairs.morris[off + k] * (0.5 * (mu[i] + mu[pj]));
                }
            });
        let sign = vec![-1.0; ctx.virt.len()];
        let offset: Vec<Vector<N>> = ctx
            .virt
            .u_wall
            .iter()
            .zip(visc_curv)
            .map(|(w, c)| 2.0 * w + c)
            .collect();
        let mut u = rhs.clone();
        // Block Jacobi in 3D and from 2,000 rows, ILU(0) below
        // ([`ppe::Preconditioner::for_viscous`]).
        let opts = |block: usize| ppe::SolverOptions {
            preconditioner: ppe::Preconditioner::for_viscous(block * n, N, block),
            ..self.solver
        };
        // The plate's share by particle, at the solved velocities ([`super::plate_load`]).
        let mut plate_terms = Vec::new();
        // The held particles' viscous force on the free ones, in the solved velocities.
        let from_inlet;
        if ctx.surf.is_some() {
            // The solvent's surface traction, implicit (`free_surface`, "Free-surface
            // traction"): every row, k_i = 2 mu_i dt s_i / rho with s_i = sum_j V grad W_ij
            // (zero in a full support on a lattice); not on the inlet's held particles.
            let k: Vec<Vector<N>> = (0..n)
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .map(|i| {
                    if held.holds(i) {
                        return Vector::<N>::zeros();
                    }
                    pairs.gradient_sum(nl, i, vol) * (2.0 * mu[i] * theta * dt / rho)
                })
                .collect();
            // Copied in parallel (a clone copies the ~8 MB at 10^4 particles on one thread).
            let mut w: Vec<Vector<N>> = pairs.grad.par_iter().copied().collect();
            nl.split_mut(&mut w)
                .into_par_iter()
                .enumerate()
                .for_each(|(i, wi)| {
                    for g in wi.iter_mut() {
                        *g = l[i] * *g * vol;
                    }
                });
            let st_fs = ppe::SurfaceTraction {
                k: &k,
                w: &w,
                along: self.along(),
                transposed: SURFACE_TRACTION_TRANSPOSED,
            };
            let stats = ppe::solve_viscous_coupled(
                n,
                nl,
                &coef,
                theta * dt / rho,
                parent,
                &sign,
                &offset,
                &rhs,
                &mut u,
                &st_fs,
                &opts(N),
            )
            .map_err(|e| format!("implicit viscous step: {e}"))?;
            books.iterations[1] = stats.iterations as u64;
            // Before the surface term's mean is taken out (which moves every free particle).
            from_inlet = self.inlet_viscous_force(ctx, &coef, theta, &u);
            t = self.lap_solve(t, &opts(N), ["viscous solve", "viscous solve, ILU(0)"]);
            if books.plate.is_on() {
                plate_terms = self.viscous_wall_terms(ctx, &coef, theta, visc_curv, &u);
            }
            // The free surface exerts no net force on the fluid, but this term is not a pair
            // force and its sum does not cancel (about 3 % of the weight of a slowly settling
            // drop, eta = 40 Pa s): its mean is removed, a uniform velocity change that no
            // gradient sees (`free_surface`, "Free-surface traction").
            let ue = ctx.virt.extend_velocity(&u, visc_curv);
            let net: Vec<Vector<N>> = (0..n)
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .map(|i| {
                    let off = nl.offset(i);
                    let mut f = Vector::<N>::zeros();
                    for (kk, &j) in nl.of(i).iter().enumerate() {
                        if j as usize != i {
                            f += st_fs.pair(i, off + kk) * (ue[j as usize] - ue[i]);
                        }
                    }
                    f
                })
                .collect();
            t = self.lap(t, "viscous: surface net force", false);
            let mean = held.mean_over_free(net.iter());
            for (i, ui) in u.iter_mut().enumerate() {
                if !held.holds(i) {
                    *ui -= mean;
                }
            }
        } else {
            let stats = ppe::solve_viscous(
                n,
                nl,
                &coef,
                theta * dt / rho,
                parent,
                &sign,
                &offset,
                &rhs,
                &mut u,
                &opts(1),
            )
            .map_err(|e| format!("implicit viscous step: {e}"))?;
            books.iterations[1] = stats.iter().map(|s| s.iterations as u64).sum();
            from_inlet = self.inlet_viscous_force(ctx, &coef, theta, &u);
            t = self.lap_solve(t, &opts(1), ["viscous solve", "viscous solve, ILU(0)"]);
            if books.plate.is_on() {
                plate_terms = self.viscous_wall_terms(ctx, &coef, theta, visc_curv, &u);
            }
            self.split_viscous_force(ctx, &coef, theta, visc_curv, &u, books);
            t = self.lap(t, "viscous: wall forces", false);
        }
        // The momentum the solve changed is the virtual particles' viscous force and the held
        // particles' (the inlet's): the coefficients between free particles are symmetric, so
        // their share cancels pair by pair (and the surface term's net has been removed). The
        // held particles' rows have none, so what they exert on the free ones is not returned
        // to them: it is the inlet's (`Books::held_momentum`), not the walls'.
        let mut total = Vector::<N>::zeros();
        for (ui, ri) in u.iter().zip(&rhs) {
            let d = (ui - ri) * (mass / dt);
            books.wall_on_fluid += d;
            total += d;
        }
        // Only with an inlet, so that the books of every other scene keep their bits.
        if !held.flags.is_empty() {
            books.held_momentum += from_inlet * dt;
            books.wall_on_fluid -= from_inlet;
            total -= from_inlet;
        }
        books.plate.add_viscous(&plate_terms, total);
        self.lap(t, "viscous: momentum books", true);
        books.viscous_time += t0.elapsed().as_secs_f64();
        Ok(u)
    }

    /// The viscous force of the inlet's held particles on the free ones in the solved velocity
    /// `u`: `theta sum_i m sum_{j held} coef_ij (u_i - u_j) / rho` over the free particles i
    /// (Morris' coefficients are negative; zero without an inlet), summed in index order.
    fn inlet_viscous_force(
        &self,
        ctx: &Context<N>,
        coef: &[f64],
        theta: f64,
        u: &[Vector<N>],
    ) -> Vector<N> {
        let (n, nl, held) = (ctx.n, &ctx.nl, &ctx.held);
        if held.flags.is_empty() {
            return Vector::<N>::zeros();
        }
        let per: Vec<Vector<N>> = (0..n)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| {
                let mut f = Vector::<N>::zeros();
                if held.holds(i) {
                    return f;
                }
                let off = nl.offset(i);
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let j = j as usize;
                    if j < n && held.holds(j) {
                        f += (u[i] - u[j]) * coef[off + kk];
                    }
                }
                f
            })
            .collect();
        per.iter().fold(Vector::<N>::zeros(), |a, f| a + f) * (theta * ctx.mass / self.rho)
    }

    /// Each wall's share of the implicit viscous force on the fluid, where the step splits the
    /// walls' force (`books.per_wall` not empty): the virtual pairs' terms of the solved
    /// Laplacian, `theta sum_i m sum_{j of the wall} coef_ij (u_i - u_j) / rho` with the
    /// no-slip continuation `u_j` of the solved `u`. Their sum over the walls is the momentum
    /// the solve changed to the solver's tolerance (the fluid pairs cancel).
    fn split_viscous_force(
        &self,
        ctx: &Context<N>,
        coef: &[f64],
        theta: f64,
        visc_curv: &[Vector<N>],
        u: &[Vector<N>],
        books: &mut Books<N>,
    ) {
        let walls = books.per_wall.len();
        if walls == 0 {
            return;
        }
        let c = theta * ctx.mass / self.rho;
        let rows =
            self.virtual_viscous_sums(ctx, coef, visc_curv, u, walls, |k| ctx.virt.wall_of(k));
        for by_wall in &rows {
            for (b, w) in books.per_wall.iter_mut().zip(by_wall) {
                *b += w * c;
            }
        }
    }

    /// Per fluid particle i, the virtual pairs' sums `sum_{j virtual} coef_ij (u_i - u_j)` of
    /// the solved Laplacian with the no-slip continuation (corrections `visc_curv`) of `u`,
    /// in `slots` sums: virtual particle k (0-based among the virtual ones) adds to
    /// `slot_of(k)`. Each wall's share ([`Isph::split_viscous_force`]) and each particle's
    /// share of the plate load ([`Isph::viscous_wall_terms`]) are these sums.
    pub(super) fn virtual_viscous_sums(
        &self,
        ctx: &Context<N>,
        coef: &[f64],
        visc_curv: &[Vector<N>],
        u: &[Vector<N>],
        slots: usize,
        slot_of: impl Fn(usize) -> usize + Sync,
    ) -> Vec<Vec<Vector<N>>> {
        let (n, nl) = (ctx.n, &ctx.nl);
        let ue = ctx.virt.extend_velocity(u, visc_curv);
        (0..n)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| {
                let off = nl.offset(i);
                let mut sums = vec![Vector::<N>::zeros(); slots];
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let j = j as usize;
                    if j >= n {
                        sums[slot_of(j - n)] += (ue[i] - ue[j]) * coef[off + kk];
                    }
                }
                sums
            })
            .collect()
    }

    /// Viscosity of the Laplacian term (solvent + EVSS's alpha_V eta0) at velocity gradient k.
    #[inline]
    pub(super) fn laplacian_viscosity(&self, k: &Tensor<N>) -> f64 {
        self.evss.viscous_viscosity(self.model.solvent_viscosity(k))
    }
}

/// The EVSS scale `evss_alpha` (alpha_V / (1 - beta)) ISPH uses in a scene with a free surface:
/// the configured one, raised so that the Laplacian carries at least
/// [`MIN_COMPACT_VISCOSITY_RATIO`] of eta0. Inelastic models (no polymer viscosity) keep theirs;
/// so does the closed channel (not measured there; King & Lind run its beta = 0 case with
/// alpha_V = 0.01).
pub fn isph_evss_alpha<R: Rheology>(model: &R, evss_alpha: f64) -> f64 {
    let eta_p = model.polymer_viscosity();
    if !R::ELASTIC || eta_p <= 0.0 {
        return evss_alpha;
    }
    let eta_s = model.solvent_viscosity(&Tensor::<2>::zeros());
    let short = MIN_COMPACT_VISCOSITY_RATIO * (eta_s + eta_p) - eta_s;
    // Relative margin: beta = 0.1 exactly must not switch EVSS on through round-off.
    if short <= 1e-9 * (eta_s + eta_p) {
        return evss_alpha;
    }
    evss_alpha.max(short / eta_p)
}
