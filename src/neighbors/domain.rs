//! The computational domain as the pair interactions see it: open, or periodic along x.
//!
//! Every pair vector x_ij = x_i - x_j in the solver goes through [`Domain::delta`], so
//! periodicity lives in one place (as in PointNeighbors.jl's `PeriodicBox`): a particle near one
//! end of a periodic channel sees the particles near the other end at their nearest image, and no
//! particle is stored twice.

use crate::Vec2;
use serde::{Deserialize, Serialize};

/// Open (unbounded) or periodic along x with period `period_x` over [0, period_x).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Domain {
    /// Period along x [m]; `None` for an open domain.
    pub period_x: Option<f64>,
}

impl Domain {
    /// An open domain: x_ij is the plain difference.
    pub const OPEN: Domain = Domain { period_x: None };

    /// A domain periodic along x with period `l` over [0, l).
    pub fn periodic_x(l: f64) -> Self {
        assert!(l > 0.0 && l.is_finite(), "period must be positive");
        Self { period_x: Some(l) }
    }

    /// x_a - x_b at the nearest periodic image. In an open domain exactly `a - b`.
    #[inline]
    pub fn delta(&self, a: &Vec2, b: &Vec2) -> Vec2 {
        let mut d = a - b;
        if let Some(l) = self.period_x {
            if d.x > 0.5 * l {
                d.x -= l;
            } else if d.x < -0.5 * l {
                d.x += l;
            }
        }
        d
    }

    /// A position brought back into the periodic box [0, period_x) (unchanged in an open domain).
    #[inline]
    pub fn wrap(&self, mut x: Vec2) -> Vec2 {
        if let Some(l) = self.period_x {
            x.x = x.x.rem_euclid(l);
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_domain_is_the_plain_difference() {
        let (a, b) = (Vec2::new(0.3, -1.0), Vec2::new(-7.0, 2.5));
        assert_eq!(Domain::OPEN.delta(&a, &b), a - b);
        assert_eq!(Domain::OPEN.wrap(a), a);
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
    }
}
