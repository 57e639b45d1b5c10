"""Chaplygin's transformation and its generalisation, derived (BKM12 §1.3-1.4, §2.4-2.6, K01 §2.3).

Everything here is sympy and is *derived*, not typed from the papers:

* :func:`theorem1` — the linear map ``M~ = m1 M + m2 gamma``, ``gamma~ = c1 M + c2 gamma``
  with ``A`` kept and ``D -> D~``. ``omega~ = A ((m1 + c1 Z~) M + (m2 + c2 Z~) gamma)`` and
  ``omega = A (M + Z gamma)``, so every 2x2 minor of ``[omega~, omega]`` is
  ``A_i A_j (M_i gamma_j - M_j gamma_i)`` times ``(m1 + c1 Z~) Z - (m2 + c2 Z~)``. On the
  energy level ``2H = E`` the scalars ``(A M, M)``, ``(gamma, A gamma)`` are functions of
  ``X = D^-1 - (gamma, A gamma)`` and ``Y = (A M, gamma)`` (BKM12-17); the factor is then a
  polynomial in ``X, Y`` over ``X^2 X~``, and requiring it to vanish for all ``X, Y`` gives
  the conditions on the coefficients (BKM12-14, equivalently BKM12-21), solved here.
  The proportionality factor follows as ``mu = m1 + c1 Z~`` (BKM12-18, corrected).
* :func:`chaplygin_map` — the orthogonality ``(M~, gamma~) = 0`` is a quadratic in
  ``f = k tan(phi)`` (``k^2 = E D``); with the normalisations ``(M~, M~) = C``,
  ``(gamma~, gamma~) = 1`` this gives the coefficients (BKM12-22, 23) in closed form.
* :func:`kilin_map` — the same transformation in Kilin's form (K01-2.29 ... 2.33): old
  vectors in terms of new ones, with ``(gamma~, gamma~) = 1`` and ``(M~, gamma~) = 0``.
* :func:`proposition2` — the spherical support (BKM12-49 ... 55): the Gram matrix
  ``Gamma`` of ``M, alpha, beta``, the metric ``g``, the generalised eigenproblem
  ``Gamma v = lam g v`` (``B = g^-1 Gamma``), its characteristic cubic and eigen-rows.
* :func:`theorem2_scalars` — the 2x2 ``X`` of BKM12-48 and the transformed ``X~, Y~`` as
  functions of ``X, Y`` and the coefficients, derived by bilinearity.

References
----------
BKM12-12 ... BKM12-23, BKM12-proofT1, BKM12-RemT1, BKM12-1.4a, K01-2.29 ... K01-2.33,
BKM12-43 ... BKM12-55, BKM12-T2, BKM12-2.4Rem (FORMULAS.md §1.3, §1.4, §1.8-1.10, §2.3).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from .algebra import seeded_factor

__all__ = [
    "Theorem1",
    "theorem1",
    "ChaplyginMap",
    "chaplygin_map",
    "chaplygin_phi_form",
    "KilinMap",
    "kilin_map",
    "Proposition2",
    "proposition2",
    "theorem2_scalars",
    "gram_orthogonal_rows",
]


# ------------------------------------------------------------------ Theorem 1
@dataclass(frozen=True)
class Theorem1:
    """The conditions of Theorem 1 derived on the energy level (scalars as symbols).

    Attributes
    ----------
    symbols : dict of str to sympy.Symbol
        ``X, Y, E, D, Dt, m1, m2, c1, c2`` (``Dt`` is ``D~``).
    X_t, Y_t : sympy.Expr
        ``X~ = D~^-1 - (gamma~, A gamma~)`` and ``Y~ = (A M~, gamma~)`` in ``X, Y, E``
        (BKM12-17), from bilinearity and ``(A M, M) = E - Y^2/X``, ``(gamma, A gamma) = D^-1 - X``.
    factor : sympy.Expr
        ``(m1 + c1 Z~) Z - (m2 + c2 Z~)``, ``Z = Y/X``, ``Z~ = Y~/X~``: every minor of
        ``[omega~, omega]`` is ``A_i A_j (M_i gamma_j - M_j gamma_i)`` times it.
    numerator : sympy.Poly
        ``X^2 X~ * factor`` as a polynomial in ``X, Y``.
    conditions : list of sympy.Expr
        Its coefficients: they vanish iff ``omega~ || omega`` on the whole level.
    R1, R2 : sympy.Expr
        BKM12-14: ``R1 = m2/D~ + E c1 Delta``, ``R2 = m1/D~ - c2 Delta/D``,
        ``Delta = m1 c2 - m2 c1``;
        ``numerator = X (R2 Y - R1 X)`` (BKM12-proofT1).
    solution : dict
        The conditions solved for ``m2`` and ``D~`` (BKM12-21).
    mu : sympy.Expr
        ``m1 + c1 Z~`` (BKM12-18, corrected): ``omega~ = mu omega``.
    """

    symbols: dict
    X_t: sp.Expr
    Y_t: sp.Expr
    factor: sp.Expr
    numerator: sp.Poly
    conditions: list
    R1: sp.Expr
    R2: sp.Expr
    solution: dict
    mu: sp.Expr


def _bilinear(u: tuple, v: tuple, gram: dict) -> sp.Expr:
    """``(u, A v)`` for ``u = u0 M + u1 gamma`` ... from the Gram values ``gram[(i, j)]``."""
    return sp.expand(
        sum(u[i] * v[j] * gram[(min(i, j), max(i, j))] for i in range(2) for j in range(2))
    )


@lru_cache(maxsize=1)
def theorem1() -> Theorem1:
    """Derive the conditions of BKM12 Theorem 1 (see :class:`Theorem1`).

    Cached: the derivation runs once per process.

    Returns
    -------
    Theorem1
        The conditions, their solution for ``m2`` and ``D~``, and ``mu``.

    Raises
    ------
    RuntimeError
        When the conditions do not have exactly one solution (a derivation failure).

    References
    ----------
    BKM12-14, BKM12-17, BKM12-proofT1, BKM12-18, BKM12-21.
    """
    X, Y = sp.symbols("X Y")
    E, D, Dt = sp.symbols("E D Dt", positive=True)
    m1, m2, c1, c2 = sp.symbols("m1 m2 c1 c2")
    # A-Gram matrix of (M, gamma) on the level 2H = E: E = (M, A M) + Z (A M, gamma), Z = Y/X
    gram = {(0, 0): E - Y**2 / X, (0, 1): Y, (1, 1): 1 / D - X}
    m, c = (m1, m2), (c1, c2)
    X_t = 1 / Dt - _bilinear(c, c, gram)
    Y_t = _bilinear(m, c, gram)
    Z, Z_t = Y / X, Y_t / X_t
    factor = (m1 + c1 * Z_t) * Z - (m2 + c2 * Z_t)
    numerator = sp.Poly(
        sp.expand(X * ((m1 * X_t + c1 * Y_t) * Y - X * (m2 * X_t + c2 * Y_t))), X, Y
    )
    conditions = [seeded_factor(co) for _, co in numerator.terms()]
    sol = sp.solve(conditions, [m2, Dt], dict=True)
    if len(sol) != 1:  # pragma: no cover - a derivation failure, not user input
        raise RuntimeError(f"Theorem 1: unexpected solutions {sol}")
    Delta = m1 * c2 - m2 * c1
    R1 = m2 / Dt + E * c1 * Delta
    R2 = m1 / Dt - c2 * Delta / D
    syms = dict(X=X, Y=Y, E=E, D=D, Dt=Dt, m1=m1, m2=m2, c1=c1, c2=c2)
    return Theorem1(syms, X_t, Y_t, factor, numerator, conditions, R1, R2, sol[0], m1 + c1 * Z_t)


# ------------------------------------------------------------------ Chaplygin's map
@dataclass(frozen=True)
class ChaplyginMap:
    """Chaplygin's coefficients (BKM12-22, 23) in the scalars ``E, D, C, Mg``.

    ``M~ = m1 M + m2 gamma``, ``gamma~ = c1 M + c2 gamma``; ``f = k tan(phi)``, ``k^2 = E D``:
    ``m2 = -f m1``, ``c2 = k^2 c1 / f`` (any ``f`` satisfies BKM12-21 with
    ``D~^-1 = E c1^2 + c2^2/D``); ``(M~, gamma~) = 0`` is the quadratic
    ``Mg f^2 - (C - E D) f - E D Mg = 0`` (``orthogonality``).

    Attributes
    ----------
    symbols : dict
        ``E, D, C, Mg, f``.
    orthogonality : sympy.Expr
        ``(M - f gamma, f M + E D gamma)`` from the Gram matrix of ``M, gamma``.
    roots : tuple of sympy.Expr
        Both roots ``f``; ``roots[0]`` is the one that tends to ``0`` as ``Mg -> 0``
        when ``C > E D`` (the map tends to the identity), written without cancellation.
    m1, m2, c1, c2, Dt_inv, Et : sympy.Expr
        In terms of ``f`` (and ``E, D, C, Mg``); ``Et = E~ = E m1^2 + m2^2/D``.
    """

    symbols: dict
    orthogonality: sp.Expr
    roots: tuple
    m1: sp.Expr
    m2: sp.Expr
    c1: sp.Expr
    c2: sp.Expr
    Dt_inv: sp.Expr
    Et: sp.Expr


@lru_cache(maxsize=1)
def chaplygin_map() -> ChaplyginMap:
    """Derive Chaplygin's coefficients (see :class:`ChaplyginMap`).

    Cached: the derivation runs once per process.

    Returns
    -------
    ChaplyginMap
        The orthogonality quadratic, both roots ``f`` and the coefficients in ``f``.

    Raises
    ------
    RuntimeError
        When the orthogonality condition does not have two roots (a derivation failure).

    References
    ----------
    BKM12-1.4a, BKM12-22, BKM12-23, K01-2.32.
    """
    E, D, C = sp.symbols("E D C", positive=True)
    Mg, f = sp.symbols("Mg f", real=True)
    k2 = E * D
    gram = {(0, 0): C, (0, 1): Mg, (1, 1): sp.S.One}  # Euclidean Gram matrix of (M, gamma)
    ortho = _bilinear((1, -f), (f, k2), gram)
    roots = sp.solve(ortho, f)
    if len(roots) != 2:  # pragma: no cover
        raise RuntimeError(f"Chaplygin's orthogonality: roots {roots}")
    # the root that vanishes with Mg, without cancellation: f = -2 k^2 Mg / ((C-k^2) + sqrt(S))
    S = sp.expand((C - k2) ** 2 + 4 * k2 * Mg**2)
    f_small = -2 * k2 * Mg / ((C - k2) + sp.sqrt(S))
    f_other = ((C - k2) + sp.sqrt(S)) / (2 * Mg)
    for r in (f_small, f_other):  # they are the roots just found
        assert sp.simplify(ortho.subs(f, r)) == 0
    norm_M = _bilinear((1, -f), (1, -f), gram)  # |M - f gamma|^2
    norm_g = _bilinear((f, k2), (f, k2), gram)  # |f M + k^2 gamma|^2
    m1 = sp.sqrt(C) / sp.sqrt(norm_M)
    m2 = -f * m1
    c1 = f / sp.sqrt(norm_g)
    c2 = k2 / sp.sqrt(norm_g)
    Dt_inv = sp.simplify(E * c1**2 + c2**2 / D)
    Et = sp.simplify(E * m1**2 + m2**2 / D)
    syms = dict(E=E, D=D, C=C, Mg=Mg, f=f)
    return ChaplyginMap(syms, ortho, (f_small, f_other), m1, m2, c1, c2, Dt_inv, Et)


def chaplygin_phi_form() -> dict[str, sp.Expr]:
    """BKM12-22/23 as printed: coefficients in ``phi, k, rho, sigma`` and ``tan(2 phi)``.

    Returns
    -------
    dict
        ``phi, k, C, Mg`` symbols; ``m1, m2, c1, c2`` (BKM12-1.4a); ``rho, sigma`` (BKM12-23);
        ``tan2phi`` (BKM12-23) and ``ortho`` = ``(M~, gamma~)/(rho sigma)`` from the Gram
        matrix, so that ``ortho = 0`` iff ``tan(2 phi) = tan2phi``.
    """
    phi = sp.Symbol("phi", real=True)
    k, C = sp.symbols("k C", positive=True)
    Mg = sp.Symbol("Mg", real=True)
    c, s = sp.cos(phi), sp.sin(phi)
    rho = sp.sqrt(C) * (C * c**2 + k**2 * s**2 - 2 * k * Mg * s * c) ** sp.Rational(-1, 2)
    sigma = (C * s**2 + k**2 * c**2 + 2 * k * Mg * c * s) ** sp.Rational(-1, 2)
    gram = {(0, 0): C, (0, 1): Mg, (1, 1): sp.S.One}
    ortho = _bilinear((c, -k * s), (s, k * c), gram)
    return dict(
        phi=phi,
        k=k,
        C=C,
        Mg=Mg,
        rho=rho,
        sigma=sigma,
        m1=rho * c,
        m2=-k * rho * s,
        c1=sigma * s,
        c2=k * sigma * c,
        tan2phi=-2 * k * Mg / (C - k**2),
        ortho=ortho,
    )


# ------------------------------------------------------------------ Kilin's form
@dataclass(frozen=True)
class KilinMap:
    """K01 §2.3: ``M = mu gamma~ + nu M~``, ``gamma = kap gamma~ + lam M~`` (letters renamed).

    K01 notation: ``n = (M, M)``, ``C = (M, gamma)``, ``h`` the energy (``E = 2h``).

    Attributes
    ----------
    symbols : dict
        ``n, C, h, D, f``.
    quadratic : sympy.Expr
        K01-2.32: ``f^2 - ((n - 2 h D)/C) f - 2 h D`` (= ChaplyginMap.orthogonality / C).
    mu, nu, kap, lam, Q, n1, h1, Dt : sympy.Expr
        K01-2.32, 2.33 (``Dt = D~``).
    inverse : sympy.Matrix
        ``[[a, b], [c, d]]`` with ``M~ = a M + b gamma``, ``gamma~ = c M + d gamma``.
    """

    symbols: dict
    quadratic: sp.Expr
    mu: sp.Expr
    nu: sp.Expr
    kap: sp.Expr
    lam: sp.Expr
    Q: sp.Expr
    n1: sp.Expr
    h1: sp.Expr
    Dt: sp.Expr
    inverse: sp.Matrix


@lru_cache(maxsize=1)
def kilin_map() -> KilinMap:
    """Kilin's form of the transformation; the inverse is derived (see :class:`KilinMap`).

    Cached: the derivation runs once per process.

    Returns
    -------
    KilinMap
        K01's coefficients in ``n, C, h, D, f`` and the inverse matrix.

    References
    ----------
    K01-2.29, K01-2.30, K01-2.32, K01-2.33.
    """
    n, h, D = sp.symbols("n h D", positive=True)
    C, f = sp.symbols("C f", real=True)
    Q = n - C**2 + (C - f) ** 2
    kap = sp.sqrt((n - C**2) / Q)
    mu = f * kap
    lam = (C - f) / sp.sqrt(n - C**2)
    nu = (n - C * f) / sp.sqrt(n - C**2)
    old = sp.Matrix([[nu, mu], [lam, kap]])  # (M, gamma) = old * (M~, gamma~)
    inverse = old.inv().applyfunc(sp.simplify)
    return KilinMap(
        symbols=dict(n=n, C=C, h=h, D=D, f=f),
        quadratic=f**2 - (n - 2 * h * D) / C * f - 2 * h * D,
        mu=mu,
        nu=nu,
        kap=kap,
        lam=lam,
        Q=Q,
        n1=(n - C**2) / Q,
        h1=h * (n - C**2) / ((n - C * f) * Q),
        Dt=f * (n - C**2) / (2 * h * (f - C)),
        inverse=inverse,
    )


# ------------------------------------------------------------------ spherical support
def gram_orthogonal_rows(g: sp.Matrix, a: sp.Matrix, w: sp.Matrix) -> sp.Matrix:
    """Rows ``m, a, b`` mutually orthogonal for the metric ``<x, y> = x^T g y`` (rational).

    ``b = g^-1 (a x w)``, ``m = g^-1 (a x b)``: ``<a, b> = a . (a x w) = 0`` and
    ``<m, a> = <m, b> = 0``. Every g-orthogonal triple with ``a`` first is of this form up
    to the scale of ``m`` (BKM12-47's hypothesis without square roots).

    Parameters
    ----------
    g : sympy.Matrix, shape (3, 3)
        Symmetric invertible metric.
    a : sympy.Matrix, shape (3, 1)
        The second row.
    w : sympy.Matrix, shape (3, 1)
        Free vector that fixes ``b`` (any vector not parallel to ``a``).

    Returns
    -------
    sympy.Matrix, shape (3, 3)
        Rows ``m^T, a^T, b^T``.

    References
    ----------
    BKM12-47
    """
    from .vectors import cross

    gi = g.inv()
    b = gi * cross(a, w)
    m = gi * cross(a, b)
    return sp.Matrix.vstack(m.T, a.T, b.T)


@dataclass(frozen=True)
class Proposition2:
    """BKM12 Proposition 2 for the support: ``Gamma v = lam g v``.

    Attributes
    ----------
    symbols : dict
        ``E, C, M_al, M_be, D_al, D_be, lam``.
    Gamma, g : sympy.Matrix
        BKM12-50.
    B : sympy.Matrix
        ``g^-1 Gamma`` (BKM12-51).
    cubic : sympy.Expr
        BKM12-55, derived as ``-D_al D_be det(Gamma - lam g)``.
    row : sympy.Matrix
        The eigen-row for the root ``lam`` (first entry 1, BKM12-54), solved from the
        second and third equations of ``(Gamma - lam g) v = 0``.
    """

    symbols: dict
    Gamma: sp.Matrix
    g: sp.Matrix
    B: sp.Matrix
    cubic: sp.Expr
    row: sp.Matrix


@lru_cache(maxsize=1)
def proposition2() -> Proposition2:
    """Derive BKM12-50 ... 55 (see :class:`Proposition2`).

    Cached: the derivation runs once per process.

    Returns
    -------
    Proposition2
        ``Gamma``, ``g``, ``B``, the cubic and the eigen-row.

    References
    ----------
    BKM12-49 ... BKM12-55.
    """
    E, C, D_al, D_be = sp.symbols("E C D_al D_be", positive=True)
    M_al, M_be, lam = sp.symbols("M_al M_be lam", real=True)
    Gamma = sp.Matrix([[C, M_al, M_be], [M_al, 1, 0], [M_be, 0, 1]])
    g = sp.diag(E, 1 / D_al, 1 / D_be)
    cubic = sp.expand(-D_al * D_be * (Gamma - lam * g).det())
    v2, v3 = sp.symbols("v2 v3")
    eqs = ((Gamma - lam * g) * sp.Matrix([1, v2, v3]))[1:, 0]
    sol = sp.solve(list(eqs), [v2, v3], dict=True)[0]
    row = sp.Matrix([[1, seeded_factor(sol[v2]), seeded_factor(sol[v3])]])
    syms = dict(E=E, C=C, M_al=M_al, M_be=M_be, D_al=D_al, D_be=D_be, lam=lam)
    return Proposition2(syms, Gamma, g, g.inv() * Gamma, cubic, row)


def theorem2_scalars(
    Q: sp.Matrix,
    X: sp.Matrix,
    Y: sp.Matrix,
    E: sp.Expr,
    Dt_inv: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr],
) -> dict[str, sp.Matrix]:
    """``X~`` (2x2) and ``Y~`` of BKM12-48 from ``X``, ``Y`` and the coefficients, by bilinearity.

    The A-Gram matrix of ``(M, alpha, beta)`` on the level ``2H = E`` is
    ``[[E - (Y, X^-1 Y), Y^T], [Y, diag(D_al^-1, D_be^-1) - X]]`` (``(A M, M) = E - (Y, X^-1 Y)``,
    ``X = diag(D^-1) - ((alpha, beta), A (alpha, beta))``).

    Parameters
    ----------
    Q : sympy.Matrix
        Rows ``m, a, b`` (coefficients of ``M~, alpha~, beta~`` in ``M, alpha, beta``).
    X : sympy.Matrix
        2x2, BKM12-34; its diagonal carries ``D_al^-1, D_be^-1`` through ``Dd_inv``.
    Y : sympy.Matrix
        ``((A M, alpha), (A M, beta))``.
    E : sympy.Expr
        Twice the energy.
    Dt_inv : (sympy.Expr, sympy.Expr, sympy.Expr, sympy.Expr)
        ``(D_al^-1, D_be^-1, D_al~^-1, D_be~^-1)``.

    Returns
    -------
    dict
        ``X_t`` (2x2), ``Y_t`` (2x1), ``Gram`` (3x3 A-Gram matrix used).

    References
    ----------
    BKM12-48, BKM12-T2
    """
    dal, dbe, tal, tbe = Dt_inv
    YXY = (Y.T * X.inv() * Y)[0, 0]
    G = sp.zeros(3, 3)
    G[0, 0] = E - YXY
    G[0, 1] = G[1, 0] = Y[0]
    G[0, 2] = G[2, 0] = Y[1]
    G[1:, 1:] = sp.diag(dal, dbe) - X
    T = Q * G * Q.T  # A-Gram matrix of (M~, alpha~, beta~)
    X_t = sp.diag(tal, tbe) - T[1:, 1:]
    Y_t = T[0, 1:].T
    return dict(X_t=X_t, Y_t=Y_t, Gram=G)
