"""The Taylor integrator in vector lanes (derive/templates/taylor_lanes.c,
chaplygin_taylor_run_lanes): every orbit's outputs, final state, time reached, steps, orders
and status are those of the one-orbit compiled loop that integrate() runs (CompiledTaylorRun:
chaplygin_taylor_run with the coefficients written out for the run's orders), bit for bit, for
1, 4 and 8 lanes (the default: 8 with AVX-512, else 4), with orbits that end at different times
(one backward), parameters per orbit, lanes at different orders (absolute and relative control
in the same vector), an orbit that becomes non-finite and one that runs out of steps, and a
number of orbits that is not a multiple of the lanes; gcc and clang give the same bytes."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.integrators.c_batch import _buf, taylor_batch_library
from chaplygin.numerics.taylor import CompiledTaylorRun, load_taylor_library, run_orders

CODE = load_model_code("chaplygin_ball")
RTOL, ATOL, MAX_STEPS = 1e-13, 1e-11, 400


def _orbits(count: int = 11) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Spans, states, parameters and output times (11 per orbit, inside its span)."""
    rng = np.random.default_rng(26)
    y0, params, t01, t_eval = [], [], [], []
    for j in range(count):
        g = rng.normal(size=3)
        g /= np.linalg.norm(g)
        m = rng.uniform(-0.9, 0.9, 3) * (300.0 if j == 2 else 1.0)  # relative control
        y0.append([*m, *g])
        params.append([*rng.uniform(1.0, 3.0, 3), rng.uniform(0.5, 1.5)])
        t1 = -2.5 if j == 5 else rng.uniform(1.0, 6.0)
        t1 = 5000.0 if j == 7 else t1  # runs out of steps
        t01.append([0.0, t1])
        t_eval.append(np.linspace(0.0, t1, 11))
    y0[4][0] = np.nan  # non-finite from its first step
    return np.array(t01), np.array(y0), np.array(params), np.array(t_eval)


def _lanes(width: int | None, t01, y0, params, t_eval, written: bool = True, lib=None
           ) -> dict[str, np.ndarray]:  # fmt: skip
    if lib is None:
        lib = taylor_batch_library(CODE, width, run_orders(RTOL, ATOL) if written else ())
    count, m, n = len(y0), t_eval.shape[1], y0.shape[1]
    out = {"y_eval": np.full((count, m, n), np.nan), "y_end": np.empty((count, n)),
           "t_reached": np.empty(count), "stats": np.zeros((count, 4), dtype=np.int64),
           "status": np.zeros(count, dtype=np.int32)}  # fmt: skip
    ctrl = np.array([RTOL, ATOL, 0.0])
    rc = lib.chaplygin_taylor_run_lanes(
        count, _buf(t01), _buf(y0), _buf(params), _buf(ctrl), 0, m, _buf(t_eval), m,
        _buf(out["y_eval"]), _buf(out["y_end"]), _buf(out["t_reached"]), MAX_STEPS,
        _buf(out["stats"], "long[]"), _buf(out["status"], "int[]"),
    )  # fmt: skip
    assert rc == 0
    return out


def _same(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize(("width", "written"), [(1, False), (None, False), (None, True),
                                               (4, True)])  # fmt: skip
def test_every_lane_is_the_one_orbit_loop_bit_for_bit(width, written):
    """The lanes' coefficients in the loop over the orders or written out for the run's
    orders (14 and 16)."""
    t01, y0, params, t_eval = _orbits()
    got = _lanes(width, t01, y0, params, t_eval, written)
    clib = load_taylor_library(CODE, "double", run_orders(RTOL, ATOL))
    for j in range(len(y0)):
        run = CompiledTaylorRun(clib, list(params[j]), RTOL, ATOL, None, None, MAX_STEPS)
        ref = run.run(list(y0[j]), tuple(t01[j]), list(t_eval[j]))
        done = len(ref.t)
        assert got["status"][j] == ref.status, j
        assert got["stats"][j].tolist() == [ref.nsteps, ref.order_max, ref.order_min, done]
        assert _same(got["y_eval"][j, :done].T, ref.y), j
        assert np.isnan(got["y_eval"][j, done:]).all()
        assert _same(got["y_end"][j], run.y_end) and got["t_reached"][j] == run.t_reached[0]
    status = got["status"].tolist()
    assert status[4] == -1 and status[7] == -2 and status.count(0) == len(y0) - 2
    assert got["t_reached"][5] == -2.5  # the backward orbit
    orders = {(int(s[1]), int(s[2])) for s in got["stats"][got["status"] == 0]}
    assert (16, 16) in orders and (14, 14) in orders  # relative and absolute lanes


def test_the_numbers_do_not_depend_on_the_lanes_or_the_chunking():
    """The default lanes (8 with AVX-512, else 4), 4 and 8, the loop or the written-out
    coefficients, and the orbits in one call or in calls of 3 (the chunking of the threads):
    the same bytes."""
    t01, y0, params, t_eval = _orbits()
    whole = _lanes(None, t01, y0, params, t_eval)
    loop = _lanes(None, t01, y0, params, t_eval, written=False)
    wide, narrow = _lanes(8, t01, y0, params, t_eval), _lanes(4, t01, y0, params, t_eval)
    parts = [_lanes(None, t01[a:a + 3], y0[a:a + 3], params[a:a + 3], t_eval[a:a + 3])
             for a in range(0, len(y0), 3)]  # fmt: skip
    for key, value in whole.items():
        assert _same(value, wide[key]) and _same(value, loop[key]), key
        assert _same(value, narrow[key]), key
        assert _same(value, np.concatenate([p[key] for p in parts])), key


@pytest.mark.parametrize("case", ["forced", "pow"])
def test_lanes_with_functions_of_time_and_powers(case, monkeypatch):
    """The other operations of the Taylor programs in lanes: BM20's forced ball (sin and cos
    of the time, quotients by constants) and the ball on an ellipsoid (rational powers),
    through integrate_many (in lanes: checked) against integrate(), bit for bit."""
    from chaplygin.numerics import ensemble
    from chaplygin.numerics.integrate import integrate

    used = []
    lanes = ensemble.run_lanes
    monkeypatch.setattr(ensemble, "run_lanes", lambda *a: used.append(1) or lanes(*a))
    if case == "forced":
        system = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
        params = [4.0, 3.0, 2.0, 4.385, 0.0, 2.0, -6.0, -3.0, -9.0, 1.07]
        g = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
        states = [[0.5 + 0.1 * j, 1.0 - 0.05 * j, 1.0, *g] for j in range(6)]
    else:
        system, params = "ball_on_surface", {"m": 1, "m_e": 0.4, "R": 0.3, "b": (1, 2, 3)}
        states = [{"omega": (0.7 - 0.1 * j, -0.4, 0.5 + 0.05 * j), "x": (1, 0, 0)}
                  for j in range(6)]  # fmt: skip
    r = ensemble.integrate_many(system, states, 3.7, params, rtol=1e-12, atol=1e-12)
    assert used == [1] and r.success.all()
    for j, s in enumerate(states):
        one = integrate(system, s, 3.7, params, rtol=1e-12, atol=1e-12)
        assert _same(r.results[j].y, one.y) and r.results[j].nsteps == one.nsteps
        assert r.results[j].message == one.message


@pytest.mark.parametrize("options", [{"order": 10}, {"order": 12, "step": 0.05}, {"step": 0.1}])
def test_lanes_with_a_fixed_order_or_step_backward(options, monkeypatch):
    """taylor_options (a fixed order, a fixed step, both) on a backward span with output
    times: integrate_many's orbits in lanes are integrate()'s, bit for bit."""
    from chaplygin.numerics import ensemble
    from chaplygin.numerics.integrate import integrate

    used = []
    lanes = ensemble.run_lanes
    monkeypatch.setattr(ensemble, "run_lanes", lambda *a: used.append(1) or lanes(*a))
    rng = np.random.default_rng(2)
    states = [{"M": tuple(rng.uniform(-0.9, 0.9, 3)), "gamma": (0.6, 0.0, 0.8)} for _ in range(5)]
    params = {"I": ("1.13", "2.07", "3.31"), "D": "0.93"}
    kw = {"rtol": 1e-11, "atol": 1e-11, "taylor_options": options, "t_eval": [0, -1, -2.5, -3]}
    r = ensemble.integrate_many("chaplygin_ball", states, (0.0, -3.0), params, **kw)
    assert used == [1] and r.success.all() and r.y.shape == (5, 6, 4)
    for j, s in enumerate(states):
        one = integrate("chaplygin_ball", s, (0.0, -3.0), params, **kw)
        assert _same(r.results[j].y, one.y) and r.results[j].nsteps == one.nsteps


@pytest.mark.skipif(shutil.which("gcc") is None or shutil.which("clang") is None,
                    reason="needs gcc and clang")  # fmt: skip
def test_gcc_and_clang_lanes_give_the_same_bytes():
    """The lanes library built by gcc and by clang (the batch library's flags, -O3
    -march=native, and -O2): the same bytes for every orbit."""
    from chaplygin.derive.emit.c_sources import taylor_batch_source
    from chaplygin.numerics.ccompile import compile_c
    from chaplygin.numerics.integrators.c_batch import NATIVE_CFLAGS, _ffi

    t01, y0, params, t_eval = _orbits()
    source = taylor_batch_source(CODE.taylor_c_source, CODE.taylor_program, run_orders(RTOL, ATOL))
    outs = []
    for compiler in ("gcc", "clang"):
        for flags in (NATIVE_CFLAGS, ()):
            lib = _ffi.dlopen(str(compile_c(source, compiler=compiler, cflags=flags)))
            outs.append(_lanes(None, t01, y0, params, t_eval, lib=lib))
    for other in outs[1:]:
        for key, value in outs[0].items():
            assert _same(value, other[key]), key
