//! Shapes of the plane only: a finite straight wall and a polygon.

use super::{Shape, Side};
use crate::Vec2;
use serde::{Deserialize, Serialize};

/// Closest point of the segment a-b to x, and the parameter s in [0, 1] of it.
#[inline]
fn closest_on_segment(a: &Vec2, b: &Vec2, x: &Vec2) -> (Vec2, f64) {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let s = if l2 > 0.0 {
        ((x - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + s * ab, s)
}

/// The left-hand unit normal of the direction a -> b (a quarter turn anticlockwise).
#[inline]
fn left_normal(a: &Vec2, b: &Vec2) -> Vec2 {
    let t = (b - a).normalize();
    Vec2::new(-t.y, t.x)
}

/// A straight wall of finite length from `a` to `b`, solid on its right (seen going from a to
/// b), fluid on its left: the left-hand normal points into the fluid, as a plate's does with
/// its downhill tangent. Beyond the ends the distance is to the nearer end; the sign is the
/// side of the wall's line.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    pub a: Vec2,
    pub b: Vec2,
}

impl Segment {
    pub fn new(a: Vec2, b: Vec2) -> Self {
        assert!(a != b, "a segment needs two distinct ends");
        Self { a, b }
    }
    /// Unit normal of the wall's line into the fluid.
    pub fn line_normal(&self) -> Vec2 {
        left_normal(&self.a, &self.b)
    }
    fn side(&self, x: &Vec2) -> f64 {
        if (x - self.a).dot(&self.line_normal()) >= 0.0 {
            1.0
        } else {
            -1.0
        }
    }
}

impl Shape<2> for Segment {
    fn signed_distance(&self, x: &Vec2) -> f64 {
        self.side(x) * (x - closest_on_segment(&self.a, &self.b, x).0).norm()
    }
    fn closest_point(&self, x: &Vec2) -> Vec2 {
        closest_on_segment(&self.a, &self.b, x).0
    }
    fn normal(&self, x: &Vec2) -> Vec2 {
        let (c, s) = closest_on_segment(&self.a, &self.b, x);
        let r = x - c;
        if s > 0.0 && s < 1.0 || r.norm() == 0.0 {
            self.line_normal()
        } else {
            self.side(x) * r.normalize()
        }
    }
}

/// A simple polygon (vertices in either order, not self-intersecting) bounding an obstacle or a
/// container.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Polygon {
    pub vertices: Vec<Vec2>,
    /// Where the fluid is.
    pub fluid: Side,
}

impl Polygon {
    pub fn new(vertices: Vec<Vec2>, fluid: Side) -> Self {
        assert!(vertices.len() >= 3, "a polygon needs three vertices");
        Self { vertices, fluid }
    }

    fn edges(&self) -> impl Iterator<Item = (&Vec2, &Vec2)> {
        self.vertices
            .iter()
            .zip(self.vertices.iter().cycle().skip(1))
    }

    /// Whether x is inside the polygon (even-odd rule; points on the boundary may go either
    /// way, where the signed distance is 0 anyway).
    pub fn contains(&self, x: &Vec2) -> bool {
        let mut inside = false;
        for (a, b) in self.edges() {
            if (a.y > x.y) != (b.y > x.y) {
                let xc = a.x + (x.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if x.x < xc {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// The closest point of the boundary and the unsigned distance to it.
    fn nearest(&self, x: &Vec2) -> (Vec2, f64) {
        let mut best = (self.vertices[0], f64::INFINITY);
        for (a, b) in self.edges() {
            let c = closest_on_segment(a, b, x).0;
            let d = (x - c).norm();
            if d < best.1 {
                best = (c, d);
            }
        }
        best
    }

    /// +1 where the fluid is, -1 in the solid.
    fn fluid_sign(&self, x: &Vec2) -> f64 {
        let outside = if self.contains(x) { -1.0 } else { 1.0 };
        outside * self.fluid.sign()
    }
}

impl Shape<2> for Polygon {
    fn signed_distance(&self, x: &Vec2) -> f64 {
        self.fluid_sign(x) * self.nearest(x).1
    }
    fn closest_point(&self, x: &Vec2) -> Vec2 {
        self.nearest(x).0
    }
    fn normal(&self, x: &Vec2) -> Vec2 {
        let (c, d) = self.nearest(x);
        if d > 0.0 {
            return self.fluid_sign(x) * (x - c) / d;
        }
        // On the boundary: the normal of the edge it lies on, turned into the fluid.
        let (a, b) = self
            .edges()
            .min_by(|(a, b), (p, q)| {
                let da = (x - closest_on_segment(a, b, x).0).norm();
                let dp = (x - closest_on_segment(p, q, x).0).norm();
                da.total_cmp(&dp)
            })
            .expect("three vertices");
        let n = left_normal(a, b);
        let probe = x + 1e-9 * (b - a).norm().max(1.0) * n;
        self.fluid_sign(&probe) * n
    }
}
