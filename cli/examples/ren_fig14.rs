//! Ren, Lu & Jiang 2015 Fig. 14: the front and back elongations X_front, X_back of a Newtonian
//! and a Cross drop spreading on plates inclined at 15, 30 and 45 degrees, against t* = t V / D,
//! under PDRI-SPH. Writes `results/ren_fig14.png` (and prints the values at t* = 8).
//!
//! `cargo run --release --example ren_fig14 [particles_per_diameter]` (default 40, 1264 fluid
//! particles, a few minutes on two cores; Ren uses 100, 7845 particles).
//!
//! Ren's sign convention (Fig. 5b): X_back > 0 uphill of the impact point, X_front < 0 downhill;
//! here X_back = spread_back / D and X_front = -spread_front / D.

use viscosph::config::Value;
use viscosph::scene::SceneConfig;
use viscosph_cli::io::plot::{line_panels, Panel, Series};
use viscosph_cli::run::{run, time_scale, RunOptions};

fn config(rheology: &str, angle: f64, ppd: i64) -> SceneConfig {
    let mut c = SceneConfig::default();
    for (k, v) in [
        ("scheme", Value::Text("pdri".into())),
        ("rheology", Value::Text(rheology.into())),
        ("viscosity", Value::Real(4.0)),
        ("cross_viscosity_inf", Value::Real(0.4)),
        ("cross_K", Value::Real(1.0)),
        ("cross_m", Value::Real(1.0)),
        ("sound_speed", Value::Real(12.0)),
        ("artificial_stress_kind", Value::Text("ren".into())),
        ("artificial_stress_b", Value::Real(0.8)),
        ("density_reinit_interval", Value::Integer(20)),
        ("plate_inclination", Value::Real(angle)),
        ("particles_per_diameter", Value::Integer(ppd)),
    ] {
        c.set(k, v).expect("valid parameter");
    }
    c
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let ppd: i64 = match std::env::args().nth(1) {
        Some(a) => a.parse()?,
        None => 40,
    };
    let mut panels = Vec::new();
    for (rheology, title) in [("newtonian", "Newtonian"), ("cross", "Cross")] {
        let mut series = Vec::new();
        for angle in [15.0, 30.0, 45.0] {
            let cfg = config(rheology, angle, ppd);
            let ts = time_scale(&cfg);
            let opts = RunOptions {
                output_interval: 0.1 * ts,
                ..RunOptions::for_scene(&cfg)
            };
            let res = run(&cfg, &opts, &viscosph::scene::NoPredictions)?;
            if let Some(e) = &res.error {
                println!("{title} {angle} deg stopped: {e}");
            }
            let d = cfg.drop.drop_diameter;
            let (t_last, o) = res.series.last().expect("at least the initial output");
            println!(
                "{title} {angle:>2} deg: t* = {:.2}, X_front = {:+.3}, X_back = {:+.3} \
                 ({} particles, {} steps, {:.1} s)",
                t_last / ts,
                -o.shared.spread_front / d,
                o.shared.spread_back / d,
                res.particles,
                res.steps,
                res.wall_seconds
            );
            let pick = |f: &dyn Fn(&viscosph::Outputs) -> f64| {
                res.series
                    .iter()
                    .map(|(t, o)| (t / ts, f(o) / d))
                    .collect::<Vec<_>>()
            };
            series.push(Series {
                label: format!("X_front {angle} deg"),
                points: pick(&|o| -o.shared.spread_front),
            });
            series.push(Series {
                label: format!("X_back {angle} deg"),
                points: pick(&|o| o.shared.spread_back),
            });
        }
        panels.push(Panel {
            title: format!("{title} drop on inclined plates (PDRI-SPH, Ren 2015 Fig. 14)"),
            x_label: "t* = t V / D [-]".into(),
            y_label: "X_back / D > 0 (uphill), X_front / D < 0 [-]".into(),
            series,
            log: (false, false),
        });
    }
    std::fs::create_dir_all("results")?;
    let path = std::path::Path::new("results/ren_fig14.png");
    line_panels(path, &panels, 2, (1600, 650))?;
    println!("wrote {}", path.display());
    Ok(())
}
