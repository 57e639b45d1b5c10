"""Benchmarks (pytest-benchmark; skipped in the default test run).

Run: ``pytest tests/benchmarks --benchmark-enable --benchmark-only``; compare medians of the
same run (the machines are shared and noisy), e.g. with ``--benchmark-group-by=group``.
"""

from __future__ import annotations

import numpy as np
import pytest
from chaplygin.numerics import integrate, load_model_code
from reference import REFERENCE_PARAMS, REFERENCE_Y0

pytestmark = pytest.mark.benchmark


@pytest.fixture(scope="module")
def ball():
    code = load_model_code("chaplygin_ball")
    y = np.array([0.7, -0.4, 0.5, 0.2, 0.3, np.sqrt(0.87)])
    p = np.array([1.0, 2.0, 3.0, 1.0])
    return code, y, p


@pytest.mark.benchmark(group="rhs call")
@pytest.mark.parametrize("backend", ["numpy", "c"])
def test_rhs_call(benchmark, ball, backend):
    code, y, p = ball
    fun = code.numpy.rhs if backend == "numpy" else code.compiled().rhs
    out = benchmark(fun, 0.0, y, p)
    assert np.all(np.isfinite(out))


@pytest.mark.benchmark(group="DOP853 reference problem, T = 1000, rtol = atol = 1e-12")
@pytest.mark.parametrize("backend", ["numpy", "c"])
def test_reference_problem(benchmark, backend):
    def run():
        return integrate(
            "chaplygin_ball",
            REFERENCE_Y0,
            1000,
            REFERENCE_PARAMS,
            rtol=1e-12,
            atol=1e-12,
            backend=backend,
        )

    r = benchmark.pedantic(run, rounds=5, iterations=1)
    assert r.drift["H"] <= 1e-10
