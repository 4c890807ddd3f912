//! `viscosph docs-tables <dir>`: the manual's tables of parameters, outputs, choices and FMU
//! variables, written as markdown files that the book (`docs/book/`) includes. They come from
//! the same tables that generate the FMU's `modelDescription.xml` ([`PARAMS`], [`OUTPUTS`], the
//! scene registry), so a parameter is never typed twice; `cli/tests/docs_tables.rs` fails when
//! the committed files differ from what this module writes.

use std::fmt::Write as _;
use std::path::Path;
use viscosph::choice::Choice;
use viscosph::config::{
    range_text, Checked, FluidParams, Kind, Numerics, ParamGroup, ParamSpec, PlateParams, Value,
};
use viscosph::diagnostics::{OutputGroup, OutputSpec, SharedOutputs};
use viscosph::scene::{
    channel::Channel, cylinder_array::CylinderArray, drop::Drop, elliptical_drop::EllipticalDrop,
    jet::Jet, name_variables, Scene, SceneConfig, SceneKind, SceneType, OUTPUTS, PARAMS, SCENES,
};

/// What the manual says about one scene: its registry entry and its own groups.
struct SceneTables {
    name: &'static str,
    description: &'static str,
    params: Vec<&'static ParamSpec>,
    outputs: &'static [OutputSpec],
}

fn scene_tables<S: SceneType>() -> SceneTables {
    let mut params = Vec::new();
    S::Params::collect_rows(&mut params);
    SceneTables {
        name: S::NAME,
        description: S::DESCRIPTION,
        params,
        outputs: S::Outputs::rows(),
    }
}

/// Every scene's tables, in registry order. The list of types is the registry's (`scenes!` in
/// `src/scene/mod.rs`); a scene added there and not here makes [`tables`] fail, so the book
/// cannot leave one out.
fn scenes() -> Result<Vec<SceneTables>, String> {
    let list = vec![
        scene_tables::<Drop>(),
        scene_tables::<Jet>(),
        scene_tables::<Channel>(),
        scene_tables::<EllipticalDrop>(),
        scene_tables::<CylinderArray>(),
    ];
    let ours: Vec<&str> = list.iter().map(|s| s.name).collect();
    let registry: Vec<&str> = SCENES.iter().map(|(n, _)| *n).collect();
    if ours != registry {
        return Err(format!(
            "the scene registry lists {registry:?}, the manual's generator {ours:?}: add the new \
             scene to cli/src/docs_tables.rs"
        ));
    }
    Ok(list)
}

/// A markdown table cell: pipes escaped, no line breaks.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

fn unit_text(unit: &str) -> &str {
    match unit {
        "" | "1" => "-",
        u => u,
    }
}

fn default_text(p: &ParamSpec) -> String {
    match p.kind {
        Kind::Real { default, .. } => format!("{default}"),
        Kind::Integer { default, .. } => format!("{default}"),
        Kind::Enumeration { default, .. } => format!("`{default}`"),
    }
}

fn type_text(p: &ParamSpec) -> &'static str {
    match p.kind {
        Kind::Real { .. } => "Real",
        Kind::Integer { .. } => "Integer",
        Kind::Enumeration { .. } => "Enumeration",
    }
}

/// Two different values a row accepts: its default and another one in its range.
fn probe_values(p: &ParamSpec) -> [Checked; 2] {
    match p.kind {
        Kind::Real {
            default, min, max, ..
        } => {
            // Half the default's size away from it (at least 0.5), inside the range: up if
            // there is room, else halfway down to the lower bound.
            let up = default + 0.5 * default.abs().max(1.0);
            let other = if up < max { up } else { 0.5 * (default + min) };
            [Checked::Real(default), Checked::Real(other)]
        }
        Kind::Integer { default, min, max } => {
            let other = if default < max {
                default + 1
            } else {
                default.max(min + 1) - 1
            };
            [Checked::Integer(default), Checked::Integer(other)]
        }
        Kind::Enumeration { items, default, .. } => {
            let other = items
                .iter()
                .map(|(n, _)| *n)
                .find(|n| *n != default)
                .unwrap_or(default);
            [Checked::Item(default), Checked::Item(other)]
        }
    }
}

fn value_text(p: &ParamSpec, v: &Value) -> String {
    match (p.kind, v) {
        (Kind::Enumeration { items, .. }, Value::Integer(i)) if *i >= 1 => items
            .get(*i as usize - 1)
            .map(|(n, _)| format!("`{n}`"))
            .unwrap_or_else(|| i.to_string()),
        (_, v) => v.to_string(),
    }
}

/// The scenes that fix a shared parameter whatever the configuration says (their
/// [`Scene::effective_config`]: the channel switches gravity off, the elliptical drop keeps its
/// own fluid), with the value they run, found by giving the parameter two different values; and
/// for the input that moves a plate, the scenes whose plate it moves.
fn fixed_by(p: &ParamSpec) -> String {
    let mut parts = Vec::new();
    for (name, _) in SCENES.iter() {
        let kind = SceneKind::from_name(name).expect("registry name");
        let scene: &dyn Scene = kind.scene();
        let runs: Vec<Option<Value>> = probe_values(p)
            .into_iter()
            .map(|v| {
                let mut cfg = SceneConfig::for_scene(kind);
                assert!(cfg.store(p.name, v), "{} is not a parameter", p.name);
                scene.effective_config(&cfg).value(p.name)
            })
            .collect();
        if let [Some(a), Some(b)] = &runs[..] {
            if a == b {
                parts.push(format!("{name}: {}", value_text(p, a)));
            }
        }
    }
    if p.name == "plate_velocity" {
        let moved: Vec<&str> = SCENES
            .iter()
            .map(|(n, _)| *n)
            .filter(|n| SceneKind::from_name(n).is_some_and(|k| k.scene().has_moving_plate()))
            .collect();
        parts.push(format!("moves the plate of: {}", moved.join(", ")));
    }
    if parts.is_empty() {
        "-".into()
    } else {
        parts.join("; ")
    }
}

/// A table of parameter rows: name, value reference, type, unit, default, range, description.
fn param_table(rows: &[&ParamSpec], with_readers: bool) -> String {
    let mut md = String::new();
    if rows.is_empty() {
        md.push_str("This scene has no parameters of its own.\n");
        return md;
    }
    md.push_str("| name | VR | type | unit | default | range | description |");
    md.push_str(if with_readers {
        " fixed by a scene |\n"
    } else {
        "\n"
    });
    md.push_str("|---|---|---|---|---|---|---|");
    md.push_str(if with_readers { "---|\n" } else { "\n" });
    for p in rows {
        let mut desc = cell(p.description);
        if p.input && !p.description.to_lowercase().contains("input") {
            desc.push_str(" (FMU input: settable at every communication point)");
        }
        if let Some(a) = p.alias.filter(|a| !p.description.contains(a)) {
            let _ = write!(desc, " (older scene-file key: `{a}`)");
        }
        let _ = write!(
            md,
            "| `{}` | {} | {} | {} | {} | {} | {} |",
            p.name,
            p.value_reference,
            type_text(p),
            unit_text(p.unit),
            default_text(p),
            cell(&range_text(&p.kind)),
            desc
        );
        if with_readers {
            let _ = write!(md, " {} |", fixed_by(p));
        }
        md.push('\n');
    }
    md
}

fn output_table(rows: &[OutputSpec]) -> String {
    let mut md = String::new();
    if rows.is_empty() {
        md.push_str("This scene has no outputs of its own: it fills the shared ones.\n");
        return md;
    }
    md.push_str("| name | VR | unit | description |\n|---|---|---|---|\n");
    for o in rows {
        let _ = writeln!(
            md,
            "| `{}` | {} | {} | {} |",
            o.name,
            o.value_reference,
            unit_text(o.unit),
            cell(o.description)
        );
    }
    md
}

/// The items of every Enumeration parameter, one table each.
fn choices() -> String {
    let mut md = String::new();
    for p in PARAMS.iter() {
        if let Kind::Enumeration {
            type_name,
            items,
            default,
        } = p.kind
        {
            let _ = writeln!(
                md,
                "### `{}` (type {type_name}, default `{default}`)\n\n| item | index | meaning |\n|---|---|---|",
                p.name
            );
            for (k, (name, desc)) in items.iter().enumerate() {
                let _ = writeln!(md, "| `{name}` | {} | {} |", k + 1, cell(desc));
            }
            md.push('\n');
        }
    }
    md
}

/// The range column of the FMU table: an Enumeration's items are listed under "Choices" of
/// the parameters page (a long list would make every row of this table tall).
fn fmu_range(p: &ParamSpec) -> String {
    match p.kind {
        Kind::Enumeration { items, .. } => {
            format!("{} items: [choices](parameters.md#choices)", items.len())
        }
        _ => cell(&range_text(&p.kind)),
    }
}

/// Every FMU variable in value-reference order, as the model description declares it.
fn fmu_variables(scenes: &[SceneTables]) -> String {
    // The group a variable belongs to: the shared groups (every scene takes them) or a scene's
    // own (the other scenes ignore its parameters and hold its outputs at 0).
    let owner_of_output = |o: &OutputSpec| -> String {
        scenes
            .iter()
            .find(|s| s.outputs.iter().any(|r| r.name == o.name))
            .map(|s| format!("{} (0 in the others)", s.name))
            .unwrap_or_else(|| "shared".into())
    };
    let owner_of_param = |p: &ParamSpec| -> String {
        scenes
            .iter()
            .find(|s| s.params.iter().any(|r| r.name == p.name))
            .map(|s| s.name.to_string())
            .unwrap_or_else(|| "shared".into())
    };
    let mut md = String::from(
        "| name | VR | type | causality | unit | default | range | group |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut rows: Vec<(u32, String)> = Vec::new();
    for p in PARAMS.iter() {
        let causality = if p.input { "input" } else { "parameter" };
        rows.push((
            p.value_reference,
            format!(
                "| `{}` | {} | {} | {causality} | {} | {} | {} | {} |",
                p.name,
                p.value_reference,
                type_text(p),
                unit_text(p.unit),
                default_text(p),
                fmu_range(p),
                owner_of_param(p)
            ),
        ));
    }
    for (p, name, vr) in name_variables() {
        rows.push((
            vr,
            format!(
                "| `{name}` | {vr} | String | parameter | - | {} | item name of `{}` | {} |",
                default_text(p),
                p.name,
                owner_of_param(p)
            ),
        ));
    }
    for o in OUTPUTS.iter() {
        rows.push((
            o.value_reference,
            format!(
                "| `{}` | {} | Real | output | {} | - | - | {} |",
                o.name,
                o.value_reference,
                unit_text(o.unit),
                owner_of_output(o)
            ),
        ));
    }
    // Value references are unique within a type only; String twins have their own range.
    rows.sort_by_key(|(vr, _)| *vr);
    for (_, r) in rows {
        md.push_str(&r);
        md.push('\n');
    }
    md
}

/// The generated files: (file name, markdown).
pub fn tables() -> Result<Vec<(String, String)>, String> {
    let scenes = scenes()?;
    let header =
        "<!-- generated by `viscosph docs-tables docs/book/src/generated`: do not edit -->\n\n";
    let mut files = Vec::new();
    let mut add = |name: String, body: String| files.push((name, format!("{header}{body}")));
    let shared: [(&str, &[ParamSpec]); 3] = [
        ("fluid", FluidParams::ROWS),
        ("numerics", Numerics::ROWS),
        ("plate", PlateParams::ROWS),
    ];
    let selectors: Vec<&ParamSpec> = PARAMS
        .iter()
        .filter(|p| p.name == "scene" || p.name == "scheme")
        .copied()
        .collect();
    add("params_selectors.md".into(), param_table(&selectors, true));
    for (group, rows) in shared {
        let rows: Vec<&ParamSpec> = rows.iter().collect();
        add(format!("params_{group}.md"), param_table(&rows, true));
    }
    for s in &scenes {
        add(
            format!("params_{}.md", s.name),
            format!(
                "Scene `{}`: {}.\n\n{}",
                s.name,
                s.description,
                param_table(&s.params, false)
            ),
        );
        add(format!("outputs_{}.md", s.name), output_table(s.outputs));
    }
    add(
        "outputs_shared.md".into(),
        output_table(SharedOutputs::rows()),
    );
    add("choices.md".into(), choices());
    add("fmu_variables.md".into(), fmu_variables(&scenes));
    Ok(files)
}

/// Write the generated files into `dir` (created if missing).
pub fn write_tables(dir: &Path) -> Result<String, Box<dyn std::error::Error>> {
    std::fs::create_dir_all(dir)?;
    let files = tables()?;
    for (name, text) in &files {
        std::fs::write(dir.join(name), text)?;
    }
    Ok(format!(
        "wrote {} files into {}",
        files.len(),
        dir.display()
    ))
}
