"""Run ViscoSPH.fmu in one co-simulation engine and print its outputs as JSON.

    python run_importer.py ENGINE FMU SETTINGS_JSON STOP_TIME STEP

ENGINE is `libcosim` (PyPI libcosimpy, the Open Simulation Platform's engine) or `ecos` (PyPI
ecospy). SETTINGS_JSON maps variable names to values: a str sets a String variable (the
enumerations' twins, e.g. rheology_name), an int an Integer, a float a Real. Prints a line
@@viscosph-json@@{"time": [...], "outputs": {name: [...]}} with one entry per communication point
(the engines print log lines of their own on stdout too).

Run in a subprocess by tests/python/test_importers.py because libcosim aborts the whole process
(not a Python exception) when an FMU refuses a value.
"""

import json
import sys

MARK = "@@viscosph-json@@"

from fmpy import read_model_description


def variables(fmu):
    md = read_model_description(fmu)
    return {v.name: v for v in md.modelVariables}


def run_libcosim(fmu, settings, stop, step):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    var = variables(fmu)
    outputs = [n for n, v in var.items() if v.causality == "output"]
    step_ns = int(round(step * 1e9))  # libcosim counts time in integer nanoseconds
    ex = CosimExecution.from_step_size(step_size=step_ns)
    index = ex.add_local_slave(CosimLocalSlave(fmu_path=fmu, instance_name="drop"))
    for name, value in settings.items():
        vr = var[name].valueReference
        if isinstance(value, str):
            ok = ex.string_initial_value(index, vr, value)
        elif isinstance(value, int):
            ok = ex.integer_initial_value(index, vr, value)
        else:
            ok = ex.real_initial_value(index, vr, float(value))
        if not ok:
            sys.exit(f"libcosim refused {name} = {value!r}")
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer)
    vrs = [var[n].valueReference for n in outputs]
    time, rows = [], []
    n = int(round(stop / step))
    for k in range(n):
        if not ex.step():
            sys.exit(f"libcosim: step {k + 1} failed")
        time.append((k + 1) * step_ns / 1e9)
        rows.append(observer.last_real_values(index, vrs))
    ex.stop()
    return time, {name: [r[j] for r in rows] for j, name in enumerate(outputs)}


def run_ecos(fmu, settings, stop, step):
    from ecospy import EcosSimulation, EcosSimulationStructure

    var = variables(fmu)
    outputs = [n for n, v in var.items() if v.causality == "output"]
    structure = EcosSimulationStructure()
    structure.add_model("drop", fmu)
    structure.add_parameter_set("initial", {f"drop::{k}": v for k, v in settings.items()})
    time, values = [], {name: [] for name in outputs}
    with EcosSimulation(structure=structure, step_size=step) as sim:
        sim.init(parameter_set="initial")
        for k in range(int(round(stop / step))):
            sim.step()
            time.append(sim.get_time())
            for name in outputs:
                values[name].append(sim.get_real(f"drop::{name}"))
        # read back what the FMU actually took, so a setting that was silently ignored shows
        for name, value in settings.items():
            if isinstance(value, str):
                got = sim.get_string(f"drop::{name}")
                if got != value:
                    sys.exit(f"ecos: {name} reads {got!r}, not {value!r}")
        sim.terminate()
    return time, values


def main():
    engine, fmu, settings, stop, step = sys.argv[1:6]
    settings = json.loads(settings)
    run = {"libcosim": run_libcosim, "ecos": run_ecos}[engine]
    time, outputs = run(fmu, settings, float(stop), float(step))
    # engines print their own log lines on stdout: mark ours
    sys.stdout.flush()
    print("\n" + MARK + json.dumps({"time": time, "outputs": outputs}), flush=True)


if __name__ == "__main__":
    main()
