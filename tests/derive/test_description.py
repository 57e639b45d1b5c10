"""The shared finishing step: descriptions as data, reduction stages, no effect names read."""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import pytest
import sympy as sp
from chaplygin.derive import (
    DerivationError,
    ball_on_surface,
    build_model,
    chaplygin_ball,
    spherical_support,
)
from chaplygin.derive.declaration import Declaration
from chaplygin.derive.description import (
    MechanicalDescription,
    Reduced,
    apply_effects,
    form_model,
)
from chaplygin.derive.effects import EFFECTS, Effect
from chaplygin.derive.model import ParameterSpec
from chaplygin.derive.support_derivation import spins_are_free
from chaplygin.derive.vectors import cross, dot, vector

DERIVE = Path(chaplygin_ball.__file__).resolve().parent


def _without_effects_line(model) -> list[str]:
    return [ln for ln in model.canonical_text().splitlines() if not ln.startswith("effects ")]


@pytest.mark.parametrize(
    ("module", "description", "effects"),
    [
        # the state includes k(t), no energy, no density: once flags, now data
        (
            chaplygin_ball,
            chaplygin_ball.ball_description,
            ("variable_gyrostat", "variable_inertia"),
        ),
        # a constraint on omega alone: its invariant relation and the density on its level
        (chaplygin_ball, chaplygin_ball.ball_description, ("rubber",)),
        # the potential and its term of the integral K
        (ball_on_surface, ball_on_surface.ellipsoid_description, ("potential",)),
        # no-twist balls: the spins are fixed (derived from the constraints)
        (
            spherical_support,
            lambda e: spherical_support.n_ball_description(1, e),
            ("gyrostat", "rubber_balls"),
        ),
    ],
)
def test_the_step_reads_what_effects_declare_never_their_names(module, description, effects):
    """The same data under an empty effects label gives the same model: only the label
    (the model's name) comes from the names."""
    chosen = frozenset(effects)
    labelled = description(chosen)
    apply_effects(labelled, chosen, module.SUPPORTED_EFFECTS)
    unlabelled = description(frozenset())
    apply_effects(unlabelled, chosen, module.SUPPORTED_EFFECTS)
    assert unlabelled.effects == frozenset()
    a, b = form_model(labelled), form_model(unlabelled)
    assert a.effects == chosen and b.effects == frozenset()
    assert _without_effects_line(a) == _without_effects_line(b)
    assert a.invariant_relations == b.invariant_relations
    assert a.references == b.references
    # and the data made a difference: the plain description gives another model
    plain = description(frozenset())
    assert _without_effects_line(form_model(plain)) != _without_effects_line(b)


def test_energy_is_an_integral_exactly_when_T_does_not_depend_on_time():
    names = {
        effects: [n for n, _ in build_model("chaplygin_ball", effects).integrals]
        for effects in ((), ("gyrostat",), ("variable_gyrostat",))
    }
    assert names[()][0] == names[("gyrostat",)][0] == "H"
    assert "H" not in names[("variable_gyrostat",)]
    # the constant gyrostat leaves K out of the state (M+K), the periodic one puts k(t) in
    assert "(M+K,gamma)" in names[("gyrostat",)]
    assert "(M,gamma)" in names[("variable_gyrostat",)]


class _AxialRotor(Effect):
    """A toy effect: a rotor about body axis 3, ``T += kappa omega_3``."""

    def declare(self, desc):
        kappa = sp.Symbol("kappa", real=True)
        return Declaration(
            kinetic_energy=kappa * desc.omega[2],
            parameters=(ParameterSpec("kappa", (kappa,), "real", "rotor momentum"),),
        )


def test_a_new_effect_is_data_in_two_places(monkeypatch):
    """An effect that only declares its data and is registered (effects.py), named by a
    system (SUPPORTED_EFFECTS, PARAMETER_ORDER), reaches the model through the one step."""
    rotor = _AxialRotor("axial_rotor", "toy", "parameter kappa", cites=(("rotor", "toy-1"),))
    monkeypatch.setitem(EFFECTS, "axial_rotor", rotor)
    order = (*chaplygin_ball.SUPPORTED_EFFECTS, "axial_rotor")
    desc = chaplygin_ball.ball_description(frozenset({"axial_rotor"}))
    apply_effects(desc, {"axial_rotor"}, order)
    with pytest.raises(DerivationError, match="kappa.*PARAMETER_ORDER"):
        form_model(desc)
    monkeypatch.setattr(
        chaplygin_ball, "PARAMETER_ORDER", (*chaplygin_ball.PARAMETER_ORDER, "kappa")
    )
    desc = chaplygin_ball.ball_description(frozenset({"axial_rotor"}))
    apply_effects(desc, {"axial_rotor"}, order)
    model = form_model(desc)
    kappa = sp.Symbol("kappa", real=True)
    assert model.param_names[-1] == "kappa"
    assert model.references["rotor"] == "toy-1"
    # the gyrostatic momentum (0, 0, kappa) stays out of the state: M' = (M + K) x omega
    P = model.group("M") + sp.Matrix([0, 0, kappa])
    assert (sp.Matrix(model.rhs[:3]) - cross(P, model.omega)).applyfunc(sp.expand).is_zero_matrix
    integrals = dict(model.integrals)
    assert sp.expand(integrals["(M+K,gamma)"] - dot(P, model.group("gamma"))) == 0
    assert "H" in integrals


def test_a_stage_refuses_data_it_does_not_take():
    surface = ball_on_surface.ellipsoid_description(frozenset())
    EFFECTS["gyrostat"].apply(surface)  # a kinetic-energy term the fixed frame cannot take
    with pytest.raises(DerivationError, match="fixed-frame .* does not take kinetic_energy"):
        form_model(surface)
    ball = chaplygin_ball.ball_description()  # a potential it takes (RollingSystem's gravity)
    ball.add_phase_space_constraint(ball.vectors["gamma"][2])
    with pytest.raises(DerivationError, match="rigid-body .* does not take phase_space"):
        form_model(ball)
    ball = chaplygin_ball.ball_description()
    ball.reduction = None
    with pytest.raises(DerivationError, match="names no reduction stage"):
        form_model(ball)


def test_a_declared_state_needs_a_rate():
    ball = chaplygin_ball.ball_description()
    ball.add_state("s", (sp.Symbol("s", real=True),), None)  # no stage derives it
    with pytest.raises(DerivationError, match="no rate for the state group 's'"):
        form_model(ball)


def test_spins_are_free_unless_a_constraint_fixes_them():
    plain = spherical_support.support_description(2)
    rubber = spherical_support.support_description(2, frozenset({"rubber_balls"}))
    apply_effects(rubber, {"rubber_balls"}, spherical_support.SUPPORTED_EFFECTS)
    assert spins_are_free(plain) == [True, True]
    assert spins_are_free(rubber) == [False, False]
    # the physical parameters follow: weight lambda (1/r^2 - 1) instead of lambda/r^2
    lam, r = sp.Rational(3), sp.Rational(1, 2)
    args = ([lam], [r], [(0, 0, 1)])
    free = spherical_support.support_parameters(*args)
    fixed = spherical_support.support_parameters(*args, effects="rubber_balls")
    assert max(free.eigenvalues) == lam / r**2
    assert max(fixed.eigenvalues) == lam * (1 / r**2 - 1)


def test_the_closed_support_declares_the_gyrostat_once():
    """``K`` comes from the gyrostat effect (not declared again by the support)."""
    desc = spherical_support.closed_support_description(frozenset({"gyrostat"}))
    assert "K" not in desc.parameters
    apply_effects(desc, {"gyrostat"}, spherical_support.SUPPORTED_EFFECTS)
    ball = chaplygin_ball.ball_description()
    EFFECTS["gyrostat"].apply(ball)
    assert desc.parameters["K"] == ball.parameters["K"]  # one declaration for every system
    assert desc.references["equations"] == "BKM12-2.3"  # the support's reference for it


def test_invariant_relations_are_declared_with_their_constraint():
    desc = chaplygin_ball.ball_description(frozenset({"rubber", "straight_line"}))
    apply_effects(desc, {"rubber", "straight_line"}, chaplygin_ball.SUPPORTED_EFFECTS)
    omega = desc.omega
    assert desc.invariant_relations == {
        "(omega,gamma)": dot(omega, vector("gamma", real=True)),
        "(omega,alpha)": dot(omega, vector("alpha", real=True)),
    }
    with pytest.raises(DerivationError, match="declared twice"):
        desc.add_invariant_relation("(omega,gamma)", dot(omega, vector("gamma", real=True)))


# ------------------------------------------------------- no step branches on an effect
#: The functions that may compare effect names: the registry's check of a user's choice
#: and the loop that applies the chosen effects in a system's order.
_NAME_HANDLERS = {"parse_effects", "apply_effects"}


def _reads_effect_names(node: ast.AST) -> bool:
    """Does ``node`` mention an effect's name or a set of chosen effects?"""
    for sub in ast.walk(node):
        if isinstance(sub, ast.Constant) and isinstance(sub.value, str) and sub.value in EFFECTS:
            return True
        if isinstance(sub, ast.Attribute) and sub.attr == "effects":
            return True
        if isinstance(sub, ast.Name) and sub.id in {"effects", "chosen"}:
            return True
    return False


def effect_branches(source: str) -> list[int]:
    """Lines of ``source`` where code branches on effect names outside :data:`_NAME_HANDLERS`:
    a comparison or a condition (``if``, ``while``, ``x if c else y``, a comprehension's
    ``if``) that mentions an effect's name or the chosen effects, or a look-up of
    ``EFFECTS`` by a constant name."""
    lines: list[int] = []

    def visit(node: ast.AST, function: str | None) -> None:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            function = node.name
        if function not in _NAME_HANDLERS:
            tests: list[ast.AST] = []
            if isinstance(node, ast.Compare):
                tests = [node]
            elif isinstance(node, ast.If | ast.IfExp | ast.While):
                tests = [node.test]
            elif isinstance(node, ast.comprehension):
                tests = list(node.ifs)
            elif (
                isinstance(node, ast.Subscript)
                and isinstance(node.value, ast.Name)
                and node.value.id == "EFFECTS"
                and isinstance(node.slice, ast.Constant)
            ):
                tests = [node.slice]
            lines.extend(t.lineno for t in tests if _reads_effect_names(t))
        for child in ast.iter_child_nodes(node):
            visit(child, function)

    visit(ast.parse(source), None)
    return lines


def test_the_check_finds_a_branch_on_an_effect():
    """Negative controls: each way of branching on an effect is found by the check."""
    branches = [
        'if "rubber" in desc.effects:\n    desc.inertia = None\n',
        'rubber = "rubber_balls" in effects\n',
        "x = [n for n in names if n in chosen]\n",
        'spin_free = False if desc.effects == {"rubber_balls"} else True\n',
        'weight = EFFECTS["rubber_balls"].adds\n',
        'def reduce(desc):\n    while "gyrostat" not in desc.effects:\n        break\n',
    ]
    for source in branches:
        assert effect_branches(source), source
    # data keyed by name, and the registry's own loop, are not branches
    assert not effect_branches('refs = {"gyrostat": {"equations": "BKM12-2.3"}}\n')
    assert not effect_branches("def apply_effects(d, effects, order):\n    if 1 in effects: pass\n")


def test_no_code_in_derive_branches_on_an_effect():
    """No finishing step, stage, system or effect compares effect names or tests the
    chosen effects: what an effect adds reaches the model only as declared data."""
    found = {
        path.name: lines
        for path in sorted(DERIVE.rglob("*.py"))
        if (lines := effect_branches(path.read_text()))
    }
    assert found == {}


@pytest.mark.parametrize("record", [MechanicalDescription, Declaration, Reduced, Effect])
def test_descriptions_and_declarations_hold_data_not_flags(record):
    """A flag an effect sets and a step reads (``total_momentum``, ``has_density`` ...) is
    a bool field: none of these records has one."""
    flags = [
        f.name
        for f in dataclasses.fields(record)
        if f.type is bool or "bool" in str(f.type).replace("|", " ").split()
    ]
    assert flags == []


# ------------------------------------------------------- the declaration reaches the model
def _declared_and_model(system, effect):
    """The effect's declaration on the system's base description, the base description
    and the model made with it (the same objects the builder uses)."""
    module, description = {
        "chaplygin_ball": (chaplygin_ball, chaplygin_ball.ball_description),
        "spherical_support": (spherical_support, spherical_support.closed_support_description),
        "ball_on_surface": (ball_on_surface, ball_on_surface.ellipsoid_description),
    }[system]
    base = description(frozenset())
    declaration = EFFECTS[effect].declare(description(frozenset()))
    desc = description(frozenset({effect}))
    apply_effects(desc, {effect}, module.SUPPORTED_EFFECTS)
    return declaration, base, form_model(desc)


@pytest.mark.parametrize(
    ("system", "effect"),
    [
        ("chaplygin_ball", "gyrostat"),
        ("chaplygin_ball", "contact_point"),
        ("chaplygin_ball", "variable_inertia"),
        ("chaplygin_ball", "variable_gyrostat"),
        ("chaplygin_ball", "rubber"),
        ("chaplygin_ball", "straight_line"),
        ("ball_on_surface", "potential"),
        ("spherical_support", "gyrostat"),
        ("spherical_support", "rubber_balls"),
    ],
)
def test_what_an_effect_declares_is_what_ends_up_in_the_model(system, effect):
    declaration, base, model = _declared_and_model(system, effect)
    groups = dict(model.state_groups)
    for name in declaration.poisson_vectors:
        assert groups[name] == tuple(vector(name, real=True))
    for group in declaration.states:
        assert groups[group.name] == group.symbols
    for spec in declaration.parameters:
        assert spec in model.parameters
    for name in declaration.redeclared_parameters:
        if all(spec.name != name for spec in declaration.parameters):
            assert name not in [spec.name for spec in model.parameters]
    # an integral term declared is the model's integral minus the system's own
    integrals = dict(model.integrals)
    for name, term in declaration.integrals:
        assert sp.simplify(integrals[name] - base.integrals.get(name, 0) - term) == 0
    relations = dict(model.invariant_relations)
    for name, expr in declaration.invariant_relations:
        assert sp.expand(relations[name] - expr) == 0
    for expr in declaration.phase_space:
        assert expr in model.constraints
    assert set(declaration.completion) <= set(model.completion)
    if declaration.momentum_in_state is not None:
        state_minus_kinetic = model.momentum_of_omega - model.inertia_operator * model.omega
        assert (state_minus_kinetic - declaration.momentum_in_state).is_zero_matrix
    if declaration.inertia is not None:
        assert model.details.inertia == declaration.inertia
    # and the effect added something the model carries
    assert model.canonical_text() != form_model(base).canonical_text()
