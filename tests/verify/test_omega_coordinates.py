"""Integrals and densities decided in the coordinates ``(omega, g)`` (verify/omega_coordinates.py):
the body on four balls in a general placement (examples/systems/body_on_balls_general.toml,
a support tensor that is not diagonal in the space axes), whose ``H`` and density the
expanded route in ``(M, g)`` did not prove in 5 minutes."""

from __future__ import annotations

import dataclasses
import json
import random
from functools import partial
from pathlib import Path

import sympy as sp
from chaplygin.derive.phase_space import sample_point
from chaplygin.derive.systems import build_model
from chaplygin.verify import omega_coordinates
from chaplygin.verify.claims.base import Claim
from chaplygin.verify.cli import main
from chaplygin.verify.identity import lie_derivative, measure_residual
from chaplygin.verify.user_claims import (
    _integral_check,
    _measure_check,
    claims_of_file,
    read_description,
)
from chaplygin.verify.verdict import check_claim

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "systems"
FILE = EXAMPLES / "body_on_balls_general.toml"


def test_verify_system_proves_h_and_the_density_of_a_general_placement(
    tmp_path, capsys, monkeypatch
):
    """The 11 integrals and the density are proved (H and the density in ``(omega, g)``,
    the method says so), the file's three controls are refuted: exit 0."""
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    assert main(["verify", "--system", str(FILE), "--jobs", "1", "--json"]) == 0
    verdicts = {v["id"]: v for v in json.loads(capsys.readouterr().out)}
    controls = [i for i in verdicts if i.startswith("BALLS-general/")]
    assert len(controls) == 3 and {verdicts.pop(i)["verdict"] for i in controls} == {"refuted"}
    assert len(verdicts) == 12 and {v["verdict"] for v in verdicts.values()} == {"proved"}
    for name in ("H", "density"):
        assert "coordinates (omega, g)" in verdicts[f"body_on_balls_general:{name}"]["method"]


def _general_model(tmp_path, ratio: str = "0.4"):
    """The example's system (ball 2's ratio changed when asked), registered and derived."""
    text = FILE.read_text().replace("ratio = 0.4", f"ratio = {ratio}")
    path = tmp_path / f"balls_{ratio}.toml"
    path.write_text(text.replace('"body_on_balls_general"', f'"balls_{ratio.replace(".", "_")}"'))
    claims = claims_of_file(path)
    return claims[0].model()


def _claim(model, kind: str, expr: sp.Expr) -> Claim:
    build = partial(_integral_check if kind == "integral" else _measure_check, expr)
    return Claim(id=f"control-{kind}", source="test", kind=kind, statement="a control",
                 system=model.system, build=build, expected="fails")  # fmt: skip


def test_the_energy_and_density_of_a_wrong_ratio_are_refuted(tmp_path, monkeypatch):
    """Ball 2's ratio 0.45 for 0.4: that support's energy ``(II' omega, omega)/2`` and its
    density ``det(II')^-1/2`` (in the frame) are refuted on the true model by the same
    route, with a witness; the true ones, written the same way, are proved by it."""
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    model, wrong = _general_model(tmp_path), _general_model(tmp_path, "0.45")
    w = sp.Matrix(model.omega)

    def energy(m):
        return (w.T * m.inertia_operator * w)[0] / 2

    M = model.group("M")  # H = (M, omega)/2 at M = II omega: the energy written in omega
    assert model.integral("H") == (M.T * w)[0] / 2
    assert (model.momentum_of_omega - model.inertia_operator * w).expand().is_zero_matrix
    for m, expected in ((wrong, "refuted"), (model, "proved")):
        for kind, expr in (("integral", energy(m)), ("measure", m.expand_aux(m.density))):
            assert not expr.free_symbols - set(model.state) - set(model.omega)
            claim = _claim(model, kind, expr)
            if expected == "proved":
                claim = dataclasses.replace(claim, expected="holds")
            verdict = check_claim(claim)
            assert (verdict.verdict, verdict.ok) == (expected, True), (kind, expected)
            assert bool(verdict.witness) == (expected == "refuted")


def _omega_point(model, seed: int) -> tuple[dict, dict]:
    """An exact point of ``(M, g)`` and the same point in ``(omega, g)``."""
    point = sample_point(model, random.Random(seed), model.state)
    omega = {w: model.expand_aux(w).xreplace(point) for w in model.omega}
    at = {s: v for s, v in point.items() if s not in set(model.group("M"))}
    return point, {**at, **omega}


def test_the_rate_in_omega_is_the_rate_in_m_at_the_same_point(tmp_path, monkeypatch):
    """Quantities that are not conserved (non-zero rates, so agreement is not 0 = 0): the
    rate in ``(omega, g)`` equals the expanded Lie derivative in ``(M, g)`` at the same
    exact points of the general placement."""
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    model = _general_model(tmp_path)
    assert omega_coordinates.applies(model)
    M, alpha = model.group("M"), model.group("alpha")
    w = model.omega
    exprs = [M[0] * w[1] + alpha[2] * M[1] ** 2, w[0] ** 2 + w[2] * alpha[0]]
    nonzero = 0
    for seed in (3, 4):
        point, in_omega = _omega_point(model, seed)
        for e in exprs:
            old = lie_derivative(e, model).xreplace(point)
            new = omega_coordinates.integral_rate(e, model).xreplace(in_omega)
            assert old.is_Rational and new - old == 0
            nonzero += old != 0
    assert nonzero == 4


def test_the_liouville_residual_in_omega_is_the_one_in_m(tmp_path, monkeypatch):
    """Liouville's residual of a density is a function on the phase space, whatever the
    coordinates: ``rho`` in ``(M, g)`` and ``rho det II`` in ``(omega, g)`` give the same
    value at the same exact point (the body on four balls of the diagonal example: its
    expanded route is small), for densities that are not invariant and the shipped one."""
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    system, _, _ = read_description(EXAMPLES / "body_on_four_balls.toml")
    claims_of_file(EXAMPLES / "body_on_four_balls.toml")
    model = build_model(system.name)
    assert omega_coordinates.applies(model)
    alpha = model.group("alpha")
    densities = [sp.S.One, model.density**2, model.density * (1 + alpha[0] ** 2)]
    nonzero = 0
    for seed in (5, 6):
        point, in_omega = _omega_point(model, seed)
        for rho in [*densities, model.density]:
            old = measure_residual(rho, model).xreplace(point)
            new = omega_coordinates.measure_residual(rho, model).xreplace(in_omega)
            assert sp.radsimp(new - old) == 0
            nonzero += old != 0
    assert nonzero == 6


def test_the_route_needs_omega_to_invert_the_momentum(tmp_path, monkeypatch):
    """A model whose stated ``M = m(omega, g)`` is not what its ``omega`` inverts (twice
    the true one) is not decided in ``(omega, g)``; nor is a model with a structured
    inverse (the Chaplygin ball, the closed model of the spherical support)."""
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    model = _general_model(tmp_path)
    assert omega_coordinates.applies(model)
    wrong = dataclasses.replace(model, momentum_of_omega=2 * model.momentum_of_omega)
    assert not omega_coordinates.applies(wrong)
    assert not omega_coordinates.applies(build_model("chaplygin_ball"))
    assert not omega_coordinates.applies(build_model("spherical_support"))
