"""The compiled multi-double Taylor integrators (issue 15): double-double for digits up to
31 (106 bits), quad-double up to 60 (203 bits).

Every working number is split exactly into its doubles, the C code (``-DCHAPLYGIN_TAYLOR_DD``,
``-DCHAPLYGIN_TAYLOR_QD``) runs the same recurrences as the double and binary128 builds, and
results come back rounded once to the working precision. References are independent routes:
the Python recurrences in MPFR (gmpy2) at 30 more digits, for coefficients and solutions
(``backend="numpy"``), and ``mpmath.odefun`` for one of those references. Tolerances:
multi-double operations have relative errors of a few units of their last limb (Hida, Li and
Bailey), below the working precision's ``2^-prec``; the bounds allow ``2^10 2^-prec`` per
coefficient relative to the largest coefficient of the same order, and ``10 * rtol`` per
step summed over the steps for solutions (the rule of ``test_input_precision.py``).
"""

from __future__ import annotations

import re

import gmpy2
import mpmath
import pytest
import sympy as sp
from chaplygin.numerics import integrate, load_model_code
from chaplygin.numerics.inputs import Precision, pack_state
from chaplygin.numerics.taylor import (
    DD_BITS,
    QD_BITS,
    _from_mpf,
    _to_mpf,
    decode_multi_double,
    encode_multi_double,
    load_taylor_library,
    python_lib,
)
from chaplygin.numerics.taylor import (
    _fma_flags as taylor_fma_flags,
)
from reference import REFERENCE_PARAMS, REFERENCE_Y0

U_DD = 2.0**-DD_BITS

# non-dyadic decimals of 31 significant digits
STATE_31 = {
    "M": ("0.7123456789012345678901234567891", "-0.4098765432109876543210987654321", "0.5"),
    "gamma": ("0.2", "0.3", "sqrt(0.87)"),
}
PARAMS = {"I": ("1.2716", "2.9031", "4.4187"), "D": "0.6513"}


def test_limbs_are_exact_and_keep_the_last_bit():
    """hi + lo equals a 106-bit working number exactly; the last bit changes the limbs."""
    with mpmath.workdps(31):
        assert mpmath.mp.prec == DD_BITS
        x = mpmath.mpf(1) / 7
        y = x + mpmath.ldexp(1, mpmath.mag(x) - DD_BITS)  # next number up at 106 bits
        assert y != x
        limbs = encode_multi_double([x, y, -x, mpmath.mpf(0), 3])
        with mpmath.workprec(400):
            for i, v in enumerate([x, y, -x, 0, 3]):
                assert mpmath.mpf(limbs[2 * i]) + mpmath.mpf(limbs[2 * i + 1]) == v
        assert tuple(limbs[:2]) != tuple(limbs[2:4])
        assert abs(limbs[1]) <= abs(limbs[0]) * 2.0**-53  # normalised: |lo| <= ulp(hi)/2
        back = decode_multi_double(limbs)
        assert back[:3] == [x, y, -x] and back[3] == 0 and back[4] == 3
        # gmpy2 numbers are split the same way
        with gmpy2.context(gmpy2.get_context(), precision=DD_BITS):
            g = gmpy2.mpfr(1) / 7
        assert list(encode_multi_double([g])) == list(limbs[:2])


def test_quad_double_limbs_are_exact_to_the_last_bit():
    """Four limbs hold a 203-bit (60-digit) working number exactly; the last bit counts."""
    with mpmath.workdps(60):
        assert mpmath.mp.prec == QD_BITS
        x = -mpmath.mpf(10) / 7
        y = x - mpmath.ldexp(1, mpmath.mag(x) - QD_BITS)
        limbs = encode_multi_double([x, y], 4)
        with mpmath.workprec(800):
            assert mpmath.fsum(mpmath.mpf(v) for v in limbs[:4]) == x
            assert mpmath.fsum(mpmath.mpf(v) for v in limbs[4:]) == y
        assert list(limbs[:4]) != list(limbs[4:])
        assert all(abs(limbs[i + 1]) <= abs(limbs[i]) * 2.0**-53 for i in range(3))
        assert decode_multi_double(limbs, limbs=4) == [x, y]


def test_a_value_wider_than_double_double_is_refused():
    """A 150-bit number has no exact two-double form: refused, not rounded silently."""
    with mpmath.workprec(150):
        x = mpmath.mpf(1) / 3
    with pytest.raises(ValueError, match="not exactly a sum of 2 doubles"):
        encode_multi_double([x])
    with pytest.raises(ValueError):
        encode_multi_double([mpmath.inf])


def test_digits_choose_the_narrowest_type_that_holds_them():
    """31 digits (106 bits) run in C double-double, 32..60 (110..203 bits) in quad-double,
    61 in MPFR (C)."""
    assert Precision(31).arithmetic.name == "dd"
    assert Precision(32).arithmetic.name == "qd"
    assert Precision(60).arithmetic.name == "qd" and Precision(60).prec == QD_BITS
    assert Precision(61).arithmetic.name == "mpfr"
    ran = [
        integrate("chaplygin_ball", REFERENCE_Y0, 0.5, REFERENCE_PARAMS, precision=d).backend
        for d in (31, 32, 61)
    ]
    assert ran == ["c-dd", "c-qd", "c-mpfr"]


def _coefficient_error(code, kind_lib, t0, y, p, order, digits=31):
    """Largest |c - c_ref| / max_i |c_ref[i][k]| over the state coefficients, the library's
    coefficients read at ``digits``, the reference in MPFR at ``digits + 30`` from the same
    (exact) inputs."""
    with mpmath.workdps(digits + 30):
        with gmpy2.context(gmpy2.get_context(), precision=mpmath.mp.prec):
            ref = code.taylor.taylor_coefficients(
                _from_mpf(t0, "gmpy2"), [_from_mpf(v, "gmpy2") for v in y],
                [_from_mpf(v, "gmpy2") for v in p], order, python_lib("gmpy2"),
            )
            ref = [[_to_mpf(c) for c in row] for row in ref]
    with mpmath.workdps(digits):
        got = kind_lib.coefficients(order, t0, y, p)
    worst = mpmath.mpf(0)
    with mpmath.workdps(digits + 30):
        for k in range(order + 1):
            scale = max(abs(row[k]) for row in ref)
            if scale == 0:
                continue
            for g, r in zip(got, ref, strict=True):
                worst = max(worst, abs(g[k] - r[k]) / scale)
    return worst


# chaplygin_ball: products and a quotient; the potential surface: a rational power; variable
# inertia: sin and cos (the transcendental functions of the multi-double builds)
@pytest.mark.parametrize("kind,digits", [("dd", 31), ("qd", 60)])
@pytest.mark.parametrize(
    "system,effects",
    [
        ("chaplygin_ball", ()),
        ("ball_on_surface", ("potential",)),
        ("chaplygin_ball", ("variable_inertia",)),
    ],
)
def test_coefficients_match_mpfr_recurrences(system, effects, kind, digits):
    """Order-24 coefficients at generic non-dyadic data, against MPFR at 30 more digits (the
    refutation of a double-rounded parameter by this comparison: next test)."""
    code = load_model_code(system, effects)
    lib = load_taylor_library(code, kind)
    assert lib is not None and lib.kind == kind
    with mpmath.workdps(digits):
        n, m = len(code.state), len(code.params)
        y = [mpmath.mpf(3 + i) / (11 + 2 * i) * (-1) ** i for i in range(n)]
        p = [mpmath.mpf(13 + 3 * i) / (7 + i) for i in range(m)]
        t0 = mpmath.mpf(3) / 10
    order = 24
    err = _coefficient_error(code, lib, t0, y, p, order, digits)
    assert err < 2**10 * 2.0 ** -Precision(digits).prec, err
    # the first parameter rounded to double changes the coefficients
    p_double = [mpmath.mpf(float(p[0])), *p[1:]]
    with mpmath.workdps(digits):
        wrong = lib.coefficients(order, t0, y, p_double)
        right = lib.coefficients(order, t0, y, p)
    assert wrong != right  # the parameter's low limb reaches the recurrences


def test_double_rounded_parameter_is_refuted_by_the_coefficient_check():
    """The comparison of the previous test detects a parameter rounded to double."""
    code = load_model_code("chaplygin_ball")
    lib = load_taylor_library(code, "dd")
    with mpmath.workdps(31):
        y = [mpmath.mpf(3 + i) / (11 + 2 * i) for i in range(6)]
        p = [mpmath.mpf(13 + 3 * i) / (7 + i) for i in range(4)]

        class Rounded:
            """The library with its first parameter rounded to double on the way in."""

            def coefficients(self, order, t0, y, p):
                return lib.coefficients(order, t0, y, [mpmath.mpf(float(p[0])), *p[1:]])

    err = _coefficient_error(code, Rounded(), mpmath.mpf(0), y, p, 16)
    assert err > 2**10 * U_DD * 1e6, err


@pytest.mark.parametrize("digits,kind", [(31, "c-dd"), (60, "c-qd")])
def test_inputs_reach_the_compiled_code_to_the_last_digit(digits, kind):
    """The output at t0 comes back from the C run: it equals the working state."""
    prec = Precision(digits)
    r = integrate("chaplygin_ball", STATE_31, (0, 1.25), PARAMS, precision=digits,
                  t_eval=[0, "1.25"])
    assert r.backend == kind
    with mpmath.workdps(digits):
        y0 = pack_state(load_model_code("chaplygin_ball"), STATE_31, prec)
        assert list(r.y[:, 0]) == list(y0)
        assert r.t[-1] == mpmath.mpf("1.25")


@pytest.mark.parametrize("digits", [20, 31, 32, 45, 60])
def test_solution_agrees_with_mpfr(digits):
    """To T = 1.25 with non-dyadic inputs: the compiled multi-double run and the MPFR
    recurrences at the same digits both within the tolerance bound of an MPFR run at 30
    more digits."""
    T = "1.25"
    kw = {"t_eval": [0, T]}
    r = integrate("chaplygin_ball", STATE_31, (0, T), PARAMS, precision=digits, **kw)
    g = integrate("chaplygin_ball", STATE_31, (0, T), PARAMS, precision=digits,
                  backend="numpy", **kw)
    ref = integrate("chaplygin_ball", STATE_31, (0, T), PARAMS, precision=digits + 30,
                    backend="numpy", **kw)
    assert r.backend == ("c-dd" if digits <= 31 else "c-qd") and g.backend == "python-gmpy2"
    rtol = r.info["rtol"]
    with mpmath.workdps(digits + 30):
        scale = max(1, max(abs(v) for v in ref.y[:, -1]))
        bound = 10 * rtol * r.nsteps * scale
        for res in (r, g):
            err = max(abs(a - b) for a, b in zip(res.y[:, -1], ref.y[:, -1], strict=True))
            assert err < bound, (res.backend, err, bound)
    assert max(r.drift.values()) < 10 * rtol * r.nsteps


def test_mpfr_reference_agrees_with_odefun():
    """The MPFR reference route of the previous test, at 45 digits, against mpmath.odefun
    (mpmath's own Taylor method) at 45 digits: 1e-40 apart."""
    kw = {"t_eval": [0, "1.25"]}
    ref = integrate("chaplygin_ball", STATE_31, (0, "1.25"), PARAMS, precision=45,
                    backend="numpy", **kw)
    odefun = integrate("chaplygin_ball", STATE_31, (0, "1.25"), PARAMS, precision=45,
                       method="odefun", **kw)
    with mpmath.workdps(45):
        pairs = zip(odefun.y[:, -1], ref.y[:, -1], strict=True)
        assert max(abs(a - b) for a, b in pairs) < 1e-40


def _gamma3(t, y):
    return y[5]


@pytest.mark.parametrize("digits,kind", [(30, "c-dd"), (50, "c-qd")])
def test_events_on_the_multi_double_polynomial(digits, kind):
    """Zero crossings of gamma3: the same crossings as the MPFR path, times equal to the
    steps' tolerance summed over the steps."""
    kw = {"events": [_gamma3], "precision": digits}
    r = integrate("chaplygin_ball", REFERENCE_Y0, 12, REFERENCE_PARAMS, **kw)
    g = integrate("chaplygin_ball", REFERENCE_Y0, 12, REFERENCE_PARAMS, backend="numpy", **kw)
    assert r.backend == kind and g.backend == "python-gmpy2"
    te, tg = r.t_events[0], g.t_events[0]
    assert len(te) == len(tg) >= 2
    rtol = r.info["rtol"]
    with mpmath.workdps(digits):
        for a, b in zip(te, tg, strict=True):
            assert abs(a - b) < 10 * rtol * r.nsteps * max(1, abs(b))
        for ye in r.y_events[0]:
            assert abs(ye[5]) < 10 * rtol


@pytest.mark.parametrize("precision,digits", [("double", None), ("quad", None), ("digits", 30),
                                              ("digits", 50)])
def test_compiled_runs_resume_exactly_in_blocks(chunk_steps, precision, digits):
    """With a wall-time limit the compiled loop runs in blocks of steps (3 here), each
    resuming from the exact time and state the last reached: the same steps, orders and
    bits as one uninterrupted call, outputs inside and across blocks included."""
    import numpy as np
    from chaplygin.numerics import taylor

    code = load_model_code("chaplygin_ball")
    with mpmath.workdps(digits or 34):
        number = float if precision == "double" else mpmath.mpf
        y0 = [number(v) for v in ("0.7", "-0.4", "0.5", "0.2", "0.3")]
        y0.append(number(mpmath.sqrt(1 - sum(mpmath.mpf(v) ** 2 for v in y0[3:]))))
        p = [number(v) for v in (1, 2, 3, 1)]
        T = number(9)
        t_eval = [number(v) / 4 for v in range(0, 37, 5)]
        tol = 1e-12 if precision == "double" else 1e-20
        kw = {"precision": digits or precision, "rtol": tol, "atol": tol, "t_eval": t_eval}
        whole = taylor.taylor_solve(code, y0, (number(0), T), p, **kw)
        chunk_steps(whole.backend[2:], 3)
        blocks = taylor.taylor_solve(code, y0, (number(0), T), p, max_wall_s=1e6, **kw)
    assert whole.backend.startswith("c-") and whole.nsteps > 3 * 3
    assert (blocks.nsteps, blocks.order_min, blocks.order_max, blocks.status) == (
        whole.nsteps, whole.order_min, whole.order_max, 0)
    assert list(blocks.t) == list(whole.t) and len(blocks.t) == len(t_eval)
    assert np.array_equal(blocks.y, whole.y)


def test_without_a_compiler_digits_fall_back_to_mpfr(tmp_path, monkeypatch):
    """No C compiler: 30 digits run the MPFR recurrences after a CompilerUnavailableWarning,
    with the same result as the MPFR path asked for directly."""
    from chaplygin.numerics.compiled import CompilerUnavailableWarning
    from chaplygin.numerics.taylor import library as taylor_library

    expected = integrate("chaplygin_ball", REFERENCE_Y0, 0.5, REFERENCE_PARAMS, precision=30,
                         backend="numpy")
    monkeypatch.setattr(taylor_library, "_LIBS", {})
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("CC", "chaplygin-no-such-cc")
    with pytest.warns(CompilerUnavailableWarning, match="dd Taylor integrator unavailable"):
        r = integrate("chaplygin_ball", REFERENCE_Y0, 0.5, REFERENCE_PARAMS, precision=30)
    assert r.backend == "python-gmpy2" and r.success
    assert list(r.y[:, -1]) == list(expected.y[:, -1])


@pytest.mark.skipif(not taylor_fma_flags(), reason="no x86-64 FMA here")
def test_hardware_fma_gives_the_bits_of_dekkers_product():
    """The quad-double build with -mfma (exact products by fused multiply-add) and without
    (Dekker's splitting): the same coefficients and run, bit for bit."""
    import numpy as np
    from chaplygin.derive.emit.c_sources import taylor_source
    from chaplygin.numerics.ccompile import compile_c
    from chaplygin.numerics.taylor import CompiledTaylor, _c_run

    code = load_model_code("chaplygin_ball")
    source = taylor_source(code.taylor_c_source, "qd")
    libs = [CompiledTaylor(compile_c(source, cflags=flags), "qd") for flags in
            (("-O3",), ("-O3", "-mfma"))]
    with mpmath.workdps(50):
        y = [mpmath.mpf(3 + i) / (11 + 2 * i) for i in range(6)]
        p = [mpmath.mpf(13 + 3 * i) / (7 + i) for i in range(4)]
        span, tol = (mpmath.mpf(0), mpmath.mpf(40)), 1e-45
        runs = [_c_run(lib, y, span, p, tol, tol, [span[1]], None, None, 10**5) for lib in libs]
        coefficients = [lib.coefficients(20, span[0], y, p) for lib in libs]
    assert runs[0].nsteps == runs[1].nsteps > 1
    assert np.array_equal(runs[0].y, runs[1].y) and coefficients[0] == coefficients[1]


@pytest.mark.parametrize("value", ["19631876950440000/7", "-3**70/(2**60 + 1)", "-2**53 - 1"])
def test_integers_wider_than_a_double_are_printed_exactly(value):
    """A constant of the Taylor program whose numerator or denominator is wider than 2^53
    (decimal inputs multiplied out make them): printed in digits of 2^48, the macro
    expression evaluated with exact rational arithmetic is the constant itself (each
    digit and scaling exact; the working precision rounds only the sums)."""
    from fractions import Fraction

    from chaplygin.derive.emit.taylor_c import _TaylorMacroPrinter

    rational = sp.Rational(sp.sympify(value))
    text = _TaylorMacroPrinter({}).doprint(rational)
    assert "R_INT(" in text and all(
        abs(int(n)) <= 2**53 for n in re.findall(r"R_INT\((-?\d+)\)", text)
    )
    exact = {
        "R_INT": Fraction, "R_ADD": lambda a, b: a + b, "R_SUB": lambda a, b: a - b,
        "R_MUL": lambda a, b: a * b, "R_DIV": lambda a, b: a / b, "R_NEG": lambda a: -a,
    }  # fmt: skip
    got = eval(text, {"__builtins__": {}}, exact)  # our own printer's output, not user text
    assert got == Fraction(int(rational.p), int(rational.q))
