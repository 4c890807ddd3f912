"""The FMU input `plate_velocity` and two-way coupling, through fmpy and libcosim.

The physics of the coupling (a free plate conserves the momentum of drop and plate, a stiff
spring gives the fixed plate's force) is checked in tests/coupling.rs on the library; here the
same master runs through the FMU: examples/spring_plate.py (fmpy's FMU2Slave) and
examples/osp/run_osp.py (libcosim)."""

import csv
import pathlib
import subprocess
import sys

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from viscosph_fmu import ROOT, Log, Slave

sys.path.insert(0, str(ROOT / "examples"))
import spring_plate  # noqa: E402

# A Newtonian drop released just above the plate: impact within the first milliseconds.
DROP = {"initial_drop_height": 0.0115, "threads": 1}
H = 2e-4


def newtonian_index(md):
    v = next(v for v in md.modelVariables if v.name == "rheology")
    return next(int(i.value) for i in v.declaredType.items if i.name == "newtonian")


def slave(unzipdir, md):
    s = Slave(unzipdir)
    s.initialize(reals={"initial_drop_height": DROP["initial_drop_height"]},
                 integers={"rheology": newtonian_index(md), "threads": DROP["threads"]})
    return s


def test_plate_velocity_is_a_continuous_input_with_a_start_value(md):
    v = next(v for v in md.modelVariables if v.name == "plate_velocity")
    assert (v.causality, v.variability, v.type, v.unit) == ("input", "continuous", "Real", "m/s")
    assert float(v.start) == 0.0


def test_a_zero_plate_velocity_gives_bitwise_the_static_plate(unzipdir, md):
    a, b = slave(unzipdir, md), slave(unzipdir, md)
    vr = b.vr["plate_velocity"]
    rows_a, rows_b = [], []
    for k in range(40):
        t = k * H
        a.fmu.doStep(t, H)
        b.fmu.setReal([vr], [0.0])
        b.fmu.doStep(t, H)
        rows_a.append(a.outputs())
        rows_b.append(b.outputs())
    rows_a, rows_b = np.array(rows_a), np.array(rows_b)
    # the drop has hit the plate, so the comparison covers the impact
    force = [v.name for v in md.modelVariables if v.causality == "output"].index(
        "wall_force_normal")
    assert rows_a[:, force].max() > 10.0
    assert np.array_equal(rows_a, rows_b)
    a.free()
    b.free()


def output(s, name):
    return s.fmu.getReal([s.vr[name]])[0]


def test_the_plate_follows_the_input_from_the_communication_point_on(unzipdir, md):
    s = slave(unzipdir, md)
    s.step_to(0.002, H)
    assert output(s, "plate_displacement") == 0.0
    s.fmu.setReal([s.vr["plate_velocity"]], [0.1])
    assert s.fmu.getReal([s.vr["plate_velocity"]])[0] == 0.1
    s.step_to(0.004, H)
    assert output(s, "plate_displacement") == pytest.approx(0.1 * 0.002, rel=1e-12)
    s.fmu.setReal([s.vr["plate_velocity"]], [-0.05])
    s.step_to(0.005, H)
    assert output(s, "plate_displacement") == pytest.approx(0.1 * 0.002 - 0.05 * 0.001, rel=1e-12)
    s.free()


def test_a_fixed_parameter_is_refused_after_initialization_naming_the_inputs(unzipdir, md):
    log = Log()
    s = Slave(unzipdir, logger=log)
    s.initialize()
    with pytest.raises(FMICallException):
        s.fmu.setReal([s.vr["impact_velocity"], s.vr["plate_velocity"]], [2.0, 0.1])
    assert "only inputs (plate_velocity, plate_position, jet_velocity) can be set" in log.text()
    s.free()


def test_state_save_and_restore_with_a_moving_plate_is_bitwise(unzipdir, md):
    s = slave(unzipdir, md)
    s.step_to(0.002, H)
    s.fmu.setReal([s.vr["plate_velocity"]], [0.2])
    state = s.fmu.getFMUState()
    t0 = s.t
    first = s.step_to(0.004, H)
    s.fmu.setFMUState(state)
    s.t = t0
    # the restored input is the one in force when the state was taken
    assert s.fmu.getReal([s.vr["plate_velocity"]])[0] == 0.2
    again = s.step_to(0.004, H)
    assert np.array_equal(first, again)
    s.fmu.freeFMUState(state)
    s.free()


def test_spring_plate_example_stiff_spring_approaches_the_fixed_plate(fmu):
    start = {"rheology_name": "newtonian", **DROP}
    stop = 0.016
    mass = 3.14
    k = 1.0e7
    stiff = spring_plate.run(fmu, mass, k, 2.0 * (k * mass) ** 0.5, H, stop, start)
    fixed = spring_plate.run(fmu, mass, k, 0.0, H, stop, start, couple=False)
    f_stiff = np.array([r["wall_force_normal"] for r in stiff])
    f_fixed = np.array([r["wall_force_normal"] for r in fixed])
    peak = f_fixed.max()
    assert peak > 10.0
    assert np.abs(f_stiff - f_fixed).max() < 0.05 * peak
    # and the FMU's plate is where the master's plate is, at every communication point
    for r in stiff:
        assert r["plate_displacement"] == pytest.approx(r["plate_x"], abs=1e-12)


def test_spring_plate_example_writes_its_table_and_plot(fmu, tmp_path):
    r = subprocess.run([sys.executable, str(ROOT / "examples" / "spring_plate.py"), "--fmu", fmu,
                        "--stop", "0.01", "--set", "rheology=newtonian",
                        "--set", "initial_drop_height=0.0115", "--out", str(tmp_path)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(open(tmp_path / "spring_plate.csv")))
    assert len(rows) == 51
    # the drop pushed the plate away from the fluid
    assert max(float(x["plate_x"]) for x in rows) > 0.0
    assert (tmp_path / "spring_plate.png").stat().st_size > 10_000


def test_osp_example_runs_the_two_drop_system_in_libcosim_like_fmpy(fmu, tmp_path):
    """libcosim runs examples/osp/OspSystemStructure.xml (a Newtonian and a Giesekus drop on
    spring plates); its Newtonian drop matches the fmpy master's run of the same system to
    round-off (libcosim counts time in integer nanoseconds), and the rheology took effect."""
    stop = 0.01
    r = subprocess.run([sys.executable, str(ROOT / "examples" / "osp" / "run_osp.py"),
                        "--stop", str(stop), "--out", str(tmp_path)],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stdout + r.stderr
    rows = list(csv.DictReader(open(tmp_path / "osp_drops.csv")))
    by = {}
    for x in rows:
        by.setdefault(x["simulator"], []).append(x)
    assert set(by) == {"newtonian", "giesekus"}
    f_n = np.array([float(x["wall_force_normal"]) for x in by["newtonian"]])
    f_g = np.array([float(x["wall_force_normal"]) for x in by["giesekus"]])
    assert np.abs(f_n - f_g).max() > 0.01 * np.abs(f_n).max()
    # fmpy, same master: libcosim's first step runs with the start input 0, like ours.
    ref = spring_plate.run(fmu, 0.314, 3.1e4, 20.0, H, stop,
                           {"rheology_name": "newtonian", **DROP})
    f_ref = np.array([r_["wall_force_normal"] for r_ in ref[1:]])
    x_ref = np.array([r_["plate_displacement"] for r_ in ref[1:]])
    x_n = np.array([float(x["plate_displacement"]) for x in by["newtonian"]])
    assert len(f_ref) == len(f_n)
    scale = np.abs(f_ref).max()
    assert np.abs(f_ref - f_n).max() <= 1e-9 * scale
    assert np.abs(x_ref - x_n).max() <= 1e-12 + 1e-9 * np.abs(x_ref).max()
    assert (tmp_path / "osp_drops.png").stat().st_size > 10_000


def test_a_jacobi_master_with_the_position_input_does_not_drift(fmi):
    """examples/spring_plate.py as a Jacobi master, through FMI 2.0 and FMI 3.0: with the
    plate's velocity alone the plate drifts from the Gauss-Seidel run; with plate_coupling =
    position and the plate's position and velocity it stays within 0.5 % of the Gauss-Seidel
    run's largest displacement."""
    start = {"rheology_name": "newtonian", **DROP}
    stop = 0.025
    runs = {c: spring_plate.run(fmi.fmu, 0.314, 3.1e4, 20.0, H, stop, start, coupling=c)
            for c in spring_plate.COUPLINGS}
    x = {c: np.array([r["plate_x"] for r in rows]) for c, rows in runs.items()}
    gs = x["gauss-seidel"]
    scale = np.abs(gs).max()
    assert scale > 1e-5
    drift = {c: np.abs(x[c] - gs).max() / scale for c in x}
    assert drift["jacobi-position"] < 0.005, drift
    assert drift["jacobi-position"] < drift["jacobi-velocity"], drift
    # the FMU's plate follows the master's to within one step's extrapolation
    rows = runs["jacobi-position"]
    gap = max(abs(r["plate_displacement"] - r["plate_x"]) for r in rows)
    assert gap < 0.005 * scale, gap


def test_libcosim_with_the_position_input_follows_the_gauss_seidel_run(fmu, tmp_path):
    """examples/osp/run_osp.py --coupling position (a Jacobi coupling in libcosim): the
    Newtonian drop's plate stays within 0.5 % of the Gauss-Seidel fmpy run's largest
    displacement."""
    stop = 0.025
    r = subprocess.run([sys.executable, str(ROOT / "examples" / "osp" / "run_osp.py"),
                        "--stop", str(stop), "--coupling", "position", "--out", str(tmp_path)],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stdout + r.stderr
    rows = [x for x in csv.DictReader(open(tmp_path / "osp_drops.csv"))
            if x["simulator"] == "newtonian"]
    ref = spring_plate.run(fmu, 0.314, 3.1e4, 20.0, H, stop,
                           {"rheology_name": "newtonian", **DROP})
    x_ref = np.array([r_["plate_x"] for r_ in ref[1:]])
    x = np.array([float(x["plate_x"]) for x in rows])
    assert len(x) == len(x_ref)
    scale = np.abs(x_ref).max()
    assert np.abs(x - x_ref).max() < 0.005 * scale
