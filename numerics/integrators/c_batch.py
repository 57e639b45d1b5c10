"""The compiled batch drivers: many points of a time-periodic model in one C call.

The DOP853 batch (``derive/templates/batch_map.c`` with the DOP853 tableau of
``variational.c``; 4 or 8 points at a time in GCC vector lanes where the model's right-hand side
has a vector form, ``generated/<model>_lanes.c``, bit-identical to one point after another)
and the Taylor batch (``taylor_batch_map.c``: the model's generated Taylor integrator, 4 or 8
points at a time in vector lanes, ``taylor_lanes.c``, each bit-identical to the one-point
loop; its driver ``chaplygin_taylor_run_lanes`` also runs
:func:`~chaplygin.numerics.ensemble.integrate_many`'s Taylor orbits). Sources from
:mod:`chaplygin.derive.emit.c_sources`, compiled and loaded here; the integrators that call
them are
:class:`~chaplygin.numerics.integrators.dop853_c.CompiledDOP853` and
:class:`~chaplygin.numerics.integrators.taylor_method.TaylorMethod`.
"""

from __future__ import annotations

import hashlib
import platform
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cffi
import numpy as np

from ...derive.emit.c_sources import JACOBIAN_LANES, batch_source, taylor_batch_source
from ..ccompile import CacheError, CompilationError, CompilerError, compile_c
from ..code import ModelCode
from ..compiled import CompilerUnavailableWarning
from .base import Problem, Solution

__all__ = [
    "BATCH_CFLAGS",
    "NATIVE_CFLAGS",
    "STATUS_MESSAGES",
    "batch_library",
    "cached_library",
    "cpu_identity",
    "lockstep_available",
    "variational_lockstep_available",
    "run_batch",
    "run_variational_batch",
    "taylor_batch_library",
]

_CDEF = """
void chaplygin_batch_map(long N, const double *Y0, const double *P, const double *T0,
                         const double *TAU_HI, const double *TAU_LO, long transient,
                         long n_record, double rtol, double atol, long max_steps, double *OUT,
                         double *STATS, int *STATUS);
void chaplygin_batch_map_lockstep(long N, const double *Y0, const double *P, const double *T0,
                                  const double *TAU_HI, const double *TAU_LO, long transient,
                                  long n_record, double rtol, double atol, long max_steps,
                                  double *OUT, double *STATS, int *STATUS);
void chaplygin_var_renormalised_many(long N, int k, const double *Z0, const double *P,
                                     const double *T0, const double *TAU, long n_intervals,
                                     double rtol, double atol, int project, long max_steps,
                                     double *Z, double *LOGS, double *DIVS, double *STATS,
                                     int *STATUS);
void chaplygin_var_renormalised_lockstep(long N, int k, const double *Z0, const double *P,
                                         const double *T0, const double *TAU, long n_intervals,
                                         double rtol, double atol, int project, long max_steps,
                                         double *Z, double *LOGS, double *DIVS, double *STATS,
                                         int *STATUS);
void chaplygin_taylor_batch_map(long N, const double *Y0, const double *P, const double *T0,
                                const double *TAU_HI, const double *TAU_LO, long transient,
                                long n_record, double rtol, double atol, long max_steps,
                                double *OUT, double *STATS, int *STATUS);
int chaplygin_taylor_lanes_width(void);
int chaplygin_lanes_sincos(long n, const double *X, double *S, double *C);
int chaplygin_taylor_run_lanes(long N, const double *T01, const double *Y0, const double *P,
                               const double *CTRL, int fixed_order, long n_eval,
                               const double *T_EVAL, long eval_stride, double *Y_EVAL,
                               double *Y_END, double *T_REACHED, long max_steps, long *STATS,
                               int *STATUS);
"""

#: Extra compiler flags of the batch library (part of the compile cache key), tried first:
#: -march=native lets the vector lanes use the CPU's widest instructions (AVX2: 4 doubles). The
#: CPU's identity (:func:`cpu_identity`) is added as a define, so that a cache shared by
#: machines of different CPUs keeps one library per CPU. No -ffast-math: ccompile's
#: -ffp-contract=off stays, so every lane computes the IEEE operations of the scalar code.
NATIVE_CFLAGS = ("-O3", "-march=native")
#: The flags used when the compiler refuses -march=native.
BATCH_CFLAGS = ("-O3",)

def cpu_identity() -> str:
    """A short hash of what ``-march=native`` depends on: the CPU's model and feature flags.

    Returns
    -------
    str
        16 hexadecimal digits (from ``/proc/cpuinfo`` on Linux, else
        :func:`platform.processor` and :func:`platform.machine`).
    """
    try:
        text = Path("/proc/cpuinfo").read_text()
        keys = ("model name", "flags", "Features", "CPU implementer", "CPU part")
        ident = "\n".join(sorted({ln for ln in text.splitlines() if ln.startswith(keys)}))
    except OSError:
        ident = ""
    ident = ident or f"{platform.processor()}|{platform.machine()}"
    return hashlib.sha256(ident.encode()).hexdigest()[:16]


_ffi = cffi.FFI()
_ffi.cdef(_CDEF)

#: Meaning of a point's status.
STATUS_MESSAGES = {
    0: "done",
    1: "the step limit of one period was reached (max_steps)",
    2: "the step size underflowed: the solution is probably singular here",
    3: "a non-finite value appeared in the state",
    4: "out of memory",
}

_LIBRARIES: dict[str, Any] = {}
_TAYLOR_LIBRARIES: dict[tuple, dict[str, Any]] = {}
_LOCKSTEP: dict[str, bool] = {}
_VARIATIONAL_LOCKSTEP: dict[str, bool] = {}


def cached_library(
    cache: dict[str, Any], code: ModelCode, build: Callable[[], Any], unavailable: str
) -> Any | None:
    """A compiled library of ``code``, built once per process by ``build``; None (also kept)
    after a :class:`CompilerUnavailableWarning` when the compiler fails or is missing.

    Parameters
    ----------
    cache : dict
        Libraries by model hash.
    code : ModelCode
    build : callable
        Compiles and loads the library (may return None: nothing to build).
    unavailable : str
        The warning, with ``{exc}`` for the compiler's error.

    Returns
    -------
    cffi library or None

    Raises
    ------
    CacheError
        Cache directory problems (the user's to fix).
    """
    if code.hash in cache:
        return cache[code.hash]
    try:
        lib = build()
    except CacheError:
        raise
    except (CompilerError, OSError) as exc:
        warnings.warn(unavailable.format(exc=exc), CompilerUnavailableWarning, stacklevel=4)
        lib = None
    cache[code.hash] = lib
    return lib


def batch_library(code: ModelCode) -> Any | None:
    """The compiled DOP853 batch library of ``code`` (:func:`cached_library`).

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    cffi library or None
    """

    def build() -> Any:
        source, has_lanes = batch_source(code.c_source, code.lanes_c_source)
        lib = _compile_native(source)
        _LOCKSTEP[code.hash] = has_lanes
        _VARIATIONAL_LOCKSTEP[code.hash] = has_lanes and JACOBIAN_LANES in code.lanes_c_source
        return lib

    return cached_library(
        _LIBRARIES, code, build,
        "the compiled batch map is unavailable ({exc}); use StroboscopicMap per point",
    )  # fmt: skip


def _compile_native(source: str, defines: tuple[str, ...] = ()) -> Any:
    """Compile ``source`` with :data:`NATIVE_CFLAGS` (else :data:`BATCH_CFLAGS`) and
    ``defines`` and load it."""
    try:
        native = (*NATIVE_CFLAGS, f"-DCHAPLYGIN_CPU_ID=cpu_{cpu_identity()}", *defines)
        path = compile_c(source, cflags=native)
    except CompilationError:  # e.g. a compiler without -march=native
        path = compile_c(source, cflags=(*BATCH_CFLAGS, *defines))
    return _ffi.dlopen(str(path))


def lockstep_available(code: ModelCode) -> bool:
    """Whether the DOP853 batch library of ``code`` has the vector-lane driver (the model's
    right-hand side calls only sin, cos, exp, log, sqrt, fabs).

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    bool
    """
    return _LOCKSTEP.get(code.hash, False)


def variational_lockstep_available(code: ModelCode) -> bool:
    """Whether the DOP853 batch library of ``code`` has the vector-lane driver of Benettin's
    loop (the model's right-hand side and Jacobian call only sin, cos, exp, log, sqrt, fabs).

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    bool
    """
    return _VARIATIONAL_LOCKSTEP.get(code.hash, False)


def taylor_batch_library(code: ModelCode, lanes: int | None = None,
                         orders: tuple[int, ...] = ()) -> Any | None:  # fmt: skip
    """The compiled Taylor batch library of ``code`` (:func:`cached_library`): the batch
    map and the Taylor integrator of many orbits in vector lanes
    (``chaplygin_taylor_run_lanes``); None also without generated Taylor code or its printed
    program.

    Parameters
    ----------
    code : ModelCode
    lanes : int, optional
        Orbits per vector (``TL_W``; default the template's: 8 where the compiler targets
        AVX-512, else 4; ``chaplygin_taylor_lanes_width()``). Every orbit's numbers are the
        same for every width; other widths are for the tests of that.
    orders : tuple of int, optional
        The orders to write the coefficients out for (a run's
        :func:`~chaplygin.numerics.taylor.run_orders`; the others run the loop: the same
        bits, slower).

    Returns
    -------
    cffi library or None
    """

    def build() -> Any | None:
        if not (code.taylor_c_source and code.taylor_program):
            return None
        source = taylor_batch_source(code.taylor_c_source, code.taylor_program, orders)
        # -O3 -march=native, as the DOP853 lanes: the recurrences on 4 lanes in one AVX2
        # register (BM20's map: 48 -> 28 us per point and period against -O2); ccompile's
        # -ffp-contract=off stays, so the bits are those of the -O2 loop of one orbit
        width = () if lanes is None else (f"-DTL_W={int(lanes)}",)
        return _compile_native(source, width)

    return cached_library(
        _TAYLOR_LIBRARIES.setdefault((lanes, tuple(orders)), {}), code, build,
        "the compiled Taylor batch map is unavailable ({exc}); use StroboscopicMap",
    )  # fmt: skip


def _buf(a: np.ndarray, kind: str = "double[]") -> Any:
    """A C pointer to ``a``'s data (the driver writes into the output arrays)."""
    return _ffi.from_buffer(kind, a, require_writable=False)


def run_batch(driver: Any, problem: Problem) -> tuple[Solution, np.ndarray]:
    """Call one batch driver on a problem of a
    :class:`~chaplygin.numerics.integrators.flows.Batch`.

    Parameters
    ----------
    driver : cffi function
        ``chaplygin_batch_map``, ``chaplygin_batch_map_lockstep`` or
        ``chaplygin_taylor_batch_map``.
    problem : Problem
        ``y0`` (N, n_state) and ``params`` (N, n_param) C-contiguous float64 arrays,
        ``t_eval`` a :class:`~chaplygin.numerics.integrators.flows.StroboscopicTimes`.

    Returns
    -------
    (Solution, ndarray)
        The map points ``y`` (N, count, n_state), the points' status in ``info["status"]``
        and the wall time in ``info["wall_s"]``; and the driver's STATS (N, 3).
    """
    Y0, P, times = problem.y0, problem.params, problem.t_eval
    N, n_state = Y0.shape
    omega = P[:, problem.code.params.index(problem.code.forcing)]
    tau_hi, tau_lo = times.periods(omega)
    out = np.empty((N, times.count, n_state))
    stats = np.zeros((N, 3))
    status = np.zeros(N, dtype=np.int32)

    start = time.perf_counter()
    driver(
        N, _buf(Y0), _buf(P), _buf(times.t0), _buf(tau_hi), _buf(tau_lo), times.transient,
        times.count, problem.rtol, problem.atol, problem.max_steps, _buf(out), _buf(stats),
        _buf(status, "int[]"),
    )  # fmt: skip
    wall = time.perf_counter() - start
    sol = Solution(
        t=None,
        y=out,
        status=0,
        message="done",
        nfev=0,
        info={"status": status, "wall_s": wall, "periods": times.transient + times.count - 1},
    )
    return sol, stats


def run_variational_batch(
    lib: Any, problem: Problem, lockstep: bool
) -> tuple[np.ndarray, dict[str, Any]]:
    """Benettin's loop for many points in one call (``templates/variational_batch.c``).

    Parameters
    ----------
    lib : cffi library
        The batch library of the problem's model (:func:`batch_library`).
    problem : Problem
        A :class:`~chaplygin.numerics.integrators.flows.VariationalBatch`: ``y0`` the augmented
        states ``(N, n + n k + 1)`` and ``params`` ``(N, n_param)`` (C-contiguous float64),
        ``options["renormalise"]`` a
        :class:`~chaplygin.numerics.integrators.flows.Renormalisation` whose ``tau`` and
        ``t0`` are arrays of shape ``(N,)``.
    lockstep : bool
        The vector-lane driver (else one point after another; the same bits).

    Returns
    -------
    (ndarray, dict)
        The augmented states at the end ``(N, n + n k + 1)``, and ``status`` (N,), ``logs``
        (N, intervals, k), ``divergence`` (N, intervals), ``stats`` (N, 4) and ``wall_s``.
    """
    plan = problem.options["renormalise"]
    Z0, P = problem.y0, problem.params
    N, k = len(Z0), problem.system.tangents
    Z = np.empty_like(Z0)
    logs = np.zeros((N, plan.intervals, k))
    divs = np.zeros((N, plan.intervals))
    stats = np.zeros((N, 4))
    status = np.zeros(N, dtype=np.int32)

    driver = (
        lib.chaplygin_var_renormalised_lockstep if lockstep else lib.chaplygin_var_renormalised_many
    )
    start = time.perf_counter()
    driver(
        N, k, _buf(Z0), _buf(P), _buf(plan.t0), _buf(plan.tau), plan.intervals, problem.rtol,
        problem.atol, int(bool(plan.project)) if plan.orthonormalise else -1, problem.max_steps,
        _buf(Z), _buf(logs), _buf(divs),
        _buf(stats), _buf(status, "int[]"),
    )  # fmt: skip
    info = {"status": status, "logs": logs, "divergence": divs, "stats": stats,
            "wall_s": time.perf_counter() - start}  # fmt: skip
    return Z, info
