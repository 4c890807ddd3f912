//! `modelDescription.xml`, generated from the parameter table [`PARAMS`] and the output table
//! [`OUTPUTS`] (each in value-reference order), so that the FMU's interface and the solver cannot drift apart.
//!
//! The committed `modelDescription/modelDescription.xml` is the output of
//! [`model_description_xml`]; `tests/fmu_model_description.rs` fails when the two differ, and
//! `cargo run -p fmu-build -- --write-model-description` rewrites the file. The GUID is a hash of
//! the rest of the document, so it changes exactly when the interface changes: an FMU whose
//! binary was built from other tables than its XML is refused by `fmi2Instantiate` (FMI 2.0
//! section 2.1.5, `fmuGUID`).
//!
//! Structure and attribute order follow the FMI 2.0 schema `fmi2ModelDescription.xsd`
//! (FMI 2.0 section 2.2): CoSimulation, UnitDefinitions, TypeDefinitions, LogCategories,
//! DefaultExperiment, ModelVariables, ModelStructure.

mod variables;

pub use variables::*;

use super::instance::Api;
use crate::config::{range_text, Kind, ParamSpec};
use crate::scene::{OUTPUTS, PARAMS};
use std::fmt::Write;

/// The FMI model identifier: the name of the shared library inside the FMU
/// (`binaries/linux64/ViscoSPH.so`, FMI 2.0 section 2.3).
pub const MODEL_IDENTIFIER: &str = "ViscoSPH";

/// Stop time of the default experiment \[s\]: the drop has spread and retracted by then.
pub const DEFAULT_STOP_TIME: f64 = 0.16;

/// Communication step of the default experiment \[s\].
pub const DEFAULT_STEP_SIZE: f64 = 0.001;

/// Log categories accepted by `fmi2SetDebugLogging` (FMI 2.0 section 2.2.4 lists these names as
/// the recommended ones), with what each one reports.
pub const LOG_CATEGORIES: &[(&str, &str)] = &[
    (
        "logEvents",
        "Life-cycle events: initialization (particle count), termination, reset, FMU state restored",
    ),
    (
        "logStatusWarning",
        "Messages of calls that return fmi2Warning",
    ),
    (
        "logStatusDiscard",
        "Messages of calls that return fmi2Discard, e.g. a numerical breakdown in fmi2DoStep",
    ),
    (
        "logStatusError",
        "Messages of calls that return fmi2Error: refused parameter values, illegal call sequences",
    ),
    (
        "logAll",
        "Everything above plus a trace of every FMI call with its arguments",
    ),
];

/// One unit of the unitDefinitions: name and exponents of kg, m, s, rad, with the factor to SI.
struct UnitDef {
    name: &'static str,
    kg: i32,
    m: i32,
    s: i32,
    rad: i32,
    factor: f64,
}

const fn unit(name: &'static str, kg: i32, m: i32, s: i32) -> UnitDef {
    UnitDef {
        name,
        kg,
        m,
        s,
        rad: 0,
        factor: 1.0,
    }
}

/// Every unit the tables use (FMI 2.0 section 2.2.2, `BaseUnit` exponents of SI base units).
const UNITS: &[UnitDef] = &[
    unit("1", 0, 0, 0),
    unit("m", 0, 1, 0),
    unit("m/s", 0, 1, -1),
    UnitDef {
        name: "deg",
        kg: 0,
        m: 0,
        s: 0,
        rad: 1,
        factor: std::f64::consts::PI / 180.0,
    },
    unit("kg/m3", 1, -3, 0),
    unit("m/s2", 0, 1, -2),
    unit("Pa.s", 1, -1, -1),
    unit("s", 0, 0, 1),
    unit("N/m", 1, 0, -2),
    unit("J/m", 1, 1, -2),
    unit("N.m/m", 1, 1, -2),
    unit("m2/s", 0, 2, -1),
    unit("Pa", 1, -1, -2),
    unit("kg/m", 1, -1, 0),
    unit("N", 1, 1, -2),
    unit("J", 1, 2, -2),
    unit("Hz", 0, 0, -1),
];

/// Escape text for an XML attribute value.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Description of a parameter as written to the XML. FMI `min`/`max` are inclusive, so a bound
/// the table excludes (a diameter must be > 0) is spelled out in the description.
pub fn parameter_description(p: &crate::config::ParamSpec) -> String {
    match p.kind {
        Kind::Real {
            min_open, max_open, ..
        } if min_open || max_open => {
            format!("{}. Allowed range {}", p.description, range_text(&p.kind))
        }
        _ => p.description.to_string(),
    }
}

/// Description of the String twin of Enumeration parameter `p`: what it sets and the names
/// it takes (importers that cannot show TypeDefinitions show this).
pub fn name_variable_description(p: &ParamSpec) -> String {
    format!(
        "{} ({}), by item name: one of {}. Sets the same parameter as the Enumeration '{}' \
         (the last value set wins); for importers that cannot set Enumerations",
        p.description,
        p.name,
        range_text(&p.kind),
        p.name
    )
}

/// Start value of the String twin of `p`: the Enumeration's default item.
pub fn name_variable_start(p: &ParamSpec) -> &'static str {
    match p.kind {
        Kind::Enumeration { default, .. } => default,
        _ => unreachable!("twins exist only for enumerations"),
    }
}

/// The units the tables use, in table order, each once.
fn used_units() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    let all = PARAMS
        .iter()
        .map(|p| p.unit)
        .chain(OUTPUTS.iter().map(|o| o.unit));
    for u in all {
        if !u.is_empty() && !names.contains(&u) {
            names.push(u);
        }
    }
    names
}

/// The `<UnitDefinitions>` element, the same in FMI 2.0 and 3.0: every unit the tables use,
/// in table order.
pub(crate) fn unit_definitions() -> String {
    let mut x = String::new();
    let w = &mut x;
    let _ = writeln!(w, "  <UnitDefinitions>");
    for name in used_units() {
        let u = UNITS
            .iter()
            .find(|u| u.name == name)
            .unwrap_or_else(|| panic!("unit '{name}' used in the tables has no definition"));
        let mut attrs = String::new();
        for (sym, e) in [("kg", u.kg), ("m", u.m), ("s", u.s), ("rad", u.rad)] {
            if e != 0 {
                let _ = write!(attrs, r#" {sym}="{e}""#);
            }
        }
        if u.factor != 1.0 {
            let _ = write!(attrs, r#" factor="{:e}""#, u.factor);
        }
        let _ = writeln!(
            w,
            r#"    <Unit name="{}"><BaseUnit{attrs}/></Unit>"#,
            escape(u.name)
        );
    }
    let _ = writeln!(w, "  </UnitDefinitions>");
    x
}

/// The enumeration types of the table, in table order: each one's name and items.
pub(crate) fn enumeration_types(
) -> impl Iterator<Item = (&'static str, &'static [(&'static str, &'static str)])> {
    PARAMS.iter().filter_map(|p| match p.kind {
        Kind::Enumeration {
            type_name, items, ..
        } => Some((type_name, items)),
        _ => None,
    })
}

/// The `<Item>` elements of an enumeration type (the same in FMI 2.0 and 3.0), 1-based.
pub(crate) fn enumeration_items(items: &[(&str, &str)], indent: &str) -> String {
    let mut x = String::new();
    for (i, (name, descr)) in items.iter().enumerate() {
        let _ = writeln!(
            x,
            r#"{indent}<Item name="{}" value="{}" description="{}"/>"#,
            escape(name),
            i + 1,
            escape(descr)
        );
    }
    x
}

/// The `<LogCategories>` element, its descriptions in the words of `api`.
pub(crate) fn log_categories(api: Api) -> String {
    let mut x = String::new();
    let _ = writeln!(x, "  <LogCategories>");
    for (name, descr) in LOG_CATEGORIES {
        let _ = writeln!(
            x,
            r#"    <Category name="{name}" description="{}"/>"#,
            escape(&api.wording(descr))
        );
    }
    let _ = writeln!(x, "  </LogCategories>");
    x
}

/// The attributes of `<fmiModelDescription>` that FMI 2.0 and 3.0 share (after `modelName`
/// and the GUID or instantiation token), one per line; `source` is the generator's file.
pub(crate) fn shared_root_attributes(source: &str) -> String {
    format!(
        r#"  description="{}"
  version="{}"
  license="MIT"
  generationTool="ViscoSPH {} ({source})"
  variableNamingConvention="flat""#,
        escape(
            "Transient viscoelastic and shear-thinning free-surface flows by SPH, in 2D and 3D: \
             a drop impacting a possibly inclined, possibly moving rigid plate (the default \
             scene), channel start-up, a buckling jet, the elliptical drop and a periodic array \
             of cylinders"
        ),
        env!("CARGO_PKG_VERSION"),
        env!("CARGO_PKG_VERSION"),
    )
}

/// Placeholder replaced by the GUID once the rest of the document is known.
const GUID_PLACEHOLDER: &str = "@GUID@";

/// The document with a placeholder instead of the GUID.
fn document_without_guid() -> String {
    let mut x = String::new();
    let w = &mut x;
    // `write!` into a String cannot fail; the results are ignored below for brevity.
    let _ = writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        w,
        r#"<fmiModelDescription
  fmiVersion="2.0"
  modelName="{MODEL_IDENTIFIER}"
  guid="{GUID_PLACEHOLDER}"
{}
  numberOfEventIndicators="0">"#,
        shared_root_attributes("src/fmi2/model_description.rs")
    );
    // FMI 2.0 section 4.3.1: capability flags of the Co-Simulation interface.
    let _ = writeln!(
        w,
        r#"  <CoSimulation
    modelIdentifier="{MODEL_IDENTIFIER}"
    needsExecutionTool="false"
    canHandleVariableCommunicationStepSize="true"
    canInterpolateInputs="false"
    maxOutputDerivativeOrder="0"
    canRunAsynchronuously="false"
    canBeInstantiatedOnlyOncePerProcess="false"
    canNotUseMemoryManagementFunctions="true"
    canGetAndSetFMUstate="true"
    canSerializeFMUstate="true"
    providesDirectionalDerivative="false"/>"#
    );

    w.push_str(&unit_definitions());

    let _ = writeln!(w, "  <TypeDefinitions>");
    for (type_name, items) in enumeration_types() {
        let _ = writeln!(w, r#"    <SimpleType name="{type_name}">"#);
        let _ = writeln!(w, "      <Enumeration>");
        w.push_str(&enumeration_items(items, "        "));
        let _ = writeln!(w, "      </Enumeration>");
        let _ = writeln!(w, "    </SimpleType>");
    }
    let _ = writeln!(w, "  </TypeDefinitions>");

    w.push_str(&log_categories(Api::Fmi2));

    let _ = writeln!(
        w,
        r#"  <DefaultExperiment startTime="0" stopTime="{DEFAULT_STOP_TIME}" stepSize="{DEFAULT_STEP_SIZE}"/>"#
    );

    let vars = model_variables();
    let _ = writeln!(w, "  <ModelVariables>");
    let mut index = 0usize;
    let mut outputs = Vec::new();
    for v in &vars {
        for (name, vr) in v.scalars() {
            index += 1;
            if v.causality == Causality::Output {
                outputs.push(index);
            }
            let _ = writeln!(w, "    <!-- index {index} -->");
            let initial = v
                .initial
                .map(|i| format!(r#" initial="{i}""#))
                .unwrap_or_default();
            let _ = writeln!(
                w,
                r#"    <ScalarVariable name="{}" valueReference="{vr}" description="{}" causality="{}" variability="{}"{initial}>"#,
                escape(&name),
                escape(&v.description),
                v.causality.name(),
                v.variability,
            );
            let unit = v.unit_attribute();
            let _ = match &v.kind {
                VarKind::Real { start: None, .. } => writeln!(w, "      <Real{unit}/>"),
                VarKind::Real {
                    start: Some(start),
                    min,
                    max,
                    ..
                } => writeln!(
                    w,
                    r#"      <Real{unit} start="{start}" min="{min}" max="{max}"/>"#
                ),
                VarKind::Integer { start, min, max } => writeln!(
                    w,
                    r#"      <Integer start="{start}" min="{min}" max="{max}"/>"#
                ),
                VarKind::Enumeration { type_name, start } => writeln!(
                    w,
                    r#"      <Enumeration declaredType="{type_name}" start="{start}"/>"#
                ),
                VarKind::String { start } => {
                    writeln!(w, r#"      <String start="{}"/>"#, escape(start))
                }
            };
            let _ = writeln!(w, "    </ScalarVariable>");
        }
    }
    let _ = writeln!(w, "  </ModelVariables>");

    // FMI 2.0 section 2.2.8: every output is listed under Outputs, and, being initial =
    // "calculated", under InitialUnknowns (nothing else is: the other variables are parameters
    // with initial = "exact" and inputs).
    //
    // Outputs: `dependencies=""`, no direct feed-through. An output is the state's at the last
    // communication point, and an input acts only on the steps after it (the plate moves during
    // the next fmi2DoStep), so after fmi2SetReal the outputs stay bitwise what they were until
    // the next fmi2DoStep (measured bitwise by a test in src/fmi2/instance/tests.rs). Without the attribute a master must assume
    // every output depends on every input and finds an algebraic loop in any two-way coupling.
    //
    // InitialUnknowns: without `dependencies`, each depends on all knowns, which is the truth
    // (the initial state is built from the parameters, and a scene may build it from an input's
    // start value, e.g. the jet's inflow speed).
    let _ = writeln!(w, "  <ModelStructure>");
    let _ = writeln!(w, "    <Outputs>");
    for i in &outputs {
        let _ = writeln!(w, r#"      <Unknown index="{i}" dependencies=""/>"#);
    }
    let _ = writeln!(w, "    </Outputs>");
    let _ = writeln!(w, "    <InitialUnknowns>");
    for i in &outputs {
        let _ = writeln!(w, r#"      <Unknown index="{i}"/>"#);
    }
    let _ = writeln!(w, "    </InitialUnknowns>");
    let _ = writeln!(w, "  </ModelStructure>");
    let _ = writeln!(w, "</fmiModelDescription>");
    x
}

/// 64-bit FNV-1a hash, seeded: deterministic across builds and platforms, unlike `std`'s hasher.
fn fnv1a(bytes: &[u8], seed: u64) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ seed;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The GUID of this interface: a hash of the model description without its GUID, written in
/// the usual `{8-4-4-4-12}` form.
pub fn guid() -> String {
    guid_of(&document_without_guid())
}

fn guid_of(doc: &str) -> String {
    let a = fnv1a(doc.as_bytes(), 0);
    let b = fnv1a(doc.as_bytes(), 0x9e37_79b9_7f4a_7c15);
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

/// The complete `modelDescription.xml`.
pub fn model_description_xml() -> String {
    let doc = document_without_guid();
    let g = guid_of(&doc);
    doc.replacen(GUID_PLACEHOLDER, &g, 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guid_is_stable_and_well_formed() {
        let g = guid();
        assert_eq!(g, guid());
        assert_eq!(g.len(), 38, "{g}");
        assert!(g.starts_with('{') && g.ends_with('}'));
        assert!(model_description_xml().contains(&format!(r#"guid="{g}""#)));
    }

    #[test]
    fn every_used_unit_is_defined() {
        for u in used_units() {
            assert!(UNITS.iter().any(|d| d.name == u), "unit {u}");
        }
    }

    #[test]
    fn escape_handles_markup() {
        assert_eq!(escape(r#"0 <= a & "b""#), "0 &lt;= a &amp; &quot;b&quot;");
    }
}
