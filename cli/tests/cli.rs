//! The `viscosph` command line: scene files, errors that name the culprit, and the files a run writes.

use std::process::Command;

fn viscosph() -> Command {
    Command::new(env!("CARGO_BIN_EXE_viscosph"))
}

/// Run a scene file with `text` to t = 20 ms with an output every 2 ms, into `dir`/out.
fn run_20ms(dir: &std::path::Path, text: &str) -> (std::process::Output, std::path::PathBuf) {
    let scene = dir.join("s.toml");
    std::fs::write(&scene, text).unwrap();
    let out_dir = dir.join("out");
    let out = viscosph()
        .args(["run", scene.to_str().unwrap(), "--t-end", "0.02"])
        .args(["--output-interval", "0.002", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    (out, out_dir)
}

/// Run a scene file with `text`; it must be refused (exit code 2). Returns stderr.
fn refused(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bad.toml");
    std::fs::write(&scene, text).unwrap();
    let out = viscosph()
        .args(["run", scene.to_str().unwrap(), "--out"])
        .arg(dir.path().join("o"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn unknown_key_and_bad_value_are_named() {
    let err = refused("drop_diametr = 0.02\n");
    assert!(err.contains("drop_diametr"), "{err}");
    let err = refused("plate_inclination = 95.0\n");
    assert!(
        err.contains("plate_inclination") && err.contains("95") && err.contains("[0, 90)"),
        "{err}"
    );
}

#[test]
fn default_scene_round_trips() {
    let out = viscosph().arg("default-scene").output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for p in viscosph::config::PARAMS {
        assert!(
            text.contains(&format!("{} = ", p.name)),
            "missing {}",
            p.name
        );
    }
    let cfg = viscosph::SceneConfig::from_toml_str(&text).unwrap();
    assert_eq!(cfg, viscosph::SceneConfig::default());
}

#[test]
fn run_writes_timeseries_snapshots_and_plots() {
    let dir = tempfile::tempdir().unwrap();
    // Missing keys take their defaults: only the resolution and the drop's start are set.
    let (out, out_dir) = run_20ms(
        dir.path(),
        "particles_per_diameter = 12\ninitial_drop_height = 0.013\n",
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let (header, rows) =
        viscosph_cli::io::csv::read_timeseries(&out_dir.join("timeseries.csv")).unwrap();
    let mut want = vec!["time".to_string()];
    want.extend(viscosph::OUTPUTS.iter().map(|o| o.name.to_string()));
    assert_eq!(header, want);
    assert_eq!(rows.len(), 11);
    assert!((rows[10][0] - 0.02).abs() < 1e-12);
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    // The drop starts 3 mm above the plate at 1 m/s: it has hit and spread by t = 20 ms.
    assert_eq!(rows[0][col("wall_force_normal")], 0.0);
    assert!(rows[10][col("wall_force_normal")] > 0.0);
    assert!(rows[10][col("drop_width")] > rows[0][col("drop_width")]);
    let n = rows[0][col("particle_count")] as usize;

    for png in ["width_height.png", "particles.png"] {
        let bytes = std::fs::read(out_dir.join(png)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{png}");
        assert!(bytes.len() > 10_000, "{png} is suspiciously small");
    }
    let vtk = std::fs::read_to_string(out_dir.join("particles_0000.vtk")).unwrap();
    assert!(
        vtk.contains(&format!("POINTS {n} double")),
        "VTK holds every particle"
    );
    assert!(vtk.contains("SCALARS trace_A double 1"));
    let snaps = std::fs::read_dir(&out_dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .starts_with("particles_")
        })
        .count();
    assert!(snaps >= 5, "{snaps} snapshots");
}

#[test]
fn a_breakdown_keeps_its_files_and_the_last_good_state() {
    let dir = tempfile::tempdir().unwrap();
    // Sound far too slow for a 1 m/s impact: the density check stops the run after impact.
    let (out, out_dir) = run_20ms(
        dir.path(),
        "particles_per_diameter = 12\ninitial_drop_height = 0.013\nsound_speed = 2.0\n",
    );
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("numerical breakdown") && stderr.contains("too fast for the sound speed"),
        "{stderr}"
    );
    let (_, rows) =
        viscosph_cli::io::csv::read_timeseries(&out_dir.join("timeseries.csv")).unwrap();
    assert!(rows.len() >= 2 && rows.len() < 11, "{} rows", rows.len());
    // One snapshot per output row, then the last good state after them.
    let vtk = |k: usize| out_dir.join(format!("particles_{k:04}.vtk"));
    assert!(vtk(rows.len() - 1).exists() && vtk(rows.len()).exists());
    assert!(!vtk(rows.len() + 1).exists());
    assert!(std::fs::read(out_dir.join("particles.png")).unwrap().len() > 10_000);
}

#[test]
fn example_scenes_are_valid() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "toml") {
            let text = std::fs::read_to_string(&path).unwrap();
            let cfg = viscosph::SceneConfig::from_toml_str(&text)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            viscosph::Simulation::new(cfg).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            n += 1;
        }
    }
    assert!(n >= 4, "{n} scenes");
}
