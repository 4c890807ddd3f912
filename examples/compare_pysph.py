#!/usr/bin/env python3
"""PySPH and ViscoSPH side by side on Monaghan's elliptical drop, on this machine, in one go.

    python3 examples/compare_pysph.py            # PySPH nx = 20 and 40 (1257 and 5025 particles)
    python3 examples/compare_pysph.py --nx 20    # one size

Installs PySPH from PyPI into .venv-pysph/ (the recipe of shared/NOTES.md: plain `pip install
pysph` does not build), builds ViscoSPH, then runs PySPH's `elliptical_drop` example (WCSPH,
Gaussian kernel, EPEC integrator, to t = 0.0076 s, single core: --no-openmp) and ViscoSPH's
`elliptical_drop` scene (wcsph and pdri, to the same time, one thread and two) at matched particle
counts: PySPH's nx = N lattice holds the same particles as ViscoSPH's particles_per_diameter = 2N.
Both errors are measured against the same exact semi-major axis, from the ODE
da/dt = -A a, dA/dt = A^2 (a^4 - 1)/(a^4 + 1) (1.9445171907 m at t = 0.0076 s), whatever each code
prints as its own exact value. Prints a table and writes it to results/bench/pysph.md (which
`viscosph bench report` puts into docs/benchmarks.md).
"""

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VENV = ROOT / ".venv-pysph"
T_END = 0.0076
EXACT_MAJOR = 1.9445171907  # shared/NOTES.md, Monaghan 1994 ODE at t = 0.0076 s


def sh(cmd, **kw):
    print("+", " ".join(str(c) for c in cmd), flush=True)
    return subprocess.run(cmd, check=True, **kw)


def ensure_pysph():
    py = VENV / "bin" / "python"
    if py.exists() and subprocess.run([py, "-c", "import pysph, matplotlib"], capture_output=True).returncode == 0:
        return VENV / "bin" / "pysph"
    sh([sys.executable, "-m", "venv", VENV])
    pip = [py, "-m", "pip", "install", "-q"]
    sh(pip + ["numpy", "cython", "mako", "setuptools", "wheel"])
    sh(pip + ["--no-build-isolation", "cyarray", "compyle", "beaker", "pytools"])
    sh(pip + ["--no-build-isolation", "pysph"])
    # PySPH prints the semi-axis only in post-processing, which needs matplotlib.
    sh(pip + ["matplotlib"])
    return VENV / "bin" / "pysph"


def run_pysph(pysph, nx, workdir):
    out = workdir / f"pysph_nx{nx}"
    t0 = time.perf_counter()
    p = subprocess.run([pysph, "run", "elliptical_drop", "--no-openmp", "--nx", str(nx), "-d", out],
                       capture_output=True, text=True, cwd=workdir)
    wall = time.perf_counter() - t0
    text = p.stdout + p.stderr
    if p.returncode != 0:
        sys.exit(f"PySPH failed:\n{text[-3000:]}")
    n = int(re.search(r"Elliptical drop :: (\d+) particles", text).group(1))
    run_took = float(re.search(r"Run took: ([0-9.]+) secs", text).group(1))
    exact, computed = map(float, re.search(
        r"Semi-major axis length \(exact, computed\) = ([0-9.eE+-]+), ([0-9.eE+-]+)", text).groups())
    return {"code": "PySPH wcsph (Gaussian, EPEC)", "threads": 1, "particles": n, "run_s": run_took,
            "wall_s": wall, "major": computed, "error": computed / EXACT_MAJOR - 1.0,
            "own_exact": exact}


def run_viscosph(exe, scheme, ppd, threads, workdir):
    scene = workdir / f"ell_{scheme}_{ppd}.toml"
    scene.write_text(f'scene = "elliptical_drop"\nscheme = "{scheme}"\nparticles_per_diameter = {ppd}\n')
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    t0 = time.perf_counter()
    p = subprocess.run([exe, "run", scene, "--t-end", str(T_END), "--output-interval", str(T_END / 4),
                        "--out", workdir / f"ours_{scheme}_{ppd}_{threads}"],
                       capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"viscosph failed:\n{p.stdout}\n{p.stderr}")
    m = re.search(r"(\d+) particles, (\d+) steps in ([0-9.]+) s", p.stdout)
    major = float(re.search(r"computed ([0-9.]+) m", p.stdout).group(1))
    return {"code": f"ViscoSPH {scheme}", "threads": threads, "particles": int(m.group(1)),
            "run_s": float(m.group(3)), "wall_s": wall, "major": major,
            "error": major / EXACT_MAJOR - 1.0}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nx", type=int, action="append", help="PySPH lattice size(s); default 20 and 40")
    args = ap.parse_args()
    sizes = args.nx or [20, 40]
    workdir = ROOT / "results" / "pysph"
    workdir.mkdir(parents=True, exist_ok=True)
    pysph = ensure_pysph()
    sh(["cargo", "build", "--release", "--bin", "viscosph"], cwd=ROOT)
    exe = ROOT / "target" / "release" / "viscosph"

    rows = []
    for nx in sizes:
        theirs = run_pysph(pysph, nx, workdir)
        rows.append(theirs)
        for scheme in ["wcsph", "pdri"]:
            for threads in [1, 2]:
                ours = run_viscosph(exe, scheme, 2 * nx, threads, workdir)
                if ours["particles"] != theirs["particles"]:
                    print(f"note: particle counts differ: PySPH {theirs['particles']}, ours {ours['particles']}")
                ours["speedup"] = theirs["run_s"] / ours["run_s"]
                rows.append(ours)

    lines = [
        f"Elliptical drop to t = {T_END} s; errors of the semi-major axis against the exact "
        f"{EXACT_MAJOR} m; 'run' is each code's own timing of the time loop (PySPH's 'Run took', "
        "ViscoSPH's run time), 'wall' the whole process including start-up.",
        "",
        "| code | threads | particles | semi-major axis [m] | error | run [s] | wall [s] | PySPH run time / this run time |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r['code']} | {r['threads']} | {r['particles']} | {r['major']:.5f} | "
                     f"{100 * r['error']:+.3f} % | {r['run_s']:.2f} | {r['wall_s']:.2f} | "
                     f"{r.get('speedup', 1.0):.1f} |")
    own = [r for r in rows if "own_exact" in r]
    if own:
        lines += ["", f"PySPH's own exact value is {own[0]['own_exact']:.7f} m (its ODE integration); "
                  "the errors above use the same exact value for both codes."]
    table = "\n".join(lines) + "\n"
    print(table)
    bench = ROOT / "results" / "bench"
    bench.mkdir(parents=True, exist_ok=True)
    (bench / "pysph.md").write_text(table)


if __name__ == "__main__":
    main()
