"""Fang et al. 2006's Newtonian and Oldroyd-B drops (WCSPH) against what the paper's text
states: the phases of the Oldroyd-B drop, the Newtonian drop's even spreading, the volume kept."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import common  # noqa: E402
import drops  # noqa: E402

case = common.Case(__file__, __doc__)


def timing(n, ob):
    case.measured(f"oldroyd_b_{n}_t_max_offset", f"Oldroyd-B, {n}/D: abs(t* - 2.5), t* of the "
                  f"widest drop ({ob['t_max']:.2f}; text: spreading until t* = 2.5)",
                  abs(ob["t_max"] - 2.5), "{:.2f}")
    case.measured(f"oldroyd_b_{n}_t_min_offset", f"Oldroyd-B, {n}/D: abs(t* - 3.75), t* of the "
                  f"narrowest drop after it ({ob['t_min']:.2f}; text: contraction until "
                  "t* = 3.75)", abs(ob["t_min"] - 3.75), "{:.2f}")


drops.newtonian_and_oldroyd_b(
    case, [(2.5, "Fang: spreading ends"), (3.75, "Fang: contraction ends")],
    "Fang's drops (WCSPH)", "fang_drops.png", ("D", "V"),
    ("spreads out evenly", " (text: within 4 %)"), timing)
case.finish("t* = t V / D with D = 2 cm, V = 1 m/s; W* is the drop's extent along the plate "
            "over D. The maximum is the first after impact, the minimum the first after it.")
