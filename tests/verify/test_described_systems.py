"""Described systems end to end: Kane's method agrees, discovery finds and proves, scenes run.

The Kane cross-check (:mod:`chaplygin.verify.kane_rolling`) is an independent derivation
(sympy.physics.mechanics, Euler angles, a real rotor for the gyrostat); its negative
control is a model with a perturbed right-hand side, refuted by the same comparison.
Jellett's integral ``(I omega, a + b gamma)`` (Routh's sphere) is typed from the
literature, not taken from the search.
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.verify.cli import main
from chaplygin.verify.discover import discover
from chaplygin.verify.identity import Domain, decide, measure_residual
from chaplygin.verify.kane_rolling import kane_compare

ROOT = Path(__file__).resolve().parents[2]
SYSTEMS = ROOT / "examples" / "systems"

GENERAL = RollingSystem(
    "general_body",
    inertia=[["I1", "I12", 0], ["I12", "I2", 0], [0, 0, "I3"]],
    centre_of_mass=("a1", "a2", "a3"),
    gravity="g",
    gyrostat=("K1", 0, "K3"),
    potential="k*gamma1*gamma2",
)
GENERAL_VALUES = dict(
    m="1.3", b="0.9", I1="0.7", I12="0.05", I2="0.8", I3="1.1", a1="0.1", a2="-0.13",
    a3="0.2", g="9.81", K1="0.3", K3="-0.2", k="0.37",
)  # fmt: skip


@pytest.mark.slow
def test_kane_agrees_with_a_general_body_and_refutes_a_perturbed_one():
    model = GENERAL.model()
    result = kane_compare(GENERAL, model, GENERAL_VALUES)
    assert result.points == 4
    assert result.agrees, result
    bad = dataclasses.replace(
        model, rhs=(*model.rhs[:2], model.rhs[2] + sp.Rational(1, 1000), *model.rhs[3:])
    )
    control = kane_compare(GENERAL, bad, GENERAL_VALUES)
    assert not control.agrees
    assert control.max_acceleration_error > 1e6 * control.tolerance


@pytest.mark.expensive  # 13 s: the general body above keeps Kane in the default run
def test_kane_agrees_with_a_rubber_body_off_centre():
    system = RollingSystem(
        "rubber_off_centre", inertia=("I1", "I2", "I3"), centre_of_mass=(0, "a2", "a3"),
        gravity="g", contact="rubber",
    )  # fmt: skip
    values = dict(m="1.3", b="0.9", I1="0.7", I2="0.8", I3="1.1", a2="-0.13", a3="0.2", g="9.81")
    result = kane_compare(system, system.model(), values)
    assert result.agrees, result


def test_routh_sphere_jellett_integral_and_density_are_found_and_proved():
    system = RollingSystem(
        "routh_found", inertia=("A", "A", "C"), centre_of_mass=(0, 0, "a"), gravity="g"
    )
    found = discover(
        system, degree=1, coefficient_degree=1, momentum="omega", in_parameters=True,
        densities=True,
    )  # fmt: skip
    assert found.all_proved
    (F,) = found.search.integrals
    assert found.search.rank == found.search.unknowns - 1  # no other in the class
    A, C, b = (sp.Symbol(n, positive=True) for n in ("A", "C", "b"))
    a = sp.Symbol("a", real=True)
    w = sp.Matrix(sp.symbols("omega1:4", real=True))
    gamma = sp.Matrix(sp.symbols("gamma1:4", real=True))
    jellett = (sp.diag(A, A, C) * w).dot(sp.Matrix([0, 0, a]) + b * gamma)
    assert sp.cancel(F / jellett).is_number  # the same integral up to a constant factor
    assert found.densities.found and found.density_proof.verdict == "proved"
    # negative control: the inverse power is refuted by the same decision procedure
    from chaplygin.derive.systems import build_model

    routh = build_model("routh_found")
    wrong = 1 / found.densities.density()
    assert decide([measure_residual(wrong, routh)], Domain(routh)).verdict == "refuted"


def test_chaplygin_top_has_the_energy_and_no_density_in_the_family():
    system = RollingSystem(
        "top_found", inertia=("0.4", "0.5", "0.6"), mass=1, radius=1,
        centre_of_mass=(0, 0, "a"), gravity=1,
    )  # fmt: skip
    found = discover(
        system, degree=2, coefficient_degree=2, momentum="omega", in_parameters=True,
        densities=True,
    )  # fmt: skip
    assert found.all_proved and len(found.search.integrals) == 1
    assert found.search.rank == found.search.unknowns - 1
    assert not found.densities.found
    assert found.densities.augmented_rank == found.densities.rank + 1  # the certificate


def _cli(*args, cache):
    env = {"CHAPLYGIN_CACHE_DIR": str(cache), "PATH": "/usr/bin:/bin"}
    return subprocess.run(
        [sys.executable, "-m", "chaplygin.verify.cli", *args],
        capture_output=True, text=True, env=env, timeout=600,
    )  # fmt: skip


def test_discover_reads_a_description_file(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    argv = [
        "discover", str(SYSTEMS / "routh_sphere.toml"), "--degree", "1",
        "--coefficient-degree", "1", "--momentum", "omega", "--in-parameters", "--json",
    ]  # fmt: skip
    assert main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    assert [i["verdict"] for i in data["integrals"]] == ["proved"]
    assert data["dimension"] == 1


@pytest.mark.parametrize(
    "table, message",
    [
        ('name = "bad"\ninertia = [[1, 0, 0], [0, 1, 0], [0, 0, 0]]', "singular"),
        ('name = "bad"\ninertia = [1, 1, 1]\npotential = "open(1)"', "not allowed"),
        ('name = "chaplygin_ball"\ninertia = [1, 1, 1]', "taken by a built-in"),
        ('name = "bad"\ninertia = [1, 1, 1]\nsupport = "sphere"', "not derived"),
    ],
)
def test_bad_system_tables_are_one_line_exit_2_and_cache_nothing(
    tmp_path, table, message, capsys, monkeypatch
):
    scene = tmp_path / "bad.toml"
    scene.write_text(
        f"[system]\n{table}\n\n[initial]\nM = [0, 0, 1]\ngamma = [0, 0, 1]\n\n[run]\nt_end = 1\n"
    )
    cache = tmp_path / "cache"
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(cache))
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert "Traceback" not in err
    assert not (tmp_path / "out").exists()
    assert not cache.exists() or not any(p.is_file() for p in cache.rglob("*"))


def test_a_scene_with_a_system_table_runs(tmp_path):
    """The Routh sphere example, shortened, on the numpy backend (no compiler needed)."""
    scene = SYSTEMS / "routh_sphere.toml"
    out = _cli(
        "run", str(scene), "--out", str(tmp_path / "out"), "--set", "run.t_end=3",
        "--set", "run.backend=numpy", "--set", "run.method=DOP853", "--json",
        cache=tmp_path / "cache",
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    drift = summary["run"]["drift"] if "run" in summary else summary["drift"]
    assert max(abs(float(v)) for v in drift.values()) < 1e-8
    assert (tmp_path / "out" / "contact_trace.png").stat().st_size > 0


def test_verify_system_checks_the_models_and_the_files_claims(tmp_path):
    """The derived model's integrals and its Kane cross-check, the finds of the file's
    [discover] class and its dimension (the search run again, exactly), the file's three
    claims proved and its control refuted by the same decision procedure (exit 0: every
    verdict the expected one)."""
    # the energy's proof (6 s) and Routh's integral squared (2 s) are left to the example
    # run of the README; the others cover every kind of claim the file makes
    claims = (
        "routh_sphere:kane,routh_sphere:found-*,routh_sphere:(gamma*,ROUTH-jellett*,ROUTH-density"
    )
    out = _cli(
        "verify", "--system", str(SYSTEMS / "routh_sphere.toml"), "--jobs", "1", "--json",
        "--claims", claims, cache=tmp_path / "cache",
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    verdicts = {v["id"]: v["verdict"] for v in json.loads(out.stdout)}
    assert verdicts == {
        "routh_sphere:(gamma,gamma)": "proved",
        "routh_sphere:kane": "numeric",  # KanesMethod agrees at 40 digits
        "routh_sphere:found-F1": "proved",  # [discover]: Jellett's integral, found
        "routh_sphere:found-class-integrals": "proved",  # its dimension, searched again
        "routh_sphere:found-density": "proved",
        "ROUTH-jellett": "proved",
        "ROUTH-density": "proved",
        "ROUTH-jellett/control-balanced": "refuted",
    }


def test_a_wrong_claim_expected_to_hold_fails_the_run(tmp_path, capsys, monkeypatch):
    text = (SYSTEMS / "routh_sphere.toml").read_text().split("[discover]")[0]
    bad = tmp_path / "wrong.toml"
    bad.write_text(
        text + '[[claims]]\nid = "W"\nkind = "integral"\nexpression = "M1*gamma1 + M2*gamma2"\n'
    )
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "c"))
    assert main(["verify", "--system", str(bad), "--jobs", "1", "--claims", "W"]) == 1
    assert "UNEXPECTED: W" in capsys.readouterr().out


@pytest.mark.parametrize(
    "entry, message",
    [
        ('id = "X"\nkind = "integral"\nexpression = "__import__(1)"', "not allowed"),
        ('id = "X"\nkind = "integral"\nexpression = "q1*gamma1"', "unknown name 'q1'"),
        ('id = "X"\nkind = "theorem"\nexpression = "gamma1"', "kind"),
    ],
)
def test_bad_claims_are_one_line_exit_2(tmp_path, entry, message, capsys, monkeypatch):
    text = (SYSTEMS / "routh_sphere.toml").read_text().split("[discover]")[0]
    bad = tmp_path / "bad.toml"
    bad.write_text(text + "[[claims]]\n" + entry + "\n")
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "c"))
    assert main(["verify", "--system", str(bad), "--jobs", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err


@pytest.mark.expensive  # 27 s: derives Routh's sphere, searches its symmetries twice (5 s each)
def test_symmetries_and_relations_of_a_file_become_claims(tmp_path, capsys, monkeypatch):
    """Routh's sphere (moments A, A, C, centre of mass on the axis) is symmetric about its
    axis: the rotation (omega2, -omega1, 0, gamma2, -gamma1, 0) in (omega, gamma) is found
    and proved a symmetry; the class's dimension (1) is a claim, searched again exactly; the
    linear class with a cofactor of degree <= 1 holds no invariant relation: a claim too."""
    text = (SYSTEMS / "routh_sphere.toml").read_text().split("[discover]")[0]
    path = tmp_path / "routh_linear.toml"
    path.write_text(
        text + '[discover]\ndegree = 1\ncoefficient_degree = 0\nmomentum = "omega"\n'
        "relations = true\nsymmetries = true\n"
    )
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "c"))
    argv = ["verify", "--system", str(path), "--jobs", "1", "--json", "--claims", "*:found-*"]
    assert main(argv) == 0
    verdicts = {v["id"]: v for v in json.loads(capsys.readouterr().out)}
    assert {k: v["verdict"] for k, v in verdicts.items()} == {
        "routh_sphere:found-class-integrals": "proved",
        "routh_sphere:found-X1": "proved",
        "routh_sphere:found-class-symmetries": "proved",
        "routh_sphere:found-class-relations": "proved",
    }
    assert "gamma2, -gamma1, 0" in verdicts["routh_sphere:found-X1"]["statement"]
    assert "exactly 0 independent invariant" in (
        verdicts["routh_sphere:found-class-relations"]["statement"]
    )
