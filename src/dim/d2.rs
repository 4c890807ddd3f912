//! Two dimensions: the closed-form 2x2 symmetric eigen-decomposition and the functions built on
//! it, and the free-surface threshold of King & Lind 2021 as printed for 2D.

use super::{Dim, D2};
use crate::{Mat2, Vec2};

/// Eigen-decomposition of a symmetric 2x2 tensor, A = R diag(l1, l2) R^T with
/// R = [[c, -s], [s, c]] and l1 >= l2 (King & Lind eq. 12), in closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymEigen {
    /// cos of the angle of the first eigenvector to the x axis.
    pub c: f64,
    /// sin of that angle.
    pub s: f64,
    /// Larger eigenvalue.
    pub l1: f64,
    /// Smaller eigenvalue.
    pub l2: f64,
}

impl SymEigen {
    /// Eigenvector matrix R (columns are the eigenvectors).
    #[inline]
    pub fn rotation(&self) -> Mat2 {
        Mat2::new(self.c, -self.s, self.s, self.c)
    }

    /// R diag(f1, f2) R^T, exactly symmetric.
    #[inline]
    pub fn compose(&self, f1: f64, f2: f64) -> Mat2 {
        let (c2, s2, cs) = (self.c * self.c, self.s * self.s, self.c * self.s);
        let xy = (f1 - f2) * cs;
        Mat2::new(f1 * c2 + f2 * s2, xy, xy, f1 * s2 + f2 * c2)
    }
}

impl Dim for D2 {
    type SymEigen = SymEigen;

    /// Closed form. An isotropic tensor (A = l I) gets R = I (atan2(0, 0) = 0): no division
    /// anywhere. For an SPD tensor the smaller eigenvalue is taken as det/l1, which keeps its
    /// relative accuracy when the tensor is strongly anisotropic.
    #[inline]
    fn sym_eigen(a: &Mat2) -> SymEigen {
        let (xx, yy) = (a[(0, 0)], a[(1, 1)]);
        let xy = 0.5 * (a[(0, 1)] + a[(1, 0)]);
        let m = 0.5 * (xx + yy);
        let hd = 0.5 * (xx - yy);
        let r = hd.hypot(xy);
        let (s, c) = (0.5 * xy.atan2(hd)).sin_cos();
        let l1 = m + r;
        let det = xx.mul_add(yy, -xy * xy);
        let l2 = if l1 > 0.0 && det > 0.0 {
            det / l1
        } else {
            m - r
        };
        SymEigen { c, s, l1, l2 }
    }

    #[inline]
    fn eigenvalues(e: &SymEigen) -> Vec2 {
        Vec2::new(e.l1, e.l2)
    }

    #[inline]
    fn with_eigenvalues(e: &SymEigen, l: &Vec2) -> SymEigen {
        SymEigen {
            l1: l[0],
            l2: l[1],
            ..*e
        }
    }

    #[inline]
    fn eigenvectors(e: &SymEigen) -> Mat2 {
        e.rotation()
    }

    #[inline]
    fn compose(e: &SymEigen, f: &Vec2) -> Mat2 {
        e.compose(f[0], f[1])
    }

    /// R [[d1, off], [off, d2]] R^T written out.
    #[inline]
    fn from_eigenframe(e: &SymEigen, s: &Mat2) -> Mat2 {
        let (d1, d2, off) = (s[(0, 0)], s[(1, 1)], s[(0, 1)]);
        let (c, s) = (e.c, e.s);
        let (c2, s2, cs) = (c * c, s * s, c * s);
        let xx = d1 * c2 + d2 * s2 - 2.0 * off * cs;
        let yy = d1 * s2 + d2 * c2 + 2.0 * off * cs;
        let xy = (d1 - d2) * cs + off * (c2 - s2);
        Mat2::new(xx, xy, xy, yy)
    }

    /// Without trigonometric functions (Fang 2006 eqs. 40-44): with the angle theta of eq. (41),
    /// tan 2 theta = 2 axy / (axx - ayy), only cos 2 theta and sin 2 theta enter, and both are
    /// ratios of the components. With d = ((axx - ayy)^2 + 4 axy^2)^{1/2}:
    /// cos 2 theta = (axx - ayy)/d, sin 2 theta = 2 axy/d, the principal values are
    /// (axx + ayy)/2 +- d/2 (eqs. 43-44), and R diag(f1, f2) R^T follows from
    /// cos^2 theta = (1 + cos 2 theta)/2, cos sin = sin 2 theta / 2 (eq. 40). An isotropic tensor
    /// (d = 0) takes theta = 0. Reads axy from the upper triangle.
    #[inline]
    fn map_principal(a: &Mat2, f: impl Fn(f64) -> f64) -> Mat2 {
        let (sxx, syy, sxy) = (a[(0, 0)], a[(1, 1)], a[(0, 1)]);
        let half_diff = 0.5 * (sxx - syy);
        // d / 2. A plain square root of the sum of squares, not `hypot`: libm's `hypot` took 4 %
        // of a WCSPH step (the artificial stress calls this per particle and stage), and the
        // stresses are nowhere near the over- and underflow it guards against. It differs from
        // `hypot` in the last bit or two.
        let radius = (half_diff * half_diff + sxy * sxy).sqrt();
        let (cos2, sin2) = if radius > 0.0 {
            (half_diff / radius, sxy / radius)
        } else {
            (1.0, 0.0)
        };
        let mean = 0.5 * (sxx + syy);
        let (f1, f2) = (f(mean + radius), f(mean - radius));
        let (f_mean, f_half) = (0.5 * (f1 + f2), 0.5 * (f1 - f2));
        let xy = f_half * sin2;
        Mat2::new(f_mean + f_half * cos2, xy, xy, f_mean - f_half * cos2)
    }

    /// The eigenvalues from the trace and the discriminant, the inverse from the adjugate, both
    /// of the symmetrised m.
    #[inline]
    fn invert_spd_or_identity(m: &Mat2, min_ratio: f64) -> Mat2 {
        let (a, b, d) = (m[(0, 0)], 0.5 * (m[(0, 1)] + m[(1, 0)]), m[(1, 1)]);
        let half_tr = 0.5 * (a + d);
        let disc = (0.25 * (a - d) * (a - d) + b * b).sqrt();
        let (lmax, lmin) = (half_tr + disc, half_tr - disc);
        if !(lmax.is_finite() && lmin.is_finite()) || lmax <= 0.0 || lmin < min_ratio * lmax {
            return Mat2::identity();
        }
        let det = a * d - b * b;
        Mat2::new(d, -b, -b, a) / det
    }

    /// King & Lind 2021 eq. (36) as printed: 1.4 + 0.5 max(C^ - 1, -0.2), against div r = 2
    /// under full support and about 1 on a flat surface.
    #[inline]
    fn surface_threshold(c_hat: f64) -> f64 {
        1.4 + 0.5 * (c_hat - 1.0).max(-0.2)
    }

    /// Along the surface's tangent t = (-n_y, n_x): `(a t . v) t`.
    #[inline]
    fn tangential(n: &Vec2, v: &Vec2, a: f64) -> Vec2 {
        let t = Vec2::new(-n.y, n.x);
        a * t.dot(v) * t
    }

    /// `t . g t` with the tangent t = (-n_y, n_x).
    #[inline]
    fn tangential_trace(n: &Vec2, g: &Mat2) -> f64 {
        let t = Vec2::new(-n.y, n.x);
        t.dot(&(g * t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::symmetric;
    use nalgebra::SymmetricEigen;
    use rand::{Rng, SeedableRng};

    fn close(a: &Mat2, b: &Mat2, tol: f64) -> bool {
        (a - b).abs().max() <= tol * (1.0 + b.abs().max())
    }

    /// Random SPD tensors with condition numbers up to 1e6, and a few special ones.
    fn spd_samples() -> Vec<Mat2> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(28);
        let mut out: Vec<Mat2> = (0..2000)
            .map(|_| {
                let t: f64 = rng.gen_range(0.0..std::f64::consts::PI);
                let r = Mat2::new(t.cos(), -t.sin(), t.sin(), t.cos());
                let l1 = 10f64.powf(rng.gen_range(-3.0..3.0));
                let l2 = l1 * 10f64.powf(rng.gen_range(-6.0..0.0));
                r * Mat2::new(l1, 0.0, 0.0, l2) * r.transpose()
            })
            .collect();
        out.push(Mat2::identity() * 2.0);
        out.push(Mat2::new(3.0, 0.0, 0.0, 1.0));
        out.push(Mat2::new(1.0, 0.0, 0.0, 3.0));
        out.push(Mat2::new(2.0, 1.0, 1.0, 2.0));
        out
    }

    /// The closed form against nalgebra's iterative `SymmetricEigen` on random SPD tensors: the
    /// same eigenvalues to round-off of the larger one, the same eigenvectors up to sign where
    /// the eigenvalues are apart (to round-off over the gap), and A recomposed to round-off.
    #[test]
    fn closed_form_matches_nalgebra_symmetric_eigen_on_random_spd_tensors() {
        for a in spd_samples() {
            let e = D2::sym_eigen(&a);
            let g = SymmetricEigen::new(a);
            let (k1, k2) = if g.eigenvalues[0] >= g.eigenvalues[1] {
                (0, 1)
            } else {
                (1, 0)
            };
            let scale = e.l1;
            assert!(e.l1 >= e.l2 && e.l2 > 0.0, "{a}");
            assert!(
                (e.l1 - g.eigenvalues[k1]).abs() <= 1e-14 * scale,
                "{a}: {e:?}"
            );
            assert!(
                (e.l2 - g.eigenvalues[k2]).abs() <= 1e-14 * scale,
                "{a}: {e:?}"
            );
            let gap = (e.l1 - e.l2) / scale;
            if gap > 1e-8 {
                let r = e.rotation();
                for (k, kg) in [(0, k1), (1, k2)] {
                    let dot = r.column(k).dot(&g.eigenvectors.column(kg)).abs();
                    assert!((dot - 1.0).abs() < 1e-14 / gap, "{a}: {dot}");
                }
            }
            assert!(close(&e.compose(e.l1, e.l2), &a, 1e-14), "{a}");
        }
    }

    /// Every 2D closed form against the N-generic function of [`symmetric`] (Jacobi), to
    /// round-off: principal-value maps on tensors with principal values of both signs, the
    /// checked inverse, the rotation back from the eigenframe.
    #[test]
    fn closed_forms_match_the_generic_functions() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(29);
        for a in spd_samples() {
            let shift = rng.gen_range(-1.0..1.0) * a.trace();
            let s = a - Mat2::identity() * shift;
            let f = |x: f64| if x > 0.0 { -0.3 * x } else { 0.0 };
            let (closed, generic) = (D2::map_principal(&s, f), symmetric::Eigen::new(&s).map(f));
            assert!(close(&closed, &generic, 1e-13), "{s}: {closed} {generic}");
            assert_eq!(closed, closed.transpose());
            let (inv, generic) = (
                D2::invert_spd_or_identity(&a, 1e-2),
                symmetric::Eigen::new(&a).inverse_or_identity(1e-2),
            );
            // Relative to the inverse's scale, 1 / l2 (the identity when both fall back).
            assert!(
                (inv - generic).abs().max() <= 1e-13 * inv.abs().max().max(1.0),
                "{a}: {inv} {generic}"
            );
            // Any symmetric tensor taken into the eigenframe and back.
            let e = D2::sym_eigen(&a);
            let t = Mat2::new(0.3, -1.1, -1.1, 2.0);
            let r = e.rotation();
            let back = D2::from_eigenframe(&e, &(r.transpose() * t * r));
            assert!(close(&back, &t, 1e-14), "{a}: {back}");
            assert_eq!(back, back.transpose());
        }
    }

    #[test]
    fn isotropic_and_round_trip() {
        let a = Mat2::new(3.0, 1.2, 1.2, 0.7);
        let e = D2::sym_eigen(&a);
        assert!(close(&D2::compose(&e, &D2::eigenvalues(&e)), &a, 1e-14));
        let i = D2::sym_eigen(&(Mat2::identity() * 2.0));
        assert_eq!((i.c, i.s, i.l1, i.l2), (1.0, 0.0, 2.0, 2.0));
        let moved = D2::with_eigenvalues(&e, &Vec2::new(5.0, 4.0));
        assert_eq!((moved.c, moved.s, moved.l1, moved.l2), (e.c, e.s, 5.0, 4.0));
        assert_eq!(D2::eigenvectors(&e), e.rotation());
    }
}
