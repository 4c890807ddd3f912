"""King & Lind 2021's Re = 4 drop, Newtonian and Oldroyd-B (De = 1, beta = 0.1): what the paper's
text states about its Fig. 12 (ISPH), and the three schemes against an independent free-surface
solver (independent_solver/: Gerris for the Newtonian drop, OpenFOAM's interFoam with the Maxwell
model for the Oldroyd-B drop)."""
import csv
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import common  # noqa: E402
import drops  # noqa: E402

case = common.Case(__file__, __doc__)
REF = case.dir / "independent_solver"
SCHEMES = ["wcsph", "pdri", "isph"]
FLUIDS = {"newtonian": "Newtonian", "oldroyd_b": "Oldroyd-B (De = 1, beta = 0.1)"}
# The reference of each fluid, the runs table its convergence is drawn from and how a run of it
# is named there.
REFERENCE = {"newtonian": ("newtonian.csv", "newtonian_runs.csv", "Gerris"),
             "oldroyd_b": ("oldroyd_b.csv", "oldroyd_b_runs.csv", "OpenFOAM")}
CHECK_TIMES = (2.0, 4.0, 8.0)


def timing(n, ob):
    case.measured(f"oldroyd_b_{n}_t_min_offset", f"Oldroyd-B, {n}/W: abs(t* - 3.5), t* of the "
                  f"narrowest drop after the first maximum ({ob['t_min']:.2f}; text: local "
                  "minimum at t* = 3.5)", abs(ob["t_min"] - 3.5), "{:.2f}")


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def reference(fluid):
    """(t*, W*, H*) arrays of the fluid's committed reference curve, or None."""
    path = REF / REFERENCE[fluid][0]
    if not path.exists():
        return None
    rows = read(path)
    return tuple(np.array([float(r[k]) for r in rows]) for k in
                 ("t_star", "width_star", "height_star"))


def differences(run, ref):
    """Signed relative differences of W* and H* at CHECK_TIMES and the rms of W* - W*_ref and
    H* - H*_ref over the reference's span (t* <= 8), the reference interpolated to the run's
    output times."""
    t, w, h = (np.array(run[k]) for k in ("t", "w", "h"))
    tr, wr, hr = ref
    m = t <= tr[-1] + 1e-9
    out = {}
    for tc in CHECK_TIMES:
        k = int(np.argmin(abs(t - tc)))
        out[f"w{tc:g}"] = w[k] / np.interp(t[k], tr, wr) - 1.0
        out[f"h{tc:g}"] = h[k] / np.interp(t[k], tr, hr) - 1.0
    out["w_rms"] = float(np.sqrt(np.mean((w[m] - np.interp(t[m], tr, wr)) ** 2)))
    out["h_rms"] = float(np.sqrt(np.mean((h[m] - np.interp(t[m], tr, hr)) ** 2)))
    return out


isph = drops.newtonian_and_oldroyd_b(
    case, [(3.5, "King & Lind: Oldroyd-B W* minimum")], "King & Lind's Re = 4 drop (ISPH)",
    None, ("W", "U"), ("spreading, no rebound", ""), timing)

resolutions = [20] if case.short else [20, 40]
runs = {}
for fluid in FLUIDS:
    for scheme in SCHEMES:
        for n in resolutions:
            label = f"{fluid} {n}"
            if scheme == "isph" and label in isph:
                runs[(fluid, scheme, n)] = isph[label]
                continue
            found = drops.run_drops(case, [(f"{fluid} {scheme} {n}", f"{fluid}.toml",
                                            {"scheme": scheme, "particles_per_diameter": n})],
                                    0.02, 1.0, [], "", None)
            runs[(fluid, scheme, n)] = found[f"{fluid} {scheme} {n}"]

plt = common.figure()
fig, axes = plt.subplots(2, 2, figsize=(11, 7.6))
colours = {"wcsph": "C0", "pdri": "C1", "isph": "C2"}
styles = {20: ":", 40: "--", 80: "-"}
table = ["Differences from the independent solver, (SPH - reference) / reference at t* = 2, 4, "
         "8 and the rms of the difference over 0 <= t* <= 8 (in W):", "",
         "| fluid | scheme | W/dr | W* t*=2 | W* t*=4 | W* t*=8 | H* t*=2 | H* t*=4 | H* t*=8 "
         "| rms W* | rms H* |", "|---|---|---|---|---|---|---|---|---|---|---|"]
for row, (fluid, title) in enumerate(FLUIDS.items()):
    ax_w, ax_h = axes[row]
    ref = reference(fluid)
    name = REFERENCE[fluid][2]
    runs_path = REF / REFERENCE[fluid][1]
    if runs_path.exists():
        # The reference's other meshes (the gas of its reference curve), thin and grey.
        all_runs = read(runs_path)
        keys = sorted({(int(r["per_width"]), r["rho_ratio"], r["mu_ratio"]) for r in all_runs})
        for n, rr, mr in keys:
            sel = [r for r in all_runs if (int(r["per_width"]), r["rho_ratio"], r["mu_ratio"])
                   == (n, rr, mr)]
            if ref is not None and len(sel) == len(ref[0]) and all(
                    float(r["width_star"]) == w for r, w in zip(sel, ref[1])):
                continue
            t = [float(r["t_star"]) for r in sel]
            for ax, k in ((ax_w, "width_star"), (ax_h, "height_star")):
                ax.plot(t, [float(r[k]) for r in sel], color="0.55", lw=0.8, ls=(0, (1, 1)))
    if ref is not None:
        for ax, y in ((ax_w, ref[1]), (ax_h, ref[2])):
            ax.plot(ref[0], y, color="k", lw=2, label=f"{name} (finest)")
    for scheme in SCHEMES:
        for n in resolutions:
            r = runs[(fluid, scheme, n)]
            ax_w.plot(r["t"], r["w"], color=colours[scheme], ls=styles[n], lw=1.2,
                      label=f"{scheme} {n}/W")
            ax_h.plot(r["t"], r["h"], color=colours[scheme], ls=styles[n], lw=1.2)
            if ref is None:
                continue
            d = differences(r, ref)
            case.measured(f"{fluid}_{scheme}_{n}_w8", f"{title}, {scheme}, {n}/W: "
                          f"abs(W*(8) / W*_ref(8) - 1) against {name}", abs(d["w8"]), "{:.3f}")
            case.measured(f"{fluid}_{scheme}_{n}_h8", f"{title}, {scheme}, {n}/W: "
                          f"abs(H*(8) / H*_ref(8) - 1) against {name}", abs(d["h8"]), "{:.3f}")
            case.measured(f"{fluid}_{scheme}_{n}_w_rms", f"{title}, {scheme}, {n}/W: rms of "
                          f"W* - W*_ref over t* <= 8 (in W)", d["w_rms"], "{:.3f}")
            table.append(f"| {fluid} | {scheme} | {n} | " + " | ".join(
                f"{100 * d[k]:+.1f} %" for k in ("w2", "w4", "w8", "h2", "h4", "h8"))
                + f" | {d['w_rms']:.3f} | {d['h_rms']:.3f} |")
    if fluid == "oldroyd_b":
        for ax in (ax_w, ax_h):
            ax.axvline(3.5, color="0.5", ls=":", lw=1)
        ax_w.text(3.5, 2.0, "King & Lind: W* minimum", rotation=90, fontsize=7, va="top",
                  ha="right")
    ax_w.set(xlabel="t* = t U / W", ylabel="W* = width / W", title=f"{title}: width")
    ax_h.set(xlabel="t* = t U / W", ylabel="H* = height / W", title=f"{title}: height")
    ax_w.legend(fontsize=6.5, ncol=2, loc="lower right")
line_names = {":": "dotted", "--": "dashed", "-": "solid"}
fig.text(0.5, 0.005, "black: the reference on its finest mesh; grey dotted: its other meshes; "
         "colour: the SPH schemes (" + ", ".join(f"{line_names[styles[n]]} {n}"
                                                 for n in resolutions)
         + " particles per W)", ha="center", fontsize=7)
fig.tight_layout(rect=(0, 0.02, 1, 1))
fig.savefig(case.out / "king_lind_drop.png", dpi=110)
if not case.short:
    sys.path.insert(0, str(REF))
    import plot_reference  # noqa: E402

    plot_reference.draw(case.out / "reference.png" if case.out != case.dir else None)
case.finish("t* = t U / W with W = 2 cm, U = 1 m/s. The independent solver's setup, its own "
            "convergence and the gas ratios: `independent_solver/README.md`.\n\n"
            + "\n".join(table))
