//! The full tables, assembled from the groups of the registry: every parameter ([`PARAMS`]) and
//! every output ([`OUTPUTS`]), each sorted by value reference (the order of the FMU's model
//! description and of scene files written out), with the lookups the FMU and the scene files
//! need.

use super::{Outputs, SceneConfig};
use crate::config::{Kind, ParamGroup, ParamSpec};
use crate::diagnostics::{OutputArray, OutputSpec};
use std::sync::LazyLock;

/// Every parameter row, sorted by value reference.
pub static PARAMS: LazyLock<Vec<&'static ParamSpec>> = LazyLock::new(|| {
    let mut rows = declared_rows();
    rows.sort_by_key(|p| p.value_reference);
    rows
});

/// Every parameter row in declaration order: the `scene` and `scheme` rows, the shared groups,
/// then each scene's group in registry order.
fn declared_rows() -> Vec<&'static ParamSpec> {
    let mut rows = Vec::new();
    SceneConfig::collect_rows(&mut rows);
    rows
}

/// Every output row, sorted by value reference.
pub static OUTPUTS: LazyLock<Vec<&'static OutputSpec>> = LazyLock::new(|| {
    let mut rows = group_output_rows();
    rows.sort_by_key(|o| o.value_reference);
    rows
});

/// Every array row ([`OutputArray`]: its elements are rows of [`OUTPUTS`]), sorted by the FMI
/// 3.0 array variable's value reference.
pub static OUTPUT_ARRAYS: LazyLock<Vec<&'static OutputArray>> = LazyLock::new(|| {
    let mut rows = Vec::new();
    Outputs::collect_arrays(&mut rows);
    rows.sort_by_key(|a| a.value_reference);
    rows
});

fn group_output_rows() -> Vec<&'static OutputSpec> {
    let mut rows = Vec::new();
    Outputs::collect_rows(&mut rows);
    rows
}

/// For each output of [`OUTPUTS`], its position in group order ([`Outputs`]' fields).
static GROUP_POSITION: LazyLock<Vec<usize>> = LazyLock::new(|| {
    let group = group_output_rows();
    OUTPUTS
        .iter()
        .map(|o| {
            group
                .iter()
                .position(|g| std::ptr::eq(*g, *o))
                .expect("every output is in a group")
        })
        .collect()
});

impl Outputs {
    /// Values in the order of [`OUTPUTS`].
    pub fn values(&self) -> Vec<f64> {
        let v = self.group_values();
        GROUP_POSITION.iter().map(|&g| v[g]).collect()
    }

    /// Set every value from a slice in the order of [`OUTPUTS`].
    pub fn set_values(&mut self, values: &[f64]) {
        let mut v = vec![0.0; values.len()];
        for (k, &g) in GROUP_POSITION.iter().enumerate() {
            v[g] = values[k];
        }
        self.set_group_values(&v);
    }

    /// Value of an output by name.
    pub fn get(&self, name: &str) -> Option<f64> {
        output_index(name).map(|i| self.values()[i])
    }
}

/// Position in [`OUTPUTS`] of the output called `name`.
pub fn output_index(name: &str) -> Option<usize> {
    OUTPUTS.iter().position(|o| o.name == name)
}

/// The parameter called `name`, or whose older name (alias) it is: `drop_height` is the older
/// name of `initial_drop_height` (the FMU needs unique variable names and `drop_height` is an
/// output).
pub fn param_spec(name: &str) -> Option<&'static ParamSpec> {
    PARAMS
        .iter()
        .find(|p| p.name == name)
        .or_else(|| PARAMS.iter().find(|p| p.is_called(name)))
        .copied()
}

/// The parameter with a given FMU value reference.
pub fn param_by_vr(vr: u32) -> Option<&'static ParamSpec> {
    PARAMS.iter().find(|p| p.value_reference == vr).copied()
}

/// The rows that are FMU inputs ([`ParamSpec::input`]) in declaration order: the shared
/// groups' (`plate_velocity`) first, then each scene's in registry order. In the running
/// simulation their values are those of the effective configuration ([`super::Inputs`]).
pub fn input_rows() -> impl Iterator<Item = &'static ParamSpec> {
    declared_rows().into_iter().filter(|p| p.input)
}

/// Value reference of an enumeration's String twin: the enumeration's own plus this offset, so
/// every variable of the FMU has a value reference of its own, whatever its type.
pub const NAME_VR_OFFSET: u32 = 1000;

/// Suffix of the String twins' names: `rheology` is also settable as `rheology_name`.
pub const NAME_SUFFIX: &str = "_name";

/// The String twin of each Enumeration row: `(row, twin name, twin value reference)`.
///
/// Why twins exist: OSP's libcosim and ecos ignore FMI 2.0 Enumeration variables (they warn
/// "variable type not supported" and leave the default), and fmpy's `simulate_fmu` converts an
/// Enumeration's start value with `int()`, so a model could be chosen there only by item number.
/// All of them, and fmi-sim, set String variables by name. The Enumeration stays the canonical
/// variable (same name and value reference as before, shown as a list of items by tools that
/// read TypeDefinitions); its twin sets the same parameter, and the last value set wins.
/// Not an Integer alias of the Enumeration (Integer and Enumeration share one value-reference
/// space): that would put two parameters, each with the start value a parameter needs, in one
/// alias set, which FMI 2.0 section 2.2.7 forbids ("at most one variable of the same alias set
/// of variables with variability != constant can have a start attribute"), and it would still
/// take only numbers.
pub fn name_variables() -> impl Iterator<Item = (&'static ParamSpec, String, u32)> {
    PARAMS.iter().filter_map(|p| match p.kind {
        Kind::Enumeration { .. } => Some((
            *p,
            format!("{}{NAME_SUFFIX}", p.name),
            p.value_reference + NAME_VR_OFFSET,
        )),
        _ => None,
    })
}

/// The Enumeration row whose String twin has value reference `vr`.
pub fn name_variable_by_vr(vr: u32) -> Option<&'static ParamSpec> {
    name_variables()
        .find(|(_, _, v)| *v == vr)
        .map(|(p, _, _)| p)
}

/// The Enumeration row whose String twin is called `name` (e.g. `rheology_name`).
pub fn name_variable(name: &str) -> Option<&'static ParamSpec> {
    let stem = name.strip_suffix(NAME_SUFFIX)?;
    PARAMS
        .iter()
        .find(|p| p.name == stem && matches!(p.kind, Kind::Enumeration { .. }))
        .copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_references_are_unique() {
        let mut vrs: Vec<u32> = PARAMS
            .iter()
            .map(|p| p.value_reference)
            .chain(name_variables().map(|(_, _, vr)| vr))
            .chain(OUTPUTS.iter().map(|o| o.value_reference))
            .collect();
        let n = vrs.len();
        vrs.sort();
        vrs.dedup();
        assert_eq!(
            vrs.len(),
            n,
            "every variable of every type has its own value reference"
        );
    }

    #[test]
    fn names_are_unique() {
        // The FMU's variables: parameters, outputs and String twins.
        let mut names: Vec<String> = PARAMS
            .iter()
            .map(|p| p.name.to_string())
            .chain(OUTPUTS.iter().map(|o| o.name.to_string()))
            .chain(name_variables().map(|(_, n, _)| n))
            .collect();
        let n = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), n, "{names:?}");
        // A scene-file key names one parameter: no alias is another parameter's name.
        for p in PARAMS.iter() {
            if let Some(alias) = p.alias {
                assert!(PARAMS.iter().all(|q| q.name != alias), "{alias}");
                assert_eq!(param_spec(alias).map(|q| q.name), Some(p.name));
            }
        }
    }

    #[test]
    fn outputs_round_trip_through_the_table_order() {
        let mut o = Outputs::default();
        let v: Vec<f64> = (0..OUTPUTS.len()).map(|k| k as f64 + 0.5).collect();
        o.set_values(&v);
        assert_eq!(o.values(), v);
        assert_eq!(o.get("drop_width"), Some(0.5));
        assert_eq!(o.shared.drop_width, 0.5);
        assert_eq!(o.jet.jet_deflection, o.get("jet_deflection").unwrap());
    }
}
