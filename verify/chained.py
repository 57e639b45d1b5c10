"""Integrals of large models decided through their auxiliaries, not their expanded form.

A described system's model may define its right-hand side through a chain of auxiliaries
(the general ball on a support surface: the contact's normal, the constraint's solution
...) whose substitution gives some 10^6 operations per component; the Groebner proof and
the exact sampling of :func:`~chaplygin.verify.identity.decide` work on the expanded
residual and do not finish. Here the rate of a function ``F`` along the flow is evaluated
exactly at random points of the phase space by the chain rule through the auxiliaries in
their order: each auxiliary's value, then its rate from the rates of those before it,
``dA/dt = sum_y dA/dy f_y + sum_B dA/dB dB/dt``, then ``dF/dt`` the same way. The numbers
are exact (rationals and the square roots a normal's length brings, put in a canonical
form that is zero exactly when the number is). Zero at every point is the verdict
``exact-sampled``; a non-zero value is a refutation with its point as the witness.

Used where :func:`applies` says so: an autonomous model (no time in its equations) whose
expanded right-hand side is over :data:`~chaplygin.derive.emit.base.CHAIN_OPS` operations.
"""

from __future__ import annotations

import functools
import random
import time
from collections.abc import Sequence

import sympy as sp

from ..derive.emit.base import CHAIN_OPS, expanded_size
from ..derive.model import Model
from ..derive.phase_space import sample_point
from .identity import Outcome

__all__ = ["applies", "rate_at", "decide_along_flow"]


def applies(model: Model, expr: sp.Expr) -> bool:
    """Whether a would-be integral of the model is decided through its auxiliaries.

    Parameters
    ----------
    model : Model
    expr : sympy.Expr
        The would-be integral.

    Returns
    -------
    bool
        The model has auxiliaries and no explicit time in its equations, and the rates of
        the state components ``expr`` depends on have over ``CHAIN_OPS`` operations
        expanded.
    """
    if not model.aux:
        return False
    used = model.expand_aux(expr).free_symbols
    rates = [e for y, e in zip(model.state, model.rhs, strict=True) if y in used]
    if expanded_size(model, rates) <= CHAIN_OPS:
        return False
    exprs = [*model.rhs, *(e for _, e in model.aux)]
    return not any(model.time in sp.sympify(e).free_symbols for e in exprs)


def _exact(x: sp.Expr) -> sp.Expr:
    """A number of the field the square roots make, in a canonical form (zero exactly
    when it is zero)."""
    return sp.expand(sp.radsimp(sp.expand(x)))


def rate_at(model: Model, expr: sp.Expr, point: dict) -> sp.Expr:
    """``d expr/dt`` along the model's flow at an exact point, through the auxiliaries.

    The auxiliaries' values and rates at a point are kept for the next expression at the
    same point of the same equations (the last few points), and every expression's
    partial derivatives for the next point: both are exact, so the rate is the same.

    Parameters
    ----------
    model : Model
        Autonomous (see :func:`applies`).
    expr : sympy.Expr
        A function of the state, parameters and auxiliaries.
    point : dict
        Exact values of the state and the parameters.

    Returns
    -------
    sympy.Expr
        The exact rate (``nan`` or ``zoo`` where an auxiliary is singular at the point).
    """
    aux, state = tuple(model.aux), tuple(model.state)
    values, rates, f = _flow_at(aux, state, tuple(model.rhs), frozenset(point.items()))
    return _along(sp.sympify(expr), state, tuple(s for s, _ in aux), values, rates, f)


@functools.lru_cache(maxsize=4096)
def _partials(e: sp.Expr, symbols: tuple) -> tuple:
    """``(s, de/ds)`` for the ``symbols`` that ``e`` has, in their order."""
    free = e.free_symbols
    return tuple((s, sp.diff(e, s)) for s in symbols if s in free)


def _along(e: sp.Expr, state: tuple, aux: tuple, values: dict, rates: dict,
           f: dict) -> sp.Expr:  # fmt: skip
    """``de/dt`` at the point of ``values``: ``sum_y de/dy f_y + sum_B de/dB dB/dt`` over the
    auxiliaries ``B`` whose rates are known (those defined before), exact."""
    total = sum((d * f[y] for y, d in _partials(e, state)), sp.S.Zero)
    total += sum((d * rates[a] for a, d in _partials(e, aux) if a in rates), sp.S.Zero)
    return _exact(total.xreplace(values))


@functools.lru_cache(maxsize=8)
def _flow_at(aux: tuple, state: tuple, rhs: tuple, point: frozenset) -> tuple:
    """The auxiliaries' exact values and rates and the right-hand side at ``point``."""
    values, rates = dict(point), {}
    for symbol, definition in aux:
        values[symbol] = _exact(sp.sympify(definition).xreplace(values))
    f = {y: _exact(sp.sympify(e).xreplace(values)) for y, e in zip(state, rhs, strict=True)}
    symbols = tuple(s for s, _ in aux)
    for symbol, definition in aux:  # each auxiliary's rate, from those before it
        rates[symbol] = _along(sp.sympify(definition), state, symbols, values, rates, f)
    return values, rates, f


def decide_along_flow(
    model: Model, exprs: Sequence[sp.Expr], points: int = 4, seed: int = 20121
) -> Outcome:
    """Decide that every expression is an integral: its rate is exactly zero at ``points``
    random regular points of the phase space (:func:`rate_at`).

    Parameters
    ----------
    model : Model
    exprs : sequence of sympy.Expr
        The would-be integrals.
    points : int
        Regular points to try (a point where an auxiliary is singular is drawn again).
    seed : int
        Seed of the sampler (the verdict is reproducible).

    Returns
    -------
    Outcome
        ``exact-sampled``, or ``refuted`` with the rate and the witness point.

    Raises
    ------
    ValueError
        When no regular point is found in ``20 points`` draws.
    """
    start = time.perf_counter()
    rng = random.Random(seed)
    tried = attempts = 0
    while tried < points and attempts < 20 * points:
        attempts += 1
        point = sample_point(model, rng, model.state)
        rates = [rate_at(model, e, point) for e in exprs]
        if any(r.has(sp.nan, sp.zoo, sp.oo, -sp.oo) for r in rates):
            continue
        tried += 1
        for r in rates:
            if r != 0:
                return Outcome(
                    "refuted",
                    "exact arithmetic through the auxiliaries at a point of the phase space",
                    time.perf_counter() - start,
                    str(r),
                    {s.name: str(v) for s, v in sorted(point.items(), key=lambda kv: kv[0].name)},
                )
    if tried == 0:
        raise ValueError("no regular sample point found for the rate through the auxiliaries")
    return Outcome(
        "exact-sampled",
        f"exactly zero at {tried} random points of the phase space, the rate evaluated "
        f"through the model's {len(model.aux)} auxiliaries in order (chain rule; the expanded "
        f"right-hand side has about {expanded_size(model):.1e} operations)",
        time.perf_counter() - start,
        "0",
    )
