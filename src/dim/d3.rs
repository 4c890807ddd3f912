//! Three dimensions: every tensor function through the N-generic Jacobi eigen-decomposition
//! ([`symmetric::Eigen`]), no closed forms.

use super::symmetric::Eigen;
use super::{Dim, Tensor, Vector};
use nalgebra::Const;

/// Three space dimensions.
pub type D3 = Const<3>;

impl Dim for D3 {
    type SymEigen = Eigen<3>;

    #[inline]
    fn sym_eigen(a: &Tensor<3>) -> Eigen<3> {
        Eigen::new(a)
    }

    #[inline]
    fn eigenvalues(e: &Eigen<3>) -> Vector<3> {
        e.values
    }

    #[inline]
    fn with_eigenvalues(e: &Eigen<3>, l: &Vector<3>) -> Eigen<3> {
        Eigen { values: *l, ..*e }
    }

    #[inline]
    fn eigenvectors(e: &Eigen<3>) -> Tensor<3> {
        e.vectors
    }

    #[inline]
    fn compose(e: &Eigen<3>, f: &Vector<3>) -> Tensor<3> {
        e.compose(f)
    }

    #[inline]
    fn from_eigenframe(e: &Eigen<3>, s: &Tensor<3>) -> Tensor<3> {
        e.from_eigenframe(s)
    }

    #[inline]
    fn map_principal(a: &Tensor<3>, f: impl Fn(f64) -> f64) -> Tensor<3> {
        Eigen::new(a).map(f)
    }

    #[inline]
    fn invert_spd_or_identity(m: &Tensor<3>, min_ratio: f64) -> Tensor<3> {
        Eigen::new(m).inverse_or_identity(min_ratio)
    }

    /// King & Lind 2021 eq. (36) is printed for 2D (1.4 + 0.5 max(C^ - 1, -0.2) against the
    /// full-support div r = 2); here it is scaled to the full-support value 3. Nothing in the
    /// weakly compressible schemes reads it; the incompressible scheme reads it for
    /// its free surface.
    #[inline]
    fn surface_threshold(c_hat: f64) -> f64 {
        1.5 * <super::D2 as Dim>::surface_threshold(c_hat)
    }

    #[inline]
    fn tangential(n: &Vector<3>, v: &Vector<3>, a: f64) -> Vector<3> {
        (v - n * n.dot(v)) * a
    }

    #[inline]
    fn tangential_trace(n: &Vector<3>, g: &Tensor<3>) -> f64 {
        g.trace() - n.dot(&(g * n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The D3 functions are those of the Jacobi decomposition: a rotated SPD tensor is
    /// recomposed, inverted and mapped to its square root within round-off.
    #[test]
    fn three_dimensional_tensor_functions() {
        let (a, b) = (0.7f64, -0.4f64);
        let rz = Tensor::<3>::new(a.cos(), -a.sin(), 0.0, a.sin(), a.cos(), 0.0, 0.0, 0.0, 1.0);
        let rx = Tensor::<3>::new(1.0, 0.0, 0.0, 0.0, b.cos(), -b.sin(), 0.0, b.sin(), b.cos());
        let r = rz * rx;
        let m = r * Tensor::<3>::from_diagonal(&Vector::<3>::new(4.0, 0.25, 1.0)) * r.transpose();
        let e = D3::sym_eigen(&m);
        assert!((D3::eigenvalues(&e) - Vector::<3>::new(4.0, 1.0, 0.25)).norm() < 1e-13);
        assert!((D3::compose(&e, &D3::eigenvalues(&e)) - m).norm() < 1e-13);
        let inv = D3::invert_spd_or_identity(&m, 1e-12);
        assert!((inv * m - Tensor::<3>::identity()).norm() < 1e-13);
        let root = D3::map_principal(&m, f64::sqrt);
        assert!((root * root - m).norm() < 1e-13);
        assert_eq!(
            D3::invert_spd_or_identity(&Tensor::<3>::zeros(), 1e-12),
            Tensor::<3>::identity()
        );
        assert_eq!(Eigen::new(&m), e);
    }
}
