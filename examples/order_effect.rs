//! What the order of the particles in memory costs (issue 16): the same drop stepped from the
//! same state with its particles in the scene's lattice order, shuffled at random, sorted
//! along a Morton (Z) curve of cells of one spacing and sorted in rows of one spacing, on one thread, alternating, minimum CPU time
//! per particle-step over the rounds. The state is permuted through `save_state`/`restore_state`
//! (a saved state is `(SceneConfig, Saved { state, .. })`, so the fluid is the second record).
//!
//! `cargo run --release --example order_effect -- SCENE.toml [STEPS] [ROUNDS] [T_START]`

use std::time::Instant;
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;
use viscosph::state::State;

fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap();
    let rest = &stat[stat.rfind(')').unwrap() + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    (f[11].parse::<u64>().unwrap() + f[12].parse::<u64>().unwrap()) as f64 / 100.0
}

fn interleave(v: u32) -> u64 {
    let mut x = v as u64;
    x = (x | (x << 16)) & 0x0000_FFFF_0000_FFFF;
    x = (x | (x << 8)) & 0x00FF_00FF_00FF_00FF;
    x = (x | (x << 4)) & 0x0F0F_0F0F_0F0F_0F0F;
    x = (x | (x << 2)) & 0x3333_3333_3333_3333;
    x = (x | (x << 1)) & 0x5555_5555_5555_5555;
    x
}

fn permuted(bytes: &[u8], order: &str, dx: f64) -> Vec<u8> {
    let mut rd = bytes;
    let cfg: SceneConfig = bincode::deserialize_from(&mut rd).unwrap();
    let mut st: State = bincode::deserialize_from(&mut rd).unwrap();
    let n = st.fluid.len();
    let mut perm: Vec<usize> = (0..n).collect();
    match order {
        "lattice" => {}
        "shuffled" => {
            let mut s = 0x9E37_79B9_7F4A_7C15u64;
            for i in (1..n).rev() {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                perm.swap(i, (s % (i as u64 + 1)) as usize);
            }
        }
        "morton" => {
            let lo = st
                .fluid
                .x
                .iter()
                .fold((f64::INFINITY, f64::INFINITY), |a, p| {
                    (a.0.min(p.x), a.1.min(p.y))
                });
            let key = |i: usize| {
                let p = st.fluid.x[i];
                let cx = ((p.x - lo.0) / dx) as u32;
                let cy = ((p.y - lo.1) / dx) as u32;
                interleave(cx) | (interleave(cy) << 1)
            };
            perm.sort_by_key(|&i| (key(i), i));
        }
        "rows" => {
            // Lattice-like: rows of one spacing, ascending x within a row.
            let key = |i: usize| {
                let p = st.fluid.x[i];
                ((p.y / dx).floor() as i64, p.x)
            };
            perm.sort_by(|&a, &b| key(a).partial_cmp(&key(b)).unwrap().then(a.cmp(&b)));
        }
        _ => panic!("order {order}"),
    }
    let f = &st.fluid;
    let mut g = f.clone();
    g.x = perm.iter().map(|&i| f.x[i]).collect();
    g.v = perm.iter().map(|&i| f.v[i]).collect();
    g.rho = perm.iter().map(|&i| f.rho[i]).collect();
    if !f.conf.is_empty() {
        g.conf = perm.iter().map(|&i| f.conf[i]).collect();
    }
    st.fluid = g;
    let mut out = bincode::serialize(&cfg).unwrap();
    out.extend(bincode::serialize(&st).unwrap());
    out.extend_from_slice(rd);
    out
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&args[1]).unwrap();
    let steps: u64 = args.get(2).map_or(20, |s| s.parse().unwrap());
    let rounds: usize = args.get(3).map_or(3, |s| s.parse().unwrap());
    // Optionally run the drop to this time first (the order after the flow has mixed it).
    let t_start: f64 = args.get(4).map_or(0.0, |s| s.parse().unwrap());
    let mut cfg = SceneConfig::from_toml_str(&text).unwrap();
    cfg.numerics.threads = 1;
    let mut sim = Simulation::new(cfg).unwrap();
    sim.advance_to(t_start.max(1e-12)).unwrap();
    let dt = sim.state().last_dt;
    let dx = sim.effective_config().dx();
    let saved = sim.save_state();
    let n = sim.state().fluid.len();
    let orders = ["lattice", "shuffled", "morton", "rows"];
    let states: Vec<Vec<u8>> = orders.iter().map(|o| permuted(&saved, o, dx)).collect();
    let mut best = [f64::INFINITY; 4];
    for _ in 0..rounds {
        for (k, s) in states.iter().enumerate() {
            sim.restore_state(s).unwrap();
            let (s0, t0) = (sim.state().step, sim.time());
            let c0 = cpu_seconds();
            let w0 = Instant::now();
            sim.advance_to(t0 + dt * steps as f64 * 0.999).unwrap();
            let cpu = cpu_seconds() - c0;
            let done = sim.state().step - s0;
            let ns = 1e9 * cpu / (n as f64 * done as f64);
            best[k] = best[k].min(ns);
            eprintln!(
                "{:9} {n} particles {done} steps: {ns:.0} CPU ns/particle-step (wall {:.2} s)",
                orders[k],
                w0.elapsed().as_secs_f64()
            );
        }
    }
    for (o, b) in orders.iter().zip(best) {
        println!("{o}: {b:.0} CPU ns per particle-step (min over {rounds} rounds)");
    }
}
