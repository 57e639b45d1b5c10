"""Claims of BKM12 §2.1-2.3: a rigid body in a spherical support (FORMULAS.md §1.6, §1.7).

Two kinds of model:

* the *N-ball* models of :func:`chaplygin.derive.spherical_support.n_ball_model`: the
  multi-body Ferrers equations reduced by projection (never the paper's result), for
  ``N = 1..4`` balls at seeded random rational contact directions fixed in space; the
  state carries the body components ``alpha, beta, gamma`` of the space axes (a frame)
  and ``n_k = c_k1 alpha + c_k2 beta + c_k3 gamma``. Every check there is proved modulo
  the frame's equations, for symbolic ``I, lambda_k, r_k`` (and ``K``), free ``omega``,
  spins ``nu_k`` and ``omega'`` (:class:`NBallClaim`);
* the registered closed model (``spherical_support``) in the eigenframe of the support
  tensor. ``BKM12-33.N*`` compares it with the N-ball derivation of a concrete support
  (random rational ``lambda_k, r_k``, directions) through
  :func:`~chaplygin.derive.spherical_support.support_parameters`: exact when the
  eigen-data are rational, else ``numeric`` (the eigenframe is irrational).
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp
from chaplygin.derive import Model
from chaplygin.derive.spherical_support import (
    derive_support,
    n_ball_model,
    support_parameters,
)
from chaplygin.derive.vectors import cross, dot

from ..identity import lie_derivative, measure_residual
from .base import Check, Claim, register

__all__ = [
    "NBallClaim",
    "SupportComparisonClaim",
    "SEEDS",
    "NUMERIC_CLAIMS",
    "support_notation",
]

SUPPORT = "spherical_support"
GYRO = ("gyrostat",)
RUBBER = ("rubber_balls",)
S21, S22, S23 = "BKM12 §2.1", "BKM12 §2.2", "BKM12 §2.3"
#: Seeds of the random rational contact directions of the N-ball checks.
SEEDS = {1: 2101, 2: 2102, 3: 2103, 4: 2104}


@lru_cache(maxsize=16)
def _n_ball(n: int, effects: tuple[str, ...], seed: int) -> Model:
    return n_ball_model(n, effects, space_directions=seed)


@dataclass(frozen=True, kw_only=True)
class NBallClaim(Claim):
    """A claim checked on the multi-body derivation of ``balls`` balls (random directions).

    Parameters
    ----------
    balls : int
        ``N``.
    """

    balls: int = 1

    def model(self) -> Model:
        """The N-ball model of the claim (cached; directions from ``SEEDS[balls]``).

        Returns
        -------
        Model
            The multi-body derivation with ``balls`` support balls and the claim's
            effects.
        """
        return _n_ball(self.balls, tuple(sorted(self.effects)), SEEDS[self.balls])


# ------------------------------------------------------------------ N-ball objects
@dataclass
class _Balls:
    omega: sp.Matrix
    n: list[sp.Matrix]  # body components of the contact directions
    w: list[sp.Matrix]  # the balls' angular velocity symbols
    nu: tuple
    I: sp.Matrix  # the paper's name
    lam: tuple
    r: tuple
    K: sp.Matrix
    vmap: dict
    P: sp.Matrix
    II: sp.Matrix
    rate: sp.Matrix
    der: object
    subs: dict


def _balls(model: Model) -> _Balls:
    der = model.details.derivation
    red = der.reduction
    subs = model.details.on_directions

    def on(e):
        return sp.sympify(e).xreplace(subs)

    return _Balls(
        omega=der.omega,
        n=model.details.directions,
        w=der.ball_velocities,
        nu=der.spins,
        I=sp.diag(*der.I),
        lam=der.lambdas,
        r=der.ratios,
        K=der.K if der.K is not None else sp.zeros(3, 1),
        vmap={s: on(e) for s, e in red.velocity_map.items()},
        P=red.momentum.applyfunc(on),
        II=red.inertia_operator.applyfunc(on),
        rate=red.momentum_rate.applyfunc(on),
        der=der,
        subs=subs,
    )


def _free(b: _Balls, *extra) -> list[sp.Symbol]:
    out = list(b.omega) + list(b.nu)
    for e in extra:
        out += list(e)
    return out


def _bkm12_30(model: Model) -> Check:
    b = _balls(model)
    red = b.der.reduction
    exprs = [sp.sympify(e).xreplace(b.subs) for e in red.quasi_momentum_rate]
    exprs += [
        sp.sympify(P).xreplace(b.subs) - b.lam[k] * b.nu[k]
        for k, P in enumerate(red.quasi_momentum)
    ]
    # nu_k = (omega_k, n_k) on the admissible velocities
    exprs += [dot(b.w[k].xreplace(b.vmap), b.n[k]) - b.nu[k] for k in range(len(b.n))]
    return Check(exprs, free=_free(b))


def _bkm12_31(model: Model) -> Check:
    b = _balls(model)
    exprs = []
    for k, n in enumerate(b.n):
        paper = -(b.omega - dot(b.omega, n) * n) / b.r[k] + b.nu[k] * n
        exprs += list(b.w[k].xreplace(b.vmap) - paper)
    P = b.I * b.omega + sum(
        (b.lam[k] / b.r[k] ** 2 * (b.omega - dot(b.omega, n) * n) for k, n in enumerate(b.n)),
        sp.zeros(3, 1),
    )
    exprs += list(b.P - b.K - P)
    exprs += list(b.rate - cross(P + b.K, b.omega))
    return Check(exprs, free=_free(b))


def _support_tensor(b: _Balls, weight) -> sp.Matrix:
    return sum(
        (weight(k) * n * n.T for k, n in enumerate(b.n)),
        sp.zeros(3, 3),
    )


def _bkm12_2_1M(weight: str = "paper"):
    def build(model: Model) -> Check:
        b = _balls(model)
        rubber = b.der.rubber

        def w(k):
            lam, r = b.lam[k], b.r[k]
            if weight == "control":  # lambda_k/r_k instead of lambda_k/r_k^2
                return lam / r
            return lam * (1 / r**2 - 1) if rubber else lam / r**2

        iso = sum((b.lam[k] / b.r[k] ** 2 for k in range(len(b.n))), sp.S.Zero)
        D_sup = _support_tensor(b, w)
        II = b.I + iso * sp.eye(3) - D_sup
        M = II * b.omega
        if weight == "control":  # the operators alone: a witness without free velocities
            return Check(list(b.II - II))
        exprs = list(b.II - II) + list(b.P - b.K - M) + list(b.rate - cross(M + b.K, b.omega))
        return Check(exprs, free=_free(b))

    return build


def _bkm12_41(model: Model) -> Check:
    b = _balls(model)
    exprs = []
    for k, n in enumerate(b.n):
        paper = -b.omega / b.r[k] + (1 + 1 / b.r[k]) * dot(b.omega, n) * n
        exprs += list(b.w[k].xreplace(b.vmap) - paper)
        exprs.append(dot(b.omega - b.w[k].xreplace(b.vmap), n))  # no twist, (39)
    return Check(exprs, free=_free(b))


def _bkm12_42(model: Model) -> Check:
    b = _balls(model)
    red = b.der.reduction
    wd = sp.Matrix(sp.symbols("omega_dot1:4", real=True))
    # the space-fixed vectors of the model (the frame of the space axes): V' = V x omega
    kin = [(model.group(name), cross(model.group(name), b.omega)) for name in model.vectors]
    kin = [(V, Vd) for V, Vd in kin if V != model.group("M")]
    exprs = []
    for k, n in enumerate(b.n):
        R = red.reaction(f"ball{k + 1}", wd).applyfunc(lambda e: e.xreplace(b.subs))
        lam, r = b.lam[k], b.r[k]
        mu = -dot(R, n)  # R = r_k n x N - mu_k n, (n x N) ⊥ n
        nxN = (R + mu * n) / r
        exprs.append(mu + lam * dot(wd, n))
        exprs += list(nxN + lam / r**2 * (wd - dot(wd, n) * n))
        n_rate = cross(n, b.omega)
        wk = b.w[k].xreplace(b.vmap)
        exprs += [dot(b.omega, n_rate), dot(wk, n_rate)]
        # (omega', n) = (omega_k', n), omega_k' = d/dt omega_k(omega, n)
        wk_rate = wk.jacobian(b.omega) * wd
        for V, Vd in kin:
            wk_rate += wk.jacobian(list(V)) * Vd
        exprs.append(dot(wd, n) - dot(wk_rate, n))
    return Check(exprs, free=_free(b, wd))


def _bkm12_2_2(model: Model) -> Check:
    """Rubber support = ordinary support with I + sum lambda_k Id and weights
    lambda_k (1/r_k^2 - 1)."""
    b = _balls(model)
    n_balls = len(b.n)
    effects = [e for e in model.effects if e != "rubber_balls"]
    plain = derive_support(n_balls, effects).reduction
    iso = sum(b.lam, sp.S.Zero)
    to_rubber = {b.lam[k]: b.lam[k] * (1 - b.r[k] ** 2) for k in range(n_balls)}
    to_rubber.update({Ii: Ii + iso for Ii in b.der.I})

    def mapped(e):
        return sp.sympify(e).xreplace(to_rubber).xreplace(b.subs)

    exprs = list(b.II - plain.inertia_operator.applyfunc(mapped))
    exprs += list(b.rate - plain.momentum_rate.applyfunc(mapped))
    exprs += list(b.P - plain.momentum.applyfunc(mapped))
    return Check(exprs, free=_free(b))


# ------------------------------------------------------------------ closed model
@dataclass
class SupportNotation:
    M: sp.Matrix
    alpha: sp.Matrix
    beta: sp.Matrix
    gamma: sp.Matrix
    omega: sp.Matrix  # the model's auxiliary omega symbols
    I: sp.Matrix
    D_iso: sp.Symbol
    D_al: sp.Symbol
    D_be: sp.Symbol
    J: sp.Matrix
    A: sp.Matrix
    K: sp.Matrix

    def operator(self) -> sp.Matrix:
        """BKM12-33: ``J - D_al alpha⊗alpha - D_be beta⊗beta``.

        Returns
        -------
        sympy.Matrix, shape (3, 3)
            The inertia operator ``M = operator() omega``.

        References
        ----------
        BKM12-33
        """
        a, b = self.alpha, self.beta
        return self.J - self.D_al * a * a.T - self.D_be * b * b.T

    def X(self) -> sp.Matrix:
        """BKM12-34: the 2x2 matrix ``X`` of ``Z = X^-1 Y``.

        ``X = [[D_al^-1 - (alpha, A alpha), -(alpha, A beta)],
        [-(alpha, A beta), D_be^-1 - (beta, A beta)]]``.

        Returns
        -------
        sympy.Matrix, shape (2, 2)
            Symmetric, in ``alpha``, ``beta`` and the parameters.

        References
        ----------
        BKM12-34
        """
        a, b, A = self.alpha, self.beta, self.A
        return sp.Matrix(
            [
                [1 / self.D_al - dot(a, A * a), -dot(a, A * b)],
                [-dot(a, A * b), 1 / self.D_be - dot(b, A * b)],
            ]
        )

    def omega_formula(self) -> sp.Matrix:
        """BKM12-34: ``A (M + Z_al alpha + Z_be beta)``, ``Z = X^-1 Y``.

        ``Y = ((A M, alpha), (A M, beta))``.

        Returns
        -------
        sympy.Matrix, shape (3, 1)
            ``omega`` in ``M``, ``alpha``, ``beta`` and the parameters.

        References
        ----------
        BKM12-34
        """
        Y = sp.Matrix([dot(self.A * self.M, self.alpha), dot(self.A * self.M, self.beta)])
        Z = self.X().inv() * Y
        return self.A * (self.M + Z[0] * self.alpha + Z[1] * self.beta)


def support_notation(model: Model) -> SupportNotation:
    """The paper's objects of §2.1 in the closed model's symbols (typed from BKM12).

    Parameters
    ----------
    model : Model
        The closed spherical-support model (groups ``M``, ``alpha``, ``beta``,
        ``gamma``; parameters ``I``, ``D_iso``, ``D_al``, ``D_be``, optionally ``K``).

    Returns
    -------
    SupportNotation
        ``J = I + D_iso Id``, ``A = J^-1``; ``K`` is zero without a gyrostat.
    """
    I = model.param_group("I")
    D_iso = model.param_group("D_iso")[0]
    J = sp.diag(*[I[i] + D_iso for i in range(3)])
    names = {p.name for p in model.parameters}
    return SupportNotation(
        M=model.group("M"),
        alpha=model.group("alpha"),
        beta=model.group("beta"),
        gamma=model.group("gamma"),
        omega=sp.Matrix(model.omega),
        I=I,
        D_iso=D_iso,
        D_al=model.param_group("D_al")[0],
        D_be=model.param_group("D_be")[0],
        J=J,
        A=sp.diag(*[1 / J[i, i] for i in range(3)]),
        K=model.param_group("K") if "K" in names else sp.zeros(3, 1),
    )


def _rhs(model: Model, group: str) -> sp.Matrix:
    return sp.Matrix([model.rhs[model.state.index(s)] for s in model.vectors[group]])


def _bkm12_32(model: Model) -> Check:
    """Model equations, and the derivation's momentum rate for every omega."""
    n = support_notation(model)
    w = n.omega
    exprs = list(_rhs(model, "M") - cross(n.M + n.K, w))
    for name in ("alpha", "beta", "gamma"):
        exprs += list(_rhs(model, name) - cross(model.group(name), w))
    M_of_w = n.operator() * w
    exprs += list(model.details.momentum_rate_of_omega - cross(M_of_w + n.K, w))
    return Check(exprs, free=list(w))


def _bkm12_33(model: Model) -> Check:
    n = support_notation(model)
    w = n.omega
    exprs = list(model.momentum_of_omega - n.operator() * w)
    exprs += list(n.operator() * model.expand_aux(w) - n.M)  # omega(M) inverts it
    return Check(exprs, free=list(w))


def _bkm12_34(model: Model) -> Check:
    n = support_notation(model)
    return Check(list(model.expand_aux(n.omega) - n.omega_formula()))


def _conserved(which: str):
    def build(model: Model) -> Check:
        n = support_notation(model)
        P = n.M + n.K
        a, b = n.alpha, n.beta
        F = {
            "35": [dot(a, a), dot(b, b), dot(a, b)],
            "36": [dot(P, a), dot(P, b), dot(P, cross(a, b))],
            "37": [dot(n.M, n.omega) / 2],
            "Rem2": [dot(P, P)],
            "2.3E/literal": [dot(n.M + n.K, n.omega) / 2],
            "control": [dot(n.M, n.A * a)],
        }[which]
        exprs = [lie_derivative(f, model) for f in F]
        if which == "37":  # and it is the derived energy
            derived = model.details.derived_energy
            exprs.append(model.expand_aux(derived - dot(n.M, n.omega) / 2))
        if which == "Rem2":
            exprs.append(dot(P, P) - dot(P, a) ** 2 - dot(P, b) ** 2 - dot(P, cross(a, b)) ** 2)
        return Check(exprs)

    return build


def _bkm12_2_3_integrals(model: Model) -> Check:
    parts = [_conserved(w)(model) for w in ("35", "36", "37")]
    return Check([e for p in parts for e in p.exprs])


def _measure(kind: str):
    def build(model: Model) -> Check:
        n = support_notation(model)
        X = n.X()
        detX = X[0, 0] * X[1, 1] - X[0, 1] ** 2
        rho = {
            "paper": n.operator().det(method="berkowitz") ** sp.Rational(-1, 2),
            "X": detX ** sp.Rational(-1, 2),
            "X+1/2": detX ** sp.Rational(1, 2),
            "X-1": 1 / detX,
        }[kind]
        return Check([measure_residual(rho, model)])

    return build


def _bkm12_38_factor(model: Model) -> Check:
    """det(J - D_al a⊗a - D_be b⊗b) = det(J) D_al D_be det(X): the densities differ by a
    constant factor; also the model's density is det(X)^-1/2."""
    n = support_notation(model)
    X = n.X()
    detX = X[0, 0] * X[1, 1] - X[0, 1] ** 2
    exprs = [n.operator().det(method="berkowitz") - n.J.det() * n.D_al * n.D_be * detX]
    exprs.append(model.density ** (-2) - detX)
    return Check(exprs)


def _rubber_closed(model: Model) -> Check:
    """The closed model with rubber balls has the same right-hand side and omega."""
    from chaplygin.derive import build_model

    plain = build_model(SUPPORT, [e for e in model.effects if e != "rubber_balls"])
    exprs = [a - b for a, b in zip(model.rhs_expanded, plain.rhs_expanded, strict=True)]
    exprs += list(model.momentum_of_omega - plain.momentum_of_omega)
    return Check(exprs, free=list(model.omega))


# ------------------------------------------------------------------ N balls vs closed model
def _concrete_support(n_balls: int, seed: int):
    rng = random.Random(seed)
    lam = [sp.Rational(rng.randint(1, 9), rng.randint(1, 4)) for _ in range(n_balls)]
    r = [sp.Rational(rng.randint(1, 6), rng.randint(2, 6)) for _ in range(n_balls)]
    return lam, r


@dataclass(frozen=True, kw_only=True)
class SupportComparisonClaim(Claim):
    """The closed model against the N-ball derivation of a concrete random support."""

    balls: int = 1

    def model(self) -> Model:
        """The closed built-in model of the claim's system and effects.

        Returns
        -------
        Model
            ``build_model(self.system, self.effects)``.
        """
        from chaplygin.derive import build_model

        return build_model(self.system, self.effects)


def _compare(n_balls: int):
    def build(model: Model) -> Check:
        nb = _n_ball(n_balls, tuple(sorted(model.effects)), SEEDS[n_balls])
        b = _balls(nb)
        lam, r = _concrete_support(n_balls, SEEDS[n_balls])
        space = nb.details.space_directions
        data = support_parameters(lam, r, [list(c) for c in space], effects=model.effects)
        n = support_notation(model)
        e = [n.alpha, n.beta, n.gamma]
        # the N-ball model's frame (space axes) written in the eigenframe
        frame_of = {}
        for i, name in enumerate(("alpha", "beta", "gamma")):
            axis = sum((data.frame[j, i] * e[j] for j in range(3)), sp.zeros(3, 1))
            frame_of.update(dict(zip(nb.group(name), axis, strict=True)))
        to_concrete = {**dict(zip(b.lam, lam, strict=True)), **dict(zip(b.r, r, strict=True))}
        to_concrete.update(
            {D: v for D, v in zip((n.D_iso, n.D_al, n.D_be), data.params().values(), strict=True)}
        )

        def balls(x):  # the N-ball expressions, in the eigenframe (same symbols!)
            return sp.sympify(x).xreplace(frame_of).xreplace(to_concrete)

        def closed(x):
            return sp.sympify(x).xreplace(to_concrete)

        w = n.omega
        II_closed = model.momentum_of_omega.jacobian(w).applyfunc(closed)
        exprs = list(b.II.applyfunc(balls) - II_closed)
        M_of_w = II_closed * w
        rate_closed = _rhs(model, "M").xreplace(dict(zip(n.M, M_of_w, strict=True)))
        exprs += list(b.rate.applyfunc(balls) - rate_closed.applyfunc(closed))
        return Check(exprs, free=list(w) + list(b.nu))

    return build


# ------------------------------------------------------------------ registration
_CLAIMS: list[Claim] = []
for N in (1, 2, 3, 4):
    _CLAIMS += [
        NBallClaim(
            id=f"BKM12-30.N{N}",
            source=f"{S21}, eq. (30)",
            kind="integral",
            statement=f"nu_k = (omega_k, n_k) = const ({N} balls at random directions)",
            system=SUPPORT,
            effects=(),
            build=_bkm12_30,
            note="the projected equations of the extra quasi-velocities nu_k: "
            "d/dt (lambda_k nu_k) = 0",
            balls=N,
        ),
        NBallClaim(
            id=f"BKM12-31.N{N}",
            source=f"{S21}, eq. (31) (reconstructed)",
            kind="equation",
            statement="omega_k = -(1/r_k)(omega - (omega, n_k) n_k) + nu_k n_k; "
            "d/dt[I omega + sum (lambda_k/r_k^2)(omega - (omega, n_k) n_k)] = [same] x omega "
            f"({N} balls)",
            system=SUPPORT,
            effects=(),
            build=_bkm12_31,
            balls=N,
        ),
        NBallClaim(
            id=f"BKM12-2.1M.N{N}",
            source=f"{S21}",
            kind="equation",
            statement="M = (I + sum_k (lambda_k/r_k^2) Id - D_sup) omega, "
            f"D_sup = sum_k (lambda_k/r_k^2) n_k ⊗ n_k, M' = M x omega ({N} balls)",
            system=SUPPORT,
            effects=(),
            build=_bkm12_2_1M(),
            balls=N,
        ),
        NBallClaim(
            id=f"BKM12-41.N{N}",
            source=f"{S22}, eq. (41)",
            kind="equation",
            statement=f"omega_k = -(1/r_k) omega + (1 + 1/r_k)(omega, n_k) n_k ({N} rubber balls)",
            system=SUPPORT,
            effects=RUBBER,
            build=_bkm12_41,
            balls=N,
        ),
        NBallClaim(
            id=f"BKM12-42.N{N}",
            source=f"{S22}, eq. (42) (reconstructed)",
            kind="equation",
            statement="(omega, n_k') = (omega_k, n_k') = 0, (omega', n_k) = (omega_k', n_k); "
            "mu_k = -lambda_k (omega', n_k), "
            f"n_k x N_k = -(lambda_k/r_k^2)(omega' - (omega', n_k) n_k) ({N} rubber balls)",
            system=SUPPORT,
            effects=RUBBER,
            build=_bkm12_42,
            note="reactions on each ball from its Ferrers equation, for every omega'",
            balls=N,
        ),
        NBallClaim(
            id=f"BKM12-2.2.N{N}",
            source=f"{S22}",
            kind="equation",
            statement="rubber balls: M = (I + sum_k (lambda_k/r_k^2) Id - D_rub) omega, M' = M x "
            "omega, "
            "D_rub = sum_k lambda_k (1/r_k^2 - 1) n_k ⊗ n_k",
            system=SUPPORT,
            effects=RUBBER,
            build=_bkm12_2_1M(),
            balls=N,
        ),
        NBallClaim(
            id=f"BKM12-2.2.equiv.N{N}",
            source=f"{S22}",
            kind="transformation",
            statement="the rubber support is the ordinary support with I -> I + sum_k lambda_k Id "
            "and "
            f"lambda_k/r_k^2 -> lambda_k (1/r_k^2 - 1) ({N} balls)",
            system=SUPPORT,
            effects=RUBBER,
            build=_bkm12_2_2,
            balls=N,
        ),
        SupportComparisonClaim(
            id=f"BKM12-33.N{N}",
            source=f"{S21}, eqs. (32), (33)",
            kind="equation",
            statement="a concrete support of N balls (random rational lambda_k, r_k, directions) "
            "gives "
            "the closed model with J = I + D_iso Id, D_al, D_be from the eigen-data of D_sup "
            f"(N = {N})",
            system=SUPPORT,
            effects=(),
            build=_compare(N),
            note="support_parameters: numeric when the eigenframe is irrational",
            balls=N,
        ),
    ]

_CLAIMS += [
    NBallClaim(
        id="BKM12-2.1M/control-weight",
        source=f"{S21} (negative control)",
        kind="equation",
        statement="the inertia operator I + sum (lambda_k/r_k^2) Id - D_sup with the weights "
        "lambda_k/r_k instead of lambda_k/r_k^2 in D_sup (2 balls)",
        system=SUPPORT,
        effects=(),
        build=_bkm12_2_1M("control"),
        expected="fails",
        balls=2,
    ),
    NBallClaim(
        id="BKM12-2.3.N2",
        source=f"{S23}",
        kind="equation",
        statement="gyrostat on 2 balls: M' = (M + K) x omega, "
        "M = (I + sum (lambda_k/r_k^2) Id - D_sup) omega",
        system=SUPPORT,
        effects=GYRO,
        build=_bkm12_2_1M(),
        balls=2,
    ),
    Claim(
        id="BKM12-32",
        source=f"{S21}, eq. (32)",
        kind="equation",
        statement="M' = M x omega, alpha' = alpha x omega, beta' = beta x omega (gamma' = gamma x "
        "omega)",
        system=SUPPORT,
        effects=(),
        build=_bkm12_32,
        note="the model's right-hand side, and the derived momentum rate for every omega",
    ),
    Claim(
        id="BKM12-33",
        source=f"{S21}, eq. (33)",
        kind="equation",
        statement="M = (J - D_al alpha⊗alpha - D_be beta⊗beta) omega, J = I + D_iso Id "
        "(D_iso = sum lambda_k/r_k^2 - D_ga0, D_al = D_al0 - D_ga0, D_be = D_be0 - D_ga0)",
        system=SUPPORT,
        effects=(),
        build=_bkm12_33,
    ),
    Claim(
        id="BKM12-34",
        source=f"{S21}, eq. (34)",
        kind="equation",
        statement="omega = A (M + Z_al alpha + Z_be beta), A = J^-1, (Z_al, Z_be) = X^-1 (Y_al, "
        "Y_be), "
        "X = [[D_al^-1 - (alpha, A alpha), -(alpha, A beta)], [-(alpha, A beta), "
        "D_be^-1 - (beta, A beta)]], Y = ((A M, alpha), (A M, beta))",
        system=SUPPORT,
        effects=(),
        build=_bkm12_34,
    ),
    Claim(
        id="BKM12-35",
        source=f"{S21}, eq. (35)",
        kind="integral",
        statement="alpha^2 = 1, beta^2 = 1, (alpha, beta) = 0 are preserved",
        system=SUPPORT,
        effects=(),
        build=_conserved("35"),
    ),
    Claim(
        id="BKM12-36",
        source=f"{S21}, eq. (36)",
        kind="integral",
        statement="(M, alpha), (M, beta), (M, alpha x beta) are first integrals",
        system=SUPPORT,
        effects=(),
        build=_conserved("36"),
    ),
    Claim(
        id="BKM12-36/control-(M,A alpha)",
        source=f"{S21} (negative control)",
        kind="integral",
        statement="(M, A alpha) is a first integral (it is not)",
        system=SUPPORT,
        effects=(),
        build=_conserved("control"),
        expected="fails",
    ),
    Claim(
        id="BKM12-37",
        source=f"{S21}, eq. (37)",
        kind="integral",
        statement="H = (M, omega)/2 is a first integral (and the derived energy without the balls' "
        "spins)",
        system=SUPPORT,
        effects=(),
        build=_conserved("37"),
    ),
    Claim(
        id="BKM12-Rem2",
        source=f"{S21}, Remark 2",
        kind="integral",
        statement="(M, M) = (M, alpha)^2 + (M, beta)^2 + (M, alpha x beta)^2 = const",
        system=SUPPORT,
        effects=(),
        build=_conserved("Rem2"),
    ),
    Claim(
        id="BKM12-38",
        source=f"{S21}, eq. (38)",
        kind="measure",
        statement="invariant measure rho dM dalpha dbeta, rho = det(J - D_al alpha⊗alpha - "
        "D_be beta⊗beta)^-1/2",
        system=SUPPORT,
        effects=(),
        build=_measure("paper"),
        note="on the frame phase space (gamma = alpha x beta carried along: div of its "
        "equation is zero)",
    ),
    Claim(
        id="BKM12-38.X",
        source=f"{S21}, eq. (38)",
        kind="measure",
        statement="rho = det(X)^-1/2 (X of BKM12-34) is invariant; det(J - D_al a⊗a - D_be b⊗b) = "
        "det(J) D_al D_be det(X) (a constant factor); the model ships det(X)^-1/2",
        system=SUPPORT,
        effects=(),
        build=lambda m: Check(_measure("X")(m).exprs + _bkm12_38_factor(m).exprs),
    ),
    Claim(
        id="BKM12-38/control-exponent+1/2",
        source=f"{S21} (negative control)",
        kind="measure",
        statement="rho = det(X)^(+1/2) is an invariant density (wrong exponent)",
        system=SUPPORT,
        effects=(),
        build=_measure("X+1/2"),
        expected="fails",
    ),
    Claim(
        id="BKM12-38/control-exponent-1",
        source=f"{S21} (negative control)",
        kind="measure",
        statement="rho = det(X)^-1 is an invariant density (wrong exponent)",
        system=SUPPORT,
        effects=(),
        build=_measure("X-1"),
        expected="fails",
    ),
    Claim(
        id="BKM12-2.2",
        source=f"{S22}",
        kind="equation",
        statement="with rubber balls the closed system is the same as (32)-(34) (only the meaning "
        "of "
        "D_iso, D_al, D_be changes)",
        system=SUPPORT,
        effects=RUBBER,
        build=_rubber_closed,
    ),
    Claim(
        id="BKM12-2.3",
        source=f"{S23}",
        kind="equation",
        statement="M' = (M + K) x omega, alpha' = alpha x omega, beta' = beta x omega, with (33), "
        "(34)",
        system=SUPPORT,
        effects=GYRO,
        build=lambda m: Check(
            _bkm12_32(m).exprs + _bkm12_34(m).exprs, free=list(m.omega)
        ),
        note="derived from T = (omega, I omega)/2 + (K, omega) + sum lambda_k omega_k^2/2",
    ),
    Claim(
        id="BKM12-2.3.integrals",
        source=f"{S23}",
        kind="integral",
        statement="alpha^2 = beta^2 = 1, (alpha, beta) = 0, (M + K, alpha), (M + K, beta), "
        "(M + K, alpha x beta), H = (M, omega)/2 are first integrals",
        system=SUPPORT,
        effects=GYRO,
        build=_bkm12_2_3_integrals,
    ),
    Claim(
        id="BKM12-2.3.measure",
        source=f"{S23}",
        kind="measure",
        statement="the density (38) is invariant for the gyrostat",
        system=SUPPORT,
        effects=GYRO,
        build=_measure("paper"),
    ),
    Claim(
        id="BKM12-2.3E/literal",
        source=f"{S23} (literal reading)",
        kind="integral",
        statement="H = (M + K, omega)/2 is a first integral",
        system=SUPPORT,
        effects=GYRO,
        build=_conserved("2.3E/literal"),
        expected="fails",
        note="FORMULAS.md: FAILED as transcribed; (M, omega)/2 is conserved (BKM12-2.3E)",
    ),
    Claim(
        id="BKM12-2.3E",
        source=f"{S23} (corrected)",
        kind="integral",
        statement="H = (M, omega)/2 is a first integral of the gyrostat in a spherical support",
        system=SUPPORT,
        effects=GYRO,
        build=_conserved("37"),
    ),
]

#: Decided ``numeric`` (the eigenframe of a random support is irrational): checked by the
#: test suite, not registered, since every registered claim that holds must be proved.
#: ``BKM12-33.N1`` (one ball: rational eigen-data) is registered and proved.
NUMERIC_CLAIMS = [c for c in _CLAIMS if c.id in ("BKM12-33.N2", "BKM12-33.N3", "BKM12-33.N4")]

register(*(c for c in _CLAIMS if c not in NUMERIC_CLAIMS))
