//! Random FMI 2.0 call sequences through the exported C functions, in-process (proptest).
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
//! seconds; well under a minute on two cores shared with builds); `VISCOSPH_FMI_SEQUENCES=<n>` runs `n`
//! cases from a random seed instead of the fixed one, for a longer search.

use super::fmu_state::*;
use super::tests::callbacks;
use super::*;
use crate::config::Kind;
use crate::fmi2::instance::Phase;
use crate::scene::{param_spec, OUTPUTS};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

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

#[derive(Debug, Clone)]
enum Call {
    Setup {
        start: f64,
        stop: Option<f64>,
    },
    Enter,
    Exit,
    Terminate,
    Reset,
    /// `fmi2DoStep(t + offset, h)` where `t` is the model's communication point.
    DoStep {
        offset: f64,
        h: f64,
    },
    GetReal(Vec<u32>),
    GetInteger(Vec<u32>),
    GetBoolean(Vec<u32>),
    GetString(Vec<u32>),
    SetReal(Vec<(u32, f64)>),
    SetInteger(Vec<(u32, i32)>),
    SetBoolean(Vec<u32>),
    SetString(Vec<(u32, String)>),
    GetState(usize),
    SetState(usize),
    FreeState(usize),
    /// Serialize the slot's state and deserialize it into the slot.
    Reserialize(usize),
    Status(u32),
    Logging(bool),
    /// `fmi2FreeInstance` and `fmi2Instantiate` again (the slots' states stay valid).
    Reinstantiate,
}

fn vr(name: &str) -> u32 {
    param_spec(name)
        .map(|p| p.value_reference)
        .unwrap_or_else(|| panic!("{name}"))
}

/// Value references: some of every kind of variable, and some of none.
fn any_vr() -> impl Strategy<Value = u32> + Clone {
    let named: Vec<u32> = [
        "scene",
        "scheme",
        "rheology",
        "impact_velocity",
        "drop_diameter",
        "viscosity",
        "relaxation_time",
        "sound_speed",
        "time_step_factor",
        "particles_per_diameter",
        "max_steps_per_do_step",
        "max_seconds_per_do_step",
        "threads",
        "equation_of_state",
        "plate_velocity",
        "plate_position",
        "plate_coupling",
        "max_plate_speed",
        "jet_velocity",
    ]
    .iter()
    .map(|n| vr(n))
    .chain([1001, 1003, 1031]) // String twins
    .collect();
    let others: Vec<u32> = OUTPUTS
        .iter()
        .take(4)
        .map(|o| o.value_reference)
        .chain([0, 35, 100, 999, 5000, u32::MAX]) // nobody's
        .collect();
    prop_oneof![
        9 => prop::sample::select(named),
        1 => prop::sample::select(others),
    ]
}

/// A special value, or `None` for one within the variable's range.
fn real_value() -> impl Strategy<Value = Option<f64>> {
    prop_oneof![
        12 => Just(None),
        1 => Just(Some(f64::NAN)),
        1 => Just(Some(f64::INFINITY)),
        1 => Just(Some(f64::NEG_INFINITY)),
        1 => Just(Some(-1.0)),
        1 => Just(Some(1e300)),
    ]
}

/// A Real value for `vr`, kept small where a large one would make the case slow (a parameter
/// that scales the particle count or the threads is never raised: those are Integers).
fn set_real() -> impl Strategy<Value = (u32, f64)> {
    (any_vr(), real_value(), 0.0..1.0f64).prop_map(|(v, special, frac)| {
        let x = special.unwrap_or_else(|| match crate::scene::param_by_vr(v).map(|p| p.kind) {
            Some(Kind::Real { min, max, .. }) => min + frac * (max - min),
            _ => frac,
        });
        // A wall-clock budget of at most 0.05 s per step keeps a case short.
        if v == vr("max_seconds_per_do_step") && x.is_finite() && x > 0.05 {
            (v, 0.05)
        } else {
            (v, x)
        }
    })
}

/// An Integer value for `vr`: never more than 8 particles across, 40 steps a call or 2 threads.
fn set_integer() -> impl Strategy<Value = (u32, i32)> {
    (any_vr(), -3..12i32, prop::bool::weighted(0.1)).prop_map(|(v, x, extreme)| {
        let x = if extreme { i32::MIN } else { x };
        let x = if v == vr("particles_per_diameter") {
            x.min(8)
        } else if v == vr("max_steps_per_do_step") {
            x.min(40)
        } else if v == vr("threads") {
            x.min(2)
        } else {
            x
        };
        (v, x)
    })
}

fn step_size() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => 1e-6..2e-3f64,
        1 => Just(0.0),
        1 => Just(-1e-3),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(1e9),
        1 => Just(1e300),
    ]
}

/// A few calls: a random one, or the usual setup-enter-exit, or a few ordinary steps, so that
/// the cases reach the stepping states as well as the refusals.
fn chunk() -> impl Strategy<Value = Vec<Call>> {
    let start = |stop| vec![Call::Setup { start: 0.0, stop }, Call::Enter, Call::Exit];
    prop_oneof![
        6 => call().prop_map(|c| vec![c]),
        2 => prop::option::of(1e-3..0.05f64).prop_map(start),
        2 => prop::option::of(1e-3..0.05f64).prop_map(move |stop| {
            let mut v = vec![Call::Reset];
            v.extend(start(stop));
            v
        }),
        3 => (1..4usize, 1e-5..1e-3f64)
            .prop_map(|(n, h)| vec![Call::DoStep { offset: 0.0, h }; n]),
        // A step far past the budget, then the master goes on from the last good state.
        2 => (0..SLOTS, 1e-5..1e-3f64).prop_map(|(k, h)| vec![
            Call::DoStep { offset: 0.0, h: 0.02 },
            Call::GetState(k),
            Call::SetState(k),
            Call::DoStep { offset: 0.0, h },
        ]),
        // An input changed between steps.
        1 => (-0.5..0.5f64, 1e-5..1e-3f64).prop_map(|(v, h)| vec![
            Call::SetReal(vec![(vr("plate_velocity"), v)]),
            Call::DoStep { offset: 0.0, h },
        ]),
    ]
}

fn call() -> impl Strategy<Value = Call> {
    let slot = 0..SLOTS;
    let vrs = prop::collection::vec(any_vr(), 0..4);
    let text = prop::sample::select(vec![
        "drop", "channel", "jet", "wcsph", "pdri", "isph", "giesekus", "tait", "", "bogus%s",
    ])
    .prop_map(String::from);
    prop_oneof![
        2 => (prop_oneof![4 => Just(0.0), 2 => Just(0.5), 1 => Just(f64::NAN)],
              prop::option::of(prop_oneof![Just(0.01), Just(1e9), Just(f64::NAN), Just(-1.0)]))
            .prop_map(|(start, stop)| Call::Setup { start, stop: stop.map(|s| if s > 0.0 { start + s } else { s }) }),
        3 => Just(Call::Enter),
        3 => Just(Call::Exit),
        1 => Just(Call::Terminate),
        3 => Just(Call::Reset),
        8 => (prop_oneof![8 => Just(0.0), 1 => Just(1e-3), 1 => Just(f64::NAN)], step_size())
            .prop_map(|(offset, h)| Call::DoStep { offset, h }),
        2 => vrs.clone().prop_map(Call::GetReal),
        1 => vrs.clone().prop_map(Call::GetInteger),
        1 => vrs.clone().prop_map(Call::GetBoolean),
        1 => vrs.clone().prop_map(Call::GetString),
        3 => prop::collection::vec(set_real(), 0..3).prop_map(Call::SetReal),
        2 => prop::collection::vec(set_integer(), 0..3).prop_map(Call::SetInteger),
        1 => vrs.prop_map(Call::SetBoolean),
        1 => prop::collection::vec((any_vr(), text), 0..3).prop_map(Call::SetString),
        2 => slot.clone().prop_map(Call::GetState),
        2 => slot.clone().prop_map(Call::SetState),
        1 => slot.clone().prop_map(Call::FreeState),
        1 => slot.prop_map(Call::Reserialize),
        1 => (0..6u32).prop_map(Call::Status),
        1 => any::<bool>().prop_map(Call::Logging),
        1 => Just(Call::Reinstantiate),
    ]
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
        Call::GetReal(_) | Call::GetInteger(_) | Call::GetBoolean(_) | Call::GetString(_) => get,
        // Inputs may also be set after a completed step.
        Call::SetReal(_) | Call::SetInteger(_) => {
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

fn status_of(code: fmi2Status) -> Status {
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
    state: fmi2FMUstate,
    restores: Option<(Phase, f64)>,
}

/// The model of the instance the sequence drives.
struct Harness {
    cb: fmi2CallbackFunctions,
    guid: CString,
    c: fmi2Component,
    phase: Phase,
    /// The communication point `fmi2DoStep` must continue from.
    t: f64,
    /// The start time of the last accepted `fmi2SetupExperiment`.
    start: f64,
    slots: Vec<Slot>,
    outputs: Vec<u32>,
}

impl Harness {
    fn new() -> Harness {
        let mut h = Harness {
            cb: callbacks(),
            guid: c_text(&guid()),
            c: ptr::null_mut(),
            phase: Phase::Instantiated,
            t: 0.0,
            start: 0.0,
            slots: (0..SLOTS)
                .map(|_| Slot {
                    state: ptr::null_mut(),
                    restores: None,
                })
                .collect(),
            outputs: OUTPUTS.iter().map(|o| o.value_reference).collect(),
        };
        h.instantiate();
        h
    }

    fn instantiate(&mut self) {
        self.c = unsafe {
            fmi2Instantiate(
                c"sequence".as_ptr(),
                FMI2_CO_SIMULATION,
                self.guid.as_ptr(),
                ptr::null(),
                &self.cb,
                FMI2_FALSE,
                FMI2_FALSE,
            )
        };
        assert!(!self.c.is_null());
        self.phase = Phase::Instantiated;
        self.start = 0.0;
        self.small();
    }

    /// Tiny scenes and small budgets, after every instantiation and reset.
    fn small(&mut self) {
        let vrs = [vr("particles_per_diameter"), vr("max_steps_per_do_step")];
        let st = unsafe { fmi2SetInteger(self.c, vrs.as_ptr(), 2, [6, 20].as_ptr()) };
        assert_eq!(status_of(st), Status::Ok);
    }

    /// The instance behind the handle, read only: its phase and error cause are checked
    /// against the model.
    fn inst(&self) -> &Instance {
        unsafe { instance(self.c) }.expect("a live instance")
    }

    fn last_successful_time(&self) -> f64 {
        let mut t = f64::NAN;
        let st = unsafe { fmi2GetRealStatus(self.c, FMI2_LAST_SUCCESSFUL_TIME, &mut t) };
        assert_eq!(status_of(st), Status::Ok);
        t
    }

    /// Make one call; check its status and the state it leaves.
    fn run(&mut self, call: &Call) {
        let before = self.phase;
        let ok_here = allowed(call, before);
        let st = self.call(call);
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
            (Call::Enter, _) => Phase::InitializationMode,
            (Call::Exit, _) => {
                self.t = self.start;
                Phase::StepComplete
            }
            (Call::Terminate, _) => Phase::Terminated,
            (Call::Reset, _) => {
                self.small();
                self.start = 0.0;
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
            "{call:?} in {before:?} answered {st:?}"
        );
        // Outputs are read where they are the last communication point's (in initialization
        // mode they are built from parameters that may still be inconsistent).
        let stepped = matches!(
            self.phase,
            Phase::StepComplete | Phase::StepFailed | Phase::Terminated
        );
        if st == Status::Ok && stepped {
            let mut v = vec![f64::NAN; self.outputs.len()];
            let st = unsafe { fmi2GetReal(self.c, self.outputs.as_ptr(), v.len(), v.as_mut_ptr()) };
            assert_eq!(status_of(st), Status::Ok, "outputs after {call:?}");
            assert!(v.iter().all(|x| x.is_finite()), "{v:?} after {call:?}");
        }
    }

    fn call(&mut self, call: &Call) -> Status {
        let c = self.c;
        let code = unsafe {
            match call {
                Call::Setup { start, stop } => fmi2SetupExperiment(
                    c,
                    FMI2_FALSE,
                    0.0,
                    *start,
                    stop.is_some() as fmi2Boolean,
                    stop.unwrap_or(0.0),
                ),
                Call::Enter => fmi2EnterInitializationMode(c),
                Call::Exit => fmi2ExitInitializationMode(c),
                Call::Terminate => fmi2Terminate(c),
                Call::Reset => fmi2Reset(c),
                Call::DoStep { offset, h } => fmi2DoStep(c, self.t + offset, *h, FMI2_FALSE),
                Call::GetReal(vrs) => {
                    let mut v = vec![0.0; vrs.len()];
                    fmi2GetReal(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr())
                }
                Call::GetInteger(vrs) => {
                    let mut v = vec![0; vrs.len()];
                    fmi2GetInteger(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr())
                }
                Call::GetBoolean(vrs) => {
                    let mut v = vec![0; vrs.len()];
                    fmi2GetBoolean(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr())
                }
                Call::GetString(vrs) => {
                    let mut v = vec![ptr::null(); vrs.len()];
                    let st = fmi2GetString(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr());
                    if st == Status::Ok.code() {
                        assert!(v.iter().all(|p| !p.is_null()));
                    }
                    st
                }
                Call::SetReal(pairs) => {
                    let (vrs, v): (Vec<u32>, Vec<f64>) = pairs.iter().copied().unzip();
                    fmi2SetReal(c, vrs.as_ptr(), vrs.len(), v.as_ptr())
                }
                Call::SetInteger(pairs) => {
                    let (vrs, v): (Vec<u32>, Vec<i32>) = pairs.iter().copied().unzip();
                    fmi2SetInteger(c, vrs.as_ptr(), vrs.len(), v.as_ptr())
                }
                Call::SetBoolean(vrs) => {
                    let v = vec![FMI2_TRUE; vrs.len()];
                    fmi2SetBoolean(c, vrs.as_ptr(), vrs.len(), v.as_ptr())
                }
                Call::SetString(pairs) => {
                    let texts: Vec<CString> = pairs.iter().map(|(_, t)| c_text(t)).collect();
                    let vrs: Vec<u32> = pairs.iter().map(|(v, _)| *v).collect();
                    let ptrs: Vec<fmi2String> = texts.iter().map(|t| t.as_ptr()).collect();
                    fmi2SetString(c, vrs.as_ptr(), vrs.len(), ptrs.as_ptr())
                }
                Call::GetState(k) => {
                    // What restoring gives: the state as it is, or after a discarded step the
                    // last good state, a completed step at fmi2LastSuccessfulTime.
                    let restores = match self.phase {
                        Phase::StepFailed if self.inst().resumable() => {
                            (Phase::StepComplete, self.last_successful_time())
                        }
                        p => (p, self.t),
                    };
                    let st = fmi2GetFMUstate(c, &mut self.slots[*k].state);
                    if st == Status::Ok.code() {
                        self.slots[*k].restores = Some(restores);
                    }
                    st
                }
                Call::SetState(k) => fmi2SetFMUstate(c, self.slots[*k].state),
                Call::FreeState(k) => {
                    let st = fmi2FreeFMUstate(c, &mut self.slots[*k].state);
                    if st == Status::Ok.code() {
                        assert!(self.slots[*k].state.is_null());
                        self.slots[*k].restores = None;
                    }
                    st
                }
                Call::Reserialize(k) => self.reserialize(*k),
                Call::Status(kind) => {
                    let mut r = 0.0;
                    let mut b = 0;
                    match kind {
                        2 => fmi2GetRealStatus(c, *kind, &mut r),
                        3 => fmi2GetBooleanStatus(c, *kind, &mut b),
                        _ => {
                            let mut s = 0;
                            fmi2GetStatus(c, *kind, &mut s)
                        }
                    }
                }
                Call::Logging(on) => fmi2SetDebugLogging(c, *on as fmi2Boolean, 0, ptr::null()),
                Call::Reinstantiate => {
                    fmi2FreeInstance(c);
                    self.instantiate();
                    Status::Ok.code()
                }
            }
        };
        status_of(code)
    }

    /// Serialize the slot's state, free it, and deserialize the bytes into the slot.
    unsafe fn reserialize(&mut self, k: usize) -> fmi2Status {
        let c = self.c;
        let s = self.slots[k].state;
        let mut size = 0usize;
        let st = fmi2SerializedFMUstateSize(c, s, &mut size);
        if st != Status::Ok.code() {
            return st;
        }
        let mut buf = vec![0 as fmi2Byte; size];
        let st = fmi2SerializeFMUstate(c, s, buf.as_mut_ptr(), size);
        assert_eq!(status_of(st), Status::Ok, "serializing a state of ours");
        assert_eq!(
            status_of(fmi2FreeFMUstate(c, &mut self.slots[k].state)),
            Status::Ok
        );
        fmi2DeSerializeFMUstate(c, buf.as_ptr(), size, &mut self.slots[k].state)
    }

    /// The instance recovers: reset, a short run, finite outputs.
    fn still_works(&mut self) {
        let c = self.c;
        unsafe {
            assert_eq!(status_of(fmi2Reset(c)), Status::Ok);
            self.small();
            assert_eq!(
                status_of(fmi2SetupExperiment(
                    c, FMI2_FALSE, 0.0, 0.0, FMI2_TRUE, 0.01
                )),
                Status::Ok
            );
            assert_eq!(status_of(fmi2EnterInitializationMode(c)), Status::Ok);
            assert_eq!(status_of(fmi2ExitInitializationMode(c)), Status::Ok);
            assert_eq!(status_of(fmi2DoStep(c, 0.0, 1e-5, FMI2_TRUE)), Status::Ok);
            let mut v = vec![f64::NAN; self.outputs.len()];
            let st = fmi2GetReal(c, self.outputs.as_ptr(), v.len(), v.as_mut_ptr());
            assert_eq!(status_of(st), Status::Ok);
            assert!(v.iter().all(|x| x.is_finite()));
        }
    }
}

impl Drop for Harness {
    fn drop(&mut self) {
        unsafe {
            for s in &mut self.slots {
                if !s.state.is_null() {
                    fmi2FreeFMUstate(self.c, &mut s.state);
                }
            }
            fmi2FreeInstance(self.c);
        }
    }
}

#[test]
fn random_call_sequences_answer_what_the_standard_allows() {
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
        let mut h = Harness::new();
        for call in chunks.iter().flatten() {
            h.run(call);
        }
        h.still_works();
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    TALLY.with(|t| {
        let t = t.borrow();
        eprintln!("{t:?}");
        for (what, n) in [
            ("completed steps", t.steps_ok),
            ("discarded steps", t.steps_discarded),
            ("refused steps", t.steps_refused),
            ("states set after a discard", t.resumed_after_discard),
            ("calls out of sequence", t.refused_out_of_sequence),
        ] {
            assert!(n >= 20, "only {n} {what}: {t:?}");
        }
    });
}
