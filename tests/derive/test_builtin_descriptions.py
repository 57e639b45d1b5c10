"""The built-in variants as RollingSystem descriptions (issue 24): the same models, exactly.

The reference is the built-in model, derived by its own module (derive/chaplygin_ball.py,
the code in generated/ and every claim run on it); the description is derived by the
RollingSystem route. After the identification (``D = m b^2``; with ``variable_gyrostat``
the built-in's total momentum ``M = M_described + K sin(Omega t)``) the vector fields are
equal identically (sympy cancels every difference to 0), every built-in integral is
conserved by the described field (Groebner normal form of its Lie derivative modulo the
phase-space constraints: a proof), and the densities are the same and invariant. The
body in a spherical support is compared on the phase space (Groebner normal forms modulo
the frame's relations: the closed model writes ``gamma⊗gamma`` as ``Id - alpha⊗alpha -
beta⊗beta``), its density up to the declared constant factor. The negative controls are
refuted by the same comparisons.
"""

from __future__ import annotations

import functools
import random
import re
from pathlib import Path

import pytest
import sympy as sp
from chaplygin.derive.builtin_descriptions import (
    BuiltinDescription,
    builtin_description,
    expressible_variants,
)
from chaplygin.derive.errors import UserInputError
from chaplygin.derive.expression_text import parse_expression
from chaplygin.derive.model import Model
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.derive.systems import SYSTEMS, build_model, builtin_variants, variant_name
from chaplygin.verify.identity import Domain, decide, measure_residual

DOCS = Path(__file__).resolve().parents[2] / "docs" / "howto" / "own-system.md"

#: Systems whose two models are equal on the phase space, not identically (the closed
#: support model eliminates gamma⊗gamma by the frame's relations; the balls do not).
ON_THE_PHASE_SPACE = ("spherical_support",)
#: Systems whose description ships fewer integrals than the built-in (the ball on a surface:
#: H and the level of the centre's surface; M03-1.5's K is the built-in's own finding): the
#: shared ones are compared, and every built-in one is proved conserved by the described flow.
SHIPS_FEWER = ("ball_on_surface",)
SHIPPED = list(builtin_variants())
IDS = [variant_name(*v) for v in SHIPPED]


@functools.cache
def _pair(system: str, effects: frozenset[str]) -> tuple[BuiltinDescription, Model, Model]:
    described = builtin_description(system, effects)
    return described, build_model(system, effects), described.model()


def _along(expr: sp.Expr, model: Model, in_omega: bool = False) -> sp.Expr:
    """``d expr/dt`` along the model's flow (the explicit time dependence included);
    ``in_omega``: the flow written in ``omega`` (its auxiliaries kept)."""
    f = model.rhs if in_omega else model.rhs_expanded
    return sp.diff(expr, model.time) + sum(
        (sp.diff(expr, y) * f[i] for i, y in enumerate(model.state)), sp.S.Zero
    )


def _at_a_point(expr: sp.Expr, seed: int = 2012) -> sp.Expr:
    """``expr`` at an exact rational point: every symbol a random rational, each
    ``sin(u), cos(u)`` a rational point of the unit circle (they enter together)."""
    rng = random.Random(seed)
    rational = lambda: sp.Rational(rng.randint(-97, 97) or 1, rng.randint(1, 89))  # noqa: E731
    circle = {}
    for u in sorted({a.args[0] for a in expr.atoms(sp.sin, sp.cos)}, key=sp.default_sort_key):
        w = rational()
        circle[sp.sin(u)] = 2 * w / (1 + w**2)
        circle[sp.cos(u)] = (1 - w**2) / (1 + w**2)
    expr = expr.xreplace(circle)
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    return expr.xreplace({s: rational() for s in symbols})


def _is_zero(expr: sp.Expr) -> bool:
    """Whether ``expr`` is identically zero: a non-zero exact value at a point proves it
    is not (fast); otherwise sympy cancels it (a proof either way)."""
    value = _at_a_point(expr)
    if value.is_Rational and value != 0:
        return False
    return sp.cancel(sp.together(expr)) == 0


def _proved_zero(expr: sp.Expr, described: Model) -> bool:
    """Whether ``expr`` vanishes on the described model's phase space: the verifier's
    Groebner normal form (a proof)."""
    return decide([sp.together(expr)], Domain(described), method="symbolic").verdict == "proved"


def _field_mismatch(
    builtin: Model, described: Model, substitution: dict[sp.Symbol, sp.Expr]
) -> list[str]:
    """The built-in state names whose rate the described flow does not reproduce.

    Each built-in state ``y`` is ``phi(described state, t)`` (the substitution); the flows
    agree when ``d phi/dt`` along the described flow is the built-in rate at ``phi``
    (for ``phi`` a state of the same name: the two right-hand sides are equal).
    :data:`ON_THE_PHASE_SPACE`: the two fields are the same expressions of the state and
    ``omega``, and ``omega`` is the same on the phase space (``"omega"`` when it is not).
    """
    in_omega = builtin.system in ON_THE_PHASE_SPACE
    bad = []
    for i, y in enumerate(builtin.state):
        ours = _along(substitution[y], described, in_omega)
        theirs = (builtin.rhs if in_omega else builtin.rhs_expanded)[i].xreplace(substitution)
        if not _is_zero(ours - theirs):
            bad.append(y.name)
    if in_omega and not _same_omega(builtin, described, substitution):
        bad.append("omega")
    return bad


def _same_omega(builtin: Model, described: Model, substitution: dict[sp.Symbol, sp.Expr]) -> bool:
    """The built-in ``omega(state)``, pulled back, gives the described momentum: ``M =
    II omega`` of the description holds on its phase space (``II`` is invertible there,
    so the two ``omega`` are equal)."""
    theirs = builtin.expand_aux(builtin.omega).xreplace(substitution)
    at = dict(zip(described.omega, theirs, strict=True))
    momentum = described.momentum_of_omega.xreplace(at) - sp.Matrix(described.group("M"))
    return all(_proved_zero(e, described) for e in momentum)


def _derivative(builtin: Model, described: Model, substitution, name: str) -> sp.Expr:
    """``d/dt`` of the built-in integral ``name`` along the described flow."""
    integral = builtin.expand_aux(builtin.integral(name)).xreplace(substitution)
    return _along(integral, described)


def _on_the_phase_space(expr: sp.Expr, model: Model) -> sp.Expr:
    """``expr`` at an exact rational point of the model's phase space (``gamma`` on the
    sphere, random rational parameters and momenta): a witness when it is not 0."""
    symbols = sorted(expr.free_symbols - set(model.params), key=lambda s: s.name)
    point = Domain(model).sample(random.Random(2012), symbols)
    return expr.xreplace(point)


def _check_field(system: str, effects: frozenset[str]) -> None:
    """The field, the integrals' names, count and expressions, the density."""
    bd, builtin, described = _pair(system, effects)
    sub = bd.substitution(builtin, described)
    assert _field_mismatch(builtin, described, sub) == []
    ours, theirs = described.integrals, builtin.integrals
    if system in SHIPS_FEWER:  # the shared names (H at least): equal expressions
        shared = [n for n, _ in ours if n in dict(theirs)]
        assert "H" in shared
        ours = [(n, e) for n, e in ours if n in shared]
        theirs = [(n, e) for n, e in theirs if n in shared]
    assert len(ours) == len(theirs)
    state_changed = any(s.name in bd.identification for s in builtin.state)
    for (name, expr), (their_name, their_expr) in zip(ours, theirs, strict=True):
        # the built-in total momentum M is the described M + K (K = k(t)): so are the names
        assert name == (re.sub(r"\bM\b", "M+K", their_name) if state_changed else their_name)
        if system in ON_THE_PHASE_SPACE:  # in omega (the same on the phase space)
            assert _is_zero(expr - their_expr.xreplace(sub))
            continue
        pulled_back = builtin.expand_aux(their_expr).xreplace(sub)
        assert _is_zero(described.expand_aux(expr) - pulled_back)
    assert (described.density is None) == (builtin.density is None)
    if builtin.density is None:
        return
    rho = builtin.expand_aux(builtin.density).xreplace(sub)
    ours = described.expand_aux(described.density)
    if bd.density_factor:  # a constant factor, declared: the squares are compared
        names = {s.name: s for s in builtin.params}
        factor = parse_expression(bd.density_factor, names, "density_factor").xreplace(sub)
        assert _proved_zero(rho**2 - factor**2 * ours**2, described)
    else:  # the state change is a translation: Jacobian 1
        assert sp.simplify(ours - rho) == 0


def _parameter_point(model: Model) -> dict[sp.Symbol, sp.Expr]:
    """Exact positive rationals for the model's parameters (seeded)."""
    rng = random.Random(33)
    return {p: sp.Rational(rng.randint(1, 40), rng.randint(1, 13)) for p in model.params}


def _check_conservation(system: str, effects: frozenset[str]) -> None:
    """Every built-in integral and the built-in density, on the described flow: proved.
    :data:`ON_THE_PHASE_SPACE`: at an exact rational point of the parameters (for symbolic
    ``lambda_k, r_k`` the normal forms exhaust the memory; for every value the
    conservation follows from the field's equality, :func:`_check_field`, and the closed
    model's claims BKM12-35..38)."""
    bd, builtin, described = _pair(system, effects)
    sub = bd.substitution(builtin, described)
    domain = Domain(described)
    point = _parameter_point(described) if system in ON_THE_PHASE_SPACE else {}
    for name, _ in builtin.integrals:
        lie = _derivative(builtin, described, sub, name).xreplace(point)
        assert decide([lie], domain, method="symbolic").verdict == "proved", name
    if builtin.density is not None:
        rho = builtin.expand_aux(builtin.density).xreplace(sub)
        residual = measure_residual(rho, described).xreplace(point)
        assert decide([residual], domain, method="symbolic").verdict == "proved"


#: The conservation proofs of more than a few seconds (Groebner normal forms in the frame).
SLOW_PROOFS = {"chaplygin_ball__straight_line"}
#: The effect combinations generated/ does not ship.
UNSHIPPED = [v for v in expressible_variants() if v not in SHIPPED]


@pytest.mark.parametrize("system, effects", SHIPPED, ids=IDS)
def test_the_described_variant_has_the_built_in_field_integrals_and_density(system, effects):
    """BKM12-2/3/4/5, K01-4.1/4.2, BM20-2.5, BKM12 §3, BKM12-57: the built-in equations,
    integrals and density from the description, D = m b^2."""
    _check_field(system, effects)


@pytest.mark.parametrize(
    "system, effects",
    [
        pytest.param(*v, marks=pytest.mark.slow) if name in SLOW_PROOFS else v
        for v, name in zip(SHIPPED, IDS, strict=True)
    ],
    ids=IDS,
)
def test_the_described_flow_keeps_the_built_in_integrals_and_density(system, effects):
    """Each built-in integral's derivative along the described flow, and the built-in
    density's Liouville residual: Groebner normal form 0 modulo the phase space."""
    _check_conservation(system, effects)


@pytest.mark.expensive
@pytest.mark.parametrize(
    "system, effects",
    UNSHIPPED,
    ids=[variant_name(*v) for v in UNSHIPPED],
)
def test_every_expressible_combination_has_the_built_in_field(system, effects):
    """The effect combinations generated/ does not ship (rubber along a line, a rubber
    gyrostat, ...): the same field, integrals and density (their conservation then
    follows from the built-in model's)."""
    _check_field(system, effects)


def test_every_shipped_variant_is_described():
    """Every variant of builtin_variants() has a description, and every expressible
    combination is of a built-in system."""
    for system, effects in builtin_variants():
        assert builtin_description(system, effects).system == system
    assert {s for s, _ in expressible_variants()} == {s for s, _ in SHIPPED}


def test_a_system_no_description_expresses_is_refused_in_one_line(monkeypatch):
    """A writer that is a reason (none is, today) refuses every effect in one line, and
    expressible_variants() leaves the system out."""
    from chaplygin.derive import builtin_descriptions

    writers = {**builtin_descriptions._WRITERS, "spherical_support": "no balls in this test"}
    monkeypatch.setattr(builtin_descriptions, "_WRITERS", writers)
    for effect in ((), *([e] for e in SYSTEMS["spherical_support"].effects)):
        with pytest.raises(UserInputError, match="not expressible: no balls") as err:
            builtin_description("spherical_support", effect)
        assert "\n" not in str(err.value)
    assert "spherical_support" not in {s for s, _ in expressible_variants()}


@pytest.mark.parametrize(
    "system, effects, message",
    [
        ("no_such_system", (), "unknown system"),
        ("chaplygin_ball", ("potential",), "unknown effect"),
        ("chaplygin_ball", ("gyrostat", "variable_gyrostat"), "exclude each other"),
    ],
)
def test_bad_input_is_refused(system, effects, message):
    with pytest.raises(UserInputError, match=message):
        builtin_description(system, effects)


def test_a_described_system_is_not_a_built_in(monkeypatch):
    from chaplygin.derive import systems

    monkeypatch.setattr(systems, "SYSTEMS", dict(systems.SYSTEMS))
    systems.register_system(RollingSystem("my_ball", inertia=(1, 2, 3)))
    with pytest.raises(UserInputError, match="not a built-in system"):
        builtin_description("my_ball")


# ---------------------------------------------------------------- negative controls
def test_a_wrong_identification_is_refuted():
    """D = 2 m b^2: the fields differ and the energy is not conserved (a witness)."""
    bd, builtin, described = _pair("chaplygin_ball", frozenset())
    sub = bd.substitution(builtin, described)
    D = next(s for s in builtin.params if s.name == "D")
    wrong = {**sub, D: 2 * sub[D]}
    assert _field_mismatch(builtin, described, wrong) != []
    assert _on_the_phase_space(_derivative(builtin, described, wrong, "H"), described) != 0


def test_the_wrong_contact_is_refuted():
    """A ball that may twist is not the rubber ball: its field differs, and the rubber
    ball's integral (omega, gamma) is not conserved by it."""
    bd, builtin, _ = _pair("chaplygin_ball", frozenset({"rubber"}))
    rolling = RollingSystem("described_chaplygin_ball", inertia=("I1", "I2", "I3")).model()
    sub = bd.substitution(builtin, rolling)
    assert _field_mismatch(builtin, rolling, sub) != []
    twist = _derivative(builtin, rolling, sub, "(omega,gamma)")
    assert _on_the_phase_space(twist, rolling) != 0


def test_a_wrong_support_identification_is_refuted():
    """D_al = w1 + w3 (for w1 - w3): the built-in omega does not give the described
    momentum on the phase space, and the energy's derivative along the described flow has
    a witness at the parameter point of the conservation proof. Without the declared
    factor the densities differ."""
    bd, builtin, described = _pair("spherical_support", frozenset())
    sub = bd.substitution(builtin, described)
    names = {s.name: s for s in (*builtin.params, *described.params)}
    wrong = {**sub, names["D_al"]: sub[names["D_al"]] + 2 * names["lambda3"] / names["r3"] ** 2}
    assert _field_mismatch(builtin, described, wrong) == ["omega"]
    lie = _derivative(builtin, described, wrong, "H").xreplace(_parameter_point(described))
    assert decide([lie], Domain(described), method="symbolic").verdict == "refuted"
    rho = builtin.expand_aux(builtin.density).xreplace(sub)
    assert not _proved_zero(rho**2 - described.expand_aux(described.density) ** 2, described)


def test_without_the_change_of_state_the_periodic_gyrostat_is_refuted():
    """BM20's total momentum is not the described M: with D = m b^2 alone the fields differ."""
    effects = frozenset({"variable_gyrostat", "variable_inertia"})
    bd, builtin, described = _pair("chaplygin_ball", effects)
    sub = bd.substitution(builtin, described)
    plain = {y: sp.Symbol(y.name, real=True) for y in builtin.state}
    assert _field_mismatch(builtin, described, {**sub, **plain}) != []


# ---------------------------------------------------------------- public surface, docs
def test_the_public_api_and_the_docs_table_name_every_shipped_variant():
    import chaplygin

    assert chaplygin.builtin_description is builtin_description
    text = DOCS.read_text()
    for system, effects in SHIPPED:
        bd = builtin_description(system, effects)
        row = next(
            (line for line in text.splitlines() if line.startswith(f"| `{bd.variant}` |")), None
        )
        assert row is not None, bd.variant
        assert f"`{bd.call()}`" in row
        for name, value in bd.identification.items():
            assert f"{name} = {value}" in row


# ------------------------------------------------ the centre's surface against the sphere
R_ = sp.Rational
#: A homogeneous ball (A, m, R) on a fixed sphere of radius S under gravity g and a potential
#: c/x3^2 of its centre's height (generic rationals); the comparison point: gamma = N0, the
#: vertical e3, the body axes along the fixed ones (Q = Id), omega = W0.
ON_SPHERE = dict(A=R_(3, 7), m=R_(13, 10), R=R_(7, 10), S=R_(29, 10), g=R_(49, 5), c=R_(5, 11))
N0, W0 = sp.Matrix([R_(2, 7), R_(3, 7), R_(6, 7)]), sp.Matrix([R_(3, 10), R_(-7, 10), R_(11, 10)])


def _values(model) -> dict:
    names = {s.name: s for s in (*model.state, *model.params, model.time)}
    return {names[k]: v for k, v in ON_SPHERE.items() if k in names}


@pytest.mark.parametrize("k", [1, 2])
def test_a_centre_on_a_sphere_moves_as_the_ball_on_the_fixed_sphere(k):
    """The centre's surface |x|^2 = (S + R)^2 (the fixed-frame stage in (omega, x)) against
    the ball on the fixed sphere of radius S (the rigid-body stage in (M, gamma, zeta), its
    potential V(gamma, zeta) = c/((S + R)^2 (gamma, zeta)^2) the same c/x3^2): with the body
    axes along the fixed ones, omega' equal and x' = (S + R)(gamma' + omega x gamma), exact.
    Control: the centre on the sphere of radius R + 2 S is refuted by the same comparison."""
    common = dict(inertia=("A", "A", "A"), mass="m", radius="R", gravity="g")
    sphere = RollingSystem(
        "ball_on_ball", support="sphere", support_radius="S",
        potential="c/((S + R)**2*(gamma1*zeta1 + gamma2*zeta2 + gamma3*zeta3)**2)", **common,
    ).model()  # fmt: skip
    centre = RollingSystem(
        "centre_on_ball", support="surface", potential="c/x3**2",
        centre_surface=f"x1**2 + x2**2 + x3**2 - (R + {k}*S)**2", **common,
    ).model()  # fmt: skip
    at = _values(sphere)
    at.update(zip(sphere.group("gamma"), N0, strict=True))
    at.update(zip(sphere.group("zeta"), (0, 0, 1), strict=True))
    w = sp.Matrix(sp.symbols("omega1:4", real=True))
    M = sphere.momentum_of_omega.xreplace(dict(zip(w, W0, strict=True))).xreplace(at)
    at.update(zip(sphere.group("M"), M, strict=True))
    omega_of_state = sphere.expand_aux(sphere.omega)
    assert (omega_of_state.xreplace(at) - W0).applyfunc(sp.simplify).is_zero_matrix
    rates = sphere.rhs_expanded.xreplace(at)
    acceleration = omega_of_state.jacobian(sp.Matrix(sphere.state)).xreplace(at) * rates
    gamma_rate = sp.Matrix(rates[3:6])
    x_rate = (ON_SPHERE["S"] + ON_SPHERE["R"]) * (gamma_rate + W0.cross(N0))
    point = _values(centre)
    point.update(zip(centre.group("omega"), W0, strict=True))
    height = ON_SPHERE["R"] + k * ON_SPHERE["S"]
    point.update(zip(centre.group("x"), height * N0, strict=True))
    theirs = centre.rhs_expanded.xreplace(point)
    expected = list(acceleration) + list(x_rate)
    same = all(sp.simplify(a - b) == 0 for a, b in zip(theirs, expected, strict=True))
    assert same == (k == 1)
