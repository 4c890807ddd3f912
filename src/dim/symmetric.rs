//! The tensor functions of [`super::Dim`] for any N from an eigen-decomposition by the cyclic
//! Jacobi method: what a dimension without closed forms delegates to, and the reference the 2D
//! closed forms are tested against.
//!
//! Why not nalgebra's `SymmetricEigen`: its eigenvalues are right, but its eigenvectors can be
//! off far beyond round-off (measured with nalgebra 0.33.3: R diag(l) R^T differs from a benign
//! 3x3 SPD tensor, eigenvalues 2.86, 2.78 and 0.76, by 2e-10 relative; nalgebra issue #1109 is
//! the same defect in 4x4), and a log-conformation step recomposes the tensor from its
//! eigenvectors every time. Jacobi rotations reproduce A to a few ulps, in a fixed sequence of
//! operations (deterministic), and need nothing of N beyond a loop bound.

use super::{Tensor, Vector};

/// Sweeps after which the Jacobi iteration gives up (it converges quadratically: 3x3 tensors
/// take about five).
const MAX_SWEEPS: usize = 64;

/// An eigen-decomposition A = R diag(values) R^T, eigenvalues descending, eigenvectors the
/// columns of R.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eigen<const N: usize> {
    pub values: Vector<N>,
    pub vectors: Tensor<N>,
}

impl<const N: usize> Eigen<N> {
    /// The eigen-decomposition of the symmetric part of `a` by cyclic Jacobi rotations (Golub &
    /// Van Loan, Matrix Computations, section 8.5): each rotation zeroes one off-diagonal entry;
    /// an entry below eps (a_pp a_qq)^{1/2} counts as zero, which keeps the small eigenvalues of
    /// an SPD tensor to their relative accuracy (Demmel & Veselic 1992). All NaN if `a` has an
    /// entry that is not finite.
    pub fn new(a: &Tensor<N>) -> Self {
        if !a.iter().all(|x| x.is_finite()) {
            return Self {
                values: Vector::<N>::repeat(f64::NAN),
                vectors: Tensor::<N>::repeat(f64::NAN),
            };
        }
        let mut m = (a + a.transpose()) * 0.5;
        let mut v = Tensor::<N>::identity();
        for _ in 0..MAX_SWEEPS {
            let mut rotated = false;
            for p in 0..N {
                for q in p + 1..N {
                    let apq = m[(p, q)];
                    if apq.abs() <= f64::EPSILON * (m[(p, p)] * m[(q, q)]).abs().sqrt() {
                        m[(p, q)] = 0.0;
                        m[(q, p)] = 0.0;
                        continue;
                    }
                    rotated = true;
                    // The rotation by theta with tan 2 theta = 2 a_pq / (a_qq - a_pp), through
                    // t = tan theta, the smaller root (|theta| <= pi/4).
                    let zeta = (m[(q, q)] - m[(p, p)]) / (2.0 * apq);
                    let t = if zeta.abs() > 1e150 {
                        0.5 / zeta
                    } else {
                        zeta.signum() / (zeta.abs() + (zeta * zeta + 1.0).sqrt())
                    };
                    let c = 1.0 / (t * t + 1.0).sqrt();
                    let s = t * c;
                    m[(p, p)] -= t * apq;
                    m[(q, q)] += t * apq;
                    m[(p, q)] = 0.0;
                    m[(q, p)] = 0.0;
                    for r in 0..N {
                        if r != p && r != q {
                            let (mrp, mrq) = (m[(r, p)], m[(r, q)]);
                            m[(r, p)] = c * mrp - s * mrq;
                            m[(p, r)] = m[(r, p)];
                            m[(r, q)] = s * mrp + c * mrq;
                            m[(q, r)] = m[(r, q)];
                        }
                        let (vrp, vrq) = (v[(r, p)], v[(r, q)]);
                        v[(r, p)] = c * vrp - s * vrq;
                        v[(r, q)] = s * vrp + c * vrq;
                    }
                }
            }
            if !rotated {
                break;
            }
        }
        Self::from_unsorted(&m.diagonal(), &v)
    }

    /// From eigenvalues in any order and their eigenvectors (columns, in the same order).
    pub fn from_unsorted(values: &Vector<N>, vectors: &Tensor<N>) -> Self {
        let mut order: [usize; N] = std::array::from_fn(|k| k);
        order.sort_by(|&i, &j| values[j].total_cmp(&values[i]));
        Self {
            values: Vector::<N>::from_fn(|k, _| values[order[k]]),
            vectors: Tensor::<N>::from_fn(|r, k| vectors[(r, order[k])]),
        }
    }

    /// R diag(f) R^T, exactly symmetric.
    pub fn compose(&self, f: &Vector<N>) -> Tensor<N> {
        symmetrise(self.vectors * Tensor::<N>::from_diagonal(f) * self.vectors.transpose())
    }

    /// R S R^T for the symmetric S whose upper triangle is `s`, exactly symmetric.
    pub fn from_eigenframe(&self, s: &Tensor<N>) -> Tensor<N> {
        let s = Tensor::<N>::from_fn(|i, j| if i <= j { s[(i, j)] } else { s[(j, i)] });
        symmetrise(self.vectors * s * self.vectors.transpose())
    }

    /// R diag(f(l)) R^T (see [`super::Dim::map_principal`]).
    pub fn map(&self, f: impl Fn(f64) -> f64) -> Tensor<N> {
        self.compose(&self.values.map(f))
    }

    /// R diag(1/l) R^T, or I where the decomposed tensor is not safely positive definite (see
    /// [`super::Dim::invert_spd_or_identity`]).
    pub fn inverse_or_identity(&self, min_ratio: f64) -> Tensor<N> {
        let (lmax, lmin) = (self.values[0], self.values[N - 1]);
        if !(lmax.is_finite() && lmin.is_finite()) || lmax <= 0.0 || lmin < min_ratio * lmax {
            return Tensor::<N>::identity();
        }
        self.map(|l| 1.0 / l)
    }
}

/// (m + m^T) / 2.
fn symmetrise<const N: usize>(m: Tensor<N>) -> Tensor<N> {
    (m + m.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SymmetricEigen;
    use rand::{Rng, SeedableRng};

    /// In 2D and 3D, on random SPD tensors with condition numbers up to 1e4 and on tensors with
    /// repeated eigenvalues: descending eigenvalues equal to the constructed ones, orthonormal
    /// eigenvectors, A recomposed to round-off, the inverse an inverse, f(A) = A^2 for
    /// f(l) = l^2, R S R^T from the eigenframe; and the fallbacks.
    fn check<const N: usize>() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(N as u64);
        let mut worst = 0.0f64;
        for case in 0..2000 {
            // The eigenvectors of a random symmetric matrix: an orthogonal matrix.
            let q = Eigen::new(&Tensor::<N>::from_fn(|_, _| rng.gen_range(-1.0..1.0))).vectors;
            let mut l = Vector::<N>::from_fn(|_, _| 10f64.powf(rng.gen_range(-2.0..2.0)));
            if case % 10 == 0 {
                l[1] = l[0]; // a repeated eigenvalue
            }
            let a = q * Tensor::<N>::from_diagonal(&l) * q.transpose();
            let e = Eigen::new(&a);
            let scale = l.max();
            for k in 1..N {
                assert!(e.values[k - 1] >= e.values[k]);
            }
            let mut sorted: Vec<f64> = l.iter().copied().collect();
            sorted.sort_by(|x, y| y.total_cmp(x));
            for (value, exact) in e.values.iter().zip(&sorted) {
                assert!((value - exact).abs() < 1e-14 * scale, "{a} {e:?}");
            }
            let orth = (e.vectors.transpose() * e.vectors - Tensor::<N>::identity()).norm();
            assert!(orth < 1e-14, "{orth:e}");
            let err = (e.compose(&e.values) - a).norm() / scale;
            worst = worst.max(err);
            assert!(err < 1e-14, "{a}: {err:e}");
            let inv = e.inverse_or_identity(1e-6);
            assert!((inv * a - Tensor::<N>::identity()).norm() < 1e-12 * scale / l.min());
            assert!((e.map(|x| x * x) - a * a).norm() < 1e-13 * scale * scale);
            let s = Tensor::<N>::from_fn(|i, j| (i + 2 * j) as f64 - 1.5);
            let s = s + s.transpose();
            let framed = e.from_eigenframe(&(e.vectors.transpose() * s * e.vectors));
            assert!((framed - s).norm() < 1e-13 * s.norm());
            assert_eq!(framed, framed.transpose());
        }
        println!("{N}D Jacobi: worst |R diag(l) R^T - A| / l_max = {worst:.1e}");
        let mut thin = Tensor::<N>::identity();
        thin[(0, 0)] = 1e-3;
        assert_eq!(
            Eigen::new(&thin).inverse_or_identity(1e-2),
            Tensor::<N>::identity()
        );
        let broken = Eigen::new(&(thin * f64::NAN));
        assert!(broken.values.iter().all(|x| x.is_nan()));
        assert_eq!(broken.inverse_or_identity(1e-2), Tensor::<N>::identity());
        // Diagonal in, diagonal out: no rotation at all.
        let d = Tensor::<N>::from_diagonal(&Vector::<N>::from_fn(|k, _| (k + 1) as f64));
        let e = Eigen::new(&d);
        assert_eq!(e.compose(&e.values), d);
    }

    #[test]
    fn jacobi_functions_in_two_and_three_dimensions() {
        check::<2>();
        check::<3>();
    }

    /// The eigenvalues against nalgebra's `SymmetricEigen` (whose eigenvalues, unlike its
    /// eigenvectors, are accurate), on random symmetric 3x3 tensors of both signs.
    #[test]
    fn eigenvalues_match_nalgebra_in_three_dimensions() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(33);
        for _ in 0..2000 {
            let a = Tensor::<3>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            let a = a + a.transpose();
            let e = Eigen::new(&a);
            let mut g: Vec<f64> = SymmetricEigen::new(a).eigenvalues.iter().copied().collect();
            g.sort_by(|x, y| y.total_cmp(x));
            for (value, reference) in e.values.iter().zip(&g) {
                assert!((value - reference).abs() < 1e-14 * a.norm(), "{a}");
            }
        }
    }
}
