"""Periodic orbits of an autonomous flow: ``phi_T(y) = y`` refined by Newton's method.

The unknowns are the state ``y`` and the period ``T``; the equations are ``phi_T(y) - y = 0``,
the phase condition ``(f(y_0), y - y_0) = 0`` (the correction is orthogonal to the flow at
the start, as AUTO and MatCont fix the phase) and ``F_j(y) = F_j(y_0)`` for every integral
the model ships (the orbit stays on the start's level: the energy, ``|gamma|`` ...). The
Jacobian is ``[[Phi - I, f(phi_T(y))], [f(y_0)^T, 0], [grad F_j^T, 0]]`` with ``Phi = d
phi_T / dy`` from the variational equations
(:func:`chaplygin.numerics.dynamics.variational.flow_with_jacobian`, the generated Jacobian)
and ``grad F_j`` by central differences of the generated integrals. An integrable system's
periodic orbits still come in families (each integral not shipped adds a multiplier 1), so
the Jacobian may be singular: the step solves the Levenberg-Marquardt equations ``(J^T J +
mu I) d = -J^T r`` with a small ``mu`` (the least-norm correction along the family), in
:mod:`chaplygin.arith.detlinalg` (the same bits on every machine).

The Floquet multipliers are the eigenvalues of ``Phi`` at the refined orbit; one of them is 1
(the flow's direction) and each independent first integral adds one.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...arith import detlinalg
from ...derive.errors import ComputationError
from ..code import ModelCode

__all__ = ["FlowOrbit", "refine_flow_orbit"]


@dataclass
class FlowOrbit:
    """A periodic orbit of an autonomous flow.

    Attributes
    ----------
    point : ndarray, shape (n,)
        A state on the orbit.
    period : float
        Its period (model time).
    residual : float
        ``max |phi_T(y) - y|`` at the refined orbit.
    tolerance : float
        What the residual had to reach: ``1000 rtol max(1, |y|)``.
    converged : bool
    iterations : int
        Newton steps taken.
    multipliers : ndarray, shape (n,)
        Eigenvalues of the monodromy matrix ``Phi``, by decreasing modulus.
    determinant : float
        ``det Phi`` (``exp`` of the divergence integrated over a period: 1 where the flow
        keeps an invariant density).
    """

    point: np.ndarray
    period: float
    residual: float
    tolerance: float
    converged: bool
    iterations: int
    multipliers: np.ndarray
    determinant: float


def refine_flow_orbit(
    code: ModelCode,
    params: Sequence[Any],
    y0: Sequence[float],
    period: float,
    *,
    rtol: float = 1e-11,
    max_iterations: int = 20,
) -> FlowOrbit:
    """Newton's method on ``phi_T(y) = y`` from ``(y0, period)`` (see the module).

    Parameters
    ----------
    code : ModelCode
        An autonomous model.
    params : sequence
        Parameter values in ``code.params`` order.
    y0 : sequence of float
        A state near the orbit.
    period : float
        Its period, approximately (> 0).
    rtol : float
        Tolerance of the variational integration (also the scale of the acceptance).
    max_iterations : int

    Returns
    -------
    FlowOrbit

    Raises
    ------
    ComputationError
        The integration failed.
    """
    from ..dynamics.variational import flow_with_jacobian

    p = np.asarray([float(v) for v in params])
    y = np.asarray([float(v) for v in y0])
    T = float(period)
    n = len(y)
    tol = 1000 * rtol * max(1.0, detlinalg.norm(y))

    def field(state):
        return np.asarray(code.numpy.rhs(0.0, state, p), dtype=float)

    def integrals(state):
        return np.asarray(code.numpy.integrals(0.0, state, p), dtype=float).reshape(-1)

    phase, start, levels = field(y), y.copy(), integrals(y)
    r_count = len(levels)
    steps = 0
    while True:
        y1, Phi = flow_with_jacobian(code, p, y, 0.0, T, rtol=rtol, atol=rtol)
        residual = float(np.max(np.abs(y1 - y)))
        if residual <= tol or steps >= max_iterations:
            break
        r = np.concatenate([y1 - y, [phase @ (y - start)], integrals(y) - levels])
        J = np.zeros((n + 1 + r_count, n + 1))
        J[:n, :n] = Phi - np.eye(n)
        J[:n, n] = field(y1)
        J[n, :n] = phase
        J[n + 1 :, :n] = _integral_gradients(integrals, y)
        normal = detlinalg.matmul(J.T, J)  # (n + 1) x (n + 1)
        mu = 1e-12 * float(np.trace(normal)) / (n + 1)
        d = detlinalg.solve(normal + mu * np.eye(n + 1), -detlinalg.matmul(J.T, r))
        y, T, steps = y + d[:n], T + float(d[n]), steps + 1
        if not (np.all(np.isfinite(y)) and np.isfinite(T) and T > 0):
            raise ComputationError("Newton's method on phi_T(y) = y left the finite states")
    values = detlinalg.eigvals(Phi)
    order = np.argsort(-np.abs(values), kind="stable")
    return FlowOrbit(
        point=y,
        period=T,
        residual=residual,
        tolerance=tol,
        converged=residual <= tol,
        iterations=steps,
        multipliers=values[order],
        determinant=float(np.real(np.prod(values))),
    )


def _integral_gradients(integrals, y: np.ndarray) -> np.ndarray:
    """Central differences of the generated integrals, one row per integral."""
    h = 1e-6 * max(1.0, float(np.max(np.abs(y))))
    columns = []
    for j in range(len(y)):
        e = np.zeros(len(y))
        e[j] = h
        columns.append((integrals(y + e) - integrals(y - e)) / (2 * h))
    return np.array(columns).T
