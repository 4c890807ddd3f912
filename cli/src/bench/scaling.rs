//! `viscosph bench scaling`: how a step's time falls with the threads, 1 to the machine's cores,
//! for the WCSPH drop at 10^4, 10^5 and 10^6 particles and the ISPH drop (King & Lind's Re = 4)
//! at 10^3, 10^4 and 10^5: wall time per step, speed-up and parallel efficiency, and from the
//! per-pass timers ([`viscosph::profile`]) the serial share of a step at one thread and its
//! Amdahl projection to 16 threads; for ISPH also the shares of the pressure and viscous solves
//! (of the CPU time at one thread) and their iterations against the particle count; for the
//! WCSPH case at 10^5 particles each part's efficiency, the points of the step's efficiency it
//! costs and its CPU time on the most threads over one thread's; and the per-pass tables of the
//! largest WCSPH case and of the ISPH case at 10^4 particles.
//!
//! On a machine shared with other work the wall clock counts the time others hold the cores: the
//! section states the load average before and after, and the CPU time per particle-step (which
//! does not count others' time) beside the wall figures.

use super::isph::king_lind_drop;
use super::machine_description;
use super::throughput::ppd_for;
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::Value;
use viscosph::profile::{amdahl_efficiency, Timings};
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

/// One timed run: `steps` steps of a case on `threads` threads.
struct Run {
    particles: usize,
    steps: u64,
    threads: usize,
    timings: Timings,
    /// Pressure-solve iterations per step (ISPH; 0 otherwise).
    ppe_iterations: f64,
    /// Viscous-solve iterations per step (ISPH's implicit viscosity; 0 otherwise).
    viscous_iterations: f64,
}

impl Run {
    /// Wall seconds per step.
    fn step_wall(&self) -> f64 {
        self.timings.total / self.steps.max(1) as f64
    }
    /// CPU nanoseconds per particle-step.
    fn cpu_ns(&self) -> f64 {
        1e9 * self.timings.total_cpu / (self.steps.max(1) as f64 * self.particles as f64)
    }
}

/// Time `steps` steps of `cfg` on `threads` threads with the per-pass timers on, from one tiny
/// first step (which builds the lists and the walls, untimed).
fn timed_run(
    cfg: &SceneConfig,
    threads: usize,
    steps: u64,
) -> Result<Run, Box<dyn std::error::Error>> {
    let mut cfg = cfg.clone();
    cfg.numerics.threads = threads as i64;
    let mut sim = Simulation::new(cfg)?;
    sim.advance_to(1e-12)?;
    let dt = sim.state().last_dt;
    let (s0, it0) = (sim.state().step, sim.state().solver_iterations);
    sim.set_profiling(true);
    let before = sim.timings();
    sim.advance_to(sim.time() + dt * steps as f64 * 0.999)?;
    let st = sim.state();
    let done = st.step - s0;
    Ok(Run {
        particles: st.fluid.len(),
        steps: done,
        threads,
        timings: sim.timings().since(&before),
        ppe_iterations: (st.solver_iterations[0] - it0[0]) as f64 / done.max(1) as f64,
        viscous_iterations: (st.solver_iterations[1] - it0[1]) as f64 / done.max(1) as f64,
    })
}

/// The load average over the last minute (Linux; NaN elsewhere).
fn load_average() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|t| t.split_whitespace().next().and_then(|x| x.parse().ok()))
        .unwrap_or(f64::NAN)
}

/// The cases: (label, scheme, configuration for about `n` particles, steps to time).
fn cases(quick: bool) -> Vec<(String, SceneConfig, u64)> {
    let (wc_sizes, isph_sizes): (&[f64], &[f64]) = if quick {
        (&[1e3, 4e3], &[300.0, 1e3])
    } else {
        (&[1e4, 1e5, 1e6], &[1e3, 1e4, 1e5])
    };
    let mut out = Vec::new();
    for &n in wc_sizes {
        let mut cfg = SceneConfig::default();
        cfg.set("rheology", Value::Text("newtonian".into()))
            .expect("valid");
        cfg.set("particles_per_diameter", Value::Integer(ppd_for(n)))
            .expect("valid");
        // Start one spacing above the plate: the walls take part from the first step.
        let h = 0.5 * cfg.drop.drop_diameter + 1.5 * cfg.dx();
        cfg.set("initial_drop_height", Value::Real(h))
            .expect("valid");
        // About 2e7 particle-steps a run (8-16 s at one thread on the machine of
        // docs/bench/scaling.md; at most 1,000 steps, at least 20): with 19 steps at 10^5 and 5
        // at 10^6 the 2-thread efficiency moved by about 4 % from run to run.
        let steps = if quick {
            ((2e6 / n) as u64).clamp(6, 200) / 4
        } else {
            ((2e7 / n) as u64).clamp(20, 1000)
        };
        out.push(("WCSPH Newtonian drop".to_string(), cfg, steps.max(4)));
    }
    for &n in isph_sizes {
        let mut cfg = king_lind_drop("newtonian", ppd_for(n));
        let h = 0.5 * cfg.drop.drop_diameter + 1.5 * cfg.dx();
        cfg.set("initial_drop_height", Value::Real(h))
            .expect("valid");
        let steps = ((2e5 / n) as u64).clamp(4, 100) / if quick { 4 } else { 1 };
        out.push(("ISPH Re = 4 drop".to_string(), cfg, steps.max(2)));
    }
    out
}

pub fn bench_scaling(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let load_before = load_average();
    let mut runs: Vec<(String, Run)> = Vec::new();
    for (label, cfg, steps) in cases(quick) {
        for threads in 1..=cores {
            eprintln!(
                "bench scaling: {label}, {} m spacing, {threads} thread(s) ...",
                cfg.dx()
            );
            runs.push((label.clone(), timed_run(&cfg, threads, steps)?));
        }
    }
    let load_after = load_average();
    let mut md = format!(
        "Wall time per step against threads, {}; load average {load_before:.1} before and \
         {load_after:.1} after (other work on the machine slows the wall clock; the CPU time \
         per particle-step counts this process alone). Serial share: the CPU time of the parts \
         of a step that run on one thread, from the per-pass timers at one thread (`viscosph \
         run --profile` prints the same table; a part marked \"all threads\" holds one-thread \
         work only where it is small: the offsets of the parallel chunks, ISPH's multigrid \
         aggregation and coarsest-level LU); Amdahl: the efficiency that share allows at 16 \
         threads, 1 / (s + (1 - s)/16) / 16.\n\n",
        machine_description()
    );
    md.push_str(
        "| case | particles | threads | steps | wall per step [ms] | speed-up | efficiency | CPU \
         ns per particle-step | serial share | Amdahl, 16 threads |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut csv = String::from(
        "case,particles,threads,steps,wall_per_step_s,speed_up,efficiency,cpu_ns_per_particle_step,serial_share,amdahl16\n",
    );
    for (label, r) in &runs {
        let one = runs
            .iter()
            .find(|(l, o)| l == label && o.particles == r.particles && o.threads == 1)
            .map(|(_, o)| o)
            .expect("every case runs on one thread first");
        let speed_up = one.step_wall() / r.step_wall();
        let eff = speed_up / r.threads as f64;
        let s = one.timings.serial_share();
        let (share, amdahl) = if r.threads == 1 {
            (
                format!("{:.2} %", 100.0 * s),
                format!("{:.0} %", 100.0 * amdahl_efficiency(s, 16)),
            )
        } else {
            (String::new(), String::new())
        };
        writeln!(
            md,
            "| {label} | {} | {} | {} | {:.3} | {speed_up:.2} | {:.0} % | {:.0} | {share} | {amdahl} |",
            r.particles,
            r.threads,
            r.steps,
            1e3 * r.step_wall(),
            100.0 * eff,
            r.cpu_ns()
        )?;
        writeln!(
            csv,
            "{label},{},{},{},{:.6e},{speed_up:.4},{eff:.4},{:.1},{s:.5},{:.4}",
            r.particles,
            r.threads,
            r.steps,
            r.step_wall(),
            r.cpu_ns(),
            amdahl_efficiency(s, 16)
        )?;
    }
    // ISPH: where the time goes and how the solves' iterations grow with the particles.
    md.push_str(
        "\n| ISPH, one thread: particles | pressure solve share | viscous solve share | PPE \
         iterations per solve | viscous iterations per step |\n|---|---|---|---|---|\n",
    );
    for (_, r) in runs
        .iter()
        .filter(|(l, r)| l.starts_with("ISPH") && r.threads == 1)
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
    // Where the WCSPH case nearest 10^5 particles (the acceptance's) loses on the most threads:
    // per part, its own parallel efficiency and the CPU it takes beyond one thread's.
    let wc_mid = runs
        .iter()
        .filter(|(l, _)| l.starts_with("WCSPH"))
        .min_by_key(|(_, r)| r.particles.abs_diff(100_000))
        .map(|(_, r)| r.particles);
    let pick = |threads: usize| {
        runs.iter()
            .find(|(l, r)| {
                l.starts_with("WCSPH") && Some(r.particles) == wc_mid && r.threads == threads
            })
            .map(|(_, r)| r)
    };
    if let (Some(one), Some(many)) = (pick(1), pick(cores).filter(|_| cores > 1)) {
        writeln!(
            md,
            "\nPer pass, WCSPH Newtonian drop, {} particles, 1 against {cores} threads: each \
             part's parallel efficiency, the points of the step's efficiency it costs \
             ({cores} times its wall time on {cores} threads less its wall time on one, over \
             {cores} times the step's wall time on {cores} threads: these sum to 100 % less the \
             step's efficiency, with the untimed rest) and the CPU time it takes on {cores} \
             threads over one thread's (above 1: overhead, or memory traffic the threads \
             share).\n\n| part | wall, 1 thread [ms/step] | wall, {cores} threads [ms/step] | \
             efficiency | step efficiency lost | CPU {cores} / 1 |\n|---|---|---|---|---|---|",
            one.particles
        )?;
        let (s1, sn) = (one.steps.max(1) as f64, many.steps.max(1) as f64);
        for p in &one.timings.parts {
            let Some(q) = many.timings.parts.iter().find(|q| q.name == p.name) else {
                continue;
            };
            let (w1, wn) = (p.wall / s1, q.wall / sn);
            if w1 < 1e-3 * one.step_wall() {
                continue;
            }
            writeln!(
                md,
                "| {} | {:.3} | {:.3} | {:.0} % | {:.1} % | {:.3} |",
                p.name,
                1e3 * w1,
                1e3 * wn,
                100.0 * w1 / (cores as f64 * wn),
                100.0 * (cores as f64 * wn - w1) / (cores as f64 * many.step_wall()),
                (q.cpu / sn) / (p.cpu / s1).max(f64::MIN_POSITIVE)
            )?;
        }
    }
    // The per-pass tables of the largest WCSPH case and of the ISPH case nearest 10^4
    // particles (the acceptance's), at one thread and at the most threads.
    let isph_mid = runs
        .iter()
        .filter(|(l, _)| l.starts_with("ISPH"))
        .min_by_key(|(_, r)| r.particles.abs_diff(10_000))
        .map(|(_, r)| r.particles);
    for (scheme, threads) in [("WCSPH", 1), ("WCSPH", cores), ("ISPH", 1), ("ISPH", cores)] {
        if let Some((label, r)) = runs
            .iter()
            .filter(|(l, r)| {
                l.starts_with(scheme)
                    && r.threads == threads
                    && (scheme == "WCSPH" || Some(r.particles) == isph_mid)
            })
            .max_by_key(|(_, r)| r.particles)
        {
            writeln!(
                md,
                "\nPer pass, {label}, {} particles, {threads} thread(s), {} steps:\n\n```text\n{}```",
                r.particles,
                r.steps,
                r.timings.table()
            )?;
        }
    }
    std::fs::write(out.join("scaling.csv"), &csv)?;
    std::fs::write(out.join("scaling.md"), &md)?;
    Ok(md)
}
