//! Second-order continuation of a fully developed wall layer across a mirror wall (King & Lind
//! 2021 section III.C mirrors, used in the closed periodic channel).
//!
//! A mirror carries its parent's velocity reflected, `u_m = 2 u_wall - u_i`: the *odd*
//! continuation of the velocity about the wall. That is exact for a linear profile, but the
//! profile of a driven channel has a curvature at the wall (`eta_s u'' = -rho g + ...`), and the
//! odd continuation flips the sign of u'' across the wall. Morris' Laplacian (King & Lind eq.
//! (21)) then reads -4.9 instead of -8 on the first row of u = 4y(1 - y) at 30 particles across
//! (-7.7 on the second), the wall layer is under-damped, and the flow behaves as if the wall
//! slipped by half a spacing: measured, the Newtonian ISPH channel settled at 1.067 U at
//! 30 across, a first-order error. The same holds for the polymer stress: the mirror's stress
//! equals its parent's (`StressMirror::NoSlip`, the even continuation), so the shear stress has
//! zero normal derivative at the wall instead of `d tau_tn / dn`, and its divergence loses the
//! part of the body force the polymer carries at the wall.
//!
//! The remedy: fit the wall-normal profiles over the particles within the mirror reach by least
//! squares, `u_t - u_wall.t = a s + b s^2 + c s^3` and `Phi_tn = c0 + c1 s + c2 s^2` (s = d / reach),
//! and give each mirror the part of the continuation the reflection gets wrong: `u''_w d^2`
//! along t (`u(-d) = -u(d) + u'' d^2` for a profile `a d + b d^2`), and `-2 (dPhi_tn/dn) d` on the
//! shear component (`Phi(-d) = Phi(d) - 2 Phi' d` for a linear profile). The fit is over the
//! whole wall, so it assumes the flow does not vary along the wall: the fully developed periodic
//! channel, where the scheme uses it (a free-surface scene keeps the plain mirrors).

use super::plate::Plate;
use crate::dim::{Tensor, Vector};
use nalgebra::{Matrix3, Vector3};

/// Fewest samples for a fit (three coefficients; anything less keeps the plain mirrors).
const MIN_SAMPLES: usize = 6;

/// Least-squares coefficients of `y = sum_k c_k phi_k(s)` over samples (s, y); None if the
/// normal matrix is singular or there are too few samples. Sums in sample order.
fn fit(
    samples: impl Iterator<Item = (f64, f64)>,
    basis: fn(f64) -> Vector3<f64>,
) -> Option<[f64; 3]> {
    let mut a = Matrix3::<f64>::zeros();
    let mut b = Vector3::<f64>::zeros();
    let mut count = 0;
    for (s, y) in samples {
        let phi = basis(s);
        a += phi * phi.transpose();
        b += phi * y;
        count += 1;
    }
    if count < MIN_SAMPLES {
        return None;
    }
    let c = a.lu().solve(&b)?;
    c.iter().all(|v| v.is_finite()).then(|| [c[0], c[1], c[2]])
}

/// Per mirror of `plate` (parents `parent`, fluid positions `x`, reach `reach`), the velocity to
/// add to `2 u_wall - u_parent`: `u''_w d^2 t`, with u'' the wall curvature of the fitted
/// tangential profile of `u`.
pub fn velocity_corrections<const N: usize>(
    plate: &Plate<N>,
    x: &[Vector<N>],
    parent: &[u32],
    u: &[Vector<N>],
    reach: f64,
) -> Vec<Vector<N>> {
    let uw = plate.wall_velocity().dot(&plate.t);
    let c = fit(
        parent.iter().map(|&i| {
            let i = i as usize;
            (plate.d(&x[i]) / reach, u[i].dot(&plate.t) - uw)
        }),
        |s| Vector3::new(s, s * s, s * s * s),
    );
    let b = c.map_or(0.0, |c| c[1]);
    parent
        .iter()
        .map(|&i| {
            let s = plate.d(&x[i as usize]) / reach;
            plate.t * (2.0 * b * s * s)
        })
        .collect()
}

/// Slope of the fitted shear component `t . Phi n` per unit of s = d / reach.
fn shear_slope_per_reach<const N: usize>(
    plate: &Plate<N>,
    x: &[Vector<N>],
    parent: &[u32],
    phi: &[Tensor<N>],
    reach: f64,
) -> f64 {
    let (t, n) = (plate.t, plate.n);
    let c = fit(
        parent.iter().map(|&i| {
            let i = i as usize;
            (plate.d(&x[i]) / reach, t.dot(&(phi[i] * n)))
        }),
        |s| Vector3::new(1.0, s, s * s),
    );
    c.map_or(0.0, |c| c[1])
}

/// The wall-normal slope `d(t . Phi n)/dn` at the wall of `plate` [Pa/m], from a quadratic fit
/// of the shear component over the mirrors' parents (0 with too few samples).
pub fn shear_stress_slope<const N: usize>(
    plate: &Plate<N>,
    x: &[Vector<N>],
    parent: &[u32],
    phi: &[Tensor<N>],
    reach: f64,
) -> f64 {
    shear_slope_per_reach(plate, x, parent, phi, reach) / reach
}

/// Per mirror, the stress to add to the parent's (even) value: `-2 (dPhi_tn/dn) d` on the shear
/// component in the wall frame, from a quadratic fit of `t . Phi n`.
pub fn shear_stress_corrections<const N: usize>(
    plate: &Plate<N>,
    x: &[Vector<N>],
    parent: &[u32],
    phi: &[Tensor<N>],
    reach: f64,
) -> Vec<Tensor<N>> {
    let (t, n) = (plate.t, plate.n);
    let slope = shear_slope_per_reach(plate, x, parent, phi, reach);
    let shape = t * n.transpose() + n * t.transpose();
    parent
        .iter()
        .map(|&i| shape * (-2.0 * slope * plate.d(&x[i as usize]) / reach))
        .collect()
}

/// Per mirror, the velocity to add to `2 u_wall - u_parent` for a given wall curvature
/// `u''_w = d^2 (u . t) / dn^2`: `u''_w d^2 t` (exact for a cubic profile).
pub fn curvature_corrections<const N: usize>(
    plate: &Plate<N>,
    x: &[Vector<N>],
    parent: &[u32],
    curvature: f64,
) -> Vec<Vector<N>> {
    parent
        .iter()
        .map(|&i| {
            let d = plate.d(&x[i as usize]);
            plate.t * (curvature * d * d)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Mat2, Vec2};

    /// Fluid rows of a channel wall at (j + 1/2) dx and the bottom plate y = 0.
    fn rows(dx: f64, reach: f64) -> (Plate, Vec<Vec2>, Vec<u32>) {
        let plate = Plate::spanning(Vec2::zeros(), Vec2::new(1.0, 0.0), dx, 0, 9);
        let mut x = Vec::new();
        for j in 0..20 {
            for i in 0..10 {
                x.push(Vec2::new((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx));
            }
        }
        let parent = (0..x.len() as u32)
            .filter(|&i| plate.d(&x[i as usize]) < reach)
            .collect();
        (plate, x, parent)
    }

    #[test]
    fn corrected_mirrors_continue_a_quadratic_profile_and_a_linear_stress_exactly() {
        let (dx, reach) = (0.05, 0.2);
        let (plate, x, parent) = rows(dx, reach);
        // u = 4 y (1 - y): the mirror at -y must carry u(-y) = -4 y (1 + y).
        let u: Vec<Vec2> = x
            .iter()
            .map(|p| Vec2::new(4.0 * p.y * (1.0 - p.y), 0.0))
            .collect();
        let du = velocity_corrections(&plate, &x, &parent, &u, reach);
        for (m, &i) in parent.iter().enumerate() {
            let y = x[i as usize].y;
            let um = -u[i as usize] + du[m];
            assert!((um.x - (-4.0 * y * (1.0 + y))).abs() < 1e-12, "{um}");
            assert_eq!(um.y, 0.0);
        }
        // tau_xy = 3 - 8 y (the shear stress of that flow plus a constant): odd part continued.
        let phi: Vec<Mat2> = x
            .iter()
            .map(|p| Mat2::new(5.0, 3.0 - 8.0 * p.y, 3.0 - 8.0 * p.y, 0.0))
            .collect();
        let dphi = shear_stress_corrections(&plate, &x, &parent, &phi, reach);
        for (m, &i) in parent.iter().enumerate() {
            let y = x[i as usize].y;
            let pm = phi[i as usize] + dphi[m];
            assert!((pm[(0, 1)] - (3.0 + 8.0 * y)).abs() < 1e-12);
            assert!((pm[(1, 0)] - (3.0 + 8.0 * y)).abs() < 1e-12);
            assert_eq!((pm[(0, 0)], pm[(1, 1)]), (5.0, 0.0));
        }
    }

    #[test]
    fn too_few_samples_keep_the_plain_mirrors() {
        let (dx, reach) = (0.05, 0.2);
        let (plate, x, _) = rows(dx, reach);
        let parent = [0u32, 1, 2];
        let u = vec![Vec2::new(1.0, 0.0); x.len()];
        assert!(velocity_corrections(&plate, &x, &parent, &u, reach)
            .iter()
            .all(|v| *v == Vec2::zeros()));
    }
}
