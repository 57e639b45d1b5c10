"""Kane's cross-check of a convex body ``f(r) = 0`` rolling on a convex support ``F(p) = 0``.

:mod:`chaplygin.derive.body_on_support` derives the motion in the fixed frame (state
``omega``, the contact point ``p`` on the support, the contact point ``r`` on the body from
its centre of mass, the body axes ``e1, e2, e3``) by Lagrange–d'Alembert, with the contact's
rate from the two surfaces' curvatures. Here the same body is set up with
``sympy.physics.mechanics.KanesMethod``, both contact points carried as coordinates and
neither surface's equation ever solved or differentiated into a curvature:

* coordinates: the body-fixed 3-2-1 Euler angles ``q1, q2, q3`` of ``B``, the contact point
  ``p`` (fixed frame, ``N.z`` up) and the contact point ``r`` (body axes, from the centre of
  mass); speeds: ``u1, u2, u3`` the space components of the angular velocity, ``u4 .. u6``
  the rates of ``p`` and ``u7 .. u9`` those of ``r`` (dependent);
* the centre of mass ``G = p - r`` (``r`` on ``B``'s axes), its velocity sympy's time
  derivative of that position; the body and its rotor at ``G``
  (:func:`~.kane_common.rigid_bodies`), gravity ``-m g N.z`` at ``G``;
* six velocity constraints: no slip at the body point ``G + r`` (three components), the
  contact staying on the support (``(grad F, p') = 0``), and the normals staying parallel:
  the time derivative of two components (``N.x``, ``N.y``) of ``grad f(r) x grad F(p)``
  (``grad f`` on ``B``'s axes). KanesMethod maps the angles' rates; its
  ``constraint_solver`` gets placeholders for ``B_dep^-1 B_ind``, filled numerically at
  each point (as in :mod:`.kane_implicit`).

The points: ``r`` where a ray from inside the body along ``g`` (of
:data:`~.kane_common.RATIONAL_UNIT_VECTORS`) leaves it, ``p`` where a ray from inside the
support along the next ``g`` leaves it (50 digits), and the attitude that turns the body's
outward normal at ``r`` onto ``-s nu(p)`` (``s = 1`` outside the support, ``-1`` inside),
read back into Euler angles. The model's ``omega'``, ``p'`` and ``r'`` (through its
auxiliaries) are compared with Kane's ``u1' .. u3'``, ``u4 .. u6`` and ``u7 .. u9``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import mpmath
import sympy as sp
import sympy.physics.mechanics as me

from ..derive.model import Model
from ..derive.rolling_system import RollingSystem
from ..derive.vectors import vector
from . import kane_common as common
from .kane_implicit import contact_on_ray
from .kane_support import compare_at_points
from .kane_support_implicit import support_contacts

__all__ = ["body_support_points", "compare_body_on_support"]

#: Kane's equations formed, by (description fingerprint, parameter values).
_FORMED: dict = {}


def _unit(x: Sequence[mpmath.mpf]) -> mpmath.matrix:
    v = mpmath.matrix(list(x))
    return v / mpmath.norm(v)


def _gradient_at(expr: sp.Expr, symbols: Sequence[sp.Symbol], at: Sequence) -> mpmath.matrix:
    values = dict(zip(symbols, at, strict=True))
    return mpmath.matrix([mpmath.mpf(sp.N(sp.diff(expr, s).xreplace(values), 60)) for s in symbols])


def body_support_points(surface: sp.Expr, support: sp.Expr, side: int) -> list[tuple]:
    """The comparison's configurations: the body's contact point ``r``, the support's ``p``
    and the attitude ``Q`` (columns: the body axes in the fixed frame) turning the body's
    outward normal at ``r`` onto ``-side nu(p)``.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(r1, r2, r3)``, numeric, convex.
    support : sympy.Expr
        ``F(p1, p2, p3)``, numeric, convex.
    side : int
        1 outside the support, -1 inside.

    Returns
    -------
    list of (list, list, mpmath.matrix)

    Raises
    ------
    ValueError
        When a ray does not leave a surface.
    """
    r_s, p_s = vector("r", real=True), vector("p", real=True)
    contacts = support_contacts(support)
    directions = common.RATIONAL_UNIT_VECTORS
    out = []
    for k, g in enumerate(directions):
        r = contact_on_ray(surface, g)
        p = contacts[(k + 1) % len(contacts)]
        nb = _unit(_gradient_at(surface, r_s, r))
        nu = _unit(_gradient_at(support, p_s, p))
        A, Bf = common.frame_of(nb), common.frame_of(-side * nu)
        out.append((r, p, Bf * A.T))  # Q nb = Bf e3 = -side nu
    return out


def _angles(Q: mpmath.matrix) -> list[mpmath.mpf]:
    """Body-fixed 3-2-1 angles with ``N.dcm(B) = Q`` (``Q = Rz(q1) Ry(q2) Rx(q3)``)."""
    return [mpmath.atan2(Q[1, 0], Q[0, 0]), -mpmath.asin(Q[2, 0]), mpmath.atan2(Q[2, 1], Q[2, 2])]


class _KaneBodyOnSupport:
    """Kane's equations of the convex body with both contact points as coordinates."""

    def __init__(self, system: RollingSystem, pvals: Mapping[sp.Symbol, sp.Expr]) -> None:
        parsed = system._parsed
        sub = {**dict.fromkeys(parsed["mass"].free_symbols, sp.S.One), **dict(pvals)}
        t = me.dynamicsymbols._t
        q, u, N, B, euler, kd, rates = common.body_coordinates("p1 p2 p3 r1 r2 r3")
        F = parsed["support_surface"].xreplace(sub)
        F = F.xreplace(dict(zip(vector("p", real=True), q[3:6], strict=True)))
        f = parsed["surface"].xreplace(sub)
        f = f.xreplace(dict(zip(vector("r", real=True), q[6:9], strict=True)))
        in_N = lambda c: c[0] * N.x + c[1] * N.y + c[2] * N.z  # noqa: E731
        in_B = lambda c: c[0] * B.x + c[1] * B.y + c[2] * B.z  # noqa: E731
        origin = me.Point("origin")
        origin.set_vel(N, 0)
        G = origin.locatenew("G", in_N(q[3:6]) - in_B(q[6:9]))
        G.set_vel(N, G.pos_from(origin).dt(N).xreplace(rates))
        at_contact = G.locatenew("C", in_B(q[6:9]))  # the body's material point there
        at_contact.v2pt_theory(G, N, B)
        grad_F = [sp.diff(F, c) for c in q[3:6]]
        cross = in_B([sp.diff(f, c) for c in q[6:9]]).cross(in_N(grad_F))
        constraints = [at_contact.vel(N).dot(e) for e in (N.x, N.y, N.z)]
        constraints.append(sum(g * w for g, w in zip(grad_F, u[3:6], strict=True)))
        constraints += [cross.dot(e).diff(t).xreplace(rates) for e in (N.x, N.y)]
        dependent = u[3:]
        if "gamma" in parsed["no_spin_about"]:  # rubber: no spin about the support's normal
            constraints.append(B.ang_vel_in(N).dot(in_N(grad_F)))
            dependent = [u[2], *dependent]
        independent = [w for w in u if w not in dependent]
        angles = (q[:3], [euler[s.diff(t)] for s in q[:3]])
        bodies, loads = common.support_loads(parsed, sub, (N, B), G, angles, (q[3:6], u[3:6]))
        self._kane = common.form_with_placeholders(
            N, q, (independent, dependent), kd, constraints, bodies, loads
        )
        self._axes = self._kane.lambdify(N.dcm(B))  # columns: B's axes in N

    def at(self, place: tuple, omega: Sequence[sp.Expr], time: mpmath.mpf):
        """The contact points (by state group), the angular velocity (space components),
        Kane's ``omega'``, the contact points' rates and the body axes (columns)."""
        r, p, Q = place
        q = [*_angles(Q), *p, *r]
        axes = mpmath.matrix(self._axes(q, [mpmath.mpf(0)] * 9, time))
        if mpmath.mnorm(axes - Q, 1) > mpmath.mpf(10) ** (5 - common.DIGITS):
            raise ValueError("the attitude was not read back into Euler angles")
        known = {f"u{i + 1}": mpmath.mpf(sp.Float(w, 50)) for i, w in enumerate(omega)}
        speed, by_name, _ = common.solve_speeds(self._kane, q, known, time)
        acc = [by_name[f"u{i}"] for i in (1, 2, 3)]
        rate = lambda k: [speed[f"u{i}"] for i in range(k, k + 3)]  # noqa: E731
        groups = {"p": list(p), "r": list(r)}
        return groups, rate(1), acc, {"p": rate(4), "r": rate(7)}, axes


def compare_body_on_support(
    system: RollingSystem,
    model: Model,
    pvals: Mapping[sp.Symbol, sp.Expr],
    omegas: Sequence[Sequence[object]],
    digits: int,
    relative: Callable[[Sequence[object], Sequence[object]], float],
) -> tuple[int, float, float]:
    """``omega'``, ``p'`` and ``r'`` of the model against Kane's at
    :func:`body_support_points`.

    Parameters
    ----------
    system : RollingSystem
        A convex ``surface`` with ``support="surface"``.
    model : Model
    pvals : mapping of sympy.Symbol to sympy.Expr
        Exact parameter values.
    omegas : sequence of 3 numbers
        Angular velocities (space components), each paired with each configuration.
    digits : int
    relative : callable
        ``relative(a, b)``: the relative difference of two vectors.

    Returns
    -------
    tuple of (int, float, float)
        Points compared, the largest ``omega'`` and contact-rate (``p'``, ``r'``)
        differences.
    """
    key = (system.fingerprint(), tuple(sorted((s.name, v) for s, v in pvals.items())))
    kane = _FORMED.get(key)
    if kane is None:  # forming Kane's equations is the cost: once per system and values
        kane = _FORMED[key] = _KaneBodyOnSupport(system, pvals)
    sub = {**dict.fromkeys(system._parsed["mass"].free_symbols, sp.S.One), **dict(pvals)}
    side = 1 if system.side == "outside" else -1
    with mpmath.workdps(digits + 20):
        places = body_support_points(
            system._parsed["surface"].xreplace(sub),
            system._parsed["support_surface"].xreplace(sub),
            side,
        )
    return compare_at_points(kane, places, model, pvals, omegas, digits, relative)
