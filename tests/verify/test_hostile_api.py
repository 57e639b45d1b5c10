"""Hostile arguments to the public API raise only the documented exceptions (issue 11, item 6).

Each test takes a valid call of one public function, spoils one argument with a value drawn
from a pool of wrong types, wrong shapes, non-finite, non-physical or unknown values, and
asserts that the call raises :class:`UserInputError` (or another :class:`ChaplyginError`)
whose message names the spoiled argument -- never ZeroDivisionError, IndexError, KeyError,
TypeError, AttributeError, a silent result or a hang. Every value in a pool is wrong for the
argument it spoils, so a call that returns is a failure too. The calls are refused before
any integration, so the suite is fast.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from chaplygin.derive.errors import ChaplyginError, UserInputError
from chaplygin.derive.systems import build_model
from chaplygin.numerics.ball import frame_turn, quadratures, separatrix, stability
from chaplygin.numerics.ball.transformation import transformation_test
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.inputs import Precision
from chaplygin.numerics.integrate import integrate
from chaplygin.verify import plots
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

pytestmark = pytest.mark.quick

EXAMPLES = 100
SETTINGS = settings(
    max_examples=EXAMPLES,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=False,
)

NAN, INF = math.nan, math.inf

# ------------------------------------------------------------------------- value pools
#: not a real number at all
NOT_NUMBER = [
    None,
    "abc",
    "",
    "__import__('os')",
    {},
    {"a": 1},
    [1, 2],
    [[1.0]],
    np.zeros(2),
    np.zeros((2, 2)),
    object(),
    True,
    complex(1, 1),
    "sqrt(-1)",
]
NON_FINITE = [NAN, INF, -INF, np.float64("nan"), np.float64("-inf"), "nan", "1e999999"]
BAD_REAL = NOT_NUMBER + NON_FINITE
NOT_POSITIVE = [0, 0.0, -0.0, -1, -1e-300, np.float64(-2.5), -(10**400)]
BAD_POSITIVE = BAD_REAL + NOT_POSITIVE
#: wrong for a count (digits, nodes, samples)
BAD_COUNT = [None, "20", 1.5, 20.0, -1, 0, 10**9, True, NAN, [20], np.zeros(2)]
#: never a system, effect, method, engine or figure name
BAD_NAME = [None, 5, 2.5, "", "nope", "chaplygin_ball ", "CHAPLYGIN_BALL", {}, [None], "../x"]
#: not three finite positive numbers
BAD_VECTOR = [
    None,
    "abc",
    {},
    {"I": 1},
    5,
    np.float64(1),
    [1, 2],
    [1, 2, 3, 4],
    [[1, 2, 3]],
    np.ones((3, 3)),
    np.ones(2),
    np.ones((1, 3)),
    [1, None, 3],
    [1, "x", 3],
    [1, {}, 3],
    [NAN, 2, 3],
    [1, INF, 3],
    [1, 2, -INF],
]
BAD_INERTIA = BAD_VECTOR + [[-1, 2, 3], [0, 2, 3], [1, 2, -3], [1, -1e-300, 3]]
#: also wrong where the separatrix needs I2 strictly between I1 and I3
BAD_MIDDLE = BAD_INERTIA + [[1, 1, 1], [1, 2, 2], [2, 2, 3], [2, 1, 3], [1, 3, 2]]
#: also wrong for sphero-conical coordinates (I1 < I2 < I3)
BAD_ORDERED = BAD_MIDDLE + [[3, 2, 1]]
BAD_BRACKET = [None, "ab", (1,), (1, 2, 3), (NAN, 1), (0, 1), (-1, 1), ("x", 1), {}, 5]


def pool(values: list, *, floats: st.SearchStrategy | None = None) -> st.SearchStrategy:
    """A fixed pool of wrong values, optionally with generated ones."""
    base = st.sampled_from(values)
    return base if floats is None else st.one_of(base, floats)


#: generated wrong values: any non-positive float (with NaN) or any non-finite one
NEG_FLOATS = st.one_of(st.floats(max_value=0.0), st.just(NAN))


def assert_refused(call, names: tuple[str, ...]) -> None:
    """``call()`` raises a documented exception whose message names one of ``names``."""
    try:
        out = call()
    except ChaplyginError as exc:
        msg = str(exc)
        assert msg.strip(), "empty message"
        assert any(n in msg for n in names), f"message does not name {names}: {msg!r}"
        assert "\n" not in msg.strip() or len(msg) < 2000
        return
    # anything else (TypeError, ZeroDivisionError, ...) propagates and fails the test
    pytest.fail(f"accepted a wrong argument, returned {type(out).__name__}")


def spoil(base: dict, pools: dict[str, st.SearchStrategy]) -> st.SearchStrategy:
    """``(name, kwargs)`` with one argument of ``base`` replaced by a value of its pool."""
    return st.sampled_from(sorted(pools)).flatmap(
        lambda name: pools[name].map(lambda v: (name, {**base, name: v}))
    )


NAMES = {  # what a message may call an argument (besides its own name)
    "Mg": ("M_gamma",),
    "Ep": ("E'",),
    "y0": ("M", "gamma", "state"),
    "params": ("I", "D", "C", "param"),
    "I": ("I1", "I2", "I3"),
    "system": ("system",),
    "effects": ("effect",),
    "value": ("precision",),
    "mu_max": ("mu_max",),
}


def check(fn, case) -> None:
    name, kwargs = case
    assert_refused(lambda: fn(**kwargs), (name, *NAMES.get(name, ())))


# ------------------------------------------------------------------------- chaplygin.*
Y0 = {"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, "sqrt(0.87)")}
P0 = {"I": (1, 2, 3), "D": 1}
BAD_Y0 = [
    None,
    "abc",
    5,
    {},
    {"M": (0.7, -0.4, 0.5)},
    {"M": None, "gamma": Y0["gamma"]},
    {"M": (1, 2), "gamma": Y0["gamma"]},
    {"M": (NAN, 0, 0), "gamma": Y0["gamma"]},
    {"M": Y0["M"], "gamma": (1, 1, 1)},  # |gamma| = sqrt(3)
    {"M": Y0["M"], "gamma": (0, 0, 0)},
    {"M": Y0["M"], "gamma": "1,0"},
    {**Y0, "nope": (1, 2, 3)},
    [1, 2],
    [1.0] * 7,
    np.ones((6, 6)),
    [0.7, -0.4, 0.5, 1.0, 1.0, 1.0],  # |gamma| = sqrt(3) as a vector
    [0.7, -0.4, 0.5, NAN, 0.0, 1.0],
]
BAD_PARAMS = [
    None,
    "abc",
    5,
    {},
    {"I": (1, 2, 3)},
    {"I": None, "D": 1},
    {"I": (1, 2), "D": 1},
    {"I": (-1, 2, 3), "D": 1},
    {"I": (0, 2, 3), "D": 1},
    {"I": (1, NAN, 3), "D": 1},
    {"I": (1, 2, 3), "D": 0},
    {"I": (1, 2, 3), "D": -1},
    {"I": (1, 2, 3), "D": INF},
    {"I": (1, 2, 3), "D": "1e-400"},
    {"I": (1, 2, 3), "D": 1, "nope": 1},
    [1, 2, 3],
    [-1.0, 2.0, 3.0, 1.0],
    [1.0, 2.0, 3.0, 0.0],
    np.ones((4, 4)),
]
BAD_T_SPAN = [
    None,
    (0,),
    (),
    (0, 1, 2),
    (0, NAN),
    (NAN, 1),
    (0, INF),
    INF,
    NAN,
    "abc",
    {},
    [[0, 1]],
]


@SETTINGS
@given(
    spoil(
        {"system": "chaplygin_ball", "y0": Y0, "t_span": 0.01, "params": P0},
        {
            "system": pool(BAD_NAME),
            "y0": pool(BAD_Y0),
            "t_span": pool(BAD_T_SPAN),
            "params": pool(BAD_PARAMS),
            "effects": pool([5, ["nope"], "nope", [None], {"a": 1}, "gyrostat,nope"]),
            "method": pool(BAD_NAME[1:]),  # None is the default method
            "precision": pool([None, "nope", 5, 15, 10**6, NAN, INF, [], {}, 2.5]),
            "rtol": pool(BAD_POSITIVE[1:], floats=NEG_FLOATS),  # None: the default
            "t_eval": pool([[], (), [0.02], [0.005, 0.001], "abc", [NAN], [[0.0]]]),
        },
    )
)
def test_integrate(case):
    check(integrate, case)


@SETTINGS
@given(
    spoil(
        {"system": "chaplygin_ball", "effects": ()},
        {
            "system": pool(BAD_NAME),
            "effects": pool([5, ["nope"], "nope", [None], {"a": 1}, "gyrostat,nope", [5]]),
        },
    )
)
def test_build_model(case):
    check(lambda **kw: build_model(kw["system"], kw["effects"], disk_cache=False), case)


@SETTINGS
@given(
    spoil(
        {"system": "chaplygin_ball", "effects": ()},
        {
            "system": pool(BAD_NAME),
            "effects": pool([5, ["nope"], "nope", [None], {"a": 1}, "gyrostat,nope", [5]]),
        },
    )
)
def test_load_model_code(case):
    check(load_model_code, case)


@SETTINGS
@given(pool([None, "nope", "", 15, 10001, 10**100, NAN, INF, -INF, [], {}, 2.5, -30, "1e9"]))
def test_precision(value):
    assert_refused(lambda: Precision(value), ("precision",))


# ------------------------------------------------------------------------- separatrix
SEP = {"I": (1, 3, 5), "D": 1}


@SETTINGS
@given(
    spoil(
        {**SEP, "b": 1, "digits": 10, "C": 1, "engine": "taylor", "methods": ("closed",)},
        {
            "I": pool(BAD_MIDDLE),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "b": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "digits": pool(BAD_COUNT),
            "C": pool(BAD_REAL + [0, 0.0]),
            "engine": pool(BAD_NAME),
            "methods": pool([None, "ode", ["nope"], [None], 5, [5]]),
        },
    )
)
def test_delta_three_ways(case):
    check(separatrix.delta_three_ways, case)


@SETTINGS
@given(spoil(SEP, {"I": pool(BAD_MIDDLE), "D": pool(BAD_POSITIVE, floats=NEG_FLOATS)}))
def test_mu_of_and_check_inertia(case):
    check(separatrix.mu_of, case)
    check(separatrix.check_inertia, case)


@SETTINGS
@given(
    spoil(
        {"mu": 1, "b": 1, "dps": 15, "method": "zeros"},
        {
            "mu": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "b": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "dps": pool(BAD_COUNT),
            "method": pool(BAD_NAME),
        },
    )
)
def test_delta_quadrature(case):
    check(separatrix.delta_quadrature, case)


@SETTINGS
@given(
    spoil(
        {"mu": 1, "b": 1, "dps": 15},
        {
            "mu": pool(BAD_REAL),
            "b": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "dps": pool(BAD_COUNT),
        },
    )
)
def test_delta_closed_form(case):
    check(separatrix.delta_closed_form, case)


@SETTINGS
@given(
    spoil(
        {**SEP, "C": 1},
        {
            "I": pool(BAD_MIDDLE),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "C": pool(BAD_REAL + [0]),
        },
    )
)
def test_separatrix_state(case):
    check(separatrix.separatrix_state, case)


@SETTINGS
@given(
    spoil(
        {**SEP, "b": 1, "C": 1, "L": 14.0, "terms": 2, "prec": 128, "order": 24, "tol": 1e-24},
        {
            "I": pool(BAD_ORDERED),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "b": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "C": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "L": pool([None, "14", 0, 0.5, 201, NAN, INF, True, [14]]),
            "terms": pool([None, "2", 1.5, -1, 51, True, NAN]),
            "prec": pool([None, "128", 128.0, 10, 5000, True]),
            "order": pool([None, "24", 2.5, 1, 61, True]),
            "tol": pool([None, "1e-24", 0, -1e-20, 1.0, NAN, INF, True]),
        },
    )
)
def test_enclose_delta(case):
    from chaplygin.numerics.ball.separatrix_enclosure import enclose_delta

    check(enclose_delta, case)


@SETTINGS
@given(
    spoil(
        {**SEP, "h": 0.15, "C": 1, "rtol": 1e-8},
        {
            "I": pool(BAD_MIDDLE),
            "D": pool(BAD_POSITIVE + ["1"], floats=NEG_FLOATS),
            "h": pool(BAD_POSITIVE + [1e6, 1e-6, "0.15"], floats=NEG_FLOATS),
            "C": pool(BAD_REAL + [0, 1e-320]),
            "rtol": pool(BAD_POSITIVE, floats=NEG_FLOATS),
        },
    )
)
def test_frame_turn(case):
    check(frame_turn.frame_turn, case)


@SETTINGS
@given(
    spoil(
        {**SEP, "bracket": (0.11, 0.16), "C": 1},
        {
            "I": pool(BAD_MIDDLE),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "bracket": pool(BAD_BRACKET),
            "C": pool(BAD_REAL + [0]),
        },
    )
)
def test_critical_energy(case):
    check(frame_turn.critical_energy, case)


def test_negative_radius_is_refused_by_every_method():
    """The audit's case: b = -1 gave +0.41 from the ODE and -0.41 from the other two."""
    with pytest.raises(UserInputError, match="b = -1"):
        separatrix.delta_three_ways((1, 3, 5), 1, -1, 20)
    with pytest.raises(UserInputError, match="b = -1"):
        separatrix.delta_quadrature(separatrix.mu_of((1, 3, 5), 1), -1, 20)
    with pytest.raises(UserInputError, match="b = -1"):
        separatrix.delta_closed_form(separatrix.mu_of((1, 3, 5), 1), -1, 20)


# ------------------------------------------------------------------------- stability
STAB = {"I": (1, 2, 3), "D": 1}


@SETTINGS
@given(
    spoil(
        {**STAB, "axis": 0, "C": 1.0, "Mg": 0.0, "branch": 0},
        {
            "I": pool(BAD_INERTIA),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "axis": pool([5, 3, -1, None, "0", 1.0, True, NAN, [0], np.zeros(2)]),
            "C": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "Mg": pool(BAD_REAL + [1.0, -2.0, 1e200]),
            "branch": pool([2, -1, None, "0", 0.5, True, [0]]),
        },
    )
)
def test_critical_state(case):
    check(stability.critical_state, case)


@SETTINGS
@given(
    spoil(
        {**STAB, "C": 1.0, "Mg": 0.3, "rtol": 1e-8},
        {
            "I": pool(BAD_INERTIA),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "C": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "Mg": pool(BAD_REAL + [1.0, 5.0]),
            "rtol": pool(BAD_POSITIVE, floats=NEG_FLOATS),
        },
    )
)
def test_steady_rotation_floquet(case):
    check(stability.steady_rotation_floquet, case)


@SETTINGS
@given(
    spoil(
        {**STAB, "Ep": 1.0, "rtol": 1e-8},
        {
            "I": pool(BAD_INERTIA),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "Ep": pool(BAD_REAL + [-5.0, 1e6]),
            "rtol": pool(BAD_POSITIVE, floats=NEG_FLOATS),
        },
    )
)
def test_euler_floquet(case):
    check(stability.euler_floquet, case)


# ------------------------------------------------------------------------- quadratures
TORUS = {"I": (1, 1.5, 3), "D": 1, "M": (0.8, 0.5, -0.6), "gamma": (0.6, 0.0, 0.8)}
BAD_GAMMA = BAD_VECTOR + [(1, 1, 1), (0, 0, 0)]


@SETTINGS
@given(
    spoil(
        {**TORUS, "digits": 15},
        {
            "I": pool(BAD_ORDERED),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "M": pool(BAD_VECTOR),
            "gamma": pool(BAD_GAMMA),
            "digits": pool(BAD_COUNT + [14]),
        },
    )
)
def test_torus_quadratures_and_rotation_number(case):
    check(quadratures.torus_quadratures, case)
    check(quadratures.rotation_number, case)


@SETTINGS
@given(
    spoil(
        {**TORUS, "t_end": 1.0, "samples_per_unit": 10.0, "rtol": 1e-8},
        {
            "I": pool(BAD_INERTIA),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "M": pool(BAD_VECTOR),
            "gamma": pool(BAD_GAMMA),
            "t_end": pool(BAD_POSITIVE + [1e300], floats=NEG_FLOATS),
            "samples_per_unit": pool(BAD_POSITIVE + [1e300], floats=NEG_FLOATS),
            "rtol": pool(BAD_POSITIVE, floats=NEG_FLOATS),
        },
    )
)
def test_measured_rotation_number(case):
    check(quadratures.measured_rotation_number, case)


@SETTINGS
@given(
    spoil(
        {"lam1": 0.5, "lam2": 0.2, "a": (1.0, 0.6, 0.3), "D": 1},
        {
            "lam1": pool(BAD_REAL),
            "lam2": pool(BAD_REAL),
            "a": pool(BAD_VECTOR),
            "D": pool(BAD_POSITIVE),
        },
    )
)
def test_separation_roots_and_R(case):
    check(quadratures.separation_roots, case)
    check(quadratures.separation_R, case)


# ------------------------------------------------------------------------- transformation
@SETTINGS
@given(
    spoil(
        {
            "I": (1, 2, 3),
            "D": 1,
            "M0": (0.7, -0.4, 0.5),
            "gamma0": (0.6, 0.0, 0.8),
            "t_end": 0.1,
            "form": "chaplygin",
            "rtol": 1e-8,
            "panel": 0.25,
            "nodes": 4,
        },
        {
            "I": pool(BAD_INERTIA),
            "D": pool(BAD_POSITIVE + ["1"], floats=NEG_FLOATS),
            "M0": pool(BAD_VECTOR),
            "gamma0": pool(BAD_GAMMA),
            "t_end": pool(BAD_POSITIVE + [1e300], floats=NEG_FLOATS),
            "form": pool(BAD_NAME),
            "rtol": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "panel": pool(BAD_POSITIVE + [1e-300], floats=NEG_FLOATS),
            "nodes": pool(BAD_COUNT + [1000]),
        },
    )
)
def test_transformation_test(case):
    check(transformation_test, case)


# ------------------------------------------------------------------------- figures
@SETTINGS
@given(
    spoil(
        {"b": 1.0, "mu_max": 6.0},
        {
            "b": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "mu_max": pool(BAD_POSITIVE + [1e300], floats=NEG_FLOATS),
        },
    )
)
def test_delta_of_mu_figure(case):
    check(plots.delta_of_mu_figure, case)


@SETTINGS
@given(
    spoil(
        {"I": (1, 3, 5), "D": 1.0, "b": 1.0},
        {
            "I": pool(BAD_MIDDLE),
            "D": pool(BAD_POSITIVE, floats=NEG_FLOATS),
            "b": pool(BAD_POSITIVE, floats=NEG_FLOATS),
        },
    )
)
def test_separatrix_figures(case):
    check(plots.separatrix_figures, case)


@SETTINGS
@given(
    spoil(
        {"figure": "k01-1", "params": None, "samples": 2, "seed": 1},
        {
            "figure": pool(BAD_NAME),
            "params": pool(
                [
                    "abc",
                    5,
                    [1, 2],
                    {"nope": 1},
                    {"I": None},
                    {"I": (1, 2)},
                    {"I": (-1, 2, 3)},
                    {"I": (1, NAN, 3)},
                    {"I": "1,2,3x"},
                    {"D": 0},
                    {"D": NAN},
                    {"D": "abc"},
                    {"C": None},
                    {"C": INF},
                ]
            ),
            "samples": pool(BAD_COUNT),
            "seed": pool([None, "abc", 1.5, -1, [1], {}]),
        },
    )
)
def test_bifurcation_figure(case):
    check(plots.bifurcation_figure, case)


@SETTINGS
@given(
    pool(
        [
            None,
            "abc",
            5,
            [],
            {},
            {"rows": None},
            {"rows": 5},
            {"rows": [{}]},
            {"rows": [None]},
            {"rows": [{"problem": "p", "median_s": "x", "error": 1}]},
        ]
    )
)
def test_work_precision_figure(study):
    assert_refused(lambda: plots.work_precision_figure(study), ("study",))


@SETTINGS
@given(
    spoil(
        {**SEP, "h": 0.15, "C": 1, "rtol": 1e-8},
        {
            "I": pool(BAD_MIDDLE),
            "D": pool(BAD_POSITIVE + ["1"], floats=NEG_FLOATS),
            "h": pool(BAD_POSITIVE + [1e6, 1e-6, "0.15"], floats=NEG_FLOATS),
            "C": pool(BAD_REAL + [0, 1e-320]),
            "rtol": pool(BAD_POSITIVE, floats=NEG_FLOATS),
        },
    )
)
def test_trace_period(case):
    from chaplygin.numerics.ball import trace_geometry

    check(trace_geometry.trace_period, case)


@SETTINGS
@given(
    spoil(
        {**SEP, "h": None, "C": 1, "K": (0.1, 0.1, 0.2), "gamma0": (0.3, -0.5, 0.81)},
        {
            "K": pool([v for v in BAD_VECTOR if v is not None]),
            "gamma0": pool(BAD_VECTOR + [[0, 0, 0]]),
            "C": pool(BAD_REAL + [0]),
        },
    )
)
def test_trace_period_with_gyrostat(case):
    from chaplygin.numerics.ball import trace_geometry

    check(trace_geometry.trace_period, case)


DENSE_Y0 = [0.7, -0.4, 0.5, 0.36, 0.48, 0.8]
BAD_STATE6 = [
    None,
    "abc",
    5,
    {},
    [1, 2],
    [1.0] * 7,
    np.ones((6, 6)),
    [0.7, -0.4, 0.5, NAN, 0.0, 1.0],
    [0.7, -0.4, 0.5, INF, 0.0, 1.0],
    [0.7, -0.4, 0.5, "0.36", 0.48, 0.8],
    [0.7, -0.4, 0.5, None, 0.48, 0.8],
]


@SETTINGS
@given(
    spoil(
        {
            "y0": DENSE_Y0,
            "t_span": (0.0, 1.0),
            "p": [1.0, 2.0, 3.0, 1.0],
            "rtol": 1e-10,
            "atol": 1e-10,
            "max_steps": 1000,
            "lib": None,
        },
        {
            "y0": pool(BAD_STATE6),
            "p": pool(BAD_STATE6[:7] + [[1.0, 2.0, NAN, 1.0], [1.0, "2", 3.0, 1.0]]),
            "t_span": pool(BAD_BRACKET[:5] + [(1.0, 1.0), (0.0, INF), ("0", 1.0)]),
            "rtol": pool(BAD_POSITIVE + [1e-17], floats=NEG_FLOATS),
            "atol": pool(BAD_POSITIVE + [1e-300], floats=NEG_FLOATS),
            "max_steps": pool([None, "20", 1.5, 0, -1, True, NAN]),
            "lib": pool(["", "C", "mpfr", 5, "gmpy2"]),
        },
    )
)
def test_taylor_dense(case):
    from chaplygin.numerics.taylor import taylor_dense

    code = load_model_code("chaplygin_ball")
    name, kwargs = case
    assert_refused(lambda: taylor_dense(code, **kwargs), (name,))
