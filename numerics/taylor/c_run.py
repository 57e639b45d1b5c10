"""The compiled loop in double, quad, double-double and quad-double: one call per
integration (:class:`CompiledTaylorRun`), kept per thread for the next call with the same
problem (:func:`_c_run`)."""

from __future__ import annotations

import threading
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..precision import ARITHMETICS
from .library import CompiledTaylor, _ffi
from .solution import _MESSAGES, TaylorSolution

__all__ = ["CompiledTaylorRun"]

#: Output buffers of at most this many points are kept by a compiled run between calls.
_KEPT_OUTPUTS_MAX = 4096


class CompiledTaylorRun:
    """The compiled loop of one problem (library, parameters, tolerances, order, step and
    limits) with its arguments converted to C pointers once: :meth:`run` packs a start, runs
    the loop, in blocks of ``ARITHMETICS[kind].chunk_steps`` when a wall-time limit is set
    (each block resumes from the exact time, state and compensation the previous one
    reached, so the steps and results are those of one uninterrupted call), and returns the
    solution.
    ``integrate`` makes one per call (:func:`_c_run`); a
    :class:`~chaplygin.numerics.propagator.Propagator` keeps one."""

    def __init__(self, clib, p, rtol, atol, order, step, max_steps, max_wall_s=None):
        ptr = CompiledTaylor._ptr
        n = clib.n_state
        self.clib, self.n, self.max_steps, self.max_wall_s = clib, n, max_steps, max_wall_s
        self.order = order
        self.chunk = max_steps if max_wall_s is None else ARITHMETICS[clib.kind].chunk_steps
        self.size = clib.real.size  # bytes per real: pointers below are char pointers
        # parameters and step control in the library's format
        self.P, self.ctrl = clib.pack(p), clib.pack([rtol, atol, step or 0])
        self.t01, self.y, self.y_end, self.t_reached = (
            clib.empty(2), clib.empty(n), clib.empty(n), clib.empty(1)
        )
        # the compensation of the state (double and quad: the rounding error the loop
        # carries), zero at the start, handed from one block of steps to the next in place
        self.y_lo = clib.empty(n)
        self.stats = np.zeros(4, dtype=np.int64)
        self.args = [ptr(self.t01), ptr(self.y), ptr(self.P), ptr(self.ctrl), order or 0, 0,
                     None, None, ptr(self.y_end), ptr(self.t_reached), 0,
                     _ffi.cast("long *", self.stats.ctypes.data), ptr(self.y_lo)]
        self._outputs: dict[int, tuple] = {}  # number of outputs -> buffers and pointers

    def _output_buffers(self, m: int) -> tuple:
        bufs = self._outputs.get(m)
        if bufs is None:
            t_buf, y_buf = self.clib.empty(max(m, 1)), self.clib.empty(max(m, 1) * self.n)
            bufs = (t_buf, y_buf, CompiledTaylor._ptr(t_buf), CompiledTaylor._ptr(y_buf))
            # kept for the next call when small (a kept run must not hold a long output)
            if len(self._outputs) < 8 and m <= _KEPT_OUTPUTS_MAX:
                self._outputs[m] = bufs
        return bufs

    def run(
        self, y0: Sequence[Any], t_span: Sequence[Any], t_eval: Sequence[Any]
    ) -> TaylorSolution:
        """Integrate from ``y0`` over ``t_span`` with output at ``t_eval``.

        Parameters
        ----------
        y0 : sequence of numbers
            The initial state (working numbers of the library's kind).
        t_span : (t0, t1)
            The span (``t1 < t0``: backward).
        t_eval : sequence of numbers
            Output times, sorted in the direction of integration, inside the span.

        Returns
        -------
        TaylorSolution
            Outputs reached, status and message, steps and orders, backend ``c-<kind>``.
        """
        clib, n, m, size = self.clib, self.n, len(t_eval), self.size
        t_buf, y_buf, t_ptr, y_ptr = self._output_buffers(m)
        # float64 buffers take the numbers as they are (numpy converts); others are packed
        pack = _same if clib.kind == "double" else clib.pack
        if m:
            t_buf[:] = pack(t_eval)  # m reals: the buffer of m outputs
        self.t01[:] = pack(t_span)
        self.y[:] = pack(y0)
        self.y_lo[:] = 0
        args, stats = self.args, self.stats
        deadline = None if self.max_wall_s is None else time.perf_counter() + self.max_wall_s
        steps, pmax, pmin, done = 0, 0, 10**9, 0
        while True:
            args[5] = m - done
            args[6] = t_ptr + size * done if done < m else t_ptr
            args[7] = y_ptr + size * done * n if done < m else y_ptr
            args[10] = min(self.chunk, self.max_steps - steps)
            status = clib.lib.chaplygin_taylor_run(*args)
            steps += int(stats[0])
            if stats[0]:
                pmax, pmin = max(pmax, int(stats[1])), min(pmin, int(stats[2]))
            done += int(stats[3])
            if status != -2 or steps >= self.max_steps:
                break
            if deadline is not None and time.perf_counter() > deadline:
                status = -6
                break
            # resume exactly where the call stopped: its time, state and compensation, as
            # they are in C (y_lo is updated in place)
            self.t01[: len(self.t_reached)] = self.t_reached
            self.y[:] = self.y_end
        real = clib.real
        if clib.kind == "double":  # the float64 buffer as it is: one copy, transposed
            y_out = y_buf[: done * n].reshape(done, n).T.copy()
        else:
            rows = real.rows(real.unpack(y_buf, done * n), done, n)
            y_out = np.array(rows, dtype=real.dtype).reshape(done, n).T.copy()
        return TaylorSolution(
            t=real.times(t_eval[:done]),
            y=y_out,
            status=int(status),
            message=_MESSAGES.get(int(status), "failed"),
            nsteps=steps,
            order_min=pmin if steps else 0,
            order_max=pmax,
            backend=f"c-{clib.kind}",
        )


def _same(values):
    return values


#: The compiled runs of recent problems, per thread (a run's buffers are its own while it
#: runs): ``integrate`` called again with the same model, parameters and control reuses the
#: pointers and buffers instead of converting them again (the outputs are copied out).
_RUNS = threading.local()
_RUNS_MAX = 16


def _c_run(clib, y0, t_span, p, rtol, atol, t_eval, order, step, max_steps, max_wall_s=None):
    try:
        key = (clib, tuple(p), rtol, atol, order, step, max_steps, max_wall_s,
               ARITHMETICS[clib.kind].chunk_steps)
        hash(key)
    except TypeError:  # pragma: no cover - working numbers are hashable
        key = None
    runs = getattr(_RUNS, "runs", None)
    if runs is None:
        runs = _RUNS.runs = {}
    run = runs.get(key) if key is not None else None
    if run is None:
        run = CompiledTaylorRun(clib, p, rtol, atol, order, step, max_steps, max_wall_s)
        if key is not None:
            if len(runs) >= _RUNS_MAX:
                del runs[next(iter(runs))]
            runs[key] = run
    return run.run(y0, t_span, t_eval)
