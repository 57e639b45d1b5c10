"""The shared finishing step: descriptions as data, reduction stages, no effect names read."""

from __future__ import annotations

import pytest
import sympy as sp
from chaplygin.derive import (
    DerivationError,
    ball_on_surface,
    build_model,
    chaplygin_ball,
    spherical_support,
)
from chaplygin.derive.description import apply_effects, form_model
from chaplygin.derive.effects import EFFECTS, Effect
from chaplygin.derive.model import ParameterSpec
from chaplygin.derive.support_derivation import spins_are_free
from chaplygin.derive.vectors import cross, dot, vector


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

    def apply(self, desc):
        kappa = sp.Symbol("kappa", real=True)
        desc.add_kinetic_energy(kappa * desc.omega[2])
        desc.add_parameter(ParameterSpec("kappa", (kappa,), "real", "rotor momentum"))


def test_a_new_effect_is_data_in_two_places(monkeypatch):
    """An effect written only with ``desc.add_*`` and registered (effects.py), named by a
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
    ball = chaplygin_ball.ball_description()
    ball.add_potential(sp.Symbol("g", positive=True) * ball.vectors["gamma"][2])
    with pytest.raises(DerivationError, match="rigid-body .* does not take potential"):
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
