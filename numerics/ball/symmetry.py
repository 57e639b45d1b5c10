"""Symmetric copies of attractors: which copy a computation reached, named by a stated rule.

The ball's equations are equivariant under ``sigma: (t, M, gamma) -> (t, M, -gamma)``:
``omega = A (M + Z gamma)`` (BKM12-3) and BM20's ``omega = A(t) (M - k(t))`` depend on
``gamma`` only through ``gamma ⊗ gamma`` and ``Z gamma``, both even, and ``gamma' =
gamma x omega`` is odd. The claims BM20-3.1 (every law ``I(t), k(t)``) and BKM12-3.sym
(the autonomous ball, with or without a constant gyrostat) prove it on the generated
equations. ``sigma`` keeps ``t``, so it maps an attractor ``A`` of the stroboscopic map
onto an attractor ``sigma(A)``: a run lands on either copy, depending on the start and, after
a chaotic transient, on the last bits of the arithmetic. (The involutions (3.3) reverse time:
they map attractors onto repellers and relate no two attractors; they are not used here.)
In BM20's Andoyer-Deprit coordinates (3.7) ``sigma`` is ``(z, l, g) -> (z, l, g + pi)``.

**The rule.** Of ``A`` and ``sigma(A)`` the *canonical* copy is the one on which the mean of
the odd function

    ``phi(M, gamma) = (gamma, u) + (gamma, W M)/|M|``  (``M = 0``: the first term alone)

is positive; ``u`` and ``W`` are the fixed generic constants :data:`U` and :data:`W` below
(``phi(M, -gamma) = -phi(M, gamma)``, so the two copies have means of opposite sign). A copy
that ``sigma`` maps onto itself (as a set, within the tolerance; a sample: its mirror image
within three times its own sampling scale or 1 % of its size, 0.9-quantile Hausdorff
distances) is ``"self"``; a sample whose mean is within 5 standard errors (batch means) of
zero is ``"undetermined"`` (the set may be symmetric, or the sample too short). Outputs
report the copy reached (``"canonical"`` or ``"mirror"``) with the symmetry's name,
``symmetric_copy = "gamma -> -gamma"`` for a mirror copy, so that two runs landing on mirror
images report the same canonical orbit.

References
----------
BM20 (3.1)-(3.2) (FORMULAS.md: BM20-3.1, BM20-3.2/3.3); BKM12-3 (BKM12-3.sym).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...arith import detlinalg
from ...derive.errors import UserInputError

__all__ = [
    "Symmetry",
    "CopyName",
    "MIRROR",
    "U",
    "W",
    "COPY_RULE",
    "symmetries_of",
    "mirror_states",
    "copy_statistic",
    "name_copy",
    "canonical_cycle",
    "map_points_scaled",
]

#: Fixed generic constants of the rule (a unit vector and a matrix with no special structure;
#: any other fixed generic choice would do, and would call other copies canonical).
U = np.array([0.6, 0.48, 0.64])
W = np.array([[0.31, -0.72, 0.17], [0.53, 0.11, -0.44], [-0.26, 0.62, 0.35]])
#: Batch means of the sample's statistic, and the standard errors that decide.
BATCHES, DECISIVE = 10, 5.0
#: A sample is its own mirror image when the two lie within this many sampling scales (the
#: distance of the sample's two halves, which a quasi-periodic orbit's correlated halves
#: underestimate: two runs on one invariant curve of BM20 Fig. 4 lie 2.1 scales apart).
SAMPLE_FACTOR = 3.0
#: ... or within this fraction of the sample's size (a near-resonant invariant curve retraces
#: itself, so its halves agree better than two runs on it: 0.4 % of its size apart on BM20
#: Fig. 4's curve, whose mirror image lies as close as another run's sample).
SIZE_FRACTION = 0.01

COPY_RULE = (
    "canonical: the copy on which the mean of phi = (gamma, u) + (gamma, W M)/|M| over the "
    "attractor's points is positive (u = (0.6, 0.48, 0.64), W fixed; chaplygin.numerics."
    "symmetry); 'self': sigma maps the set onto itself (a sample: within 3 sampling scales or "
    "1 % of its size); "
    "'undetermined': |mean| within 5 standard errors"
)

#: Effects with which the ball keeps the symmetry (the contact point is carried along, its
#: states untouched: copies are named from M and gamma alone).
_EFFECTS = {"gyrostat", "variable_inertia", "variable_gyrostat", "contact_point"}


@dataclass(frozen=True)
class Symmetry:
    """A symmetry of the equations that keeps the time: state groups with their signs.

    Attributes
    ----------
    name : str
        ``"gamma -> -gamma"``.
    signs : dict of str to int
        Sign of each state group it changes (``{"gamma": -1}``).
    claims : tuple of str
        The claims that prove it.
    """

    name: str
    signs: dict
    claims: tuple[str, ...]

    def sign_vector(self, state: Sequence[str], groups: dict[str, Sequence[str]]) -> NDArray:
        """The diagonal of the symmetry on a state vector.

        Parameters
        ----------
        state : sequence of str
            The model's state names in order.
        groups : dict of str to sequence of str
            The model's state groups.

        Returns
        -------
        ndarray, shape (n,)
        """
        out = np.ones(len(state))
        for group, sign in self.signs.items():
            for name in groups[group]:
                out[list(state).index(name)] = sign
        return out


#: BM20 (3.1): ``(t, M, gamma) -> (t, M, -gamma)``.
MIRROR = Symmetry(
    "gamma -> -gamma",
    {"gamma": -1},
    ("BM20-3.1", "BM20-3.2/3.3", "BKM12-3.sym", "BKM12-3.sym.gyrostat"),
)


def symmetries_of(code: object) -> tuple[Symmetry, ...]:
    """The symmetries that map attractors of ``code``'s model onto attractors.

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    tuple of Symmetry
        ``(MIRROR,)`` for the Chaplygin ball with any of the effects ``gyrostat``,
        ``variable_inertia``, ``variable_gyrostat``, ``contact_point``; empty otherwise.
    """
    groups = code.state_groups
    if (
        code.system == "chaplygin_ball"
        and set(code.effects) <= _EFFECTS
        and {"M", "gamma"} <= set(groups)
    ):
        return (MIRROR,)
    return ()


def mirror_states(y: ArrayLike, state: Sequence[str]) -> NDArray[np.float64]:
    """``sigma`` applied to states (``gamma -> -gamma``, everything else kept).

    Parameters
    ----------
    y : array_like, shape (..., n)
    state : sequence of str
        State names (``gamma1``, ``gamma2``, ``gamma3`` are flipped).

    Returns
    -------
    ndarray, shape (..., n)
    """
    y = np.array(y, dtype=float)
    for i, name in enumerate(state):
        if name in ("gamma1", "gamma2", "gamma3"):
            y[..., i] = -y[..., i]
    return y


def map_points_scaled(y: ArrayLike, state: tuple[str, ...]) -> NDArray[np.float64]:
    """The map points in ``(M/|M|, gamma)`` (``M`` left as is where ``|M| = 0``): coordinates
    of size one, in which a closing tolerance is relative.

    Parameters
    ----------
    y : array_like, shape (n_points, n)
    state : tuple of str

    Returns
    -------
    ndarray, shape (n_points, 6)
    """
    y = np.atleast_2d(np.asarray(y, dtype=float))
    m = [state.index(f"M{i}") for i in (1, 2, 3)]
    g = [state.index(f"gamma{i}") for i in (1, 2, 3)]
    M = y[:, m]
    norm = np.sqrt(M[:, 0] * M[:, 0] + M[:, 1] * M[:, 1] + M[:, 2] * M[:, 2])[:, None]
    return np.hstack([np.where(norm > 0, M / np.where(norm > 0, norm, 1.0), M), y[:, g]])


def _columns(state: Sequence[str]) -> tuple[list[int], list[int]]:
    state = list(state)
    try:
        return (
            [state.index(f"M{i}") for i in (1, 2, 3)],
            [state.index(f"gamma{i}") for i in (1, 2, 3)],
        )
    except ValueError:
        raise UserInputError(f"naming a symmetric copy needs M and gamma, got {state}") from None


def _phi(y: NDArray, state: Sequence[str]) -> NDArray:
    m, g = _columns(state)
    M, gamma = y[:, m], y[:, g]
    # elementwise products summed in a fixed order (no BLAS, no einsum kernels: the same bits
    # on every processor)
    norm = np.sqrt(M[:, 0] * M[:, 0] + M[:, 1] * M[:, 1] + M[:, 2] * M[:, 2])
    WM = [W[i, 0] * M[:, 0] + W[i, 1] * M[:, 1] + W[i, 2] * M[:, 2] for i in range(3)]
    bilinear = gamma[:, 0] * WM[0] + gamma[:, 1] * WM[1] + gamma[:, 2] * WM[2]
    with np.errstate(invalid="ignore", divide="ignore"):
        scaled = np.where(norm > 0, bilinear / np.where(norm > 0, norm, 1.0), 0.0)
    return gamma[:, 0] * U[0] + gamma[:, 1] * U[1] + gamma[:, 2] * U[2] + scaled


def copy_statistic(y: ArrayLike, state: Sequence[str]) -> tuple[float, float]:
    """Mean of ``phi`` over the points and its standard error (batch means over 10 batches;
    0 for fewer than 10 points).

    Parameters
    ----------
    y : array_like, shape (n, n_state)
        Points of the attractor (states).
    state : sequence of str

    Returns
    -------
    (mean, error) : (float, float)
    """
    y = np.atleast_2d(np.asarray(y, dtype=float))
    values = _phi(y, state)
    mean = math.fsum(values) / len(values)  # correctly rounded sums: no kernel-dependent order
    if len(values) < BATCHES:
        return mean, 0.0
    usable = (len(values) // BATCHES) * BATCHES
    rows = values[len(values) - usable :].reshape(BATCHES, -1)
    batches = [math.fsum(row) / len(row) for row in rows]
    centre = math.fsum(batches) / BATCHES
    spread = math.sqrt(math.fsum((b - centre) ** 2 for b in batches) / (BATCHES - 1))
    return mean, spread / math.sqrt(BATCHES)


@dataclass(frozen=True)
class CopyName:
    """Which copy of an attractor was reached.

    Attributes
    ----------
    symmetry : str
        The symmetry's name (``"gamma -> -gamma"``).
    copy : str
        ``"canonical"``, ``"mirror"`` (the symmetry's image of the canonical copy), ``"self"``
        or ``"undetermined"``.
    statistic, error : float
        The mean of ``phi`` over the points reached and its standard error (or the
        tolerance, for a periodic orbit).
    rule : str
        :data:`COPY_RULE`.
    """

    symmetry: str
    copy: str
    statistic: float
    error: float
    rule: str = COPY_RULE

    @property
    def symmetric_copy(self) -> str:
        """The symmetry that maps the canonical copy onto the one reached: its name for a
        mirror copy, ``"none"`` for the canonical or a self-symmetric one, ``"undetermined"``.

        Returns
        -------
        str
        """
        return {"mirror": self.symmetry, "undetermined": "undetermined"}.get(self.copy, "none")

    @property
    def code(self) -> int:
        """0 canonical, 1 mirror, 2 self, -1 undetermined (for stores).

        Returns
        -------
        int
        """
        return {"canonical": 0, "mirror": 1, "self": 2}.get(self.copy, -1)

    def summary(self) -> dict:
        """The fields an output reports.

        Returns
        -------
        dict
        """
        return {
            "symmetry": self.symmetry,
            "copy_reached": self.copy,
            "symmetric_copy": self.symmetric_copy,
            "statistic": f"{self.statistic:.6g} +- {self.error:.2g}",
            "rule": self.rule,
        }


def _set_invariant(y: NDArray, state: Sequence[str], tol: float) -> bool:
    """Every mirrored point has a point of the set within ``tol`` (max norm)."""
    mirrored = mirror_states(y, state)
    d = np.max(np.abs(mirrored[:, None, :] - y[None, :, :]), axis=2)
    return bool(np.all(d.min(axis=1) <= tol))


def name_copy(
    y: ArrayLike,
    state: Sequence[str],
    *,
    periodic: bool = False,
    tol: float = 0.0,
    symmetry: Symmetry = MIRROR,
) -> CopyName:
    """Name the copy of an attractor that the points ``y`` sample.

    Parameters
    ----------
    y : array_like, shape (n, n_state)
        States on the attractor: the points of a periodic orbit (``periodic=True``), or a
        sample of map points.
    state : sequence of str
        State names (``M1..M3``, ``gamma1..gamma3`` are used).
    periodic : bool
        The points are a periodic orbit, exact to ``tol``: ``"self"`` when the mirrored
        orbit is the orbit (each mirrored point within ``tol`` of one of its points). A
        sample (20 points or more) is ``"self"`` when its mirror image lies within
        :data:`SAMPLE_FACTOR` sampling scales (the distance between its two halves), or
        :data:`SIZE_FRACTION` of its size, of it.
    tol : float
        Tolerance of the points (max norm, state units).
    symmetry : Symmetry
        Only :data:`MIRROR` is known.

    Returns
    -------
    CopyName

    Raises
    ------
    UserInputError
        No points, no M and gamma, or another symmetry.
    """
    if symmetry is not MIRROR:
        raise UserInputError(f"only the symmetry {MIRROR.name!r} is known")
    y = np.atleast_2d(np.asarray(y, dtype=float))
    if not len(y):
        raise UserInputError("naming a symmetric copy needs points")
    mean, error = copy_statistic(y, state)
    if periodic:  # the mean over the exact cycle: its error is the points' (|d phi| <= 4 |d y|)
        error = 4 * float(tol)
        if _set_invariant(y, state, 10 * tol):
            return CopyName(symmetry.name, "self", mean, error)
    elif len(y) >= 2 * BATCHES and _sample_invariant(y, state):
        return CopyName(symmetry.name, "self", mean, error)
    if abs(mean) <= DECISIVE * error or mean == 0:
        return CopyName(symmetry.name, "undetermined", mean, error)
    return CopyName(symmetry.name, "canonical" if mean > 0 else "mirror", mean, error)


def _sample_invariant(y: NDArray, state: Sequence[str]) -> bool:
    """A sample whose mirror image lies within 3 of its own sampling scales, or 1 % of its size,
    of it: the 0.9-quantile Hausdorff distance
    (:func:`~chaplygin.numerics.dynamics.reversibility.set_distance`) of the sample and its mirror,
    in ``(M/|M|, gamma)``, against that of its two halves or the diagonal of its bounding box. (The
    mean of ``phi`` over a quasi-periodic sample converges like ``1/N``, and so does its batch
    error: on a symmetric invariant curve it could look decisive.)"""
    from ..dynamics.reversibility import set_distance

    x = map_points_scaled(y, tuple(state))
    xm = map_points_scaled(mirror_states(y, state), tuple(state))
    half = len(x) // 2
    size = detlinalg.norm(np.ptp(x, axis=0))  # the diagonal of its bounding box
    scale = max(SAMPLE_FACTOR * set_distance(x[:half], x[half:]), SIZE_FRACTION * size)
    return set_distance(x, xm) <= scale


def canonical_cycle(points: ArrayLike, state: Sequence[str], copy: CopyName) -> NDArray:
    """A periodic orbit as its canonical copy, starting at a fixed point of the cycle.

    The mirror copy is mapped back by the symmetry; the cycle then starts at its point of
    largest ``phi`` (so two runs reaching the orbit at different points of the cycle print
    the same list).

    Parameters
    ----------
    points : array_like, shape (p, n_state)
        The orbit's states in order.
    state : sequence of str
    copy : CopyName
        From :func:`name_copy`.

    Returns
    -------
    ndarray, shape (p, n_state)
    """
    y = np.atleast_2d(np.asarray(points, dtype=float))
    if copy.copy == "mirror":
        y = mirror_states(y, state)
    start = int(np.argmax(_phi(y, state)))
    return np.roll(y, -start, axis=0)
