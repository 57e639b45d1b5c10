"""scipy's ``solve_ivp`` methods, in double precision on the generated right-hand side.

They integrate a model's equations and its reversed flow; the explicit ones (RK45, DOP853)
also the variational equations (the numpy module's ``rhs`` and ``jac``: what the compiled
DOP853 of :mod:`~chaplygin.numerics.integrators.dop853_c` falls back to without a compiler).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from scipy.integrate import solve_ivp

from ...derive.errors import UserInputError
from .base import Budget, BudgetExceeded, Integrator, Problem, Solution
from .flows import ModelFlow, ReversedFlow, VariationalFlow

__all__ = ["ScipyMethod", "RK45", "DOP853", "LSODA", "Radau", "BDF"]


def _counting(method: str) -> tuple[type, list[int]]:
    """scipy's solver class ``method`` counting its accepted steps into the returned list.

    ``solve_ivp`` reports no step count, and with ``t_eval`` its ``t`` holds the output
    times, not the steps; ``solve_ivp`` takes an ``OdeSolver`` subclass as ``method``, whose
    public :meth:`~scipy.integrate.OdeSolver.step` is one accepted step when it returns None.
    """
    import scipy.integrate

    base = getattr(scipy.integrate, method)
    count = [0]

    class Counting(base):
        def step(self):
            message = super().step()
            if message is None:
                count[0] += 1
            return message

    Counting.__name__ = base.__name__
    return Counting, count


def _scipy_event(g):
    """``g(t, y)`` as scipy calls events (with the ``args``), keeping terminal/direction."""

    def event(t, y, *args):
        return g(t, y)

    event.terminal = getattr(g, "terminal", False)
    event.direction = getattr(g, "direction", 0)
    return event


class ScipyMethod(Integrator):
    """A ``scipy.integrate.solve_ivp`` method in double precision, on the generated C or
    numpy right-hand side; implicit methods get the generated Jacobian."""

    implicit: ClassVar[bool] = False
    flows = (ModelFlow, ReversedFlow)
    supports_events = True
    backends = ("c", "numpy")
    #: steps allowed by default (``max_steps``)
    default_max_steps: ClassVar[int] = 1_000_000
    #: right-hand-side calls counted as one step by the step limit (the explicit methods'
    #: stages; an allowance for the implicit ones' Newton iterations)
    calls_per_step: ClassVar[int] = 20

    def _prepare(self, problem: Problem, backend: str) -> str:
        if isinstance(problem.system, VariationalFlow):
            return "numpy"  # the numpy module's rhs and jac (the compiled ones are in C)
        if backend == "numpy":
            return "numpy"
        chosen = "c" if problem.code.compiled() is not None else "numpy"
        if backend == "c" and chosen != "c":
            raise UserInputError("backend 'c' needs a C compiler (install gcc or set CC)")
        return chosen

    def _solve(self, problem: Problem, backend: str) -> Solution:
        flow = problem.system
        kwargs = {}
        if problem.events:
            kwargs["events"] = [_scipy_event(g) for g in problem.events]
        rhs, jac = flow.double_rhs(backend)
        if self.implicit:
            kwargs["jac"] = jac
        steps = problem.max_steps or self.default_max_steps
        budget = Budget(steps * self.calls_per_step, problem.max_wall_s, f"max_steps={steps}")
        y0 = np.asarray(problem.y0, dtype=float)
        method, steps_taken = _counting(self.name)
        try:
            sol = solve_ivp(
                budget.wrap(rhs),
                problem.t_span,
                y0,
                method=method,
                rtol=problem.rtol,
                atol=flow.atol(problem.atol, y0.size),
                args=(np.asarray(problem.params, dtype=float),),
                t_eval=problem.t_eval,
                **kwargs,
            )
        except BudgetExceeded as stop:  # scipy keeps no partial solution: the start only
            return Solution(
                t=np.array([problem.t_span[0]], dtype=float),
                y=y0.reshape(-1, 1),
                status=stop.status,
                message=stop.message,
                nfev=budget.calls,
                nsteps=steps_taken[0],
            )
        message = sol.message
        if sol.status != 0 and not isinstance(flow, VariationalFlow):
            message += "; try a smaller rtol/atol, an implicit method (Radau, LSODA) or more digits"
        return Solution(
            t=sol.t,
            y=sol.y,
            status=sol.status,
            message=message,
            nfev=sol.nfev,
            njev=sol.njev,
            nsteps=steps_taken[0],  # the solver's accepted steps (not the outputs)
            t_events=list(sol.t_events) if problem.events else [],
            y_events=list(sol.y_events) if problem.events else [],
        )


class RK45(ScipyMethod):
    """scipy's explicit Runge-Kutta 5(4) (Dormand-Prince)."""

    name = "RK45"
    flows = (ModelFlow, ReversedFlow, VariationalFlow)
    calls_per_step = 6


class DOP853(ScipyMethod):
    """scipy's explicit Runge-Kutta 8(5,3) (Hairer's DOP853)."""

    name = "DOP853"
    flows = (ModelFlow, ReversedFlow, VariationalFlow)
    calls_per_step = 12


class LSODA(ScipyMethod):
    """scipy's LSODA (Adams/BDF switching), with the generated Jacobian."""

    name = "LSODA"
    implicit = True


class Radau(ScipyMethod):
    """scipy's implicit Runge-Kutta Radau IIA of order 5, with the generated Jacobian."""

    name = "Radau"
    implicit = True


class BDF(ScipyMethod):
    """scipy's variable-order BDF, with the generated Jacobian."""

    name = "BDF"
    implicit = True
