//! `viscosph exact <model>`: the exact and model solutions the validation gallery
//! (`validation/<case>/`) compares the SPH runs with, as CSV on stdout. The solutions themselves
//! live in the solver's scene modules and in `viscosph-reference`; this command only samples them,
//! so that a script outside Rust compares against the same code the tests and the bench use.

use clap::Subcommand;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use viscosph::scene::elliptical_drop;
use viscosph::SceneConfig;
use viscosph_reference::analytic::waters_king::WatersKing;
use viscosph_reference::analytic::{falling_sheet, falling_thread};

#[derive(Subcommand, Debug)]
pub enum ExactKind {
    /// Monaghan's elliptical drop (the exact ODE of the `elliptical_drop` scene): time,
    /// semi-minor and semi-major axis \[m\] from t = 0 to --t-end; with `--dimension 3`, the
    /// sphere's three semi-axes along x, y and z.
    EllipticalDrop {
        /// 2 (Monaghan's ellipse) or 3 (the sphere under u = A0 (-x, y, 0)).
        #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
        dimension: u8,
        /// End time \[s\].
        #[arg(long, default_value_t = elliptical_drop::T_END)]
        t_end: f64,
        /// Time between rows \[s\].
        #[arg(long, default_value_t = elliptical_drop::T_END / 160.0)]
        interval: f64,
    },
    /// Waters & King 1970's start-up of plane Poiseuille flow for a channel scene file (its
    /// density, viscosity, viscosity ratio, relaxation time, width and body force): time and
    /// centre-line velocity \[m/s\] from t = 0 to --t-end.
    WatersKing {
        /// Scene file (TOML) of a channel.
        scene: PathBuf,
        /// End time \[s\].
        #[arg(long)]
        t_end: f64,
        /// Time between rows \[s\].
        #[arg(long)]
        interval: f64,
    },
    /// The slender-sheet model of a jet scene file: the time its leading end reaches the plate
    /// \[s\], its speed then \[m/s\] and its smallest width \[m\].
    FallingSheet {
        /// Scene file (TOML) of a jet.
        scene: PathBuf,
    },
    /// The slender-thread model (Matovich & Pearson 1969) of a round jet's scene file: the
    /// time its leading end reaches the plate \[s\], its speed then \[m/s\], its smallest
    /// diameter \[m\] and the mass below the exit then \[kg\].
    FallingThread {
        /// Scene file (TOML) of a jet (its `jet_width` the nozzle's diameter).
        scene: PathBuf,
    },
}

fn scene(path: &Path) -> Result<SceneConfig, Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Ok(SceneConfig::from_toml_str(&text).map_err(|e| format!("{}: {e}", path.display()))?)
}

/// The times 0, dt, 2 dt, ... up to t_end (inclusive within a millionth of a step).
fn times(t_end: f64, dt: f64) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
    if !(t_end > 0.0 && dt > 0.0 && t_end / dt <= 1e6) {
        return Err("--t-end and --interval must be positive, at most 10^6 rows".into());
    }
    let n = (t_end / dt + 1e-6).floor() as usize;
    Ok((0..=n).map(|k| k as f64 * dt).collect())
}

/// The CSV text of the solution asked for.
pub fn exact_csv(kind: &ExactKind) -> Result<String, Box<dyn std::error::Error>> {
    let mut out = String::new();
    match kind {
        ExactKind::EllipticalDrop {
            dimension: 3,
            t_end,
            interval,
        } => {
            writeln!(out, "time,semi_axis_x,semi_axis_y,semi_axis_z")?;
            for t in times(*t_end, *interval)? {
                let [x, y, z] = elliptical_drop::exact_axes::<3>(t)
                    .a
                    .map(|a| a * elliptical_drop::RADIUS);
                writeln!(out, "{t:.9e},{x:.12e},{y:.12e},{z:.12e}")?;
            }
        }
        ExactKind::EllipticalDrop {
            t_end, interval, ..
        } => {
            writeln!(out, "time,semi_minor,semi_major")?;
            for t in times(*t_end, *interval)? {
                let e = elliptical_drop::exact(t);
                let r = elliptical_drop::RADIUS;
                writeln!(out, "{t:.9e},{:.12e},{:.12e}", e.a * r, r / e.a)?;
            }
        }
        ExactKind::WatersKing {
            scene: path,
            t_end,
            interval,
        } => {
            let cfg = scene(path)?;
            let wk =
                WatersKing::from_config(&cfg, cfg.channel.channel_width, cfg.channel.body_force)?;
            writeln!(out, "time,centreline_velocity")?;
            for t in times(*t_end, *interval)? {
                writeln!(out, "{t:.9e},{:.12e}", wk.centreline_velocity(t))?;
            }
        }
        ExactKind::FallingSheet { scene: path } => {
            let cfg = scene(path)?;
            let a = falling_sheet::arrival(&cfg, falling_sheet::ELEMENTS_PER_WIDTH, 10.0)
                .ok_or("the slender-sheet model does not reach the plate within 10 s")?;
            writeln!(out, "arrival_time,tip_speed,min_width")?;
            writeln!(
                out,
                "{:.9e},{:.9e},{:.9e}",
                a.time, a.tip_speed, a.min_width
            )?;
        }
        ExactKind::FallingThread { scene: path } => {
            let cfg = scene(path)?;
            let a = falling_thread::arrival(&cfg, falling_thread::ELEMENTS_PER_DIAMETER, 10.0)
                .ok_or("the slender-thread model does not reach the plate within 10 s")?;
            writeln!(out, "arrival_time,tip_speed,min_diameter,mass")?;
            writeln!(
                out,
                "{:.9e},{:.9e},{:.9e},{:.9e}",
                a.time, a.tip_speed, a.min_width, a.mass
            )?;
        }
    }
    Ok(out)
}
