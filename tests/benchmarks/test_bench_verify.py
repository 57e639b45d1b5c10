"""Benchmark of the whole verification (per claim in ``extra_info``, total as the timing).

Run: ``pytest tests/benchmarks/test_bench_verify.py --benchmark-enable --benchmark-only``.
The issue's target: every claim of the four papers in under 120 s on 2 cores. Models are
derived (or read from the on-disk model cache) once, outside the timing; ``serial`` checks
in this process, ``parallel`` with one worker process per available CPU.
"""

from __future__ import annotations

import pytest
from chaplygin.verify.claims import select_claims
from chaplygin.verify.verdict import check_claims, default_jobs


@pytest.mark.benchmark(group="verify")
@pytest.mark.parametrize("mode", ["serial", "parallel"])
def test_verify_all_claims(benchmark, mode):
    claims = select_claims()
    for claim in claims:  # derive every model once, outside the timing
        claim.model()
    jobs = 1 if mode == "serial" else default_jobs()

    def run():
        return check_claims(claims, jobs=jobs)

    verdicts = benchmark.pedantic(run, rounds=1, iterations=1)
    benchmark.extra_info["jobs"] = jobs
    benchmark.extra_info["claims"] = len(verdicts)
    benchmark.extra_info["per_claim_seconds"] = {v.id: round(v.seconds, 4) for v in verdicts}
    benchmark.extra_info["total_check_seconds"] = round(sum(v.seconds for v in verdicts), 2)
    assert all(v.ok for v in verdicts)
