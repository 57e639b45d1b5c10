"""Linear invariant relations and symmetries of a stated form (derive/invariants.py).

References by independent routes: Hess's invariant relation of the heavy top (Hess 1890;
the condition ``(a1 - a2) r3^2 = (a2 - a3) r1^2`` for ``r = (r1, 0, r3)``, ``a = I^-1``)
derived by hand below and checked with sympy's ``reduced`` modulo the sphere; the
rotations that preserve the ball's inertia tensor commute with its reduced field
(equivariance of ``M' = M x omega``, ``gamma' = gamma x omega`` under ``R`` with
``R I R^T = I``), checked by differentiating the model's right-hand side directly.
"""

from __future__ import annotations

import pytest
import sympy as sp
from chaplygin.derive import UserInputError, build_model
from chaplygin.derive.invariants import find_invariant_relations, specialise
from chaplygin.derive.model import Model
from chaplygin.derive.symmetries import find_symmetries

R = sp.Rational
#: a = I^-1 with (a1 - a2)/(a2 - a3) = (3/2)^2: Hess's condition holds for r1/r3 = 3/2.
HESS_A = (R(31, 11), R(13, 11), R(5, 11))
HESS_R = (R(15, 7), 0, R(10, 7))


@pytest.fixture(scope="module")
def ball():
    return build_model("chaplygin_ball")


def _top(ball, r, a=HESS_A) -> Model:
    """The heavy top (Euler-Poisson) at numbers: M' = M x A M + gamma x r, gamma' = gamma x A M."""
    M, g = sp.Matrix(ball.group("M")), sp.Matrix(ball.group("gamma"))
    w = sp.diag(*a) * M
    rhs = (*(M.cross(w) + g.cross(sp.Matrix(r))), *g.cross(w))
    return Model(
        system="heavy_top", effects=frozenset(), time=ball.time,
        state_groups=ball.state_groups, parameters=(), aux=(),
        rhs=tuple(sp.expand(e) for e in rhs), constraints=ball.constraints,
        geometry=ball.geometry, integrals=(), density=None,
    )  # fmt: skip


def _rate_of_change_mod_sphere(model, F, rate):
    """NF(dF/dt - rate F) modulo (gamma, gamma) = 1, by sympy alone."""
    f = dict(zip(model.state, model.rhs_expanded, strict=True))
    lie = sum((sp.diff(F, s) * f[s] for s in model.state), sp.S.Zero)
    g = model.group("gamma")
    _, nf = sp.reduced(
        sp.expand(sp.numer(sp.together(lie - rate * F))), [sum(s**2 for s in g) - 1],
        *model.state, order="grevlex",
    )  # fmt: skip
    return nf


def test_hess_relation_is_found_with_its_cofactor_and_no_other(ball):
    """F = (M, r) = 0 with dF/dt = det(M, A M, r) = M2 ((a2 - a1) r3 M1 + (a3 - a2) r1 M3),
    which is -(a1 - a2) (r3/r1) M2 F under Hess's condition: lambda = -12/11 M2 here."""
    top = _top(ball, HESS_R)
    found = find_invariant_relations(top, coefficient_degree=0, cofactor_degree=1)
    assert found.complete and len(found.relations) == 1
    (rel,) = found.relations
    M1, M2, M3 = ball.group("M")
    expected_rate = -(HESS_A[0] - HESS_A[1]) * HESS_R[2] / HESS_R[0] * M2
    assert sp.expand(rel.rate - expected_rate) == 0
    ratio = sp.cancel(rel.expression / (HESS_R[0] * M1 + HESS_R[2] * M3))
    assert ratio.is_Rational and ratio != 0
    assert _rate_of_change_mod_sphere(top, rel.expression, rel.rate) == 0
    # no integral in this class (constant coefficients: M' = M x AM + gamma x r)
    assert found.integrals == ()
    assert dict(found.ranks)["0"] == found.unknowns - 1  # only the constants


def test_off_hess_top_has_no_relation_by_the_same_machinery(ball):
    """Negative control: r3 = 11/7 breaks Hess's condition; (M, r) is no longer a relation
    (sympy alone) and the search proves the class holds none."""
    r = (R(15, 7), 0, R(11, 7))
    top = _top(ball, r)
    M1, M2, M3 = ball.group("M")
    F = r[0] * M1 + r[2] * M3
    rate = -(HESS_A[0] - HESS_A[1]) * r[2] / r[0] * M2
    assert _rate_of_change_mod_sphere(top, F, rate) != 0
    found = find_invariant_relations(top, coefficient_degree=0, cofactor_degree=1)
    assert found.complete and found.relations == ()
    assert "no other" in found.certificate()


def _rotation(ball, e):
    M, g = sp.Matrix(ball.group("M")), sp.Matrix(ball.group("gamma"))
    e = sp.Matrix(e)
    return (*e.cross(M), *e.cross(g))


def _bracket_mod_sphere(model, X):
    """[X, f] modulo the sphere, by direct differentiation of the model's field."""
    f = model.rhs_expanded
    x = model.state
    g = model.group("gamma")
    out = []
    for i in range(len(x)):
        comp = sum((X[k] * sp.diff(f[i], x[k]) - f[k] * sp.diff(X[i], x[k]) for k in range(6)), 0)
        num = sp.expand(sp.numer(sp.together(comp)))
        _, nf = sp.reduced(num, [sum(s**2 for s in g) - 1], *x, order="grevlex")
        out.append(nf)
    return out


def _in_span(X, fields, gens):
    """X = sum c_i fields_i with rational c_i (sympy.linsolve on the coefficients)."""
    c = sp.symbols(f"c0:{len(fields)}")
    eqs = []
    for k in range(len(X)):
        diff = sp.expand(X[k] - sum((ci * f[k] for ci, f in zip(c, fields, strict=True)), 0))
        eqs += sp.Poly(diff, *gens).coeffs()
    return sp.linsolve(eqs, *c) != sp.EmptySet


INERTIA = {
    "generic": dict(I1="7/5", I2="11/6", I3="13/4", D="9/7"),
    "axisymmetric": dict(I1="7/5", I2="7/5", I3="13/4", D="9/7"),
    "spherical": dict(I1="7/5", I2="7/5", I3="7/5", D="9/7"),
}


@pytest.mark.parametrize(
    ("inertia", "axes"), [("generic", 0), ("axisymmetric", 1), ("spherical", 3)]
)
def test_ball_rotations_are_symmetries_exactly_when_they_preserve_the_inertia(ball, inertia, axes):
    """Rotations e x (M, gamma) commute with the ball's field iff they preserve I: none for
    distinct moments, the axis e3 for I1 = I2, all three for a spherical one. The class
    (components affine in M, coefficients of degree <= 1 in gamma) holds no other
    (rank = unknowns - axes)."""
    model = specialise(ball, INERTIA[inertia])
    found = find_symmetries(model, coefficient_degree=1)
    assert (found.dimension, len(found.fields), found.trivial) == (axes, axes, ())
    e3 = _rotation(ball, (0, 0, 1))
    e1 = _rotation(ball, (1, 0, 0))
    commutes_e3 = all(c == 0 for c in _bracket_mod_sphere(model, e3))
    assert commutes_e3 == (axes >= 1)  # independent route
    if axes:
        assert _in_span(e3, found.fields, ball.state)
        assert _in_span(e1, found.fields, ball.state) == (axes == 3)


def test_a_field_in_its_own_class_is_identified_as_trivial(ball):
    """The spherical heavy top (A = a Id): f = (gamma x r, a gamma x M) is affine in M, so f
    itself is in the class and commutes with f: it is reported as trivial (parallel to the
    field); the rotation about r is the one non-trivial symmetry."""
    a = (R(5, 11),) * 3
    top = _top(ball, HESS_R, a)
    found = find_symmetries(top, coefficient_degree=1)
    assert (len(found.trivial), len(found.fields)) == (1, 1)
    f = top.rhs_expanded
    (T,) = found.trivial
    ratios = {sp.cancel(t / fk) for t, fk in zip(T, f, strict=True) if fk != 0}
    assert len(ratios) == 1 and next(iter(ratios)).is_Rational
    assert _in_span(_rotation(ball, HESS_R), [*found.fields, T], ball.state)


def test_bad_linear_classes_are_refused_before_any_work(ball):
    with pytest.raises(UserInputError, match="cofactor degree"):
        find_invariant_relations(ball, cofactor_degree=-1)
    with pytest.raises(UserInputError, match=r"coefficients, more than"):
        find_invariant_relations(ball, coefficient_degree=0, cofactor_degree=4)
    with pytest.raises(UserInputError, match="unknowns, more than"):
        find_symmetries(ball, coefficient_degree=6)
    with pytest.raises(UserInputError, match="autonomous"):
        find_symmetries(build_model("chaplygin_ball", ["variable_inertia"]))
    with pytest.raises(UserInputError, match="no parameter 'J'"):
        specialise(ball, {"J": 1})
    with pytest.raises(UserInputError, match="exact rational"):
        specialise(ball, {"D": "sqrt(2)"})
