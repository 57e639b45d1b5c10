"""The number parser: bounded before it evaluates, real results only, one error type.

Hostile text (towers of powers, huge exponents, deep nesting, complex results, junk) must
end in a finite real ``mpf`` or a :class:`UserInputError`, quickly, never in another
exception, a hang or a large allocation (issue 11, the parser's limits).
"""

from __future__ import annotations

import mpmath
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics.inputs import MAX_LOG10, MAX_TEXT, Precision, parse_number, working_number
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

literals = st.one_of(
    st.integers(-(10**30), 10**30).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.builds(lambda m, e: f"{m}e{e}", st.integers(-99, 99), st.integers(-10**6, 10**6)),
    st.sampled_from(["pi", "e", "nan", "inf", "x", "__import__", "0x10", "1_000", ".5", "5."]),
)


def _combine(children):
    ops = st.sampled_from(["+", "-", "*", "/", "**", "%", "//", "<<", "@", ","])
    funcs = st.sampled_from(["sqrt", "cbrt", "exp", "log", "sin", "cos", "open", "eval", ""])
    return st.one_of(
        st.builds(lambda a, o, b: f"({a}){o}({b})", children, ops, children),
        st.builds(lambda f, a: f"{f}({a})", funcs, children),
        st.builds(lambda a: f"-{a}", children),
        st.builds(lambda a, n: "-" * n + a, children, st.integers(0, 200)),
    )


expressions = st.recursive(literals, _combine, max_leaves=12)
junk = st.text(max_size=80)


def _assert_number_or_user_error(text: str, dps: int) -> None:
    try:
        value = parse_number(text, dps)
    except UserInputError as exc:
        assert str(exc) and "\n" not in str(exc)
        return
    assert isinstance(value, mpmath.mpf) and mpmath.isfinite(value)
    assert value == 0 or abs(float(mpmath.log10(abs(value)))) <= MAX_LOG10 + 1


@pytest.mark.quick
@settings(max_examples=400, deadline=2000, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(expressions, junk), st.sampled_from([15, 30, 100]))
def test_hostile_text_is_a_number_or_a_user_error(text, dps):
    _assert_number_or_user_error(text, dps)


@pytest.mark.quick
@settings(max_examples=200, deadline=2000)
@given(expressions, st.sampled_from(["double", "quad", 40]))
def test_hostile_text_at_a_working_precision(text, precision):
    try:
        value = working_number(text, Precision(precision))
    except UserInputError:
        return
    assert mpmath.isfinite(value)


@pytest.mark.quick
@pytest.mark.parametrize(
    ("text", "why"),
    [
        ("9**9**9**9", "power is beyond"),
        ("2**2**2**2**2**2", "power is beyond"),
        ("exp(1e10)", "exp of"),
        ("sqrt(-1)", "not real"),
        ("log(-1)", "not real"),
        ("(-8)**(1/3)", "not real"),
        ("-" * 50_000 + "1", "too long"),
        ("-" * 60 + "1", "nested deeper"),
        ("1e99999", "beyond"),
        ("1/0", "division by zero"),
        ("log(0)", "not finite"),
        ("sin(1e999)", "beyond 1e100"),
        ("__import__('os')", "cannot read"),
    ],
)
def test_the_reported_hostile_inputs_are_refused_with_a_reason(text, why):
    with pytest.raises(UserInputError, match=why):
        parse_number(text, 30)


@pytest.mark.quick
def test_limits_leave_ordinary_inputs_alone():
    assert parse_number("cbrt(-8)", 30) == -2
    assert parse_number("(-8)**3", 30) == -512
    assert parse_number("1e-400", 30) > 0
    assert len("sqrt(0.87)") < MAX_TEXT
