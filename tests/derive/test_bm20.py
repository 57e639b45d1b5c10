"""BM20: the Chaplygin ball with periodically varying inertia and gyrostatic momentum.

Claims get their expected verdicts (refutations with exact witnesses that are re-evaluated
here), negative controls are refuted by the same machinery, the effects leave nothing
behind when off, and the variable model integrates in double and at 30 digits.
"""

from __future__ import annotations

import random
import re
import warnings

import mpmath
import numpy as np
import pytest
import sympy as sp
from chaplygin.derive import Model, UserInputError, build_model
from chaplygin.derive.chaplygin_ball import build_chaplygin_ball
from chaplygin.derive.emit import CEmitter, NumpyEmitter
from chaplygin.derive.vectors import dot
from chaplygin.numerics import integrate, load_model_code
from chaplygin.numerics.code import ModelCode, generated_manifest
from chaplygin.verify.claims import REGISTRY, Check, Claim, ComputedClaim, select_claims
from chaplygin.verify.claims.bm20 import (
    INVOLUTION_1,
    SYMMETRY,
    GenericLawClaim,
    generic_model,
    transformation_residual,
)
from chaplygin.verify.identity import (
    Domain,
    Outcome,
    Residuals,
    decide,
    lie_derivative,
    measure_residual,
)
from chaplygin.verify.verdict import check_claim
from reference import random_params, random_state, verdict

#: The symbolic BM20 claims (the computed ones, BM20-Lyap, BM20-3.1obs, BM20-3.3pair ..., are
#: decided in tests/verify/test_claims.py and beside their numerics).
BM20 = [c.id for c in select_claims("BM20-*") if not isinstance(c, ComputedClaim)]
BM20_FAILS = [i for i in BM20 if REGISTRY[i].expected == "fails"]
VARIABLE = ("variable_gyrostat", "variable_inertia")
#: Fig. 5 of BM20 (FORMULAS.md §3): I = diag(4, 3, 2), K = (-6, -3, -9), d = 4.385,
#: J_off = 0, delta = 2, Omega = 1.07.
FIG5 = {"I": (4, 3, 2), "D": 4.385, "J_off": 0, "delta": 2, "K": (-6, -3, -9), "Omega": 1.07}


def _code(effects: tuple[str, ...] | str) -> ModelCode:
    """Code of a variant, emitted in memory when generated/ does not hold it yet."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return load_model_code("chaplygin_ball", effects)


# ------------------------------------------------------------------ claims
def test_every_bm20_claim_of_the_brief_is_registered():
    """The IDs of the BM20 issue row, with the literal reading and the controls."""
    expected = {
        "BM20-2.2",
        "BM20-2.4",
        "BM20-2.5",
        "BM20-2.5int",
        "BM20-2.6/literal",
        "BM20-2.6",
        "BM20-2.6/time-varying",
        "BM20-2.7.k0",
        "BM20-2.7.k",
        "BM20-3.1",
        "BM20-3.2/3.3",
        "BM20-3.4J",
        "BM20-3.6",
        "BM20-map",
        "BM20-3.7",
        "BM20-3.2rem",
    }
    assert expected <= set(BM20)
    assert set(BM20_FAILS) == {
        "BM20-2.6/literal",
        "BM20-2.6/time-varying",
        "BM20-3.1/involution",
        "BM20-3.4J",
        "BM20-3.2rem/control-sin",
    }


@pytest.mark.parametrize("claim_id", BM20)
def test_bm20_claim_gets_its_expected_verdict(claim_id):
    """Every claim that holds is proved; literal readings and controls are refuted."""
    v = verdict(claim_id)
    if REGISTRY[claim_id].expected == "holds":
        assert v.verdict == "proved", (v.verdict, v.residual, v.witness)
        assert v.residual == "0"
    else:
        assert v.verdict == "refuted"
        assert v.witness
    assert v.ok


def _witness_values(claim: Claim, check: Check, witness: dict) -> list[sp.Expr]:
    """The check's expressions at the witness, atoms (sin(Omega*t), I1(t) ...) by name."""
    model = claim.model()
    point = {s: sp.Rational(witness[s.name]) for s in model.state + model.params}
    atoms = {
        a: sp.Rational(witness[str(a)])
        for e in check.exprs
        for a in e.atoms(sp.Derivative) | e.atoms(sp.Function)
        if str(a) in witness
    }
    return [e.xreplace(atoms).xreplace(point) for e in check.exprs]


@pytest.mark.parametrize("claim_id", BM20_FAILS)
def test_refutation_witness_is_a_physical_point_where_the_residual_is_not_zero(claim_id):
    """Re-evaluate each witness independently in exact arithmetic."""
    claim = REGISTRY[claim_id]
    v = verdict(claim.id)
    model = claim.model()
    gamma = model.group("gamma").xreplace({s: sp.Rational(v.witness[s.name]) for s in model.state})
    assert dot(gamma, gamma) == 1
    for spec in model.parameters:
        if spec.domain == "positive":
            assert all(sp.Rational(v.witness[s.name]) > 0 for s in spec.symbols)
    assert ("sin(Omega*t)" in v.witness) == ("cos(Omega*t)" in v.witness)
    if "sin(Omega*t)" in v.witness:  # a point of the circle, when time enters
        s, c = (sp.Rational(v.witness[n]) for n in ("sin(Omega*t)", "cos(Omega*t)"))
        assert s**2 + c**2 == 1
    values = _witness_values(claim, claim.build(model), v.witness)
    assert all(val.is_Rational for val in values)
    worst = max(abs(val) for val in values)
    assert worst != 0
    assert abs(float(worst) - abs(float(sp.sympify(v.residual)))) <= 1e-12 * float(worst)


def test_time_dependent_reparametrisation_gives_a_physical_witness():
    """A_i = 1/J_ii(t) is evaluated at the sampled point of the circle (sin, cos)."""
    claim = REGISTRY["BM20-3.4J"]
    v = verdict(claim.id)
    w = {k: sp.Rational(x) for k, x in v.witness.items()}
    offset = (w["J_off"] + w["delta"] * w["sin(Omega*t)"]) ** 2
    assert w["A1"] == 1 / (w["I1"] + offset + w["D"])
    assert w["A2"] == 1 / (w["I2"] + w["D"])
    assert w["A3"] == 1 / (w["I3"] + offset + w["D"])
    assert w["J_off"] != 0 and w["delta"] != 0  # the involutions fail because J_off != 0


def test_exact_sampling_and_numeric_methods_agree_on_time_dependent_claims():
    """The weaker methods reach the same verdicts with sin/cos and I_i(t) generators."""
    for claim_id in ("BM20-3.2/3.3", "BM20-3.4.J0", "BM20-2.5int"):
        assert check_claim(REGISTRY[claim_id], method="exact-sampled").verdict == "exact-sampled"
    assert check_claim(REGISTRY["BM20-3.4J"], method="exact-sampled").verdict == "refuted"
    # undefined functions of t as generators (generic laws) and, below, the time-dependent
    # forward map A_i = 1/J_ii(t) of the concrete laws, in the mpmath path
    assert check_claim(REGISTRY["BM20-3.6"], method="numeric").verdict == "numeric"
    assert check_claim(REGISTRY["BM20-2.6/time-varying"], method="numeric").verdict == "refuted"


# ------------------------------------------------------------------ negative controls
def _decide(model: Model, exprs: list[sp.Expr], free: tuple = ()) -> Outcome:
    """Decide residuals on a model's phase space (``free``: other real variables)."""
    return decide(exprs, Domain(model, free=list(free)))


def test_a_wrong_integral_is_refuted_for_arbitrary_laws():
    """(M, k(t)) and (M, A gamma) are not first integrals of the generic model."""
    model = generic_model(VARIABLE)
    M, g = model.group("M"), model.group("gamma")
    k = sp.Matrix(model.details.gyrostatic_momentum_of_time)
    out = _decide(model, [lie_derivative(dot(M, k), model)])
    assert out.verdict == "refuted" and "Derivative(k1(t), t)" in out.witness
    I = model.details.inertia
    out = _decide(model, [lie_derivative(dot(M, I * g), model)])
    assert out.verdict == "refuted"


def test_a_wrong_density_is_refuted_and_the_right_one_proved_for_periodic_k():
    """Constant I with k(t): the density (2.7) is still invariant (time-independent)."""
    model = build_model("chaplygin_ball", ("variable_gyrostat",))
    assert model.density is not None
    assert _decide(model, [measure_residual(model.density, model)]).verdict == "proved"
    wrong = _decide(model, [measure_residual(model.density ** (-1), model)])
    assert wrong.verdict == "refuted" and wrong.witness


def test_the_density_of_constant_inertia_is_not_invariant_for_periodic_inertia():
    """rho(t) = det(X(t))^-1/2: div(rho f) = 0 at every frozen t, d rho/dt is left over."""
    model = build_model("chaplygin_ball", VARIABLE)
    assert model.density is None
    rho = model.structured_inverse.X().det() ** sp.Rational(-1, 2)
    residual = measure_residual(rho, model)
    assert _decide(model, [residual]).verdict == "refuted"
    frozen = residual - sp.diff(sp.log(rho), model.time)
    assert _decide(model, [frozen]).verdict == "proved"


def test_the_energy_is_not_conserved_with_a_periodic_gyrostat():
    """Constant I, k(t) = K sin(Omega t): the rotors do work on the ball."""
    model = build_model("chaplygin_ball", ("variable_gyrostat",))
    M, k = model.group("M"), sp.Matrix(model.details.gyrostatic_momentum_of_time)
    w = model.expand_aux(sp.Matrix(model.omega))
    out = _decide(model, [lie_derivative(dot(M - k, w) / 2, model)])
    assert out.verdict == "refuted" and "sin(Omega*t)" in out.witness


def test_a_wrong_transformation_is_refuted():
    """(t, M, gamma) -> (-t, M, -gamma) is no involution even for even I and odd k."""
    model = generic_model(VARIABLE)
    t = model.time
    parity = {}
    for i in (1, 2, 3):
        parity[sp.Function(f"I{i}", positive=True)(-t)] = sp.Function(f"I{i}", positive=True)(t)
        parity[sp.Function(f"k{i}", real=True)(-t)] = -sp.Function(f"k{i}", real=True)(t)
    good = transformation_residual(model, *INVOLUTION_1, parity=parity)
    assert _decide(model, good).verdict == "proved"
    wrong = transformation_residual(model, {"gamma": -1}, -1, parity=parity)
    assert _decide(model, wrong).verdict == "refuted"


def test_a_wrong_law_is_refuted_by_the_law_substitution_check():
    """The variant is the generic model with (3.4) substituted, not with delta -> 2 delta."""
    model = build_model("chaplygin_ball", ("variable_inertia",))
    generic = generic_model(("variable_inertia",))
    t = model.time
    J_off, delta, Omega = (model.param_group(n)[0] for n in ("J_off", "delta", "Omega"))
    I1, I2, I3 = model.param_group("I")
    offset = (J_off + 2 * delta * sp.sin(Omega * t)) ** 2  # wrong amplitude
    law = {
        sp.Function("I1", positive=True)(t): I1 + offset,
        sp.Function("I2", positive=True)(t): I2,
        sp.Function("I3", positive=True)(t): I3 + offset,
    }
    wrong = list(model.rhs_expanded - generic.rhs_expanded.xreplace(law))
    assert _decide(model, wrong).verdict == "refuted"
    assert verdict("BM20-3.4").verdict == "proved"


def test_generic_claims_use_the_generic_model():
    """Claims about arbitrary laws see I_i(t), k_i(t) as undefined functions, no sin."""
    claim = REGISTRY["BM20-2.5int"]
    assert isinstance(claim, GenericLawClaim)
    model = claim.model()
    assert model.param_names == ("D", "b")
    funcs = {str(f) for e in model.rhs_expanded for f in e.atoms(sp.Function)}
    assert {"I1(t)", "k3(t)"} <= funcs
    assert not any(str(f).startswith("sin") for f in funcs)


# ------------------------------------------------------------------ the model
@pytest.mark.parametrize(
    ("effect", "names", "absent"),
    [
        ("variable_inertia", ["J_off", "delta", "Omega"], ["K1", "K2", "K3"]),
        ("variable_gyrostat", ["K1", "K2", "K3", "Omega"], ["J_off", "delta"]),
    ],
)
def test_effect_off_leaves_nothing_behind(effect, names, absent):
    """Parameters, time dependence and emitted code exist only with the effect on."""
    off = build_model("chaplygin_ball", ())
    on = build_model("chaplygin_ball", (effect,))
    for model, present in ((off, False), (on, True)):
        ((_, np_src),) = NumpyEmitter().emit(model)
        ((_, c_src),) = CEmitter().emit(model)
        uses_time = any(model.time in e.free_symbols for e in model.rhs_expanded)
        assert uses_time == present
        assert ("chaplygin_sin(" in c_src) == present and ("detmath.sin(" in np_src) == present
        for name in names:
            assert (name in model.param_names) == present
            assert bool(re.search(rf"\bp_{name}\b", c_src)) == present
        for name in absent:
            assert name not in model.param_names
            assert not re.search(rf"\bp_{name}\b", c_src)
    assert off.param_names == ("I1", "I2", "I3", "D")
    assert [n for n, _ in off.integrals][0] == "H"
    assert "H" not in dict(on.integrals)


def test_original_variants_are_unchanged():
    """The four variants of the foundation keep their hashes (generated/ stays valid)."""
    manifest = generated_manifest()
    for effects in ((), ("gyrostat",), ("contact_point",), ("contact_point", "gyrostat")):
        model = build_model("chaplygin_ball", effects)
        assert model.hash == manifest[model.name]["hash"]


def test_constant_and_periodic_gyrostat_exclude_each_other():
    """One gyrostatic momentum: constant or periodic, never both (a clear user error)."""
    message = "'gyrostat'.*'variable_gyrostat'.*exclude each other"
    with pytest.raises(UserInputError, match=message):
        build_model("chaplygin_ball", ("gyrostat", "variable_gyrostat"))
    with pytest.raises(UserInputError, match=message), warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # "not in generated/: deriving it now"
        load_model_code("chaplygin_ball", "gyrostat,variable_gyrostat")
    with pytest.raises(UserInputError, match=message), warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        integrate("chaplygin_ball", {}, 1.0, {}, effects="variable_gyrostat,gyrostat")
    with pytest.raises(ValueError, match="unknown parameter laws"):
        build_chaplygin_ball((), _laws="sinusoidal")


def test_periodic_inertia_with_a_constant_gyrostat_keeps_its_integrals():
    """variable_inertia + gyrostat: state BKM12's M, integrals in M + K, no energy."""
    model = build_model("chaplygin_ball", ("gyrostat", "variable_inertia"))
    names = [n for n, _ in model.integrals]
    assert names == ["(M+K,M+K)", "(M+K,gamma)", "(gamma,gamma)"]
    for _, F in model.integrals:
        assert _decide(model, [lie_derivative(F, model)]).verdict == "proved"


def test_the_state_is_bm20s_total_momentum_with_the_periodic_gyrostat():
    """M = II omega + k(t): M' = M x omega exactly, integrals free of time."""
    model = build_model("chaplygin_ball", VARIABLE)
    omega = sp.Matrix(model.omega)
    k = sp.Matrix(model.details.gyrostatic_momentum_of_time)
    II = model.inertia_operator
    assert sp.expand(model.momentum_of_omega - II * omega - k) == sp.zeros(3, 1)
    assert model.euler_poincare_remainder == sp.zeros(3, 1)
    assert [n for n, _ in model.integrals] == ["(M,M)", "(M,gamma)", "(gamma,gamma)"]
    assert all(model.time not in F.free_symbols for _, F in model.integrals)


# ------------------------------------------------------------------ numerics
@pytest.mark.parametrize("effects", [("variable_inertia",), VARIABLE])
def test_numpy_c_mpmath_and_sympy_agree_at_a_nonzero_time(effects):
    """The emitted rhs (time printed as t, T in C) matches sympy at t = 0.7."""
    model, code = build_model("chaplygin_ball", effects), _code(effects)
    rng = np.random.default_rng(20)
    lib = code.compiled()
    T = 0.7  # sin(Omega T) != 0: every time-dependent term contributes
    symbols = [model.time, *model.state, *model.params]
    for _ in range(10):
        y, p = random_state(code, rng), random_params(code, rng)
        point = {s: sp.Float(float(v), 60) for s, v in zip(symbols, [T, *y, *p], strict=True)}
        exact = np.array([float(sp.N(e.xreplace(point), 60)) for e in model.rhs_expanded])
        scale = np.max(np.abs(exact))
        assert np.max(np.abs(code.numpy.rhs(T, y, p) - exact)) <= 1e-13 * scale
        if lib is not None:
            assert np.max(np.abs(lib.rhs(T, y, p) - exact)) <= 1e-13 * scale
        with mpmath.workdps(40):
            mp = code.mpmath.rhs(
                mpmath.mpf(T), [mpmath.mpf(v) for v in y], list(map(mpmath.mpf, p))
            )
            assert max(abs(float(a) - b) for a, b in zip(mp, exact, strict=True)) <= 1e-15 * scale


def test_variable_model_integrates_in_double_and_at_30_digits():
    """Fig. 5 parameters: both precisions agree to a few rtol and keep the integrals."""
    y0 = {"M": ("0.5", "-1.2", "sqrt(9 - 0.25 - 1.44)"), "gamma": ("0.6", "0", "0.8")}
    rtol = 1e-12
    code = _code(VARIABLE)
    double = integrate(code, y0, 3.0, FIG5, rtol=rtol, atol=rtol)
    digits = integrate(code, y0, 3.0, FIG5, precision=30)
    assert double.success and digits.success
    assert set(double.drift) == {"(M,M)", "(M,gamma)", "(gamma,gamma)"}
    y_double = double.y[:, -1]
    y_digits = np.array([float(v) for v in digits.y[:, -1]])
    scale = np.max(np.abs(y_digits))
    # global error of DOP853 at rtol: a modest multiple of rtol over a few periods
    assert np.max(np.abs(y_double - y_digits)) <= 1e3 * rtol * scale
    assert max(double.drift.values()) < 1e3 * rtol
    assert max(digits.drift.values()) < 1e-25
    # G^2 = (M, M) = 9 at the start (BM20's G = 3)
    assert abs(sum(float(v) ** 2 for v in digits.y[:3, 0]) - 9) < 1e-25


def test_contact_trace_variant_keeps_the_space_fixed_integrals():
    """BM20 Fig. 5's contact trace: (M, alpha), (M, beta) and the frame are conserved."""
    code = _code(("contact_point", *VARIABLE))
    params = {**FIG5, "b": 1}
    y0 = {"M": ("0.5", "-1.2", "sqrt(9 - 0.25 - 1.44)"), "gamma": ("0.6", "0", "0.8")}
    r = integrate(code, y0, 3.0, params, rtol=1e-12, atol=1e-12)
    assert r.success
    assert {"(M,alpha)", "(M,beta)", "(alpha,beta)"} <= set(r.drift)
    assert max(r.drift.values()) < 1e-9
    assert abs(r.y_final["x"]) + abs(r.y_final["y"]) > 0  # the contact point moves


def test_the_involution_maps_a_computed_trajectory_to_a_trajectory():
    """J_off = 0: x(t) -> S x(-t), S = diag(-1, 1) on (M, gamma), integrated numerically."""
    code = _code(VARIABLE)
    y0 = {"M": ("0.5", "-1.2", "0.3"), "gamma": ("0.6", "0", "0.8")}
    T = 2.0
    forward = integrate(code, y0, (0.0, T), FIG5, rtol=1e-12, atol=1e-12)
    end = forward.y[:, -1]
    S = np.array([-1, -1, -1, 1, 1, 1.0])
    back = integrate(code, list(S * end), (-T, 0.0), FIG5, rtol=1e-12, atol=1e-12)
    start = np.array([0.5, -1.2, 0.3, 0.6, 0.0, 0.8])
    assert np.max(np.abs(back.y[:, -1] - S * start)) < 1e-8
    # with J_off != 0 the same construction misses the start (BM20-3.4J)
    shifted = {**FIG5, "J_off": -0.5}
    forward = integrate(code, y0, (0.0, T), shifted, rtol=1e-12, atol=1e-12)
    back = integrate(code, list(S * forward.y[:, -1]), (-T, 0.0), shifted, rtol=1e-12, atol=1e-12)
    assert np.max(np.abs(back.y[:, -1] - S * start)) > 1e-4


def test_the_symmetry_holds_for_every_law_not_only_even_ones():
    """(t, M, gamma) -> (t, M, -gamma) needs no parity of I(t), k(t)."""
    model = generic_model(VARIABLE)
    assert _decide(model, transformation_residual(model, *SYMMETRY)).verdict == "proved"


def test_sampler_evaluates_time_dependent_forward_maps_after_the_circle():
    """A_i = 1/J_ii(t) waits for the value of sin(Omega t), then is exact and positive."""
    model = build_model("chaplygin_ball", ("variable_inertia",))
    omega = sp.Matrix(model.omega)
    res = Residuals([lie_derivative(dot(model.group("M"), omega), model)], Domain(model))
    rng = random.Random(3)
    point = res.domain.sample(rng, [s for s in res.symbols])
    assert sp.Symbol("A1", positive=True) not in point  # needs sin(Omega t) first
    res.complete_point(point, rng)
    A1 = sp.Symbol("A1", positive=True)
    assert point[A1].is_Rational and point[A1] > 0
