"""Many orbits prepared once and advanced together (heyoka's ``taylor_adaptive_batch``).

:func:`~chaplygin.numerics.ensemble.integrate_many` reads and checks its ``N`` starts every
call (the same call again skips the reading, not the key of its inputs). An
:class:`EnsemblePropagator` reads and checks them once, as ``integrate_many`` does, keeps the
starts and parameters as arrays and the compiled integrator loaded, and each
:meth:`EnsemblePropagator.propagate_until` integrates every orbit from the shared
:attr:`~EnsemblePropagator.time` to ``t`` and returns an
:class:`~chaplygin.numerics.ensemble.EnsembleResult`, every orbit with the drift of its first
integrals over the call's outputs as evidence.

In double precision with the Taylor method on the C backend the orbits run in the vector
lanes (:mod:`~chaplygin.numerics.ensemble_lanes`), so orbit ``j``'s numbers are, bit for bit,
those of a :class:`~chaplygin.numerics.propagator.Propagator` of orbit ``j`` called with the
same times; otherwise (quad, decimal digits, the numpy backend) each orbit has its own
``Propagator``, called one after another.

The orbits move together: when every orbit of a call reached its end, :attr:`time` and
:attr:`states` move to it; when one did not (its status says why), nothing moves, and the call
can be repeated, e.g. with a step limit, or the orbits replaced by :meth:`reset`.

Examples
--------
>>> import chaplygin
>>> states = [{"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, "sqrt(0.87)")},
...           {"M": (0.6, -0.3, 0.4), "gamma": (0.6, 0.0, 0.8)}]
>>> ens = chaplygin.EnsemblePropagator("chaplygin_ball", states, {"I": (1, 2, 3), "D": 1},
...                                    rtol=1e-12, atol=1e-12)
>>> r = ens.propagate_until(10.0)
>>> r.success.tolist(), ens.time == 10.0, bool(r.drift["H"].max() < 1e-10)
([True, True], True, True)
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..derive.errors import UserInputError
from .code import ModelCode
from .ensemble import (
    EnsembleResult,
    LazyResults,
    _collect,
    _read_at_once,
    _rows,
    _thread_count,
    start_arrays,
)
from .ensemble_evidence import ensemble_evidence
from .ensemble_lanes import lanes_library, lanes_result, run_lanes
from .inputs import Precision, working_number
from .integrate import DEFAULT_MAX_WALL_S, prepare_problem
from .propagator import Propagator, _RunView, call_span
from .step_budget import DEFAULT_MAX_STEPS

__all__ = ["EnsemblePropagator"]


class EnsemblePropagator:
    """``N`` orbits of one model, prepared once and advanced together by
    :meth:`propagate_until`.

    Parameters
    ----------
    system : str or ModelCode
        ``"chaplygin_ball"`` (with ``effects``) or loaded code.
    y0 : mapping or sequence, or a list (or 2-D array) of them
        One initial state per orbit, or one for all (as
        :func:`~chaplygin.numerics.ensemble.integrate_many` takes them).
    params : mapping or sequence, or a list (or 2-D array) of them
        One parameter set for all, or one per orbit.
    effects : sequence of str or str, optional
    t0 : float or str, optional
        The initial time of every orbit (default 0), read at the working precision.
    precision : "double", "quad" or int
    rtol, atol : float, optional
        Tolerances (the Taylor method's defaults of ``integrate``).
    taylor_options : mapping, optional
        ``order`` and/or ``step``, ``max_steps``.
    backend : {"auto", "c", "numpy"}
    max_wall_s : float or None
        Wall-time limit of each orbit's call (not checked inside a block of lanes, as in
        ``integrate_many``).
    threads : int, optional
        As for ``integrate_many`` (in the lanes; default: as many as the work needs).

    Attributes
    ----------
    code : ModelCode
    time : float or mpmath.mpf
        Where the orbits are (``t0`` at first).
    count : int
        The number of orbits.

    Raises
    ------
    UserInputError
        What ``integrate_many`` refuses, for the same reasons (the message names the orbit).
    """

    def __init__(
        self,
        system: str | ModelCode,
        y0: Any,
        params: Any,
        *,
        effects: Sequence[str] | str | None = None,
        t0: float | str = 0.0,
        precision: str | int = "double",
        rtol: float | None = None,
        atol: float | None = None,
        taylor_options: Mapping[str, object] | None = None,
        backend: str = "auto",
        max_wall_s: float | None = DEFAULT_MAX_WALL_S,
        threads: int | None = None,
    ) -> None:
        if backend not in ("auto", "c", "numpy"):
            raise UserInputError(f"unknown backend {backend!r}; valid: auto, c, numpy")
        prec = Precision(precision)
        t_start = working_number(t0, prec)
        self._options = {"effects": effects, "precision": precision, "rtol": rtol,
                         "atol": atol, "taylor_options": taylor_options,
                         "max_wall_s": max_wall_s}  # fmt: skip
        self._params, self._backend, self._precision = params, backend, prec
        states, sets = self._rows(y0)
        first = self._prepare(system, states, sets, y0, 0, t_start)
        self.code: ModelCode = first[1].code
        self._first = first
        self._lanes = lanes_library(*first, backend)
        self._max_steps = None if first[1].options.get("max_steps") else DEFAULT_MAX_STEPS
        self.count = 0
        self._read(y0, t_start, first)
        self._workers = _thread_count(threads, prec, self.count)
        self._spread = threads is None
        self._start = (self.time, self._keep())

    # ------------------------------------------------------------------ reading
    def _rows(self, y0: Any) -> tuple:
        """The states and parameter sets as rows (None: one for every orbit), checked to be
        as many."""
        states, sets = _rows(y0, "y0"), _rows(self._params, "params")
        if states is not None and sets is not None and len(states) != len(sets):
            raise UserInputError(
                f"y0 has {len(states)} rows but params has {len(sets)}: give one of them once "
                "or both with the same number of rows"
            )
        return states, sets

    def _prepare(self, system: Any, states: Any, sets: Any, y0: Any, j: int,
                 t_start: Any) -> tuple:  # fmt: skip
        """Orbit ``j``'s integrator and problem, read by ``integrate``'s route."""
        try:
            return prepare_problem(
                system, y0 if states is None else states[j], (t_start, t_start + 1),
                self._params if sets is None else sets[j], method="taylor", **self._options,
            )  # fmt: skip
        except UserInputError as exc:
            raise UserInputError(f"orbit {j}: {exc}") from None

    def _read(self, y0: Any, t_start: Any, first: tuple | None = None) -> None:
        """Read and check the starts (all before anything changes; ``first``: orbit 0's
        problem when already read at ``t_start``)."""
        states, sets = self._rows(y0)
        count = len(states) if states is not None else len(sets) if sets is not None else 1
        if self.count and count != self.count:
            raise UserInputError(f"reset needs {self.count} states, got {count}")
        code = self.code
        if self._lanes is None:  # one Propagator per orbit
            kw = {k: v for k, v in self._options.items() if k != "effects"}
            props = []
            for j in range(count):
                try:
                    props.append(Propagator(
                        code, y0 if states is None else states[j],
                        self._params if sets is None else sets[j], t0=t_start,
                        backend=self._backend, **kw,
                    ))  # fmt: skip
                except UserInputError as exc:
                    raise UserInputError(f"orbit {j}: {exc}") from None
            self._props, self.count, self.time = props, count, t_start
            return
        if first is None:
            first = self._prepare(code, states, sets, y0, 0, t_start)
        read = _read_at_once(code, first, states, sets, self._precision, count, True)
        slow = {0: first[1]}
        if read is None or not read.ok.all():
            slow.update({j: self._prepare(code, states, sets, y0, j, t_start)[1]
                         for j in range(1, count) if read is None or not read.ok[j]})  # fmt: skip
        # read's arrays are its own (made for this call): filled in place
        Y, P = start_arrays(first[1], read, slow, count)
        self._slow, self._read_starts = slow, read
        self._Y, self._P, self.count, self.time = Y, P, count, t_start

    def _keep(self) -> Any:
        """What :meth:`reset` goes back to."""
        if self._lanes is None:
            return [(p.time, list(p._state)) for p in self._props]
        return self._Y.copy()

    def _problem_of(self, j: int) -> Any:
        return self._slow[j] if j in self._slow else self._read_starts.problem(j)

    # ------------------------------------------------------------------ the public calls
    @property
    def states(self) -> np.ndarray:
        """The orbits' states at :attr:`time`, one row each (a copy; ``object`` of
        mpmath.mpf outside double precision)."""
        if self._lanes is not None:
            return self._Y.copy()
        return np.array([p.state for p in self._props])

    def __repr__(self) -> str:
        return (
            f"EnsemblePropagator({self.code.name}, {self.count} orbits, "
            f"t={float(self.time):.6g}, {self._precision!r}, "
            f"{'vector lanes' if self._lanes is not None else 'one orbit after another'})"
        )

    def reset(self, y0: Any = None, t0: float | str | None = None) -> None:
        """Start again: from the constructor's states and time, or from ``y0`` (as many
        states as orbits, read and checked as the constructor reads them; refused input
        changes nothing) and/or ``t0``.

        Parameters
        ----------
        y0 : mapping, sequence, or a list (or 2-D array) of them, optional
        t0 : float or str, optional

        Raises
        ------
        UserInputError
            States or a time the constructor would refuse, or another number of states.
        """
        if y0 is None and t0 is None:
            self.time, kept = self._start
            if self._lanes is None:
                for p, (t, s) in zip(self._props, kept, strict=True):
                    p.time, p._state = t, list(s)
            else:
                self._Y = kept.copy()
            return
        t_start = self._start[0] if t0 is None else working_number(t0, self._precision)
        if y0 is None:  # the constructor's states, read again at the new time
            kept = self._start[1]
            y0 = kept if self._lanes is not None else [list(s) for _, s in kept]
        self._read(y0, t_start)  # assigns only when every state passed

    def propagate_until(self, t: float | str,
                        t_eval: Sequence[float] | None = None) -> EnsembleResult:  # fmt: skip
        """Integrate every orbit from :attr:`time` to ``t`` (forward or backward).

        Parameters
        ----------
        t : float or str
            The end time, read at the working precision.
        t_eval : sequence of float, optional
            Output times inside the span, sorted in its direction (default: its two ends);
            ``t`` is appended when it is not the last.

        Returns
        -------
        EnsembleResult
            Every orbit as a ``Propagator`` of it would give it (drift over the outputs).
            When every orbit reached ``t``, :attr:`time` and :attr:`states` move there;
            otherwise nothing moves.

        Raises
        ------
        UserInputError
            As :meth:`Propagator.propagate_until`.
        """
        start = time.perf_counter()
        t_end, outputs = call_span(self.time, t, t_eval, self._precision, self._max_steps)
        if self._lanes is None:
            return self._one_after_another(t_end, outputs, start)
        integrator, problem = self._first
        view = _RunView(problem, self.time, t_end, outputs)
        run = run_lanes(view, self._lanes[0], self._workers, self._Y, self._P, self._spread)
        now = self.time

        def result(j: int) -> Any:
            orbit = _RunView(self._problem_of(j), now, t_end, outputs)
            return lanes_result(integrator, orbit, run, j, self._lanes[1], 0.0)

        results = LazyResults(self.count, result)
        status, drift = ensemble_evidence(
            self.code, self.code.compiled(), run.t_eval, run.y, run.done, run.status, self._P,
            problem.precision.zero, results.__getitem__,
        )  # fmt: skip
        if not status.any():  # every orbit reached the end (always an output)
            self._Y = np.ascontiguousarray(run.y[:, :, -1])
            self.time = t_end
        return EnsembleResult(results=results, t=run.t_eval, y=run.y, status=status,
                              drift=drift, nsteps=run.nsteps,
                              wall_s=time.perf_counter() - start, threads=run.threads,
                              orbit_wall_s=run.wall)  # fmt: skip

    def _one_after_another(self, t_end: Any, outputs: list, start: float) -> EnsembleResult:
        """Each orbit's own ``Propagator``, one after another; undone when one failed."""
        kept = [(p.time, p._state) for p in self._props]
        results = [p.propagate_until(t_end, outputs) for p in self._props]
        out = _collect(results, self._precision, time.perf_counter() - start, 1)
        if out.status.any():
            for p, (t, s) in zip(self._props, kept, strict=True):
                p.time, p._state = t, s
        else:
            self.time = t_end
        return out

    def propagate_for(self, dt: float | str,
                      t_eval: Sequence[float] | None = None) -> EnsembleResult:  # fmt: skip
        """:meth:`propagate_until` ``time + dt``.

        Parameters
        ----------
        dt : float or str
            The span (negative: backward).
        t_eval : sequence of float, optional

        Returns
        -------
        EnsembleResult

        Raises
        ------
        UserInputError
            As :meth:`propagate_until`.
        """
        return self.propagate_until(self.time + working_number(dt, self._precision), t_eval)
