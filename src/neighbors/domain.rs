//! The computational domain as the pair interactions see it: open, or periodic along any of its
//! axes.
//!
//! Every pair vector x_ij = x_i - x_j in the solver goes through [`Domain::delta`], so
//! periodicity lives in one place (as in PointNeighbors.jl's `PeriodicBox`): a particle near one
//! end of a periodic channel sees the particles near the other end at their nearest image, and no
//! particle is stored twice.

use crate::dim::Vector;
use serde::{Deserialize, Serialize};

/// Open (unbounded) or periodic along x, y and/or z, with period l over [0, l) on each
/// periodic axis. The same value serves positions of any dimension N; only the first N axes
/// count, and the neighbour grid refuses a period on an axis the positions do not have.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Domain {
    /// Period along x \[m\]; `None` if open along x.
    pub period_x: Option<f64>,
    /// Period along y \[m\]; `None` if open along y.
    pub period_y: Option<f64>,
    /// Period along z \[m\] (3D); `None` if open along z.
    pub period_z: Option<f64>,
}

impl Domain {
    /// An open domain: x_ij is the plain difference.
    pub const OPEN: Domain = Domain {
        period_x: None,
        period_y: None,
        period_z: None,
    };

    /// A domain periodic along x with period `l` over [0, l).
    pub fn periodic_x(l: f64) -> Self {
        Self::OPEN.with_period(0, l)
    }

    /// This domain made periodic along `axis` (0 = x, 1 = y, 2 = z) with period `l` over
    /// [0, l).
    pub fn with_period(mut self, axis: usize, l: f64) -> Self {
        assert!(l > 0.0 && l.is_finite(), "period must be positive");
        *match axis {
            0 => &mut self.period_x,
            1 => &mut self.period_y,
            2 => &mut self.period_z,
            _ => panic!("a domain has the axes 0, 1 and 2, not {axis}"),
        } = Some(l);
        self
    }

    /// The period along `axis` (0 = x, 1 = y, 2 = z; None beyond).
    #[inline]
    pub fn period(&self, axis: usize) -> Option<f64> {
        match axis {
            0 => self.period_x,
            1 => self.period_y,
            2 => self.period_z,
            _ => None,
        }
    }

    /// Whether any axis is periodic.
    #[inline]
    pub fn is_periodic(&self) -> bool {
        (0..3).any(|a| self.period(a).is_some())
    }

    /// x_a - x_b at the nearest periodic image. In an open domain exactly `a - b`.
    #[inline]
    pub fn delta<const N: usize>(&self, a: &Vector<N>, b: &Vector<N>) -> Vector<N> {
        let mut d = a - b;
        for axis in 0..N {
            if let Some(l) = self.period(axis) {
                if d[axis] > 0.5 * l {
                    d[axis] -= l;
                } else if d[axis] < -0.5 * l {
                    d[axis] += l;
                }
            }
        }
        d
    }

    /// A position brought back into the periodic box, [0, l) on every periodic axis (unchanged
    /// along open ones).
    #[inline]
    pub fn wrap<const N: usize>(&self, mut x: Vector<N>) -> Vector<N> {
        for axis in 0..N {
            if let Some(l) = self.period(axis) {
                x[axis] = x[axis].rem_euclid(l);
            }
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec2;

    #[test]
    fn open_domain_is_the_plain_difference() {
        let (a, b) = (Vec2::new(0.3, -1.0), Vec2::new(-7.0, 2.5));
        assert_eq!(Domain::OPEN.delta(&a, &b), a - b);
        assert_eq!(Domain::OPEN.wrap(a), a);
        assert!(!Domain::OPEN.is_periodic());
    }

    #[test]
    fn periodic_difference_is_the_nearest_image() {
        let d = Domain::periodic_x(1.0);
        let dx = d.delta(&Vec2::new(0.95, 0.2), &Vec2::new(0.05, 0.1));
        assert!((dx.x + 0.1).abs() < 1e-15 && (dx.y - 0.1).abs() < 1e-15);
        let dx = d.delta(&Vec2::new(0.05, 0.0), &Vec2::new(0.95, 0.0));
        assert!((dx.x - 0.1).abs() < 1e-15);
        assert!((d.wrap(Vec2::new(-0.25, 3.0)).x - 0.75).abs() < 1e-15);
        assert!((d.wrap(Vec2::new(1.25, 3.0)).x - 0.25).abs() < 1e-15);
        assert!(d.is_periodic());
    }

    #[test]
    fn each_axis_has_its_own_period() {
        let d = Domain::OPEN.with_period(1, 2.0);
        assert_eq!(
            (d.period(0), d.period(1), d.period(2)),
            (None, Some(2.0), None)
        );
        let x = d.delta(&Vec2::new(0.9, 1.9), &Vec2::new(-0.9, 0.1));
        assert!((x.x - 1.8).abs() < 1e-15 && (x.y + 0.2).abs() < 1e-15);
        assert_eq!(d.wrap(Vec2::new(5.0, -0.5)), Vec2::new(5.0, 1.5));
        let both = Domain::periodic_x(1.0).with_period(1, 2.0);
        let x = both.delta(&Vec2::new(0.9, 1.9), &Vec2::new(0.0, 0.0));
        assert!((x.x + 0.1).abs() < 1e-15 && (x.y + 0.1).abs() < 1e-15);
        // Three axes: z wraps too; a 2D position ignores it.
        let cube = both.with_period(2, 3.0);
        let p = crate::dim::Vector::<3>::new(0.2, 0.2, 2.9);
        let q = crate::dim::Vector::<3>::new(0.1, 0.1, 0.1);
        assert!((cube.delta(&p, &q).z + 0.2).abs() < 1e-15);
    }
}
