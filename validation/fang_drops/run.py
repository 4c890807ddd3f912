"""Fang et al. 2006's Newtonian and Oldroyd-B drops (WCSPH) against what the paper's text
states: the phases of the Oldroyd-B drop, the Newtonian drop's even spreading, the volume kept."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import common  # noqa: E402
import drops  # noqa: E402

case = common.Case(__file__, __doc__)
resolutions = [20] if case.short else [20, 40]
runs = []
for n in resolutions:
    runs += [(f"newtonian {n}", "newtonian.toml", {"particles_per_diameter": n}),
             (f"oldroyd_b {n}", "oldroyd_b.toml", {"particles_per_diameter": n})]
marks = [(2.5, "Fang: spreading ends"), (3.75, "Fang: contraction ends")]
found = drops.run_drops(case, runs, 0.02, 1.0, marks, "Fang's drops (WCSPH)", "fang_drops.png")
for n in resolutions:
    ob, nw = found[f"oldroyd_b {n}"], found[f"newtonian {n}"]
    case.measured(f"oldroyd_b_{n}_t_max_offset", f"Oldroyd-B, {n}/D: abs(t* - 2.5), t* of the "
                  f"widest drop ({ob['t_max']:.2f}; text: spreading until t* = 2.5)",
                  abs(ob["t_max"] - 2.5), "{:.2f}")
    case.measured(f"oldroyd_b_{n}_t_min_offset", f"Oldroyd-B, {n}/D: abs(t* - 3.75), t* of the "
                  f"narrowest drop after it ({ob['t_min']:.2f}; text: contraction until "
                  "t* = 3.75)", abs(ob["t_min"] - 3.75), "{:.2f}")
    case.measured(f"oldroyd_b_{n}_retraction", f"Oldroyd-B, {n}/D: largest retraction of W*",
                  ob["retraction"], "{:.3f}")
    case.measured(f"newtonian_{n}_retraction", f"Newtonian, {n}/D: largest retraction of W* "
                  "(text: spreads out evenly)", nw["retraction"], "{:.4f}")
    for label, r in (("newtonian", nw), ("oldroyd_b", ob)):
        case.measured(f"{label}_{n}_volume", f"{label}, {n}/D: largest abs(volume_error) "
                      "(text: within 4 %)", r["volume"], "{:.4f}")
case.finish("t* = t V / D with D = 2 cm, V = 1 m/s; W* is the drop's extent along the plate "
            "over D. The maximum is the first after impact, the minimum the first after it.")
