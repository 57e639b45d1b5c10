"""The Taylor orbits of :func:`~chaplygin.numerics.ensemble.integrate_many` in vector lanes.

In double precision with the Taylor method on the C backend (no events, no dense output), the
orbits run in the compiled lanes driver ``chaplygin_taylor_run_lanes``
(``derive/templates/taylor_lanes.c``): four orbits at a time (eight where the compiler targets
AVX-512) share the vector instructions of the Taylor recurrences, each lane with the operations
of the one-orbit loop in the same order, so that every orbit's outputs, final time, steps and
orders are those of ``integrate()``'s compiled loop, bit for bit, whatever the number of lanes,
threads or orbits per call. The orbits are cut into one contiguous block per thread (the driver
releases the interpreter lock); with the threads chosen from the work (``spread``: the default
of ``integrate_many``) the first group of lanes runs alone first, timed, and
:func:`spread_threads` decides how many blocks the others make. The orbits go in and come
out as arrays (:class:`LanesRun`): no Python object per orbit is made on the way, and each
orbit's
:class:`~chaplygin.numerics.integrators.IntegrationResult` is made only when it is asked for,
by the integrator's own :meth:`~chaplygin.numerics.integrators.base.Integrator._result`, as
``integrate()`` makes it (:func:`lanes_result`); the evidence of all orbits at once is in
:mod:`~chaplygin.numerics.ensemble_evidence`.

The one difference: the wall-time limit ``max_wall_s`` is not checked inside a block (the
step limit is); a block's time is its orbits' ``wall_s`` shared out equally.
"""

from __future__ import annotations

import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

from .integrators import IntegrationResult
from .integrators.c_batch import taylor_batch_library
from .integrators.flows import ModelFlow
from .taylor import MAX_STEPS, REAL_TYPES, run_orders
from .taylor.solution import _MESSAGES, TaylorSolution
from .taylor.stepper import _loop_linspace

__all__ = [
    "SPREAD_MIN_S",
    "LanesRun",
    "lanes_library",
    "lanes_result",
    "run_lanes",
    "spread_threads",
]

def lanes_library(integrator: Any, problem: Any, backend: str) -> tuple[Any, str] | None:
    """The lanes library and the chosen backend when the orbits of ``problem`` can run in the
    lanes (every orbit of an ensemble shares its method, precision, options and system).

    Parameters
    ----------
    integrator : Integrator
    problem : Problem
        The first orbit's, as :func:`~chaplygin.numerics.integrate.prepare_problem` made it.
    backend : str
        The backend asked for.

    Returns
    -------
    (cffi library, str) or None
        None for another method or precision, events, dense output, a reversed flow, a
        backend other than C, or no compiled lanes (no compiler, no printed program).
    """
    if integrator.name != "taylor" or not problem.precision.is_double:
        return None
    if problem.events or problem.dense_output or type(problem.system) is not ModelFlow:
        return None
    chosen = integrator.prepare(problem, backend)
    if chosen != "c":
        return None
    orders = run_orders(problem.rtol, problem.atol, problem.options.get("order"))
    lib = taylor_batch_library(problem.code, orders=orders)
    return None if lib is None else (lib, chosen)


#: Threads kept for the blocks of lanes (starting threads for every call cost 0.5-3 ms, more
#: than a short ensemble's integration): [pool, its threads, the process it belongs to];
#: grown to the most blocks asked for, made anew in a forked child (whose copy has no threads).
_POOL: list = [None, 0, 0]
_POOL_LOCK = threading.Lock()


def _pool(threads: int) -> ThreadPoolExecutor:
    """The kept pool of this process, with at least ``threads`` threads."""
    with _POOL_LOCK:
        pid = os.getpid()
        if _POOL[1] < threads or _POOL[2] != pid:
            old = _POOL[0] if _POOL[2] == pid else None
            pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="chaplygin-lanes")
            _POOL[:] = [pool, threads, pid]
            if old is not None:
                old.shutdown(wait=False)  # its running blocks finish
        return _POOL[0]


def _blocks(count: int, workers: int, lanes: int, first: int = 0) -> list[range]:
    """Orbits ``first`` to ``count`` in at most ``workers`` contiguous blocks, multiples of
    ``lanes``."""
    size = -(-(count - first) // workers)
    size = -(-size // lanes) * lanes
    return [range(a, min(a + size, count)) for a in range(first, count, size)]


@dataclass
class LanesRun:
    """What the lanes driver gives for ``N`` orbits (arrays, one row per orbit).

    Attributes
    ----------
    t_eval : ndarray, shape (m,)
        The output times.
    y : ndarray, shape (N, n_state, m)
        The outputs; NaN after an orbit's last output.
    done : ndarray of int, shape (N,)
        Outputs each orbit reached.
    status : ndarray of int, shape (N,)
        The driver's status (0: reached the end; else a key of the Taylor loop's messages).
    nsteps, order_min, order_max : ndarray of int, shape (N,)
    wall : ndarray, shape (N,)
        Each orbit's share of its block's wall time.
    threads : int
        Threads the blocks ran on (after the first group of lanes, where it was timed alone).
    """

    t_eval: np.ndarray
    y: np.ndarray
    done: np.ndarray
    status: np.ndarray
    nsteps: np.ndarray
    order_min: np.ndarray
    order_max: np.ndarray
    wall: np.ndarray
    threads: int = 1


def run_lanes(first: Any, lib: Any, workers: int, y0: np.ndarray,
              params: np.ndarray, spread: bool = False) -> LanesRun:  # fmt: skip
    """Integrate the orbits ``y0`` (rows) with ``params`` (rows) in the lanes driver.

    Parameters
    ----------
    first : Problem
        The first orbit's problem: span, tolerances, options and output times of all.
    lib : cffi library
        :func:`lanes_library`'s.
    workers : int
        Threads (one block of orbits each); with ``spread``, the most threads.
    y0 : ndarray, shape (N, n_state)
    params : ndarray, shape (N, n_param)
    spread : bool
        Choose the threads from the work (the default of ``integrate_many``): the first group
        of lanes runs on this thread, and the other orbits are cut into blocks for
        :func:`spread_threads` of them, estimated from that group's time (one thread, this
        one, for a short ensemble). The orbits' numbers do not depend on it.

    Returns
    -------
    LanesRun
    """
    from .integrators.c_batch import _buf

    count, n = y0.shape
    options = first.options
    max_steps = first.max_steps or options.get("max_steps") or MAX_STEPS
    t0, t1 = first.t_span
    t_eval = first.t_eval
    if t_eval is None:
        t_eval = _loop_linspace(first.precision, t0, t1, 11)
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    m = len(t_eval)
    t01 = np.empty((count, 2))
    t01[:, 0], t01[:, 1] = float(t0), float(t1)
    y0 = np.ascontiguousarray(y0, dtype=float)
    params = np.ascontiguousarray(params, dtype=float).reshape(count, -1)
    ctrl = np.array([first.rtol, first.atol, options.get("step") or 0.0], dtype=float)
    y_eval, y_end = np.full((count, max(m, 1), n), np.nan), np.empty((count, n))
    t_reached = np.empty(count)
    stats, status = np.zeros((count, 4), dtype=np.int64), np.zeros(count, dtype=np.int32)
    # one pointer per array; a block's rows are an offset from it (the arrays are C-ordered)
    arrays = (t01, y0, params, y_eval, y_end, t_reached, stats, status)
    kinds = ("double[]",) * 6 + ("long[]", "int[]")
    bufs = [_buf(a, k) for a, k in zip(arrays, kinds, strict=True)]
    row = [a.size // count for a in arrays]
    fixed = (_buf(ctrl), options.get("order") or 0, m, _buf(t_eval), 0)
    run = lib.chaplygin_taylor_run_lanes

    def block(rows: range) -> float:
        a = rows.start
        p = [b + a * k for b, k in zip(bufs, row, strict=True)]
        start = time.perf_counter()
        run(rows.stop - a, p[0], p[1], p[2], *fixed, p[3], p[4], p[5], max_steps, p[6], p[7])
        return (time.perf_counter() - start) / (rows.stop - a)

    width = lib.chaplygin_taylor_lanes_width()
    walls: list[float] = []
    first_rows = range(0)
    if spread and workers > 1 and count > width:  # the first group tells the work per orbit
        first_rows = range(0, width)
        walls.append(block(first_rows))
        workers = spread_threads(walls[0], count - width, workers)
    rest = _blocks(count, workers, width, first_rows.stop)
    if len(rest) == 1:
        walls.append(block(rest[0]))
    else:  # the last block in this thread, the others on the kept pool's threads
        others = [_pool(len(rest) - 1).submit(block, rows) for rows in rest[:-1]]
        last = block(rest[-1])
        walls += [f.result() for f in others] + [last]
    blocks = ([first_rows] if len(first_rows) else []) + rest
    wall = np.repeat(walls, [len(r) for r in blocks])
    steps = stats[:, 0]
    return LanesRun(
        t_eval=t_eval,
        y=y_eval[:, :m].transpose(0, 2, 1),
        done=stats[:, 3].copy(),
        status=status.astype(np.int64),
        nsteps=steps.copy(),
        order_min=np.where(steps > 0, stats[:, 2], 0),
        order_max=stats[:, 1].copy(),
        wall=wall,
        threads=len(rest),
    )


#: The least estimated work, in seconds, for each thread of :func:`spread_threads` beyond the
#: first: below it, handing blocks to other threads costs about as much as it saves. Measured
#: on 2 cores (AMD EPYC, 20-step separatrix runs, tol 1e-9): 16 orbits took 0.67 ms on one
#: thread and 1.09 ms on two, 64 orbits 1.33 and 1.6 ms, 256 orbits 4.1 and 3.2 ms.
SPREAD_MIN_S = 1e-3


def spread_threads(per_orbit_s: float, left: int, workers: int) -> int:
    """Threads for ``left`` orbits of about ``per_orbit_s`` seconds each, at most ``workers``.

    Parameters
    ----------
    per_orbit_s : float
        Estimated seconds per orbit on one thread (the first group of lanes' time).
    left : int
        Orbits still to run.
    workers : int
        The most threads.

    Returns
    -------
    int
        ``k`` threads, the most with at least :data:`SPREAD_MIN_S` of work for each (at least
        1; 1 where the estimate is not a finite number).
    """
    estimate = per_orbit_s * left
    if not np.isfinite(estimate) or estimate < 2 * SPREAD_MIN_S:
        return 1
    most = min(workers, left)
    return most if SPREAD_MIN_S <= 0 else int(max(1, min(most, estimate // SPREAD_MIN_S)))


def lanes_result(integrator: Any, problem: Any, run: LanesRun, j: int, chosen: str,
                 setup_s: float) -> IntegrationResult:  # fmt: skip
    """Orbit ``j``'s result, made as ``integrate()`` makes it from the compiled loop's.

    Parameters
    ----------
    integrator : Integrator
    problem : Problem
        Orbit ``j``'s problem.
    run : LanesRun
    j : int
    chosen : str
        The backend the integrator chose (``"c"``).
    setup_s : float
        The orbit's share of the call's set-up time.

    Returns
    -------
    IntegrationResult
    """
    done, code = int(run.done[j]), int(run.status[j])
    sol = TaylorSolution(
        t=REAL_TYPES["double"].times(run.t_eval[:done]),
        y=np.ascontiguousarray(run.y[j, :, :done]),
        status=code,
        message=_MESSAGES.get(code, "failed"),
        nsteps=int(run.nsteps[j]),
        order_min=int(run.order_min[j]),
        order_max=int(run.order_max[j]),
        backend="c-double",
    )
    solution = integrator._solution(problem, sol)
    return integrator._result(problem, solution, chosen, float(run.wall[j]), setup_s)
