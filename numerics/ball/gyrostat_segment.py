"""The segment of K01 §4 with the gyrostat: on M + K || gamma the states of a given
C = |M + K| form a segment of the sphere of gamma; its equilibria (steady rotations),
the gradient lines of the energy on it along which the trace's period is followed, and the
energy where the trace's turning changes sign.

References
----------
K01-4.4, K01 §4 (FORMULAS.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from scipy.optimize import brentq

from ...arith import detlinalg
from ...derive.errors import UserInputError
from ..arguments import check_real
from ..code import load_model_code
from .trace_geometry import (
    LINE_FLAT,
    LINE_STEP,
    SYSTEM,
    _check_body,
    _segment_energy,
    _unit_vector,
    trace_period,
)

__all__ = ["gradient_line", "segment_equilibria", "turning_critical_energy"]


def _tangent_basis(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    e = np.zeros(3)
    e[int(np.argmin(np.abs(g)))] = 1.0
    u = e - g * detlinalg.dot(e, g)
    u = u / detlinalg.norm(u)
    return u, np.cross(g, u)


def _sphere_gradient(I, D, K, C, g: np.ndarray) -> np.ndarray:
    """Tangential gradient of the segment energy at unit ``g``.

    On ``|gamma| = 1`` the energy is ``h = (M, omega)/2 = (M, W(gamma) M)/2`` with ``omega =
    A (M + s gamma)``, ``s = (A gamma, M)/(1/D - (A gamma, gamma))`` (``A = (I + D)^-1``);
    its gradient in ``M`` is ``omega`` and in ``gamma`` (``M`` fixed) ``s omega``, so along
    ``M = C gamma - K`` it is ``(C + s) omega``, projected on the tangent plane.
    ``tests/numerics/ball/test_trace_geometry.py`` checks it against complex steps of the
    generated energy.
    """
    omega, s = _omega_and_s(I, D, C * g - np.asarray(K), g)
    grad = (C + s) * omega
    return grad - g * detlinalg.dot(grad, g)


def segment_equilibria(
    I: Sequence[float], D: float, K: Sequence[float], C: float = 1.0
) -> list[dict[str, object]]:
    """The equilibria of ``gamma`` on ``M + K = C gamma``: critical points of the energy.

    They are the ends of the steady-rotation families on ``n = C^2``
    (:func:`~chaplygin.numerics.ball.gyrostat_diagram.steady_rotation_branches`), polished by
    Newton's method on the tangential gradient and classified by the Hessian of the
    energy on the sphere (``"min"``, ``"max"``, ``"saddle"``). For a saddle, ``rate`` is the
    eigenvalue ``lam_s > 0`` of the reduced flow ``gamma' = gamma x omega`` there and
    ``spin`` is ``sigma = (omega, gamma)``.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C : float

    Returns
    -------
    list of dict
        ``gamma``, ``h``, ``kind``, ``spin``, ``rate`` (``None`` unless a saddle), sorted
        by ``h``.

    References
    ----------
    K01-4.3, K01-4.4 (FORMULAS.md).
    """
    from .gyrostat_diagram import steady_rotation_branches

    I, D, K, C = _check_body(I, D, K, C)
    found: list[np.ndarray] = []
    for branch in steady_rotation_branches(I, D, K, C, 1.1 * C * C):
        k = int(np.argmin(branch["n"]))
        if branch["n"][k] - C * C > 1e-6 * C * C:
            continue
        g = np.asarray(branch["states"][3:, k], float)
        g = _polish(I, D, K, C, _on_sphere(g))
        if all(detlinalg.norm(g - f) > 1e-6 for f in found):
            found.append(g)
    code = load_model_code(SYSTEM, ("gyrostat",))
    p = [*I, D, *K]
    out = []
    for g in found:
        u, w = _tangent_basis(g)
        H, A = np.zeros((2, 2)), np.zeros((2, 2))
        eps = 1e-5
        for j, e in enumerate((u, w)):
            gp, gm = _on_sphere(g + eps * e), _on_sphere(g - eps * e)
            dgrad = (_sphere_gradient(I, D, K, C, gp) - _sphere_gradient(I, D, K, C, gm)) / (
                2 * eps
            )
            H[:, j] = [detlinalg.dot(dgrad, u), detlinalg.dot(dgrad, w)]
            flow = [code.numpy.rhs(0.0, np.concatenate([C * x - np.asarray(K), x]), p)[3:6]
                    for x in (gp, gm)]  # fmt: skip
            df = (flow[0] - flow[1]) / (2 * eps)
            A[:, j] = [detlinalg.dot(df, u), detlinalg.dot(df, w)]
        det = H[0, 0] * H[1, 1] - H[0, 1] * H[1, 0]
        kind = "saddle" if det < 0 else ("min" if H[0, 0] + H[1, 1] > 0 else "max")
        detA = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
        f = code.numpy.rhs(0.0, np.concatenate([C * g - np.asarray(K), g]), p)
        M = C * g - np.asarray(K)
        omega, _ = _omega_and_s(I, D, M, g)
        out.append(
            {
                "gamma": g,
                "h": float(_segment_energy(I, D, K, C, g)),
                "kind": kind,
                "spin": detlinalg.dot(omega, g),
                "rate": math.sqrt(-detA) if kind == "saddle" and detA < 0 else None,
                "residual": detlinalg.norm(f[3:6]),
            }
        )
    return sorted(out, key=lambda e: e["h"])


def _omega_and_s(I, D, M, g) -> tuple[np.ndarray, float]:
    """``omega = A (M + s gamma)`` from ``M = J omega - D (omega, gamma) gamma`` (``J = I +
    D = A^-1``), and ``s = D (omega, gamma)``."""
    A = 1 / (np.asarray(I) + D)
    s = detlinalg.dot(A * g, M) / (1 / D - detlinalg.dot(A * g, g))
    return A * (M + s * g), s


def _on_sphere(g: np.ndarray) -> np.ndarray:
    return g / detlinalg.norm(g)


def _polish(I, D, K, C, g: np.ndarray) -> np.ndarray:
    """Newton's method for a zero of the tangential gradient (Hessian by differences)."""
    for _ in range(8):
        grad = _sphere_gradient(I, D, K, C, g)
        if detlinalg.norm(grad) < 1e-14:
            break
        u, w = _tangent_basis(g)
        eps = 1e-6
        H = np.zeros((2, 2))
        for j, e in enumerate((u, w)):
            dg = (
                _sphere_gradient(I, D, K, C, _on_sphere(g + eps * e))
                - _sphere_gradient(I, D, K, C, _on_sphere(g - eps * e))
            ) / (2 * eps)
            H[:, j] = [detlinalg.dot(dg, u), detlinalg.dot(dg, w)]
        r = np.array([detlinalg.dot(grad, u), detlinalg.dot(grad, w)])
        det = H[0, 0] * H[1, 1] - H[0, 1] * H[1, 0]
        if det == 0:
            break
        a = (H[1, 1] * r[0] - H[0, 1] * r[1]) / det
        c = (-H[1, 0] * r[0] + H[0, 0] * r[1]) / det
        g = _on_sphere(g - a * u - c * w)
    return g


def gradient_line(
    I: Sequence[float],
    D: float,
    K: Sequence[float],
    C: float,
    start: Sequence[float],
    ascending: bool,
    offset: float = 1e-4,
) -> dict[str, np.ndarray]:
    """A line of steepest ascent (or descent) of the segment energy from an extremum.

    It crosses every orbit of the reduced flow it meets exactly once (the energy is
    monotone along it), so its points parametrise families of periodic orbits by their
    energy. It starts ``offset`` away from ``start`` (along the first tangent basis
    vector) and runs at unit speed (the normalised tangential gradient) until the gradient
    vanishes (the opposite extremum): classical Runge-Kutta steps of :data:`LINE_STEP` in
    arc length, each point put back on the sphere, a step kept only where the energy moves
    on by at least half of what the gradient promises (so ``h`` is strictly monotone and no
    step passes over the extremum), else halved (and doubled again after a kept one, up to
    :data:`LINE_STEP`), until the gradient's norm or the step is below :data:`LINE_FLAT`.
    Deterministic: IEEE operations in a fixed order.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C : float
    start : sequence of 3 floats
        An extremum (:func:`segment_equilibria`).
    ascending : bool
    offset : float

    Returns
    -------
    dict
        ``s`` (arc length), ``gamma`` (shape (3, N)), ``h`` (increasing if ``ascending``),
        and ``at(h)``: the point of the line with energy ``h`` (Brent's method along the
        Runge-Kutta step from the point before it, a smooth curve through the line's
        points).

    Raises
    ------
    UserInputError
        Bad parameters, a ``start`` that is not a nonzero vector, ``offset`` not positive;
        ``at(h)`` for an energy the line does not reach.
    """
    I, D, K, C = _check_body(I, D, K, C)
    offset = float(check_real(offset, "offset", positive=True, double=True))
    g0 = _unit_vector(start, "start")
    u, _ = _tangent_basis(g0)
    g0 = _on_sphere(g0 + offset * u)
    sign = 1.0 if ascending else -1.0

    def slope(g: np.ndarray) -> tuple[np.ndarray, float]:
        grad = _sphere_gradient(I, D, K, C, _on_sphere(g))
        return grad, detlinalg.norm(grad)

    def tangent(g: np.ndarray) -> np.ndarray | None:
        grad, n = slope(g)
        return sign * grad / n if n > LINE_FLAT else None

    def advance(g: np.ndarray, step: float) -> np.ndarray | None:
        """One classical Runge-Kutta step of length ``step`` (None where flat)."""
        k1 = tangent(g)
        k2 = None if k1 is None else tangent(g + (step / 2) * k1)
        k3 = None if k2 is None else tangent(g + (step / 2) * k2)
        k4 = None if k3 is None else tangent(g + step * k3)
        if k4 is None:
            return None
        return _on_sphere(g + (step / 6) * (k1 + 2 * k2 + 2 * k3 + k4))

    def energy(g: np.ndarray) -> float:
        return float(_segment_energy(I, D, K, C, g))

    s, gam, h, steps = [0.0], [g0], [energy(g0)], []
    steepness = slope(g0)[1]
    step = LINE_STEP
    while steepness > LINE_FLAT and s[-1] < 2 * math.pi and step >= LINE_FLAT:
        g = advance(gam[-1], step)
        e = energy(g) if g is not None else math.nan
        # kept if the energy moves on by at least half what the gradient promises (not so
        # near the extremum that the step would pass it), else taken again shorter
        if not sign * (e - h[-1]) >= 0.5 * step * steepness:
            step /= 2
            continue
        s.append(s[-1] + step)
        gam.append(g)
        h.append(e)
        steps.append(step)
        steepness = slope(g)[1]
        step = min(2 * step, LINE_STEP)
    gam_arr, h_arr = np.array(gam).T.copy(), np.array(h)

    def at(value: float) -> np.ndarray:
        k = int(np.searchsorted(sign * h_arr, sign * value))
        if k <= 0 or k >= len(h_arr):
            raise UserInputError(
                f"h = {value} is not on this line: its energies run over "
                f"[{h_arr.min()}, {h_arr.max()}]"
            )
        base = gam[k - 1]

        def excess(x: float) -> float:
            point = base if x == 0 else advance(base, x)
            return energy(point) - value

        root = brentq(excess, 0.0, steps[k - 1], xtol=1e-15)
        return base if root == 0 else advance(base, root)

    return {"s": np.array(s), "gamma": gam_arr, "h": h_arr, "at": at}


def turning_critical_energy(
    line_at: Callable[[float], np.ndarray] | None,
    I: Sequence[float],
    D: float,
    K: Sequence[float] | None,
    C: float,
    bracket: tuple[float, float],
    m: int,
    rtol: float = 1e-12,
) -> float:
    """The energy in ``bracket`` where ``Theta = 2 pi m`` along a family (Brent).

    Parameters
    ----------
    line_at : callable
        ``h -> gamma0`` (``gradient_line(...)["at"]``), or None for the plain ball's
        start of :func:`trace_period`.
    I, D, K, C
        As in :func:`trace_period`.
    bracket : (float, float)
    m : int
    rtol : float

    Returns
    -------
    float
        The critical energy.
    """

    def excess(h):
        g0 = None if line_at is None else line_at(h)
        tp = trace_period(I, D, None if g0 is not None else h, C, K, g0, rtol)
        return tp.turning - 2 * np.pi * m

    return float(brentq(excess, *bracket, xtol=1e-13))
