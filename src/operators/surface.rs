//! Free-surface detection and surface normals of King & Lind 2021 section III.D.
//!
//! Detection, eqs. (36)-(37): particle i is on the free surface when
//! `div r_i <= 1.4 + 0.5 max(C^_i - 1, -0.2)`, with the divergence of position
//! `div r_i = sum_j V_j x_ji . grad_i W_ij` (2 under full support in 2D, 3 in 3D, about half
//! that on a flat surface), the concentration `C_i = sum_j V_j W_ij` and
//! `C^_i = N C_i / sum_k C_k` over the N fluid particles: a compressed region (C^ > 1) gets a
//! higher threshold. The threshold is the paper's (2D) as printed (King's code uses the same),
//! kept with the dimension ([`Dim::surface_threshold`]); the uncorrected kernel gradient is used.
//! Ghost (mirror) points count as neighbours, so particles next to a wall are not surface.
//!
//! Normals, eqs. (38)-(39): `n*_i = (1/h) sum_j V_j grad_i W_ij`, the concentration gradient,
//! then smoothed, `n_i = sum_j V_j n*_j W_ij / C_j` over the fluid neighbours (ghosts carry no
//! n*). The concentration gradient points *into* the fluid (grad_i W_ij points from i towards
//! j), so the unit outward normal is `-n_i / |n_i|` (the paper's n in (34) points out of the
//! fluid). Where |n_i| vanishes (deep inside), the normal is zero.

use crate::dim::{Const, Dim, Vector};
use crate::kernel::Kernel;
use crate::neighbors::{Domain, NeighborList};
use rayon::prelude::*;

/// Detection threshold of King & Lind 2021 eq. (36) at normalised concentration `c_hat` in N
/// dimensions ([`Dim::surface_threshold`]; in 2D 1.4 + 0.5 max(C^ - 1, -0.2)).
#[inline]
pub fn threshold<const N: usize>(c_hat: f64) -> f64
where
    Const<N>: Dim,
{
    Const::<N>::surface_threshold(c_hat)
}

/// Everything section III.D defines, per fluid particle, in N dimensions (2 unless said).
#[derive(Debug, Clone, PartialEq)]
pub struct Surface<const N: usize = 2> {
    /// Divergence of position, eq. (36).
    pub div_r: Vec<f64>,
    /// Concentration C_i, eq. (37).
    pub concentration: Vec<f64>,
    /// Free-surface set FS.
    pub is_surface: Vec<bool>,
    /// Near-surface set NS: not in FS, with at least one neighbour in FS.
    pub near_surface: Vec<bool>,
    /// Unit outward normal (zero where the smoothed concentration gradient vanishes).
    pub normal: Vec<Vector<N>>,
}

/// Detect the free surface and its normals for the first `n_fluid` points; the lists'
/// neighbours may include ghosts (index >= `n_fluid`), which count in div r and C but carry no
/// normal.
pub fn detect<const N: usize, K: Kernel<N>>(
    x: &[Vector<N>],
    vol: &[f64],
    nl: &NeighborList,
    kernel: &K,
    domain: &Domain,
    n_fluid: usize,
) -> Surface<N>
where
    Const<N>: Dim,
{
    assert!(nl.len() >= n_fluid);
    let inv_h = 1.0 / kernel.h();
    // Per particle: div r, C, n*.
    let (div_r, (concentration, n_star)): (Vec<f64>, (Vec<f64>, Vec<Vector<N>>)) = (0..n_fluid)
        .into_par_iter()
        .map(|i| {
            let (mut div, mut c, mut g) = (0.0, 0.0, Vector::<N>::zeros());
            for &j in nl.of(i) {
                let j = j as usize;
                let xij = domain.delta(&x[i], &x[j]);
                let (w, f) = kernel.w_and_dw_over_r(xij.norm());
                let grad = xij * f;
                div -= vol[j] * xij.dot(&grad);
                c += vol[j] * w;
                g += vol[j] * grad;
            }
            (div, (c, g * inv_h))
        })
        .unzip();
    detect_from_sums(
        div_r,
        concentration,
        n_star,
        x,
        vol,
        nl,
        kernel,
        domain,
        n_fluid,
    )
}

/// The rest of [`detect`] from its per-particle sums (div r, C and n* of eqs. (36)-(38)), for a
/// scheme that gathers them in a pass it makes anyway (ISPH's fused neighbour pass).
#[allow(clippy::too_many_arguments)]
pub fn detect_from_sums<const N: usize, K: Kernel<N>>(
    div_r: Vec<f64>,
    concentration: Vec<f64>,
    n_star: Vec<Vector<N>>,
    x: &[Vector<N>],
    vol: &[f64],
    nl: &NeighborList,
    kernel: &K,
    domain: &Domain,
    n_fluid: usize,
) -> Surface<N>
where
    Const<N>: Dim,
{
    let mean_c = crate::operators::sums::fixed_sum(&concentration) / n_fluid.max(1) as f64;
    let is_surface: Vec<bool> = (0..n_fluid)
        .map(|i| div_r[i] <= threshold::<N>(concentration[i] / mean_c))
        .collect();
    let near_surface = (0..n_fluid)
        .into_par_iter()
        .map(|i| {
            !is_surface[i]
                && nl
                    .of(i)
                    .iter()
                    .any(|&j| (j as usize) < n_fluid && is_surface[j as usize])
        })
        .collect();
    let normal = (0..n_fluid)
        .into_par_iter()
        .map(|i| {
            let mut n = Vector::<N>::zeros();
            for &j in nl.of(i) {
                let j = j as usize;
                if j >= n_fluid {
                    continue;
                }
                let r = domain.delta(&x[i], &x[j]).norm();
                n += vol[j] * n_star[j] * kernel.w(r) / concentration[j];
            }
            let len = n.norm();
            if len > 1e-12 {
                -n / len
            } else {
                Vector::<N>::zeros()
            }
        })
        .collect();
    Surface {
        div_r,
        concentration,
        is_surface,
        near_surface,
        normal,
    }
}

/// Wendland C2 kernel in 1D with smoothing length `h` (support 2h), unnormalised.
#[inline]
fn wendland_1d(r: f64, h: f64) -> f64 {
    let q = r / h;
    if q >= 2.0 {
        0.0
    } else {
        let t = 1.0 - 0.5 * q;
        t * t * t * (1.0 + 1.5 * q)
    }
}

/// Line density of the free-surface row at each surface particle, relative to a straight row
/// of spacing `dx` (1 there, 1 / s for a row of spacing s dx; 0 off the surface): a 1D kernel
/// sum over the surface neighbours only, with smoothing length `h`. In 3D the surface is a
/// sheet: the same sum against a flat square sheet of spacing `dx`, square-rooted, so that a
/// sheet of spacing s dx again gives 1 / s.
pub fn row_density<const N: usize>(
    x: &[Vector<N>],
    nl: &NeighborList,
    domain: &Domain,
    is_surface: &[bool],
    h: f64,
    dx: f64,
) -> Vec<f64> {
    let n = is_surface.len();
    let reach = (2.0 * h / dx).ceil() as i64;
    assert!(N == 2 || N == 3, "a surface row or sheet in 2D or 3D");
    let flat: f64 = if N == 2 {
        (-reach..=reach)
            .map(|k| wendland_1d((k as f64 * dx).abs(), h))
            .sum()
    } else {
        (-reach..=reach)
            .flat_map(|a| (-reach..=reach).map(move |b| (a, b)))
            .map(|(a, b)| wendland_1d(dx * ((a * a + b * b) as f64).sqrt(), h))
            .sum()
    };
    (0..n)
        .into_par_iter()
        .map(|i| {
            if !is_surface[i] {
                return 0.0;
            }
            let mut c = 0.0;
            for &j in nl.of(i) {
                let j = j as usize;
                if j < n && is_surface[j] {
                    c += wendland_1d(domain.delta(&x[i], &x[j]).norm(), h);
                }
            }
            if N == 2 {
                c / flat
            } else {
                (c / flat).sqrt()
            }
        })
        .collect()
}

/// The concentration `sum_j V_j W_ij` a particle keeps when the fluid ends at a straight row a
/// distance `a` from it along the outward normal, as a share of its value inside the full
/// lattice: the rows at `a - k dx`, k >= 0, each with the tangentially averaged line sum
/// `R(y) = int W(sqrt(s^2 + y^2)) ds`, over the rows at `a - k dx` for every integer k. It is
/// the reference of the near-surface density-invariant source of `scheme::isph` (a truncated
/// support reads as expansion against the interior's C0; against this it does not). In 3D the
/// rows are planes and R(y) is the plane integral `2 pi int W(sqrt(s^2 + y^2)) s ds`.
#[derive(Debug, Clone)]
pub struct HalfLattice {
    dx: f64,
    reach: f64,
    /// R(y) at `TABLE + 1` points on [0, reach].
    line: Vec<f64>,
    /// The row's second moment `M(y) = (1/2) int rho^2 W(sqrt(rho^2 + y^2)) dA` (2D: over the
    /// line) at the same points: the concentration a curved surface removes per unit of its
    /// mean curvature ([`HalfLattice::curved_share`]).
    moment: Vec<f64>,
}

impl HalfLattice {
    const TABLE: usize = 512;
    /// Simpson intervals of one line integral.
    const QUAD: usize = 400;

    pub fn new<const N: usize, K: Kernel<N>>(kernel: &K, dx: f64) -> Self {
        let reach = kernel.radius();
        let (line, moment) = if N == 3 {
            // Plane integrals by Simpson's rule in the radius.
            let hs = reach / Self::QUAD as f64;
            let two_pi = 2.0 * std::f64::consts::PI;
            (
                Self::tabulate(kernel, 0.0, hs, two_pi, |s| s),
                Self::tabulate(kernel, 0.0, hs, std::f64::consts::PI, |s| s * s * s),
            )
        } else {
            assert_eq!(N, 2, "a half lattice in 2D or 3D");
            let hs = 2.0 * reach / Self::QUAD as f64;
            (
                Self::tabulate(kernel, -reach, hs, 1.0, |_| 1.0),
                Self::tabulate(kernel, -reach, hs, 1.0, |s| 0.5 * s * s),
            )
        };
        Self {
            dx,
            reach,
            line,
            moment,
        }
    }

    /// `scale int f(s) W(sqrt(s^2 + y^2)) ds` by Simpson's rule over s = `start` + q `hs`,
    /// q = 0..=QUAD, at the `TABLE + 1` points y on [0, reach]: the tables of R and M.
    fn tabulate<const N: usize, K: Kernel<N>>(
        kernel: &K,
        start: f64,
        hs: f64,
        scale: f64,
        f: impl Fn(f64) -> f64,
    ) -> Vec<f64> {
        let reach = kernel.radius();
        (0..=Self::TABLE)
            .map(|k| {
                let y = reach * k as f64 / Self::TABLE as f64;
                let sum = Self::simpson(|q| {
                    let s = start + q as f64 * hs;
                    f(s) * kernel.w((s * s + y * y).sqrt())
                });
                scale * sum * hs / 3.0
            })
            .collect()
    }

    /// Simpson's weighted sum of `f(q)` over the points q = 0..=QUAD (times h / 3: the
    /// integral).
    fn simpson(f: impl Fn(usize) -> f64) -> f64 {
        (0..=Self::QUAD)
            .map(|q| {
                let wq = if q == 0 || q == Self::QUAD {
                    1.0
                } else if q % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                wq * f(q)
            })
            .sum()
    }

    fn line_sum(&self, y: f64) -> f64 {
        Self::interpolate(&self.line, y, self.reach)
    }

    fn interpolate(table: &[f64], y: f64, reach: f64) -> f64 {
        let y = y.abs();
        if y >= reach {
            return 0.0;
        }
        let t = y / reach * Self::TABLE as f64;
        let k = (t as usize).min(Self::TABLE - 1);
        let f = t - k as f64;
        table[k] * (1.0 - f) + table[k + 1] * f
    }

    /// [`HalfLattice::share`] below a surface of mean curvature `curvature` (the mean of the
    /// principal curvatures, positive where the fluid is convex; in 2D the curvature of the
    /// line): the fluid between the tangent plane and the surface, `curvature rho^2 / 2` thick at
    /// lateral distance rho, is missing from the share, i.e. `curvature M(s) / (dx sum_k R)` with
    /// the surface `s = a + dx / 2` above the particle (its row's own layer). At least half the
    /// flat share.
    pub fn curved_share(&self, a: f64, curvature: f64) -> f64 {
        let flat = self.share(a);
        let a = a.max(0.0);
        if a >= self.reach {
            return flat;
        }
        let kmax = ((a + self.reach) / self.dx).ceil() as i64;
        let kmin = -(((self.reach - a) / self.dx).ceil() as i64);
        let all: f64 = (kmin..=kmax)
            .map(|k| self.line_sum(a - k as f64 * self.dx))
            .sum();
        let missing = curvature * Self::interpolate(&self.moment, a + 0.5 * self.dx, self.reach)
            / (self.dx * all);
        (flat - missing).max(0.5 * flat)
    }

    /// The share at distance `a` inside the last row (1 from the kernel's reach on).
    pub fn share(&self, a: f64) -> f64 {
        let a = a.max(0.0);
        if a >= self.reach {
            return 1.0;
        }
        let kmax = ((a + self.reach) / self.dx).ceil() as i64;
        let kmin = -(((self.reach - a) / self.dx).ceil() as i64);
        let (mut part, mut all) = (0.0, 0.0);
        for k in kmin..=kmax {
            let r = self.line_sum(a - k as f64 * self.dx);
            all += r;
            if k >= 0 {
                part += r;
            }
        }
        part / all
    }
}

/// Mean curvature (the mean of the principal curvatures; in 2D the curvature) of the free
/// surface at each free-surface particle, positive where the fluid is convex, from the heights of
/// its surface neighbours below its tangent plane: a surface `z = -(k1 x^2 + k2 y^2) / 2` puts
/// neighbour j at `d_j = -n . x_ji` below the plane at lateral distance `rho_j`, and
/// `2 sum_j W d_j / sum_j W rho_j^2` is `(k1 + k2) / 2` for neighbours spread evenly about the
/// normal (`k` in 2D). Zero off the surface and where no surface neighbour has a lateral
/// distance.
pub fn mean_curvature<const N: usize, K: Kernel<N>>(
    x: &[Vector<N>],
    nl: &NeighborList,
    domain: &Domain,
    surface: &Surface<N>,
    kernel: &K,
) -> Vec<f64> {
    let n = surface.is_surface.len();
    (0..n)
        .into_par_iter()
        .map(|i| {
            let ni = surface.normal[i];
            if !surface.is_surface[i] || ni == Vector::<N>::zeros() {
                return 0.0;
            }
            let (mut num, mut den) = (0.0, 0.0);
            for &j in nl.of(i) {
                let j = j as usize;
                if j >= n || j == i || !surface.is_surface[j] {
                    continue;
                }
                let xji = domain.delta(&x[j], &x[i]);
                let w = kernel.w(xji.norm());
                let along = xji.dot(&ni);
                num += w * -along;
                den += w * (xji.norm_squared() - along * along);
            }
            if den > 0.0 {
                2.0 * num / den
            } else {
                0.0
            }
        })
        .collect()
}

/// The kernel-weighted mean of the surface neighbours' `curvature` ([`mean_curvature`]) at
/// fluid particle `i` (0 without one): the curvature of the surface row above a near-surface
/// particle.
pub fn row_curvature<const N: usize, K: Kernel<N>>(
    i: usize,
    x: &[Vector<N>],
    nl: &NeighborList,
    domain: &Domain,
    surface: &Surface<N>,
    curvature: &[f64],
    kernel: &K,
) -> f64 {
    surface_neighbour_mean(i, x, nl, domain, surface, kernel, |j, _| Some(curvature[j]))
        .unwrap_or(0.0)
}

/// Distance of fluid particle `i` from the free-surface row along the outward normal: the
/// kernel-weighted mean of `(x_j - x_i) . n_j` over its free-surface neighbours j with a normal
/// (None without one), at least 0.
#[allow(clippy::too_many_arguments)]
pub fn row_distance<const N: usize, K: Kernel<N>>(
    i: usize,
    x: &[Vector<N>],
    nl: &NeighborList,
    domain: &Domain,
    surface: &Surface<N>,
    kernel: &K,
) -> Option<f64> {
    let normal = &surface.normal;
    surface_neighbour_mean(i, x, nl, domain, surface, kernel, |j, xji| {
        (normal[j] != Vector::<N>::zeros()).then(|| xji.dot(&normal[j]))
    })
    .map(|a| a.max(0.0))
}

/// The kernel-weighted mean over the free-surface neighbours j of fluid particle `i` of
/// `value(j, x_j - x_i)`, skipping the neighbours for which it is None (None when none is left):
/// the one loop of [`row_curvature`] and [`row_distance`].
fn surface_neighbour_mean<const N: usize, K: Kernel<N>>(
    i: usize,
    x: &[Vector<N>],
    nl: &NeighborList,
    domain: &Domain,
    surface: &Surface<N>,
    kernel: &K,
    value: impl Fn(usize, &Vector<N>) -> Option<f64>,
) -> Option<f64> {
    let n = surface.is_surface.len();
    let (mut sw, mut sa) = (0.0, 0.0);
    for &j in nl.of(i) {
        let j = j as usize;
        if j < n && j != i && surface.is_surface[j] {
            let xji = domain.delta(&x[j], &x[i]);
            if let Some(v) = value(j, &xji) {
                let w = kernel.w(xji.norm());
                sw += w;
                sa += w * v;
            }
        }
    }
    (sw > 0.0).then(|| sa / sw)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::QuinticSpline;
    use crate::neighbors::CellGrid;
    use crate::operators::fixtures::disc;
    use crate::Vec2;

    fn run(x: &[Vec2], dr: f64) -> Surface {
        let k = QuinticSpline::new(1.3 * dr);
        let grid = CellGrid::build(x, k.radius(), &crate::neighbors::Domain::OPEN);
        let nl = NeighborList::build(&grid, x, x, k.radius(), &crate::neighbors::Domain::OPEN);
        let vol = vec![dr * dr; x.len()];
        detect(x, &vol, &nl, &k, &Domain::OPEN, x.len())
    }

    /// The half-lattice share is 1 beyond the kernel's reach, 0.715 on the last row
    /// (the row itself and the half plane below it), rises with depth, and matches the lattice
    /// sum of a particle that many rows below a straight edge to 0.2 %.
    #[test]
    fn half_lattice_share_is_the_lattice_sum_below_a_straight_edge() {
        let dx = 0.01;
        let k = QuinticSpline::new(1.3 * dx);
        let hl = HalfLattice::new(&k, dx);
        assert_eq!(hl.share(k.radius() + dx), 1.0);
        let reach = (k.radius() / dx).ceil() as i64 + 1;
        let full: f64 = (-reach..=reach)
            .flat_map(|a| (-reach..=reach).map(move |b| (a, b)))
            .map(|(a, b)| k.w(dx * ((a * a + b * b) as f64).sqrt()))
            .sum();
        let mut last = 0.0;
        for m in 0..4 {
            // Rows y <= m dx above the particle, all rows below.
            let half: f64 = (-reach..=reach)
                .flat_map(|a| (-reach..=m).map(move |b| (a, b)))
                .map(|(a, b)| k.w(dx * ((a * a + b * b) as f64).sqrt()))
                .sum();
            let s = hl.share(m as f64 * dx);
            assert!(
                (s - half / full).abs() < 2e-3,
                "row {m}: {s} vs {}",
                half / full
            );
            assert!(s > last);
            last = s;
        }
        // The last row keeps its own row and the half plane below it: 0.715 for the quintic at
        // h = 1.3 dx (the row itself weighs more than the half plane beyond it).
        assert!((0.70..0.73).contains(&hl.share(0.0)), "{}", hl.share(0.0));
    }

    /// On a lattice disc the surface set is the outer ring: every particle less than 0.5 dr from
    /// the circle is flagged, none deeper than 0.75 dr (the lattice's staircase puts the
    /// outermost particles between 0 and 0.7 dr inside), and the ring is closed (every 6-degree
    /// sector has a surface particle). Normals are radial to 4 degrees on average, 7.5 at worst
    /// (the staircase tilts the local surface).
    #[test]
    fn lattice_disc_surface_is_the_outer_ring_with_radial_normals() {
        let dr = 0.01;
        let radius = 20.0 * dr;
        let x = disc(radius, dr, 0.0, 0).x;
        let s = run(&x, dr);
        let mut sectors = [false; 60];
        let mut angles = Vec::new();
        for (i, p) in x.iter().enumerate() {
            let depth = (radius - p.norm()) / dr;
            if depth < 0.5 {
                assert!(s.is_surface[i], "{p:?}: div r = {}", s.div_r[i]);
            }
            if depth > 0.75 {
                assert!(!s.is_surface[i], "{p:?}: div r = {}", s.div_r[i]);
            }
            if s.is_surface[i] {
                let a = p.y.atan2(p.x).to_degrees() + 180.0;
                sectors[((a / 6.0) as usize).min(59)] = true;
                angles.push(s.normal[i].dot(&p.normalize()).min(1.0).acos().to_degrees());
            }
        }
        assert!(sectors.iter().all(|&b| b), "ring has a gap");
        let mean = angles.iter().sum::<f64>() / angles.len() as f64;
        let worst = angles.iter().cloned().fold(0.0, f64::max);
        assert!(mean < 4.5 && worst < 8.0, "mean {mean} worst {worst}");
        // Deep inside: full support, div r = 2 to a fraction of a percent.
        for (i, p) in x.iter().enumerate() {
            if p.norm() < radius - 5.0 * dr {
                assert!((s.div_r[i] - 2.0).abs() < 0.01, "{}", s.div_r[i]);
                assert!(!s.near_surface[i]);
            }
        }
        assert!(s.near_surface.iter().any(|&b| b));
    }

    /// Square block: the surface is the outermost row and column on each side; the normals of
    /// the edge particles (corners excepted) are the side's outward normal within 3 degrees.
    #[test]
    fn square_block_surface_and_normals() {
        let dr = 0.02;
        let n = 24;
        let x: Vec<Vec2> = (0..n * n)
            .map(|k| Vec2::new((k % n) as f64 * dr, (k / n) as f64 * dr))
            .collect();
        let s = run(&x, dr);
        for k in 0..n * n {
            let (i, j) = (k % n, k / n);
            let edge = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            assert_eq!(s.is_surface[k], edge, "({i}, {j}): div r = {}", s.div_r[k]);
            let corner_zone = (i < 3 || i > n - 4) && (j < 3 || j > n - 4);
            if edge && !corner_zone {
                let out = if i == 0 {
                    Vec2::new(-1.0, 0.0)
                } else if i == n - 1 {
                    Vec2::new(1.0, 0.0)
                } else if j == 0 {
                    Vec2::new(0.0, -1.0)
                } else {
                    Vec2::new(0.0, 1.0)
                };
                assert!(
                    s.normal[k].dot(&out) > 3f64.to_radians().cos(),
                    "({i}, {j}) {:?}",
                    s.normal[k]
                );
            }
        }
    }

    /// The surface row's line density is 1 on a straight row of spacing dr, 1 / s on a row of
    /// spacing s dr (crowded: above 1), and 0 off the surface.
    #[test]
    fn row_density_measures_the_surface_spacing() {
        let dr = 0.01;
        let h = 1.3 * dr;
        for (s, expect) in [(1.0, 1.0), (0.8, 1.25), (1.25, 0.8)] {
            let mut x: Vec<Vec2> = (0..41).map(|k| Vec2::new(k as f64 * s * dr, 0.0)).collect();
            x.push(Vec2::new(20.0 * s * dr, -dr));
            let mut fs = vec![true; 41];
            fs.push(false);
            let grid = CellGrid::build(&x, 3.0 * h, &Domain::OPEN);
            let nl = NeighborList::build(&grid, &x, &x, 3.0 * h, &Domain::OPEN);
            let c = row_density(&x, &nl, &Domain::OPEN, &fs, h, dr);
            assert!(
                (c[20] - expect).abs() < 0.01 * expect,
                "spacing {s}: {}",
                c[20]
            );
            assert_eq!(c[41], 0.0);
        }
    }

    #[test]
    fn threshold_follows_the_concentration() {
        assert_eq!(threshold::<2>(1.0), 1.4);
        assert!((threshold::<2>(0.5) - 1.3).abs() < 1e-15);
        assert!((threshold::<2>(1.2) - 1.5).abs() < 1e-15);
    }
}
