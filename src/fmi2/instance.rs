//! One FMU instance: the FMI 2.0 Co-Simulation state machine over a [`Simulation`].
//!
//! This is safe Rust with no C types except [`Status`]: `exports.rs` turns pointers into slices
//! and strings and calls the methods here, so everything below can be unit-tested in-process.
//!
//! Every public method checks the instance's [`Phase`] against the mask of phases in which the
//! call is allowed (FMI 2.0 section 4.2.4, the Co-Simulation state machine, with the masks of the
//! Reference-FMUs' `fmi2Functions.c`). A call that answers `fmi2Error` - an illegal call
//! sequence, a refused value, a failed initialization - logs why and moves the instance to
//! [`Phase::Terminated`], which stands for the standard's *error* state: from there only the
//! getters, `fmi2GetFMUstate`/`fmi2SetFMUstate`, `fmi2Reset` and `fmi2FreeInstance` are accepted
//! (FMI 2.0 section 2.1.3, `fmi2Error`: "the simulation cannot be continued with this FMU
//! instance"; `fmi2Reset` or `fmi2SetFMUstate` recover it).

use super::model_description::{guid, LOG_CATEGORIES};
use super::types::Status;
use crate::config::{Kind, ParamSpec, Value};
use crate::scene::{
    input_rows, name_variable_by_vr, param_by_vr, Outputs, SceneConfig, NAME_SUFFIX, OUTPUTS,
};
use crate::simulation::{SimError, Simulation};
use serde::{Deserialize, Serialize};

/// Where an instance is in the Co-Simulation state machine (FMI 2.0 figure in section 4.2.4).
/// `StepInProgress` and `StepCanceled` do not exist here because `fmi2DoStep` is synchronous.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Phase {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    /// After `fmi2Terminate`, and the error state after any `fmi2Error`.
    Terminated,
}

impl Phase {
    const ALL: [Phase; 5] = [
        Phase::Instantiated,
        Phase::InitializationMode,
        Phase::StepComplete,
        Phase::StepFailed,
        Phase::Terminated,
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
    pub const ANY: u8 =
        b(Instantiated) | b(InitializationMode) | b(StepComplete) | b(StepFailed) | b(Terminated);
    pub const SETUP: u8 = b(Instantiated);
    pub const EXIT_INIT: u8 = b(InitializationMode);
    pub const TERMINATE: u8 = b(StepComplete) | b(StepFailed);
    pub const GET: u8 = b(InitializationMode) | b(StepComplete) | b(StepFailed) | b(Terminated);
    /// Every parameter has variability "fixed": settable only before the end of initialization
    /// (FMI 2.0 section 2.2.7, table of `fmi2SetXXX` per causality and variability).
    pub const SET: u8 = b(Instantiated) | b(InitializationMode);
    /// `fmi2SetReal`/`fmi2SetInteger`: as [`SET`], and inputs also after a completed step
    /// (FMI 2.0 section 4.2.4); a fixed parameter is refused there value by value.
    pub const SET_OR_INPUT: u8 = SET | b(StepComplete);
    pub const DO_STEP: u8 = b(StepComplete);
    pub const STATUS: u8 = b(StepComplete) | b(StepFailed) | b(Terminated);
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

/// A variable of the interface, found by value reference.
enum Var {
    Param(&'static ParamSpec),
    /// The String twin of an Enumeration parameter ([`crate::config::name_variables`]).
    Name(&'static ParamSpec),
    Output(usize),
}

fn lookup(vr: u32) -> Option<Var> {
    if let Some(p) = param_by_vr(vr) {
        return Some(Var::Param(p));
    }
    if let Some(p) = name_variable_by_vr(vr) {
        return Some(Var::Name(p));
    }
    OUTPUTS
        .iter()
        .position(|o| o.value_reference == vr)
        .map(Var::Output)
}

/// The refusal of a set call on an output.
fn output_cannot_be_set(vr: u32, i: usize) -> Fail {
    Fail::Error(format!(
        "'{}' (valueReference {vr}) is an output and cannot be set",
        OUTPUTS[i].name
    ))
}

fn unknown_vr(vr: u32) -> Fail {
    Fail::Error(format!(
        "unknown valueReference {vr}: no variable of modelDescription.xml has it"
    ))
}

/// The FMI type name of a variable, for "use fmi2GetInteger instead" messages.
fn type_of(v: &Var) -> &'static str {
    match v {
        Var::Output(_) => "Real",
        Var::Name(_) => "String",
        Var::Param(p) => match p.kind {
            Kind::Real { .. } => "Real",
            Kind::Integer { .. } => "Integer",
            Kind::Enumeration { .. } => "Enumeration",
        },
    }
}

fn name_of(v: &Var) -> String {
    match v {
        Var::Output(i) => OUTPUTS[*i].name.to_string(),
        Var::Param(p) => p.name.to_string(),
        Var::Name(p) => format!("{}{NAME_SUFFIX}", p.name),
    }
}

/// "'drop_width' (valueReference 101) is a Real variable; use fmi2GetReal".
fn wrong_type(vr: u32, v: &Var, verb: &str) -> Fail {
    let ty = type_of(v);
    let fun = if ty == "Enumeration" { "Integer" } else { ty };
    Fail::Error(format!(
        "'{}' (valueReference {vr}) is an {ty} variable; use fmi2{verb}{fun}",
        name_of(v)
    ))
}

/// Everything of an instance that an FMU state holds (FMI 2.0 section 2.1.8): no pointers, so a
/// serialized state restores in another process.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Snapshot {
    /// The interface the state belongs to; a state of another interface is refused.
    guid: String,
    phase: Phase,
    cfg: SceneConfig,
    /// [`Simulation::save_state`] once initialized.
    sim: Option<Vec<u8>>,
    start_time: f64,
    stop_time: Option<f64>,
    t_comm: f64,
    last_successful_time: f64,
    wants_to_terminate: bool,
    outputs: Outputs,
}

impl Snapshot {
    /// The bytes of `fmi2SerializeFMUstate`: a tag and a bincode body.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = SNAPSHOT_TAG.to_vec();
        out.extend(bincode::serialize(self).expect("snapshot serialises"));
        out
    }

    /// Inverse of [`Snapshot::to_bytes`]; the message says what is wrong with the bytes.
    pub fn from_bytes(bytes: &[u8]) -> Result<Snapshot, String> {
        let body = bytes.strip_prefix(SNAPSHOT_TAG).ok_or_else(|| {
            format!(
                "the {} bytes are not a serialized ViscoSPH FMU state",
                bytes.len()
            )
        })?;
        let snap: Snapshot =
            bincode::deserialize(body).map_err(|e| format!("corrupt serialized FMU state: {e}"))?;
        let ours = guid();
        if snap.guid != ours {
            return Err(format!(
                "the serialized FMU state belongs to the interface {} but this FMU is {ours}",
                snap.guid
            ));
        }
        Ok(snap)
    }
}

const SNAPSHOT_TAG: &[u8] = b"ViscoSPH FMU state v1\n";

/// One FMU instance.
pub struct Instance {
    name: String,
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
        }
    }

    pub fn name(&self) -> &str {
        &self.name
    }
    pub fn phase(&self) -> Phase {
        self.phase
    }
    pub fn config(&self) -> &SceneConfig {
        &self.cfg
    }

    /// Log `message` under `category` if that category is enabled.
    pub fn log(&self, category: Category, status: Status, message: &str) {
        if self.enabled[category as usize] {
            (self.sink)(status, category.name(), message);
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
                let suffix = if self.phase == Phase::Terminated {
                    ""
                } else {
                    " [the instance is now in the error state; fmi2Reset, fmi2SetFMUstate or fmi2FreeInstance continue]"
                };
                self.log(
                    Category::Error,
                    Status::Error,
                    &format!("{func}: {m}{suffix}"),
                );
                self.phase = Phase::Terminated;
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
            let msg = illegal_sequence(func, allowed, self.phase);
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
                let n = sim.state().fluid.len();
                s.outputs = outputs;
                s.sim = Some(sim);
                s.t_comm = s.start_time;
                s.last_successful_time = s.start_time;
                s.wants_to_terminate = false;
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
            s.log(
                Category::Events,
                Status::Ok,
                "reset to the default parameters",
            );
            Ok(Status::Ok)
        })
    }

    /// The outputs now: those of the last communication point, or, before the simulation
    /// exists, those of the initial state built from the current parameters.
    fn current_outputs(&mut self) -> Answer<Outputs> {
        if self.sim.is_some() {
            return Ok(self.outputs);
        }
        if self.preview.is_none() {
            let sim = Simulation::new(self.cfg.clone()).map_err(|e| {
                Fail::Error(format!(
                    "the outputs cannot be computed from the current parameters: {e}"
                ))
            })?;
            self.preview = Some(sim);
        }
        Ok(self.preview.as_ref().expect("just built").outputs())
    }

    pub fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Status {
        self.call(
            "fmi2GetReal",
            mask::GET,
            || format!("vr={vrs:?}"),
            |s| {
                let mut outputs: Option<Outputs> = None;
                for (k, &vr) in vrs.iter().enumerate() {
                    let var = lookup(vr).ok_or_else(|| unknown_vr(vr))?;
                    values[k] = match &var {
                        Var::Output(i) => {
                            if outputs.is_none() {
                                outputs = Some(s.current_outputs()?);
                            }
                            outputs.expect("set above").values()[*i]
                        }
                        Var::Param(p) => match (p.kind, s.cfg.get(p.name)) {
                            (Kind::Real { .. }, Ok(Value::Real(x))) => x,
                            _ => return Err(wrong_type(vr, &var, "Get")),
                        },
                        Var::Name(_) => return Err(wrong_type(vr, &var, "Get")),
                    };
                }
                Ok(Status::Ok)
            },
        )
    }

    pub fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Status {
        self.call(
            "fmi2GetInteger",
            mask::GET,
            || format!("vr={vrs:?}"),
            |s| {
                for (k, &vr) in vrs.iter().enumerate() {
                    let var = lookup(vr).ok_or_else(|| unknown_vr(vr))?;
                    values[k] = match &var {
                        Var::Param(p) => match (p.kind, s.cfg.get(p.name)) {
                            (
                                Kind::Integer { .. } | Kind::Enumeration { .. },
                                Ok(Value::Integer(i)),
                            ) => i32::try_from(i).expect("table ranges fit in fmi2Integer"),
                            _ => return Err(wrong_type(vr, &var, "Get")),
                        },
                        Var::Output(_) | Var::Name(_) => return Err(wrong_type(vr, &var, "Get")),
                    };
                }
                Ok(Status::Ok)
            },
        )
    }

    /// `fmi2GetString`: the item names of the String twins of the Enumeration parameters, as
    /// `'static` strings (the table's), so the pointers handed to the importer stay valid.
    pub fn get_string(&mut self, vrs: &[u32], values: &mut [&'static str]) -> Status {
        self.call(
            "fmi2GetString",
            mask::GET,
            || format!("vr={vrs:?}"),
            |s| {
                for (k, &vr) in vrs.iter().enumerate() {
                    let var = lookup(vr).ok_or_else(|| unknown_vr(vr))?;
                    values[k] = match &var {
                        Var::Name(p) => s
                            .cfg
                            .item_name(p.name)
                            .map_err(|e| Fail::Error(e.to_string()))?,
                        _ => return Err(wrong_type(vr, &var, "Get")),
                    };
                }
                Ok(Status::Ok)
            },
        )
    }

    /// `fmi2SetString`: a String twin takes an item name of its Enumeration (refused with the
    /// list of names otherwise). All or nothing, like [`Instance::set_real`].
    pub fn set_string(&mut self, vrs: &[u32], values: &[Option<String>]) -> Status {
        self.call(
            "fmi2SetString",
            mask::SET,
            || format!("vr={vrs:?}, value={values:?}"),
            |s| {
                let mut cfg = s.cfg.clone();
                for (&vr, x) in vrs.iter().zip(values) {
                    let var = lookup(vr).ok_or_else(|| unknown_vr(vr))?;
                    match &var {
                        Var::Name(p) => {
                            let Some(text) = x else {
                                return error(format!(
                                    "value[] holds NULL for '{}' (valueReference {vr})",
                                    name_of(&var)
                                ));
                            };
                            cfg.set(p.name, Value::Text(text.clone()))
                                .map_err(|e| Fail::Error(format!("'{}': {e}", name_of(&var))))?
                        }
                        Var::Output(i) => return Err(output_cannot_be_set(vr, *i)),
                        _ => return Err(wrong_type(vr, &var, "Set")),
                    }
                }
                s.cfg = cfg;
                s.preview = None;
                Ok(Status::Ok)
            },
        )
    }

    /// `fmi2GetBoolean`: the interface has no such variables, so any value reference is
    /// refused.
    pub fn get_none(&mut self, func: &'static str, vrs: &[u32]) -> Status {
        self.call(
            func,
            mask::GET,
            || format!("vr={vrs:?}"),
            |_| no_variables_of_type(vrs, "Get"),
        )
    }

    /// `fmi2SetBoolean`: see [`Instance::get_none`].
    pub fn set_none(&mut self, func: &'static str, vrs: &[u32]) -> Status {
        self.call(
            func,
            mask::SET,
            || format!("vr={vrs:?}"),
            |_| no_variables_of_type(vrs, "Set"),
        )
    }

    /// `fmi2SetReal`: every value goes through [`SceneConfig::set`], whose message names the
    /// variable, the value and the allowed range. All or nothing: a refused value leaves the
    /// parameters as they were before the call.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        self.set_parameters(
            "fmi2SetReal",
            vrs,
            values,
            |k| matches!(k, Kind::Real { .. }),
            Value::Real,
        )
    }

    /// `fmi2SetInteger`, for Integer and Enumeration parameters (enumerations by their 1-based
    /// item index, FMI 2.0 section 2.2.3). Same checks as [`Instance::set_real`].
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Status {
        self.set_parameters(
            "fmi2SetInteger",
            vrs,
            values,
            |k| matches!(k, Kind::Integer { .. } | Kind::Enumeration { .. }),
            |i| Value::Integer(i64::from(i)),
        )
    }

    /// The body of `fmi2SetReal` and `fmi2SetInteger`: parameters whose kind `accepts` the
    /// call's type take `value(x)` through [`SceneConfig::set`], on a copy that replaces the
    /// configuration only when every value was accepted; outputs and other types are refused.
    fn set_parameters<T: Copy + std::fmt::Debug>(
        &mut self,
        func: &'static str,
        vrs: &[u32],
        values: &[T],
        accepts: impl Fn(&Kind) -> bool,
        value: impl Fn(T) -> Value,
    ) -> Status {
        self.call(
            func,
            mask::SET_OR_INPUT,
            || format!("vr={vrs:?}, value={values:?}"),
            |s| {
                let stepping = s.phase == Phase::StepComplete;
                let mut cfg = s.cfg.clone();
                for (&vr, &x) in vrs.iter().zip(values) {
                    let var = lookup(vr).ok_or_else(|| unknown_vr(vr))?;
                    match &var {
                        Var::Param(p) if stepping && !p.is_input() => {
                            return error(format!(
                                "'{}' (valueReference {vr}) is a parameter with variability \"fixed\": \
                                 after fmi2ExitInitializationMode only inputs ({}) can be set; call fmi2Reset to change it",
                                p.name,
                                input_rows().map(|p| p.name).collect::<Vec<_>>().join(", ")
                            ))
                        }
                        Var::Param(p) if accepts(&p.kind) => cfg
                            .set(p.name, value(x))
                            .map_err(|e| Fail::Error(e.to_string()))?,
                        Var::Output(i) => return Err(output_cannot_be_set(vr, *i)),
                        _ => return Err(wrong_type(vr, &var, "Set")),
                    }
                }
                if stepping {
                    // Inputs act from this communication point on (the simulation lands on it
                    // exactly, going back one internal step if it had passed it).
                    let sim = s.sim.as_mut().expect("a simulation exists in StepComplete");
                    sim.set_inputs(cfg.inputs())
                        .map_err(|e| Fail::Error(e.to_string()))?;
                }
                s.cfg = cfg;
                s.preview = None;
                Ok(Status::Ok)
            },
        )
    }

    /// `fmi2DoStep` (FMI 2.0 section 4.2.2): advance from `t` to exactly `t + h` with the
    /// scheme's own adaptive sub-steps, so the outputs at a communication point do not depend
    /// on the communication step size beyond the shortened last sub-step.
    ///
    /// A numerical breakdown answers `fmi2Discard`: the simulation stays at its last good
    /// sub-step, the outputs are those of that state, `fmi2LastSuccessfulTime` is its time, and
    /// `fmi2Terminated` becomes true because a smaller communication step would not help.
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        self.call(
            "fmi2DoStep",
            mask::DO_STEP,
            || format!("currentCommunicationPoint={t}, communicationStepSize={h}"),
            |s| {
                if !(h.is_finite() && h > 0.0) {
                    return error(format!("communicationStepSize = {h} must be > 0"));
                }
                let tol = 1e-9 * s.t_comm.abs().max(1.0);
                if !t.is_finite() || (t - s.t_comm).abs() > tol {
                    return error(format!(
                        "currentCommunicationPoint = {t} does not continue from the last communication point {} (tolerance {tol:e})",
                        s.t_comm
                    ));
                }
                let target = t + h;
                if let Some(stop) = s.stop_time {
                    if target > stop + 1e-9 * stop.abs().max(1.0) {
                        return error(format!(
                            "the step to t = {target} goes past stopTime = {stop} given to fmi2SetupExperiment"
                        ));
                    }
                }
                let start = s.start_time;
                let sim = s.sim.as_mut().expect("a simulation exists in StepComplete");
                match sim.advance_to(target - start) {
                    Ok(()) => {
                        let outputs = sim.outputs();
                        if let Some(bad) = non_finite(&outputs) {
                            s.phase = Phase::StepFailed;
                            s.wants_to_terminate = true;
                            return Err(Fail::Discard(format!(
                                "output '{bad}' became non-finite in the step from t = {t} s to {target} s; \
                                 the outputs keep their values at t = {t} s"
                            )));
                        }
                        s.outputs = outputs;
                        s.t_comm = target;
                        s.last_successful_time = target;
                        Ok(Status::Ok)
                    }
                    Err(e @ SimError::Breakdown { .. }) => {
                        let reached = start + sim.time();
                        let outputs = sim.outputs();
                        if non_finite(&outputs).is_none() {
                            s.outputs = outputs;
                            s.last_successful_time = reached;
                        }
                        s.phase = Phase::StepFailed;
                        s.wants_to_terminate = true;
                        Err(Fail::Discard(format!(
                            "{e}. The outputs hold the last good state, at t = {} s \
                             (fmi2LastSuccessfulTime); the slave cannot continue (fmi2Terminated)",
                            s.last_successful_time
                        )))
                    }
                    Err(e) => error(e.to_string()),
                }
            },
        )
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

    /// `fmi2GetFMUstate`: a snapshot of everything that evolves.
    pub fn get_state(&mut self, out: &mut Option<Snapshot>) -> Status {
        self.call("fmi2GetFMUstate", mask::ANY, String::new, |s| {
            *out = Some(Snapshot {
                guid: guid(),
                phase: s.phase,
                cfg: s.cfg.clone(),
                sim: s.sim.as_ref().map(|m| m.save_state()),
                start_time: s.start_time,
                stop_time: s.stop_time,
                t_comm: s.t_comm,
                last_successful_time: s.last_successful_time,
                wants_to_terminate: s.wants_to_terminate,
                outputs: s.outputs,
            });
            Ok(Status::Ok)
        })
    }

    /// `fmi2SetFMUstate`: restore a snapshot, phase included.
    pub fn set_state(&mut self, snap: &Snapshot) -> Status {
        self.call("fmi2SetFMUstate", mask::ANY, String::new, |s| {
            if snap.guid != guid() {
                return error(format!(
                    "the FMU state belongs to the interface {} but this FMU is {}",
                    snap.guid,
                    guid()
                ));
            }
            match (&snap.sim, s.sim.as_mut()) {
                (None, _) => s.sim = None,
                (Some(bytes), Some(sim)) => sim
                    .restore_state(bytes)
                    .map_err(|e| Fail::Error(e.to_string()))?,
                (Some(bytes), None) => {
                    let mut sim = Simulation::new(snap.cfg.clone())
                        .map_err(|e| Fail::Error(e.to_string()))?;
                    sim.restore_state(bytes)
                        .map_err(|e| Fail::Error(e.to_string()))?;
                    s.sim = Some(sim);
                }
            }
            s.phase = snap.phase;
            s.cfg = snap.cfg.clone();
            s.preview = None;
            s.start_time = snap.start_time;
            s.stop_time = snap.stop_time;
            s.t_comm = snap.t_comm;
            s.last_successful_time = snap.last_successful_time;
            s.wants_to_terminate = snap.wants_to_terminate;
            s.outputs = snap.outputs;
            s.log(
                Category::Events,
                Status::Ok,
                &format!(
                    "FMU state restored: t = {} s, phase {}",
                    s.t_comm,
                    s.phase.name()
                ),
            );
            Ok(Status::Ok)
        })
    }

    /// Check that an FMU-state call is allowed now (for the calls that only touch the
    /// snapshot itself: free, size, serialize, deserialize), and report `problem` if any.
    pub fn state_call(&mut self, func: &'static str, problem: Option<String>) -> Status {
        self.call(func, mask::ANY, String::new, move |_| match problem {
            Some(p) => error(p),
            None => Ok(Status::Ok),
        })
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

fn no_variables_of_type(vrs: &[u32], verb: &str) -> Answer {
    match vrs.first() {
        None => Ok(Status::Ok),
        Some(&vr) => match lookup(vr) {
            None => Err(unknown_vr(vr)),
            Some(v) => Err(wrong_type(vr, &v, verb)),
        },
    }
}

/// "fmi2DoStep is not allowed in state Instantiated (allowed in: StepComplete)" with a hint of
/// what to call first.
fn illegal_sequence(func: &str, allowed: u8, phase: Phase) -> String {
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
    if allowed == mask::NEVER {
        format!("{func} is never allowed by this FMU")
    } else {
        format!(
            "illegal call sequence: {func} is not allowed in state {} (allowed in: {}){hint}",
            phase.name(),
            names.join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;
    use std::rc::Rc;

    type Log = Rc<RefCell<Vec<(Status, String, String)>>>;

    fn instance(logging_on: bool) -> (Instance, Log) {
        let log: Log = Rc::new(RefCell::new(Vec::new()));
        let l = log.clone();
        let sink: LogSink = Box::new(move |st, cat, msg| {
            l.borrow_mut().push((st, cat.to_string(), msg.to_string()))
        });
        (Instance::new("test", logging_on, sink), log)
    }

    fn vr(name: &str) -> u32 {
        crate::scene::param_spec(name)
            .map(|p| p.value_reference)
            .or_else(|| {
                OUTPUTS
                    .iter()
                    .find(|o| o.name == name)
                    .map(|o| o.value_reference)
            })
            .unwrap()
    }

    #[test]
    fn string_twins_set_and_read_the_enumerations_all_or_nothing() {
        let (mut i, log) = instance(false);
        let twin = |name: &str| vr(name) + crate::scene::NAME_VR_OFFSET;
        assert_eq!(
            i.set_string(
                &[twin("rheology"), twin("scheme")],
                &[Some("giesekus".into()), Some("pdri".into())]
            ),
            Status::Ok
        );
        assert_eq!(
            i.config().fluid.rheology,
            crate::config::RheologyKind::Giesekus
        );
        assert_eq!(i.config().scheme, crate::scene::SchemeKind::Pdri);
        // a bad name in the second place leaves the first value unset too
        assert_eq!(
            i.set_string(
                &[twin("rheology"), twin("scene")],
                &[Some("cross".into()), Some("splash".into())]
            ),
            Status::Error
        );
        let msg = log.borrow().last().unwrap().2.clone();
        assert!(
            msg.contains("scene_name") && msg.contains("splash") && msg.contains("'drop'"),
            "{msg}"
        );
        assert_eq!(i.reset(), Status::Ok);
        assert_eq!(
            i.set_string(&[twin("rheology")], &[Some("ucm".into())]),
            Status::Ok
        );
        assert_eq!(
            i.set_string(&[twin("scheme")], &[None]),
            Status::Error,
            "NULL is refused"
        );
        i.reset();
        assert_eq!(i.enter_initialization_mode(), Status::Ok);
        let mut names = [""; 2];
        assert_eq!(
            i.get_string(&[twin("rheology"), twin("equation_of_state")], &mut names),
            Status::Ok
        );
        assert_eq!(
            names,
            ["oldroyd_b", "linear"],
            "reset restored the defaults"
        );
        // the Enumeration itself is not a String, nor the twin an Integer
        assert_eq!(
            i.get_string(&[vr("rheology")], &mut names[..1]),
            Status::Error
        );
        let mut ints = [0];
        assert_eq!(i.get_integer(&[twin("rheology")], &mut ints), Status::Error);
        let msg = log.borrow().last().unwrap().2.clone();
        assert!(
            msg.contains("rheology_name") && msg.contains("String"),
            "{msg}"
        );
    }

    #[test]
    fn do_step_before_initialization_is_refused_and_reset_recovers() {
        let (mut i, log) = instance(false);
        assert_eq!(i.do_step(0.0, 0.001), Status::Error);
        let last = log.borrow().last().unwrap().clone();
        assert_eq!(last.1, "logStatusError");
        assert!(
            last.2.contains("fmi2DoStep") && last.2.contains("Instantiated"),
            "{}",
            last.2
        );
        assert_eq!(i.phase(), Phase::Terminated);
        assert_eq!(i.set_real(&[vr("drop_diameter")], &[0.03]), Status::Error);
        assert_eq!(i.reset(), Status::Ok);
        assert_eq!(i.phase(), Phase::Instantiated);
        assert_eq!(i.set_real(&[vr("drop_diameter")], &[0.03]), Status::Ok);
    }

    #[test]
    fn bad_values_name_variable_value_and_range_and_change_nothing() {
        let (mut i, log) = instance(false);
        let st = i.set_real(
            &[vr("initial_drop_height"), vr("drop_diameter")],
            &[0.05, -0.01],
        );
        assert_eq!(st, Status::Error);
        let msg = log.borrow().last().unwrap().2.clone();
        assert!(
            msg.contains("drop_diameter") && msg.contains("-0.01") && msg.contains("(0, 10]"),
            "{msg}"
        );
        assert_eq!(
            i.config().drop.initial_drop_height,
            SceneConfig::default().drop.initial_drop_height
        );
        i.reset();
        assert_eq!(
            i.set_real(&[vr("plate_inclination")], &[90.0]),
            Status::Error
        );
        i.reset();
        assert_eq!(
            i.set_real(&[vr("viscosity_ratio")], &[f64::NAN]),
            Status::Error
        );
        assert!(log.borrow().last().unwrap().2.contains("NaN"));
        i.reset();
        assert_eq!(i.set_real(&[9999], &[1.0]), Status::Error);
        assert!(log.borrow().last().unwrap().2.contains("9999"));
        i.reset();
        assert_eq!(i.set_real(&[vr("drop_width")], &[1.0]), Status::Error);
        assert!(log.borrow().last().unwrap().2.contains("output"));
        i.reset();
        assert_eq!(i.set_real(&[vr("rheology")], &[1.0]), Status::Error);
        assert!(log.borrow().last().unwrap().2.contains("fmi2SetInteger"));
    }

    #[test]
    fn cross_parameter_errors_surface_at_exit_initialization() {
        let (mut i, log) = instance(false);
        assert_eq!(
            i.set_integer(&[vr("particles_per_diameter")], &[4000]),
            Status::Ok
        );
        assert_eq!(i.enter_initialization_mode(), Status::Ok);
        assert_eq!(i.exit_initialization_mode(), Status::Error);
        let msg = log.borrow().last().unwrap().2.clone();
        assert!(
            msg.contains("particles_per_diameter") && msg.contains("memory"),
            "{msg}"
        );
    }

    #[test]
    fn the_jet_under_isph_with_p_zero_on_its_surface_warns_once_at_initialization() {
        let twin = |name: &str| vr(name) + crate::scene::NAME_VR_OFFSET;
        let warnings = |scheme: &str, surface: &str| {
            let (mut i, log) = instance(true);
            assert_eq!(
                i.set_string(
                    &[twin("scene"), twin("scheme"), twin("isph_free_surface")],
                    &[
                        Some("jet".into()),
                        Some(scheme.into()),
                        Some(surface.into())
                    ]
                ),
                Status::Ok
            );
            i.set_integer(&[vr("particles_per_diameter")], &[4]);
            assert_eq!(i.enter_initialization_mode(), Status::Ok);
            assert_eq!(i.exit_initialization_mode(), Status::Ok);
            assert_eq!(i.do_step(0.0, 1e-3), Status::Ok);
            let l = log.borrow();
            l.iter()
                .filter(|(st, cat, _)| *st == Status::Warning && cat == "logStatusWarning")
                .map(|(_, _, m)| m.clone())
                .collect::<Vec<_>>()
        };
        let w = warnings("isph", "zero_pressure");
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("does not buckle") && w[0].contains("docs/methods.md"),
            "{}",
            w[0]
        );
        // The jet's own choice (auto: King & Lind's (35a) normal stress) buckles: no warning.
        assert!(warnings("isph", "auto").is_empty());
        assert!(warnings("wcsph", "auto").is_empty());
    }

    #[test]
    fn logging_categories_are_honoured() {
        let (mut i, log) = instance(false);
        i.enter_initialization_mode();
        i.exit_initialization_mode();
        assert!(log.borrow().is_empty(), "events are off without loggingOn");
        assert_eq!(i.set_debug_logging(true, &["logEvents".into()]), Status::Ok);
        i.terminate();
        assert_eq!(log.borrow().last().unwrap().1, "logEvents");
        let n = log.borrow().len();
        assert_eq!(i.set_debug_logging(false, &[]), Status::Ok);
        assert_eq!(i.do_step(0.0, 1e-3), Status::Error, "Terminated");
        assert_eq!(log.borrow().len(), n, "everything off");
        assert_eq!(
            i.set_debug_logging(true, &["logBogus%s".into()]),
            Status::Error
        );
        assert_eq!(i.set_debug_logging(true, &["logAll".into()]), Status::Ok);
        assert_eq!(
            i.set_debug_logging(true, &["logBogus%s".into()]),
            Status::Error
        );
        let msg = log.borrow().last().unwrap().2.clone();
        assert!(
            msg.contains("'logBogus%s'") && msg.contains("logStatusDiscard"),
            "{msg}"
        );
    }

    #[test]
    fn a_short_run_reports_outputs_and_last_successful_time() {
        let (mut i, _log) = instance(true);
        i.set_integer(&[vr("particles_per_diameter")], &[12]);
        i.setup_experiment(None, 0.0, Some(0.01));
        i.enter_initialization_mode();
        let mut w0 = [0.0];
        assert_eq!(i.get_real(&[vr("drop_width")], &mut w0), Status::Ok);
        assert!((w0[0] - 0.02).abs() < 1e-12, "{}", w0[0]);
        assert_eq!(i.exit_initialization_mode(), Status::Ok);
        assert_eq!(i.do_step(0.0, 0.005), Status::Ok);
        assert_eq!(i.do_step(0.004, 0.005), Status::Error, "not continuing");
        i.reset();
        i.set_integer(&[vr("particles_per_diameter")], &[12]);
        i.setup_experiment(None, 0.0, Some(0.01));
        i.enter_initialization_mode();
        i.exit_initialization_mode();
        assert_eq!(i.do_step(0.0, 0.005), Status::Ok);
        assert_eq!(i.do_step(0.005, 0.0), Status::Error, "h = 0");
        let mut t = 0.0;
        assert_eq!(i.get_real_status(2, &mut t), Status::Ok);
        assert_eq!(t, 0.005);
        let mut ppd = [0];
        assert_eq!(
            i.get_integer(&[vr("particles_per_diameter")], &mut ppd),
            Status::Ok
        );
        assert_eq!(ppd[0], 12);
    }

    #[test]
    fn snapshots_round_trip_through_bytes_and_refuse_garbage() {
        let (mut i, _log) = instance(false);
        i.set_integer(&[vr("particles_per_diameter")], &[12]);
        i.enter_initialization_mode();
        i.exit_initialization_mode();
        i.do_step(0.0, 0.004);
        let mut snap = None;
        assert_eq!(i.get_state(&mut snap), Status::Ok);
        let bytes = snap.unwrap().to_bytes();
        let back = Snapshot::from_bytes(&bytes).unwrap();
        i.do_step(0.004, 0.004);
        let mut a = [0.0; 2];
        i.get_real(&[vr("drop_width"), vr("wall_force_normal")], &mut a);
        assert_eq!(i.set_state(&back), Status::Ok);
        i.do_step(0.004, 0.004);
        let mut b = [0.0; 2];
        i.get_real(&[vr("drop_width"), vr("wall_force_normal")], &mut b);
        assert_eq!(a, b);
        assert!(Snapshot::from_bytes(b"nonsense").is_err());
        assert!(Snapshot::from_bytes(&bytes[..bytes.len() / 2]).is_err());
    }
}
