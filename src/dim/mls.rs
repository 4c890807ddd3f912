//! The small (N+1) x (N+1) solve of a first-order moving-least-squares correction (Ren, Lu &
//! Jiang 2015 eqs. 18a-18c): the moment matrix M = sum_j V_j g_ij (1, x_ji)^T with
//! g_ij = (W_ij, grad_i W_ij), and the corrected sum (M^{-T} e_1) . sum_j g_ij. N + 1 is not a
//! const expression on stable Rust, so each dimension names its augmented size ([`Mls`]).

use super::{Const, Vector};
use nalgebra::{SMatrix, SVector};

/// The sums of a first-order MLS correction over one particle's neighbours, in M = N + 1
/// components.
#[derive(Debug, Clone, Copy)]
pub struct Moments<const M: usize> {
    /// The moment matrix.
    pub m: SMatrix<f64, M, M>,
    /// sum_j g_ij.
    pub s: SVector<f64, M>,
}

impl<const M: usize> Default for Moments<M> {
    fn default() -> Self {
        Self {
            m: SMatrix::zeros(),
            s: SVector::zeros(),
        }
    }
}

impl<const M: usize> Moments<M> {
    /// Add neighbour j: kernel value `w`, gradient `grad` = grad_i W_ij, x_ji = `xji`, volume
    /// `vol`.
    #[inline]
    fn add_pair<const N: usize>(&mut self, w: f64, grad: &Vector<N>, xji: &Vector<N>, vol: f64) {
        let g = SVector::<f64, M>::from_fn(|k, _| if k == 0 { w } else { grad[k - 1] });
        let x = SVector::<f64, M>::from_fn(|k, _| if k == 0 { 1.0 } else { xji[k - 1] });
        self.m += g * (x.transpose() * vol);
        self.s += g;
    }
}

/// A dimension's MLS sums (module documentation): implemented for `Const<N>`.
pub trait Mls<const N: usize> {
    /// [`Moments`] of size N + 1.
    type Moments: Default + Copy + Send;
    /// Add neighbour j (see [`Moments`]).
    fn add_pair(acc: &mut Self::Moments, w: f64, grad: &Vector<N>, xji: &Vector<N>, vol: f64);
    /// sum_j W_ij.
    fn kernel_sum(acc: &Self::Moments) -> f64;
    /// (M^{-T} e_1) . sum_j g_ij, None when M is (nearly) singular.
    fn corrected(acc: &Self::Moments, min_det: f64) -> Option<f64>;
}

macro_rules! mls {
    ($n:literal, $m:literal) => {
        impl Mls<$n> for Const<$n> {
            type Moments = Moments<$m>;
            #[inline]
            fn add_pair(acc: &mut Moments<$m>, w: f64, g: &Vector<$n>, x: &Vector<$n>, v: f64) {
                acc.add_pair(w, g, x, v)
            }
            #[inline]
            fn kernel_sum(acc: &Moments<$m>) -> f64 {
                acc.s[0]
            }
            #[inline]
            fn corrected(acc: &Moments<$m>, min_det: f64) -> Option<f64> {
                // nalgebra's determinant and LU take a concrete size.
                if acc.m.determinant().abs() < min_det {
                    return None;
                }
                let e1 = SVector::<f64, $m>::from_fn(|k, _| if k == 0 { 1.0 } else { 0.0 });
                acc.m
                    .transpose()
                    .lu()
                    .solve(&e1)
                    .map(|beta| beta.dot(&acc.s))
            }
        }
    };
}
mls!(2, 3);
mls!(3, 4);
