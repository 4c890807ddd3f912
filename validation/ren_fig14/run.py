"""Ren, Lu & Jiang 2015 Fig. 14: front and back elongations of Newtonian and Cross drops on
plates inclined at 15, 30 and 45 degrees (PDRI-SPH), against what the paper's text states."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import common  # noqa: E402

case = common.Case(__file__, __doc__)
n = 20 if case.short else 40
angles = [15, 30, 45]
D = 0.02
plt = common.figure()
fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
end = {}
for ax, fluid in zip(axes, ["newtonian", "cross"]):
    for angle, colour in zip(angles, ["C0", "C1", "C2"]):
        s, _ = case.run(f"{fluid}.toml", f"{fluid}_{angle}",
                        {"plate_inclination": float(angle), "particles_per_diameter": n},
                        interval=0.002)
        t = [x / D for x in s["time"]]
        # Ren's convention (Fig. 5b): X_back > 0 uphill of the impact point, X_front < 0.
        front = [-x / D for x in s["spread_front"]]
        back = [x / D for x in s["spread_back"]]
        ax.plot(t, front, colour + "-", label=f"X_front {angle} deg")
        ax.plot(t, back, colour + "--", label=f"X_back {angle} deg")
        # Before contact X_back is the projection of the falling drop: the back edge's motion
        # on the plate starts with the first force on the plate.
        k0 = next((k for k, f in enumerate(s["wall_force_normal"]) if f != 0.0), 0)
        end[fluid, angle] = dict(front=front[-1], back=back[-1], back_max=max(back[k0:]))
    ax.set(xlabel="t* = t V / D", title=f"{fluid} drop, PDRI-SPH, {n} per diameter")
    ax.axhline(0, color="k", lw=0.6)
    ax.legend(fontsize=7, ncol=2)
axes[0].set_ylabel("elongation X / D")
fig.tight_layout()
fig.savefig(case.out / "ren_fig14.png", dpi=110)

for angle in angles:
    nw = end["newtonian", angle]
    case.measured(f"newtonian_{angle}_back_slip", f"Newtonian, {angle} deg: X_back's maximum "
                  "after contact minus its final value (text: the back edge slips forward)",
                  nw["back_max"] - nw["back"], "{:.3f}")
    case.measured(f"cross_faster_{angle}", f"{angle} deg: Newtonian X_front minus Cross "
                  "X_front at t* = 8 (text: the Cross drop spreads faster)",
                  nw["front"] - end["cross", angle]["front"], "{:.3f}")
slip = [end["newtonian", a]["back_max"] - end["newtonian", a]["back"] for a in angles]
case.measured("newtonian_back_slip_growth", "Newtonian: smallest growth of the back edge's slip "
              "from one angle to the next (text: more evident as the angle grows)",
              min(slip[k + 1] - slip[k] for k in range(len(angles) - 1)), "{:.3f}")
for fluid in ["newtonian", "cross"]:
    down = [end[fluid, a]["back"] + end[fluid, a]["front"] for a in angles]
    case.measured(f"{fluid}_asymmetry_growth", f"{fluid}: smallest growth of the downhill "
                  "shift -(X_front + X_back) at t* = 8 from one angle to the next (text: "
                  "asymmetry grows with the angle)",
                  min(down[k] - down[k + 1] for k in range(len(angles) - 1)), "{:.3f}")
case.finish("X_front = -spread_front / D, X_back = spread_back / D, measured along the plate "
            "from the impact point (the plate point below the drop's initial centre).")
