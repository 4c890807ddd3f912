//! The FMI 3.0 entry points in-process: against the official header's typedefs (bindgen
//! output of `fmi-sys`), bitwise against the FMI 2.0 core they share, FMU states, the plate
//! input, and the statuses of wrong calls.
use super::*;
use crate::fmi2::instance::Phase;
use crate::scene::{param_spec, OUTPUTS};
use fmi_sys::fmi3 as h;
use std::ffi::CStr;
use std::os::raw::{c_char, c_void};

/// Every function of `fmi3Functions.h` is exported with exactly the header's type (the list
/// is the one fmpy 0.3.32 resolves when it loads a binary); a wrong argument list does not
/// compile.
#[test]
fn exports_match_the_header_signatures() {
    let _: h::fmi3ActivateModelPartitionTYPE = Some(fmi3ActivateModelPartition);
    let _: h::fmi3CompletedIntegratorStepTYPE = Some(fmi3CompletedIntegratorStep);
    let _: h::fmi3DeserializeFMUStateTYPE = Some(fmi3DeserializeFMUState);
    let _: h::fmi3DoStepTYPE = Some(fmi3DoStep);
    let _: h::fmi3EnterConfigurationModeTYPE = Some(fmi3EnterConfigurationMode);
    let _: h::fmi3EnterContinuousTimeModeTYPE = Some(fmi3EnterContinuousTimeMode);
    let _: h::fmi3EnterEventModeTYPE = Some(fmi3EnterEventMode);
    let _: h::fmi3EnterInitializationModeTYPE = Some(fmi3EnterInitializationMode);
    let _: h::fmi3EnterStepModeTYPE = Some(fmi3EnterStepMode);
    let _: h::fmi3EvaluateDiscreteStatesTYPE = Some(fmi3EvaluateDiscreteStates);
    let _: h::fmi3ExitConfigurationModeTYPE = Some(fmi3ExitConfigurationMode);
    let _: h::fmi3ExitInitializationModeTYPE = Some(fmi3ExitInitializationMode);
    let _: h::fmi3FreeFMUStateTYPE = Some(fmi3FreeFMUState);
    let _: h::fmi3FreeInstanceTYPE = Some(fmi3FreeInstance);
    let _: h::fmi3GetAdjointDerivativeTYPE = Some(fmi3GetAdjointDerivative);
    let _: h::fmi3GetBinaryTYPE = Some(fmi3GetBinary);
    let _: h::fmi3GetBooleanTYPE = Some(fmi3GetBoolean);
    let _: h::fmi3GetClockTYPE = Some(fmi3GetClock);
    let _: h::fmi3GetContinuousStateDerivativesTYPE = Some(fmi3GetContinuousStateDerivatives);
    let _: h::fmi3GetContinuousStatesTYPE = Some(fmi3GetContinuousStates);
    let _: h::fmi3GetDirectionalDerivativeTYPE = Some(fmi3GetDirectionalDerivative);
    let _: h::fmi3GetEventIndicatorsTYPE = Some(fmi3GetEventIndicators);
    let _: h::fmi3GetFMUStateTYPE = Some(fmi3GetFMUState);
    let _: h::fmi3GetFloat32TYPE = Some(fmi3GetFloat32);
    let _: h::fmi3GetFloat64TYPE = Some(fmi3GetFloat64);
    let _: h::fmi3GetInt16TYPE = Some(fmi3GetInt16);
    let _: h::fmi3GetInt32TYPE = Some(fmi3GetInt32);
    let _: h::fmi3GetInt64TYPE = Some(fmi3GetInt64);
    let _: h::fmi3GetInt8TYPE = Some(fmi3GetInt8);
    let _: h::fmi3GetIntervalDecimalTYPE = Some(fmi3GetIntervalDecimal);
    let _: h::fmi3GetIntervalFractionTYPE = Some(fmi3GetIntervalFraction);
    let _: h::fmi3GetNominalsOfContinuousStatesTYPE = Some(fmi3GetNominalsOfContinuousStates);
    let _: h::fmi3GetNumberOfContinuousStatesTYPE = Some(fmi3GetNumberOfContinuousStates);
    let _: h::fmi3GetNumberOfEventIndicatorsTYPE = Some(fmi3GetNumberOfEventIndicators);
    let _: h::fmi3GetNumberOfVariableDependenciesTYPE = Some(fmi3GetNumberOfVariableDependencies);
    let _: h::fmi3GetOutputDerivativesTYPE = Some(fmi3GetOutputDerivatives);
    let _: h::fmi3GetShiftDecimalTYPE = Some(fmi3GetShiftDecimal);
    let _: h::fmi3GetShiftFractionTYPE = Some(fmi3GetShiftFraction);
    let _: h::fmi3GetStringTYPE = Some(fmi3GetString);
    let _: h::fmi3GetUInt16TYPE = Some(fmi3GetUInt16);
    let _: h::fmi3GetUInt32TYPE = Some(fmi3GetUInt32);
    let _: h::fmi3GetUInt64TYPE = Some(fmi3GetUInt64);
    let _: h::fmi3GetUInt8TYPE = Some(fmi3GetUInt8);
    let _: h::fmi3GetVariableDependenciesTYPE = Some(fmi3GetVariableDependencies);
    let _: h::fmi3GetVersionTYPE = Some(fmi3GetVersion);
    let _: h::fmi3InstantiateCoSimulationTYPE = Some(fmi3InstantiateCoSimulation);
    let _: h::fmi3InstantiateModelExchangeTYPE = Some(fmi3InstantiateModelExchange);
    let _: h::fmi3InstantiateScheduledExecutionTYPE = Some(fmi3InstantiateScheduledExecution);
    let _: h::fmi3ResetTYPE = Some(fmi3Reset);
    let _: h::fmi3SerializeFMUStateTYPE = Some(fmi3SerializeFMUState);
    let _: h::fmi3SerializedFMUStateSizeTYPE = Some(fmi3SerializedFMUStateSize);
    let _: h::fmi3SetBinaryTYPE = Some(fmi3SetBinary);
    let _: h::fmi3SetBooleanTYPE = Some(fmi3SetBoolean);
    let _: h::fmi3SetClockTYPE = Some(fmi3SetClock);
    let _: h::fmi3SetContinuousStatesTYPE = Some(fmi3SetContinuousStates);
    let _: h::fmi3SetDebugLoggingTYPE = Some(fmi3SetDebugLogging);
    let _: h::fmi3SetFMUStateTYPE = Some(fmi3SetFMUState);
    let _: h::fmi3SetFloat32TYPE = Some(fmi3SetFloat32);
    let _: h::fmi3SetFloat64TYPE = Some(fmi3SetFloat64);
    let _: h::fmi3SetInt16TYPE = Some(fmi3SetInt16);
    let _: h::fmi3SetInt32TYPE = Some(fmi3SetInt32);
    let _: h::fmi3SetInt64TYPE = Some(fmi3SetInt64);
    let _: h::fmi3SetInt8TYPE = Some(fmi3SetInt8);
    let _: h::fmi3SetIntervalDecimalTYPE = Some(fmi3SetIntervalDecimal);
    let _: h::fmi3SetIntervalFractionTYPE = Some(fmi3SetIntervalFraction);
    let _: h::fmi3SetShiftDecimalTYPE = Some(fmi3SetShiftDecimal);
    let _: h::fmi3SetShiftFractionTYPE = Some(fmi3SetShiftFraction);
    let _: h::fmi3SetStringTYPE = Some(fmi3SetString);
    let _: h::fmi3SetTimeTYPE = Some(fmi3SetTime);
    let _: h::fmi3SetUInt16TYPE = Some(fmi3SetUInt16);
    let _: h::fmi3SetUInt32TYPE = Some(fmi3SetUInt32);
    let _: h::fmi3SetUInt64TYPE = Some(fmi3SetUInt64);
    let _: h::fmi3SetUInt8TYPE = Some(fmi3SetUInt8);
    let _: h::fmi3TerminateTYPE = Some(fmi3Terminate);
    let _: h::fmi3UpdateDiscreteStatesTYPE = Some(fmi3UpdateDiscreteStates);
    assert_eq!(
        Status::Discard.code() as fmi3Status,
        h::fmi3Status_fmi3Discard
    );
    assert_eq!(Status::Error.code() as fmi3Status, h::fmi3Status_fmi3Error);
}

/// The messages an instance logged: "status category message".
type Log = Vec<String>;

unsafe extern "C" fn record(
    env: *mut c_void,
    status: fmi3Status,
    category: *const c_char,
    message: *const c_char,
) {
    let log = &mut *(env as *mut Log);
    log.push(format!(
        "{status} {} {}",
        CStr::from_ptr(category).to_string_lossy(),
        CStr::from_ptr(message).to_string_lossy()
    ));
}

/// `fmi3InstantiateCoSimulation` with `token`, logging into `log`.
unsafe fn instantiate(token: &CStr, event_mode_used: bool, log: &mut Log) -> fmi3Instance {
    fmi3InstantiateCoSimulation(
        c"drop".as_ptr(),
        token.as_ptr(),
        ptr::null(),
        false,
        false,
        event_mode_used,
        false,
        ptr::null(),
        0,
        log as *mut Log as *mut c_void,
        Some(record),
        None,
    )
}

/// An FMI 3.0 instance logging into `log`, with `particles_per_diameter` = 12 (a small drop)
/// set through fmi3SetInt32.
unsafe fn small_instance(log: &mut Box<Log>) -> fmi3Instance {
    let c = instantiate(&c_text(&guid()), false, log);
    assert!(!c.is_null());
    let ppd = [vr("particles_per_diameter")];
    assert_eq!(fmi3SetInt32(c, ppd.as_ptr(), 1, [12].as_ptr(), 1), OK);
    c
}

/// Reset `c` and step it from t = 0 into the impact (the drop's gap of 0.03 m at 1 m/s), so
/// that the plate-load bins hold load.
unsafe fn restart_into_the_impact(c: fmi3Instance) {
    assert_eq!(fmi3Reset(c), OK);
    assert_eq!(
        fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
        OK
    );
    assert_eq!(fmi3ExitInitializationMode(c), OK);
    for k in 0..10 {
        assert_eq!(step(c, 0.004 * k as f64, 0.004).0, OK);
    }
}

/// [`small_instance`] initialised at `start` with the stop time `stop`, in Step Mode.
unsafe fn stepping_instance(log: &mut Box<Log>, start: f64, stop: Option<f64>) -> fmi3Instance {
    let c = small_instance(log);
    let status =
        fmi3EnterInitializationMode(c, false, 0.0, start, stop.is_some(), stop.unwrap_or(0.0));
    assert_eq!(status, OK);
    assert_eq!(fmi3ExitInitializationMode(c), OK);
    c
}

/// The same small drop on the core directly, as the FMI 2.0 entry points drive it.
fn small_core() -> Instance {
    let mut i = Instance::new("drop", false, Box::new(|_, _, _| {}));
    assert_eq!(
        i.set_integer(&[vr("particles_per_diameter")], &[12]),
        Status::Ok
    );
    i
}

const OK: fmi3Status = 0;
const DISCARD: fmi3Status = 2;
const ERROR: fmi3Status = 3;

fn vr(name: &str) -> u32 {
    param_spec(name).unwrap().value_reference
}

fn output_vrs() -> Vec<u32> {
    OUTPUTS.iter().map(|o| o.value_reference).collect()
}

fn output_vr(name: &str) -> u32 {
    OUTPUTS
        .iter()
        .find(|o| o.name == name)
        .unwrap()
        .value_reference
}

unsafe fn outputs3(c: fmi3Instance) -> Vec<f64> {
    let vrs = output_vrs();
    let mut v = vec![f64::NAN; vrs.len()];
    assert_eq!(
        fmi3GetFloat64(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), v.len()),
        OK
    );
    v
}

fn outputs_core(i: &mut Instance) -> Vec<f64> {
    let vrs = output_vrs();
    let mut v = vec![f64::NAN; vrs.len()];
    assert_eq!(i.get_real(&vrs, &mut v), Status::Ok);
    v
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// One fmi3DoStep with its out-arguments: (status, terminateSimulation, lastSuccessfulTime).
unsafe fn step(c: fmi3Instance, t: f64, h: f64) -> (fmi3Status, bool, f64) {
    let (mut event, mut term, mut early, mut last) = (true, true, true, f64::NAN);
    let st = fmi3DoStep(c, t, h, false, &mut event, &mut term, &mut early, &mut last);
    assert!(!event && !early, "no event handling, no early return");
    (st, term, last)
}

#[test]
fn the_drop_through_fmi3_is_the_fmi2_drop_bitwise() {
    let mut log = Box::default();
    unsafe {
        let c = stepping_instance(&mut log, 0.0, Some(0.16));
        let mut core = small_core();
        assert_eq!(core.setup_experiment(None, 0.0, Some(0.16)), Status::Ok);
        assert_eq!(core.enter_initialization_mode(), Status::Ok);
        assert_eq!(core.exit_initialization_mode(), Status::Ok);
        assert_eq!(bits(&outputs3(c)), bits(&outputs_core(&mut core)));
        for k in 0..3 {
            let t = k as f64 * 0.002;
            assert_eq!(step(c, t, 0.002), (OK, false, t + 0.002));
            assert_eq!(core.do_step(t, 0.002), Status::Ok);
            assert_eq!(
                bits(&outputs3(c)),
                bits(&outputs_core(&mut core)),
                "t = {t}"
            );
        }
        // The drop fell: its centre is lower and it moves downwards.
        let h0 = small_core_initial_height();
        let i = OUTPUTS
            .iter()
            .position(|o| o.name == "drop_height")
            .unwrap();
        assert!(outputs3(c)[i] != h0);
        assert_eq!(fmi3Terminate(c), OK);
        fmi3FreeInstance(c);
    }
    assert!(
        log.iter().all(|m| !m.contains("fmi2")),
        "FMI 3.0 messages name FMI 3.0 calls: {log:?}"
    );
}

fn small_core_initial_height() -> f64 {
    let mut core = small_core();
    assert_eq!(core.enter_initialization_mode(), Status::Ok);
    let i = OUTPUTS
        .iter()
        .position(|o| o.name == "drop_height")
        .unwrap();
    outputs_core(&mut core)[i]
}

/// FMU state: a restored state continues bitwise as the original did, from the instance and
/// from its serialized bytes.
#[test]
fn fmu_state_save_and_restore_are_bitwise() {
    let mut log = Box::default();
    unsafe {
        let c = stepping_instance(&mut log, 0.0, None);
        assert_eq!(step(c, 0.0, 0.002).0, OK);
        let mut s: fmi3FMUState = ptr::null_mut();
        assert_eq!(fmi3GetFMUState(c, &mut s), OK);
        assert_eq!(step(c, 0.002, 0.002).0, OK);
        let first = bits(&outputs3(c));

        assert_eq!(fmi3SetFMUState(c, s), OK);
        assert_eq!(step(c, 0.002, 0.002), (OK, false, 0.004));
        assert_eq!(bits(&outputs3(c)), first);

        let mut size = 0usize;
        assert_eq!(fmi3SerializedFMUStateSize(c, s, &mut size), OK);
        let mut buf = vec![0u8; size];
        assert_eq!(fmi3SerializeFMUState(c, s, buf.as_mut_ptr(), size), OK);
        assert_eq!(fmi3FreeFMUState(c, &mut s), OK);
        assert!(s.is_null());
        let mut s2: fmi3FMUState = ptr::null_mut();
        assert_eq!(fmi3DeserializeFMUState(c, buf.as_ptr(), size, &mut s2), OK);
        assert_eq!(fmi3Reset(c), OK);
        assert_eq!(fmi3SetFMUState(c, s2), OK);
        assert_eq!(step(c, 0.002, 0.002), (OK, false, 0.004));
        assert_eq!(bits(&outputs3(c)), first);
        assert_eq!(fmi3FreeFMUState(c, &mut s2), OK);
        fmi3FreeInstance(c);
    }
}

/// The plate input through fmi3SetFloat64 after initialization: the plate moves at the speed
/// set (its displacement is the speed times the time since), and the outputs are those of the
/// FMI 2.0 core given the same input, bitwise.
#[test]
fn the_plate_input_moves_the_plate() {
    let mut log = Box::default();
    let v = -0.5;
    let input = [vr("plate_velocity")];
    unsafe {
        let c = stepping_instance(&mut log, 0.0, None);
        let mut core = small_core();
        assert_eq!(core.enter_initialization_mode(), Status::Ok);
        assert_eq!(core.exit_initialization_mode(), Status::Ok);
        assert_eq!(step(c, 0.0, 0.002).0, OK);
        assert_eq!(core.do_step(0.0, 0.002), Status::Ok);
        assert_eq!(fmi3SetFloat64(c, input.as_ptr(), 1, [v].as_ptr(), 1), OK);
        assert_eq!(core.set_real(&input, &[v]), Status::Ok);
        let mut back = [0.0];
        assert_eq!(
            fmi3GetFloat64(c, input.as_ptr(), 1, back.as_mut_ptr(), 1),
            OK
        );
        assert_eq!(back[0], v);
        let d = [output_vr("plate_displacement")];
        let mut d0 = [f64::NAN];
        assert_eq!(fmi3GetFloat64(c, d.as_ptr(), 1, d0.as_mut_ptr(), 1), OK);
        assert_eq!(d0[0], 0.0, "the plate has not moved before the input");
        for k in 1..3 {
            let t = k as f64 * 0.002;
            assert_eq!(step(c, t, 0.002).0, OK);
            assert_eq!(core.do_step(t, 0.002), Status::Ok);
        }
        assert_eq!(bits(&outputs3(c)), bits(&outputs_core(&mut core)));
        let mut d1 = [f64::NAN];
        assert_eq!(fmi3GetFloat64(c, d.as_ptr(), 1, d1.as_mut_ptr(), 1), OK);
        let expected = v * 0.004;
        assert!(
            (d1[0].abs() - expected.abs()).abs() < 1e-12,
            "plate displacement {} after 4 ms at {v} m/s",
            d1[0]
        );
        fmi3FreeInstance(c);
    }
}

/// Wrong calls answer the statuses FMI 3.0 allows, in FMI 3.0's words, and the error state
/// is left by fmi3Reset.
#[test]
fn wrong_calls_answer_error_in_fmi3_words() {
    let mut log: Box<Log> = Box::default();
    let token = c_text(&guid());
    unsafe {
        let env = &mut *log as *mut Log as *mut c_void;
        // Interfaces and tokens this binary does not have.
        assert!(fmi3InstantiateModelExchange(
            c"me".as_ptr(),
            token.as_ptr(),
            ptr::null(),
            false,
            false,
            env,
            Some(record)
        )
        .is_null());
        assert!(instantiate(c"{00000000-0000-0000-0000-000000000000}", false, &mut log).is_null());
        assert!(
            log.last().unwrap().contains("instantiationToken"),
            "{log:?}"
        );
        assert!(instantiate(&token, true, &mut log).is_null());
        assert!(log.last().unwrap().contains("eventModeUsed"), "{log:?}");

        let c = small_instance(&mut log);
        let inst = instance(c).unwrap();
        // A step before initialization: the error state, named in FMI 3.0 words.
        assert_eq!(step(c, 0.0, 0.001).0, ERROR);
        assert_eq!(inst.phase(), Phase::Error);
        let m = log.last().unwrap();
        assert!(
            m.starts_with("3 logStatusError fmi3DoStep: illegal call sequence"),
            "{m}"
        );
        assert!(
            m.contains("fmi3EnterInitializationMode") && !m.contains("fmi2"),
            "{m}"
        );
        assert_eq!(fmi3Reset(c), OK);
        assert_eq!(inst.phase(), Phase::Instantiated);

        // Types: Int32 is for Integer parameters, Int64 for Enumerations.
        let scheme = [vr("scheme")];
        let ppd = [vr("particles_per_diameter")];
        let mut i64v = [0i64];
        let mut i32v = [0i32];
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            OK
        );
        assert_eq!(
            fmi3GetInt64(c, scheme.as_ptr(), 1, i64v.as_mut_ptr(), 1),
            OK
        );
        assert!(i64v[0] >= 1);
        assert_eq!(fmi3GetInt32(c, ppd.as_ptr(), 1, i32v.as_mut_ptr(), 1), OK);
        assert_eq!(i32v[0], 20, "the default after fmi3Reset");
        assert_eq!(
            fmi3GetInt32(c, scheme.as_ptr(), 1, i32v.as_mut_ptr(), 1),
            ERROR
        );
        assert_eq!(fmi3Reset(c), OK);
        assert_eq!(
            fmi3SetInt64(c, scheme.as_ptr(), 1, [1i64 << 40].as_ptr(), 1),
            ERROR
        );
        assert!(log.last().unwrap().contains("outside"), "{log:?}");
        assert_eq!(fmi3Reset(c), OK);
        // nValues must count the values of the variables named.
        assert_eq!(
            fmi3SetFloat64(c, scheme.as_ptr(), 1, [1.0, 2.0].as_ptr(), 2),
            ERROR
        );
        assert!(log.last().unwrap().contains("nValues = 2"), "{log:?}");
        assert_eq!(fmi3Reset(c), OK);
        // No Boolean variables: an empty call is fine, a named one is refused with its type.
        assert_eq!(fmi3SetBoolean(c, ptr::null(), 0, ptr::null(), 0), OK);
        assert_eq!(
            fmi3SetBoolean(c, ppd.as_ptr(), 1, [true].as_ptr(), 1),
            ERROR
        );
        assert_eq!(fmi3Reset(c), OK);
        // Steps that are not finite, out-arguments that are NULL.
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            OK
        );
        assert_eq!(fmi3ExitInitializationMode(c), OK);
        assert_eq!(step(c, 0.0, f64::INFINITY).0, ERROR);
        assert!(log.last().unwrap().contains("must be finite"), "{log:?}");
        assert_eq!(fmi3Reset(c), OK);
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            OK
        );
        assert_eq!(fmi3ExitInitializationMode(c), OK);
        let (mut a, mut b, mut l) = (false, false, 0.0);
        assert_eq!(
            fmi3DoStep(
                c,
                0.0,
                0.001,
                false,
                &mut a,
                ptr::null_mut(),
                &mut b,
                &mut l
            ),
            ERROR
        );
        assert_eq!(fmi3Reset(c), OK);
        // Functions this FMU does not provide.
        assert_eq!(fmi3SetTime(c, 0.0), ERROR);
        assert_eq!(fmi3Reset(c), OK);
        assert_eq!(fmi3EnterEventMode(c), ERROR);
        assert_eq!(fmi3Reset(c), OK);
        // A stop time past the run-length rule is refused at initialization.
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, true, 1e9),
            OK
        );
        assert_eq!(fmi3ExitInitializationMode(c), ERROR);
        assert!(
            log.last().unwrap().contains("fmi3EnterInitializationMode"),
            "{log:?}"
        );
        fmi3FreeInstance(c);
        // A discarded step (over the step budget) answers fmi3Discard with the last good time.
        let c = small_instance(&mut log);
        let budget = [vr("max_steps_per_do_step")];
        assert_eq!(fmi3SetInt32(c, budget.as_ptr(), 1, [2].as_ptr(), 1), OK);
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            OK
        );
        assert_eq!(fmi3ExitInitializationMode(c), OK);
        let (st, term, last) = step(c, 0.0, 0.01);
        assert_eq!((st, term), (DISCARD, false));
        assert!(last > 0.0 && last < 0.01, "{last}");
        assert_eq!(fmi3Terminate(c), OK);
        fmi3FreeInstance(c);
    }
    assert!(log.iter().all(|m| !m.contains("fmi2")), "{log:?}");
    assert_eq!(unsafe { CStr::from_ptr(fmi3GetVersion()) }, c"3.0");
}

/// The FMI 3.0 array variables `wall_pressure` and `wall_shear` hold their scalar elements
/// bitwise (FMI 3.0 section 2.2.6.2: `nValues` counts the array's elements), and `time` (value
/// reference 0) reads the current communication point and cannot be set.
#[test]
fn arrays_are_their_elements_and_time_is_the_communication_point() {
    use crate::scene::OUTPUT_ARRAYS;
    let mut log = Box::default();
    unsafe {
        let c = stepping_instance(&mut log, 0.5, Some(0.66));
        let time = [crate::fmi3::TIME_VR];
        let mut t = [f64::NAN];
        assert_eq!(fmi3GetFloat64(c, time.as_ptr(), 1, t.as_mut_ptr(), 1), OK);
        assert_eq!(t[0], 0.5);
        let mut now = 0.5;
        while now < 0.5 + 0.008 {
            assert_eq!(step(c, now, 0.004).0, OK);
            now += 0.004;
        }
        assert_eq!(fmi3GetFloat64(c, time.as_ptr(), 1, t.as_mut_ptr(), 1), OK);
        assert_eq!(t[0], now);
        assert_eq!(
            fmi3SetFloat64(c, time.as_ptr(), 1, [1.0].as_ptr(), 1),
            ERROR
        );
        assert!(
            log.last().unwrap().contains("independent variable"),
            "{log:?}"
        );
        restart_into_the_impact(c);
        assert_eq!(OUTPUT_ARRAYS.len(), 2);
        let mut normal_load = 0.0;
        for a in OUTPUT_ARRAYS.iter() {
            let elements: Vec<u32> = (0..a.len as u32).map(|k| a.first_element_vr + k).collect();
            let mut scalars = vec![f64::NAN; a.len];
            assert_eq!(
                fmi3GetFloat64(c, elements.as_ptr(), a.len, scalars.as_mut_ptr(), a.len),
                OK
            );
            // The array alone, then between two scalars: nValues = len + 2.
            let mut array = vec![f64::NAN; a.len];
            let one = [a.value_reference];
            assert_eq!(
                fmi3GetFloat64(c, one.as_ptr(), 1, array.as_mut_ptr(), a.len),
                OK
            );
            assert_eq!(bits(&array), bits(&scalars), "{}", a.name);
            let mixed = [
                output_vr("drop_width"),
                a.value_reference,
                output_vr("wall_moment"),
            ];
            let mut v = vec![f64::NAN; a.len + 2];
            assert_eq!(
                fmi3GetFloat64(c, mixed.as_ptr(), 3, v.as_mut_ptr(), a.len + 2),
                OK
            );
            assert_eq!(bits(&v[1..=a.len]), bits(&scalars));
            // nValues that does not count the elements is refused.
            assert_eq!(
                fmi3GetFloat64(c, one.as_ptr(), 1, array.as_mut_ptr(), 1),
                ERROR
            );
            assert!(log.last().unwrap().contains("nValues = 1"), "{log:?}");
            restart_into_the_impact(c);
            if a.name == "wall_pressure" {
                normal_load = scalars.iter().sum::<f64>();
            }
        }
        assert!(normal_load > 0.0, "the drop loads the plate by 40 ms");
        fmi3FreeInstance(c);
    }
}
