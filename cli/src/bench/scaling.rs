//! `viscosph bench scaling`: how a step's time falls with the threads, 1 to the machine's cores,
//! for the WCSPH drop at 10^4, 10^5 and 10^6 particles and the ISPH drop (King & Lind's Re = 4)
//! at 10^3, 10^4 and 10^5: wall time per step, speed-up and parallel efficiency, and from the
//! per-pass timers ([`viscosph::profile`]) the serial share of a step at one thread and its
//! Amdahl projection to 16 threads; for ISPH also the shares of the pressure and viscous solves
//! (of the CPU time at one thread) and their iterations against the particle count; for the
//! acceptance's cases (WCSPH at 10^5, ISPH at 10^4 particles) each part's efficiency, the points
//! of the step's efficiency it costs and its CPU time on the most threads over one thread's; and
//! the per-pass tables of the largest WCSPH case and of the ISPH case at 10^4 particles.
//!
//! On a machine shared with other work the wall clock counts the time others hold the cores, and
//! one run per thread count, one after the other, measured the 2-thread efficiency at 10^5
//! particles anywhere between 74 % and 93 %. So each case keeps one simulation per thread count
//! alive and times them in rounds, alternating (`measure_case`): every round runs the same steps
//! (after an untimed warm-up) on every thread count, about 3 s each; the section reports the
//! median wall per step, the efficiency from the medians and its spread over the rounds, the
//! load average before and after each case, and the CPU time per particle-step (which does not
//! count others' time) beside the wall figures.

use super::isph::king_lind_drop;
use super::machine_description;
use super::throughput::ppd_for;
use clap::Args;
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::Value;
use viscosph::profile::{amdahl_efficiency, Timings};
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

/// Options of `viscosph bench scaling`.
#[derive(Args, Debug, Clone, Default)]
pub struct ScalingArgs {
    /// Timed runs per size and thread count, taken in rounds that alternate the thread counts
    /// (1, 2, ..., then the reverse) on the same steps; default 7 (about 5 min on the idle 2-core
    /// machine of docs/bench/scaling.md), 2 with --quick.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub repeats: Option<u64>,
    /// Only these cases (comma-separated): a scheme, `wcsph` or `isph`, optionally with its
    /// nominal particle count, `isph:1e4`. For measuring one part; the full section runs all.
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
}

/// One timed run: `steps` steps of a case on one thread count.
struct Run {
    steps: u64,
    timings: Timings,
}

impl Run {
    /// Wall seconds per step.
    fn step_wall(&self) -> f64 {
        self.timings.total / self.steps.max(1) as f64
    }
}

/// Every run of one case on one thread count, and what they add up to.
struct Series {
    label: String,
    particles: usize,
    threads: usize,
    runs: Vec<Run>,
    /// The runs' timings summed, part by part (`steps` = every timed step).
    timings: Timings,
    /// Pressure-solve iterations per step (ISPH; 0 otherwise).
    ppe_iterations: f64,
    /// Viscous-solve iterations per step (ISPH's implicit viscosity; 0 otherwise).
    viscous_iterations: f64,
    /// Load average (1 min) before the case's first simulation was built and after its last run.
    load: (f64, f64),
    /// Whether this thread count's final state is bitwise the one-thread run's (fluid positions
    /// and velocities).
    bitwise: bool,
}

impl Series {
    /// Median over the runs of the wall seconds per step.
    fn median_wall(&self) -> f64 {
        median(self.runs.iter().map(Run::step_wall).collect())
    }
    /// CPU nanoseconds per particle-step, median over the runs.
    fn median_cpu_ns(&self) -> f64 {
        median(
            self.runs
                .iter()
                .map(|r| {
                    1e9 * r.timings.total_cpu / (r.steps.max(1) as f64 * self.particles as f64)
                })
                .collect(),
        )
    }
}

/// The median (the mean of the middle two for an even count).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The thread counts measured: 1, 2, 4, ... up to the cores, and the cores (every count alive at
/// once, one simulation each: doubling bounds their memory on a many-core machine).
fn thread_counts(cores: usize) -> Vec<usize> {
    let mut t: Vec<usize> = std::iter::successors(Some(1usize), |t| Some(2 * t))
        .take_while(|&t| t < cores)
        .collect();
    t.push(cores);
    t
}

/// Measure one case on every thread count of `threads`, alternating: one simulation per thread
/// count, all started alike and taken through the same untimed first step and `warmup` steps,
/// then `repeats` rounds in each of which every simulation advances to the same time, about
/// `steps` steps on (the thread counts in turn, the order reversed every other round, so a
/// change of the machine's load falls on all of them alike). The trajectories are bitwise the
/// same for any thread count, so every round times the same steps on each.
fn measure_case(
    case: &Case,
    threads: &[usize],
    repeats: u64,
) -> Result<Vec<Series>, Box<dyn std::error::Error>> {
    let load_before = load_average();
    let mut sims = Vec::new();
    for &t in threads {
        let mut cfg = case.cfg.clone();
        cfg.numerics.threads = t as i64;
        let mut sim = Simulation::new(cfg)?;
        // One tiny first step builds the lists and the walls.
        sim.advance_to(1e-12)?;
        sims.push(sim);
    }
    let span =
        |sim: &Simulation, steps: u64| sim.time() + sim.state().last_dt * steps as f64 * 0.999;
    let t_warm = span(&sims[0], case.warmup);
    for sim in &mut sims {
        sim.advance_to(t_warm)?;
        sim.set_profiling(true);
    }
    let (s0, it0) = (sims[0].state().step, sims[0].state().solver_iterations);
    let mut runs: Vec<Vec<Run>> = threads.iter().map(|_| Vec::new()).collect();
    for round in 0..repeats {
        // Every simulation is at the same state here: one target time for all.
        let t_end = span(&sims[0], case.steps);
        let mut order: Vec<usize> = (0..threads.len()).collect();
        if round % 2 == 1 {
            order.reverse();
        }
        for k in order {
            eprintln!(
                "bench scaling: {}, {} m spacing, {} thread(s), run {} of {repeats} ...",
                case.label,
                case.cfg.dx(),
                threads[k],
                round + 1
            );
            let sim = &mut sims[k];
            let (before, step0) = (sim.timings(), sim.state().step);
            sim.advance_to(t_end)?;
            runs[k].push(Run {
                steps: sim.state().step - step0,
                timings: sim.timings().since(&before),
            });
        }
    }
    let load_after = load_average();
    let bits = |sim: &Simulation| -> Vec<u64> {
        let f = &sim.state().fluid;
        f.x.iter()
            .chain(&f.v)
            .flat_map(|v| v.iter().map(|c| c.to_bits()))
            .collect()
    };
    let reference = bits(&sims[0]);
    let bitwise: Vec<bool> = sims.iter().map(|s| bits(s) == reference).collect();
    let st = sims[0].state();
    let done = (st.step - s0).max(1) as f64;
    let (ppe, visc) = (
        (st.solver_iterations[0] - it0[0]) as f64 / done,
        (st.solver_iterations[1] - it0[1]) as f64 / done,
    );
    Ok(threads
        .iter()
        .zip(runs)
        .zip(bitwise)
        .map(|((&t, runs), bitwise)| {
            let mut timings = runs
                .iter()
                .fold(Timings::default(), |acc, r| acc.merged(&r.timings));
            timings.steps = runs.iter().map(|r| r.steps).sum();
            Series {
                label: case.label.clone(),
                particles: st.fluid.len(),
                threads: t,
                runs,
                timings,
                ppe_iterations: ppe,
                viscous_iterations: visc,
                load: (load_before, load_after),
                bitwise,
            }
        })
        .collect())
}

/// The load average over the last minute (Linux; NaN elsewhere).
fn load_average() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|t| t.split_whitespace().next().and_then(|x| x.parse().ok()))
        .unwrap_or(f64::NAN)
}

/// Wall seconds of one timed run at one thread the step counts aim at (on the machine of
/// docs/bench/scaling.md).
fn run_wall(quick: bool) -> f64 {
    if quick {
        0.05
    } else {
        3.0
    }
}

/// One case: a label, its configuration, the steps of a timed run and of the untimed warm-up.
struct Case {
    label: String,
    cfg: SceneConfig,
    steps: u64,
    warmup: u64,
}

/// The cases: WCSPH's drop at about 10^4, 10^5 and 10^6 particles and ISPH's at 10^3, 10^4 and
/// 10^5 (smaller with `quick`).
fn cases(quick: bool, only: &[String]) -> Vec<Case> {
    // Whether `--only` keeps the case of `scheme` at about `n` particles.
    let keep = |scheme: &str, n: f64| {
        only.is_empty()
            || only.iter().any(|o| {
                let (s, size) = match o.split_once(':') {
                    Some((s, size)) => (s, Some(size.trim().parse::<f64>())),
                    None => (o.as_str(), None),
                };
                s.trim().eq_ignore_ascii_case(scheme)
                    && size.is_none_or(|x| x.is_ok_and(|x| x == n))
            })
    };
    let (wc_sizes, isph_sizes): (&[f64], &[f64]) = if quick {
        (&[1e3, 4e3], &[300.0, 1e3])
    } else {
        (&[1e4, 1e5, 1e6], &[1e3, 1e4, 1e5])
    };
    // Steps per timed run: about 3 s of one thread's wall (0.05 s with `quick`) on the machine of
    // docs/bench/scaling.md (WCSPH about 800 ns, ISPH 11-21 us per particle-step), so that the
    // start of a run (waking the pool's threads, caches filled by the other simulation) weighs
    // little; at least 2. With one run of 19 steps per thread count at 10^5 the 2-thread
    // efficiency moved by 10 points from run to run on a shared machine.
    let run_wall = run_wall(quick);
    let steps = |ns_per_particle_step: f64, n: f64| {
        ((run_wall / (ns_per_particle_step * 1e-9 * n)) as u64).clamp(2, 1000)
    };
    let warmup = if quick { 1 } else { 3 };
    let mut out = Vec::new();
    for &n in wc_sizes.iter().filter(|&&n| keep("wcsph", n)) {
        let mut cfg = SceneConfig::default();
        cfg.set("rheology", Value::Text("newtonian".into()))
            .expect("valid");
        cfg.set("particles_per_diameter", Value::Integer(ppd_for(n)))
            .expect("valid");
        // Start one spacing above the plate: the walls take part from the first step.
        let h = 0.5 * cfg.drop.drop_diameter + 1.5 * cfg.dx();
        cfg.set("initial_drop_height", Value::Real(h))
            .expect("valid");
        out.push(Case {
            label: "WCSPH Newtonian drop".to_string(),
            cfg,
            steps: steps(800.0, n),
            warmup,
        });
    }
    for &n in isph_sizes.iter().filter(|&&n| keep("isph", n)) {
        let mut cfg = king_lind_drop("newtonian", ppd_for(n));
        let h = 0.5 * cfg.drop.drop_diameter + 1.5 * cfg.dx();
        cfg.set("initial_drop_height", Value::Real(h))
            .expect("valid");
        out.push(Case {
            label: "ISPH Re = 4 drop".to_string(),
            cfg,
            steps: steps(15e3, n),
            warmup,
        });
    }
    out
}

pub fn bench_scaling(
    args: &ScalingArgs,
    out: &Path,
    quick: bool,
) -> Result<String, Box<dyn std::error::Error>> {
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let threads = thread_counts(cores);
    let repeats = args.repeats.unwrap_or(if quick { 2 } else { 7 });
    let cases = cases(quick, &args.only);
    let warmup = cases.first().map_or(0, |c| c.warmup);
    let mut series: Vec<Series> = Vec::new();
    for case in &cases {
        series.extend(measure_case(case, &threads, repeats)?);
    }
    let load = (
        series.first().map_or(f64::NAN, |s| s.load.0),
        series.last().map_or(f64::NAN, |s| s.load.1),
    );
    let mut md = format!(
        "Wall time per step against threads, {}; load average {:.1} before and {:.1} after \
         (other work on the machine slows the wall clock; the CPU time per particle-step counts \
         this process alone).\n\nMethod: per case one simulation per thread count, all started \
         alike and taken untimed through a first step and {warmup} more (the steady part only \
         is timed), then {repeats} rounds: in each every simulation runs the same steps (about \
         {} s of one thread's wall; the trajectories are bitwise the same for any thread count), \
         the thread counts one after the other, in reverse order every other round, so that a \
         change of the machine's load falls on all of them alike. Wall per step: the median \
         over the runs (min-max beside it); speed-up and efficiency: from the medians; spread: \
         the lowest and highest efficiency of a single round (the same steps on each thread \
         count); load: the 1-minute load average before the case's first simulation is built \
         and after its last run. Serial share: the CPU time of the parts of a step that run on \
         one thread, from the per-pass timers at one thread, every run summed (`viscosph run \
         --profile` prints the same table; a part marked \"all threads\" holds one-thread work \
         only where it is small: the offsets of the parallel chunks, ISPH's multigrid \
         aggregation and coarsest-level LU); Amdahl: the efficiency that share allows at 16 \
         threads, 1 / (s + (1 - s)/16) / 16.\n\n",
        machine_description(),
        load.0,
        load.1,
        run_wall(quick)
    );
    md.push_str(
        "| case | particles | threads | runs x steps (median) | wall per step, median [ms] | min-max \
         [ms] | speed-up | efficiency | spread over rounds | CPU ns per particle-step | load \
         before, after | serial share | Amdahl, 16 threads |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    // Columns 0-9 as before (read by other code and by earlier results' readers); steps: every
    // timed step; wall per step, speed-up, efficiency and CPU: medians.
    let mut csv = String::from(
        "case,particles,threads,steps,wall_per_step_s,speed_up,efficiency,cpu_ns_per_particle_step,serial_share,amdahl16,\
         repeats,steps_per_run,wall_per_step_min_s,wall_per_step_max_s,efficiency_min,efficiency_max,load_before,load_after,warmup_steps,bitwise\n",
    );
    for r in &series {
        let one = series
            .iter()
            .find(|o| o.label == r.label && o.particles == r.particles && o.threads == 1)
            .expect("every case runs on one thread");
        let speed_up = one.median_wall() / r.median_wall();
        let eff = speed_up / r.threads as f64;
        // Per round: the same steps on one thread and on r.threads.
        let per_round: Vec<f64> = one
            .runs
            .iter()
            .zip(&r.runs)
            .map(|(a, b)| a.step_wall() / (r.threads as f64 * b.step_wall()))
            .collect();
        let eff_min = per_round.iter().copied().fold(f64::INFINITY, f64::min);
        let eff_max = per_round.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let walls: Vec<f64> = r.runs.iter().map(Run::step_wall).collect();
        let w_min = walls.iter().copied().fold(f64::INFINITY, f64::min);
        let w_max = walls.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let s = one.timings.serial_share();
        let (share, amdahl, load) = if r.threads == 1 {
            (
                format!("{:.2} %", 100.0 * s),
                format!("{:.0} %", 100.0 * amdahl_efficiency(s, 16)),
                format!("{:.1}, {:.1}", r.load.0, r.load.1),
            )
        } else {
            (String::new(), String::new(), String::new())
        };
        let steps_per_run = median(r.runs.iter().map(|x| x.steps as f64).collect());
        writeln!(
            md,
            "| {} | {} | {} | {} x {steps_per_run} | {:.3} | {:.3}-{:.3} | {speed_up:.2} | {:.0} % \
             | {:.0}-{:.0} % | {:.0} | {load} | {share} | {amdahl} |",
            r.label,
            r.particles,
            r.threads,
            r.runs.len(),
            1e3 * r.median_wall(),
            1e3 * w_min,
            1e3 * w_max,
            100.0 * eff,
            100.0 * eff_min,
            100.0 * eff_max,
            r.median_cpu_ns()
        )?;
        writeln!(
            csv,
            "{},{},{},{},{:.6e},{speed_up:.6},{eff:.6},{:.1},{s:.5},{:.4},{},{steps_per_run},{w_min:.6e},{w_max:.6e},{eff_min:.6},{eff_max:.6},{:.2},{:.2},{warmup},{}",
            r.label,
            r.particles,
            r.threads,
            r.timings.steps,
            r.median_wall(),
            r.median_cpu_ns(),
            amdahl_efficiency(s, 16),
            r.runs.len(),
            r.load.0,
            r.load.1,
            u8::from(r.bitwise)
        )?;
    }
    let differ: Vec<String> = series
        .iter()
        .filter(|r| !r.bitwise)
        .map(|r| {
            format!(
                "{}, {} particles, {} threads",
                r.label, r.particles, r.threads
            )
        })
        .collect();
    if differ.is_empty() {
        md.push_str(
            "\nEvery case's final state (fluid positions and velocities) is bitwise the same on \
             every thread count.\n",
        );
    } else {
        writeln!(
            md,
            "\n**The final state differs from the one-thread run's**: {}.",
            differ.join("; ")
        )?;
    }
    // ISPH: where the time goes and how the solves' iterations grow with the particles.
    md.push_str(
        "\n| ISPH, one thread: particles | pressure solve share | viscous solve share | PPE \
         iterations per solve | viscous iterations per step |\n|---|---|---|---|---|\n",
    );
    for r in series
        .iter()
        .filter(|r| r.label.starts_with("ISPH") && r.threads == 1)
    {
        let t = &r.timings;
        writeln!(
            md,
            "| {} | {:.0} % | {:.0} % | {:.1} | {:.1} |",
            r.particles,
            100.0 * (t.share("pressure solve") + t.share("pressure solve, ILU(0)")),
            100.0 * (t.share("viscous solve") + t.share("viscous solve, ILU(0)")),
            r.ppe_iterations,
            r.viscous_iterations
        )?;
    }
    // Where the acceptance's cases (WCSPH nearest 10^5 particles, ISPH nearest 10^4) lose on the
    // most threads: per part, its own parallel efficiency and the CPU it takes beyond one
    // thread's.
    let nearest = |scheme: &str, n: usize| {
        series
            .iter()
            .filter(|r| r.label.starts_with(scheme))
            .min_by_key(|r| r.particles.abs_diff(n))
            .map(|r| r.particles)
    };
    let most = *threads.last().expect("one thread at least");
    for (scheme, n) in [("WCSPH", 100_000), ("ISPH", 10_000)] {
        let size = nearest(scheme, n);
        let pick = |t: usize| {
            series.iter().find(|r| {
                r.label.starts_with(scheme) && Some(r.particles) == size && r.threads == t
            })
        };
        if let (Some(one), Some(many)) = (pick(1), pick(most).filter(|_| most > 1)) {
            per_part_table(&mut md, one, many)?;
        }
    }
    // The per-pass tables of the largest WCSPH case and of the ISPH case nearest 10^4
    // particles, at one thread and at the most threads.
    let isph_mid = nearest("ISPH", 10_000);
    for (scheme, t) in [("WCSPH", 1), ("WCSPH", most), ("ISPH", 1), ("ISPH", most)] {
        if let Some(r) = series
            .iter()
            .filter(|r| {
                r.label.starts_with(scheme)
                    && r.threads == t
                    && (scheme == "WCSPH" || Some(r.particles) == isph_mid)
            })
            .max_by_key(|r| r.particles)
        {
            writeln!(
                md,
                "\nPer pass, {}, {} particles, {t} thread(s), {} runs, {} steps:\n\n```text\n{}```",
                r.label,
                r.particles,
                r.runs.len(),
                r.timings.steps,
                r.timings.table()
            )?;
        }
    }
    std::fs::write(out.join("scaling.csv"), &csv)?;
    std::fs::write(out.join("scaling.md"), &md)?;
    Ok(md)
}

/// Per part of a step, one thread against `many.threads` (every run summed): the part's own
/// parallel efficiency, the points of the step's efficiency it costs and its CPU time on the
/// most threads over one thread's.
fn per_part_table(md: &mut String, one: &Series, many: &Series) -> std::fmt::Result {
    let p = many.threads;
    writeln!(
        md,
        "\nPer pass, {}, {} particles, 1 against {p} threads, every run summed: each part's \
         parallel efficiency, the points of the step's efficiency it costs ({p} times its wall \
         time on {p} threads less its wall time on one, over {p} times the step's wall time on \
         {p} threads: these sum to 100 % less the step's efficiency, with the untimed rest) and \
         the CPU time it takes on {p} threads over one thread's (above 1: overhead, or memory \
         traffic the threads share).\n\n| part | wall, 1 thread [ms/step] | wall, {p} threads \
         [ms/step] | efficiency | step efficiency lost | CPU {p} / 1 |\n|---|---|---|---|---|---|",
        one.label, one.particles
    )?;
    let (s1, sn) = (
        one.timings.steps.max(1) as f64,
        many.timings.steps.max(1) as f64,
    );
    let step_wall_n = many.timings.total / sn;
    for a in &one.timings.parts {
        let Some(b) = many.timings.parts.iter().find(|b| b.name == a.name) else {
            continue;
        };
        let (w1, wn) = (a.wall / s1, b.wall / sn);
        if w1 < 1e-3 * one.timings.total / s1 {
            continue;
        }
        writeln!(
            md,
            "| {} | {:.3} | {:.3} | {:.0} % | {:.1} % | {:.3} |",
            a.name,
            1e3 * w1,
            1e3 * wn,
            100.0 * w1 / (p as f64 * wn),
            100.0 * (p as f64 * wn - w1) / (p as f64 * step_wall_n),
            (b.cpu / sn) / (a.cpu / s1).max(f64::MIN_POSITIVE)
        )?;
    }
    Ok(())
}
