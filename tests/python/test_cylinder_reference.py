"""The finite-element reference of King & Lind's periodic array of cylinders
(validation/cylinder_array): the coarsest level is solved again here (about a second) and must
reproduce the stored convergence tables; the stored tables must show the convergence they claim.

The full study (`python validation/cylinder_array/reference/stokes_fem.py all`, ~10 min) is not
run here."""

import csv
import math
import sys
from pathlib import Path

import pytest

REF = Path(__file__).resolve().parents[2] / "validation" / "cylinder_array" / "reference"
sys.path.insert(0, str(REF))

import stokes_fem as fem  # noqa: E402 (after the path insert)


def table(name):
    with open(REF / name, newline="") as fh:
        return [{k: fem._num(v) for k, v in row.items()} for row in csv.DictReader(fh)]


def rel(a, b):
    return abs(a - b) / abs(b)


@pytest.fixture(scope="module")
def cell_level0():
    return fem.solve(fem.kl_geometry(), fem.kl_physics(inertia=True), 0)


def test_coarsest_cell_reproduces_stored_level(cell_level0):
    stokes, ns = cell_level0
    for sol, name in ((stokes, "convergence_stokes.csv"), (ns, "convergence_navier_stokes.csv")):
        stored = table(name)[0]
        assert stored["level"] == 0
        assert sol.results["unknowns"] == stored["unknowns"], "a different mesh than the stored one"
        for key in ("drag", "lift", "wall_force", "flow_rate", "u_mean_fluid", "K_fluid", "K_pd"):
            assert sol.results[key] == pytest.approx(stored[key], rel=1e-8, abs=1e-9), key


def test_coarsest_cell_physics(cell_level0):
    stokes, ns = cell_level0
    r = stokes.results
    # body force on the fluid = drag on the cylinder + shear on the walls (exact for Stokes)
    assert abs(r["balance_residual"]) < 1e-12
    # the cell is fore-aft and up-down symmetric: no lift beyond the mesh's asymmetry
    assert abs(r["lift"]) < 2e-5 * r["drag"]
    # the stress integrated on the cylinder agrees with the variational drag
    assert rel(r["drag_surface"], r["drag"]) < 2e-3
    # <u> over the fluid and Q/H differ by the cylinder's blockage: <u> = (Q/H) L H / A_fluid
    # (to the discrete divergence error: Taylor-Hood conserves mass only weakly)
    assert r["u_mean_fluid"] == pytest.approx(r["u_bulk"] * 6.0 * 4.0 / r["fluid_area"], rel=1e-4)
    assert r["fluid_area"] == pytest.approx(24.0 - math.pi, rel=1e-5)
    # King & Lind: g = 300 m/s^2 gives <u> ~ 1 m/s and Re = 2.4e-2
    assert r["u_mean_fluid"] == pytest.approx(1.0, abs=0.03)
    assert r["Re"] == pytest.approx(2.4e-2, abs=0.1e-2)
    # inertia at this Re changes K by less than 1e-5 (it is O(Re^2): fore-aft symmetry)
    assert rel(ns.results["K_fluid"], r["K_fluid"]) < 1e-5
    assert ns.results["iterations"] <= 8
    # the coarsest level is within its stored error of the extrapolated value
    stored = table("convergence_stokes.csv")[0]
    for key in ("drag", "u_mean_fluid", "K_fluid"):
        extrap = r[key] / (1.0 + stored[f"error_{key}"])
        assert rel(r[key], extrap) < 1.5e-3, key


def test_stored_cell_convergence_is_fourth_order():
    for name in ("convergence_stokes.csv", "convergence_navier_stokes.csv"):
        rows = table(name)
        assert len(rows) >= 5
        for key in ("drag", "flow_rate", "u_mean_fluid", "K_fluid"):
            errors = [abs(r[f"error_{key}"]) for r in rows[:-1]]
            assert all(b < a for a, b in zip(errors, errors[1:])), (name, key, errors)
            orders = [r[f"order_{key}"] for r in rows[2:]]
            assert all(3.4 < p < 4.6 for p in orders), (name, key, orders)
        # converged to 0.1 % from level 1 on, to 1e-6 at the finest level
        assert fem.converged_level(rows) <= 1
        assert abs(rows[-2]["error_K_fluid"]) < 1e-6
        # exact for Stokes; with inertia the convective term's momentum is conserved only to
        # the discrete divergence error
        tol = 1e-12 if "stokes" in name and "navier" not in name else 1e-6
        assert all(abs(r["balance_residual"]) < tol for r in rows), name


def test_stored_cell_results_and_centreline():
    res = {(r["model"], r["quantity"]): r for r in table("cell_results.csv")}
    drag, u = res[("stokes", "drag")], res[("stokes", "u_mean_fluid")]
    assert drag["uncertainty"] < 1e-8 * drag["value"] * 1e3  # < 1e-5 relative
    assert res[("stokes", "K_fluid")]["value"] == pytest.approx(
        drag["value"] / (41.66 * u["value"])
    )
    body, wall = res[("stokes", "body_force")]["value"], res[("stokes", "wall_force")]["value"]
    assert body == pytest.approx(drag["value"] + wall, rel=1e-10)
    prof = table("centreline.csv")
    assert len(prof) == 200
    s = [p["s_over_R"] for p in prof]
    uu = [p["u_over_mean"] for p in prof]
    assert s[0] == 0.0 and s[-1] == pytest.approx(4.0)
    assert uu[0] == 0.0 and uu[-1] == 0.0  # no slip at the rear and the front stagnation points
    # Stokes flow is fore-aft symmetric: u(s) = u(4R - s)
    assert max(abs(a - b) for a, b in zip(uu, reversed(uu))) < 1e-5
    assert max(uu) == pytest.approx(uu[100], rel=1e-3)
    assert 1.1 < max(uu) < 1.25


def test_confined_benchmark_and_long_cells():
    lit = table("literature.csv")
    k0 = [r for r in lit if r["Wi"] == 0.0 and r["quantity"] == "K"]
    assert k0, "the Newtonian benchmark value is missing from literature.csv"
    ch = table("convergence_channel.csv")
    errors = [abs(r["error_drag"]) for r in ch[:-1]]
    assert all(b < a for a, b in zip(errors, errors[1:]))
    assert all(3.4 < r["order_drag"] < 4.6 for r in ch[2:])
    for r in k0:  # the published 132.36 is matched to its last printed digit
        assert rel(ch[-1]["K_pd"], r["value"]) < 0.5 * 10 ** -r["decimals"] / r["value"] + 1e-6
    cells = table("long_cells.csv")
    assert [c["L_over_R"] for c in cells] == [6, 12, 24, 48, 96]
    # with the pressure-driven drag and the bulk velocity the 6R cell is already within 0.02 %
    assert all(abs(c["rel_diff_K_pd"]) < 2e-4 for c in cells)
    assert all(abs(c["rel_diff_K_pd"]) < 1e-6 for c in cells[1:])
    # the body-force drag over <u> approaches 132.36 - 12 pi R^2 / H^2 only as 1/L
    kf = [c["K_fluid"] for c in cells]
    assert all(b > a for a, b in zip(kf, kf[1:]))
    assert kf[-1] < cells[-1]["K_channel"] - 12 * math.pi / 16


def test_channel_coarsest_level():
    (s,) = fem.solve(fem.channel_geometry(), fem.CHANNEL_PHYSICS, 0, h_max=2.0)
    stored = table("convergence_channel.csv")[0]
    assert s.results["unknowns"] == stored["unknowns"]
    assert s.results["drag"] == pytest.approx(stored["drag"], rel=1e-8)
    assert s.results["flow_rate"] == pytest.approx(4.0, rel=1e-12)


def test_oldroyd_b_coarsest_level_and_stored_convergence():
    """The Oldroyd-B (beta = 0.59) reference: level 0 at lam = 0.2 s re-solved (~5 s), and the
    stored levels converging."""
    import oldroyd_b_fem as ob

    kl = fem.KL
    model = ob.OldroydB(
        fem.kl_geometry(), kl["rho"], 0.59 * kl["eta0"], 0.41 * kl["eta0"], kl["g"], 0
    )
    r = ob.sweep(model, targets=(0.2,))[0.2][0]
    rows = table("oldroyd_b_convergence.csv")
    stored = [row for row in rows if row["lam"] == 0.2 and row["level"] == 0][0]
    assert len(model.free) == stored["unknowns"], "a different mesh than the stored one"
    for key in ("drag", "flow_rate", "u_mean_fluid", "K_fluid"):
        assert r[key] == pytest.approx(stored[key], rel=1e-7), key
    # elasticity reduces the drag at fixed body force (Wi = 0.21): K below the Newtonian 92.94
    newtonian = table("convergence_stokes.csv")[0]
    assert r["K_fluid"] < newtonian["K_fluid"] - 2.0
    assert r["Wi"] == pytest.approx(0.2 * r["u_mean_fluid"], rel=1e-12)
    # the stored levels converge monotonically, at an order of at least 2
    sub = [row for row in rows if row["lam"] == 0.2]
    assert len(sub) >= 4
    errors = [abs(row["error_K_fluid"]) for row in sub[:-1]]
    assert all(b < a for a, b in zip(errors, errors[1:]))
    assert all(row["order_K_fluid"] > 2.0 for row in sub[2:])
    assert abs(sub[-2]["error_K_fluid"]) < 1e-4
