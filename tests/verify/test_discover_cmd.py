"""``chaplygin discover`` and ``chaplygin.discover``: the search, its proofs and bad input."""

from __future__ import annotations

import json

import chaplygin
import pytest
import sympy as sp
from chaplygin.verify.cli import main


def test_discover_json_gives_the_basis_its_proofs_and_the_rank(capsys):
    """Degree 1 in M with coefficients of degree 1 in gamma: 15 unknowns modulo the sphere
    and constants; the only integral is (M, gamma) (BKM12-5), so the rank is 14."""
    argv = ["discover", "chaplygin_ball", "--degree", "1", "--coefficient-degree", "1", "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["unknowns"], out["rank"], out["dimension"]) == (15, 14, 1)
    (found,) = out["integrals"]
    assert found["verdict"] == "proved"
    M1, M2, M3, g1, g2, g3 = sp.symbols("M1 M2 M3 gamma1 gamma2 gamma3")
    ratio = sp.cancel(sp.sympify(found["expression"]) / (M1 * g1 + M2 * g2 + M3 * g3))
    assert ratio.is_Rational and ratio != 0
    assert out["class"]["degree"] == 1 and "rational numbers" in out["class"]["description"]


def test_a_wrong_integral_is_refuted_by_the_same_proof_machinery():
    """Negative control of the proof step: (M, gamma) + M1 gamma1 is no integral."""
    from chaplygin.verify.identity import Domain, decide, lie_derivative

    model = chaplygin.build_model("chaplygin_ball")
    found = chaplygin.discover("chaplygin_ball", degree=1, coefficient_degree=1)
    assert found.all_proved and len(found.search.integrals) == 1
    wrong = found.search.integrals[0] + model.state[0] * model.state[3]
    assert decide([lie_derivative(wrong, model)], Domain(model)).verdict == "refuted"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["discover", "chaplygin_ball", "--degree", "0"], "at least 1"),
        (
            ["discover", "chaplygin_ball", "--degree", "9", "--coefficient-degree", "9"],
            "48400 unknowns",
        ),
        (["discover", "chaplygin_ball", "--momentum", "L"], "no group 'L'"),
        (["discover", "chaplygin_ball", "--effects", "variable_inertia"], "autonomous"),
        (["discover", "no_such_system"], "unknown system"),
    ],
)
def test_bad_discover_input_is_one_line_exit_2(capsys, argv, message):
    assert main(argv) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], captured.err
    assert captured.out == ""
