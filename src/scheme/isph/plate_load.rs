//! The plate's load by fluid particle under ISPH (`State::plate_load`, the drop's
//! `wall_pressure_NNN` / `wall_shear_NNN` bins), booked where each part of the walls' force is
//! computed, for a scene whose one wall is its plate (the drops):
//! * the predictor's and the projection's virtual pairs of particle i (`Books::wall_on_fluid`'s
//!   pair forces, row by row);
//! * its share of the implicit viscous solve's wall momentum: the virtual pairs' terms of the
//!   solved Laplacian, `theta m sum_{j virtual} coef_ij (u_i - u_j) / rho` at the solved
//!   velocities (before the free-surface traction's mean is removed: that uniform shift is not
//!   the wall's). The solve's wall momentum (`sum_i m (u_i - rhs_i) / dt`) equals their sum only
//!   to the solver's tolerance; the difference, the one part that cannot be split exactly, is
//!   spread over the particles in proportion to the size of their virtual-pair terms (all
//!   particles alike when none has one), so the entries still sum to the wall force. Measured
//!   on the Newtonian drop of tests/plate_load.rs (16 across, level and 30 degrees, 42 steps in
//!   contact): at most 8e-7 N/m, 1e-8 of the viscous wall force at the median, 5e-6 at most;
//! * its contact impulse over the step (`advect`).
//!
//! Each row is computed on its own and gathered by index, so the load is bitwise the same for
//! any thread count; the trajectory does not read it (the ISPH goldens stay bitwise). With more
//! than one wall, or no plate, the load is left empty (the bins read 0).

use super::{Context, Isph};
use crate::dim::{Const, Dim, Vector};
use crate::rheology::Rheology;
use crate::state::State;

/// The plate's force on each fluid particle as a step books it; empty when not booked.
#[derive(Debug, Default)]
pub(super) struct PlateBook<const N: usize> {
    /// Force of the plate on fluid particle i \[N/m\] (virtual pairs and viscous share).
    on_fluid: Vec<Vector<N>>,
}

impl<const N: usize> PlateBook<N> {
    /// Booked for a state whose one wall is its plate, with at least one fluid particle.
    pub fn of(st: &State<N>) -> Self {
        let on = st.walls.len() == 1 && st.plate == Some(0);
        Self {
            on_fluid: if on {
                vec![Vector::<N>::zeros(); st.fluid.len()]
            } else {
                Vec::new()
            },
        }
    }

    /// Whether the step books the load.
    #[inline]
    pub fn is_on(&self) -> bool {
        !self.on_fluid.is_empty()
    }

    /// Adds the force `f` of the plate on fluid particle `i` (nothing when not booked).
    #[inline]
    pub fn add(&mut self, i: usize, f: Vector<N>) {
        if let Some(e) = self.on_fluid.get_mut(i) {
            *e += f;
        }
    }

    /// Adds the implicit viscous solve's share: `terms` per particle (its virtual pairs' force)
    /// and `total` the solve's whole wall momentum over dt, the difference spread in proportion
    /// to |terms_i| (module documentation).
    pub fn add_viscous(&mut self, terms: &[Vector<N>], total: Vector<N>) {
        if !self.is_on() {
            return;
        }
        let sum = terms.iter().fold(Vector::<N>::zeros(), |a, t| a + t);
        let rest = total - sum;
        let weight: f64 = terms.iter().map(|t| t.norm()).sum();
        let n = self.on_fluid.len() as f64;
        for (e, t) in self.on_fluid.iter_mut().zip(terms) {
            let share = if weight > 0.0 {
                t.norm() / weight
            } else {
                1.0 / n
            };
            *e += t + rest * share;
        }
    }

    /// The load: the force of each particle on the plate over the step, `contact[i]` the
    /// momentum the plate's contact gave particle i, `dt` the step. Empty when not booked.
    pub fn into_load(self, contact: &[Vector<N>], dt: f64) -> Vec<Vector<N>> {
        self.on_fluid
            .iter()
            .zip(contact)
            .map(|(f, m)| -f - m / dt)
            .collect()
    }
}

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// Per fluid particle, the virtual pairs' terms of the implicit viscous solve at the
    /// solved velocities `u`: `theta m sum_{j virtual} coef_ij (u_i - u_j) / rho` with the
    /// no-slip continuation (corrections `visc_curv`) of `u` (as `split_viscous_force`).
    pub(super) fn viscous_wall_terms(
        &self,
        ctx: &Context<N>,
        coef: &[f64],
        theta: f64,
        visc_curv: &[Vector<N>],
        u: &[Vector<N>],
    ) -> Vec<Vector<N>> {
        let c = theta * ctx.mass / self.rho;
        self.virtual_viscous_sums(ctx, coef, visc_curv, u, 1, |_| 0)
            .into_iter()
            .map(|f| f[0] * c)
            .collect()
    }
}
