"""Hamiltonisation of the Chaplygin ball and separation of variables at zero area constant.

Kilin (K01 §2.2) after Borisov–Mamaev: with the new time ``d tau = rho dt`` and the new
momentum ``L = rho M``, ``rho = (1 - D (gamma, J^-1 gamma))^(-1/2)`` (Chaplygin's
multiplier, K01-2.2), the ball's equations become Hamiltonian with the energy (K01-2.8)
and a nonlinear Poisson bracket (K01-2.9) whose Casimirs are ``(L, gamma)/rho`` (the
constant of areas) and ``(gamma, gamma)`` (K01-2.10). At ``(L, gamma) = 0`` the bracket is
``e(3)``; sphero-conical coordinates ``q1, q2`` on the sphere (K01-2.11, 2.12) and their
conjugate momenta (K01-2.13, 2.14) separate the Hamilton–Jacobi equation (K01-2.15 …
2.18), which gives Chaplygin's Abel–Jacobi quadratures (K01-2.22).

The parts live by role: here the time change, the energy, the Poisson structure and its
Casimirs (K01-2.7 ... 2.10); the sphero-conical coordinates and K01's separation
(K01-2.11 ... 2.22) in :mod:`.spheroconical`; BKM12's form of them and its quadratures
(BKM12 §1.2) in :mod:`.bkm12_quadratures`. This module re-exports both, so that
``chaplygin.derive.hamiltonisation`` holds every name.

Everything here is sympy; the functions take the symbols (or expressions) to build
with, so that a check can use a model's own state and parameters.

Conventions
-----------
``a_i = 1/I_i`` (K01; BKM12 uses ``a_i = D/I_i``, so ``q_BKM = D q_K01``), ``I1 < I2 < I3``
so that ``a3 < q2 < a2 < q1 < a1``. The bracket is written with the convention
``x' = {x, H}`` (FORMULAS.md K01-2.9: the printed bracket has the opposite sign of eps,
which is the convention ``x' = {H, x}``).

References
----------
K01-2.7 … K01-2.23, K01-2.27; BKM12-8, 10, 1.2a, 1.2b, 11, RemEis (FORMULAS.md).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from .bkm12_quadratures import (
    bkm12_energy_q,
    bkm12_F1_q,
    bkm12_Phi,
    bkm12_quadratures,
    momentum_from_gamma,
    omega_from_gamma,
)
from .spheroconical import (
    hamiltonian_qp,
    integral_n_qp,
    k01_f,
    k01_K,
    momentum_components,
    momentum_map,
    q_gradient,
    quadrature_derivatives,
    separation_constants,
    separation_polynomial,
    spheroconical_function,
    spheroconical_gamma_squared,
    spheroconical_polynomial,
)
from .vectors import dot

__all__ = [
    "multiplier_inverse_square",
    "k01_multiplier",
    "hamiltonian",
    "poisson_tensor",
    "bracket",
    "hamiltonian_flow",
    "jacobi_residuals",
    "rescaled_flow",
    "area_casimir",
    "spheroconical_gamma_squared",
    "spheroconical_function",
    "spheroconical_polynomial",
    "q_gradient",
    "momentum_map",
    "momentum_components",
    "k01_f",
    "hamiltonian_qp",
    "integral_n_qp",
    "k01_K",
    "separation_polynomial",
    "separation_constants",
    "quadrature_derivatives",
    "bkm12_Phi",
    "bkm12_energy_q",
    "bkm12_F1_q",
    "bkm12_quadratures",
    "omega_from_gamma",
    "momentum_from_gamma",
]


def _J_inv(I: Sequence[sp.Expr], D: sp.Expr) -> sp.Matrix:
    return sp.diag(*[1 / (I[i] + D) for i in range(3)])


# ------------------------------------------------------------------ K01-2.7 … 2.10
def multiplier_inverse_square(gamma: sp.Matrix, I: Sequence[sp.Expr], D: sp.Expr) -> sp.Expr:
    """``rho^-2 = 1 - D (gamma, J^-1 gamma)`` (rational; K01-2.2).

    Parameters
    ----------
    gamma : sympy.Matrix, shape (3, 1)
        Unit normal in the body frame.
    I : sequence of three sympy.Expr
        Principal moments ``I1, I2, I3``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        ``1 - D (gamma, J^-1 gamma)`` with ``J = I + D Id``.

    References
    ----------
    K01-2.2
    """
    return 1 - D * dot(gamma, _J_inv(I, D) * gamma)


def k01_multiplier(gamma: sp.Matrix, I: Sequence[sp.Expr], D: sp.Expr) -> sp.Expr:
    """Chaplygin's multiplier in K01's normalisation, ``rho = (1 - D (gamma, J^-1 gamma))^-1/2``.

    It is ``D^-1/2`` times BKM12's ``rho`` (the density the ball model ships).

    Parameters
    ----------
    gamma : sympy.Matrix, shape (3, 1)
        Unit normal in the body frame.
    I : sequence of three sympy.Expr
        Principal moments ``I1, I2, I3``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        ``rho``, the inverse square root of :func:`multiplier_inverse_square`.

    References
    ----------
    K01-2.2, K01-2.7
    """
    return multiplier_inverse_square(gamma, I, D) ** sp.Rational(-1, 2)


def hamiltonian(L: sp.Matrix, gamma: sp.Matrix, I: Sequence[sp.Expr], D: sp.Expr) -> sp.Expr:
    """K01-2.8: ``H = (1 - D (gamma, J^-1 gamma)) (L, J^-1 L)/2 + D (gamma, J^-1 L)^2/2``.

    Parameters
    ----------
    L : sympy.Matrix, shape (3, 1)
        Rescaled momentum ``L = rho M``.
    gamma : sympy.Matrix, shape (3, 1)
        Unit normal in the body frame.
    I : sequence of three sympy.Expr
        Principal moments ``I1, I2, I3``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        The energy in the variables ``(L, gamma)``.

    References
    ----------
    K01-2.8
    """
    A = _J_inv(I, D)
    return (
        multiplier_inverse_square(gamma, I, D) * dot(L, A * L) / 2 + D * dot(gamma, A * L) ** 2 / 2
    )


def poisson_tensor(
    L: sp.Matrix,
    gamma: sp.Matrix,
    I: Sequence[sp.Expr],
    D: sp.Expr,
    d_sign: int = -1,
) -> sp.Matrix:
    """The Poisson tensor of K01-2.9 in the coordinates ``(L1, L2, L3, gamma1, gamma2, gamma3)``.

    ``{L_i, L_j} = -eps_ijk (L_k - D (L, gamma) rho^2 (J^-1 gamma)_k)``,
    ``{L_i, gamma_j} = -eps_ijk gamma_k``, ``{gamma_i, gamma_j} = 0``, so that
    ``x' = {x, H} = sum_l P[x, l] dH/dl``. ``rho^2 = (1 - D (gamma, J^-1 gamma))^-1`` makes
    the tensor rational.

    Parameters
    ----------
    L, gamma : sympy.Matrix, shape (3, 1)
        Rescaled momentum and unit normal (the coordinates).
    I : sequence of three sympy expressions
        Principal moments ``I1, I2, I3``.
    D : sympy expression
        ``m b^2``.
    d_sign : {-1, +1}
        Sign of the ``D``-term (``-1`` is K01's; ``+1`` is a negative control).

    Returns
    -------
    sympy.Matrix, shape (6, 6)
        Antisymmetric; ``P[i, j] = {x_i, x_j}``.

    References
    ----------
    K01-2.9
    """
    A = _J_inv(I, D)
    rho2 = 1 / multiplier_inverse_square(gamma, I, D)
    W = L + d_sign * D * dot(L, gamma) * rho2 * (A * gamma)
    P = sp.zeros(6, 6)
    for i in range(3):
        for j in range(3):
            for k in range(3):
                e = sp.LeviCivita(i, j, k)
                if e:
                    P[i, j] += -e * W[k]
                    P[i, 3 + j] += -e * gamma[k]
                    P[3 + j, i] += e * gamma[k]
    return P


def bracket(F: sp.Expr, G: sp.Expr, coords: Sequence[sp.Symbol], P: sp.Matrix) -> sp.Expr:
    """``{F, G} = grad F^T P grad G``.

    Parameters
    ----------
    F, G : sympy.Expr
        Functions of ``coords``.
    coords : sequence of n sympy.Symbol
        The coordinates ``P`` is written in.
    P : sympy.Matrix, shape (n, n)
        Poisson tensor, ``P[i, j] = {x_i, x_j}`` (e.g. :func:`poisson_tensor`).

    Returns
    -------
    sympy.Expr
        The bracket ``{F, G}`` (not simplified).
    """
    gF = sp.Matrix([sp.diff(F, x) for x in coords])
    gG = sp.Matrix([sp.diff(G, x) for x in coords])
    return (gF.T * P * gG)[0, 0]


def hamiltonian_flow(H: sp.Expr, coords: Sequence[sp.Symbol], P: sp.Matrix) -> sp.Matrix:
    """``x' = {x, H} = P grad H``, shape (n, 1).

    Parameters
    ----------
    H : sympy.Expr
        Hamiltonian, a function of ``coords``.
    coords : sequence of n sympy.Symbol
        The coordinates ``P`` is written in.
    P : sympy.Matrix, shape (n, n)
        Poisson tensor.

    Returns
    -------
    sympy.Matrix, shape (n, 1)
        The vector field ``P grad H``.
    """
    return P * sp.Matrix([sp.diff(H, x) for x in coords])


def jacobi_residuals(P: sp.Matrix, coords: Sequence[sp.Symbol]) -> list[sp.Expr]:
    """The Jacobi identity of a Poisson tensor, one expression per triple ``i < j < k``.

    ``sum_l (P[i,l] d_l P[j,k] + P[j,l] d_l P[k,i] + P[k,l] d_l P[i,j])`` (the
    Schouten bracket ``[P, P]`` up to a factor).

    Parameters
    ----------
    P : sympy.Matrix, shape (n, n)
        Antisymmetric tensor, ``P[i, j] = {x_i, x_j}``.
    coords : sequence of n sympy.Symbol
        The coordinates ``P`` is written in.

    Returns
    -------
    list of sympy.Expr
        ``n (n-1) (n-2) / 6`` residuals (not simplified), all zero exactly when ``P``
        obeys the Jacobi identity.
    """
    n = len(coords)
    dP = [[[sp.diff(P[j, k], coords[l]) for l in range(n)] for k in range(n)] for j in range(n)]
    out = []
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(j + 1, n):
                e = sp.S.Zero
                for l in range(n):
                    e += P[i, l] * dP[j][k][l] + P[j, l] * dP[k][i][l] + P[k, l] * dP[i][j][l]
                out.append(e)
    return out


def rescaled_flow(
    rhs_M: sp.Matrix, rhs_gamma: sp.Matrix, M: sp.Matrix, gamma: sp.Matrix, rho: sp.Expr
) -> tuple[sp.Matrix, sp.Matrix]:
    """K01-2.7: the flow in the time ``tau`` (``d tau = rho dt``) for ``L = rho M``.

    ``dL/d tau = rho^-1 d(rho M)/dt = (rho'/rho) M + M'``, ``d gamma/d tau = gamma'/rho``,
    where ``'`` is the model's time derivative and ``rho`` depends on ``gamma`` (and
    ``M``) only.

    Parameters
    ----------
    rhs_M, rhs_gamma : sympy.Matrix, shape (3, 1)
        The model's ``M'`` and ``gamma'``.
    M, gamma : sympy.Matrix, shape (3, 1)
        The model's state symbols.
    rho : sympy.Expr
        Time-change multiplier, a function of ``M`` and ``gamma``.

    Returns
    -------
    (dL/dtau, dgamma/dtau) : two sympy.Matrix of shape (3, 1), in the model's variables.

    References
    ----------
    K01-2.7
    """
    state = list(M) + list(gamma)
    f = list(rhs_M) + list(rhs_gamma)
    rho_dot = sum((sp.diff(rho, x) * fx for x, fx in zip(state, f, strict=True)), sp.S.Zero)
    dL = rho_dot / rho * M + rhs_M
    dg = rhs_gamma / rho
    return dL, dg


def area_casimir(L: sp.Matrix, gamma: sp.Matrix, I: Sequence[sp.Expr], D: sp.Expr) -> sp.Expr:
    """K01-2.10: ``C = (L, gamma)/rho`` (equals ``(M, gamma)`` for ``L = rho M``).

    Parameters
    ----------
    L : sympy.Matrix, shape (3, 1)
        Rescaled momentum.
    gamma : sympy.Matrix, shape (3, 1)
        Unit normal in the body frame.
    I : sequence of three sympy.Expr
        Principal moments ``I1, I2, I3``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        The Casimir ``(L, gamma) (1 - D (gamma, J^-1 gamma))^(1/2)``.

    References
    ----------
    K01-2.10
    """
    return dot(L, gamma) * multiplier_inverse_square(gamma, I, D) ** sp.S.Half
