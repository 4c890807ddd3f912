//! docs/benchmarks.md is what `viscosph bench report` generates from the committed results in
//! docs/bench/ (no hand edits that the next report would lose), with every benchmark's section,
//! and a section whose commit or machine is not known is refused rather than reported.

use std::path::{Path, PathBuf};
use viscosph_cli::bench::report::{render, SECTIONS};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn committed() -> String {
    std::fs::read_to_string(root().join("docs/benchmarks.md")).unwrap()
}

#[test]
fn the_committed_report_is_generated_from_the_committed_results() {
    let generated = render(&root().join("docs/bench")).unwrap();
    if generated != committed() {
        let line = generated
            .lines()
            .zip(committed().lines())
            .position(|(a, b)| a != b)
            .map_or(
                generated.lines().count().min(committed().lines().count()),
                |k| k,
            );
        panic!(
            "docs/benchmarks.md differs from what `viscosph bench report --out docs/bench` \
             generates (first at line {}): regenerate it",
            line + 1
        );
    }
}

#[test]
fn every_benchmark_has_its_section_with_command_commit_and_machine() {
    let report = committed();
    for s in SECTIONS {
        let head = format!("## {}\n\n`{}`\n\nMeasured on commit ", s.title, s.command);
        let at = report
            .find(&head)
            .unwrap_or_else(|| panic!("no section {:?}", s.title));
        let line = report[at + head.len()..].lines().next().unwrap();
        let (commit, machine) = line.split_once("; machine: ").expect("a machine");
        assert!(
            commit.chars().take(7).all(|c| c.is_ascii_hexdigit()),
            "{}: {commit}",
            s.title
        );
        assert!(machine.contains("GiB"), "{}: {machine}", s.title);
        for png in s.pngs {
            assert!(
                report.contains(&format!("(bench/{png})")),
                "{}: {png}",
                s.title
            );
            assert!(root().join("docs/bench").join(png).exists(), "{png}");
        }
    }
}

#[test]
fn a_section_without_its_commit_or_machine_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("drop.md"), "A table.\n").unwrap();
    let err = render(dir.path()).unwrap_err().to_string();
    assert!(
        err.contains("drop.commit") && err.contains("viscosph bench drop"),
        "{err}"
    );
    std::fs::write(dir.path().join("drop.commit"), "abc1234\n").unwrap();
    assert!(render(dir.path())
        .unwrap_err()
        .to_string()
        .contains("drop.machine"));
    std::fs::write(dir.path().join("drop.machine"), "a CPU, 2 cores, 1 GiB\n").unwrap();
    let md = render(dir.path()).unwrap();
    assert!(md.contains("Measured on commit abc1234; machine: a CPU, 2 cores, 1 GiB."));
    // Sections without results are left out, not announced.
    assert!(!md.contains("## Throughput"), "{md}");
}
