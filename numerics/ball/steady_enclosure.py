"""Stability of the Chaplygin ball's steady rotations proved by computation (BKM12 §1.5).

A steady rotation about the body axis ``e_a`` is ``omega = w e_a``, ``gamma(t)`` turning
about ``e_a`` with ``gamma_a = g`` fixed, ``M = (I_a + D) w e_a - D w g gamma`` (BKM12-crit):
an exact periodic solution of period ``T = 2 pi/|w|`` of ``M' = M x omega``,
``gamma' = gamma x omega`` (BKM12-2). On the level ``(M, M) = C``, ``(M, gamma) = M_gamma``,
``|gamma| = 1``: ``I_a w g = M_gamma`` and ``w^2 = (C + D (2 I_a + D) M_gamma^2/I_a^2)/(I_a +
D)^2``, so the state and the period are closed forms, enclosed here in Arb balls.

The monodromy ``Phi = d phi_T/d y0`` is enclosed by the validated integrator
(:func:`~chaplygin.numerics.validated.enclose_flow`, C^1). Its multipliers follow from three
facts proved symbolically by ``chaplygin verify``:

- ``F0 = (gamma, gamma)``, ``F1 = (M, M)``, ``F2 = (M, gamma)`` are integrals (BKM12-5.F0,
  F1, F2); their gradients ``G`` at ``y0`` have rank 3 (a 3 x 3 minor enclosed away from 0).
  Since ``y(T) = y0``, ``G Phi = G``: ``Phi`` keeps ``K = ker G`` and induces the identity on
  ``R^6/K`` (three multipliers 1).
- ``Phi f(y0) = f(y0)`` (``f`` the vector field): on ``K`` one more multiplier 1, and a map
  ``B`` on ``K/span f`` (2 x 2).
- ``rho = (D^-1 - (gamma, A gamma))^-1/2`` is an invariant density (BKM12-4): Liouville's
  formula gives ``det Phi = rho(y0)/rho(y(T)) = 1``, so ``det B = 1``.

The characteristic polynomial of ``Phi`` is therefore ``(l - 1)^4 (l^2 - t l + 1)`` with
``t = tr B = tr Phi - 4``: ``|t| < 2`` proves the other two multipliers ``exp(+-i theta)``,
``theta`` not 0 or pi (every multiplier of modulus 1: BKM12's "stable"); ``|t| > 2`` proves
a real multiplier of modulus above 1 (unstable). The enclosure of ``det Phi`` containing 1
and of ``y(T)`` containing ``y0`` are checks of the computation, not hypotheses.

References
----------
BKM12-1.5stab, BKM12-1.5stab8, BKM12-crit, BKM12-4, BKM12-5 (FORMULAS.md).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

from flint import arb, arb_mat

from ...derive.errors import ComputationError, UserInputError
from ..code import load_model_code
from ..validated.lohner import enclose_flow, to_ball, working_precision

__all__ = ["SteadyRotationProof", "prove_steady_rotation_stability", "steady_rotation_ball"]

SYSTEM = "chaplygin_ball"


@dataclass
class SteadyRotationProof:
    """What :func:`prove_steady_rotation_stability` proved, with its evidence.

    Attributes
    ----------
    axis, branch : int
        The body axis (0, 1, 2) and the sense of rotation (0: ``w < 0``, 1: ``w > 0``).
    period : arb
        ``2 pi/|w|``.
    trace : arb
        ``t = tr Phi - 4``, the trace of the induced 2 x 2 map.
    det : arb
        ``det Phi`` (contains 1 when the computation is consistent).
    verdict : str
        ``"elliptic"`` (``|t| < 2`` proved: every multiplier of modulus 1),
        ``"hyperbolic"`` (``|t| > 2`` proved: a real multiplier of modulus above 1) or
        ``"undecided"``.
    multiplier : arb
        The largest modulus of the nontrivial pair: 1 when elliptic,
        ``(|t| + sqrt(t^2 - 4))/2`` when hyperbolic.
    minor : arb
        The 3 x 3 minor of the integrals' gradients that proves their rank.
    closure : float
        Width of the enclosure of ``y(T) - y0`` (which contains 0).
    width : float
        Widest entry of the enclosed monodromy.
    steps : int
    prec : int
    seconds : float
    """

    axis: int
    branch: int
    period: arb
    trace: arb
    det: arb
    verdict: str
    multiplier: arb
    minor: arb
    closure: float
    width: float
    steps: int
    prec: int
    seconds: float


def steady_rotation_ball(
    I: Sequence, D: object, axis: int, C: object = "1", Mg: object = "0", branch: int = 0
) -> tuple[list[arb], arb]:
    """The state ``(M, gamma)`` at ``t = 0`` and the period of a steady rotation, in Arb.

    Call inside :func:`~chaplygin.numerics.validated.working_precision` for more than the
    current precision.

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia (floats exact, decimal strings enclosed, or balls).
    D : number
        ``D = m b^2``.
    axis : {0, 1, 2}
        The body axis of the rotation.
    C, Mg : number
        ``(M, M)`` and ``(M, gamma)`` (``C > 0``, ``Mg^2 < C``).
    branch : {0, 1}
        The sense of rotation: ``w < 0`` or ``w > 0`` (the order of
        :func:`~chaplygin.numerics.ball.stability.critical_state`).

    Returns
    -------
    state : list of 6 arb
        ``M1, M2, M3, gamma1, gamma2, gamma3`` with ``gamma = g e_a + sqrt(1 - g^2) e_(a+1)``.
    period : arb
        ``2 pi/|w|``.

    Raises
    ------
    UserInputError
        A bad axis or branch, non-positive moments or ``D``, or ``(C, Mg)`` off the range
        (``|g| < 1`` not proved).
    """
    if axis not in (0, 1, 2) or branch not in (0, 1):
        raise UserInputError(f"axis must be 0, 1 or 2 and branch 0 or 1, got {axis!r}, {branch!r}")
    if isinstance(I, str | bytes) or len(I) != 3:
        raise UserInputError(f"I must be three moments of inertia, got {I!r}")
    Ib, Db, Cb, Mgb = [to_ball(v) for v in I], to_ball(D), to_ball(C), to_ball(Mg)
    if not (all(v > 0 for v in Ib) and Db > 0 and Cb > 0):
        raise UserInputError("the moments of inertia, D and C must be positive")
    Ia = Ib[axis]
    w = ((Cb + Db * (2 * Ia + Db) * Mgb * Mgb / (Ia * Ia)) / ((Ia + Db) * (Ia + Db))).sqrt()
    w = -w if branch == 0 else w
    g = Mgb / (Ia * w)
    if not (g * g < 1):
        raise UserInputError(f"no steady rotation about e_{axis + 1} at C = {C}, M_gamma = {Mg}")
    gamma = [arb(0)] * 3
    gamma[axis], gamma[(axis + 1) % 3] = g, (1 - g * g).sqrt()
    M = [-Db * w * g * c for c in gamma]
    M[axis] += (Ia + Db) * w
    return [*M, *gamma], 2 * arb.pi() / abs(w)


def _gradient_minor(y: list[arb]) -> arb:
    """The largest 3 x 3 minor (chosen at the midpoints) of the gradients of
    ``(gamma, gamma)``, ``(M, M)``, ``(M, gamma)`` at ``y``."""
    from itertools import combinations

    M, g = y[:3], y[3:]
    zero = [arb(0)] * 3
    rows = [zero + [2 * c for c in g], [2 * c for c in M] + zero, list(g) + list(M)]
    best = None
    for cols in combinations(range(6), 3):
        m = arb_mat([[r[c] for c in cols] for r in rows]).det()
        if best is None or abs(m.mid()) > abs(best.mid()):
            best = m
    return best


def prove_steady_rotation_stability(
    I: Sequence,
    D: object,
    axis: int,
    C: object = "1",
    Mg: object = "0",
    branch: int = 0,
    *,
    prec: int = 128,
    order: int = 24,
    tol: float = 1e-30,
) -> SteadyRotationProof:
    """Prove a steady rotation of the Chaplygin ball elliptic (stable) or hyperbolic.

    The monodromy over one period is enclosed in Arb balls from the closed-form orbit; its
    nontrivial multipliers are the roots of ``l^2 - t l + 1`` with ``t = tr Phi - 4`` (see
    the module's docstring for the proof).

    Parameters
    ----------
    I, D, axis, C, Mg, branch
        As for :func:`steady_rotation_ball`; decimal strings are enclosed as typed.
    prec : int, optional
        Arb working precision in bits.
    order : int, optional
        Taylor order of the validated integrator.
    tol : float, optional
        Its step-size control.

    Returns
    -------
    SteadyRotationProof

    Raises
    ------
    UserInputError
        From :func:`steady_rotation_ball`.
    ComputationError
        The rank of the integrals' gradients was not proved, or the enclosed ``y(T)`` misses
        ``y0`` (a defect of the computation), or the flow could not be enclosed.

    Examples
    --------
    >>> r = prove_steady_rotation_stability(("1", "1.5", "3"), "1", axis=1, prec=64,
    ...                                     order=16, tol=1e-14)
    >>> r.verdict   # the middle axis: a real multiplier above 1
    'hyperbolic'
    """
    started = time.perf_counter()
    code = load_model_code(SYSTEM)
    with working_precision(prec):
        y0, T = steady_rotation_ball(I, D, axis, C, Mg, branch)
        params = [to_ball(v) for v in I] + [to_ball(D)]
        minor = _gradient_minor(y0)
        if minor.contains(0):
            raise ComputationError(f"the rank of the integrals' gradients is not proved: {minor}")
        e = enclose_flow(code, params, y0, 0, T, jacobian=True, order=order, prec=prec, tol=tol)
        gap = [a - b for a, b in zip(e.state, y0, strict=True)]
        if not all(d.contains(0) for d in gap):
            raise ComputationError("the enclosed y(T) does not contain y0: the orbit is not closed")
        Phi = arb_mat(e.jacobian)
        t = sum((Phi[i, i] for i in range(6)), arb(0)) - 4
        if abs(t) < 2:
            verdict, mult = "elliptic", arb(1)
        elif abs(t) > 2:
            verdict, mult = "hyperbolic", (abs(t) + (t**2 - 4).sqrt()) / 2
        else:
            verdict, mult = "undecided", arb("nan")
        width = max(float(Phi[i, j].rad()) for i in range(6) for j in range(6))
        return SteadyRotationProof(
            axis=axis,
            branch=branch,
            period=T,
            trace=t,
            det=Phi.det(),
            verdict=verdict,
            multiplier=mult,
            minor=minor,
            closure=max(2 * float(d.rad()) for d in gap),
            width=2 * width,
            steps=e.steps,
            prec=prec,
            seconds=time.perf_counter() - started,
        )
