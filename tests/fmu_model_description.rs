//! `modelDescription/modelDescription.xml` against the tables it is generated from.
//!
//! Two checks, so the XML and the solver cannot drift apart: the committed file is byte for
//! byte what `viscosph::fmi2::model_description_xml()` generates from `PARAMS` and `OUTPUTS`
//! today, and, parsed with a general XML parser (roxmltree), every variable's name, value
//! reference, causality, variability, type, start, min, max and unit is the table's (FMI 2.0
//! section 2.2.7), the enumeration types list the table's items in order, every unit used is
//! defined, names and value references are unique, and the ModelStructure lists exactly the
//! outputs (section 2.2.8).

use roxmltree::{Document, Node};
use std::collections::HashSet;
use viscosph::config::{Kind, Value};
use viscosph::fmi2::model_description::{name_variable_description, parameter_description};
use viscosph::fmi2::{guid, model_description_xml};
use viscosph::scene::{name_variables, param_spec, SceneConfig, PARAMS};
use viscosph::scene::{OUTPUTS, OUTPUT_ARRAYS};

const PATH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/modelDescription/modelDescription.xml"
);

fn committed() -> String {
    std::fs::read_to_string(PATH).expect("modelDescription/modelDescription.xml exists")
}

fn child<'a, 'i>(n: Node<'a, 'i>, tag: &str) -> Node<'a, 'i> {
    n.children()
        .find(|c| c.has_tag_name(tag))
        .unwrap_or_else(|| panic!("<{}> has no <{tag}>", n.tag_name().name()))
}

fn elements<'a, 'i>(n: Node<'a, 'i>, tag: &'a str) -> impl Iterator<Item = Node<'a, 'i>> + 'a {
    n.children().filter(move |c| c.has_tag_name(tag))
}

fn attr<'a>(n: Node<'a, '_>, name: &str) -> &'a str {
    n.attribute(name).unwrap_or_else(|| {
        panic!(
            "<{} name={:?}> has no attribute {name}",
            n.tag_name().name(),
            n.attribute("name")
        )
    })
}

fn num(n: Node, name: &str) -> f64 {
    attr(n, name)
        .parse()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn committed_file_is_the_generated_one() {
    assert!(
        committed() == model_description_xml(),
        "modelDescription/modelDescription.xml is stale: run \
         `cargo run --release -p fmu-build -- --write-model-description` and commit it"
    );
}

#[test]
fn every_variable_matches_the_tables() {
    let text = committed();
    let doc = Document::parse(&text).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "fmiModelDescription");
    assert_eq!(attr(root, "fmiVersion"), "2.0");
    assert_eq!(attr(root, "guid"), guid());

    // Co-Simulation only, with the capability flags of issue 3.
    assert!(root.children().all(|c| !c.has_tag_name("ModelExchange")));
    let cs = child(root, "CoSimulation");
    assert_eq!(attr(cs, "modelIdentifier"), "ViscoSPH");
    for (flag, value) in [
        ("canHandleVariableCommunicationStepSize", "true"),
        ("canGetAndSetFMUstate", "true"),
        ("canSerializeFMUstate", "true"),
        ("canNotUseMemoryManagementFunctions", "true"),
        ("canBeInstantiatedOnlyOncePerProcess", "false"),
    ] {
        assert_eq!(attr(cs, flag), value, "{flag}");
    }

    let units: HashSet<&str> = elements(child(root, "UnitDefinitions"), "Unit")
        .map(|u| attr(u, "name"))
        .collect();
    let types: Vec<Node> = elements(child(root, "TypeDefinitions"), "SimpleType").collect();

    let vars: Vec<Node> = elements(child(root, "ModelVariables"), "ScalarVariable").collect();
    assert_eq!(
        vars.len(),
        PARAMS.len() + OUTPUTS.len() + name_variables().count()
    );
    let names: HashSet<&str> = vars.iter().map(|v| attr(*v, "name")).collect();
    assert_eq!(names.len(), vars.len(), "variable names are unique");
    let vrs: HashSet<&str> = vars.iter().map(|v| attr(*v, "valueReference")).collect();
    assert_eq!(vrs.len(), vars.len(), "value references are unique");

    let find = |name: &str| -> (usize, Node) {
        vars.iter()
            .enumerate()
            .find(|(_, v)| v.attribute("name") == Some(name))
            .map(|(i, v)| (i + 1, *v))
            .unwrap_or_else(|| panic!("{name} is not in modelDescription.xml"))
    };
    let unit_ok = |elem: Node, unit: &str| {
        if unit.is_empty() {
            assert!(elem.attribute("unit").is_none());
        } else {
            assert_eq!(attr(elem, "unit"), unit);
            assert!(units.contains(unit), "unit {unit} is defined");
        }
    };

    for p in PARAMS.iter() {
        let (_, v) = find(p.name);
        assert_eq!(
            num(v, "valueReference"),
            p.value_reference as f64,
            "{}",
            p.name
        );
        let (index, _) = find(p.name);
        if p.is_input() {
            // FMI 2.0 section 2.2.7: an input is continuous, has a start value and no
            // `initial`; listed after the outputs and the String twins.
            assert_eq!(attr(v, "causality"), "input", "{}", p.name);
            assert_eq!(attr(v, "variability"), "continuous", "{}", p.name);
            assert!(v.attribute("initial").is_none(), "{}", p.name);
            assert!(
                index > PARAMS.len() + OUTPUTS.len(),
                "{} after the outputs",
                p.name
            );
        } else {
            assert_eq!(attr(v, "causality"), "parameter", "{}", p.name);
            assert_eq!(attr(v, "variability"), "fixed", "{}", p.name);
            assert_eq!(attr(v, "initial"), "exact", "{}", p.name);
        }
        assert_eq!(attr(v, "description"), parameter_description(p));
        match p.kind {
            Kind::Real {
                default, min, max, ..
            } => {
                let e = child(v, "Real");
                assert_eq!(num(e, "start"), default, "{}", p.name);
                assert_eq!(num(e, "min"), min, "{}", p.name);
                assert_eq!(num(e, "max"), max, "{}", p.name);
                unit_ok(e, p.unit);
            }
            Kind::Integer { default, min, max } => {
                let e = child(v, "Integer");
                assert_eq!(num(e, "start"), default as f64, "{}", p.name);
                assert_eq!(num(e, "min"), min as f64, "{}", p.name);
                assert_eq!(num(e, "max"), max as f64, "{}", p.name);
            }
            Kind::Enumeration {
                type_name,
                items,
                default,
            } => {
                let e = child(v, "Enumeration");
                assert_eq!(attr(e, "declaredType"), type_name);
                let start = items.iter().position(|(n, _)| *n == default).unwrap() + 1;
                assert_eq!(num(e, "start"), start as f64, "{}", p.name);
                let t = types
                    .iter()
                    .find(|t| t.attribute("name") == Some(type_name))
                    .unwrap_or_else(|| panic!("type {type_name} is defined"));
                let listed: Vec<(String, String)> = elements(child(*t, "Enumeration"), "Item")
                    .map(|i| (attr(i, "name").to_string(), attr(i, "value").to_string()))
                    .collect();
                let expected: Vec<(String, String)> = items
                    .iter()
                    .enumerate()
                    .map(|(k, (n, _))| (n.to_string(), (k + 1).to_string()))
                    .collect();
                assert_eq!(listed, expected, "{type_name}");
            }
        }
    }

    let mut output_indices = Vec::new();
    for o in OUTPUTS.iter() {
        let (index, v) = find(o.name);
        output_indices.push(index.to_string());
        assert_eq!(
            num(v, "valueReference"),
            o.value_reference as f64,
            "{}",
            o.name
        );
        assert_eq!(attr(v, "causality"), "output");
        assert_eq!(attr(v, "variability"), "continuous");
        assert_eq!(attr(v, "initial"), "calculated");
        assert_eq!(attr(v, "description"), o.description);
        let e = child(v, "Real");
        assert!(e.attribute("start").is_none(), "calculated: no start");
        unit_ok(e, o.unit);
    }

    // The String twin of every Enumeration: a fixed parameter whose start is the default item,
    // listed after the outputs.
    let mut twins = 0;
    for (p, name, vr) in name_variables() {
        twins += 1;
        let (index, v) = find(&name);
        assert!(
            index > PARAMS.len() - PARAMS.iter().filter(|p| p.input).count() + OUTPUTS.len(),
            "{name} after the outputs"
        );
        assert_eq!(num(v, "valueReference"), vr as f64, "{name}");
        assert_eq!(attr(v, "causality"), "parameter", "{name}");
        assert_eq!(attr(v, "variability"), "fixed", "{name}");
        assert_eq!(attr(v, "initial"), "exact", "{name}");
        assert_eq!(attr(v, "description"), name_variable_description(p));
        let Kind::Enumeration { default, items, .. } = p.kind else {
            panic!("{name} twins an enumeration")
        };
        assert_eq!(attr(child(v, "String"), "start"), default, "{name}");
        for (item, _) in items {
            assert!(
                attr(v, "description").contains(&format!("'{item}'")),
                "{name}"
            );
        }
    }
    // One per Enumeration parameter of the table.
    assert_eq!(
        twins,
        PARAMS
            .iter()
            .filter(|p| matches!(p.kind, Kind::Enumeration { .. }))
            .count()
    );
    assert_eq!(twins, 13);

    let ms = child(root, "ModelStructure");
    for list in ["Outputs", "InitialUnknowns"] {
        let listed: Vec<String> = elements(child(ms, list), "Unknown")
            .map(|u| attr(u, "index").to_string())
            .collect();
        assert_eq!(listed, output_indices, "ModelStructure/{list}");
    }
}

/// FMI 2.0 section 2.2.8, read from the parsed XML: every output is listed once under Outputs
/// with `dependencies=""` (no output depends directly on an input: an input acts on the steps
/// after it, see the instance's test of bitwise unchanged outputs after fmi2SetReal), and
/// InitialUnknowns lists exactly the variables the standard requires there (outputs with
/// initial "approx" or "calculated", calculated parameters; no states in Co-Simulation), in
/// ascending index order, without a `dependencies` attribute (each depends on all knowns: the
/// initial state is built from the parameters and the inputs' start values).
#[test]
fn model_structure_declares_no_direct_feed_through() {
    let text = committed();
    let doc = Document::parse(&text).expect("well-formed XML");
    let root = doc.root_element();
    let vars: Vec<Node> = elements(child(root, "ModelVariables"), "ScalarVariable").collect();
    let index_of = |u: Node| -> usize {
        let i: usize = attr(u, "index").parse().expect("an index");
        assert!((1..=vars.len()).contains(&i), "index {i}");
        i
    };
    let with = |pred: &dyn Fn(Node) -> bool| -> Vec<usize> {
        vars.iter()
            .enumerate()
            .filter(|(_, v)| pred(**v))
            .map(|(k, _)| k + 1)
            .collect()
    };
    let outputs = with(&|v| attr(v, "causality") == "output");
    assert_eq!(outputs.len(), OUTPUTS.len());
    let ms = child(root, "ModelStructure");

    let listed: Vec<Node> = elements(child(ms, "Outputs"), "Unknown").collect();
    assert_eq!(
        listed.iter().map(|u| index_of(*u)).collect::<Vec<_>>(),
        outputs,
        "Outputs lists every output once, in index order"
    );
    for u in &listed {
        assert_eq!(
            u.attribute("dependencies"),
            Some(""),
            "output {} declares no direct dependency",
            attr(vars[index_of(*u) - 1], "name")
        );
        assert!(u.attribute("dependenciesKind").is_none());
    }

    let initial = with(&|v| {
        let calculated = matches!(v.attribute("initial"), Some("approx" | "calculated"));
        match attr(v, "causality") {
            "output" => calculated || v.attribute("initial").is_none(),
            "calculatedParameter" => true,
            _ => false,
        }
    });
    let listed: Vec<Node> = elements(child(ms, "InitialUnknowns"), "Unknown").collect();
    assert_eq!(
        listed.iter().map(|u| index_of(*u)).collect::<Vec<_>>(),
        initial
    );
    assert!(listed.iter().all(|u| u.attribute("dependencies").is_none()));
    // Co-Simulation without continuous states: no Derivatives.
    assert!(ms.children().all(|c| !c.has_tag_name("Derivatives")));
}

/// The parameter `drop_height` of early scene files is `initial_drop_height` in the FMU (the
/// name `drop_height` belongs to an output, and FMU names are unique); both names set it.
#[test]
fn drop_height_is_the_older_name_of_initial_drop_height() {
    assert_eq!(
        param_spec("drop_height").map(|p| p.name),
        Some("initial_drop_height")
    );
    let mut a = SceneConfig::default();
    let mut b = SceneConfig::default();
    a.set("drop_height", Value::Real(0.05)).unwrap();
    b.set("initial_drop_height", Value::Real(0.05)).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.drop.initial_drop_height, 0.05);
    assert_eq!(a.get("initial_drop_height").unwrap(), Value::Real(0.05));
}

/// The FMI 3.0 model description (`modelDescription/fmi3/modelDescription.xml`): the committed
/// file is the generated one, and, parsed, every variable of the FMI 2.0 description is there
/// with the same value reference, causality, variability, start, range and unit (FMI 3.0
/// section 2.4.7: Float64 for Real, Int32 for Integer, Enumeration, String with a `<Start>`
/// child), one independent variable `time`, one Float64 array per array row of the output
/// table (`wall_pressure`, `wall_shear`: `<Dimension start="24"/>`, the unit and causality of
/// its elements, which stay scalar variables of their own), and the ModelStructure lists
/// exactly the outputs, by value reference, with `dependencies=""` as Output.
#[test]
fn fmi3_model_description_has_the_same_variables() {
    const PATH3: &str = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/modelDescription/fmi3/modelDescription.xml"
    );
    let text3 = std::fs::read_to_string(PATH3).expect("the FMI 3.0 model description exists");
    assert!(
        text3 == viscosph::fmi3::model_description_xml(),
        "modelDescription/fmi3/modelDescription.xml is stale: run \
         `cargo run --release -p fmu-build -- --write-model-description` and commit it"
    );
    let doc3 = Document::parse(&text3).expect("well-formed XML");
    let root3 = doc3.root_element();
    assert_eq!(attr(root3, "fmiVersion"), "3.0");
    assert_eq!(attr(root3, "instantiationToken"), guid());
    let vars3: Vec<Node> = child(root3, "ModelVariables")
        .children()
        .filter(|n| n.is_element())
        .collect();
    let text2 = committed();
    let doc2 = Document::parse(&text2).expect("well-formed XML");
    let vars2: Vec<Node> = elements(
        child(doc2.root_element(), "ModelVariables"),
        "ScalarVariable",
    )
    .collect();
    assert_eq!(
        vars3.len(),
        vars2.len() + 1 + OUTPUT_ARRAYS.len(),
        "FMI 2.0's variables, time and the arrays"
    );
    for a in OUTPUT_ARRAYS.iter() {
        let v3 = vars3
            .iter()
            .find(|v| v.attribute("name") == Some(a.name))
            .unwrap_or_else(|| panic!("array {} is not in the FMI 3.0 description", a.name));
        assert_eq!(v3.tag_name().name(), "Float64");
        assert_eq!(attr(*v3, "valueReference"), a.value_reference.to_string());
        let len = a.len.to_string();
        assert_eq!(
            child(*v3, "Dimension").attribute("start"),
            Some(len.as_str())
        );
        for k in 1..=a.len {
            let element = format!("{}_{k:03}", a.name);
            let e2 = vars2
                .iter()
                .find(|v| v.attribute("name") == Some(element.as_str()))
                .unwrap_or_else(|| panic!("{element} is not in the FMI 2.0 description"));
            assert_eq!(
                attr(*e2, "valueReference"),
                (a.first_element_vr + k as u32 - 1).to_string()
            );
            for at in ["causality", "variability", "initial"] {
                assert_eq!(v3.attribute(at), e2.attribute(at), "{}: {at}", a.name);
            }
            let unit2 = e2
                .children()
                .find(|c| c.is_element())
                .unwrap()
                .attribute("unit");
            assert_eq!(v3.attribute("unit"), unit2, "{}", a.name);
        }
    }
    let independent: Vec<&Node> = vars3
        .iter()
        .filter(|v| v.attribute("causality") == Some("independent"))
        .collect();
    assert_eq!(independent.len(), 1);
    assert_eq!(attr(*independent[0], "name"), "time");
    for v2 in &vars2 {
        let name = attr(*v2, "name");
        let v3 = vars3
            .iter()
            .find(|v| v.attribute("name") == Some(name))
            .unwrap_or_else(|| panic!("{name} is not in the FMI 3.0 description"));
        for a in ["valueReference", "causality", "variability", "initial"] {
            assert_eq!(v3.attribute(a), v2.attribute(a), "{name}: {a}");
        }
        let ty2 = v2
            .children()
            .find(|c| c.is_element())
            .expect("a type element");
        let expected = match ty2.tag_name().name() {
            "Real" => "Float64",
            "Integer" => "Int32",
            other => other,
        };
        assert_eq!(v3.tag_name().name(), expected, "{name}");
        if expected == "String" {
            assert_eq!(
                child(*v3, "Start").attribute("value"),
                ty2.attribute("start"),
                "{name}"
            );
        } else {
            for a in ["start", "min", "max", "unit", "declaredType"] {
                assert_eq!(v3.attribute(a), ty2.attribute(a), "{name}: {a}");
            }
        }
    }
    let ms = child(root3, "ModelStructure");
    let output_vrs: Vec<&str> = vars3
        .iter()
        .filter(|v| v.attribute("causality") == Some("output"))
        .map(|v| attr(*v, "valueReference"))
        .collect();
    assert_eq!(output_vrs.len(), OUTPUTS.len() + OUTPUT_ARRAYS.len());
    let listed: Vec<&str> = elements(ms, "Output")
        .map(|u| {
            assert_eq!(u.attribute("dependencies"), Some(""));
            attr(u, "valueReference")
        })
        .collect();
    assert_eq!(listed, output_vrs);
    let initial: Vec<&str> = elements(ms, "InitialUnknown")
        .map(|u| attr(u, "valueReference"))
        .collect();
    assert_eq!(initial, output_vrs);
    let types3: Vec<&str> = elements(child(root3, "TypeDefinitions"), "EnumerationType")
        .map(|t| attr(t, "name"))
        .collect();
    let types2: Vec<&str> = elements(child(doc2.root_element(), "TypeDefinitions"), "SimpleType")
        .map(|t| attr(t, "name"))
        .collect();
    assert_eq!(types3, types2);
}
