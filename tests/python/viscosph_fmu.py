"""Helpers for the fmpy tests of ViscoSPH.fmu and ViscoSPH-fmi3.fmu: where the FMUs are, how to
build them, a logger that records the FMU's messages, and thin wrappers over fmpy's simulate_fmu
and its FMU2Slave / FMU3Slave (one `Slave` for both FMI versions)."""

import ctypes
import pathlib
import subprocess
import tempfile
import threading
import zipfile

import numpy as np
from fmpy import read_model_description, simulate_fmu
from fmpy.simulation import instantiate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU = ROOT / "target" / "fmu" / "ViscoSPH.fmu"
FMU3 = ROOT / "target" / "fmu" / "ViscoSPH-fmi3.fmu"

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
    """An fmpy logger callback that records (status, category, message); thread-safe. Serves
    both FMI 2.0 (component, instanceName, status, category, message) and FMI 3.0's logMessage
    (instanceEnvironment, status, category, message): the last three arguments are the same."""

    def __init__(self):
        self.records = []
        self._lock = threading.Lock()

    def __call__(self, *args):
        status, category, message = args[-3:]
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
    if not pathlib.Path(fmu).is_dir():
        # fmpy extracts an archive into a temporary folder that it removes only when the run
        # returns: a run that raises (a refused parameter, a discard) left 61 MB in /tmp per call
        with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as unzipdir:
            with zipfile.ZipFile(fmu) as z:
                z.extractall(unzipdir)
            return simulate(unzipdir, start_values, stop_time, step, logger, debug)
    md = read_model_description(str(pathlib.Path(fmu) / "modelDescription.xml"))
    return simulate_fmu(str(fmu), start_values=start_values or {}, stop_time=stop_time,
                        output_interval=step, output=output_names(md), logger=logger,
                        debug_logging=debug)


def value_references(md):
    return {v.name: v.valueReference for v in md.modelVariables}


def output_names(md):
    """The scalar outputs (FMI 3.0's arrays wall_pressure / wall_shear are views of scalar ones)."""
    return [v.name for v in md.modelVariables if v.causality == "output" and not v.dimensions]


class Slave:
    """One co-simulation instance driven by hand (the calls fmpy's simulate_fmu makes, exposed),
    through FMI 2.0 (FMU2Slave) or FMI 3.0 (FMU3Slave), whichever the unzipped FMU declares.

    `fmu` is fmpy's object, for calls of one version; the methods below are the calls both
    versions have, each made the way its version makes it. `api` ("fmi2" or "fmi3") is the
    prefix of the function names the FMU's messages use."""

    def __init__(self, unzipdir, logger=None, debug=False):
        self.md = read_model_description(str(pathlib.Path(unzipdir) / "modelDescription.xml"))
        self.api = "fmi3" if self.md.fmiVersion == "3.0" else "fmi2"
        self.vr = value_references(self.md)
        self.log = logger if logger is not None else Log()
        self.fmu = instantiate_fmu(unzipdir, self.md, "CoSimulation", logger=self.log,
                                   debug_logging=debug)
        self.t = 0.0
        # FMI 3.0: the out-arguments of the last fmi3DoStep
        self._terminate = ctypes.c_bool()
        self._last_successful_time = ctypes.c_double()

    def initialize(self, reals=None, integers=None, start=0.0):
        if self.api == "fmi2":
            self.fmu.setupExperiment(startTime=start)
        if reals:
            self.set_reals(reals)
        if integers:
            self.set_integers(integers)
        if self.api == "fmi2":
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=start)
        self.fmu.exitInitializationMode()
        self.t = start
        return self

    def set_reals(self, values):
        vrs, xs = [self.vr[k] for k in values], list(values.values())
        (self.fmu.setReal if self.api == "fmi2" else self.fmu.setFloat64)(vrs, xs)

    def set_integers(self, values):
        vrs, xs = [self.vr[k] for k in values], list(values.values())
        (self.fmu.setInteger if self.api == "fmi2" else self.fmu.setInt32)(vrs, xs)

    def get_reals(self, names):
        vrs = [self.vr[k] for k in names]
        return (self.fmu.getReal if self.api == "fmi2" else self.fmu.getFloat64)(vrs)

    def do_step(self, t, h):
        """fmi2DoStep / fmi3DoStep; raises FMICallException past fmiWarning, as fmpy does. FMI 3.0's
        out-arguments are kept even when the call answers fmi3Discard (fmpy's doStep drops them
        then), for `terminated` and `last_successful_time`."""
        if self.api == "fmi2":
            return self.fmu.doStep(t, h)
        event, early = ctypes.c_bool(), ctypes.c_bool()
        self._terminate.value, self._last_successful_time.value = False, float("nan")
        return self.fmu.fmi3DoStep(self.fmu.component, t, h, True, ctypes.byref(event),
                                   ctypes.byref(self._terminate), ctypes.byref(early),
                                   ctypes.byref(self._last_successful_time))

    def terminated(self):
        """fmi2GetBooleanStatus(fmi2Terminated), or terminateSimulation of the last fmi3DoStep."""
        if self.api == "fmi2":
            return self.fmu.getBooleanStatus(TERMINATED)
        return self._terminate.value

    def last_successful_time(self):
        """fmi2GetRealStatus(fmi2LastSuccessfulTime), or lastSuccessfulTime of the last fmi3DoStep."""
        if self.api == "fmi2":
            return self.fmu.getRealStatus(LAST_SUCCESSFUL_TIME)
        return self._last_successful_time.value

    def get_state(self):
        return (self.fmu.getFMUstate if self.api == "fmi2" else self.fmu.getFMUState)()

    def set_state(self, state):
        (self.fmu.setFMUstate if self.api == "fmi2" else self.fmu.setFMUState)(state)

    def step_to(self, t_end, h):
        """doStep from the current time to t_end in steps of h; outputs after each step."""
        rows = []
        n = int(round((t_end - self.t) / h))
        t0 = self.t
        for k in range(n):
            t_next = t0 + (k + 1) * h
            self.do_step(self.t, t_next - self.t)
            self.t = t_next
            rows.append(self.outputs())
        return np.array(rows)

    def outputs(self):
        return self.get_reals(output_names(self.md))

    def free(self):
        self.fmu.freeInstance()
