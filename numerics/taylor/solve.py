"""The entry of the Taylor integrator, :func:`taylor_solve`: the backend chosen from the
precision's arithmetic."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import gmpy2
import mpmath

from ..precision import Precision
from .c_run import _c_run
from .control import MAX_STEPS, run_orders
from .library import load_taylor_library, load_taylor_mpfr_library
from .mpfr_run import _mpfr_run, _MpfrStepper
from .solution import TaylorSolution
from .stepper import _loop_linspace, _py_run, _Stepper

if TYPE_CHECKING:
    from ..code import ModelCode

__all__ = ["taylor_solve"]


def taylor_solve(
    code: ModelCode,
    y0: Sequence[float | mpmath.mpf],
    t_span: tuple[float | mpmath.mpf, float | mpmath.mpf],
    p: Sequence[float | mpmath.mpf],
    *,
    precision: Precision | str | int = "double",
    rtol: float,
    atol: float,
    t_eval: Sequence[float | mpmath.mpf] | None = None,
    events: Sequence[Callable] | Callable | None = None,
    order: int | None = None,
    step: float | None = None,
    max_steps: int = MAX_STEPS,
    lib: str | None = None,
    max_wall_s: float | None = None,
) -> TaylorSolution:
    """Integrate with the Taylor method; see :mod:`chaplygin.numerics.taylor`.

    Parameters
    ----------
    code : ModelCode
        The model (:func:`chaplygin.numerics.code.load_model_code`).
    y0, p : sequence
        State and parameters (floats in double, ``mpmath.mpf`` otherwise).
    t_span : (t0, t1)
        Start and end times; ``t1 < t0`` integrates backward.
    precision : Precision, "double", "quad" or int
        The working precision (a number: of digits); the run enters its context
        (:meth:`~chaplygin.numerics.precision.Precision.context`) itself.
    rtol, atol : float
        Local tolerances of the Jorba-Zou control.
    t_eval : sequence, optional
        Output times inside the span (default 11 equispaced points).
    events : callable or sequence of callables, optional
        ``g(t, y)``; a sign change inside a step is an event, located on the step's Taylor
        polynomial to the working precision. ``g.terminal = True`` stops the integration at
        the first event; ``g.direction`` (> 0 rising, < 0 falling, 0 both) as in scipy.
    order, step : optional
        Fixed order and/or fixed step (for convergence studies); default adaptive.
    lib : {"c", "gmpy2", "mpmath", "float"}, optional
        Force a backend (default: the compiled integrator in the precision's arithmetic:
        double, quad, double-double up to :data:`DD_BITS` bits, quad-double up to
        :data:`QD_BITS`, MPFR beyond).
    max_wall_s : float, optional
        Wall-time limit (status -6 past it), checked between steps of the Python loop and
        between calls of ``precision.arithmetic.chunk_steps`` steps of the compiled loop
        (which resume exactly: the results do not depend on the limit).

    max_steps : int
        Largest number of steps (status -2 beyond it).

    Returns
    -------
    TaylorSolution
        States at ``t_eval``, status (0: reached ``t1``) and message, step count, the orders
        used, the backend and the events.

    Raises
    ------
    ValueError
        A fixed order outside 2..80, ``t_eval`` not sorted in the direction of
        integration, or ``lib="float"`` outside double precision.
    UserInputError
        An unknown precision.
    """
    precision = Precision(precision)
    with precision.context():
        return _solve(
            code, y0, t_span, p, precision, rtol, atol, t_eval, events, order, step,
            max_steps, lib, max_wall_s,
        )  # fmt: skip


def _solve(code, y0, t_span, p, precision, rtol, atol, t_eval, events, order, step, max_steps,
           lib, max_wall_s) -> TaylorSolution:
    """:func:`taylor_solve` inside the precision's context: the backend from its arithmetic."""
    if order is not None and not 2 <= order <= 80:
        raise ValueError("order must be in 2..80")
    t0, t1 = t_span
    direction = 1 if t1 > t0 else -1
    t_eval = list(_loop_linspace(precision, t0, t1, 11) if t_eval is None else t_eval)
    if any(direction * (t_eval[i + 1] - t_eval[i]) < 0 for i in range(len(t_eval) - 1)):
        raise ValueError("t_eval must be sorted in the direction of integration")
    if events is not None and callable(events):
        events = [events]
    events = list(events or [])
    arithmetic = precision.arithmetic
    clib = None
    if lib in (None, "c") and arithmetic.name != "mpfr":
        # the compiled integrator in the precision's arithmetic: double, __float128, or
        # fixed-size multi-double where it carries the working precision
        clib = load_taylor_library(code, arithmetic.name, run_orders(rtol, atol, order))
    elif lib in (None, "c"):
        # MPFR in C beyond (one call per step when events are asked for)
        mlib = load_taylor_mpfr_library(code)
        if mlib is not None and not events:
            return _mpfr_run(mlib, y0, (t0, t1), p, rtol, atol, t_eval, order, step, max_steps,
                             max_wall_s, precision.bits)  # fmt: skip
        if mlib is not None:  # events located in Python on the compiled steps
            stepper = _MpfrStepper(mlib, p, rtol, atol, order, step, precision.bits)
            return _py_run(
                stepper, y0, (t0, t1), t_eval, events, max_steps, precision, max_wall_s
            )
    numbers = "mpmath" if lib == "mpmath" else arithmetic.python_numbers
    if clib is None and lib == "float" and numbers != "float":
        raise ValueError("lib='float' works in double precision only")
    if clib is not None and not events:
        return _c_run(clib, y0, (t0, t1), p, rtol, atol, t_eval, order, step, max_steps, max_wall_s)
    if clib is None and numbers == "gmpy2":
        # gmpy2/MPFR at the working precision (113 bits for the quad fallback). The stepper
        # converts the parameters when it is made: it must be made inside the context, or
        # MPFR rounds them to the default 53 bits.
        with gmpy2.context(gmpy2.get_context(), precision=precision.bits):
            stepper = _Stepper(code, numbers, p, rtol, atol, order, step, clib)
            return _py_run(stepper, y0, (t0, t1), t_eval, events, max_steps, precision, max_wall_s)
    stepper = _Stepper(code, numbers, p, rtol, atol, order, step, clib)
    return _py_run(stepper, y0, (t0, t1), t_eval, events, max_steps, precision, max_wall_s)
