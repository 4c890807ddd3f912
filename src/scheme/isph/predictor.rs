//! Step 4 of King & Lind 2021's ISPH, the predictor (24):
//! `u* = u^n + dt [u_ps . grad u^n + nu lap u + div Phi / rho]`. Per particle, in one pass over
//! the pair cache: the ALE remapping `u_ps . grad u^n` (kappa u_ps), div Phi / rho by the positive
//! form of (20) with a free surface (L = I; momentum-conserving pairs) and by the corrected
//! negative form in the closed channel (module documentation, "The closed periodic channel"), and
//! the part of the solvent (and EVSS) viscosity by Morris' Laplacian (21) that is explicit: all
//! of it under `isph_viscous_step = explicit` (the paper's (24)), `1 - theta` of it under the
//! implicit step ([`super::viscous`]), which then solves for the rest. The virtual particles'
//! share of each pair force is the walls' (`Books::wall_on_fluid`). In a closed cell with a
//! curved wall also `-grad p^n / rho` (the incremental pressure correction: module
//! documentation of `isph`, "Curved walls").
//!
//! **div Phi with the normal-stress surface condition** (the jet): the positive form with the
//! Bonet & Lok 1999 correction on its difference part,
//! `sum_j [(Phi_j - Phi_i) L_i grad W_ij + 2 Phi_i grad W_ij] V_j / rho`, L_i every row's own
//! matrix (the surface rows' included, `Context::l_own`). The positive form is the difference
//! form plus `2 Phi_i s_i`: it keeps that stress-free part, and the difference part, which on a
//! truncated support carries the stress gradient along the surface short by the moment
//! `sum_j V x_ji grad W_ij` (0.72 on the surface rows of a column, 0.84-0.87 on average over a
//! column 4-5 particles wide), reads it in full. The departure from the positive form is not a
//! pair force; its mean over the free particles is removed (a free surface exerts no net
//! force). Measured with the polymer's normal stress in (35a)'s surface value and the surface
//! rows' own gradient in the conformation ([`super::free_surface`], [`super::conformation`]):
//! docs/methods.md, "Why ISPH's column falls early".
//!
//! The solvent's free-surface traction ([`super::free_surface`]) is explicit here under the
//! explicit viscous step and implicit in the viscous solve otherwise. The inlet's held particles
//! keep their velocity; the momentum the step would have given them is the inlet's.

use super::free_surface::SURFACE_TRACTION_TRANSPOSED;
use super::projection::extend_pressure;
use super::{Books, Context, Fields, Isph, MIN_TASK};
use crate::config::ViscousStep;
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::geometry::Shape;
use crate::rheology::Rheology;
use crate::state::State;
use rayon::prelude::*;

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// The predicted velocity u* of the state `st` for the fields `f` of step 3, with the
    /// inlet's held particles reset to their velocity.
    pub(super) fn predictor(
        &self,
        st: &State<N>,
        ctx: &Context<N>,
        f: &Fields<N>,
        books: &mut Books<N>,
    ) -> Result<Vec<Vector<N>>, String> {
        let t = self.clock();
        let fl = &st.fluid;
        let (n, dt, vol, rho) = (ctx.n, ctx.dt, ctx.vol, self.rho);
        let (nl, l, pairs) = (&ctx.nl, &ctx.l, &self.pairs);
        let (kappa, u_ps, mu, phi, phi_virtual) =
            (&f.kappa, &f.u_ps, &f.mu, &f.phi, &f.phi_virtual);
        let explicit = self.viscous == ViscousStep::Explicit;
        // Closed channel: the virtual particles of the viscous term continue the wall curvature
        // that the wall's momentum balance prescribes.
        let visc_curv_closed: Vec<Vector<N>>;
        let visc_curv: &[Vector<N>] = if self.free_surface {
            &ctx.u_curv
        } else {
            visc_curv_closed = self.viscous_curvature(ctx, &st.walls, phi, mu);
            &visc_curv_closed
        };
        let u_visc_closed: Vec<Vector<N>>;
        let u_visc: &[Vector<N>] = if self.free_surface {
            &f.u_n
        } else {
            u_visc_closed = ctx.virt.extend_velocity(&fl.v, visc_curv);
            &u_visc_closed
        };
        // Weight of u^n in the viscous term: all of it explicitly, 1 - theta implicitly.
        let theta = if explicit { 0.0 } else { self.theta };
        let w_old = 1.0 - theta;
        let mass = ctx.mass;
        let free_surface = self.free_surface;
        let walls = books.per_wall.len();
        // With the normal-stress surface condition div Phi is the corrected positive form
        // (module documentation): its departure from the positive form, per row.
        let corrected_phi = R::ELASTIC && self.normal_stress;
        type Row<const N: usize> = (Vector<N>, Vector<N>, Vector<N>, Vec<Vector<N>>, Vector<N>);
        let rows: Vec<Row<N>> = (0..n)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| {
                let off = nl.offset(i);
                let remap = kappa[i] * u_ps[i];
                let (mut f, mut fw) = (Vector::<N>::zeros(), Vector::<N>::zeros());
                // The virtual pairs' share wall by wall, where the step splits it.
                let mut by_wall = vec![Vector::<N>::zeros(); walls];
                // Closed cell, elastic, split: the difference form's fluid pairs less the
                // momentum-conserving positive form of the same pairs (see below).
                let mut remainder = Vector::<N>::zeros();
                // The corrected positive form's departure: (L_i - I) on the difference part.
                let mut departure = Vector::<N>::zeros();
                let l_less_i = if corrected_phi && !ctx.held.holds(i) {
                    Some(ctx.l_own[i] - Tensor::<N>::identity())
                } else {
                    None
                };
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let j = j as usize;
                    let pj = ctx.source(j);
                    let mut a = Vector::<N>::zeros();
                    if R::ELASTIC {
                        let phi_j = if j < n { phi[j] } else { phi_virtual[j - n] };
                        a += if free_surface {
                            (phi[i] + phi_j) * pairs.grad[off + kk] * (vol / rho)
                        } else {
                            (phi_j - phi[i]) * (l[i] * pairs.grad[off + kk]) * (vol / rho)
                        };
                        if let Some(d) = &l_less_i {
                            departure +=
                                (phi_j - phi[i]) * (d * pairs.grad[off + kk]) * (vol / rho);
                        }
                        if walls > 0 && j < n && !free_surface {
                            remainder += a - (phi[i] + phi_j) * pairs.grad[off + kk] * (vol / rho);
                        }
                    }
                    if w_old > 0.0 {
                        let c = pairs.morris[off + kk] * 0.5 * (mu[i] + mu[pj]) / rho * w_old;
                        a += (u_visc[i] - u_visc[j]) * c;
                    }
                    ctx.add_pair(j, a, &mut f, &mut fw, &mut by_wall);
                }
                // Closed channel: the difference form's fluid pairs do not cancel; what they
                // leave is the force the walls exert through the stress (no other boundary).
                // Split wall by wall: the positive form (phi_i + phi_j) grad W_ij of the same
                // pairs cancels pair by pair, so the fluid pairs' sum is the sum of each
                // particle's difference from it, `remainder`, which vanishes where the kernel's
                // support is full (it is -2 phi_i sum_j grad W_ij V_j with L = I) and is booked
                // to the particle's nearest wall.
                let on_wall = if free_surface || !R::ELASTIC {
                    fw
                } else {
                    f + fw
                };
                if walls > 0 && R::ELASTIC && !free_surface {
                    let nearest = (0..walls)
                        .min_by(|&a, &b| {
                            let (da, db) = (
                                st.walls[a].signed_distance(&fl.x[i]),
                                st.walls[b].signed_distance(&fl.x[i]),
                            );
                            da.total_cmp(&db)
                        })
                        .unwrap_or(0);
                    by_wall[nearest] += remainder;
                }
                (remap, f + fw, on_wall, by_wall, departure)
            })
            .collect();
        // Closed channel: the body force goes into the predictor (King & Lind eq. (24) as
        // printed). Nothing balances it but the viscous and polymer stresses, and with the
        // corrector's g (free-surface scenes, [`super::projection`]) the implicit viscous step
        // acts on u* = u - g dt: measured, the Newtonian channel then settled g dt (0.067 U at
        // 30 across) above Poiseuille everywhere, a wall slip of order dt.
        let g_pred = if self.free_surface {
            Vector::<N>::zeros()
        } else {
            self.p.gravity
        };
        let mut rhs: Vec<Vector<N>> = Vec::with_capacity(n);
        for (i, (remap, a, aw, by_wall, _)) in rows.iter().enumerate() {
            books.remap_force += remap * mass;
            books.wall_on_fluid += aw * mass;
            books.plate.add(i, aw * mass);
            for (b, w) in books.per_wall.iter_mut().zip(by_wall) {
                *b += w * mass;
            }
            rhs.push(fl.v[i] + (remap + a + g_pred) * dt);
        }
        // The incremental pressure correction: -grad p^n / rho in u* (module documentation of
        // `isph`, "Curved walls"), booked as the projection's pressure force.
        if self.incremental(ctx) {
            let p_n = self.previous_pressure(st, ctx);
            let p_all = extend_pressure(ctx, &p_n, &self.pressure_offsets(ctx));
            let grad = self.pressure_accelerations(ctx, &p_all, walls);
            for (i, (r, (a, aw, by_wall))) in rhs.iter_mut().zip(grad).enumerate() {
                books.wall_on_fluid += aw * mass;
                books.plate.add(i, aw * mass);
                for (b, w) in books.per_wall.iter_mut().zip(by_wall) {
                    *b += w * mass;
                }
                *r += a * dt;
            }
        }
        let held = &ctx.held;
        if corrected_phi {
            // Not a pair force: a free surface exerts no net force, so the departure's mean
            // over the free particles is removed, as for the surface terms.
            let mean = held.mean_over_free(rows.iter().map(|r| &r.4));
            for (i, (r, row)) in rhs.iter_mut().zip(&rows).enumerate() {
                if !held.holds(i) {
                    *r += (row.4 - mean) * dt;
                }
            }
        }
        if explicit && self.free_surface {
            // The solvent's surface traction, explicit (the implicit solve's
            // SurfaceTraction term on u^n): 2 mu_i (G_i + G_i^T) s_i / rho, its mean removed.
            let acc: Vec<Vector<N>> = (0..n)
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .map(|i| {
                    if held.holds(i) {
                        return Vector::<N>::zeros();
                    }
                    let s_i = pairs.gradient_sum(nl, i, vol);
                    let sym = self.along() * kappa[i]
                        + SURFACE_TRACTION_TRANSPOSED * kappa[i].transpose();
                    sym * s_i * (2.0 * mu[i] / rho)
                })
                .collect();
            let mean = held.mean_over_free(acc.iter());
            for (i, r) in rhs.iter_mut().enumerate() {
                if !held.holds(i) {
                    *r += (acc[i] - mean) * dt;
                }
            }
        }
        // The inlet's held particles keep their velocity: what the step's forces would have
        // given them is the inlet's, taken before the viscous solve, in which they are
        // Dirichlet rows (`viscous`), so that the column below hangs from a nozzle at the
        // inflow velocity, not from one it drags along within the step.
        for i in (0..n).filter(|&i| held.holds(i)) {
            books.held_momentum += (fl.v[i] - rhs[i]) * mass;
            rhs[i] = fl.v[i];
        }
        self.lap(t, "predictor: explicit terms", false);
        let mut u_star = if explicit {
            rhs
        } else {
            self.viscous_step(ctx, mu, visc_curv, theta, rhs, books)?
        };
        for i in (0..n).filter(|&i| held.holds(i)) {
            books.held_momentum += (fl.v[i] - u_star[i]) * mass;
            u_star[i] = fl.v[i];
        }
        Ok(u_star)
    }
}
