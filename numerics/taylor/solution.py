"""The outcome of a Taylor integration (:class:`TaylorSolution`) and its status messages."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["TaylorSolution"]

# --------------------------------------------------------------------------- solution


@dataclass
class TaylorSolution:
    """Raw outcome of :func:`taylor_solve` (``integrate`` wraps it in an IntegrationResult).

    ``y`` is ``(n_state, len(t))``: float64 in double, ``mpmath.mpf`` objects otherwise;
    ``t_events[i]``, ``y_events[i]``: times and states where event ``i`` fired.
    """

    t: np.ndarray
    y: np.ndarray
    status: int
    message: str
    nsteps: int
    order_min: int
    order_max: int
    backend: str
    t_events: list = field(default_factory=list)
    y_events: list = field(default_factory=list)


_MESSAGES = {
    0: "reached t_end",
    -1: "the solution became NaN or infinite; check the parameters and state",
    -2: "too many steps (max_steps); shorten the span or loosen the tolerance",
    -3: "the step size underflowed: the solution is singular near this time",
    -4: "out of memory in the C integrator",
    -6: "the wall-time limit (max_wall_s) was reached: raise it (None: no limit) or shorten "
    "the span",
}
