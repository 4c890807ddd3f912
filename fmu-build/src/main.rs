//! Builds `target/fmu/ViscoSPH.fmu` (FMI 2.0 section 2.3, the FMU archive layout):
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/ViscoSPH.so      the release cdylib, debug info stripped if `strip` exists
//! documentation/index.html          generated from the parameter and output tables
//! ```
//!
//! Usage: `cargo run --release -p fmu-build [-- --write-model-description]`. The scripts add
//! `--target-dir target/fmu-build`, so that building the FMU never competes with the feature
//! set of `cargo test --workspace` in `target/` (each would otherwise recompile the library
//! the other just built). The FMU is always written to `target/fmu/ViscoSPH.fmu`.
//!
//! The XML packed is generated from the tables this binary was compiled with, which are the
//! ones the cdylib is built from a moment later (same workspace). The committed
//! `modelDescription/modelDescription.xml` must equal it; if it does not, the build stops and
//! says how to regenerate it, so a table change cannot ship with a stale committed interface.

mod docs;

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use viscosph::fmi2::{model_description_xml, MODEL_IDENTIFIER};
use zip::write::SimpleFileOptions;

/// The workspace root: fmu-build's manifest directory's parent.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("fmu-build lives inside the workspace")
        .to_path_buf()
}

/// The target directory this binary was built in (`<target-dir>/release/fmu-build`): the
/// cdylib is built there too, with the same package selection as `cargo run -p fmu-build`, so
/// cargo resolves the same features and finds everything fresh. (A different selection, such
/// as `-p viscosph` alone, unifies dependency features differently and would recompile the
/// library on every alternation.)
fn own_target_dir() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    exe.parent()
        .and_then(Path::parent)
        .map(Path::to_path_buf)
        .ok_or_else(|| format!("cannot find the target directory of {}", exe.display()))
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("fmu-build: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let root = root();
    let committed_path = root.join("modelDescription").join("modelDescription.xml");
    let xml = model_description_xml();
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("--write-model-description") => {
            fs::create_dir_all(committed_path.parent().expect("has a parent"))
                .map_err(|e| e.to_string())?;
            fs::write(&committed_path, &xml).map_err(|e| e.to_string())?;
            println!("wrote {}", committed_path.display());
            return Ok(());
        }
        Some(other) => {
            return Err(format!(
                "unknown argument '{other}'; usage: fmu-build [--write-model-description]"
            ))
        }
        None => {}
    }

    let committed = fs::read_to_string(&committed_path).unwrap_or_default();
    if committed != xml {
        return Err(format!(
            "{} differs from the interface generated from src/config.rs and src/diagnostics.rs; \
             run `cargo run --release -p fmu-build -- --write-model-description` and commit it",
            committed_path.display()
        ));
    }

    if !(cfg!(target_os = "linux") && cfg!(target_arch = "x86_64")) {
        return Err("only the linux64 platform (Linux on x86_64) is supported".into());
    }

    // Build the cdylib with the same cargo that runs us.
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let target = own_target_dir()?;
    let status = Command::new(&cargo)
        .args([
            "build",
            "--release",
            "-p",
            "viscosph",
            "-p",
            "fmu-build",
            "--lib",
        ])
        .arg("--target-dir")
        .arg(&target)
        .current_dir(&root)
        .status()
        .map_err(|e| format!("could not run {cargo}: {e}"))?;
    if !status.success() {
        return Err(format!(
            "`{cargo} build --release -p viscosph --lib` failed"
        ));
    }

    let lib = target.join("release").join("libviscosph.so");
    // The contract's location, whichever target directory was used to build.
    let out_dir = root.join("target").join("fmu");
    fs::create_dir_all(&out_dir).map_err(|e| e.to_string())?;
    let pid = std::process::id();
    let binary = stripped(&lib, &out_dir.join(format!("{MODEL_IDENTIFIER}.{pid}.so")))?;

    let fmu_path = out_dir.join(format!("{MODEL_IDENTIFIER}.fmu"));
    let tmp_path = out_dir.join(format!("{MODEL_IDENTIFIER}.fmu.{pid}.tmp"));
    write_zip(&tmp_path, &xml, &binary, &docs::index_html())?;
    // Rename is atomic: a test reading the FMU never sees half an archive.
    fs::rename(&tmp_path, &fmu_path).map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} kB)",
        fmu_path.display(),
        fs::metadata(&fmu_path).map(|m| m.len() / 1024).unwrap_or(0)
    );
    Ok(())
}

/// The library's bytes without debug sections (about 20 times smaller), or as built if
/// `strip` is not available.
fn stripped(lib: &Path, out: &Path) -> Result<Vec<u8>, String> {
    let ok = Command::new("strip")
        .arg("--strip-debug")
        .arg("-o")
        .arg(out)
        .arg(lib)
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    let path = if ok {
        out
    } else {
        eprintln!("fmu-build: `strip` not available; packing the library with its debug info");
        lib
    };
    let bytes = fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()));
    let _ = fs::remove_file(out);
    bytes
}

fn write_zip(path: &Path, xml: &str, binary: &[u8], html: &str) -> Result<(), String> {
    let file = fs::File::create(path).map_err(|e| e.to_string())?;
    let mut zip = zip::ZipWriter::new(file);
    let text = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let exe = text.unix_permissions(0o755);
    let entries: [(&str, &[u8], SimpleFileOptions); 3] = [
        ("modelDescription.xml", xml.as_bytes(), text),
        (
            &format!("binaries/linux64/{MODEL_IDENTIFIER}.so"),
            binary,
            exe,
        ),
        ("documentation/index.html", html.as_bytes(), text),
    ];
    for (name, bytes, opts) in entries {
        zip.start_file(name, opts).map_err(|e| e.to_string())?;
        zip.write_all(bytes).map_err(|e| e.to_string())?;
    }
    zip.finish().map_err(|e| e.to_string())?;
    Ok(())
}
