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

__all__ = ["FlowBranch", "FlowOrbit", "continue_flow_orbit", "refine_flow_orbit"]


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
    monodromy : ndarray, shape (n, n)
        ``Phi`` itself.
    """

    point: np.ndarray
    period: float
    residual: float
    tolerance: float
    converged: bool
    iterations: int
    multipliers: np.ndarray
    determinant: float
    monodromy: np.ndarray | None = None


def refine_flow_orbit(
    code: ModelCode,
    params: Sequence[Any],
    y0: Sequence[float],
    period: float,
    *,
    rtol: float = 1e-11,
    max_iterations: int = 20,
    levels: Sequence[float] | None = None,
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
    levels : sequence of float, optional
        The values the model's integrals must keep (default: theirs at ``y0``).

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

    phase, start = field(y), y.copy()
    levels = integrals(y) if levels is None else np.asarray(levels, dtype=float).reshape(-1)
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
        monodromy=Phi,
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


@dataclass
class FlowBranch:
    """A periodic orbit of an autonomous flow followed in one parameter
    (:func:`continue_flow_orbit`).

    Attributes
    ----------
    parameter : str
    values : ndarray, shape (m,)
        The parameter's values reached, the start first.
    orbits : list of FlowOrbit
        The refined orbit at each value.
    unit_tol : ndarray, shape (m,)
        How far above 1 a multiplier's modulus must be to count: ``sqrt(1000 rtol max(1,
        |Phi|))`` (a multiplier 1 of a Jordan block of size 2 moves by the square root of the
        perturbation of ``Phi``, whose entries are integrated to about ``rtol |Phi|``).
    stable : ndarray of bool, shape (m,)
        Every multiplier of modulus at most ``1 + unit_tol``.
    changes : list of tuple
        ``(a, b)``: consecutive values between which the stability changes.
    stopped : str
        ``"reached"`` or why the branch ends early.
    """

    parameter: str
    values: np.ndarray
    orbits: list
    unit_tol: np.ndarray
    stable: np.ndarray
    changes: list
    stopped: str

    @property
    def periods(self) -> np.ndarray:
        """The periods along the branch.

        Returns
        -------
        ndarray, shape (m,)
        """
        return np.array([o.period for o in self.orbits])


def continue_flow_orbit(
    code: ModelCode,
    params: Sequence[Any],
    orbit: FlowOrbit,
    parameter: str,
    to: float,
    steps: int,
    *,
    rtol: float = 1e-11,
    halvings: int = 4,
) -> FlowBranch:
    """Follow a refined periodic orbit of an autonomous flow from the parameter's value in
    ``params`` to ``to`` in ``steps`` equal steps: at each value the orbit predicted by the
    secant through the last two (the orbit itself at the first step) is refined by
    :func:`refine_flow_orbit` on the levels the start orbit's point has under the new value
    (every integral the model ships keeps that value: of a family of orbits, the one on those
    levels; the least-norm correction picks the orbit nearest the prediction among any that
    remain). A step that does not converge is halved (``halvings`` times at most) before
    the branch stops. The multipliers at every point tell where the stability changes.

    Parameters
    ----------
    code : ModelCode
        An autonomous model.
    params : sequence
        Parameter values in ``code.params`` order (the start).
    orbit : FlowOrbit
        The refined orbit at the start (:func:`refine_flow_orbit`).
    parameter : str
        The name of the parameter varied.
    to : float
        Its last value.
    steps : int
        Steps from the start to ``to`` (>= 1).
    rtol : float
        As for :func:`refine_flow_orbit`.
    halvings : int
        Times a failed step is halved before the branch stops.

    Returns
    -------
    FlowBranch

    Raises
    ------
    UserInputError
        An unknown parameter, ``steps < 1``, a value that is not finite.
    """
    from ...derive.errors import UserInputError
    from ..arguments import check_real

    if parameter not in code.params:
        raise UserInputError(
            f"{code.name} has no parameter {parameter!r} ({', '.join(code.params)})"
        )
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
        raise UserInputError(f"steps must be an integer >= 1, got {steps!r}")
    p = np.asarray([float(v) for v in params])
    index, start = code.params.index(parameter), float(p[code.params.index(parameter)])
    end = float(check_real(to, "to", double=True))
    reached = 0.0  # the fraction of the way from start to end reached
    values, orbits, stopped = [start], [orbit], "reached"
    while reached < 1.0:
        step, found = 1.0 / steps, None
        for _ in range(halvings + 1):
            fraction = min(1.0, reached + step)
            if fraction > 1.0 - 1e-9:
                fraction = 1.0
            value = end if fraction == 1.0 else start + fraction * (end - start)
            y, T = _predicted(values, orbits, value)
            q = p.copy()
            q[index] = value
            levels = np.asarray(code.numpy.integrals(0.0, orbit.point, q), float).reshape(-1)
            try:
                found = refine_flow_orbit(code, q, y, T, rtol=rtol, levels=levels)
            except ComputationError:
                found = None
            if found is not None and found.converged:
                break
            found, step = None, step / 2
        if found is None:
            stopped = (
                f"no convergence past {parameter} = {values[-1]:.12g} "
                f"(step halved {halvings} times)"
            )
            break
        reached = fraction
        values.append(value)
        orbits.append(found)
    unit = np.array([np.sqrt(1000 * rtol * max(1.0, float(np.max(np.abs(o.monodromy)))))
                     for o in orbits])  # fmt: skip
    stable = np.array(
        [float(np.max(np.abs(o.multipliers))) <= 1 + u for o, u in zip(orbits, unit, strict=True)]
    )
    changes = [
        (values[i], values[i + 1]) for i in range(len(values) - 1) if stable[i] != stable[i + 1]
    ]
    return FlowBranch(parameter, np.array(values), orbits, unit, stable, changes, stopped)


def _predicted(values: list, orbits: list, value: float) -> tuple[np.ndarray, float]:
    """The secant prediction of ``(point, period)`` at ``value`` from the last two orbits
    (the last orbit itself when there is one only)."""
    last = orbits[-1]
    if len(orbits) < 2:
        return last.point.copy(), last.period
    prev = orbits[-2]
    s = (value - values[-1]) / (values[-1] - values[-2])
    return last.point + s * (last.point - prev.point), last.period + s * (last.period - prev.period)
