"""Integration: the foundation acceptance problem, precision paths, evidence, bad input."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from chaplygin.derive import UserInputError
from chaplygin.numerics import METHODS, integrate
from reference import EPS, REFERENCE_PARAMS, REFERENCE_Y0

BALL = "chaplygin_ball"


def test_reference_problem_conserves_H_and_M2_to_1e10_over_T1000():
    """Foundation acceptance: DOP853, rtol = atol = 1e-12, T = 1000."""
    r = integrate(
        BALL, REFERENCE_Y0, 1000, REFERENCE_PARAMS, method="DOP853", rtol=1e-12, atol=1e-12
    )
    assert r.success, r.message
    assert r.drift["H"] <= 1e-10
    assert r.drift["(M,M)"] <= 1e-10
    assert set(r.drift) == {"H", "(M,M)", "(M,gamma)", "(gamma,gamma)"}
    # evidence carried by the result
    assert r.nfev > 0 and r.nsteps > 0 and r.wall_s > 0 and r.backend in ("c", "numpy")


def test_c_and_numpy_backends_give_the_same_trajectory():
    a = integrate(BALL, REFERENCE_Y0, 10, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12, backend="c")
    b = integrate(BALL, REFERENCE_Y0, 10, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12, backend="numpy")
    # the right-hand sides agree to a few ulps per call (test_codegen); over the steps
    # rounding can accumulate at most linearly
    assert np.max(np.abs(a.y[:, -1] - b.y[:, -1])) <= 100 * a.nsteps * EPS


@pytest.mark.parametrize("rtol", [1e-6, 1e-9, 1e-12])
def test_dop853_error_is_within_its_tolerance_against_a_30_digit_reference(rtol):
    ref = integrate(BALL, REFERENCE_Y0, 2, REFERENCE_PARAMS, precision=30)
    y_true = np.array([float(v) for v in ref.y[:, -1]])
    r = integrate(BALL, REFERENCE_Y0, 2, REFERENCE_PARAMS, method="DOP853", rtol=rtol, atol=rtol)
    e = np.abs(r.y[:, -1] - y_true) / (rtol + rtol * np.abs(y_true))
    assert np.all(e < 5)  # scipy's test_ivp criterion


@pytest.mark.parametrize("method", ["RK45", "LSODA", "Radau", "BDF"])
def test_other_scipy_methods_run_and_report_drift(method):
    r = integrate(BALL, REFERENCE_Y0, 5, REFERENCE_PARAMS, method=method, rtol=1e-9, atol=1e-11)
    assert r.success, r.message
    assert max(r.drift.values()) < 1e-6
    assert METHODS[method].implicit == (method != "RK45")
    if method in ("Radau", "BDF"):  # LSODA may stay in its non-stiff (Adams) mode
        assert r.njev > 0  # the generated Jacobian was used


@pytest.mark.parametrize("digits,backend", [(30, "c-dd"), (50, "c-qd"), (70, "c-mpfr")])
def test_high_precision_path_keeps_its_digits(digits, backend):
    r = integrate(BALL, REFERENCE_Y0, 2, REFERENCE_PARAMS, precision=digits)
    assert r.success and r.method == "taylor" and r.backend == backend
    assert isinstance(r.y[0, -1], mpmath.mpf)
    assert max(r.drift.values()) <= 10.0 ** (5 - digits)
    assert r.precision == f"{digits} digits"


def test_effects_do_not_change_the_balls_motion():
    base = integrate(BALL, REFERENCE_Y0, 10, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12)
    zero_k = integrate(
        BALL,
        REFERENCE_Y0,
        10,
        {**REFERENCE_PARAMS, "K": (0, 0, 0)},
        effects="gyrostat",
        rtol=1e-12,
        atol=1e-12,
    )
    assert np.array_equal(base.y[:, -1], zero_k.y[:, -1])
    cp = integrate(
        BALL,
        REFERENCE_Y0,
        10,
        {**REFERENCE_PARAMS, "b": 1},
        effects="contact_point",
        rtol=1e-12,
        atol=1e-12,
    )
    y = base.y[:, -1]
    e = np.abs(cp.y[:6, -1] - y) / (1e-12 + 1e-12 * np.abs(y))
    assert np.all(e < 10)  # two solutions each within scipy's e < 5
    assert cp.drift["(alpha,alpha)"] < 1e-10 and "(alpha,beta)" in cp.drift_absolute
    assert abs(cp.y_final["x"]) + abs(cp.y_final["y"]) > 0.1  # the contact point moved


def test_gyrostat_changes_the_motion_and_keeps_its_integrals():
    r = integrate(
        BALL,
        REFERENCE_Y0,
        50,
        {**REFERENCE_PARAMS, "K": (0.1, 0.1, 0.2)},
        effects="gyrostat",
        rtol=1e-12,
        atol=1e-12,
    )
    base = integrate(BALL, REFERENCE_Y0, 50, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12)
    assert np.max(np.abs(r.y[:, -1] - base.y[:, -1])) > 1e-3
    assert max(r.drift.values()) < 1e-10


BAD = [
    ({"I": (1, 2)}, REFERENCE_Y0, "needs 3"),
    ({"I": (1, -2, 3), "D": 1}, REFERENCE_Y0, "positive"),
    ({"I": (1, 2, 3), "D": 0}, REFERENCE_Y0, "positive"),
    ({"I": (1, 2, "nan"), "D": 1}, REFERENCE_Y0, "finite"),
    ({"I": (1, 2, float("inf")), "D": 1}, REFERENCE_Y0, "finite"),
    ({"I": (1, 2, 3), "D": 1, "Q": 1}, REFERENCE_Y0, "unknown parameter"),
    ({"I": (1, 2, 3)}, REFERENCE_Y0, "missing parameter D"),
    (REFERENCE_PARAMS, {"M": (1, 2, 3), "gamma": (0, 0.1, 1)}, "unit vector"),
    (REFERENCE_PARAMS, {"M": (1, 2, 3), "gamma": (0, 0, 1), "omega": (1, 2, 3)}, "unknown state"),
    (REFERENCE_PARAMS, {"gamma": (0, 0, 1)}, "missing initial value of M"),
    (REFERENCE_PARAMS, {"M": ("1", "__import__('os')", "3"), "gamma": (0, 0, 1)}, "cannot read"),
]


@pytest.mark.parametrize(("params", "y0", "message"), BAD)
def test_bad_input_is_a_clear_user_error(params, y0, message):
    with pytest.raises(UserInputError, match=message):
        integrate(BALL, y0, 1, params)


def test_bad_options_are_user_errors():
    with pytest.raises(UserInputError, match="unknown method"):
        integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, method="Euler")
    with pytest.raises(UserInputError, match="double precision can deliver"):
        integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, rtol=1e-17)
    with pytest.raises(UserInputError, match="taylor"):
        integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, method="DOP853", precision=30)
    with pytest.raises(UserInputError, match="precision"):
        integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, precision="quadruple")
    with pytest.raises(UserInputError, match="frame"):
        integrate(
            BALL,
            {**REFERENCE_Y0, "alpha": (1, 0, 0), "beta": (1, 0, 0)},
            1,
            {**REFERENCE_PARAMS, "b": 1},
            effects="contact_point",
        )


# ------------------------------------------------------------------ the integrator protocol


def test_method_may_be_a_name_a_class_or_an_instance():
    from chaplygin.numerics.integrators import DOP853, get_integrator

    runs = [
        integrate(BALL, REFERENCE_Y0, 2, REFERENCE_PARAMS, method=m, rtol=1e-10, atol=1e-10)
        for m in ("DOP853", DOP853, DOP853())
    ]
    assert {r.method for r in runs} == {"DOP853"}
    assert all(np.array_equal(r.y, runs[0].y) for r in runs)
    with pytest.raises(UserInputError, match="valid methods: RK45, DOP853, LSODA") as err:
        get_integrator("dop853")
    assert all(name in str(err.value) for name in METHODS)


def test_method_data_is_consistent():
    """Every method's floor covers its precisions, and it is >= 1 eps (no method beats the
    unit roundoff); the default method of each precision works in it; METHODS are the
    registry's integrators of a model's own equations."""
    from chaplygin.numerics.inputs import Precision
    from chaplygin.numerics.integrators import INTEGRATORS, ModelFlow

    for name, cls in INTEGRATORS.items():
        assert cls.name == name
        assert set(cls.rtol_floor) == set(cls.precisions)
        assert min(cls.rtol_floor.values()) >= 1
        assert cls.backends and set(cls.backends) <= {"c", "numpy", "mpmath"}
    assert METHODS == {n: c for n, c in INTEGRATORS.items() if ModelFlow in c.flows}
    assert "dop853" in INTEGRATORS and "dop853" not in METHODS
    for kind in ("double", "quad", 30):
        prec = Precision(kind)
        assert prec.kind in METHODS[prec.default_method].precisions
    prec = Precision(30)
    assert METHODS["taylor"]().floor(prec) == prec.epsilon
    assert METHODS["odefun"]().floor(prec) == prec.min_rtol
    # a method with one backend runs on it whatever is asked
    r = integrate(
        BALL, REFERENCE_Y0, 0.1, REFERENCE_PARAMS, precision=20, method="odefun", backend="numpy"
    )
    assert r.success and r.backend == "mpmath"


def test_result_repr_is_short_and_names_the_evidence():
    r = integrate(BALL, REFERENCE_Y0, 5, REFERENCE_PARAMS, rtol=1e-10, atol=1e-10)
    text = repr(r)
    assert len(text) < 600 and len(text.splitlines()) < 12
    for key in ("taylor", "success", "drift", "nfev", "M1=", "(gamma,gamma)"):
        assert key in text
    assert f"({r.t.size})" in text  # the time array is shortened, its length given
    html = r._repr_html_()
    assert html.startswith("<table>") and "taylor" in html and "nfev" in html
    q = integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, precision=40)
    assert "40 digits" in repr(q) and len(repr(q)) < 600


@pytest.mark.parametrize("precision", [30, "quad"])
def test_a_results_values_show_at_the_runs_precision(precision):
    """``r.y_final["M1"]`` of a 30-digit run prints 30 digits (issue 28, 5): what ``str`` of
    the same number gives with mpmath's global precision raised to the run's bits, while
    the global precision stays where the user left it (15 digits)."""
    import pickle

    from chaplygin.numerics.precision import Precision
    from mpmath.libmp import prec_to_dps

    bits = Precision(precision).prec
    digits = prec_to_dps(bits)  # 30, and 33 for binary128's 113 bits
    r = integrate("chaplygin_ball", REFERENCE_Y0, 1, REFERENCE_PARAMS, precision=precision)
    assert mpmath.mp.dps == 15
    values = [r.y_final["M1"], r.t[-1], r.y[2, 3], r.params["D"]]
    shown = [str(v) for v in values]
    with mpmath.workprec(bits):
        expected = [str(mpmath.mpf(v)) for v in values]
        # repr reads back to the same number at the run's precision
        assert all(mpmath.mpf(repr(v)[5:-2]) == v for v in values)
    assert shown == expected and len(shown[0].lstrip("-0.")) >= digits - 1 >= 29
    assert str(mpmath.mpf(r.y_final["M1"])) != shown[0]  # a plain mpf: 15 digits (control)
    assert type(r.y_final["M1"] + 1) is mpmath.mpf  # arithmetic: plain mpf
    assert str(pickle.loads(pickle.dumps(r.y_final["M1"]))) == shown[0]
    assert isinstance(integrate("chaplygin_ball", REFERENCE_Y0, 1, REFERENCE_PARAMS).y[0, -1],
                      float)  # fmt: skip
