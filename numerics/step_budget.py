"""How many steps a span needs, estimated before any work (a guard against spans such as
``t_end = 1e9`` that could only end at a step or time limit).

The estimate is ``T * rtol^(-1/(p+1))`` for an order-p scipy method and ``T * e^2`` for the
Taylor methods, with ``T = span * max(1, |f(y0)|/|y0|)`` (per state group: a fast spin turns
gamma at its rate). On the reference problem it is about ten times the steps taken (``rtol``
1e-12, 1000 time units: 21544 estimated, 2152 taken): a guard, not a prediction.

``chaplygin integrate`` and scenes refuse a span whose estimate exceeds their step budget
(``--max-steps``, ``[run] max_steps``; default :data:`DEFAULT_MAX_STEPS`). The Python API
(:func:`~chaplygin.numerics.integrate.integrate`, :class:`~chaplygin.numerics.propagator.
Propagator`) runs up to its ``max_steps``; when none is given, it refuses up front a span whose
estimate at unit rate exceeds :data:`API_REFUSAL_FACTOR` times the default limit: such a run
could only end at that limit.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..arith import detlinalg

__all__ = [
    "DEFAULT_MAX_STEPS",
    "API_REFUSAL_FACTOR",
    "estimated_steps",
    "motion_rate",
    "refuse_hopeless_span",
]

#: The step budget of ``chaplygin integrate`` and of scenes unless raised.
DEFAULT_MAX_STEPS = 10_000_000

#: The API refuses a span whose estimate (at unit rate) is this many times its ``max_steps``.
API_REFUSAL_FACTOR = 100

#: Orders of the scipy methods: at unit frequency a step of an order-p method at relative
#: tolerance rtol is about rtol**(1/(p+1)) time units long.
SCIPY_ORDERS = {"rk45": 5, "dop853": 8, "lsoda": 5, "radau": 5, "bdf": 5, "rk23": 3}

#: Steps per time unit of the Taylor methods (taylor, odefun) at unit radius of
#: convergence: the Jorba-Zou step is e^-2 times the radius, whatever the tolerance.
TAYLOR_STEPS_PER_TIME = math.e**2


def estimated_steps(span: float, method: str | None, rtol: float | None, double: bool) -> float:
    """Steps an integration over ``span`` time units needs at unit frequency (a guard).

    Parameters
    ----------
    span : float
        ``|t_end - t_start|``, in units of the motion's time scale (multiply it by
        :func:`motion_rate` when that is known).
    method : str or None
        The method's name (None: taylor).
    rtol : float or None
        The relative tolerance (None: 1e-10 in double; the Taylor step does not depend on it).
    double : bool
        Double precision (the scipy methods) or not.

    Returns
    -------
    float
        ``span * rtol**(-1/(p+1))`` for a scipy method of order p, ``span * e**2`` for the
        Taylor methods. Faster motions (large momenta, small inertia) need more.
    """
    name = (method or "taylor").lower()
    if name in SCIPY_ORDERS:
        tol = 1e-10 if rtol is None else float(rtol)
        return span * tol ** (-1.0 / (SCIPY_ORDERS[name] + 1))
    return span * TAYLOR_STEPS_PER_TIME


def motion_rate(code: Any, t0: float, y: Sequence[float], p: Sequence[float]) -> float:
    """``max(1, max_g |f_g(t0, y)| / |y_g|)`` over the state groups g (M, gamma, ...): how
    fast the state moves at the start.

    Parameters
    ----------
    code : ModelCode
    t0 : float
    y, p : sequence of float
        State and parameters (read as doubles).

    Returns
    -------
    float
        At least 1; 1 where it cannot be evaluated in double precision.
    """
    try:
        yy = np.asarray([float(v) for v in y])
        pp = np.asarray([float(v) for v in p])
        with np.errstate(all="ignore"):
            f = np.asarray(code.numpy.rhs(float(t0), yy, pp), float)
    except (ArithmeticError, ValueError, TypeError):
        return 1.0
    rate = 1.0
    with np.errstate(all="ignore"):
        for names in code.state_groups.values():
            index = [code.state.index(n) for n in names]
            size = detlinalg.norm(yy[index])
            if size > 0:
                rate = max(rate, detlinalg.norm(f[index]) / size)
    return rate if math.isfinite(rate) else 1.0


def refuse_hopeless_span(
    span: float, method: str | None, rtol: float | None, double: bool, max_steps: int
) -> str | None:
    """Why the API refuses ``span`` before any work, or None.

    A span is refused when its estimate at unit rate exceeds :data:`API_REFUSAL_FACTOR`
    times ``max_steps``: the run could only end at the step limit.

    Parameters
    ----------
    span : float
        ``|t_end - t_start|`` (a float; infinite for spans beyond double).
    method, rtol, double
        As for :func:`estimated_steps`.
    max_steps : int
        The run's step limit.

    Returns
    -------
    str or None
        The reason (one sentence naming the numbers and the remedy).
    """
    steps = estimated_steps(span, method, rtol, double)
    if steps <= API_REFUSAL_FACTOR * max_steps:
        return None
    return (
        f"a span of {span:.3g} needs about {steps:.2g} steps, more than "
        f"{API_REFUSAL_FACTOR} times max_steps = {max_steps:.3g}: it could only end at the "
        "step limit; shorten the span (or raise max_steps)"
    )
