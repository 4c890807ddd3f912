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
    /// a zero diagonal is inserted where missing. Rows are sorted and merged in parallel, each
    /// by itself, so the result does not depend on the thread count.
    pub fn from_rows(mut rows: Vec<Vec<(u32, f64)>>) -> Self {
        let diag_at: Vec<usize> = rows
            .par_iter_mut()
            .enumerate()
            .with_min_len(ROW_CHUNK)
            .map(|(i, r)| {
                r.push((i as u32, 0.0));
                // Stable: duplicates keep their order, so their sum is in a fixed order.
                r.sort_by_key(|e| e.0);
                let mut k = 0;
                for m in 0..r.len() {
                    if m > 0 && r[m].0 == r[k].0 {
                        r[k].1 += r[m].1;
                    } else {
                        if m > 0 {
                            k += 1;
                        }
                        r[k] = r[m];
                    }
                }
                r.truncate(k + 1);
                r.iter()
                    .position(|e| e.0 as usize == i)
                    .expect("diagonal inserted")
            })
            .collect();
        let (row_ptr, col, val) = flatten_rows(&rows);
        drop_in_parallel(rows);
        let diag = diag_at.iter().zip(&row_ptr).map(|(d, s)| d + s).collect();
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
        rows_times(&self.row_ptr, &self.col, &self.val, x, y, false);
    }

    /// Diagonal entries.
    pub fn diagonal(&self) -> Vec<f64> {
        self.diag.iter().map(|&d| self.val[d]).collect()
    }
}

/// Row pointers, columns and values of per-row (column, value) lists, in row order. The
/// entries are copied in parallel, each run of `ROW_CHUNK` rows into its own slice of the
/// arrays: collecting a parallel iterator of unknown length appends its pieces on one thread,
/// which in the viscous system's 2 x 10^6 entries at 10^4 particles was a few per cent of an
/// ISPH step.
pub(super) fn flatten_rows(rows: &[Vec<(u32, f64)>]) -> (Vec<usize>, Vec<u32>, Vec<f64>) {
    let mut row_ptr = Vec::with_capacity(rows.len() + 1);
    row_ptr.push(0);
    for r in rows {
        row_ptr.push(row_ptr.last().expect("non-empty") + r.len());
    }
    let (col, val) = fill_rows(&row_ptr, ROW_CHUNK, |i, c, v| {
        for ((e, c), v) in rows[i].iter().zip(c).zip(v) {
            (*c, *v) = (e.0, e.1);
        }
    });
    (row_ptr, col, val)
}

/// Drop a vector of per-row allocations on every thread, in runs of `ROW_CHUNK` rows. Dropped
/// at the end of a scope, its elements are freed one after the other on one thread: at 10^4
/// particles the row lists of the pressure system, of its multigrid hierarchy (strong
/// neighbours, prolongation, Galerkin products) and of the coupled viscous system are some
/// 10^5 allocations a step, freed while the other threads wait.
pub(super) fn drop_in_parallel<T: Send>(v: Vec<T>) {
    v.into_par_iter().with_min_len(ROW_CHUNK).for_each(drop);
}

/// Columns and values of the rows `row_ptr` describes, filled in parallel in runs of `rows`
/// consecutive rows: `fill(i, col, val)` writes row i's entries.
pub(super) fn fill_rows(
    row_ptr: &[usize],
    rows: usize,
    fill: impl Fn(usize, &mut [u32], &mut [f64]) + Sync,
) -> (Vec<u32>, Vec<f64>) {
    let n = row_ptr.len() - 1;
    let nnz = row_ptr[n];
    let (mut col, mut val) = (vec![0u32; nnz], vec![0.0f64; nnz]);
    let mut runs = Vec::with_capacity(n.div_ceil(rows.max(1)));
    let (mut c_rest, mut v_rest) = (col.as_mut_slice(), val.as_mut_slice());
    for r0 in (0..n).step_by(rows.max(1)) {
        let r1 = (r0 + rows).min(n);
        let len = row_ptr[r1] - row_ptr[r0];
        let (c, ct) = c_rest.split_at_mut(len);
        let (v, vt) = v_rest.split_at_mut(len);
        runs.push((r0, r1, c, v));
        (c_rest, v_rest) = (ct, vt);
    }
    runs.into_par_iter().for_each(|(r0, r1, c, v)| {
        let base = row_ptr[r0];
        for i in r0..r1 {
            let (a, b) = (row_ptr[i] - base, row_ptr[i + 1] - base);
            fill(i, &mut c[a..b], &mut v[a..b]);
        }
    });
    (col, val)
}

/// y = M x (or y += M x with `add`) for compressed rows `(row_ptr, col, val)` of any shape:
/// row-parallel in chunks of `ROW_CHUNK`, each row summed in column order, so the result is
/// the same on any number of threads. The one row loop of [`CsrMatrix::matvec`] and of the
/// multigrid's transfer operators.
#[inline]
pub(super) fn rows_times(
    row_ptr: &[usize],
    col: &[u32],
    val: &[f64],
    x: &[f64],
    y: &mut [f64],
    add: bool,
) {
    y.par_chunks_mut(ROW_CHUNK)
        .enumerate()
        .for_each(|(c, out)| {
            for (k, yi) in out.iter_mut().enumerate() {
                let i = c * ROW_CHUNK + k;
                let (a, b) = (row_ptr[i], row_ptr[i + 1]);
                let mut s = 0.0;
                for (&j, &v) in col[a..b].iter().zip(&val[a..b]) {
                    s += v * x[j as usize];
                }
                if add {
                    *yi += s;
                } else {
                    *yi = s;
                }
            }
        });
}
