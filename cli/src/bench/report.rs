//! `viscosph bench report`: docs/benchmarks.md assembled from the other commands' results.

use super::{git_commit, machine_description};
use std::fmt::Write as _;
use std::path::Path;

/// The sections of the report: (title, command, markdown file, PNG files) from `results`.
const REPORT_SECTIONS: &[(&str, &str, &str, &[&str])] = &[
    (
        "Accuracy against cost",
        "viscosph bench accuracy",
        "accuracy.md",
        &["accuracy.png"],
    ),
    (
        "Fang's drops at 20/40/80 particles per diameter",
        "viscosph bench drop",
        "drop.md",
        &["drop.png"],
    ),
    (
        "Throughput",
        "viscosph bench throughput",
        "throughput.md",
        &["throughput.png"],
    ),
    (
        "Stability maps",
        "viscosph bench stability",
        "stability.md",
        &[
            "stability_de_wcsph.png",
            "stability_de_pdri.png",
            "stability_de_isph.png",
            "stability_beta.png",
            "stability_inclination.png",
            "stability_velocity.png",
            "stability_resolution.png",
        ],
    ),
    (
        "Every rheology on Fang's drop",
        "viscosph bench rheologies",
        "rheologies.md",
        &[
            "rheologies_wcsph.png",
            "rheologies_pdri.png",
            "rheologies_isph.png",
        ],
    ),
    (
        "Channel: start-up Poiseuille flow (King & Lind section IV.A)",
        "viscosph bench channel",
        "channel.md",
        &[
            "channel_accuracy.png",
            "channel_wi.png",
            "channel_nonlinear.png",
        ],
    ),
    (
        "The buckling jet (King & Lind section IV.D)",
        "viscosph bench jet",
        "jet.md",
        &[],
    ),
    (
        "ISPH (King & Lind 2021) on their Newtonian Re = 4 drop",
        "nice -n 10 viscosph bench isph",
        "isph.md",
        &[],
    ),
    (
        "PySPH side by side",
        "python3 examples/compare_pysph.py",
        "pysph.md",
        &[],
    ),
];

pub fn bench_report(results: &Path, docs: &Path) -> Result<String, Box<dyn std::error::Error>> {
    let img_dir = docs.join("bench");
    std::fs::create_dir_all(&img_dir)?;
    let mut md = String::from("# ViscoSPH benchmarks\n\n");
    writeln!(
        md,
        "What each benchmark command measures, with the commit it was measured on, the machine \
         and the command. Assembled by `viscosph bench report` from the results of the commands \
         named in each section.\n"
    )?;
    // The commit each section was measured on (written by the subcommand that measured it).
    let measured = |file: &str| {
        let f = results.join(file.replace(".md", ".commit"));
        std::fs::read_to_string(f)
            .ok()
            .map(|t| t.trim().to_string())
    };
    let mut commits: Vec<String> = REPORT_SECTIONS
        .iter()
        .filter_map(|(_, _, file, _)| measured(file))
        .collect();
    commits.sort();
    commits.dedup();
    writeln!(md, "- machine: {}", machine_description())?;
    writeln!(
        md,
        "- measured on commit: {}",
        if commits.is_empty() {
            "unknown".to_string()
        } else {
            commits.join(", ")
        }
    )?;
    writeln!(md, "- report assembled at commit: {}\n", git_commit())?;
    for (title, cmd, file, pngs) in REPORT_SECTIONS {
        writeln!(md, "## {title}\n\n`{cmd}`\n")?;
        if let Some(c) = measured(file) {
            writeln!(md, "Measured on commit {c}.\n")?;
        }
        match std::fs::read_to_string(results.join(file)) {
            Ok(t) => md.push_str(&t),
            Err(_) => writeln!(
                md,
                "_not run yet: `{cmd}` writes `{}`_",
                results.join(file).display()
            )?,
        }
        md.push('\n');
        for png in *pngs {
            let src = results.join(png);
            if src.exists() {
                std::fs::copy(&src, img_dir.join(png))?;
                writeln!(md, "![{png}](bench/{png})\n")?;
            }
        }
    }
    std::fs::write(docs.join("benchmarks.md"), &md)?;
    Ok(format!("wrote {}", docs.join("benchmarks.md").display()))
}
