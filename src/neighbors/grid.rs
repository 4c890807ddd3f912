//! A uniform cell grid filled by a counting sort, and compact (CSR) neighbour lists built from it
//! in parallel, in N dimensions. Along a periodic axis of the domain the grid spans exactly one
//! period and its cells wrap, so particles near one end find those near the other at their
//! nearest image.
//!
//! Determinism: each list is sorted by neighbour index, so every sum over neighbours runs in the
//! same order whatever the thread count and whenever the list was last rebuilt. Lists are built with
//! a skin (radius = support + skin) and reused until some particle has moved more than half the
//! skin; particles in the skin but outside the support contribute exact zeros.

use super::Domain;
use crate::dim::Vector;
use rayon::prelude::*;

/// Uniform grid of cells over the bounding box of a point set in N dimensions (over one period
/// along a periodic axis).
#[derive(Debug, Clone)]
pub struct Grid<const N: usize> {
    origin: Vector<N>,
    /// Inverse cell side per axis (the number of cells over the period along a periodic axis).
    inv_cell: [f64; N],
    /// Whether the cells wrap along each axis.
    periodic: [bool; N],
    /// Number of cells per axis; cell (c_0, c_1, ...) is number c_0 + n_0 (c_1 + n_1 (...)).
    cells: [usize; N],
    /// `cell_start[c]..cell_start[c+1]` indexes `sorted` for cell c.
    cell_start: Vec<u32>,
    /// Point indices ordered by cell, ascending index within a cell.
    sorted: Vec<u32>,
}

/// The 2D grid.
pub type CellGrid = Grid<2>;

impl<const N: usize> Default for Grid<N> {
    /// An empty grid of one cell.
    fn default() -> Self {
        Self {
            origin: Vector::<N>::zeros(),
            inv_cell: [1.0; N],
            periodic: [false; N],
            cells: [1; N],
            cell_start: vec![0, 0],
            sorted: Vec::new(),
        }
    }
}

impl<const N: usize> Grid<N> {
    /// Bin `points` into cells of side `cell` (>= the largest search radius used with it) in the
    /// domain `dom` (points of a periodic domain lie in its box).
    pub fn build(points: &[Vector<N>], cell: f64, dom: &Domain) -> Self {
        assert!(cell > 0.0 && cell.is_finite());
        assert!(
            (N..3).all(|a| dom.period(a).is_none()),
            "a periodic axis the {N}D positions do not have"
        );
        let inv_cell = 1.0 / cell;
        if points.is_empty() {
            return Self {
                inv_cell: [inv_cell; N],
                ..Default::default()
            };
        }
        let (lo, hi) = points
            .par_iter()
            .fold(
                || {
                    (
                        Vector::<N>::repeat(f64::INFINITY),
                        Vector::<N>::repeat(f64::NEG_INFINITY),
                    )
                },
                |(lo, hi), p| (lo.inf(p), hi.sup(p)),
            )
            .reduce(
                || {
                    (
                        Vector::<N>::repeat(f64::INFINITY),
                        Vector::<N>::repeat(f64::NEG_INFINITY),
                    )
                },
                |a, b| (a.0.inf(&b.0), a.1.sup(&b.1)),
            );
        let mut grid = Self {
            origin: lo,
            inv_cell: [inv_cell; N],
            periodic: [false; N],
            cells: [1; N],
            cell_start: Vec::new(),
            sorted: Vec::new(),
        };
        for a in 0..N {
            match dom.period(a) {
                // Whole cells of at least `cell` across one period, from 0.
                Some(l) => {
                    let n = ((l * inv_cell).floor() as usize).max(1);
                    grid.origin[a] = 0.0;
                    grid.cells[a] = n;
                    grid.inv_cell[a] = n as f64 / l;
                    grid.periodic[a] = true;
                }
                None => {
                    grid.cells[a] = (((hi[a] - lo[a]) * inv_cell).floor() as usize + 1).max(1);
                }
            }
        }
        let total: usize = grid.cells.iter().product();
        let cells: Vec<u32> = points.par_iter().map(|p| grid.cell_of(p) as u32).collect();
        let mut count = vec![0u32; total + 1];
        for &c in &cells {
            count[c as usize + 1] += 1;
        }
        for c in 0..total {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut sorted = vec![0u32; points.len()];
        for (i, &c) in cells.iter().enumerate() {
            sorted[fill[c as usize] as usize] = i as u32;
            fill[c as usize] += 1;
        }
        grid.cell_start = count;
        grid.sorted = sorted;
        grid
    }

    /// Cell coordinates of `p` per axis (outside the grid for a point outside its box).
    #[inline]
    fn coords(&self, p: &Vector<N>) -> [i64; N] {
        std::array::from_fn(|a| ((p[a] - self.origin[a]) * self.inv_cell[a]).floor() as i64)
    }

    /// The cell of `p`, the nearest one for a point outside the grid.
    #[inline]
    fn cell_of(&self, p: &Vector<N>) -> usize {
        let c = self.coords(p);
        let mut index = 0;
        for a in (0..N).rev() {
            index = index * self.cells[a] + c[a].clamp(0, self.cells[a] as i64 - 1) as usize;
        }
        index
    }

    /// Call `f` with every point index binned in the 3^N block of cells around `p`
    /// (a superset of the points within one cell side of `p`).
    #[inline]
    pub fn for_each_candidate(&self, p: &Vector<N>, mut f: impl FnMut(u32)) {
        let c = self.coords(p);
        // Per axis, the cells to visit: the three around c, wrapped and without repeats along a
        // periodic axis (a period of one or two cells), those inside the grid along an open one.
        let mut span = [[0usize; 3]; N];
        let mut len = [0usize; N];
        for a in 0..N {
            let n = self.cells[a] as i64;
            if self.periodic[a] {
                let ca = c[a].clamp(0, n - 1);
                for x in [ca - 1, ca, ca + 1] {
                    let x = x.rem_euclid(n) as usize;
                    if !span[a][..len[a]].contains(&x) {
                        span[a][len[a]] = x;
                        len[a] += 1;
                    }
                }
            } else {
                for x in (c[a] - 1).max(0)..=(c[a] + 1).min(n - 1) {
                    span[a][len[a]] = x as usize;
                    len[a] += 1;
                }
            }
            if len[a] == 0 {
                return;
            }
        }
        // Every combination, x fastest.
        let mut k = [0usize; N];
        loop {
            let mut cell = 0;
            for a in (0..N).rev() {
                cell = cell * self.cells[a] + span[a][k[a]];
            }
            let (from, to) = (
                self.cell_start[cell] as usize,
                self.cell_start[cell + 1] as usize,
            );
            for &j in &self.sorted[from..to] {
                f(j);
            }
            let mut a = 0;
            loop {
                if a == N {
                    return;
                }
                k[a] += 1;
                if k[a] < len[a] {
                    break;
                }
                k[a] = 0;
                a += 1;
            }
        }
    }
}

/// Compressed neighbour lists: `neighbors(i)` are the indices within `radius` of query point i,
/// ascending.
#[derive(Debug, Clone, Default)]
pub struct NeighborList {
    start: Vec<u32>,
    idx: Vec<u32>,
    /// Number of points the lists index: every entry is below it.
    points: usize,
}

/// For each chunk of query points (in order), the number of points within `radius` of each
/// query and their indices, ascending per query; `delta(p, q)` is x_p - x_q.
fn candidates_within<const N: usize>(
    grid: &Grid<N>,
    points: &[Vector<N>],
    queries: &[Vector<N>],
    radius: f64,
    delta: impl Fn(&Vector<N>, &Vector<N>) -> Vector<N> + Sync,
) -> Vec<(Vec<u32>, Vec<u32>)> {
    let r2 = radius * radius;
    const CHUNK: usize = 512;
    queries
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut counts = Vec::with_capacity(chunk.len());
            let mut idx = Vec::with_capacity(chunk.len() * 40);
            for q in chunk {
                let before = idx.len();
                grid.for_each_candidate(q, |j| {
                    if delta(&points[j as usize], q).norm_squared() <= r2 {
                        idx.push(j);
                    }
                });
                idx[before..].sort_unstable();
                counts.push((idx.len() - before) as u32);
            }
            (counts, idx)
        })
        .collect()
}

impl NeighborList {
    /// Lists for every query point of the points within `radius`, using `grid` built over
    /// `points` with a cell side >= radius. Runs in parallel over chunks of query points and
    /// concatenates in order, so the result does not depend on the thread count.
    pub fn build<const N: usize>(
        grid: &Grid<N>,
        points: &[Vector<N>],
        queries: &[Vector<N>],
        radius: f64,
        dom: &Domain,
    ) -> Self {
        // In an open domain x_ij is the plain difference (bitwise what `delta` returns): the
        // test runs for every candidate pair, and the per-axis period checks cost as much as the
        // distance itself (callgrind: a fifth of the neighbour search of a drop). Each case is
        // its own instance of the candidate loop, with no test of the domain inside it.
        let parts = if dom.is_periodic() {
            candidates_within(grid, points, queries, radius, |p, q| dom.delta(p, q))
        } else {
            candidates_within(grid, points, queries, radius, |p, q| p - q)
        };
        let mut start = Vec::with_capacity(queries.len() + 1);
        start.push(0u32);
        let total: usize = parts.iter().map(|p| p.1.len()).sum();
        let mut idx = Vec::with_capacity(total);
        for (counts, part) in parts {
            for c in counts {
                let last = *start.last().expect("non-empty");
                start.push(last + c);
            }
            idx.extend_from_slice(&part);
        }
        Self {
            start,
            idx,
            points: points.len(),
        }
    }

    /// Index of query point i's first entry in the flat pair arrays.
    #[inline]
    pub fn offset(&self, i: usize) -> usize {
        self.start[i] as usize
    }

    /// Neighbours of query point i, ascending.
    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.idx[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// Number of query points.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Split `buf` (one entry per stored pair) into one slice per query point, so per-pair data
    /// aligned with the lists can be written in parallel, each query point writing its own slice.
    pub fn split_mut<'a, T>(&self, mut buf: &'a mut [T]) -> Vec<&'a mut [T]> {
        assert_eq!(buf.len(), self.idx.len());
        let mut out = Vec::with_capacity(self.len());
        for w in self.start.windows(2) {
            let (head, tail) = buf.split_at_mut((w[1] - w[0]) as usize);
            out.push(head);
            buf = tail;
        }
        out
    }

    /// Split `buf` (one entry per stored pair) into one slice per run of `chunk` consecutive
    /// query points (the last run may be shorter): the pair data of a run are contiguous, so a
    /// pass can give each parallel task a run and slice it per point with [`Self::offset`].
    pub fn split_chunks_mut<'a, T>(&self, mut buf: &'a mut [T], chunk: usize) -> Vec<&'a mut [T]> {
        assert_eq!(buf.len(), self.idx.len());
        assert!(chunk > 0);
        let n = self.len();
        let mut out = Vec::with_capacity(n.div_ceil(chunk));
        for from in (0..n).step_by(chunk) {
            let to = (from + chunk).min(n);
            let (head, tail) = buf.split_at_mut((self.start[to] - self.start[from]) as usize);
            out.push(head);
            buf = tail;
        }
        out
    }

    /// Number of points the lists were built over: every entry is below it (the gather passes
    /// check this once and then index their per-particle records without bounds tests).
    pub fn points(&self) -> usize {
        self.points
    }

    /// Total number of stored pairs.
    pub fn pairs(&self) -> usize {
        self.idx.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec2;
    use rand::{Rng, SeedableRng};

    #[test]
    fn equals_brute_force_on_random_sets() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for &(n, radius) in &[(1usize, 0.1), (50, 0.3), (2000, 0.05), (3000, 0.11)] {
            let pts: Vec<Vec2> = (0..n)
                .map(|_| Vec2::new(rng.gen_range(-1.0..1.0), rng.gen_range(0.0..0.5)))
                .collect();
            let queries: Vec<Vec2> = (0..300)
                .map(|_| Vec2::new(rng.gen_range(-1.2..1.2), rng.gen_range(-0.2..0.7)))
                .collect();
            let grid = CellGrid::build(&pts, radius, &Domain::OPEN);
            let list = NeighborList::build(&grid, &pts, &queries, radius, &Domain::OPEN);
            assert_eq!(list.len(), queries.len());
            for (i, q) in queries.iter().enumerate() {
                let brute: Vec<u32> = (0..n as u32)
                    .filter(|&j| (pts[j as usize] - q).norm_squared() <= radius * radius)
                    .collect();
                assert_eq!(list.of(i), &brute[..]);
            }
        }
    }

    #[test]
    fn periodic_lists_equal_brute_force_nearest_images() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        // Periods of 1 to 6 columns, including those too short for three distinct columns.
        for &(l, radius) in &[
            (1.0, 0.3),
            (0.5, 0.2),
            (0.25, 0.11),
            (1.0, 0.05),
            (0.3, 0.3),
        ] {
            let dom = Domain::periodic_x(l);
            let pts: Vec<Vec2> = (0..1500)
                .map(|_| Vec2::new(rng.gen_range(0.0..l), rng.gen_range(0.0..0.6)))
                .collect();
            let grid = CellGrid::build(&pts, radius, &dom);
            let list = NeighborList::build(&grid, &pts, &pts, radius, &dom);
            for (i, q) in pts.iter().enumerate() {
                let brute: Vec<u32> = (0..pts.len() as u32)
                    .filter(|&j| dom.delta(&pts[j as usize], q).norm_squared() <= radius * radius)
                    .collect();
                assert_eq!(
                    list.of(i),
                    &brute[..],
                    "period {l}, radius {radius}, point {i}"
                );
            }
        }
    }

    /// Lists equal to brute force through `Domain::delta` for every combination of periodic
    /// axes, in 2D and in 3D, including periods of one and two cells (too short for three
    /// distinct cells along the axis).
    fn brute_force_per_axis<const N: usize>(seed: u64, box_len: [f64; N], radius: f64) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        for mask in 0..(1usize << N) {
            let mut dom = Domain::OPEN;
            for (a, &l) in box_len.iter().enumerate() {
                if mask & (1 << a) != 0 {
                    dom = dom.with_period(a, l);
                }
            }
            let pts: Vec<Vector<N>> = (0..1500)
                .map(|_| Vector::<N>::from_fn(|a, _| rng.gen_range(0.0..box_len[a])))
                .collect();
            let grid = Grid::build(&pts, radius, &dom);
            let list = NeighborList::build(&grid, &pts, &pts, radius, &dom);
            for (i, q) in pts.iter().enumerate() {
                let brute: Vec<u32> = (0..pts.len() as u32)
                    .filter(|&j| dom.delta(&pts[j as usize], q).norm_squared() <= radius * radius)
                    .collect();
                assert_eq!(list.of(i), &brute[..], "{dom:?}, point {i}");
            }
        }
    }

    #[test]
    fn periodic_along_each_axis_equals_brute_force_in_two_and_three_dimensions() {
        brute_force_per_axis::<2>(5, [1.0, 0.6], 0.11);
        brute_force_per_axis::<2>(6, [0.25, 0.5], 0.2);
        brute_force_per_axis::<3>(7, [1.0, 0.6, 0.45], 0.15);
        brute_force_per_axis::<3>(8, [0.3, 0.5, 0.7], 0.25);
    }

    #[test]
    #[should_panic(expected = "periodic axis")]
    fn a_period_along_a_missing_axis_is_refused() {
        let pts = vec![Vec2::zeros()];
        CellGrid::build(&pts, 0.1, &Domain::OPEN.with_period(2, 1.0));
    }

    #[test]
    fn independent_of_thread_count() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let pts: Vec<Vec2> = (0..5000)
            .map(|_| Vec2::new(rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0)))
            .collect();
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    let dom = Domain::periodic_x(1.0);
                    let g = CellGrid::build(&pts, 0.03, &dom);
                    let l = NeighborList::build(&g, &pts, &pts, 0.03, &dom);
                    (l.start.clone(), l.idx.clone())
                })
        };
        assert_eq!(run(1), run(2));
    }
}
