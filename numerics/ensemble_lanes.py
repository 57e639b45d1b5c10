"""The Taylor orbits of :func:`~chaplygin.numerics.ensemble.integrate_many` in vector lanes.

In double precision with the Taylor method on the C backend (no events, no dense output), the
orbits run in the compiled lanes driver ``chaplygin_taylor_run_lanes``
(``derive/templates/taylor_lanes.c``): four orbits at a time (eight where the compiler targets
AVX-512) share the vector instructions of the Taylor recurrences, each lane with the operations
of the one-orbit loop in the same order, so that every orbit's outputs, final time, steps and
orders are those of ``integrate()``'s compiled loop, bit for bit, whatever the number of lanes,
threads or orbits per call. The orbits are cut into one contiguous block per thread (the driver
releases the interpreter lock), and every orbit's
:class:`~chaplygin.numerics.integrators.IntegrationResult` is then made by the integrator's own
:meth:`~chaplygin.numerics.integrators.base.Integrator._result` (the finiteness check and the
drift of every first integral), as ``integrate()`` makes it.

The one difference: the wall-time limit ``max_wall_s`` is not checked inside a block (the
step limit is); a block's time is its orbits' ``wall_s`` shared out equally.
"""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

from .integrators import IntegrationResult
from .integrators.c_batch import taylor_batch_library
from .integrators.flows import ModelFlow
from .taylor import MAX_STEPS, REAL_TYPES, run_orders
from .taylor.solution import _MESSAGES, TaylorSolution
from .taylor.stepper import _loop_linspace

__all__ = ["lanes_library", "run_in_lanes"]

def lanes_library(prepared: list[tuple], backend: str) -> tuple[Any, str] | None:
    """The lanes library and the chosen backend when every orbit can run in the lanes.

    Parameters
    ----------
    prepared : list of (Integrator, Problem)
        The orbits, as :func:`~chaplygin.numerics.integrate.prepare_problem` made them.
    backend : str
        The backend asked for.

    Returns
    -------
    (cffi library, str) or None
        None for another method or precision, events, dense output, a reversed flow, a
        backend other than C, or no compiled lanes (no compiler, no printed program).
    """
    integrator, problem = prepared[0]
    if integrator.name != "taylor" or not problem.precision.is_double:
        return None
    if any(p.events or p.dense_output or type(p.system) is not ModelFlow for _, p in prepared):
        return None
    chosen = integrator.prepare(problem, backend)
    if chosen != "c":
        return None
    orders = run_orders(problem.rtol, problem.atol, problem.options.get("order"))
    lib = taylor_batch_library(problem.code, orders=orders)
    return None if lib is None else (lib, chosen)


def _blocks(count: int, workers: int, lanes: int) -> list[range]:
    """``count`` orbits in at most ``workers`` contiguous blocks, multiples of ``lanes``."""
    size = -(-count // workers)
    size = -(-size // lanes) * lanes
    return [range(a, min(a + size, count)) for a in range(0, count, size)]


def run_in_lanes(prepared: list[tuple], lib: Any, chosen: str, workers: int,
                 setup_s: float) -> list[IntegrationResult]:  # fmt: skip
    """Every orbit's result, from the lanes driver.

    Parameters
    ----------
    prepared : list of (Integrator, Problem)
        Orbits sharing method, span, tolerances, options and output times.
    lib : cffi library
        :func:`lanes_library`'s.
    chosen : str
        The backend the integrator chose (``"c"``).
    workers : int
        Threads (one block of orbits each).
    setup_s : float
        Set-up time of the whole call, shared out.

    Returns
    -------
    list of IntegrationResult
    """
    from .integrators.c_batch import _buf

    integrator, first = prepared[0]
    count, n = len(prepared), len(first.code.state)
    options = first.options
    max_steps = first.max_steps or options.get("max_steps") or MAX_STEPS
    t0, t1 = first.t_span
    t_eval = first.t_eval
    if t_eval is None:
        t_eval = _loop_linspace(first.precision, t0, t1, 11)
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    m = len(t_eval)
    t01 = np.array([[float(v) for v in p.t_span] for _, p in prepared])
    y0 = np.array([[float(v) for v in p.y0] for _, p in prepared])
    params = np.array([[float(v) for v in p.params] for _, p in prepared]).reshape(count, -1)
    ctrl = np.array([first.rtol, first.atol, options.get("step") or 0.0], dtype=float)
    y_eval, y_end = np.full((count, max(m, 1), n), np.nan), np.empty((count, n))
    t_reached = np.empty(count)
    stats, status = np.zeros((count, 4), dtype=np.int64), np.zeros(count, dtype=np.int32)

    def block(rows: range) -> float:
        a, b = rows.start, rows.stop
        start = time.perf_counter()
        lib.chaplygin_taylor_run_lanes(
            b - a, _buf(t01[a:b]), _buf(y0[a:b]), _buf(params[a:b]), _buf(ctrl),
            options.get("order") or 0, m, _buf(t_eval), 0, _buf(y_eval[a:b]),
            _buf(y_end[a:b]), _buf(t_reached[a:b]), max_steps, _buf(stats[a:b], "long[]"),
            _buf(status[a:b], "int[]"),
        )  # fmt: skip
        return (time.perf_counter() - start) / (b - a)

    blocks = _blocks(count, workers, lib.chaplygin_taylor_lanes_width())
    with ThreadPoolExecutor(max_workers=max(1, len(blocks))) as pool:
        walls = list(pool.map(block, blocks))
    wall = np.concatenate([np.full(len(r), w) for r, w in zip(blocks, walls, strict=True)])
    results = []
    for j, (_, problem) in enumerate(prepared):
        steps, done = int(stats[j, 0]), int(stats[j, 3])
        sol = TaylorSolution(
            t=REAL_TYPES["double"].times(t_eval[:done]),
            y=y_eval[j, :done].T.copy(),
            status=int(status[j]),
            message=_MESSAGES.get(int(status[j]), "failed"),
            nsteps=steps,
            order_min=int(stats[j, 2]) if steps else 0,
            order_max=int(stats[j, 1]),
            backend="c-double",
        )
        solution = integrator._solution(problem, sol)
        results.append(integrator._result(problem, solution, chosen, float(wall[j]),
                                          setup_s / count))  # fmt: skip
    return results
