//! A straight rigid plate of any inclination: its frame, its motion and the range of columns of
//! virtual particles built along it so far. What the virtual particles carry is the business of
//! a wall model ([`super::ghost`] for Fang's and Ren's walls).
//!
//! Frame: the plate passes through its origin (the impact point for a drop), its downhill unit
//! tangent is t = (cos a, -sin a) and its unit normal into the fluid n = (sin a, cos a). A point
//! is x = origin + s t + d n. Virtual particles come in columns at s_k = k dx, each with an
//! interior point at d = +dx inside the fluid. Columns are created only where fluid comes near
//! (the plate is as long as it needs to be and a scene never pays for wall it does not wet); the
//! range only grows, so it is deterministic.
//!
//! The plate moves rigidly along its normal with `velocity` (positive away from the fluid, i.e.
//! along -n); `displacement` is how far it has moved so far. What sets the velocity is the
//! wall's own [`Motion`], and the wall integrates its own pose ([`Plate::advance`]).

use crate::dim::Vector;
use crate::geometry::HalfPlane;
use crate::Vec2;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What moves a wall: nothing, a given function of time, or an input of the running
/// simulation. The motion is a rigid translation along the wall's normal, positive away from the
/// fluid; over one step the velocity is the one in force at the step's start.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum Motion {
    /// The wall stays where it was built.
    #[default]
    Fixed,
    /// The velocity is a given function of time (see [`Prescribed`]).
    Prescribed(Prescribed),
    /// The velocity is the input `plate_velocity` in force (the drop's plate), set by the
    /// simulation whenever the inputs change.
    Input,
}

/// A prescribed normal velocity `v(t) = velocity + amplitude sin(angular_frequency t)` [m/s].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Prescribed {
    pub velocity: f64,
    pub amplitude: f64,
    pub angular_frequency: f64,
}

impl Prescribed {
    /// A constant velocity.
    pub fn constant(velocity: f64) -> Self {
        Self {
            velocity,
            ..Self::default()
        }
    }

    /// The velocity at time t.
    pub fn at(&self, t: f64) -> f64 {
        if self.amplitude == 0.0 {
            self.velocity
        } else {
            self.velocity + self.amplitude * (self.angular_frequency * t).sin()
        }
    }
}

/// The plate and the range of columns built so far. In N dimensions the plate is the plane
/// through `origin` with normal `n`, and `t` is a downhill unit tangent in it; the columns of
/// virtual particles run along `t` (one row of them: the two-dimensional wall models' layout;
/// covering the plane's other tangent directions is left to the three-dimensional wall models).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plate<const N: usize = 2> {
    /// A point of the plate line: s = d = 0 there \[m\].
    pub origin: Vector<N>,
    /// Velocity of the plate along its normal, positive away from the fluid (along -n) [m/s].
    pub velocity: f64,
    /// Distance the plate has moved along -n since t = 0 \[m\].
    pub displacement: f64,
    /// Downhill unit tangent.
    pub t: Vector<N>,
    /// Unit normal into the fluid.
    pub n: Vector<N>,
    /// Column spacing (the particle spacing).
    pub dx: f64,
    /// First and last column index (inclusive); `k_min > k_max` means no column yet.
    pub k_min: i64,
    pub k_max: i64,
    /// Whether the column range is fixed (a periodic channel's wall spans exactly one period)
    /// instead of growing to follow the fluid.
    #[serde(default)]
    pub fixed: bool,
    /// What moves the wall.
    #[serde(default)]
    pub motion: Motion,
}

impl Plate {
    /// A plate through the origin inclined at `inclination_deg` to the horizontal, downhill
    /// towards +x.
    pub fn new(inclination_deg: f64, dx: f64) -> Self {
        let a = inclination_deg.to_radians();
        Self {
            origin: Vec2::zeros(),
            velocity: 0.0,
            displacement: 0.0,
            t: Vec2::new(a.cos(), -a.sin()),
            n: Vec2::new(a.sin(), a.cos()),
            dx,
            k_min: 0,
            k_max: -1,
            fixed: false,
            motion: Motion::Fixed,
        }
    }

    /// A plate through `origin` with downhill tangent `t` (a unit vector; the normal into the
    /// fluid is t turned a quarter turn anticlockwise) and the fixed columns `k_min..=k_max`.
    pub fn spanning(origin: Vec2, t: Vec2, dx: f64, k_min: i64, k_max: i64) -> Self {
        Self {
            origin,
            velocity: 0.0,
            displacement: 0.0,
            t,
            n: Vec2::new(-t.y, t.x),
            dx,
            k_min,
            k_max,
            fixed: true,
            motion: Motion::Fixed,
        }
    }
}

impl<const N: usize> Plate<N> {
    /// A plate of any dimension: the plane through `origin` with unit normal `n` into the
    /// fluid and downhill unit tangent `t` (orthogonal to `n`), columns growing with the fluid.
    pub fn through(origin: Vector<N>, n: Vector<N>, t: Vector<N>, dx: f64) -> Self {
        debug_assert!(n.dot(&t).abs() < 1e-12);
        Self {
            origin,
            velocity: 0.0,
            displacement: 0.0,
            t,
            n,
            dx,
            k_min: 0,
            k_max: -1,
            fixed: false,
            motion: Motion::Fixed,
        }
    }

    /// The same wall moved by `motion` (a prescribed motion starts at its velocity at t = 0).
    pub fn with_motion(mut self, motion: Motion) -> Self {
        self.motion = motion;
        if let Motion::Prescribed(p) = motion {
            self.velocity = p.at(0.0);
        }
        self
    }

    /// Move the wall over a step of `dt` that ended at `t`: a rigid translation along -n at the
    /// velocity in force over the step, then the velocity of a prescribed motion at `t` for the
    /// next step.
    pub fn advance(&mut self, t: f64, dt: f64) {
        let ds = self.velocity * dt;
        if ds != 0.0 {
            self.displacement += ds;
            self.origin -= self.n * ds;
        }
        if let Motion::Prescribed(p) = self.motion {
            self.velocity = p.at(t);
        }
    }

    /// The solid's shape: the half-plane below the plate line.
    #[inline]
    pub fn shape(&self) -> HalfPlane<N> {
        HalfPlane::new(self.origin, self.n)
    }

    /// Along-plate coordinate s (positive downhill) of a point.
    #[inline]
    pub fn s(&self, x: &Vector<N>) -> f64 {
        (x - self.origin).dot(&self.t)
    }

    /// Distance of a point from the plate, positive on the fluid side.
    #[inline]
    pub fn d(&self, x: &Vector<N>) -> f64 {
        use crate::geometry::Shape;
        self.shape().signed_distance(x)
    }

    /// Global position of plate coordinates (s, d).
    #[inline]
    pub fn point(&self, s: f64, d: f64) -> Vector<N> {
        self.origin + (self.t * s + self.n * d)
    }

    pub fn columns(&self) -> usize {
        if self.k_max < self.k_min {
            0
        } else {
            (self.k_max - self.k_min + 1) as usize
        }
    }

    /// Grow the column range so that it covers [s_lo, s_hi]. Returns whether it changed.
    pub fn cover(&mut self, s_lo: f64, s_hi: f64) -> bool {
        if self.fixed {
            return false;
        }
        let lo = (s_lo / self.dx).floor() as i64;
        let hi = (s_hi / self.dx).ceil() as i64;
        if self.columns() == 0 {
            self.k_min = lo;
            self.k_max = hi;
            return true;
        }
        let (a, b) = (self.k_min.min(lo), self.k_max.max(hi));
        let changed = (a, b) != (self.k_min, self.k_max);
        self.k_min = a;
        self.k_max = b;
        changed
    }

    /// Grow the column range to cover the points `x` with `margin` to spare at both ends
    /// (nothing without points).
    pub fn cover_points(&mut self, x: &[Vector<N>], margin: f64) {
        // On all threads: a minimum and a maximum do not depend on the order.
        let (lo, hi) = x
            .par_iter()
            .with_min_len(4096)
            .fold(
                || (f64::INFINITY, f64::NEG_INFINITY),
                |(lo, hi), p| {
                    let s = self.s(p);
                    (lo.min(s), hi.max(s))
                },
            )
            .reduce(
                || (f64::INFINITY, f64::NEG_INFINITY),
                |a, b| (a.0.min(b.0), a.1.max(b.1)),
            );
        if lo.is_finite() {
            self.cover(lo - margin, hi + margin);
        }
    }

    /// s of column c (0-based within the built range).
    #[inline]
    pub fn column_s(&self, c: usize) -> f64 {
        (self.k_min + c as i64) as f64 * self.dx
    }

    /// Velocity of the plate's material points (a rigid motion along the normal) [m/s].
    #[inline]
    pub fn wall_velocity(&self) -> Vector<N> {
        -self.n * self.velocity
    }

    /// Positions of `rows` rows of virtual particles, column by column, from the plate line
    /// (d = 0) down to d = -(rows - 1) dx.
    pub fn virtual_positions(&self, rows: usize) -> Vec<Vector<N>> {
        let mut out = Vec::with_capacity(self.columns() * rows);
        for c in 0..self.columns() {
            let s = self.column_s(c);
            for row in 0..rows {
                out.push(self.point(s, -(row as f64) * self.dx));
            }
        }
        out
    }

    /// Position of the interior point of column c (at d = +dx).
    #[inline]
    pub fn interior_point(&self, c: usize) -> Vector<N> {
        self.point(self.column_s(c), self.dx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_orthonormal_and_downhill() {
        let p = Plate::new(30.0, 0.1);
        assert!((p.t.norm() - 1.0).abs() < 1e-15 && p.t.dot(&p.n).abs() < 1e-15);
        assert!(p.t.y < 0.0, "downhill goes down");
        assert!(p.n.y > 0.0, "normal points up into the fluid");
        let x = p.point(0.3, 0.2);
        assert!((p.s(&x) - 0.3).abs() < 1e-14 && (p.d(&x) - 0.2).abs() < 1e-14);
    }

    #[test]
    fn a_wall_integrates_its_own_motion() {
        let dt = 1e-3;
        let mut fixed = Plate::new(30.0, 0.1);
        fixed.advance(dt, dt);
        assert_eq!((fixed.origin, fixed.displacement), (Vec2::zeros(), 0.0));
        // A sinusoidal prescribed motion: the velocity over each step is the one at its start,
        // the displacement the sum of v(t_k) dt, the origin moved along -n by it.
        let p = Prescribed {
            velocity: 0.2,
            amplitude: 0.5,
            angular_frequency: 40.0,
        };
        let mut w = Plate::new(30.0, 0.1).with_motion(Motion::Prescribed(p));
        let mut s = 0.0;
        for k in 0..100 {
            assert_eq!(w.velocity, p.at(k as f64 * dt));
            s += p.at(k as f64 * dt) * dt;
            w.advance((k + 1) as f64 * dt, dt);
        }
        assert!((w.displacement - s).abs() < 1e-15);
        assert!((w.origin + w.n * s).norm() < 1e-15);
        assert!(
            (w.d(&Vec2::zeros()) - s).abs() < 1e-15,
            "the fluid side grew by s"
        );
        // An input-driven wall keeps the velocity it is given.
        let mut i = Plate::new(0.0, 0.1).with_motion(Motion::Input);
        i.velocity = -0.3;
        i.advance(dt, dt);
        assert_eq!((i.velocity, i.displacement), (-0.3, -0.3 * dt));
    }

    #[test]
    fn columns_grow_only() {
        let mut p = Plate::new(0.0, 0.1);
        assert!(p.cover(-0.25, 0.31));
        assert_eq!((p.k_min, p.k_max), (-3, 4));
        assert!(!p.cover(-0.1, 0.1));
        assert!(p.cover(0.0, 0.55));
        assert_eq!((p.k_min, p.k_max), (-3, 6));
        assert_eq!(p.virtual_positions(4).len(), 40);
    }
}
