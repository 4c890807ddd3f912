//! Square (2D) and cubic (3D) particle lattices: the index boxes the scenes cut their fluid
//! from.

use super::Vector;

/// The lattice indices `lo[a] <= i[a] < hi[a]` on every axis a, visited with the x index
/// fastest (in 2D: row by row, each row from left to right, as the scenes' `for j { for i }`
/// loops do). Point i sits at `(i + offset) dx` per axis ([`Lattice::point`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lattice<const N: usize> {
    /// Smallest index per axis.
    pub lo: [i64; N],
    /// One past the largest index per axis.
    pub hi: [i64; N],
}

impl<const N: usize> Lattice<N> {
    pub fn new(lo: [i64; N], hi: [i64; N]) -> Self {
        Self { lo, hi }
    }

    /// The same index range `lo..hi` on every axis.
    pub fn cube(lo: i64, hi: i64) -> Self {
        Self {
            lo: [lo; N],
            hi: [hi; N],
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        (0..N)
            .map(|a| (self.hi[a] - self.lo[a]).max(0) as usize)
            .product()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every index, x fastest.
    pub fn indices(&self) -> impl Iterator<Item = [i64; N]> {
        let (lo, hi) = (self.lo, self.hi);
        let mut next = (!self.is_empty()).then_some(lo);
        std::iter::from_fn(move || {
            let here = next?;
            // Odometer: advance x; at the end of its range, reset it and carry to y, and so on.
            let mut i = here;
            next = None;
            for a in 0..N {
                i[a] += 1;
                if i[a] < hi[a] {
                    next = Some(i);
                    break;
                }
                i[a] = lo[a];
            }
            Some(here)
        })
    }

    /// The position of index `i`: `(i + offset) dx` per axis (offset 0: nodes on the lattice
    /// lines through the origin; 1/2: cell centres, none at the origin).
    #[inline]
    pub fn point(i: [i64; N], dx: f64, offset: f64) -> Vector<N> {
        Vector::<N>::from_fn(|a, _| (i[a] as f64 + offset) * dx)
    }

    /// Every point, in the order of [`Lattice::indices`].
    pub fn points(&self, dx: f64, offset: f64) -> impl Iterator<Item = Vector<N>> {
        self.indices().map(move |i| Self::point(i, dx, offset))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec2;

    /// The drop of `scene::drop` (cell centres in a disc): the same points, bitwise, in the same
    /// order as its double loop.
    #[test]
    fn reproduces_the_scenes_double_loop() {
        let (n, dx) = (20i64, 0.003);
        let r = 0.5 * n as f64 * dx;
        let mut by_loop = Vec::new();
        for j in -n..n {
            for i in -n..n {
                let (ls, ld) = ((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx);
                if ls * ls + ld * ld < r * r {
                    by_loop.push(Vec2::new(ls, ld));
                }
            }
        }
        let by_lattice: Vec<Vec2> = Lattice::<2>::cube(-n, n)
            .points(dx, 0.5)
            .filter(|p| p.norm_squared() < r * r)
            .collect();
        assert_eq!(by_loop, by_lattice);
        assert!(by_loop.len() > 300);
    }

    #[test]
    fn visits_every_index_once_x_fastest() {
        let l = Lattice::<3>::new([-1, 0, 2], [1, 3, 4]);
        let all: Vec<[i64; 3]> = l.indices().collect();
        assert_eq!(all.len(), l.len());
        assert_eq!(l.len(), 2 * 3 * 2);
        assert_eq!(&all[..3], &[[-1, 0, 2], [0, 0, 2], [-1, 1, 2]]);
        assert_eq!(*all.last().unwrap(), [0, 2, 3]);
        let mut sorted = all.clone();
        sorted.sort_by_key(|i| (i[2], i[1], i[0]));
        sorted.dedup();
        assert_eq!(sorted, all);
        assert_eq!(Lattice::<2>::new([0, 0], [0, 5]).indices().count(), 0);
        assert!(Lattice::<2>::new([3, 0], [1, 5]).is_empty());
        assert_eq!(Lattice::<2>::point([2, -3], 0.5, 0.0), Vec2::new(1.0, -1.5));
    }
}
