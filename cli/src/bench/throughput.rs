//! `viscosph bench throughput`: particle-steps per second of the Newtonian and Oldroyd-B drop on
//! 1 and 2 threads at about 10^3, 10^4, 10^5 and (Newtonian only, 6 steps) 10^6 particles, the
//! CPU time and peak RSS per particle, the Oldroyd-B / Newtonian cost ratio, and the cost of the
//! FMI layer over the library.

use super::fang_cases;
use crate::io::plot::{line_panels, Panel, Series};
use std::fmt::Write as _;
use std::path::Path;
use viscosph::config::Value;
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

/// Particles per diameter giving about `n` particles in the disc (pi/4 ppd^2 = n).
pub fn ppd_for(n: f64) -> i64 {
    (4.0 * n / std::f64::consts::PI).sqrt().round() as i64
}

/// CPU time this process has used so far, all threads \[s\] ([`viscosph::profile`]'s clock;
/// `None` where the platform has none). On a machine shared with other work the wall clock
/// counts the time others hold the cores; CPU time does not.
pub fn process_cpu_seconds() -> Option<f64> {
    let s = viscosph::profile::process_cpu_seconds();
    (s > 0.0).then_some(s)
}

/// One throughput measurement.
#[derive(Debug, Clone, Copy)]
pub struct Throughput {
    pub particles: usize,
    /// Particle-steps per wall-clock second.
    pub per_second: f64,
    /// CPU nanoseconds (all threads) per particle-step; NaN where CPU time is not available.
    pub cpu_ns: f64,
}

/// Measure particle-steps per second of `cfg` over `steps` steps on `threads` threads, starting
/// just before impact (the drop is set down one spacing above the plate so walls take part).
/// Particles are fluid particles (the plate's are part of the cost), in 2D or 3D.
pub fn measure_throughput(
    cfg: &SceneConfig,
    steps: u64,
    threads: usize,
) -> Result<Throughput, Box<dyn std::error::Error>> {
    // The simulation runs in its own pool of `threads` workers.
    let mut cfg = cfg.clone();
    cfg.numerics.threads = threads as i64;
    let r: Result<Throughput, viscosph::simulation::SimError> = (|| {
        let mut sim = Simulation::new(cfg)?;
        // One tiny step to learn the stable step, then time `steps` steps.
        sim.advance_to(1e-12)?;
        let dt = sim.last_dt();
        let s0 = sim.steps();
        let cpu0 = process_cpu_seconds();
        let start = std::time::Instant::now();
        sim.advance_to(sim.time() + dt * steps as f64 * 0.999)?;
        let secs = start.elapsed().as_secs_f64();
        let cpu = match (cpu0, process_cpu_seconds()) {
            (Some(a), Some(b)) => b - a,
            _ => f64::NAN,
        };
        let done = sim.steps() - s0;
        let n = sim.particle_count();
        let ps = n as f64 * done as f64;
        Ok(Throughput {
            particles: n,
            per_second: ps / secs,
            cpu_ns: 1e9 * cpu / ps,
        })
    })();
    Ok(r?)
}

pub fn bench_throughput(out: &Path, quick: bool) -> Result<String, Box<dyn std::error::Error>> {
    // Each case's peak memory comes from a process of its own ([`memory_per_particle`]). 10^6 runs
    // the Newtonian drop only, for a few steps (cost per particle-step, not a trajectory).
    let sizes: &[f64] = if quick {
        &[300.0, 1000.0]
    } else {
        &[1e3, 1e4, 1e5, 1e6]
    };
    let mut md = String::from(
        "| case | particles | threads | particle-steps/s (wall) | per core | CPU ns per \
         particle-step | peak RSS per particle [bytes] |\n|---|---|---|---|---|---|---|\n",
    );
    let mut csv = String::from(
        "case,particles,threads,particle_steps_per_second,cpu_ns_per_particle_step,peak_rss_bytes_per_particle\n",
    );
    let mut by: Vec<(String, usize, usize, f64, f64)> = Vec::new();
    for &n in sizes {
        for (name, _) in fang_cases() {
            if n > 2e5 && name != "newtonian" {
                continue;
            }
            let ppd = ppd_for(n);
            let cfg = throughput_case(name, 2, ppd)?;
            let steps = ((2e6 / n) as u64).clamp(6, 400) / if quick { 4 } else { 1 };
            for threads in [1usize, 2] {
                eprintln!("bench throughput: {name}, {n:.0} particles, {threads} thread(s) ...");
                let t = measure_throughput(&cfg, steps.max(4), threads)?;
                let np = t.particles;
                let rss = memory_per_particle(name, 2, ppd, threads);
                by.push((name.to_string(), np, threads, t.per_second, t.cpu_ns));
                writeln!(
                    csv,
                    "{name},{np},{threads},{:.4e},{:.1},{rss:.0}",
                    t.per_second, t.cpu_ns
                )?;
                writeln!(
                    md,
                    "| {name} | {np} | {threads} | {:.3e} | {:.3e} | {:.0} | {rss:.0} |",
                    t.per_second,
                    t.per_second / threads as f64,
                    t.cpu_ns
                )?;
            }
        }
    }
    writeln!(
        md,
        "\n| particles | threads | cost ratio Oldroyd-B / Newtonian (CPU time) |\n|---|---|---|"
    )?;
    for (name, np, th, _, cn) in &by {
        if name == "newtonian" {
            if let Some((_, _, _, _, co)) = by.iter().find(|(n2, np2, th2, _, _)| {
                n2 == "oldroyd_b" && *th2 == *th && (*np2 as f64 / *np as f64 - 1.0).abs() < 0.05
            }) {
                writeln!(md, "| {np} | {th} | {:.2} |", co / cn)?;
            }
        }
    }
    plot_throughput(out, &by)?;
    three_dimensions(&mut md, &mut csv, &by, sizes, quick)?;
    let (lib, chunks, fmu) = fmu_overhead(if quick { 0.04 } else { 0.16 })?;
    writeln!(
        md,
        "\n### FMU overhead: the default drop to t = {} s\n",
        if quick { 0.04 } else { 0.16 }
    )?;
    writeln!(
        md,
        "| path | wall time [s] | relative to one library call |\n|---|---|---|"
    )?;
    writeln!(md, "| library, one `advance_to` | {lib:.3} | 1.00 |")?;
    writeln!(
        md,
        "| library, `advance_to` + `outputs` every 1 ms | {chunks:.3} | {:.3} |",
        chunks / lib
    )?;
    writeln!(
        md,
        "| FMI layer, `fmi2DoStep` + `fmi2GetReal` of every output every 1 ms | {fmu:.3} | {:.3} |",
        fmu / lib
    )?;
    writeln!(csv, "fmu_overhead_library_one_call,,,{lib:.4}\nfmu_overhead_library_1ms,,,{chunks:.4}\nfmu_overhead_fmi_1ms,,,{fmu:.4}")?;
    std::fs::write(out.join("throughput.csv"), &csv)?;
    std::fs::write(out.join("throughput.md"), &md)?;
    Ok(md)
}

/// Arguments of the hidden `viscosph bench memory-probe`: one throughput case, run in a process
/// of its own so that its peak memory is its own.
#[derive(clap::Args, Debug, Clone)]
pub struct ProbeArgs {
    /// `newtonian` or `oldroyd_b` (Fang's drops, [`fang_cases`]).
    #[arg(long)]
    pub case: String,
    /// 2 or 3.
    #[arg(long)]
    pub dimension: i64,
    /// Particles per diameter.
    #[arg(long)]
    pub ppd: i64,
    /// Worker threads.
    #[arg(long)]
    pub threads: usize,
}

/// A throughput case: Fang's drop `name` in `dimension` at `ppd` particles per diameter, set
/// down one and a half spacings above the plate, moving down, so walls take part from the first step.
fn throughput_case(
    name: &str,
    dimension: i64,
    ppd: i64,
) -> Result<SceneConfig, Box<dyn std::error::Error>> {
    let mut cfg = fang_cases()
        .into_iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| format!("no throughput case {name:?} (newtonian, oldroyd_b)"))?
        .1;
    if dimension != 2 {
        cfg.set("dimension", Value::Integer(dimension))?;
    }
    cfg.set("particles_per_diameter", Value::Integer(ppd))?;
    let h = 0.5 * cfg.drop.drop_diameter + 1.5 * cfg.dx();
    cfg.set("initial_drop_height", Value::Real(h))?;
    Ok(cfg)
}

/// The probe itself: the resident set size before the simulation exists, then two steps (the
/// neighbour lists, pair caches and the solver's work arrays are all allocated by the end of the
/// first), then the process's peak; prints `particles peak_bytes_over_base`.
pub fn memory_probe(a: &ProbeArgs) -> Result<String, Box<dyn std::error::Error>> {
    let mut cfg = throughput_case(&a.case, a.dimension, a.ppd)?;
    cfg.numerics.threads = a.threads as i64;
    let base = resident_bytes("VmRSS:").ok_or("no /proc/self/status here")?;
    let r: Result<usize, viscosph::simulation::SimError> = (|| {
        let mut sim = Simulation::new(cfg)?;
        sim.advance_to(1e-12)?;
        let dt = sim.last_dt();
        sim.advance_to(sim.time() + 1.999 * dt)?;
        Ok(sim.particle_count())
    })();
    let np = r?;
    let peak = resident_bytes("VmHWM:").ok_or("no /proc/self/status here")?;
    Ok(format!("{np} {}", peak.saturating_sub(base)))
}

/// A size line of `/proc/self/status` (`VmRSS:`, `VmHWM:`) \[bytes\]; `None` off Linux.
fn resident_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Peak memory per fluid particle of one case \[bytes\]: [`memory_probe`] in a child process of
/// this binary, since a process's high-water mark cannot be taken back: in one process the
/// allocator keeps the heap an earlier, larger run freed, the next run reuses it and reads near
/// 0. NaN where the probe cannot run (not Linux).
fn memory_per_particle(name: &str, dimension: i64, ppd: i64, threads: usize) -> f64 {
    let probe = || -> Option<f64> {
        let out = std::process::Command::new(std::env::current_exe().ok()?)
            .args(["bench", "--out"])
            .arg(std::env::temp_dir())
            .args(["memory-probe", "--case", name])
            .args([
                "--dimension",
                &dimension.to_string(),
                "--ppd",
                &ppd.to_string(),
            ])
            .args(["--threads", &threads.to_string()])
            .output()
            .ok()?;
        let text = String::from_utf8(out.stdout).ok()?;
        let mut it = text.split_whitespace();
        let np: f64 = it.next()?.parse().ok()?;
        let bytes: f64 = it.next()?.parse().ok()?;
        (out.status.success() && np > 0.0).then_some(bytes / np)
    };
    probe().unwrap_or(f64::NAN)
}

/// The same Fang drops as a sphere (`dimension = 3`, dummy walls: three layers under the plate
/// where the fluid can reach it) at about the same fluid particle counts as the 2D rows (10^3 and 10^4;
/// 10^5 is not run: 3D at that size is `viscosph run`'s), 1 and 2 threads: CPU time per fluid
/// particle-step against the 2D row of the same size, and the peak RSS per fluid particle
/// ([`memory_per_particle`]).
fn three_dimensions(
    md: &mut String,
    csv: &mut String,
    by: &[(String, usize, usize, f64, f64)],
    sizes: &[f64],
    quick: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    writeln!(
        md,
        "\n### Three dimensions: the sphere against the disc\n\n| case | particles 3D | threads | \
         CPU ns per particle-step 3D | 2D (particles) | cost ratio 3D / 2D | peak RSS per particle \
         3D [bytes] |\n|---|---|---|---|---|---|---|"
    )?;
    for &n in sizes.iter().filter(|&&n| n < 2e4) {
        for (name, _) in fang_cases() {
            let ppd = (6.0 * n / std::f64::consts::PI).cbrt().round() as i64;
            let cfg = throughput_case(name, 3, ppd)?;
            let steps = ((2e5 / n) as u64).clamp(6, 100) / if quick { 4 } else { 1 };
            for threads in [1usize, 2] {
                eprintln!("bench throughput: 3D {name}, {n:.0} particles, {threads} thread(s) ...");
                let t = measure_throughput(&cfg, steps.max(4), threads)?;
                let np = t.particles;
                let rss = memory_per_particle(name, 3, ppd, threads);
                let d2 = by.iter().find(|(n2, np2, th2, _, _)| {
                    n2 == name && *th2 == threads && (*np2 as f64 / n - 1.0).abs() < 0.1
                });
                let (d2_text, ratio) = match d2 {
                    Some((_, np2, _, _, c2)) => (format!("{c2:.0} ({np2})"), t.cpu_ns / c2),
                    None => ("-".to_string(), f64::NAN),
                };
                writeln!(
                    csv,
                    "{name}_3d,{np},{threads},{:.4e},{:.1},{rss:.0}",
                    t.per_second, t.cpu_ns
                )?;
                writeln!(
                    md,
                    "| {name} | {np} | {threads} | {:.0} | {d2_text} | {ratio:.2} | {rss:.0} |",
                    t.cpu_ns
                )?;
            }
        }
    }
    Ok(())
}

/// Cost per particle-step (CPU nanoseconds, all threads) against the particle count,
/// one line per case and thread count: flat means the cost grows linearly with the particles.
fn plot_throughput(
    out: &Path,
    by: &[(String, usize, usize, f64, f64)],
) -> Result<(), Box<dyn std::error::Error>> {
    let mut series = Vec::new();
    for (name, _) in fang_cases() {
        for threads in [1usize, 2] {
            let points: Vec<(f64, f64)> = by
                .iter()
                .filter(|(n, _, th, _, _)| n == name && *th == threads)
                .map(|(_, np, _, _, cpu_ns)| (*np as f64, *cpu_ns))
                .collect();
            if !points.is_empty() {
                series.push(Series {
                    label: format!("{name}, {threads} thread(s)"),
                    points,
                });
            }
        }
    }
    let panel = Panel {
        title: "cost per particle-step (WCSPH drop)".into(),
        x_label: "particles".into(),
        y_label: "CPU ns per particle-step".into(),
        series,
        log: (true, false),
    };
    line_panels(&out.join("throughput.png"), &[panel], 1, (900, 600))?;
    Ok(())
}

/// Wall times of the default drop to `t_end`: one library call, the library in 1 ms chunks with
/// the outputs read each time, and the FMI 2.0 instance layer (the code behind the exported
/// `fmi2*` functions: state machine, value-reference lookup, `fmi2DoStep`, `fmi2GetReal` of every
/// output) at a 1 ms communication step. The C ABI hop on top of that layer is a null check and a
/// `catch_unwind`, nanoseconds per call.
pub fn fmu_overhead(t_end: f64) -> Result<(f64, f64, f64), Box<dyn std::error::Error>> {
    use viscosph::fmi2::instance::Instance;
    let cfg = SceneConfig::default();
    let h = 1e-3;
    let n = (t_end / h).round() as usize;
    let start = std::time::Instant::now();
    let mut sim = Simulation::new(cfg.clone())?;
    sim.advance_to(t_end)?;
    let lib = start.elapsed().as_secs_f64();

    let start = std::time::Instant::now();
    let mut sim = Simulation::new(cfg)?;
    let mut sink = 0.0;
    for k in 1..=n {
        sim.advance_to(k as f64 * h)?;
        sink += sim.outputs().shared.drop_width;
    }
    let chunks = start.elapsed().as_secs_f64();

    let vrs: Vec<u32> = viscosph::OUTPUTS
        .iter()
        .filter(|o| o.name != "particle_count")
        .map(|o| o.value_reference)
        .collect();
    let mut values = vec![0.0; vrs.len()];
    let start = std::time::Instant::now();
    let mut inst = Instance::new("bench", false, Box::new(|_, _, _| {}));
    let ok =
        |s: viscosph::fmi2::types::Status, what: &str| -> Result<(), Box<dyn std::error::Error>> {
            if s == viscosph::fmi2::types::Status::Ok {
                Ok(())
            } else {
                Err(format!("FMI layer: {what} answered {s:?}").into())
            }
        };
    ok(
        inst.setup_experiment(None, 0.0, Some(t_end)),
        "setup_experiment",
    )?;
    ok(
        inst.enter_initialization_mode(),
        "enter_initialization_mode",
    )?;
    ok(inst.exit_initialization_mode(), "exit_initialization_mode")?;
    for k in 0..n {
        ok(inst.do_step(k as f64 * h, h), "do_step")?;
        ok(inst.get_real(&vrs, &mut values), "get_real")?;
        sink += values[0];
    }
    let fmu = start.elapsed().as_secs_f64();
    assert!(sink.is_finite());
    Ok((lib, chunks, fmu))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ppd_for_hits_the_particle_count() {
        for n in [1e3, 1e4, 1e5] {
            let ppd = ppd_for(n) as f64;
            let got = std::f64::consts::FRAC_PI_4 * ppd * ppd;
            assert!((got / n - 1.0).abs() < 0.02, "{n} -> {got}");
        }
    }
}
