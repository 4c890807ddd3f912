//! Inputs held in the state and exact landing on communication points once they change
//! (the seam the FMU's `plate_velocity` input builds on).

mod common;

use common::{r, s};
use viscosph::scene::SceneConfig;
use viscosph::simulation::Simulation;

fn drop_cfg() -> SceneConfig {
    let mut c = SceneConfig::default();
    c.set("rheology", s("newtonian")).unwrap();
    c.set("sound_speed", r(12.5)).unwrap();
    c.set("initial_drop_height", r(0.014)).unwrap();
    c.set("plate_inclination", r(20.0)).unwrap();
    c
}

#[test]
fn setting_unchanged_inputs_changes_nothing() {
    let mut a = Simulation::new(drop_cfg()).unwrap();
    let mut b = Simulation::new(drop_cfg()).unwrap();
    for k in 1..=4 {
        let t = 0.0017 * k as f64;
        a.advance_to(t).unwrap();
        b.advance_to(t).unwrap();
        b.set_inputs(drop_cfg().inputs()).unwrap();
    }
    assert_eq!(a.state(), b.state());
    assert_eq!(a.outputs(), b.outputs());
}

#[test]
fn an_input_change_acts_from_the_communication_point_exactly() {
    let mut sim = Simulation::new(drop_cfg()).unwrap();
    let t1 = 0.00313;
    sim.advance_to(t1).unwrap();
    // Dense output: the solver's own state stepped past t1.
    assert!(sim.state().time > t1, "{}", sim.state().time);
    let before = sim.state().plate().unwrap().clone();
    sim.set_inputs(sim.inputs().with("plate_velocity", 0.25))
        .unwrap();
    // It went back and landed on t1 with the old input: the plate has not moved yet.
    assert_eq!(sim.state().time, t1);
    assert_eq!(sim.time(), t1);
    assert_eq!(sim.state().plate().unwrap().origin, before.origin);
    // From now on every communication point is landed on exactly.
    let t2 = 0.00471;
    sim.advance_to(t2).unwrap();
    assert_eq!(sim.state().time, t2);
    let plate = sim.state().plate().unwrap();
    let moved = 0.25 * (t2 - t1);
    assert!(
        (plate.displacement - moved).abs() < 1e-15,
        "{}",
        plate.displacement
    );
    // A rigid motion away from the fluid, along -n.
    let shift = plate.origin - before.origin;
    assert!((shift + plate.n * moved).norm() < 1e-15, "{shift}");
    // The outputs are those of the state itself (nothing to interpolate).
    let o = sim.outputs();
    assert_eq!(
        o.shared.drop_width,
        sim.scene()
            .outputs(sim.state(), sim.effective_config())
            .shared
            .drop_width
    );
}

#[test]
fn inputs_are_checked() {
    let mut sim = Simulation::new(drop_cfg()).unwrap();
    assert!(sim
        .set_inputs(sim.inputs().with("plate_velocity", f64::NAN))
        .is_err());
    let mut c = SceneConfig::default();
    c.set("scene", s("elliptical_drop")).unwrap();
    let mut ell = Simulation::new(c).unwrap();
    let e = ell
        .set_inputs(ell.inputs().with("plate_velocity", 1.0))
        .unwrap_err();
    assert!(e.to_string().contains("no free-standing plate"), "{e}");
}

#[test]
fn a_stop_flag_stops_before_the_next_step() {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let mut sim = Simulation::new(drop_cfg()).unwrap();
    sim.advance_to(0.001).unwrap();
    let flag = Arc::new(AtomicBool::new(false));
    sim.set_stop_flag(Some(flag.clone()));
    flag.store(true, Ordering::Relaxed);
    let step = sim.state().step;
    let e = sim.advance_to(0.01).unwrap_err();
    assert!(matches!(e, viscosph::SimError::Interrupted { .. }), "{e}");
    // Not one step more; the communication time is the state's.
    assert_eq!(sim.state().step, step);
    assert_eq!(sim.time(), sim.state().time);
    flag.store(false, Ordering::Relaxed);
    sim.advance_to(0.002).unwrap();
    assert!(sim.state().step > step);
}

/// A saved state holds the inputs in force and the moved plate: a run restored from it repeats
/// the original bitwise, in dense-output and in exact-landing mode alike.
#[test]
fn save_and_restore_with_a_moving_plate_repeat_the_run_bitwise() {
    let mut sim = Simulation::new(drop_cfg()).unwrap();
    sim.advance_to(0.002).unwrap();
    sim.set_inputs(sim.inputs().with("plate_velocity", 0.2))
        .unwrap();
    let saved = sim.save_state();
    sim.advance_to(0.004).unwrap();
    let first = (sim.state().clone(), sim.outputs());
    sim.restore_state(&saved).unwrap();
    assert_eq!(sim.inputs().get("plate_velocity").unwrap(), 0.2);
    sim.advance_to(0.004).unwrap();
    assert_eq!(first.1, sim.outputs());
    assert_eq!(first.0, *sim.state());
}

/// An input beyond the range the run was set up for is refused by name, before any change;
/// the same value runs when the run is set up for it.
#[test]
fn inputs_beyond_the_runs_range_are_refused_by_name() {
    use viscosph::SimError;
    let mut sim = Simulation::new(drop_cfg()).unwrap();
    let before = sim.state().clone();
    let e = sim
        .set_inputs(sim.inputs().with("plate_velocity", -5.0))
        .unwrap_err();
    assert!(matches!(e, SimError::InputOutOfRange(_)), "{e:?}");
    let msg = e.to_string();
    for part in [
        "plate_velocity = -5 m/s",
        "max_plate_speed = 1 m/s",
        "at least 5 m/s",
    ] {
        assert!(msg.contains(part), "{part}: {msg}");
    }
    assert_eq!(sim.inputs().get("plate_velocity"), Some(0.0));
    assert_eq!(*sim.state(), before);
    // Either way along the normal.
    assert!(sim
        .set_inputs(sim.inputs().with("plate_velocity", 1.5))
        .is_err());
    // Set up for it: max_plate_speed raised, and the automatic sound speed (which then covers
    // it; the 12.5 m/s of drop_cfg breaks down at 0.47 ms).
    let mut c = drop_cfg();
    c.set("max_plate_speed", r(5.0)).unwrap();
    c.set("sound_speed", r(0.0)).unwrap();
    let mut sim = Simulation::new(c.clone()).unwrap();
    sim.set_inputs(sim.inputs().with("plate_velocity", -5.0))
        .unwrap();
    sim.advance_to(0.001).unwrap();
    // A start value beyond it is refused when the simulation is built.
    c.set("max_plate_speed", r(0.5)).unwrap();
    c.set("plate_velocity", r(0.7)).unwrap();
    let e = Simulation::new(c).err().unwrap().to_string();
    assert!(
        e.contains("plate_velocity = 0.7 m/s") && e.contains("max_plate_speed"),
        "{e}"
    );
}

/// `plate_coupling = position`: over each communication step the plate moves at the constant
/// velocity that lands it on plate_position + plate_velocity (t - t_set); a jump it could
/// reach only faster than max_plate_speed is refused before any work.
#[test]
fn a_position_input_lands_the_plate_on_its_extrapolated_target() {
    let mut c = drop_cfg();
    c.set("plate_coupling", s("position")).unwrap();
    let mut sim = Simulation::new(c).unwrap();
    sim.advance_to(0.001).unwrap();
    assert_eq!(
        sim.state().time,
        0.001,
        "the steps land on communication points"
    );
    sim.set_inputs(
        sim.inputs()
            .with("plate_position", 2e-4)
            .with("plate_velocity", 0.1),
    )
    .unwrap();
    sim.advance_to(0.002).unwrap();
    let d = sim.outputs().shared.plate_displacement;
    assert!((d - (2e-4 + 0.1 * 1e-3)).abs() < 1e-15, "{d}");
    // Inputs held: the target goes on along the same line.
    sim.advance_to(0.003).unwrap();
    let d = sim.outputs().shared.plate_displacement;
    assert!((d - (2e-4 + 0.1 * 2e-3)).abs() < 1e-15, "{d}");
    // 1 cm in 1 ms is 10 m/s.
    sim.set_inputs(sim.inputs().with("plate_position", 0.01))
        .unwrap();
    let e = sim.advance_to(0.004).unwrap_err().to_string();
    assert!(
        e.contains("plate_position = 0.01 m") && e.contains("max_plate_speed"),
        "{e}"
    );
    assert_eq!(sim.time(), 0.003);
}

/// The jet's inflow: up to max_jet_velocity (0 = its start value).
#[test]
fn the_jet_velocity_input_is_held_to_max_jet_velocity() {
    use viscosph::scene::SceneKind;
    let mut c = SceneConfig::for_scene(SceneKind::Jet);
    c.set("particles_per_diameter", common::i(4)).unwrap();
    let mut sim = Simulation::new(c.clone()).unwrap();
    let e = sim
        .set_inputs(sim.inputs().with("jet_velocity", 0.4))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("jet_velocity = 0.4 m/s") && e.contains("max_jet_velocity"),
        "{e}"
    );
    sim.set_inputs(sim.inputs().with("jet_velocity", 0.1))
        .unwrap();
    c.set("max_jet_velocity", r(0.4)).unwrap();
    let mut sim = Simulation::new(c).unwrap();
    sim.set_inputs(sim.inputs().with("jet_velocity", 0.4))
        .unwrap();
}
