"""Helpers for the fmpy tests of ViscoSPH.fmu: where the FMU is, how to build it, a logger that
records the FMU's messages, and thin wrappers over fmpy's simulate_fmu and FMU2Slave."""

import pathlib
import subprocess
import threading

import numpy as np
from fmpy import read_model_description, simulate_fmu
from fmpy.simulation import instantiate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU = ROOT / "target" / "fmu" / "ViscoSPH.fmu"

# The variables ARCHITECTURE.md ("The FMU contract") names. The parameter the contract calls
# drop_height is initial_drop_height in the FMU, because FMU names are unique and drop_height
# is an output.
CONTRACT_PARAMETERS = [
    "scene", "scheme", "rheology", "plate_inclination", "impact_velocity", "drop_diameter",
    "initial_drop_height", "density", "gravity", "viscosity", "viscosity_ratio",
    "relaxation_time", "fene_L2", "ptt_epsilon", "giesekus_alpha", "cross_viscosity_inf",
    "cross_K", "cross_m", "particles_per_diameter",
]
CONTRACT_OUTPUTS = [
    "drop_width", "drop_height", "wall_force_normal", "wall_force_tangential", "spread_front",
    "spread_back", "kinetic_energy", "volume_error", "max_conformation_trace", "time_step",
    "particle_count",
]

# fmi2Status and fmi2StatusKind values (FMI 2.0 sections 2.1.3, 4.2.3).
OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3
LAST_SUCCESSFUL_TIME, TERMINATED = 2, 3


def build_fmu():
    """Build target/fmu/ViscoSPH.fmu the way tests/run_all.sh does."""
    subprocess.run(["cargo", "run", "--release", "-p", "fmu-build"], cwd=ROOT, check=True)


class Log:
    """An fmpy logger callback that records (status, category, message); thread-safe."""

    def __init__(self):
        self.records = []
        self._lock = threading.Lock()

    def __call__(self, component, instance_name, status, category, message):
        with self._lock:
            self.records.append((status, category.decode(), message.decode()))

    def messages(self, status=None):
        with self._lock:
            return [m for s, _, m in self.records if status is None or s == status]

    def categories(self):
        with self._lock:
            return {c for _, c, _ in self.records}

    def text(self):
        return "\n".join(self.messages())


def simulate(fmu, start_values=None, stop_time=0.1, step=1e-3, logger=None, debug=False):
    """simulate_fmu with every output recorded; returns a numpy structured array.

    Always passes a logger. fmpy 0.3's native logger proxy (fmpy/logging, addLoggerProxy)
    keeps one process-wide pointer to the last Python logger registered, and fmpy's default
    callbacks (used when logger=None) call through it: after a simulate_fmu(logger=...) has
    returned and its ctypes callback has been collected, a later logger=None run that logs
    (a refused parameter) can call freed memory and crash the interpreter, depending on GC
    timing. Registering a fresh logger for every run keeps the proxy pointing at a live one.
    """
    if logger is None:
        logger = Log()
    md = read_model_description(fmu if not pathlib.Path(fmu).is_dir()
                                else pathlib.Path(fmu) / "modelDescription.xml")
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    return simulate_fmu(fmu, start_values=start_values or {}, stop_time=stop_time,
                        output_interval=step, output=outputs, logger=logger,
                        debug_logging=debug)


def value_references(md):
    return {v.name: v.valueReference for v in md.modelVariables}


def output_names(md):
    return [v.name for v in md.modelVariables if v.causality == "output"]


class Slave:
    """One FMU2Slave instance driven by hand (the calls fmpy's simulate_fmu makes, exposed)."""

    def __init__(self, unzipdir, logger=None, debug=False):
        self.md = read_model_description(str(pathlib.Path(unzipdir) / "modelDescription.xml"))
        self.vr = value_references(self.md)
        self.log = logger if logger is not None else Log()
        self.fmu = instantiate_fmu(unzipdir, self.md, "CoSimulation", logger=self.log,
                                   debug_logging=debug)
        self.t = 0.0

    def initialize(self, reals=None, integers=None, start=0.0):
        self.fmu.setupExperiment(startTime=start)
        if reals:
            self.fmu.setReal([self.vr[k] for k in reals], list(reals.values()))
        if integers:
            self.fmu.setInteger([self.vr[k] for k in integers], list(integers.values()))
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.t = start
        return self

    def step_to(self, t_end, h):
        """doStep from the current time to t_end in steps of h; outputs after each step."""
        rows = []
        n = int(round((t_end - self.t) / h))
        t0 = self.t
        for k in range(n):
            t_next = t0 + (k + 1) * h
            self.fmu.doStep(self.t, t_next - self.t)
            self.t = t_next
            rows.append(self.outputs())
        return np.array(rows)

    def outputs(self):
        return self.fmu.getReal([self.vr[n] for n in output_names(self.md)])

    def free(self):
        self.fmu.freeInstance()
