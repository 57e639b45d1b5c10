"""The Lagrange–d'Alembert engine: derivation of the ball from its constraint."""

from __future__ import annotations

import pytest
import sympy as sp
from chaplygin.derive import DerivationError, RigidBodyDescription, build_model, lagrange_dalembert
from chaplygin.derive.chaplygin_ball import build_chaplygin_ball
from chaplygin.derive.vectors import cross, dot, vector


def _ball_description(r_sign: int = -1, extra_constraints=()):
    t = sp.Symbol("t")
    I = vector("I", positive=True)
    m, b = sp.symbols("m b", positive=True)
    omega, v, gamma = vector("omega"), vector("v"), vector("gamma")
    T = (omega.T * sp.diag(*I) * omega)[0] / 2 + m * dot(v, v) / 2
    r = r_sign * b * gamma
    return RigidBodyDescription(
        omega=omega,
        v=v,
        kinetic_energy=T,
        constraints=list(v + cross(omega, r)) + list(extra_constraints),
        kinematics={"gamma": (gamma, cross(gamma, omega))},
        time=t,
    ), (I, m, b, omega, gamma)


def test_multipliers_are_eliminated_by_the_admissible_velocities():
    desc, _ = _ball_description()
    red = lagrange_dalembert(desc)
    Phi = sp.Matrix(
        [[sp.diff(c, q) for q in list(desc.omega) + list(desc.v)] for c in desc.constraints]
    )
    # G spans the admissible velocities: Phi G = 0, so G^T Phi^T lambda = 0
    assert (Phi * red.admissible).applyfunc(sp.expand) == sp.zeros(3, 3)
    assert len(red.multipliers) == 3
    # the unreduced equations really contain the multipliers
    assert set(red.multipliers) <= red.with_multipliers.free_symbols


def test_ball_momentum_about_contact_point_and_euler_poincare_form():
    desc, (I, m, b, omega, gamma) = _ball_description()
    red = lagrange_dalembert(desc)
    D = m * b**2
    expected = sp.diag(*I) * omega + D * cross(gamma, cross(omega, gamma))
    assert (red.momentum - expected).applyfunc(sp.expand) == sp.zeros(3, 1)
    M = vector("M")
    _, remainder = red.euler_poincare_form(M)
    assert remainder == sp.zeros(3, 1)


def test_constraint_sign_reaches_the_velocity_but_not_the_momentum():
    """r = +b gamma (contact above the centre): same momentum, opposite centre velocity."""
    desc, (I, m, b, omega, gamma) = _ball_description(r_sign=+1)
    red = lagrange_dalembert(desc)
    D = m * b**2
    ball = sp.diag(*I) * omega + D * cross(gamma, cross(omega, gamma))
    # same kinetic form (r enters quadratically) but the velocity map flips sign
    assert red.velocity_map != lagrange_dalembert(_ball_description()[0]).velocity_map
    assert (red.momentum - ball).applyfunc(sp.expand) == sp.zeros(3, 1)


def test_structured_inverse_is_the_papers_sherman_morrison_form():
    model = build_model("chaplygin_ball")
    s = model.structured_inverse
    I = model.param_group("I")
    D = model.param_group("D")[0]
    assert s.J == sp.diag(*[I[i] + D for i in range(3)])
    assert s.C == sp.Matrix([[-D]])
    assert s.U == model.group("gamma")


def test_radius_leaves_the_model_without_contact_point():
    assert "b" not in build_model("chaplygin_ball").param_names
    assert "b" in build_model("chaplygin_ball", ["contact_point"]).param_names


def test_nonlinear_constraint_is_rejected():
    desc, (_, _, _, omega, _) = _ball_description()
    desc.constraints = [*desc.constraints[:2], desc.constraints[2] + omega[0] ** 2]
    with pytest.raises(DerivationError, match="linear"):
        lagrange_dalembert(desc)


def test_constraint_on_omega_alone_keeps_its_multiplier():
    omega, gamma = vector("omega"), vector("gamma")  # the same symbols the builder uses
    desc, _ = _ball_description(extra_constraints=[dot(omega, gamma)])
    red = lagrange_dalembert(desc)
    assert red.omega_constraints == gamma.T
    (mu,) = red.omega_multipliers
    M = vector("M")
    _, remainder = red.euler_poincare_form(M)
    assert (remainder - mu * gamma).applyfunc(sp.expand) == sp.zeros(3, 1)


def _rubber_ball_checks():
    """Residuals for the rubber ball (no slip, no twist) derived by the engine."""
    model = build_model("chaplygin_ball")  # supplies symbols, sphere and sampler
    t = model.time
    I = model.param_group("I")
    D = model.param_group("D")[0]
    b = sp.Symbol("b", positive=True)
    M, gamma = model.group("M"), model.group("gamma")
    omega, v = sp.Matrix(model.omega), vector("v", real=True)
    T = (omega.T * sp.diag(*I) * omega)[0] / 2 + D / b**2 * dot(v, v) / 2
    desc = RigidBodyDescription(
        omega=omega,
        v=v,
        kinetic_energy=T,
        constraints=list(v + cross(omega, -b * gamma)) + [dot(omega, gamma)],
        kinematics={"gamma": (gamma, cross(gamma, omega))},
        time=t,
    )
    red = lagrange_dalembert(desc)
    structured = red.structured_inverse(model.ideal)
    rhs_M, remainder = red.euler_poincare_form(M)
    (mu,) = red.omega_multipliers
    F = rhs_M - mu * gamma
    mu_val = red.multiplier_solution(F, structured.apply_inverse)[mu]
    omega_of_M = structured.apply_inverse(M)
    # A point of the constraint surface: omega = gamma x u, M = II(gamma) omega. There
    # omega(M, gamma) = gamma x u modulo (gamma, gamma) = 1, so the vector field may be
    # evaluated with omega = gamma x u directly (equal modulo the ideal).
    u = vector("u", real=True)
    w = cross(gamma, u)
    point = {
        **dict(zip(M, red.inertia_operator * w, strict=True)),
        **dict(zip(omega, w, strict=True)),
    }
    f_M = (F + mu_val * gamma).xreplace(point)
    f_g = cross(gamma, w)

    def rate(expr):
        grad = [sp.diff(expr, s).xreplace(point) for s in list(M) + list(gamma)]
        return sum((g * f for g, f in zip(grad, list(f_M) + list(f_g), strict=True)), sp.S.Zero)

    twist = dot(omega_of_M, gamma)
    energy = dot(M, omega_of_M) / 2
    K = M - dot(M, gamma) * gamma
    checks = {
        "twist preserved": [rate(twist)],
        "energy": [rate(energy)],
        "K' = K x omega": list(sp.Matrix([rate(k) for k in K]) - cross(K, w).xreplace(point)),
        "(M, M) (not an integral)": [rate(dot(M, M))],
    }
    return model, u, checks


def test_rubber_ball_multiplier_keeps_the_flow_on_the_constraint_and_conserves_energy():
    from chaplygin.verify.identity import Domain, decide

    model, u, checks = _rubber_ball_checks()
    domain = Domain(model, free=list(u))
    for name in ("twist preserved", "energy", "K' = K x omega"):
        assert decide(checks[name], domain).verdict == "proved", name
    # negative control: (M, M) is an integral of the Chaplygin ball, not of the rubber ball
    assert decide(checks["(M, M) (not an integral)"], domain).verdict == "refuted"


def test_model_hash_is_stable_and_depends_on_effects():
    a = build_chaplygin_ball()
    b = build_chaplygin_ball()
    assert a.hash == b.hash
    assert a.hash != build_chaplygin_ball(["gyrostat"]).hash
