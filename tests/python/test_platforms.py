"""The FMU's binaries beyond this machine: linux64 loads on old distributions (glibc symbol
versions at most 2.28), and win64 exists, exports every fmi2 function, and, run under wine by a
small importer compiled for Windows, steps the default drop to the same outputs as linux64. The
FMI 3.0 FMU's x86_64-windows (wine) and aarch64-linux (qemu-aarch64) binaries, driven through
the fmi3 functions by the same importer, give x86_64-linux's outputs within 1e-12.

Skipped, with the reason printed, only where mingw-w64, wine, gcc-aarch64-linux-gnu or
qemu-user are not installed; the test command installs them (tests/install_toolchains.sh)."""

import os
import pathlib
import re
import shutil
import subprocess
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description

ROOT = pathlib.Path(__file__).resolve().parents[2]
IMPORTER = ROOT / "tests" / "platform" / "importer.c"
MINGW = "x86_64-w64-mingw32-gcc"
# The default drop, cut short: it falls 3 cm, lands at about 0.03 s and spreads.
STOP, STEP = 0.04, 1e-3


@pytest.fixture(scope="module")
def extracted(fmu, tmp_path_factory):
    d = tmp_path_factory.mktemp("platforms")
    with zipfile.ZipFile(fmu) as z:
        z.extractall(d)
    return d


def glibc_versions(lib):
    out = subprocess.run(["objdump", "-T", str(lib)], capture_output=True, text=True,
                         check=True).stdout
    return {tuple(int(x) for x in v.split(".")) for v in re.findall(r"GLIBC_(\d+(?:\.\d+)+)", out)}


def test_linux64_needs_at_most_glibc_2_28(extracted):
    versions = glibc_versions(extracted / "binaries" / "linux64" / "ViscoSPH.so")
    assert versions, "objdump -T lists the glibc symbols the library needs"
    newest = max(versions)
    print(f"linux64 needs GLIBC_{'.'.join(map(str, newest))}")
    assert newest <= (2, 28), f"needs GLIBC_{'.'.join(map(str, newest))} (Debian 10 / RHEL 8 have 2.28)"


def fmi2_exports_linux(lib):
    out = subprocess.run(["objdump", "-T", str(lib)], capture_output=True, text=True,
                         check=True).stdout
    return {w for w in re.findall(r"\b(fmi2\w+)$", out, re.M)}


def dll_exports(dll):
    objdump = shutil.which("x86_64-w64-mingw32-objdump") or "objdump"
    out = subprocess.run([objdump, "-p", str(dll)], capture_output=True, text=True,
                         check=True).stdout
    table = out.split("[Ordinal/Name Pointer] Table", 1)[1]
    return set(re.findall(r"\]\s+(fmi2\w+)", table))


def require(tool, what):
    if shutil.which(tool) is None:
        message = f"{tool} not installed ({what}); tests/install_toolchains.sh installs it"
        if os.environ.get("CI"):
            # In CI the test command has installed it: a missing tool is a failed install.
            pytest.fail(message)
        pytest.skip(message)


def test_win64_dll_exports_every_fmi2_function(extracted):
    require(MINGW, "Debian's mingw-w64 builds the win64 DLL")
    dll = extracted / "binaries" / "win64" / "ViscoSPH.dll"
    assert dll.is_file(), "mingw-w64 is installed, so fmu-build packs binaries/win64"
    linux = fmi2_exports_linux(extracted / "binaries" / "linux64" / "ViscoSPH.so")
    assert len(linux) == 44, sorted(linux)  # every function of fmi2Functions.h
    assert dll_exports(dll) == linux


def run_importer(cmd, lib, guid, md, env=None, extra=()):
    outputs = scalar_outputs(md)
    vrs = ",".join(str(v.valueReference) for v in outputs)
    run = subprocess.run(cmd + [lib, guid, str(STOP), str(STEP), vrs, *extra],
                         capture_output=True, text=True, timeout=900, env=env)
    assert run.returncode == 0, f"{cmd}: {run.returncode}\n{run.stderr[-3000:]}"
    rows = np.array([[float(x) for x in line.split(",")] for line in run.stdout.split()])
    assert rows.shape == (int(round(STOP / STEP)), 1 + len(outputs)), rows.shape
    return rows


def importers(tmp_path):
    """The test importer for Linux (gcc) and for Windows (mingw-w64), in `tmp_path`."""
    linux_exe, win_exe = tmp_path / "importer", tmp_path / "importer.exe"
    subprocess.run(["gcc", "-O1", "-o", str(linux_exe), str(IMPORTER), "-ldl"], check=True)
    subprocess.run([MINGW, "-O1", "-o", str(win_exe), str(IMPORTER)], check=True)
    # wine 8 lacks Windows 10's bcryptprimitives.dll (ProcessPrng, used by Rust's std): a
    # stand-in next to the importer, found before the system directory (see its source)
    subprocess.run([MINGW, "-O1", "-shared", "-o", str(tmp_path / "bcryptprimitives.dll"),
                    str(IMPORTER.with_name("bcryptprimitives.c")), "-ladvapi32"], check=True)
    return linux_exe, win_exe


def wine_env():
    env = dict(os.environ, WINEDEBUG="-all", WINEPREFIX=str(ROOT / "target" / "wineprefix"),
               WINEDLLOVERRIDES="mscoree,mshtml=")
    env.pop("DISPLAY", None)
    return env


def wine_path(path):
    """wine maps the Unix file system to drive Z:"""
    return "Z:" + str(path).replace("/", "\\")


def test_win64_under_wine_matches_linux64(extracted, tmp_path):
    require(MINGW, "compiles the Windows importer")
    require("wine", "runs the Windows importer")
    md = read_model_description(str(extracted / "modelDescription.xml"))
    linux_exe, win_exe = importers(tmp_path)

    linux = run_importer([str(linux_exe)],
                         str(extracted / "binaries" / "linux64" / "ViscoSPH.so"), md.guid, md)
    dll = wine_path(extracted / "binaries" / "win64" / "ViscoSPH.dll")
    windows = run_importer(["wine", str(win_exe)], dll, md.guid, md, env=wine_env())
    # Before the impact the two runs are bitwise equal; after it, the platforms' libm (glibc's
    # and msvcrt's pow, exp, ...) round differently in the last bit, which the flow carries on.
    names = [v.name for v in scalar_outputs(md)]
    compare(linux, windows, names, "win64 vs linux64")


# --- FMI 3.0: ViscoSPH-fmi3.fmu on x86_64-linux, x86_64-windows (wine) and aarch64-linux (qemu)

FMU3 = ROOT / "target" / "fmu" / "ViscoSPH-fmi3.fmu"
AARCH64_GCC = "aarch64-linux-gnu-gcc"
# qemu-user's sysroot for the aarch64 importer and library: Debian's libc6-arm64-cross
AARCH64_SYSROOT = "/usr/aarch64-linux-gnu"


@pytest.fixture(scope="module")
def extracted3(fmu, tmp_path_factory):
    assert FMU3.is_file(), "fmu-build writes ViscoSPH-fmi3.fmu next to ViscoSPH.fmu"
    d = tmp_path_factory.mktemp("platforms3")
    with zipfile.ZipFile(FMU3) as z:
        z.extractall(d)
    return d


def scalar_outputs(md):
    """The outputs with one value each: the importer reads one value per value reference (the
    FMI 3.0 arrays wall_pressure and wall_shear are their scalar elements again)."""
    return [v for v in md.modelVariables if v.causality == "output" and not v.dimensions]


def compare(reference, other, names, what):
    """`other` equals `reference` within 1e-12 of each output's scale, bitwise before the
    impact, and the impact happened (the wall force is on, so the comparison covers it)."""
    force = reference[:, 1 + names.index("wall_force_normal")]
    assert force.max() > 0, "the drop has landed within the run"
    scale = np.maximum(np.abs(reference).max(axis=0), 1e-300)
    # the two force components share one scale, the force's size: on a level plate the
    # tangential force is round-off (about 1e-13 N/m against 100 N/m normal)
    forces = [1 + names.index("wall_force_normal"), 1 + names.index("wall_force_tangential")]
    scale[forces] = scale[forces].max()
    rel = np.abs(other - reference).max(axis=0) / scale
    print(f"largest relative difference {what}: {rel.max():.3e}")
    assert rel.max() <= 1e-12, dict(zip(["time"] + names, rel))
    falling = force == 0
    assert falling.any() and (other[falling] == reference[falling]).all()


def run3(cmd, lib, md, env=None):
    # a small drop (12 particles across) keeps the run under qemu short
    ppd = next(v for v in md.modelVariables if v.name == "particles_per_diameter")
    return run_importer(cmd + ["--fmi3"], lib, md.instantiationToken, md, env=env,
                        extra=[f"i:{ppd.valueReference}=12"])


def test_fmi3_aarch64_under_qemu_matches_x86_64(extracted3, tmp_path):
    require(AARCH64_GCC, "compiles the aarch64 importer")
    require("qemu-aarch64", "runs it")
    md = read_model_description(str(extracted3 / "modelDescription.xml"))
    lib = extracted3 / "binaries" / "aarch64-linux" / "ViscoSPH.so"
    assert lib.is_file(), "fmu-build packs binaries/aarch64-linux"
    assert "aarch64" in subprocess.run(["file", "-b", str(lib)], capture_output=True,
                                       text=True).stdout.replace("ARM aarch64", "aarch64")
    newest = max(glibc_versions(lib))
    assert newest <= (2, 28), f"needs GLIBC_{'.'.join(map(str, newest))}"
    x86_exe, arm_exe = tmp_path / "importer", tmp_path / "importer-aarch64"
    subprocess.run(["gcc", "-O1", "-o", str(x86_exe), str(IMPORTER), "-ldl"], check=True)
    subprocess.run([AARCH64_GCC, "-O1", "-o", str(arm_exe), str(IMPORTER), "-ldl"], check=True)
    x86 = run3([str(x86_exe)], str(extracted3 / "binaries" / "x86_64-linux" / "ViscoSPH.so"), md)
    arm = run3(["qemu-aarch64", "-L", AARCH64_SYSROOT, str(arm_exe)], str(lib), md)
    names = [v.name for v in scalar_outputs(md)]
    compare(x86, arm, names, "aarch64-linux (qemu) vs x86_64-linux")


def test_fmi3_x86_64_windows_under_wine_matches_x86_64_linux(extracted3, tmp_path):
    require(MINGW, "compiles the Windows importer")
    require("wine", "runs the Windows importer")
    md = read_model_description(str(extracted3 / "modelDescription.xml"))
    linux_exe, win_exe = importers(tmp_path)
    linux = run3([str(linux_exe)],
                 str(extracted3 / "binaries" / "x86_64-linux" / "ViscoSPH.so"), md)
    dll = wine_path(extracted3 / "binaries" / "x86_64-windows" / "ViscoSPH.dll")
    windows = run3(["wine", str(win_exe)], dll, md, env=wine_env())
    names = [v.name for v in scalar_outputs(md)]
    compare(linux, windows, names, "x86_64-windows (wine) vs x86_64-linux")
