//! The FMI 3.0 `modelDescription.xml` (FMI 3.0 section 2.4), written from the same variable
//! list as the FMI 2.0 one ([`model_variables`]), with the same value references: the table is
//! the contract, whichever standard reads it.
//!
//! The committed `modelDescription/fmi3/modelDescription.xml` is the output of
//! [`model_description_xml`]; `tests/fmu_model_description.rs` fails when they differ and
//! `cargo run -p fmu-build -- --write-model-description` rewrites both files.
//!
//! Differences from FMI 2.0, all of the standard's making: one element per type (`Float64`,
//! `Int32`, `Enumeration`, `String` with a `<Start>` child) instead of `ScalarVariable`;
//! `EnumerationType` in the TypeDefinitions; an independent variable `time` (FMI 3.0 section
//! 2.4.7.4 requires exactly one), given the value reference 0 that the FMI 2.0 table never
//! used; an array variable is one variable with a `<Dimension>`; the ModelStructure names
//! value references, not indices.

use crate::fmi2::instance::Api;
use crate::fmi2::model_description::{
    array_variables, enumeration_items, enumeration_types, escape, guid, log_categories,
    model_variables, shared_root_attributes, unit_definitions, Causality, ModelVariable, VarKind,
    DEFAULT_STEP_SIZE, DEFAULT_STOP_TIME, MODEL_IDENTIFIER,
};
use std::fmt::Write;
use std::sync::OnceLock;

/// Value reference of the independent variable `time` (FMI 3.0 only; the instance core reads
/// it, so it is declared there).
pub use crate::fmi2::instance::TIME_VR;

/// One variable as an FMI 3.0 element.
fn variable_element(v: &ModelVariable) -> String {
    let (element, attrs) = match &v.kind {
        VarKind::Real {
            start, min, max, ..
        } => (
            "Float64",
            match start {
                Some(start) => format!(r#" start="{start}" min="{min}" max="{max}""#),
                None => String::new(),
            },
        ),
        VarKind::Integer { start, min, max } => (
            "Int32",
            format!(r#" start="{start}" min="{min}" max="{max}""#),
        ),
        VarKind::Enumeration { type_name, start } => (
            "Enumeration",
            format!(r#" declaredType="{type_name}" start="{start}""#),
        ),
        VarKind::String { .. } => ("String", String::new()),
    };
    let initial = v
        .initial
        .map(|i| format!(r#" initial="{i}""#))
        .unwrap_or_default();
    let mut x = format!(
        r#"    <{element} name="{}" valueReference="{}" description="{}" causality="{}" variability="{}"{initial}{}{attrs}"#,
        escape(&v.name),
        v.value_reference,
        escape(&v.description),
        v.causality.name(),
        v.variability,
        v.unit_attribute(),
    );
    let mut children = String::new();
    if let Some(a) = v.array {
        let _ = writeln!(children, r#"      <Dimension start="{}"/>"#, a.len);
    }
    if let VarKind::String { start } = v.kind {
        let _ = writeln!(children, r#"      <Start value="{}"/>"#, escape(start));
    }
    if children.is_empty() {
        x.push_str("/>\n");
    } else {
        let _ = write!(x, ">\n{children}    </{element}>\n");
    }
    x
}

/// The complete FMI 3.0 `modelDescription.xml`.
pub fn model_description_xml() -> String {
    let mut x = String::new();
    let w = &mut x;
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription
  fmiVersion="3.0"
  modelName="{MODEL_IDENTIFIER}"
  instantiationToken="{}"
{}>"#,
        guid(),
        shared_root_attributes("src/fmi3/model_description.rs")
    );
    // FMI 3.0 section 4.3.1: the Co-Simulation capability flags, those of FMI 2.0 plus the new
    // ones (no event mode, no intermediate update, no early return).
    let _ = writeln!(
        w,
        r#"  <CoSimulation
    modelIdentifier="{MODEL_IDENTIFIER}"
    needsExecutionTool="false"
    canBeInstantiatedOnlyOncePerProcess="false"
    canGetAndSetFMUState="true"
    canSerializeFMUState="true"
    providesDirectionalDerivatives="false"
    providesAdjointDerivatives="false"
    providesPerElementDependencies="false"
    canHandleVariableCommunicationStepSize="true"
    maxOutputDerivativeOrder="0"
    providesIntermediateUpdate="false"
    mightReturnEarlyFromDoStep="false"
    canReturnEarlyAfterIntermediateUpdate="false"
    hasEventMode="false"
    providesEvaluateDiscreteStates="false"/>"#
    );
    w.push_str(&unit_definitions());
    let _ = writeln!(w, "  <TypeDefinitions>");
    for (type_name, items) in enumeration_types() {
        let _ = writeln!(w, r#"    <EnumerationType name="{type_name}">"#);
        w.push_str(&enumeration_items(items, "      "));
        let _ = writeln!(w, "    </EnumerationType>");
    }
    let _ = writeln!(w, "  </TypeDefinitions>");
    w.push_str(&log_categories(Api::Fmi3));
    let _ = writeln!(
        w,
        r#"  <DefaultExperiment startTime="0" stopTime="{DEFAULT_STOP_TIME}" stepSize="{DEFAULT_STEP_SIZE}"/>"#
    );

    // The scalars, each array variable after its last element.
    let arrays = array_variables();
    let mut vars = Vec::new();
    for v in model_variables() {
        let last_of = arrays
            .iter()
            .find(|a| a.scalars().last().map(|(_, vr)| *vr) == Some(v.value_reference));
        vars.push(v);
        vars.extend(last_of.cloned());
    }
    let _ = writeln!(w, "  <ModelVariables>");
    let _ = writeln!(
        w,
        r#"    <Float64 name="time" valueReference="{TIME_VR}" description="Simulation time" causality="independent" variability="continuous" unit="s"/>"#
    );
    for v in &vars {
        w.push_str(&variable_element(v));
    }
    let _ = writeln!(w, "  </ModelVariables>");

    // FMI 3.0 section 2.4.8. Outputs: `dependencies=""`, no direct feed-through (the reasoning
    // and the test are those of the FMI 2.0 ModelStructure: an input acts only on the steps
    // after it). InitialUnknowns: without `dependencies`, each depends on all knowns, which is
    // the truth (the initial state is built from the parameters).
    let _ = writeln!(w, "  <ModelStructure>");
    let outputs: Vec<&ModelVariable> = vars
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .collect();
    for v in &outputs {
        let _ = writeln!(
            w,
            r#"    <Output valueReference="{}" dependencies=""/>"#,
            v.value_reference
        );
    }
    for v in &outputs {
        let _ = writeln!(
            w,
            r#"    <InitialUnknown valueReference="{}"/>"#,
            v.value_reference
        );
    }
    let _ = writeln!(w, "  </ModelStructure>");
    let _ = writeln!(w, "</fmiModelDescription>");
    x
}

/// The value references the instance reads for the FMI 3.0 value references `vrs`: an array's
/// elements in order, a scalar as itself (FMI 3.0 section 2.2.6.2: the values of all variables
/// named, serialized in row-major order, one after the other).
pub fn core_value_references(vrs: &[u32]) -> Vec<u32> {
    // The arrays and their elements, once per process (the tables are constant).
    static ARRAYS: OnceLock<Vec<(u32, Vec<u32>)>> = OnceLock::new();
    let arrays = ARRAYS.get_or_init(|| {
        array_variables()
            .into_iter()
            .map(|v| {
                (
                    v.value_reference,
                    v.scalars().into_iter().map(|(_, e)| e).collect(),
                )
            })
            .collect()
    });
    let mut out = Vec::with_capacity(vrs.len());
    for &vr in vrs {
        match arrays.iter().find(|(a, _)| *a == vr) {
            Some((_, elements)) => out.extend_from_slice(elements),
            None => out.push(vr),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variable_of_fmi2_is_in_fmi3_with_its_value_reference() {
        let two = crate::fmi2::model_description_xml();
        let three = model_description_xml();
        let vr_of = |doc: &str, name: &str| -> Option<u32> {
            let key = format!(r#"name="{name}" valueReference=""#);
            let at = doc.find(&key)? + key.len();
            doc[at..].split('"').next()?.parse().ok()
        };
        for v in model_variables() {
            for (name, vr) in v.scalars() {
                assert_eq!(vr_of(&two, &name), Some(vr), "{name} in FMI 2.0");
            }
            assert_eq!(
                vr_of(&three, &v.name),
                Some(v.value_reference),
                "{} in FMI 3.0",
                v.name
            );
        }
        // The arrays: FMI 3.0 only, their elements in both.
        for v in array_variables() {
            assert_eq!(
                vr_of(&two, &v.name),
                None,
                "{} is no FMI 2.0 variable",
                v.name
            );
            assert_eq!(
                vr_of(&three, &v.name),
                Some(v.value_reference),
                "{}",
                v.name
            );
            for (name, vr) in v.scalars() {
                assert_eq!(vr_of(&two, &name), Some(vr), "{name} in FMI 2.0");
                assert_eq!(vr_of(&three, &name), Some(vr), "{name} in FMI 3.0");
            }
        }
        assert!(three.contains(&format!(r#"instantiationToken="{}""#, guid())));
    }

    #[test]
    fn an_array_row_is_one_fmi3_variable_and_fmi2_scalars() {
        let v = ModelVariable {
            name: "wall_pressure".into(),
            value_reference: 300,
            description: "pressure along the plate".into(),
            causality: Causality::Output,
            variability: "continuous",
            initial: Some("calculated"),
            kind: VarKind::Real {
                unit: "Pa",
                start: None,
                min: f64::NEG_INFINITY,
                max: f64::INFINITY,
            },
            array: Some(crate::fmi2::model_description::Array {
                len: 3,
                first_element_vr: 200,
            }),
        };
        assert_eq!(
            variable_element(&v),
            "    <Float64 name=\"wall_pressure\" valueReference=\"300\" description=\"pressure along the plate\" causality=\"output\" variability=\"continuous\" initial=\"calculated\" unit=\"Pa\">\n      <Dimension start=\"3\"/>\n    </Float64>\n"
        );
        assert_eq!(
            v.scalars(),
            vec![
                ("wall_pressure_001".to_string(), 200),
                ("wall_pressure_002".to_string(), 201),
                ("wall_pressure_003".to_string(), 202)
            ]
        );
    }
}
