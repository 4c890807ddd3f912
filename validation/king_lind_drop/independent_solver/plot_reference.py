"""Draws reference.png from the committed runs tables: the independent solvers' own convergence
(W*(t*) and H*(t*) at each mesh) and the effect of the ambient gas' density and viscosity ratios;
`--table` prints the same as a markdown table (the README's). Runs no solver; `../run.py` calls
`draw` in full mode."""
import csv
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))
import common  # noqa: E402

KEYS = ("per_width", "rho_ratio", "mu_ratio")
# (title, solver, runs tables)
PANELS = [
    ("Newtonian", "Gerris", ["newtonian_runs.csv", "newtonian_gas_runs.csv"]),
    ("Newtonian", "OpenFOAM", ["newtonian_openfoam_runs.csv"]),
    ("Oldroyd-B (De = 1, beta = 0.1)", "OpenFOAM + Maxwell", ["oldroyd_b_runs.csv"]),
]


def runs(files):
    """[((per_width, rho ratio, mu ratio), rows)] of the tables, sorted."""
    out = {}
    for name in files:
        path = HERE / name
        if not path.exists():
            continue
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                key = (int(r["per_width"]), float(r["rho_ratio"]), float(r["mu_ratio"]))
                out.setdefault(key, []).append(r)
    return sorted(out.items())


def draw(out=None):
    """reference.png (into this directory unless `out` names another file)."""
    out = out or HERE / "reference.png"
    plt = common.figure()
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.4))
    for k, (title, solver, files) in enumerate(PANELS):
        aw, ah = axes[1] if k == 2 else axes[0]
        for j, ((n, rr, mr), rows) in enumerate(runs(files)):
            t = [float(r["t_star"]) for r in rows]
            colour = f"C{(j + 4 * k) % 10}"
            ls = "--" if k == 1 else ("-" if (rr, mr) == (1e-3, 1e-3) or k == 2 else "-.")
            aw.plot(t, [float(r["width_star"]) for r in rows], color=colour, ls=ls, lw=1,
                    label=f"{solver} {n}/W, gas {rr:g} / {mr:g}")
            ah.plot(t, [float(r["height_star"]) for r in rows], color=colour, ls=ls, lw=1)
    for row, what in ((0, "Newtonian"), (1, "Oldroyd-B")):
        aw, ah = axes[row]
        aw.set(xlabel="t* = t U / W", ylabel="W* = width / W",
               title=f"{what}: width (gas: density / viscosity ratio)")
        ah.set(xlabel="t* = t U / W", ylabel="H* = height / W", title=f"{what}: height")
        aw.legend(fontsize=6.5, loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def table():
    lines = ["| fluid | solver | cells per W | gas rho / eta ratio | W*(2) | W*(4) | W*(8) | H*(2) "
             "| H*(4) | H*(8) | largest volume change |", "|---|---|---|---|---|---|---|---|---|"
             "---|---|"]
    for title, solver, files in PANELS:
        for (n, rr, mr), rows in runs(files):
            at = {r["t_star"]: r for r in rows}
            cells = [f"{float(at[t]['width_star']):.4f}" if t in at else "" for t in
                     ("2.00", "4.00", "8.00")]
            cells += [f"{float(at[t]['height_star']):.4f}" if t in at else "" for t in
                      ("2.00", "4.00", "8.00")]
            vol = max(abs(float(r["volume_change"])) for r in rows)
            lines.append(f"| {title.split(' ')[0]} | {solver} | {n} | {rr:g} / {mr:g} | "
                         + " | ".join(cells) + f" | {vol:.1e} |")
    return "\n".join(lines)


if __name__ == "__main__":
    if "--table" in sys.argv:
        print(table())
    else:
        draw()
