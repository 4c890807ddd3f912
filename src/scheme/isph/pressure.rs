//! Step 5 of King & Lind 2021's ISPH: the pressure Poisson equation (25)
//! `lap p = (rho / dt) div u*` (Morris' Laplacian (21), the divergence of the corrected gradient
//! (20) of u*), with a density-invariant source, the free-surface rows of
//! [`super::free_surface`], the virtual particles Neumann with the hydrostatic offset
//! (`Isph::pressure_offsets`) and the inlet's held particles Neumann where free fluid sees them;
//! solved by BiCGStab warm started from p^n, preconditioned by ILU(0) or, from
//! [`ppe::AMG_MIN_ROWS`] particles, algebraic multigrid ([`super::ppe`]).
//!
//! **Density-invariant PPE source** on the particles with a full kernel support (neither on
//! the free surface nor next to it): `b_i += alpha rho (C0 - C_i) / (C0 dt^2)` with the
//! concentration `C_i = sum_j V_j W_ij` (fluid and mirrors) and `C0` its value inside a square
//! lattice, alpha = 0.05 (the "stabilised ISPH" of Asai et al. 2012; Lind et al. 2012 mix a
//! density term in likewise). The velocity-divergence source alone lets the particle
//! arrangement drift: the Newtonian Re = 4 drop at W/dr = 40 covered +3.4 % more area after
//! impact; with the term, at most 1.7 % (alpha = 0.2: 1.8 %). Applied on every particle, the
//! truncated sums near the surface read as expansion and pull the surface in (-1.9 % at
//! W/dr = 40, alpha = 0.2); applied only where compressed, it did nothing measurable. What
//! remains is tangential crowding of the free-surface row (Dirichlet rows, which no source
//! reaches): docs/isph.md, "Volume".
//!
//! **Volume at W/dr = 40** (target 0.5 %; docs/isph.md, "Volume": largest |volume_error|
//! of the Newtonian Re = 4 drop over t* <= 8 from 0.63 % to 0.46 %, 1.79 % to 0.86 % at
//! W/dr = 20, 0.44 % to 0.22 % at 80), four parts measured together and apart:
//! - *Surface rows keep their continuity equation.* A Dirichlet row has no div u and no density
//!   feedback, so the contact line's pile-up of surface particles (about 9 particles 0.48 dx apart
//!   on the rim's face at t* = 8) never returned to the bulk. Row i instead takes the part of
//!   Morris' Laplacian its missing neighbours would give if p fell linearly to 0 at `depth` outside
//!   it (a Robin row, [`super::ppe::assemble_poisson_surface`], built in [`super::free_surface`]).
//! - *Density-invariant source on those rows* (`SURFACE_ROW_INVARIANCE`) against the share
//!   of the last row of a straight lattice edge ([`surface::HalfLattice`]): with it the late
//!   loss (-0.56 % at t* = 8) stays within -0.33 %.
//! - *Near-surface source* (`NEAR_SURFACE_INVARIANCE`) against the share a particle keeps
//!   at its distance below the surface row ([`surface::row_distance`]): the bulk and the NS
//!   band had stayed 0.6-1 % expanded after impact.
//! - *Frame-independent shifting.* King & Lind's coefficient (41) follows the particle's
//!   speed; it follows the speed relative to the fluid's mean velocity, so a drop in free
//!   flight at 1 m/s is not reshuffled (with the surface-row source alone the flying drop
//!   first contracted, then expanded 1.2 % at impact).
//!
//! **Curved surfaces (3D).** The two near-surface references above are those of a flat surface.
//! A convex surface holds fewer neighbours within the kernel's reach, so against them a drop's
//! surface rows read as expanded and the sources pull them in every step, with nothing to stop
//! them: a sphere in free fall (a rigid motion, no reason to compress) lost 3.7 % of its
//! second-moment volume in t* = 0.5 at 10 particles per diameter (the covered volume on the
//! plate: -3.8 % to -4.9 % over t* = 0.5-2). With both sources off it moved as a rigid body;
//! each alone took about half. In 3D both references therefore lose the fluid between the
//! tangent plane and the surface ([`surface::HalfLattice::curved_share`]), with the mean
//! curvature fitted to the surface neighbours' heights ([`surface::mean_curvature`], the
//! surface row's for a near-surface particle, [`surface::row_curvature`]): free fall -1.3 %,
//! plate -1.1 % to +1.1 % (the raster's own scatter at 10 per diameter is about 1.4 %). The 2D
//! drop has the same cause at half the strength (one curvature): the 2D Re = 4 drop at 10 per
//! diameter falling freely for t* = 0.5 goes from +0.23 % to -3.07 % `volume_error` with the flat
//! references and to -0.76 % with the curved ones; 2D keeps the flat references (its tests and
//! goldens were measured with them; docs/isph.md, "Dimensions").

use super::ppe::{self, GhostLink};
use super::step_size::DT_COEF_PER_FACTOR;
use super::{Books, Context, Fields, Isph, MIN_TASK};
use crate::dim::{Const, Dim, Vector};
use crate::kernel::Kernel;
use crate::operators::kinematics::{corrected_velocity_gradients, recorrect_rows};
use crate::operators::surface;
use crate::rheology::Rheology;
use crate::state::State;
use rayon::prelude::*;
use std::time::Instant;

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

/// The pressure of step 5 and what the projection reads with it.
pub(super) struct Pressure {
    /// Fluid pressures.
    pub p: Vec<f64>,
    /// Hydrostatic offsets of the virtual particles' pressures.
    pub offsets: Vec<f64>,
    /// (35a)'s surface value on each surface row (zeros with p = 0).
    pub p_fs: Vec<f64>,
}

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// Solve the PPE for the predicted velocity `u_star` of the state `st`.
    pub(super) fn pressure(
        &self,
        st: &State<N>,
        ctx: &Context<N>,
        f: &Fields<N>,
        u_star: &[Vector<N>],
        books: &mut Books<N>,
    ) -> Result<Pressure, String> {
        let t0 = Instant::now();
        let t = self.clock();
        let (n, dt, vol, rho) = (ctx.n, ctx.dt, ctx.vol, self.rho);
        let (nl, held, pairs) = (&ctx.nl, &ctx.held, &self.pairs);
        let us_all = ctx.extend(u_star);
        let mut kappa_star = corrected_velocity_gradients(n, &us_all, vol, nl, pairs, &ctx.l);
        let mut b: Vec<f64> = kappa_star
            .iter()
            .enumerate()
            .map(|(i, k)| {
                if held.holds(i) {
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
        if let Some(s) = &ctx.surf {
            let c0 = self.c_lattice;
            let lim = self.advective_limit(ctx.umax);
            let ratio = dt / (DT_COEF_PER_FACTOR * DEFAULT_STEP_FACTOR * lim);
            let per_default_step = if ratio < 1.0 - 1e-9 { ratio } else { 1.0 };
            let alpha_ns = NEAR_SURFACE_INVARIANCE * per_default_step;
            let alpha_fs = SURFACE_ROW_INVARIANCE * per_default_step;
            let c_row = c0 * self.half_lattice.share(0.0);
            let dom = self.p.domain;
            // In 3D the references follow the surface's mean curvature (module documentation,
            // "Curved surfaces").
            let curved = N == 3;
            let curvature = if curved {
                surface::mean_curvature(&self.all_x, nl, &dom, s, &self.kernel)
            } else {
                Vec::new()
            };
            // Each particle's source by itself, in parallel.
            b.par_iter_mut()
                .enumerate()
                .with_min_len(MIN_TASK)
                .for_each(|(i, bi)| {
                    if held.holds(i) {
                        return;
                    }
                    if s.is_surface[i] {
                        let c_row = if curved {
                            c0 * self.half_lattice.curved_share(0.0, curvature[i])
                        } else {
                            c_row
                        };
                        *bi += alpha_fs * rho / (dt * dt) * ((c_row - s.concentration[i]) / c_row);
                        return;
                    }
                    let (alpha, c_ref) = if !s.near_surface[i] {
                        (DENSITY_INVARIANCE, c0)
                    } else if let Some(a) =
                        surface::row_distance(i, &self.all_x, nl, &dom, s, &self.kernel)
                    {
                        let share = if curved {
                            let k = surface::row_curvature(
                                i,
                                &self.all_x,
                                nl,
                                &dom,
                                s,
                                &curvature,
                                &self.kernel,
                            );
                            self.half_lattice.curved_share(a, k)
                        } else {
                            self.half_lattice.share(a)
                        };
                        (alpha_ns, c0 * share)
                    } else {
                        return;
                    };
                    *bi += alpha * rho / (dt * dt) * (c_ref - s.concentration[i]) / c_ref;
                });
        }
        // Inlet particles within reach of free fluid: Neumann (module documentation of
        // `isph`, "Inlet").
        let neumann = |i: usize| {
            held.holds(i)
                && nl
                    .of(i)
                    .iter()
                    .any(|&j| (j as usize) < n && !held.holds(j as usize))
        };
        let offsets = self.pressure_offsets(ctx);
        // (35a)'s surface value reads the tangential strain with the surface particles' own
        // correction ([`super::free_surface`], "Free-surface pressure"); elsewhere `l_own` is
        // `l`, so only the surface rows' gradients change (the source above is already summed).
        if let (true, Some(s)) = (self.normal_stress, &ctx.surf) {
            recorrect_rows(
                &mut kappa_star,
                &s.is_surface,
                &us_all,
                vol,
                nl,
                pairs,
                &ctx.l_own,
            );
        }
        let rows = self.surface_rows(st, ctx, &offsets, &kappa_star, &f.mu, &f.phi, neumann);
        let ghosts = GhostLink {
            parent: &ctx.virt.parent,
            sign: &[],
            offset: &offsets,
        };
        let t = self.lap(t, "pressure: source, surface rows", false);
        let sys = ppe::assemble_poisson_surface(
            n,
            nl,
            &pairs.morris,
            &ghosts,
            &rows.dirichlet,
            &rows.robin,
            &b,
        );
        let mut pres = if self.incremental(ctx) {
            // The increment p^{n+1} - p^n, from zero.
            vec![0.0; n]
        } else if st.pressure.len() == n {
            st.pressure.clone()
        } else if st.inflow.is_some() && st.pressure.len() < n {
            // Particles entered at the end of the list: the others keep their warm start.
            let mut p = st.pressure.clone();
            p.resize(n, 0.0);
            p
        } else {
            vec![0.0; n]
        };
        let opts = ppe::SolverOptions {
            preconditioner: ppe::Preconditioner::for_pressure(n),
            ..self.solver
        };
        let stats = ppe::solve(&sys, &mut pres, &opts)
            .map_err(|e| format!("pressure Poisson equation: {e}"))?;
        books.iterations[0] = stats.iterations as u64;
        self.lap_solve(t, &opts, ["pressure solve", "pressure solve, ILU(0)"]);
        books.pressure_time += t0.elapsed().as_secs_f64();
        Ok(Pressure {
            p: pres,
            offsets,
            p_fs: rows.p_fs,
        })
    }
}

/// The concentration `sum_j V_j W_ij` of a particle inside an unbounded square (3D: cubic)
/// lattice of spacing `dx` (V = dx^N): the value of a particle of the uncompressed fluid.
pub(super) fn lattice_concentration<const N: usize, K: Kernel<N>>(kernel: &K, dx: f64) -> f64 {
    let reach = (kernel.radius() / dx).ceil() as i64;
    let mut c = 0.0;
    if N == 2 {
        for j in -reach..=reach {
            for i in -reach..=reach {
                c += kernel.w(dx * ((i * i + j * j) as f64).sqrt());
            }
        }
        return c * dx * dx;
    }
    assert_eq!(N, 3, "a square or cubic lattice");
    for k in -reach..=reach {
        for j in -reach..=reach {
            for i in -reach..=reach {
                c += kernel.w(dx * ((i * i + j * j + k * k) as f64).sqrt());
            }
        }
    }
    c * dx * dx * dx
}
