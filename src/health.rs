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

/// Smallest number of points per parallel task.
const MIN_TASK: usize = 1024;

/// Void fraction of a point set given in a frame where the wall, if any, lies along `y = 0`
/// below the fluid (`wall_below`), with cells of side `cell`.
pub fn void_fraction(points: &[(f64, f64)], cell: f64, wall_below: bool) -> f64 {
    if points.len() < 4 {
        return 0.0;
    }
    // The bounding box and the cell of every point in parallel (a minimum, a maximum and a
    // per-point cell do not depend on the order); the marking and the flood fill after them
    // run on one thread.
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
    // One empty cell of margin all round.
    let nx = ((x1 - x0) / cell).floor() as usize + 3;
    let ny = ((y1 - y0) / cell).floor() as usize + 3;
    if nx * ny > 50_000_000 {
        return 0.0; // a fluid spread this thin is not torn by the tensile instability
    }
    let idx = |x: f64, y: f64| {
        let i = ((x - x0) / cell).floor() as usize + 1;
        let j = ((y - y0) / cell).floor() as usize + 1;
        j * nx + i
    };
    // 0 = empty, 1 = fluid, 2 = reached from outside
    let mut grid = vec![0u8; nx * ny];
    let cells: Vec<usize> = points
        .par_iter()
        .with_min_len(MIN_TASK)
        .map(|&(x, y)| idx(x, y))
        .collect();
    for c in cells {
        grid[c] = 1;
    }
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
        // With a wall below, the bottom margin row is solid: the flood does not run under the fluid.
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
