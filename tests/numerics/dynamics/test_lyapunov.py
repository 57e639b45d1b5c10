"""Lyapunov spectra (numerics/dynamics/lyapunov.py): the QR machinery against an independent flow,
the sum of the spectrum against the average divergence, the density bound of the autonomous ball
(BKM12-4), BM20's dissipative attractor, units and bad input."""

from __future__ import annotations

import functools
import math

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics.ball.initial_state import state_from_andoyer
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.dynamics.lyapunov import (
    UNITS_PER_ITERATION,
    UNITS_PER_TIME,
    lyapunov_spectrum,
    states_on_level_set,
)
from chaplygin.numerics.dynamics.variational import VariationalSystem
from chaplygin.numerics.integrators import dop853_c

BM20 = ("chaplygin_ball", "variable_gyrostat,variable_inertia")
# BM20 Fig. 5: I = diag(4, 3, 2), d = 4.385, J = 0, delta = 2, K = (-6, -3, -9), Omega = 1.07
FIG5_PARAMS = [4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.07]
RTOL = 1e-10


def _fig5_state():
    s = state_from_andoyer(mpmath.mpf(3), mpmath.mpf("0.5"), mpmath.mpf(1), mpmath.mpf(1))
    return np.array([float(v) for v in s["M"] + s["gamma"]])


@pytest.mark.parametrize("project", [False, True], ids=["full", "level-set"])
def test_qr_logs_are_the_volume_growth_of_an_independent_flow(monkeypatch, project):
    """sum of log R_jj (j < m) over the intervals = log of the m-volume spanned by Phi V0.

    Phi comes from scipy's DOP853 on the same system with the numpy Jacobian (another
    integrator, another code path). The exact flow maps the level set's tangent space to
    itself, so projecting leaves the identity intact. About 50 steps per period, 8 periods:
    a global error below 400 local tolerances, so 1e3 rtol bounds the difference.
    """
    code = load_model_code(*BM20)
    y0 = _fig5_state()
    compiled = VariationalSystem(code, FIG5_PARAMS, rtol=RTOL)
    _, tangent = compiled.level_set_basis(0.0, y0)
    V0 = tangent if project else np.eye(6)[:, [0, 2, 4]] + 0.3 * np.eye(6)[:, [1, 3, 5]]
    V0 = np.linalg.qr(V0)[0]
    period = 2 * math.pi / 1.07
    logs, *_ = compiled.renormalised(y0, V0, 0.0, period, 8, project=project)
    monkeypatch.setitem(dop853_c._LIBRARIES, code.hash, None)
    reference = VariationalSystem(code, FIG5_PARAMS, rtol=RTOL / 10, atol=1e-14)
    W = reference.flow(y0, 0.0, 8 * period, V0).V
    for m in (1, 2, 3):
        volume = 0.5 * math.log(np.linalg.det(W[:, :m].T @ W[:, :m]))
        assert abs(logs[:, :m].sum() - volume) < 1e3 * RTOL
    # negative control through the same identity: the volume after 7 periods is another one
    W7 = reference.flow(y0, 0.0, 7 * period, V0).V
    assert abs(logs[:, :1].sum() - math.log(np.linalg.norm(W7[:, 0]))) > 1e3 * RTOL


def _log_density_range(I, D):
    """(max - min) of log rho on |gamma| = 1, rho = (1/D - sum gamma_i^2/(D + I_i))^(-1/2)
    (BKM12-4): the quadratic form lies between 1/D - 1/(D + min I) and 1/D - 1/(D + max I)."""
    lo = 1 / D - 1 / (D + min(I))
    hi = 1 / D - 1 / (D + max(I))
    return 0.5 * abs(math.log(hi / lo))


#: Fig. 5's attractor run shared by the density control and the dissipation test: the level-set
#: spectrum over 8000 forcing periods after 500 discarded (the orbit from Fig. 5's start is on
#: the attractor by then: its mean divergence over periods 300-1300 is already the attractor's
#: on every perturbed start tried), one initial state, 10 windows, DOP853 at rtol 1e-10.
FIG5_RUN = {"intervals": 8000, "transient": 500}


@functools.cache
def _fig5_attractor():
    return lyapunov_spectrum(load_model_code(*BM20), FIG5_PARAMS, _fig5_state(), **FIG5_RUN)


def test_autonomous_ball_average_divergence_is_bounded_by_its_density():
    """div f = -d/dt log rho (BKM12-4), so |mean div| <= range(log rho)/T; the sum of the full
    spectrum (QR route) equals it (Liouville) and so does the density route. BM20's ball, which
    has no invariant density, breaks the same bound (negative control).

    Why no side can flip with the last bits of a run. The ball is integrable (not chaotic) and
    the bound is an identity along any orbit (|log rho(end) - log rho(start)| <= range);
    measured T |mean div| / range = 0.30-0.40 at 600, 3000, 6000 intervals. The control runs on
    Fig. 5's attractor (500 periods of transient discarded: from Fig. 5's start with none, the
    first 174 periods gave |mean div| between 1.5e-4 and 4e-3 per unit time depending on the
    last bits, and on some processors failed the old 10 x bound), over 8000 periods, and is
    compared with the bound at its own length T' by its own standard error (batch means over
    10 windows): |mean div| - 5 SE > 10 range/T'. On 160 starts perturbed by 1e-12 (relative)
    the smallest (|mean div| - 10 range/T') / SE was 9.9 and |mean div| T' / range >= 2200;
    the attractor's intermittent excursions (a few hundred periods every few thousand, mean
    divergence near 0) are what widen the standard error.
    """
    code = load_model_code("chaplygin_ball")
    I, D = (2.1, 3.3, 4.7), 1.3
    y0 = [0.3, -0.7, 1.1, 0.36, 0.48, 0.8]
    res = lyapunov_spectrum(
        code, [*I, D], y0, spectrum="full", interval=1.7, intervals=6000, transient=0
    )
    T = res.intervals * res.interval
    bound = _log_density_range(I, D) / T
    assert abs(res.mean_divergence) <= bound
    assert abs(res.density_rate - res.mean_divergence) < 1e3 * RTOL
    assert abs(res.divergence_difference) < 1e3 * RTOL
    assert res.integral_rank == 4 and res.forced_zeros.size == 4
    assert res.period is None and "per_iteration" not in res.summary()
    assert res.summary()["per_unit_time"]["units"] == UNITS_PER_TIME
    with pytest.raises(UserInputError):
        res.per_iteration(res.exponents)
    # negative control: BM20's field on Fig. 5's attractor breaks the same bound (at its own
    # length) by far more than its standard error
    bm20 = _fig5_attractor()
    own_bound = _log_density_range(I, D) / (bm20.intervals * bm20.interval)
    assert abs(bm20.mean_divergence) - 5 * bm20.divergence_error > 10 * own_bound
    assert bm20.density_rate is None


def test_bm20_attractor_is_dissipative():
    """On Fig. 5's attractor the average divergence (quadrature of tr J) is negative and the
    level-set spectrum sums to the same number (the normal directions contribute zero), with
    one exponent above the rate of linear growth (chaotic); the full spectrum has six exponents
    (three forced zeros) summing to its own average divergence (Liouville).

    Why none of it can flip with the last bits: the sign is a statistical bound, mean div
    + 5 SE < 0 (batch-means standard error of the run itself), which held by at least 9.9 SE on
    160 starts perturbed by 1e-12; chaos is lambda_1 > ln(N)/N per iteration (what a tangent
    vector growing linearly, on a torus or a periodic orbit, shows after N periods), with
    lambda_1 >= 0.0335 per iteration = 29.8 ln(N)/N on 60 perturbed starts (the old
    lambda_1 > 3 SE fell to 2.8 SE on one of 48: the excursions, with lambda_1 near 0.25, widen
    the error bar but only raise lambda_1). The sums equal the average divergence by Liouville's
    identity up to the integration's error (measured at most 2.4e-12 per unit time against the
    1e3 rtol = 1e-7 asserted, not a tolerance scaled by where the orbit went), so the short
    full-spectrum run asserts nothing about its orbit.
    """
    code = load_model_code(*BM20)
    level = _fig5_attractor()
    assert level.exponents.shape == (3,)
    assert level.mean_divergence + 5 * level.divergence_error < 0
    assert level.sum_of_exponents < 0
    # the normal directions contribute zero: |grad F| is constant on BM20's level set
    assert abs(level.divergence_difference) < 1e3 * RTOL
    per_iteration = level.summary()["per_iteration"]
    assert per_iteration["exponents"][0] > math.log(level.intervals) / level.intervals  # chaotic
    assert per_iteration["units"] == UNITS_PER_ITERATION
    np.testing.assert_allclose(
        per_iteration["exponents"], level.exponents * 2 * math.pi / 1.07, rtol=1e-15
    )
    assert level.convergence.shape[2] == 3
    full = lyapunov_spectrum(
        code, FIG5_PARAMS, _fig5_state(), spectrum="full", intervals=200, transient=20
    )
    assert full.exponents.shape == (6,) and full.integral_rank == 3
    assert full.forced_zeros.size == 3
    assert abs(full.divergence_difference) < 1e3 * RTOL


def test_states_on_level_set_keep_the_integrals():
    code = load_model_code(*BM20)
    vs = VariationalSystem(code, FIG5_PARAMS)
    y0 = _fig5_state()
    states = states_on_level_set(vs, y0, 4, spread=0.02)
    F0 = code.numpy.integrals(0.0, y0, vs.params)
    for y in states[1:]:
        assert np.linalg.norm(y - y0) > 1e-3
        np.testing.assert_allclose(code.numpy.integrals(0.0, y, vs.params), F0, atol=1e-13)


def test_bad_settings_raise_user_input_error():
    code = load_model_code(*BM20)
    y0 = _fig5_state()
    with pytest.raises(UserInputError, match="unknown spectrum"):
        lyapunov_spectrum(code, FIG5_PARAMS, y0, spectrum="both")
    with pytest.raises(UserInputError, match="windows"):
        lyapunov_spectrum(code, FIG5_PARAMS, y0, intervals=5, windows=10)
    with pytest.raises(UserInputError, match="autonomous"):
        lyapunov_spectrum(load_model_code("chaplygin_ball"), [1, 2, 3, 1], [0, 0, 1, 0, 0, 1])
