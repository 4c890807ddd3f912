//! Builds `target/fmu/ViscoSPH.fmu` (FMI 2.0 section 2.3, the FMU archive layout):
//!
//! ```text
//! modelDescription.xml
//! binaries/linux64/ViscoSPH.so      release cdylib; needs glibc 2.17 when built with zig
//! binaries/win64/ViscoSPH.dll       release cdylib for x86_64-pc-windows-gnu, if MinGW-w64 is here
//! documentation/index.html          generated from the parameter and output tables
//! ```
//! and `target/fmu/ViscoSPH-fmi3.fmu` (FMI 3.0, from the same library, which exports both
//! APIs): `modelDescription/fmi3/modelDescription.xml`, `binaries/x86_64-linux/ViscoSPH.so`,
//! `binaries/x86_64-windows/ViscoSPH.dll` and `binaries/aarch64-linux/ViscoSPH.so` (cross-built
//! by `cargo zigbuild --target aarch64-unknown-linux-gnu.2.17` with a rustc that has the aarch64
//! standard library: see [`aarch64_rustc`]).
//! (debug info stripped when `strip` / `x86_64-w64-mingw32-strip` exist).
//!
//! Usage: `cargo run --release -p fmu-build [-- --write-model-description]`, in the default
//! target directory: the tests (`cargo test --release --workspace`) and the main job build the
//! host library there once, with the same features (see fmu-build/Cargo.toml). The portable
//! binaries are cross builds in `target/cross`: linux64 by `cargo zigbuild --target
//! x86_64-unknown-linux-gnu.2.17` (zig links against glibc 2.17's symbol versions; a plain
//! build would need the build machine's glibc, e.g. `hypot@GLIBC_2.35`), win64 by `cargo build
//! --target x86_64-pc-windows-gnu` with Debian's mingw-w64 as the linker. A machine without
//! those tool chains still gets an FMU (linux64 from the host build) and a note saying what
//! is missing. The FMU is always written to `target/fmu/ViscoSPH.fmu`.
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
    let committed_path3 = root
        .join("modelDescription")
        .join("fmi3")
        .join("modelDescription.xml");
    let xml3 = viscosph::fmi3::model_description_xml();
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("--write-model-description") => {
            for (path, text) in [(&committed_path, &xml), (&committed_path3, &xml3)] {
                fs::create_dir_all(path.parent().expect("has a parent"))
                    .map_err(|e| e.to_string())?;
                fs::write(path, text).map_err(|e| e.to_string())?;
                println!("wrote {}", path.display());
            }
            return Ok(());
        }
        Some(other) => {
            return Err(format!(
                "unknown argument '{other}'; usage: fmu-build [--write-model-description]"
            ))
        }
        None => {}
    }

    for (path, text) in [(&committed_path, &xml), (&committed_path3, &xml3)] {
        if fs::read_to_string(path).unwrap_or_default() != *text {
            return Err(format!(
                "{} differs from the interface generated from the parameter and output tables (src/config/, src/scene/); \
                 run `cargo run --release -p fmu-build -- --write-model-description` and commit it",
                path.display()
            ));
        }
    }

    if !(cfg!(target_os = "linux") && cfg!(target_arch = "x86_64")) {
        return Err("only a Linux x86_64 machine builds the FMU".into());
    }

    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let target = own_target_dir()?;
    // The cross builds have a target directory of their own: their build scripts run with the
    // cross tool chain's environment, which would otherwise invalidate the host's.
    let cross_dir = root.join("target").join("cross");
    let mut binaries: Vec<(String, Vec<u8>)> = Vec::new();
    let mut notes: Vec<String> = Vec::new();

    let out_dir = root.join("target").join("fmu");
    fs::create_dir_all(&out_dir).map_err(|e| e.to_string())?;
    let pid = std::process::id();

    // linux64: against glibc 2.17 with zig as the linker when cargo-zigbuild is there (a plain
    // build links the newest symbol versions of this machine's glibc, e.g. hypot@GLIBC_2.35,
    // and does not load on older distributions), else a plain build that says so.
    let linux_lib = match zig_tools(&root) {
        Some((path, zig)) => {
            cargo_build(
                &cargo,
                &root,
                &["zigbuild", "--target", LINUX_ZIG_TARGET],
                &cross_dir,
                &[
                    ("PATH", path.as_os_str()),
                    ("CARGO_ZIGBUILD_ZIG_PATH", zig.as_os_str()),
                ],
            )?;
            cross_dir
                .join("x86_64-unknown-linux-gnu")
                .join("release")
                .join("libviscosph.so")
        }
        None => {
            notes.push(
                "linux64 binary built against this machine's glibc: it will not load on older \
                 distributions (`pip install cargo-zigbuild` into .venv, which brings ziglang, \
                 for one that needs glibc 2.17)"
                    .into(),
            );
            // Same package selection as `cargo run -p fmu-build`, so cargo resolves the same
            // features and finds the library it just built fresh.
            cargo_build(&cargo, &root, &["build", "-p", "fmu-build"], &target, &[])?;
            target.join("release").join("libviscosph.so")
        }
    };
    let linux = strip(
        "strip",
        &linux_lib,
        &out_dir.join(format!("{MODEL_IDENTIFIER}.{pid}.so")),
    )?;
    binaries.push((format!("binaries/linux64/{MODEL_IDENTIFIER}.so"), linux));

    // win64: the MinGW-w64 target, when its Rust standard library and linker are installed.
    match windows_tool_chain() {
        Ok(()) => {
            cargo_build(
                &cargo,
                &root,
                &["build", "--target", WINDOWS_TARGET],
                &cross_dir,
                &[],
            )?;
            let dll = cross_dir
                .join(WINDOWS_TARGET)
                .join("release")
                .join("viscosph.dll");
            let bytes = strip(
                "x86_64-w64-mingw32-strip",
                &dll,
                &out_dir.join(format!("{MODEL_IDENTIFIER}.{pid}.dll")),
            )?;
            binaries.push((format!("binaries/win64/{MODEL_IDENTIFIER}.dll"), bytes));
        }
        Err(why) => notes.push(format!("no win64 binary: {why}")),
    }

    pack(
        &out_dir,
        &format!("{MODEL_IDENTIFIER}.fmu"),
        &xml,
        &binaries,
    )?;

    // FMI 3.0: the same libraries (one cdylib exports fmi2* and fmi3*) under FMI 3.0's platform
    // tuples (FMI 3.0 section 2.5.1.1), and aarch64-linux, which FMI 2.0 cannot name.
    let mut binaries3: Vec<(String, Vec<u8>)> = binaries
        .iter()
        .map(|(name, bytes)| {
            let name = name
                .replace("binaries/linux64/", "binaries/x86_64-linux/")
                .replace("binaries/win64/", "binaries/x86_64-windows/");
            (name, bytes.clone())
        })
        .collect();
    match (aarch64_rustc(), zig_tools(&root)) {
        (Ok(rustc), Some((path, zig))) => {
            let dir = root.join("target").join("cross-aarch64");
            cargo_build(
                &cargo,
                &root,
                &["zigbuild", "--target", AARCH64_ZIG_TARGET],
                &dir,
                &[
                    ("PATH", path.as_os_str()),
                    ("CARGO_ZIGBUILD_ZIG_PATH", zig.as_os_str()),
                    ("RUSTC", rustc.as_os_str()),
                ],
            )?;
            let lib = dir
                .join("aarch64-unknown-linux-gnu")
                .join("release")
                .join("libviscosph.so");
            let bytes = strip(
                "aarch64-linux-gnu-strip",
                &lib,
                &out_dir.join(format!("{MODEL_IDENTIFIER}.{pid}.aarch64.so")),
            )?;
            binaries3.push((
                format!("binaries/aarch64-linux/{MODEL_IDENTIFIER}.so"),
                bytes,
            ));
        }
        (Err(why), _) => notes.push(format!("no aarch64-linux binary in the FMI 3.0 FMU: {why}")),
        (_, None) => notes.push(
            "no aarch64-linux binary in the FMI 3.0 FMU: cargo-zigbuild and zig are not installed"
                .into(),
        ),
    }
    pack(
        &out_dir,
        &format!("{MODEL_IDENTIFIER}-fmi3.fmu"),
        &xml3,
        &binaries3,
    )?;
    for n in &notes {
        eprintln!("fmu-build: note: {n}");
    }
    Ok(())
}

/// Write the FMU `file_name` into `out_dir` (through a temporary file and a rename, which is
/// atomic: a test reading the FMU never sees half an archive) and say so.
fn pack(
    out_dir: &Path,
    file_name: &str,
    xml: &str,
    binaries: &[(String, Vec<u8>)],
) -> Result<(), String> {
    let fmu_path = out_dir.join(file_name);
    let tmp_path = out_dir.join(format!("{file_name}.{}.tmp", std::process::id()));
    let platforms: Vec<&str> = binaries
        .iter()
        .map(|(name, _)| name.split('/').nth(1).unwrap_or("?"))
        .collect();
    write_zip(&tmp_path, xml, binaries, &docs::index_html(&platforms))?;
    fs::rename(&tmp_path, &fmu_path).map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} kB; platforms: {})",
        fmu_path.display(),
        fs::metadata(&fmu_path).map(|m| m.len() / 1024).unwrap_or(0),
        platforms.join(", ")
    );
    Ok(())
}

/// cargo-zigbuild's target for aarch64 Linux, glibc 2.17 symbol versions like x86_64's.
const AARCH64_ZIG_TARGET: &str = "aarch64-unknown-linux-gnu.2.17";

/// The rustc that has an aarch64-unknown-linux-gnu standard library: rustup's when it has
/// one, else Debian's rustc-web with its arm64 standard library, unpacked by
/// tests/install_toolchains.sh into `~/.cache/viscosph/rust-aarch64` (rustup cannot download
/// targets on a machine that reaches only package registries), or `$VISCOSPH_AARCH64_RUSTC`.
fn aarch64_rustc() -> Result<PathBuf, String> {
    const TARGET: &str = "aarch64-unknown-linux-gnu";
    let has_target = |rustc: &Path| {
        Command::new(rustc)
            .args(["--print", "sysroot"])
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| {
                Path::new(String::from_utf8_lossy(&o.stdout).trim())
                    .join("lib/rustlib")
                    .join(TARGET)
                    .join("lib")
                    .is_dir()
            })
            .unwrap_or(false)
    };
    let mut candidates: Vec<PathBuf> = Vec::new();
    if let Some(p) = std::env::var_os("VISCOSPH_AARCH64_RUSTC") {
        candidates.push(PathBuf::from(p));
    }
    candidates.push(PathBuf::from("rustc"));
    if let Some(home) = std::env::var_os("HOME") {
        candidates.push(Path::new(&home).join(".cache/viscosph/rust-aarch64/rustc"));
    }
    candidates
        .into_iter()
        .find(|c| has_target(c))
        .ok_or_else(|| {
            format!(
                "no rustc with the {TARGET} standard library (tests/install_toolchains.sh unpacks \
                 Debian's rustc-web and libstd-rust-web-dev:arm64 into ~/.cache/viscosph/rust-aarch64)"
            )
        })
}

/// cargo-zigbuild's target: x86_64 Linux, glibc 2.17 symbol versions (CentOS 7 and later).
const LINUX_ZIG_TARGET: &str = "x86_64-unknown-linux-gnu.2.17";
/// Rust's MinGW-w64 target: a DLL that needs only the Windows system libraries.
const WINDOWS_TARGET: &str = "x86_64-pc-windows-gnu";

/// `cargo <args> --release --lib -p viscosph --target-dir <dir>`, with extra environment.
fn cargo_build(
    cargo: &str,
    root: &Path,
    args: &[&str],
    target_dir: &Path,
    env: &[(&str, &std::ffi::OsStr)],
) -> Result<(), String> {
    let mut cmd = Command::new(cargo);
    cmd.args(args)
        .args(["--release", "--lib", "-p", "viscosph", "--target-dir"])
        .arg(target_dir)
        .current_dir(root);
    for (k, v) in env {
        cmd.env(k, v);
    }
    let status = cmd
        .status()
        .map_err(|e| format!("could not run {cargo}: {e}"))?;
    if !status.success() {
        return Err(format!(
            "`cargo {} --release --lib -p viscosph` failed",
            args.join(" ")
        ));
    }
    Ok(())
}

/// `(PATH, zig)` for `cargo zigbuild`, if cargo-zigbuild and zig are installed: from the
/// project's .venv (PyPI's cargo-zigbuild and ziglang, which tests/python/setup_venv.sh
/// installs), else from the PATH. The PATH returned has .venv/bin first, where cargo looks for
/// the `cargo-zigbuild` subcommand.
fn zig_tools(root: &Path) -> Option<(std::ffi::OsString, PathBuf)> {
    let works = |prog: &Path, arg: &str| {
        Command::new(prog)
            .arg(arg)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .map(|s| s.success())
            .unwrap_or(false)
    };
    let venv_bin = root.join(".venv").join("bin");
    let mut dirs = vec![venv_bin.clone()];
    dirs.extend(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    ));
    let path = std::env::join_paths(&dirs).ok()?;
    let find = |name: &str| dirs.iter().map(|d| d.join(name)).find(|p| p.is_file());
    let zigbuild = find("cargo-zigbuild")?;
    if !works(&zigbuild, "--version") {
        return None;
    }
    let zig = find("python-zig")
        .filter(|z| works(z, "version"))
        .or_else(|| find("zig").filter(|z| works(z, "version")))?;
    Some((path, zig))
}

/// Whether the win64 DLL can be built here, and if not, what is missing.
fn windows_tool_chain() -> Result<(), String> {
    let linker = Command::new("x86_64-w64-mingw32-gcc")
        .arg("--version")
        .stdout(std::process::Stdio::null())
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    if !linker {
        return Err("x86_64-w64-mingw32-gcc not found (Debian: apt-get install mingw-w64)".into());
    }
    let sysroot = Command::new("rustc")
        .args(["--print", "sysroot"])
        .output()
        .map_err(|e| format!("rustc: {e}"))?;
    let sysroot = String::from_utf8_lossy(&sysroot.stdout).trim().to_string();
    let std_dir = Path::new(&sysroot)
        .join("lib")
        .join("rustlib")
        .join(WINDOWS_TARGET);
    if !std_dir.is_dir() {
        return Err(format!(
            "the Rust standard library for {WINDOWS_TARGET} is not installed \
             (rustup target add {WINDOWS_TARGET})"
        ));
    }
    Ok(())
}

/// The library's bytes without debug sections (about 20 times smaller), or as built if the
/// `strip` program for its format is not available.
fn strip(program: &str, lib: &Path, out: &Path) -> Result<Vec<u8>, String> {
    let ok = Command::new(program)
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
        eprintln!(
            "fmu-build: `{program}` not available; packing {} with its debug info",
            lib.display()
        );
        lib
    };
    let bytes = fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()));
    let _ = fs::remove_file(out);
    bytes
}

fn write_zip(
    path: &Path,
    xml: &str,
    binaries: &[(String, Vec<u8>)],
    html: &str,
) -> Result<(), String> {
    let file = fs::File::create(path).map_err(|e| e.to_string())?;
    let mut zip = zip::ZipWriter::new(file);
    let text = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let exe = text.unix_permissions(0o755);
    let mut entries: Vec<(&str, &[u8], SimpleFileOptions)> =
        vec![("modelDescription.xml", xml.as_bytes(), text)];
    for (name, bytes) in binaries {
        entries.push((name, bytes, exe));
    }
    entries.push(("documentation/index.html", html.as_bytes(), text));
    for (name, bytes, opts) in entries {
        zip.start_file(name, opts).map_err(|e| e.to_string())?;
        zip.write_all(bytes).map_err(|e| e.to_string())?;
    }
    zip.finish().map_err(|e| e.to_string())?;
    Ok(())
}
