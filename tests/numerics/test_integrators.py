"""The one door (numerics/integrators/) and the precision row (numerics/precision.py).

Where a computation used to call a solver itself, the door's result is compared with that
direct call, written out here (tests may call solvers): bit for bit, since the door must not
change what users see. New routes (odefun backward, the reversed flow on scipy's methods) are
checked against an independent integrator at a tolerance derived from the requested one.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.integrators import (
    INTEGRATORS,
    METHODS,
    Batch,
    ModelFlow,
    Problem,
    ReversedFlow,
    VariationalFlow,
    get_integrator,
)
from chaplygin.numerics.precision import ARITHMETICS, Precision
from reference import REFERENCE_PARAMS, REFERENCE_Y0
from scipy.integrate import solve_ivp

BALL = "chaplygin_ball"
#: Generic non-dyadic state and parameters of the plain ball (|gamma| = 1 not needed here).
Y0 = [0.31, -0.72, 1.13, 0.36, 0.48, 0.8]
P = [2.1, 3.3, 4.7, 1.3]
DOUBLE = Precision("double")


def _bits(a) -> np.ndarray:
    return np.asarray(a, dtype=np.float64).view(np.int64)


# ------------------------------------------------------------------ the registry


def test_the_users_methods_are_unchanged_and_the_registry_holds_every_integrator():
    assert list(METHODS) == ["RK45", "DOP853", "LSODA", "Radau", "BDF", "taylor", "odefun"]
    assert set(INTEGRATORS) == set(METHODS) | {"dop853"}
    with pytest.raises(UserInputError, match="unknown method 'dop853'; valid methods: RK45"):
        get_integrator("dop853")  # a user's name: only the methods of a model's equations
    assert get_integrator("dop853", INTEGRATORS).name == "dop853"


def test_an_integrator_refuses_a_flow_it_does_not_integrate():
    code = load_model_code(BALL)
    z = VariationalFlow(code, 1).pack(np.array(Y0), np.ones((6, 1)))
    problem = Problem(VariationalFlow(code, 1), z, (0.0, 1.0), P, DOUBLE, 1e-10, 1e-10)
    with pytest.raises(UserInputError, match="taylor does not integrate variational equations"):
        INTEGRATORS["taylor"]().solve(problem)
    with pytest.raises(UserInputError, match="does not integrate a model's own equations"):
        INTEGRATORS["dop853"]().solve(Problem(code, Y0, (0.0, 1.0), P, DOUBLE, 1e-10, 1e-10))
    with pytest.raises(UserInputError, match="run\\(\\) gives the evidence of a model's run"):
        INTEGRATORS["DOP853"]().run(problem)
    # the same flow through a method that integrates it (a control: the problem is sound)
    sol = INTEGRATORS["DOP853"]().solve(problem)
    assert sol.status == 0 and sol.y.shape[0] == 6 + 6 + 1
    assert isinstance(Problem(code, Y0, (0, 1), P, DOUBLE, 1, 1).system, ModelFlow)


# ------------------------------------------------------------------ new routes


def test_odefun_integrates_backward_on_the_reversed_flow():
    """method="odefun" over a backward span (mpmath.odefun alone only runs forward) against
    the generated Taylor integrator at the same 30 digits: both within 10^-25 (odefun works
    to the full precision, the Taylor run at rtol 1e-28 over ~2 time units)."""
    span = (0, "-2.3")
    back = integrate(BALL, REFERENCE_Y0, span, REFERENCE_PARAMS, method="odefun", precision=30)
    ref = integrate(
        BALL, REFERENCE_Y0, span, REFERENCE_PARAMS, method="taylor", precision=30, rtol=1e-28,
        atol=1e-28,
    )  # fmt: skip
    assert back.success and ref.success
    with mpmath.workdps(30):
        assert back.t[-1] == ref.t[-1] == mpmath.mpf("-2.3")
    assert list(back.t) == list(ref.t)  # the same 11 output times, in decreasing order
    err = max(abs(a - b) for a, b in zip(back.y.ravel(), ref.y.ravel(), strict=True))
    assert err < mpmath.mpf(10) ** -25
    # a control: the forward run ends elsewhere
    fwd = integrate(BALL, REFERENCE_Y0, (0, "2.3"), REFERENCE_PARAMS, method="odefun", precision=30)
    assert max(abs(a - b) for a, b in zip(fwd.y[:, -1], ref.y[:, -1], strict=True)) > 1e-3


@pytest.mark.parametrize("method", ["DOP853", "Radau"])
def test_the_reversed_flow_forward_is_the_model_backward(method):
    """ReversedFlow over s in (0, T) (scipy's methods, the reversed Jacobian for Radau)
    against the model over t in (0, -T): the states agree to 100 rtol."""
    code = load_model_code(BALL)
    rtol = 1e-10
    ends = []
    for flow, span in ((ReversedFlow(code), (0.0, 3.7)), (ModelFlow(code), (0.0, -3.7))):
        problem = Problem(flow, Y0, span, P, DOUBLE, rtol, rtol)
        sol = INTEGRATORS[method]().solve(problem)
        assert sol.status == 0
        ends.append(sol.y[:, -1])
    assert np.abs(ends[0] - ends[1]).max() < 100 * rtol * np.abs(ends[1]).max()
    forward = INTEGRATORS[method]().solve(Problem(code, Y0, (0.0, 3.7), P, DOUBLE, rtol, rtol))
    assert np.abs(forward.y[:, -1] - ends[1]).max() > 1e-3  # a control


# ------------------------------------------------------------------ work counters


@pytest.mark.parametrize("method", ["RK45", "DOP853", "LSODA", "Radau", "BDF"])
def test_nsteps_is_the_solvers_steps_also_with_output_times(method):
    """``nsteps`` counts the solver's accepted steps, not the output times (issue 28, 1):
    with 1000 output times it is the step count of scipy's own run without them (its ``t``
    then lists every step), far from 999."""
    code = load_model_code(BALL)
    rtol = 1e-8
    direct = solve_ivp(
        code.numpy.rhs, (0.0, 4.0), Y0, method=method, rtol=rtol, atol=rtol,
        args=(np.asarray(P, dtype=float),),
        **({"jac": code.numpy.jac} if method in ("LSODA", "Radau", "BDF") else {}),
    )  # fmt: skip
    steps = len(direct.t) - 1
    for t_eval in (None, np.linspace(0.0, 4.0, 1000)):
        problem = Problem(code, Y0, (0.0, 4.0), P, DOUBLE, rtol, rtol, t_eval=t_eval)
        sol = INTEGRATORS[method]().solve(problem, chosen="numpy")
        assert sol.status == 0 and sol.nsteps == steps != 999


def test_odefun_nsteps_is_its_taylor_series_count():
    """``method="odefun"``: one step is one Taylor series of ``mpmath.odefun``, counted here
    from the list of expansion points in a direct call's solution (its closure), with and
    without output times."""
    import inspect

    code = load_model_code(BALL)
    with mpmath.workdps(20):
        y0, p = [mpmath.mpf(v) for v in Y0], [mpmath.mpf(v) for v in P]
        counts = []
        for t_eval in (None, [mpmath.mpf(k) / 4 for k in range(5)]):
            problem = Problem(code, y0, (0, 1), p, Precision(20), 1e-18, 1e-18, t_eval=t_eval)
            counts.append(INTEGRATORS["odefun"]().solve(problem).nsteps)
        solution = mpmath.odefun(lambda t, y: code.mpmath.rhs(t, y, p), 0, y0)
        solution(mpmath.mpf(1))
        get_series = inspect.getclosurevars(solution).nonlocals["get_series"]
        expected = len(inspect.getclosurevars(get_series).nonlocals["series_data"])
    assert counts == [expected, expected] and expected not in (4, 10)


# ------------------------------------------------------------------ the door against direct calls


def test_separatrix_flow_is_the_direct_taylor_and_odefun_calls_bit_for_bit():
    """separatrix.flow through the door against what it called itself before: taylor_solve
    at the ambient 30 digits, and mpmath.odefun on -f for the backward half."""
    from chaplygin.numerics.ball.separatrix import flow, separatrix_quantities, separatrix_state
    from chaplygin.numerics.taylor import taylor_solve

    code = load_model_code(BALL, ("contact_point",))
    with mpmath.workdps(40):
        I, D, b = [mpmath.mpf(1), mpmath.mpf(3), mpmath.mpf(5)], mpmath.mpf(1), mpmath.mpf(1)
        T = 2 / separatrix_quantities(I, D)["lam"]
        y0 = separatrix_state(I, D)
    params = [*I, D, b]
    with mpmath.workdps(30):
        direct = taylor_solve(
            code, [mpmath.mpf(v) for v in y0], (mpmath.mpf(0), mpmath.mpf(T)),
            [mpmath.mpf(v) for v in params], precision=30, rtol=1e-30, atol=1e-30,
            t_eval=[mpmath.mpf(T)],
        )  # fmt: skip
    assert flow(y0, params, T, 30) == (list(direct.y[:, -1]), direct.nsteps)
    rhs, calls, t_end = code.mpmath.rhs, [0], -T / 4
    with mpmath.workdps(20):
        p = [mpmath.mpf(v) for v in params]

        def F(t, y):
            calls[0] += 1
            return [-1 * v for v in rhs(t, y, p)]

        sol = mpmath.odefun(F, 0, [mpmath.mpf(v) for v in y0])
        expected = list(sol(abs(mpmath.mpf(t_end))))
    assert flow(y0, params, t_end, 20, engine="odefun") == (expected, calls[0])


def test_variational_fallback_is_the_direct_scipy_call_bit_for_bit(monkeypatch):
    """Without the compiled library the variational equations run on scipy's DOP853 through
    the door: the bits of the direct solve_ivp call on the same augmented system."""
    from chaplygin.arith import detlinalg
    from chaplygin.numerics.dynamics.variational import VariationalSystem
    from chaplygin.numerics.integrators import dop853_c

    code = load_model_code(BALL)
    monkeypatch.setitem(dop853_c._LIBRARIES, code.hash, None)
    system = VariationalSystem(code, P, rtol=1e-9, atol=1e-11)
    assert not system.compiled
    V0 = np.eye(6)[:, :2] + 0.1
    res = system.flow(Y0, 0.2, 1.9, V0)
    n, k, p = 6, 2, np.array(P)

    def f(t, z):
        J = np.asarray(code.numpy.jac(t, z[:n], p), dtype=np.float64)
        out = np.empty_like(z)
        out[:n] = code.numpy.rhs(t, z[:n], p)
        out[n:-1] = detlinalg.matmul(J, z[n:-1].reshape(n, k)).ravel()
        out[-1] = np.trace(J)
        return out

    z0 = np.concatenate([Y0, V0.ravel(), [0.0]])
    atol = np.full(z0.size, 1e-11)
    atol[-1] = np.inf
    sol = solve_ivp(f, (0.2, 1.9), z0, method="DOP853", rtol=1e-9, atol=atol)
    z = sol.y[:, -1]
    assert np.array_equal(_bits(res.y), _bits(z[:n]))
    assert np.array_equal(_bits(res.V), _bits(z[n:-1].reshape(n, k)))
    assert res.divergence_integral == z[-1] and res.evaluations == sol.nfev


def test_the_dense_solution_is_the_engines_bit_for_bit():
    """trace_geometry.dense_solution (the taylor integrator with dense_output) against the
    engine's taylor_dense called directly, at times across the span."""
    from chaplygin.numerics.ball.trace_geometry import dense_solution
    from chaplygin.numerics.taylor import taylor_dense

    code = load_model_code(BALL)
    y0, p = np.array(Y0), np.array(P)
    door = dense_solution(code, y0, (0.0, -7.3), p, 1e-11)
    direct = taylor_dense(code, y0, (0.0, -7.3), p, rtol=1e-11, atol=1e-11)
    times = np.linspace(0.0, -7.3, 53)
    assert np.array_equal(_bits(door(times)), _bits(direct(times)))
    assert np.array_equal(_bits(door.t), _bits(direct.t)) and door.status == 0


def test_a_batch_through_the_registry_is_the_batch_map():
    """A Batch problem solved by the 'dop853' and 'taylor' integrators gives what
    BatchStroboscopicMap reports (the same call), and the two integrators agree to their
    tolerance over 3 periods."""
    from chaplygin.numerics.dynamics.batch_map import BatchStroboscopicMap, batch_map_available
    from chaplygin.numerics.integrators import StroboscopicTimes

    code = load_model_code(BALL, ["variable_inertia", "variable_gyrostat"])
    if not batch_map_available(code):
        pytest.skip("no C compiler")
    params = np.array([[4.1, 3.3, 2.2, 4.385, 0.13, 2.0, -6.0, -3.0, -9.0, 1.07]] * 2)
    params[1, -1] = 0.61
    y0 = np.array([[2.18, 1.4, 1.5, 0.6, -0.64, 0.48], [0.3, -0.7, 1.1, 0.36, 0.48, 0.8]])
    times = StroboscopicTimes(np.zeros(2), 1, 3)
    out = {}
    for name in ("dop853", "taylor"):
        problem = Problem(Batch(code), y0, None, params, DOUBLE, 1e-11, 1e-11, t_eval=times,
                          max_steps=100_000)  # fmt: skip
        sol = INTEGRATORS[name]().solve(problem)
        mapped = BatchStroboscopicMap(code, rtol=1e-11, atol=1e-11, method=name).run(
            y0, params, 3, 1
        )
        assert (sol.info["status"] == 0).all()
        assert np.array_equal(_bits(sol.y), _bits(mapped.y))
        out[name] = sol.y
    assert np.abs(out["dop853"] - out["taylor"]).max() < 1e-7


# ------------------------------------------------------------------ the precision row


@pytest.mark.parametrize(
    "value, kind, bits, arithmetic",
    [("double", "double", 53, "double"), ("quad", "quad", 113, "quad"), (16, "digits", 56, "dd"),
     (31, "digits", 106, "dd"), (32, "digits", 110, "qd"), (60, "digits", 203, "qd"),
     (61, "digits", 206, "mpfr"), (1000, "digits", 3325, "mpfr")],
)
def test_a_precision_names_its_row(value, kind, bits, arithmetic):
    prec = Precision(value)
    assert (prec.kind, prec.bits, prec.arithmetic.name) == (kind, bits, arithmetic)
    assert prec.arithmetic is ARITHMETICS[arithmetic]
    assert Precision(prec) == prec and hash(Precision(prec)) == hash(prec)
    most = prec.arithmetic.most_bits
    assert most is None or bits <= most
    with prec.context():
        assert mpmath.mp.prec == (53 if prec.is_double else mpmath.libmp.dps_to_prec(prec.digits))
        third = prec.number(1) / 3
    assert isinstance(third, prec.number_type)
    assert mpmath.mp.prec == 53  # the context is left as it was
    text = prec.format(third)
    assert text == (repr(1 / 3) if prec.is_double else "0." + "3" * prec.digits)


def test_an_internal_precision_may_have_fewer_digits_than_a_user_one():
    with pytest.raises(UserInputError, match="16..10000"):
        Precision(12)
    prec = Precision.working(12)
    assert prec.digits == 12 and prec.arithmetic.name == "dd" and repr(prec) == "12 digits"
    with pytest.raises(UserInputError, match="at least 1 digit"):
        Precision.working(0)


def test_the_taylor_engine_takes_its_precision_explicitly():
    """taylor_solve given Precision(40) runs at 40 digits whatever the ambient context is
    (the old "digits" read mpmath.mp.prec); the same run inside workdps(40) gives the same
    bits, and one at 20 digits differs (a control)."""
    from chaplygin.numerics.taylor import taylor_solve

    code = load_model_code(BALL)
    y0 = [mpmath.mpf(v) for v in Y0]
    p = [mpmath.mpf(v) for v in P]
    with mpmath.workdps(40):
        y0, p = [+v for v in y0], [+v for v in p]
    outside = taylor_solve(code, y0, (0, 1), p, precision=40, rtol=1e-38, atol=1e-38,
                           t_eval=[1])  # fmt: skip
    with mpmath.workdps(40):
        inside = taylor_solve(code, y0, (0, 1), p, precision=Precision(40), rtol=1e-38,
                              atol=1e-38, t_eval=[1])  # fmt: skip
    assert outside.backend == "c-qd" and list(outside.y[:, -1]) == list(inside.y[:, -1])
    with mpmath.workdps(20):
        low = taylor_solve(code, y0, (0, 1), p, precision=20, rtol=1e-18, atol=1e-18, t_eval=[1])
    assert low.backend == "c-dd"
    assert max(abs(a - b) for a, b in zip(low.y[:, -1], inside.y[:, -1], strict=True)) > 0
    with pytest.raises(UserInputError):
        taylor_solve(code, y0, (0, 1), p, precision="digits", rtol=1e-9, atol=1e-9)
    assert math.isfinite(float(outside.y[0, -1]))
