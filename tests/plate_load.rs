//! The load along the plate (`wall_pressure_NNN`, `wall_shear_NNN`, `wall_moment`,
//! `wall_centre_of_pressure`, filled by the drop scene from `State::plate_load`).

mod common;

use common::{i, r, s};
use viscosph::scene::drop::{WALL_BINS, WALL_BIN_SPAN};
use viscosph::scene::{Outputs, SceneConfig};
use viscosph::simulation::Simulation;

fn drop_cfg(scheme: &str, inclination: f64) -> SceneConfig {
    let mut c = SceneConfig::default();
    c.set("scheme", s(scheme)).unwrap();
    c.set("rheology", s("newtonian")).unwrap();
    c.set("sound_speed", r(12.5)).unwrap();
    c.set("plate_inclination", r(inclination)).unwrap();
    c.set(
        "initial_drop_height",
        r(0.0115 / inclination.to_radians().cos()),
    )
    .unwrap();
    c.set("particles_per_diameter", i(16)).unwrap();
    if scheme == "isph" {
        c.set("wall_boundary", s("auto")).unwrap();
    }
    c
}

fn bins(o: &Outputs, stem: &str) -> Vec<f64> {
    (1..=WALL_BINS)
        .map(|k| o.get(&format!("{stem}_{k:03}")).unwrap())
        .collect()
}

/// Sum of the bins times the bin length: the force they stand for [N/m].
fn integral(o: &Outputs, stem: &str, width: f64) -> f64 {
    bins(o, stem).iter().map(|p| p * width).sum()
}

/// The bins integrate to the total wall force, normal and tangential, to round-off, for the
/// three schemes and an inclined plate; the moment over the normal force is the centre of
/// pressure.
#[test]
fn the_bins_integrate_to_the_wall_force() {
    for (scheme, inclination) in [
        ("wcsph", 0.0),
        ("pdri", 0.0),
        ("wcsph", 30.0),
        ("isph", 0.0),
        ("isph", 30.0),
    ] {
        let c = drop_cfg(scheme, inclination);
        let width = WALL_BIN_SPAN * c.drop.drop_diameter / WALL_BINS as f64;
        let mut sim = Simulation::new(c).unwrap();
        let mut loaded = 0;
        for k in 1..=12 {
            sim.advance_to(0.0005 * k as f64).unwrap();
            let o = sim.outputs();
            let (f_n, f_t) = (o.shared.wall_force_normal, o.shared.wall_force_tangential);
            let scale = f_n.abs().max(f_t.abs()).max(1e-300);
            let (e_n, e_t) = (
                (integral(&o, "wall_pressure", width) - f_n).abs() / scale,
                (integral(&o, "wall_shear", width) - f_t).abs() / scale,
            );
            assert!(
                e_n < 1e-12 && e_t < 1e-12,
                "{scheme} {inclination} deg, t = {}: {e_n:e} {e_t:e}",
                sim.time()
            );
            // The centre of pressure of the state itself (the outputs at a communication
            // point are interpolated value by value, and a ratio does not interpolate).
            let own = sim.scene().outputs(sim.state(), sim.effective_config());
            let f_n = own.shared.wall_force_normal;
            if f_n > 0.0 {
                loaded += 1;
                let centre = own.get("wall_centre_of_pressure").unwrap();
                let moment = own.get("wall_moment").unwrap();
                assert!(
                    (centre * f_n - moment).abs() <= 1e-12 * moment.abs().max(1e-300) + 1e-15,
                    "{centre} {moment} {f_n}"
                );
                // The load sits under the drop.
                assert!(centre.abs() < o.shared.drop_width, "{centre}");
            }
        }
        assert!(
            loaded >= 4,
            "{scheme}: the drop loaded the plate at {loaded} points"
        );
    }
}

/// A normal impact on a level plate is symmetric about the impact point: the normal load
/// mirrors bin for bin, the shear changes sign, the moment and the centre of pressure vanish
/// (against the load's own size).
#[test]
fn a_symmetric_impact_gives_symmetric_bins() {
    symmetric_bins("wcsph", 1e-9);
}

/// The same under the incompressible scheme, whose linear solves sum in index order and so
/// are mirror-symmetric only to the solvers' tolerance (measured at t = 4 ms: bins 3.3e-9 of
/// the peak, moment 5e-10 of the normal force times a bin length).
#[test]
fn a_symmetric_impact_gives_symmetric_bins_isph() {
    symmetric_bins("isph", 1e-7);
}

fn symmetric_bins(scheme: &str, tol: f64) {
    let c = drop_cfg(scheme, 0.0);
    let width = WALL_BIN_SPAN * c.drop.drop_diameter / WALL_BINS as f64;
    let mut sim = Simulation::new(c).unwrap();
    sim.advance_to(0.004).unwrap();
    let o = sim.outputs();
    let (p, t) = (bins(&o, "wall_pressure"), bins(&o, "wall_shear"));
    let peak = p.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let shear = t.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(peak > 0.0 && shear > 0.0, "loaded: {p:?} {t:?}");
    let f_n = o.shared.wall_force_normal;
    let moment = o.get("wall_moment").unwrap();
    for k in 0..WALL_BINS {
        let m = WALL_BINS - 1 - k;
        assert!(
            (p[k] - p[m]).abs() <= tol * peak,
            "pressure bins {k}, {m}: {} {}",
            p[k],
            p[m]
        );
        assert!(
            (t[k] + t[m]).abs() <= tol * peak,
            "shear bins {k}, {m}: {} {}",
            t[k],
            t[m]
        );
    }
    assert!(moment.abs() <= tol * f_n * width, "{moment}");
    assert!(o.get("wall_centre_of_pressure").unwrap().abs() <= tol * width);
}

/// Scenes other than the drop hold 0 in every bin.
#[test]
fn the_bins_are_zero_where_they_are_not_measured() {
    let mut c = SceneConfig::default();
    c.set("scene", s("channel")).unwrap();
    c.set("particles_per_diameter", i(8)).unwrap();
    let mut sim = Simulation::new(c).unwrap();
    sim.advance_to(0.001).unwrap();
    let o = sim.outputs();
    assert!(bins(&o, "wall_shear").iter().all(|&p| p == 0.0));
    assert_eq!(o.get("wall_moment"), Some(0.0));
}

/// The incompressible scheme's load by particle is bitwise the same for any thread count.
#[test]
fn the_isph_load_does_not_depend_on_the_thread_count() {
    let load = |threads: i64| {
        let mut c = drop_cfg("isph", 30.0);
        c.set("threads", i(threads)).unwrap();
        let mut sim = Simulation::new(c).unwrap();
        sim.advance_to(0.003).unwrap();
        assert_eq!(sim.state().plate_load.len(), sim.state().fluid.len());
        sim.state().plate_load.clone()
    };
    let one = load(1);
    assert!(one.iter().any(|f| f.norm() > 0.0));
    assert_eq!(one, load(3));
}
