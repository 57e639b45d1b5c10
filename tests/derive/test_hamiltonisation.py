"""Hamiltonisation and separation of variables (K01 §2.2, BKM12 §1.2): claims and cross-checks."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
from chaplygin.derive import build_model
from chaplygin.derive import hamiltonisation as hz
from chaplygin.numerics.code import load_model_code
from chaplygin.verify.claims import REGISTRY, select_claims
from chaplygin.verify.verdict import check_claim

PROVED = [
    "K01-2.7",
    "K01-2.8",
    "K01-2.9",
    "K01-2.9.e3",
    "K01-2.10.C",
    "K01-2.10.gamma",
    "K01-2.10.n",
    "K01-2.11",
    "K01-2.12",
    "BKM12-1.2a",
    "K01-2.14",
    "K01-2.15",
    "K01-2.16",
    "K01-2.17",
    "K01-2.18",
    "K01-2.22",
    "BKM12-8",
    "BKM12-10",
    "BKM12-1.2b.H",
    "BKM12-1.2b.F1",
    "BKM12-11",
    "BKM12-RemEis",
]
REFUTED = [
    "K01-2.7/control-sign",
    "K01-2.10/control-(L,gamma)",
    "K01-2.10/control-sign",
    "K01-2.15/literal",
    "K01-2.16/literal",
]


def test_registered():
    select_claims()
    assert set(PROVED + REFUTED + ["K01-2.13"]) <= set(REGISTRY)
    assert all(REGISTRY[c].expected == "fails" for c in REFUTED)


@pytest.mark.parametrize("cid", ["K01-2.7", "K01-2.9", "K01-2.10.C", "K01-2.15", "K01-2.16"])
def test_key_claims_are_proved_symbolically(cid):
    select_claims()
    v = check_claim(REGISTRY[cid])
    assert v.verdict == "proved", v


@pytest.mark.parametrize("cid", REFUTED)
def test_controls_and_literal_readings_are_refuted_with_witness(cid):
    select_claims()
    v = check_claim(REGISTRY[cid])
    assert v.verdict == "refuted" and v.witness


def _random_state(rng):
    g = np.array([rng.uniform(-1, 1) for _ in range(3)])
    g /= np.linalg.norm(g)
    M = np.array([rng.uniform(-2, 2) for _ in range(3)])
    return M, g


def test_bracket_flow_matches_generated_code_numerically():
    """K01-2.7 by another route: P grad H (lambdified) vs the generated numpy rhs / rho,
    at random states with (M, gamma) != 0, to 1e-12 relative."""
    model = build_model("chaplygin_ball")
    I = sp.symbols("I1:4", positive=True)
    D = sp.Symbol("D", positive=True)
    L = sp.Matrix(sp.symbols("L1:4"))
    g = sp.Matrix(sp.symbols("g1:4"))
    P = hz.poisson_tensor(L, g, I, D)
    X = hz.hamiltonian_flow(hz.hamiltonian(L, g, I, D), list(L) + list(g), P)
    f = sp.lambdify([*L, *g, *I, D], list(X), modules="numpy")
    rho_f = sp.lambdify([*g, *I, D], hz.k01_multiplier(g, I, D), modules="numpy")
    code = load_model_code("chaplygin_ball", ())
    rng = random.Random(7)
    params = np.array([1.0, 1.5, 3.0, 1.0])
    for _ in range(5):
        M, gv = _random_state(rng)
        y = np.concatenate([M, gv])
        rhs = np.asarray(code.numpy.rhs(0.0, y, params), dtype=float)
        rho = rho_f(*gv, *params)
        # dL/dtau = (rho'/rho) M + M', rho' from the gamma rate (numerically, by chain rule)
        eps = 1e-7
        rho_dot = (
            rho_f(*(gv + eps * rhs[3:]), *params) - rho_f(*(gv - eps * rhs[3:]), *params)
        ) / (2 * eps)
        expected = np.concatenate([rho_dot / rho * M + rhs[:3], rhs[3:] / rho])
        got = np.array(f(*(rho * M), *gv, *params), dtype=float)
        assert np.allclose(got, expected, rtol=1e-7, atol=1e-9)
    assert model.state_names[:3] == ("M1", "M2", "M3")


def test_separated_hamiltonian_numerically_at_a_point():
    """K01-2.14/2.15 at a numeric point: (M, gamma) = 0, H(q, p) = (4/K) H_printed = H_2.8."""
    q1, q2, p1, p2 = 0.8, 0.45, 0.3, -0.7
    a = (1.0, 2 / 3, 1 / 3)
    D = 1.0
    M = np.array([float(x) for x in hz.momentum_components((p1, p2), (q1, q2), a)])
    g2 = hz.spheroconical_gamma_squared(q1, q2, a)
    gv = np.sqrt(np.array([float(x) for x in g2]))
    assert abs(np.dot(M, gv)) < 1e-14 and abs(np.sum(gv**2) - 1) < 1e-14
    I = [1 / x for x in a]
    H28 = float(hz.hamiltonian(sp.Matrix(M), sp.Matrix(gv), I, D))
    Hq = float(hz.hamiltonian_qp((p1, p2), (q1, q2), a, D))
    Hp = float(hz.hamiltonian_qp((p1, p2), (q1, q2), a, D, printed=True))
    K = float(hz.k01_K(a, D))
    assert abs(Hq - H28) < 1e-13 * abs(H28)
    assert abs(Hp * 4 / K - H28) < 1e-13 * abs(H28)
    assert abs(Hp - H28) > 0.1 * abs(H28)  # the printed normalisation is off by 4/K
