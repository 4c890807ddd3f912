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
    for p in viscosph::scene::PARAMS.iter() {
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

#[test]
fn the_automatic_sound_speed_is_printed_and_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let (out, out_dir) = run_20ms(
        dir.path(),
        "particles_per_diameter = 12\ninitial_drop_height = 0.013\nimpact_velocity = 3.0\n",
    );
    assert!(out.status.success());
    // 3 m/s plus a free fall of 3 mm: U = sqrt(9 + 2 * 9.81 * 0.003) = 3.0098 m/s, plus the
    // default max_plate_speed of 1 m/s: c = 10 (U + 1).
    let c = 10.0 * ((9.0f64 + 2.0 * 9.81 * 0.003).sqrt() + 1.0);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains(&format!("sound speed c = {c:.3} m/s (automatic")),
        "{stdout}"
    );
    let scene = std::fs::read_to_string(out_dir.join("scene.toml")).unwrap();
    let rerun = viscosph::SceneConfig::from_toml_str(&scene).unwrap();
    assert!((rerun.numerics.sound_speed - c).abs() < 1e-9, "{scene}");
}

#[test]
fn an_unwritable_out_names_the_path_and_the_operation() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a_file");
    std::fs::write(&file, "not a folder").unwrap();
    let bad = file.join("out");
    let out = viscosph()
        .args(["run", "--t-end", "0.001", "--out"])
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&bad.display().to_string()) && err.contains("cannot create the output folder"),
        "{err}"
    );
}

#[test]
fn a_reused_out_folder_loses_the_earlier_runs_files_only() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    // An earlier, longer run's snapshot and a file of the user's.
    std::fs::write(out_dir.join("particles_0042.vtk"), "old").unwrap();
    std::fs::write(out_dir.join("notes.txt"), "mine").unwrap();
    let (out, _) = run_20ms(
        dir.path(),
        "particles_per_diameter = 12\ninitial_drop_height = 0.013\n",
    );
    assert!(out.status.success());
    assert!(!out_dir.join("particles_0042.vtk").exists());
    assert_eq!(
        std::fs::read_to_string(out_dir.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(out_dir.join("particles_0008.vtk").exists());
}

#[test]
fn both_names_of_the_drop_height_are_refused() {
    let err = refused("drop_height = 0.05\ninitial_drop_height = 0.06\n");
    assert!(
        err.contains("drop_height") && err.contains("initial_drop_height"),
        "{err}"
    );
}

#[test]
fn an_absurd_run_length_needs_force() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    let out = viscosph()
        .args(["run", "--t-end", "1e9", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("steps") && err.contains("--force") && err.contains("1000000000"),
        "{err}"
    );
    assert!(!out_dir.exists(), "nothing written before the refusal");
}

/// Start a long run, send `signal` once it has written its first snapshot, and check that it
/// stopped early, wrote the CSV, the PNGs and a last snapshot, and exited non-zero.
fn interrupted_run(signal: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    let scene = dir.path().join("s.toml");
    std::fs::write(&scene, "particles_per_diameter = 30\n").unwrap();
    let child = viscosph()
        .args(["run", scene.to_str().unwrap(), "--out"])
        .arg(&out_dir)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while !out_dir.join("particles_0001.vtk").exists() {
        assert!(t0.elapsed().as_secs() < 300, "no snapshot after 5 minutes");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let killed = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{signal}: {err}");
    assert!(err.contains("interrupted at t ="), "{err}");
    let (_, rows) =
        viscosph_cli::io::csv::read_timeseries(&out_dir.join("timeseries.csv")).unwrap();
    let t_last = rows.last().unwrap()[0];
    // The default run ends at t* = 8, 0.16 s; the second snapshot is at t* = 1 (0.02 s).
    assert!(
        (0.02..0.16).contains(&t_last),
        "{signal}: stopped at {t_last}"
    );
    for png in ["width_height.png", "particles.png"] {
        assert!(
            std::fs::read(out_dir.join(png)).unwrap().len() > 10_000,
            "{png}"
        );
    }
    // The last state is the snapshot after the regular ones, and the scene is recorded.
    let snaps = std::fs::read_dir(&out_dir)
        .unwrap()
        .filter(|e| {
            let n = e.as_ref().unwrap().file_name();
            let n = n.to_string_lossy();
            n.starts_with("particles_") && n.ends_with(".vtk")
        })
        .count();
    assert!(snaps >= 3, "{snaps} snapshots");
    assert!(out_dir.join("scene.toml").exists());
}

#[test]
fn sigint_stops_the_run_and_keeps_its_files() {
    interrupted_run("-INT");
}

#[test]
fn sigterm_stops_the_run_and_keeps_its_files() {
    interrupted_run("-TERM");
}

#[test]
fn the_jet_under_isph_with_p_zero_on_its_surface_warns_once() {
    let dir = tempfile::tempdir().unwrap();
    let run = |scheme: &str, surface: &str| {
        let (out, _) = run_20ms(
            dir.path(),
            &format!(
                "scene = \"jet\"\nscheme = \"{scheme}\"\nrheology = \"newtonian\"\n\
                 particles_per_diameter = 4\nisph_free_surface = \"{surface}\"\n"
            ),
        );
        assert!(out.status.success(), "{out:?}");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let err = run("isph", "zero_pressure");
    assert_eq!(err.matches("warning:").count(), 1, "{err}");
    assert!(
        err.contains("does not buckle") && err.contains("docs/methods.md"),
        "{err}"
    );
    // The jet's own choice (auto: King & Lind's (35a) normal stress) buckles: no warning.
    assert!(!run("isph", "auto").contains("warning:"));
    assert!(!run("isph", "normal_stress").contains("warning:"));
    assert!(!run("wcsph", "auto").contains("warning:"));
}
