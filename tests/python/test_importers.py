"""Model selection in every engine: the Enumeration parameters' String twins (rheology_name, ...)
let OSP libcosim (libcosimpy) and ecos (ecospy), which ignore FMI 2.0 Enumerations, and fmpy's
start_values choose the model by name; the runs agree with fmpy's to 1e-12 and the choice takes
effect. Also: the FMU passes fmu-manipulation-toolbox's checker."""

import json
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from viscosph_fmu import ERROR, Log, Slave, simulate

HERE = pathlib.Path(__file__).resolve().parent
# A short Giesekus drop on a 30 degree plate, coarse, started 3 mm above it: impact at about
# 3 ms, then 20 ms of spreading, in which the polymer stress (and so the constitutive model)
# shapes the flow.
SETTINGS = {"rheology_name": "giesekus", "plate_inclination": 30.0,
            "particles_per_diameter": 12, "initial_drop_height": 0.015}
STOP, STEP = 0.025, 1e-3


def fmpy_run(fmu, settings):
    res = simulate(fmu, start_values=settings, stop_time=STOP, step=STEP)
    names = [n for n in res.dtype.names if n != "time"]
    # simulate_fmu records t = 0 too; the engines below record after each step
    return res["time"][1:], {n: res[n][1:] for n in names}


@pytest.fixture(scope="module")
def reference(fmu):
    return fmpy_run(fmu, SETTINGS)


def engine_run(engine, fmu, settings):
    run = subprocess.run(
        [sys.executable, str(HERE / "run_importer.py"), engine, fmu, json.dumps(settings),
         str(STOP), str(STEP)],
        capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, f"{engine} failed ({run.returncode}):\n{run.stderr[-3000:]}"
    line = [ln for ln in run.stdout.splitlines() if ln.startswith("@@viscosph-json@@")][-1]
    out = json.loads(line[len("@@viscosph-json@@"):])
    return np.array(out["time"]), {k: np.array(v) for k, v in out["outputs"].items()}


def assert_same(got, ref, rtol=1e-12):
    t, out = got
    t_ref, out_ref = ref
    assert len(t) == len(t_ref)
    np.testing.assert_allclose(t, t_ref, rtol=1e-15, atol=0)
    for name, r in out_ref.items():
        scale = max(np.max(np.abs(r)), 1e-300)
        np.testing.assert_allclose(out[name], r, rtol=rtol, atol=rtol * scale, err_msg=name)


def test_fmpy_sets_the_rheology_by_name_as_by_number(fmu, reference):
    settings = {k: v for k, v in SETTINGS.items() if k != "rheology_name"}
    by_number = fmpy_run(fmu, {**settings, "rheology": 8})
    assert_same(by_number, reference, rtol=0)


def test_the_rheology_takes_effect(fmu, reference):
    oldroyd = fmpy_run(fmu, {**SETTINGS, "rheology_name": "oldroyd_b"})
    _, ref = reference
    differs = {n: np.max(np.abs(oldroyd[1][n] - ref[n])) / np.max(np.abs(ref[n]))
               for n in ["drop_width", "drop_height", "wall_force_normal",
                         "max_conformation_trace"]}
    # Giesekus' quadratic stress term (alpha = 0.1) changes the stress, and with it the
    # spreading, by far more than round-off
    assert max(differs.values()) > 1e-3, differs


@pytest.mark.parametrize("engine", ["libcosim", "ecos"])
def test_engine_runs_the_giesekus_drop_like_fmpy(engine, fmu, reference):
    assert_same(engine_run(engine, fmu, SETTINGS), reference)


def test_bad_name_is_refused_with_the_choices(fmu):
    log = Log()
    with pytest.raises(FMICallException):
        simulate(fmu, start_values={"rheology_name": "honey"}, logger=log, stop_time=0.001)
    text = log.text()
    assert "rheology" in text and "honey" in text and "'giesekus'" in text, text


def test_string_twin_reads_the_enumeration(unzipdir):
    s = Slave(unzipdir)
    try:
        s.fmu.setupExperiment(startTime=0.0)
        s.fmu.setInteger([s.vr["scheme"]], [2])
        s.fmu.enterInitializationMode()  # values are readable from here on
        assert s.fmu.getString([s.vr["scheme_name"], s.vr["rheology_name"]]) == [
            b"pdri", b"oldroyd_b"]
        s.fmu.setString([s.vr["rheology_name"]], ["cross"])
        assert s.fmu.getInteger([s.vr["rheology"]]) == [9]
        # a String twin is not an Integer variable
        with pytest.raises(FMICallException):
            s.fmu.getInteger([s.vr["rheology_name"]])
        assert any("String" in m for m in s.log.messages(ERROR))
    finally:
        s.free()


def test_fmutool_check_passes(fmu):
    fmutool = pathlib.Path(sys.executable).with_name("fmutool")
    exe = str(fmutool) if fmutool.exists() else shutil.which("fmutool")
    assert exe, "fmutool (fmu-manipulation-toolbox) is installed by tests/python/setup_venv.sh"
    run = subprocess.run([exe, "-input", fmu, "-check"], capture_output=True, text=True,
                         timeout=300)
    text = run.stdout + run.stderr
    assert run.returncode == 0, text
    assert "compliant with FMI-2.0" in text and "No semantic error" in text, text
