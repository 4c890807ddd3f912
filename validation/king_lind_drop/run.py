"""King & Lind 2021's Re = 4 drop (ISPH), Newtonian and Oldroyd-B (De = 1, beta = 0.1), against
what the paper's text states about its Fig. 12."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import common  # noqa: E402
import drops  # noqa: E402

case = common.Case(__file__, __doc__)


def timing(n, ob):
    case.measured(f"oldroyd_b_{n}_t_min_offset", f"Oldroyd-B, {n}/W: abs(t* - 3.5), t* of the "
                  f"narrowest drop after the first maximum ({ob['t_min']:.2f}; text: local "
                  "minimum at t* = 3.5)", abs(ob["t_min"] - 3.5), "{:.2f}")


drops.newtonian_and_oldroyd_b(
    case, [(3.5, "King & Lind: Oldroyd-B W* minimum")], "King & Lind's Re = 4 drop (ISPH)",
    "king_lind_drop.png", ("W", "U"), ("spreading, no rebound", ""), timing)
case.finish("t* = t U / W with W = 2 cm, U = 1 m/s. The comparison with an independent "
            "free-surface solver goes in `independent_solver/` (see its README).")
