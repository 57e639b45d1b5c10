"""Claims about the Chaplygin ball: BKM12 §1.1 and K01 §2.1, §4 (gyrostat).

Each check compares what the engine *derived* with the formula the paper prints.
"""

from __future__ import annotations

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.vectors import cross, dot

from ..identity import lie_derivative, measure_residual
from .base import Check, Claim, register
from .notation import ball_notation

BALL = "chaplygin_ball"
CONTACT = ("contact_point",)
GYRO = ("gyrostat",)


def _rhs(model: Model, group: str) -> sp.Matrix:
    idx = [model.state.index(s) for s in model.vectors[group]]
    return sp.Matrix([model.rhs[i] for i in idx])


def _omega(model: Model) -> sp.Matrix:
    return sp.Matrix(model.omega)


# ---------------------------------------------------------------- BKM12 §1.1
def _bkm12_1(model: Model) -> Check:
    n = ball_notation(model)
    derived = model.momentum_of_omega
    return Check(list(derived - n.momentum(n.omega)), free=list(n.omega))


def _equations(model: Model, K=None) -> Check:
    """The engine's momentum rate and the model's right-hand side against M' = (M+K) x omega."""
    n = ball_notation(model)
    red = model.details.reduced_equations
    P0 = red.gyrostatic_momentum
    K = K if K is not None else sp.zeros(3, 1)
    raw = red.momentum_rate - cross(red.inertia_operator * n.omega + K, n.omega)
    exprs = list(raw) + list(P0 - K)
    exprs += list(_rhs(model, "M") - cross(n.M + K, n.omega))
    exprs += list(_rhs(model, "gamma") - cross(n.gamma, n.omega))
    return Check(exprs, free=list(n.omega))


def _bkm12_3(model: Model) -> Check:
    n = ball_notation(model)
    w = model.expand_aux(n.omega)
    II = model.inertia_operator
    return Check(list(w - n.omega_formula()) + list(II * w - n.M))


def _measure(exponent, variant="bkm12"):
    def build(model: Model) -> Check:
        n = ball_notation(model)
        if variant == "k01":  # K01-2.2: 1/sqrt(1 - D (gamma, J^-1 gamma))
            rho = (1 - n.D * dot(n.gamma, n.J.inv() * n.gamma)) ** exponent
        elif variant == "one":
            rho = sp.S.One
        else:
            rho = n.rho(exponent)
        return Check([measure_residual(rho, model)])

    return build


def _integral(which):
    def build(model: Model) -> Check:
        n = ball_notation(model)
        K = n.K if n.K is not None else sp.zeros(3, 1)
        P = n.M + K
        F = {
            "F0": dot(n.gamma, n.gamma),
            "F1": dot(P, P),
            "F2": dot(P, n.gamma),
            "H": dot(n.M, n.omega) / 2,
            "MAgamma": dot(n.M, n.A * n.gamma),
        }[which]
        return Check([lie_derivative(F, model)])

    return build


def _energy_forms(model: Model) -> Check:
    n = ball_notation(model)
    half_M_omega = dot(n.M, model.expand_aux(n.omega)) / 2
    paper = dot(n.M, n.A * n.M) / 2 + n.Z * dot(n.A * n.M, n.gamma) / 2
    derived = model.expand_aux(model.integral("H"))
    return Check([half_M_omega - paper, derived - half_M_omega])


def _contact_point(model: Model) -> Check:
    n = ball_notation(model)
    x_rate, y_rate = _rhs(model, "x")[0], _rhs(model, "y")[0]
    v = model.details.centre_velocity
    return Check(
        [
            x_rate - n.b * dot(n.beta, n.omega),
            y_rate + n.b * dot(n.alpha, n.omega),
            x_rate - dot(v, n.alpha),
            y_rate - dot(v, n.beta),
        ],
        free=list(n.omega),
    )


def _bkm12_7(model: Model) -> Check:
    n = ball_notation(model)
    C, Mg = dot(n.M, n.M), dot(n.M, n.gamma)
    s = sp.sqrt(C - Mg**2)
    alpha = cross(n.M, n.gamma) / s
    beta = (n.M - Mg * n.gamma) / s
    w = model.expand_aux(n.omega)
    exprs = [dot(alpha, alpha) - 1, dot(beta, beta) - 1, dot(alpha, beta)]
    exprs += list(cross(alpha, beta) - n.gamma)
    exprs += [lie_derivative(a, model) - c for a, c in zip(alpha, cross(alpha, w), strict=True)]
    exprs += [lie_derivative(b, model) - c for b, c in zip(beta, cross(beta, w), strict=True)]
    return Check(exprs)


def _no_slip(model: Model) -> Check:
    n = ball_notation(model)
    r = -n.b * n.gamma
    v = model.details.centre_velocity
    return Check(list(v - cross(r, n.omega)) + list(v + cross(n.omega, r)), free=list(n.omega))


def _space_fixed_frame(model: Model) -> Check:
    n = ball_notation(model)
    exprs = list(_rhs(model, "alpha") - cross(n.alpha, n.omega))
    exprs += list(_rhs(model, "beta") - cross(n.beta, n.omega))
    frame = [dot(n.alpha, n.alpha), dot(n.beta, n.beta), dot(n.alpha, n.beta)]
    frame += list(n.gamma - cross(n.alpha, n.beta))
    exprs += [lie_derivative(F, model) for F in frame]
    return Check(exprs, free=list(n.omega))


def _k01_2_1(model: Model) -> Check:
    a, b = _bkm12_1(model), _equations(model)
    return Check(a.exprs + b.exprs, free=a.free)


def _k01_4_1(model: Model) -> Check:
    n = ball_notation(model)
    a = _bkm12_1(model)
    b = _equations(model, K=n.K)
    return Check(a.exprs + b.exprs, free=a.free)


S11 = "BKM12 §1.1"


# ------------------------------------------------- K01 §4.3-4.4 (M + K parallel to gamma)
def _zv_quantities(model: Model):
    """``C, h, l, mu_K, Jh`` of K01-4.3/4.4 in the model's expanded variables."""
    n = ball_notation(model)
    w = model.expand_aux(n.omega)
    C = dot(n.M + n.K, n.gamma)
    h = dot(n.M, w) / 2
    l = C + n.D * (2 * h + dot(n.K, w)) / C  # K01's letter
    mu_K = C + 2 * n.D * h / C
    Jh = n.J - n.D * n.K * n.K.T / (C * mu_K)
    return n, w, C, l, mu_K, Jh


def _k01_4_3(model: Model) -> Check:
    """On M + K = C gamma: J omega + K = l gamma."""
    n, w, _, l, _, _ = _zv_quantities(model)
    return Check(list(n.J * w + n.K - l * n.gamma), on=list(cross(n.M + n.K, n.gamma)))


def _k01_4_4(model: Model) -> Check:
    """x = omega / l, d tau = l dt: gamma = Jh x + K/mu_K, Jh x' = (Jh x + K/mu_K) x x.

    The second follows from the first by differentiating it along the flow: ``Jh`` and
    ``mu_K`` are constant there (``C`` and ``h`` are integrals, K01-4.2), so
    ``Jh dx/dt = gamma' = gamma x omega = l (Jh x + K/mu_K) x x``. The check proves the
    identity and the model's ``gamma' = l gamma x x`` on the invariant set; expanding
    ``x'`` itself gives numerators of ~27k terms whose normal form takes minutes.
    """
    n, w, _, l, mu_K, Jh = _zv_quantities(model)
    x = w / l
    f = model.rhs_expanded
    gamma_rate = sp.Matrix([f[model.state.index(s)] for s in n.gamma])
    exprs = list(n.gamma - (Jh * x + n.K / mu_K))
    exprs += list(gamma_rate - l * cross(n.gamma, x))
    return Check(
        exprs,
        on=list(cross(n.M + n.K, n.gamma)),
        note="x' from differentiating gamma = Jh x + K/mu_K, with C, h integrals (K01-4.2)",
    )


def _k01_4_4_control(model: Model) -> Check:
    """The same with mu_K replaced by C (the gyrostat's shift dropped): must fail."""
    n, w, C, l, _, _ = _zv_quantities(model)
    Jh = n.J - n.D * n.K * n.K.T / C**2
    x = w / l
    return Check(list(n.gamma - (Jh * x + n.K / C)), on=list(cross(n.M + n.K, n.gamma)))


register(
    Claim(
        id="BKM12-1",
        source=f"{S11}",
        kind="equation",
        statement="M = I omega + D gamma x (omega x gamma), D = m b^2",
        system=BALL,
        effects=(),
        build=_bkm12_1,
        note="the engine's projected momentum G^T dT/d(omega, v) against the paper's formula",
    ),
    Claim(
        id="BKM12-2",
        source=f"{S11}",
        kind="equation",
        statement="M' = M x omega, gamma' = gamma x omega",
        system=BALL,
        effects=(),
        build=_equations,
        note="the engine's raw momentum rate (multipliers eliminated) and the model's "
        "right-hand side, for every omega",
        covers=("BKM12-9",),  # gamma' = gamma x omega again (FORMULAS.md)
    ),
    Claim(
        id="BKM12-3",
        source=f"{S11}",
        kind="equation",
        statement="omega = A (M + Z gamma), A = (I + D Id)^-1, Z = (A M, gamma)/(D^-1 - (gamma, A "
        "gamma))",
        system=BALL,
        effects=(),
        build=_bkm12_3,
        note="also: the derived inertia operator times this omega gives M back",
    ),
    Claim(
        id="BKM12-4",
        source=f"{S11}",
        kind="measure",
        statement="invariant measure rho dM dgamma, rho = (D^-1 - (gamma, A gamma))^-1/2",
        system=BALL,
        effects=(),
        build=_measure(sp.Rational(-1, 2)),
        note="div(rho f) = 0 on (gamma, gamma) = 1",
    ),
    Claim(
        id="BKM12-4/control-exponent+1/2",
        source=f"{S11} (negative control)",
        kind="measure",
        statement="rho = (D^-1 - (gamma, A gamma))^(+1/2) is an invariant density (wrong exponent)",
        system=BALL,
        effects=(),
        build=_measure(sp.Rational(1, 2)),
        expected="fails",
    ),
    Claim(
        id="BKM12-4/control-rho=1",
        source=f"{S11} (negative control)",
        kind="measure",
        statement="rho = 1: the flow preserves the Lebesgue measure dM dgamma",
        system=BALL,
        effects=(),
        build=_measure(1, "one"),
        expected="fails",
    ),
    Claim(
        id="BKM12-5.F0",
        source=f"{S11}",
        kind="integral",
        statement="F0 = (gamma, gamma) is a first integral",
        system=BALL,
        effects=(),
        build=_integral("F0"),
    ),
    Claim(
        id="BKM12-5.F1",
        source=f"{S11}",
        kind="integral",
        statement="F1 = (M, M) is a first integral",
        system=BALL,
        effects=(),
        build=_integral("F1"),
    ),
    Claim(
        id="BKM12-5.F2",
        source=f"{S11}",
        kind="integral",
        statement="F2 = (M, gamma) is a first integral",
        system=BALL,
        effects=(),
        build=_integral("F2"),
    ),
    Claim(
        id="BKM12-5.H",
        source=f"{S11}",
        kind="integral",
        statement="H = (M, omega)/2 is a first integral",
        system=BALL,
        effects=(),
        build=_integral("H"),
    ),
    Claim(
        id="BKM12-5.Hform",
        source=f"{S11}",
        kind="equation",
        statement="H = (M, omega)/2 = (M, A M)/2 + Z (A M, gamma)/2 (and = the derived kinetic "
        "energy)",
        system=BALL,
        effects=(),
        build=_energy_forms,
    ),
    Claim(
        id="BKM12-5/control-(M,A gamma)",
        source=f"{S11} (negative control)",
        kind="integral",
        statement="(M, A gamma) is a first integral (it is not)",
        system=BALL,
        effects=(),
        build=_integral("MAgamma"),
        expected="fails",
    ),
    Claim(
        id="BKM12-6",
        source=f"{S11}",
        kind="equation",
        statement="x' = b (beta, omega), y' = -b (alpha, omega)  "
        "(= (v, alpha), (v, beta), v = b omega x gamma)",
        system=BALL,
        effects=CONTACT,
        build=_contact_point,
        note="modulo the orthonormality of alpha, beta, gamma",
    ),
    Claim(
        id="BKM12-7",
        source=f"{S11}",
        kind="equation",
        statement="alpha = M x gamma / s, beta = (M - (M, gamma) gamma)/s, s = sqrt((M,M) - "
        "(M,gamma)^2): "
        "orthonormal, alpha x beta = gamma, alpha' = alpha x omega, beta' = beta x omega",
        system=BALL,
        effects=(),
        build=_bkm12_7,
        note="square root split off exactly: A + B s = 0 with A = B = 0",
    ),
    # ------------------------------------------------------------ K01 §2.1
    Claim(
        id="K01-2.1",
        source="K01 §2.1",
        kind="equation",
        statement="M' = M x omega, gamma' = gamma x omega, "
        "M = I omega + D gamma x (omega x gamma), D = m a^2",
        system=BALL,
        effects=(),
        build=_k01_2_1,
    ),
    Claim(
        id="K01-2.2",
        source="K01 §2.1",
        kind="measure",
        statement="Chaplygin's multiplier rho = 1/sqrt(1 - D (gamma, J^-1 gamma)), J = I + D Id",
        system=BALL,
        effects=(),
        build=_measure(sp.Rational(-1, 2), "k01"),
    ),
    Claim(
        id="K01-2.3.h",
        source="K01 §2.1",
        kind="integral",
        statement="h = (M, omega)/2 is a first integral",
        system=BALL,
        effects=(),
        build=_integral("H"),
    ),
    Claim(
        id="K01-2.3.C",
        source="K01 §2.1",
        kind="integral",
        statement="C = (M, gamma) is a first integral",
        system=BALL,
        effects=(),
        build=_integral("F2"),
    ),
    Claim(
        id="K01-2.3.n",
        source="K01 §2.1",
        kind="integral",
        statement="n = (M, M) is a first integral",
        system=BALL,
        effects=(),
        build=_integral("F1"),
    ),
    Claim(
        id="K01-2.3.gamma",
        source="K01 §2.1",
        kind="integral",
        statement="(gamma, gamma) = 1 is preserved",
        system=BALL,
        effects=(),
        build=_integral("F0"),
    ),
    Claim(
        id="K01-2.4",
        source="K01 §2.1",
        kind="equation",
        statement="alpha' = alpha x omega, beta' = beta x omega (alpha, beta fixed in space); the "
        "frame "
        "(alpha, beta, alpha x beta = gamma) stays orthonormal",
        system=BALL,
        effects=CONTACT,
        build=_space_fixed_frame,
    ),
    Claim(
        id="K01-2.5",
        source="K01 §2.1",
        kind="equation",
        statement="no slip: v = r x omega, r = -a gamma",
        system=BALL,
        effects=CONTACT,
        build=_no_slip,
    ),
    Claim(
        id="K01-2.6",
        source="K01 §2.1",
        kind="equation",
        statement="x' = (v, alpha) = a (beta, omega), y' = (v, beta) = -a (alpha, omega)",
        system=BALL,
        effects=CONTACT,
        build=_contact_point,
    ),
    # ------------------------------------------------------------ K01 §4 (gyrostat)
    Claim(
        id="K01-4.1",
        source="K01 §4",
        kind="equation",
        statement="M' = (M + K) x omega, gamma' = gamma x omega, "
        "M = I omega + D gamma x (omega x gamma), K constant",
        system=BALL,
        effects=GYRO,
        build=_k01_4_1,
        note="derived from T = (omega, I omega)/2 + (K, omega) + m v^2/2",
    ),
    Claim(
        id="K01-4.2.h",
        source="K01 §4",
        kind="integral",
        statement="h = (M, omega)/2 is a first integral",
        system=BALL,
        effects=GYRO,
        build=_integral("H"),
    ),
    Claim(
        id="K01-4.2.C",
        source="K01 §4",
        kind="integral",
        statement="C = (M + K, gamma) is a first integral",
        system=BALL,
        effects=GYRO,
        build=_integral("F2"),
    ),
    Claim(
        id="K01-4.2.gamma",
        source="K01 §4",
        kind="integral",
        statement="(gamma, gamma) = 1 is preserved",
        system=BALL,
        effects=GYRO,
        build=_integral("F0"),
    ),
    Claim(
        id="K01-4.2.n",
        source="K01 §4",
        kind="integral",
        statement="n = (M + K, M + K) is a first integral",
        system=BALL,
        effects=GYRO,
        build=_integral("F1"),
    ),
    Claim(
        id="K01-4.2m",
        source="K01 §4",
        kind="measure",
        statement="the measure of K01-2.2 is invariant for the ball with a gyrostat",
        system=BALL,
        effects=GYRO,
        build=_measure(sp.Rational(-1, 2), "k01"),
    ),
    Claim(
        id="K01-4.3",
        source="K01 §4",
        kind="solution",
        statement="on M + K = C gamma: J omega + K = l gamma, l = C + D (2h + (K, omega))/C",
        system=BALL,
        effects=GYRO,
        build=_k01_4_3,
        note="checked on the invariant set (M + K) x gamma = 0",
    ),
    Claim(
        id="K01-4.4",
        source="K01 §4",
        kind="transformation",
        statement="on M + K = C gamma, omega = l x, dt = d tau / l: Jh x' = (Jh x + K/mu_K) x x "
        "(Zhukovsky–Volterra), gamma = Jh x + K/mu_K, Jh = J - D K ⊗ K/(C mu_K), "
        "mu_K = C + 2 D h/C",
        system=BALL,
        effects=GYRO,
        build=_k01_4_4,
        note="checked on the invariant set (M + K) x gamma = 0",
    ),
    Claim(
        id="K01-4.4/control-muK",
        source="negative control",
        kind="transformation",
        statement="gamma = Jh x + K/C with Jh = J - D K ⊗ K/C^2 (mu_K replaced by C: false)",
        system=BALL,
        effects=GYRO,
        build=_k01_4_4_control,
        expected="fails",
    ),
)
