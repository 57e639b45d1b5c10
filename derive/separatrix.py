"""The separatrix on M || gamma at the energy of the middle axis, and its displacement Delta.

K01 §3.3. On the invariant set ``M = C gamma`` (K01-2.34) ``J omega = l gamma``,
``l = C + 2 D h/C``, and ``gamma`` obeys the Euler equations of a free top with inertia
``J = I + D Id``: ``gamma' = l gamma x J^-1 gamma``. At ``h = h2 = C^2/(2 I2)`` (K01-3.3seg)
``l = C J2/I2`` and ``gamma`` runs along a separatrix of that top. Everything here is
derived with sympy, step by step:

1. :func:`separatrix_gamma` solves the two quadrics of the Euler top for ``gamma1^2``,
   ``gamma3^2`` in terms of ``gamma2`` and the remaining Riccati equation
   ``gamma2' = lam (1 - gamma2^2)`` with ``sympy.dsolve`` (``gamma2 = tanh(lam t)``).
2. :func:`separatrix_frame` writes the space-fixed horizontal frame as
   ``alpha = cos(phi) T + sin(phi) N`` (``T`` the unit tangent of ``gamma(t)``,
   ``N = T x gamma``), ``beta = gamma x alpha``, and solves ``alpha' = alpha x omega`` for
   ``phi'``: a constant, ``kap = C/I2``.
3. :func:`contact_velocity` gives ``x' = b (beta, omega)``, ``y' = -b (alpha, omega)`` on the
   solution: ``nu cos(kap t)/ch(lam t)``, ``nu sin(kap t)/ch(lam t)``, ``nu = b lam`` (K01-3.5).
4. :func:`sech_fourier_integral` evaluates ``int cos(k s)/ch(s) ds`` over the real line by
   the residue theorem on the rectangle ``0 <= Im z <= pi`` (sympy's ``residue`` and
   ``limit``), so ``Delta = b pi/ch(pi xi/2)``, ``xi = kap/lam = 1/(J2 sqrt(a21 a32))``
   (K01-3.6, 3.7; the issue calls ``xi`` ``mu``).

The hyperbolic functions are written in ``q = exp(-lam t)``:
``th(lam t) = (1 - q^2)/(1 + q^2)``, ``1/ch(lam t) = 2 q/(1 + q^2)``, ``d/dt = -lam q d/dq``,
so every residual is rational in ``q`` and in ``cos(phi), sin(phi)``, ``phi = kap t``.

Sign conventions (``I1 < I2 < I3``, so ``J1 < J2 < J3``): ``d21 = 1/J1 - 1/J2 > 0``,
``d32 = 1/J2 - 1/J3 > 0``, ``d31 = d21 + d32``; K01's ``a_ij = 1/J_i - 1/J_j`` gives
``a21 a32 = d21 d32`` and ``s32 = sqrt(a32/a31) = sqrt(d32/d31)``,
``s21 = sqrt(d21/d31)``.

References
----------
K01-2.34, K01-3.3seg, K01-3.4, K01-3.5, K01-3.6, K01-3.7 (FORMULAS.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from .algebra import seeded_factor
from .vectors import cross, dot

__all__ = [
    "SeparatrixSymbols",
    "Separatrix",
    "separatrix_symbols",
    "separatrix_gamma",
    "separatrix_frame",
    "contact_velocity",
    "sech_fourier_integral",
    "derive_separatrix",
    "hyperbolic_in_q",
    "delta_closed_form",
]


@dataclass(frozen=True)
class SeparatrixSymbols:
    """Symbols of the derivation (all positive: ``I1 < I2 < I3``, ``C > 0``)."""

    I1: sp.Symbol
    I2: sp.Symbol
    I3: sp.Symbol
    D: sp.Symbol
    b: sp.Symbol
    C: sp.Symbol
    q: sp.Symbol  # exp(-lam t)
    phi: sp.Symbol  # kap t
    t: sp.Symbol

    @property
    def J(self) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        """Moments about the contact point, ``J_i = I_i + D``.

        Returns
        -------
        tuple of three sympy.Expr
            ``(J1, J2, J3)``.
        """
        return (self.I1 + self.D, self.I2 + self.D, self.I3 + self.D)

    @property
    def d21(self) -> sp.Expr:
        """``d21 = 1/J1 - 1/J2`` (positive).

        Returns
        -------
        sympy.Expr
            ``d21`` in ``I1, I2, D``.
        """
        J1, J2, _ = self.J
        return 1 / J1 - 1 / J2

    @property
    def d32(self) -> sp.Expr:
        """``d32 = 1/J2 - 1/J3`` (positive).

        Returns
        -------
        sympy.Expr
            ``d32`` in ``I2, I3, D``.
        """
        _, J2, J3 = self.J
        return 1 / J2 - 1 / J3

    @property
    def d31(self) -> sp.Expr:
        """``d31 = d21 + d32 = 1/J1 - 1/J3``.

        Returns
        -------
        sympy.Expr
            ``d31`` in ``I1, I2, I3, D``.
        """
        return self.d21 + self.d32


def separatrix_symbols() -> SeparatrixSymbols:
    """Fresh positive symbols ``I1, I2, I3, D, b, C, q`` and real ``phi, t``.

    Returns
    -------
    SeparatrixSymbols
        New symbols (sympy caches them by name and assumptions, so repeated calls
        give equal symbols).
    """
    I1, I2, I3, D, b, C, q = sp.symbols("I1 I2 I3 D b C q", positive=True)
    phi, t = sp.symbols("phi t", real=True)
    return SeparatrixSymbols(I1, I2, I3, D, b, C, q, phi, t)


def hyperbolic_in_q(q: sp.Symbol) -> tuple[sp.Expr, sp.Expr]:
    """``(th(lam t), 1/ch(lam t))`` as rational functions of ``q = exp(-lam t)``.

    Parameters
    ----------
    q : sympy.Symbol
        Stands for ``exp(-lam t)``.

    Returns
    -------
    (th, sech) : tuple of two sympy.Expr
        ``(1 - q^2)/(1 + q^2)`` and ``2 q/(1 + q^2)``.
    """
    return (1 - q**2) / (1 + q**2), 2 * q / (1 + q**2)


@dataclass
class Separatrix:
    """The derived separatrix (C > 0, ``sigma`` = the branch ``sign gamma1(0)``).

    Attributes
    ----------
    symbols : SeparatrixSymbols
    l : sympy.Expr
        ``C + 2 D h2/C = C J2/I2``.
    lam, kap : sympy.Expr
        ``lam = l sqrt(d21 d32)``, ``kap = C/I2``.
    s32, s21 : sympy.Expr
    gamma, alpha, beta, omega : sympy.Matrix
        In ``q`` and ``phi`` (and the parameters); ``omega = l J^-1 gamma``.
    x_rate, y_rate : sympy.Expr
        ``b (beta, omega)``, ``-b (alpha, omega)``.
    nu : sympy.Expr
        ``x_rate = nu cos(phi)/ch(lam t)``.
    xi : sympy.Expr
        ``kap/lam``.
    delta : sympy.Expr
        ``nu int cos(kap t)/ch(lam t) dt``, from the residue computation.
    """

    symbols: SeparatrixSymbols
    l: sp.Expr  # K01's letter
    lam: sp.Expr
    kap: sp.Expr
    s32: sp.Expr
    s21: sp.Expr
    gamma: sp.Matrix
    alpha: sp.Matrix
    beta: sp.Matrix
    omega: sp.Matrix
    x_rate: sp.Expr
    y_rate: sp.Expr
    nu: sp.Expr
    xi: sp.Expr
    delta: sp.Expr
    steps: dict


def separatrix_gamma(S: SeparatrixSymbols, sigma: int = -1) -> dict[str, object]:
    """Step 1: ``gamma(t)`` on the separatrix from the Euler top ``gamma' = l gamma x J^-1 gamma``.

    Parameters
    ----------
    S : SeparatrixSymbols
        Symbols to derive with.
    sigma : {-1, 1}
        The branch: ``sign gamma1 = sign gamma3 = sigma`` (both branches are separatrices;
        ``-1`` is the form of FORMULAS.md's corrected K01-3.4).

    Returns
    -------
    dict
        ``l``, ``lam``, ``s32``, ``s21``, ``gamma`` (in ``q``), ``gamma2_t`` (the dsolve
        solution in ``t``), ``quadric_solution``.
    """
    J1, J2, J3 = S.J
    h2 = S.C**2 / (2 * S.I2)  # K01-3.3seg: the segment meets p2 there
    l = sp.simplify(S.C + 2 * S.D * h2 / S.C)  # K01-2.34
    g1, g2, g3 = sp.symbols("g1 g2 g3", real=True)
    g = sp.Matrix([g1, g2, g3])
    Jinv = sp.diag(1 / J1, 1 / J2, 1 / J3)
    # the two integrals of the top in x = J omega = l gamma: |x|^2 = l^2 and
    # (x, J^-1 x) = 2 h l / C = l^2/J2 at h = h2
    quadrics = [dot(g, g) - 1, dot(g, Jinv * g) - sp.simplify(2 * h2 * l / S.C) / l**2]
    sol = sp.solve(quadrics, [g1**2, g3**2], dict=True)[0]
    one_minus = 1 - g2**2
    r1 = seeded_factor(sp.simplify(sol[g1**2] / one_minus))
    r3 = seeded_factor(sp.simplify(sol[g3**2] / one_minus))
    s32 = sp.sqrt(S.d32 / S.d31)
    s21 = sp.sqrt(S.d21 / S.d31)
    assert sp.simplify(r1 - s32**2) == 0 and sp.simplify(r3 - s21**2) == 0
    # gamma1 = sigma s32 sqrt(1 - g2^2), gamma3 = sigma s21 sqrt(1 - g2^2); the middle
    # Euler equation gamma2' = l (1/J1 - 1/J3) gamma3 gamma1 becomes a Riccati equation
    rhs = sp.simplify(l * (1 / J1 - 1 / J3) * s32 * s21)  # times sigma^2 (1 - g2^2)
    lam = sp.simplify(rhs)
    T = sp.Function("g2")
    L = sp.Symbol("lam", positive=True)  # lam > 0 is checked in the claims (sampled)
    ode = sp.Eq(T(S.t).diff(S.t), L * (1 - T(S.t) ** 2))
    general = sp.dsolve(ode, T(S.t)).rhs
    (c1,) = general.free_symbols - {S.t, L}
    # the constant from gamma2(0) = 0 (sympy offers both +-i pi/2: the same function)
    roots = sp.solve(general.subs(S.t, 0), c1)
    g2_t = general.subs(c1, roots[0])
    th, sech = hyperbolic_in_q(S.q)
    # dsolve's solution at exp(-lam t) = q is the q-form's th
    check = sp.simplify(g2_t.rewrite(sp.exp).subs(S.t, -sp.log(S.q) / L) - th)
    g2_t = g2_t.subs(L, lam)
    if check != 0:
        raise AssertionError(f"dsolve's solution is not tanh(lam t): {g2_t}")
    gamma = sp.Matrix([sigma * s32 * sech, th, sigma * s21 * sech])
    return {
        "l": l,
        "lam": lam,
        "s32": s32,
        "s21": s21,
        "gamma": gamma,
        "gamma2_t": g2_t,
        "quadric_solution": {"gamma1^2/(1-gamma2^2)": r1, "gamma3^2/(1-gamma2^2)": r3},
    }


def _simplify_vec(v: sp.Matrix) -> sp.Matrix:
    return v.applyfunc(lambda e: seeded_factor(sp.simplify(e)))


def separatrix_frame(
    S: SeparatrixSymbols, step1: dict[str, object]
) -> dict[str, sp.Expr | sp.Matrix]:
    """Step 2: the space-fixed frame ``alpha, beta`` along the separatrix.

    ``alpha = cos(phi) T + sin(phi) N``, ``T = gamma'/|gamma'|``, ``N = T x gamma``;
    ``alpha' = alpha x omega`` is solved for ``phi'`` (it comes out constant, ``kap``).

    Parameters
    ----------
    S : SeparatrixSymbols
        Symbols of the derivation.
    step1 : dict
        The result of :func:`separatrix_gamma` (``gamma``, ``lam``, ``l`` are used).

    Returns
    -------
    dict
        ``omega`` (``l J^-1 gamma``), ``T``, ``N``, ``kap``, ``alpha``, ``beta``: sympy
        matrices of shape (3, 1) in ``q`` and ``phi``, and ``kap`` a sympy.Expr.

    Raises
    ------
    AssertionError
        When the projected equation does not determine ``phi'`` uniquely.

    References
    ----------
    K01-3.4
    """
    J1, J2, J3 = S.J
    gamma, lam, l = step1["gamma"], step1["lam"], step1["l"]
    omega = l * sp.diag(1 / J1, 1 / J2, 1 / J3) * gamma
    # Euler equations hold for gamma(q): gamma' = gamma x omega (checked by the caller)
    dgamma = gamma.applyfunc(lambda e: -lam * S.q * sp.diff(e, S.q))
    th, sech = hyperbolic_in_q(S.q)
    T = _simplify_vec(dgamma / (lam * sech))  # |gamma'| = lam sech
    N = _simplify_vec(cross(T, gamma))
    w = sp.Symbol("w")  # phi'
    alpha = sp.cos(S.phi) * T + sp.sin(S.phi) * N
    dalpha = alpha.applyfunc(lambda e: -lam * S.q * sp.diff(e, S.q) + w * sp.diff(e, S.phi))
    res = dalpha - cross(alpha, omega)
    # project on N at phi = 0 (alpha = T there): (res, N) = w - (something)
    eq = sp.simplify(dot(res, N).subs(S.phi, 0))
    sol = sp.solve(eq, w)
    if len(sol) != 1:
        raise AssertionError(f"phi' not determined: {sol}")
    kap = sp.simplify(sol[0])
    beta = cross(gamma, alpha)
    return {
        "omega": omega,
        "T": T,
        "N": N,
        "kap": kap,
        "alpha": _simplify_vec(alpha),
        "beta": _simplify_vec(beta),
    }


def contact_velocity(
    S: SeparatrixSymbols,
    alpha: sp.Matrix,
    beta: sp.Matrix,
    omega: sp.Matrix,
    lam: sp.Expr,
) -> dict[str, sp.Expr]:
    """Step 3: ``x' = b (beta, omega)``, ``y' = -b (alpha, omega)`` (BKM12-6) and ``nu``.

    Parameters
    ----------
    S : SeparatrixSymbols
        Symbols of the derivation.
    alpha, beta, omega : sympy.Matrix, shape (3, 1)
        Frame and angular velocity along the separatrix (:func:`separatrix_frame`).
    lam : sympy.Expr
        Rate of the separatrix (unused: the rates are written in ``q``).

    Returns
    -------
    dict
        ``x_rate``, ``y_rate`` (sympy.Expr in ``q`` and ``phi``) and ``nu`` with
        ``x_rate = nu cos(phi)/ch(lam t)``, ``y_rate = nu sin(phi)/ch(lam t)``.

    Raises
    ------
    AssertionError
        When the rates are not of that form.

    References
    ----------
    BKM12-6, K01-3.5
    """
    _, sech = hyperbolic_in_q(S.q)
    x_rate = sp.simplify(S.b * dot(beta, omega))
    y_rate = sp.simplify(-S.b * dot(alpha, omega))
    nu = sp.simplify(x_rate / (sp.cos(S.phi) * sech))
    if nu.has(S.q) or nu.has(S.phi):
        raise AssertionError(f"x' is not nu cos(phi) sech: {x_rate}")
    if sp.simplify(y_rate - nu * sp.sin(S.phi) * sech) != 0:
        raise AssertionError(f"y' is not nu sin(phi) sech: {y_rate}")
    return {"x_rate": x_rate, "y_rate": y_rate, "nu": seeded_factor(nu)}


@lru_cache(maxsize=1)
def sech_fourier_integral() -> tuple[sp.Symbol, sp.Expr, dict[str, sp.Expr]]:
    """``F(k) = int_{-oo}^{oo} cos(k s)/ch(s) ds`` by residues, derived with sympy.

    ``f(z) = exp(i k z)/ch(z)``; on the rectangle ``[-R, R] x [0, pi]`` the top side is
    ``-exp(-k pi)`` times the bottom one (``ch(z + i pi) = -ch(z)``), the vertical sides
    vanish as ``R -> oo`` (``|f| <= exp(|k| pi)/sh(R)``, the limit is taken by sympy), and
    the only pole inside is ``z = i pi/2``. So ``(1 + exp(-k pi)) F = 2 pi i Res``.

    Returns
    -------
    k : sympy.Symbol
    F : sympy.Expr
        ``pi/ch(pi k/2)``.
    steps : dict
        The residue, the side bound's limit, the pole check.
    """
    k = sp.Symbol("k", real=True)
    z = sp.Symbol("z")
    R = sp.Symbol("R", positive=True)
    f = sp.exp(sp.I * k * z) / sp.cosh(z)
    pole = sp.I * sp.pi / 2
    # the poles of 1/ch are i pi (1/2 + n); only n = 0 lies in 0 < Im z < pi
    assert sp.simplify(sp.cosh(pole)) == 0
    assert sp.simplify(sp.cosh(pole + sp.I * sp.pi)) == 0  # on no side: Im = 3 pi/2
    # top side: f(x + i pi) = -exp(-k pi) f(x)
    x = sp.Symbol("x", real=True)
    shift = sp.simplify((f.subs(z, x + sp.I * sp.pi) / f.subs(z, x)).rewrite(sp.exp))
    assert sp.simplify(shift + sp.exp(-k * sp.pi)) == 0
    res = sp.simplify(sp.residue(f, z, pole))
    side_bound = sp.exp(sp.Abs(k) * sp.pi) * sp.pi / sp.sinh(R)
    side_limit = sp.limit(side_bound, R, sp.oo)
    assert side_limit == 0
    # the integral of f over the real line is F (sin(k s)/ch(s) is odd)
    F = sp.simplify(2 * sp.pi * sp.I * res / (1 + sp.exp(-k * sp.pi)))
    F = sp.simplify(F.rewrite(sp.cosh))
    target = sp.pi / sp.cosh(sp.pi * k / 2)
    if sp.simplify((F - target).rewrite(sp.exp)) != 0:
        raise AssertionError(f"residue computation gave {F}")
    return k, F, {"residue": res, "shift": shift, "side_limit": side_limit, "target": target}


@lru_cache(maxsize=2)
def derive_separatrix(sigma: int = -1) -> Separatrix:
    """Run steps 1-4 and return the separatrix with ``Delta`` in closed form.

    ``Delta = nu int cos(kap t)/ch(lam t) dt = (nu/lam) F(kap/lam)`` with ``F`` of
    :func:`sech_fourier_integral`. Cached per ``sigma``.

    Parameters
    ----------
    sigma : {-1, 1}, optional
        The branch ``sign gamma1(0)`` (see :func:`separatrix_gamma`).

    Returns
    -------
    Separatrix
        Every derived quantity, and the intermediate results in ``steps``.

    Raises
    ------
    AssertionError
        When a step's derived form is not the expected one.

    References
    ----------
    K01-3.4, K01-3.5, K01-3.6, K01-3.7
    """
    S = separatrix_symbols()
    one = separatrix_gamma(S, sigma)
    two = separatrix_frame(S, one)
    three = contact_velocity(S, two["alpha"], two["beta"], two["omega"], one["lam"])
    lam, kap = one["lam"], two["kap"]
    xi = sp.simplify(kap / lam)
    k, F, four = sech_fourier_integral()
    delta = sp.simplify(three["nu"] / lam * F.subs(k, xi))
    return Separatrix(
        symbols=S,
        l=one["l"],
        lam=lam,
        kap=kap,
        s32=one["s32"],
        s21=one["s21"],
        gamma=one["gamma"],
        alpha=two["alpha"],
        beta=two["beta"],
        omega=two["omega"],
        x_rate=three["x_rate"],
        y_rate=three["y_rate"],
        nu=three["nu"],
        xi=xi,
        delta=delta,
        steps={"gamma": one, "frame": two, "contact": three, "fourier": four},
    )


def delta_closed_form(xi: sp.Expr | float, b: sp.Expr | float) -> sp.Expr:
    """``Delta = pi b / ch(pi xi/2)`` (sympy).

    Parameters
    ----------
    xi : sympy.Expr or float
        ``kap/lam``.
    b : sympy.Expr or float
        Ball radius.

    Returns
    -------
    sympy.Expr
        The displacement ``Delta`` of the contact point along the separatrix.

    References
    ----------
    K01-3.6, K01-3.7
    """
    return sp.pi * b / sp.cosh(sp.pi * xi / 2)
