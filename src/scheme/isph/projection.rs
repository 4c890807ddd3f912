//! Step 6 of King & Lind 2021's ISPH, the projection (26): `u^{n+1} = u* - dt grad p / rho +
//! dt g`, the pressure gradient by the positive form `sum_j (p_i + p_j) grad W_ij V_j` over the
//! fluid and the virtual particles (momentum-conserving pairs: module documentation of `isph`;
//! in a closed cell with a curved wall the corrected difference form of the increment
//! `p^{n+1} - p^n`, ibid., "Curved walls");
//! with the normal-stress surface condition the positive form of `p - p_s`
//! ([`super::free_surface`], "Free-surface pressure").
//!
//! **Gravity in the corrector** (King's newer code) with the hydrostatic mirror pressure
//! `p_m = p_i + rho g . (r_m - r_i)`: a fluid at rest then holds its hydrostatic pressure exactly
//! instead of through the no-slip mirror velocities of g dt.

use super::pressure::Pressure;
use super::{Books, Context, Isph, MIN_TASK};
use crate::dim::{Const, Dim, Vector};
use crate::particles::Fluid;
use crate::rheology::Rheology;
use crate::state::State;
use rayon::prelude::*;

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// The new velocities from the predicted `u_star` and the pressure of step 5; the inlet's
    /// held particles keep theirs (`fl.v`).
    pub(super) fn projection(
        &self,
        fl: &Fluid<N>,
        ctx: &Context<N>,
        u_star: &[Vector<N>],
        pressure: &Pressure,
        books: &mut Books<N>,
    ) -> Vec<Vector<N>> {
        let (n, dt, vol, mass, rho) = (ctx.n, ctx.dt, ctx.vol, ctx.mass, self.rho);
        let (nl, held, pairs) = (&ctx.nl, &ctx.held, &self.pairs);
        let pres = &pressure.p;
        // The closed channel takes the body force in the predictor (`predictor`).
        let g_corr = if self.free_surface {
            self.p.gravity
        } else {
            Vector::<N>::zeros()
        };
        let p_all = extend_pressure(ctx, pres, &pressure.offsets);
        let p_ghost = self.ghost_surface_pressure(ctx, &pressure.p_fs);
        let walls = books.per_wall.len();
        let grad = self.pressure_accelerations(ctx, &p_all, walls);
        let proj: Vec<(Vector<N>, Vector<N>, Vector<N>, Vec<Vector<N>>)> = grad
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .enumerate()
            .map(|(i, (a, fw, by_wall))| {
                // The positive form of p - p_s: the pressure beyond the surface continues as
                // 2 p_s - p_i, not -p_i (`free_surface`, "Free-surface pressure").
                let surface = match p_ghost.get(i) {
                    Some(&ps) if !held.holds(i) => {
                        pairs.gradient_sum(nl, i, vol) * (2.0 * ps / rho)
                    }
                    _ => Vector::<N>::zeros(),
                };
                (a + surface, fw, surface, by_wall)
            })
            .collect();
        // The surface term is not a pair force and its sum does not cancel; a free surface
        // exerts no net force, so its mean over the free particles is removed, as for the
        // solvent's surface traction.
        let surface_mean = held.mean_over_free(proj.iter().map(|p| &p.2));
        let mut u_new = Vec::with_capacity(n);
        for (i, (a, aw, _, by_wall)) in proj.iter().enumerate() {
            books.wall_on_fluid += aw * mass;
            books.plate.add(i, aw * mass);
            for (b, w) in books.per_wall.iter_mut().zip(by_wall) {
                *b += w * mass;
            }
            let a = if p_ghost.is_empty() || held.holds(i) {
                *a
            } else {
                a - surface_mean
            };
            u_new.push(u_star[i] + (a + g_corr) * dt);
            if held.holds(i) {
                books.held_momentum += (fl.v[i] - u_new[i]) * mass;
                u_new[i] = fl.v[i];
            }
        }
        u_new
    }

    /// Per fluid particle, `-grad p / rho` for the pressures `p_all` of the fluid and the
    /// virtual particles, with the virtual particles' share and that share wall by wall (`walls`
    /// entries where the step splits the walls' force): the positive form
    /// `-sum_j (p_i + p_j) grad W_ij V_j / rho` (momentum-conserving pairs), or in a closed cell
    /// with a curved wall the corrected difference form `-L_i sum_j (p_j - p_i) grad W_ij V_j /
    /// rho`, its departure from the positive form booked as the first curved wall's force
    /// (module documentation, "Curved walls").
    pub(super) fn pressure_accelerations(
        &self,
        ctx: &Context<N>,
        p_all: &[f64],
        walls: usize,
    ) -> Vec<(Vector<N>, Vector<N>, Vec<Vector<N>>)> {
        let (n, vol, rho) = (ctx.n, ctx.vol, self.rho);
        let (nl, pairs) = (&ctx.nl, &self.pairs);
        let curved = self.curved_wall(ctx);
        (0..n)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| {
                let off = nl.offset(i);
                let (mut f, mut fw) = (Vector::<N>::zeros(), Vector::<N>::zeros());
                // The virtual pairs' share wall by wall, where the step splits it.
                let mut by_wall = vec![Vector::<N>::zeros(); walls];
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let j = j as usize;
                    let a = pairs.grad[off + kk] * ((p_all[i] + p_all[j]) * (-vol / rho));
                    ctx.add_pair(j, a, &mut f, &mut fw, &mut by_wall);
                }
                if let Some(w) = curved {
                    let mut d = Vector::<N>::zeros();
                    for (kk, &j) in nl.of(i).iter().enumerate() {
                        d += pairs.grad[off + kk] * (p_all[j as usize] - p_all[i]);
                    }
                    let corr = ctx.l[i] * d * (-vol / rho) - (f + fw);
                    fw += corr;
                    if walls > 0 {
                        by_wall[w] += corr;
                    }
                }
                (f + fw, fw, by_wall)
            })
            .collect()
    }

    /// Whether the step is an incremental pressure correction (a closed cell with a curved
    /// wall, module documentation, "Curved walls"): u* carries `-grad p^n / rho`, the PPE
    /// solves for the increment `p^{n+1} - p^n`.
    pub(super) fn incremental(&self, ctx: &Context<N>) -> bool {
        self.curved_wall(ctx).is_some()
    }

    /// The pressure p^n of the state `st` (zeros before the first solve).
    pub(super) fn previous_pressure(&self, st: &State<N>, ctx: &Context<N>) -> Vec<f64> {
        if st.pressure.len() == ctx.n {
            st.pressure.clone()
        } else {
            vec![0.0; ctx.n]
        }
    }

    /// The first curved wall of a closed cell (no free surface), whose mirrors make the
    /// corrected difference form of the pressure gradient and the incremental pressure
    /// correction necessary (module documentation, "Curved walls"); None otherwise.
    pub(super) fn curved_wall(&self, ctx: &Context<N>) -> Option<usize> {
        if self.free_surface {
            None
        } else {
            ctx.virt.straight.iter().position(|s| !s)
        }
    }
}

/// The fluid pressures `p` extended over the virtual particles (their parents' plus `offsets`).
pub(super) fn extend_pressure<const N: usize>(
    ctx: &Context<N>,
    p: &[f64],
    offsets: &[f64],
) -> Vec<f64> {
    p.iter()
        .copied()
        .chain(
            ctx.virt
                .parent
                .iter()
                .zip(offsets)
                .map(|(&i, o)| p[i as usize] + o),
        )
        .collect()
}
