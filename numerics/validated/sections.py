"""A rigorous section map: the crossing of a surface ``s(y) = 0`` enclosed, with the crossing
time, transversality checked, and the derivative of the section map (C^1).

Given a start (point or box) at ``t0`` and a time window ``[t_a, t_b]`` in which the floating-
point orbit crosses the section once:

1. the flow is enclosed to ``t_a`` and over the whole window (``enclose_flow`` with an interval
   end time), and ``s`` is proved to change sign between ``t_a`` and ``t_b``;
2. transversality: ``g'(t) = grad s(y) . f(t, y)`` is enclosed over the window's enclosure and
   must not contain 0, so ``g(t) = s(phi(t))`` is strictly monotone there;
3. interval Newton on ``g``: ``N = m - g(m) / g'(T)``, ``T <- T ∩ N`` (``g(m)`` from an enclosure
   of the flow to the midpoint), which proves one and only one crossing in ``T`` when
   ``N ⊆ int T`` and shrinks ``T`` to the crossing time's enclosure;
4. the crossing state is the flow's enclosure over the final ``T``; with ``jacobian``, the section
   map's derivative ``(Id - f grad s^T / (grad s . f)) D phi`` over it.

``s`` is a Python function of the state (a list of balls or of jets: it is differentiated by
:mod:`~chaplygin.numerics.validated.jets`), e.g. ``lambda y: y[0]`` for ``theta = 0``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from flint import arb, arb_mat

from ...derive.errors import ComputationError
from .jets import ARB_LIB, jet_gradient, jet_value, seed_jets
from .lohner import enclose_flow, to_ball, working_precision

__all__ = ["SectionCrossing", "enclose_crossing"]


@dataclass
class SectionCrossing:
    """The result of :func:`enclose_crossing`.

    Attributes
    ----------
    time : arb
        Encloses the crossing time (of every start in the initial box).
    state : list of arb
        Encloses the state at the crossing.
    transversality : arb
        Encloses ``grad s . f`` over the crossing window (0 is not in it).
    jacobian : list of list of arb or None
        Encloses the derivative of the section map (start -> crossing state).
    newton_steps : int
        Interval Newton steps taken.
    """

    time: arb
    state: list
    transversality: arb
    jacobian: list | None
    newton_steps: int


def _field(code: Any, params: list, T: arb, Y: list) -> list:
    """The right-hand side over the time ball ``T`` and the state box ``Y`` (Taylor order 1)."""
    c = code.taylor.taylor_coefficients(T, Y, params, 1, ARB_LIB)
    return [row[1] for row in c]


def _over_window(code, P, Xa, ta, tb, prec, options, pieces=16):  # noqa: ANN001, ANN202
    """The hull of the flow's enclosures over ``[t_a, t_b]``, in pieces short enough for one
    Taylor step each (each piece from the enclosure at its start)."""
    hull, X, t = None, Xa, ta
    for k in range(1, pieces + 1):
        t_next = ta + (tb - ta) * k / pieces if k < pieces else tb
        over = enclose_flow(code, P, X, t, t.union(t_next), prec=prec, **options).state
        hull = over if hull is None else [a.union(b) for a, b in zip(hull, over, strict=True)]
        X = enclose_flow(code, P, X, t, t_next, prec=prec, **options).state
        t = t_next
    return hull


def enclose_crossing(
    code: Any,
    params: Sequence,
    state: Sequence,
    t0: Any,
    window: tuple[Any, Any],
    section: Callable[[list], Any],
    *,
    jacobian: bool = False,
    newton_steps: int = 6,
    prec: int = 128,
    **options: Any,
) -> SectionCrossing:
    """Enclose the crossing of ``section(y) = 0`` inside a time window.

    Parameters
    ----------
    code : ModelCode
        The model's generated code (or any object with ``state``, ``params``, ``name`` and
        ``taylor.taylor_coefficients``).
    params, state : sequence
        As for :func:`~chaplygin.numerics.validated.lohner.enclose_flow`.
    t0 : number or str
        The start time.
    window : (t_a, t_b)
        A window (``t0 <= t_a < t_b``) in which the orbit crosses the section once.
    section : callable
        ``s(y)`` on a list of balls or jets.
    jacobian : bool, optional
        Also enclose the section map's derivative.
    newton_steps : int, optional
        Interval Newton steps on the crossing time.
    prec : int, optional
        Arb working precision (bits).
    **options
        Passed to ``enclose_flow`` (``order``, ``tol``).

    Returns
    -------
    SectionCrossing

    Raises
    ------
    ComputationError
        The sign change, the transversality or the uniqueness could not be proved in the
        window.
    """
    with working_precision(prec):
        P = [to_ball(p) for p in params]
        ta, tb = to_ball(window[0]), to_ball(window[1])
        start = to_ball(t0)
        # to the window's start (with the derivative when the section map's is asked for)
        first = (
            enclose_flow(code, P, state, start, ta, jacobian=jacobian, prec=prec, **options)
            if ta.mid() > start.mid()
            else None
        )
        Xa = first.state if first is not None else [to_ball(v) for v in state]
        Xb = enclose_flow(code, P, Xa, ta, tb, prec=prec, **options).state
        sa, sb = jet_value(section(Xa)), jet_value(section(Xb))
        if not ((sa < 0 and sb > 0) or (sa > 0 and sb < 0)):
            raise ComputationError(
                f"no proved sign change of the section between t = {window[0]} and {window[1]} "
                f"(s = {sa} and {sb})"
            )
        T = ta.union(tb)
        YT = _over_window(code, P, Xa, ta, tb, prec, options)
        n = len(YT)
        grad = jet_gradient(section(seed_jets(YT)), n)
        f = _field(code, P, T, YT)
        slope = sum((g * v for g, v in zip(grad, f, strict=True)), arb(0))
        if slope.contains(0):
            raise ComputationError(f"transversality not proved: grad s . f = {slope} in the window")
        unique = False
        for _ in range(newton_steps):
            m = T.mid()
            gm = jet_value(section(enclose_flow(code, P, Xa, ta, m, prec=prec, **options).state))
            N = m - gm / slope
            unique = unique or bool(T.contains_interior(N))
            try:
                T = T.intersection(N)
            except ValueError:
                raise ComputationError("interval Newton left the window: no crossing") from None
            # the slope again over the smaller window (Newton then converges quadratically)
            YT = enclose_flow(code, P, Xa, ta, T, prec=prec, **options).state
            g = jet_gradient(section(seed_jets(YT)), n)
            f = _field(code, P, T, YT)
            slope = slope.intersection(sum((a * b for a, b in zip(g, f, strict=True)), arb(0)))
        if not unique:
            raise ComputationError("interval Newton did not prove one crossing in the window")
        final = enclose_flow(code, P, Xa, ta, T, jacobian=jacobian, prec=prec, **options)
        D = None
        if jacobian:
            grad = jet_gradient(section(seed_jets(final.state)), n)
            f = _field(code, P, T, final.state)
            Dphi = arb_mat(final.jacobian)
            if first is not None:
                Dphi = Dphi * arb_mat(first.jacobian)
            fg = arb_mat([[f[i] * grad[j] / slope for j in range(n)] for i in range(n)])
            eye = arb_mat([[1 if i == j else 0 for j in range(n)] for i in range(n)])
            Dm = (eye - fg) * Dphi
            D = [[Dm[i, j] for j in range(n)] for i in range(n)]
    return SectionCrossing(T, final.state, slope, D, newton_steps)
