//! Smoothing kernels in 2D, each with W, dW/dr and d2W/dr2.
//!
//! Kernels are generic parameters of the schemes (as in salva), so the hot loops inline them.

use std::f64::consts::PI;

/// A radially symmetric 2D smoothing kernel of compact support `support_factor() * h`.
pub trait Kernel: Copy + Send + Sync + std::fmt::Debug + 'static {
    /// Support radius over h (2 for the cubic spline, 3 for the quintic).
    fn support_factor(&self) -> f64;
    /// Smoothing length h.
    fn h(&self) -> f64;
    /// W(r).
    fn w(&self, r: f64) -> f64;
    /// dW/dr (<= 0 on the support).
    fn dw(&self, r: f64) -> f64;
    /// d2W/dr2.
    fn d2w(&self, r: f64) -> f64;
    /// Support radius.
    #[inline]
    fn radius(&self) -> f64 {
        self.support_factor() * self.h()
    }
    /// W(r) and (1/r) dW/dr together (one evaluation of q and of the branches on the hot path).
    #[inline]
    fn w_and_dw_over_r(&self, r: f64) -> (f64, f64) {
        (self.w(r), self.dw_over_r(r))
    }
    /// (1/r) dW/dr, so that grad_i W_ij = x_ij * dw_over_r (Fang 2006 eq. 21). Finite at r = 0.
    #[inline]
    fn dw_over_r(&self, r: f64) -> f64 {
        if r > 1e-12 * self.h() {
            self.dw(r) / r
        } else {
            0.0
        }
    }
}

/// Cubic B-spline, Fang 2006 eq. (22): support 2h, w0 = 15/(7 pi h^2) in 2D.
#[derive(Debug, Clone, Copy)]
pub struct CubicSpline {
    h: f64,
    inv_h: f64,
    w0: f64,
}

impl CubicSpline {
    pub fn new(h: f64) -> Self {
        Self {
            h,
            inv_h: 1.0 / h,
            w0: 15.0 / (7.0 * PI * h * h),
        }
    }
}

impl Kernel for CubicSpline {
    #[inline]
    fn support_factor(&self) -> f64 {
        2.0
    }
    #[inline]
    fn h(&self) -> f64 {
        self.h
    }
    #[inline]
    fn w(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        if q < 1.0 {
            self.w0 * (2.0 / 3.0 - q * q + 0.5 * q * q * q)
        } else if q < 2.0 {
            let t = 2.0 - q;
            self.w0 * t * t * t / 6.0
        } else {
            0.0
        }
    }
    #[inline]
    fn dw(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        if q < 1.0 {
            self.w0 * self.inv_h * (-2.0 * q + 1.5 * q * q)
        } else if q < 2.0 {
            let t = 2.0 - q;
            -0.5 * self.w0 * self.inv_h * t * t
        } else {
            0.0
        }
    }
    #[inline]
    fn d2w(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        let c = self.w0 * self.inv_h * self.inv_h;
        if q < 1.0 {
            c * (-2.0 + 3.0 * q)
        } else if q < 2.0 {
            c * (2.0 - q)
        } else {
            0.0
        }
    }
    #[inline]
    fn w_and_dw_over_r(&self, r: f64) -> (f64, f64) {
        // Both pieces evaluated and the value chosen by a select, not a branch: the hot pair
        // loops call this over whole lists, where q < 1 or not has no pattern (a mispredicted
        // branch per pair), and a loop without branches vectorises. Each piece is the same
        // expression as before, so the values are bitwise those of the branching form. The
        // outer piece divides by r, which may be 0 in a lane that the select drops.
        let q = r * self.inv_h;
        let t = 2.0 - q;
        let w_in = self.w0 * (2.0 / 3.0 - q * q + 0.5 * q * q * q);
        let d_in = self.w0 * self.inv_h * self.inv_h * (-2.0 + 1.5 * q);
        let w_out = self.w0 * t * t * t / 6.0;
        let d_out = -0.5 * self.w0 * self.inv_h * t * t / r;
        let inner = q < 1.0;
        let outer = q < 2.0;
        let w = if inner { w_in } else { w_out };
        let d = if inner { d_in } else { d_out };
        (if outer { w } else { 0.0 }, if outer { d } else { 0.0 })
    }
    #[inline]
    fn dw_over_r(&self, r: f64) -> f64 {
        // For q < 1, dW/dr / r = w0/h^2 (-2 + 1.5 q): no division, finite at r = 0.
        let q = r * self.inv_h;
        if q < 1.0 {
            self.w0 * self.inv_h * self.inv_h * (-2.0 + 1.5 * q)
        } else if q < 2.0 {
            let t = 2.0 - q;
            -0.5 * self.w0 * self.inv_h * t * t / r
        } else {
            0.0
        }
    }
}

/// Quintic spline used by King & Lind 2021: support 3h, w0 = 7/(478 pi h^2) in 2D.
#[derive(Debug, Clone, Copy)]
pub struct QuinticSpline {
    h: f64,
    inv_h: f64,
    w0: f64,
}

impl QuinticSpline {
    pub fn new(h: f64) -> Self {
        Self {
            h,
            inv_h: 1.0 / h,
            w0: 7.0 / (478.0 * PI * h * h),
        }
    }
    /// Sum of c_k (k - q)^p over the active pieces k = 3, 2, 1 with weights 1, -6, 15.
    #[inline]
    fn pieces(q: f64, p: i32, scale: [f64; 3]) -> f64 {
        let mut s = 0.0;
        for (k, (w, sc)) in [(3.0, 1.0), (2.0, -6.0), (1.0, 15.0)]
            .iter()
            .zip(scale)
            .map(|(&(k, w), sc)| (k, (w, sc)))
        {
            if q < k {
                s += w * sc * (k - q).powi(p);
            }
        }
        s
    }
}

impl Kernel for QuinticSpline {
    #[inline]
    fn support_factor(&self) -> f64 {
        3.0
    }
    #[inline]
    fn h(&self) -> f64 {
        self.h
    }
    #[inline]
    fn w(&self, r: f64) -> f64 {
        self.w0 * Self::pieces(r * self.inv_h, 5, [1.0; 3])
    }
    #[inline]
    fn dw(&self, r: f64) -> f64 {
        -5.0 * self.w0 * self.inv_h * Self::pieces(r * self.inv_h, 4, [1.0; 3])
    }
    #[inline]
    fn d2w(&self, r: f64) -> f64 {
        20.0 * self.w0 * self.inv_h * self.inv_h * Self::pieces(r * self.inv_h, 3, [1.0; 3])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Integral of W over the plane by the midpoint rule in polar coordinates.
    fn integral<K: Kernel>(k: &K) -> f64 {
        let n = 20000;
        let dr = k.radius() / n as f64;
        (0..n)
            .map(|i| {
                let r = (i as f64 + 0.5) * dr;
                2.0 * PI * r * k.w(r) * dr
            })
            .sum()
    }

    fn check_derivatives<K: Kernel>(k: &K) {
        let eps = 1e-7 * k.h();
        for i in 1..300 {
            let r = i as f64 / 300.0 * k.radius() * 1.01;
            let fd = (k.w(r + eps) - k.w(r - eps)) / (2.0 * eps);
            assert!(
                (fd - k.dw(r)).abs() < 1e-5 * k.w(0.0) / k.h(),
                "dW at r={r}"
            );
            let fd2 = (k.dw(r + eps) - k.dw(r - eps)) / (2.0 * eps);
            assert!(
                (fd2 - k.d2w(r)).abs() < 1e-4 * k.w(0.0) / k.h().powi(2),
                "d2W at r={r}"
            );
        }
        // Zero at the edge of the support (to round-off in q = r/h) and exactly zero beyond it.
        assert!(k.w(k.radius()).abs() < 1e-12 * k.w(0.0));
        assert_eq!(k.w(k.radius() * 1.0001), 0.0);
        assert_eq!(k.dw(k.radius() * 1.0001), 0.0);
    }

    #[test]
    fn cubic_is_normalised_with_consistent_derivatives() {
        let k = CubicSpline::new(0.3);
        assert!((integral(&k) - 1.0).abs() < 1e-8);
        check_derivatives(&k);
        // Fang section 3.2: W(0)/W(dx) = 1.8 for h = 1.5 dx (to the two digits quoted).
        let ratio = k.w(0.0) / k.w(0.3 / 1.5);
        assert!((ratio - 1.8).abs() < 0.05, "{ratio}");
    }

    #[test]
    fn quintic_is_normalised_with_consistent_derivatives() {
        let k = QuinticSpline::new(0.7);
        assert!((integral(&k) - 1.0).abs() < 1e-8);
        check_derivatives(&k);
    }

    #[test]
    fn dw_over_r_matches() {
        let k = CubicSpline::new(1.0);
        for r in [0.1, 0.5, 0.99, 1.0, 1.5, 1.99, 2.5] {
            if r < 2.0 {
                assert!((k.dw_over_r(r) - k.dw(r) / r).abs() < 1e-12);
            }
            let (w, g) = k.w_and_dw_over_r(r);
            assert_eq!((w, g), (k.w(r), k.dw_over_r(r)));
        }
    }

    /// On a lattice, sum_j V_j W_ij ~ 1 and sum_j V_j grad W_ij = 0 (Fang eq. 24).
    #[test]
    fn lattice_partition_of_unity() {
        let dx = 0.1;
        let k = CubicSpline::new(1.5 * dx);
        let (mut s, mut gx) = (0.0, 0.0);
        for i in -6..=6 {
            for j in -6..=6 {
                let (x, y) = (i as f64 * dx + 0.013, j as f64 * dx);
                let r = (x * x + y * y).sqrt();
                s += dx * dx * k.w(r);
                gx += dx * dx * x * k.dw_over_r(r);
            }
        }
        assert!((s - 1.0).abs() < 0.01, "{s}");
        assert!(gx.abs() < 0.05 / dx, "{gx}");
    }
}
