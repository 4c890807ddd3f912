//! Particle sets for the unit tests of the ISPH building blocks and for the solver benchmark
//! (`examples/ppe_bench.rs`): a lattice disc with an optional deterministic jitter, and a channel
//! periodic in x between two straight walls, its periodic images and wall mirrors given as ghost
//! points of an open domain (so the lists need no periodic search).
//!
//! Written against `viscosph::` paths only: the library's unit tests compile this same file as
//! their `operators::fixtures` (where `viscosph` names the library itself), the examples use it
//! from this crate.

use viscosph::neighbors::{CellGrid, Domain, NeighborList};
use viscosph::Vec2;

/// Fluid particles `x[..n_fluid]`, then ghost points, each with its fluid parent.
#[derive(Debug, Clone)]
pub struct ParticleSet {
    pub x: Vec<Vec2>,
    pub n_fluid: usize,
    /// Fluid parent of each ghost (`x[n_fluid + m]` has parent `parent[m]`).
    pub parent: Vec<u32>,
    /// Whether ghost m is reflected across a wall (otherwise a plain periodic image).
    pub reflected: Vec<bool>,
    /// Lattice spacing.
    pub dr: f64,
}

impl ParticleSet {
    /// Neighbour lists of the fluid particles among all points within `radius`.
    pub fn neighbours(&self, radius: f64) -> NeighborList {
        let grid = CellGrid::build(&self.x, radius, &Domain::OPEN);
        NeighborList::build(
            &grid,
            &self.x,
            &self.x[..self.n_fluid],
            radius,
            &Domain::OPEN,
        )
    }

    /// Ghost signs for a no-slip velocity (-1 across a wall, +1 for a periodic image).
    pub fn signs_no_slip(&self) -> Vec<f64> {
        self.reflected
            .iter()
            .map(|&r| if r { -1.0 } else { 1.0 })
            .collect()
    }
}

/// SplitMix64: a tiny deterministic generator for reproducible jitter in library code.
pub fn splitmix(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// Square-lattice points of spacing `dr` inside the disc of radius `radius` centred at the
/// origin (lattice offset by dr/2 so no point sits at the centre), each moved by a uniform
/// random vector of up to `jitter * dr` per component.
pub fn disc(radius: f64, dr: f64, jitter: f64, seed: u64) -> ParticleSet {
    let n = (radius / dr).ceil() as i64 + 1;
    let mut s = seed;
    let mut x = Vec::new();
    for j in -n..n {
        for i in -n..n {
            let p = Vec2::new((i as f64 + 0.5) * dr, (j as f64 + 0.5) * dr);
            if p.norm() < radius {
                let d = Vec2::new(splitmix(&mut s) - 0.5, splitmix(&mut s) - 0.5) * 2.0 * jitter;
                x.push(p + d * dr);
            }
        }
    }
    let n_fluid = x.len();
    ParticleSet {
        x,
        n_fluid,
        parent: Vec::new(),
        reflected: Vec::new(),
        dr,
    }
}

/// `nx` x `ny` lattice particles filling [0, nx dr) x (0, ny dr), periodic in x, walls at y = 0
/// and y = ny dr. Ghosts: every periodic image, wall mirror and mirrored image within `reach` of
/// the fluid box (mirrors bisected by the wall, King & Lind 2021 section III.C).
pub fn channel(nx: usize, ny: usize, dr: f64, jitter: f64, reach: f64, seed: u64) -> ParticleSet {
    let (l, h) = (nx as f64 * dr, ny as f64 * dr);
    let mut s = seed;
    let mut x = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let d = Vec2::new(splitmix(&mut s) - 0.5, splitmix(&mut s) - 0.5) * 2.0 * jitter * dr;
            x.push(Vec2::new((i as f64 + 0.5) * dr, (j as f64 + 0.5) * dr) + d);
        }
    }
    let n_fluid = x.len();
    let (mut parent, mut reflected) = (Vec::new(), Vec::new());
    for k in 0..n_fluid {
        for sx in [-l, 0.0, l] {
            for refl in 0..3 {
                if sx == 0.0 && refl == 0 {
                    continue;
                }
                let p = x[k];
                let y = match refl {
                    0 => p.y,
                    1 => -p.y,
                    _ => 2.0 * h - p.y,
                };
                let q = Vec2::new(p.x + sx, y);
                let inside = q.x > -reach && q.x < l + reach && q.y > -reach && q.y < h + reach;
                if inside {
                    x.push(q);
                    parent.push(k as u32);
                    reflected.push(refl != 0);
                }
            }
        }
    }
    ParticleSet {
        x,
        n_fluid,
        parent,
        reflected,
        dr,
    }
}
