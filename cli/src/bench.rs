//! Benchmarks: `viscosph bench <what>`. Speed is measured here, never by timed assertions in tests.
//!
//! One file per command under `bench/`: [`mod@drop`], [`throughput`], [`scaling`], [`stability`], [`accuracy`]
//! (with `replot`), [`rheologies`], [`jet`], [`channel`], [`cylinders`], [`isph`] and [`report`]; here are the
//! arguments, the dispatch and what several commands share (cases, the convergence order, the
//! machine description).
//!
//! A case is a named [`SceneConfig`]; adding a scheme or a scene to a benchmark is adding a line to
//! its case list.

pub mod accuracy;
pub mod channel;
pub mod cylinders;
pub mod drop;
pub mod isph;
pub mod jet;
pub mod report;
pub mod rheologies;
pub mod scaling;
pub mod stability;
pub mod throughput;

use clap::{Args, Subcommand};
use std::path::PathBuf;
use viscosph::config::Value;
use viscosph::scene::Outputs;
use viscosph::scene::SceneConfig;
use viscosph::scene::SchemeKind;
use viscosph::scheme::SCHEMES;

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchKind,
    /// Output directory for CSV, Markdown and PNG files.
    #[arg(long, global = true, default_value = "results/bench")]
    pub out: PathBuf,
    /// Smaller sizes, for smoke tests: checks the outputs' structure, not speed.
    #[arg(long, global = true)]
    pub quick: bool,
}

#[derive(Subcommand, Debug, Clone)]
pub enum BenchKind {
    /// Fang's drops at 20/40/80 particles per diameter: cost and convergence of W*(t*).
    Drop,
    /// Particle-steps per second on 1 and 2 threads at 10^3..10^6 particles, FMU overhead.
    Throughput,
    /// Threads 1 to the cores x sizes (WCSPH 10^4..10^6, ISPH 10^3..10^5 particles): speed-up,
    /// efficiency, the serial share of a step from the per-pass timers and its Amdahl
    /// projection to 16 threads; the thread counts alternate over repeated runs of the same
    /// steps (median and spread).
    Scaling(scaling::ScalingArgs),
    /// Stability maps: sweeps of De, beta, inclination, impact velocity and resolution.
    Stability(stability::StabilityArgs),
    /// Error against run time for every scheme on problems with a trustworthy reference.
    Accuracy,
    /// Fang's drop (De = 1, beta = 0.1) with every rheology: W*(t*) and H*(t*) overlaid, like
    /// King & Lind's Fig. 16.
    Rheologies,
    /// King & Lind's buckling jet: Wi, FENE and Giesekus sweeps and the Newtonian fall height.
    Jet,
    /// Start-up Poiseuille flow against Waters & King: accuracy and order, King & Lind's Wi
    /// sweeps, the non-linear models' steady profiles (see `bench/channel.rs`).
    Channel(channel::ChannelArgs),
    /// King & Lind's periodic array of cylinders: Wi sweep per scheme to the steady state, cost
    /// against Wi, Newtonian drag against resolution, Figs. 9-11 (see `bench/cylinders.rs`).
    Cylinders(cylinders::CylindersArgs),
    /// ISPH (King & Lind 2021) on their Newtonian Re = 4 drop: cost with the implicit and the
    /// explicit viscous step (steps, PPE iterations per step, share of time in the linear
    /// solves), convergence of W*(t*) at W/dr = 20, 40, 80, and the volume it keeps.
    Isph,
    /// Redraw the PNGs that the CSV files in --out hold the data of (accuracy.png), without
    /// running anything: for a change of the plot style.
    Replot,
    /// Regenerate docs/benchmarks.md: the sections found in --out (run their commands first) are
    /// taken into docs/bench/, the committed results, and the report is written from there.
    Report {
        /// Where the report goes.
        #[arg(long, default_value = "docs")]
        docs: PathBuf,
    },
    /// One throughput case's peak memory, in a process of its own (`bench throughput` runs it).
    #[command(hide = true)]
    MemoryProbe(throughput::ProbeArgs),
}

pub fn main(args: BenchArgs) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all(&args.out)?;
    // Which commit each measurement ran on, for the report (which may be assembled later);
    // taken before measuring, so a commit made meanwhile is not credited.
    let commit = git_commit();
    let stem = match args.what {
        BenchKind::Drop => Some("drop"),
        BenchKind::Throughput => Some("throughput"),
        BenchKind::Scaling(_) => Some("scaling"),
        BenchKind::Stability(_) => Some("stability"),
        BenchKind::Accuracy => Some("accuracy"),
        BenchKind::Rheologies => Some("rheologies"),
        BenchKind::Jet => Some("jet"),
        BenchKind::Channel(_) => Some("channel"),
        BenchKind::Cylinders(_) => Some("cylinders"),
        BenchKind::Isph => Some("isph"),
        BenchKind::Report { .. } | BenchKind::Replot | BenchKind::MemoryProbe(_) => None,
    };
    let report = match args.what {
        BenchKind::Drop => drop::bench_drop(&args.out, args.quick)?,
        BenchKind::Throughput => throughput::bench_throughput(&args.out, args.quick)?,
        BenchKind::Scaling(ref a) => scaling::bench_scaling(a, &args.out, args.quick)?,
        BenchKind::Stability(ref a) => stability::bench_stability(a, &args.out, args.quick)?,
        BenchKind::Accuracy => accuracy::bench_accuracy(&args.out, args.quick)?,
        BenchKind::Rheologies => rheologies::bench_rheologies(&args.out, args.quick)?,
        BenchKind::Jet => jet::bench_jet(&args.out, args.quick)?,
        BenchKind::Channel(ref c) => channel::main(c, &args.out, args.quick)?,
        BenchKind::Cylinders(ref c) => cylinders::bench_cylinders(c, &args.out, args.quick)?,
        BenchKind::Isph => isph::bench_isph(&args.out, args.quick)?,
        BenchKind::Report { ref docs } => report::bench_report(&args.out, docs)?,
        BenchKind::Replot => accuracy::bench_replot(&args.out)?,
        BenchKind::MemoryProbe(ref a) => throughput::memory_probe(a)?,
    };
    if let Some(stem) = stem {
        std::fs::write(args.out.join(format!("{stem}.commit")), commit + "\n")?;
        std::fs::write(
            args.out.join(format!("{stem}.machine")),
            machine_description() + "\n",
        )?;
    }
    println!("{report}");
    Ok(())
}

/// A configuration from the defaults and (name, value) pairs; panics on a bad pair (benchmark
/// cases are written in code, so a bad one is a programming error).
pub fn case(pairs: &[(&str, Value)]) -> SceneConfig {
    let mut c = SceneConfig::default();
    for (k, v) in pairs {
        c.set(k, v.clone())
            .unwrap_or_else(|e| panic!("benchmark case: {e}"));
    }
    c
}

/// Fang's Newtonian drop (epsilon = 0.2) and Oldroyd-B drop (epsilon = 0.5, the defaults).
pub fn fang_cases() -> Vec<(&'static str, SceneConfig)> {
    vec![
        (
            "newtonian",
            case(&[
                ("rheology", Value::Text("newtonian".into())),
                ("artificial_stress_epsilon", Value::Real(0.2)),
            ]),
        ),
        ("oldroyd_b", case(&[])),
    ]
}

/// Largest difference of W* = width/D between two series sampled at the same times.
pub fn max_width_difference(a: &[(f64, Outputs)], b: &[(f64, Outputs)], d: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|((_, x), (_, y))| ((x.shared.drop_width - y.shared.drop_width) / d).abs())
        .fold(0.0, f64::max)
}

/// Observed order of convergence p of a result converging as Q(h) = Q* + C h^p, h ~ 1 / n with
/// n the resolution (particles per width or diameter), from two errors: `e1` = |Q(h_a) - Q(h_b)|
/// between the resolutions `n1` = [a, b] and `e2` likewise between `n2`; a resolution of
/// `f64::INFINITY` stands for the exact solution Q* (in both pairs or in neither). The errors
/// are in any norm (max over the output times, RMS over time of an L2 norm over the particles).
/// Solves e1 / e2 = (h_a^p - h_b^p) / (h_c^p - h_d^p) (Richardson):
/// * in closed form, p = log2(e1 / e2) / log2(h_a / h_c), when both pairs refine by the same
///   ratio (b / a = d / c): successive differences of doubling resolutions, two errors against
///   the exact solution;
/// * otherwise (W/dr = 40, 80, 120) by bisection on p in [-4, 8] (the ratio rises with p).
///
/// Errors that shrink with resolution give a positive order, errors that grow a negative one;
/// NaN when e1 / e2 is not finite and positive (no order can be read).
pub fn convergence_order(e1: f64, n1: [f64; 2], e2: f64, n2: [f64; 2]) -> f64 {
    let target = e1 / e2;
    if !(target.is_finite() && target > 0.0) {
        return f64::NAN;
    }
    if n1[1] / n1[0] == n2[1] / n2[0] {
        // (h_a^p - h_b^p) / (h_c^p - h_d^p) = (h_a / h_c)^p, with h_a / h_c = n_c / n_a.
        return target.log2() / (n2[0] / n1[0]).log2();
    }
    let h1 = n1.map(|n| 1.0 / n);
    let h2 = n2.map(|n| 1.0 / n);
    let ratio = |p: f64| {
        if p.abs() < 1e-12 {
            (h1[0] / h1[1]).ln() / (h2[0] / h2[1]).ln()
        } else {
            (h1[0].powf(p) - h1[1].powf(p)) / (h2[0].powf(p) - h2[1].powf(p))
        }
    };
    let (mut lo, mut hi) = (-4.0_f64, 8.0_f64);
    if target <= ratio(lo) {
        return lo;
    }
    if target >= ratio(hi) {
        return hi;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if ratio(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Schemes the solver can build now (the others are refused by validation and left out).
pub fn built_schemes() -> Vec<SchemeKind> {
    SCHEMES
        .iter()
        .filter_map(|(n, _)| SchemeKind::parse(n))
        .filter(|s| {
            let c = SceneConfig {
                scheme: *s,
                ..Default::default()
            };
            c.validate().is_ok()
        })
        .collect()
}

/// One line about the machine: CPU model, cores, memory.
pub fn machine_description() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let mem = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("MemTotal"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map(|kb| format!("{:.0} GiB", kb / 1024.0 / 1024.0))
        .unwrap_or_default();
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    format!("{cpu}, {cores} cores, {mem}")
}

/// The commit the binary runs from, `-dirty` if the work tree has uncommitted changes.
fn git_commit() -> String {
    std::process::Command::new("git")
        .args(["describe", "--always", "--dirty", "--abbrev=7"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_convergence_order_recovers_the_power_law() {
        let inf = f64::INFINITY;
        // Successive differences of doubling resolutions: log2 of their ratio.
        assert_eq!(
            convergence_order(0.04, [20.0, 40.0], 0.01, [40.0, 80.0]),
            2.0
        );
        // W/dr = 40, 80, 120 with an error 3 h^1.5 (h = 1/ppd): the differences alone give 1.5.
        let err = |n: f64| 3.0 * (1.0 / n).powf(1.5);
        let p = convergence_order(
            err(40.0) - err(80.0),
            [40.0, 80.0],
            err(80.0) - err(120.0),
            [80.0, 120.0],
        );
        assert!((p - 1.5).abs() < 1e-9, "{p}");
        // Errors against the exact solution: second order from 15 to 30 across, and 1.5 from
        // 15 to 40 (not a doubling).
        assert!((convergence_order(4e-2, [15.0, inf], 1e-2, [30.0, inf]) - 2.0).abs() < 1e-12);
        let p = convergence_order(err(15.0), [15.0, inf], err(40.0), [40.0, inf]);
        assert!((p - 1.5).abs() < 1e-12, "{p}");
        // Differences that grow with resolution: a negative order; none at all: NaN.
        assert!(convergence_order(0.01, [20.0, 40.0], 0.02, [40.0, 80.0]) < 0.0);
        assert!(convergence_order(0.01, [20.0, 40.0], 0.0, [40.0, 80.0]).is_nan());
        assert!(convergence_order(0.0, [15.0, inf], 0.01, [30.0, inf]).is_nan());
    }
}
