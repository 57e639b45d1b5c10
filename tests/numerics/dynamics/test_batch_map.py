"""The compiled batch map (numerics/dynamics/batch_map.py): against the single-point StroboscopicMap
(the Taylor method at a much tighter tolerance, an independent route), points independent of each
other (a failing point spoils no other), and the sweep reducers that use it."""

from __future__ import annotations

import math

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.dynamics.batch_map import BatchStroboscopicMap, batch_map_available
from chaplygin.numerics.dynamics.poincare import StroboscopicMap

CODE = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])

pytestmark = pytest.mark.skipif(not batch_map_available(CODE), reason="no C compiler")

#: Generic non-dyadic parameters (I1, I2, I3, D, J_off, delta, K1, K2, K3, Omega), one row per
#: point: BM20 Fig. 5's neighbourhood, Fig. 2's, and a third set.
PARAMS = [
    [4.1, 3.3, 2.2, 4.385, 0.13, 2.0, -6.0, -3.0, -9.0, 1.07],
    [3.7, 2.9, 2.3, 1.5, -0.21, 1.2, 3.0, -1.0, -2.0, 0.43],
    [4.0, 3.1, 1.9, 2.7, 0.05, 0.7, 1.3, -2.2, 0.9, 1.9],
]


def _states() -> list[list[float]]:
    rows = [
        [2.18, 1.40, 1.5, 0.68, -0.56, -0.47],
        [0.3, -0.7, 1.1, 0.6, 0.64, -0.48],
        [-1.3, 0.2, 0.9, -0.36, 0.48, 0.8],
    ]
    return [[*y[:3], *(np.array(y[3:]) / np.linalg.norm(y[3:]))] for y in rows]


def test_batch_matches_the_taylor_map_within_the_accumulated_tolerance():
    """Every point (its own parameters and period) against StroboscopicMap at rtol = 1e-15:
    the relative error after k periods stays within the sum of the local tolerances of the
    steps taken (rtol per step, no amplification allowed), and shrinks with rtol."""
    y0 = _states()
    n, transient = 3, 1
    errors = {}
    for rtol in (1e-8, 1e-12):
        r = BatchStroboscopicMap(CODE, rtol=rtol, atol=rtol).run(y0, PARAMS, n, transient)
        assert (r.status == 0).all() and r.y.shape == (3, n, 6)
        for j, p in enumerate(PARAMS):
            ref = StroboscopicMap(CODE, p, rtol=1e-15, atol=1e-15).orbit(y0[j], n, transient).y
            err = float(np.abs(r.y[j] - ref).max() / np.abs(ref).max())
            assert err <= rtol * r.steps[j], (rtol, j, err, int(r.steps[j]))
            errors[rtol, j] = err
    for j in range(3):  # tolerance proportionality: 4 decades of rtol buy at least 2 of error
        assert errors[1e-12, j] <= 1e-2 * errors[1e-8, j]


def test_a_failing_point_spoils_no_other():
    """A non-finite state and an overflowing one fail with their own status (NaN points); the
    other points are bit-identical to the same points run alone."""
    y0 = _states()
    bad_nan = [math.nan, *y0[0][1:]]
    bad_huge = [1e300, 1e300, -1e300, *y0[1][3:]]
    rows = [y0[0], bad_nan, y0[1], bad_huge, y0[2]]
    params = [PARAMS[0], PARAMS[0], PARAMS[1], PARAMS[1], PARAMS[2]]
    bm = BatchStroboscopicMap(CODE, rtol=1e-10, atol=1e-10)
    r = bm.run(rows, params, n=4, transient=2)
    assert r.lockstep == bm.lockstep_available
    assert list(r.status) == [0, 3, 0, r.status[3], 0] and r.status[3] != 0
    assert np.isnan(r.y[1]).all() and np.isnan(r.y[3]).all()
    for j, (y, p) in zip((0, 2, 4), zip(y0, PARAMS, strict=True), strict=True):
        alone = bm.run([y], [p], n=4, transient=2)
        assert np.array_equal(alone.y[0], r.y[j])
        assert alone.evaluations[0] == r.evaluations[j]


def test_lockstep_lanes_are_bit_identical_to_one_point_at_a_time():
    """Seven points (more than the 4 lanes, so lanes are refilled; one fails at once, one has
    its own Omega and D) in vector lanes give the bits and the work counts of the one-point
    driver: each lane does the same IEEE operations."""
    bm = BatchStroboscopicMap(CODE, rtol=1e-11, atol=1e-11)
    if not bm.lockstep_available:
        pytest.skip("the model's right-hand side has no vector form")
    y0 = _states()
    rows = [y0[0], y0[1], [math.nan, *y0[2][1:]], y0[2], y0[0], y0[1], y0[2]]
    params = [PARAMS[0], PARAMS[1], PARAMS[2], PARAMS[2], PARAMS[1], PARAMS[0], PARAMS[2]]
    params[4] = [*PARAMS[1][:3], 1.7320508, *PARAMS[1][4:9], 0.6180339]
    lanes = bm.run(rows, params, n=3, transient=2, lockstep=True)
    single = bm.run(rows, params, n=3, transient=2, lockstep=False)
    assert lanes.lockstep and not single.lockstep
    assert list(lanes.status) == list(single.status) == [0, 0, 3, 0, 0, 0, 0]
    assert np.array_equal(lanes.y, single.y, equal_nan=True)
    for counter in ("steps", "rejected", "evaluations"):
        assert np.array_equal(getattr(lanes, counter), getattr(single, counter)), counter


def test_work_is_counted():
    r = BatchStroboscopicMap(CODE, rtol=1e-12).run([_states()[0]], [PARAMS[0]], n=5)
    # DOP853: 12 evaluations per step attempt, plus the first evaluation and the starting step
    assert r.evaluations[0] == 12 * (r.steps[0] + r.rejected[0]) + 2


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"y0": [[1, 2, 3]]}, "shape"),
        ({"params": [PARAMS[0][:-1]]}, "shape"),
        ({"n": 0}, "n >= 1"),
        ({"params": [[*PARAMS[0][:9], -1.07]]}, "Omega must be positive"),
        ({"params": [[*PARAMS[0][:9], math.inf]]}, "finite"),
    ],
)
def test_bad_input_is_a_user_error(kwargs, match):
    args = {"y0": [_states()[0]], "params": [PARAMS[0]], "n": 2}
    args.update(kwargs)
    with pytest.raises(UserInputError, match=match):
        BatchStroboscopicMap(CODE).run(**args)


def test_an_autonomous_model_is_refused():
    with pytest.raises(UserInputError, match="Omega"):
        BatchStroboscopicMap(load_model_code("chaplygin_ball"))


def test_map_throughput_reports_the_work_it_did():
    """The bench section (no timing asserted): every row present, the batch map's counts
    consistent (12 evaluations per step attempt, 2 to start), its first periods near the Taylor
    run's."""
    from chaplygin.verify.bench_map import map_throughput

    row = map_throughput(periods=12, repeats=1, peers=False)
    for name in ("ours_taylor_c", "ours_batch1", "ours_batch4", "ours_batch16"):
        assert row[f"{name}_us"] > 0 and row[f"{name}_cpu_us"] >= 0
    steps = row["ours_batch_steps_per_period"] + row["ours_batch_rejected_per_period"]
    assert row["ours_batch_rhs_per_period"] == pytest.approx(12 * steps + 2 / 12, rel=1e-12)
    # 10 periods of about 70 steps, each within rtol = 1e-12 (and the Taylor run's own error)
    assert row["ours_batch_vs_taylor_first_10_periods"] < 1e-12 * 12 * 70 * 10
    for name in ("ours_taylor_batch1", "ours_taylor_batch4", "ours_taylor_batch16"):
        assert row[f"{name}_us"] > 0 and row[f"{name}_cpu_us"] >= 0
    # the Taylor batch takes the single-point Taylor run's steps: the same map points up to
    # the rounding of the sampling times (a few rtol)
    assert row["ours_taylor_batch_vs_taylor_first_10_periods"] < 4e-12 * 10
    assert row["ours_taylor_batch_steps_per_period"] > 0


def test_the_equal_accuracy_section_picks_a_taylor_tolerance_no_less_accurate():
    """The bench's Taylor-against-DOP853 section (no timing asserted): the Taylor tolerance
    it picks is one of those tried whose error is at most the DOP853's; every tolerance is
    timed."""
    from chaplygin.verify.bench_map import EQUAL_ACCURACY_RTOLS, taylor_map_equal_accuracy

    row = taylor_map_equal_accuracy(periods=12, repeats=1, points=5)
    assert row["dop853_error"] > 0 and row["dop853_us"] > 0
    assert row["taylor_error"] <= row["dop853_error"] and row["taylor_rtol"] in EQUAL_ACCURACY_RTOLS
    assert all(row[f"taylor_{tol:g}_us"] > 0 for tol in EQUAL_ACCURACY_RTOLS)
    assert row["ratio_taylor_to_dop853"] == row["taylor_us"] / row["dop853_us"]
    with pytest.raises(UserInputError):
        taylor_map_equal_accuracy(periods=5)


# --------------------------------------------------------------- the Taylor batch (method="taylor")


def test_taylor_batch_equals_the_single_point_taylor_map():
    """The same method (the generated Taylor steps, dense output at the sampling times) as
    StroboscopicMap with method "taylor" at the same tolerances: every point, with its own
    parameters and period, agrees to a few rtol (the sampling times are the only difference:
    rounded once from a double-double here, from 40 digits there)."""
    y0 = _states()
    n, transient, rtol = 4, 2, 1e-11
    r = BatchStroboscopicMap(CODE, rtol=rtol, atol=rtol, method="taylor").run(
        y0, PARAMS, n, transient
    )
    assert r.method == "taylor" and r.lockstep and r.y.shape == (3, n, 6)
    assert (r.status == 0).all() and (r.steps > 0).all() and (r.rejected == 0).all()
    for j, p in enumerate(PARAMS):
        ref = StroboscopicMap(CODE, p, rtol=rtol, atol=rtol, method="taylor").orbit(
            y0[j], n, transient
        )
        assert r.steps[j] == ref.nsteps  # the same steps
        assert float(np.abs(r.y[j] - ref.y).max() / np.abs(ref.y).max()) <= 4 * rtol


def test_taylor_batch_agrees_with_the_dop853_batch():
    """An independent method: the Taylor batch against the DOP853 batch at the same rtol; the
    difference stays within the two methods' accumulated local tolerances (rtol per step of
    each) and shrinks with rtol (the control: 4 decades of rtol buy at least 2 of agreement)."""
    y0 = _states()
    n, transient = 3, 3
    diffs = {}
    for rtol in (1e-7, 1e-11):
        t = BatchStroboscopicMap(CODE, rtol=rtol, atol=rtol, method="taylor").run(
            y0, PARAMS, n, transient
        )
        d = BatchStroboscopicMap(CODE, rtol=rtol, atol=rtol).run(y0, PARAMS, n, transient)
        assert (t.status == 0).all() and (d.status == 0).all()
        for j in range(len(PARAMS)):
            diff = float(np.abs(t.y[j] - d.y[j]).max() / np.abs(d.y[j]).max())
            assert diff <= rtol * (t.steps[j] + d.steps[j]), (rtol, j, diff)
            diffs[rtol, j] = diff
    for j in range(len(PARAMS)):
        assert diffs[1e-11, j] <= 1e-2 * diffs[1e-7, j]


def test_taylor_batch_a_failing_point_spoils_no_other():
    """A NaN parameter (D, given straight to the C entry point: run() refuses non-finite
    parameters), a NaN state and an overflowing state fail with their own status and NaN map
    points; the other points are bit-identical to the same points run alone."""
    y0 = _states()
    bm = BatchStroboscopicMap(CODE, rtol=1e-10, atol=1e-10, method="taylor")
    nan_d = [*PARAMS[1][:3], math.nan, *PARAMS[1][4:]]
    rows = [y0[0], y0[1], [math.nan, *y0[2][1:]], y0[2], [1e300, 1e300, -1e300, *y0[1][3:]]]
    params = [PARAMS[0], nan_d, PARAMS[2], PARAMS[2], PARAMS[1]]
    r = bm._advance(np.array(rows), np.array(params), np.zeros(5), 4, 2, lockstep=False)
    assert list(r.status[:4]) == [0, 3, 3, 0] and r.status[4] != 0
    assert np.isnan(r.y[[1, 2, 4]]).all() and not np.isnan(r.y[[0, 3]]).any()
    for j, (y, p) in ((0, (y0[0], PARAMS[0])), (3, (y0[2], PARAMS[2]))):
        alone = bm.run([y], [p], n=4, transient=2)
        assert np.array_equal(alone.y[0], r.y[j]) and alone.steps[0] == r.steps[j]


def test_taylor_batch_lands_on_the_sampling_times_from_t0():
    """transient = 0 records y0 itself first; a phase t0 != 0 shifts the sampling times (the
    same map points as the single-point map from that phase)."""
    y0, p, rtol = _states()[1], PARAMS[1], 1e-12
    bm = BatchStroboscopicMap(CODE, rtol=rtol, atol=rtol, method="taylor")
    r = bm.run([y0], [p], n=3, t0=0.37)
    assert np.array_equal(r.y[0, 0], y0)
    ref = StroboscopicMap(CODE, p, rtol=rtol, atol=rtol).orbit(y0, 3, t0=0.37).y
    assert float(np.abs(r.y[0] - ref).max() / np.abs(ref).max()) <= 4 * rtol


def test_an_unknown_batch_method_is_a_user_error():
    with pytest.raises(UserInputError, match="method"):
        BatchStroboscopicMap(CODE, method="rk4")
    with pytest.raises(UserInputError, match="method"):
        batch_map_available(CODE, "rk4")
