"""Start-up Poiseuille flow of an Oldroyd-B fluid at several Wi (ISPH) against Waters & King
1970's exact series: the centre-line velocity over time."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import common  # noqa: E402

case = common.Case(__file__, __doc__)
n, t_end = (15, 3.0) if case.short else (30, 10.0)
interval = 0.02
wis = [1, 10, 100]
plt = common.figure()
fig, axes = plt.subplots(1, len(wis), figsize=(12, 3.6))
for ax, wi in zip(axes, wis):
    s, _ = case.run("scene.toml", f"wi{wi}",
                    {"relaxation_time": float(wi), "particles_per_diameter": n},
                    t_end=t_end, interval=interval)
    # The exact series for the scene file as run (`viscosph exact waters-king`).
    ex = case.exact("waters-king", case.work / f"wi{wi}" / "scene.in.toml",
                    "--t-end", s["time"][-1], "--interval", interval)
    t, u, ue = s["time"], s["centreline_velocity"], ex["centreline_velocity"]
    # Off by at most this fraction of max(U, |u_exact|) at every output time (U = 1 m/s).
    err = max(abs(a - b) / max(1.0, abs(b)) for a, b in zip(u, ue))
    ax.plot(ex["time"], ue, "k-", lw=2, label="Waters & King (exact)")
    ax.plot(t, u, "C3--", label=f"ISPH, {n} across")
    ax.set(xlabel="t U / H", ylabel="centre-line velocity / U",
           title=f"Oldroyd-B, Re = 1, beta = 0.1, Wi = {wi}")
    ax.legend(fontsize=7)
    case.measured(f"wi{wi}_error", f"Wi = {wi}, {n} across: max over t of "
                  "abs(u_c - u_exact) / max(U, abs(u_exact))", err, "{:.4f}")
fig.tight_layout()
fig.savefig(case.out / "waters_king.png", dpi=110)
case.finish(f"Centre-line velocity every {interval} H/U to t = {t_end} H/U; the exact one is "
            "the series of `viscosph-reference` (`viscosph exact waters-king` on the scene "
            "file as run).")
