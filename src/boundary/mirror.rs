//! King & Lind 2021's mirror particles (section III.C) for a straight plate of any inclination,
//! built in the plate's own frame.
//!
//! The plate passes through `origin` with unit tangent t and unit normal n into the fluid. Every
//! fluid particle at a distance 0 < d < r_s from the plate (King's code: r_s = 3h, the kernel
//! support) gets a mirror at `x_m = x_i - 2 d n`: x_i - x_m is perpendicular to the plate and
//! bisected by it. Mirror values:
//! * velocity `u_m = 2 u_wall - u_i` (no slip: the mean of a particle and its mirror, the value
//!   at the plate, is u_wall);
//! * pressure `p_m = p_i` (Neumann) plus, optionally, the hydrostatic correction
//!   `rho g . (x_m - x_i)` of King's newer code, so a fluid at rest sees a continued hydrostatic
//!   field;
//! * polymer stress: see [`StressMirror`].
//!
//! In the ISPH linear systems (`scheme::isph::ppe`) the mirrors are ghosts linked to their
//! parents ([`Boundary::parents`]): pressure sign +1 with offsets [`pressure_offsets`], velocity
//! sign -1 with offset 2 u_wall ([`Boundary::wall_velocities`]). Particles on the wrong side
//! (d <= 0) get no mirror; putting them back (King's code reflects them across the wall with
//! [`MirrorPlate::reflect`]) is the scheme's job.

use super::plate::Plate;
use super::wall::Wall;
use super::Boundary;
use crate::dim::{Tensor, Vector};
use crate::geometry::{HalfPlane, Shape};
use crate::neighbors::Grid;
use crate::particles::Fluid;
use crate::{Mat2, Vec2};

/// How a mirror's polymer stress follows from its parent's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StressMirror {
    /// `tau_m = tau_i`. The extension consistent with the no-slip velocity: near a no-slip wall
    /// the flow is a shear u_t ~ y (plus extension vanishing at the wall), whose mirrored field
    /// `2 u_wall - u(R x)` has the *same* shear rate, so the stress (a function of the shear
    /// rate) is even across the wall, shear component included. With it a uniform shear stress
    /// exerts no force on the near-wall particles, as it must (test
    /// `uniform_shear_stress_exerts_no_force_near_the_wall`).
    #[default]
    NoSlip,
    /// `tau_m = R tau_i R` with `R = I - 2 n n^T`: the stress reflected in the wall's frame
    /// (in (t, n) components, the shear component changes sign). Symmetric and involutive; it
    /// is the extension of a symmetry plane (free slip). At a no-slip wall it makes the shear
    /// stress odd across the wall, so a uniform shear exerts a spurious tangential force of
    /// order tau / dr on the first rows of particles (measured in the test above). King's code
    /// instead flips the whole normal row in the wall frame, which is not symmetric.
    Reflected,
}

/// A straight plate for mirror particles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MirrorPlate {
    /// A point of the plate.
    pub origin: Vec2,
    /// Unit tangent.
    pub t: Vec2,
    /// Unit normal into the fluid.
    pub n: Vec2,
    /// Velocity of the plate.
    pub u_wall: Vec2,
    /// Mirror reach r_s (King's code: 3h).
    pub reach: f64,
}

impl MirrorPlate {
    /// A plate through `origin` with unit tangent `t` and unit normal `n` into the fluid.
    pub fn new(origin: Vec2, t: Vec2, n: Vec2, u_wall: Vec2, reach: f64) -> Self {
        assert!(
            (t.norm() - 1.0).abs() < 1e-12
                && (n.norm() - 1.0).abs() < 1e-12
                && t.dot(&n).abs() < 1e-12,
            "t and n must be orthonormal"
        );
        assert!(reach > 0.0);
        Self {
            origin,
            t,
            n,
            u_wall,
            reach,
        }
    }

    /// The drop scenes' convention (as `boundary::plate::Plate`): inclined by `deg` degrees,
    /// downhill tangent (cos a, -sin a), normal into the fluid (sin a, cos a).
    pub fn inclined(origin: Vec2, deg: f64, u_wall: Vec2, reach: f64) -> Self {
        let a = deg.to_radians();
        Self::new(
            origin,
            Vec2::new(a.cos(), -a.sin()),
            Vec2::new(a.sin(), a.cos()),
            u_wall,
            reach,
        )
    }

    /// The solid's shape: the half-plane below the plate line.
    #[inline]
    pub fn shape(&self) -> HalfPlane<2> {
        HalfPlane::new(self.origin, self.n)
    }

    /// Signed distance from the plate, positive on the fluid side.
    #[inline]
    pub fn distance(&self, x: &Vec2) -> f64 {
        self.shape().signed_distance(x)
    }

    /// Mirror image of a point across the plate.
    #[inline]
    pub fn reflect(&self, x: &Vec2) -> Vec2 {
        self.shape().reflect(x)
    }

    /// No-slip mirror velocity, `2 u_wall - u`.
    #[inline]
    pub fn mirror_velocity(&self, u: &Vec2) -> Vec2 {
        2.0 * self.u_wall - u
    }

    /// `R s R` with `R = I - 2 n n^T`.
    #[inline]
    pub fn reflect_tensor(&self, s: &Mat2) -> Mat2 {
        let r = Mat2::identity() - 2.0 * self.n * self.n.transpose();
        r * s * r
    }

    /// Mirror polymer stress.
    #[inline]
    pub fn mirror_stress(&self, s: &Mat2, mode: StressMirror) -> Mat2 {
        match mode {
            StressMirror::NoSlip => *s,
            StressMirror::Reflected => self.reflect_tensor(s),
        }
    }
}

impl MirrorPlate {
    /// The mirror plate of a scene's plate (same frame and motion) with reach `reach`.
    pub fn of_plate(plate: &Plate, reach: f64) -> Self {
        Self {
            origin: plate.origin,
            t: plate.t,
            n: plate.n,
            u_wall: plate.wall_velocity(),
            reach,
        }
    }
}

/// The mirror-particle wall model of one wall of any shape as a [`Boundary`]:
/// [`Boundary::place`] builds a mirror for every fluid particle within `reach` of the wall (in
/// ascending particle order) across the wall's local tangent ([`Shape::reflect`]: across a
/// plate, its line; across a circle, the tangent at the closest point), the fill steps give them
/// the no-slip velocity and the [`StressMirror::NoSlip`] stress of their parents. The incompressible scheme reads the parents ([`Boundary::parents`]) to link
/// mirror pressures and velocities to their parents in its linear systems.
#[derive(Debug, Clone)]
pub struct MirrorWall<const N: usize = 2> {
    reach: f64,
    mirrors: Mirrors<N>,
}

impl<const N: usize> MirrorWall<N> {
    /// Mirrors reaching `reach` from the plate (King's code: 3h, the kernel support).
    pub fn new(reach: f64) -> Self {
        Self {
            reach,
            mirrors: Mirrors::default(),
        }
    }
}

impl<const N: usize> Boundary<N> for MirrorWall<N> {
    fn place(
        &mut self,
        wall: &mut Wall<N>,
        fluid_x: &[Vector<N>],
        _fluid_grid: &Grid<N>,
        _radius: f64,
        out: &mut Vec<Vector<N>>,
    ) {
        self.mirrors = build_across(&*wall, self.reach, fluid_x);
        out.extend_from_slice(&self.mirrors.x);
    }

    /// No slip: `2 u_wall - u_parent` (the wall moves rigidly, so u_wall is the same at every
    /// closest point).
    fn fill_velocities(&self, wall: &Wall<N>, fluid: &Fluid<N>, out: &mut [Vector<N>]) {
        let uw = wall.wall_velocity();
        for (o, &i) in out.iter_mut().zip(&self.mirrors.parent) {
            *o = 2.0 * uw - fluid.v[i as usize];
        }
    }

    fn fill_stresses(
        &self,
        _wall: &Wall<N>,
        _fluid: &Fluid<N>,
        _sigma: &[Tensor<N>],
        tau_p: &[Tensor<N>],
        out: &mut [Tensor<N>],
    ) {
        // StressMirror::NoSlip: the parent's stress, whatever the wall's orientation.
        for (o, &i) in out.iter_mut().zip(&self.mirrors.parent) {
            *o = tau_p
                .get(i as usize)
                .copied()
                .unwrap_or_else(Tensor::<N>::zeros);
        }
    }

    fn positions(&self, _wall: &Wall<N>) -> Vec<Vector<N>> {
        self.mirrors.x.clone()
    }

    fn parents(&self) -> &[u32] {
        &self.mirrors.parent
    }
}

/// Mirror points and their fluid parents (ascending parent order).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mirrors<const N: usize = 2> {
    pub x: Vec<Vector<N>>,
    pub parent: Vec<u32>,
}

/// A mirror for every fluid particle with 0 < d < reach from the plate, in ascending particle
/// order.
pub fn build(plate: &MirrorPlate, x: &[Vec2]) -> Mirrors {
    build_across(&plate.shape(), plate.reach, x)
}

/// A mirror across the wall `shape` (reflected across its local tangent) for every fluid
/// particle at a signed distance 0 < d < reach, in ascending particle order.
pub fn build_across<const N: usize>(
    shape: &dyn Shape<N>,
    reach: f64,
    x: &[Vector<N>],
) -> Mirrors<N> {
    let mut m = Mirrors::default();
    for (i, p) in x.iter().enumerate() {
        let d = shape.signed_distance(p);
        if d > 0.0 && d < reach {
            m.x.push(shape.reflect(p));
            m.parent.push(i as u32);
        }
    }
    m
}

/// Mirror velocities from the fluid velocities.
pub fn velocities(plate: &MirrorPlate, m: &Mirrors, u: &[Vec2]) -> Vec<Vec2> {
    m.parent
        .iter()
        .map(|&i| plate.mirror_velocity(&u[i as usize]))
        .collect()
}

/// Mirror polymer stresses from the fluid stresses.
pub fn stresses(plate: &MirrorPlate, m: &Mirrors, tau: &[Mat2], mode: StressMirror) -> Vec<Mat2> {
    m.parent
        .iter()
        .map(|&i| plate.mirror_stress(&tau[i as usize], mode))
        .collect()
}

/// Hydrostatic pressure offsets `rho g . (x_m - x_i)` (the PPE ghost offsets; zeros for a plain
/// Neumann condition).
pub fn pressure_offsets(m: &Mirrors, x: &[Vec2], rho: f64, g: Vec2) -> Vec<f64> {
    m.parent
        .iter()
        .zip(&m.x)
        .map(|(&i, xm)| rho * g.dot(&(xm - x[i as usize])))
        .collect()
}

/// Mirror pressures `p_i + offset`.
pub fn pressures(m: &Mirrors, p: &[f64], offsets: &[f64]) -> Vec<f64> {
    m.parent
        .iter()
        .zip(offsets)
        .map(|(&i, o)| p[i as usize] + o)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{Kernel, QuinticSpline};
    use crate::neighbors::{CellGrid, NeighborList};

    const ANGLES: [f64; 6] = [0.0, 17.0, 30.0, 45.0, 90.0, 133.0];

    fn points() -> Vec<Vec2> {
        (0..40)
            .map(|k| {
                Vec2::new(
                    0.013 * k as f64 - 0.2,
                    0.007 * ((k * 7) % 11) as f64 + 0.001,
                )
            })
            .collect()
    }

    #[test]
    fn mirror_of_a_mirror_is_the_particle_and_the_wall_bisects_them() {
        for deg in ANGLES {
            let plate = MirrorPlate::inclined(Vec2::new(0.03, -0.01), deg, Vec2::zeros(), 1.0);
            for x in points() {
                let m = plate.reflect(&x);
                assert!((plate.reflect(&m) - x).norm() < 1e-15);
                assert!((plate.distance(&m) + plate.distance(&x)).abs() < 1e-15);
                assert!(plate.distance(&(0.5 * (x + m))).abs() < 1e-15);
                assert!((x - m).dot(&plate.t).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn no_slip_velocity_at_the_wall_midpoint_is_the_wall_velocity() {
        for deg in ANGLES {
            let uw = Vec2::new(0.4, -0.25);
            let plate = MirrorPlate::inclined(Vec2::zeros(), deg, uw, 1.0);
            for (k, x) in points().iter().enumerate() {
                let u = Vec2::new((k as f64).sin(), 0.3 * k as f64) + x;
                let um = plate.mirror_velocity(&u);
                assert!((0.5 * (u + um) - uw).norm() < 1e-15);
                assert!((plate.mirror_velocity(&um) - u).norm() < 1e-15);
            }
        }
    }

    #[test]
    fn reflected_stress_is_symmetric_involutive_and_keeps_invariants() {
        let s = Mat2::new(3.0, -1.25, -1.25, 0.5);
        for deg in ANGLES {
            let plate = MirrorPlate::inclined(Vec2::zeros(), deg, Vec2::zeros(), 1.0);
            let r = plate.reflect_tensor(&s);
            assert!((r - r.transpose()).norm() < 1e-15);
            assert!((plate.reflect_tensor(&r) - s).norm() < 1e-14);
            assert!((r.trace() - s.trace()).abs() < 1e-14);
            assert!((r.determinant() - s.determinant()).abs() < 1e-13);
            // In the wall frame the normal components are kept and the shear flips.
            let (t, n) = (plate.t, plate.n);
            assert!((t.dot(&(r * t)) - t.dot(&(s * t))).abs() < 1e-14);
            assert!((n.dot(&(r * n)) - n.dot(&(s * n))).abs() < 1e-14);
            assert!((t.dot(&(r * n)) + t.dot(&(s * n))).abs() < 1e-14);
            assert_eq!(plate.mirror_stress(&s, StressMirror::NoSlip), s);
        }
    }

    #[test]
    fn build_selects_particles_within_reach_and_hydrostatic_pressure_continues() {
        let plate = MirrorPlate::inclined(Vec2::zeros(), 30.0, Vec2::zeros(), 0.05);
        let x = points();
        let m = build(&plate, &x);
        let expect: Vec<u32> = (0..x.len() as u32)
            .filter(|&i| {
                let d = plate.distance(&x[i as usize]);
                d > 0.0 && d < 0.05
            })
            .collect();
        assert!(!expect.is_empty() && expect.len() < x.len());
        assert_eq!(m.parent, expect);
        // A fluid at rest: p(x) = p0 + rho g . x; the corrected mirror pressure is the same
        // field at the mirror's position.
        let (rho, g, p0) = (1000.0, Vec2::new(0.0, -9.81), 50.0);
        let p: Vec<f64> = x.iter().map(|x| p0 + rho * g.dot(x)).collect();
        let off = pressure_offsets(&m, &x, rho, g);
        let pm = pressures(&m, &p, &off);
        for (xm, pm) in m.x.iter().zip(&pm) {
            assert!((pm - (p0 + rho * g.dot(xm))).abs() < 1e-10);
        }
        let u: Vec<Vec2> = x.iter().map(|x| Vec2::new(x.y, -x.x)).collect();
        let um = velocities(&plate, &m, &u);
        assert!(m
            .parent
            .iter()
            .zip(&um)
            .all(|(&i, v)| (v + u[i as usize]).norm() < 1e-15));
    }

    /// Across a circle (a cylinder and a circular tank), mirrors are reflected across the local
    /// tangent: the circle bisects a parent and its mirror at the closest point, and the mirror
    /// of any velocity is no slip there (the mean of parent and mirror is the wall's velocity,
    /// here at rest).
    #[test]
    fn mirrors_across_a_circle_are_no_slip_at_the_closest_point() {
        use crate::geometry::Ball;
        for ball in [
            Ball::obstacle(Vec2::new(0.01, 0.02), 0.1),
            Ball::container(Vec2::new(0.01, 0.02), 0.25),
        ] {
            let mut wall = Wall::from(ball);
            let x: Vec<Vec2> = (0..400)
                .map(|k| {
                    let a = 0.7 * k as f64;
                    let r = 0.05 + 0.25 * (k as f64 / 400.0);
                    Vec2::new(0.01, 0.02) + r * Vec2::new(a.cos(), a.sin())
                })
                .collect();
            let mut model = MirrorWall::new(0.03);
            let grid = CellGrid::build(&x, 0.03, &crate::neighbors::Domain::OPEN);
            let mut out = Vec::new();
            model.place(&mut wall, &x, &grid, 0.03, &mut out);
            assert!(!out.is_empty());
            let fluid = Fluid {
                mass: 1.0,
                v: x.iter().map(|p| Vec2::new(0.3 - p.y, 2.0 * p.x)).collect(),
                x: x.clone(),
                ..Default::default()
            };
            let mut v = vec![Vec2::zeros(); out.len()];
            model.fill_velocities(&wall, &fluid, &mut v);
            for (k, &i) in model.parents().iter().enumerate() {
                let (xi, xm) = (x[i as usize], out[k]);
                let d = ball.signed_distance(&xi);
                assert!(d > 0.0 && d < 0.03);
                assert!((0.5 * (xi + xm) - ball.closest_point(&xi)).norm() < 1e-15);
                assert!((ball.signed_distance(&xm) + d).abs() < 1e-15);
                assert!((0.5 * (fluid.v[i as usize] + v[k])).norm() < 1e-15);
            }
            let within = x
                .iter()
                .filter(|p| {
                    let d = ball.signed_distance(p);
                    d > 0.0 && d < 0.03
                })
                .count();
            assert_eq!(model.parents().len(), within);
        }
    }

    /// Through the [`Boundary`] trait, as the incompressible scheme sees it: the parents are
    /// the particles within reach in ascending order, every mirror takes the moving plate's
    /// velocity for its no-slip continuation, and the filled velocities and stresses are that
    /// continuation and the parents' stresses.
    #[test]
    fn mirror_wall_through_the_boundary_trait() {
        let mut plate = Plate::new(30.0, 0.01);
        plate.velocity = 0.3;
        let mut whole = Wall::from(plate.clone());
        let x = points();
        let mut wall: Box<dyn Boundary> = Box::new(MirrorWall::new(0.05));
        let grid = CellGrid::build(&x, 0.05, &crate::neighbors::Domain::OPEN);
        let mut out = vec![Vec2::new(9.0, 9.0)];
        wall.place(&mut whole, &x, &grid, 0.05, &mut out);
        let m = build(&MirrorPlate::of_plate(&plate, 0.05), &x);
        assert!(!m.parent.is_empty());
        assert_eq!(wall.parents(), &m.parent[..]);
        assert_eq!(&out[1..], &m.x[..]);
        assert_eq!(wall.positions(&whole), m.x);
        let mut uw = vec![Vec2::zeros()];
        wall.wall_velocities(&whole, &mut uw);
        assert_eq!(uw.len(), 1 + m.parent.len());
        assert!(uw[1..].iter().all(|u| *u == -plate.n * 0.3));
        let fluid = Fluid {
            mass: 1.0,
            x: x.clone(),
            v: x.iter().map(|p| Vec2::new(p.y, 2.0 * p.x)).collect(),
            rho: vec![1.0; x.len()],
            ..Default::default()
        };
        let mut v = vec![Vec2::zeros(); m.parent.len()];
        wall.fill_velocities(&whole, &fluid, &mut v);
        let tau: Vec<Mat2> = x.iter().map(|p| Mat2::new(p.x, p.y, p.y, 1.0)).collect();
        let mut s = vec![Mat2::zeros(); m.parent.len()];
        wall.fill_stresses(&whole, &fluid, &[], &tau, &mut s);
        for (k, &i) in m.parent.iter().enumerate() {
            let i = i as usize;
            assert_eq!(v[k], 2.0 * uw[1 + k] - fluid.v[i]);
            assert_eq!(s[k], tau[i]);
        }
    }

    /// A uniform polymer shear stress (tau_tn = 1, first normal difference 4) on a lattice above
    /// a plate at 30 degrees: the positive-form divergence (King & Lind 2021 eq. (20)),
    /// `sum_j (tau_i + tau_j) grad W_ij V_j`, over fluid and mirror neighbours, must vanish at
    /// every particle. With `NoSlip` mirrors it does (to round-off); with `Reflected` mirrors
    /// the first rows feel a spurious tangential force of order tau / dr.
    #[test]
    fn uniform_shear_stress_exerts_no_force_near_the_wall() {
        let dr = 0.01;
        let k = QuinticSpline::new(1.3 * dr);
        let plate = MirrorPlate::inclined(Vec2::zeros(), 30.0, Vec2::zeros(), k.radius());
        let (t, n) = (plate.t, plate.n);
        let x: Vec<Vec2> = (0..30 * 12)
            .map(|q| ((q % 30) as f64 - 14.5) * dr * t + ((q / 30) as f64 + 0.5) * dr * n)
            .collect();
        let tau_wall = Mat2::new(4.0, 1.0, 1.0, 0.0); // (t, n) components
        let frame = Mat2::from_columns(&[t, n]);
        let tau = frame * tau_wall * frame.transpose();
        let force = |mode: StressMirror| {
            let m = build(&plate, &x);
            let mut all = x.clone();
            all.extend_from_slice(&m.x);
            let mut taus = vec![tau; x.len()];
            taus.extend(stresses(&plate, &m, &vec![tau; x.len()], mode));
            let grid = CellGrid::build(&all, k.radius(), &crate::neighbors::Domain::OPEN);
            let nl =
                NeighborList::build(&grid, &all, &x, k.radius(), &crate::neighbors::Domain::OPEN);
            (0..x.len())
                .filter(|&i| x[i].dot(&t).abs() < 8.0 * dr && plate.distance(&x[i]) < 4.0 * dr)
                .map(|i| {
                    let mut f = Vec2::zeros();
                    for &j in nl.of(i) {
                        let j = j as usize;
                        let xij = all[i] - all[j];
                        f += dr * dr * (taus[i] + taus[j]) * (xij * k.dw_over_r(xij.norm()));
                    }
                    f.norm()
                })
                .fold(0.0, f64::max)
        };
        let even = force(StressMirror::NoSlip);
        let odd = force(StressMirror::Reflected);
        assert!(even < 1e-9 / dr, "{even}");
        assert!(odd > 0.1 / dr, "{odd}");
    }

    /// A fluid layer at rest on a 30-degree plate: the PPE (King & Lind 2021 eq. (25)) with zero
    /// right-hand side, mirrors carrying the hydrostatic offsets as Neumann ghosts, and the
    /// hydrostatic value as Dirichlet data on the free rows (top and ends) returns the
    /// hydrostatic field everywhere, the rows next to the plate included.
    #[test]
    fn ppe_with_mirrors_holds_the_hydrostatic_pressure() {
        use crate::scheme::isph::ppe::{
            assemble_poisson, morris_coefficients, solve, GhostLink, SolverOptions,
        };
        let dr = 0.01;
        let k = QuinticSpline::new(1.3 * dr);
        let plate = MirrorPlate::inclined(Vec2::zeros(), 30.0, Vec2::zeros(), k.radius());
        let (t, n) = (plate.t, plate.n);
        let (cols, rows) = (40, 12);
        let x: Vec<Vec2> = (0..cols * rows)
            .map(|q| ((q % cols) as f64 - 19.5) * dr * t + ((q / cols) as f64 + 0.5) * dr * n)
            .collect();
        let (rho, g) = (1000.0, Vec2::new(0.0, -9.81));
        let top = x.iter().map(|p| plate.distance(p)).fold(0.0, f64::max);
        let exact = |p: &Vec2| rho * g.dot(&(p - (top * n)));
        let m = build(&plate, &x);
        let mut all = x.clone();
        all.extend_from_slice(&m.x);
        let grid = CellGrid::build(&all, k.radius(), &crate::neighbors::Domain::OPEN);
        let nl = NeighborList::build(&grid, &all, &x, k.radius(), &crate::neighbors::Domain::OPEN);
        let vol = vec![dr * dr; all.len()];
        let coef = morris_coefficients(&all, &vol, &nl, &k, &crate::neighbors::Domain::OPEN, None);
        let off = pressure_offsets(&m, &x, rho, g);
        let ghosts = GhostLink {
            parent: &m.parent,
            sign: &[],
            offset: &off,
        };
        let dirichlet: Vec<Option<f64>> = (0..x.len())
            .map(|q| {
                let (c, r) = (q % cols, q / cols);
                (r >= rows - 3 || c < 3 || c >= cols - 3).then(|| exact(&x[q]))
            })
            .collect();
        let sys = assemble_poisson(
            x.len(),
            &nl,
            &coef,
            &ghosts,
            &dirichlet,
            &vec![0.0; x.len()],
        );
        let mut p = vec![0.0; x.len()];
        solve(&sys, &mut p, &SolverOptions::default()).unwrap();
        let scale = rho * 9.81 * top;
        for (pi, xi) in p.iter().zip(&x) {
            assert!(
                (pi - exact(xi)).abs() < 1e-7 * scale,
                "{pi} vs {}",
                exact(xi)
            );
        }
    }
}
