"""The points of a level set of any first integrals, enumerated: ``point = k`` of a request.

:mod:`chaplygin.numerics.integral_levels` solves the free components of a given state for
prescribed integral values from their given values (one root, the one Newton reaches). With
``point = k`` the level set is enumerated instead, by a fixed and documented procedure that
does not depend on the given values of the free components (only on the components that are
not free, the parameters, the values and the working precision):

* **Unknowns.** A free group that is a unit vector of the model (``code.geometry``:
  ``gamma``) is a point of the sphere (two unknowns, a chart ``g = (g0 + a e1 + b e2)/|...|``
  at each start ``g0``, ``e1, e2`` = :func:`~chaplygin.numerics.frame.horizontal_frame`);
  every other free component is a scalar. Unknowns and values must be as many.
* **Starts.** Unit vectors: the Fibonacci lattice of the sphere with :data:`SPHERE_STARTS`
  points (:data:`SPHERE_STARTS_WITH_SCALARS` when scalars are free too), the lattice of
  :mod:`chaplygin.numerics.ball.level_set`. Free scalars, where the energy ``H`` is among the
  values and is a positive-definite quadratic in them (a momentum: ``T`` is positive
  definite; fitted exactly and checked at another point), lie on the ellipsoid ``H = h``
  (every point of the level set does): ``x = x* + sqrt(2 (h - H*)) L^-T u`` with ``x*`` the
  least point, ``Q = L L^T`` the Hessian and ``u`` on a lattice of the unit sphere of their
  dimension ``m``: ``u = -1, 1`` (m = 1), :data:`CIRCLE_STARTS` equal angles (m = 2), a
  Fibonacci lattice of :data:`ELLIPSOID_STARTS` points (m = 3), the normalised points of
  ``{-1, 0, 1}^m`` without 0 (m >= 4); none where ``h < H*``. Otherwise the scalars start on
  the tensor grid of :data:`BOX_STARTS` ** (1/m) (at least 2) cell centres per axis of the box
  of half-width ``1 + max |given|`` about the given values (0 where a free group is not given;
  a stated box, not a natural domain: points outside it can be missed). The starts are the
  product of the blocks' (for each unit vector's lattice point, the scalars' starts there).
* **Roots.** From every start, the damped Newton of ``integral_levels`` (central-difference
  Jacobian, a step halved at most :data:`HALVINGS` times until the residual falls,
  :data:`ITERATIONS` iterations at most) at ``parse_dps + 10`` digits, to a
  residual below ``10^-(digits - 8) (1 + |values|)``; starts that do not converge give none.
* **De-duplication.** Two roots are one when each free component of one is within
  ``10^-(digits/2) (1 + |x_i|)`` of the other's; the first found (in start order) is kept.
* **Order.** The free components in the request's order (a unit vector's three components),
  compared one after the other, two of them equal within the de-duplication tolerance:
  point 0 has the least first free component.

Everything runs in mpmath at the solve's digits: the same bits on every machine and every run.
What is a proof and what is not: a point returned satisfies the values to the residual stated;
the enumeration is every root reached from the starts, not a proof that the level set has no
other point. A request with no point found is refused; the refusal is a proof when a
certificate is found (:mod:`chaplygin.numerics.level_certificate`): multipliers ``lambda`` for
which ``sum lambda_i (F_i - v_i)``, a quadratic in the free scalars, is positive definite with a
positive least value, so no real point has the values (for the quadratics the conditions are,
fitted exactly from their values and checked at another point; the energy alone below its
least value is the case ``lambda = e_H``).
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mpmath

from ..derive.errors import UserInputError
from .code import ModelCode
from .frame import horizontal_frame
from .inputs import complete_state
from .integral_levels import (
    IntegralLevelError,
    LevelRequest,
    _evaluators,
    _free_components,
    _newton,
)
from .level_certificate import (
    certificate_refusal,
    fibonacci_lattice,
    least_of_quadratic,
    quadratic_fit,
    unit_sphere_lattice,
)
from .precision import Precision

__all__ = [
    "LevelPoints",
    "level_points",
    "point_on_levels",
    "SPHERE_STARTS",
    "SPHERE_STARTS_WITH_SCALARS",
    "ELLIPSOID_STARTS",
    "CIRCLE_STARTS",
    "BOX_STARTS",
]

#: Fibonacci lattice points of a free unit vector's sphere (no free scalars).
SPHERE_STARTS = 64
#: The same when scalars are free too (the starts are a product).
SPHERE_STARTS_WITH_SCALARS = 12
#: Lattice points of the energy ellipsoid of three free scalars (Fibonacci).
ELLIPSOID_STARTS = 32
#: Angles of the energy ellipse of two free scalars.
CIRCLE_STARTS = 16
#: Starts of the box grid of free scalars without an energy ellipsoid (at most).
BOX_STARTS = 64
#: Newton iterations from each start at most.
ITERATIONS = 30
#: Halvings of a Newton step at most (the start is given up when none lowers the residual).
HALVINGS = 10


@dataclass(frozen=True)
class LevelPoints:
    """The points of a level set found by :func:`level_points`.

    Attributes
    ----------
    points : list of dict
        State groups of each point (text at the solve's digits), in the documented order.
    free : tuple of str
        The free components, in the request's order (the order's key).
    grid : str
        The starts, in words (for messages and summaries).
    starts : int
        How many starts were solved from.
    tolerance : mpmath.mpf
        The de-duplication tolerance (relative, max norm).
    """

    points: list
    free: tuple
    grid: str
    starts: int
    tolerance: mpmath.mpf


@dataclass(frozen=True)
class _Unknowns:
    """The free components split into scalars ``(group, index, name)`` and unit vectors
    (group names), with the starting state groups (wholly free groups filled with zeros)."""

    scalars: list
    spheres: list
    names: tuple
    base: dict


def _unknowns(code: ModelCode, request: LevelRequest, count: int) -> _Unknowns:
    unit = {names[0] for kind, names in code.geometry if kind == "unit_vector"}
    tied = {n for _, names in code.geometry for n in names}
    groups = code.state_groups
    given = {k: list(v) for k, v in request.given.items()}
    for item in request.free:
        if item in groups and item not in given:
            given[item] = [0] * len(groups[item])
    free = _free_components(code, given, request.free)
    spheres = [g for g in dict.fromkeys(g for g, _, _ in free) if g in unit]
    for group, _, name in free:
        if group in tied and (group not in spheres or _item_count(free, group) != 3):
            raise IntegralLevelError(
                f"point = k: {name} is part of the unit vector or frame {group}; free a unit "
                f'vector as a whole (free = ["{group}"]: a point of its sphere)',
                "free",
            )
    scalars = [(g, i, n) for g, i, n in free if g not in spheres]
    unknowns = len(scalars) + 2 * len(spheres)
    if unknowns != count or not unknowns:
        raise IntegralLevelError(
            f"{count} integral value(s) need as many unknowns, {unknowns} given (a free unit "
            "vector is 2: a point of its sphere; any other component 1)",
            "free",
        )
    return _Unknowns(scalars, spheres, tuple(n for _, _, n in free), given)


def _item_count(free: Sequence, group: str) -> int:
    """How many of the free components ``(group, index, name)`` are in ``group``."""
    return sum(1 for g, _, _ in free if g == group)


def _compare(tol):
    def cmp(a, b):
        for u, v in zip(a, b, strict=True):
            if abs(u - v) > tol * (1 + max(abs(u), abs(v))):
                return -1 if u < v else 1
        return 0

    return functools.cmp_to_key(cmp)


def level_points(
    code: ModelCode, params: Mapping[str, object], request: LevelRequest, precision: Precision
) -> LevelPoints:
    """Every point of the level set the documented starts reach, in the documented order.

    Parameters
    ----------
    code : ModelCode
    params : mapping of str to number
        Parameter values by symbol.
    request : LevelRequest
        As for :func:`~chaplygin.numerics.integral_levels.state_on_levels` (the free
        components' given values are not used, but for the box grid's centre).
    precision : Precision
        The working precision (the solve runs at ``precision.parse_dps + 10`` digits).

    Returns
    -------
    LevelPoints
        Possibly no point (:func:`point_on_levels` refuses then).

    Raises
    ------
    IntegralLevelError
        Unknown names, a count of unknowns other than the values', part of a unit vector free,
        or (no point found) a certificate that the values are never taken.
    """
    from .inputs import parse_number

    dps = precision.parse_dps + 10
    with mpmath.workdps(dps):
        evaluate = _evaluators(code, request)
        names = list(request.targets)
        unknowns = _unknowns(code, request, len(names))
        target = mpmath.matrix([parse_number(request.targets[n], dps) for n in names])
        p = [mpmath.mpf(params[k]) for k in code.params]
        base = {k: [parse_number(v, dps) for v in vals] for k, vals in unknowns.base.items()}
        solve = _Solve(code, evaluate, names, p, base, unknowns, Precision(dps))
        tol = mpmath.mpf(10) ** (-(dps // 2))
        roots, starts, kinds = [], 0, set()
        for centres, x_starts, kind in solve.starts(target):
            kinds.add(kind)
            for x in x_starts:
                starts += 1
                z0 = mpmath.matrix([*x, *([0] * (2 * len(centres)))])
                try:
                    z = _newton(
                        lambda z, c=centres: solve.residual(z, c) - target,
                        z0, names, list(unknowns.names), target, dps, ITERATIONS, HALVINGS,
                    )  # fmt: skip
                except IntegralLevelError:
                    continue  # no root from this start
                root = solve.components(z, centres)
                if not any(_compare(tol)(root) == _compare(tol)(r) for r, _ in roots):
                    roots.append((root, solve.text(z, centres)))
        roots.sort(key=lambda item: _compare(tol)(item[0]))
        grid = solve.describe(kinds, starts)
        if not roots and not unknowns.spheres:
            x0 = mpmath.matrix([base[g][i] for g, i, _ in unknowns.scalars])
            proof = certificate_refusal(lambda x: solve.residual(x, []), x0, names, target)
            if proof:
                raise IntegralLevelError(proof, "integrals")
    return LevelPoints([g for _, g in roots], unknowns.names, grid, starts, tol)


class _Solve:
    """The state at the unknowns, the residual and the starts of one request."""

    def __init__(self, code, evaluate, names, p, base, unknowns, precision):
        self.code, self.evaluate, self.names, self.p = code, evaluate, names, p
        self.base, self.unknowns, self.precision = base, unknowns, precision
        self.shipped = [n for n in names if n in code.integral_names]
        self._frames: dict = {}

    def _vectors(self, z, centres):
        m = len(self.unknowns.scalars)
        out = []
        for k, g0 in enumerate(centres):
            key = tuple(g0)
            if key not in self._frames:
                self._frames[key] = horizontal_frame(g0)
            e1, e2 = self._frames[key]
            a, b = z[m + 2 * k], z[m + 2 * k + 1]
            v = [g + a * u + b * w for g, u, w in zip(g0, e1, e2, strict=True)]
            norm = mpmath.sqrt(sum(c * c for c in v))
            out.append([c / norm for c in v])
        return out

    def groups(self, z, centres) -> dict:
        trial = {k: list(v) for k, v in self.base.items()}
        for (group, i, _), value in zip(self.unknowns.scalars, z, strict=False):
            trial[group][i] = value
        for group, v in zip(self.unknowns.spheres, self._vectors(z, centres), strict=True):
            trial[group] = v
        return trial

    def text(self, z, centres) -> dict:
        """The point's state groups as text at the solve's digits."""
        return {
            k: [mpmath.nstr(v, mpmath.mp.dps) for v in vals]
            for k, vals in self.groups(z, centres).items()
        }

    def components(self, z, centres) -> list:
        """The free components of the point (the order's key), in the request's order."""
        groups = self.groups(z, centres)
        by_name = {
            n: groups[g][i]
            for g, comps in self.code.state_groups.items()
            if g in groups
            for i, n in enumerate(comps)
        }
        return [by_name[n] for n in self.unknowns.names]

    def residual(self, z, centres):
        try:
            y = complete_state(self.code, self.groups(z, centres), self.precision).y
        except UserInputError as exc:
            raise IntegralLevelError(str(exc), "integrals") from None
        y = [mpmath.mpf(v) for v in y]
        shipped = {}
        if self.shipped:  # the model's integrals at once
            every = self.code.mpmath.integrals(mpmath.mpf(0), y, self.p)
            shipped = {n: every[self.code.integral_names.index(n)] for n in self.shipped}
        return mpmath.matrix(
            [shipped[n] if n in shipped else self.evaluate[n](y, self.p) for n in self.names]
        )

    def starts(self, target):
        """``(sphere centres, scalar starts, kind)`` in the documented order."""
        scalars = self.unknowns.scalars
        count = SPHERE_STARTS_WITH_SCALARS if scalars else SPHERE_STARTS
        lattices = [fibonacci_lattice(count) for _ in self.unknowns.spheres]
        for centres in itertools.product(*lattices):
            if not scalars:
                yield list(centres), [[]], "sphere"
                continue
            x0 = mpmath.matrix([self.base[g][i] for g, i, _ in scalars])
            yield (list(centres), *self._scalar_starts(list(centres), x0, target))

    def _scalar_starts(self, centres, x0, target):
        m = len(x0)
        if "H" in self.names:
            k = self.names.index("H")
            try:
                fit = quadratic_fit(lambda x: self.residual(_join(x, centres), centres), x0)[k]
            except UserInputError:
                fit = None
            least = None if fit is None else least_of_quadratic(*fit)
            if least is not None:
                level, offset = least
                if target[k] < level:
                    return [], "ellipsoid"  # no state at this sphere point has the energy
                radius = mpmath.sqrt(2 * (target[k] - level))
                L = mpmath.cholesky(fit[2])
                centre = x0 + offset
                return [
                    list(centre + radius * mpmath.lu_solve(L.T, mpmath.matrix(u)))
                    for u in unit_sphere_lattice(m, CIRCLE_STARTS, ELLIPSOID_STARTS, 1)
                ], "ellipsoid"
        per_axis = max(2, int(mpmath.floor(mpmath.mpf(BOX_STARTS) ** (mpmath.mpf(1) / m) + 1e-9)))
        half = 1 + max(abs(v) for v in x0)
        axis = [2 * (j + mpmath.mpf(1) / 2) / per_axis - 1 for j in range(per_axis)]
        return [
            [x0[i] + half * t[i] for i in range(m)] for t in itertools.product(axis, repeat=m)
        ], "box"

    def describe(self, kinds, starts) -> str:
        parts = []
        if self.unknowns.spheres:
            count = SPHERE_STARTS_WITH_SCALARS if self.unknowns.scalars else SPHERE_STARTS
            parts.append(
                f"{', '.join(self.unknowns.spheres)} on the Fibonacci lattice of {count} points"
            )
        if "ellipsoid" in kinds:
            parts.append("the free scalars on a lattice of the energy ellipsoid H = h")
        if "box" in kinds:
            parts.append(f"the free scalars on a grid of about {BOX_STARTS} in the box of "
                         "half-width 1 + max |given| about their given values")  # fmt: skip
        return "; ".join(parts) + f" ({starts} starts)"


def _join(x, centres):
    """Scalars ``x`` and zero chart coordinates for the sphere ``centres``."""
    return mpmath.matrix([*x, *([0] * (2 * len(centres)))])


def point_on_levels(
    code: ModelCode, params: Mapping[str, object], request: LevelRequest, precision: Precision
) -> tuple[dict, dict, str]:
    """The ``request.point``-th point of :func:`level_points` (as
    :func:`~chaplygin.numerics.integral_levels.state_on_levels` returns a state).

    Parameters
    ----------
    code : ModelCode
    params : mapping of str to number
    request : LevelRequest
        With ``point`` set.
    precision : Precision

    Returns
    -------
    (dict, dict, str)
        The state groups, the prescribed values and how the point was chosen.

    Raises
    ------
    IntegralLevelError
        As :func:`level_points`, or ``point`` beyond the points found (the message says how
        many were found and on which grid).
    """
    if request.point is None or request.point < 0:
        raise IntegralLevelError(f"point must be 0 or more, got {request.point}", "point")
    found = level_points(code, params, request, precision)
    k, n = request.point, len(found.points)
    if k >= n:
        what = "no point" if not n else f"{n} point(s) (point = 0..{n - 1})"
        proof = "" if n else " (not a proof that none exists)"
        raise IntegralLevelError(
            f"point = {k}: the level set {', '.join(request.targets)} = "
            f"{', '.join(str(v) for v in request.targets.values())} has {what} from "
            f"{found.grid}{proof}",
            "point",
        )
    how = (
        f"point {k} of {n} of the level set {', '.join(request.targets)} over "
        f"{', '.join(found.free)}: roots of Newton from {found.grid}, de-duplicated at "
        f"{mpmath.nstr(found.tolerance, 3)} and ordered by {', '.join(found.free)}"
    )
    return found.points[k], dict(request.targets), how
