//! `viscosph bench drop`: Fang's Newtonian and Oldroyd-B drops at 20, 40 and 80 particles per
//! diameter: wall time, steps, particle-steps per second, and the largest difference of W*(t*)
//! from the finest run.

use super::{fang_cases, max_width_difference};
use crate::io::plot::{line_panels, Panel, Series};
use crate::run::{run, time_scale, RunOptions};
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::Value;
use viscosph::scene::Outputs;
use viscosph::scene::SceneConfig;

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
            let r = run(&cfg, &opts, &crate::predictions::ReferenceModels)?;
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
        let d = base.drop.drop_diameter;
        for row in &mut group {
            row.w_diff = max_width_difference(&row.series, &finest, d);
        }
        rows.extend(group);
    }
    Ok(rows)
}

pub fn bench_drop(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let ppds: &[i64] = if quick { &[10, 14, 20] } else { &[20, 40, 80] };
    let t_star_end = if quick { 3.0 } else { 8.0 };
    let rows = drop_convergence(&fang_cases(), ppds, t_star_end)?;
    // CSV, Markdown table, PNG.
    let mut csv = String::from("case,particles_per_diameter,particles,steps,wall_seconds,particle_steps_per_second,max_w_star_difference_from_finest,wall_reflections,error\n");
    let resolutions: Vec<String> = ppds.iter().map(|p| p.to_string()).collect();
    let mut md = format!(
        "WCSPH (Fang et al. 2006) on Fang's Newtonian and Oldroyd-B drops (D = 20 mm, V = 1 m/s) \
         at {} particles per diameter to t* = {t_star_end}: steps, cost, the largest difference of \
         W*(t*) to the finest run, how often a particle was put back above the plate, and \
         breakdowns.\n\n",
        resolutions.join("/")
    );
    md.push_str("| case | particles/D | particles | steps | wall time [s] | particle-steps/s | max \\|ΔW*\\| vs finest | put back above the plate | breakdown |\n|---|---|---|---|---|---|---|---|---|\n");
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
    let d = cfg.drop.drop_diameter;
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
                        .map(|(t, o)| (t / ts, o.shared.drop_width / d))
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
