"""Hairer's DOP853 written in C, for the variational equations and the batches.

``derive/templates/variational.c`` is compiled with the model's emitted C source
(``chaplygin_rhs_jac``: the right-hand side and Jacobian in one routine): the augmented system of a
:class:`~chaplygin.numerics.integrators.flows.VariationalFlow` is integrated with no Python
inside a step, the error of a step measured on the state and the tangent vectors together,
optionally with Benettin's QR renormalisation after each of equal intervals (a
:class:`~chaplygin.numerics.integrators.flows.Renormalisation`). Without a C compiler the
same system runs on scipy's ``DOP853`` with the numpy module's ``rhs`` and ``jac`` (backend
``numpy``), after a warning. ``derive/templates/batch_map.c`` advances a
:class:`~chaplygin.numerics.integrators.flows.Batch` of a time-periodic model
(:mod:`~chaplygin.numerics.integrators.c_batch`). Double precision only.

References
----------
E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I, II.5 and
II.10 (DOP853).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import cffi
import numpy as np

from ...arith import detlinalg, detmath
from ...derive.emit.c_sources import variational_source
from ...derive.errors import ComputationError, UserInputError
from ..ccompile import compile_c
from ..code import ModelCode
from . import c_batch
from .base import Integrator, Problem, Solution
from .flows import Batch, Renormalisation, VariationalBatch, VariationalFlow
from .scipy_methods import DOP853

__all__ = ["CompiledDOP853", "variational_library", "VARIATIONAL_STATUS"]

_CDEF = """
int chaplygin_var_flow(double t0, double t1, double *z, int k, const double *P, double rtol,
                       double atol, long max_steps, double *stats);
int chaplygin_var_renormalised(double t0, double tau, long n_intervals, double *z, int k,
                               const double *P, double rtol, double atol, int project,
                               long max_steps, double *logs, double *divs, double *stats);
void chaplygin_var_integral_gradients(double t, const double *y, const double *P, double *out);
int chaplygin_var_normal_rank(double t, const double *y, const double *P);
void chaplygin_integrals(double T, const double *Y, const double *P, double *OUT);
"""

_ffi = cffi.FFI()
_ffi.cdef(_CDEF)

#: Meaning of the C integrator's status.
VARIATIONAL_STATUS = {
    1: "the step limit was reached (max_steps); raise it or loosen rtol",
    2: "the step size underflowed: the solution is probably singular here",
    3: "a non-finite value appeared in the state or the tangent vectors",
}
#: The C status as the integrators' (-2 step limit, -3 step-size underflow, -1 non-finite).
_STATUS = {1: -2, 2: -3, 3: -1}

_LIBRARIES: dict[str, Any] = {}


def variational_library(code: ModelCode) -> Any | None:
    """The compiled variational library of ``code``
    (:func:`~chaplygin.numerics.integrators.c_batch.cached_library`).

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    cffi library or None
    """

    def build() -> Any:
        return _ffi.dlopen(str(compile_c(variational_source(code.c_source))))

    return c_batch.cached_library(
        _LIBRARIES, code, build,
        "compiled variational equations unavailable, using scipy's DOP853 with the numpy "
        "module instead (slower): {exc}",
    )  # fmt: skip


class CompiledDOP853(Integrator):
    """DOP853 in C on the variational equations and on batches of a time-periodic model.

    ``y0`` of a variational problem is ``z = (y, V, 0)``
    (:meth:`~chaplygin.numerics.integrators.flows.VariationalFlow.pack`); its solution is
    ``z`` at the end, the work counters in ``info`` (``steps``, ``rejected``,
    ``evaluations``) and, with ``options["renormalise"]``, the logarithms of the QR
    diagonals (``info["logs"]``) and each interval's divergence integral
    (``info["divergence"]``). A batch's solution is described in
    :func:`~chaplygin.numerics.integrators.c_batch.run_batch`; ``options["lockstep"]``
    (default True) advances 4 points at a time in vector lanes where available. A
    :class:`~chaplygin.numerics.integrators.flows.VariationalBatch` runs Benettin's loop for
    every row (:func:`~chaplygin.numerics.integrators.c_batch.run_variational_batch`, 4 rows at
    a time in vector lanes where the Jacobian has them, bit-identical to one row at a time):
    ``y`` the augmented states at the end (N, n + n k + 1), ``info`` per row ``status`` (0 or
    a key of :data:`VARIATIONAL_STATUS`), ``logs``, ``divergence``, ``steps``, ``rejected``,
    ``evaluations``, and ``lockstep``.
    """

    name = "dop853"
    flows = (VariationalFlow, Batch, VariationalBatch)
    precisions = ("double",)
    backends = ("c", "numpy")
    rtol_floor = {"double": 100.0}

    def __init__(self) -> None:
        # the variational libraries this instance prepared, kept for its later solves
        self._libraries: dict[str, Any] = {}

    def _library(self, code: ModelCode) -> Any | None:
        if code.hash not in self._libraries:
            self._libraries[code.hash] = variational_library(code)
        return self._libraries[code.hash]

    def integral_gradients(
        self, code: ModelCode, t: float, y: np.ndarray, P: np.ndarray
    ) -> np.ndarray:
        """Gradients of the model's first integrals from the compiled variational library
        (prepared for ``code``).

        Parameters
        ----------
        code : ModelCode
        t : float
        y : ndarray, shape (n,)
        P : ndarray, shape (n_param,)

        Returns
        -------
        ndarray, shape (n_integrals, n)
        """
        m, n = len(code.integral_names), len(code.state)
        out = np.zeros((max(m, 1), n))
        self._library(code).chaplygin_var_integral_gradients(
            float(t), _ffi.from_buffer("double[]", y), _ffi.from_buffer("double[]", P),
            _ffi.from_buffer("double[]", out, True),
        )  # fmt: skip
        return out[:m]

    def _prepare(self, problem: Problem, backend: str) -> str:
        code = problem.code
        if isinstance(problem.system, Batch | VariationalBatch):
            if c_batch.batch_library(code) is None:
                raise ComputationError(
                    "the batches need a C compiler (the Taylor one also the model's generated "
                    "Taylor code); use StroboscopicMap or lyapunov_spectrum per point"
                )
            return "c"
        if backend == "numpy":
            return "numpy"
        if self._library(code) is None:
            if backend == "c":
                raise UserInputError("backend 'c' needs a C compiler (install gcc or set CC)")
            return "numpy"
        return "c"

    def _solve(self, problem: Problem, backend: str) -> Solution:
        if isinstance(problem.system, Batch):
            return self._batch(problem)
        if isinstance(problem.system, VariationalBatch):
            return self._variational_batch(problem)
        renormalise = problem.options.get("renormalise")
        if backend == "numpy":
            if renormalise is not None:
                return _renormalised_numpy(problem, renormalise)
            return DOP853().solve(problem, chosen="numpy")
        if renormalise is not None:
            return self._renormalised(problem, renormalise)
        return self._flow(problem)

    @staticmethod
    def _batch(problem: Problem) -> Solution:
        lib = c_batch.batch_library(problem.code)
        lockstep = (
            problem.options.get("lockstep", True)
            and c_batch.lockstep_available(problem.code)
            and len(problem.y0) > 1
        )
        driver = lib.chaplygin_batch_map_lockstep if lockstep else lib.chaplygin_batch_map
        sol, stats = c_batch.run_batch(driver, problem)
        sol.info.update(
            steps=stats[:, 0].astype(np.int64),
            rejected=stats[:, 1].astype(np.int64),
            evaluations=stats[:, 2].astype(np.int64),
            lockstep=lockstep,
        )
        sol.nsteps = int(stats[:, 0].sum())
        sol.nfev = int(stats[:, 2].sum())
        return sol

    @staticmethod
    def _variational_batch(problem: Problem) -> Solution:
        code = problem.code
        lockstep = (
            problem.options.get("lockstep", True)
            and c_batch.variational_lockstep_available(code)
            and len(problem.y0) > 1
        )
        Z, info = c_batch.run_variational_batch(c_batch.batch_library(code), problem, lockstep)
        stats = info.pop("stats")
        info.update(
            steps=stats[:, 0].astype(np.int64),
            rejected=stats[:, 1].astype(np.int64),
            evaluations=stats[:, 2].astype(np.int64),
            lockstep=lockstep,
        )
        return Solution(
            t=None, y=Z, status=0, message="done", nfev=int(stats[:, 2].sum()),
            nsteps=int(stats[:, 0].sum()), info=info,
        )  # fmt: skip

    def _flow(self, problem: Problem) -> Solution:
        lib = self._library(problem.code)
        z = np.array(problem.y0, dtype=np.float64)
        P = np.asarray(problem.params, dtype=np.float64)
        stats = np.zeros(4)
        t0, t1 = (float(v) for v in problem.t_span)
        # no step size carried over from an earlier call: a result depends on its inputs only
        # (not on which points a sweep chunk ran before it)
        status = lib.chaplygin_var_flow(
            t0, t1, _ffi.from_buffer("double[]", z, True), problem.system.tangents,
            _ffi.from_buffer("double[]", P), problem.rtol, problem.atol,
            _max_steps(problem), _ffi.from_buffer("double[]", stats, True),
        )  # fmt: skip
        return _variational_solution(np.array([t1]), z, status, stats)

    def _renormalised(self, problem: Problem, plan: Renormalisation) -> Solution:
        lib = self._library(problem.code)
        z = np.array(problem.y0, dtype=np.float64)
        P = np.asarray(problem.params, dtype=np.float64)
        k = problem.system.tangents
        logs = np.zeros((plan.intervals, k))
        divs = np.zeros(plan.intervals)
        stats = np.zeros(4)
        t0 = float(problem.t_span[0])
        # no step size carried over from an earlier call (as _flow)
        status = lib.chaplygin_var_renormalised(
            t0, float(plan.tau), plan.intervals, _ffi.from_buffer("double[]", z, True), k,
            _ffi.from_buffer("double[]", P), problem.rtol, problem.atol, int(bool(plan.project)),
            _max_steps(problem), _ffi.from_buffer("double[]", logs, True),
            _ffi.from_buffer("double[]", divs, True), _ffi.from_buffer("double[]", stats, True),
        )  # fmt: skip
        sol = _variational_solution(np.array([t0 + plan.intervals * plan.tau]), z, status, stats)
        sol.info.update(logs=logs, divergence=divs)
        return sol


def _max_steps(problem: Problem) -> int:
    return int(problem.max_steps) if problem.max_steps is not None else 1_000_000


def _variational_solution(t: np.ndarray, z: np.ndarray, status: int, stats: np.ndarray
                          ) -> Solution:
    steps, rejected, evaluations = (int(v) for v in stats[:3])
    return Solution(
        t=t,
        y=z.reshape(-1, 1),
        status=_STATUS.get(status, -status) if status else 0,
        message=VARIATIONAL_STATUS.get(status, f"status {status}") if status else "reached t_end",
        nfev=evaluations,
        nsteps=steps,
        info={"steps": steps, "rejected": rejected, "evaluations": evaluations},
    )


def _renormalised_numpy(problem: Problem, plan: Renormalisation) -> Solution:
    """Benettin's loop without the compiled library: each interval by scipy's DOP853, then the
    projection (``plan.normal_basis``) and the QR in Python (:mod:`~chaplygin.arith.detlinalg`)."""
    flow, t0, tau = problem.system, float(problem.t_span[0]), float(plan.tau)
    n, k = len(problem.code.state), flow.tangents
    z = np.array(problem.y0, dtype=np.float64)
    y, V = z[:n].copy(), z[n : n + n * k].reshape(n, k).copy()
    logs, divs = np.zeros((plan.intervals, k)), np.zeros(plan.intervals)
    work = {"steps": 0, "rejected": 0, "evaluations": 0}
    for i in range(plan.intervals):
        tb = t0 + (i + 1) * tau
        interval = dataclasses.replace(
            problem, y0=flow.pack(y, V), t_span=(t0 + i * tau, tb), options={}
        )
        sol = DOP853().solve(interval, chosen="numpy")
        if sol.status:
            return sol
        zi = sol.y[:, -1]
        y, V = zi[:n].copy(), zi[n:-1].reshape(n, k).copy()
        divs[i] = float(zi[-1])
        work["steps"] += sol.nsteps
        work["evaluations"] += sol.nfev
        if plan.project:
            normal = plan.normal_basis(tb, y)
            V = V - detlinalg.matmul(normal, detlinalg.matmul(normal.T, V))
        V, R = detlinalg.qr(V)
        logs[i] = detmath.log(np.diag(R).copy())
    return Solution(
        t=np.array([t0 + plan.intervals * tau]),
        y=flow.pack(y, V).reshape(-1, 1),
        status=0,
        message="reached t_end",
        nfev=work["evaluations"],
        nsteps=work["steps"],
        info={**work, "logs": logs, "divergence": divs},
    )
