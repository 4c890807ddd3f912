"""examples/sweep.py: 8 cases on a Dask LocalCluster give bitwise the rows of the same cases run
serially in this process (one instance reused with fmi2Reset in both, in different orders and
on different workers), and a case that breaks down is a row with its cause."""

import importlib
import math
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def sweep():
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        return importlib.import_module("sweep")
    finally:
        sys.path.remove(str(ROOT / "examples"))


# WCSPH with the sound speed fixed at Fang's 12.5 m/s: at 5 m/s the flow outruns it (Mach 0.4)
# and the run breaks down; at 1 m/s it does not.
# The drops start two particle spacings above the plate (sweep.start_height).
SETTINGS = {"particles_per_diameter": 10, "sound_speed": 12.5, "scheme_name": "wcsph"}
STOP, STEP = 0.02, 1e-3


def test_dask_matches_serial_bitwise_and_breakdowns_are_rows(sweep, fmu, tmp_path):
    from dask.distributed import Client, LocalCluster

    fmu_bytes = pathlib.Path(fmu).read_bytes()
    cases = sweep.grid([0.0, 30.0], [1.0, 5.0], ["oldroyd_b", "giesekus"])
    assert len(cases) == 8
    serial = sweep.run_serial(fmu_bytes, cases, SETTINGS, STOP, STEP, progress=False)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        parallel = sweep.run_dask(client, fmu_bytes, cases, SETTINGS, STOP, STEP,
                                  progress=False)
    assert [r["case"] for r in parallel] == list(range(8))
    for s, p in zip(serial, parallel):
        for k in sweep.COLUMNS:
            same = (s[k] == p[k]) or (isinstance(s[k], float) and math.isnan(s[k])
                                       and math.isnan(p[k]))
            assert same, (k, s, p)  # bitwise: == on floats, no tolerance

    for r in serial:
        if r["impact_velocity"] == 5.0:
            assert r["breakdown"], r
            assert "sound" in r["breakdown"] or "fast" in r["breakdown"], r["breakdown"]
            assert r["time_reached"] < STOP
        else:
            assert r["breakdown"] == "", r
            assert r["time_reached"] == pytest.approx(STOP)
            # the drop has landed and spread: wider than it was, pushing on the plate
            assert r["max_spreading_factor"] > 1.0 and r["peak_wall_force"] > 0
    giesekus = [r for r in serial if r["rheology"] == "giesekus" and not r["breakdown"]]
    oldroyd = [r for r in serial if r["rheology"] == "oldroyd_b" and not r["breakdown"]]
    assert any(g["max_spreading_factor"] != o["max_spreading_factor"]
               or g["peak_wall_force"] != o["peak_wall_force"]
               for g, o in zip(giesekus, oldroyd))

    sweep.write_csv(serial, tmp_path / "sweep.csv")
    lines = (tmp_path / "sweep.csv").read_text().splitlines()
    assert len(lines) == 9 and "peak_wall_force [N/m]" in lines[0]
    sweep.regime_map(serial, tmp_path / "sweep.png", "test")
    assert (tmp_path / "sweep.png").stat().st_size > 10_000
