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


def test_the_k01_critical_energy_claims_are_rigorous_with_controls() -> None:
    """K01 Fig. 6(f): two critical energies to prove, FORMULAS.md's third resonance (atan2's
    branch cut) and the printed energy as controls to refute."""
    ids = [
        "K01-Fig6f.critical",
        "K01-Fig6f.critical-2",
        "K01-Fig6f.critical/resonance-0.171990",
        "K01-Fig6f.critical/control-printed",
    ]
    claims = [REGISTRY[i] for i in ids]
    assert all(isinstance(c, ComputedClaim) and c.rigorous for c in claims)
    assert [c.expected_verdict() for c in claims] == [
        "proved by computation",
        "proved by computation",
        "refuted",
        "refuted",
    ]


def test_an_enclosure_that_blows_up_leaves_the_claim_numeric_with_where_it_grew() -> None:
    """A rigorous claim whose flow cannot be enclosed (x' = 3 x from a ball of radius 1e-30,
    limit 1e-20: passed at t = ln(5e9)/3 = 7.44) is not decided: verdict ``numeric`` (not
    the expected one), the widest enclosure and the growth report in the witness."""
    from types import SimpleNamespace

    from chaplygin.numerics.validated import enclose_flow, to_ball, working_precision
    from flint import arb

    def coefficients(t0, y, p, order, lib):  # noqa: ANN001, ANN202
        c = [y[0]]
        for k in range(order):
            c.append(p[0] * c[k] / (k + 1))
        return [c]

    code = SimpleNamespace(
        name="growth", state=("x",), params=("p",),
        taylor=SimpleNamespace(taylor_coefficients=coefficients),
    )  # fmt: skip

    def run() -> Computed:
        with working_precision(128):
            enclose_flow(
                code, ["3"], [to_ball("1") + arb(0, 1e-30)], 0, 20, max_width=1e-20, tol=1e-36
            )
        return Computed(error=0.0, bound=0.0, what="never reached", decided="proved")

    claim = ComputedClaim(
        id="TEST-blow-up", source="test", kind="solution", statement="a long unstable run",
        system="chaplygin_ball", compute=run, rigorous=True,
    )  # fmt: skip
    v = check_claim(claim)
    assert (v.verdict, v.ok) == ("numeric", False)
    assert "blew up" in v.method and "grew past 1e-20" in v.method
    widest, at = v.witness["widest enclosure"].split(" at t = ")
    assert float(widest) > 1e-20 and abs(float(at) - 7.44) < 0.5


def test_the_delta_claims_are_rigorous_with_a_control() -> None:
    ids = [
        "K01-Fig4.delta-enclosed-1",
        "K01-Fig4.delta-enclosed-2",
        "K01-3.7.enclosed/control-ch(pi mu)",
    ]
    claims = [REGISTRY[i] for i in ids]
    assert all(c.rigorous for c in claims)
    assert [c.expected_verdict() for c in claims] == [
        "proved by computation",
        "proved by computation",
        "refuted",
    ]
    # every hypothesis the proof uses is a claim of the catalogue, named in its 'what'
    assert all(h in REGISTRY for h in ("K01-3.4", "K01-3.5", "K01-3.7"))


def test_a_delta_enclosure_that_fails_leaves_the_claim_numeric(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from chaplygin.numerics.validated import EnclosureError
    from chaplygin.verify.claims import enclosures_delta

    def fails(key: str) -> None:
        raise EnclosureError("the enclosure grew past 1", [1e-20, 2.0], [0.5, 1.5])

    monkeypatch.setattr(enclosures_delta, "_enclosure", fails)
    v = check_claim(REGISTRY["K01-Fig4.delta-enclosed-1"])
    assert (v.verdict, v.ok) == ("numeric", False)
    assert "blew up" in v.method
