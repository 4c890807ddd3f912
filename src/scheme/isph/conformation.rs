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

use super::{Context, Isph, MIN_TASK};
use crate::config::ConformationMethod;
use crate::dim::{Const, Dim, Tensor, Vector};
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
            // Runge-Kutta is stable for it. The Lagrangian shift is a small displacement and
            // keeps the single stage of eq. (31).
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
                    let a_n = rheology::advance(method, model, &a0, &a0, &kappa[i], 0.5 * dt);
                    rheology::advance(method, model, &a0, &a_n, &kappa[i], dt)
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
