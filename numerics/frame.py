"""The horizontal frame ``alpha, beta`` of the contact point: the one rule that completes it.

With the contact point the state carries the body-frame images ``alpha, beta`` of two fixed
horizontal axes (``alpha x beta = gamma``). When a user gives ``M`` and ``gamma`` but no frame,
the frame is completed by this rule, the same for the API (:func:`chaplygin.integrate`), the
command line and scenes (through :func:`chaplygin.numerics.inputs.pack_state`):

* off the line ``M || gamma``: BKM12-7, ``alpha = M x gamma/|M x gamma|``, ``beta = gamma x alpha``;
* on it (``|M x gamma| <= 1e-6 max(|M|, 1)``, where BKM12-7 is undefined or ill-conditioned):
  ``alpha`` is the projection, onto the plane perpendicular to ``gamma``, of the body axis least
  aligned with ``gamma`` (the first of the axes with the smallest ``|gamma_i|``), normalised, and
  ``beta = gamma x alpha`` (:func:`horizontal_frame`). The choice fixes the origin of the
  contact point's azimuth; :attr:`FrameCompletion.note` says it was made (a scene's
  ``initial_how`` shows it). A user who wants another frame gives ``alpha`` and ``beta``.

A frame given by the user is checked (orthonormal, right-handed, within ``tolerance``) and
re-orthonormalised exactly against ``gamma``.

References
----------
BKM12-7 (FORMULAS.md).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mpmath

from ..derive.errors import UserInputError

__all__ = [
    "PARALLEL_FRAME_NOTE",
    "PARALLEL_TOLERANCE",
    "FrameCompletion",
    "complete_frame",
    "horizontal_frame",
    "unit_vector",
]

#: What :func:`complete_frame` reports when ``M || gamma`` made it use :func:`horizontal_frame`.
PARALLEL_FRAME_NOTE = (
    "M || gamma: alpha = the body axis least aligned with gamma, projected "
    "(BKM12-7 is undefined there)"
)

#: ``|M x gamma| <= PARALLEL_TOLERANCE max(|M|, 1)`` is the line ``M || gamma`` for the frame.
PARALLEL_TOLERANCE = 1e-6


@dataclass(frozen=True)
class FrameCompletion:
    """A frame ``alpha, beta`` (lists of mpmath.mpf) and how it was obtained.

    Attributes
    ----------
    alpha, beta : list of mpmath.mpf
    note : str
        Empty for a frame given or built by BKM12-7; :data:`PARALLEL_FRAME_NOTE` on
        ``M || gamma``.
    """

    alpha: list
    beta: list
    note: str = ""


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b, strict=True))


def _norm(v):
    return mpmath.sqrt(sum(x * x for x in v))


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _unit(v):
    n = mpmath.sqrt(_dot(v, v))
    return [x / n for x in v]


def horizontal_frame(gamma: Sequence) -> tuple[list, list]:
    """A right-handed horizontal frame ``alpha, beta`` (``alpha x beta = gamma``) by a fixed rule.

    ``alpha`` is the projection, onto the plane perpendicular to ``gamma``, of the body axis
    least aligned with ``gamma`` (ties: the first such axis), normalised; ``beta = gamma x alpha``.
    Evaluated at the current mpmath precision.

    Parameters
    ----------
    gamma : sequence of 3 numbers
        A unit vector.

    Returns
    -------
    alpha, beta : list of mpmath.mpf
    """
    g = [mpmath.mpf(v) for v in gamma]
    k = min(range(3), key=lambda i: (abs(g[i]), i))
    e = [mpmath.mpf(int(i == k)) for i in range(3)]
    alpha = _unit([a - _dot(e, g) * b for a, b in zip(e, g, strict=True)])
    return alpha, _cross(g, alpha)


def complete_frame(
    M: Sequence,
    gamma: Sequence,
    alpha: Sequence | None = None,
    beta: Sequence | None = None,
    tolerance: float = 1e-9,
    *,
    names: Sequence[str],
) -> FrameCompletion:
    """The frame ``alpha, beta`` for a state ``M, gamma``: checked if given, else by the rule of
    the module (BKM12-7, or :func:`horizontal_frame` on ``M || gamma``).

    Evaluated at the current mpmath precision (callers enter ``mpmath.workdps``).

    Parameters
    ----------
    M : sequence of 3 mpmath.mpf
        The vector the frame is built about (the momentum in BKM12-7).
    gamma : sequence of 3 mpmath.mpf
        A unit vector.
    alpha, beta : sequence of 3 mpmath.mpf, optional
        A frame given by the user (both or neither).
    tolerance : float
        How far a given frame may be from unit, orthogonal and right-handed.
    names : pair of str
        The frame's names in the model (for the messages).

    Returns
    -------
    FrameCompletion

    Raises
    ------
    UserInputError
        Only one of ``alpha`` and ``beta``; a given frame that is not a right-handed
        orthonormal frame with ``alpha x beta = gamma`` within ``tolerance``.

    References
    ----------
    BKM12-7 (FORMULAS.md).
    """
    first, second = names
    if (alpha is None) != (beta is None):
        raise UserInputError(
            f"give both {first} and {second}, or neither (they are then computed)"
        )
    if alpha is not None:
        alpha = unit_vector(first, alpha, tolerance)
        beta = unit_vector(second, beta, tolerance)
        err = max(
            abs(_dot(alpha, beta)),
            *(abs(c - g) for c, g in zip(_cross(alpha, beta), gamma, strict=True)),
        )
        if err > tolerance:
            raise UserInputError(
                "alpha, beta, gamma must be a right-handed orthonormal frame "
                "(gamma = alpha x beta) "
                f"within {tolerance:g}; the error is {mpmath.nstr(err, 6)}"
            )
        # exact re-orthonormalisation against gamma
        a_dot_g = _dot(alpha, gamma)
        alpha = [a - a_dot_g * g for a, g in zip(alpha, gamma, strict=True)]
        n = _norm(alpha)
        alpha = [a / n for a in alpha]
        return FrameCompletion(alpha, _cross(gamma, alpha))
    mxg = _cross(M, gamma)
    s = _norm(mxg)
    if s <= PARALLEL_TOLERANCE * max(_norm(M), mpmath.mpf(1)):
        # BKM12-7 divides by |M x gamma|: on (or next to) the line M || gamma it is undefined
        # (or ill-conditioned); the fixed rule chooses the frame, and says so
        alpha, beta = horizontal_frame(gamma)
        return FrameCompletion(alpha, beta, PARALLEL_FRAME_NOTE)
    alpha = [c / s for c in mxg]  # BKM12-7
    return FrameCompletion(alpha, _cross(gamma, alpha))


def unit_vector(name: str, v: Sequence, tolerance: float) -> list:
    """``v`` normalised, or :class:`UserInputError` if it is further than ``tolerance`` from unit
    length (relatively).

    Parameters
    ----------
    name : str
        The vector's name in the message.
    v : sequence of mpmath.mpf
    tolerance : float

    Returns
    -------
    list of mpmath.mpf

    Raises
    ------
    UserInputError
    """
    n = _norm(v)
    if abs(n - 1) > tolerance:
        raise UserInputError(
            f"{name} must be a unit vector: |{name}| = {mpmath.nstr(n, 12)} differs from 1 by more "
            f"than {tolerance:g}; normalise it (e.g. gamma=0.2,0.3,sqrt(0.87))"
        )
    return [x / n for x in v]
