"""What every case of the validation gallery shares: running the `viscosph` binary on a scene,
reading its time series, the thresholds a case's README states, and the results file.

A case is a directory validation/<case>/ with README.md, scene files (*.toml), run.py and, after
a full run, the figure <case>.png and results.md. `run.py` runs the case (`--short`: the low
resolution of the CI; without: the resolution the README quotes), compares with the reference,
writes the figure and the results and exits 1 when a measured error breaks a threshold of the
README's table "Thresholds" for that mode.
"""

import argparse
import csv
import hashlib
import io
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# Files of a run kept beside its time series when the run writes them (read through
# `Case.kept[label]`): the cylinder array's time-averaged centre line.
KEPT_FILES = ("centreline.csv",)


def binary():
    """The release binary (VISCOSPH_BIN overrides): the gallery builds nothing itself."""
    b = Path(os.environ.get("VISCOSPH_BIN", ROOT / "target" / "release" / "viscosph"))
    if not b.exists():
        sys.exit(f"{b} does not exist: cargo build --release -p viscosph-cli first")
    return str(b)


def commit():
    """The commit the results belong to (`-dirty` with uncommitted changes)."""
    r = subprocess.run(["git", "describe", "--always", "--dirty", "--abbrev=7"], cwd=ROOT,
                       capture_output=True, text=True)
    return r.stdout.strip() if r.returncode == 0 else "unknown"


def arguments(description):
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--short", action="store_true",
                   help="low resolution (the CI's check); results go to --out, not the case")
    p.add_argument("--out", type=Path, default=None,
                   help="where the figure and results go (default: the case directory in full "
                        "mode, target/validation/<case> with --short)")
    return p


class Case:
    """One gallery case: its directory, mode, output directory and measured quantities."""

    def __init__(self, file, description):
        self.dir = Path(file).resolve().parent
        self.name = self.dir.name
        args = arguments(description).parse_args()
        self.short = args.short
        self.mode = "short" if self.short else "full"
        self.out = args.out or (ROOT / "target" / "validation" / self.name if self.short
                                else self.dir)
        self.out.mkdir(parents=True, exist_ok=True)
        self.work = Path(tempfile.mkdtemp(prefix=f"viscosph-{self.name}-"))
        self.rows = []  # (key, description, value, format)
        self.kept = {}  # label -> the directory that keeps the run's files (see `run`)

    def run(self, scene, label, overrides=None, t_end=None, interval=None):
        """Run a scene file of the case with some keys replaced; returns (series, stdout).
        series maps each column of timeseries.csv to a list of floats."""
        text = (self.dir / scene).read_text()
        for key, value in (overrides or {}).items():
            line = f"{key} = {toml_value(value)}"
            text, n = re.subn(rf"(?m)^{key}\s*=.*$", line, text)
            if n == 0:
                text += line + "\n"
        run_dir = self.work / label
        run_dir.mkdir(parents=True, exist_ok=True)
        path = run_dir / "scene.in.toml"
        path.write_text(text)
        cmd = [binary(), "run", str(path), "--out", str(run_dir)]
        if t_end is not None:
            cmd += ["--t-end", repr(t_end)]
        if interval is not None:
            cmd += ["--output-interval", repr(interval)]
        # Every run's time series is kept under target/validation/runs/<case>/, named by the
        # label and a hash of the scene and options; VALIDATION_REUSE=1 reads it instead of
        # running again (to redraw against a new reference: the binary is not part of the key).
        key = hashlib.sha1((text + repr(cmd[5:])).encode()).hexdigest()[:12]
        kept = ROOT / "target" / "validation" / "runs" / self.name / f"{label}-{key}"
        self.kept[label] = kept
        if os.environ.get("VALIDATION_REUSE") == "1" and (kept / "timeseries.csv").exists():
            return (read_series(kept / "timeseries.csv"),
                    (kept / "stdout.txt").read_text())
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"{self.name}/{label}: viscosph run failed ({r.returncode}):\n"
                     f"{r.stdout}{r.stderr}")
        kept.mkdir(parents=True, exist_ok=True)
        for name in ("timeseries.csv", *KEPT_FILES):
            if (run_dir / name).exists():
                shutil.copy(run_dir / name, kept / name)
        (kept / "stdout.txt").write_text(r.stdout)
        return read_series(run_dir / "timeseries.csv"), r.stdout

    def exact(self, *args):
        """`viscosph exact ...` as columns (the solutions of the solver's reference code)."""
        r = subprocess.run([binary(), "exact", *map(str, args)], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"{self.name}: viscosph exact {' '.join(map(str, args))}: {r.stderr}")
        return columns(csv.DictReader(io.StringIO(r.stdout)))

    def measured(self, key, description, value, fmt="{:.4g}"):
        self.rows.append((key, description, value, fmt))

    def finish(self, notes=""):
        """Write results.md (full mode: into the case), compare with the README's thresholds
        for this mode, print the verdict and exit 1 on a broken one."""
        limits = thresholds(self.dir / "README.md", self.mode)
        failed = []
        lines = [f"Measured by `python3 validation/{self.name}/run.py"
                 f"{' --short' if self.short else ''}` on commit {commit()}.", "",
                 "| quantity | what | measured | threshold | verdict |",
                 "|---|---|---|---|---|"]
        for key, desc, value, fmt in self.rows:
            limit = limits.pop(key, None)
            verdict = ""
            if limit is not None:
                op, bound = limit
                ok = value <= bound if op == "<=" else value >= bound
                verdict = "pass" if ok else "FAIL"
                if not ok:
                    failed.append(f"{key} = {fmt.format(value)} (threshold {op} {bound})")
            shown = f"{op} {bound}" if limit is not None else ""
            lines.append(f"| `{key}` | {desc} | {fmt.format(value)} | {shown} | {verdict} |")
        if limits:
            failed.append(f"README thresholds without a measurement: {sorted(limits)}")
        text = "\n".join(lines) + "\n" + (f"\n{notes}\n" if notes else "")
        (self.out / "results.md").write_text(text)
        print(f"== {self.name} ({self.mode}): {self.out / 'results.md'}")
        print(text)
        if failed:
            print(f"{self.name}: FAILED: " + "; ".join(failed))
            sys.exit(1)


def toml_value(v):
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, bool):
        return "true" if v else "false"
    return repr(v)


def columns(reader):
    data = {}
    for row in reader:
        for k, v in row.items():
            data.setdefault(k, []).append(float(v))
    return data


def read_series(path):
    with open(path, newline="") as f:
        return columns(csv.DictReader(f))


def thresholds(readme, mode):
    """{key: (op, bound)} from the README's rows `| mode | ... | `key` | <= bound |`: the
    README is where a threshold is stated, the script only reads it."""
    out = {}
    for line in Path(readme).read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 3 and cells[0] == mode:
            key = re.search(r"`([a-z0-9_]+)`", line)
            bound = re.search(r"(<=|>=)\s*(-?[0-9.eE+-]+)\s*\|?\s*$", line.strip())
            if key and bound:
                out[key.group(1)] = (bound.group(1), float(bound.group(2)))
    return out


def figure():
    """A matplotlib figure module with a file backend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 9, "axes.grid": True, "grid.alpha": 0.3})
    return plt


def local_extrema(t, y, kind, t_from=0.0):
    """Times of the local maxima ('max') or minima ('min') of a sampled series after t_from."""
    out = []
    for k in range(1, len(y) - 1):
        if t[k] < t_from:
            continue
        if kind == "max" and y[k] >= y[k - 1] and y[k] > y[k + 1]:
            out.append(t[k])
        if kind == "min" and y[k] <= y[k - 1] and y[k] < y[k + 1]:
            out.append(t[k])
    return out
