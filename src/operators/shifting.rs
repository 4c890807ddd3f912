//! Fickian particle shifting (Lind, Xu, Stansby & Rogers 2012), in King & Lind 2021's form
//! (section III.E, eqs. (40)-(44)) with the corrections their code makes to the printed
//! equations.
//!
//! Concentration gradient, eq. (42):
//! `grad C_i = sum_j (1 + 0.25 (W_ij / W(dr))^4) grad_i W_ij V_j - alpha_i sum_j Q(q_ij) x_ij / r_ij`
//! * the tensile-correction weight divides by W(dr), the kernel at one particle spacing (the
//!   printed W_ii = W(0) makes the term negligible);
//! * Q of eq. (43) (1/32 below q = 0.5, q^3 (1 - q)^3 up to q = 1) is evaluated at
//!   q = r / (2 dr) (the printed q = 2 r / dr leaves no neighbour inside its support), with
//!   alpha = 32 / (pi h) for interior particles and 0 on the free surface (eq. (44) prints
//!   64 / (pi h));
//! * the Q term enters with a minus sign, so that after the down-gradient shift below it pushes
//!   particles closer than 2 dr apart (a short-range repulsion, as the paper describes it).
//!
//! Caveat, kept as paper and code have it: Q jumps from 1/32 to 1/64 at q = 0.5, i.e. exactly at
//! r = dr, the lattice spacing, so on a perfect lattice whether a nearest neighbour gets 1/32 or
//! 1/64 depends on round-off in r. It is the surface-tension kernel of Akinci et al. 2013, whose
//! inner branch is 2 q^3 (1 - q)^3 - 1/64 (continuous, 1/64 at q = 0.5), garbled into a
//! constant; a continuous replacement would be a modelling change to make with the scheme's
//! tests in hand.
//!
//! Displacement, eq. (40), *down* the concentration gradient:
//! `dr_i = -D_i grad C_i` inside; on the free surface only its tangential part,
//! `dr_i = -D_i (m_i . grad C_i) m_i` with m_i the unit tangent (m . n = 0), so shifting never
//! moves a surface particle across the surface. Each displacement is capped at 0.1 h per step.
//! `D_i` here is the paper's coefficient (41) times the time step (a length squared):
//! [`coefficient_internal`] (h^2 / 4) or [`coefficients_free_surface`]
//! (4 h dt (|u_i| + 0.2 max|u| exp(-5 |u_i| / max|u|))). The shifting velocity of the ALE
//! algorithm (section III.A) is `u_ps = dr / dt`.

use crate::dim::{Const, Dim, Vector};
use crate::kernel::Kernel;
use crate::neighbors::{Domain, NeighborList};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Largest displacement per step, in units of h (King's code).
pub const CAP_OVER_H: f64 = 0.1;

/// Eq. (43) at q = r / (2 dr).
#[inline]
pub fn cohesion_q(q: f64) -> f64 {
    if q <= 0.0 || q > 1.0 {
        0.0
    } else if q <= 0.5 {
        1.0 / 32.0
    } else {
        let t = q * (1.0 - q);
        t * t * t
    }
}

/// grad C_i of eq. (42) for the first `n` particles (neighbours may include ghosts, which take
/// part like fluid points). `repulsion[i]` selects the Q term (interior particles of a
/// free-surface flow; all particles of a closed one); empty = none.
#[allow(clippy::too_many_arguments)]
pub fn concentration_gradient<const N: usize, K: Kernel<N>>(
    x: &[Vector<N>],
    vol: &[f64],
    nl: &NeighborList,
    kernel: &K,
    domain: &Domain,
    dr: f64,
    n: usize,
    repulsion: &[bool],
) -> Vec<Vector<N>> {
    let w_dr = kernel.w(dr);
    let alpha = cohesion_alpha(kernel.h());
    (0..n)
        .into_par_iter()
        .map(|i| {
            let use_q = repulsion.get(i).copied().unwrap_or(false);
            let mut g = Vector::<N>::zeros();
            for &j in nl.of(i) {
                let j = j as usize;
                let xij = domain.delta(&x[i], &x[j]);
                let r = xij.norm();
                if j == i || r == 0.0 {
                    continue;
                }
                let (w, f) = kernel.w_and_dw_over_r(r);
                g += gradient_term(w, f, w_dr, vol[j], xij);
                if use_q {
                    g -= cohesion_term(alpha, r, dr, xij);
                }
            }
            g
        })
        .collect()
}

/// One pair's term of eq. (42)'s concentration gradient, with the anti-clumping factor:
/// `(1 + 0.25 (W / W(dr))^4) V_j (1/r) dW/dr x_ij` (w = W_ij, f = (1/r) dW/dr, w_dr = W(dr)).
#[inline]
pub fn gradient_term<const N: usize>(
    w: f64,
    f: f64,
    w_dr: f64,
    vol_j: f64,
    xij: Vector<N>,
) -> Vector<N> {
    let t = w / w_dr;
    (1.0 + 0.25 * t * t * t * t) * vol_j * f * xij
}

/// One pair's repulsion Q of eqs. (42)-(43), subtracted from the gradient: `alpha q(r / 2dr)
/// x_ij / r` with `alpha = 32 / (pi h)`.
#[inline]
pub fn cohesion_term<const N: usize>(alpha: f64, r: f64, dr: f64, xij: Vector<N>) -> Vector<N> {
    alpha * cohesion_q(r / (2.0 * dr)) * xij / r
}

/// `alpha` of [`cohesion_term`] for smoothing length `h`.
#[inline]
pub fn cohesion_alpha(h: f64) -> f64 {
    32.0 / (PI * h)
}

/// Shift coefficient D dt for internal flows (eq. (41), first line): h^2 / 4.
pub fn coefficient_internal(h: f64) -> f64 {
    0.25 * h * h
}

/// Shift coefficients D_i dt for free-surface flows (eq. (41), second line):
/// `4 h dt (|u_i| + 0.2 max|u| exp(-5 |u_i| / max|u|))`; zero for a fluid at rest.
pub fn coefficients_free_surface<const N: usize>(u: &[Vector<N>], h: f64, dt: f64) -> Vec<f64> {
    let umax = u.iter().map(|v| v.norm()).fold(0.0, f64::max);
    u.iter()
        .map(|v| {
            let a = v.norm();
            if umax > 0.0 {
                4.0 * h * dt * (a + 0.2 * umax * (-5.0 * a / umax).exp())
            } else {
                0.0
            }
        })
        .collect()
}

/// Displacements `dr_i` (eq. (40) down the gradient, tangential on the free surface, capped at
/// [`CAP_OVER_H`] h). `d[i]` is D_i dt; `surface = Some((is_surface, outward_normal))` for a
/// free-surface flow.
pub fn displacements<const N: usize>(
    grad_c: &[Vector<N>],
    d: &[f64],
    surface: Option<(&[bool], &[Vector<N>])>,
    h: f64,
) -> Vec<Vector<N>>
where
    Const<N>: Dim,
{
    assert_eq!(grad_c.len(), d.len());
    let cap = CAP_OVER_H * h;
    (0..grad_c.len())
        .into_par_iter()
        .map(|i| {
            let mut s = -d[i] * grad_c[i];
            if let Some((fs, n)) = surface {
                if fs[i] {
                    s = Const::<N>::tangential(&n[i], &grad_c[i], -d[i]);
                }
            }
            let len = s.norm();
            if len > cap {
                s *= cap / len;
            }
            s
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::QuinticSpline;
    use crate::neighbors::CellGrid;
    use crate::operators::fixtures::disc;
    use crate::operators::surface;
    use crate::Vec2;

    fn lists(x: &[Vec2], k: &QuinticSpline) -> NeighborList {
        let g = CellGrid::build(x, k.radius(), &crate::neighbors::Domain::OPEN);
        NeighborList::build(&g, x, x, k.radius(), &crate::neighbors::Domain::OPEN)
    }

    /// Coefficient of variation of the nearest-neighbour distance over particles deeper than
    /// `depth` inside the disc: zero on a lattice.
    fn disorder(x: &[Vec2], nl: &NeighborList, radius: f64, depth: f64) -> f64 {
        let d: Vec<f64> = (0..x.len())
            .filter(|&i| x[i].norm() < radius - depth)
            .map(|i| {
                nl.of(i)
                    .iter()
                    .filter(|&&j| j as usize != i)
                    .map(|&j| (x[i] - x[j as usize]).norm())
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / d.len() as f64).sqrt() / mean
    }

    /// A disc perturbed by up to +/-0.3 dr, shifted 20 times with the free-surface treatment:
    /// the interior's nearest-neighbour spread falls by more than half; surface particles move
    /// only along the surface.
    #[test]
    fn perturbed_disc_becomes_more_uniform_and_surface_moves_tangentially() {
        let dr = 0.01;
        let radius = 20.0 * dr;
        let k = QuinticSpline::new(1.3 * dr);
        let mut x = disc(radius, dr, 0.3, 31).x;
        let vol = vec![dr * dr; x.len()];
        let nl = lists(&x, &k);
        let before = disorder(&x, &nl, radius, 4.0 * dr);
        for _ in 0..20 {
            let nl = lists(&x, &k);
            let s = surface::detect(&x, &vol, &nl, &k, &Domain::OPEN, x.len());
            let interior: Vec<bool> = s.is_surface.iter().map(|&b| !b).collect();
            let g =
                concentration_gradient(&x, &vol, &nl, &k, &Domain::OPEN, dr, x.len(), &interior);
            let d = vec![coefficient_internal(k.h()); x.len()];
            let dx = displacements(&g, &d, Some((&s.is_surface, &s.normal)), k.h());
            for ((d, &fs), n) in dx.iter().zip(&s.is_surface).zip(&s.normal) {
                if fs {
                    assert!(d.dot(n).abs() <= 1e-12 * d.norm().max(1e-300));
                }
                assert!(d.norm() <= CAP_OVER_H * k.h() * (1.0 + 1e-12));
            }
            x.iter_mut().zip(&dx).for_each(|(p, d)| *p += d);
        }
        let after = disorder(&x, &lists(&x, &k), radius, 4.0 * dr);
        assert!(after < 0.5 * before, "disorder {before} -> {after}");
    }

    /// On a perfect lattice far from any surface, the Fickian grad C vanishes by symmetry: no
    /// spurious drift (the Q term is left out here: its jump at r = dr makes the lattice's
    /// nearest neighbours depend on round-off, see the module documentation). A pair closer
    /// than dr is pushed apart by the repulsion.
    #[test]
    fn lattice_does_not_drift_and_close_pairs_repel() {
        let dr = 0.01;
        let k = QuinticSpline::new(1.3 * dr);
        let n = 15;
        let mut x: Vec<Vec2> = (0..n * n)
            .map(|m| Vec2::new((m % n) as f64 * dr, (m / n) as f64 * dr))
            .collect();
        let c = 7 * n + 7;
        let vol = vec![dr * dr; x.len()];
        let all = vec![true; x.len()];
        let g = concentration_gradient(
            &x,
            &vol,
            &lists(&x, &k),
            &k,
            &Domain::OPEN,
            dr,
            x.len(),
            &[],
        );
        assert!(g[c].norm() < 1e-9 / dr, "{}", g[c].norm());
        // Move the centre particle 0.6 dr towards its right-hand neighbour.
        x[c].x += 0.6 * dr;
        let g = concentration_gradient(
            &x,
            &vol,
            &lists(&x, &k),
            &k,
            &Domain::OPEN,
            dr,
            x.len(),
            &all,
        );
        let dx = displacements(&g[c..=c], &[coefficient_internal(k.h())], None, k.h());
        assert!(dx[0].x < 0.0 && dx[0].y.abs() < 1e-12 * dr, "{:?}", dx[0]);
    }

    /// The displacement is capped at 0.1 h whatever D, and the free-surface coefficient is
    /// positive even at a stagnation point (the exponential term) and zero at rest.
    #[test]
    fn cap_and_coefficients() {
        let h = 0.013;
        let g = vec![Vec2::new(300.0, -400.0), Vec2::new(1e-3, 0.0)];
        let dx = displacements(&g, &[1.0, 1e-6], None, h);
        assert!((dx[0].norm() - 0.1 * h).abs() < 1e-15);
        assert!((dx[0].normalize() - Vec2::new(-0.6, 0.8)).norm() < 1e-12);
        assert!((dx[1] - Vec2::new(-1e-9, 0.0)).norm() < 1e-24);
        let d = coefficients_free_surface(&[Vec2::zeros(), Vec2::new(2.0, 0.0)], h, 1e-4);
        assert!((d[0] - 4.0 * h * 1e-4 * 0.4).abs() < 1e-18);
        assert!((d[1] - 4.0 * h * 1e-4 * (2.0 + 0.4 * (-5f64).exp())).abs() < 1e-18);
        assert_eq!(
            coefficients_free_surface(&[Vec2::zeros(); 3], h, 1e-4),
            vec![0.0; 3]
        );
        assert_eq!(cohesion_q(0.3), 1.0 / 32.0);
        assert_eq!(cohesion_q(0.75), (0.75f64 * 0.25).powi(3));
        assert_eq!(cohesion_q(1.2), 0.0);
    }

    /// Surface detection, corrected gradients and shifting give bitwise the same results on 1
    /// and 2 threads (per-particle gathers in ascending neighbour order).
    #[test]
    fn operators_are_bitwise_independent_of_thread_count() {
        let dr = 0.01;
        let k = QuinticSpline::new(1.3 * dr);
        let x = disc(30.0 * dr, dr, 0.2, 41).x;
        let vol = vec![dr * dr; x.len()];
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    let nl = lists(&x, &k);
                    let s = surface::detect(&x, &vol, &nl, &k, &Domain::OPEN, x.len());
                    let inside: Vec<bool> = s.is_surface.iter().map(|&b| !b).collect();
                    let g = concentration_gradient(
                        &x,
                        &vol,
                        &nl,
                        &k,
                        &Domain::OPEN,
                        dr,
                        x.len(),
                        &inside,
                    );
                    let u: Vec<Vec2> = x.iter().map(|p| Vec2::new(p.y, -p.x)).collect();
                    let d = coefficients_free_surface(&u, k.h(), 1e-4);
                    let dx = displacements(&g, &d, Some((&s.is_surface, &s.normal)), k.h());
                    let l = crate::operators::correction::correction_matrices(
                        &x,
                        &vol,
                        &nl,
                        &k,
                        &Domain::OPEN,
                    );
                    let mut bits: Vec<u64> = s
                        .div_r
                        .iter()
                        .chain(&s.concentration)
                        .map(|v| v.to_bits())
                        .collect();
                    bits.extend(
                        s.normal
                            .iter()
                            .chain(&dx)
                            .flat_map(|v| [v.x.to_bits(), v.y.to_bits()]),
                    );
                    bits.extend(
                        l.iter()
                            .flat_map(|m| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>()),
                    );
                    bits
                })
        };
        assert_eq!(run(1), run(2));
    }
}
