"""Two-way coupling: a drop falls onto a plate that sits on a spring and a damper.

ViscoSPH.fmu simulates the drop; the plate is a rigid body of mass M per unit depth on a spring
k and a damper c, written here. A small co-simulation master (fmpy's FMU2Slave) couples them at
every communication point t_k (Gauss-Seidel):

  1. read the fluid's force on the plate, `wall_force_normal` F_k (positive into the plate);
  2. advance the plate over [t_k, t_k + h] with F_k held constant:
        M x'' = F_k - k x - c x'      (x: displacement away from the fluid)
     in sub-steps short against the spring's period;
  3. set the FMU input `plate_velocity` to the plate's mean velocity over the step,
     (x_{k+1} - x_k) / h, so that the FMU's plate (which moves rigidly at the input velocity)
     lands exactly where the plate model is; the FMU's `plate_displacement` output equals x;
  4. fmi2DoStep(t_k, h).

--coupling jacobi-velocity and jacobi-position run the two as a Jacobi master does (fmpy's SSP
runner, libcosim): both advance from the values at t_k. jacobi-velocity gives the FMU the
plate's velocity at t_k, so the FMU's plate drifts from the master's (about 3 % of the largest
displacement by 25 ms); jacobi-position sets the FMU parameter plate_coupling = position and
gives it the plate's position and velocity at t_k (`plate_position`, `plate_velocity`), which
the FMU's plate reaches, extrapolated, at t_k + h: no drift (tests/python/test_coupling.py).

Writes results/spring_plate.csv (time, plate displacement and velocity, wall force, drop width)
and results/spring_plate.png. Usage:

    .venv/bin/python examples/spring_plate.py [--mass 0.314] [--stiffness 3.1e4] [--damping 20]
        [--step 2e-4] [--stop 0.05] [--set rheology=giesekus --set plate_inclination=30 ...]

--stiffness 0 --damping 0 is a free plate: drop and plate then exchange momentum and their total
changes only by the weight of the fluid (tests/coupling.rs checks that, within 1 %).
"""

import argparse
import csv
import math
import pathlib
import shutil
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.fmi3 import FMU3Slave  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))
from fmu_drop import parse_start_values  # noqa: E402


class SpringPlate:
    """A rigid plate of mass m [kg/m] on a spring k [N/m/m] and a damper c [N s/m/m], moving
    along its normal; x is its displacement away from the fluid [m], v its velocity [m/s]."""

    def __init__(self, m, k, c):
        if not m > 0:
            raise ValueError(f"plate mass {m} must be > 0")
        if k < 0 or c < 0:
            raise ValueError(f"stiffness {k} and damping {c} must be >= 0")
        self.m, self.k, self.c = m, k, c
        self.x = 0.0
        self.v = 0.0

    def step(self, force, h):
        """Advance over h with the fluid's force held constant (semi-implicit Euler in
        sub-steps of at most 1/20 of the spring's period and of the damping time); returns the
        mean velocity over h."""
        x0 = self.x
        rate = math.sqrt(self.k / self.m) + self.c / self.m
        n = max(1, math.ceil(h * rate / 0.05))
        dt = h / n
        for _ in range(n):
            self.v += dt * (force - self.k * self.x - self.c * self.v) / self.m
            self.x += dt * self.v
        return (self.x - x0) / h


COUPLINGS = ("gauss-seidel", "jacobi-velocity", "jacobi-position")


def run(fmu_path, mass, stiffness, damping, step, stop, start_values=None, couple=True,
        logger=None, coupling="gauss-seidel"):
    """Run the coupled system; returns a list of rows (dicts) at t = 0, h, 2h, ... stop.

    With couple=False the plate input is never set (the fixed-plate run, for comparison).
    `coupling` is one of COUPLINGS (see the module documentation)."""
    if coupling not in COUPLINGS:
        raise ValueError(f"coupling {coupling!r} is not one of {', '.join(COUPLINGS)}")
    start_values = dict(start_values or {})
    if coupling == "jacobi-position":
        start_values["plate_coupling_name"] = "position"
    md = read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipdir = tempfile.mkdtemp(prefix="viscosph_spring_")
    try:
        extract(str(fmu_path), unzipdir)
        kwargs = {"logger": logger} if logger is not None else {}
        fmi3 = md.fmiVersion.startswith("3")
        fmu = (FMU3Slave if fmi3 else FMU2Slave)(
            guid=md.guid, unzipDirectory=unzipdir,
            modelIdentifier=md.coSimulation.modelIdentifier, instanceName="drop", **kwargs)
        types = {v.name: v.type for v in md.modelVariables}
        fmu.instantiate()
        if fmi3:
            # FMI 3.0: no setupExperiment (the stop time goes to enterInitializationMode),
            # Float64 / Int32 / Int64 (enumerations) in place of Real / Integer.
            get_real, set_real = fmu.getFloat64, fmu.setFloat64
            set_int = {"Int32": fmu.setInt32, "Enumeration": fmu.setInt64}
        else:
            fmu.setupExperiment(startTime=0.0, stopTime=stop)
            get_real, set_real = fmu.getReal, fmu.setReal
            set_int = {"Integer": fmu.setInteger, "Enumeration": fmu.setInteger}
        for name, value in start_values.items():
            if types[name] == "String":
                fmu.setString([vr[name]], [value])
            elif types[name] in set_int:
                set_int[types[name]]([vr[name]], [int(value)])
            else:
                set_real([vr[name]], [float(value)])
        if fmi3:
            fmu.enterInitializationMode(startTime=0.0, stopTime=stop)
        else:
            fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        plate = SpringPlate(mass, stiffness, damping)
        names = ["wall_force_normal", "plate_displacement", "drop_width", "drop_height"]
        refs = [vr[n] for n in names]
        rows = []
        n = int(round(stop / step))
        for k in range(n + 1):
            t = k * step
            out = dict(zip(names, get_real(refs)))
            rows.append({"time": t, "plate_x": plate.x, "plate_v": plate.v, **out})
            if k == n:
                break
            if couple and coupling == "gauss-seidel":
                u = plate.step(out["wall_force_normal"], step)
                set_real([vr["plate_velocity"]], [u])
            elif couple and coupling == "jacobi-velocity":
                set_real([vr["plate_velocity"]], [plate.v])
                plate.step(out["wall_force_normal"], step)
            elif couple:
                set_real([vr["plate_position"], vr["plate_velocity"]], [plate.x, plate.v])
                plate.step(out["wall_force_normal"], step)
            try:
                fmu.doStep(currentCommunicationPoint=t, communicationStepSize=step)
            except FMICallException as e:
                api = "fmi3" if fmi3 else "fmi2"
                raise RuntimeError(f"{api}DoStep at t = {t} s failed: {e}") from None
        fmu.terminate()
        fmu.freeInstance()
        return rows
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)


def plot(rows, fixed, path, title):
    t = [1e3 * r["time"] for r in rows]
    fig, (a, b) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    a.plot(t, [1e3 * r["plate_x"] for r in rows], label="plate displacement x (master)")
    a.plot(t, [1e3 * r["plate_displacement"] for r in rows], "--",
           label="plate_displacement (FMU output)")
    a.set_ylabel("displacement away from the fluid [mm]")
    a.legend(loc="best")
    a.set_title(title, fontsize=10)
    b.plot(t, [r["wall_force_normal"] for r in rows], label="spring-mounted plate")
    if fixed:
        b.plot([1e3 * r["time"] for r in fixed], [r["wall_force_normal"] for r in fixed], ":",
               label="fixed plate")
    b.set_xlabel("time [ms]")
    b.set_ylabel("wall force normal [N/m]")
    b.legend(loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "ViscoSPH.fmu"))
    ap.add_argument("--mass", type=float, default=0.314,
                    help="plate mass per unit depth [kg/m] (default: about the drop's)")
    ap.add_argument("--stiffness", type=float, default=3.1e4,
                    help="spring stiffness [N/m per m depth] (default: about 50 Hz)")
    ap.add_argument("--damping", type=float, default=20.0, help="damper [N s/m per m depth]")
    ap.add_argument("--step", type=float, default=2e-4, help="communication step [s]")
    ap.add_argument("--stop", type=float, default=0.05, help="stop time [s]")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="an FMU parameter, e.g. rheology=giesekus")
    ap.add_argument("--coupling", choices=COUPLINGS, default="gauss-seidel",
                    help="how the master couples the plate (see above)")
    ap.add_argument("--no-fixed", action="store_true",
                    help="skip the fixed-plate run drawn for comparison")
    ap.add_argument("--out", default=str(ROOT / "results"))
    args = ap.parse_args()
    md = read_model_description(args.fmu)
    try:
        start = parse_start_values(args.set, md)
        rows = run(args.fmu, args.mass, args.stiffness, args.damping, args.step, args.stop, start,
                   coupling=args.coupling)
    except (ValueError, RuntimeError) as e:
        sys.exit(f"spring_plate: {e}")
    fixed = None if args.no_fixed else run(args.fmu, args.mass, args.stiffness, args.damping,
                                           args.step, args.stop, start, couple=False)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "spring_plate.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    title = (f"drop on a spring-mounted plate\nM = {args.mass:g} kg/m, k = {args.stiffness:g} N/m2, "
             f"c = {args.damping:g} N s/m2")
    plot(rows, fixed, out / "spring_plate.png", title)
    peak = max(r["wall_force_normal"] for r in rows)
    xmax = max(r["plate_x"] for r in rows)
    print(f"peak wall force {peak:.2f} N/m, largest plate displacement {1e3 * xmax:.3f} mm; "
          f"wrote {out / 'spring_plate.csv'} and {out / 'spring_plate.png'}")


if __name__ == "__main__":
    main()
