"""Periodic orbits of maps: period detection, Newton refinement, Floquet multipliers.

A map is given by :class:`SmoothMap`: ``f(x, p) -> x'`` and ``df(x, p) -> (x', J)`` with
``J = DP(x)`` (for a stroboscopic map of an ODE: the state-transition matrix of the
variational equations over one forcing period). A period-``k`` orbit is a zero of
``F(x) = P^k(x) - x``; Newton's method uses ``DF = J_{k-1} ... J_1 J_0 - Id``, the product
of the Jacobians along the orbit (the chain rule). The eigenvalues of the product
``D P^k = J_{k-1} ... J_0`` are the orbit's Floquet multipliers; the orbit is stable when
they all lie inside the unit circle.

Two precisions: IEEE double (numpy arrays) and ``digits`` decimal digits (mpmath matrices,
the map evaluated at that precision by the caller's ``f``/``df``; every operation here
inside ``mpmath.workdps``). Angles (coordinates defined modulo ``2 pi``) are wrapped in
every difference, so an orbit that winds is still closed.

References
----------
Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory* (3rd ed., 2004), §1.5, §4.5
(multipliers of fixed points and cycles of maps); AUTO-07p, MatCont (cycles of maps).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from contextlib import nullcontext
from dataclasses import dataclass, field
from typing import Any

import mpmath
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...arith import detlinalg
from ...derive.errors import ComputationError, UserInputError

__all__ = [
    "SmoothMap",
    "PeriodicOrbit",
    "detect_period",
    "refine_periodic_orbit",
    "floquet_multipliers",
    "orbit_jacobian",
    "as_numpy_points",
]

TWO_PI = 2 * np.pi


@dataclass(frozen=True)
class SmoothMap:
    """A map with its Jacobian, depending on one scalar parameter.

    Parameters
    ----------
    f : callable
        ``f(x, p) -> x'`` (numpy vector of length ``dim``, or an mpmath column matrix when
        ``digits`` is set).
    df : callable
        ``df(x, p) -> (x', J)``, ``J`` of shape ``(dim, dim)``.
    dim : int
        Dimension of the map.
    angles : tuple of int
        Indices of coordinates defined modulo ``2 pi``.
    digits : int or None
        None: double precision (numpy); an int: the map works at that many decimal digits
        (mpmath).
    accuracy : float
        Absolute accuracy of one evaluation of ``f`` (the integration tolerance of a
        stroboscopic map; machine epsilon times a modest factor for a closed-form map).
        Tolerances of period detection and Newton are derived from it.
    """

    f: Callable[[Any, Any], Any]
    df: Callable[[Any, Any], tuple[Any, Any]]
    dim: int
    angles: tuple[int, ...] = ()
    digits: int | None = None
    accuracy: float = 1e3 * float(np.finfo(float).eps)

    def difference(self, a: Any, b: Any) -> Any:
        """``a - b`` with angles wrapped to ``[-pi, pi)``.

        Parameters
        ----------
        a, b : array_like or mpmath.matrix
            Points of the map's space (numpy arrays may carry leading dimensions).

        Returns
        -------
        ndarray or mpmath.matrix
        """
        if self.digits is None:
            d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
            for i in self.angles:
                d[..., i] = (d[..., i] + np.pi) % TWO_PI - np.pi
            return d
        d = a - b
        for i in self.angles:
            twopi = 2 * mpmath.pi
            d[i] = (d[i] + mpmath.pi) % twopi - mpmath.pi
        return d

    def iterate(self, x: Any, p: Any, n: int) -> list:
        """The orbit ``x, P(x), ..., P^n(x)``.

        Parameters
        ----------
        x : array_like or mpmath.matrix
        p : float or mpmath.mpf
        n : int

        Returns
        -------
        list
            ``n + 1`` points.
        """
        points = [x]
        for _ in range(n):
            points.append(self.f(points[-1], p))
        return points


@dataclass
class PeriodicOrbit:
    """A periodic orbit of a map, refined by Newton's method, with its evidence.

    Attributes
    ----------
    points : list
        The ``period`` points ``x_0, ..., x_{k-1}`` (numpy vectors or mpmath matrices).
    period : int
        Minimal period ``k`` found for the orbit (smaller periods are excluded).
    parameter : float or mpmath.mpf
    multipliers : ndarray or list of mpmath.mpc
        Eigenvalues of ``D P^k(x_0)``, sorted by decreasing modulus.
    monodromy : ndarray or mpmath.matrix
        ``D P^k(x_0)``.
    residual : float
        ``|P^k(x_0) - x_0|`` (max norm, angles wrapped) after the last Newton step.
    tolerance : float
        The residual Newton had to reach.
    iterations : int
    converged : bool
    stable : bool
        All multipliers inside the unit circle by more than ``multiplier_tolerance``.
    multiplier_tolerance : float
        Uncertainty of the multipliers' moduli: ``sqrt`` of the map's relative accuracy
        times the product's growth (a double multiplier moves by the square root of a
        perturbation).
    digits : int or None
        Working precision (None: double).
    message : str
    """

    points: list
    period: int
    parameter: Any
    multipliers: Any
    monodromy: Any
    residual: float
    tolerance: float
    iterations: int
    converged: bool
    stable: bool
    multiplier_tolerance: float
    digits: int | None = None
    message: str = ""
    history: list[float] = field(default_factory=list)

    @property
    def max_abs_multiplier(self) -> float:
        """``max |multiplier|`` (as a float).

        Returns
        -------
        float
        """
        return float(max(abs(m) for m in self.multipliers))


# ------------------------------------------------------------------ period detection
def detect_period(
    orbit: ArrayLike,
    max_period: int,
    tol: float,
    *,
    angles: Sequence[int] = (),
    window: int | None = None,
) -> int | None:
    """The smallest period ``k <= max_period`` of an orbit (after its transient).

    ``k`` is accepted when ``|x_{i+k} - x_i| <= tol`` (max norm, angles wrapped) for every
    ``i`` of the last ``window`` points.

    Parameters
    ----------
    orbit : array_like, shape (n, dim)
        Consecutive iterates, the transient already discarded.
    max_period : int
        Largest period tried; ``n >= max_period + window`` points are needed.
    tol : float
        Closing tolerance (derive it from the map's accuracy and the orbit's contraction:
        an orbit converging like ``|mu|^n`` has not closed below ``|mu|^n``).
    angles : sequence of int
        Indices of coordinates defined modulo ``2 pi``.
    window : int, optional
        Number of points checked (default ``max_period``).

    Returns
    -------
    int or None
        The period, or None when no ``k <= max_period`` closes within ``tol``.

    Raises
    ------
    UserInputError
        Too few points, ``max_period < 1`` or ``tol <= 0``.
    """
    x = np.asarray(orbit, dtype=float)
    if x.ndim != 2:
        raise UserInputError(f"the orbit must have shape (n, dim), got {x.shape}")
    if max_period < 1 or not tol > 0:
        raise UserInputError(f"need max_period >= 1 and tol > 0, got {max_period}, {tol}")
    window = max_period if window is None else int(window)
    if len(x) < max_period + window:
        raise UserInputError(
            f"period detection up to {max_period} over {window} points needs "
            f"{max_period + window} iterates, got {len(x)}"
        )
    tail = x[len(x) - window - max_period :]
    for k in range(1, max_period + 1):
        d = tail[k : k + window] - tail[:window]
        for i in angles:
            d[:, i] = (d[:, i] + np.pi) % TWO_PI - np.pi
        if np.max(np.abs(d)) <= tol:
            return k
    return None


# ------------------------------------------------------------------ linear algebra by precision
def _identity(n: int, digits: int | None):
    return np.eye(n) if digits is None else mpmath.eye(n)


def _norm(v, digits: int | None) -> float:
    if digits is None:
        return float(np.max(np.abs(v)))
    return float(max(abs(e) for e in v))


def _solve(A, b, digits: int | None):
    if digits is None:
        return detlinalg.solve(A, b)
    return mpmath.lu_solve(A, b)


def _eigenvalues(A, digits: int | None):
    if digits is None:
        ev = detlinalg.eigvals(A)
        return ev[np.argsort(-np.abs(ev), kind="stable")]
    if A.rows == 1:  # mpmath.eig returns a tuple for 1x1 matrices
        return [A[0, 0]]
    return sorted(mpmath.eig(A, left=False, right=False), key=lambda m: -abs(m))


def _as_point(x, smap: SmoothMap):
    if smap.digits is None:
        v = np.array(x, dtype=float).reshape(-1)
        if v.shape != (smap.dim,):
            raise UserInputError(f"a point of this map has {smap.dim} coordinates, got {v.size}")
        return v
    with mpmath.workdps(smap.digits):
        v = mpmath.matrix([mpmath.mpf(e) for e in (x if not isinstance(x, mpmath.matrix) else x)])
    if v.rows != smap.dim:
        raise UserInputError(f"a point of this map has {smap.dim} coordinates, got {v.rows}")
    return v


def orbit_jacobian(smap: SmoothMap, x0: Any, p: Any, period: int) -> tuple[list, Any]:
    """The orbit of ``x0`` over ``period`` steps and ``D P^k(x0)``.

    Parameters
    ----------
    smap : SmoothMap
    x0 : array_like or mpmath.matrix
    p : float or mpmath.mpf
        The map's parameter.
    period : int
        ``k >= 1``.

    Returns
    -------
    points : list
        ``x_0, ..., x_k`` (``k + 1`` points).
    jacobian : ndarray or mpmath.matrix
        ``J_{k-1} ... J_0``.
    """
    points = [x0]
    product = _identity(smap.dim, smap.digits)
    for _ in range(period):
        x1, J = smap.df(points[-1], p)
        product = detlinalg.matmul(J, product) if smap.digits is None else J * product
        points.append(x1)
    return points, product


def floquet_multipliers(smap: SmoothMap, x0: ArrayLike, p: Any, period: int) -> Any:
    """Multipliers of the period-``k`` orbit through ``x0`` (eigenvalues of ``D P^k``).

    Parameters
    ----------
    smap : SmoothMap
    x0 : array_like or mpmath.matrix
        A point of the orbit.
    p : float or mpmath.mpf
    period : int

    Returns
    -------
    ndarray or list of mpmath.mpc
        Sorted by decreasing modulus.
    """
    x0 = _as_point(x0, smap)
    if smap.digits is None:
        return _eigenvalues(orbit_jacobian(smap, x0, p, period)[1], None)
    with mpmath.workdps(smap.digits):
        return _eigenvalues(orbit_jacobian(smap, x0, p, period)[1], smap.digits)


# ------------------------------------------------------------------ Newton refinement
def refine_periodic_orbit(
    smap: SmoothMap,
    x0: ArrayLike,
    period: int,
    p: Any,
    *,
    tol: float | None = None,
    max_iter: int = 30,
    check_minimal: bool = True,
) -> PeriodicOrbit:
    """Newton's method on ``F(x) = P^k(x) - x`` with ``DF = J_{k-1} ... J_0 - Id``.

    Once the residual is within ``tol``, one more Newton step polishes the orbit (kept only
    if it closes better), so an initial guess that already closes is still refined.

    Parameters
    ----------
    smap : SmoothMap
    x0 : array_like or mpmath.matrix
        Initial guess (a point near the orbit).
    period : int
        ``k >= 1``.
    p : float or mpmath.mpf
        The map's parameter.
    tol : float, optional
        Residual to reach (max norm). Default: ``10 k accuracy`` of the map (each of the
        ``k`` evaluations carries ``accuracy``).
    max_iter : int
    check_minimal : bool
        Refuse an orbit whose minimal period is a proper divisor of ``k`` (Newton fell
        onto a shorter orbit): ``converged`` is then False with a message.

    Returns
    -------
    PeriodicOrbit
        ``converged`` False (with a message saying why) when the residual was not reached;
        the multipliers are those of the last iterate.

    Raises
    ------
    UserInputError
        ``period < 1`` or a point of the wrong length.
    ComputationError
        ``DF`` singular (a multiplier exactly 1: a fold or a continuum of orbits).
    """
    if int(period) != period or period < 1:
        raise UserInputError(f"the period must be a positive integer, got {period!r}")
    period = int(period)
    tol = 10 * period * smap.accuracy if tol is None else float(tol)
    digits = smap.digits
    x = _as_point(x0, smap)
    ctx = mpmath.workdps(digits) if digits is not None else nullcontext()
    with ctx:
        eye = _identity(smap.dim, digits)
        history: list[float] = []
        converged = False
        best = None  # (x, points, product, residual) of an iterate within tol
        for it in range(max_iter + 1):
            points, product = orbit_jacobian(smap, x, p, period)
            F = smap.difference(points[-1], x)
            residual = _norm(F, digits)
            history.append(residual)
            if best is not None:
                # after the polishing step: keep whichever iterate closes better
                if residual > best[3]:
                    x, points, product, residual = best
                converged = True
                break
            if residual <= tol:
                best = (x, points, product, residual)  # within tol: one more (polishing) step
            if it == max_iter:
                converged = best is not None
                break
            try:
                dx = _solve(product - eye, -F, digits)
            except (detlinalg.LinAlgError, ZeroDivisionError) as exc:
                if best is not None:  # already within tol: no polishing at a fold
                    converged = True
                    break
                raise ComputationError(
                    f"Newton's matrix D P^{period} - Id is singular at parameter {p}: a "
                    "multiplier equals 1 (a fold, or a continuum of periodic orbits)"
                ) from exc
            x = x + dx
        multipliers = _eigenvalues(product, digits)
        scale = max(1.0, _norm(product, digits))
        mult_tol = float(np.sqrt(max(smap.accuracy, tol) * scale))
        stable = all(float(abs(m)) < 1 - mult_tol for m in multipliers)
        message = (
            f"converged in {it} Newton steps to |P^{period}(x) - x| = {residual:.2e}"
            if converged
            else f"Newton did not reach |P^{period}(x) - x| <= {tol:.1e} in {max_iter} steps "
            f"(last residual {residual:.2e}): a better initial guess or a smaller step is needed"
        )
        if converged and check_minimal and period > 1:
            for q in range(1, period):
                if period % q == 0 and _norm(smap.difference(points[q], x), digits) <= 10 * tol:
                    converged = False
                    message = (
                        f"Newton converged to an orbit of period {q}, a divisor of {period}: "
                        f"start nearer the period-{period} orbit"
                    )
                    break
    return PeriodicOrbit(
        points=points[:period],
        period=period,
        parameter=p,
        multipliers=multipliers,
        monodromy=product,
        residual=residual,
        tolerance=tol,
        iterations=it,
        converged=converged,
        stable=stable,
        multiplier_tolerance=mult_tol,
        digits=digits,
        message=message,
        history=history,
    )


def as_numpy_points(orbit: PeriodicOrbit) -> NDArray[np.float64]:
    """The orbit's points as a float array of shape ``(period, dim)``.

    Parameters
    ----------
    orbit : PeriodicOrbit

    Returns
    -------
    ndarray
    """
    return np.array([[float(e) for e in x] for x in orbit.points], dtype=float)
