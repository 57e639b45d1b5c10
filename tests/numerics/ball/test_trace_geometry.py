"""The contact trace period by period on M || gamma and M + K || gamma (K01 §3.3, §4).

Independent routes: the turn per period against ``frame_turn.frame_turn`` (another return
condition, the frame instead of the velocity); the circle of the points ``z(kT)`` against a
long integration of the full equations (the straight drift refuted by the same comparison);
the equilibria of the gyrostat's segment against the Euler characteristic and the extreme
energies of a grid; a saddle's rate against the logarithmic growth of the period; the
spiral centres against K01-3.7's closed form of Delta. All motions here are integrable
(``gamma`` periodic), none chaotic.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate
from chaplygin.numerics.ball.frame_turn import frame_turn
from chaplygin.numerics.ball.gyrostat_segment import gradient_line, segment_equilibria
from chaplygin.numerics.ball.separatrix import delta_closed_form, mu_of
from chaplygin.numerics.ball.trace_geometry import segment_energy, spiral_centres, trace_period

#: A generic body (non-dyadic values), and K01 Fig. 7's.
GEN = {"I": (1.3, 2.9, 4.4), "D": 0.7, "C": 0.83}
FIG7 = {"I": (1.0, 3.0, 5.0), "D": 1.0, "K": (0.1, 0.1, 0.2), "C": 1.0}


def _segment_ends(I, D, C):
    hs = sorted(C * C / (2 * np.asarray(I)))
    return hs[0], hs[1], hs[2]


@pytest.mark.parametrize("where", [0.23, 0.71])
def test_turn_per_period_is_minus_the_frame_turn(where):
    I, D, C = GEN["I"], GEN["D"], GEN["C"]
    h3, h2, h1 = _segment_ends(I, D, C)
    h = h3 + where * (h1 - h3)
    assert abs(h - h2) > 1e-3
    tp = trace_period(I, D, h, C)
    T, phi = frame_turn(I, D, h, C)
    assert tp.period == pytest.approx(T, rel=1e-9)
    assert abs(np.angle(np.exp(1j * (tp.turn + phi)))) < 1e-8
    # the turning of the tangent is a lift of the turn
    assert abs(np.angle(np.exp(1j * (tp.turning - tp.turn)))) < 1e-8
    assert tp.closure < 1e-8
    assert tp.inner <= tp.radius <= tp.outer * (1 + 1e-12)


def test_points_after_whole_periods_lie_on_the_circle_not_on_a_line():
    I, D, C = GEN["I"], GEN["D"], GEN["C"]
    h3, _, h1 = _segment_ends(I, D, C)
    tp = trace_period(I, D, h3 + 0.61 * (h1 - h3), C)
    k = np.arange(9)
    r = integrate(
        "chaplygin_ball",
        tp.y0,
        float(k[-1] * tp.period),
        {"I": I, "D": D, "b": 1.0},
        effects=("contact_point",),
        rtol=1e-12,
        atol=1e-12,
        t_eval=k * tp.period,
    )
    z = r.y[r.state_names.index("x")] + 1j * r.y[r.state_names.index("y")]
    q = np.exp(1j * tp.turn)
    circle = z[0] + tp.displacement * (1 - q**k) / (1 - q)
    line = z[0] + tp.displacement * k
    scale = abs(tp.displacement) * k[-1]
    assert np.max(np.abs(z - circle)) / scale < 1e-8
    assert np.max(np.abs(z - line)) / scale > 1e-2  # the straight drift is refuted
    # every point is on the circle of radius R about the centre
    assert np.max(np.abs(np.abs(z - tp.centre) - tp.radius)) / tp.radius < 1e-8


def test_turning_is_continuous_along_the_family():
    I, D, C = GEN["I"], GEN["D"], GEN["C"]
    h3, h2, _ = _segment_ends(I, D, C)
    a = trace_period(I, D, h3 + 0.4 * (h2 - h3), C).turning
    b = trace_period(I, D, h3 + 0.4001 * (h2 - h3), C).turning
    assert abs(a - b) < 1e-2


def test_spiral_centres_are_delta_apart_near_h2():
    I, D = (1.0, 3.0, 5.0), 1.0
    Delta = float(delta_closed_form(mu_of(I, D), 1.0))
    for dh in (1e-6, -1e-6):
        sc = spiral_centres(I, D, 1 / 6 + dh)
        assert abs(sc["chord"] / Delta - 1) < 1e-6
        # the centres are on one circle about the chain's centre
        tp = sc["period"]
        assert abs(abs(sc["centres"][1] - tp.centre) - sc["radius"]) / sc["radius"] < 1e-6
        predicted = sc["chord"] / (2 * abs(math.sin(sc["half_turn"] / 2)))
        assert sc["radius"] == pytest.approx(predicted, rel=1e-6)
    # further from h2 the linearised passage is a worse model: the chord is off by more
    far = spiral_centres(I, D, 1 / 6 + 1e-3)
    assert abs(far["chord"] / Delta - 1) > 1e-5


def test_gyrostat_segment_equilibria():
    p = FIG7
    eq = segment_equilibria(p["I"], p["D"], p["K"], p["C"])
    kinds = [e["kind"] for e in eq]
    # Euler characteristic of the sphere: minima - saddles + maxima = 2
    assert kinds.count("min") - kinds.count("saddle") + kinds.count("max") == 2
    assert all(e["residual"] < 1e-12 for e in eq)
    # the least and largest energy on the sphere (a fine grid) are the extreme equilibria
    k = np.arange(200_000) + 0.5
    z = 1 - 2 * k / len(k)
    phi = np.pi * (1 + 5**0.5) * k
    g = np.vstack([np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z])
    h = segment_energy(p["I"], p["D"], g, p["C"], p["K"])
    assert eq[0]["kind"] == "min" and eq[-1]["kind"] == "max"
    # no grid point beyond them, and the grid comes within its spacing squared (the
    # energy's curvature is of order 1 here)
    spacing2 = 4 * np.pi / len(k)
    assert np.all(h >= eq[0]["h"] - 1e-14) and np.all(h <= eq[-1]["h"] + 1e-14)
    assert h.min() - eq[0]["h"] < spacing2 and eq[-1]["h"] - h.max() < spacing2


def test_saddle_rate_gives_the_logarithmic_growth_of_the_period():
    """Next to a saddle the period grows by k ln(10)/lam_s per decade of |h - h_s|."""
    p = FIG7
    eq = segment_equilibria(p["I"], p["D"], p["K"], p["C"])
    line = gradient_line(p["I"], p["D"], p["K"], p["C"], eq[0]["gamma"], ascending=True)
    saddle = next(e for e in eq if e["kind"] == "saddle")
    T = [
        trace_period(p["I"], p["D"], None, p["C"], p["K"], line["at"](saddle["h"] - d)).period
        for d in (1e-5, 1e-6)
    ]
    # below the lower saddle the orbits enclose one loop of its separatrix: one passage
    assert (T[1] - T[0]) == pytest.approx(math.log(10) / saddle["rate"], rel=2e-3)


def test_segment_gradient_is_the_generated_energys():
    """The closed-form tangential gradient ``(C + s) omega`` of the segment energy against
    complex steps of the generated energy (another route: the model's own formula,
    differentiated by the complex step), at generic points of the sphere."""
    from chaplygin.numerics.ball.gyrostat_segment import _sphere_gradient
    from chaplygin.numerics.ball.trace_geometry import _check_body

    I, D, K, C = _check_body(FIG7["I"], FIG7["D"], (0.13, -0.07, 0.21), 0.83)
    rng = np.random.default_rng(7)
    for _ in range(5):
        g = rng.normal(size=3)
        g /= math.sqrt(float(np.sum(g * g)))
        step = 1e-30
        grad = np.imag(segment_energy(I, D, g[:, None] + 1j * step * np.eye(3), C, K)) / step
        tangential = grad - g * float(np.sum(grad * g))
        closed = _sphere_gradient(I, D, K, C, g)
        assert float(np.max(np.abs(closed - tangential))) < 1e-14 * float(np.max(np.abs(grad)))
        assert abs(float(np.sum(closed * g))) < 1e-15  # tangent to the sphere


def test_gradient_line_is_monotone_and_finds_energies():
    p = FIG7
    eq = segment_equilibria(p["I"], p["D"], p["K"], p["C"])
    line = gradient_line(p["I"], p["D"], p["K"], p["C"], eq[-1]["gamma"], ascending=False)
    assert np.all(np.diff(line["h"]) < 0)
    # it ends at a minimum (LINE_FLAT = 1e-7 away in gamma: its energy to 1e-13), not short
    # of it nor circling it
    end = line["gamma"][:, -1]
    nearest = min(eq, key=lambda e: float(np.sum((e["gamma"] - end) ** 2)))
    assert nearest["kind"] == "min"
    assert float(np.sqrt(np.sum((nearest["gamma"] - end) ** 2))) < 1e-5
    assert 0 < line["h"][-1] - nearest["h"] < 1e-13
    assert line["s"][-1] < 4.0  # 2.87 here; a line circling the minimum runs to the cap 2 pi
    g = line["at"](0.3)
    assert float(segment_energy(p["I"], p["D"], g, p["C"], p["K"])) == pytest.approx(0.3, abs=1e-13)
    with pytest.raises(UserInputError, match="not on this line"):
        line["at"](10.0)


def test_bad_input_is_refused():
    with pytest.raises(UserInputError):
        trace_period((1, 3, 5), 1.0, None, 1.0)  # neither h nor gamma0
    with pytest.raises(UserInputError):
        trace_period((1, 3, 5), 1.0, 0.3, 1.0, K=(0.1, 0.1, 0.2))  # the gyrostat needs gamma0
    with pytest.raises(UserInputError):
        trace_period((1, 3, 5), -1.0, 0.3)
