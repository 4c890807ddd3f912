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
        let cells: Vec<u32> = points
            .par_iter()
            .with_min_len(SORT_MIN)
            .map(|p| grid.cell_of(p) as u32)
            .collect();
        (grid.cell_start, grid.sorted) = counting_sort(&cells, total);
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

/// Points per parallel task of the grid's fill, and cells per task of its scans.
const SORT_MIN: usize = 4096;

/// The stable counting sort of the points 0..n by their cell `cells[i]` (< `total`): the
/// cell starts (`total + 1` entries) and the point indices ordered by cell, ascending within a
/// cell. On all threads: the points in runs, each run counting its own histogram; per cell the
/// runs' counts are scanned in run order (cells in blocks, in parallel) into each run's first
/// slot in the cell; each run then places its points from there. The slots do not depend on
/// how many runs there are, so neither does the result.
fn counting_sort(cells: &[u32], total: usize) -> (Vec<u32>, Vec<u32>) {
    use std::sync::atomic::{AtomicU32, Ordering};
    let n = cells.len();
    // Each run zeroes and scans a histogram over every cell: no more runs than keep that work
    // within a few times the points'.
    let runs = (2 * rayon::current_num_threads())
        .min(n.div_ceil(SORT_MIN))
        .min(4 * n / total.max(1))
        .max(1);
    if runs == 1 {
        // One run: the plain counting sort, without the pool.
        let mut start = vec![0u32; total + 1];
        for &c in cells {
            start[c as usize + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut next = start.clone();
        let mut sorted = vec![0u32; n];
        for (i, &c) in cells.iter().enumerate() {
            sorted[next[c as usize] as usize] = i as u32;
            next[c as usize] += 1;
        }
        return (start, sorted);
    }
    let run_len = n.div_ceil(runs).max(1);
    let mut hist: Vec<Vec<u32>> = cells
        .par_chunks(run_len)
        .map(|run| {
            let mut h = vec![0u32; total];
            for &c in run {
                h[c as usize] += 1;
            }
            h
        })
        .collect();
    // Per block of cells, the block's count; then each block's first slot (a scan over the
    // blocks), then per cell its start and each run's first slot.
    let block = SORT_MIN.max(total.div_ceil(8 * rayon::current_num_threads()));
    let block_sums: Vec<u32> = (0..total.div_ceil(block))
        .into_par_iter()
        .map(|b| {
            let range = b * block..((b + 1) * block).min(total);
            hist.iter()
                .map(|h| h[range.clone()].iter().sum::<u32>())
                .sum()
        })
        .collect();
    let mut block_start = Vec::with_capacity(block_sums.len());
    let mut at = 0u32;
    for s in &block_sums {
        block_start.push(at);
        at += s;
    }
    // The runs' histograms cut into the blocks of cells, block by block.
    let mut per_block: Vec<Vec<&mut [u32]>> = (0..block_sums.len())
        .map(|_| Vec::with_capacity(runs))
        .collect();
    for h in hist.iter_mut() {
        for (b, piece) in h.chunks_mut(block).enumerate() {
            per_block[b].push(piece);
        }
    }
    let mut start = vec![0u32; total + 1];
    start[..total]
        .par_chunks_mut(block)
        .zip(per_block.into_par_iter().zip(block_start.par_iter()))
        .for_each(|(starts, (mut pieces, &first))| {
            let mut at = first;
            for (c, s) in starts.iter_mut().enumerate() {
                *s = at;
                for piece in pieces.iter_mut() {
                    let k = piece[c];
                    piece[c] = at;
                    at += k;
                }
            }
        });
    start[total] = n as u32;
    let mut sorted = vec![0u32; n];
    {
        // SAFETY: AtomicU32 has the size, alignment and bit validity of u32, and `sorted` is
        // borrowed exclusively while the atomic view lives. Every slot is written once (the
        // runs' slots are disjoint), so the order of the stores does not matter.
        let slots: &[AtomicU32] =
            unsafe { &*(sorted.as_mut_slice() as *mut [u32] as *const [AtomicU32]) };
        cells
            .par_chunks(run_len)
            .zip(hist.par_iter_mut())
            .enumerate()
            .for_each(|(r, (run, next))| {
                for (k, &c) in run.iter().enumerate() {
                    let slot = &mut next[c as usize];
                    slots[*slot as usize].store((r * run_len + k) as u32, Ordering::Relaxed);
                    *slot += 1;
                }
            });
    }
    (start, sorted)
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

/// Query points per parallel task of the list build.
const CHUNK: usize = 512;

/// For each chunk of [`CHUNK`] query points (in order), the number of points within `radius` of each
/// query and their indices, ascending per query; `delta(p, q)` is x_p - x_q.
fn candidates_within<const N: usize>(
    grid: &Grid<N>,
    points: &[Vector<N>],
    queries: &[Vector<N>],
    radius: f64,
    delta: impl Fn(&Vector<N>, &Vector<N>) -> Vector<N> + Sync,
) -> Vec<(Vec<u32>, Vec<u32>)> {
    let r2 = radius * radius;
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
        // Concatenated in parallel: each chunk's pairs go to their offset (a scan over the
        // chunks' totals) and its starts count on from there.
        let mut offsets = Vec::with_capacity(parts.len());
        let mut total = 0usize;
        for (_, part) in &parts {
            offsets.push(total as u32);
            total += part.len();
        }
        let mut idx = vec![0u32; total];
        let mut pieces = Vec::with_capacity(parts.len());
        let mut rest = idx.as_mut_slice();
        for (_, part) in &parts {
            let (head, tail) = rest.split_at_mut(part.len());
            pieces.push(head);
            rest = tail;
        }
        let mut start = vec![0u32; queries.len() + 1];
        start[1..]
            .par_chunks_mut(CHUNK)
            .zip(parts.par_iter().zip(offsets.par_iter()))
            .zip(pieces.into_par_iter())
            .for_each(|((starts, ((counts, part), &offset)), piece)| {
                let mut at = offset;
                for (s, &c) in starts.iter_mut().zip(counts) {
                    at += c;
                    *s = at;
                }
                piece.copy_from_slice(part);
            });
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

    /// The parallel counting sort gives the stable sort by cell (ascending index within a
    /// cell), whatever the threads, for few and many cells per point.
    #[test]
    fn counting_sort_is_the_stable_sort_by_cell() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(13);
        for (n, total) in [
            (0usize, 1usize),
            (5, 3),
            (20_000, 7),
            (50_000, 30_000),
            (9_000, 200_000),
        ] {
            let cells: Vec<u32> = (0..n).map(|_| rng.gen_range(0..total as u32)).collect();
            let mut want: Vec<u32> = (0..n as u32).collect();
            want.sort_by_key(|&i| cells[i as usize]);
            let mut want_start = vec![0u32; total + 1];
            for &c in &cells {
                want_start[c as usize + 1] += 1;
            }
            for c in 0..total {
                want_start[c + 1] += want_start[c];
            }
            for threads in [1, 2, 5] {
                let got = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap()
                    .install(|| counting_sort(&cells, total));
                assert_eq!(got.0, want_start, "{n} {total} {threads}");
                assert_eq!(got.1, want, "{n} {total} {threads}");
            }
        }
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
