"""A prepared integration advanced step by step in time (heyoka's ``taylor_adaptive``).

:func:`~chaplygin.numerics.integrate.integrate` reads and checks its inputs, loads the
compiled integrator and integrates, every call. A :class:`Propagator` does the first two
once: its inputs are checked as ``integrate`` checks them, the compiled integrator (for the
Taylor method in double precision the coefficients written out for the run's orders) is
loaded when it is made, and each :meth:`Propagator.propagate_until` integrates from where the
last one stopped and returns the same :class:`IntegrationResult`, with the drift of every
first integral over its outputs as evidence.

Examples
--------
>>> import chaplygin
>>> prop = chaplygin.Propagator("chaplygin_ball", {"M": (0.7, -0.4, 0.5),
...     "gamma": (0.2, 0.3, "sqrt(0.87)")}, {"I": (1, 2, 3), "D": 1}, rtol=1e-12, atol=1e-12)
>>> r = prop.propagate_until(1000.0)
>>> r.success, prop.time == 1000.0, r.drift["H"] < 1e-10
(True, True, True)
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Mapping, Sequence

import numpy as np

from ..derive.errors import UserInputError
from .code import ModelCode
from .inputs import Precision, working_number
from .integrate import DEFAULT_MAX_WALL_S, _read_start, check_output_times, prepare_problem
from .integrators import IntegrationResult
from .step_budget import DEFAULT_MAX_STEPS, refuse_hopeless_span

__all__ = ["Propagator", "call_span"]


class Propagator:
    """A Taylor integration prepared once and advanced by :meth:`propagate_until`.

    Parameters
    ----------
    system : str or ModelCode
        ``"chaplygin_ball"`` (with ``effects``) or loaded code.
    y0 : mapping or sequence
        Initial state, as for :func:`~chaplygin.numerics.integrate.integrate`.
    params : mapping or sequence
        Parameters, as for ``integrate``.
    effects : sequence of str or str, optional
    t0 : float or str, optional
        Initial time (default 0), read at the working precision.
    precision : "double", "quad" or int
        As for ``integrate`` (the Taylor method runs in every precision).
    rtol, atol : float, optional
        Tolerances (the defaults of ``integrate`` for the Taylor method).
    taylor_options : mapping, optional
        ``order`` and/or ``step`` (fixed order, fixed step), ``max_steps``.
    backend : {"auto", "c", "numpy"}
        As for ``integrate``.
    max_wall_s : float or None
        Wall-time limit of each call.

    Attributes
    ----------
    code : ModelCode
        The model.
    time : float or mpmath.mpf
        Where the last call stopped (``t0`` at first).
    state : numpy.ndarray
        The state at :attr:`time` (float, or object array of mpmath.mpf).

    Raises
    ------
    UserInputError
        Every input ``integrate`` refuses, for the same reasons.
    """

    def __init__(
        self,
        system: str | ModelCode,
        y0: Mapping[str, object] | Sequence[float],
        params: Mapping[str, object] | Sequence[float],
        *,
        effects: Sequence[str] | str | None = None,
        t0: float | str = 0.0,
        precision: str | int = "double",
        rtol: float | None = None,
        atol: float | None = None,
        taylor_options: Mapping[str, object] | None = None,
        backend: str = "auto",
        max_wall_s: float | None = DEFAULT_MAX_WALL_S,
    ) -> None:
        start = time.perf_counter()
        # the span only has to pass integrate's checks here; each call sets its own
        t0_value = working_number(t0, Precision(precision))
        self._integrator, self._problem = prepare_problem(
            system,
            y0,
            (t0_value, t0_value + 1),
            params,
            effects=effects,
            method="taylor",
            precision=precision,
            rtol=rtol,
            atol=atol,
            taylor_options=taylor_options,
            max_wall_s=max_wall_s,
        )
        if backend not in ("auto", "c", "numpy"):
            raise UserInputError(f"unknown backend {backend!r}; valid: auto, c, numpy")
        # load (compile once) the integrator now: a call only integrates
        self._backend = self._integrator.prepare(self._problem, backend)
        self._requested_backend = backend
        # a span that could only end at the default step limit is refused (not a given one)
        self._max_steps = None if self._problem.options.get("max_steps") else DEFAULT_MAX_STEPS
        self.code: ModelCode = self._problem.code
        self.time = self._problem.t_span[0]
        self._state = list(self._problem.y0)
        # the compiled double loop with its buffers, when each call can go straight to it
        # (double precision, C backend); else None (each call runs the method's whole path)
        self._fast = self._integrator.session(self._problem, self._backend)
        self.setup_s = time.perf_counter() - start

    def reset(self, y0: Mapping[str, object] | Sequence[float] | None = None,
              t0: float | str | None = None) -> None:
        """Start again from ``y0`` at ``t0`` (heyoka's ``ta.state[:] = ...; ta.time = ...``).

        Parameters
        ----------
        y0 : mapping or sequence, optional
            A new initial state, read and checked as the constructor reads it (default: the
            constructor's).
        t0 : float or str, optional
            The new initial time (default: the constructor's).

        Raises
        ------
        UserInputError
            A state or time the constructor would refuse; nothing changes then.
        """
        prec = self._problem.precision
        t_start = self._problem.t_span[0] if t0 is None else working_number(t0, prec)
        if y0 is None and t0 is None:
            state = list(self._problem.y0)
        else:
            _, state = _read_start(self.code, self._problem.y0 if y0 is None else y0,
                                   self._problem.params, prec, t_start)
        self.time, self._state = t_start, state

    @property
    def state(self) -> np.ndarray:
        """The state at :attr:`time` (a copy)."""
        return np.array(self._state, dtype=float if self._problem.precision.is_double else object)

    def __repr__(self) -> str:
        return (
            f"Propagator({self.code.name}, t={float(self.time):.6g}, "
            f"{self._problem.precision!r}, rtol={self._problem.rtol:g}, backend={self._backend})"
        )

    def propagate_until(
        self, t: float | str, t_eval: Sequence[float] | None = None
    ) -> IntegrationResult:
        """Integrate from :attr:`time` to ``t`` (forward or backward) and stop there.

        Parameters
        ----------
        t : float or str
            The end time, read at the working precision.
        t_eval : sequence of float, optional
            Output times inside the span, sorted in its direction (default: its two ends);
            ``t`` is appended when it is not the last.

        Returns
        -------
        IntegrationResult
            As :func:`~chaplygin.numerics.integrate.integrate` returns it (drift over the
            outputs, steps, times); on success :attr:`time` and :attr:`state` move to ``t``,
            otherwise they stay where they were.

        Raises
        ------
        UserInputError
            ``t`` not a finite number or equal to :attr:`time`, ``t_eval`` outside the span,
            a span that could only end at the default step limit
            (:func:`~chaplygin.numerics.step_budget.refuse_hopeless_span`).
        """
        prec = self._problem.precision
        t_end, outputs = call_span(self.time, t, t_eval, prec, self._max_steps)
        if self._fast is None:
            problem = dataclasses.replace(
                self._problem, y0=list(self._state), t_span=(self.time, t_end), t_eval=outputs
            )
            result = self._integrator.run(problem, self._requested_backend)
        else:  # the C loop with its arguments converted once: what run() does, less work
            start = time.perf_counter()
            view = _RunView(self._problem, self.time, t_end, outputs)
            sol = self._fast.solve(view, self._state, (self.time, t_end), outputs)
            wall = time.perf_counter() - start
            result = self._integrator._result(view, sol, "c", wall, 0.0)
        if result.success and result.y.shape[1]:
            self._state = result.y[:, -1].tolist()
            self.time = t_end
        return result

    def propagate_for(self, dt: float, t_eval: Sequence[float] | None = None) -> IntegrationResult:
        """:meth:`propagate_until` ``time + dt``.

        Parameters
        ----------
        dt : float
            The span (negative: backward).
        t_eval : sequence of float, optional
            Output times (default: the two ends).

        Returns
        -------
        IntegrationResult
            As :meth:`propagate_until`.

        Raises
        ------
        UserInputError
            As :meth:`propagate_until`.
        """
        return self.propagate_until(self.time + working_number(dt, self._problem.precision), t_eval)



def call_span(now: object, t: float | str, t_eval: Sequence[float] | None, prec: Precision,
              max_steps: int | None) -> tuple[object, list]:  # fmt: skip
    """The end time and the output times of a call from ``now`` to ``t`` (the checks of
    :meth:`Propagator.propagate_until`).

    Parameters
    ----------
    now : number
        Where the last call stopped.
    t : float or str
        The end time asked for.
    t_eval : sequence of float or None
        The output times asked for (None: the two ends); ``t`` is appended when it is not
        the last.
    prec : Precision
    max_steps : int or None
        The default step limit (a span that could only end at it is refused), or None when
        a limit was given.

    Returns
    -------
    (number, list)
        The end time and the output times, at the working precision.

    Raises
    ------
    UserInputError
        As :meth:`Propagator.propagate_until`.
    """
    t_end = working_number(t, prec)
    if not t_end != now:
        raise UserInputError(f"the end time {t!r} equals the current time")
    if max_steps is not None:
        hopeless = refuse_hopeless_span(
            abs(float(t_end - now)), "taylor", None, prec.is_double, max_steps
        )
        if hopeless:
            raise UserInputError(hopeless)
    if t_eval is None:
        return t_end, [now, t_end]
    if isinstance(t_eval, str | bytes) or not hasattr(t_eval, "__len__"):
        raise UserInputError(f"t_eval must be a sequence of numbers, got {t_eval!r}")
    outputs = [working_number(v, prec) for v in t_eval]
    lo, hi = min(now, t_end), max(now, t_end)
    if any(not lo <= v <= hi for v in outputs):
        raise UserInputError("t_eval must lie inside the span of the call")
    check_output_times(outputs, (now, t_end))
    if not outputs or outputs[-1] != t_end:  # the end is always an output: the next call
        outputs.append(t_end)  # starts from its state
    return t_end, outputs


class _RunView:
    """The prepared problem seen with one call's span (what ``_solution`` and ``_result``
    read of it; ``dataclasses.replace`` of the problem costs as much as the evidence)."""

    __slots__ = ("code", "params", "precision", "rtol", "atol", "options", "max_steps",
                 "t_span", "t_eval")  # fmt: skip

    def __init__(self, problem, t0, t_end, outputs):
        self.code, self.params, self.precision = problem.code, problem.params, problem.precision
        self.rtol, self.atol = problem.rtol, problem.atol
        self.options, self.max_steps = problem.options, problem.max_steps
        self.t_span, self.t_eval = (t0, t_end), outputs
