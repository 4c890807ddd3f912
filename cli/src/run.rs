//! Running a scene to files: the loop behind `viscosph run`, shared by the CLI, examples and tests.

use crate::io::{csv, plot, vtk};
use std::path::{Path, PathBuf};
use viscosph::diagnostics::Outputs;
use viscosph::simulation::{SimError, Simulation};
use viscosph::{SceneConfig, Vec2};

/// Settings of one run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub t_end: f64,
    pub output_interval: f64,
    /// How many particle snapshots (VTK and panels of the particle PNG) to keep, evenly spread.
    pub snapshots: usize,
    pub out_dir: Option<PathBuf>,
    pub progress: bool,
}

/// Characteristic time of a scene, the unit of t*: D/V for a drop (Fang's t* = t V / D),
/// D / sqrt(g D) if V = 0; for the elliptical drop, an eighth of Ren's end time 0.008 s.
pub fn time_scale(cfg: &SceneConfig) -> f64 {
    if cfg.scene == viscosph::config::Scene::EllipticalDrop {
        return viscosph::scene::elliptical_drop::TIME_SCALE;
    }
    let v = if cfg.impact_velocity > 0.0 {
        cfg.impact_velocity
    } else {
        (cfg.gravity * cfg.drop_diameter).sqrt().max(1e-12)
    };
    cfg.drop_diameter / v
}

impl RunOptions {
    /// Defaults for a scene: to t* = 8 (Fang's figures), an output every t* = 0.05, 8 snapshots.
    pub fn for_scene(cfg: &SceneConfig) -> Self {
        let ts = time_scale(cfg);
        Self {
            t_end: 8.0 * ts,
            output_interval: 0.05 * ts,
            snapshots: 8,
            out_dir: None,
            progress: false,
        }
    }
}

/// What a run produced.
#[derive(Debug, Clone)]
pub struct RunResult {
    pub series: Vec<(f64, Outputs)>,
    /// The breakdown that stopped the run early, if any.
    pub error: Option<SimError>,
    pub wall_seconds: f64,
    pub steps: u64,
    pub particles: usize,
    /// Particles put back above the plate by the impenetrability condition of Fang's walls.
    pub wall_reflections: u64,
    /// For the elliptical drop: the semi-axes at the end against the exact ones.
    pub elliptical: Option<viscosph::scene::elliptical_drop::SemiAxes>,
}

impl RunResult {
    /// Particle-steps per second of wall time.
    pub fn throughput(&self) -> f64 {
        self.particles as f64 * self.steps as f64 / self.wall_seconds.max(1e-12)
    }
}

/// The scalar a particle is coloured by: tr(A) for elastic models, speed otherwise.
pub fn colour_field(sim: &Simulation) -> (&'static str, Vec<f64>) {
    let f = &sim.state().fluid;
    if f.conf.is_empty() {
        ("speed [m/s]", f.v.iter().map(|v| v.norm()).collect())
    } else {
        ("tr(A)", f.conf.iter().map(|a| a.trace()).collect())
    }
}

fn snapshot(sim: &Simulation, ts: f64) -> plot::Snapshot {
    let f = &sim.state().fluid;
    plot::Snapshot {
        title: format!("t* = {:.2}", sim.time() / ts),
        points: f.x.iter().map(|p| (p.x, p.y)).collect(),
        values: colour_field(sim).1,
        walls: sim
            .wall_positions()
            .iter()
            .step_by(2)
            .map(|p| (p.x, p.y))
            .collect(),
    }
}

fn write_vtk(dir: &Path, k: usize, sim: &Simulation) -> std::io::Result<()> {
    let f = &sim.state().fluid;
    let p: Vec<f64> = f.rho.clone();
    let (name, values) = colour_field(sim);
    let name = if name.starts_with("tr") {
        "trace_A"
    } else {
        "speed"
    };
    vtk::write_particles(
        &dir.join(format!("particles_{k:04}.vtk")),
        &f.x,
        &f.v,
        &[
            vtk::Field {
                name: "density",
                values: &p,
            },
            vtk::Field {
                name,
                values: &values,
            },
        ],
    )?;
    let w = sim.wall_positions();
    vtk::write_particles(
        &dir.join("walls.vtk"),
        &w,
        &vec![Vec2::zeros(); w.len()],
        &[],
    )
}

/// Run `cfg` to `opts.t_end`, recording outputs every `opts.output_interval`; with an output
/// directory, write `timeseries.csv`, VTK snapshots, `width_height.png` and `particles.png`.
/// A numerical breakdown stops the run and is returned in the result (files are still written,
/// with the last good state as the final snapshot).
pub fn run(cfg: &SceneConfig, opts: &RunOptions) -> Result<RunResult, Box<dyn std::error::Error>> {
    let mut sim = Simulation::new(cfg.clone())?;
    let ts = time_scale(cfg);
    let n_out = (opts.t_end / opts.output_interval).round().max(1.0) as usize;
    let snap_every = (n_out / opts.snapshots.max(1)).max(1);
    if let Some(d) = &opts.out_dir {
        std::fs::create_dir_all(d)?;
    }
    let bar = if opts.progress {
        let b = indicatif::ProgressBar::new(n_out as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} outputs  {msg}  [{elapsed_precise} < {eta_precise}]",
            )
            .expect("valid template"),
        );
        Some(b)
    } else {
        None
    };
    let start = std::time::Instant::now();
    let mut series = vec![(0.0, sim.outputs())];
    let mut shots = vec![snapshot(&sim, ts)];
    let mut error = None;
    if let Some(d) = &opts.out_dir {
        write_vtk(d, 0, &sim)?;
    }
    for k in 1..=n_out {
        let t = (k as f64 * opts.output_interval).min(opts.t_end);
        if let Err(e) = sim.advance_to(t) {
            // The last good state, where the cause can be looked at: one more panel of the
            // particle PNG and one more VTK snapshot.
            let mut shot = snapshot(&sim, ts);
            shot.title = format!(
                "t* = {:.3}, last state before the breakdown",
                sim.state().time / ts
            );
            shots.push(shot);
            if let Some(d) = &opts.out_dir {
                write_vtk(d, shots.len() - 1, &sim)?;
            }
            error = Some(e);
            break;
        }
        let o = sim.outputs();
        series.push((sim.time(), o));
        if k % snap_every == 0 {
            shots.push(snapshot(&sim, ts));
            if let Some(d) = &opts.out_dir {
                write_vtk(d, k / snap_every, &sim)?;
            }
        }
        if let Some(b) = &bar {
            b.set_position(k as u64);
            b.set_message(format!(
                "t* = {:.2}  W* = {:.3}",
                t / ts,
                o.drop_width / cfg.drop_diameter
            ));
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let result = RunResult {
        series,
        error,
        wall_seconds: start.elapsed().as_secs_f64(),
        steps: sim.state().step,
        particles: sim.state().fluid.len(),
        wall_reflections: sim.state().wall_reflections,
        elliptical: sim.elliptical_semi_axes(),
    };
    if let Some(d) = &opts.out_dir {
        csv::write_timeseries(&d.join("timeseries.csv"), &result.series)?;
        plot_width_height(
            &d.join("width_height.png"),
            cfg,
            &[("".into(), &result.series)],
        )?;
        let (field, _) = colour_field(&sim);
        let view = view_of(&shots);
        plot::particle_snapshots(
            &d.join("particles.png"),
            &shots,
            field,
            3,
            view,
            (1500, 1100),
        )?;
        std::fs::write(d.join("scene.toml"), cfg.to_toml_string())?;
    }
    Ok(result)
}

/// A window holding every snapshot's particles, with a margin.
fn view_of(shots: &[plot::Snapshot]) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for s in shots {
        for p in &s.points {
            x0 = x0.min(p.0);
            x1 = x1.max(p.0);
            y0 = y0.min(p.1);
            y1 = y1.max(p.1);
        }
    }
    let m = 0.08 * (x1 - x0).max(y1 - y0);
    ((x0 - m, x1 + m), (y0 - 3.0 * m, y1 + m))
}

/// W* = width/D and H* = height/D against t* = t V/D, one line per labelled series.
pub fn plot_width_height(
    path: &Path,
    cfg: &SceneConfig,
    runs: &[(String, &[(f64, Outputs)])],
) -> Result<(), Box<dyn std::error::Error>> {
    let ts = time_scale(cfg);
    let d = cfg.drop_diameter;
    let mk = |f: fn(&Outputs) -> f64| {
        runs.iter()
            .map(|(label, s)| plot::Series {
                label: label.clone(),
                points: s.iter().map(|(t, o)| (t / ts, f(o) / d)).collect(),
            })
            .collect::<Vec<_>>()
    };
    plot::line_panels(
        path,
        &[
            plot::Panel {
                title: "width W* = W/D".into(),
                x_label: "t* = t V / D".into(),
                y_label: "W*".into(),
                series: mk(|o| o.drop_width),
                log: (false, false),
            },
            plot::Panel {
                title: "height H* = H/D".into(),
                x_label: "t* = t V / D".into(),
                y_label: "H*".into(),
                series: mk(|o| o.drop_height),
                log: (false, false),
            },
        ],
        2,
        (1400, 550),
    )
}
