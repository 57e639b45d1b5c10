"""Every number a user types reaches the integrators at the working precision (issue 9).

Each built-in system and effect combination is integrated at 30 digits (the generated
Taylor integrator on gmpy2/MPFR) and in quad (the C ``__float128`` Taylor integrator) with
non-dyadic decimal parameters, initial state and end time given as text, and compared with
an independent route: ``mpmath.odefun`` (mpmath's own Taylor-series method, not our
recurrences) at 40 digits, with the same numbers given as ``fractions.Fraction`` (exact
rationals, read by a different branch of the input code than decimal text). Before the fix
the 30-digit results were off by about 1e-16 (parameters rounded to double).

Tolerances come from the requested tolerance: the Taylor control keeps each local error
below ``rtol`` (default ``Precision.min_rtol``) relative to the state's size; the bound
allows ``10 * rtol`` per step, summed over the steps, on the scale ``max(1, |y|)``. The
reference's own error (40 digits) is negligible against it.
"""

from __future__ import annotations

import math
from decimal import Decimal
from fractions import Fraction

import gmpy2
import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate, load_model_code
from chaplygin.numerics.inputs import Precision, pack_params, working_number
from hypothesis import given
from hypothesis import strategies as st

T_END = "1.37"

# non-dyadic decimals for every parameter of every built-in system
PARAMETERS: dict[str, str | tuple[str, ...]] = {
    "I": ("1.2716", "2.9031", "4.4187"),
    "D": "0.6513",
    "b": "0.7213",
    "K": ("0.131", "-0.217", "0.319"),
    "J_off": "0.113",
    "delta": "0.2371",
    "Omega": "1.0713",
    "D_iso": "0.4113",
    "D_al": "0.1217",
    "D_be": "-0.0913",
    "m": "1.3",
    "m_e": "0.7",
    "R": "0.31",
    "k": "0.53",
    "c": ("0.011", "0.023", "0.031"),
}
ELLIPSOID = ("1.13", "2.07", "2.91")  # b of ball_on_surface: (x, B^-1 x) = 1, B = diag(b)

# (system, effects): every variant that generated/ holds and integrate() accepts
VARIANTS = [
    ("chaplygin_ball", ()),
    ("chaplygin_ball", ("gyrostat",)),
    ("chaplygin_ball", ("contact_point",)),
    ("chaplygin_ball", ("contact_point", "gyrostat")),
    ("chaplygin_ball", ("rubber",)),
    ("chaplygin_ball", ("straight_line",)),
    ("chaplygin_ball", ("variable_inertia",)),
    ("chaplygin_ball", ("variable_gyrostat", "variable_inertia")),
    ("chaplygin_ball", ("contact_point", "variable_gyrostat", "variable_inertia")),
    ("spherical_support", ()),
    ("spherical_support", ("gyrostat",)),
    ("ball_on_surface", ()),
    ("ball_on_surface", ("potential",)),
]


def _frame() -> tuple[list[Fraction], list[Fraction], list[Fraction]]:
    """A generic rational right-handed frame: the rotation of the quaternion (1, 2, 3, 4)/sqrt 30.

    Its entries (k/15, k/30) have non-terminating decimal expansions: they reach the code
    as the text "k/30".
    """
    a, b, c, d = 1, 2, 3, 4
    n = Fraction(a * a + b * b + c * c + d * d)
    R = [
        [a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)],
        [2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)],
        [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d],
    ]
    cols = [[Fraction(R[i][j]) / n for i in range(3)] for j in range(3)]
    return cols[0], cols[1], cols[2]


def _cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def _dot(u, v):
    return sum(x * y for x, y in zip(u, v, strict=True))


def _text(q: Fraction) -> str:
    return f"{q.numerator}/{q.denominator}" if q.denominator != 1 else str(q.numerator)


def _problem(system: str, effects: tuple[str, ...]):
    """Parameters and initial state of a variant, as text and as exact references.

    Returns ``(params_text, y0_text, params_exact, y0_exact)``: text goes through the
    parser; the exact values are ``Fraction`` (or, for the ellipsoid's square roots,
    ``mpf`` computed at 80 digits from fractions).
    """
    code = load_model_code(system, effects)
    ptext = {name: PARAMETERS[name] for name in code.parameter_groups}
    if system == "ball_on_surface":
        ptext["b"] = ELLIPSOID

    def exact(v):
        return tuple(Fraction(x) for x in v) if isinstance(v, tuple) else Fraction(v)

    pexact = {k: exact(v) for k, v in ptext.items()}
    alpha, beta, gamma = _frame()
    u = [Fraction("0.31"), Fraction("-0.57"), Fraction("0.23")]
    if system == "ball_on_surface":
        unit = [Fraction("0.36"), Fraction("0.48"), Fraction("0.8")]
        ytext = {
            "omega": ("0.31", "-0.57", "0.23"),
            "x": tuple(f"sqrt({bi})*{ui}" for bi, ui in zip(ELLIPSOID, ("0.36", "0.48", "0.8"),
                                                             strict=True)),
        }
        with mpmath.workdps(80):
            x = tuple(
                mpmath.sqrt(mpmath.mpf(Fraction(bi).numerator) / Fraction(bi).denominator)
                * (mpmath.mpf(ui.numerator) / ui.denominator)
                for bi, ui in zip(ELLIPSOID, unit, strict=True)
            )
        return ptext, ytext, pexact, {"omega": tuple(u), "x": x}
    groups = code.state_groups
    I, D = pexact["I"], pexact.get("D", Fraction(0))
    if "rubber" in effects:  # (omega, gamma) = 0: omega = gamma x u, M = (I + D) omega
        omega = _cross(gamma, u)
        M = [(I[i] + D) * omega[i] for i in range(3)]
    elif "straight_line" in effects:  # (omega, alpha) = 0; M = I omega + D gamma x (omega x gamma)
        omega = _cross(alpha, u)
        M = [(I[i] + D) * omega[i] - D * gamma[i] * _dot(gamma, omega) for i in range(3)]
    else:
        M = [Fraction("-0.31"), Fraction("0.83"), Fraction("0.47")]
    yexact: dict[str, tuple] = {"M": tuple(M), "gamma": tuple(gamma)}
    if "alpha" in groups:
        yexact.update(alpha=tuple(alpha), beta=tuple(beta))
    if "x" in groups:
        yexact.update(x=(Fraction("0.17"),), y=(Fraction("-0.29"),))
    ytext = {k: tuple(_text(q) for q in v) for k, v in yexact.items()}
    return ptext, ytext, pexact, yexact


def _as_fraction(x: mpmath.mpf) -> Fraction:
    man, exp = x.man_exp  # (not mpmath.mpf(x): that rounds to the context's precision)
    return Fraction(int(man)) * Fraction(2) ** int(exp)


def _max_error(result, reference) -> mpmath.mpf:
    with mpmath.workdps(60):
        return max(
            abs(mpmath.mpf(a) - mpmath.mpf(b))
            for a, b in zip(result.y[:, -1], reference.y[:, -1], strict=True)
        )


def _bound(result, precision: Precision) -> mpmath.mpf:
    rtol = precision.min_rtol  # the default tolerance of the run
    scale = max([1.0] + [abs(float(v)) for v in result.y[:, -1]])
    return 10 * max(result.nsteps, 1) * rtol * scale


@pytest.fixture(scope="module")
def references():
    """The odefun reference of every variant at 40 digits from exact fractions (cached)."""
    cache = {}

    def get(system, effects):
        key = (system, effects)
        if key not in cache:
            _, _, pexact, yexact = _problem(system, effects)
            cache[key] = integrate(
                system, yexact, (Fraction(0), Fraction(T_END)), pexact, effects=effects,
                precision=40, method="odefun",
            )
        return cache[key]

    return get


@pytest.mark.slow
@pytest.mark.parametrize("precision", [30, "quad"], ids=["30digits", "quad"])
@pytest.mark.parametrize(("system", "effects"), VARIANTS, ids=lambda v: "+".join(v) if
                         isinstance(v, tuple) else v)
def test_decimal_inputs_give_the_working_precision(system, effects, precision, references):
    ptext, ytext, _, _ = _problem(system, effects)
    r = integrate(system, ytext, T_END, ptext, effects=effects, precision=precision)
    assert r.success, r.message
    prec = Precision(precision)
    err, bound = _max_error(r, references(system, effects)), _bound(r, prec)
    assert err <= bound, f"{system} {effects} {prec!r}: error {mpmath.nstr(err, 3)} > {bound:.1e}"
    # t is reported exactly as asked
    with mpmath.workprec(prec.prec):
        assert r.t[-1] == mpmath.mpf(T_END)


def test_a_double_rounded_parameter_is_caught_by_the_same_comparison(references):
    """Negative control: the defect of issue 9 (a parameter rounded to double) is refuted."""
    system, effects = "chaplygin_ball", ()
    ptext, ytext, _, _ = _problem(system, effects)
    ptext = dict(ptext, D=float(ptext["D"]))  # 0.6513 as the double nearest to it
    r = integrate(system, ytext, T_END, ptext, effects=effects, precision=30)
    err, bound = _max_error(r, references(system, effects)), _bound(r, Precision(30))
    assert err > 1e6 * bound


@pytest.mark.parametrize("precision", ["double", "quad", 30, 50, 100])
def test_each_parameter_equals_the_decimal_given_to_the_last_digit(precision):
    code = load_model_code("chaplygin_ball", ("contact_point",))
    prec = Precision(precision)
    given = {"I": ("1.2716", "2.9031", "0.1e1"), "D": "0.6513", "b": "7.213e-1"}
    values = pack_params(code, given, prec)
    texts = [*given["I"], given["D"], given["b"]]
    for value, text in zip(values, texts, strict=True):
        if prec.is_double:
            assert value == float(text)  # Python's correctly rounded conversion
        else:
            with mpmath.workprec(prec.prec):
                assert value == mpmath.mpf(text)
            # and exactly the binary number nearest to the decimal (independent check by
            # integer arithmetic: |value - decimal| <= half an ulp)
            q = Fraction(text)
            exact = _as_fraction(value)
            m, e = mpmath.frexp(value)
            half_ulp = Fraction(2) ** (int(e) - prec.prec - 1)
            assert abs(exact - q) <= half_ulp


@pytest.mark.parametrize(
    "value",
    [
        "0.6513",
        Fraction(6513, 10000),
        Decimal("0.6513"),
        gmpy2.mpfr("0.6513", 300),
        "6513/10000",
        "6.513e-1",
    ],
    ids=["str", "Fraction", "Decimal", "mpfr300", "expression", "exponent"],
)
@pytest.mark.parametrize("precision", ["quad", 30, 60])
def test_every_number_type_reaches_the_working_precision(value, precision):
    prec = Precision(precision)
    with mpmath.workprec(prec.prec):
        assert working_number(value, prec) == mpmath.mpf("0.6513")


def test_a_float_is_its_exact_binary_value():
    prec = Precision(40)
    x = working_number(0.1, prec)
    assert _as_fraction(x) == Fraction(0.1)
    assert working_number(np.float64(0.1), prec) == x
    # a numpy float32 too is its own binary value (not the double nearest to 0.1)
    assert _as_fraction(working_number(np.float32(0.1), prec)) == Fraction(float(np.float32(0.1)))
    assert working_number("0.1", prec) != x


def test_times_keep_their_digits():
    y0 = {"M": ("-0.3", "0.8", "0.45"), "gamma": ("0.36", "0.48", "0.8")}
    p = {"I": ("1.7", "2.9", "4.4"), "D": "0.65"}
    r = integrate("chaplygin_ball", y0, ("0.1", "13.7"), p, precision=30,
                  t_eval=["0.1", "2.3", "13.7"])
    with mpmath.workdps(30):
        assert list(r.t) == [mpmath.mpf("0.1"), mpmath.mpf("2.3"), mpmath.mpf("13.7")]
    r = integrate("chaplygin_ball", y0, "13.7", p, precision="quad")
    with mpmath.workprec(113):
        assert r.t[-1] == mpmath.mpf("13.7")


def test_drift_is_evaluated_with_the_parameters_of_the_trajectory():
    """30 digits: every integral, H included, is kept to the working precision."""
    y0 = {"M": ("-0.3", "0.8", "0.45"), "gamma": ("0.36", "0.48", "0.8")}
    p = {"I": ("1.7", "2.9", "4.4"), "D": "0.65"}
    r = integrate("chaplygin_ball", y0, "20", p, precision=30)
    for name, value in r.drift.items():
        assert value < 100 * Precision(30).min_rtol, (name, value)


@pytest.mark.parametrize("text", ["1e309", "-1e400", "1e-400"])
def test_a_value_double_cannot_hold_is_refused_in_double(text):
    with pytest.raises(UserInputError, match="double precision"):
        working_number(text, Precision("double"))
    with mpmath.workprec(Precision(30).prec):
        assert working_number(text, Precision(30)) == mpmath.mpf(text)


def test_a_fractional_number_of_digits_is_refused():
    with pytest.raises(UserInputError, match="20.7"):
        Precision(20.7)
    assert Precision(20.0).digits == 20


# ------------------------------------------------ double fast path: same as rounding once


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_double_fast_path_of_floats_is_the_exact_value(x):
    got = working_number(x, Precision("double"))
    assert got == x and np.signbit(got) == np.signbit(x)  # -0.0 and subnormals kept
    assert working_number(np.float64(x), Precision("double")) == x
    # the general route (the exact value, then rounded once) agrees
    assert working_number(Fraction(x), Precision("double")) == x


@given(st.integers(min_value=-(2**62), max_value=2**62))
def test_double_fast_path_of_ints_rounds_once_correctly(n):
    # Fraction -> float is correctly rounded (half to even): an independent route
    assert working_number(n, Precision("double")) == float(Fraction(n))


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf"), np.float64("nan")])
def test_double_fast_path_still_refuses_non_finite(bad):
    with pytest.raises(UserInputError, match="not finite"):
        working_number(bad, Precision("double"))


def test_double_fast_path_refuses_bools():
    with pytest.raises(UserInputError):
        working_number(True, Precision("double"))


@given(
    st.integers(min_value=-(2**70), max_value=2**70),
    st.integers(min_value=-1200, max_value=1100),
)
def test_double_fast_path_of_mpf_rounds_once_correctly(m, e):
    """An mpf of any size (the fast path takes those of at most 53 bits in the normal range,
    the others go the general way): rounded to nearest once, as Fraction -> float does
    (an independent route; overflow refused either way)."""
    with mpmath.workprec(200):
        x = mpmath.ldexp(mpmath.mpf(m), e)
    exact = Fraction(m) * Fraction(2) ** e
    try:
        want = float(exact)
    except OverflowError:
        with pytest.raises(UserInputError):
            working_number(x, Precision("double"))
        return
    if math.isinf(want):  # pragma: no cover - float(Fraction) raises instead
        return
    try:
        got = working_number(x, Precision("double"))
    except UserInputError:  # refused: rounds to infinity, or a nonzero value to zero
        assert abs(exact) >= Fraction(2) ** 1024 * (1 - Fraction(1, 2**54)) or (
            want == 0 and exact != 0
        )
        return
    assert got == want
