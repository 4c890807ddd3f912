//! Artificial viscosity (Fang 2006 eqs. 30-37, Ren 2015 eq. 19) and the two artificial stresses
//! against the tensile instability: Fang's principal-stress version (Fang 2006 eqs. 38-44, after
//! Gray, Monaghan & Swift) and Ren's, keyed to the sign of the kernel's second derivative (Ren 2015
//! eqs. 20a-20b, after Swegle et al.).

use crate::config::ArtificialStressKind;
use crate::dim::{Const, Dim, Tensor, Vector};
use crate::kernel::Kernel;

/// Monaghan's artificial viscosity Pi_ij (Fang 2006 eqs. 31-37).
///
/// Sign convention: Fang writes eq. (30) as sigma_i/rho_i^2 + sigma_j/rho_j^2 + Pi_ij delta, but
/// with sigma = -p I the viscous pressure must enter like p, i.e. as -Pi_ij delta in the stress
/// form (Monaghan's -(p_i/rho_i^2 + p_j/rho_j^2 + Pi_ij)). We return Pi_ij >= 0 and the caller
/// subtracts it; with Fang's literal sign the term would pull approaching particles together.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn viscosity<const N: usize>(
    alpha: f64,
    beta: f64,
    h: f64,
    c_mean: f64,
    rho_mean: f64,
    vij: &Vector<N>,
    xij: &Vector<N>,
    r2: f64,
) -> f64 {
    viscosity_of_dot(alpha, beta, h, c_mean, rho_mean, vij.dot(xij), r2)
}

/// [`viscosity`] from `vx` = v_ij . x_ij: the same operations, for loops that compute the dot
/// product where the neighbour's record is at hand and the rest over arrays.
#[inline(always)]
pub fn viscosity_of_dot(
    alpha: f64,
    beta: f64,
    h: f64,
    c_mean: f64,
    rho_mean: f64,
    vx: f64,
    r2: f64,
) -> f64 {
    let phi = h * vx / (r2 + 0.01 * h * h); // eq. (33)
    let pi = (-alpha * c_mean * phi + beta * phi * phi) / rho_mean; // eq. (31)
                                                                    // eq. (32): receding pairs feel nothing. Chosen by a mask, not a branch: half the pairs of
                                                                    // a flow approach and half recede with no pattern, and a mispredicted branch per pair cost
                                                                    // more than the arithmetic (issue 16's profile). The value is the same bits either way.
    let keep = if vx < 0.0 { u64::MAX } else { 0 };
    f64::from_bits(pi.to_bits() & keep)
}

/// Artificial stress tensor R of one particle from its total stress sigma (Fang 2006 eqs. 40-44):
/// rotate to principal axes (eqs. 41, 43-44), take R' = -eps sigma'/rho^2 for each tensile
/// (positive) principal stress (eq. 42), rotate back (eq. 40). The rotation is the dimension's
/// [`Dim::map_principal`]: in 2D Fang's closed form without trigonometric functions (the profile
/// of the 80 per diameter drop had spent 7 % of its time in atan2, sin and cos here).
#[inline]
pub fn fang_stress<const N: usize>(eps: f64, sigma: &Tensor<N>, rho: f64) -> Tensor<N>
where
    Const<N>: Dim,
{
    if eps == 0.0 {
        return Tensor::<N>::zeros();
    }
    let k = -eps / (rho * rho);
    Const::<N>::map_principal(sigma, |s| if s > 0.0 { k * s } else { 0.0 })
}

/// Hessian of the kernel with respect to x_i, d2W_ij / dx_i^a dx_i^b, for the pair separation
/// `xij` = x_i - x_j with |xij|^2 = `r2`: W'' e e^T + (W'/r)(I - e e^T) with e = xij/r (isotropic,
/// W''(0) I, at r = 0).
#[inline]
pub fn kernel_hessian<const N: usize, K: Kernel<N>>(
    kernel: &K,
    xij: &Vector<N>,
    r2: f64,
) -> Tensor<N> {
    let r = r2.sqrt();
    let d2 = kernel.d2w(r);
    if r <= 1e-12 * kernel.h() {
        return Tensor::<N>::identity() * d2;
    }
    let dw_r = kernel.dw_over_r(r);
    let ee = xij * xij.transpose() / r2;
    ee * (d2 - dw_r) + Tensor::<N>::identity() * dw_r
}

/// Ren's artificial stress S of one particle (Ren 2015 eq. 20b), component by component:
/// S^ab = -b sigma^ab / rho^2 where (sum_j d2W_ij/dx^a dx^b) sigma^ab > 0, else 0. `hess_sum` is
/// that sum over the particle's neighbours. Swegle et al. showed the instability grows where the
/// stress and the kernel's second derivative have the same sign, in compression as in tension;
/// Fang's version only acts on tension.
/// The tensors are read as symmetric (upper triangle).
#[inline]
pub fn ren_stress<const N: usize>(
    b: f64,
    sigma: &Tensor<N>,
    rho: f64,
    hess_sum: &Tensor<N>,
) -> Tensor<N> {
    if b == 0.0 {
        return Tensor::<N>::zeros();
    }
    let k = -b / (rho * rho);
    let pick = |a: usize, c: usize| {
        if hess_sum[(a, c)] * sigma[(a, c)] > 0.0 {
            k * sigma[(a, c)]
        } else {
            0.0
        }
    };
    let mut s = Tensor::<N>::zeros();
    for a in 0..N {
        for c in a..N {
            let v = pick(a, c);
            s[(a, c)] = v;
            s[(c, a)] = v;
        }
    }
    s
}

/// Intervals of the table of Ren's f^n over r in [0, 2h].
const REN_TABLE: usize = 4096;

/// The artificial stress against the tensile instability, resolved once: Fang 2006 eqs. (38)-(44)
/// or Ren 2015 eqs. (20a)-(20b). Both add f_ij^n (R_i + R_j) to the pair term of the momentum
/// equation with f_ij = W_ij / W(d0) (Fang eq. 39, Ren eq. 20a); they differ in R and in n.
///
/// Fang's n = 4 costs two multiplications. Ren's n = W(0)/W(d0) (1.8 for h = 1.5 d0) is not an
/// integer, and `powf` on every pair took a fifth of a PDRI step; f^n depends on r only, so it is
/// tabulated over r and interpolated linearly (error below 5e-7; f^n is 1 at r = d0).
/// (Over r^2 it would save the square root, but W is not smooth in r^2 at r = 0.)
#[derive(Debug, Clone)]
pub struct ArtificialStress {
    kind: ArtificialStressKind,
    /// Fang's epsilon or Ren's b.
    coef: f64,
    /// The exponent n: 4 for Fang (section 3.2), W(0)/W(d0) for Ren (eq. 20a).
    n: f64,
    /// 1 / W(d0).
    inv_w_d0: f64,
    /// Ren: f^n at r = k 2h / REN_TABLE, k = 0..=REN_TABLE, and the index scale.
    table: Vec<f64>,
    per_r: f64,
}

impl ArtificialStress {
    pub fn new<const N: usize, K: Kernel<N>>(
        kernel: &K,
        kind: ArtificialStressKind,
        coef: f64,
        dx: f64,
    ) -> Self {
        let w_d0 = kernel.w(dx);
        let n = match kind {
            ArtificialStressKind::Fang => 4.0,
            ArtificialStressKind::Ren => kernel.w(0.0) / w_d0,
        };
        let radius = kernel.radius();
        let table = if kind == ArtificialStressKind::Ren {
            (0..=REN_TABLE)
                .map(|k| (kernel.w(radius * k as f64 / REN_TABLE as f64) / w_d0).powf(n))
                .collect()
        } else {
            Vec::new()
        };
        Self {
            kind,
            coef,
            n,
            inv_w_d0: 1.0 / w_d0,
            table,
            per_r: REN_TABLE as f64 / radius,
        }
    }

    /// Whether the term is there at all.
    #[inline]
    pub fn is_on(&self) -> bool {
        self.coef > 0.0
    }

    /// Whether R needs the sum of kernel Hessians over the neighbours (Ren eq. 20b).
    #[inline]
    pub fn needs_hessian(&self) -> bool {
        self.is_on() && self.kind == ArtificialStressKind::Ren
    }

    /// The exponent n.
    pub fn exponent(&self) -> f64 {
        self.n
    }

    /// R of one particle from its total stress, density and (Ren) Hessian sum.
    #[inline]
    pub fn of_particle<const N: usize>(
        &self,
        sigma: &Tensor<N>,
        rho: f64,
        hess: &Tensor<N>,
    ) -> Tensor<N>
    where
        Const<N>: Dim,
    {
        match self.kind {
            ArtificialStressKind::Fang => fang_stress(self.coef, sigma, rho),
            ArtificialStressKind::Ren => ren_stress(self.coef, sigma, rho, hess),
        }
    }

    /// Whether the pair factor is Fang's (a function of W alone) rather than Ren's (a table of
    /// r): the hot pair loop picks its variant once, outside the loop, so Fang's (pure
    /// arithmetic) vectorises.
    #[inline]
    pub fn is_fang(&self) -> bool {
        self.kind == ArtificialStressKind::Fang
    }

    /// Fang's f_ij^n = (W_ij / W(d0))^n, n = 4 (Fang 2006 eq. 39), from the kernel value `w`.
    #[inline(always)]
    pub fn fang_pair_factor(&self, w: f64) -> f64 {
        let f = w * self.inv_w_d0;
        let f2 = f * f;
        f2 * f2
    }

    /// Ren's f_ij^n (Ren 2015 eq. 20a), tabulated in r, from the squared distance `r2`.
    #[inline(always)]
    pub fn ren_pair_factor(&self, r2: f64) -> f64 {
        let x = r2.sqrt() * self.per_r;
        let k = (x as usize).min(REN_TABLE - 1);
        let t = x - k as f64;
        self.table[k] + (self.table[k + 1] - self.table[k]) * t
    }

    /// f_ij^n for a pair with kernel value `w` at squared distance `r2` (inside the support).
    #[inline]
    pub fn pair_factor(&self, w: f64, r2: f64) -> f64 {
        match self.kind {
            ArtificialStressKind::Fang => self.fang_pair_factor(w),
            ArtificialStressKind::Ren => self.ren_pair_factor(r2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::CubicSpline;
    use crate::{Mat2, Vec2};

    #[test]
    fn kernel_hessian_matches_finite_differences() {
        let k = CubicSpline::new(1.0);
        let w = |p: Vec2| k.w(p.norm());
        let e = 1e-4;
        for p in [
            Vec2::new(0.3, 0.2),
            Vec2::new(-1.1, 0.5),
            Vec2::new(0.2, -1.6),
        ] {
            let h = kernel_hessian(&k, &p, p.norm_squared());
            for a in 0..2 {
                for b in 0..2 {
                    let (mut ea, mut eb) = (Vec2::zeros(), Vec2::zeros());
                    ea[a] = e;
                    eb[b] = e;
                    let fd = (w(p + ea + eb) - w(p + ea - eb) - w(p - ea + eb) + w(p - ea - eb))
                        / (4.0 * e * e);
                    assert!(
                        (h[(a, b)] - fd).abs() < 1e-5,
                        "{a}{b}: {} vs {fd}",
                        h[(a, b)]
                    );
                }
            }
        }
    }

    #[test]
    fn ren_stress_follows_the_sign_of_hessian_times_stress() {
        let sigma = Mat2::new(2.0, -1.0, -1.0, -3.0);
        // Positive xx curvature with tension, negative yy with compression, xy same sign: all on.
        let hess = Mat2::new(1.0, -0.5, -0.5, -2.0);
        let s = ren_stress(0.8, &sigma, 2.0, &hess);
        assert_eq!(s, sigma * (-0.8 / 4.0));
        // Flip the curvature: all off (compression with positive curvature is stable).
        assert_eq!(ren_stress(0.8, &sigma, 2.0, &(-hess)), Mat2::zeros());
        assert_eq!(ren_stress(0.0, &sigma, 2.0, &hess), Mat2::zeros());
    }

    #[test]
    fn artificial_stress_acts_only_on_tension() {
        // Pure compression: no artificial stress.
        let comp = Mat2::new(-3.0, 0.0, 0.0, -1.0);
        assert_eq!(fang_stress(0.5, &comp, 1.0), Mat2::zeros());
        // Uniaxial tension along x: R = -eps sigma / rho^2 along x only.
        let ten = Mat2::new(4.0, 0.0, 0.0, -1.0);
        let r = fang_stress(0.5, &ten, 2.0);
        assert!((r[(0, 0)] + 0.5).abs() < 1e-14 && r[(1, 1)].abs() < 1e-14);
        // Rotated tension: R is the rotated principal R, and is symmetric.
        let a = 0.3f64;
        let q = Mat2::new(a.cos(), -a.sin(), a.sin(), a.cos());
        let rr = fang_stress(0.5, &(q * ten * q.transpose()), 2.0);
        let expect = q * r * q.transpose();
        assert!((rr - expect).norm() < 1e-12, "{rr} vs {expect}");
    }

    #[test]
    fn artificial_stress_equals_fangs_trigonometric_form() {
        // Fang eqs. (40)-(44) literally, with theta from eq. (41).
        let literal = |eps: f64, sg: &Mat2, rho: f64| {
            let (sxx, syy, sxy) = (sg[(0, 0)], sg[(1, 1)], sg[(0, 1)]);
            let t = 0.5 * (2.0 * sxy).atan2(sxx - syy);
            let (s, c) = t.sin_cos();
            let spx = c * c * sxx + 2.0 * c * s * sxy + s * s * syy;
            let spy = s * s * sxx - 2.0 * c * s * sxy + c * c * syy;
            let f = |v: f64| if v > 0.0 { -eps * v / (rho * rho) } else { 0.0 };
            let (rx, ry) = (f(spx), f(spy));
            Mat2::new(
                c * c * rx + s * s * ry,
                c * s * (rx - ry),
                c * s * (rx - ry),
                s * s * rx + c * c * ry,
            )
        };
        for sg in [
            Mat2::new(3.0, 1.5, 1.5, -2.0),
            Mat2::new(-1.0, 2.0, 2.0, -1.0),
            Mat2::new(2.0, 0.0, 0.0, 2.0),
            Mat2::new(-4.0, 0.3, 0.3, 1.0),
            Mat2::new(0.5, -0.7, -0.7, 0.2),
        ] {
            let (a, b) = (fang_stress(0.3, &sg, 1.7), literal(0.3, &sg, 1.7));
            assert!(
                (a - b).norm() < 1e-14 * (1.0 + b.norm()),
                "{sg}: {a} vs {b}"
            );
        }
    }

    #[test]
    fn viscosity_only_for_approaching_pairs() {
        let x = Vec2::new(1.0, 0.0);
        assert_eq!(
            viscosity(1.0, 2.0, 1.0, 10.0, 1.0, &Vec2::new(1.0, 0.0), &x, 1.0),
            0.0
        );
        assert!(viscosity(1.0, 2.0, 1.0, 10.0, 1.0, &Vec2::new(-1.0, 0.0), &x, 1.0) > 0.0);
    }

    #[test]
    fn ren_pair_factor_table_matches_the_power() {
        let dx = 0.01;
        let kernel = CubicSpline::new(1.5 * dx);
        let art = ArtificialStress::new(&kernel, ArtificialStressKind::Ren, 0.8, dx);
        // n = W(0)/W(d0) = 1.8 exactly for h = 1.5 d0 (Fang 2006 section 3.2 quotes the ratio).
        assert!((art.exponent() - 1.8).abs() < 1e-12);
        for k in 0..30011 {
            let r = kernel.radius() * k as f64 / 30011.0;
            let w = kernel.w(r);
            let exact = (w / kernel.w(dx)).powf(1.8);
            let table = art.pair_factor(w, r * r);
            assert!((table - exact).abs() < 5e-7, "r = {r}: {table} vs {exact}");
        }
    }
}
