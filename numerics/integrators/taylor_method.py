"""The Taylor integrator generated from the model, as an integration method."""

from __future__ import annotations

from collections.abc import Mapping
from typing import ClassVar

from ...derive.errors import UserInputError
from .base import Integrator, Problem, Solution

__all__ = ["TaylorMethod"]


class TaylorMethod(Integrator):
    """Taylor method generated from the model (:mod:`chaplygin.numerics.taylor`).

    Adaptive order and step (Jorba-Zou) from rtol/atol, dense output, event location.
    ``double``, ``quad``, up to 31 digits (double-double), up to 60 (quad-double) and more
    digits (MPFR) run in compiled C (``backend="numpy"`` or no compiler: the Python
    recurrences, with MPFR numbers past double). Its step control works to
    the unit roundoff: the tolerance floor is 1 eps in every precision.
    """

    name = "taylor"
    precisions = ("double", "quad", "digits")
    rtol_floor = {"double": 1.0, "quad": 1.0, "digits": 1.0}
    supports_events = True
    options = ("order", "step", "max_steps")
    backends = ("c", "numpy", "mpmath")

    #: precision kinds with a compiled C integrator (``double``, ``__float128``)
    compiled: ClassVar[tuple[str, ...]] = ("double", "quad")
    #: number library of the Python recurrences, per precision kind (``backend="numpy"``)
    python_libs: ClassVar[Mapping[str, str]] = {
        "double": "float",
        "quad": "gmpy2",
        "digits": "gmpy2",
    }

    def _prepare(self, problem: Problem, backend: str) -> str:
        from ..taylor import (
            digits_real_type,
            load_taylor_library,
            load_taylor_mpfr_library,
            run_orders,
        )

        kind = problem.precision.kind
        if backend == "numpy":
            return "numpy"
        if kind not in self.compiled:
            # up to 31 digits double-double, up to 60 quad-double, more digits MPFR, all in C
            # (compiled or loaded now: set-up time); without a compiler MPFR in Python
            c_kind = digits_real_type(problem.precision.prec)
            if c_kind is not None and load_taylor_library(problem.code, c_kind) is not None:
                return "c"
            if c_kind is None and load_taylor_mpfr_library(problem.code) is not None:
                return "c"
            return "mpmath"
        # compile or load now (the coefficients written out for the run's orders): set-up,
        # not wall time
        orders = run_orders(problem.rtol, problem.atol, problem.options.get("order"))
        if load_taylor_library(problem.code, kind, orders) is None and backend == "c":
            raise UserInputError("backend 'c' needs a C compiler (install gcc or set CC)")
        return "c"

    def _solve(self, problem: Problem, backend: str) -> Solution:
        from ..taylor import taylor_solve

        kind = problem.precision.kind
        sol = taylor_solve(
            problem.code,
            problem.y0,
            problem.t_span,
            problem.params,
            precision=kind,
            rtol=problem.rtol,
            atol=problem.atol,
            t_eval=problem.t_eval,
            events=problem.events,
            lib=self.python_libs[kind] if backend == "numpy" else None,
            max_wall_s=problem.max_wall_s,
            **{
                **problem.options,
                **({"max_steps": problem.max_steps} if problem.max_steps else {}),
            },
        )
        return self._solution(problem, sol)

    @staticmethod
    def _solution(problem: Problem, sol) -> Solution:
        """A :class:`~chaplygin.numerics.taylor.TaylorSolution` as the protocol's Solution."""
        return Solution(
            t=sol.t,
            y=sol.y,
            status=sol.status,
            message=f"{sol.message}; orders {sol.order_min}..{sol.order_max} ({sol.backend})",
            nfev=sol.nsteps,
            nsteps=sol.nsteps,
            backend=sol.backend,
            t_events=sol.t_events,
            y_events=sol.y_events,
            info={
                "order_min": sol.order_min,
                "order_max": sol.order_max,
                "taylor_backend": sol.backend,
                "rtol": problem.rtol,
                "atol": problem.atol,
            },
        )
