"""The contact trace of a body on a fixed sphere (the effect contact_point there): the fixed
frame alpha, beta, zeta joins the state and the contact point is +-R ((gamma, alpha),
(gamma, beta), (gamma, zeta)) from the sphere's centre.

The independent route is the ball on a support surface F = |p|^2 - R^2
(derive/ball_on_support.py), whose state is the contact point p itself in the fixed frame:
a homogeneous ball (an integrable motion, not chaotic) is integrated by both routes from the
same start and the traces compared."""

from __future__ import annotations

import chaplygin
import numpy as np
import pytest
import sympy as sp
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.identity import Domain, decide, lie_derivative

R, B, MASS, G, K = 2.9, 0.7, 1.3, 9.81, 0.4
COMMON = dict(inertia=(f"{K}*m*b**2",) * 3, gravity="g")


def _on_sphere(name: str, side: str) -> RollingSystem:
    return RollingSystem(name, support="sphere", support_radius="R", side=side, **COMMON)


def _group(run, name: str) -> np.ndarray:
    names = list(map(str, run.state_names))
    return np.asarray(run.y, float)[[names.index(f"{name}{i}") for i in (1, 2, 3)], :]


@pytest.mark.parametrize("side", ["outside", "inside"])
def test_the_trace_on_a_sphere_is_the_support_surface_ball_s_contact_point(side):
    """A heavy homogeneous ball (I = 2/5... here 0.4 m b^2) on the outside of a sphere of
    radius 2.9 and inside it: the trace sign(side) R ((gamma, alpha), (gamma, beta), (gamma,
    zeta)) of the sphere route equals the support surface route's state p at 7 times over
    3 time units (the contact moves by 0.8 inside, 3 outside) within 1e3 rtol R (the
    global error of a tolerance-controlled run of about 10^2 steps, both routes, relative
    to the sphere);
    the trace scaled by R + b (the centre's sphere: a plausible slip) is refuted by the same
    comparison."""
    sign = 1 if side == "outside" else -1
    sphere = _on_sphere(f"trace_ball_{side}", side)
    surface = RollingSystem(
        f"trace_ball_surface_{side}", support="surface", side=side,
        support_surface="p1**2 + p2**2 + p3**2 - R**2", **COMMON,
    )  # fmt: skip
    chaplygin.register_system(sphere)
    chaplygin.register_system(surface)
    n0 = np.array([0.3, -0.2, 0.9]) / np.linalg.norm([0.3, -0.2, 0.9])
    w0 = np.array([0.7, -1.1, 0.4])  # body = fixed axes at t = 0: omega the same in both
    I = K * MASS * B * B
    M0 = I * w0 + MASS * B * B * (w0 - n0 * (n0 @ w0))  # momentum about the contact point
    T, rtol = 3.0, 1e-12
    options = dict(method="DOP853", backend="numpy", rtol=rtol, atol=rtol,
                   t_eval=list(np.linspace(0, T, 7)))  # fmt: skip
    start = {"M": tuple(M0), "gamma": tuple(n0), "zeta": (0.0, 0.0, 1.0),
             "alpha": (1.0, 0.0, 0.0), "beta": (0.0, 1.0, 0.0)}  # fmt: skip
    a = chaplygin.integrate(sphere.name, start, (0, T), {"m": MASS, "b": B, "R": R, "g": G},
                            effects="contact_point", **options)  # fmt: skip
    c = chaplygin.integrate(surface.name, {"omega": tuple(w0), "p": tuple(sign * R * n0)},
                            (0, T), {"b": B, "g": G}, **options)  # fmt: skip
    gamma = _group(a, "gamma")
    frame = [_group(a, n) for n in ("alpha", "beta", "zeta")]
    unit = np.array([(gamma * axis).sum(axis=0) for axis in frame])
    p = _group(c, "p")
    assert np.abs(p[:, -1] - p[:, 0]).max() > 0.5  # the contact moved (0.8 to 3)
    bound = 1e3 * rtol * R
    assert np.abs(sign * R * unit - p).max() <= bound
    assert np.abs(sign * (R + B) * unit - p).max() > 1e3 * bound


def test_the_sphere_s_frame_relations_and_momentum_components_are_proved():
    """With the trace, a balanced ball on a sphere without a field ships the fixed frame's
    relations (alpha, beta, zeta: (zeta, alpha), not the turning normal's (gamma, alpha)),
    (gamma, gamma) and the components of M along the fixed axes (the reaction passes
    through the contact point, whose velocity is parallel to the centre's): each is
    proved an integral by the verifier; (gamma, alpha), which a plane would ship, is
    refuted by the same machinery."""
    model = RollingSystem("trace_ball_free", inertia=("I1", "I2", "I3"), support="sphere",
                          support_radius="R").model(["contact_point"])  # fmt: skip
    names = dict(model.integrals)
    for expected in ("(M,alpha)", "(M,beta)", "(M,zeta)", "(zeta,alpha)", "(zeta,beta)"):
        assert expected in names
    assert "(gamma,alpha)" not in names and "(gamma,beta)" not in names
    domain = Domain(model)
    for name, value in model.integrals:
        assert decide([lie_derivative(value, model)], domain).verdict == "proved", name
    gamma, alpha = sp.Matrix(model.group("gamma")), sp.Matrix(model.group("alpha"))
    assert decide([lie_derivative(gamma.dot(alpha), model)], domain).verdict == "refuted"


def test_zeta_starts_as_the_normal_without_a_field_and_must_be_given_with_one():
    """Without a field the vertical only orients the trace: omitted, zeta starts as the
    normal gamma (normalised) and alpha, beta complete the frame about M; with gravity the
    vertical is physics and an omitted zeta is refused in one line; a normal that is not a
    unit vector is refused as gamma's."""
    free = RollingSystem("trace_ball_nofield", inertia=("2/5*m*b**2",) * 3, support="sphere",
                         support_radius="R")  # fmt: skip
    chaplygin.register_system(free)
    gamma = (2 / 7, -3 / 7, 6 / 7)
    run = chaplygin.integrate(free.name, {"M": (0.3, -0.2, 0.5), "gamma": gamma}, (0, 0.5),
                              {"m": MASS, "b": B, "R": R}, effects="contact_point",
                              method="DOP853", backend="numpy")  # fmt: skip
    zeta, g0 = _group(run, "zeta")[:, 0], np.array(gamma) / np.linalg.norm(gamma)
    assert np.abs(zeta - g0).max() <= 4 * np.finfo(float).eps
    alpha, beta = _group(run, "alpha")[:, 0], _group(run, "beta")[:, 0]
    eps = np.finfo(float).eps  # the frame is completed at a guard precision, rounded once
    assert abs(alpha @ zeta) <= 4 * eps and abs(beta @ zeta) <= 4 * eps
    assert abs(np.cross(alpha, beta) @ zeta - 1) <= 4 * eps
    with pytest.raises(UserInputError, match="gamma must be a unit vector"):
        bad = {"M": (0.3, -0.2, 0.5), "gamma": (0.2, -0.4, 0.8)}
        chaplygin.integrate(free.name, bad, (0, 0.5), {"m": MASS, "b": B, "R": R},
                            effects="contact_point")  # fmt: skip
    heavy = _on_sphere("trace_ball_heavy", "outside")
    chaplygin.register_system(heavy)
    with pytest.raises(UserInputError, match="zeta"):
        values = {"m": MASS, "b": B, "R": R, "g": G}
        chaplygin.integrate(heavy.name, {"M": (0.3, -0.2, 0.5), "gamma": gamma}, (0, 0.5),
                            values, effects="contact_point")  # fmt: skip


def test_the_example_over_a_sphere_draws_its_trace_from_its_scene(tmp_path):
    """examples/systems/chaplygin_ball_on_sphere.toml asks for outputs.contact_trace: run for
    5 time units, the effect is added for it, the figure is written, and the frame's
    relations and the momentum's fixed components keep their values to the run's
    tolerance (their drifts: the evidence)."""
    import json
    from pathlib import Path

    from chaplygin.verify.cli import main

    example = Path(__file__).parents[2] / "examples" / "systems" / "chaplygin_ball_on_sphere.toml"
    out = tmp_path / "out"
    assert main(["run", str(example), "--out", str(out), "--set", "run.t_end=5"]) == 0
    assert (out / "contact_trace.png").stat().st_size > 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["effects"] == ["contact_point"]
    drift = summary["run"]["drift"] if "run" in summary else summary["drift"]
    for name in ("(M,alpha)", "(M,beta)", "(M,zeta)", "(zeta,alpha)", "(alpha,beta)"):
        assert abs(float(drift[name])) < 1e3 * 1e-12, name
