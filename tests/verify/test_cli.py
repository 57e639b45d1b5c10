"""The command line: output formats, exit codes, one-line errors, no eval of user text."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from chaplygin.verify.cli import main

ACCEPTANCE = [
    "integrate",
    "chaplygin_ball",
    "--param",
    "I=1,2,3",
    "--param",
    "D=1",
    "--y0",
    "M=0.7,-0.4,0.5",
    "--y0",
    "gamma=0.2,0.3,0.93273790530888150455",
    "--t-end",
    "1000",
    "--rtol",
    "1e-12",
    "--atol",
    "1e-12",
    "--json",
]


def test_integrate_json_has_the_promised_fields(capsys):
    assert main(ACCEPTANCE) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"status", "t", "y", "drift", "wall_s"} <= set(out)
    assert out["status"] == 0
    assert set(out["y"]) == {"M1", "M2", "M3", "gamma1", "gamma2", "gamma3"}
    assert all(isinstance(v, str) for v in out["y"].values())
    # full double precision: the decimal string round-trips
    assert all(repr(float(v)) == v for v in out["y"].values())
    assert out["drift"]["H"] <= 1e-10 and out["drift"]["(M,M)"] <= 1e-10


def test_integrate_digits_prints_every_digit(capsys):
    args = ACCEPTANCE[:-7] + ["--t-end", "1", "--precision", "30", "--json"]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    for value in out["y"].values():
        digits = value.lstrip("-").replace(".", "").lstrip("0")
        assert len(digits) >= 30


BAD_ARGS = [
    (["integrate", "no_such_system", "--t-end", "1"], "unknown system"),
    (
        [
            "integrate",
            "chaplygin_ball",
            "--param",
            "I=1,2",
            "--param",
            "D=1",
            "--y0",
            "M=1,2,3",
            "--y0",
            "gamma=0,0,1",
            "--t-end",
            "1",
        ],
        "I needs 3 values",
    ),
    (
        [
            "integrate",
            "chaplygin_ball",
            "--param",
            "I=1,2,0",
            "--param",
            "D=1",
            "--y0",
            "M=1,2,3",
            "--y0",
            "gamma=0,0,1",
            "--t-end",
            "1",
        ],
        "positive",
    ),
    (
        [
            "integrate",
            "chaplygin_ball",
            "--param",
            "I=1,2,3",
            "--param",
            "D=1",
            "--y0",
            "M=1,2,3",
            "--y0",
            "gamma=0,0.5,1",
            "--t-end",
            "1",
        ],
        "unit vector",
    ),
    (
        [
            "integrate",
            "chaplygin_ball",
            "--param",
            "I=1,2,3",
            "--param",
            "D=nan",
            "--y0",
            "M=1,2,3",
            "--y0",
            "gamma=0,0,1",
            "--t-end",
            "1",
        ],
        "finite",
    ),
    (
        [
            "integrate",
            "chaplygin_ball",
            "--param",
            "I=1,2,3",
            "--param",
            "D=1",
            "--y0",
            "M=1,2,3",
            "--y0",
            "gamma=0,0,1",
            "--t-end",
            "1",
            "--effects",
            "magnetic",
        ],
        "unknown effect",
    ),
    (["integrate", "chaplygin_ball", "--param", "I", "--t-end", "1"], "NAME=VALUE"),
    (["integrate", "chaplygin_ball", "--rtol", "-1", "--t-end", "1"], "positive"),
    (["verify", "--claims", "NOPE-*"], "no claim matches"),
    (["frobnicate"], "invalid choice"),
]


@pytest.mark.parametrize(("argv", "message"), BAD_ARGS)
def test_user_errors_are_one_line_exit_2_no_traceback(capsys, argv, message):
    assert main(argv) == 2  # argparse's errors too: main returns, never raises SystemExit
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert message in lines[0] and "Traceback" not in captured.err
    assert captured.out == ""


def test_user_text_is_never_evaluated(tmp_path: Path, capsys):
    marker = tmp_path / "pwned"
    payload = f"__import__('os').system('touch {marker}')"
    argv = [
        "integrate",
        "chaplygin_ball",
        "--param",
        f"I={payload},2,3",
        "--param",
        "D=1",
        "--y0",
        "M=1,2,3",
        "--y0",
        "gamma=0,0,1",
        "--t-end",
        "1",
    ]
    assert main(argv) == 2
    assert not marker.exists()
    assert "cannot read" in capsys.readouterr().err


def test_verify_json_subset(capsys):
    assert main(["verify", "--claims", "BKM12-4,BKM12-4/*", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [v["id"] for v in out] == [
        "BKM12-4",
        "BKM12-4/control-exponent+1/2",
        "BKM12-4/control-rho=1",
    ]
    for v in out:
        assert {"id", "verdict", "method", "seconds"} <= set(v)
        assert ("witness" in v) == (v["verdict"] == "refuted")
        assert "residual" in v
    assert out[0]["verdict"] == "proved"


def test_json_text_is_strict_json():
    from chaplygin.verify.cli_common import json_text

    text = json_text({"a": float("nan"), "b": [float("inf"), 1.5, (-float("inf"),)], "c": "x"})
    assert json.loads(text) == {"a": None, "b": [None, 1.5, [None]], "c": "x"}
    assert "NaN" not in text and "Infinity" not in text


def test_every_command_prints_json_through_json_text():
    """A bare json.dumps (which writes NaN, not JSON) in a command module is a regression."""
    import chaplygin.verify

    folder = Path(chaplygin.verify.__file__).parent
    commands = sorted(folder.glob("*_cmd.py"))
    from chaplygin.verify.cli import COMMANDS

    assert len(commands) == len(COMMANDS)  # every subcommand module is looked at
    for path in commands:
        assert "json.dumps" not in path.read_text(), path.name


def test_output_paths_are_checked_before_any_work(tmp_path: Path, capsys, monkeypatch):
    from chaplygin.verify import plots

    def no_work(*args, **kwargs):
        raise AssertionError("the diagram was drawn before the path was checked")

    monkeypatch.setattr(plots, "bifurcation_figure", no_work)
    for out in ("", str(tmp_path), str(tmp_path / "missing" / "d.png"), str(tmp_path / "d")):
        assert main(["bifurcation", "chaplygin_ball", "--out", out]) == 2
        assert len(capsys.readouterr().err.splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
