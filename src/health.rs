//! Health measures shared by the schemes: what makes a run stop with a message instead of
//! returning garbage.
//!
//! Fracture by the tensile instability (Fang 2006 section 3.2, Fig. 2) tears holes into the fluid:
//! particles clump into filaments with empty space between them. We measure it as the
//! *void fraction*: rasterise the fluid onto square cells of side `cell`, flood-fill the empty
//! cells from the outside of the fluid's bounding box (a wall, if any, is solid), and count the
//! empty cells the flood cannot reach: holes enclosed by fluid. Their area over the area of the
//! occupied cells is the void fraction. An intact fluid at a cell side of about two particle
//! spacings has none (every cell holds several particles); a torn one has a large fraction.

use rayon::prelude::*;
use std::sync::atomic::{AtomicU8, Ordering};

/// Smallest number of points per parallel task.
const MIN_TASK: usize = 1024;

/// Void fraction of a point set given in a frame where the wall, if any, lies along `y = 0`
/// below the fluid (`wall_below`), with cells of side `cell`.
///
/// Every step runs it (the fracture check), so every part runs on all threads: the bounding
/// box, the marking of the occupied cells (each stores the same 1, so the order of the stores
/// does not matter), and the flood, as a labelling of the empty cells' connected components
/// strip by strip of rows (`empty_components`), the strips then joined along their edges. The
/// cells the flood reaches are the component of the empty margin ring all round the grid: the
/// bottom margin row is empty too (no point lies in it), so with a wall below it is reached
/// from the side columns and climbs into the row above; the walk below (the old single-thread
/// flood, kept as the test's reference) reaches the same cells either way. The result is a ratio
/// of two cell counts: the same whatever the thread count or the strips.
pub fn void_fraction(points: &[(f64, f64)], cell: f64, wall_below: bool) -> f64 {
    let Some(grid) = OccupancyGrid::of(points, cell) else {
        return 0.0;
    };
    // With or without a wall below, the flood reaches the margin ring's component (see above).
    let _ = wall_below;
    let (enclosed, occupied) = empty_components(&grid);
    enclosed as f64 / occupied.max(1) as f64
}

/// The occupied cells of a point set: one empty cell of margin all round.
struct OccupancyGrid {
    nx: usize,
    ny: usize,
    /// 0 = empty, 1 = occupied, row by row.
    cells: Vec<u8>,
}

impl OccupancyGrid {
    /// None for fewer than 4 points, or a grid too large to be a torn fluid.
    fn of(points: &[(f64, f64)], cell: f64) -> Option<Self> {
        if points.len() < 4 {
            return None;
        }
        // A minimum and a maximum do not depend on the order they are taken in.
        let (x0, x1, y0, y1) = points
            .par_iter()
            .with_min_len(MIN_TASK)
            .fold(
                || (f64::MAX, f64::MIN, f64::MAX, f64::MIN),
                |(x0, x1, y0, y1), &(x, y)| (x0.min(x), x1.max(x), y0.min(y), y1.max(y)),
            )
            .reduce(
                || (f64::MAX, f64::MIN, f64::MAX, f64::MIN),
                |a, b| (a.0.min(b.0), a.1.max(b.1), a.2.min(b.2), a.3.max(b.3)),
            );
        let nx = ((x1 - x0) / cell).floor() as usize + 3;
        let ny = ((y1 - y0) / cell).floor() as usize + 3;
        if nx * ny > 50_000_000 {
            return None; // a fluid spread this thin is not torn by the tensile instability
        }
        let mut cells = vec![0u8; nx * ny];
        {
            // SAFETY: AtomicU8 has the size, alignment and bit validity of u8, and `cells` is
            // borrowed exclusively while the atomic view lives.
            let marks: &[AtomicU8] =
                unsafe { &*(cells.as_mut_slice() as *mut [u8] as *const [AtomicU8]) };
            points
                .par_iter()
                .with_min_len(MIN_TASK)
                .for_each(|&(x, y)| {
                    let i = ((x - x0) / cell).floor() as usize + 1;
                    let j = ((y - y0) / cell).floor() as usize + 1;
                    marks[j * nx + i].store(1, Ordering::Relaxed);
                });
        }
        Some(Self { nx, ny, cells })
    }
}

/// One strip of rows labelled alone: its components (union-find roots among its provisional
/// labels) with their sizes and whether they touch the grid's margin, and the labels along its
/// first and last rows (u32::MAX: occupied) to join it to its neighbours.
struct Strip {
    first: Vec<u32>,
    last: Vec<u32>,
    /// Per provisional label: its root; per root: size and margin flag.
    root: Vec<u32>,
    size: Vec<u64>,
    margin: Vec<bool>,
    occupied: u64,
}

/// Root of `k` in the forest `parent`, halving the path on the way.
fn find(parent: &mut [u32], mut k: u32) -> u32 {
    while parent[k as usize] != k {
        let up = parent[parent[k as usize] as usize];
        parent[k as usize] = up;
        k = up;
    }
    k
}

/// Join the sets of `a` and `b` (the smaller root under the larger: any rule gives the same
/// sets).
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (a, b) = (find(parent, a), find(parent, b));
    if a != b {
        parent[a.max(b) as usize] = a.min(b);
    }
}

/// Connected components (4-neighbour) of the empty cells of rows `rows` alone, in one scan.
fn label_strip(g: &OccupancyGrid, rows: std::ops::Range<usize>) -> Strip {
    let nx = g.nx;
    let mut lab = vec![u32::MAX; rows.len() * nx];
    let mut parent: Vec<u32> = Vec::new();
    let mut size: Vec<u64> = Vec::new();
    let mut margin: Vec<bool> = Vec::new();
    let mut occupied = 0u64;
    for (r, j) in rows.clone().enumerate() {
        let row = &g.cells[j * nx..(j + 1) * nx];
        let edge_row = j == 0 || j + 1 == g.ny;
        for (i, &c) in row.iter().enumerate() {
            if c != 0 {
                occupied += 1;
                continue;
            }
            let at = r * nx + i;
            let left = if i > 0 { lab[at - 1] } else { u32::MAX };
            let up = if r > 0 { lab[at - nx] } else { u32::MAX };
            let k = match (left != u32::MAX, up != u32::MAX) {
                (false, false) => {
                    parent.push(parent.len() as u32);
                    size.push(0);
                    margin.push(false);
                    parent.len() as u32 - 1
                }
                (true, false) => left,
                (false, true) => up,
                (true, true) => {
                    union(&mut parent, left, up);
                    left
                }
            };
            lab[at] = k;
            size[k as usize] += 1;
            margin[k as usize] |= edge_row || i == 0 || i + 1 == nx;
        }
    }
    // Sizes and flags onto the roots; every label points at its root.
    for k in 0..parent.len() as u32 {
        let r = find(&mut parent, k);
        parent[k as usize] = r;
        if r != k {
            size[r as usize] += size[k as usize];
            size[k as usize] = 0;
            let m = margin[k as usize];
            margin[r as usize] |= m;
        }
    }
    let edge = |r: usize| -> Vec<u32> {
        lab[r * nx..(r + 1) * nx]
            .iter()
            .map(|&k| if k == u32::MAX { k } else { parent[k as usize] })
            .collect()
    };
    Strip {
        first: edge(0),
        last: edge(rows.len() - 1),
        root: parent,
        size,
        margin,
        occupied,
    }
}

/// The number of empty cells the margin ring's component does not reach (enclosed by occupied
/// cells) and of occupied cells: strips of rows labelled in parallel, then joined along their
/// edges by a union-find over the strips' components (one pass over one row per strip).
fn empty_components(g: &OccupancyGrid) -> (u64, u64) {
    let rows = (g.ny / (4 * rayon::current_num_threads())).max(8);
    let strips: Vec<Strip> = (0..g.ny.div_ceil(rows))
        .into_par_iter()
        .map(|s| label_strip(g, s * rows..((s + 1) * rows).min(g.ny)))
        .collect();
    let mut offset = Vec::with_capacity(strips.len());
    let mut total = 0u32;
    for s in &strips {
        offset.push(total);
        total += s.root.len() as u32;
    }
    let mut parent: Vec<u32> = (0..total).collect();
    for (s, pair) in strips.windows(2).enumerate() {
        for (&a, &b) in pair[0].last.iter().zip(&pair[1].first) {
            if a != u32::MAX && b != u32::MAX {
                union(&mut parent, a + offset[s], b + offset[s + 1]);
            }
        }
    }
    let mut size = vec![0u64; total as usize];
    let mut margin = vec![false; total as usize];
    for (s, strip) in strips.iter().enumerate() {
        for (k, &r) in strip.root.iter().enumerate() {
            if r as usize == k {
                let gr = find(&mut parent, r + offset[s]) as usize;
                size[gr] += strip.size[k];
                margin[gr] |= strip.margin[k];
            }
        }
    }
    let enclosed = size
        .iter()
        .zip(&margin)
        .filter(|(_, &m)| !m)
        .map(|(s, _)| s)
        .sum();
    (enclosed, strips.iter().map(|s| s.occupied).sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc(n: i32, hole: f64) -> Vec<(f64, f64)> {
        let mut v = Vec::new();
        for i in -n..=n {
            for j in -n..=n {
                let (x, y) = (i as f64, j as f64);
                let r = (x * x + y * y).sqrt();
                if r <= n as f64 && r >= hole {
                    v.push((x, y + n as f64 + 1.0));
                }
            }
        }
        v
    }

    /// The single-thread flood fill from the margin that the strips replace (with a wall below,
    /// the flood does not step down from the first row above the margin).
    fn flood_reference(points: &[(f64, f64)], cell: f64, wall_below: bool) -> f64 {
        let Some(g) = OccupancyGrid::of(points, cell) else {
            return 0.0;
        };
        let (nx, ny, mut grid) = (g.nx, g.ny, g.cells);
        let mut stack = Vec::new();
        for i in 0..nx {
            stack.push((ny - 1) * nx + i);
            if !wall_below {
                stack.push(i);
            }
        }
        for j in 0..ny {
            stack.push(j * nx);
            stack.push(j * nx + nx - 1);
        }
        while let Some(c) = stack.pop() {
            if grid[c] != 0 {
                continue;
            }
            grid[c] = 2;
            let (i, j) = (c % nx, c / nx);
            if i > 0 {
                stack.push(c - 1);
            }
            if i + 1 < nx {
                stack.push(c + 1);
            }
            if j > usize::from(wall_below) {
                stack.push(c - nx);
            }
            if j + 1 < ny {
                stack.push(c + nx);
            }
        }
        let enclosed = grid.iter().filter(|&&g| g == 0).count();
        let occupied = grid.iter().filter(|&&g| g == 1).count();
        enclosed as f64 / occupied.max(1) as f64
    }

    /// Torn random clouds (many holes, some touching the bottom): the strips joined give the
    /// flood's value bitwise, with and without a wall, on one thread and on three (other
    /// strips).
    #[test]
    fn strips_give_the_flood_fill_on_torn_clouds() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(21);
        for (n, w, hgt) in [
            (300usize, 40.0, 20.0),
            (3000, 120.0, 60.0),
            (20_000, 400.0, 90.0),
        ] {
            let pts: Vec<(f64, f64)> = (0..n)
                .map(|_| (rng.gen_range(0.0..w), rng.gen_range(0.0..hgt)))
                .collect();
            for cell in [1.0, 2.0, 3.5] {
                for wall in [false, true] {
                    let want = flood_reference(&pts, cell, wall);
                    for threads in [1, 3] {
                        let got = rayon::ThreadPoolBuilder::new()
                            .num_threads(threads)
                            .build()
                            .unwrap()
                            .install(|| void_fraction(&pts, cell, wall));
                        assert_eq!(got.to_bits(), want.to_bits(), "{n} {cell} {wall} {threads}");
                    }
                    if cell == 2.0 {
                        assert!(want > 0.0, "{n}: the cloud has holes");
                    }
                }
            }
        }
    }

    #[test]
    fn intact_disc_has_no_voids() {
        assert_eq!(void_fraction(&disc(20, 0.0), 2.0, true), 0.0);
        assert_eq!(void_fraction(&disc(20, 0.0), 2.0, false), 0.0);
    }

    #[test]
    fn ring_encloses_its_hole() {
        let f = void_fraction(&disc(20, 8.0), 2.0, false);
        // hole area pi 8^2 ~ 201 against ring area ~ 1056: about 0.19 (in cells of 2 x 2)
        assert!(f > 0.12 && f < 0.3, "{f}");
    }

    #[test]
    fn open_notch_is_not_a_void() {
        // A slot cut from the top to the middle of a square is open to the outside.
        let pts: Vec<(f64, f64)> = (0..40)
            .flat_map(|i| (0..40).map(move |j| (i as f64, j as f64)))
            .filter(|&(x, y)| !(x > 17.0 && x < 23.0 && y > 20.0))
            .collect();
        assert_eq!(void_fraction(&pts, 2.0, true), 0.0);
    }
}
