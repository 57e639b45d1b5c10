"""Effects: an effect that is off leaves no term, state or parameter in generated code."""

from __future__ import annotations

import re

import pytest
from chaplygin.derive import UserInputError, build_model
from chaplygin.derive.emit import CEmitter, NumpyEmitter
from chaplygin.numerics import load_model_code


def _source(effects):
    model = build_model("chaplygin_ball", effects)
    ((_, np_src),) = NumpyEmitter().emit(model)
    ((_, c_src),) = CEmitter().emit(model)
    return model, np_src, c_src


@pytest.mark.parametrize(
    ("effect", "names"),
    [("gyrostat", ["K1", "K2", "K3"]), ("contact_point", ["alpha1", "beta3", "x", "y", "b"])],
)
def test_effect_off_leaves_nothing_behind(effect, names):
    model_off, np_off, c_off = _source(())
    model_on, np_on, c_on = _source([effect])
    for name in names:
        word = re.compile(rf"\b{re.escape(name)}\b")
        assert name not in model_off.state_names + model_off.param_names
        assert name in model_on.state_names + model_on.param_names
        # the C code names states s_<name> and parameters p_<name>; its header lists them
        header_off = [ln for ln in c_off.splitlines() if ln.startswith(("state:", "parameters:"))]
        header_on = [ln for ln in c_on.splitlines() if ln.startswith(("state:", "parameters:"))]
        assert not re.search(rf"\b[sp]_{re.escape(name)}\b", c_off)
        assert not any(word.search(ln) for ln in header_off)
        assert any(word.search(ln) for ln in header_on)
        # the numpy functions unpack exactly the model's states and parameters
        unpack_off = [ln for ln in np_off.splitlines() if ln.endswith((" = y", " = p"))]
        unpack_on = [ln for ln in np_on.splitlines() if ln.endswith((" = y", " = p"))]
        assert not any(word.search(ln.rsplit("=", 1)[0]) for ln in unpack_off)
        assert any(word.search(ln.rsplit("=", 1)[0]) for ln in unpack_on)


def test_gyrostat_enters_the_equations():
    model = build_model("chaplygin_ball", ["gyrostat"])
    K = set(model.param_group("K"))
    assert any(K & e.free_symbols for e in model.rhs[:3])


def test_unknown_effect_lists_valid_ones():
    with pytest.raises(UserInputError, match="contact_point, gyrostat"):
        build_model("chaplygin_ball", ["magnetic"])
    with pytest.raises(UserInputError, match="valid systems"):
        load_model_code("rubber_ball")


# ------------------------------------------------------- conflicts and requirements
def test_conflicting_effects_fail_before_any_derivation():
    """A conflict is refused by the name check alone: no derivation starts."""
    import time

    start = time.perf_counter()
    with pytest.raises(UserInputError, match="'gyrostat'.*'variable_gyrostat'.*exclude each other"):
        build_model("chaplygin_ball", "gyrostat,variable_gyrostat", disk_cache=False)
    assert time.perf_counter() - start < 0.5


def test_a_missing_requirement_is_refused_with_the_fix(monkeypatch):
    from chaplygin.derive.effects import EFFECTS, Effect, parse_effects

    monkeypatch.setitem(EFFECTS, "needy", Effect("needy", "test effect", "nothing", ("gyrostat",)))
    with pytest.raises(
        UserInputError,
        match=r"'needy' needs the effect\(s\) 'gyrostat'.*"
        r"effects=\"gyrostat,needy\"",
    ):
        parse_effects("needy", ("needy", "gyrostat"))
    assert parse_effects("needy,gyrostat", ("needy", "gyrostat")) == {"needy", "gyrostat"}


# ------------------------------------------------------- each effect alone
def _description_of(system, effects):
    """A system's base description with ``effects`` applied (nothing derived)."""
    from chaplygin.derive import ball_on_surface, chaplygin_ball, spherical_support
    from chaplygin.derive.description import apply_effects

    module, description = {
        "chaplygin_ball": (chaplygin_ball, chaplygin_ball.ball_description),
        "spherical_support": (
            spherical_support,
            lambda e: spherical_support.support_description(2, e),
        ),
        "ball_on_surface": (ball_on_surface, ball_on_surface.ellipsoid_description),
    }[system]
    desc = description(frozenset(effects))
    apply_effects(desc, effects, module.SUPPORTED_EFFECTS)
    states = [s.name for _, group, _ in desc.states for s in group]
    params = [s.name for spec in desc.parameters.values() for s in spec.symbols]
    return desc, states, params


#: What each effect adds alone: (states, parameters, extra constraints).
ALONE = {
    ("chaplygin_ball", "gyrostat"): ([], ["K1", "K2", "K3"], 0),
    ("chaplygin_ball", "contact_point"): (
        ["alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3", "x", "y"],
        ["b"],
        0,
    ),
    ("chaplygin_ball", "variable_inertia"): ([], ["J_off", "delta", "Omega"], 0),
    ("chaplygin_ball", "variable_gyrostat"): ([], ["K1", "K2", "K3", "Omega"], 0),
    ("chaplygin_ball", "rubber"): ([], [], 1),
    ("chaplygin_ball", "straight_line"): (
        ["alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3"],
        [],
        1,
    ),
    ("spherical_support", "gyrostat"): ([], ["K1", "K2", "K3"], 0),
    ("spherical_support", "rubber_balls"): ([], [], 2),  # one no-twist row per ball
    ("ball_on_surface", "potential"): ([], ["k", "c1", "c2", "c3"], 0),
}


@pytest.mark.parametrize(("system", "effect"), sorted(ALONE))
def test_each_effect_alone_adds_exactly_its_states_parameters_and_constraints(system, effect):
    base, base_states, base_params = _description_of(system, ())
    desc, states, params = _description_of(system, (effect,))
    new_states, new_params, n_constraints = ALONE[system, effect]
    assert states == base_states + new_states
    assert sorted(params) == sorted(base_params + new_params)
    assert len(desc.constraints) == len(base.constraints) + n_constraints


@pytest.mark.parametrize(
    "effect", ["gyrostat", "contact_point", "variable_inertia", "variable_gyrostat", "rubber"]
)
def test_each_ball_effect_alone_gives_a_model_with_exactly_its_states_and_parameters(effect):
    plain = build_model("chaplygin_ball")
    model = build_model("chaplygin_ball", [effect])
    new_states, new_params, _ = ALONE["chaplygin_ball", effect]
    assert model.state_names == plain.state_names + tuple(new_states)
    assert sorted(model.param_names) == sorted(plain.param_names + tuple(new_params))


# ------------------------------------------------------- the Model validates itself
def _toy(rhs, params=("a",), integrals=(), relations=(), unknowns=()):
    import sympy as sp
    from chaplygin.derive import Model, ParameterSpec

    x = sp.Symbol("x", real=True)
    return Model(
        system="toy",
        effects=frozenset(),
        time=sp.Symbol("t", real=True),
        state_groups=(("x", (x,)),),
        parameters=tuple(
            ParameterSpec(p, (sp.Symbol(p, positive=True),), "positive", p) for p in params
        ),
        aux=(),
        rhs=(rhs(x, sp.Symbol("a", positive=True)),),
        constraints=(),
        geometry=(),
        integrals=integrals,
        density=None,
        invariant_relations=relations,
        relation_unknowns=unknowns,
    )


def test_a_valid_model_is_accepted():
    model = _toy(lambda x, a: -a * x)
    assert model.param_names == ("a",)


def test_a_model_with_an_undeclared_symbol_is_refused():
    import sympy as sp
    from chaplygin.derive import DerivationError

    c = sp.Symbol("c", real=True)
    with pytest.raises(DerivationError, match="right-hand side uses c, which is neither"):
        _toy(lambda x, a: -a * x * c)
    with pytest.raises(DerivationError, match="integral E uses c"):
        _toy(lambda x, a: -a * x, integrals=(("E", c * sp.Symbol("x", real=True)),))


def test_a_model_with_an_unused_parameter_is_refused():
    from chaplygin.derive import DerivationError

    with pytest.raises(DerivationError, match="parameters b are used by no equation"):
        _toy(lambda x, a: -a * x, params=("a", "b"))


def test_invariant_relations_need_their_unknowns():
    import sympy as sp
    from chaplygin.derive import DerivationError

    x = sp.Symbol("x", real=True)
    with pytest.raises(DerivationError, match="relation_unknowns"):
        _toy(lambda x, a: -a * x, relations=(("x", x),))
    assert _toy(lambda x, a: -a * x, relations=(("x", x),), unknowns=(x,)).relation_unknowns


def test_bad_input_for_a_variant_not_in_generated_fails_before_deriving_it(monkeypatch):
    """``rubber,straight_line`` is not in generated/; a missing parameter is refused from
    the variant's signature (its description, nothing derived), not after a derivation."""
    import time

    from chaplygin.derive import systems
    from chaplygin.numerics import integrate

    monkeypatch.setenv("CHAPLYGIN_MODEL_CACHE", "0")
    monkeypatch.setattr(systems, "_CACHE", {})
    y0 = {"M": (0.1, 0.2, 0.3), "gamma": (0, 0, 1)}
    start = time.perf_counter()
    with pytest.raises(
        UserInputError,
        match=r"missing parameter I .* give params\[\"I\"\]=\(VALUE1, VALUE2, VALUE3\)",
    ):
        integrate("chaplygin_ball", y0, 1.0, {"D": 1}, effects=["rubber", "straight_line"])
    assert time.perf_counter() - start < 0.5
    assert not systems._CACHE  # nothing was derived


def test_the_signature_is_the_derived_models():
    from chaplygin.derive.systems import variant_signature

    for effects in (["contact_point", "gyrostat"], ["variable_gyrostat", "variable_inertia"]):
        signature = variant_signature("chaplygin_ball", effects)
        model = build_model("chaplygin_ball", effects)
        assert signature.state == model.state_names
        assert signature.params == model.param_names
