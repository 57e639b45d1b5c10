"""The Taylor integrator generated from the model, as an integration method."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ...derive.errors import ComputationError, UserInputError
from . import c_batch
from .base import Integrator, Problem, Solution
from .flows import Batch, ModelFlow

__all__ = ["TaylorMethod", "TaylorSession"]


class TaylorMethod(Integrator):
    """Taylor method generated from the model (:mod:`chaplygin.numerics.taylor`).

    Adaptive order and step (Jorba-Zou) from rtol/atol, dense output, event location.
    ``double``, ``quad``, up to 31 digits (double-double), up to 60 (quad-double) and more
    digits (MPFR) run in compiled C (``backend="numpy"`` or no compiler: the Python
    recurrences, with MPFR numbers past double): the precision's
    :attr:`~chaplygin.numerics.precision.Precision.arithmetic`. Its step control works to
    the unit roundoff: the tolerance floor is 1 eps in every precision.

    It also integrates a :class:`~chaplygin.numerics.integrators.flows.Batch` of a
    time-periodic model in one C call (``derive/templates/taylor_batch_map.c``: the
    double build's integrator 4 or 8 points at a time in vector lanes, ``taylor_lanes.c``, each
    point bit-identical to ``chaplygin_taylor_run``; the step polynomials evaluated at the
    sampling times), and keeps the solution between the outputs in double precision when the
    problem asks for ``dense_output`` (:class:`~chaplygin.numerics.taylor.TaylorDense`).
    """

    name = "taylor"
    flows = (ModelFlow, Batch)
    precisions = ("double", "quad", "digits")
    rtol_floor = {"double": 1.0, "quad": 1.0, "digits": 1.0}
    supports_events = True
    options = ("order", "step", "max_steps")
    backends = ("c", "numpy", "mpmath")

    def _prepare(self, problem: Problem, backend: str) -> str:
        from ..taylor import load_taylor_library, load_taylor_mpfr_library, run_orders

        if isinstance(problem.system, Batch):
            orders = run_orders(problem.rtol, problem.atol)
            if c_batch.taylor_batch_library(problem.code, orders=orders) is None:
                raise ComputationError(
                    "the batch map needs a C compiler (the Taylor one also the model's "
                    "generated Taylor code); use StroboscopicMap"
                )
            return "c"
        precision = problem.precision
        arithmetic = precision.arithmetic
        if backend == "numpy":
            return "numpy"
        if precision.kind == "digits":
            # up to 31 digits double-double, up to 60 quad-double, more digits MPFR, all in C
            # (compiled or loaded now: set-up time); without a compiler MPFR in Python
            if arithmetic.name != "mpfr":
                if load_taylor_library(problem.code, arithmetic.name) is not None:
                    return "c"
            elif load_taylor_mpfr_library(problem.code) is not None:
                return "c"
            return "mpmath"
        # compile or load now (the coefficients written out for the run's orders): set-up,
        # not wall time
        orders = run_orders(problem.rtol, problem.atol, problem.options.get("order"))
        if load_taylor_library(problem.code, arithmetic.name, orders) is None and backend == "c":
            raise UserInputError("backend 'c' needs a C compiler (install gcc or set CC)")
        return "c"

    def _solve(self, problem: Problem, backend: str) -> Solution:
        from ..taylor import taylor_solve

        if isinstance(problem.system, Batch):
            return _batch(problem)
        if problem.dense_output:
            return _dense(problem, backend)
        precision = problem.precision
        sol = taylor_solve(
            problem.code,
            problem.y0,
            problem.t_span,
            problem.params,
            precision=precision,
            rtol=problem.rtol,
            atol=problem.atol,
            t_eval=problem.t_eval,
            events=problem.events,
            lib=precision.arithmetic.python_numbers if backend == "numpy" else None,
            max_wall_s=problem.max_wall_s,
            **{
                **problem.options,
                **({"max_steps": problem.max_steps} if problem.max_steps else {}),
            },
        )
        return self._solution(problem, sol)

    def session(self, problem: Problem, chosen: str) -> TaylorSession | None:
        """A prepared compiled double loop for many calls on one problem (a
        :class:`~chaplygin.numerics.propagator.Propagator`): its parameters, tolerances and
        buffers converted once; None where each call needs the whole path (not double, not
        on the C backend).

        Parameters
        ----------
        problem : Problem
            A model's equations.
        chosen : str
            The backend :meth:`prepare` chose for it.

        Returns
        -------
        TaylorSession or None
        """
        from ..taylor import MAX_STEPS, CompiledTaylorRun, load_taylor_library, run_orders

        if not (problem.precision.is_double and chosen == "c"):
            return None
        options = problem.options
        order = options.get("order")
        lib = load_taylor_library(problem.code, "double",
                                  run_orders(problem.rtol, problem.atol, order))
        if lib is None:
            return None
        run = CompiledTaylorRun(lib, problem.params, problem.rtol, problem.atol, order,
                                options.get("step"), options.get("max_steps") or MAX_STEPS,
                                problem.max_wall_s)  # fmt: skip
        return TaylorSession(self, run)

    @staticmethod
    def _solution(problem: Any, sol) -> Solution:
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


class TaylorSession:
    """The compiled double Taylor loop of one problem, called again and again
    (:meth:`TaylorMethod.session`)."""

    def __init__(self, method: TaylorMethod, loop: Any):
        self._method = method
        #: the :class:`~chaplygin.numerics.taylor.CompiledTaylorRun`
        self.loop = loop

    def solve(self, view: Any, y0: Sequence, t_span: tuple, t_eval: Sequence) -> Solution:
        """Integrate from ``y0`` over ``t_span`` with output at ``t_eval``.

        Parameters
        ----------
        view : object
            The problem as the result reads it (``rtol``, ``atol``).
        y0 : sequence of float
        t_span : (t0, t1)
        t_eval : sequence of float

        Returns
        -------
        Solution
        """
        return self._method._solution(view, self.loop.run(y0, t_span, t_eval))


def _dense(problem: Problem, backend: str) -> Solution:
    """The double-precision solution with every step's polynomial
    (:func:`~chaplygin.numerics.taylor.taylor_dense`): ``Solution.dense``, the start and the
    time reached as ``t`` and the states there as ``y``."""
    from ..taylor import MAX_STEPS, taylor_dense

    if not problem.precision.is_double or problem.events:
        raise UserInputError("dense output is kept in double precision, without events")
    dense = taylor_dense(
        problem.code, problem.y0, problem.t_span, problem.params,
        rtol=problem.rtol, atol=problem.atol, max_steps=problem.max_steps or MAX_STEPS,
        lib="float" if backend == "numpy" else None,
    )  # fmt: skip
    ends = np.array([dense.t[0], dense.t[-1]])
    return Solution(
        t=ends,
        y=np.asarray(dense(ends)),
        status=dense.status,
        message=dense.message,
        nfev=len(dense.t) - 1,
        nsteps=len(dense.t) - 1,
        backend=dense.backend,
        dense=dense,
    )


def _batch(problem: Problem) -> Solution:
    from ..taylor import run_orders

    orders = run_orders(problem.rtol, problem.atol)
    lib = c_batch.taylor_batch_library(problem.code, orders=orders)
    sol, stats = c_batch.run_batch(lib.chaplygin_taylor_batch_map, problem)
    steps = stats[:, 0].astype(np.int64)  # STATS: steps, lowest order, highest order
    sol.info.update(
        steps=steps,
        rejected=np.zeros(len(steps), dtype=np.int64),
        evaluations=steps.copy(),
        orders=stats[:, 1:].astype(np.int64),
        lockstep=True,
    )
    sol.nsteps = sol.nfev = int(steps.sum())
    return sol
