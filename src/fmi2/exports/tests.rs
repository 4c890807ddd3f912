//! The exported functions against the official header (bindgen output of `fmi-sys`, a
//! dev-dependency), and the C-level argument checks, in-process with `fmi-sys`'s C logger.
use super::fmu_state::*;
use super::unsupported::*;
use super::*;
use fmi::fmi2::binding as h;
use std::mem::{align_of, offset_of, size_of};

/// Each export has exactly the type of the header's `fmi2...TYPE` typedef; a wrong
/// argument list does not compile. (`fmi2Instantiate` and `fmi2NewDiscreteStates` use our
/// own struct types, checked for layout below.)
#[test]
fn exports_match_the_header_signatures() {
    let _: h::fmi2GetTypesPlatformTYPE = Some(fmi2GetTypesPlatform);
    let _: h::fmi2GetVersionTYPE = Some(fmi2GetVersion);
    let _: h::fmi2SetDebugLoggingTYPE = Some(fmi2SetDebugLogging);
    let _: h::fmi2FreeInstanceTYPE = Some(fmi2FreeInstance);
    let _: h::fmi2SetupExperimentTYPE = Some(fmi2SetupExperiment);
    let _: h::fmi2EnterInitializationModeTYPE = Some(fmi2EnterInitializationMode);
    let _: h::fmi2ExitInitializationModeTYPE = Some(fmi2ExitInitializationMode);
    let _: h::fmi2TerminateTYPE = Some(fmi2Terminate);
    let _: h::fmi2ResetTYPE = Some(fmi2Reset);
    let _: h::fmi2GetRealTYPE = Some(fmi2GetReal);
    let _: h::fmi2GetIntegerTYPE = Some(fmi2GetInteger);
    let _: h::fmi2GetBooleanTYPE = Some(fmi2GetBoolean);
    let _: h::fmi2GetStringTYPE = Some(fmi2GetString);
    let _: h::fmi2SetRealTYPE = Some(fmi2SetReal);
    let _: h::fmi2SetIntegerTYPE = Some(fmi2SetInteger);
    let _: h::fmi2SetBooleanTYPE = Some(fmi2SetBoolean);
    let _: h::fmi2SetStringTYPE = Some(fmi2SetString);
    let _: h::fmi2GetFMUstateTYPE = Some(fmi2GetFMUstate);
    let _: h::fmi2SetFMUstateTYPE = Some(fmi2SetFMUstate);
    let _: h::fmi2FreeFMUstateTYPE = Some(fmi2FreeFMUstate);
    let _: h::fmi2SerializedFMUstateSizeTYPE = Some(fmi2SerializedFMUstateSize);
    let _: h::fmi2SerializeFMUstateTYPE = Some(fmi2SerializeFMUstate);
    let _: h::fmi2DeSerializeFMUstateTYPE = Some(fmi2DeSerializeFMUstate);
    let _: h::fmi2GetDirectionalDerivativeTYPE = Some(fmi2GetDirectionalDerivative);
    let _: h::fmi2EnterEventModeTYPE = Some(fmi2EnterEventMode);
    let _: h::fmi2EnterContinuousTimeModeTYPE = Some(fmi2EnterContinuousTimeMode);
    let _: h::fmi2CompletedIntegratorStepTYPE = Some(fmi2CompletedIntegratorStep);
    let _: h::fmi2SetTimeTYPE = Some(fmi2SetTime);
    let _: h::fmi2SetContinuousStatesTYPE = Some(fmi2SetContinuousStates);
    let _: h::fmi2GetDerivativesTYPE = Some(fmi2GetDerivatives);
    let _: h::fmi2GetEventIndicatorsTYPE = Some(fmi2GetEventIndicators);
    let _: h::fmi2GetContinuousStatesTYPE = Some(fmi2GetContinuousStates);
    let _: h::fmi2GetNominalsOfContinuousStatesTYPE = Some(fmi2GetNominalsOfContinuousStates);
    let _: h::fmi2SetRealInputDerivativesTYPE = Some(fmi2SetRealInputDerivatives);
    let _: h::fmi2GetRealOutputDerivativesTYPE = Some(fmi2GetRealOutputDerivatives);
    let _: h::fmi2DoStepTYPE = Some(fmi2DoStep);
    let _: h::fmi2CancelStepTYPE = Some(fmi2CancelStep);
    let _: h::fmi2GetStatusTYPE = Some(fmi2GetStatus);
    let _: h::fmi2GetRealStatusTYPE = Some(fmi2GetRealStatus);
    let _: h::fmi2GetIntegerStatusTYPE = Some(fmi2GetIntegerStatus);
    let _: h::fmi2GetBooleanStatusTYPE = Some(fmi2GetBooleanStatus);
    let _: h::fmi2GetStringStatusTYPE = Some(fmi2GetStringStatus);

    // The two signatures with struct pointers: same layout as the header's structs.
    let _: unsafe extern "C" fn(
        fmi2String,
        fmi2Type,
        fmi2String,
        fmi2String,
        *const fmi2CallbackFunctions,
        fmi2Boolean,
        fmi2Boolean,
    ) -> fmi2Component = fmi2Instantiate;
    let _: unsafe extern "C" fn(fmi2Component, *mut fmi2EventInfo) -> fmi2Status =
        fmi2NewDiscreteStates;
    assert_eq!(
        size_of::<fmi2CallbackFunctions>(),
        size_of::<h::fmi2CallbackFunctions>()
    );
    assert_eq!(
        offset_of!(fmi2CallbackFunctions, component_environment),
        offset_of!(h::fmi2CallbackFunctions, componentEnvironment)
    );
    assert_eq!(size_of::<fmi2EventInfo>(), size_of::<h::fmi2EventInfo>());
    assert_eq!(align_of::<fmi2EventInfo>(), align_of::<h::fmi2EventInfo>());
    assert_eq!(
        offset_of!(fmi2EventInfo, next_event_time),
        offset_of!(h::fmi2EventInfo, nextEventTime)
    );
    assert_eq!(Status::Discard.code(), h::fmi2Status_fmi2Discard);
    assert_eq!(
        FMI2_LAST_SUCCESSFUL_TIME,
        h::fmi2StatusKind_fmi2LastSuccessfulTime
    );
    assert_eq!(FMI2_CO_SIMULATION, h::fmi2Type_fmi2CoSimulation);
}

/// Callbacks with `fmi-sys`'s C-variadic logger (it formats and forwards to the `log` crate).
pub(super) fn callbacks() -> fmi2CallbackFunctions {
    let logger: unsafe extern "C" fn(
        h::fmi2ComponentEnvironment,
        h::fmi2String,
        h::fmi2Status,
        h::fmi2String,
        h::fmi2String,
        ...
    ) = h::logger::callback_logger_handler;
    fmi2CallbackFunctions {
        logger: Some(logger),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: ptr::null_mut(),
    }
}

unsafe fn new_instance(cb: &fmi2CallbackFunctions, guid_text: &CStr) -> fmi2Component {
    fmi2Instantiate(
        c"inst".as_ptr(),
        FMI2_CO_SIMULATION,
        guid_text.as_ptr(),
        ptr::null(),
        cb,
        FMI2_FALSE,
        FMI2_FALSE,
    )
}

#[test]
fn instantiate_refuses_wrong_guid_missing_logger_and_model_exchange() {
    let cb = callbacks();
    let g = c_text(&guid());
    unsafe {
        assert!(new_instance(&cb, c"{00000000-0000-0000-0000-000000000000}").is_null());
        let no_logger = fmi2CallbackFunctions { logger: None, ..cb };
        assert!(new_instance(&no_logger, &g).is_null());
        assert!(fmi2Instantiate(
            c"me".as_ptr(),
            FMI2_MODEL_EXCHANGE,
            g.as_ptr(),
            ptr::null(),
            &cb,
            0,
            0
        )
        .is_null());
        assert!(fmi2Instantiate(
            c"x".as_ptr(),
            FMI2_CO_SIMULATION,
            g.as_ptr(),
            ptr::null(),
            ptr::null(),
            0,
            0
        )
        .is_null());
        let c = new_instance(&cb, &g);
        assert!(!c.is_null());
        fmi2FreeInstance(c);
    }
}

#[test]
fn null_and_foreign_pointers_are_refused_not_dereferenced() {
    let cb = callbacks();
    let g = c_text(&guid());
    let err = Status::Error.code();
    unsafe {
        assert_eq!(fmi2Reset(ptr::null_mut()), err);
        let mut not_ours = [0u64; 8];
        assert_eq!(fmi2Reset(not_ours.as_mut_ptr() as fmi2Component), err);
        fmi2FreeInstance(ptr::null_mut());

        let c = new_instance(&cb, &g);
        assert_eq!(fmi2SetReal(c, ptr::null(), 1, ptr::null()), err);
        assert_eq!(fmi2Reset(c), Status::Ok.code());
        assert_eq!(fmi2EnterInitializationMode(c), Status::Ok.code());
        let vr = [101u32];
        assert_eq!(fmi2GetReal(c, vr.as_ptr(), 1, ptr::null_mut()), err);
        assert_eq!(fmi2Reset(c), Status::Ok.code());
        assert_eq!(
            fmi2SetReal(c, ptr::null(), 0, ptr::null()),
            Status::Ok.code()
        );
        assert_eq!(fmi2SetFMUstate(c, ptr::null_mut()), err);
        assert_eq!(fmi2Reset(c), Status::Ok.code());
        assert_eq!(fmi2SetTime(c, 0.0), err, "Model Exchange");
        fmi2FreeInstance(c);
    }
}

#[test]
fn fmu_state_round_trip_through_the_c_interface() {
    let cb = callbacks();
    let g = c_text(&guid());
    let ok = Status::Ok.code();
    unsafe {
        let c = new_instance(&cb, &g);
        let ppd = [viscosph_vr("particles_per_diameter")];
        assert_eq!(fmi2SetInteger(c, ppd.as_ptr(), 1, [12].as_ptr()), ok);
        assert_eq!(fmi2EnterInitializationMode(c), ok);
        assert_eq!(fmi2ExitInitializationMode(c), ok);
        assert_eq!(fmi2DoStep(c, 0.0, 0.003, FMI2_TRUE), ok);
        let mut s: fmi2FMUstate = ptr::null_mut();
        assert_eq!(fmi2GetFMUstate(c, &mut s), ok);
        let mut size = 0usize;
        assert_eq!(fmi2SerializedFMUstateSize(c, s, &mut size), ok);
        let mut buf = vec![0 as fmi2Byte; size];
        assert_eq!(
            fmi2SerializeFMUstate(c, s, buf.as_mut_ptr(), size - 1),
            Status::Error.code()
        );
        assert_eq!(fmi2Reset(c), ok);
        assert_eq!(fmi2SerializeFMUstate(c, s, buf.as_mut_ptr(), size), ok);
        assert_eq!(fmi2FreeFMUstate(c, &mut s), ok);
        assert!(s.is_null());
        let mut s2: fmi2FMUstate = ptr::null_mut();
        assert_eq!(fmi2DeSerializeFMUstate(c, buf.as_ptr(), size, &mut s2), ok);
        assert_eq!(fmi2SetFMUstate(c, s2), ok);
        let mut t = 0.0;
        assert_eq!(fmi2GetRealStatus(c, FMI2_LAST_SUCCESSFUL_TIME, &mut t), ok);
        assert_eq!(t, 0.003);
        assert_eq!(fmi2DoStep(c, 0.003, 0.001, FMI2_TRUE), ok);
        assert_eq!(fmi2FreeFMUstate(c, &mut s2), ok);
        fmi2FreeInstance(c);
    }
}

fn viscosph_vr(name: &str) -> u32 {
    crate::scene::param_spec(name).unwrap().value_reference
}
