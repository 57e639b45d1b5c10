"""The contact trace of a convex body on a fixed sphere (the effect contact_point there): the
fixed frame alpha, beta, zeta joins the body-frame stage's state (omega, r) and the contact
point is +-R ((n, alpha), (n, beta), (n, zeta)) from the sphere's centre, n = -grad f(r)/|grad
f(r)| the sphere's normal at the contact in body axes.

The independent route is the convex body on the support surface F = |p|^2 - R^2
(derive/body_on_support.py), whose state is the contact point p itself in the fixed frame,
the body axes e1, e2, e3 in it and omega in space axes: with the body axes equal to the
fixed ones at t = 0 both start from the same numbers, and the traces are compared."""

from __future__ import annotations

import chaplygin
import numpy as np
import pytest
import sympy as sp
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.identity import Domain, decide, lie_derivative

R, MASS, G = 2.9, 1.3, 9.81
AXES = np.array([0.31, 0.27, 0.19])  # the ellipsoid's semi-axes (its centre off the mass's)
CENTRE = (0.02, -0.015, 0.03)  # the centre of mass from the ellipsoid's centre
SURFACE = " + ".join(f"(x{i + 1} + ({c}))**2/{float(a * a)!r}" for i, (a, c) in
                     enumerate(zip(AXES, CENTRE, strict=True))) + " - 1"  # fmt: skip
INERTIA = [["I1", "I12", 0], ["I12", "I2", 0], [0, 0, "I3"]]
VALUES = {"m": MASS, "I1": 0.021, "I2": 0.026, "I12": 0.0013, "I3": 0.031, "R": R, "g": G}


def _system(name: str, side: str, field: bool, **support) -> RollingSystem:
    extra = {"gravity": "g"} if field else {}
    return RollingSystem(name, inertia=INERTIA, surface=SURFACE, side=side, **support, **extra)


def _group(run, name: str) -> np.ndarray:
    names = list(map(str, run.state_names))
    return np.asarray(run.y, float)[[names.index(f"{name}{i}") for i in (1, 2, 3)], :]


def _contact(outward: np.ndarray) -> np.ndarray:
    """The point r (from the centre of mass) where the ellipsoid's outward normal is along
    ``outward``."""
    a2 = AXES**2
    x = a2 * outward / np.sqrt((a2 * outward**2).sum())  # grad f ~ x/a^2 ~ outward
    return x - np.array(CENTRE)


def _normal(r: np.ndarray) -> np.ndarray:
    """The sphere's normal at the contact, body axes: -grad f(r)/|grad f(r)|."""
    grad = (r + np.array(CENTRE)[:, None]) / (AXES**2)[:, None]
    return -grad / np.linalg.norm(grad, axis=0)


@pytest.mark.slow  # the support-surface route's first derivation: about 40 s a side
@pytest.mark.parametrize(("side", "field"), [("outside", False), ("inside", True)])
def test_the_trace_on_a_sphere_is_the_support_surface_body_s_contact_point(side, field):
    """A triaxial ellipsoid (a product of inertia, the centre of mass off its centre) on
    the outside of a sphere of radius 2.9 without a field, and inside it under gravity:
    the trace sign(side) R ((n, alpha), (n, beta), (n, zeta)) of the body-frame route
    equals the support-surface route's state p at 7 times over 2 time units within 1e3
    rtol R (the global error of two tolerance-controlled runs of about 10^2 steps,
    relative to the sphere); omega in space axes and r agree to the same bound. The trace
    scaled by R + 0.3 (the contact taken on the sphere through the body's centre) is
    refuted by the same comparison."""
    sign = 1 if side == "outside" else -1
    sphere = _system(f"ctrace_{side}", side, field, support="sphere", support_radius="R")
    surface = _system(f"ctrace_surface_{side}", side, field, support="surface",
                      support_surface=f"p1**2 + p2**2 + p3**2 - {R}**2")  # fmt: skip
    chaplygin.register_system(sphere)
    chaplygin.register_system(surface)
    n0 = np.array([0.3, -0.2, 0.9]) / np.linalg.norm([0.3, -0.2, 0.9])  # the sphere's normal
    r0 = _contact(-n0)  # the body's outward normal is -n
    w0 = np.array([0.7, -1.1, 0.4])  # body axes = fixed axes at t = 0
    T, rtol = 2.0, 1e-12
    options = dict(method="DOP853", backend="numpy", rtol=rtol, atol=rtol,
                   t_eval=list(np.linspace(0, T, 7)))  # fmt: skip
    start = {"omega": tuple(w0), "r": tuple(r0), "zeta": (0.0, 0.0, 1.0),
             "alpha": (1.0, 0.0, 0.0), "beta": (0.0, 1.0, 0.0)}  # fmt: skip
    values = {k: v for k, v in VALUES.items() if field or k != "g"}
    a = chaplygin.integrate(sphere.name, start, (0, T), values, effects="contact_point",
                            **options)  # fmt: skip
    frame = {f"e{j}": tuple(np.eye(3)[:, j - 1]) for j in (1, 2, 3)}
    c = chaplygin.integrate(
        surface.name, {"omega": tuple(w0), "p": tuple(sign * R * n0), "r": tuple(r0), **frame},
        (0, T), {k: v for k, v in values.items() if k != "R"}, **options,
    )  # fmt: skip
    n = _normal(_group(a, "r"))
    unit = np.array([(n * _group(a, axis)).sum(axis=0) for axis in ("alpha", "beta", "zeta")])
    p = _group(c, "p")
    assert np.abs(p[:, -1] - p[:, 0]).max() > 0.2  # the contact moved (0.28 outside)
    bound = 1e3 * rtol * R
    assert np.abs(sign * R * unit - p).max() <= bound
    assert np.abs(sign * (R + 0.3) * unit - p).max() > 1e3 * bound
    assert np.abs(_group(a, "r") - _group(c, "r")).max() <= bound
    axes = [_group(a, X) for X in ("alpha", "beta", "zeta")]  # space components of omega
    w_space = np.array([(_group(a, "omega") * X).sum(axis=0) for X in axes])
    assert np.abs(w_space - _group(c, "omega")).max() <= bound * np.abs(w0).max()


def test_the_frame_relations_are_proved_and_the_normal_s_refuted():
    """A convex body on a sphere with the trace ships the fixed frame's relations (alpha,
    beta, zeta: (zeta, alpha), not the plane's (alpha, gamma)): each is proved an integral
    by the verifier; (alpha, grad f(r)), which is constant on a fixed plane, is refuted by
    the same machinery (the sphere's normal turns)."""
    model = _system("ctrace_free", "outside", False, support="sphere",
                    support_radius="R").model(["contact_point"])  # fmt: skip
    names = dict(model.integrals)
    for expected in ("(zeta,alpha)", "(zeta,beta)", "(zeta,zeta)", "(alpha,beta)", "f"):
        assert expected in names
    assert "(alpha,gamma)" not in names
    domain = Domain(model)
    for name, value in model.integrals:
        if name.startswith("(") or name == "f":
            assert decide([lie_derivative(value, model)], domain).verdict == "proved", name
    r, alpha = sp.Matrix(model.group("r")), sp.Matrix(model.group("alpha"))
    x = sp.symbols("x1:4")
    f = sp.sympify(SURFACE, locals={f"x{i + 1}": x[i] for i in range(3)})
    grad = sp.Matrix([sp.diff(f, v).subs(dict(zip(x, r, strict=True))) for v in x])
    assert decide([lie_derivative(grad.dot(alpha), model)], domain).verdict == "refuted"


def test_zeta_must_be_given_and_the_frame_completes_about_omega():
    """A convex body has no unit normal in its state to start the vertical from: an omitted
    zeta is refused in one line; given, alpha and beta complete the frame about omega
    (orthonormal with zeta to a few double epsilons)."""
    free = _system("ctrace_nofield", "outside", False, support="sphere", support_radius="R")
    chaplygin.register_system(free)
    r0 = _contact(-np.array([0.0, 0.0, 1.0]))
    values = {k: v for k, v in VALUES.items() if k != "g"}
    with pytest.raises(UserInputError, match="zeta"):
        chaplygin.integrate(free.name, {"omega": (0.3, -0.2, 0.5), "r": tuple(r0)}, (0, 0.5),
                            values, effects="contact_point")  # fmt: skip
    zeta = (2 / 7, -3 / 7, 6 / 7)
    run = chaplygin.integrate(free.name, {"omega": (0.3, -0.2, 0.5), "r": tuple(r0),
                                          "zeta": zeta}, (0, 0.5), values,
                              effects="contact_point", method="DOP853",
                              backend="numpy")  # fmt: skip
    eps = np.finfo(float).eps
    z, alpha, beta = (_group(run, X)[:, 0] for X in ("zeta", "alpha", "beta"))
    assert np.abs(z - np.array(zeta)).max() <= 4 * eps
    assert abs(alpha @ z) <= 8 * eps and abs(beta @ z) <= 8 * eps
    assert abs(np.cross(alpha, beta) @ z - 1) <= 8 * eps


def test_the_bowl_example_draws_its_trace_and_its_claims_are_decided(tmp_path):
    """examples/systems/ellipsoid_in_bowl.toml: its scene, shortened to 2 time units, adds
    the effect for outputs.contact_trace, writes the figure and keeps the frame's relations
    and the level f to the run's tolerance (1e3 rtol, the drift evidence); the file's claims
    are decided by the verifier: (zeta, zeta) proved, the control (n, zeta) refuted with a
    witness."""
    import json
    from pathlib import Path

    from chaplygin.verify.cli import main
    from chaplygin.verify.user_claims import claims_of_file
    from chaplygin.verify.verdict import check_claim

    example = Path(__file__).parents[2] / "examples" / "systems" / "ellipsoid_in_bowl.toml"
    out = tmp_path / "out"
    assert main(["run", str(example), "--out", str(out), "--set", "run.t_end=2"]) == 0
    assert (out / "contact_trace.png").stat().st_size > 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["effects"] == ["contact_point"]
    drift = summary["run"]["drift"] if "run" in summary else summary["drift"]
    for name in ("(zeta,alpha)", "(alpha,beta)", "(zeta,zeta)", "f"):
        assert abs(float(drift[name])) < 1e3 * 1e-11, name
    claims = {c.id.split(":")[-1]: c for c in claims_of_file(example)}
    vertical = check_claim(claims["ELLIPSOID-IN-BOWL-vertical"])
    assert (vertical.verdict, vertical.ok) == ("proved", True)
    control = check_claim(claims["ELLIPSOID-IN-BOWL-normal/control"])
    assert (control.verdict, control.ok) == ("refuted", True) and control.witness
