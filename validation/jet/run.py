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

# The round jet (dimension = 3): the 4 D Newtonian fall against the slender-thread model (the
# summary line's two times: the fluid's lowest point passing D/2 above the plate, against the
# model's fall of H - D/2, and its contact), and in full mode the tall (12 D) and short (2 D)
# Oldroyd-B falls (to t = 0.7 and 0.3 s): the tall one folds along the seed's direction (an
# elongated heap), neither coils.
if case.short:
    fig, ax1 = plt.subplots(figsize=(6, 3.8))
else:
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.8))
for n, style in zip([6] if case.short else [6, 10], ["-", "--"]):
    label = f"round_4d_{n}"
    s, out = case.run("scene_3d.toml", label, {"rheology": "newtonian", "nozzle_height": 0.024,
                                               "particles_per_diameter": n},
                      t_end=0.12, interval=0.001)
    half = re.search(r"passed D/2 above the plate at t = ([0-9.eE+-]+) s \(the "
                     r"slender-thread model's: ([0-9.eE+-]+) s", out)
    contact = re.search(r"reached the plate at t = ([0-9.eE+-]+) s", out)
    if not (half and contact):
        sys.exit(f"jet/{label}: no arrival in the run's summary:\n{out}")
    t_half, m_half, t_sph = float(half.group(1)), float(half.group(2)), float(contact.group(1))
    t_model = case.exact("falling-thread", case.work / label / "scene.in.toml")["arrival_time"][0]
    ax1.plot(s["time"], [h * 1e3 for h in s["jet_tip_height"]], "C2" + style,
             label=f"{n} across: D/2 at {t_half:.4f} s, contact {t_sph:.4f} s")
    ax1.plot([t_half], [3.0], "C2o")
    if n == 6:
        ax1.axvline(m_half, color="k", lw=1, ls="--",
                    label=f"thread model at D/2: {m_half:.4f} s")
        ax1.axvline(t_model, color="k", lw=2, alpha=0.4,
                    label=f"thread model arrives: {t_model:.4f} s")
    case.measured(f"round_4d_{n}_arrival_error", f"round jet, Newtonian, 4 D, {n} across: "
                  "abs(t_SPH / t_model - 1) of the lowest point's passage D/2 above the plate",
                  abs(t_half / m_half - 1), "{:.4f}")
    case.measured(f"round_4d_{n}_contact_error", f"... of the contact (the lowest point within "
                  "half a spacing) against the model's arrival", abs(t_sph / t_model - 1),
                  "{:.4f}")
ax1.set(xlabel="t [s]", ylabel="jet_tip_height [mm]", xlim=(0.05, 0.115), ylim=(0, 12),
        title="round jet (4 D, Newtonian): the lowest point's fall")
ax1.legend(fontsize=7)
if not case.short:
    d = 0.006
    # The 2 D fall to 0.3 s: its heap reaches the nozzle's exit (2 D) by then.
    for h, colour, t_end in [(12, "C0", 0.7), (2, "C1", 0.3)]:
        label = f"round_{h}d_fall"
        s, out = case.run("scene_3d.toml", label, {"nozzle_height": h * d},
                          t_end=t_end, interval=0.002)
        t = s["time"]
        m = re.search(r"reached the plate at t = ([0-9.eE+-]+) s", out)
        if not m:
            sys.exit(f"jet/{label}: no arrival in the run's summary:\n{out}")
        after = [k for k in range(len(t)) if t[k] >= float(m.group(1))]
        aspect = [s["drop_width"][k] / s["drop_width_transverse"][k] for k in range(len(t))
                  if s["drop_width_transverse"][k] > 0]
        ax2.plot(t[len(t) - len(aspect):], aspect, colour,
                 label=f"H = {h} D: heap's length along x over its width across")
        ax2.plot(t, [x / d for x in s["jet_coil_radius"]], colour + ":", lw=1,
                 label=f"H = {h} D: jet_coil_radius / D")
        case.measured(f"round_{h}d_heap_aspect", f"round jet, Oldroyd-B, {h} D, 6 across: the "
                      "heap's length along x (the seed's direction) over its width across at "
                      f"t = {t_end} s", aspect[-1], "{:.3f}")
        case.measured(f"round_{h}d_coil_share", "... share of the outputs after contact with "
                      "jet_coil_radius above 0.1 D",
                      sum(1 for k in after if s["jet_coil_radius"][k] > 0.1 * d) / len(after),
                      "{:.3f}")
    ax2.axhline(0.1, color="k", lw=1, ls=":")
    ax2.set(xlabel="t [s]", ylabel="[-]", ylim=(0, 1.6),
            title="round jet (Oldroyd-B, 6 across): folding along x, no coil")
    ax2.legend(fontsize=7)
fig.tight_layout()
fig.savefig(case.out / "jet_3d.png", dpi=110)
case.finish("The SPH arrival is the first output (every 2 ms) at which fluid lies on the "
            "plate (the heap has a height), as the jet scene reports it; the model's arrival is "
            "when the sheet's free end has fallen the nozzle height (`viscosph exact "
            "falling-sheet`). The figure shows the force on the plate, which starts a little "
            "earlier (the head within a kernel support of the wall particles). The round jet's "
            "arrival is the first time its lowest point (`jet_tip_height`) comes within half a "
            "spacing of the plate (contact), and the time it passes D/2 above the plate, where "
            "the plate is not yet felt, interpolated between outputs every 1 ms; the thread "
            "model's are when its free end has fallen the nozzle height (`viscosph exact "
            "falling-thread`) and that less D/2.")
