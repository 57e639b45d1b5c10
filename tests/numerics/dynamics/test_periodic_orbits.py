"""Periodic orbits of maps and their continuation, on maps whose answers are known.

References are computed by independent routes: closed forms (logistic period 2,
``r2 = 1 + sqrt(6)``; Hénon fixed point and its doubling ``a1 = 3 (1 - b)^2/4``; the
period-3 window of the logistic map at ``1 + sqrt(8)``; the delayed logistic map's
Neimark–Sacker at ``a = 2``) and, for the later doublings, ``mpmath.findroot`` at 40 digits
on the system ``f^k(x) = x``, ``(f^k)'(x) = -1`` (a different method from the continuation's
test function and secant location). Feigenbaum's delta = 4.669201609102990... (Feigenbaum
1978).
"""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import ComputationError, UserInputError
from chaplygin.numerics.dynamics.continuation import bifurcation_indicators, continue_periodic_orbit
from chaplygin.numerics.dynamics.periodic_orbits import (
    SmoothMap,
    detect_period,
    floquet_multipliers,
    refine_periodic_orbit,
)

EPS = float(np.finfo(float).eps)
FEIGENBAUM_DELTA = 4.669201609102990


# ------------------------------------------------------------------ maps
def logistic(digits: int | None = None) -> SmoothMap:
    def f(x, r):
        return r * x * (1 - x)

    def df(x, r):
        if digits is None:
            return f(x, r), np.array([[r * (1 - 2 * x[0])]])
        return f(x, r), mpmath.matrix([[r * (1 - 2 * x[0])]])

    return SmoothMap(
        f,
        df,
        1,
        digits=digits,
        accuracy=10 * EPS if digits is None else float(mpmath.mpf(10) ** (2 - digits)),
    )


def henon(b: float = 0.3) -> SmoothMap:
    def f(x, a):
        return np.array([1 - a * x[0] ** 2 + x[1], b * x[0]])

    def df(x, a):
        return f(x, a), np.array([[-2 * a * x[0], 1.0], [b, 0.0]])

    return SmoothMap(f, df, 2, accuracy=10 * EPS)


def delayed_logistic() -> SmoothMap:
    """x' = a x (1 - y), y' = x (Kuznetsov §4.7)."""

    def f(x, a):
        return np.array([a * x[0] * (1 - x[1]), x[0]])

    def df(x, a):
        return f(x, a), np.array([[a * (1 - x[1]), -a * x[0]], [1.0, 0.0]])

    return SmoothMap(f, df, 2, accuracy=10 * EPS)


def neutral_saddle() -> SmoothMap:
    """Fixed point 0 with real multipliers 2 + p and 1/2: their product passes 1 at p = 0
    (a neutral saddle, not a Neimark–Sacker)."""

    def f(x, p):
        return np.array([(2 + p) * x[0] + x[0] ** 2, 0.5 * x[1] + x[1] ** 3])

    def df(x, p):
        return f(x, p), np.array([[2 + p + 2 * x[0], 0.0], [0.0, 0.5 + 3 * x[1] ** 2]])

    return SmoothMap(f, df, 2, accuracy=10 * EPS)


def _doubling_reference(k: int, r_guess: str, x_guess: float) -> mpmath.mpf:
    """r where the period-k orbit of the logistic map has multiplier -1 (40 digits)."""
    with mpmath.workdps(40):

        def system(x, r):
            y, d = x, mpmath.mpf(1)
            for _ in range(k):
                d *= r * (1 - 2 * y)
                y = r * y * (1 - y)
            return [y - x, d + 1]

        x, r = mpmath.findroot(system, (mpmath.mpf(x_guess), mpmath.mpf(r_guess)))
        return +r


# ------------------------------------------------------------------ period detection
@pytest.mark.parametrize("r, period", [(3.2, 2), (3.5, 4), (3.83, 3)])
def test_detect_period_of_the_logistic_attractor(r, period):
    m = logistic()
    orbit = np.array(m.iterate(np.array([0.3141]), r, 3000)[2000:])
    # contraction |mu|^n after 2000 steps is far below 1e-10 for these stable orbits
    assert detect_period(orbit, 32, 1e-10) == period


def test_detect_period_none_on_chaos():
    m = logistic()
    orbit = np.array(m.iterate(np.array([0.3141]), 3.7, 3000)[1000:])
    assert detect_period(orbit, 64, 1e-6) is None


def test_detect_period_wraps_angles():
    # rotation by 2 pi / 5 on a circle: period 5 only with the angle wrapped
    theta = (0.37 + 2 * np.pi / 5 * np.arange(40)) % (2 * np.pi) - np.pi
    assert detect_period(theta[:, None], 10, 1e-12, angles=(0,)) == 5
    unwrapped = 0.37 + 2 * np.pi / 5 * np.arange(40)
    assert detect_period(unwrapped[:, None], 10, 1e-12) is None
    assert detect_period(unwrapped[:, None], 10, 1e-12, angles=(0,)) == 5


def test_detect_period_bad_input():
    with pytest.raises(UserInputError, match="iterates"):
        detect_period(np.zeros((5, 1)), 10, 1e-8)
    with pytest.raises(UserInputError):
        detect_period(np.zeros(50), 10, 1e-8)
    with pytest.raises(UserInputError):
        detect_period(np.zeros((50, 1)), 10, 0.0)


# ------------------------------------------------------------------ Newton and multipliers
def _period2_closed_form(r):
    """Logistic period-2 orbit: x = (r + 1 -+ sqrt((r - 3)(r + 1)))/(2 r), multiplier
    4 + 2 r - r^2."""
    sq = mpmath.sqrt((r - 3) * (r + 1)) if isinstance(r, mpmath.mpf) else np.sqrt((r - 3) * (r + 1))
    return (r + 1 - sq) / (2 * r), (r + 1 + sq) / (2 * r), 4 + 2 * r - r * r


def test_refine_period_two_double():
    r = 3.3137
    lo, hi, mult = _period2_closed_form(r)
    orbit = refine_periodic_orbit(logistic(), [0.5], 2, r)
    assert orbit.converged and orbit.residual <= orbit.tolerance
    x = sorted(float(p[0]) for p in orbit.points)
    # Newton's fixed point: error ~ residual / |mult - 1| (condition of F = P^2 - x)
    bound = 10 * orbit.tolerance / abs(mult - 1)
    assert abs(x[0] - lo) <= bound and abs(x[1] - hi) <= bound
    assert abs(orbit.multipliers[0] - mult) <= 100 * EPS * abs(mult) + bound * 4 * r * r
    assert orbit.stable == (abs(mult) < 1)


def test_refine_period_two_mpmath_40_digits():
    with mpmath.workdps(40):
        r = mpmath.mpf("3.3137")
        lo, hi, mult = _period2_closed_form(r)
    m = logistic(digits=40)
    orbit = refine_periodic_orbit(m, [mpmath.mpf("0.5")], 2, r)
    assert orbit.converged and orbit.digits == 40
    with mpmath.workdps(40):
        x = sorted(p[0] for p in orbit.points)
        bound = 10 * orbit.tolerance / abs(mult - 1)
        assert abs(x[0] - lo) <= bound and abs(x[1] - hi) <= bound
        assert abs(orbit.multipliers[0] - mult) <= 100 * bound
    assert bound < 1e-35  # far beyond double precision


def test_henon_fixed_point_multipliers_closed_form():
    a, b = 0.2718, 0.3
    x = (-(1 - b) + np.sqrt((1 - b) ** 2 + 4 * a)) / (2 * a)
    orbit = refine_periodic_orbit(henon(b), [0.5, 0.1], 1, a)
    assert orbit.converged
    assert np.max(np.abs(orbit.points[0] - [x, b * x])) <= 10 * orbit.tolerance
    # multipliers: lambda^2 + 2 a x lambda - b = 0
    expected = np.sort(np.roots([1, 2 * a * x, -b]))
    got = np.sort(floquet_multipliers(henon(b), orbit.points[0], a, 1).real)
    assert np.max(np.abs(got - expected)) <= 1e3 * EPS


def test_newton_onto_a_shorter_orbit_is_refused():
    # control: near the (unstable) fixed point 1 - 1/r, Newton for period 2 lands on it
    r = 3.2
    orbit = refine_periodic_orbit(logistic(), [1 - 1 / r + 1e-9], 2, r)
    assert not orbit.converged and "period 1" in orbit.message


def test_refine_bad_period():
    with pytest.raises(UserInputError):
        refine_periodic_orbit(logistic(), [0.5], 0, 3.2)
    with pytest.raises(UserInputError):
        refine_periodic_orbit(logistic(), [0.5, 0.2], 1, 3.2)


def test_singular_newton_matrix_is_a_computation_error():
    # a translation x' = x + p: D P - Id = 0 everywhere
    m = SmoothMap(lambda x, p: x + p, lambda x, p: (x + p, np.array([[1.0]])), 1)
    with pytest.raises(ComputationError, match="singular"):
        refine_periodic_orbit(m, [0.3], 1, 0.1)


# ------------------------------------------------------------------ continuation
def test_logistic_cascade_and_feigenbaum_ratios():
    res = continue_periodic_orbit(logistic(), [0.6], 1, 2.8, 3.5699, step=0.02, follow_doublings=5)
    found = res.doublings()
    assert [b.period for b in res.branches] == [1, 2, 4, 8, 16, 32]
    assert len(found) == 6
    refs = [mpmath.mpf(3), 1 + mpmath.sqrt(6)]
    # the published values (e.g. OEIS A086181 for r3) only start findroot; its root is the
    # reference (the orbit point of the located event starts x)
    guesses = ("3.5440903596", "3.5644072661", "3.5687594195", "3.5696916098")
    for e, r in zip(res.events[2:], guesses, strict=True):
        refs.append(_doubling_reference(e.period, r, float(e.point[0])))
    for e, ref in zip(res.events, refs, strict=True):
        assert e.kind == "period-doubling"
        # the continuation's Newton tolerance 10 k accuracy bounds the location (the bracket
        # is 10x that in p, and d(test)/dp >= 1 here); the multiplier is -1 to within the
        # square root of it (a multiplier's uncertainty, as in refine_periodic_orbit)
        newton_tol = 10 * e.period * logistic().accuracy
        assert abs(e.parameter - float(ref)) <= newton_tol, (e.period, e.parameter, ref)
        assert abs(e.multipliers[0] + 1) <= np.sqrt(newton_tol)
    ratios = np.diff(found)[:-1] / np.diff(found)[1:]
    ref_ratios = [float((refs[i + 1] - refs[i]) / (refs[i + 2] - refs[i + 1])) for i in range(4)]
    assert np.max(np.abs(ratios - ref_ratios)) <= 1e-3
    # the ratios approach Feigenbaum's delta
    err = np.abs(ratios - FEIGENBAUM_DELTA)
    assert err[-1] < err[0] and err[-1] < 1e-3


def test_no_event_where_nothing_happens():
    # control: the fixed point of the logistic map is stable on (1, 3): no event
    res = continue_periodic_orbit(logistic(), [0.6], 1, 2.2, 2.9, step=0.02)
    assert res.events == [] and "reached" in res.message


def test_henon_doublings():
    b = 0.3
    res = continue_periodic_orbit(
        henon(b), [0.8, 0.24], 1, 0.25, 1.0, step=0.02, follow_doublings=1
    )
    a1 = 3 * (1 - b) ** 2 / 4
    pd = [e for e in res.events if e.kind == "period-doubling"]
    assert abs(pd[0].parameter - a1) <= 1e-10
    # second doubling: the period-2 orbit with multiplier -1, by findroot at 40 digits
    with mpmath.workdps(40):

        def system(x, y, a):
            p = mpmath.matrix([[1, 0], [0, 1]])
            u, v = x, y
            for _ in range(2):
                p = mpmath.matrix([[-2 * a * u, 1], [b, 0]]) * p
                u, v = 1 - a * u * u + v, b * u
            return [u - x, v - y, mpmath.det(p + mpmath.eye(2))]

        x2, y2 = pd[1].point
        ref = mpmath.findroot(system, (x2 + 0.01, y2, pd[1].parameter + 0.001))[2]
    assert abs(pd[1].parameter - float(ref)) <= 1e-10


def test_saddle_node_of_the_period_three_window():
    # the period-3 window opens by a saddle-node at r = 1 + sqrt(8) (a fold of the branch)
    m = logistic()
    r0 = 3.845
    orbit = np.array(m.iterate(np.array([0.5]), r0, 2000)[-1])
    res = continue_periodic_orbit(m, orbit, 3, r0, 3.80, step=0.003, max_points=400)
    sn = [e for e in res.events if e.kind == "saddle-node"]
    assert len(sn) >= 1
    assert abs(sn[0].parameter - (1 + np.sqrt(8))) <= 1e-9
    assert abs(sn[0].multipliers[0] - 1) <= 1e-4
    # past the fold the branch comes back (the unstable partner): r rises again
    params = res.branches[0].parameters
    assert params.min() <= 1 + np.sqrt(8) + 1e-6 and params[-1] > params.min() + 1e-3


def test_neimark_sacker_of_the_delayed_logistic_map():
    # fixed point x = y = 1 - 1/a; D P has trace 1, det a - 1: |mu|^2 = a - 1, NS at a = 2
    res = continue_periodic_orbit(delayed_logistic(), [0.4, 0.4], 1, 1.5, 2.4, step=0.05)
    (ns,) = res.events
    assert ns.kind == "neimark-sacker"
    assert abs(ns.parameter - 2) <= 1e-10
    assert np.allclose(np.abs(ns.multipliers), 1, atol=1e-8)
    assert abs(abs(np.angle(ns.multipliers[0])) - np.pi / 3) <= 1e-8  # trace 1 = 2 cos(pi/3)


def test_neutral_saddle_is_not_a_neimark_sacker():
    # control: the bialternate test function changes sign at p = 0 here too, but the pair
    # (2 + p, 1/2) is real: the same location step must refuse to call it Neimark-Sacker
    tf = [bifurcation_indicators([2 + p, 0.5])["neimark-sacker"] for p in (-0.1, 0.1)]
    assert tf[0] * tf[1] < 0
    res = continue_periodic_orbit(neutral_saddle(), [0.0, 0.0], 1, -0.3, 0.3, step=0.05)
    assert res.events == []


def test_continuation_bad_input():
    with pytest.raises(UserInputError, match="different"):
        continue_periodic_orbit(logistic(), [0.6], 1, 2.5, 2.5)
    with pytest.raises(UserInputError, match="event"):
        continue_periodic_orbit(logistic(), [0.6], 1, 2.5, 2.8, events=("hopf",))
    with pytest.raises(UserInputError, match="double"):
        continue_periodic_orbit(logistic(digits=30), [0.6], 1, 2.5, 2.8)


# ------------------------------------------------------------------ BM20 reduced coordinates
def test_andoyer_deprit_round_trip_and_tangent():
    from chaplygin.numerics.ball.bm20_map import bm20_point, bm20_state
    from chaplygin.numerics.ball.map_coordinates import reduced_tangent

    G = 2.7183
    x = np.array([0.3141, -2.2718, 1.4142])
    y = bm20_state(x, G)
    # on BM20's level set: |M| = G, (M, gamma) = 0, |gamma| = 1 (BM20-3.7)
    assert abs(np.linalg.norm(y[:3]) - G) <= 10 * EPS * G
    assert abs(y[:3] @ y[3:]) <= 10 * EPS * G
    assert abs(np.linalg.norm(y[3:]) - 1) <= 10 * EPS
    assert np.max(np.abs(bm20_point(y) - x)) <= 100 * EPS
    # the tangent against central differences (error h^2 |y'''| / 6 + eps/h)
    h = 1e-5
    fd = np.array(
        [(bm20_state(x + h * e, G) - bm20_state(x - h * e, G)) / (2 * h) for e in np.eye(3)]
    ).T
    assert np.max(np.abs(fd - reduced_tangent(x, G))) <= G * (h**2 + 10 * EPS / h)


def test_reduced_tangent_refuses_the_poles():
    from chaplygin.numerics.ball.map_coordinates import reduced_tangent

    with pytest.raises(UserInputError, match="singular"):
        reduced_tangent((1.0, 0.3, 0.2), 3.0)


def test_many_map_points_at_once_are_the_points_one_at_a_time():
    """bm20_points on an array of states: bit for bit bm20_point on each (the poles, where
    l = 0 by convention, and a state at the pole included)."""
    import numpy as np
    from chaplygin.numerics.ball.bm20_map import bm20_point, bm20_points, bm20_state

    rng = np.random.default_rng(7)
    X = np.column_stack([rng.uniform(-0.99, 0.99, 200), rng.uniform(-3, 3, 200),
                         rng.uniform(-3, 3, 200)])  # fmt: skip
    Y = np.array([bm20_state(x, 3.0) for x in X] + [bm20_state([1.0, 0.0, 0.4], 3.0)])
    many = bm20_points(Y)
    one = np.array([bm20_point(y) for y in Y])
    assert many.shape == (201, 3)
    assert np.array_equal(many.view(np.uint64), one.view(np.uint64))
    assert np.allclose(many[:200], X, atol=1e-12)  # and they are the map points
