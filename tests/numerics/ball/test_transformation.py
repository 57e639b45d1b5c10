"""Chaplygin's transformation: derivation, claims and the trajectory test (issue 4, item 3).

Acceptance: "the transformation test passes for random parameters and initial states
(seeded)": a trajectory of the ball with (M, gamma) != 0, mapped with the coefficients of
BKM12-22/23 (or K01-2.29 ... 2.33) and time-changed with ds = dt/mu (BKM12-19), agrees with
an independent integration of the transformed ball from the mapped initial state, where
(M~, gamma~) = 0.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.transformation import chaplygin_map, proposition2, theorem1
from chaplygin.numerics.ball.transformation import (
    chaplygin_coefficients,
    random_support_state,
    support_coefficients,
    transformation_test,
)

EPS = np.finfo(float).eps


def _random_ball(rng: np.random.Generator):
    """Random physical ball and state with (M, gamma) != 0 whose transformed ball is physical."""
    while True:
        I = rng.uniform(0.5, 3.0, 3)
        D = rng.uniform(0.3, 2.0)
        g = rng.normal(size=3)
        g /= np.linalg.norm(g)
        M = rng.normal(size=3)
        Mg = M @ g
        if abs(Mg) < 0.05:
            continue
        A = 1 / (I + D)
        X = 1 / D - g @ (A * g)
        E = M @ (A * (M + (A * M) @ g / X * g))
        k = chaplygin_coefficients(E, D, M @ M, Mg)
        if np.all(I + D - k.Dt > 0.05):
            return I, D, M, g


# ------------------------------------------------------------------ derivation
def test_theorem1_conditions_are_derived_and_equal_21():
    t = theorem1()
    s = t.symbols
    # two conditions (coefficients of X^2 and X Y), solved for m2 and D~ as in (21)
    assert len(t.conditions) == 2
    E, D = s["E"], s["D"]
    assert sp.simplify(t.solution[s["m2"]] + E * D * s["m1"] * s["c1"] / s["c2"]) == 0
    assert sp.simplify(1 / t.solution[s["Dt"]] - (E * s["c1"] ** 2 + s["c2"] ** 2 / D)) == 0


def test_chaplygin_roots_differ_by_quarter_turn():
    """The two roots f = k tan(phi) of BKM12-23: phi2 = phi1 + pi/2, i.e. f1 f2 = -k^2."""
    cm = chaplygin_map()
    s = cm.symbols
    vals = {
        s["E"]: sp.Rational(3, 2),
        s["D"]: sp.Rational(2, 3),
        s["C"]: 5,
        s["Mg"]: sp.Rational(-1, 3),
    }
    f1, f2 = (r.xreplace(vals) for r in cm.roots)
    assert sp.simplify(f1 * f2 + vals[s["E"]] * vals[s["D"]]) == 0


def test_cubic_55_derived():
    from chaplygin.verify.claims.support_transformation import printed_cubic_55

    p = proposition2()
    assert sp.expand(p.cubic - printed_cubic_55(p.symbols)) == 0


# ------------------------------------------------------------------ trajectory test
@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("form", ["chaplygin", "kilin"])
def test_transformation_trajectory(seed, form):
    rng = np.random.default_rng(4000 + seed)
    I, D, M, g = _random_ball(rng)
    rtol = 1e-13
    r = transformation_test(I, D, M, g, t_end=8.0, form=form, rtol=rtol)
    # mapped initial state: (M~, gamma~) = 0, |gamma~| = 1 to working precision
    scale = max(1.0, r.initial_products["(M~,M~)"])
    assert abs(r.initial_products["(M~,gamma~)"]) <= 64 * EPS * scale
    assert abs(r.initial_products["(gamma~,gamma~)-1"]) <= 64 * EPS
    if form == "chaplygin":  # (M~, M~) = C (BKM12-23)
        assert abs(r.initial_products["(M~,M~)"] - M @ M) <= 64 * EPS * (M @ M)
    # E~ from the state equals E m1^2 + m2^2/D (BKM12-20) / 2 h1 (K01-2.33)
    assert abs(r.initial_products["E~"] - r.coefficients.Et) <= 1e3 * EPS * abs(r.coefficients.Et)
    # the acceptance criterion: agreement 1e-10 or better, within the derived tolerance
    assert r.max_error <= r.tolerance
    assert r.max_error <= 1e-10
    assert r.s[-1] > 0 and np.all(np.diff(r.s) > 0)


def test_transformation_control_wrong_time_direction():
    """Negative control: using s = int mu dt instead of int dt/mu breaks the agreement."""
    rng = np.random.default_rng(4100)
    I, D, M, g = _random_ball(rng)
    r = transformation_test(I, D, M, g, t_end=4.0, rtol=1e-12)
    from chaplygin.numerics.ball.transformation import map_state, mu_of_mapped
    from chaplygin.numerics.integrate import integrate

    k = r.coefficients
    A = 1 / (np.asarray(I) + D)
    res = integrate(
        "chaplygin_ball",
        np.concatenate([M, g]),
        (0.0, 4.0),
        {"I": tuple(I), "D": D},
        rtol=1e-12,
        atol=1e-12,
        t_eval=r.t,
    )
    yt = map_state(res.y, k)
    mu = mu_of_mapped(yt, A, k)
    assert np.ptp(mu) > 1e-3  # mu is not constant: the direction matters
    # s with the wrong direction (trapezoid is enough to show a gross mismatch)
    s_wrong = np.concatenate([[0.0], np.cumsum(np.diff(r.t) * (mu[1:] + mu[:-1]) / 2)])
    r2 = integrate(
        "chaplygin_ball",
        yt[:, 0],
        (0.0, s_wrong[-1]),
        r.params_new,
        rtol=1e-12,
        atol=1e-12,
        t_eval=s_wrong,
    )
    assert np.max(np.abs(r2.y - yt)) > 1e3 * r.tolerance
    assert r.passed


def test_transformation_rejects_zero_constant_of_areas():
    g = np.array([0.0, 0.0, 1.0])
    with pytest.raises(UserInputError):
        transformation_test((1, 2, 3), 1.0, (1.0, 0.5, 0.0), g, 1.0)
    with pytest.raises(UserInputError):
        transformation_test((1, 2, 3), 1.0, (1.0, 0.5, 0.3), g, 1.0, form="nope")


# ------------------------------------------------------------------ support (Prop. 2)
@pytest.mark.parametrize("seed", range(5))
def test_proposition2_rows_numerically(seed):
    """BKM12-51..55 at random states: positive roots, Q Gamma Q^T and Q g Q^T diagonal."""
    # a random frame alpha, beta and momentum, and a positive energy value
    out = support_coefficients(*random_support_state(np.random.default_rng(5500 + seed)))
    roots, Q, Gam, g = out["roots"], out["Q"], out["Gamma"], out["g"]
    assert np.all(roots > 0)  # BKM12-55pos
    assert np.all(np.abs(np.polyval(out["cubic"], roots)) <= 1e-10 * np.max(np.abs(out["cubic"])))
    L = Q @ Gam @ Q.T
    G = Q @ g @ Q.T
    for Mx in (L, G):
        off = Mx - np.diag(np.diag(Mx))
        assert np.max(np.abs(off)) <= 1e-10 * np.max(np.abs(Mx))
    # BKM12-53: lam = Lambda_ii / g~_ii; (Q^T)^-1 = g~^-1 Q g
    assert np.allclose(np.diag(L) / np.diag(G), roots, rtol=1e-10)
    assert np.allclose(np.linalg.inv(Q.T), np.diag(1 / np.diag(G)) @ Q @ g, rtol=1e-9, atol=1e-12)
