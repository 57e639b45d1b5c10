"""API errors speak of arguments; the command line prints its own flags (issue 10, item 5)."""

from __future__ import annotations

import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate
from chaplygin.verify.vocabulary import to_cli

pytestmark = pytest.mark.quick

Y0 = {"M": (0.1, 0.2, 0.3), "gamma": (0, 0, 1)}
P = {"I": (1, 2, 3), "D": 1}


@pytest.mark.parametrize(
    ("call", "api", "cli"),
    [
        (
            lambda: integrate("chaplygin_ball", Y0, 1, {"D": 1}),
            'params["I"]=(VALUE1, VALUE2, VALUE3)',
            "--param I=VALUE1,VALUE2,VALUE3",
        ),
        (
            lambda: integrate("chaplygin_ball", {"M": (0.1, 0.2, 0.3)}, 1, P),
            'y0["gamma"]=(V1, V2, V3)',
            "--y0 gamma=V1,V2,V3",
        ),
        (
            lambda: integrate("chaplygin_ball", Y0, 1, P, precision="triple"),
            'precision="quad"',
            "--precision quad",
        ),
        (
            lambda: integrate("chaplygin_ball", Y0, 1, P, rtol=1e-20),
            'precision="quad"',
            "--precision quad",
        ),
        (lambda: integrate("chaplygin_ball", Y0, 1, P, method="odefun"), 'method="', "--method "),
    ],
)
def test_api_errors_name_arguments_and_the_cli_names_flags(call, api, cli):
    with pytest.raises(UserInputError) as err:
        call()
    message = str(err.value)
    assert api in message and "--" not in message
    assert cli in to_cli(message)


def test_text_without_arguments_is_unchanged():
    text = "gamma must be a unit vector: |gamma| = 1.2 differs from 1 by more than 1e-09"
    assert to_cli(text) == text


# ------------------------------------------------------------------ the commands' flags
def _run(argv, capsys):
    from chaplygin.verify.cli import main

    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_rotation_takes_the_integrate_vocabulary_and_its_old_flags(capsys):
    new = [
        "rotation",
        "--param",
        "I=1,1.5,3",
        "--param",
        "D=1",
        "--y0",
        "M=0.48,0.5,-0.36",
        "--y0",
        "gamma=0.6,0,0.8",
        "--precision",
        "20",
        "--json",
    ]
    old = [
        "rotation",
        "--I",
        "1,1.5,3",
        "--D",
        "1",
        "--M",
        "0.48,0.5,-0.36",
        "--gamma",
        "0.6,0,0.8",
        "--digits",
        "20",
        "--json",
    ]
    a, b = _run(new, capsys), _run(old, capsys)
    assert a[0] == b[0] == 0 and a[1] == b[1]
    code, out, err = _run(new[:5] + new[7:], capsys)  # no M
    assert code == 2 and "missing --y0 M=" in err and out == ""


def test_delta_takes_precision_and_its_old_digits(capsys):
    base = ["delta", "--param", "I=1,3,5", "--param", "D=1", "--param", "b=1", "--json"]
    a = _run([*base, "--precision", "12"], capsys)
    b = _run([*base, "--digits", "12"], capsys)
    assert a[0] == b[0] == 0
    import json

    assert json.loads(a[1])["delta_closed_form"] == json.loads(b[1])["delta_closed_form"]
    code, _, err = _run([*base, "--precision", "12", "--digits", "13"], capsys)
    assert code == 2 and "--precision once" in err


# ------------------------------------------------------------ one spelling per concept
def _commands() -> dict:
    import argparse

    from chaplygin.verify.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _flags(parser, visible: bool) -> set[str]:
    import argparse

    return {
        o
        for a in parser._actions
        if (a.help != argparse.SUPPRESS) == visible
        for o in a.option_strings
    }


def test_every_command_shows_one_spelling_per_concept():
    """No command offers an old spelling (``--output``, ``--t-eval``, ``--digits``, ...) in
    its help; where one is still accepted it is a hidden alias of the one spelling."""
    from chaplygin.verify.vocabulary import RENAMED_FLAGS

    commands = _commands()
    assert {"integrate", "delta", "rotation", "run", "sweep"} <= set(commands)
    aliases = 0
    for name, parser in commands.items():
        shown, hidden = _flags(parser, True), _flags(parser, False)
        assert not shown & set(RENAMED_FLAGS), name
        for old in hidden & set(RENAMED_FLAGS):
            assert RENAMED_FLAGS[old] in shown, (name, old)
            aliases += 1
    assert aliases >= 4  # integrate --output/--t-eval, delta and rotation --digits, ...
    outs = {n for n, p in commands.items() if "--out" in _flags(p, True)}
    assert {"integrate", "run", "sweep", "derive", "bench", "bifurcation"} <= outs


@pytest.mark.parametrize("value", ["double", "quad", "30"])
def test_every_command_reads_a_precision_the_same_way(value):
    """``--precision double|quad|N`` on every command that has it (not a count of digits
    on some): the digits it works at are the ones :class:`Precision` gives the value."""
    import argparse

    from chaplygin.numerics.precision import Precision
    from chaplygin.verify.cli_common import precision_digits

    having = {
        name: parser
        for name, parser in _commands().items()
        if "--precision" in _flags(parser, True)
    }
    assert {"integrate", "delta", "rotation"} <= set(having)
    for name, parser in having.items():
        action = next(a for a in parser._actions if "--precision" in a.option_strings)
        args = argparse.Namespace(precision=value, digits=None, default_digits=7)
        got = (
            Precision(action.type(value) if action.type else value).decimal_digits
            if name == "integrate"
            else precision_digits(args)
        )
        assert got == Precision(value).decimal_digits, name


def test_the_commands_that_print_progress_take_quiet():
    """``--quiet`` wherever a command prints progress (a bar, or lines while it works)."""
    import inspect

    from chaplygin.verify import cli
    from chaplygin.verify.vocabulary import PROGRESS_COMMANDS

    commands = _commands()
    talking = {
        m.__name__.rsplit(".", 1)[1].removesuffix("_cmd")
        for m in cli.COMMANDS
        if "progress" in inspect.getsource(m)
    }
    assert talking and talking <= set(PROGRESS_COMMANDS)
    for name in PROGRESS_COMMANDS:
        action = next(a for a in commands[name]._actions if "--quiet" in a.option_strings)
        assert action.dest == "quiet" and action.nargs == 0 and action.default is False


def _keys(value, path=()):
    """Every (path, key, value) of a JSON document."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield (*path, k), k, v
            if k != "precision":  # its own keys: kind, digits, bits
                yield from _keys(v, (*path, k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _keys(v, (*path, i))


def _assert_vocabulary(document) -> None:
    import re

    from chaplygin.verify.vocabulary import RENAMED_JSON_KEYS

    for where, key, value in _keys(document):
        assert key not in RENAMED_JSON_KEYS, where
        if key == "precision":
            assert set(value) == {"kind", "digits", "bits"}, where
            assert value["kind"] in ("double", "quad", "digits") and value["digits"] >= 1
        if isinstance(value, str):
            assert not re.fullmatch(r"\d+ digits", value), where


def test_the_json_of_every_command_speaks_one_vocabulary(capsys, tmp_path):
    """``--json`` of integrate, rotation, delta and run: no retired key (``nsteps``,
    ``digits``, ``digits_requested``), a precision as a structured value, and the system,
    effects and model under the same keys in integrate and run."""
    import json
    from pathlib import Path

    ball = ["--param", "I=1,2,3", "--param", "D=1", "--y0", "M=0.7,-0.4,0.5",
            "--y0", "gamma=0.2,0.3,sqrt(0.87)"]  # fmt: skip
    docs = {}
    for name, argv in {
        "integrate": ["integrate", "chaplygin_ball", *ball, "--t-end", "1", "--precision",
                      "20", "--json"],
        "rotation": ["rotation", "--param", "I=1,1.5,3", "--param", "D=1", "--y0",
                     "M=0.48,0.5,-0.36", "--y0", "gamma=0.6,0,0.8", "--precision", "20",
                     "--json"],
        "delta": ["delta", "--param", "I=1,3,5", "--param", "D=1", "--param", "b=1",
                  "--precision", "12", "--json"],
        "run": ["run", str(Path(__file__).parents[2] / "examples" / "scenes" / "k01-fig6f.toml"),
                "--set", "run.t_end=1", "--out", str(tmp_path / "run"), "--json", "--quiet"],
    }.items():  # fmt: skip
        code = _run(argv, capsys)
        assert code[0] == 0, code[2]
        docs[name] = json.loads(code[1])
        _assert_vocabulary(docs[name])
    assert docs["integrate"]["precision"] == {"kind": "digits", "digits": 20, "bits": 70}
    assert docs["rotation"]["precision"]["digits"] == 20
    assert docs["delta"]["precision"]["digits"] == 12
    for name in ("integrate", "run"):
        assert {"system", "effects", "model", "steps", "precision"} <= set(docs[name]), name
    assert docs["integrate"]["steps"] > 0 and docs["run"]["steps"] > 0
    # a control: the check finds a relapse
    with pytest.raises(AssertionError):
        _assert_vocabulary({"work": {"nsteps": 3}})
    with pytest.raises(AssertionError):
        _assert_vocabulary({"precision": "30 digits"})
