//! Artificial viscosity (Fang 2006 eqs. 30-37) and the principal-stress artificial stress against
//! the tensile instability (Fang 2006 eqs. 38-44, after Gray, Monaghan & Swift).

use crate::{Mat2, Vec2};

/// Monaghan's artificial viscosity Pi_ij (Fang 2006 eqs. 31-37).
///
/// Sign convention: Fang writes eq. (30) as sigma_i/rho_i^2 + sigma_j/rho_j^2 + Pi_ij delta, but
/// with sigma = -p I the viscous pressure must enter like p, i.e. as -Pi_ij delta in the stress
/// form (Monaghan's -(p_i/rho_i^2 + p_j/rho_j^2 + Pi_ij)). We return Pi_ij >= 0 and the caller
/// subtracts it; with Fang's literal sign the term would pull approaching particles together.
#[inline]
pub fn viscosity(
    alpha: f64,
    beta: f64,
    h: f64,
    c_mean: f64,
    rho_mean: f64,
    vij: &Vec2,
    xij: &Vec2,
    r2: f64,
) -> f64 {
    let vx = vij.dot(xij);
    if vx >= 0.0 {
        return 0.0; // eq. (32): receding pairs feel nothing
    }
    let phi = h * vx / (r2 + 0.01 * h * h); // eq. (33)
    (-alpha * c_mean * phi + beta * phi * phi) / rho_mean // eq. (31)
}

/// Artificial stress tensor R of one particle from its total stress sigma (Fang 2006 eqs. 40-44):
/// rotate to principal axes, take R' = -eps sigma'/rho^2 for each tensile (positive) principal
/// stress, rotate back.
#[inline]
pub fn fang_stress(eps: f64, sigma: &Mat2, rho: f64) -> Mat2 {
    if eps == 0.0 {
        return Mat2::zeros();
    }
    let (sxx, syy, sxy) = (sigma[(0, 0)], sigma[(1, 1)], sigma[(0, 1)]);
    // eq. (41), with atan2 so that sxx = syy is handled.
    let theta = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let (s, c) = theta.sin_cos();
    let (c2, s2, cs) = (c * c, s * s, c * s);
    let sp_xx = c2 * sxx + 2.0 * cs * sxy + s2 * syy; // eq. (43)
    let sp_yy = s2 * sxx - 2.0 * cs * sxy + c2 * syy; // eq. (44)
    let inv_rho2 = 1.0 / (rho * rho);
    let rxx = if sp_xx > 0.0 {
        -eps * sp_xx * inv_rho2
    } else {
        0.0
    }; // eq. (42)
    let ryy = if sp_yy > 0.0 {
        -eps * sp_yy * inv_rho2
    } else {
        0.0
    };
    let xy = cs * (rxx - ryy); // eq. (40)
    Mat2::new(c2 * rxx + s2 * ryy, xy, xy, s2 * rxx + c2 * ryy)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn viscosity_only_for_approaching_pairs() {
        let x = Vec2::new(1.0, 0.0);
        assert_eq!(
            viscosity(1.0, 2.0, 1.0, 10.0, 1.0, &Vec2::new(1.0, 0.0), &x, 1.0),
            0.0
        );
        assert!(viscosity(1.0, 2.0, 1.0, 10.0, 1.0, &Vec2::new(-1.0, 0.0), &x, 1.0) > 0.0);
    }
}
