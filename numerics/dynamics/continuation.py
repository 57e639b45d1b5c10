"""Continuation of periodic orbits of maps in a parameter, with their bifurcations.

Pseudo-arclength continuation (Keller) of the zeros of ``G(x, p) = P^k(x; p) - x`` in the
unknowns ``u = (x, p)``: a predictor along the tangent ``t`` (the null vector of
``DG = [D P^k - Id, dG/dp]``), a Newton corrector on ``G = 0`` with the constraint
``t . (u - u_pred) = 0``, and step control (longer after an easy correction, halved after a
failed one). The column ``dG/dp`` is a central difference of the map in ``p``: it enters
only the Newton matrix (the convergence rate), never the residual that is driven to zero.

Bifurcations are sign changes of test functions of the monodromy ``A = D P^k`` between
consecutive points of the branch (as in AUTO, MatCont and BifurcationKit.jl):

- period doubling (a multiplier through -1): ``det(A + Id)``;
- saddle-node (a multiplier through +1, at a fold of the branch): ``det(A - Id)``;
- Neimark–Sacker (a complex pair through the unit circle): ``prod_{i<j} (mu_i mu_j - 1)``,
  the determinant of ``A (.) A - Id`` on the bialternate product; a zero with a *real*
  pair ``mu, 1/mu`` (a neutral saddle) is not a bifurcation and is not reported.

A sign change is located by the secant method with bisection safeguard (Illinois) on the
test function along the secant of the two points, each trial point corrected back onto
the branch. At a period doubling the continuation can switch to the doubled branch: the
period-``2k`` orbit is solved from ``x* + eps v`` (``v`` the eigenvector of ``-1``) with the
constraint ``v . (x - x*) = eps`` and the parameter free, and followed on; a cascade is
followed by switching again.

Double precision only (the orbits themselves can be refined at higher precision with
:func:`chaplygin.numerics.dynamics.periodic_orbits.refine_periodic_orbit`).

References
----------
H. B. Keller (1977), pseudo-arclength continuation; Yu. A. Kuznetsov, *Elements of Applied
Bifurcation Theory*, §10.2-10.3 (test functions, bialternate products); E. Doedel et al.,
AUTO-07p manual; A. Dhooge et al., MatCont; R. Veltz, BifurcationKit.jl.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...arith import detlinalg
from ...derive.errors import UserInputError
from .periodic_orbits import SmoothMap, orbit_jacobian, refine_periodic_orbit

__all__ = [
    "BifurcationEvent",
    "Branch",
    "ContinuationResult",
    "continue_periodic_orbit",
    "bifurcation_indicators",
    "EVENT_KINDS",
]

EVENT_KINDS = ("period-doubling", "saddle-node", "neimark-sacker")


@dataclass
class BifurcationEvent:
    """A located bifurcation of a branch of periodic orbits.

    Attributes
    ----------
    kind : str
        One of :data:`EVENT_KINDS` (or ``"branch-point"``: a multiplier +1 without a fold).
    parameter : float
        Located parameter value.
    uncertainty : float
        Half-width of the final bracket in the parameter.
    period : int
        Period of the orbit that bifurcates.
    point : ndarray
        A point of the orbit at the event.
    multipliers : ndarray
        Its multipliers there.
    """

    kind: str
    parameter: float
    uncertainty: float
    period: int
    point: NDArray[np.float64]
    multipliers: NDArray[np.complex128]


@dataclass
class Branch:
    """One branch of period-``k`` orbits.

    Attributes
    ----------
    period : int
    parameters : ndarray, shape (n,)
    points : ndarray, shape (n, dim)
        A point of the orbit at each parameter.
    multipliers : ndarray, shape (n, dim)
        Sorted by decreasing modulus.
    events : list of BifurcationEvent
    message : str
        Why the branch ended.
    """

    period: int
    parameters: NDArray[np.float64]
    points: NDArray[np.float64]
    multipliers: NDArray[np.complex128]
    events: list[BifurcationEvent] = field(default_factory=list)
    message: str = ""


@dataclass
class ContinuationResult:
    """Branches followed, in order (a cascade gives one branch per period).

    Attributes
    ----------
    branches : list of Branch
    message : str
    """

    branches: list[Branch]
    message: str = ""

    @property
    def events(self) -> list[BifurcationEvent]:
        """Every located event, in the order met.

        Returns
        -------
        list of BifurcationEvent
        """
        return [e for b in self.branches for e in b.events]

    def doublings(self) -> list[float]:
        """Parameters of the period doublings met, in order.

        Returns
        -------
        list of float
        """
        return [e.parameter for e in self.events if e.kind == "period-doubling"]


def bifurcation_indicators(multipliers: Any) -> dict[str, float]:
    """The three test functions of a monodromy with the given multipliers.

    Parameters
    ----------
    multipliers : array_like of complex
        All eigenvalues of ``D P^k``.

    Returns
    -------
    dict of str to float
        ``period-doubling``: ``prod(mu + 1)``; ``saddle-node``: ``prod(mu - 1)``;
        ``neimark-sacker``: ``prod_{i<j}(mu_i mu_j - 1)`` (1.0 in dimension 1).
    """
    mu = np.asarray(multipliers, dtype=complex)
    ns = 1.0 + 0j
    for i in range(len(mu)):
        for j in range(i + 1, len(mu)):
            ns *= mu[i] * mu[j] - 1
    return {
        "period-doubling": float(np.prod(mu + 1).real),
        "saddle-node": float(np.prod(mu - 1).real),
        "neimark-sacker": float(ns.real),
    }


class _Continuer:
    """Pseudo-arclength machinery for one map and one period."""

    def __init__(self, smap: SmoothMap, period: int, tol: float, dp: float) -> None:
        self.smap, self.period, self.tol, self.dp = smap, period, tol, dp
        self.dim = smap.dim

    def G(self, x: NDArray, p: float) -> NDArray:
        y = x
        for _ in range(self.period):
            y = self.smap.f(y, p)
        return self.smap.difference(y, x)

    def jacobian(self, x: NDArray, p: float) -> tuple[NDArray, NDArray, NDArray]:
        with np.errstate(over="ignore", invalid="ignore"):
            return self._jacobian(x, p)

    def _jacobian(self, x: NDArray, p: float) -> tuple[NDArray, NDArray, NDArray]:
        points, A = orbit_jacobian(self.smap, x, p, self.period)
        g = self.smap.difference(points[-1], x)
        h = self.dp * max(1.0, abs(p))
        gp = (self.G(x, p + h) - self.G(x, p - h)) / (2 * h)
        return g, np.hstack([A - np.eye(self.dim), gp[:, None]]), A

    def tangent(self, DG: NDArray, previous: NDArray | None) -> NDArray:
        t = detlinalg.null_vector(DG)
        if previous is not None and detlinalg.dot(t, previous) < 0:
            t = -t
        return t

    def correct(
        self, u: NDArray, normal: NDArray, anchor: NDArray, max_iter: int = 8
    ) -> tuple[NDArray, NDArray, int, NDArray] | None:
        """Newton on G(u) = 0, normal . (u - anchor) = 0: (u, A, iterations, DG) or None."""
        for it in range(max_iter + 1):
            g, DG, A = self.jacobian(u[:-1], u[-1])
            if not (np.all(np.isfinite(g)) and np.all(np.isfinite(DG))):
                return None
            if np.max(np.abs(g)) <= self.tol:
                return u, A, it, DG
            if it == max_iter:
                return None
            r = detlinalg.dot(normal, u - anchor)
            M = np.vstack([DG, normal])
            try:
                du = detlinalg.solve(M, -np.append(g, r))
            except detlinalg.LinAlgError:
                return None
            u = u + du
        return None


def _multipliers(A: NDArray) -> NDArray:
    ev = detlinalg.eigvals(A)
    return ev[np.argsort(-np.abs(ev), kind="stable")]


def _check_range(smap: SmoothMap, events: tuple[str, ...], p0: Any, p_end: Any) -> tuple:
    """The range of :func:`continue_periodic_orbit` as floats, or :class:`UserInputError`."""
    if smap.digits is not None:
        raise UserInputError("continuation runs in double precision: give a double map")
    unknown = set(events) - set(EVENT_KINDS)
    if unknown:
        raise UserInputError(f"unknown event kinds {sorted(unknown)}; valid: {list(EVENT_KINDS)}")
    p0, p_end = float(p0), float(p_end)
    if not (np.isfinite(p0) and np.isfinite(p_end)) or p0 == p_end:
        raise UserInputError(
            f"the parameter range must be two different numbers, got {p0}, {p_end}"
        )
    return p0, p_end


def continue_periodic_orbit(
    smap: SmoothMap,
    x0: Any,
    period: int,
    p0: float,
    p_end: float,
    *,
    step: float | None = None,
    min_step: float | None = None,
    max_step: float | None = None,
    max_points: int = 2000,
    tol: float | None = None,
    location_tol: float | None = None,
    events: tuple[str, ...] = EVENT_KINDS,
    follow_doublings: int = 0,
    progress: Any = None,
) -> ContinuationResult:
    """Follow a period-``k`` orbit from ``p0`` towards ``p_end`` and locate its bifurcations.

    Parameters
    ----------
    smap : SmoothMap
        A double-precision map (``digits`` None).
    x0 : array_like
        A point near the orbit at ``p0`` (refined first).
    period : int
    p0, p_end : float
        Start and end of the parameter range (either order).
    step : float, optional
        Initial arclength step (default ``|p_end - p0| / 50``).
    min_step, max_step : float, optional
        Bounds of the step (default ``step / 2^12`` and ``4 step``).
    max_points : int
        Points per branch at most.
    tol : float, optional
        Newton residual (default ``10 k accuracy`` of the map).
    location_tol : float, optional
        Width in ``p`` to which events are located (default ``10 tol``; the test
        function's own noise may stop the location earlier, see the event's uncertainty).
    events : tuple of str
        Which events to detect (subset of :data:`EVENT_KINDS`).
    follow_doublings : int
        How many period doublings to switch at (0: report them and go on along the same
        branch).
    progress : callable, optional
        ``progress(message)``.

    Returns
    -------
    ContinuationResult

    Raises
    ------
    UserInputError
        A map at higher precision, bad ranges or steps, unknown event kinds.
    ComputationError
        The initial orbit cannot be refined.
    """
    p0, p_end = _check_range(smap, events, p0, p_end)
    span = abs(p_end - p0)
    step = span / 50 if step is None else float(step)
    if not step > 0:
        raise UserInputError(f"the step must be positive, got {step}")
    min_step = step / 2**12 if min_step is None else float(min_step)
    max_step = 4 * step if max_step is None else float(max_step)
    direction = np.sign(p_end - p0)
    branches: list[Branch] = []
    x = np.asarray(x0, dtype=float)
    k = int(period)
    p = p0
    remaining = follow_doublings
    start_p = p0
    while True:
        btol = 10 * k * smap.accuracy if tol is None else float(tol)
        ltol = 10 * btol if location_tol is None else float(location_tol)
        orbit = refine_periodic_orbit(smap, x, k, p, tol=btol)
        if not orbit.converged:
            if branches:
                branches[-1].message += f"; the period-{k} orbit was not found: {orbit.message}"
                break
            from ...derive.errors import ComputationError

            raise ComputationError(f"the initial period-{k} orbit at p = {p}: {orbit.message}")
        branch, switch = _follow(
            _Continuer(smap, k, btol, float(np.cbrt(np.finfo(float).eps))),
            orbit.points[0],
            p,
            p_end,
            direction,
            step,
            min_step,
            max_step,
            max_points,
            ltol,
            events,
            remaining > 0,
            progress,
        )
        branches.append(branch)
        if switch is None:
            break
        remaining -= 1
        # the next doubling comes about 4.7 times sooner (Feigenbaum): steps of a tenth of
        # the last interval at most, so no doubling is stepped over
        interval = abs(branch.events[-1].parameter - start_p)
        start_p = branch.events[-1].parameter
        x, p, step = switch
        k *= 2
        max_step = min(max_step, interval / 10)
        step = min(step, max_step)
        min_step = min(min_step, step / 2**12)
    return ContinuationResult(branches, branches[-1].message)


def _follow(
    c: _Continuer,
    x: NDArray,
    p: float,
    p_end: float,
    direction: float,
    step: float,
    min_step: float,
    max_step: float,
    max_points: int,
    ltol: float,
    kinds,
    switch: bool,
    progress,
    max_multiplier_change: float = 0.25,
) -> tuple[Branch, tuple[NDArray, float, float] | None]:
    u = np.append(x, p)
    p_start = p
    g, DG, A = c.jacobian(x, p)
    t = c.tangent(DG, None)
    if t[-1] * direction < 0:
        t = -t
    params, points, mults = [p], [x.copy()], [_multipliers(A)]
    tests = [bifurcation_indicators(mults[-1])]
    found: list[BifurcationEvent] = []
    message = ""
    h = step
    while True:
        if len(params) >= max_points:
            message = f"stopped after {max_points} points"
            break
        pred = u + h * t
        res = c.correct(pred, t, pred)
        if res is None:
            h /= 2
            if h < min_step:
                message = f"step below {min_step:.1e} at p = {u[-1]:.10g}: Newton fails there"
                break
            continue
        u_new, A_new, its, DG_new = res
        mu = _multipliers(A_new)
        # how far the multipliers moved, as sets (their order by modulus may swap)
        moved = np.max(np.min(np.abs(mu[:, None] - mults[-1][None, :]), axis=1))
        if moved > max_multiplier_change and h > min_step:
            h = max(h / 2, min_step)  # the multipliers moved too far: a smaller step
            continue
        tf = bifurcation_indicators(mu)
        t_new = c.tangent(DG_new, t)
        # events between u and u_new
        switch_to = None
        for kind in kinds:
            if np.sign(tf[kind]) != np.sign(tests[-1][kind]) and tests[-1][kind] != 0:
                ev = _locate(c, kind, u, u_new, tests[-1][kind], tf[kind], ltol, t, t_new)
                if ev is not None:
                    found.append(ev)
                    if progress:
                        progress(
                            f"{ev.kind} of the period-{c.period} orbit at p = {ev.parameter:.12g}"
                        )
                    if switch and ev.kind == "period-doubling" and switch_to is None:
                        switch_to = _switch(c, ev, direction, h)
        params.append(u_new[-1])
        points.append(u_new[:-1].copy())
        mults.append(mu)
        tests.append(tf)
        u, t = u_new, t_new
        if switch_to is not None:
            message = (
                f"switched to the period-{2 * c.period} branch at p = {found[-1].parameter:.12g}"
            )
            break
        if switch and found and found[-1].kind == "period-doubling":
            message = "the period-doubled orbit was not found: stopped at the doubling"
            break
        if (u[-1] - p_end) * direction >= 0:
            message = f"reached p = {u[-1]:.10g}"
            break
        if (u[-1] - p_start) * direction < 0:
            message = f"the branch turned back out of the range at p = {u[-1]:.10g}"
            break
        h = min(max_step, h * 1.5) if its <= 3 else (h / 2 if its >= 6 else h)
        h = max(h, min_step)
    branch = Branch(c.period, np.array(params), np.array(points), np.array(mults), found, message)
    return branch, switch_to


def _locate(
    c: _Continuer,
    kind: str,
    ua: NDArray,
    ub: NDArray,
    fa: float,
    fb: float,
    ltol: float,
    ta: NDArray,
    tb: NDArray,
) -> BifurcationEvent | None:
    """Illinois on the test function along the chord ua -> ub (each trial corrected)."""
    if kind == "saddle-node":
        fold = np.sign(ta[-1]) != np.sign(tb[-1])
    chord = ub - ua
    length = detlinalg.norm(chord)
    normal = chord / length
    a, b = 0.0, 1.0
    side = 0
    u_mid, A_mid = ub, None
    for _ in range(100):
        if abs(ub[-1] - ua[-1]) * abs(b - a) <= ltol and A_mid is not None:
            break
        s = b - fb * (b - a) / (fb - fa) if fb != fa else (a + b) / 2
        if not a < s < b:
            s = (a + b) / 2
        anchor = ua + s * chord
        res = c.correct(anchor, normal, anchor)
        if res is None:
            return None
        u_mid, A_mid, _, _ = res
        fm = bifurcation_indicators(_multipliers(A_mid))[kind]
        if fm == 0:
            a = b = s
            break
        if np.sign(fm) == np.sign(fa):
            a, fa = s, fm
            if side == -1:
                fb /= 2
            side = -1
        else:
            b, fb = s, fm
            if side == 1:
                fa /= 2
            side = 1
    mu = _multipliers(A_mid)
    if kind == "neimark-sacker":
        # the pair whose product is nearest 1 must be complex (else: a neutral saddle)
        pairs = [
            (abs(mu[i] * mu[j] - 1), i, j) for i in range(len(mu)) for j in range(i + 1, len(mu))
        ]
        _, i, j = min(pairs)
        if abs(mu[i].imag) <= 1e-8 * max(1.0, abs(mu[i])):
            return None
    if kind == "saddle-node" and not fold:
        kind = "branch-point"
    return BifurcationEvent(
        kind=kind,
        parameter=float(u_mid[-1]),
        uncertainty=float(abs(ub[-1] - ua[-1]) * abs(b - a) / 2),
        period=c.period,
        point=u_mid[:-1].copy(),
        multipliers=mu,
    )


def _switch(
    c: _Continuer, ev: BifurcationEvent, direction: float, h: float
) -> tuple[NDArray, float, float] | None:
    """A point of the period-2k branch born at the doubling ``ev``: ``(x, p, step)``."""
    x_star, p_star = ev.point, ev.parameter
    _, A = orbit_jacobian(c.smap, x_star, p_star, c.period)
    w, V = detlinalg.eig(A)
    v = np.real(V[:, np.argmin(np.abs(w + 1))])
    v /= detlinalg.norm(v)
    doubled = _Continuer(c.smap, 2 * c.period, c.tol, c.dp)
    scale = max(1.0, float(np.max(np.abs(x_star))))
    eps = 1e-2 * scale
    for _ in range(30):
        for sgn in (1, -1):
            anchor = np.append(x_star + sgn * eps * v, p_star)
            row = np.append(v, 0.0)
            res = doubled.correct(anchor, row, anchor, max_iter=12)
            if res is None:
                continue
            u, _, _, _ = res
            dp = u[-1] - p_star
            small = abs(dp) <= h
            genuine = np.max(np.abs(c.G(u[:-1], u[-1]))) > 100 * c.tol
            if small and genuine and dp * direction > 0:
                return u[:-1], u[-1], max(abs(dp), 4 * c.tol)
        eps /= 2
    return None
