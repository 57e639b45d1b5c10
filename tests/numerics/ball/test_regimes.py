"""Regimes of the stroboscopic map's attractor (numerics/ball/regimes.py) and the symmetric copies
of attractors (numerics/ball/symmetry.py): the ball's equations are equivariant under
gamma -> -gamma (BM20-3.1, BKM12-3.sym), so a run lands on either of two mirror copies; both
report the same canonical orbit with the copy named.

BM20 Fig. 5/7's system: I = diag(4, 3, 2), K = (-6, -3, -9), d = 4.385, J = 0, delta = 2,
G = 3. No test rests on where a chaotic orbit goes: the periodic cases start near a stable
cycle (or compare a run with its exact mirror image), the chaotic one is decided by its
largest Lyapunov exponent, about 10 standard errors above the threshold.
"""

from __future__ import annotations

import numpy as np
import pytest
from chaplygin.numerics.ball.bm20_map import BM20_STATE, bm20_point, bm20_state
from chaplygin.numerics.ball.regimes import attractor_regime, linear_growth_rate, map_points_scaled
from chaplygin.numerics.ball.symmetry import (
    MIRROR,
    canonical_cycle,
    copy_statistic,
    mirror_states,
    name_copy,
    symmetries_of,
)
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.dynamics.batch_map import batch_map_available

CODE = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
pytestmark = pytest.mark.skipif(not batch_map_available(CODE), reason="no C compiler")
FIG5 = [4, 3, 2, 4.385, 0, 2, -6, -3, -9]  # I1 I2 I3 D J_off delta K1 K2 K3 (Omega appended)
START = bm20_state([0.5, 1.0, 1.0], 3.0)  # BM20 Fig. 5's g = l = 1, z = 0.5
#: A start 3e-3 from a point of Fig. 7A's 7-cycle (tests/verify/scene/test_periodic_output.py),
#: in its basin:
#: the cycle is reached by its own contraction (multipliers 0.97 per period 7), not after a
#: chaotic transient whose length depends on the last bits (from START: 825 to 8112 periods on
#: 48 perturbed starts).
NEAR_CYCLE = bm20_state([-0.44, 1.46, -1.01], 3.0)


@pytest.mark.parametrize(
    "effects", [(), ("gyrostat",), ("variable_inertia",), ("variable_inertia", "variable_gyrostat")]
)
def test_the_generated_equations_are_equivariant_under_the_mirror(effects):
    """f(t, M, -gamma) = S f(t, M, gamma) (S = diag(1, 1, 1, -1, -1, -1)) for the generated
    right-hand sides at seeded random states and parameters, to rounding; the same test
    refutes the reversing map (M, gamma) -> (-M, gamma) without t -> -t (the control)."""
    code = load_model_code("chaplygin_ball", list(effects))
    assert symmetries_of(code) == (MIRROR,)
    S = MIRROR.sign_vector(code.state, code.state_groups)
    R = np.where(np.isin(code.state, ["M1", "M2", "M3"]), -1.0, 1.0)
    rng = np.random.default_rng(22)
    worst_control = 0.0
    for _ in range(5):
        y = rng.normal(size=len(code.state))
        y[3:6] /= np.linalg.norm(y[3:6])
        p = rng.uniform(0.5, 2.0, len(code.params))
        t = float(rng.uniform(0, 10))
        f = np.asarray(code.numpy.rhs(t, y, p), float)
        g = np.asarray(code.numpy.rhs(t, S * y, p), float)
        assert np.max(np.abs(g - S * f)) <= 64 * np.finfo(float).eps * np.max(np.abs(f))
        h = np.asarray(code.numpy.rhs(t, R * y, p), float)
        worst_control = max(worst_control, np.max(np.abs(h - R * f)) / np.max(np.abs(f)))
    assert worst_control > 1e-3


def test_no_symmetry_is_claimed_for_other_systems():
    assert symmetries_of(load_model_code("spherical_support")) == ()


def test_copy_rule_is_odd_and_names_self_symmetric_sets():
    """phi changes sign under the mirror, so a sample and its mirror image are named as
    opposite copies; a set that contains its own mirror image is 'self' (as a periodic orbit
    and as a sample); a rotation of the cycle
    (another starting point) is the same copy (the control: not every change flips it)."""
    rng = np.random.default_rng(5)
    y = np.column_stack([rng.normal(size=(40, 3)) + [0.3, -0.2, 0.5], rng.normal(size=(40, 3))])
    y[:, 3:] /= np.linalg.norm(y[:, 3:], axis=1, keepdims=True)
    y[:, 3:] += [0.4, 0.1, 0.3]  # a mean of gamma: not a symmetric set
    a = name_copy(y, BM20_STATE, periodic=True, tol=1e-12)
    b = name_copy(mirror_states(y, BM20_STATE), BM20_STATE, periodic=True, tol=1e-12)
    assert {a.copy, b.copy} == {"canonical", "mirror"}
    assert a.statistic == pytest.approx(-b.statistic, abs=1e-15)
    assert name_copy(np.roll(y, 7, axis=0), BM20_STATE, periodic=True, tol=1e-12).copy == a.copy
    both = np.vstack([y, mirror_states(y, BM20_STATE)])
    assert name_copy(both, BM20_STATE, periodic=True, tol=1e-12).copy == "self"
    assert abs(copy_statistic(both, BM20_STATE)[0]) <= 1e-15
    assert name_copy(both, BM20_STATE).copy == "self"  # as a sample: its mirror is itself
    assert (
        canonical_cycle(y, BM20_STATE, a).tolist()
        == canonical_cycle(mirror_states(y, BM20_STATE), BM20_STATE, b).tolist()
    )


def test_mirror_images_of_the_fig7a_cycle_report_the_same_canonical_orbit():
    """BM20 Fig. 7A (Omega = 1.06675): from a start in the 7-cycle's basin and from its mirror
    image the map lands on the stable 7-cycle (multipliers 0.97, BM20 README) and its mirror
    copy (the equations are equivariant): the copies are named opposite and the canonical
    orbits agree to the closing tolerance; in (z, l, g) the mirror is g + pi (the issue's
    observation)."""
    p = [*FIG5, 1.06675]
    runs = [attractor_regime(CODE, p, y0, transient=3000, max_period=32) for y0 in
            (NEAR_CYCLE, mirror_states(NEAR_CYCLE, BM20_STATE))]  # fmt: skip
    assert [r.regime for r in runs] == ["periodic", "periodic"]
    assert [r.period for r in runs] == [7, 7]
    assert {r.copy.copy for r in runs} == {"canonical", "mirror"}
    assert {r.copy.symmetric_copy for r in runs} == {"none", "gamma -> -gamma"}
    cycles = [canonical_cycle(r.points[-7:], BM20_STATE, r.copy) for r in runs]
    assert np.max(np.abs(map_points_scaled(cycles[0], BM20_STATE)
                         - map_points_scaled(cycles[1], BM20_STATE))) <= 1e-4  # fmt: skip
    x, xm = bm20_point(runs[0].points[-1]), bm20_point(runs[1].points[-1])
    assert abs(xm[0] - x[0]) < 1e-8 and abs(xm[1] - x[1]) < 1e-8
    assert abs((xm[2] - x[2]) % (2 * np.pi) - np.pi) < 1e-8


def test_regimes_periodic_quasi_periodic_and_chaotic():
    """Omega = 1.06675: the 7-cycle (started on it: the end state of the run above's kind);
    1.0675 (between the Neimark-Sacker at 1.06707 and the 1:4 locking at 1.0681): an
    invariant curve, largest exponent zero within its error; 1.07 (Fig. 5): chaotic, the
    largest exponent over 8000 iterations 0.04 per iteration (BM20-Lyap: 0.041 +- 0.009),
    far above ln(N)/N + 3 errors. The classification uses no knowledge of these values."""
    near = attractor_regime(CODE, [*FIG5, 1.06675], NEAR_CYCLE, transient=3000, max_period=32).end
    cycle = attractor_regime(CODE, [*FIG5, 1.06675], near, transient=0, max_period=32)
    assert (cycle.regime, cycle.period) == ("periodic", 7)
    assert np.isnan(cycle.lyapunov)  # not measured
    curve = attractor_regime(CODE, [*FIG5, 1.0675], near, transient=4000, max_period=32)
    assert (curve.regime, curve.period) == ("quasi-periodic", 0)
    assert abs(curve.lyapunov) <= 3 * curve.lyapunov_error + linear_growth_rate(2000)
    chaos = attractor_regime(CODE, [*FIG5, 1.07], START, transient=500, intervals=8000)
    assert chaos.regime == "chaotic" and chaos.period == 0
    assert chaos.lyapunov - 3 * chaos.lyapunov_error > linear_growth_rate(8000)
    assert abs(chaos.lyapunov - 0.041) <= 3 * np.hypot(chaos.lyapunov_error, 0.009)


def test_regime_refuses_bad_settings():
    from chaplygin.derive.errors import UserInputError

    with pytest.raises(UserInputError, match="recorded"):
        attractor_regime(CODE, [*FIG5, 1.07], START, recorded=10, max_period=32)
    with pytest.raises(UserInputError, match="tol"):
        attractor_regime(CODE, [*FIG5, 1.07], START, tol=2.0)
    with pytest.raises(UserInputError, match="Omega"):
        attractor_regime(load_model_code("chaplygin_ball"), [1, 2, 3, 1], START)


def test_fig4_invariant_curves_are_their_own_mirror_images():
    """BM20 Fig. 4 (Omega = 2, d = 4.5, K = (-4, -5, 3)): the attracting invariant curve of the
    starts (-0.5, -2, 2) and (0.1, 2.5, -1) is its own mirror image (within 1 % of its size;
    the phi statistic of a near-resonant sample is not decisive there), while the 7-cycle of
    Fig. 7A is not (the control, by the same naming)."""
    p = [4, 3, 2, 4.5, 0, 2, -4, -5, 3, 2.0]
    for x in ([-0.5, -2, 2], [0.1, 2.5, -1]):
        r = attractor_regime(CODE, p, bm20_state(x, 3.0), transient=3000, intervals=500)
        assert r.regime == "quasi-periodic" and r.copy.copy == "self"
    cycle = attractor_regime(CODE, [*FIG5, 1.06675], NEAR_CYCLE, transient=3000, max_period=32)
    points = np.vstack([cycle.points] * 3)  # the cycle as a sample, not as a periodic orbit
    assert name_copy(points, BM20_STATE).copy in ("canonical", "mirror")


def test_classify_exponent_thresholds():
    """The rule on synthetic exponents (N = 2000, r = ln(N)/N = 0.0038): chaotic beyond r + 3
    errors, contracting below -(r + 3 errors), quasi-periodic within r + 2 errors of 0,
    undecided between (an intermittent orbit: 0.09 +- 0.03)."""
    from chaplygin.numerics.ball.regimes import classify_exponent

    r = linear_growth_rate(2000)
    assert classify_exponent(0.044, 0.004, 2000) == "chaotic"
    assert classify_exponent(0.09, 0.03, 2000) == "undecided"
    assert classify_exponent(0.0005, 0.001, 2000) == "quasi-periodic"
    assert classify_exponent(r + 2 * 0.001 + 1e-9, 0.001, 2000) == "undecided"
    assert classify_exponent(-0.02, 0.001, 2000) == "contracting"
    assert classify_exponent(-r - 2.5 * 0.001, 0.001, 2000) == "undecided"


def test_settled_period_tells_a_slow_spiral_from_a_longer_cycle():
    """A spiral onto a 7-cycle whose multiplier turns by pi/2 per cycle closes at 28 before it
    settles: its period is 7; a genuine 14-cycle (pairs 1e-3 apart, settled) keeps 14; a
    spiral with closure at 28 found by closing_period on such data (the control: without the
    check the period would be 28)."""
    from chaplygin.numerics.ball.regimes import closing_period, settled_period

    rng = np.random.default_rng(3)
    cycle = rng.normal(size=(7, 3))
    k = np.arange(600)
    decay = 5e-4 * 0.9934**k  # |mu| = 0.955 per 7 iterations
    turn = (np.pi / 2) * (k // 7)  # the multiplier's argument, per cycle of 7
    spiral = (
        cycle[k % 7]
        + (decay * np.cos(turn))[:, None] * [1, 0, 0]
        + (decay * np.sin(turn))[:, None] * [0, 1, 0]
    )
    p = closing_period(spiral, 64, 1e-4)
    assert p == 28  # the control: it closes at 28 ...
    assert settled_period(spiral, p) == 7  # ... but settles onto the 7-cycle
    slow = (
        cycle[k % 7]
        + (5e-5 * 0.9992**k * np.cos(turn))[:, None] * [1, 0, 0]
        + (5e-5 * 0.9992**k * np.sin(turn))[:, None] * [0, 1, 0]
    )  # |mu| = 0.9946 per cycle: 38 % decay over the record
    assert settled_period(slow, 28) == 7
    doubled = np.vstack([cycle, cycle + 1e-3])[(k % 14)]
    assert closing_period(doubled, 64, 1e-4) == 14 and settled_period(doubled, 14) == 14


def test_lyapunov_from_rest_on_the_sphere_of_gamma():
    """From rest (Fig. 2's body at Omega = 0.6, J = 0.9) the map acts on the sphere of gamma:
    with subspace = {delta M = 0, delta gamma normal to gamma} (projected onto the level set as
    usual) the two exponents sum to the mean divergence (tr J: the delta M block only
    rotates) to rounding; the level set's whole tangent space (the control) adds the rotating
    delta M directions, whose exponent 0 hides the contraction: its largest exponent lies
    above the sphere's by more than 3 errors."""
    from chaplygin.numerics.ball.regimes import _from_rest_subspace
    from chaplygin.numerics.dynamics.lyapunov import lyapunov_spectrum

    p = [4, 3, 2, 1.5, 0.9, 1.2, 3, -1, -2, 0.6]
    y0 = np.array([0, 0, 0, 0.6, 0.0, 0.8])
    sphere = lyapunov_spectrum(CODE, p, y0, intervals=2000, transient=200,
                               subspace=_from_rest_subspace(y0, CODE.state))  # fmt: skip
    lam, err = sphere.per_iteration(sphere.exponents), sphere.per_iteration(sphere.errors)
    assert len(lam) == 2 and lam[0] < 0  # two exponents, both negative
    div = sphere.per_iteration(sphere.mean_divergence)
    assert abs(lam.sum() - div) <= 1e-6 * abs(div)  # Liouville on the sphere's plane
    level = lyapunov_spectrum(CODE, p, y0, intervals=2000, transient=200, count=1)
    top = level.per_iteration(level.exponents)[0]
    assert top - lam[0] > 3 * (err[0] + level.per_iteration(level.errors)[0])


def test_regimes_of_many_starts_are_each_start_s_on_its_own():
    """attractor_regimes: five starts in one call (a 7-cycle, an invariant curve, two chaotic
    starts with different phases, a start that fails) give each start the result of
    attractor_regime on it alone, bit for bit (points, period, exponent, error); the
    exponents are those of lyapunov_spectrum (one point, no lanes) from the end states. The
    failing start (its equations overflow) fails alone."""
    from chaplygin.derive.errors import ComputationError
    from chaplygin.numerics.ball.regimes import attractor_regimes
    from chaplygin.numerics.dynamics.lyapunov import lyapunov_spectrum

    near = attractor_regime(CODE, [*FIG5, 1.06675], NEAR_CYCLE, transient=3000, max_period=32).end
    starts = [near, near, START, START, START]
    params = [[*FIG5, w] for w in (1.06675, 1.0675, 1.07, 1.0703, 1.07)]
    params[4][3] = 1e300  # an absurd d: the equations overflow, this start fails
    phases = [0.0, 0.0, 0.0, 0.37, 0.0]
    opts = dict(transient=400, max_period=32, intervals=300)
    many = attractor_regimes(CODE, params, starts, t0=phases, **opts)
    assert isinstance(many[4], ComputationError)
    with pytest.raises(ComputationError):
        attractor_regime(CODE, params[4], START, **opts)
    assert many[0].regime == "periodic" and many[0].period == 7
    assert [r.period for r in many[1:4]] == [0, 0, 0]
    for j in range(4):
        one = attractor_regime(CODE, params[j], starts[j], t0=phases[j], **opts)
        assert np.array_equal(one.points, many[j].points)
        assert (one.regime, one.period, one.work) == (many[j].regime, many[j].period, many[j].work)
        assert np.array_equal([one.lyapunov, one.lyapunov_error],
                              [many[j].lyapunov, many[j].lyapunov_error], equal_nan=True)
        if many[j].period == 0:
            tau = 2 * np.pi / params[j][-1]
            spec = lyapunov_spectrum(CODE, params[j], many[j].end, intervals=300, transient=100,
                                     t0=phases[j] + (400 + 600) * tau, rtol=1e-10,
                                     atol=1e-12, count=1)  # fmt: skip
            assert spec.per_iteration(spec.exponents)[0] == many[j].lyapunov
            assert spec.per_iteration(spec.errors)[0] == many[j].lyapunov_error


def test_regimes_refuse_mismatched_shapes():
    from chaplygin.derive.errors import UserInputError
    from chaplygin.numerics.ball.regimes import attractor_regimes

    with pytest.raises(UserInputError, match="rows"):
        attractor_regimes(CODE, [[*FIG5, 1.07]] * 2, [START] * 3)
