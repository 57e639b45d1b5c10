"""A convex body rolling along the fixed line alpha of a plane ((omega, alpha) = 0, the
constraint of BKM12-57, Veselov's system): the convex-body route with the line against the
spherical body's (a sphere written as a surface; the body-frame engine stage with the
line's reaction against the momentum route's), and against Kane's method."""

from __future__ import annotations

import pytest
import sympy as sp
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.kane_rolling import kane_compare

R = sp.Rational
VALUES = {"m": R(13, 10), "g": R(981, 100)}
CENTRE = ("1/10", "-1/20", "2/25")
COMMON = dict(inertia=("0.31", "0.43", "0.57"), gravity="g", centre_of_mass=CENTRE)
#: A point: the normal gamma (body axes), the line alpha orthogonal to it.
GAMMA = sp.Matrix([R(2, 7), R(3, 7), R(6, 7)])
ALPHA = sp.Matrix([R(3, 7), R(-6, 7), R(2, 7)])


def _rates(model, point: dict) -> dict:
    """The state's rates at the point (groups by name), exact through the auxiliaries."""
    names = {x.name: x for x in model.state}
    values = {names[f"{g}{i + 1}"]: v[i] for g, v in point.items() for i in range(3)
              if f"{g}1" in names}  # fmt: skip
    values.update({s: VALUES[s.name] for s in model.params})
    for symbol, expr in model.aux:
        values[symbol] = expr.xreplace(values)
    pairs = zip(model.state, model.rhs, strict=True)
    return {x.name: rhs.xreplace(values) for x, rhs in pairs}


def _omega_rate(sphere, point: dict) -> sp.Matrix:
    """omega' of the spherical route (state M): the chain rule through its omega(M, gamma)."""
    names = {x.name: x for x in sphere.state}
    values = {names[f"{g}{i + 1}"]: v[i] for g, v in point.items() for i in range(3)}
    omega = sphere.expand_aux(sphere.omega).xreplace({s: VALUES[s.name] for s in sphere.params})
    rates = _rates(sphere, point)
    return sp.Matrix([sum((sp.diff(w, x).xreplace(values) * rates[x.name] for x in sphere.state),
                          sp.S.Zero) for w in omega])  # fmt: skip


@pytest.mark.parametrize("plane", ["fixed", "turntable"])
@pytest.mark.parametrize("agrees", [True, False])
def test_a_sphere_written_as_a_surface_rolls_along_the_line_as_the_spherical_body(agrees, plane):
    """The sphere |x - c0|^2 = b^2 (the centre of mass off the centre) as a convex body
    along the line alpha on a fixed plane, and on a turntable (at Omega = 3/7: the line it
    carries, the contact's place rho horizontal): omega' (body axes) and r' = -b gamma' equal
    the spherical body's along the same line exactly at a point with (omega, alpha) = 0 (the
    body-frame stage against the momentum route: the frame's rates, the line's reaction and
    the turntable's no-slip derived twice); the control is the convex body rolling without
    the line (refuted by the same comparison)."""
    b = R(7, 10)
    surface = " + ".join(f"x{i + 1}**2" for i in range(3)) + f" - ({b})**2"
    contact = "line" if agrees else "rolling"
    turning = dict(support="rotating_plane", rotation_rate="3/7") if plane == "turntable" else {}
    convex = RollingSystem("line_sphere_surface_" + contact, surface=surface, contact=contact,
                           **COMMON, **turning).model()  # fmt: skip
    sphere = RollingSystem("line_sphere", radius="7/10", contact="line", **COMMON,
                           **turning).model()  # fmt: skip
    a = sp.Matrix([sp.Rational(c) for c in CENTRE])
    w = sp.Matrix([R(3, 10), R(-7, 10), R(11, 10)])
    w = w - ALPHA * ALPHA.dot(w)  # (omega, alpha) = 0
    beta = GAMMA.cross(ALPHA)
    frame = {"alpha": ALPHA, "beta": beta}
    if turning:  # the contact's place from the axis: horizontal
        seed = sp.Matrix([R(5, 7), R(-3, 11), R(2, 13)])
        frame["rho"] = seed - GAMMA * GAMMA.dot(seed)
    ours = _rates(convex, {"omega": w, "r": -a - b * GAMMA, **frame})
    M = sp.Matrix(sphere.group("M"))
    omega_of_M = sphere.expand_aux(sphere.omega).xreplace(
        {**{s: VALUES[s.name] for s in sphere.params},
         **{x: v[i] for g, v in (("gamma", GAMMA), *frame.items())
            for i, x in enumerate(sphere.group(g))}}
    )  # fmt: skip
    M_value = M.xreplace(sp.solve(list(omega_of_M - w), list(M), dict=True)[0])
    point = {"M": M_value, "gamma": GAMMA, **frame}
    theirs_omega = _omega_rate(sphere, point)
    theirs = _rates(sphere, point)
    ours_omega = sp.Matrix([ours[f"omega{i}"] for i in (1, 2, 3)])
    assert (sp.simplify(ours_omega - theirs_omega) == sp.zeros(3, 1)) is agrees
    r_rate = sp.Matrix([ours[f"r{i}"] for i in (1, 2, 3)])
    gamma_rate = sp.Matrix([theirs[f"gamma{i}"] for i in (1, 2, 3)])
    assert sp.simplify(r_rate + b * gamma_rate) == sp.zeros(3, 1)  # kinematics: either way


@pytest.mark.slow
@pytest.mark.parametrize(
    "surface",
    ["x1**2/(1/4) + x2**2/(1/9) + x3**2/(1/5) - 1",
     "x1**4 + x2**2/(1/9) + x3**2/(1/5) + x1**2 - 1"],
    ids=["ellipsoid", "quartic"],
)  # fmt: skip
def test_kane_agrees_with_a_convex_body_along_a_line(surface):
    """An ellipsoid (Kane with the contact in closed form) and a quartic (the contact point
    as coordinates) along the fixed line N.x: Kane's own constraint (omega, N.x) = 0 with
    omega's first space component dependent; omega' agrees at 40 digits; the body rolling
    without the line is refuted by the same comparison; the shipped (omega, alpha) is the
    constraint."""
    fields = dict(COMMON, surface=surface, centre_of_mass=("0.05", "-0.04", "0.06"))
    system = RollingSystem("egg_line", contact="line", **fields)
    model = system.model()
    assert "(omega,alpha)" in dict(model.integrals)
    result = kane_compare(system, model, {"m": "1.3", "g": "9.81"})
    assert result.points == 4 and result.agrees, result
    free = RollingSystem("egg_free", **fields).model()
    control = kane_compare(system, free, {"m": "1.3", "g": "9.81"})
    assert control.max_acceleration_error > 1e6 * control.tolerance


def test_a_line_is_refused_for_a_convex_body_on_a_sphere():
    """Along a line: on a plane only (one line, before any work; a turntable's line:
    ``test_turning_line.py``)."""
    with pytest.raises(UserInputError, match="along a line") as info:
        RollingSystem("bad", surface="x1**2 + x2**2 + x3**2 - 1", inertia=(1, 2, 3),
                      contact="line", support="sphere", support_radius=3)  # fmt: skip
    assert "\n" not in str(info.value)
