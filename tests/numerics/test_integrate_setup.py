"""What ``integrate`` and ``Propagator`` do once instead of every call (issue 15): the start
read and checked once per input (memoised by value and type), the drift evidence of C runs
from the compiled model."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.inputs import Precision
from chaplygin.numerics.integrators.base import _drift
from reference import REFERENCE_PARAMS, REFERENCE_Y0

# the module (its name is shadowed by the function in chaplygin.numerics)
integrate_module = importlib.import_module("chaplygin.numerics.integrate")
BALL = "chaplygin_ball"
EPS = float(np.finfo(float).eps)


def _count_calls(monkeypatch, name: str) -> list:
    """integrate's module function ``name`` wrapped to record its calls (returned)."""
    calls = []
    real = getattr(integrate_module, name)

    def wrapped(*args, **kw):
        calls.append(args)
        return real(*args, **kw)

    monkeypatch.setattr(integrate_module, name, wrapped)
    return calls


@pytest.fixture
def counted(monkeypatch):
    """pack_state wrapped to count the reads (the memo emptied first)."""
    calls = _count_calls(monkeypatch, "pack_state")
    monkeypatch.setattr(integrate_module, "_STARTS", {})
    monkeypatch.setattr(integrate_module, "_PREPARED", {})
    return calls


def test_a_call_made_again_is_prepared_once_and_gives_the_same_bits(monkeypatch):
    """integrate called again with the same inputs skips reading and checking them and goes
    to its compiled loop (a session, as a Propagator's); the result is bit for bit the one
    the whole path gives (an integrator object as the method: never memoised)."""
    import threading

    from chaplygin.numerics.integrators import get_integrator

    monkeypatch.setattr(integrate_module, "_PREPARED", {})
    monkeypatch.setattr(integrate_module, "_SESSIONS", threading.local())
    prepared = _count_calls(monkeypatch, "prepare_problem")

    def run(method="taylor", **kw):
        return integrate(BALL, REFERENCE_Y0, 7.3, REFERENCE_PARAMS, method=method, rtol=1e-11,
                         atol=1e-11, t_eval=[0.0, 2.9, 7.3], **kw)

    first, again, third = run(), run(), run()
    assert len(prepared) == 1 and len(integrate_module._SESSIONS.by_key) == 1
    whole = run(method=get_integrator("taylor"))
    assert len(prepared) == 2 and len(integrate_module._SESSIONS.by_key) == 1
    for r in (first, again, third):
        assert r.success and np.array_equal(r.y, whole.y) and np.array_equal(r.t, whole.t)
        assert r.drift == whole.drift and r.nsteps == whole.nsteps
    # a step limit, events or the default outputs: the whole path, prepared once
    for _ in range(2):
        limited = run(max_steps=10**6)
    assert len(prepared) == 3 and np.array_equal(limited.y, whole.y)
    assert len(integrate_module._SESSIONS.by_key) == 1
    # another working precision of mpmath is another call
    import mpmath

    with mpmath.workdps(40):
        run()
    assert len(prepared) == 4


def test_the_same_start_is_read_once(counted):
    code, prec = load_model_code(BALL), Precision("double")
    y0 = {"M": ("0.7", "-0.4", "0.5"), "gamma": ("0.2", "0.3", "sqrt(0.87)")}
    p1, s1 = integrate_module._read_start(code, y0, REFERENCE_PARAMS, prec, 0.0)
    p2, s2 = integrate_module._read_start(code, dict(y0), REFERENCE_PARAMS, prec, 0.0)
    assert len(counted) == 1 and s1 == s2 and p1 == p2
    s2[0] = 99.0  # a caller's copy: the memo keeps its own
    _, s3 = integrate_module._read_start(code, y0, REFERENCE_PARAMS, prec, 0.0)
    assert s3 == s1 and len(counted) == 1
    # another value, another type of the same value, another precision: read again
    integrate_module._read_start(code, {**y0, "M": ("0.7", "-0.4", "0.51")}, REFERENCE_PARAMS,
                                 prec, 0.0)
    integrate_module._read_start(code, {**y0, "M": (0.7, -0.4, 0.5)}, REFERENCE_PARAMS, prec, 0.0)
    integrate_module._read_start(code, y0, REFERENCE_PARAMS, Precision("quad"), 0.0)
    assert len(counted) == 4


def test_a_mutated_input_is_read_anew(counted):
    y0 = {"M": [0.7, -0.4, 0.5], "gamma": [0.2, 0.3, "sqrt(0.87)"]}
    a = integrate(BALL, y0, 1.0, REFERENCE_PARAMS, method="taylor", rtol=1e-12, atol=1e-12)
    y0["M"][2] = 0.25
    b = integrate(BALL, y0, 1.0, REFERENCE_PARAMS, method="taylor", rtol=1e-12, atol=1e-12)
    assert len(counted) == 2 and b.y[2, 0] == 0.25 and a.y[2, 0] == 0.5


def test_refused_inputs_are_refused_every_time(counted):
    bad = {"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, 0.3)}
    for _ in range(2):
        with pytest.raises(UserInputError, match="unit vector"):
            integrate(BALL, bad, 1.0, REFERENCE_PARAMS, method="taylor")
    assert len(counted) == 2 and integrate_module._STARTS == {}


def test_keys_keep_types_apart():
    key = integrate_module._input_key
    assert key(True) is None and key(float("nan")) is None and key(object()) is None
    assert key(1) != key(1.0) and key("1") != key(1)
    assert key([1.0, 2.0]) == key(np.array([1.0, 2.0])) == key((1.0, 2.0))
    assert key([1.0, float("nan")]) is None and key([[1.0], [float("nan")]]) is None
    assert key([1.0, "2.0"]) != key([1.0, 2.0]) != key([1.0, 2]) and key([1.0, True]) is None
    assert key({"a": [1.0]}) == key({"a": (1.0,)}) and key({1: 2.0}) is None


def test_compiled_evidence_agrees_with_the_numpy_module():
    """A C run's drift from the compiled integrals against the same outputs' drift from the
    generated numpy module: the integrals are the same expressions, each evaluated with a
    relative error of a few eps, so the relative drifts differ by at most 8 eps."""
    code = load_model_code(BALL)
    r = integrate(BALL, REFERENCE_Y0, 30.0, REFERENCE_PARAMS, method="taylor", rtol=1e-9,
                  atol=1e-9, t_eval=[0, 11.0, 30.0])
    assert r.backend == "c-double" and r.success
    prec = Precision("double")
    numpy_drift, absolute = _drift(code, r.t, r.y, list(r.params.values()), prec)
    assert absolute == r.drift_absolute
    for name, value in r.drift.items():
        assert abs(value - numpy_drift[name]) <= 8 * EPS, (name, value, numpy_drift[name])
    assert max(r.drift.values()) > 100 * EPS  # rtol 1e-9 drifts: not a comparison of zeros


def test_compiled_evidence_sees_a_value_that_is_not_finite():
    code = load_model_code(BALL)
    p = [1.0, 2.0, 3.0, 1.0]  # I1, I2, I3, D
    y = np.array([[0.7, 0.7], [-0.4, math.nan], [0.5, 0.5], [0.2, 0.2], [0.3, 0.3],
                  [0.87**0.5, 0.87**0.5]])
    prec = Precision("double")
    drift, _ = _drift(code, [0.0, 1.0], y, p, prec, code.compiled())
    ref, _ = _drift(code, [0.0, 1.0], y, p, prec)
    assert all(math.isnan(drift[k]) == math.isnan(ref[k]) for k in ref)
    assert any(math.isnan(v) for v in drift.values())



def test_the_memo_is_bounded(counted, monkeypatch):
    monkeypatch.setattr(integrate_module, "_STARTS_MAX", 3)
    code, prec = load_model_code(BALL), Precision("double")
    starts = [{"M": (0.7, -0.4, 0.1 * k), "gamma": (0.2, 0.3, "sqrt(0.87)")} for k in range(5)]
    for y0 in starts:
        integrate_module._read_start(code, y0, REFERENCE_PARAMS, prec, 0.0)
    assert len(integrate_module._STARTS) == 3 and len(counted) == 5
    integrate_module._read_start(code, starts[-1], REFERENCE_PARAMS, prec, 0.0)  # kept
    integrate_module._read_start(code, starts[0], REFERENCE_PARAMS, prec, 0.0)  # evicted
    assert len(counted) == 6


def test_the_compiled_run_of_a_problem_is_kept_per_thread(monkeypatch):
    """integrate called again with the same model, parameters and control reuses its
    compiled run (pointers and buffers), gets the same bits and a result of its own; other
    parameters or another thread get another run."""
    import threading

    c_run = importlib.import_module("chaplygin.numerics.taylor.c_run")
    monkeypatch.setattr(c_run, "_RUNS", threading.local())
    made = []
    real = c_run.CompiledTaylorRun

    class Counted(real):
        def __init__(self, *args, **kw):
            made.append(args)
            super().__init__(*args, **kw)

    monkeypatch.setattr(c_run, "CompiledTaylorRun", Counted)
    # the sessions of calls made again (TaylorMethod.session) take it from the package
    monkeypatch.setattr(importlib.import_module("chaplygin.numerics.taylor"),
                        "CompiledTaylorRun", Counted)

    def run(params=REFERENCE_PARAMS, y0=REFERENCE_Y0):
        return integrate(BALL, y0, 3.7, params, method="taylor", rtol=1e-11, atol=1e-11,
                         backend="c", t_eval=[0.0, 1.3, 3.7])

    monkeypatch.setattr(integrate_module, "_PREPARED", {})
    monkeypatch.setattr(integrate_module, "_SESSIONS", threading.local())
    a = run()
    b = run()  # the call made again: its own session (integrate_module._session)
    assert len(made) == 2 and a.success and b.success
    assert np.array_equal(a.y, b.y) and a.y is not b.y
    b.y[:] = 0.0  # a result of its own: the first is untouched, the next is fresh
    assert np.array_equal(run().y, a.y) and not np.array_equal(a.y, b.y)
    assert len(made) == 2
    # another start, same problem: the same run; other parameters: another one
    other = {**REFERENCE_Y0, "M": (0.6, -0.4, 0.5)}
    c = run(y0=other)
    assert len(made) == 2 and not np.array_equal(c.y, a.y)
    run(params={**REFERENCE_PARAMS, "D": 1.3})
    assert len(made) == 3
    # another thread makes its own (a run's buffers are in use while it runs)
    box = []
    worker = threading.Thread(target=lambda: box.append(run()))
    worker.start()
    worker.join()
    assert len(made) == 4 and np.array_equal(box[0].y, a.y)


@pytest.mark.parametrize("size", [3, 12, 65, 400])
def test_the_finiteness_check_sees_nan_and_infinity(size):
    """_all_finite (the check behind status -1): on Python floats for a few outputs, numpy
    for many; both see a NaN or an infinity anywhere."""
    from chaplygin.numerics.integrators.base import _all_finite

    y = np.linspace(-1.0, 1.0, size).reshape(-1, 1) if size % 2 else np.ones((2, size // 2))
    assert _all_finite(y)
    for bad in (math.nan, math.inf, -math.inf):
        z = y.copy()
        z.flat[size // 3] = bad
        assert not _all_finite(z)


def test_a_kept_run_does_not_hold_a_long_output():
    """The compiled run kept between calls keeps the buffers of a few outputs, not those of
    a long output (memory returned after the call); both give the same bits as a new run."""
    taylor = importlib.import_module("chaplygin.numerics.taylor")
    code = load_model_code(BALL)
    prec = Precision("double")
    p, y = integrate_module._read_start(code, REFERENCE_Y0, REFERENCE_PARAMS, prec, 0.0)
    lib = taylor.load_taylor_library(code, "double", taylor.run_orders(1e-10, 1e-10))
    run = taylor.CompiledTaylorRun(lib, p, 1e-10, 1e-10, None, None, 10**6)
    short = run.run(y, (0.0, 5.0), [0.0, 2.5, 5.0])
    long_eval = list(np.linspace(0.0, 5.0, taylor._KEPT_OUTPUTS_MAX + 1))
    long = run.run(y, (0.0, 5.0), long_eval)
    assert set(run._outputs) == {3}
    fresh = taylor.CompiledTaylorRun(lib, p, 1e-10, 1e-10, None, None, 10**6)
    assert np.array_equal(fresh.run(y, (0.0, 5.0), long_eval).y, long.y)
    assert np.array_equal(fresh.run(y, (0.0, 5.0), [0.0, 2.5, 5.0]).y, short.y)
