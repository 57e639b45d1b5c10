"""Convex bodies whose contact point is implicit against Kane's method (issue 24).

A body ``f(r) = 0`` that is not a quadric on a plane (fixed, turning, shaken), and any
convex body on a fixed sphere, is set up again by :mod:`chaplygin.verify.kane_implicit`:
``KanesMethod`` with the contact point ``r`` as coordinates, the holonomic conditions
``(grad f(r), t_i) = 0`` (``t_i`` the support's tangents) differentiated by sympy as
velocity constraints beside no slip, a potential as ``-dV/dq`` of the coordinates. The
model's ``omega'``, ``r'``, the carried vectors' rates and its momentum about the contact
agree at 40 digits; the controls — the model of another surface, Kane on a sphere of
another radius, the model with its contact rate ``r'`` reversed — are refuted by the same
comparison.
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys

import pytest
import sympy as sp
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.kane_rolling import kane_compare

#: A convex quartic (not a quadric): its contact point has no closed form.
QUARTIC = "x1**4 + x2**4 + x3**4 + x1**2/a1**2 + 2*x2**2/a2**2 + 3*x3**2/a3**2 - 1"
#: The control's surface: the quartic with another x3**4 term.
OTHER_QUARTIC = QUARTIC.replace("x3**4", "3*x3**4")
ELLIPSOID = "x1**2/a1**2 + x2**2/a2**2 + x3**2/a3**2 - 1"
VALUES = dict(
    m="1.3", I1="0.31", I2="0.43", I3="0.57", a1="0.9", a2="0.7", a3="0.5", g="9.81",
    R="2.3", c1="0.11", c3="0.07", W="1.7", e="0.03", w="1.1", V1="0.8", V2="-0.6",
    k="0.37", K3="0.23",
)  # fmt: skip
BODY = dict(inertia=("I1", "I2", "I3"), positive=("a1", "a2", "a3"))


def _compare(system: RollingSystem, model=None, **values):
    values = {k: v for k, v in {**VALUES, **values}.items() if k in system.parameter_names}
    return kane_compare(system, model or system.model(), values)


def _reversed_contact_rate(model):
    """The model with ``r' -> -r'`` (its auxiliary ``rdot``): a wrong contact kinematics."""
    aux = tuple((s, -e if s.name.startswith("rdot") else e) for s, e in model.aux)
    return dataclasses.replace(model, aux=aux)


def _refuted(result) -> bool:
    worst = max(
        result.max_acceleration_error, result.max_momentum_error, result.max_normal_rate_error
    )
    return worst > 1e6 * result.tolerance


@pytest.mark.slow
def test_kane_agrees_with_a_quartic_body_on_the_plane_and_refutes_another_surface():
    """A quartic under gravity with an offset centre, a rotor and a potential of the
    normal on the fixed plane: omega', r' and the momentum agree. Controls: the model of
    another quartic (compared at the contact points of Kane's), and the model whose r' is
    reversed."""
    fields = dict(
        gravity="g", centre_of_mass=("c1", 0, "c3"), gyrostat=(0, 0, "K3"),
        potential="k*gamma1*gamma2", **BODY,
    )  # fmt: skip
    system = RollingSystem("quartic_on_plane", surface=QUARTIC, **fields)
    model = system.model()
    result = _compare(system, model)
    assert result.points == 4 and result.agrees, result
    other = RollingSystem("quartic_on_plane", surface=OTHER_QUARTIC, **fields).model()
    control = _compare(system, other)
    assert _refuted(control), control
    assert control.max_acceleration_error > 1e6 * control.tolerance
    reversed_rate = _compare(system, _reversed_contact_rate(model))
    assert reversed_rate.max_normal_rate_error > 1e6 * reversed_rate.tolerance  # r' itself


@pytest.mark.slow
@pytest.mark.parametrize(
    "fields, other",
    [
        (
            dict(support="rotating_plane", rotation_rate="W*(1 + e*sin(w*t))", contact="rubber"),
            dict(support="rotating_plane", rotation_rate="-W*(1 + e*sin(w*t))", contact="rubber"),
        ),
        (
            dict(support="moving_plane", plane_velocity=("V1*sin(w*t)", "V2*t")),
            dict(support="moving_plane", plane_velocity=("-V1*sin(w*t)", "V2*t")),
        ),
    ],
    ids=["turntable-rubber", "shaken-rolling"],
)
def test_kane_agrees_with_a_quartic_body_on_a_moving_plane(fields, other):
    """A heavy quartic on a turntable at W (1 + e sin wt), rubber (rho' compared too), and
    on a plane shaken at (V1 sin wt, V2 t), rolling (alpha', beta'). Control: the model of
    the plane turning the other way, or shaken along -N.x, is refuted."""
    system = RollingSystem("quartic_moving", surface=QUARTIC, gravity="g", **BODY, **fields)
    result = _compare(system)
    assert result.points == 4 and result.agrees, result
    wrong = RollingSystem("quartic_moving", surface=QUARTIC, gravity="g", **BODY, **other)
    control = _compare(system, wrong.model())
    assert control.max_acceleration_error > 1e6 * control.tolerance


@pytest.mark.slow
@pytest.mark.parametrize("contact", ["rolling", "rubber"])
def test_kane_agrees_with_a_heavy_ellipsoid_outside_a_sphere(contact):
    """A heavy ellipsoid outside a fixed sphere (the vertical zeta a state; Kane's body
    placed away from the pole), rolling and rubber. Control: Kane on a sphere of radius
    11 R/10 refutes the model of radius R."""
    fields = dict(surface=ELLIPSOID, gravity="g", support="sphere", contact=contact, **BODY)
    system = RollingSystem("egg_on_sphere", support_radius="R", **fields)
    model = system.model()
    result = _compare(system, model)
    assert result.points == 4 and result.agrees, result
    wider = RollingSystem("egg_on_sphere", support_radius="11*R/10", **fields)
    control = _compare(wider, model)
    assert _refuted(control), control


@pytest.mark.slow
def test_kane_agrees_with_a_quartic_inside_a_sphere_and_refutes_a_reversed_contact_rate():
    """A heavy quartic with an offset centre inside a fixed sphere of radius 4.7 (larger
    than the body's radii of curvature, about 2.8 at most: at R = 2.3 the contact would be
    nearly degenerate, the agreement 4e-34 at 40 digits and 4e-54 at 60). Controls: the
    model with r' reversed; the model of the body outside the sphere."""
    fields = dict(
        surface=QUARTIC, gravity="g", support="sphere", support_radius="R",
        centre_of_mass=("c1", 0, "c3"), **BODY,
    )  # fmt: skip
    system = RollingSystem("quartic_in_sphere", side="inside", **fields)
    model = system.model()
    result = _compare(system, model, R="4.7")
    assert result.points == 4 and result.agrees, result
    assert _refuted(_compare(system, _reversed_contact_rate(model), R="4.7"))
    outside = RollingSystem("quartic_in_sphere", side="outside", **fields).model()
    assert _refuted(_compare(system, outside, R="4.7"))


@pytest.mark.slow
@pytest.mark.parametrize("support", ["plane", "sphere"])
def test_kane_agrees_with_a_quartic_whose_inertia_and_rotor_are_prescribed(support):
    """I(t) with a product of inertia and K(t) (a driven rotor), an offset centre under
    gravity, on the plane and outside a sphere (Kane: sympy's rigid body with dI/dt, real
    rotors spun by their motors). Control: the model of the constant K(T0) — the same
    momentum at the comparison time, without K' — is refuted."""
    from chaplygin.verify.kane_rolling import T0

    fields = dict(
        surface=QUARTIC, gravity="g", centre_of_mass=("c1", 0, "c3"), support=support,
        inertia=[["I1 + e*cos(w*t)", "e*sin(w*t)/3", 0], ["e*sin(w*t)/3", "I2", 0], [0, 0, "I3"]],
        positive=BODY["positive"],
    )  # fmt: skip
    if support == "sphere":
        fields["support_radius"] = "R"
    system = RollingSystem("quartic_timed", gyrostat=("k*cos(w*t)", 0, "K3"), **fields)
    result = _compare(system)
    assert result.points == 4 and result.agrees, result
    frozen = RollingSystem("quartic_timed", gyrostat=(f"k*cos(w*{T0})", 0, "K3"), **fields)
    control = _compare(system, frozen.model())
    assert control.max_acceleration_error > 1e6 * control.tolerance


@pytest.mark.slow
def test_kane_agrees_with_a_quartic_under_a_potential_of_the_vertical_on_a_sphere():
    """A quartic with a rotor outside a sphere under V = k zeta3 gamma1 + k gamma2^2 (the
    potential's loads in Kane: -dV/dq of the Euler angles and the contact's place)."""
    system = RollingSystem(
        "quartic_potential_sphere", surface=QUARTIC, support="sphere", support_radius="R",
        gyrostat=(0, 0, "K3"), potential="k*zeta3*gamma1 + k*gamma2**2", **BODY,
    )  # fmt: skip
    result = _compare(system)
    assert result.points == 4 and result.agrees, result


def test_kane_covers_a_convex_body_where_the_comparison_places_it():
    """The :kane claim exists for a non-quadric body on a plane and for a body on a
    sphere; not where no ray from the centre of mass meets the surface (at the claim's
    generic values, f > 0 everywhere)."""
    from chaplygin.verify.user_claims import kane_covers

    assert kane_covers(RollingSystem("quartic", surface=QUARTIC, **BODY))
    on_sphere = dict(surface=ELLIPSOID, support="sphere", support_radius="R", **BODY)
    assert kane_covers(RollingSystem("egg_on_sphere", **on_sphere))
    surface = "x1**4 + x2**4 + x3**4 + c*x1**2 + c"  # c = 11/8 there: f > 0
    empty = RollingSystem("empty", surface=surface, inertia=(1, 2, 3))
    assert not kane_covers(empty)


def test_verify_system_gives_a_quartic_body_its_kane_claim(tmp_path):
    """``chaplygin verify --system`` on a file describing a heavy quartic off centre on the
    plane: the claim ``:kane`` is made and gets ``numeric`` (40-digit agreement)."""
    path = tmp_path / "quartic.toml"
    path.write_text(
        '[system]\nname = "quartic_body"\ninertia = ["I1", "I2", "I3"]\n'
        f'surface = "{QUARTIC}"\npositive = ["a1", "a2", "a3"]\ngravity = "g"\n'
        'centre_of_mass = ["c1", 0, "c3"]\n\n[parameters]\nm = 1.3\nI1 = 0.31\nI2 = 0.43\n'
        "I3 = 0.57\na1 = 0.9\na2 = 0.7\na3 = 0.5\ng = 9.81\nc1 = 0.11\nc3 = 0.07\n"
    )
    env = {"CHAPLYGIN_CACHE_DIR": str(tmp_path / "cache"), "PATH": "/usr/bin:/bin"}
    out = subprocess.run(
        [sys.executable, "-m", "chaplygin.verify.cli", "verify", "--system", str(path),
         "--jobs", "1", "--json", "--claims", "quartic_body:kane"],
        capture_output=True, text=True, env=env, timeout=600,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    verdicts = {v["id"]: v["verdict"] for v in json.loads(out.stdout)}
    assert verdicts == {"quartic_body:kane": "numeric"}


def test_the_contact_point_lies_on_the_surface_along_its_ray():
    """:func:`contact_on_ray`: ``f`` vanishes at the point (to its digits), the point is
    along the direction from the centre of mass (inside: ``f(0) < 0``), and halfway
    ``f < 0`` (the smallest positive root); with the centre of mass outside the body the
    ray starts at :func:`interior_point` instead (``f < 0`` there)."""
    import mpmath
    from chaplygin.derive.vectors import vector
    from chaplygin.verify.kane_implicit import contact_on_ray, interior_point

    r = vector("r", real=True)
    a = {f"a{i}": sp.Rational(VALUES[f"a{i}"]) for i in (1, 2, 3)}
    text = QUARTIC.replace("x", "r")
    f = sp.sympify(text, locals={**a, **{f"r{i}": r[i - 1] for i in (1, 2, 3)}})
    d = (sp.Rational(2, 7), sp.Rational(-3, 7), sp.Rational(6, 7))
    with mpmath.workdps(60):
        at = lambda p: {r[i]: sp.Float(p[i], 60) for i in range(3)}  # noqa: E731
        point = contact_on_ray(f, d)
        assert abs(f.xreplace(at(point))) < 1e-50
        s = point[2] * 7 / 6
        assert all(abs(point[i] - s * mpmath.mpf(sp.Float(d[i], 60))) < 1e-50 for i in range(3))
        assert f.xreplace(at([x / 2 for x in point])) < 0
        shifted = f.xreplace({r[0]: r[0] + 2})  # the centre of mass at x1 = -2: outside
        assert shifted.xreplace(dict.fromkeys(r, 0)) > 0
        inside = interior_point(shifted)
        assert shifted.xreplace(at(inside)) < 0
        point = contact_on_ray(shifted, d)
        assert abs(shifted.xreplace(at(point))) < 1e-50
