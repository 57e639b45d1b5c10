"""Coordinates of Poincaré maps: Andoyer-Deprit ``(G, z, l, g)`` (BM20 (3.7)) with the inverse,
BM20's cylindrical ``(z, l)`` for motion from rest (BM20 §3.1), and expressions of the state.

Every function works on numbers or arrays of the working precision: ``float``/``float64``
arrays with numpy, ``mpmath.mpf`` (or object arrays of them, from quad and digits runs) with
mpmath, so that a map computed at 34 digits keeps its 34 digits in its coordinates.

Conventions (BM20 (3.7)): ``M = (G s sin l, G s cos l, G z)``, ``s = sqrt(1 - z^2)``,
``gamma = (z cos g sin l + sin g cos l, z cos g cos l - sin g sin l, -s cos g)`` on the level
``(M, gamma) = 0``, ``|gamma| = 1``; ``z in [-1, 1]``, ``l, g in [-pi, pi)``.
At the poles ``z = +-1`` (``M`` along the third axis) ``l`` is not defined: only ``l + g``
(``z = 1``) or ``g - l`` (``z = -1``) is. There :func:`andoyer_deprit` returns ``l = 0`` and puts
the whole angle into ``g``, and :func:`from_andoyer_deprit` of that triple gives back the state.

References
----------
BM20-3.7, BM20-map (``docs FORMULAS.md``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ...arith import detmath
from ...derive.errors import UserInputError
from ..dynamics.state_expression import (
    StateExpression,
    is_exact,
    number_ops,
    scalar_or_array,
    wrap_angle,
)

__all__ = [
    "andoyer_deprit",
    "from_andoyer_deprit",
    "cylindrical",
    "from_cylindrical",
    "wrap_angle",
    "reduced_point",
    "state_from_reduced",
    "StateExpression",
    "COORDINATE_SYSTEMS",
]

#: Named coordinate systems of maps: name -> the coordinate names.
COORDINATE_SYSTEMS: dict[str, tuple[str, ...]] = {
    "andoyer": ("z", "l", "g"),
    "cylindrical": ("z", "l"),
}


def andoyer_deprit(M: Sequence, gamma: Sequence) -> tuple[Any, Any, Any, Any]:
    """Andoyer-Deprit variables ``(G, z, l, g)`` (BM20 (3.7)) of a state.

    ``G = |M|``, ``z = M3/G`` (Deprit's ``L/G``), ``l = atan2(M1, M2)``; ``g`` is the angle of
    the part of ``gamma`` normal to ``M`` in the frame ``e_a, e_b`` of :func:`from_andoyer_deprit`:
    ``sin g ~ gamma1 cos l - gamma2 sin l``, ``cos g ~ z (gamma1 sin l + gamma2 cos l) -
    sqrt(1 - z^2) gamma3`` (both from (3.7), and well conditioned at every ``z``, poles
    included). On BM20's level ``(M, gamma) = 0`` this inverts (3.7); for ``(M, gamma) = H != 0``
    (K01) it gives Deprit's variables, inverted by ``from_andoyer_deprit(..., H=H)``.

    Parameters
    ----------
    M, gamma : sequence of 3 numbers or of 3 arrays (shape ``(n,)``)
        Components; float or ``mpmath.mpf`` (the result has their precision).

    Returns
    -------
    G, z, l, g : numbers or arrays
        ``G >= 0``, ``z in [-1, 1]``, angles in ``[-pi, pi)``. At ``G = 0`` (no momentum)
        ``z, l`` are not defined: ``z = 1``, ``l = 0`` and ``g`` from ``gamma`` (so that
        :func:`from_andoyer_deprit` still gives back ``gamma``). At ``z = +-1``, ``l = 0``.

    References
    ----------
    BM20-3.7.
    """
    ops = number_ops(*M, *gamma)
    M1, M2, M3 = (np.asarray(c) for c in M)
    g1, g2, g3 = (np.asarray(c) for c in gamma)
    rho = ops.sqrt(M1 * M1 + M2 * M2)
    G = ops.sqrt(rho * rho + M3 * M3)
    zero_G = G == 0
    safe_G = np.where(zero_G, 1, G)
    z = np.where(zero_G, 1, M3 / safe_G)
    s = np.where(zero_G, 0, rho / safe_G)  # sqrt(1 - z^2), without cancellation near the poles
    pole = rho == 0
    l_ = np.where(pole, ops.zero, ops.atan2(np.where(pole, 0, M1), np.where(pole, 1, M2)))
    sl, cl = ops.sin(l_), ops.cos(l_)
    sin_g = g1 * cl - g2 * sl
    cos_g = z * (g1 * sl + g2 * cl) - s * g3
    g = ops.atan2(sin_g, cos_g)
    return (
        scalar_or_array(G),
        scalar_or_array(z),
        scalar_or_array(wrap_angle(l_)),
        scalar_or_array(wrap_angle(g)),
    )


def from_andoyer_deprit(G: Any, z: Any, l: Any, g: Any, H: Any = 0) -> tuple[list, list]:
    """``M, gamma`` from Andoyer-Deprit variables; inverse of :func:`andoyer_deprit`.

    With ``m = M/G = (s sin l, s cos l, z)``, ``e_a = (z sin l, z cos l, -s)`` and
    ``e_b = (cos l, -sin l, 0)`` (an orthonormal frame, ``s = sqrt(1 - z^2)``):
    ``gamma = (H/G) m + sqrt(1 - H^2/G^2) (cos g e_a + sin g e_b)``, ``H = (M, gamma)``.
    For ``H = 0`` this is BM20 (3.7) term by term.

    Parameters
    ----------
    G, z, l, g : numbers or arrays of one shape
        ``G >= 0``, ``|z| <= 1`` (not checked here: see
        :func:`chaplygin.numerics.ball.initial_state.state_from_andoyer` for user input).
    H : number, optional
        The constant of areas ``(M, gamma)``, ``|H| <= G`` (default 0, BM20's level set).

    Returns
    -------
    M, gamma : list of 3 numbers or arrays
        ``(M, gamma) = H``, ``|gamma| = 1``, ``|M| = G`` to rounding.

    References
    ----------
    BM20-3.7.
    """
    ops = number_ops(G, z, l, g, H)
    z_ = np.asarray(z)
    s = ops.sqrt(np.maximum(1 - z_ * z_, 0) if z_.dtype != object else 1 - z_ * z_)
    sl, cl, sg, cg = ops.sin(l), ops.cos(l), ops.sin(g), ops.cos(g)
    M = [G * s * sl, G * s * cl, G * z_]
    gamma = [z_ * cg * sl + sg * cl, z_ * cg * cl - sg * sl, -s * cg]
    if np.any(np.asarray(H) != 0):
        c = H / np.asarray(G)
        rho = ops.sqrt(1 - c * c)
        m = [s * sl, s * cl, z_]
        gamma = [c * mk + rho * gk for mk, gk in zip(m, gamma, strict=True)]
    return [scalar_or_array(c) for c in M], [scalar_or_array(c) for c in gamma]


def cylindrical(gamma: Sequence) -> tuple[Any, Any]:
    """BM20 §3.1's cylindrical coordinates ``(z, l)`` of ``gamma`` (motion from rest).

    ``gamma = (sqrt(1 - z^2) sin l, sqrt(1 - z^2) cos l, z)``, so ``z = gamma3`` and
    ``l = atan2(gamma1, gamma2)`` (``l = 0`` at the poles ``z = +-1``).

    Parameters
    ----------
    gamma : sequence of 3 numbers or arrays

    Returns
    -------
    z, l : numbers or arrays
        ``l`` in ``[-pi, pi)``.

    References
    ----------
    BM20-map.
    """
    ops = number_ops(*gamma)
    g1, g2, g3 = (np.asarray(c) for c in gamma)
    pole = (g1 == 0) & (g2 == 0)
    l_ = np.where(pole, ops.zero, ops.atan2(np.where(pole, 0, g1), np.where(pole, 1, g2)))
    return scalar_or_array(g3), scalar_or_array(wrap_angle(l_))


def from_cylindrical(z: Any, l: Any) -> list:
    """``gamma`` from BM20 §3.1's ``(z, l)``; inverse of :func:`cylindrical`.

    Parameters
    ----------
    z, l : numbers or arrays

    Returns
    -------
    list of 3 numbers or arrays

    References
    ----------
    BM20-map.
    """
    ops = number_ops(z, l)
    z_ = np.asarray(z)
    s = ops.sqrt(np.maximum(1 - z_ * z_, 0) if z_.dtype != object else 1 - z_ * z_)
    return [scalar_or_array(s * ops.sin(l)), scalar_or_array(s * ops.cos(l)), scalar_or_array(z_)]


# ------------------------------------------------------------- BM20's reduced 3-D map (G fixed)
def _indices(state_names: Sequence[str]) -> tuple[list[int], list[int]]:
    try:
        M = [list(state_names).index(f"M{i}") for i in (1, 2, 3)]
        gamma = [list(state_names).index(f"gamma{i}") for i in (1, 2, 3)]
    except ValueError:
        raise UserInputError(
            f"reduced coordinates need the states M1..M3, gamma1..gamma3; got "
            f"{', '.join(state_names)}"
        ) from None
    return M, gamma


def reduced_point(y: Sequence, state_names: Sequence[str]) -> tuple[Any, np.ndarray]:
    """A state on BM20's level set ``(M, gamma) = 0`` as ``G`` and the point ``(z, l, g)`` of the
    3-D map (BM20 §3.2).

    Parameters
    ----------
    y : sequence
        The state vector (float or mpf) in the model's order.
    state_names : sequence of str
        The model's state names (``ModelCode.state``).

    Returns
    -------
    G : number
    x : ndarray, shape (3,)
        ``(z, l, g)``; at the poles ``z = +-1``, ``l = 0`` (see :func:`andoyer_deprit`).

    Raises
    ------
    UserInputError
        The model has no ``M`` and ``gamma``.

    References
    ----------
    BM20-3.7.
    """
    iM, ig = _indices(state_names)
    G, z, l, g = andoyer_deprit([y[i] for i in iM], [y[i] for i in ig])
    return G, np.array([z, l, g], dtype=object if is_exact(G) else float)


def state_from_reduced(
    x: Sequence, G: Any, y_template: Sequence, state_names: Sequence[str]
) -> list:
    """The state with Andoyer-Deprit ``(G, z, l, g)``, ``x = (z, l, g)``; inverse of
    :func:`reduced_point`.

    Parameters
    ----------
    x : sequence of 3 numbers
        ``(z, l, g)``; ``|z| <= 1`` (clipped to it: a Newton step may overshoot the pole).
    G : number
        ``|M|``.
    y_template : sequence
        A state supplying the other components (none for BM20's ``M, gamma``).
    state_names : sequence of str

    Returns
    -------
    list
        The state vector.

    References
    ----------
    BM20-3.7.
    """
    iM, ig = _indices(state_names)
    z = x[0]
    z = max(min(z, 1), -1)
    M, gamma = from_andoyer_deprit(G, z, x[1], x[2])
    y = list(y_template)
    for k in range(3):
        y[iM[k]], y[ig[k]] = M[k], gamma[k]
    return y


def reduced_tangent(x: Sequence, G: float) -> np.ndarray:
    """The derivative ``d(M, gamma)/d(z, l, g)`` of :func:`state_from_reduced` (double).

    Parameters
    ----------
    x : sequence of 3 floats
        ``(z, l, g)`` with ``|z| < 1`` (the chart is singular at the poles).
    G : float
        ``|M|``.

    Returns
    -------
    ndarray, shape (6, 3)
        Rows ``M1, M2, M3, gamma1, gamma2, gamma3``; columns ``z, l, g``.

    Raises
    ------
    UserInputError
        ``|z| >= 1``.

    References
    ----------
    BM20-3.7.
    """
    z, l, g = (float(v) for v in x)
    if not abs(z) < 1:
        raise UserInputError(f"the Andoyer-Deprit chart is singular at z = {z} (|z| must be < 1)")
    G = float(G)
    s = math.sqrt(1 - z * z)
    ds = -z / s
    sl, cl, sg, cg = detmath.sin(l), detmath.cos(l), detmath.sin(g), detmath.cos(g)
    return np.array(
        [
            [G * ds * sl, G * s * cl, 0.0],
            [G * ds * cl, -G * s * sl, 0.0],
            [G, 0.0, 0.0],
            [cg * sl, z * cg * cl - sg * sl, -z * sg * sl + cg * cl],
            [cg * cl, -z * cg * sl - sg * cl, -z * sg * cl - cg * sl],
            [-ds * cg, 0.0, s * sg],
        ]
    )


# --------------------------------------------------------------------- expressions of the state
