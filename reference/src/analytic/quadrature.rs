//! Gauss-Legendre quadrature for the analytic solutions: fixed rules and an adaptive composite
//! rule.
//!
//! An n-point Gauss-Legendre rule integrates polynomials of degree 2n - 1 exactly; for a function
//! analytic in a Bernstein ellipse of parameter rho around the interval its error falls like
//! rho^(-2n) (Trefethen, *Approximation Theory and Approximation Practice*, 2013, Theorem 19.3),
//! so a 20-point rule on an interval short against the distance to the nearest singularity is
//! at round-off. The nodes are computed here (Newton on the three-term Legendre recurrence,
//! Golub & Welsch 1969 give the same numbers) rather than tabulated, so there is no transcription
//! error to check; the unit tests integrate polynomials of degree 2n - 1 exactly.

use std::sync::OnceLock;

/// Points of the rule used by [`gauss_legendre`] and [`adaptive`].
pub const ORDER: usize = 20;

/// Nodes x_i and weights w_i of the n-point Gauss-Legendre rule on [-1, 1], ascending.
pub fn rule(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        // Tricomi's initial guess, then Newton on P_n.
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * z * p1 - (kf - 1.0) * p0) / kf;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { z } else { p1 };
            let pnm1 = if n == 1 { 1.0 } else { p0 };
            // P_n'(z) = n (z P_n - P_{n-1}) / (z^2 - 1).
            dp = n as f64 * (z * pn - pnm1) / (z * z - 1.0);
            let dz = pn / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        let wi = 2.0 / ((1.0 - z * z) * dp * dp);
        w[i] = wi;
        w[n - 1 - i] = wi;
    }
    (x, w)
}

fn rule20() -> &'static (Vec<f64>, Vec<f64>) {
    static RULE: OnceLock<(Vec<f64>, Vec<f64>)> = OnceLock::new();
    RULE.get_or_init(|| rule(ORDER))
}

/// The 20-point Gauss-Legendre approximation of the integral of `f` over [a, b].
pub fn gauss_legendre(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> f64 {
    let (x, w) = rule20();
    let (c, r) = (0.5 * (a + b), 0.5 * (b - a));
    let mut s = 0.0;
    for (xi, wi) in x.iter().zip(w) {
        s += wi * f(c + r * xi);
    }
    s * r
}

/// Adaptive composite Gauss-Legendre: [a, b] is cut into `panels` equal panels; a panel is
/// accepted when its 20-point value and the sum of the 20-point values on its two halves differ
/// by less than its share of `tol` (absolute), otherwise both halves are refined the same way (at
/// most 30 levels). The halves' sum is returned, so the error is normally far below the
/// difference used as its estimate. Panels are visited in a fixed order: the result does not
/// depend on anything but the arguments.
pub fn adaptive(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, tol: f64, panels: usize) -> f64 {
    let panels = panels.max(1);
    let h = (b - a) / panels as f64;
    let mut total = 0.0;
    for k in 0..panels {
        let (lo, hi) = (
            a + k as f64 * h,
            if k + 1 == panels {
                b
            } else {
                a + (k + 1) as f64 * h
            },
        );
        let whole = gauss_legendre(f, lo, hi);
        total += refine(f, lo, hi, whole, tol / panels as f64, 0);
    }
    total
}

fn refine(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, whole: f64, tol: f64, depth: u32) -> f64 {
    let m = 0.5 * (a + b);
    let left = gauss_legendre(f, a, m);
    let right = gauss_legendre(f, m, b);
    if (left + right - whole).abs() <= tol || depth >= 30 {
        left + right
    } else {
        refine(f, a, m, left, 0.5 * tol, depth + 1) + refine(f, m, b, right, 0.5 * tol, depth + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_integrate_polynomials_of_degree_2n_minus_1_exactly() {
        for n in [1, 2, 5, 10, 20] {
            let (x, w) = rule(n);
            // sum of weights = 2; int_{-1}^{1} x^k = 2/(k+1) for even k, 0 for odd k.
            for k in 0..2 * n {
                let num: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                let exact = if k % 2 == 0 {
                    2.0 / (k as f64 + 1.0)
                } else {
                    0.0
                };
                assert!(
                    (num - exact).abs() < 1e-14,
                    "n = {n}, x^{k}: {num} vs {exact}"
                );
            }
            // ...and not degree 2n: the rule is not exact one degree higher.
            let k = 2 * n;
            let num: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
            if n <= 5 {
                assert!((num - 2.0 / (k as f64 + 1.0)).abs() > 1e-6, "n = {n}");
            }
        }
    }

    #[test]
    fn adaptive_rule_reaches_its_tolerance_on_hard_integrands() {
        // An integrable endpoint singularity and a sharp peak.
        let exact_sqrt = 2.0 / 3.0;
        let got = adaptive(&mut |x: f64| x.sqrt(), 0.0, 1.0, 1e-12, 1);
        assert!((got - exact_sqrt).abs() < 1e-12, "{got}");
        let eps: f64 = 1e-3;
        let exact_peak = 2.0 * (1.0 / eps).atan() / eps;
        let got = adaptive(&mut |x: f64| 1.0 / (x * x + eps * eps), -1.0, 1.0, 1e-9, 4);
        assert!(
            (got - exact_peak).abs() < 1e-9 * exact_peak,
            "{got} vs {exact_peak}"
        );
    }
}
