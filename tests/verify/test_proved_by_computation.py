"""The verdict of a claim decided by enclosures: ``proved by computation``, ``refuted`` with its
witness, or ``numeric`` (not the expected verdict) when the enclosures decide nothing."""

from __future__ import annotations

import pytest
from chaplygin.verify.claims import REGISTRY
from chaplygin.verify.claims.base import Computed, ComputedClaim
from chaplygin.verify.verdict import check_claim


def _claim(decided: str, expected: str = "holds") -> ComputedClaim:
    return ComputedClaim(
        id=f"TEST-{decided}-{expected}",
        source="test",
        kind="solution",
        statement="a statement decided by enclosures",
        system="chaplygin_ball",
        compute=lambda: Computed(
            error=0.0, bound=0.0, what="a test", values={"box": "[1 +/- 1e-9]"}, decided=decided
        ),
        rigorous=True,
        expected=expected,
    )


@pytest.mark.parametrize(
    ("decided", "expected", "verdict", "ok"),
    [
        ("proved", "holds", "proved by computation", True),
        ("refuted", "fails", "refuted", True),
        ("refuted", "holds", "refuted", False),
        ("proved", "fails", "proved by computation", False),
        ("undecided", "holds", "numeric", False),
        ("undecided", "fails", "numeric", False),
    ],
)
def test_verdict_of_a_rigorous_claim(decided: str, expected: str, verdict: str, ok: bool) -> None:
    v = check_claim(_claim(decided, expected))
    assert (v.verdict, v.ok) == (verdict, ok)
    assert "ball arithmetic" in v.method
    if verdict == "refuted":
        assert v.witness == {"box": "[1 +/- 1e-9]"}


def test_the_bm20_cycle_claims_are_rigorous_with_a_control() -> None:
    ids = ["BM20-Fig7A.cycle", "BM20-Fig7B.cycle", "BM20-Fig7C.cycle/control"]
    claims = [REGISTRY[i] for i in ids]
    assert all(c.rigorous for c in claims)
    assert [c.expected_verdict() for c in claims] == [
        "proved by computation",
        "proved by computation",
        "refuted",
    ]
