"""King & Lind's periodic array of cylinders (ISPH, Eulerian) against the finite-element solution
of the same cell in reference/: the drag coefficient K = F / (eta0 <u>) over resolution
(Newtonian), the time-averaged centre-line velocity, and (full mode) Oldroyd-B at lambda 0.2 and
0.6 s: K and the centre-line polymer stress."""
import csv
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import common  # noqa: E402

REF = Path(__file__).resolve().parent / "reference"
L = 6.0  # the cell's length [m]; the cylinder sits at x = 3, radius R = 1
ETA0, BETA = 41.66, 0.59
# Runs stop three time units after the steady state (stop_at_steady_state); T_END only caps them.
# The fields are averaged over the outputs, one every INTERVAL.
T_END, INTERVAL = 20.0, 0.05


def read(path):
    with open(path, newline="") as f:
        return common.columns(csv.DictReader(row for row in f if not row.startswith("#")))


def fem_k(model):
    """K_fluid of the FEM's finest level for 'navier_stokes' or Oldroyd-B lambda (float)."""
    if isinstance(model, str):
        with open(REF / "cell_results.csv", newline="") as f:
            for r in csv.DictReader(f):
                if r["model"] == model and r["quantity"] == "K_fluid":
                    return float(r["value"])
    rows = read(REF / "oldroyd_b_convergence.csv")
    best = max((lv, k) for lam, lv, k in zip(rows["lam"], rows["level"], rows["K_fluid"])
               if abs(lam - model) < 1e-9)
    return best[1]


def averaged_k(stdout):
    """K over the three time units after the steady state, as `viscosph run` prints it."""
    m = re.search(r"means over the next 3 time units:.*?K = ([0-9.eE+-]+)", stdout)
    if m is None:
        sys.exit("cylinder_array: the run did not reach a steady state:\n" + stdout)
    return float(m.group(1))


def centreline(label):
    """The run's averaged centre line as (s/R from the cylinder's rear, u/<u>, tau_xx), from
    x = 4 R (the rear) through the periodic boundary to 2 R + L (the next cylinder's front)."""
    c = read(case.kept[label] / "centreline.csv")
    pts = sorted(((x - 4.0) % L, u, t) for x, u, t, n in
                 zip(c["x"], c["u_over_mean"], c["tau_xx"], c["particles"])
                 if n > 0 and (x - 4.0) % L <= 4.0)
    return [p[0] for p in pts], [p[1] for p in pts], [p[2] for p in pts]


def interp(x, xs, ys):
    for k in range(1, len(xs)):
        if xs[k] >= x:
            w = (x - xs[k - 1]) / (xs[k] - xs[k - 1])
            return ys[k - 1] + w * (ys[k] - ys[k - 1])
    return ys[-1]


case = common.Case(__file__, __doc__)
sizes = [8, 12] if case.short else [12, 16, 24]
k_ns = fem_k("navier_stokes")
ref = read(REF / "centreline.csv")
plt = common.figure()
fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(13, 3.8))
ks = []
for n in sizes:
    _, out = case.run("scene.toml", f"newtonian{n}", {"particles_per_diameter": n},
                      t_end=T_END, interval=INTERVAL)
    k = averaged_k(out)
    ks.append(k)
    case.measured(f"k_error_{n}", f"Newtonian, {n} across: abs(K - K_FEM) / K_FEM",
                  abs(k - k_ns) / k_ns, "{:.4f}")
a1.plot(sizes, ks, "C3o-", label="ISPH (Eulerian), Newtonian")
a1.axhline(k_ns, color="k", lw=1.5, label=f"FEM, Newtonian: {k_ns:.2f}")
s, u, _ = centreline(f"newtonian{sizes[-1]}")
err = max(abs(ui - interp(si, ref["s_over_R"], ref["u_over_mean_navier_stokes"]))
          for si, ui in zip(s, u))
case.measured(f"centreline_error_{sizes[-1]}", f"Newtonian, {sizes[-1]} across: max over the "
              "centre line of abs(u/⟨u⟩ - FEM)", err, "{:.4f}")
a2.plot(ref["s_over_R"], ref["u_over_mean_navier_stokes"], "k-", lw=1.5, label="FEM, Newtonian")
a2.plot(s, u, "C3.", ms=4, label=f"ISPH, {sizes[-1]} across")
if not case.short:
    ob = read(REF / "oldroyd_b_centreline.csv")
    n = 16
    for lam, colour in ((0.2, "C0"), (0.6, "C2")):
        label = f"oldroyd_b_lam{lam}_{n}"
        _, out = case.run("scene.toml", label, {"particles_per_diameter": n,
                                                "rheology": "oldroyd_b",
                                                "viscosity_ratio": BETA,
                                                "relaxation_time": lam},
                              t_end=T_END, interval=INTERVAL)
        k, k_ref = averaged_k(out), fem_k(lam)
        case.measured(f"k_error_oldroyd_b_lam{round(10 * lam):02d}",
                      f"Oldroyd-B beta 0.59, lambda {lam} s, {n} across: abs(K - K_FEM) / K_FEM",
                      abs(k - k_ref) / k_ref, "{:.4f}")
        a1.plot([n], [k], colour + "s", label=f"ISPH, Oldroyd-B lambda {lam} s")
        a1.axhline(k_ref, color=colour, lw=1, ls="--", label=f"FEM, lambda {lam} s: {k_ref:.2f}")
        s, u, tau = centreline(label)
        a2.plot(s, u, colour + ".", ms=3, label=f"ISPH, lambda {lam} s")
        a2.plot(ob["s_over_R"], ob[f"u_over_mean_lam{lam}"], colour + "-", lw=1)
        # The FEM's tau_xx is divided by eta_s <u> / R (eta_s = beta eta0, R = 1 m); the SPH
        # centre line is in Pa: multiply back with the FEM's own <u>.
        u_fem = read(REF / "oldroyd_b_convergence.csv")
        u_fem = max((lv, u) for la, lv, u in zip(u_fem["lam"], u_fem["level"],
                                                 u_fem["u_mean_fluid"]) if abs(la - lam) < 1e-9)[1]
        a3.plot(ob["s_over_R"], [t * BETA * ETA0 * u_fem for t in ob[f"tauxx_scaled_lam{lam}"]],
                colour + "-", lw=1.5, label=f"FEM, lambda {lam} s")
        a3.plot(s, tau, colour + ".", ms=3, label=f"ISPH, {n} across")
    a3.set(xlabel="s / R from the cylinder's rear", ylabel="polymer stress tau_xx [Pa]",
           title="Oldroyd-B centre line (Fig. 10)")
    a3.legend(fontsize=7)
else:
    a3.axis("off")
    a3.text(0.5, 0.5, "Oldroyd-B runs: full mode only", ha="center", va="center")
a1.set(xlabel="particles across the cylinder (2R)", ylabel="K = F / (eta0 <u>)",
       title="Drag coefficient")
a1.legend(fontsize=7)
a2.set(xlabel="s / R from the cylinder's rear", ylabel="u / <u> on y = H/2",
       title="Centre-line velocity, time-averaged")
a2.legend(fontsize=7)
fig.suptitle("Periodic array of cylinders (King & Lind 2021 section IV.B), ISPH against the "
             "finite-element cell", fontsize=10)
fig.tight_layout()
fig.savefig(case.out / "cylinder_array.png", dpi=110)
case.finish("K is averaged over the three time units R/⟨u⟩ after King & Lind's steady state "
            "(as `viscosph run` prints it); the FEM values are reference/cell_results.csv "
            "(Navier-Stokes, finest level) and reference/oldroyd_b_convergence.csv (finest "
            "level).")
