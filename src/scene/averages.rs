//! Time-averaged fields of a steady flow: what `viscosph run` writes once a scene with a steady
//! state (the cylinder array, King & Lind 2021 section IV.B) has reached it. Particles move
//! (the Lagrangian frame) and carry their values with them, so the averages are taken in the
//! Eulerian frame: every recorded state is binned on a fixed grid of square cells one particle
//! spacing wide, and each cell's value is the mean over every particle seen in it over the
//! window. The centre line y = y_c gets its own row of bins, the particles within one spacing of
//! it (King & Lind's Figs. 10 and 11 are profiles along it).

use super::SceneConfig;
use crate::dim::Tensor;
use crate::rheology::{AnyRheology, Rheology};
use crate::state::State;
use crate::Vec2;

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
}

/// Quantities averaged per bin, in this order: u, v, tr A, tau_p,xx, det A (the last three 0
/// for a model without a conformation tensor).
pub const FIELDS: [&str; 5] = ["u", "v", "trace_A", "tau_xx", "det_A"];

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

    /// The centre line: (x of the bin's centre, mean values, particles seen) of every bin a
    /// particle was seen in, from x = lower.x on.
    pub fn centre_line(&self) -> Vec<(f64, [f64; 5], u64)> {
        (0..self.nx)
            .filter_map(|i| {
                let x = self.window.lower.x + (i as f64 + 0.5) * self.dx;
                self.line.mean(i).map(|m| (x, m, self.line.count[i]))
            })
            .collect()
    }
}
