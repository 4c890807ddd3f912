//! Random FMI 2.0 and FMI 3.0 call sequences through the exported C functions, in-process
//! (proptest).
//!
//! One generator and one model of the standard serve both APIs: a sequence is a list of
//! [`Call`]s, and [`CApi`] makes each call through FMI 2.0's functions ([`fmi2::Fmi2`]) or FMI
//! 3.0's ([`fmi3::Fmi3`]: `fmi3EnterInitializationMode` takes the experiment's start and stop
//! time, which FMI 2.0 sets by `fmi2SetupExperiment`; Int32 or Int64; `nValues`; no status
//! getters). Both standards' Co-Simulation state machines are the same one for these calls
//! (FMI 3.0's Step Mode is FMI 2.0's stepComplete; a discarded step leaves the instance where
//! only the last good state, the getters, reset and terminate are allowed).
//!
//! Each case instantiates an FMU and makes up to 40 random calls: setup (with finite, NaN and
//! huge stop times), enter/exit initialization, get/set of Real, Integer, Boolean and String
//! variables with valid and invalid value references and values (NaN, infinities, out of
//! range), `fmi2DoStep` with tiny, zero, negative, NaN, infinite and huge steps, get, set,
//! free and serialize FMU states, the status getters, reset, terminate, and free and
//! instantiate again. The properties:
//!
//! - the process neither crashes nor hangs (the test ends);
//! - every call answers a status the standard allows for it in the state the instance is in
//!   (a call the state machine forbids answers `fmi2Error`; nothing answers `fmi2Fatal` or
//!   `fmi2Pending`), and the instance is then in the state the standard says (FMI 2.0 section
//!   4.2.4, modelled here independently of `instance::mask` and checked against the instance);
//! - an instance whose call answered `fmi2OK` keeps working: all of its outputs can be read and
//!   are finite wherever reading is allowed, and at the end of every case `fmi2Reset` and a short
//!   run succeed.
//!
//! The work of a case is bounded by a tiny resolution (4 to 8 particles across, set after every
//! instantiation and reset and never raised by the random calls), small budgets
//! (`max_steps_per_do_step` of 1 to 40) and the run-length rule. 4000 cases by default (a few
//! seconds; well under a minute on two cores shared with builds) for each API;
//! `VISCOSPH_FMI_SEQUENCES=<n>` runs `n` cases from a random seed instead of the fixed one, for a
//! longer search.

use super::*;
use crate::fmi2::instance::Phase;
use crate::scene::{OUTPUTS, OUTPUT_ARRAYS};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::marker::PhantomData;
use std::os::raw::c_char;

mod fmi2;
mod fmi3;
mod generator;

use generator::*;

/// An instance or an FMU state: the same C pointer in both APIs.
type Handle = *mut std::ffi::c_void;

/// One FMI version's C API, as the harness calls it: the status of each call (and the values
/// a getter read).
trait CApi {
    const NAME: &'static str;
    unsafe fn instantiate() -> Handle;
    unsafe fn free_instance(c: Handle);
    /// `fmi2SetupExperiment`; None where the API has no such call (FMI 3.0).
    unsafe fn setup(c: Handle, start: f64, stop: Option<f64>) -> Option<Status>;
    /// Enter initialization mode; FMI 3.0 takes the start and stop time of the last setup here.
    unsafe fn enter(c: Handle, start: f64, stop: Option<f64>) -> Status;
    unsafe fn exit(c: Handle) -> Status;
    unsafe fn terminate(c: Handle) -> Status;
    unsafe fn reset(c: Handle) -> Status;
    unsafe fn do_step(c: Handle, t: f64, h: f64) -> Status;
    unsafe fn get_real(c: Handle, vrs: &[u32]) -> (Status, Vec<f64>);
    /// `wide`: FMI 3.0's Int64 (Enumerations) rather than Int32; FMI 2.0 has one Integer.
    unsafe fn get_integer(c: Handle, vrs: &[u32], wide: bool) -> Status;
    unsafe fn get_boolean(c: Handle, vrs: &[u32]) -> Status;
    unsafe fn get_string(c: Handle, vrs: &[u32]) -> (Status, Vec<*const c_char>);
    unsafe fn set_real(c: Handle, vrs: &[u32], v: &[f64]) -> Status;
    unsafe fn set_integer(c: Handle, vrs: &[u32], v: &[i32], wide: bool) -> Status;
    unsafe fn set_boolean(c: Handle, vrs: &[u32]) -> Status;
    unsafe fn set_string(c: Handle, vrs: &[u32], v: &[*const c_char]) -> Status;
    unsafe fn get_state(c: Handle, s: &mut Handle) -> Status;
    unsafe fn set_state(c: Handle, s: Handle) -> Status;
    unsafe fn free_state(c: Handle, s: &mut Handle) -> Status;
    unsafe fn serialized_size(c: Handle, s: Handle, size: &mut usize) -> Status;
    unsafe fn serialize(c: Handle, s: Handle, buf: &mut [u8]) -> Status;
    unsafe fn deserialize(c: Handle, buf: &[u8], s: &mut Handle) -> Status;
    /// The status getters of FMI 2.0; None in FMI 3.0, which has none.
    unsafe fn status(c: Handle, kind: u32) -> Option<Status>;
    unsafe fn logging(c: Handle, on: bool) -> Status;
    unsafe fn last_successful_time(c: Handle) -> f64;
}

/// Number of FMU-state slots a sequence juggles.
const SLOTS: usize = 3;

/// What the cases exercised, to show the search reaches the interesting places (steps that
/// complete, steps discarded by the budget, states set after a discard, refusals).
#[derive(Debug, Default)]
struct Tally {
    steps_ok: usize,
    steps_discarded: usize,
    steps_refused: usize,
    resumed_after_discard: usize,
    refused_out_of_sequence: usize,
    calls: usize,
}

thread_local! {
    static TALLY: std::cell::RefCell<Tally> = std::cell::RefCell::new(Tally::default());
}

fn tally(f: impl FnOnce(&mut Tally)) {
    TALLY.with(|t| f(&mut t.borrow_mut()));
}

/// The phases in which the standard allows each call (FMI 2.0 section 4.2.4, the table of the
/// Co-Simulation state machine; `Error` is its error state).
fn allowed(call: &Call, p: Phase) -> bool {
    use Phase::*;
    let get = matches!(
        p,
        InitializationMode | StepComplete | StepFailed | Terminated | Error
    );
    match call {
        Call::Setup { .. } | Call::Enter => p == Instantiated,
        Call::Exit => p == InitializationMode,
        Call::Terminate => matches!(p, StepComplete | StepFailed),
        Call::DoStep { .. } => p == StepComplete,
        Call::GetReal(_) | Call::GetInteger(..) | Call::GetBoolean(_) | Call::GetString(_) => get,
        // Inputs may also be set after a completed step.
        Call::SetReal(_) | Call::SetInteger(..) => {
            matches!(p, Instantiated | InitializationMode | StepComplete)
        }
        Call::SetBoolean(_) | Call::SetString(_) => matches!(p, Instantiated | InitializationMode),
        Call::Status(_) => matches!(p, StepComplete | StepFailed | Terminated | Error),
        Call::Reset
        | Call::GetState(_)
        | Call::SetState(_)
        | Call::FreeState(_)
        | Call::Reserialize(_)
        | Call::Logging(_)
        | Call::Reinstantiate => true,
    }
}

/// The statuses a call may answer when allowed (never fmi2Fatal, never fmi2Pending: the
/// slave is synchronous, `canRunAsynchronuously = false`).
fn may_answer(call: &Call, s: Status) -> bool {
    match call {
        Call::DoStep { .. } | Call::Status(_) => {
            matches!(
                s,
                Status::Ok | Status::Warning | Status::Discard | Status::Error
            )
        }
        _ => matches!(s, Status::Ok | Status::Warning | Status::Error),
    }
}

fn status_of(code: u32) -> Status {
    match code {
        0 => Status::Ok,
        1 => Status::Warning,
        2 => Status::Discard,
        3 => Status::Error,
        4 => Status::Fatal,
        5 => Status::Pending,
        other => panic!("status code {other} is not an fmi2Status"),
    }
}

/// A slot: the C state handle, and the phase and communication point restoring it gives.
struct Slot {
    state: Handle,
    restores: Option<(Phase, f64)>,
}

/// The model of the instance the sequence drives through API `A`.
struct Harness<A: CApi> {
    c: Handle,
    phase: Phase,
    /// The communication point the next step must continue from.
    t: f64,
    /// The start time of the last accepted `fmi2SetupExperiment` (FMI 3.0: of the last
    /// accepted `fmi3EnterInitializationMode`).
    start: f64,
    /// FMI 3.0: the start and stop time of the last [`Call::Setup`], for the next
    /// `fmi3EnterInitializationMode`.
    experiment: (f64, Option<f64>),
    slots: Vec<Slot>,
    /// The outputs read after every call that answered OK: the scalars, and in FMI 3.0 the
    /// arrays too.
    outputs: Vec<u32>,
    api: PhantomData<A>,
}

impl<A: CApi> Harness<A> {
    fn new() -> Harness<A> {
        let mut outputs: Vec<u32> = OUTPUTS.iter().map(|o| o.value_reference).collect();
        if A::NAME == fmi3::Fmi3::NAME {
            outputs.extend(OUTPUT_ARRAYS.iter().map(|a| a.value_reference));
        }
        let mut h = Harness {
            c: ptr::null_mut(),
            phase: Phase::Instantiated,
            t: 0.0,
            start: 0.0,
            experiment: (0.0, None),
            slots: (0..SLOTS)
                .map(|_| Slot {
                    state: ptr::null_mut(),
                    restores: None,
                })
                .collect(),
            outputs,
            api: PhantomData,
        };
        h.instantiate();
        h
    }

    fn instantiate(&mut self) {
        self.c = unsafe { A::instantiate() };
        assert!(!self.c.is_null());
        self.phase = Phase::Instantiated;
        self.start = 0.0;
        self.experiment = (0.0, None);
        self.small();
    }

    /// Tiny scenes and small budgets, after every instantiation and reset.
    fn small(&mut self) {
        let vrs = [vr("particles_per_diameter"), vr("max_steps_per_do_step")];
        let st = unsafe { A::set_integer(self.c, &vrs, &[6, 20], false) };
        assert_eq!(st, Status::Ok);
    }

    /// The instance behind the handle, read only: its phase and error cause are checked
    /// against the model.
    fn inst(&self) -> &Instance {
        unsafe { instance(self.c) }.expect("a live instance")
    }

    /// Make one call; check its status and the state it leaves.
    fn run(&mut self, call: &Call) {
        let before = self.phase;
        let ok_here = allowed(call, before);
        let Some(st) = self.call(call) else {
            // A call the API does not have (FMI 3.0's setup is part of entering
            // initialization, and it has no status getters): nothing happened.
            return;
        };
        tally(|t| {
            t.calls += 1;
            match (call, ok_here, st) {
                (_, false, _) => t.refused_out_of_sequence += 1,
                (Call::DoStep { .. }, _, Status::Ok) => t.steps_ok += 1,
                (Call::DoStep { .. }, _, Status::Discard) => t.steps_discarded += 1,
                (Call::DoStep { .. }, _, _) => t.steps_refused += 1,
                (Call::SetState(k), _, Status::Ok)
                    if before == Phase::StepFailed
                        && self.slots[*k].restores.map(|r| r.0) == Some(Phase::StepComplete) =>
                {
                    t.resumed_after_discard += 1
                }
                _ => {}
            }
        });
        if st == Status::Error {
            let cause = self.inst().error_cause().unwrap_or_default();
            assert!(
                !cause.contains("(panic)"),
                "{call:?} in {before:?}: {cause}"
            );
        }
        if !ok_here {
            assert_eq!(st, Status::Error, "{call:?} in {before:?}");
        } else {
            assert!(
                may_answer(call, st),
                "{call:?} in {before:?} answered {st:?}"
            );
        }
        self.phase = match (call, st) {
            (Call::Reinstantiate, _) => Phase::Instantiated,
            (_, Status::Error) => Phase::Error,
            (Call::Setup { start, .. }, _) => {
                self.start = *start;
                before
            }
            (Call::Enter, _) => {
                if A::NAME == fmi3::Fmi3::NAME {
                    self.start = self.experiment.0;
                }
                Phase::InitializationMode
            }
            (Call::Exit, _) => {
                self.t = self.start;
                Phase::StepComplete
            }
            (Call::Terminate, _) => Phase::Terminated,
            (Call::Reset, _) => {
                self.small();
                self.start = 0.0;
                self.experiment = (0.0, None);
                Phase::Instantiated
            }
            (Call::DoStep { .. }, Status::Discard) => Phase::StepFailed,
            (Call::DoStep { h, .. }, _) => {
                self.t += h;
                Phase::StepComplete
            }
            (Call::SetState(k), _) => {
                let (p, t) = self.slots[*k].restores.expect("a state was set");
                self.t = t;
                p
            }
            _ => before,
        };
        assert_eq!(
            self.inst().phase(),
            self.phase,
            "{} {call:?} in {before:?} answered {st:?}",
            A::NAME
        );
        // Outputs are read where they are the last communication point's (in initialization
        // mode they are built from parameters that may still be inconsistent).
        let stepped = matches!(
            self.phase,
            Phase::StepComplete | Phase::StepFailed | Phase::Terminated
        );
        if st == Status::Ok && stepped {
            let (st, v) = unsafe { A::get_real(self.c, &self.outputs) };
            assert_eq!(st, Status::Ok, "outputs after {call:?}");
            assert!(v.iter().all(|x| x.is_finite()), "{v:?} after {call:?}");
        }
    }

    /// Make the call; None for a call the API does not have.
    fn call(&mut self, call: &Call) -> Option<Status> {
        let c = self.c;
        unsafe {
            Some(match call {
                Call::Setup { start, stop } => match A::setup(c, *start, *stop) {
                    Some(st) => st,
                    None => {
                        self.experiment = (*start, *stop);
                        return None;
                    }
                },
                Call::Enter => A::enter(c, self.experiment.0, self.experiment.1),
                Call::Exit => A::exit(c),
                Call::Terminate => A::terminate(c),
                Call::Reset => A::reset(c),
                Call::DoStep { offset, h } => A::do_step(c, self.t + offset, *h),
                Call::GetReal(vrs) => A::get_real(c, vrs).0,
                Call::GetInteger(vrs, wide) => A::get_integer(c, vrs, *wide),
                Call::GetBoolean(vrs) => A::get_boolean(c, vrs),
                Call::GetString(vrs) => {
                    let (st, v) = A::get_string(c, vrs);
                    if st == Status::Ok {
                        assert!(v.iter().all(|p| !p.is_null()));
                    }
                    st
                }
                Call::SetReal(pairs) => {
                    let (vrs, v): (Vec<u32>, Vec<f64>) = pairs.iter().copied().unzip();
                    A::set_real(c, &vrs, &v)
                }
                Call::SetInteger(pairs, wide) => {
                    let (vrs, v): (Vec<u32>, Vec<i32>) = pairs.iter().copied().unzip();
                    A::set_integer(c, &vrs, &v, *wide)
                }
                Call::SetBoolean(vrs) => A::set_boolean(c, vrs),
                Call::SetString(pairs) => {
                    let texts: Vec<CString> = pairs.iter().map(|(_, t)| c_text(t)).collect();
                    let vrs: Vec<u32> = pairs.iter().map(|(v, _)| *v).collect();
                    let ptrs: Vec<*const c_char> = texts.iter().map(|t| t.as_ptr()).collect();
                    A::set_string(c, &vrs, &ptrs)
                }
                Call::GetState(k) => {
                    // What restoring gives: the state as it is, or after a discarded step the
                    // last good state, a completed step at the last successful time.
                    let restores = match self.phase {
                        Phase::StepFailed if self.inst().resumable() => {
                            (Phase::StepComplete, A::last_successful_time(c))
                        }
                        p => (p, self.t),
                    };
                    let st = A::get_state(c, &mut self.slots[*k].state);
                    if st == Status::Ok {
                        self.slots[*k].restores = Some(restores);
                    }
                    st
                }
                Call::SetState(k) => A::set_state(c, self.slots[*k].state),
                Call::FreeState(k) => {
                    let st = A::free_state(c, &mut self.slots[*k].state);
                    if st == Status::Ok {
                        assert!(self.slots[*k].state.is_null());
                        self.slots[*k].restores = None;
                    }
                    st
                }
                Call::Reserialize(k) => self.reserialize(*k),
                Call::Status(kind) => return A::status(c, *kind),
                Call::Logging(on) => A::logging(c, *on),
                Call::Reinstantiate => {
                    A::free_instance(c);
                    self.instantiate();
                    Status::Ok
                }
            })
        }
    }

    /// Serialize the slot's state, free it, and deserialize the bytes into the slot.
    unsafe fn reserialize(&mut self, k: usize) -> Status {
        let c = self.c;
        let s = self.slots[k].state;
        let mut size = 0usize;
        let st = A::serialized_size(c, s, &mut size);
        if st != Status::Ok {
            return st;
        }
        let mut buf = vec![0u8; size];
        assert_eq!(
            A::serialize(c, s, &mut buf),
            Status::Ok,
            "serializing a state of ours"
        );
        assert_eq!(A::free_state(c, &mut self.slots[k].state), Status::Ok);
        A::deserialize(c, &buf, &mut self.slots[k].state)
    }

    /// The instance recovers: reset, a short run, finite outputs.
    fn still_works(&mut self) {
        let c = self.c;
        unsafe {
            assert_eq!(A::reset(c), Status::Ok);
            self.small();
            if let Some(st) = A::setup(c, 0.0, Some(0.01)) {
                assert_eq!(st, Status::Ok);
            }
            assert_eq!(A::enter(c, 0.0, Some(0.01)), Status::Ok);
            assert_eq!(A::exit(c), Status::Ok);
            assert_eq!(A::do_step(c, 0.0, 1e-5), Status::Ok);
            let (st, v) = A::get_real(c, &self.outputs);
            assert_eq!(st, Status::Ok);
            assert!(v.iter().all(|x| x.is_finite()));
        }
    }
}

impl<A: CApi> Drop for Harness<A> {
    fn drop(&mut self) {
        unsafe {
            for s in &mut self.slots {
                if !s.state.is_null() {
                    A::free_state(self.c, &mut s.state);
                }
            }
            A::free_instance(self.c);
        }
    }
}

/// The random sequences through API `A`: `VISCOSPH_FMI_SEQUENCES` cases from a random seed,
/// or 4000 from a fixed one.
fn random_call_sequences<A: CApi>() {
    TALLY.with(|t| *t.borrow_mut() = Tally::default());
    let long = std::env::var("VISCOSPH_FMI_SEQUENCES").ok().map(|n| {
        n.parse::<u32>()
            .expect("VISCOSPH_FMI_SEQUENCES is a number")
    });
    let config = Config {
        cases: long.unwrap_or(4000),
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = match long {
        Some(_) => TestRunner::new(config),
        None => TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha)),
    };
    let result = runner.run(&prop::collection::vec(chunk(), 1..16), |chunks| {
        let mut h = Harness::<A>::new();
        for call in chunks.iter().flatten() {
            h.run(call);
        }
        h.still_works();
        Ok(())
    });
    if let Err(e) = result {
        panic!("{}: {e}", A::NAME);
    }
    TALLY.with(|t| {
        let t = t.borrow();
        eprintln!("{}: {t:?}", A::NAME);
        for (what, n) in [
            ("completed steps", t.steps_ok),
            ("discarded steps", t.steps_discarded),
            ("refused steps", t.steps_refused),
            ("states set after a discard", t.resumed_after_discard),
            ("calls out of sequence", t.refused_out_of_sequence),
        ] {
            assert!(n >= 20, "{}: only {n} {what}: {t:?}", A::NAME);
        }
    });
}

#[test]
fn random_call_sequences_answer_what_the_standard_allows() {
    random_call_sequences::<fmi2::Fmi2>();
}

#[test]
fn random_fmi3_call_sequences_answer_what_the_standard_allows() {
    random_call_sequences::<fmi3::Fmi3>();
}
