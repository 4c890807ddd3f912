//! Adami, Hu & Adams 2012's dummy wall particles (J. Comput. Phys. 231, 7057-7075, section 2.3),
//! the wall model of the weakly compressible schemes on walls of any shape.
//!
//! Layers of particles fill the solid within the kernel support of its boundary, at the particle
//! spacing dx: rows below a straight wall (at d = -(k + 1/2) dx, on the plate's columns), rings
//! inside a cylinder or outside a circular tank (at radii R -+ (k + 1/2) dx, each ring divided
//! into the whole number of arcs nearest dx). They sit still in the wall's frame and take their
//! values from the fluid around them by Shepard interpolation, so nothing about the wall's
//! shape enters the values. A plate's layout covers the fluid's extent with three search radii
//! to spare; of it only the particles some fluid particle can reach before the next placement
//! are kept (within the search radius plus one kernel radius of the fluid), which leaves every
//! result bitwise the same: under a spread drop the plate's layout is a square around a round
//! footprint, and before the impact the drop is far from all of it.
//!
//! The values:
//! * velocity (eqs. 22-23): `u_w = 2 u_wall - sum_f u_f W_wf / sum_f W_wf`, so that the velocity
//!   interpolated at the wall is the wall's (no slip). It enters the velocity gradient, hence
//!   the viscous and polymer stresses; the continuity equation takes the wall's own velocity
//!   `u_wall` ([`Boundary::continuity_at_wall_velocity`]), as in Adami et al. 2012, where the
//!   extrapolation serves the viscous forces only. The extrapolated velocity mirrors the
//!   tangential velocity of the fluid next to the wall: where that varies along the wall (a
//!   drop or a jet's heap spreading from the axis), its divergence read across the wall is a
//!   false compression rate of the first fluid rows (+0.5 rho G in the first row of the
//!   stagnation flow u = (G x, -G y) on a plate at y = 0, tests/walls.rs), which the density
//!   accumulates over a long run;
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
use crate::dim::{Const, Tensor, Vector};
use crate::kernel::Kernel;
use crate::neighbors::{Domain, Grid, NeighborList};
use crate::particles::Fluid;
use crate::Vec2;
use rayon::prelude::*;

/// Dummy particles per task of the parallel fills: each costs a Shepard sum over its fluid
/// neighbours, a few hundred flops, so a task of this many outweighs its scheduling.
const MIN_TASK: usize = 256;

/// Where a dimension puts the dummy particles of a wall: `layers` layers at the spacing `dx`
/// inside the solid. Along a plate the layers sit on the plate's columns (s = k dx) and, in 3D,
/// on rows along the plate's second tangent `lateral` covers; a circle or sphere gets shells.
pub trait DummyLayout<const N: usize> {
    /// The dummy particles of `wall` (module documentation), `lateral` the rows along a
    /// plate's second tangent (ignored in 2D).
    fn layout(wall: &Wall<N>, layers: usize, dx: f64, lateral: &Lateral) -> Vec<Vector<N>>;
}

/// The rows a plate's dummy particles cover along its second tangent (3D): `l_min..=l_max`
/// at offsets l dx from the plate's origin, rebuilt at every [`Boundary::place`] to cover the
/// fluid (one period where the domain is periodic along that tangent).
#[derive(Debug, Clone, Copy, Default)]
pub struct Lateral {
    l_min: i64,
    l_max: i64,
}

impl DummyLayout<2> for Const<2> {
    fn layout(wall: &Wall, layers: usize, dx: f64, _: &Lateral) -> Vec<Vec2> {
        let mut out = Vec::new();
        match wall {
            Wall::Straight(p) => {
                for c in 0..p.columns() {
                    let s = p.column_s(c);
                    for k in 0..layers {
                        out.push(p.point(s, -(k as f64 + 0.5) * dx));
                    }
                }
            }
            Wall::Circle(c) => {
                let b = c.ball;
                for k in 0..layers {
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
        out
    }
}

impl DummyLayout<3> for Const<3> {
    /// On a plane: the columns along the downhill tangent t times the rows along b = n x t.
    /// In a sphere's shells: the points of a Fibonacci lattice, about dx apart.
    fn layout(wall: &Wall<3>, layers: usize, dx: f64, lateral: &Lateral) -> Vec<Vector<3>> {
        let mut out = Vec::new();
        match wall {
            Wall::Straight(p) => {
                let b = p.n.cross(&p.t);
                for c in 0..p.columns() {
                    let s = p.column_s(c);
                    for l in lateral.l_min..=lateral.l_max {
                        for k in 0..layers {
                            out.push(p.point(s, -(k as f64 + 0.5) * dx) + b * (l as f64 * dx));
                        }
                    }
                }
            }
            Wall::Circle(c) => {
                let ball = c.ball;
                let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
                for k in 0..layers {
                    let r = ball.radius - ball.fluid.sign() * (k as f64 + 0.5) * dx;
                    if r <= 0.0 {
                        break;
                    }
                    let n =
                        ((4.0 * std::f64::consts::PI * r * r / (dx * dx)).round() as usize).max(1);
                    for j in 0..n {
                        let z = 1.0 - (2.0 * j as f64 + 1.0) / n as f64;
                        let rho = (1.0 - z * z).sqrt();
                        let a = golden * j as f64;
                        out.push(
                            ball.centre + r * Vector::<3>::new(rho * a.cos(), rho * a.sin(), z),
                        );
                    }
                }
            }
        }
        out
    }
}

impl Lateral {
    /// The rows along plate `wall`'s second tangent b (3D) that cover the points `x` with
    /// `margin` to spare, or one period of `domain` where b is a periodic axis; none in 2D.
    fn covering<const N: usize>(
        wall: &Wall<N>,
        x: &[Vector<N>],
        margin: f64,
        dx: f64,
        domain: &Domain,
    ) -> Self {
        let Some(p) = wall.plate().filter(|_| N == 3) else {
            return Self::default();
        };
        // b = n x t, written out for N = 3.
        let b = Vector::<N>::from_fn(|a, _| {
            let (i, j) = ((a + 1) % 3, (a + 2) % 3);
            p.n[i] * p.t[j] - p.n[j] * p.t[i]
        });
        // b is an axis to round-off (n x t of a plate tilted about y is (0, cos^2 + sin^2, 0)).
        if let Some(l) = (0..N)
            .find(|&a| (b[a].abs() - 1.0).abs() < 1e-12)
            .and_then(|a| domain.period(a))
        {
            return Self {
                l_min: 0,
                l_max: (l / dx).round() as i64 - 1,
            };
        }
        let (lo, hi) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| {
                let s = (q - p.origin).dot(&b);
                (lo.min(s), hi.max(s))
            });
        if !lo.is_finite() {
            return Self::default();
        }
        Self {
            l_min: ((lo - margin) / dx).floor() as i64,
            l_max: ((hi + margin) / dx).ceil() as i64,
        }
    }
}

/// Dummy wall particles of one wall (module documentation), in N dimensions.
#[derive(Debug, Clone)]
pub struct DummyWall<K: Kernel<N>, const N: usize = 2> {
    kernel: K,
    domain: Domain,
    /// Particle spacing.
    dx: f64,
    /// Body force per unit mass (gravity).
    gravity: Vector<N>,
    /// Layers of particles: enough to fill the kernel support.
    layers: usize,
    /// A plate's rows along its second tangent (3D), as of the last [`Boundary::place`].
    lateral: Lateral,
    /// Which points of the whole layout were kept at the last [`Boundary::place`] (ascending
    /// indices into [`DummyWall::layout`]): those a fluid particle can reach before the next
    /// placement ([`DummyWall::keep_reachable`]).
    kept: Vec<u32>,
    /// The positions placed at the last [`Boundary::place`].
    x: Vec<Vector<N>>,
    /// The wall's displacement along -n then: a plate that moved since carries its dummy
    /// particles with it, and they interpolate the fluid where they are now.
    placed_at: f64,
    /// Fluid neighbours of each dummy particle.
    list: NeighborList,
}

impl<K: Kernel<N>, const N: usize> DummyWall<K, N>
where
    Const<N>: DummyLayout<N>,
{
    pub fn new(kernel: K, domain: Domain, dx: f64, gravity: Vector<N>) -> Self {
        let layers = (kernel.radius() / dx).ceil() as usize;
        Self {
            kernel,
            domain,
            dx,
            gravity,
            layers,
            lateral: Lateral::default(),
            kept: Vec::new(),
            x: Vec::new(),
            placed_at: 0.0,
            list: NeighborList::default(),
        }
    }

    /// The positions of the dummy particles of `wall` (its columns built so far, for a plate),
    /// inside the periodic box if the domain has one.
    pub fn layout(&self, wall: &Wall<N>) -> Vec<Vector<N>> {
        let mut out = Const::<N>::layout(wall, self.layers, self.dx, &self.lateral);
        if self.domain.is_periodic() {
            out.iter_mut().for_each(|p| *p = self.domain.wrap(*p));
        }
        out
    }

    /// The points of the whole layout of `wall` kept at the last [`Boundary::place`].
    fn kept_layout(&self, wall: &Wall<N>) -> Vec<Vector<N>> {
        let all = self.layout(wall);
        self.kept.iter().map(|&k| all[k as usize]).collect()
    }

    /// The indices of the points of `all` within `reach` of some fluid particle at `fluid_x`,
    /// ascending. The others cannot act: a fluid particle moves less than half the skin
    /// before the lists and the dummy particles are rebuilt, so it only ever sees a dummy
    /// particle within the search radius of where it was at the placement, and a dummy particle's
    /// own sums (its Shepard values over the fluid within the search radius; Ren's wall Hessian,
    /// [`crate::operators::artificial`], over the virtual particles within one kernel radius)
    /// reach no farther than the search radius plus one kernel radius. Dropping the rest leaves
    /// every sum of the schemes the same term by term in the same order (the lists are sorted by
    /// index and the kept points keep their order), so the results are bitwise those of the
    /// whole layout; the whole layout covers the fluid with three search radii to spare, and
    /// over a spreading drop most of it lies beyond that reach.
    fn keep_reachable(
        all: &[Vector<N>],
        fluid_x: &[Vector<N>],
        reach: f64,
        dom: &Domain,
    ) -> Vec<u32> {
        if fluid_x.is_empty() {
            return Vec::new();
        }
        let grid = Grid::build(fluid_x, reach, dom);
        let reach2 = reach * reach;
        all.par_iter()
            .with_min_len(1024)
            .enumerate()
            .filter(|(_, xw)| {
                let mut near = false;
                grid.for_each_candidate(xw, |j| {
                    near = near || dom.delta(xw, &fluid_x[j as usize]).norm_squared() < reach2;
                });
                near
            })
            .map(|(k, _)| k as u32)
            .collect()
    }

    /// Where `wall`'s dummy particles are now: as placed, or, on a plate that has moved since
    /// (the neighbour lists, built with a skin, stay valid meanwhile), laid out afresh from the
    /// plate's current pose, the same positions the fluid passes see
    /// ([`Boundary::positions`]). Laying them out afresh rather than shifting the placed ones
    /// keeps a restored run bitwise: its scheme places the particles at the restore time.
    fn where_now<'a>(&'a self, wall: &Wall<N>) -> std::borrow::Cow<'a, [Vector<N>]> {
        if wall.displacement() == self.placed_at {
            std::borrow::Cow::Borrowed(&self.x)
        } else {
            std::borrow::Cow::Owned(self.kept_layout(wall))
        }
    }

    /// Shepard sums over the fluid neighbours of dummy particle `k`, now at `xw`: sum W, and
    /// `f(j, W)` for every neighbour j with W > 0.
    fn shepard(
        &self,
        fluid: &Fluid<N>,
        k: usize,
        xw: Vector<N>,
        mut f: impl FnMut(usize, f64, Vector<N>),
    ) -> f64 {
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

impl<K: Kernel<N>, const N: usize> Boundary<N> for DummyWall<K, N>
where
    Const<N>: DummyLayout<N>,
{
    fn place(
        &mut self,
        wall: &mut Wall<N>,
        fluid_x: &[Vector<N>],
        fluid_grid: &Grid<N>,
        radius: f64,
        out: &mut Vec<Vector<N>>,
    ) {
        if let Some(p) = wall.plate_mut() {
            // Columns only where fluid comes near, as for Fang's and Ren's walls.
            p.cover_points(fluid_x, 3.0 * radius);
        }
        self.lateral = Lateral::covering(wall, fluid_x, 3.0 * radius, self.dx, &self.domain);
        let all = self.layout(wall);
        let reach = radius + self.kernel.radius();
        self.kept = Self::keep_reachable(&all, fluid_x, reach, &self.domain);
        self.x = self.kept.iter().map(|&k| all[k as usize]).collect();
        self.placed_at = wall.displacement();
        out.extend_from_slice(&self.x);
        self.list = NeighborList::build(fluid_grid, fluid_x, &self.x, radius, &self.domain);
    }

    fn fill_velocities(&self, wall: &Wall<N>, fluid: &Fluid<N>, out: &mut [Vector<N>]) {
        let (uw, xs) = (wall.wall_velocity(), self.where_now(wall));
        // Each dummy particle on its own: on all threads, bitwise whatever their number.
        out.par_iter_mut()
            .with_min_len(MIN_TASK)
            .enumerate()
            .for_each(|(k, o)| {
                let mut su = Vector::zeros();
                let sw = self.shepard(fluid, k, xs[k], |j, w, _| su += fluid.v[j] * w);
                *o = if sw > 0.0 { 2.0 * uw - su / sw } else { uw };
            });
    }

    fn fill_stresses(
        &self,
        wall: &Wall<N>,
        fluid: &Fluid<N>,
        sigma: &[Tensor<N>],
        _tau_p: &[Tensor<N>],
        out: &mut [Tensor<N>],
    ) {
        let xs = self.where_now(wall);
        out.par_iter_mut()
            .with_min_len(MIN_TASK)
            .enumerate()
            .for_each(|(k, o)| {
                let (mut ss, mut sr) = (Tensor::zeros(), Vector::zeros());
                let sw = self.shepard(fluid, k, xs[k], |j, w, rwf| {
                    ss += sigma[j] * w;
                    sr += rwf * (fluid.rho[j] * w);
                });
                *o = if sw > 0.0 {
                    (ss - Tensor::identity() * self.gravity.dot(&sr)) / sw
                } else {
                    Tensor::zeros()
                };
            });
    }

    fn positions(&self, wall: &Wall<N>) -> Vec<Vector<N>> {
        self.kept_layout(wall)
    }

    /// Adami et al. 2012 section 2.3: the extrapolated velocity is the viscous forces'; the
    /// continuity equation takes the wall's velocity (module documentation).
    fn continuity_at_wall_velocity(&self) -> bool {
        true
    }
}
