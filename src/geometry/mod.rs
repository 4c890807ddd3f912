//! Wall shapes: what a wall model needs to know about the solid a wall bounds, whatever its
//! shape: the signed distance of a point from it (positive on the fluid side), the closest point
//! of its boundary and the unit normal into the fluid there.
//!
//! * [`HalfPlane`] (a straight wall of unbounded length: the drop's plate, the channel's walls)
//!   and [`Ball`] (a circle in 2D, a sphere in 3D) are written once for every dimension, over
//!   the const N of [`crate::dim::Vector`]: a 3D plane and sphere are the same types with N = 3
//!   (nothing of a shape needs the [`crate::dim::Dim`] trait's tensor functions).
//! * [`Segment`] and [`Polygon`] are 2D: a straight wall of finite length (a container's side)
//!   and a polygonal obstacle or container.
//! * [`Union`] is several solids as one (a cylinder between two walls), closest member first.
//!
//! Every shape bounds a solid on one side. Which side the fluid is on is part of the shape: a
//! [`Ball`] may be an obstacle (fluid outside, a cylinder) or a container (fluid inside, a
//! circular tank), and so may a [`Polygon`].
//!
//! Mirror particles across a curved wall (King & Lind 2021, section III.C) are reflected across
//! the local tangent: `x_m = 2 c(x) - x`, with c(x) the closest point ([`Shape::reflect`]); on a
//! straight wall that is the usual reflection.

mod planar;

pub use planar::{Polygon, Segment};

use crate::dim::Vector;
use serde::{Deserialize, Serialize};

/// A solid's boundary seen from the fluid, in N dimensions.
pub trait Shape<const N: usize>: Send + Sync + std::fmt::Debug {
    /// Signed distance of `x` from the boundary: positive on the fluid side, negative inside
    /// the solid.
    fn signed_distance(&self, x: &Vector<N>) -> f64;

    /// The point of the boundary closest to `x`.
    fn closest_point(&self, x: &Vector<N>) -> Vector<N>;

    /// Unit normal into the fluid at the boundary point closest to `x` (for a point off the
    /// boundary, the direction from the closest point to `x`, signed to point into the fluid:
    /// the gradient of the signed distance).
    fn normal(&self, x: &Vector<N>) -> Vector<N>;

    /// Whether the boundary is one straight line (plane): the wall models that build their
    /// virtual particles in a straight wall's frame (Fang 2006, Ren 2015) need it.
    fn is_straight(&self) -> bool {
        false
    }

    /// Mirror image of `x` across the boundary's local tangent line (plane) at the closest
    /// point: `2 c(x) - x`.
    fn reflect(&self, x: &Vector<N>) -> Vector<N> {
        2.0 * self.closest_point(x) - x
    }

    /// Volume ratio of the mirror image of `x` to `x` (the Jacobian determinant of
    /// [`Shape::reflect`] at `x`): exactly 1 across a straight wall (an isometry); across a
    /// curved wall the reflection across the local tangent stretches the tangential directions
    /// by the ratio of the image's distance from the centre of curvature to the point's.
    /// Mirror particles carry their parent's volume times this ratio, so that they fill the
    /// kernel support across the wall as the fluid would (ISPH, `scheme::isph::walls`).
    fn reflection_jacobian(&self, _x: &Vector<N>) -> f64 {
        1.0
    }
}

/// Which side of a closed boundary the fluid is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Side {
    /// Fluid outside, solid inside: an obstacle (a cylinder).
    Outside,
    /// Fluid inside, solid outside: a container (a circular tank).
    Inside,
}

impl Side {
    /// +1 for fluid outside, -1 for fluid inside: the sign that turns "distance outside the
    /// closed curve" into "distance into the fluid".
    #[inline]
    pub fn sign(self) -> f64 {
        match self {
            Side::Outside => 1.0,
            Side::Inside => -1.0,
        }
    }
}

/// The solid below a straight line (plane): every point x = origin + d n with d < 0. A straight
/// plate of any inclination.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HalfPlane<const N: usize> {
    /// A point of the boundary.
    pub origin: Vector<N>,
    /// Unit normal into the fluid.
    pub n: Vector<N>,
}

impl<const N: usize> HalfPlane<N> {
    pub fn new(origin: Vector<N>, n: Vector<N>) -> Self {
        Self { origin, n }
    }
}

impl<const N: usize> Shape<N> for HalfPlane<N> {
    #[inline]
    fn signed_distance(&self, x: &Vector<N>) -> f64 {
        (x - self.origin).dot(&self.n)
    }
    #[inline]
    fn closest_point(&self, x: &Vector<N>) -> Vector<N> {
        x - self.signed_distance(x) * self.n
    }
    #[inline]
    fn normal(&self, _x: &Vector<N>) -> Vector<N> {
        self.n
    }
    fn is_straight(&self) -> bool {
        true
    }
    /// `x - 2 d n`, the form the straight-wall mirrors have always used.
    #[inline]
    fn reflect(&self, x: &Vector<N>) -> Vector<N> {
        x - 2.0 * self.signed_distance(x) * self.n
    }
}

/// A circle (2D) or sphere (3D) bounding an obstacle or a container.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ball<const N: usize> {
    pub centre: Vector<N>,
    pub radius: f64,
    /// Where the fluid is.
    pub fluid: Side,
}

impl<const N: usize> Ball<N> {
    /// A solid ball with fluid around it (a cylinder in 2D).
    pub fn obstacle(centre: Vector<N>, radius: f64) -> Self {
        Self {
            centre,
            radius,
            fluid: Side::Outside,
        }
    }
    /// A container with fluid inside.
    pub fn container(centre: Vector<N>, radius: f64) -> Self {
        Self {
            centre,
            radius,
            fluid: Side::Inside,
        }
    }
    /// Unit vector from the centre towards `x` (any unit vector at the centre itself).
    fn radial(&self, x: &Vector<N>) -> Vector<N> {
        let r = x - self.centre;
        let l = r.norm();
        if l > 0.0 {
            r / l
        } else {
            let mut e = Vector::<N>::zeros();
            e[0] = 1.0;
            e
        }
    }
}

impl<const N: usize> Shape<N> for Ball<N> {
    fn signed_distance(&self, x: &Vector<N>) -> f64 {
        self.fluid.sign() * ((x - self.centre).norm() - self.radius)
    }
    fn closest_point(&self, x: &Vector<N>) -> Vector<N> {
        self.centre + self.radius * self.radial(x)
    }
    fn normal(&self, x: &Vector<N>) -> Vector<N> {
        self.fluid.sign() * self.radial(x)
    }
    /// `(r_m / r)^(N-1)`: the image lies at `r_m = 2 R - r` from the centre, on the same ray.
    fn reflection_jacobian(&self, x: &Vector<N>) -> f64 {
        let r = (x - self.centre).norm();
        ((2.0 * self.radius - r) / r).powi(N as i32 - 1)
    }
}

/// Several solids as one: the fluid is where it is for every member (outside all obstacles,
/// inside all containers). The signed distance is the smallest of the members'; the closest
/// point and normal are those of the member it comes from (the first of equals, so the result is
/// deterministic).
#[derive(Debug)]
pub struct Union<const N: usize> {
    pub members: Vec<Box<dyn Shape<N>>>,
}

impl<const N: usize> Union<N> {
    pub fn new(members: Vec<Box<dyn Shape<N>>>) -> Self {
        assert!(!members.is_empty(), "a union of no shape");
        Self { members }
    }
    /// The member closest to `x` and its signed distance.
    pub fn nearest(&self, x: &Vector<N>) -> (usize, f64) {
        let mut best = (0, self.members[0].signed_distance(x));
        for (k, m) in self.members.iter().enumerate().skip(1) {
            let d = m.signed_distance(x);
            if d < best.1 {
                best = (k, d);
            }
        }
        best
    }
}

impl<const N: usize> Shape<N> for Union<N> {
    fn signed_distance(&self, x: &Vector<N>) -> f64 {
        self.nearest(x).1
    }
    fn closest_point(&self, x: &Vector<N>) -> Vector<N> {
        self.members[self.nearest(x).0].closest_point(x)
    }
    fn normal(&self, x: &Vector<N>) -> Vector<N> {
        self.members[self.nearest(x).0].normal(x)
    }
    fn reflection_jacobian(&self, x: &Vector<N>) -> f64 {
        self.members[self.nearest(x).0].reflection_jacobian(x)
    }
}

#[cfg(test)]
mod tests;
