"""The channel scene through the FMU (issue 12): start-up Poiseuille flow chosen by name, its
outputs filled, the drop's outputs 0."""

import numpy as np
import pytest

from viscosph_fmu import Log, simulate


@pytest.mark.parametrize(
    "scheme,frame", [("wcsph", "lagrangian"), ("isph", "lagrangian"), ("isph", "eulerian")]
)
def test_newtonian_channel_through_the_fmu_approaches_the_exact_start_up(fmu, scheme, frame):
    # H = 2 cm, rho = 1000, eta0 = 4 Pa s, g = 80 m/s2: U = 1 m/s, t_v = rho H^2 / eta0 = 0.1 s.
    # isph: King & Lind's mirror walls, periodic images as neighbours, either frame.
    log = Log()
    r = simulate(
        fmu,
        start_values={
            "scene_name": "channel",
            "scheme_name": scheme,
            "isph_frame_name": frame,
            "rheology_name": "newtonian",
            "particles_per_diameter": 12,
            "sound_speed": 12.5,
        },
        stop_time=0.05,
        step=1e-2,
        logger=log,
    )
    t = r["time"]
    uc = r["centreline_velocity"]
    # Exact centre line (Newtonian start-up): 1 - 32/pi^3 sum_k (-1)^k/(2k+1)^3 exp(-(2k+1)^2 pi^2 s).
    s = t / 0.1
    exact = 1.0 - 32.0 / np.pi**3 * sum(
        (-1) ** k / (2 * k + 1) ** 3 * np.exp(-((2 * k + 1) ** 2) * np.pi**2 * s) for k in range(50)
    )
    assert np.all(np.abs(uc[1:] - exact[1:]) < 0.03), (uc, exact)
    assert np.all(np.diff(uc) > 0), "a Newtonian start-up rises monotonically"
    assert r["flow_rate"][-1] == pytest.approx(2.0 / 3.0 * 0.02 * uc[-1], rel=0.03)
    assert r["wall_shear_stress"][-1] > 0.0
    for name in ["drop_width", "drop_height", "spread_front", "wall_force_normal"]:
        assert np.all(r[name] == 0.0), name
