//! The falling column's state, for tests and measurements of the jet: how many particles each
//! band of it holds across, the largest vertical gap in it (a torn column), how far apart its
//! particles stand, how many of them the free-surface detection of King & Lind 2021 eq. (36)
//! flags, and the smallest determinant of the conformation tensor (Oldroyd-B in an
//! incompressible flow keeps det A >= 1 from det A = 1 at rest; a value well below 1 says the
//! velocity gradient the conformation sees has a trace).

use super::{Nozzle, SceneConfig};
use crate::kernel::{Kernel, QuinticSplineKernel};
use crate::neighbors::{Domain, Grid, NeighborList};
use crate::operators::surface;
use crate::state::State;

/// The column between the nozzle's exit and the heap (or the head, before contact), in bands
/// three particle spacings tall (rows stretched along the fall do not alias with them).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Column {
    /// Length of the column in particle spacings, from the exit down to its lower end: half a
    /// jet width above the heap's top once there is a heap, the lowest free particle before.
    pub length: f64,
    /// Largest vertical distance between consecutive particles of the column (sorted by
    /// height), in particle spacings: 1 on the lattice, up to about 1.5 where its rows are
    /// stretched apart, more where it has torn.
    pub largest_gap: f64,
    /// Fewest particles across (a band's count / 3), and the median over the bands.
    pub thinnest: f64,
    pub median_across: f64,
    /// Median over the column's particles of the mean distance to their 4 nearest
    /// neighbours, in particle spacings (1 on the lattice; more where the column dilates).
    pub spacing: f64,
    /// Column particles flagged free surface by eq. (36), and all the column's particles.
    pub surface: usize,
    pub particles: usize,
    /// Smallest det A over the free fluid (1 for an inelastic fluid).
    pub min_det: f64,
}

/// The column of a 2D jet state on a horizontal plate (`cfg` its effective configuration).
pub fn column(st: &State, cfg: &SceneConfig) -> Column {
    let fl = &st.fluid;
    let nz = Nozzle::from_config(cfg);
    let (dx, d) = (nz.dx, cfg.jet.jet_width);
    let u0 = cfg.jet.jet_velocity;
    let free: Vec<usize> = (0..fl.len()).filter(|&i| !nz.contains(&fl.x[i])).collect();
    let min_det = free
        .iter()
        .filter_map(|&i| fl.conf.get(i))
        .map(|a| a[(0, 0)] * a[(1, 1)] - a[(0, 1)] * a[(1, 0)])
        .fold(1.0f64, f64::min);
    // The heap as the outputs define it: free fluid moving towards the plate slower than U0/2.
    let heap_top = free
        .iter()
        .filter(|&&i| -fl.v[i].y < 0.5 * u0)
        .map(|&i| fl.x[i].y)
        .fold(f64::NEG_INFINITY, f64::max);
    let lowest = free
        .iter()
        .map(|&i| fl.x[i].y)
        .fold(f64::INFINITY, f64::min);
    let bottom = if heap_top.is_finite() {
        heap_top + 0.5 * d
    } else {
        lowest
    };
    if !bottom.is_finite() || bottom >= nz.exit {
        return Column {
            min_det,
            ..Default::default()
        };
    }
    let band = 3.0 * dx;
    let length = nz.exit - bottom;
    let bands = ((length / band).floor() as usize).max(1);
    let reach = 2.0 * d;
    let in_column = |i: usize| fl.x[i].y < nz.exit && fl.x[i].y >= bottom;
    let mut count = vec![0usize; bands];
    let col: Vec<usize> = free
        .iter()
        .copied()
        .filter(|&i| in_column(i) && fl.x[i].x.abs() < reach)
        .collect();
    for &i in &col {
        let b = ((nz.exit - fl.x[i].y) / band) as usize;
        count[b.min(bands - 1)] += 1;
    }
    let mut sorted = count.clone();
    sorted.sort_unstable();
    let mut ys: Vec<f64> = col.iter().map(|&i| fl.x[i].y).collect();
    ys.push(nz.exit);
    ys.sort_by(f64::total_cmp);
    let largest_gap = ys.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max) / dx;
    // Spacing and free surface over all fluid near the column (held particles included, so
    // that the exit's rows see their full support).
    let kernel = QuinticSplineKernel::<2>::new(1.3 * dx);
    let x = &fl.x;
    let dom = Domain::OPEN;
    let grid = Grid::build(x, kernel.radius(), &dom);
    let nl = NeighborList::build(&grid, x, x, kernel.radius(), &dom);
    let vol = vec![dx * dx; x.len()];
    let s = surface::detect::<2, _>(x, &vol, &nl, &kernel, &dom, x.len());
    let mut spacing: Vec<f64> = col
        .iter()
        .map(|&i| {
            let mut r: Vec<f64> = nl
                .of(i)
                .iter()
                .filter(|&&j| j as usize != i)
                .map(|&j| (x[j as usize] - x[i]).norm())
                .collect();
            r.sort_by(f64::total_cmp);
            let k = r.len().clamp(1, 4);
            r.iter().take(k).sum::<f64>() / k as f64 / dx
        })
        .collect();
    spacing.sort_by(f64::total_cmp);
    Column {
        length: length / dx,
        largest_gap,
        thinnest: sorted.first().copied().unwrap_or(0) as f64 / 3.0,
        median_across: median_usize(&sorted) / 3.0,
        spacing: spacing.get(spacing.len() / 2).copied().unwrap_or(0.0),
        surface: col.iter().filter(|&&i| s.is_surface[i]).count(),
        particles: col.len(),
        min_det,
    }
}

fn median_usize(sorted: &[usize]) -> f64 {
    match sorted.len() {
        0 => 0.0,
        n if n % 2 == 1 => sorted[n / 2] as f64,
        n => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]) as f64,
    }
}
