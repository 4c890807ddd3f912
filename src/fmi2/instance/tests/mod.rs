//! Unit tests of the FMU instance's state machine.

use super::*;
use std::cell::RefCell;
use std::rc::Rc;

mod stepping;

type Log = Rc<RefCell<Vec<(Status, String, String)>>>;

fn instance(logging_on: bool) -> (Instance, Log) {
    let log: Log = Rc::new(RefCell::new(Vec::new()));
    let l = log.clone();
    let sink: LogSink =
        Box::new(move |st, cat, msg| l.borrow_mut().push((st, cat.to_string(), msg.to_string())));
    (Instance::new("test", logging_on, sink), log)
}

fn vr(name: &str) -> u32 {
    crate::scene::param_spec(name)
        .map(|p| p.value_reference)
        .or_else(|| {
            OUTPUTS
                .iter()
                .find(|o| o.name == name)
                .map(|o| o.value_reference)
        })
        .unwrap()
}

#[test]
fn string_twins_set_and_read_the_enumerations_all_or_nothing() {
    let (mut i, log) = instance(false);
    let twin = |name: &str| vr(name) + crate::scene::NAME_VR_OFFSET;
    assert_eq!(
        i.set_string(
            &[twin("rheology"), twin("scheme")],
            &[Some("giesekus".into()), Some("pdri".into())]
        ),
        Status::Ok
    );
    assert_eq!(
        i.config().fluid.rheology,
        crate::config::RheologyKind::Giesekus
    );
    assert_eq!(i.config().scheme, crate::scene::SchemeKind::Pdri);
    // a bad name in the second place leaves the first value unset too
    assert_eq!(
        i.set_string(
            &[twin("rheology"), twin("scene")],
            &[Some("cross".into()), Some("splash".into())]
        ),
        Status::Error
    );
    let msg = log.borrow().last().unwrap().2.clone();
    assert!(
        msg.contains("scene_name") && msg.contains("splash") && msg.contains("'drop'"),
        "{msg}"
    );
    assert_eq!(i.reset(), Status::Ok);
    assert_eq!(
        i.set_string(&[twin("rheology")], &[Some("ucm".into())]),
        Status::Ok
    );
    assert_eq!(
        i.set_string(&[twin("scheme")], &[None]),
        Status::Error,
        "NULL is refused"
    );
    i.reset();
    assert_eq!(i.enter_initialization_mode(), Status::Ok);
    let mut names = [""; 2];
    assert_eq!(
        i.get_string(&[twin("rheology"), twin("equation_of_state")], &mut names),
        Status::Ok
    );
    assert_eq!(
        names,
        ["oldroyd_b", "linear"],
        "reset restored the defaults"
    );
    // the Enumeration itself is not a String, nor the twin an Integer
    assert_eq!(
        i.get_string(&[vr("rheology")], &mut names[..1]),
        Status::Error
    );
    let mut ints = [0];
    assert_eq!(i.get_integer(&[twin("rheology")], &mut ints), Status::Error);
    let msg = log.borrow().last().unwrap().2.clone();
    assert!(
        msg.contains("rheology_name") && msg.contains("String"),
        "{msg}"
    );
}

#[test]
fn do_step_before_initialization_is_refused_and_reset_recovers() {
    let (mut i, log) = instance(false);
    assert_eq!(i.do_step(0.0, 0.001), Status::Error);
    let last = log.borrow().last().unwrap().clone();
    assert_eq!(last.1, "logStatusError");
    assert!(
        last.2.contains("fmi2DoStep") && last.2.contains("Instantiated"),
        "{}",
        last.2
    );
    assert_eq!(i.phase(), Phase::Error);
    assert_eq!(i.set_real(&[vr("drop_diameter")], &[0.03]), Status::Error);
    assert_eq!(i.reset(), Status::Ok);
    assert_eq!(i.phase(), Phase::Instantiated);
    assert_eq!(i.set_real(&[vr("drop_diameter")], &[0.03]), Status::Ok);
}

#[test]
fn bad_values_name_variable_value_and_range_and_change_nothing() {
    let (mut i, log) = instance(false);
    let st = i.set_real(
        &[vr("initial_drop_height"), vr("drop_diameter")],
        &[0.05, -0.01],
    );
    assert_eq!(st, Status::Error);
    let msg = log.borrow().last().unwrap().2.clone();
    assert!(
        msg.contains("drop_diameter") && msg.contains("-0.01") && msg.contains("(0, 10]"),
        "{msg}"
    );
    assert_eq!(
        i.config().drop.initial_drop_height,
        SceneConfig::default().drop.initial_drop_height
    );
    i.reset();
    assert_eq!(
        i.set_real(&[vr("plate_inclination")], &[90.0]),
        Status::Error
    );
    i.reset();
    assert_eq!(
        i.set_real(&[vr("viscosity_ratio")], &[f64::NAN]),
        Status::Error
    );
    assert!(log.borrow().last().unwrap().2.contains("NaN"));
    i.reset();
    assert_eq!(i.set_real(&[9999], &[1.0]), Status::Error);
    assert!(log.borrow().last().unwrap().2.contains("9999"));
    i.reset();
    assert_eq!(i.set_real(&[vr("drop_width")], &[1.0]), Status::Error);
    assert!(log.borrow().last().unwrap().2.contains("output"));
    i.reset();
    assert_eq!(i.set_real(&[vr("rheology")], &[1.0]), Status::Error);
    assert!(log.borrow().last().unwrap().2.contains("fmi2SetInteger"));
}

#[test]
fn cross_parameter_errors_surface_at_exit_initialization() {
    let (mut i, log) = instance(false);
    assert_eq!(
        i.set_integer(&[vr("particles_per_diameter")], &[4000]),
        Status::Ok
    );
    assert_eq!(i.enter_initialization_mode(), Status::Ok);
    assert_eq!(i.exit_initialization_mode(), Status::Error);
    let msg = log.borrow().last().unwrap().2.clone();
    assert!(
        msg.contains("particles_per_diameter") && msg.contains("memory"),
        "{msg}"
    );
}

#[test]
fn the_jet_under_isph_with_p_zero_on_its_surface_warns_once_at_initialization() {
    let twin = |name: &str| vr(name) + crate::scene::NAME_VR_OFFSET;
    let warnings = |scheme: &str, surface: &str| {
        let (mut i, log) = instance(true);
        assert_eq!(
            i.set_string(
                &[twin("scene"), twin("scheme"), twin("isph_free_surface")],
                &[
                    Some("jet".into()),
                    Some(scheme.into()),
                    Some(surface.into())
                ]
            ),
            Status::Ok
        );
        i.set_integer(&[vr("particles_per_diameter")], &[4]);
        assert_eq!(i.enter_initialization_mode(), Status::Ok);
        assert_eq!(i.exit_initialization_mode(), Status::Ok);
        assert_eq!(i.do_step(0.0, 1e-3), Status::Ok);
        let l = log.borrow();
        l.iter()
            .filter(|(st, cat, _)| *st == Status::Warning && cat == "logStatusWarning")
            .map(|(_, _, m)| m.clone())
            .collect::<Vec<_>>()
    };
    let w = warnings("isph", "zero_pressure");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("does not buckle") && w[0].contains("docs/methods.md"),
        "{}",
        w[0]
    );
    // The jet's own choice (auto: King & Lind's (35a) normal stress) buckles: no warning.
    assert!(warnings("isph", "auto").is_empty());
    assert!(warnings("wcsph", "auto").is_empty());
}

#[test]
fn logging_categories_are_honoured() {
    let (mut i, log) = instance(false);
    i.enter_initialization_mode();
    i.exit_initialization_mode();
    assert!(log.borrow().is_empty(), "events are off without loggingOn");
    assert_eq!(i.set_debug_logging(true, &["logEvents".into()]), Status::Ok);
    i.terminate();
    assert_eq!(log.borrow().last().unwrap().1, "logEvents");
    let n = log.borrow().len();
    assert_eq!(i.set_debug_logging(false, &[]), Status::Ok);
    assert_eq!(i.do_step(0.0, 1e-3), Status::Error, "Terminated");
    assert_eq!(log.borrow().len(), n, "everything off");
    assert_eq!(
        i.set_debug_logging(true, &["logBogus%s".into()]),
        Status::Error
    );
    assert_eq!(i.set_debug_logging(true, &["logAll".into()]), Status::Ok);
    assert_eq!(
        i.set_debug_logging(true, &["logBogus%s".into()]),
        Status::Error
    );
    let msg = log.borrow().last().unwrap().2.clone();
    assert!(
        msg.contains("'logBogus%s'") && msg.contains("logStatusDiscard"),
        "{msg}"
    );
}

#[test]
fn a_short_run_reports_outputs_and_last_successful_time() {
    let (mut i, _log) = instance(true);
    i.set_integer(&[vr("particles_per_diameter")], &[12]);
    i.setup_experiment(None, 0.0, Some(0.01));
    i.enter_initialization_mode();
    let mut w0 = [0.0];
    assert_eq!(i.get_real(&[vr("drop_width")], &mut w0), Status::Ok);
    assert!((w0[0] - 0.02).abs() < 1e-12, "{}", w0[0]);
    assert_eq!(i.exit_initialization_mode(), Status::Ok);
    assert_eq!(i.do_step(0.0, 0.005), Status::Ok);
    assert_eq!(i.do_step(0.004, 0.005), Status::Error, "not continuing");
    i.reset();
    i.set_integer(&[vr("particles_per_diameter")], &[12]);
    i.setup_experiment(None, 0.0, Some(0.01));
    i.enter_initialization_mode();
    i.exit_initialization_mode();
    assert_eq!(i.do_step(0.0, 0.005), Status::Ok);
    assert_eq!(i.do_step(0.005, 0.0), Status::Error, "h = 0");
    let mut t = 0.0;
    assert_eq!(i.get_real_status(2, &mut t), Status::Ok);
    assert_eq!(t, 0.005);
    let mut ppd = [0];
    assert_eq!(
        i.get_integer(&[vr("particles_per_diameter")], &mut ppd),
        Status::Ok
    );
    assert_eq!(ppd[0], 12);
}

#[test]
fn snapshots_round_trip_through_bytes_and_refuse_garbage() {
    let (mut i, _log) = instance(false);
    i.set_integer(&[vr("particles_per_diameter")], &[12]);
    i.enter_initialization_mode();
    i.exit_initialization_mode();
    i.do_step(0.0, 0.004);
    let mut snap = None;
    assert_eq!(i.get_state(&mut snap), Status::Ok);
    let bytes = snap.unwrap().to_bytes();
    let back = Snapshot::from_bytes(&bytes).unwrap();
    i.do_step(0.004, 0.004);
    let mut a = [0.0; 2];
    i.get_real(&[vr("drop_width"), vr("wall_force_normal")], &mut a);
    assert_eq!(i.set_state(&back), Status::Ok);
    i.do_step(0.004, 0.004);
    let mut b = [0.0; 2];
    i.get_real(&[vr("drop_width"), vr("wall_force_normal")], &mut b);
    assert_eq!(a, b);
    assert!(Snapshot::from_bytes(b"nonsense").is_err());
    assert!(Snapshot::from_bytes(&bytes[..bytes.len() / 2]).is_err());
}
