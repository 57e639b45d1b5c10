"""Benchmarks of Delta along the separatrix (pytest-benchmark; skipped by default).

Run: ``pytest tests/benchmarks/test_bench_separatrix.py --benchmark-enable --benchmark-only``.
"""

from __future__ import annotations

import mpmath
import pytest
from chaplygin.numerics.ball.separatrix import delta_closed_form, delta_ode, delta_quadrature, mu_of

pytestmark = pytest.mark.benchmark

I, D, B = (1, 3, 5), 1, 1


@pytest.mark.benchmark(group="delta 30 digits")
def test_delta_ode_taylor_30_digits(benchmark):
    r = benchmark.pedantic(delta_ode, args=(I, D, B, 30), rounds=3, iterations=1)
    with mpmath.workdps(40):
        assert abs(r["delta"] - delta_closed_form(mu_of(I, D), B, 40)) < mpmath.mpf(10) ** -30


@pytest.mark.benchmark(group="delta 30 digits")
def test_delta_quadrature_30_digits(benchmark):
    with mpmath.workdps(40):
        mu = mu_of(I, D)
    v = benchmark.pedantic(delta_quadrature, args=(mu, B, 30), rounds=3, iterations=1)
    assert abs(v - delta_closed_form(mu, B, 40)) < mpmath.mpf(10) ** -30
