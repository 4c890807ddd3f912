//! The compressed sparse row matrix of the pressure Poisson and viscous systems.

use super::*;

/// A sparse matrix in compressed-row form, columns ascending within a row, the diagonal always
/// stored.
#[derive(Debug, Clone, PartialEq)]
pub struct CsrMatrix {
    /// `row_ptr[i]..row_ptr[i+1]` indexes `col` and `val` for row i.
    pub row_ptr: Vec<usize>,
    pub col: Vec<u32>,
    pub val: Vec<f64>,
    /// Position of the diagonal entry of each row in `col`/`val`.
    pub diag: Vec<usize>,
}

impl CsrMatrix {
    /// Build from per-row (column, value) lists; duplicate columns are summed in list order and
    /// a zero diagonal is inserted where missing.
    pub fn from_rows(rows: Vec<Vec<(u32, f64)>>) -> Self {
        let n = rows.len();
        let mut row_ptr = Vec::with_capacity(n + 1);
        // Sized once: growing by doubling cost a third of this function in page faults
        // (profile of the ISPH drop, docs/benchmarks.md).
        let cap = rows.iter().map(|r| r.len() + 1).sum();
        let mut col = Vec::with_capacity(cap);
        let mut val = Vec::with_capacity(cap);
        let mut diag = Vec::with_capacity(n);
        row_ptr.push(0);
        for (i, mut r) in rows.into_iter().enumerate() {
            r.push((i as u32, 0.0));
            // Stable: duplicates keep their order, so their sum is in a fixed order.
            r.sort_by_key(|e| e.0);
            let mut d = usize::MAX;
            for (c, v) in r {
                if col.len() > *row_ptr.last().expect("non-empty")
                    && *col.last().expect("non-empty") == c
                {
                    *val.last_mut().expect("non-empty") += v;
                } else {
                    if c as usize == i {
                        d = col.len();
                    }
                    col.push(c);
                    val.push(v);
                }
            }
            diag.push(d);
            row_ptr.push(col.len());
        }
        Self {
            row_ptr,
            col,
            val,
            diag,
        }
    }

    /// Number of rows (= columns).
    pub fn n(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.col.len()
    }

    /// Entries of row i: (columns, values).
    #[inline]
    pub fn row(&self, i: usize) -> (&[u32], &[f64]) {
        let (a, b) = (self.row_ptr[i], self.row_ptr[i + 1]);
        (&self.col[a..b], &self.val[a..b])
    }

    /// y = A x, row-parallel, each row summed in column order.
    pub fn matvec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.n());
        assert_eq!(y.len(), self.n());
        y.par_chunks_mut(ROW_CHUNK)
            .enumerate()
            .for_each(|(c, out)| {
                for (k, yi) in out.iter_mut().enumerate() {
                    let (cols, vals) = self.row(c * ROW_CHUNK + k);
                    let mut s = 0.0;
                    for (&j, &a) in cols.iter().zip(vals) {
                        s += a * x[j as usize];
                    }
                    *yi = s;
                }
            });
    }

    /// Diagonal entries.
    pub fn diagonal(&self) -> Vec<f64> {
        self.diag.iter().map(|&d| self.val[d]).collect()
    }
}
