//! Step 3 of King & Lind 2021's ISPH (section III.B): the conformation tensor from n-1/2 to
//! n+1/2 with the corrected velocity gradient (20) of u^n through the project's rheology
//! ([`rheology::advance`], log-conformation by default) by the midpoint rule (the rate taken at
//! A^n, predicted by a half step), plus the ALE term `dt u_ps . grad Psi` of (31) (of A for the
//! direct update); then the stress Phi (EVSS) of the fluid and of the virtual particles.
//!
//! **Second order in time where it could be measured.** Measured on King & Lind's channel
//! (Oldroyd-B, Re = 1, beta = 0.1, Wi = 5, Eulerian, 30 across, t = 0..3, centre line against
//! Waters & King at t = 2.35 / 2.65): the first-order forward-Euler conformation update (rate at
//! A^{n-1/2}) with backward Euler for the solvent was -4.8 % / -6.0 % at the default step and -0.9
//! % at a third of it. With the midpoint conformation update: +1.5 % / +2.2 % (backward Euler),
//! +1.1 % / +1.6 % (Crank-Nicolson), the same +1.0 % / +1.6 % at a third of the step and with the
//! explicit viscous step (the rest is spatial: 7 % at 15 across). The solvent step is the theta
//! method `(I - theta dt nu lap) u* = (I + (1 - theta) dt nu lap) u^n + dt [...]`: theta = 1/2 in
//! the closed channel (Newtonian start-up: largest centre-line error 0.2 % against 2.7 % with theta
//! = 1), theta = 1 with a free surface, where Crank-Nicolson's undamped stiff modes rang: the
//! Newtonian drop of King & Lind IV.C at W/dr = 40 lost 48 % of its volume by t* = 8 (theta = 0.6:
//! 4.1 %; theta = 1: 1.7 %). In the channel the viscous term's mirrors continue the wall curvature
//! of the wall's momentum balance, `mu_w u''_w = -(rho g.t + dPhi_tn/dn)` (no acceleration at a
//! no-slip wall), not the curvature fitted to u^n (`boundary::wall_profile`): the fitted one is
//! explicit in u and, with Crank-Nicolson, fed back into the wall row until it ran away (Newtonian
//! wall row 1.78 U, centre line 1.052 U); backward Euler damped it. What is still first order: the
//! conformation is stored at the end of the step, not staggered by half a step (symplectic Euler in
//! the coupling of u and A): at 15 across the centre lines at the default step, a third and a tenth
//! of it differ by 0.0083 U and 0.0028 U (a ratio of 3).
//!
//! **Eulerian ALE term by three stages.** In the Eulerian frame the ALE term of (31),
//! `dt u_ps . grad Psi` with u_ps = -u, is the whole advection of the stress: a central
//! difference, which forward Euler amplifies by about 1 + (u dt k)^2 per step for every mode
//! that varies along the flow (King & Lind's Eulerian "checkerboard-type instability",
//! crashing at Wi >= 16). It is integrated by Shu & Osher's three-stage SSP Runge-Kutta
//! scheme (stable for a central difference up to u dt k = sqrt 3), three neighbour sums of
//! Psi per step. Measured (Oldroyd-B, Re = 1, beta = 0.1, 30 across): Wi = 50 broke at
//! t = 2.87 (det A from 1 to 0.005 once tr A passed 3000) and now follows Waters & King
//! within 0.20 % to t = 4 with det A >= 1; Wi = 5 within 1.8 % to t = 3. Tried first:
//! sub-cycling the constitutive update (no change: breakdown at t = 2.871 both ways),
//! dropping the term (a diagnostic, exact only for this flow: det A >= 1 to t = 3), a
//! Lax-Wendroff term by the compact Espanol & Revenga second derivative (to t = 4, but det A
//! drifted to 0.68 and the centre line 4 % low) and a one-sided (upwind) gradient (stable,
//! but its error in the cross-stream second derivative put Wi = 5 off by 3.6 U at t = 2.95).
//!
//! **Traceless velocity gradient.** The conformation equation is written for an incompressible
//! flow, where `tr(kappa) = div u = 0`; its upper-convected part changes `ln det A` at
//! `2 tr(kappa)` (`logconf`, the diagonal of B), and relaxation alone keeps `det A >= 1` for
//! Oldroyd-B and UCM. The corrected gradient (20) of u^n is not traceless: the PPE makes the
//! divergence of u* plus the density-invariant sources vanish at r*, not that of u^n at the
//! next step's positions, and the free-surface particles take L = I. So in scenes with a free
//! surface the conformation step takes `kappa - tr(kappa) / N I` (the EVSS stress and the shear
//! rate of the viscosity keep the full gradient). Closed flows keep the full gradient: there
//! the PPE has no density source and no surface rows, and in the Eulerian Oldroyd-B channel at
//! Wi = 50 (test `eulerian_isph_channel_advects_the_stress_stably_at_wi_50`) the traceless
//! gradient lowered the smallest det A from above 0.9999999 to 0.99998. Measured on King &
//! Lind's drop (UCM, De = 10, W/dr = 40): in free flight (a rigid translation) min det A is
//! 1.000, against 0.766 with the full gradient.
//!
//! **The surface rows' stretching** (normal-stress surface condition, the jet). The rest of the
//! step gives the free surface the uncorrected gradient ([`super::neighbours`]), which on a
//! truncated support reads the stretching along the surface short (0.73-0.80 of the column's
//! dv/dy on the surface rows of King & Lind's jet at 6 across), so the polymer of the surface
//! rows, a third to a half of a column 4-6 particles wide, was stretched too little. With
//! `isph_free_surface = normal_stress` the conformation takes each surface row's gradient
//! with its own Bonet & Lok 1999 matrix, as (35a)'s surface value does ([`super::free_surface`]);
//! the stress Phi's EVSS part, the viscosity and the ALE remapping keep the uncorrected one.
//! Measured (Oldroyd-B jet, Wi = 1/3, H = 12 D, 6 across, first contact against the slender-sheet
//! model): -9.1 % -> -6.8 % alone (docs/methods.md, "Why ISPH's column falls early"). The drops
//! (p = 0 on the surface) keep the uncorrected gradient, whose stability they need.
//!
//! **Bounded ALE term with a free surface.** With the traceless gradient, the one thing left
//! that could lower det A is the Lagrangian ALE term `dt u_ps . grad Psi` of (31). As a central
//! difference it is not bounded: where Psi varies steeply (the wall row at the moving contact
//! line, where the no-slip shear stretches the polymer) it overshoots, and the shifted value
//! leaves the range of its neighbours. Measured on the UCM drop at De = 10 (W/dr = 40, default
//! step, a per-step trace of the worst particles): from impact (t* = 0.47) tr A in the contact
//! line's wall row grew to 1.5e3 by t* = 1.0 and 1.4e4 by t* = 1.035, det A fell to 0.4, the
//! row's speed ran away (20 m/s at t* = 1.042) and the conformation became non-finite at
//! t* = 1.05. So with a free surface the Lagrangian ALE term is one-sided and convex
//! (`Isph::ale_one_sided`): the shifted Psi_i is `Psi_i + c sum_j w_ij (Psi_j - Psi_i)` over the
//! neighbours ahead of the shift (`w_ij = V grad W_ij . u_s > 0`), `c` chosen so that a field
//! linear along the shift moves exactly as the central form moves it, and capped so that the
//! weights of the neighbours sum to at most 1. The new Psi_i is then a convex combination of
//! Psi_i and its neighbours': tr Psi = ln det A stays within their range, so with relaxation
//! (which raises det A towards 1 for UCM and Oldroyd-B) min det A stays >= 1 for good; the
//! shift is a fraction of dx per step, so the one-sided error is small. The Eulerian frame's
//! ALE term is the whole advection and keeps its three stages (above); the closed channel's
//! Lagrangian frame keeps the central single stage (not measured there). Measured on the drop
//! (eta0 = 5 Pa s, default step, `viscosph run`, threads 1, outputs every 0.2 t*; W*(8) /
//! largest |volume_error| / min det A over t* <= 8, the central difference in brackets):
//! UCM, De = 10: W/dr = 20 3.851 / 4.56 % / 1.000 (breakdown at t* = 2.8), W/dr = 40
//! 3.605 / 2.46 % / 1.000 (breakdown at t* = 1.03); both spread to W* = 4.70 at t* = 2.8 and
//! retract, and at W/dr = 20 the sheet, three particles thick, tears from t* = 4 (the volume
//! error is that). UCM, De = 1: W/dr = 20 2.024 / 2.50 % / 1.000 (1.995 / 2.02 % / 0.653);
//! W/dr = 40 1.918 / 1.36 % / 1.000 (1.906 / 1.65 % / 0.098). Oldroyd-B, De = 1,
//! beta = 0.1: W/dr = 20 1.879 / 2.91 % / 1.000 (1.877 / 2.49 % / 1.000); W/dr = 40
//! 1.862 / 1.35 % / 1.000 (1.868 / 1.49 % / 0.980). Tried first: clipping the central
//! difference's result into the neighbours' range component by component (UCM De = 10,
//! W/dr = 40: breakdown at t* = 1.88, tr A 1.7e3 in the contact line's row at t* = 1.66; at
//! half the step t* = 6.97, det A down to 0.27), the closed channel's stretched-polymer wave
//! limit (`step_size`: it never bound, c dt / h <= 0.7), and EVSS's explicit part on the
//! compact operator, i.e. `-alpha_V eta0 lap u^n` by Morris' Laplacian instead of
//! `alpha_V eta0 2D` in Phi (both-sides diffusion: it only filters the explicit forces, and
//! the drop broke at impact, t* = 0.56).

use super::{Context, Isph, MIN_TASK};
use crate::config::ConformationMethod;
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::operators::kinematics::recorrect_rows;
use crate::rheology::{self, logconf, Rheology};
use crate::state::State;
use rayon::prelude::*;

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// The conformation tensors at n + 1/2 from those of n - 1/2 (`conf`), the velocity
    /// gradients `kappa` of u^n and the ALE velocity `u_ps` (empty for an inelastic model); a
    /// non-finite tensor is a breakdown.
    pub(super) fn conformation(
        &self,
        conf: &[Tensor<N>],
        kappa: &[Tensor<N>],
        u_ps: &[Vector<N>],
        ctx: &Context<N>,
    ) -> Result<Vec<Tensor<N>>, String> {
        let (n, dt, vol, umax) = (ctx.n, ctx.dt, ctx.vol, ctx.umax);
        let (nl, l, pairs) = (&ctx.nl, &ctx.l, &self.pairs);
        let conf: Vec<Tensor<N>> = if R::ELASTIC {
            let log = self.method == ConformationMethod::Log;
            // The field the ALE term advects: Psi = log A, or A for the direct update.
            let psi: Vec<Tensor<N>> = conf
                .par_iter()
                .map(|a| if log { logconf::log_spd(a) } else { *a })
                .collect();
            let (model, method) = (&self.model, self.method);
            // dt u_ps . grad f (King & Lind eq. (31)'s ALE term) for every particle.
            let ale = |f: &[Tensor<N>]| -> Vec<Tensor<N>> {
                (0..n)
                    .into_par_iter()
                    .with_min_len(MIN_TASK)
                    .map(|i| {
                        let off = nl.offset(i);
                        let us = l[i].transpose() * u_ps[i];
                        let mut adv = Tensor::<N>::zeros();
                        if us != Vector::<N>::zeros() {
                            for (kk, &j) in nl.of(i).iter().enumerate() {
                                // Virtual particles carry their parent's conformation (the
                                // mirrors' NoSlip stress).
                                let pj = ctx.source(j as usize);
                                adv += (f[pj] - f[i]) * (pairs.grad[off + kk].dot(&us) * vol);
                            }
                        }
                        adv * dt
                    })
                    .collect()
            };
            // Eulerian frame: the ALE term is the whole advection, a central difference that
            // forward Euler amplifies (module documentation); Shu & Osher's three-stage SSP
            // Runge-Kutta is stable for it. The Lagrangian shift is a small displacement: with
            // a free surface the bounded one-sided form (module documentation, "Bounded ALE
            // term"), in the closed channel the single stage of eq. (31).
            let advected: Vec<Tensor<N>> = if !ctx.lagrangian {
                let d0 = ale(&psi);
                let p1: Vec<Tensor<N>> = psi.iter().zip(&d0).map(|(p, d)| p + d).collect();
                let d1 = ale(&p1);
                let p2: Vec<Tensor<N>> = psi
                    .iter()
                    .zip(p1.iter().zip(&d1))
                    .map(|(p, (q, d))| p * 0.75 + (q + d) * 0.25)
                    .collect();
                let d2 = ale(&p2);
                psi.iter()
                    .zip(p2.iter().zip(&d2))
                    .map(|(p, (q, d))| p * (1.0 / 3.0) + (q + d) * (2.0 / 3.0))
                    .collect()
            } else if self.free_surface {
                self.ale_one_sided(&psi, u_ps, ctx)
            } else {
                psi.iter().zip(ale(&psi)).map(|(p, d)| p + d).collect()
            };
            (0..n)
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .map(|i| {
                    let shifted = advected[i];
                    let a0 = if log {
                        logconf::exp_sym(&shifted)
                    } else {
                        shifted
                    };
                    // Midpoint rule: the rate of A from n - 1/2 to n + 1/2 is taken at
                    // A^n (predicted by a half step), not at A^{n-1/2}: second order in time.
                    // With a free surface, the incompressible part of the velocity gradient
                    // (module documentation, "Traceless velocity gradient").
                    let k = if self.free_surface {
                        deviatoric(&kappa[i])
                    } else {
                        kappa[i]
                    };
                    let a_n = rheology::advance(method, model, &a0, &a0, &k, 0.5 * dt);
                    rheology::advance(method, model, &a0, &a_n, &k, dt)
                })
                .collect()
        } else {
            Vec::new()
        };
        if let Some(i) = conf.iter().position(|a| !a.iter().all(|v| v.is_finite())) {
            return Err(format!(
                "the conformation tensor of particle {i} became non-finite: the polymer stress \
                 integration blew up (max |u| = {umax:.3e} m/s)"
            ));
        }
        Ok(conf)
    }

    /// The velocity gradients the conformation takes where they differ from `kappa` (module
    /// documentation, "The surface rows' stretching"): with the normal-stress surface condition
    /// and an elastic model, `kappa` with each surface row's gradient of `u_n` (fluid and
    /// virtual velocities) recomputed with its own correction matrix; None otherwise.
    pub(super) fn surface_own_gradient(
        &self,
        kappa: &[Tensor<N>],
        u_n: &[Vector<N>],
        ctx: &Context<N>,
    ) -> Option<Vec<Tensor<N>>> {
        let s = ctx
            .surf
            .as_ref()
            .filter(|_| R::ELASTIC && self.normal_stress)?;
        let mut k = kappa.to_vec();
        recorrect_rows(
            &mut k,
            &s.is_surface,
            u_n,
            ctx.vol,
            &ctx.nl,
            &self.pairs,
            &ctx.l_own,
        );
        Some(k)
    }

    /// The stress Phi (polymer stress with EVSS's part, King & Lind eqs. (6)-(8)) of the
    /// conformations `conf` at the velocity gradients `kappa`, for the fluid and for the virtual
    /// particles (both empty for an inelastic model).
    pub(super) fn polymer_stress(
        &self,
        st: &State<N>,
        ctx: &Context<N>,
        conf: &[Tensor<N>],
        kappa: &[Tensor<N>],
    ) -> (Vec<Tensor<N>>, Vec<Tensor<N>>) {
        if !R::ELASTIC {
            return (Vec::new(), Vec::new());
        }
        let phi: Vec<Tensor<N>> = conf
            .iter()
            .map(|a| self.model.polymer_stress(a))
            .zip(kappa)
            .map(|(t, k)| self.evss.phi(&t, k))
            .collect();
        let virt = self.virtual_stresses(ctx, &st.walls, &st.fluid, &phi);
        (phi, virt)
    }
}

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// The Lagrangian ALE term of eq. (31) with a free surface, bounded (module documentation,
    /// "Bounded ALE term"): `f_i + c sum_j w_ij (f_j - f_i)` over the neighbours ahead of the
    /// shift, `w_ij = V grad W_ij . u_s > 0` (`u_s = L_i^T u_ps`, as in the central form),
    /// with `c = dt |u_s|^2 / sum_j w_ij (x_j - x_i) . u_s` so that a field linear along the
    /// shift moves by `dt u_s . grad f` exactly, capped at `c sum_j w_ij <= 1`: the new value
    /// is a convex combination of `f_i` and its neighbours'. Virtual particles carry their
    /// parent's `f`. No neighbour ahead (a surface particle shifted outwards): `f_i`.
    fn ale_one_sided(
        &self,
        f: &[Tensor<N>],
        u_ps: &[Vector<N>],
        ctx: &Context<N>,
    ) -> Vec<Tensor<N>> {
        let (nl, l, pairs, x) = (&ctx.nl, &ctx.l, &self.pairs, &self.all_x);
        let (dt, vol, dom) = (ctx.dt, ctx.vol, &self.p.domain);
        (0..ctx.n)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| {
                let off = nl.offset(i);
                let us = l[i].transpose() * u_ps[i];
                let us2 = us.norm_squared();
                if us2 == 0.0 {
                    return f[i];
                }
                let xi = ctx.xs[i];
                let (mut num, mut wsum, mut den) = (Tensor::<N>::zeros(), 0.0, 0.0);
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let w = pairs.grad[off + kk].dot(&us) * vol;
                    if w > 0.0 {
                        num += (f[ctx.source(j as usize)] - f[i]) * w;
                        wsum += w;
                        den += w * dom.delta(&x[j as usize], &xi).dot(&us);
                    }
                }
                if den <= 0.0 {
                    return f[i];
                }
                f[i] + num * (dt * us2 / den).min(1.0 / wsum)
            })
            .collect()
    }
}

/// `kappa - tr(kappa) / N I`: the velocity gradient of an incompressible flow, which the
/// conformation equation is written for (module documentation, "Traceless velocity
/// gradient").
fn deviatoric<const N: usize>(kappa: &Tensor<N>) -> Tensor<N>
where
    Const<N>: Dim,
{
    kappa - Tensor::<N>::identity() * (kappa.trace() / N as f64)
}
