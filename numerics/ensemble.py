"""Many orbits in one call: :func:`integrate_many` and its :class:`EnsembleResult`.

``integrate_many`` integrates ``N`` orbits of one model over one span: ``N`` initial states
with one parameter set, one initial state with ``N`` parameter sets, or ``N`` of each. Every
orbit is read and checked as :func:`~chaplygin.numerics.integrate.integrate` reads and checks
its inputs (all of them before any work: a bad orbit raises :class:`UserInputError` naming
its index, and nothing runs), then integrated by the same integrator through the one door,
so that orbit ``j``'s result is the :class:`IntegrationResult` that ``integrate`` gives for
it, bit for bit, with its own status, message, work counters and the drift of every first
integral as its evidence.

In double precision with the Taylor method (compiled, without events or dense output) the
orbits run in vector lanes (:mod:`~chaplygin.numerics.ensemble_lanes`): four or eight orbits
at a time share the instructions of the Taylor recurrences, each lane bit-identical to the
one-orbit loop, and the orbits are cut into one block per thread (``threads``; by default the
usable CPUs, as many as the work needs: the first group of lanes is timed, and a short ensemble
stays on the calling thread; the compiled driver releases the interpreter lock); the wall-time
limit is not checked inside a block. With another method in double the orbits are spread over
the threads one call each (the compiled loops -- the variational and batch drivers, DOP853 --
release the lock too). The orbits are independent and each is placed by its index, so the
numbers do not depend on the number of threads or lanes or on the order in which the threads
finish. In quad and in decimal digits the orbits run one after another (mpmath's working
precision is one setting of the process).

Examples
--------
>>> import chaplygin
>>> states = [{"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, "sqrt(0.87)")},
...           {"M": (0.6, -0.3, 0.4), "gamma": (0.6, 0.0, 0.8)}]
>>> r = chaplygin.integrate_many("chaplygin_ball", states, 10.0, {"I": (1, 2, 3), "D": 1},
...                              rtol=1e-12, atol=1e-12)
>>> r.success.tolist(), r.y.shape, bool(r.drift["H"].max() < 1e-10)
([True, True], (2, 6, 11), True)
"""

from __future__ import annotations

import dataclasses
import os
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..derive.errors import UserInputError
from .code import ModelCode
from .ensemble_evidence import ensemble_evidence
from .ensemble_inputs import ReadStarts, numeric_rows, read_starts
from .ensemble_lanes import lanes_library, lanes_result, run_lanes
from .integrate import DEFAULT_MAX_WALL_S, _call_key, prepare_problem
from .integrators import IntegrationResult
from .precision import Precision

__all__ = ["EnsembleResult", "LazyResults", "integrate_many", "start_arrays"]


@dataclass
class EnsembleResult:
    """The orbits of :func:`integrate_many`, each with its evidence.

    Attributes
    ----------
    results : sequence of IntegrationResult
        Orbit ``j``'s result, as ``integrate`` gives it (in the vector lanes made when it is
        first asked for: the arrays below are computed for all orbits at once).
    t : ndarray, shape (n_points,)
        The output times (the same for every orbit).
    y : ndarray, shape (N, n_state, n_points)
        The outputs (``float64`` in double precision, ``object`` of mpmath.mpf otherwise); an
        orbit that stopped early has NaN (double) or None after its last output.
    status : ndarray of int, shape (N,)
        0: reached the end; else the orbit's failure (its ``message``).
    drift : dict of str to ndarray, shape (N,)
        Every first integral's drift, per orbit (as ``IntegrationResult.drift``).
    nsteps : ndarray of int, shape (N,)
    wall_s : float
        Wall time of the whole call (reading the inputs included).
    threads : int
        Threads that integrated.
    orbit_wall_s : ndarray, shape (N,)
        Each orbit's integration time (in the lanes, its share of its block's).
    """

    results: Sequence[IntegrationResult]
    t: np.ndarray
    y: np.ndarray
    status: np.ndarray
    drift: dict[str, np.ndarray]
    nsteps: np.ndarray
    wall_s: float
    threads: int
    orbit_wall_s: np.ndarray

    @property
    def success(self) -> np.ndarray:
        """Which orbits reached the end.

        Returns
        -------
        ndarray of bool, shape (N,)
        """
        return self.status == 0

    @property
    def messages(self) -> list[str]:
        """Each orbit's message.

        Returns
        -------
        list of str
        """
        return [r.message for r in self.results]

    def __len__(self) -> int:
        return len(self.results)

    def __repr__(self) -> str:
        done = int(self.success.sum())
        worst = {k: float(np.nanmax(v)) if len(v) else float("nan") for k, v in self.drift.items()}
        return (
            f"EnsembleResult({len(self)} orbits, {done} reached the end, {len(self.t)} outputs, "
            f"largest drift {worst}, {self.wall_s:.3g} s on {self.threads} thread(s))"
        )


class LazyResults(Sequence):
    """Orbit ``j``'s :class:`IntegrationResult`, made by ``make(j)`` when first asked for.

    Parameters
    ----------
    count : int
    make : callable
        ``j -> IntegrationResult``.
    """

    def __init__(self, count: int, make: Callable[[int], IntegrationResult]):
        self._made: list[IntegrationResult | None] = [None] * count
        self._make = make

    def __len__(self) -> int:
        return len(self._made)

    def __getitem__(self, j: Any) -> Any:
        if isinstance(j, slice):
            return [self[i] for i in range(*j.indices(len(self)))]
        j = range(len(self))[j]  # an IndexError for an index out of range, as a list's
        made = self._made[j]
        if made is None:
            made = self._made[j] = self._make(j)
        return made

    def __repr__(self) -> str:
        return f"<{len(self)} IntegrationResults>"

    def __reduce__(self) -> tuple:  # pickled (e.g. from a Dask task) as the plain list
        return (list, (list(self),))


def _is_one_vector(value: Any) -> bool:
    """A mapping, or a flat sequence of numbers or number texts: one state or parameter set."""
    if isinstance(value, Mapping):
        return True
    if isinstance(value, np.ndarray):
        return value.ndim == 1
    if isinstance(value, str) or not isinstance(value, Sequence):
        return False
    return all(not isinstance(v, Mapping | Sequence | np.ndarray) or isinstance(v, str)
               for v in value)  # fmt: skip


def _rows(value: Any, what: str) -> list[Any] | np.ndarray | None:
    """``value`` as a list of rows (a 2-D array as it is), or None when it is one vector
    (shared by every orbit)."""
    if _is_one_vector(value):
        return None
    if isinstance(value, np.ndarray):
        if value.ndim != 2 or len(value) == 0:
            raise UserInputError(f"{what} must be one vector or N rows, got shape {value.shape}")
        return value
    if isinstance(value, str) or not isinstance(value, Sequence) or len(value) == 0:
        raise UserInputError(f"{what} must be one vector (or mapping) or a non-empty list of them")
    return list(value)


def _thread_count(threads: int | None, precision: Precision, orbits: int) -> int:
    if threads is not None and (
        isinstance(threads, bool) or not isinstance(threads, int) or threads < 1
    ):
        raise UserInputError(f"threads must be a positive integer, got {threads!r}")
    if not precision.is_double:
        return 1
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return max(1, min(threads or usable or 1, orbits))


def integrate_many(
    system: str | ModelCode,
    y0: Any,
    t_span: tuple[float, float] | float,
    params: Any,
    *,
    effects: Sequence[str] | str | None = None,
    method: str | None = None,
    precision: str | int = "double",
    rtol: float | None = None,
    atol: float | None = None,
    backend: str = "auto",
    t_eval: Sequence[float] | None = None,
    taylor_options: Mapping[str, object] | None = None,
    max_steps: int | None = None,
    max_wall_s: float | None = DEFAULT_MAX_WALL_S,
    threads: int | None = None,
) -> EnsembleResult:
    """Integrate many orbits of one model over one span; every orbit with its evidence.

    Parameters
    ----------
    system : str or ModelCode
        As for :func:`~chaplygin.numerics.integrate.integrate`.
    y0 : mapping or sequence, or a list (or 2-D array) of them
        One initial state for every orbit, or one per orbit (each as ``integrate`` takes it).
    t_span : (t0, t1) or float
        The span of every orbit.
    params : mapping or sequence, or a list (or 2-D array) of them
        One parameter set, or one per orbit. ``y0`` and ``params`` given per orbit must have
        the same number of rows.
    effects, method, precision, rtol, atol, backend, t_eval, taylor_options, max_steps, \
max_wall_s
        As for ``integrate`` (``t_eval`` default: 11 points, as ``integrate``'s Taylor
        method; give it for a method whose default output is every step, so that the orbits
        share their output times).
    threads : int, optional
        Threads in double precision, at most one per orbit. Default: the usable CPUs; in
        vector lanes, as many of them as the work needs (the first group of lanes is timed
        alone, and the other orbits are spread over threads only where each gets at least
        :data:`~chaplygin.numerics.ensemble_lanes.SPREAD_MIN_S` of work: a short ensemble runs
        on this thread). Ignored in quad and digits (one after another). The numbers never
        depend on it.

    Returns
    -------
    EnsembleResult

    Raises
    ------
    UserInputError
        What ``integrate`` refuses, for any orbit (the message names the orbit's index);
        ``y0`` and ``params`` with different numbers of rows; a bad ``threads``.
    """
    start = time.perf_counter()
    states, sets = _rows(y0, "y0"), _rows(params, "params")
    if states is not None and sets is not None and len(states) != len(sets):
        raise UserInputError(
            f"y0 has {len(states)} rows but params has {len(sets)}: give one of them once or "
            "both with the same number of rows"
        )
    count = len(states) if states is not None else len(sets) if sets is not None else 1
    prec = Precision(precision)
    workers = _thread_count(threads, prec, count)
    def prepare(j: int, system: Any, t_eval: Any) -> tuple:
        try:
            return prepare_problem(
                system, y0 if states is None else states[j], t_span,
                params if sets is None else sets[j], effects=effects, method=method,
                precision=precision, rtol=rtol, atol=atol, t_eval=t_eval,
                taylor_options=taylor_options, max_steps=max_steps, max_wall_s=max_wall_s,
            )  # fmt: skip
        except UserInputError as exc:
            raise UserInputError(f"orbit {j}: {exc}") from None

    key = _call_key((system, y0, t_span, params, effects, method, precision, rtol, atol,
                     t_eval, None, taylor_options, max_steps, max_wall_s))  # fmt: skip
    kept = _READ.get((key, backend)) if key is not None else None
    if kept is not None:  # the same call again: its starts read and checked already
        first, lanes, read, t_eval = kept
        return _in_lanes(first, _copy(read), lambda j: prepare(j, first[1].code, t_eval),
                         count, lanes, workers, start, threads is None)  # fmt: skip
    first = prepare(0, system, t_eval)
    code = first[1].code
    if t_eval is None and first[0].name != "taylor":  # shared output times: 11, as Taylor's
        a, b = first[1].t_span
        t_eval = [a + (b - a) * k / 10 for k in range(10)] + [b]
        first = prepare(0, code, t_eval)
    lanes = lanes_library(*first, backend)
    read = _read_at_once(code, first, states, sets, prec, count, lanes is not None)
    if lanes is not None:  # the Taylor method in double: the orbits in vector lanes
        if key is not None:
            if len(_READ) >= _READ_MAX:
                del _READ[next(iter(_READ))]
            _READ[(key, backend)] = (first, lanes, _copy(read), t_eval)
        return _in_lanes(first, _copy(read), lambda j: prepare(j, code, t_eval), count, lanes,
                         workers, start, threads is None)  # fmt: skip
    prepared = [first] + [
        (first[0], read.problem(j)) if read is not None and read.ok[j]
        else prepare(j, code, t_eval)
        for j in range(1, count)
    ]  # fmt: skip
    setup_s = time.perf_counter() - start

    def run(j: int) -> IntegrationResult:
        integrator, problem = prepared[j]
        return integrator.run(problem, backend, setup_s=setup_s / count)

    results = [run(0)]  # the first in this thread: compiled libraries loaded once
    if count > 1:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            results += list(pool.map(run, range(1, count)))
    return _collect(results, prec, time.perf_counter() - start, workers)


#: The starts of ensembles in vector lanes already read and checked, by the inputs as typed
#: (:func:`~chaplygin.numerics.integrate._call_key`, mpmath's precision included) and the
#: backend: the same call again skips reading them (``read_starts``: a fixed cost of about
#: 0.2 ms for 64 orbits); each call gets its own copy of the arrays.
_READ: dict[tuple, tuple] = {}
_READ_MAX = 16


def _copy(read: ReadStarts | None) -> ReadStarts | None:
    if read is None:
        return None
    return dataclasses.replace(read, Y=read.Y.copy(), ok=read.ok.copy(),
                               P=None if read.P is None else read.P.copy())  # fmt: skip


def _read_at_once(code: ModelCode, first: tuple, states: Any, sets: Any, prec: Precision,
                  count: int, compiled: bool) -> ReadStarts | None:  # fmt: skip
    """The starts read at once (double, numbers only:
    :mod:`~chaplygin.numerics.ensemble_inputs`; ``compiled``: checked with the compiled
    model); None where ``integrate``'s route reads all."""
    if not prec.is_double or count < 2:
        return None
    Y = numeric_rows(states, len(code.state)) if states is not None else None
    P = numeric_rows(sets, len(code.params)) if sets is not None else None
    if (states is not None and Y is None) or (sets is not None and P is None):
        return None
    problem = first[1]
    if Y is None:
        Y = np.tile(np.asarray(problem.y0, dtype=np.float64), (count, 1))
    return read_starts(code, problem, Y, P, code.compiled() if compiled else None)


def start_arrays(problem: Any, read: ReadStarts | None, slow: dict[int, Any],
                 count: int) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The starts and parameters of ``count`` orbits as rows (double): those ``read`` at
    once, and the ``slow`` ones (index -> problem, read by ``integrate``'s route) filled in;
    ``read``'s own arrays are filled (the callers pass a copy).

    Parameters
    ----------
    problem : Problem
        The first orbit's (its parameters for every orbit when ``read`` has none).
    read : ReadStarts or None
    slow : dict of int to Problem
    count : int

    Returns
    -------
    (ndarray, ndarray)
        ``Y`` of shape ``(count, n_state)`` and ``P`` of shape ``(count, n_param)``.
    """
    n = len(problem.code.state)
    Y = np.empty((count, n)) if read is None else read.Y
    if read is None or read.P is None:
        P = np.tile(np.asarray(problem.params, dtype=float), (count, 1))
    else:
        P = read.P
    for j, other in slow.items():
        Y[j] = [float(v) for v in other.y0]
        P[j] = [float(v) for v in other.params]
    return Y, P


def _in_lanes(first: tuple, read: ReadStarts | None, prepare: Callable[[int], tuple],
              count: int, lanes: tuple, workers: int, start: float,
              spread: bool) -> EnsembleResult:  # fmt: skip
    """The ensemble in vector lanes: the starts as arrays (those not read at once through
    ``prepare``, ``integrate``'s route), the results made when asked for."""
    integrator, problem = first
    slow = {0: problem}
    if read is None or not read.ok.all():
        slow.update({j: prepare(j)[1] for j in range(1, count) if read is None or not read.ok[j]})
    # read's arrays are its own: the rows of the starts it did not accept are filled here
    Y, P = start_arrays(problem, read, slow, count)
    setup_s = (time.perf_counter() - start) / count
    run = run_lanes(problem, lanes[0], workers, Y, P, spread)

    def problem_of(j: int) -> Any:
        return slow[j] if j in slow else read.problem(j)

    def result(j: int) -> IntegrationResult:
        return lanes_result(integrator, problem_of(j), run, j, lanes[1], setup_s)

    results = LazyResults(count, result)
    status, drift = ensemble_evidence(
        problem.code, problem.code.compiled(), run.t_eval, run.y, run.done, run.status,
        P, problem.precision.zero, results.__getitem__,
    )  # fmt: skip
    return EnsembleResult(results=results, t=run.t_eval, y=run.y, status=status, drift=drift,
                          nsteps=run.nsteps, wall_s=time.perf_counter() - start,
                          threads=run.threads, orbit_wall_s=run.wall)  # fmt: skip


def _collect(results: list[IntegrationResult], prec: Precision, wall: float,
             threads: int) -> EnsembleResult:  # fmt: skip
    """The ensemble's arrays from its orbits' results."""
    longest = max(results, key=lambda r: len(r.t))
    n_points, n_state = len(longest.t), len(longest.state_names)
    dtype = np.float64 if prec.is_double else object
    y = np.full((len(results), n_state, n_points), np.nan if prec.is_double else None, dtype=dtype)
    for j, r in enumerate(results):
        y[j, :, : r.y.shape[-1]] = r.y
    drift = {name: np.array([r.drift.get(name, np.nan) for r in results], dtype=float)
             for name in longest.drift}  # fmt: skip
    return EnsembleResult(
        results=results,
        t=np.asarray(longest.t),
        y=y,
        status=np.array([r.status for r in results], dtype=np.int64),
        drift=drift,
        nsteps=np.array([r.nsteps for r in results], dtype=np.int64),
        wall_s=wall,
        threads=threads,
        orbit_wall_s=np.array([r.wall_s for r in results]),
    )
