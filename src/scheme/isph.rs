//! Incompressible SPH of King & Lind 2021 (section III): Chorin's projection with a pressure
//! Poisson equation, log-conformation stresses at half steps, EVSS, Fickian shifting, mirror
//! walls and a normal-stress free-surface condition.
//!
//! One step (`Isph::step`), the paper's steps 1-7 of section III.A:
//! 1. advect `r* = r^n + dt u^n` (23) (Eulerian frame: particles stay);
//! 2. mirrors of every plate ([`MirrorWall`], a [`Boundary`]), neighbour lists, the Bonet & Lok
//!    correction matrices (22), the free surface (36)-(39) and the shifting velocity (40)-(44)
//!    ([`shifting`], with the corrections its documentation lists); Eulerian: `u_ps = -u^n`;
//! 3. the conformation tensor from n-1/2 to n+1/2 with the velocity gradient of u^n (corrected
//!    gradient (20)) through the project's rheology ([`rheology::advance`], log-conformation by
//!    default) by the midpoint rule (the rate taken at A^n, predicted by a half step), plus the
//!    ALE term `dt u_ps . grad Psi` of (31) (of A for the direct update);
//! 4. the predictor (24): `u* = u^n + dt [u_ps . grad u^n + nu lap u + div Phi / rho]`, div Phi by
//!    the positive form of (20) (L = I) with a free surface, by the corrected negative form in the
//!    closed channel (see below), the solvent (and EVSS) viscosity by Morris' Laplacian (21),
//!    explicitly as in the paper, or implicitly ([`ppe::solve_viscous`]: the default; backward
//!    Euler with a free surface, Crank-Nicolson in the closed channel, see below);
//! 5. the PPE (25) `lap p = (rho / dt) div u*` ([`ppe::assemble_poisson`], BiCGStab + ILU(0) warm
//!    started from p^n), free-surface particles Dirichlet (p = 0 on the surface half a layer
//!    outside them, see below: the paper's (35a) was measured unstable here), mirrors Neumann
//!    with the hydrostatic offset;
//! 6. projection (26) `u^{n+1} = u* - dt grad p / rho + dt g`;
//! 7. advection (27) `r^{n+1} = r^n + dt/2 (u^n + u^{n+1} + 2 u_ps)`.
//!
//! Choices where the paper is silent or where we depart from it, each for a stated reason:
//! * **Gravity in the corrector** (King's newer code) with the hydrostatic mirror pressure
//!   `p_m = p_i + rho g . (r_m - r_i)`: a fluid at rest then holds its hydrostatic pressure exactly
//!   instead of through the no-slip mirror velocities of g dt.
//! * **Momentum-conserving pair forms.** The divergence of Phi is the positive form (the paper's
//!   choice with a free surface; the closed channel takes the negative one, below), the Laplacian is Morris' with the uncorrected gradient (King's
//!   code; symmetric coefficients), and the projection uses the positive form
//!   `grad p_i = sum_j (p_i + p_j) grad W_ij V_j` (Cummins & Rudman 1999, Shao & Lo 2003) instead
//!   of the corrected difference form: every fluid-fluid pair then exchanges equal and opposite
//!   momentum, so the force of the wall is exactly what the mirrors exert and the momentum balance
//!   is exact (`State::wall_impulse`), as for the weakly compressible schemes. The one term that
//!   is not a force, the ALE remapping `u_ps . grad u` of (24), is accounted separately
//!   (`State::remap_impulse`).
//! * **Implicit solvent viscosity** (`isph_viscous_step = implicit`, default; issue 11 item 6):
//!   `(I - dt nu lap) u* = u^n + dt [u_ps . grad u + div Phi / rho]` with the same Laplacian and
//!   mirrors (no-slip ghosts) as the explicit term. The step is then (28) without its viscous part,
//!   plus the polymer's limit: `h / c_e` with the elastic wave speed `c_e = sqrt(G / rho)` while
//!   that is shorter than lambda, otherwise `max(lambda, rho h^2 / eta_p)` (a fast-relaxing
//!   polymer is an explicit viscosity). The implicit viscous force on the wall is the momentum
//!   the solve changed, which by the symmetry of the fluid-fluid coefficients is the mirrors'
//!   part exactly. `explicit` is the paper's (24) with (28) as printed (with eta0 = the total
//!   viscosity, plus EVSS's alpha_V eta0).
//! * **Low solvent viscosity: an EVSS floor.** With a free surface the compact (Morris)
//!   Laplacian carries at least [`MIN_COMPACT_VISCOSITY_RATIO`] = 0.05 of eta0: when
//!   beta eta0 + alpha_V eta0 is less, alpha_V is raised ([`isph_evss_alpha`]; the closed
//!   channel keeps the configured alpha_V). EVSS (King & Lind eqs. (6)-(8)) is an identity of
//!   the continuous equations, so this changes the discretisation, not the fluid. Cause,
//!   measured on the UCM drop (beta = 0, De = 0.1, Re = 4): with no solvent, every viscous
//!   stress goes through the positive-form divergence of the corrected gradients, a wide stencil
//!   that does not see grid-scale modes, and the impact's velocity jump excites them unchecked:
//!   the conformation blew up at t* = 1.5 (W/dr = 40), and a third of the step did not help
//!   (W/dr = 20), so it is not a time-step limit. King & Lind need EVSS for beta = 0 (alpha_V =
//!   0.01 in the channel) and report beta = 0.05 as the drop's lowest stable value. alpha_V eta0
//!   = 0.01 eta0 still splashed at impact (W/dr = 20 and 40); 0.05 eta0 spreads like the
//!   Oldroyd-B drop at beta = 0.1 (W*(8) = 1.94 and 1.95 at W/dr = 20 and 40, eta0 = 4), and
//!   so does 0.1 eta0 (1.95 at W/dr = 40); but a floor of 0.1 made the Oldroyd-B drop at
//!   beta = 0.05 (De = 1, W/dr = 40) splash (W* = 5.3 at t* = 8, against a spread to 2.14 and
//!   a retraction to 1.64 without EVSS), so the floor is King & Lind's 0.05. Larger alpha_V is
//!   worse: EVSS's explicit part, the wide operator on alpha_V eta0 2D, is not cancelled by
//!   the implicit compact one near the free surface and in a disordered set, and with
//!   alpha_V = (1 - beta) the UCM drop (De = 1, W/dr = 40) blew up in flight, before impact
//!   (t* = 0.42 with the step limit below, 0.62 without; tr A should stay 2 in flight), at
//!   De = 0.1 and W/dr = 20 it ran; 0.2 and 0.3 broke at impact like 0.1 (De = 1,
//!   W/dr = 40). UCM at De = 1 is beyond this floor at W/dr = 40 (the stability map in
//!   docs/benchmarks.md).
//! * **EVSS's explicit part limits the implicit step**: `rho h^2 / (alpha_V eta0)`, the explicit
//!   viscous limit of the wide operator on alpha_V eta0 2D. Without it alpha_V eta0 went
//!   through the implicit solve but its explicit counterpart ran at nu alpha dt / h^2 = 1.2
//!   (UCM, De = 0.1, W/dr = 40; that run broke at t* = 1.1). At the floor's 0.05 eta0 the limit
//!   does not bind at W/dr = 40 (it is 4.6 times the elastic step there).
//! * **Second order in time where it could be measured** (issue 12). Measured on King & Lind's
//!   channel (Oldroyd-B, Re = 1, beta = 0.1, Wi = 5, Eulerian, 30 across, t = 0..3, centre line
//!   against Waters & King at t = 2.35 / 2.65): the first-order forward-Euler conformation update
//!   (rate at A^{n-1/2}) with backward Euler for the solvent was -4.8 % / -6.0 % at the default
//!   step and -0.9 % at a third of it. With the midpoint conformation update: +1.5 % / +2.2 %
//!   (backward Euler), +1.1 % / +1.6 % (Crank-Nicolson), the same +1.0 % / +1.6 % at a third of
//!   the step and with the explicit viscous step (the rest is spatial: 7 % at 15 across). The
//!   solvent step is the theta method
//!   `(I - theta dt nu lap) u* = (I + (1 - theta) dt nu lap) u^n + dt [...]`: theta = 1/2 in the closed channel (Newtonian start-up: largest centre-line error
//!   0.2 % against 2.7 % with theta = 1), theta = 1 with a free surface, where Crank-Nicolson's
//!   undamped stiff modes rang: the Newtonian drop of King & Lind IV.C at W/dr = 40 lost 48 % of
//!   its volume by t* = 8 (theta = 0.6: 4.1 %; theta = 1: 1.7 %). In the channel the viscous
//!   term's mirrors continue the wall curvature of the wall's momentum balance,
//!   `mu_w u''_w = -(rho g.t + dPhi_tn/dn)` (no acceleration at a no-slip wall), not the curvature
//!   fitted to u^n ([`wall_profile`]): the fitted one is explicit in u and, with Crank-Nicolson,
//!   fed back into the wall row until it ran away (Newtonian wall row 1.78 U, centre line
//!   1.052 U); backward Euler damped it. What is still first order: the conformation is stored at
//!   the end of the step, not staggered by half a step (symplectic Euler in the coupling of u and
//!   A): at 15 across the centre lines at the default step, a third and a tenth of it differ by
//!   0.0083 U and 0.0028 U (a ratio of 3).
//! * **Time step** (28) with the coefficient 2/3 `time_step_factor` (0.2 at the default), plus
//!   `sqrt(h / |g|)` so a fluid at rest still has a finite step. In the closed channel also the
//!   stretched polymer's wave: `5 h / c` (times the coefficient: a Courant number of 1) with
//!   `c^2 = (G + s_max) / rho`, s_max the largest principal polymer stress (a string under
//!   tension G A carries transverse waves at sqrt(G l_max(A) / rho)); (28) and `h / sqrt(G / rho)`
//!   do not see the stretch, and as a start-up flow slows (28)'s step grows while tr A still
//!   rises. [`STRETCHED_WAVE_LIMIT`] gives the measurements. In free-surface scenes also the
//!   positive-form pressure wave `0.5 h sqrt(rho / p_max)` (not scaled by the factor): the
//!   projection's `(p_i + p_j)` gradient is an explicit interparticle spring of stiffness
//!   proportional to p, and at the gravity limit of a drop resting on the plate its Courant
//!   number grows as sqrt(H / h) (the Newtonian Re = 4 drop blew up at W/dr = 120, t* = 1.5,
//!   without it). [`Isph::pressure_wave_dt`] derives it; [`PRESSURE_WAVE_LIMIT`] gives the
//!   measurements.
//! * Kernel: the quintic spline, h = 1.3 dx (`smoothing_ratio` is ignored). No equation of state,
//!   sound speed, artificial viscosity or artificial stress: those parameters are ignored.
//!   `rho` of the particles stays rho0.
//! * A particle that crosses a plate is reflected back with its normal velocity removed (King's
//!   code reflects it too); the momentum removed counts in the wall force.
//! * **Free-surface pressure** (`isph_free_surface`): p = 0 (`zero_pressure`, every scene but
//!   the jet) or (35a)'s solvent normal stress (`normal_stress`, the jet's `auto`). The
//!   normal-stress form takes `p_s = 2 mu n.D.n = -2 mu t.G(u*).t` (continuity; G the velocity
//!   gradient of the predicted velocity) as the surface value of the surface rows (the Robin
//!   rows' target, added to the Dirichlet value) and projects with the positive form of
//!   `p - p_s`: `sum_j (p_i + p_j) grad W_ij V_j - 2 p_s s_i`, `s_i = sum_j V_j grad W_ij`,
//!   p_s a surface row's own value or its surface neighbours' kernel-weighted mean. King &
//!   Lind's positive form on a truncated support acts as if p were -p_i beyond the surface,
//!   i.e. p = 0 there whatever the surface value; with p_s it continues as 2 p_s - p_i, so a
//!   compressive surface value no longer pushes its row out (the dilation that made (35a)
//!   unusable before). The `G s` part of the solvent's surface traction is then the pressure's
//!   (`along` = 0), and the `-2 p_s s_i` term, not a pair force, has its mean over the free
//!   particles removed (a free surface exerts no net force; the jet's wall impulse balance
//!   holds to round-off). Measured (Newtonian, `viscosph run`): the jet (H = 12 D, 6 / 10
//!   across) buckles, 0.47 / 0.55 D, heap at 0.200 / 0.205 s (p = 0: 0.019 / 0.034 D, 0.165 /
//!   0.175 s; WCSPH 0.227 s), and not from H = 2 D (0.035 D); the Re = 4 drop at W/dr = 20 /
//!   40 gives W*(8) 1.997 / 1.910, largest |volume_error| 0.93 / 0.52 % (p = 0: 2.127 / 1.962,
//!   0.85 / 0.45 %), hence p = 0 for drops (docs/methods.md, "The ISPH jet with (35a)").
//!   **p = 0**, King's public code's choice, was first taken instead of the normal-stress value
//!   of (35a) because, measured on the drop of King & Lind IV.C at W/dr = 20: with the solvent's
//!   2 eta_s n.D.n in the Dirichlet value, the Newtonian drop splashes at impact (W* = 4.5 at
//!   t* = 2.4, holes) with the explicit viscous step of (24)-(28), and a drop at rest blows up with
//!   the implicit one (the value is explicit in the velocity, so it is a viscous term with the
//!   explicit limit rho h^2 / eta_s); with only the polymer's n.tau_p.n the Oldroyd-B drop
//!   (De = 1, beta = 0.1) spreads without bound (W* = 23 at t* = 8). With p = 0 the Newtonian
//!   drop spreads to W* = 2.16 at t* = 8 under both viscous steps, and the Oldroyd-B drop spreads
//!   to 2.1 and retracts. The positive form of div Phi still carries the stress-free condition
//!   approximately (King & Lind section III.A).
//!   **Where p = 0 is imposed.** The surface lies half a layer outside the surface particles'
//!   centres, so a surface particle takes the pressure that far inside the surface,
//!   `depth (-dp/dn)` ([`surface_pressure`], from the last step's pressures of its interior
//!   neighbours), with `depth = dx/2` times the surface row's line density
//!   ([`surface::row_density`]: a crowded row stands for a thicker layer). With p = 0 on the
//!   centres the surface row crowded tangentially as the free perimeter shrank (0.81 dx apart at
//!   W/dr = 20), and nothing returned its particles to the bulk: largest |volume_error| of the
//!   Newtonian drop 5.32 %, 1.76 %, 0.62 % at W/dr = 20, 40, 80; now 2.73 %, 1.02 %, 0.39 %
//!   (docs/isph.md, "Volume").
//! * **Free-surface traction** of the solvent, implicit (King & Lind 2021 eq. (35a)'s viscous
//!   part in a stable form; [`ppe::SurfaceTraction`]): Morris et al. 1997's Laplacian (21) sees
//!   a missing neighbour as one with the particle's own velocity, i.e. the normal derivative,
//!   not the traction; the positive form of the divergence of 2 eta D differs from the
//!   difference form by `2 sigma_i s_i`, `s_i = sum_j V grad W_ij`. Every row of the implicit
//!   viscous step takes `(2 eta_i / rho) (G_i + G_i^T) s_i` with the Bonet & Lok 1999 corrected
//!   gradient G_i of the new velocity, both components solved together. Measured on the
//!   extensional mode of a free sheet (exact decay 3.87 nu k^2): 1.74 without, 2.68 with, at
//!   0.2 ms; the Newtonian Re = 4 drop's W*(8) at W/dr = 40 and a third of the step 1.987 ->
//!   1.858 (Oldroyd-B at De = 0.1: 1.80), largest |volume_error| at the default step 1.02 % ->
//!   0.64 % (docs/isph.md). The term is not a pair force; a free surface exerts no net
//!   force, so the term's mean velocity change is removed after the solve (without that, a
//!   slowly settling drop felt 3 % of its weight from it).
//! * **Uncorrected gradients on the free surface.** There the Bonet & Lok moment matrix (22) is
//!   nearly singular along the normal, and L_i amplified the velocity gradient that drives the
//!   stress: the Oldroyd-B drop above blew up at impact (tr A = 5000 at t* = 0.8) with L_i on
//!   every particle, and ran with L = I on the free-surface set (as the positive form of (20)
//!   has it).
//! * **Density-invariant PPE source** on the particles with a full kernel support (neither on
//!   the free surface nor next to it): `b_i += alpha rho (C0 - C_i) / (C0 dt^2)` with the
//!   concentration `C_i = sum_j V_j W_ij` (fluid and mirrors) and `C0` its value inside a square
//!   lattice, alpha = 0.05 (the "stabilised ISPH" of Asai et al. 2012; Lind et al. 2012 mix a
//!   density term in likewise). The velocity-divergence source alone lets the particle
//!   arrangement drift: the Newtonian Re = 4 drop at W/dr = 40 covered +3.4 % more area after
//!   impact; with the term, at most 1.7 % (alpha = 0.2: 1.8 %). Applied on every particle, the
//!   truncated sums near the surface read as expansion and pull the surface in (-1.9 % at
//!   W/dr = 40, alpha = 0.2); applied only where compressed, it did nothing measurable. What
//!   remains is tangential crowding of the free-surface row (Dirichlet rows, which no source
//!   reaches): docs/isph.md, "Volume".
//! * **Volume at W/dr = 40** (issue 11's 0.5 %; docs/isph.md, "Volume": largest |volume_error|
//!   of the Newtonian Re = 4 drop over t* <= 8 from 0.63 % to 0.46 %, 1.79 % to 0.86 % at
//!   W/dr = 20, 0.44 % to 0.22 % at 80), four parts measured together and apart:
//!   - *Surface rows keep their continuity equation.* A Dirichlet row has no div u and no
//!     density feedback, so the contact line's pile-up of surface particles (about 9 particles
//!     0.48 dx apart on the rim's face at t* = 8) never returned to the bulk. Row i instead
//!     takes the part of Morris' Laplacian its missing neighbours would give if p fell
//!     linearly to 0 at `depth` outside it (a Robin row, [`ppe::assemble_poisson_surface`]).
//!   - *Density-invariant source on those rows* ([`SURFACE_ROW_INVARIANCE`]) against the share
//!     of the last row of a straight lattice edge ([`surface::HalfLattice`]): with it the late
//!     loss (-0.56 % at t* = 8) stays within -0.33 %.
//!   - *Near-surface source* ([`NEAR_SURFACE_INVARIANCE`]) against the share a particle keeps
//!     at its distance below the surface row ([`surface::row_distance`]): the bulk and the NS
//!     band had stayed 0.6-1 % expanded after impact.
//!   - *Frame-independent shifting.* King & Lind's coefficient (41) follows the particle's
//!     speed; it follows the speed relative to the fluid's mean velocity, so a drop in free
//!     flight at 1 m/s is not reshuffled (with the surface-row source alone the flying drop
//!     first contracted, then expanded 1.2 % at impact).
//! * **The closed periodic channel** (no free surface; issue 12) differs in three places, each
//!   measured on King & Lind's unit channel at 30 across: the body force is in the predictor
//!   (with the corrector's g the implicit viscous step acts on u - g dt, and the Newtonian flow
//!   settled g dt = 0.067 U fast everywhere); the mirrors continue the wall curvature of the
//!   velocity (fitted for the velocity gradient, from the wall's momentum balance for the viscous
//!   term, see above) and the fitted slope of the shear stress ([`wall_profile`]; Newtonian
//!   centre line 0.9994 U, flow rate 0.66663 U H, against 1.0016 U and 0.6688 U H without); and
//!   div Phi is the negative form of (20) with the Bonet & Lok correction,
//!   `sum_j (Phi_j - Phi_i) L_i grad W_ij V_j`, which is what King & Lind use "for closed domains"
//!   (their section III, after (20): "more accurate, and provides increased stability when large
//!   stress gradients are present"; their (24) prints the positive form, the one of their
//!   free-surface runs). Its fluid pairs do not cancel, so the net stress force on the fluid is
//!   booked as the walls' (a periodic channel has no other boundary). Measured (Oldroyd-B,
//!   Re = 1, beta = 0.1, Lagrangian, t = 0..3): with the positive form the wall rows under the
//!   polymer's tension (tr A = 120 at Wi = 2) lost their lattice from t = 1.9, min det A fell
//!   to 0.87 (Oldroyd-B keeps det A >= 1 in shear) and the centre line left Waters & King by
//!   0.49 U (Wi = 2, 30 across; 0.55 U at 15 across, Wi = 5 likewise); with the negative form
//!   the largest deviation is 1.8 % (Wi = 2), 1.5 % (Wi = 1), det A >= 1 throughout, at the
//!   full step. The Lagrangian frame took a third of (28)'s step before, as a cure for that
//!   disorder; with the negative form the third changed nothing measurable (Wi = 2: 1.83 %
//!   against 1.77 %; Wi = 1: 1.48 % against 1.45 %) and is gone.
//! * **Eulerian ALE term by three stages.** In the Eulerian frame the ALE term of (31),
//!   `dt u_ps . grad Psi` with u_ps = -u, is the whole advection of the stress: a central
//!   difference, which forward Euler amplifies by about 1 + (u dt k)^2 per step for every mode
//!   that varies along the flow (King & Lind's Eulerian "checkerboard-type instability",
//!   crashing at Wi >= 16). It is integrated by Shu & Osher's three-stage SSP Runge-Kutta
//!   scheme (stable for a central difference up to u dt k = sqrt 3), three neighbour sums of
//!   Psi per step. Measured (Oldroyd-B, Re = 1, beta = 0.1, 30 across): Wi = 50 broke at
//!   t = 2.87 (det A from 1 to 0.005 once tr A passed 3000) and now follows Waters & King
//!   within 0.20 % to t = 4 with det A >= 1; Wi = 5 within 1.8 % to t = 3. Tried first:
//!   sub-cycling the constitutive update (no change: breakdown at t = 2.871 both ways),
//!   dropping the term (a diagnostic, exact only for this flow: det A >= 1 to t = 3), a
//!   Lax-Wendroff term by the compact Espanol & Revenga second derivative (to t = 4, but det A
//!   drifted to 0.68 and the centre line 4 % low) and a one-sided (upwind) gradient (stable,
//!   but its error in the cross-stream second derivative put Wi = 5 off by 3.6 U at t = 2.95).
//! * A pressure or viscous solve that does not converge stops the run with the solver's cause.
//! * **Inlet** (the jet's nozzle, [`crate::state::Inflow::holds`]): a buffer of particles held at
//!   the inflow velocity, in the spirit of the moving ghost particles King & Lind cite for their
//!   jet. A held particle moves with its prescribed velocity (no shifting) and keeps it through
//!   the step: the momentum the forces of the step would have given it is taken by the inlet
//!   (`Inflow::momentum`), so the momentum balance stays exact. Velocity prescribed means a
//!   Neumann condition on the pressure: held particles are unknowns of the PPE with
//!   `lap p = 0` (the prescribed flow is divergence-free) and, where free fluid is within
//!   their kernel support, never Dirichlet, so the free fluid at the exit sees the pressure
//!   continued into the nozzle (the truncated Laplacian at the nozzle's sides and top is a
//!   zero normal gradient) instead of a free surface. Held particles out of reach of free fluid
//!   keep the free-surface p = 0 of their edges: that fixes the pressure level when the nozzle
//!   holds all the fluid (t = 0, or a closed valve after the jet has left).

pub mod ppe;

use super::health;
use super::params::Params;
use super::Scheme;
use crate::boundary::ghost::keep_above_plate;
use crate::boundary::mirror::MirrorWall;
use crate::boundary::plate::Plate;
use crate::boundary::wall_profile;
use crate::boundary::Boundary;
use crate::config::{ConformationMethod, IsphFrame, IsphFreeSurface, Numerics, ViscousStep};
use crate::kernel::{Kernel, QuinticSpline};
use crate::neighbors::{CellGrid, NeighborList};
use crate::operators::kinematics::corrected_velocity_gradients;
use crate::operators::pairs::PairCache;
use crate::operators::{correction, shifting, surface};
use crate::rheology::{self, logconf, Evss, Rheology};
use crate::state::State;
use crate::{Mat2, Vec2};
use ppe::{GhostLink, SolverOptions};
use rayon::prelude::*;
use std::time::Instant;

/// h / dx of King & Lind's quintic kernel.
pub const H_OVER_DX: f64 = 1.3;
/// The coefficient of King & Lind eq. (28) per unit `time_step_factor` (0.3 -> 0.2).
const DT_COEF_PER_FACTOR: f64 = 2.0 / 3.0;
/// Relaxation coefficient of the density-invariant PPE source (module documentation).
const DENSITY_INVARIANCE: f64 = 0.05;
/// Relaxation coefficient of the same source on the near-surface particles, against the
/// concentration a particle at their distance below a straight surface row keeps
/// ([`surface::HalfLattice`]; module documentation, "Volume"), per step of the default
/// advective step (`time_step_factor` [`DEFAULT_STEP_FACTOR`]); a shorter step takes
/// proportionally less, so the relaxation rate does not depend on the step (a per-step 0.1 made
/// `implicit_viscosity_converges_to_explicit` diverge as the step shrank: 3.1, 2.5, 9.6 %).
const NEAR_SURFACE_INVARIANCE: f64 = 0.1;
/// The same on the free-surface rows, against the share of the last row of a straight lattice
/// edge (module documentation, "Volume"): without it the contact line's pile-up of surface
/// particles takes 0.5-0.9 % of the drop's area by t* = 8 at W/dr = 40.
const SURFACE_ROW_INVARIANCE: f64 = 0.1;
/// The default `time_step_factor`: the step the near-surface coefficients are given for.
const DEFAULT_STEP_FACTOR: f64 = 0.3;
/// Smallest share of eta0 the compact (Morris) viscous operator carries under ISPH: when the
/// solvent's beta eta0 plus `evss_alpha`'s alpha_V eta0 is less, alpha_V is raised to make up
/// the difference (module documentation, "Low solvent viscosity"). EVSS is an identity of the
/// continuous equations (King & Lind eqs. (6)-(8)), so this changes the discretisation, not the
/// model. 0.05 is King & Lind's lowest stable beta for the drop (section IV.C). Measured on the
/// UCM drop (De = 0.1): 0.01 of eta0 still splashed at impact (W/dr = 20 and 40), 0.05 and 0.1
/// spread like the Oldroyd-B drop at beta = 0.1; on the Oldroyd-B drop at beta = 0.05 (De = 1,
/// W/dr = 40) a floor of 0.1 made it splash, 0.05 leaves it as it was (spreads and retracts).
pub const MIN_COMPACT_VISCOSITY_RATIO: f64 = 0.05;
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
/// Smallest number of particles per parallel task.
const MIN_TASK: usize = 64;
/// A stable step (28) this far below the scene's time scale ([`Isph::time_scale`]) means the
/// flow has blown up. An incompressible run has no density to watch, and (28) follows a
/// diverging speed down without ever reaching zero: a Re = 4 drop that diverged at W/dr = 80
/// (an experimental surface pressure, session 9) reached a kinetic energy of 6e32 J/m and a step
/// of 5e-23 s and kept crawling instead of stopping. A legitimate run stays within a few decades
/// of the scale: in the drop of IV.C it would take a particle at about 1e6 m/s to reach this.
const DT_COLLAPSE: f64 = 1e-8;
/// Implicitness of the solvent viscous step in the closed channel: Crank-Nicolson (second order
/// in time). Measured on the Newtonian start-up (Re = 1, 30 across, Eulerian, default step):
/// largest centre-line error 0.2 % against 2.7 % with backward Euler (theta = 1). Free-surface
/// scenes keep backward Euler (`Isph::new`).
const VISCOUS_THETA_CLOSED: f64 = 0.5;

/// Weights of the solvent's free-surface traction in the implicit viscous step
/// ([`ppe::SurfaceTraction`]): `(2 eta / rho) (along G + transposed G^T) s_i` on every row, the
/// difference between the positive form of div(2 eta D) and the difference form, with G the
/// Bonet & Lok 1999 corrected velocity gradient (module documentation, "Free-surface
/// traction"). Measured on the extensional mode of a free Newtonian sheet (kH = pi/10, exact
/// decay rate 3.87 nu k^2, test `free_sheet_resists_extension_with_the_surface_traction`), at
/// dt = 5e-5 / 2e-4 / 1e-3 s: Morris' Laplacian alone 1.84 / 1.74 / 1.47 nu k^2; G^T s only
/// (along = 0) 2.79 / 2.54 / 1.92; both 3.02 / 2.68 / 1.97 (kept).
const SURFACE_TRACTION_ALONG: f64 = 1.0;
const SURFACE_TRACTION_TRANSPOSED: f64 = 1.0;

/// Wall-clock time spent in the parts of the step (for `viscosph bench`), seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct IsphTimings {
    /// Whole steps.
    pub total: f64,
    /// Pressure Poisson equation: assembly, preconditioner and BiCGStab.
    pub pressure_solve: f64,
    /// Implicit viscous step: assembly, preconditioner and BiCGStab.
    pub viscous_solve: f64,
}

/// The ISPH scheme for rheology `R`.
pub struct Isph<R: Rheology> {
    kernel: QuinticSpline,
    model: R,
    p: Params,
    evss: Evss,
    method: ConformationMethod,
    frame: IsphFrame,
    viscous: ViscousStep,
    /// Weight of the new velocity in the implicit viscous step (theta method).
    theta: f64,
    /// Whether the domain has a free surface (every scene but the closed channel).
    free_surface: bool,
    dt_coef: f64,
    rho: f64,
    solver: SolverOptions,
    /// One wall model per plate of the state, in the state's order: King & Lind's mirror
    /// particles ([`MirrorWall`]), read only through the [`Boundary`] trait.
    walls: Vec<Box<dyn Boundary>>,
    /// Positions of fluid (r*) then mirrors, of the last step.
    all_x: Vec<Vec2>,
    /// Kernel values of the last step's pairs (full layout).
    pairs: PairCache,
    /// Kernel sum `sum_j V W_ij` of a particle inside an unbounded square lattice.
    c_lattice: f64,
    /// Its share below a straight surface row (near-surface density-invariant source).
    half_lattice: surface::HalfLattice,
    /// Free-surface pressure from King & Lind eq. (35a)'s solvent normal stress, with the
    /// projection's consistent ghost pressure (`isph_free_surface`; module documentation,
    /// "Free-surface pressure"); p = 0 on the surface otherwise.
    normal_stress: bool,
    pub timings: IsphTimings,
}

impl<R: Rheology> Isph<R> {
    /// The scheme for the numerics `cfg` of an effective configuration, the constants `p` (which
    /// say whether the scene has a free surface and what `auto` means for it) and the plates of
    /// the initial state.
    pub fn new(model: R, p: Params, cfg: &Numerics, plates: &[Plate]) -> Self {
        let kernel = QuinticSpline::new(H_OVER_DX * p.dx);
        // The EVSS floor was measured on drops; the closed channel keeps the configured
        // alpha_V (King & Lind's beta = 0 channel uses alpha_V = 0.01).
        let free_surface = p.free_surface;
        let evss_alpha = if free_surface {
            isph_evss_alpha(&model, p.evss_alpha)
        } else {
            p.evss_alpha
        };
        let evss = Evss::new(&model, evss_alpha);
        let method = match cfg.conformation_method {
            ConformationMethod::Auto => ConformationMethod::Log,
            m => m,
        };
        let reach = kernel.radius();
        let c_lattice = lattice_concentration(&kernel, p.dx);
        let half_lattice = surface::HalfLattice::new(&kernel, p.dx);
        Self {
            kernel,
            model,
            evss,
            method,
            frame: cfg.isph_frame,
            viscous: cfg.isph_viscous_step,
            // With a free surface, Crank-Nicolson's undamped stiff modes ring: the Newtonian
            // K&L drop (W/dr = 40) lost 48 % of its volume by t* = 8 at theta = 1/2 and 4.1 %
            // at theta = 0.6, against 1.7 % with backward Euler.
            theta: if free_surface {
                1.0
            } else {
                VISCOUS_THETA_CLOSED
            },
            free_surface,
            dt_coef: DT_COEF_PER_FACTOR * cfg.time_step_factor,
            rho: p.eos.rho0,
            solver: SolverOptions::default(),
            walls: plates
                .iter()
                .map(|_| Box::new(MirrorWall::new(reach)) as Box<dyn Boundary>)
                .collect(),
            all_x: Vec::new(),
            pairs: PairCache::default(),
            c_lattice,
            half_lattice,
            normal_stress: free_surface
                && match cfg.isph_free_surface {
                    IsphFreeSurface::Auto => p.auto_free_surface == IsphFreeSurface::NormalStress,
                    IsphFreeSurface::ZeroPressure => false,
                    IsphFreeSurface::NormalStress => true,
                },
            timings: IsphTimings::default(),
            p,
        }
    }

    /// The weight of `G s` in the solvent's surface traction: with the normal-stress surface
    /// pressure that part is the pressure's (module documentation, "Free-surface pressure").
    fn along(&self) -> f64 {
        if self.normal_stress {
            0.0
        } else {
            SURFACE_TRACTION_ALONG
        }
    }

    /// Viscosity of the Laplacian term (solvent + EVSS's alpha_V eta0) at velocity gradient k.
    #[inline]
    fn laplacian_viscosity(&self, k: &Mat2) -> f64 {
        self.evss.viscous_viscosity(self.model.solvent_viscosity(k))
    }

    /// The scene's own time scale for the blow-up guard: the larger of the gravity time
    /// sqrt(h / g) and the viscous time rho h^2 / eta0 over one smoothing length.
    fn time_scale(&self) -> f64 {
        let h = self.kernel.h();
        let eta_all = self.model.max_viscosity() + self.evss.added_viscosity();
        let g = self.p.gravity.norm();
        let gravity = if g > 0.0 { (h / g).sqrt() } else { 0.0 };
        gravity.max(self.rho * h * h / eta_all)
    }

    /// The flow's part of King & Lind eq. (28): the smaller of `h / |u|_max` and
    /// `sqrt(h / g)`, infinite when nothing moves and nothing pulls. The step's other limits
    /// come on top of it in [`Self::stable_dt`]; the near-surface sources measure their step
    /// against it.
    fn advective_limit(&self, umax: f64) -> f64 {
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

    /// King & Lind eq. (28), see the module documentation.
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
        let p_max = pressure.iter().fold(0.0f64, |m, &p| m.max(p));
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
    fn stretched_wave_dt(&self, conf: &[Mat2]) -> f64 {
        if !R::ELASTIC || self.free_surface {
            return f64::INFINITY;
        }
        let g_mod = self.model.modulus();
        let s_max = conf
            .iter()
            .map(|a| logconf::sym_eigen(&self.model.polymer_stress(a)).l1)
            .fold(0.0f64, f64::max);
        let c = ((g_mod + s_max) / self.rho).sqrt();
        if c > 0.0 && c.is_finite() {
            self.dt_coef * STRETCHED_WAVE_LIMIT * self.kernel.h() / c
        } else {
            f64::INFINITY
        }
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
    let eta_s = model.solvent_viscosity(&Mat2::zeros());
    let short = MIN_COMPACT_VISCOSITY_RATIO * (eta_s + eta_p) - eta_s;
    // Relative margin: beta = 0.1 exactly must not switch EVSS on through round-off.
    if short <= 1e-9 * (eta_s + eta_p) {
        return evss_alpha;
    }
    evss_alpha.max(short / eta_p)
}

/// A fluid velocity field extended over the mirrors: King & Lind's no-slip continuation
/// `2 u_wall - u_parent` plus the wall-curvature correction of each mirror
/// ([`wall_profile`]; zero with a free surface).
fn extend_over_mirrors(u: &[Vec2], parent: &[u32], u_wall: &[Vec2], curv: &[Vec2]) -> Vec<Vec2> {
    let mut out = Vec::with_capacity(u.len() + parent.len());
    out.extend_from_slice(u);
    out.extend(
        parent
            .iter()
            .zip(u_wall)
            .zip(curv)
            .map(|((&i, uw), c)| 2.0 * uw - u[i as usize] + c),
    );
    out
}

/// Velocities relative to their mean (summed in index order): the speed King & Lind's shifting
/// coefficient (41) follows, made independent of the frame (module documentation, "Volume").
fn relative_to_mean(u: &[Vec2]) -> Vec<Vec2> {
    if u.is_empty() {
        return Vec::new();
    }
    let mean = u.iter().fold(Vec2::zeros(), |a, v| a + v) / u.len() as f64;
    u.iter().map(|v| v - mean).collect()
}

/// The concentration `sum_j V_j W_ij` of a particle inside an unbounded square lattice of
/// spacing `dx` (V = dx^2): the value of a particle of the uncompressed fluid.
fn lattice_concentration<K: Kernel>(kernel: &K, dx: f64) -> f64 {
    let reach = (kernel.radius() / dx).ceil() as i64;
    let mut c = 0.0;
    for j in -reach..=reach {
        for i in -reach..=reach {
            c += kernel.w(dx * ((i * i + j * j) as f64).sqrt());
        }
    }
    c * dx * dx
}

/// What one fused pass over the neighbour lists gives besides the pair cache (step 2 of the
/// module documentation).
struct NeighbourSums {
    /// Bonet & Lok correction matrices L_i (King & Lind eq. (22)).
    l: Vec<Mat2>,
    /// Free surface and normals (eqs. (36)-(39)), with a free surface.
    surface: Option<surface::Surface>,
    /// Concentration gradient of eq. (42) without and with the repulsion Q (Lagrangian frame;
    /// empty otherwise): which one a particle takes is known only once the surface is.
    grad_c: Vec<Vec2>,
    grad_c_q: Vec<Vec2>,
}

/// The pair cache `pairs` (gradients and Morris coefficients, full layout), the moment matrices, the sums of the
/// free-surface detection and the shifting's concentration gradient of every fluid particle, in
/// one pass over its neighbour list that evaluates the kernel once per pair. Before, five
/// passes (`pair_data`, `correction::correction_matrices`, `surface::detect`,
/// `shifting::concentration_gradient`) each evaluated the quintic's three pieces again; every
/// sum keeps its own order and expression (the operators' per-pair helpers), so the results
/// are bitwise those of the separate passes. `shift_dr` = Some(dr) computes the shifting sums.
#[allow(clippy::too_many_arguments)]
fn neighbour_sums(
    pairs: &mut PairCache,
    x: &[Vec2],
    vols: &[f64],
    nl: &NeighborList,
    k: &QuinticSpline,
    dom: &crate::neighbors::Domain,
    n: usize,
    free_surface: bool,
    shift_dr: Option<f64>,
) -> NeighbourSums {
    pairs.reset_full(nl);
    let gs = nl.split_mut(&mut pairs.grad);
    let ms = nl.split_mut(&mut pairs.morris);
    let inv_h = 1.0 / k.h();
    let (w_dr, alpha, dr) = match shift_dr {
        Some(dr) => (k.w(dr), shifting::cohesion_alpha(k.h()), dr),
        None => (1.0, 0.0, 1.0),
    };
    type Row = (Mat2, (f64, f64, Vec2), (Vec2, Vec2));
    let rows: Vec<Row> = (gs, ms)
        .into_par_iter()
        .with_min_len(MIN_TASK)
        .enumerate()
        .map(|(i, (g, m))| {
            let mut mom = Mat2::zeros();
            let (mut div, mut c, mut cg) = (0.0, 0.0, Vec2::zeros());
            let (mut sh, mut sh_q) = (Vec2::zeros(), Vec2::zeros());
            for (kk, &j) in nl.of(i).iter().enumerate() {
                let j = j as usize;
                let xij = dom.delta(&x[i], &x[j]);
                let r2 = xij.norm_squared();
                let r = r2.sqrt();
                let (w, f) = (k.w(r), k.dw_over_r(r));
                let gij = xij * f;
                // Pair data: zero for the self pair.
                if j != i && r2 != 0.0 {
                    g[kk] = gij;
                    m[kk] = 2.0 * vols[j] * f;
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
        .iter()
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

impl<R: Rheology> Scheme for Isph<R> {
    fn step(&mut self, st: &mut State, max_dt: f64) -> Result<f64, String> {
        let t_start = Instant::now();
        let n = st.fluid.len();
        let (rho, h, dx) = (self.rho, self.kernel.h(), self.p.dx);
        let vol = st.fluid.mass / rho;
        let dom = self.p.domain;
        let g = self.p.gravity;
        let fl = &st.fluid;
        let umax = fl.v.iter().fold(0.0f64, |m, v| m.max(v.norm()));
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
        let lagrangian = self.frame == IsphFrame::Lagrangian;
        // Inlet particles (module documentation): velocity prescribed (the scene has just put
        // it back), empty without an inlet.
        let held: Vec<bool> = match &st.inflow {
            Some(inl) => fl.x.iter().map(|x| inl.holds(x)).collect(),
            None => Vec::new(),
        };
        let is_held = |i: usize| held.get(i).copied().unwrap_or(false);
        // Momentum the inlet takes from its particles to hold them at the inflow velocity.
        let mut held_momentum = Vec2::zeros();

        // Step 1, eq. (23).
        let xs: Vec<Vec2> = if lagrangian {
            fl.x.par_iter()
                .zip(fl.v.par_iter())
                .map(|(x, v)| dom.wrap(x + v * dt))
                .collect()
        } else {
            fl.x.clone()
        };

        // Step 2: mirrors, lists, correction, surface, shifting.
        let radius = self.kernel.radius();
        self.all_x.clear();
        self.all_x.extend_from_slice(&xs);
        let mut parent: Vec<u32> = Vec::new();
        let mut u_wall: Vec<Vec2> = Vec::new();
        // Closed channel: each wall's mirrors as a range of the mirror list, for the
        // second-order continuation of the wall layer (`boundary::wall_profile`).
        let mut wall_ranges: Vec<(usize, std::ops::Range<usize>)> = Vec::new();
        {
            let fluid_grid = CellGrid::build(&xs, radius, &dom);
            for (wall, plate) in self.walls.iter_mut().zip(st.walls.iter_mut()) {
                let before = self.all_x.len();
                wall.place(plate, &xs, &fluid_grid, radius, &mut self.all_x);
                // Every virtual particle follows one fluid parent: its values are affine in
                // the parent's in the linear systems below.
                if wall.parents().len() != self.all_x.len() - before {
                    return Err(
                        "ISPH needs a wall model whose virtual particles each follow \
                                one fluid particle (mirror particles)"
                            .into(),
                    );
                }
                let start = parent.len();
                parent.extend_from_slice(wall.parents());
                wall_ranges.push((wall_ranges.len(), start..parent.len()));
                wall.wall_velocities(plate, &mut u_wall);
            }
        }
        let all_x = &self.all_x;
        let nm = parent.len();
        let grid = CellGrid::build(all_x, radius, &dom);
        let nl = NeighborList::build(&grid, all_x, &xs, radius, &dom);
        let vols = vec![vol; all_x.len()];
        let pairs = &mut self.pairs;
        let sums = neighbour_sums(
            pairs,
            all_x,
            &vols,
            &nl,
            &self.kernel,
            &dom,
            n,
            self.free_surface,
            lagrangian.then_some(dx),
        );
        let pairs = &self.pairs;
        let (mut l, surf) = (sums.l, sums.surface);
        // Free-surface particles take the uncorrected gradient (module documentation).
        if let Some(s) = &surf {
            for (li, &fs) in l.iter_mut().zip(&s.is_surface) {
                if fs {
                    *li = Mat2::identity();
                }
            }
        }
        // Closed channel: the wall curvature of u^n the odd mirror continuation misses
        // (`boundary::wall_profile`), added to every mirror velocity of this step.
        let u_curv: Vec<Vec2> = if self.free_surface {
            vec![Vec2::zeros(); nm]
        } else {
            let mut c = Vec::with_capacity(nm);
            for (w, r) in &wall_ranges {
                c.extend(wall_profile::velocity_corrections(
                    &st.walls[*w],
                    &xs,
                    &parent[r.clone()],
                    &fl.v,
                    radius,
                ));
            }
            c
        };
        // Extend a fluid velocity field over the mirrors (no slip).
        let extend_u = |u: &[Vec2]| extend_over_mirrors(u, &parent, &u_wall, &u_curv);
        let u_n = extend_u(&fl.v);
        let u_ps: Vec<Vec2> = if lagrangian {
            // The repulsion Q acts on the interior particles of a free-surface flow (eq. (42)).
            let (grad_c, d): (Vec<Vec2>, Vec<f64>) = match &surf {
                Some(s) => (
                    s.is_surface
                        .iter()
                        .enumerate()
                        .map(
                            |(i, &fs)| {
                                if fs {
                                    sums.grad_c[i]
                                } else {
                                    sums.grad_c_q[i]
                                }
                            },
                        )
                        .collect(),
                    shifting::coefficients_free_surface(&relative_to_mean(&fl.v), h, dt),
                ),
                None => (sums.grad_c, vec![shifting::coefficient_internal(h); n]),
            };
            let s = surf
                .as_ref()
                .map(|s| (s.is_surface.as_slice(), s.normal.as_slice()));
            shifting::displacements(&grad_c, &d, s, h)
                .into_iter()
                .map(|d| d / dt)
                .collect()
        } else {
            fl.v.iter().map(|v| -v).collect()
        };
        // Held particles move with the inflow, not shifted.
        let u_ps: Vec<Vec2> = u_ps
            .into_iter()
            .enumerate()
            .map(|(i, u)| if is_held(i) { Vec2::zeros() } else { u })
            .collect();

        // Step 3: the conformation tensor to n + 1/2 (section III.B).
        let kappa = corrected_velocity_gradients(n, &u_n, vol, &nl, pairs, &l);
        let conf: Vec<Mat2> = if R::ELASTIC {
            let log = self.method == ConformationMethod::Log;
            // The field the ALE term advects: Psi = log A, or A for the direct update.
            let psi: Vec<Mat2> = fl
                .conf
                .par_iter()
                .map(|a| if log { logconf::log_spd(a) } else { *a })
                .collect();
            let (model, method) = (&self.model, self.method);
            // dt u_ps . grad f (King & Lind eq. (31)'s ALE term) for every particle.
            let ale = |f: &[Mat2]| -> Vec<Mat2> {
                (0..n)
                    .into_par_iter()
                    .with_min_len(MIN_TASK)
                    .map(|i| {
                        let off = nl.offset(i);
                        let us = l[i].transpose() * u_ps[i];
                        let mut adv = Mat2::zeros();
                        if us != Vec2::zeros() {
                            for (kk, &j) in nl.of(i).iter().enumerate() {
                                let j = j as usize;
                                // Mirrors carry their parent's conformation (NoSlip mirror
                                // stress).
                                let pj = if j < n { j } else { parent[j - n] as usize };
                                adv += (f[pj] - f[i]) * (pairs.grad[off + kk].dot(&us) * vol);
                            }
                        }
                        adv * dt
                    })
                    .collect()
            };
            // Eulerian frame: the ALE term is the whole advection, a central difference that
            // forward Euler amplifies (module documentation, the closed channel); Shu &
            // Osher's three-stage SSP Runge-Kutta is stable for it. The Lagrangian shift is a
            // small displacement and keeps the single stage of eq. (31).
            let advected: Vec<Mat2> = if !lagrangian {
                let d0 = ale(&psi);
                let p1: Vec<Mat2> = psi.iter().zip(&d0).map(|(p, d)| p + d).collect();
                let d1 = ale(&p1);
                let p2: Vec<Mat2> = psi
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
        let tau_p: Vec<Mat2> = conf.iter().map(|a| self.model.polymer_stress(a)).collect();
        let phi: Vec<Mat2> = if R::ELASTIC {
            tau_p
                .iter()
                .zip(&kappa)
                .map(|(t, k)| self.evss.phi(t, k))
                .collect()
        } else {
            Vec::new()
        };
        // Closed channel: the mirrors' Phi continues the fitted shear-stress slope.
        let phi_mirror: Vec<Mat2> = if R::ELASTIC {
            // Each wall's model continues Phi across it (mirrors: the parent's, NoSlip).
            let mut pm = vec![Mat2::zeros(); nm];
            for ((wall, plate), (_, r)) in self.walls.iter().zip(&st.walls).zip(&wall_ranges) {
                wall.fill_stresses(plate, &st.fluid, &[], &phi, &mut pm[r.clone()]);
            }
            if !self.free_surface {
                for (w, r) in &wall_ranges {
                    let d = wall_profile::shear_stress_corrections(
                        &st.walls[*w],
                        &xs,
                        &parent[r.clone()],
                        &phi,
                        radius,
                    );
                    for (p, dp) in pm[r.clone()].iter_mut().zip(d) {
                        *p += dp;
                    }
                }
            }
            pm
        } else {
            Vec::new()
        };

        // Step 4: the predictor (24). Per particle: remap u_ps . grad u, div Phi / rho (positive
        // form) and, explicitly, the viscous Laplacian; the mirrors' share of the forces apart.
        let mu: Vec<f64> = kappa.iter().map(|k| self.laplacian_viscosity(k)).collect();
        let explicit = self.viscous == ViscousStep::Explicit;
        // Closed channel: the mirrors of the viscous term continue the wall curvature that the
        // wall's momentum balance prescribes (no acceleration at a no-slip wall):
        // mu_w u''_w = -(rho g.t + dPhi_tn/dn).
        let visc_curv_closed: Vec<Vec2>;
        let visc_curv: &[Vec2] = if self.free_surface {
            &u_curv
        } else {
            let mut c = Vec::with_capacity(nm);
            for (w, r) in &wall_ranges {
                let plate = &st.walls[*w];
                let par = &parent[r.clone()];
                let slope = if R::ELASTIC {
                    wall_profile::shear_stress_slope(plate, &xs, par, &phi, radius)
                } else {
                    0.0
                };
                let mu_w = if par.is_empty() {
                    0.0
                } else {
                    par.iter().map(|&i| mu[i as usize]).sum::<f64>() / par.len() as f64
                };
                let curv = if mu_w > 0.0 {
                    -(rho * g.dot(&plate.t) + slope) / mu_w
                } else {
                    0.0
                };
                c.extend(wall_profile::curvature_corrections(plate, &xs, par, curv));
            }
            visc_curv_closed = c;
            &visc_curv_closed
        };
        let u_visc_closed: Vec<Vec2>;
        let u_visc: &[Vec2] = if self.free_surface {
            &u_n
        } else {
            u_visc_closed = extend_over_mirrors(&fl.v, &parent, &u_wall, visc_curv);
            &u_visc_closed
        };
        // Weight of u^n in the viscous term: all of it explicitly, 1 - theta implicitly.
        let theta = if explicit { 0.0 } else { self.theta };
        let w_old = 1.0 - theta;
        let mass = st.fluid.mass;
        let free_surface = self.free_surface;
        let rows: Vec<(Vec2, Vec2, Vec2)> = (0..n)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| {
                let off = nl.offset(i);
                let remap = kappa[i] * u_ps[i];
                let (mut f, mut fw) = (Vec2::zeros(), Vec2::zeros());
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let j = j as usize;
                    let pj = if j < n { j } else { parent[j - n] as usize };
                    let mut a = Vec2::zeros();
                    if R::ELASTIC {
                        let phi_j = if j < n { phi[j] } else { phi_mirror[j - n] };
                        a += if free_surface {
                            (phi[i] + phi_j) * pairs.grad[off + kk] * (vol / rho)
                        } else {
                            (phi_j - phi[i]) * (l[i] * pairs.grad[off + kk]) * (vol / rho)
                        };
                    }
                    if w_old > 0.0 {
                        let c = pairs.morris[off + kk] * 0.5 * (mu[i] + mu[pj]) / rho * w_old;
                        a += (u_visc[i] - u_visc[j]) * c;
                    }
                    if j < n {
                        f += a;
                    } else {
                        fw += a;
                    }
                }
                // Closed channel: the difference form's fluid pairs do not cancel; what they
                // leave is the force the walls exert through the stress (no other boundary).
                let on_wall = if free_surface || !R::ELASTIC {
                    fw
                } else {
                    f + fw
                };
                (remap, f + fw, on_wall)
            })
            .collect();
        // Closed channel: the body force goes into the predictor (King & Lind eq. (24) as
        // printed). Nothing balances it but the viscous and polymer stresses, and with the
        // corrector's g (free-surface scenes, see the module documentation) the implicit
        // viscous step acts on u* = u - g dt: measured, the Newtonian channel then settled
        // g dt (0.067 U at 30 across) above Poiseuille everywhere, a wall slip of order dt.
        let (g_pred, g_corr) = if self.free_surface {
            (Vec2::zeros(), g)
        } else {
            (g, Vec2::zeros())
        };
        let mut remap_force = Vec2::zeros();
        let mut wall_on_fluid = Vec2::zeros();
        let mut rhs: Vec<Vec2> = Vec::with_capacity(n);
        for (i, (remap, a, aw)) in rows.iter().enumerate() {
            remap_force += remap * mass;
            wall_on_fluid += aw * mass;
            rhs.push(fl.v[i] + (remap + a + g_pred) * dt);
        }
        // s_i = sum_j V_j grad_i W_ij: about -n / delta where the support is truncated, zero
        // in a full lattice support; the surface traction's weight (module documentation,
        // "Free-surface traction").
        let surface_sum = |i: usize| -> Vec2 { pairs.gradient_sum(&nl, i, vol) };
        // The surface traction is not a pair force, so its sum does not cancel; a free surface
        // exerts no net force, so the mean over the free (not held) particles is removed.
        let mean_over_free = |v: &[Vec2]| -> Vec2 {
            let free = (0..n).filter(|&i| !is_held(i)).count().max(1);
            v.iter().fold(Vec2::zeros(), |a, f| a + f) / free as f64
        };
        if explicit && self.free_surface {
            // The solvent's surface traction, explicit (the implicit solve's
            // SurfaceTraction term on u^n): 2 mu_i (G_i + G_i^T) s_i / rho, its mean removed.
            let acc: Vec<Vec2> = (0..n)
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .map(|i| {
                    if is_held(i) {
                        return Vec2::zeros();
                    }
                    let s_i = surface_sum(i);
                    let sym = self.along() * kappa[i]
                        + SURFACE_TRACTION_TRANSPOSED * kappa[i].transpose();
                    sym * s_i * (2.0 * mu[i] / rho)
                })
                .collect();
            let mean = mean_over_free(&acc);
            for (i, r) in rhs.iter_mut().enumerate() {
                if !is_held(i) {
                    *r += (acc[i] - mean) * dt;
                }
            }
        }
        let mut iters = [0u64; 2];
        let u_star: Vec<Vec2> = if explicit {
            rhs
        } else {
            let t0 = Instant::now();
            // (I - dt/rho lap_mu) u* = rhs; pair coefficients carry the pair's mean viscosity.
            let mut coef = pairs.morris.clone();
            nl.split_mut(&mut coef)
                .into_par_iter()
                .enumerate()
                .for_each(|(i, c)| {
                    for (ck, &j) in c.iter_mut().zip(nl.of(i)) {
                        let j = j as usize;
                        let pj = if j < n { j } else { parent[j - n] as usize };
                        *ck *= 0.5 * (mu[i] + mu[pj]);
                    }
                });
            let sign = vec![-1.0; nm];
            let offset: Vec<Vec2> = u_wall
                .iter()
                .zip(visc_curv)
                .map(|(w, c)| 2.0 * w + c)
                .collect();
            let mut u = rhs.clone();
            if surf.is_some() {
                // The solvent's surface traction, implicit (module documentation, "Free-surface
                // traction"): every row, k_i = 2 mu_i dt s_i / rho with s_i = sum_j V grad W_ij
                // (zero in a full support on a lattice); not on the inlet's held particles.
                let k: Vec<Vec2> = (0..n)
                    .into_par_iter()
                    .with_min_len(MIN_TASK)
                    .map(|i| {
                        if is_held(i) {
                            return Vec2::zeros();
                        }
                        surface_sum(i) * (2.0 * mu[i] * theta * dt / rho)
                    })
                    .collect();
                let mut w = pairs.grad.clone();
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
                    &nl,
                    &coef,
                    theta * dt / rho,
                    &parent,
                    &sign,
                    &offset,
                    &rhs,
                    &mut u,
                    &st_fs,
                    &self.solver,
                )
                .map_err(|e| format!("implicit viscous step: {e}"))?;
                iters[1] = stats.iterations as u64;
                // The free surface exerts no net force on the fluid, but this term is not a
                // pair force and its sum does not cancel (about 3 % of the weight of a slowly
                // settling drop, eta = 40 Pa s): its mean is removed, a uniform velocity
                // change that no gradient sees (module documentation).
                let ue = extend_over_mirrors(&u, &parent, &u_wall, visc_curv);
                let net: Vec<Vec2> = (0..n)
                    .into_par_iter()
                    .with_min_len(MIN_TASK)
                    .map(|i| {
                        let off = nl.offset(i);
                        let mut f = Vec2::zeros();
                        for (kk, &j) in nl.of(i).iter().enumerate() {
                            if j as usize != i {
                                f += st_fs.pair(i, off + kk) * (ue[j as usize] - ue[i]);
                            }
                        }
                        f
                    })
                    .collect();
                let mean = mean_over_free(&net);
                for (i, ui) in u.iter_mut().enumerate() {
                    if !is_held(i) {
                        *ui -= mean;
                    }
                }
            } else {
                let stats = ppe::solve_viscous(
                    n,
                    &nl,
                    &coef,
                    theta * dt / rho,
                    &parent,
                    &sign,
                    &offset,
                    &rhs,
                    &mut u,
                    &self.solver,
                )
                .map_err(|e| format!("implicit viscous step: {e}"))?;
                iters[1] = (stats[0].iterations + stats[1].iterations) as u64;
            }
            // The momentum the solve changed is the mirrors' viscous force: the fluid-fluid
            // coefficients are symmetric, so their share cancels pair by pair (and the surface
            // term's net has been removed).
            for (ui, ri) in u.iter().zip(&rhs) {
                wall_on_fluid += (ui - ri) * (mass / dt);
            }
            self.timings.viscous_solve += t0.elapsed().as_secs_f64();
            u
        };
        let mut u_star = u_star;
        for i in (0..n).filter(|&i| is_held(i)) {
            held_momentum += (fl.v[i] - u_star[i]) * mass;
            u_star[i] = fl.v[i];
        }

        // Step 5: the PPE (25) with the free-surface pressure of (35a).
        let t0 = Instant::now();
        let us_all = extend_u(&u_star);
        let kappa_star = corrected_velocity_gradients(n, &us_all, vol, &nl, pairs, &l);
        let mut b: Vec<f64> = kappa_star
            .iter()
            .enumerate()
            .map(|(i, k)| {
                if is_held(i) {
                    0.0
                } else {
                    rho / dt * k.trace()
                }
            })
            .collect();
        // Density invariance (Asai et al. 2012): where the support is full (neither on the free
        // surface nor next to it), a concentration above the lattice's pushes apart, one below
        // pulls together; near the surface the truncated sum would read a spurious expansion.
        // Not on the inlet's held particles (their velocity is prescribed).
        // Near the surface the reference is the concentration a particle keeps at its distance
        // below a straight surface row, and the free-surface rows (which keep their continuity
        // equation, below) take the same source against the last row's share (module
        // documentation, "Volume"); both per step of the default advective step.
        if let Some(s) = &surf {
            let c0 = self.c_lattice;
            let lim = self.advective_limit(umax);
            let ratio = dt / (DT_COEF_PER_FACTOR * DEFAULT_STEP_FACTOR * lim);
            let per_default_step = if ratio < 1.0 - 1e-9 { ratio } else { 1.0 };
            let alpha_ns = NEAR_SURFACE_INVARIANCE * per_default_step;
            let alpha_fs = SURFACE_ROW_INVARIANCE * per_default_step;
            let c_row = c0 * self.half_lattice.share(0.0);
            for (i, bi) in b.iter_mut().enumerate() {
                if is_held(i) {
                    continue;
                }
                if s.is_surface[i] {
                    *bi += alpha_fs * rho / (dt * dt) * ((c_row - s.concentration[i]) / c_row);
                    continue;
                }
                let (alpha, c_ref) = if !s.near_surface[i] {
                    (DENSITY_INVARIANCE, c0)
                } else if let Some(a) = surface::row_distance(i, all_x, &nl, &dom, s, &self.kernel)
                {
                    (alpha_ns, c0 * self.half_lattice.share(a))
                } else {
                    continue;
                };
                *bi += alpha * rho / (dt * dt) * (c_ref - s.concentration[i]) / c_ref;
            }
        }
        // Inlet particles within reach of free fluid: Neumann (module documentation).
        let neumann = |i: usize| {
            is_held(i)
                && nl
                    .of(i)
                    .iter()
                    .any(|&j| (j as usize) < n && !is_held(j as usize))
        };
        let offsets: Vec<f64> = parent
            .iter()
            .enumerate()
            .map(|(m, &i)| rho * g.dot(&dom.delta(&all_x[n + m], &xs[i as usize])))
            .collect();
        // Free-surface particles: Dirichlet rows whose value puts p = 0 on the surface of the
        // layer they stand for, not on their centres (module documentation).
        let dirichlet: Vec<Option<f64>> = match &surf {
            Some(s) => {
                let depth = surface::row_density(all_x, &nl, &dom, &s.is_surface, h, dx);
                let p_prev: &[f64] = if st.pressure.len() == n {
                    &st.pressure
                } else {
                    &[]
                };
                (0..n)
                    .map(|i| {
                        (s.is_surface[i] && !neumann(i)).then(|| {
                            surface_pressure(
                                i,
                                n,
                                p_prev,
                                &s.is_surface,
                                &parent,
                                &offsets,
                                &nl,
                                &self.kernel,
                                all_x,
                                &dom,
                                s.normal[i],
                                0.5 * dx * depth[i],
                            )
                        })
                    })
                    .collect()
            }
            None => Vec::new(),
        };
        let ghosts = GhostLink {
            parent: &parent,
            sign: &[],
            offset: &offsets,
        };
        let mut dirichlet = dirichlet;
        // King & Lind (35a)'s solvent normal stress as the surface pressure (normal_stress):
        // 2 mu n.D.n = -2 mu t.G(u*).t by continuity, from the velocity the projection is about
        // to correct (module documentation, "Free-surface pressure"). Zero elsewhere.
        let p_fs: Vec<f64> = match &surf {
            Some(s) if self.normal_stress => (0..n)
                .map(|i| {
                    if !s.is_surface[i] || is_held(i) {
                        return 0.0;
                    }
                    let t = Vec2::new(-s.normal[i].y, s.normal[i].x);
                    -2.0 * mu[i] * t.dot(&(kappa_star[i] * t))
                })
                .collect(),
            _ => vec![0.0; n],
        };
        for (i, d) in dirichlet.iter_mut().enumerate() {
            if let Some(v) = d {
                *v += p_fs[i];
            }
        }
        // Free-surface rows keep their continuity equation (module documentation, "Volume"):
        // row i of `-lap p = -b` takes `c_i p_i`, the part of Morris' Laplacian that the
        // neighbours missing beyond the surface would give if p fell linearly to 0 at `depth`
        // outside the particle, `c_i = -n . sum_j c_ij x_ji / depth` (the first moment of a full
        // support vanishes, so the missing neighbours' moment is minus the present ones');
        // Dirichlet where that is not positive.
        let robin: Vec<(f64, f64)> = match &surf {
            Some(s) => {
                let depth = surface::row_density(all_x, &nl, &dom, &s.is_surface, h, dx);
                (0..n)
                    .map(|i| {
                        if dirichlet[i].is_none() {
                            return (0.0, 0.0);
                        }
                        let off = nl.offset(i);
                        let mut m1 = Vec2::zeros();
                        for (kk, &j) in nl.of(i).iter().enumerate() {
                            let j = j as usize;
                            if j != i {
                                m1 -= dom.delta(&all_x[j], &xs[i]) * pairs.morris[off + kk];
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
                    .collect()
            }
            _ => Vec::new(),
        };
        let sys =
            ppe::assemble_poisson_surface(n, &nl, &pairs.morris, &ghosts, &dirichlet, &robin, &b);
        let mut pres = if st.pressure.len() == n {
            st.pressure.clone()
        } else if st.inflow.is_some() && st.pressure.len() < n {
            // Particles entered at the end of the list: the others keep their warm start.
            let mut p = st.pressure.clone();
            p.resize(n, 0.0);
            p
        } else {
            vec![0.0; n]
        };
        let stats = ppe::solve(&sys, &mut pres, &self.solver)
            .map_err(|e| format!("pressure Poisson equation: {e}"))?;
        iters[0] = stats.iterations as u64;
        self.timings.pressure_solve += t0.elapsed().as_secs_f64();

        // Step 6: projection (26) with gravity, positive-form pressure gradient.
        let p_all: Vec<f64> = pres
            .iter()
            .copied()
            .chain(
                parent
                    .iter()
                    .zip(&offsets)
                    .map(|(&i, o)| pres[i as usize] + o),
            )
            .collect();
        // The surface pressure each particle's truncated support sees (normal_stress): its own
        // on a surface row, the kernel-weighted mean of its surface neighbours' elsewhere (zero
        // where the support is full, where it would not matter: sum_j V grad W_ij = 0 there).
        let p_ghost: Vec<f64> = match &surf {
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
        };
        let proj: Vec<(Vec2, Vec2, Vec2)> = (0..n)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| {
                let off = nl.offset(i);
                let (mut f, mut fw) = (Vec2::zeros(), Vec2::zeros());
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let j = j as usize;
                    let a = pairs.grad[off + kk] * ((p_all[i] + p_all[j]) * (-vol / rho));
                    if j < n {
                        f += a;
                    } else {
                        fw += a;
                    }
                }
                // The positive form of p - p_s: the pressure beyond the surface continues as
                // 2 p_s - p_i, not -p_i (module documentation, "Free-surface pressure").
                let surface = match p_ghost.get(i) {
                    Some(&ps) if !is_held(i) => surface_sum(i) * (2.0 * ps / rho),
                    _ => Vec2::zeros(),
                };
                (f + fw + surface, fw, surface)
            })
            .collect();
        // The surface term is not a pair force and its sum does not cancel; a free surface
        // exerts no net force, so its mean over the free particles is removed, as for the
        // solvent's surface traction.
        let free = (0..n).filter(|&i| !is_held(i)).count().max(1);
        let surface_mean = proj.iter().fold(Vec2::zeros(), |a, p| a + p.2) / free as f64;
        let mut u_new = Vec::with_capacity(n);
        for (i, (a, aw, _)) in proj.iter().enumerate() {
            wall_on_fluid += aw * mass;
            let a = if p_ghost.is_empty() || is_held(i) {
                *a
            } else {
                a - surface_mean
            };
            u_new.push(u_star[i] + (a + g_corr) * dt);
            if is_held(i) {
                held_momentum += (fl.v[i] - u_new[i]) * mass;
                u_new[i] = fl.v[i];
            }
        }

        // Step 7: advection (27).
        let fl = &mut st.fluid;
        if lagrangian {
            for i in 0..n {
                fl.x[i] = dom.wrap(fl.x[i] + (fl.v[i] + u_new[i] + 2.0 * u_ps[i]) * (0.5 * dt));
            }
        }
        if let Some(inl) = st.inflow.as_mut() {
            inl.momentum += held_momentum;
        }
        fl.v = u_new;
        if R::ELASTIC {
            fl.conf = conf;
        }
        let mut contact = Vec2::zeros();
        for wall in &st.walls {
            let (m, reflections) = keep_above_plate(&mut st.fluid, wall);
            contact += m;
            st.wall_reflections += reflections;
        }
        st.wall_force = -wall_on_fluid - contact / dt;
        st.wall_impulse += -wall_on_fluid * dt - contact;
        st.remap_impulse += remap_force * dt;
        st.pressure = pres;
        st.solver_iterations[0] += iters[0];
        st.solver_iterations[1] += iters[1];
        st.last_dt = dt_stable;
        // No density to check, and no tensile instability to act on: the void fraction is
        // reported, not acted on.
        health::check_particles(
            &st.fluid,
            &st.walls,
            dx,
            self.p.domain_radius,
            R::ELASTIC,
            None,
        )?;
        st.void_fraction = health::fluid_void_fraction(&st.fluid, st.walls.first(), dx);
        self.timings.total += t_start.elapsed().as_secs_f64();
        Ok(dt)
    }

    fn timings(&self) -> super::Timings {
        super::Timings {
            total: self.timings.total,
            parts: vec![
                ("pressure solve", self.timings.pressure_solve),
                ("viscous solve", self.timings.viscous_solve),
            ],
        }
    }

    fn wall_positions(&self, st: &State) -> Vec<Vec2> {
        self.walls
            .iter()
            .zip(&st.walls)
            .flat_map(|(w, p)| w.positions(p))
            .collect()
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
fn surface_pressure(
    i: usize,
    n: usize,
    p_prev: &[f64],
    is_surface: &[bool],
    parent: &[u32],
    offsets: &[f64],
    nl: &NeighborList,
    kernel: &QuinticSpline,
    x: &[Vec2],
    dom: &crate::neighbors::Domain,
    normal: Vec2,
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
