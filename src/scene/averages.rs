//! Time-averaged fields of a steady flow: what `viscosph run` writes once a scene with a steady
//! state (the cylinder array, King & Lind 2021 section IV.B) has reached it. Particles move
//! (the Lagrangian frame) and carry their values with them, so the averages are taken in the
//! Eulerian frame: every recorded state is binned on a fixed grid of square cells one particle
//! spacing wide, and each cell's value is the mean over every particle seen in it over the
//! window. The centre line y = y_c gets its own row of bins, the particles within one spacing of
//! it (King & Lind's Figs. 10 and 11 are profiles along it).
//!
//! Where the particles stay put (ISPH's Eulerian frame) each particle's own mean is kept as
//! well, and the centre line is those means interpolated to points on y = y_c by a weighted
//! quadratic least-squares fit ([`FieldAverage::interpolate`]): the cylinder array's ring
//! lattice puts particles on the line while the square lattice beyond it puts them half a
//! spacing off, so a row of bins jumps wherever the two kinds alternate (measured at 16 across:
//! tau_xx and det A stepped at the fourth ring, s = 0.56 R behind the cylinder, where the wake's
//! stress strand is a few spacings wide).

use super::SceneConfig;
use crate::dim::Tensor;
use crate::rheology::{AnyRheology, Rheology};
use crate::state::State;
use crate::Vec2;
use nalgebra::{SMatrix, SVector};

/// Radius of the interpolation's support in particle spacings ([`FieldAverage::interpolate`]):
/// about 12 particles of a square lattice, twice the 6 coefficients of the quadratic.
const FIT_RADIUS: f64 = 2.0;
/// A point farther than this many spacings from every particle is outside the fluid
/// ([`FieldAverage::interpolate`]).
const NEAREST: f64 = 0.75;

/// The span of time over which a steady run averages its fields, and the box they cover
/// ([`super::Scene::steady_window`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyWindow {
    /// When the flow became steady \[s\].
    pub start: f64,
    /// The end of the averaging \[s\] (the cylinder array: three time units after `start`).
    pub end: f64,
    /// Whether the run ends at `end` (the cylinder array's `stop_at_steady_state`).
    pub stop: bool,
    /// The corners of the box the grid covers \[m\].
    pub lower: Vec2,
    pub upper: Vec2,
    /// The height of the centre line \[m\].
    pub centre_line: f64,
    /// Whether the box is one period of the flow along x (the fluid continues across
    /// x = lower.x and x = upper.x): the interpolation then sees across.
    pub periodic_x: bool,
}

/// Quantities averaged per bin, in this order: u, v, tr A, tau_p,xx, det A (the last three 0
/// for a model without a conformation tensor).
pub const FIELDS: [&str; 5] = ["u", "v", "trace_A", "tau_xx", "det_A"];

/// An interpolated value ([`FieldAverage::interpolate`]): the five fields and the particles used.
pub type Sample = ([f64; 5], u64);

/// Sums over the particles seen in each bin.
#[derive(Debug, Clone)]
struct Bins {
    sum: Vec<[f64; 5]>,
    count: Vec<u64>,
}

impl Bins {
    fn new(n: usize) -> Self {
        Self {
            sum: vec![[0.0; 5]; n],
            count: vec![0; n],
        }
    }

    fn add(&mut self, k: usize, values: &[f64; 5]) {
        for (s, v) in self.sum[k].iter_mut().zip(values) {
            *s += v;
        }
        self.count[k] += 1;
    }

    /// The mean of bin k, None if no particle was seen in it.
    fn mean(&self, k: usize) -> Option<[f64; 5]> {
        let n = self.count[k];
        (n > 0).then(|| self.sum[k].map(|s| s / n as f64))
    }
}

/// Whether a model carries a conformation tensor.
fn elastic<R: Rheology>(_: &R) -> bool {
    R::ELASTIC
}

/// The time-averaged fields of one run (see the module documentation).
#[derive(Debug, Clone)]
pub struct FieldAverage {
    window: SteadyWindow,
    dx: f64,
    /// Cells along x and y.
    nx: usize,
    ny: usize,
    grid: Bins,
    line: Bins,
    model: Option<AnyRheology>,
    /// Per particle (in the order of the fluid): the position first seen and the sums of the
    /// values, kept while every particle stays within half a spacing of where it was first
    /// seen (ISPH's Eulerian frame), dropped as soon as one moves farther or the count changes.
    particles: Option<(Vec<Vec2>, Vec<[f64; 5]>)>,
    /// States taken in, and the first and last of their times.
    samples: usize,
    span: (f64, f64),
}

impl FieldAverage {
    /// An empty average over `window` for the flow of `cfg` (the effective configuration).
    pub fn new(cfg: &SceneConfig, window: SteadyWindow) -> Self {
        let dx = cfg.dx();
        let size = window.upper - window.lower;
        let nx = ((size.x / dx).round() as usize).max(1);
        let ny = ((size.y / dx).round() as usize).max(1);
        Self {
            window,
            dx,
            nx,
            ny,
            grid: Bins::new(nx * ny),
            line: Bins::new(nx),
            model: AnyRheology::from_config(cfg)
                .ok()
                .filter(|m| crate::dispatch_rheology!(m, m => elastic(m))),
            particles: None,
            samples: 0,
            span: (f64::INFINITY, f64::NEG_INFINITY),
        }
    }

    /// The window the average covers.
    pub fn window(&self) -> &SteadyWindow {
        &self.window
    }

    /// How many states were taken in, and over which times.
    pub fn samples(&self) -> (usize, (f64, f64)) {
        (self.samples, self.span)
    }

    /// Take in the state `st` (in order, particle by particle: the sums do not depend on the
    /// thread count).
    pub fn add(&mut self, st: &State) {
        let fl = &st.fluid;
        let (lo, dx) = (self.window.lower, self.dx);
        if self.samples == 0 {
            self.particles = Some((fl.x.clone(), vec![[0.0; 5]; fl.len()]));
        }
        if let Some((x0, _)) = &self.particles {
            let stays = x0.len() == fl.len()
                && x0.iter().zip(&fl.x).all(|(a, b)| (a - b).norm() < 0.5 * dx);
            if !stays {
                self.particles = None;
            }
        }
        for (k, (x, v)) in fl.x.iter().zip(&fl.v).enumerate() {
            let mut values = [v.x, v.y, 0.0, 0.0, 0.0];
            if let (Some(m), Some(a)) = (&self.model, fl.conf.get(k)) {
                let tau: Tensor<2> = crate::dispatch_rheology!(m, m => m.polymer_stress(a));
                values[2] = a.trace();
                values[3] = tau[(0, 0)];
                values[4] = a.determinant();
            }
            if let Some((_, sums)) = &mut self.particles {
                for (s, v) in sums[k].iter_mut().zip(&values) {
                    *s += v;
                }
            }
            let i = ((x.x - lo.x) / dx).floor();
            let j = ((x.y - lo.y) / dx).floor();
            if i < 0.0 || j < 0.0 || i >= self.nx as f64 || j >= self.ny as f64 {
                continue;
            }
            let (i, j) = (i as usize, j as usize);
            self.grid.add(j * self.nx + i, &values);
            if (x.y - self.window.centre_line).abs() < dx {
                self.line.add(i, &values);
            }
        }
        self.samples += 1;
        self.span = (self.span.0.min(st.time), self.span.1.max(st.time));
    }

    /// The grid: (centre of the cell, mean values, particles seen) of every cell a particle was
    /// seen in, row by row from the bottom.
    pub fn cells(&self) -> Vec<(Vec2, [f64; 5], u64)> {
        (0..self.nx * self.ny)
            .filter_map(|k| {
                let (i, j) = (k % self.nx, k / self.nx);
                let centre = self.window.lower
                    + Vec2::new((i as f64 + 0.5) * self.dx, (j as f64 + 0.5) * self.dx);
                self.grid.mean(k).map(|m| (centre, m, self.grid.count[k]))
            })
            .collect()
    }

    /// Per particle, if the particles stayed put over the window (ISPH's Eulerian frame): where
    /// each was first seen and its mean values, the field without the grid's empty cells next to
    /// a curved wall.
    pub fn particles(&self) -> Option<Vec<(Vec2, [f64; 5])>> {
        let (x, sums) = self.particles.as_ref()?;
        let n = self.samples.max(1) as f64;
        Some(
            x.iter()
                .zip(sums)
                .map(|(x, s)| (*x, s.map(|v| v / n)))
                .collect(),
        )
    }

    /// The centre line: (x of the bin's centre, mean values, particles used) at every bin
    /// along it, from x = lower.x on. Where the particles stayed put, the per-particle means
    /// interpolated to (x, y_c) ([`Self::interpolate`]; the count is the particles in the fit);
    /// otherwise the mean over the particles seen within one spacing of the line, for every
    /// bin one was seen in.
    pub fn centre_line(&self) -> Vec<(f64, [f64; 5], u64)> {
        let xs: Vec<f64> = (0..self.nx)
            .map(|i| self.window.lower.x + (i as f64 + 0.5) * self.dx)
            .collect();
        let on_line: Vec<Vec2> = xs
            .iter()
            .map(|&x| Vec2::new(x, self.window.centre_line))
            .collect();
        if let Some(fitted) = self.interpolate(&on_line) {
            return xs
                .iter()
                .zip(fitted)
                .filter_map(|(&x, f)| f.map(|(m, n)| (x, m, n)))
                .collect();
        }
        xs.iter()
            .enumerate()
            .filter_map(|(i, &x)| self.line.mean(i).map(|m| (x, m, self.line.count[i])))
            .collect()
    }

    /// The per-particle means (only where the particles stayed put, else None) at the points
    /// `at`: at each, a quadratic in x and y fitted by least squares to the particles within
    /// `FIT_RADIUS` spacings, weighted by Wendland's C2 function of the distance, and its
    /// value there with the number of particles used; the weighted mean where fewer than the
    /// quadratic's 6 coefficients are determined; None outside the fluid, where no particle is
    /// within `NEAREST` spacings (a lattice leaves no point of the fluid farther than
    /// sqrt(1/2) spacings from a particle, and the first particles sit half a spacing from a
    /// wall). Second order whatever the particles' arrangement (ring or square lattice, one
    /// side of the cylinder); within one and a half spacings of a straight wall only two rows
    /// are in reach, the quadratic is not determined across them and the value is the
    /// weighted mean (measured: 1.0782 for 1.0893 on the first row of a quadratic field).
    pub fn interpolate(&self, at: &[Vec2]) -> Option<Vec<Option<Sample>>> {
        let means = self.particles()?;
        let h = self.dx;
        let radius = FIT_RADIUS * h;
        // Buckets of `radius` along x and y: a point's neighbours are in its 3 x 3 buckets.
        let lo = self.window.lower;
        let key = |p: &Vec2| {
            (
                ((p.x - lo.x) / radius).floor() as i64,
                ((p.y - lo.y) / radius).floor() as i64,
            )
        };
        // Each particle, and across a periodic box's ends its image within reach.
        let period = self.window.upper.x - lo.x;
        let mut images: Vec<(Vec2, usize)> = Vec::with_capacity(means.len());
        for (k, (x, _)) in means.iter().enumerate() {
            images.push((*x, k));
            if self.window.periodic_x {
                if x.x - lo.x < radius {
                    images.push((x + Vec2::new(period, 0.0), k));
                }
                if self.window.upper.x - x.x < radius {
                    images.push((x - Vec2::new(period, 0.0), k));
                }
            }
        }
        let mut buckets: std::collections::BTreeMap<(i64, i64), Vec<usize>> = Default::default();
        for (k, (x, _)) in images.iter().enumerate() {
            buckets.entry(key(x)).or_default().push(k);
        }
        Some(
            at.iter()
                .map(|p| {
                    let (bi, bj) = key(p);
                    let mut m = SMatrix::<f64, 6, 6>::zeros();
                    let mut rhs = [SVector::<f64, 6>::zeros(); 5];
                    let (mut wsum, mut wf, mut used) = (0.0, [0.0; 5], 0u64);
                    let mut nearest = f64::INFINITY;
                    for di in -1..=1 {
                        for dj in -1..=1 {
                            for &k in buckets.get(&(bi + di, bj + dj)).into_iter().flatten() {
                                let (x, k) = &images[k];
                                let f = &means[*k].1;
                                let d = (x - p) / h;
                                nearest = nearest.min(d.norm());
                                let q = d.norm() / FIT_RADIUS;
                                if q >= 1.0 {
                                    continue;
                                }
                                // Wendland C2 on the support radius.
                                let w = (1.0 - q).powi(4) * (1.0 + 4.0 * q);
                                let b = SVector::<f64, 6>::from([
                                    1.0,
                                    d.x,
                                    d.y,
                                    d.x * d.x,
                                    d.x * d.y,
                                    d.y * d.y,
                                ]);
                                m += b * b.transpose() * w;
                                for (r, v) in rhs.iter_mut().zip(f) {
                                    *r += b * (w * v);
                                }
                                wsum += w;
                                for (s, v) in wf.iter_mut().zip(f) {
                                    *s += w * v;
                                }
                                used += 1;
                            }
                        }
                    }
                    if used == 0 || nearest >= NEAREST {
                        return None;
                    }
                    // The fit where its normal equations are well conditioned (relative to the
                    // weights: a row of particles on one line leaves the quadratic undetermined).
                    let fit = (used >= 6)
                        .then(|| m.cholesky())
                        .flatten()
                        .filter(|c| {
                            let d = c.l().diagonal();
                            d.min() > 1e-6 * wsum.sqrt()
                        })
                        .map(|c| rhs.map(|r| c.solve(&r)[0]));
                    Some((fit.unwrap_or(wf.map(|v| v / wsum)), used))
                })
                .collect(),
        )
    }
}
