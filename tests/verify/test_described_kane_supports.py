"""Described systems against Kane's method: curved and moving supports.

The Kane cross-check (:mod:`chaplygin.verify.kane_rolling`) is an independent derivation
(sympy.physics.mechanics, Euler angles, a real rotor for the gyrostat); its negative
control is a model with a perturbed right-hand side, refuted by the same comparison.
Here a fixed sphere (inside and outside, with gravity, and a potential of gamma and the
vertical), a turntable (classical and rubber rolling), a plane moving by a prescribed law and
a fixed ellipsoid and a quartic support (with a potential, rubber contact, K(t) and
I(t) there); the bodies on a fixed plane are in ``test_described_kane_bodies.py``, the
rest of the described systems in ``test_described_systems.py``.
"""

from __future__ import annotations

import pytest
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.identity import Domain, decide, lie_derivative
from chaplygin.verify.kane_rolling import kane_compare


@pytest.mark.slow
def test_kane_agrees_on_a_sphere_and_refutes_the_other_side():
    """Inside a spherical shell, with an offset centre of mass (a product of inertia and a
    rotor on a sphere were checked by hand: 2e-41, 5e-41; the plane's test above covers
    them); the model of the same body outside the sphere is refuted by the same check."""
    fields = dict(
        inertia=("I1", "I2", "I3"), centre_of_mass=("a1", 0, "a3"), support="sphere",
        support_radius="R",
    )  # fmt: skip
    inside = RollingSystem("in_shell", side="inside", **fields)
    values = dict(m="1.3", b="0.7", I1="0.31", I2="0.43", I3="0.57", a1="0.11", a3="0.2", R="2.3")
    result = kane_compare(inside, inside.model(), values)
    assert result.points == 4 and result.agrees, result
    outside = RollingSystem("in_shell", side="outside", **fields).model()
    control = kane_compare(inside, outside, values)
    assert control.max_normal_rate_error > 1e6 * control.tolerance
    assert control.max_acceleration_error > 1e6 * control.tolerance


@pytest.mark.slow
def test_kane_agrees_under_gravity_on_a_sphere_and_refutes_a_centre_at_rest():
    """Gravity on a fixed sphere (the vertical zeta joins the state; Kane's body sits away
    from the pole, so zeta is not the normal): an offset centre of mass outside and inside,
    and a potential of gamma and zeta (its loads in Kane: a torque and, since the normal
    turns as the centre moves, a force at the centre). Control: the model that takes only
    the torque of the centre of mass about the body's centre, m g (a, zeta) — as if the
    centre did not rise with gamma — is refuted by the same check."""
    fields = dict(inertia=("I1", "I2", "I3"), support="sphere", support_radius="R")
    values = dict(
        m="1.3", b="0.7", I1="0.31", I2="0.43", I3="0.57", a1="0.11", a3="0.2", R="2.9",
        g="9.81", k="0.37",
    )  # fmt: skip
    offset = dict(centre_of_mass=("a1", 0, "a3"), gravity="g")
    for side in ("outside", "inside"):
        system = RollingSystem("heavy_on_sphere", side=side, **fields, **offset)
        result = kane_compare(system, system.model(), values)
        assert result.points == 4 and result.agrees, (side, result)
    potential = RollingSystem("pot_on_sphere", potential="k*zeta3*gamma1 + k*gamma2**2", **fields)
    result = kane_compare(potential, potential.model(), values)
    assert result.agrees, result
    heavy = RollingSystem("heavy_on_sphere", **fields, **offset)
    resting = RollingSystem(
        "heavy_on_sphere", potential="m*g*(a1*zeta1 + a3*zeta3)", centre_of_mass=("a1", 0, "a3"),
        **fields,
    )  # fmt: skip
    control = kane_compare(heavy, resting.model(), values)
    assert control.max_acceleration_error > 1e6 * control.tolerance


@pytest.mark.slow
def test_kane_agrees_on_a_rotating_plane_and_refutes_the_plane_turning_the_other_way():
    """Affine constraints: the body's contact point moves with the plane. An offset centre
    of mass under gravity (the balanced body and a rotor were checked by hand: 5e-41,
    8e-41); the model of the plane turning at -Omega is refuted by the same check."""
    fields = dict(
        inertia=("I1", "I2", "I3"), centre_of_mass=("a1", 0, "a3"), gravity="g",
        support="rotating_plane",
    )  # fmt: skip
    system = RollingSystem("turntable", rotation_rate="Omega", **fields)
    values = dict(
        m="1.3", b="0.7", I1="0.31", I2="0.43", I3="0.57", a1="0.11", a3="0.2", g="9.81",
        Omega="0.37",
    )  # fmt: skip
    result = kane_compare(system, system.model(), values)
    assert result.points == 4 and result.agrees, result
    reverse = RollingSystem("turntable", rotation_rate="-Omega", **fields).model()
    control = kane_compare(system, reverse, values)
    assert control.max_acceleration_error > 1e6 * control.tolerance
    assert control.max_normal_rate_error > 1e6 * control.tolerance  # rho' too


@pytest.mark.slow
def test_kane_agrees_with_rolling_along_a_line_on_a_moving_plane():
    """Rolling along the fixed line alpha ((omega, alpha) = 0, Veselov's constraint,
    BKM12-57) on a plane translated by V(t) = (sin t/3, t^2/5): the line stays one in space,
    the model is the plane's with the constraint; Kane (its own (omega, N.x) = 0 and the
    plane's law) agrees at 40 digits; the model of another law and that of the fixed plane
    are refuted by the same comparison."""
    base = dict(inertia=("0.31", "0.43", "0.57"), centre_of_mass=(0, 0, "0.1"), gravity="g",
                support="moving_plane", contact="line")  # fmt: skip
    system = RollingSystem("line_shaken", plane_velocity=("sin(t)/3", "t**2/5"), **base)
    values = dict(m="1.3", b="0.7", g="9.81")
    result = kane_compare(system, system.model(), values)
    assert result.points == 4 and result.agrees, result
    assert "(omega,alpha)" in dict(system.model().invariant_relations)
    for wrong in (RollingSystem("line_shaken_w", plane_velocity=("sin(t)/3", "t**2/4"), **base),
                  RollingSystem("line_fixed", **{**base, "support": "plane"})):  # fmt: skip
        control = kane_compare(system, wrong.model(), values)
        assert control.max_acceleration_error > 1e6 * control.tolerance


@pytest.mark.slow
def test_kane_agrees_on_a_plane_moving_by_a_prescribed_law_and_refutes_another_law():
    """An offset centre of mass under gravity on a plane shaken horizontally, V = (u cos wt,
    u sin 2wt) along the fixed axes, compared at t = 7/10 (a turntable at Omega (1 + e sin
    wt) was checked by hand: 4e-41); the model of the law (u cos wt, u sin wt) is refuted."""
    fields = dict(
        inertia=("I1", "I2", "I3"), centre_of_mass=("a1", 0, "a3"), gravity="g",
        support="moving_plane",
    )  # fmt: skip
    system = RollingSystem("shaken", plane_velocity=("u*cos(w*t)", "u*sin(2*w*t)"), **fields)
    values = dict(
        m="1.3", b="0.7", I1="0.31", I2="0.43", I3="0.57", a1="0.11", a3="0.2", g="9.81",
        u="0.8", w="1.7",
    )  # fmt: skip
    result = kane_compare(system, system.model(), values)
    assert result.points == 4 and result.agrees, result
    other = RollingSystem("shaken", plane_velocity=("u*cos(w*t)", "u*sin(w*t)"), **fields)
    control = kane_compare(system, other.model(), values)
    assert control.max_acceleration_error > 1e6 * control.tolerance


@pytest.mark.slow
def test_kane_agrees_with_rubber_rolling_on_a_turntable_and_refutes_the_other_turn():
    """Rubber rolling on a turntable: no twist relative to the plane, (omega, gamma) =
    Omega — an affine constraint on omega alone (its multiplier from d/dt (C omega + c) =
    0). Kane with u3 = Omega a dependent speed (an offset centre under gravity at Omega(1 +
    e sin wt) and a rubber body on a shaken plane checked by hand: 2e-41, 9e-42). The model
    of the plane turning the other way is refuted by the same check; the integral the model
    ships is proved by the verifier."""
    fields = dict(inertia=("I1", "I2", "I3"), support="rotating_plane", contact="rubber")
    values = dict(m="1.3", b="0.7", I1="0.31", I2="0.43", I3="0.57", Omega="0.37")
    system = RollingSystem("rubber_turntable", rotation_rate="Omega", **fields)
    model = system.model()
    result = kane_compare(system, model, values)
    assert result.points == 4 and result.agrees, result
    reverse = RollingSystem("rubber_turntable", rotation_rate="-Omega", **fields).model()
    control = kane_compare(system, reverse, values)
    assert control.max_acceleration_error > 1e6 * control.tolerance
    relations = dict(model.invariant_relations)
    assert "(omega,gamma)" in relations and "H" not in dict(model.integrals)
    for name, expr in model.integrals:
        assert decide([lie_derivative(expr, model)], Domain(model)).verdict == "proved", name


@pytest.mark.slow
def test_kane_agrees_with_a_ball_on_an_ellipsoidal_support_and_refutes_the_other_side():
    """A homogeneous heavy ball outside an ellipsoid off the origin: Kane's method on a
    parametrisation of the support (the contact point p(x, y), the centre p + b nu(p))
    against the model's implicit normal grad F/|grad F|: omega' and p' agree at 40 digits;
    the model of the ball inside the same ellipsoid is refuted by the same check. The
    file's :kane claim exists where the comparison places its contacts (not on an open
    paraboloid)."""
    from chaplygin.verify.user_claims import kane_covers

    fields = dict(
        inertia=("2/5*m*b**2",) * 3, gravity="g", support="surface",
        support_surface="p1**2/4 + p2**2/(9/4) + (p3 - 1/3)**2 - 1",
    )  # fmt: skip
    system = RollingSystem("ball_on_egg", **fields)
    values = dict(b="0.7", g="9.81")
    result = kane_compare(system, system.model(), values)
    assert result.points == 4 and result.agrees, result
    inside = RollingSystem("ball_on_egg", side="inside", **fields).model()
    control = kane_compare(system, inside, values)
    assert control.max_acceleration_error > 1e6 * control.tolerance
    assert control.max_normal_rate_error > 1e6 * control.tolerance  # p' too
    assert kane_covers(system)
    bumpy = dict(fields, support_surface="p1**4 + p2**2 + p3**2 - 1")  # kane_support_implicit
    assert kane_covers(RollingSystem("ball_on_bump", **bumpy))
    bowl = dict(fields, support_surface="p1**2 + p2**2 - p3")  # rays that never leave it
    assert not kane_covers(RollingSystem("ball_in_bowl", **bowl))


@pytest.mark.slow
def test_kane_agrees_with_a_general_ball_on_an_ellipsoidal_support_and_refutes_a_moved_centre():
    """A ball with a product of inertia, its centre of mass off the centre and a rotor,
    heavy, outside an ellipsoid off the origin (the general route, body axes e1, e2, e3 in
    the state): Kane's method on the support's parametrisation (the centre of mass G = O +
    a, the rotor as the torque -omega x K) agrees in omega' and p' at 40 digits; the model
    with the centre of mass moved along the third axis is refuted in omega'."""
    _general_ball_agrees_and_a_moved_centre_is_refuted(
        "ball_on_egg", support_surface="p1**2/4 + p2**2/(9/4) + (p3 - 1/3)**2 - 1"
    )


def _general_ball_agrees_and_a_moved_centre_is_refuted(name: str, **support) -> None:
    """A heavy ball with a product of inertia, an offset centre of mass and a rotor on the
    support given: Kane agrees in omega' and p' at 4 points, the model with the centre of
    mass moved by 0.05 is refuted in omega', and the file's :kane claim covers it."""
    from chaplygin.verify.user_claims import kane_covers

    inertia = [["0.31", "0.02", 0], ["0.02", "0.43", "-0.03"], [0, "-0.03", "0.57"]]
    fields = dict(
        inertia=inertia, gyrostat=("0.14", 0, "0.33"), gravity="g", support="surface", **support
    )  # fmt: skip
    system = RollingSystem(name, centre_of_mass=("0.1", "-0.05", "-0.2"), **fields)
    values = dict(m="1.3", b="0.7", g="9.81")
    result = kane_compare(system, system.model(), values)
    assert result.points == 4 and result.agrees, result
    moved = RollingSystem(name, centre_of_mass=("0.1", "-0.05", "-0.15"), **fields)
    control = kane_compare(system, moved.model(), values)
    assert control.max_acceleration_error > 1e6 * control.tolerance
    assert kane_covers(system)


#: A heavy ball with a product of inertia, an offset centre of mass and a rotor on a convex
#: quartic support off the origin, and what each case adds (with the control's fields: the
#: same system with one thing wrong).
_QUARTIC = dict(
    inertia=[["0.31", "0.02", 0], ["0.02", "0.43", "-0.03"], [0, "-0.03", "0.57"]],
    gyrostat=("0.14", 0, "0.33"), gravity="g", support="surface",
    centre_of_mass=("0.1", "-0.05", "-0.2"),
    support_surface="p1**4 + p2**4/2 + p1**2 + (p2 - 1/5)**2 + (p3 + 1/3)**2 - 3",
)  # fmt: skip
_ROW3 = [0, "-0.03", "0.57"]
_FIELDS = {
    "potential": ({"potential": "k*(e3_3*p1 + e1_2**2)"}, {"potential": "2*k*(e3_3*p1 + e1_2**2)"}),
    "rubber": ({"contact": "rubber"}, {"contact": "rolling"}),
    # K(t) = (0.14, t/3, 0.33) against the rotor frozen at its value at T0 = 7/10
    "K(t)": ({"gyrostat": ("0.14", "t/3", "0.33")}, {"gyrostat": ("0.14", "7/30", "0.33")}),
    # I22(t) = 0.43 + t^2/5 against the tensor frozen at T0 (0.43 + 0.098)
    "I(t)": (
        {"inertia": [["0.31", "0.02", 0], ["0.02", "0.43 + t**2/5", "-0.03"], _ROW3]},
        {"inertia": [["0.31", "0.02", 0], ["0.02", "0.528", "-0.03"], _ROW3]},
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", list(_FIELDS))
def test_kane_agrees_on_a_support_surface_with_a_potential_rubber_contact_k_t_and_i_t(case):
    """What the ellipsoid's parametrisation does not set up, on a quartic support (the
    contact point as Kane's coordinates, kane_support_implicit): a potential V(p, e1, e2,
    e3) as the loads -dV/dq_j on the Euler angles and the contact point, rubber contact as
    the fourth constraint (omega, nu) = 0 (omega's normal component dependent), K(t) and
    I(t) as real rotors and a tensor of Kane's time (kane_common.rigid_bodies): omega' and
    p' agree at 40 digits at T0 = 7/10 and the file's :kane claim covers them. The model
    of the same system with one thing wrong (twice the potential, rolling for rubber, the
    rotor or the tensor frozen at their values at T0: only their rates are missing) is
    refuted by the same comparison."""
    from chaplygin.verify.user_claims import kane_covers

    fields, wrong = _FIELDS[case]
    name = "ball_on_quartic_" + {"K(t)": "kt", "I(t)": "it"}.get(case, case)
    system = RollingSystem(name, **{**_QUARTIC, **fields})
    values = {k: v for k, v in dict(m="1.3", b="0.7", g="9.81", k="0.37").items()
              if k in system.parameter_names}  # fmt: skip
    result = kane_compare(system, system.model(), values)
    assert result.points == 4 and result.agrees, result
    assert kane_covers(system)
    control = RollingSystem(name + "_wrong", **{**_QUARTIC, **wrong})
    refuted = kane_compare(system, control.model(), values)
    assert refuted.max_acceleration_error > 1e6 * refuted.tolerance, refuted


@pytest.mark.parametrize("side", ["outside", "inside"])
def test_kane_agrees_with_a_general_ball_on_a_quartic_support_and_refutes_a_moved_centre(side):
    """A support that is not an ellipsoid (a convex quartic, off the origin): Kane's method
    with the contact point p as coordinates (no parametrisation: the support's equation
    is never solved; no slip at the body point O - sigma b nu in all three components) for
    a heavy ball with a product of inertia, its centre of mass off the centre and a rotor,
    outside and inside: omega' and p' agree at 40 digits at the points where rays from
    inside meet the support; the model with the centre of mass moved is refuted in
    omega'; the file's :kane claim now covers such supports."""
    _general_ball_agrees_and_a_moved_centre_is_refuted(
        "ball_on_quartic", side=side,
        support_surface="p1**4 + p2**4/2 + p1**2 + (p2 - 1/5)**2 + (p3 + 1/3)**2 - 3",
    )  # fmt: skip


#: A tilted ellipsoidal body (semi-axes about 1/2, 1/3, 0.45) with its centre of mass off
#: its centre, on an ellipsoid off the origin (outside) or inside a larger one.
_CONVEX = dict(
    inertia=_QUARTIC["inertia"], gyrostat=("0.14", 0, "0.33"), gravity="g", support="surface",
    surface="x1**2/(1/4) + x2**2/(1/9) + x3**2/(1/5) + x1*x2/7 - 1",
    centre_of_mass=("0.05", "-0.04", "0.06"),
)  # fmt: skip
_CONVEX_SUPPORT = {
    "outside": "p1**2/4 + p2**2/(9/4) + (p3 - 1/3)**2 - 1",
    "inside": "p1**2/16 + p2**2/9 + (p3 - 1/3)**2/9 - 1",
}


@pytest.mark.slow
@pytest.mark.parametrize("side", ["outside", "inside"])
def test_kane_agrees_with_a_convex_body_on_a_support_surface_and_refutes_wrong_ones(side):
    """A convex body on a convex support (derive/body_on_support.py: the contact's rate from
    both surfaces' curvatures): Kane's method with both contact points as coordinates
    (kane_body_support: no slip at the body's material point, the contact kept on the
    support and the two normals kept parallel — neither surface's curvature is written)
    agrees in omega', p' and r' at 40 digits, outside an ellipsoid and inside a larger one;
    the model with the centre of mass moved, and the model of a body with another third
    axis, are refuted by the same comparison; the file's :kane claim covers it."""
    from chaplygin.verify.user_claims import kane_covers

    fields = dict(_CONVEX, side=side, support_surface=_CONVEX_SUPPORT[side])
    system = RollingSystem(f"egg_on_egg_{side}", **fields)
    values = dict(m="1.3", g="9.81")
    result = kane_compare(system, system.model(), values)
    assert result.points == 4 and result.agrees, result
    assert kane_covers(system)
    other_axis = _CONVEX["surface"].replace("x3**2/(1/5)", "x3**2/(1/6)")
    for wrong in ({"centre_of_mass": ("0.05", "-0.04", "0.11")}, {"surface": other_axis}):
        control = RollingSystem(f"egg_on_egg_{side}_wrong", **{**fields, **wrong})
        refuted = kane_compare(system, control.model(), values)
        worst = max(refuted.max_acceleration_error, refuted.max_normal_rate_error)
        assert worst > 1e6 * refuted.tolerance, (wrong, refuted)


@pytest.mark.slow
@pytest.mark.parametrize("case", list(_FIELDS))
def test_kane_agrees_with_a_convex_body_on_a_support_with_each_field(case):
    """The convex body on the ellipsoid with a potential V(p, e1, e2, e3), rubber contact,
    K(t) or I(t) (Kane: the potential's loads on the angles and the contact point, (omega,
    grad F) = 0 a seventh constraint, real rotors and a tensor of Kane's time): omega', p'
    and r' agree at 40 digits at T0; the model with the field wrong (twice the potential,
    rolling, K or I frozen at T0) is refuted by the same comparison."""
    fields, wrong = _FIELDS[case]
    base = dict(_CONVEX, support_surface=_CONVEX_SUPPORT["outside"])
    name = "egg_field_" + {"K(t)": "kt", "I(t)": "it"}.get(case, case)
    system = RollingSystem(name, **{**base, **fields})
    values = {k: v for k, v in dict(m="1.3", g="9.81", k="0.37").items()
              if k in system.parameter_names}  # fmt: skip
    result = kane_compare(system, system.model(), values)
    assert result.points == 4 and result.agrees, result
    control = RollingSystem(name + "_wrong", **{**base, **wrong})
    refuted = kane_compare(system, control.model(), values)
    assert refuted.max_acceleration_error > 1e6 * refuted.tolerance, refuted
