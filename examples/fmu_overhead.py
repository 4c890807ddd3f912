"""FMU overhead at a 1 ms communication step (issue 16, item 4).

The same drop (the FMU's defaults: Fang 2006's Oldroyd-B drop, to t = 0.16 s = t* 8, one thread)
is run through ViscoSPH.fmu twice per round, alternating: once as a single doStep over the whole
run, once in 1 ms communication steps reading every output after each step (what a master
coupling at 1 kHz does). The overhead is the ratio of the minimum CPU times over the rounds
(CPU time of this process, which runs the FMU's solver: comparable on a loaded machine).
Both runs must end with the same outputs (the landing on communication points does not change
the solver's step sequence), which the script checks.

    .venv/bin/python examples/fmu_overhead.py [--fmu target/fmu/ViscoSPH.fmu] [--rounds 3]
        [--particles-per-diameter 20]
"""

import argparse
import sys
import time

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

T_END = 0.16


def run(md, unzipped, step, ppd):
    """CPU and wall time of one run stepped at `step`, and the outputs at its end."""
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outputs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    s = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipped,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="overhead",
    )
    s.instantiate()
    s.setupExperiment(startTime=0.0, stopTime=T_END)
    s.enterInitializationMode()
    s.setInteger([vr["threads"], vr["particles_per_diameter"]], [1, ppd])
    s.exitInitializationMode()
    cpu0, wall0 = time.process_time(), time.perf_counter()
    last = None
    n = round(T_END / step)
    for k in range(n):
        s.doStep(currentCommunicationPoint=k * step, communicationStepSize=step)
        last = s.getReal(outputs)
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    s.terminate()
    s.freeInstance()
    return cpu, wall, last


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmu", default="target/fmu/ViscoSPH.fmu")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--particles-per-diameter", type=int, default=20)
    a = ap.parse_args()
    md = read_model_description(a.fmu)
    unzipped = extract(a.fmu)
    cpu = {T_END: [], 0.001: []}
    ends = {}
    for r in range(a.rounds):
        for step in (T_END, 0.001):
            c, w, last = run(md, unzipped, step, a.particles_per_diameter)
            cpu[step].append(c)
            ends[step] = last
            print(f"round {r}, communication step {step} s: CPU {c:.3f} s, wall {w:.3f} s", flush=True)
    if ends[T_END] != ends[0.001]:
        print("the two runs ended with different outputs", file=sys.stderr)
        return 1
    one, ms = min(cpu[T_END]), min(cpu[0.001])
    print(
        f"W/dr = {a.particles_per_diameter}: one doStep {one:.3f} s CPU, 1 ms steps {ms:.3f} s CPU: "
        f"overhead {100 * (ms / one - 1):+.2f} % (minimum over {a.rounds} alternating rounds)"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
