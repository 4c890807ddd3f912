//! The `extern "C"` entry points of `fmi3Functions.h` (FMI 3.0 chapter 2 and section 4.2),
//! exported unmangled from the same cdylib as the FMI 2.0 ones.
//!
//! A second thin C API over the one [`Instance`]: an instance created by
//! `fmi3InstantiateCoSimulation` words its messages in FMI 3.0 ([`Api::Fmi3`]) and is the same
//! `Handle` as an FMI 2.0 instance, so wherever the two standards' functions take the same C
//! arguments (the FMU state, reset, terminate, the Float64 and String accessors) the FMI 3.0
//! entry point forwards to the FMI 2.0 one; the others (instantiation, the logger,
//! `fmi3EnterInitializationMode`, `fmi3DoStep`'s out-arguments, Int32 / Int64 / Boolean, the
//! `nValues` argument) translate here. Every function of the header is exported, because
//! importers such as fmpy resolve all of them when they load a binary; those this
//! Co-Simulation FMU does not provide answer `fmi3Error` with the reason.

#![allow(non_snake_case)]
#![allow(clippy::missing_safety_doc)]
#![allow(clippy::too_many_arguments)]

use super::model_description::core_value_references;
use super::types::*;
use crate::fmi2::exports::fmu_state::*;
use crate::fmi2::exports::unsupported::unsupported;
use crate::fmi2::exports::*;
use crate::fmi2::guid;
use crate::fmi2::instance::{Api, Category, Instance, IntKind, LogSink};
use crate::fmi2::types::{Status, FMI2_FALSE, FMI2_TRUE};
use std::ffi::CStr;
use std::panic::catch_unwind;
use std::ptr;

#[cfg(test)]
mod tests;
pub mod unsupported_calls;
#[cfg(test)]
use unsupported_calls::*;

fn fmi2_bool(b: fmi3Boolean) -> crate::fmi2::types::fmi2Boolean {
    if b {
        FMI2_TRUE
    } else {
        FMI2_FALSE
    }
}

// ---------------------------------------------------------------------------------------------
// FMI 3.0 section 2.3.1: inquire version number, set debug logging
// ---------------------------------------------------------------------------------------------

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const fmi3Char {
    c"3.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    fmi2SetDebugLogging(instance, fmi2_bool(loggingOn), nCategories, categories) as fmi3Status
}

// ---------------------------------------------------------------------------------------------
// FMI 3.0 section 2.3.1: creation and destruction of instances
// ---------------------------------------------------------------------------------------------

/// The log sink of an FMI 3.0 instance: the importer's `logMessage`, if it gave one (FMI 3.0
/// allows NULL: then nothing is logged).
fn fmi3_sink(logger: Option<fmi3LogMessageCallback>, env: fmi3InstanceEnvironment) -> LogSink {
    Box::new(move |status, category, message| {
        if let Some(logger) = logger {
            let category = c_text(category);
            let message = c_text(message);
            unsafe {
                logger(
                    env,
                    status.code() as fmi3Status,
                    category.as_ptr(),
                    message.as_ptr(),
                )
            }
        }
    })
}

/// Where the binary of this platform lives in the FMU (FMI 3.0 section 2.5.1.1), for messages.
fn binary_path() -> &'static str {
    if cfg!(all(target_arch = "aarch64", target_os = "linux")) {
        "binaries/aarch64-linux/ViscoSPH.so"
    } else if cfg!(target_os = "windows") {
        "binaries/x86_64-windows/ViscoSPH.dll"
    } else {
        "binaries/x86_64-linux/ViscoSPH.so"
    }
}

/// `fmi3InstantiateCoSimulation`: NULL without an instance name, when the importer wants Event
/// Mode (hasEventMode = false), or when its instantiation token is not the one this binary was
/// built for (the token is the FMI 2.0 GUID: both interfaces come from the same tables).
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    _nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _intermediateUpdate: Option<fmi3IntermediateUpdateCallback>,
) -> fmi3Instance {
    catch_unwind(|| {
        let sink = fmi3_sink(logMessage, instanceEnvironment);
        let refuse = |msg: String| {
            sink(
                Status::Error,
                Category::Error.name(),
                &format!("fmi3InstantiateCoSimulation: {msg}"),
            );
            ptr::null_mut()
        };
        if instanceName.is_null() {
            return refuse("instanceName must not be NULL".into());
        }
        let name = CStr::from_ptr(instanceName).to_string_lossy().into_owned();
        if eventModeUsed {
            return refuse(
                "eventModeUsed = true, but ViscoSPH has no Event Mode (hasEventMode = false)".into(),
            );
        }
        let ours = guid();
        let given = if instantiationToken.is_null() {
            "NULL".to_string()
        } else {
            CStr::from_ptr(instantiationToken)
                .to_string_lossy()
                .into_owned()
        };
        if given != ours {
            return refuse(format!(
                "instantiationToken {given} does not match this binary's {ours}: modelDescription.xml and {} come from different builds",
                binary_path()
            ));
        }
        let inst = Instance::new(&name, loggingOn, sink).with_api(Api::Fmi3);
        inst.log(
            Category::Events,
            Status::Ok,
            &format!(
                "instantiated '{name}' (ViscoSPH {}, FMI 3.0 Co-Simulation)",
                env!("CARGO_PKG_VERSION")
            ),
        );
        into_component(inst)
    })
    .unwrap_or(ptr::null_mut())
}

/// An interface type this FMU does not have: NULL, with the reason logged if there is a logger.
unsafe fn refuse_interface(
    func: &str,
    env: fmi3InstanceEnvironment,
    logger: Option<fmi3LogMessageCallback>,
) -> fmi3Instance {
    let _ = catch_unwind(|| {
        fmi3_sink(logger, env)(
            Status::Error,
            Category::Error.name(),
            &format!("{func}: ViscoSPH is a Co-Simulation FMU; use fmi3InstantiateCoSimulation"),
        )
    });
    ptr::null_mut()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
) -> fmi3Instance {
    refuse_interface(
        "fmi3InstantiateModelExchange",
        instanceEnvironment,
        logMessage,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _clockUpdate: Option<fmi3ClockUpdateCallback>,
    _lockPreemption: Option<fmi3LockPreemptionCallback>,
    _unlockPreemption: Option<fmi3UnlockPreemptionCallback>,
) -> fmi3Instance {
    refuse_interface(
        "fmi3InstantiateScheduledExecution",
        instanceEnvironment,
        logMessage,
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    fmi2FreeInstance(instance)
}

// ---------------------------------------------------------------------------------------------
// FMI 3.0 section 2.3.2-2.3.6: initialization, termination, reset
// ---------------------------------------------------------------------------------------------

/// `fmi3EnterInitializationMode`: FMI 2.0's `fmi2SetupExperiment` and
/// `fmi2EnterInitializationMode` in one call (same checks of the start and stop time).
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    toleranceDefined: fmi3Boolean,
    tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    guarded(instance, "fmi3EnterInitializationMode", |inst| {
        let st = inst.setup_experiment(
            toleranceDefined.then_some(tolerance),
            startTime,
            stopTimeDefined.then_some(stopTime),
        );
        if st != Status::Ok {
            return st;
        }
        inst.enter_initialization_mode()
    }) as fmi3Status
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
    fmi2ExitInitializationMode(instance) as fmi3Status
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
    fmi2Terminate(instance) as fmi3Status
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    fmi2Reset(instance) as fmi3Status
}

// ---------------------------------------------------------------------------------------------
// FMI 3.0 section 2.3.7: getting and setting variable values
// ---------------------------------------------------------------------------------------------

/// The value references the instance reads for those named (an array's elements; a scalar
/// as itself), after the `nValues` check of every accessor (FMI 3.0 section 2.2.6.2: the number
/// of values is the sum of the sizes of the variables named). `Err` is the status to return:
/// `fmi3Error` for a NULL `valueReferences` or a count that does not match.
unsafe fn core_vrs(
    instance: fmi3Instance,
    func: &'static str,
    vr: *const fmi3ValueReference,
    nvr: usize,
    n_values: usize,
) -> Result<Vec<u32>, fmi3Status> {
    let fail =
        |msg: String| guarded(instance, func, |inst| inst.fail_error(func, msg)) as fmi3Status;
    let Some(vrs) = slice(vr, nvr) else {
        return Err(fail("argument valueReferences[] must not be NULL".into()));
    };
    let core = core_value_references(vrs);
    if core.len() != n_values {
        return Err(fail(format!(
            "nValues = {n_values}, but the {nvr} variables named have {} values",
            core.len()
        )));
    }
    Ok(core)
}

/// An FMI 3.0 accessor that is an FMI 2.0 one once arrays are spelled out as their elements.
macro_rules! forward_accessor {
    ($name:ident, $value:ty => $fmi2:ident) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: $value,
            nValues: usize,
        ) -> fmi3Status {
            match core_vrs(
                instance,
                stringify!($name),
                valueReferences,
                nValueReferences,
                nValues,
            ) {
                Ok(vrs) => $fmi2(instance, vrs.as_ptr(), vrs.len(), values) as fmi3Status,
                Err(st) => st,
            }
        }
    };
}

forward_accessor!(fmi3GetFloat64, *mut fmi3Float64 => fmi2GetReal);
forward_accessor!(fmi3SetFloat64, *const fmi3Float64 => fmi2SetReal);
forward_accessor!(fmi3GetString, *mut fmi3String => fmi2GetString);
forward_accessor!(fmi3SetString, *const fmi3String => fmi2SetString);

/// The integer accessors (Int32 for Integer parameters, Int64 for Enumerations): the values
/// pass through the core's `i32`, converting each way; an Int64 outside `i32` is refused by
/// name rather than truncated.
macro_rules! integer_accessor {
    (get $name:ident, $value:ty, $kind:expr) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *mut $value,
            nValues: usize,
        ) -> fmi3Status {
            const F: &str = stringify!($name);
            let vrs = match core_vrs(instance, F, valueReferences, nValueReferences, nValues) {
                Ok(vrs) => vrs,
                Err(st) => return st,
            };
            guarded(instance, F, |inst| {
                let Some(out) = slice_mut(values, vrs.len()) else {
                    return null_arg(inst, F, "values[]");
                };
                let mut ints = vec![0i32; vrs.len()];
                let st = inst.get_integer_of(F, $kind, &vrs, &mut ints);
                if st == Status::Ok {
                    for (o, i) in out.iter_mut().zip(ints) {
                        *o = <$value>::from(i);
                    }
                }
                st
            }) as fmi3Status
        }
    };
    (set $name:ident, $value:ty, $kind:expr) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: *const $value,
            nValues: usize,
        ) -> fmi3Status {
            const F: &str = stringify!($name);
            let vrs = match core_vrs(instance, F, valueReferences, nValueReferences, nValues) {
                Ok(vrs) => vrs,
                Err(st) => return st,
            };
            guarded(instance, F, |inst| {
                let Some(given) = slice(values, vrs.len()) else {
                    return null_arg(inst, F, "values[]");
                };
                let mut ints = Vec::with_capacity(given.len());
                for (&vr, &x) in vrs.iter().zip(given) {
                    match i32::try_from(x) {
                        Ok(i) => ints.push(i),
                        Err(_) => {
                            return inst.fail_error(
                                F,
                                format!("value {x} for valueReference {vr} is outside the variable's range"),
                            )
                        }
                    }
                }
                inst.set_integer_of(F, $kind, &vrs, &ints)
            }) as fmi3Status
        }
    };
}

integer_accessor!(get fmi3GetInt32, fmi3Int32, IntKind::Integer);
integer_accessor!(set fmi3SetInt32, fmi3Int32, IntKind::Integer);
integer_accessor!(get fmi3GetInt64, fmi3Int64, IntKind::Enumeration);
integer_accessor!(set fmi3SetInt64, fmi3Int64, IntKind::Enumeration);

/// An accessor of a type the interface has no variables of: OK for no value references, else
/// `fmi3Error` naming the variable's real type.
macro_rules! no_variables {
    ($get:ident $(, $extra:ident: $ty:ty)*) => {
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            $($extra: $ty,)*
        ) -> fmi3Status {
            const F: &str = stringify!($get);
            guarded(instance, F, |inst| {
                let Some(vrs) = slice(valueReferences, nValueReferences) else {
                    return null_arg(inst, F, "valueReferences[]");
                };
                if F.starts_with("fmi3Get") {
                    inst.get_none(F, vrs)
                } else {
                    inst.set_none(F, vrs)
                }
            }) as fmi3Status
        }
    };
}

no_variables!(fmi3GetFloat32, _values: *mut fmi3Float32, _nValues: usize);
no_variables!(fmi3SetFloat32, _values: *const fmi3Float32, _nValues: usize);
no_variables!(fmi3GetInt8, _values: *mut fmi3Int8, _nValues: usize);
no_variables!(fmi3SetInt8, _values: *const fmi3Int8, _nValues: usize);
no_variables!(fmi3GetUInt8, _values: *mut fmi3UInt8, _nValues: usize);
no_variables!(fmi3SetUInt8, _values: *const fmi3UInt8, _nValues: usize);
no_variables!(fmi3GetInt16, _values: *mut fmi3Int16, _nValues: usize);
no_variables!(fmi3SetInt16, _values: *const fmi3Int16, _nValues: usize);
no_variables!(fmi3GetUInt16, _values: *mut fmi3UInt16, _nValues: usize);
no_variables!(fmi3SetUInt16, _values: *const fmi3UInt16, _nValues: usize);
no_variables!(fmi3GetUInt32, _values: *mut fmi3UInt32, _nValues: usize);
no_variables!(fmi3SetUInt32, _values: *const fmi3UInt32, _nValues: usize);
no_variables!(fmi3GetUInt64, _values: *mut fmi3UInt64, _nValues: usize);
no_variables!(fmi3SetUInt64, _values: *const fmi3UInt64, _nValues: usize);
no_variables!(fmi3GetBoolean, _values: *mut fmi3Boolean, _nValues: usize);
no_variables!(fmi3SetBoolean, _values: *const fmi3Boolean, _nValues: usize);
no_variables!(fmi3GetBinary, _valueSizes: *mut usize, _values: *mut fmi3Binary, _nValues: usize);
no_variables!(fmi3SetBinary, _valueSizes: *const usize, _values: *const fmi3Binary, _nValues: usize);
no_variables!(fmi3GetClock, _values: *mut fmi3Clock);
no_variables!(fmi3SetClock, _values: *const fmi3Clock);

// ---------------------------------------------------------------------------------------------
// FMI 3.0 section 2.3.8: the complete FMU state (same arguments as FMI 2.0's)
// ---------------------------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    fmi2GetFMUstate(instance, FMUState) as fmi3Status
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    fmi2SetFMUstate(instance, FMUState) as fmi3Status
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    fmi2FreeFMUstate(instance, FMUState) as fmi3Status
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    fmi2SerializedFMUstateSize(instance, FMUState, size) as fmi3Status
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    fmi2SerializeFMUstate(instance, FMUState, serializedState.cast(), size) as fmi3Status
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    fmi2DeSerializeFMUstate(instance, serializedState.cast(), size, FMUState) as fmi3Status
}

// ---------------------------------------------------------------------------------------------
// FMI 3.0 section 4.2.2: fmi3DoStep
// ---------------------------------------------------------------------------------------------

/// `fmi3DoStep`: the FMI 2.0 step, with the results of `fmi2GetRealStatus` /
/// `fmi2GetBooleanStatus` as out-arguments (`lastSuccessfulTime`, `terminateSimulation`).
/// No event handling and no early return are ever needed. `noSetFMUStatePriorToCurrentPoint`
/// is not needed because a saved state is a complete copy.
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    const F: &str = "fmi3DoStep";
    guarded(instance, F, |inst| {
        for (p, arg) in [
            (eventHandlingNeeded, "eventHandlingNeeded"),
            (terminateSimulation, "terminateSimulation"),
            (earlyReturn, "earlyReturn"),
        ] {
            if p.is_null() {
                return null_arg(inst, F, arg);
            }
        }
        if lastSuccessfulTime.is_null() {
            return null_arg(inst, F, "lastSuccessfulTime");
        }
        let st = inst.do_step(currentCommunicationPoint, communicationStepSize);
        *eventHandlingNeeded = false;
        *earlyReturn = false;
        *terminateSimulation = inst.wants_to_terminate();
        *lastSuccessfulTime = inst.last_successful_time();
        st
    }) as fmi3Status
}
