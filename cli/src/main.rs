//! `viscosph`: run a scene file (or the embedded default) and write results, or benchmark.

use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use viscosph::SceneConfig;
use viscosph_cli::predictions::ReferenceModels;
use viscosph_cli::run::{run, sound_speed_text, RunOptions};

#[derive(Parser)]
#[command(
    name = "viscosph",
    version,
    about = "Viscoelastic free-surface flows by SPH"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene: a flat TOML file whose keys are the FMU parameter names (missing keys take
    /// their defaults); without a file, Fang 2006's Oldroyd-B drop.
    Run {
        /// Scene file (TOML).
        scene: Option<PathBuf>,
        /// Output directory: timeseries.csv, particles_*.vtk, walls.vtk, width_height.png,
        /// particles.png, scene.toml. Those files left there by an earlier run are removed first
        /// (other files are left alone).
        #[arg(long)]
        out: PathBuf,
        /// End time \[s\]; default t* = 8, i.e. 8 D/V.
        #[arg(long)]
        t_end: Option<f64>,
        /// Time between rows of timeseries.csv \[s\]; default t* = 0.05.
        #[arg(long)]
        output_interval: Option<f64>,
        /// Run even if the run would take more than 10^8 steps.
        #[arg(long)]
        force: bool,
        /// Time every pass of the steps (wall and CPU seconds, which parts run on one thread)
        /// and print the table at the end.
        #[arg(long)]
        profile: bool,
    },
    /// Print the default scene file with every parameter.
    DefaultScene,
    /// Benchmarks: see `viscosph bench --help`.
    Bench(viscosph_cli::bench::BenchArgs),
    /// Sample an exact or model solution the validation gallery compares with (CSV on stdout).
    #[command(subcommand)]
    Exact(viscosph_cli::exact::ExactKind),
    /// Write the manual's generated tables (parameters, outputs, choices, FMU variables) as
    /// markdown files into a directory (docs/book/src/generated).
    DocsTables {
        /// Output directory.
        dir: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run {
            scene,
            out,
            t_end,
            output_interval,
            force,
            profile,
        } => {
            let cfg = match scene {
                Some(path) => match std::fs::read_to_string(&path)
                    .map_err(|e| format!("cannot read the scene file: {e}"))
                    .and_then(|t| SceneConfig::from_toml_str(&t).map_err(|e| e.to_string()))
                {
                    Ok(c) => c,
                    Err(e) => {
                        eprintln!("error: {}: {e}", path.display());
                        return ExitCode::from(2);
                    }
                },
                None => SceneConfig::default(),
            };
            let mut opts = RunOptions::for_scene(&cfg);
            if let Some(t) = t_end {
                opts.t_end = t;
            }
            if let Some(dt) = output_interval {
                opts.output_interval = dt;
            }
            if !(opts.t_end > 0.0 && opts.output_interval > 0.0) {
                eprintln!("error: --t-end and --output-interval must be positive");
                return ExitCode::from(2);
            }
            opts.out_dir = Some(out.clone());
            opts.progress = std::io::stderr().is_terminal();
            opts.force = force;
            opts.profile = profile;
            // SIGINT (Ctrl-C) and SIGTERM: stop at the next step, write the files, exit 130.
            let stop = Arc::new(AtomicBool::new(false));
            let flag = stop.clone();
            if let Err(e) = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed)) {
                eprintln!("warning: cannot catch Ctrl-C ({e}): an interrupted run writes no files");
            }
            opts.stop = Some(stop);
            match viscosph::Simulation::new(cfg.clone()) {
                Ok(sim) => {
                    println!("{}", sound_speed_text(&cfg, sim.effective_config()));
                    if let Some(w) = cfg.warning() {
                        eprintln!("warning: {w}");
                    }
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::from(2);
                }
            }
            match run(&cfg, &opts, &ReferenceModels) {
                Ok(r) => {
                    println!(
                        "{} particles, {} steps in {:.2} s ({:.3e} particle-steps/s); results in {}",
                        r.particles,
                        r.steps,
                        r.wall_seconds,
                        r.throughput(),
                        out.display()
                    );
                    if r.wall_reflections > 0 {
                        println!(
                            "{} times a particle that had crossed the plate was put back above it \
                             (see docs/methods.md: walls under tension)",
                            r.wall_reflections
                        );
                    }
                    for line in &r.summary {
                        println!("{line}");
                    }
                    if let Some(a) = &r.averages {
                        let (n, (t0, t1)) = a.samples();
                        println!(
                            "fields averaged over {n} outputs from t = {t0:.4} s to {t1:.4} s \
                             (steady at {:.4} s{}): averaged_fields.csv, averaged_fields.vtk, \
                             centreline.csv",
                            a.window().start,
                            if a.window().stop && t1 >= a.window().end {
                                "; stop_at_steady_state ended the run there"
                            } else {
                                ""
                            }
                        );
                    }
                    if profile {
                        println!(
                            "\nwhere the steps' time went ({} thread(s); shares of the CPU time):\n{}between the steps \
                             (outputs, snapshots): {:.3} s wall, {:.3} s CPU",
                            r.threads,
                            r.timings.table(),
                            r.between_steps.0,
                            r.between_steps.1
                        );
                    }
                    if let Some(e) = r.error {
                        eprintln!("error: {e}");
                        return ExitCode::from(1);
                    }
                    if let Some(t) = r.interrupted {
                        eprintln!(
                            "interrupted at t = {t:.6} s: the files in {} hold the run up to then",
                            out.display()
                        );
                        return ExitCode::from(130);
                    }
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Command::DefaultScene => {
            print!("{}", SceneConfig::default().to_toml_string());
            ExitCode::SUCCESS
        }
        Command::Bench(args) => match viscosph_cli::bench::main(args) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(1)
            }
        },
        Command::Exact(kind) => match viscosph_cli::exact::exact_csv(&kind) {
            Ok(csv) => {
                print!("{csv}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(1)
            }
        },
        Command::DocsTables { dir } => match viscosph_cli::docs_tables::write_tables(&dir) {
            Ok(msg) => {
                println!("{msg}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(1)
            }
        },
    }
}
