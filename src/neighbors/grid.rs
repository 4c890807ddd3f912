//! A uniform cell grid filled by a counting sort, and compact (CSR) neighbour lists built from it
//! in parallel. In a domain periodic along x the grid spans exactly one period and its columns
//! wrap, so particles near one end find those near the other at their nearest image.
//!
//! Determinism: each list is sorted by neighbour index, so every sum over neighbours runs in the
//! same order whatever the thread count and whenever the list was last rebuilt. Lists are built with
//! a skin (radius = support + skin) and reused until some particle has moved more than half the
//! skin; particles in the skin but outside the support contribute exact zeros.

use super::Domain;
use crate::Vec2;
use rayon::prelude::*;

/// Uniform grid of square cells over the bounding box of a point set.
#[derive(Debug, Clone, Default)]
pub struct CellGrid {
    origin: Vec2,
    /// Inverse cell side along x (the period over the number of columns when periodic) and y.
    inv_cell_x: f64,
    inv_cell: f64,
    /// Whether the columns wrap (periodic along x).
    periodic: bool,
    nx: usize,
    ny: usize,
    /// `cell_start[c]..cell_start[c+1]` indexes `sorted` for cell c.
    cell_start: Vec<u32>,
    /// Point indices ordered by cell, ascending index within a cell.
    sorted: Vec<u32>,
}

impl CellGrid {
    /// Bin `points` into cells of side `cell` (>= the largest search radius used with it) in the
    /// domain `dom` (points of a periodic domain lie in its box).
    pub fn build(points: &[Vec2], cell: f64, dom: &Domain) -> Self {
        assert!(cell > 0.0 && cell.is_finite());
        if points.is_empty() {
            return Self {
                inv_cell_x: 1.0 / cell,
                inv_cell: 1.0 / cell,
                nx: 1,
                ny: 1,
                cell_start: vec![0, 0],
                ..Default::default()
            };
        }
        let (lo, hi) = points
            .par_iter()
            .fold(
                || (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.inf(p), hi.sup(p)),
            )
            .reduce(
                || (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
                |a, b| (a.0.inf(&b.0), a.1.sup(&b.1)),
            );
        let inv_cell = 1.0 / cell;
        let ny = (((hi.y - lo.y) * inv_cell).floor() as usize + 1).max(1);
        let (origin, nx, inv_cell_x) = match dom.period_x {
            // Whole columns of at least `cell` across one period.
            Some(l) => {
                let nx = ((l * inv_cell).floor() as usize).max(1);
                (Vec2::new(0.0, lo.y), nx, nx as f64 / l)
            }
            None => (
                lo,
                (((hi.x - lo.x) * inv_cell).floor() as usize + 1).max(1),
                inv_cell,
            ),
        };
        let mut grid = Self {
            origin,
            inv_cell_x,
            inv_cell,
            periodic: dom.period_x.is_some(),
            nx,
            ny,
            cell_start: Vec::new(),
            sorted: Vec::new(),
        };
        let cells: Vec<u32> = points.par_iter().map(|p| grid.cell_of(p) as u32).collect();
        let mut count = vec![0u32; nx * ny + 1];
        for &c in &cells {
            count[c as usize + 1] += 1;
        }
        for c in 0..nx * ny {
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

    #[inline]
    fn coords(&self, p: &Vec2) -> (i64, i64) {
        (
            ((p.x - self.origin.x) * self.inv_cell_x).floor() as i64,
            ((p.y - self.origin.y) * self.inv_cell).floor() as i64,
        )
    }

    #[inline]
    fn cell_of(&self, p: &Vec2) -> usize {
        let (cx, cy) = self.coords(p);
        let cx = cx.clamp(0, self.nx as i64 - 1) as usize;
        let cy = cy.clamp(0, self.ny as i64 - 1) as usize;
        cy * self.nx + cx
    }

    /// Call `f` with every point index binned in the 3x3 block of cells around `p`
    /// (a superset of the points within one cell side of `p`).
    #[inline]
    pub fn for_each_candidate(&self, p: &Vec2, mut f: impl FnMut(u32)) {
        let (cx, cy) = self.coords(p);
        // Columns to visit: the three around cx, wrapped and without repeats when periodic.
        let nx = self.nx as i64;
        let mut cols = [0i64; 3];
        let mut ncols = 0;
        if self.periodic {
            let cx = cx.clamp(0, nx - 1);
            for x in [cx - 1, cx, cx + 1] {
                let x = x.rem_euclid(nx);
                if !cols[..ncols].contains(&x) {
                    cols[ncols] = x;
                    ncols += 1;
                }
            }
        } else {
            for x in (cx - 1).max(0)..=(cx + 1).min(nx - 1) {
                cols[ncols] = x;
                ncols += 1;
            }
        }
        for y in (cy - 1).max(0)..=(cy + 1).min(self.ny as i64 - 1) {
            for &x in &cols[..ncols] {
                let c = y as usize * self.nx + x as usize;
                let (a, b) = (self.cell_start[c] as usize, self.cell_start[c + 1] as usize);
                for &j in &self.sorted[a..b] {
                    f(j);
                }
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

impl NeighborList {
    /// Lists for every query point of the points within `radius`, using `grid` built over
    /// `points` with a cell side >= radius. Runs in parallel over chunks of query points and
    /// concatenates in order, so the result does not depend on the thread count.
    pub fn build(
        grid: &CellGrid,
        points: &[Vec2],
        queries: &[Vec2],
        radius: f64,
        dom: &Domain,
    ) -> Self {
        let r2 = radius * radius;
        const CHUNK: usize = 512;
        let parts: Vec<(Vec<u32>, Vec<u32>)> = queries
            .par_chunks(CHUNK)
            .map(|chunk| {
                let mut counts = Vec::with_capacity(chunk.len());
                let mut idx = Vec::with_capacity(chunk.len() * 40);
                for q in chunk {
                    let before = idx.len();
                    grid.for_each_candidate(q, |j| {
                        if dom.delta(&points[j as usize], q).norm_squared() <= r2 {
                            idx.push(j);
                        }
                    });
                    idx[before..].sort_unstable();
                    counts.push((idx.len() - before) as u32);
                }
                (counts, idx)
            })
            .collect();
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
