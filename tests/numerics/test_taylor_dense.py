"""The dense Taylor solution in double precision (numerics/taylor/dense.py ``taylor_dense``).

Its steps are the integrator's own: at any output time it gives what ``integrate(...,
method="taylor", t_eval=...)`` gives there, bit for bit (the compiled loop's compensated
state update included); between the outputs its error against an independent 20-digit run
(``mpmath.odefun``) stays within a bound derived from the tolerance and the number of steps;
backward spans, continuation, event location and bad input.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.taylor import taylor_dense, taylor_solve

#: A generic body (non-dyadic) and start of the plain ball (quasi-periodic motion).
I, D = (1.3, 2.9, 4.4), 0.7
P = [*I, D]
G = np.array([0.31, -0.52, 0.77])
Y0 = np.concatenate([[0.62, -0.41, 0.53], G / math.sqrt(float(np.sum(G * G)))])


@pytest.fixture(scope="module")
def code():
    return load_model_code("chaplygin_ball")


def _output_times(sol, count: int, seed: int) -> np.ndarray:
    """Random times in the span, the step ends and both ends of the span, sorted in the
    direction of integration."""
    t0, t1 = sol.t[0], sol.t[-1]
    rng = np.random.default_rng(seed)
    times = np.concatenate([t0 + (t1 - t0) * rng.random(count), sol.t, [t0, t1]])
    return np.sort(times) if t1 > t0 else -np.sort(-times)


@pytest.mark.parametrize("span", [(0.0, 30.0), (0.0, -17.0)])
def test_dense_values_are_the_integrators_outputs_bit_for_bit(code, span):
    sol = taylor_dense(code, Y0, span, P, rtol=1e-12, atol=1e-12)
    assert sol.status == 0 and sol.t[-1] == span[1] and sol.nsteps > 10
    assert sol.backend == "c-double" and sol.compensated
    times = _output_times(sol, 400, 1)
    run = integrate(code, Y0, span, P, method="taylor", rtol=1e-12, atol=1e-12, t_eval=times)
    assert run.success and run.y.shape == (6, times.size)
    assert np.array_equal(sol(times), run.y)
    assert np.array_equal(sol(span[1]), sol.y_end)
    # one number gives one state, equal to the same time in a sequence
    k = times.size // 3
    assert np.array_equal(sol(times[k]), run.y[:, k])


def test_python_recurrences_give_the_python_loops_outputs_bit_for_bit(code):
    sol = taylor_dense(code, Y0, (0.0, 6.0), P, rtol=1e-10, atol=1e-12, lib="float")
    assert sol.backend == "python-float" and not sol.compensated
    assert not np.any(sol.y_lo)
    times = _output_times(sol, 100, 2)
    run = taylor_solve(code, Y0, (0.0, 6.0), P, rtol=1e-10, atol=1e-12, t_eval=list(times),
                       lib="float")  # fmt: skip
    assert np.array_equal(sol(times), run.y)


@pytest.fixture(scope="module")
def reference(code):
    """The state at 60 times over [0, 12] from ``mpmath.odefun`` at 20 digits (its own
    Taylor series of the mpmath right-hand side: not the generated recurrences)."""
    times = np.linspace(0.0, 12.0, 61)[1:] - 0.0731  # off the step ends
    run = integrate(code, list(Y0), (0.0, 12.0), P, precision=20, method="odefun",
                    t_eval=list(times))  # fmt: skip
    assert run.success
    return times, np.array(run.y, dtype=float)


def _bound(sol, rtol: float, exact: np.ndarray) -> float:
    """The local tolerance of every step summed: the Jorba-Zou order and step keep each
    step's truncation error below ``rtol`` times the state's size (relative control), and
    the motion is quasi-periodic (no exponential growth of the errors)."""
    return sol.nsteps * rtol * float(np.max(np.abs(exact)))


@pytest.mark.parametrize("rtol", [1e-6, 1e-9, 1e-12])
def test_dense_values_between_steps_are_within_the_tolerance(code, reference, rtol):
    times, exact = reference
    sol = taylor_dense(code, Y0, (0.0, 12.0), P, rtol=rtol, atol=rtol)
    assert float(np.max(np.abs(sol(times) - exact))) <= _bound(sol, rtol, exact)


def test_a_low_order_interpolant_breaks_the_bound(code, reference):
    """Control: cubic Hermite interpolation between the same step ends (states and
    derivatives, what a low-order dense output gives) is refuted by the same bound."""
    times, exact = reference
    sol = taylor_dense(code, Y0, (0.0, 12.0), P, rtol=1e-9, atol=1e-9)
    ends = sol(sol.t)
    slopes = np.array(code.numpy.rhs(0.0, ends, P), dtype=float)
    j = np.searchsorted(sol.t[1:], times)
    h = sol.t[j + 1] - sol.t[j]
    u = (times - sol.t[j]) / h
    hermite = (
        (2 * u**3 - 3 * u**2 + 1) * ends[:, j]
        + (u**3 - 2 * u**2 + u) * h * slopes[:, j]
        + (-2 * u**3 + 3 * u**2) * ends[:, j + 1]
        + (u**3 - u**2) * h * slopes[:, j + 1]
    )
    assert float(np.max(np.abs(hermite - exact))) > _bound(sol, 1e-9, exact)


def test_backward_run_returns_to_the_start(code):
    forward = taylor_dense(code, Y0, (0.0, 9.0), P, rtol=1e-13, atol=1e-13)
    back = taylor_dense(code, forward.y_end, (9.0, 0.0), P, rtol=1e-13, atol=1e-13)
    assert back.direction == -1 and back.t[-1] == 0.0
    bound = (forward.nsteps + back.nsteps) * 1e-13 * float(np.max(np.abs(Y0)))  # as _bound
    assert float(np.max(np.abs(back(0.0) - Y0))) < bound
    # at the same times the two runs agree to the same bound
    t = np.linspace(0.0, 9.0, 37)
    assert float(np.max(np.abs(back(t[::-1])[:, ::-1] - forward(t)))) < bound


def test_extend_goes_on_from_the_end(code):
    sol = taylor_dense(code, Y0, (0.0, 5.0), P, rtol=1e-12, atol=1e-12)
    steps, first = sol.nsteps, sol(np.linspace(0.0, 5.0, 21))
    sol.extend(11.0)
    assert sol.t[-1] == 11.0 and sol.nsteps > steps
    assert np.array_equal(sol(np.linspace(0.0, 5.0, 21)), first)  # the old steps are kept
    whole = taylor_dense(code, Y0, (0.0, 11.0), P, rtol=1e-12, atol=1e-12)
    t = np.linspace(5.0, 11.0, 25)
    bound = (sol.nsteps + whole.nsteps) * 1e-12 * float(np.max(np.abs(whole(t))))
    assert float(np.max(np.abs(sol(t) - whole(t)))) < bound
    with pytest.raises(UserInputError, match="not beyond"):
        sol.extend(3.0)


def test_crossings_are_the_integrators_events(code):
    sol = taylor_dense(code, Y0, (0.0, 80.0), P, rtol=1e-12, atol=1e-12)

    def gamma2(t, y):
        return y[4]

    t_all, y_all = sol.crossings(gamma2)
    t_up, _ = sol.crossings(gamma2, direction=1)
    t_down, _ = sol.crossings(gamma2, direction=-1)
    assert len(t_all) >= 4 and len(t_all) == len(t_up) + len(t_down)
    assert np.all(np.diff(t_all) > 0)
    assert np.array_equal(np.sort(np.concatenate([t_up, t_down])), t_all)
    # the located state is on the surface, to rounding
    assert float(np.max(np.abs(y_all[:, 4]))) < 1e-14
    # the integrator's own event location (Illinois on the same polynomials)
    run = taylor_solve(code, Y0, (0.0, 80.0), P, rtol=1e-12, atol=1e-12, events=gamma2)
    assert np.allclose(t_all, run.t_events[0], rtol=0, atol=1e-13)


def test_too_many_steps_stop_the_run(code):
    sol = taylor_dense(code, Y0, (0.0, 30.0), P, rtol=1e-12, atol=1e-12, max_steps=3)
    assert sol.status == -2 and sol.nsteps == 3 and sol.t[-1] < 30.0
    assert "max_steps" in sol.message
    with pytest.raises(UserInputError, match="outside the span"):
        sol(29.0)


@pytest.mark.parametrize(
    "change, match",
    [
        ({"y0": Y0[:5]}, "y0 needs"),
        ({"y0": [*Y0[:5], math.nan]}, "y0"),
        ({"y0": [*Y0[:5], "0.3"]}, "y0"),
        ({"p": P[:3]}, "p needs"),
        ({"t_span": (1.0, 1.0)}, "t_span must be non-empty"),
        ({"t_span": (0.0, math.inf)}, "t_span"),
        ({"rtol": -1e-9}, "rtol"),
        ({"atol": 1e-17}, "unit roundoff"),
        ({"max_steps": 0}, "max_steps"),
        ({"lib": "fortran"}, "lib"),
    ],
)
def test_bad_input_is_refused(code, change, match):
    args = {"y0": Y0, "t_span": (0.0, 1.0), "p": P, "rtol": 1e-10, "atol": 1e-10}
    args |= change
    extra = {k: args.pop(k) for k in ("max_steps", "lib") if k in args}
    with pytest.raises(UserInputError, match=match):
        taylor_dense(code, args["y0"], args["t_span"], args["p"], rtol=args["rtol"],
                     atol=args["atol"], **extra)  # fmt: skip


def test_bad_times_and_events_are_refused(code):
    sol = taylor_dense(code, Y0, (0.0, 2.0), P, rtol=1e-10, atol=1e-10)
    for bad in (2.5, -0.1, math.nan, [0.5, 3.0], [[0.5]], "1.0", [0.5, "1"], None):
        with pytest.raises(UserInputError):
            sol(bad)
    with pytest.raises(UserInputError, match="direction"):
        sol.crossings(lambda t, y: y[4], direction=2)
    with pytest.raises(UserInputError, match="samples"):
        sol.crossings(lambda t, y: y[4], samples=0)
