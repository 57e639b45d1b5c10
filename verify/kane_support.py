"""Kane's cross-check of a ball on an ellipsoidal support surface.

The model (:mod:`chaplygin.derive.ball_on_support`, or for a ball that is not homogeneous
:mod:`chaplygin.derive.ball_on_support_general`, its body axes ``e1, e2, e3`` in the state)
takes the contact point ``p`` as the state and the support's normal from the implicit
``grad F``. Here the ball is set up
again with ``sympy.physics.mechanics.KanesMethod`` from a *parametrisation* of the
support: for ``F = (p - p0)^T A (p - p0) - s^2`` (``A > 0``) the contact point is ``p =
p0 + s L^-T e(x, y)`` with ``A = L L^T`` and ``e = (cos x, sin x cos y, sin x sin y)``;
the centre ``O = p + sigma b nu(p)`` (``sigma = 1`` outside, ``-1`` inside), the
generalised coordinates the body's 3-2-1 Euler angles and ``x, y``; speeds the space
components of ``omega`` and ``x', y'``; no slip at the body point ``O - sigma b nu``
along the two tangents ``dp/dx, dp/dy`` (``x', y'`` dependent); the centre of mass ``G =
O + a`` (body axes) with the inertia tensor about it, gravity ``-m g N.z`` at ``G`` and a
rotor ``K`` as the torque ``-omega x K`` on the body. At points of the support (40
digits) the model's ``omega'`` and ``p'`` are compared with Kane's ``u1', u2', u3'`` and
``(dp/dx) x' + (dp/dy) y'``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import mpmath
import sympy as sp
import sympy.physics.mechanics as me

from ..derive.model import Model
from ..derive.rolling_system import RollingSystem
from ..derive.vectors import vector
from .kane_common import T0
from .kane_euler import euler_rates

__all__ = [
    "compare_at_points",
    "compare_on_support",
    "ellipsoid_support",
    "heavy_ball",
    "is_ellipsoid",
    "parametrised_covers",
]

#: Kane's equations formed, by (description fingerprint, parameter values).
_FORMED: dict = {}

#: Where the contact point sits at the comparison points (the angles ``x, y``).
SUPPORT_ANGLES = (("1.1", "0.7"), ("0.4", "2.3"), ("2.6", "-1.2"), ("1.9", "0.3"))


def ellipsoid_support(F: sp.Expr, p: Sequence[sp.Symbol]) -> tuple[sp.Matrix, sp.Matrix, sp.Expr]:
    """``A``, ``p0`` and ``s^2`` of ``F = (p - p0)^T A (p - p0) - s^2``.

    Parameters
    ----------
    F : sympy.Expr
        A polynomial of degree 2 in ``p`` with numeric coefficients.
    p : sequence of sympy.Symbol

    Returns
    -------
    tuple of (sympy.Matrix, sympy.Matrix, sympy.Expr)

    Raises
    ------
    ValueError
        When ``F`` is not an ellipsoid.
    """
    A = sp.hessian(F, list(p)) / 2
    if A.free_symbols or not A.is_positive_definite:
        raise ValueError("the Kane comparison takes an ellipsoidal support (A > 0) only")
    linear = sp.Matrix([sp.diff(F, c) for c in p]).xreplace(dict.fromkeys(p, 0))
    p0 = -A.inv() * linear / 2
    s2 = -F.xreplace(dict(zip(p, p0, strict=True)))
    if not s2 > 0:
        raise ValueError("the support's quadric is empty")
    return A, p0, s2


def is_ellipsoid(F: sp.Expr) -> bool:
    """Whether :func:`ellipsoid_support` takes ``F`` (in ``p1, p2, p3``).

    Parameters
    ----------
    F : sympy.Expr

    Returns
    -------
    bool
    """
    try:
        ellipsoid_support(F, sp.symbols("p1:4", real=True))
    except ValueError:
        return False
    return True


def parametrised_covers(parsed: Mapping) -> bool:
    """Whether the parametrised set-up here covers the description's fields: gravity, an
    offset centre of mass and a constant rotor — not a potential, rubber contact, ``I(t)``
    or ``K(t)`` (:mod:`.kane_support_implicit` sets those up).

    Parameters
    ----------
    parsed : mapping
        The description's parsed fields (``RollingSystem._parsed``).

    Returns
    -------
    bool
    """
    t = sp.Symbol("t", real=True)
    return not (
        not parsed["potential"].is_zero
        or parsed["inertia"].has(t)
        or parsed["rotor_momentum"].has(t)
        or "gamma" in parsed["no_spin_about"]
    )


def heavy_ball(
    parsed: Mapping, sub: Mapping, frames: tuple, O: me.Point
) -> tuple[me.RigidBody, list]:
    """The ball as Kane's rigid body and its loads: the centre of mass ``G = O + a`` (body
    axes) with the inertia tensor about it, gravity ``-m g N.z`` at ``G`` and a constant
    rotor ``K`` as the torque ``-omega x K``.

    Parameters
    ----------
    parsed : mapping
        The description's parsed fields (``mass``, ``inertia``, ``centre``,
        ``rotor_momentum``, ``field``).
    sub : mapping
        The parameters' values.
    frames : tuple of sympy.physics.mechanics.ReferenceFrame
        ``(N, B)``: the fixed frame and the body's.
    O : sympy.physics.mechanics.Point
        The ball's geometric centre, its velocity in ``N`` set.

    Returns
    -------
    tuple of (RigidBody, list)
    """
    N, B = frames
    m = parsed["mass"].xreplace(sub)
    I, a, K = (parsed[k].xreplace(sub) for k in ("inertia", "centre", "rotor_momentum"))
    axes = (B.x, B.y, B.z)
    G = O.locatenew("G", sum((a[i] * axes[i] for i in range(3)), me.Vector(0)))
    G.v2pt_theory(O, N, B)
    tensor = sum((I[i, j] * (axes[i] | axes[j]) for i in range(3) for j in range(3)), me.Dyadic(0))
    ball = me.RigidBody("ball", G, B, m, (tensor, G))
    loads = [(G, -m * parsed["field"].xreplace(sub) * N.z)]
    if not K.is_zero_matrix:  # a rotor: d/dt K = omega x K, the body feels -omega x K
        rotor = sum((K[i] * axes[i] for i in range(3)), me.Vector(0))
        loads.append((B, -(B.ang_vel_in(N) ^ rotor)))
    return ball, loads


class _KaneOnSupport:
    """Kane's equations of the ball on the ellipsoid (parameters substituted)."""

    def __init__(self, system: RollingSystem, pvals: Mapping[sp.Symbol, sp.Expr]) -> None:
        parsed = system._parsed
        # a mass the model dropped (I = k m b^2: the equations do not depend on it) is 1
        sub = {**dict.fromkeys(parsed["mass"].free_symbols, sp.S.One), **dict(pvals)}
        q = list(me.dynamicsymbols("q1 q2 q3 x y"))
        u = list(me.dynamicsymbols("u1 u2 u3 u4 u5"))
        t = me.dynamicsymbols._t
        N, B = me.ReferenceFrame("N"), me.ReferenceFrame("B")
        B.orient_body_fixed(N, tuple(q[:3]), "zyx")
        solved = euler_rates()
        kd = [r - solved[r] for r in (s.diff(t) for s in q[:3])]
        kd += [q[3].diff(t) - u[3], q[4].diff(t) - u[4]]
        B.set_ang_vel(N, u[0] * N.x + u[1] * N.y + u[2] * N.z)
        ps = list(vector("p", real=True))
        F = parsed["support_surface"].xreplace(sub)
        A, p0, s2 = ellipsoid_support(F, ps)
        L = A.cholesky(hermitian=False)
        e = sp.Matrix([sp.cos(q[3]), sp.sin(q[3]) * sp.cos(q[4]), sp.sin(q[3]) * sp.sin(q[4])])
        p = p0 + sp.sqrt(s2) * L.T.inv() * e
        grad = A * (p - p0)
        nu = grad / sp.sqrt(grad.dot(grad))
        b = parsed["radius"].xreplace(sub)
        sigma = 1 if system.side == "outside" else -1
        to_vec = lambda c: c[0] * N.x + c[1] * N.y + c[2] * N.z  # noqa: E731
        origin = me.Point("origin")
        origin.set_vel(N, 0)
        O = origin.locatenew("O", to_vec(p + sigma * b * nu))
        O.set_vel(N, O.pos_from(origin).dt(N).subs({q[3].diff(t): u[3], q[4].diff(t): u[4]}))
        P = O.locatenew("P", to_vec(-sigma * b * nu))
        P.v2pt_theory(O, N, B)
        tangents = [to_vec(p.diff(q[3])), to_vec(p.diff(q[4]))]
        constraints = [P.vel(N).dot(tangent) for tangent in tangents]
        ball, loads = heavy_ball(parsed, sub, (N, B), O)
        kane = me.KanesMethod(
            N, q_ind=q, u_ind=u[:3], u_dependent=u[3:], kd_eqs=kd,
            velocity_constraints=constraints,
        )  # fmt: skip
        kane.kanes_equations([ball], loads)
        # the dependent speeds: linear in them, solved numerically at each point
        C = sp.Matrix(constraints)
        args = (q, u, t)
        self._dep_matrix = sp.lambdify(args, C.jacobian(u[3:]), modules="mpmath")
        self._dep_rhs = sp.lambdify(args, -C.xreplace(dict.fromkeys(u[3:], 0)), modules="mpmath")
        self._mass = sp.lambdify(args, kane.mass_matrix, modules="mpmath")
        self._forcing = sp.lambdify(args, kane.forcing, modules="mpmath")
        self._p = sp.lambdify(args, p, modules="mpmath")
        self._axes = sp.lambdify(args, N.dcm(B), modules="mpmath")  # columns: B's axes
        self._p_rate = sp.lambdify(args, p.diff(q[3]) * u[3] + p.diff(q[4]) * u[4], "mpmath")
        self._order = [str(s.func) for s in kane.u]

    def at(self, angles: Sequence[str], omega: Sequence[sp.Expr], time: Any = 0):
        """The contact point, the angular velocity, Kane's ``omega'`` and ``p'`` (space
        components) and the body axes (the columns of the returned matrix, space
        components); nothing here depends on ``time``."""
        q = [mpmath.mpf("0.3"), mpmath.mpf("0.2"), mpmath.mpf("-0.4")]
        q += [mpmath.mpf(a) for a in angles]
        u = [mpmath.mpf(sp.Float(w, 50)) for w in omega] + [mpmath.mpf(0)] * 2
        dep = mpmath.lu_solve(
            mpmath.matrix(self._dep_matrix(q, u, 0)), mpmath.matrix(self._dep_rhs(q, u, 0))
        )
        u[3], u[4] = dep[0], dep[1]
        solved = mpmath.lu_solve(
            mpmath.matrix(self._mass(q, u, 0)), mpmath.matrix(self._forcing(q, u, 0))
        )
        udot = dict(zip(self._order, solved, strict=True))
        acc = [udot[f"u{i}"] for i in (1, 2, 3)]
        contact = self._p(q, u, 0)
        rate = self._p_rate(q, u, 0)
        axes = self._axes(q, u, 0)
        contact, rate = [contact[i] for i in range(3)], [rate[i] for i in range(3)]
        return {"p": contact}, u[:3], acc, {"p": rate}, axes


def compare_on_support(
    system: RollingSystem,
    model: Model,
    pvals: Mapping[sp.Symbol, sp.Expr],
    omegas: Sequence[Sequence[object]],
    digits: int,
    relative: Callable[[Sequence[object], Sequence[object]], float],
) -> tuple[int, float, float]:
    """``omega'`` and ``p'`` of the model against Kane's at :data:`SUPPORT_ANGLES`.

    Parameters
    ----------
    system : RollingSystem
        With ``support="surface"`` and an ellipsoidal ``support_surface``.
    model : Model
    pvals : mapping of sympy.Symbol to sympy.Expr
        Exact parameter values.
    omegas : sequence of 3 numbers
        Angular velocities (space components), each paired with each contact point.
    digits : int
        Working digits.
    relative : callable
        ``relative(a, b)``: the relative difference of two vectors.

    Returns
    -------
    tuple of (int, float, float)
        Points compared, the largest ``omega'`` and ``p'`` differences.
    """
    key = (system.fingerprint(), tuple(sorted((s.name, v) for s, v in pvals.items())))
    kane = _FORMED.get(key)
    if kane is None:  # forming Kane's equations is the cost: once per system and values
        kane = _FORMED[key] = _KaneOnSupport(system, pvals)
    return compare_at_points(kane, SUPPORT_ANGLES, model, pvals, omegas, digits, relative)


def compare_at_points(
    kane: Any,
    points: Sequence[Any],
    model: Model,
    pvals: Mapping[sp.Symbol, sp.Expr],
    omegas: Sequence[Sequence[object]],
    digits: int,
    relative: Callable[[Sequence[object], Sequence[object]], float],
) -> tuple[int, float, float]:
    """The model's ``omega'`` and the contact points' rates (its auxiliaries in order)
    against Kane's (``kane.at(point, omega, time)``: the contact points by state group —
    ``p``, a convex body's ``r`` —, the angular velocity it took, ``omega'``, the contact
    points' rates by group and the body axes as columns) at each point and angular velocity,
    at :data:`~.kane_common.T0` (the time of a prescribed law).

    Parameters
    ----------
    kane : object
        Kane's equations formed (:mod:`.kane_support`, :mod:`.kane_support_implicit`).
    points : sequence
        Where ``kane.at`` places the contact.
    model, pvals, omegas, digits, relative
        As :func:`compare_on_support`.

    Returns
    -------
    tuple of (int, float, float)
        Points compared, the largest ``omega'`` and ``p'`` differences.
    """
    omega = sp.Matrix(model.group("omega"))
    state = list(model.state)
    frame = [n for n in ("e1", "e2", "e3") if n in dict(model.state_groups)]
    exact = lambda c: sp.Float(mpmath.nstr(c, digits + 5), digits + 5)  # noqa: E731
    time = sp.Symbol("t", real=True)

    def field(w, places, axes):  # the model's rates: its auxiliary definitions in order
        values = {**pvals, time: T0, **{s: exact(c) for s, c in zip(omega, w, strict=True)}}
        for name, where in places.items():  # the contact points (p; a convex body's r)
            values.update((s, exact(c)) for s, c in zip(model.group(name), where, strict=True))
        for j, name in enumerate(frame):  # a general ball's body axes (fixed frame)
            values.update((s, exact(axes[i, j])) for i, s in enumerate(model.group(name)))
        for symbol, expr in model.aux:
            values[symbol] = sp.N(expr.xreplace(values), digits + 5)
        rate = lambda s: sp.N(model.rhs[state.index(s)].xreplace(values), digits + 5)  # noqa: E731
        return [rate(s) for s in omega], {n: [rate(s) for s in model.group(n)] for n in places}

    worst_acc = worst_rate = 0.0
    count = 0
    with mpmath.workdps(digits):
        for w in omegas:
            for point in points:
                places, used, acc, rates, axes = kane.at(point, w, mpmath.mpf(T0))
                model_acc, model_rates = field(used, places, axes)
                worst_acc = max(worst_acc, relative(model_acc, acc))
                for name, rate in rates.items():
                    worst_rate = max(worst_rate, relative(model_rates[name], rate))
                count += 1
    return count, worst_acc, worst_rate
