"""Steady rotations of the Chaplygin ball proved stable or unstable in ball arithmetic: the
closed-form orbit checked against the generated equations, the enclosed trace against an
independent mpmath integration of the variational equations (mpmath.odefun, 25 digits), the
verdicts against K01's rule for a generic body, bad input refused."""

from __future__ import annotations

import mpmath
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import load_model_code
from chaplygin.numerics.ball.steady_enclosure import (
    prove_steady_rotation_stability,
    steady_rotation_ball,
)
from chaplygin.numerics.validated.lohner import working_precision
from flint import arb

#: A generic body (no dyadic numbers, A_i = 1/(I_i + D) ordered A1 > A2 > A3: e_2 is the
#: middle axis) on a level with a short period (C large: the time scale only).
BODY, D, C, MG = ("1.1", "1.7", "2.3"), "0.9", "40", "0.37"


def _mp(b: arb) -> mpmath.mpf:
    return mpmath.mpf(b.mid().str(40, radius=False))


def test_closed_form_orbit_is_a_steady_rotation_of_the_generated_equations() -> None:
    code = load_model_code("chaplygin_ball")
    with working_precision(160), mpmath.workdps(40):
        for axis in range(3):
            for branch in (0, 1):
                y0, T = steady_rotation_ball(BODY, D, axis, C, MG, branch)
                M, g = y0[:3], y0[3:]
                # on the level: |gamma| = 1, (M, M) = C, (M, gamma) = M_gamma
                assert (sum(c * c for c in g) - 1).contains(0)
                assert (sum(c * c for c in M) - arb(C)).contains(0)
                assert (sum(a * b for a, b in zip(M, g, strict=True)) - arb(MG)).contains(0)
                # the model's gamma' is gamma x w e_a with |w| = 2 pi/T: a rotation about e_a
                y = [_mp(v) for v in y0]
                p = [mpmath.mpf(v) for v in BODY] + [mpmath.mpf(D)]
                f = code.mpmath.rhs(0, y, p)
                w = (1 if branch else -1) * 2 * mpmath.pi / _mp(T)
                omega = [w if i == axis else 0 for i in range(3)]
                cross = [
                    y[4] * omega[2] - y[5] * omega[1],
                    y[5] * omega[0] - y[3] * omega[2],
                    y[3] * omega[1] - y[4] * omega[0],
                ]
                assert max(abs(f[3 + i] - cross[i]) for i in range(3)) < mpmath.mpf(10) ** -35
                assert f[axis] == 0 or abs(f[axis]) < mpmath.mpf(10) ** -35  # M_a is constant


def _mpmath_trace(axis: int, branch: int) -> mpmath.mpf:
    """``tr Phi(T) - 4`` by mpmath.odefun on the generated mpmath ``rhs`` and ``jac``."""
    code = load_model_code("chaplygin_ball")
    with working_precision(160):
        y0, T = steady_rotation_ball(BODY, D, axis, C, MG, branch)
    p = [mpmath.mpf(v) for v in BODY] + [mpmath.mpf(D)]

    def F(t: mpmath.mpf, z: list) -> list:
        x, V = z[:6], z[6:]
        J = code.mpmath.jac(t, x, p)
        dV = [sum(J[i][k] * V[6 * k + j] for k in range(6)) for i in range(6) for j in range(6)]
        return list(code.mpmath.rhs(t, x, p)) + dV

    z0 = [_mp(v) for v in y0] + [mpmath.mpf(int(i == j)) for i in range(6) for j in range(6)]
    zT = mpmath.odefun(F, 0, z0)(_mp(T))
    return sum(zT[6 + 7 * i] for i in range(6)) - 4


@pytest.mark.parametrize(("axis", "verdict"), [(0, "elliptic"), (1, "hyperbolic")])
def test_enclosed_trace_contains_an_independent_reference(axis: int, verdict: str) -> None:
    with mpmath.workdps(25):
        reference = _mpmath_trace(axis, 1)
        r = prove_steady_rotation_stability(BODY, D, axis, C, MG, 1, prec=64, order=16, tol=1e-14)
        ref = arb(mpmath.nstr(reference, 25))
    # mpmath's own error (~1e-24) is far below the enclosure's width
    assert r.trace.contains(ref)
    width = 2 * float(r.trace.rad())
    assert width < 1e-9
    assert not r.trace.contains(ref + 3 * width) and not r.trace.contains(ref - 3 * width)
    # K01's rule: the extreme axes elliptic, the middle one hyperbolic
    assert r.verdict == verdict
    assert r.det.contains(1)  # det Phi = 1 (the invariant density BKM12-4)
    if verdict == "hyperbolic":
        t = reference
        assert r.multiplier.contains(arb(mpmath.nstr((abs(t) + mpmath.sqrt(t * t - 4)) / 2, 25)))


def test_bad_input_is_refused() -> None:
    with pytest.raises(UserInputError, match="axis"):
        steady_rotation_ball(BODY, D, 3)
    with pytest.raises(UserInputError, match="no steady rotation"):
        steady_rotation_ball(BODY, D, 0, "1", "1.2")  # M_gamma^2 > C
    with pytest.raises(UserInputError, match="positive"):
        steady_rotation_ball(BODY, "-0.9", 0)
    with pytest.raises(UserInputError):
        steady_rotation_ball(("1", "2"), D, 0)


def test_the_claims_are_rigorous_with_their_expected_verdicts() -> None:
    from chaplygin.verify.claims import REGISTRY

    for cid, expected in (
        ("BKM12-1.5stab.enclosed", "holds"),
        ("BKM12-1.5stab8.enclosed", "holds"),
        ("BKM12-1.5stab.enclosed/control-middle-stable", "fails"),
    ):
        claim = REGISTRY[cid]
        assert claim.rigorous and claim.expected == expected
