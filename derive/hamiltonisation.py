"""Hamiltonisation of the Chaplygin ball and separation of variables at zero area constant.

Kilin (K01 §2.2) after Borisov–Mamaev: with the new time ``d tau = rho dt`` and the new
momentum ``L = rho M``, ``rho = (1 - D (gamma, J^-1 gamma))^(-1/2)`` (Chaplygin's
multiplier, K01-2.2), the ball's equations become Hamiltonian with the energy (K01-2.8)
and a nonlinear Poisson bracket (K01-2.9) whose Casimirs are ``(L, gamma)/rho`` (the
constant of areas) and ``(gamma, gamma)`` (K01-2.10). At ``(L, gamma) = 0`` the bracket is
``e(3)``; sphero-conical coordinates ``q1, q2`` on the sphere (K01-2.11, 2.12) and their
conjugate momenta (K01-2.13, 2.14) separate the Hamilton–Jacobi equation (K01-2.15 …
2.18), which gives Chaplygin's Abel–Jacobi quadratures (K01-2.22).

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

from .vectors import cross, dot

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


# ------------------------------------------------------------------ K01-2.11 … 2.14
def spheroconical_gamma_squared(
    q1: sp.Expr, q2: sp.Expr, a: Sequence[sp.Expr]
) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """K01-2.12 / BKM12-1.2a: ``gamma_i^2 = (a_i - q1)(a_i - q2) / prod_{j != i}(a_i - a_j)``.

    Parameters
    ----------
    q1, q2 : sympy.Expr
        Sphero-conical coordinates.
    a : sequence of three sympy.Expr
        ``a_1, a_2, a_3`` (``1/I_i`` in K01, ``D/I_i`` in BKM12).

    Returns
    -------
    tuple of three sympy.Expr
        ``(gamma_1^2, gamma_2^2, gamma_3^2)``.

    References
    ----------
    K01-2.12, BKM12-1.2a
    """
    out = []
    for i in range(3):
        j, k = [m for m in range(3) if m != i]
        out.append((a[i] - q1) * (a[i] - q2) / ((a[i] - a[j]) * (a[i] - a[k])))
    return tuple(out)


def spheroconical_function(q: sp.Expr, gamma: sp.Matrix, a: Sequence[sp.Expr]) -> sp.Expr:
    """K01-2.11: ``f(q) = sum_i gamma_i^2/(a_i - q)``; ``q1, q2`` are its zeros.

    Parameters
    ----------
    q : sympy.Expr
        The argument.
    gamma : sympy.Matrix, shape (3, 1)
        Unit normal in the body frame.
    a : sequence of three sympy.Expr
        ``a_1, a_2, a_3``.

    Returns
    -------
    sympy.Expr
        ``f(q)``.

    References
    ----------
    K01-2.11
    """
    return sum((gamma[i] ** 2 / (a[i] - q) for i in range(3)), sp.S.Zero)


def spheroconical_polynomial(q: sp.Expr, gamma: sp.Matrix, a: Sequence[sp.Expr]) -> sp.Expr:
    """``f(q) prod_i (a_i - q) = sum_i gamma_i^2 prod_{j != i}(a_j - q)``.

    On the sphere its leading coefficient is ``(gamma, gamma) = 1``: it equals
    ``(q - q1)(q - q2)``, so ``q1 + q2`` and ``q1 q2`` are quadratic forms in ``gamma``.

    Parameters
    ----------
    q : sympy.Expr
        The argument.
    gamma : sympy.Matrix, shape (3, 1)
        Unit normal in the body frame.
    a : sequence of three sympy.Expr
        ``a_1, a_2, a_3``.

    Returns
    -------
    sympy.Expr
        The quadratic polynomial in ``q`` (not expanded).

    References
    ----------
    K01-2.11
    """
    out = sp.S.Zero
    for i in range(3):
        j, k = [m for m in range(3) if m != i]
        out += gamma[i] ** 2 * (a[j] - q) * (a[k] - q)
    return out


def q_gradient(q: sp.Expr, gamma: sp.Matrix, a: Sequence[sp.Expr]) -> sp.Matrix:
    """``dq/dgamma`` of a root ``q(gamma)`` of ``f(q) = 0`` (implicit function theorem).

    ``f`` is homogeneous of degree 2 in ``gamma``, so this extension of ``q`` off the sphere
    is homogeneous of degree 0 and its gradient is tangent to the sphere.

    Parameters
    ----------
    q : sympy.Expr
        The root (a symbol standing for ``q1`` or ``q2``).
    gamma : sympy.Matrix, shape (3, 1)
        Unit normal in the body frame.
    a : sequence of three sympy.Expr
        ``a_1, a_2, a_3``.

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        ``-(df/dgamma) / (df/dq)`` with ``f`` of :func:`spheroconical_function`.
    """
    # f(q, gamma) = sum_i gamma_i^2/(a_i - q): df/dgamma_i = 2 gamma_i/(a_i - q),
    # df/dq = sum_i gamma_i^2/(a_i - q)^2; dq/dgamma = -(df/dgamma)/(df/dq).
    fq = sum((gamma[i] ** 2 / (a[i] - q) ** 2 for i in range(3)), sp.S.Zero)
    return sp.Matrix([-2 * gamma[i] / (a[i] - q) / fq for i in range(3)])


def momentum_map(
    p: Sequence[sp.Expr], q: Sequence[sp.Expr], gamma: sp.Matrix, a: Sequence[sp.Expr]
) -> sp.Matrix:
    """K01-2.13: ``M = p1 (dq1/dgamma x gamma) + p2 (dq2/dgamma x gamma)``.

    ``M`` here is K01's rescaled momentum (``L`` of :func:`hamiltonian`).

    Parameters
    ----------
    p : sequence of two sympy.Expr
        Conjugate momenta ``p1, p2``.
    q : sequence of two sympy.Expr
        Sphero-conical coordinates ``q1, q2`` (roots of ``f`` at ``gamma``).
    gamma : sympy.Matrix, shape (3, 1)
        Unit normal in the body frame.
    a : sequence of three sympy.Expr
        ``a_1, a_2, a_3``.

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        The momentum, in ``p, q`` and ``gamma``.

    References
    ----------
    K01-2.13
    """
    return p[0] * cross(q_gradient(q[0], gamma, a), gamma) + p[1] * cross(
        q_gradient(q[1], gamma, a), gamma
    )


def momentum_components(
    p: Sequence[sp.Expr], q: Sequence[sp.Expr], a: Sequence[sp.Expr]
) -> sp.Matrix:
    """K01-2.14: the components of (2.13) in ``q, p`` (``gamma`` in the positive octant).

    Parameters
    ----------
    p : sequence of two sympy.Expr
        Conjugate momenta ``p1, p2``.
    q : sequence of two sympy.Expr
        Sphero-conical coordinates ``q1, q2`` (``a3 < q2 < a2 < q1 < a1``).
    a : sequence of three sympy.Expr
        ``a_1, a_2, a_3``.

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        ``(M1, M2, M3)`` as printed in K01 (with square roots).

    References
    ----------
    K01-2.14
    """
    p1, p2 = p
    q1, q2 = q
    a1, a2, a3 = a
    F = (
        2
        / (q1 - q2)
        * sp.sqrt(
            (a1 - q1)
            * (a1 - q2)
            * (q1 - a2)
            * (a2 - q2)
            * (q1 - a3)
            * (q2 - a3)
            / ((a1 - a2) * (a2 - a3) * (a1 - a3))
        )
    )
    M1 = (
        F
        * sp.sqrt(a2 - a3)
        * (p1 * sp.sqrt((a1 - q1) / (a1 - q2)) - p2 * sp.sqrt((a1 - q2) / (a1 - q1)))
    )
    M2 = (
        F
        * sp.sqrt(a1 - a3)
        * (p1 * sp.sqrt((q1 - a2) / (a2 - q2)) + p2 * sp.sqrt((a2 - q2) / (q1 - a2)))
    )
    M3 = (
        F
        * sp.sqrt(a1 - a2)
        * (-p1 * sp.sqrt((q1 - a3) / (q2 - a3)) + p2 * sp.sqrt((q2 - a3) / (q1 - a3)))
    )
    return sp.Matrix([M1, M2, M3])


# ------------------------------------------------------------------ K01-2.15 … 2.22
def k01_f(q: sp.Expr, a: Sequence[sp.Expr], D: sp.Expr) -> sp.Expr:
    """K01-2.15: ``f(q) = q^-1 (q - a1)(q - a2)(q - a3)(1 + D q)``.

    Parameters
    ----------
    q : sympy.Expr
        A sphero-conical coordinate.
    a : sequence of three sympy.Expr
        ``a_i = 1/I_i``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        ``f(q)``.

    References
    ----------
    K01-2.15
    """
    return (q - a[0]) * (q - a[1]) * (q - a[2]) * (1 + D * q) / q


def k01_K(a: Sequence[sp.Expr], D: sp.Expr) -> sp.Expr:
    """``K = prod_i (1 + D a_i) = prod_i J_i/I_i`` (the missing factor of K01-2.15, 2.16).

    Parameters
    ----------
    a : sequence of three sympy.Expr
        ``a_i = 1/I_i``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        The product ``K``.

    References
    ----------
    K01-2.15, K01-2.16
    """
    return sp.Mul(*[1 + D * ai for ai in a])


def hamiltonian_qp(
    p: Sequence[sp.Expr],
    q: Sequence[sp.Expr],
    a: Sequence[sp.Expr],
    D: sp.Expr,
    printed: bool = False,
) -> sp.Expr:
    """K01-2.15: ``H = c/2 (q2^-1 - q1^-1)^-1 (-p1^2 f(q1) + p2^2 f(q2))``.

    ``c = 4/K`` (corrected, FORMULAS.md) or ``c = 1`` (``printed=True``: as K01 prints it).

    Parameters
    ----------
    p : sequence of two sympy.Expr
        Conjugate momenta ``p1, p2``.
    q : sequence of two sympy.Expr
        Sphero-conical coordinates ``q1, q2``.
    a : sequence of three sympy.Expr
        ``a_i = 1/I_i``.
    D : sympy.Expr
        ``m b^2``.
    printed : bool, optional
        Use K01's printed factor ``c = 1`` instead of the corrected ``4/K``.

    Returns
    -------
    sympy.Expr
        The Hamiltonian in ``(q, p)``.

    References
    ----------
    K01-2.15
    """
    c = sp.S.One if printed else 4 / k01_K(a, D)
    q1, q2 = q
    p1, p2 = p
    return c / 2 / (1 / q2 - 1 / q1) * (-(p1**2) * k01_f(q1, a, D) + p2**2 * k01_f(q2, a, D))


def integral_n_qp(
    p: Sequence[sp.Expr],
    q: Sequence[sp.Expr],
    a: Sequence[sp.Expr],
    D: sp.Expr,
    printed: bool = False,
) -> sp.Expr:
    """K01-2.16: ``n = c (-p1^2 f(q1) q1 (1 + D q2) + p2^2 f(q2) q2 (1 + D q1))/(q1 - q2)``.

    ``c`` as in :func:`hamiltonian_qp`.

    Parameters
    ----------
    p : sequence of two sympy.Expr
        Conjugate momenta ``p1, p2``.
    q : sequence of two sympy.Expr
        Sphero-conical coordinates ``q1, q2``.
    a : sequence of three sympy.Expr
        ``a_i = 1/I_i``.
    D : sympy.Expr
        ``m b^2``.
    printed : bool, optional
        Use K01's printed factor ``c = 1`` instead of the corrected ``4/K``.

    Returns
    -------
    sympy.Expr
        The integral ``n = (M, M)`` in ``(q, p)``.

    References
    ----------
    K01-2.16
    """
    c = sp.S.One if printed else 4 / k01_K(a, D)
    q1, q2 = q
    p1, p2 = p
    f1, f2 = k01_f(q1, a, D), k01_f(q2, a, D)
    return c * (-(p1**2) * f1 * q1 * (1 + D * q2) + p2**2 * f2 * q2 * (1 + D * q1)) / (q1 - q2)


def separation_polynomial(
    q: sp.Expr, lam1: sp.Expr, lam2: sp.Expr, a: Sequence[sp.Expr], D: sp.Expr
) -> sp.Expr:
    """K01-2.17: ``R(q) = (2 lam1 + q lam2)(q - a1)(q - a2)(q - a3)(1 + D q)``.

    Parameters
    ----------
    q : sympy.Expr
        The argument.
    lam1, lam2 : sympy.Expr
        Separation constants (:func:`separation_constants`).
    a : sequence of three sympy.Expr
        ``a_i = 1/I_i``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        ``R(q)`` (not expanded).

    References
    ----------
    K01-2.17
    """
    return (2 * lam1 + q * lam2) * (q - a[0]) * (q - a[1]) * (q - a[2]) * (1 + D * q)


def separation_constants(h: sp.Expr, n: sp.Expr, D: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """K01-2.18: ``lam1 = H``, ``lam2 = 2 D H - n``.

    Parameters
    ----------
    h : sympy.Expr
        Energy ``H``.
    n : sympy.Expr
        Integral ``n = (M, M)``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    (lam1, lam2) : tuple of two sympy.Expr

    References
    ----------
    K01-2.18
    """
    return h, 2 * D * h - n


def quadrature_derivatives(
    q: Sequence[sp.Expr], p: Sequence[sp.Expr], a: Sequence[sp.Expr], D: sp.Expr
) -> tuple[sp.Expr, sp.Expr]:
    """``dq_i/d tau = dH/dp_i`` of the corrected K01-2.15.

    Parameters
    ----------
    q : sequence of two sympy.Expr
        Sphero-conical coordinates ``q1, q2``.
    p : sequence of two sympy.Symbol
        Conjugate momenta ``p1, p2`` (differentiated by).
    a : sequence of three sympy.Expr
        ``a_i = 1/I_i``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    (dq1/dtau, dq2/dtau) : tuple of two sympy.Expr

    References
    ----------
    K01-2.15, K01-2.22
    """
    H = hamiltonian_qp(p, q, a, D)
    return sp.diff(H, p[0]), sp.diff(H, p[1])


# ------------------------------------------------------------------ BKM12 §1.2
def bkm12_Phi(x: sp.Expr, a: Sequence[sp.Expr]) -> sp.Expr:
    """BKM12 §1.2: ``Phi(x) = (1 + x)(a1 - x)(a2 - x)(a3 - x)`` (``a_i = D/I_i``).

    Parameters
    ----------
    x : sympy.Expr
        The argument.
    a : sequence of three sympy.Expr
        ``a_i = D/I_i``.

    Returns
    -------
    sympy.Expr
        ``Phi(x)`` (not expanded).

    References
    ----------
    BKM12-1.2b
    """
    return (1 + x) * (a[0] - x) * (a[1] - x) * (a[2] - x)


def _bkm12_Delta(q1: sp.Expr, q2: sp.Expr) -> sp.Expr:
    return (1 + q1) * (1 + q2) / 4


def bkm12_energy_q(
    q: Sequence[sp.Expr], qdot: Sequence[sp.Expr], a: Sequence[sp.Expr], D: sp.Expr
) -> sp.Expr:
    """BKM12-1.2b: ``H = Delta D (q1 - q2)/2 (q1'^2/(q2 Phi(q1)) - q2'^2/(q1 Phi(q2)))``.

    ``Delta = (1 + q1)(1 + q2)/4``.

    Parameters
    ----------
    q : sequence of two sympy.Expr
        Sphero-conical coordinates ``q1, q2`` (BKM12's, ``a_i = D/I_i``).
    qdot : sequence of two sympy.Expr
        Their time derivatives ``q1', q2'``.
    a : sequence of three sympy.Expr
        ``a_i = D/I_i``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        The energy ``H`` as a quadratic form in ``q'``.

    References
    ----------
    BKM12-1.2b
    """
    q1, q2 = q
    d1, d2 = qdot
    return (
        _bkm12_Delta(q1, q2)
        * D
        * (q1 - q2)
        / 2
        * (d1**2 / (q2 * bkm12_Phi(q1, a)) - d2**2 / (q1 * bkm12_Phi(q2, a)))
    )


def bkm12_F1_q(
    q: Sequence[sp.Expr], qdot: Sequence[sp.Expr], a: Sequence[sp.Expr], D: sp.Expr
) -> sp.Expr:
    """BKM12-1.2b: ``F1``.

    ``F1 = Delta D^2 (q1 - q2)((1+q2) q1'^2/(q2^2 Phi(q1)) - (1+q1) q2'^2/(q1^2 Phi(q2)))``.

    Parameters
    ----------
    q : sequence of two sympy.Expr
        Sphero-conical coordinates ``q1, q2`` (BKM12's).
    qdot : sequence of two sympy.Expr
        Their time derivatives ``q1', q2'``.
    a : sequence of three sympy.Expr
        ``a_i = D/I_i``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Expr
        The integral ``F1 = (M, M)`` as a quadratic form in ``q'``.

    References
    ----------
    BKM12-1.2b
    """
    q1, q2 = q
    d1, d2 = qdot
    return (
        _bkm12_Delta(q1, q2)
        * D**2
        * (q1 - q2)
        * (
            (1 + q2) * d1**2 / (q2**2 * bkm12_Phi(q1, a))
            - (1 + q1) * d2**2 / (q1**2 * bkm12_Phi(q2, a))
        )
    )


def bkm12_quadratures(
    q: Sequence[sp.Expr], a: Sequence[sp.Expr], D: sp.Expr, E: sp.Expr, C: sp.Expr
) -> tuple[sp.Expr, sp.Expr]:
    """BKM12-11: ``q1'^2`` and ``q2'^2`` on ``2H = E``, ``F1 = C``.

    Parameters
    ----------
    q : sequence of two sympy.Expr
        Sphero-conical coordinates ``q1, q2`` (BKM12's).
    a : sequence of three sympy.Expr
        ``a_i = D/I_i``.
    D : sympy.Expr
        ``m b^2``.
    E : sympy.Expr
        Twice the energy.
    C : sympy.Expr
        Value of ``F1 = (M, M)``.

    Returns
    -------
    (q1'^2, q2'^2) : tuple of two sympy.Expr

    References
    ----------
    BKM12-11
    """
    q1, q2 = q
    den = _bkm12_Delta(q1, q2) * D**2 * (q1 - q2) ** 2
    return (
        q2**2 * bkm12_Phi(q1, a) * (C * q1 - E * D * (1 + q1)) / den,
        q1**2 * bkm12_Phi(q2, a) * (C * q2 - E * D * (1 + q2)) / den,
    )


def omega_from_gamma(gamma: sp.Matrix, gamma_dot: sp.Matrix, I: Sequence[sp.Expr]) -> sp.Matrix:
    """BKM12-10: ``omega = k gamma' x I gamma``, ``k^-1 = (gamma, I gamma)``.

    Valid on ``(I omega, gamma) = 0``.

    Parameters
    ----------
    gamma, gamma_dot : sympy.Matrix, shape (3, 1)
        Unit normal and its time derivative.
    I : sequence of three sympy.Expr
        Principal moments ``I1, I2, I3``.

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        Angular velocity ``omega``.

    References
    ----------
    BKM12-10
    """
    Ig = sp.diag(*I) * gamma
    return cross(gamma_dot, Ig) / dot(gamma, Ig)


def momentum_from_gamma(
    gamma: sp.Matrix, gamma_dot: sp.Matrix, I: Sequence[sp.Expr], D: sp.Expr
) -> sp.Matrix:
    """BKM12-10: ``M = k I (gamma' x I gamma) - D gamma x gamma'``.

    ``k^-1 = (gamma, I gamma)``; valid on ``(M, gamma) = 0``.

    Parameters
    ----------
    gamma, gamma_dot : sympy.Matrix, shape (3, 1)
        Unit normal and its time derivative.
    I : sequence of three sympy.Expr
        Principal moments ``I1, I2, I3``.
    D : sympy.Expr
        ``m b^2``.

    Returns
    -------
    sympy.Matrix, shape (3, 1)
        Angular momentum ``M`` about the contact point.

    References
    ----------
    BKM12-10
    """
    Ig = sp.diag(*I) * gamma
    return sp.diag(*I) * cross(gamma_dot, Ig) / dot(gamma, Ig) - D * cross(gamma, gamma_dot)
