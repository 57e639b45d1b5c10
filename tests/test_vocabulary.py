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
