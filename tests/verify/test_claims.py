"""The claim machinery: registration, expected verdicts, strict decisions, controls' witnesses.

``chaplygin verify`` decides every registered claim (CI runs it once and fails on any verdict
that is not the expected one: the verdict must be the method the claim expects -- a proof,
not a sampled or numeric check, unless the check chose one and says why -- a proof has the
residual 0 and a refutation its witness; see :attr:`Verdict.problem`). The tests here decide
a representative sample of the claims that hold (every claim module, every kind of
decision: proof, exact sampling, numeric check, computed quantity, a multiplier's fallback,
the model claims, the Kane cross-check) and every negative control, whose witness is
re-evaluated independently.
"""

from __future__ import annotations

import dataclasses
import subprocess
import sys

import pytest
import sympy as sp
from chaplygin.derive.vectors import dot
from chaplygin.verify.claims import (
    KINDS,
    REGISTRY,
    VERDICT_OF_METHOD,
    Check,
    Claim,
    ClaimRegistry,
    ComputedClaim,
    select_claims,
)
from chaplygin.verify.claims.notation import ball_notation
from chaplygin.verify.identity import VERDICTS, Domain, decide, measure_residual
from chaplygin.verify.verdict import Verdict, check_claim
from reference import verdict as _verdict

#: The claims of the papers and the Kane cross-check (the model claims, ``MODEL:...``, are
#: named after the integrals of the derived models: listing them derives every variant).
PAPER_CLAIMS = select_claims("BKM12-*,K01-*,BM20-*,M03-*,KANE-*")
FOUNDATION = [
    "BKM12-1",
    "BKM12-2",
    "BKM12-3",
    "BKM12-4",
    "BKM12-5.F0",
    "BKM12-5.F1",
    "BKM12-5.F2",
    "BKM12-5.H",
    "BKM12-5.Hform",
    "BKM12-6",
    "BKM12-7",
    "K01-2.1",
    "K01-2.2",
    "K01-2.3.h",
    "K01-2.3.C",
    "K01-2.3.n",
    "K01-2.3.gamma",
    "K01-2.4",
    "K01-2.5",
    "K01-2.6",
    "K01-4.1",
    "K01-4.2.h",
    "K01-4.2.C",
    "K01-4.2.gamma",
    "K01-4.2.n",
    "K01-4.2m",
]
#: Claims that hold, decided here: two of every claim module (the foundation above is the
#: ball's), and every kind of decision.
SAMPLE = [
    "K01-3.2a",  # bifurcation
    "BKM12-25",
    "BM20-2.2",  # bm20
    "BM20-2.7.k",
    "K01-3.2stab",  # computed quantities: Floquet multipliers, a region, Proposition 2
    "BKM12-Fig2region",
    "BKM12-49-54",
    "BM20-3.3pair",  # the attractor-repeller pair (sampled sets)
    "BKM12-8",  # hamiltonisation
    "K01-2.11",
    "K01-3.3seg",  # k01_separatrix
    "K01-3.7",  # a check that chooses the numeric method (52-digit quadrature)
    "K01-Fig4",
    "M03-1.2",  # m03: the generic surface, the body on a sphere
    "M03-2.3",
    "BKM12-3rub.H",  # rubber: proved for every multiplier, or by the fallback
    "BKM12-3rub.K",
    "BKM12-2.1M.N1",  # support: the N-ball derivation
    "BKM12-30.N1",
    "BKM12-55",  # support_transformation
    "K01-2.29",  # transformation: a check that chooses exact sampling
    "BKM12-21",
    "MODEL:chaplygin_ball.integral(M,M)",  # our models' integrals and densities
    "MODEL:chaplygin_ball__rubber.integralH",
    "MODEL:chaplygin_ball.density",
    "KANE-ball",  # the independent Kane's-method derivation
]
CONTROLS = [c.id for c in PAPER_CLAIMS if c.expected == "fails"]
#: Controls decided by residual expressions (their witness can be re-evaluated exactly).
EXPR_CONTROLS = [i for i in CONTROLS if not isinstance(REGISTRY[i], ComputedClaim)]
# floating-point computations (the rigorous ones -- minutes of ball arithmetic each -- are
# decided by chaplygin verify in CI; tests/verify/test_proved_by_computation.py checks their
# verdict logic)
COMPUTED_CONTROLS = [
    i for i in CONTROLS if isinstance(REGISTRY[i], ComputedClaim) and not REGISTRY[i].rigorous
]


@pytest.mark.quick
def test_registry_covers_the_foundation_claims_and_controls():
    ids = {c.id for c in PAPER_CLAIMS}
    assert set(FOUNDATION) <= ids and set(SAMPLE) - ids <= {i for i in SAMPLE if "MODEL:" in i}
    assert {
        "BKM12-4/control-exponent+1/2",
        "BKM12-4/control-rho=1",
        "BKM12-5/control-(M,A gamma)",
    } <= set(CONTROLS)
    # every literal reading of a garbled formula is expected to fail and has its correction
    for claim_id in ids:
        if claim_id.endswith("/literal"):
            assert REGISTRY[claim_id].expected == "fails"
            assert claim_id[: -len("/literal")] in REGISTRY


@pytest.mark.quick
def test_every_paper_claim_has_a_kind_and_an_expected_verdict():
    for claim in PAPER_CLAIMS:
        assert claim.kind in KINDS and claim.statement and claim.source
        wanted = claim.expected_verdict()
        if claim.expected == "fails":
            assert wanted == "refuted"
        else:
            if isinstance(claim, ComputedClaim):
                assert wanted == ("proved by computation" if claim.rigorous else "numeric")
            else:
                assert wanted == "proved"
        # a negative control and a literal reading of a garbled formula must be refuted
        if "/control-" in claim.id or claim.id.endswith("/literal"):
            assert claim.expected == "fails"


@pytest.mark.quick
def test_claims_take_keyword_arguments_and_register_once():
    fields = dict(
        id="X-1", source="s", kind="integral", statement="t", system="chaplygin_ball", build=len
    )
    with pytest.raises(TypeError):
        Claim("X-1", "s", "integral", "t", "chaplygin_ball", (), len)
    with pytest.raises(ValueError, match="unknown claim kind"):
        Claim(**{**fields, "kind": "theorem"})
    registry = ClaimRegistry()
    registry.add(Claim(**fields))
    with pytest.raises(ValueError, match="duplicate claim ID X-1"):
        registry.add(Claim(**fields))
    # a computed claim is its own type: no build, no model
    computed = ComputedClaim(**{**fields, "build": None}, compute=lambda: None)
    assert computed.model() is None and computed.expected_verdict() == "numeric"
    with pytest.raises(ValueError, match="says why"):
        Check([], method="exact-sampled")
    assert set(VERDICT_OF_METHOD.values()) <= set(VERDICTS)


@pytest.mark.quick
def test_the_registry_fills_itself_and_derives_no_model_for_a_paper_claim():
    """A fresh interpreter: ``REGISTRY[id]`` works without ``select_claims()``, and neither
    it nor a selection of the papers' claims derives the models (the model claims load on
    demand)."""
    code = (
        "import sys\n"
        "from chaplygin.verify.claims import REGISTRY, select_claims\n"
        "assert REGISTRY['BKM12-4'].id == 'BKM12-4' and 'K01-2.2' in REGISTRY\n"
        "assert select_claims('K01-4.*')\n"
        "assert 'chaplygin.verify.claims.model_invariants' not in sys.modules\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    # a model claim's ID loads the model claims
    assert REGISTRY["MODEL:chaplygin_ball.density"].kind == "measure"


@pytest.mark.parametrize(
    "claim_id",
    [pytest.param(i, marks=pytest.mark.quick) for i in FOUNDATION] + SAMPLE,
)
def test_claim_gets_expected_verdict(claim_id):
    v = _verdict(claim_id)
    assert v.verdict in VERDICTS
    claim = REGISTRY[claim_id]
    if isinstance(claim, ComputedClaim):  # a computed quantity: within its derived bound
        assert v.verdict == v.expected_verdict == "numeric", (v.verdict, v.residual)
        assert "computed:" in v.method and "bound" in v.method
    else:
        # integrals, the measure and the equations must be proved symbolically, unless
        # the check itself chose the exact sampled or numeric method (and says why)
        check = claim.build(claim.model())
        expected = check.method if check.method in ("exact-sampled", "numeric") else "proved"
        assert v.verdict == v.expected_verdict == expected, (v.verdict, v.residual, v.witness)
        if expected != "proved":
            assert check.note, "a claim that is not proved says why"
        if expected != "numeric":
            assert v.residual == "0"
    assert v.ok and not v.problem


@pytest.mark.parametrize("claim_id", COMPUTED_CONTROLS)
def test_computed_control_is_refuted_by_its_error_beyond_the_bound(claim_id):
    """A wrong number (a printed value, a rule, a normalisation) is refuted by the same
    computation that checks the right one: run again, its error exceeds the derived bound
    and is the residual the verdict reports."""
    v = _verdict(claim_id)
    assert v.verdict == "refuted" and v.witness and v.ok
    result = REGISTRY[claim_id].compute()
    assert not result.holds and result.error > result.bound
    assert v.witness == result.values
    assert v.residual == f"{result.error:.6g}"


@pytest.mark.parametrize("claim_id", EXPR_CONTROLS)
def test_control_witness_is_a_phase_space_point_where_the_residual_is_not_zero(claim_id):
    """Re-evaluate the witness independently, in exact arithmetic."""
    claim = REGISTRY[claim_id]
    v = _verdict(claim_id)
    assert v.verdict == "refuted" and v.ok
    model = claim.model()
    check = claim.build(model)
    # a residual need not involve every state variable (generic-surface models); free
    # variables of the check (momenta, coordinates) carry their witness values too
    names = model.state + model.params + tuple(check.free)
    point = {s: sp.Rational(v.witness[s.name]) for s in names if s.name in v.witness}
    # the witness lies exactly on the phase space (unit gamma, the surface ...)
    assert all(sp.nsimplify(c.xreplace(point)) == 0 for c in model.constraints)
    positive = [s for spec in model.parameters if spec.domain == "positive" for s in spec.symbols]
    assert all(point[s] > 0 for s in positive if s in point)  # a physical body
    # a refuted claim's residual comes from the last check decided (its fallback)
    while check.fallback is not None:
        check = check.fallback
    # and the witness lies on the model's invariant relations and the check's level set
    for _, rel in model.invariant_relations:
        assert sp.nsimplify(model.expand_aux(rel).xreplace(point)) == 0
    assert all(sp.nsimplify(model.expand_aux(r).xreplace(point)) == 0 for r in check.on)
    # time-dependent residuals: sin(Omega t), cos(Omega t), I1(t), k1'(t) ... carry their
    # witness values by name (derivatives before the functions they contain)
    # the residuals as the verifier decides them (in its verification parameters), so
    # that atoms like sin(A1 c t) and free symbols of the check (c, w ...) match the
    # witness by name
    prepared = [Domain(model).prepare(e) for e in check.exprs]
    atoms = {
        a: sp.Rational(v.witness[str(a)])
        for e in prepared
        for a in e.atoms(sp.Derivative) | e.atoms(sp.Function)
        if str(a) in v.witness
    }
    exprs = [e.xreplace(atoms) for e in prepared]
    extra = {
        s: sp.Rational(v.witness[s.name])
        for e in exprs
        for s in e.free_symbols
        if s not in point and s.name in v.witness
    }
    exprs = [e.xreplace({**point, **extra}) for e in exprs]
    # the verdict reports the residual of largest modulus among the check's expressions
    value = max((abs(sp.nsimplify(e)) for e in exprs), key=float)
    assert value != 0
    assert (
        abs(float(value) - abs(float(sp.sympify(v.residual)))) <= 1e-12 * abs(float(value)) + 1e-300
    )


@pytest.mark.quick
@pytest.mark.parametrize("claim_id", ["BKM12-1", "BKM12-3", "BKM12-6", "K01-2.2"])
def test_exact_sampling_agrees_with_the_proof(claim_id):
    v = check_claim(REGISTRY[claim_id], method="exact-sampled")
    assert v.verdict == v.expected_verdict == "exact-sampled" and v.ok


@pytest.mark.quick
def test_numeric_method_agrees_and_refutes_the_control():
    v = check_claim(REGISTRY["BKM12-4"], method="numeric")
    assert v.verdict == v.expected_verdict == "numeric" and v.ok
    assert check_claim(REGISTRY["BKM12-4/control-rho=1"], method="numeric").verdict == "refuted"


def _perturbed(claim_id: str, build) -> Claim:
    return dataclasses.replace(REGISTRY[claim_id], id=claim_id + "/perturbed", build=build)


@pytest.mark.quick
def test_a_wrong_momentum_formula_is_refuted():
    def build(model):
        n = ball_notation(model)
        wrong = sp.diag(*n.I) * n.omega + 2 * n.D * (n.omega - dot(n.gamma, n.omega) * n.gamma)
        return Check(list(model.momentum_of_omega - wrong), free=list(n.omega))

    v = check_claim(_perturbed("BKM12-1", build))
    assert v.verdict == "refuted" and not v.ok and v.problem == "refuted, expected proved"


@pytest.mark.quick
def test_a_wrong_Z_is_refuted():
    def build(model):
        n = ball_notation(model)
        Z = dot(n.A * n.M, n.gamma) / (1 / n.D + dot(n.gamma, n.A * n.gamma))  # sign flipped
        return Check(list(model.expand_aux(n.omega) - n.A * (n.M + Z * n.gamma)))

    assert check_claim(_perturbed("BKM12-3", build)).verdict == "refuted"


@pytest.mark.quick
def test_a_true_claim_decided_by_another_method_than_expected_is_unexpected(monkeypatch):
    """Strict verification: a claim that should be proved but is only sampled (a proof that
    degraded, e.g. an ideal that is no longer radical) does not get its expected verdict."""
    import chaplygin.verify.verdict as verdict_module

    def sampled(exprs, domain, method="auto", points=8):
        out = decide(exprs, domain, method="exact-sampled", points=points)
        assert out.verdict == "exact-sampled"
        return out

    monkeypatch.setattr(verdict_module, "decide", sampled)
    v = check_claim(REGISTRY["BKM12-4"])
    assert v.verdict == "exact-sampled" and v.residual == "0" and v.expected_verdict == "proved"
    assert not v.ok and v.problem == "exact-sampled, expected proved"
    # asked for explicitly, the sampled verdict is the expected one
    assert check_claim(REGISTRY["BKM12-4"], method="exact-sampled").ok


@pytest.mark.quick
def test_a_verdict_is_ok_only_with_its_evidence():
    base = dict(id="X-1", statement="H' = 0", source="s", kind="integral", seconds=0.1)
    good = Verdict(
        **base, verdict="proved", method="m", residual="0", witness=None, expected="holds"
    )
    assert good.ok and good.expected_verdict == "proved"
    bad = [
        ("proved", "1", None, "holds", "proved with the residual 1 (not 0)"),
        ("refuted", "1", None, "fails", "refuted without a witness"),
        ("refuted", "1", {"a": "1"}, "holds", "refuted, expected proved"),
        ("proved", "0", None, "fails", "proved, expected refuted"),
        ("error", None, None, "holds", "error: m"),
    ]
    for verdict, residual, witness, expected, problem in bad:
        v = Verdict(
            **base,
            verdict=verdict,
            method="m",
            residual=residual,
            witness=witness,
            expected=expected,
        )
        assert not v.ok and v.problem == problem


@pytest.mark.quick
def test_a_verdict_shows_itself_briefly_and_its_statement_in_latex():
    v = _verdict("BKM12-4")
    assert repr(v) == f"<Verdict BKM12-4: proved, {v.seconds:.3g} s>"
    latex = v._repr_latex_()
    assert latex.startswith(r"$\text{BKM12-4}:") and latex.endswith(r"\text{(proved)}$")
    assert r"\rho" in latex and v.latex in latex
    html = v._repr_html_()
    assert "<b>BKM12-4</b>" in html and "proved" in html and "residual 0" in html
    control = _verdict("BKM12-4/control-rho=1")
    assert "at " in control._repr_html_()  # the witness
    wrong = dataclasses.replace(v, verdict="refuted", witness={"a": "1"})
    assert "UNEXPECTED (refuted, expected proved)" in repr(wrong)
    assert "unexpected" in wrong._repr_html_()


@pytest.mark.quick
def test_measure_holds_only_on_the_sphere_direction_is_irrelevant():
    """The proof is modulo (gamma, gamma) = 1; a wrong density stays wrong there."""
    model = REGISTRY["BKM12-4"].model()
    n = ball_notation(model)
    out = decide([measure_residual(n.rho(sp.Rational(-1, 3)), model)], Domain(model))
    assert out.verdict == "refuted"


@pytest.mark.quick
def test_claim_selection_by_glob():
    ids = [c.id for c in select_claims("K01-4.*")]
    assert ids and all(i.startswith("K01-4.") for i in ids)
    assert select_claims("nothing-like-this*") == []
