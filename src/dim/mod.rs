//! The number of space dimensions as a type.
//!
//! Positions, velocities and tensors are nalgebra's fixed-size types with a const generic
//! dimension N ([`Vector`]`<N>`, [`Tensor`]`<N>`), so generic code keeps every nalgebra method and
//! a call with a `Vec2` or `Mat2` argument infers N = 2 without annotation. What cannot be written
//! once for every N lives in the [`Dim`] trait, implemented for nalgebra's `Const<N>`:
//!
//! * the eigen-decomposition of a symmetric tensor and what is built from it (log-conformation,
//!   King & Lind 2021 eqs. 12-19; principal stresses, Fang 2006 eqs. 40-44; the Bonet & Lok
//!   1999 correction matrix of King & Lind eq. 22),
//! * the free-surface threshold on div r (King & Lind eq. 36), whose full-support value is N.
//!
//! [`D2`] (`Const<2>`, in `d2.rs`) uses closed forms, bit for bit those the solver has always
//! used; [`D3`] (`d3.rs`) delegates every tensor function to the N-generic Jacobi
//! decomposition of [`symmetric`], as a further dimension would. The small (N+1)x(N+1) solve
//! of an MLS correction is [`mls::Mls`], one impl per dimension. What is the same in
//! every dimension is written once for every N elsewhere: kernel normalisation (a table per
//! kernel in `kernel.rs`), the neighbour grid (cells per axis, a 3^N stencil), the periodic
//! domain (per axis), the square/cubic [`Lattice`], tr I = N in the rheologies.
//!
//! Generic code is written over `const N: usize` with the bound `Const<N>: Dim`:
//! ```
//! use viscosph::dim::{Const, Dim, Tensor};
//! fn largest_principal<const N: usize>(a: &Tensor<N>) -> f64
//! where
//!     Const<N>: Dim,
//! {
//!     let e = Const::<N>::sym_eigen(a);
//!     Const::<N>::eigenvalues(&e)[0]
//! }
//! assert_eq!(largest_principal(&viscosph::Mat2::new(3.0, 0.0, 0.0, 1.0)), 3.0);
//! ```

mod d2;
mod d3;
mod lattice;
pub mod mls;
pub mod symmetric;

pub use d2::SymEigen;
pub use d3::D3;
pub use lattice::Lattice;
pub use nalgebra::Const;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, DimName, OMatrix, OVector, SMatrix, SVector};

/// A point or vector in N dimensions.
pub type Vector<const N: usize> = SVector<f64, N>;
/// An N x N tensor: velocity gradients, stresses, conformation tensors.
pub type Tensor<const N: usize> = SMatrix<f64, N, N>;

/// Two space dimensions.
pub type D2 = Const<2>;

/// What a space dimension must supply beyond nalgebra's N-generic algebra (module
/// documentation). Implemented for `Const<N>`; in generic code, `Const<N>: Dim`. The tensor
/// arguments are `Tensor<N>` (nalgebra spells them `OMatrix<f64, Self, Self>` here, which is the
/// same type).
///
/// Every function that returns a tensor built from an eigen-decomposition returns it exactly
/// symmetric.
pub trait Dim: DimName + Copy + Send + Sync + std::fmt::Debug + 'static
where
    DefaultAllocator: Allocator<Self> + Allocator<Self, Self>,
{
    /// An eigen-decomposition A = R diag(l) R^T of a symmetric tensor, eigenvalues descending.
    type SymEigen: Copy + std::fmt::Debug + PartialEq + Send + Sync;

    /// The eigen-decomposition of the symmetric part of `a` (King & Lind 2021 eq. 12).
    fn sym_eigen(a: &OMatrix<f64, Self, Self>) -> Self::SymEigen;

    /// The eigenvalues l, descending.
    fn eigenvalues(e: &Self::SymEigen) -> OVector<f64, Self>;

    /// The same eigenvectors with the eigenvalues `l` (descending) instead.
    fn with_eigenvalues(e: &Self::SymEigen, l: &OVector<f64, Self>) -> Self::SymEigen;

    /// The eigenvector matrix R (columns are the eigenvectors).
    fn eigenvectors(e: &Self::SymEigen) -> OMatrix<f64, Self, Self>;

    /// R diag(f) R^T.
    fn compose(e: &Self::SymEigen, f: &OVector<f64, Self>) -> OMatrix<f64, Self, Self>;

    /// R S R^T for a symmetric S given in the eigenframe (its upper triangle is read).
    fn from_eigenframe(
        e: &Self::SymEigen,
        s: &OMatrix<f64, Self, Self>,
    ) -> OMatrix<f64, Self, Self>;

    /// f applied to the principal values of the symmetric tensor `a`: R diag(f(l)) R^T. Fang
    /// 2006's artificial stress (eqs. 40-44) is this with f keeping the tensile principal
    /// stresses.
    fn map_principal(
        a: &OMatrix<f64, Self, Self>,
        f: impl Fn(f64) -> f64,
    ) -> OMatrix<f64, Self, Self>;

    /// The inverse of the symmetric positive semi-definite `m`, or I when its smallest
    /// eigenvalue is below `min_ratio` times its largest or anything is not finite (the Bonet &
    /// Lok correction matrix with its fallback, King & Lind 2021 eq. 22).
    fn invert_spd_or_identity(
        m: &OMatrix<f64, Self, Self>,
        min_ratio: f64,
    ) -> OMatrix<f64, Self, Self>;

    /// The free-surface threshold on div r at normalised concentration `c_hat` (King & Lind
    /// 2021 eq. 36): a particle with div r at or below it is on the free surface. div r is N
    /// under full support.
    fn surface_threshold(c_hat: f64) -> f64;

    /// `a` times the part of `v` along the free surface of unit normal `n`, `a (I - n n^T) v`
    /// (King & Lind 2021's shifting on the surface, after eq. 40).
    fn tangential(n: &OVector<f64, Self>, v: &OVector<f64, Self>, a: f64) -> OVector<f64, Self>;

    /// The trace of `g` over the plane normal to the unit vector `n`, `tr g - n . g n`: with
    /// tr g = 0 (continuity) it is minus the normal component `n . g n` of King & Lind 2021 eq.
    /// (35a)'s normal stress.
    fn tangential_trace(n: &OVector<f64, Self>, g: &OMatrix<f64, Self, Self>) -> f64;
}
