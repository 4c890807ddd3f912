//! Advection of King & Lind 2021's ISPH: the predicted positions of step 1, eq. (23)
//! `r* = r^n + dt u^n`; the shifting velocity of step 2, eqs. (40)-(44) (`u_ps = dr_s / dt`,
//! with the corrections [`shifting`] lists), which is also the ALE velocity of (24) and (31);
//! and the positions of step 7, eq. (27) `r^{n+1} = r^n + dt/2 (u^n + u^{n+1} + 2 u_ps)`. In the
//! Eulerian frame the particles stay and `u_ps = -u^n`.
//!
//! **Frame-independent shifting.** King & Lind's coefficient (41) follows the particle's speed;
//! here it follows the speed relative to the fluid's mean velocity, so a drop in free flight at
//! 1 m/s is not reshuffled ([`super::pressure`], "Volume at W/dr = 40"). The inlet's held
//! particles move with the inflow, not shifted.
//!
//! **Plate contact.** A particle that crosses a plate is reflected back with its normal velocity
//! removed (King's code reflects it too); the momentum removed counts in the wall force.

use super::{Context, Isph};
use crate::boundary::ghost::keep_out_of_walls;
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::kernel::Kernel;
use crate::operators::shifting;
use crate::particles::Fluid;
use crate::rheology::Rheology;
use crate::state::State;
use rayon::prelude::*;

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// Step 1, eq. (23): the positions r* (the particles' own in the Eulerian frame).
    pub(super) fn predict_positions(
        &self,
        fl: &Fluid<N>,
        dt: f64,
        lagrangian: bool,
    ) -> Vec<Vector<N>> {
        let dom = self.p.domain;
        if lagrangian {
            fl.x.par_iter()
                .zip(fl.v.par_iter())
                .map(|(x, v)| dom.wrap(x + v * dt))
                .collect()
        } else {
            fl.x.clone()
        }
    }

    /// The shifting velocity u_ps of eqs. (40)-(44) from the concentration gradients of
    /// step 2 without (`grad_c`) and with (`grad_c_q`) the repulsion Q; `-u^n` in the Eulerian
    /// frame; zero on the inlet's held particles.
    pub(super) fn shifting_velocity(
        &self,
        fl: &Fluid<N>,
        ctx: &Context<N>,
        grad_c: Vec<Vector<N>>,
        grad_c_q: Vec<Vector<N>>,
    ) -> Vec<Vector<N>> {
        let (n, dt, h) = (ctx.n, ctx.dt, self.kernel.h());
        let u_ps: Vec<Vector<N>> = if ctx.lagrangian {
            // The repulsion Q acts on the interior particles of a free-surface flow (eq. (42)).
            let (grad_c, d): (Vec<Vector<N>>, Vec<f64>) = match &ctx.surf {
                Some(s) => (
                    s.is_surface
                        .iter()
                        .enumerate()
                        .map(|(i, &fs)| if fs { grad_c[i] } else { grad_c_q[i] })
                        .collect(),
                    shifting::coefficients_free_surface(&relative_to_mean(&fl.v), h, dt),
                ),
                None => (grad_c, vec![shifting::coefficient_internal(h); n]),
            };
            let s = ctx
                .surf
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
        u_ps.into_iter()
            .enumerate()
            .map(|(i, u)| {
                if ctx.held.holds(i) {
                    Vector::<N>::zeros()
                } else {
                    u
                }
            })
            .collect()
    }

    /// Step 7, eq. (27): the new positions (Lagrangian frame), velocities `u_new` and
    /// conformations `conf`, the inlet's momentum `held_momentum`, then the plate contact.
    /// Returns the momentum each wall gave the fluid by the contact (in the walls' order) and
    /// the plate's by particle (empty without a plate).
    pub(super) fn advect(
        &self,
        st: &mut State<N>,
        ctx: &Context<N>,
        u_ps: &[Vector<N>],
        u_new: Vec<Vector<N>>,
        conf: Vec<Tensor<N>>,
        held_momentum: Vector<N>,
    ) -> (Vec<Vector<N>>, Vec<Vector<N>>) {
        let (dom, dt) = (self.p.domain, ctx.dt);
        let fl = &mut st.fluid;
        if ctx.lagrangian {
            fl.x[..ctx.n]
                .par_iter_mut()
                .zip(fl.v.par_iter().zip(u_new.par_iter().zip(u_ps.par_iter())))
                .for_each(|(x, (v, (u, ps)))| *x = dom.wrap(*x + (v + u + 2.0 * ps) * (0.5 * dt)));
        }
        if let Some(inl) = st.inflow.as_mut() {
            inl.momentum += held_momentum;
        }
        fl.v = u_new;
        if R::ELASTIC {
            fl.conf = conf;
        }
        let mut plate_contact = vec![Vector::<N>::zeros(); st.plate.map_or(0, |_| st.fluid.len())];
        let (contacts, on_plate, reflections) =
            keep_out_of_walls(&mut st.fluid, &st.walls, st.plate);
        for (i, m) in on_plate {
            plate_contact[i] += m;
        }
        st.wall_reflections += reflections;
        (contacts, plate_contact)
    }
}

/// Velocities relative to their mean (summed in index order): the speed King & Lind's shifting
/// coefficient (41) follows, made independent of the frame (module documentation).
fn relative_to_mean<const N: usize>(u: &[Vector<N>]) -> Vec<Vector<N>> {
    if u.is_empty() {
        return Vec::new();
    }
    let mean = u.iter().fold(Vector::<N>::zeros(), |a, v| a + v) / u.len() as f64;
    u.iter().map(|v| v - mean).collect()
}
