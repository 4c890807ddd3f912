//! Step 6 of King & Lind 2021's ISPH, the projection (26): `u^{n+1} = u* - dt grad p / rho +
//! dt g`, the pressure gradient by the positive form `sum_j (p_i + p_j) grad W_ij V_j` over the
//! fluid and the virtual particles (momentum-conserving pairs: module documentation of `isph`);
//! with the normal-stress surface condition the positive form of `p - p_s`
//! ([`super::free_surface`], "Free-surface pressure").
//!
//! **Gravity in the corrector** (King's newer code) with the hydrostatic mirror pressure
//! `p_m = p_i + rho g . (r_m - r_i)`: a fluid at rest then holds its hydrostatic pressure exactly
//! instead of through the no-slip mirror velocities of g dt.

use super::pressure::Pressure;
use super::{Books, Context, Isph, MIN_TASK};
use crate::particles::Fluid;
use crate::rheology::Rheology;
use crate::Vec2;
use rayon::prelude::*;

impl<R: Rheology> Isph<R> {
    /// The new velocities from the predicted `u_star` and the pressure of step 5; the inlet's
    /// held particles keep theirs (`fl.v`).
    pub(super) fn projection(
        &self,
        fl: &Fluid,
        ctx: &Context,
        u_star: &[Vec2],
        pressure: &Pressure,
        books: &mut Books,
    ) -> Vec<Vec2> {
        let (n, dt, vol, mass, rho) = (ctx.n, ctx.dt, ctx.vol, ctx.mass, self.rho);
        let (nl, held, pairs) = (&ctx.nl, &ctx.held, &self.pairs);
        let pres = &pressure.p;
        // The closed channel takes the body force in the predictor (`predictor`).
        let g_corr = if self.free_surface {
            self.p.gravity
        } else {
            Vec2::zeros()
        };
        let p_all: Vec<f64> = pres
            .iter()
            .copied()
            .chain(
                ctx.virt
                    .parent
                    .iter()
                    .zip(&pressure.offsets)
                    .map(|(&i, o)| pres[i as usize] + o),
            )
            .collect();
        let p_ghost = self.ghost_surface_pressure(ctx, &pressure.p_fs);
        let walls = books.per_wall.len();
        let proj: Vec<(Vec2, Vec2, Vec2, Vec<Vec2>)> = (0..n)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| {
                let off = nl.offset(i);
                let (mut f, mut fw) = (Vec2::zeros(), Vec2::zeros());
                // The virtual pairs' share wall by wall, where the step splits it.
                let mut by_wall = vec![Vec2::zeros(); walls];
                for (kk, &j) in nl.of(i).iter().enumerate() {
                    let j = j as usize;
                    let a = pairs.grad[off + kk] * ((p_all[i] + p_all[j]) * (-vol / rho));
                    if j < n {
                        f += a;
                    } else {
                        fw += a;
                        if walls > 0 {
                            by_wall[ctx.virt.wall_of(j - n)] += a;
                        }
                    }
                }
                // The positive form of p - p_s: the pressure beyond the surface continues as
                // 2 p_s - p_i, not -p_i (`free_surface`, "Free-surface pressure").
                let surface = match p_ghost.get(i) {
                    Some(&ps) if !held.holds(i) => {
                        pairs.gradient_sum(nl, i, vol) * (2.0 * ps / rho)
                    }
                    _ => Vec2::zeros(),
                };
                (f + fw + surface, fw, surface, by_wall)
            })
            .collect();
        // The surface term is not a pair force and its sum does not cancel; a free surface
        // exerts no net force, so its mean over the free particles is removed, as for the
        // solvent's surface traction.
        let surface_mean = held.mean_over_free(proj.iter().map(|p| &p.2));
        let mut u_new = Vec::with_capacity(n);
        for (i, (a, aw, _, by_wall)) in proj.iter().enumerate() {
            books.wall_on_fluid += aw * mass;
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
}
