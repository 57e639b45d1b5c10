"""The verification runner: a check that raises, hangs or kills its process gives a
verdict of its own ('error', 'timeout') and the other claims are still decided."""

from __future__ import annotations

import pytest
from chaplygin.verify.claims import REGISTRY, select_claims
from chaplygin.verify.verdict import check_claims, iter_verdicts
from pool_claims import lookup

select_claims()
GOOD = ["K01-2.2", "BKM12-4/control-rho=1", "K01-2.3.h"]  # proved, a refuted control, proved


def test_a_check_that_raises_is_an_error_in_process():
    verdicts = check_claims([lookup("pool/raises"), REGISTRY["K01-2.2"]], jobs=1)
    assert [v.verdict for v in verdicts] == ["error", "proved"]
    assert "ZeroDivisionError" in verdicts[0].method
    assert not verdicts[0].ok and verdicts[1].ok


@pytest.mark.slow
def test_workers_survive_errors_deaths_and_hangs_and_keep_the_order():
    ids = ["pool/raises", GOOD[0], "pool/dies", GOOD[1], "pool/hangs", GOOD[2]]
    claims = [lookup(i) for i in ids]
    verdicts = list(iter_verdicts(claims, jobs=2, timeout=20, lookup=lookup))
    assert [v.id for v in verdicts] == ids
    got = {v.id: v for v in verdicts}
    raised = got["pool/raises"]
    assert raised.verdict == "error" and "ZeroDivisionError" in raised.method
    assert got["pool/dies"].verdict == "error" and "exit code 7" in got["pool/dies"].method
    assert got["pool/hangs"].verdict == "timeout"
    assert got["pool/hangs"].seconds >= 20
    assert not any(got[i].ok for i in ("pool/raises", "pool/dies", "pool/hangs"))
    # the same verdicts as in this process
    for i, v in zip(GOOD, check_claims([REGISTRY[i] for i in GOOD], jobs=1), strict=True):
        assert (got[i].verdict, got[i].residual, got[i].ok) == (v.verdict, v.residual, v.ok)
        assert got[i].ok


def test_a_claim_and_its_controls_are_one_family():
    """claim_families: the claims by the part of their ID before the first '/', in the order
    of their first claim, each with its index in the list; nothing lost, nothing repeated."""
    from chaplygin.verify.verdict import claim_families

    ids = ["BM20-Lyap", "K01-2.2", "BM20-Lyap/control-sign", "K01-2.3.h", "K01-2.2/control-x"]

    class Named:
        def __init__(self, claim_id):
            self.id = claim_id

    families = claim_families([Named(i) for i in ids])
    assert families == [
        [(0, "BM20-Lyap"), (2, "BM20-Lyap/control-sign")],
        [(1, "K01-2.2"), (4, "K01-2.2/control-x")],
        [(3, "K01-2.3.h")],
    ]
