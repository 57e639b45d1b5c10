"""Attractors and repellers of reversible maps (BM20 §3, involutions (3.3)).

For ``I(-t) = I(t)`` and ``k(-t) = -k(t)`` (BM20 (3.2); ``J_off = 0`` in (3.4)-(3.5)) the
involution ``R1: (t, M, gamma) -> (-t, -M, gamma)`` (and ``R2: (-t, -M, -gamma)``) maps
solutions to solutions (claims BM20-3.2/3.3, BM20-3.4.J0). On the stroboscopic section
``t = 0 mod 2 pi/Omega`` it conjugates the map to its inverse, ``R P R = P^-1``, so the
image ``R(A)`` of an attractor ``A`` of ``P`` is an attractor of ``P^-1``: a repeller of
``P``. Here both are *sampled*: ``A`` by iterating ``P`` from one state, the repeller by
iterating ``P^-1`` (integrating backwards in time) from another, unrelated state; the two
point sets are compared by a quantile Hausdorff distance against the distance between two
independent samples of ``A`` itself (the sampling scale).

References
----------
BM20 §3, (3.2)-(3.3); D. P. Huttenlocher, G. A. Klanderman, W. J. Rucklidge, "Comparing
images using the Hausdorff distance", IEEE TPAMI 15 (1993) (the partial, quantile
Hausdorff distance); J. S. W. Lamb, J. A. G. Roberts, "Time-reversal symmetry in dynamical
systems: a survey", Physica D 112 (1998) (attractor-repeller pairs of reversible maps).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from ...arith import detlinalg
from ...derive.errors import UserInputError
from ..code import ModelCode

__all__ = [
    "set_distance",
    "stroboscopic_samples",
    "AttractorRepellerPair",
    "attractor_repeller_pair",
    "INVOLUTIONS",
]

#: The involutions (3.3) on the section t = 0, as sign vectors on (M, gamma).
INVOLUTIONS = {
    "R1 (M, gamma) -> (-M, gamma)": np.array([-1.0, -1, -1, 1, 1, 1]),
    "R2 (M, gamma) -> (-M, -gamma)": np.array([-1.0, -1, -1, -1, -1, -1]),
}


def set_distance(a: ArrayLike, b: ArrayLike, quantile: float = 0.9) -> float:
    """Quantile Hausdorff distance between two point sets.

    ``max(q-quantile of d(a_i, b), q-quantile of d(b_j, a))``, ``d`` the Euclidean distance
    to the nearest point of the other set; ``quantile = 1`` is the Hausdorff distance. A
    quantile below 1 ignores the rarest excursions, which finite samples of a strange
    attractor meet or miss by chance.

    Parameters
    ----------
    a, b : array_like, shape (n, dim) and (m, dim)
    quantile : float
        In ``(0, 1]``.

    Returns
    -------
    float

    Raises
    ------
    UserInputError
        Empty sets, different dimensions or a quantile outside ``(0, 1]``.
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.ndim != 2 or b.ndim != 2 or a.shape[1] != b.shape[1] or not len(a) or not len(b):
        raise UserInputError(f"need two non-empty (n, dim) point sets, got {a.shape}, {b.shape}")
    if not 0 < quantile <= 1:
        raise UserInputError(f"the quantile must be in (0, 1], got {quantile}")
    da = cKDTree(b).query(a)[0]
    db = cKDTree(a).query(b)[0]
    return float(max(np.quantile(da, quantile), np.quantile(db, quantile)))


def stroboscopic_samples(
    code: ModelCode,
    params: Sequence[float],
    y0: ArrayLike,
    n: int,
    *,
    transient: int = 500,
    backward: bool = False,
    rtol: float = 1e-10,
) -> NDArray[np.float64]:
    """States at ``t = j 2 pi/Omega`` (``-j`` when ``backward``), ``j = transient + 1 ..
    transient + n``: :meth:`~chaplygin.numerics.dynamics.poincare.StroboscopicMap.orbit` in double.

    Parameters
    ----------
    code : ModelCode
        A BM20 model (``Omega`` among its parameters).
    params : sequence of float
        The parameter vector in the model's order.
    y0 : array_like
        Initial state at ``t = 0``.
    n : int
        Number of states kept.
    transient : int
        Periods discarded first.
    backward : bool
        Iterate the inverse map (integrate backwards in time).
    rtol : float
        Tolerance of the compiled Taylor integrator (``atol = rtol``).

    Returns
    -------
    ndarray, shape (n, dim)

    Raises
    ------
    ComputationError
        The integration failed.
    """
    from .poincare import StroboscopicMap

    strobe = StroboscopicMap(code, params, rtol=rtol, atol=rtol, backward=backward)
    orbit = strobe.orbit(np.asarray(y0, dtype=float), n, transient=transient + 1)
    return np.asarray(orbit.y, dtype=float)


@dataclass
class AttractorRepellerPair:
    """Distances between an attractor, its images and a repeller (all in ``(M/G, gamma)``).

    Attributes
    ----------
    image_distance : dict of str to float
        ``set_distance(R(A), repeller)`` for each involution of :data:`INVOLUTIONS`.
    sampling_distance : float
        ``set_distance(A, A')``, ``A'`` a second, independent sample of the attractor.
    attractor_distance : float
        ``set_distance(A, repeller)`` (the control: no involution applied).
    attractor, second_attractor, repeller : ndarray, shape (n, 6)
    quantile : float
    """

    image_distance: dict[str, float]
    sampling_distance: float
    attractor_distance: float
    attractor: NDArray[np.float64]
    second_attractor: NDArray[np.float64]
    repeller: NDArray[np.float64]
    quantile: float


def attractor_repeller_pair(
    code: ModelCode,
    params: Sequence[float],
    starts: Sequence[ArrayLike],
    *,
    n: int = 2000,
    transient: int = 500,
    rtol: float = 1e-10,
    quantile: float = 0.9,
) -> AttractorRepellerPair:
    """Sample an attractor twice and a repeller once, and compare them.

    Parameters
    ----------
    code : ModelCode
    params : sequence of float
    starts : sequence of three states
        Starts of the attractor, of its second sample and of the repeller (backward map);
        three unrelated states.
    n, transient : int
        Samples kept, periods discarded.
    rtol : float
    quantile : float
        Of :func:`set_distance`.

    Returns
    -------
    AttractorRepellerPair

    Raises
    ------
    UserInputError
        Not three starts.
    ComputationError
        An integration failed.
    """
    if len(starts) != 3:
        raise UserInputError("give three initial states: attractor, its second sample, repeller")
    G = detlinalg.norm(np.asarray(starts[0], dtype=float)[:3])
    scale = np.array([1 / G] * 3 + [1.0] * 3) if G > 0 else np.ones(6)

    def sample(y0, backward):
        return scale * stroboscopic_samples(
            code, params, y0, n, transient=transient, backward=backward, rtol=rtol
        )

    A = sample(starts[0], False)
    A2 = sample(starts[1], False)
    rep = sample(starts[2], True)
    return AttractorRepellerPair(
        image_distance={k: set_distance(s * A, rep, quantile) for k, s in INVOLUTIONS.items()},
        sampling_distance=set_distance(A, A2, quantile),
        attractor_distance=set_distance(A, rep, quantile),
        attractor=A,
        second_attractor=A2,
        repeller=rep,
        quantile=quantile,
    )
