"""A general ball on a support surface with a potential, a prescribed rotor K(t) or a
time-dependent inertia I(t) (derive/ball_on_support_general.py), against routes that share
no formula with it: gravity written as a potential against the built-in field, and on the
plane F = p3 the engine's body-frame ball on a plane with the same potential (of gamma =
the axes' third components), K(t) and I(t)."""

from __future__ import annotations

import random

import pytest
import sympy as sp
from chaplygin.derive.phase_space import sample_point
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.chained import rate_at
from test_support_general import E3, INERTIA, OFFSET, OMEGA, R_, ROTOR, B, G, M, Q

T0 = R_(7, 5)  # the time of the comparisons
ELLIPSOID = "p1**2/4 + 4*p2**2/9 + p3**2 - 1"
#: The centre of mass's height on that ellipsoid: p3 + b n3 + (Q a)_3, n = grad F/|grad F|.
HEIGHT = "p3 + b*p3/sqrt(p1**2/16 + 16*p2**2/81 + p3**2) + a1*e1_3 + a2*e2_3 + a3*e3_3"


def _ball(name: str, **fields) -> RollingSystem:
    fields = {"inertia": INERTIA.tolist(), "mass": M, "radius": B,
              "centre_of_mass": list(OFFSET), **fields}  # fmt: skip
    return RollingSystem(name, **fields)


def _point(model, p: sp.Matrix, omega: sp.Matrix = OMEGA) -> dict:
    names = {x.name: x for x in (*model.state, model.time)}
    point = {names[f"omega{i + 1}"]: omega[i] for i in range(3)}
    point.update({names[f"p{i + 1}"]: p[i] for i in range(3)})
    point.update({names[f"e{j + 1}_{i + 1}"]: Q[i, j] for i in range(3) for j in range(3)})
    point[model.time] = T0
    return point


def _surface_rates(model, p: sp.Matrix, omega: sp.Matrix = OMEGA) -> tuple[sp.Matrix, sp.Matrix]:
    """``omega'`` and ``p'`` at ``(omega, p, Q)``, time ``T0``, the auxiliaries in order."""
    point = _point(model, p, omega)
    for symbol, expr in model.aux:
        point[symbol] = sp.radsimp(expr.xreplace(point))
    rates = sp.Matrix(model.rhs).xreplace(point).applyfunc(sp.radsimp)
    return sp.Matrix(rates[:3]), sp.Matrix(rates[3:6])


def _plane_acceleration(model, omega: sp.Matrix = OMEGA, vectors: dict | None = None) -> sp.Matrix:
    """``Q omega_b'`` of a body-frame route at ``omega_b = Q^T omega``, gamma = Q^T e3 (or
    the body-frame ``vectors`` given), time ``T0`` (``omega = omega(M, gamma, t)``: its
    explicit time derivative too)."""
    names = {x.name: x for x in model.state}
    vectors = {"gamma": Q.T * E3} if vectors is None else vectors
    point = {names[f"{n}{i + 1}"]: v[i] for n, v in vectors.items() for i in range(3)}
    point[model.time] = T0
    momentum = sp.Matrix(model.group("M"))
    omega_of_m = model.expand_aux(model.omega)
    solved = sp.solve(list(omega_of_m.xreplace(point) - Q.T * omega), list(momentum), dict=True)
    point.update(solved[0])
    rates = model.rhs_expanded.xreplace(point)
    state = sp.Matrix(model.state)
    acceleration = omega_of_m.jacobian(state).xreplace(point) * rates
    acceleration += omega_of_m.diff(model.time).xreplace(point)
    return Q * acceleration


@pytest.mark.parametrize("factor, agrees", [(1, True), (2, False)])
def test_gravity_written_as_a_potential_moves_as_the_field(factor, agrees):
    """On an ellipsoid, V = m g (height of the centre of mass) with no field against the
    field g itself: omega' and p' equal at an exact point (the generalised force -d(dV/dt)/d
    omega through the contact's rate and the axes, against the weight's moment about the
    contact); twice the potential is the control."""
    values = {**{f"a{i + 1}": OFFSET[i] for i in range(3)}, "b": B}
    height = HEIGHT
    for k, v in values.items():
        height = height.replace(k, f"({v})")
    field = _ball("field", gravity=G, support="surface", support_surface=ELLIPSOID).model()
    potential = _ball(
        "potential", support="surface", support_surface=ELLIPSOID,
        potential=f"{factor}*({M})*({G})*({height})",
    ).model()  # fmt: skip
    u = sp.Matrix([R_(2, 7), R_(3, 7), R_(6, 7)])
    p = sp.Matrix([4 * u[0], R_(9, 4) * u[1], u[2]])  # on F = 0, |grad F| rational
    omega_a, p_a = _surface_rates(field, p)
    omega_b, p_b = _surface_rates(potential, p)
    assert p_a == p_b
    assert ((omega_a - omega_b).applyfunc(sp.simplify) == sp.zeros(3, 1)) is agrees


@pytest.mark.parametrize("sign, agrees", [(1, True), (-1, False)])
def test_a_potential_of_the_attitude_on_p3_moves_as_on_the_plane(sign, agrees):
    """V = k (e1_3^2 - e2_3 e3_3) + c e3_3 on F = p3 against the plane route's potential of
    gamma (gamma_i = e_i . e3 = e{i}_3), for an unbalanced ball with a product of inertia and
    a rotor under gravity; the plane route's potential with the other sign is the control."""
    V = "k*(X1**2 - X2*X3) + c*X3"
    k, c = R_(3, 7), R_(-5, 11)
    on_surface = V.replace("X1", "e1_3").replace("X2", "e2_3").replace("X3", "e3_3")
    on_plane = V.replace("X", "gamma")
    common = {"gyrostat": list(ROTOR), "gravity": G, "positive": ()}
    surface = _ball("attitude_surface", support="surface", support_surface="p3",
                    potential=f"{sign}*({on_surface})", **common).model()  # fmt: skip
    plane = _ball("attitude_plane", potential=on_plane, **common).model()
    values = {"k": k, "c": c}
    omega_rate, _ = _surface_rates(surface, sp.Matrix([R_(1, 3), R_(2, 3), 0]))
    acceleration = _plane_acceleration(plane)
    subs = {s: values[s.name] for s in (*surface.params, *plane.params) if s.name in values}
    difference = (acceleration - omega_rate).xreplace(subs).applyfunc(sp.simplify)
    assert (difference == sp.zeros(3, 1)) is agrees


@pytest.mark.parametrize("frozen, agrees", [(False, True), (True, False)])
def test_a_prescribed_rotor_and_inertia_on_p3_move_as_on_the_plane(frozen, agrees):
    """K(t) and I(t) (a moment and a product changing with t) on F = p3 against the plane
    route's prescribed gyrostat and time-dependent inertia at t = T0; the control freezes the
    plane route's I and K at their values at T0 (their rates missing)."""
    t = sp.Symbol("t", real=True)
    inertia = INERTIA + sp.Matrix([[0, t / 30, 0], [t / 30, 0, 0], [0, 0, t**2 / 25]])
    rotor = sp.Matrix([ROTOR[0] * t, R_(2, 9) * t**2, ROTOR[2]])
    plane_inertia, plane_rotor = (
        (inertia.subs(t, T0), rotor.subs(t, T0)) if frozen else (inertia, rotor)
    )
    surface = _ball("timed_surface", inertia=inertia.tolist(), gyrostat=list(rotor), gravity=G,
                    support="surface", support_surface="p3").model()  # fmt: skip
    plane = _ball("timed_plane", inertia=plane_inertia.tolist(), gyrostat=list(plane_rotor),
                  gravity=G).model()  # fmt: skip
    assert [n for n, _ in surface.integrals] == ["F"]  # no energy: the motors do work
    omega_rate, _ = _surface_rates(surface, sp.Matrix([R_(1, 3), R_(2, 3), 0]))
    acceleration = _plane_acceleration(plane)
    assert ((acceleration - omega_rate).applyfunc(sp.simplify) == sp.zeros(3, 1)) is agrees


@pytest.mark.parametrize("contact", ["rolling", "rubber"])
@pytest.mark.parametrize("sign, conserved", [(1, True), (-1, False)])
def test_the_energy_with_a_potential_is_an_integral(contact, sign, conserved):
    """On an ellipsoid with symbolic axes, a heavy unbalanced ball under a potential of the
    contact point and the attitude, rolling or rubber rolling (the sampled points on its
    invariant relation (omega, grad F) = 0): H (shipped) has exactly zero rate at sampled
    points of the phase space, through the auxiliaries; H with the potential's sign flipped
    does not."""
    system = RollingSystem(
        f"potential_egg_{contact}", inertia=[["A", "D", 0], ["D", "B", 0], [0, 0, "C"]],
        centre_of_mass=(0, 0, "a"), gravity="g", support="surface",
        support_surface="p1**2/c1 + p2**2/c2 + p3**2/c3 - 1",
        potential="k*(p1**2 + e1_3*p2) + q*e2_1*e3_3", contact=contact,
    )  # fmt: skip
    model = system.model()
    names = {x.name: x for x in (*model.state, *model.params)}
    V = names["k"] * (names["p1"] ** 2 + names["e1_3"] * names["p2"])
    V += names["q"] * names["e2_1"] * names["e3_3"]
    energy = model.integral("H") + (sign - 1) * V
    rng = random.Random(5)
    for _ in range(2):
        point = sample_point(model, rng, model.state)
        for _, relation in model.invariant_relations:
            assert relation.xreplace(point) == 0
        assert (rate_at(model, energy, point) == 0) is conserved
        for _, relation in model.invariant_relations:  # kept by the flow
            assert rate_at(model, relation, point) == 0


#: Angular velocities with no spin about the normal: of the plane (e3) and of the sphere's
#: normal n = (2, 3, 6)/7.
NO_SPIN = {"plane": sp.Matrix([R_(3, 10), R_(-7, 10), 0]),
           "sphere": sp.Matrix([R_(3, 10), R_(-1, 5), 0])}  # fmt: skip


@pytest.mark.parametrize("contact, agrees", [("rubber", True), ("rolling", False)])
def test_rubber_rolling_on_p3_moves_as_the_rubber_ball_on_the_plane(contact, agrees):
    """Rubber rolling ((omega, n) = 0, the reaction mu n) on F = p3 against the plane
    route's rubber ball (the no-twist constraint (omega, gamma) = 0 in the body frame), for an
    unbalanced ball with a product of inertia and a rotor under gravity, at an angular
    velocity without spin; the plane route rolling (twist allowed) is the control."""
    omega = NO_SPIN["plane"]
    common = {"gyrostat": list(ROTOR), "gravity": G}
    surface = _ball("rubber_surface", support="surface", support_surface="p3",
                    contact="rubber", **common).model()  # fmt: skip
    plane = _ball("rubber_plane", contact=contact, **common).model()
    omega_rate, _ = _surface_rates(surface, sp.Matrix([R_(1, 3), R_(2, 3), 0]), omega)
    assert omega_rate[2] == 0  # no spin is kept
    acceleration = _plane_acceleration(plane, omega)
    assert ((acceleration - omega_rate).applyfunc(sp.simplify) == sp.zeros(3, 1)) is agrees


@pytest.mark.parametrize("side", ["outside", "inside"])
@pytest.mark.parametrize("contact, agrees", [("rubber", True), ("rolling", False)])
def test_rubber_rolling_on_a_sphere_moves_as_on_the_sphere_support(side, contact, agrees):
    """F = |p|^2 - R^2 with rubber contact against the sphere support's rubber ball (body
    frame: the normal gamma, the vertical zeta), outside and inside; the sphere route rolling
    is the control."""
    R, s = R_(29, 10), 1 if side == "outside" else -1
    n = sp.Matrix([R_(2, 7), R_(3, 7), R_(6, 7)])
    omega = NO_SPIN["sphere"]
    assert omega.dot(n) == 0
    common = {"gyrostat": list(ROTOR), "gravity": G, "side": side}
    shape = f"p1**2 + p2**2 + p3**2 - ({R})**2"
    surface = _ball("rubber_on_sphere_surface", support="surface", support_surface=shape,
                    contact="rubber", **common).model()  # fmt: skip
    sphere = _ball("rubber_on_sphere", support="sphere", support_radius=R, contact=contact,
                   **common).model()  # fmt: skip
    omega_rate, _ = _surface_rates(surface, s * R * n, omega)
    acceleration = _plane_acceleration(sphere, omega, {"gamma": Q.T * n, "zeta": Q.T * E3})
    assert ((acceleration - omega_rate).applyfunc(sp.simplify) == sp.zeros(3, 1)) is agrees
