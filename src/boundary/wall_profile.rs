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
//! channel, where the scheme uses it (a free-surface scene keeps the plain mirrors). Along a
//! curved wall in a closed cell (the cylinder array) the shear-stress slope is fitted locally,
//! over the parents within half the reach along the wall ([`local_shear_stress_corrections`]).

use super::plate::Plate;
use crate::dim::{Tensor, Vector};
use crate::geometry::Shape;
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

/// The rotation in the plane of the unit vectors `a` and `b` that takes `a` to `b`, applied to
/// `v`: `v - ((a + b).v / (1 + a.b)) (a + b) + 2 (a.v) b` (any dimension; `a` and `b` not
/// opposite). Carries a vector given in the wall frame at one point of a curved wall (normal
/// `a`) into the wall frame at another (normal `b`).
fn rotate<const N: usize>(a: &Vector<N>, b: &Vector<N>, v: &Vector<N>) -> Vector<N> {
    let ab = a + b;
    v - ab * (ab.dot(v) / (1.0 + a.dot(b))) + b * (2.0 * a.dot(v))
}

/// Least-squares coefficients of `y = sum_k c_k phi_k(s)` for a vector-valued `y`, component by
/// component with one normal matrix; None as `fit`.
fn fit_vector<const N: usize>(
    samples: impl Iterator<Item = (f64, Vector<N>)>,
    basis: fn(f64) -> Vector3<f64>,
) -> Option<[Vector<N>; 3]> {
    let mut a = Matrix3::<f64>::zeros();
    let mut b = [Vector3::<f64>::zeros(); N];
    let mut count = 0;
    for (s, y) in samples {
        let phi = basis(s);
        a += phi * phi.transpose();
        for (bk, yk) in b.iter_mut().zip(y.iter()) {
            *bk += phi * *yk;
        }
        count += 1;
    }
    if count < MIN_SAMPLES {
        return None;
    }
    let lu = a.lu();
    let mut c = [Vector::<N>::zeros(); 3];
    for (k, bk) in b.iter().enumerate() {
        let ck = lu.solve(bk)?;
        for (m, cm) in c.iter_mut().enumerate() {
            cm[k] = ck[m];
        }
    }
    c.iter()
        .all(|v| v.iter().all(|x| x.is_finite()))
        .then_some(c)
}

/// The mirrors' parents whose closest wall points lie within `window` of that of parent `p`
/// (`cp` the closest points, in the order of `parent`): the samples of a local fit.
fn neighbourhood<'a, const N: usize>(
    cp: &'a [Vector<N>],
    p: usize,
    window: f64,
) -> impl Iterator<Item = usize> + 'a {
    let w2 = window * window;
    (0..cp.len()).filter(move |&q| (cp[q] - cp[p]).norm_squared() < w2)
}

/// A curved wall's version of [`shear_stress_corrections`]: per mirror, `-2 s (c1 n^T + n c1^T)`
/// with c1 the normal slope (per unit of s = d / reach) of the tangential traction `Phi n`,
/// fitted as `c0 + c1 s + c2 s^2` over the parents within `window` along the wall (each
/// sample's traction carried into the parent's wall frame, its tangential part fitted). The
/// even continuation of the stress leaves the first ring round King & Lind's cylinder without
/// the polymer's share of the wall friction: on the finite-element Newtonian field sampled on
/// ISPH's lattice (16 across, `Phi = eta0 (kappa + kappa^T)` with kappa the corrected gradient
/// (20)), the negative-form divergence (20) gives the first ring a force along the flow of
/// +7 N/m (summed over the ring, times the particle volume) against the exact -261 N/m, -227 N/m
/// with these corrections; Morris' Laplacian (21) of the same field gives -103 N/m. The first
/// ring then slips and its stress runs ahead of the finite-element one
/// (`validation/cylinder_array/README.md`).
pub fn local_shear_stress_corrections<const N: usize>(
    wall: &dyn Shape<N>,
    x: &[Vector<N>],
    parent: &[u32],
    phi: &[Tensor<N>],
    reach: f64,
    window: f64,
) -> Vec<Tensor<N>> {
    let frame = frames(wall, x, parent, reach);
    (0..parent.len())
        .map(|p| {
            let (np, sp) = (frame.normal[p], frame.s[p]);
            let c = fit_vector(
                neighbourhood(&frame.cp, p, window).map(|q| {
                    let nq = frame.normal[q];
                    let v = rotate(&nq, &np, &(phi[parent[q] as usize] * nq));
                    (frame.s[q], v - np * np.dot(&v))
                }),
                |s| Vector3::new(1.0, s, s * s),
            );
            c.map_or(Tensor::<N>::zeros(), |c| {
                let c1 = c[1] - np * np.dot(&c[1]);
                (c1 * np.transpose() + np * c1.transpose()) * (-2.0 * sp)
            })
        })
        .collect()
}

/// Each parent's closest wall point, wall normal and distance over the reach.
struct Frames<const N: usize> {
    cp: Vec<Vector<N>>,
    normal: Vec<Vector<N>>,
    s: Vec<f64>,
}

fn frames<const N: usize>(
    wall: &dyn Shape<N>,
    x: &[Vector<N>],
    parent: &[u32],
    reach: f64,
) -> Frames<N> {
    let xs = parent.iter().map(|&i| &x[i as usize]);
    Frames {
        cp: xs.clone().map(|p| wall.closest_point(p)).collect(),
        normal: xs.clone().map(|p| wall.normal(p)).collect(),
        s: xs.map(|p| wall.signed_distance(p) / reach).collect(),
    }
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

    /// Round a cylinder (fluid outside) and inside a circular tank, on rings at the distances
    /// (k + 1/2) dx from the wall: a shear stress linear in the distance s from the wall,
    /// `Phi = (c0 + c1 s)(t n^T + n t^T)` in the local frame, is continued by the corrected
    /// mirrors as its own continuation `(c0 - c1 d)(t n^T + n t^T)` at the image of a parent at
    /// distance d: the local frames carried along the circle by the rotation between the
    /// normals lose nothing.
    #[test]
    fn local_corrections_continue_a_linear_shear_stress_round_a_circle() {
        use crate::geometry::Ball;
        let (dx, reach) = (0.05, 0.2);
        for ball in [
            Ball::obstacle(Vec2::new(0.3, -0.1), 1.0),
            Ball::container(Vec2::new(0.3, -0.1), 1.0),
        ] {
            let mut x = Vec::new();
            for k in 0..6 {
                let d = (k as f64 + 0.5) * dx;
                let r = match ball.fluid {
                    crate::geometry::Side::Outside => ball.radius + d,
                    crate::geometry::Side::Inside => ball.radius - d,
                };
                let arcs = (2.0 * std::f64::consts::PI * r / dx).round() as usize;
                for q in 0..arcs {
                    let a = 2.0 * std::f64::consts::PI * (q as f64 + 0.5 * (k % 2) as f64)
                        / arcs as f64;
                    x.push(ball.centre + r * Vec2::new(a.cos(), a.sin()));
                }
            }
            let parent: Vec<u32> = (0..x.len() as u32)
                .filter(|&i| ball.signed_distance(&x[i as usize]) < reach)
                .collect();
            let frame = |p: &Vec2| {
                let n = ball.normal(p);
                (n, Vec2::new(-n.y, n.x), ball.signed_distance(p))
            };
            let (c0, c1) = (2.0, -5.0);
            let phi: Vec<Mat2> = x
                .iter()
                .map(|p| {
                    let (n, t, s) = frame(p);
                    (t * n.transpose() + n * t.transpose()) * (c0 + c1 * s)
                })
                .collect();
            let dphi = local_shear_stress_corrections(&ball, &x, &parent, &phi, reach, 0.1);
            for (m, &i) in parent.iter().enumerate() {
                let (n, t, d) = frame(&x[i as usize]);
                let pm = phi[i as usize] + dphi[m];
                let want = (t * n.transpose() + n * t.transpose()) * (c0 - c1 * d);
                assert!((pm - want).norm() < 1e-10, "{pm} against {want}");
            }
        }
    }
}
