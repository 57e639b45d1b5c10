"""BM20's stroboscopic map in Andoyer-Deprit coordinates ``(z, l, g)`` on the level
``|M| = G``, ``(M, gamma) = 0`` (BM20 §3.2, (3.7)), with its Jacobian: the
:class:`~chaplygin.numerics.dynamics.periodic_orbits.SmoothMap` the periodic-orbit search,
continuation and regimes of BM20 work on.

References
----------
BM20-3.7, BM20-map (FORMULAS.md).
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import partial
from typing import Any

import mpmath
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...arith import detlinalg
from ...derive.errors import UserInputError
from ..dynamics.periodic_orbits import SmoothMap
from .map_coordinates import andoyer_deprit, reduced_point, reduced_tangent, state_from_reduced

__all__ = [
    "BM20_EFFECTS",
    "BM20_STATE",
    "bm20_map_with_jacobian",
    "bm20_points",
    "bm20_point",
    "bm20_state",
    "reduced_step",
]

BM20_EFFECTS = "variable_gyrostat,variable_inertia"
#: Parameter order of the BM20 model (I1, I2, I3, D, J_off, delta, K1, K2, K3, Omega).
_OMEGA = 9
#: The BM20 model's state (without contact_point).
BM20_STATE = ("M1", "M2", "M3", "gamma1", "gamma2", "gamma3")


def bm20_state(x: ArrayLike, G: float) -> NDArray[np.float64]:
    """BM20 (3.7): the state ``(M, gamma)`` of the map point ``x = (z, l, g)`` at ``|M| = G``,
    ``(M, gamma) = 0`` (:func:`~chaplygin.numerics.ball.map_coordinates.state_from_reduced`).

    Parameters
    ----------
    x : array_like, shape (3,)
    G : float

    Returns
    -------
    ndarray, shape (6,)
    """
    return np.array(state_from_reduced(np.asarray(x, float), G, [0.0] * 6, BM20_STATE), float)


def bm20_point(y: ArrayLike) -> NDArray[np.float64]:
    """The map point ``(z, l, g)`` of a BM20 state ``(M, gamma)`` (inverse of
    :func:`bm20_state`; :func:`~chaplygin.numerics.ball.map_coordinates.reduced_point`).

    Parameters
    ----------
    y : array_like, shape (6,)

    Returns
    -------
    ndarray, shape (3,)
    """
    return np.asarray(reduced_point(np.asarray(y, float), BM20_STATE)[1], dtype=float)


def bm20_points(Y: ArrayLike) -> NDArray[np.float64]:
    """:func:`bm20_point` of many states at once (one array pass of the project's elementary
    functions, whose bits do not depend on the array: the same points as one at a time).

    Parameters
    ----------
    Y : array_like, shape (n, 6)

    Returns
    -------
    ndarray, shape (n, 3)
    """
    Y = np.asarray(Y, dtype=float)
    M = [Y[:, BM20_STATE.index(f"M{i}")] for i in (1, 2, 3)]
    gamma = [Y[:, BM20_STATE.index(f"gamma{i}")] for i in (1, 2, 3)]
    _, z, l, g = andoyer_deprit(M, gamma)
    return np.column_stack([np.asarray(v, dtype=float) for v in (z, l, g)])


def bm20_map_with_jacobian(
    params: Sequence[float],
    G: float,
    *,
    vary: str = "Omega",
    rtol: float = 1e-11,
    backward: bool = False,
    digits: int | None = None,
) -> SmoothMap:
    """BM20's stroboscopic map in Andoyer-Deprit ``(z, l, g)`` (BM20-3.7, BM20-map), with
    one scalar parameter of the model as the map's parameter.

    One step integrates ``y' = f(t, y)``, ``Phi' = J(t, y) Phi`` (the variational equations
    in C with the generated right-hand side and Jacobian,
    :class:`~chaplygin.numerics.dynamics.variational.VariationalSystem`) over one forcing period
    ``2 pi/Omega`` from ``t = 0`` (``backward``: to ``-2 pi/Omega``, the inverse map) with
    DOP853 at ``rtol = atol``; coordinates by
    :func:`~chaplygin.numerics.ball.map_coordinates.reduced_point` and its inverse; the reduced
    Jacobian solves
    ``E(x1) J = Phi E(x0)`` (``E = d(M, gamma)/d(z, l, g)``, ``Phi`` maps the tangent space
    of the level set ``|M| = G``, ``(M, gamma) = 0``, ``|gamma| = 1`` into itself).

    With ``digits``, the map itself runs at that many decimal digits (the Taylor integrator of
    :class:`~chaplygin.numerics.dynamics.poincare.StroboscopicMap`, tolerance ``10^-digits``) on
    mpmath points, and the Jacobian stays the double-precision one: Newton then converges
    linearly, gaining about ``-log10(rtol)`` digits per step, to an orbit that closes at the
    working precision; its multipliers carry double-precision accuracy.

    Parameters
    ----------
    params : sequence of numbers or decimal strings
        The model's parameter vector (``Omega`` at index 9 is replaced by the map's argument);
        with ``digits``, each is rounded once to the working precision (pass text such as
        ``"4.385"`` to keep a decimal value exact).
    G : float
        The level ``|M| = G`` (BM20: ``G = 3``).
    vary : str
        The map's parameter: a scalar parameter of the model (``"Omega"``, ``"D"``,
        ``"delta"``, ``"J_off"``).
    rtol : float
        Tolerance of the double-precision variational equations.
    backward : bool
    digits : int, optional
        Decimal digits of the map (None: double).

    Returns
    -------
    SmoothMap
        ``f(x, Omega)``, ``df(x, Omega)`` on points ``(z, l, g)``; ``angles = (1, 2)``;
        ``accuracy = 100 rtol`` (``10^(3 - digits)`` with ``digits``).
    """
    from ..code import load_model_code
    from ..dynamics.variational import VariationalSystem

    code = load_model_code("chaplygin_ball", BM20_EFFECTS)
    names = code.params
    exact = list(params)
    base = np.array([float(mpmath.mpf(v)) for v in exact], dtype=float)
    if vary not in ("Omega", "D", "delta", "J_off"):
        raise UserInputError(f"the BM20 map varies Omega, D, delta or J_off, not {vary!r}")
    index = names.index(vary)
    sign = -1.0 if backward else 1.0

    def system(value: float) -> tuple[float, VariationalSystem]:
        p = base.copy()
        p[index] = value
        return sign * 2 * np.pi / p[_OMEGA], VariationalSystem(code, p, rtol=rtol, atol=rtol)

    to_state, to_point = partial(bm20_state, G=G), bm20_point

    def f(x: NDArray, value: float) -> NDArray:
        T, var = system(value)
        # one zero tangent vector: the state alone drives the error control
        flow = var.flow(to_state(x), 0.0, T, V0=np.zeros((len(code.state), 1)))
        return to_point(flow.y)

    def df(x: NDArray, value: float) -> tuple[NDArray, NDArray]:
        T, var = system(value)
        x = np.asarray(x, dtype=float)
        flow = var.flow(to_state(x), 0.0, T)
        x1 = to_point(flow.y)
        J = detlinalg.lstsq(reduced_tangent(x1, G), detlinalg.matmul(flow.V, reduced_tangent(x, G)))
        return x1, J

    if digits is None:
        return SmoothMap(f, df, 3, angles=(1, 2), accuracy=100 * rtol)
    return _bm20_map_at_digits(code, exact, index, G, df, backward, int(digits))


def _bm20_map_at_digits(code, exact, index, G, df_double, backward, digits) -> SmoothMap:
    """The BM20 map at ``digits`` digits with the double-precision Jacobian (see
    :func:`bm20_map_with_jacobian`)."""
    from ..dynamics.poincare import StroboscopicMap

    tol = mpmath.mpf(10) ** (-digits)

    def strobe(value: Any) -> StroboscopicMap:
        p = list(exact)
        p[index] = value
        return StroboscopicMap(code, p, precision=digits, rtol=tol, atol=tol, backward=backward)

    def f(x: Any, value: Any) -> Any:
        with mpmath.workdps(digits):
            y = state_from_reduced(list(x), G, [0] * len(code.state), code.state)
            y1 = strobe(value).step(y)
            return mpmath.matrix(list(reduced_point(list(y1), code.state)[1]))

    def df(x: Any, value: Any) -> tuple[Any, Any]:
        x1 = f(x, value)
        _, J = df_double(np.array([float(v) for v in x]), float(value))
        with mpmath.workdps(digits):
            return x1, mpmath.matrix(J.tolist())

    return SmoothMap(f, df, 3, angles=(1, 2), digits=digits, accuracy=float(1000 * tol))


def reduced_step(smap: Any, x: Sequence, G: object, t0: object = 0) -> np.ndarray:
    """BM20's 3-D map on the level ``|M| = G``, ``(M, gamma) = 0``: ``(z, l, g) -> (z', l',
    g')`` one period of a :class:`~chaplygin.numerics.dynamics.poincare.StroboscopicMap` later
    (BM20 §3.2).

    Parameters
    ----------
    smap : StroboscopicMap
        The stroboscopic map of a model with the state ``(M, gamma)``.
    x : sequence of 3 numbers
        ``(z, l, g)`` (:func:`~chaplygin.numerics.ball.map_coordinates.reduced_point`).
    G : number
        ``|M|``, kept by the flow.
    t0 : number

    Returns
    -------
    ndarray, shape (3,)
        ``(z, l, g)`` after one period, angles in ``[-pi, pi)``.

    References
    ----------
    BM20-3.7, BM20-map.
    """
    state = smap.code.state
    y = state_from_reduced(x, G, [0] * len(state), state)
    return reduced_point(smap.step(y, t0), state)[1]
