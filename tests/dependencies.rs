//! The solver library (and so the FMU's cdylib, built from the same package) links none of the
//! command line's crates: clap, plotters and indicatif belong to `cli/`; nor the references the
//! solver is checked against (analytic solutions, fixtures): they belong to `reference/`.

use std::process::Command;

#[test]
fn the_library_does_not_depend_on_cli_crates() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let manifest = concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml");
    let out = Command::new(cargo)
        .args(["tree", "--offline", "-p", "viscosph", "-e", "normal"])
        .args(["--prefix", "none", "--manifest-path", manifest])
        .output()
        .unwrap();
    let tree = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "cargo tree: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let names: Vec<&str> = tree
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    // The tree is the library's: it starts at viscosph and holds its solver dependencies.
    assert_eq!(names.first(), Some(&"viscosph"), "{tree}");
    for want in ["nalgebra", "rayon", "toml"] {
        assert!(names.contains(&want), "{want} missing from\n{tree}");
    }
    for banned in [
        "clap",
        "plotters",
        "indicatif",
        "csv",
        "viscosph-cli",
        "viscosph-reference",
    ] {
        assert!(
            !names.contains(&banned),
            "the library depends on {banned}:\n{tree}"
        );
    }
}

/// The cdylib that fmu-build packs holds the solver only: none of the analytic solutions (Waters
/// & King, steady shear, the falling sheet) nor the particle-set fixtures, by name, anywhere in
/// the built file (symbol table, debug line tables). The file is the one cargo built with the
/// rlib this test links (both crate types come from one compilation), beside this executable.
#[test]
fn the_fmu_library_holds_no_reference_code() {
    use std::env::consts::{DLL_PREFIX, DLL_SUFFIX};
    let exe = std::env::current_exe().unwrap();
    let lib = exe
        .parent()
        .unwrap()
        .join(format!("{DLL_PREFIX}viscosph{DLL_SUFFIX}"));
    let bytes = std::fs::read(&lib).unwrap_or_else(|e| panic!("{}: {e}", lib.display()));
    let has = |name: &str| bytes.windows(name.len()).any(|w| w == name.as_bytes());
    // Names the solver's code leaves in the file: the FMI export, a rheology module. Without
    // them (a stripped build) the file says nothing about what was compiled into it.
    for present in ["fmi2DoStep", "logconf"] {
        assert!(
            has(present),
            "{} lacks the name {present}: stripped, so it cannot be checked",
            lib.display()
        );
    }
    for banned in [
        "waters_king",
        "steady_shear",
        "falling_sheet",
        "fixtures",
        "viscosph_reference",
    ] {
        assert!(
            !has(banned),
            "{} holds {banned}: reference code compiled into the FMU library",
            lib.display()
        );
    }
}
