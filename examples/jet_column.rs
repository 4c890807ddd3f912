//! The falling column of the buckling jet over time (`viscosph::scene::jet::column`): its
//! length from the exit to the heap, its largest vertical gap (a torn column), particles across,
//! nearest-neighbour spacing, free-surface particles, smallest det A, first wall contact and
//! the deflection, where the smallest det A is (height, mm) and how many are below 0.9. Starts from King & Lind's jet (a scene file with only `scene = "jet"`);
//! every further argument is a scene-file line.
//!
//! `cargo run --release --example jet_column -- T_END INTERVAL 'scheme = "isph"' ...`

use viscosph::scene::jet::column;
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let t_end: f64 = args.get(1).map_or(0.3, |s| s.parse().unwrap());
    let every: f64 = args.get(2).map_or(0.005, |s| s.parse().unwrap());
    let mut text = String::from("scene = \"jet\"\n");
    for line in args.iter().skip(3) {
        text.push_str(line);
        text.push('\n');
    }
    let cfg = SceneConfig::from_toml_str(&text).unwrap();
    let mut sim = Simulation::new(cfg).unwrap();
    let eff = sim.effective_config().clone();
    println!(
        "{:>6} {:>6} {:>7} {:>6} {:>5} {:>5} {:>6} {:>6} {:>9} {:>8} {:>8} {:>7} {:>5}",
        "t",
        "steps",
        "contact",
        "length",
        "gap",
        "thin",
        "across",
        "nn",
        "surf/n",
        "min detA",
        "defl/D",
        "y(minA)",
        "n<0.9"
    );
    let mut contact = None;
    while sim.time() < t_end - 1e-12 {
        let t = sim.time() + every;
        if let Err(e) = sim.advance_to(t) {
            println!("breakdown at {:.4} s: {e}", sim.time());
            break;
        }
        let o = sim.outputs();
        if contact.is_none() && o.shared.wall_force_normal.abs() > 1e-3 {
            contact = Some(sim.time());
        }
        let c = column(sim.state(), &eff);
        // Where the smallest det A sits (height above the plate, mm) and how many are below 0.9.
        let st = sim.state();
        let dets: Vec<(f64, f64)> = st
            .fluid
            .conf
            .iter()
            .zip(&st.fluid.x)
            .map(|(a, x)| (a[(0, 0)] * a[(1, 1)] - a[(0, 1)] * a[(1, 0)], x.y))
            .collect();
        let low = dets.iter().filter(|d| d.0 < 0.9).count();
        let at = dets
            .iter()
            .fold((f64::INFINITY, 0.0), |m, d| if d.0 < m.0 { *d } else { m })
            .1;
        println!(
            "{:6.3} {:6} {:>7} {:6.1} {:5.1} {:5.1} {:6.1} {:6.2} {:>9} {:8.3} {:8.3} {:7.1} {:5}",
            sim.time(),
            sim.steps(),
            contact.map_or("-".to_string(), |t| format!("{t:.3}")),
            c.length,
            c.largest_gap,
            c.thinnest,
            c.median_across,
            c.spacing,
            format!("{}/{}", c.surface, c.particles),
            c.min_det,
            o.jet.jet_deflection / eff.jet.jet_width,
            at * 1e3,
            low,
        );
    }
}
