"""Vectors fixed in space and seen from the body: their constraints and exact samples.

A *Poisson group* is a set of unit vectors fixed in space whose body-frame components
obey the Poisson equations ``X' = X x omega``: the vertical ``gamma`` alone (a point of
the unit sphere), or the right-handed orthonormal triple ``alpha, beta, gamma`` (a
rotation). The group knows the polynomial constraints it lives on and how to draw an
exact rational point of that variety (used by the ``exact-sampled`` verdicts).
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import sympy as sp

from .vectors import cross, dot

__all__ = ["PoissonGroup", "UNIT_VECTOR", "FRAME"]

UNIT_VECTOR = "unit_vector"
FRAME = "frame"


@dataclass(frozen=True)
class PoissonGroup:
    """Space-fixed unit vectors in body coordinates.

    Parameters
    ----------
    kind : {"unit_vector", "frame"}
        ``unit_vector``: one vector on the unit sphere. ``frame``: three vectors
        ``(alpha, beta, gamma)``, orthonormal and right-handed (``gamma = alpha x beta``).
    names : tuple of str
        State-group names of the vectors, in order (``("gamma",)`` or
        ``("alpha", "beta", "gamma")``).
    """

    kind: str
    names: tuple[str, ...]

    def __post_init__(self) -> None:
        expected = {UNIT_VECTOR: 1, FRAME: 3}
        if self.kind not in expected or len(self.names) != expected[self.kind]:
            raise ValueError(f"bad Poisson group {self.kind!r} with names {self.names}")

    def constraints(self, vectors: dict[str, sp.Matrix]) -> list[sp.Expr]:
        """Polynomials vanishing on the group's variety.

        For a frame the constraints are ``gamma - alpha x beta = 0`` and the
        orthonormality of ``alpha, beta``; they imply ``|gamma| = 1`` and
        ``gamma`` orthogonal to both.

        Parameters
        ----------
        vectors : dict of str to sympy.Matrix
            Body-frame vectors (shape (3, 1)) by name; must contain ``names``.

        Returns
        -------
        list of sympy.Expr
            One polynomial for a unit vector; six (three components, two norms, one
            scalar product) for a frame.
        """
        if self.kind == UNIT_VECTOR:
            (g,) = (vectors[n] for n in self.names)
            return [dot(g, g) - 1]
        a, b, g = (vectors[n] for n in self.names)
        return [*(g - cross(a, b)), dot(a, a) - 1, dot(b, b) - 1, dot(a, b)]

    def sample_rational(self, rng: random.Random, height: int = 9) -> dict[str, list[sp.Rational]]:
        """An exact rational point of the variety, as ``{name: [c1, c2, c3]}``.

        A unit vector comes from the inverse stereographic projection of a random
        rational point; a frame from the rotation matrix of a random integer
        quaternion (Euler–Rodrigues), whose entries are rational.

        Parameters
        ----------
        rng : random.Random
            Source of the random integers (the caller seeds it).
        height : int, optional
            Bound on the numerators and denominators drawn (stereographic
            coordinates) or on the quaternion's integer entries.

        Returns
        -------
        dict of str to list of three sympy.Rational
            The components of each vector of the group, by name.
        """

        def r() -> sp.Rational:
            return sp.Rational(rng.randint(-height, height), rng.randint(1, height))

        if self.kind == UNIT_VECTOR:
            s, t = r(), r()
            n = 1 + s**2 + t**2
            return {self.names[0]: [2 * s / n, 2 * t / n, (1 - s**2 - t**2) / n]}
        while True:
            q0, q1, q2, q3 = (sp.Integer(rng.randint(-height, height)) for _ in range(4))
            n = q0**2 + q1**2 + q2**2 + q3**2
            if n != 0:
                break
        rot = (
            sp.Matrix(
                [
                    [
                        q0**2 + q1**2 - q2**2 - q3**2,
                        2 * (q1 * q2 - q0 * q3),
                        2 * (q1 * q3 + q0 * q2),
                    ],
                    [
                        2 * (q1 * q2 + q0 * q3),
                        q0**2 - q1**2 + q2**2 - q3**2,
                        2 * (q2 * q3 - q0 * q1),
                    ],
                    [
                        2 * (q1 * q3 - q0 * q2),
                        2 * (q2 * q3 + q0 * q1),
                        q0**2 - q1**2 - q2**2 + q3**2,
                    ],
                ]
            )
            / n
        )
        # Rows of a proper rotation are the body components of the space axes.
        return {name: list(rot.row(i)) for i, name in enumerate(self.names)}
