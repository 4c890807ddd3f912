//! The built `target/fmu/ViscoSPH.fmu`, loaded by an independent importer: the `fmi` crate 0.8
//! (libloading underneath, Co-Simulation via `instantiate_cs` and `do_step`). A short drop
//! impact through the FMU must give the same outputs as the library's own [`Simulation`]
//! advanced to the same communication points, because the FMU is a thin translator.
//!
//! The FMU tested is the one named by the environment variable `VISCOSPH_FMU`, which
//! tests/run_all.sh sets after building `target/fmu/ViscoSPH.fmu` in its previous stage (one
//! build for the tests and the main job). Without it (`cargo test` alone) the test builds the
//! FMU itself, so it works on a clean checkout and never tests a stale binary: in its own
//! target directory, `target/fmu-build`, clear of the lock `cargo test` holds on `target/`.
//!
//! `fmi-schema` (the importer's XML reader) only reads part of the FMI 2.0 attributes; the full
//! XML is checked with a general XML parser in `tests/fmu_model_description.rs`.

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use fmi::traits::{FmiImport, FmiInstance, FmiStatus};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;
use std::time::Instant;
use viscosph::config::Value;
use viscosph::scene::OUTPUTS;
use viscosph::scene::{param_spec, SceneConfig};
use viscosph::Simulation;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Build the FMU once per test binary and return its path.
fn fmu_path() -> &'static Path {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        if let Some(p) = std::env::var_os("VISCOSPH_FMU").map(PathBuf::from) {
            assert!(p.is_file(), "VISCOSPH_FMU = {} is not a file", p.display());
            return p;
        }
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| env!("CARGO").to_string());
        let status = Command::new(cargo)
            .args(["run", "--release", "-p", "fmu-build", "--target-dir"])
            .arg(root().join("target").join("fmu-build"))
            .current_dir(root())
            .status()
            .expect("cargo runs");
        assert!(status.success(), "fmu-build failed");
        let p = root().join("target").join("fmu").join("ViscoSPH.fmu");
        assert!(p.is_file(), "{} was not written", p.display());
        p
    })
}

/// Import the FMU (unzipped into a temporary directory that lives as long as the import).
fn import() -> Fmi2Import {
    fmi::import::from_path::<Fmi2Import>(fmu_path()).expect("the fmi crate imports the FMU")
}

fn vr(name: &str) -> u32 {
    OUTPUTS
        .iter()
        .find(|o| o.name == name)
        .map(|o| o.value_reference)
        .or_else(|| param_spec(name).map(|p| p.value_reference))
        .unwrap_or_else(|| panic!("no variable {name}"))
}

const PPD: i32 = 16;
const INCLINATION: f64 = 30.0;

/// Instantiate, set the resolution and inclination, initialize.
fn start(imp: &Fmi2Import, name: &str) -> InstanceCS {
    let mut inst = imp
        .instantiate_cs(name, false, false)
        .expect("fmi2Instantiate answers an instance");
    inst.set_integer(&[vr("particles_per_diameter")], &[PPD])
        .unwrap();
    inst.set_real(&[vr("plate_inclination")], &[INCLINATION])
        .unwrap();
    FmiInstance::enter_initialization_mode(&mut inst, None, 0.0, None).unwrap();
    FmiInstance::exit_initialization_mode(&mut inst).unwrap();
    inst
}

fn all_outputs(inst: &mut InstanceCS) -> Vec<f64> {
    let vrs: Vec<u32> = OUTPUTS.iter().map(|o| o.value_reference).collect();
    let mut v = vec![0.0; vrs.len()];
    inst.get_real(&vrs, &mut v).unwrap();
    v
}

#[test]
fn a_short_run_through_the_fmu_equals_the_library() {
    let imp = import();
    assert_eq!(imp.model_description().model_name, "ViscoSPH");
    assert_eq!(imp.model_description().guid, viscosph::fmi2::guid());

    let (h, steps) = (0.002, 20);
    let t0 = Instant::now();
    let mut inst = start(&imp, "fmu");
    let mut via_fmu = vec![all_outputs(&mut inst)];
    for k in 0..steps {
        inst.do_step(k as f64 * h, h, true).expect("fmi2DoStep");
        via_fmu.push(all_outputs(&mut inst));
    }
    let fmu_time = t0.elapsed();

    let t0 = Instant::now();
    let mut cfg = SceneConfig::default();
    cfg.set("particles_per_diameter", Value::Integer(PPD.into()))
        .unwrap();
    cfg.set("plate_inclination", Value::Real(INCLINATION))
        .unwrap();
    let mut sim = Simulation::new(cfg).unwrap();
    let mut direct = vec![sim.outputs().values().to_vec()];
    for k in 1..=steps {
        sim.advance_to(k as f64 * h).unwrap();
        direct.push(sim.outputs().values().to_vec());
    }
    let lib_time = t0.elapsed();
    println!(
        "0.04 s at {PPD} particles per diameter: through the FMU {:.3} s, library {:.3} s",
        fmu_time.as_secs_f64(),
        lib_time.as_secs_f64()
    );

    for (k, (a, b)) in via_fmu.iter().zip(&direct).enumerate() {
        for (i, o) in OUTPUTS.iter().enumerate() {
            let tol = 1e-9 * b[i].abs().max(1e-12);
            assert!(
                (a[i] - b[i]).abs() <= tol,
                "{} at t = {}: FMU {} vs library {}",
                o.name,
                k as f64 * h,
                a[i],
                b[i]
            );
        }
    }
    // The run did something: the drop fell onto the plate and spread.
    let (first, last) = (&via_fmu[0], &via_fmu[steps]);
    let at = |name: &str| OUTPUTS.iter().position(|o| o.name == name).unwrap();
    assert!(last[at("drop_height")] < 0.8 * first[at("drop_height")]);
    assert!(last[at("drop_width")] > first[at("drop_width")]);
}

#[test]
fn fmu_state_serializes_and_restores_through_the_importer() {
    let imp = import();
    let mut inst = start(&imp, "state");
    inst.do_step(0.0, 0.004, true).unwrap();
    let s = inst.get_fmu_state().unwrap();
    let bytes = inst.serialize_fmu_state(&s).unwrap();
    inst.do_step(0.004, 0.004, true).unwrap();
    let reference = all_outputs(&mut inst);

    // Restore in a second, fresh instance of another import (another unzipped binary).
    let imp2 = import();
    let mut other = imp2.instantiate_cs("other", false, false).unwrap();
    let restored = other.deserialize_fmu_state(&bytes).unwrap();
    other
        .set_fmu_state(&restored)
        .ok()
        .expect("fmi2SetFMUstate");
    assert_eq!(other.last_successful_time().unwrap(), 0.004);
    other.do_step(0.004, 0.004, true).unwrap();
    assert_eq!(all_outputs(&mut other), reference);
}

#[test]
fn out_of_order_and_bad_values_are_refused_not_crashes() {
    let imp = import();
    let mut inst = imp.instantiate_cs("errors", false, false).unwrap();
    assert!(
        inst.do_step(0.0, 0.001, true).is_err(),
        "doStep before init"
    );
    assert!(
        Common::reset(&mut inst).is_ok(),
        "fmi2Reset recovers from the error state"
    );
    assert!(inst.set_real(&[vr("drop_diameter")], &[-0.02]).is_err());
    Common::reset(&mut inst).unwrap();
    assert!(inst.set_real(&[424242], &[1.0]).is_err(), "unknown vr");
    Common::reset(&mut inst).unwrap();
    inst.set_real(&[vr("drop_diameter")], &[0.03]).unwrap();
    let mut d = [0.0];
    FmiInstance::enter_initialization_mode(&mut inst, None, 0.0, None).unwrap();
    inst.get_real(&[vr("drop_diameter")], &mut d).unwrap();
    assert_eq!(d[0], 0.03);
    assert!(Common::set_debug_logging(&mut inst, true, &["logNonsense"]).is_err());
}

#[test]
fn two_instances_on_two_threads_match_their_solo_runs() {
    let run = |inclination: f64| {
        move || {
            let imp = import();
            let mut inst = imp.instantiate_cs("thread", false, false).unwrap();
            inst.set_integer(&[vr("particles_per_diameter")], &[12])
                .unwrap();
            inst.set_real(&[vr("plate_inclination")], &[inclination])
                .unwrap();
            FmiInstance::enter_initialization_mode(&mut inst, None, 0.0, None).unwrap();
            FmiInstance::exit_initialization_mode(&mut inst).unwrap();
            for k in 0..10 {
                inst.do_step(k as f64 * 0.003, 0.003, true).unwrap();
            }
            all_outputs(&mut inst)
        }
    };
    let solo = (run(0.0)(), run(45.0)());
    let a = std::thread::spawn(run(0.0));
    let b = std::thread::spawn(run(45.0));
    let together = (a.join().unwrap(), b.join().unwrap());
    assert_eq!(solo, together);
    assert_ne!(solo.0, solo.1, "the two parameter sets differ");
}
