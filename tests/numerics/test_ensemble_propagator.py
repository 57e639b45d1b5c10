"""Many orbits prepared once and advanced together (numerics/ensemble_propagator.py, issue 26).

The reference for every orbit is a :class:`Propagator` of that orbit alone, called with the
same times: another route (the one-orbit compiled loop, or in quad the one-orbit mpmath/C
route, against the vector lanes), the same operations, so the same bits.
"""

from __future__ import annotations

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics.ensemble_propagator import EnsemblePropagator
from chaplygin.numerics.propagator import Propagator
from reference import REFERENCE_PARAMS

BALL = "chaplygin_ball"


def _starts(count: int, seed: int = 11) -> list[list[float]]:
    """Generic starts (no dyadic numbers): M random, gamma a random unit vector."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        g = rng.normal(size=3)
        out.append([*(rng.uniform(-0.9, 0.9, 3)), *(g / np.linalg.norm(g))])
    return out


def _params(count: int, seed: int = 5) -> list[list[float]]:
    rng = np.random.default_rng(seed)
    return [[*np.sort(rng.uniform(1.1, 3.3, 3)), rng.uniform(0.7, 1.4)] for _ in range(count)]


def _bits(a) -> np.ndarray:
    return np.asarray(a, dtype=np.float64).view(np.int64)


def _same_orbit(got, one) -> bool:
    return (
        got.status == one.status
        and got.nsteps == one.nsteps
        and np.array_equal(_bits(got.y), _bits(one.y))
        and got.drift == one.drift
        and got.message == one.message
    )


@pytest.mark.parametrize("rtol", [1e-9, 1e-12])
def test_every_orbit_is_its_own_propagator_bit_for_bit_over_several_calls(rtol):
    """Forward with outputs, on, then backward: each orbit of the ensemble (its own
    parameters too) against its own Propagator, for 9 orbits (not a multiple of the lanes)."""
    starts, params = _starts(9), _params(9)
    ens = EnsemblePropagator(BALL, starts, params, rtol=rtol, atol=rtol)
    singles = [Propagator(BALL, s, p, rtol=rtol, atol=rtol)
               for s, p in zip(starts, params, strict=True)]  # fmt: skip
    calls = [(3.7, [0.9, 2.3]), (8.1, None), (-1.3, [5.2, 0.4])]
    for t, t_eval in calls:
        r = ens.propagate_until(t, t_eval)
        assert r.success.all() and ens.time == t
        for j, single in enumerate(singles):
            one = single.propagate_until(t, t_eval)
            assert _same_orbit(r.results[j], one), (t, j)
            assert np.array_equal(_bits(r.y[j]), _bits(one.y))
            assert r.status[j] == one.status
            assert {k: v[j] for k, v in r.drift.items()} == one.drift
            assert np.array_equal(_bits(ens.states[j]), _bits(single.state))


def test_one_state_with_many_parameter_sets_and_propagate_for():
    params = _params(6, seed=9)
    start = _starts(1, seed=3)[0]
    ens = EnsemblePropagator(BALL, start, params, rtol=1e-10, atol=1e-10, t0="0.25")
    r = ens.propagate_for(2.9)
    for j, p in enumerate(params):
        one = Propagator(BALL, start, p, rtol=1e-10, atol=1e-10, t0="0.25").propagate_for(2.9)
        assert _same_orbit(r.results[j], one)
    assert ens.time == 0.25 + 2.9


@pytest.mark.parametrize("backend", ["auto", "numpy"])
def test_when_an_orbit_fails_nothing_moves_and_each_orbit_says_why(backend):
    """A step limit between the orbits' needs: the slower orbits reach the end, the fastest
    spinning one does not; the ensemble stays where it was (the reference: each orbit's
    Propagator with the same limit), in the lanes and one orbit after another. The control:
    without the limit every orbit moves."""
    starts = _starts(5, seed=2)
    starts[3] = [3 * v for v in starts[3][:3]] + starts[3][3:]  # spins faster: more steps
    kw = {"rtol": 1e-12, "atol": 1e-12, "backend": backend}
    need = [Propagator(BALL, s, REFERENCE_PARAMS, **kw).propagate_until(6.1).nsteps
            for s in starts]  # fmt: skip
    limit = (max(need) + sorted(need)[-2]) // 2
    assert sorted(need)[-2] < limit < max(need)
    opts = {"max_steps": limit}
    ens = EnsemblePropagator(BALL, starts, REFERENCE_PARAMS, taylor_options=opts, **kw)
    before = ens.states
    r = ens.propagate_until(6.1)
    assert r.success.tolist() == [n <= limit for n in need]
    assert ens.time == 0.0 and np.array_equal(_bits(ens.states), _bits(before))
    for j, s in enumerate(starts):
        one = Propagator(BALL, s, REFERENCE_PARAMS, taylor_options=opts, **kw)
        assert r.status[j] == one.propagate_until(6.1).status
    again = ens.propagate_until(6.1)  # from where it was: the same outcome
    assert np.array_equal(_bits(again.y[:, :, 0]), _bits(r.y[:, :, 0]))
    free = EnsemblePropagator(BALL, starts, REFERENCE_PARAMS, **kw)
    assert free.propagate_until(6.1).success.all() and free.time == 6.1


def test_reset_goes_back_and_refused_input_changes_nothing():
    starts = _starts(6, seed=4)
    ens = EnsemblePropagator(BALL, starts, REFERENCE_PARAMS, rtol=1e-11, atol=1e-11)
    first = ens.propagate_until(4.4)
    ens.propagate_until(7.0)
    ens.reset()
    assert ens.time == 0.0
    again = ens.propagate_until(4.4)
    assert np.array_equal(_bits(first.y), _bits(again.y))
    moved = ens.states
    with pytest.raises(UserInputError, match="orbit 2"):
        ens.reset([*starts[:2], [0.1, 0.2, 0.3, 0.6, 0.0, 0.7], *starts[3:]])  # |gamma| != 1
    with pytest.raises(UserInputError, match="needs 6 states"):
        ens.reset(starts[:5])
    assert ens.time == 4.4 and np.array_equal(_bits(ens.states), _bits(moved))
    new = _starts(6, seed=8)
    ens.reset(new, t0=1.5)
    r = ens.propagate_until(3.0)
    one = Propagator(BALL, new[4], REFERENCE_PARAMS, rtol=1e-11, atol=1e-11, t0=1.5)
    assert _same_orbit(r.results[4], one.propagate_until(3.0))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"backend": "fortran"}, "unknown backend"),
        ({"threads": 0}, "threads must be a positive integer"),
        ({"y0": [[0.1, 0.2, 0.3, 0.6, 0.0, 0.8], [0.1, 0.2, 0.3, 1.6, 0.0, 0.8]]}, "orbit 1"),
        ({"params": [REFERENCE_PARAMS] * 3}, "y0 has 2 rows but params has 3"),
    ],
)
def test_bad_input_is_refused_naming_the_orbit(kwargs, match):
    args = {"y0": _starts(2), "params": REFERENCE_PARAMS, **kwargs}
    y0, params = args.pop("y0"), args.pop("params")
    with pytest.raises(UserInputError, match=match):
        EnsemblePropagator(BALL, y0, params, **args)


def test_the_end_time_is_checked_as_a_propagators():
    ens = EnsemblePropagator(BALL, _starts(2), REFERENCE_PARAMS)
    with pytest.raises(UserInputError, match="equals the current time"):
        ens.propagate_until(0.0)
    with pytest.raises(UserInputError, match="inside the span"):
        ens.propagate_until(1.0, [0.5, 1.5])
    assert ens.time == 0.0


@pytest.mark.parametrize(("precision", "backend"), [("quad", "auto"), ("double", "numpy")])
def test_outside_the_lanes_each_orbit_is_its_propagator(precision, backend):
    """Quad, and the numpy backend in double: one Propagator per orbit (the same numbers)."""
    starts = _starts(3, seed=6)
    kw = {"precision": precision, "backend": backend, "rtol": 1e-20 if precision == "quad"
          else 1e-10}  # fmt: skip
    kw["atol"] = kw["rtol"]
    ens = EnsemblePropagator(BALL, starts, REFERENCE_PARAMS, **kw)
    assert "one orbit after another" in repr(ens)
    r = ens.propagate_until("0.7")
    for j, s in enumerate(starts):
        one = Propagator(BALL, s, REFERENCE_PARAMS, **kw).propagate_until("0.7")
        assert r.status[j] == one.status and r.nsteps[j] == one.nsteps
        assert all(a == b for a, b in zip(r.y[j].ravel(), one.y.ravel(), strict=True))
    assert ens.time == one.t[-1]
