//! The C types of `fmi3PlatformTypes.h` and `fmi3FunctionTypes.h` (FMI 3.0 section 2.2.1)
//! under their standard names. The status is a C enum (`int`); its values are those of FMI 2.0,
//! so the core's [`Status`](crate::fmi2::types::Status) codes cross this boundary unchanged.

#![allow(non_camel_case_types)]

use std::os::raw::{c_char, c_uint, c_void};

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3FMUState = *mut c_void;
pub type fmi3ValueReference = u32;
pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
/// C99 `bool`.
pub type fmi3Boolean = bool;
pub type fmi3Char = c_char;
pub type fmi3String = *const fmi3Char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const fmi3Byte;
pub type fmi3Clock = bool;
/// `fmi3Status` as it crosses the boundary: a C enum, which compiles to `unsigned int` on the
/// platforms built for (as FMI 2.0's, see [`crate::fmi2::types`]).
pub type fmi3Status = c_uint;
/// `fmi3DependencyKind`.
pub type fmi3DependencyKind = c_uint;
/// `fmi3IntervalQualifier`.
pub type fmi3IntervalQualifier = c_uint;

/// `fmi3LogMessageCallback` (FMI 3.0 section 2.3.1): not variadic, unlike FMI 2.0's logger,
/// and without the instance name.
pub type fmi3LogMessageCallback = unsafe extern "C" fn(
    instance_environment: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
);

/// `fmi3IntermediateUpdateCallback`: never called (providesIntermediateUpdate = false).
pub type fmi3IntermediateUpdateCallback = unsafe extern "C" fn(
    instance_environment: fmi3InstanceEnvironment,
    intermediate_update_time: fmi3Float64,
    intermediate_variable_set_requested: fmi3Boolean,
    intermediate_variable_get_allowed: fmi3Boolean,
    intermediate_step_finished: fmi3Boolean,
    can_return_early: fmi3Boolean,
    early_return_requested: *mut fmi3Boolean,
    early_return_time: *mut fmi3Float64,
);

/// `fmi3ClockUpdateCallback`, `fmi3LockPreemptionCallback`, `fmi3UnlockPreemptionCallback`:
/// only in the signature of `fmi3InstantiateScheduledExecution`.
pub type fmi3ClockUpdateCallback = unsafe extern "C" fn(fmi3InstanceEnvironment);
pub type fmi3LockPreemptionCallback = unsafe extern "C" fn();
pub type fmi3UnlockPreemptionCallback = unsafe extern "C" fn();

/// Unused, for signatures that take a `void*`.
pub type fmi3Void = c_void;
