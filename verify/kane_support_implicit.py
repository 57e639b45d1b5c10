"""Kane's cross-check of a ball on any convex support surface ``F(p) = 0`` (issue 24).

:mod:`.kane_support` sets the ball up on an ellipsoid through its parametrisation. A
support that is not an ellipsoid has none in closed form; here, as :mod:`.kane_implicit`
does for a convex body, the contact point is carried as coordinates and the support's
equation is never solved:

* coordinates: the body-fixed 3-2-1 Euler angles ``q1, q2, q3`` of ``B`` and the contact
  point ``p = (p1, p2, p3)`` (fixed frame, ``N.z`` up);
* speeds: ``u1, u2, u3`` the space components of the angular velocity, ``u4, u5, u6`` the
  rates of ``p`` (dependent);
* the ball's centre ``O = p + sigma b nu(p)``, ``nu = grad F/|grad F|`` (``sigma = 1``
  outside, ``-1`` inside), its velocity sympy's time derivative of that position; the
  centre of mass ``G = O + a`` (body axes) with the inertia tensor about it (a tensor
  ``I(t)`` of Kane's time), gravity ``-m g N.z`` at ``G``, the rotor ``K`` (constant or
  ``K(t)``) as real rotors (:func:`~.kane_common.rigid_bodies`), a potential ``V(p, e1,
  e2, e3)`` (``e_i`` the body axes' space components, from the Euler angles) as the
  loads ``-dV/dq_j`` of :func:`~.kane_common.potential_loads` on the angles and on ``p``;
* velocity constraints: no slip at the body point ``O - sigma b nu`` (all three components:
  the normal one keeps ``p`` on its level set of ``F``); rubber contact adds ``(omega,
  nu) = 0`` (no spin about the normal; ``u3`` dependent too, solved at each point).

The comparison runs at the time :data:`~.kane_common.T0` (where a prescribed law is read).

KanesMethod's ``constraint_solver`` gets placeholders for ``B_dep^-1 B_ind``, filled
numerically at each point (as in :mod:`.kane_implicit`). The comparison points are where
rays from a point inside the support (``F < 0``) along the directions of
:data:`~.kane_common.RATIONAL_UNIT_VECTORS` leave it (the smallest positive root of ``F``
along the ray, 50 digits), at a fixed attitude; the model's ``omega'`` and ``p'`` are
evaluated there through its auxiliaries and compared with Kane's ``u1', u2', u3'`` and
``u4, u5, u6``.
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

__all__ = ["compare_on_implicit_support", "support_contacts"]

#: Kane's equations formed, by (description fingerprint, parameter values).
_FORMED: dict = {}
#: The attitude (3-2-1 Euler angles) of the comparisons.
ANGLES = ("0.3", "0.2", "-0.4")


def support_contacts(support: sp.Expr) -> list[list]:
    """The comparison's contact points on ``F = 0``: where the rays from a point inside
    along :data:`~.kane_common.RATIONAL_UNIT_VECTORS` leave the support.

    Parameters
    ----------
    support : sympy.Expr
        ``F(p1, p2, p3)`` with exact numeric coefficients, convex.

    Returns
    -------
    list of list of mpmath.mpf

    Raises
    ------
    ValueError
        When a ray does not meet ``F = 0`` or no inside point is found.
    """
    p, r = vector("p", real=True), vector("r", real=True)
    in_r = support.xreplace(dict(zip(p, r, strict=True)))
    return [contact_on_ray(in_r, g) for g in common.RATIONAL_UNIT_VECTORS]


class _KaneOnImplicitSupport:
    """Kane's equations of the ball with its contact point as coordinates."""

    def __init__(self, system: RollingSystem, pvals: Mapping[sp.Symbol, sp.Expr]) -> None:
        parsed = system._parsed
        sub = {**dict.fromkeys(parsed["mass"].free_symbols, sp.S.One), **dict(pvals)}
        q, u, N, B, solved, kd, rates = common.body_coordinates("p1 p2 p3")
        ps = vector("p", real=True)
        at_q = dict(zip(ps, q[3:], strict=True))
        F = parsed["support_surface"].xreplace(sub).xreplace(at_q)
        grad = sp.Matrix([sp.diff(F, c) for c in q[3:]])
        nu = grad / sp.sqrt(grad.dot(grad))
        b = parsed["radius"].xreplace(sub)
        sigma = 1 if system.side == "outside" else -1
        to_vec = lambda c: c[0] * N.x + c[1] * N.y + c[2] * N.z  # noqa: E731
        origin = me.Point("origin")
        origin.set_vel(N, 0)
        O = origin.locatenew("O", to_vec(sp.Matrix(q[3:]) + sigma * b * nu))
        O.set_vel(N, O.pos_from(origin).dt(N).xreplace(rates))
        P = O.locatenew("P", to_vec(-sigma * b * nu))
        P.v2pt_theory(O, N, B)
        constraints = [P.vel(N).dot(e) for e in (N.x, N.y, N.z)]
        dependent = u[3:]
        if "gamma" in parsed["no_spin_about"]:  # rubber: no spin about the support's normal
            constraints.append(B.ang_vel_in(N).dot(to_vec(nu)))
            dependent = [u[2], *dependent]
        independent = [s for s in u if s not in dependent]
        bodies, loads = self._loads(parsed, sub, (N, B), O, q, u, solved)
        self._kane = common.form_with_placeholders(
            N, q, (independent, dependent), kd, constraints, bodies, loads
        )
        self._axes = self._kane.lambdify(N.dcm(B))  # columns: B's axes in N

    @staticmethod
    def _loads(parsed, sub, frames, O, q, u, euler) -> tuple[list, list]:  # noqa: ANN001
        """The body and its rotors (:func:`~.kane_common.rigid_bodies`: ``I(t)``, ``K(t)``)
        at ``G = O + a``; gravity at ``G``; a potential ``V(p, e1, e2, e3)`` as the loads of
        :func:`~.kane_common.potential_loads` on the Euler angles and the contact point."""
        N, B = frames
        t = me.dynamicsymbols._t
        a = parsed["centre"].xreplace(sub)
        G = O.locatenew("G", a[0] * B.x + a[1] * B.y + a[2] * B.z)
        G.v2pt_theory(O, N, B)
        angles = (q[:3], [euler[s.diff(t)] for s in q[:3]])
        return common.support_loads(parsed, sub, (N, B), G, angles, (q[3:], u[3:]))

    def at(self, contact: Sequence[mpmath.mpf], omega: Sequence[sp.Expr], time: mpmath.mpf):
        """The contact point, the angular velocity (space components; with rubber contact
        its normal component solved from the constraint), Kane's ``omega'`` and ``p'`` at
        them and the body axes (columns), at ``time``."""
        q = [mpmath.mpf(a) for a in ANGLES] + list(contact)
        known = {f"u{i + 1}": mpmath.mpf(sp.Float(w, 50)) for i, w in enumerate(omega)}
        speed, by_name, u = common.solve_speeds(self._kane, q, known, time)
        w = [speed[f"u{i}"] for i in (1, 2, 3)]
        acc = [by_name[f"u{i}"] for i in (1, 2, 3)]
        rate = [speed[f"u{i}"] for i in (4, 5, 6)]
        return {"p": list(contact)}, w, acc, {"p": rate}, mpmath.matrix(self._axes(q, u, time))


def compare_on_implicit_support(
    system: RollingSystem,
    model: Model,
    pvals: Mapping[sp.Symbol, sp.Expr],
    omegas: Sequence[Sequence[object]],
    digits: int,
    relative: Callable[[Sequence[object], Sequence[object]], float],
) -> tuple[int, float, float]:
    """``omega'`` and ``p'`` of the model against Kane's at :func:`support_contacts`.

    Parameters
    ----------
    system : RollingSystem
        With ``support="surface"`` (any convex ``support_surface``), rolling, gravity, an
        offset centre and a constant rotor.
    model : Model
    pvals : mapping of sympy.Symbol to sympy.Expr
        Exact parameter values.
    omegas : sequence of 3 numbers
        Angular velocities (space components), each paired with each contact point.
    digits : int
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
        kane = _FORMED[key] = _KaneOnImplicitSupport(system, pvals)
    sub = {**dict.fromkeys(system._parsed["mass"].free_symbols, sp.S.One), **dict(pvals)}
    contacts = support_contacts(system._parsed["support_surface"].xreplace(sub))
    return compare_at_points(kane, contacts, model, pvals, omegas, digits, relative)
