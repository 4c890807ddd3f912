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

use super::instance::{Category, Instance, LogSink};
use super::model_description::guid;
use super::types::*;
use std::ffi::{CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

#[cfg(test)]
mod call_sequences;
pub(crate) mod fmu_state;
#[cfg(test)]
mod tests;
pub(crate) mod unsupported;

/// What an `fmi2Component` (and an `fmi3Instance`) points to.
pub(crate) struct Handle {
    tag: u64,
    inst: Instance,
}

const INSTANCE_TAG: u64 = u64::from_le_bytes(*b"ViscoSPH");

/// The instance behind `c`, or `None` for NULL or a pointer that is not a live instance.
pub(crate) unsafe fn instance<'a>(c: fmi2Component) -> Option<&'a mut Instance> {
    if c.is_null() {
        return None;
    }
    let h = &mut *(c as *mut Handle);
    (h.tag == INSTANCE_TAG).then_some(&mut h.inst)
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
pub(crate) unsafe fn guarded(
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
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts(p, n))
    }
}

/// A writable C array as a slice; `None` if it is NULL although `n > 0`.
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts_mut(p, n))
    }
}

pub(crate) fn null_arg(inst: &mut Instance, func: &str, arg: &str) -> Status {
    inst.fail_error(func, format!("argument {arg} must not be NULL"))
}

/// A Rust string as a C string, with any NUL byte replaced so nothing is cut off.
pub(crate) fn c_text(s: &str) -> CString {
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
    into_component(inst)
}

/// The pointer handed to the importer for `inst` (freed by `fmi2FreeInstance` /
/// `fmi3FreeInstance`).
pub(crate) fn into_component(inst: Instance) -> fmi2Component {
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
