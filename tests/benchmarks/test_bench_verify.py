"""Benchmark of the whole verification (per claim in ``extra_info``, total as the timing).

Run: ``pytest tests/benchmarks/test_bench_verify.py --benchmark-enable --benchmark-only``.
"""

from __future__ import annotations

import pytest
from chaplygin.verify.claims import select_claims
from chaplygin.verify.verdict import check_claim


@pytest.mark.benchmark(group="verify")
def test_verify_all_claims(benchmark):
    claims = select_claims()
    for claim in claims:  # derive every model once, outside the timing
        claim.model()

    def run():
        return [check_claim(c) for c in claims]

    verdicts = benchmark.pedantic(run, rounds=1, iterations=1)
    benchmark.extra_info["per_claim_seconds"] = {v.id: round(v.seconds, 4) for v in verdicts}
    benchmark.extra_info["total_seconds"] = round(sum(v.seconds for v in verdicts), 2)
    assert all(v.ok for v in verdicts)
