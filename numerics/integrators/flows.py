"""The right-hand sides a :class:`~chaplygin.numerics.integrators.Problem` integrates.

Everything the project integrates is one of these, made from a model's generated code:

* :class:`ModelFlow` -- the model's own equations ``y' = f(t, y)``;
* :class:`ReversedFlow` -- the same flow backward in time, ``y'(s) = -f(-s, y)`` with
  ``s = -t`` (what a method that only runs forward integrates for a backward span);
* :class:`VariationalFlow` -- the state with ``k`` tangent vectors and the integral of the
  divergence, ``z = (y, V, q)``: ``y' = f``, ``V' = J V``, ``q' = tr J`` (``J`` the generated
  Jacobian);
* :class:`Batch` -- many copies of a flow, each with its own state and parameters (a
  problem's ``y0`` and ``params`` have one row per copy);
* :class:`VariationalBatch` -- many copies of the variational equations, each with its own
  augmented state, parameters, start time and renormalisation interval.

An :class:`~chaplygin.numerics.integrators.Integrator` names the flows it integrates
(``flows``); the flows give the scipy and mpmath methods their right-hand sides.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import mpmath
import numpy as np

from ...arith import detlinalg
from ..code import ModelCode

__all__ = [
    "Flow",
    "ModelFlow",
    "ReversedFlow",
    "VariationalFlow",
    "Batch",
    "VariationalBatch",
    "StroboscopicTimes",
    "Renormalisation",
]


@dataclass(frozen=True)
class Flow:
    """Base of the right-hand sides: the model whose generated code they are made from.

    Attributes
    ----------
    code : ModelCode
    """

    code: ModelCode

    #: How messages name the flow.
    what: ClassVar[str] = "a flow"

    @property
    def state_names(self) -> tuple[str, ...]:
        """Names of the integrated components (the model's state, for the flows of it)."""
        return tuple(self.code.state)

    def double_rhs(self, backend: str) -> tuple[Callable, Callable | None]:
        """``(f(t, y, p), jac(t, y, p) or None)`` in double precision, on the compiled model
        (``backend="c"``) or the numpy module (``"numpy"``).

        Parameters
        ----------
        backend : {"c", "numpy"}

        Returns
        -------
        (callable, callable or None)
        """
        raise NotImplementedError  # pragma: no cover

    def mpmath_rhs(self) -> Callable:
        """``f(t, y, p)`` on mpmath numbers (lists).

        Returns
        -------
        callable
        """
        raise NotImplementedError  # pragma: no cover

    def atol(self, atol: float, size: int) -> float | np.ndarray:
        """The absolute tolerance of each component (``atol`` for all, by default).

        Parameters
        ----------
        atol : float
        size : int
            Number of components.

        Returns
        -------
        float or ndarray
        """
        return atol


def _library(code: ModelCode, backend: str) -> Any:
    return code.compiled() if backend == "c" else code.numpy


@dataclass(frozen=True)
class ModelFlow(Flow):
    """The model's own equations ``y' = f(t, y)``."""

    what: ClassVar[str] = "a model's own equations"

    def double_rhs(self, backend: str) -> tuple[Callable, Callable | None]:
        """The generated ``rhs`` and ``jac`` (compiled or numpy).

        Parameters
        ----------
        backend : {"c", "numpy"}

        Returns
        -------
        (callable, callable or None)
        """
        lib = _library(self.code, backend)
        return lib.rhs, lib.jac

    def mpmath_rhs(self) -> Callable:
        """The generated mpmath ``rhs``.

        Returns
        -------
        callable
        """
        return self.code.mpmath.rhs


@dataclass(frozen=True)
class ReversedFlow(Flow):
    """The model's flow backward in time: ``y'(s) = -f(-s, y)``, ``s = -t``, so that the
    state at ``s`` is the model's state at ``t = -s``."""

    what: ClassVar[str] = "a model's reversed flow"

    def double_rhs(self, backend: str) -> tuple[Callable, Callable | None]:
        """``-f(-s, y)`` and ``-J(-s, y)`` from the generated ``rhs`` and ``jac``.

        Parameters
        ----------
        backend : {"c", "numpy"}

        Returns
        -------
        (callable, callable or None)
        """
        lib = _library(self.code, backend)
        rhs, jac = lib.rhs, lib.jac

        def reversed_rhs(s, y, p):
            return -np.asarray(rhs(-s, y, p), dtype=float)

        def reversed_jac(s, y, p):
            return -np.asarray(jac(-s, y, p), dtype=float)

        return reversed_rhs, reversed_jac

    def mpmath_rhs(self) -> Callable:
        """``-f(-s, y)`` from the generated mpmath ``rhs``.

        Returns
        -------
        callable
        """
        rhs = self.code.mpmath.rhs

        def reversed_rhs(s, y, p):
            return [-v for v in rhs(-s, y, p)]

        return reversed_rhs


@dataclass(frozen=True)
class VariationalFlow(Flow):
    """The variational equations: ``z = (y, V, q)`` with ``y' = f(t, y)``,
    ``V' = J(t, y) V`` (``k`` tangent vectors, ``V`` row by row) and ``q' = tr J(t, y)``
    (the integral of the divergence, not error-controlled).

    Attributes
    ----------
    code : ModelCode
    tangents : int
        ``k``, the number of tangent vectors (1..n).
    """

    tangents: int = 1
    what: ClassVar[str] = "variational equations"

    @property
    def state_names(self) -> tuple[str, ...]:
        n, k = len(self.code.state), self.tangents
        return (
            *self.code.state,
            *(f"V{i}{j}" for i in range(n) for j in range(k)),
            "div_integral",
        )

    def pack(self, y: np.ndarray, V: np.ndarray) -> np.ndarray:
        """``z = (y, V, 0)`` as one vector.

        Parameters
        ----------
        y : ndarray, shape (n,)
        V : ndarray, shape (n, k)

        Returns
        -------
        ndarray, shape (n + n k + 1,)
        """
        n, k = len(y), V.shape[1]
        z = np.zeros(n + n * k + 1)
        z[:n] = y
        z[n : n + n * k] = V.ravel()
        return z

    def double_rhs(self, backend: str) -> tuple[Callable, Callable | None]:
        """The augmented system on the numpy module's ``rhs`` and ``jac`` (``J V`` by
        :func:`~chaplygin.arith.detlinalg.matmul`); no Jacobian of it (the compiled one is the
        C DOP853's).

        Parameters
        ----------
        backend : {"c", "numpy"}

        Returns
        -------
        (callable, callable or None)
        """
        # the numpy module's rhs and jac (the compiled variational code is the C DOP853's)
        n, k = len(self.code.state), self.tangents
        rhs, jac = self.code.numpy.rhs, self.code.numpy.jac

        def f(t, z, p):
            J = np.asarray(jac(t, z[:n], p), dtype=np.float64)
            out = np.empty_like(z)
            out[:n] = rhs(t, z[:n], p)
            out[n:-1] = detlinalg.matmul(J, z[n:-1].reshape(n, k)).ravel()
            out[-1] = np.trace(J)
            return out

        return f, None

    def atol(self, atol: float, size: int) -> np.ndarray:
        """``atol`` for the state and the tangent vectors, none for the divergence integral.

        Parameters
        ----------
        atol : float
        size : int

        Returns
        -------
        ndarray
        """
        out = np.full(size, atol)
        out[-1] = np.inf  # the quadrature is not error-controlled
        return out


@dataclass(frozen=True)
class Batch(Flow):
    """Many copies of a flow, each with its own initial state and parameter vector (a
    problem's ``y0`` has shape ``(N, n_state)`` and its ``params`` ``(N, n_param)``).

    Attributes
    ----------
    code : ModelCode
    member : str
        The flow of each copy: ``"model"`` (the model's own equations; the batches the
        project integrates).
    """

    member: str = "model"
    what: ClassVar[str] = "a batch of a model's equations"


@dataclass(frozen=True)
class VariationalBatch(Flow):
    """Many copies of a :class:`VariationalFlow` with ``tangents`` tangent vectors each: a
    problem's ``y0`` has shape ``(N, n + n k + 1)`` (the augmented states ``(y, V, q)``, one
    row per copy) and its ``params`` ``(N, n_param)``; its ``options["renormalise"]`` is a
    :class:`Renormalisation` with one ``tau`` and one ``t0`` per copy.

    Attributes
    ----------
    code : ModelCode
    tangents : int
        ``k`` (1..n).
    """

    tangents: int = 1
    what: ClassVar[str] = "a batch of variational equations"


@dataclass(frozen=True)
class StroboscopicTimes:
    """Output times of a batch of a time-periodic model: point ``j`` at
    ``t0_j + (transient + k) tau_j``, ``k = 0 .. count - 1``, ``tau_j = 2 pi/Omega_j`` (a
    problem's ``t_eval``).

    Attributes
    ----------
    t0 : ndarray, shape (N,)
        Phase of each point's section.
    transient : int
        Periods before the first output.
    count : int
        Outputs per point.
    """

    t0: np.ndarray
    transient: int
    count: int

    @staticmethod
    def periods(omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``tau = 2 pi/Omega`` of every point as a double-double ``tau_hi + tau_lo`` (from
        40 digits), so that the sampling times carry no accumulated rounding.

        Parameters
        ----------
        omega : ndarray, shape (N,)

        Returns
        -------
        (ndarray, ndarray)
        """
        tau_hi, tau_lo = np.empty(len(omega)), np.empty(len(omega))
        with mpmath.workdps(40):
            for j, w in enumerate(omega):
                tau = 2 * mpmath.pi / mpmath.mpf(float(w))
                tau_hi[j] = float(tau)
                tau_lo[j] = float(tau - mpmath.mpf(tau_hi[j]))
        return tau_hi, tau_lo


@dataclass(frozen=True)
class Renormalisation:
    """Benettin's loop on a :class:`VariationalFlow` (a problem's ``options["renormalise"]``):
    ``intervals`` intervals of length ``tau`` from ``t_span[0]``, each followed by a QR
    re-orthonormalisation of the tangent vectors, projected first onto the tangent space of
    the integrals' level set when ``project`` is set.

    Attributes
    ----------
    tau : float, or ndarray of shape (N,) for a :class:`VariationalBatch`
    intervals : int
    project : bool
    normal_basis : callable or None
        ``(t, y) -> orthonormal basis (n, r)`` of the integrals' gradients, for a method that
        projects in Python (the compiled one has its own).
    t0 : ndarray of shape (N,), or None
        A :class:`VariationalBatch`'s start times (one problem starts at ``t_span[0]``).
    orthonormalise : bool
        False: no projection and no QR (a :class:`VariationalBatch` only): the tangent
        vectors at the end are the flow's derivative applied to the initial ones.
    """

    tau: float | np.ndarray
    intervals: int
    project: bool
    normal_basis: Callable[[float, np.ndarray], np.ndarray] | None = None
    t0: np.ndarray | None = None
    orthonormalise: bool = True
