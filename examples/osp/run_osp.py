"""Two drops on spring-mounted plates as an OSP system, run by libcosim (PyPI libcosimpy).

    .venv/bin/python examples/osp/run_osp.py [--stop 0.03] [--mass 0.314] [--stiffness 3.1e4]
        [--damping 20] [--structure examples/osp/OspSystemStructure.xml]

OspSystemStructure.xml declares the simulators (two instances of ViscoSPH.fmu with their
initial values) and the base step. libcosim runs them; this script is the rest of the system:
after every step it reads each drop's `wall_force_normal` through a last-value observer,
advances that drop's plate (SpringPlate of examples/spring_plate.py, the same coupling scheme)
and overrides the drop's `plate_velocity` input with the plate's mean velocity over the next
step through libcosim's override manipulator, which applies it when the next step commences.

With --coupling position the plates are coupled as a Jacobi master couples them: each drop
gets `plate_coupling_name = position` among its initial values, and before the plate is
advanced its position and velocity at the communication point override the drop's
`plate_position` and `plate_velocity` inputs; the FMU's plate then reaches that position,
extrapolated with that velocity, at the end of the step (docs/book/src/coupling.md).

Writes results/osp_drops.csv and results/osp_drops.png (plate displacement and wall force of
each drop).
"""

import argparse
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from fmpy import read_model_description  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(ROOT / "examples"))
from spring_plate import SpringPlate  # noqa: E402


def with_position_coupling(structure, directory):
    """A copy of the system structure in `directory` whose drops have plate_coupling_name =
    position among their initial values (and absolute FMU paths)."""
    import xml.etree.ElementTree as ET

    uri = "http://opensimulationplatform.com/MSMI/OSPSystemStructure"
    ET.register_namespace("", uri)
    tree = ET.parse(structure)
    base = pathlib.Path(structure).resolve().parent
    for sim in tree.getroot().iter(f"{{{uri}}}Simulator"):
        sim.set("source", str((base / sim.get("source")).resolve()))
        values = sim.find(f"{{{uri}}}InitialValues")
        value = ET.SubElement(values, f"{{{uri}}}InitialValue", variable="plate_coupling_name")
        ET.SubElement(value, f"{{{uri}}}String", value="position")
    path = pathlib.Path(directory) / "OspSystemStructure.xml"
    tree.write(path, encoding="utf-8", xml_declaration=True)
    return path


def run(structure, mass, stiffness, damping, stop, coupling="velocity"):
    """Run the system; returns {simulator name: list of rows} at t = h, 2h, ... stop.
    coupling = "velocity" gives each drop its plate's mean velocity over the next step
    (Gauss-Seidel), "position" its plate's position and velocity now (Jacobi)."""
    import tempfile
    import xml.etree.ElementTree as ET

    if coupling == "position":
        structure = with_position_coupling(structure, tempfile.mkdtemp(prefix="viscosph_osp_"))

    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver

    ns = {"osp": "http://opensimulationplatform.com/MSMI/OSPSystemStructure"}
    root = ET.parse(structure).getroot()
    step = float(root.find("osp:BaseStepSize", ns).text)
    sims = root.findall("osp:Simulators/osp:Simulator", ns)
    fmu = (pathlib.Path(structure).parent / sims[0].get("source")).resolve()
    vr = {v.name: v.valueReference for v in read_model_description(str(fmu)).modelVariables}

    ex = CosimExecution.from_osp_config_file(str(structure))
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer)
    manipulator = CosimManipulator.create_override()
    ex.add_manipulator(manipulator)
    names = ["wall_force_normal", "plate_displacement", "drop_width"]
    refs = [vr[n] for n in names]
    plates, index, rows = {}, {}, {}
    for s in sims:
        name = s.get("name")
        index[name] = ex.slave_index_from_instance_name(name)
        plates[name] = SpringPlate(mass, stiffness, damping)
        rows[name] = []
    n = int(round(stop / step))
    for k in range(n):
        if not ex.step():
            raise RuntimeError(f"libcosim: step {k + 1} failed")
        t = (k + 1) * step
        for name, i in index.items():
            out = dict(zip(names, observer.last_real_values(i, refs)))
            plate = plates[name]
            rows[name].append({"time": t, "plate_x": plate.x, "plate_v": plate.v, **out})
            if coupling == "position":
                refs_in, values = [vr["plate_position"], vr["plate_velocity"]], [plate.x, plate.v]
                plate.step(out["wall_force_normal"], step)
            else:
                refs_in = [vr["plate_velocity"]]
                values = [plate.step(out["wall_force_normal"], step)]
            if not manipulator.slave_real_values(i, refs_in, values):
                raise RuntimeError(f"libcosim refused {values} for {name}")
    ex.stop()
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--structure", default=str(HERE / "OspSystemStructure.xml"))
    ap.add_argument("--stop", type=float, default=0.03, help="stop time [s]")
    ap.add_argument("--mass", type=float, default=0.314, help="plate mass [kg/m]")
    ap.add_argument("--stiffness", type=float, default=3.1e4, help="spring [N/m per m depth]")
    ap.add_argument("--damping", type=float, default=20.0, help="damper [N s/m per m depth]")
    ap.add_argument("--coupling", choices=["velocity", "position"], default="velocity",
                    help="Gauss-Seidel by velocity, or Jacobi by position (see above)")
    ap.add_argument("--out", default=str(ROOT / "results"))
    args = ap.parse_args()
    rows = run(args.structure, args.mass, args.stiffness, args.damping, args.stop,
               args.coupling)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "osp_drops.csv", "w", newline="") as f:
        fields = ["simulator"] + list(next(iter(rows.values()))[0])
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        for name, rs in rows.items():
            for r in rs:
                w.writerow({"simulator": name, **r})
    fig, (a, b) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for name, rs in rows.items():
        t = [1e3 * r["time"] for r in rs]
        a.plot(t, [1e3 * r["plate_displacement"] for r in rs], label=name)
        b.plot(t, [r["wall_force_normal"] for r in rs], label=name)
    a.set_ylabel("plate displacement [mm]")
    a.set_title("two drops on spring-mounted plates (libcosim)")
    a.legend(loc="best")
    b.set_ylabel("wall force normal [N/m]")
    b.set_xlabel("time [ms]")
    b.legend(loc="best")
    fig.tight_layout()
    fig.savefig(out / "osp_drops.png", dpi=120)
    plt.close(fig)
    for name, rs in rows.items():
        peak = max(r["wall_force_normal"] for r in rs)
        print(f"{name}: peak wall force {peak:.2f} N/m, "
              f"largest plate displacement {1e3 * max(r['plate_x'] for r in rs):.3f} mm")
    print(f"wrote {out / 'osp_drops.csv'} and {out / 'osp_drops.png'}")


if __name__ == "__main__":
    main()
