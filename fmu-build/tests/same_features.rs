//! The main job's `cargo run --release -p fmu-build` must resolve every package it shares with
//! `cargo test --release --workspace` with the same features; otherwise cargo gives the
//! library (and every crate above the differing one) another hash and compiles it a second
//! time in `target/`, which is what made the main job recompile for minutes after the tests.
//! The extra dependencies in fmu-build/Cargo.toml exist to satisfy this test.

use std::collections::BTreeSet;
use std::process::Command;

/// `cargo tree` lines "name version [features]" for the given selection.
fn resolved(args: &[&str]) -> BTreeSet<String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .arg("tree")
        .args(args)
        .args(["--locked", "--prefix", "none", "-f", "{p} [{f}]"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .expect("cargo tree runs");
    assert!(
        out.status.success(),
        "cargo tree {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('['))
        .map(|l| l.trim_end_matches(" (*)").to_string())
        .collect()
}

/// Every package line of the main job's resolution must appear, features and all, in the
/// tests' resolution. Checked twice: with build-dependency edges (the host side: build scripts
/// and their dependencies), and without them, where a package is listed once per feature set
/// of the compiled-for-the-target side; a full tree alone hides a target-side difference
/// behind the host-side copy of the same package (libc's "align" was such a case).
#[test]
fn fmu_build_resolves_the_features_of_the_test_build() {
    for (tests, main_job) in [
        (
            resolved(&["--workspace", "-e", "normal,build,dev"]),
            resolved(&["-p", "fmu-build", "-e", "normal,build"]),
        ),
        (
            resolved(&["--workspace", "-e", "normal,dev"]),
            resolved(&["-p", "fmu-build", "-e", "normal"]),
        ),
    ] {
        assert!(tests.len() > main_job.len() && main_job.len() > 50);
        let differing: Vec<&String> = main_job.difference(&tests).collect();
        assert!(
            differing.is_empty(),
            "`cargo run -p fmu-build` resolves these packages with other features than \
             `cargo test --workspace`, so the library would compile twice; add the tests' \
             features to fmu-build/Cargo.toml:\n{differing:#?}"
        );
    }
}
