//! Benchmarks: `viscosph bench <what>`. Speed is measured here, never by timed assertions in tests.
//!
//! * `drop` (issue 2): Fang's Newtonian and Oldroyd-B drops at 20, 40 and 80 particles per
//!   diameter: wall time, steps, particle-steps per second, and the largest difference of W*(t*)
//!   from the finest run.
//! * `throughput`: particle-steps per second of the Newtonian and Oldroyd-B drop on 1 and 2
//!   threads at about 10^3, 10^4, 10^5 and (Newtonian only, 6 steps) 10^6 particles, the CPU
//!   time and peak RSS per particle, and the Oldroyd-B / Newtonian cost ratio.
//!
//! A case is a named [`SceneConfig`]; adding a scheme or a scene to a benchmark is adding a line to
//! its case list.

pub mod channel;
pub mod jet;

use crate::io::plot::{line_panels, panel_grid, status_grid, Panel, Series};
use crate::run::{run, time_scale, RunOptions};
use clap::{Args, Subcommand};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use viscosph::config::{RheologyKind, SchemeKind, RHEOLOGIES, SCHEMES};
use viscosph::config::{SceneConfig, Value};
use viscosph::diagnostics::Outputs;
use viscosph::simulation::Simulation;

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
    /// Stability maps: sweeps of De, beta, inclination, impact velocity and resolution.
    Stability(StabilityArgs),
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
    /// ISPH (King & Lind 2021) on their Newtonian Re = 4 drop: cost with the implicit and the
    /// explicit viscous step (steps, PPE iterations per step, share of time in the linear
    /// solves), convergence of W*(t*) at W/dr = 20, 40, 80, and the volume it keeps.
    Isph,
    /// Redraw the PNGs that the CSV files in --out hold the data of (accuracy.png), without
    /// running anything: for a change of the plot style.
    Replot,
    /// Assemble docs/benchmarks.md from the results of the other subcommands (run them first),
    /// with the machine and commit noted and the PNGs copied to docs/bench/.
    Report {
        /// Where the report goes.
        #[arg(long, default_value = "docs")]
        docs: PathBuf,
    },
}

pub fn main(args: BenchArgs) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all(&args.out)?;
    // Which commit each measurement ran on, for the report (which may be assembled later);
    // taken before measuring, so a commit made meanwhile is not credited.
    let commit = git_commit();
    let stem = match args.what {
        BenchKind::Drop => Some("drop"),
        BenchKind::Throughput => Some("throughput"),
        BenchKind::Stability(_) => Some("stability"),
        BenchKind::Accuracy => Some("accuracy"),
        BenchKind::Rheologies => Some("rheologies"),
        BenchKind::Jet => Some("jet"),
        BenchKind::Channel(_) => Some("channel"),
        BenchKind::Isph => Some("isph"),
        BenchKind::Report { .. } | BenchKind::Replot => None,
    };
    let report = match args.what {
        BenchKind::Drop => bench_drop(&args.out, args.quick)?,
        BenchKind::Throughput => bench_throughput(&args.out, args.quick)?,
        BenchKind::Stability(ref a) => bench_stability(a, &args.out, args.quick)?,
        BenchKind::Accuracy => bench_accuracy(&args.out, args.quick)?,
        BenchKind::Rheologies => bench_rheologies(&args.out, args.quick)?,
        BenchKind::Jet => jet::bench_jet(&args.out, args.quick)?,
        BenchKind::Channel(ref c) => channel::main(c, &args.out, args.quick)?,
        BenchKind::Isph => bench_isph(&args.out, args.quick)?,
        BenchKind::Report { ref docs } => bench_report(&args.out, docs)?,
        BenchKind::Replot => bench_replot(&args.out)?,
    };
    if let Some(stem) = stem {
        std::fs::write(args.out.join(format!("{stem}.commit")), commit + "\n")?;
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

/// King & Lind 2021 section IV.C's drop under ISPH: W = 2 cm, centre W above the plate,
/// U = 1 m/s, eta0 = 5 Pa s, rho = 1000 kg/m3 (Re = 4).
pub fn king_lind_drop(rheology: &str, ppd: i64) -> SceneConfig {
    case(&[
        ("scheme", Value::Text("isph".into())),
        ("rheology", Value::Text(rheology.into())),
        ("viscosity", Value::Real(5.0)),
        ("initial_drop_height", Value::Real(0.02)),
        ("particles_per_diameter", Value::Integer(ppd)),
        ("threads", Value::Integer(2)),
    ])
}

/// One ISPH run: outputs every 0.05 t*, the run's cost and where the time went.
struct IsphRun {
    series: Vec<(f64, Outputs)>,
    error: Option<String>,
    wall: f64,
    steps: u64,
    particles: usize,
    iterations: [u64; 2],
    timings: viscosph::scheme::isph::IsphTimings,
}

impl IsphRun {
    /// W* = W / (2 cm) at the last output (NaN without outputs).
    fn w_star_end(&self) -> f64 {
        self.series
            .last()
            .map_or(f64::NAN, |(_, o)| o.drop_width / 0.02)
    }

    /// The largest |volume_error| over the outputs.
    fn max_volume_error(&self) -> f64 {
        self.series
            .iter()
            .map(|(_, o)| o.volume_error.abs())
            .fold(0.0, f64::max)
    }
}

fn isph_run(cfg: &SceneConfig, t_star_end: f64) -> Result<IsphRun, Box<dyn std::error::Error>> {
    let ts = time_scale(cfg);
    let mut sim = Simulation::new(cfg.clone())?;
    let t0 = std::time::Instant::now();
    let (series, err) = sim.record(t_star_end * ts, 0.05 * ts);
    let wall = t0.elapsed().as_secs_f64();
    let st = sim.state();
    Ok(IsphRun {
        series,
        error: err.map(|e| e.to_string()),
        wall,
        steps: st.step,
        particles: st.fluid.len(),
        iterations: st.solver_iterations,
        timings: sim.scheme_timings().unwrap_or_default(),
    })
}

fn bench_isph(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let t_star_end = if quick { 2.0 } else { 8.0 };
    let speed_ppd = if quick { 16 } else { 40 };
    let mut md = format!(
        "Newtonian drop of King & Lind 2021 IV.C (Re = 4) to t* = {t_star_end}, 2 threads, {}.\n\n",
        machine_description()
    );
    md.push_str("| viscous step | particles/W | particles | steps | wall [s] | PPE iterations/step | viscous iterations/step | time in PPE | time in viscous solve | W*(end) | max \\|volume_error\\| |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    let mut csv = String::from("kind,viscous_step,ppd,particles,steps,wall_seconds,ppe_iterations,viscous_iterations,ppe_seconds,viscous_seconds,w_end,max_volume_error,error\n");
    let row = |md: &mut String,
               csv: &mut String,
               kind: &str,
               step: &str,
               ppd: i64,
               r: &IsphRun|
     -> std::fmt::Result {
        let n = r.steps.max(1) as f64;
        let (w_end, vmax) = (r.w_star_end(), r.max_volume_error());
        let tot = r.timings.total.max(1e-12);
        // The explicit viscous step has no viscous solve: "-", not "0.0" and "0 %".
        let (visc_iters, visc_share) = if r.iterations[1] == 0 {
            ("-".to_string(), "-".to_string())
        } else {
            (
                format!("{:.1}", r.iterations[1] as f64 / n),
                format!("{:.0} %", 100.0 * r.timings.viscous_solve / tot),
            )
        };
        writeln!(
            md,
            "| {step} | {ppd} | {} | {} | {:.2} | {:.1} | {visc_iters} | {:.0} % | {visc_share} | {w_end:.3} | {:.2} % |{}",
            r.particles,
            r.steps,
            r.wall,
            r.iterations[0] as f64 / n,
            100.0 * r.timings.pressure_solve / tot,
            100.0 * vmax,
            r.error.as_ref().map(|e| format!(" broke down: {e}")).unwrap_or_default()
        )?;
        writeln!(
            csv,
            "{kind},{step},{ppd},{},{},{:.3},{},{},{:.3},{:.3},{w_end:.5},{vmax:.5},\"{}\"",
            r.particles,
            r.steps,
            r.wall,
            r.iterations[0],
            r.iterations[1],
            r.timings.pressure_solve,
            r.timings.viscous_solve,
            r.error.clone().unwrap_or_default().replace('"', "'")
        )
    };
    for step in ["implicit", "explicit"] {
        let mut cfg = king_lind_drop("newtonian", speed_ppd);
        cfg.set("isph_viscous_step", Value::Text(step.into()))?;
        eprintln!("bench isph: speed, {step} viscosity, W/dr = {speed_ppd} ...");
        let r = isph_run(&cfg, t_star_end)?;
        row(&mut md, &mut csv, "speed", step, speed_ppd, &r)?;
    }
    // At the default step (h / |u|-limited, so it shrinks with h: temporal and spatial error
    // mixed) up to the paper's production resolution W/dr = 120, and at a third of it to 80
    // (docs/isph.md: the default step's temporal error dominates; W/dr = 120 at the small step
    // would take about an hour here).
    // The convergence sentences go below the table, so that its rows stay one table.
    let mut notes = String::new();
    for (factor, label, file, ppds) in [
        (
            0.3,
            "implicit",
            "isph_convergence.csv",
            if quick {
                &[10, 14, 20][..]
            } else {
                &[20, 40, 80, 120][..]
            },
        ),
        (
            0.1,
            "implicit, time_step_factor 0.1",
            "isph_convergence_small_step.csv",
            if quick {
                &[10, 14, 20][..]
            } else {
                &[20, 40, 80][..]
            },
        ),
    ] {
        let mut runs = Vec::new();
        for &ppd in ppds {
            eprintln!("bench isph: convergence, {label}, W/dr = {ppd} ...");
            let mut cfg = king_lind_drop("newtonian", ppd);
            cfg.set("time_step_factor", Value::Real(factor))?;
            let r = isph_run(&cfg, t_star_end)?;
            row(&mut md, &mut csv, "convergence", label, ppd, &r)?;
            runs.push(r);
        }
        if runs.iter().all(|r| r.error.is_none()) {
            let d = 0.02;
            let diffs: Vec<f64> = runs
                .windows(2)
                .map(|w| max_width_difference(&w[0].series, &w[1].series, d))
                .collect();
            write!(
                notes,
                "\nConvergence of W*(t*), {label}, t* <= {t_star_end} (max norm):"
            )?;
            for (k, e) in diffs.iter().enumerate() {
                write!(notes, " |W*_{} - W*_{}| = {e:.4};", ppds[k], ppds[k + 1])?;
            }
            let orders: Vec<String> = (0..diffs.len().saturating_sub(1))
                .map(|k| {
                    let p = order_from_differences(
                        [ppds[k], ppds[k + 1], ppds[k + 2]].map(|v| v as f64),
                        diffs[k],
                        diffs[k + 1],
                    );
                    format!("{p:.2} ({}-{}-{})", ppds[k], ppds[k + 1], ppds[k + 2])
                })
                .collect();
            writeln!(notes, " observed order {}.", orders.join(", "))?;
            let mut series = String::from("t_star");
            for &p in ppds {
                write!(series, ",w_star_{p}")?;
            }
            series.push('\n');
            for k in 0..runs.iter().map(|r| r.series.len()).min().unwrap_or(0) {
                write!(series, "{:.3}", runs[0].series[k].0 / 0.02)?;
                for r in &runs {
                    write!(series, ",{:.5}", r.series[k].1.drop_width / 0.02)?;
                }
                series.push('\n');
            }
            std::fs::write(out.join(file), series)?;
        }
    }
    md.push_str(&notes);
    cross_scheme(out, quick, t_star_end, &mut md)?;
    std::fs::write(out.join("isph.csv"), csv)?;
    std::fs::write(out.join("isph.md"), &md)?;
    Ok(md)
}

/// Cross-scheme agreement on the Newtonian Re = 4 drop (issue 11): isph, wcsph and pdri at one
/// resolution, and the weakly compressible schemes without artificial viscosity (Monaghan's
/// alpha = 1 at c = 12.6 m/s adds a viscosity comparable to the fluid's at this resolution):
/// W*(end) and the largest |Delta W*| over the run for every pair, into `md` and
/// `isph_cross_scheme.csv`.
fn cross_scheme(
    out: &Path,
    quick: bool,
    t_star_end: f64,
    md: &mut String,
) -> Result<(), Box<dyn std::error::Error>> {
    let ppd = if quick { 12 } else { 80 };
    let variants: [(&str, &str, f64); 5] = [
        ("isph", "isph", 1.0),
        ("wcsph", "wcsph", 1.0),
        ("pdri", "pdri", 1.0),
        ("wcsph, alpha = 0", "wcsph", 0.0),
        ("pdri, alpha = 0", "pdri", 0.0),
    ];
    let mut runs = Vec::new();
    for (label, scheme, av) in variants {
        let mut cfg = king_lind_drop("newtonian", ppd);
        cfg.set("scheme", Value::Text(scheme.into()))?;
        cfg.set("artificial_viscosity_alpha", Value::Real(av))?;
        eprintln!("bench isph: cross-scheme, {label}, W/dr = {ppd} ...");
        runs.push((label, isph_run(&cfg, t_star_end)?));
    }
    writeln!(
        md,
        "\nCross-scheme agreement, Newtonian Re = 4 drop, W/dr = {ppd}, t* <= {t_star_end} \
         (max |Delta W*| over outputs every 0.05 t*; the weakly compressible schemes with \
         c = 12.6 m/s):\n\n| scheme | steps | wall [s] | W*(end) | max \\|volume_error\\| | {} |\n|---|---|---|---|---|{}",
        variants.map(|v| format!("vs {}", v.0)).join(" | "),
        "---|".repeat(variants.len())
    )?;
    let mut csv = String::from("scheme,other,max_abs_dw\n");
    for (label, r) in &runs {
        let (w_end, vmax) = (r.w_star_end(), r.max_volume_error());
        write!(
            md,
            "| {label} | {} | {:.2} | {w_end:.3} | {:.2} % |",
            r.steps,
            r.wall,
            100.0 * vmax
        )?;
        for (other, q) in &runs {
            let d = max_width_difference(&r.series, &q.series, 0.02);
            write!(md, " {d:.3} |")?;
            writeln!(csv, "{label},{other},{d:.5}")?;
        }
        writeln!(
            md,
            "{}",
            r.error
                .as_ref()
                .map(|e| format!(" broke down: {e}"))
                .unwrap_or_default()
        )?;
    }
    std::fs::write(out.join("isph_cross_scheme.csv"), csv)?;
    Ok(())
}

/// One row of a drop benchmark.
#[derive(Debug, Clone)]
pub struct DropRow {
    pub case: String,
    pub ppd: i64,
    pub particles: usize,
    pub steps: u64,
    pub wall_seconds: f64,
    pub throughput: f64,
    /// Largest |W*(t*) - W*_finest(t*)| over the common output times.
    pub w_diff: f64,
    /// Particles put back above the plate (the impenetrability condition of Fang's walls).
    pub wall_reflections: u64,
    pub error: Option<String>,
    pub series: Vec<(f64, Outputs)>,
}

/// Largest difference of W* = width/D between two series sampled at the same times.
pub fn max_width_difference(a: &[(f64, Outputs)], b: &[(f64, Outputs)], d: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|((_, x), (_, y))| ((x.drop_width - y.drop_width) / d).abs())
        .fold(0.0, f64::max)
}

/// Run each case at each resolution to `t_star_end` and fill in the difference of W* from the
/// finest run of its case.
pub fn drop_convergence(
    cases: &[(&'static str, SceneConfig)],
    ppds: &[i64],
    t_star_end: f64,
) -> Result<Vec<DropRow>, Box<dyn std::error::Error>> {
    let mut rows: Vec<DropRow> = Vec::new();
    for (name, base) in cases {
        let mut group = Vec::new();
        for &ppd in ppds {
            let mut cfg = base.clone();
            cfg.set("particles_per_diameter", Value::Integer(ppd))?;
            let ts = time_scale(&cfg);
            let opts = RunOptions {
                t_end: t_star_end * ts,
                output_interval: 0.05 * ts,
                ..RunOptions::for_scene(&cfg)
            };
            eprintln!(
                "bench: {} {name} at {ppd} particles per diameter ...",
                cfg.scheme
            );
            let r = run(&cfg, &opts)?;
            group.push(DropRow {
                case: name.to_string(),
                ppd,
                particles: r.particles,
                steps: r.steps,
                wall_seconds: r.wall_seconds,
                throughput: r.throughput(),
                w_diff: 0.0,
                wall_reflections: r.wall_reflections,
                error: r.error.map(|e| e.to_string()),
                series: r.series,
            });
        }
        let finest = group.last().expect("resolutions").series.clone();
        let d = base.drop_diameter;
        for row in &mut group {
            row.w_diff = max_width_difference(&row.series, &finest, d);
        }
        rows.extend(group);
    }
    Ok(rows)
}

/// Observed order of convergence from three resolutions refined by a factor of 2
/// (Richardson): p = log2(|W_c - W_m| / |W_m - W_f|) in the max norm over the common times.
/// The order p of a quantity converging as C h^p, from its differences between three
/// resolutions `ppd` (particles per width, h ~ 1 / ppd) that need not double:
/// e1 / e2 = (h1^p - h2^p) / (h2^p - h3^p), solved by bisection on p in [-4, 8] (the ratio rises
/// with p). With doubling resolutions it is log2(e1 / e2). NaN when the differences give no
/// positive ratio.
pub fn order_from_differences(ppd: [f64; 3], e1: f64, e2: f64) -> f64 {
    let target = e1 / e2;
    if !(target.is_finite() && target > 0.0) {
        return f64::NAN;
    }
    let h = ppd.map(|n| 1.0 / n);
    let ratio = |p: f64| {
        if p.abs() < 1e-12 {
            (h[0] / h[1]).ln() / (h[1] / h[2]).ln()
        } else {
            (h[0].powf(p) - h[1].powf(p)) / (h[1].powf(p) - h[2].powf(p))
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

pub fn observed_order(
    coarse: &[(f64, Outputs)],
    mid: &[(f64, Outputs)],
    fine: &[(f64, Outputs)],
    d: f64,
) -> f64 {
    let e1 = max_width_difference(coarse, mid, d);
    let e2 = max_width_difference(mid, fine, d);
    (e1 / e2).log2()
}

fn bench_drop(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let ppds: &[i64] = if quick { &[10, 14, 20] } else { &[20, 40, 80] };
    let t_star_end = if quick { 3.0 } else { 8.0 };
    let rows = drop_convergence(&fang_cases(), ppds, t_star_end)?;
    // CSV, Markdown table, PNG.
    let mut csv = String::from("case,particles_per_diameter,particles,steps,wall_seconds,particle_steps_per_second,max_w_star_difference_from_finest,wall_reflections,error\n");
    let mut md = String::from("| case | particles/D | particles | steps | wall time [s] | particle-steps/s | max \\|ΔW*\\| vs finest | put back above the plate | breakdown |\n|---|---|---|---|---|---|---|---|---|\n");
    for r in &rows {
        let err = r.error.clone().unwrap_or_default();
        let cells = [
            r.case.clone(),
            r.ppd.to_string(),
            r.particles.to_string(),
            r.steps.to_string(),
            format!("{:.2}", r.wall_seconds),
            format!("{:.3e}", r.throughput),
            format!("{:.4}", r.w_diff),
            r.wall_reflections.to_string(),
        ];
        writeln!(csv, "{},\"{err}\"", cells.join(","))?;
        let breakdown = if err.is_empty() { "none" } else { &err };
        writeln!(md, "| {} | {breakdown} |", cells.join(" | "))?;
    }
    std::fs::write(out.join("drop.csv"), &csv)?;
    std::fs::write(out.join("drop.md"), &md)?;
    let cfg = SceneConfig::default();
    let ts = time_scale(&cfg);
    let d = cfg.drop_diameter;
    let mut panels = Vec::new();
    for (name, _) in fang_cases() {
        panels.push(Panel {
            title: format!("{name}: W*(t*) at each resolution"),
            x_label: "t* = t V / D [-]".into(),
            y_label: "W* = W / D [-]".into(),
            series: rows
                .iter()
                .filter(|r| r.case == name)
                .map(|r| Series {
                    label: format!("{} particles/D", r.ppd),
                    points: r
                        .series
                        .iter()
                        .map(|(t, o)| (t / ts, o.drop_width / d))
                        .collect(),
                })
                .collect(),
            log: (false, false),
        });
    }
    panels.push(Panel {
        title: "cost against difference from the finest run".into(),
        x_label: "wall time [s]".into(),
        y_label: "max |W* - W*_finest| [-]".into(),
        series: fang_cases()
            .iter()
            .map(|(name, _)| Series {
                label: name.to_string(),
                points: rows
                    .iter()
                    .filter(|r| r.case == *name && r.w_diff > 0.0)
                    .map(|r| (r.wall_seconds, r.w_diff))
                    .collect(),
            })
            .collect(),
        log: (true, true),
    });
    line_panels(&out.join("drop.png"), &panels, 3, (1950, 620))?;
    Ok(md)
}

/// Particles per diameter giving about `n` particles in the disc (pi/4 ppd^2 = n).
pub fn ppd_for(n: f64) -> i64 {
    (4.0 * n / std::f64::consts::PI).sqrt().round() as i64
}

/// Peak resident set size of this process so far [bytes] (Linux `VmHWM`; `None` elsewhere).
pub fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// CPU time this process has used so far, all threads, user and system [s], from
/// `/proc/self/stat` (Linux; `None` elsewhere). On a machine shared with other work the wall
/// clock counts the time others hold the cores; CPU time does not.
pub fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15, in
    // USER_HZ = 100 ticks per second (fixed by the /proc ABI).
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = f.get(11)?.parse::<u64>().ok()? + f.get(12)?.parse::<u64>().ok()?;
    Some(ticks as f64 / 100.0)
}

/// One throughput measurement.
#[derive(Debug, Clone, Copy)]
pub struct Throughput {
    pub particles: usize,
    /// Particle-steps per wall-clock second.
    pub per_second: f64,
    /// CPU nanoseconds (all threads) per particle-step; NaN where CPU time is not available.
    pub cpu_ns: f64,
}

/// Measure particle-steps per second of `cfg` over `steps` steps on `threads` threads, starting
/// just before impact (the drop is set down one spacing above the plate so walls take part).
pub fn measure_throughput(
    cfg: &SceneConfig,
    steps: u64,
    threads: usize,
) -> Result<Throughput, Box<dyn std::error::Error>> {
    // The simulation runs in its own pool of `threads` workers.
    let mut cfg = cfg.clone();
    cfg.threads = threads as i64;
    let r: Result<Throughput, viscosph::simulation::SimError> = (|| {
        let mut sim = Simulation::new(cfg)?;
        // One tiny step to learn the stable step, then time `steps` steps.
        sim.advance_to(1e-12)?;
        let dt = sim.state().last_dt;
        let s0 = sim.state().step;
        let cpu0 = process_cpu_seconds();
        let start = std::time::Instant::now();
        sim.advance_to(sim.time() + dt * steps as f64 * 0.999)?;
        let secs = start.elapsed().as_secs_f64();
        let cpu = match (cpu0, process_cpu_seconds()) {
            (Some(a), Some(b)) => b - a,
            _ => f64::NAN,
        };
        let done = sim.state().step - s0;
        let n = sim.state().fluid.len();
        let ps = n as f64 * done as f64;
        Ok(Throughput {
            particles: n,
            per_second: ps / secs,
            cpu_ns: 1e9 * cpu / ps,
        })
    })();
    Ok(r?)
}

fn bench_throughput(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    // Sizes outer, ascending, so that the process's peak RSS after a run is that run's own peak
    // (less the RSS before the first run: the binary and the allocator's base). 10^6 runs the
    // Newtonian drop only, for a few steps (cost per particle-step, not a trajectory).
    let sizes: &[f64] = if quick {
        &[300.0, 1000.0]
    } else {
        &[1e3, 1e4, 1e5, 1e6]
    };
    let rss0 = peak_rss();
    let mut md = String::from(
        "| case | particles | threads | particle-steps/s (wall) | per core | CPU ns per \
         particle-step | peak RSS per particle [bytes] |\n|---|---|---|---|---|---|---|\n",
    );
    let mut csv = String::from(
        "case,particles,threads,particle_steps_per_second,cpu_ns_per_particle_step,peak_rss_bytes_per_particle\n",
    );
    let mut by: Vec<(String, usize, usize, f64, f64)> = Vec::new();
    for &n in sizes {
        for (name, base) in fang_cases() {
            if n > 2e5 && name != "newtonian" {
                continue;
            }
            let mut cfg = base.clone();
            let ppd = ppd_for(n);
            cfg.set("particles_per_diameter", Value::Integer(ppd))?;
            // Start one spacing above the plate, moving down: walls are in play from the first step.
            let h = 0.5 * cfg.drop_diameter + 1.5 * cfg.dx();
            cfg.set("initial_drop_height", Value::Real(h))?;
            let steps = ((2e6 / n) as u64).clamp(6, 400) / if quick { 4 } else { 1 };
            for threads in [1usize, 2] {
                eprintln!("bench throughput: {name}, {n:.0} particles, {threads} thread(s) ...");
                let t = measure_throughput(&cfg, steps.max(4), threads)?;
                let np = t.particles;
                let rss = match (rss0, peak_rss()) {
                    (Some(a), Some(b)) => b.saturating_sub(a) as f64 / np as f64,
                    _ => f64::NAN,
                };
                by.push((name.to_string(), np, threads, t.per_second, t.cpu_ns));
                writeln!(
                    csv,
                    "{name},{np},{threads},{:.4e},{:.1},{rss:.0}",
                    t.per_second, t.cpu_ns
                )?;
                writeln!(
                    md,
                    "| {name} | {np} | {threads} | {:.3e} | {:.3e} | {:.0} | {rss:.0} |",
                    t.per_second,
                    t.per_second / threads as f64,
                    t.cpu_ns
                )?;
            }
        }
    }
    writeln!(
        md,
        "\n| particles | threads | cost ratio Oldroyd-B / Newtonian (CPU time) |\n|---|---|---|"
    )?;
    for (name, np, th, _, cn) in &by {
        if name == "newtonian" {
            if let Some((_, _, _, _, co)) = by.iter().find(|(n2, np2, th2, _, _)| {
                n2 == "oldroyd_b" && *th2 == *th && (*np2 as f64 / *np as f64 - 1.0).abs() < 0.05
            }) {
                writeln!(md, "| {np} | {th} | {:.2} |", co / cn)?;
            }
        }
    }
    plot_throughput(out, &by)?;
    let (lib, chunks, fmu) = fmu_overhead(if quick { 0.04 } else { 0.16 })?;
    writeln!(
        md,
        "\n### FMU overhead: the default drop to t = {} s\n",
        if quick { 0.04 } else { 0.16 }
    )?;
    writeln!(
        md,
        "| path | wall time [s] | relative to one library call |\n|---|---|---|"
    )?;
    writeln!(md, "| library, one `advance_to` | {lib:.3} | 1.00 |")?;
    writeln!(
        md,
        "| library, `advance_to` + `outputs` every 1 ms | {chunks:.3} | {:.3} |",
        chunks / lib
    )?;
    writeln!(
        md,
        "| FMI layer, `fmi2DoStep` + `fmi2GetReal` of every output every 1 ms | {fmu:.3} | {:.3} |",
        fmu / lib
    )?;
    writeln!(csv, "fmu_overhead_library_one_call,,,{lib:.4}\nfmu_overhead_library_1ms,,,{chunks:.4}\nfmu_overhead_fmi_1ms,,,{fmu:.4}")?;
    std::fs::write(out.join("throughput.csv"), &csv)?;
    std::fs::write(out.join("throughput.md"), &md)?;
    Ok(md)
}

/// Cost per particle-step (CPU nanoseconds, all threads) against the particle count,
/// one line per case and thread count: flat means the cost grows linearly with the particles.
fn plot_throughput(
    out: &Path,
    by: &[(String, usize, usize, f64, f64)],
) -> Result<(), Box<dyn std::error::Error>> {
    let mut series = Vec::new();
    for (name, _) in fang_cases() {
        for threads in [1usize, 2] {
            let points: Vec<(f64, f64)> = by
                .iter()
                .filter(|(n, _, th, _, _)| n == name && *th == threads)
                .map(|(_, np, _, _, cpu_ns)| (*np as f64, *cpu_ns))
                .collect();
            if !points.is_empty() {
                series.push(Series {
                    label: format!("{name}, {threads} thread(s)"),
                    points,
                });
            }
        }
    }
    let panel = Panel {
        title: "cost per particle-step (WCSPH drop)".into(),
        x_label: "particles".into(),
        y_label: "CPU ns per particle-step".into(),
        series,
        log: (true, false),
    };
    line_panels(&out.join("throughput.png"), &[panel], 1, (900, 600))?;
    Ok(())
}

/// Wall times of the default drop to `t_end`: one library call, the library in 1 ms chunks with
/// the outputs read each time, and the FMI 2.0 instance layer (the code behind the exported
/// `fmi2*` functions: state machine, value-reference lookup, `fmi2DoStep`, `fmi2GetReal` of every
/// output) at a 1 ms communication step. The C ABI hop on top of that layer is a null check and a
/// `catch_unwind`, nanoseconds per call.
pub fn fmu_overhead(t_end: f64) -> Result<(f64, f64, f64), Box<dyn std::error::Error>> {
    use viscosph::fmi2::instance::Instance;
    let cfg = SceneConfig::default();
    let h = 1e-3;
    let n = (t_end / h).round() as usize;
    let start = std::time::Instant::now();
    let mut sim = Simulation::new(cfg.clone())?;
    sim.advance_to(t_end)?;
    let lib = start.elapsed().as_secs_f64();

    let start = std::time::Instant::now();
    let mut sim = Simulation::new(cfg)?;
    let mut sink = 0.0;
    for k in 1..=n {
        sim.advance_to(k as f64 * h)?;
        sink += sim.outputs().drop_width;
    }
    let chunks = start.elapsed().as_secs_f64();

    let vrs: Vec<u32> = viscosph::OUTPUTS
        .iter()
        .filter(|o| o.name != "particle_count")
        .map(|o| o.value_reference)
        .collect();
    let mut values = vec![0.0; vrs.len()];
    let start = std::time::Instant::now();
    let mut inst = Instance::new("bench", false, Box::new(|_, _, _| {}));
    let ok =
        |s: viscosph::fmi2::types::Status, what: &str| -> Result<(), Box<dyn std::error::Error>> {
            if s == viscosph::fmi2::types::Status::Ok {
                Ok(())
            } else {
                Err(format!("FMI layer: {what} answered {s:?}").into())
            }
        };
    ok(
        inst.setup_experiment(None, 0.0, Some(t_end)),
        "setup_experiment",
    )?;
    ok(
        inst.enter_initialization_mode(),
        "enter_initialization_mode",
    )?;
    ok(inst.exit_initialization_mode(), "exit_initialization_mode")?;
    for k in 0..n {
        ok(inst.do_step(k as f64 * h, h), "do_step")?;
        ok(inst.get_real(&vrs, &mut values), "get_real")?;
        sink += values[0];
    }
    let fmu = start.elapsed().as_secs_f64();
    assert!(sink.is_finite());
    Ok((lib, chunks, fmu))
}

/// One point of an accuracy-against-cost curve.
#[derive(Debug, Clone)]
pub struct AccuracyPoint {
    pub problem: String,
    pub scheme: String,
    pub resolution: String,
    pub wall_seconds: f64,
    pub error: f64,
}

fn bench_accuracy(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let mut points: Vec<AccuracyPoint> = Vec::new();
    let mut md = String::new();
    // Fang's drops: error of W*(t*) against a Richardson extrapolation from resolutions 1:2:4.
    let ppds: &[i64] = if quick { &[8, 16, 32] } else { &[20, 40, 80] };
    let t_star_end = if quick { 3.0 } else { 8.0 };
    writeln!(
        md,
        "### Fang drop: W*(t*) to t* = {t_star_end} against a Richardson extrapolation\n"
    )?;
    writeln!(md, "| scheme | case | particles/D | wall time [s] | max \\|W* - W*_extrapolated\\| | observed order |\n|---|---|---|---|---|---|")?;
    for scheme in built_schemes() {
        let cases: Vec<(&'static str, SceneConfig)> = fang_cases()
            .into_iter()
            .map(|(n, mut c)| {
                c.scheme = scheme;
                (n, c)
            })
            .collect();
        let rows = drop_convergence(&cases, ppds, t_star_end)?;
        let d = SceneConfig::default().drop_diameter;
        for (name, _) in &cases {
            let g: Vec<&DropRow> = rows.iter().filter(|r| r.case == *name).collect();
            if g.iter().any(|r| r.error.is_some()) {
                writeln!(
                    md,
                    "| {scheme} | {name} | - | - | broke down: {} | - |",
                    g.iter().find_map(|r| r.error.clone()).unwrap_or_default()
                )?;
                continue;
            }
            let p = observed_order(&g[0].series, &g[1].series, &g[2].series, d);
            // Extrapolated W* = W_f + (W_f - W_m) / (2^p - 1), with p at least 1 so a noisy
            // order estimate does not blow the correction up.
            let pe = p.max(1.0);
            let ext: Vec<(f64, Outputs)> = g[2]
                .series
                .iter()
                .zip(&g[1].series)
                .map(|((t, f), (_, m))| {
                    let mut o = *f;
                    o.drop_width =
                        f.drop_width + (f.drop_width - m.drop_width) / (2f64.powf(pe) - 1.0);
                    (*t, o)
                })
                .collect();
            for r in &g {
                let e = max_width_difference(&r.series, &ext, d);
                writeln!(
                    md,
                    "| {scheme} | {name} | {} | {:.2} | {:.4} | {:.2} |",
                    r.ppd, r.wall_seconds, e, p
                )?;
                points.push(AccuracyPoint {
                    problem: format!("drop_{name}"),
                    scheme: scheme.to_string(),
                    resolution: format!("{} particles/D", r.ppd),
                    wall_seconds: r.wall_seconds,
                    error: e,
                });
            }
        }
    }
    // Monaghan's elliptical drop: semi-major axis at t = 0.008 s against the exact ODE.
    let ell_ppds: &[i64] = if quick { &[12, 25] } else { &[25, 50, 100] };
    writeln!(
        md,
        "\n### Elliptical drop: semi-major axis at t = 0.008 s against the exact ODE\n"
    )?;
    writeln!(md, "| scheme | particles/diameter | particles | wall time [s] | semi-major axis error | product of semi-axes (extents / second moments) |\n|---|---|---|---|---|---|")?;
    let variants: Vec<(String, SceneConfig)> = built_schemes()
        .into_iter()
        .flat_map(|scheme| {
            let intervals: Vec<i64> = if scheme == SchemeKind::Pdri {
                vec![10, 20, 40]
            } else {
                vec![0]
            };
            intervals.into_iter().map(move |k| {
                let c = SceneConfig {
                    scene: viscosph::config::Scene::EllipticalDrop,
                    scheme,
                    density_reinit_interval: k,
                    ..Default::default()
                };
                let name = if scheme == SchemeKind::Pdri {
                    format!("pdri/{k}")
                } else {
                    scheme.to_string()
                };
                (name, c)
            })
        })
        .collect();
    for (name, base) in &variants {
        for &ppd in ell_ppds {
            let cfg = SceneConfig {
                particles_per_diameter: ppd,
                ..base.clone()
            };
            let opts = RunOptions {
                t_end: viscosph::scene::elliptical_drop::T_END,
                output_interval: viscosph::scene::elliptical_drop::T_END,
                ..RunOptions::for_scene(&cfg)
            };
            eprintln!("bench: elliptical drop, {name} at {ppd} ...");
            let r = run(&cfg, &opts)?;
            let Some(e) = r.elliptical else { continue };
            writeln!(
                md,
                "| {name} | {ppd} | {} | {:.2} | {:+.3} % | {:.4} / {:.4} |",
                r.particles,
                r.wall_seconds,
                100.0 * e.major_error,
                e.product,
                e.fitted_product
            )?;
            points.push(AccuracyPoint {
                problem: "elliptical_drop".into(),
                scheme: name.clone(),
                resolution: format!("{} particles", r.particles),
                wall_seconds: r.wall_seconds,
                error: e.major_error.abs(),
            });
        }
    }
    let mut csv = String::from("problem,scheme,resolution,wall_seconds,error\n");
    for p in &points {
        writeln!(
            csv,
            "{},{},{},{:.4},{:.6e}",
            p.problem, p.scheme, p.resolution, p.wall_seconds, p.error
        )?;
    }
    std::fs::write(out.join("accuracy.csv"), &csv)?;
    std::fs::write(out.join("accuracy.md"), &md)?;
    plot_accuracy(out, &points)?;
    Ok(md)
}

/// `accuracy.png` from the points of `accuracy.csv`: error against wall time per problem.
fn plot_accuracy(out: &Path, points: &[AccuracyPoint]) -> Result<(), Box<dyn std::error::Error>> {
    // Each problem once, in the order first met (the points come scheme by scheme).
    let mut problems: Vec<String> = Vec::new();
    for p in points {
        if !problems.contains(&p.problem) {
            problems.push(p.problem.clone());
        }
    }
    let panels: Vec<Panel> = problems
        .iter()
        .map(|prob| {
            let mut schemes: Vec<String> = points
                .iter()
                .filter(|p| &p.problem == prob)
                .map(|p| p.scheme.clone())
                .collect();
            schemes.dedup();
            Panel {
                title: format!("{prob}: error against cost"),
                x_label: "wall time [s]".into(),
                y_label: if prob.starts_with("drop") {
                    "max |W* - W*_extrapolated| [-]".into()
                } else {
                    "|semi-major axis error| [-]".into()
                },
                series: schemes
                    .iter()
                    .map(|s| Series {
                        label: s.clone(),
                        points: points
                            .iter()
                            .filter(|p| &p.problem == prob && &p.scheme == s && p.error > 0.0)
                            .map(|p| (p.wall_seconds, p.error))
                            .collect(),
                    })
                    .collect(),
                log: (true, true),
            }
        })
        .collect();
    panel_grid(
        &out.join("accuracy.png"),
        &panels,
        panels.len().min(3),
        (600, 500),
    )?;
    Ok(())
}

/// Redraw the PNGs that can be drawn from the CSV files in `out` without running anything
/// (today `accuracy.png` from `accuracy.csv`), e.g. after a change of the plot style.
fn bench_replot(out: &Path) -> Result<String, Box<dyn std::error::Error>> {
    let path = out.join("accuracy.csv");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut points = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != 5 {
            return Err(format!("{}: bad row '{line}'", path.display()).into());
        }
        points.push(AccuracyPoint {
            problem: f[0].into(),
            scheme: f[1].into(),
            resolution: f[2].into(),
            wall_seconds: f[3].parse()?,
            error: f[4].parse()?,
        });
    }
    plot_accuracy(out, &points)?;
    Ok(format!("redrew {}", out.join("accuracy.png").display()))
}

/// Fang's drop with each rheology in `RHEOLOGIES` (model parameters at their defaults).
pub fn rheology_cases() -> Vec<(RheologyKind, SceneConfig)> {
    RHEOLOGIES
        .iter()
        .filter_map(|(n, _)| RheologyKind::parse(n))
        .map(|r| {
            let c = SceneConfig {
                rheology: r,
                ..Default::default()
            };
            (r, c)
        })
        .collect()
}

/// Fang's drop (De = 1, beta = 0.1) with every rheology under every scheme the solver builds
/// (issue 11: ISPH in the rheology benchmark like the other schemes): one table with a scheme
/// column, one CSV, and one W*(t*)/H*(t*) figure per scheme (`rheologies_<scheme>.png`, like
/// King & Lind 2021 Fig. 16).
fn bench_rheologies(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let ppd = if quick { 12 } else { 30 };
    let mut md = String::from("| scheme | rheology | first peak W* | t* of peak | W* at t* = 8 | H* at t* = 8 | max tr(A) | wall time [s] | breakdown |\n|---|---|---|---|---|---|---|---|---|\n");
    let mut csv = String::from("scheme,rheology,time,t_star,w_star,h_star\n");
    for scheme in built_schemes() {
        let mut runs = Vec::new();
        for (r, mut c) in rheology_cases() {
            c.particles_per_diameter = ppd;
            c.scheme = scheme;
            let opts = RunOptions::for_scene(&c);
            eprintln!("bench rheologies: {scheme} {r} ...");
            let res = run(&c, &opts)?;
            let ts = time_scale(&c);
            let d = c.drop_diameter;
            let w: Vec<(f64, f64)> = res
                .series
                .iter()
                .map(|(t, o)| (t / ts, o.drop_width / d))
                .collect();
            let (peak_w, peak_t) = match first_peak(&w) {
                Some((t, w)) => (format!("{w:.3}"), format!("{t:.2}")),
                None => ("none (keeps spreading)".to_string(), "-".to_string()),
            };
            let last = res.series.last().expect("series").1;
            writeln!(
                md,
                "| {scheme} | {r} | {peak_w} | {peak_t} | {:.3} | {:.3} | {} | {:.2} | {} |",
                last.drop_width / d,
                last.drop_height / d,
                res.max_trace_text(),
                res.wall_seconds,
                res.error_text()
            )?;
            for (t, o) in &res.series {
                writeln!(
                    csv,
                    "{scheme},{r},{t:.6e},{:.4},{:.5},{:.5}",
                    t / ts,
                    o.drop_width / d,
                    o.drop_height / d
                )?;
            }
            let label = match res.error {
                Some(_) => format!("{r} (broke down)"),
                None => r.to_string(),
            };
            runs.push((label, res.series));
        }
        let cfg = SceneConfig {
            scheme,
            ..Default::default()
        };
        let refs: Vec<(String, &[(f64, Outputs)])> =
            runs.iter().map(|(n, s)| (n.clone(), &s[..])).collect();
        crate::run::plot_width_height(&out.join(format!("rheologies_{scheme}.png")), &cfg, &refs)?;
    }
    std::fs::write(out.join("rheologies.csv"), &csv)?;
    std::fs::write(out.join("rheologies.md"), &md)?;
    Ok(md)
}

/// The first spreading peak of W*: the first point, once the curve has risen 1 % above its
/// start, after which the curve falls by 1 % of it before it rises above it again (a retraction,
/// not a wiggle of one particle spacing). `None` if the drop never retracts (a Newtonian drop
/// keeps spreading): its largest W* is then its last, which is no peak.
pub fn first_peak(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let start = points.first()?.1;
    for (i, p) in points.iter().enumerate() {
        if p.1 <= 1.01 * start {
            continue;
        }
        for q in &points[i + 1..] {
            if q.1 > p.1 {
                break;
            }
            if q.1 < 0.99 * p.1 {
                return Some(*p);
            }
        }
    }
    None
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

/// The sections of the report: (title, command, markdown file, PNG files) from `results`.
const REPORT_SECTIONS: &[(&str, &str, &str, &[&str])] = &[
    (
        "Accuracy against cost",
        "viscosph bench accuracy",
        "accuracy.md",
        &["accuracy.png"],
    ),
    (
        "Fang's drops at 20/40/80 particles per diameter",
        "viscosph bench drop",
        "drop.md",
        &["drop.png"],
    ),
    (
        "Throughput",
        "viscosph bench throughput",
        "throughput.md",
        &["throughput.png"],
    ),
    (
        "Stability maps",
        "viscosph bench stability",
        "stability.md",
        &[
            "stability_de_wcsph.png",
            "stability_de_pdri.png",
            "stability_de_isph.png",
            "stability_beta.png",
            "stability_inclination.png",
            "stability_velocity.png",
            "stability_resolution.png",
        ],
    ),
    (
        "Every rheology on Fang's drop",
        "viscosph bench rheologies",
        "rheologies.md",
        &[
            "rheologies_wcsph.png",
            "rheologies_pdri.png",
            "rheologies_isph.png",
        ],
    ),
    (
        "Channel: start-up Poiseuille flow (King & Lind section IV.A)",
        "viscosph bench channel",
        "channel.md",
        &[
            "channel_accuracy.png",
            "channel_wi.png",
            "channel_nonlinear.png",
        ],
    ),
    (
        "The buckling jet (King & Lind section IV.D)",
        "viscosph bench jet",
        "jet.md",
        &[],
    ),
    (
        "ISPH (King & Lind 2021) on their Newtonian Re = 4 drop (issue 11)",
        "nice -n 10 viscosph bench isph",
        "isph.md",
        &[],
    ),
    (
        "PySPH side by side",
        "python3 examples/compare_pysph.py",
        "pysph.md",
        &[],
    ),
];

fn bench_report(results: &Path, docs: &Path) -> Result<String, Box<dyn std::error::Error>> {
    let img_dir = docs.join("bench");
    std::fs::create_dir_all(&img_dir)?;
    let mut md = String::from("# ViscoSPH benchmarks\n\n");
    writeln!(md, "Generated by `viscosph bench report` from the results of the commands named in each section.\n")?;
    // The commit each section was measured on (written by the subcommand that measured it).
    let measured = |file: &str| {
        let f = results.join(file.replace(".md", ".commit"));
        std::fs::read_to_string(f)
            .ok()
            .map(|t| t.trim().to_string())
    };
    let mut commits: Vec<String> = REPORT_SECTIONS
        .iter()
        .filter_map(|(_, _, file, _)| measured(file))
        .collect();
    commits.sort();
    commits.dedup();
    writeln!(md, "- machine: {}", machine_description())?;
    writeln!(
        md,
        "- measured on commit: {}",
        if commits.is_empty() {
            "unknown".to_string()
        } else {
            commits.join(", ")
        }
    )?;
    writeln!(md, "- report assembled at commit: {}\n", git_commit())?;
    for (title, cmd, file, pngs) in REPORT_SECTIONS {
        writeln!(md, "## {title}\n\n`{cmd}`\n")?;
        if let Some(c) = measured(file) {
            writeln!(md, "Measured on commit {c}.\n")?;
        }
        match std::fs::read_to_string(results.join(file)) {
            Ok(t) => md.push_str(&t),
            Err(_) => writeln!(
                md,
                "_not run yet: `{cmd}` writes `{}`_",
                results.join(file).display()
            )?,
        }
        md.push('\n');
        for png in *pngs {
            let src = results.join(png);
            if src.exists() {
                std::fs::copy(&src, img_dir.join(png))?;
                writeln!(md, "![{png}](bench/{png})\n")?;
            }
        }
    }
    std::fs::write(docs.join("benchmarks.md"), &md)?;
    Ok(format!("wrote {}", docs.join("benchmarks.md").display()))
}

/// Options of `viscosph bench stability`.
#[derive(Args, Debug, Clone)]
pub struct StabilityArgs {
    /// Which part: the map of the largest stable De per scheme and rheology, the one-parameter
    /// sweeps of the Oldroyd-B drop, or both.
    #[arg(long, value_enum, default_value = "all")]
    pub part: StabilityPart,
    /// Particles per diameter of the De map and of the one-parameter sweeps (the issue asks for
    /// 40 or finer: at 20 every case was stable up to the largest De tried, which measures
    /// little).
    #[arg(long, default_value_t = 40)]
    pub resolution: i64,
    /// Only these one-parameter sweeps (comma-separated: beta, inclination, velocity,
    /// resolution); default all. Lets the sweeps run as separate processes side by side.
    #[arg(long, value_delimiter = ',')]
    pub sweeps: Vec<String>,
    /// Only these schemes (comma-separated); default every scheme the solver builds.
    #[arg(long, value_delimiter = ',')]
    pub schemes: Vec<String>,
}

/// The parts of `viscosph bench stability`.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum StabilityPart {
    All,
    De,
    Sweeps,
}

/// How one stability run ended.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub stable: bool,
    /// t* of the breakdown.
    pub t_star: Option<f64>,
    pub cause: Option<String>,
    pub wall_seconds: f64,
}

/// Run a drop to `t_star_end` and classify it; configuration errors count as "not run" (None).
pub fn classify(cfg: &SceneConfig, t_star_end: f64) -> Option<Outcome> {
    cfg.validate().ok()?;
    let ts = time_scale(cfg);
    let start = std::time::Instant::now();
    let mut sim = Simulation::new(cfg.clone()).ok()?;
    let r = sim.advance_to(t_star_end * ts);
    let wall_seconds = start.elapsed().as_secs_f64();
    Some(match r {
        Ok(()) => Outcome {
            stable: true,
            t_star: None,
            cause: None,
            wall_seconds,
        },
        Err(e) => {
            let (t, cause) = match &e {
                viscosph::simulation::SimError::Breakdown { time, cause, .. } => {
                    (Some(time / ts), cause.clone())
                }
                other => (None, other.to_string()),
            };
            Outcome {
                stable: false,
                t_star: t,
                cause: Some(cause),
                wall_seconds,
            }
        }
    })
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

/// The models with a relaxation time (a Deborah number to sweep).
pub fn elastic_rheologies() -> Vec<RheologyKind> {
    RHEOLOGIES
        .iter()
        .filter_map(|(n, _)| RheologyKind::parse(n))
        .filter(|r| !matches!(r, RheologyKind::Newtonian | RheologyKind::Cross))
        .collect()
}

fn bench_stability(
    args: &StabilityArgs,
    out: &Path,
    quick: bool,
) -> Result<String, Box<dyn std::error::Error>> {
    // A misspelt sweep name is an error before anything runs, not a silently missing table.
    const SWEEPS: [&str; 4] = ["beta", "inclination", "velocity", "resolution"];
    if let Some(n) = args.sweeps.iter().find(|n| !SWEEPS.contains(&n.as_str())) {
        return Err(format!("unknown sweep '{n}' (known: {})", SWEEPS.join(", ")).into());
    }
    let t_star_end = if quick { 3.0 } else { 8.0 };
    // The De map and the one-parameter sweeps run at `--resolution` (40 by default: at 20 ISPH
    // loses single particles at the contact line of Fang's drop, and every weakly compressible
    // case was stable, which measured little); the resolution sweep goes from 12 to 60.
    let ppd: i64 = if quick { 12 } else { args.resolution };
    let ppd_de = ppd;
    // Decades up to 10^5: at De >> 1 the polymer modulus eta_p / lambda is small and the drop
    // behaves like its solvent, so a scheme that survives 10^3 usually survives more; the ladder
    // goes on until a run breaks, and the table says what the largest value tried was.
    let des: Vec<f64> = if quick {
        vec![0.1, 1.0, 100.0]
    } else {
        vec![0.1, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5]
    };
    let schemes: Vec<SchemeKind> = if args.schemes.is_empty() {
        built_schemes()
    } else {
        args.schemes
            .iter()
            .map(|n| SchemeKind::parse(n).ok_or_else(|| format!("unknown scheme '{n}'")))
            .collect::<Result<_, _>>()?
    };
    let mut csv = String::from(
        "sweep,scheme,rheology,parameter,value,stable,breakdown_t_star,cause,wall_seconds\n",
    );
    let mut md = String::new();
    let base = |scheme: SchemeKind, rheo: RheologyKind, ppd: i64| SceneConfig {
        scheme,
        rheology: rheo,
        particles_per_diameter: ppd,
        ..Default::default()
    };
    let record = |csv: &mut String,
                  sweep: &str,
                  c: &SceneConfig,
                  param: &str,
                  value: f64,
                  o: &Option<Outcome>| {
        let (st, t, cause, w) = match o {
            Some(o) => (
                if o.stable { "stable" } else { "broken" },
                o.t_star.map(|t| format!("{t:.3}")).unwrap_or_default(),
                o.cause.clone().unwrap_or_default().replace('"', "'"),
                o.wall_seconds,
            ),
            None => (
                "not_run",
                String::new(),
                "refused by validation".into(),
                0.0,
            ),
        };
        let _ = writeln!(
            csv,
            "{sweep},{},{},{param},{value},{st},{t},\"{cause}\",{w:.3}",
            c.scheme, c.rheology
        );
    };

    // 1. Deborah number De = lambda V / D, per scheme and elastic rheology (beta = 0.1), in
    // ascending decades until the first breakdown (the larger values are then not run).
    if args.part != StabilityPart::Sweeps {
        writeln!(md, "### Largest stable De (drop to t* = {t_star_end}, {ppd_de} particles per diameter, beta = 0.1)\n")?;
        writeln!(
            md,
            "De in decades from {} to {}, stopping at the first breakdown; \"none\" in the last \
             column means every value tried was stable, so the limit lies above the largest \
             tried.\n",
            des[0],
            des[des.len() - 1]
        )?;
        writeln!(
            md,
            "| scheme | rheology | largest stable De | largest tried | first failure | wall time [s] |\n|---|---|---|---|---|---|"
        )?;
        for &scheme in &schemes {
            let rheos = elastic_rheologies();
            let mut cells = Vec::new();
            for &rheo in &rheos {
                let mut row = Vec::new();
                let mut best: Option<f64> = None;
                let mut tried = 0.0;
                let mut wall = 0.0;
                let mut first_fail = String::from("none");
                for &de in &des {
                    if first_fail != "none" {
                        row.push(None);
                        continue;
                    }
                    let mut c = base(scheme, rheo, ppd_de);
                    c.relaxation_time = de * c.drop_diameter / c.impact_velocity;
                    eprintln!("bench stability: {scheme} {rheo} De = {de} ...");
                    let o = classify(&c, t_star_end);
                    record(&mut csv, "deborah", &c, "De", de, &o);
                    // Row by row, so a sweep of hours stopped early keeps what it measured.
                    std::fs::write(out.join("stability.csv"), &csv)?;
                    row.push(o.as_ref().map(|o| o.stable));
                    match &o {
                        Some(o) if o.stable => {
                            best = Some(de);
                            tried = de;
                            wall += o.wall_seconds;
                        }
                        Some(o) => {
                            tried = de;
                            wall += o.wall_seconds;
                            first_fail = format!(
                                "De = {de}: {} (t* = {})",
                                o.cause.clone().unwrap_or_default(),
                                o.t_star.map(|t| format!("{t:.2}")).unwrap_or_default()
                            )
                        }
                        None => {}
                    }
                }
                writeln!(
                    md,
                    "| {scheme} | {rheo} | {} | {tried} | {first_fail} | {wall:.0} |",
                    best.map(|d| d.to_string())
                        .unwrap_or(format!("< {}", des[0]))
                )?;
                cells.push(row);
            }
            status_grid(
                &out.join(format!("stability_de_{scheme}.png")),
                &format!(
                    "{scheme}, {ppd_de} per diameter: stable (green) / broken (red) / not run (grey) against De"
                ),
                "De = lambda V / D [-]",
                "rheology",
                &des.iter().map(|d| format!("{d:e}")).collect::<Vec<_>>(),
                &rheos.iter().map(|r| r.to_string()).collect::<Vec<_>>(),
                &cells,
            )?;
        }
    }

    // 2. One-parameter sweeps of the Oldroyd-B drop (De = 1) per scheme.
    if args.part == StabilityPart::De {
        std::fs::write(out.join("stability.csv"), &csv)?;
        std::fs::write(out.join("stability.md"), &md)?;
        return Ok(md);
    }
    type Setter = fn(&mut SceneConfig, f64);
    // Each sweep runs from the mildest value to the most severe and, per scheme, stops at the
    // first breakdown (the rest are "not run"), like the De ladder: a sweep in which everything
    // is stable measures only that the limit lies beyond the largest value tried, so the ranges
    // reach far (impact at 50 m/s, a plate at 70 degrees) and the table names the largest tried.
    // viscosity_ratio ends at its physical end, 0 (UCM); the resolution sweep runs every value
    // (coarser is not simply more severe) and its coarsest values are where it can fail.
    let sweeps: Vec<(&str, &str, Vec<f64>, Setter, bool)> = vec![
        (
            "beta",
            "viscosity_ratio",
            vec![0.5, 0.1, 0.05, 0.01, 0.0],
            |c, v| c.viscosity_ratio = v,
            true,
        ),
        (
            "inclination",
            "plate_inclination [deg]",
            // From 75 degrees the default drop (centre 2 D above the impact point) starts
            // within a particle spacing of the plate: validation refuses it.
            vec![0.0, 15.0, 30.0, 45.0, 60.0, 70.0],
            |c, v| c.plate_inclination = v,
            true,
        ),
        (
            "velocity",
            "impact_velocity [m/s]",
            vec![0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0],
            |c, v| {
                // keep De = 1 as V changes
                c.relaxation_time = c.drop_diameter / v;
                c.impact_velocity = v;
            },
            true,
        ),
        (
            "resolution",
            "particles_per_diameter",
            vec![12.0, 16.0, 20.0, 30.0, 40.0, 60.0],
            |c, v| c.particles_per_diameter = v as i64,
            false,
        ),
    ];
    writeln!(
        md,
        "\n### One-parameter sweeps (Oldroyd-B, De = 1 unless swept, {ppd} particles per diameter unless swept, drop to t* = {t_star_end})\n"
    )?;
    for (name, label, values, set, stop_at_failure) in sweeps {
        debug_assert!(SWEEPS.contains(&name), "{name} missing from SWEEPS");
        if !args.sweeps.is_empty() && !args.sweeps.iter().any(|s| s == name) {
            continue;
        }
        let values: Vec<f64> = if quick {
            values.into_iter().take(2).collect()
        } else {
            values
        };
        let schemes = schemes.clone();
        let mut cells = Vec::new();
        let mut summary = String::new();
        writeln!(
            md,
            "| scheme | {label} | outcome | wall time [s] |\n|---|---|---|---|"
        )?;
        for &scheme in &schemes {
            let mut row = Vec::new();
            let mut stable_values = Vec::new();
            let mut tried = Vec::new();
            let mut first_fail: Option<String> = None;
            for &v in &values {
                if stop_at_failure && first_fail.is_some() {
                    row.push(None);
                    continue;
                }
                let mut c = base(scheme, RheologyKind::OldroydB, ppd);
                set(&mut c, v);
                eprintln!("bench stability: {scheme} {name} = {v} ...");
                let o = classify(&c, t_star_end);
                record(&mut csv, name, &c, label, v, &o);
                std::fs::write(out.join("stability.csv"), &csv)?;
                row.push(o.as_ref().map(|o| o.stable));
                let (desc, wall) = match &o {
                    Some(o) if o.stable => ("stable".to_string(), o.wall_seconds),
                    Some(o) => (
                        format!(
                            "broken at t* = {}: {}",
                            o.t_star.map(|t| format!("{t:.2}")).unwrap_or_default(),
                            o.cause.clone().unwrap_or_default()
                        ),
                        o.wall_seconds,
                    ),
                    None => ("refused by validation".into(), 0.0),
                };
                if let Some(o) = &o {
                    tried.push(v);
                    if o.stable {
                        stable_values.push(v);
                    } else if first_fail.is_none() {
                        first_fail = Some(format!("{v}"));
                    }
                }
                writeln!(md, "| {scheme} | {v} | {desc} | {wall:.0} |")?;
            }
            let list = |v: &[f64]| {
                v.iter()
                    .map(|x| x.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            writeln!(
                summary,
                "- {scheme}: stable at {}; {}",
                if stable_values.is_empty() {
                    "none".to_string()
                } else {
                    list(&stable_values)
                },
                match &first_fail {
                    Some(f) => format!("first breakdown at {f}"),
                    None => format!(
                        "no breakdown: every value tried ({}) was stable, the limit lies beyond",
                        list(&tried)
                    ),
                }
            )?;
            cells.push(row);
        }
        writeln!(md, "\n{summary}")?;
        status_grid(
            &out.join(format!("stability_{name}.png")),
            &format!(
                "Oldroyd-B drop, De = 1: stable (green) / broken (red) / not run (grey) against {label}"
            ),
            label,
            "scheme",
            &values.iter().map(|d| d.to_string()).collect::<Vec<_>>(),
            &schemes.iter().map(|s| s.to_string()).collect::<Vec<_>>(),
            &cells,
        )?;
    }
    std::fs::write(out.join("stability.csv"), &csv)?;
    std::fs::write(out.join("stability.md"), &md)?;
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_order_from_three_resolutions_recovers_the_power_law() {
        // Doubling resolutions: log2 of the ratio of differences.
        assert!((order_from_differences([20.0, 40.0, 80.0], 0.04, 0.01) - 2.0).abs() < 1e-9);
        // W/dr = 40, 80, 120 with an error 3 h^1.5 (h = 1/ppd): the differences alone give 1.5.
        let err = |n: f64| 3.0 * (1.0 / n).powf(1.5);
        let p = order_from_differences(
            [40.0, 80.0, 120.0],
            err(40.0) - err(80.0),
            err(80.0) - err(120.0),
        );
        assert!((p - 1.5).abs() < 1e-9, "{p}");
        // Differences that grow with resolution: a negative order; none at all: NaN.
        assert!(order_from_differences([20.0, 40.0, 80.0], 0.01, 0.02) < 0.0);
        assert!(order_from_differences([20.0, 40.0, 80.0], 0.01, 0.0).is_nan());
    }

    #[test]
    fn a_curve_that_keeps_rising_has_no_first_peak() {
        // A Newtonian drop: W* rises, with a wiggle smaller than 1 %, to its last value.
        let rising: Vec<(f64, f64)> = (0..50)
            .map(|k| {
                let t = k as f64 * 0.1;
                (t, 1.0 + t - if k == 20 { 0.005 } else { 0.0 })
            })
            .collect();
        assert_eq!(first_peak(&rising), None);
        // An Oldroyd-B drop: up to 2.1 at t* = 2.2, retracts to 1.7, spreads again past 2.1.
        let retracting: Vec<(f64, f64)> = (0..80)
            .map(|k| {
                let t = k as f64 * 0.1;
                let w = if t <= 2.2 {
                    1.0 + 0.5 * t
                } else if t <= 4.0 {
                    2.1 - 0.4 * (t - 2.2) / 1.8
                } else {
                    1.7 + 0.3 * (t - 4.0)
                };
                (t, w)
            })
            .collect();
        let (t, w) = first_peak(&retracting).unwrap();
        assert!((t - 2.2).abs() < 1e-9 && (w - 2.1).abs() < 1e-9, "{t} {w}");
        assert!(
            retracting.last().unwrap().1 > w,
            "the final value is larger: not the peak"
        );
    }

    #[test]
    fn ppd_for_hits_the_particle_count() {
        for n in [1e3, 1e4, 1e5] {
            let ppd = ppd_for(n) as f64;
            let got = std::f64::consts::FRAC_PI_4 * ppd * ppd;
            assert!((got / n - 1.0).abs() < 0.02, "{n} -> {got}");
        }
    }
}
