"""Cross-check of any described rolling body through ``sympy.physics.mechanics.KanesMethod``.

A :class:`~chaplygin.derive.rolling_system.RollingSystem` is set up again from scratch
with Kane's method, sharing no code and no formula with the Lagrange–d'Alembert engine
that derived its model:

* ``N`` inertial, ``N.z`` up, the plane ``z = 0``; the body frame ``B`` oriented by
  body-fixed 3-2-1 Euler angles ``q1, q2, q3``; the sphere's centre ``O`` at
  ``x N.x + y N.y + b N.z``; the centre of mass ``G = O + a`` (``a`` fixed in ``B``).
* On a fixed sphere of radius ``R`` (centre at the origin): ``O`` on the sphere of radius
  ``rho = R + b`` (outside) or ``R - b`` (inside) at the angles ``x, y`` (``O = rho
  (cos x, sin x cos y, sin x sin y)``), the contact point ``P = O -+ b e_r``; its
  comparison points sit at ``x = y = pi/2`` (``e_r = N.z``).
* Speeds: ``u1, u2, u3`` the *space-frame* components of the angular velocity, ``u4,
  u5`` the horizontal velocity of ``O`` (on a sphere: the rates of ``x, y``). No slip:
  the body point at the contact ``P`` has zero tangential velocity (``u4, u5``
  dependent) — on a rotating plane the plane's velocity there, ``Omega N.z x (x N.x + y
  N.y)`` (affine constraints). No twist (``"rubber"``): ``u3 = 0`` as a third velocity
  constraint. Along a line: no spin about it, ``u1`` dependent — the line ``N.x``, on a
  turntable the line it carries (:func:`~.kane_common.support_line`).
* Loads: gravity ``-m g N.z`` at ``G``; a potential of the orientation as the torque
  ``gamma x dV/dgamma`` on ``B`` (the one place a formula is shared: the torque of a
  potential); a gyrostatic momentum ``K`` (constant or prescribed ``K(t)``) as real
  rotors (massless bodies turning about the body axes ``e_i`` relative to ``B`` at the
  rates ``K_i(t)/Ia`` their motors set; the body's own tensor is the given one minus
  the rotors').

At exact points of the phase space the model's angular acceleration
``d omega/d(M, gamma) . (M', gamma')`` is compared with Kane's (body components of
``C u'``), and the model's momentum ``M`` with sympy's angular momentum about the
contact point, at :data:`DIGITS` digits: the tolerance is ``10**-(DIGITS - 10)``
relative, ten digits left to the conditioning of the two linear solves.

A convex body whose contact point has no closed form (any surface but an ellipsoid on a
plane; every body on a fixed sphere) is compared by :mod:`.kane_implicit` instead: the
contact point carried as coordinates with its holonomic conditions.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import mpmath
import sympy as sp
import sympy.physics.mechanics as me

from ..derive.model import Model
from ..derive.rolling_system import RollingSystem
from .kane_common import (
    _RHO_SEED,
    DIGITS,
    RATIONAL_UNIT_VECTORS,
    T0,
    KaneComparison,
    _mpf,
    _relative,
    model_rates,
    placement,
    rigid_bodies,
    support_line,
)
from .kane_euler import euler_rates
from .kane_implicit import compare_implicit

__all__ = ["KaneComparison", "kane_compare", "DIGITS", "RATIONAL_UNIT_VECTORS", "T0"]

def _support_compare(system: RollingSystem, pvals: Mapping[sp.Symbol, sp.Expr]) -> Callable:
    """The comparison on a support surface: a ball on an ellipsoid's parametrisation
    (gravity, an offset, a constant rotor; the support at the values ``pvals``), or with
    its contact point as coordinates; a convex body with both contact points as
    coordinates."""
    from .kane_support import compare_on_support, is_ellipsoid, parametrised_covers
    from .kane_support_implicit import compare_on_implicit_support

    if system._parsed["surface"] is not None:
        from .kane_body_support import compare_body_on_support

        return compare_body_on_support
    by_name = {s.name: v for s, v in pvals.items()}
    F = system._parsed["support_surface"]
    F = F.xreplace({s: by_name[s.name] for s in F.free_symbols if s.name in by_name})
    closed = is_ellipsoid(F) and parametrised_covers(system._parsed)
    return compare_on_support if closed else compare_on_implicit_support


def kane_compare(
    system: RollingSystem,
    model: Model,
    values: Mapping[str, object],
    momenta: Sequence[Sequence[object]] = (
        (sp.Rational(3, 10), sp.Rational(-7, 10), sp.Rational(11, 10)),
    ),
    line_carried: bool = True,
) -> KaneComparison:
    """Compare ``model`` (derived from ``system``) with Kane's method.

    Parameters
    ----------
    system : RollingSystem
    model : Model
        Its model (any route; the Lagrange–d'Alembert one normally).
    values : mapping of str to number
        A value of every parameter (exact: rationals; strings are read exactly).
    momenta : sequence of 3 numbers
        Momentum components; with ``"rubber"`` the third is solved from the invariant
        relation. Each is paired with each of :data:`RATIONAL_UNIT_VECTORS`. On a
        support surface: the angular velocity's (space) components, each paired with
        each contact point of :data:`~.kane_support.SUPPORT_ANGLES` (the ball's
        ``omega'`` and ``p'`` compared; ``max_momentum_error`` is 0: no momentum state).
        A convex body without a closed-form contact (:mod:`.kane_implicit`): the angular
        velocity's body components, each paired with the contact points of the rays along
        ``-g``, ``g`` in :data:`RATIONAL_UNIT_VECTORS`.
    line_carried : bool
        Along a line on a turntable: Kane's line turns with it (False: Kane's is held fixed
        in space, a control the model should fail).

    Returns
    -------
    KaneComparison
    """
    pvals = {s: sp.Rational(str(values[s.name])) for s in model.params}
    tolerance = 10.0 ** -(DIGITS - 10)
    if system.support == "surface":  # on a support surface: omega' and the contact's rates
        compare = _support_compare(system, pvals)
        count, acc, rate = compare(system, model, pvals, momenta, DIGITS, _relative)
        return KaneComparison(count, acc, 0.0, rate, tolerance)  # no momentum state there
    if system._parsed["surface"] is not None and not _closed_form(system, pvals):
        return compare_implicit(system, model, pvals, momenta, line_carried)
    # along a line (a convex body's model has no relation for it: its omega is state)
    line = system.contact == "line" or "(omega,alpha)" in dict(model.invariant_relations)
    values = tuple(sorted((s.name, v) for s, v in pvals.items()))
    key = (system.fingerprint(), line, line_carried, values)
    kane = _KANE.get(key)
    if kane is None:  # forming Kane's equations is the cost (seconds): once per point
        kane = _KANE[key] = _KaneRolling(system, pvals, line, line_carried)
    if system._parsed["surface"] is not None:
        return _compare_convex(system, model, kane, pvals, momenta)
    omega_of_x = model.expand_aux(model.omega).xreplace(pvals)
    jac = omega_of_x.jacobian(sp.Matrix(model.state))  # evaluated at exact points below
    explicit = omega_of_x.diff(sp.Symbol("t", real=True))  # I(t): omega(M, t)
    relations = [  # the ones on the momentum (no twist); rho is placed horizontal below
        model.expand_aux(e).xreplace(pvals)
        for name, e in model.invariant_relations
        if name.startswith("(omega,")
    ]
    M = sp.Matrix(model.group("M"))
    # the velocity-independent momentum the state leaves out (K; on a rotating plane
    # also the carried contact's m r x (Omega gamma x rho))
    P0 = model.details.gyrostatic_momentum.xreplace(pvals)
    g = sp.Matrix(model.group("gamma"))
    rate_groups = ["gamma"] + [n for n in ("rho", "zeta", "alpha", "beta")
                               if n in dict(model.state_groups)]  # fmt: skip
    at_group = {n: [list(model.state).index(s) for s in model.group(n)] for n in rate_groups}
    groups = dict(model.state_groups)
    time = sp.Symbol("t", real=True)
    # prescribed rates (of the model or of the system Kane sets up): compared at T0
    prescribed = ("rotation_rate", "plane_velocity", "rotor_momentum", "inertia")
    timed = _has_time(model, time, P0, *(sp.sympify(system._parsed[k]) for k in prescribed))
    worst_acc = worst_mom = worst_rate = 0.0
    count = 0
    for m0 in momenta:
        for gamma in RATIONAL_UNIT_VECTORS:
            point = {**dict(zip(g, gamma, strict=True)), **dict(zip(M, m0, strict=True))}
            rho = None
            if "rho" in dict(model.state_groups):  # horizontal: (rho, gamma) = 0
                w = sp.Matrix(_RHO_SEED)
                rho = list(w - w.dot(sp.Matrix(gamma)) * sp.Matrix(gamma))
                point.update(zip(model.group("rho"), rho, strict=True))
            if "zeta" in groups:  # the vertical where Kane's body is (40 digits)
                point.update(
                    (s, sp.Float(mpmath.nstr(c, DIGITS + 5), DIGITS))
                    for s, c in zip(groups["zeta"], kane.vertical(gamma), strict=True)
                )
            if "alpha" in groups:  # the fixed axes where Kane's body is (40 digits)
                alpha, beta = kane.frame(gamma)
                for name, comps in (("alpha", alpha), ("beta", beta)):
                    point.update(
                        (s, sp.Float(mpmath.nstr(c, DIGITS + 5), DIGITS))
                        for s, c in zip(groups[name], comps, strict=True)
                    )
            if timed:
                point[time] = T0
            if relations:  # the last momentum components solved from the relations
                unknowns = list(M[3 - len(relations) :])
                for x in unknowns:
                    point.pop(x)
                rels = sp.Matrix([sp.numer(sp.together(rel.xreplace(point))) for rel in relations])
                # linear in the unknowns; LU keeps the 40-digit frame's digits (solve would not)
                A = rels.jacobian(unknowns)
                rhs0 = -rels.xreplace(dict.fromkeys(unknowns, 0))
                point.update(zip(unknowns, A.LUsolve(rhs0), strict=True))
            w = [omega_of_x[i].xreplace(point) for i in range(3)]
            F = sp.Matrix(model_rates(model, {**pvals, **point}))  # not the expanded rhs
            J = jac.xreplace(point)
            ours = list(J * F + explicit.xreplace(point))  # + d omega/dt at fixed state
            theirs, momentum, rates = kane.at(gamma, w, rho, point.get(time, 0))
            worst_acc = max(worst_acc, _relative(ours, theirs))
            for name, idx in at_group.items():
                worst_rate = max(worst_rate, _relative([F[i] for i in idx], rates[name]))
            P0_here = P0.xreplace(point)
            total = [point[M[i]] + P0_here[i] for i in range(3)]
            worst_mom = max(worst_mom, _relative(total, momentum))
            count += 1
    return KaneComparison(count, worst_acc, worst_mom, worst_rate, 10.0 ** -(DIGITS - 10))


def quadric_contact(surface: sp.Expr, up: sp.Matrix) -> sp.Matrix:
    """The contact point ``r`` of a convex quadric ``f(r) = 0`` whose outward normal is
    ``-up``: ``r = r0 - s A^-1 up / sqrt(up . A^-1 up)`` for ``f = (r - r0)^T A (r - r0) -
    s^2`` (the inverse of the Gauss map, in closed form for a quadric only).

    Parameters
    ----------
    surface : sympy.Expr
        A polynomial of degree 2 in ``r1, r2, r3`` with numeric coefficients.
    up : sympy.Matrix, shape (3, 1)
        The upward normal in body axes.

    Returns
    -------
    sympy.Matrix, shape (3, 1)

    Raises
    ------
    ValueError
        When ``surface`` is not an ellipsoid.
    """
    r = sp.Matrix(sp.symbols("r1:4", real=True))
    A = sp.hessian(surface, list(r)) / 2
    if A.free_symbols & set(r) or not A.is_positive_definite:
        raise ValueError("the Kane comparison takes an ellipsoid (a quadric with A > 0) only")
    linear = sp.Matrix([sp.diff(surface, x) for x in r]).xreplace(dict.fromkeys(r, 0))
    r0 = -A.inv() * linear / 2
    s2 = -surface.xreplace(dict(zip(r, r0, strict=True)))
    w = A.inv() * up
    return r0 - sp.sqrt(s2) * w / sp.sqrt(up.dot(w))


def _closed_form(system: RollingSystem, pvals: Mapping[sp.Symbol, sp.Expr]) -> bool:
    """Whether the body's contact point is :func:`quadric_contact`'s: an ellipsoid on a
    plane (on a sphere, or for any other surface, it is implicit)."""
    if system.support == "sphere":
        return False
    try:
        quadric_contact(system._parsed["surface"].xreplace(pvals), sp.Matrix([0, 0, 1]))
    except ValueError:
        return False
    return True


def _has_time(model: Model, time: sp.Symbol, *others: sp.Basic | sp.MatrixBase) -> bool:
    """Whether the model's right-hand side, its auxiliaries or ``others`` contain ``time``."""
    return any(e.has(time) for e in (*model.rhs, *(e for _, e in model.aux), *others))


def _compare_convex(system, model, kane, pvals, momenta) -> KaneComparison:
    """``omega'``, ``r'`` (and on a turntable ``rho'``) of the state ``(omega, r, ...)``
    against Kane's, and the momentum about the contact, at the contact points of
    :data:`RATIONAL_UNIT_VECTORS` (at :data:`T0` when a law depends on time; a rubber
    body's ``omega`` moved onto ``(omega, gamma) = Omega``; on a shaken plane the fixed
    axes where Kane's body is)."""
    groups = dict(model.state_groups)
    omega, r = sp.Matrix(groups["omega"]), sp.Matrix(groups["r"])
    time = sp.Symbol("t", real=True)
    compared = [n for n in ("omega", "r", "rho", "alpha", "beta") if n in groups]
    index = {s: list(model.state).index(s) for n in compared for s in groups[n]}
    momentum = model.details.equations.reduced.momentum.xreplace(pvals)
    surface = system._parsed["surface"].xreplace(pvals)
    timed = _has_time(model, time, momentum)
    now = T0 if timed else sp.S.Zero
    Omega = system._parsed["rotation_rate"].xreplace({**pvals, time: now})
    worst = [0.0, 0.0, 0.0]
    count = 0
    for w in momenta:
        for gamma in RATIONAL_UNIT_VECTORS:
            g = sp.Matrix(gamma)
            contact = quadric_contact(surface, g)
            w = sp.Matrix(w)
            if system.contact == "rubber":
                w = w + (Omega - w.dot(g)) * g
            if system.contact == "line":  # onto (omega, alpha) = 0
                a = sp.Matrix([sp.Float(mpmath.nstr(c, DIGITS + 5), DIGITS + 5)
                               for c in kane.frame(gamma)[0]])  # fmt: skip
                w = w - w.dot(a) * a
            point = {**dict(zip(omega, w, strict=True)), **dict(zip(r, contact, strict=True))}
            point[time] = now
            rho = None
            if "rho" in groups:  # horizontal
                rho = list(sp.Matrix(_RHO_SEED) - sp.Matrix(_RHO_SEED).dot(g) * g)
                point.update(zip(groups["rho"], rho, strict=True))
            if "alpha" in groups:
                for name, comps in zip(("alpha", "beta"), kane.frame(gamma), strict=True):
                    point.update(
                        (s, sp.Float(mpmath.nstr(c, DIGITS + 5), DIGITS))
                        for s, c in zip(groups[name], comps, strict=True)
                    )
            F = model_rates(model, {**pvals, **point})
            theirs, H, rates = kane.at(gamma, list(w), rho, now, contact if rho else None)
            worst[0] = max(worst[0], _relative([F[index[s]] for s in omega], theirs))
            worst[1] = max(worst[1], _relative(list(momentum.xreplace(point)), H))
            for name in compared[1:]:
                ours = [F[index[s]] for s in groups[name]]
                worst[2] = max(worst[2], _relative(ours, rates[name]))
            count += 1
    return KaneComparison(count, *worst, 10.0 ** -(DIGITS - 10))


#: Kane's equations formed, by (description fingerprint, parameter values).
_KANE: dict = {}


class _KaneRolling:
    """Kane's equations of the described body, parameters substituted (exact)."""

    def __init__(
        self, system: RollingSystem, pvals: Mapping[sp.Symbol, sp.Expr], line: bool = False,
        line_carried: bool = True,
    ) -> None:  # fmt: skip
        sub = dict(pvals)
        q = list(me.dynamicsymbols("q1 q2 q3 x y"))
        u = list(me.dynamicsymbols("u1 u2 u3 u4 u5"))
        t = me.dynamicsymbols._t
        N, B = me.ReferenceFrame("N"), me.ReferenceFrame("B")
        B.orient_body_fixed(N, tuple(q[:3]), "zyx")
        solved = euler_rates()
        kd = [r - solved[r] for r in (s.diff(t) for s in q[:3])]
        kd += [q[3].diff(t) - u[3], q[4].diff(t) - u[4]]
        B.set_ang_vel(N, u[0] * N.x + u[1] * N.y + u[2] * N.z)
        p = system._parsed
        m = p["mass"].xreplace(sub)
        self._flip = system.support == "sphere" and system.side == "inside"
        self._at_pole = system.support == "sphere"
        G, P, normal, tangents, carried = self._contact(system, p, sub, (N, B), q, u, t, solved)
        gamma_B = sp.Matrix([N.z.dot(B.x), N.z.dot(B.y), N.z.dot(B.z)])
        slip = P.vel(N) - carried
        constraints = [slip.dot(tangents[0]), slip.dot(tangents[1])]
        dependent = [u[3], u[4]]
        if system.contact == "rubber":  # no twist relative to the support (a turntable's Omega)
            Omega = p["rotation_rate"].xreplace({sp.Symbol("t", real=True): t, **sub})
            constraints.append(u[2] - Omega)
            dependent = [u[2], u[3], u[4]]
        now = {sp.Symbol("t", real=True): t, **sub}  # prescribed rates: of Kane's time
        turning = p["rotation_rate"].xreplace(now) if line else sp.S.Zero
        line_direction, settle = support_line(N, turning, line_carried)
        if line:  # along the line (N.x, or a turntable's): no spin about it
            constraints.append(B.ang_vel_in(N).dot(line_direction))
            dependent = [u[0], *dependent]
        # a prescribed I(t) is a function of Kane's time (its dI/dt enters the torque)
        bodies = rigid_bodies(p, sub, (N, B), G, t)
        loads = []
        g_field = p["field"].xreplace(sub)
        if g_field != 0:
            loads.append((G, -m * g_field * N.z))
        loads += self._potential_loads(p["potential"].xreplace(sub), (N, B), normal, self._centre)
        independent = [s for s in u if s not in dependent]
        kane = me.KanesMethod(
            N,
            q_ind=q,
            u_ind=independent,
            u_dependent=dependent,
            kd_eqs=kd,
            velocity_constraints=constraints,
        )
        kane.kanes_equations(bodies, loads)
        # linear in the dependent speeds (lambdified below: no simplification needed)
        A_dep, b_dep = sp.linear_eq_to_matrix(constraints, dependent)
        dep = dict(zip(dependent, A_dep.LUsolve(b_dep), strict=True))
        H = sum((body.angular_momentum(P, N) for body in bodies), me.Vector(0))
        H_B = sp.Matrix([H.dot(B.x), H.dot(B.y), H.dot(B.z)]).xreplace(dep)
        C = sp.Matrix(3, 3, lambda i, j: (B.x, B.y, B.z)[i].dot((N.x, N.y, N.z)[j]))
        args = (q, u, t)
        self._mass = sp.lambdify(args, settle(kane.mass_matrix), modules="mpmath")
        self._forcing = sp.lambdify(args, settle(kane.forcing), modules="mpmath")
        self._momentum = sp.lambdify(args, settle(H_B), modules="mpmath")
        self._C = sp.lambdify(args, C, modules="mpmath")
        normal_B = sp.Matrix([normal.dot(B.x), normal.dot(B.y), normal.dot(B.z)])
        normal_rate = normal_B.diff(t).xreplace(kane.kindiffdict())
        self._normal_rate = sp.lambdify(args, normal_rate, modules="mpmath")
        vertical_rate = gamma_B.diff(t).xreplace(kane.kindiffdict())  # N.z in body axes
        self._vertical_rate = sp.lambdify(args, vertical_rate, modules="mpmath")
        # the contact point from the axis (a turntable; for a quadric G + r lies on the plane)
        position = P.pos_from(self._origin) if self._quadric else q[3] * N.x + q[4] * N.y
        position_B = sp.Matrix([position.dot(B.x), position.dot(B.y), position.dot(B.z)])
        position_rate = position_B.diff(t).xreplace(kane.kindiffdict())
        self._position_rate = sp.lambdify(args, position_rate, modules="mpmath")
        if self._quadric:  # the contact point from the centre of mass, body axes
            contact_rate = self._position.diff(t).xreplace(kane.kindiffdict())
            self._contact_rate = sp.lambdify(args, contact_rate, modules="mpmath")
        self._dep = sp.lambdify(args, settle(sp.Matrix([dep[s] for s in dependent])),
                                modules="mpmath")  # fmt: skip
        in_B = lambda v: sp.Matrix([v.dot(B.x), v.dot(B.y), v.dot(B.z)])  # noqa: E731
        self._frame_rates = {  # the line's frame (alpha, beta: N.x, N.y when compared)
            name: sp.lambdify(args, settle(in_B(X).diff(t).xreplace(kane.kindiffdict())),
                              modules="mpmath")
            for name, X in (("alpha", line_direction), ("beta", N.z.cross(line_direction)))
        }  # fmt: skip
        self._order = [str(s.func) for s in kane.u]
        self._dependent = [str(s.func) for s in dependent]

    def _potential_loads(self, V: sp.Expr, frames, normal, O) -> list:
        """The loads of a potential ``V(gamma, zeta)``: ``gamma`` the support's normal
        into the body, ``zeta`` the vertical ``N.z``, both in body axes. Turning the body
        by ``delta theta`` turns both: the torque ``gamma x dV/dgamma + zeta x dV/dzeta``
        on ``B``; on a sphere the normal also turns when ``O`` moves, ``delta n = +- P
        delta O/rho`` (``P`` the tangential projector; + outside): the force ``-+ P dV/dn
        / rho`` at ``O``."""
        if V == 0:
            return []
        N, B = frames
        in_body = lambda vec: sp.Matrix([vec.dot(B.x), vec.dot(B.y), vec.dot(B.z)])  # noqa: E731
        n_B, z_B = in_body(normal), in_body(N.z)
        gs, zs = sp.symbols("gamma1:4", real=True), sp.symbols("zeta1:4", real=True)
        at = {**dict(zip(gs, n_B, strict=True)), **dict(zip(zs, z_B, strict=True))}
        grad_n = sp.Matrix([sp.diff(V, s) for s in gs]).xreplace(at)
        grad_z = sp.Matrix([sp.diff(V, s) for s in zs]).xreplace(at)
        tau = n_B.cross(grad_n) + z_B.cross(grad_z)
        loads = [(B, tau[0] * B.x + tau[1] * B.y + tau[2] * B.z)]
        if self._at_pole:  # on a sphere: the force of the normal's dependence on O
            rho = self._rho
            g_vec = grad_n[0] * B.x + grad_n[1] * B.y + grad_n[2] * B.z
            tangential = g_vec - g_vec.dot(normal) * normal
            sign = -1 if self._flip else 1
            loads.append((O, -sign * tangential / rho))
        return loads

    def _contact(self, system, p, sub, frames, q, u, t, solved):
        """The centre of mass ``G``, the body point ``P`` at the contact, the support's
        normal and tangents there and the support's velocity at the contact."""
        N, B = frames
        b = None if p["radius"] is None else p["radius"].xreplace(sub)
        a = p["centre"].xreplace(sub)
        origin = self._origin = me.Point("origin")
        origin.set_vel(N, 0)
        gamma_B = sp.Matrix([N.z.dot(B.x), N.z.dot(B.y), N.z.dot(B.z)])
        self._quadric = p["surface"] is not None
        if self._quadric:  # a convex quadric: the contact point r(gamma), G at height h
            r_B = quadric_contact(p["surface"].xreplace(sub), gamma_B)
            h = -r_B.dot(gamma_B)
            h_rate = sum((h.diff(s) * solved[s.diff(t)] for s in q[:3]), sp.S.Zero)
            G = origin.locatenew("G", q[3] * N.x + q[4] * N.y + h * N.z)
            G.set_vel(N, u[3] * N.x + u[4] * N.y + h_rate * N.z)
            O, normal, tangents = G, N.z, (N.x, N.y)
        elif system.support == "sphere":
            R = p["support_radius"].xreplace(sub)
            inside = system.side == "inside"
            rho = self._rho = R - b if inside else R + b
            e_r = (
                sp.cos(q[3]) * N.x
                + sp.sin(q[3]) * sp.cos(q[4]) * N.y
                + sp.sin(q[3]) * sp.sin(q[4]) * N.z
            )
            O = origin.locatenew("O", rho * e_r)
            O.set_vel(N, rho * (u[3] * e_r.diff(q[3], N) + u[4] * e_r.diff(q[4], N)))
            normal = -e_r if inside else e_r  # into the body at the contact
            tangents = (e_r.diff(q[3], N), e_r.diff(q[4], N))
        else:
            O = origin.locatenew("O", q[3] * N.x + q[4] * N.y + b * N.z)
            O.set_vel(N, u[3] * N.x + u[4] * N.y)
            normal, tangents = N.z, (N.x, N.y)
        # a rotating plane carries the contact point: P's velocity is Omega N.z x OP
        # prescribed rates are functions of the model's time: Kane's t here
        now = {sp.Symbol("t", real=True): t, **sub}
        Omega = p["rotation_rate"].xreplace(now)
        axis_to_contact = q[3] * N.x + q[4] * N.y  # O (G for a quadric) from the axis
        if self._quadric:  # the contact point P = G + r, horizontally
            axis_to_contact += r_B[0] * B.x + r_B[1] * B.y + r_B[2] * B.z
        carried = Omega * N.z.cross(axis_to_contact) if Omega != 0 else me.Vector(0)
        V = p["plane_velocity"].xreplace(now)  # a moving plane: along the fixed axes
        carried = carried + V[0] * N.x + V[1] * N.y
        if self._quadric:
            P = G.locatenew("P", r_B[0] * B.x + r_B[1] * B.y + r_B[2] * B.z)
            P.v2pt_theory(G, N, B)  # the body point at the contact: v_G + omega x r
        else:
            G = O.locatenew("G", a[0] * B.x + a[1] * B.y + a[2] * B.z)
            G.v2pt_theory(O, N, B)
            P = O.locatenew("P", -b * normal)
            P.v2pt_theory(O, N, B)
        self._position = r_B if self._quadric else None
        self._centre = O
        return G, P, normal, tangents, carried

    def frame(self, gamma: Sequence[sp.Expr]) -> tuple[list, list]:
        """The body components of ``N.x, N.y`` (``alpha, beta``) where :meth:`at` puts the
        body for ``gamma`` (at :data:`DIGITS` digits)."""
        with mpmath.workdps(DIGITS):
            C = mpmath.matrix(self._C(self._angles(gamma), [0] * 5, 0))
            return [C[i, 0] for i in range(3)], [C[i, 1] for i in range(3)]

    def _angles(self, gamma: Sequence[sp.Expr]) -> list:
        """Euler angles and position putting the support's normal at body components
        ``gamma``: on a plane ``N.z`` is the normal; on a sphere ``O`` sits at the generic
        angles :data:`SPHERE_POSITION` (the vertical is not the normal there) and the
        body is turned so that ``e_r`` (outside; ``-e_r`` inside) has components ``gamma``."""
        return placement(gamma, self._at_pole, self._flip)

    def vertical(self, gamma: Sequence[sp.Expr]) -> list:
        """The body components of ``N.z`` (the model's ``zeta``) where :meth:`at` puts the
        body for ``gamma`` (at :data:`DIGITS` digits)."""
        with mpmath.workdps(DIGITS):
            C = mpmath.matrix(self._C(self._angles(gamma), [0] * 5, 0))
            return [C[i, 2] for i in range(3)]

    def at(
        self,
        gamma: Sequence[sp.Expr],
        omega_body: Sequence[sp.Expr],
        rho: Sequence[sp.Expr] | None = None,
        time: sp.Expr = sp.S.Zero,
        contact: Sequence[sp.Expr] | None = None,
    ):
        """Kane's angular acceleration, momentum about the contact, the rate of the
        support's normal (``gamma'``) and of the contact point's position ``rho`` from a
        rotating plane's axis (given: ``rho``), body components, at ``time``; a quadric's
        contact point ``r`` from its centre of mass (given: ``contact``) places its centre
        of mass at ``rho - r`` from the axis."""
        with mpmath.workdps(DIGITS):
            q = self._angles(gamma)
            T = mpmath.mpf(sp.Float(time, DIGITS))
            C = mpmath.matrix(self._C(q, [0] * 5, T))
            if rho is not None:  # its space components: the contact point at (x, y, 0)
                space = C.T * mpmath.matrix([_mpf(x) for x in rho])
                if contact is not None:  # the horizontal place of G = P - r
                    space = space - C.T * mpmath.matrix([_mpf(x) for x in contact])
                q[3], q[4] = space[0], space[1]
            wb = mpmath.matrix([_mpf(x) for x in omega_body])
            ws = C.T * wb  # space components
            u = [ws[0], ws[1], ws[2], mpmath.mpf(0), mpmath.mpf(0)]
            dep = self._dep(q, u, T)
            for name, value in zip(self._dependent, dep, strict=True):
                if name in ("u1", "u3", "u4", "u5"):
                    u[int(name[1:]) - 1] = value
            A = mpmath.matrix(self._mass(q, u, T))
            f = mpmath.matrix(self._forcing(q, u, T))
            solved = mpmath.lu_solve(A, f)
            udot = [mpmath.mpf(0)] * 5
            for name, value in zip(self._order, solved, strict=True):
                udot[int(name[1:]) - 1] = value
            acc = C * mpmath.matrix(udot[:3])
            momentum = self._momentum(q, u, T)
            rate = self._normal_rate(q, u, T)  # of the normal into the body (the model's gamma)
            rates = {"gamma": [rate[i] for i in range(3)]}
            rate = self._vertical_rate(q, u, T)
            rates["zeta"] = [rate[i] for i in range(3)]
            if rho is not None:
                rate = self._position_rate(q, u, T)
                rates["rho"] = [rate[i] for i in range(3)]
            if self._quadric:
                rate = self._contact_rate(q, u, T)
                rates["r"] = [rate[i] for i in range(3)]
            for name, f in self._frame_rates.items():
                rate = f(q, u, T)
                rates[name] = [rate[i] for i in range(3)]
            return [acc[i] for i in range(3)], [momentum[i] for i in range(3)], rates
