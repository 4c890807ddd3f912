//! `viscosph bench cylinders`: the flow past a periodic array of cylinders (King & Lind 2021
//! section IV.B) against the finite-element reference of `validation/cylinder_array/`.
//!
//! Every run is King & Lind's cell (R = 1 m, L = 6R, H = 4R, rho = 1 kg/m3, eta0 = 41.66 Pa s,
//! g = 300 m/s2, Oldroyd-B with beta = 0.59) under `stop_at_steady_state = 1`: it ends three
//! time units R/⟨u⟩ after King & Lind's steady state (the flow rate changes by less than 2 %
//! over one time unit), and its figures are the means over those three units. lambda is set to
//! the Wi asked for (⟨u⟩ is about 1 m/s); the table gives the Wi measured, ⟨u⟩ lambda / R.
//!
//! * **Wi sweep**, per scheme: Wi = 0 (Newtonian), 0.2, 0.6, 0.8, then 1, 1.5, 2, 3, 4, 6, 8,
//!   12, 16 until a run breaks down or does not reach the steady state by its end time: time to
//!   the steady state, steps, wall and CPU time, ⟨u⟩ against the finite elements (Wi 0, 0.2,
//!   0.6), K = F / (eta0 ⟨u⟩) against the finite elements' (Wi 0, 0.2, 0.6).
//! * **Cost against Wi**: the exponent p of CPU time ~ Wi^p fitted over the stable Wi >= 0.2
//!   (King & Lind: resolved runs cost about Wi^5).
//! * **Resolution sweep**: the Newtonian drag coefficient against the finite elements' 92.830
//!   and the run's CPU time, ISPH at 8 to 24 particles across the diameter, WCSPH and PDRI at 8
//!   and 16; ISPH's Oldroyd-B K at lambda = 0.2 and 0.6 s against the finite elements' 89.066
//!   and 81.924 at 12, 16 and 24 across.
//! * **Figures** in the style of King & Lind's Figs. 9-11 from the averaged fields
//!   (`scene::FieldAverage`): speed and tr A in the cell on a grid of half a spacing with the
//!   cylinder drawn over them, the centre-line u/⟨u⟩ and tau_xx at Wi = 0.2, 0.6, 0.8 with the
//!   finite elements' Newtonian and Oldroyd-B profiles (thin black), det A along the centre
//!   line for every Wi reached; one colour per Wi in every panel.
//!
//! `--isph-only`: the ISPH parts alone (sweep, both resolution sweeps, figures), about half the
//! CPU time.
//!
//! `--quick` (the test suite): ISPH at 8 across, Wi = 0 and 0.2 only, asserting what must hold
//! at 8 across: both runs reach the steady state, Q > 0, K within 15 % of the finite elements
//! (measured -12.8 %), ⟨u⟩ at Wi = 0.2 above the Newtonian (the elastic cell flows faster under
//! the same body force, as the finite elements say: 1.0486 against 1.0183 m/s). About 10 s.

use super::{case, machine_description};
use crate::io::plot::{self, line_panels_keyed, Panel, Series, REFERENCE_PREFIX};
use crate::run::{mean_speed, run, RunOptions, RunResult};
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::Value;
use viscosph::scene::cylinder_array::{steady_means, REFERENCE_DRAG_COEFFICIENT};
use viscosph::scene::{NoPredictions, SceneConfig};

type BenchResult<T> = Result<T, Box<dyn std::error::Error>>;

/// ⟨u⟩ of the finite elements (fluid mean, extrapolated or finest level) at lambda = 0, 0.2,
/// 0.6 s: `validation/cylinder_array/reference/cell_results.csv` and
/// `oldroyd_b_convergence.csv`.
const FEM_MEAN_VELOCITY: [(f64, f64); 3] =
    [(0.0, 1.01833196), (0.2, 1.04857927), (0.6, 1.11117300)];

/// The finite elements' K = F / (eta0 ⟨u⟩) at lambda = 0, 0.2, 0.6 s.
const FEM_K: [(f64, f64); 3] = [
    (0.0, REFERENCE_DRAG_COEFFICIENT),
    (0.2, 89.066),
    (0.6, 81.924),
];

/// The Weissenberg numbers of the sweep, in order (a scheme stops at its first failure).
const WI_SWEEP: [f64; 13] = [
    0.0, 0.2, 0.6, 0.8, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0,
];

/// Particles across the diameter of the Oldroyd-B resolution sweep (ISPH).
const ELASTIC_RESOLUTIONS: [i64; 3] = [12, 16, 24];

/// The Wi of King & Lind's Fig. 10 profiles.
const PROFILE_WI: [f64; 3] = [0.2, 0.6, 0.8];

fn text(s: &str) -> Value {
    Value::Text(s.into())
}

/// A scheme of the sweep: its label and the parameters that select it.
struct Scheme {
    label: &'static str,
    pairs: Vec<(&'static str, Value)>,
    /// Particles across the diameter in the Wi sweep.
    across: i64,
}

/// King & Lind's cell at `wi` (0: Newtonian) under `scheme` with `across` particles across the
/// diameter, stopping three time units after the steady state.
fn kl_cell(scheme: &Scheme, wi: f64, across: i64) -> SceneConfig {
    let mut pairs: Vec<(&str, Value)> = vec![
        ("scene", text("cylinder_array")),
        (
            "rheology",
            text(if wi > 0.0 { "oldroyd_b" } else { "newtonian" }),
        ),
        ("density", Value::Real(1.0)),
        ("viscosity", Value::Real(41.66)),
        ("viscosity_ratio", Value::Real(0.59)),
        ("relaxation_time", Value::Real(wi.max(1e-3))),
        ("particles_per_diameter", Value::Integer(across)),
        ("stop_at_steady_state", Value::Integer(1)),
    ];
    pairs.extend(scheme.pairs.iter().cloned());
    case(&pairs)
}

/// One run of the cell and what the tables need of it.
struct CellRun {
    wi_asked: f64,
    across: i64,
    result: RunResult,
    cpu: f64,
    /// Time of the steady state and the means (drag, lift, wall shear, ⟨u⟩, Q) over the three
    /// units after it, if reached.
    steady: Option<(f64, [f64; 5])>,
}

impl CellRun {
    fn stable(&self) -> bool {
        self.result.error.is_none() && self.steady.is_some()
    }

    fn mean_velocity(&self) -> f64 {
        self.steady.map_or(f64::NAN, |(_, m)| m[3])
    }

    /// K = F / (eta0 ⟨u⟩), None where the scheme does not split the walls' force.
    fn k(&self) -> Option<f64> {
        let (_, m) = self.steady?;
        (m[0] != 0.0).then(|| m[0] / (41.66 * m[3]))
    }
}

/// Run `cfg` to its steady state and three units more, or to `t_end`.
fn cell_run(cfg: &SceneConfig, wi: f64, t_end: f64) -> BenchResult<CellRun> {
    let mut opts = RunOptions::for_scene(cfg);
    opts.t_end = t_end;
    opts.output_interval = 0.02;
    opts.force = true;
    let across = cfg.numerics.particles_per_diameter;
    let t0 = viscosph::profile::Stamp::now();
    let result = run(cfg, &opts, &NoPredictions)?;
    let (_, cpu) = t0.elapsed();
    let steady = result.averages.as_ref().and_then(|a| {
        let w = a.window();
        let s = steady_means(&result.series, w.start, (w.end - w.start) / 3.0);
        s.means.map(|m| (s.time, m))
    });
    Ok(CellRun {
        wi_asked: wi,
        across,
        result,
        cpu,
        steady,
    })
}

/// The reference value of a table at lambda = `wi`, if it has one.
fn at(table: &[(f64, f64)], wi: f64) -> Option<f64> {
    table
        .iter()
        .find(|(l, _)| (l - wi).abs() < 1e-9)
        .map(|(_, v)| *v)
}

/// Least-squares slope of log y against log x.
fn log_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    if points.len() < 2 {
        return f64::NAN;
    }
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Options of `viscosph bench cylinders`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct CylindersArgs {
    /// ISPH only: its Wi sweep, its Newtonian and Oldroyd-B resolution sweeps and the figures
    /// (about half the CPU time of the whole); WCSPH and PDRI are left out.
    #[arg(long)]
    pub isph_only: bool,
}

pub fn bench_cylinders(args: &CylindersArgs, out: &Path, quick: bool) -> BenchResult<String> {
    let mut schemes: Vec<Scheme> = if quick {
        vec![Scheme {
            label: "isph",
            pairs: vec![("scheme", text("isph")), ("isph_frame", text("eulerian"))],
            across: 8,
        }]
    } else {
        vec![
            Scheme {
                label: "isph",
                pairs: vec![("scheme", text("isph")), ("isph_frame", text("eulerian"))],
                across: 16,
            },
            Scheme {
                label: "wcsph",
                pairs: vec![("scheme", text("wcsph"))],
                across: 8,
            },
            Scheme {
                label: "pdri",
                pairs: vec![("scheme", text("pdri"))],
                across: 8,
            },
        ]
    };
    if args.isph_only {
        schemes.truncate(1);
    }
    let wi_list: &[f64] = if quick { &WI_SWEEP[..2] } else { &WI_SWEEP };
    let t_end = if quick { 6.0 } else { 12.0 };
    let mut md = format!(
        "King & Lind's cell (R = 1 m, 6R x 4R, rho = 1, eta0 = 41.66 Pa s, g = 300 m/s2, \
         Oldroyd-B beta = 0.59, lambda = Wi s), `stop_at_steady_state = 1`: each run ends three \
         time units R/⟨u⟩ after King & Lind's steady state (or at t = {t_end} s), and its \
         figures are the means over those three units. Eulerian ISPH. {}; CPU time of the \
         process (all threads).{}\n\n",
        machine_description(),
        if args.isph_only && !quick {
            " ISPH only (`--isph-only`): WCSPH and PDRI were not run; `viscosph bench \
             cylinders` runs them too."
        } else {
            ""
        }
    );
    let mut csv = String::from(
        "part,scheme,across,wi_asked,wi,steady_time,t_end,steps,wall_seconds,cpu_seconds,mean_velocity,fem_mean_velocity,K,fem_K,max_trace,error\n",
    );
    md.push_str("### Wi sweep\n\n| scheme | across | Wi (asked) | Wi = ⟨u⟩ lambda / R | steady at [s] | steps | wall [s] | CPU [s] | ⟨u⟩ | ⟨u⟩ FEM | K | K FEM | max tr A | breakdown |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    let mut sweeps: Vec<(&'static str, Vec<CellRun>)> = Vec::new();
    for s in &schemes {
        let mut runs = Vec::new();
        for &wi in wi_list {
            eprintln!(
                "bench cylinders: {} Wi = {wi} at {} across ...",
                s.label, s.across
            );
            let r = cell_run(&kl_cell(s, wi, s.across), wi, t_end)?;
            row(&mut md, &mut csv, "wi", s.label, &r)?;
            let stable = r.stable();
            runs.push(r);
            if !stable {
                break;
            }
        }
        sweeps.push((s.label, runs));
    }
    // Cost against Wi.
    md.push_str("\n### Cost against Wi\n\nThe exponent p of CPU time ~ Wi^p, least squares over the stable runs with Wi >= 0.2 (King & Lind: about Wi^5 for resolved runs, whose resolution grows with Wi; here the resolution is fixed).\n\n| scheme | runs | p (CPU time) | p (steps) | largest stable Wi |\n|---|---|---|---|---|\n");
    for (label, runs) in &sweeps {
        let stable: Vec<&CellRun> = runs
            .iter()
            .filter(|r| r.stable() && r.wi_asked >= 0.2)
            .collect();
        let cpu: Vec<(f64, f64)> = stable.iter().map(|r| (r.wi_asked, r.cpu)).collect();
        let steps: Vec<(f64, f64)> = stable
            .iter()
            .map(|r| (r.wi_asked, r.result.steps as f64))
            .collect();
        let largest = runs
            .iter()
            .filter(|r| r.stable())
            .map(|r| r.wi_asked)
            .fold(f64::NAN, f64::max);
        writeln!(
            md,
            "| {label} | {} | {:.2} | {:.2} | {largest} |",
            stable.len(),
            log_slope(&cpu),
            log_slope(&steps)
        )?;
    }
    // Resolution sweep, Newtonian: ISPH at 8-24 across, WCSPH and PDRI at 8 and 16.
    md.push_str("\n### Resolution: the Newtonian drag against the finite elements (K = 92.830)\n\n| scheme | across | K | error | steps | wall [s] | CPU [s] |\n|---|---|---|---|---|---|---|\n");
    for (s, (label, runs)) in schemes.iter().zip(&sweeps) {
        let resolutions: &[i64] = match (quick, s.label) {
            (true, _) => &[],
            (false, "isph") => &[8, 12, 16, 24],
            (false, _) => &[8, 16],
        };
        let mut res_runs: Vec<CellRun> = Vec::new();
        // The sweep's own Newtonian run counts at its resolution.
        if let Some(r0) = runs.first() {
            res_runs.push(CellRun {
                wi_asked: 0.0,
                across: r0.across,
                result: r0.result.clone(),
                cpu: r0.cpu,
                steady: r0.steady,
            });
        }
        for &n in resolutions.iter().filter(|&&n| n != s.across) {
            eprintln!("bench cylinders: {label} Newtonian at {n} across ...");
            let r = cell_run(&kl_cell(s, 0.0, n), 0.0, t_end)?;
            row(&mut String::new(), &mut csv, "resolution", label, &r)?;
            res_runs.push(r);
        }
        res_runs.sort_by_key(|r| r.across);
        for r in &res_runs {
            let k = r.k().unwrap_or(f64::NAN);
            writeln!(
                md,
                "| {label} | {} | {k:.3} | {:+.2} % | {} | {:.1} | {:.1} |",
                r.across,
                100.0 * (k / REFERENCE_DRAG_COEFFICIENT - 1.0),
                r.result.steps,
                r.result.wall_seconds,
                r.cpu
            )?;
        }
    }
    // Resolution, Oldroyd-B: ISPH's K at lambda = 0.2 and 0.6 s against the finite elements'
    // (the sweep's runs at its resolution, more at 12 and 24 across).
    if !quick {
        if let (Some(s), Some((label, runs))) = (schemes.first(), sweeps.first()) {
            md.push_str(
                "
### Resolution: the Oldroyd-B drag against the finite elements

| scheme | lambda [s] | across | Wi = ⟨u⟩ lambda / R | ⟨u⟩ | ⟨u⟩ FEM | K | K FEM | error | CPU [s] |
|---|---|---|---|---|---|---|---|---|---|
",
            );
            for lambda in [0.2, 0.6] {
                let mut res_runs: Vec<CellRun> = Vec::new();
                for &n in ELASTIC_RESOLUTIONS.iter().filter(|&&n| n != s.across) {
                    eprintln!("bench cylinders: {label} lambda = {lambda} at {n} across ...");
                    let r = cell_run(&kl_cell(s, lambda, n), lambda, t_end)?;
                    row(&mut String::new(), &mut csv, "resolution", label, &r)?;
                    res_runs.push(r);
                }
                let own = runs.iter().find(|r| r.wi_asked == lambda);
                let mut all: Vec<&CellRun> = res_runs.iter().chain(own).collect();
                all.sort_by_key(|r| r.across);
                let (fem_u, fem_k) = (at(&FEM_MEAN_VELOCITY, lambda), at(&FEM_K, lambda));
                for r in all {
                    let (u, k) = (r.mean_velocity(), r.k().unwrap_or(f64::NAN));
                    let fk = fem_k.unwrap_or(f64::NAN);
                    writeln!(
                        md,
                        "| {label} | {lambda} | {} | {:.3} | {u:.4} | {:.4} | {k:.3} | {fk:.3} | {:+.2} % | {:.1} |",
                        r.across,
                        u * lambda,
                        fem_u.unwrap_or(f64::NAN),
                        100.0 * (k / fk - 1.0),
                        r.cpu
                    )?;
                }
            }
        }
    }
    figures(out, &sweeps)?;
    std::fs::write(out.join("cylinders.csv"), &csv)?;
    std::fs::write(out.join("cylinders.md"), &md)?;
    if quick {
        check_quick(&sweeps)?;
    }
    Ok(md)
}

/// One row of the Wi table and of the CSV.
fn row(
    md: &mut String,
    csv: &mut String,
    part: &str,
    label: &str,
    r: &CellRun,
) -> std::fmt::Result {
    let u = r.mean_velocity();
    let wi = u * r.wi_asked;
    let t_end = r.result.series.last().map_or(0.0, |(t, _)| *t);
    let steady = r.steady.map_or("-".to_string(), |(t, _)| format!("{t:.2}"));
    let fem_u = at(&FEM_MEAN_VELOCITY, r.wi_asked);
    let fem_k = at(&FEM_K, r.wi_asked);
    let opt = |v: Option<f64>, p: usize| v.map_or("-".to_string(), |v| format!("{v:.p$}"));
    let error = r.result.error_text();
    let error = if r.result.error.is_none() && r.steady.is_none() {
        format!("not steady by t = {t_end:.2} s")
    } else {
        error
    };
    writeln!(
        md,
        "| {label} | {} | {} | {wi:.3} | {steady} | {} | {:.1} | {:.1} | {u:.4} | {} | {} | {} | {} | {error} |",
        r.across,
        r.wi_asked,
        r.result.steps,
        r.result.wall_seconds,
        r.cpu,
        opt(fem_u, 4),
        opt(r.k(), 2),
        opt(fem_k, 2),
        r.result.max_trace_text()
    )?;
    writeln!(
        csv,
        "{part},{label},{},{},{wi},{steady},{t_end},{},{:.3},{:.3},{u},{},{},{},{},\"{}\"",
        r.across,
        r.wi_asked,
        r.result.steps,
        r.result.wall_seconds,
        r.cpu,
        opt(fem_u, 6),
        opt(r.k(), 4),
        opt(fem_k, 4),
        r.result.max_trace_text(),
        error.replace('"', "'")
    )
}

/// The points of the cylinder's outline (drawn as wall points in the field plots).
fn outline(centre: (f64, f64), radius: f64) -> Vec<(f64, f64)> {
    (0..180)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 180.0;
            (centre.0 + radius * a.cos(), centre.1 + radius * a.sin())
        })
        .collect()
}

/// The points and values of a Fig. 9 field, and their spacing: where the particles stayed put
/// (Eulerian ISPH) a square grid of half a particle spacing (`dx`) over the fluid, each point
/// with the mean of its nearest particle, so that the squares of the picture tile the fluid
/// (squares at the particles leave gaps where the ring lattice round the cylinder meets the
/// square lattice beyond); else the average's cells, one spacing wide. Nearest, not
/// `FieldAverage::interpolate`: next to the walls under the cylinder, where rings and rows
/// meet, its quadratic overshot (speed 3.3 m/s on the wall at 8 across).
fn field_points(
    a: &viscosph::scene::FieldAverage,
    centre: (f64, f64),
    dx: f64,
) -> (Vec<(viscosph::Vec2, [f64; 5])>, f64) {
    let Some(particles) = a.particles() else {
        return (a.cells().into_iter().map(|(c, m, _)| (c, m)).collect(), dx);
    };
    let w = a.window();
    let h = 0.5 * dx;
    let (nx, ny) = (
        ((w.upper.x - w.lower.x) / h).round() as usize,
        ((w.upper.y - w.lower.y) / h).round() as usize,
    );
    let c = viscosph::Vec2::new(centre.0, centre.1);
    let points = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| {
                w.lower + viscosph::Vec2::new((i as f64 + 0.5) * h, (j as f64 + 0.5) * h)
            })
        })
        // The fluid: outside the cylinder (radius 1 m).
        .filter(|p| (p - c).norm() > 1.0)
        .filter_map(|p| {
            particles
                .iter()
                .min_by(|a, b| (a.0 - p).norm().total_cmp(&(b.0 - p).norm()))
                .map(|q| (p, q.1))
        })
        .collect();
    (points, h)
}

/// King & Lind's Figs. 9-11 from the ISPH sweep (the first scheme).
fn figures(out: &Path, sweeps: &[(&'static str, Vec<CellRun>)]) -> BenchResult<()> {
    let Some((label, runs)) = sweeps.first() else {
        return Ok(());
    };
    let with_fields: Vec<&CellRun> = runs
        .iter()
        .filter(|r| r.result.averages.is_some())
        .collect();
    // Fig. 9: the fields at the profile Wi (or whatever was reached), speed and tr A.
    let shown: Vec<&CellRun> = with_fields
        .iter()
        .copied()
        .filter(|r| PROFILE_WI.contains(&r.wi_asked) || r.wi_asked == 0.0)
        .collect();
    for (file, field, k) in [
        ("cylinders_speed.png", "speed [m/s]", None),
        // tr A spans 2-9 at Wi 0.2 and 2-100 at Wi 0.8: each panel over its own largest
        // value (named in its title), so that every panel uses the whole colour bar.
        ("cylinders_trace.png", "tr(A) / panel max [-]", Some(2)),
    ] {
        let shots: Vec<plot::Snapshot> = shown
            .iter()
            .filter(|r| k.is_none() || r.wi_asked > 0.0)
            .map(|r| {
                let a = r.result.averages.as_ref().expect("filtered");
                let w = a.window();
                let centre = (0.5 * (w.lower.x + w.upper.x), 0.5 * (w.lower.y + w.upper.y));
                let (points, spacing) = field_points(a, centre, 2.0 / r.across as f64);
                let values: Vec<f64> = points
                    .iter()
                    .map(|(_, m)| match k {
                        Some(k) => m[k],
                        None => m[0].hypot(m[1]),
                    })
                    .collect();
                let (title, values) = match k {
                    Some(_) => {
                        let top = values.iter().copied().fold(0.0f64, f64::max);
                        let scaled = values.iter().map(|v| v / top.max(1e-300)).collect();
                        (format!("Wi = {}, tr A up to {top:.3}", r.wi_asked), scaled)
                    }
                    None => (format!("Wi = {}", r.wi_asked), values),
                };
                plot::Snapshot {
                    title,
                    points: points.iter().map(|(c, _)| (c.x, c.y)).collect(),
                    values,
                    walls: Vec::new(),
                    spacing,
                    plates: vec![
                        plot::PlateLine {
                            point: (0.0, w.lower.y),
                            tangent: (1.0, 0.0),
                        },
                        plot::PlateLine {
                            point: (0.0, w.upper.y),
                            tangent: (1.0, 0.0),
                        },
                    ],
                    nozzle: None,
                    axes: ("x".into(), "y".into()),
                    // A field, not a lattice: squares one spacing across.
                    splat: true,
                    outline: outline(centre, 1.0),
                }
            })
            .collect();
        if shots.is_empty() {
            continue;
        }
        plot::particle_snapshots(
            &out.join(file),
            &format!(
                "{label}: time-averaged {} in the steady cell (King & Lind Fig. 9)",
                field.split(" [").next().unwrap_or(field)
            ),
            &shots,
            field,
            shots.len().min(2),
            (1700, 600 * shots.len().div_ceil(2) as u32 + 100),
        )?;
    }
    // Figs. 10 and 11: along the centre line from the rear of the cylinder (s = 0) to the front
    // of the next (s = L - 2R), King & Lind's abscissa.
    let profile = |r: &CellRun, k: usize, over_mean: bool| -> Series {
        let a = r.result.averages.as_ref().expect("filtered");
        let mean = mean_speed(&a.cells());
        let (lo, hi) = (a.window().lower.x, a.window().upper.x);
        let (xc, period) = (0.5 * (lo + hi), hi - lo);
        let mut points: Vec<(f64, f64)> = a
            .centre_line()
            .iter()
            .map(|(x, m, _)| {
                let s = (x - xc).rem_euclid(period) - 1.0;
                (s, if over_mean { m[k] / mean } else { m[k] })
            })
            .collect();
        points.sort_by(|p, q| p.0.total_cmp(&q.0));
        Series {
            label: format!("Wi = {}", r.wi_asked),
            points,
        }
    };
    // Wi = 0 last: the elastic runs come first in every panel (the colours follow the labels
    // across the panels, `line_panels_keyed`).
    let mut fig10: Vec<&CellRun> = with_fields
        .iter()
        .copied()
        .filter(|r| PROFILE_WI.contains(&r.wi_asked) || r.wi_asked == 0.0)
        .collect();
    fig10.sort_by_key(|r| r.wi_asked == 0.0);
    let mut u_series: Vec<Series> = fig10.iter().map(|r| profile(r, 0, true)).collect();
    let (fem_u, fem_tau) = fem_centreline();
    u_series.extend(fem_u);
    let mut tau_series: Vec<Series> = fig10
        .iter()
        .filter(|r| r.wi_asked > 0.0)
        .map(|r| profile(r, 3, false))
        .collect();
    tau_series.extend(fem_tau);
    let det_series: Vec<Series> = with_fields
        .iter()
        .filter(|r| r.wi_asked > 0.0 && r.stable())
        .map(|r| profile(r, 4, false))
        .collect();
    let panel = |title: &str, y: &str, series: Vec<Series>| Panel {
        title: title.into(),
        x_label: "s / R, from the rear of the cylinder to the front of the next".into(),
        y_label: y.into(),
        series,
        log: (false, false),
    };
    line_panels_keyed(
        &out.join("cylinders_centreline.png"),
        &[
            panel(
                &format!("{label}: u/<u> on the centre line (Fig. 10)"),
                "u / <u>",
                u_series,
            ),
            panel(
                "tau_p,xx on the centre line (Fig. 10)",
                "tau_xx [Pa]",
                tau_series,
            ),
            panel("det A on the centre line (Fig. 11)", "det A", det_series),
        ],
        1,
        (1400, 1500),
    )?;
    Ok(())
}

/// The finite elements' centre-line u/⟨u⟩ (Newtonian, and Oldroyd-B at lambda 0.2 and 0.6)
/// and tau_p,xx [Pa] (Oldroyd-B) against s / R from the rear of the cylinder: the reference
/// curves of Fig. 10, read from
/// `validation/cylinder_array/reference/`; none if the files are not there (an installed binary).
fn fem_centreline() -> (Vec<Series>, Vec<Series>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../validation/cylinder_array/reference");
    let read = |file: &str, column: &str| -> Option<Vec<(f64, f64)>> {
        let text = std::fs::read_to_string(dir.join(file)).ok()?;
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let head: Vec<&str> = lines.next()?.split(',').collect();
        let (s, c) = (
            head.iter().position(|h| *h == "s_over_R")?,
            head.iter().position(|h| *h == column)?,
        );
        Some(
            lines
                .filter_map(|l| {
                    let f: Vec<f64> = l.split(',').filter_map(|v| v.parse().ok()).collect();
                    Some((*f.get(s)?, *f.get(c)?))
                })
                .collect(),
        )
    };
    let u: Vec<Series> = [
        ("centreline.csv", "u_over_mean"),
        ("oldroyd_b_centreline.csv", "u_over_mean_lam0.2"),
        ("oldroyd_b_centreline.csv", "u_over_mean_lam0.6"),
    ]
    .iter()
    .filter_map(|(f, c)| read(f, c))
    .map(|points| Series {
        label: format!("{REFERENCE_PREFIX}FEM (Wi = 0, 0.21, 0.67)"),
        points,
    })
    .collect();
    // tau_xx over eta_s ⟨u⟩ / R (R = 1 m) in the file: times beta eta0 and the FEM's own ⟨u⟩.
    let tau: Vec<Series> = [(0.2, "tauxx_scaled_lam0.2"), (0.6, "tauxx_scaled_lam0.6")]
        .iter()
        .filter_map(|&(lambda, c)| {
            let scale = 0.59 * 41.66 * at(&FEM_MEAN_VELOCITY, lambda)?;
            let points = read("oldroyd_b_centreline.csv", c)?;
            Some(Series {
                label: format!("{REFERENCE_PREFIX}FEM (Wi = 0.21, 0.67)"),
                points: points.into_iter().map(|(s, t)| (s, t * scale)).collect(),
            })
        })
        .collect();
    (u, tau)
}

/// What `--quick` asserts: physics that holds at 8 across.
fn check_quick(sweeps: &[(&'static str, Vec<CellRun>)]) -> BenchResult<()> {
    let runs = &sweeps[0].1;
    if runs.len() < 2 || !runs.iter().all(CellRun::stable) {
        return Err("bench cylinders --quick: a run did not reach its steady state".into());
    }
    for r in runs {
        let q = r.steady.map_or(0.0, |(_, m)| m[4]);
        if q <= 0.0 {
            return Err(format!("bench cylinders --quick: Q = {q} at Wi = {}", r.wi_asked).into());
        }
    }
    let k = runs[0].k().unwrap_or(f64::NAN);
    // Written so that a NaN K (no drag measured) fails too.
    let within = (k / REFERENCE_DRAG_COEFFICIENT - 1.0).abs() < 0.15;
    if !within {
        return Err(format!(
            "bench cylinders --quick: Newtonian K = {k}, not within 15 % of {REFERENCE_DRAG_COEFFICIENT}"
        )
        .into());
    }
    let (u0, u1) = (runs[0].mean_velocity(), runs[1].mean_velocity());
    let above = u1 > u0;
    if !above {
        return Err(format!(
            "bench cylinders --quick: ⟨u⟩ = {u1} at Wi = 0.2 not above the Newtonian {u0} (FEM: 1.0486 > 1.0183)"
        )
        .into());
    }
    Ok(())
}
