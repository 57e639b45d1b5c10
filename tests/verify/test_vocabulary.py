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
