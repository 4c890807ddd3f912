//! The FMI 3.0 C API as the call-sequence harness drives it: the same calls as FMI 2.0 in FMI
//! 3.0's functions. FMI 3.0 has no `fmi2SetupExperiment` (its arguments go to
//! `fmi3EnterInitializationMode`) and no status getters (`lastSuccessfulTime` is an
//! out-argument of `fmi3DoStep`); an integer is Int32 or, for an Enumeration, Int64; `nValues`
//! counts the values of the variables named (an array's 24).

use super::super::*;
use super::{status_of, CApi, Handle};
use crate::fmi3::exports::*;
use crate::fmi3::model_description::core_value_references;
use std::os::raw::c_char;

/// The FMI 3.0 entry points of this library.
pub struct Fmi3;

/// The number of values of the variables `vrs` names.
fn n_values(vrs: &[u32]) -> usize {
    core_value_references(vrs).len()
}

impl CApi for Fmi3 {
    const NAME: &'static str = "FMI 3.0";

    unsafe fn instantiate() -> Handle {
        let token = c_text(&crate::fmi2::guid());
        fmi3InstantiateCoSimulation(
            c"sequence".as_ptr(),
            token.as_ptr(),
            ptr::null(),
            false,
            false,
            false,
            false,
            ptr::null(),
            0,
            ptr::null_mut(),
            None,
            None,
        )
    }
    unsafe fn free_instance(c: Handle) {
        fmi3FreeInstance(c)
    }
    unsafe fn setup(_c: Handle, _start: f64, _stop: Option<f64>) -> Option<Status> {
        None
    }
    unsafe fn enter(c: Handle, start: f64, stop: Option<f64>) -> Status {
        status_of(fmi3EnterInitializationMode(
            c,
            false,
            0.0,
            start,
            stop.is_some(),
            stop.unwrap_or(0.0),
        ))
    }
    unsafe fn exit(c: Handle) -> Status {
        status_of(fmi3ExitInitializationMode(c))
    }
    unsafe fn terminate(c: Handle) -> Status {
        status_of(fmi3Terminate(c))
    }
    unsafe fn reset(c: Handle) -> Status {
        status_of(fmi3Reset(c))
    }
    unsafe fn do_step(c: Handle, t: f64, h: f64) -> Status {
        let (mut event, mut term, mut early, mut last) = (true, true, true, f64::NAN);
        let st = status_of(fmi3DoStep(
            c, t, h, false, &mut event, &mut term, &mut early, &mut last,
        ));
        if matches!(st, Status::Ok | Status::Warning | Status::Discard) {
            assert!(!event && !early, "no event handling, no early return");
            assert!(last.is_finite(), "lastSuccessfulTime {last}");
        }
        st
    }
    unsafe fn get_real(c: Handle, vrs: &[u32]) -> (Status, Vec<f64>) {
        let n = n_values(vrs);
        let mut v = vec![f64::NAN; n];
        let st = fmi3GetFloat64(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), n);
        (status_of(st), v)
    }
    unsafe fn get_integer(c: Handle, vrs: &[u32], wide: bool) -> Status {
        let n = n_values(vrs);
        status_of(if wide {
            let mut v = vec![0i64; n];
            fmi3GetInt64(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), n)
        } else {
            let mut v = vec![0i32; n];
            fmi3GetInt32(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), n)
        })
    }
    unsafe fn get_boolean(c: Handle, vrs: &[u32]) -> Status {
        let n = n_values(vrs);
        let mut v = vec![false; n];
        status_of(fmi3GetBoolean(
            c,
            vrs.as_ptr(),
            vrs.len(),
            v.as_mut_ptr(),
            n,
        ))
    }
    unsafe fn get_string(c: Handle, vrs: &[u32]) -> (Status, Vec<*const c_char>) {
        let n = n_values(vrs);
        let mut v = vec![ptr::null(); n];
        let st = fmi3GetString(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), n);
        (status_of(st), v)
    }
    unsafe fn set_real(c: Handle, vrs: &[u32], v: &[f64]) -> Status {
        status_of(fmi3SetFloat64(
            c,
            vrs.as_ptr(),
            vrs.len(),
            v.as_ptr(),
            v.len(),
        ))
    }
    unsafe fn set_integer(c: Handle, vrs: &[u32], v: &[i32], wide: bool) -> Status {
        status_of(if wide {
            let v: Vec<i64> = v.iter().map(|&x| i64::from(x)).collect();
            fmi3SetInt64(c, vrs.as_ptr(), vrs.len(), v.as_ptr(), v.len())
        } else {
            fmi3SetInt32(c, vrs.as_ptr(), vrs.len(), v.as_ptr(), v.len())
        })
    }
    unsafe fn set_boolean(c: Handle, vrs: &[u32]) -> Status {
        let v = vec![true; vrs.len()];
        status_of(fmi3SetBoolean(
            c,
            vrs.as_ptr(),
            vrs.len(),
            v.as_ptr(),
            v.len(),
        ))
    }
    unsafe fn set_string(c: Handle, vrs: &[u32], v: &[*const c_char]) -> Status {
        status_of(fmi3SetString(
            c,
            vrs.as_ptr(),
            vrs.len(),
            v.as_ptr(),
            v.len(),
        ))
    }
    unsafe fn get_state(c: Handle, s: &mut Handle) -> Status {
        status_of(fmi3GetFMUState(c, s))
    }
    unsafe fn set_state(c: Handle, s: Handle) -> Status {
        status_of(fmi3SetFMUState(c, s))
    }
    unsafe fn free_state(c: Handle, s: &mut Handle) -> Status {
        status_of(fmi3FreeFMUState(c, s))
    }
    unsafe fn serialized_size(c: Handle, s: Handle, size: &mut usize) -> Status {
        status_of(fmi3SerializedFMUStateSize(c, s, size))
    }
    unsafe fn serialize(c: Handle, s: Handle, buf: &mut [u8]) -> Status {
        status_of(fmi3SerializeFMUState(c, s, buf.as_mut_ptr(), buf.len()))
    }
    unsafe fn deserialize(c: Handle, buf: &[u8], s: &mut Handle) -> Status {
        status_of(fmi3DeserializeFMUState(c, buf.as_ptr(), buf.len(), s))
    }
    unsafe fn status(_c: Handle, _kind: u32) -> Option<Status> {
        None
    }
    unsafe fn logging(c: Handle, on: bool) -> Status {
        status_of(fmi3SetDebugLogging(c, on, 0, ptr::null()))
    }
    unsafe fn last_successful_time(c: Handle) -> f64 {
        instance(c).expect("a live instance").last_successful_time()
    }
}
