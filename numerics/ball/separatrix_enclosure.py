"""Delta, the displacement of the contact point along the separatrix, enclosed from the full
equations (K01 §3.3), with an analytic bound for the separatrix tails.

On ``M = C gamma`` at ``h = C^2/(2 I2)`` the ball tumbles once along the separatrix of the
middle axis, and its contact point moves by ``Delta`` (K01 (3.4)-(3.7)). The proof by
computation:

1. The separatrix point at ``t = 0`` (the corrected K01-3.4 solution: ``M = C gamma``,
   ``gamma = (-s32, 0, -s21)``, ``alpha = e2``, ``beta = (s21, 0, -s32)``, ``x = y = 0``) is
   enclosed in Arb balls from its closed form; ``K01-3.4`` (proved symbolically for
   ``I1 < I2 < I3``, ``C > 0``) says the solution of the model's equations through it is the
   separatrix for all ``t``.
2. The flow of the 14-dimensional ``chaplygin_ball__contact_point`` model is enclosed by the
   validated Taylor integrator (:func:`~chaplygin.numerics.validated.lohner.enclose_flow`,
   forward to ``T`` and backward to ``-T``, ``lam T = L``): ``x(T)``, ``x(-T)``, ``y(T)``,
   ``y(-T)`` in balls.
3. The tails: on the separatrix ``x' = nu cos(kap t)/ch(lam t)``, ``y' = nu sin(kap t)/ch(lam
   t)``, ``nu = -b lam`` (``K01-3.5``, proved symbolically), so with ``s = lam t``
   ``x(+oo) - x(T) = x(-T) - x(-oo) = -b int_L^oo cos(mu s)/ch(s) ds`` (and ``y(+oo) - y(T) =
   -b int_L^oo sin(mu s)/ch(s) ds``, ``y(-T) - y(-oo) = +b`` the same): with ``1/ch(s) = 2
   sum_n (-1)^n exp(-(2n+1) s)`` the first ``N`` terms integrate in closed form (in Arb) and the
   rest is at most ``2 exp(-(2N+1) L)/(2N+1)`` per tail (``|cos|, |sin| <= 1``; ``N = 0`` is the
   plain bound ``|x(+oo) - x(T)| <= |nu| int_T^oo dt/ch(lam t) <= 2 b exp(-L)``).

So ``x(+oo) - x(-oo)`` lies in ``x(T) - x(-T)`` plus the two tails; ``Delta`` is its length (it
is negative: the contact point moves along ``-alpha``). The closed form ``pi b/ch(pi mu/2)``
(K01-3.7, ``mu = 1/(J2 sqrt(a21 a32))``) is enclosed in Arb too and compared. A few terms of
the series let ``L`` stay small (16 instead of 36 for 1e-14), which keeps the flow's
enclosure narrow: a perturbation off the separatrix grows like ``exp(lam t)``.

The initial balls are about ``2^-prec`` wide and the local errors of the integrator about
``tol``: the enclosure at ``lam T = L`` is about ``exp(L)`` times wider.

References
----------
K01-3.4, K01-3.5, K01-3.6, K01-3.7, K01-Fig4 (FORMULAS.md).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from flint import arb

from ...derive.errors import UserInputError
from ..arguments import check_inertia_vector, check_real
from ..code import load_model_code
from ..validated.lohner import enclose_flow, to_ball, working_precision

__all__ = [
    "DeltaEnclosure",
    "enclose_delta",
    "separatrix_ball",
    "delta_closed_form_ball",
    "tail_series",
]

SYSTEM = "chaplygin_ball"
EFFECTS = ("contact_point",)


@dataclass
class DeltaEnclosure:
    """What :func:`enclose_delta` enclosed, with its evidence.

    Attributes
    ----------
    delta : arb
        Encloses ``Delta = |x(+oo) - x(-oo)|``.
    signed : arb
        Encloses ``x(+oo) - x(-oo)`` (negative: the contact point moves along ``-alpha``).
    y_shift : arb
        Encloses ``y(+oo) - y(-oo)`` (K01-3.6: it is 0).
    closed : arb
        The closed form ``pi b/ch(pi mu/2)`` (K01-3.7) enclosed.
    mu, lam, kap : arb
        ``mu = kap/lam``, the rates of ``ch(lam t)`` and ``cos(kap t)``.
    tail : arb
        Encloses ``x(+oo) - x(T) + x(-T) - x(-oo)`` (the two tails of ``x``).
    tail_bound : float
        The bound of the omitted terms of the tails' series (both tails; with ``terms = 0``
        the plain bound ``4 b exp(-L)``).
    terms : int
        Terms ``N`` of the tails' series summed.
    flow_width : float
        Width of the enclosure of ``x(T) - x(-T)``.
    width : float
        Width of ``delta`` (``flow_width`` plus twice ``tail_bound``).
    L : float
        ``lam T`` at the ends.
    T : float
        The end time ``T`` (exact; ``lam T`` contains ``L``).
    steps : int
        Steps of the two integrations.
    prec : int
        Arb working precision (bits).
    seconds : float
        Wall time.
    """

    delta: arb
    signed: arb
    y_shift: arb
    closed: arb
    mu: arb
    lam: arb
    kap: arb
    tail: arb
    tail_bound: float
    terms: int
    flow_width: float
    width: float
    L: float
    T: float
    steps: int
    prec: int
    seconds: float

    def contains(self, value: Any) -> bool:
        """Whether ``value`` (a float, decimal string, ``mpf`` or ball) lies in ``delta``.

        Parameters
        ----------
        value : float, str, mpf or arb

        Returns
        -------
        bool
        """
        with working_precision(self.prec):
            return bool(self.delta.contains(to_ball(value)))


def _ball(value: Any, name: str) -> arb:
    try:
        return to_ball(value)
    except UserInputError as exc:
        raise UserInputError(f"{name}: {exc} (give a number or a decimal)") from None


def _body(I: Any, D: Any, b: Any, C: Any) -> tuple[list[arb], arb, arb, arb]:
    """The balls of ``I, D, b, C``, or :class:`UserInputError` naming the argument unless
    ``0 < I1 < I2 < I3`` and ``D, b, C > 0`` (the order decided on the balls)."""
    check_inertia_vector(I, D)
    check_real(b, "b", positive=True)
    check_real(C, "C", positive=True)
    Ib = [_ball(v, f"I[{i}]") for i, v in enumerate(I)]
    Db, bb, Cb = _ball(D, "D"), _ball(b, "b"), _ball(C, "C")
    if not (Ib[0] < Ib[1] and Ib[1] < Ib[2]):
        raise UserInputError(
            f"I = {list(I)!r}: give I1 < I2 < I3 (K01-3.4 is proved for that order; the "
            "separatrix belongs to the middle axis)"
        )
    return Ib, Db, bb, Cb


def _quantities(Ib: list[arb], Db: arb, Cb: arb) -> dict[str, arb]:
    """``lam, kap, mu, s32, s21`` in Arb (:func:`~chaplygin.numerics.ball.separatrix.
    separatrix_quantities` re-derived on balls)."""
    J1, J2, J3 = (v + Db for v in Ib)
    d21, d32 = 1 / J1 - 1 / J2, 1 / J2 - 1 / J3
    root = (d21 * d32).sqrt()
    return {
        "lam": Cb * J2 / Ib[1] * root,
        "kap": Cb / Ib[1],
        "mu": 1 / (J2 * root),
        "s32": (d32 / (d21 + d32)).sqrt(),
        "s21": (d21 / (d21 + d32)).sqrt(),
    }


def separatrix_ball(
    I: Sequence[Any], D: Any, C: Any = 1, prec: int = 192
) -> tuple[list[arb], dict[str, arb]]:
    """The separatrix point at ``t = 0`` (corrected K01-3.4) and its rates, in Arb balls.

    Parameters
    ----------
    I : sequence of 3 numbers
        ``I1 < I2 < I3``: floats (exact), ints, ``Fraction``, decimal strings (enclosed),
        ``mpf`` or balls.
    D : number
        ``D = m b^2 > 0``.
    C : number
        ``C = (M, gamma) > 0``.
    prec : int
        Arb working precision (bits).

    Returns
    -------
    state : list of arb, length 14
        ``M = C gamma``, ``gamma = (-s32, 0, -s21)``, ``alpha = e2``, ``beta = (s21, 0,
        -s32)``, ``x = y = 0`` (the order of ``chaplygin_ball__contact_point``).
    rates : dict of str to arb
        ``lam, kap, mu, s32, s21``.

    Raises
    ------
    UserInputError
        Not ``0 < I1 < I2 < I3``, ``D <= 0``, ``C <= 0`` or a value that is not a number.

    References
    ----------
    K01-3.4 (FORMULAS.md, the corrected form for ``C > 0``).
    """
    _check_prec(prec)
    with working_precision(prec):
        Ib, Db, _, Cb = _body(I, D, 1, C)
        Q = _quantities(Ib, Db, Cb)
        zero, one = arb(0), arb(1)
        gamma = [-Q["s32"], zero, -Q["s21"]]
        alpha = [zero, one, zero]
        beta = [Q["s21"], zero, -Q["s32"]]
        return [Cb * g for g in gamma] + gamma + alpha + beta + [zero, zero], Q


def delta_closed_form_ball(mu: arb, b: arb | int, half: bool = True) -> arb:
    """``pi b/ch(pi mu/2)`` (K01-3.7) in Arb; ``half=False``: ``pi b/ch(pi mu)`` (the
    control with the factor 1/2 dropped).

    Parameters
    ----------
    mu : arb
        ``mu = kap/lam``.
    b : arb or int
        The radius.
    half : bool
        The factor ``1/2`` in the argument of ``ch``.

    Returns
    -------
    arb
    """
    x = arb.pi() * mu
    return arb.pi() * b / (x / 2 if half else x).cosh()


def _check_prec(prec: object) -> None:
    if not (isinstance(prec, int) and 53 <= prec <= 4096):
        raise UserInputError(f"prec must be an integer number of bits in 53..4096, got {prec!r}")


def tail_series(mu: arb, L: arb, terms: int) -> tuple[arb, arb]:
    """``int_L^oo cos(mu s)/ch(s) ds`` and ``int_L^oo sin(mu s)/ch(s) ds`` enclosed.

    ``1/ch(s) = 2 sum_n (-1)^n exp(-(2n+1) s)`` (``s > 0``): the first ``terms`` terms are
    integrated in closed form, ``int_L^oo exp(-a s) cos(mu s) ds = exp(-a L) (a cos(mu L) - mu
    sin(mu L))/(a^2 + mu^2)`` (sine: ``a sin + mu cos``); the rest of the series is
    ``2 (-1)^N exp(-(2N+1) s)/(1 + exp(-2s))``, at most ``2 exp(-(2N+1) s)`` in modulus, so
    its integral against ``cos`` or ``sin`` is at most ``2 exp(-(2N+1) L)/(2N+1)``.

    Parameters
    ----------
    mu, L : arb
        The frequency and the lower limit (``L > 0``).
    terms : int
        ``N >= 0`` (0: only the bound).

    Returns
    -------
    (arb, arb)
        The two integrals, the omitted terms' bound included as radius.

    References
    ----------
    K01-3.5, K01-3.7 (FORMULAS.md).
    """
    c, s_ = (mu * L).cos(), (mu * L).sin()
    cos_part, sin_part = arb(0), arb(0)
    for n in range(terms):
        a = 2 * n + 1
        w = 2 * (-1) ** n * (-a * L).exp() / (a * a + mu * mu)
        cos_part += w * (a * c - mu * s_)
        sin_part += w * (a * s_ + mu * c)
    a = 2 * terms + 1
    rest = arb(0, float((2 * (-a * L).exp() / a).upper()) * (1 + 2**-40))
    return cos_part + rest, sin_part + rest


def enclose_delta(
    I: Sequence[Any],
    D: Any,
    b: Any,
    C: Any = 1,
    L: float = 16.0,
    *,
    terms: int = 2,
    prec: int = 128,
    order: int = 24,
    tol: float = 1e-25,
) -> DeltaEnclosure:
    """Enclose Delta from the full equations: the flow from the separatrix point to
    ``lam t = +-L`` and the tails from K01-3.5.

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia ``0 < I1 < I2 < I3``: floats (exact), ints, ``Fraction``, decimal
        strings (enclosed at ``prec``), ``mpf`` or balls.
    D : number
        ``D = m b^2 > 0``.
    b : number
        Radius ``b > 0``.
    C : number
        ``C = (M, gamma) > 0`` (the time scale; Delta does not depend on it).
    L : float
        ``lam T`` at the ends, 1 to 200.
    terms : int
        Terms of the tails' series summed (:func:`tail_series`), 0 to 50; the omitted ones
        are bounded by ``4 b exp(-(2N+1) L)/(2N+1)`` in all (``N = 0``: ``4 b exp(-L)``).
    prec : int
        Arb working precision (bits); the flow's enclosure grows like ``exp(L)``.
    order : int
        Taylor order of the validated integrator.
    tol : float
        Step control of the validated integrator (the Lagrange remainder of a step).

    Returns
    -------
    DeltaEnclosure

    Raises
    ------
    UserInputError
        Not ``0 < I1 < I2 < I3``, ``D, b, C`` not positive, ``L`` outside 1..200, ``terms``
        outside 0..50, ``tol`` outside (0, 1), a bad ``prec`` or ``order``.
    EnclosureError
        The flow could not be enclosed (``prec`` too low or ``tol`` too large for ``L``).

    References
    ----------
    K01-3.4, K01-3.5, K01-3.7 (FORMULAS.md).

    Examples
    --------
    >>> r = enclose_delta(["1", "3", "5"], 1, 1, L=5, terms=4, order=16, tol=1e-12)
    >>> r.delta.contains(r.closed)  # the closed form pi b/ch(pi mu/2) lies inside
    True
    >>> r.width < 1e-6
    True
    """
    started = time.perf_counter()
    if isinstance(L, bool) or not isinstance(L, int | float) or not 1 <= L <= 200:
        raise UserInputError(f"L must be a number in 1..200, got {L!r}")
    if isinstance(terms, bool) or not isinstance(terms, int) or not 0 <= terms <= 50:
        raise UserInputError(f"terms must be an integer in 0..50, got {terms!r}")
    if isinstance(tol, bool) or not isinstance(tol, int | float) or not 0 < tol < 1:
        raise UserInputError(f"tol must be a number in (0, 1), got {tol!r}")
    state, Q = separatrix_ball(I, D, C, prec)
    code = load_model_code(SYSTEM, EFFECTS)
    with working_precision(prec):
        Ib, Db, bb, _ = _body(I, D, b, C)
        T = float((arb(L) / Q["lam"]).mid())  # an exact end time; lam T encloses ~L
        runs = [
            enclose_flow(code, [*Ib, Db, bb], state, 0, t1, order=order, prec=prec, tol=tol)
            for t1 in (T, -T)
        ]
        fwd, bwd = runs[0].state, runs[1].state
        Fc, Fs = tail_series(Q["mu"], Q["lam"] * arb(T), terms)
        # x(oo) - x(T) = x(-T) - x(-oo) = -b Fc; y(oo) - y(T) = -b Fs, y(-T) - y(-oo) = +b Fs
        tail_x, tail_y = -bb * Fc - bb * Fc, -bb * Fs + bb * Fs
        dx, dy = fwd[12] - bwd[12], fwd[13] - bwd[13]
        signed, y_shift = dx + tail_x, dy + tail_y
        delta = abs(signed)
        closed = delta_closed_form_ball(Q["mu"], bb)
    a = 2 * terms + 1
    return DeltaEnclosure(
        delta=delta,
        signed=signed,
        y_shift=y_shift,
        closed=closed,
        mu=Q["mu"],
        lam=Q["lam"],
        kap=Q["kap"],
        tail=tail_x,
        tail_bound=4 * float(bb.upper()) * math.exp(-a * L) / a,
        terms=terms,
        flow_width=2 * float(dx.rad()),
        width=2 * float(delta.rad()),
        L=float(L),
        T=T,
        steps=sum(r.steps for r in runs),
        prec=prec,
        seconds=time.perf_counter() - started,
    )
