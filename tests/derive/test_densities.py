"""Invariant densities found by ``derive/densities.py``, compared with the models' own.

The reference exponents come from the density each model declares (BKM12-4 for the ball,
the rubber ball's and the line's densities derived in ``derive/chaplygin_ball.py`` and
proved by the verifier): that expression is split into irreducible factors by
``sympy.factor_list`` (not the search's ring factorisation), each factor is matched with a
factor of the search's family by proportional normal forms modulo the model's constraint
ideal, and the exponents are compared as rational numbers.
"""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp
from chaplygin.derive import DerivationError, build_model
from chaplygin.derive.densities import find_invariant_densities
from chaplygin.derive.vectors import dot

BALL = "chaplygin_ball"


def _declared_exponents(model, factors) -> list[sp.Rational]:
    """Exponents of ``model.density`` on ``factors`` (matched modulo the constraints)."""
    squared = sp.cancel(sp.together(model.expand_aux(model.density) ** 2))
    state = set(model.state)
    exponents = [sp.S.Zero] * len(factors)
    normal = [model.ideal.reduce(sp.expand(g)) for g in factors]
    for part, sign in zip(sp.fraction(squared), (1, -1), strict=True):
        _, irreducible = sp.factor_list(part)
        for h, k in irreducible:
            if not h.free_symbols & state:
                continue  # a constant
            h_normal = model.ideal.reduce(sp.expand(h))
            ratios = [sp.cancel(h_normal / g) for g in normal]
            hits = [j for j, r in enumerate(ratios) if not r.free_symbols & state]
            assert len(hits) == 1, f"declared factor {h} is not one of the family's factors"
            exponents[hits[0]] += sign * sp.Rational(k, 2)
    return exponents


@pytest.mark.parametrize(
    "effects",
    [
        pytest.param((), id="ball-BKM12-4"),
        ("rubber",),
        pytest.param(("straight_line",), marks=pytest.mark.slow),
    ],
)
def test_finds_the_declared_density(effects):
    model = build_model(BALL, effects)
    found = find_invariant_densities(model)
    assert found.found
    assert found.directions == ()  # unique in the family: no product of factors is an integral
    assert found.rank == found.augmented_rank == len(found.factors)
    assert list(found.exponents) == _declared_exponents(model, found.factors)
    assert all(e.is_Rational for e in found.exponents)


def test_ball_family_exponents():
    """BKM12-4: rho = (1/D - (gamma, A gamma))^(-1/2), the one factor of the denominator."""
    found = find_invariant_densities(build_model(BALL, ()))
    assert len(found.factors) == 1 and found.denominator_powers == (1,)
    assert found.exponents == (sp.Rational(-1, 2),)


def test_integrals_in_the_family_are_free_directions():
    """(M, M) and (M, gamma) are integrals of the ball: their exponents are free, the
    denominator's stays -1/2, and (gamma, gamma A gamma) added as a quadratic form gets 0."""
    model = build_model(BALL, ())
    M, gamma = model.group("M"), model.group("gamma")
    A = sp.diag(*[1 / (I + model.param_group("D")[0]) for I in model.param_group("I")])
    extra = [dot(M, M), dot(M, gamma), dot(gamma, A * gamma)]
    found = find_invariant_densities(model, extra_factors=extra)
    assert found.found and len(found.factors) == 4
    index = {}
    for j, g in enumerate(found.factors):
        for name, e in zip(("MM", "Mgamma", "gAg"), extra, strict=True):
            if not sp.cancel(g / e).free_symbols & set(model.state):
                index[name] = j
        if found.denominator_powers[j]:
            index["W"] = j
    assert sorted(index) == ["MM", "Mgamma", "W", "gAg"]
    assert found.rank == 2 and len(found.directions) == 2
    free = {index["MM"], index["Mgamma"]}
    for v in found.directions:  # the homogeneous solutions move only the integrals' exponents
        assert all(v[j] == 0 for j in range(4) if j not in free)
    span = sp.Matrix([[v[j] for j in sorted(free)] for v in found.directions])
    assert span.rank() == 2
    assert found.exponents[index["W"]] == sp.Rational(-1, 2)
    assert found.exponents[index["gAg"]] == 0


def test_negative_control_perturbed_ball_has_none():
    """M' = M x omega + Z M: the same factors, no density; refuted by the same solve."""
    model = build_model(BALL, ())
    Z = next(s for s in model.aux_symbols if s.name == "Z")
    rhs = list(model.rhs)
    for i, m in enumerate(model.group("M")):
        rhs[i] = rhs[i] + Z * m
    perturbed = dataclasses.replace(model, rhs=tuple(rhs))
    found = find_invariant_densities(perturbed)
    assert not found.found and found.exponents is None
    assert found.augmented_rank == found.rank + 1
    assert len(found.factors) == 1  # the family is the ball's own
    with pytest.raises(ValueError):
        found.density()


def test_caller_family_without_the_density_has_none():
    """Searching the ball in the family of (gamma, A gamma) alone: none (the denominator's
    factor is not in it), with the certificate."""
    model = build_model(BALL, ())
    gamma = model.group("gamma")
    A = sp.diag(*[1 / (I + model.param_group("D")[0]) for I in model.param_group("I")])
    found = find_invariant_densities(model, factors=[dot(gamma, A * gamma)])
    assert not found.found and found.augmented_rank == found.rank + 1 == 2


def test_refuses_what_it_cannot_do():
    model = build_model(BALL, ())
    with pytest.raises(DerivationError, match="no factor in the state"):
        find_invariant_densities(model, factors=[sp.Integer(3)])
    with pytest.raises(DerivationError, match="not a rational function"):
        find_invariant_densities(
            dataclasses.replace(model, rhs=(sp.sqrt(model.state[0]),) + model.rhs[1:])
        )


@pytest.mark.slow
@pytest.mark.parametrize(
    ("which", "integral"),
    [pytest.param("KK", True, marks=pytest.mark.expensive), ("MM", False)],
)
def test_rubber_integral_factor_on_the_relation(which, integral):
    """On the rubber ball's phase space ((omega, gamma) = 0), (K, K) = (M, M) - (M, gamma)^2
    is an integral (BKM12 §3) and (M, M) is not (the README's control): as a factor of the
    family the first gets a free exponent, the second none. This holds only on the invariant
    relation, so it checks the restriction to it."""
    model = build_model(BALL, ("rubber",))
    M, gamma = model.group("M"), model.group("gamma")
    factor = {"KK": dot(M, M) - dot(M, gamma) ** 2, "MM": dot(M, M)}[which]
    found = find_invariant_densities(model, extra_factors=[factor])
    assert found.found and len(found.factors) == 3
    (j,) = [i for i, g in enumerate(found.factors) if sp.cancel(g / factor).is_constant()]
    if integral:
        assert len(found.directions) == 1
        assert [x != 0 for x in found.directions[0]] == [i == j for i in range(3)]
    else:
        assert found.directions == ()
        assert found.exponents[j] == 0
    others = [e for i, e in enumerate(found.exponents) if i != j]
    assert sorted(others) == [-1, sp.Rational(1, 2)]  # the rubber ball's density
