"""Fang 2006's Oldroyd-B drop impact, simulated through ViscoSPH.fmu with fmpy.

Writes results/fmu_drop.csv (time and every output of the FMU) and results/fmu_drop.png (drop
width and height, and the force on the plate, against time). Run by examples/main.sh after it
has built the FMU and the Python venv:

    .venv/bin/python examples/fmu_drop.py [--set plate_inclination=30 --set rheology=1 ...]

Enumeration parameters (scene, scheme, rheology, ...) may be given by item name.
"""

import argparse
import csv
import pathlib
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from fmpy import read_model_description, simulate_fmu  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def parse_start_values(pairs, md):
    """name=value pairs -> fmpy start values; enumeration items may be named."""
    variables = {v.name: v for v in md.modelVariables}
    values = {}
    for pair in pairs:
        name, _, text = pair.partition("=")
        if name not in variables:
            sys.exit(f"unknown parameter '{name}'")
        v = variables[name]
        if v.type == "Enumeration":
            items = {i.name: int(i.value) for i in v.declaredType.items}
            values[name] = items[text] if text in items else int(text)
        elif v.type == "Integer":
            values[name] = int(text)
        elif v.type == "String":  # an enumeration's twin: --set rheology_name=giesekus
            values[name] = text
        else:
            values[name] = float(text)
    return values


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "ViscoSPH.fmu"))
    ap.add_argument("--out", default=str(ROOT / "results"), help="output directory")
    ap.add_argument("--stop-time", type=float, default=None, help="s (default: 0.16)")
    ap.add_argument("--step", type=float, default=1e-3, help="communication step, s")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="parameter value, repeatable")
    args = ap.parse_args()

    md = read_model_description(args.fmu)
    start_values = parse_start_values(args.set, md)
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    messages = []

    def logger(_component, _instance, status, category, message):
        text = message.decode()
        messages.append(text)
        print(f"[FMU {category.decode()}] {text}", file=sys.stderr)

    t0 = time.perf_counter()
    try:
        result = simulate_fmu(args.fmu, start_values=start_values, stop_time=args.stop_time,
                              output_interval=args.step, output=outputs, logger=logger)
    except FMICallException as e:
        sys.exit(f"the FMU refused the run: {e}")
    elapsed = time.perf_counter() - t0

    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    csv_path = out / "fmu_drop.csv"
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(result.dtype.names)
        for row in result:
            w.writerow([repr(float(x)) for x in row])

    t = result["time"]
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    ax1.plot(t, 1e3 * result["drop_width"], label="width")
    ax1.plot(t, 1e3 * result["drop_height"], label="height")
    ax1.set_ylabel("mm")
    ax1.legend()
    ax1.grid(alpha=0.3)
    title = ", ".join(f"{k} = {v}" for k, v in start_values.items()) or "defaults"
    ax1.set_title(f"ViscoSPH.fmu through fmpy ({title})")
    ax2.plot(t, result["wall_force_normal"], label="normal (into the plate)")
    ax2.plot(t, result["wall_force_tangential"], label="tangential (downhill)")
    ax2.set_ylabel("wall force [N/m]")
    ax2.set_xlabel("t [s]")
    ax2.legend()
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    png_path = out / "fmu_drop.png"
    fig.savefig(png_path, dpi=120)

    w = result["drop_width"]
    i = int(w.argmax())
    print(f"simulated {t[-1]:.3f} s in {elapsed:.2f} s wall time "
          f"({len(t)} communication points, {int(result['particle_count'][0])} particles)")
    print(f"width {w[0] * 1e3:.2f} mm -> max {w[i] * 1e3:.2f} mm at t = {t[i]:.3f} s "
          f"-> {w[-1] * 1e3:.2f} mm at t = {t[-1]:.3f} s")
    print(f"peak normal wall force {result['wall_force_normal'].max():.2f} N/m")
    print(f"wrote {csv_path} and {png_path}")
    if messages:
        print(f"the FMU logged {len(messages)} message(s); the last: {messages[-1]}")


if __name__ == "__main__":
    main()
