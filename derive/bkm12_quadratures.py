"""BKM12 §1.2: the ball at zero area constant in sphero-conical coordinates, and its quadratures.

Borisov, Kilin and Mamaev (BKM12) write the energy and the integral ``F1 = (M, M)`` as
quadratic forms in ``q'`` (BKM12-1.2b), solve them for ``q1'^2, q2'^2`` (BKM12-11) and recover
the angular velocity and momentum from ``gamma, gamma'`` (BKM12-10). Their ``a_i = D/I_i``
(K01's ``a_i = 1/I_i`` of :mod:`.spheroconical`, so ``q_BKM = D q_K01``).

Everything here is sympy; the functions take the symbols (or expressions) to build with.
:mod:`chaplygin.derive.hamiltonisation` re-exports every name.

References
----------
BKM12-1.2b, BKM12-10, BKM12-11 (FORMULAS.md).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from .vectors import cross, dot

__all__ = [
    "bkm12_Phi",
    "bkm12_energy_q",
    "bkm12_F1_q",
    "bkm12_quadratures",
    "omega_from_gamma",
    "momentum_from_gamma",
]


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
