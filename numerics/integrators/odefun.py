"""``mpmath.odefun``, the baseline the generated Taylor integrator is compared with."""

from __future__ import annotations

import mpmath
import numpy as np

from .base import Budget, BudgetExceeded, Integrator, Problem, Solution

__all__ = ["MpmathOdefun"]


class MpmathOdefun(Integrator):
    """``mpmath.odefun``: mpmath's Taylor-series method at the working precision (baseline).

    Kept for comparison with :class:`TaylorMethod`; it ignores rtol/atol (it works to the
    full working precision) and supports no events.
    """

    name = "odefun"
    precisions = ("quad", "digits")
    rtol_floor = {"quad": 10.0, "digits": 10.0}

    def _solve(self, problem: Problem, backend: str) -> Solution:
        rhs, p = problem.code.mpmath.rhs, problem.params
        budget = Budget(problem.max_steps, problem.max_wall_s, f"max_steps={problem.max_steps}")

        def F(t, y):
            budget.tick()
            return rhs(t, y, p)

        t0, t1 = (mpmath.mpf(v) for v in problem.t_span)
        solution = mpmath.odefun(F, t0, list(problem.y0))
        t_eval = problem.t_eval
        times = list(t_eval) if t_eval is not None else list(mpmath.linspace(t0, t1, 11))
        try:
            y = np.array([solution(mpmath.mpf(t)) for t in times], dtype=object).T
        except BudgetExceeded as stop:
            return Solution(
                t=np.array([t0], dtype=object),
                y=np.array([list(problem.y0)], dtype=object).T,
                status=stop.status,
                message=stop.message,
                nfev=budget.calls,
                nsteps=0,
            )
        return Solution(
            t=np.array(times, dtype=object),
            y=y,
            status=0,
            message="reached t_end",
            nfev=budget.calls,
            nsteps=len(times) - 1,
        )
