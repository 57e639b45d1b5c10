"""A body on balls from a file: ``verify --system`` proves what the model ships, a scene
integrates it, a bad ball table is one line (examples/systems/body_on_four_balls.toml)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from chaplygin.verify.cli import main

FILE = Path(__file__).resolve().parents[2] / "examples" / "systems" / "body_on_four_balls.toml"


@pytest.mark.slow
def test_verify_system_proves_the_shipped_integrals_and_refutes_the_control(
    tmp_path, capsys, monkeypatch
):
    """The 11 integrals and the density the derived model ships are proved (Groebner
    normal forms), the file's control is refuted: exit 0."""
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    assert main(["verify", "--system", str(FILE), "--jobs", "1", "--json"]) == 0
    verdicts = {v["id"]: v["verdict"] for v in json.loads(capsys.readouterr().out)}
    assert verdicts.pop("BALLS4-rotor/control") == "refuted"
    assert "body_on_four_balls:H" in verdicts and "body_on_four_balls:density" in verdicts
    assert len(verdicts) == 12 and set(verdicts.values()) == {"proved"}


def test_a_scene_integrates_the_body_on_balls(tmp_path, monkeypatch):
    """The file as a scene, shortened, on the numpy backend: the shipped integrals drift
    by less than 1e-8."""
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    argv = ["run", str(FILE), "--out", str(tmp_path / "out"), "--set", "run.t_end=2",
            "--set", "run.backend=numpy", "--set", "run.method=DOP853", "--json"]  # fmt: skip
    assert main(argv) == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    drift = summary["run"]["drift"] if "run" in summary else summary["drift"]
    assert "H" in drift and max(abs(float(v)) for v in drift.values()) < 1e-8


@pytest.mark.parametrize(
    "ball, message",
    [
        ("moment = 1\nratio = 0.5\ndirection = [0, 0, 0]", "zero vector"),
        ("moment = -1\nratio = 0.5\ndirection = [0, 0, 1]", "moment must be positive"),
    ],
)
def test_a_bad_ball_table_is_one_line_exit_2(tmp_path, ball, message, capsys, monkeypatch):
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    scene = tmp_path / "bad.toml"
    scene.write_text(
        '[system]\nname = "bad"\ninertia = [1, 2, 3]\nsupport = "balls"\n\n'
        f"[[system.balls]]\n{ball}\n\n[initial]\nM = [0, 0, 1]\nalpha = [1, 0, 0]\n"
        "beta = [0, 1, 0]\ngamma = [0, 0, 1]\n\n[run]\nt_end = 1\n"
    )
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err, err
    assert not (tmp_path / "out").exists()
