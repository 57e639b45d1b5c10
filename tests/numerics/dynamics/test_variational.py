"""The variational equations in C (numerics/dynamics/variational.py,
derive/templates/variational.c).

The state-transition matrix is checked against an independent route: central differences of the
flow computed by the generated Taylor integrator in quadruple precision (34 digits), so the
reference is accurate to ~h^2 ~ 1e-14, far below the tolerance under test.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import ComputationError, UserInputError
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.dynamics.variational import VariationalSystem, flow_with_jacobian
from chaplygin.numerics.integrators import dop853_c
from chaplygin.numerics.taylor import taylor_solve

# BM20's ball (time-periodic inertia and gyrostat), generic non-dyadic values
BM20 = ("chaplygin_ball", "variable_gyrostat,variable_inertia")
BM20_PARAMS = [4.1, 3.3, 2.2, 4.385, 0.3, 2.0, -6.1, -3.2, -9.0, 1.07]
BM20_Y0 = [1.3, -2.1, 0.7, 0.36, 0.48, 0.8]
BALL_PARAMS = [2.1, 3.3, 4.7, 1.3]
BALL_Y0 = [0.3, -0.7, 1.1, 0.36, 0.48, 0.8]


def _quad_flow(code, params, y, t0, t1):
    """The flow in quadruple precision (generated Taylor method in C), off the constraint
    |gamma| = 1 as well (the variational equations differentiate in every direction)."""
    mp_y = [mpmath.mpf(v) for v in y]
    mp_p = [mpmath.mpf(float(v)) for v in params]
    res = taylor_solve(code, mp_y, (mpmath.mpf(t0), mpmath.mpf(t1)), mp_p, precision="quad",
                       rtol=1e-32, atol=1e-32, t_eval=[mpmath.mpf(t1)])  # fmt: skip
    assert res.status == 0
    return [mpmath.mpf(v) for v in res.y[:, -1]]


def _reference_phi(code, params, y0, t0, t1, h=1e-6):
    """Central differences of the quad-precision flow (error ~ h^2 |y'''| + 1e-33/h)."""
    n = len(y0)
    phi = np.zeros((n, n))
    y1 = _quad_flow(code, params, y0, t0, t1)
    for j in range(n):
        plus = [mpmath.mpf(v) for v in y0]
        minus = [mpmath.mpf(v) for v in y0]
        plus[j] += h
        minus[j] -= h
        fp = _quad_flow(code, params, plus, t0, t1)
        fm = _quad_flow(code, params, minus, t0, t1)
        phi[:, j] = [float((a - b) / (2 * h)) for a, b in zip(fp, fm, strict=True)]
    return np.array([float(v) for v in y1]), phi


@pytest.mark.parametrize(
    ("model", "params", "y0", "span"),
    [
        (BM20, BM20_PARAMS, BM20_Y0, (0.3, 1.9)),
        (("chaplygin_ball", ""), BALL_PARAMS, BALL_Y0, (0.0, 1.7)),
        (BM20, BM20_PARAMS, BM20_Y0, (1.9, 0.3)),  # backwards
    ],
    ids=["bm20", "ball", "bm20-backwards"],
)
def test_phi_matches_differences_of_the_quad_flow(model, params, y0, span):
    code = load_model_code(*model)
    rtol, atol = 1e-9, 1e-12
    y1, phi = flow_with_jacobian(code, params, y0, *span, rtol=rtol, atol=atol)
    y_ref, phi_ref = _reference_phi(code, params, y0, *span)
    # scipy's test_ivp measure: error relative to atol + rtol |reference|, global error a few
    # times the local tolerance over these short spans
    e_y = np.abs(y1 - y_ref) / (atol + rtol * np.abs(y_ref))
    e_phi = np.abs(phi - phi_ref) / (atol + rtol * np.abs(phi_ref).max())
    assert e_y.max() < 5, e_y
    assert e_phi.max() < 5, e_phi
    # negative control through the same comparison: Phi at a displaced start differs
    _, phi_other = flow_with_jacobian(code, params, np.add(y0, 0.05), *span, rtol=rtol, atol=atol)
    assert (np.abs(phi_other - phi_ref) / (atol + rtol * np.abs(phi_ref).max())).max() > 1e3


def test_divergence_integral_is_log_det_phi():
    """Liouville: integral of tr J dt = log det Phi (two outputs of one run, two routes)."""
    code = load_model_code(*BM20)
    res = VariationalSystem(code, BM20_PARAMS, rtol=1e-11, atol=1e-13).flow(BM20_Y0, 0.0, 4.0)
    log_det = math.log(abs(np.linalg.det(res.V)))
    assert abs(log_det - res.divergence_integral) < 1e-8
    assert abs(res.divergence_integral) > 1e-3  # BM20's field is not divergence-free


def test_scipy_fallback_agrees(monkeypatch):
    """Without a compiler the same system runs in scipy's DOP853 (numpy rhs and jac)."""
    code = load_model_code(*BM20)
    rtol = 1e-10
    compiled = VariationalSystem(code, BM20_PARAMS, rtol=rtol)
    assert compiled.compiled
    monkeypatch.setitem(dop853_c._LIBRARIES, code.hash, None)
    fallback = VariationalSystem(code, BM20_PARAMS, rtol=rtol)
    assert not fallback.compiled
    a = compiled.flow(BM20_Y0, 0.0, 2.5)
    b = fallback.flow(BM20_Y0, 0.0, 2.5)
    assert np.abs(a.V - b.V).max() < 100 * rtol * np.abs(a.V).max()
    V0 = np.eye(6)[:, :3]
    la, *_ = compiled.renormalised(BM20_Y0, V0, 0.0, 1.0, 3, project=False)
    lb, *_ = fallback.renormalised(BM20_Y0, V0, 0.0, 1.0, 3, project=False)
    assert np.abs(la - lb).max() < 1e3 * rtol


def test_integral_gradients_are_exact_for_the_quadratic_integrals():
    code = load_model_code(*BM20)
    vs = VariationalSystem(code, BM20_PARAMS)
    y = np.array(BM20_Y0)
    M, g = y[:3], y[3:]
    expected = np.array(
        [np.r_[2 * M, 0, 0, 0], np.r_[g, M], np.r_[0, 0, 0, 2 * g]]
    )  # (M,M), (M,gamma), (gamma,gamma)
    assert np.abs(vs.integral_gradients(0.7, y) - expected).max() < 1e-8
    normal, tangent = vs.level_set_basis(0.7, y)
    assert normal.shape == (6, 3) and tangent.shape == (6, 3)
    assert np.abs(expected @ tangent).max() < 1e-8


def test_bad_input_raises_documented_errors():
    code = load_model_code(*BM20)
    with pytest.raises(UserInputError):
        VariationalSystem(code, BM20_PARAMS[:-1])
    with pytest.raises(UserInputError):
        VariationalSystem(code, BM20_PARAMS, rtol=2.0)
    vs = VariationalSystem(code, BM20_PARAMS)
    with pytest.raises(UserInputError):
        vs.flow([1.0, 2.0], 0, 1)
    with pytest.raises(UserInputError):
        vs.flow([float("nan")] * 6, 0, 1)
    with pytest.raises(UserInputError):
        vs.renormalised(BM20_Y0, np.eye(6), 0.0, -1.0, 3, project=False)
    tiny = VariationalSystem(code, BM20_PARAMS)
    tiny.max_steps = 2
    with pytest.raises(ComputationError, match="step limit"):
        tiny.flow(BM20_Y0, 0.0, 50.0)


def test_many_flow_jacobians_are_each_point_s_on_its_own():
    """flow_jacobians: seven points of BM20's model (different parameters, starts, phases and
    lengths, one that blows up) in vector lanes and one after another give every point the
    state and Phi of flow_with_jacobian on its own, bit for bit; the point that fails fails
    alone. Phi itself is checked against the quad-precision differences for one point (the
    independent route of the test above)."""
    from chaplygin.numerics.dynamics.variational import flow_jacobians

    code = load_model_code(*BM20)
    rng = np.random.default_rng(20261127)
    P = np.array([BM20_PARAMS] * 7) * rng.uniform(0.97, 1.03, (7, len(BM20_PARAMS)))
    Y = np.array([BM20_Y0] * 7) + rng.uniform(-0.1, 0.1, (7, 6))
    T0 = rng.uniform(0.0, 2.0, 7)
    TAU = 2 * np.pi / P[:, -1] * np.array([1, 1, 0.5, 1, 2, 1, 1])
    P[5, 3] = 1e300  # an absurd d: the equations overflow, this point fails
    lanes = flow_jacobians(code, P, Y, T0, TAU, rtol=1e-10, atol=1e-12)
    serial = flow_jacobians(code, P, Y, T0, TAU, rtol=1e-10, atol=1e-12, lockstep=False)
    assert lanes.lockstep and not serial.lockstep
    assert lanes.status[5] != 0 and np.isnan(lanes.jacobians[5]).all()
    assert (np.delete(lanes.status, 5) == 0).all()
    for j in range(7):
        assert np.array_equal(lanes.y[j], serial.y[j], equal_nan=True)
        assert np.array_equal(lanes.jacobians[j], serial.jacobians[j], equal_nan=True)
        if j == 5:
            with pytest.raises(ComputationError):
                flow_with_jacobian(code, P[j], Y[j], T0[j], T0[j] + TAU[j])
            continue
        y1, phi = flow_with_jacobian(code, P[j], Y[j], T0[j], T0[j] + TAU[j])
        assert np.array_equal(y1, lanes.y[j]) and np.array_equal(phi, lanes.jacobians[j])
    y_ref, phi_ref = _reference_phi(code, P[2], Y[2], T0[2], T0[2] + TAU[2])
    scale = 1e-12 + 1e-10 * np.abs(phi_ref).max()
    assert (np.abs(lanes.jacobians[2] - phi_ref) / scale).max() < 5
    assert (np.abs(lanes.jacobians[3] - phi_ref) / scale).max() > 1e3  # another point's Phi


def test_flow_jacobians_refuse_bad_input():
    from chaplygin.numerics.dynamics.variational import flow_jacobians

    code = load_model_code(*BM20)
    with pytest.raises(UserInputError, match="tau"):
        flow_jacobians(code, [BM20_PARAMS], [BM20_Y0], 0.0, -1.0)
    with pytest.raises(UserInputError, match="rows"):
        flow_jacobians(code, [BM20_PARAMS], [BM20_Y0, BM20_Y0], 0.0, 1.0)
    for bad in ("abc", None, [[1.0, "x"]], [BM20_Y0[:5]], [[np.nan] * 6]):
        with pytest.raises(UserInputError, match="y0"):
            flow_jacobians(code, [BM20_PARAMS], bad, 0.0, 1.0)
    with pytest.raises(UserInputError, match="t0"):
        flow_jacobians(code, [BM20_PARAMS], [BM20_Y0], "soon", 1.0)
