//! The variables of the interface, one per row of the tables ([`model_variables`], and the
//! FMI 3.0 arrays [`array_variables`]), from which both standards' model descriptions are
//! written.

use super::{escape, name_variable_description, name_variable_start, parameter_description};
use crate::config::{Kind, ParamSpec};
use crate::diagnostics::OutputSpec;
use crate::scene::{input_rows, name_variables, OUTPUTS, OUTPUT_ARRAYS, PARAMS};

/// The causality of a variable (FMI 2.0 section 2.2.7, FMI 3.0 section 2.4.7.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
}

impl Causality {
    pub fn name(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

/// The type of a variable with its start value and range, as the tables give them.
#[derive(Debug, Clone, PartialEq)]
pub enum VarKind {
    /// FMI 2.0 Real, FMI 3.0 Float64; an output has no start value and no range.
    Real {
        unit: &'static str,
        start: Option<f64>,
        min: f64,
        max: f64,
    },
    /// FMI 2.0 Integer, FMI 3.0 Int32.
    Integer {
        start: i64,
        min: i64,
        max: i64,
    },
    /// An Enumeration of the TypeDefinitions, `start` its 1-based item index.
    Enumeration {
        type_name: &'static str,
        start: usize,
    },
    String {
        start: &'static str,
    },
}

/// An array variable, FMI 3.0 only ([`array_variables`]): one variable with a
/// `<Dimension start="len"/>` whose elements are the scalar outputs `name_001`, `name_002`, ...
/// with the value references `first_element_vr`, `first_element_vr + 1`, ... (variables of
/// their own in FMI 2.0 and 3.0 alike, the ones the instance reads); the FMI 3.0 layer
/// translates the array's value reference to those.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Array {
    pub len: usize,
    pub first_element_vr: u32,
}

/// One variable of the interface, from one row of the tables; both standards' model
/// descriptions are written from the same list ([`model_variables`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ModelVariable {
    pub name: String,
    pub value_reference: u32,
    pub description: String,
    pub causality: Causality,
    pub variability: &'static str,
    pub initial: Option<&'static str>,
    pub kind: VarKind,
    pub array: Option<Array>,
}

impl ModelVariable {
    /// The scalars this variable stands for: itself, or each element of an array.
    pub fn scalars(&self) -> Vec<(String, u32)> {
        match self.array {
            None => vec![(self.name.clone(), self.value_reference)],
            Some(a) => (0..a.len)
                .map(|i| {
                    (
                        format!("{}_{:03}", self.name, i + 1),
                        a.first_element_vr + i as u32,
                    )
                })
                .collect(),
        }
    }

    /// ` unit="..."` for a Real with a unit, else nothing.
    pub fn unit_attribute(&self) -> String {
        match self.kind {
            VarKind::Real { unit, .. } if !unit.is_empty() => {
                format!(r#" unit="{}""#, escape(unit))
            }
            _ => String::new(),
        }
    }
}

/// A parameter row of the table as a variable of the interface.
fn parameter_variable(p: &ParamSpec) -> ModelVariable {
    let kind = match p.kind {
        Kind::Real {
            default, min, max, ..
        } => VarKind::Real {
            unit: p.unit,
            start: Some(default),
            min,
            max,
        },
        Kind::Integer { default, min, max } => VarKind::Integer {
            start: default,
            min,
            max,
        },
        Kind::Enumeration {
            type_name,
            items,
            default,
        } => VarKind::Enumeration {
            type_name,
            start: items
                .iter()
                .position(|(n, _)| *n == default)
                .expect("enumeration default is one of its items")
                + 1,
        },
    };
    let input = p.is_input();
    ModelVariable {
        name: p.name.to_string(),
        value_reference: p.value_reference,
        description: parameter_description(p),
        causality: if input {
            Causality::Input
        } else {
            Causality::Parameter
        },
        // FMI 2.0 section 2.2.7: an input has a start value and no `initial` attribute;
        // continuous, because a master may change it at every communication point.
        variability: if input { "continuous" } else { "fixed" },
        initial: (!input).then_some("exact"),
        kind,
        array: None,
    }
}

/// Every variable of the interface in FMI 2.0 index order: the parameters, the outputs, the
/// String twins of the enumerations, the inputs (each group after the earlier ones so that the
/// indices of earlier versions stay).
pub fn model_variables() -> Vec<ModelVariable> {
    let mut vars: Vec<ModelVariable> = PARAMS
        .iter()
        .filter(|p| !p.is_input())
        .map(|p| parameter_variable(p))
        .collect();
    vars.extend(OUTPUTS.iter().map(|o| output_variable(o)));
    vars.extend(name_variables().map(|(p, name, vr)| ModelVariable {
        name,
        value_reference: vr,
        description: name_variable_description(p),
        causality: Causality::Parameter,
        variability: "fixed",
        initial: Some("exact"),
        kind: VarKind::String {
            start: name_variable_start(p),
        },
        array: None,
    }));
    vars.extend(input_rows().map(|p| {
        assert!(
            matches!(p.kind, Kind::Real { .. }),
            "input '{}' must be a Real row",
            p.name
        );
        parameter_variable(p)
    }));
    vars
}

/// An output row of the table as a variable of the interface.
fn output_variable(o: &OutputSpec) -> ModelVariable {
    ModelVariable {
        name: o.name.to_string(),
        value_reference: o.value_reference,
        description: o.description.to_string(),
        causality: Causality::Output,
        variability: "continuous",
        initial: Some("calculated"),
        kind: VarKind::Real {
            unit: o.unit,
            start: None,
            min: f64::NEG_INFINITY,
            max: f64::INFINITY,
        },
        array: None,
    }
}

/// The array variables of FMI 3.0, one per array row of the output table ([`OUTPUT_ARRAYS`]),
/// in value-reference order. They add to [`model_variables`], whose scalars include their
/// elements: FMI 2.0 has only those, FMI 3.0 both (the scalars are public names).
pub fn array_variables() -> Vec<ModelVariable> {
    OUTPUT_ARRAYS
        .iter()
        .map(|a| ModelVariable {
            array: Some(Array {
                len: a.len,
                first_element_vr: a.first_element_vr,
            }),
            ..output_variable(&OutputSpec {
                name: a.name,
                value_reference: a.value_reference,
                unit: a.unit,
                description: a.description,
            })
        })
        .collect()
}
