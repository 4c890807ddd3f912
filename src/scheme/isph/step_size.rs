//! The step of King & Lind 2021's ISPH: their eq. (28), `0.2 min(h / max|u|, rho h^2 / eta0)`,
//! with the limits this scheme needs besides, and the guard that stops a blown-up run.
//!
//! **Time step** (28) with the coefficient 2/3 `time_step_factor` (0.2 at the default), plus
//! `sqrt(h / |g|)` so a fluid at rest still has a finite step. In the closed channel also the
//! stretched polymer's wave: `5 h / c` (times the coefficient: a Courant number of 1) with
//! `c^2 = (G + s_max) / rho`, s_max the largest principal polymer stress (a string under
//! tension G A carries transverse waves at sqrt(G l_max(A) / rho)); (28) and `h / sqrt(G / rho)`
//! do not see the stretch, and as a start-up flow slows (28)'s step grows while tr A still
//! rises. `STRETCHED_WAVE_LIMIT` gives the measurements. In free-surface scenes also the
//! positive-form pressure wave `0.5 h sqrt(rho / p_max)` (not scaled by the factor): the
//! projection's `(p_i + p_j)` gradient is an explicit interparticle spring of stiffness
//! proportional to p, and at the gravity limit of a drop resting on the plate its Courant
//! number grows as sqrt(H / h) (the Newtonian Re = 4 drop blew up at W/dr = 120, t* = 1.5,
//! without it). `Isph::pressure_wave_dt` derives it; `PRESSURE_WAVE_LIMIT` gives the
//! measurements.
//!
//! **With the normal-stress surface condition (the jet) the implicit viscous step keeps
//! `nu dt / h^2 <= 1`** at the default factor (`SPLIT_VISCOUS_LIMIT`): an accuracy limit.
//! Split from the projection, backward Euler's viscous solve equilibrates the surface rows to
//! its own surface terms within the step, and the pressure that the explicit step's PPE builds
//! from the viscous force's lateral part (a suction two to three times (35a)'s tension inside
//! a 4-particle column, measured) is then missing from the column's tension: the Newtonian jet
//! landed 7-11 % early at nu dt / h^2 of about 3.6, converging only as the square root of the
//! step (docs/methods.md, "Why ISPH's column falls early").
//!
//! **EVSS's explicit part limits the implicit step**: `rho h^2 / (alpha_V eta0)`, the explicit
//! viscous limit of the wide operator on alpha_V eta0 2D. Without it alpha_V eta0 went
//! through the implicit solve but its explicit counterpart ran at nu alpha dt / h^2 = 1.2
//! (UCM, De = 0.1, W/dr = 40; that run broke at t* = 1.1). At the floor's 0.05 eta0 the limit
//! does not bind at W/dr = 40 (it is 4.6 times the elastic step there).
//!
//! **The default step's temporal error is the splitting's, not a limit's**: on the Re = 4 drop
//! at W/dr = 20, W*(8) is 16 % wider at the default step than at an eighth of it, and the error
//! sits in the slow spreading under the gravity limit, where the pressure gradient and gravity
//! (applied in the corrector, outside the implicit viscous solve) slip along the wall
//! (docs/isph.md, "The default step's temporal error, and where it sits").
//!
//! **A blow-up stops the run.** With no density to watch, a diverging incompressible run would
//! crawl on: (28) follows the speed down and never reaches zero. A stable step below
//! `DT_COLLAPSE` of the scene's time scale `h / c` (its sound speed, ten times the largest
//! speed it expects) is a breakdown that names the fastest particle's speed.

use super::Isph;
use crate::config::ViscousStep;
use crate::dim::{Const, Dim, Tensor};
use crate::kernel::Kernel;
use crate::rheology::{logconf, Rheology};
use crate::state::State;
use rayon::prelude::*;

/// The coefficient of King & Lind eq. (28) per unit `time_step_factor` (0.3 -> 0.2).
pub(super) const DT_COEF_PER_FACTOR: f64 = 2.0 / 3.0;
/// The stretched-polymer wave limit of the closed channel per unit time-step coefficient
/// ([`Isph::stretched_wave_dt`]): 5, so a Courant number c dt / h of 1 at the default
/// coefficient 0.2. Measured (Oldroyd-B, Re = 1, 30 across, Lagrangian): without it Wi = 100
/// followed Waters & King within 0.1 % to t = 17.5 and broke at t = 18.3, where c dt / h had
/// grown to 2.4 (tr A = 1.1e5); beta = 0 at Wi = 16 broke at t = 4.0 once it passed 1 (3 at
/// the end), as the flow slowed and (28)'s step grew while tr A still rose.
const STRETCHED_WAVE_LIMIT: f64 = 5.0;
/// The positive-form pressure wave limit of free-surface scenes ([`Isph::pressure_wave_dt`]):
/// `dt <= PRESSURE_WAVE_LIMIT h sqrt(rho / p_max)`, a stability limit, so not scaled by
/// `time_step_factor` (scaled as 1.25 times the coefficient, test
/// `implicit_viscosity_converges_to_explicit` blew up at factor 0.03, presumably because the
/// pressure of the density-invariant source grows as 1 / dt^2 and fed back into the step; not
/// investigated further). Measured on a Newtonian drop
/// (eta = 5 Pa s, D = 2 cm) settling on the plate from rest, plate force (weight 3.08 N/m):
/// at W/dr = 40 (t = 0.1-0.4 s, time_step_factor 1.0) its standard deviation was 1.52 N/m
/// without the limit (0.62 at the default 0.3), 0.89 with 1 h / c_p, 0.04 with 0.5, 0.03 with
/// 0.25 and 0.12; at W/dr = 80 (t = 0.02-0.12 s) 0.22 with 0.5 (a noisy layer next to the
/// plate, particles at 0.08 m/s) and 0.03 with 0.25 (clean). 0.25 costs volume at W/dr = 40
/// (largest |volume_error| 0.88 % against 0.63 %: the per-step density-invariant source acts
/// harder at smaller steps), so 0.5 is kept: stable, the near-wall layer's noise left open
/// (docs/isph.md, "The positive-form pressure wave").
const PRESSURE_WAVE_LIMIT: f64 = 0.5;
/// The implicit viscous step's splitting limit with the normal-stress surface condition (the
/// jet): `dt <= SPLIT_VISCOUS_LIMIT rho h^2 / eta0` per unit time-step coefficient, i.e.
/// `nu dt / h^2 <= 1` at the default factor (eta0 the whole viscosity, as (28)'s viscous
/// limit; [`Isph::stable_dt`]). An accuracy limit, not a stability one: backward Euler's
/// viscous solve, split from the projection, lets the column's stretching lose part of its
/// tension within a layer of depth sqrt(nu dt) at the free surface, and a planar jet 4-6
/// particles across is all such layer. Measured on King & Lind's Newtonian jet (H = 12 D, 6
/// across, the sheet model 0.2243 s; lowest point at D/2 above the plate / first contact,
/// against the slender-sheet model of the same fall; with (35a)'s surface value from the
/// surface particles' own corrected gradient, `free_surface`): without the limit (nu dt / h^2
/// about 3.6) -6.9 % / -7.7 %, 275 steps to contact; `time_step_factor` 0.1 -3.0 % / -3.7 %,
/// 827 steps; this limit -2.2 % / -2.8 %, 1110 steps (1.2 s CPU against 0.4 s, the explicit
/// viscous step 2.9 s, +1.3 % / +0.8 %). Drops and channels (p = 0 on the surface, or none)
/// do not take it.
const SPLIT_VISCOUS_LIMIT: f64 = 5.0;
/// A stable step (28) this far below the scene's time scale ([`Isph::time_scale`]) means the
/// flow has blown up. An incompressible run has no density to watch, and (28) follows a
/// diverging speed down without ever reaching zero: a Re = 4 drop that diverged at W/dr = 80
/// (under an experimental surface pressure) reached a kinetic energy of 6e32 J/m and a step
/// of 5e-23 s and kept crawling instead of stopping. A legitimate run stays within a few decades
/// of the scale `h / c` (c ten times the largest speed the scene expects): it takes a particle
/// at about 2e7 c to reach this, 2e8 m/s in the drop of IV.C.
const DT_COLLAPSE: f64 = 1e-8;

/// The step [`Isph::step_size`] chose.
#[derive(Debug, Clone, Copy)]
pub(super) struct StepSize {
    /// The step taken.
    pub dt: f64,
    /// The stable step (at least `dt`; `State::last_dt`).
    pub stable: f64,
    /// Largest fluid speed.
    pub umax: f64,
}

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// The stable step of the state `st` (module documentation), at most `max_dt`; a step that
    /// collapsed or fell below [`DT_COLLAPSE`] of the scene's time scale is a breakdown.
    pub(super) fn step_size(&self, st: &State<N>, max_dt: f64) -> Result<StepSize, String> {
        let fl = &st.fluid;
        // A maximum does not depend on the order it is taken in: in parallel.
        let umax = fl.v.par_iter().map(|v| v.norm()).reduce(|| 0.0, f64::max);
        let dt_stable = self
            .stable_dt(umax)
            .min(self.stretched_wave_dt(&fl.conf))
            .min(self.pressure_wave_dt(&st.pressure));
        let dt = dt_stable.min(max_dt);
        if dt.is_nan() || dt <= 0.0 {
            return Err(format!("time step collapsed to {dt:e} s"));
        }
        let scale = self.time_scale();
        if dt_stable < DT_COLLAPSE * scale {
            return Err(format!(
                "the flow has blown up: the fastest particle moves at {umax:.3e} m/s, which sets \
                 a time step of {dt_stable:.3e} s, below {DT_COLLAPSE:e} of the scene's time \
                 scale {scale:.3e} s"
            ));
        }
        Ok(StepSize {
            dt,
            stable: dt_stable,
            umax,
        })
    }

    /// The scene's own time scale for the blow-up guard: one smoothing length at the scene's
    /// sound speed, `h / c` (`Params::eos`, 10 times the largest speed the scene expects,
    /// or the configured `sound_speed`), so the guard fires when the fastest particle moves
    /// at about `2e7 c`. A scale from the fluid's properties fails at one end or the other: the
    /// viscous time `rho h^2 / eta0` grows without bound as the viscosity falls (the ISPH
    /// elliptical drop, eta = 1e-3 Pa s, R = 1 m, 10 per diameter: 6.8e4 s, so its first step,
    /// 5e-4 s, read as a blow-up), and the gravity time is absent without gravity.
    fn time_scale(&self) -> f64 {
        let c = self.p.eos.c;
        if c > 0.0 && c.is_finite() {
            return self.kernel.h() / c;
        }
        // No sound speed given: the gravity time, else the viscous time.
        let h = self.kernel.h();
        let g = self.p.gravity.norm();
        if g > 0.0 {
            (h / g).sqrt()
        } else {
            self.rho * h * h / (self.model.max_viscosity() + self.evss.added_viscosity())
        }
    }

    /// The flow's part of King & Lind eq. (28): the smaller of `h / |u|_max` and
    /// `sqrt(h / g)`, infinite when nothing moves and nothing pulls. The step's other limits
    /// come on top of it in [`Self::stable_dt`]; the near-surface sources measure their step
    /// against it.
    pub(super) fn advective_limit(&self, umax: f64) -> f64 {
        let h = self.kernel.h();
        let mut lim = f64::INFINITY;
        if umax > 0.0 {
            lim = h / umax;
        }
        let g = self.p.gravity.norm();
        if g > 0.0 {
            lim = lim.min((h / g).sqrt());
        }
        lim
    }

    /// King & Lind eq. (28) with the limits of the viscous step (module documentation).
    fn stable_dt(&self, umax: f64) -> f64 {
        let h = self.kernel.h();
        let mut lim = self.advective_limit(umax);
        let rho_h2 = self.rho * h * h;
        let eta_all = self.model.max_viscosity() + self.evss.added_viscosity();
        if !lim.is_finite() {
            // Nothing moves and nothing pulls: the viscous limit gives the scale.
            lim = rho_h2 / eta_all;
        }
        match self.viscous {
            ViscousStep::Explicit => lim = lim.min(rho_h2 / eta_all),
            ViscousStep::Implicit => {
                if self.normal_stress {
                    lim = lim.min(SPLIT_VISCOUS_LIMIT * rho_h2 / eta_all);
                }
                if self.evss.is_on() {
                    lim = lim.min(rho_h2 / self.evss.added_viscosity());
                }
                if R::ELASTIC {
                    let (g_mod, lambda) = (self.model.modulus(), self.model.relaxation_time());
                    let eta_p = self.model.polymer_viscosity();
                    if g_mod > 0.0 {
                        let t_e = h / (g_mod / self.rho).sqrt();
                        lim = lim.min(if t_e <= lambda {
                            t_e
                        } else {
                            lambda.max(rho_h2 / eta_p)
                        });
                    }
                }
            }
        }
        self.dt_coef * lim
    }

    /// The positive-form pressure wave limit of a free-surface scene:
    /// `dt <= PRESSURE_WAVE_LIMIT h / c_p`, `c_p = sqrt(p_max / rho)`, p_max the
    /// largest pressure of the last step. The projection's pressure gradient is the positive
    /// form `-sum_j (p_i + p_j) grad W_ij V_j / rho` (momentum-conserving pairs), which is not
    /// zero-order consistent: under a uniform pressure p a particle displaced from its lattice
    /// site feels `-2 p s_i / rho`, `s_i = sum_j V_j grad_i W_ij`, a restoring spring of
    /// angular frequency `omega^2 = 2 p V |W''(0)| / rho` (about `0.66 p / (rho h^2)` for the
    /// quintic at h = 1.3 dx). The PPE does not see it, and it is explicit: with the velocity
    /// damped within the step (implicit viscosity, an overdamped particle) and the advection
    /// (27) averaging u^n and u^{n+1}, a displacement obeys
    /// `d_{n+1} = (1 - b) d_n - b d_{n-1}`, `b = (omega dt)^2 / 2`, unstable for
    /// `omega dt > sqrt(2)` (about `1.7 h / c_p`; the modes of neighbouring particles moving
    /// against each other are stiffer). This is the sound-speed condition of weakly
    /// compressible SPH (Monaghan 1992) with the pressure's own wave speed in place of c.
    /// (28)'s `h / |u|` and `sqrt(h / g)` do not see it: under the hydrostatic pressure of a
    /// drop of height H, `c_p dt / h = dt_coef sqrt(H / h)` at the gravity limit, which grows
    /// with the resolution (docs/isph.md, "The positive-form pressure wave").
    /// Infinite in closed flows (the pressure is defined up to a constant there) and before
    /// the first pressure solve.
    fn pressure_wave_dt(&self, pressure: &[f64]) -> f64 {
        if !self.free_surface {
            return f64::INFINITY;
        }
        let p_max = pressure.par_iter().copied().reduce(|| 0.0, f64::max);
        if p_max > 0.0 && p_max.is_finite() {
            PRESSURE_WAVE_LIMIT * self.kernel.h() * (self.rho / p_max).sqrt()
        } else {
            f64::INFINITY
        }
    }

    /// The closed channel's limit for a stretched polymer:
    /// `dt <= dt_coef STRETCHED_WAVE_LIMIT h / c` with `c^2 = (G + s_max) / rho`, s_max the
    /// largest tensile principal polymer stress over the particles (for f_S = A - I,
    /// G + s_max = G l_max(A)): the speed of a transverse wave along a string under that
    /// tension (module documentation, "Time step").
    /// Infinite for an inelastic model and in scenes with a free surface (not measured there).
    fn stretched_wave_dt(&self, conf: &[Tensor<N>]) -> f64 {
        if !R::ELASTIC || self.free_surface {
            return f64::INFINITY;
        }
        let g_mod = self.model.modulus();
        let s_max = conf
            .iter()
            .map(|a| Const::<N>::eigenvalues(&logconf::sym_eigen(&self.model.polymer_stress(a)))[0])
            .fold(0.0f64, f64::max);
        let c = ((g_mod + s_max) / self.rho).sqrt();
        if c > 0.0 && c.is_finite() {
            self.dt_coef * STRETCHED_WAVE_LIMIT * self.kernel.h() / c
        } else {
            f64::INFINITY
        }
    }
}
