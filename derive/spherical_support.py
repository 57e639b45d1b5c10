"""A rigid body in a spherical support (Fedorov's problem, BKM12 §2.1-2.3).

A body (central principal moments ``I1, I2, I3``) is rigidly enclosed in a spherical
shell of radius ``R0`` centred at its centre of mass; ``N`` dynamically symmetric balls
(moments of inertia ``lambda_k``, radii ``R_k``, ratios ``r_k = R_k/R0``) with fixed
centres touch the shell at the space-fixed unit directions ``n_k`` (body components
``n_k' = n_k x omega``).

Mechanical description (BKM12-27, 28, 39; nothing of the result is typed in):

* ``T = (omega, I omega)/2 + sum_k lambda_k (omega_k, omega_k)/2`` (+ ``(K, omega)`` with
  the ``gyrostat`` effect, BKM12 §2.3), the balls' angular velocities ``omega_k`` in the
  body frame;
* no slip at the contacts, ``f_k = omega x n_k + r_k omega_k x n_k = 0`` (BKM12-27); with
  ``rubber_balls`` also no twist, ``g_k = (omega - omega_k, n_k) = 0`` (BKM12-39);
* without ``rubber_balls`` the constraints leave the spins ``nu_k = (omega_k, n_k)`` free:
  they are extra quasi-velocities of the reduction.

:func:`derive_support` reduces the Ferrers equations of ``N`` balls with symbolic unit
directions (:mod:`.multibody`, multipliers eliminated by projection) and
:func:`n_ball_model` makes a :class:`~.model.Model` of it, optionally for concrete
space-fixed directions written in a body-fixed view of the space axes (a frame
``alpha, beta, gamma``).

The registered closed model (BKM12-32..34) lives in the eigenframe ``alpha, beta, gamma``
(body components, fixed in space) of the support tensor ``D_sup``. Parameters:

``I1, I2, I3``
    central principal moments of inertia of the body;
``D_iso``
    isotropic part of the support, ``J = I + D_iso Id``:
    ``D_iso = sum_k lambda_k/r_k^2 - D_ga0``;
``D_al, D_be``
    ``D_al = D_al0 - D_ga0``, ``D_be = D_be0 - D_ga0`` (BKM12-33), from the eigenvalues
    ``D_al0, D_be0, D_ga0`` of ``D_sup = sum_k lambda_k/r_k^2 n_k ⊗ n_k`` (rubber balls:
    ``sum_k lambda_k (1/r_k^2 - 1) n_k ⊗ n_k``, BKM12-2.2);
``K1, K2, K3``
    gyrostatic momentum (``gyrostat``).

so that ``M = (J - D_al alpha⊗alpha - D_be beta⊗beta) omega``. Any support with the same
tensor gives the same reduced equations (BKM12-2.1M, checked for N = 1..4 balls by the
claims), so the closed model is derived from the support of three balls along
``alpha, beta, gamma`` whose weights realise ``D_iso, D_al, D_be``; ``omega`` comes from
the engine's rank-2 structured inverse ``U = [alpha beta]`` (the 2x2 ``X`` of BKM12-34).
:func:`support_parameters` computes ``D_iso, D_al, D_be`` and the eigenframe from
physical ball data.

References
----------
BKM12-27..38, BKM12-Rem2, BKM12-39..42, BKM12-2.2, BKM12-2.3 (FORMULAS.md §1.6, §1.7).
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import lru_cache

import mpmath
import sympy as sp

from .algebra import ConstraintIdeal
from .description import MechanicalDescription, apply_effects
from .effects import parse_effects
from .engine import ReducedEquations
from .errors import DerivationError, UserInputError
from .geometry import FRAME, UNIT_VECTOR, PoissonGroup
from .model import Model, ModelDetails, ParameterSpec, Reparametrisation
from .multibody import MultiBodyDescription, MultiBodyReduction, ferrers_multibody
from .vectors import cross, dot, vector

__all__ = [
    "NAME",
    "DESCRIPTION",
    "SUPPORTED_EFFECTS",
    "GENERATED_VARIANTS",
    "BUILDER",
    "SupportDerivation",
    "NBallDetails",
    "ClosedSupportDetails",
    "support_description",
    "SupportParameters",
    "derive_support",
    "n_ball_model",
    "support_parameters",
    "build_spherical_support",
]

NAME = "spherical_support"
DESCRIPTION = (
    "rigid body in a spherical support of N balls (Fedorov's problem), closed system in the "
    "eigenframe of the support tensor (BKM12 §2.1-2.3)"
)
SUPPORTED_EFFECTS = ("gyrostat", "rubber_balls")
#: Effect combinations whose code is committed in generated/ (``rubber_balls`` gives the same
#: closed equations as the plain support: only the meaning of the D parameters changes).
GENERATED_VARIANTS: tuple[tuple[str, ...], ...] = ((), ("gyrostat",))

T_SYMBOL = sp.Symbol("t", real=True)


# ============================================================== N-ball derivation
@dataclass
class SupportDerivation:
    """The reduced Ferrers equations of a body on ``N`` balls (symbolic directions).

    Attributes
    ----------
    reduction : MultiBodyReduction
    omega : sympy.Matrix
        Angular velocity of the body.
    ball_velocities : list of sympy.Matrix
        ``omega_k`` symbols.
    directions : list of sympy.Matrix
        Symbolic unit vectors ``n_k`` (state groups ``n1 .. nN``).
    spins : tuple of sympy.Symbol
        ``nu_k`` (empty with rubber balls).
    I, lambdas, ratios, K :
        Parameter symbols (``K`` is None without gyrostat).
    rubber : bool
    """

    reduction: MultiBodyReduction
    omega: sp.Matrix
    ball_velocities: list[sp.Matrix]
    directions: list[sp.Matrix]
    spins: tuple[sp.Symbol, ...]
    I: sp.Matrix  # the paper's name
    lambdas: tuple[sp.Symbol, ...]
    ratios: tuple[sp.Symbol, ...]
    K: sp.Matrix | None
    rubber: bool

    def weight(self, k: int) -> sp.Expr:
        """Weight of ball ``k`` in the support tensor (``lambda_k/r_k^2``, rubber:
        ``lambda_k (1/r_k^2 - 1)``).

        Parameters
        ----------
        k : int
            Index of the ball, ``0 .. N-1``.

        Returns
        -------
        sympy.Expr
            ``lambda_k / r_k^2``, or ``lambda_k (1/r_k^2 - 1)`` with rubber balls.

        References
        ----------
        BKM12-2.1M (the support tensor), BKM12-2.2 (rubber balls).
        """
        lam, r = self.lambdas[k], self.ratios[k]
        return lam * (1 / r**2 - 1) if self.rubber else lam / r**2


@dataclass(frozen=True)
class NBallDetails(ModelDetails):
    """Derived objects of :func:`n_ball_model` (``Model.details``).

    Attributes
    ----------
    derivation : SupportDerivation
    directions : list of sympy.Matrix
        Body-frame contact directions (symbolic, or in the frame ``alpha, beta, gamma``).
    space_directions : list of sympy.Matrix or None
        Their exact space components (None for symbolic directions).
    on_directions : dict
        The substitution of the symbolic ``n_k`` by ``directions``.
    support_tensor : sympy.Matrix, shape (3, 3)
        ``sum_k w_k n_k ⊗ n_k``.
    n_balls : int
    """

    derivation: SupportDerivation
    directions: list[sp.Matrix]
    space_directions: list[sp.Matrix] | None
    on_directions: dict
    support_tensor: sp.Matrix
    n_balls: int


@dataclass(frozen=True)
class ClosedSupportDetails(ModelDetails):
    """Derived objects of the closed support model (``Model.details``).

    Attributes
    ----------
    derivation : SupportDerivation
        The three virtual balls' derivation the model comes from.
    gyrostatic_momentum : sympy.Matrix, shape (3, 1)
    virtual_support : dict
        Substitution of the virtual balls' data (directions, weights, ratios, spins).
    momentum_rate_of_omega : sympy.Matrix, shape (3, 1)
        ``M'`` in ``omega`` and the frame as derived.
    derived_energy : sympy.Expr
        ``T`` on the admissible velocities (equal to ``(M, omega)/2``, BKM12-37).
    """

    derivation: SupportDerivation
    gyrostatic_momentum: sp.Matrix
    virtual_support: dict
    momentum_rate_of_omega: sp.Matrix
    derived_energy: sp.Expr


def _check_n(n_balls: int) -> int:
    if isinstance(n_balls, bool) or not isinstance(n_balls, int) or n_balls < 1:
        raise UserInputError(
            f"a spherical support needs at least one ball: got N = {n_balls!r} (give N >= 1)"
        )
    return n_balls


def support_description(
    n_balls: int, effects: frozenset[str] = frozenset()
) -> MechanicalDescription:
    """The body on ``n_balls`` balls that roll without slipping (no effect applied yet).

    ``T = (omega, I omega)/2 + sum_k lambda_k (omega_k, omega_k)/2`` and the no-slip
    constraints ``omega x n_k + r_k omega_k x n_k = 0`` (BKM12-27); the bodies are the
    balls ``(omega_k, n_k)``.

    Parameters
    ----------
    n_balls : int
    effects : frozenset of str
        Recorded in the description; not applied here.

    Returns
    -------
    MechanicalDescription
    """
    omega = vector("omega", real=True)
    Iv = vector("I", positive=True)
    lambdas = sp.symbols(f"lambda1:{n_balls + 1}", positive=True)
    ratios = sp.symbols(f"r1:{n_balls + 1}", positive=True)
    balls = [vector(f"omega_{k + 1}_", real=True) for k in range(n_balls)]
    dirs = [vector(f"n{k + 1}_", real=True) for k in range(n_balls)]
    desc = MechanicalDescription(
        system=NAME, effects=effects, time=T_SYMBOL, omega=omega, inertia=list(Iv)
    )
    desc.add_kinetic_energy(
        sum((lam * dot(w, w) / 2 for lam, w in zip(lambdas, balls, strict=True)), sp.S.Zero)
    )
    desc.bodies = list(zip(balls, dirs, strict=True))
    for k in range(n_balls):
        desc.add_kinematics(f"n{k + 1}", dirs[k], cross(dirs[k], omega))
        for c in cross(omega, dirs[k]) + ratios[k] * cross(balls[k], dirs[k]):
            desc.add_constraint(c)
    desc.add_parameter(ParameterSpec("I", tuple(Iv), "positive", "central principal moments"))
    desc.add_parameter(ParameterSpec("lambda", lambdas, "positive", "moments of the balls"))
    desc.add_parameter(ParameterSpec("r", ratios, "positive", "radius ratios r_k = R_k/R0"))
    return desc


@lru_cache(maxsize=16)
def _derive(n_balls: int, effects: frozenset[str]) -> SupportDerivation:
    desc = support_description(n_balls, effects)
    apply_effects(desc, effects, SUPPORTED_EFFECTS)
    omega = desc.omega
    balls = [w for w, _ in desc.bodies]
    dirs = [n for _, n in desc.bodies]
    spins = sp.symbols(f"nu1:{n_balls + 1}", real=True) if desc.free_spins else ()
    quasi = [(spins[k], dot(balls[k], dirs[k])) for k in range(len(spins))]
    ideal = ConstraintIdeal([dot(n, n) - 1 for n in dirs], [s for n in dirs for s in n])
    mb = MultiBodyDescription(
        omega=omega,
        bodies={f"ball{k + 1}": balls[k] for k in range(n_balls)},
        kinetic_energy=desc.total_kinetic_energy(),
        constraints=desc.constraints,
        kinematics=desc.kinematics,
        phase_space=ideal,
        time=T_SYMBOL,
        quasi_velocities=quasi,
    )
    return SupportDerivation(
        reduction=ferrers_multibody(mb),
        omega=omega,
        ball_velocities=balls,
        directions=dirs,
        spins=tuple(spins),
        I=sp.Matrix(desc.parameters["I"].symbols),
        lambdas=desc.parameters["lambda"].symbols,
        ratios=desc.parameters["r"].symbols,
        K=sp.Matrix(desc.parameters["K"].symbols) if "K" in desc.parameters else None,
        rubber=not desc.free_spins,
    )


def derive_support(n_balls: int, effects: Iterable[str] | str | None = ()) -> SupportDerivation:
    """Reduce the Ferrers equations of a body supported by ``n_balls`` balls.

    Parameters
    ----------
    n_balls : int
        ``N >= 1``.
    effects : iterable of str or str, optional
        ``"gyrostat"``, ``"rubber_balls"``.

    Returns
    -------
    SupportDerivation
        Directions are symbolic unit vectors (the proof is for every placement).

    Raises
    ------
    UserInputError
        ``N < 1`` or an unknown effect.

    Examples
    --------
    >>> d = derive_support(2)
    >>> d.reduction.quasi_momentum_rate.is_zero_matrix  # the spins are conserved
    True
    """
    return _derive(_check_n(n_balls), parse_effects(effects, SUPPORTED_EFFECTS))


def _random_unit_vectors(n: int, seed: int) -> list[sp.Matrix]:
    import random

    rng = random.Random(seed)
    group = PoissonGroup(UNIT_VECTOR, ("n",))
    return [sp.Matrix(group.sample_rational(rng)["n"]) for _ in range(n)]


def _adjugate_and_det(A: sp.Matrix) -> tuple[sp.Matrix, sp.Expr]:
    """Adjugate and determinant of a 3x3 matrix by cofactors, without simplification."""

    def cofactor(i: int, j: int) -> sp.Expr:
        (a, b), (c, d) = ([A[p, q] for q in range(3) if q != j] for p in range(3) if p != i)
        return (-1) ** (i + j) * (a * d - b * c)

    cof = sp.Matrix(3, 3, cofactor)
    return cof.T, sum((A[0, j] * cof[0, j] for j in range(3)), sp.S.Zero)


def n_ball_model(
    n_balls: int,
    effects: Iterable[str] | str | None = (),
    space_directions: Sequence[Sequence[sp.Expr]] | int | None = None,
) -> Model:
    """Model of the body on ``n_balls`` balls straight from the multi-body derivation.

    Parameters
    ----------
    n_balls : int
    effects : iterable of str or str, optional
    space_directions : sequence of 3-vectors, or int, optional
        ``None``: symbolic body-frame unit directions (state groups ``n1 .. nN``). Else
        exact space components of the contact directions (an ``int`` is a seed for
        random rational unit vectors); the state then carries the body components
        ``alpha, beta, gamma`` of the space axes (a frame) and
        ``n_k = c_k1 alpha + c_k2 beta + c_k3 gamma``.

    Returns
    -------
    Model
        State ``M`` (the reduced momentum) and the directions or the frame; ``omega`` is
        an auxiliary ``II^-1 M`` (cofactors, unsimplified); ``details`` (NBallDetails)
        carry the derivation, the body-frame directions, the support tensor and the
        substitution ``on_directions``.
    """
    der = derive_support(n_balls, effects)
    red = der.reduction
    M = vector("M", real=True)
    omega = der.omega
    if space_directions is None:
        geometry = tuple(PoissonGroup(UNIT_VECTOR, (f"n{k + 1}",)) for k in range(n_balls))
        groups = [(f"n{k + 1}", tuple(der.directions[k])) for k in range(n_balls)]
        body_dirs = list(der.directions)
        subs: dict = {}
        space = None
    else:
        if isinstance(space_directions, int):
            space = _random_unit_vectors(n_balls, space_directions)
        else:
            space = [_unit_exact(d, k) for k, d in enumerate(space_directions)]
        if len(space) != n_balls:
            raise UserInputError(f"{n_balls} balls need {n_balls} directions, got {len(space)}")
        frame = [vector(name, real=True) for name in ("alpha", "beta", "gamma")]
        geometry = (PoissonGroup(FRAME, ("alpha", "beta", "gamma")),)
        groups = [
            (name, tuple(v)) for name, v in zip(("alpha", "beta", "gamma"), frame, strict=True)
        ]
        body_dirs = [sum((c[i] * frame[i] for i in range(3)), sp.zeros(3, 1)) for c in space]
        subs = {
            s: e
            for n, b in zip(der.directions, body_dirs, strict=True)
            for s, e in zip(n, b, strict=True)
        }
    II = red.inertia_operator.xreplace(subs)
    adj, det = _adjugate_and_det(II)  # unexpanded: omega is only evaluated, never simplified
    detII = sp.Symbol("det_II", real=True)
    P0 = red.gyrostatic_momentum
    omega_val = adj * (M - P0) / detII
    aux = [(detII, det)] + [(omega[i], omega_val[i]) for i in range(3)]
    rate = red.momentum_rate.xreplace(subs)
    rhs = list(rate)
    for _, vec in groups:
        rhs += list(cross(sp.Matrix(vec), omega))
    vectors = {name: sp.Matrix(v) for name, v in groups}
    constraints = [c for g in geometry for c in g.constraints(vectors)]
    specs = [
        ParameterSpec("I", tuple(der.I), "positive", "central principal moments of the body"),
        ParameterSpec("lambda", der.lambdas, "positive", "moments of inertia of the balls"),
        ParameterSpec("r", der.ratios, "positive", "radius ratios r_k = R_k/R0"),
    ]
    if der.K is not None:
        specs.append(ParameterSpec("K", tuple(der.K), "real", "gyrostatic momentum"))
    tensor = sum(
        (der.weight(k) * body_dirs[k] * body_dirs[k].T for k in range(n_balls)), sp.zeros(3, 3)
    )
    effects_set = parse_effects(effects, SUPPORTED_EFFECTS)
    return Model(
        system="spherical_support_n_balls",
        effects=effects_set,
        time=T_SYMBOL,
        state_groups=(("M", tuple(M)), *groups),
        parameters=tuple(specs),
        aux=tuple(aux),
        rhs=tuple(rhs),
        constraints=tuple(constraints),
        geometry=geometry,
        integrals=(),
        density=None,
        omega=omega,
        details=NBallDetails(
            derivation=der,
            directions=body_dirs,
            space_directions=space,
            on_directions=subs,
            support_tensor=tensor,
            n_balls=n_balls,
        ),
        references={"equations": "BKM12-31", "momentum": "BKM12-2.1M"},
    )


# ============================================================== closed model
def _sample_physical_support(D_iso, D_al, D_be, rng, point) -> None:
    al0, be0, ga0 = (sp.Rational(rng.randint(1, 40), rng.randint(1, 12)) for _ in range(3))
    point[D_iso], point[D_al], point[D_be] = al0 + be0, al0 - ga0, be0 - ga0


def _physical_support_sampler(D_iso: sp.Symbol, D_al: sp.Symbol, D_be: sp.Symbol):
    """Exact sampler of physical support parameters (for the verifier's witnesses).

    The support tensor's eigenvalues ``D_al0, D_be0, D_ga0`` are non-negative, so
    ``D_iso = D_al0 + D_be0``, ``D_al = D_al0 - D_ga0``, ``D_be = D_be0 - D_ga0``: the
    eigenvalues are drawn as positive rationals and the parameters set from them. The
    sampler is picklable (models are cached on disk).
    """
    return functools.partial(_sample_physical_support, D_iso, D_al, D_be)


def _virtual_weights(rubber: bool):
    """Ball data along ``alpha, beta, gamma`` that realise ``D_iso, D_al, D_be``."""
    D_iso, D_al, D_be = sp.symbols("D_iso D_al D_be", real=True)
    lam = sp.symbols("_la _lb _lg")
    r = sp.Rational(1, 2) if rubber else sp.S.One  # any r != 1 works for rubber balls
    w = [x * (1 / r**2 - 1) if rubber else x / r**2 for x in lam]
    iso = sum(x / r**2 for x in lam)
    (sol,) = sp.linsolve([iso - w[2] - D_iso, w[0] - w[2] - D_al, w[1] - w[2] - D_be], lam)
    return (D_iso, D_al, D_be), list(sol), r


def build_spherical_support(effects: Iterable[str] | str | None = ()) -> Model:
    """The closed model of a body in a spherical support (BKM12-32..34, 2.2, 2.3).

    Parameters
    ----------
    effects : iterable of str or str, optional
        ``"gyrostat"`` (constant gyrostatic momentum ``K``), ``"rubber_balls"`` (no-twist
        balls: the same equations, the parameters come from the modified tensor).

    Returns
    -------
    Model
        State ``M, alpha, beta, gamma`` (a frame, ``gamma = alpha x beta``), parameters
        ``I1, I2, I3, D_iso, D_al, D_be`` (+ ``K1, K2, K3``), aux ``Z_al, Z_be, omega``.

    Examples
    --------
    >>> model = build_spherical_support()
    >>> model.param_names
    ('I1', 'I2', 'I3', 'D_iso', 'D_al', 'D_be')
    """
    effects = parse_effects(effects, SUPPORTED_EFFECTS)
    der = _derive(3, effects)  # the effects applied themselves to the balls' description
    rubber, gyro = der.rubber, der.K is not None
    red = der.reduction
    M = vector("M", real=True)
    alpha, beta, gamma = (vector(n, real=True) for n in ("alpha", "beta", "gamma"))
    frame = (alpha, beta, gamma)
    (D_iso, D_al, D_be), lam, r = _virtual_weights(rubber)
    subs = {
        s: e for n, b in zip(der.directions, frame, strict=True) for s, e in zip(n, b, strict=True)
    }
    subs.update(dict(zip(der.lambdas, lam, strict=True)))
    subs.update({ri: r for ri in der.ratios})
    subs.update({nu: 0 for nu in der.spins})  # the virtual balls' spins (constant) are zero
    omega = der.omega
    geometry = (PoissonGroup(FRAME, ("alpha", "beta", "gamma")),)
    vectors = {"alpha": alpha, "beta": beta, "gamma": gamma}
    constraints = geometry[0].constraints(vectors)
    frame_ideal = ConstraintIdeal(constraints, [s for v in frame for s in v])
    ab_ideal = ConstraintIdeal(
        [dot(alpha, alpha) - 1, dot(beta, beta) - 1, dot(alpha, beta)], [*alpha, *beta]
    )
    gamma_ab = dict(zip(gamma, cross(alpha, beta), strict=True))
    II = red.inertia_operator.xreplace(subs).applyfunc(sp.expand)
    P0 = red.gyrostatic_momentum.xreplace(subs)
    rate = red.momentum_rate.xreplace(subs).applyfunc(sp.expand)
    energy = sp.expand(red.energy.xreplace(subs))
    # the rank-2 structure J - D_al alpha⊗alpha - D_be beta⊗beta (gamma⊗gamma eliminated)
    kin = {"alpha": (alpha, cross(alpha, omega)), "beta": (beta, cross(beta, omega))}
    proxy = ReducedEquations(
        with_multipliers=sp.zeros(3, 1),
        multipliers=(),
        velocity_map={},
        admissible=sp.eye(3),
        momentum=II * omega + P0,
        inertia_operator=II.xreplace(gamma_ab).applyfunc(sp.expand),
        gyrostatic_momentum=P0,
        momentum_rate=rate,
        energy=energy,
        omega=omega,
        kinematics=kin,
        time=T_SYMBOL,
    )
    structured = proxy.structured_inverse(ab_ideal)
    if structured is None or structured.U.shape[1] != 2:  # pragma: no cover
        raise DerivationError("no rank-2 structure J + U C U^T of the support's inertia operator")
    rhs_M, remainder = proxy.euler_poincare_form(M)
    if any(frame_ideal.reduce(sp.expand(e)) != 0 for e in remainder):  # pragma: no cover
        raise DerivationError("the momentum rate is not (M + K) x omega")
    rhs_M = cross(M + P0, omega)
    A, U = structured.A, structured.U
    X = structured.X()
    Z = sp.Matrix(sp.symbols("Z_al Z_be", real=True))
    Y = U.T * A * M
    det_X = X[0, 0] * X[1, 1] - X[0, 1] * X[1, 0]
    Z_val = sp.Matrix([X[1, 1] * Y[0] - X[0, 1] * Y[1], X[0, 0] * Y[1] - X[1, 0] * Y[0]]) / det_X
    omega_val = A * (M + U * Z)
    aux = [(Z[i], Z_val[i]) for i in range(2)] + [(omega[i], omega_val[i]) for i in range(3)]
    density = det_X ** sp.Rational(-1, 2)
    rhs = list(rhs_M) + [e for v in frame for e in cross(v, omega)]
    Iv = der.I
    specs = [
        ParameterSpec(
            "I", tuple(Iv), "positive", "central principal moments of inertia I1, I2, I3"
        ),
        ParameterSpec(
            "D_iso",
            (D_iso,),
            "real",
            "isotropic part of the support, J = I + D_iso Id: sum_k lambda_k/r_k^2 - D_ga0 (>= 0)",
        ),
        ParameterSpec(
            "D_al",
            (D_al,),
            "real",
            "D_al0 - D_ga0 (eigenvalues of the support tensor along alpha and gamma; non-zero)",
        ),
        ParameterSpec(
            "D_be",
            (D_be,),
            "real",
            "D_be0 - D_ga0 (eigenvalues of the support tensor along beta and gamma; non-zero)",
        ),
    ]
    if gyro:
        specs.append(ParameterSpec("K", tuple(der.K), "real", "constant gyrostatic momentum K"))
    P = M + P0
    P_name = "M+K" if gyro else "M"
    integrals = [
        # (M, omega)/2 on the phase space; the derived energy (T on the admissible
        # velocities, in details.derived_energy) is proved equal to it (BKM12-37)
        # but its Lie derivative is far larger to reduce
        ("H", dot(M, omega) / 2),
        (f"({P_name},alpha)", sp.expand(dot(P, alpha))),
        (f"({P_name},beta)", sp.expand(dot(P, beta))),
        (f"({P_name},gamma)", sp.expand(dot(P, gamma))),
        (f"({P_name},{P_name})", sp.expand(dot(P, P))),
        ("(alpha,alpha)", dot(alpha, alpha)),
        ("(beta,beta)", dot(beta, beta)),
        ("(alpha,beta)", dot(alpha, beta)),
        ("(gamma,alpha)", dot(gamma, alpha)),
        ("(gamma,beta)", dot(gamma, beta)),
        ("(gamma,gamma)", dot(gamma, gamma)),
    ]
    A_syms = sp.symbols("A1:4", positive=True)
    model = Model(
        system=NAME,
        effects=effects,
        time=T_SYMBOL,
        state_groups=(
            ("M", tuple(M)),
            ("alpha", tuple(alpha)),
            ("beta", tuple(beta)),
            ("gamma", tuple(gamma)),
        ),
        parameters=tuple(specs),
        aux=tuple(aux),
        rhs=tuple(rhs),
        constraints=tuple(constraints),
        geometry=geometry,
        integrals=tuple(integrals),
        density=density,
        omega=omega,
        momentum_of_omega=II * omega,
        inertia_operator=II,
        structured_inverse=structured,
        euler_poincare_remainder=remainder,
        sampler=_physical_support_sampler(D_iso, D_al, D_be),
        reparametrisation=Reparametrisation(
            forward={A_syms[i]: 1 / structured.J[i, i] for i in range(3)},
            inverse={Iv[i]: 1 / A_syms[i] - D_iso for i in range(3)},
        ),
        details=ClosedSupportDetails(
            derivation=der,
            gyrostatic_momentum=P0,
            virtual_support=subs,
            momentum_rate_of_omega=rate,
            derived_energy=energy,
        ),
        references={
            "equations": "BKM12-2.3" if gyro else "BKM12-32",
            "momentum": "BKM12-33",
            "omega": "BKM12-34",
            "integrals": "BKM12-2.3" if gyro else "BKM12-35,36,37,Rem2",
            "density": "BKM12-38",
            "rubber_balls": "BKM12-2.2",
        },
    )
    return model


BUILDER = build_spherical_support


# ============================================================== physical support -> model
@dataclass(frozen=True)
class SupportParameters:
    """The closed model's parameters of a concrete support, and its eigenframe.

    Attributes
    ----------
    D_iso, D_al, D_be : sympy.Expr
        Parameters of :func:`build_spherical_support` (exact, or ``sympy.Float``).
    eigenvalues : tuple of sympy.Expr
        ``(D_al0, D_be0, D_ga0)``.
    frame : sympy.Matrix, shape (3, 3)
        Rows: space components of ``alpha, beta, gamma`` (right-handed, orthonormal).
    tensor : sympy.Matrix
        ``D_sup`` in space components.
    exact : bool
        False when the eigen-data are floating point (``dps`` digits).
    directions : tuple of sympy.Matrix
        The unit contact directions in space components.
    """

    D_iso: sp.Expr
    D_al: sp.Expr
    D_be: sp.Expr
    eigenvalues: tuple[sp.Expr, sp.Expr, sp.Expr]
    frame: sp.Matrix
    tensor: sp.Matrix
    exact: bool
    directions: tuple[sp.Matrix, ...]

    def params(self, inertia: Sequence[sp.Expr] | None = None) -> dict[str, object]:
        """``{"D_iso": ..., "D_al": ..., "D_be": ...}`` (+ ``"I"`` when given).

        Parameters
        ----------
        inertia : sequence of sympy.Expr, optional
            Principal moments ``I1, I2, I3`` of the body; None leaves ``"I"`` out.

        Returns
        -------
        dict of str to object
            Parameter values for the closed model: the three support parameters as
            ``sympy.Expr`` and, when given, ``"I"`` as a tuple of three values.
        """
        out: dict[str, object] = {"D_iso": self.D_iso, "D_al": self.D_al, "D_be": self.D_be}
        if inertia is not None:
            out["I"] = tuple(inertia)
        return out

    def eigen_coordinates(self, k: int) -> sp.Matrix:
        """Components of direction ``k`` along ``alpha, beta, gamma``.

        Parameters
        ----------
        k : int
            Index of the contact direction, ``0 .. N-1``.

        Returns
        -------
        sympy.Matrix, shape (3, 1)
            ``frame * n_k``: the direction in the eigenframe of the support tensor.
        """
        return self.frame * self.directions[k]


def _positive_number(value, what: str) -> sp.Expr:
    try:
        v = sp.nsimplify(value) if isinstance(value, float) else sp.sympify(value)
    except (sp.SympifyError, TypeError) as exc:
        raise UserInputError(f"{what} must be a number, got {value!r}") from exc
    if not v.is_number or not v.is_real or not v.is_finite:
        raise UserInputError(f"{what} must be a finite real number, got {value!r}")
    if not v.is_positive:
        raise UserInputError(f"{what} must be positive, got {value!r}")
    return v


def _unit_exact(d, k: int) -> sp.Matrix:
    try:
        vec = sp.Matrix([sp.nsimplify(c) if isinstance(c, float) else sp.sympify(c) for c in d])
    except (sp.SympifyError, TypeError) as exc:
        raise UserInputError(f"direction n_{k + 1} must be three numbers, got {d!r}") from exc
    if vec.shape != (3, 1) or not all(c.is_number and c.is_real for c in vec):
        raise UserInputError(f"direction n_{k + 1} must be three real numbers, got {d!r}")
    norm2 = sp.nsimplify(dot(vec, vec))
    if norm2 == 0:
        raise UserInputError(f"direction n_{k + 1} is the zero vector: give the contact direction")
    return vec if norm2 == 1 else vec / sp.sqrt(norm2)


def support_parameters(
    lambdas: Sequence[object],
    ratios: Sequence[object],
    directions: Sequence[Sequence[object]],
    effects: Iterable[str] | str | None = (),
    dps: int = 60,
) -> SupportParameters:
    """From physical ball data to the closed model's parameters and eigenframe.

    Parameters
    ----------
    lambdas : sequence of numbers
        Moments of inertia ``lambda_k > 0`` of the balls.
    ratios : sequence of numbers
        ``r_k = R_k/R0 > 0``.
    directions : sequence of 3-vectors
        Space components of the contact directions (normalised here; not zero).
    effects : iterable of str or str, optional
        ``"rubber_balls"`` uses the tensor ``sum lambda_k (1/r_k^2 - 1) n_k ⊗ n_k``.
    dps : int, optional
        Digits of the eigen-decomposition when the eigenvalues are not rational.

    Returns
    -------
    SupportParameters
        Exact (sympy) when the support tensor has rational eigenvalues, else floats with
        ``dps`` digits. Convention: ``gamma`` belongs to the simple eigenvalue when one is
        double, else to the smallest one (then ``D_al, D_be > 0``).

    Raises
    ------
    UserInputError
        No balls, lists of different lengths, a non-positive ``lambda_k`` or ``r_k``, a
        zero direction, or an isotropic support tensor (``D_al = D_be = 0``: no closed
        rank-2 model; the body moves as a free rigid body with inertia ``J``).

    Examples
    --------
    >>> p = support_parameters([1], [1], [(0, 0, 1)])
    >>> (p.D_iso, p.D_al, p.D_be)
    (0, -1, -1)
    """
    effects = parse_effects(effects, SUPPORTED_EFFECTS)
    n = len(directions)
    if n == 0:
        raise UserInputError("a spherical support needs at least one ball (N = 0 given)")
    if len(lambdas) != n or len(ratios) != n:
        raise UserInputError(
            f"give one lambda_k and one r_k per ball: {len(lambdas)} lambdas, "
            f"{len(ratios)} ratios, {n} directions"
        )
    lam = [
        _positive_number(v, f"lambda_{k + 1} (moment of inertia of ball {k + 1})")
        for k, v in enumerate(lambdas)
    ]
    rat = [
        _positive_number(v, f"r_{k + 1} (radius ratio R_{k + 1}/R0)") for k, v in enumerate(ratios)
    ]
    dirs = [_unit_exact(d, k) for k, d in enumerate(directions)]
    rubber = "rubber_balls" in effects
    w = [la * (1 / r**2 - 1) if rubber else la / r**2 for la, r in zip(lam, rat, strict=True)]
    S = sum((wk * d * d.T for wk, d in zip(w, dirs, strict=True)), sp.zeros(3, 3)).applyfunc(
        sp.nsimplify
    )
    iso = sum((la / r**2 for la, r in zip(lam, rat, strict=True)), sp.S.Zero)
    x = sp.Symbol("x")
    charpoly = sp.Poly(S.charpoly(x).as_expr(), x)
    exact = all(S[i, j].is_Rational for i in range(3) for j in range(3)) and all(
        sp.degree(f, x) == 1 for f, _ in sp.factor_list(charpoly.as_expr())[1]
    )
    if exact:
        pairs = []
        for val, mult, vecs in S.eigenvects():
            basis = sp.GramSchmidt([sp.Matrix(v) for v in vecs], orthonormal=True)
            pairs += [(val, b) for b in basis]
            del mult
        vals = [p[0] for p in pairs]
        vecs = [p[1] for p in pairs]
    else:
        with mpmath.workdps(dps):
            E, Q = mpmath.eigsy(
                mpmath.matrix(
                    [
                        [
                            mpmath.mpf(sp.Rational(S[i, j]).p) / sp.Rational(S[i, j]).q
                            if S[i, j].is_Rational
                            else mpmath.mpf(str(sp.N(S[i, j], dps + 10)))
                            for j in range(3)
                        ]
                        for i in range(3)
                    ]
                )
            )
            vals = [sp.Float(str(E[i]), dps) for i in range(3)]
            vecs = [sp.Matrix([sp.Float(str(Q[j, i]), dps) for j in range(3)]) for i in range(3)]
    tol = sp.Float(10) ** (-(dps // 2))

    def same(a, b) -> bool:
        return a == b if exact else abs(a - b) <= tol * (1 + abs(a) + abs(b))

    order = sorted(range(3), key=lambda i: vals[i])
    if same(vals[order[0]], vals[order[2]]):
        raise UserInputError(
            "the support tensor is isotropic (D_sup = d Id): D_al = D_be = 0, the body moves as a "
            "free rigid body with J = I + (sum lambda_k/r_k^2 - d) Id; the closed rank-2 model "
            "does not apply"
        )
    if same(vals[order[0]], vals[order[1]]):
        g = order[2]  # double smallest: gamma takes the simple (largest) one
    else:
        g = order[0]  # distinct or double largest: gamma takes the smallest (simple) one
    a, b = [i for i in order if i != g][:2]
    ea, eb = vecs[a], vecs[b]
    eg = cross(ea, eb)  # right-handed
    frame = sp.Matrix.vstack(ea.T, eb.T, eg.T)
    D_al0, D_be0, D_ga0 = vals[a], vals[b], vals[g]
    return SupportParameters(
        D_iso=sp.nsimplify(iso - D_ga0) if exact else iso - D_ga0,
        D_al=D_al0 - D_ga0,
        D_be=D_be0 - D_ga0,
        eigenvalues=(D_al0, D_be0, D_ga0),
        frame=frame.applyfunc(sp.radsimp) if exact else frame,
        tensor=S,
        exact=exact,
        directions=tuple(dirs),
    )
