"""The stroboscopic map of many points in one compiled call.

:class:`BatchStroboscopicMap` advances ``N`` points, each with its own initial state and
parameter vector (its own ``Omega``, hence its own period ``tau = 2 pi/Omega``), through
``transient + n - 1`` forcing periods and records the ``n`` map points
``P^(transient + k)(y0)``, ``k = 0 .. n-1``, of every point, in one call into C
(``numerics/templates/batch_map.c``, compiled with the model's generated C source and the
DOP853 tableau of ``numerics/templates/variational.c``): no Python runs per step or per period.
Every step lands exactly on the sampling times ``t0 + k tau``, computed from ``tau`` held as a
double-double (from 40-digit ``2 pi/Omega``) so that they carry no accumulated rounding.

Four points at a time run in the lanes of GCC vector types (the generated right-hand side with
every double a vector, :func:`vector_rhs_source`; lanes are refilled as points finish), each
lane doing the IEEE operations of the one-point driver, so the two drivers give the same bits.
The library is built with ``-O3 -march=native`` (the CPU's identity in the cache key), or
``-O3`` where the compiler refuses that. Points are independent: one that fails (non-finite
value, step-size underflow, step limit) gets its own status and NaN points, and the others are
unaffected. Double precision only.

``BatchStroboscopicMap(code, method="taylor")`` runs the same call through the model's generated
Taylor integrator instead (``numerics/templates/taylor_batch_map.c`` appended to the double build
of the model's Taylor C source: ``chaplygin_taylor_run`` per point from C, the step polynomials
evaluated at the sampling times; the steps of ``StroboscopicMap(method="taylor")`` and its map
points up to the rounding of the sampling times; one point after another, no vector lanes).

This is the fast path of the sweep's ``period`` reducer (:mod:`chaplygin.verify.sweep`; DOP853
for ``period.engine`` "auto" and "batch", Taylor for "taylor-batch"); the
single-point :class:`~chaplygin.numerics.poincare.StroboscopicMap` (Taylor method, any
precision) is the reference it is tested against.

Examples
--------
>>> from chaplygin.numerics.code import load_model_code
>>> code = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
>>> bm = BatchStroboscopicMap(code, rtol=1e-12)
>>> p = [4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.07]
>>> r = bm.run([[1.5, 2.0, 1.0, 0.6, -0.8, 0.0]] * 2, [p, p], n=3)
>>> r.y.shape, r.status.tolist()
((2, 3, 6), [0, 0])

References
----------
BM20-map; E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I,
II.5 and II.10 (DOP853).
"""

from __future__ import annotations

import hashlib
import platform
import re
import time
import warnings
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import cffi
import mpmath
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..derive.errors import ComputationError, UserInputError
from .ccompile import CacheError, CompilationError, CompilerError, compile_c
from .code import ModelCode
from .compiled import CompilerUnavailableWarning

__all__ = [
    "BatchMapResult",
    "BatchStroboscopicMap",
    "batch_map_available",
    "cpu_identity",
    "vector_rhs_source",
    "STATUS_MESSAGES",
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
void chaplygin_taylor_batch_map(long N, const double *Y0, const double *P, const double *T0,
                                const double *TAU_HI, const double *TAU_LO, long transient,
                                long n_record, double rtol, double atol, long max_steps,
                                double *OUT, double *STATS, int *STATUS);
"""

#: Functions the vector right-hand side applies lane by lane (batch_map.c BM_LANEWISE): the
#: project's elementary functions (arith/templates/detmath.h) and the exact sqrt, fabs.
_LANEWISE = frozenset(
    {"chaplygin_sin", "chaplygin_cos", "chaplygin_exp", "chaplygin_log", "sqrt", "fabs"}
)

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

#: The integration methods of :class:`BatchStroboscopicMap`.
METHODS = ("dop853", "taylor")

#: Extra compiler flags of the batch library (part of the compile cache key), tried first:
#: -march=native lets the vector lanes use the CPU's widest instructions (AVX2: 4 doubles). The
#: CPU's identity (:func:`cpu_identity`) is added as a define, so that a cache shared by
#: machines of different CPUs keeps one library per CPU. No -ffast-math: ccompile's
#: -ffp-contract=off stays, so every lane computes the IEEE operations of the scalar code.
NATIVE_CFLAGS = ("-O3", "-march=native")
#: The flags used when the compiler refuses -march=native.
BATCH_CFLAGS = ("-O3",)

_LIBRARIES: dict[str, Any] = {}
_TAYLOR_LIBRARIES: dict[str, Any] = {}
_LOCKSTEP: dict[str, bool] = {}


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


def vector_rhs_source(c_source: str) -> str | None:
    """``bm_rhs_vec``: the generated ``chaplygin_rhs`` with every double a vector of lanes.

    The emitted function is straight-line code (``const double x = expression;`` and
    ``OUT[i] = expression;``); with GCC's vector types the same text computes every lane with
    the same IEEE operations, libm calls being applied lane by lane. None when the function
    calls anything else (then only the one-point-at-a-time driver is built).

    Parameters
    ----------
    c_source : str
        A model's emitted C source.

    Returns
    -------
    str or None
    """
    head = "void chaplygin_rhs(double T, const double *restrict Y, const double *restrict P, "
    start = c_source.find(head)
    if start < 0:
        return None
    open_brace = c_source.index("{", start)
    end = c_source.index("\n}\n", open_brace) + 3
    body = c_source[open_brace:end]
    called = set(re.findall(r"\b([A-Za-z_]\w*)\s*\(", body))
    if not called <= _LANEWISE or re.search(r"\b(int|long|float|if|for|while)\b", body):
        return None
    body = re.sub(r"\bconst double\b", "const bm_vec", body)
    if "double" in body:
        return None
    for name in called:
        body = re.sub(rf"\b{name}\s*\(", f"bm_v_{name}(", body)
    return (
        "static void bm_rhs_vec(bm_vec T, const bm_vec *restrict Y, const bm_vec *restrict P, "
        "bm_vec *restrict OUT)\n" + body
    )


def _library(code: ModelCode) -> Any | None:
    """The compiled batch library of ``code`` (cached per process), or None without a compiler."""
    if code.hash in _LIBRARIES:
        return _LIBRARIES[code.hash]
    templates = resources.files("chaplygin.numerics").joinpath("templates")
    vector_rhs = vector_rhs_source(code.c_source)
    source = "\n".join(
        (
            code.c_source,
            templates.joinpath("variational.c").read_text(),
            "#define BM_VEC_RHS 1" if vector_rhs else "",
            templates.joinpath("batch_map.c").read_text(),
            vector_rhs or "",
        )
    )
    try:
        lib = _compile_native(source)
        _LOCKSTEP[code.hash] = vector_rhs is not None
    except CacheError:  # cache directory problems are the user's to fix
        raise
    except (CompilerError, OSError) as exc:
        warnings.warn(
            f"the compiled batch map is unavailable ({exc}); use StroboscopicMap per point",
            CompilerUnavailableWarning,
            stacklevel=3,
        )
        lib = None
    _LIBRARIES[code.hash] = lib
    return lib


def _compile_native(source: str) -> Any:
    """Compile ``source`` with :data:`NATIVE_CFLAGS` (else :data:`BATCH_CFLAGS`) and load it."""
    try:
        native = (*NATIVE_CFLAGS, f"-DCHAPLYGIN_CPU_ID=cpu_{cpu_identity()}")
        path = compile_c(source, cflags=native)
    except CompilationError:  # e.g. a compiler without -march=native
        path = compile_c(source, cflags=BATCH_CFLAGS)
    return _ffi.dlopen(str(path))


def _c_function(source: str, name: str) -> str:
    """The text of the C function ``name`` of ``source`` (from its declaration to the first
    ``}`` in column 0)."""
    start = re.search(rf"^static \w+ {name}\(", source, re.MULTILINE)
    if start is None:
        raise ComputationError(f"no C function {name} in the batch map templates")
    return source[start.start() : source.index("\n}\n", start.start()) + 3]


def _taylor_library(code: ModelCode) -> Any | None:
    """The compiled Taylor batch library of ``code`` (cached per process): the model's
    generated Taylor C source (double) + ``bm_time`` of batch_map.c + taylor_batch_map.c,
    compiled with the default flags; None without a compiler or without generated Taylor
    code."""
    if code.hash in _TAYLOR_LIBRARIES:
        return _TAYLOR_LIBRARIES[code.hash]
    lib = None
    if code.taylor_c_source:
        templates = resources.files("chaplygin.numerics").joinpath("templates")
        source = "\n".join(
            (
                code.taylor_c_source,
                "#include <float.h>",
                _c_function(templates.joinpath("batch_map.c").read_text(), "bm_time"),
                templates.joinpath("taylor_batch_map.c").read_text(),
            )
        )
        try:  # the flags of the single-point Taylor library (-O2): -O3 (with or without
            # -march=native) made it about 1.6 times slower here (vectorised short recurrences)
            lib = _ffi.dlopen(str(compile_c(source)))
        except CacheError:
            raise
        except (CompilerError, OSError) as exc:
            warnings.warn(
                f"the compiled Taylor batch map is unavailable ({exc}); use StroboscopicMap",
                CompilerUnavailableWarning,
                stacklevel=3,
            )
    _TAYLOR_LIBRARIES[code.hash] = lib
    return lib


def batch_map_available(code: ModelCode, method: str = "dop853") -> bool:
    """Whether the compiled batch map can be built for ``code`` (a C compiler is present).

    Parameters
    ----------
    code : ModelCode
    method : {"dop853", "taylor"}
        The integrator of the batch (see :class:`BatchStroboscopicMap`).

    Returns
    -------
    bool

    Raises
    ------
    UserInputError
        An unknown ``method``.
    """
    if method not in METHODS:
        raise UserInputError(f"the batch map's method must be one of {METHODS}, got {method!r}")
    if "Omega" not in code.params:
        return False
    return (_taylor_library(code) if method == "taylor" else _library(code)) is not None


@dataclass
class BatchMapResult:
    """Map points of a batch with their status and work counters.

    Attributes
    ----------
    y : ndarray, shape (N, n, n_state)
        ``y[j, k]`` is point ``j``'s state at ``t0 + (transient + k) tau_j`` (NaN after a
        failure).
    status : ndarray of int, shape (N,)
        0 done, else a key of :data:`STATUS_MESSAGES`.
    steps, rejected, evaluations : ndarray of int, shape (N,)
        DOP853: accepted and rejected steps and right-hand-side evaluations per point. Taylor:
        steps, zeros (a Taylor step is never rejected) and the evaluations of the Taylor
        coefficients (one per step).
    periods : int
        Forcing periods advanced per point (``transient + n - 1``).
    wall_s : float
        Wall time of the call.
    lockstep : bool
        Whether the points ran 4 at a time in vector lanes (else one after another).
    method : str
        ``"dop853"`` or ``"taylor"``.
    orders : ndarray of int, shape (N, 2), or None
        Taylor: the lowest and highest order of each point's steps (None for DOP853).
    """

    y: NDArray[np.float64]
    status: NDArray[np.int32]
    steps: NDArray[np.int64]
    rejected: NDArray[np.int64]
    evaluations: NDArray[np.int64]
    periods: int
    wall_s: float
    lockstep: bool = False
    method: str = "dop853"
    orders: NDArray[np.int64] | None = None

    @property
    def ok(self) -> NDArray[np.bool_]:
        """Which points finished.

        Returns
        -------
        ndarray of bool, shape (N,)
        """
        return self.status == 0


class BatchStroboscopicMap:
    """The period map ``y(t0) -> y(t0 + tau)`` of a time-periodic model for many points at once.

    With ``method="taylor"`` every point is integrated by the model's generated Taylor
    integrator (``chaplygin_taylor_run`` of the double build, called per point from C by
    ``numerics/templates/taylor_batch_map.c``): the steps of
    ``integrate(method="taylor")`` from ``t0`` to the last sampling time, the map points
    being the step polynomials evaluated at the sampling times; one point after another (no
    vector lanes).

    Parameters
    ----------
    code : ModelCode
        A model with the parameter ``Omega`` (BM20's ``variable_inertia``/``variable_gyrostat``).
    rtol, atol : float
        Tolerances of the DOP853 error control (per component, ``atol + rtol |y|``), or of the
        Taylor method (its order and step size, Jorba & Zou).
    max_steps : int
        Cap on the steps of one forcing period of one point (Taylor: on a point's steps
        divided by its periods).
    method : {"dop853", "taylor"}
        The integrator.

    Raises
    ------
    UserInputError
        The model has no ``Omega``; tolerances out of (0, 1); ``max_steps < 1``; an unknown
        ``method``.
    ComputationError
        No C compiler (use :class:`~chaplygin.numerics.poincare.StroboscopicMap`).

    References
    ----------
    BM20-map.
    """

    def __init__(
        self,
        code: ModelCode,
        *,
        rtol: float = 1e-12,
        atol: float = 1e-12,
        max_steps: int = 100_000,
        method: str = "dop853",
    ) -> None:
        if "Omega" not in code.params:
            raise UserInputError(
                f"{code.name} is not time-periodic (no parameter Omega): a stroboscopic map needs "
                "the effects variable_inertia or variable_gyrostat"
            )
        for name, tol in (("rtol", rtol), ("atol", atol)):
            if not (0 < float(tol) < 1):
                raise UserInputError(f"{name} must be in (0, 1), got {tol}")
        if int(max_steps) < 1:
            raise UserInputError(f"max_steps must be at least 1, got {max_steps}")
        if method not in METHODS:
            raise UserInputError(f"the batch map's method must be one of {METHODS}, got {method!r}")
        self.code = code
        self.method = method
        self.rtol, self.atol, self.max_steps = float(rtol), float(atol), int(max_steps)
        self._lib = _taylor_library(code) if method == "taylor" else _library(code)
        if self._lib is None:
            raise ComputationError(
                "the batch map needs a C compiler (the Taylor one also the model's generated "
                "Taylor code); use StroboscopicMap"
            )
        self._omega = code.params.index("Omega")

    def _rows(self, values: ArrayLike, width: int, what: str) -> NDArray[np.float64]:
        a = np.array(values, dtype=np.float64)
        if a.ndim != 2 or a.shape[1] != width:
            raise UserInputError(f"{what} must be an array of shape (N, {width}), got {a.shape}")
        return np.ascontiguousarray(a)

    @property
    def lockstep_available(self) -> bool:
        """Whether the vector-lane driver was built (the model's right-hand side calls only
        sin, cos, exp, log, sqrt, fabs).

        Returns
        -------
        bool
        """
        return self.method == "dop853" and _LOCKSTEP.get(self.code.hash, False)

    def run(
        self,
        y0: ArrayLike,
        params: ArrayLike,
        n: int,
        transient: int = 0,
        t0: ArrayLike = 0.0,
        lockstep: bool = True,
    ) -> BatchMapResult:
        """Advance every point and record its map points.

        Parameters
        ----------
        y0 : array_like, shape (N, n_state)
            Initial states (double).
        params : array_like, shape (N, n_param)
            Parameters in ``code.params`` order, one row per point (double).
        n : int
            Map points recorded per point (>= 1).
        transient : int
            Periods discarded first (>= 0).
        t0 : float or array_like, shape (N,)
            Phase of the section (default 0).
        lockstep : bool, default True
            Advance 4 points at a time in vector lanes where available (bit-identical to one
            after another, faster); False: one after another. Ignored by the Taylor method
            (always one after another).

        Returns
        -------
        BatchMapResult

        Raises
        ------
        UserInputError
            Wrong shapes, ``n < 1``, ``transient < 0``, non-finite parameters or ``Omega <= 0``.
        """
        n_state, n_param = len(self.code.state), len(self.code.params)
        Y0 = self._rows(y0, n_state, "y0")
        P = self._rows(params, n_param, "params")
        N = len(Y0)
        if len(P) != N:
            raise UserInputError(f"y0 has {N} rows but params has {len(P)}")
        if not (isinstance(n, int) and n >= 1 and isinstance(transient, int) and transient >= 0):
            raise UserInputError("a batch map needs n >= 1 points and transient >= 0")
        if not np.all(np.isfinite(P)):
            raise UserInputError("the parameters must be finite")
        omega = P[:, self._omega]
        if not np.all(omega > 0):
            raise UserInputError("Omega must be positive for a stroboscopic map")
        T0 = np.ascontiguousarray(np.broadcast_to(np.asarray(t0, dtype=np.float64), (N,)))
        return self._advance(Y0, P, T0, n, transient, lockstep)

    def _advance(
        self,
        Y0: NDArray[np.float64],
        P: NDArray[np.float64],
        T0: NDArray[np.float64],
        n: int,
        transient: int,
        lockstep: bool,
    ) -> BatchMapResult:
        """The C call of :meth:`run` on checked arrays (C-contiguous, shapes (N, n_state),
        (N, n_param), (N,))."""
        N, n_state = Y0.shape
        omega = P[:, self._omega]
        tau_hi, tau_lo = np.empty(N), np.empty(N)
        with mpmath.workdps(40):
            for j, w in enumerate(omega):
                tau = 2 * mpmath.pi / mpmath.mpf(float(w))
                tau_hi[j] = float(tau)
                tau_lo[j] = float(tau - mpmath.mpf(tau_hi[j]))
        out = np.empty((N, n, n_state))
        stats = np.zeros((N, 3))
        status = np.zeros(N, dtype=np.int32)

        def buf(a: np.ndarray, kind: str = "double[]") -> Any:
            return _ffi.from_buffer(kind, a, require_writable=False)

        lib = self._lib
        use_lockstep = self.method == "dop853" and lockstep and self.lockstep_available and N > 1
        if self.method == "taylor":
            driver = lib.chaplygin_taylor_batch_map
        elif use_lockstep:
            driver = lib.chaplygin_batch_map_lockstep
        else:
            driver = lib.chaplygin_batch_map
        start = time.perf_counter()
        driver(
            N, buf(Y0), buf(P), buf(T0), buf(tau_hi), buf(tau_lo), transient, n,
            self.rtol, self.atol, self.max_steps, buf(out), buf(stats), buf(status, "int[]"),
        )  # fmt: skip
        wall = time.perf_counter() - start
        if self.method == "taylor":  # STATS: steps, lowest order, highest order
            steps = stats[:, 0].astype(np.int64)
            return BatchMapResult(
                y=out, status=status, steps=steps, rejected=np.zeros(N, dtype=np.int64),
                evaluations=steps.copy(), periods=transient + n - 1, wall_s=wall,
                lockstep=False, method="taylor", orders=stats[:, 1:].astype(np.int64),
            )  # fmt: skip
        return BatchMapResult(
            y=out,
            status=status,
            steps=stats[:, 0].astype(np.int64),
            rejected=stats[:, 1].astype(np.int64),
            evaluations=stats[:, 2].astype(np.int64),
            periods=transient + n - 1,
            wall_s=wall,
            lockstep=use_lockstep,
        )
