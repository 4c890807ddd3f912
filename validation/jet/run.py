"""King & Lind 2021's buckling jet (WCSPH): when the jet reaches the plate, against the
slender-sheet model of a falling planar sheet (Matovich & Pearson 1969's long-wave equations in
planar form, `viscosph-reference`'s falling_sheet)."""
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import common  # noqa: E402

case = common.Case(__file__, __doc__)
resolutions = [6] if case.short else [6, 10]
fluids = [("oldroyd_b", {"rheology": "oldroyd_b"}),
          ("newtonian", {"rheology": "newtonian"})]
plt = common.figure()
fig, ax = plt.subplots(figsize=(7, 3.8))
for (fluid, keys), colour in zip(fluids, ["C0", "C1"]):
    for n, style in zip(resolutions, ["-", "--"]):
        label = f"{fluid}_{n}"
        s, out = case.run("scene.toml", label, {**keys, "particles_per_diameter": n},
                          t_end=0.26, interval=0.002)
        # The scene's own arrival (the first output with fluid on the plate: the heap has a
        # height), as `viscosph run` reports it.
        m = re.search(r"reached the plate at t = ([0-9.eE+-]+) s", out)
        if not m:
            sys.exit(f"jet/{label}: no arrival in the run's summary:\n{out}")
        t_sph = float(m.group(1))
        model = case.exact("falling-sheet", case.work / label / "scene.in.toml")
        t_model = model["arrival_time"][0]
        ax.plot(s["time"], s["wall_force_normal"], colour + style,
                label=f"{fluid}, {n} across: arrival {t_sph:.4f} s")
        ax.axvline(t_sph, color=colour, ls=":", lw=1)
        if n == resolutions[0]:
            ax.axvline(t_model, color=colour, lw=2, alpha=0.4,
                       label=f"{fluid}: slender-sheet model {t_model:.4f} s")
        case.measured(f"{fluid}_{n}_arrival_error", f"{fluid}, {n} across: abs(t_SPH / "
                      "t_model - 1) of the arrival at the plate", abs(t_sph / t_model - 1),
                      "{:.4f}")
ax.set(xlabel="t [s]", ylabel="normal force on the plate [N/m]",
       title="planar jet reaching the plate: SPH against the slender-sheet model")
ax.set_xlim(0.15, 0.26)
ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(case.out / "jet.png", dpi=110)
case.finish("The SPH arrival is the first output (every 2 ms) at which fluid lies on the "
            "plate (the heap has a height), as the jet scene reports it; the model's arrival is "
            "when the sheet's free end has fallen the nozzle height (`viscosph exact "
            "falling-sheet`). The figure shows the force on the plate, which starts a little "
            "earlier (the head within a kernel support of the wall particles).")
