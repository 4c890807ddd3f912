"""Fang 2006's Oldroyd-B drop impact, simulated through ViscoSPH.fmu with fmpy.

Writes results/fmu_drop.csv (time and every output of the FMU) and results/fmu_drop.png (drop
width and height, and the force on the plate, against time). Run by examples/main.sh after it
has built the FMU and the Python venv:

    .venv/bin/python examples/fmu_drop.py [--set plate_inclination=30 --set rheology=giesekus ...]

Enumeration parameters (scene, scheme, rheology, ...) may be given by item name (the names are
read from the FMU's modelDescription.xml) or by number. A numerical breakdown (the FMU discards
a step) still writes the CSV and the PNG, with the breakdown marked, and exits with status 1.
"""

import argparse
import csv
import pathlib
import sys
import tempfile
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from fmpy import extract, read_model_description, simulate_fmu  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def enumeration_items(v):
    """{name: value} of an enumeration-like variable, read from the modelDescription: an
    Enumeration's declared type items, or an Integer variable with a declared type that lists
    items (fmpy's Item objects), whatever mechanism the FMU uses; {} for other variables."""
    declared = getattr(v, "declaredType", None)
    items = getattr(declared, "items", None) or []
    return {i.name: int(i.value) for i in items}


def parse_start_values(pairs, md):
    """name=value pairs -> fmpy start values; enumeration items may be named. Raises
    ValueError with a message naming the parameter and what it accepts."""
    variables = {v.name: v for v in md.modelVariables}
    values = {}
    for pair in pairs:
        name, sep, text = pair.partition("=")
        if not sep:
            raise ValueError(f"--set {pair}: expected NAME=VALUE")
        if name not in variables or variables[name].causality not in ("parameter", "input"):
            known = ", ".join(v.name for v in md.modelVariables if v.causality == "parameter")
            raise ValueError(f"unknown parameter '{name}'; the parameters are: {known}")
        v = variables[name]
        items = enumeration_items(v)
        try:
            if items:
                values[name] = items[text] if text in items else int(text)
                if values[name] not in items.values():
                    raise ValueError
            elif v.type == "Integer":
                values[name] = int(text)
            elif v.type == "Boolean":
                values[name] = text.lower() in ("1", "true", "yes")
            elif v.type == "String":  # an enumeration's twin: --set rheology_name=giesekus
                values[name] = text
            else:
                values[name] = float(text)
        except ValueError:
            if items:
                allowed = ", ".join(f"{k} ({n})" for k, n in items.items())
                raise ValueError(f"{name} = '{text}' is not one of {allowed}") from None
            raise ValueError(f"{name} = '{text}' is not a {v.type.lower()} number") from None
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
    try:
        start_values = parse_start_values(args.set, md)
    except ValueError as e:
        sys.exit(f"error: {e}")
    stop_time = args.stop_time
    if stop_time is None:
        stop_time = md.defaultExperiment.stopTime if md.defaultExperiment else 0.16
        stop_time = float(stop_time) if stop_time is not None else 0.16
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    messages = []
    discards = []

    def logger(_component, _instance, status, category, message):
        text = message.decode()
        messages.append(text)
        if status >= 2:  # fmi2Discard, fmi2Error
            discards.append(text)
        print(f"[FMU {category.decode()}] {text}", file=sys.stderr)

    t0 = time.perf_counter()
    # Unzipped here rather than by simulate_fmu, which leaves its folder behind when a call raises
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as unzipdir:
        extract(args.fmu, unzipdir=unzipdir)
        try:
            result = simulate_fmu(unzipdir, start_values=start_values, stop_time=stop_time,
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
    broke = bool(discards) or t[-1] < stop_time - 1e-9 * max(1.0, stop_time)
    # The project's plot style (cli/src/io/plot.rs): labelled axes with units, legible text.
    plt.rcParams.update({"font.size": 12, "axes.titlesize": 13, "axes.labelsize": 13})
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(8, 7))
    ax1.plot(1e3 * t, 1e3 * result["drop_width"], label="width W")
    ax1.plot(1e3 * t, 1e3 * result["drop_height"], label="height H")
    ax1.set_ylabel("drop size [mm]")
    ax1.legend()
    ax1.grid(alpha=0.3)
    names = {v.name: v for v in md.modelVariables}
    shown = []
    for k, v in start_values.items():
        by_name = {n: i for i, n in enumeration_items(names[k]).items()}
        shown.append(f"{k} = {by_name.get(v, v)}")
    # Wrapped between settings, never inside one, so that no setting is cut off.
    lines = ["ViscoSPH.fmu through fmpy:"]
    for k, part in enumerate(shown or ["default parameters"]):
        part += "," if k < len(shown) - 1 else ""
        if len(lines[-1]) + 1 + len(part) > 64:
            lines.append(part)
        else:
            lines[-1] += " " + part
    title = "\n".join(lines)
    ax1.set_title(title)
    ax2.plot(1e3 * t, result["wall_force_normal"], label="normal (into the plate)")
    ax2.plot(1e3 * t, result["wall_force_tangential"], label="tangential (downhill)")
    ax2.set_ylabel("force on the plate [N/m]")
    ax2.set_xlabel("t [ms]")
    ax2.legend()
    ax2.grid(alpha=0.3)
    if broke:
        for ax in (ax1, ax2):
            ax.axvline(1e3 * t[-1], color="red", lw=2, ls="--")
            ax.axvspan(1e3 * t[-1], 1e3 * stop_time, color="red", alpha=0.08)
        ax1.text(1e3 * t[-1], ax1.get_ylim()[1], " numerical breakdown\n (run stopped)",
                 color="red", va="top", ha="left" if t[-1] < 0.6 * stop_time else "right")
        ax2.set_xlim(right=1e3 * stop_time)
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
    if broke:
        why = discards[-1] if discards else "the FMU stopped before the stop time"
        print(f"error: the run ended at t = {t[-1]:.4f} s of {stop_time} s: {why}",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
