"""``[initial]`` with ``M`` (a direction), ``gamma`` and ``h``: M scaled to the energy h.

The reference energy is BKM12-3's closed form, typed here (not the generated integral):
``H = (M, omega)/2``, ``omega = A (M + Z gamma)``, ``Z = (A M, gamma) / (D^-1 - (gamma, A
gamma))``, ``A = (I + D)^-1``, evaluated at 40 digits; the tolerance is 30 digits' worth
(the state is rounded to the 30-digit working precision once).
"""

from __future__ import annotations

import mpmath
import pytest
from chaplygin.numerics.ball.initial_state import InitialStateError, initial_state
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.precision import Precision

I = ("1.3", "2.1", "2.9")  # noqa: E741
D = "0.7"


def _bkm12_3_energy(y):
    with mpmath.workdps(40):
        A = [1 / (mpmath.mpf(i) + mpmath.mpf(D)) for i in I]
        M, g = [mpmath.mpf(v) for v in y[:3]], [mpmath.mpf(v) for v in y[3:6]]
        gAg = sum(a * x * x for a, x in zip(A, g, strict=True))
        Z = sum(a * m * x for a, m, x in zip(A, M, g, strict=True)) / (1 / mpmath.mpf(D) - gAg)
        omega = [a * (m + Z * x) for a, m, x in zip(A, M, g, strict=True)]
        return sum(m * w for m, w in zip(M, omega, strict=True)) / 2


def test_the_ball_scaled_to_an_energy_matches_bkm12_3():
    code = load_model_code("chaplygin_ball")
    params = {"I1": I[0], "I2": I[1], "I3": I[2], "D": D}
    request = {"M": [0.3, -0.7, 1.1], "gamma": [0.28, 0.3, "sqrt(1 - 0.28**2 - 0.3**2)"]}
    got = initial_state(code, params, {**request, "h": "0.4321"}, Precision(30))
    assert "scaled to the energy" in got.how
    with mpmath.workdps(40):
        assert abs(_bkm12_3_energy(got.y0) - mpmath.mpf("0.4321")) < mpmath.mpf(10) ** -28
        ratio = [
            mpmath.mpf(a) / mpmath.mpf(b) for a, b in zip(got.y0[:3], [0.3, -0.7, 1.1], strict=True)
        ]
        assert max(ratio) - min(ratio) < mpmath.mpf(10) ** -28  # the direction is kept


def test_an_energy_no_multiple_reaches_is_refused():
    code = load_model_code("chaplygin_ball")
    params = {"I1": I[0], "I2": I[1], "I3": I[2], "D": D}
    request = {"M": [0.3, -0.7, 1.1], "gamma": [0, 0, 1], "h": "-0.1"}
    with pytest.raises(InitialStateError, match="no multiple of the given M") as info:
        initial_state(code, params, request, Precision("double"))
    assert info.value.key == "h"
