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
//! gradient lowered the smallest det A from above 0.9999999 to 0.99998. Measured on King & Lind's drop (eta0 = 5 Pa s, default step, outputs
//! every 0.2 t*, `viscosph run`, W*(8) / largest |volume_error| / min det A over t* <= 8, the
//! full gradient in brackets): in free flight (a rigid translation) min det A is now 1.000
//! (UCM De = 10, W/dr = 40: 0.766). UCM, De = 1: W/dr = 20 1.995 / 2.02 % / 0.653
//! (2.307 / 2.51 % / 0.303); W/dr = 40 1.906 / 1.65 % / 0.098 (2.019 / 1.77 % / 0.195).
//! Oldroyd-B, De = 1, beta = 0.1: W/dr = 20 1.877 / 2.49 % / 1.000 (1.933 / 2.78 % / 0.314);
//! W/dr = 40 1.868 / 1.49 % / 0.980 (1.908 / 1.51 % / 0.401): 20 and 40 now agree to 0.009 in
//! W*(8) (0.025). The Newtonian drop has no conformation and is unchanged. What still lowers
//! det A after impact is the ALE term (a central difference of Psi, which can undershoot
//! tr Psi where the stretch varies steeply). **UCM at De = 10 still breaks down** at W/dr = 40
//! (t* = 1.03, a non-finite conformation after the velocity ran away, 6.8e3 m/s; the full
//! gradient: t* = 1.31; at half the step t* = 1.16), while Oldroyd-B at beta = 0.05 and De = 10
//! runs to t* = 8 (W*(8) 2.348, min det A 0.914): the breakdown belongs to beta = 0, where all
//! of the viscous stress but EVSS's 0.05 eta0 goes through the explicit polymer stress.

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

/// `kappa - tr(kappa) / N I`: the velocity gradient of an incompressible flow, which the
/// conformation equation is written for (module documentation, "Traceless velocity
/// gradient").
fn deviatoric<const N: usize>(kappa: &Tensor<N>) -> Tensor<N>
where
    Const<N>: Dim,
{
    kappa - Tensor::<N>::identity() * (kappa.trace() / N as f64)
}
