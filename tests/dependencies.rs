//! The solver library (and so the FMU's cdylib, built from the same package) links none of the
//! command line's crates: clap, plotters and indicatif belong to `cli/` (issue 10, item 3).

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
    for banned in ["clap", "plotters", "indicatif", "csv", "viscosph-cli"] {
        assert!(
            !names.contains(&banned),
            "the library depends on {banned}:\n{tree}"
        );
    }
}
