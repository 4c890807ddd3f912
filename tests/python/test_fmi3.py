"""ViscoSPH-fmi3.fmu through fmpy's FMI 3.0 support: the archive validates, simulate_fmu runs the
default drop to the outputs the FMI 2.0 FMU gives (one library exports both APIs), the plate
input moves the plate, FMU states restore bitwise, and a refused call is fmi3Error with an FMI
3.0 message."""

import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

from viscosph_fmu import FMU, Log, simulate

STOP, STEP = 0.04, 1e-3
SMALL = {"particles_per_diameter": 14}


def outputs(md):
    """The scalar outputs (the FMI 2.0 FMU's); the arrays are views of some of them."""
    return [v for v in md.modelVariables if v.causality == "output" and not v.dimensions]


def arrays(md):
    return [v for v in md.modelVariables if v.causality == "output" and v.dimensions]


def test_fmi3_fmu_validates_and_holds_the_three_platforms(fmu3):
    assert validate_fmu(fmu3) == []
    md = read_model_description(fmu3)
    assert md.fmiVersion == "3.0"
    assert md.instantiationToken == read_model_description(str(FMU)).guid
    names = zipfile.ZipFile(fmu3).namelist()
    for lib in ["binaries/x86_64-linux/ViscoSPH.so", "binaries/x86_64-windows/ViscoSPH.dll",
                "binaries/aarch64-linux/ViscoSPH.so"]:
        assert lib in names, names


def test_simulate_fmu_gives_the_fmi2_outputs(fmu3):
    md = read_model_description(fmu3)
    names = [v.name for v in outputs(md)]
    three = simulate_fmu(fmu3, fmi_type="CoSimulation", start_values=SMALL, stop_time=STOP,
                         output_interval=STEP, output=names, logger=Log())
    two = simulate(str(FMU), start_values=SMALL, stop_time=STOP, step=STEP)
    assert len(three) == len(two) == int(round(STOP / STEP)) + 1
    for n in names:
        assert np.array_equal(three[n], two[n]), n
    # the drop has landed on the plate within the run
    assert three["wall_force_normal"].max() > 0


def slave(unzip3, md, log):
    s = FMU3Slave(guid=md.instantiationToken, unzipDirectory=str(unzip3),
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName="fmi3")
    s.instantiate(logMessage=log)
    return s


def vr_of(md, name):
    return next(v.valueReference for v in md.modelVariables if v.name == name)


def test_plate_input_moves_the_plate_and_state_restores_bitwise(unzip3):
    md = read_model_description(str(unzip3 / "modelDescription.xml"))
    log = Log()
    s = slave(unzip3, md, log)
    s.setInt32([vr_of(md, "particles_per_diameter")], [14])
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    out = [v.valueReference for v in outputs(md)]
    d = vr_of(md, "plate_displacement")
    t = 0.0
    for _ in range(5):
        assert s.doStep(t, STEP) == (False, False, False, pytest.approx(t + STEP, abs=1e-15))
        t += STEP
    s.setFloat64([vr_of(md, "plate_velocity")], [-0.5])
    state = s.getFMUState()
    for _ in range(5):
        s.doStep(t, STEP)
        t += STEP
    first = s.getFloat64(out)
    # the plate moved 0.5 m/s x 5 ms from where it stood
    assert abs(abs(s.getFloat64([d])[0]) - 0.0025) < 1e-12
    s.setFMUState(state)
    data = s.serializeFMUState(state)
    s.freeFMUState(state)
    t = 5 * STEP
    for _ in range(5):
        s.doStep(t, STEP)
        t += STEP
    assert s.getFloat64(out) == first
    restored = s.deserializeFMUState(data)
    s.setFMUState(restored)
    s.freeFMUState(restored)
    t = 5 * STEP
    for _ in range(5):
        s.doStep(t, STEP)
        t += STEP
    assert s.getFloat64(out) == first
    s.terminate()
    s.freeInstance()


def test_plate_load_arrays_are_the_scalar_bins_and_integrate_to_the_wall_force(unzip3):
    """wall_pressure and wall_shear (FMI 3.0 arrays of 24, read with nValues = 24) equal their
    scalar elements wall_pressure_001..024 bitwise, and the bins times the bin length (6 D / 24)
    sum to wall_force_normal and wall_force_tangential within 1e-12 of the force."""
    md = read_model_description(str(unzip3 / "modelDescription.xml"))
    by_name = {v.name: v for v in arrays(md)}
    assert sorted(by_name) == ["wall_pressure", "wall_shear"]
    assert [int(d.start) for d in by_name["wall_pressure"].dimensions] == [24]
    assert (by_name["wall_pressure"].valueReference, by_name["wall_shear"].valueReference) == (180, 181)
    log = Log()
    s = slave(unzip3, md, log)
    s.setInt32([vr_of(md, "threads")], [1])
    s.setFloat64([vr_of(md, "initial_drop_height")], [0.012])
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    width = 6.0 * 0.02 / 24
    forces = [vr_of(md, "wall_force_normal"), vr_of(md, "wall_force_tangential")]
    seen, t, h = 0, 0.0, 2e-4
    for _ in range(20):
        s.doStep(t, h)
        t += h
        f_n, f_t = s.getFloat64(forces)
        scale = max(abs(f_n), abs(f_t), 1e-300)
        for name, force in [("wall_pressure", f_n), ("wall_shear", f_t)]:
            array = s.getFloat64([by_name[name].valueReference], nValues=24)
            scalars = s.getFloat64([vr_of(md, f"{name}_{k:03d}") for k in range(1, 25)])
            assert list(array) == list(scalars), name
            assert abs(sum(array) * width - force) <= 1e-12 * scale, name
        # the time of the communication point, from the independent variable
        assert s.getFloat64([0]) == [pytest.approx(t, abs=1e-15)]
        seen += f_n > 0
    assert seen > 3
    s.terminate()
    s.freeInstance()


def test_a_refused_call_is_fmi3_error_in_fmi3_words(unzip3):
    md = read_model_description(str(unzip3 / "modelDescription.xml"))
    log = Log()
    s = slave(unzip3, md, log)
    with pytest.raises(FMICallException):
        s.doStep(0.0, STEP)
    message = log.messages()[-1]
    assert "fmi3DoStep: illegal call sequence" in message
    assert "fmi3EnterInitializationMode" in message and "fmi2" not in message
    s.reset()
    with pytest.raises(FMICallException):
        s.setFloat64([vr_of(md, "plate_inclination")], [1e9])
    assert "plate_inclination" in log.messages()[-1]
    s.freeInstance()
