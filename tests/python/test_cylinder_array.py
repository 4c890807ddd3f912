"""The cylinder array through the FMU (King & Lind 2021 section IV.B): the scene runs a few
steps under ISPH and WCSPH, `cylinder_drag` and the other outputs of the scene are filled, and
an FMU state saved and restored repeats the run bit for bit."""

import numpy as np
import pytest

from viscosph_fmu import Slave

H = 1e-3


def index(md, variable, item):
    v = next(v for v in md.modelVariables if v.name == variable)
    return next(int(i.value) for i in v.declaredType.items if i.name == item)


def cell(unzipdir, scheme):
    # King & Lind's cell (R = 1 m, rho = 1, eta0 = 41.66 Pa s, g = 300 m/s2), Newtonian,
    # 8 particles across the diameter.
    s = Slave(unzipdir)
    md = s.md
    return s.initialize(
        reals={"density": 1.0, "viscosity": 41.66},
        integers={
            "scene": index(md, "scene", "cylinder_array"),
            "scheme": index(md, "scheme", scheme),
            "rheology": index(md, "rheology", "newtonian"),
            "particles_per_diameter": 8,
        },
    )


@pytest.mark.parametrize("scheme", ["isph", "wcsph"])
def test_cylinder_drag_through_the_fmu_and_state_restore(unzipdir, scheme):
    s = cell(unzipdir, scheme)
    names = [v.name for v in s.md.modelVariables if v.causality == "output"]
    col = {n: k for k, n in enumerate(names)}
    s.step_to(3 * H, H)
    state = s.fmu.getFMUstate()
    first = s.step_to(6 * H, H)
    last = first[-1]
    # The flow pushes the cylinder and the walls along it; the cell is symmetric about y = H/2.
    assert last[col["cylinder_drag"]] > 0.0
    assert last[col["wall_shear_force"]] > 0.0
    assert abs(last[col["cylinder_lift"]]) < 1e-2 * last[col["cylinder_drag"]]
    assert last[col["mean_velocity"]] > 0.0 and last[col["flow_rate"]] > 0.0
    for name in ["drop_width", "centreline_velocity", "wall_force_normal"]:
        assert np.all(first[:, col[name]] == 0.0), name
    s.fmu.setFMUstate(state)
    s.fmu.freeFMUstate(state)
    s.t = 3 * H
    again = s.step_to(6 * H, H)
    assert np.array_equal(first, again)
    s.free()
