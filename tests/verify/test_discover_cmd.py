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


AXISYMMETRIC = "I1=7/5,I2=7/5,I3=13/4,D=9/7"
VALUES = dict(item.split("=") for item in AXISYMMETRIC.split(","))


def test_relations_and_symmetries_json_give_the_class_the_basis_and_the_proofs(
    capsys, tmp_path, monkeypatch
):
    """The axisymmetric ball at rational values: the rotation about the axis e3 is the one
    symmetry of the linear class (proved by the verifier), no invariant relation with a
    cofactor of degree <= 1 (the certificate says why), (M, gamma) its only integral."""
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path))
    argv = [
        "discover", "chaplygin_ball", "--degree", "1", "--coefficient-degree", "1",
        "--relations", "--symmetries", "--values", AXISYMMETRIC, "--json",
    ]  # fmt: skip
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    sym = out["symmetry_search"]
    assert (sym["dimension"], sym["trivial"]) == (1, [])
    (X,) = sym["fields"]
    assert X["verdict"] == "proved"
    comps = [sp.sympify(c) for c in X["components"]]
    M1, M2, M3, g1, g2, g3 = sp.symbols("M1 M2 M3 gamma1 gamma2 gamma3")
    rotation = [M2, -M1, 0, g2, -g1, 0]  # e3 x (M, gamma), up to a factor
    ratios = {sp.cancel(c / r) for c, r in zip(comps, rotation, strict=True) if r != 0}
    assert len(ratios) == 1 and comps[2] == comps[5] == 0
    rel = out["relation_search"]
    assert rel["relations"] == [] and rel["complete"]
    assert "lambda = K/Q" in rel["class"]["description"] and "no other" in rel["certificate"]
    assert out["values"] == {"I1": "7/5", "I2": "7/5", "I3": "13/4", "D": "9/7"}


def test_a_second_identical_discovery_answers_from_the_cache(tmp_path, monkeypatch):
    """Not recomputed (the searches are counted), the same result; a damaged entry and an
    entry of ours planted under another key are refused and recomputed."""
    import chaplygin.verify.discover as mod

    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path))
    calls = []
    real = mod.find_polynomial_integrals

    def counted(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(mod, "find_polynomial_integrals", counted)

    def run(**extra):
        return chaplygin.discover("chaplygin_ball", degree=1, coefficient_degree=1, **extra)

    first = run()
    second = run()
    assert (len(calls), first.from_cache, second.from_cache) == (1, False, True)
    same = {k: v for k, v in first.as_dict().items() if k != "from_cache"}
    assert same == {k: v for k, v in second.as_dict().items() if k != "from_cache"}
    (entry,) = (tmp_path / "discovery").glob("*.pickle")
    # damaged: one byte of the pickle changed
    blob = bytearray(entry.read_bytes())
    blob[-5] ^= 0xFF
    entry.write_bytes(bytes(blob))
    third = run()
    assert (len(calls), third.from_cache) == (2, False)
    assert [str(F) for F in third.search.integrals] == [str(F) for F in first.search.integrals]
    # planted: our own valid entry copied under the key of another class
    other = run(symmetries=True, values=VALUES)
    assert len(calls) == 3 and not other.from_cache
    entries = sorted((tmp_path / "discovery").glob("*.pickle"))
    assert len(entries) == 2
    target = next(p for p in entries if p != entry)
    target.write_bytes(entry.read_bytes())
    planted = run(symmetries=True, values=VALUES)
    assert (len(calls), planted.from_cache) == (4, False)
    assert planted.symmetries is not None
    # and without the cache nothing is read
    assert not run(cache=False).from_cache and len(calls) == 5


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--values", "I1"], "not NAME=VALUE"),
        (["--values", "J=1"], "no parameter 'J'"),
        (["--values", "D=sqrt(2)"], "exact rational"),
        (["--relations", "--cofactor-degree", "5"], "more than this machine"),
    ],
)
def test_bad_linear_class_input_is_one_line_exit_2(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path))
    assert main(["discover", "chaplygin_ball", "--degree", "1", *argv]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], captured.err
    assert captured.out == ""
    folder = tmp_path / "discovery"
    assert not folder.exists() or not any(p.is_file() for p in folder.rglob("*"))
