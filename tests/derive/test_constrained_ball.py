"""The rubber ball and the ball along a straight line (constraints on omega alone).

The models are the Chaplygin ball with one more constraint, ``(omega, gamma) = 0`` or
``(omega, alpha) = 0``; their phase space is the zero level of that constraint (an invariant
relation). The claims (``verify/claims/rubber.py``, run by ``test_claims``) prove the
equations, integrals and measure; here: exact sampling on the relation, the numerics'
refusal of a state off it, and integration that stays on it.
"""

from __future__ import annotations

import random
import re

import numpy as np
import pytest
import sympy as sp
from chaplygin.derive import UserInputError, build_model
from chaplygin.derive.vectors import cross, dot
from chaplygin.numerics import integrate
from chaplygin.verify.identity import Domain, decide

BALL = "chaplygin_ball"
PARAMS = {"I": (1, 2, 3), "D": 1}
RTOL = 1e-10
ATOL = 1e-12


def _admissible_state(constraint: str, seed: int = 7) -> dict[str, np.ndarray]:
    """A random frame; omega orthogonal to the constraint vector; M = II omega."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    if np.linalg.det(q) < 0:
        q[:, 2] *= -1
    alpha, beta, gamma = q[:, 0], q[:, 1], q[:, 2]
    c = gamma if constraint == "rubber" else alpha
    w = rng.normal(size=3)
    w -= np.dot(w, c) * c
    II = np.diag([1.0, 2.0, 3.0]) + 1.0 * (np.eye(3) - np.outer(gamma, gamma))
    state = {"M": II @ w, "gamma": gamma}
    if constraint == "straight_line":
        state.update(alpha=alpha, beta=beta)
    return state


@pytest.mark.parametrize("effect", ["rubber", "straight_line"])
def test_sampled_points_lie_exactly_on_the_invariant_relation(effect):
    model = build_model(BALL, [effect])
    domain = Domain(model)
    (_, relation), *_ = model.invariant_relations
    rel = model.expand_aux(relation)
    rng = random.Random(3)
    for _ in range(5):
        point = domain.sample(rng, set(model.state) | set(model.params))
        assert rel.xreplace(point) == 0
    # and the flow does leave the relation's level sets alone: (M, M) is no integral
    M = model.group("M")
    from chaplygin.verify.identity import lie_derivative

    assert decide([lie_derivative(dot(M, M), model)], domain).verdict == "refuted"


def test_a_level_set_of_rank_two_is_sampled_exactly():
    """(M + K) x gamma = 0 has three rows of rank two (K01-4.3's invariant set)."""
    model = build_model(BALL, ["gyrostat"])
    M, gamma, K = model.group("M"), model.group("gamma"), model.param_group("K")
    domain = Domain(model, relations=list(cross(M + K, gamma)))
    point = domain.sample(random.Random(5), set(model.state) | set(model.params))
    assert cross(M + K, gamma).xreplace(point) == sp.zeros(3, 1)


@pytest.mark.parametrize(
    ("effect", "relation"), [("rubber", "(omega,gamma)"), ("straight_line", "(omega,alpha)")]
)
def test_integration_stays_on_the_relation_and_conserves_the_energy(effect, relation):
    y0 = _admissible_state(effect)
    r = integrate(BALL, y0, 50, PARAMS, effects=[effect], rtol=RTOL, atol=ATOL)
    assert r.success, r.message
    # the relation starts at zero: its drift is absolute, bounded like the state's error
    assert r.drift[relation] <= 1e3 * (RTOL + ATOL)
    assert r.drift["H"] <= 1e3 * RTOL
    assert "(M,M)" not in r.drift  # not an integral of these systems


@pytest.mark.parametrize("effect", ["rubber", "straight_line"])
def test_a_state_off_the_relation_is_refused_with_the_nearest_admissible_momentum(effect):
    y0 = _admissible_state(effect)
    bad = dict(y0, M=y0["M"] + 0.3 * (y0["gamma"] if effect == "rubber" else y0["alpha"]))
    with pytest.raises(UserInputError, match=r"off the phase space.*nearest admissible") as err:
        integrate(BALL, bad, 1, PARAMS, effects=[effect])
    suggested = re.search(r"M=([-0-9.e,]+)", str(err.value)).group(1)
    fixed = dict(bad, M=tuple(float(v) for v in suggested.split(",")))
    r = integrate(BALL, fixed, 1, PARAMS, effects=[effect], rtol=RTOL, atol=ATOL)
    assert r.success


def test_the_rubber_ball_on_a_line_has_two_multipliers_and_the_density_found():
    """The shipped density is (D^-1 - (gamma, A gamma))^-1 (the find, claim
    BKM12-3rub57.measure) times the root of (gamma x alpha, J gamma x alpha): the ratio
    rho^2 (D^-1 - (gamma, A gamma))^2 / (gamma x alpha, J gamma x alpha) takes the same value
    at two orthonormal pairs (gamma, alpha), exact rationals (the symbolic identity is the
    claim BKM12-3rub57.shipped-density)."""
    model = build_model(BALL, ["rubber", "straight_line"])
    assert [s.name for s in model.aux_symbols if s.name.startswith("mu")] == ["mu1", "mu2"]
    rho = model.expand_aux(model.density)
    p = {s.name: s for s in model.params}
    values = {p["I1"]: sp.Rational(3, 2), p["I2"]: sp.Rational(5, 3), p["I3"]: sp.Rational(7, 4)}
    values[p["D"]] = sp.Rational(2, 5)
    J = sp.diag(*(values[p[f"I{i}"]] + values[p["D"]] for i in (1, 2, 3)))
    ratios = []
    for g, a in (((2, 1, 2), (1, 2, -2)), ((2, 3, 6), (3, -6, 2))):
        n = 3 if g[0] == 2 and g[1] == 1 else 7
        gv, av = sp.Matrix(g) / n, sp.Matrix(a) / n
        at = dict(zip((*model.group("gamma"), *model.group("alpha")), (*gv, *av), strict=True))
        found = 1 / (1 / values[p["D"]] - (gv.T * J.inv() * gv)[0, 0])
        g_x_a = gv.cross(av)
        value = sp.simplify(rho.xreplace({**values, **at}) ** 2)
        ratios.append(sp.simplify(value / (found**2 * (g_x_a.T * J * g_x_a)[0, 0])))
    assert ratios[0] == ratios[1] and ratios[0] > 0
    names = [n for n, _ in model.integrals]
    assert {"(omega,gamma)", "(omega,alpha)", "(M,beta)"} <= set(names)
    assert "(M,gamma)" not in names and "(M,alpha)" not in names
