//! Fang 2006's boundary + image particles (section 3.3, eqs. 46-48) and Ren 2015's wall + ghost
//! particles (section 3.5, eqs. 23a-23b) on a straight plate.
//!
//! Both papers put one row of particles on the wall and image/ghost rows below it, at rest (or
//! moving with the wall) and at the reference density; a column's wall particle and its interior
//! point P (Fang) or F (Ren) at d = +dx take values interpolated from nearby fluid particles, and
//! the particles below the wall extrapolate linearly, L_G = L_F + (1 + d_G/d_F)(L_W - L_F)
//! (Fang eqs. 47-48, Ren eq. 23b), for the velocity (L_W = the wall's velocity, no slip) and the
//! stress (L_W from the wall particle). They differ in the interpolation weights ([`WallModel`]).
//! The number of image rows covers the kernel's support (three for the cubic spline at
//! h = 1.5 dx, as in both papers).

use super::wall::Wall;
use super::Boundary;
use crate::dim::Vector;
use crate::geometry::Shape;
use crate::kernel::Kernel;
use crate::neighbors::{CellGrid, Domain, NeighborList};
use crate::particles::Fluid;
use crate::{Mat2, Vec2};
use rayon::prelude::*;

/// Smallest number of wall columns per parallel task.
const MIN_COLUMNS: usize = 16;

/// How the virtual particles of a plate take their values from the fluid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallModel {
    /// Fang 2006 eq. (46): normalised SPH interpolation, weights (m_j/rho_j) W_ij.
    Fang,
    /// Ren 2015 eq. (23a): weights 2h - r_ij.
    Ren,
}

impl WallModel {
    /// Normalised interpolation weights of the fluid neighbours of point `q` (fluid particles
    /// only, as both papers say): calls `f(j, w_j)` with sum_j w_j = 1, and returns false when no
    /// fluid is within reach.
    #[inline]
    pub fn interpolate<K: Kernel>(
        self,
        kernel: &K,
        dom: &Domain,
        fluid: &Fluid,
        list: &[u32],
        q: &Vec2,
        mut f: impl FnMut(usize, f64),
    ) -> bool {
        let radius = kernel.radius();
        let r2max = radius * radius;
        let weight = |j: usize, r2: f64| match self {
            WallModel::Fang => fluid.mass / fluid.rho[j] * kernel.w(r2.sqrt()),
            WallModel::Ren => radius - r2.sqrt(),
        };
        let mut den = 0.0;
        for &j in list {
            let j = j as usize;
            let r2 = dom.delta(&fluid.x[j], q).norm_squared();
            if r2 < r2max {
                den += weight(j, r2);
            }
        }
        if den <= 0.0 {
            return false;
        }
        let inv = 1.0 / den;
        for &j in list {
            let j = j as usize;
            let r2 = dom.delta(&fluid.x[j], q).norm_squared();
            if r2 < r2max {
                f(j, weight(j, r2) * inv);
            }
        }
        true
    }
}

/// Extrapolation factor 1 + d_I/d_P of image/ghost row m (d_I = m dx, d_P = dx; Fang eqs. 47-48,
/// Ren eq. 23b with d_F = d0).
#[inline]
fn image_factor(row: usize) -> f64 {
    1.0 + row as f64
}

/// A plate's wall and image/ghost particles for kernel `K`.
#[derive(Debug, Clone)]
pub struct GhostWall<K: Kernel> {
    kernel: K,
    model: WallModel,
    domain: Domain,
    /// Virtual particles per column: the wall particle, then the image rows.
    per_column: usize,
    /// Fluid neighbours of each column's wall particle (2c) and interior point (2c + 1).
    clist: NeighborList,
}

impl<K: Kernel> GhostWall<K> {
    /// A wall model for particle spacing `dx`, with enough image rows to fill the kernel's
    /// support below the wall.
    pub fn new(kernel: K, model: WallModel, domain: Domain, dx: f64) -> Self {
        let rows = (kernel.radius() / dx - 1e-9).ceil().max(1.0) as usize;
        Self {
            kernel,
            model,
            domain,
            per_column: 1 + rows,
            clist: NeighborList::default(),
        }
    }

    /// Interpolate at `q` by the model's weights.
    #[inline]
    fn interpolate(
        &self,
        fluid: &Fluid,
        list: &[u32],
        q: &Vec2,
        f: impl FnMut(usize, f64),
    ) -> bool {
        self.model
            .interpolate(&self.kernel, &self.domain, fluid, list, q, f)
    }

    /// Number of image (ghost) rows below the wall particle.
    pub fn image_rows(&self) -> usize {
        self.per_column - 1
    }
}

impl<K: Kernel> Boundary for GhostWall<K> {
    fn place(
        &mut self,
        wall: &mut Wall,
        fluid_x: &[Vec2],
        fluid_grid: &CellGrid,
        radius: f64,
        out: &mut Vec<Vec2>,
    ) {
        let whole = wall;
        let wall = whole.straight_mut();
        wall.cover_points(fluid_x, 3.0 * radius);
        let dom = self.domain;
        out.extend(self.positions(whole));
        let wall = whole.straight();
        let mut queries = Vec::with_capacity(2 * wall.columns());
        for c in 0..wall.columns() {
            queries.push(dom.wrap(wall.point(wall.column_s(c), 0.0)));
            queries.push(dom.wrap(wall.interior_point(c)));
        }
        self.clist = NeighborList::build(fluid_grid, fluid_x, &queries, radius, &self.domain);
    }

    fn fill_velocities(&self, wall: &Wall, fluid: &Fluid, out: &mut [Vec2]) {
        let wall = wall.straight();
        let clist = &self.clist;
        let vw = wall.wall_velocity();
        out.par_chunks_mut(self.per_column)
            .with_min_len(MIN_COLUMNS)
            .enumerate()
            .for_each(|(c, out)| {
                let q = wall.interior_point(c);
                let mut vp = Vec2::zeros();
                self.interpolate(fluid, clist.of(2 * c + 1), &q, |j, w| vp += fluid.v[j] * w);
                out[0] = vw; // the wall particle moves with the wall
                for (row, o) in out.iter_mut().enumerate().skip(1) {
                    // Fang eq. (47), Ren eq. (23b): v_P + (1 + d_I/d_P)(v_W - v_P).
                    *o = vp - (vp - vw) * image_factor(row);
                }
            });
    }

    fn fill_stresses(
        &self,
        wall: &Wall,
        fluid: &Fluid,
        sigma: &[Mat2],
        tau_p: &[Mat2],
        out: &mut [Mat2],
    ) {
        let wall = wall.straight();
        let n = wall.n;
        let nn = n * n.transpose();
        let elastic = !tau_p.is_empty();
        let clist = &self.clist;
        out.par_chunks_mut(self.per_column)
            .with_min_len(MIN_COLUMNS)
            .enumerate()
            .for_each(|(c, sig)| {
                let qb = wall.point(wall.column_s(c), 0.0);
                let mut sb = Mat2::zeros();
                let mut snn = 0.0;
                self.interpolate(fluid, clist.of(2 * c), &qb, |j, w| {
                    sb += sigma[j] * w;
                    if elastic {
                        snn += n.dot(&(tau_p[j] * n)) * w;
                    }
                });
                // Fang 3.3: the wall-normal component of the elastic stress is zero on the wall
                // (Ren's Cross fluid has none; kept for elastic models under both wall models).
                sb -= nn * snn;
                let qp = wall.interior_point(c);
                let mut sp = Mat2::zeros();
                if !self.interpolate(fluid, clist.of(2 * c + 1), &qp, |j, w| sp += sigma[j] * w) {
                    sp = sb;
                }
                sig[0] = sb;
                for (row, s) in sig.iter_mut().enumerate().skip(1) {
                    *s = sp + (sb - sp) * image_factor(row); // Fang (48), Ren (23b)
                }
            });
    }

    /// Inside the periodic box, if the domain has one.
    fn positions(&self, wall: &Wall) -> Vec<Vec2> {
        let wall = wall.straight();
        let mut x = wall.virtual_positions(self.per_column);
        if self.domain.period_x.is_some() {
            x.iter_mut().for_each(|p| *p = self.domain.wrap(*p));
        }
        x
    }
}

/// A wall's impenetrability, kinematically: a fluid particle found inside the solid (signed
/// distance d < 0) is mirrored back across the wall's local tangent (for a plate, across the
/// plate line), and the part of its velocity (relative to the wall) that runs into the wall
/// along the normal there is removed (an inelastic contact). Returns the momentum the wall gave
/// the fluid this way \[kg m/s per m\] and the number of particles put back; `each(i, m)` is told
/// the momentum m particle i received. The particles inside are found on all threads (rarely
/// any: the test is the work); those are then put back one by one in particle order, so the sum
/// is the same on any number of threads. Used by Fang's scheme (see [`crate::scheme::wcsph`]),
/// Ren's ([`crate::scheme::pdri`]) and the incompressible one.
pub fn keep_out_of_wall<const N: usize>(
    fl: &mut Fluid<N>,
    wall: &Wall<N>,
    mut each: impl FnMut(usize, Vector<N>),
) -> (Vector<N>, u64) {
    let mut momentum = Vector::zeros();
    let mut count = 0;
    let uw = wall.wall_velocity();
    let inside: Vec<usize> =
        fl.x.par_iter()
            .with_min_len(1024)
            .enumerate()
            .filter(|(_, x)| wall.signed_distance(x) < 0.0)
            .map(|(i, _)| i)
            .collect();
    for i in inside {
        let (x, v) = (&mut fl.x[i], &mut fl.v[i]);
        let n = wall.normal(x);
        *x = wall.reflect(x);
        let vn = v.dot(&n) - uw.dot(&n);
        if vn < 0.0 {
            *v -= n * vn;
            momentum -= n * (vn * fl.mass);
            each(i, -n * (vn * fl.mass));
        }
        count += 1;
    }
    (momentum, count)
}

/// [`keep_out_of_wall`] for every wall in order: the momentum each wall gave the fluid (in wall
/// order), the momentum each particle put back by the plate wall `plate` received (in the order
/// they were put back) and the number of particles put back. The one contact step of all three
/// schemes; each books the momenta into its own wall forces and plate load.
#[allow(clippy::type_complexity)]
pub fn keep_out_of_walls<const N: usize>(
    fl: &mut Fluid<N>,
    walls: &[Wall<N>],
    plate: Option<usize>,
) -> (Vec<Vector<N>>, Vec<(usize, Vector<N>)>, u64) {
    let mut per_wall = Vec::with_capacity(walls.len());
    let mut on_plate = Vec::new();
    let mut count = 0;
    for (k, wall) in walls.iter().enumerate() {
        let own = plate == Some(k);
        let (m, reflections) = keep_out_of_wall(fl, wall, |i, m| {
            if own {
                on_plate.push((i, m));
            }
        });
        per_wall.push(m);
        count += reflections;
    }
    (per_wall, on_plate, count)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::plate::Plate;

    #[test]
    fn particles_below_the_plate_are_mirrored_and_stopped() {
        // A 30 degree plate; one particle above it, one below moving into it, one below moving
        // away from it.
        let pl = Plate::new(30.0, 0.01);
        let mut fl = Fluid {
            mass: 0.1,
            x: vec![
                pl.point(0.0, 0.004),
                pl.point(0.01, -0.003),
                pl.point(0.02, -0.001),
            ],
            v: vec![pl.t - pl.n, pl.t * 2.0 - pl.n * 3.0, pl.t + pl.n * 0.5],
            rho: vec![1000.0; 3],
            ..Default::default()
        };
        let before = fl.clone();
        let (momentum, count) = keep_out_of_wall(&mut fl, &Wall::from(pl.clone()), |_, _| {});
        assert_eq!(count, 2);
        assert_eq!((fl.x[0], fl.v[0]), (before.x[0], before.v[0]));
        assert!((pl.d(&fl.x[1]) - 0.003).abs() < 1e-15 && (pl.s(&fl.x[1]) - 0.01).abs() < 1e-15);
        assert!((pl.d(&fl.x[2]) - 0.001).abs() < 1e-15);
        // Into the plate: the normal velocity is removed, the tangential one kept.
        assert!(fl.v[1].dot(&pl.n).abs() < 1e-15 && (fl.v[1].dot(&pl.t) - 2.0).abs() < 1e-14);
        assert_eq!(fl.v[2], before.v[2]);
        // The momentum handed to the fluid is what its velocities gained.
        let gained = (fl.v[1] - before.v[1]) * fl.mass;
        assert!((momentum - gained).norm() < 1e-15 && (momentum - pl.n * 0.3).norm() < 1e-14);
    }

    #[test]
    fn cubic_spline_at_1_5_dx_gets_three_image_rows() {
        let dx = 0.01;
        let w = GhostWall::new(
            crate::kernel::CubicSpline::new(1.5 * dx),
            WallModel::Fang,
            Domain::OPEN,
            dx,
        );
        assert_eq!(w.image_rows(), 3);
        let w = GhostWall::new(
            crate::kernel::QuinticSpline::new(1.3 * dx),
            WallModel::Ren,
            Domain::OPEN,
            dx,
        );
        assert_eq!(w.image_rows(), 4);
    }
}
