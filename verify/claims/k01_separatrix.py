"""K01 §2.3, §3.3: the ball on M || gamma, the separatrix at h2 and the displacement Delta.

The separatrix solutions (K01-3.4) are checked against the *full* equations of the
``chaplygin_ball__contact_point`` model: the state ``M = C gamma(t), gamma(t), alpha(t),
beta(t)`` is substituted in the model's derived right-hand side and compared with the
time derivative of the formulas. The hyperbolic functions are rational in
``q = exp(-lam t)`` (``th = (1 - q^2)/(1 + q^2)``, ``sech = 2 q/(1 + q^2)``,
``d/dt = -lam q d/dq + kap d/dphi``, ``phi = kap t``); ``cos(phi), sin(phi)`` are the
verifier's circle generators. The square roots ``s32 = sqrt(a32/a31)``,
``s21 = sqrt(a21/a31)``, ``sqrt(a21 a32)`` are made rational by a parametrisation of the
ordered inertias: ``s32 = cos(theta)``, ``s21 = sin(theta)`` (a circle generator of the
verifier, ``s32^2 + s21^2 = 1``), ``1/J2 = 1/J3 + s32^2 (1/J1 - 1/J3)``, ``I2 = J2 - D``,
so ``sqrt(a21 a32) = (1/J1 - 1/J3) s32 s21``. With ``I1 < I3`` and ``0 < theta < pi/2``
this maps onto the region ``I1 < I2 < I3``, and there the square roots are the positive
ones; a rational identity in ``(I1, I3, D, b, C, q)`` and the two circle generators,
proved by the Groebner normal form, therefore holds for every ``I1 < I2 < I3``. (A
refutation's witness may lie outside that region: it shows the rational function is not
zero, hence not zero almost everywhere inside.)

Numerical claims (the quadrature of (3.7) against the closed form, the values of Fig. 4)
compute their residuals with mpmath at 50 digits and are decided with method ``numeric``.
"""

from __future__ import annotations

from functools import lru_cache

import mpmath
import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.vectors import cross, dot

from .base import Check, Claim, register
from .notation import ball_notation

BALL = "chaplygin_ball"
CONTACT = ("contact_point",)
S33 = "K01 §3.3"

C, q = sp.symbols("C q", positive=True)
phi, theta = sp.symbols("phi theta", real=True)
TH = (1 - q**2) / (1 + q**2)
SECH = 2 * q / (1 + q**2)


def _ordered_inertia(model: Model) -> dict:
    """The parametrisation of ``I1 < I2 < I3`` (module docstring) and derived quantities."""
    n = ball_notation(model)
    D = n.D
    u, v = sp.cos(theta), sp.sin(theta)  # s32, s21: on the circle u^2 + v^2 = 1
    I = n.I
    J1, J3 = I[0] + D, I[2] + D
    d31 = 1 / J1 - 1 / J3
    inv_J2 = 1 / J3 + u**2 * d31  # a32/a31 = s32^2
    J2 = 1 / inv_J2
    return {
        "n": n,
        "sub": {I[1]: J2 - D},
        "s32": u,
        "s21": v,
        "J2": J2,
        "I2": J2 - D,
        "sqrt_a21a32": d31 * u * v,
    }


def _solution(form: str, P: dict):
    """``(gamma, alpha, beta, lam, kap, Cval)`` of a K01-3.4 form, in q and phi."""
    s32, s21, J2, I2 = P["s32"], P["s21"], P["J2"], P["I2"]
    c, s = sp.cos(phi), sp.sin(phi)
    if form == "corrected":  # FORMULAS.md K01-3.4fix, C > 0
        Cv = C
        gamma = sp.Matrix([-s32 * SECH, TH, -s21 * SECH])
        alpha = sp.Matrix([s32 * TH * c - s21 * s, SECH * c, s21 * TH * c + s32 * s])
        beta = sp.Matrix([s32 * TH * s + s21 * c, SECH * s, s21 * TH * s - s32 * c])
    else:  # the printed form; "literal": with C > 0, "negative": with C = -|C| < 0
        Cv = C if form == "literal" else -C
        gamma = sp.Matrix([s32 * SECH, -TH, s21 * SECH])
        alpha = sp.Matrix([s32 * TH * c + s21 * s, SECH * c, s21 * TH * c - s32 * s])
        beta = sp.Matrix([s32 * TH * s - s21 * c, SECH * s, s21 * TH * s + s32 * c])
    lam = sp.Abs(Cv) * J2 / I2 * P["sqrt_a21a32"]  # lam = |C| J2/I2 sqrt(a32 a21)
    lam = lam.subs(sp.Abs(-C), C).subs(sp.Abs(C), C)
    kap = Cv / I2
    return gamma, alpha, beta, lam, kap, Cv


def _d_dt(expr, lam, kap):
    return -lam * q * sp.diff(expr, q) + kap * sp.diff(expr, phi)


def _substituted_rhs(model: Model, P: dict, gamma, alpha, beta, Cv) -> dict:
    n = P["n"]
    values = {}
    for vec, val in ((n.M, Cv * gamma), (n.gamma, gamma), (n.alpha, alpha), (n.beta, beta)):
        values.update({vec[i]: val[i] for i in range(3)})
    values.update(P["sub"])
    rhs = model.rhs_expanded
    return {s: rhs[i].xreplace(values) for i, s in enumerate(model.state)}, values


def _k01_3_4(form: str):
    def build(model: Model) -> Check:
        P = _ordered_inertia(model)
        n = P["n"]
        gamma, alpha, beta, lam, kap, Cv = _solution(form, P)
        rhs, _ = _substituted_rhs(model, P, gamma, alpha, beta, Cv)
        exprs = []
        for vec, val in ((n.M, Cv * gamma), (n.gamma, gamma), (n.alpha, alpha), (n.beta, beta)):
            exprs += [_d_dt(val[i], lam, kap) - rhs[vec[i]] for i in range(3)]
        # on the phase space: unit gamma, orthonormal right-handed frame (alpha, beta, gamma)
        exprs += [dot(gamma, gamma) - 1, dot(alpha, alpha) - 1, dot(beta, beta) - 1]
        exprs += [dot(alpha, beta)] + list(cross(alpha, beta) - gamma)
        # and at the energy of the middle axis
        omega = sp.Matrix([model.expand_aux(w) for w in n.omega]).xreplace(
            _substituted_rhs(model, P, gamma, alpha, beta, Cv)[1]
        )
        exprs.append(Cv * dot(gamma, omega) / 2 - Cv**2 / (2 * P["I2"]))
        return Check(
            exprs,
            note="the model's derived right-hand side at M = C gamma(t), gamma, alpha, beta; "
            "rational in q = exp(-lam t), I1 < I2 < I3 parametrised rationally",
        )

    return build


def _k01_3_5(model: Model) -> Check:
    P = _ordered_inertia(model)
    n = P["n"]
    gamma, alpha, beta, lam, kap, Cv = _solution("corrected", P)
    rhs, values = _substituted_rhs(model, P, gamma, alpha, beta, Cv)
    b = n.b.xreplace(values)
    x, y = model.group("x")[0], model.group("y")[0]
    nu = -b * lam
    return Check(
        [rhs[x] - nu * sp.cos(phi) * SECH, rhs[y] - nu * sp.sin(phi) * SECH],
        note="on the corrected K01-3.4 solution; nu = -b lam (|nu| = a lam, the sign is "
        "the orientation of that frame)",
    )


def _k01_3_6(model: Model) -> Check:
    """x' is even and y' odd in t along the separatrix: y(+oo) = y(-oo), Delta = x(oo) - x(-oo).

    ``t -> -t`` is ``q -> 1/q``, ``phi -> -phi``; the model's x', y' on the corrected K01-3.4
    solution, so ``int y' dt = 0`` over the real line and ``Delta = 2 int_0^oo x' dt``.
    """
    P = _ordered_inertia(model)
    gamma, alpha, beta, lam, kap, Cv = _solution("corrected", P)
    rhs, _ = _substituted_rhs(model, P, gamma, alpha, beta, Cv)
    x, y = model.group("x")[0], model.group("y")[0]
    flip = {q: 1 / q, phi: -phi}
    return Check(
        [rhs[x] - rhs[x].xreplace(flip), rhs[y] + rhs[y].xreplace(flip)],
        note="t -> -t is q -> 1/q, phi -> -phi",
    )


def _k01_2_34(model: Model) -> Check:
    """On M x gamma = 0: J omega = l gamma, l = C + 2 D h/C; gamma' = gamma x omega there.

    With ``C`` and ``h`` first integrals (K01-2.3, proved) ``l`` is constant, so
    ``(J omega)' = l gamma' = l gamma x omega = J omega x omega`` (the Euler equations).
    """
    n = ball_notation(model)
    w = model.expand_aux(n.omega)
    Cv = dot(n.M, n.gamma)
    h = dot(n.M, w) / 2
    l = Cv + 2 * n.D * h / Cv
    f = model.rhs_expanded
    gamma_rate = sp.Matrix([f[model.state.index(s)] for s in n.gamma])
    exprs = list(n.J * w - l * n.gamma) + list(gamma_rate - cross(n.gamma, w))
    exprs += [dot(n.M, n.M) - Cv**2]
    return Check(
        exprs,
        on=list(cross(n.M, n.gamma)),
        note="checked on the invariant set M x gamma = 0; the Euler form follows with C, h "
        "integrals (K01-2.3)",
    )


def _h_on_segment(model: Model):
    n = ball_notation(model)
    w = model.expand_aux(n.omega)
    Cv = dot(n.M, n.gamma)
    return n, Cv, dot(n.M, w) / 2


def _k01_3_3seg(model: Model) -> Check:
    """h = C^2/(2 (1/g - D)), g = (gamma, J^-1 gamma) in [1/J3, 1/J1]; ends on p1, p3."""
    n, Cv, h = _h_on_segment(model)
    g = dot(n.gamma, n.A * n.gamma)
    exprs = [h - Cv**2 / (2 * (1 / g - n.D))]
    Cs = sp.Symbol("C", positive=True)
    for i in range(3):
        e = sp.Matrix([1 if j == i else 0 for j in range(3)])
        vals = {n.gamma[j]: e[j] for j in range(3)} | {n.M[j]: Cs * e[j] for j in range(3)}
        h_axis = h.xreplace(vals)
        p_i = (Cs**2 + n.D * Cs**2 / n.I[i]) / (2 * n.J[i, i])  # K01-3.2c at n = C^2
        exprs += [h_axis - Cs**2 / (2 * n.I[i]), h_axis - p_i]
    return Check(
        exprs,
        on=list(cross(n.M, n.gamma)),
        note="h is increasing in g = (gamma, A gamma), whose range on the sphere is "
        "[1/J3, 1/J1] (its values at e3, e1): the segment runs from p3 to p1",
    )


def _k01_3_3seg_literal(model: Model) -> Check:
    """The lower end of the segment (gamma = e3) lies on p2 (the printed 'p1 and p2')."""
    n, _, h = _h_on_segment(model)
    Cs = sp.Symbol("C", positive=True)
    vals = {n.gamma[j]: (1 if j == 2 else 0) for j in range(3)}
    vals |= {n.M[j]: Cs * (1 if j == 2 else 0) for j in range(3)}
    p2 = (Cs**2 + n.D * Cs**2 / n.I[1]) / (2 * n.J[1, 1])
    return Check([h.xreplace(vals) - p2])


# ------------------------------------------------------------ numerical claims
def _fig4_cases():
    return (("1", "3/2", "2"), "0.002858"), (("1", "3", "5"), "0.411829")


@lru_cache(maxsize=16)
def _delta_numbers(I, D="1", b="1", dps=42):
    from chaplygin.numerics.ball.separatrix import delta_closed_form, delta_quadrature, mu_of

    with mpmath.workdps(dps):
        Iv = [mpmath.mpf(sp.Rational(x).p) / sp.Rational(x).q for x in I]
        Dv, bv = mpmath.mpf(sp.Rational(D)), mpmath.mpf(sp.Rational(b))
        mu = mu_of(Iv, Dv)
        return mu, delta_quadrature(mu, bv, dps), delta_closed_form(mu, bv, dps)


_SAMPLES_3_7 = (("1", "3", "5"), ("3/10", "7/5", "9"))


def _k01_3_7(form: str):
    def build(model: Model) -> Check:
        exprs = []
        with mpmath.workdps(50):
            for I in _SAMPLES_3_7:
                mu, quad, closed = _delta_numbers(I)
                if form == "control":
                    closed = mpmath.pi / mpmath.cosh(mpmath.pi * mu)
                exprs.append(sp.Float(mpmath.nstr(quad / closed - 1, 60), 60))
        return Check(
            exprs,
            method="numeric",
            note="Delta/(closed form) - 1 at I = (1,3,5), (0.3,1.4,9), D = b = 1; Delta by "
            "Gauss-Legendre between the zeros of cos(mu s) at 52 digits",
        )

    return build


def _k01_fig4(model: Model) -> Check:
    exprs = []
    with mpmath.workdps(50):
        for I, printed in _fig4_cases():
            _, quad, closed = _delta_numbers(I)
            for value in (quad, closed):
                truncated = sp.Rational(int(mpmath.floor(value * 10**6)), 10**6)
                exprs.append(truncated - sp.Rational(printed))
    return Check(
        [sp.Float(e, 50) for e in exprs],
        method="numeric",
        note="Delta (quadrature and closed form, 50 digits) truncated to 6 decimals "
        "minus the printed value; D = b = C = 1",
    )


def _k01_fig6(model: Model) -> Check:
    """Fig. 6: h_i = C^2/(2 I_i) from the model at M = C e_i, gamma = e_i (C = 1)."""
    n, _, h = _h_on_segment(model)
    exprs = []
    for I, expected in (
        (("1", "3", "5"), ("1/2", "1/6", "1/10")),
        (("1", "3/2", "2"), ("1/2", "1/3", "1/4")),
    ):
        for i in range(3):
            vals = {n.gamma[j]: int(j == i) for j in range(3)}
            vals |= {n.M[j]: int(j == i) for j in range(3)}
            vals |= {n.I[j]: sp.Rational(I[j]) for j in range(3)} | {n.D: 1}
            exprs.append(h.xreplace(vals) - sp.Rational(expected[i]))
    # the printed energies lie on the segment [h3, h1] next to the h_i named in FORMULAS.md
    tol = sp.Rational(1, 1000)
    for value, near in (
        ("0.4993", "1/2"),
        ("0.1002", "1/10"),
        ("0.16667", "1/6"),
        ("0.33335", "1/3"),
    ):  # (a), (b), (d) for (1, 3, 5); (e) for (1, 1.5, 2)
        gap = abs(sp.Rational(value) - sp.Rational(near))
        exprs.append(sp.Max(0, gap - tol))
    return Check(exprs, everywhere=True, note="exact rational values at the principal axes")


register(
    Claim(
        id="K01-2.34",
        source="K01 §2.3",
        kind="equation",
        statement="on M = C gamma: (M, M) = C^2, J omega = (C + 2 D h/C) gamma, "
        "J omega' = J omega x omega (Euler equations)",
        system=BALL,
        effects=(),
        build=_k01_2_34,
    )
)
register(
    Claim(
        id="K01-3.3seg",
        source=S33,
        kind="equation",
        statement="on n = C^2 (M || gamma): h = C^2/(2 (1/(gamma, A gamma) - D)) runs over "
        "[C^2/(2 I3), C^2/(2 I1)]; at gamma = e_i, h = h_i = C^2/(2 I_i) on p_i "
        "(K01-3.2c at n = C^2)",
        system=BALL,
        effects=(),
        build=_k01_3_3seg,
    )
)
register(
    Claim(
        id="K01-3.3seg/literal",
        source=f"{S33} as printed",
        kind="equation",
        statement="the segment n = C^2 is bounded by the branches p1 and p2: its lower end "
        "(gamma = e3) lies on p2",
        system=BALL,
        effects=(),
        build=_k01_3_3seg_literal,
        expected="fails",
    )
)
register(
    Claim(
        id="K01-3.4",
        source=f"{S33}, eq. (3.4), corrected for C > 0",
        kind="solution",
        statement="C > 0, h = C^2/(2 I2): M = C gamma, gamma = (-s32 sech, th, -s21 sech), "
        "alpha = (s32 th c - s21 s, sech c, s21 th c + s32 s), "
        "beta = (s32 th s + s21 c, sech s, s21 th s - s32 c), sech = 1/ch(lam t), "
        "th = th(lam t), c = cos(kap t), s = sin(kap t), s_ij = sqrt(a_ij/a31), "
        "kap = C/I2, lam = C J2/I2 sqrt(a32 a21) solves M' = M x omega, gamma' = gamma x omega, "
        "alpha' = alpha x omega, beta' = beta x omega",
        system=BALL,
        effects=CONTACT,
        build=_k01_3_4("corrected"),
    )
)
register(
    Claim(
        id="K01-3.4/literal",
        source=f"{S33}, eq. (3.4) as printed, with C > 0",
        kind="solution",
        statement="C > 0: gamma = (s32 sech, -th, s21 sech), alpha = (s32 th c + s21 s, sech c, "
        "s21 th c - s32 s), beta = (s32 th s - s21 c, sech s, s21 th s + s32 c) solves the "
        "equations",
        system=BALL,
        effects=CONTACT,
        build=_k01_3_4("literal"),
        expected="fails",
    )
)
register(
    Claim(
        id="K01-3.4neg",
        source=f"{S33}, eq. (3.4) as printed, with C < 0",
        kind="solution",
        statement="C < 0 (M antiparallel to gamma), lam = |C| J2/I2 sqrt(a32 a21), kap = C/I2: the "
        "printed gamma, alpha, beta solve the equations",
        system=BALL,
        effects=CONTACT,
        build=_k01_3_4("negative"),
    )
)
register(
    Claim(
        id="K01-3.5",
        source=f"{S33}, eq. (3.5)",
        kind="equation",
        statement="on the separatrix (K01-3.4): x' = nu cos(kap t)/ch(lam t), "
        "y' = nu sin(kap t)/ch(lam t), nu = -b lam (|nu| = a lam)",
        system=BALL,
        effects=CONTACT,
        build=_k01_3_5,
    )
)
register(
    Claim(
        id="K01-3.6",
        source=f"{S33}, eq. (3.6)",
        kind="equation",
        statement="x(t) = nu int_{-oo}^t cos(kap s)/ch(lam s) ds, y(t) = nu int_{-oo}^t sin(kap "
        "s)/ch(lam s) "
        "ds: x' even, y' odd in t, so y(+oo) = 0 and x(+oo) = Delta = 2 nu int_0^oo ...",
        system=BALL,
        effects=CONTACT,
        build=_k01_3_6,
    )
)
register(
    Claim(
        id="K01-3.7",
        source=f"{S33}, eqs. (3.6), (3.7)",
        kind="value",
        statement="|Delta| = |nu| int cos(kap t)/ch(lam t) dt = pi a/ch(pi xi/2), "
        "xi = mu = kap/lam = 1/(J2 sqrt(a21 a32))",
        system=BALL,
        effects=CONTACT,
        build=_k01_3_7("closed"),
    )
)
register(
    Claim(
        id="K01-3.7/control-ch(pi xi)",
        source=f"{S33} (negative control)",
        kind="value",
        statement="|Delta| = pi a/ch(pi xi) (the factor 1/2 dropped)",
        system=BALL,
        effects=CONTACT,
        build=_k01_3_7("control"),
        expected="fails",
    )
)
register(
    Claim(
        id="K01-Fig4",
        source=f"{S33}, Fig. 4",
        kind="value",
        statement="Delta = 0.002858 for I = (1, 1.5, 2) and 0.411829 for I = (1, 3, 5) "
        "(D = 1, a = 1, C = 1; printed values truncated to 6 decimals)",
        system=BALL,
        effects=CONTACT,
        build=_k01_fig4,
    )
)
register(
    Claim(
        id="K01-Fig6",
        source=f"{S33}, Fig. 6",
        kind="value",
        statement="the energies of Fig. 6 sit next to h_i = C^2/(2 I_i) on n = C^2: I = (1, 3, 5): "
        "h1 = 1/2 (0.4993), h3 = 1/10 (0.1002), h2 = 1/6 (0.16667); I = (1, 1.5, 2): "
        "h2 = 1/3 (0.33335)",
        system=BALL,
        effects=(),
        build=_k01_fig6,
    )
)
