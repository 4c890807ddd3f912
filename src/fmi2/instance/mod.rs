//! One FMU instance: the FMI 2.0 Co-Simulation state machine over a [`Simulation`].
//!
//! This is safe Rust with no C types except [`Status`]: `exports.rs` turns pointers into slices
//! and strings and calls the methods here, so everything below can be unit-tested in-process.
//!
//! Every public method checks the instance's [`Phase`] against the mask of phases in which the
//! call is allowed (FMI 2.0 section 4.2.4, the Co-Simulation state machine, with the masks of the
//! Reference-FMUs' `fmi2Functions.c`). A call that answers `fmi2Error` - an illegal call
//! sequence, a refused value, a failed initialization - logs why and moves the instance to
//! [`Phase::Error`], the standard's *error* state, which remembers the call and the reason that
//! put it there for the messages of later calls: from there only the getters,
//! `fmi2GetFMUstate`/`fmi2SetFMUstate`, `fmi2Reset` and `fmi2FreeInstance` are accepted (FMI 2.0
//! section 2.1.3, `fmi2Error`: "the simulation cannot be continued with this FMU instance";
//! `fmi2Reset` or `fmi2SetFMUstate` recover it).
//!
//! Every call is bounded: `fmi2DoStep` runs within the step budget `max_steps_per_do_step` (and
//! `max_seconds_per_do_step`), and a stop time or a communication step whose estimated step
//! count breaks the run-length rule of [`crate::budget`] is refused before any work.

mod api;
mod state;
mod step;
#[cfg(test)]
mod tests;
mod variables;

pub use api::Api;
pub use state::Snapshot;
pub use variables::IntKind;

/// Value reference of the independent variable `time`, which FMI 3.0 declares and FMI 2.0 does
/// not (`crate::fmi3`'s modelDescription writes it; the core answers reads of it under
/// [`Api::Fmi3`]).
pub const TIME_VR: u32 = 0;

use super::model_description::{guid, DEFAULT_STOP_TIME, LOG_CATEGORIES};
use super::types::Status;
use crate::budget::{Budget, RunLength};
use crate::scene::{Outputs, SceneConfig, OUTPUTS};
use crate::simulation::{SimError, Simulation};
use serde::{Deserialize, Serialize};
use std::time::Duration;

/// Where an instance is in the Co-Simulation state machine (FMI 2.0 figure in section 4.2.4).
/// `StepInProgress` and `StepCanceled` do not exist here because `fmi2DoStep` is synchronous.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Phase {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    /// After `fmi2Terminate`.
    Terminated,
    /// The standard's error state, after any `fmi2Error` (FMI 2.0 section 2.1.3).
    Error,
}

impl Phase {
    const ALL: [Phase; 6] = [
        Phase::Instantiated,
        Phase::InitializationMode,
        Phase::StepComplete,
        Phase::StepFailed,
        Phase::Terminated,
        Phase::Error,
    ];

    fn bit(self) -> u8 {
        1 << (self as u8)
    }

    fn name(self) -> &'static str {
        match self {
            Phase::Instantiated => "Instantiated",
            Phase::InitializationMode => "InitializationMode",
            Phase::StepComplete => "StepComplete",
            Phase::StepFailed => "StepFailed",
            Phase::Terminated => "Terminated",
            Phase::Error => "Error",
        }
    }
}

/// Allowed-phase masks per function (Reference-FMUs `MASK_fmi2*`, restricted to the phases a
/// synchronous Co-Simulation slave can be in).
mod mask {
    use super::Phase::*;
    const fn b(p: super::Phase) -> u8 {
        1 << (p as u8)
    }
    pub const ANY: u8 = b(Instantiated)
        | b(InitializationMode)
        | b(StepComplete)
        | b(StepFailed)
        | b(Terminated)
        | b(Error);
    pub const SETUP: u8 = b(Instantiated);
    pub const EXIT_INIT: u8 = b(InitializationMode);
    pub const TERMINATE: u8 = b(StepComplete) | b(StepFailed);
    pub const GET: u8 =
        b(InitializationMode) | b(StepComplete) | b(StepFailed) | b(Terminated) | b(Error);
    /// Every parameter has variability "fixed": settable only before the end of initialization
    /// (FMI 2.0 section 2.2.7, table of `fmi2SetXXX` per causality and variability).
    pub const SET: u8 = b(Instantiated) | b(InitializationMode);
    /// `fmi2SetReal`/`fmi2SetInteger`: as [`SET`], and inputs also after a completed step
    /// (FMI 2.0 section 4.2.4); a fixed parameter is refused there value by value.
    pub const SET_OR_INPUT: u8 = SET | b(StepComplete);
    pub const DO_STEP: u8 = b(StepComplete);
    pub const STATUS: u8 = b(StepComplete) | b(StepFailed) | b(Terminated) | b(Error);
    pub const NEVER: u8 = 0;
}

/// The log categories of `modelDescription.xml`, in [`LOG_CATEGORIES`] order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    Events = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    /// The per-call trace; enabling `logAll` also enables every other category.
    All = 4,
}

impl Category {
    pub fn name(self) -> &'static str {
        LOG_CATEGORIES[self as usize].0
    }
}

/// Where log messages go: `(status, category, message)`. In the cdylib this calls the
/// importer's C logger; in tests it records the messages.
pub type LogSink = Box<dyn Fn(Status, &str, &str)>;

/// Why a call failed: the status it answers and the message logged.
enum Fail {
    Discard(String),
    Error(String),
}

type Answer<T = Status> = Result<T, Fail>;

fn error<T>(msg: impl Into<String>) -> Answer<T> {
    Err(Fail::Error(msg.into()))
}

/// One FMU instance.
pub struct Instance {
    name: String,
    /// The C API the instance was created through: the words of its messages.
    api: Api,
    sink: LogSink,
    /// Enabled log categories, indexed by [`Category`].
    enabled: [bool; 5],
    phase: Phase,
    cfg: SceneConfig,
    /// Built at `fmi2ExitInitializationMode`.
    sim: Option<Simulation>,
    /// Built on demand when outputs are read before the simulation exists (initialization
    /// mode); dropped when a parameter changes, reused by `fmi2ExitInitializationMode`.
    preview: Option<Simulation>,
    /// Outputs at the last communication point; never NaN.
    outputs: Outputs,
    start_time: f64,
    stop_time: Option<f64>,
    /// The last communication point (FMU time; the simulation's own clock starts at 0 at
    /// `start_time`).
    t_comm: f64,
    last_successful_time: f64,
    /// Set after a breakdown: the slave cannot go on (`fmi2Terminated` status).
    wants_to_terminate: bool,
    /// In [`Phase::StepFailed`]: whether the simulation holds the last good state, at
    /// `last_successful_time`, so that an FMU state taken now continues from there (see
    /// [`Instance::get_state`]).
    resumable: bool,
    /// The scheme's first stable time step, from a one-step probe at
    /// `fmi2ExitInitializationMode`, for the run-length rule before the first step.
    first_dt: Option<f64>,
    /// In [`Phase::Error`]: the call that answered `fmi2Error` and why.
    error_cause: Option<String>,
}

impl Instance {
    /// A new instance in phase `Instantiated` with the default parameters. With `logging_on`
    /// every category is enabled; without it, only errors and discards are reported, because a
    /// failed call that does not say why is useless (FMI 2.0 section 2.1.3 expects the logger
    /// to have shown the message of an `fmi2Error`).
    pub fn new(name: &str, logging_on: bool, sink: LogSink) -> Instance {
        let mut enabled = [logging_on; 5];
        enabled[Category::Error as usize] = true;
        enabled[Category::Discard as usize] = true;
        Instance {
            name: name.to_string(),
            api: Api::Fmi2,
            sink,
            enabled,
            phase: Phase::Instantiated,
            cfg: SceneConfig::default(),
            sim: None,
            preview: None,
            outputs: Outputs::default(),
            start_time: 0.0,
            stop_time: None,
            t_comm: 0.0,
            last_successful_time: 0.0,
            wants_to_terminate: false,
            resumable: false,
            first_dt: None,
            error_cause: None,
        }
    }

    /// The same instance answering to `api`: its messages name that version's calls.
    pub fn with_api(mut self, api: Api) -> Instance {
        self.api = api;
        self
    }

    pub fn name(&self) -> &str {
        &self.name
    }
    /// The end of the last completed communication step (`fmi2LastSuccessfulTime`, the
    /// `lastSuccessfulTime` out-argument of `fmi3DoStep`).
    pub fn last_successful_time(&self) -> f64 {
        self.last_successful_time
    }
    /// Whether the slave cannot go on (`fmi2Terminated`, the `terminateSimulation`
    /// out-argument of `fmi3DoStep`).
    pub fn wants_to_terminate(&self) -> bool {
        self.wants_to_terminate
    }
    pub fn phase(&self) -> Phase {
        self.phase
    }
    pub fn config(&self) -> &SceneConfig {
        &self.cfg
    }
    /// In [`Phase::Error`]: the call that answered `fmi2Error` first, and why.
    pub fn error_cause(&self) -> Option<&str> {
        self.error_cause.as_deref()
    }
    /// After a discarded `fmi2DoStep`: whether the simulation holds the last good state, which
    /// `fmi2GetFMUstate` then saves as a completed step (see [`Instance::get_state`]).
    pub fn resumable(&self) -> bool {
        self.phase == Phase::StepFailed && self.resumable
    }

    /// Log `message` under `category` if that category is enabled.
    pub fn log(&self, category: Category, status: Status, message: &str) {
        if self.enabled[category as usize] {
            (self.sink)(status, category.name(), &self.api.wording(message));
        }
    }

    fn trace(&self, func: &str, args: impl FnOnce() -> String) {
        if self.enabled[Category::All as usize] {
            self.log(Category::All, Status::Ok, &format!("{func}({})", args()));
        }
    }

    /// Log a failure and apply its consequence for the state machine.
    fn fail(&mut self, func: &str, f: Fail) -> Status {
        match f {
            Fail::Discard(m) => {
                self.log(Category::Discard, Status::Discard, &format!("{func}: {m}"));
                Status::Discard
            }
            Fail::Error(m) => {
                let suffix = if self.phase == Phase::Error {
                    ""
                } else {
                    " [the instance is now in the Error state; fmi2Reset, fmi2SetFMUstate or fmi2FreeInstance continue]"
                };
                self.log(
                    Category::Error,
                    Status::Error,
                    &format!("{func}: {m}{suffix}"),
                );
                if self.phase != Phase::Error {
                    self.error_cause = Some(format!("{func} returned fmi2Error: {m}"));
                }
                self.phase = Phase::Error;
                Status::Error
            }
        }
    }

    /// Report a failure of the calling layer (a null pointer, a caught panic) as `fmi2Error`.
    pub fn fail_error(&mut self, func: &str, message: String) -> Status {
        self.fail(func, Fail::Error(message))
    }

    /// The common frame of every call: trace, phase check, body, failure handling.
    fn call(
        &mut self,
        func: &'static str,
        allowed: u8,
        args: impl FnOnce() -> String,
        body: impl FnOnce(&mut Self) -> Answer,
    ) -> Status {
        self.trace(func, args);
        if self.phase.bit() & allowed == 0 {
            let msg = illegal_sequence(func, allowed, self.phase, self.error_cause.as_deref());
            return self.fail(func, Fail::Error(msg));
        }
        match body(self) {
            Ok(s) => s,
            Err(f) => self.fail(func, f),
        }
    }

    /// `fmi2SetDebugLogging` (FMI 2.0 section 2.1.5): with no categories, switch all on or off;
    /// with categories, switch exactly those on or off and leave the others as they are.
    /// `logAll` stands for every category. An unknown category is refused.
    pub fn set_debug_logging(&mut self, logging_on: bool, categories: &[String]) -> Status {
        self.call(
            "fmi2SetDebugLogging",
            mask::ANY,
            || format!("loggingOn={logging_on}, categories={categories:?}"),
            |s| {
                let mut idx = Vec::new();
                for c in categories {
                    match LOG_CATEGORIES.iter().position(|(n, _)| n == c) {
                        Some(i) if i == Category::All as usize => idx.extend(0..5),
                        Some(i) => idx.push(i),
                        None => {
                            let names: Vec<&str> = LOG_CATEGORIES.iter().map(|c| c.0).collect();
                            return error(format!(
                                "unknown log category '{c}'; the categories are {}",
                                names.join(", ")
                            ));
                        }
                    }
                }
                if categories.is_empty() {
                    idx.extend(0..5);
                }
                for i in idx {
                    s.enabled[i] = logging_on;
                }
                Ok(Status::Ok)
            },
        )
    }

    /// `fmi2SetupExperiment` (FMI 2.0 section 2.1.6). The tolerance is ignored: the scheme's
    /// time step is set by its own stability limits.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Status {
        self.call(
            "fmi2SetupExperiment",
            mask::SETUP,
            || format!("tolerance={tolerance:?}, startTime={start_time}, stopTime={stop_time:?}"),
            |s| {
                if !start_time.is_finite() {
                    return error(format!("startTime = {start_time} is not a finite number"));
                }
                if let Some(stop) = stop_time {
                    if !(stop.is_finite() && stop >= start_time) {
                        return error(format!(
                            "stopTime = {stop} must be a finite number >= startTime = {start_time}"
                        ));
                    }
                }
                s.start_time = start_time;
                s.stop_time = stop_time;
                s.t_comm = start_time;
                s.last_successful_time = start_time;
                Ok(Status::Ok)
            },
        )
    }

    pub fn enter_initialization_mode(&mut self) -> Status {
        self.call(
            "fmi2EnterInitializationMode",
            mask::SETUP,
            String::new,
            |s| {
                s.phase = Phase::InitializationMode;
                Ok(Status::Ok)
            },
        )
    }

    /// Build the simulation from the parameters: the cross-parameter checks of
    /// [`SceneConfig::validate`] happen here, and a refusal answers `fmi2Error`.
    pub fn exit_initialization_mode(&mut self) -> Status {
        self.call(
            "fmi2ExitInitializationMode",
            mask::EXIT_INIT,
            String::new,
            |s| {
                let sim = match s.preview.take() {
                    Some(p) => p,
                    None => Simulation::new(s.cfg.clone()).map_err(|e| Fail::Error(e.to_string()))?,
                };
                let outputs = sim.outputs();
                if let Some(bad) = non_finite(&outputs) {
                    return error(format!("the initial state has a non-finite output '{bad}'"));
                }
                let n = sim.particle_count();
                s.first_dt = first_time_step(&s.cfg)?;
                if let (Some(stop), Some(dt)) = (s.stop_time, s.first_dt) {
                    let what = format!(
                        "stopTime - startTime = {stop} s - {} s = {} s",
                        s.start_time,
                        stop - s.start_time
                    );
                    if let Some(refusal) = RunLength::at_step(stop - s.start_time, dt, n).too_long(&what) {
                        return error(format!(
                            "{refusal}. Check the stopTime given to fmi2SetupExperiment (the default experiment stops at {DEFAULT_STOP_TIME} s)"
                        ));
                    }
                }
                s.outputs = outputs;
                s.sim = Some(sim);
                s.t_comm = s.start_time;
                s.last_successful_time = s.start_time;
                s.wants_to_terminate = false;
                s.resumable = false;
                s.phase = Phase::StepComplete;
                s.log(
                    Category::Events,
                    Status::Ok,
                    &format!(
                        "initialized: scene {}, scheme {}, rheology {}, {n} fluid particles, dx = {} m",
                        s.cfg.scene,
                        s.cfg.scheme,
                        s.cfg.fluid.rheology,
                        s.cfg.dx()
                    ),
                );
                if let Some(w) = s.cfg.warning() {
                    s.log(Category::Warning, Status::Warning, w);
                }
                Ok(Status::Ok)
            },
        )
    }

    pub fn terminate(&mut self) -> Status {
        self.call("fmi2Terminate", mask::TERMINATE, String::new, |s| {
            s.phase = Phase::Terminated;
            s.log(
                Category::Events,
                Status::Ok,
                &format!("terminated at t = {} s", s.t_comm),
            );
            Ok(Status::Ok)
        })
    }

    /// `fmi2Reset` (FMI 2.0 section 2.1.6): back to the state right after `fmi2Instantiate`,
    /// default parameters included. The debug-logging settings are kept.
    pub fn reset(&mut self) -> Status {
        self.call("fmi2Reset", mask::ANY, String::new, |s| {
            s.phase = Phase::Instantiated;
            s.cfg = SceneConfig::default();
            s.sim = None;
            s.preview = None;
            s.outputs = Outputs::default();
            s.start_time = 0.0;
            s.stop_time = None;
            s.t_comm = 0.0;
            s.last_successful_time = 0.0;
            s.wants_to_terminate = false;
            s.resumable = false;
            s.first_dt = None;
            s.error_cause = None;
            s.log(
                Category::Events,
                Status::Ok,
                "reset to the default parameters",
            );
            Ok(Status::Ok)
        })
    }

    /// `fmi2GetStatus`: only meaningful after `fmi2Pending`, which this synchronous slave never
    /// answers (FMI 2.0 section 4.2.3), so it is discarded with an explanation.
    pub fn get_status(&mut self, func: &'static str, kind: u32) -> Status {
        self.call(
            func,
            mask::STATUS,
            || format!("kind={kind}"),
            |_| {
                Err(Fail::Discard(format!(
                    "status kind {kind} is not provided: fmi2DoStep is synchronous and never answers fmi2Pending"
                )))
            },
        )
    }

    /// `fmi2GetRealStatus(fmi2LastSuccessfulTime)`.
    pub fn get_real_status(&mut self, kind: u32, value: &mut f64) -> Status {
        self.call(
            "fmi2GetRealStatus",
            mask::STATUS,
            || format!("kind={kind}"),
            |s| {
                if kind != super::types::FMI2_LAST_SUCCESSFUL_TIME {
                    return Err(Fail::Discard(format!(
                        "status kind {kind} has no Real value; use fmi2LastSuccessfulTime (2)"
                    )));
                }
                *value = s.last_successful_time;
                Ok(Status::Ok)
            },
        )
    }

    /// `fmi2GetBooleanStatus(fmi2Terminated)`: true once the slave cannot go on.
    pub fn get_boolean_status(&mut self, kind: u32, value: &mut bool) -> Status {
        self.call(
            "fmi2GetBooleanStatus",
            mask::STATUS,
            || format!("kind={kind}"),
            |s| {
                if kind != super::types::FMI2_TERMINATED {
                    return Err(Fail::Discard(format!(
                        "status kind {kind} has no Boolean value; use fmi2Terminated (3)"
                    )));
                }
                *value = s.wants_to_terminate;
                Ok(Status::Ok)
            },
        )
    }

    /// A function this FMU does not provide (Model Exchange, directional derivatives, input
    /// derivatives): always `fmi2Error`, with the reason.
    pub fn unsupported(&mut self, func: &'static str, reason: &str) -> Status {
        let reason = reason.to_string();
        self.call(func, mask::ANY, String::new, move |_| error(reason))
    }
}

/// The first output that is NaN or infinite.
fn non_finite(o: &Outputs) -> Option<&'static str> {
    o.values()
        .iter()
        .zip(OUTPUTS.iter())
        .find(|(v, _)| !v.is_finite())
        .map(|(_, s)| s.name)
}

/// "fmi2DoStep is not allowed in state Instantiated (allowed in: StepComplete)" with a hint of
/// what to call first.
fn illegal_sequence(func: &str, allowed: u8, phase: Phase, cause: Option<&str>) -> String {
    let names: Vec<&str> = Phase::ALL
        .iter()
        .filter(|p| p.bit() & allowed != 0)
        .map(|p| p.name())
        .collect();
    let hint = match (func, phase) {
        ("fmi2DoStep", Phase::Instantiated | Phase::InitializationMode) => {
            "; call fmi2EnterInitializationMode and fmi2ExitInitializationMode first"
        }
        ("fmi2SetReal" | "fmi2SetInteger" | "fmi2SetBoolean" | "fmi2SetString", _) => {
            "; every parameter has variability \"fixed\": set it before fmi2ExitInitializationMode, or call fmi2Reset (inputs can also be set after a completed step)"
        }
        ("fmi2GetReal" | "fmi2GetInteger", Phase::Instantiated) => {
            "; call fmi2EnterInitializationMode first"
        }
        _ => "",
    };
    let why = match (phase, cause) {
        (Phase::Error, Some(c)) => format!(
            " (the instance is in the Error state since {c}; fmi2Reset or fmi2SetFMUstate continue)"
        ),
        _ => String::new(),
    };
    if allowed == mask::NEVER {
        format!("{func} is never allowed by this FMU")
    } else {
        format!(
            "illegal call sequence: {func} is not allowed in state {}{why} (allowed in: {}){hint}",
            phase.name(),
            names.join(", ")
        )
    }
}

/// The scheme's first stable time step for `cfg`: one step of a separate simulation, so that the
/// instance's own trajectory is not touched (the CLI takes this step on its run, whose outputs
/// are never read at t = 0 afterwards).
/// `None` if that step breaks down: the run's own first `fmi2DoStep` then reports it.
fn first_time_step(cfg: &SceneConfig) -> Answer<Option<f64>> {
    let mut probe = Simulation::new(cfg.clone()).map_err(|e| Fail::Error(e.to_string()))?;
    let stepped = probe.advance_to(f64::MIN_POSITIVE).is_ok();
    Ok(Some(probe.last_dt()).filter(|&dt| stepped && dt > 0.0))
}
