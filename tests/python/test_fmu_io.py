"""The FMU's inputs within the range a run is set up for, and the load along the plate,
through fmpy (tests/inputs.rs and tests/plate_load.rs check the same on the library)."""

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from viscosph_fmu import DISCARD, WARNING, Log, Slave

H = 2e-4
BINS = 24  # scene::drop::WALL_BINS


def test_the_plate_input_ranges_are_declared(fmi):
    v = {x.name: x for x in fmi.md.modelVariables}
    for name in ("plate_velocity", "plate_position"):
        assert v[name].causality == "input"
        assert v[name].min is not None and v[name].max is not None
        assert float(v[name].min) < 0.0 < float(v[name].max), name
    assert v["max_plate_speed"].causality == "parameter"
    assert float(v["max_plate_speed"].start) == 1.0
    assert v["max_jet_velocity"].causality == "parameter"
    assert [i.name for i in v["plate_coupling"].declaredType.items] == ["velocity", "position"]


@pytest.mark.parametrize("speed", [-1.0, -5.0])
def test_a_plate_driven_into_the_default_drop(fmi, speed):
    """The default drop with the plate driven into it: -1 m/s (within max_plate_speed) runs,
    -5 m/s warns at fmi2SetReal / fmi3SetFloat64 and is discarded by name at fmi2DoStep /
    fmi3DoStep before any work (lastSuccessfulTime stays at the start, no termination)."""
    log = Log()
    s = Slave(fmi.unzipdir, logger=log, debug=True)  # warnings are logged with loggingOn
    s.initialize(reals={"initial_drop_height": 0.012}, integers={"threads": 1})
    s.set_reals({"plate_velocity": speed})
    if speed == -1.0:
        assert log.messages(WARNING) == []
        s.step_to(0.004, H)
        assert s.get_reals(["plate_displacement"])[0] == pytest.approx(-0.004, rel=1e-9)
    else:
        warning = log.messages(WARNING)[-1]
        assert "plate_velocity" in warning and "max_plate_speed" in warning, warning
        setter = {"fmi2": "fmi2SetReal", "fmi3": "fmi3SetFloat64"}[fmi.api]
        assert warning.startswith(setter + ":"), warning
        with pytest.raises(FMICallException) as e:
            s.do_step(0.0, H)
        assert e.value.status == DISCARD
        text = log.text()
        assert "plate_velocity = -5 m/s" in text and "max_plate_speed = 1 m/s" in text
        msg = log.messages(DISCARD)[-1]
        assert f"{fmi.api}DoStep" in msg and "Nothing was computed" in msg, msg
        assert fmi.api == "fmi2" or "fmi2" not in msg, msg
        assert s.last_successful_time() == 0.0 and not s.terminated()
        assert s.get_reals(["plate_displacement"]) == [0.0]
    s.free()


def test_the_bins_integrate_to_the_wall_force(unzipdir):
    s = Slave(unzipdir)
    s.initialize(reals={"initial_drop_height": 0.012}, integers={"threads": 1})
    d = 0.02
    width = 6.0 * d / BINS
    p = [s.vr[f"wall_pressure_{k:03d}"] for k in range(1, BINS + 1)]
    t = [s.vr[f"wall_shear_{k:03d}"] for k in range(1, BINS + 1)]
    f = [s.vr["wall_force_normal"], s.vr["wall_force_tangential"]]
    seen = 0
    for k in range(20):
        s.fmu.doStep(k * H, H)
        f_n, f_t = s.fmu.getReal(f)
        scale = max(abs(f_n), abs(f_t), 1e-300)
        assert abs(sum(s.fmu.getReal(p)) * width - f_n) <= 1e-12 * scale
        assert abs(sum(s.fmu.getReal(t)) * width - f_t) <= 1e-12 * scale
        seen += f_n > 0
    assert seen > 3
    pressure = np.array(s.fmu.getReal(p))
    # a normal impact: symmetric about the impact point
    assert np.abs(pressure - pressure[::-1]).max() <= 1e-9 * np.abs(pressure).max()
    s.free()
