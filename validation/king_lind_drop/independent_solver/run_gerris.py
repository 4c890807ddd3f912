"""Runs the Newtonian Re = 4 drop under Gerris (drop.gfs) and measures W*(t*) and H*(t*) from its
volume-fraction field the way ViscoSPH measures drop_width and drop_height; writes the CSVs of
this directory. Not part of the gallery's short mode (that reads the committed CSVs).

    python3 run_gerris.py                      the resolutions and gas ratios of the README
    python3 run_gerris.py --level 8 --ratio 1e-2 --out /tmp/x   one run, its CSV to stdout

Needs `gerris2D` (Debian: gerris, plus openmpi-bin whose orted the MPI build of gerris2D
starts even on one process) and numpy. Runs at nice 10, one at a time.
"""
import argparse
import csv
import re
import resource
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
BOX = 4.0  # side of Gerris' box in W
AXIS, PLATE = -2.0, -2.0  # x of the symmetry axis, y of the plate
# (finest level, gas density ratio, gas viscosity ratio): 2^level / 4 cells per W.
CONVERGENCE = [(7, 1e-3, 1e-3), (8, 1e-3, 1e-3), (9, 1e-3, 1e-3)]
RATIOS = [(7, 1e-2, 1e-2), (7, 1e-3, 1e-2), (7, 1e-2, 1e-3), (7, 1e-4, 1e-4)]
BASE = (1e-3, 1e-3)  # the gas ratios of newtonian.csv: its finest run with them
FRACTION = 0.01  # cells with T below this are gas (VOF leaves round-off traces)


def measure(path):
    """(W*, H*, relative volume change) of one text dump of the leaf cells (x y z T level).

    ViscoSPH: drop_width = max s - min s + dx over the particles, i.e. the extent of the cells
    dx wide the particles stand for; drop_height = max d + dx / 2, the top of the highest cell
    above the plate. Here a cell h wide holding the fraction T contributes the liquid's edge at
    its low side + T h (the interface taken normal to the direction measured, which it is at
    the drop's rim and top); the width is twice the largest such x from the symmetry axis, the
    height the largest such y above the plate. Both converge to the true extent as h -> 0."""
    d = np.loadtxt(path, comments="#", ndmin=2)
    x, y, frac, level = d[:, 0], d[:, 1], d[:, 3], d[:, 4]
    h = BOX / 2.0**level
    m = frac >= FRACTION
    right = np.max(x[m] - h[m] / 2 + frac[m] * h[m])
    top = np.max(y[m] - h[m] / 2 + frac[m] * h[m])
    volume = 2.0 * np.sum(frac * h * h)  # the mirror half included
    return 2.0 * (right - AXIS), top - PLATE, volume / (np.pi / 4.0) - 1.0


def collect(work):
    """Rows (t*, W*, H*, volume change) of the dumps in a run directory, in time order."""
    rows = []
    for f in Path(work).glob("sim-*.txt"):
        t = float(re.search(r"sim-([0-9.]+)\.txt", f.name).group(1))
        rows.append((t, *measure(f)))
    return sorted(rows)


def run(level, rho_ratio, mu_ratio, end=8.0):
    """Runs one case in a temporary directory; returns rows (t*, W*, H*, volume change) and the
    CPU seconds."""
    text = (HERE / "drop.gfs").read_text()
    for key, value in {"LEVEL": level, "RHOR": rho_ratio, "MUR": mu_ratio, "END": end}.items():
        text = text.replace(f"@{key}@", str(value))
    work = Path(tempfile.mkdtemp(prefix=f"gerris-l{level}-"))
    (work / "drop.gfs").write_text(text)
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    r = subprocess.run(["nice", "-n", "10", "gerris2D", "drop.gfs"], cwd=work,
                       capture_output=True, text=True)
    cpu = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before
    if r.returncode != 0:
        sys.exit(f"gerris2D failed in {work}:\n{r.stderr[-2000:]}")
    rows = collect(work)
    shutil.rmtree(work)
    return rows, cpu


def write(path, rows, header):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)


HEADER = ["level", "per_width", "rho_ratio", "mu_ratio", "t_star", "width_star", "height_star",
          "volume_change"]


def load(path):
    """{(level, rho ratio, mu ratio): rows} of a runs table."""
    done = {}
    if path.exists():
        with open(path) as f:
            for r in csv.DictReader(f):
                key = (int(r["level"]), float(r["rho_ratio"]), float(r["mu_ratio"]))
                done.setdefault(key, []).append(r)
    return done


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--level", type=int)
    p.add_argument("--ratio", type=float, default=1e-3, help="gas density and viscosity ratio")
    p.add_argument("--only", choices=["convergence", "ratios", "none"],
                   help="none: only rewrite newtonian.csv from newtonian_runs.csv")
    p.add_argument("--collect", metavar="DIR",
                   help="add the dumps of a run stopped early (its directory, with --level) to "
                        "newtonian_runs.csv as far as it got; newtonian.csv keeps the finest "
                        "run that reached t* = 8")
    a = p.parse_args()
    if a.collect:
        rows = collect(a.collect)
        path = HERE / "newtonian_runs.csv"
        done = load(path)
        done[(a.level, *BASE)] = [dict(level=a.level, per_width=2**a.level // 4,
                                       rho_ratio=BASE[0], mu_ratio=BASE[1], t_star=f"{t:.2f}",
                                       width_star=f"{w:.5f}", height_star=f"{h:.5f}",
                                       volume_change=f"{v:.2e}") for t, w, h, v in rows]
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, HEADER, lineterminator="\n")
            w.writeheader()
            for key in sorted(done):
                w.writerows(done[key])
        print(f"level {a.level}: {len(rows)} dumps to t* = {rows[-1][0]:.2f}")
        a.only = "none"
    elif a.level is not None:
        rows, cpu = run(a.level, a.ratio, a.ratio)
        print("t_star,width_star,height_star,volume_change")
        for r in rows:
            print(",".join(f"{v:.5g}" for v in r))
        print(f"cpu {cpu:.1f} s", file=sys.stderr)
        return
    # The meshes at the baseline gas, and the gas ratios at one mesh, each in its own table;
    # a run already in its table is not repeated.
    tables = {"convergence": (CONVERGENCE, HERE / "newtonian_runs.csv"),
              "ratios": (RATIOS, HERE / "newtonian_gas_runs.csv")}
    for name, (todo, path) in tables.items():
        if a.only not in (None, name):
            continue
        for level, rr, mr in todo:
            done = load(path)
            if (level, rr, mr) in done:
                continue
            rows, cpu = run(level, rr, mr)
            print(f"level {level} ({2**level // 4}/W), gas {rr:g}/{mr:g}: W*(8) = "
                  f"{rows[-1][1]:.4f}, H*(8) = {rows[-1][2]:.4f}, largest |volume change| "
                  f"{max(abs(r[3]) for r in rows):.2e}, {cpu:.0f} s CPU", flush=True)
            done = load(path)
            done[(level, rr, mr)] = [dict(level=level, per_width=2**level // 4, rho_ratio=rr,
                                          mu_ratio=mr, t_star=f"{t:.2f}", width_star=f"{w:.5f}",
                                          height_star=f"{h:.5f}", volume_change=f"{v:.2e}")
                                     for t, w, h, v in rows]
            with open(path, "w", newline="") as f:
                w = csv.DictWriter(f, HEADER, lineterminator="\n")
                w.writeheader()
                for key in sorted(done):
                    w.writerows(done[key])
    done = load(HERE / "newtonian_runs.csv")
    base = [key for key in done if key[1:] == BASE and float(done[key][-1]["t_star"]) >= 8.0]
    if base:
        write(HERE / "newtonian.csv",
              [(r["t_star"], r["width_star"], r["height_star"]) for r in done[max(base)]],
              ["t_star", "width_star", "height_star"])


if __name__ == "__main__":
    main()
