"""Claims about the rubber ball and the ball along a straight line (BKM12 §3).

Both are the Chaplygin ball with one more constraint on the angular velocity alone: no
twist, ``(omega, gamma) = 0`` (the rubber ball), or Veselovs' ``(omega, alpha) = 0`` (the
ball rolls along the space-fixed line ``alpha``). The engine keeps the constraint's
multiplier ``mu`` and eliminates it from ``d/dt (C omega) = 0``; the model's phase space is
the zero level of ``C omega``. BKM12 §3 writes the equations in ``K``, the momentum with
its component along the constraint vector removed; these claims compare that form, its
integrals (58), the reductions 3.1 and 3.2 to the rubber ball, and the rubber ball's own
integrals and measure with what the engine derived.
"""

from __future__ import annotations

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.vectors import cross, dot

from ..identity import lie_derivative, measure_residual
from .base import Check, Claim, register
from .notation import ball_notation

BALL = "chaplygin_ball"
RUBBER = ("rubber",)
LINE = ("straight_line",)
RUBBER_LINE = ("rubber", "straight_line")


def _omega(model: Model) -> sp.Matrix:
    return model.expand_aux(sp.Matrix(model.omega))


def _multipliers(model: Model) -> list[sp.Symbol]:
    return [s for s in model.aux_symbols if s.name.startswith("mu")]


def _free_mu(exprs: list[sp.Expr], model: Model) -> list[sp.Expr]:
    """Split ``exprs`` (linear in the multipliers) into their coefficients."""
    mu = _multipliers(model)
    out = []
    for e in exprs:
        out.append(e.xreplace({m: 0 for m in mu}))
        out += [sp.diff(e, m) for m in mu]
    return out


def _rate_check(model: Model, fields, extra=(), on=()) -> Check:
    """``fields(rate) -> residuals``, first for every value of the multipliers.

    ``rate(expr)`` is the Lie derivative, with the multipliers kept as free symbols in
    the first check and expanded in the fallback. The reaction of a constraint on
    omega alone has no moment about the free axes and does no work on the constraint,
    so most statements hold whatever the multipliers are (and that proof is cheap).
    """
    mu = _multipliers(model)

    def keep(e):
        return lie_derivative(e, model, keep=mu)

    def full(e):
        return lie_derivative(e, model)

    fallback = Check(list(fields(full)) + list(extra), on=list(on))
    if not mu:
        return fallback
    return Check(
        _free_mu(list(fields(keep)), model) + list(extra),
        free=mu,
        on=list(on),
        fallback=fallback,
        note="for every value of the multipliers",
    )


def _K(model: Model, along: str) -> sp.Matrix:
    """The momentum without its component along the constraint vector (BKM12 §3)."""
    M, c = model.group("M"), model.group(along)
    return M - dot(M, c) * c


# ------------------------------------------------------------- the rubber ball
def _rubber_constraint(model: Model) -> Check:
    n = ball_notation(model)
    return Check([lie_derivative(dot(n.omega, n.gamma), model)], everywhere=True)


def _rubber_equations(model: Model) -> Check:
    """M' - M x omega is the reaction mu gamma (along gamma), gamma' = gamma x omega."""
    n = ball_notation(model)
    w = _omega(model)
    f = model.rhs_expanded
    Mdot, gdot = f[:3, :], f[3:6, :]
    return Check(list(cross(Mdot - cross(n.M, w), n.gamma)) + list(gdot - cross(n.gamma, w)))


def _rubber_K(model: Model) -> Check:
    """K = M - (M, gamma) gamma: K' = K x omega and K = (J - gamma ⊗ J gamma) omega."""
    n = ball_notation(model)
    w = _omega(model)
    K = _K(model, "gamma")
    rubber_form = n.J * w - n.gamma * dot(n.J * n.gamma, w)
    return _rate_check(
        model,
        lambda rate: [rate(K[i]) - cross(K, w)[i] for i in range(3)],
        extra=list(K - rubber_form),
    )


def _rubber_integral(which: str):
    def build(model: Model) -> Check:
        n = ball_notation(model)
        w = _omega(model)
        K = _K(model, "gamma")
        F = {
            "H": dot(n.M, w) / 2,
            "KK": dot(K, K),
            "gamma": dot(n.gamma, n.gamma),
            "MM": dot(n.M, n.M),  # control: an integral of the Chaplygin ball only
            "Mgamma": dot(n.M, n.gamma),  # control: the reaction has a moment about gamma
        }[which]
        return _rate_check(model, lambda rate: [rate(F)])

    return build


def _rubber_density(kind: str):
    def build(model: Model) -> Check:
        n = ball_notation(model)
        Ag = dot(n.gamma, n.A * n.gamma)
        rho = {
            "rubber": sp.sqrt(Ag) / (1 / n.D - Ag),
            "chaplygin": n.rho(),  # control: the density of the ball without the constraint
        }[kind]
        return Check([measure_residual(rho, model)])

    return build


# ------------------------------------------------- the rubber ball along a straight line
def _rubber_line_constraints(model: Model) -> Check:
    """Both multipliers eliminated, the flow keeps ``(omega, gamma)`` and ``(omega, alpha)``
    constant everywhere (identically, not only on their zero levels)."""
    n = ball_notation(model)
    return Check(
        [lie_derivative(dot(n.omega, v), model) for v in (n.gamma, n.alpha)], everywhere=True
    )


def _rubber_line_density(power: sp.Rational):
    """``(D^-1 - (gamma, A gamma))^power``: ``-1`` is the density ``chaplygin discover
    --densities`` finds for the rubber ball on a line; ``-1/2`` (the plain ball's) is the
    negative control."""

    def build(model: Model) -> Check:
        n = ball_notation(model)
        return Check([measure_residual((1 / n.D - dot(n.gamma, n.A * n.gamma)) ** power, model)])

    return build


def _rubber_line_shipped_density(model: Model) -> Check:
    """The model's density is the find times the square root of ``det(J) (gamma x alpha,
    J gamma x alpha)``, a first integral: ``rho^2 (D^-1 - (gamma, A gamma))^2 / (gamma x alpha,
    J gamma x alpha)`` is a constant on the phase space and that quadratic form's rate vanishes
    there (the constant is the ratio's value at one point of the phase space)."""
    n = ball_notation(model)
    found = 1 / (1 / n.D - dot(n.gamma, n.A * n.gamma))
    g_x_a = cross(n.gamma, n.alpha)
    form = dot(g_x_a, n.J * g_x_a)
    rho = model.expand_aux(model.density)
    ratio = sp.together(rho**2 / (found**2 * form))
    # its value at gamma = e3, alpha = e1 (the density is free of M and beta)
    at = dict(zip((*n.gamma, *n.alpha), (0, 0, 1, 1, 0, 0), strict=True))
    if rho.free_symbols & (set(model.state) - set(at)):
        raise ValueError("the model's density depends on more than gamma and alpha")
    constant = sp.factor(sp.cancel(ratio.xreplace(at)))
    return Check([lie_derivative(form, model), ratio - constant])


# ---------------------------------------------------- the ball along a straight line
def _line_constraint(model: Model) -> Check:
    n = ball_notation(model)
    return Check([lie_derivative(dot(n.omega, n.alpha), model)], everywhere=True)


def _bkm12_57(model: Model) -> Check:
    """K' = K x omega, alpha' = alpha x omega, beta' = beta x omega,
    K = (I + D beta ⊗ beta - alpha ⊗ I alpha) omega, K = K0 - (K0, alpha) alpha."""
    n = ball_notation(model)
    w = _omega(model)
    K = _K(model, "alpha")
    I = sp.diag(*n.I)
    printed = I * w + n.D * n.beta * dot(n.beta, w) - n.alpha * dot(I * n.alpha, w)
    K0 = I * w + n.D * cross(n.gamma, cross(w, n.gamma))
    f = model.rhs_expanded
    idx = {g: [model.state.index(s) for s in model.vectors[g]] for g in ("alpha", "beta")}
    exprs = list(K - printed) + list(K - (K0 - dot(K0, n.alpha) * n.alpha))
    for g, vec in (("alpha", n.alpha), ("beta", n.beta)):
        exprs += list(sp.Matrix([f[i] for i in idx[g]]) - cross(vec, w))
    return _rate_check(
        model, lambda rate: [rate(K[i]) - cross(K, w)[i] for i in range(3)], extra=exprs
    )


def _line_integral(which: str):
    def build(model: Model) -> Check:
        n = ball_notation(model)
        w = _omega(model)
        K = _K(model, "alpha")
        F = {
            "Kbeta": dot(K, n.beta),
            "Kgamma": dot(K, n.gamma),
            "E": dot(K, w),
            "frame": None,
            "Malpha": dot(n.M, n.alpha),  # control: the reaction torque is along alpha
            "MM": dot(n.M, n.M),  # control
        }[which]
        if which == "E":
            # E = (M, omega) on the phase space (the constraint kills (M, alpha)(alpha,
            # omega)); (M, omega) is conserved whatever the multiplier, and the phase space
            # is invariant (BKM12-57.constraint)
            return _rate_check(model, lambda rate: [rate(dot(n.M, w))], extra=[F - dot(n.M, w)])
        if which == "frame":
            a, b = n.alpha, n.beta
            casimirs = (dot(a, a), dot(b, b), dot(a, b), dot(n.gamma, n.gamma))
            return _rate_check(model, lambda rate: [rate(e) for e in casimirs])
        return _rate_check(model, lambda rate: [rate(F)])

    return build


def _bkm12_58_identities(model: Model) -> Check:
    """(K, alpha) = 0 and (K, K) = (K, beta)^2 + (K, gamma)^2 on the phase space."""
    n = ball_notation(model)
    K = _K(model, "alpha")
    return Check([dot(K, n.alpha), dot(K, K) - dot(K, n.beta) ** 2 - dot(K, n.gamma) ** 2])


def _reduction(case: str, sign: int = 1):
    """BKM12-3.1 ((K, beta) = 0) and 3.2 ((K, gamma) = 0): a rubber ball's K~.

    ``sign = -1`` in 3.1 is the negative control (the sign of 3.2).
    """

    def build(model: Model) -> Check:
        n = ball_notation(model)
        w = _omega(model)
        K = _K(model, "alpha")
        E = dot(K, w)
        I = sp.diag(*n.I)
        if case == "3.1":
            level = dot(n.M, n.beta)  # (K, beta) = (M, beta)
            inertia = n.J
        else:
            level = dot(n.M, n.gamma)
            inertia = I
        rubber_form = inertia * w - n.alpha * dot(inertia * n.alpha, w)
        # On the level set K = (K, e) e (e = gamma in 3.1, beta in 3.2) and E = (K, e)(e,
        # omega), so the printed K~ is K -+ D (e, omega) e: two identities without the
        # division (the same statement, far smaller numerators).
        e = n.gamma if case == "3.1" else n.beta
        sgn = sign if case == "3.1" else -1
        identity = list(E * K - dot(K, e) ** 2 * dot(e, w) * e)
        identity += list(K + sgn * n.D * dot(e, w) * e - rubber_form)
        if sign < 0:
            return Check(identity, on=[level])
        # K~ = K (1 + ...) with E and (K, gamma) or (K, beta) integrals of the flow
        # (BKM12-58): K~' = K~ x omega follows from K' = K x omega
        return _rate_check(
            model,
            lambda rate: [rate(K[i]) - cross(K, w)[i] for i in range(3)],
            extra=identity,
            on=[level],
        )

    return build


register(
    # ------------------------------------------------------------ rubber ball
    Claim(
        id="BKM12-3rub.constraint",
        source="BKM12 §3 (rubber ball)",
        kind="equation",
        statement="with the no-twist multiplier eliminated the flow keeps (omega, gamma) constant "
        "on the whole phase space, so (omega, gamma) = 0 is invariant",
        system=BALL,
        effects=RUBBER,
        build=_rubber_constraint,
        note="constraints v + omega x r = 0, (omega, gamma) = 0; mu from d/dt (omega, gamma) = 0",
    ),
    Claim(
        id="BKM12-3rub.eq",
        source="BKM12 §3 (rubber ball)",
        kind="equation",
        statement="M' = M x omega + mu gamma (the reaction torque of the no-twist constraint is "
        "along gamma), gamma' = gamma x omega",
        system=BALL,
        effects=RUBBER,
        build=_rubber_equations,
    ),
    Claim(
        id="BKM12-3rub.K",
        source="BKM12 §3 (rubber ball)",
        kind="equation",
        statement="K = M - (M, gamma) gamma = (J - gamma ⊗ J gamma) omega, K' = K x omega (the "
        "rubber "
        "ball of BKM12 §3, inertia J = I + D Id)",
        system=BALL,
        effects=RUBBER,
        build=_rubber_K,
    ),
    Claim(
        id="BKM12-3rub.H",
        source="BKM12 §3 (rubber ball)",
        kind="integral",
        statement="H = (M, omega)/2 is a first integral on (omega, gamma) = 0",
        system=BALL,
        effects=RUBBER,
        build=_rubber_integral("H"),
    ),
    Claim(
        id="BKM12-3rub.KK",
        source="BKM12 §3 (rubber ball)",
        kind="integral",
        statement="(K, K) = (M, M) - (M, gamma)^2 is a first integral",
        system=BALL,
        effects=RUBBER,
        build=_rubber_integral("KK"),
    ),
    Claim(
        id="BKM12-3rub.gamma",
        source="BKM12 §3 (rubber ball)",
        kind="integral",
        statement="(gamma, gamma) = 1 is preserved",
        system=BALL,
        effects=RUBBER,
        build=_rubber_integral("gamma"),
    ),
    Claim(
        id="BKM12-3rub.measure",
        source="BKM12 §3 (rubber ball)",
        kind="measure",
        statement="rho = (gamma, A gamma)^(1/2) / (D^-1 - (gamma, A gamma)) satisfies Liouville's "
        "equation on (omega, gamma) = 0: rho dM dgamma / d(omega, gamma) is invariant",
        system=BALL,
        effects=RUBBER,
        build=_rubber_density("rubber"),
        note="the Chaplygin ball's density times (C II^-1 C^T)^(1/2), C = gamma^T; "
        "not printed in BKM12 (derived here)",
    ),
    Claim(
        id="BKM12-3rub/control-MM",
        source="negative control",
        kind="integral",
        statement="(M, M) is a first integral of the rubber ball (false: only (K, K) is)",
        system=BALL,
        effects=RUBBER,
        build=_rubber_integral("MM"),
        expected="fails",
    ),
    Claim(
        id="BKM12-3rub/control-Mgamma",
        source="negative control",
        kind="integral",
        statement="(M, gamma) is a first integral of the rubber ball (false: the reaction twists)",
        system=BALL,
        effects=RUBBER,
        build=_rubber_integral("Mgamma"),
        expected="fails",
    ),
    Claim(
        id="BKM12-3rub/control-measure",
        source="negative control",
        kind="measure",
        statement="the Chaplygin ball's density (D^-1 - (gamma, A gamma))^-1/2 is invariant for "
        "the "
        "rubber ball (false)",
        system=BALL,
        effects=RUBBER,
        build=_rubber_density("chaplygin"),
        expected="fails",
    ),
    # ------------------------------------------ the rubber ball along a straight line
    Claim(
        id="BKM12-3rub57.constraint",
        source="BKM12 §3 (rubber ball along a straight line)",
        kind="equation",
        statement="with both multipliers eliminated the flow keeps (omega, gamma) and (omega, "
        "alpha) constant on the whole phase space, so their common zero level is invariant and "
        "an ambient density that satisfies Liouville's equation there is the density of an "
        "invariant measure rho dM dgamma dalpha dbeta / (d(omega, gamma) d(omega, alpha))",
        system=BALL,
        effects=RUBBER_LINE,
        build=_rubber_line_constraints,
        note="constraints v + omega x r = 0, (omega, gamma) = 0, (omega, alpha) = 0",
    ),
    Claim(
        id="BKM12-3rub57.measure",
        source="BKM12 §3 (rubber ball along a straight line); found by chaplygin discover",
        kind="measure",
        statement="rho = (D^-1 - (gamma, A gamma))^-1 satisfies Liouville's equation on "
        "(omega, gamma) = (omega, alpha) = 0 (the density chaplygin discover --densities finds "
        "in the family of the vector field's denominator factors; BKM12 leaves it open)",
        system=BALL,
        effects=RUBBER_LINE,
        build=_rubber_line_density(sp.Integer(-1)),
        note="invariant with BKM12-3rub57.constraint (the level-set property)",
    ),
    Claim(
        id="BKM12-3rub57.shipped-density",
        source="BKM12 §3 (rubber ball along a straight line)",
        kind="measure",
        statement="the model's density det(C II^-1 C^T)^(1/2) det(X)^(-1/2) (C = (gamma; "
        "alpha)) is the found one times (gamma x alpha, J gamma x alpha)^(1/2), and that "
        "quadratic form is a first integral: the shipped density is invariant too",
        system=BALL,
        effects=RUBBER_LINE,
        build=_rubber_line_shipped_density,
    ),
    Claim(
        id="BKM12-3rub57/control-measure",
        source="negative control",
        kind="measure",
        statement="the plain ball's density (D^-1 - (gamma, A gamma))^-1/2 is invariant for the "
        "rubber ball along a line (false: the exponent is -1)",
        system=BALL,
        effects=RUBBER_LINE,
        build=_rubber_line_density(sp.Rational(-1, 2)),
        expected="fails",
    ),
    # -------------------------------------------------- the ball along a straight line
    Claim(
        id="BKM12-57.constraint",
        source="BKM12 §3, eq. (57)",
        kind="equation",
        statement="with Veselovs' multiplier eliminated the flow keeps (omega, alpha) constant on "
        "the "
        "whole phase space, so (omega, alpha) = 0 is invariant",
        system=BALL,
        effects=LINE,
        build=_line_constraint,
        note="constraints v + omega x r = 0 and (omega, alpha) = 0",
    ),
    Claim(
        id="BKM12-57",
        source="BKM12 §3, eq. (57)",
        kind="equation",
        statement="K' = K x omega, alpha' = alpha x omega, beta' = beta x omega, "
        "K = (I + D beta ⊗ beta - alpha ⊗ (I alpha)) omega = K0 - (K0, alpha) alpha, "
        "K0 = I omega + D gamma x (omega x gamma)",
        system=BALL,
        effects=LINE,
        build=_bkm12_57,
    ),
    Claim(
        id="BKM12-58.frame",
        source="BKM12 §3, eq. (58)",
        kind="integral",
        statement="(alpha, alpha) = (beta, beta) = 1, (alpha, beta) = 0 (and (gamma, gamma) = 1) "
        "are preserved",
        system=BALL,
        effects=LINE,
        build=_line_integral("frame"),
    ),
    Claim(
        id="BKM12-58.Kbeta",
        source="BKM12 §3, eq. (58)",
        kind="integral",
        statement="(K, beta) = const",
        system=BALL,
        effects=LINE,
        build=_line_integral("Kbeta"),
    ),
    Claim(
        id="BKM12-58.Kgamma",
        source="BKM12 §3, eq. (58)",
        kind="integral",
        statement="(K, gamma) = (K, alpha x beta) = const",
        system=BALL,
        effects=LINE,
        build=_line_integral("Kgamma"),
    ),
    Claim(
        id="BKM12-58.E",
        source="BKM12 §3, eq. (58)",
        kind="integral",
        statement="E = (K, omega) = const",
        system=BALL,
        effects=LINE,
        build=_line_integral("E"),
    ),
    Claim(
        id="BKM12-58.identities",
        source="BKM12 §3, eq. (58)",
        kind="definition",
        statement="(K, alpha) = 0 and the quadratic integral (K, K) = (K, beta)^2 + (K, gamma)^2 "
        "is a "
        "combination of the linear ones",
        system=BALL,
        effects=LINE,
        build=_bkm12_58_identities,
    ),
    Claim(
        id="BKM12-3.1",
        source="BKM12 §3",
        kind="transformation",
        statement="on (K, beta) = 0: K~ = K + D E K/(K, gamma)^2 = (J - alpha ⊗ (J alpha)) omega "
        "and "
        "K~' = K~ x omega: a rubber ball with inertia J = I + D Id (vertical alpha)",
        system=BALL,
        effects=LINE,
        build=_reduction("3.1"),
    ),
    Claim(
        id="BKM12-3.2",
        source="BKM12 §3",
        kind="transformation",
        statement="on (K, gamma) = 0: K~ = K - D E K/(K, beta)^2 = (I - alpha ⊗ (I alpha)) omega "
        "and "
        "K~' = K~ x omega: a rubber ball with inertia I (vertical alpha)",
        system=BALL,
        effects=LINE,
        build=_reduction("3.2"),
    ),
    Claim(
        id="BKM12-3.1/control-sign",
        source="negative control",
        kind="transformation",
        statement="on (K, beta) = 0: K - D E K/(K, gamma)^2 = (J - alpha ⊗ (J alpha)) omega (the "
        "sign "
        "of 3.2 in 3.1: false)",
        system=BALL,
        effects=LINE,
        build=_reduction("3.1", sign=-1),
        expected="fails",
    ),
    Claim(
        id="BKM12-58/control-Malpha",
        source="negative control",
        kind="integral",
        statement="(M, alpha) is a first integral of the ball along a line (false: the reaction "
        "torque "
        "is along alpha)",
        system=BALL,
        effects=LINE,
        build=_line_integral("Malpha"),
        expected="fails",
    ),
)
