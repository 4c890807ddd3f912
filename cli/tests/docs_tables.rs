//! The manual's generated tables (docs/book/src/generated) are what `viscosph docs-tables`
//! writes from the parameter table today: a parameter, output or choice added, renamed or given
//! another range or default without regenerating them fails here.

use std::path::Path;

#[test]
fn committed_tables_match_the_parameter_table() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/book/src/generated");
    let files = viscosph_cli::docs_tables::tables().expect("tables");
    assert!(files.len() >= 10, "{} files", files.len());
    let mut stale = Vec::new();
    for (name, text) in &files {
        match std::fs::read_to_string(dir.join(name)) {
            Ok(committed) if committed == *text => {}
            _ => stale.push(name.clone()),
        }
    }
    // No committed table that the generator no longer writes.
    for entry in std::fs::read_dir(&dir).expect("docs/book/src/generated") {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if !files.iter().any(|(n, _)| *n == name) {
            stale.push(format!("{name} (not generated any more)"));
        }
    }
    assert!(
        stale.is_empty(),
        "stale generated tables {stale:?}: run `cargo run --release -p viscosph-cli -- docs-tables docs/book/src/generated`"
    );
}

#[test]
fn tables_hold_every_variable_of_the_fmu() {
    let files = viscosph_cli::docs_tables::tables().expect("tables");
    let fmu = &files
        .iter()
        .find(|(n, _)| n == "fmu_variables.md")
        .unwrap()
        .1;
    for p in viscosph::scene::PARAMS.iter() {
        assert!(
            fmu.contains(&format!("| `{}` | {} |", p.name, p.value_reference)),
            "{}",
            p.name
        );
    }
    for o in viscosph::OUTPUTS.iter() {
        assert!(
            fmu.contains(&format!(
                "| `{}` | {} | Real | output |",
                o.name, o.value_reference
            )),
            "{}",
            o.name
        );
    }
    for (_, name, vr) in viscosph::scene::name_variables() {
        assert!(
            fmu.contains(&format!("| `{name}` | {vr} | String |")),
            "{name}"
        );
    }
}

/// The "fixed by a scene" column agrees with what the scenes say of themselves: the channel
/// switches gravity off, and the elliptical drop fixes only parameters outside the list of
/// those it takes from a scene file (`elliptical_drop::TAKEN`), among them its own fluid.
#[test]
fn fixed_parameters_are_the_scenes_own() {
    let files = viscosph_cli::docs_tables::tables().expect("tables");
    let text = |name: &str| files.iter().find(|(n, _)| n == name).unwrap().1.clone();
    let fluid = text("params_fluid.md");
    let gravity = fluid
        .lines()
        .find(|l| l.starts_with("| `gravity` |"))
        .unwrap();
    assert!(gravity.contains("channel: 0"), "{gravity}");
    let density = fluid
        .lines()
        .find(|l| l.starts_with("| `density` |"))
        .unwrap();
    assert!(density.contains("elliptical_drop: 1000"), "{density}");
    let taken = viscosph::scene::elliptical_drop::TAKEN;
    let mut fixed = 0;
    for file in ["params_fluid.md", "params_numerics.md", "params_plate.md"] {
        for line in text(file)
            .lines()
            .filter(|l| l.contains("elliptical_drop: "))
        {
            let name = line.split('`').nth(1).unwrap();
            assert!(!taken.contains(&name), "{name} is taken yet fixed: {line}");
            fixed += 1;
        }
    }
    assert!(fixed >= 5, "{fixed}");
    let plate = text("params_plate.md");
    assert!(plate.contains("moves the plate of: drop |"), "{plate}");
}

/// Every generated table is shown: some page of the book includes it (a new scene's tables
/// need a page, or a line on an existing one).
#[test]
fn every_generated_table_is_included_by_a_page() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/book/src");
    let mut pages = String::new();
    let mut dirs = vec![src.clone()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                if !path.ends_with("generated") {
                    dirs.push(path);
                }
            } else if path.extension().is_some_and(|e| e == "md") {
                pages.push_str(&std::fs::read_to_string(&path).unwrap());
            }
        }
    }
    for (name, _) in viscosph_cli::docs_tables::tables().expect("tables") {
        assert!(
            pages.contains(&format!("generated/{name}}}}}")),
            "no page of docs/book/src includes generated/{name}"
        );
    }
}
