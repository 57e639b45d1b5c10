"""Discovery of polynomial first integrals (derive/discovery.py), exact, with "no other" by rank.

Span membership is decided here by an independent route: sympy's ``reduced`` modulo
``(gamma, gamma) - 1`` and ``sympy.linsolve`` over the unknown combination coefficients,
never by comparing strings. The known integrals come from the model's declared integrals
(BKM12-5: ``H``, ``(M, M)``, ``(M, gamma)``; K01-4.1 for the gyrostat).
"""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp
from chaplygin.derive import UserInputError, build_model
from chaplygin.derive.discovery import find_polynomial_integrals


@pytest.fixture(scope="module")
def ball():
    return build_model("chaplygin_ball")


def _in_span(target, basis, gens, sphere):
    """True when ``target = const + sum a_i basis_i`` on ``(gamma, gamma) = 1``.

    The ``a_i`` may be rational functions of the parameters: they are the unknowns of a
    linear system made of the coefficients (in ``gens``) of the normal form.
    """
    a = sp.symbols(f"a0:{len(basis) + 1}")
    combo = target - a[0] - sum((ai * b for ai, b in zip(a[1:], basis, strict=True)), sp.S.Zero)
    _, nf = sp.reduced(sp.expand(combo), [sphere], *gens, order="grevlex")
    equations = sp.Poly(sp.expand(nf), *gens).coeffs() if nf != 0 else []
    return bool(equations == [] or sp.linsolve(equations, *a) != sp.EmptySet)


def _sphere(model):
    g = model.group("gamma")
    return sum(s**2 for s in g) - 1, tuple(g)


def test_ball_in_M_finds_exactly_the_casimirs_and_their_square(ball):
    """Degree <= 2 in M, coefficients of degree <= 2 in gamma, rational numbers.

    Expected dimension 3 (modulo constants and (gamma, gamma) = 1): the integrals of the
    class are polynomials in the ball's integrals H, F1 = (M, M), F2 = (M, gamma) that lie
    in it. H is not (it carries the denominator D^-1 - (gamma, A gamma) in M, BKM12-3),
    nor is any polynomial in H; what remains is F1, F2, F2^2. A further one would be a
    fourth integral independent of H, F1, F2 (or an algebraic relation the generic
    flow does not have); the rank 86 of 89 unknowns is the proof that there is none.
    """
    found = find_polynomial_integrals(ball, 2, coefficient_degree=2)
    assert (found.unknowns, found.dimension) == (89, 3)
    assert found.rank == found.unknowns - len(found.integrals)
    sphere, g = _sphere(ball)
    gens = (*ball.group("M"), *g)
    for name in ("(M,M)", "(M,gamma)"):
        assert _in_span(ball.integral(name), found.integrals, gens, sphere), name
    assert _in_span(ball.integral("(M,gamma)") ** 2, found.integrals, gens, sphere)
    # not everything is in the span: M1 gamma1 alone is no integral
    assert not _in_span(gens[0] * g[0], found.integrals, gens, sphere)
    # each found integral's Lie derivative vanishes on the phase space (sympy, independently)
    f = dict(zip(ball.state, ball.rhs_expanded, strict=True))
    for F in found.integrals:
        lie = sum(sp.diff(F, s) * f[s] for s in ball.state)
        assert ball.ideal.is_zero(lie)


def test_classes_too_small_find_only_what_they_hold(ball):
    """Degree 1 in M, constant coefficients: M' = M x omega, no linear integral. With
    coefficients of degree 1 in gamma: exactly (M, gamma)."""
    none = find_polynomial_integrals(ball, 1)
    assert (none.unknowns, none.rank, none.integrals) == (3, 3, ())
    one = find_polynomial_integrals(ball, 1, coefficient_degree=1)
    assert one.dimension == 1
    sphere, g = _sphere(ball)
    gens = (*ball.group("M"), *g)
    assert _in_span(ball.integral("(M,gamma)"), one.integrals, gens, sphere)
    assert _in_span(one.integrals[0], [ball.integral("(M,gamma)")], gens, sphere)


def test_perturbed_vector_field_loses_its_integrals(ball):
    """Negative control by the same machinery: M1' = (8/7) (M2 omega3 - M3 omega2) loses
    (M, M) and (M, gamma)."""
    rhs = list(ball.rhs)
    rhs[0] = sp.Rational(8, 7) * rhs[0]
    bent = dataclasses.replace(ball, rhs=tuple(rhs))
    found = find_polynomial_integrals(bent, 2, coefficient_degree=2)
    sphere, g = _sphere(ball)
    gens = (*ball.group("M"), *g)
    assert found.dimension < 3
    for name in ("(M,M)", "(M,gamma)"):
        assert not _in_span(ball.integral(name), found.integrals, gens, sphere), name
    # ... and finds the bent field's own quadratic integral (by hand: its Lie derivative is
    # 16 (M, M x omega) = 0)
    M1, M2, M3 = ball.group("M")
    assert _in_span(7 * M1**2 + 8 * M2**2 + 8 * M3**2, found.integrals, gens, sphere)


@pytest.mark.slow
def test_ball_in_omega_over_the_parameters_finds_the_energy(ball):
    """Degree <= 2 in omega, coefficients of degree <= 2 in gamma, in QQ(I, D).

    In omega the energy H = (omega, I omega)/2 + D (|omega|^2 - (omega, gamma)^2)/2 is
    polynomial, and M = I omega + D gamma x (omega x gamma) too, so the class holds H,
    (M, M), (M, gamma) = (I omega, gamma) and (M, gamma)^2: dimension 4 modulo constants
    (same argument as in M, now with H in the class); the rank (85 of 89) proves there is
    no fifth.
    """
    found = find_polynomial_integrals(
        ball, 2, coefficient_degree=2, momentum="omega", in_parameters=True
    )
    assert (found.unknowns, found.dimension, found.rank) == (89, 4, 85)
    sphere, g = _sphere(ball)
    omega = tuple(ball.omega)
    gens = (*omega, *g)
    in_omega = dict(zip(ball.group("M"), ball.momentum_of_omega, strict=True))
    for name in ("H", "(M,M)", "(M,gamma)"):
        target = sp.expand(ball.integral(name).xreplace(in_omega))
        assert _in_span(target, found.integrals, gens, sphere), name
    # negative control, same search: with M1' = (8/7) (M2 omega3 - M3 omega2) H is lost
    rhs = list(ball.rhs)
    rhs[0] = sp.Rational(8, 7) * rhs[0]
    bent = find_polynomial_integrals(
        dataclasses.replace(ball, rhs=tuple(rhs)),
        2,
        coefficient_degree=2,
        momentum="omega",
        in_parameters=True,
    )
    assert bent.dimension < found.dimension
    H = sp.expand(ball.integral("H"))
    assert not _in_span(H, bent.integrals, gens, sphere)
    # with rational coefficients only, H and (M, gamma) = (I omega, gamma) leave the class
    rational = find_polynomial_integrals(ball, 1, coefficient_degree=1, momentum="omega")
    assert rational.dimension == 0


def test_too_large_a_class_is_refused_with_its_size_before_any_work(ball):
    # 165 monomials of degree <= 8 in M times 165 of degree <= 8 in gamma
    with pytest.raises(UserInputError, match=r"has 27225 unknowns, more than"):
        find_polynomial_integrals(ball, 8, coefficient_degree=8)
    with pytest.raises(UserInputError, match="degree"):
        find_polynomial_integrals(ball, 0)
    with pytest.raises(UserInputError, match="no group"):
        find_polynomial_integrals(ball, 1, momentum="L")


def test_time_dependent_models_are_refused():
    model = build_model("chaplygin_ball", ["variable_inertia"])
    with pytest.raises(UserInputError, match="autonomous"):
        find_polynomial_integrals(model, 1)


def _in_span_modulo(target, basis, gens, ideal):
    """``_in_span`` modulo several generators (a Groebner basis computed here by sympy)."""
    a = sp.symbols(f"a0:{len(basis) + 1}")
    combo = target - a[0] - sum((ai * b for ai, b in zip(a[1:], basis, strict=True)), sp.S.Zero)
    groebner = sp.groebner(ideal, *gens, order="grevlex")
    _, nf = sp.reduced(sp.expand(combo), list(groebner.exprs), *gens, order="grevlex")
    equations = sp.Poly(sp.expand(nf), *gens).coeffs() if nf != 0 else []
    return bool(equations == [] or sp.linsolve(equations, *a) != sp.EmptySet)


def _same_span(found, references, gens, ideal):
    """Span equality modulo constants and the ideal, both ways."""
    return all(_in_span_modulo(r, found, gens, ideal) for r in references) and all(
        _in_span_modulo(f, references, gens, ideal) for f in found
    )


def _ball_momentum(omega, gamma, inertia, D):
    """M = I omega + D gamma x (omega x gamma) (BKM12-1, K01-2.1), written here."""
    w, g = sp.Matrix(omega), sp.Matrix(gamma)
    return sp.diag(*inertia) * w + D * g.cross(w.cross(g))


@pytest.mark.expensive
def test_rubber_ball_in_omega_finds_its_energy_and_quadratic_integral():
    """Degree <= 2 in omega, coefficients of degree <= 2 in gamma, in QQ(I, D), modulo
    (gamma, gamma) = 1 and (omega, gamma) = 0: exactly H = (M, omega)/2 and (K, K) with
    K = (J - gamma ⊗ J gamma) omega, J = I + D Id (BKM12 §3, the rubber ball; the claims
    BKM12-3rub.H, BKM12-3rub.K, BKM12-3rub.KK), dimension 2 (about 20 s)."""
    model = build_model("chaplygin_ball", ["rubber"])
    found = find_polynomial_integrals(
        model, 2, coefficient_degree=2, momentum="omega", in_parameters=True
    )
    assert found.dimension == 2 and found.rank == found.unknowns - 2
    w, g = tuple(model.omega), tuple(model.group("gamma"))
    p = {s.name: s for s in model.params}
    inertia, D = (p["I1"], p["I2"], p["I3"]), p["D"]
    M = _ball_momentum(w, g, inertia, D)
    J = sp.diag(*(i + D for i in inertia))
    wv, gv = sp.Matrix(w), sp.Matrix(g)
    K = J * wv - gv * (J * gv).dot(wv)
    references = [sp.expand(M.dot(wv) / 2), sp.expand(K.dot(K))]
    ideal = [gv.dot(gv) - 1, gv.dot(wv)]
    assert _same_span(list(found.integrals), references, (*w, *g), ideal)
    # (M, M), an integral of the ball without the no-twist constraint, is not in the span
    assert not _in_span_modulo(sp.expand(M.dot(M)), list(found.integrals), (*w, *g), ideal)


@pytest.mark.expensive
def test_gyrostat_in_omega_finds_markeevs_integrals():
    """Degree <= 2 in omega, coefficients of degree <= 2 in gamma, in QQ(I, D, K): the span
    of K01-4.2's h = (M, omega)/2, n = (M + K, M + K), C = (M + K, gamma) and C^2,
    dimension 4; the rank (85 of 89) proves there is no other (about a minute)."""
    model = build_model("chaplygin_ball", ["gyrostat"])
    found = find_polynomial_integrals(
        model, 2, coefficient_degree=2, momentum="omega", in_parameters=True
    )
    assert (found.unknowns, found.dimension, found.rank) == (89, 4, 85)
    w, g = tuple(model.omega), tuple(model.group("gamma"))
    p = {s.name: s for s in model.params}
    inertia, D = (p["I1"], p["I2"], p["I3"]), p["D"]
    Kv = sp.Matrix([p["K1"], p["K2"], p["K3"]])
    M = _ball_momentum(w, g, inertia, D)
    gv = sp.Matrix(g)
    C = (M + Kv).dot(gv)
    references = [sp.expand(e) for e in (M.dot(sp.Matrix(w)) / 2, (M + Kv).dot(M + Kv), C, C**2)]
    assert _same_span(list(found.integrals), references, (*w, *g), [gv.dot(gv) - 1])
    # (M, M) (the integral without the rotor) is not in the span
    assert not _in_span_modulo(sp.expand(M.dot(M)), list(found.integrals), (*w, *g),
                               [gv.dot(gv) - 1])  # fmt: skip


def test_parametric_null_space_matches_sympys_on_a_small_block():
    """The Markowitz elimination over QQ(parameters), checked against sympy's own
    ``Matrix.nullspace`` (an independent route) on a 3 x 5 block of rank 3 with entries
    polynomial in two parameters; and a block whose rows are dependent is refused (None)."""
    from chaplygin.derive.sparse_nullspace import markowitz_null_vectors
    from sympy.polys.domains import QQ

    p, q = sp.symbols("p q")
    rows = sp.Matrix(
        [
            [p, 1, 0, q + 2, 0],
            [0, q, p**2 - 3, 0, 1],
            [1, 0, p * q, 5, sp.Rational(2, 7)],
        ]
    )
    field_ = QQ.frac_field(p, q)
    sdm = {
        i: {j: field_.from_sympy(rows[i, j]) for j in range(5) if rows[i, j] != 0}
        for i in range(3)
    }
    vectors = markowitz_null_vectors(sdm, 5, field_)
    assert vectors is not None and len(vectors) == 2
    mine = sp.Matrix([[field_.to_sympy(c) for c in v] for v in vectors])
    reference = sp.Matrix.hstack(*rows.nullspace()).T
    assert (rows * mine.T).applyfunc(sp.cancel).is_zero_matrix
    assert mine.rank() == 2 and sp.Matrix.vstack(mine, reference).rank(simplify=True) == 2
    dependent = {0: dict(sdm[0]), 1: {j: 2 * c for j, c in sdm[0].items()}}
    assert markowitz_null_vectors(dependent, 5, field_) is None


def test_a_convex_body_s_omega_is_searched_as_its_state_group():
    """A convex body's state group is omega itself (no momentum): the default search and
    momentum="omega" search in that group, and the field, which carries the normal's square
    root, is refused for that reason (before: "no angular velocity expressed through its
    momentum", which is not why)."""
    from chaplygin.derive.rolling_system import RollingSystem

    egg = RollingSystem("egg_discovered", inertia=("A", "B", "C"),
                        surface="x1**2 + x2**2/2 + x3**2/3 - 1").model()  # fmt: skip
    for momentum in (None, "omega"):
        with pytest.raises(UserInputError, match="not a rational function") as info:
            find_polynomial_integrals(egg, 1, coefficient_degree=1, momentum=momentum)
        assert "r1" in str(info.value) and "\n" not in str(info.value)  # |grad f(r)|
