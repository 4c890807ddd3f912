//! Issue 11's speed figures for one drop of King & Lind 2021 IV.C (W = 2 cm, centre W above the
//! plate, U = 1 m/s, eta0 = 5 Pa s, rho = 1000 kg/m3, Re = 4) under ISPH: steps, wall and CPU
//! time, PPE and viscous iterations per step, and the share of the step in each linear solve.
//!
//! `cargo run --release --example isph_speed -- RHEOLOGY W_OVER_DR [THREADS] [T_STAR_END] [DIM]`
//! (e.g. `newtonian 40 2 8`, `oldroyd_b 120 2 8`, the sphere `newtonian 20 1 8 3`; Oldroyd-B at
//! De = 1, beta = 0.1, the defaults; DIM 2 or 3, default 2).
//! Prints a progress line every t* = 1 (W* and the time so far) and a table row at the end. The
//! run is `viscosph bench isph`'s, without its outputs every 0.05 t* (W* is read once per t*).
//! A last line prints a hash of the final positions' and velocities' bits, to check that two
//! builds compute the same run.

use std::time::Instant;
use viscosph::config::Value;
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

/// CPU time of this process (user + system), seconds.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name (which is in parentheses): utime and stime are 14 and 15.
    let rest = stat.rsplit(')').next().unwrap_or("");
    let f: Vec<&str> = rest.split_whitespace().collect();
    let tick = 100.0; // sysconf(_SC_CLK_TCK) on Linux
    let get = |k: usize| f.get(k).and_then(|s| s.parse::<f64>().ok()).unwrap_or(0.0);
    (get(11) + get(12)) / tick
}

/// FNV-1a hash of the bits of every fluid position and velocity: two builds that claim the
/// same arithmetic must print the same fingerprint.
fn fingerprint(sim: &Simulation) -> u64 {
    let bits: Vec<u64> = match sim.state_3d() {
        Some(st) => (st.fluid.x.iter().chain(&st.fluid.v))
            .flat_map(|v| v.iter().map(|c| c.to_bits()))
            .collect(),
        None => {
            let f = &sim.state().fluid;
            (f.x.iter().chain(&f.v))
                .flat_map(|v| v.iter().map(|c| c.to_bits()))
                .collect()
        }
    };
    bits.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Steps, the solvers' iterations and the particle count of a 2D or 3D run.
fn counts(sim: &Simulation) -> (u64, [u64; 2], usize) {
    match sim.state_3d() {
        Some(st) => (st.step, st.solver_iterations, st.fluid.len()),
        None => {
            let st = sim.state();
            (st.step, st.solver_iterations, st.fluid.len())
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rheology = args.first().map_or("newtonian", |s| s.as_str());
    let ppd: i64 = args.get(1).map_or(Ok(40), |s| s.parse())?;
    let threads: i64 = args.get(2).map_or(Ok(2), |s| s.parse())?;
    let t_star_end: f64 = args.get(3).map_or(Ok(8.0), |s| s.parse())?;
    let dimension: i64 = args.get(4).map_or(Ok(2), |s| s.parse())?;
    let mut cfg = SceneConfig::default();
    for (k, v) in [
        ("scheme", Value::Text("isph".into())),
        ("rheology", Value::Text(rheology.into())),
        ("viscosity", Value::Real(5.0)),
        ("initial_drop_height", Value::Real(0.02)),
        ("particles_per_diameter", Value::Integer(ppd)),
        ("threads", Value::Integer(threads)),
        ("dimension", Value::Integer(dimension)),
    ] {
        cfg.set(k, v)?;
    }
    // t* = t U / W with U = 1 m/s and W = 2 cm.
    let ts = 0.02;
    let mut sim = Simulation::new(cfg)?;
    let (t0, c0) = (Instant::now(), cpu_seconds());
    let mut error = None;
    let mut k = 0.0;
    while k < t_star_end {
        k = (k + 1.0f64).min(t_star_end);
        if let Err(e) = sim.advance_to(k * ts) {
            error = Some(e.to_string());
            break;
        }
        let o = sim.outputs();
        let st = counts(&sim);
        eprintln!(
            "t* = {k:.1}: W* = {:.3}, {} steps, PPE iterations {}, viscous {}, {:.1} s, CPU {:.1} s",
            o.shared.drop_width / 0.02,
            st.0,
            st.1[0],
            st.1[1],
            t0.elapsed().as_secs_f64(),
            cpu_seconds() - c0
        );
    }
    let (wall, cpu) = (t0.elapsed().as_secs_f64(), cpu_seconds() - c0);
    let st = counts(&sim);
    let steps = st.0.max(1) as f64;
    let tm = sim.scheme_timings();
    let tot = tm.total.max(1e-12);
    println!("| rheology | W/dr | particles | threads | t* | steps | wall [s] | CPU [s] | PPE iterations/step | viscous iterations/step | time in PPE | time in viscous solve |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    println!(
        "| {rheology} | {ppd} | {} | {threads} | {k} | {} | {wall:.1} | {cpu:.1} | {:.1} | {:.1} | {:.0} % | {:.0} % |{}",
        st.2,
        st.0,
        st.1[0] as f64 / steps,
        st.1[1] as f64 / steps,
        100.0 * tm.part("pressure solve") / tot,
        100.0 * tm.part("viscous solve") / tot,
        error.map(|e| format!(" broke down: {e}")).unwrap_or_default()
    );
    println!("state fingerprint {:016x}", fingerprint(&sim));
    Ok(())
}
