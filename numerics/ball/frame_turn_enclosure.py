"""The critical energies of K01 Fig. 6(f) proved by computation: the frame turn enclosed.

On the segment ``M = C gamma`` of the Chaplygin ball at energy ``h``
(:func:`~chaplygin.numerics.ball.frame_turn.near_separatrix_state`: ``gamma = (cos psi, 0,
sin psi)`` with ``(gamma, A gamma) = 1/(D + C^2/(2h))``, ``alpha = e2``, ``beta = gamma x
alpha``), ``gamma(t)`` is periodic; after one period ``T`` the space-fixed horizontal frame seen
from the body has turned by ``Phi(h) = atan2(alpha_T . beta_0, alpha_T . alpha_0)``, and the
contact point's trace is unbounded exactly where ``Phi = 0 mod 2 pi`` (K01-Fig6f).

Here the return of ``gamma`` to the plane ``gamma2 = 0`` (going the same way) is the rigorous
section crossing :func:`~chaplygin.numerics.validated.enclose_crossing` in a window around the
floating-point period (the sign change and the transversality ``gamma2' != 0`` proved over the
window, the crossing time by interval Newton): since ``gamma(t)`` is periodic and its curve
crosses the plane once each way per period, a same-way crossing within half a period of ``T``
is the return after exactly one period. The start is a function of ``h`` evaluated on jets of
``h``; the section map's derivative carries ``d/dh`` to ``alpha_T``, so ``Phi'(h)`` is
enclosed over a whole interval of energies. A zero of ``Phi`` is then proved by the interval
Newton test ``m - Phi(m)/Phi'(N) ⊂ int N``: one and only one zero in ``N``, inside the
(much smaller) Newton image.

References
----------
K01-Fig6f, K01-3.3seg, K01-2.34 (FORMULAS.md); Moore (1966), interval Newton.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from flint import arb, arb_mat

from ...derive.errors import ComputationError, UserInputError
from ..code import load_model_code
from ..validated.jets import (
    ARB_LIB,
    jet_atan2,
    jet_gradient,
    jet_value,
    jets_from_matrix,
    seed_jets,
)
from ..validated.lohner import to_ball, working_precision
from ..validated.sections import enclose_crossing

__all__ = [
    "FrameTurnEnclosure",
    "CriticalEnergyProof",
    "enclose_frame_turn",
    "prove_critical_energy",
]

#: The model: M, gamma, alpha, beta, x, y (the frame is alpha, beta).
SYSTEM, EFFECTS = "chaplygin_ball", ("contact_point",)


@dataclass
class FrameTurnEnclosure:
    """:func:`enclose_frame_turn`'s result.

    Attributes
    ----------
    h : arb
        The energy (a ball or an interval of energies).
    period : arb
        Encloses the return time of ``gamma`` for every energy in ``h``.
    turn : arb
        Encloses ``Phi`` (radians) for every energy in ``h``.
    slope : arb or None
        Encloses ``Phi'(h)`` over ``h`` (when asked for).
    seconds : float
    cosine : arb or None
        Encloses ``alpha_T . alpha_0 = cos Phi`` (``alpha_T`` is horizontal again after a
        period): negative means ``Phi`` is at least ``pi/2`` from ``0 mod 2 pi``, which holds
        even where ``atan2``'s branch cut makes ``turn`` indeterminate.
    """

    h: arb
    period: arb
    turn: arb
    slope: arb | None
    seconds: float
    cosine: arb | None = None


@dataclass
class CriticalEnergyProof:
    """:func:`prove_critical_energy`'s result.

    Attributes
    ----------
    verdict : {"unique zero", "no zero", "undecided"}
        On the neighbourhood ``N``: exactly one zero of ``Phi`` (inside ``energy``), none, or
        not decided.
    energy : arb
        The interval Newton image: contains the zero (when there is one).
    neighbourhood : arb
        ``N``, where ``Phi'`` is enclosed away from 0 (``Phi`` is monotone there).
    slope : arb
        ``Phi'`` over ``N``.
    turn_at_centre : arb
        ``Phi`` at the centre of ``N`` (over all of ``N`` when that enclosure already
        decides: ``cos Phi < 0``, or ``0 < cos Phi`` and ``Phi`` away from 0 on ``N``).
    ends : tuple of arb
        ``Phi`` at the two ends of ``energy`` (opposite signs when a zero is proved).
    seconds : float
    cosine : arb
        ``cos Phi`` over ``N``.
    """

    verdict: str
    energy: arb
    neighbourhood: arb
    slope: arb
    turn_at_centre: arb
    ends: tuple
    seconds: float
    cosine: arb


def _start(I: list, D: arb, C: arb, h: Any) -> list:
    """``near_separatrix_state`` in balls or jets of ``h``."""
    J1, J3 = I[0] + D, I[2] + D
    g = 1 / (D + C * C / (2 * h))
    c2 = (g - 1 / J3) / (1 / J1 - 1 / J3)
    c2v = jet_value(c2)
    if not (c2v > 0 and c2v < 1):
        raise UserInputError("h is not (provably) inside the segment n = C^2")
    s1, s3 = c2**0.5, (1 - c2) ** 0.5
    zero = arb(0)
    gamma = [s1, zero, s3]
    alpha = [zero, arb(1), zero]
    beta = [-s3, zero, s1]  # gamma x alpha
    return [*(C * v for v in gamma), *gamma, *alpha, *beta, zero, zero]


def enclose_frame_turn(
    I: Sequence,
    D: Any,
    h: Any,
    period_guess: float,
    C: Any = "1",
    *,
    derivative: bool = False,
    window: float = 0.25,
    prec: int = 128,
    order: int = 20,
    tol: float = 1e-20,
) -> FrameTurnEnclosure:
    """Enclose the period of ``gamma`` and the frame turn ``Phi`` at the energy (or energies) ``h``.

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia (``I1 < I2 < I3``); decimal strings are enclosed as typed.
    D : number
        ``D = m b^2``.
    h : number, str, (lo, hi) or arb
        The energy, or an interval of energies.
    period_guess : float
        The floating-point period (:func:`~chaplygin.numerics.ball.frame_turn.frame_turn`);
        the crossing is searched in ``period_guess +- window``.
    C : number, optional
        ``(M, gamma)``.
    derivative : bool, optional
        Also enclose ``Phi'(h)`` over ``h``.
    window : float, optional
        Half-width of the time window of the crossing (less than half a period).
    prec, order, tol : optional
        The validated integrator's precision (bits), Taylor order and step control.

    Returns
    -------
    FrameTurnEnclosure

    Raises
    ------
    UserInputError
        ``h`` not inside the segment, a bad body.
    ComputationError
        The crossing could not be proved in the window (from
        :func:`~chaplygin.numerics.validated.enclose_crossing`).
    """
    started = time.perf_counter()
    code = load_model_code(SYSTEM, EFFECTS)
    with working_precision(prec):
        Ib, Db, Cb, hb = [to_ball(v) for v in I], to_ball(D), to_ball(C), to_ball(h)
        if not (Ib[0] < Ib[1] < Ib[2] and Db > 0):
            raise UserInputError("need I1 < I2 < I3 and D > 0")
        params = [*Ib, Db, arb(1)]
        seeds = _start(Ib, Db, Cb, seed_jets([hb])[0]) if derivative else None
        y0 = [jet_value(v) for v in seeds] if derivative else _start(Ib, Db, Cb, hb)
        f0 = code.taylor.taylor_coefficients(arb(0), y0, params, 1, ARB_LIB)[4][1]
        sign = 1 if f0 > 0 else -1 if f0 < 0 else 0
        if sign == 0:
            raise ComputationError("the start's gamma2' is not proved nonzero")
        window_t = (arb(period_guess - window), arb(period_guess + window))
        crossing = enclose_crossing(
            code, params, y0, 0, window_t, lambda y: y[4] * sign, jacobian=derivative,
            prec=prec, order=order, tol=tol,
        )  # fmt: skip
        if not crossing.transversality > 0:
            raise ComputationError("the return crosses gamma2 = 0 the other way")
        if derivative:
            dy0 = arb_mat([jet_gradient(v, 1) for v in seeds])
            yT = jets_from_matrix(crossing.state, arb_mat(crossing.jacobian) * dy0)
            alpha0, beta0 = seeds[6:9], seeds[9:12]
        else:
            yT, alpha0, beta0 = crossing.state, y0[6:9], y0[9:12]
        aT = yT[6:9]
        cosine = sum(a * b for a, b in zip(aT, alpha0, strict=True))
        phi = jet_atan2(sum(a * b for a, b in zip(aT, beta0, strict=True)), cosine)
        return FrameTurnEnclosure(
            h=hb,
            period=crossing.time,
            turn=jet_value(phi),
            slope=jet_gradient(phi, 1)[0] if derivative else None,
            seconds=time.perf_counter() - started,
            cosine=jet_value(cosine),
        )


def prove_critical_energy(
    I: Sequence,
    D: Any,
    h_guess: str,
    period_guess: float,
    C: Any = "1",
    *,
    radius: float = 1e-7,
    slope_tol: float | None = None,
    **options: Any,
) -> CriticalEnergyProof:
    """Prove one and only one critical energy (``Phi = 0``) near ``h_guess``, or none.

    ``Phi'`` enclosed over ``N = m +- radius`` (``m = h_guess``), ``Phi(m)`` enclosed: the
    interval Newton image ``m - Phi(m)/Phi'(N)``
    inside ``N`` proves exactly one zero in ``N``, inside the image; disjoint from ``N``,
    proves none; so do ``cos Phi < 0`` over ``N`` (``Phi`` near ``pi``, where ``atan2``'s
    branch cut would leave the turn indeterminate) and ``0 < cos Phi`` with ``Phi`` away from
    0 over ``N`` (then ``Phi(m)`` is not computed). ``Phi`` is enclosed at the image's ends
    too (their signs differ).

    Parameters
    ----------
    I, D, C
        As for :func:`enclose_frame_turn`.
    h_guess : str
        A decimal energy near the critical one (the floating-point route's, e.g.
        :func:`~chaplygin.numerics.ball.frame_turn.critical_energy`); the proof does not
        depend on how it was found.
    period_guess : float
        The floating-point period there.
    radius : float, optional
        Half-width of the neighbourhood ``N``.
    slope_tol : float, optional
        The integrator's step control for ``Phi'`` over ``N`` (whose width is ``N``'s, not
        the steps'): a looser one than the point enclosures' ``tol`` saves steps.
    **options
        Passed to :func:`enclose_frame_turn` (``prec``, ``order``, ``tol``, ``window``).

    Returns
    -------
    CriticalEnergyProof

    Raises
    ------
    UserInputError, ComputationError
        From :func:`enclose_frame_turn`.
    """
    started = time.perf_counter()
    prec = options.get("prec", 128)
    with working_precision(prec):
        m = to_ball(h_guess)
        N = m + arb(0, radius)
    over_options = options if slope_tol is None else {**options, "tol": slope_tol}
    over = enclose_frame_turn(I, D, N, period_guess, C, derivative=True, **over_options)
    slope, centre_turn = over.slope, over.turn
    with working_precision(prec):
        if over.cosine < 0:  # Phi is at least pi/2 from 0 mod 2 pi on all of N
            verdict, image = "no zero", N
        elif over.cosine > 0 and not over.turn.contains(0):  # |Phi| < pi/2, never 0 on N
            verdict, image = "no zero", N
        elif slope.contains(0):
            verdict, image = "undecided", N
        else:
            verdict, image = "newton", N
    if verdict == "newton":
        centre_turn = enclose_frame_turn(I, D, m, period_guess, C, **options).turn
        with working_precision(prec):
            newton = m - centre_turn / slope
            if N.contains_interior(newton):
                verdict, image = "unique zero", newton
            elif not N.overlaps(newton):
                verdict, image = "no zero", newton
            else:
                verdict, image = "undecided", newton
    ends: tuple = ()
    if verdict == "unique zero":
        ends = tuple(
            enclose_frame_turn(I, D, arb(e), period_guess, C, **options).turn
            for e in (image.lower(), image.upper())
        )
    return CriticalEnergyProof(
        verdict=verdict,
        energy=image,
        neighbourhood=N,
        slope=slope,
        turn_at_centre=centre_turn,
        ends=ends,
        seconds=time.perf_counter() - started,
        cosine=over.cosine,
    )
