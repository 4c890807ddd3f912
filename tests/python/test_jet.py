"""The jet scene through the FMU (issue 13): `jet_velocity` is an input a pump or valve model
drives; the inlet follows a step change of it, and the mass that enters is rho U0 D exactly to
within one particle row, under every scheme family (weakly compressible and incompressible).
The jet's physics (momentum balance, buckling) is tested in tests/jet.rs on the library."""

import pytest

from viscosph_fmu import Slave

D, RHO, N = 0.006, 1023.0, 4
DX = D / N
ROW = RHO * D * DX  # mass of one row of particles [kg/m]


def test_jet_velocity_is_a_continuous_input_with_a_start_value(md):
    v = next(v for v in md.modelVariables if v.name == "jet_velocity")
    assert (v.causality, v.variability, v.type, v.unit) == ("input", "continuous", "Real", "m/s")
    assert float(v.start) == 0.2


@pytest.mark.parametrize("scheme", ["wcsph", "isph"])
def test_the_inlet_follows_steps_of_jet_velocity(unzipdir, scheme):
    s = Slave(unzipdir)
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.setString([s.vr["scene_name"]], ["jet"])
    s.fmu.setString([s.vr["scheme_name"]], [scheme])
    s.fmu.setString([s.vr["rheology_name"]], ["newtonian"])
    # The pump's schedule below reaches 0.4 m/s: the run is set up for it (max_jet_velocity).
    s.fmu.setReal([s.vr[k] for k in ["density", "viscosity", "jet_width", "nozzle_height",
                                     "max_jet_velocity"]],
                  [RHO, 8.8, D, 4 * D, 0.4])
    s.fmu.setInteger([s.vr["particles_per_diameter"], s.vr["threads"]], [N, 1])
    s.fmu.enterInitializationMode()
    s.fmu.exitInitializationMode()
    vr = s.vr["jet_velocity"]

    def injected():
        return s.fmu.getReal([s.vr["injected_mass"]])[0]

    def count():
        return s.fmu.getReal([s.vr["particle_count"]])[0]

    n0 = count()
    # A pump's schedule: 0.2 m/s, then twice as fast, then the valve closes.
    expected = 0.0
    for u, t_end in [(0.2, 0.05), (0.4, 0.1), (0.0, 0.14)]:
        s.fmu.setReal([vr], [u])
        assert s.fmu.getReal([vr])[0] == u
        t0 = s.t
        s.step_to(t_end, 0.005)
        expected += RHO * u * D * (t_end - t0)
        # Within one row of rho U0 D t (plus what entered during the last internal step).
        # Rows are emitted before a step, so the count lags by what entered during the last
        # one: U0 dt / dx, 0.05 rows under WCSPH; ISPH's steps are up to 0.2 h / U0, 0.35 rows.
        lag = 1.05 if scheme == "wcsph" else 1.4
        assert injected() == pytest.approx(expected, abs=lag * ROW), (t_end, injected(), expected)
        # Nothing lost: the particle count is the initial nozzle plus what entered.
        assert count() == pytest.approx(n0 + injected() / (RHO * DX * DX), abs=1e-6)
    # The valve is closed: nothing more enters.
    closed = injected()
    s.step_to(0.16, 0.005)
    assert injected() == closed
    s.free()
