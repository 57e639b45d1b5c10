"""Integrals decided through the model's auxiliaries (verify/chained.py): the rate along the
flow by the chain rule at exact points, for models whose expanded right-hand side is too large
to expand (the general ball on a support surface)."""

from __future__ import annotations

import random

import pytest
import sympy as sp
from chaplygin.derive.phase_space import sample_point
from chaplygin.derive.systems import build_model
from chaplygin.verify.chained import applies, rate_at
from chaplygin.verify.identity import lie_derivative
from chaplygin.verify.user_claims import claims_of_file
from chaplygin.verify.verdict import check_claim

EGG_FILE = """
[system]
name = "heavy_ball_on_ellipsoid_chained"
inertia = [["A", "D", 0], ["D", "B", 0], [0, 0, "C"]]
centre_of_mass = [0, 0, "a"]
gyrostat = [0, 0, "k"]
gravity = "g"
support = "surface"
support_surface = "p1**2/c1 + p2**2/c2 + p3**2/c3 - 1"

[[claims]]
id = "egg.speed-control"
kind = "integral"
expression = "omega1**2 + omega2**2 + omega3**2"
expected = "fails"
"""


def test_the_chain_rule_gives_the_expanded_rate_at_exact_points():
    """On the gyrostat ball (auxiliaries omega, small enough to expand) the rate through
    the auxiliaries equals the expanded Lie derivative evaluated at the same exact points,
    for quantities that are not conserved (non-zero values, so the agreement is not 0 = 0)
    and for the energy (zero on both routes)."""
    model = build_model("chaplygin_ball", ["gyrostat"])
    assert model.aux
    M, gamma = model.vectors["M"], model.vectors["gamma"]
    exprs = [M[0] * gamma[1] + M[2] ** 2, M[0] * M[1] * gamma[2]]
    rng = random.Random(7)
    nonzero = 0
    for _ in range(3):
        point = sample_point(model, rng, model.state)
        for e in exprs:
            expanded = sp.nsimplify(lie_derivative(e, model).xreplace(point))
            chained = rate_at(model, e, point)
            assert sp.simplify(chained - expanded) == 0
            nonzero += chained != 0
        assert rate_at(model, model.integral("H"), point) == 0
    assert nonzero >= 5


def test_the_auxiliaries_at_a_point_are_evaluated_once_for_every_expression():
    """Two expressions at one point of the gyrostat ball: the auxiliaries' values and rates
    are evaluated once (counted), the second rate still equals the expanded Lie derivative
    at the point (an independent route), and a new point evaluates them anew."""
    from chaplygin.verify import chained

    model = build_model("chaplygin_ball", ["gyrostat"])
    M, gamma = model.vectors["M"], model.vectors["gamma"]
    rng = random.Random(31)
    point = sample_point(model, rng, model.state)
    chained._flow_at.cache_clear()
    first = rate_at(model, M[1] * gamma[0], point)
    e = M[2] * gamma[1] - M[0] ** 2
    second = rate_at(model, e, dict(point))  # an equal point, another dict
    info = chained._flow_at.cache_info()
    assert (info.misses, info.hits) == (1, 1) and first != 0 and second != 0
    assert sp.simplify(second - sp.nsimplify(lie_derivative(e, model).xreplace(point))) == 0
    rate_at(model, e, sample_point(model, rng, model.state))
    assert chained._flow_at.cache_info().misses == 2


def test_only_large_rates_go_through_the_auxiliaries():
    """The gyrostat ball's rates expand (the Groebner route); the general ball's omega
    rates do not, while its F (the contact on the surface, rates of p only) does."""
    small = build_model("chaplygin_ball", ["gyrostat"])
    assert not applies(small, small.integral("H"))


@pytest.mark.slow
def test_the_general_balls_energy_is_exact_sampled_and_a_control_refuted(tmp_path):
    """A heavy ball with a product of inertia, an offset and a rotor on an ellipsoid with
    symbolic axes (expanded right-hand side about 10^6 operations): H is exactly
    conserved at the sampled points, F is proved by the Groebner route, and the file's
    control (|omega|^2, not conserved) is refuted by the same chained computation, with a
    witness."""
    path = tmp_path / "egg.toml"
    path.write_text(EGG_FILE)
    claims = {c.id.split(":")[-1]: c for c in claims_of_file(path)}
    model = claims["H"].model()
    assert applies(model, model.integral("H")) and not applies(model, model.integral("F"))
    h = check_claim(claims["H"])
    assert (h.verdict, h.ok) == ("exact-sampled", True) and "auxiliaries" in h.method
    f = check_claim(claims["F"])
    assert (f.verdict, f.ok) == ("proved", True)
    control = check_claim(claims["egg.speed-control"])
    assert (control.verdict, control.ok) == ("refuted", True)
    assert "auxiliaries" in control.method and control.witness
