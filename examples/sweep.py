"""Parameter sweep of ViscoSPH.fmu on Dask: a grid of drop impacts, one table, one regime map.

    .venv/bin/python examples/sweep.py                       # LocalCluster on this machine
    .venv/bin/python examples/sweep.py --scheduler tcp://host:8786   # an existing cluster
    .venv/bin/python examples/sweep.py --inclination 0 30 60 --velocity 0.5 1 2 \\
        --rheology newtonian oldroyd_b giesekus --set particles_per_diameter=16

The grid is plate_inclination x impact_velocity x rheology (the defaults below). Each Dask
worker unzips the FMU once (the archive's bytes are sent to every worker, so a remote cluster
needs no shared file system) and keeps one FMU instance, which it resets (fmi2Reset) between
cases. A case that fails (a numerical breakdown answering fmi2Discard, a refused parameter) is
a row of the table with its cause; the sweep itself never fails because of one case.

Writes OUT/sweep.csv (one row per case: the parameters, the maximum spreading factor
D_max/D_0, the time of that maximum, the rebound, the peak wall force, the time reached and
the breakdown cause if any; `settings` lists the other parameters set, e.g. the start height,
which by default puts every drop two particle spacings above the plate) and OUT/sweep.png (a regime map per rheology: spreading factor over
plate inclination and impact velocity, failed cases crossed out). Results do not depend on the
scheduler or the number of workers: each case is computed by the same deterministic solver
from a freshly reset instance (tests/python/test_sweep.py checks Dask against a serial run).
"""

import argparse
import csv
import hashlib
import io
import itertools
import math
import pathlib
import sys
import tempfile
import zipfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
DEFAULT_FMU = ROOT / "target" / "fmu" / "ViscoSPH.fmu"

COLUMNS = ["case", "plate_inclination", "impact_velocity", "rheology", "settings",
           "max_spreading_factor", "time_of_max_spreading", "rebound", "peak_wall_force",
           "time_reached", "breakdown"]
UNITS = {"plate_inclination": "deg", "impact_velocity": "m/s", "time_of_max_spreading": "s",
         "peak_wall_force": "N/m", "time_reached": "s"}

# ---------------------------------------------------------------------------------------------
# Worker side: one unzipped FMU and one instance per worker process, reused across cases.
# ---------------------------------------------------------------------------------------------

_WORKER = {}


class _Log:
    """Keeps the FMU's messages of the current case (the cause of a failure is the last)."""

    def __init__(self):
        self.messages = []

    def __call__(self, _component, _instance, status, _category, message):
        self.messages.append((status, message.decode(errors="replace")))


def _instance(fmu_bytes):
    """The worker's (slave, model description, log) for this FMU, unzipped on first use."""
    from fmpy import read_model_description
    from fmpy.simulation import instantiate_fmu

    key = hashlib.sha256(fmu_bytes).hexdigest()
    if _WORKER.get("key") != key:
        if "slave" in _WORKER:
            _WORKER["slave"].freeInstance()
        d = tempfile.mkdtemp(prefix="viscosph-sweep-")
        zipfile.ZipFile(io.BytesIO(fmu_bytes)).extractall(d)
        md = read_model_description(str(pathlib.Path(d) / "modelDescription.xml"))
        log = _Log()
        slave = instantiate_fmu(d, md, "CoSimulation", logger=log)
        _WORKER.update(key=key, slave=slave, md=md, log=log, fresh=True)
    return _WORKER


def run_case(fmu_bytes, case, settings, stop_time, step):
    """Run one case on this worker's instance; returns a table row (a dict). Never raises for
    a failure of the FMU: the row's `breakdown` says what happened."""
    from fmpy.fmi1 import FMICallException

    w = _instance(fmu_bytes)
    slave, md, log = w["slave"], w["md"], w["log"]
    if not w["fresh"]:
        slave.reset()  # the same instance, back to its defaults
    w["fresh"] = False
    log.messages.clear()
    var = {v.name: v for v in md.modelVariables}
    outputs = ["drop_width", "drop_height", "wall_force_normal"]
    out_vrs = [var[n].valueReference for n in outputs]
    row = {"case": case["case"], "plate_inclination": case["plate_inclination"],
           "impact_velocity": case["impact_velocity"], "rheology": case["rheology"]}
    values = {"plate_inclination": float(case["plate_inclination"]),
              "impact_velocity": float(case["impact_velocity"]),
              "rheology_name": str(case["rheology"]), **settings}
    values.setdefault("initial_drop_height", start_height(values))
    times, rows, cause = [], [], ""
    try:
        slave.setupExperiment(startTime=0.0, stopTime=stop_time)
        for name, value in values.items():
            v = var[name]
            if v.type == "String":
                slave.setString([v.valueReference], [str(value)])
            elif v.type in ("Integer", "Enumeration"):
                slave.setInteger([v.valueReference], [int(value)])
            else:
                slave.setReal([v.valueReference], [float(value)])
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        n = int(round(stop_time / step))
        for k in range(n):
            t, t_next = k * step, (k + 1) * step
            try:
                slave.doStep(currentCommunicationPoint=t, communicationStepSize=t_next - t)
            except FMICallException:
                # fmi2Discard: the outputs are those of the last good state
                t_next = slave.getRealStatus(2)  # fmi2LastSuccessfulTime
                times.append(t_next)
                rows.append(slave.getReal(out_vrs))
                raise
            times.append(t_next)
            rows.append(slave.getReal(out_vrs))
    except FMICallException as e:
        msgs = [m for s, m in log.messages if s >= 2]
        cause = msgs[-1] if msgs else str(e)
        # the instance may be in the error state; the next case resets it
    except Exception as e:  # anything else is still a row, never a lost sweep
        cause = f"{type(e).__name__}: {e}"
    row["settings"] = " ".join(f"{k}={v}" for k, v in sorted(values.items())
                               if k not in ("plate_inclination", "impact_velocity",
                                            "rheology_name"))
    row.update(summarise(np.array(times), np.array(rows) if rows else np.zeros((0, 3)),
                         float(values.get("drop_diameter", 0.02))))
    row["breakdown"] = cause.replace("\n", " ")
    return row


def start_height(values):
    """Initial height of the drop centre above the impact point [m] when none is given: the
    drop starts two particle spacings from the plate (measured along the plate's normal), so
    every case reaches the plate at once, at its impact velocity, whatever the inclination."""
    d = float(values.get("drop_diameter", 0.02))
    dx = d / int(values.get("particles_per_diameter", 20))
    return (0.5 * d + 2.0 * dx) / math.cos(math.radians(float(values["plate_inclination"])))


def summarise(t, y, diameter):
    """Spreading factor D_max/D_0 and its time, rebound, peak wall force, time reached."""
    if len(t) == 0:
        return {"max_spreading_factor": math.nan, "time_of_max_spreading": math.nan,
                "rebound": math.nan, "peak_wall_force": math.nan, "time_reached": 0.0}
    width, height, force = y[:, 0], y[:, 1], y[:, 2]
    i = int(np.argmax(width))
    # rebound: how far the drop rises again after its widest, flattest moment, in diameters
    # (0 for a drop that stays spread; a recoiling elastic drop rises)
    rebound = float(np.max(height[i:]) - height[i]) / diameter
    return {"max_spreading_factor": float(width[i]) / diameter,
            "time_of_max_spreading": float(t[i]), "rebound": rebound,
            "peak_wall_force": float(np.max(force)), "time_reached": float(t[-1])}


# ---------------------------------------------------------------------------------------------
# Client side
# ---------------------------------------------------------------------------------------------

def grid(inclinations, velocities, rheologies):
    cases = []
    for k, (a, v, r) in enumerate(itertools.product(inclinations, velocities, rheologies)):
        cases.append({"case": k, "plate_inclination": a, "impact_velocity": v, "rheology": r})
    return cases


def run_serial(fmu_bytes, cases, settings, stop_time, step, progress=True):
    rows = []
    for c in _progress(cases, progress):
        rows.append(run_case(fmu_bytes, c, settings, stop_time, step))
    return rows


def run_dask(client, fmu_bytes, cases, settings, stop_time, step, progress=True):
    from dask.distributed import as_completed

    # The workers run `sweep.run_case` from this very file, sent to each of them: a function of
    # an importable module travels by reference, so the worker's cache (_WORKER: the unzipped
    # FMU and its instance) lives as long as the worker, not as long as one task.
    client.upload_file(str(pathlib.Path(__file__).resolve()))
    module = _importable_self()
    fmu_future = client.scatter(fmu_bytes, broadcast=True)
    futures = [client.submit(module.run_case, fmu_future, c, settings, stop_time, step,
                             key=f"viscosph-case-{c['case']}-{hashlib.sha1(repr((c, settings, stop_time, step)).encode()).hexdigest()[:8]}",
                             pure=False)
               for c in cases]
    rows = []
    for f in _progress(as_completed(futures), progress, total=len(futures)):
        rows.append(f.result())
    return sorted(rows, key=lambda r: r["case"])


def _importable_self():
    """This file as the module `sweep` (not `__main__`, which pickles by value)."""
    if __name__ == "sweep":
        return sys.modules[__name__]
    here = str(pathlib.Path(__file__).resolve().parent)
    if here not in sys.path:
        sys.path.insert(0, here)
    import sweep
    return sweep


def _progress(it, on, total=None):
    if not on:
        return it
    from tqdm import tqdm
    return tqdm(it, total=total, desc="cases", unit="case", file=sys.stderr)


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        header = {c: f"{c} [{UNITS[c]}]" if c in UNITS else c for c in COLUMNS}
        w.writerow(header)
        for r in rows:
            w.writerow({c: (repr(r[c]) if isinstance(r[c], float) else r[c]) for c in COLUMNS})


def regime_map(rows, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    rheologies = list(dict.fromkeys(r["rheology"] for r in rows))
    incl = sorted({r["plate_inclination"] for r in rows})
    vel = sorted({r["impact_velocity"] for r in rows})
    ok = [r["max_spreading_factor"] for r in rows if not r["breakdown"]]
    vmin, vmax = (min(ok), max(ok)) if ok else (0.0, 1.0)
    if vmax <= vmin:
        vmax = vmin + 1e-9
    fig, axes = plt.subplots(1, len(rheologies), figsize=(4.6 * len(rheologies) + 1.4, 4.8),
                             squeeze=False, constrained_layout=True)
    im = None
    for ax, rh in zip(axes[0], rheologies):
        z = np.full((len(vel), len(incl)), np.nan)
        for r in rows:
            if r["rheology"] == rh and not r["breakdown"]:
                z[vel.index(r["impact_velocity"]), incl.index(r["plate_inclination"])] = \
                    r["max_spreading_factor"]
        im = ax.imshow(z, origin="lower", aspect="auto", cmap="viridis", vmin=vmin, vmax=vmax,
                       extent=(-0.5, len(incl) - 0.5, -0.5, len(vel) - 0.5))
        for r in rows:
            if r["rheology"] != rh:
                continue
            x, y = incl.index(r["plate_inclination"]), vel.index(r["impact_velocity"])
            if r["breakdown"]:
                ax.plot(x, y, marker="x", color="crimson", markersize=22, mew=3)
            else:
                ax.text(x, y, f"{r['max_spreading_factor']:.2f}", ha="center", va="center",
                        fontsize=12, color="white" if r["max_spreading_factor"] <
                        (vmin + vmax) / 2 else "black")
        ax.set_xticks(range(len(incl)), [f"{a:g}" for a in incl], fontsize=12)
        ax.set_yticks(range(len(vel)), [f"{v:g}" for v in vel], fontsize=12)
        ax.set_xlabel("plate inclination [deg]", fontsize=13)
        ax.set_ylabel("impact velocity [m/s]", fontsize=13)
        ax.set_title(rh.replace("_", "-"), fontsize=14)
    cb = fig.colorbar(im, ax=axes[0].tolist(), shrink=0.9)
    cb.set_label("max spreading factor $D_{max}/D_0$ [-]", fontsize=13)
    cb.ax.tick_params(labelsize=11)
    handles = [Line2D([], [], marker="x", color="crimson", ls="", markersize=12, mew=3,
                      label="breakdown (see sweep.csv)")]
    if any(r["breakdown"] for r in rows):
        fig.legend(handles=handles, loc="lower left", fontsize=11, frameon=False)
    fig.suptitle(title, fontsize=13)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def parse_settings(pairs):
    out = {}
    for p in pairs:
        name, _, text = p.partition("=")
        try:
            out[name] = int(text)
        except ValueError:
            try:
                out[name] = float(text)
            except ValueError:
                out[name] = text  # an enumeration's name (its String twin: scheme_name=pdri)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmu", default=str(DEFAULT_FMU))
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: a "
                    "LocalCluster on this machine)")
    ap.add_argument("--workers", type=int, default=None,
                    help="LocalCluster worker processes (default: one per core)")
    ap.add_argument("--serial", action="store_true", help="no Dask: run the cases one by one")
    ap.add_argument("--inclination", type=float, nargs="+", default=[0.0, 20.0, 40.0, 60.0],
                    help="plate inclinations, deg")
    ap.add_argument("--velocity", type=float, nargs="+", default=[0.5, 1.0, 1.5, 2.0],
                    help="impact velocities, m/s")
    ap.add_argument("--rheology", nargs="+", default=["newtonian", "oldroyd_b", "giesekus"])
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="a parameter for every case (enumerations by name: scheme_name=pdri)")
    ap.add_argument("--stop-time", type=float, default=0.05, help="s")
    ap.add_argument("--step", type=float, default=1e-3, help="communication step, s")
    ap.add_argument("--out", default=str(ROOT / "results"), help="output directory")
    args = ap.parse_args(argv)

    settings = {"particles_per_diameter": 16, **parse_settings(args.set)}
    fmu_bytes = pathlib.Path(args.fmu).read_bytes()
    cases = grid(args.inclination, args.velocity, args.rheology)
    print(f"{len(cases)} cases, {args.stop_time} s each", file=sys.stderr)
    if args.serial:
        rows = run_serial(fmu_bytes, cases, settings, args.stop_time, args.step)
    else:
        from dask.distributed import Client, LocalCluster
        if args.scheduler:
            client, cluster = Client(args.scheduler), None
        else:
            cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1,
                                   processes=True, dashboard_address=None)
            client = Client(cluster)
        try:
            rows = run_dask(client, fmu_bytes, cases, settings, args.stop_time, args.step)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()

    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / "sweep.csv")
    fixed = ", ".join(f"{k} = {v}" for k, v in sorted(settings.items()))
    regime_map(rows, out / "sweep.png",
               f"Drop impact regime map: maximum spreading over {args.stop_time:g} s ({fixed})")
    failed = sum(1 for r in rows if r["breakdown"])
    print(f"wrote {out / 'sweep.csv'} and {out / 'sweep.png'}: {len(rows)} cases, "
          f"{failed} broke down", file=sys.stderr)


if __name__ == "__main__":
    main()
