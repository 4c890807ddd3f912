"""Refusals: bad parameter values, calls out of order, NULL pointers, unknown value references,
Model-Exchange calls, unknown log categories, and a numerical breakdown (fmi2Discard). None of
them may crash the process, and each must say why through the logger."""

import ctypes
import math
import re

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from viscosph_fmu import DISCARD, ERROR, Log, Slave, simulate

BAD_VALUES = [
    # (start values, fragments the log message must contain)
    ({"drop_diameter": -0.01}, ["drop_diameter", "-0.01", "(0, 10]"]),
    ({"plate_inclination": 90.0}, ["plate_inclination", "90", "[0, 90)"]),
    ({"plate_inclination": -5.0}, ["plate_inclination", "-5", "[0, 90)"]),
    ({"viscosity_ratio": 1.5}, ["viscosity_ratio", "1.5", "[0, 1]"]),
    ({"viscosity_ratio": math.nan}, ["viscosity_ratio", "NaN", "[0, 1]"]),
    ({"particles_per_diameter": 2}, ["particles_per_diameter", "2", "[4, 4000]"]),
    ({"rheology": 42}, ["rheology", "42", "oldroyd_b"]),
    # accepted one by one, refused together at fmi2ExitInitializationMode
    ({"particles_per_diameter": 4000}, ["particles_per_diameter", "4000", "memory"]),
    ({"initial_drop_height": 0.01}, ["initial_drop_height", "0.01", "plate"]),
]


@pytest.mark.parametrize("start_values,fragments", BAD_VALUES,
                         ids=[next(iter(sv)) + "=" + str(next(iter(sv.values())))
                              for sv, _ in BAD_VALUES])
def test_bad_parameters_raise_with_a_message_naming_variable_value_and_range(
        fmu, start_values, fragments):
    log = Log()
    with pytest.raises(FMICallException) as e:
        simulate(fmu, start_values, stop_time=0.01, logger=log)
    assert e.value.status == ERROR
    errors = log.messages(ERROR)
    assert errors, "the refusal is logged"
    assert all(f in errors[0] for f in fragments), errors[0]
    assert log.categories() == {"logStatusError"}


def test_the_process_survives_refusals_and_runs_afterwards(fmu):
    for start_values, _ in BAD_VALUES[:3]:
        with pytest.raises(FMICallException):
            simulate(fmu, start_values, stop_time=0.01)
    result = simulate(fmu, {"particles_per_diameter": 8}, stop_time=0.01)
    assert np.isfinite(result["drop_width"]).all()


def test_do_step_before_initialization_is_refused_not_a_crash(unzipdir):
    s = Slave(unzipdir)
    with pytest.raises(FMICallException) as e:
        s.fmu.doStep(0.0, 1e-3)
    assert e.value.status == ERROR
    msg = s.log.messages(ERROR)[-1]
    assert "fmi2DoStep" in msg and "illegal call sequence" in msg and "Instantiated" in msg
    # the instance is in the error state: parameters are refused until fmi2Reset
    with pytest.raises(FMICallException):
        s.fmu.setReal([s.vr["drop_diameter"]], [0.03])
    s.fmu.reset()
    s.initialize(integers={"particles_per_diameter": 8})
    assert s.step_to(0.004, 2e-3).shape[0] == 2
    s.free()


def test_steps_that_do_not_continue_or_are_not_positive_are_refused(unzipdir):
    for t, h in [(0.001, 1e-3), (0.0, 0.0), (0.0, -1e-3), (0.0, math.nan)]:
        s = Slave(unzipdir).initialize(integers={"particles_per_diameter": 8})
        with pytest.raises(FMICallException):
            s.fmu.doStep(t, h)
        assert "fmi2DoStep" in s.log.messages(ERROR)[-1]
        s.free()


def test_parameters_are_fixed_after_initialization(unzipdir):
    s = Slave(unzipdir).initialize(integers={"particles_per_diameter": 8})
    with pytest.raises(FMICallException):
        s.fmu.setReal([s.vr["viscosity"]], [5.0])
    assert "fixed" in s.log.messages(ERROR)[-1]
    s.free()


def test_null_pointers_unknown_references_and_wrong_types_are_refused(unzipdir):
    s = Slave(unzipdir)
    s.fmu.setupExperiment(startTime=0.0)
    s.fmu.enterInitializationMode()
    raw = s.fmu.dll
    c = s.fmu.component
    raw.fmi2GetReal.restype = ctypes.c_int
    assert raw.fmi2GetReal(c, None, ctypes.c_size_t(2), None) == ERROR
    assert "must not be NULL" in s.log.messages(ERROR)[-1]
    s.fmu.reset()
    s.fmu.setupExperiment(startTime=0.0)
    with pytest.raises(FMICallException):
        s.fmu.setReal([999999], [1.0])
    assert "unknown valueReference 999999" in s.log.messages(ERROR)[-1]
    s.fmu.reset()
    with pytest.raises(FMICallException):
        s.fmu.setReal([s.vr["particles_per_diameter"]], [12.0])
    assert "fmi2SetInteger" in s.log.messages(ERROR)[-1]
    s.fmu.reset()
    with pytest.raises(FMICallException):
        s.fmu.setReal([s.vr["drop_width"]], [1.0])
    assert "output" in s.log.messages(ERROR)[-1]
    s.fmu.reset()
    # NULL instance: refused without a logger to tell
    assert raw.fmi2Reset(None) == ERROR
    s.free()


def test_model_exchange_and_unprovided_functions_answer_error(unzipdir):
    s = Slave(unzipdir)
    # fmpy declares no argument types for the Model-Exchange functions of a slave: pass the
    # instance as a pointer explicitly (a bare int would be truncated to 32 bits).
    raw, c = s.fmu.dll, ctypes.c_void_p(s.fmu.component)
    for name, args in [("fmi2SetTime", (ctypes.c_double(0.0),)),
                       ("fmi2EnterEventMode", ()),
                       ("fmi2GetDirectionalDerivative",
                        (None, ctypes.c_size_t(0), None, ctypes.c_size_t(0), None, None)),
                       ("fmi2CancelStep", ())]:
        f = getattr(raw, name)
        f.restype = ctypes.c_int
        assert f(c, *args) == ERROR, name
        assert name in s.log.messages(ERROR)[-1]
        s.fmu.reset()
    s.free()


def test_instantiate_refuses_a_wrong_guid(unzipdir):
    s = Slave(unzipdir)
    raw = s.fmu.dll
    raw.fmi2Instantiate.restype = ctypes.c_void_p
    comp = raw.fmi2Instantiate(b"x", 1, b"{not-the-guid}", b"", ctypes.byref(s.fmu.callbacks),
                               0, 0)
    assert comp is None
    assert "GUID" in s.log.messages(ERROR)[-1]
    comp = raw.fmi2Instantiate(b"me", 0, s.md.guid.encode(), b"", ctypes.byref(s.fmu.callbacks),
                               0, 0)
    assert comp is None, "Model Exchange"
    s.free()


def test_debug_logging_categories_are_honoured_and_messages_are_not_formats(unzipdir):
    s = Slave(unzipdir, debug=True)
    s.initialize(integers={"particles_per_diameter": 8})
    assert any(m.startswith("initialized") for m in s.log.messages()), "logEvents is on"
    s.fmu.setDebugLogging(False, [])
    s.fmu.setDebugLogging(True, ["logAll"])
    s.fmu.doStep(0.0, 1e-3)
    assert "logAll" in s.log.categories(), "the call trace"
    # a category that is not one of ours, with printf conversions in it: refused, and the
    # message carries it verbatim (the FMU passes text as the argument of "%s")
    with pytest.raises(FMICallException):
        s.fmu.setDebugLogging(True, ["log%s%n%d"])
    assert "'log%s%n%d'" in s.log.messages(ERROR)[-1]
    s.free()

    quiet = Slave(unzipdir, debug=False)
    quiet.initialize(integers={"particles_per_diameter": 8})
    quiet.step_to(0.002, 1e-3)
    assert quiet.log.records == [], "without loggingOn only errors and discards are reported"
    quiet.fmu.setDebugLogging(False, [])
    with pytest.raises(FMICallException):
        quiet.fmu.doStep(0.5, 1e-3)
    assert quiet.log.records == [], "logStatusError switched off as well"
    quiet.free()


# The words a discarded step uses for where the last good state is told and how to keep it:
# FMI 2.0's status query and FMUstate calls, FMI 3.0's out-argument of fmi3DoStep and FMUState calls.
DISCARD_WORDS = {"fmi2": ["fmi2LastSuccessfulTime", "fmi2GetFMUstate", "fmi2SetFMUstate"],
                 "fmi3": ["lastSuccessfulTime of fmi3DoStep", "fmi3GetFMUState", "fmi3SetFMUState"]}


def assert_in_words_of(api, msg):
    assert all(w in msg for w in DISCARD_WORDS[api]), msg
    assert api == "fmi2" or "fmi2" not in msg, msg


def test_a_numerical_breakdown_is_a_discard_with_time_and_cause(fmi):
    # A sound speed below the impact velocity: the weakly compressible fluid compresses by more
    # than 30 % and the health check stops the run.
    breakdown = {"sound_speed": 1.0, "particles_per_diameter": 12}
    log = Log()
    if fmi.api == "fmi2":
        result = simulate(fmi.fmu, breakdown, stop_time=0.1, logger=log)
        assert 0.0 < result["time"][-1] < 0.1, "fmpy stopped at the last successful time"
        assert all(np.isfinite(result[n]).all() for n in result.dtype.names)
    else:
        # fmpy's FMI 3.0 simulate_fmu does not handle fmi3Discard: it raises
        with pytest.raises(FMICallException) as e:
            simulate(fmi.fmu, breakdown, stop_time=0.1, logger=log)
        assert e.value.status == DISCARD
    msg = log.messages(DISCARD)[-1]
    assert f"{fmi.api}DoStep" in msg and "breakdown at t =" in msg and "density" in msg, msg
    assert_in_words_of(fmi.api, msg)
    stops = {"fmi2": "(fmi2Terminated)", "fmi3": "(terminateSimulation of fmi3DoStep)"}
    assert stops[fmi.api] in msg, msg
    t_end = float(re.search(r"the last good state, at t = (\S+) s", msg).group(1))
    assert 0.0 < t_end < 0.1
    if fmi.api == "fmi2":
        assert t_end == pytest.approx(result["time"][-1])

    s = Slave(fmi.unzipdir).initialize(reals={"sound_speed": 1.0},
                                       integers={"particles_per_diameter": 12})
    with pytest.raises(FMICallException) as e:
        s.step_to(0.1, 1e-3)
    assert e.value.status == DISCARD
    assert s.terminated()
    last = s.last_successful_time()
    assert last == pytest.approx(t_end)
    assert s.t <= last < s.t + 1e-3, "within the discarded communication step"
    assert np.isfinite(s.outputs()).all()
    state = s.get_state()  # the last good state, a completed step at `last`
    with pytest.raises(FMICallException):
        s.do_step(s.t, 1e-3)  # StepFailed: no further steps
    assert f"{fmi.api}DoStep" in s.log.messages(ERROR)[-1]
    s.set_state(state)
    if fmi.api == "fmi2":
        assert s.last_successful_time() == last
        assert not s.terminated()
    else:
        # FMI 3.0 has no status query: the independent variable tells where the state stands
        assert s.get_reals(["time"]) == [last]
    with pytest.raises(FMICallException) as e:
        s.do_step(last, 1e-3)  # stepping again from there: the same inputs break again
    assert e.value.status == DISCARD
    assert s.last_successful_time() == last and s.terminated()
    s.fmu.terminate()
    s.free()


def test_a_step_past_its_budget_is_a_discard_and_the_master_goes_on(fmi):
    s = Slave(fmi.unzipdir).initialize(integers={"particles_per_diameter": 12,
                                                 "max_steps_per_do_step": 5})
    t, discards = 0.0, 0
    while t < 0.004:
        try:
            s.do_step(t, 0.004 - t)
            t = 0.004
        except FMICallException as e:
            assert e.status == DISCARD
            msg = s.log.messages(DISCARD)[-1]
            assert "max_steps_per_do_step" in msg and "5 solver steps" in msg, msg
            assert f"{fmi.api}DoStep" in msg, msg
            assert_in_words_of(fmi.api, msg)
            assert not s.terminated()
            reached = s.last_successful_time()
            assert t < reached < 0.004
            s.set_state(s.get_state())
            t, discards = reached, discards + 1
    assert discards >= 2
    assert np.isfinite(s.outputs()).all()
    s.free()


def test_a_stop_time_of_too_many_steps_is_refused_with_the_estimate(fmi):
    log = Log()
    with pytest.raises(FMICallException) as e:
        simulate(fmi.fmu, {"particles_per_diameter": 8}, stop_time=1e9, step=1e8, logger=log)
    assert e.value.status == ERROR
    msg = log.messages(ERROR)[0]
    assert f"{fmi.api}ExitInitializationMode" in msg and "stopTime" in msg, msg
    assert "would take about" in msg and "more than 1e8" in msg, msg
    # where the stopTime came from: fmi2SetupExperiment, or fmi3EnterInitializationMode
    given = {"fmi2": "fmi2SetupExperiment", "fmi3": "fmi3EnterInitializationMode"}[fmi.api]
    assert given in msg and ("fmi2" in msg) == (fmi.api == "fmi2"), msg


def test_an_infinite_step_must_be_finite_and_later_calls_name_the_error_state(fmi):
    s = Slave(fmi.unzipdir).initialize(integers={"particles_per_diameter": 8})
    with pytest.raises(FMICallException) as e:
        s.do_step(0.0, math.inf)
    assert e.value.status == ERROR
    first = s.log.messages(ERROR)[-1]
    assert "must be finite" in first and f"{fmi.api}DoStep" in first, first
    with pytest.raises(FMICallException) as e:
        s.do_step(0.0, 1e-3)
    assert e.value.status == ERROR
    msg = s.log.messages(ERROR)[-1]
    assert "state Error" in msg and f"{fmi.api}DoStep returned {fmi.api}Error" in msg, msg
    assert "Terminated" not in msg, msg
    if fmi.api == "fmi3":
        assert "fmi2" not in msg, msg
    s.free()
