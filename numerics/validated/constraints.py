"""Invariant relations that tighten an enclosure: a box of states is intersected with what a
relation the flow keeps allows (``|gamma|^2 = 1``: each component within
``+- sqrt(1 - the others' squares)``). Only relations proved to be kept (a claim proved
symbolically, e.g. BKM12-5.F0) may be given: the intersection assumes them.

References
----------
BKM12-5.F0 (FORMULAS.md); Nedialkov, Jackson & Pryce (2001) on constraints in validated
integration.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from flint import arb

from ...derive.errors import ComputationError, UserInputError
from .lohner import to_ball

__all__ = ["unit_norm"]


def unit_norm(indices: Sequence[int], value: Any = 1) -> Callable[[list], list]:
    """A tightening for ``sum_i y_i^2 = value`` over the components ``indices``.

    Parameters
    ----------
    indices : sequence of int
        The components (e.g. ``(3, 4, 5)`` for ``gamma`` in ``M, gamma``).
    value : number, optional
        The relation's value (``1`` for a unit vector; a ball or decimal string allowed).

    Returns
    -------
    callable
        ``box -> box``: each component intersected with ``[-sqrt(u), sqrt(u)]``, ``u`` the
        upper bound of ``value`` minus the others' squares, and, where its sign is known,
        with ``+-sqrt(value - the others' squares)``.

    Raises
    ------
    UserInputError
        Fewer than two distinct non-negative indices.

    Examples
    --------
    >>> from flint import arb
    >>> box = [arb("0.6", 1e-6), arb("0.8", 1e-6), arb(0, 0.5)]
    >>> tight = unit_norm((0, 1, 2))(box)  # gamma3 only within +-sqrt(2.8e-6)
    >>> float(tight[2].rad()) < 2e-3
    True
    """
    idx = list(indices)
    if (
        len(set(idx)) != len(idx)
        or len(idx) < 2
        or any(not isinstance(i, int) or i < 0 for i in idx)
    ):
        raise UserInputError(f"indices must be two or more distinct components, got {indices!r}")

    def tighten(box: list) -> list:
        out = list(box)
        total = to_ball(value)
        for i in idx:
            rest = total - sum((out[j] * out[j] for j in idx if j != i), arb(0))
            upper = arb(rest.upper())
            if upper < 0:
                raise ComputationError("the box has no point on the invariant relation")
            bound = upper.sqrt()
            allowed = arb(0).union(bound).union(-bound)
            x = out[i]
            if x > 0 or x < 0:
                low = arb(rest.lower())
                magnitude = (low.sqrt() if low > 0 else arb(0)).union(bound)
                allowed = magnitude if x > 0 else -magnitude
            try:
                out[i] = x.intersection(allowed)
            except ValueError:
                raise ComputationError("the box has no point on the invariant relation") from None
        return out

    return tighten
