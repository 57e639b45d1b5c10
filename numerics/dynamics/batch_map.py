"""The stroboscopic map of many points in one compiled call.

:class:`BatchStroboscopicMap` advances ``N`` points, each with its own initial state and
parameter vector (its own ``Omega``, hence its own period ``tau = 2 pi/Omega``), through
``transient + n - 1`` forcing periods and records the ``n`` map points
``P^(transient + k)(y0)``, ``k = 0 .. n-1``, of every point, in one call into C
(``derive/templates/batch_map.c``, compiled with the model's generated C source and the
DOP853 tableau of ``derive/templates/variational.c``): no Python runs per step or per period.
Every step lands exactly on the sampling times ``t0 + k tau``, computed from ``tau`` held as a
double-double (from 40-digit ``2 pi/Omega``) so that they carry no accumulated rounding.

Four points at a time run in the lanes of GCC vector types (the generated right-hand side with
every double a vector, ``generated/<model>_lanes.c`` of
:class:`~chaplygin.derive.emit.c_emitter.CLanesEmitter`; lanes are refilled as points finish), each
lane doing the IEEE operations of the one-point driver, so the two drivers give the same bits.
The library is built with ``-O3 -march=native`` (the CPU's identity in the cache key), or
``-O3`` where the compiler refuses that. Points are independent: one that fails (non-finite
value, step-size underflow, step limit) gets its own status and NaN points, and the others are
unaffected. Double precision only.

``BatchStroboscopicMap(code, method="taylor")`` runs the same call through the model's generated
Taylor integrator instead (``derive/templates/taylor_batch_map.c`` appended to the double build
of the model's Taylor C source and its lanes driver, ``derive/templates/taylor_lanes.c``: 4 or 8
points at a time in vector lanes, each point's numbers those of ``chaplygin_taylor_run`` on it,
bit for bit; the step polynomials evaluated at the sampling times; the steps of
``StroboscopicMap(method="taylor")`` and its map points up to the rounding of the sampling
times).

Both are integrators of the one registry (``dop853`` and ``taylor`` of
:data:`~chaplygin.numerics.integrators.INTEGRATORS`, on a
:class:`~chaplygin.numerics.integrators.flows.Batch`); this module reads and checks the
inputs and shapes the result.

This is the fast path of the sweep's ``period`` reducer (:mod:`chaplygin.verify.sweep`; DOP853
for ``period.engine`` "auto" and "batch", Taylor for "taylor-batch"); the
single-point :class:`~chaplygin.numerics.dynamics.poincare.StroboscopicMap` (Taylor method, any
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

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...derive.errors import UserInputError
from ..code import ModelCode
from ..integrators import INTEGRATORS, Batch, Problem, StroboscopicTimes
from ..integrators.c_batch import (
    BATCH_CFLAGS,
    NATIVE_CFLAGS,
    STATUS_MESSAGES,
    batch_library,
    cpu_identity,
    lockstep_available,
    taylor_batch_library,
)
from ..precision import Precision

__all__ = [
    "BatchMapResult",
    "BatchStroboscopicMap",
    "batch_map_available",
    "cpu_identity",
    "STATUS_MESSAGES",
    "NATIVE_CFLAGS",
    "BATCH_CFLAGS",
]

#: The integration methods of :class:`BatchStroboscopicMap` (names in
#: :data:`~chaplygin.numerics.integrators.INTEGRATORS`).
METHODS = ("dop853", "taylor")

_DOUBLE = Precision("double")


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
    if code.forcing is None:
        return False
    return (taylor_batch_library(code) if method == "taylor" else batch_library(code)) is not None


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
    integrator in vector lanes (``derive/templates/taylor_batch_map.c`` on
    ``taylor_lanes.c``: 4 or 8 points at a time, each bit-identical to ``chaplygin_taylor_run``
    of the double build on it): the steps of ``integrate(method="taylor")`` from ``t0`` to
    the last sampling time, the map points being the step polynomials evaluated at the
    sampling times.

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
        No C compiler (use :class:`~chaplygin.numerics.dynamics.poincare.StroboscopicMap`).

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
        if code.forcing is None:
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
        self._integrator = INTEGRATORS[method]()
        # compiled or loaded now (ComputationError without a compiler): a run only integrates
        self._backend = self._integrator.prepare(self._problem(np.zeros((0, 0)), None, None))
        self._omega = code.params.index(code.forcing)

    def _problem(self, Y0, P, times, lockstep: bool = True) -> Problem:
        return Problem(Batch(self.code), Y0, None, P, _DOUBLE, self.rtol, self.atol,
                       t_eval=times, options={"lockstep": lockstep},
                       max_steps=self.max_steps)  # fmt: skip

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
        return self.method == "dop853" and lockstep_available(self.code)

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
            Advance 4 or 8 points at a time in vector lanes where available (bit-identical to one
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
        """The integration of :meth:`run` on checked arrays (C-contiguous, shapes (N, n_state),
        (N, n_param), (N,))."""
        problem = self._problem(Y0, P, StroboscopicTimes(T0, transient, n), lockstep)
        sol = self._integrator.solve(problem, chosen=self._backend)
        info = sol.info
        return BatchMapResult(
            y=sol.y,
            status=info["status"],
            steps=info["steps"],
            rejected=info["rejected"],
            evaluations=info["evaluations"],
            periods=info["periods"],
            wall_s=info["wall_s"],
            lockstep=info["lockstep"],
            method=self.method,
            orders=info.get("orders"),
        )
