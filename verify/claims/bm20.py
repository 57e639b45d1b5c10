"""Claims of BM20: the Chaplygin ball with periodically varying inertia and gyrostat.

Borisov, Mikishanina, "Dynamics of the Chaplygin ball with variable parameters" (2020);
FORMULAS.md §3. BM20's ``M`` is the *total* momentum about the contact point,
``M = I(t) omega + d gamma x (omega x gamma) + k(t)`` (``d = D``): the state of the model
with ``variable_gyrostat``; with the constant ``gyrostat`` effect the model's state is
BKM12's ``M`` and BM20's is ``M + K``.

Claims about *arbitrary* laws ``I(t)``, ``k(t)`` (the equations, the integrals, the
symmetries) are checked on a model whose ``I_i(t)``, ``k_i(t)`` are undefined functions
of time (:class:`GenericLawClaim`), so a proof covers every law, not only (3.4)-(3.5);
``BM20-3.4`` and ``BM20-3.5`` prove that the built-in variants are that model with the
laws (3.4)-(3.5) substituted.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import cache

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.chaplygin_ball import build_chaplygin_ball
from chaplygin.derive.errors import ComputationError
from chaplygin.derive.vectors import cross, dot
from sympy.core.function import AppliedUndef

from ..identity import lie_derivative, measure_residual
from .base import Check, Claim, Computed, ComputedClaim, register

__all__ = ["GenericLawClaim", "generic_model", "transformation_residual"]

BALL = "chaplygin_ball"
GYRO = ("gyrostat",)
VI = ("variable_inertia",)
VB = ("variable_gyrostat", "variable_inertia")
VBC = ("contact_point", "variable_gyrostat", "variable_inertia")

_GENERIC: dict[frozenset[str], Model] = {}


def generic_model(effects: Iterable[str]) -> Model:
    """The ball with ``I(t)``, ``k(t)`` undefined functions of time (memoised).

    Parameters
    ----------
    effects : iterable of str
        Effects of :func:`~chaplygin.derive.chaplygin_ball.build_chaplygin_ball`.

    Returns
    -------
    Model
        The generic-law ball model, built once per set of effects.
    """
    key = frozenset(effects)
    if key not in _GENERIC:
        _GENERIC[key] = build_chaplygin_ball(key, _laws="generic")
    return _GENERIC[key]


@dataclass(frozen=True, kw_only=True)
class GenericLawClaim(Claim):
    """A claim about every law ``I(t)``, ``k(t)``: checked on :func:`generic_model`."""

    def model(self) -> Model:
        """The ball with generic laws ``I(t)``, ``k(t)`` for the claim's effects.

        Returns
        -------
        Model
            :func:`generic_model` of the claim's effects (cached).
        """
        return generic_model(self.effects)


# ------------------------------------------------------------------ notation
@dataclass
class _Notation:
    """BM20's objects in a model's symbols (``M`` is BM20's total momentum)."""

    M: sp.Matrix
    gamma: sp.Matrix
    omega: sp.Matrix  # the model's auxiliary omega symbols
    I: sp.Matrix  # the paper's name; diagonal, maybe time-dependent
    D: sp.Symbol
    k: sp.Matrix  # gyrostatic momentum k(t) (or the constant K)
    alpha: sp.Matrix | None
    beta: sp.Matrix | None
    b: sp.Symbol | None

    def inertia_about_contact(self) -> sp.Matrix:
        """``I + d (Id - gamma ⊗ gamma)`` (BM20-2.4)."""
        return self.I + self.D * (sp.eye(3) - self.gamma * self.gamma.T)


def _notation(model: Model) -> _Notation:
    M = model.group("M")
    names = {p.name for p in model.parameters}
    if "gyrostat" in model.effects:  # constant K: BM20's M is the state plus K
        k = model.param_group("K")
        M = M + k
    else:
        k = sp.Matrix(model.details.gyrostatic_momentum_of_time)
    return _Notation(
        M=M,
        gamma=model.group("gamma"),
        omega=sp.Matrix(model.omega),
        I=sp.Matrix(model.details.inertia),
        D=model.param_group("D")[0],
        k=k,
        alpha=model.group("alpha") if "alpha" in model.vectors else None,
        beta=model.group("beta") if "beta" in model.vectors else None,
        b=model.param_group("b")[0] if "b" in names else None,
    )


def _rhs(model: Model, group: str, expanded: bool = False) -> sp.Matrix:
    rhs = model.rhs_expanded if expanded else model.rhs
    return sp.Matrix([rhs[model.state.index(s)] for s in model.vectors[group]])


# ------------------------------------------------------------------ symmetries
def _parity_map(model: Model, inertia: int, gyrostat: int) -> dict:
    """``I_i(-t) -> I_i(t)``, ``k_i(-t) -> ±k_i(t)`` for the generic laws (even/odd)."""
    t = model.time
    n = _notation(model)
    out = {}
    for f in n.I.diagonal():
        if isinstance(f, AppliedUndef) and f.args == (t,):
            out[f.func(-t)] = inertia * f
    for f in n.k:
        if isinstance(f, AppliedUndef) and f.args == (t,):
            out[f.func(-t)] = gyrostat * f
    return out


def transformation_residual(
    model: Model,
    signs: dict[str, int],
    time_sign: int,
    parity: dict[sp.Expr, sp.Expr] | None = None,
    at: dict[sp.Expr, sp.Expr] | None = None,
) -> list[sp.Expr]:
    """Residual of ``(t, x) -> (s t, S x)`` (``S`` diagonal signs) mapping solutions to solutions.

    ``x(t)`` solves ``x' = f(t, x)`` iff ``y(t) = S x(s t)`` does exactly when
    ``f(s t, S x) = s S f(t, x)`` for all ``t, x``: the residual is the difference.

    Parameters
    ----------
    model : Model
        The model whose flow ``x' = f(t, x)`` is tested.
    signs : dict of str to int
        Sign of each state group (``{"M": -1, "gamma": 1}``); groups not named keep +1.
    time_sign : {1, -1}
        ``-1`` for a reversing symmetry (involution).
    parity : dict, optional
        Substitution applied after ``t -> -t`` (``I1(-t) -> I1(t)`` for an even law).
    at : dict, optional
        Substitution applied to the right-hand side first (``M -> 0`` on an invariant
        set, a parameter value).

    Returns
    -------
    list of sympy.Expr
        ``f(s t, S x) - s S f(t, x)``, one entry per state component.
    """
    f = model.rhs_expanded
    if at:
        f = f.xreplace(at)
    S = {}
    scale = []
    for name, group in model.state_groups:
        sign = signs.get(name, 1)
        scale += [sign] * len(group)
        S.update({s: sign * s for s in group if sign != 1})
    moved = f.xreplace({**S, model.time: time_sign * model.time})
    if parity:
        moved = moved.xreplace(parity)
    return [moved[i] - time_sign * scale[i] * f[i] for i in range(len(scale))]


def _transformations(
    maps: list[tuple[dict[str, int], int]], inertia: int, gyrostat: int, at=None
) -> Callable[[Model], Check]:
    def build(model: Model) -> Check:
        parity = _parity_map(model, inertia, gyrostat)
        exprs = []
        for signs, time_sign in maps:
            exprs += transformation_residual(model, signs, time_sign, parity, at)
        return Check(exprs)

    return build


SYMMETRY = ({"gamma": -1}, 1)  # (t, M, gamma) -> (t, M, -gamma)
INVOLUTION_1 = ({"M": -1}, -1)  # (t, M, gamma) -> (-t, -M, gamma)
INVOLUTION_2 = ({"M": -1, "gamma": -1}, -1)  # (t, M, gamma) -> (-t, -M, -gamma)


# ------------------------------------------------------------------ checks
def _bm20_2_2(model: Model) -> Check:
    n = _notation(model)
    paper = n.I * n.omega + n.D * cross(n.gamma, cross(n.omega, n.gamma)) + n.k
    red = model.details.reduced_equations
    exprs = list(red.momentum - paper) + list(model.momentum_of_omega - paper)
    return Check(exprs, free=list(n.omega))


def _bm20_2_4(model: Model) -> Check:
    n = _notation(model)
    II = n.inertia_about_contact()
    exprs = list(model.momentum_of_omega - (II * n.omega + n.k))
    exprs += list(model.inertia_operator - II)
    return Check(exprs, free=list(n.omega))


def _bm20_2_5(model: Model) -> Check:
    n = _notation(model)
    t = model.time
    red = model.details.reduced_equations
    # the engine's raw rate of its momentum (multipliers eliminated), for every omega:
    # d/dt (II omega + k) = (II omega + k) x omega
    raw = red.momentum_rate + sp.diff(red.gyrostatic_momentum, t)
    exprs = list(raw - cross(red.inertia_operator * n.omega + n.k, n.omega))
    exprs += list(red.gyrostatic_momentum - n.k)
    exprs += list(_rhs(model, "M") - cross(n.M, n.omega))
    exprs += list(_rhs(model, "gamma") - cross(n.gamma, n.omega))
    # omega = A (M - k), A = (I + d (Id - gamma ⊗ gamma))^-1, without inverting A
    w = model.expand_aux(n.omega)
    exprs += list(n.inertia_about_contact() * w - (n.M - n.k))
    return Check(exprs, free=list(n.omega))


def _integrals(model: Model) -> Check:
    n = _notation(model)
    F = [dot(n.gamma, n.gamma), dot(n.M, n.M), dot(n.M, n.gamma)]
    if n.alpha is not None:
        F += [dot(n.M, n.alpha), dot(n.M, n.beta)]
    return Check([lie_derivative(e, model) for e in F])


def _energy(literal: bool) -> Callable[[Model], Check]:
    def build(model: Model) -> Check:
        n = _notation(model)
        w = model.expand_aux(n.omega)
        E = dot(n.M if literal else n.M - n.k, w) / 2
        exprs = [lie_derivative(E, model)]
        if not literal:
            exprs.append(E - dot(w, n.inertia_about_contact() * w) / 2)
            if "H" in dict(model.integrals):
                exprs.append(model.expand_aux(model.integral("H")) - E)
        return Check(exprs)

    return build


def _bm20_2_7(model: Model) -> Check:
    n = _notation(model)
    J = n.I + n.D * sp.eye(3)
    rho = (1 - n.D * dot(n.gamma, J.inv() * n.gamma)) ** sp.Rational(-1, 2)
    return Check([measure_residual(rho, model)])


def _bm20_2_8(model: Model) -> Check:
    n = _notation(model)
    x, y = _rhs(model, "x")[0], _rhs(model, "y")[0]
    exprs = [x - n.b * dot(n.beta, n.omega), y + n.b * dot(n.alpha, n.omega)]
    # BM20's frame alpha = M x gamma / G, beta = M / G, G = |M|, on (M, gamma) = 0:
    # write M = gamma x u (u free) so that (M, gamma) = 0 identically.
    u = sp.Matrix(sp.symbols("u1:4", real=True))
    M_on = cross(n.gamma, u)
    G = sp.sqrt(dot(M_on, M_on))
    frame = dict(zip(n.alpha, cross(M_on, n.gamma) / G, strict=True))
    frame.update(zip(n.beta, M_on / G, strict=True))
    frame.update(zip(model.group("M"), M_on, strict=True))
    exprs += [
        x.xreplace(frame) - n.b / G * dot(M_on, n.omega),
        y.xreplace(frame) - n.b / G * dot(cross(n.gamma, M_on), n.omega),
    ]
    return Check(exprs, free=list(n.omega) + list(u))


def _law_substitution(model: Model) -> Check:
    """The variant's equations are the generic model's with BM20's laws (3.4)-(3.5)."""
    generic = generic_model(model.effects)
    n, g = _notation(model), _notation(generic)
    laws = {f: value for f, value in zip(g.I.diagonal(), n.I.diagonal(), strict=True) if f != value}
    laws.update({f: value for f, value in zip(g.k, n.k, strict=True) if f != value})
    if generic.state != model.state:  # pragma: no cover - same builder, same state
        raise AssertionError("state of the generic model differs")
    substituted = generic.rhs_expanded.xreplace(laws)
    exprs = list(model.rhs_expanded - substituted)
    pairs = zip(model.integrals, generic.integrals, strict=True)
    exprs += [a - b.xreplace(laws) for (_, a), (_, b) in pairs]
    return Check(exprs)


def _order_certificate(cos_square: bool):
    """BM20 §3.2 remark: I = (4, 3, 2), J_off = 0 in the law (3.4).

    ``I1(t) - I2 = 1 + delta^2 sin^2`` and ``I2 - I3(t) = (1 - delta^2) + delta^2 cos^2``:
    a certificate that ``I1(t) > I2 > I3(t)`` for every t iff ``delta < 1`` (the bound
    ``1 - delta^2`` is attained where ``cos(Omega t) = 0``). ``cos_square=False`` is the
    control with ``sin^2`` in the second identity.
    """

    def build(model: Model) -> Check:
        n = _notation(model)
        I0 = model.param_group("I")
        J_off = model.param_group("J_off")[0]
        delta, Omega = model.param_group("delta")[0], model.param_group("Omega")[0]
        fig = {I0[0]: 4, I0[1]: 3, I0[2]: 2, J_off: 0}
        It = [n.I[i, i].xreplace(fig) for i in range(3)]
        s, c = sp.sin(Omega * model.time), sp.cos(Omega * model.time)
        last = c if cos_square else s
        return Check(
            [
                It[0] - It[1] - (1 + delta**2 * s**2),
                It[1] - It[2] - (1 - delta**2) - (delta * last) ** 2,
            ]
        )

    return build


def _bm20_3_6(model: Model) -> Check:
    n = _notation(model)
    t = model.time
    rest = {s: 0 for s in model.group("M")}  # G = 0
    f = model.rhs_expanded.xreplace(rest)
    exprs = list(_rhs(model, "M", expanded=True).xreplace(rest))  # M = 0 is invariant
    w = model.expand_aux(n.omega).xreplace(rest)
    # gamma' = gamma x (-A k(t)): A^-1 w = -k and gamma' = gamma x w
    exprs += list(n.inertia_about_contact() * w + n.k)
    exprs += list(_rhs(model, "gamma", expanded=True).xreplace(rest) - cross(n.gamma, w))
    # symmetry gamma -> -gamma (any law) and, with (3.2), the involution (t, gamma) ->
    # (-t, -gamma) of the reduced system
    parity = _parity_map(model, 1, -1)
    idx = [model.state.index(s) for s in model.group("gamma")]
    flip = {s: -s for s in model.group("gamma")}
    exprs += [f[i].xreplace(flip) + f[i] for i in idx]
    exprs += [f[i].xreplace({**flip, t: -t}).xreplace(parity) - f[i] for i in idx]
    return Check(exprs)


# Andoyer–Deprit variables (BM20 §3.1, §3.2)
_z, _l, _g = sp.symbols("z l g", real=True)
_G = sp.Symbol("G", positive=True)
_root = sp.sqrt(1 - _z**2)


def _bm20_map(model: Model) -> Check:
    gamma = sp.Matrix([_root * sp.sin(_l), _root * sp.cos(_l), _z])
    return Check([dot(gamma, gamma) - 1], free=[_z, _l])


def _bm20_3_7(model: Model) -> Check:
    M = sp.Matrix([_G * _root * sp.sin(_l), _G * _root * sp.cos(_l), _G * _z])
    gamma = sp.Matrix(
        [
            _z * sp.cos(_g) * sp.sin(_l) + sp.sin(_g) * sp.cos(_l),
            _z * sp.cos(_g) * sp.cos(_l) - sp.sin(_g) * sp.sin(_l),
            -_root * sp.cos(_g),
        ]
    )
    return Check([dot(gamma, gamma) - 1, dot(M, gamma), dot(M, M) - _G**2], free=[_z, _l, _g, _G])


def _involutions_at(J_off_value) -> Callable[[Model], Check]:
    def build(model: Model) -> Check:
        at = {} if J_off_value is None else {model.param_group("J_off")[0]: J_off_value}
        exprs = []
        for signs, time_sign in (INVOLUTION_1, INVOLUTION_2):
            exprs += transformation_residual(model, signs, time_sign, at=at)
        return Check(exprs)

    return build


# ------------------------------------------------------------------ registry
S21, S3 = "BM20 §2.1", "BM20 §3"
register(
    GenericLawClaim(
        id="BM20-2.2",
        source=f"{S21}, eq. (2.2)",
        kind="equation",
        statement="M = I omega + d gamma x (omega x gamma) + k, d = m a^2, I = I(t), k = k(t)",
        system=BALL,
        effects=VB,
        build=_bm20_2_2,
        note="the engine's projected momentum G^T dT/d(omega, v) (T with (I(t) omega, omega)/2 "
        "+ (k(t), omega)) for arbitrary laws I_i(t), k_i(t)",
    ),
    GenericLawClaim(
        id="BM20-2.4",
        source=f"{S21}, eq. (2.4)",
        kind="equation",
        statement="M = (I + d (Id - gamma ⊗ gamma)) omega + k",
        system=BALL,
        effects=VB,
        build=_bm20_2_4,
        note="also: the derived inertia operator is I(t) + d (Id - gamma ⊗ gamma) on the sphere",
    ),
    GenericLawClaim(
        id="BM20-2.5",
        source=f"{S21}, eqs. (2.3), (2.5)",
        kind="equation",
        statement="M' = M x omega, gamma' = gamma x omega, omega = A (M - k), "
        "A = (I + d (Id - gamma ⊗ gamma))^-1, for arbitrary I(t), k(t)",
        system=BALL,
        effects=VB,
        build=_bm20_2_5,
        note="the engine's raw momentum rate (explicit d/dt of T included) and the model's "
        "right-hand side, for arbitrary laws",
    ),
    GenericLawClaim(
        id="BM20-2.5int",
        source=f"{S21}",
        kind="integral",
        statement="gamma^2, M^2 = G^2, (M, gamma) = H and, with (2.1), (M, alpha) = F, (M, beta) = "
        "Q "
        "are first integrals for arbitrary I(t), k(t)",
        system=BALL,
        effects=VBC,
        build=_integrals,
        note="Lie derivatives include the explicit d/dt; I_i(t), k_i(t) and their derivatives "
        "are independent generators",
    ),
    Claim(
        id="BM20-2.6/literal",
        source=f"{S21}, eq. (2.6) (literal reading)",
        kind="integral",
        statement="E = (M, omega)/2 (BM20's M, which includes k) is a first integral for constant "
        "I "
        "and constant k",
        system=BALL,
        effects=GYRO,
        build=_energy(literal=True),
        expected="fails",
        note="BM20's M = M_BKM12 + K; not conserved for K != 0 (FORMULAS.md: FAILED as "
        "transcribed)",
    ),
    Claim(
        id="BM20-2.6",
        source=f"{S21}, eq. (2.6) (corrected)",
        kind="integral",
        statement="E = (M - k, omega)/2 = (omega, (I + d (Id - gamma ⊗ gamma)) omega)/2 is a first "
        "integral for constant I and constant k (zero or not)",
        system=BALL,
        effects=GYRO,
        build=_energy(literal=False),
        note="also: E is the engine's generalised energy",
    ),
    Claim(
        id="BM20-2.6/time-varying",
        source=f"{S21} (the energy needs constant parameters)",
        kind="integral",
        statement="E = (M - k, omega)/2 is a first integral for the time-varying I(t) of (3.4) (k "
        "= 0)",
        system=BALL,
        effects=VI,
        build=_energy(literal=False),
        expected="fails",
        note="the moving masses do work: dE/dt = -(omega, I'(t) omega)/2 != 0",
    ),
    Claim(
        id="BM20-2.7.k0",
        source=f"{S21}, eq. (2.7)",
        kind="measure",
        statement="constant I, k = 0: invariant measure with rho = (1 - d (gamma, (I + d Id)^-1 "
        "gamma))^-1/2",
        system=BALL,
        effects=(),
        build=_bm20_2_7,
    ),
    Claim(
        id="BM20-2.7.k",
        source=f"{S21}, eq. (2.7)",
        kind="measure",
        statement="constant I, constant k != 0: the same rho is an invariant density",
        system=BALL,
        effects=GYRO,
        build=_bm20_2_7,
    ),
    GenericLawClaim(
        id="BM20-2.8",
        source="BM20 §2.2, eq. (2.8)",
        kind="equation",
        statement="X' = a (beta, omega), Y' = -a (alpha, omega); with alpha = M x gamma/G, beta = "
        "M/G "
        "on (M, gamma) = 0: X' = (a/G)(M, omega), Y' = (a/G)(gamma x M, omega)",
        system=BALL,
        effects=VBC,
        build=_bm20_2_8,
        note="for arbitrary I(t), k(t); (M, gamma) = 0 imposed by M = gamma x u",
    ),
    GenericLawClaim(
        id="BM20-3.1",
        source=f"{S3}, (3.1)",
        kind="transformation",
        statement="I(-t) = I(t), k(-t) = k(t): (t, M, gamma) -> (t, M, -gamma) maps solutions to "
        "solutions",
        system=BALL,
        effects=VB,
        build=_transformations([SYMMETRY], 1, 1),
        note="f(t, M, -gamma) = S f(t, M, gamma) exactly (for every law, even or not)",
    ),
    GenericLawClaim(
        id="BM20-3.1/involution",
        source=f"{S3}, (3.1) ('only the symmetry')",
        kind="transformation",
        statement="I(-t) = I(t), k(-t) = k(t): (t, M, gamma) -> (-t, -M, gamma) is a reversing "
        "symmetry",
        system=BALL,
        effects=VB,
        build=_transformations([INVOLUTION_1], 1, 1),
        expected="fails",
        note="BM20 says only the symmetry survives for even k: the involution must be refuted",
    ),
    GenericLawClaim(
        id="BM20-3.2/3.3",
        source=f"{S3}, (3.2), (3.3)",
        kind="transformation",
        statement="I(-t) = I(t), k(-t) = -k(t): the symmetry (t, M, gamma) -> (t, M, -gamma) and "
        "the "
        "involutions (t, M, gamma) -> (-t, -M, gamma), (-t, -M, -gamma)",
        system=BALL,
        effects=VB,
        build=_transformations([SYMMETRY, INVOLUTION_1, INVOLUTION_2], 1, -1),
        note="f(s t, S x) = s S f(t, x) exactly, for every even I(t) and odd k(t)",
    ),
    Claim(
        id="BKM12-3.sym",
        source="BKM12 §1.1, (2)-(3) (our derivation; used to name symmetric copies)",
        kind="transformation",
        statement="(t, M, gamma) -> (t, M, -gamma) maps solutions of the ball to solutions: "
        "omega = A (M + Z gamma) is even in gamma, gamma' = gamma x omega odd",
        system=BALL,
        effects=(),
        build=_transformations([SYMMETRY], 1, 1),
        note="chaplygin.numerics.ball.symmetry names the copy of an attractor reached under it",
    ),
    Claim(
        id="BKM12-3.sym.gyrostat",
        source="BKM12 §2.3, K01 §4 (our derivation)",
        kind="transformation",
        statement="with a constant gyrostat K: (t, M, gamma) -> (t, M, -gamma) maps solutions to "
        "solutions",
        system=BALL,
        effects=GYRO,
        build=_transformations([SYMMETRY], 1, 1),
    ),
    Claim(
        id="BKM12-3.sym/control-M",
        source="control",
        kind="transformation",
        statement="(wrong) (t, M, gamma) -> (t, -M, gamma) (no time reversal) maps solutions of "
        "the ball to solutions",
        system=BALL,
        effects=(),
        build=_transformations([({"M": -1}, 1)], 1, 1),
        expected="fails",
    ),
    Claim(
        id="BM20-3.4",
        source=f"{S3}, eq. (3.4)",
        kind="definition",
        statement="the variable_inertia model is (2.5) with I(t) = diag(I1 + (J_off + delta "
        "sin(Omega t))^2, "
        "I2, I3 + (J_off + delta sin(Omega t))^2)",
        system=BALL,
        effects=VI,
        build=_law_substitution,
        note="right-hand side and integrals = the generic model's with the law substituted",
    ),
    Claim(
        id="BM20-3.5",
        source=f"{S3}, eqs. (3.4), (3.5)",
        kind="definition",
        statement="the variable_gyrostat, variable_inertia model is (2.5) with I(t) of (3.4) and "
        "k(t) = K sin(Omega t)",
        system=BALL,
        effects=VB,
        build=_law_substitution,
    ),
    Claim(
        id="BM20-3.4.J0",
        source=f"{S3}, eqs. (3.3)-(3.5)",
        kind="transformation",
        statement="J_off = 0: I(t) of (3.4) is even, k(t) of (3.5) odd, and the involutions "
        "(t, M, gamma) -> (-t, -M, gamma), (-t, -M, -gamma) hold for the model",
        system=BALL,
        effects=VB,
        build=_involutions_at(0),
    ),
    Claim(
        id="BM20-3.4J",
        source=f"{S3}, eq. (3.4), Fig. 2 (J_off = -0.5)",
        kind="transformation",
        statement="the involutions (3.3) hold for I(t) of (3.4) and k(t) of (3.5) with J_off != 0",
        system=BALL,
        effects=VB,
        build=_involutions_at(None),
        expected="fails",
        note="I(t) is even only for J_off = 0 (FORMULAS.md [BM20-3.4J])",
    ),
    Claim(
        id="BM20-3.2rem",
        source=f"{S3}.2 (remark on delta)",
        kind="value",
        statement="I = (4, 3, 2), J_off = 0 in (3.4): I1(t) - I2 = 1 + delta^2 sin^2(Omega t) and "
        "I2 - I3(t) = (1 - delta^2) + delta^2 cos^2(Omega t), so I1(t) > I2 > I3(t) for all t "
        "iff delta < 1; delta = 2 violates the order (at sin(Omega t) = +-1)",
        system=BALL,
        effects=VI,
        build=_order_certificate(cos_square=True),
        note="a certificate: the minimum 1 - delta^2 of I2 - I3(t) is attained at cos = 0",
    ),
    Claim(
        id="BM20-3.2rem/control-sin",
        source=f"{S3}.2 (remark on delta; control)",
        kind="value",
        statement="the same certificate with I2 - I3(t) = (1 - delta^2) + delta^2 sin^2(Omega t)",
        system=BALL,
        effects=VI,
        build=_order_certificate(cos_square=False),
        expected="fails",
    ),
    GenericLawClaim(
        id="BM20-3.6",
        source=f"{S3}.1, eq. (3.6)",
        kind="equation",
        statement="start from rest: G = 0 is invariant and there gamma' = gamma x (-A k(t)), "
        "A = (I + d (Id - gamma ⊗ gamma))^-1; symmetry gamma -> -gamma; with (3.2) the "
        "involution (t, gamma) -> (-t, -gamma)",
        system=BALL,
        effects=VB,
        build=_bm20_3_6,
        note="for arbitrary I(t), k(t) (the involution for even I, odd k)",
    ),
    Claim(
        id="BM20-map",
        source=f"{S3}.1",
        kind="transformation",
        statement="gamma = (sqrt(1 - z^2) sin l, sqrt(1 - z^2) cos l, z) is a unit vector",
        system=BALL,
        effects=(),
        build=_bm20_map,
    ),
    Claim(
        id="BM20-3.7",
        source=f"{S3}.2, eq. (3.7) (Andoyer–Deprit variables)",
        kind="transformation",
        statement="M = G (sqrt(1-z^2) sin l, sqrt(1-z^2) cos l, z), gamma = (z cos g sin l + sin g "
        "cos l, "
        "z cos g cos l - sin g sin l, -sqrt(1-z^2) cos g): |gamma| = 1, (M, gamma) = 0, |M| = G",
        system=BALL,
        effects=(),
        build=_bm20_3_7,
        note="sqrt(1 - z^2) split off exactly; (sin, cos) pairs on the unit circle",
    ),
)


# ------------------------------------------------------------------------ Lyapunov spectrum
#: BM20 §3.2, Fig. 5: the strange attractor's exponents, per map iteration (per period
#: 2 pi/Omega), as printed with their error bars.
BM20_LYAPUNOV_PRINTED = ((0.041, 0.009), (-0.0033, 0.0011), (-0.075, 0.006))
#: Fig. 5's parameters (I = diag(4, 3, 2), d = 4.385, J = 0, delta = 2, K = (-6, -3, -9),
#: Omega = 1.07) in the model's order (I1, I2, I3, D, J_off, delta, K1, K2, K3, Omega).
BM20_FIG5_PARAMS = (4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.07)
#: Fig. 5's start in Andoyer-Deprit variables (BM20 (3.7)): G, z, l, g.
BM20_FIG5_ANDOYER = ("3", "0.5", "1", "1")
#: The run behind BM20-Lyap: renormalisation every forcing period, 500 periods of transient,
#: 8000 averaged, 3 initial states on Fig. 5's level set, 10 windows, DOP853 at rtol 1e-10.
#: A statistical bound (2 standard errors of ours + the printed error bar), not a margin: on 12
#: runs of this claim from starts perturbed by 1e-12, and 16 of three independently perturbed
#: starts each, the largest ratio was 0.74 and the control's smallest 2.5. Longer runs would
#: not widen it: our lambda_3 tends to -0.080 per iteration, 0.83 printed error bars from the
#: printed -0.075.
BM20_LYAPUNOV_RUN = {"intervals": 8000, "transient": 500, "states": 3, "windows": 10}


@cache
def _bm20_fig5_spectrum():  # noqa: ANN202 - a LyapunovResult
    """The level-set spectrum of Fig. 5's attractor (:data:`BM20_LYAPUNOV_RUN`), computed
    once per process: BM20-Lyap and its control compare the same run with other numbers."""
    import mpmath
    from chaplygin.numerics.ball.initial_state import state_from_andoyer
    from chaplygin.numerics.code import load_model_code
    from chaplygin.numerics.dynamics.lyapunov import lyapunov_spectrum

    code = load_model_code(BALL, VB)
    with mpmath.workdps(30):
        start = state_from_andoyer(*(mpmath.mpf(v) for v in BM20_FIG5_ANDOYER))
        y0 = [float(v) for v in start["M"] + start["gamma"]]
    return lyapunov_spectrum(code, BM20_FIG5_PARAMS, y0, rtol=1e-10, **BM20_LYAPUNOV_RUN)


def _bm20_lyapunov(printed: tuple[tuple[float, float], ...]) -> Callable:
    """Our level-set spectrum of Fig. 5's attractor against ``printed`` (per iteration).

    Agreement: each |ours - printed| within twice our standard error (batch means over
    windows or the spread over the initial states, the larger) plus the printed error bar;
    the error reported is the largest ratio of the two, to be at most 1.
    """

    def run():
        import numpy as np

        res = _bm20_fig5_spectrum()
        ours = res.per_iteration(res.exponents)
        errors = res.per_iteration(res.errors)
        paper = np.array([p for p, _ in printed])
        paper_err = np.array([e for _, e in printed])
        ratio = np.abs(ours - paper) / (2 * errors + paper_err)
        fmt = ", ".join
        return Computed(
            error=float(ratio.max()),
            bound=1.0,
            what=(
                f"level-set Lyapunov exponents per map iteration (per period 2 pi/Omega) of "
                f"Fig. 5's attractor, {res.intervals} periods after {res.transient} from "
                f"{res.per_state.shape[0]} states (DOP853 + variational equations in C, "
                f"rtol {res.rtol:g}), against the printed ones: the largest |difference| / "
                f"(2 x our standard error + printed error) must be <= 1"
            ),
            values={
                "ours per iteration": fmt(
                    f"{v:.4f} +- {e:.4f}" for v, e in zip(ours, errors, strict=True)
                ),
                "printed per iteration": fmt(f"{p} +- {e}" for p, e in printed),
                "ours per unit time": fmt(f"{v:.5f}" for v in res.exponents),
                "sum vs mean divergence per iteration": (
                    f"{res.per_iteration(res.sum_of_exponents):.6f} vs "
                    f"{res.per_iteration(res.mean_divergence):.6f}"
                ),
                "ratios": fmt(f"{v:.2f}" for v in ratio),
            },
        )

    return run


register(
    ComputedClaim(
        id="BM20-Lyap",
        source=f"{S3}.2, Fig. 5 (Lyapunov exponents of the strange attractor)",
        kind="value",
        statement="K = (-6, -3, -9), d = 4.385, J = 0, delta = 2, Omega = 1.07, G = 3, "
        "I = diag(4, 3, 2): Lyapunov exponents 0.041 +- 0.009, -0.0033 +- 0.0011, "
        "-0.075 +- 0.006 per map iteration",
        system=BALL,
        effects=VB,
        compute=_bm20_lyapunov(BM20_LYAPUNOV_PRINTED),
        note="Benettin/QR on the level set G = 3, (M, gamma) = 0, |gamma| = 1 (3 exponents), "
        "8000 periods, 3 initial states",
    ),
    ComputedClaim(
        id="BM20-Lyap/control-sign",
        source="control",
        kind="value",
        statement="(wrong) the largest exponent with its sign flipped: -0.041 +- 0.009, "
        "-0.0033 +- 0.0011, -0.075 +- 0.006 per map iteration (a regular attractor)",
        system=BALL,
        effects=VB,
        compute=_bm20_lyapunov(((-0.041, 0.009), *BM20_LYAPUNOV_PRINTED[1:])),
        expected="fails",
    ),
)


# ------------------------------------------------------------ BM20-3.1obs: from rest, J = 0
def _period_map_displacement(J_off: float, rtol: float = 1e-12):
    """Largest ``|P(gamma) - gamma|`` of the period map from rest (G = 0, BM20 §3.1) over
    eight starts spread over the sphere, at BM20 Fig. 2's K = (3, -1, -2), d = 1.5,
    delta = 1.2 and both printed Omega = 0.18, 0.4, with the given J.

    Found: for J = 0, ``gamma' = -gamma x A(t) k(t)`` is odd in t (A(t) even, k(t) odd) and
    tau-periodic, so every solution is even about t = 0 and t = tau/2: ``gamma(tau) = gamma(0)``,
    the period map is the identity and every motion from rest is periodic (BM20's "only
    periodic modes"). The bound is the integration's: 1000 rtol (about 10^2 Taylor steps per
    period, each within rtol)."""

    def run():
        import numpy as np
        from chaplygin.numerics.ball.map_coordinates import from_cylindrical
        from chaplygin.numerics.code import load_model_code
        from chaplygin.numerics.dynamics.poincare import StroboscopicMap

        code = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
        starts = [(0.83, 0.1), (0.41, 1.7), (-0.27, -2.3), (-0.9, 2.9), (0.05, -0.8),
                  (0.62, -1.9), (-0.55, 0.6), (0.97, 2.2)]  # fmt: skip
        worst, values = 0.0, {}
        for omega in (0.18, 0.4):
            params = {"I": (4, 3, 2), "D": 1.5, "J_off": J_off, "delta": 1.2,
                      "K": (3, -1, -2), "Omega": omega}  # fmt: skip
            strobe = StroboscopicMap(code, params, rtol=rtol, atol=rtol / 100)
            for z, l in starts:
                y0 = [0.0, 0.0, 0.0, *from_cylindrical(z, l)]
                y1 = strobe.step(y0)
                d = float(np.max(np.abs(np.asarray(y1, float) - y0)))
                worst = max(worst, d)
                values[f"Omega={omega} z={z} l={l}"] = f"{d:.3g}"
        return Computed(
            error=worst,
            bound=1000 * rtol,
            what=f"max |P(gamma) - gamma| of the period map from rest (J = {J_off}), 16 starts",
            values=values,
        )

    return run


register(
    ComputedClaim(
        id="BM20-3.1obs",
        source="BM20 §3.1",
        kind="solution",
        statement="from rest with J = 0 only periodic modes: the period map 2 pi/Omega is the "
        "identity at Fig. 2's K, d, delta and Omega = 0.18, 0.4 (every motion from rest periodic)",
        system="chaplygin_ball",
        compute=_period_map_displacement(0.0),
    )
)
register(
    ComputedClaim(
        id="BM20-3.1obs/control-J",
        source="control",
        kind="solution",
        statement="(wrong) with Fig. 2's J = -0.5 the period map from rest is the identity too",
        system="chaplygin_ball",
        compute=_period_map_displacement(-0.5),
        expected="fails",
    )
)


# ------------------------------------------------- BM20-3.1obs: no strange attractor from rest
#: The search of the claim (the sweep examples/sweeps/bm20-rest-search.toml searches wider):
#: Omega, J_off and starts (z, l, g) of BM20 (3.7) at G = 0, at Fig. 2's K, d, delta.
_REST_OMEGA, _REST_J = (0.18, 0.4, 1.3), (-1.0, -0.5, 0.6)
_REST_STARTS = ((0.7, 1.0, 0.3), (-0.6, 1.0, 1.2))
#: Map iterations: transient, recorded (period search), Lyapunov intervals.
_REST_RUN = {"transient": 300, "recorded": 200, "max_period": 32, "tol": 1e-6}


def _strange_attractor_search(points, intervals: int) -> Callable[[], Computed]:
    """Largest ``lambda - 3 s`` (per map iteration; ``s`` its standard error) over the
    attractors reached from the given (params, state) points, against ``ln(N)/N`` with
    ``N = intervals``: a chaotic attractor exceeds it
    (:func:`chaplygin.numerics.ball.regimes.attractor_regime`)."""

    def run() -> Computed:
        import numpy as np
        from chaplygin.numerics.ball.regimes import attractor_regime, linear_growth_rate
        from chaplygin.numerics.code import load_model_code

        code = load_model_code(BALL, list(VB))
        worst, counts, values = -np.inf, {}, {}
        for label, params, y0 in points():
            r = attractor_regime(code, params, y0, **_REST_RUN, intervals=intervals)
            counts[r.regime] = counts.get(r.regime, 0) + 1
            if r.period == 0:
                excess = r.lyapunov - 3 * r.lyapunov_error
                if excess > worst:
                    worst = excess
                    values["largest lambda - 3 s at"] = label
                    values["lambda per iteration"] = f"{r.lyapunov:.4g} +- {r.lyapunov_error:.2g}"
        values["regimes"] = ", ".join(f"{k}: {v}" for k, v in sorted(counts.items()))
        n = intervals
        return Computed(
            error=max(float(worst), 0.0),
            bound=linear_growth_rate(n),
            what=(
                f"{sum(counts.values())} attractors: {_REST_RUN['transient']} map iterations, "
                f"the period (<= {_REST_RUN['max_period']}, closing within {_REST_RUN['tol']:g}) "
                f"of the next {_REST_RUN['recorded']}, else the largest Lyapunov exponent over "
                f"{n} iterations (from rest: on the sphere of gamma); largest lambda - 3 s per "
                f"iteration against ln(N)/N = {linear_growth_rate(n):.2g} (DOP853 in C, rtol "
                f"1e-10; about {2 + 0.3 * n * sum(counts.values()) / 1000:.0f} s on an idle core)"
            ),
            values=values,
        )

    return run


def _from_rest_points():
    from chaplygin.numerics.ball.map_coordinates import from_andoyer_deprit

    for omega in _REST_OMEGA:
        for J in _REST_J:
            for z, l, g in _REST_STARTS:
                _, gamma = from_andoyer_deprit(0.0, z, l, g)
                params = [4, 3, 2, 1.5, J, 1.2, 3, -1, -2, omega]
                state = [0.0, 0.0, 0.0, *map(float, gamma)]
                yield f"Omega={omega} J={J} (z,l,g)={z, l, g}", params, state


def _fig5_point():
    from chaplygin.numerics.ball.bm20_map import bm20_state

    yield "Fig. 5, G = 3", list(BM20_FIG5_PARAMS), list(bm20_state([0.5, 1.0, 1.0], 3.0))


register(
    ComputedClaim(
        id="BM20-3.1obs.search",
        source="BM20 §3.1 ('no strange attractors were found'), §4",
        kind="solution",
        statement="from rest (G = 0) at Fig. 2's K = (3, -1, -2), d = 1.5, delta = 1.2: no "
        "strange attractor for Omega in {0.18, 0.4, 1.3}, J in {-1, -0.5, 0.6}, 2 starts each "
        "(the largest Lyapunov exponent of every attractor reached is not positive beyond 3 "
        "errors); the sweep examples/sweeps/bm20-rest-search.toml searches 15 x 13 x 6",
        system=BALL,
        effects=VB,
        compute=_strange_attractor_search(_from_rest_points, 1500),
    ),
    ComputedClaim(
        id="BM20-3.1obs.search/control-G3",
        source="control",
        kind="solution",
        statement="(wrong) the same holds for BM20 Fig. 5's motion (G = 3, Omega = 1.07, d = "
        "4.385): no strange attractor (6000 iterations: lambda - 3 s about 20 times ln(N)/N)",
        system=BALL,
        effects=VB,
        compute=_strange_attractor_search(_fig5_point, 6000),
        expected="fails",
    ),
)


# ------------------------------------------------------- BM20 Fig. 2: the attractors from rest
#: Starts (z, l, g) of BM20 (3.7) at G = 0 for the Fig. 2 claim.
_FIG2_STARTS = ((0.7, 1.0, 0.3), (-0.6, 1.0, 1.2), (0.1, 2.0, 2.5))


@cache
def _fig2_regime(omega: float, start: tuple[float, float, float]):  # noqa: ANN202
    """The regime from rest at Fig. 2's values from the start ``(z, l, g)``, computed once per
    process (BM20-Fig2.attractors and its control read the same runs)."""
    from chaplygin.numerics.ball.map_coordinates import from_andoyer_deprit
    from chaplygin.numerics.ball.regimes import attractor_regime
    from chaplygin.numerics.code import load_model_code

    code = load_model_code(BALL, list(VB))
    params = [4, 3, 2, 1.5, -0.5, 1.2, 3, -1, -2, omega]
    _, gamma = from_andoyer_deprit(0.0, *start)
    y0 = [0.0, 0.0, 0.0, *map(float, gamma)]
    return attractor_regime(code, params, y0, transient=10000, recorded=200, tol=1e-6,
                            intervals=1000)  # fmt: skip


def _fig2_regimes(expected: dict[float, str]) -> Callable[[], Computed]:
    """The regime reached from rest from each start at Fig. 2's values, after 10000 iterations
    (the map on the sphere contracts at -0.0019 per iteration and faster: e^-19; after 3000, a
    spiral onto the fixed point whose multipliers turn by about 2 pi/3 still closed at period 3
    within 1e-6), against the expected regime per Omega; the error counts the runs that
    differ."""

    def run() -> Computed:
        wrong, values = 0, {}
        for omega, regime in expected.items():
            for z, l, g in _FIG2_STARTS:
                r = _fig2_regime(omega, (z, l, g))
                wrong += r.regime != regime
                values[f"Omega={omega} start {z, l, g}"] = (
                    f"{r.regime}, period {r.period}, lambda {r.lyapunov:.2g} +- "
                    f"{r.lyapunov_error:.1g}, copy {r.copy.copy}"
                )
        return Computed(
            error=float(wrong),
            bound=0.0,
            what=(
                "from rest, I = diag(4, 3, 2), K = (3, -1, -2), d = 1.5, J = -0.5, delta = 1.2: "
                "regime after 10000 map iterations (period <= 64 within 1e-6, else the largest "
                "exponent on the sphere over 1000 iterations) from 3 starts per Omega, against "
                f"{expected}; runs that differ, counted (about 5 s)"
            ),
            values=values,
        )

    return run


register(
    ComputedClaim(
        id="BM20-Fig2.attractors",
        source="BM20 §3.1, Fig. 2 (fixed points and invariant curves)",
        kind="solution",
        statement="Fig. 2's maps with the transient discarded: at Omega = 0.18 (Fig. 2A) every "
        "start reaches a periodic point of the map (the fixed points of a mirror pair under "
        "gamma -> -gamma), at Omega = 0.4 (Fig. 2B) an attracting invariant curve "
        "(quasi-periodic)",
        system=BALL,
        effects=VB,
        compute=_fig2_regimes({0.18: "periodic", 0.4: "quasi-periodic"}),
    ),
    ComputedClaim(
        id="BM20-Fig2.attractors/control-swapped",
        source="control",
        kind="solution",
        statement="(wrong) invariant curves at Omega = 0.18, fixed points at 0.4",
        system=BALL,
        effects=VB,
        compute=_fig2_regimes({0.18: "quasi-periodic", 0.4: "periodic"}),
        expected="fails",
    ),
)


# ----------------------------------------------------------- BM20 Fig. 4: the fourth start
#: BM20 Fig. 4: I = diag(4, 3, 2), K = (-4, -5, 3), d = 4.5, J = 0, delta = 2, Omega = 2, G = 3;
#: the example scene's fourth start (z, l, g) = (0.5, 1, 1) and one of the other three.
_FIG4 = (4.0, 3.0, 2.0, 4.5, 0.0, 2.0, -4.0, -5.0, 3.0, 2.0)
_FIG4_FOURTH, _FIG4_OTHER = (0.5, 1.0, 1.0), (-0.5, -2.0, 2.0)
#: Map iterations: the fourth start's transient (its transverse exponents are about -3e-4 per
#: iteration: ~3e4 iterations to settle), the other's, and the points kept.
_FIG4_TRANSIENT, _FIG4_OTHER_TRANSIENT, _FIG4_POINTS = 40000, 3000, 2000


@cache
def _fig4_samples():
    from chaplygin.numerics import load_model_code
    from chaplygin.numerics.ball.bm20_map import bm20_points, bm20_state
    from chaplygin.numerics.dynamics.batch_map import BatchStroboscopicMap

    code = load_model_code(BALL, VB)
    bm = BatchStroboscopicMap(code, rtol=1e-10, atol=1e-12)
    out = []
    for x, transient in ((_FIG4_FOURTH, _FIG4_TRANSIENT), (_FIG4_OTHER, _FIG4_OTHER_TRANSIENT)):
        r = bm.run([bm20_state(x, 3.0)], [_FIG4], n=_FIG4_POINTS, transient=transient)
        if r.status[0]:
            raise ComputationError(f"BM20 Fig. 4 map failed from {x}")
        y = r.y[0]
        out.append((y, bm20_points(y)))
    return code, out


def _fig4_claim(same_curve: bool) -> Callable[[], Computed]:
    """The fourth start's attractor: a closed curve over g (its points sorted by g move by at
    most 5 % of the curve's extent in l and z from one to the next), at a distance from the
    other starts' curve of more than 3 sampling scales; ``same_curve`` is the control (the
    distance within 3 sampling scales)."""

    def run() -> Computed:
        import numpy as np
        from chaplygin.numerics.ball.regimes import map_points_scaled
        from chaplygin.numerics.dynamics.reversibility import set_distance

        code, ((y4, x4), (yo, _)) = _fig4_samples()
        q = x4[np.argsort(x4[:, 2])]
        extent = float(max(np.ptp(q[:, 0]), np.ptp(q[:, 1])))
        jump = float(np.max(np.abs(np.diff(q[:, :2], axis=0))))
        a, b = map_points_scaled(y4, code.state), map_points_scaled(yo, code.state)
        h = len(a) // 2
        scale = max(set_distance(a[:h], a[h:]), set_distance(b[:h], b[h:]))
        distance = set_distance(a, b)
        if same_curve:
            error, bound = distance / (3 * scale), 1.0
        else:
            error, bound = max(jump / (0.05 * extent), 3 * scale / distance), 1.0
        return Computed(
            error=error,
            bound=bound,
            what=(
                f"BM20 Fig. 4: map points {_FIG4_TRANSIENT} iterations after the fourth start "
                f"(z, l, g) = {_FIG4_FOURTH} and {_FIG4_OTHER_TRANSIENT} after {_FIG4_OTHER} "
                f"({_FIG4_POINTS} each, DOP853 in C, rtol 1e-10; about 4 s): the fourth's "
                "points sorted by g (a curve over g: largest step in l, z against 5 % of its "
                "extent) and the 0.9-quantile Hausdorff distance of the two sets in "
                "(M/G, gamma) against 3 sampling scales (halves)"
            ),
            values={
                "fourth: l range": f"[{q[:, 1].min():.4f}, {q[:, 1].max():.4f}]",
                "fourth: z range": f"[{q[:, 0].min():.4f}, {q[:, 0].max():.4f}]",
                "largest step along g": f"{jump:.2g} (extent {extent:.3g})",
                "distance of the two attractors": f"{distance:.3g}",
                "sampling scale": f"{scale:.2g}",
            },
        )

    return run


register(
    ComputedClaim(
        id="BM20-Fig4.fourth",
        source="BM20 §3.2, Fig. 4 ('the system comes to a quasi-periodic mode'); our scene's "
        "fourth start",
        kind="solution",
        statement="I = diag(4, 3, 2), K = (-4, -5, 3), d = 4.5, J = 0, delta = 2, Omega = 2, "
        "G = 3: from (z, l, g) = (0.5, 1, 1) the map settles (slowly: ~3e4 iterations) on an "
        "attracting closed invariant curve over g, another than the one the starts "
        "(-0.5, -2, 2), (0.1, 2.5, -1), (0.9, -0.7, 0.3) reach: two quasi-periodic attractors "
        "coexist",
        system=BALL,
        effects=VB,
        compute=_fig4_claim(same_curve=False),
    ),
    ComputedClaim(
        id="BM20-Fig4.fourth/control-same",
        source="control",
        kind="solution",
        statement="(wrong) the fourth start reaches the invariant curve of the other three",
        system=BALL,
        effects=VB,
        compute=_fig4_claim(same_curve=True),
        expected="fails",
    ),
)


# ------------------------------------------------- BM20 Fig. 6: the doubling 7 -> 14
#: Omega along the stable branch of the Fig. 7 cycle at d = 4.385 (saddle-node 1.0662312,
#: Neimark-Sacker 1.0670746: docs/howto/dynamics.md), up and down from
#: Fig. 7A's 1.06675, each refined by Newton from the previous one.
_BRANCH = ((1.06675, 1.0669, 1.0670), (1.0665, 1.0664, 1.06635))


@cache
def _seven_cycle_branch():
    import numpy as np
    from chaplygin.numerics.ball.bm20_map import bm20_map_with_jacobian, bm20_point, bm20_state
    from chaplygin.numerics.ball.regimes import attractor_regime
    from chaplygin.numerics.code import load_model_code
    from chaplygin.numerics.dynamics.periodic_orbits import refine_periodic_orbit

    code = load_model_code(BALL, list(VB))
    params = list(BM20_FIG5_PARAMS)
    params[9] = 1.06675
    # a start 3e-3 from a point of the cycle, in its basin (from Fig. 5's start the cycle is
    # reached after a chaotic transient whose length the last bits decide)
    r = attractor_regime(code, params, bm20_state([-0.44, 1.46, -1.01], 3.0), transient=3000,
                         max_period=32, intervals=10)  # fmt: skip
    smap = bm20_map_with_jacobian(params, 3.0, rtol=1e-10)
    out = []
    for omegas in _BRANCH:
        x = bm20_point(r.points[-1])
        for omega in omegas:
            orbit = refine_periodic_orbit(smap, x, 7, omega)
            x = np.asarray(orbit.points[0], dtype=float)
            out.append((omega, orbit))
    return r.period, sorted(out, key=lambda t: t[0])


def _doubling_claim(at_minus_one: bool) -> Callable[[], Computed]:
    """The multipliers of the Fig. 7 cycle along its stable branch. A period doubling needs a
    real multiplier at -1: the claim's error is the most negative real multiplier (0 when all
    are positive; infinite when Newton did not converge), bound 0; the control's error is the
    least ``|mu + 1|`` on the branch, bound 0.01."""

    def run() -> Computed:
        import numpy as np

        period, branch = _seven_cycle_branch()
        values, negative, nearest = {}, 0.0, np.inf
        for omega, orbit in branch:
            mu = np.asarray([complex(m) for m in orbit.multipliers])
            real = mu[np.abs(mu.imag) <= 1e-9].real
            negative = max(negative, *(-real), 0.0) if orbit.converged else np.inf
            nearest = min(nearest, float(np.min(np.abs(mu + 1))))
            values[f"Omega = {omega}"] = (
                f"{'converged' if orbit.converged else 'NOT converged'}, multipliers "
                + ", ".join(f"{abs(m):.4f} e^({np.angle(m):+.3f} i)" for m in mu)
            )
        values["least |mu + 1|"] = f"{nearest:.4f}"
        return Computed(
            error=float(nearest if at_minus_one else negative),
            bound=1e-2 if at_minus_one else 0.0,
            what=(
                f"the period-{period} cycle reached from a start 3e-3 from it (z, l, g = -0.44, "
                "1.46, -1.01) at Fig. 7A's Omega = 1.06675 (d = 4.385), refined by Newton on P^7 "
                "at Omega = "
                f"{[o for o, _ in branch]} (variational equations in C, rtol 1e-10; about 3 s) "
                "and its multipliers: "
                + (
                    "the least |mu + 1| on the branch (a doubling: <= 0.01)"
                    if at_minus_one
                    else "the most negative real multiplier (none: 0)"
                )
            ),
            values=values,
        )

    return run


register(
    ComputedClaim(
        id="BM20-Fig6.no-doubling",
        source="BM20 §3.2, Fig. 6 ('A doubling of period 7-14 was detected')",
        kind="solution",
        statement="the stable period-7 cycle of Figs. 6-7 (d = 4.385) does not double: along "
        "its branch from the saddle-node (Omega = 1.06623) to the Neimark-Sacker point "
        "(1.06707) its real multiplier stays positive and the complex pair leaves the unit "
        "circle off the real axis (BM20's 7 -> 14 is not this cycle's)",
        system=BALL,
        effects=VB,
        compute=_doubling_claim(at_minus_one=False),
    ),
    ComputedClaim(
        id="BM20-Fig6.no-doubling/control-minus-one",
        source="control",
        kind="solution",
        statement="(wrong, BM20's reading) a multiplier of the period-7 cycle reaches -1 on the "
        "branch (a period doubling 7 -> 14)",
        system=BALL,
        effects=VB,
        compute=_doubling_claim(at_minus_one=True),
        expected="fails",
    ),
)


# ------------------------------------------------------------------ attractor-repeller pair
#: BM20 Fig. 5 (I, D, J_off, delta, K, Omega) and three unrelated starts (z, l, g) at G = 3:
#: the paper's g(0) = l(0) = 1, z(0) = 0.5 for the attractor, two others for its second
#: sample and for the repeller.
_FIG5 = (4.0, 3.0, 2.0, 4.385, 0.0, 2.0, -6.0, -3.0, -9.0, 1.07)
_PAIR_STARTS = ((0.5, 1.0, 1.0), (-0.2, 2.5, -1.2), (-0.3, 2.2, -0.7))
#: Samples kept, periods discarded, integration tolerance, quantile of the set distance. The
#: attractor is intermittent (excursions of a few hundred periods every few thousand), so the
#: share of a sample spent in excursions is decided by the last bits of its start: up to 30 %
#: of 4000 points. The 0.9-quantile distance of 4000-point samples then failed the claim on 5
#: of 64 starts perturbed by 1e-12 (d(R1 A, repeller) up to 3.25 d(A, A')); the median
#: ignores the excursions and 12000 points average their share: on 40 perturbed starts
#: d(R_i A, repeller)/d(A, A') was 1.01 with standard deviation 0.10, at most 1.24 (the bound
#: 2 is ten standard deviations away) and the control's d(A, repeller)/d(A, A') at least 19
#: (9.5 times the bound).
_PAIR_N, _PAIR_TRANSIENT, _PAIR_RTOL, _PAIR_QUANTILE = 12000, 300, 1e-9, 0.5


@cache
def _pair(J_off: float):
    import numpy as np
    from chaplygin.numerics import load_model_code
    from chaplygin.numerics.ball.bm20_map import bm20_state
    from chaplygin.numerics.dynamics.reversibility import attractor_repeller_pair

    code = load_model_code(BALL, VB)
    params = list(_FIG5)
    params[4] = J_off
    starts = [bm20_state(np.array(x), 3.0) for x in _PAIR_STARTS]
    return attractor_repeller_pair(
        code,
        params,
        starts,
        n=_PAIR_N,
        transient=_PAIR_TRANSIENT,
        rtol=_PAIR_RTOL,
        quantile=_PAIR_QUANTILE,
    )


def _pair_claim(involution: str | None) -> Callable[[], Computed]:
    """d(R(A), repeller) (or d(A, repeller) for None) against twice the sampling scale
    d(A, A'): two samples of one invariant set differ by about the sampling scale, and the
    factor 2 covers the spread of that scale between samples (ten standard deviations of the
    ratio measured over perturbed starts, see ``_PAIR_N``)."""

    def run() -> Computed:
        r = _pair(0.0)
        error = r.attractor_distance if involution is None else r.image_distance[involution]
        return Computed(
            error=error,
            bound=2 * r.sampling_distance,
            what=(
                f"BM20 Fig. 5 (J_off = 0, Omega = 1.07, d = 4.385, G = 3): attractor A and a "
                f"second sample A' of it ({_PAIR_N} forward map points each after "
                f"{_PAIR_TRANSIENT}), repeller = {_PAIR_N} points of the inverse map from an "
                f"unrelated start; {_PAIR_QUANTILE:g}-quantile Hausdorff distance in "
                f"(M/G, gamma) of "
                f"{'A' if involution is None else involution.split()[0] + '(A)'} and the "
                f"repeller, bound 2 d(A, A') (Taylor, rtol {_PAIR_RTOL:g})"
            ),
            values={
                "d(A, A') (sampling)": f"{r.sampling_distance:.4f}",
                "d(A, repeller)": f"{r.attractor_distance:.4f}",
                **{
                    f"d({k.split()[0]}(A), repeller)": f"{v:.4f}"
                    for k, v in r.image_distance.items()
                },
            },
        )

    return run


register(
    ComputedClaim(
        id="BM20-3.3pair",
        source=f"{S3}, (3.3), Fig. 5",
        kind="solution",
        statement="J_off = 0, odd k(t): the involution (t, M, gamma) -> (-t, -M, gamma) maps the "
        "Fig. 5 attractor of the stroboscopic map onto a repeller (an attractor of the inverse "
        "map)",
        system=BALL,
        compute=_pair_claim("R1 (M, gamma) -> (-M, gamma)"),
        note="the repeller is sampled by the inverse map from a start unrelated to the "
        "attractor's, so the match is not built in",
    ),
    ComputedClaim(
        id="BM20-3.3pair/control-no-involution",
        source=f"{S3}, (3.3), Fig. 5 (control)",
        kind="solution",
        statement="the repeller of the Fig. 5 map is the attractor itself (no involution applied)",
        system=BALL,
        compute=_pair_claim(None),
        expected="fails",
    ),
)
