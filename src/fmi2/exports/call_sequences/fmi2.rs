//! The FMI 2.0 C API as the call-sequence harness drives it.

use super::super::fmu_state::*;
use super::super::tests::callbacks;
use super::super::*;
use super::{status_of, CApi, Handle};
use std::os::raw::c_char;

/// The FMI 2.0 entry points of this library.
pub struct Fmi2;

impl CApi for Fmi2 {
    const NAME: &'static str = "FMI 2.0";

    unsafe fn instantiate() -> Handle {
        // The callbacks must outlive the instance: one set per thread, kept for the process.
        thread_local! {
            static CB: &'static fmi2CallbackFunctions = Box::leak(Box::new(callbacks()));
        }
        let guid = c_text(&crate::fmi2::guid());
        CB.with(|cb| {
            fmi2Instantiate(
                c"sequence".as_ptr(),
                FMI2_CO_SIMULATION,
                guid.as_ptr(),
                ptr::null(),
                *cb,
                FMI2_FALSE,
                FMI2_FALSE,
            )
        })
    }
    unsafe fn free_instance(c: Handle) {
        fmi2FreeInstance(c)
    }
    unsafe fn setup(c: Handle, start: f64, stop: Option<f64>) -> Option<Status> {
        Some(status_of(fmi2SetupExperiment(
            c,
            FMI2_FALSE,
            0.0,
            start,
            stop.is_some() as fmi2Boolean,
            stop.unwrap_or(0.0),
        )))
    }
    unsafe fn enter(c: Handle, _start: f64, _stop: Option<f64>) -> Status {
        status_of(fmi2EnterInitializationMode(c))
    }
    unsafe fn exit(c: Handle) -> Status {
        status_of(fmi2ExitInitializationMode(c))
    }
    unsafe fn terminate(c: Handle) -> Status {
        status_of(fmi2Terminate(c))
    }
    unsafe fn reset(c: Handle) -> Status {
        status_of(fmi2Reset(c))
    }
    unsafe fn do_step(c: Handle, t: f64, h: f64) -> Status {
        status_of(fmi2DoStep(c, t, h, FMI2_FALSE))
    }
    unsafe fn get_real(c: Handle, vrs: &[u32]) -> (Status, Vec<f64>) {
        let mut v = vec![f64::NAN; vrs.len()];
        let st = fmi2GetReal(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr());
        (status_of(st), v)
    }
    unsafe fn get_integer(c: Handle, vrs: &[u32], _wide: bool) -> Status {
        let mut v = vec![0; vrs.len()];
        status_of(fmi2GetInteger(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()))
    }
    unsafe fn get_boolean(c: Handle, vrs: &[u32]) -> Status {
        let mut v = vec![0; vrs.len()];
        status_of(fmi2GetBoolean(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()))
    }
    unsafe fn get_string(c: Handle, vrs: &[u32]) -> (Status, Vec<*const c_char>) {
        let mut v = vec![ptr::null(); vrs.len()];
        let st = fmi2GetString(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr());
        (status_of(st), v)
    }
    unsafe fn set_real(c: Handle, vrs: &[u32], v: &[f64]) -> Status {
        status_of(fmi2SetReal(c, vrs.as_ptr(), vrs.len(), v.as_ptr()))
    }
    unsafe fn set_integer(c: Handle, vrs: &[u32], v: &[i32], _wide: bool) -> Status {
        status_of(fmi2SetInteger(c, vrs.as_ptr(), vrs.len(), v.as_ptr()))
    }
    unsafe fn set_boolean(c: Handle, vrs: &[u32]) -> Status {
        let v = vec![FMI2_TRUE; vrs.len()];
        status_of(fmi2SetBoolean(c, vrs.as_ptr(), vrs.len(), v.as_ptr()))
    }
    unsafe fn set_string(c: Handle, vrs: &[u32], v: &[*const c_char]) -> Status {
        status_of(fmi2SetString(c, vrs.as_ptr(), vrs.len(), v.as_ptr()))
    }
    unsafe fn get_state(c: Handle, s: &mut Handle) -> Status {
        status_of(fmi2GetFMUstate(c, s))
    }
    unsafe fn set_state(c: Handle, s: Handle) -> Status {
        status_of(fmi2SetFMUstate(c, s))
    }
    unsafe fn free_state(c: Handle, s: &mut Handle) -> Status {
        status_of(fmi2FreeFMUstate(c, s))
    }
    unsafe fn serialized_size(c: Handle, s: Handle, size: &mut usize) -> Status {
        status_of(fmi2SerializedFMUstateSize(c, s, size))
    }
    unsafe fn serialize(c: Handle, s: Handle, buf: &mut [u8]) -> Status {
        status_of(fmi2SerializeFMUstate(
            c,
            s,
            buf.as_mut_ptr().cast(),
            buf.len(),
        ))
    }
    unsafe fn deserialize(c: Handle, buf: &[u8], s: &mut Handle) -> Status {
        status_of(fmi2DeSerializeFMUstate(
            c,
            buf.as_ptr().cast(),
            buf.len(),
            s,
        ))
    }
    unsafe fn status(c: Handle, kind: u32) -> Option<Status> {
        let mut r = 0.0;
        let mut b = 0;
        let mut s = 0;
        Some(status_of(match kind {
            2 => fmi2GetRealStatus(c, kind, &mut r),
            3 => fmi2GetBooleanStatus(c, kind, &mut b),
            _ => fmi2GetStatus(c, kind, &mut s),
        }))
    }
    unsafe fn logging(c: Handle, on: bool) -> Status {
        status_of(fmi2SetDebugLogging(c, on as fmi2Boolean, 0, ptr::null()))
    }
    unsafe fn last_successful_time(c: Handle) -> f64 {
        let mut t = f64::NAN;
        let st = fmi2GetRealStatus(c, FMI2_LAST_SUCCESSFUL_TIME, &mut t);
        assert_eq!(status_of(st), Status::Ok);
        t
    }
}
