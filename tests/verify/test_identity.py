"""The identity machinery itself: normal forms, radicals, exact sampling."""

from __future__ import annotations

import random

import sympy as sp
from chaplygin.derive import build_model
from chaplygin.derive.geometry import FRAME, UNIT_VECTOR, PoissonGroup
from chaplygin.derive.vectors import cross, dot, vector
from chaplygin.verify.identity import Domain, decide


def test_rational_samples_lie_exactly_on_the_variety():
    rng = random.Random(1)
    g = vector("gamma")
    a, b = vector("alpha"), vector("beta")
    sphere = PoissonGroup(UNIT_VECTOR, ("gamma",))
    frame = PoissonGroup(FRAME, ("alpha", "beta", "gamma"))
    for _ in range(20):
        (comps,) = sphere.sample_rational(rng).values()
        assert sum(c**2 for c in comps) == 1
        pts = frame.sample_rational(rng)
        vals = {n: sp.Matrix(v) for n, v in pts.items()}
        assert all(
            sp.simplify(
                c.xreplace(
                    dict(
                        zip(
                            list(a) + list(b) + list(g),
                            list(vals["alpha"]) + list(vals["beta"]) + list(vals["gamma"]),
                            strict=True,
                        )
                    )
                )
            )
            == 0
            for c in frame.constraints({"alpha": a, "beta": b, "gamma": g})
        )


def test_identity_that_needs_the_constraint_is_proved_and_fails_without_it():
    model = build_model("chaplygin_ball")
    g = model.group("gamma")
    expr = dot(g, g) ** 2 - 1  # zero on the sphere only
    assert decide([expr], Domain(model)).verdict == "proved"
    assert decide([dot(g, g) - 2], Domain(model)).verdict == "refuted"


def test_square_roots_are_split_exactly():
    model = build_model("chaplygin_ball")
    M, g = model.group("M"), model.group("gamma")
    s = sp.sqrt(dot(M, M) - dot(M, g) ** 2)
    a = cross(M, g) / s
    assert decide([dot(a, a) - 1], Domain(model)).verdict == "proved"
    out = decide([dot(a, a) - 1 + s / 1000], Domain(model))
    assert out.verdict == "refuted" and out.witness


def test_verdicts_are_reproducible():
    model = build_model("chaplygin_ball")
    M = model.group("M")
    a = decide([M[0] ** 2 - 1], Domain(model))
    b = decide([M[0] ** 2 - 1], Domain(model))
    assert a.verdict == b.verdict == "refuted" and a.witness == b.witness


def test_trigonometric_and_function_atoms_are_generators():
    """sin/cos pairs live on the circle; a function and its derivative are independent."""
    model = build_model("chaplygin_ball")
    t, w = model.time, sp.Symbol("Omega", positive=True)
    f = sp.Function("I1", positive=True)(t)
    assert decide([sp.sin(w * t) ** 2 + sp.cos(w * t) ** 2 - 1], Domain(model)).verdict == "proved"
    assert decide([sp.sin(w * t) ** 2 - 1], Domain(model)).verdict == "refuted"
    assert decide([sp.diff(f**2, t) - 2 * f * sp.diff(f, t)], Domain(model)).verdict == "proved"
    wrong = decide([sp.diff(f**2, t) - f * sp.diff(f, t)], Domain(model))
    assert wrong.verdict == "refuted" and "Derivative(I1(t), t)" in wrong.witness
    sampled = decide([sp.sin(w * t) ** 2 + sp.cos(w * t) ** 2 - 1], Domain(model), "exact-sampled")
    assert sampled.verdict == "exact-sampled"


def test_exact_values_are_sympys_evaluation():
    """The term-by-term evaluation of the sampling (exact_value) against sympy's own
    evaluation one variable at a time: the same rational for random sparse polynomials over
    QQ at random rational points (powers shared between polynomials at one point), for the
    zero polynomial and a constant; a point one coordinate off gives another value."""
    from chaplygin.verify.identity import exact_value
    from sympy.polys.domains import QQ
    from sympy.polys.rings import ring

    rng = random.Random(7)
    R, *x = ring(",".join(f"x{i}" for i in range(9)), QQ, order="grevlex")
    for _ in range(5):
        polys = [R.zero, R(QQ(-7, 3))]
        for _ in range(3):
            f = R.zero
            for _ in range(200):
                term = R(QQ(rng.randint(-50, 50), rng.randint(1, 30)))
                for v in x:
                    term *= v ** rng.choice([0, 0, 0, 1, 2, 5])
                f += term
            polys.append(f)
        args = [QQ(rng.randint(-9, 9), rng.randint(1, 9)) for _ in x]
        powers: list[dict] = [{} for _ in x]
        for f in polys:
            assert exact_value(f, args, powers) == f(*args)
        moved = [args[0] + QQ(1, 11), *args[1:]]
        assert exact_value(polys[-1], moved) != polys[-1](*args)
