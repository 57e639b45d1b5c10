"""The Taylor integrator generated from the model (issue 5 §1).

Recurrences against an independent series expansion of the exact solution and exact
Lie-derivative coefficients; C double and quad coefficients against mpmath at their
epsilon; the fitted convergence order; adaptive runs against references at more digits;
dense output, event location; quad digits; precision errors; CLI.
"""

from __future__ import annotations

import functools
import json
import math
import random
import warnings

import mpmath
import numpy as np
import pytest
import sympy as sp
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.systems import build_model as _build_model
from chaplygin.derive.systems import builtin_variants
from chaplygin.numerics import integrate, load_model_code
from chaplygin.numerics.inputs import Precision
from chaplygin.numerics.taylor import (
    decode_binary128,
    encode_binary128,
    jorba_zou_order,
    load_taylor_library,
    python_lib,
    taylor_solve,
)
from chaplygin.verify.cli import main
from reference import REFERENCE_PARAMS, REFERENCE_Y0
from taylor_reference import lie_coefficients, series_coefficients

BALL = "chaplygin_ball"
VARIANTS = [(s, tuple(sorted(e))) for s, e in builtin_variants()]
EPS_QUAD = 2.0**-112


@functools.cache
def build_model(system: str, effects: tuple[str, ...]):
    """Derivations are slow (seconds for the rubber ball): once per test session."""
    return _build_model(system, effects)


def _mp(q) -> mpmath.mpf:
    q = sp.Rational(q)
    return mpmath.mpf(q.p) / q.q


def _rational_point(model, seed: int = 3):
    """Exact rational data: positive parameters in [1.1, 3], state in [-0.9, 0.9], t0 = 3/10."""
    rng = random.Random(seed)
    params = [sp.Rational(rng.randint(11, 30), 10) for _ in model.params]
    state = [sp.Rational(rng.randint(-9, 9), 10) for _ in model.state]
    return sp.Rational(3, 10), state, params


def _reference_state(digits: int):
    with mpmath.workdps(digits):
        return [
            mpmath.mpf("0.7"),
            mpmath.mpf("-0.4"),
            mpmath.mpf("0.5"),
            mpmath.mpf("0.2"),
            mpmath.mpf("0.3"),
            mpmath.sqrt(mpmath.mpf("0.87")),
        ]


# ------------------------------------------------------------------ recurrences


@pytest.mark.slow
@pytest.mark.parametrize("system,effects", VARIANTS, ids=["__".join([s, *e]) for s, e in VARIANTS])
def test_recurrences_match_series_of_the_solution(system, effects):
    """Every built-in variant (BM20's sin(Omega t) included): order 6 at 40 digits.

    Tolerance: 10^3 units of the working precision relative to max(1, |coefficient|) (a
    few hundred roundings in the recurrences and in the reference).
    """
    model = build_model(system, effects)
    code = load_model_code(system, effects)
    t0, y0, p = _rational_point(model)
    K, dps = 5, 40
    with mpmath.workdps(dps):
        ref = series_coefficients(model, t0, y0, p, K)
        got = code.taylor.taylor_coefficients(
            _mp(t0), [_mp(v) for v in y0], [_mp(v) for v in p], K, python_lib("mpmath")
        )
        for i in range(len(y0)):
            for k in range(K + 1):
                bound = 1000 * mpmath.mpf(10) ** -dps * max(1, abs(ref[i][k]))
                assert abs(got[i][k] - ref[i][k]) <= bound, (model.state[i], k)
        # the coefficients are not trivially zero: the test can fail
        assert max(abs(got[i][K]) for i in range(len(y0))) > 0


@pytest.mark.parametrize(
    "system,effects", [("chaplygin_ball", ()), ("chaplygin_ball", ("variable_inertia",))]
)
def test_recurrences_match_exact_lie_derivatives(system, effects):
    """Exact rational y'' / 2 (differentiation along the flow) equals the recurrences."""
    model = build_model(system, effects)
    code = load_model_code(system, effects)
    t0, y0, p = _rational_point(model, seed=5)
    if model.time in sp.Matrix(model.rhs_expanded).free_symbols:
        t0 = sp.Integer(0)  # sin(Omega t0) is then exactly rational (0)
    exact = lie_coefficients(model, t0, y0, p, 2)
    with mpmath.workdps(50):
        got = code.taylor.taylor_coefficients(
            _mp(t0), [_mp(v) for v in y0], [_mp(v) for v in p], 2, python_lib("mpmath")
        )
        for i in range(len(y0)):
            for k in range(3):
                assert abs(got[i][k] - _mp(exact[i][k])) <= mpmath.mpf(10) ** -47 * max(
                    1, abs(_mp(exact[i][k]))
                )


def test_negative_control_a_wrong_coefficient_is_detected():
    """A perturbed parameter changes the coefficients far beyond the tolerance."""
    model = build_model("chaplygin_ball", ())
    code = load_model_code("chaplygin_ball")
    t0, y0, p = _rational_point(model)
    with mpmath.workdps(40):
        ref = series_coefficients(model, t0, y0, p, 4)
        wrong = [*p[:-1], p[-1] * (1 + sp.Rational(1, 10**20))]
        got = code.taylor.taylor_coefficients(
            _mp(t0), [_mp(v) for v in y0], [_mp(v) for v in wrong], 4, python_lib("mpmath")
        )
        worst = max(abs(got[i][k] - ref[i][k]) for i in range(6) for k in range(5))
        assert worst > 1000 * mpmath.mpf(10) ** -40


@pytest.mark.parametrize("kind,eps", [("double", 2.0**-52), ("quad", EPS_QUAD)])
@pytest.mark.parametrize(
    "system,effects",
    [
        ("chaplygin_ball", ()),
        ("chaplygin_ball", ("contact_point", "gyrostat")),
        ("chaplygin_ball", ("variable_inertia",)),
        ("ball_on_surface", ("potential",)),
    ],
)
def test_c_coefficients_agree_with_mpmath(kind, eps, system, effects):
    """C double / quad against 50-digit mpmath: |error| <= 64 (k+1) eps max_i |c_ik| per order."""
    code = load_model_code(system, effects)
    lib = load_taylor_library(code, kind)
    if lib is None:
        pytest.skip("no C compiler")
    model = build_model(system, effects)
    t0, y0, p = _rational_point(model)
    order = 20
    with mpmath.workdps(50):
        ref = code.taylor.taylor_coefficients(
            _mp(t0), [_mp(v) for v in y0], [_mp(v) for v in p], order, python_lib("mpmath")
        )
        if kind == "double":
            args = (float(t0), [float(v) for v in y0], [float(v) for v in p])
            # the double inputs are roundings of the rationals: use them for the reference
            ref = code.taylor.taylor_coefficients(
                mpmath.mpf(args[0]),
                [mpmath.mpf(v) for v in args[1]],
                [mpmath.mpf(v) for v in args[2]],
                order,
                python_lib("mpmath"),
            )
        else:
            with mpmath.workprec(113):
                args = (+_mp(t0), [+_mp(v) for v in y0], [+_mp(v) for v in p])
            ref = code.taylor.taylor_coefficients(
                args[0], args[1], args[2], order, python_lib("mpmath")
            )
        got = lib.coefficients(order, *args)
        worst = 0.0
        for k in range(order + 1):
            scale = max(abs(ref[i][k]) for i in range(len(y0)))
            for i in range(len(y0)):
                err = abs(mpmath.mpf(got[i][k]) - ref[i][k])
                ratio = float(err / (eps * (k + 1) * scale)) if scale else float(err)
                worst = max(worst, ratio)
        assert worst <= 64, worst


def test_binary128_round_trip():
    with mpmath.workdps(40):
        values = [mpmath.mpf(1) / 3, -mpmath.pi, mpmath.mpf(0), mpmath.mpf("1e-300")]
        back = decode_binary128(encode_binary128(values))
        for v, b in zip(values, back, strict=True):
            assert abs(v - b) <= abs(v) * EPS_QUAD / 2
        with mpmath.workprec(113):
            exact = [+v for v in values]
        assert back == exact


# ------------------------------------------------------------------ order and step


def test_jorba_zou_order():
    assert jorba_zou_order(1e-16) == math.ceil(-0.5 * math.log(1e-16) + 1) == 20
    assert jorba_zou_order(1e-34) == 41
    assert jorba_zou_order(1e-300, max_order=80) == 80


@pytest.mark.parametrize("order", [3, 5])
def test_fitted_convergence_order_matches(order):
    """Fixed order, fixed step h: global error ~ h^order; fitted slope within 0.35 of it."""
    code = load_model_code(BALL)
    y0 = [0.7, -0.4, 0.5, 0.2, 0.3, math.sqrt(0.87)]
    p = [1.0, 2.0, 3.0, 1.0]
    T = 2.0
    ref = taylor_solve(code, y0, (0.0, T), p, rtol=1e-16, atol=1e-16, t_eval=[T])
    hs = [0.25, 0.125, 0.0625, 0.03125]  # exact in binary: T / h steps exactly
    errs = []
    for h in hs:
        sol = taylor_solve(
            code, y0, (0.0, T), p, rtol=1e-16, atol=1e-16, t_eval=[T], order=order, step=h
        )
        assert sol.nsteps == round(T / h)
        errs.append(np.max(np.abs(sol.y[:, -1] - ref.y[:, -1])))
    slope = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert abs(slope - order) <= 0.35, (slope, errs)


def test_fitted_convergence_order_at_30_digits():
    """Same at 30 digits in the Python recurrences (order 8): no roundoff floor."""
    code = load_model_code(BALL)
    with mpmath.workdps(30):
        y0 = _reference_state(30)
        p = [mpmath.mpf(v) for v in (1, 2, 3, 1)]
        T = mpmath.mpf(1)
        ref = taylor_solve(
            code, y0, (0, T), p, precision=30, rtol=1e-29, atol=1e-29, t_eval=[T]
        )
        hs = [mpmath.mpf(1) / 4, mpmath.mpf(1) / 8, mpmath.mpf(1) / 16]
        errs = []
        for h in hs:
            sol = taylor_solve(
                code,
                y0,
                (0, T),
                p,
                precision=30,
                rtol=1e-29,
                atol=1e-29,
                t_eval=[T],
                order=8,
                step=h,
            )
            errs.append(
                float(max(abs(a - b) for a, b in zip(sol.y[:, -1], ref.y[:, -1], strict=True)))
            )
    slope = np.polyfit(np.log([float(h) for h in hs]), np.log(errs), 1)[0]
    assert abs(slope - 8) <= 0.35, (slope, errs)


# ------------------------------------------------------------------ adaptive accuracy


def _scaled_error(y, y_ref, rtol, atol):
    y = np.array([float(v) for v in y])
    y_ref = np.array([float(v) for v in y_ref])
    return float(np.max(np.abs(y - y_ref) / (atol + rtol * np.abs(y_ref))))


@pytest.mark.parametrize("rtol,atol", [(1e-8, 1e-10), (1e-12, 1e-14)])
def test_adaptive_double_meets_tolerance(rtol, atol):
    """Scipy-style e = err / (atol + rtol |y|) < 5 at 11 points to T = 20 against 40 digits."""
    r = integrate(BALL, REFERENCE_Y0, 20, REFERENCE_PARAMS, method="taylor", rtol=rtol, atol=atol)
    ref = integrate(BALL, REFERENCE_Y0, 20, REFERENCE_PARAMS, method="taylor", precision=40)
    assert r.success and r.backend == "c-double" and r.method == "taylor"
    assert r.nsteps > 5 and r.info["order_max"] == jorba_zou_order(rtol)
    for j in range(r.y.shape[1]):
        assert _scaled_error(r.y[:, j], ref.y[:, j], rtol, atol) < 5
    assert max(r.drift.values()) < 10 * rtol


def test_quad_gives_30_digits_on_the_reference_problem():
    """Quad (C, binary128) to T = 5 against a 60-digit reference: >= 30 correct digits."""
    r = integrate(BALL, REFERENCE_Y0, 5, REFERENCE_PARAMS, precision="quad")
    ref = integrate(BALL, REFERENCE_Y0, 5, REFERENCE_PARAMS, precision=60)
    assert r.success and r.precision == "quad" and r.backend == "c-quad"
    with mpmath.workdps(60):
        err = max(abs(a - b) for a, b in zip(r.y[:, -1], ref.y[:, -1], strict=True))
    assert err < 1e-30, err
    assert max(r.drift.values()) < 1e-31


@pytest.mark.parametrize(
    "backend,ran_on", [("auto", "c-dd"), ("numpy", "python-gmpy2")]
)
def test_digits_path_meets_tolerance_and_agrees_with_odefun(backend, ran_on):
    """30 digits, C double-double (default) and gmpy2 recurrences, vs mpmath.odefun at 40
    digits (independent method)."""
    r = integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, precision=30, backend=backend)
    ref = integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, precision=40, method="odefun")
    assert r.method == "taylor" and r.backend == ran_on and ref.method == "odefun"
    rtol = r.info["rtol"]
    for j in range(r.y.shape[1]):
        with mpmath.workdps(40):
            err = max(
                abs(a - b) / (rtol + rtol * abs(b))
                for a, b in zip(r.y[:, j], ref.y[:, j], strict=True)
            )
        assert err < 5


def test_python_fallback_agrees_with_c():
    """The Python float recurrences (used without a compiler) match the C double code."""
    code = load_model_code(BALL)
    y0 = [0.7, -0.4, 0.5, 0.2, 0.3, math.sqrt(0.87)]
    p = [1.0, 2.0, 3.0, 1.0]
    c = taylor_solve(code, y0, (0.0, 3.0), p, rtol=1e-13, atol=1e-13)
    f = taylor_solve(code, y0, (0.0, 3.0), p, rtol=1e-13, atol=1e-13, lib="float")
    assert f.backend == "python-float" and c.backend == "c-double"
    assert c.nsteps == f.nsteps
    assert np.max(np.abs(c.y - f.y)) < 1e-12


def test_time_dependent_model_integrates():
    """BM20 variable inertia (sin(Omega t)): taylor double vs DOP853 at tight tolerance."""
    params = {"I": (1, 2, 3), "D": 1, "J_off": "0.3", "delta": "0.2", "Omega": 2}
    y0 = REFERENCE_Y0
    kw = {"effects": "variable_inertia"}
    a = integrate(BALL, y0, 5, params, method="taylor", rtol=1e-13, atol=1e-13, t_eval=[5], **kw)
    b = integrate(BALL, y0, 5, params, method="DOP853", rtol=1e-13, atol=1e-13, t_eval=[5], **kw)
    assert a.success and b.success
    assert np.max(np.abs(a.y[:, -1] - b.y[:, -1])) < 1e-10


# ------------------------------------------------------------------ dense output and events


def test_dense_output_matches_runs_ending_there():
    """Output at 7 inner times equals a 40-digit reference there (to the tolerance)."""
    times = [0.3, 1.7, 2.5, 4.0, 4.1, 6.66, 9.0]
    rtol = atol = 1e-13
    r = integrate(
        BALL, REFERENCE_Y0, 9, REFERENCE_PARAMS, method="taylor", rtol=rtol, atol=atol, t_eval=times
    )
    assert r.nsteps < len(times) * 3  # steps are longer than the output spacing
    ref = integrate(BALL, REFERENCE_Y0, 9, REFERENCE_PARAMS, precision=40, t_eval=times)
    assert list(r.t) == times
    for j in range(len(times)):
        assert _scaled_error(r.y[:, j], ref.y[:, j], rtol, atol) < 5


def _gamma3(t, y):
    return y[5]


def test_event_location_gamma3_zero_crossing():
    """Zero crossings of gamma3: double vs 40 digits (event times to ~1e-12), g(y_e) ~ eps."""
    T = 30
    r = integrate(
        BALL,
        REFERENCE_Y0,
        T,
        REFERENCE_PARAMS,
        method="taylor",
        rtol=1e-14,
        atol=1e-14,
        events=[_gamma3],
    )
    ref = integrate(BALL, REFERENCE_Y0, T, REFERENCE_PARAMS, precision=40, events=[_gamma3])
    te, tr = r.t_events[0], ref.t_events[0]
    assert len(te) == len(tr) >= 2
    for a, b in zip(te, tr, strict=True):
        assert abs(a - float(b)) < 1e-11
    for ye in r.y_events[0]:
        assert abs(ye[5]) < 1e-15
    with mpmath.workdps(40):
        for ye in ref.y_events[0]:
            assert abs(ye[5]) < mpmath.mpf(10) ** -37
        # a scipy DOP853 run finds the same crossings (independent root finder)
    s = integrate(BALL, REFERENCE_Y0, T, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12, events=[_gamma3])
    assert np.allclose(s.t_events[0], te, atol=1e-8)


def test_terminal_event_with_direction_stops_there():
    def falling(t, y):
        return y[5]

    falling.terminal = True
    falling.direction = -1
    r = integrate(BALL, REFERENCE_Y0, 30, REFERENCE_PARAMS, precision="quad", events=[falling])
    assert r.message.startswith("a terminal event occurred")
    (te,) = r.t_events[0]
    assert r.t[-1] == te and abs(r.y[5, -1]) < 1e-30
    with mpmath.workdps(40):  # gamma3 falls there: its derivative is negative
        assert r.y_events[0][0][5] == r.y[5, -1]


# ------------------------------------------------------------------ precision and input


def test_precision_errors_name_a_precision_that_works():
    with pytest.raises(UserInputError, match="precision=\"quad\""):
        integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, method="taylor", rtol=1e-20)
    with pytest.raises(UserInputError, match=r"quad precision.*precision=42"):
        integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, precision="quad", rtol=1e-40)
    with pytest.raises(UserInputError, match="30 digits precision"):
        integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, precision=30, rtol=1e-35)
    with pytest.raises(UserInputError, match="does not locate events"):
        integrate(
            BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, precision=30, method="odefun", events=[_gamma3]
        )
    with pytest.raises(UserInputError, match="taylor option"):
        integrate(
            BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, method="taylor", taylor_options={"ordre": 3}
        )
    assert Precision("quad").is_quad and Precision("quad").digits == 34


def test_cli_integrate_quad_taylor(capsys):
    args = [
        "integrate",
        BALL,
        "--param",
        "I=1,2,3",
        "--param",
        "D=1",
        "--y0",
        "M=0.7,-0.4,0.5",
        "--y0",
        "gamma=0.2,0.3,sqrt(0.87)",
        "--t-end",
        "2",
        "--precision",
        "quad",
        "--method",
        "taylor",
        "--json",
    ]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["precision"] == {"kind": "quad", "digits": 34, "bits": 113}
    assert out["backend"] == "c-quad"
    assert out["info"]["order_max"] == jorba_zou_order(10 * EPS_QUAD)
    assert max(out["drift"].values()) < 1e-31
    assert len(out["y"]["M1"].lstrip("-").replace(".", "").lstrip("0")) >= 33
    assert main([*args[:-5], "--precision", "quad", "--rtol", "1e-40"]) == 2
    assert "--precision 42" in capsys.readouterr().err


def test_no_compiler_falls_back_with_a_warning(monkeypatch):
    import chaplygin.numerics.taylor.library as taylor_library

    monkeypatch.setattr(taylor_library, "_LIBS", {})

    def broken(*args, **kwargs):
        raise taylor_library.CompilerError("no compiler here")

    monkeypatch.setattr(taylor_library, "compile_c", broken)
    code = load_model_code(BALL)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with mpmath.workdps(34):
            sol = taylor_solve(
                code,
                _reference_state(34),
                (0, 1),
                [1, 2, 3, 1],
                precision="quad",
                rtol=1e-30,
                atol=1e-30,
            )
    assert any("Python" in str(w.message) for w in caught)
    assert sol.backend == "python-gmpy2" and sol.status == 0


@pytest.mark.parametrize("precision", ["double", "quad"])
def test_backward_integration_returns_to_the_start(precision):
    """Forward to T = 3, then backward from there: the initial state comes back."""
    fwd = integrate(
        BALL, REFERENCE_Y0, 3, REFERENCE_PARAMS, method="taylor", precision=precision, t_eval=[3]
    )
    y3 = dict(zip(("M", "gamma"), (fwd.y[:3, -1], fwd.y[3:, -1]), strict=True))
    back = integrate(
        BALL,
        {k: tuple(v) for k, v in y3.items()},
        (3, 0),
        REFERENCE_PARAMS,
        method="taylor",
        precision=precision,
        t_eval=[2, 1, 0],
    )
    assert back.success and list(back.t) == [2, 1, 0]
    start = integrate(
        BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, method="taylor", precision=precision, t_eval=[0]
    ).y[:, 0]
    bound = 1e-12 if precision == "double" else 1e-30
    assert max(abs(a - b) for a, b in zip(back.y[:, -1], start, strict=True)) < bound


def test_precision_rows_agree_with_the_precisions_they_describe():
    """The precision row and REAL_TYPES (method data): the loop's unit roundoff within a
    decade of the stated epsilon, the arithmetic a C real type of the size of its format
    (MPFR has none), the number type, and a pack/unpack round trip exact to the arithmetic's
    bits."""
    from chaplygin.numerics.precision import ARITHMETICS
    from chaplygin.numerics.taylor import REAL_TYPES

    seen = set()
    for value in ("double", "quad", 20, 31, 32, 60, 61, 100):
        prec = Precision(value)
        with prec.context():
            # within a decade: mpmath's 2^-102 against the stated 10^-30 at 30 digits
            assert abs(mpmath.log10(prec.unit_roundoff() / prec.epsilon)) < 1
            assert isinstance(prec.number(1), float if prec.is_double else mpmath.mpf)
        arithmetic = prec.arithmetic
        seen.add(arithmetic.name)
        assert arithmetic.most_bits is None or prec.bits <= arithmetic.most_bits
        assert (arithmetic.name in REAL_TYPES) == (arithmetic.name != "mpfr")
    assert seen == set(ARITHMETICS)
    sizes = {k: r.size for k, r in REAL_TYPES.items()}
    assert sizes == {"double": 8, "quad": 16, "dd": 16, "qd": 32}
    for kind, real in REAL_TYPES.items():
        bits = ARITHMETICS[kind].most_bits
        with mpmath.workprec(bits):
            values = [mpmath.mpf(1) / 3, mpmath.mpf(-2) ** 40]
            back = real.unpack(real.pack(values), 2)
            assert abs(mpmath.mpf(back[0]) * 3 - 1) <= 4 * mpmath.ldexp(1, 1 - bits)
        assert len(real.pack(values)) * (1 if kind == "quad" else 8) == 2 * real.size
        assert mpmath.mpf(back[1]) == 2**40
