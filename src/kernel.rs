//! Smoothing kernels, each with W, dW/dr and d2W/dr2, in N = 1, 2 or 3 dimensions.
//!
//! Kernels are generic parameters of the schemes (as in salva), so the hot loops inline them. A
//! kernel type carries its dimension (`CubicSplineKernel<N>` implements `Kernel<N>`), so a
//! generic operator cannot pair a 2D kernel with 3D positions; `CubicSpline` and
//! `QuinticSpline` are the 2D ones. The dimension enters only through the normalisation
//! w0 = sigma_N / h^N, one table per kernel.

use std::f64::consts::PI;

/// A radially symmetric smoothing kernel in N dimensions, of compact support
/// `support_factor() * h`. `Kernel` alone means the 2D one.
pub trait Kernel<const N: usize = 2>: Copy + Send + Sync + std::fmt::Debug + 'static {
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

/// w0 = num / (den h^N) from a kernel's table of (num, den) for N = 1, 2, 3, the product
/// evaluated left to right: in 2D exactly the expression num / (den * h * h).
#[inline]
fn normalisation<const N: usize>(table: &[(f64, f64); 3], h: f64) -> f64 {
    const {
        assert!(
            N >= 1 && N <= 3,
            "kernels are normalised in 1, 2 and 3 dimensions"
        )
    };
    let (num, mut den) = table[N - 1];
    for _ in 0..N {
        den *= h;
    }
    num / den
}

/// Cubic B-spline, Fang 2006 eq. (22): support 2h, W = w0 (2/3 - q^2 + q^3/2) for q < 1 and
/// w0 (2 - q)^3 / 6 for 1 <= q < 2, w0 = 15/(7 pi h^2) in 2D (Fang's), 3/(2 pi h^3) in 3D and
/// 1/h in 1D (Monaghan 1992's 10/(7 pi h^2), 1/(pi h^3) and 2/(3 h) for the form
/// 1 - 3/2 q^2 + 3/4 q^3, which is 3/2 times this one).
#[derive(Debug, Clone, Copy)]
pub struct CubicSplineKernel<const N: usize> {
    h: f64,
    inv_h: f64,
    w0: f64,
}

/// The 2D cubic spline.
pub type CubicSpline = CubicSplineKernel<2>;

/// (num, den) of w0 = num / (den h^N) for N = 1, 2, 3.
const CUBIC_NORMALISATION: [(f64, f64); 3] = [(1.0, 1.0), (15.0, 7.0 * PI), (3.0, 2.0 * PI)];

impl<const N: usize> CubicSplineKernel<N> {
    pub fn new(h: f64) -> Self {
        Self {
            h,
            inv_h: 1.0 / h,
            w0: normalisation::<N>(&CUBIC_NORMALISATION, h),
        }
    }
}

impl<const N: usize> Kernel<N> for CubicSplineKernel<N> {
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

/// Quintic spline used by King & Lind 2021 (Morris, Fox & Zhu 1997): support 3h,
/// W = w0 [(3 - q)^5 - 6 (2 - q)^5 + 15 (1 - q)^5] (each term where positive),
/// w0 = 7/(478 pi h^2) in 2D, 1/(120 pi h^3) in 3D, 1/(120 h) in 1D. (The 3D value 3/(359 pi h^3)
/// found in the literature is 0.3 % too large: the bracket integrates to exactly 120 pi over the
/// ball of radius 3.)
#[derive(Debug, Clone, Copy)]
pub struct QuinticSplineKernel<const N: usize> {
    h: f64,
    inv_h: f64,
    w0: f64,
}

/// The 2D quintic spline.
pub type QuinticSpline = QuinticSplineKernel<2>;

/// (num, den) of w0 = num / (den h^N) for N = 1, 2, 3.
const QUINTIC_NORMALISATION: [(f64, f64); 3] = [(1.0, 120.0), (7.0, 478.0 * PI), (1.0, 120.0 * PI)];

impl<const N: usize> QuinticSplineKernel<N> {
    pub fn new(h: f64) -> Self {
        Self {
            h,
            inv_h: 1.0 / h,
            w0: normalisation::<N>(&QUINTIC_NORMALISATION, h),
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

impl<const N: usize> Kernel<N> for QuinticSplineKernel<N> {
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
    use crate::dim::{Lattice, Vector};
    use rand::{Rng, SeedableRng};

    /// sum_j dx^N W(|x_j - c|) and sum_j dx^N grad W over the lattice of spacing `dx`, about
    /// the point c = (shift, shift / 2, ...), off the lattice.
    fn lattice_sums<const N: usize, K: Kernel<N>>(k: &K, dx: f64, shift: f64) -> (f64, Vector<N>) {
        let n = (k.radius() / dx).ceil() as i64 + 2;
        let vol = dx.powi(N as i32);
        let c = Vector::<N>::from_fn(|a, _| shift / (a + 1) as f64);
        let (mut s, mut g) = (0.0, Vector::<N>::zeros());
        for p in Lattice::<N>::cube(-n, n + 1).points(dx, 0.0) {
            let x = p - c;
            let r = x.norm();
            s += vol * k.w(r);
            g += x * (vol * k.dw_over_r(r));
        }
        (s, g)
    }

    /// Through the trait, in 1, 2 and 3 dimensions: the kernel sums to 1 over a fine lattice
    /// (where the sum is the integral to far below the tolerance), wherever the lattice sits
    /// under it, and its gradient sums to 0 (to the size of W' times the tolerance).
    fn unit_integral<const N: usize, K: Kernel<N>>(k: &K, per_h: f64) {
        let dx = k.h() / per_h;
        for shift in [0.0, 0.37 * dx] {
            let (s, g) = lattice_sums(k, dx, shift);
            assert!((s - 1.0).abs() < 1e-6, "N = {N}, {k:?}: {s}");
            assert!(
                g.norm() * k.h() < 1e-6 * k.w(0.0) * k.h().powi(N as i32),
                "{g}"
            );
        }
    }

    #[test]
    fn kernels_integrate_to_one_on_a_fine_lattice_in_one_two_and_three_dimensions() {
        unit_integral(&CubicSplineKernel::<1>::new(0.2), 40.0);
        unit_integral(&CubicSpline::new(0.2), 40.0);
        unit_integral(&CubicSplineKernel::<3>::new(0.2), 12.0);
        unit_integral(&QuinticSplineKernel::<1>::new(0.2), 40.0);
        unit_integral(&QuinticSpline::new(0.2), 40.0);
        unit_integral(&QuinticSplineKernel::<3>::new(0.2), 12.0);
    }

    /// The 2D normalisations are the papers' expressions, bit for bit (the goldens depend on it).
    #[test]
    fn two_dimensional_normalisation_is_the_papers_expression() {
        for h in [0.013, 0.3, 1.0, 7.7] {
            assert_eq!(CubicSpline::new(h).w0, 15.0 / (7.0 * PI * h * h));
            assert_eq!(QuinticSpline::new(h).w0, 7.0 / (478.0 * PI * h * h));
        }
    }

    /// Positive inside the support and exactly zero (value and derivatives) outside it; the pair
    /// gradient grad_i W_ij = x_ij (1/r) dW/dr is exactly antisymmetric, grad_j W_ji = -grad_i
    /// W_ij.
    fn support_and_antisymmetry<const N: usize, K: Kernel<N>>(k: &K) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(N as u64 + 100);
        for _ in 0..2000 {
            let r = rng.gen_range(0.0..2.0 * k.radius());
            if r < k.radius() * (1.0 - 1e-9) {
                assert!(k.w(r) > 0.0 && k.dw(r) <= 0.0, "r = {r}");
            } else if r > k.radius() {
                assert_eq!(
                    (k.w(r), k.dw(r), k.d2w(r), k.dw_over_r(r)),
                    (0.0, 0.0, 0.0, 0.0)
                );
                assert_eq!(k.w_and_dw_over_r(r), (0.0, 0.0));
            }
            let xi = Vector::<N>::from_fn(|_, _| rng.gen_range(-1.0..1.0) * k.radius());
            let xj = Vector::<N>::from_fn(|_, _| rng.gen_range(-1.0..1.0) * k.radius());
            let (xij, xji) = (xi - xj, xj - xi);
            let gij = xij * k.dw_over_r(xij.norm());
            let gji = xji * k.dw_over_r(xji.norm());
            assert_eq!(gij, -gji);
        }
    }

    #[test]
    fn compact_support_and_antisymmetric_gradients() {
        support_and_antisymmetry(&CubicSplineKernel::<1>::new(0.1));
        support_and_antisymmetry(&CubicSpline::new(0.1));
        support_and_antisymmetry(&CubicSplineKernel::<3>::new(0.1));
        support_and_antisymmetry(&QuinticSpline::new(0.1));
        support_and_antisymmetry(&QuinticSplineKernel::<3>::new(0.1));
    }

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
