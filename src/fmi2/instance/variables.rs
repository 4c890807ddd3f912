//! The instance's variables: looking them up by value reference, reading and setting them, and
//! the messages that refuse a call of the wrong type.

use super::*;
use crate::config::{Kind, ParamSpec, Value};
use crate::scene::{input_rows, name_variable_by_vr, param_by_vr, NAME_SUFFIX};

/// Which integer parameters an integer accessor reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntKind {
    /// Integer and Enumeration (FMI 2.0's `fmi2Integer` serves both).
    Any,
    /// Integer only (FMI 3.0's Int32).
    Integer,
    /// Enumeration only (FMI 3.0 accesses them as Int64).
    Enumeration,
}

impl IntKind {
    fn accepts(self, kind: &Kind) -> bool {
        matches!(
            (self, kind),
            (IntKind::Any | IntKind::Integer, Kind::Integer { .. })
                | (
                    IntKind::Any | IntKind::Enumeration,
                    Kind::Enumeration { .. }
                )
        )
    }
}

/// A variable of the interface, found by value reference.
pub(super) enum Var {
    Param(&'static ParamSpec),
    /// The String twin of an Enumeration parameter ([`crate::config::name_variables`]).
    Name(&'static ParamSpec),
    Output(usize),
    /// The independent variable `time` of FMI 3.0 (value reference [`TIME_VR`], which FMI 2.0
    /// does not use): readable, like every variable, never settable (its value is set by
    /// `fmi3EnterInitializationMode`'s startTime and `fmi3DoStep`).
    Time,
}

pub(super) fn lookup(api: Api, vr: u32) -> Option<Var> {
    if api == Api::Fmi3 && vr == TIME_VR {
        return Some(Var::Time);
    }
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
pub(super) fn output_cannot_be_set(vr: u32, i: usize) -> Fail {
    Fail::Error(format!(
        "'{}' (valueReference {vr}) is an output and cannot be set",
        OUTPUTS[i].name
    ))
}

pub(super) fn unknown_vr(vr: u32) -> Fail {
    Fail::Error(format!(
        "unknown valueReference {vr}: no variable of modelDescription.xml has it"
    ))
}

/// The FMI type name of a variable, for "use fmi2GetInteger instead" messages.
pub(super) fn type_of(v: &Var) -> &'static str {
    match v {
        Var::Output(_) | Var::Time => "Real",
        Var::Name(_) => "String",
        Var::Param(p) => match p.kind {
            Kind::Real { .. } => "Real",
            Kind::Integer { .. } => "Integer",
            Kind::Enumeration { .. } => "Enumeration",
        },
    }
}

pub(super) fn name_of(v: &Var) -> String {
    match v {
        Var::Output(i) => OUTPUTS[*i].name.to_string(),
        Var::Time => "time".to_string(),
        Var::Param(p) => p.name.to_string(),
        Var::Name(p) => format!("{}{NAME_SUFFIX}", p.name),
    }
}

/// "'drop_width' (valueReference 101) is a Real variable; use fmi2GetReal".
pub(super) fn wrong_type(vr: u32, v: &Var, verb: &str) -> Fail {
    let ty = type_of(v);
    let fun = if ty == "Enumeration" { "Integer" } else { ty };
    Fail::Error(format!(
        "'{}' (valueReference {vr}) is an {ty} variable; use fmi2{verb}{fun}",
        name_of(v)
    ))
}

impl Instance {
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

    /// The frame of the `fmi2Get*` calls: each value reference looked up (an unknown one
    /// refused) and its value taken from `value`, which refuses a variable of another type.
    fn get_each<T>(
        &mut self,
        func: &'static str,
        vrs: &[u32],
        values: &mut [T],
        mut value: impl FnMut(&mut Self, u32, &Var) -> Result<T, Fail>,
    ) -> Status {
        self.call(
            func,
            mask::GET,
            || format!("vr={vrs:?}"),
            |s| {
                for (k, &vr) in vrs.iter().enumerate() {
                    let var = lookup(s.api, vr).ok_or_else(|| unknown_vr(vr))?;
                    values[k] = value(s, vr, &var)?;
                }
                Ok(Status::Ok)
            },
        )
    }

    pub fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Status {
        // The outputs are computed once per call, and only if one is asked for.
        let mut outputs: Option<Outputs> = None;
        self.get_each("fmi2GetReal", vrs, values, |s, vr, var| match var {
            Var::Output(i) => {
                if outputs.is_none() {
                    outputs = Some(s.current_outputs()?);
                }
                Ok(outputs.as_ref().expect("set above").values()[*i])
            }
            Var::Param(p) => match (p.kind, s.cfg.get(p.name)) {
                (Kind::Real { .. }, Ok(Value::Real(x))) => Ok(x),
                _ => Err(wrong_type(vr, var, "Get")),
            },
            Var::Time => Ok(s.t_comm),
            Var::Name(_) => Err(wrong_type(vr, var, "Get")),
        })
    }

    pub fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Status {
        self.get_integer_of("fmi2GetInteger", IntKind::Any, vrs, values)
    }

    /// The integer getters: `fmi2GetInteger` reads Integer and Enumeration parameters alike
    /// ([`IntKind::Any`]); FMI 3.0 reads an Int32 by `fmi3GetInt32` and an Enumeration by
    /// `fmi3GetInt64` (FMI 3.0 section 2.2.6.2), each refusing the other.
    pub fn get_integer_of(
        &mut self,
        func: &'static str,
        kind: IntKind,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Status {
        self.get_each(func, vrs, values, |s, vr, var| match var {
            Var::Param(p) if kind.accepts(&p.kind) => match s.cfg.get(p.name) {
                Ok(Value::Integer(i)) => {
                    Ok(i32::try_from(i).expect("table ranges fit in fmi2Integer"))
                }
                _ => Err(wrong_type(vr, var, "Get")),
            },
            _ => Err(wrong_type(vr, var, "Get")),
        })
    }

    /// `fmi2GetString`: the item names of the String twins of the Enumeration parameters, as
    /// `'static` strings (the table's), so the pointers handed to the importer stay valid.
    pub fn get_string(&mut self, vrs: &[u32], values: &mut [&'static str]) -> Status {
        self.get_each("fmi2GetString", vrs, values, |s, vr, var| match var {
            Var::Name(p) => s
                .cfg
                .item_name(p.name)
                .map_err(|e| Fail::Error(e.to_string())),
            _ => Err(wrong_type(vr, var, "Get")),
        })
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
                    let var = lookup(s.api, vr).ok_or_else(|| unknown_vr(vr))?;
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
            |s| no_variables_of_type(s.api, vrs, "Get"),
        )
    }

    /// `fmi2SetBoolean`: see [`Instance::get_none`].
    pub fn set_none(&mut self, func: &'static str, vrs: &[u32]) -> Status {
        self.call(
            func,
            mask::SET,
            || format!("vr={vrs:?}"),
            |s| no_variables_of_type(s.api, vrs, "Set"),
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
        self.set_integer_of("fmi2SetInteger", IntKind::Any, vrs, values)
    }

    /// The integer setters, each for the parameters of its [`IntKind`] (see
    /// [`Instance::get_integer_of`]).
    pub fn set_integer_of(
        &mut self,
        func: &'static str,
        kind: IntKind,
        vrs: &[u32],
        values: &[i32],
    ) -> Status {
        self.set_parameters(
            func,
            vrs,
            values,
            |k| kind.accepts(k),
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
                    let var = lookup(s.api, vr).ok_or_else(|| unknown_vr(vr))?;
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
                        Var::Time => {
                            return error(format!(
                                "'time' (valueReference {vr}) is the independent variable and cannot be set: \
                                 its value is the startTime of fmi2SetupExperiment, then the end of each fmi2DoStep"
                            ))
                        }
                        _ => return Err(wrong_type(vr, &var, "Set")),
                    }
                }
                let mut status = Status::Ok;
                if stepping {
                    // Inputs act from this communication point on (the simulation lands on it
                    // exactly, going back one internal step if it had passed it). An input
                    // beyond the range the run was set up for is kept here but not put in
                    // force: the next fmi2DoStep is discarded unless a value within it is set
                    // first (`Instance::do_step`).
                    let sim = s.sim.as_mut().expect("a simulation exists in StepComplete");
                    match sim.set_inputs(cfg.inputs()) {
                        Ok(()) => {}
                        Err(SimError::InputOutOfRange(m)) => {
                            s.log(
                                Category::Warning,
                                Status::Warning,
                                &format!("{func}: {m}; the next fmi2DoStep will be discarded unless a value within it is set first"),
                            );
                            status = Status::Warning;
                        }
                        Err(e) => return error(e.to_string()),
                    }
                }
                s.cfg = cfg;
                s.preview = None;
                Ok(status)
            },
        )
    }
}

pub(super) fn no_variables_of_type(api: Api, vrs: &[u32], verb: &str) -> Answer {
    match vrs.first() {
        None => Ok(Status::Ok),
        Some(&vr) => match lookup(api, vr) {
            None => Err(unknown_vr(vr)),
            Some(v) => Err(wrong_type(vr, &v, verb)),
        },
    }
}
