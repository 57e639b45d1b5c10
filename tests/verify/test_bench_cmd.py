"""``chaplygin bench``: the quick work-precision study writes its table, plot and rows.

Timings are never asserted (they belong to benchmarks); accuracy is: every measured row has
a finite error against the high-precision reference, and the Taylor rows reach their
requested precision.
"""

from __future__ import annotations

import json
import math

import mpmath
import numpy as np
import pytest
from chaplygin.numerics import load_model_code
from chaplygin.verify.bench import PROBLEMS, peers_available, separatrix_state
from chaplygin.verify.cli import main

FIELDS = {"problem", "method", "rhs", "precision", "rtol", "T", "error", "drift", "median_s",
          "runs", "steps", "nfev", "note"}


@pytest.fixture(scope="module")
def quick_study(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        status = main(["bench", "--quick", "--json", "--problems", "reference", "--out", str(out)])
    return status, json.loads(buf.getvalue()), out


@pytest.mark.slow
def test_quick_bench_writes_table_and_plot(quick_study):
    status, rows, out = quick_study
    assert status == 0
    table = (out / "bench.md").read_text()
    assert "| method |" in table and "final error" in table and "quick" in table.lower()
    png = (out / "bench.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000
    saved = json.loads((out / "bench.json").read_text())
    assert saved["rows"] == rows
    assert saved["rhs_call_s"] and all(v > 0 for v in saved["rhs_call_s"].values())
    # the reference is cached in the output folder
    assert list(out.glob("reference_reference_*.json"))


@pytest.mark.slow
def test_quick_bench_rows_have_fields_and_finite_errors(quick_study):
    _, rows, _ = quick_study
    assert rows and all(FIELDS <= set(r) for r in rows)
    measured = [r for r in rows if r["median_s"] is not None]
    families = {(r["method"], r["rhs"], r["precision"]) for r in measured}
    for method in ("RK45", "DOP853", "LSODA", "Radau"):
        assert {(method, "numpy", "double"), (method, "C", "double")} <= families
    assert ("odefun", "mpmath", "50 digits") in families
    for r in measured:
        assert math.isfinite(r["error"]) and r["error"] >= 0, r
        assert all(math.isfinite(v) for v in r["drift"].values()), r
        assert r["median_s"] > 0 and "quick" in r["note"]
    # Taylor rows meet their precision: error below 1e3 x the working epsilon (short spans)
    eps = {"double": 2.0**-52, "quad": 2.0**-112, "30 digits": 1e-29, "50 digits": 1e-49,
           "100 digits": 1e-99}
    eps["quad (real128)"] = eps["quad"]
    for r in measured:
        if r["method"] in ("taylor", "heyoka", "jitcode"):  # peers: independent implementations
            assert r["error"] <= max(1e3 * eps[r["precision"]], 1e2 * r["rtol"]), r
    for name, ok in peers_available().items():
        if not ok:
            assert any(r["method"] == name and "not installed" in r["note"] for r in rows)


def test_separatrix_point_is_on_the_separatrix():
    """M = C gamma at the energy h2 = C^2/(2 I2) of the middle axis (K01-3.3seg, K01-3.4)."""
    code = load_model_code("chaplygin_ball")
    st = separatrix_state(dps=40)
    with mpmath.workdps(40):
        y = [mpmath.mpf(v) for v in (*st["M"], *st["gamma"])]
        p = [mpmath.mpf(v) for v in (1, 2, 3, 1)]
        F = dict(zip(code.integral_names, code.mpmath.integrals(0, y, p), strict=True))
        assert abs(F["(gamma,gamma)"] - 1) < mpmath.mpf(10) ** -35
        assert abs(F["H"] - mpmath.mpf(1) / 4) < mpmath.mpf(10) ** -35
    # negative control: moved along the segment M = C gamma (gamma tilted towards e1), the
    # energy leaves h2 at first order (e2 is tangent to the separatrix itself, e1 is not)
    g = np.array([float(v) for v in st["gamma"]]) + np.array([0.01, 0.0, 0.0])
    g /= np.linalg.norm(g)
    F2 = code.numpy.integrals(0.0, np.concatenate([g, g]), np.array([1.0, 2.0, 3.0, 1.0]))
    assert abs(F2[code.integral_names.index("H")] - 0.25) > 1e-6
    assert set(PROBLEMS) == {"reference", "separatrix"}


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["--problems", "nope"], "unknown problem"),
        (["--repeats", "0"], "--repeats"),
        (["--out", "/nonexistent-dir/x/y"], "parent folder"),
    ],
)
def test_bench_bad_input_exits_2_with_one_line(args, fragment, capsys, tmp_path):
    argv = ["bench", "--quick", *args]
    if "--out" not in args:
        argv += ["--out", str(tmp_path / "o")]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert fragment in err and "\n" not in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


def test_bench_out_is_a_file(capsys, tmp_path):
    f = tmp_path / "file.txt"
    f.write_text("x")
    assert main(["bench", "--quick", "--out", str(f)]) == 2
    assert "not a folder" in capsys.readouterr().err
    assert f.read_text() == "x"


def _row(method, precision, rtol, error, median_s, **kw):
    base = {"problem": "reference", "method": method, "rhs": "C", "precision": precision,
            "rtol": rtol, "T": 50.0, "error": error, "drift": {}, "median_s": median_s,
            "runs": 5, "steps": None, "nfev": None, "note": "", "call_s": None,
            "setup_s": None, "evidence_s": None, "propagate_s": None}
    return {**base, **kw}


def test_speed_targets_compare_at_equal_or_better_error():
    """The fastest of our rows whose error is at most EQUAL_ERROR_FACTOR x heyoka's is
    compared; a faster row with a worse error is not; no row reaching it says so."""
    from chaplygin.verify.bench_report import EQUAL_ERROR_FACTOR, speed_targets

    rows = [
        _row("heyoka", "30 digits", 1e-30, 2.0e-29, 0.060),
        _row("heyoka", "50 digits", 1e-50, 3.0e-49, 0.190),
        # fast but 10x worse than heyoka: not eligible
        _row("taylor", "30 digits", 1e-26, 2.0e-28, 0.001, call_s=0.002, setup_s=1e-4,
             evidence_s=1e-4, propagate_s=0.0015),
        # eligible (within the factor), slower
        _row("taylor", "30 digits", 1e-28, EQUAL_ERROR_FACTOR * 2.0e-29, 0.010, call_s=0.012,
             setup_s=1e-3, evidence_s=1e-3, propagate_s=0.011),
        _row("taylor", "50 digits", 1e-48, 1e-47, 0.1, call_s=0.15, setup_s=1e-3,
             evidence_s=1e-3, propagate_s=0.14),
    ]
    lines = speed_targets({"rows": rows})
    assert len(lines) == 2
    assert "30 digits" in lines[0] and "ratio 0.20 / 0.18" in lines[0] and "met)" in lines[0]
    assert "integrate() 12 ms" in lines[0] and "rtol 1e-28" in lines[0]
    assert "50 digits" in lines[1] and "no Taylor row" in lines[1] and "missed" in lines[1]
    assert "closest: 1.0e-47 at rtol 1e-48, 33.3x heyoka's error, in 0.79x its time" in lines[1]
    # a ratio above one with the Propagator below one is reported as such
    rows[3]["call_s"], rows[3]["propagate_s"] = 0.07, 0.05
    assert "met by Propagator only" in speed_targets({"rows": rows})[0]
    rows[3]["propagate_s"] = 0.08
    assert "missed" in speed_targets({"rows": rows})[0]


def test_short_runs_are_repeated_to_a_time_budget():
    from chaplygin.verify.bench_timing import (
        SHORT_RUN_BUDGET_S,
        SHORT_RUNS_MAX,
        run_count,
        timed_runs,
    )

    assert run_count(1.0, 5) == 5  # long runs: the asked number
    assert run_count(SHORT_RUN_BUDGET_S / 50, 5) == 50
    assert run_count(1e-9, 5) == SHORT_RUNS_MAX
    assert run_count(1e-9, 1) == 1  # one run asked for: one run
    calls = []

    def fn():
        calls.append(1)
        return SHORT_RUN_BUDGET_S / 20, len(calls)

    times, last = timed_runs(fn, 5)
    assert len(times) == len(calls) == last == 20


def test_the_verify_time_row_runs_the_command_and_counts_its_verdicts():
    """bench's verify-time row (no timing asserted): the command in its own process on a
    claim and its control, its verdicts counted as verify decides them; a selection that
    matches nothing is the command's error, raised as ComputationError."""
    from chaplygin.derive.errors import ComputationError
    from chaplygin.verify.bench_verify import verify_time

    row = verify_time("K01-2.2,BKM12-4/control-rho=1", jobs=1)
    assert row["claims"] == 2 and row["unexpected"] == 0
    assert row["verdicts"] == {"proved": 1, "refuted": 1}
    assert row["wall_s"] > row["checking_s"] > 0
    with pytest.raises(ComputationError):
        verify_time("NO-SUCH-CLAIM-*")


def test_the_enclosure_row_compares_an_enclosure_with_the_floating_point_run():
    """bench's enclosure row (no timing asserted): one BM20 period enclosed from a point is
    narrower than over a 1e-13 box and than one rounding of a double; the ratios are the
    times' ratios."""
    from chaplygin.verify.bench_enclosure import enclosure_cost

    row = enclosure_cost(1, proof=False)
    assert 0 < row["width from the point"] < 2**-52
    assert row["width from the point"] < row["width over the box"]
    point = row["one period, enclosure from a point (s)"]
    double = row["one period, double Taylor rtol 1e-15 (s)"]
    assert row["ratio point enclosure / double"] == point / double
    # the steady rotation's row: the enclosed trace agrees with the double one within the
    # double run's tolerance (sqrt(rtol), FloquetResult.tolerance) and is far narrower
    assert row["steady rotation e_2, |double - enclosed| of tr Phi - 4"] < 1e-6
    assert row["steady rotation e_2, width of tr Phi - 4"] < 1e-12
