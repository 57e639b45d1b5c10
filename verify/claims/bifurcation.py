"""Bifurcation curves, periodic and critical solutions: BKM12 §1.5, §2.7 and K01 §3.1-3.2.

The curves are compared with what ``derive/bifurcation.py`` derives from the model (the
steady rotations ``omega = w e_i``, their integrals, the parameters eliminated); the
solutions are substituted into the model's own right-hand side (``sin``/``cos`` of time
are generators on the unit circle for the verifier), so "solves the equations" is a proof.
The Floquet multipliers of these solutions (BKM12-1.5stab, 1.5stab8) are numerical by
nature: they are computed by ``numerics/ball/stability.py`` and asserted in
``tests/numerics/ball/test_bifurcation.py``, not registered here.
"""

from __future__ import annotations

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.bifurcation import (
    bifurcation_curve,
    family_integrals,
    multiple_root_locus,
    steady_rotation,
)
from chaplygin.derive.vectors import cross, dot

from .base import Check, Claim, register
from .notation import ball_notation

BALL = "chaplygin_ball"
SUPPORT = "spherical_support"
S15 = "BKM12 §1.5"
S27 = "BKM12 §2.7"
K32 = "K01 §3.2"

# free symbols of the checks
_E, _C = sp.symbols("E C", real=True)
_Mg = sp.Symbol("M_gamma", real=True)
_c = sp.Symbol("c", positive=True)  # sqrt(C)
_w = sp.Symbol("w", real=True)
_k, _rho = sp.symbols("k rho", positive=True)
_phi = sp.Symbol("phi", real=True)
_m = sp.Symbol("m", real=True)


def _e(i: int) -> sp.Matrix:
    return sp.Matrix([1 if j == i else 0 for j in range(3)])


def _solution_residual(model: Model, state: dict) -> list[sp.Expr]:
    """``d/dt state(t) - f(state(t))`` for every state variable of the model."""
    t = model.time
    f = model.rhs_expanded.xreplace(state)
    return [sp.diff(state[s], t) - f[k] for k, s in enumerate(model.state)]


def _steady_residual(model: Model, fam) -> list[sp.Expr]:
    """:func:`_solution_residual` of a steady-rotation family, at ``t = 0``.

    The family at time ``t`` starting from the vectors ``v0`` is the family at time 0
    starting from ``R(-w t) v0``, again a point of the phase space (the model's symbols
    range over all of it), and the system is autonomous: the residual at ``t = 0`` for
    every ``v0`` is the residual at every time. This keeps sin/cos out of the (large)
    right-hand side of the support.
    """
    t = model.time
    at0 = {t: 0}
    state0 = {s: e.xreplace(at0) for s, e in fam.state.items()}
    f = model.rhs_expanded.xreplace(state0)
    return [sp.diff(fam.state[s], t).xreplace(at0) - f[k] for k, s in enumerate(model.state)]


def _omega_at(model: Model, state: dict) -> sp.Matrix:
    return model.expand_aux(sp.Matrix(model.omega)).xreplace(state)


def _sigma(n, i: int, C, Mg) -> sp.Expr:
    """BKM12 Sigma_i as printed (reconstructed): ``A_i C + A_i^2 M_gamma^2/(D^-1 - A_i)``."""
    A = n.A[i, i]
    return A * C + A**2 * Mg**2 / (1 / n.D - A)


# ----------------------------------------------------------------- the ball, M_gamma = 0
def _bkm12_1_5R(model: Model) -> Check:
    """Multiple roots of R(x) = Phi(x)((C - E D) x - E D), a_i = D/I_i: E = A_i C."""
    n = ball_notation(model)
    derived = multiple_root_locus(tuple(n.D / n.I[i] for i in range(3)), n.D, _E, _C)
    with_E = [f for f in derived if f.has(_E)]
    without = [f for f in derived if not f.has(_E)]
    printed = [_E - n.A[i, i] * _C for i in range(3)]
    exprs = [sp.Mul(*with_E) - sp.Mul(*printed), sp.Integer(len(with_E) - 3)]
    # the only other factor is C itself (the trivial level M = 0)
    exprs += [sp.Mul(*without) - _C]
    return Check(exprs, free=[_E, _C])


def _bkm12_24(model: Model) -> Check:
    n = ball_notation(model)
    exprs = [bifurcation_curve(model, i).xreplace({_Mg: 0}) - n.A[i, i] * _C for i in range(3)]
    return Check(exprs, free=[_C])


def _bkm12_25(sign_of_phase: int):
    """The six families M = s sqrt(C) e_i, gamma = cos(phi) e_j + sin(phi) e_k.

    ``sign_of_phase = -1``: phi = -s A_i sqrt(C) t (FORMULAS.md); ``+1``: as printed.
    """

    def build(model: Model) -> Check:
        n = ball_notation(model)
        t = model.time
        exprs = []
        for i in range(3):
            j, k = (i + 1) % 3, (i + 2) % 3
            A = n.A[i, i]
            for s in (1, -1):
                phi = sign_of_phase * s * A * _c * t
                M = s * _c * _e(i)
                gamma = sp.cos(phi) * _e(j) + sp.sin(phi) * _e(k)
                state = dict(zip(n.M, M, strict=True)) | dict(zip(n.gamma, gamma, strict=True))
                exprs += _solution_residual(model, state)
                w = _omega_at(model, state)
                exprs += list(w - s * A * _c * _e(i))
                exprs += [dot(M, w) - A * _c**2, dot(M, gamma)]  # on the line (24)
        return Check(exprs, free=[_c])

    return build


# ------------------------------------------------------------ the ball, general M_gamma
def _family_values(model: Model, i: int):
    fam = steady_rotation(model, i, _w)
    vals = family_integrals(model, fam)
    return fam, vals["E"], vals["C"], vals["(M,gamma)"]


def _sigma_i(coefficient=1, axes=(0, 1, 2)):
    def build(model: Model) -> Check:
        n = ball_notation(model)
        exprs = []
        for i in axes:
            A = n.A[i, i]
            printed = A * _C + coefficient * A**2 * _Mg**2 / (1 / n.D - A)
            if coefficient == 1:  # the eliminated curve, derived from the model
                exprs.append(bifurcation_curve(model, i) - printed)
            _, E, C, Mg = _family_values(model, i)
            exprs.append(E - printed.xreplace({_C: C, _Mg: Mg}))
        return Check(exprs, free=[_C, _Mg, _w])

    return build


def _bkm12_crit(model: Model) -> Check:
    """Steady rotations about e_i with any gamma(0): exact solutions and (25)-(26) relations."""
    n = ball_notation(model)
    exprs = []
    for i in range(3):
        fam, E, C, Mg = _family_values(model, i)
        exprs += _steady_residual(model, fam)
        state = {s: e.xreplace({model.time: 0}) for s, e in fam.state.items()}
        A = n.A[i, i]
        lam = _w / A  # omega = lambda A_i e_i
        M, gamma = fam.M.xreplace(state), fam.vectors["gamma"].xreplace(state)
        Z = model.expand_aux(n.Z).xreplace(state)
        Mi, gi = M[i], gamma[i]
        Dinv = 1 / n.D
        exprs += list(_omega_at(model, state) - lam * A * _e(i))
        exprs += list(M + Z * gamma - lam * _e(i))
        exprs += [
            C + Z * Mg - lam * Mi,
            Mg + Z - lam * gi,
            Mi + Z * gi - lam,
            Dinv * Z - A * lam * gi,
            lam * Mi - (C + A * Mg**2 / (Dinv - A)),
            lam * gi - Dinv * Mg / (Dinv - A),
            lam**2 - (C + (2 * Dinv - A) * A * Mg**2 / (Dinv - A) ** 2),
            Z - A * Mg / (Dinv - A),
            E - lam * A * Mi,
        ]
        # M_perp = -Z gamma_perp (components j, k)
        exprs += [M[j] + Z * gamma[j] for j in range(3) if j != i]
    return Check(exprs, free=[_w])


def _bkm12_sigma45(model: Model) -> Check:
    """On M = M_gamma gamma: gamma' = gamma x A~ gamma, A~ = M_gamma (1 + E D/C) A."""
    n = ball_notation(model)
    f = model.rhs_expanded
    w = model.expand_aux(n.omega)
    E = dot(n.M, w)
    C = _m**2
    rate = {s: f[k] for k, s in enumerate(model.state)}
    g_rate = sp.Matrix([rate[s] for s in n.gamma])
    M_rate = sp.Matrix([rate[s] for s in n.M])
    At = _m * (1 + E * n.D / C) * n.A
    exprs = list(M_rate - _m * g_rate)  # the set M = M_gamma gamma is invariant
    exprs += list(g_rate - cross(n.gamma, At * n.gamma))
    exprs += [dot(n.gamma, n.A * n.gamma) - E / (C + E * n.D)]
    exprs += [dot(n.M, n.M) - C, dot(n.M, n.gamma) - _m]
    return Check(exprs, free=[_m], on=list(n.M - _m * n.gamma))


def _bkm12_fig3(model: Model) -> Check:
    """E' = E D/C, g = M_gamma/sqrt(C): Sigma_i <-> E' = b_i + b_i^2 g^2/(1 - b_i)."""
    n = ball_notation(model)
    g = sp.Symbol("g", real=True)
    exprs = []
    for i in range(3):
        b = n.D * n.A[i, i]
        sig = _sigma(n, i, _c**2, g * _c)
        exprs.append(sig * n.D / _c**2 - (b + b**2 * g**2 / (1 - b)))
        exprs.append((b + b**2 / (1 - b)) - b / (1 - b))  # Sigma_4 meets Sigma_i
    # Sigma_4, Sigma_5 (g = +-1) are the sets M = M_gamma gamma: there
    # E'/(1 + E') = D (gamma, A gamma), in [b_min, b_max] (FORMULAS.md: found)
    w = model.expand_aux(n.omega)
    E = dot(n.M, w)
    Ep = E * n.D / _m**2
    exprs.append(Ep / (1 + Ep) - n.D * dot(n.gamma, n.A * n.gamma))
    return Check(exprs, free=[_c, g, _m], on=list(n.M - _m * n.gamma))


def _bkm12_1_5a(model: Model) -> Check:
    """(22): M~ = rho (cos phi M - k sin phi gamma): (M~, M~) and E~ = E m1^2 + m2^2/D."""
    n = ball_notation(model)
    Mt = _rho * (sp.cos(_phi) * n.M - _k * sp.sin(_phi) * n.gamma)
    C, Mg = dot(n.M, n.M), dot(n.M, n.gamma)
    printed_C = (
        _rho**2 / 2 * (C + _k**2 + (C - _k**2) * sp.cos(2 * _phi) - 2 * _k * Mg * sp.sin(2 * _phi))
    )
    m1, m2 = _rho * sp.cos(_phi), -_k * _rho * sp.sin(_phi)
    E = _k**2 / n.D  # k^2 = E D (BKM12-1.4a)
    exprs = [
        sp.expand_trig(dot(Mt, Mt) - printed_C),
        E * m1**2 + m2**2 / n.D - _k**2 * _rho**2 / n.D,  # BKM12-20 on the level
    ]
    return Check(exprs, free=[_rho, _k, _phi])


def _bkm12_26(control: bool = False):
    """E~ = A_i C~ and (M~, gamma~) = 0 imply (k^2 - D A_i C)(1 - D A_i) = D^2 A_i^2 M_gamma^2.

    The hypotheses are linear in M_gamma and C: with u = 2 phi on the circle they are
    solved for them, and the printed relation must then hold identically.
    """

    def build(model: Model) -> Check:
        n = ball_notation(model)
        cs, sn = sp.symbols("cs sn", real=True)  # cos 2phi, sin 2phi (put back below)
        back = {cs: sp.cos(2 * _phi), sn: sp.sin(2 * _phi)}
        exprs = []
        for i in range(3):
            A = n.A[i, i]
            # (M~, gamma~) = rho sigma ((C - k^2) sin 2phi/2 + k M_gamma cos 2phi) = 0
            Mg = -(_C - _k**2) * sn / (2 * _k * cs)
            # E~ = k^2 rho^2/D = A_i C~ (BKM12-1.5a) with this M_gamma, solved for C
            C = sp.Symbol("Cs")
            eq = _k**2 / n.D - A / 2 * (
                C + _k**2 + (C - _k**2) * cs - 2 * _k * Mg.xreplace({_C: C}) * sn
            )
            eq = sp.expand(sp.numer(sp.together(eq))).xreplace({sn**2: 1 - cs**2})
            (Csol,) = sp.solve(eq, C)
            Mg_sol = Mg.xreplace({_C: Csol})
            coef = 2 if control else 1
            printed = (_k**2 - n.D * A * Csol) * (1 - n.D * A) - coef * n.D**2 * A**2 * Mg_sol**2
            exprs.append(printed.xreplace(back))
            if not control:
                # with k^2 = E D it is Sigma_i: D (1 - D A_i)(E - Sigma_i)
                lhs = (_E * n.D - n.D * A * _C) * (1 - n.D * A) - n.D**2 * A**2 * _Mg**2
                exprs.append(lhs - n.D * (1 - n.D * A) * (_E - _sigma(n, i, _C, _Mg)))
        return Check(exprs, free=[_k, _phi, _E, _C, _Mg])

    return build


# ------------------------------------------------------------------------- K01 §3
def _k01_3_1(model: Model) -> Check:
    n = ball_notation(model)
    h, nn = sp.symbols("h n", real=True)
    exprs = []
    for i in range(3):
        curve = bifurcation_curve(model, i).xreplace({_Mg: 0, _C: nn})
        exprs.append(curve / 2 - nn / (2 * (n.I[i] + n.D)))
    return Check(exprs, free=[nn])


def _k01_3_2a(model: Model) -> Check:
    n = ball_notation(model)
    MxG = cross(n.M, n.gamma)
    return Check([dot(n.M, n.M) - dot(n.M, n.gamma) ** 2 - dot(MxG, MxG)])


def _k01_3_2b(model: Model) -> Check:
    """h1/n1 = h/(n - C f) with K01-2.33; on h1/n1 = 1/(2 J_i) (2.32) gives p_i."""
    n = ball_notation(model)
    h, nn, f, C = sp.symbols("h n f C", real=True)
    Q = nn - C**2 + (C - f) ** 2
    n1 = (nn - C**2) / Q
    h1 = h * (nn - C**2) / ((nn - C * f) * Q)
    exprs = [h1 / n1 - h / (nn - C * f)]
    for i in range(3):
        J = n.J[i, i]
        fi = (nn - 2 * h * J) / C  # 2 h/(n - C f) = 1/J_i solved for f
        quad = fi**2 - (nn - 2 * h * n.D) / C * fi - 2 * h * n.D  # (2.32)
        p_i = h - (nn + n.D * C**2 / n.I[i]) / (2 * J)  # K01-3.2c
        exprs.append(quad - (4 * h * J * n.I[i] / C**2) * p_i)
    return Check(exprs, free=[h, nn, f, C])


def _k01_3_2c(model: Model) -> Check:
    n = ball_notation(model)
    h, nn = sp.symbols("h n", real=True)
    exprs = []
    for i in range(3):
        curve = bifurcation_curve(model, i).xreplace({_C: nn})
        exprs.append(curve / 2 - (nn + n.D * _Mg**2 / n.I[i]) / (2 * n.J[i, i]))
    return Check(exprs, free=[nn, _Mg])


_g1 = sp.Symbol("g1", real=True)


def _k01_3_2(sense: int):
    """omega = (w1, 0, 0), gamma = (g1, s cos(w1 t), sense * s sin(w1 t)), s = sqrt(1 - g1^2).

    ``sense = +1``: as printed; ``-1``: corrected. M is the momentum (2.1) of this omega.
    """

    def build(model: Model) -> Check:
        n = ball_notation(model)
        t = model.time
        s = sp.sqrt(1 - _g1**2)
        omega = _w * _e(0)
        gamma = sp.Matrix([_g1, s * sp.cos(_w * t), sense * s * sp.sin(_w * t)])
        M = n.J * omega - n.D * dot(omega, gamma) * gamma  # K01-2.1
        state = dict(zip(n.M, M, strict=True)) | dict(zip(n.gamma, gamma, strict=True))
        exprs = _solution_residual(model, state)
        exprs += list(_omega_at(model, state) - omega)
        return Check(exprs, free=[_w, _g1])

    return build


def _k01_3_3(model: Model) -> Check:
    """w1^2 = (2 I1^2 h + D C^2)/(J1 I1^2), g1^2 = J1 C^2/(2 I1^2 h + D C^2) on p1."""
    n = ball_notation(model)
    fam, E, _, Mg = _family_values(model, 0)
    g1 = model.vectors["gamma"][0]  # gamma_1 is constant along the family
    h = E / 2
    I1, J1 = n.I[0], n.J[0, 0]
    exprs = [
        _w**2 - (2 * I1**2 * h + n.D * Mg**2) / (J1 * I1**2),
        g1**2 - J1 * Mg**2 / (2 * I1**2 * h + n.D * Mg**2),
    ]
    return Check(exprs, free=[_w])


def _k01_3_2y(model: Model) -> Check:
    """alpha || M (C = 0): y' = -b (alpha, omega) = -2 b h/sqrt(n), constant.

    The model's ``y' = -b (alpha, omega)`` (K01-2.6) with ``omega`` kept free: on
    ``M = (M, alpha) alpha`` it is ``-b (M, omega)/(M, alpha) = -2 b h/sqrt(n)``, a ratio of
    integrals (``h``; ``(M, alpha)``, BKM12-7), whatever ``omega`` is.
    """
    n = ball_notation(model)
    y_rate = model.rhs[model.state.index(model.vectors["y"][0])]
    h = dot(n.M, n.omega) / 2
    sqrt_n = dot(n.M, n.alpha)  # alpha = M/|M|
    exprs = [
        y_rate + n.b * dot(n.alpha, n.omega),
        y_rate * sqrt_n + 2 * n.b * h,
        sqrt_n**2 - dot(n.M, n.M),
        dot(n.M, n.gamma),  # C = 0 follows
    ]
    on_set = dict(zip(n.M, _m * n.alpha, strict=True))  # M = m alpha, m = sqrt(n)
    return Check([e.xreplace(on_set) for e in exprs], free=[*n.omega, _m])


# ------------------------------------------------------------ spherical support §2.7
def _support(model: Model):
    I = model.param_group("I")
    D_iso, D_al, D_be = (model.param_group(k)[0] for k in ("D_iso", "D_al", "D_be"))
    J = [I[i] + D_iso for i in range(3)]
    return J, D_al, D_be


def _bkm12_2_7a(variant: str):
    """M = M_al e_i, alpha = e_i, beta = cos(phi) e_j + sin(phi) e_k, gamma = alpha x beta."""

    def build(model: Model) -> Check:
        J, D_al, _ = _support(model)
        t = model.time
        exprs = []
        for i in range(3):
            j, k = (i + 1) % 3, (i + 2) % 3
            A = 1 / J[i]
            if variant == "literal":
                w_i, phi = _m * A, _m * A * t
            else:
                w_i = _m * A / (1 - D_al * A)
                phi = -w_i * t
            alpha = _e(i)
            beta = sp.cos(phi) * _e(j) + sp.sin(phi) * _e(k)
            gamma = cross(alpha, beta)
            vec = {"M": _m * _e(i), "alpha": alpha, "beta": beta, "gamma": gamma}
            state = {
                s: e for name, v in vec.items() for s, e in zip(model.vectors[name], v, strict=True)
            }
            exprs += _solution_residual(model, state)
            exprs += list(_omega_at(model, state) - w_i * _e(i))
            if variant == "curve":
                E = dot(vec["M"], _omega_at(model, state))
                exprs += [E - A * _m**2 / (1 - D_al * A), E - _m**2 / (J[i] - D_al)]
        return Check(exprs, free=[_m])

    return build


def _aux_chain(model: Model, state: dict, omega: sp.Matrix) -> tuple[list, sp.Matrix]:
    """The model's auxiliaries at ``state`` equal their values on ``omega = w e_i``.

    Each auxiliary (``Z_al, Z_be``, then ``omega``) is compared with its expected value,
    the later ones written with the earlier expected values: a chain of small residuals
    instead of one expansion of the right-hand side through the 2x2 inverse. The
    expected ``Z_x = D_x (x, omega)`` come from ``M = J omega - sum_x D_x (x, omega) x``.
    """
    expected: dict[sp.Symbol, sp.Expr] = {}
    for x in ("alpha", "beta"):
        D_x = model.param_group("D_al" if x == "alpha" else "D_be")[0]
        vec = sp.Matrix([e for s, e in state.items() if s in set(model.vectors[x])])
        expected[sp.Symbol(f"Z_{x[:2]}", real=True)] = D_x * dot(vec, omega)
    expected.update(dict(zip(model.omega, omega, strict=True)))
    out = []
    for sym, expr in model.aux:
        out.append(expr.xreplace(state).xreplace(expected) - expected[sym])
    # the right-hand side with the auxiliaries at their (now proved) values
    f = sp.Matrix(model.rhs).xreplace(state).xreplace(expected)
    return out, f


def _bkm12_2_7b(axes=(0, 1, 2)):
    def build(model: Model) -> Check:
        """Steady rotations about e_i with any frame: exact solutions, relations, surfaces."""
        J, D_al, D_be = _support(model)
        t = model.time
        exprs = []
        for i in axes:
            fam = steady_rotation(model, i, _w)
            vals = family_integrals(model, fam)
            E, C = vals["E"], vals["C"]
            Mal, Mbe, Mga = vals["(M,alpha)"], vals["(M,beta)"], vals["(M,gamma)"]
            state = {s: e.xreplace({t: 0}) for s, e in fam.state.items()}
            chain, f = _aux_chain(model, state, fam.omega)
            exprs += chain
            # at t = 0 for every frame, hence at every t (see _steady_residual)
            exprs += [
                sp.diff(fam.state[s], t).xreplace({t: 0}) - f[k] for k, s in enumerate(model.state)
            ]
            A = 1 / J[i]
            lam = _w / A
            M, al, be = (
                x.xreplace(state) for x in (fam.M, fam.vectors["alpha"], fam.vectors["beta"])
            )
            Zal, Zbe = D_al * dot(al, fam.omega), D_be * dot(be, fam.omega)  # = the model's (chain)
            exprs += list(M + Zal * al + Zbe * be - lam * _e(i))
            ial, ibe = 1 / D_al, 1 / D_be
            exprs += [
                lam**2
                - (
                    C
                    + (2 * ial - A) * A * Mal**2 / (ial - A) ** 2
                    + (2 * ibe - A) * A * Mbe**2 / (ibe - A) ** 2
                ),
                lam * M[i] - (C + A * Mal**2 / (ial - A) + A * Mbe**2 / (ibe - A)),
                lam * al[i] - ial * Mal / (ial - A),
                lam * be[i] - ibe * Mbe / (ibe - A),
                Zal - A * Mal / (ial - A),
                Zbe - A * Mbe / (ibe - A),
            ]
            surface = A * C + A**2 * Mal**2 / (ial - A) + A**2 * Mbe**2 / (ibe - A)
            exprs += [
                E - surface,
                surface - (Mal**2 / (J[i] - D_al) + Mbe**2 / (J[i] - D_be) + Mga**2 / J[i]),
            ]
        return Check(exprs, free=[_w])

    return build


def _bkm12_2_7c(model: Model) -> Check:
    """E' = E/C, g_x = M_x/sqrt(C): sum g_x^2/(J_i^0 - D_x0) = E' on sum g_x^2 = 1."""
    J, D_al, D_be = _support(model)
    exprs = []
    for i in range(3):
        fam = steady_rotation(model, i, _w)
        vals = family_integrals(model, fam)
        C = vals["C"]
        g = [vals[f"(M,{x})"] / sp.sqrt(C) for x in ("alpha", "beta", "gamma")]
        Ep = vals["E"] / C
        exprs += [
            g[0] ** 2 / (J[i] - D_al) + g[1] ** 2 / (J[i] - D_be) + g[2] ** 2 / J[i] - Ep,
            g[0] ** 2 + g[1] ** 2 + g[2] ** 2 - 1,
        ]
    return Check(exprs, free=[_w])


_CLAIMS = [
    Claim(
        id="BKM12-1.5R",
        source=S15,
        kind="equation",
        statement="R(x) = Phi(x)((C - E D) x - E D), Phi(x) = (1 + x)(a1 - x)(a2 - x)(a3 - x), a_i "
        "= D/I_i, "
        "has a multiple root exactly on E = A_i C (and on the trivial level C = 0)",
        system=BALL,
        effects=(),
        build=_bkm12_1_5R,
        note="factors of res(Phi, (C - E D) x - E D) that involve E, C "
        "(disc(Phi L) = disc(Phi) disc(L) res(Phi, L)^2)",
    ),
    Claim(
        id="BKM12-24",
        source=S15,
        kind="equation",
        statement="at M_gamma = 0 the bifurcation curves are E = A_i C, i = 1, 2, 3",
        system=BALL,
        effects=(),
        build=_bkm12_24,
        note="the energy of the steady rotations omega = w e_i with w, gamma_i eliminated "
        "(derive/bifurcation.py), at M_gamma = 0",
    ),
    Claim(
        id="BKM12-25",
        source=S15,
        kind="solution",
        statement="M = s sqrt(C) e_i, gamma = cos(phi) e_j + sin(phi) e_k, phi = -s A_i sqrt(C) t, "
        "omega = s A_i sqrt(C) e_i, (i, j, k) cyclic, s = +-1 (six families) solve (2); "
        "E = A_i C, M_gamma = 0",
        system=BALL,
        effects=(),
        build=_bkm12_25(-1),
        note="substituted into the model's right-hand side; sin/cos of t on the unit circle",
    ),
    Claim(
        id="BKM12-25/literal",
        source=S15,
        kind="solution",
        statement="the six families (25) with the phase as printed, phi = +s A_i sqrt(C) t",
        system=BALL,
        effects=(),
        build=_bkm12_25(+1),
        expected="fails",
        note="FORMULAS.md: the printed phase sign must be opposite to s",
    ),
    Claim(
        id="BKM12-Sigma_i",
        source=S15,
        kind="equation",
        statement="Sigma_i: E = A_i C + A_i^2 M_gamma^2/(D^-1 - A_i), i = 1, 2, 3",
        system=BALL,
        effects=(),
        build=_sigma_i(),
        note="the curve eliminated from the steady rotations, and the energy along them",
    ),
    Claim(
        id="BKM12-Sigma_i/control-coefficient",
        source=f"{S15} (negative control)",
        kind="equation",
        statement="Sigma_2 with a wrong coefficient: E = A_2 C + 2 A_2^2 M_gamma^2/(D^-1 - A_2)",
        system=BALL,
        effects=(),
        build=_sigma_i(coefficient=2, axes=(1,)),
        expected="fails",
    ),
    Claim(
        id="BKM12-crit",
        source=S15,
        kind="solution",
        statement="omega = lambda A_i e_i constant, M + Z gamma = lambda e_i, gamma turning about "
        "e_i: "
        "exact solutions for every gamma(0); C + Z M_gamma = lambda M_i, M_gamma + Z = "
        "lambda gamma_i, M_i + Z gamma_i = lambda, D^-1 Z = A_i lambda gamma_i; lambda M_i = "
        "C + A_i M_gamma^2/(D^-1 - A_i), lambda gamma_i = D^-1 M_gamma/(D^-1 - A_i), "
        "lambda^2 = C + (2 D^-1 - A_i) A_i M_gamma^2/(D^-1 - A_i)^2, Z = A_i M_gamma/(D^-1 - A_i), "
        "E = lambda A_i M_i, M_perp = -Z gamma_perp",
        system=BALL,
        effects=(),
        build=_bkm12_crit,
    ),
    Claim(
        id="BKM12-Sigma45",
        source=S15,
        kind="solution",
        statement="M = M_gamma gamma is invariant, C = M_gamma^2; gamma' = gamma x A~ gamma, "
        "A~ = M_gamma (1 + E D/C) A (Euler equation); (gamma, A gamma) = E/(C + E D)",
        system=BALL,
        effects=(),
        build=_bkm12_sigma45,
        note="checked on the invariant set M = M_gamma gamma",
    ),
    Claim(
        id="BKM12-Fig3",
        source=S15,
        kind="equation",
        statement="E' = E D/C, g = M_gamma/sqrt(C): Sigma_i: E' = b_i + b_i^2 g^2/(1 - b_i), b_i = "
        "D A_i; "
        "Sigma_4,5: g = +-1 (M = M_gamma gamma), where E'/(1 + E') = D (gamma, A gamma); "
        "Sigma_4 meets Sigma_i at E' = b_i/(1 - b_i)",
        system=BALL,
        effects=(),
        build=_bkm12_fig3,
    ),
    Claim(
        id="BKM12-1.5a",
        source=S15,
        kind="transformation",
        statement="with (22), k^2 = E D: E~ = k^2 rho^2 D^-1, (M~, M~) = rho^2/2 (C + k^2 + (C - "
        "k^2) "
        "cos 2phi - 2 k M_gamma sin 2phi)",
        system=BALL,
        effects=(),
        build=_bkm12_1_5a,
        note="E~ = E m1^2 + D^-1 m2^2 is BKM12-20",
    ),
    Claim(
        id="BKM12-26",
        source=S15,
        kind="equation",
        statement="E~ = A_i C~ with (M~, gamma~) = 0 (23) gives (k^2 - D A_i C)(1 - D A_i) = "
        "D^2 A_i^2 M_gamma^2, i.e. Sigma_i for k^2 = E D",
        system=BALL,
        effects=(),
        build=_bkm12_26(),
        note="the hypotheses solved for M_gamma and C (linear), 2 phi on the unit circle",
    ),
    Claim(
        id="BKM12-26/control-factor2",
        source=f"{S15} (negative control)",
        kind="equation",
        statement="(k^2 - D A_i C)(1 - D A_i) = 2 D^2 A_i^2 M_gamma^2 (wrong factor)",
        system=BALL,
        effects=(),
        build=_bkm12_26(control=True),
        expected="fails",
    ),
    Claim(
        id="K01-3.1",
        source="K01 §3.1",
        kind="equation",
        statement="C = 0: p_i: h = n/(2 (I_i + D)), i = 1, 2, 3",
        system=BALL,
        effects=(),
        build=_k01_3_1,
        note="the derived curves with h = E/2, n = (M, M), C = (M, gamma) = 0",
    ),
    Claim(
        id="K01-3.2a",
        source=K32,
        kind="equation",
        statement="n >= C^2: n - C^2 = |M x gamma|^2 on (gamma, gamma) = 1",
        system=BALL,
        effects=(),
        build=_k01_3_2a,
    ),
    Claim(
        id="K01-3.2b",
        source=K32,
        kind="equation",
        statement="h1/n1 = h/(n - C f) (K01-2.33); h1 = n1/(2 J_i) with (2.32) gives p_i",
        system=BALL,
        effects=(),
        build=_k01_3_2b,
        note="(2.32) at f = (n - 2 h J_i)/C is (4 h J_i I_i/C^2) (h - h_i)",
    ),
    Claim(
        id="K01-3.2c",
        source=K32,
        kind="equation",
        statement="p_i: h_i = (n + D C^2/I_i)/(2 J_i), J_i = I_i + D (= BKM12 Sigma_i)",
        system=BALL,
        effects=(),
        build=_k01_3_2c,
    ),
    Claim(
        id="K01-3.2",
        source=K32,
        kind="solution",
        statement="omega = (w1, 0, 0), gamma = (g1, s cos(w1 t), -s sin(w1 t)), s = sqrt(1 - "
        "g1^2), "
        "M = J omega - D (omega, gamma) gamma solve (2.1) (corrected rotation sense)",
        system=BALL,
        effects=(),
        build=_k01_3_2(-1),
    ),
    Claim(
        id="K01-3.2/literal",
        source=K32,
        kind="solution",
        statement="as printed: gamma = (g1, s cos(w1 t), s sin(w1 t)) with omega = (w1, 0, 0)",
        system=BALL,
        effects=(),
        build=_k01_3_2(+1),
        expected="fails",
        note="FORMULAS.md: this solves gamma' = omega x gamma, not (2.1)",
    ),
    Claim(
        id="K01-3.3",
        source=K32,
        kind="equation",
        statement="on p1: w1^2 = (2 I1^2 h + D C^2)/(J1 I1^2), g1^2 = J1 C^2/(2 I1^2 h + D C^2)",
        system=BALL,
        effects=(),
        build=_k01_3_3,
        note="h, C of the steady rotations about e_1",
    ),
    Claim(
        id="K01-3.2y",
        source=K32,
        kind="equation",
        statement="C = 0, alpha = M/|M|: y' = -a (alpha, omega) = -2 a h/sqrt(n) (constant)",
        system=BALL,
        effects=("contact_point",),
        build=_k01_3_2y,
        note="on M = m alpha (alpha || M), sqrt(n) = (M, alpha) = m, omega free",
    ),
    Claim(
        id="BKM12-2.7a",
        source=S27,
        kind="equation",
        statement="M || alpha: E = A_i M_al^2/(1 - D_al A_i) = M_al^2/(J_i^0 - D_al0) on the "
        "steady "
        "rotations M = M_al e_i, alpha = e_i",
        system=SUPPORT,
        effects=(),
        build=_bkm12_2_7a("curve"),
    ),
    Claim(
        id="BKM12-2.7a-sol",
        source=S27,
        kind="solution",
        statement="M = M_al e_i, alpha = e_i, beta = cos(phi) e_j + sin(phi) e_k, "
        "omega = M_al A_i/(1 - D_al A_i) e_i, phi' = -omega_i solve (32)-(34)",
        system=SUPPORT,
        effects=(),
        build=_bkm12_2_7a("solution"),
    ),
    Claim(
        id="BKM12-2.7a-sol/literal",
        source=S27,
        kind="solution",
        statement="as extracted: omega = M_al A_i e_i, phi = A_i M_al t",
        system=SUPPORT,
        effects=(),
        build=_bkm12_2_7a("literal"),
        expected="fails",
        note="FORMULAS.md: the factor 1/(1 - D_al A_i) is missing",
    ),
    *(
        Claim(
            id=f"BKM12-2.7b.e{i + 1}",
            source=S27,
            kind="solution",
            statement=f"i = {i + 1}: omega = lambda A_i e_i, M + Z_al alpha + Z_be beta = lambda "
            f"e_i (any "
            "frame turning about e_i) solve (32)-(34); lambda^2, lambda M_i, lambda alpha_i, "
            "lambda beta_i, Z_al, Z_be as printed; E = A_i C + A_i^2 M_al^2/(D_al^-1 - A_i) + "
            "A_i^2 M_be^2/(D_be^-1 - A_i) = M_al^2/(J_i^0 - D_al0) + M_be^2/(J_i^0 - D_be0) + "
            "M_ga^2/(J_i^0 - D_ga0)",
            system=SUPPORT,
            effects=(),
            build=_bkm12_2_7b((i,)),
            note="J_i^0 - D_x0 = J_i - D_x in the model's parameters (D_ga = 0); the model's "
            "Z_al, Z_be, omega compared one after the other",
        )
        for i in range(3)
    ),
    Claim(
        id="BKM12-2.7c",
        source=S27,
        kind="equation",
        statement="E' = E/C, g_x = M_x/sqrt(C): g_al^2/(J_i^0 - D_al0) + g_be^2/(J_i^0 - D_be0) + "
        "g_ga^2/(J_i^0 - D_ga0) = E' on g_al^2 + g_be^2 + g_ga^2 = 1",
        system=SUPPORT,
        effects=(),
        build=_bkm12_2_7c,
    ),
]

register(*_CLAIMS)
