"""King & Lind 2021's Re = 4 drop (ISPH), Newtonian and Oldroyd-B (De = 1, beta = 0.1), against
what the paper's text states about its Fig. 12."""
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
marks = [(3.5, "King & Lind: Oldroyd-B W* minimum")]
found = drops.run_drops(case, runs, 0.02, 1.0, marks, "King & Lind's Re = 4 drop (ISPH)",
                        "king_lind_drop.png", names=("W", "U"))
for n in resolutions:
    ob, nw = found[f"oldroyd_b {n}"], found[f"newtonian {n}"]
    case.measured(f"oldroyd_b_{n}_t_min_offset", f"Oldroyd-B, {n}/W: abs(t* - 3.5), t* of the "
                  f"narrowest drop after the first maximum ({ob['t_min']:.2f}; text: local "
                  "minimum at t* = 3.5)", abs(ob["t_min"] - 3.5), "{:.2f}")
    case.measured(f"oldroyd_b_{n}_retraction", f"Oldroyd-B, {n}/W: largest retraction of W*",
                  ob["retraction"], "{:.3f}")
    case.measured(f"newtonian_{n}_retraction", f"Newtonian, {n}/W: largest retraction of W* "
                  "(text: spreading, no rebound)", nw["retraction"], "{:.4f}")
    for label, r in (("newtonian", nw), ("oldroyd_b", ob)):
        case.measured(f"{label}_{n}_volume", f"{label}, {n}/W: largest abs(volume_error)",
                      r["volume"], "{:.4f}")
case.finish("t* = t U / W with W = 2 cm, U = 1 m/s. The comparison with an independent "
            "free-surface solver goes in `independent_solver/` (see its README).")
