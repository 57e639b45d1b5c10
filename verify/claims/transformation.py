"""Claims of Chaplygin's transformation: BKM12 §1.3-1.4 (Theorem 1, (22)-(23)), K01 §2.3.

The coefficients and conditions come from :mod:`chaplygin.derive.transformation` (derived
there); the checks compare them with the papers' formulas on the ball's phase space. The
energy level ``2H = E`` is handled by taking ``E`` to be the model's energy
``(M, omega)`` of the state, so every residual is rational in the state (square roots
such as the discriminant of Chaplygin's quadratic are split off exactly).
"""

from __future__ import annotations

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.transformation import (
    chaplygin_map,
    chaplygin_phi_form,
    kilin_map,
    theorem1,
)
from chaplygin.derive.vectors import cross, dot

from ..identity import lie_derivative
from .base import Check, Claim, register
from .notation import ball_notation

__all__ = ["BallMap", "ball_map"]

BALL = "chaplygin_ball"
S13, S14, K23 = "BKM12 §1.3", "BKM12 §1.4", "K01 §2.3"

m1, m2, c1, c2, s_free = sp.symbols("m1 m2 c1 c2 s")
Dt = sp.Symbol("Dt", positive=True)


class BallMap:
    """The map ``M~ = m1 M + m2 gamma``, ``gamma~ = c1 M + c2 gamma`` on the ball's state.

    Parameters
    ----------
    model : Model
        A Chaplygin-ball model.
    coeffs : (m1, m2, c1, c2)
        Coefficients of the map (sympy expressions).
    Dt_inv : sympy.Expr
        ``D~^-1``.
    sign : int
        ``-1`` for the correct ``Z~ = (A M~, gamma~)/(D~^-1 - (gamma~, A gamma~))``,
        ``+1`` for the literal reading of BKM12-19.
    """

    def __init__(
        self,
        model: Model,
        coeffs: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr],
        Dt_inv: sp.Expr,
        sign: int = -1,
    ):
        n = ball_notation(model)
        self.n = n
        self.omega = model.expand_aux(n.omega)
        self.E = dot(n.M, self.omega)
        self.C = dot(n.M, n.M)
        self.Mg = dot(n.M, n.gamma)
        a1, a2, b1, b2 = coeffs
        self.coeffs = coeffs
        self.Mt = a1 * n.M + a2 * n.gamma
        self.gt = b1 * n.M + b2 * n.gamma
        self.Dt_inv = Dt_inv
        self.Zt = dot(n.A * self.Mt, self.gt) / (Dt_inv + sign * dot(self.gt, n.A * self.gt))
        self.omega_t = n.A * (self.Mt + self.Zt * self.gt)
        self.mu = a1 + b1 * self.Zt


def ball_map(
    model: Model,
    coeffs: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr],
    Dt_inv: sp.Expr,
    sign: int = -1,
) -> BallMap:
    """A :class:`BallMap` (E, C, Mg of the state available as attributes).

    Parameters
    ----------
    model : Model
        A Chaplygin-ball model.
    coeffs : (m1, m2, c1, c2)
        Coefficients of ``M~ = m1 M + m2 gamma``, ``gamma~ = c1 M + c2 gamma``.
    Dt_inv : sympy.Expr
        ``D~^-1``.
    sign : int, optional
        ``-1`` for the correct ``Z~``, ``+1`` for the literal reading of BKM12-19.

    Returns
    -------
    BallMap
        The transformed ``M~``, ``gamma~``, ``Z~``, ``omega~`` and ``mu`` in the state.

    References
    ----------
    BKM12-12, BKM12-19
    """
    return BallMap(model, coeffs, Dt_inv, sign)


def _energy(model: Model) -> sp.Expr:
    n = ball_notation(model)
    return dot(n.M, model.expand_aux(n.omega))


def _t1_coeffs(model: Model, violate: str = ""):
    """Coefficients satisfying (21) (derived solution), ``m1, c1, c2`` free; E of the state."""
    t = theorem1()
    E = _energy(model)
    n = ball_notation(model)
    sub = {
        t.symbols["E"]: E,
        t.symbols["D"]: n.D,
        t.symbols["m1"]: m1,
        t.symbols["c1"]: c1,
        t.symbols["c2"]: c2,
    }
    mm2 = t.solution[t.symbols["m2"]].xreplace(sub)
    Dt_inv = 1 / t.solution[t.symbols["Dt"]].xreplace(sub)
    if violate == "m2":
        mm2 = mm2 + c1
    elif violate == "Dt":
        Dt_inv = Dt_inv + 2 * c2**2 / n.D  # E c1^2 - ... replaced by E c1^2 + 3 c2^2/D
    return (m1, mm2, c1, c2), Dt_inv


def _scalars_sub(model: Model, bm: BallMap) -> dict:
    t = theorem1()
    n = bm.n
    X = 1 / n.D - dot(n.gamma, n.A * n.gamma)
    Y = dot(n.A * n.M, n.gamma)
    return {t.symbols["X"]: X, t.symbols["Y"]: Y, t.symbols["E"]: bm.E, t.symbols["D"]: n.D}


# ------------------------------------------------------------------ Theorem 1 claims
def _bkm12_12(model: Model) -> Check:
    bm = ball_map(model, (m1, m2, c1, c2), 1 / Dt)
    n = bm.n
    exprs = [
        lie_derivative(x, model) - y for x, y in zip(bm.Mt, cross(bm.Mt, bm.omega), strict=True)
    ]
    exprs += [
        lie_derivative(x, model) - y for x, y in zip(bm.gt, cross(bm.gt, bm.omega), strict=True)
    ]
    exprs += [lie_derivative(dot(bm.gt, bm.gt), model), lie_derivative(dot(bm.Mt, bm.gt), model)]
    del n
    return Check(exprs, note="constant coefficients m1, m2, c1, c2 free")


def _bkm12_14(model: Model) -> Check:
    """The derived conditions are (14): numerator = X (R2 Y - R1 X)."""
    t = theorem1()
    X, Y = t.symbols["X"], t.symbols["Y"]
    exprs = [t.numerator.as_expr() - X * (t.R2 * Y - t.R1 * X)]
    exprs += [t.numerator.coeff_monomial(X**2) + t.R1, t.numerator.coeff_monomial(X * Y) - t.R2]
    return Check(exprs, everywhere=True, note="scalar identity in X, Y and the coefficients")


def _bkm12_21(model: Model) -> Check:
    """(21) solves (14): R1 = R2 = 0 with m2 = -E D m1 c1/c2, D~^-1 = E c1^2 + D^-1 c2^2."""
    t = theorem1()
    s = t.symbols
    E, D = s["E"], s["D"]
    sub = {
        s["m2"]: -E * D * s["m1"] * s["c1"] / s["c2"],
        s["Dt"]: 1 / (E * s["c1"] ** 2 + s["c2"] ** 2 / D),
    }
    exprs = [t.R1.xreplace(sub), t.R2.xreplace(sub)]
    # and the derived solution is (21)
    sol = t.solution
    exprs += [
        E * s["m1"] * s["c1"] + sol[s["m2"]] * s["c2"] / D,
        1 / sol[s["Dt"]] - (E * s["c1"] ** 2 + s["c2"] ** 2 / D),
    ]
    return Check(exprs, everywhere=True, note="scalar identity in E, D and the coefficients")


def _theorem1_on_ball(model: Model):
    """Theorem 1's derivation, the ball map with free coefficients and ``D~``, and the
    substitution of the model's scalars and those coefficients into the derivation."""
    t = theorem1()
    bm = ball_map(model, (m1, m2, c1, c2), 1 / Dt)
    sub = _scalars_sub(model, bm)
    sub.update(
        {
            t.symbols["m1"]: m1,
            t.symbols["m2"]: m2,
            t.symbols["c1"]: c1,
            t.symbols["c2"]: c2,
            t.symbols["Dt"]: Dt,
        }
    )
    return t, bm, sub


def _bkm12_17(model: Model) -> Check:
    t, bm, sub = _theorem1_on_ball(model)
    n = bm.n
    X, Y = sub[t.symbols["X"]], sub[t.symbols["Y"]]
    exprs = [dot(n.A * n.M, n.M) - (bm.E - Y**2 / X), dot(n.gamma, n.A * n.gamma) - (1 / n.D - X)]
    exprs += [1 / Dt - dot(bm.gt, n.A * bm.gt) - t.X_t.xreplace(sub)]
    exprs += [dot(n.A * bm.Mt, bm.gt) - t.Y_t.xreplace(sub)]
    return Check(exprs, note="E = (M, omega) of the state; coefficients and D~ free")


def _proof_t1(model: Model) -> Check:
    t, bm, sub = _theorem1_on_ball(model)
    n = bm.n
    X, Y, E, D = (sub[t.symbols[k]] for k in ("X", "Y", "E", "D"))
    R1, R2 = t.R1.xreplace(sub), t.R2.xreplace(sub)
    Phi = (R2 * Y - R1 * X) / ((c2 * X - c1 * Y) ** 2 - X * (E * c1**2 + c2**2 / D - 1 / Dt))
    w, wt = bm.omega, bm.omega_t
    exprs = []
    for i, j in ((0, 1), (1, 2), (0, 2)):
        minor = wt[i] * w[j] - wt[j] * w[i]
        exprs.append(
            minor - n.A[i, i] * n.A[j, j] * (n.M[i] * n.gamma[j] - n.M[j] * n.gamma[i]) * Phi
        )
    return Check(exprs, note="general coefficients and D~ (not satisfying (14))")


def _parallel(coeff_kind: str):
    def build(model: Model) -> Check:
        coeffs, Dt_inv = _t1_coeffs(model, violate=coeff_kind)
        bm = ball_map(model, coeffs, Dt_inv)
        return Check(
            list(cross(bm.omega_t, bm.omega)),
            note="coefficients from the derived solution of (14) (m1, c1, c2 free)",
        )

    return build


def _bkm12_18(which: str):
    def build(model: Model) -> Check:
        coeffs, Dt_inv = _t1_coeffs(model)
        bm = ball_map(model, coeffs, Dt_inv)
        mu = bm.mu if which == "corrected" else m1 + c1 * bm.n.Z
        return Check(list(bm.omega_t - mu * bm.omega))

    return build


def _bkm12_19(sign: int):
    def build(model: Model) -> Check:
        coeffs, Dt_inv = _t1_coeffs(model)
        bm = ball_map(model, coeffs, Dt_inv, sign=sign)
        # multiplied by mu (non-zero where the map is defined)
        exprs = [
            bm.mu * lie_derivative(x, model) - y
            for x, y in zip(bm.Mt, cross(bm.Mt, bm.omega_t), strict=True)
        ]
        exprs += [
            bm.mu * lie_derivative(x, model) - y
            for x, y in zip(bm.gt, cross(bm.gt, bm.omega_t), strict=True)
        ]
        return Check(exprs, note="times mu")

    return build


def _bkm12_20(model: Model) -> Check:
    coeffs, Dt_inv = _t1_coeffs(model)
    bm = ball_map(model, coeffs, Dt_inv)
    a1, a2, _, _ = coeffs
    return Check([dot(bm.Mt, bm.omega_t) - (bm.E * a1**2 + a2**2 / bm.n.D)])


def _rem_t1(model: Model) -> Check:
    """Metric <x, y> = E x1 y1 + D^-1 x2 y2: <m, c> = 0, D~^-1 = <c, c>, E~ = <m, m>."""
    coeffs, Dt_inv = _t1_coeffs(model)
    bm = ball_map(model, coeffs, Dt_inv)
    a1, a2, b1, b2 = coeffs
    E, D = bm.E, bm.n.D

    def g(x, y):
        return E * x[0] * y[0] + x[1] * y[1] / D

    m, c = (a1, a2), (b1, b2)
    return Check([g(m, c), Dt_inv - g(c, c), dot(bm.Mt, bm.omega_t) - g(m, m)])


# ------------------------------------------------------------------ Chaplygin's coefficients
F = sp.Symbol("f")


def _bkm12_22(model: Model) -> Check:
    """Every f = k tan phi: normalisations, (21), (20) and omega~ || omega."""
    cm = chaplygin_map()
    n = ball_notation(model)
    E = _energy(model)
    C, Mg = dot(n.M, n.M), dot(n.M, n.gamma)
    sub = {
        cm.symbols["E"]: E,
        cm.symbols["D"]: n.D,
        cm.symbols["C"]: C,
        cm.symbols["Mg"]: Mg,
        cm.symbols["f"]: F,
    }
    # m1, c1 are non-zero factors: u = M~/m1, v = gamma~/c1; m1^2, c1^2 are rational in f
    m1sq, c1sq = (cm.m1**2).xreplace(sub), (cm.c1**2).xreplace(sub)
    r_m, r_c = sp.cancel(cm.m2 / cm.m1).xreplace(sub), sp.cancel(cm.c2 / cm.c1).xreplace(sub)
    Dt_inv, Et = cm.Dt_inv.xreplace(sub), cm.Et.xreplace(sub)
    u = n.M + r_m * n.gamma
    v = n.M + r_c * n.gamma
    exprs = [m1sq * dot(u, u) - C, c1sq * dot(v, v) - 1]
    exprs += [E + r_m * r_c / n.D, Dt_inv - c1sq * (E + r_c**2 / n.D)]
    exprs += [Et - m1sq * (E + r_m**2 / n.D)]
    return Check(
        exprs,
        free=[F],
        note="f free (every phi); m1, c1 enter through m1^2, c1^2; "
        "E = (M, omega) of the state; omega~ || omega for every phi is BKM12-1.4a",
    )


def _bkm12_23(wrong: bool = False):
    def build(model: Model) -> Check:
        cm = chaplygin_map()
        n = ball_notation(model)
        E = _energy(model)
        k2 = E * n.D
        # vector level, every f: (M - f gamma, f M + k^2 gamma) is the Gram form
        ortho = cm.orthogonality.xreplace(
            {
                cm.symbols["E"]: E,
                cm.symbols["D"]: n.D,
                cm.symbols["C"]: dot(n.M, n.M),
                cm.symbols["Mg"]: dot(n.M, n.gamma),
                cm.symbols["f"]: F,
            }
        )
        exprs = [dot(n.M - F * n.gamma, F * n.M + k2 * n.gamma) - ortho]
        # scalar level: the Gram form vanishes at both roots (C, Mg, E, D free scalars)
        s = cm.symbols
        if wrong:  # a root of Mg f^2 - (C - E D) f + E D Mg (sign of the last term flipped)
            K2 = s["E"] * s["D"]
            roots = [
                ((s["C"] - K2) + sp.sqrt((s["C"] - K2) ** 2 - 4 * K2 * s["Mg"] ** 2))
                / (2 * s["Mg"])
            ]
        else:
            roots = list(cm.roots)
        exprs += [cm.orthogonality.xreplace({s["f"]: r}) for r in roots]
        return Check(
            exprs,
            free=[F, s["C"], s["Mg"], s["E"], s["D"]],
            note="(M~, gamma~)/(m1 c1) = the Gram form in C, M_gamma, E (proved on the "
            "phase space); the form at both roots f = k tan phi (square root split off)",
        )

    return build


def _bkm12_23_phi(model: Model) -> Check:
    """Printed phi-form: rho, sigma normalise for every phi, k; tan(2 phi) "
    "gives (M~, gamma~) = 0."""
    p = chaplygin_phi_form()
    n = ball_notation(model)
    k = p["k"]
    phi = p["phi"]
    C, Mg = dot(n.M, n.M), dot(n.M, n.gamma)
    sub = {p["C"]: C, p["Mg"]: Mg}
    a1, a2, b1, b2 = (p[x].xreplace(sub) for x in ("m1", "m2", "c1", "c2"))
    Mt, gt = a1 * n.M + a2 * n.gamma, b1 * n.M + b2 * n.gamma
    exprs = [dot(Mt, Mt) - C, dot(gt, gt) - 1]
    # (M~, gamma~) = rho sigma ((C - k^2) sin(2 phi)/2 + k Mg cos(2 phi))
    exprs.append(
        dot(Mt, gt)
        - p["rho"].xreplace(sub)
        * p["sigma"].xreplace(sub)
        * ((C - k**2) * sp.sin(phi) * sp.cos(phi) + k * Mg * (sp.cos(phi) ** 2 - sp.sin(phi) ** 2))
    )
    # with tan(2 phi) = -2 k Mg/(C - k^2): sin 2phi, cos 2phi on the unit circle
    R = sp.sqrt((C - k**2) ** 2 + 4 * k**2 * Mg**2)
    s2, c2_ = -2 * k * Mg / R, (C - k**2) / R
    exprs.append((C - k**2) * s2 / 2 + k * Mg * c2_)
    return Check(exprs, free=[k], note="phi free (sin, cos on the circle), k > 0 free")


def _bkm12_1_4a(model: Model) -> Check:
    """For every phi (k^2 = E D, D~^-1 = E sigma^2): (21) holds and omega~ || omega.

    (21) is checked on the printed coefficients divided by the positive ``rho sigma``
    (resp. ``sigma^2``): only ``k^2`` enters. For the parallelism, ``f = k tan phi`` (free):
    ``u = M~/(rho cos phi) = M - f gamma``, ``v = k gamma~/(sigma cos phi) = f M + k^2 gamma`` and
    ``Z~ gamma~/(rho cos phi) = (A u, v) v/(E (k^2 + f^2) - (v, A v))``
    (``cos^-2 phi = 1 + f^2/k^2``).
    """
    p = chaplygin_phi_form()
    n = ball_notation(model)
    E = _energy(model)
    C, Mg = dot(n.M, n.M), dot(n.M, n.gamma)
    sub = {p["C"]: C, p["Mg"]: Mg}
    a1, a2 = ((p[x] / p["rho"]).xreplace(sub) for x in ("m1", "m2"))
    b1, b2 = ((p[x] / p["sigma"]).xreplace(sub) for x in ("c1", "c2"))
    k2 = E * n.D
    kk = {p["k"] ** 2: k2}
    exprs = [sp.expand(E * a1 * b1 + a2 * b2 / n.D).xreplace(kk)]
    exprs += [sp.expand(E - (E * b1**2 + b2**2 / n.D)).xreplace(kk)]
    f = sp.Symbol("f")
    u = n.M - f * n.gamma
    v = f * n.M + k2 * n.gamma
    Ztg = dot(n.A * u, v) / (E * (k2 + f**2) - dot(v, n.A * v)) * v
    wt = n.A * (u + Ztg)
    exprs += list(cross(wt, model.expand_aux(n.omega)))
    return Check(
        exprs, free=[f], note="phi on the circle, f = k tan phi free; only k^2 = E D enters"
    )


# ------------------------------------------------------------------ Kilin's form
def _kilin(model: Model):
    """Kilin's new vectors for a free f; D~ from BKM12-21 (D~^-1 = E c1^2 + c2^2/D)."""
    km, cm = kilin_map(), chaplygin_map()
    n = ball_notation(model)
    E = _energy(model)
    nn, Cg = dot(n.M, n.M), dot(n.M, n.gamma)
    s = km.symbols
    sub = {s["n"]: nn, s["C"]: Cg, s["h"]: E / 2, s["D"]: n.D, s["f"]: F}
    vals = {k: getattr(km, k).xreplace(sub) for k in ("mu", "nu", "kap", "lam", "Q", "n1")}
    # the inverse of [[nu, mu], [lam, kap]] (derive's ``inverse``), written with the same
    # kap so that square roots of related radicands are not taken as independent:
    # 1/sqrt((n - C^2) Q) = kap/(n - C^2)
    root = sp.sqrt(nn - Cg**2)
    Mt = root * (n.M - F * n.gamma) / vals["Q"]
    gt = vals["kap"] * ((F - Cg) * n.M + (nn - Cg * F) * n.gamma) / (nn - Cg**2)
    inv = sp.Matrix([[root / vals["Q"], -F * root / vals["Q"]], [0, 0]])
    vals["Dt"] = 1 / cm.Dt_inv.xreplace(
        {
            cm.symbols["E"]: E,
            cm.symbols["D"]: n.D,
            cm.symbols["C"]: nn,
            cm.symbols["Mg"]: Cg,
            cm.symbols["f"]: F,
        }
    )
    vals["m1"], vals["m2"] = inv[0, 0], inv[0, 1]
    return n, E, nn, Cg, vals, Mt, gt


def _k01_2_29(which: str):
    def build(model: Model) -> Check:
        n, E, nn, Cg, v, Mt, gt = _kilin(model)
        if which == "2.30":
            exprs = [
                v["mu"] ** 2 + v["nu"] ** 2 * v["n1"] - nn,
                v["kap"] ** 2 + v["lam"] ** 2 * v["n1"] - 1,
                v["mu"] * v["kap"] + v["nu"] * v["lam"] * v["n1"] - Cg,
            ]
        else:
            exprs = list(n.M - (v["mu"] * gt + v["nu"] * Mt))
            exprs += list(n.gamma - (v["kap"] * gt + v["lam"] * Mt))
            exprs += [dot(Mt, Mt) - v["n1"], dot(gt, gt) - 1]
            return Check(
                exprs,
                free=[F],
                method="exact-sampled",
                note="for every f; exact sampling: the Groebner proof with the two "
                "square roots takes ~5 s",
            )
        return Check(exprs, free=[F], note="for every f (the relations do not need (2.32))")

    return build


def _k01_2_31(model: Model) -> Check:
    """The new ball's energy and (M~, M~) in Kilin's form, for every f and every D~.

    ``J omega~ = M~ + Z~ gamma~`` and ``(omega~, gamma~) = Z~/D~`` make both identities hold
    for any ``D~``; the value of ``D~`` (K01-2.33) and ``omega~ || omega`` (BKM12-1.4a,
    every ``f``) are separate claims.
    """
    n = ball_notation(model)
    Mt, gt = n.M, n.gamma  # the new ball's state: any M~, unit gamma~
    Zt = dot(n.A * Mt, gt) / (1 / Dt - dot(gt, n.A * gt))
    wt = n.A * (Mt + Zt * gt)
    J = n.J
    wg = dot(wt, gt)
    exprs = [dot(J * wt, wt) - Dt * wg**2 - dot(Mt, wt)]
    exprs += [dot(J * wt, J * wt) - Dt**2 * wg**2 - dot(Mt, Mt) - 2 * Dt * wg * dot(Mt, gt)]
    return Check(
        exprs,
        free=[Dt],
        note="at every state (M~, gamma~), |gamma~| = 1, and any D~ "
        "(Kilin's (M~, M~) = n1 is K01-2.29, "
        "(M~, gamma~) = 0 at the root BKM12-23, 2 h1 and D~ K01-2.33)",
    )


# scalar level: n, C (= M_gamma), D, f free; E = 2h eliminated with the quadratic (2.32)
_n, _D = sp.symbols("n D", positive=True)
_C = sp.Symbol("C")


def _on_quadratic():
    km = kilin_map()
    s = km.symbols
    E = F * (_n - _C * F) / (_D * (F - _C))  # solves Mg f^2 - (n - E D) f - E D Mg = 0
    sub = {s["n"]: _n, s["C"]: _C, s["h"]: E / 2, s["D"]: _D, s["f"]: F}
    return km, E, sub


def _k01_2_31c(model: Model) -> Check:
    km, E, sub = _on_quadratic()
    v = {k: getattr(km, k).xreplace(sub) for k in ("mu", "nu", "kap", "lam", "Q", "n1", "h1", "Dt")}
    h, D = E / 2, _D
    det2 = (v["mu"] * v["lam"] - v["nu"] * v["kap"]) ** 2
    exprs = [
        km.quadratic.xreplace(sub),
        det2 * v["h1"] - (h * v["kap"] ** 2 + v["mu"] ** 2 / (2 * D)),
        det2 / v["Dt"] - (2 * h * v["lam"] ** 2 + v["nu"] ** 2 / D),
        v["mu"] * v["nu"] / D + 2 * h * v["kap"] * v["lam"],
        det2 * v["h1"] / v["Dt"] - h / D,
    ]
    return Check(
        exprs,
        free=[_n, _C, _D, F],
        everywhere=True,
        note="scalars n, C, D, f; 2h = f (n - C f)/(D (f - C)) solves (2.32)",
    )


def _k01_2_32(model: Model) -> Check:
    km, cm = kilin_map(), chaplygin_map()
    E = sp.Symbol("E", positive=True)
    s = km.symbols
    sub = {s["n"]: _n, s["C"]: _C, s["h"]: E / 2, s["D"]: _D, s["f"]: F}
    quad = km.quadratic.xreplace(sub)
    orth = cm.orthogonality.xreplace(
        {
            cm.symbols["E"]: E,
            cm.symbols["D"]: _D,
            cm.symbols["C"]: _n,
            cm.symbols["Mg"]: _C,
            cm.symbols["f"]: F,
        }
    )
    v = {k: getattr(km, k).xreplace(sub) for k in ("mu", "nu", "kap", "lam", "Q")}
    exprs = [_C * quad + orth, (v["mu"] * v["lam"] - v["nu"] * v["kap"]) ** 2 - v["Q"]]
    return Check(
        exprs,
        free=[_n, _C, _D, F, E],
        everywhere=True,
        note="K01's quadratic is -1/M_gamma times BKM12's orthogonality (scalars free)",
    )


def _k01_2_33(control: bool = False):
    def build(model: Model) -> Check:
        km, E, sub = _on_quadratic()
        cm = chaplygin_map()
        v = {k: getattr(km, k).xreplace(sub) for k in ("n1", "h1", "Dt", "Q")}
        csub = {
            cm.symbols["E"]: E,
            cm.symbols["D"]: _D,
            cm.symbols["C"]: _n,
            cm.symbols["Mg"]: _C,
            cm.symbols["f"]: F,
        }
        Dt_bkm = 1 / cm.Dt_inv.xreplace(csub)
        m1sq = (_n - _C**2) / v["Q"] ** 2  # Kilin's M~ = sqrt(n - C^2) (M - f gamma)/Q
        Et = m1sq * (E + F**2 / _D)  # BKM12-20
        if control:
            return Check(
                [F * (_n - _C**2) / (E * (F + _C)) - Dt_bkm], free=[_n, _C, _D, F], everywhere=True
            )
        exprs = [v["Dt"] - Dt_bkm, 2 * v["h1"] - Et, v["n1"] - m1sq * (_n - 2 * _C * F + F**2)]
        return Check(
            exprs,
            free=[_n, _C, _D, F],
            everywhere=True,
            note="scalars; 2h = f (n - C f)/(D (f - C)) solves (2.32); against BKM12-20, 21",
        )

    return build


def _k01_rem1(model: Model) -> Check:
    """M~ -> s M~: omega~ -> s omega~ at every state and D~, and (21) is kept (m -> s m)."""
    n = ball_notation(model)
    E = _energy(model)

    def omega_t(M_):
        Zt = dot(n.A * M_, n.gamma) / (1 / Dt - dot(n.gamma, n.A * n.gamma))
        return n.A * (M_ + Zt * n.gamma)

    coeffs, Dt_inv = _t1_coeffs(model)
    a1, a2, b1, b2 = coeffs
    exprs = list(omega_t(s_free * n.M) - s_free * omega_t(n.M))
    exprs += [E * (s_free * a1) * b1 + (s_free * a2) * b2 / n.D]
    return Check(
        exprs,
        free=[s_free, Dt],
        note="the new ball's state (M~, gamma~) is the model's state; D~, s free",
    )


register(
    Claim(
        id="BKM12-12",
        source=S13,
        kind="transformation",
        statement="M~ = m1 M + m2 gamma, gamma~ = c1 M + c2 gamma (constant coefficients): "
        "M~' = M~ x omega, gamma~' = gamma~ x omega, (gamma~, gamma~) and (M~, gamma~) conserved",
        system=BALL,
        effects=(),
        build=_bkm12_12,
    ),
    Claim(
        id="BKM12-14",
        source=S13,
        kind="transformation",
        statement="omega~ || omega on 2H = E iff R1 = m2 D~^-1 + E c1 Delta = 0, R2 = m1 "
        "D~^-1 - c2 D^-1 Delta = 0, "
        "Delta = m1 c2 - m2 c1 (the derived coefficients of X^2 X~ times the minor factor)",
        system=BALL,
        effects=(),
        build=_bkm12_14,
        note="derived in chaplygin.derive.transformation.theorem1",
    ),
    Claim(
        id="BKM12-17",
        source=S13,
        kind="equation",
        statement="(A M, M) = E - X^-1 Y^2, (gamma, A gamma) = D^-1 - X, "
        "X~ = D~^-1 - c1^2 (E - X^-1 Y^2) - c2^2 (D^-1 - X) - 2 c1 c2 Y, "
        "Y~ = m1 c1 (E - X^-1 Y^2) + m2 c2 (D^-1 - X) + (m1 c2 + m2 c1) Y",
        system=BALL,
        effects=(),
        build=_bkm12_17,
    ),
    Claim(
        id="BKM12-proofT1",
        source=S13,
        kind="transformation",
        statement="omega~_i omega_j - omega~_j omega_i = A_i A_j (M_i gamma_j - M_j gamma_i) Phi, "
        "Phi = (R2 Y - R1 X)/((c2 X - c1 Y)^2 - X (E c1^2 + D^-1 c2^2 - D~^-1))",
        system=BALL,
        effects=(),
        build=_proof_t1,
    ),
    Claim(
        id="BKM12-21",
        source=S13,
        kind="transformation",
        statement="(14) <=> E m1 c1 + D^-1 m2 c2 = 0, D~^-1 = E c1^2 + D^-1 c2^2 (the derived "
        "solution)",
        system=BALL,
        effects=(),
        build=_bkm12_21,
    ),
    Claim(
        id="BKM12-15",
        source=S13,
        kind="transformation",
        statement="under (21): omega~ = A (M~ + Z~ gamma~) is parallel to omega on 2H = E",
        system=BALL,
        effects=(),
        build=_parallel(""),
        covers=("BKM12-1.3a",),  # the same A, D -> D~: a trajectory isomorphism
    ),
    Claim(
        id="BKM12-15/control-m2",
        source=f"{S13} (negative control)",
        kind="transformation",
        statement="omega~ || omega with m2 = -E D m1 c1/c2 + c1 (violating (21))",
        system=BALL,
        effects=(),
        build=_parallel("m2"),
        expected="fails",
    ),
    Claim(
        id="BKM12-15/control-Dt",
        source=f"{S13} (negative control)",
        kind="transformation",
        statement="omega~ || omega with D~^-1 = E c1^2 + 3 D^-1 c2^2 (violating (21))",
        system=BALL,
        effects=(),
        build=_parallel("Dt"),
        expected="fails",
    ),
    Claim(
        id="BKM12-18",
        source=S13,
        kind="transformation",
        statement="omega~ = mu omega, mu = m1 + c1 Z~ (corrected: Z~, not Z)",
        system=BALL,
        effects=(),
        build=_bkm12_18("corrected"),
    ),
    Claim(
        id="BKM12-18/literal",
        source=f"{S13} (literal reading)",
        kind="transformation",
        statement="omega~ = mu omega, mu = m1 + c1 Z (as extracted)",
        system=BALL,
        effects=(),
        build=_bkm12_18("literal"),
        expected="fails",
    ),
    Claim(
        id="BKM12-19",
        source=S13,
        kind="transformation",
        statement="M~' = mu^-1 M~ x omega~, gamma~' = mu^-1 gamma~ x omega~, "
        "Z~ = (A M~, gamma~)/(D~^-1 - (gamma~, A gamma~))",
        system=BALL,
        effects=(),
        build=_bkm12_19(-1),
    ),
    Claim(
        id="BKM12-19/literal",
        source=f"{S13} (literal reading)",
        kind="transformation",
        statement="the same with Z~ = (A M~, gamma~)/(D~^-1 + (gamma~, A gamma~)) (denominator as "
        "extracted)",
        system=BALL,
        effects=(),
        build=_bkm12_19(+1),
        expected="fails",
    ),
    Claim(
        id="BKM12-20",
        source=S13,
        kind="integral",
        statement="E~ = (M~, omega~) = E m1^2 + D^-1 m2^2",
        system=BALL,
        effects=(),
        build=_bkm12_20,
    ),
    Claim(
        id="BKM12-RemT1",
        source=S13,
        kind="transformation",
        statement="<x, y> = E x1 y1 + D^-1 x2 y2: <m, c> = 0, D~^-1 = <c, c>, E~ = (M~, omega~) = "
        "<m, m>",
        system=BALL,
        effects=(),
        build=_rem_t1,
    ),
    Claim(
        id="BKM12-1.4a",
        source=S14,
        kind="transformation",
        statement="m1 = rho cos phi, m2 = -k rho sin phi, c1 = sigma sin phi, c2 = k "
        "sigma cos phi, k^2 = E D, "
        "D~^-1 = E sigma^2: (21) holds and omega~ || omega for every phi",
        system=BALL,
        effects=(),
        build=_bkm12_1_4a,
    ),
    Claim(
        id="BKM12-23.phi",
        source=S14,
        kind="transformation",
        statement="rho = sqrt(C) (C cos^2 phi + k^2 sin^2 phi - 2 k M_gamma sin phi cos phi)^-1/2, "
        "sigma = (C sin^2 phi + k^2 cos^2 phi + 2 k M_gamma cos phi sin "
        "phi)^-1/2 give (M~, M~) = C, "
        "(gamma~, gamma~) = 1; tan(2 phi) = -2 k M_gamma/(C - k^2) gives (M~, gamma~) = 0",
        system=BALL,
        effects=(),
        build=_bkm12_23_phi,
    ),
    Claim(
        id="BKM12-22",
        source=S14,
        kind="transformation",
        statement="M~ = rho (cos phi M - k sin phi gamma), gamma~ = sigma (sin phi M + k cos phi "
        "gamma), "
        "f = k tan phi: (M~, M~) = C, (gamma~, gamma~) = 1, (21) and E~ = E m1^2 + m2^2/D "
        "for every phi (the derived closed forms)",
        system=BALL,
        effects=(),
        build=_bkm12_22,
    ),
    Claim(
        id="BKM12-23",
        source=S14,
        kind="transformation",
        statement="(M~, gamma~) = 0 at both roots of tan(2 phi) = -2 k M_gamma/(C - k^2), i.e. of "
        "M_gamma f^2 - (C - E D) f - E D M_gamma = 0 (f = k tan phi; the roots differ by pi/2)",
        system=BALL,
        effects=(),
        build=_bkm12_23(),
    ),
    Claim(
        id="BKM12-23/control-quadratic",
        source=f"{S14} (negative control)",
        kind="transformation",
        statement="(M - f gamma, f M + E D gamma) = 0 for a root of M_gamma f^2 - (C - E D) f + E "
        "D M_gamma",
        system=BALL,
        effects=(),
        build=_bkm12_23(wrong=True),
        expected="fails",
    ),
    Claim(
        id="K01-2.29",
        source=K23,
        kind="transformation",
        statement="M = mu gamma~ + nu M~, gamma = kap gamma~ + lam M~ (the derived inverse map) "
        "with "
        "(M~, M~) = n1, (gamma~, gamma~) = 1",
        system=BALL,
        effects=(),
        build=_k01_2_29("2.29"),
    ),
    Claim(
        id="K01-2.30",
        source=K23,
        kind="transformation",
        statement="mu^2 + nu^2 n1 = n, kap^2 + lam^2 n1 = 1, mu kap + nu lam n1 = C "
        "(kap = sqrt((n - C^2)/Q), mu = f kap, lam = (C - f)/sqrt(n - C^2), nu "
        "= (n - C f)/sqrt(n - C^2))",
        system=BALL,
        effects=(),
        build=_k01_2_29("2.30"),
    ),
    Claim(
        id="K01-2.31",
        source=K23,
        kind="transformation",
        statement="(J omega~, omega~) - D~ (omega~, gamma~)^2 = (M~, omega~) = 2 h1, "
        "(J omega~, J omega~) - D~^2 (omega~, gamma~)^2 = (M~, M~) = n1 where (M~, gamma~) = 0, "
        "J = I + D Id = I~ + D~ Id",
        system=BALL,
        effects=(),
        build=_k01_2_31,
    ),
    Claim(
        id="K01-2.31c",
        source=K23,
        kind="transformation",
        statement="(mu lam - nu kap)^2 h1 = h kap^2 + mu^2/(2D), (mu lam - nu kap)^2/D~ "
        "= 2 h lam^2 + nu^2/D, "
        "mu nu/D + 2 h kap lam = 0, (mu lam - nu kap)^2 h1/D~ = h/D",
        system=BALL,
        effects=(),
        build=_k01_2_31c,
    ),
    Claim(
        id="K01-2.32",
        source=K23,
        kind="transformation",
        statement="f^2 - ((n - 2hD)/C) f - 2hD = 0 is Chaplygin's orthogonality (BKM12-23, f = k "
        "tan phi); "
        "|mu lam - nu kap| = sqrt(Q)",
        system=BALL,
        effects=(),
        build=_k01_2_32,
    ),
    Claim(
        id="K01-2.33",
        source=K23,
        kind="transformation",
        statement="n1 = (M~, M~) = (n - C^2)/(n - C^2 + (C - f)^2); h1 = h (n - C^2)/((n - C f) "
        "Q), "
        "D~ = f (n - C^2)/(2h (f - C)) (reconstructed) agree with BKM12-20, 21",
        system=BALL,
        effects=(),
        build=_k01_2_33(),
    ),
    Claim(
        id="K01-2.33/control-Dt",
        source=f"{K23} (negative control)",
        kind="transformation",
        statement="D~ = f (n - C^2)/(2h (f + C)) agrees with BKM12-21",
        system=BALL,
        effects=(),
        build=_k01_2_33(control=True),
        expected="fails",
    ),
    Claim(
        id="K01-Rem1",
        source=K23,
        kind="transformation",
        statement="the transformation is defined up to M~ -> s M~: omega~ -> s omega~, "
        "still parallel to omega",
        system=BALL,
        effects=(),
        build=_k01_rem1,
    ),
)
