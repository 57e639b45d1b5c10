"""The claim registry covers every checkable FORMULAS.md entry of the systems issues."""

from __future__ import annotations

from pathlib import Path

import pytest
from chaplygin.verify.claims import Claim, select_claims
from chaplygin.verify.cli import main
from chaplygin.verify.coverage import (
    FORMULAS_ENTRIES,
    SECTIONS,
    coverage,
    covered_entry,
    parse_formulas,
)

SHEET = Path(__file__).resolve().parents[3] / "shared" / "FORMULAS.md"


@pytest.mark.skipif(not SHEET.exists(), reason="shared/FORMULAS.md is not beside the checkout")
def test_table_is_the_sheet_transcribed():
    assert parse_formulas(SHEET.read_text()) == list(FORMULAS_ENTRIES)


def test_every_section_is_known_and_ids_are_unique():
    ids = [e[0] for e in FORMULAS_ENTRIES]
    assert len(ids) == len(set(ids))
    assert {e[1] for e in FORMULAS_ENTRIES} <= set(SECTIONS)


@pytest.mark.parametrize(
    ("claim_id", "entry"),
    [
        ("BKM12-2.1M.N3", "BKM12-2.1M"),
        ("BKM12-2", "BKM12-2"),
        ("K01-2.3.h", "K01-2.3"),
        ("K01-2.27/literal", "K01-2.27"),
        ("BKM12-2.3E/literal", "BKM12-2.3"),
        ("BKM12-3.1/control-sign", "BKM12-3.1"),
        ("MODEL:chaplygin_ball.density", None),
    ],
)
def test_a_claim_speaks_about_the_longest_entry_at_a_boundary(claim_id, entry):
    assert covered_entry(claim_id) == entry


def test_the_foundation_and_systems_sections_are_covered():
    """Issues 2 and 3: every checkable entry has a claim expected to hold, and every
    literal reading FORMULAS.md marks FAILED has its /literal claim."""
    rows = coverage(select_claims())
    missing = [r.id for r in rows if r.issue in (2, 3) and not r.covered]
    assert missing == []
    literal = [r for r in rows if r.issue in (2, 3) and r.literal_failed]
    assert {r.id for r in literal} >= {"BM20-2.6", "M03-1.5", "M03-1.7", "M03-2.2", "BKM12-2.3"}


def _claim(claim_id: str, expected: str = "holds", covers=()) -> Claim:
    return Claim(
        id=claim_id,
        source="",
        kind="equation",
        statement="",
        system="chaplygin_ball",
        effects=(),
        build=lambda m: None,
        expected=expected,
        covers=covers,
    )


def test_controls_alone_do_not_cover_and_failed_entries_need_their_literal_reading():
    rows = {r.id: r for r in coverage([_claim("BKM12-4/control-x", "fails")])}
    assert not rows["BKM12-4"].covered
    rows = {r.id: r for r in coverage([_claim("M03-1.5")])}
    assert not rows["M03-1.5"].covered  # FAILED as transcribed: the literal must be refuted
    rows = {r.id: r for r in coverage([_claim("M03-1.5"), _claim("M03-1.5/literal", "fails")])}
    assert rows["M03-1.5"].covered
    rows = {r.id: r for r in coverage([_claim("M03-2.5/control-y", "fails", ("M03-2.4",))])}
    assert rows["M03-2.4"].covered and not rows["M03-2.5"].covered


def test_cli_coverage_lists_sections(capsys):
    assert main(["verify", "--coverage"]) == 0
    out = capsys.readouterr().out
    assert "| 1.6 BKM12 §2.1 spherical support | 3 | 11 | 11 | - |" in out
    assert "checkable entries in FORMULAS.md" in out
