"""Variational equations of a model: the flow with its state-transition matrix, in C.

The augmented system ``y' = f(t, y)``, ``V' = J(t, y) V``, ``q' = tr J(t, y)`` (``J`` the
generated Jacobian, ``q`` the integral of the divergence of the vector field) is integrated by
an adaptive DOP853 written in C (``numerics/templates/variational.c``) that is compiled
together with the model's emitted C source (``generated/<model>.c``: ``chaplygin_rhs`` and
``chaplygin_jac``), so the right-hand side and Jacobian are the generated ones and no Python
runs inside a step. The error of a step is measured on ``y`` and ``V`` together.
Double precision only.

Without a C compiler the same system is integrated by :func:`scipy.integrate.solve_ivp`
(``DOP853``) with the numpy module's ``rhs`` and ``jac``, after a warning.

Examples
--------
>>> from chaplygin.numerics.code import load_model_code
>>> code = load_model_code("chaplygin_ball")
>>> y1, Phi = flow_with_jacobian(code, [2, 3, 4, 1], [1, 0, 0, 0, 0.6, 0.8], 0, 1)
>>> Phi.shape
(6, 6)
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from typing import Any

import cffi
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..arith import detlinalg, detmath
from ..derive.errors import ComputationError, UserInputError
from .ccompile import CacheError, CompilerError, compile_c
from .code import ModelCode
from .compiled import CompilerUnavailableWarning

__all__ = ["VariationalSystem", "TangentFlow", "flow_with_jacobian", "variational_system"]

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

_STATUS = {
    1: "the step limit was reached (max_steps); raise it or loosen rtol",
    2: "the step size underflowed: the solution is probably singular here",
    3: "a non-finite value appeared in the state or the tangent vectors",
}

#: Default cap on the steps of one interval.
DEFAULT_MAX_STEPS = 1_000_000

_LIBRARIES: dict[str, Any] = {}


def _template() -> str:
    return resources.files("chaplygin.numerics").joinpath("templates/variational.c").read_text()


def _library(code: ModelCode) -> Any | None:
    """The compiled variational library of ``code`` (cached per process), or None."""
    if code.hash in _LIBRARIES:
        return _LIBRARIES[code.hash]
    source = code.c_source + "\n" + _template()
    try:
        path = compile_c(source)
        lib = _ffi.dlopen(str(path))
    except CacheError:  # cache directory problems are the user's to fix
        raise
    except (CompilerError, OSError) as exc:
        warnings.warn(
            f"compiled variational equations unavailable, using scipy's DOP853 with the numpy "
            f"module instead (slower): {exc}",
            CompilerUnavailableWarning,
            stacklevel=3,
        )
        lib = None
    _LIBRARIES[code.hash] = lib
    return lib


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
        self._lib = _library(code)

    @property
    def compiled(self) -> bool:
        """Whether the C integrator is used (else scipy's DOP853).

        Returns
        -------
        bool
        """
        return self._lib is not None

    def _state(self, y: ArrayLike) -> NDArray[np.float64]:
        y = np.array(y, dtype=np.float64).ravel()
        if y.shape != (self.n,):
            raise UserInputError(f"the state must have {self.n} components, got {y.size}")
        if not np.all(np.isfinite(y)):
            raise UserInputError("the state must be finite")
        return y

    def _pack(self, y: NDArray, V: NDArray) -> NDArray[np.float64]:
        k = V.shape[1]
        z = np.zeros(self.n + self.n * k + 1)
        z[: self.n] = y
        z[self.n : self.n + self.n * k] = V.ravel()
        return z

    def _raise(self, status: int, t: float) -> None:
        raise ComputationError(
            f"variational equations of {self.code.name} failed near t = {t:.6g}: "
            f"{_STATUS.get(status, f'status {status}')}"
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
        if self._lib is None:
            return self._flow_scipy(y, V, t0, t1)
        z = self._pack(y, V)
        stats = np.zeros(4)
        # no step size carried over from an earlier call: a result depends on its inputs only
        # (not on which points a sweep chunk ran before it)
        status = self._lib.chaplygin_var_flow(
            t0, t1, _ffi.from_buffer("double[]", z, True), k,
            _ffi.from_buffer("double[]", self.params), self.rtol, self.atol, self.max_steps,
            _ffi.from_buffer("double[]", stats, True),
        )  # fmt: skip
        if status:
            self._raise(status, t0)
        n = self.n
        return TangentFlow(
            y=z[:n].copy(),
            V=z[n : n + n * k].reshape(n, k).copy(),
            divergence_integral=float(z[-1]),
            steps=int(stats[0]),
            rejected=int(stats[1]),
            evaluations=int(stats[2]),
        )

    def _flow_scipy(self, y: NDArray, V: NDArray, t0: float, t1: float) -> TangentFlow:
        from scipy.integrate import solve_ivp

        n, k = self.n, V.shape[1]
        p = self.params
        rhs, jac = self.code.numpy.rhs, self.code.numpy.jac

        def f(t: float, z: NDArray) -> NDArray:
            J = np.asarray(jac(t, z[:n], p), dtype=np.float64)
            out = np.empty_like(z)
            out[:n] = rhs(t, z[:n], p)
            out[n:-1] = detlinalg.matmul(J, z[n:-1].reshape(n, k)).ravel()
            out[-1] = np.trace(J)
            return out

        z0 = self._pack(y, V)
        atol = np.full(z0.size, self.atol)
        atol[-1] = np.inf  # the quadrature is not error-controlled
        sol = solve_ivp(f, (t0, t1), z0, method="DOP853", rtol=self.rtol, atol=atol)
        if not sol.success:
            raise ComputationError(f"variational equations of {self.code.name}: {sol.message}")
        z = sol.y[:, -1]
        return TangentFlow(
            y=z[:n].copy(),
            V=z[n:-1].reshape(n, k).copy(),
            divergence_integral=float(z[-1]),
            steps=int(sol.t.size - 1),
            rejected=0,
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
        if self._lib is not None:
            out = np.zeros((max(m, 1), self.n))
            self._lib.chaplygin_var_integral_gradients(
                float(t), _ffi.from_buffer("double[]", y),
                _ffi.from_buffer("double[]", self.params), _ffi.from_buffer("double[]", out, True),
            )  # fmt: skip
            return out[:m]
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
        logs = np.zeros((n_intervals, k))
        divs = np.zeros(n_intervals)
        if self._lib is None:
            return self._renormalised_python(y, V, float(t0), float(tau), logs, divs, project)
        z = self._pack(y, V)
        stats = np.zeros(4)
        # no step size carried over from an earlier call: a result depends on its inputs only
        # (not on which points a sweep chunk ran before it)
        status = self._lib.chaplygin_var_renormalised(
            float(t0), float(tau), n_intervals, _ffi.from_buffer("double[]", z, True), k,
            _ffi.from_buffer("double[]", self.params), self.rtol, self.atol, int(bool(project)),
            self.max_steps, _ffi.from_buffer("double[]", logs, True),
            _ffi.from_buffer("double[]", divs, True), _ffi.from_buffer("double[]", stats, True),
        )  # fmt: skip
        if status:
            self._raise(status, float(t0))
        n = self.n
        work = {"steps": int(stats[0]), "rejected": int(stats[1]), "evaluations": int(stats[2])}
        return logs, divs, z[:n].copy(), z[n : n + n * k].reshape(n, k).copy(), work

    def _renormalised_python(
        self,
        y: NDArray,
        V: NDArray,
        t0: float,
        tau: float,
        logs: NDArray,
        divs: NDArray,
        project: bool,
    ) -> tuple[NDArray, NDArray, NDArray, NDArray, dict[str, int]]:
        work = {"steps": 0, "rejected": 0, "evaluations": 0}
        for i in range(logs.shape[0]):
            tb = t0 + (i + 1) * tau
            res = self._flow_scipy(y, V, t0 + i * tau, tb)
            y, V = res.y, res.V
            divs[i] = res.divergence_integral
            work["steps"] += res.steps
            work["evaluations"] += res.evaluations
            if project:
                normal, _ = self.level_set_basis(tb, y)
                V = V - detlinalg.matmul(normal, detlinalg.matmul(normal.T, V))
            V, R = detlinalg.qr(V)
            logs[i] = detmath.log(np.diag(R).copy())
        return logs, divs, y, V, work


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
