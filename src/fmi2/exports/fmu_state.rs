//! FMI 2.0 section 2.1.8: getting, setting and serializing the complete FMU state.

#![allow(non_snake_case)]

use super::*;
use crate::fmi2::instance::Snapshot;

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

const STATE_TAG: u64 = u64::from_le_bytes(*b"VSPHstat");

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
