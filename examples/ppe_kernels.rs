//! The PPE's sparse kernels against this machine's memory bandwidth (issue 16 item 3).
//!
//! `cargo run --release --example ppe_kernels [threads] [rounds]` (default 1 thread, 7 rounds).
//!
//! Systems: King & Lind 2021 eq. (25) on a disc of particles (quintic kernel, h = 1.3 dr,
//! lattice displaced by up to +/-0.15 dr, outer ring Dirichlet) at about 1e4 and 1e5 rows,
//! assembled by `ppe::assemble_poisson`. For each, in alternating rounds (best of `rounds`):
//! * a STREAM-like copy `a = b` and triad `a = b + s c` (McCalpin's kernels) over arrays of the
//!   matrix's size (so the same cache level) and over 3 x 128 MB (main memory);
//! * `CsrMatrix::matvec` (bytes moved: values 8 + column 4 per entry, row pointer 8 and y 8 per
//!   row, x 8 per row once), and the same product with four partial sums per row (not the
//!   library's order: shows what the fixed sequential sum costs);
//! * the ILU(0) factorisation and its two triangular solves, the library's against the loops
//!   as they were before issue 16 (copied below as `baseline_*`), checked bitwise equal.
//!
//! Prints GB/s (10^9 bytes/s) and ns per stored entry.

use std::hint::black_box;
use std::time::Instant;
use viscosph::kernel::{Kernel, QuinticSpline};
use viscosph::neighbors::Domain;
use viscosph::scheme::isph::ppe::*;
use viscosph_reference::fixtures::disc;

/// The ILU(0) factorisation as it was before issue 16 (a branch per update).
fn baseline_ilu0(a: &CsrMatrix) -> Vec<f64> {
    let n = a.n();
    let mut lu = a.val.clone();
    let mut pos = vec![usize::MAX; n];
    for i in 0..n {
        let (s, e) = (a.row_ptr[i], a.row_ptr[i + 1]);
        for p in s..e {
            pos[a.col[p] as usize] = p;
        }
        for p in s..a.diag[i] {
            let k = a.col[p] as usize;
            let lik = lu[p] / lu[a.diag[k]];
            lu[p] = lik;
            for q in a.diag[k] + 1..a.row_ptr[k + 1] {
                let t = pos[a.col[q] as usize];
                if t != usize::MAX {
                    lu[t] -= lik * lu[q];
                }
            }
        }
        for p in s..e {
            pos[a.col[p] as usize] = usize::MAX;
        }
    }
    lu
}

/// The ILU(0) triangular solves as they were before issue 16.
fn baseline_apply(a: &CsrMatrix, lu: &[f64], r: &[f64], z: &mut [f64]) {
    let n = a.n();
    for i in 0..n {
        let mut s = r[i];
        for p in a.row_ptr[i]..a.diag[i] {
            s -= lu[p] * z[a.col[p] as usize];
        }
        z[i] = s;
    }
    for i in (0..n).rev() {
        let mut s = z[i];
        for p in a.diag[i] + 1..a.row_ptr[i + 1] {
            s -= lu[p] * z[a.col[p] as usize];
        }
        z[i] = s / lu[a.diag[i]];
    }
}

/// y = A x with four partial sums per row (entries k, k+4, ... in lane k mod 4), added as
/// (s0 + s1) + (s2 + s3), then the tail: a different (still fixed) summation order.
fn matvec_four_lanes(a: &CsrMatrix, x: &[f64], y: &mut [f64]) {
    for (i, yi) in y.iter_mut().enumerate() {
        let (s, e) = (a.row_ptr[i], a.row_ptr[i + 1]);
        let (cols, vals) = (&a.col[s..e], &a.val[s..e]);
        let mut acc = [0.0f64; 4];
        let mut cc = cols.chunks_exact(4);
        let mut vc = vals.chunks_exact(4);
        for (c4, v4) in (&mut cc).zip(&mut vc) {
            for l in 0..4 {
                acc[l] += v4[l] * x[c4[l] as usize];
            }
        }
        let mut t = (acc[0] + acc[1]) + (acc[2] + acc[3]);
        for (&c, &v) in cc.remainder().iter().zip(vc.remainder()) {
            t += v * x[c as usize];
        }
        *yi = t;
    }
}

fn best<F: FnMut()>(best: &mut f64, mut f: F) {
    let t = Instant::now();
    f();
    *best = best.min(t.elapsed().as_secs_f64());
}

fn stream(len: usize, rounds: usize) -> (f64, f64) {
    let b: Vec<f64> = (0..len).map(|i| i as f64).collect();
    let c: Vec<f64> = (0..len).map(|i| 0.5 * i as f64).collect();
    let mut a = vec![0.0; len];
    let reps = (2e7 / len as f64).ceil() as usize;
    let (mut tc, mut tt) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..rounds {
        best(&mut tc, || {
            for _ in 0..reps {
                a.copy_from_slice(black_box(&b));
                black_box(&mut a);
            }
        });
        best(&mut tt, || {
            for _ in 0..reps {
                let s = black_box(3.0);
                for ((a, b), c) in a.iter_mut().zip(&b).zip(&c) {
                    *a = b + s * c;
                }
                black_box(&mut a);
            }
        });
    }
    let bytes = len as f64 * 8.0 * reps as f64;
    (2.0 * bytes / tc / 1e9, 3.0 * bytes / tt / 1e9)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let threads: usize = args.next().map_or(1, |a| a.parse().expect("threads"));
    let rounds: usize = args.next().map_or(7, |a| a.parse().expect("rounds"));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| run(threads, rounds));
}

fn run(threads: usize, rounds: usize) {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_default();
    println!("CPU: {cpu}; {threads} thread(s), best of {rounds} alternating rounds");
    let (mc, mt) = stream(1 << 24, rounds.min(3));
    println!("STREAM over 3 x 128 MB: copy {mc:.1} GB/s, triad {mt:.1} GB/s\n");
    println!("| rows | nnz/row | matrix MB | copy GB/s | triad GB/s | matvec GB/s (ns/entry) | 4 sums GB/s | ILU(0) factor ms: before / now | ILU(0) solves GB/s: before / now |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for radius in [56.4, 178.4] {
        let set = disc(radius, 1.0, 0.15, 7);
        let k = QuinticSpline::new(1.3 * set.dr);
        let nl = set.neighbours(k.radius());
        let vol = vec![set.dr * set.dr; set.x.len()];
        let coef = morris_coefficients(&set.x, &vol, &nl, &k, &Domain::OPEN, None);
        let n = set.n_fluid;
        let dirichlet: Vec<Option<f64>> = set.x[..n]
            .iter()
            .map(|x| (x.norm() > radius - 1.0).then_some(0.0))
            .collect();
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1000) as f64 * 1e-3).collect();
        let sys = assemble_poisson(n, &nl, &coef, &GhostLink::NONE, &dirichlet, &b);
        let a = &sys.matrix;
        let nnz = a.nnz();
        // Bytes one pass reads and writes (x counted once: it is reused from cache).
        let mv_bytes = (nnz * 12 + n * (8 + 8 + 8)) as f64;
        let (sc, st) = stream((mv_bytes / 24.0) as usize, rounds);
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let (mut y, mut y4) = (vec![0.0; n], vec![0.0; n]);
        let reps = (2e7 / nnz as f64).ceil() as usize;
        let fac = match Factor::new(a, Preconditioner::Ilu0).expect("ilu") {
            Factor::Ilu0(lu) => lu,
            _ => unreachable!(),
        };
        let fac_old = baseline_ilu0(a);
        assert!(
            fac.iter()
                .zip(&fac_old)
                .all(|(p, q)| p.to_bits() == q.to_bits()),
            "ILU(0) factors differ from the baseline loop"
        );
        let m = Factor::Ilu0(fac.clone());
        let (mut z, mut z_old) = (vec![0.0; n], vec![0.0; n]);
        let (mut t_mv, mut t_mv4, mut t_f, mut t_f_old, mut t_ap, mut t_ap_old) = (
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
        );
        for _ in 0..rounds {
            best(&mut t_mv, || {
                for _ in 0..reps {
                    a.matvec(black_box(&x), &mut y);
                }
            });
            best(&mut t_mv4, || {
                for _ in 0..reps {
                    matvec_four_lanes(a, black_box(&x), &mut y4);
                }
            });
            best(&mut t_f_old, || {
                black_box(baseline_ilu0(black_box(a)));
            });
            best(&mut t_f, || {
                black_box(Factor::new(black_box(a), Preconditioner::Ilu0).expect("ilu"));
            });
            best(&mut t_ap_old, || {
                for _ in 0..reps {
                    baseline_apply(a, &fac_old, black_box(&x), &mut z_old);
                }
            });
            best(&mut t_ap, || {
                for _ in 0..reps {
                    m.apply(a, black_box(&x), &mut z);
                }
            });
        }
        assert!(
            z.iter()
                .zip(&z_old)
                .all(|(p, q)| p.to_bits() == q.to_bits()),
            "ILU(0) solves differ from the baseline loop"
        );
        let rel = y
            .iter()
            .zip(&y4)
            .map(|(p, q)| (p - q).abs() / p.abs().max(1e-300))
            .fold(0.0, f64::max);
        let gbs = |t: f64| mv_bytes * reps as f64 / t / 1e9;
        println!(
            "| {n} | {:.1} | {:.1} | {sc:.1} | {st:.1} | {:.1} ({:.2}) | {:.1} | {:.2} / {:.2} | {:.1} / {:.1} |",
            nnz as f64 / n as f64,
            mv_bytes / 1e6,
            gbs(t_mv),
            t_mv / (reps * nnz) as f64 * 1e9,
            gbs(t_mv4),
            t_f_old * 1e3,
            t_f * 1e3,
            gbs(t_ap_old),
            gbs(t_ap),
        );
        eprintln!("  four-sum product: largest relative difference {rel:.1e}");
    }
}
