use viscosph::config::Value;
use viscosph::*;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut cfg = SceneConfig::default();
    for kv in &args[1..] {
        let (k, v) = kv.split_once('=').unwrap();
        let val = if let Ok(i) = v.parse::<i64>() { config::Value::Integer(i) } else if let Ok(x) = v.parse::<f64>() { Value::Real(x) } else { Value::Text(v.into()) };
        cfg.set(k, val).unwrap();
    }
    let mut sim = Simulation::new(cfg.clone()).unwrap();
    let t0 = std::time::Instant::now();
    let d = cfg.drop_diameter; let v = cfg.impact_velocity.max(1e-9);
    for k in 1..=40 {
        let t = k as f64 * 0.004;
        if let Err(e) = sim.advance_to(t) { println!("ERR {e}"); break; }
        let o = sim.outputs();
        println!("t*={:5.2} W*={:.3} H*={:.3} Fn={:8.3} Ft={:8.3} front={:.4} back={:.4} KE={:.3e} vol={:+.4} trA={:.3} dt={:.2e} steps={}",
          t*v/d, o.drop_width/d, o.drop_height/d, o.wall_force_normal, o.wall_force_tangential, o.spread_front, o.spread_back, o.kinetic_energy, o.volume_error, o.max_conformation_trace, o.time_step, sim.state().step);
    }
    let el = t0.elapsed().as_secs_f64();
    println!("N={} wall={:.2}s psteps/s={:.3e}", sim.state().fluid.len(), el, sim.state().fluid.len() as f64 * sim.state().step as f64 / el);
}
