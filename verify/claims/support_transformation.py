"""Claims of the generalised transformation for the spherical support: BKM12 §2.4-2.6.

Proposition 1 (43)-(44) and the Remark of §2.4 on the ``spherical_support`` model's state
(restricted to the invariant set where constants of areas vanish); Theorem 2 through the
2x2 ``X`` of BKM12-48 (the transformed ``X~, Y~`` derived by bilinearity in
:func:`chaplygin.derive.transformation.theorem2_scalars`); Proposition 2 (49)-(55) on the
scalar level, with ``E`` and ``C`` eliminated by the cubic at two of its roots (the cubic
is linear in both).
"""

from __future__ import annotations

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.transformation import (
    gram_orthogonal_rows,
    proposition2,
    theorem2_scalars,
)
from chaplygin.derive.vectors import cross, dot

from .base import Check, Claim, register
from .support import support_notation

__all__: list[str] = []

SUPPORT = "spherical_support"
S24, S25, S26 = "BKM12 §2.4", "BKM12 §2.5", "BKM12 §2.6"


def _state(model: Model):
    n = support_notation(model)
    w = model.expand_aux(n.omega)
    E = dot(n.M, w)
    return n, w, E


# ------------------------------------------------------------------ §2.4
_Mal, _Mbe = sp.symbols("M_al M_be")


def _restricted(model: Model, Mbe_zero: bool):
    """The state with M = M_al alpha (+ M_be beta): the invariant set of §2.4, M_al, M_be free."""
    n = support_notation(model)
    Mb = 0 if Mbe_zero else _Mbe
    M_on = _Mal * n.alpha + Mb * n.beta
    sub = dict(zip(list(n.M), list(M_on), strict=True))
    w = model.expand_aux(n.omega).xreplace(sub)
    return n, M_on, w, dot(M_on, w), sub


def _bkm12_43(model: Model) -> Check:
    n, M, w, E, _ = _restricted(model, True)
    exprs = [dot(M, n.beta), dot(M, cross(n.alpha, n.beta)), dot(M, M) - _Mal**2]
    exprs += [_Mal * dot(n.alpha, w) - E]
    return Check(
        exprs, free=[_Mal], note="on (M, beta) = (M, alpha x beta) = 0: M = M_al alpha, M_al free"
    )


def _bkm12_44(model: Model) -> Check:
    n, M, w, E, _ = _restricted(model, True)
    C = dot(M, M)
    Mt = (1 + E * n.D_al / C) * M
    b = n.beta
    Z = dot(n.A * Mt, b) / (1 / n.D_be - dot(b, n.A * b))
    exprs = list(Mt - (n.J - n.D_be * b * b.T) * w)
    exprs += list(w - n.A * (Mt + Z * b))
    exprs += [
        dot(Mt, w) - E * (1 + E * n.D_al / C),
        dot(Mt, b),
        dot(Mt, Mt) - C * (1 + E * n.D_al / C) ** 2,
    ]
    return Check(
        exprs,
        free=[_Mal],
        note="on M = M_al alpha (M_al free); M~ ∝ M with a constant factor, so "
        "M~' = M~ x omega follows from M' = M x omega",
    )


def _bkm12_2_4rem(model: Model) -> Check:
    n, M, w, E, _ = _restricted(model, False)
    a, b = n.alpha, n.beta
    Mal, Mbe = _Mal, _Mbe
    Dal, Dbe = n.D_al, n.D_be
    D2 = Dal * a * a.T + Dbe * b * b.T
    xi = Dal * Mbe * a - Dbe * Mal * b
    D_M = Dal * Dbe / (Dbe * Mal**2 + Dal * Mbe**2)
    D_xi = 1 / (Dal * Mbe**2 + Dbe * Mal**2)
    k2 = Dal**2 * Mbe**2 + Dbe**2 * Mal**2
    exprs = list(D2 - D_M * M * M.T - D_xi * xi * xi.T)
    # (M, D2^-1 xi) = 0 on span(alpha, beta): D2^-1 there is alpha⊗alpha/D_al + beta⊗beta/D_be
    D2inv = a * a.T / Dal + b * b.T / Dbe
    exprs += [dot(M, D2inv * xi), 1 / D_M - dot(M, D2inv * M), 1 / D_xi - dot(xi, D2inv * xi)]
    Mt = (1 + E * D_M) * M
    exprs += list(Mt - (n.J - D_xi * xi * xi.T) * w)  # = (J - D_xi k^2 gamma~⊗gamma~) omega
    exprs += [dot(xi, xi) - k2, dot(Mt, xi) - (1 + E * D_M) * (Dal - Dbe) * Mal * Mbe]
    return Check(
        exprs,
        free=[_Mal, _Mbe],
        note="on M = M_al alpha + M_be beta (M_al, M_be free); (M~, gamma~) checked times k = |xi|",
    )


# ------------------------------------------------------------------ §2.5 Theorem 2
_xaa, _xab, _xbb, _ya, _yb = sp.symbols("X_aa X_ab X_bb Y_al Y_be")
_E, _Dal, _Dbe = sp.symbols("E D_al D_be", positive=True)
_avec = sp.Matrix(sp.symbols("a1:4"))
_wvec = sp.Matrix(sp.symbols("w1:4"))


def _t2_setup():
    g = sp.diag(_E, 1 / _Dal, 1 / _Dbe)
    Q = gram_orthogonal_rows(g, _avec, _wvec)
    m, a, b = Q[0, :].T, Q[1, :].T, Q[2, :].T
    tal, tbe = (a.T * g * a)[0, 0], (b.T * g * b)[0, 0]
    X = sp.Matrix([[_xaa, _xab], [_xab, _xbb]])
    Y = sp.Matrix([_ya, _yb])
    # X's diagonal carries D^-1 - (., A .): the Gram matrix needs D_al^-1, D_be^-1 themselves
    out = theorem2_scalars(Q, X, Y, _E, (1 / _Dal, 1 / _Dbe, tal, tbe))
    return g, Q, m, a, b, X, Y, out


def _bkm12_t2(which: str):
    """Theorem 2 on the scalar level, without fractions in ``Z``, ``Z~``.

    ``omega~ = mu omega`` iff ``Q^T (1, Z~) = mu (1, Z)`` (``M, alpha, beta`` independent), i.e.
    ``Q^T (det X~, adj(X~) Y~) x (det X, adj(X) Y) = 0``.
    """

    def build(model: Model) -> Check:
        g, Q, m, a, b, X, Y, out = _t2_setup()
        Xt, Yt = out["X_t"], out["Y_t"]
        dXt, dX = Xt.det(), X.det()
        Pt = sp.Matrix([dXt, *(Xt.adjugate() * Yt)])
        P = sp.Matrix([dX, *(X.adjugate() * Y)])
        lhs = Q.T * Pt  # = det X~ mu (1, Z) when the theorem holds
        if which == "mu":
            exprs = list(cross(lhs, P))
            # mu^-1 = [(a2 b3 - a3 b2) + (a3 b1 - a1 b3) Z_al + (a1 b2 - a2 b1) Z_be]/det Q_E
            num_inv = (
                (a[1] * b[2] - a[2] * b[1]) * P[0]
                + (a[2] * b[0] - a[0] * b[2]) * P[1]
                + (a[0] * b[1] - a[1] * b[0]) * P[2]
            )
            exprs.append(lhs[0] * num_inv - dXt * Q.det() * dX)
        else:
            T00 = (Q * out["Gram"] * Q.T)[0, 0]
            # (M~, omega~) = (M~, A M~) + (Y~, X~^-1 Y~), times det X~
            exprs = [T00 * dXt + (Yt.T * Xt.adjugate() * Yt)[0, 0] - (m.T * g * m)[0, 0] * dXt]
        free = [_xaa, _xab, _xbb, _ya, _yb, _E, _Dal, _Dbe, *_avec, *_wvec]
        return Check(
            exprs,
            free=free,
            everywhere=True,
            method="exact-sampled",
            note="scalar identity in X (2x2), Y, E and g-orthogonal rows "
            "b = g^-1 (a x w), m = g^-1 (a x b), fractions cleared; exact sampling (the "
            "expanded numerators are too large for a quick proof)",
        )

    return build


def _printed_48(u, v, X, Y, YXY):
    """The printed right-hand side of BKM12-48 for rows u, v."""
    return (
        u[0] * v[0] * YXY
        + u[1] * v[1] * X[0, 0]
        + u[2] * v[2] * X[1, 1]
        + (u[1] * v[2] + u[2] * v[1]) * X[0, 1]
        - (u[0] * v[1] + u[1] * v[0]) * Y[0]
        - (u[0] * v[2] + u[2] * v[0]) * Y[1]
    )


def _bkm12_48(literal: bool = False):
    def build(model: Model) -> Check:
        n, w, E = _state(model)
        X = n.X()
        Y = sp.Matrix([dot(n.A * n.M, n.alpha), dot(n.A * n.M, n.beta)])
        q = sp.Matrix(3, 3, sp.symbols("q1:10"))
        m_, a_, b_ = q[0, :], q[1, :], q[2, :]

        def metric(u, v):  # BKM12-46 with E the state's energy
            return E * u[0] * v[0] + u[1] * v[1] / n.D_al + u[2] * v[2] / n.D_be

        A = n.A
        YXY = (Y.T * X.adjugate() * Y)[0, 0] / X.det()
        if literal:  # Y~_be = (A M~, beta~) = m1 b1 (Y, X^-1 Y) + ... (no minus sign), with (47)
            b1 = -(m_[1] * b_[1] / n.D_al + m_[2] * b_[2] / n.D_be) / (E * m_[0])  # <m, b> = 0
            bb = sp.Matrix([[b1, b_[1], b_[2]]])
            Mt = m_[0] * n.M + m_[1] * n.alpha + m_[2] * n.beta
            bt = bb[0] * n.M + bb[1] * n.alpha + bb[2] * n.beta
            return Check([dot(A * Mt, bt) - _printed_48(m_, bb, X, Y, YXY)], free=list(q))
        Mt = m_[0] * n.M + m_[1] * n.alpha + m_[2] * n.beta
        at = a_[0] * n.M + a_[1] * n.alpha + a_[2] * n.beta
        bt = b_[0] * n.M + b_[1] * n.alpha + b_[2] * n.beta
        exprs = [dot(n.M, A * n.M) - (E - YXY)]
        # general rows: the printed forms plus the metric terms that (47) and
        # D~_al^-1 = <a, a>, D~_be^-1 = <b, b> remove
        exprs += [
            metric(a_, a_) - dot(at, A * at) - _printed_48(a_, a_, X, Y, YXY),
            metric(a_, b_) - dot(at, A * bt) - _printed_48(a_, b_, X, Y, YXY),
            metric(b_, b_) - dot(bt, A * bt) - _printed_48(b_, b_, X, Y, YXY),
        ]
        exprs += [
            metric(m_, a_) - dot(A * Mt, at) - _printed_48(m_, a_, X, Y, YXY),
            metric(m_, b_) - dot(A * Mt, bt) - _printed_48(m_, b_, X, Y, YXY),
        ]
        return Check(
            exprs,
            free=list(q),
            note="general coefficients: X~ = D~^-1 - ... and -Y~ equal the printed forms "
            "minus the metric products <u, v> (zero under (47)); E = (M, omega) of the state",
        )

    return build


# ------------------------------------------------------------------ §2.6 Proposition 2
def printed_cubic_55(s: dict[str, sp.Symbol]) -> sp.Expr:
    """BKM12 (55) as printed, in the symbols ``s`` of :func:`proposition2`.

    Parameters
    ----------
    s : dict of str to sympy.Symbol
        ``Proposition2.symbols``: ``E, C, M_al, M_be, D_al, D_be, lam``.

    Returns
    -------
    sympy.Expr
        The characteristic cubic in ``lam``, as printed.

    References
    ----------
    BKM12-55
    """
    E, C, Ma, Mb, Da, Db, lam = (s[k] for k in ("E", "C", "M_al", "M_be", "D_al", "D_be", "lam"))
    return (
        E * lam**3
        - (E * (Da + Db) + C) * lam**2
        + (Da * (C - Ma**2) + Db * (C - Mb**2) + E * Da * Db) * lam
        - (C - Ma**2 - Mb**2) * Da * Db
    )


def _bkm12_55(model: Model) -> Check:
    p = proposition2()
    s = p.symbols
    Da, Db, lam = s["D_al"], s["D_be"], s["lam"]
    exprs = [p.cubic - printed_cubic_55(s), p.cubic + Da * Db * (p.Gamma - lam * p.g).det()]
    exprs += list(p.B - p.g.inv() * p.Gamma) + list(p.B - (p.Gamma * p.g.inv()).T)
    return Check(exprs, free=list(s.values()), everywhere=True, note="scalar identity")


def _bkm12_55pos(model: Model) -> Check:
    """Gamma is the Gram matrix of M, alpha, beta (positive semi-definite): det = (M, gamma)^2."""
    n = support_notation(model)
    Mal, Mbe, Mg = dot(n.M, n.alpha), dot(n.M, n.beta), dot(n.M, n.gamma)
    Gamma = sp.Matrix([[dot(n.M, n.M), Mal, Mbe], [Mal, 1, 0], [Mbe, 0, 1]])
    G = sp.Matrix([[Mal, Mbe, Mg], [1, 0, 0], [0, 1, 0]])  # rows in the frame alpha, beta, gamma
    exprs = list(Gamma - G * G.T) + [Gamma.det() - Mg**2]
    return Check(
        exprs,
        note="Gamma = G G^T, g > 0: the roots of det(Gamma - lam g) are real and "
        ">= 0 (> 0 when (M, gamma) != 0, det Gamma = (M, gamma)^2)",
    )


def _roots_elimination():
    """E and C from the cubic at two roots lam, lam2 (the cubic is linear in E and C)."""
    p = proposition2()
    s = p.symbols
    lam2 = sp.Symbol("lam2")
    E, C = s["E"], s["C"]
    eqs = [p.cubic, p.cubic.xreplace({s["lam"]: lam2})]
    sol = sp.solve(eqs, [E, C], dict=True)[0]
    return p, s, lam2, sol


def _bkm12_51(model: Model) -> Check:
    p, s, lam2, sol = _roots_elimination()
    v1 = p.row.T.xreplace(sol)
    v2 = p.row.T.xreplace({s["lam"]: lam2}).xreplace(sol)
    G, g = p.Gamma.xreplace(sol), p.g.xreplace(sol)
    exprs = list((G - s["lam"] * g) * v1) + list((G - lam2 * g) * v2)
    exprs += [(v1.T * g * v2)[0, 0], (v1.T * G * v2)[0, 0]]  # (47): <m, a> = 0; (52) off-diagonal
    exprs += [
        (v1.T * G * v1)[0, 0] - s["lam"] * (v1.T * g * v1)[0, 0]
    ]  # (53) lam = Lambda_ii/g~_ii
    free = [s["lam"], lam2, s["M_al"], s["M_be"], s["D_al"], s["D_be"]]
    return Check(
        exprs,
        free=free,
        everywhere=True,
        note="two distinct roots lam, lam2 free; E and C solved from the cubic at both",
    )


def _bkm12_51_control(model: Model) -> Check:
    """The rows with D_al and D_be swapped are not eigen-rows."""
    p, s, lam2, sol = _roots_elimination()
    sw = {s["D_al"]: s["D_be"], s["D_be"]: s["D_al"]}
    v1 = p.row.T.xreplace(sw).xreplace(sol)
    v2 = p.row.T.xreplace({s["lam"]: lam2}).xreplace(sw).xreplace(sol)
    g = p.g.xreplace(sol)
    free = [s["lam"], lam2, s["M_al"], s["M_be"], s["D_al"], s["D_be"]]
    return Check([(v1.T * g * v2)[0, 0]], free=free, everywhere=True)


register(
    Claim(
        id="BKM12-43",
        source=S24,
        kind="solution",
        statement="(M, beta) = (M, alpha x beta) = 0 => M = (M, alpha) alpha, (alpha, omega) = "
        "E/(M, alpha)",
        system=SUPPORT,
        effects=(),
        build=_bkm12_43,
    ),
    Claim(
        id="BKM12-44",
        source=S24,
        kind="transformation",
        statement="Proposition 1: M~ = (1 + E D_al/C) M = (J - D_be beta⊗beta) omega, "
        "omega = A (M~ + Z beta), "
        "Z = (A M~, beta)/(D_be^-1 - (beta, A beta)), E~ = E (1 + E D_al/C), (M~, beta) = 0",
        system=SUPPORT,
        effects=(),
        build=_bkm12_44,
    ),
    Claim(
        id="BKM12-2.4Rem",
        source=S24,
        kind="transformation",
        statement="on (M, alpha x beta) = 0: D_al alpha⊗alpha + D_be beta⊗beta = D_M M⊗M + D_xi "
        "xi⊗xi, "
        "xi = D_al M_be alpha - D_be M_al beta, (M, D2^-1 xi) = 0, M~ = (1 + E D_M) M = "
        "(J - D_xi k^2 gamma~⊗gamma~) omega, (M~, gamma~) = k^-1 (1 + E "
        "D_M)(D_al - D_be) M_al M_be",
        system=SUPPORT,
        effects=(),
        build=_bkm12_2_4rem,
    ),
    Claim(
        id="BKM12-48",
        source=S25,
        kind="equation",
        statement="(A M, M) = E - (Y, X^-1 Y); X~_aa, X~_ab, X~_bb, -Y~_al = -(A M~, alpha~), "
        "-Y~_be = -(A M~, beta~) in X, Y (the printed forms; derived by bilinearity)",
        system=SUPPORT,
        effects=(),
        build=_bkm12_48(),
    ),
    Claim(
        id="BKM12-48/literal",
        source=f"{S25} (literal reading)",
        kind="equation",
        statement="Y~_be = (A M~, beta~) = m1 b1 (Y, X^-1 Y) + m2 b2 X_aa + ... (the minus sign "
        "dropped)",
        system=SUPPORT,
        effects=(),
        build=_bkm12_48(literal=True),
        expected="fails",
    ),
    Claim(
        id="BKM12-47",
        source=S25,
        kind="transformation",
        statement="Theorem 2: rows m, a, b of Q_E mutually <, >-orthogonal, D_al~^-1 = <a, a>, "
        "D_be~^-1 = <b, b> => mu Z_al = m2 + a2 Z~_al + b2 Z~_be, mu Z_be = m3 "
        "+ a3 Z~_al + b3 Z~_be "
        "with mu = m1 + a1 Z~_al + b1 Z~_be, i.e. omega~ = mu omega; mu^-1 = [(a2 b3 - a3 b2) + "
        "(a3 b1 - a1 b3) Z_al + (a1 b2 - a2 b1) Z_be]/det Q_E",
        system=SUPPORT,
        effects=(),
        build=_bkm12_t2("mu"),
    ),
    Claim(
        id="BKM12-T2E",
        source=S25,
        kind="integral",
        statement="E~ = (M~, omega~) = E m1^2 + D_al^-1 m2^2 + D_be^-1 m3^2 = <m, m>",
        system=SUPPORT,
        effects=(),
        build=_bkm12_t2("E"),
    ),
    Claim(
        id="BKM12-55",
        source=S26,
        kind="equation",
        statement="E lam^3 - (E (D_al + D_be) + C) lam^2 + (D_al (C - M_al^2) + D_be (C "
        "- M_be^2) + E D_al D_be) lam "
        "- (C - M_al^2 - M_be^2) D_al D_be = -D_al D_be det(Gamma - lam g); B "
        "= g^-1 Gamma = (Gamma g^-1)^T",
        system=SUPPORT,
        effects=(),
        build=_bkm12_55,
    ),
    Claim(
        id="BKM12-55pos",
        source=S26,
        kind="equation",
        statement="Gamma is the Gram matrix of M, alpha, beta (det Gamma = (M, gamma)^2): the "
        "roots of the "
        "cubic are real and non-negative",
        system=SUPPORT,
        effects=(),
        build=_bkm12_55pos,
    ),
    Claim(
        id="BKM12-51",
        source=S26,
        kind="transformation",
        statement="Proposition 2: eigen-rows m1 (1, M_al D_al/(lam - D_al), M_be D_be/(lam - "
        "D_be)) (54) of "
        "B for two roots of (55) are <, >-orthogonal (47), Q_E Gamma Q_E^T is diagonal (52) and "
        "lam = Lambda_ii/g~_ii (53)",
        system=SUPPORT,
        effects=(),
        build=_bkm12_51,
    ),
    Claim(
        id="BKM12-51/control-swap",
        source=f"{S26} (negative control)",
        kind="transformation",
        statement="the rows with D_al and D_be swapped are <, >-orthogonal",
        system=SUPPORT,
        effects=(),
        build=_bkm12_51_control,
        expected="fails",
    ),
)
