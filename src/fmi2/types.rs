//! The C types of `fmi2TypesPlatform.h` and `fmi2FunctionTypes.h` (FMI 2.0 sections 2.1.2-2.1.5)
//! under their standard names, with the "default" platform types: `fmi2Real` = double,
//! `fmi2Integer` = `fmi2Boolean` = int, C enums = unsigned int (as the header's enums compile on
//! Linux). Using exactly these types lets a unit test compare every exported function against the
//! header's `fmi2...TYPE` typedefs (bindgen output of the `fmi-sys` crate).
//!
//! Enumerations that arrive from the importer (`fmi2Type`, `fmi2StatusKind`) stay plain integers
//! and are checked, because an out-of-range value in a Rust enum would be undefined behaviour.
//! Inside the crate the status is the Rust enum [`Status`].

#![allow(non_camel_case_types)]

use std::os::raw::{c_char, c_int, c_uint, c_void};

pub type fmi2Component = *mut c_void;
pub type fmi2ComponentEnvironment = *mut c_void;
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = c_uint;
pub type fmi2Real = f64;
pub type fmi2Integer = c_int;
pub type fmi2Boolean = c_int;
pub type fmi2Char = c_char;
pub type fmi2String = *const fmi2Char;
pub type fmi2Byte = c_char;
/// `fmi2Status` as it crosses the C boundary.
pub type fmi2Status = c_uint;
/// `fmi2Type`.
pub type fmi2Type = c_uint;
/// `fmi2StatusKind`.
pub type fmi2StatusKind = c_uint;

pub const FMI2_TRUE: fmi2Boolean = 1;
pub const FMI2_FALSE: fmi2Boolean = 0;

pub const FMI2_MODEL_EXCHANGE: fmi2Type = 0;
pub const FMI2_CO_SIMULATION: fmi2Type = 1;

/// `fmi2StatusKind` values (FMI 2.0 section 4.2.3).
pub const FMI2_DO_STEP_STATUS: fmi2StatusKind = 0;
pub const FMI2_PENDING_STATUS: fmi2StatusKind = 1;
pub const FMI2_LAST_SUCCESSFUL_TIME: fmi2StatusKind = 2;
pub const FMI2_TERMINATED: fmi2StatusKind = 3;

/// `fmi2Status` (FMI 2.0 section 2.1.3), inside the crate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}

impl Status {
    /// The value that crosses the C boundary.
    pub fn code(self) -> fmi2Status {
        self as fmi2Status
    }
}

/// `fmi2CallbackLogger`: C-variadic, so the message is a printf format. We always pass `"%s"`
/// and the text as its argument, so a `%` in a variable name or a path cannot be read as a
/// conversion (FMI 2.0 section 2.1.5, `logger`).
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    env: fmi2ComponentEnvironment,
    instance_name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    message: fmi2String,
    ...
);

/// `fmi2CallbackFunctions`. ViscoSPH declares `canNotUseMemoryManagementFunctions`, so only
/// `logger` and `componentEnvironment` are used; the struct is copied at `fmi2Instantiate`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct fmi2CallbackFunctions {
    pub logger: Option<fmi2CallbackLogger>,
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    pub step_finished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    pub component_environment: fmi2ComponentEnvironment,
}

/// `fmi2EventInfo`, only needed for the signature of the Model-Exchange function
/// `fmi2NewDiscreteStates`.
#[repr(C)]
#[derive(Clone, Copy, Default)]
pub struct fmi2EventInfo {
    pub new_discrete_states_needed: fmi2Boolean,
    pub terminate_simulation: fmi2Boolean,
    pub nominals_of_continuous_states_changed: fmi2Boolean,
    pub values_of_continuous_states_changed: fmi2Boolean,
    pub next_event_time_defined: fmi2Boolean,
    pub next_event_time: fmi2Real,
}
