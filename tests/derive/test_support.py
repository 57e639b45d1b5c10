"""A rigid body in a spherical support (BKM12 §2.1-2.3): derivation, claims, numerics."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import sympy as sp
from chaplygin.derive import UserInputError, build_model
from chaplygin.derive.spherical_support import (
    derive_support,
    n_ball_model,
    support_parameters,
)
from chaplygin.verify.claims import select_claims
from chaplygin.verify.verdict import check_claim
from reference import verdict

SUPPORT = "spherical_support"


def _verdict(claim_id: str):
    select_claims()  # load the registry
    from chaplygin.verify.claims.support import NUMERIC_CLAIMS

    numeric = {c.id: c for c in NUMERIC_CLAIMS}
    if claim_id in numeric:
        return check_claim(numeric[claim_id])
    return verdict(claim_id)


# ----------------------------------------------------------------- derivation
@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_n_ball_derivation_gives_the_closed_model(n):
    """The multi-body Ferrers reduction (random rational directions) is BKM12-2.1M and,
    through the eigen-data of the support tensor, the registered closed model."""
    tensor_form = _verdict(f"BKM12-2.1M.N{n}")
    assert tensor_form.verdict == "proved", tensor_form
    closed = _verdict(f"BKM12-33.N{n}")
    # one ball: rational eigen-data, a proof; more: an irrational eigenframe, 50 digits
    assert closed.verdict == ("proved" if n == 1 else "numeric"), closed
    spins = _verdict(f"BKM12-30.N{n}")
    assert spins.verdict == "proved"


def test_spins_are_conserved_for_symbolic_directions():
    d = derive_support(2)
    assert d.reduction.quasi_momentum_rate.is_zero_matrix
    assert d.spins == sp.symbols("nu1:3", real=True)
    # the reduced momentum does not depend on the spins
    assert not d.reduction.momentum.free_symbols & set(d.spins)


def test_closed_model_structure():
    model = build_model(SUPPORT)
    assert model.param_names == ("I1", "I2", "I3", "D_iso", "D_al", "D_be")
    assert model.state_names[:3] == ("M1", "M2", "M3")
    s = model.structured_inverse
    assert s.U.shape == (3, 2)  # rank-2 Woodbury split U = [alpha beta]
    D_al, D_be = model.param_group("D_al")[0], model.param_group("D_be")[0]
    assert s.C == sp.diag(-D_al, -D_be)


# ----------------------------------------------------------------- claims
@pytest.mark.parametrize(
    "claim_id",
    ["BKM12-32", "BKM12-34", "BKM12-35", "BKM12-36", "BKM12-37", "BKM12-Rem2", "BKM12-38"],
)
def test_closed_model_claims_are_proved(claim_id):
    assert _verdict(claim_id).verdict == "proved"


@pytest.mark.parametrize(
    "claim_id",
    [
        "BKM12-38/control-exponent+1/2",
        "BKM12-38/control-exponent-1",
        "BKM12-36/control-(M,A alpha)",
        "BKM12-2.1M/control-weight",
        "BKM12-2.3E/literal",
    ],
)
def test_controls_and_the_literal_energy_are_refuted_with_a_witness(claim_id):
    v = _verdict(claim_id)
    assert v.verdict == "refuted" and v.ok
    assert v.witness


def test_rubber_balls_are_the_ordinary_support_with_the_modified_tensor():
    assert _verdict("BKM12-2.2.equiv.N2").verdict == "proved"
    assert _verdict("BKM12-41.N2").verdict == "proved"
    assert _verdict("BKM12-42.N1").verdict == "proved"
    assert _verdict("BKM12-2.2").verdict == "proved"
    # helper: the rubber tensor has the weights lambda (1/r^2 - 1)
    lam, r = sp.Rational(2), sp.Rational(1, 2)
    plain = support_parameters([lam], [r], [(0, 0, 1)])
    rubber = support_parameters([lam], [r], [(0, 0, 1)], effects="rubber_balls")
    assert plain.eigenvalues[2] == lam / r**2
    assert rubber.eigenvalues[2] == lam * (1 / r**2 - 1)
    assert rubber.D_iso == lam / r**2 - lam * (1 / r**2 - 1)


def test_gyrostat_equations_integrals_and_measure():
    for claim_id in ("BKM12-2.3", "BKM12-2.3.integrals", "BKM12-2.3.measure", "BKM12-2.3E"):
        assert _verdict(claim_id).verdict == "proved", claim_id
    model = build_model(SUPPORT, "gyrostat")
    assert "(M+K,alpha)" in dict(model.integrals)


# ----------------------------------------------------------------- physical support
def test_single_ball_support_parameters_are_exact():
    p = support_parameters([3], [sp.Rational(1, 2)], [(0, 0, 2)])
    assert p.exact
    assert (p.D_iso, p.D_al, p.D_be) == (0, -12, -12)
    assert p.frame * p.frame.T == sp.eye(3)
    assert list(p.frame.row(2)) == [0, 0, 1]  # gamma along the ball (the simple eigenvalue)


def test_generic_support_parameters_are_an_orthonormal_eigenframe():
    p = support_parameters([1, 2, 1.5], [0.5, 0.7, 0.4], [(0, 0, 1), (1, 2, 2), (3, 0, 4)])
    assert not p.exact
    F = np.array(p.frame.tolist(), dtype=float)
    assert np.allclose(F @ F.T, np.eye(3), atol=1e-14)
    assert np.isclose(np.linalg.det(F), 1)
    S = np.array(p.tensor.tolist(), dtype=float)
    assert np.allclose(F @ S @ F.T, np.diag([float(e) for e in p.eigenvalues]), atol=1e-12)
    assert float(p.D_al) > 0 and float(p.D_be) > 0  # gamma = smallest eigenvalue


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (([-1], [1], [(0, 0, 1)]), "lambda_1.*positive"),
        (([1], [0], [(0, 0, 1)]), "r_1.*positive"),
        (([], [], []), "at least one ball"),
        (([1], [1], [(0, 0, 0)]), "zero vector"),
        (([1, 1], [1], [(0, 0, 1), (1, 0, 0)]), "one lambda_k and one r_k per ball"),
        (([1, 1, 1], [1, 1, 1], [(1, 0, 0), (0, 1, 0), (0, 0, 1)]), "isotropic"),
        ((["x"], [1], [(0, 0, 1)]), "lambda_1"),
    ],
)
def test_bad_support_input_raises_a_user_input_error(args, match):
    with pytest.raises(UserInputError, match=match):
        support_parameters(*args)


@pytest.mark.parametrize("n", [0, -2])
def test_no_balls_is_a_user_input_error(n):
    with pytest.raises(UserInputError, match="at least one ball"):
        derive_support(n)


def test_n_ball_model_rejects_a_zero_direction():
    with pytest.raises(UserInputError, match="zero vector"):
        n_ball_model(1, space_directions=[(0, 0, 0)])


# ----------------------------------------------------------------- numerics
def test_closed_model_integrates_with_small_drift():
    from chaplygin.numerics import integrate, load_model_code

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # not in generated/ yet: emitted in memory
        code = load_model_code(SUPPORT)
    p = support_parameters([1, 2, 1.5], [0.5, 0.7, 0.4], [(0, 0, 1), (1, 2, 2), (3, 0, 4)])
    params = {"I": (1.0, 2.0, 3.0), **{k: float(v) for k, v in p.params().items()}}
    y0 = {
        "M": (0.7, -0.4, 0.5),
        "alpha": (1, 0, 0),
        "beta": (0, 0.6, 0.8),
        "gamma": (0, -0.8, 0.6),
    }
    rtol = 1e-10
    r = integrate(code, y0, 5.0, params, rtol=rtol, atol=1e-12, backend="numpy")
    assert r.success, r.message
    assert set(r.drift) >= {"H", "(M,alpha)", "(M,beta)", "(M,gamma)", "(M,M)"}
    assert max(r.drift.values()) <= 1e3 * rtol
