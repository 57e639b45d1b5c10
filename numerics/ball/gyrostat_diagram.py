"""The energy diagram (n, h) of the ball with a gyrostat at fixed ``C = (M + K, gamma)``.

The ball with a constant gyrostatic momentum ``K`` (K01 §4: ``M' = (M + K) x omega``,
``gamma' = gamma x omega``, ``M = I omega + D gamma x (omega x gamma)``) has the integrals
``h``, ``C = (M + K, gamma)``, ``n = (M + K, M + K)`` and ``(gamma, gamma) = 1`` (K01-4.2).
Its diagram at fixed ``C`` is drawn from

* **the steady rotations** (derived here): ``omega`` constant makes ``gamma`` turn about
  ``omega`` with ``s = (gamma, omega)`` constant, ``M = J omega - D s gamma`` (``J = I + D``),
  ``M' = -D s gamma x omega``; the equation of ``M`` then holds exactly when
  ``(J omega + K) x omega = 0``, i.e. ``J omega + K = lam omega``:
  ``omega_i = K_i/(lam - J_i)`` (a component with ``K_i = 0`` may instead be free at
  ``lam = J_i``, the ball's family about ``e_i``). On such a rotation
  ``C = (lam - D) s``, so ``s = C/(lam - D)``, and it exists where ``s^2 <= |omega|^2``.
  Without ``K`` these are the ball's families ``p_i`` (K01-3.2);
* **the segment n = C^2** (``M + K || gamma``), over which the energy runs between its least
  and largest value on the sphere of ``gamma`` (K01-4.3);
* **the region of motion**: ``(n, h)`` of seeded random states on the level ``C``.

Energies and integrals are evaluated with the generated code of ``chaplygin_ball__gyrostat``
(its ``integrals``), so the curves use the model's own energy. The stability of each steady
rotation is that of the ball's diagrams: the Floquet multipliers of the periodic solution
(:func:`chaplygin.numerics.ball.stability.floquet` on the gyrostat's generated code, period
``2 pi/|omega|``), stable where both nontrivial multipliers lie on the unit circle
(:func:`steady_rotation_stability`, :func:`branch_stability`).

References
----------
K01-4.1, K01-4.2, K01-4.3, K01-3.2, K01-Fig7 (FORMULAS.md).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ...arith import detlinalg, detmath
from ..code import load_model_code

if TYPE_CHECKING:
    from .stability import FloquetResult

__all__ = [
    "steady_rotation_states",
    "steady_rotation_branches",
    "steady_rotation_energies",
    "parallel_segment",
    "level_samples",
    "level_integrals",
    "steady_rotation_stability",
    "branch_stability",
    "steady_rotations_on_level",
    "steady_rotations_at_energy",
]


def _params(I: Sequence[float], D: float, K: Sequence[float]) -> np.ndarray:
    return np.array([*map(float, I), float(D), *map(float, K)])


def level_integrals(
    states: np.ndarray, I: Sequence[float], D: float, K: Sequence[float]
) -> dict[str, np.ndarray]:
    """``h``, ``n = (M + K, M + K)`` and ``C = (M + K, gamma)`` of states (generated code).

    Parameters
    ----------
    states : ndarray, shape (6, N)
        ``M, gamma`` in the state order of ``chaplygin_ball__gyrostat``.
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats

    Returns
    -------
    dict of str to ndarray
        ``"h"``, ``"n"``, ``"C"``.
    """
    code = load_model_code("chaplygin_ball", ("gyrostat",))
    values = np.asarray(code.numpy.integrals(0.0, states, _params(I, D, K)), float)
    names = list(code.integral_names)
    return {
        "h": values[names.index("H")],
        "n": values[names.index("(M+K,M+K)")],
        "C": values[names.index("(M+K,gamma)")],
    }


def _unit_normal(e: np.ndarray) -> np.ndarray:
    """A unit vector orthogonal to the unit vector ``e`` (columns)."""
    axis = np.zeros_like(e)
    axis[np.argmin(np.abs(e), axis=0), np.arange(e.shape[1])] = 1.0
    u = np.cross(e, axis, axis=0)
    return u / np.linalg.norm(u, axis=0)


def steady_rotation_states(
    I: Sequence[float],
    D: float,
    K: Sequence[float],
    C: float,
    omega: np.ndarray,
    lam: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """States of the steady rotations with angular velocities ``omega`` at ``C``.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C : float
        ``(M + K, gamma)``.
    omega : ndarray, shape (3, N)
        Angular velocities with ``J omega + K = lam omega``.
    lam : ndarray, shape (N,)

    Returns
    -------
    states : ndarray, shape (6, N)
        ``M, gamma`` (NaN where the rotation does not exist at this ``C``).
    exists : ndarray of bool, shape (N,)
        ``s^2 <= |omega|^2`` with ``s = C/(lam - D)``.
    """
    J = np.asarray(I, float)[:, None] + float(D)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = float(C) / (lam - float(D))
        w = np.linalg.norm(omega, axis=0)
        exists = np.isfinite(s) & (s * s <= w * w) & (w > 0)
        e = omega / w
        c = np.where(exists, s / w, np.nan)
        gamma = c * e + np.sqrt(1 - c * c) * _unit_normal(np.nan_to_num(e) + (w == 0))
        M = J * omega - float(D) * s * gamma
    return np.vstack([M, gamma]), exists


def _families(I, D, K, samples):
    """Every family as ``(omega_and_lam, parameters)``: ``omega_and_lam(x)`` gives
    ``(omega (3, N), lam (N,))`` for parameter values ``x``.

    ``lam`` runs over each interval between the poles ``J_i`` (``K_i != 0``) and ``D``
    (where ``s = C/(lam - D)`` is infinite), sampled densely near the ends; where
    ``K_i = 0`` the family ``lam = J_i`` has ``omega_i`` as its parameter."""
    J = np.asarray(I, float) + float(D)
    K = np.asarray(K, float)
    scale = max(float(np.max(J)), 1.0)
    tau = np.linspace(-18, 18, samples)
    out = []

    def lam_family(lam):
        with np.errstate(divide="ignore", invalid="ignore"):
            return K[:, None] / (lam[None, :] - J[:, None]), lam

    poles = sorted({float(D), *(float(J[i]) for i in range(3) if K[i] != 0)})
    ends = [-np.inf, *poles, np.inf]
    for lo, hi in zip(ends[:-1], ends[1:], strict=True):
        if np.isinf(lo):
            x = hi - scale * detmath.exp(tau / 2)
        elif np.isinf(hi):
            x = lo + scale * detmath.exp(tau / 2)
        else:
            x = lo + (hi - lo) / (1 + detmath.exp(-tau))
            x = x[(x > lo) & (x < hi)]
        out.append((lam_family, np.unique(x)))
    for i in range(3):
        if K[i] != 0:
            continue
        others = [j for j in range(3) if j != i]
        if any(K[j] != 0 and J[j] == J[i] for j in others):
            continue
        base = np.zeros(3)
        for j in others:
            base[j] = K[j] / (J[i] - J[j]) if K[j] != 0 else 0.0

        def free_family(w, base=base, i=i):
            return base[:, None] + np.outer(np.eye(3)[i], w), np.full(len(w), J[i])

        w = scale * detmath.exp(tau / 2)
        out.append((free_family, np.concatenate([-w[::-1], w])))
    return out


def steady_rotation_branches(
    I: Sequence[float],
    D: float,
    K: Sequence[float],
    C: float,
    n_max: float,
    samples: int = 4000,
) -> list[dict[str, np.ndarray]]:
    """The curves of the steady rotations in the (n, h) plane at ``C``, up to ``n_max``.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C : float
    n_max : float
        Largest ``n`` kept.
    samples : int
        Points per family before clipping.

    Returns
    -------
    list of dict
        One per connected piece: ``"n"``, ``"h"``, ``"x"`` (the family's parameter: ``lam``,
        or ``omega_i`` where ``K_i = 0``), ``"states"`` (shape (6, N)), ``"family"`` (its
        index) and ``"axis"`` (the nearest ``J_i`` to ``lam``, 0..2), in the family's order.
    """
    J = np.asarray(I, float) + float(D)
    branches = []
    for index, (family, x) in enumerate(_families(I, D, K, samples)):
        omega, lam = family(x)
        states, exists = steady_rotation_states(I, D, K, C, omega, lam)
        if not exists.any():
            continue
        # where a family stops existing (gamma || omega: it meets n = C^2) is located to
        # rounding, so that the curves end on the segment
        x = np.sort(np.concatenate([x, _existence_ends(family, x, exists, C, D)]))
        omega, lam = family(x)
        states, exists = steady_rotation_states(I, D, K, C, omega, lam)
        vals = level_integrals(np.nan_to_num(states), I, D, K)
        keep = exists & (vals["n"] <= n_max)
        edges = np.flatnonzero(np.diff(np.r_[0, keep.astype(int), 0]))
        for a, b in zip(edges[::2], edges[1::2], strict=True):
            if b - a < 2:
                continue
            branches.append(
                {
                    "n": vals["n"][a:b],
                    "h": vals["h"][a:b],
                    "x": x[a:b],
                    "states": states[:, a:b],
                    "family": index,
                    "axis": int(np.argmin(np.abs(J - np.median(lam[a:b])))),
                }
            )
    return branches


def _existence_ends(family, x, exists, C, D) -> np.ndarray:
    """Parameters where ``s^2 = |omega|^2`` between neighbouring samples that differ in
    existence (bisection of ``|omega|^2 - s^2 >= 0`` to rounding)."""

    def margin(v):
        omega, lam = family(np.atleast_1d(v))
        return float(np.sum(omega[:, 0] ** 2) - (float(C) / (lam[0] - float(D))) ** 2)

    ends = []
    for k in np.flatnonzero(exists[:-1] != exists[1:]):
        a, b = x[k], x[k + 1]
        fa, fb = margin(a), margin(b)
        if np.isfinite(fa) and np.isfinite(fb) and fa * fb < 0:
            inside, outside = (a, b) if fa >= 0 else (b, a)
            for _ in range(200):  # bisection to the last parameter where it exists
                mid = (inside + outside) / 2
                if mid in (inside, outside):
                    break
                inside, outside = (mid, outside) if margin(mid) >= 0 else (inside, mid)
            ends.append(inside)
    return np.asarray(ends, float)


def steady_rotation_energies(
    I: Sequence[float], D: float, K: Sequence[float], C: float, n: float
) -> np.ndarray:
    """Energies of every steady rotation on the level ``(C, n)``, located to rounding.

    Each sign change of ``n(x) - n`` along a family is refined by Brent's method.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C, n : float

    Returns
    -------
    ndarray
        The energies, sorted.
    """
    return np.sort(np.asarray([r["h"] for r in _rotations_where(I, D, K, C, "n", n)], float))


def _sphere(count: int) -> np.ndarray:
    """A Fibonacci grid of ``count`` unit vectors (columns)."""
    k = np.arange(count) + 0.5
    z = 1 - 2 * k / count
    phi = np.pi * (1 + math.sqrt(5)) * k
    r = np.sqrt(1 - z * z)
    return np.vstack([r * detmath.cos(phi), r * detmath.sin(phi), z])


def parallel_segment(
    I: Sequence[float], D: float, K: Sequence[float], C: float, count: int = 20000
) -> tuple[float, float]:
    """Least and largest energy on ``M + K = C gamma`` (the segment ``n = C^2``).

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C : float
    count : int
        Points of the Fibonacci grid of ``gamma``.

    Returns
    -------
    (h_min, h_max) : tuple of float
        Over the grid (the extreme values up to the grid's spacing squared).
    """
    gamma = _sphere(count)
    M = float(C) * gamma - np.asarray(K, float)[:, None]
    h = level_integrals(np.vstack([M, gamma]), I, D, K)["h"]
    return float(np.min(h)), float(np.max(h))


def level_samples(
    I: Sequence[float],
    D: float,
    K: Sequence[float],
    C: float,
    n_max: float,
    samples: int = 2000,
    seed: int = 1,
) -> dict[str, np.ndarray]:
    """``(n, h)`` of seeded random states on the level ``C`` with ``n <= n_max``.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C : float
    n_max : float
    samples : int
    seed : int

    Returns
    -------
    dict of str to ndarray
        ``"n"``, ``"h"``, ``"states"`` (shape (6, samples)).
    """
    rng = np.random.default_rng(seed)
    gamma = detlinalg.unit_vectors(rng, samples, 3).T.copy()
    u = detlinalg.unit_vectors(rng, samples, 3).T.copy()
    u -= gamma * np.sum(u * gamma, axis=0)
    u /= np.linalg.norm(u, axis=0)
    radius = np.sqrt(rng.uniform(0, max(float(n_max) - float(C) ** 2, 0.0), samples))
    M = float(C) * gamma + radius * u - np.asarray(K, float)[:, None]
    states = np.vstack([M, gamma])
    vals = level_integrals(states, I, D, K)
    return {"n": vals["n"], "h": vals["h"], "states": states}


def steady_rotation_stability(
    I: Sequence[float],
    D: float,
    K: Sequence[float],
    state: np.ndarray,
    rtol: float = 1e-12,
) -> FloquetResult:
    """Floquet multipliers of the steady rotation through ``state`` (``M, gamma``).

    ``omega`` is constant, so ``gamma`` turns about it with period ``T = 2 pi/|omega|``
    and so does ``M = J omega - D (omega, gamma) gamma``: the state is periodic with period
    ``T``, and its monodromy matrix (variational equations of the generated Jacobian,
    DOP853) gives the multipliers (:func:`chaplygin.numerics.ball.stability.floquet`).

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    state : ndarray, shape (6,)
        ``M, gamma`` of a steady rotation (:func:`steady_rotation_branches`).
    rtol : float
        Tolerance of the monodromy; ``sqrt(rtol)`` is the stability tolerance.

    Returns
    -------
    FloquetResult

    References
    ----------
    K01-4.1, BKM12-1.5stab (FORMULAS.md).
    """
    from .stability import floquet

    y0 = np.asarray(state, float)
    A = 1 / (np.asarray(I, float) + float(D))
    M, g = y0[:3], y0[3:]
    s = detlinalg.dot(A * g, M) / (1 / float(D) - detlinalg.dot(A * g, g))
    omega = A * (M + s * g)
    T = 2 * np.pi / detlinalg.norm(omega)
    return floquet(
        None, None, y0, T, rtol=rtol, system="chaplygin_ball", params=_params(I, D, K),
        effects=("gyrostat",),
    )  # fmt: skip


def branch_stability(
    I: Sequence[float],
    D: float,
    K: Sequence[float],
    C: float,
    branch: dict[str, np.ndarray],
    points: int = 9,
    rtol: float = 1e-12,
) -> list[tuple[int, int, bool, float]]:
    """Stability along one branch of :func:`steady_rotation_branches`, piece by piece.

    The multipliers are computed at ``points`` samples spread over the branch (its ends
    excepted: there ``gamma || omega`` and the orbit is a fixed point of the reduced
    flow); where two neighbours differ, the change is located by bisection in the
    branch's samples.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C : float
    branch : dict
        One entry of :func:`steady_rotation_branches`.
    points : int
        Samples of the multipliers before bisection.
    rtol : float

    Returns
    -------
    list of (start, stop, stable, max_abs)
        Index ranges ``[start, stop)`` of the branch's samples with one stability, and the
        largest ``max |multiplier|`` met in each.
    """
    states = branch["states"]
    N = states.shape[1]
    cache: dict[int, tuple[bool, float]] = {}

    def at(k: int) -> tuple[bool, float]:
        if k not in cache:
            r = steady_rotation_stability(I, D, K, states[:, k], rtol)
            cache[k] = (bool(r.stable), float(r.max_abs))
        return cache[k]

    lo, hi = (1, N - 2) if N > 4 else (0, N - 1)
    ks = sorted({int(round(v)) for v in np.linspace(lo, hi, max(points, 2))})
    changes = []
    for a, b in zip(ks[:-1], ks[1:], strict=True):
        if at(a)[0] != at(b)[0]:
            while b - a > 1:
                m = (a + b) // 2
                a, b = (m, b) if at(m)[0] == at(a)[0] else (a, m)
            changes.append(b)
    bounds = [0, *changes, N]
    pieces = []
    for start, stop in zip(bounds[:-1], bounds[1:], strict=True):
        inside = [k for k in cache if start <= k < stop]
        stable = at(inside[0] if inside else min(max(start, lo), hi))[0]
        worst = max(cache[k][1] for k in inside) if inside else float("nan")
        pieces.append((start, stop, stable, worst))
    return pieces


def steady_rotations_on_level(
    I: Sequence[float], D: float, K: Sequence[float], C: float, n: float, rtol: float = 1e-12
) -> list[dict[str, object]]:
    """Every steady rotation on the level ``(C, n)``, with its energy and stability.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C, n : float
    rtol : float
        Tolerance of the Floquet multipliers.

    Returns
    -------
    list of dict
        ``h``, ``n``, ``state`` (``M, gamma``), ``lam`` (``J omega + K = lam omega``),
        ``omega``, ``period``, ``stable``, ``max_abs``, ``axis`` (the ``J_i`` nearest ``lam``),
        sorted by ``h``.
    """
    return sorted(_rotations_where(I, D, K, C, "n", n, rtol), key=lambda e: e["h"])


def steady_rotations_at_energy(
    I: Sequence[float], D: float, K: Sequence[float], C: float, h: float, rtol: float = 1e-12
) -> list[dict[str, object]]:
    """Every steady rotation with energy ``h`` at ``C``, with its ``n`` and stability.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    K : sequence of 3 floats
    C, h : float
    rtol : float

    Returns
    -------
    list of dict
        As :func:`steady_rotations_on_level`, sorted by ``n``.
    """
    return sorted(_rotations_where(I, D, K, C, "h", h, rtol), key=lambda e: e["n"])


def _rotations_where(
    I, D, K, C, key: str, value: float, rtol: float | None = None
) -> list[dict]:
    """The steady rotations where the integral ``key`` (``"n"`` or ``"h"``) equals ``value``:
    sign changes along every family, refined by Brent's method; with ``rtol`` also their
    Floquet multipliers."""
    from scipy.optimize import brentq

    J = np.asarray(I, float) + float(D)
    out = []
    for family, x in _families(I, D, K, 4000):

        def excess(values, family=family):
            omega, lam = family(np.atleast_1d(values))
            states, exists = steady_rotation_states(I, D, K, C, omega, lam)
            vals = level_integrals(np.nan_to_num(states), I, D, K)
            return np.where(exists, vals[key] - value, np.nan), vals, states, omega, lam

        f = excess(x)[0]
        ok = np.isfinite(f[:-1]) & np.isfinite(f[1:]) & (np.sign(f[:-1]) != np.sign(f[1:]))
        for k in np.flatnonzero(ok):
            root = brentq(lambda v: excess(v)[0][0], x[k], x[k + 1], xtol=1e-15, rtol=1e-15)
            _, vals, states, omega, lam = excess(root)
            rotation = {
                "h": float(vals["h"][0]),
                "n": float(vals["n"][0]),
                "state": states[:, 0],
                "lam": float(lam[0]),
                "omega": omega[:, 0],
                "axis": int(np.argmin(np.abs(J - float(lam[0])))),
            }
            if rtol is not None:
                r = steady_rotation_stability(I, D, K, states[:, 0], rtol)
                rotation |= {"period": r.period, "stable": bool(r.stable), "max_abs": r.max_abs}
            out.append(rotation)
    return out
