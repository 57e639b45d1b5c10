"""``mpmath.odefun``, the baseline the generated Taylor integrator is compared with."""

from __future__ import annotations

import dataclasses

import mpmath
import numpy as np

from .base import Budget, BudgetExceeded, Integrator, Problem, Solution
from .flows import ModelFlow, ReversedFlow

__all__ = ["MpmathOdefun"]


class MpmathOdefun(Integrator):
    """``mpmath.odefun``: mpmath's Taylor-series method at the working precision (baseline).

    Kept for comparison with :class:`TaylorMethod`; it ignores rtol/atol (it works to the
    full working precision) and supports no events. ``mpmath.odefun`` only runs forward: a
    backward span of a model's equations is the forward span of its
    :class:`~chaplygin.numerics.integrators.flows.ReversedFlow` (``s = -t``).
    """

    name = "odefun"
    flows = (ModelFlow, ReversedFlow)
    precisions = ("quad", "digits")
    rtol_floor = {"quad": 10.0, "digits": 10.0}

    def _solve(self, problem: Problem, backend: str) -> Solution:
        t0, t1 = (mpmath.mpf(v) for v in problem.t_span)
        if t1 < t0:  # backward: the reversed flow forward, its times s = -t
            mirrored = dataclasses.replace(
                problem,
                system=_reversed(problem.system),
                t_span=(-t0, -t1),
                t_eval=None if problem.t_eval is None else [-mpmath.mpf(t) for t in problem.t_eval],
            )
            sol = self._forward(mirrored)
            sol.t = np.array([-t for t in sol.t], dtype=object)
            return sol
        return self._forward(problem)

    @staticmethod
    def _forward(problem: Problem) -> Solution:
        rhs, p = problem.system.mpmath_rhs(), problem.params
        budget = Budget(problem.max_steps, problem.max_wall_s, f"max_steps={problem.max_steps}")

        def F(t, y):
            budget.tick()
            return rhs(t, y, p)

        t0, t1 = (mpmath.mpf(v) for v in problem.t_span)
        # mpmath's own default degree, given so that the steps can be counted: each step
        # (one Taylor series) evaluates F exactly ``degree`` times (mpmath ``ode_taylor``)
        degree = 3 + int(3 * mpmath.mp.dps / 2)
        solution = mpmath.odefun(F, t0, list(problem.y0), degree=degree)
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
                nsteps=budget.calls // degree,
            )
        return Solution(
            t=np.array(times, dtype=object),
            y=y,
            status=0,
            message="reached t_end",
            nfev=budget.calls,
            nsteps=budget.calls // degree,
        )


def _reversed(flow):
    """The flow with the other direction of time."""
    if isinstance(flow, ReversedFlow):
        return ModelFlow(flow.code)
    return ReversedFlow(flow.code)
