//! `viscosph bench stability`: stability maps of the drop: the largest stable De per scheme and
//! elastic rheology, and one-parameter sweeps of beta, inclination, impact velocity and
//! resolution. `--dimension 3` runs the De map and the sweeps on the sphere (20 particles per
//! diameter by default) into `stability_3d.*`, the 2D limits beside the 3D ones.

use super::built_schemes;
use crate::io::plot::status_grid;
use crate::run::time_scale;
use clap::Args;
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::{RheologyKind, RHEOLOGIES};
use viscosph::scene::{SceneConfig, SchemeKind};
use viscosph::simulation::Simulation;

/// Options of `viscosph bench stability`.
#[derive(Args, Debug, Clone)]
pub struct StabilityArgs {
    /// Which part: the map of the largest stable De per scheme and rheology, the one-parameter
    /// sweeps of the Oldroyd-B drop, or both.
    #[arg(long, value_enum, default_value = "all")]
    pub part: StabilityPart,
    /// Particles per diameter of the De map and of the one-parameter sweeps; default 40 in 2D
    /// (at 20 every case was stable up to the largest De tried, which measures little) and 20
    /// in 3D (a sphere at 20 per diameter is 4,000 particles, at 40 already 34,000).
    #[arg(long)]
    pub resolution: Option<i64>,
    /// 2: Fang's disc; 3: the sphere on a plane (results in `stability_3d.*`, PNGs
    /// `stability_3d_*.png`, with the 2D limits of `stability.csv` in the same directory, if
    /// there, beside the 3D ones).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(i64).range(2..=3))]
    pub dimension: i64,
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

/// The models with a relaxation time (a Deborah number to sweep).
pub fn elastic_rheologies() -> Vec<RheologyKind> {
    RHEOLOGIES
        .iter()
        .filter_map(|(n, _)| RheologyKind::parse(n))
        .filter(|r| !matches!(r, RheologyKind::Newtonian | RheologyKind::Cross))
        .collect()
}

pub fn bench_stability(
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
    let three = args.dimension == 3;
    // The De map and the one-parameter sweeps run at `--resolution` (40 by default in 2D: at
    // 20 ISPH loses single particles at the contact line of Fang's drop, and every weakly
    // compressible case was stable, which measured little; 20 in 3D, 8 with --quick); the
    // resolution sweep goes from 12 to 60 (2D) or 10 to 30 (3D).
    let ppd: i64 = match (quick, three) {
        (true, false) => 12,
        (true, true) => 8,
        (false, _) => args.resolution.unwrap_or(if three { 20 } else { 40 }),
    };
    // Every file of a 3D run carries `_3d` after `stability`, so the 2D results stay.
    let stem = if three { "stability_3d" } else { "stability" };
    let file = |rest: &str| out.join(format!("{stem}{rest}"));
    // The 2D limits beside the 3D ones: the last value each 2D sweep found stable.
    let limits_2d = if three {
        std::fs::read_to_string(out.join("stability.csv")).unwrap_or_default()
    } else {
        String::new()
    };
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
    let base = |scheme: SchemeKind, rheo: RheologyKind, ppd: i64| {
        let mut c = SceneConfig {
            scheme,
            ..Default::default()
        };
        c.fluid.rheology = rheo;
        c.numerics.particles_per_diameter = ppd;
        c.numerics.dimension = args.dimension;
        c
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
            c.scheme, c.fluid.rheology
        );
    };

    // 1. Deborah number De = lambda V / D, per scheme and elastic rheology (beta = 0.1), in
    // ascending decades until the first breakdown (the larger values are then not run).
    if args.part != StabilityPart::Sweeps {
        writeln!(md, "### Largest stable De ({}drop to t* = {t_star_end}, {ppd_de} particles per diameter, beta = 0.1)\n", if three { "3D: the sphere; " } else { "" })?;
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
            "| scheme | rheology | largest stable De | largest tried | first failure | wall time [s] |{}\n|---|---|---|---|---|---|{}",
            if three { " most severe stable in 2D |" } else { "" },
            if three { "---|" } else { "" },
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
                    c.fluid.relaxation_time = de * c.drop.drop_diameter / c.drop.impact_velocity;
                    eprintln!("bench stability: {scheme} {rheo} De = {de} ...");
                    let o = classify(&c, t_star_end);
                    record(&mut csv, "deborah", &c, "De", de, &o);
                    // Row by row, so a sweep of hours stopped early keeps what it measured.
                    std::fs::write(file(".csv"), &csv)?;
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
                    "| {scheme} | {rheo} | {} | {tried} | {first_fail} | {wall:.0} |{}",
                    best.map(|d| d.to_string())
                        .unwrap_or(format!("< {}", des[0])),
                    if three {
                        format!(
                            " {} |",
                            last_stable(&limits_2d, "deborah", scheme.as_str(), rheo.as_str())
                        )
                    } else {
                        String::new()
                    }
                )?;
                cells.push(row);
            }
            status_grid(
                &file(&format!("_de_{scheme}.png")),
                &format!(
                    "{}{scheme}, {ppd_de} per diameter: stable (green) / broken (red) / not run (grey) against De",
                    if three { "3D sphere, " } else { "" }
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
        std::fs::write(file(".csv"), &csv)?;
        std::fs::write(file(".md"), &md)?;
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
            |c, v| c.fluid.viscosity_ratio = v,
            true,
        ),
        (
            "inclination",
            "plate_inclination [deg]",
            // From 75 degrees the default drop (centre 2 D above the impact point) starts
            // within a particle spacing of the plate: validation refuses it.
            vec![0.0, 15.0, 30.0, 45.0, 60.0, 70.0],
            |c, v| c.plate.plate_inclination = v,
            true,
        ),
        (
            "velocity",
            "impact_velocity [m/s]",
            vec![0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0],
            |c, v| {
                // keep De = 1 as V changes
                c.fluid.relaxation_time = c.drop.drop_diameter / v;
                c.drop.impact_velocity = v;
            },
            true,
        ),
        (
            "resolution",
            "particles_per_diameter",
            if three {
                vec![10.0, 16.0, 20.0, 30.0]
            } else {
                vec![12.0, 16.0, 20.0, 30.0, 40.0, 60.0]
            },
            |c, v| c.numerics.particles_per_diameter = v as i64,
            false,
        ),
    ];
    writeln!(
        md,
        "\n### One-parameter sweeps ({}Oldroyd-B, De = 1 unless swept, {ppd} particles per diameter unless swept, drop to t* = {t_star_end})\n",
        if three { "3D: the sphere; " } else { "" }
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
                std::fs::write(file(".csv"), &csv)?;
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
            let beside = if three {
                format!(
                    " (2D: most severe stable value {})",
                    last_stable(&limits_2d, name, scheme.as_str(), "oldroyd_b")
                )
            } else {
                String::new()
            };
            writeln!(
                summary,
                "- {scheme}: stable at {}; {}{beside}",
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
            &file(&format!("_{name}.png")),
            &format!(
                "{}Oldroyd-B drop, De = 1: stable (green) / broken (red) / not run (grey) against {label}",
                if three { "3D sphere, " } else { "" }
            ),
            label,
            "scheme",
            &values.iter().map(|d| d.to_string()).collect::<Vec<_>>(),
            &schemes.iter().map(|s| s.to_string()).collect::<Vec<_>>(),
            &cells,
        )?;
    }
    std::fs::write(file(".csv"), &csv)?;
    std::fs::write(file(".md"), &md)?;
    Ok(md)
}

/// The most severe value a sweep of `stability.csv` (text `csv`) found stable for `scheme` and
/// `rheology`: the last stable row (each sweep runs from the mildest value to the most severe;
/// the resolution sweep's rows all run, so there it is the finest): "-" when the file has no
/// such rows, "none" when every row broke.
fn last_stable(csv: &str, sweep: &str, scheme: &str, rheology: &str) -> String {
    let mut seen = false;
    let mut last: Option<&str> = None;
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.splitn(7, ',').collect();
        if f.len() < 6 || f[0] != sweep || f[1] != scheme || f[2] != rheology {
            continue;
        }
        seen = true;
        if f[5] == "stable" {
            last = Some(f[4]);
        }
    }
    match (seen, last) {
        (false, _) => "-".into(),
        (true, None) => "none".into(),
        (true, Some(v)) => v.into(),
    }
}
