"""Lyapunov spectra of many points in one call (numerics/dynamics/lyapunov_batch.py): every
point's spectrum bit-identical to the one-point function, in the vector lanes and one after
another, with a failing point among them; the sweep's ``lyapunov_max`` through the batch equals
the point-by-point reducer; bad input."""

from __future__ import annotations

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.dynamics.lyapunov import lyapunov_spectrum
from chaplygin.numerics.dynamics.lyapunov_batch import lyapunov_spectra
from chaplygin.numerics.integrators import c_batch

BM20 = ("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
# BM20 Fig. 5: I = diag(4, 3, 2), d = 4.385, J = 0, delta = 2, K = (-6, -3, -9), Omega = 1.07
FIG5_PARAMS = [4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.07]
SETTINGS = {"intervals": 60, "transient": 7, "windows": 4}


def _points(count: int, seed: int = 11) -> tuple[np.ndarray, np.ndarray]:
    """Generic (non-dyadic) parameters and states near Fig. 5's: every point its own Omega
    (its own interval), body and start."""
    rng = np.random.default_rng(seed)
    P = np.tile(np.array(FIG5_PARAMS, dtype=float), (count, 1))
    P[:, 3] += rng.uniform(-0.02, 0.02, count)  # d
    P[:, 4] = rng.uniform(-0.3, 0.3, count)  # J
    P[:, 9] += rng.uniform(-0.05, 0.05, count)  # Omega
    Y = np.tile(np.array([1.3, 2.1, 0.7, 0.6, -0.8, 0.0]), (count, 1))
    Y[:, :3] += rng.uniform(-0.2, 0.2, (count, 3))
    Y[:, 3:] += rng.uniform(-0.1, 0.1, (count, 3))
    Y[:, 3:] /= np.linalg.norm(Y[:, 3:], axis=1)[:, None]
    return P, Y


def _same(a, b) -> bool:
    """Bit for bit (NaN equal to NaN)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and bool(np.all((a == b) | (np.isnan(a) & np.isnan(b))))


@pytest.mark.parametrize("count", [1, None], ids=["largest", "level-set spectrum"])
def test_every_point_is_bit_identical_to_the_one_point_spectrum(count):
    """5 points (not a multiple of the 4 lanes: lanes refill and idle) with their own Omega,
    J, d and start; point 3's body has I1 + I(t) crossing zero within the first forcing
    period (I1 = -(d + J^2) - delta^2/2), so its equations blow up: it fails alone, with its
    status, and every other point's exponents, errors, convergence, divergence and work
    equal those of lyapunov_spectrum on that point alone, bit for bit, in the lanes and one
    after another."""
    code = load_model_code(*BM20)
    P, Y = _points(5)
    P[3, 0] = -(P[3, 3] + P[3, 4] ** 2) - 0.5 * P[3, 5] ** 2
    lanes = lyapunov_spectra(code, P, Y, count=count, **SETTINGS)
    serial = lyapunov_spectra(code, P, Y, count=count, lockstep=False, **SETTINGS)
    assert lanes.lockstep == c_batch.variational_lockstep_available(code)
    assert not serial.lockstep
    assert lanes.status[3] != 0 and lanes.spectra[3] is None
    assert np.array_equal(lanes.status, serial.status)
    assert "done" not in lanes.messages[3]
    for j in (0, 1, 2, 4):
        one = lyapunov_spectrum(code, P[j], Y[j], count=count, **SETTINGS)
        for batch in (lanes, serial):
            spec = batch.spectra[j]
            assert batch.status[j] == 0
            for name in ("exponents", "errors", "convergence", "per_state"):
                assert _same(getattr(spec, name), getattr(one, name)), (j, name)
            assert spec.mean_divergence == one.mean_divergence
            assert spec.divergence_error == one.divergence_error
            assert spec.work == one.work
            assert spec.interval == one.interval and spec.period == one.period
    with pytest.raises(Exception, match="near t"):
        lyapunov_spectrum(code, P[3], Y[3], count=count, **SETTINGS)
    lam, err = lanes.largest()
    assert np.isnan(lam[3]) and np.all(np.isfinite(np.delete(lam, 3)))
    assert np.all(np.delete(err, 3) > 0)


def test_the_exponents_are_the_same_whatever_the_batch_holds():
    """A point's numbers do not depend on its neighbours in the batch or on its position
    (the same point first among 6 and alone; lanes are refilled in another order)."""
    code = load_model_code(*BM20)
    P, Y = _points(6, seed=23)
    many = lyapunov_spectra(code, P, Y, count=1, **SETTINGS)
    alone = lyapunov_spectra(code, P[[4]], Y[[4]], count=1, **SETTINGS)
    assert _same(many.spectra[4].exponents, alone.spectra[0].exponents)
    assert _same(many.spectra[4].convergence, alone.spectra[0].convergence)
    # the control: different points do give different numbers
    assert many.spectra[0].exponents[0] != many.spectra[4].exponents[0]


def test_bad_batches_are_refused():
    """Wrong shapes, mismatched rows and non-finite parameters raise UserInputError before
    anything runs."""
    code = load_model_code(*BM20)
    P, Y = _points(2)
    with pytest.raises(UserInputError, match="shape"):
        lyapunov_spectra(code, P, Y[:, :5], **SETTINGS)
    with pytest.raises(UserInputError, match="rows"):
        lyapunov_spectra(code, P[:1], Y, **SETTINGS)
    P[1, 2] = np.nan
    with pytest.raises(UserInputError, match="finite"):
        lyapunov_spectra(code, P, Y, **SETTINGS)
    with pytest.raises(UserInputError, match="spectrum"):
        lyapunov_spectra(code, P[:1], Y[:1], spectrum="some", **SETTINGS)


def test_lyapunov_throughput_reports_the_work_it_did():
    """The bench section (no timing asserted): every row present and positive, no point
    failed, the lanes ran where the library has them, the chart's estimate from the lanes'
    rate."""
    from chaplygin.verify.bench_map import lyapunov_throughput

    row = lyapunov_throughput(intervals=20, transient=2, repeats=1, points=5)
    for name in ("ours_one", "ours_one_3_vectors", "ours_lanes", "ours_serial"):
        assert row[f"{name}_s"] > 0 and row[f"{name}_cpu_s"] >= 0
    assert row["failed_points"] == 0
    code = load_model_code(*BM20)
    assert row["lanes_ran"] == c_batch.variational_lockstep_available(code)
    assert row["chart_101x101_core_min"] == row["ours_lanes_cpu_s"] * 101 * 101 / 60
    with pytest.raises(UserInputError):
        lyapunov_throughput(intervals=5)


def test_several_states_run_in_the_lanes_with_the_bits_of_one_after_another(monkeypatch):
    """lyapunov_spectrum with states = 3 runs the three starts in one batch call: its
    exponents, error bars (batch means and the spread over the states), convergence,
    divergence and density rate equal, bit for bit, those of the same call with the batch
    switched off (each state's loop on its own)."""
    from chaplygin.numerics.dynamics import lyapunov

    code = load_model_code(*BM20)
    P, Y = _points(1, seed=31)
    kw = {"states": 3, "intervals": 40, "transient": 5, "windows": 4}
    lanes = lyapunov_spectrum(code, P[0], Y[0], **kw)
    monkeypatch.setattr(lyapunov, "variational_batch_available", lambda code: False)
    alone = lyapunov_spectrum(code, P[0], Y[0], **kw)
    for name in ("exponents", "errors", "window_errors", "state_errors", "per_state",
                 "convergence", "initial_states"):  # fmt: skip
        assert _same(getattr(lanes, name), getattr(alone, name)), name
    assert lanes.mean_divergence == alone.mean_divergence
    assert lanes.divergence_error == alone.divergence_error and lanes.work == alone.work
    assert np.all(np.isfinite(lanes.state_errors))  # three states: a spread was measured


def test_a_failing_state_raises_what_the_loop_raises(monkeypatch):
    """Two states of a body whose equations blow up (I1 + I(t) crosses zero): the batch
    raises the ComputationError of the loop one state after another, the same message."""
    from chaplygin.derive.errors import ComputationError
    from chaplygin.numerics.dynamics import lyapunov

    code = load_model_code(*BM20)
    P, Y = _points(1, seed=41)
    P[0, 0] = -(P[0, 3] + P[0, 4] ** 2) - 0.5 * P[0, 5] ** 2
    kw = {"states": 2, "count": 1, **SETTINGS}
    with pytest.raises(ComputationError, match="near t") as lanes:
        lyapunov_spectrum(code, P[0], Y[0], **kw)
    monkeypatch.setattr(lyapunov, "variational_batch_available", lambda code: False)
    with pytest.raises(ComputationError, match="near t") as alone:
        lyapunov_spectrum(code, P[0], Y[0], **kw)
    assert str(lanes.value) == str(alone.value)


def test_the_density_route_is_the_same_in_the_lanes(monkeypatch):
    """The autonomous ball (its proved density, BKM12-4): two states in the lanes give the
    density rate, divergence and exponents of the two loops one after another, bit for bit."""
    from chaplygin.numerics.dynamics import lyapunov

    code = load_model_code("chaplygin_ball")
    p = [1.13, 2.07, 3.31, 0.93]
    y = [0.61, -0.37, 0.52, 0.2, 0.3, float(np.sqrt(0.87))]
    kw = {"states": 2, "intervals": 30, "transient": 3, "windows": 3, "interval": 0.7}
    lanes = lyapunov_spectrum(code, p, y, **kw)
    monkeypatch.setattr(lyapunov, "variational_batch_available", lambda code: False)
    alone = lyapunov_spectrum(code, p, y, **kw)
    assert lanes.density_rate is not None and lanes.density_rate == alone.density_rate
    assert _same(lanes.exponents, alone.exponents)
    assert lanes.mean_divergence == alone.mean_divergence
