"""Benchmarks of the generated Taylor integrator against scipy and mpmath (issue 5 §1).

Run: ``pytest tests/benchmarks/test_bench_taylor.py --benchmark-enable --benchmark-only
--benchmark-group-by=group``; the ratios are those of medians in one run, side by side.
Every timed run also asserts its accuracy against a reference at more digits, so a fast
but wrong configuration fails.
"""

from __future__ import annotations

import mpmath
import pytest
from chaplygin.numerics import integrate
from reference import REFERENCE_PARAMS, REFERENCE_Y0

pytestmark = pytest.mark.benchmark

BALL = "chaplygin_ball"


def _final_error(result, ref) -> float:
    with mpmath.workdps(80):
        return float(
            max(abs(mpmath.mpf(a) - b) for a, b in zip(result.y[:, -1], ref.y[:, -1], strict=True))
        )


@pytest.fixture(scope="module")
def ref_1000():
    """T = 1000 in quad (binary128, Taylor): error ~1e-30, far below the double targets."""
    return integrate(BALL, REFERENCE_Y0, 1000, REFERENCE_PARAMS, precision="quad", t_eval=[1000])


@pytest.fixture(scope="module")
def ref_50():
    """T = 50 at 70 digits (Taylor, MPFR)."""
    return integrate(BALL, REFERENCE_Y0, 50, REFERENCE_PARAMS, precision=70, t_eval=[50])


@pytest.mark.benchmark(group="double, T = 1000, final error <= 1e-10")
@pytest.mark.parametrize(
    "method,rtol,atol",
    [("taylor", 1e-13, 1e-13), ("DOP853", 2.5e-14, 2.5e-14)],
    ids=["taylor-C", "DOP853-C-rhs"],
)
def test_double_reference_problem(benchmark, ref_1000, method, rtol, atol):
    integrate(BALL, REFERENCE_Y0, 1, REFERENCE_PARAMS, method=method)  # compile outside

    def run():
        return integrate(
            BALL,
            REFERENCE_Y0,
            1000,
            REFERENCE_PARAMS,
            method=method,
            rtol=rtol,
            atol=atol,
            backend="c",
            t_eval=[1000],
        )

    r = benchmark.pedantic(run, rounds=7, iterations=1, warmup_rounds=1)
    benchmark.extra_info["final_error"] = err = _final_error(r, ref_1000)
    benchmark.extra_info["wall_s"] = r.wall_s
    assert r.success and err <= 1e-10


@pytest.mark.benchmark(group="32+ digits, T = 50")
@pytest.mark.parametrize("method", ["taylor-quad", "odefun-32"])
def test_quad_reference_problem(benchmark, ref_50, method):
    kw = {"precision": "quad"} if method == "taylor-quad" else {"precision": 32, "method": "odefun"}

    def run():
        return integrate(BALL, REFERENCE_Y0, 50, REFERENCE_PARAMS, t_eval=[50], **kw)

    r = benchmark.pedantic(run, rounds=3 if "odefun" in method else 7, iterations=1)
    benchmark.extra_info["final_error"] = err = _final_error(r, ref_50)
    assert r.success and err <= 1e-30


@pytest.mark.benchmark(group="50 digits, T = 50")
@pytest.mark.parametrize("method", ["taylor", "odefun"])
def test_50_digits_reference_problem(benchmark, ref_50, method):
    def run():
        return integrate(
            BALL, REFERENCE_Y0, 50, REFERENCE_PARAMS, precision=50, method=method, t_eval=[50]
        )

    r = benchmark.pedantic(run, rounds=3, iterations=1)
    benchmark.extra_info["final_error"] = err = _final_error(r, ref_50)
    assert r.success and err <= 1e-45
