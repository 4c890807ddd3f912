//! Running a scene to files: the loop behind `viscosph run`, shared by the CLI, examples and tests.

use crate::io::{csv, plot, vtk};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use viscosph::budget::RunLength;
use viscosph::scene::{time_text, Outputs, Predictions, TimePlot};
use viscosph::simulation::Particles;
use viscosph::simulation::{SimError, Simulation};
use viscosph::SceneConfig;

/// Settings of one run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub t_end: f64,
    pub output_interval: f64,
    /// How many particle snapshots (VTK and panels of the particle PNG) to keep, evenly spread.
    pub snapshots: usize,
    pub out_dir: Option<PathBuf>,
    pub progress: bool,
    /// Run even when the estimated step count exceeds [`MAX_STEPS`].
    pub force: bool,
    /// Set (by a signal handler) to stop the run at its next step; the files are still written.
    pub stop: Option<Arc<AtomicBool>>,
    /// Time every pass of the steps (`viscosph run --profile`, the scaling benchmark): the
    /// result's `timings`.
    pub profile: bool,
}

/// Estimated step counts above this are refused without `force` (the library's rule, shared
/// with the FMU's `stopTime`).
pub use viscosph::budget::MAX_STEPS;

/// The files a run writes into its output folder: those of an earlier run there are removed
/// first (and nothing else), so the folder never mixes two runs' snapshots.
pub fn is_run_output(name: &str) -> bool {
    matches!(
        name,
        "timeseries.csv"
            | "walls.vtk"
            | "width_height.png"
            | "particles.png"
            | "particles_top.png"
            | "scene.toml"
            | "averaged_fields.csv"
            | "averaged_fields.vtk"
            | "averaged_particles.csv"
            | "centreline.csv"
    ) || (name.starts_with("particles_") && name.ends_with(".vtk"))
}

/// Characteristic time of a scene, the unit of t* (the scene's own, see
/// `viscosph::scene::Scene::time_scale`): D/V for a drop (Fang's t* = t V / D), D / sqrt(g D) if
/// V = 0; for the elliptical drop, an eighth of Ren's end time 0.008 s; H/U for the channel.
pub fn time_scale(cfg: &SceneConfig) -> f64 {
    let eff = cfg.effective();
    eff.scene_def().time_scale(&eff)
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
            force: false,
            stop: None,
            profile: false,
        }
    }
}

/// An error with the path and the operation that failed.
#[derive(Debug)]
pub struct FileError {
    pub operation: &'static str,
    pub path: PathBuf,
    pub source: Box<dyn std::error::Error>,
}

impl std::fmt::Display for FileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "cannot {} {}: {}",
            self.operation,
            self.path.display(),
            self.source
        )
    }
}

impl std::error::Error for FileError {}

/// Attach the operation and the path to a file error.
fn at<T, E: Into<Box<dyn std::error::Error>>>(
    r: Result<T, E>,
    operation: &'static str,
    path: &Path,
) -> Result<T, FileError> {
    r.map_err(|e| FileError {
        operation,
        path: path.to_path_buf(),
        source: e.into(),
    })
}

/// Create `dir` and remove the files an earlier run wrote there ([`is_run_output`]).
pub fn prepare_out_dir(dir: &Path) -> Result<usize, FileError> {
    at(
        std::fs::create_dir_all(dir),
        "create the output folder",
        dir,
    )?;
    let mut removed = 0;
    for e in at(std::fs::read_dir(dir), "list the output folder", dir)? {
        let e = at(e, "list the output folder", dir)?;
        let name = e.file_name().to_string_lossy().into_owned();
        if is_run_output(&name) && e.path().is_file() {
            at(
                std::fs::remove_file(e.path()),
                "remove the earlier run's file",
                &e.path(),
            )?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// The scene file that records a run: every parameter the run used, the automatic sound speed
/// replaced by the value chosen (so the file reruns the same flow), and for a scene that takes
/// only some parameters from the configuration (the elliptical drop) only those
/// (`Scene::taken_parameters`).
pub fn scene_record(cfg: &SceneConfig, eff: &SceneConfig) -> String {
    let mut c = cfg.clone();
    let mut head = String::new();
    if eff.numerics.sound_speed == 0.0 {
        c.numerics.sound_speed = eff.resolved_sound_speed();
        head = format!(
            "# sound_speed was automatic (0): {} x {:.4} m/s, the largest expected speed\n",
            viscosph::config::SOUND_SPEED_FACTOR,
            eff.max_expected_speed()
        );
    }
    let text = c.to_toml_string();
    match cfg.scene_def().taken_parameters() {
        Some((note, used)) => {
            head.push_str(note);
            for line in text.lines() {
                if used.iter().any(|u| line.starts_with(&format!("{u} = "))) {
                    head.push_str(line);
                    head.push('\n');
                }
            }
            head
        }
        None => head + &text,
    }
}

/// A one-line description of the sound speed a configuration runs with, for the CLI.
pub fn sound_speed_text(cfg: &SceneConfig, eff: &SceneConfig) -> String {
    let c = eff.resolved_sound_speed();
    if let Some(text) = cfg.scheme.sound_speed_text() {
        text.into()
    } else if cfg.numerics.sound_speed > 0.0 {
        format!("sound speed c = {c} m/s (set)")
    } else if let Some(own) = cfg.scene_def().own_sound_speed() {
        format!("sound speed c = {c} m/s ({own})")
    } else {
        format!(
            "sound speed c = {c:.3} m/s (automatic: {} x {:.3} m/s, impact speed plus free fall, plus max_plate_speed for the drop)",
            viscosph::config::SOUND_SPEED_FACTOR,
            eff.max_expected_speed()
        )
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
    /// What the scene says about the run (`Scene::summary`): e.g. the elliptical drop's
    /// semi-axis error, the jet's buckling.
    pub summary: Vec<String>,
    /// The state at the end (the last good one after a breakdown) of a 2D run; None in 3D.
    pub state: Option<viscosph::State>,
    /// Stopped by [`RunOptions::stop`] (a signal) before `t_end`, at this time.
    pub interrupted: Option<f64>,
    /// With [`RunOptions::profile`]: where the time of the steps went, per pass (empty
    /// otherwise).
    pub timings: viscosph::scheme::Timings,
    /// With [`RunOptions::profile`]: wall and CPU seconds between the steps (outputs, snapshots,
    /// files written during the run).
    pub between_steps: (f64, f64),
    /// Threads of the run's pool.
    pub threads: usize,
    /// The fields averaged over the steady window of a scene with a steady state
    /// (`Scene::steady_window`), from the outputs inside it; None if the run never got there.
    pub averages: Option<viscosph::scene::FieldAverage>,
}

impl RunResult {
    /// For benchmark tables: the largest trace of the conformation tensor over the recorded
    /// outputs to two decimals, or "-" for a model without one.
    pub fn max_trace_text(&self) -> String {
        let trace = self
            .series
            .iter()
            .map(|(_, o)| o.shared.max_conformation_trace)
            .fold(0.0, f64::max);
        if trace > 0.0 {
            format!("{trace:.2}")
        } else {
            "-".into()
        }
    }

    /// For benchmark tables: the breakdown's message, or "none".
    pub fn error_text(&self) -> String {
        self.error
            .as_ref()
            .map_or_else(|| "none".into(), |e| e.to_string())
    }

    /// Particle-steps per second of wall time.
    pub fn throughput(&self) -> f64 {
        self.particles as f64 * self.steps as f64 / self.wall_seconds.max(1e-12)
    }
}

/// The scalar a particle is coloured by: tr(A) for elastic models, speed otherwise.
pub fn colour_field(p: &Particles) -> (&'static str, Vec<f64>) {
    match &p.trace {
        Some(trace) => ("tr(A) [-]", trace.clone()),
        None => (
            "speed [m/s]",
            p.v.iter()
                .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
                .collect(),
        ),
    }
}

/// The field of a 3D top view: each particle's height above the plate (along its normal), or
/// z without a plate, in mm.
pub const HEIGHT_FIELD: &str = "height [mm]";

/// [`HEIGHT_FIELD`] of every fluid particle \[mm\].
fn heights(p: &Particles) -> Vec<f64> {
    let (o, n) = match p.plates.first() {
        Some((o, _, n)) => (*o, *n),
        None => ([0.0; 3], [0.0, 0.0, 1.0]),
    };
    p.x.iter()
        .map(|x| 1e3 * (0..3).map(|k| (x[k] - o[k]) * n[k]).sum::<f64>())
        .collect()
}

/// The views a snapshot shows: in 2D the plane of the flow; in 3D the side view (x, z) of the
/// section within one particle spacing of the plane y = 0 through the drop's centre and the
/// downhill line, coloured by [`colour_field`], and the top view (x, y) of every particle,
/// coloured by its height ([`HEIGHT_FIELD`]), the highest drawn last, each dot as wide as the
/// spacing ([`plot::Snapshot::splat`]).
fn snapshot(sim: &Simulation) -> Vec<plot::Snapshot> {
    let p = sim.particles();
    let eff = sim.effective_config();
    let dx = eff.dx();
    let values = colour_field(&p).1;
    let height = heights(&p);
    let title = sim.scene().time_label(eff, sim.time());
    // (horizontal axis, vertical axis, name of each, which points: all or the slab |y| < dx).
    let views: Vec<(usize, usize, (&str, &str), bool)> = if p.dimension == 3 {
        vec![(0, 2, ("x", "z"), true), (0, 1, ("x", "y"), false)]
    } else {
        vec![(0, 1, ("x", "y"), false)]
    };
    views
        .into_iter()
        .map(|(a, b, axes, slab)| {
            let keep = |q: &[f64; 3]| !slab || q[1].abs() < dx;
            let mut order: Vec<usize> = (0..p.x.len()).filter(|&i| keep(&p.x[i])).collect();
            let top = p.dimension == 3 && !slab;
            if top {
                order.sort_by(|&i, &j| height[i].total_cmp(&height[j]));
            }
            let field = if top { &height } else { &values };
            plot::Snapshot {
                title: title.clone(),
                // Every straight wall surface seen edge-on (the drop's plate, both channel
                // walls); seen from above a plate is the grey field of its wall particles.
                plates: p
                    .plates
                    .iter()
                    .filter(|_| p.dimension == 2 || b == 2)
                    .map(|(o, t, _)| plot::PlateLine {
                        point: (o[a], o[b]),
                        tangent: (t[a], t[b]),
                    })
                    .collect(),
                nozzle: sim.scene().inlet_mark(eff),
                spacing: dx,
                points: order.iter().map(|&i| (p.x[i][a], p.x[i][b])).collect(),
                values: order.iter().map(|&i| field[i]).collect(),
                walls: p
                    .walls
                    .iter()
                    .filter(|q| keep(q))
                    .step_by(2)
                    .map(|q| (q[a], q[b]))
                    .collect(),
                axes: (axes.0.to_string(), axes.1.to_string()),
                splat: top,
                outline: Vec::new(),
            }
        })
        .collect()
}

fn write_vtk(dir: &Path, k: usize, sim: &Simulation) -> Result<(), FileError> {
    let p = sim.particles();
    let (name, values) = colour_field(&p);
    let name = if name.starts_with("tr") {
        "trace_A"
    } else {
        "speed"
    };
    let path = dir.join(format!("particles_{k:04}.vtk"));
    at(
        vtk::write_particles(
            &path,
            &p.x,
            &p.v,
            &[
                vtk::Field {
                    name: "density",
                    values: &p.rho,
                },
                vtk::Field {
                    name,
                    values: &values,
                },
            ],
        ),
        "write",
        &path,
    )?;
    let path = dir.join("walls.vtk");
    at(
        vtk::write_particles(&path, &p.walls, &vec![[0.0; 3]; p.walls.len()], &[]),
        "write",
        &path,
    )
}

/// Append each view of one snapshot to its own sequence (`shots[v]` is view v over time).
fn push_views(shots: &mut Vec<Vec<plot::Snapshot>>, views: Vec<plot::Snapshot>) {
    shots.resize_with(views.len(), Vec::new);
    for (seq, view) in shots.iter_mut().zip(views) {
        seq.push(view);
    }
}

/// Advance to `t`; the simulation checks the stop flag (see `Simulation::set_stop_flag`) before
/// every step. Returns whether it stopped early.
fn advance_watching(sim: &mut Simulation, t: f64) -> Result<bool, SimError> {
    match sim.advance_to(t) {
        Ok(()) => Ok(false),
        Err(SimError::Interrupted { .. }) => Ok(true),
        Err(e) => Err(e),
    }
}

/// Run `cfg` to `opts.t_end`, recording outputs every `opts.output_interval`; with an output
/// directory (cleaned of an earlier run's files first), write `timeseries.csv`, VTK snapshots,
/// `width_height.png`, `particles.png` and `scene.toml`. A numerical breakdown or a stop request
/// ends the run early and is reported in the result; the files are still written, with the last
/// state as the final snapshot. Errors writing files name the operation and the path. The
/// scene's summary of the run may quote `predictions` (models outside the solver).
pub fn run(
    cfg: &SceneConfig,
    opts: &RunOptions,
    predictions: &dyn Predictions,
) -> Result<RunResult, Box<dyn std::error::Error>> {
    let mut sim = Simulation::new(cfg.clone())?;
    sim.set_profiling(opts.profile);
    let mut between = (0.0, 0.0);
    let ts = sim.scene().time_scale(sim.effective_config());
    let n_out = (opts.t_end / opts.output_interval).round().max(1.0) as usize;
    let snap_every = (n_out / opts.snapshots.max(1)).max(1);
    let start = std::time::Instant::now();
    let mut series = vec![(0.0, sim.outputs())];
    let mut shots: Vec<Vec<plot::Snapshot>> = Vec::new();
    push_views(&mut shots, snapshot(&sim));
    // One step first: the scheme's stable time step gives the run's length in steps, checked
    // before any file is touched. (Steps are never shortened to land on an output time, so this
    // does not change the trajectory.)
    let first = if n_out > 0 {
        sim.advance_to(f64::MIN_POSITIVE).map(|_| ())
    } else {
        Ok(())
    };
    if first.is_ok() && !opts.force {
        let what = format!("t_end = {} s", opts.t_end);
        // At the scheme's stable step after the first step (`State::last_dt`).
        let length = RunLength::at_step(
            opts.t_end - sim.state_time(),
            sim.last_dt(),
            sim.particle_count(),
        );
        if let Some(refusal) = length.too_long(&what) {
            return Err(format!(
                "{refusal}. Check --t-end (the default is t* = 8, {} s), or pass --force to run \
                 it anyway",
                8.0 * ts
            )
            .into());
        }
    }
    if let Some(d) = &opts.out_dir {
        prepare_out_dir(d)?;
        write_vtk(d, 0, &sim)?;
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
    let mut error = first.err();
    let mut interrupted = None;
    let reference_length = {
        let eff = sim.effective_config();
        sim.scene().reference_length(eff)
    };
    sim.set_stop_flag(opts.stop.clone());
    let mut averages: Option<viscosph::scene::FieldAverage> = None;
    for k in 1..=n_out {
        if error.is_some() {
            break;
        }
        let t = (k as f64 * opts.output_interval).min(opts.t_end);
        match advance_watching(&mut sim, t) {
            Err(e) => {
                error = Some(e);
                break;
            }
            Ok(true) => {
                // Stopped by a signal between outputs: one more row and the last state.
                interrupted = Some(sim.time());
                series.push((sim.time(), sim.outputs()));
                break;
            }
            Ok(false) => {}
        }
        let t_out = opts.profile.then(viscosph::profile::Stamp::now);
        let o = sim.outputs();
        series.push((sim.time(), o));
        if k % snap_every == 0 {
            push_views(&mut shots, snapshot(&sim));
            if let Some(d) = &opts.out_dir {
                write_vtk(d, k / snap_every, &sim)?;
            }
        }
        if let Some(b) = &bar {
            b.set_position(k as u64);
            b.set_message(format!(
                "t* = {:.2}  W* = {:.3}",
                t / ts,
                o.shared.drop_width / reference_length
            ));
        }
        if let Some(t) = t_out {
            let (wall, cpu) = t.elapsed();
            between.0 += wall;
            between.1 += cpu;
        }
        if steady_average(&sim, &mut averages) {
            break;
        }
    }
    if error.is_some() || interrupted.is_some() {
        // The last good state, where the cause can be looked at: one more panel of the
        // particle PNG and one more VTK snapshot.
        let mut views = snapshot(&sim);
        for shot in &mut views {
            // Short enough for one panel's width (a longer caption ran into the next panel).
            shot.title = format!(
                "t = {}, before {}",
                time_text(sim.state_time()),
                if error.is_some() {
                    "breakdown"
                } else {
                    "interrupt"
                }
            );
        }
        push_views(&mut shots, views);
        if let Some(d) = &opts.out_dir {
            write_vtk(d, shots[0].len() - 1, &sim)?;
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    // The scenes sum up a run: a 2D one from its state and outputs, a 3D one from its outputs.
    let summary = match sim.state_3d() {
        None => sim
            .scene()
            .summary(sim.effective_config(), sim.state(), &series, predictions),
        Some(st) => sim
            .scene()
            .summary_3d(sim.effective_config(), st, &series, predictions),
    };
    let result = RunResult {
        series,
        error,
        wall_seconds: start.elapsed().as_secs_f64(),
        steps: sim.steps(),
        particles: sim.particle_count(),
        wall_reflections: sim.wall_reflections(),
        summary,
        state: sim.state_3d().is_none().then(|| sim.state().clone()),
        interrupted,
        timings: sim.timings(),
        between_steps: between,
        threads: sim.threads(),
        averages,
    };
    if let Some(d) = &opts.out_dir {
        let path = d.join("timeseries.csv");
        at(csv::write_timeseries(&path, &result.series), "write", &path)?;
        let path = d.join("width_height.png");
        let t_last = sim.state_time();
        let ended = match (&result.error, interrupted) {
            (Some(_), _) => Some(("breakdown", t_last)),
            (None, Some(t)) => Some(("interrupted", t)),
            _ => None,
        };
        at(
            plot_width_height_marked(
                &path,
                sim.effective_config(),
                &[("".into(), &result.series)],
                ended,
            ),
            "write",
            &path,
        )?;
        let (field, _) = colour_field(&sim.particles());
        // particles.png: the plane of a 2D flow or the side view of a 3D one (a section
        // through the centre); particles_top.png: a 3D run seen from above.
        for (views, (name, what, field)) in shots.iter().zip([
            (
                "particles.png",
                if sim.dimension() == 3 {
                    ", side view of the section |y| < dx"
                } else {
                    ""
                },
                field,
            ),
            ("particles_top.png", ", seen from above", HEIGHT_FIELD),
        ]) {
            let field_name = field.split(" [").next().unwrap_or(field);
            let title = sim
                .scene()
                .snapshot_title(sim.effective_config(), field_name);
            let path = d.join(name);
            at(
                plot::particle_snapshots(
                    &path,
                    &format!("{title}{what}"),
                    views,
                    field,
                    sim.scene().snapshot_columns(views.len()),
                    (1700, 1250),
                ),
                "write",
                &path,
            )?;
        }
        let path = d.join("scene.toml");
        at(
            std::fs::write(&path, scene_record(cfg, sim.effective_config())),
            "write",
            &path,
        )?;
        if let Some(a) = &result.averages {
            write_averages(d, a)?;
        }
    }
    Ok(result)
}

/// Once a 2D flow is steady (`Scene::steady_window`): take the state at an output time inside
/// the window into the averages. Returns whether the run ends here (the window is complete and
/// the scene asks to stop there).
fn steady_average(sim: &Simulation, averages: &mut Option<viscosph::scene::FieldAverage>) -> bool {
    if sim.state_3d().is_some() {
        return false;
    }
    let (eff, st) = (sim.effective_config(), sim.state());
    let Some(window) = sim.scene().steady_window(eff, st) else {
        return false;
    };
    if st.time >= window.start && st.time <= window.end {
        averages
            .get_or_insert_with(|| viscosph::scene::FieldAverage::new(eff, window))
            .add(st);
    }
    // The record's time (an output time; the state may have stepped past it).
    window.stop && sim.time() >= window.end
}

/// The averaged fields of a steady run: `averaged_fields.csv` and `.vtk` (the grid's cells, a
/// point each, for ParaView), `averaged_particles.csv` (per particle, when the particles stayed
/// put: ISPH's Eulerian frame) and `centreline.csv` (the centre line, u over the mean velocity
/// of the cell's fluid).
pub fn write_averages(dir: &Path, a: &viscosph::scene::FieldAverage) -> Result<(), FileError> {
    use std::fmt::Write as _;
    let (samples, (t0, t1)) = a.samples();
    let cells = a.cells();
    let head = format!(
        "# time-averaged over {samples} states from t = {t0} s to {t1} s (steady at {} s), \
         Eulerian bins of one particle spacing\n",
        a.window().start
    );
    // One row of a field file: where, then u, v, speed, tr A, tau_xx, det A.
    let row = |c: &viscosph::Vec2, m: &[f64; 5]| {
        format!(
            "{},{},{},{},{},{},{},{}",
            c.x,
            c.y,
            m[0],
            m[1],
            m[0].hypot(m[1]),
            m[2],
            m[3],
            m[4]
        )
    };
    let mut csv = head.clone() + "x,y,u,v,speed,trace_A,tau_xx,det_A,particles\n";
    for (c, m, n) in &cells {
        let _ = writeln!(csv, "{},{n}", row(c, m));
    }
    let path = dir.join("averaged_fields.csv");
    at(std::fs::write(&path, csv), "write", &path)?;
    let points: Vec<[f64; 3]> = cells.iter().map(|(c, _, _)| [c.x, c.y, 0.0]).collect();
    let v: Vec<[f64; 3]> = cells.iter().map(|(_, m, _)| [m[0], m[1], 0.0]).collect();
    let column = |k: usize| cells.iter().map(|(_, m, _)| m[k]).collect::<Vec<_>>();
    let (trace, tau, det) = (column(2), column(3), column(4));
    let path = dir.join("averaged_fields.vtk");
    at(
        vtk::write_particles(
            &path,
            &points,
            &v,
            &[
                vtk::Field {
                    name: "trace_A",
                    values: &trace,
                },
                vtk::Field {
                    name: "tau_xx",
                    values: &tau,
                },
                vtk::Field {
                    name: "det_A",
                    values: &det,
                },
            ],
        ),
        "write",
        &path,
    )?;
    if let Some(particles) = a.particles() {
        let mut csv = head.clone() + "x,y,u,v,speed,trace_A,tau_xx,det_A\n";
        for (c, m) in &particles {
            let _ = writeln!(csv, "{}", row(c, m));
        }
        let path = dir.join("averaged_particles.csv");
        at(std::fs::write(&path, csv), "write", &path)?;
    }
    let mean = mean_speed(&cells);
    let mut csv = head + "x,u,u_over_mean,tau_xx,det_A,trace_A,particles\n";
    for (x, m, n) in a.centre_line() {
        let _ = writeln!(
            csv,
            "{x},{},{},{},{},{},{n}",
            m[0],
            m[0] / mean,
            m[3],
            m[4],
            m[2]
        );
    }
    let path = dir.join("centreline.csv");
    at(std::fs::write(&path, csv), "write", &path)
}

/// The mean of u over the grid's cells weighted by the particles seen in them: the mean
/// velocity ⟨u⟩ of the fluid over the window.
pub fn mean_speed(cells: &[(viscosph::Vec2, [f64; 5], u64)]) -> f64 {
    let (sum, n) = cells.iter().fold((0.0, 0u64), |(s, c), (_, m, n)| {
        (s + m[0] * *n as f64, c + n)
    });
    if n > 0 {
        sum / n as f64
    } else {
        f64::NAN
    }
}

/// The scene's plot of its outputs against time (`Scene::time_plot`: W* = width/D and
/// H* = height/D against t* = t V/D for the drops and the jet, one line per labelled series.
pub fn plot_width_height(
    path: &Path,
    cfg: &SceneConfig,
    runs: &[(String, &[(f64, Outputs)])],
) -> Result<(), Box<dyn std::error::Error>> {
    plot_width_height_marked(path, cfg, runs, None)
}

/// [`plot_width_height`], with a note in the titles when the run ended early: `ended` is
/// why ("breakdown", "interrupted") and the time of the last good state.
pub fn plot_width_height_marked(
    path: &Path,
    cfg: &SceneConfig,
    runs: &[(String, &[(f64, Outputs)])],
    ended: Option<(&str, f64)>,
) -> Result<(), Box<dyn std::error::Error>> {
    let TimePlot {
        time_unit,
        x_label,
        panels,
    } = cfg.scene_def().time_plot(cfg);
    let note = match ended {
        Some(("breakdown", t)) => format!(" (breakdown after t = {})", time_text(t)),
        Some((why, t)) => format!(" ({why} at t = {})", time_text(t)),
        None => String::new(),
    };
    let panels: Vec<plot::Panel> = panels
        .into_iter()
        .map(|p| plot::Panel {
            title: p.title + &note,
            x_label: x_label.clone(),
            y_label: p.y_label,
            series: runs
                .iter()
                .map(|(label, s)| plot::Series {
                    label: label.clone(),
                    points: s
                        .iter()
                        .map(|(t, o)| (t / time_unit, (p.value)(o)))
                        .collect(),
                })
                .collect(),
            log: (false, false),
        })
        .collect();
    plot::line_panels(path, &panels, 2, (1400, 600))
}
