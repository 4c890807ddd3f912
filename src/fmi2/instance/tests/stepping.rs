//! Unit tests of `fmi2DoStep`: the step budget, breakdowns, the run-length rule, inputs between
//! steps, and the error state after a refused step.

use super::*;

/// A small drop (12 particles across) set up for a run to `stop` (if any), initialized.
fn small_drop(reals: &[(&str, f64)], max_steps: Option<i32>, stop: Option<f64>) -> (Instance, Log) {
    let (mut i, log) = instance(false);
    assert_eq!(
        i.set_integer(&[vr("particles_per_diameter")], &[12]),
        Status::Ok
    );
    for &(name, x) in reals {
        assert_eq!(i.set_real(&[vr(name)], &[x]), Status::Ok, "{name}");
    }
    if let Some(n) = max_steps {
        assert_eq!(
            i.set_integer(&[vr("max_steps_per_do_step")], &[n]),
            Status::Ok
        );
    }
    assert_eq!(i.setup_experiment(None, 0.0, stop), Status::Ok);
    assert_eq!(i.enter_initialization_mode(), Status::Ok);
    assert_eq!(i.exit_initialization_mode(), Status::Ok);
    (i, log)
}

fn last_message(log: &Log) -> String {
    log.borrow().last().expect("a message").2.clone()
}

fn outputs_of(i: &mut Instance) -> Vec<f64> {
    let vrs: Vec<u32> = OUTPUTS.iter().map(|o| o.value_reference).collect();
    let mut v = vec![0.0; vrs.len()];
    assert_eq!(i.get_real(&vrs, &mut v), Status::Ok);
    v
}

fn last_successful_time(i: &mut Instance) -> f64 {
    let mut t = f64::NAN;
    assert_eq!(
        i.get_real_status(crate::fmi2::types::FMI2_LAST_SUCCESSFUL_TIME, &mut t),
        Status::Ok
    );
    t
}

fn terminated(i: &mut Instance) -> bool {
    let mut b = true;
    assert_eq!(
        i.get_boolean_status(crate::fmi2::types::FMI2_TERMINATED, &mut b),
        Status::Ok
    );
    b
}

/// Past `max_steps_per_do_step` a step is discarded at the last sub-step reached; the FMU state
/// taken then continues from there, and the budget changes where calls stop, not the
/// trajectory: a run pieced together from budget-cut steps ends bitwise where a run without a
/// budget ends (sub-steps are never shortened to land on a communication point, so the two
/// take the same sub-steps; the unbudgeted run's last step starts where the pieced one's does,
/// so that both compute the same end time).
#[test]
fn the_step_budget_discards_and_the_last_good_state_goes_on_bitwise() {
    let t_end = 0.006;
    let (mut i, log) = small_drop(&[], Some(7), None);
    let mut t = 0.0;
    let mut discards = 0;
    loop {
        match i.do_step(t, t_end - t) {
            Status::Ok => break,
            Status::Discard => {
                discards += 1;
                let msg = last_message(&log);
                assert!(
                    msg.contains("max_steps_per_do_step") && msg.contains("7 solver steps"),
                    "{msg}"
                );
                assert_eq!(i.phase(), Phase::StepFailed);
                assert!(!terminated(&mut i), "a budget stop is not the end");
                let reached = last_successful_time(&mut i);
                assert!(t < reached && reached < t_end, "{t} < {reached} < {t_end}");
                // StepFailed: no step until the last good state is set
                let mut snap = None;
                assert_eq!(i.get_state(&mut snap), Status::Ok);
                assert_eq!(i.set_state(&snap.unwrap()), Status::Ok);
                assert_eq!(i.phase(), Phase::StepComplete);
                t = reached;
            }
            other => panic!("{other:?}: {}", last_message(&log)),
        }
        assert!(discards < 1000);
    }
    assert!(discards >= 2, "the budget cut the step {discards} times");
    let got = outputs_of(&mut i);
    let (mut whole, _) = small_drop(&[], None, None);
    assert_eq!(whole.do_step(0.0, t), Status::Ok);
    assert_eq!(whole.do_step(t, t_end - t), Status::Ok);
    let want = outputs_of(&mut whole);
    for ((a, b), o) in got.iter().zip(&want).zip(OUTPUTS.iter()) {
        assert_eq!(a.to_bits(), b.to_bits(), "{}: {a} vs {b}", o.name);
    }
}

/// After a numerical breakdown the FMU state taken holds the last good state, at
/// fmi2LastSuccessfulTime; setting it lets the master step again from there.
#[test]
fn after_a_breakdown_the_last_good_state_is_retrievable_and_goes_on() {
    // Sound far slower than the impact: the fluid compresses and the health check stops it.
    let (mut i, log) = small_drop(&[("sound_speed", 1.0)], None, None);
    let h = 1e-3;
    let mut t = 0.0;
    let status = loop {
        match i.do_step(t, h) {
            Status::Ok => t += h,
            other => break other,
        }
        assert!(t < 0.1, "no breakdown");
    };
    assert_eq!(status, Status::Discard, "{}", last_message(&log));
    assert!(last_message(&log).contains("breakdown"));
    assert!(terminated(&mut i));
    let reached = last_successful_time(&mut i);
    assert!(
        t < reached && reached < t + h,
        "{t} < {reached} < {}",
        t + h
    );
    let at_discard = outputs_of(&mut i);
    assert!(at_discard.iter().all(|v| v.is_finite()));
    assert_eq!(i.do_step(t, h), Status::Error, "StepFailed takes no step");

    let (mut i, _) = small_drop(&[("sound_speed", 1.0)], None, None);
    let mut tt = 0.0;
    while i.do_step(tt, h) == Status::Ok {
        tt += h;
    }
    let mut snap = None;
    assert_eq!(i.get_state(&mut snap), Status::Ok);
    let snap = snap.unwrap();
    assert_eq!(i.set_state(&snap), Status::Ok);
    assert_eq!(i.phase(), Phase::StepComplete);
    assert!(!terminated(&mut i));
    assert_eq!(last_successful_time(&mut i), reached);
    let restored = outputs_of(&mut i);
    for (a, b) in restored.iter().zip(&at_discard) {
        assert_eq!(a.to_bits(), b.to_bits());
    }
    // The master may step again from there: with the same inputs the same sub-step (never
    // shortened without an input change) breaks down again, reproducibly.
    assert_eq!(i.do_step(reached, h), Status::Discard);
    assert_eq!(last_successful_time(&mut i), reached);
    assert_eq!(i.set_state(&snap), Status::Ok);
    assert_eq!(i.do_step(reached, h), Status::Discard);
    assert_eq!(last_successful_time(&mut i), reached);
}

/// The run-length rule of the CLI, on stopTime at fmi2ExitInitializationMode and on a
/// communication step (without stopTime) before any work.
#[test]
fn too_many_steps_are_refused_with_the_estimate() {
    let (mut i, log) = instance(false);
    i.set_integer(&[vr("particles_per_diameter")], &[12]);
    assert_eq!(i.setup_experiment(None, 0.0, Some(1e9)), Status::Ok);
    assert_eq!(i.enter_initialization_mode(), Status::Ok);
    assert_eq!(i.exit_initialization_mode(), Status::Error);
    let msg = last_message(&log);
    assert!(
        msg.contains("stopTime") && msg.contains("would take about") && msg.contains("1e8"),
        "{msg}"
    );

    let (mut i, log) = small_drop(&[], None, None);
    let started = std::time::Instant::now();
    assert_eq!(i.do_step(0.0, 1e9), Status::Discard);
    let msg = last_message(&log);
    assert!(
        msg.contains("communicationStepSize = 1000000000 s would take about")
            && msg.contains("nothing was computed"),
        "{msg}"
    );
    assert!(
        started.elapsed().as_secs_f64() < 60.0,
        "refused before any work"
    );
    assert_eq!(last_successful_time(&mut i), 0.0);
    let mut snap = None;
    assert_eq!(i.get_state(&mut snap), Status::Ok);
    assert_eq!(i.set_state(&snap.unwrap()), Status::Ok);
    assert_eq!(i.do_step(0.0, 1e-3), Status::Ok);
}

/// An input acts on the steps after it: no output feeds through (the ModelStructure's
/// `dependencies=""`), measured bitwise.
#[test]
fn setting_an_input_leaves_every_output_bitwise_until_the_next_step() {
    let (mut i, _) = small_drop(&[], None, None);
    let h = 1e-3;
    let mut t = 0.0;
    for _ in 0..4 {
        assert_eq!(i.do_step(t, h), Status::Ok);
        t += h;
    }
    let before = outputs_of(&mut i);
    assert_eq!(i.set_real(&[vr("plate_velocity")], &[-0.4]), Status::Ok);
    let after = outputs_of(&mut i);
    for (a, b) in before.iter().zip(&after) {
        assert_eq!(a.to_bits(), b.to_bits());
    }
    assert_eq!(i.do_step(t, h), Status::Ok);
    let next = outputs_of(&mut i);
    let k = crate::scene::output_index("plate_displacement").unwrap();
    assert!(
        ((next[k] - before[k]).abs() - 0.4 * h).abs() < 1e-12,
        "the plate moved 0.4 mm in the step: {} -> {}",
        before[k],
        next[k]
    );
}

/// "must be finite" for an infinite or NaN step, and the state after a refusal is called the
/// Error state, with the call and the reason that put the instance there.
#[test]
fn an_infinite_step_must_be_finite_and_later_calls_name_the_error_state() {
    for h in [f64::INFINITY, f64::NAN] {
        let (mut i, log) = small_drop(&[], None, None);
        assert_eq!(i.do_step(0.0, h), Status::Error);
        let msg = last_message(&log);
        assert!(msg.contains("must be finite"), "{msg}");
        assert_eq!(i.phase(), Phase::Error);
    }
    let (mut i, log) = instance(false);
    assert_eq!(i.set_real(&[vr("drop_diameter")], &[-1.0]), Status::Error);
    assert_eq!(i.enter_initialization_mode(), Status::Error);
    let msg = last_message(&log);
    assert!(
        msg.contains("state Error")
            && msg.contains("fmi2SetReal returned fmi2Error")
            && msg.contains("drop_diameter")
            && !msg.contains("Terminated"),
        "{msg}"
    );
    assert_eq!(i.reset(), Status::Ok);
    assert_eq!(i.enter_initialization_mode(), Status::Ok);
}

/// The first input change after a step the solver took past the communication point (it goes
/// back to the state before that step, whose wall had not grown yet): the next step runs, and
/// the plate moves by exactly v h. (Found by the random call sequences: the scheme kept the
/// wall particles of the later state and panicked.)
#[test]
fn an_input_set_after_the_first_step_moves_the_plate_from_there() {
    for ppd in [6, 12] {
        let (mut i, log) = instance(false);
        i.set_integer(&[vr("particles_per_diameter")], &[ppd]);
        i.enter_initialization_mode();
        assert_eq!(i.exit_initialization_mode(), Status::Ok);
        assert_eq!(i.do_step(0.0, 1e-5), Status::Ok);
        assert_eq!(i.set_real(&[vr("plate_velocity")], &[0.485]), Status::Ok);
        let h = 3.4e-4;
        assert_eq!(i.do_step(1e-5, h), Status::Ok, "{:?}", log.borrow().last());
        let k = crate::scene::output_index("plate_displacement").unwrap();
        let d = outputs_of(&mut i)[k];
        assert!((d.abs() - 0.485 * h).abs() < 1e-15, "ppd {ppd}: {d}");
    }
}

/// An input beyond the range the run was set up for: fmi2SetReal keeps it with a warning,
/// fmi2DoStep discards before any work with a message naming the input, its value and the
/// parameter to raise; the outputs stay those of the last communication point. A run set up
/// for it (max_plate_speed raised) takes the same value.
#[test]
fn a_plate_input_beyond_max_plate_speed_is_discarded_by_name() {
    let (mut i, log) = small_drop(&[("initial_drop_height", 0.012)], None, None);
    assert_eq!(i.do_step(0.0, 1e-3), Status::Ok);
    let before = outputs_of(&mut i);
    assert_eq!(
        i.set_real(&[vr("plate_velocity")], &[-5.0]),
        Status::Warning
    );
    assert_eq!(i.do_step(1e-3, 1e-3), Status::Discard);
    let msg = last_message(&log);
    for part in [
        "plate_velocity = -5 m/s",
        "max_plate_speed = 1 m/s",
        "at least 5 m/s",
        "Nothing was computed",
    ] {
        assert!(msg.contains(part), "{part}: {msg}");
    }
    assert_eq!(i.phase(), Phase::StepFailed);
    assert!(i.resumable());
    assert_eq!(outputs_of(&mut i), before, "nothing was computed");
    let mut t = 0.0;
    assert_eq!(i.get_real_status(2, &mut t), Status::Ok);
    assert_eq!(t, 1e-3);
    // Within the range: the same value runs.
    let (mut j, _) = small_drop(
        &[("initial_drop_height", 0.012), ("max_plate_speed", 5.0)],
        None,
        None,
    );
    assert_eq!(j.set_real(&[vr("plate_velocity")], &[-5.0]), Status::Ok);
    assert_eq!(j.do_step(0.0, 2e-3), Status::Ok);
    let d = outputs_of(&mut j)[OUTPUTS
        .iter()
        .position(|o| o.name == "plate_displacement")
        .unwrap()];
    assert!((d + 5.0 * 2e-3).abs() < 1e-15, "{d}");
}

/// A value set back within the range after the warning is put in force, and the step runs.
#[test]
fn an_input_set_back_within_the_range_runs() {
    let (mut i, _) = small_drop(&[("initial_drop_height", 0.012)], None, None);
    assert_eq!(i.set_real(&[vr("plate_velocity")], &[2.0]), Status::Warning);
    assert_eq!(i.set_real(&[vr("plate_velocity")], &[0.5]), Status::Ok);
    assert_eq!(i.do_step(0.0, 1e-3), Status::Ok);
    let d = outputs_of(&mut i)[OUTPUTS
        .iter()
        .position(|o| o.name == "plate_displacement")
        .unwrap()];
    assert!((d - 0.5e-3).abs() < 1e-15, "{d}");
}
