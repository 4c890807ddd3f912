"""Issue 15: the default drop runs at any impact velocity from 0.5 to 5 m/s, because the default
sound speed is automatic (10 times the impact speed plus free fall, config.rs
SceneConfig::resolved_sound_speed). Before, c stayed at 12.5 m/s and the drop broke down at 2 m/s.
"""

import numpy as np
import pytest

from viscosph_fmu import DISCARD, ERROR, Log, simulate

D = 0.02  # the default drop diameter [m]


@pytest.mark.parametrize("scheme", ["wcsph", "pdri"])
@pytest.mark.parametrize("velocity", [0.5, 1.0, 2.0, 3.0, 5.0])
def test_default_drop_runs_to_t8_at_any_impact_velocity(fmu, md, scheme, velocity):
    items = {v.name: v for v in md.modelVariables}["scheme"].declaredType.items
    index = {i.name: int(i.value) for i in items}[scheme]
    stop = 8.0 * D / velocity  # t* = t V / D = 8
    log = Log()
    result = simulate(fmu, {"impact_velocity": velocity, "scheme": index,
                            "particles_per_diameter": 12},
                      stop_time=stop, step=stop / 80, logger=log)
    assert log.messages(DISCARD) == [] and log.messages(ERROR) == [], log.text()
    assert result["time"][-1] == pytest.approx(stop), "stopped early"
    # The drop hit the plate and spread: the run is a real impact, not a free fall.
    assert result["wall_force_normal"].max() > 0.0
    assert result["drop_width"][-1] > 1.3 * D
    vol = np.abs(result["volume_error"])
    assert vol.max() <= 0.04, f"|volume error| reached {vol.max():.4f} at V = {velocity} m/s"
