//! The `extern "C"` entry points of `fmi2Functions.h`, exported unmangled from the cdylib.
//!
//! Each one is a thin translator: check the instance pointer, turn C arrays and strings into
//! slices (refusing NULL where the standard requires an array), call the safe [`Instance`]
//! method, and return its status. Every body that can fail runs inside `catch_unwind` (all but
//! the two constant-string getters), so a panic becomes an `fmi2Error` with a log message
//! instead of unwinding into the importer (undefined behaviour) or aborting the host process.
//!
//! All 44 functions of the header are exported, because importers such as fmpy resolve every
//! `fmi2*` symbol when they load a binary (FMI 2.0 section 2.1.1). The Model-Exchange ones and
//! the optional Co-Simulation ones this FMU does not provide answer `fmi2Error` with a message.
//!
//! The instance pointer handed out by `fmi2Instantiate` is a `Box<Handle>`; a tag at its start
//! catches pointers that are not ours (a freed instance, another FMU's instance) in most cases,
//! which is the best that can be done with an opaque `void*`.

#![allow(non_snake_case)]
#![allow(clippy::missing_safety_doc)]

use super::instance::{Category, Instance, LogSink, Snapshot};
use super::model_description::guid;
use super::types::*;
use std::ffi::{CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// What an `fmi2Component` points to.
struct Handle {
    tag: u64,
    inst: Instance,
}

/// What an `fmi2FMUstate` points to; the serialized bytes are computed once, on demand.
struct StateHandle {
    tag: u64,
    snap: Snapshot,
    bytes: Option<Vec<u8>>,
}

impl StateHandle {
    fn bytes(&mut self) -> &[u8] {
        if self.bytes.is_none() {
            self.bytes = Some(self.snap.to_bytes());
        }
        self.bytes.as_deref().expect("just set")
    }
}

const INSTANCE_TAG: u64 = u64::from_le_bytes(*b"ViscoSPH");
const STATE_TAG: u64 = u64::from_le_bytes(*b"VSPHstat");

/// The instance behind `c`, or `None` for NULL or a pointer that is not a live instance.
unsafe fn instance<'a>(c: fmi2Component) -> Option<&'a mut Instance> {
    if c.is_null() {
        return None;
    }
    let h = &mut *(c as *mut Handle);
    (h.tag == INSTANCE_TAG).then_some(&mut h.inst)
}

/// The FMU state behind `s`, or `None` if `s` is NULL or not one of ours.
unsafe fn state<'a>(s: fmi2FMUstate) -> Option<&'a mut StateHandle> {
    if s.is_null() {
        return None;
    }
    let h = &mut *(s as *mut StateHandle);
    (h.tag == STATE_TAG).then_some(h)
}

/// Put `snap` into the state `*slot` names: overwrite it if it is one of ours, else allocate a
/// new one there (FMI 2.0 section 2.1.8: `*FMUstate` NULL means "make a new state"). `slot`
/// must be a valid, non-NULL pointer whose target is NULL or one of our states (callers check).
unsafe fn store_state(slot: *mut fmi2FMUstate, snap: Snapshot) {
    match state(*slot) {
        Some(h) => {
            h.snap = snap;
            h.bytes = None;
        }
        None => {
            *slot = Box::into_raw(Box::new(StateHandle {
                tag: STATE_TAG,
                snap,
                bytes: None,
            })) as fmi2FMUstate;
        }
    }
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_string()
    }
}

/// Run `f` on the instance behind `c` inside `catch_unwind`. NULL or a foreign pointer answers
/// `fmi2Error` (there is no logger to tell); a panic is logged and answers `fmi2Error`.
unsafe fn guarded(
    c: fmi2Component,
    func: &'static str,
    f: impl FnOnce(&mut Instance) -> Status,
) -> fmi2Status {
    let Some(inst) = instance(c) else {
        return Status::Error.code();
    };
    let st = match catch_unwind(AssertUnwindSafe(|| f(&mut *inst))) {
        Ok(s) => s,
        Err(p) => {
            let msg = format!("internal error (panic): {}", panic_message(&*p));
            catch_unwind(AssertUnwindSafe(|| inst.fail_error(func, msg))).unwrap_or(Status::Error)
        }
    };
    st.code()
}

/// A C array as a slice; `None` if it is NULL although `n > 0`.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts(p, n))
    }
}

/// A writable C array as a slice; `None` if it is NULL although `n > 0`.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts_mut(p, n))
    }
}

fn null_arg(inst: &mut Instance, func: &str, arg: &str) -> Status {
    inst.fail_error(func, format!("argument {arg} must not be NULL"))
}

/// A Rust string as a C string, with any NUL byte replaced so nothing is cut off.
fn c_text(s: &str) -> CString {
    CString::new(s.replace('\0', "\u{fffd}")).expect("NUL bytes were replaced")
}

/// The log sink of an instance: the importer's logger, called with the format `"%s"` and the
/// message as its one variadic argument.
fn c_sink(
    logger: fmi2CallbackLogger,
    env: fmi2ComponentEnvironment,
    instance_name: CString,
) -> LogSink {
    Box::new(move |status, category, message| {
        let category = c_text(category);
        let message = c_text(message);
        unsafe {
            logger(
                env,
                instance_name.as_ptr(),
                status.code(),
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            )
        }
    })
}

// ---------------------------------------------------------------------------------------------
// FMI 2.0 section 2.1.4: inquire platform and version
// ---------------------------------------------------------------------------------------------

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const fmi2Char {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const fmi2Char {
    c"2.0".as_ptr()
}

// ---------------------------------------------------------------------------------------------
// FMI 2.0 section 2.1.5: creation, destruction and logging
// ---------------------------------------------------------------------------------------------

/// `fmi2Instantiate`: NULL when there is no logger to report to, when the importer asks for
/// Model Exchange, or when its GUID is not the one this binary was built for (the XML and the
/// binary would then disagree on the value references).
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    _fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    catch_unwind(|| instantiate(instanceName, fmuType, fmuGUID, functions, loggingOn))
        .unwrap_or(ptr::null_mut())
}

unsafe fn instantiate(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    fmu_guid: fmi2String,
    functions: *const fmi2CallbackFunctions,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    if functions.is_null() {
        return ptr::null_mut();
    }
    let callbacks = *functions;
    let Some(logger) = callbacks.logger else {
        return ptr::null_mut();
    };
    let name = if instance_name.is_null() {
        String::new()
    } else {
        CStr::from_ptr(instance_name).to_string_lossy().into_owned()
    };
    let sink = c_sink(logger, callbacks.component_environment, c_text(&name));
    let refuse = |msg: String| {
        sink(
            Status::Error,
            Category::Error.name(),
            &format!("fmi2Instantiate: {msg}"),
        );
        ptr::null_mut()
    };
    if instance_name.is_null() {
        return refuse("instanceName must not be NULL".into());
    }
    if fmu_type != FMI2_CO_SIMULATION {
        return refuse(format!(
            "fmuType = {fmu_type}: ViscoSPH is a Co-Simulation FMU (fmi2CoSimulation = 1); Model Exchange is not supported"
        ));
    }
    let ours = guid();
    let given = if fmu_guid.is_null() {
        "NULL".to_string()
    } else {
        CStr::from_ptr(fmu_guid).to_string_lossy().into_owned()
    };
    if given != ours {
        return refuse(format!(
            "fmuGUID {given} does not match this binary's {ours}: modelDescription.xml and \
             binaries/linux64/ViscoSPH.so come from different builds"
        ));
    }
    let inst = Instance::new(&name, logging_on != FMI2_FALSE, sink);
    inst.log(
        Category::Events,
        Status::Ok,
        &format!(
            "instantiated '{name}' (ViscoSPH {})",
            env!("CARGO_PKG_VERSION")
        ),
    );
    Box::into_raw(Box::new(Handle {
        tag: INSTANCE_TAG,
        inst,
    })) as fmi2Component
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if instance(c).is_none() {
        return;
    }
    let _ = catch_unwind(|| {
        let mut h = Box::from_raw(c as *mut Handle);
        h.tag = 0;
        drop(h);
    });
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    guarded(c, "fmi2SetDebugLogging", |inst| {
        let Some(cats) = slice(categories, nCategories) else {
            return null_arg(inst, "fmi2SetDebugLogging", "categories[]");
        };
        let mut names = Vec::with_capacity(cats.len());
        for &p in cats {
            if p.is_null() {
                return null_arg(inst, "fmi2SetDebugLogging", "categories[i]");
            }
            names.push(CStr::from_ptr(p).to_string_lossy().into_owned());
        }
        inst.set_debug_logging(loggingOn != FMI2_FALSE, &names)
    })
}

// ---------------------------------------------------------------------------------------------
// FMI 2.0 section 2.1.6: initialization, termination, reset
// ---------------------------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    toleranceDefined: fmi2Boolean,
    tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    guarded(c, "fmi2SetupExperiment", |inst| {
        inst.setup_experiment(
            (toleranceDefined != FMI2_FALSE).then_some(tolerance),
            startTime,
            (stopTimeDefined != FMI2_FALSE).then_some(stopTime),
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    guarded(c, "fmi2EnterInitializationMode", |inst| {
        inst.enter_initialization_mode()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    guarded(c, "fmi2ExitInitializationMode", |inst| {
        inst.exit_initialization_mode()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    guarded(c, "fmi2Terminate", |inst| inst.terminate())
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    guarded(c, "fmi2Reset", |inst| inst.reset())
}

// ---------------------------------------------------------------------------------------------
// FMI 2.0 section 2.1.7: getting and setting variable values
// ---------------------------------------------------------------------------------------------

/// An fmi2Get*/fmi2Set* array accessor (FMI 2.0 section 2.1.7): checks that `vr[]` and
/// `value[]` are not NULL when `nvr > 0`, names the NULL argument otherwise, and hands both as
/// slices to `$body`.
macro_rules! array_accessor {
    ($name:ident, $value:ty, $as_slice:ident, |$inst:ident, $vrs:ident, $values:pat_param| $body:expr) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: $value,
        ) -> fmi2Status {
            guarded(c, stringify!($name), |$inst| {
                let Some($vrs) = slice(vr, nvr) else {
                    return null_arg($inst, stringify!($name), "vr[]");
                };
                let Some($values) = $as_slice(value, nvr) else {
                    return null_arg($inst, stringify!($name), "value[]");
                };
                $body
            })
        }
    };
}

array_accessor!(
    fmi2GetReal,
    *mut fmi2Real,
    slice_mut,
    |inst, vrs, values| inst.get_real(vrs, values)
);
array_accessor!(
    fmi2GetInteger,
    *mut fmi2Integer,
    slice_mut,
    |inst, vrs, values| inst.get_integer(vrs, values)
);
array_accessor!(
    fmi2GetBoolean,
    *mut fmi2Boolean,
    slice_mut,
    |inst, vrs, _| inst.get_none("fmi2GetBoolean", vrs)
);
array_accessor!(
    fmi2GetString,
    *mut fmi2String,
    slice_mut,
    |inst, vrs, values| {
        let mut names = vec![""; vrs.len()];
        let st = inst.get_string(vrs, &mut names);
        if st == Status::Ok {
            for (v, name) in values.iter_mut().zip(names) {
                *v = item_c_str(name);
            }
        }
        st
    }
);
array_accessor!(fmi2SetReal, *const fmi2Real, slice, |inst, vrs, values| {
    inst.set_real(vrs, values)
});
array_accessor!(
    fmi2SetInteger,
    *const fmi2Integer,
    slice,
    |inst, vrs, values| inst.set_integer(vrs, values)
);
array_accessor!(fmi2SetBoolean, *const fmi2Boolean, slice, |inst, vrs, _| {
    inst.set_none("fmi2SetBoolean", vrs)
});
array_accessor!(
    fmi2SetString,
    *const fmi2String,
    slice,
    |inst, vrs, values| {
        let texts: Vec<Option<String>> = values
            .iter()
            .map(|&p| (!p.is_null()).then(|| CStr::from_ptr(p).to_string_lossy().into_owned()))
            .collect();
        inst.set_string(vrs, &texts)
    }
);

/// The NUL-terminated copy of an enumeration item name, for `fmi2GetString`. Built once from
/// the parameter table and never changed, so the pointers stay valid for the life of the
/// library (FMI 2.0 section 2.1.7 only asks until the next call) and instances share nothing
/// mutable.
fn item_c_str(name: &str) -> fmi2String {
    use std::sync::OnceLock;
    static NAMES: OnceLock<Vec<(&'static str, CString)>> = OnceLock::new();
    let names = NAMES.get_or_init(|| {
        crate::scene::PARAMS
            .iter()
            .filter_map(|p| match p.kind {
                crate::config::Kind::Enumeration { items, .. } => Some(items),
                _ => None,
            })
            .flatten()
            .map(|(n, _)| (*n, c_text(n)))
            .collect()
    });
    names
        .iter()
        .find(|(n, _)| *n == name)
        .map_or(c"".as_ptr(), |(_, c)| c.as_ptr())
}

// ---------------------------------------------------------------------------------------------
// FMI 2.0 section 2.1.8: getting and setting the complete FMU state
// ---------------------------------------------------------------------------------------------

/// `fmi2GetFMUstate`: a new state if `*FMUstate` is NULL, else the given one is overwritten.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    guarded(c, "fmi2GetFMUstate", |inst| {
        if FMUstate.is_null() {
            return null_arg(inst, "fmi2GetFMUstate", "FMUstate");
        }
        let existing = *FMUstate;
        if !existing.is_null() && state(existing).is_none() {
            return inst.fail_error(
                "fmi2GetFMUstate",
                "*FMUstate is neither NULL nor an FMU state of ViscoSPH".into(),
            );
        }
        let mut snap = None;
        let st = inst.get_state(&mut snap);
        if let Some(snap) = snap {
            store_state(FMUstate, snap);
        }
        st
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    guarded(c, "fmi2SetFMUstate", |inst| match state(FMUstate) {
        Some(h) => inst.set_state(&h.snap),
        None => inst.fail_error(
            "fmi2SetFMUstate",
            "FMUstate is NULL or not an FMU state of ViscoSPH".into(),
        ),
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: fmi2Component,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    guarded(c, "fmi2FreeFMUstate", |inst| {
        if FMUstate.is_null() {
            return null_arg(inst, "fmi2FreeFMUstate", "FMUstate");
        }
        if (*FMUstate).is_null() {
            return inst.state_call("fmi2FreeFMUstate", None);
        }
        if state(*FMUstate).is_none() {
            return inst.state_call(
                "fmi2FreeFMUstate",
                Some("*FMUstate is not an FMU state of ViscoSPH".into()),
            );
        }
        let st = inst.state_call("fmi2FreeFMUstate", None);
        if st == Status::Ok {
            let mut h = Box::from_raw(*FMUstate as *mut StateHandle);
            h.tag = 0;
            drop(h);
            *FMUstate = ptr::null_mut();
        }
        st
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    guarded(c, "fmi2SerializedFMUstateSize", |inst| {
        if size.is_null() {
            return null_arg(inst, "fmi2SerializedFMUstateSize", "size");
        }
        match state(FMUstate) {
            Some(h) => {
                let st = inst.state_call("fmi2SerializedFMUstateSize", None);
                if st == Status::Ok {
                    *size = h.bytes().len();
                }
                st
            }
            None => inst.state_call(
                "fmi2SerializedFMUstateSize",
                Some("FMUstate is NULL or not an FMU state of ViscoSPH".into()),
            ),
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    const F: &str = "fmi2SerializeFMUstate";
    guarded(c, F, |inst| {
        let Some(h) = state(FMUstate) else {
            return inst.state_call(
                F,
                Some("FMUstate is NULL or not an FMU state of ViscoSPH".into()),
            );
        };
        if serializedState.is_null() {
            return null_arg(inst, F, "serializedState");
        }
        let bytes = h.bytes();
        if size < bytes.len() {
            return inst.state_call(
                F,
                Some(format!(
                    "size = {size} is smaller than the {} bytes fmi2SerializedFMUstateSize reports",
                    bytes.len()
                )),
            );
        }
        let st = inst.state_call(F, None);
        if st == Status::Ok {
            ptr::copy_nonoverlapping(bytes.as_ptr(), serializedState as *mut u8, bytes.len());
        }
        st
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    const F: &str = "fmi2DeSerializeFMUstate";
    guarded(c, F, |inst| {
        if FMUstate.is_null() {
            return null_arg(inst, F, "FMUstate");
        }
        let Some(bytes) = slice(serializedState as *const u8, size) else {
            return null_arg(inst, F, "serializedState");
        };
        let snap = match Snapshot::from_bytes(bytes) {
            Ok(s) => s,
            Err(e) => return inst.state_call(F, Some(e)),
        };
        let st = inst.state_call(F, None);
        if st != Status::Ok {
            return st;
        }
        store_state(FMUstate, snap);
        st
    })
}

/// An entry point the FMU has but does not support: it reports why through the logger and
/// returns fmi2Error (through [`guarded`], so it too never panics across the boundary).
macro_rules! unsupported {
    ($name:ident($($arg:ident: $ty:ty),* $(,)?), $why:expr $(,)?) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: fmi2Component, $($arg: $ty),*) -> fmi2Status {
            guarded(c, stringify!($name), |i| i.unsupported(stringify!($name), $why))
        }
    };
}

// ---------------------------------------------------------------------------------------------
// FMI 2.0 section 2.1.9: partial derivatives (not provided)
// ---------------------------------------------------------------------------------------------

unsupported!(
    fmi2GetDirectionalDerivative(
        _vUnknown_ref: *const fmi2ValueReference,
        _nUnknown: usize,
        _vKnown_ref: *const fmi2ValueReference,
        _nKnown: usize,
        _dvKnown: *const fmi2Real,
        _dvUnknown: *mut fmi2Real,
    ),
    "directional derivatives are not provided (providesDirectionalDerivative = false)"
);

// ---------------------------------------------------------------------------------------------
// FMI 2.0 chapter 3: Model Exchange (not supported)
// ---------------------------------------------------------------------------------------------

const NO_ME: &str = "Model Exchange is not supported: ViscoSPH is a Co-Simulation FMU";

unsupported!(fmi2EnterEventMode(), NO_ME);

unsupported!(fmi2NewDiscreteStates(_fmi2eventInfo: *mut fmi2EventInfo), NO_ME);

unsupported!(fmi2EnterContinuousTimeMode(), NO_ME);

unsupported!(
    fmi2CompletedIntegratorStep(
        _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
        _enterEventMode: *mut fmi2Boolean,
        _terminateSimulation: *mut fmi2Boolean,
    ),
    NO_ME
);

unsupported!(fmi2SetTime(_time: fmi2Real), NO_ME);

unsupported!(fmi2SetContinuousStates(_x: *const fmi2Real, _nx: usize), NO_ME);

unsupported!(fmi2GetDerivatives(_derivatives: *mut fmi2Real, _nx: usize), NO_ME);

unsupported!(fmi2GetEventIndicators(_eventIndicators: *mut fmi2Real, _ni: usize), NO_ME);

unsupported!(fmi2GetContinuousStates(_x: *mut fmi2Real, _nx: usize), NO_ME);

unsupported!(fmi2GetNominalsOfContinuousStates(_x_nominal: *mut fmi2Real, _nx: usize), NO_ME);

// ---------------------------------------------------------------------------------------------
// FMI 2.0 chapter 4: Co-Simulation
// ---------------------------------------------------------------------------------------------

unsupported!(
    fmi2SetRealInputDerivatives(
        _vr: *const fmi2ValueReference,
        _nvr: usize,
        _order: *const fmi2Integer,
        _value: *const fmi2Real,
    ),
    "the inputs are held constant over a communication step; their derivatives are not used (canInterpolateInputs = false)"
);

unsupported!(
    fmi2GetRealOutputDerivatives(
        _vr: *const fmi2ValueReference,
        _nvr: usize,
        _order: *const fmi2Integer,
        _value: *mut fmi2Real,
    ),
    "output derivatives are not provided (maxOutputDerivativeOrder = 0)"
);

/// `fmi2DoStep` (FMI 2.0 section 4.2.2); `noSetFMUStatePriorToCurrentPoint` is not needed
/// because a saved state is a complete copy.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    guarded(c, "fmi2DoStep", |inst| {
        inst.do_step(currentCommunicationPoint, communicationStepSize)
    })
}

unsupported!(
    fmi2CancelStep(),
    "no step is in progress: fmi2DoStep is synchronous (canRunAsynchronuously = false)"
);

/// An fmi2Get*Status function (FMI 2.0 section 4.2.3): refuses a NULL `value`, then `$body`.
macro_rules! status_getter {
    ($name:ident, $value:ty, |$inst:ident, $s:ident, $v:ident| $body:block) => {
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            c: fmi2Component,
            $s: fmi2StatusKind,
            $v: *mut $value,
        ) -> fmi2Status {
            guarded(c, stringify!($name), |$inst| {
                if $v.is_null() {
                    return null_arg($inst, stringify!($name), "value");
                }
                $body
            })
        }
    };
}

status_getter!(fmi2GetStatus, fmi2Status, |inst, s, _value| {
    inst.get_status("fmi2GetStatus", s)
});
status_getter!(fmi2GetRealStatus, fmi2Real, |inst, s, value| {
    inst.get_real_status(s, &mut *value)
});
status_getter!(fmi2GetIntegerStatus, fmi2Integer, |inst, s, _value| {
    inst.get_status("fmi2GetIntegerStatus", s)
});
status_getter!(fmi2GetBooleanStatus, fmi2Boolean, |inst, s, value| {
    let mut b = false;
    let st = inst.get_boolean_status(s, &mut b);
    if st == Status::Ok {
        *value = if b { FMI2_TRUE } else { FMI2_FALSE };
    }
    st
});
status_getter!(fmi2GetStringStatus, fmi2String, |inst, s, _value| {
    inst.get_status("fmi2GetStringStatus", s)
});

#[cfg(test)]
mod tests {
    //! The exported functions against the official header (bindgen output of `fmi-sys`, a
    //! dev-dependency), and the C-level argument checks, in-process with `fmi-sys`'s C logger.
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
    fn callbacks() -> fmi2CallbackFunctions {
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
}
