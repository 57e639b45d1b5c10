"""Rolling along a line a turntable carries (``contact="line"`` on ``support=
"rotating_plane"``): the line's frame turns with the plane, ``alpha' = alpha x omega + Omega
gamma x alpha`` (likewise ``beta``), and the body does not spin about the line, ``(omega,
alpha) = 0``. Kane's method with its own constraint (the line ``N.x + tan(theta) N.y`` with
``theta' = Omega``, :func:`chaplygin.verify.kane_common.support_line`) agrees with the derived
equations for a spherical body and an ellipsoid, at a constant rate and at ``Omega(t)``; Kane's
line held fixed in space instead (the control) is refuted by the same comparison."""

from __future__ import annotations

import json

import pytest
import sympy as sp
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.identity import Domain, decide, lie_derivative
from chaplygin.verify.kane_rolling import kane_compare

R = sp.Rational
BODY = dict(inertia=("0.31", "0.43", "0.57"), mass="1.3", gravity="g", support="rotating_plane",
            contact="line")  # fmt: skip
SPHERE = dict(radius="0.7", centre_of_mass=("0.1", "-0.05", "0.08"))
ELLIPSOID = dict(surface="x1**2/(9/10)**2 + x2**2/(7/10)**2 + x3**2/(1/2)**2 - 1",
                 centre_of_mass=("1/13", 0, "1/10"))  # fmt: skip
QUARTIC = dict(surface="x1**4 + x2**2/(1/9) + x3**2/(1/5) + x1**2 - 1",
               centre_of_mass=("0.05", "-0.04", "0.06"))  # Kane: the contact as coordinates
RATES = {"constant": "W", "prescribed": "W*(1 + e*sin(w*t))"}
VALUES = {"g": "9.81", "W": "0.37", "e": "0.3", "w": "1.7"}


def _values(model) -> dict:
    return {s.name: VALUES[s.name] for s in model.params}


@pytest.mark.parametrize("body", [SPHERE, ELLIPSOID], ids=["sphere", "ellipsoid"])
def test_the_carried_frame_turns_with_the_plane_and_the_trace_is_not_taken(body):
    """The frame's rates are the turning ones (at an exact point: alpha x omega + Omega gamma
    x alpha, with the plane's normal gamma), the constraint and the frame's relations are
    shipped, the energy is not (the plane does work), J for the spherical body only (its
    relation (omega, alpha) = 0 is on the momentum; a convex body's omega is state), and the
    contact trace is not offered (its space-fixed axes would be other vectors than the
    carried alpha, beta)."""
    system = RollingSystem("turning_line", rotation_rate="W", **BODY, **body)
    assert system.effects_taken == ()
    model = system.model()
    names = {x.name: x for x in model.state}
    shipped = {n for n, _ in (*model.integrals, *model.invariant_relations)}
    assert {"(omega,alpha)", "(alpha,beta)", "(rho,gamma)"} <= shipped and "H" not in shipped
    assert ("J" in shipped) is (body is SPHERE)  # a convex body's J: not on a relation
    omega = sp.Matrix([R(3, 10), R(-7, 10), R(11, 10)])
    gamma = sp.Matrix([R(2, 7), R(3, 7), R(6, 7)])
    alpha = sp.Matrix([R(3, 7), R(-6, 7), R(2, 7)])
    beta = gamma.cross(alpha)
    W = next(s for s in model.params if s.name == "W")
    if "r1" in names:  # the convex body: omega is state, the normal n(r) at the contact
        normal = model.details.equations.normal
        r = sp.Matrix(model.group("r"))
        contact = sp.Matrix([R(2, 5), R(1, 3), R(-1, 4)])  # (not on the surface: the rate's
        gamma = normal.xreplace(dict(zip(r, contact, strict=True)))  # form holds anywhere)
        point = {**dict(zip(model.group("omega"), omega, strict=True)),
                 **dict(zip(r, contact, strict=True))}  # fmt: skip
    else:  # the spherical body: omega(M) is an auxiliary; the rate is written in omega
        point = dict(zip(sp.symbols("omega1:4", real=True), omega, strict=True))
        point.update(zip(model.group("gamma"), gamma, strict=True))
    point.update(zip(model.group("alpha"), alpha, strict=True))
    point.update(zip(model.group("beta"), beta, strict=True))
    rates = dict(zip(model.state, model.rhs, strict=True))
    for name, X in (("alpha", alpha), ("beta", beta)):
        ours = sp.Matrix([rates[s] for s in model.group(name)]).xreplace(point)
        expected = X.cross(omega) + W * gamma.cross(X)
        assert (ours - expected).applyfunc(sp.simplify) == sp.zeros(3, 1), name


@pytest.mark.parametrize("off", [0, R(1, 5)], ids=["on_the_line", "off_it"])
def test_a_balls_turning_frame_energy_is_kept_where_it_does_not_spin_about_the_line(off):
    """J (shipped at a constant rate) has the rate 0 at an exact point of the phase space
    ((omega, alpha) = 0, the relation, solved for M3; rho horizontal): the line's reaction
    does no work in the turning frame there; the same point moved off the relation (M3 +
    1/5) changes J, the reason the relation is part of the phase space."""
    system = RollingSystem("turning_line_ball", rotation_rate="37/100", **BODY, **SPHERE)
    model = system.model()
    J = model.expand_aux(model.integral("J")).xreplace({s: R(VALUES[s.name]) for s in model.params})
    gamma = sp.Matrix([R(2, 7), R(3, 7), R(6, 7)])
    alpha = sp.Matrix([R(3, 7), R(-6, 7), R(2, 7)])
    seed = sp.Matrix([R(5, 7), R(-3, 11), R(2, 13)])
    point = {}
    for name, X in (("gamma", gamma), ("alpha", alpha), ("beta", gamma.cross(alpha)),
                    ("rho", seed - gamma * gamma.dot(seed))):  # fmt: skip
        point.update(zip(model.group(name), X, strict=True))
    M = model.group("M")
    point.update({M[0]: R(3, 10), M[1]: R(-7, 10)})
    relation = model.expand_aux(dict(model.invariant_relations)["(omega,alpha)"])
    relation = relation.xreplace({s: R(VALUES[s.name]) for s in model.params})
    point[M[2]] = sp.solve(relation.xreplace(point), M[2])[0] + off
    rhs = model.rhs_expanded.xreplace({s: R(VALUES[s.name]) for s in model.params})
    rate = sum((sp.diff(J, x).xreplace(point) * rhs[i].xreplace(point)
                for i, x in enumerate(model.state)), sp.S.Zero)  # fmt: skip
    assert (sp.simplify(rate) == 0) is (off == 0)


@pytest.mark.slow
def test_the_verifier_proves_what_a_balanced_ball_along_a_turntables_line_ships():
    """A balanced asymmetric ball along the line a turntable turning at 37/100 carries: the
    verifier proves every shipped integral (the area integral (M+K, gamma), the frame's
    relations, the constraint, (rho, gamma), (gamma, gamma) and J) and refutes (M+K, alpha),
    the momentum's projection on the line the reaction acts along. (With the centre of mass
    off on the axis of symmetry and gravity J was proved too, 53 s; a convex body's J holds on
    (omega, alpha) = 0 but off it the verifier refutes it, 17 min: not shipped.)"""
    model = RollingSystem("turning_line_balanced", rotation_rate="37/100", inertia=BODY["inertia"],
                          mass="1.3", radius="0.7", support="rotating_plane",
                          contact="line").model()  # fmt: skip
    names = [n for n, _ in model.integrals]
    assert {"(M+K,gamma)", "(omega,alpha)", "J"} <= set(names)
    for name, expr in model.integrals:
        assert decide([lie_derivative(expr, model)], Domain(model)).verdict == "proved", name
    M = sp.Matrix(model.group("M")) + model.details.gyrostatic_momentum
    control = M.dot(sp.Matrix(model.group("alpha")))
    assert decide([lie_derivative(control, model)], Domain(model)).verdict == "refuted"


@pytest.mark.slow
@pytest.mark.parametrize("rate", list(RATES), ids=list(RATES))
@pytest.mark.parametrize(
    "body", [SPHERE, ELLIPSOID, QUARTIC], ids=["sphere", "ellipsoid", "quartic"]
)
def test_kane_agrees_along_a_turntables_line_and_refutes_the_line_fixed_in_space(body, rate):
    """An offset centre of mass under gravity, a spherical body, an ellipsoid (Kane's
    contact in closed form) and a quartic (Kane's contact point as coordinates,
    :mod:`~chaplygin.verify.kane_implicit`): omega', the momentum about the contact and the
    rates of the normal (a convex body's r'), rho, alpha and beta agree with Kane at 40
    digits; Kane's line held fixed in space is refuted by the same comparison (omega' and the
    frame's rates)."""
    system = RollingSystem("turning_line", rotation_rate=RATES[rate], **BODY, **body)
    model = system.model()
    result = kane_compare(system, model, _values(model))
    assert result.points == 4 and result.agrees, result
    control = kane_compare(system, model, _values(model), line_carried=False)
    assert control.max_acceleration_error > 1e6 * control.tolerance
    assert control.max_normal_rate_error > 1e6 * control.tolerance


TURNING_LINE_FILE = """[system]
name = "ball_on_a_turntables_line"
inertia = ["0.31", "0.43", "0.57"]
centre_of_mass = ["0.1", "-0.05", "0.08"]
gravity = "g"
support = "rotating_plane"
rotation_rate = "W*(1 + e*sin(w*t))"
contact = "line"
"""


@pytest.mark.slow
def test_verify_system_gives_a_kane_claim_that_agrees(tmp_path, capsys, monkeypatch):
    """``chaplygin verify --system`` on a file with a ball along a turntable's line (Omega(t))
    makes the ``:kane`` claim and Kane agrees (a numeric verdict at 40 digits, exit 0)."""
    from chaplygin.verify.cli import main

    path = tmp_path / "turning_line.toml"
    path.write_text(TURNING_LINE_FILE)
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    args = ["verify", "--system", str(path), "--jobs", "1", "--json", "--claims", "*:kane"]
    assert main(args) == 0
    verdicts = {v["id"]: v["verdict"] for v in json.loads(capsys.readouterr().out)}
    assert verdicts == {"ball_on_a_turntables_line:kane": "numeric"}
