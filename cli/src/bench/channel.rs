//! `viscosph bench channel`: the start-up of plane Poiseuille flow (King & Lind 2021 section
//! IV.A) against its exact solutions, per scheme.
//!
//! Every case is King & Lind's non-dimensional channel: H = 1, rho = 1, eta0 = 1/Re,
//! g = 8/Re (so the Newtonian centre-line velocity U = rho g H^2 / (8 eta0) = 1), lambda = Wi,
//! periodic with period H. Three parts, each writing CSV, Markdown and a PNG into `--out`:
//!
//! * `accuracy` (a): Oldroyd-B, Re = Wi = 1, beta = 0.1 at 15/30/60 particles across (120 with
//!   `--full`): the L2 velocity error against Waters & King 1970 over time, its RMS over the run,
//!   the observed order and the wall time; error against cost on log axes, one line per scheme.
//! * `wi` (b): the Weissenberg sweeps of King & Lind Figs. 5 (Re = 1, 30 across) and 6
//!   (Re = 0.01, 15 across), beta = 0.1: Wi = 1, 2, 5, 10, 20, 50, 85, 100, 200, 500, 1000
//!   upwards until a run fails (below 1 downwards until one passes). A run **passes** when it
//!   reaches the end time without a breakdown and its centre-line velocity stays within 5 % of
//!   Waters & King's at every output time, 5 % of max(U, |u_exact(t)|): relative during the
//!   overshoots (up to 8.5 U at Re = 0.01), never tighter than 0.05 U where the exact velocity
//!   passes through small values. A run is stopped at the first output that is off by more. The
//!   largest passing Wi per scheme is the table's "largest stable Wi".
//! * `nonlinear` (c): the steady profiles of Oldroyd-B, FENE-CR, FENE-P, linear and exponential
//!   PTT and Giesekus (Re = Wi = 1, beta = 0.1, the models' default parameters) against the
//!   steady analytic solutions of [`viscosph_reference::analytic::steady_shear`]: relative L2
//!   errors of u, tau_p,xy and tau_p,xx over the particles.
//!
//! The default run is cut short against King & Lind's end times (measured on two cores shared
//! with other builds, load average 12-15: 9, 23 and 12 minutes of wall time for the three parts):
//! the accuracy runs end at t = 0.6 H/U (through the first overshoot, where the error is largest),
//! the sweeps at t = 3 (Fig. 5: past the second overshoot at Wi = 1) and t = 0.2 H/U (Fig. 6:
//! past the first overshoot). `--full` runs King & Lind's end times (t = 5 for the accuracy,
//! t = 20 for the sweeps) and 120 across; its cost is dominated by the explicit viscous
//! time-step limit, dt ~ 0.15 h^2 rho / eta0 (Fang 2006 eq. 53): Fig. 6 at Re = 0.01 takes 1.3
//! million steps to t = 20 (about 20 minutes per Wi on a busy core). `--figure 5` or `6` runs
//! one sweep only.
//!
//! Schemes are the lines of [`variants`]: adding a scheme (ISPH, in its Lagrangian and Eulerian
//! frames) is adding a line there.

use crate::bench::{case, convergence_order, machine_description};
use crate::io::plot::{line_panels, panel_grid, Panel, Series};
use clap::{Args, ValueEnum};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use viscosph::config::Value;
use viscosph::rheology::{AnyRheology, Rheology};
use viscosph::scene::channel::centreline_velocity;
use viscosph::scene::SceneConfig;
use viscosph::simulation::{SimError, Simulation};
use viscosph_reference::analytic::waters_king::WatersKing;
use viscosph_reference::analytic::{self, SteadyChannel};

type BenchResult<T> = Result<T, Box<dyn std::error::Error>>;

/// Which part of the channel benchmark to run.
#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    All,
    Accuracy,
    Wi,
    Nonlinear,
}

#[derive(Args, Debug, Clone)]
pub struct ChannelArgs {
    /// King & Lind's end times (t = 20 H/U for the sweeps) and 120 particles across: hours.
    #[arg(long)]
    pub full: bool,
    /// Run one part only (the Markdown summary gathers every part found in --out).
    #[arg(long, value_enum, default_value = "all")]
    pub part: Part,
    /// The Wi sweep of King & Lind's Fig. 5 (Re = 1) or Fig. 6 (Re = 0.01) only; both if absent.
    #[arg(long, value_parser = clap::value_parser!(u8).range(5..=6))]
    pub figure: Option<u8>,
    /// Only the schemes whose label starts with this text (e.g. `isph`, `wcsph`); all if absent.
    #[arg(long)]
    pub schemes: Option<String>,
}

/// The `--schemes` filter of this run (set once by [`main`]).
static SCHEMES: std::sync::OnceLock<Option<String>> = std::sync::OnceLock::new();

fn selected(v: &Variant) -> bool {
    SCHEMES
        .get()
        .and_then(|s| s.as_deref())
        .is_none_or(|p| v.label.starts_with(p))
}

/// A scheme as the channel benchmark runs it: a label and the parameters that select it.
pub struct Variant {
    pub label: &'static str,
    pub pairs: Vec<(&'static str, Value)>,
}

fn text(s: &str) -> Value {
    Value::Text(s.into())
}

/// The schemes compared, one line each. Fang's artificial stress is lowered to epsilon = 0.1 for
/// the weakly compressible schemes: its rotated principal-stress term has a shear component that
/// slows a channel flow (steady centre line 1.13 U at Fang's 0.5), while without it the wall
/// layers turn unstable after 11 H/U (docs/methods.md, the channel). Variants that the solver
/// refuses (a scheme not built yet) are reported as such and skipped.
pub fn variants() -> Vec<Variant> {
    let v = |label, pairs: &[(&'static str, Value)]| Variant {
        label,
        pairs: pairs.to_vec(),
    };
    let all = vec![
        v(
            "wcsph",
            &[
                ("scheme", text("wcsph")),
                ("artificial_stress_epsilon", Value::Real(0.1)),
            ],
        ),
        v(
            "pdri",
            &[
                ("scheme", text("pdri")),
                ("artificial_stress_epsilon", Value::Real(0.1)),
            ],
        ),
        v(
            "isph/lagrangian",
            &[("scheme", text("isph")), ("isph_frame", text("lagrangian"))],
        ),
        v(
            "isph/eulerian",
            &[("scheme", text("isph")), ("isph_frame", text("eulerian"))],
        ),
    ];
    all.into_iter().filter(selected).collect()
}

/// The schemes of the Wi sweeps and the steady profiles: [`variants`] and, for the schemes with
/// Fang's artificial stress,
/// the same without it (epsilon = 0), since the stress term is what keeps the wall layers stable
/// but also biases the steady flow (measured at Re = 5, Wi = 0.5: centre line 1.028 U with
/// epsilon = 0.1, 1.007 U without).
pub fn sweep_variants() -> Vec<Variant> {
    let mut all = variants();
    let without: Vec<Variant> = all
        .iter()
        .filter(|v| v.pairs.iter().any(|p| p.0 == "artificial_stress_epsilon"))
        .map(|v| Variant {
            label: match v.label {
                "wcsph" => "wcsph, eps = 0",
                "pdri" => "pdri, eps = 0",
                other => other,
            },
            pairs: v
                .pairs
                .iter()
                .map(|(k, x)| {
                    if *k == "artificial_stress_epsilon" {
                        (*k, Value::Real(0.0))
                    } else {
                        (*k, x.clone())
                    }
                })
                .collect(),
        })
        .collect();
    all.extend(without);
    all
}

/// King & Lind's channel at (Re, Wi, beta) with `across` particles across the width, the given
/// rheology, and a sound speed of 10 times `u_peak` (the largest speed the flow reaches, for
/// density variations of about 1 %).
pub fn kl_channel(
    variant: &Variant,
    rheology: &str,
    re: f64,
    wi: f64,
    beta: f64,
    across: i64,
    u_peak: f64,
) -> SceneConfig {
    let mut pairs: Vec<(&str, Value)> = vec![
        ("scene", text("channel")),
        ("rheology", text(rheology)),
        ("channel_width", Value::Real(1.0)),
        ("density", Value::Real(1.0)),
        ("viscosity", Value::Real(1.0 / re)),
        ("body_force", Value::Real(8.0 / re)),
        ("viscosity_ratio", Value::Real(beta)),
        ("relaxation_time", Value::Real(wi)),
        ("particles_per_diameter", Value::Integer(across)),
        ("sound_speed", Value::Real(10.0 * u_peak.max(1.0))),
    ];
    pairs.extend(variant.pairs.iter().cloned());
    case(&pairs)
}

/// Largest centre-line velocity of Waters & King's solution on [0, t_end] (over its extrema and
/// the end value).
pub fn analytic_peak(wk: &WatersKing, t_end: f64) -> f64 {
    wk.centreline_extrema(t_end)
        .iter()
        .filter(|e| e.maximum)
        .map(|e| e.velocity)
        .fold(wk.centreline_velocity(t_end), f64::max)
}

/// RMS over the particles of |v_i - (u(y_i, t), 0)|, in units of U (= 1 here).
pub fn l2_velocity_error(sim: &Simulation, wk: &WatersKing) -> f64 {
    let st = sim.state();
    let f = &st.fluid;
    if f.is_empty() {
        return f64::NAN;
    }
    let sum: f64 =
        f.x.iter()
            .zip(&f.v)
            .map(|(x, v)| (v.x - wk.velocity(x.y, st.time)).powi(2) + v.y * v.y)
            .sum();
    (sum / f.len() as f64).sqrt() / wk.velocity_scale()
}

/// The breakdown's time and cause, or the error's text.
fn failure(e: &SimError) -> (Option<f64>, String) {
    match e {
        SimError::Breakdown { time, cause, .. } => (Some(*time), cause.clone()),
        other => (None, other.to_string()),
    }
}

pub fn main(args: &ChannelArgs, out: &Path, quick: bool) -> BenchResult<String> {
    SCHEMES.get_or_init(|| args.schemes.clone());
    let parts = match args.part {
        Part::All => vec![Part::Accuracy, Part::Wi, Part::Nonlinear],
        p => vec![p],
    };
    for p in parts {
        let md = match p {
            Part::Accuracy => accuracy(out, quick, args.full)?,
            Part::Wi => wi_sweeps(out, quick, args.full, args.figure)?,
            Part::Nonlinear => nonlinear(out, quick, args.full)?,
            Part::All => unreachable!("expanded above"),
        };
        let name = match p {
            Part::Accuracy => "channel_accuracy.md",
            Part::Wi => "channel_wi.md",
            _ => "channel_nonlinear.md",
        };
        let md = format!(
            "{md}\n_Machine: {}; measured with `{}`._\n",
            machine_description(),
            command(p, quick, args.full, args.figure, args.schemes.as_deref())
        );
        std::fs::write(out.join(name), md)?;
    }
    // The report's section: every part found in `out`, in order.
    let mut all = String::new();
    for name in [
        "channel_accuracy.md",
        "channel_wi.md",
        "channel_nonlinear.md",
    ] {
        if let Ok(t) = std::fs::read_to_string(out.join(name)) {
            all.push_str(&t);
            all.push('\n');
        }
    }
    std::fs::write(out.join("channel.md"), &all)?;
    Ok(all)
}

fn command(p: Part, quick: bool, full: bool, figure: Option<u8>, schemes: Option<&str>) -> String {
    let mut c = String::from("nice -n 10 viscosph bench channel");
    match p {
        Part::Accuracy => c.push_str(" --part accuracy"),
        Part::Wi => c.push_str(" --part wi"),
        Part::Nonlinear => c.push_str(" --part nonlinear"),
        Part::All => {}
    }
    if full {
        c.push_str(" --full");
    }
    if let (Part::Wi, Some(f)) = (p, figure) {
        write!(c, " --figure {f}").unwrap_or(());
    }
    if let Some(s) = schemes {
        write!(c, " --schemes {s}").unwrap_or(());
    }
    if quick {
        c.push_str(" --quick");
    }
    c
}

// ---------------------------------------------------------------------------------------------
// (a) accuracy and convergence

struct AccuracyRun {
    scheme: &'static str,
    across: i64,
    particles: usize,
    steps: u64,
    wall: f64,
    rms: f64,
    max: f64,
    end: f64,
    failed: Option<String>,
    series: Vec<(f64, f64, f64, f64)>,
}

fn accuracy(out: &Path, quick: bool, full: bool) -> BenchResult<String> {
    let (re, wi, beta) = (1.0, 1.0, 0.1);
    let (t_end, sample, resolutions): (f64, f64, Vec<i64>) = if quick {
        (0.2, 0.05, vec![10, 15])
    } else if full {
        (5.0, 0.02, vec![15, 30, 60, 120])
    } else {
        (0.6, 0.02, vec![15, 30, 60])
    };
    let wk = WatersKing::new(analytic::Channel::from_re_wi(re, wi, beta))?;
    let peak = analytic_peak(&wk, t_end);
    let mut runs: Vec<AccuracyRun> = Vec::new();
    let mut skipped = Vec::new();
    for v in variants() {
        for &n in &resolutions {
            let cfg = kl_channel(&v, "oldroyd_b", re, wi, beta, n, peak);
            let mut sim = match Simulation::new(cfg) {
                Ok(s) => s,
                Err(e) => {
                    skipped.push(format!("{}: {e}", v.label));
                    break;
                }
            };
            let start = Instant::now();
            let mut series = Vec::new();
            let mut failed = None;
            let samples = (t_end / sample).round() as usize;
            for k in 1..=samples {
                if let Err(e) = sim.advance_to(k as f64 * sample) {
                    let (t, cause) = failure(&e);
                    failed = Some(format!("t = {:.3}: {cause}", t.unwrap_or(f64::NAN)));
                    break;
                }
                let st = sim.state();
                let uc = centreline_velocity(&st.fluid, 1.0, 1.0 / n as f64);
                series.push((
                    st.time,
                    l2_velocity_error(&sim, &wk),
                    uc,
                    wk.centreline_velocity(st.time),
                ));
            }
            let wall = start.elapsed().as_secs_f64();
            let errs: Vec<f64> = series.iter().map(|s| s.1).collect();
            let rms = (errs.iter().map(|e| e * e).sum::<f64>() / errs.len().max(1) as f64).sqrt();
            eprintln!(
                "channel accuracy: {} {n} across: L2 rms {rms:.4e} in {wall:.1} s{}",
                v.label,
                failed
                    .as_deref()
                    .map(|f| format!(" ({f})"))
                    .unwrap_or_default()
            );
            runs.push(AccuracyRun {
                scheme: v.label,
                across: n,
                particles: sim.state().fluid.len(),
                steps: sim.state().step,
                wall,
                rms,
                max: errs.iter().copied().fold(0.0, f64::max),
                end: errs.last().copied().unwrap_or(f64::NAN),
                failed,
                series,
            });
        }
    }
    // CSV: one row per run, and the error histories.
    let mut csv = String::from(
        "scheme,across,particles,steps,wall_seconds,l2_rms,l2_max,l2_end,order_rms,failure\n",
    );
    let mut hist = String::from(
        "scheme,across,time,l2_velocity_error,centreline_velocity,centreline_velocity_exact\n",
    );
    let mut md = format!(
        "### (a) Oldroyd-B start-up against Waters & King (Re = Wi = 1, beta = 0.1)\n\n\
         L2 = RMS over the particles of |v - (u_exact(y, t), 0)| / U, sampled every {sample} H/U \
         to t = {t_end} H/U; \"RMS in time\" is the RMS of those samples, the observed order is \
         taken from it between successive resolutions. Centre line: the first overshoot of the \
         exact solution, {:.4} U at t = {:.3} H/U.\n\n\
         | scheme | across | particles | steps | wall time [s] | L2 RMS in time | L2 max | L2 at end | observed order |\n\
         |---|---|---|---|---|---|---|---|---|\n",
        peak,
        wk.centreline_extrema(t_end)
            .first()
            .map_or(f64::NAN, |e| e.time)
    );
    for (k, r) in runs.iter().enumerate() {
        let prev = k
            .checked_sub(1)
            .map(|j| &runs[j])
            .filter(|p| p.scheme == r.scheme && p.failed.is_none() && r.failed.is_none());
        // Both errors are against the exact solution (an infinite resolution).
        let ord = prev.map(|p| {
            let inf = f64::INFINITY;
            convergence_order(p.rms, [p.across as f64, inf], r.rms, [r.across as f64, inf])
        });
        writeln!(
            csv,
            "{},{},{},{},{:.3},{:.6e},{:.6e},{:.6e},{},{}",
            r.scheme,
            r.across,
            r.particles,
            r.steps,
            r.wall,
            r.rms,
            r.max,
            r.end,
            ord.map(|o| format!("{o:.3}")).unwrap_or_default(),
            r.failed.clone().unwrap_or_default().replace(',', ";")
        )?;
        writeln!(
            md,
            "| {} | {} | {} | {} | {:.1} | {:.4e} | {:.4e} | {:.4e} | {}{} |",
            r.scheme,
            r.across,
            r.particles,
            r.steps,
            r.wall,
            r.rms,
            r.max,
            r.end,
            ord.map(|o| format!("{o:.2}")).unwrap_or_else(|| "-".into()),
            r.failed
                .as_deref()
                .map(|f| format!(" (broke: {f})"))
                .unwrap_or_default()
        )?;
        for s in &r.series {
            writeln!(
                hist,
                "{},{},{:.6},{:.6e},{:.6e},{:.6e}",
                r.scheme, r.across, s.0, s.1, s.2, s.3
            )?;
        }
    }
    for s in &skipped {
        writeln!(md, "\nNot run: {s}")?;
    }
    std::fs::write(out.join("channel_accuracy.csv"), csv)?;
    std::fs::write(out.join("channel_accuracy_series.csv"), hist)?;
    let schemes: Vec<&str> = dedup(runs.iter().map(|r| r.scheme));
    let cost = Panel {
        title: "L2 velocity error against cost".into(),
        x_label: "wall time [s]".into(),
        y_label: "L2 error, RMS in time [U]".into(),
        series: schemes
            .iter()
            .map(|s| Series {
                label: s.to_string(),
                points: runs
                    .iter()
                    .filter(|r| r.scheme == *s && r.failed.is_none())
                    .map(|r| (r.wall, r.rms))
                    .collect(),
            })
            .collect(),
        log: (true, true),
    };
    let history = Panel {
        title: "L2 velocity error over time".into(),
        x_label: "t [H/U]".into(),
        y_label: "L2 error [U]".into(),
        series: runs
            .iter()
            .map(|r| Series {
                label: format!("{} {}", r.scheme, r.across),
                points: r.series.iter().map(|s| (s.0, s.1)).collect(),
            })
            .collect(),
        log: (false, true),
    };
    line_panels(
        &out.join("channel_accuracy.png"),
        &[cost, history],
        2,
        (1400, 600),
    )?;
    Ok(md)
}

fn dedup<'a>(it: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let mut v: Vec<&str> = Vec::new();
    for s in it {
        if !v.contains(&s) {
            v.push(s);
        }
    }
    v
}

// ---------------------------------------------------------------------------------------------
// (b) Weissenberg sweeps

/// The sweep's Weissenberg numbers upwards from 1 (King & Lind's 85 among them) and downwards
/// below 1, for a scheme that fails at Wi = 1.
pub const WI_UP: &[f64] = &[
    1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 85.0, 100.0, 200.0, 500.0, 1000.0,
];
pub const WI_DOWN: &[f64] = &[0.5, 0.2, 0.1, 0.05];
/// Largest deviation of the centre-line velocity from Waters & King's for a run to pass, as a
/// fraction of max(U, |u_exact(t)|).
pub const WI_TOLERANCE: f64 = 0.05;

/// Whether a centre-line velocity `uc` is within [`WI_TOLERANCE`] of the exact `exact` (scale
/// `u`): 5 % of the exact value, never less than 5 % of U. Also false for NaN.
pub fn within_tolerance(uc: f64, exact: f64, u: f64) -> bool {
    (uc - exact).abs() <= WI_TOLERANCE * u.max(exact.abs())
}

/// One run of a sweep.
pub struct SweepRun {
    pub wi: f64,
    pub passed: bool,
    /// Why it failed: a breakdown's cause or the deviation, with the time [H/U].
    pub why: String,
    /// Largest |u_c - u_exact| / max(U, |u_exact|).
    pub max_deviation: f64,
    pub t_reached: f64,
    pub wall: f64,
    /// (t, SPH centre line, exact centre line).
    pub series: Vec<(f64, f64, f64)>,
}

/// Run the channel at one Wi to `t_end`, stopping at a breakdown or at the first output whose
/// centre-line velocity is more than [`WI_TOLERANCE`] U from Waters & King's.
pub fn sweep_run(v: &Variant, re: f64, wi: f64, across: i64, t_end: f64) -> BenchResult<SweepRun> {
    let beta = 0.1;
    let wk = WatersKing::new(analytic::Channel::from_re_wi(re, wi, beta))?;
    // Outputs fine enough to follow the fastest analytic time scale (t_v = Re H/U at the start).
    let sample = 0.05f64.min(0.5 * re).min(t_end / 10.0);
    let peak = analytic_peak(&wk, t_end);
    let cfg = kl_channel(v, "oldroyd_b", re, wi, beta, across, peak);
    let mut sim = Simulation::new(cfg)?;
    let start = Instant::now();
    let mut run = SweepRun {
        wi,
        passed: true,
        why: String::new(),
        max_deviation: 0.0,
        t_reached: 0.0,
        wall: 0.0,
        series: vec![(0.0, 0.0, 0.0)],
    };
    let samples = (t_end / sample).round() as usize;
    for k in 1..=samples {
        if let Err(e) = sim.advance_to(k as f64 * sample) {
            let (t, cause) = failure(&e);
            run.passed = false;
            run.why = format!("breakdown at t = {:.2}: {cause}", t.unwrap_or(f64::NAN));
            break;
        }
        let st = sim.state();
        let uc = centreline_velocity(&st.fluid, 1.0, 1.0 / across as f64);
        let exact = wk.centreline_velocity(st.time);
        run.series.push((st.time, uc, exact));
        run.t_reached = st.time;
        let dev = (uc - exact).abs() / wk.velocity_scale().max(exact.abs());
        run.max_deviation = run.max_deviation.max(dev);
        if !within_tolerance(uc, exact, wk.velocity_scale()) {
            run.passed = false;
            run.why = format!(
                "centre line {uc:.3} U vs exact {exact:.3} U at t = {:.2}",
                st.time
            );
            break;
        }
    }
    run.wall = start.elapsed().as_secs_f64();
    Ok(run)
}

/// The sweep of one scheme: upwards from Wi = 1 until a run fails; if Wi = 1 fails, downwards
/// until one passes.
pub fn sweep(
    v: &Variant,
    re: f64,
    across: i64,
    t_end: f64,
    wis: (&[f64], &[f64]),
) -> BenchResult<Vec<SweepRun>> {
    let mut runs = Vec::new();
    for &wi in wis.0 {
        let r = sweep_run(v, re, wi, across, t_end)?;
        eprintln!(
            "channel Wi sweep Re = {re}: {} Wi = {wi}: {} ({:.1} s)",
            v.label,
            if r.passed { "passed" } else { &r.why },
            r.wall
        );
        let passed = r.passed;
        runs.push(r);
        if !passed {
            break;
        }
    }
    if runs.first().is_some_and(|r| !r.passed) {
        for &wi in wis.1 {
            let r = sweep_run(v, re, wi, across, t_end)?;
            eprintln!(
                "channel Wi sweep Re = {re}: {} Wi = {wi}: {} ({:.1} s)",
                v.label,
                if r.passed { "passed" } else { &r.why },
                r.wall
            );
            let passed = r.passed;
            runs.push(r);
            if passed {
                break;
            }
        }
    }
    Ok(runs)
}

fn wi_sweeps(out: &Path, quick: bool, full: bool, figure: Option<u8>) -> BenchResult<String> {
    // (figure, Re, particles across, end time)
    let figs: Vec<(&str, f64, i64, f64)> = if quick {
        vec![("Fig. 5", 1.0, 12, 0.5), ("Fig. 6", 0.01, 10, 0.05)]
    } else if full {
        vec![("Fig. 5", 1.0, 30, 20.0), ("Fig. 6", 0.01, 15, 20.0)]
    } else {
        vec![("Fig. 5", 1.0, 30, 3.0), ("Fig. 6", 0.01, 15, 0.2)]
    };
    let figs: Vec<_> = figs
        .into_iter()
        .filter(|f| figure.is_none_or(|n| f.0.ends_with(&n.to_string())))
        .collect();
    let (up, down): (&[f64], &[f64]) = if quick {
        (&[1.0, 2.0], &[0.5])
    } else {
        (WI_UP, WI_DOWN)
    };
    let mut csv = String::from(
        "figure,re,across,t_end,scheme,wi,passed,t_reached,max_deviation,wall_seconds,why\n",
    );
    let mut hist =
        String::from("figure,scheme,wi,time,centreline_velocity,centreline_velocity_exact\n");
    let mut md = String::from(
        "### (b) Largest stable Weissenberg number (King & Lind Figs. 5 and 6, beta = 0.1)\n\n\
         Oldroyd-B, Wi = 1, 2, 5, 10, 20, 50, 85, 100, 200, 500, 1000 upwards until a run \
         fails (below 1 downwards until one passes). **Stable** = reaches the end time \
         without a breakdown with the centre-line velocity within 5 % of Waters & King's at \
         every output (5 % of max(U, |u_exact|)); a run is stopped at its first output off by \
         more. King & Lind (ISPH, \
         Lagrangian, shifting, log-conformation): Fig. 5 accurate to Wi = 85 to t = 20; Fig. 6 \
         accurate to Wi = 32, Wi = 64 breaks at t ~ 4.5.\n\n\
         | figure | Re | across | end time [H/U] | scheme | largest stable Wi | first failing Wi | how it failed | wall time of the sweep [s] |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    let mut panels = Vec::new();
    for (fig, re, across, t_end) in &figs {
        for v in sweep_variants() {
            let runs = match sweep(&v, *re, *across, *t_end, (up, down)) {
                Ok(r) => r,
                Err(e) => {
                    writeln!(
                        md,
                        "| {fig} | {re} | {across} | {t_end} | {} | not run: {e} | | | |",
                        v.label
                    )?;
                    continue;
                }
            };
            let best = runs
                .iter()
                .filter(|r| r.passed)
                .map(|r| r.wi)
                .fold(f64::NAN, f64::max);
            let first_fail = runs
                .iter()
                .filter(|r| !r.passed && (best.is_nan() || r.wi > best))
                .map(|r| r.wi)
                .fold(f64::NAN, f64::min);
            let why = runs
                .iter()
                .find(|r| r.wi == first_fail)
                .map_or(String::new(), |r| r.why.clone());
            let wall: f64 = runs.iter().map(|r| r.wall).sum();
            let show = |x: f64, none: &str| {
                if x.is_nan() {
                    none.to_string()
                } else {
                    format!("{x}")
                }
            };
            writeln!(
                md,
                "| {fig} | {re} | {across} | {t_end} | {} | {} | {} | {} | {wall:.0} |",
                v.label,
                show(best, &format!("< {}", down.last().copied().unwrap_or(1.0))),
                show(
                    first_fail,
                    &format!("> {}", up.last().copied().unwrap_or(1.0))
                ),
                why.replace('|', "/")
            )?;
            let mut series = Vec::new();
            for r in &runs {
                writeln!(
                    csv,
                    "{fig},{re},{across},{t_end},{},{},{},{:.4},{:.4e},{:.2},{}",
                    v.label,
                    r.wi,
                    r.passed,
                    r.t_reached,
                    r.max_deviation,
                    r.wall,
                    r.why.replace(',', ";")
                )?;
                for s in &r.series {
                    writeln!(
                        hist,
                        "{fig},{},{},{:.6},{:.6e},{:.6e}",
                        v.label, r.wi, s.0, s.1, s.2
                    )?;
                }
                series.push(Series {
                    label: format!(
                        "Wi = {} SPH{}",
                        r.wi,
                        if r.passed { "" } else { " (failed)" }
                    ),
                    points: r.series.iter().map(|s| (s.0, s.1)).collect(),
                });
                // The exact curve over the whole window, so a failed run shows what it missed.
                if let Ok(wk) = WatersKing::new(analytic::Channel::from_re_wi(*re, r.wi, 0.1)) {
                    let n = 400;
                    series.push(Series {
                        // A reference curve (thin black, one legend entry for all).
                        label: String::new(),
                        points: (0..=n)
                            .map(|k| {
                                let t = t_end * k as f64 / n as f64;
                                (t, wk.centreline_velocity(t))
                            })
                            .collect(),
                    });
                }
            }
            panels.push(Panel {
                title: format!("{fig}, Re = {re}, {across} across: {}", v.label),
                x_label: "t [H/U]".into(),
                y_label: "centre-line velocity [U]".into(),
                series,
                log: (false, false),
            });
        }
    }
    std::fs::write(out.join("channel_wi.csv"), csv)?;
    std::fs::write(out.join("channel_wi_series.csv"), hist)?;
    panel_grid(
        &out.join("channel_wi.png"),
        &panels,
        sweep_variants().len(),
        (700, 600),
    )?;
    Ok(md)
}

// ---------------------------------------------------------------------------------------------
// (c) steady profiles of the non-linear models

/// The models with a steady analytic channel solution (Cross has none).
pub const STEADY_MODELS: &[&str] = &[
    "oldroyd_b",
    "fene_cr",
    "fene_p",
    "ptt_linear",
    "ptt_exponential",
    "giesekus",
];

/// Relative L2 errors (u, tau_p,xy, tau_p,xx) of a state against a steady solution:
/// sqrt(sum (f_i - f(y_i))^2 / sum f(y_i)^2) over the particles.
pub fn steady_errors(sim: &Simulation, exact: &SteadyChannel) -> (f64, f64, f64) {
    let cfg = sim.effective_config();
    let f = &sim.state().fluid;
    let model = AnyRheology::from_config(cfg).ok();
    let (mut e, mut n) = ([0.0f64; 3], [0.0f64; 3]);
    for (k, (x, v)) in f.x.iter().zip(&f.v).enumerate() {
        let p = exact.at(x.y);
        e[0] += (v.x - p.velocity).powi(2);
        n[0] += p.velocity.powi(2);
        if let (Some(m), Some(a)) = (&model, f.conf.get(k)) {
            let tau = viscosph::dispatch_rheology!(m, m => m.polymer_stress(a));
            e[1] += (tau[(0, 1)] - p.tau_p_xy).powi(2);
            n[1] += p.tau_p_xy.powi(2);
            e[2] += (tau[(0, 0)] - p.tau_p_xx).powi(2);
            n[2] += p.tau_p_xx.powi(2);
        }
    }
    let rel = |k: usize| {
        if n[k] > 0.0 {
            (e[k] / n[k]).sqrt()
        } else {
            f64::NAN
        }
    };
    (rel(0), rel(1), rel(2))
}

fn nonlinear(out: &Path, quick: bool, full: bool) -> BenchResult<String> {
    let (re, wi, beta) = (1.0, 1.0, 0.1);
    let (across, t_end, models): (i64, f64, &[&str]) = if quick {
        (12, 0.5, &STEADY_MODELS[..2])
    } else if full {
        (30, 10.0, STEADY_MODELS)
    } else {
        (20, 5.0, STEADY_MODELS)
    };
    let mut csv = String::from("scheme,model,across,t_end,wall_seconds,l2_u,l2_tau_xy,l2_tau_xx,centreline_velocity,centreline_velocity_exact,failure\n");
    let mut prof = String::from("scheme,model,y,u,u_exact\n");
    let mut md = format!(
        "### (c) Steady profiles of the non-linear models (Re = Wi = 1, beta = 0.1, {across} across, t = {t_end} H/U)\n\n\
         Relative L2 errors over the particles, sqrt(sum (f_i - f(y_i))^2 / sum f(y_i)^2), \
         against the steady solutions of `reference/src/analytic/steady_shear.rs`; the models' default \
         parameters (FENE L^2 = 100, PTT epsilon = 0.25, Giesekus alpha = 0.1), King & Lind's \
         protocol (t = 5 H/U, where Oldroyd-B's exact centre line is still 1.020 U: the \
         errors include what is left of the transient; `--full` runs to t = 10). King & Lind at 30 across: \
         FENE-P 5.2 % (tau_xy) and 3.4 % (tau_xx) at t = 5; PTT 0.8 % (linear) and 1.3 % \
         (exponential).\n\n\
         | scheme | model | wall time [s] | L2 u | L2 tau_p,xy | L2 tau_p,xx | centre line (exact) [U] |\n\
         |---|---|---|---|---|---|---|\n"
    );
    let mut panels = Vec::new();
    for v in sweep_variants() {
        let mut series = Vec::new();
        for model in models {
            let probe = kl_channel(&v, model, re, wi, beta, across, 1.0);
            let exact = SteadyChannel::from_config(&probe, 1.0, 8.0 / re)?;
            // The start-up overshoots like Oldroyd-B's (the non-linear models overshoot less).
            let wk = WatersKing::new(analytic::Channel::from_re_wi(re, wi, beta))?;
            let cfg = kl_channel(&v, model, re, wi, beta, across, analytic_peak(&wk, t_end));
            let mut sim = match Simulation::new(cfg) {
                Ok(s) => s,
                Err(e) => {
                    writeln!(md, "| {} | {model} | not run: {e} | | | | |", v.label)?;
                    continue;
                }
            };
            let start = Instant::now();
            let res = sim.advance_to(t_end);
            let wall = start.elapsed().as_secs_f64();
            // A breakdown leaves the last good state: its errors are listed with the time.
            let fail = res.err().map(|e| match failure(&e) {
                (Some(t), cause) => format!("at t = {t:.2}: {cause}"),
                (None, cause) => cause,
            });
            let (eu, exy, exx) = steady_errors(&sim, &exact);
            let uc = centreline_velocity(&sim.state().fluid, 1.0, 1.0 / across as f64);
            eprintln!(
                "channel steady {} {model}: L2 u {eu:.3e} tau_xy {exy:.3e} tau_xx {exx:.3e} ({wall:.1} s)",
                v.label
            );
            writeln!(
                csv,
                "{},{model},{across},{t_end},{wall:.2},{eu:.6e},{exy:.6e},{exx:.6e},{uc:.6},{:.6},{}",
                v.label,
                exact.centreline_velocity(),
                fail.clone().unwrap_or_default().replace(',', ";")
            )?;
            writeln!(
                md,
                "| {} | {model} | {wall:.1} | {:.2} % | {:.2} % | {:.2} % | {uc:.4} ({:.4}){} |",
                v.label,
                100.0 * eu,
                100.0 * exy,
                100.0 * exx,
                exact.centreline_velocity(),
                fail.map(|f| format!(" broke: {f}")).unwrap_or_default()
            )?;
            // The profile: particle velocities averaged over each row of the lattice.
            let mut rows: Vec<(f64, f64)> = sim
                .state()
                .fluid
                .x
                .iter()
                .zip(&sim.state().fluid.v)
                .map(|(x, v)| (x.y, v.x))
                .collect();
            rows.sort_by(|a, b| a.0.total_cmp(&b.0));
            let bins = across as usize;
            let mut binned = vec![(0.0, 0.0, 0usize); bins];
            for (y, u) in rows {
                let b = ((y * bins as f64) as usize).min(bins - 1);
                binned[b].0 += y;
                binned[b].1 += u;
                binned[b].2 += 1;
            }
            let pts: Vec<(f64, f64)> = binned
                .iter()
                .filter(|b| b.2 > 0)
                .map(|b| (b.0 / b.2 as f64, b.1 / b.2 as f64))
                .collect();
            for (y, u) in &pts {
                writeln!(
                    prof,
                    "{},{model},{y:.6},{u:.6e},{:.6e}",
                    v.label,
                    exact.velocity(*y)
                )?;
            }
            series.push(Series {
                label: format!("{model} SPH"),
                points: pts.iter().map(|(y, u)| (*u, *y)).collect(),
            });
            series.push(Series {
                label: format!("{model} exact"),
                points: (0..=100)
                    .map(|k| {
                        let y = k as f64 / 100.0;
                        (exact.velocity(y), y)
                    })
                    .collect(),
            });
        }
        panels.push(Panel {
            title: format!("steady profiles, {}", v.label),
            x_label: "u [U]".into(),
            y_label: "y [H]".into(),
            series,
            log: (false, false),
        });
    }
    std::fs::write(out.join("channel_nonlinear.csv"), csv)?;
    std::fs::write(out.join("channel_nonlinear_profiles.csv"), prof)?;
    panel_grid(
        &out.join("channel_nonlinear.png"),
        &panels,
        panels.len().min(2),
        (800, 800),
    )?;
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerance_is_relative_above_u_and_absolute_below() {
        assert!(within_tolerance(2.344, 2.291, 1.0)); // 2.3 % of the exact value
        assert!(!within_tolerance(2.344, 2.191, 1.0)); // 7 %
        assert!(within_tolerance(0.40, 0.36, 1.0)); // 0.04 U: 11 % of 0.36, but below 0.05 U
        assert!(!within_tolerance(0.42, 0.36, 1.0));
        assert!(!within_tolerance(f64::NAN, 1.0, 1.0));
    }

    #[test]
    fn every_variant_selects_a_scheme_the_configuration_knows() {
        for v in variants() {
            let c = kl_channel(&v, "oldroyd_b", 1.0, 1.0, 0.1, 15, 2.85);
            assert_eq!(c.scheme.as_str(), v.label.split('/').next().unwrap());
            // U = rho g H^2 / (8 eta0) = 1 and Re = rho U H / eta0 = 1.
            assert_eq!(
                (
                    c.channel.body_force,
                    c.fluid.viscosity,
                    c.fluid.relaxation_time
                ),
                (8.0, 1.0, 1.0)
            );
            assert!((c.numerics.sound_speed - 28.5).abs() < 1e-12);
        }
    }
}
