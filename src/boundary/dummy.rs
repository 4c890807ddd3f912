//! Adami, Hu & Adams 2012's dummy wall particles (J. Comput. Phys. 231, 7057-7075, section 2.3),
//! the wall model of the weakly compressible schemes on walls of any shape.
//!
//! Layers of particles fill the solid within the kernel support of its boundary, at the particle
//! spacing dx: rows below a straight wall (at d = -(k + 1/2) dx, on the plate's columns), rings
//! inside a cylinder or outside a circular tank (at radii R -+ (k + 1/2) dx, each ring divided
//! into the whole number of arcs nearest dx). They sit still in the wall's frame and take their
//! values from the fluid around them by Shepard interpolation, so nothing about the wall's
//! shape enters the values:
//! * velocity (eqs. 22-23): `u_w = 2 u_wall - sum_f u_f W_wf / sum_f W_wf`, so that the velocity
//!   interpolated at the wall is the wall's (no slip);
//! * stress (eq. 27, written for the total stress sigma = -p I + tau): `sigma_w = sum_f sigma_f
//!   W_wf / sum_f W_wf - ((g - a_wall) . sum_f rho_f r_wf W_wf / sum_f W_wf) I`, r_wf = x_w -
//!   x_f: the fluid's stress carried to the wall particle plus the hydrostatic pressure
//!   difference, so a fluid at rest under gravity feels its own hydrostatic pressure in the wall.
//!   The walls here move at constant velocity over a step, so a_wall = 0.
//!
//! Dummy particles keep the reference density rho0 (the schemes give every virtual particle
//! rho0 and the volume m / rho0); Adami's density from the wall pressure through the equation of
//! state changes the volume by O(p / (rho0 c^2)), the weakly compressible error itself.
//! A dummy particle with no fluid within reach takes the wall's velocity and zero stress.

use super::wall::Wall;
use super::Boundary;
use crate::kernel::Kernel;
use crate::neighbors::{CellGrid, Domain, NeighborList};
use crate::particles::Fluid;
use crate::{Mat2, Vec2};

/// Dummy wall particles of one wall (module documentation).
#[derive(Debug, Clone)]
pub struct DummyWall<K: Kernel> {
    kernel: K,
    domain: Domain,
    /// Particle spacing.
    dx: f64,
    /// Body force per unit mass (gravity).
    gravity: Vec2,
    /// Layers of particles: enough to fill the kernel support.
    layers: usize,
    /// The positions placed at the last [`Boundary::place`].
    x: Vec<Vec2>,
    /// Fluid neighbours of each dummy particle.
    list: NeighborList,
}

impl<K: Kernel> DummyWall<K> {
    pub fn new(kernel: K, domain: Domain, dx: f64, gravity: Vec2) -> Self {
        let layers = (kernel.radius() / dx).ceil() as usize;
        Self {
            kernel,
            domain,
            dx,
            gravity,
            layers,
            x: Vec::new(),
            list: NeighborList::default(),
        }
    }

    /// The positions of the dummy particles of `wall` (its columns built so far, for a plate).
    pub fn layout(&self, wall: &Wall) -> Vec<Vec2> {
        let dx = self.dx;
        let mut out = Vec::new();
        match wall {
            Wall::Straight(p) => {
                for c in 0..p.columns() {
                    let s = p.column_s(c);
                    for k in 0..self.layers {
                        out.push(p.point(s, -(k as f64 + 0.5) * dx));
                    }
                }
            }
            Wall::Circle(c) => {
                let b = c.ball;
                for k in 0..self.layers {
                    // Into the solid: inwards for a cylinder, outwards for a tank.
                    let r = b.radius - b.fluid.sign() * (k as f64 + 0.5) * dx;
                    if r <= 0.0 {
                        break;
                    }
                    let n = ((std::f64::consts::TAU * r / dx).round() as usize).max(1);
                    for j in 0..n {
                        let a =
                            std::f64::consts::TAU * (j as f64 + 0.5 * (k % 2) as f64) / n as f64;
                        out.push(b.centre + r * Vec2::new(a.cos(), a.sin()));
                    }
                }
            }
        }
        if self.domain.period_x.is_some() {
            out.iter_mut().for_each(|p| *p = self.domain.wrap(*p));
        }
        out
    }

    /// Shepard sums over the fluid neighbours of dummy particle `k`: sum W, and `f(j, W)` for
    /// every neighbour j with W > 0.
    fn shepard(&self, fluid: &Fluid, k: usize, mut f: impl FnMut(usize, f64, Vec2)) -> f64 {
        let xw = self.x[k];
        let r2max = self.kernel.radius().powi(2);
        let mut sw = 0.0;
        for &j in self.list.of(k) {
            let j = j as usize;
            let rwf = self.domain.delta(&xw, &fluid.x[j]);
            let r2 = rwf.norm_squared();
            if r2 < r2max {
                let w = self.kernel.w(r2.sqrt());
                sw += w;
                f(j, w, rwf);
            }
        }
        sw
    }
}

impl<K: Kernel> Boundary for DummyWall<K> {
    fn place(
        &mut self,
        wall: &mut Wall,
        fluid_x: &[Vec2],
        fluid_grid: &CellGrid,
        radius: f64,
        out: &mut Vec<Vec2>,
    ) {
        if let Some(p) = wall.plate_mut() {
            // Columns only where fluid comes near, as for Fang's and Ren's walls.
            p.cover_points(fluid_x, 3.0 * radius);
        }
        self.x = self.layout(wall);
        out.extend_from_slice(&self.x);
        self.list = NeighborList::build(fluid_grid, fluid_x, &self.x, radius, &self.domain);
    }

    fn fill_velocities(&self, wall: &Wall, fluid: &Fluid, out: &mut [Vec2]) {
        let uw = wall.wall_velocity();
        for (k, o) in out.iter_mut().enumerate() {
            let mut su = Vec2::zeros();
            let sw = self.shepard(fluid, k, |j, w, _| su += fluid.v[j] * w);
            *o = if sw > 0.0 { 2.0 * uw - su / sw } else { uw };
        }
    }

    fn fill_stresses(
        &self,
        _wall: &Wall,
        fluid: &Fluid,
        sigma: &[Mat2],
        _tau_p: &[Mat2],
        out: &mut [Mat2],
    ) {
        for (k, o) in out.iter_mut().enumerate() {
            let (mut ss, mut sr) = (Mat2::zeros(), Vec2::zeros());
            let sw = self.shepard(fluid, k, |j, w, rwf| {
                ss += sigma[j] * w;
                sr += rwf * (fluid.rho[j] * w);
            });
            *o = if sw > 0.0 {
                (ss - Mat2::identity() * self.gravity.dot(&sr)) / sw
            } else {
                Mat2::zeros()
            };
        }
    }

    fn positions(&self, wall: &Wall) -> Vec<Vec2> {
        self.layout(wall)
    }
}
