"""The rigorous section map against the pendulum's closed form: from rest at theta0 the
pendulum first crosses theta = 0 at the complete elliptic integral K(k^2), k = sin(theta0/2),
with the velocity -2k; the section map's derivative in theta0 is -sin(theta0)/(2k)."""

from __future__ import annotations

import mpmath
import pytest
from chaplygin.derive.errors import ComputationError
from chaplygin.numerics.validated.lohner import working_precision
from chaplygin.numerics.validated.sections import enclose_crossing
from flint import arb

from .test_lohner import PENDULUM


def _ref(value: mpmath.mpf) -> arb:
    with working_precision(256):
        return arb(mpmath.nstr(value, 40)) + arb(0, 1e-36)


def test_the_pendulum_crosses_theta_0_at_the_elliptic_integral() -> None:
    theta0 = "2.1"
    c = enclose_crossing(
        PENDULUM, [], [theta0, "0"], 0, ("1.9", "2.3"), lambda y: y[0], jacobian=True
    )
    with mpmath.workdps(40):
        k = mpmath.sin(mpmath.mpf(theta0) / 2)
        K = mpmath.ellipk(k * k)
        assert c.time.contains(_ref(K))
        assert not c.time.contains(_ref(K + 3 * 2 * float(c.time.rad())))
        assert c.state[1].contains(_ref(-2 * k))
        dv = -mpmath.sin(mpmath.mpf(theta0)) / (2 * k)
        assert c.jacobian[1][0].overlaps(_ref(dv))
        assert c.jacobian[0][0].contains(0) and c.jacobian[0][1].contains(0)  # theta stays 0
    assert float(c.time.rad()) < 2**-52  # narrower than one rounding of a double
    assert not c.transversality.contains(0)


def test_no_crossing_in_the_window_is_an_error() -> None:
    """Control: the same machinery refuses a window before the crossing (no sign change)."""
    with pytest.raises(ComputationError, match="sign change"):
        enclose_crossing(PENDULUM, [], ["2.1", "0"], 0, ("0.5", "1.0"), lambda y: y[0])
