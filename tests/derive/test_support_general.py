"""A ball of any mass distribution on a support surface F(p) = 0 (fixed frame, the body
axes e1, e2, e3 in the state) against routes that share no formula with it: the
body-frame engine on a plane and on a fixed sphere, and the homogeneous fixed-frame
route (M03 section 1's derivation) on an ellipsoid.

The body-frame routes carry the body-frame momentum and the support's normal gamma (and
the vertical zeta); at a state ``(omega, p, Q)`` of the new route they are at
``omega_b = Q^T omega``, ``gamma = Q^T n``, ``zeta = Q^T e3``, and ``omega' = Q omega_b'``
(``Q' omega_b = omega x omega = 0``)."""

from __future__ import annotations

import random
import re

import pytest
import sympy as sp
from chaplygin.derive.ball_on_support_general import general_ball_model
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.phase_space import sample_point
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.derive.vectors import vector
from chaplygin.verify.chained import rate_at

R_ = sp.Rational
M, B, G = R_(13, 10), R_(7, 10), R_(49, 5)
INERTIA = sp.Matrix(
    [[R_(3, 10), R_(1, 20), 0], [R_(1, 20), R_(2, 5), R_(-1, 30)], [0, R_(-1, 30), R_(1, 2)]]
)
OFFSET = sp.Matrix([R_(1, 10), R_(-1, 20), R_(-1, 5)])
ROTOR = sp.Matrix([R_(1, 7), 0, R_(1, 3)])
OMEGA = sp.Matrix([R_(3, 10), R_(-7, 10), R_(11, 10)])
E3 = sp.Matrix([0, 0, 1])


def _rotation(q0: int, q1: int, q2: int, q3: int) -> sp.Matrix:
    """The proper rotation of the integer quaternion (Euler–Rodrigues), rational."""
    n = q0**2 + q1**2 + q2**2 + q3**2
    return (
        sp.Matrix(
            [
                [q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
                [2 * (q1 * q2 + q0 * q3), q0**2 - q1**2 + q2**2 - q3**2, 2 * (q2 * q3 - q0 * q1)],
                [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2],
            ]
        )
        / n
    )


Q = _rotation(3, -1, 2, 5)


def _system(name: str, inertia=INERTIA, offset=OFFSET, **fields) -> RollingSystem:
    return RollingSystem(
        name, inertia=inertia.tolist(), mass=M, radius=B, centre_of_mass=list(offset),
        gyrostat=list(ROTOR), gravity=G, **fields,
    )  # fmt: skip


def _new_rates(model, p: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
    """``omega'`` and ``p'`` of the fixed-frame route at ``(OMEGA, p, Q)``."""
    names = {x.name: x for x in model.state}
    point = {names[f"omega{i + 1}"]: OMEGA[i] for i in range(3)}
    point.update({names[f"p{i + 1}"]: p[i] for i in range(3)})
    point.update({names[f"e{j + 1}_{i + 1}"]: Q[i, j] for i in range(3) for j in range(3)})
    assert all(sp.expand(c.xreplace(point)) == 0 for c in model.constraints)
    for symbol, expr in model.aux:  # in order: each at the values of those before it
        point[symbol] = sp.radsimp(expr.xreplace(point))
    rates = sp.Matrix(model.rhs).xreplace(point).applyfunc(sp.radsimp)
    return sp.Matrix(rates[:3]), sp.Matrix(rates[3:6])


def _body_rates(model, vectors: dict[str, sp.Matrix]) -> tuple[sp.Matrix, dict]:
    """``Q omega_b'`` of a body-frame route at ``omega_b = Q^T OMEGA`` and the body-frame
    vectors given, with the rates of every state symbol."""
    names = {x.name: x for x in model.state}
    point = {names[f"{n}{i + 1}"]: v[i] for n, v in vectors.items() for i in range(3)}
    momentum = sp.Matrix(model.group("M"))
    omega_of_m = model.expand_aux(model.omega)
    solved = sp.solve(list(omega_of_m.xreplace(point) - Q.T * OMEGA), list(momentum), dict=True)
    point.update(solved[0])
    rates = model.rhs_expanded.xreplace(point)
    acceleration = omega_of_m.jacobian(sp.Matrix(model.state)).xreplace(point) * rates
    return Q * acceleration, dict(zip(model.state, rates, strict=True))


@pytest.mark.parametrize(
    "offset, agrees", [(OFFSET, True), (OFFSET + sp.Matrix([0, 0, R_(1, 20)]), False)]
)
def test_on_the_plane_F_p3_it_moves_as_the_body_frame_ball_on_the_plane(offset, agrees):
    """F = p3 (a plane written as a support surface) against the engine's body-frame ball
    on a plane (state M, gamma; with the contact trace x, y in the fixed axes alpha, beta):
    omega' and p' agree exactly for an unbalanced ball with a product of inertia and a
    rotor, and disagree when the plane route's centre of mass is moved (the control)."""
    new = _system("on_plane_surface", support="surface", support_surface="p3").model()
    body = _system("on_plane", offset=offset).model(("contact_point",))
    p = sp.Matrix([R_(1, 3), R_(2, 3), 0])
    omega_rate, p_rate = _new_rates(new, p)
    vectors = {"gamma": Q.T * E3, "alpha": Q.T * sp.Matrix([1, 0, 0])}
    vectors["beta"] = Q.T * sp.Matrix([0, 1, 0])
    acceleration, rates = _body_rates(body, vectors)
    trace = {x.name: r for x, r in rates.items() if x.name in ("x", "y")}
    assert p_rate == sp.Matrix([trace["x"], trace["y"], 0])  # kinematics: no mass enters
    assert ((acceleration - omega_rate).applyfunc(sp.simplify) == sp.zeros(3, 1)) is agrees


@pytest.mark.parametrize("side", ["outside", "inside"])
@pytest.mark.parametrize("agrees", [True, False])
def test_on_a_spherical_surface_it_moves_as_the_ball_on_the_sphere_support(side, agrees):
    """F = |p|^2 - R^2 against the sphere support (body frame: M, the normal gamma turning
    at R/(R +- b) of Poisson's rate, the vertical zeta): omega' agrees exactly and so does
    p' = s R Q (gamma' + omega_b x gamma) (p = s R n); a different product of inertia on
    the sphere's side is the control."""
    R = R_(29, 10)
    s = 1 if side == "outside" else -1
    product = sp.Matrix([[0, R_(1, 50), 0], [R_(1, 50), 0, 0], [0, 0, 0]])
    inertia = INERTIA if agrees else INERTIA + product
    shape = f"p1**2 + p2**2 + p3**2 - ({R})**2"
    new = _system("on_sphere_surface", support="surface", support_surface=shape, side=side)
    body = _system("on_sphere", inertia=inertia, support="sphere", support_radius=R, side=side)
    new, body = new.model(), body.model()
    n = sp.Matrix([R_(2, 7), R_(3, 7), R_(6, 7)])  # from the contact to the centre
    omega_rate, p_rate = _new_rates(new, s * R * n)
    acceleration, rates = _body_rates(body, {"gamma": Q.T * n, "zeta": Q.T * E3})
    gamma = sp.Matrix(body.group("gamma"))
    gamma_rate = gamma.xreplace(rates)
    assert (p_rate - s * R * Q * (gamma_rate + (Q.T * OMEGA).cross(Q.T * n))).applyfunc(
        sp.simplify
    ) == sp.zeros(3, 1)
    assert ((acceleration - omega_rate).applyfunc(sp.simplify) == sp.zeros(3, 1)) is agrees


@pytest.mark.parametrize("offset, agrees", [(sp.zeros(3, 1), True), (OFFSET, False)])
def test_a_homogeneous_ball_moves_as_on_the_homogeneous_route(offset, agrees):
    """Equal moments, the centre of mass at the centre, no rotor on an ellipsoid: the new
    route (called directly: RollingSystem sends a homogeneous ball to the homogeneous
    route) equals SupportSurfaceReduction's omega' and p' at any attitude; with the centre
    of mass moved off the centre (the control) omega' differs."""
    c = (R_(4), R_(9, 4), R_(1))
    shape = f"p1**2/{c[0]} + p2**2/({c[1]}) + p3**2/{c[2]} - 1"
    moment = R_(2, 5) * M * B**2
    homogeneous = RollingSystem(
        "homogeneous", inertia=(moment,) * 3, mass=M, radius=B, gravity=G,
        support="surface", support_surface=shape,
    ).model()  # fmt: skip
    p = vector("p", real=True)
    F = sum((p[i] ** 2 / c[i] for i in range(3)), sp.S.Zero) - 1
    new = general_ball_model(F, M, B, moment * sp.eye(3), offset, sp.zeros(3, 1), gravity=G)
    u = sp.Matrix([R_(2, 7), R_(3, 7), R_(6, 7)])  # grad F = 2 u: |grad F| = 2 exactly
    point = sp.Matrix([c[i] * u[i] for i in range(3)])
    omega_rate, p_rate = _new_rates(new, point)
    names = {x.name: x for x in homogeneous.state}
    at = {names[f"omega{i + 1}"]: OMEGA[i] for i in range(3)}
    at.update({names[f"p{i + 1}"]: point[i] for i in range(3)})
    theirs = homogeneous.rhs_expanded.xreplace(at)
    assert p_rate == sp.Matrix(theirs[3:6])
    assert (omega_rate == sp.Matrix(theirs[:3]).applyfunc(sp.radsimp)) is agrees


#: A ball with a product of inertia, an offset, a rotor and gravity on an ellipsoid with
#: symbolic axes.
EGG = dict(
    inertia=[["A", "D", 0], ["D", "B", 0], [0, 0, "C"]], centre_of_mass=(0, 0, "a"),
    gyrostat=(0, 0, "k"), gravity="g", support="surface",
    support_surface="p1**2/c1 + p2**2/c2 + p3**2/c3 - 1",
)  # fmt: skip


def test_a_general_ball_is_derived_and_what_is_not_is_refused():
    """The description with symbols (any inertia with a product, offset, rotor, an
    ellipsoid with symbolic axes) derives the state omega, p, e1, e2, e3 and the integrals
    H and F; a line contact and a potential of what is not the configuration are refused
    on one line (rubber contact, K(t), I(t) and potentials of p and the axes are derived:
    tests/derive/test_support_general_fields.py)."""
    system = RollingSystem("egg", **EGG)
    model = system.model()
    assert model.state_names[:6] == ("omega1", "omega2", "omega3", "p1", "p2", "p3")
    assert len(model.state) == 15 and len(model.constraints) == 6
    assert [n for n, _ in model.integrals] == ["H", "F"]
    assert set(model.param_names) == set("m b A B C D a g k c1 c2 c3".split())
    refused = (
        ({"contact": "line"}, "contact 'line'"),
        ({"potential": "omega1"}, "['omega1'] are reserved"),
        ({"centre_of_mass": (0, 0, "af3")}, "['af3'] are the derivation's auxiliaries"),
    )
    for fields, message in refused:
        with pytest.raises(UserInputError, match=re.escape(message)):
            RollingSystem(
                "bad", inertia=("A", "B", "C"), support="surface", support_surface="p3", **fields
            )


@pytest.mark.parametrize("potential, conserved", [(1, True), (0, False), (-1, False)])
def test_the_energy_is_an_integral_on_an_ellipsoid_with_symbolic_parameters(potential, conserved):
    """H = T + m g (height of the centre of mass) on an ellipsoid with symbolic axes, a
    symbolic inertia with a product, offset and rotor: exactly zero rate at exact points
    of the phase space drawn by the verifier's sampler (random rational parameters, a
    rational frame e1, e2, e3, omega and p; the flow keeps every level set of F, so p need
    not be on F = 0); the level F too. H without its potential term, or with it of the
    wrong sign, changes (the controls). The verifier's Groebner proof and its exact
    sampling of the expanded residual (10^6 operations) do not finish in 10 minutes."""
    system = RollingSystem("egg", **EGG)
    model = system.model()
    names = {x.name: x for x in model.params}
    m, g = names["m"], names["g"]
    e3 = model.vectors["e3"]
    height = model.vectors["p"][2] + sp.Symbol("nu3", real=True) * names["b"] + names["a"] * e3[2]
    H = model.integral("H")
    energy = H + (potential - 1) * m * g * height
    rng = random.Random(24)
    for _ in range(2):
        point = sample_point(model, rng, model.state)
        assert (rate_at(model, energy, point) == 0) is conserved
        assert rate_at(model, model.integral("F"), point) == 0
