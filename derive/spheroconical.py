"""Sphero-conical coordinates on the Poisson sphere and K01's separation of variables.

At zero area constant ``(L, gamma) = 0`` the Hamiltonised ball (:mod:`.hamiltonisation`) lives
on ``e(3)``; the sphero-conical coordinates ``q1, q2`` of ``gamma`` (K01-2.11, 2.12; BKM12-1.2a)
and their conjugate momenta (K01-2.13, 2.14) separate the Hamilton-Jacobi equation
(K01-2.15 ... 2.18), which gives Chaplygin's Abel-Jacobi quadratures (K01-2.22).

Everything here is sympy; the functions take the symbols (or expressions) to build with.
:mod:`chaplygin.derive.hamiltonisation` re-exports every name.

Conventions
-----------
``a_i = 1/I_i`` (K01; BKM12 uses ``a_i = D/I_i``, so ``q_BKM = D q_K01``), ``I1 < I2 < I3``
so that ``a3 < q2 < a2 < q1 < a1``.

References
----------
K01-2.11 ... K01-2.18, K01-2.22; BKM12-1.2a (FORMULAS.md).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from .vectors import cross

__all__ = [
    "spheroconical_gamma_squared",
    "spheroconical_function",
    "spheroconical_polynomial",
    "q_gradient",
    "momentum_map",
    "momentum_components",
    "k01_f",
    "k01_K",
    "hamiltonian_qp",
    "integral_n_qp",
    "separation_polynomial",
    "separation_constants",
    "quadrature_derivatives",
]


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
