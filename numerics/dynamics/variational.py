"""Variational equations of a model: the flow with its state-transition matrix, in C.

The augmented system ``y' = f(t, y)``, ``V' = J(t, y) V``, ``q' = tr J(t, y)`` (``J`` the
generated Jacobian, ``q`` the integral of the divergence of the vector field; a
:class:`~chaplygin.numerics.integrators.flows.VariationalFlow`) is integrated through the
integrators' door by the ``dop853`` integrator: an adaptive DOP853 written in C
(``derive/templates/variational.c``) that is compiled together with the model's emitted C
source (``generated/<model>.c``: ``chaplygin_rhs_jac``, the two in one routine), so the right-hand
side and Jacobian are the generated ones and no Python runs inside a step. The error of a
step is measured on ``y`` and ``V`` together. Double precision only.

Without a C compiler the same system is integrated by scipy's ``DOP853`` with the numpy
module's ``rhs`` and ``jac``, after a warning (the integrator's ``numpy`` backend).

Examples
--------
>>> from chaplygin.numerics.code import load_model_code
>>> code = load_model_code("chaplygin_ball")
>>> y1, Phi = flow_with_jacobian(code, [2, 3, 4, 1], [1, 0, 0, 0, 0.6, 0.8], 0, 1)
>>> Phi.shape
(6, 6)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...arith import detlinalg
from ...derive.errors import ComputationError, UserInputError
from ..arguments import check_rows
from ..code import ModelCode
from ..integrators import (
    INTEGRATORS,
    Problem,
    Renormalisation,
    Solution,
    VariationalBatch,
    VariationalFlow,
)
from ..integrators.c_batch import batch_library
from ..precision import Precision

__all__ = [
    "VariationalSystem",
    "TangentFlow",
    "flow_with_jacobian",
    "flow_jacobians",
    "FlowJacobians",
    "renormalised_many",
    "renormalised_after_transient",
    "BenettinRuns",
    "variational_batch_available",
    "variational_system",
]

#: Default cap on the steps of one interval.
DEFAULT_MAX_STEPS = 1_000_000

_DOUBLE = Precision("double")


@dataclass
class TangentFlow:
    """The result of integrating the variational equations over a span.

    Attributes
    ----------
    y : ndarray, shape (n,)
        The state at the end.
    V : ndarray, shape (n, k)
        The tangent vectors at the end (``Phi @ V0``).
    divergence_integral : float
        ``integral of div f dt`` over the span (``tr J`` along the orbit).
    steps, rejected, evaluations : int
        Work counters (accepted and rejected steps, evaluations of the augmented system).
    """

    y: NDArray[np.float64]
    V: NDArray[np.float64]
    divergence_integral: float
    steps: int
    rejected: int
    evaluations: int


class VariationalSystem:
    """The variational equations of one model at fixed parameters (double precision).

    Parameters
    ----------
    code : ModelCode
        The model's generated code.
    params : array_like, shape (n_param,)
        Parameter values (in ``code.params`` order); converted to double.
    rtol, atol : float
        Tolerances of the DOP853 error control, applied to the state and the tangent vectors.
    max_steps : int, optional
        Cap on the steps of one call.

    Raises
    ------
    UserInputError
        Wrong number of parameters, non-finite values, tolerances out of (0, 1).
    """

    def __init__(
        self,
        code: ModelCode,
        params: ArrayLike,
        *,
        rtol: float = 1e-10,
        atol: float = 1e-12,
        max_steps: int = DEFAULT_MAX_STEPS,
    ) -> None:
        self.code = code
        self.n = len(code.state)
        p = np.array([float(v) for v in params], dtype=np.float64)
        if p.shape != (len(code.params),):
            raise UserInputError(
                f"{code.name} takes {len(code.params)} parameters ({', '.join(code.params)}), "
                f"got {p.size}"
            )
        if not np.all(np.isfinite(p)):
            raise UserInputError("the parameters must be finite")
        for name, tol in (("rtol", rtol), ("atol", atol)):
            if not (0 < float(tol) < 1):
                raise UserInputError(f"{name} must be in (0, 1), got {tol}")
        self.params = p
        self.rtol = float(rtol)
        self.atol = float(atol)
        self.max_steps = int(max_steps)
        self._integrator = INTEGRATORS["dop853"]()
        probe = self._problem(VariationalFlow(code, 1), np.zeros(2 * self.n + 1), (0.0, 0.0))
        self._backend = self._integrator.prepare(probe)

    @property
    def compiled(self) -> bool:
        """Whether the C integrator is used (else scipy's DOP853).

        Returns
        -------
        bool
        """
        return self._backend == "c"

    def _problem(self, flow: VariationalFlow, z: NDArray, span: tuple, **options: Any) -> Problem:
        return Problem(flow, z, span, self.params, _DOUBLE, self.rtol, self.atol,
                       options=options, max_steps=self.max_steps)  # fmt: skip

    def _solve(self, problem: Problem) -> Solution:
        """The door's solve, a failure raised as a ComputationError."""
        sol = self._integrator.solve(problem, chosen=self._backend)
        if sol.status:
            if self._backend == "c":
                self._raise(sol.message, float(problem.t_span[0]))
            raise ComputationError(f"variational equations of {self.code.name}: {sol.message}")
        return sol

    def _state(self, y: ArrayLike) -> NDArray[np.float64]:
        y = np.array(y, dtype=np.float64).ravel()
        if y.shape != (self.n,):
            raise UserInputError(f"the state must have {self.n} components, got {y.size}")
        if not np.all(np.isfinite(y)):
            raise UserInputError("the state must be finite")
        return y

    def _raise(self, message: str, t: float) -> None:
        raise ComputationError(
            f"variational equations of {self.code.name} failed near t = {t:.6g}: {message}"
        )

    def flow(self, y0: ArrayLike, t0: float, t1: float, V0: ArrayLike | None = None) -> TangentFlow:
        """Integrate the state and tangent vectors from ``t0`` to ``t1``.

        Parameters
        ----------
        y0 : array_like, shape (n,)
            Initial state.
        t0, t1 : float
            The span (``t1 < t0`` integrates backwards).
        V0 : array_like, shape (n, k), optional
            Initial tangent vectors; the identity (so that ``V`` is ``Phi``) by default.

        Returns
        -------
        TangentFlow
            The state, the tangent vectors and the divergence integral at ``t1``.

        Raises
        ------
        UserInputError
            Wrong shapes or non-finite input.
        ComputationError
            The integration failed (step limit, step-size underflow, overflow).
        """
        y = self._state(y0)
        V = np.eye(self.n) if V0 is None else np.array(V0, dtype=np.float64)
        if V.ndim != 2 or V.shape[0] != self.n or not 1 <= V.shape[1] <= self.n:
            raise UserInputError(f"V0 must have shape ({self.n}, k) with 1 <= k <= {self.n}")
        t0, t1 = float(t0), float(t1)
        k = V.shape[1]
        flow = VariationalFlow(self.code, k)
        sol = self._solve(self._problem(flow, flow.pack(y, V), (t0, t1)))
        z, n = sol.y[:, -1], self.n
        return TangentFlow(
            y=z[:n].copy(),
            V=z[n : n + n * k].reshape(n, k).copy(),
            divergence_integral=float(z[-1]),
            steps=int(sol.nsteps),
            rejected=int(sol.info.get("rejected", 0)),
            evaluations=int(sol.nfev),
        )

    def integral_gradients(self, t: float, y: ArrayLike) -> NDArray[np.float64]:
        """Gradients of the model's first integrals (central differences, exact for quadrics).

        Parameters
        ----------
        t : float
            Time.
        y : array_like, shape (n,)
            State.

        Returns
        -------
        ndarray, shape (n_integrals, n)
            Row ``i`` is ``d integral_i / dy`` (``code.integral_names`` order).

        Raises
        ------
        UserInputError
            Wrong shape or non-finite state.
        """
        y = self._state(y)
        m = len(self.code.integral_names)
        if self.compiled:
            return self._integrator.integral_gradients(self.code, t, y, self.params)
        out = np.zeros((m, self.n))
        for j in range(self.n):
            h = np.cbrt(np.finfo(float).eps) * max(1.0, abs(y[j]))
            e = y.copy()
            e[j] = y[j] + h
            fp = np.asarray(self.code.numpy.integrals(t, e, self.params), dtype=float)
            e[j] = y[j] - h
            fm = np.asarray(self.code.numpy.integrals(t, e, self.params), dtype=float)
            out[:, j] = (fp - fm) / (2 * h)
        return out

    def level_set_basis(self, t: float, y: ArrayLike) -> tuple[NDArray, NDArray]:
        """Orthonormal bases of the normal and tangent spaces of the integrals' level set.

        Parameters
        ----------
        t : float
            Time.
        y : array_like, shape (n,)
            A state on the level set.

        Returns
        -------
        normal : ndarray, shape (n, r)
            Orthonormal basis of the span of the integrals' gradients (``r`` their rank).
        tangent : ndarray, shape (n, n - r)
            Orthonormal basis of its orthogonal complement (the level set's tangent space).

        Raises
        ------
        UserInputError
            Wrong shape or non-finite state.
        """
        return detlinalg.orthonormal_split(self.integral_gradients(t, y), rtol=1e-8)

    def renormalised(
        self,
        y0: ArrayLike,
        V0: ArrayLike,
        t0: float,
        tau: float,
        n_intervals: int,
        *,
        project: bool,
    ) -> tuple[NDArray, NDArray, NDArray, NDArray, dict[str, int]]:
        """Benettin's loop: integrate over ``n_intervals`` intervals of length ``tau``, each
        followed by a QR re-orthonormalisation of the tangent vectors.

        Parameters
        ----------
        y0 : array_like, shape (n,)
            Initial state.
        V0 : array_like, shape (n, k)
            Initial tangent vectors (orthonormalised by the first QR).
        t0, tau : float
            Start time and interval length (``tau > 0``).
        n_intervals : int
            Number of intervals.
        project : bool
            Project the tangent vectors onto the tangent space of the integrals' level set
            before each QR.

        Returns
        -------
        logs : ndarray, shape (n_intervals, k)
            ``log R_jj`` of each interval's QR (growth of the j-th Gram-Schmidt vector).
        divergence : ndarray, shape (n_intervals,)
            ``integral of div f dt`` over each interval.
        y : ndarray, shape (n,)
            The state at the end.
        V : ndarray, shape (n, k)
            The orthonormal tangent vectors at the end.
        work : dict of str to int
            ``steps``, ``rejected``, ``evaluations``.

        Raises
        ------
        UserInputError
            Bad shapes, ``tau <= 0`` or a negative count.
        ComputationError
            The integration failed.
        """
        y = self._state(y0)
        V = np.array(V0, dtype=np.float64)
        if V.ndim != 2 or V.shape[0] != self.n or not 1 <= V.shape[1] <= self.n:
            raise UserInputError(f"V0 must have shape ({self.n}, k) with 1 <= k <= {self.n}")
        if not float(tau) > 0:
            raise UserInputError(f"the renormalisation interval must be > 0, got {tau}")
        n_intervals = int(n_intervals)
        if n_intervals < 0:
            raise UserInputError("the number of intervals must be >= 0")
        k = V.shape[1]
        flow = VariationalFlow(self.code, k)
        plan = Renormalisation(
            float(tau), n_intervals, bool(project),
            normal_basis=lambda t, y: self.level_set_basis(t, y)[0],
        )  # fmt: skip
        sol = self._solve(
            self._problem(flow, flow.pack(y, V), (float(t0), float(t0)), renormalise=plan)
        )
        z, n = sol.y[:, -1], self.n
        work = {key: int(sol.info[key]) for key in ("steps", "rejected", "evaluations")}
        return (
            sol.info["logs"], sol.info["divergence"], z[:n].copy(),
            z[n : n + n * k].reshape(n, k).copy(), work,
        )  # fmt: skip


def variational_batch_available(code: ModelCode) -> bool:
    """Whether Benettin's loop for many points in one call can be built for ``code`` (a C
    compiler is present; see :func:`renormalised_many`).

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    bool
    """
    return batch_library(code) is not None


def renormalised_many(
    code: ModelCode,
    params: NDArray[np.float64],
    Z0: NDArray[np.float64],
    t0: NDArray[np.float64],
    tau: NDArray[np.float64],
    n_intervals: int,
    *,
    tangents: int,
    project: bool,
    rtol: float,
    atol: float,
    max_steps: int = DEFAULT_MAX_STEPS,
    lockstep: bool = True,
) -> Solution:
    """:meth:`VariationalSystem.renormalised` for ``N`` rows in one C call: row ``j``'s
    augmented state ``Z0[j] = (y, V, q)`` with parameters ``params[j]`` from ``t0[j]`` over
    ``n_intervals`` intervals of ``tau[j]``; four rows at a time in vector lanes where
    available, each row bit-identical to its own one-point run
    (:class:`~chaplygin.numerics.integrators.VariationalBatch`).

    Parameters
    ----------
    code : ModelCode
    params : ndarray, shape (N, n_param)
    Z0 : ndarray, shape (N, n + n k + 1)
    t0, tau : ndarray, shape (N,)
    n_intervals : int
    tangents : int
        ``k``.
    project : bool
        Project onto the level set's tangent space before each QR.
    rtol, atol : float
    max_steps : int
        Cap on the steps of one interval.
    lockstep : bool
        The vector lanes (else one row after another in the same call).

    Returns
    -------
    Solution
        ``y`` the augmented states at the end (N, n + n k + 1); ``info``: ``status`` (0 or a
        key of ``VARIATIONAL_STATUS``), ``logs`` (N, n_intervals, k), ``divergence``,
        ``steps``, ``rejected``, ``evaluations`` per row, ``lockstep``.

    Raises
    ------
    ComputationError
        No C compiler (:func:`variational_batch_available`).
    """
    taus, starts = (np.ascontiguousarray(v, dtype=np.float64) for v in (tau, t0))
    plan = Renormalisation(taus, int(n_intervals), bool(project), t0=starts)
    problem = Problem(VariationalBatch(code, tangents), np.ascontiguousarray(Z0), None,
                      np.ascontiguousarray(params, dtype=np.float64), _DOUBLE, float(rtol),
                      float(atol), options={"renormalise": plan, "lockstep": lockstep},
                      max_steps=int(max_steps))  # fmt: skip
    return INTEGRATORS["dop853"]().solve(problem)


@dataclass
class BenettinRuns:
    """What :func:`renormalised_after_transient` returns.

    Attributes
    ----------
    start : ndarray, shape (N, n + n k + 1)
        The augmented states the measured intervals start from (after the transient).
    t_start : ndarray, shape (N,)
        Their times.
    measured : Solution
        :func:`renormalised_many`'s solution over the measured intervals.
    status : ndarray of int, shape (N,)
        0, or the first failure of each row (transient or measured).
    failed_in_transient : ndarray of bool, shape (N,)
    work : ndarray of int, shape (N, 3)
        Accepted and rejected steps and evaluations of both calls.
    """

    start: NDArray[np.float64]
    t_start: NDArray[np.float64]
    measured: Solution
    status: NDArray[np.int32]
    failed_in_transient: NDArray[np.bool_]
    work: NDArray[np.int64]


def _work(info: dict) -> NDArray[np.int64]:
    return np.stack([info["steps"], info["rejected"], info["evaluations"]], axis=1)


def renormalised_after_transient(
    code: ModelCode,
    params: NDArray[np.float64],
    Z0: NDArray[np.float64],
    t0: NDArray[np.float64],
    tau: NDArray[np.float64],
    transient: int,
    intervals: int,
    **settings: Any,
) -> BenettinRuns:
    """Benettin's loop as the Lyapunov functions run it, for ``N`` rows: ``transient``
    intervals (their logs dropped), then ``intervals`` measured ones from where they got, the
    divergence integral reset (:func:`renormalised_many` twice; a row's measured run is its
    one-point :meth:`VariationalSystem.renormalised` from the same start, bit for bit).

    Parameters
    ----------
    code, params, Z0, t0, tau
        As :func:`renormalised_many`.
    transient, intervals : int
    **settings
        ``tangents``, ``project``, ``rtol``, ``atol``, ``max_steps``, ``lockstep`` of
        :func:`renormalised_many`.

    Returns
    -------
    BenettinRuns
    """
    Z, T = Z0, np.asarray(t0, dtype=np.float64)
    status = np.zeros(len(Z0), dtype=np.int32)
    work = np.zeros((len(Z0), 3), dtype=np.int64)
    if transient:
        first = renormalised_many(code, params, Z0, T, tau, transient, **settings)
        Z, status = first.y.copy(), first.info["status"].astype(np.int32)
        Z[:, -1] = 0.0
        work += _work(first.info)
        T = T + transient * np.asarray(tau, dtype=np.float64)
    in_transient = status != 0
    sol = renormalised_many(code, params, np.ascontiguousarray(Z), T, tau, intervals, **settings)
    status = np.where(in_transient, status, sol.info["status"]).astype(np.int32)
    work += _work(sol.info)
    return BenettinRuns(Z, T, sol, status, in_transient, work)


def variational_system(
    code: ModelCode, params: ArrayLike, *, rtol: float = 1e-10, atol: float = 1e-12
) -> VariationalSystem:
    """The variational equations of ``code`` at ``params`` (compiled on first use).

    Parameters
    ----------
    code : ModelCode
        The model's generated code.
    params : array_like, shape (n_param,)
        Parameter values in ``code.params`` order.
    rtol, atol : float
        Tolerances of the integrator.

    Returns
    -------
    VariationalSystem

    Raises
    ------
    UserInputError
        Wrong number of parameters, non-finite values or bad tolerances.
    """
    return VariationalSystem(code, params, rtol=rtol, atol=atol)


def flow_with_jacobian(
    code: ModelCode,
    params: Sequence[Any] | ArrayLike,
    y0: ArrayLike,
    t0: float,
    t1: float,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The flow from ``t0`` to ``t1`` and its state-transition matrix ``Phi = dy(t1)/dy(t0)``.

    Parameters
    ----------
    code : ModelCode
        The model's generated code.
    params : array_like, shape (n_param,)
        Parameter values in ``code.params`` order (converted to double).
    y0 : array_like, shape (n,)
        Initial state.
    t0, t1 : float
        The span.
    rtol, atol : float
        Tolerances (applied to the state and to ``Phi``).

    Returns
    -------
    y1 : ndarray, shape (n,)
        The state at ``t1``.
    Phi : ndarray, shape (n, n)
        ``Phi[i, j] = d y_i(t1) / d y_j(t0)``.

    Raises
    ------
    UserInputError
        Bad shapes, non-finite values or tolerances.
    ComputationError
        The integration failed.
    """
    res = VariationalSystem(code, params, rtol=rtol, atol=atol).flow(y0, t0, t1)
    return res.y, res.V


@dataclass
class FlowJacobians:
    """What :func:`flow_jacobians` returns.

    Attributes
    ----------
    y : ndarray, shape (N, n)
        The states at ``t0 + tau`` (NaN rows where a point failed).
    jacobians : ndarray, shape (N, n, n)
        ``Phi[j]``, the derivative of point ``j``'s flow (NaN where it failed).
    status : ndarray of int32, shape (N,)
        0 done, else a key of ``VARIATIONAL_STATUS``.
    messages : list of str
        Per point ``"done"`` or what failed.
    lockstep : bool
        Whether the vector lanes ran.
    """

    y: NDArray[np.float64]
    jacobians: NDArray[np.float64]
    status: NDArray[np.int32]
    messages: list[str]
    lockstep: bool


def flow_jacobians(
    code: ModelCode,
    params: ArrayLike,
    y0: ArrayLike,
    t0: ArrayLike,
    tau: ArrayLike,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    lockstep: bool = True,
    max_steps: int = DEFAULT_MAX_STEPS,
) -> FlowJacobians:
    """The flows of ``N`` points over ``[t0, t0 + tau]`` and their derivatives
    ``Phi = dy(t0 + tau)/dy(t0)`` (e.g. a stroboscopic map's Jacobians, ``tau = 2 pi/Omega``) in
    one C call: four points at a time in vector lanes where available, each point's state and
    ``Phi`` bit-identical to :func:`flow_with_jacobian` from ``t0`` to ``t0 + tau`` (the sum
    rounded as Python rounds it) on its own.

    Parameters
    ----------
    code : ModelCode
    params : array_like, shape (N, n_param)
        Parameters per point, in ``code.params`` order (double).
    y0 : array_like, shape (N, n)
        Initial states.
    t0, tau : float or array_like, shape (N,)
        Start times and lengths (``tau > 0``).
    rtol, atol : float
        Tolerances (applied to the state and to ``Phi``).
    lockstep : bool
        The vector lanes (else one point after another in the same call; the same bits).
    max_steps : int
        Cap on the steps of one point.

    Returns
    -------
    FlowJacobians

    Raises
    ------
    UserInputError
        Bad shapes, non-finite values, ``tau <= 0``.
    ComputationError
        No C compiler (the lanes need the compiled variational equations).
    """
    from ..integrators.dop853_c import VARIATIONAL_STATUS

    n = len(code.state)
    Y = check_rows(y0, "y0", n)
    P = check_rows(params, "params", len(code.params), len(Y))
    N = len(Y)
    T0, TAU = (check_rows(np.broadcast_to(_floats(v, k), (N,))[:, None], k, 1)[:, 0]
               for v, k in ((t0, "t0"), (tau, "tau")))  # fmt: skip
    if not (TAU > 0).all():
        raise UserInputError("tau must be > 0")
    if not variational_batch_available(code):
        raise ComputationError("flow_jacobians needs a C compiler (use flow_with_jacobian)")
    flow = VariationalFlow(code, n)
    Z0 = np.stack([flow.pack(Y[j], np.eye(n)) for j in range(N)])
    plan = Renormalisation(TAU, 1, False, t0=T0, orthonormalise=False)
    problem = Problem(VariationalBatch(code, n), Z0, None, P, _DOUBLE, float(rtol), float(atol),
                      options={"renormalise": plan, "lockstep": lockstep},
                      max_steps=int(max_steps))  # fmt: skip
    sol = INTEGRATORS["dop853"]().solve(problem)
    status = np.asarray(sol.info["status"], dtype=np.int32)
    Z = np.asarray(sol.y, dtype=np.float64).copy()
    Z[status != 0] = np.nan
    return FlowJacobians(
        y=Z[:, :n],
        jacobians=Z[:, n : n + n * n].reshape(N, n, n),
        status=status,
        messages=[VARIATIONAL_STATUS.get(int(s), f"status {s}") if s else "done" for s in status],
        lockstep=bool(sol.info.get("lockstep", False)),
    )


def _floats(value: object, name: str) -> NDArray[np.float64]:
    """``value`` (a number or an array of them) as float64, else UserInputError."""
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise UserInputError(f"{name} must be a number or an array of numbers") from None
