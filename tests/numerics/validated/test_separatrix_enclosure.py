"""Delta enclosed from the full equations (K01 §3.3): the enclosures contain references
computed by independent routes (the separatrix point and Delta by mpmath through
:mod:`chaplygin.numerics.ball.separatrix`: the floating high-precision integration and the
closed form; the tails by mpmath's quadrature) and are narrow enough for that to mean
something (a reference moved by three widths falls outside)."""

from __future__ import annotations

import mpmath
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics.ball.separatrix import (
    delta_closed_form,
    delta_ode,
    mu_of,
    separatrix_state,
)
from chaplygin.numerics.ball.separatrix_enclosure import (
    enclose_delta,
    separatrix_ball,
    tail_series,
)
from chaplygin.numerics.validated import working_precision
from flint import arb

#: A generic body (not one of the papers'), as typed.
BODY = (("1.1", "1.7", "2.3"), "0.9")
DPS = 50


def _ref(value: mpmath.mpf, digits: int) -> arb:
    """The reference as a ball at 256 bits: its decimal rounding at ``digits`` digits and
    ``10^(3 - digits)`` relative for the error of the route that computed it."""
    with working_precision(256):
        return arb(mpmath.nstr(value, digits)) + arb(
            0, 10.0 ** (3 - digits) * (1 + abs(float(value)))
        )


@pytest.fixture(scope="module")
def generic() -> object:
    I, D = BODY
    return enclose_delta(I, D, "0.8", L=6, terms=4, prec=128, order=20, tol=1e-14)


def test_the_separatrix_point_contains_the_mpmath_state() -> None:
    I, D = BODY
    state, rates = separatrix_ball(I, D, "1.3", prec=256)
    with mpmath.workdps(DPS):
        ref = separatrix_state([mpmath.mpf(v) for v in I], mpmath.mpf(D), mpmath.mpf("1.3"))
    assert len(state) == 14
    for ball, value in zip(state, ref, strict=True):
        r = _ref(value, DPS)
        assert r.contains(ball)  # agrees with mpmath to its 47 digits
        assert float(ball.rad()) < 1e-60
        if value != 0:
            assert not r.contains(ball + arb(10.0 ** (-44)))
    with mpmath.workdps(DPS):
        assert _ref(mu_of([mpmath.mpf(v) for v in I], mpmath.mpf(D)), DPS).contains(rates["mu"])


def test_the_enclosure_contains_the_floating_and_the_closed_form(generic) -> None:
    I, D = BODY
    r = generic
    with mpmath.workdps(40):
        Iv, Dv = [mpmath.mpf(v) for v in I], mpmath.mpf(D)
        ode = delta_ode(Iv, Dv, mpmath.mpf("0.8"), 22)
        closed = delta_closed_form(mu_of(Iv, Dv), mpmath.mpf("0.8"), 30)
    for value, digits in ((ode["delta"], 20), (closed, 28)):
        ref = _ref(value, digits)
        assert r.delta.contains(ref)
        moved = ref + 3 * r.width
        assert not r.delta.contains(moved)
    assert r.delta.contains(r.closed)
    assert r.contains(mpmath.nstr(closed, 30))  # a decimal string, enclosed at r.prec
    assert r.y_shift.contains(0)  # K01-3.6: y(+oo) = y(-oo)
    assert r.width < 1e-6 * float(r.delta.mid())
    assert r.signed < 0  # the contact point moves along -alpha (nu = -b lam)


@pytest.mark.parametrize("terms", [0, 1, 3])
def test_the_tail_series_contains_the_quadrature(terms: int) -> None:
    with mpmath.workdps(30), working_precision(128):
        mu, L = mpmath.mpf("1.7"), mpmath.mpf(3)
        Fc, Fs = tail_series(arb("1.7"), arb(3), terms)
        for ball, f in ((Fc, mpmath.cos), (Fs, mpmath.sin)):
            value = mpmath.quad(lambda s, f=f: f(mu * s) / mpmath.cosh(s), [L, 10, 40, mpmath.inf])
            assert ball.contains(_ref(value, 25))
            bound = 2 * mpmath.exp(-(2 * terms + 1) * L) / (2 * terms + 1)
            assert float(ball.rad()) >= float(bound)
            assert float(ball.rad()) < 1.01 * float(bound) + 1e-25


@pytest.mark.parametrize(
    "kwargs",
    [
        {"I": ("1.7", "1.1", "2.3")},  # I2 not the middle, or the order reversed
        {"I": ("2.3", "1.7", "1.1")},
        {"I": ("1.1", "1.7")},
        {"I": ("1.1", "nan", "2.3")},
        {"D": "0"},
        {"b": "-1"},
        {"C": "-1"},
        {"L": 0.5},
        {"L": True},
        {"terms": -1},
        {"prec": 10},
        {"order": 1},
        {"tol": -1e-20},
        {"tol": float("nan")},
    ],
)
def test_bad_input_is_refused(kwargs: dict) -> None:
    args = {"I": BODY[0], "D": BODY[1], "b": 1, "C": 1}
    args.update(kwargs)
    with pytest.raises(UserInputError):
        enclose_delta(**args)
