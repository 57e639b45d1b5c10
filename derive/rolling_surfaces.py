"""The surfaces of a described rolling system: a convex body ``f(x) = 0`` (on a plane, a
fixed sphere or a support surface) and a fixed support surface ``F(p) = 0`` (a ball or a
convex body on it).

Split from :mod:`.rolling_system` (which calls these while reading and deriving a
:class:`~.rolling_system.RollingSystem`): the reading of the two surfaces, what each
refuses, and the descriptions their reduction stages derive
(:class:`~.body_on_sphere.BodyOnSphereReduction`,
:class:`~.ball_on_support.SupportSurfaceReduction` for a homogeneous ball,
:class:`~.ball_on_support_general.GeneralBallReduction` for any other,
:class:`~.body_on_support.BodyOnSupportReduction` for a convex body).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import sympy as sp

from .ball_on_support import SupportSurfaceReduction
from .ball_on_support_general import AUX_NAMES, general_ball_description
from .body_on_sphere import BodyOnSphereReduction, PlaneMotion, outer_normal, turning_frame_energy
from .body_on_support import BODY_AUX_NAMES, aligned_sampler, body_on_support_description
from .description import MechanicalDescription, apply_effects
from .errors import UserInputError
from .expression_text import parse_expression
from .model import ParameterSpec
from .vectors import cross, dot, vector

if TYPE_CHECKING:
    from .rolling_system import RollingSystem

__all__: list[str] = []

#: The centre's state symbols of a ball named by its centre's surface (``x_1`` ...: the
#: emitters name subexpressions ``x0, x1, ...``) by the names a text uses for them.
CENTRE = {f"x{i}": sp.Symbol(f"x_{i}", real=True) for i in (1, 2, 3)}
#: The names a potential of a ball on a support surface may use: the contact point ``p1 ..
#: p3`` and the body axes' fixed-frame components ``e1_1 .. e3_3`` (the state's symbols).
SUPPORT_CONFIGURATION = {
    **{f"p{i}": sp.Symbol(f"p{i}", real=True) for i in (1, 2, 3)},
    **{f"e{i}_{j}": sp.Symbol(f"e{i}_{j}", real=True) for i in (1, 2, 3) for j in (1, 2, 3)},
}


def _convex_body_description(
    s: RollingSystem, effects: frozenset[str] = frozenset()
) -> MechanicalDescription:
    """A convex body on a plane or a fixed sphere: state ``omega`` and the contact point
    ``r``; on a rotating plane also the contact's position ``rho`` from the axis, on a
    moving plane the fixed axes ``alpha, beta``, on a sphere the vertical ``zeta`` when a
    field or the potential needs it. On a plane the trace's velocity (for the effect
    ``contact_point``): the plane's under the contact plus ``r'``."""
    p = s._parsed
    if s.support == "surface":  # on a support surface F(p) = 0: the fixed frame
        return _body_on_support_description(s)
    omega, r, zeta = vector("omega", real=True), vector("r", real=True), vector("zeta", real=True)
    m = p["mass"]
    names = tuple(x.name for x in p["parameters"])
    rubber, line = ("gamma" in p["no_spin_about"]), ("alpha" in p["no_spin_about"])
    plane = PlaneMotion(no_twist=True) if rubber else None  # on the fixed sphere
    if s.support != "sphere":
        velocity = p["plane_velocity"]
        plane = PlaneMotion(
            p["rotation_rate"], None if velocity.is_zero_matrix else velocity, no_twist=rubber,
            along_line=line,
        )  # fmt: skip
    vertical = s.support == "sphere" and (
        p["field"] != 0 or bool(p["potential"].free_symbols & set(zeta))
    )
    desc = MechanicalDescription(
        system=s.name,
        effects=frozenset(effects),
        time=sp.Symbol("t", real=True),
        omega=omega,
        reduction=BodyOnSphereReduction(
            p["surface"], m, _support_curvature(s), gyrostat=p["rotor_momentum"],
            gravity=p["field"], plane=plane,
            potential=_potential_of_gamma(p["potential"]), vertical=vertical,
        ),  # fmt: skip
        parameter_order=names,
        inertia=p["inertia"],
    )
    desc.add_state("omega", tuple(omega), None)
    desc.add_state("r", tuple(r), None)
    if s.support == "rotating_plane":  # horizontal: (rho, grad f) = 0 on the phase space
        rho = vector("rho", real=True)
        desc.add_state("rho", tuple(rho), None)
        grad = [sp.diff(p["surface"], x) for x in r]
        desc.add_invariant_relation("(rho,gamma)", sp.expand(dot(rho, sp.Matrix(grad))))
    if line and s.support == "rotating_plane":  # the turntable's line: its rates derived
        for name in ("alpha", "beta"):
            desc.add_state(name, tuple(vector(name, real=True)), None)
    elif s.support == "moving_plane" or line:
        desc.add_frame()  # the fixed axes the plane's velocity or the line is given along
    if s.support != "sphere":
        n = outer_normal(p["surface"], r)
        desc.trace_velocity = plane.velocity_at_contact(n) + vector("rdot", real=True)
        t = sp.Symbol("t", real=True)  # a constant velocity carries the trace, not the body
        constant = p["plane_velocity"].free_symbols - {t} - set(p["parameters"])
        desc.trace_parameters = tuple(
            ParameterSpec(x.name, (x,), "real", "plane velocity component")
            for x in sorted(constant, key=lambda x: x.name)
        )  # fmt: skip
        desc.parameter_order += tuple(x.name for x in desc.trace_parameters)
    if vertical:  # fixed in space (Poisson's equation)
        desc.add_state("zeta", tuple(zeta), None)
    desc.trace_on_normal = _trace_on_normal(s, p)  # on a sphere: +-R n(r) in alpha, beta, zeta
    # the contact point stays on the surface: its level is an integral
    r_free = p["surface"].xreplace(dict.fromkeys(r, 0))
    desc.add_integral("f", sp.expand(p["surface"] - r_free))  # the level: up to a constant
    _declare_parameters(desc, p)
    apply_effects(desc, effects, tuple(sorted(effects)))
    return desc


def _body_on_support_description(s: RollingSystem) -> MechanicalDescription:
    """A convex body on the support ``F(p) = 0`` (:mod:`.body_on_support`): state
    ``omega``, ``p``, ``r`` and the body axes ``e1, e2, e3``."""
    p = s._parsed
    desc = body_on_support_description(
        p["support_surface"], p["surface"], p["mass"], p["inertia"], p["rotor_momentum"],
        side=1 if s.side == "outside" else -1, gravity=p["field"], potential=p["potential"],
        rubber=_no_spin_about_normal(p), system=s.name,
    )  # fmt: skip
    desc.parameter_order = tuple(x.name for x in p["parameters"])
    _declare_parameters(desc, p)
    return desc


def _potential_of_gamma(potential: sp.Expr) -> tuple[sp.Expr, sp.Matrix] | None:
    """The description's potential of the orientation and its vector ``gamma`` (None: none)."""
    return None if potential.is_zero else (potential, vector("gamma", real=True))


def _support_surface_description(s: RollingSystem) -> MechanicalDescription:
    """A ball on the support ``F(p) = 0``: homogeneous, state ``omega`` (fixed frame) and
    the contact point ``p``; any other, also its body axes ``e1, e2, e3`` (fixed frame,
    :mod:`.ball_on_support_general`)."""
    p = s._parsed
    omega, contact = vector("omega", real=True), vector("p", real=True)
    b, m = p["radius"], p["mass"]
    side = 1 if s.side == "outside" else -1
    names = tuple(x.name for x in p["parameters"])
    if _attitude_needed(p):
        desc = general_ball_description(
            p["support_surface"], m, b, p["inertia"], p["centre"], p["rotor_momentum"],
            side=side, gravity=p["field"], potential=p["potential"],
            rubber=_no_spin_about_normal(p), system=s.name,
        )  # fmt: skip
        desc.parameter_order = names
        _declare_parameters(desc, p)
        return desc
    ratio = sp.simplify(p["inertia"][0, 0] / (m * b**2))
    if ratio.is_number:  # m drops out of the equations: the energy per unit mass
        m = sp.S.One
    desc = MechanicalDescription(
        system=s.name,
        effects=frozenset(),
        time=sp.Symbol("t", real=True),
        omega=omega,
        reduction=SupportSurfaceReduction(
            p["support_surface"], m, ratio * m, b, side=side, gravity=p["field"]
        ),
        parameter_order=names,
    )
    desc.add_state("omega", tuple(omega), None)
    desc.add_state("p", tuple(contact), None)
    _declare_parameters(desc, p)
    return desc


def _homogeneous(parsed: dict) -> bool:
    """Equal moments, the centre of mass at the centre, no rotor: the fixed-frame angular
    momentum does not depend on the attitude."""
    inertia = parsed["inertia"]
    return (
        inertia.is_diagonal()
        and inertia[0, 0] == inertia[1, 1] == inertia[2, 2]
        and parsed["centre"].is_zero_matrix
        and parsed["rotor_momentum"].is_zero_matrix
    )


def _attitude_needed(parsed: dict) -> bool:
    """A ball on a support surface the homogeneous route does not derive (not homogeneous, a
    potential, ``I(t)``, rubber contact): the general route, the body axes in the state."""
    t = sp.Symbol("t", real=True)
    return (
        not _homogeneous(parsed)
        or not parsed["potential"].is_zero
        or parsed["inertia"].has(t)
        or _no_spin_about_normal(parsed)
    )


def _no_spin_about_normal(parsed: dict) -> bool:
    """Whether the contact forbids spinning about the support's normal (``gamma``)."""
    return "gamma" in parsed.get("no_spin_about", ())


def _read_support_surface(s: RollingSystem, scope: dict, parsed: dict) -> sp.Expr | None:
    """``F(p)`` of a support surface; what it refuses (line contact; for a convex body a
    body and a support neither of which is a quadric)."""
    if s.support != "surface":
        if s.support_surface is not None:
            raise UserInputError(f"support_surface is given but the support is a {s.support}")
        return None
    if s.support_surface is None:
        raise UserInputError("support 'surface' needs support_surface (F(p1, p2, p3) = 0)")
    refused = {f"contact {s.contact!r}": s.contact == "line"}
    # (the homogeneous route's nu, Dnu, pdot too; a convex body's Dnb, Cf, Ac, rg)
    clash = sorted(set(scope) & (AUX_NAMES | BODY_AUX_NAMES))
    if clash:
        raise UserInputError(f"parameter names {clash} are the derivation's auxiliaries")
    if any(refused.values()):
        what = ", ".join(k for k, v in refused.items() if v)
        raise UserInputError(
            f"on a support surface this version derives a ball (any inertia, centre of mass, "
            f"rotor, gravity, potential) rolling or rubber rolling, not {what}"
        )
    x = {f"p{i}": sp.Symbol(f"p{i}", real=True) for i in (1, 2, 3)}
    F = read_fixed_surface(s.support_surface, scope, x, "support_surface")
    F = F.xreplace({x[f"p{i + 1}"]: c for i, c in enumerate(vector("p", real=True))})
    if s.surface is not None and aligned_sampler(F, parsed["surface"], 1) is None:
        raise UserInputError(  # (the verifier's exact points need one of them to be a quadric)
            "a convex body on a support surface needs the body or the support to be a quadric "
            "(degree 2) in this version"
        )
    return F


def read_fixed_surface(text: object, scope: dict, x: dict, what: str) -> sp.Expr:
    """A surface of the fixed frame, ``F`` in the names of ``x``: a polynomial of degree 1
    or more, and a quadric convex where its Hessian is numeric.

    Parameters
    ----------
    text : str or sympy.Expr
    scope : dict
        The description's names.
    x : dict of str to sympy.Symbol
        The coordinates' names in ``text`` and their symbols.
    what : str
        The field, for the messages.

    Returns
    -------
    sympy.Expr

    Raises
    ------
    UserInputError
        Not a polynomial in ``x``, a constant, or a quadric that is not convex.
    """
    F = parse_expression(text, {**scope, **x}, what)
    xs = list(x.values())
    if not F.is_polynomial(*xs) or sp.Poly(F, *xs).total_degree() < 1:
        raise UserInputError(f"{what}: F must be a polynomial in {', '.join(x)}")
    hessian = sp.hessian(F, xs)
    if sp.Poly(F, *xs).total_degree() == 2 and hessian.is_symbolic() is False:
        if not hessian.is_positive_semidefinite:
            raise UserInputError(f"{what}: the quadric {F} = 0 is not convex")
    return F


def _support_curvature(s: RollingSystem) -> sp.Expr:
    """M03's signed curvature ``k`` of the support (the contact point is ``c - n/k``, ``n``
    the normal into the body): 0 on a plane, ``-1/R`` outside a sphere (``n`` points away
    from its centre ``c``), ``1/R`` inside."""
    if s.support != "sphere":
        return sp.S.Zero
    R = s._parsed["support_radius"]
    return -1 / R if s.side == "outside" else 1 / R


def _read_surface(s: RollingSystem, scope: dict, centre: sp.Matrix) -> sp.Expr | None:
    """``f`` in the contact point ``r`` from the centre of mass: ``f(r + c)``."""
    if s.surface is None:
        return None
    planes = ("plane", "rotating_plane", "moving_plane")
    line = s.contact == "line" and s.support in planes
    if s.support not in (*planes, "sphere", "surface") or (s.contact == "line" and not line):
        raise UserInputError(
            "a convex body (surface) is derived rolling or rubber rolling on a plane (fixed, "
            "rotating or moving), a fixed sphere or a support surface, and along a line on a "
            f"plane, only in this version, not with support {s.support!r}, "
            f"contact {s.contact!r}"
        )
    x = {f"x{i}": sp.Symbol(f"x{i}", real=True) for i in (1, 2, 3)}
    f = parse_expression(s.surface, {**scope, **x}, "surface")
    if not f.is_polynomial(*x.values()) or sp.Poly(f, *x.values()).total_degree() < 2:
        raise UserInputError("surface: f must be a polynomial of degree 2 or more in x1, x2, x3")
    xs = list(x.values())
    hessian = sp.hessian(f, xs)
    if sp.Poly(f, *xs).total_degree() == 2 and hessian.is_symbolic() is False:
        if not hessian.is_positive_definite:  # a quadric: convex iff its Hessian is PD
            raise UserInputError(f"surface: the quadric {f} = 0 is not convex (Hessian {hessian})")
    inside = f.xreplace(dict(zip(xs, centre, strict=True)))
    if inside.is_number and inside >= 0:
        raise UserInputError(f"centre_of_mass: f = {inside} >= 0 there, not inside the body f < 0")
    r = vector("r", real=True)
    return f.xreplace({x[f"x{i + 1}"]: r[i] + centre[i] for i in range(3)})


def _declare_parameters(desc: MechanicalDescription, parsed: dict) -> None:
    """Declare each parameter of a parsed description, with its domain and role."""
    for x in parsed["parameters"]:
        domain = "positive" if x.is_positive else "real"
        desc.add_parameter(ParameterSpec(x.name, (x,), domain, _role(x, parsed)))


def _role(symbol: sp.Symbol, parsed: dict) -> str:
    for role, value in parsed["roles"].items():
        if value == symbol:
            return role
    if symbol in parsed["inertia"].free_symbols:
        return "inertia tensor entry"
    if symbol in parsed["centre"].free_symbols:
        return "centre of mass coordinate"
    if symbol in parsed["rotor_momentum"].free_symbols:
        return "gyrostatic momentum component"
    return "parameter of the description"


def _used_parameters(parameters: tuple[sp.Symbol, ...], p: dict) -> tuple[sp.Symbol, ...]:
    """The parameters a surface's description uses: a name only in the constant term of a
    surface is its level, which the state (``r``, ``x`` or ``p``) sets; a constant velocity
    of the plane changes nothing (Galilean: only ``V'`` enters); on a support surface the
    mass drops out when ``I = k m b^2`` with a number ``k`` (the energy is per unit mass)."""
    t = sp.Symbol("t", real=True)
    free = lambda *values: set().union(*(sp.sympify(v).free_symbols for v in values))  # noqa: E731
    used = None
    if p["surface"] is not None:
        used = free(p["inertia"], p["mass"], p["centre"], p["field"], p["support_radius"],
                    p["rotation_rate"], p["plane_velocity"].diff(t), p["rotor_momentum"],
                    p["potential"], *(sp.diff(p["surface"], c) for c in vector("r", real=True)))
    if p["centre_surface"] is not None:
        used = free(p["inertia"], p["mass"], p["radius"], p["field"], p["potential"],
                    *(sp.diff(p["centre_surface"], c) for c in CENTRE.values()))
    if p["support_surface"] is not None and p["surface"] is not None:  # a convex body
        used |= free(*(sp.diff(p["support_surface"], c) for c in vector("p", real=True)))
    elif p["support_surface"] is not None:
        ratio = sp.simplify(p["inertia"][0, 0] / (p["mass"] * p["radius"] ** 2))
        kept = (p["radius"],) if ratio.is_number else (p["inertia"], p["mass"], p["radius"])
        if _attitude_needed(p):  # the general ball's
            kept = (p["inertia"], p["mass"], p["radius"], p["centre"], p["rotor_momentum"])
        used = free(*kept, p["field"], p["potential"],
                    *(sp.diff(p["support_surface"], c) for c in vector("p", real=True)))
    if p.get("balls") is not None:  # the centre of mass is fixed: no mass, no radius
        used = free(p["inertia"], p["rotor_momentum"], *(x for b in p["balls"] for x in b[:2]))
    return parameters if used is None else tuple(x for x in parameters if x in used)


def _trace_on_normal(s: RollingSystem, parsed: dict) -> sp.Expr | None:
    """On a fixed sphere the contact point is ``+-R gamma`` from its centre (fixed frame)."""
    if s.support != "sphere":
        return None
    return parsed["support_radius"] * (1 if s.side == "outside" else -1)


def _normal_rate_factor(s: RollingSystem, parsed: dict) -> sp.Expr:
    """``s`` of ``gamma' = s gamma x omega``: 1 on a plane; on a sphere of radius ``R``
    the body's centre moves on the sphere of radius ``R +- b`` (outside/inside), and
    no slip turns the normal at ``R/(R +- b)`` of the body's rate."""
    if s.support != "sphere":
        return sp.S.One
    R, b = parsed["support_radius"], parsed["radius"]
    return R / (R + b) if s.side == "outside" else R / (R - b)


def _line_frame(desc: MechanicalDescription, Omega: sp.Expr) -> None:
    """The frame ``alpha, beta`` of the line a spherical body rolls along (``(omega, alpha)
    = 0``), with its completion: fixed in space (Poisson's ``X' = X x omega``) or carried by
    a plane turning at ``Omega`` about the vertical ``gamma`` (a horizontal vector turning
    in space at ``Omega N.z x X`` has, in body axes, ``X' = X x omega + Omega gamma x
    X``)."""
    gamma = desc.vectors["gamma"]
    for name in ("alpha", "beta"):
        if name not in desc.kinematics:  # (a moving plane's fixed axes: there already)
            X = vector(name, real=True)
            rate = cross(X, desc.omega) + Omega * cross(gamma, X)
            desc.add_kinematics(name, X, rate)
            desc.add_state(name, tuple(X), list(rate))
    desc.add_completion(("alpha", "beta"), "frame_bkm12_7")


def _jacobi_integral(s: RollingSystem, desc: MechanicalDescription) -> None:
    """On a plane turning at a constant rate (rolling, rubber or along the carried line: the
    no-twist reaction does no work in the turning frame on ``(omega, gamma) = Omega``, the
    line's on ``(omega, alpha) = 0``, relations of the state; nothing prescribed in time): the
    energy in the turning frame ``J = E - Omega (gamma, I omega + K + m (rho - r) x v)``
    with ``r = -a - b gamma`` and ``v = r x omega + Omega gamma x rho`` (the no-slip
    constraint is homogeneous in the turning frame's velocities), in ``omega`` (the model's
    ``omega(M)``), ``gamma`` and ``rho``."""
    p, t = s._parsed, desc.time
    Omega = p["rotation_rate"]
    timed = p["inertia"].has(t) or p["rotor_momentum"].has(t)
    if s.support != "rotating_plane" or Omega.has(t) or timed:
        return
    gamma = desc.vectors["gamma"]
    r = -p["centre"] - p["radius"] * gamma
    J = turning_frame_energy(p["inertia"], p["mass"], p["rotor_momentum"], desc.omega, r, gamma,
                             Omega, desc.potential)  # fmt: skip
    desc.add_integral("J", sp.expand(J))
