"""A prepared Taylor integration advanced in time (numerics/propagator.py, issue 15)."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate
from chaplygin.numerics.propagator import Propagator
from reference import REFERENCE_PARAMS, REFERENCE_Y0

BALL = "chaplygin_ball"


def _bits(a) -> np.ndarray:
    return np.asarray(a, dtype=np.float64).view(np.int64)


@pytest.mark.parametrize("rtol", [1e-9, 1e-12])
def test_one_call_is_integrate_bit_for_bit(rtol):
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=rtol, atol=rtol)
    r = prop.propagate_until(37.3)
    ref = integrate(
        BALL, REFERENCE_Y0, (0, 37.3), REFERENCE_PARAMS, method="taylor", rtol=rtol, atol=rtol,
        t_eval=[0, 37.3],
    )
    assert r.success and ref.success and r.nsteps == ref.nsteps
    assert np.array_equal(_bits(r.y), _bits(ref.y))
    assert r.drift == ref.drift
    assert prop.time == 37.3 and np.array_equal(_bits(prop.state), _bits(ref.y[:, -1]))


def test_calls_continue_where_the_last_stopped():
    """Two calls against a quad-precision run (independent: another number type and its own
    steps), to the global error the tolerance allows: steps x rtol x |y|, growth included
    by a factor 10 per unit of the largest Lyapunov-like growth over T = 20 (rigid-body
    motion, growth at most linear here)."""
    rtol = 1e-12
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=rtol, atol=rtol)
    first = prop.propagate_until(7.7)
    second = prop.propagate_until("20.1", t_eval=[10, 15, 20.1])
    assert first.success and second.success and prop.time == 20.1
    quad = integrate(BALL, REFERENCE_Y0, (0, "20.1"), REFERENCE_PARAMS, precision="quad",
                     method="taylor", rtol=1e-30, atol=1e-30, t_eval=[0, "20.1"])
    steps = first.nsteps + second.nsteps
    bound = 10 * steps * rtol * float(np.max(np.abs(prop.state)))
    err = max(abs(float(a) - float(b)) for a, b in zip(prop.state, quad.y[:, -1], strict=True))
    assert err <= bound, (err, bound)
    assert err > 0  # a double run is not the quad run: the comparison is not trivial


def test_backward_returns_to_the_start():
    rtol = 1e-13
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=rtol, atol=rtol)
    y0 = prop.state
    fwd = prop.propagate_until(12.5)
    back = prop.propagate_until(0.0)
    assert fwd.success and back.success and prop.time == 0.0
    bound = 10 * (fwd.nsteps + back.nsteps) * rtol * float(np.max(np.abs(y0)))
    assert float(np.max(np.abs(prop.state - y0))) <= bound


def test_quad_precision_keeps_mpf_numbers():
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, precision="quad")
    r = prop.propagate_for(2)
    assert r.success and prop.state.dtype == object
    assert isinstance(prop.state[0], mpmath.mpf)
    assert max(r.drift.values()) < 1e-28


def test_bad_input_is_refused_and_changes_nothing():
    with pytest.raises(UserInputError, match="unit vector"):
        Propagator(BALL, {"M": (1, 0, 0), "gamma": (0.3, 0.3, 0.3)}, REFERENCE_PARAMS)
    with pytest.raises(UserInputError):
        Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=-1)
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=1e-10, atol=1e-10)
    y0 = prop.state
    for bad in ("nan", 0.0, "abc"):
        with pytest.raises(UserInputError):
            prop.propagate_until(bad)
    with pytest.raises(UserInputError, match="inside the span"):
        prop.propagate_until(5.0, t_eval=[1, 6])
    assert prop.time == 0.0 and np.array_equal(_bits(prop.state), _bits(y0))


def test_the_end_is_always_an_output():
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=1e-11, atol=1e-11)
    r = prop.propagate_until(5.0, t_eval=[1.0, 2.5])
    assert r.success and list(r.t) == [1.0, 2.5, 5.0] and prop.time == 5.0
    assert np.array_equal(_bits(prop.state), _bits(r.y[:, -1]))
    back = prop.propagate_for(-5.0, t_eval=[4.0, 1.0, 0.0])
    assert back.success and list(back.t) == [4.0, 1.0, 0.0] and prop.time == 0.0


@pytest.mark.parametrize("method", ["taylor", "DOP853"])
def test_output_times_out_of_order_are_refused(method):
    with pytest.raises(UserInputError, match="sorted in the direction"):
        integrate(BALL, REFERENCE_Y0, 10, REFERENCE_PARAMS, method=method, t_eval=[0, 5, 2, 10])
    with pytest.raises(UserInputError, match="sorted in the direction"):
        integrate(BALL, REFERENCE_Y0, (10, 0), REFERENCE_PARAMS, method=method, t_eval=[10, 2, 5])
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS)
    with pytest.raises(UserInputError, match="sorted in the direction"):
        prop.propagate_until(10, t_eval=[5, 2])
    assert prop.time == 0.0


def test_reset_goes_back_to_the_start_bit_for_bit():
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12)
    first = prop.propagate_until(11.3, t_eval=[0, 4.1, 11.3])
    prop.propagate_until(15.0)
    prop.reset()
    assert prop.time == 0.0
    again = prop.propagate_until(11.3, t_eval=[0, 4.1, 11.3])
    assert np.array_equal(_bits(first.y), _bits(again.y)) and first.drift == again.drift


def test_reset_to_a_new_state_reads_it_as_integrate_does():
    other = {"M": ("0.31", "-0.52", "0.77"), "gamma": ("0.6", "-0.48", "sqrt(0.4096)")}
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12)
    prop.reset(other, t0="0.25")
    r = prop.propagate_until(9.0)
    ref = integrate(BALL, other, ("0.25", 9.0), REFERENCE_PARAMS, method="taylor",
                    rtol=1e-12, atol=1e-12, t_eval=["0.25", 9.0])
    assert np.array_equal(_bits(r.y), _bits(ref.y)) and r.drift == ref.drift


def test_reset_refuses_a_bad_state_and_changes_nothing():
    prop = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12)
    prop.propagate_until(3.0)
    before, t = prop.state, prop.time
    with pytest.raises(UserInputError, match="unit vector"):
        prop.reset({"M": (0.7, -0.4, 0.5), "gamma": (0.2, 0.3, 0.3)})
    with pytest.raises(UserInputError):
        prop.reset(t0="nan")
    assert prop.time == t and np.array_equal(_bits(prop.state), _bits(before))


def test_blocks_of_the_compiled_loop_give_the_uncut_run(chunk_steps):
    """With a wall-time limit the compiled loop runs in blocks resumed from the exact state,
    time and compensation; blocks of 7 steps give the bits of one uninterrupted call, the
    outputs that fall in later blocks included (the buffers are addressed past the first)."""

    t_eval = list(np.linspace(0.0, 40.0, 23))
    whole = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12,
                       max_wall_s=None).propagate_until(40.0, t_eval)
    chunk_steps("double", 7)
    cut = Propagator(BALL, REFERENCE_Y0, REFERENCE_PARAMS, rtol=1e-12, atol=1e-12)
    assert cut._fast is not None and cut._fast.loop.chunk == 7
    r = cut.propagate_until(40.0, t_eval)
    assert whole.success and r.success and r.nsteps == whole.nsteps > 7 * 5
    assert np.array_equal(_bits(r.t), _bits(whole.t))
    assert np.array_equal(_bits(r.y), _bits(whole.y))
