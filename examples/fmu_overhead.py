"""What stepping the FMU at a 1 ms communication step costs against one long doStep (issue 16:
the FMU's overhead must stay below 5 %), through fmpy's low-level FMI 2.0 API, in one process.

Usage (the FMU from `cargo run --release -p fmu-build`; fmpy from tests' venv):
  python3 examples/fmu_overhead.py [--fmu target/fmu/ViscoSPH.fmu] [--t-end 0.16] [--rounds 3]

Both variants run the default scene (Fang's Oldroyd-B drop) from t = 0 to --t-end:
  * one: a single fmi2DoStep over the whole interval, then fmi2GetReal of every output;
  * 1ms: fmi2DoStep every 1 ms, each followed by fmi2GetReal of every output (what a
    co-simulation master does at each communication point).
Alternating rounds; prints the process CPU time (the FMU steps in its own thread pool, so CPU
time counts all its threads) and the wall time of each, the minimum over the rounds, and the
ratio 1ms / one of the minima.
"""
import argparse
import os
import time

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from compare_speed import cpu_model  # the same CPU line as the side-by-side timings


def run(md, unzipdir, t_end, h):
    """Wall and CPU seconds of one run to t_end at communication step h (h = t_end: one step)."""
    outputs = [v.valueReference for v in md.modelVariables if v.causality == "output"
               and v.type == "Real"]
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="overhead")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0, stopTime=t_end)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    n = int(round(t_end / h))
    c0, w0 = time.process_time(), time.perf_counter()
    last = None
    for k in range(n):
        fmu.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
        last = fmu.getReal(outputs)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    fmu.terminate()
    fmu.freeInstance()
    return wall, cpu, dict(zip(outputs, last))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fmu", default="target/fmu/ViscoSPH.fmu")
    ap.add_argument("--t-end", type=float, default=0.16)
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()
    md = read_model_description(a.fmu)
    unzipdir = extract(a.fmu)
    best = {}
    finals = {}
    for r in range(a.rounds):
        for name, h in (("one", a.t_end), ("1ms", 1e-3)):
            wall, cpu, last = run(md, unzipdir, a.t_end, h)
            finals[name] = last
            b = best.setdefault(name, [float("inf"), float("inf")])
            b[0], b[1] = min(b[0], wall), min(b[1], cpu)
            print(f"round {r + 1}: {name:4s} wall {wall:.3f} s, CPU {cpu:.3f} s", flush=True)
    print(f"\nCPU: {cpu_model()}, {os.cpu_count()} logical CPUs; load average "
          f"{os.getloadavg()[0]:.1f}; {a.rounds} alternating rounds; t_end = {a.t_end} s")
    print("| path | min wall [s] | min CPU [s] |\n|---|---|---|")
    for name, label in (("one", "one fmi2DoStep to t_end"),
                        ("1ms", "fmi2DoStep + fmi2GetReal of every output every 1 ms")):
        print(f"| {label} | {best[name][0]:.3f} | {best[name][1]:.3f} |")
    print(f"\noverhead of the 1 ms step (min CPU): {best['1ms'][1] / best['one'][1] - 1:+.1%}, "
          f"(min wall): {best['1ms'][0] / best['one'][0] - 1:+.1%}")
    # The two paths must end in the same state (the step taken never depends on where the
    # communication points fall, except for landing on them): report the largest difference.
    diff = max(abs(finals["one"][k] - finals["1ms"][k]) / max(abs(finals["one"][k]), 1e-30)
               for k in finals["one"])
    print(f"largest relative difference of the outputs at t_end between the two: {diff:.2e}")


if __name__ == "__main__":
    main()
