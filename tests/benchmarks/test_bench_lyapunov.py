"""Benchmark of a Lyapunov run (issue 13 part 6; pytest-benchmark, skipped by default).

BM20 Fig. 5's attractor, 3 tangent vectors on the level set, DOP853 with the variational
equations in C, rtol = 1e-10: the time of 1000 forcing periods (divide by 1000 for ms per
period; the issue's target is <= 0.3 ms per period). Run:
``pytest tests/benchmarks/test_bench_lyapunov.py --benchmark-enable --benchmark-only -n 0``.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from chaplygin.numerics.ball.initial_state import state_from_andoyer
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.dynamics.variational import VariationalSystem

pytestmark = pytest.mark.benchmark

FIG5_PARAMS = [4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.07]
PERIODS = 1000


@pytest.mark.benchmark(group="Lyapunov, BM20 Fig. 5, 3 vectors, rtol 1e-10, 1000 periods")
@pytest.mark.parametrize("vectors", ["level_set", "full"])
def test_lyapunov_periods(benchmark, vectors):
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    s = state_from_andoyer(mpmath.mpf(3), mpmath.mpf("0.5"), mpmath.mpf(1), mpmath.mpf(1))
    y0 = np.array([float(v) for v in s["M"] + s["gamma"]])
    system = VariationalSystem(code, FIG5_PARAMS, rtol=1e-10, atol=1e-12)
    _, tangent = system.level_set_basis(0.0, y0)
    V0 = tangent if vectors == "level_set" else np.eye(6)
    tau = 2 * math.pi / 1.07
    # on the attractor first
    _, _, y, V, _ = system.renormalised(y0, V0, 0.0, tau, 200, project=vectors == "level_set")

    def run():
        return system.renormalised(y, V, 200 * tau, tau, PERIODS, project=vectors == "level_set")

    logs, *_ = benchmark.pedantic(run, rounds=3, iterations=1)
    assert np.all(np.isfinite(logs))
