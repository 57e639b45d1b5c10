"""Order rules and limits of the Taylor integrator.

The order of Jorba and Zou (2005) for a tolerance, and the orders a compiled run can choose
(the step-size rule runs in the C loop, ``derive/templates/taylor.c``, and in the Python
stepper, :mod:`chaplygin.numerics.taylor.stepper`); see :mod:`chaplygin.numerics.taylor`.
"""

from __future__ import annotations

import functools
import math

from ...arith import detmath

__all__ = ["PY_MAX_ORDER", "MAX_STEPS", "jorba_zou_order", "run_orders"]

#: Largest order the Python recurrences use by default (the C library has its own cap).
PY_MAX_ORDER = 400

#: Default largest number of steps of one integration.
MAX_STEPS = 10_000_000


@functools.lru_cache(maxsize=256)
def jorba_zou_order(eps: float, max_order: int = 80) -> int:
    """Order ``ceil(-ln(eps)/2 + 1)`` of Jorba and Zou (2005), between 2 and ``max_order``.

    Parameters
    ----------
    eps : float
        Tolerance of the step (``atol`` or ``rtol``, see :mod:`chaplygin.numerics.taylor`), ``> 0``.
    max_order : int
        Largest order returned.

    Returns
    -------
    int
        The order ``p``.
    """
    return int(min(max(math.ceil(-0.5 * detmath.log(eps) + 1.0), 2), max_order))


def run_orders(rtol: float, atol: float, order: int | None = None) -> tuple[int, ...]:
    """The orders the C step control can choose for these tolerances (or the fixed order).

    Parameters
    ----------
    rtol, atol : float
        Tolerances (relative control uses the order of ``rtol``, absolute that of ``atol``).
    order : int, optional
        A fixed order.

    Returns
    -------
    tuple of int
        One or two orders (:func:`jorba_zou_order`, capped at the C limit 80).
    """
    if order:
        return (int(order),)
    return tuple(sorted({jorba_zou_order(float(rtol)), jorba_zou_order(float(atol))}))
