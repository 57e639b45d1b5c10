"""Kane's cross-check of a convex body whose contact point is implicit (issue 24).

A body ``f(r) = 0`` that is not an ellipsoid on a plane, and any convex body on a fixed
sphere, has no contact point in closed form. Here it is set up again with
``sympy.physics.mechanics.KanesMethod`` carrying the contact point as coordinates, sharing
no formula with the Lagrange–d'Alembert engine (:mod:`chaplygin.derive.body_on_sphere`):

* coordinates: the body-fixed 3-2-1 Euler angles ``q1, q2, q3`` of ``B``; the place of
  the contact on the support, ``S = x N.x + y N.y`` on the plane ``z = 0`` (``N.z`` up,
  ``x, y`` from a turntable's axis) or ``S = R e_r(x, y)`` on a fixed sphere of radius
  ``R`` centred at the origin (``e_r = (cos x, sin x cos y, sin x sin y)``); the contact
  point ``r = (r1, r2, r3)`` from the centre of mass, body axes. The centre of mass is
  ``G = S - r``; its velocity is sympy's time derivative of that position.
* speeds: ``u1, u2, u3`` the space components of the angular velocity, ``u4 .. u8`` the
  rates of ``x, y, r1, r2, r3`` — all but the angular velocity dependent.
* velocity constraints: no slip — the body point at the contact moves with the support
  there (all three components: ``0`` on a fixed support, ``Omega N.z x S`` on a turntable,
  ``V1 N.x + V2 N.y`` on a shaken plane); the time derivatives (sympy's) of the holonomic
  conditions that ``grad f(r)`` is normal to the support, ``(grad f, t_i) = 0`` for its
  two tangents ``N.x, N.y`` (plane) or ``de_r/dx, de_r/dy`` (sphere), body components.
  (``f(r) = 0`` is kept by the normal component of no slip.) No twist (``"rubber"``):
  ``(omega, n) = Omega`` with ``u3`` dependent, ``n`` the support's normal into the body.
  Along a line: no spin about it with ``u1`` dependent (``N.x``, on a turntable the line it
  carries, :func:`~.kane_common.support_line`).
* loads: gravity ``-m g N.z`` at ``G``; a potential ``V(gamma, zeta)`` of the normal
  ``gamma = n`` and the vertical ``zeta = N.z`` (body axes) written as a function of the
  coordinates and applied as the generalised force ``-dV/dq_j`` (two massless points
  whose velocities are the coordinates' rates carry it: no torque formula); the gyrostat
  as real rotors (:func:`~.kane_common.rigid_bodies`).

KanesMethod's ``constraint_solver`` is handed placeholders for ``B_dep^-1 B_ind`` (the
dependent speeds' coefficients), filled numerically at each point: the symbolic inverse
of the constraints' 5 x 5 block would swell beyond use. The comparison points are exact
directions from the centre of mass, each meeting the surface at the smallest positive
root of a polynomial (``f`` along the ray: real-root isolation, then 50 digits); the
support is placed where its normal into the body is ``n(r) = -grad f/|grad f|``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import mpmath
import sympy as sp
import sympy.physics.mechanics as me

from ..derive.model import Model
from ..derive.rolling_system import RollingSystem
from ..derive.vectors import vector
from . import kane_common as common
from .kane_common import DIGITS, KaneComparison, placement, rigid_bodies, support_line

__all__ = ["compare_implicit", "contact_on_ray", "interior_point", "places_contacts"]

#: Kane's equations formed, by (description fingerprint, parameter values).
_FORMED: dict = {}


def interior_point(surface: sp.Expr) -> mpmath.matrix:
    """A point inside the body (``f < 0``), from every ray of which the body is left once:
    the centre of mass where it is inside, else the first point of a damped Newton descent
    of ``f`` from it that is.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(r)`` in ``r1, r2, r3`` with numeric coefficients, convex.

    Returns
    -------
    mpmath.matrix
        At :data:`~.kane_common.DIGITS` + 20 digits.

    Raises
    ------
    ValueError
        When ``f`` has symbols left, or the descent finds no point with ``f < 0`` (an
        empty body; ``f`` not convex).
    """
    r = vector("r", real=True)
    if surface.free_symbols - set(r):
        raise ValueError(f"the surface {surface} has symbols the model does not fix")
    grad = [sp.diff(surface, x) for x in r]
    f, g, H = (
        sp.lambdify([list(r)], e, modules="mpmath")
        for e in (surface, grad, sp.hessian(surface, list(r)))
    )
    with mpmath.workdps(DIGITS + 20):
        c = mpmath.matrix([0, 0, 0])
        for _ in range(200):
            now = f(list(c))
            if now < 0:
                return c
            slope_vector = mpmath.matrix(g(list(c)))
            try:
                step = mpmath.lu_solve(mpmath.matrix(H(list(c))), slope_vector)
            except ZeroDivisionError:  # a singular Hessian: no Newton step
                break
            slope = (slope_vector.T * step)[0]
            if not slope > 0:  # not a descent direction (f not convex, or a minimum)
                break
            t = mpmath.mpf(1)
            while f(list(c - t * step)) > now - t * slope / 4 and t > mpmath.mpf(2) ** -60:
                t /= 2
            c = c - t * step
    raise ValueError(f"no point inside the body {surface} < 0 found (empty, or not convex)")


def contact_on_ray(surface: sp.Expr, direction: Sequence[sp.Expr]) -> list:
    """Where the ray from :func:`interior_point` along ``direction`` leaves the body: the
    smallest positive root of the polynomial ``f(c + s d)``, polished by Newton.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(r)`` in ``r1, r2, r3`` with numeric coefficients.
    direction : sequence of 3 numbers

    Returns
    -------
    list of mpmath.mpf
        The contact point (from the centre of mass), :data:`~.kane_common.DIGITS` + 20
        digits.

    Raises
    ------
    ValueError
        When the ray does not meet the surface (or :func:`interior_point` fails).
    """
    c = interior_point(surface)
    s = sp.Symbol("s", real=True)
    r = vector("r", real=True)
    with mpmath.workdps(DIGITS + 20):
        at = lambda x: sp.Float(x, DIGITS + 20)  # noqa: E731
        d = mpmath.matrix([mpmath.mpf(at(sp.N(x, DIGITS + 25))) for x in direction])
        along = {r[i]: at(c[i]) + s * at(d[i]) for i in range(3)}
        poly = sp.Poly(sp.expand(surface.xreplace(along)), s)
        coeffs = [mpmath.mpf(x) for x in poly.all_coeffs()]
        roots = mpmath.polyroots(coeffs, maxsteps=400, extraprec=4 * (DIGITS + 20))
        tiny = mpmath.mpf(10) ** -(DIGITS // 2)
        real = [mpmath.re(x) for x in roots if abs(mpmath.im(x)) < tiny and mpmath.re(x) > 0]
        if not real:
            raise ValueError(f"the ray along {tuple(direction)} does not meet {surface} = 0")
        root = mpmath.findroot(lambda x: mpmath.polyval(coeffs, x), min(real))
        return [c[i] + root * d[i] for i in range(3)]


def places_contacts(surface: sp.Expr) -> bool:
    """Whether :func:`compare_implicit` finds its contact points: every ray along ``-g``
    (``g`` in :data:`~.kane_common.RATIONAL_UNIT_VECTORS`) meets the surface.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(r)`` with exact coefficients.

    Returns
    -------
    bool
    """
    try:
        for g in common.RATIONAL_UNIT_VECTORS:
            contact_on_ray(surface, [-c for c in g])
    except ValueError:
        return False
    return True


class _KaneImplicit:
    """Kane's equations of the convex body with its contact point as coordinates."""

    def __init__(
        self, system: RollingSystem, pvals: Mapping[sp.Symbol, sp.Expr], line_carried: bool = True
    ) -> None:
        p, sub = system._parsed, _by_name(system, pvals)
        t = me.dynamicsymbols._t
        now = {sp.Symbol("t", real=True): t, **sub}
        q, u, N, B, euler, kd, rates = common.body_coordinates("x y r1 r2 r3")
        in_B = lambda v: sp.Matrix([v.dot(B.x), v.dot(B.y), v.dot(B.z)])  # noqa: E731
        self._sphere, self._inside = system.support == "sphere", system.side == "inside"
        if self._sphere:
            e_r = sp.cos(q[3]) * N.x + sp.sin(q[3]) * (sp.cos(q[4]) * N.y + sp.sin(q[4]) * N.z)
            S = p["support_radius"].xreplace(sub) * e_r
            normal = -e_r if self._inside else e_r  # into the body
            tangents = (e_r.diff(q[3], N), e_r.diff(q[4], N))
        else:
            S, normal, tangents = q[3] * N.x + q[4] * N.y, N.z, (N.x, N.y)
        r_vec = q[5] * B.x + q[6] * B.y + q[7] * B.z
        origin = me.Point("origin")
        origin.set_vel(N, 0)
        G = origin.locatenew("G", S - r_vec)
        G.set_vel(N, G.pos_from(origin).dt(N).xreplace(rates))
        P = origin.locatenew("P", S)  # where the contact is (the momentum's point)
        body_point = G.locatenew("Q", r_vec)
        body_point.v2pt_theory(G, N, B)
        Omega = p["rotation_rate"].xreplace(now)
        V = p["plane_velocity"].xreplace(now)
        carried = Omega * N.z.cross(S) + V[0] * N.x + V[1] * N.y
        slip = body_point.vel(N) - carried
        constraints = [slip.dot(e) for e in (N.x, N.y, N.z)]
        r_symbols = vector("r", real=True)
        at_r = dict(zip(r_symbols, q[5:], strict=True))
        surface = p["surface"].xreplace(sub)
        grad = sp.Matrix([sp.diff(surface, s) for s in r_symbols]).xreplace(at_r)
        constraints += [grad.dot(in_B(e)).diff(t) for e in tangents]  # KanesMethod maps q'
        dependent = u[3:]
        if system.contact == "rubber":  # no twist relative to the support
            constraints.append(B.ang_vel_in(N).dot(normal) - Omega)
            dependent = [u[2], *dependent]
        turning = Omega if system.contact == "line" else sp.S.Zero
        line, settle = support_line(N, turning, line_carried)  # N.x, or a turntable's
        if system.contact == "line":  # along the line: (omega, line) = 0
            constraints.append(B.ang_vel_in(N).dot(line))
            dependent = [u[0], *dependent]
        independent = [s for s in u if s not in dependent]
        bodies = rigid_bodies(p, sub, (N, B), G, t)
        loads = []
        field = p["field"].xreplace(sub)
        if field != 0:
            loads.append((G, -bodies[0].mass * field * N.z))
        loads += self._potential(p["potential"].xreplace(sub), (N, B), q, u, normal, euler)
        self._kane = common.form_with_placeholders(
            N, q, (independent, dependent), kd, constraints, bodies, loads, settle
        )
        self._lambdify((N, B), (P, S, bodies), t, (line, settle))

    def _lambdify(self, frames, places, t, line) -> None:
        """The further numeric functions of ``(q, u, t)`` :meth:`at` evaluates (``line``:
        the line's direction and what settles its angle, :func:`~.kane_common.support_line`)."""
        N, B = frames
        P, S, bodies = places
        in_B = lambda v: sp.Matrix([v.dot(B.x), v.dot(B.y), v.dot(B.z)])  # noqa: E731
        fn, kdmap = self._kane.lambdify, self._kane.method.kindiffdict()
        H = sum((body.angular_momentum(P, N) for body in bodies), me.Vector(0))
        line, settle = line
        self._momentum = fn(settle(in_B(H)))
        self._C = fn(sp.Matrix(3, 3, lambda i, j: (B.x, B.y, B.z)[i].dot((N.x, N.y, N.z)[j])))
        carried = {"rho": in_B(S), "alpha": in_B(line), "beta": in_B(N.z.cross(line)),
                   "zeta": in_B(N.z)}  # fmt: skip
        self._rates = {n: fn(settle(v.diff(t).xreplace(kdmap))) for n, v in carried.items()}

    def _potential(self, V: sp.Expr, frames, q, u, normal, euler) -> list:
        """``V(gamma, zeta)`` as a function of the coordinates, applied as ``-dV/dq_j``: at a
        massless point moving at ``(q1', q2', q3')`` and one moving at ``(x', y', 0)``."""
        if V == 0:
            return []
        N, B = frames
        t = me.dynamicsymbols._t
        gs, zs = sp.symbols("gamma1:4", real=True), sp.symbols("zeta1:4", real=True)
        at = dict(zip(gs, [normal.dot(e) for e in (B.x, B.y, B.z)], strict=True))
        at.update(zip(zs, [N.z.dot(e) for e in (B.x, B.y, B.z)], strict=True))
        groups = [("angles", q[:3], [euler[s.diff(t)] for s in q[:3]]), ("place", q[3:5], u[3:5])]
        return common.potential_loads(V.xreplace(at), N, groups)

    def frame(self, q: Sequence[mpmath.mpf], time: mpmath.mpf) -> mpmath.matrix:
        """``C`` (rows: the body axes in ``N``) at the coordinates ``q``."""
        return mpmath.matrix(self._C(q, [mpmath.mpf(0)] * 8, time))

    def at(self, q: list, omega_space: Sequence[mpmath.mpf], time: mpmath.mpf) -> dict:
        """Kane's rates at the coordinates ``q`` and angular velocity (space components):
        ``omega'`` (body components), ``r'``, the carried vectors' rates and the momentum
        about the contact (body components)."""
        known = dict(zip(("u1", "u2", "u3"), omega_space, strict=True))
        speed, by_name, u = common.solve_speeds(self._kane, q, known, time)
        C = self.frame(q, time)
        acc = C * mpmath.matrix([by_name[f"u{i}"] for i in (1, 2, 3)])
        rates = {"omega": list(acc), "r": [speed[f"u{i}"] for i in (6, 7, 8)]}
        rates.update((n, list(mpmath.matrix(f(q, u, time)))) for n, f in self._rates.items())
        rates["momentum"] = list(mpmath.matrix(self._momentum(q, u, time)))
        return rates


def compare_implicit(
    system: RollingSystem,
    model: Model,
    pvals: Mapping[sp.Symbol, sp.Expr],
    momenta: Sequence[Sequence[object]],
    line_carried: bool = True,
) -> KaneComparison:
    """The model's rates against Kane's at the contact points of the directions ``-g``,
    ``g`` in :data:`~.kane_common.RATIONAL_UNIT_VECTORS`, at the time
    :data:`~.kane_common.T0`.

    Compared: ``omega'`` and the momentum about the contact, and ``r'`` with the carried
    vectors' rates (``rho'`` on a turntable, ``alpha', beta'`` on a shaken plane,
    ``zeta'`` on a sphere with the vertical) as ``max_normal_rate_error``.

    Parameters
    ----------
    system : RollingSystem
        A convex body (``surface``) on a plane, turning or shaken, or on a fixed sphere.
    model : Model
        Its model (any route).
    pvals : mapping of sympy.Symbol to sympy.Expr
        Exact values of the parameters.
    momenta : sequence of 3 numbers
        Angular velocities (body components), each paired with each contact point; with
        ``"rubber"`` moved onto ``(omega, n) = Omega``.
    line_carried : bool
        Along a line on a turntable: Kane's line turns with it (False: held fixed in
        space, a control).

    Returns
    -------
    KaneComparison
    """
    values = tuple(sorted((s.name, v) for s, v in pvals.items()))
    key = (system.fingerprint(), line_carried, values)
    kane = _FORMED.get(key)
    if kane is None:  # forming Kane's equations is the cost: once per system and values
        kane = _FORMED[key] = _KaneImplicit(system, pvals, line_carried)
    groups = dict(model.state_groups)
    time = sp.Symbol("t", real=True)
    index = {s: list(model.state).index(s) for s in model.state}
    momentum = model.details.equations.reduced.momentum.xreplace(pvals)
    sub = _by_name(system, pvals)  # the system's symbols (Kane's may differ: controls)
    surface = system._parsed["surface"].xreplace(sub)
    r = vector("r", real=True)
    grad = sp.lambdify([list(r)], [sp.diff(surface, s) for s in r], modules="mpmath")
    Omega = system._parsed["rotation_rate"].xreplace({**sub, time: common.T0})
    carried = [n for n in ("rho", "alpha", "beta", "zeta") if n in groups]
    worst = [0.0, 0.0, 0.0]
    count = 0
    with mpmath.workdps(DIGITS):
        T = common._mpf(common.T0)
        for w in momenta:
            for g in common.RATIONAL_UNIT_VECTORS:
                contact = contact_on_ray(surface, [-c for c in g])
                n = -mpmath.matrix(grad(contact))
                n = n / mpmath.norm(n)  # the support's normal into the body
                q = placement(list(n), kane._sphere, kane._inside) + contact
                C = kane.frame(q, T)
                point = {time: common.T0}
                if "rho" in groups:  # the contact's place from the axis: horizontal
                    seed = mpmath.matrix([common._mpf(c) for c in common._RHO_SEED])
                    rho = seed - (seed.T * n)[0] * n
                    space = C.T * rho
                    q[3], q[4] = space[0], space[1]
                    point.update(zip(groups["rho"], map(_float, rho), strict=True))
                wb = mpmath.matrix([common._mpf(c) for c in w])
                if system.contact == "rubber":
                    wb = wb + (common._mpf(Omega) - (wb.T * n)[0]) * n
                if system.contact == "line":  # onto (omega, alpha) = 0, alpha = N.x in B
                    alpha = mpmath.matrix([C[i, 0] for i in range(3)])
                    wb = wb - (wb.T * alpha)[0] * alpha
                point.update(zip(groups["omega"], map(_float, wb), strict=True))
                point.update(zip(groups["r"], map(_float, contact), strict=True))
                for name, column in (("alpha", 0), ("beta", 1), ("zeta", 2)):
                    if name in groups:
                        comps = [C[i, column] for i in range(3)]
                        point.update(zip(groups[name], map(_float, comps), strict=True))
                theirs = kane.at(q, list(C.T * wb), T)
                F = common.model_rates(model, {**pvals, **point})
                ours = {name: [F[index[s]] for s in groups[name]] for name in groups}
                worst[0] = max(worst[0], common._relative(ours["omega"], theirs["omega"]))
                H = list(momentum.xreplace(point))
                worst[1] = max(worst[1], common._relative(H, theirs["momentum"]))
                for name in ("r", *carried):
                    worst[2] = max(worst[2], common._relative(ours[name], theirs[name]))
                count += 1
    return KaneComparison(count, *worst, 10.0 ** -(DIGITS - 10))


def _by_name(system: RollingSystem, pvals: Mapping[sp.Symbol, sp.Expr]) -> dict:
    """The values of the system's parameters, matched to ``pvals`` (the model's) by name."""
    values = {s.name: v for s, v in pvals.items()}
    return {x: values[x.name] for x in system._parsed["parameters"] if x.name in values}


def _float(c: mpmath.mpf) -> sp.Float:
    """A sympy number carrying ``c``'s digits (five beyond the comparison's)."""
    return sp.Float(mpmath.nstr(c, DIGITS + 5), DIGITS + 5)
