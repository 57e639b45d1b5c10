"""A convex body f(x) = 0 on a moving plane, with K(t), I(t), and on a fixed sphere under
a field or a potential, rolling or rubber (issue 24).

The reference of each check is the spherical body's route (the rigid-body stage in (M,
gamma), sharing no formula with the body-frame stage in (omega, r)): a sphere of radius
b written as the surface |x|^2 = b^2 must move as the spherical body on the same support,
exactly at a generic rational point; a control with another law of the support (or the
frozen law) is refuted by the same comparison. The integrals are decided by the verifier.
"""

from __future__ import annotations

import pytest
import sympy as sp
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.expression_dag import dag_xreplace
from chaplygin.derive.rolling_system import RollingSystem

R = sp.Rational
#: An offset body with a product of inertia, gravity and a rotor (generic rationals).
VALUES = dict(
    m=R(13, 10), I1=R(3, 7), I2=R(5, 9), I3=R(8, 11), c12=R(1, 17), a1=R(1, 9),
    a3=R(-2, 13), g=R(49, 5), K2=R(-3, 10), W=R(5, 3), w=R(7, 4), V1=R(4, 3), V2=R(-5, 6),
    e=R(2, 15), k=R(3, 19),
)  # fmt: skip
B = R(7, 10)  # the sphere's radius
T0 = R(7, 10)  # the time of the comparison
GAMMA = sp.Matrix([R(2, 7), R(3, 7), R(6, 7)])
ALPHA = sp.Matrix([R(3, 7), R(-6, 7), R(2, 7)])  # (alpha, beta, gamma) right-handed
BETA = GAMMA.cross(ALPHA)
RHO_SEED = sp.Matrix([R(5, 7), R(-3, 11), R(2, 13)])
OMEGA = sp.Matrix([R(3, 10), R(-7, 10), R(11, 10)])
CONTACT = -B * GAMMA - sp.Matrix([VALUES["a1"], 0, VALUES["a3"]])  # G -> contact point
ZETA = sp.Matrix([R(6, 11), R(-2, 11), R(9, 11)])  # the vertical on a sphere (not gamma)

COMMON = dict(
    inertia=[["I1", "c12", 0], ["c12", "I2", 0], [0, 0, "I3"]], centre_of_mass=("a1", 0, "a3"),
    gravity="g", gyrostat=(0, "K2", 0),
)  # fmt: skip
SPHERE = "x1**2 + x2**2 + x3**2 - b**2"


def _names(model) -> dict:
    return {s.name: s for s in (*model.state, *model.params, model.time)}


def _at(matrix: sp.Matrix, point: dict) -> sp.Matrix:
    """``matrix.xreplace(point)`` with each distinct subexpression replaced once (the rates
    repeat theirs: a tree walk took most of a comparison's time)."""
    memo: dict = {}
    return matrix.applyfunc(lambda e: dag_xreplace(e, point, memo))


def _carried(model) -> dict:
    """The carried groups at the comparison point (rho horizontal; the fixed frame; the
    vertical)."""
    groups = dict(model.state_groups)
    point = {}
    if "rho" in groups:
        rho = RHO_SEED - RHO_SEED.dot(GAMMA) * GAMMA
        point.update(zip(groups["rho"], rho, strict=True))
    if "alpha" in groups:
        point.update(zip(groups["alpha"], ALPHA, strict=True))
        point.update(zip(groups["beta"], BETA, strict=True))
    if "zeta" in groups:
        point.update(zip(groups["zeta"], ZETA, strict=True))
    return point


def _sphere_rates(model, omega: sp.Matrix) -> tuple[dict, sp.Matrix, sp.Matrix]:
    """The spherical body's rates at (omega, gamma, carried): its M from omega, then
    omega' = d omega/d state . state' + d omega/dt."""
    ns = _names(model)
    at = {ns[k]: v for k, v in VALUES.items() if k in ns}
    at.update({ns["b"]: B, ns["t"]: T0, **dict(zip(model.group("gamma"), GAMMA, strict=True))})
    at.update(_carried(model))
    w = sp.Matrix(sp.symbols("omega1:4", real=True))
    M = model.momentum_of_omega.xreplace(dict(zip(w, omega, strict=True))).xreplace(at)
    at.update(zip(model.group("M"), M, strict=True))
    omega_of_state = model.expand_aux(model.omega)
    assert (omega_of_state.xreplace(at) - omega).applyfunc(sp.simplify).is_zero_matrix
    rates = _at(model.rhs_expanded, at)
    jac = _at(omega_of_state.jacobian(sp.Matrix(model.state)), at)
    acceleration = jac * rates + omega_of_state.diff(ns["t"]).xreplace(at)
    return at, rates, acceleration


def _convex_rates(model, omega: sp.Matrix) -> sp.Matrix:
    ns = _names(model)
    at = {ns[k]: v for k, v in VALUES.items() if k in ns}
    at.update(zip(model.group("omega"), omega, strict=True))
    at.update(zip(model.group("r"), CONTACT, strict=True))
    at.update(_carried(model))
    if "t" in ns:
        at[ns["t"]] = T0
    return _at(model.rhs_expanded, at)


def _same_motion(sphere, convex, omega: sp.Matrix) -> bool:
    """omega' equal, r' = -b gamma', the carried groups' rates equal (exact)."""
    _, rates, acceleration = _sphere_rates(sphere, omega)
    theirs = _convex_rates(convex, omega)
    expected = list(acceleration) + list(-B * sp.Matrix(rates[3:6])) + list(rates[6:])
    assert len(expected) == len(theirs)
    return all(sp.simplify(a - b) == 0 for a, b in zip(theirs, expected, strict=True))


SUPPORTS = {
    "turntable": dict(support="rotating_plane", rotation_rate="W"),
    "accelerating_turntable": dict(support="rotating_plane", rotation_rate="W*cos(w*t)"),
    "shaken_plane": dict(support="moving_plane", plane_velocity=("V1*sin(w*t)", "V2*t")),
}
#: A fixed sphere under the body (outside unless a side is given).
ON_SPHERE = dict(support="sphere", support_radius="29/10")


@pytest.mark.slow
@pytest.mark.parametrize("contact", ["rolling", "rubber"])
@pytest.mark.parametrize("support", list(SUPPORTS))
def test_a_sphere_as_a_convex_surface_moves_as_the_spherical_body_on_a_moving_plane(
    support, contact
):
    """The body-frame stage in (omega, r) with the plane's velocity at the carried contact
    against the rigid-body stage in (M, gamma): omega', r' = -b gamma' and rho' (or
    alpha', beta') agree exactly at a generic point, at the time T0; a rubber body's
    omega satisfies (omega, gamma) = Omega there. Control: the convex body on the fixed
    plane (and on the turntable the other rate) is refuted by the same comparison."""
    fields = dict(COMMON, contact=contact, **SUPPORTS[support])
    sphere = RollingSystem("as_sphere", **fields).model()
    convex = RollingSystem("as_surface", surface=SPHERE, **fields).model()
    omega = OMEGA
    if contact == "rubber":  # (omega, gamma) = Omega(T0)
        t = sp.Symbol("t", real=True)
        Omega = sp.sympify(fields.get("rotation_rate", "0").replace("W", "5/3"))
        Omega = Omega.xreplace({sp.Symbol("w"): VALUES["w"], t: T0}).subs(sp.Symbol("t"), T0)
        omega = OMEGA + (Omega - OMEGA.dot(GAMMA)) * GAMMA
    assert _same_motion(sphere, convex, omega)
    fixed = dict(COMMON, contact=contact)
    control = RollingSystem("as_surface", surface=SPHERE, **fixed).model()
    _, rates, acceleration = _sphere_rates(sphere, omega)
    wrong = _convex_rates(control, omega)
    assert any(sp.simplify(wrong[i] - acceleration[i]) != 0 for i in range(3))


@pytest.mark.slow
@pytest.mark.parametrize(
    "fields",
    [
        dict(inertia=[["I1 + e*cos(w*t)", "c12", 0], ["c12", "I2", 0], [0, 0, "I3"]]),
        dict(gyrostat=("k*sin(w*t)", "K2", 0)),
    ],
    ids=["I(t)", "K(t)"],
)
@pytest.mark.parametrize("support", ["plane", "turntable", "sphere"])
def test_a_sphere_as_a_convex_surface_with_prescribed_inertia_or_rotor(fields, support):
    """I(t) (masses moving in symmetric pairs) and K(t) (driven rotors) on the fixed plane,
    on a turntable and outside a fixed sphere (gravity everywhere): the convex route agrees
    exactly with the spherical body's; the energy is not shipped (T depends on t).
    Control: the frozen law at T0 (the same momentum then, no I' or K') is refuted by the
    same comparison."""
    base = dict(COMMON, **fields)
    base.update(SUPPORTS.get(support, {}))
    if support == "sphere":
        base.update(ON_SPHERE)
    sphere = RollingSystem("as_sphere", **base).model()
    convex = RollingSystem("as_surface", surface=SPHERE, **base).model()
    assert not {"H", "J"} & {n for n, _ in convex.integrals}
    assert _same_motion(sphere, convex, OMEGA)
    frozen = {
        k: [[str(x).replace("t", f"({T0})") if "t" in str(x) else x for x in row] for row in v]
        if k == "inertia"
        else tuple(str(x).replace("t", f"({T0})") if "t" in str(x) else x for x in v)
        for k, v in fields.items()
    }
    control = RollingSystem("as_surface", surface=SPHERE, **dict(base, **frozen)).model()
    _, rates, acceleration = _sphere_rates(sphere, OMEGA)
    wrong = _convex_rates(control, OMEGA)
    assert any(sp.simplify(wrong[i] - acceleration[i]) != 0 for i in range(3))


@pytest.mark.parametrize(
    "fields, message",
    [
        (dict(contact="line", support="sphere", support_radius="R"), "contact 'line'"),
    ],  # (along a line on any plane: derived)
)
def test_what_a_convex_body_is_not_derived_on_is_refused_in_one_line(fields, message):
    with pytest.raises(UserInputError, match=message) as info:
        RollingSystem("refused", inertia=("I1", "I2", "I3"), surface=SPHERE, **fields)
    assert "\n" not in str(info.value)


ELLIPSOID = "x1**2/(9/10)**2 + x2**2/(7/10)**2 + x3**2/(1/2)**2 - 1"
HEAVY = dict(
    inertia=("31/100", "43/100", "57/100"), mass="13/10", surface=ELLIPSOID, gravity="49/5",
    centre_of_mass=("1/13", 0, "1/10"), gyrostat=(0, "3/10", 0), support="rotating_plane",
)  # fmt: skip


def _energy_and_axial_momentum(
    model, Omega: sp.Expr, sphere: tuple[sp.Expr, int] | None = None
) -> tuple[sp.Expr, sp.Expr, sp.Matrix]:
    """Written here from first principles: the energy E and the angular momentum about
    the vertical axis (n, I omega + K + m (rho - r) x v), with v = r x omega + Omega n x
    rho (no slip on the turntable; rho = 0 on the fixed plane), n = -grad f/|grad f| (also
    returned) and the centre of mass at the height -(r, n) (f the ellipsoid of HEAVY, its
    centre at -c from the centre of mass). On a fixed sphere of radius R, ``sphere = (R,
    +1)`` outside and ``(R, -1)`` inside, the contact point is at +-R n from the sphere's
    centre, the centre of mass at +-R n - r, its height that along the vertical zeta."""
    omega = sp.Matrix(model.group("omega"))
    r = sp.Matrix(model.group("r"))
    rho = model.group("rho") if "rho" in dict(model.state_groups) else sp.zeros(3, 1)
    x = r + sp.Matrix([R(1, 13), 0, R(1, 10)])
    grad = sp.Matrix([2 * x[0] / R(81, 100), 2 * x[1] / R(49, 100), 2 * x[2] / R(1, 4)])
    # the radicand in the model's canonical form (the verifier splits square roots off by
    # their radicands: sqrt(4 S) and 2 sqrt(S) would be two independent generators)
    n = -grad / sp.sqrt(sp.factor_terms(sp.expand(grad.dot(grad))))
    m, g, K = R(13, 10), R(49, 5), sp.Matrix([0, R(3, 10), 0])
    inertia = sp.diag(R(31, 100), R(43, 100), R(57, 100))
    v = r.cross(omega) + Omega * n.cross(rho)
    height = -r.dot(n)
    if sphere is not None:
        height = (sphere[1] * sphere[0] * n - r).dot(sp.Matrix(model.group("zeta")))
    energy = (omega.T * inertia * omega)[0] / 2 + m * v.dot(v) / 2 + m * g * height
    return energy, n.dot(inertia * omega + K + m * (rho - r).cross(v)), n


@pytest.mark.slow
def test_the_energy_in_the_turntable_s_frame_is_an_integral_at_a_constant_rate_only():
    """A heavy ellipsoid with an offset centre and a rotor rolling on a turntable turning
    at a constant rate: the energy is not an integral (the plane does work) but the energy
    in the turning frame J (the Jacobi integral: the no-slip constraint is homogeneous in
    the turning frame's velocities) is, proved by the verifier; the model ships it (the
    same function). Controls refuted by the same machinery: the energy alone, and J on a
    turntable whose rate changes (Omega = W cos t)."""
    from chaplygin.verify.identity import Domain, decide, lie_derivative

    model = RollingSystem("turntable_egg", rotation_rate="5/3", **HEAVY).model()
    assert [n for n, _ in model.integrals] == ["J", "(rho,gamma)", "f"]
    energy, axial, _ = _energy_and_axial_momentum(model, R(5, 3))
    J = energy - R(5, 3) * axial
    proof = decide([lie_derivative(J, model)], Domain(model))
    assert proof.verdict == "proved", proof
    assert decide([model.integral("J") - J], Domain(model)).verdict == "proved"
    assert decide([lie_derivative(energy, model)], Domain(model)).verdict == "refuted"
    t = sp.Symbol("t", real=True)
    turning = RollingSystem("turntable_egg", rotation_rate="5/3*cos(t)", **HEAVY).model()
    assert "J" not in dict(turning.integrals)
    energy, axial, _ = _energy_and_axial_momentum(turning, R(5, 3) * sp.cos(t))
    J_t = energy - R(5, 3) * sp.cos(t) * axial
    assert decide([lie_derivative(J_t, turning)], Domain(turning)).verdict == "refuted"


@pytest.mark.slow
@pytest.mark.parametrize("contact", ["rolling", "rubber"])
def test_the_spherical_body_on_a_turntable_keeps_the_same_energy_in_the_turning_frame(contact):
    """The spherical route ships J too, rolling and rubber (on the rubber body's invariant
    relation (omega, gamma) = Omega: the no-twist reaction does no work in the turning
    frame): written here from first principles with r = -a - b gamma, v = r x omega + Omega
    gamma x rho and omega(M) the model's own, the verifier proves it an integral of the (M,
    gamma, rho) model and equal to the shipped one; the energy alone is refuted by the same
    machinery."""
    from chaplygin.verify.identity import Domain, decide, lie_derivative

    fields = {k: v for k, v in HEAVY.items() if k not in ("surface", "contact")}
    model = RollingSystem(
        f"turntable_ball_{contact}", radius="7/10", rotation_rate="5/3", contact=contact, **fields
    ).model()
    assert "J" in dict(model.integrals)
    omega = model.expand_aux(model.omega)
    gamma, rho = sp.Matrix(model.group("gamma")), sp.Matrix(model.group("rho"))
    a, m, Omega = sp.Matrix([R(1, 13), 0, R(1, 10)]), R(13, 10), R(5, 3)
    inertia, K = sp.diag(R(31, 100), R(43, 100), R(57, 100)), sp.Matrix([0, R(3, 10), 0])
    r = -a - R(7, 10) * gamma
    v = r.cross(omega) + Omega * gamma.cross(rho)
    energy = (omega.T * inertia * omega)[0] / 2 + m * v.dot(v) / 2 + m * R(49, 5) * a.dot(gamma)
    J = energy - Omega * gamma.dot(inertia * omega + K + m * (rho - r).cross(v))
    assert decide([lie_derivative(J, model)], Domain(model)).verdict == "proved"
    shipped = model.expand_aux(model.integral("J"))
    assert decide([shipped - J], Domain(model)).verdict == "proved"
    assert decide([lie_derivative(energy, model)], Domain(model)).verdict == "refuted"


#: A potential of the orientation (generic rationals): a magnet's -(mu, B)-like term and a
#: quadratic one, through the parameters k and e of VALUES.
POTENTIAL = "k*gamma1*gamma2 + e*gamma3**2 - (2/7)*gamma1"


@pytest.mark.slow
@pytest.mark.parametrize("contact", ["rolling", "rubber"])
@pytest.mark.parametrize("support", ["plane", "turntable"])
def test_a_sphere_as_a_convex_surface_moves_as_the_spherical_body_under_a_potential(
    support, contact
):
    """A potential V(gamma) on a convex body (the torque n x dV/dn, V(n) in the energy):
    the sphere written as a surface moves exactly as the spherical body (whose potential
    is the rigid-body stage's Poisson-vector torque: no shared formula) on the fixed plane
    and on a turntable, rolling and rubber. Control: the convex body without the potential is
    refuted by the same comparison."""
    fields = dict(COMMON, contact=contact, potential=POTENTIAL, **SUPPORTS.get(support, {}))
    sphere = RollingSystem("as_sphere", **fields).model()
    convex = RollingSystem("as_surface", surface=SPHERE, **fields).model()
    omega = OMEGA
    if contact == "rubber":  # (omega, gamma) = Omega
        Omega = VALUES["W"] if support == "turntable" else 0
        omega = OMEGA + (Omega - OMEGA.dot(GAMMA)) * GAMMA
    assert _same_motion(sphere, convex, omega)
    bare = {k: v for k, v in fields.items() if k != "potential"}
    control = RollingSystem("as_surface", surface=SPHERE, **bare).model()
    _, _, acceleration = _sphere_rates(sphere, omega)
    wrong = _convex_rates(control, omega)
    assert any(sp.simplify(wrong[i] - acceleration[i]) != 0 for i in range(3))


@pytest.mark.slow
def test_the_energy_with_a_potential_is_an_integral_of_a_convex_body():
    """A heavy ellipsoid with an offset centre and a rotor under V(gamma) on the fixed
    plane: the shipped H (the potential included) is proved an integral by the verifier
    and equals E + V written here (E from first principles, V the description's with
    gamma = n(r)); E alone is refuted by the same machinery."""
    from chaplygin.verify.identity import Domain, decide, lie_derivative

    fields = {k: v for k, v in HEAVY.items() if k != "support"}
    model = RollingSystem("egg_in_a_field", potential="(3/7)*gamma1*gamma2 - (2/7)*gamma3**2",
                          **fields).model()  # fmt: skip
    H = model.integral("H")
    assert decide([lie_derivative(H, model)], Domain(model)).verdict == "proved"
    energy, _, n = _energy_and_axial_momentum(model, 0)
    V = R(3, 7) * n[0] * n[1] - R(2, 7) * n[2] ** 2
    assert decide([H - energy - V], Domain(model)).verdict == "proved"
    assert decide([lie_derivative(energy, model)], Domain(model)).verdict == "refuted"


#: A potential of a fixed sphere's normal gamma and of the vertical.
SPHERE_POTENTIAL = "k*gamma1*zeta2 + e*gamma3**2 - (2/7)*zeta1*gamma2"


@pytest.mark.parametrize(
    "side, contact",
    [
        ("outside", "rolling"),
        pytest.param("outside", "rubber", marks=pytest.mark.slow),
        pytest.param("inside", "rolling", marks=pytest.mark.slow),
        pytest.param("inside", "rubber", marks=pytest.mark.slow),
    ],
)
def test_a_sphere_as_a_convex_surface_on_a_fixed_sphere_under_gravity_and_a_potential(
    side, contact
):
    """The body-frame stage on a sphere (curvature -+1/R) with the vertical zeta carried
    (zeta' = zeta x omega), the weight -m g zeta at the centre of mass and a potential of
    the normal and the vertical, against the spherical body's route (gamma turning at
    R/(R +- b) of Poisson's rate, the centre's height c (gamma, zeta) + (a, zeta), the
    potential's Poisson-vector torque): omega', r' = -b gamma' and zeta' agree exactly at a
    generic point with an offset centre, a product of inertia and a rotor, rolling and
    rubber ((omega, gamma) = 0 there). Controls: the convex body without the field, and
    without the potential, are refuted by the same comparison."""
    fields = dict(COMMON, contact=contact, side=side, potential=SPHERE_POTENTIAL, **ON_SPHERE)
    sphere = RollingSystem("as_sphere", **fields).model()
    convex = RollingSystem("as_surface", surface=SPHERE, **fields).model()
    twist = ["(omega,gamma)"] if contact == "rubber" else []
    assert [n for n, _ in convex.integrals] == ["H", *twist, "(zeta,zeta)", "f"]
    omega = OMEGA if contact == "rolling" else OMEGA - OMEGA.dot(GAMMA) * GAMMA
    assert _same_motion(sphere, convex, omega)
    _, _, acceleration = _sphere_rates(sphere, omega)
    for load in ("gravity", "potential"):
        bare = {k: v for k, v in fields.items() if k != load}
        wrong = _convex_rates(RollingSystem("as_surface", surface=SPHERE, **bare).model(), omega)
        assert any(sp.simplify(wrong[i] - acceleration[i]) != 0 for i in range(3))


@pytest.mark.slow
def test_a_potential_of_the_normal_on_a_sphere_turns_the_body_as_the_spherical_body_s():
    """A potential of gamma alone on a sphere (no field: the vertical is not in the state):
    the sphere as a surface moves exactly as the spherical body. Along the motion the
    normal turns at n x omega - k r', not Poisson's rate, and the torque follows it: the
    potential's torque, I_Q times the change of omega' it makes, is R/(R + b) gamma x dV/dgamma
    (the rate at which the spherical body's gamma turns), written here; the plane's law
    gamma x dV/dgamma is refuted."""
    fields = dict(COMMON, potential="k*gamma1*gamma2 + e*gamma3**2 - (2/7)*gamma1", **ON_SPHERE)
    fields.pop("gravity")
    sphere = RollingSystem("as_sphere", **fields).model()
    convex = RollingSystem("as_surface", surface=SPHERE, **fields).model()
    assert [n for n, _ in convex.state_groups] == ["omega", "r"]
    assert _same_motion(sphere, convex, OMEGA)
    bare = {k: v for k, v in fields.items() if k != "potential"}
    without = RollingSystem("as_surface", surface=SPHERE, **bare).model()
    change = (_convex_rates(convex, OMEGA) - _convex_rates(without, OMEGA))[:3, :]
    ns = _names(convex)
    at = {ns[k]: v for k, v in VALUES.items() if k in ns}
    at.update(zip(convex.group("r"), CONTACT, strict=True))
    torque = convex.details.equations.inertia_operator.xreplace(at) * change
    k, e = VALUES["k"], VALUES["e"]
    dV = sp.Matrix([k * GAMMA[1] - R(2, 7), k * GAMMA[0], 2 * e * GAMMA[2]])
    expected = R(29, 10) / (R(29, 10) + B) * GAMMA.cross(dV)
    assert (torque - expected).applyfunc(sp.simplify).is_zero_matrix
    assert not (torque - GAMMA.cross(dV)).applyfunc(sp.simplify).is_zero_matrix


@pytest.mark.slow
@pytest.mark.parametrize("side, sign", [("outside", 1), ("inside", -1)])
def test_the_energy_of_a_heavy_ellipsoid_on_a_sphere_is_an_integral(side, sign):
    """A heavy ellipsoid off centre with a rotor on a fixed sphere of radius 29/10: the
    shipped H is proved an integral by the verifier and equal to the energy written from
    first principles (the centre of mass's height above the sphere's centre); the energy
    with the height above the tangent plane at the contact, -(r, n), is refuted by the same
    machinery."""
    from chaplygin.verify.identity import Domain, decide, lie_derivative

    fields = {k: v for k, v in HEAVY.items() if k != "support"}
    model = RollingSystem("egg_on_a_ball", side=side, **ON_SPHERE, **fields).model()
    H = model.integral("H")
    assert decide([lie_derivative(H, model)], Domain(model)).verdict == "proved"
    energy, _, _ = _energy_and_axial_momentum(model, 0, (R(29, 10), sign))
    assert decide([H - energy], Domain(model)).verdict == "proved"
    tangent, _, _ = _energy_and_axial_momentum(model, 0)
    assert decide([lie_derivative(tangent, model)], Domain(model)).verdict == "refuted"


def test_the_body_frame_stage_refuses_a_moving_sphere_and_a_field_without_the_vertical():
    """derive_body_on_sphere's documented ValueError: a moving support or a field without
    the vertical on a sphere, a vertical on a plane (where the normal is the vertical)."""
    from chaplygin.derive.body_on_sphere import PlaneMotion, derive_body_on_sphere
    from chaplygin.derive.vectors import vector

    omega, r, zeta = (vector(n, real=True) for n in ("omega", "r", "zeta"))
    surface = r.dot(r) - 1
    m, g, W = sp.symbols("m g W", positive=True)
    for k, extra in (
        (-R(1, 3), dict(plane=PlaneMotion(W))),
        (-R(1, 3), dict(gravity=g)),
        (sp.S.Zero, dict(vertical=zeta)),
    ):
        with pytest.raises(ValueError):
            derive_body_on_sphere(surface, sp.eye(3), m, k, omega, r, **extra)


@pytest.mark.slow
def test_the_energy_with_a_potential_of_gamma_and_zeta_is_an_integral_on_a_sphere():
    """The heavy ellipsoid off centre with a rotor outside a fixed sphere under V(gamma,
    zeta), gamma = n(r): the shipped H is proved an integral (the Groebner proof through the
    sphere's square root: about 7 s since the builder works in FLINT, a minute before)
    and equal to the first-principles energy plus V;
    the energy without V is refuted by the same machinery."""
    from chaplygin.verify.identity import Domain, decide, lie_derivative

    fields = {k: v for k, v in HEAVY.items() if k != "support"}
    model = RollingSystem("egg_on_a_ball", potential="(3/7)*gamma1*zeta2 - (2/7)*gamma3**2",
                          **ON_SPHERE, **fields).model()  # fmt: skip
    H = model.integral("H")
    assert decide([lie_derivative(H, model)], Domain(model)).verdict == "proved"
    energy, _, n = _energy_and_axial_momentum(model, 0, (R(29, 10), 1))
    zeta = model.group("zeta")
    V = R(3, 7) * n[0] * zeta[1] - R(2, 7) * n[2] ** 2
    assert decide([H - energy - V], Domain(model)).verdict == "proved"
    assert decide([lie_derivative(energy, model)], Domain(model)).verdict == "refuted"


# ------------------------------------------------------------------ the contact trace
# The trace of a convex body on a plane (the contact_point effect): the spherical body's route
# (BKM12-6: the trace moves with the sphere's centre) against the body-frame stage (the trace
# moves with the contact point's own velocity, the plane's under it plus r'): no shared formula.
TRACE = ("contact_point",)
PLANES = {
    "fixed_plane": dict(support="plane"),
    "turntable": dict(support="rotating_plane", rotation_rate="W"),
    "shaken_plane": dict(support="moving_plane", plane_velocity=("V1*sin(w*t)", "V2*t")),
}


@pytest.mark.slow
@pytest.mark.parametrize("plane", list(PLANES))
def test_the_trace_of_a_sphere_as_a_convex_surface_is_the_spherical_body_s(plane):
    """Every rate equal, x' and y' included, on each plane; the control (the sphere on the
    turntable against the convex body on the fixed plane, or the other way round) gives
    another x' or y'."""
    fields = dict(COMMON, **PLANES[plane])
    sphere = RollingSystem("as_sphere", **fields).model(TRACE)
    convex = RollingSystem("as_surface", surface=SPHERE, **fields).model(TRACE)
    assert convex.state_names[-2:] == ("x", "y")
    assert _same_motion(sphere, convex, OMEGA)
    other = "fixed_plane" if plane != "fixed_plane" else "turntable"
    control = RollingSystem("as_surface", surface=SPHERE, **COMMON, **PLANES[other])
    wrong = _convex_rates(control.model(TRACE), OMEGA)
    _, rates, _ = _sphere_rates(sphere, OMEGA)
    assert any(sp.simplify(wrong[i] - rates[i]) != 0 for i in (-2, -1))


def test_the_trace_of_a_constant_plane_velocity_is_a_parameter_of_the_trace_only():
    """A constant velocity of the plane does not move the body (it is not a parameter of the
    motion) but carries the trace: a parameter with the effect, and x' gains V1."""
    fields = dict(surface=SPHERE, inertia=("A", "A", "C"), support="moving_plane",
                  plane_velocity=("V1", "V2"))  # fmt: skip
    system = RollingSystem("shaken_egg", **fields)
    assert "V1" not in system.model().param_names
    model = system.model(TRACE)
    assert model.param_names[-2:] == ("V1", "V2")
    x_rate = model.rhs_expanded[model.state_names.index("x")]
    V1 = next(p for p in model.params if p.name == "V1")
    assert sp.diff(x_rate, V1) != 0


def test_a_convex_body_on_a_support_surface_takes_no_trace_and_says_so():
    """On a support surface the contact point p is the state itself: the effect is refused
    in one line (on a fixed sphere it is derived: tests/derive/test_convex_sphere_trace.py)."""
    s = RollingSystem("egg_on_bowl", surface=SPHERE, inertia=("A", "A", "C"),
                      support="surface", support_surface="p1**2 + p2**2 + p3**2 - 9")  # fmt: skip
    assert s.effects_taken == ()
    with pytest.raises(UserInputError, match="unknown effect 'contact_point'") as err:
        s.model(TRACE)
    assert "\n" not in str(err.value)


@pytest.mark.slow
def test_the_trace_on_a_turntable_is_the_projection_of_rho_an_integral():
    """A heavy ellipsoid (offset centre, rotor) on a turntable: x - (rho, alpha) and y -
    (rho, beta) are integrals (the trace is where the carried rho points on the fixed
    axes), proved by the verifier; x alone is refuted by the same machinery."""
    from chaplygin.verify.identity import Domain, decide, lie_derivative

    model = RollingSystem("turntable_egg", rotation_rate="5/3", **HEAVY).model(TRACE)
    names = [n for n, _ in model.integrals]
    assert {"x-(rho,alpha)", "y-(rho,beta)", "J", "(alpha,gamma)"} <= set(names)
    domain = Domain(model)
    for name in ("x-(rho,alpha)", "y-(rho,beta)"):
        assert decide([lie_derivative(model.integral(name), model)], domain).verdict == "proved"
    x = next(s for s in model.state if s.name == "x")
    assert decide([lie_derivative(x, model)], domain).verdict == "refuted"
