//! One row of the parameter table ([`ParamSpec`]), its type and range ([`Kind`]), the values that
//! arrive from scene files and the FMU ([`Value`]), and how a group of rows stores them
//! ([`ParamGroup`], implemented by the [`params!`](crate::params) macro).

use crate::choice::Choice;
use std::fmt;
use thiserror::Error;

/// What went wrong with a parameter. The message names the variable, the value and what is allowed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    #[error("unknown parameter '{0}'")]
    Unknown(String),
    #[error("parameter '{name}' = {value} is outside the allowed range {range}")]
    OutOfRange {
        name: String,
        value: String,
        range: String,
    },
    #[error("parameter '{name}' has a value of the wrong type: {detail}")]
    WrongType { name: String, detail: String },
    #[error("parameter '{name}': '{value}' is not one of {allowed}")]
    BadChoice {
        name: String,
        value: String,
        allowed: String,
    },
    #[error("{0}")]
    Inconsistent(String),
    #[error("scene file: {0}")]
    Parse(String),
}

/// The type of one parameter, with its default and limits.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// A real number in `[min, max]`; `min_open`/`max_open` make an end exclusive.
    Real {
        default: f64,
        min: f64,
        max: f64,
        min_open: bool,
        max_open: bool,
    },
    /// An integer in `[min, max]`.
    Integer { default: i64, min: i64, max: i64 },
    /// One of `items`, numbered 1.. in the FMU (FMI 2.0 Enumeration).
    Enumeration {
        type_name: &'static str,
        items: &'static [(&'static str, &'static str)],
        default: &'static str,
    },
}

/// A real in `[min, max]`.
pub const fn real(default: f64, min: f64, max: f64) -> Kind {
    Kind::Real {
        default,
        min,
        max,
        min_open: false,
        max_open: false,
    }
}

/// A real in `(0, max]`: a size, a density, a time.
pub const fn real_pos(default: f64, max: f64) -> Kind {
    Kind::Real {
        default,
        min: 0.0,
        max,
        min_open: true,
        max_open: false,
    }
}

/// An integer in `[min, max]`.
pub const fn integer(default: i64, min: i64, max: i64) -> Kind {
    Kind::Integer { default, min, max }
}

/// One of the items of the choice `C` (an FMI Enumeration of type `type_name`).
pub const fn enumeration<C: Choice>(type_name: &'static str, default: &'static str) -> Kind {
    Kind::Enumeration {
        type_name,
        items: C::ITEMS,
        default,
    }
}

/// One row of the parameter table: the FMU variable and the scene-file key of one parameter.
#[derive(Debug, Clone, Copy)]
pub struct ParamSpec {
    /// FMU variable name and scene-file key (also the field name of the group that holds it).
    pub name: &'static str,
    pub value_reference: u32,
    pub kind: Kind,
    /// SI unit name as used in the FMU's unitDefinitions ("" for dimensionless).
    pub unit: &'static str,
    pub description: &'static str,
    /// An older name scene files may still use (never both in one file).
    pub alias: Option<&'static str>,
    /// An FMU *input* (causality "input", variability "continuous") rather than a fixed
    /// parameter: a co-simulation master may set it again after initialization, at every
    /// communication point (FMI 2.0 section 2.2.7, and section 4.2.4 for Co-Simulation). The
    /// row gives its start value, range and scene-file key like any parameter's.
    pub input: bool,
}

impl ParamSpec {
    /// The row of a parameter that chooses one of the items of `C` (an FMI Enumeration of type
    /// `type_name`), declared by a registry rather than in a group (`scene`, `scheme`).
    pub const fn choice<C: Choice>(
        name: &'static str,
        value_reference: u32,
        type_name: &'static str,
        default: &'static str,
        description: &'static str,
    ) -> Self {
        Self {
            name,
            value_reference,
            kind: enumeration::<C>(type_name, default),
            unit: "",
            description,
            alias: None,
            input: false,
        }
    }

    /// Whether this row is an input (see [`ParamSpec::input`]).
    pub fn is_input(&self) -> bool {
        self.input
    }

    /// Whether `name` names this row (its name or its older alias).
    pub fn is_called(&self, name: &str) -> bool {
        self.name == name || self.alias == Some(name)
    }
}

/// A parameter value as it arrives from a scene file or the FMU.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i64),
    Text(String),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Real(x) => write!(f, "{x}"),
            Value::Integer(i) => write!(f, "{i}"),
            Value::Text(s) => write!(f, "'{s}'"),
        }
    }
}

/// A value that passed its row's type and range check ([`Kind::check`]), in the row's own type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Checked {
    Real(f64),
    Integer(i64),
    Item(&'static str),
}

impl Kind {
    /// The row's default.
    pub fn default_value(&self) -> Checked {
        match *self {
            Kind::Real { default, .. } => Checked::Real(default),
            Kind::Integer { default, .. } => Checked::Integer(default),
            Kind::Enumeration { default, .. } => Checked::Item(default),
        }
    }

    /// Check `value` for parameter `name` against this kind: its type (a real also takes an
    /// integer, an integer a whole real, an enumeration its item name or 1-based index) and its
    /// range. The error names the parameter, the value and what is allowed.
    pub fn check(&self, name: &str, value: Value) -> Result<Checked, ConfigError> {
        match *self {
            Kind::Real {
                min,
                max,
                min_open,
                max_open,
                ..
            } => {
                let x = match value {
                    Value::Real(x) => x,
                    Value::Integer(i) => i as f64,
                    Value::Text(ref s) => {
                        return Err(ConfigError::WrongType {
                            name: name.into(),
                            detail: format!("expected a real number, got '{s}'"),
                        })
                    }
                };
                let lo_ok = if min_open { x > min } else { x >= min };
                let hi_ok = if max_open { x < max } else { x <= max };
                if !x.is_finite() || !lo_ok || !hi_ok {
                    return Err(ConfigError::OutOfRange {
                        name: name.into(),
                        value: format!("{x}"),
                        range: range_text(self),
                    });
                }
                Ok(Checked::Real(x))
            }
            Kind::Integer { min, max, .. } => {
                let i = match value {
                    Value::Integer(i) => i,
                    Value::Real(x) if x.fract() == 0.0 && x.is_finite() => x as i64,
                    other => {
                        return Err(ConfigError::WrongType {
                            name: name.into(),
                            detail: format!("expected an integer, got {other}"),
                        })
                    }
                };
                if i < min || i > max {
                    return Err(ConfigError::OutOfRange {
                        name: name.into(),
                        value: format!("{i}"),
                        range: range_text(self),
                    });
                }
                Ok(Checked::Integer(i))
            }
            Kind::Enumeration { items, .. } => {
                let text = match value {
                    Value::Text(s) => s,
                    Value::Integer(i) if i >= 1 && (i as usize) <= items.len() => {
                        items[(i - 1) as usize].0.to_string()
                    }
                    other => {
                        return Err(ConfigError::BadChoice {
                            name: name.into(),
                            value: other.to_string(),
                            allowed: choices_text(items),
                        })
                    }
                };
                items
                    .iter()
                    .find(|(n, _)| *n == text)
                    .map(|(n, _)| Checked::Item(n))
                    .ok_or_else(|| ConfigError::BadChoice {
                        name: name.into(),
                        value: text,
                        allowed: choices_text(items),
                    })
            }
        }
    }
}

/// Human-readable range of a row, e.g. "[0, 90)".
pub fn range_text(kind: &Kind) -> String {
    match *kind {
        Kind::Real {
            min,
            max,
            min_open,
            max_open,
            ..
        } => format!(
            "{}{}, {}{}",
            if min_open { "(" } else { "[" },
            min,
            max,
            if max_open { ")" } else { "]" }
        ),
        Kind::Integer { min, max, .. } => format!("[{min}, {max}]"),
        Kind::Enumeration { items, .. } => choices_text(items),
    }
}

fn choices_text(items: &[(&str, &str)]) -> String {
    let names: Vec<String> = items.iter().map(|(n, _)| format!("'{n}'")).collect();
    format!("{{{}}}", names.join(", "))
}

/// The Rust type of a parameter field: how it is read out as a [`Value`] and stored from a
/// [`Checked`] value of its row. A field whose type does not match its row's kind fails the
/// first time its group is built (`Default`), which every test does.
pub trait ParamValue: Copy {
    /// The value as the table reports it (an enumeration as its 1-based index).
    fn to_value(self) -> Value;
    /// The value of a checked row value of the matching kind.
    fn from_checked(v: Checked) -> Self;
}

impl ParamValue for f64 {
    fn to_value(self) -> Value {
        Value::Real(self)
    }
    fn from_checked(v: Checked) -> Self {
        match v {
            Checked::Real(x) => x,
            other => panic!("a real parameter was given {other:?}"),
        }
    }
}

impl ParamValue for i64 {
    fn to_value(self) -> Value {
        Value::Integer(self)
    }
    fn from_checked(v: Checked) -> Self {
        match v {
            Checked::Integer(i) => i,
            other => panic!("an integer parameter was given {other:?}"),
        }
    }
}

impl<C: Choice> ParamValue for C {
    fn to_value(self) -> Value {
        Value::Integer(self.item_index())
    }
    fn from_checked(v: Checked) -> Self {
        match v {
            Checked::Item(name) => C::from_name(name)
                .unwrap_or_else(|| panic!("'{name}' is in the table but not in the enum")),
            other => panic!("an enumeration parameter was given {other:?}"),
        }
    }
}

/// A group of parameters: a struct whose fields are rows of the table, declared once with
/// [`params!`](crate::params) (rows, fields, defaults, reading and storing by name). Groups
/// nest: the whole configuration is a group of the scenes' and the shared groups.
pub trait ParamGroup {
    /// Append the rows of this group (nested groups included), in declaration order.
    fn collect_rows(out: &mut Vec<&'static ParamSpec>);
    /// The value of the parameter called `name` (its table name), if this group holds it.
    fn value(&self, name: &str) -> Option<Value>;
    /// Store the checked value of the parameter called `name` (its table name); false if this
    /// group does not hold it.
    fn store(&mut self, name: &str, v: Checked) -> bool;
}
