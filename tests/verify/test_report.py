"""``chaplygin verify --report``: sections, errata pairing, LaTeX, counts per paper."""

from __future__ import annotations

from pathlib import Path

from chaplygin.verify.cli import main
from chaplygin.verify.report import paper_of, plain_to_latex, render_report
from chaplygin.verify.verdict import Verdict


def _verdict(id_, verdict, expected="holds", witness=None):
    return Verdict(
        id=id_,
        statement="rho = (D^-1 - (gamma, A gamma))^-1/2",
        source="s",
        kind="measure",
        verdict=verdict,
        method="m",
        seconds=0.01,
        residual="0" if verdict != "refuted" else "0.5",
        witness=witness,
        expected=expected,
    )


def test_errata_pair_each_literal_reading_with_its_correction():
    verdicts = [
        _verdict("XYZ-1/literal", "refuted", "fails", {"a": "1/2"}),
        _verdict("XYZ-1", "proved"),
        _verdict("ABC-2", "proved"),
    ]
    text = render_report(verdicts)
    errata = text.split("## Errata", 1)[1].split("## Claims", 1)[0]
    assert "XYZ-1/literal" in errata and "| XYZ-1: $" in errata and "a = 1/2" in errata
    assert "ABC-2" not in errata
    assert "| XYZ | 2 | 1 | 0 | 0 | 0 | 1 | 0 |" in text
    assert "every verdict is the expected one" in text


def test_unexpected_verdicts_are_flagged():
    text = render_report([_verdict("ABC-3", "refuted", "holds", {"a": "1"})])
    assert "**1 unexpected verdicts**" in text and "(unexpected)" in text


def test_latex_translation():
    assert plain_to_latex("M' = M x omega") == r"M' = M \times \omega "
    assert r"^{-1/2}" in plain_to_latex("rho = X^-1/2")
    assert r"\sqrt{(M,M) - 1}" in plain_to_latex("sqrt((M,M) - 1)")
    assert paper_of("BKM12-4/control-rho=1") == "BKM12"
    assert paper_of("MODEL:chaplygin_ball.density") == "chaplygin models"


def test_cli_writes_the_report(tmp_path: Path, capsys):
    target = tmp_path / "report.md"
    assert main(["verify", "--claims", "BKM12-4*,K01-2.2", "--report", str(target)]) == 0
    text = target.read_text()
    assert "## Summary per paper" in text and "## Errata" in text
    assert "| BKM12-4 | $" in text and "\\rho" in text
    capsys.readouterr()


def test_cli_refuses_an_unwritable_report_path_and_writes_nothing(tmp_path: Path, capsys):
    target = tmp_path / "missing-folder" / "report.md"
    assert main(["verify", "--claims", "BKM12-4", "--report", str(target)]) == 2
    assert not target.exists()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot write the report" in err[0]
