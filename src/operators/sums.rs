//! Sums over particles in a fixed order, so that a reduction gives the same bits on any number of
//! threads: fixed-size chunks summed in parallel, the partial sums added in chunk order.

use rayon::prelude::*;

/// Chunk length of the fixed-order reductions (dot products, norms).
pub const DOT_CHUNK: usize = 2048;

/// Sum of a slice in fixed chunks, the partial sums added in order (thread-count independent).
pub fn fixed_sum(a: &[f64]) -> f64 {
    let parts: Vec<f64> = a
        .par_chunks(DOT_CHUNK)
        .map(|c| c.iter().sum::<f64>())
        .collect();
    parts.iter().sum()
}

/// Dot product in fixed chunks (thread-count independent).
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    let parts: Vec<f64> = a
        .par_chunks(DOT_CHUNK)
        .zip(b.par_chunks(DOT_CHUNK))
        .map(|(x, y)| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>())
        .collect();
    parts.iter().sum()
}
