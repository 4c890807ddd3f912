//! The walls' virtual particles as the incompressible scheme reads them (King & Lind 2021
//! section III.C): each wall is a [`Boundary`] whose virtual particles each follow one fluid
//! particle ([`Boundary::parents`]), so their values are affine in their parents' and enter the
//! linear systems as ghosts: velocity no slip, `2 u_wall - u_parent`
//! ([`Boundary::wall_velocities`]), pressure Neumann plus the hydrostatic offset
//! `rho g . (r_m - r_i)` (`Isph::pressure_offsets`), polymer stress as the wall model fills it
//! ([`Boundary::fill_stresses`]; mirrors: the parent's). The scheme never asks for the model's
//! type: King & Lind's mirror particles ([`MirrorWall`]) are what `mirror_walls` builds, and
//! any model that names parents plugs in.
//!
//! In the closed periodic channel the continuation is second order: the virtual velocities
//! carry the wall curvature the odd continuation misses, and the virtual Phi the fitted
//! shear-stress slope ([`wall_profile`], which fits the profiles across the plate's normal: a
//! fully developed channel between straight walls). Across a curved wall in a closed cell (the
//! cylinder array) the virtual Phi carries the shear-stress slope fitted along the wall
//! ([`wall_profile::local_shear_stress_corrections`]); the virtual velocities keep the plain
//! odd continuation (the curvature fitted along the cylinder made the drag worse: see
//! `validation/cylinder_array/README.md`).

use super::{Context, Isph};
use crate::boundary::mirror::MirrorWall;
use crate::boundary::wall::Wall;
use crate::boundary::wall_profile;
use crate::boundary::Boundary;
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::geometry::Shape;
use crate::kernel::Kernel;
use crate::neighbors::{Domain, Grid};
use crate::particles::Fluid;
use crate::rheology::Rheology;
use std::ops::Range;

/// King & Lind's mirror particles for every plate of `plates`, reaching `reach` (King's code:
/// the kernel support).
pub(super) fn mirror_walls<const N: usize>(
    plates: &[Wall<N>],
    reach: f64,
) -> Vec<Box<dyn Boundary<N>>> {
    plates
        .iter()
        .map(|_| Box::new(MirrorWall::new(reach)) as Box<dyn Boundary<N>>)
        .collect()
}

/// The virtual particles of every wall for one step, in the order of the lists (after the
/// fluid particles, wall by wall).
#[derive(Debug, Default)]
pub(super) struct Virtual<const N: usize = 2> {
    /// The fluid particle each one follows.
    pub parent: Vec<u32>,
    /// The wall's velocity where each one is continued across.
    pub u_wall: Vec<Vector<N>>,
    /// Each one's volume relative to its parent's: the Jacobian of the reflection
    /// ([`Shape::reflection_jacobian`]; exactly 1 across a straight wall). Across a curved
    /// wall the reflection across the local tangent is not area-preserving: behind a concave
    /// wall (a circular tank) the images spread out by `(2R - r) / r`, behind a convex one (a
    /// cylinder) they crowd. With the parent's volume they under- or over-fill the kernel
    /// support, and the positive-form pressure gradient `sum_j (p_i + p_j) grad W_ij V_j` of
    /// the projection keeps `2 p_i grad C_i`: measured on a tank of radius 20 dx at rest with
    /// the exact hydrostatic pressure (zero at the centre), a residual acceleration of 1.16 g
    /// on the particles dx / 2 from the wall, 0.06 g with the ratio (test
    /// `isph_mirrors_hold_a_circular_tank_at_rest`).
    pub volume: Vec<f64>,
    /// Whether each wall (in the state's order) is straight.
    pub straight: Vec<bool>,
    /// Each wall's virtual particles as a range of the above (walls in the state's order).
    pub ranges: Vec<Range<usize>>,
}

impl<const N: usize> Virtual<N> {
    /// Place the virtual particles of every wall model `walls` of the plates `plates` for the
    /// fluid at `xs`, appending their positions to `all_x` (which holds `xs` already); `radius`
    /// is the search radius. A model without parents is refused.
    pub fn place(
        walls: &mut [Box<dyn Boundary<N>>],
        plates: &mut [Wall<N>],
        xs: &[Vector<N>],
        radius: f64,
        dom: &Domain,
        all_x: &mut Vec<Vector<N>>,
    ) -> Result<Self, String> {
        let mut v = Self::default();
        let fluid_grid = Grid::<N>::build(xs, radius, dom);
        for (wall, plate) in walls.iter_mut().zip(plates.iter_mut()) {
            let before = all_x.len();
            wall.place(plate, xs, &fluid_grid, radius, all_x);
            // Every virtual particle follows one fluid parent: its values are affine in the
            // parent's in the linear systems.
            if wall.parents().len() != all_x.len() - before {
                return Err(
                    "ISPH needs a wall model whose virtual particles each follow one \
                            fluid particle (mirror particles)"
                        .into(),
                );
            }
            let start = v.parent.len();
            v.parent.extend_from_slice(wall.parents());
            v.volume.extend(
                wall.parents()
                    .iter()
                    .map(|&i| plate.reflection_jacobian(&xs[i as usize])),
            );
            v.ranges.push(start..v.parent.len());
            v.straight.push(plate.is_straight());
            wall.wall_velocities(plate, &mut v.u_wall);
        }
        Ok(v)
    }

    /// The wall (index into the state's walls) of virtual particle `k`.
    #[inline]
    pub fn wall_of(&self, k: usize) -> usize {
        self.ranges.partition_point(|r| r.end <= k)
    }

    /// Number of virtual particles.
    pub fn len(&self) -> usize {
        self.parent.len()
    }

    /// A fluid velocity field `u` extended over the virtual particles: King & Lind's no-slip
    /// continuation `2 u_wall - u_parent` plus the correction `curv` of each (the closed
    /// channel's wall curvature; zeros with a free surface).
    pub fn extend_velocity(&self, u: &[Vector<N>], curv: &[Vector<N>]) -> Vec<Vector<N>> {
        let mut out = Vec::with_capacity(u.len() + self.parent.len());
        out.extend_from_slice(u);
        out.extend(
            self.parent
                .iter()
                .zip(&self.u_wall)
                .zip(curv)
                .map(|((&i, uw), c)| 2.0 * uw - u[i as usize] + c),
        );
        out
    }

    /// Closed channel: per virtual particle, the wall curvature of `u` (fluid at `xs`) that the
    /// odd continuation misses ([`wall_profile::velocity_corrections`]).
    pub fn velocity_curvature(
        &self,
        plates: &[Wall<N>],
        xs: &[Vector<N>],
        u: &[Vector<N>],
        radius: f64,
    ) -> Vec<Vector<N>> {
        let mut c = Vec::with_capacity(self.len());
        for (wall, r) in plates.iter().zip(&self.ranges) {
            match wall.plate() {
                Some(plate) => c.extend(wall_profile::velocity_corrections(
                    plate,
                    xs,
                    &self.parent[r.clone()],
                    u,
                    radius,
                )),
                // The profile fits are across a straight wall (a fully developed channel); a
                // curved wall's mirrors take the plain odd continuation.
                None => c.extend(std::iter::repeat_n(Vector::<N>::zeros(), r.len())),
            }
        }
        c
    }
}

impl<R: Rheology, const N: usize> Isph<R, N>
where
    Const<N>: Dim,
{
    /// The virtual particles' Phi from the fluid's `phi`, as each wall model continues it across
    /// its wall (mirrors: the parent's); in a closed cell plus the fitted shear-stress slope,
    /// over the whole wall for a straight one ([`wall_profile::shear_stress_corrections`]) and
    /// along the wall for a curved one ([`wall_profile::local_shear_stress_corrections`]).
    pub(super) fn virtual_stresses(
        &self,
        ctx: &Context<N>,
        plates: &[Wall<N>],
        fluid: &Fluid<N>,
        phi: &[Tensor<N>],
    ) -> Vec<Tensor<N>> {
        let virt = &ctx.virt;
        let mut pm = vec![Tensor::<N>::zeros(); virt.len()];
        for ((wall, plate), r) in self.walls.iter().zip(plates).zip(&virt.ranges) {
            wall.fill_stresses(plate, fluid, &[], phi, &mut pm[r.clone()]);
        }
        if !self.free_surface {
            let (radius, par) = (self.kernel.radius(), &virt.parent);
            for (wall, r) in plates.iter().zip(&virt.ranges) {
                let d = match wall.plate() {
                    Some(plate) => wall_profile::shear_stress_corrections(
                        plate,
                        &ctx.xs,
                        &par[r.clone()],
                        phi,
                        radius,
                    ),
                    // A curved wall: the slope fitted along it, over half the reach.
                    None => wall_profile::local_shear_stress_corrections(
                        wall,
                        &ctx.xs,
                        &par[r.clone()],
                        phi,
                        radius,
                        0.5 * radius,
                    ),
                };
                for (p, dp) in pm[r.clone()].iter_mut().zip(d) {
                    *p += dp;
                }
            }
        }
        pm
    }

    /// Closed channel: per virtual particle, the velocity correction of the viscous term's
    /// continuation, the wall curvature that the wall's momentum balance prescribes (no
    /// acceleration at a no-slip wall): `mu_w u''_w = -(rho g.t + dPhi_tn/dn)`, mu_w the mean
    /// viscosity `mu` of the wall's parents, Phi the fluid's `phi` (empty: inelastic).
    pub(super) fn viscous_curvature(
        &self,
        ctx: &Context<N>,
        plates: &[Wall<N>],
        phi: &[Tensor<N>],
        mu: &[f64],
    ) -> Vec<Vector<N>> {
        let (rho, g, radius) = (self.rho, self.p.gravity, self.kernel.radius());
        let virt = &ctx.virt;
        let mut c = Vec::with_capacity(virt.len());
        for (wall, r) in plates.iter().zip(&virt.ranges) {
            let par = &virt.parent[r.clone()];
            // Straight walls only (see `velocity_curvature`).
            let Some(plate) = wall.plate() else {
                c.extend(std::iter::repeat_n(Vector::<N>::zeros(), par.len()));
                continue;
            };
            let slope = if R::ELASTIC {
                wall_profile::shear_stress_slope(plate, &ctx.xs, par, phi, radius)
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
            c.extend(wall_profile::curvature_corrections(
                plate, &ctx.xs, par, curv,
            ));
        }
        c
    }

    /// The hydrostatic offsets `rho g . (r_m - r_i)` of the virtual particles' pressures (King's
    /// newer code): a fluid at rest holds its hydrostatic pressure across the wall. Zeros in a
    /// closed cell, whose body force is in the predictor (`predictor`), not in the corrector:
    /// the pressure there has no hydrostatic part to continue, and the offsets would impose
    /// `dp/dn = rho g . n` on the wall. Across the channel's walls (g along the wall) they are
    /// exactly zero anyway; across a cylinder they are not: measured on the cylinder array
    /// (16 across, incremental pressure correction), p accumulated the offset every step and
    /// the flow ran backwards through the cylinder.
    pub(super) fn pressure_offsets(&self, ctx: &Context<N>) -> Vec<f64> {
        let g = if self.free_surface {
            self.p.gravity
        } else {
            Vector::<N>::zeros()
        };
        let (rho, dom, n) = (self.rho, self.p.domain, ctx.n);
        ctx.virt
            .parent
            .iter()
            .enumerate()
            .map(|(m, &i)| rho * g.dot(&dom.delta(&self.all_x[n + m], &ctx.xs[i as usize])))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::ghost::{GhostWall, WallModel};
    use crate::boundary::plate::Plate;
    use crate::geometry::Shape;
    use crate::kernel::{CubicSpline, QuinticSpline};
    use crate::Vec2;

    /// A lattice of fluid above a plate inclined at 30 degrees that moves away from the fluid.
    fn layer(dx: f64) -> (Vec<Wall>, Vec<Vec2>) {
        let mut plate = Plate::new(30.0, dx);
        plate.velocity = 0.2;
        let xs = (0..20 * 8)
            .map(|q| plate.point(((q % 20) as f64 - 9.5) * dx, ((q / 20) as f64 + 0.5) * dx))
            .collect();
        (vec![plate.into()], xs)
    }

    /// `Virtual::place` of `walls` for the fluid `xs`, with the positions of fluid then virtual
    /// particles.
    fn place(
        walls: &mut [Box<dyn Boundary>],
        plates: &mut [Wall],
        xs: &[Vec2],
        radius: f64,
    ) -> (Result<Virtual, String>, Vec<Vec2>) {
        let mut all_x = xs.to_vec();
        let virt = Virtual::place(walls, plates, xs, radius, &Domain::OPEN, &mut all_x);
        (virt, all_x)
    }

    /// Through the trait alone, the mirror wall gives every virtual particle a parent and the
    /// plate's velocity, and the extended velocity is no slip: a particle and its mirror
    /// average to the wall's velocity (plus the correction given).
    #[test]
    fn mirror_walls_extend_a_velocity_as_no_slip() {
        let dx = 0.01;
        let k = QuinticSpline::new(1.3 * dx);
        let (mut plates, xs) = layer(dx);
        let mut walls = mirror_walls(&plates, k.radius());
        let (virt, all_x) = place(&mut walls, &mut plates, &xs, k.radius());
        let virt = virt.unwrap();
        assert!(virt.len() > 0 && all_x.len() == xs.len() + virt.len());
        assert_eq!(virt.ranges, vec![0..virt.len()]);
        let uw = plates[0].wall_velocity();
        assert!(virt.u_wall.iter().all(|u| *u == uw));
        let u: Vec<Vec2> = xs.iter().map(|x| Vec2::new(x.y, -2.0 * x.x)).collect();
        let curv: Vec<Vec2> = (0..virt.len()).map(|m| Vec2::new(m as f64, 1.0)).collect();
        let ext = virt.extend_velocity(&u, &curv);
        assert_eq!(&ext[..xs.len()], &u[..]);
        for (m, &i) in virt.parent.iter().enumerate() {
            let i = i as usize;
            // The mirror is the parent reflected across the plate.
            let (xm, xi) = (all_x[xs.len() + m], xs[i]);
            assert!(
                (plates[0].signed_distance(&xm) + plates[0].signed_distance(&xi)).abs() < 1e-15
            );
            let mean = 0.5 * (ext[xs.len() + m] - curv[m] + u[i]);
            assert!((mean - uw).norm() < 1e-12);
        }
    }

    /// A wall model whose virtual particles interpolate several fluid particles (Fang's) has
    /// no parents to link in the linear systems: ISPH refuses it instead of misreading it.
    #[test]
    fn a_wall_model_without_parents_is_refused() {
        let dx = 0.01;
        let k = CubicSpline::new(1.5 * dx);
        let (mut plates, xs) = layer(dx);
        let mut walls: Vec<Box<dyn Boundary>> = vec![Box::new(GhostWall::new(
            k,
            WallModel::Fang,
            Domain::OPEN,
            dx,
        ))];
        let (placed, _) = place(&mut walls, &mut plates, &xs, k.radius());
        assert!(placed.unwrap_err().contains("mirror particles"));
    }
}
