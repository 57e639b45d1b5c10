"""The body on ``N`` balls of a spherical support: its description and multi-body reduction.

A body (central principal moments ``I1, I2, I3``) is rigidly enclosed in a spherical
shell; ``N`` dynamically symmetric balls (moments of inertia ``lambda_k``, radius ratios
``r_k = R_k/R0``) with fixed centres touch the shell at the space-fixed unit directions
``n_k`` (body components ``n_k' = n_k x omega``).

Mechanical description (BKM12-27, 28, 39; nothing of the result is typed in):

* ``T = (omega, I omega)/2 + sum_k lambda_k (omega_k, omega_k)/2`` (+ ``(K, omega)`` with
  the ``gyrostat`` effect, BKM12 §2.3), the balls' angular velocities ``omega_k`` in the
  body frame;
* no slip at the contacts, ``omega x n_k + r_k omega_k x n_k = 0`` (BKM12-27); with
  ``rubber_balls`` also no twist, ``(omega - omega_k, n_k) = 0`` (BKM12-39);
* where the constraints leave a ball's spin ``nu_k = (omega_k, n_k)`` free (no twist
  constraint fixes it), the spin is an extra quasi-velocity of the reduction.

:func:`support_derivation` reduces the Ferrers equations of such a description with
symbolic unit directions (:mod:`.multibody`, multipliers eliminated by projection); the
stages of :mod:`.spherical_support` make models of it.

References
----------
BKM12-27..31, BKM12-39..42, BKM12-2.1M, BKM12-2.2 (FORMULAS.md §1.6, §1.7).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from .algebra import ConstraintIdeal
from .description import MechanicalDescription, apply_effects
from .effects import parse_effects
from .errors import UserInputError
from .model import ParameterSpec
from .multibody import MultiBodyDescription, MultiBodyReduction, ferrers_multibody
from .vectors import cross, dot, vector

__all__ = [
    "SUPPORTED_EFFECTS",
    "SupportDerivation",
    "support_description",
    "support_derivation",
    "derive_support",
    "ball_weight",
    "spins_are_free",
]

#: The effects a support takes, in the order they are applied (derive/effects.py).
SUPPORTED_EFFECTS = ("gyrostat", "rubber_balls")

T_SYMBOL = sp.Symbol("t", real=True)


def ball_weight(moment: sp.Expr, ratio: sp.Expr, spin_free: bool) -> sp.Expr:
    """Weight of a ball in the support tensor ``D_sup = sum_k w_k n_k ⊗ n_k``.

    Parameters
    ----------
    moment, ratio : sympy.Expr
        ``lambda_k`` and ``r_k``.
    spin_free : bool
        Whether the constraints leave the ball's spin free (:func:`spins_are_free`).

    Returns
    -------
    sympy.Expr
        ``lambda_k/r_k^2``, or ``lambda_k (1/r_k^2 - 1)`` when the spin is fixed (rubber
        balls).

    References
    ----------
    BKM12-2.1M (the support tensor), BKM12-2.2 (rubber balls).
    """
    return moment / ratio**2 if spin_free else moment * (1 / ratio**2 - 1)


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
    I, lambdas, ratios :
        Parameter symbols.
    K : sympy.Matrix or None
        The gyrostatic momentum the reduction finds (None when zero).
    rubber : bool
        No ball's spin is free (rubber balls).
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
        """Weight of ball ``k`` in the support tensor (:func:`ball_weight`).

        Parameters
        ----------
        k : int
            Index of the ball, ``0 .. N-1``.

        Returns
        -------
        sympy.Expr
            ``lambda_k / r_k^2``, or ``lambda_k (1/r_k^2 - 1)`` with rubber balls.
        """
        return ball_weight(self.lambdas[k], self.ratios[k], not self.rubber)


def check_n_balls(n_balls: int) -> int:
    """``n_balls`` when it is an integer ``>= 1``.

    Parameters
    ----------
    n_balls : int

    Returns
    -------
    int

    Raises
    ------
    UserInputError
        Otherwise.
    """
    if isinstance(n_balls, bool) or not isinstance(n_balls, int) or n_balls < 1:
        raise UserInputError(
            f"a spherical support needs at least one ball: got N = {n_balls!r} (give N >= 1)"
        )
    return n_balls


def add_balls(
    desc: MechanicalDescription,
    n_balls: int,
    moments: Sequence[sp.Expr] | None = None,
    ratios: Sequence[sp.Expr] | None = None,
) -> None:
    """Add ``n_balls`` balls rolling without slipping on the body (BKM12-27).

    Their kinetic energy ``sum_k lambda_k (omega_k, omega_k)/2``, the no-slip constraints
    ``omega x n_k + r_k omega_k x n_k = 0``, the directions' kinematics ``n_k`` and the
    bodies ``(omega_k, n_k, lambda_k, r_k)``; no parameter is declared.

    Parameters
    ----------
    desc : MechanicalDescription
        Modified in place.
    n_balls : int
    moments, ratios : sequence of sympy.Expr, optional
        The balls' ``lambda_k`` and ``r_k`` (a description's numbers or names); by default
        the symbols ``lambda1 .. lambdaN``, ``r1 .. rN``.
    """
    omega = desc.omega
    if moments is None:
        moments = sp.symbols(f"lambda1:{n_balls + 1}", positive=True)
    if ratios is None:
        ratios = sp.symbols(f"r1:{n_balls + 1}", positive=True)
    balls = [vector(f"omega_{k + 1}_", real=True) for k in range(n_balls)]
    dirs = [vector(f"n{k + 1}_", real=True) for k in range(n_balls)]
    desc.add_kinetic_energy(
        sum((lam * dot(w, w) / 2 for lam, w in zip(moments, balls, strict=True)), sp.S.Zero)
    )
    desc.bodies = list(zip(balls, dirs, moments, ratios, strict=True))
    for k in range(n_balls):
        desc.add_kinematics(f"n{k + 1}", dirs[k], cross(dirs[k], omega))
        for c in cross(omega, dirs[k]) + ratios[k] * cross(balls[k], dirs[k]):
            desc.add_constraint(c)


def support_body(
    system: str,
    effects: frozenset[str],
    inertia: sp.Matrix | None = None,
    moments: tuple[sp.Symbol, ...] = (),
) -> MechanicalDescription:
    """The body of a support: ``T = (omega, I omega)/2`` and its references.

    Parameters
    ----------
    system : str
    effects : frozenset of str
        Recorded in the description; not applied here.
    inertia : sympy.Matrix, optional
        The body's central inertia tensor (a description's); by default ``diag(I1, I2,
        I3)``, declared as the parameter ``I``.
    moments : tuple of sympy.Symbol, optional
        With ``inertia``: the symbols its principal moments are written in (none when
        they are not three symbols).

    Returns
    -------
    MechanicalDescription
        No balls, stage or state yet.
    """
    omega = vector("omega", real=True)
    Iv = vector("I", positive=True)
    desc = MechanicalDescription(
        system=system,
        effects=effects,
        time=T_SYMBOL,
        omega=omega,
        inertia=sp.diag(*Iv) if inertia is None else inertia,
        moments=tuple(Iv) if inertia is None else moments,
    )
    if inertia is None:
        desc.add_parameter(
            ParameterSpec(
                "I", tuple(Iv), "positive", "central principal moments of inertia I1, I2, I3"
            )
        )
    # the gyrostat in a support: BKM12 §2.3 (instead of the ball's K01 §4)
    desc.effect_references["gyrostat"] = {"equations": "BKM12-2.3", "integrals": "BKM12-2.3"}
    return desc


def support_description(
    n_balls: int, effects: frozenset[str] = frozenset(), system: str = "spherical_support"
) -> MechanicalDescription:
    """The body on ``n_balls`` balls that roll without slipping (no effect applied yet).

    ``T = (omega, I omega)/2 + sum_k lambda_k (omega_k, omega_k)/2`` and the no-slip
    constraints ``omega x n_k + r_k omega_k x n_k = 0`` (BKM12-27); the bodies are the
    balls ``(omega_k, n_k, lambda_k, r_k)``; parameters ``I, lambda, r``.

    Parameters
    ----------
    n_balls : int
    effects : frozenset of str
        Recorded in the description; not applied here.
    system : str

    Returns
    -------
    MechanicalDescription
        Without a state or a reduction stage (see :mod:`.spherical_support`).
    """
    desc = support_body(system, effects)
    add_balls(desc, n_balls)
    lambdas = tuple(lam for _, _, lam, _ in desc.bodies)
    ratios = tuple(r for _, _, _, r in desc.bodies)
    desc.add_parameter(
        ParameterSpec("lambda", lambdas, "positive", "moments of inertia of the balls")
    )
    desc.add_parameter(ParameterSpec("r", ratios, "positive", "radius ratios r_k = R_k/R0"))
    return desc


def spins_are_free(desc: MechanicalDescription) -> list[bool]:
    """For each ball: do the constraints leave its spin about the contact direction free?

    Parameters
    ----------
    desc : MechanicalDescription
        With ``bodies``.

    Returns
    -------
    list of bool
        True where the constraints on the ball's angular velocity do not determine it
        (no slip alone leaves ``(omega_k, n_k)`` free; no twist fixes it).
    """
    out = []
    for w, _, _, _ in desc.bodies:
        rows = [c for c in desc.constraints if set(w) & sp.sympify(c).free_symbols]
        solutions = sp.linsolve(rows, list(w))
        values = next(iter(solutions), ())
        out.append(bool(set().union(*(sp.sympify(v).free_symbols for v in values)) & set(w)))
    return out


@lru_cache(maxsize=32)
def _ferrers(
    omega: sp.ImmutableMatrix,
    bodies: tuple[tuple[str, sp.ImmutableMatrix], ...],
    kinetic_energy: sp.Expr,
    constraints: tuple[sp.Expr, ...],
    kinematics: tuple[tuple[str, sp.ImmutableMatrix, sp.ImmutableMatrix], ...],
    directions: tuple[sp.ImmutableMatrix, ...],
    quasi: tuple[tuple[sp.Symbol, sp.Expr], ...],
) -> MultiBodyReduction:
    """The multi-body reduction, cached by its inputs (the N-ball models and the closed
    model of the same balls share it)."""
    dirs = [sp.Matrix(n) for n in directions]
    unit = ConstraintIdeal([dot(n, n) - 1 for n in dirs], [s for n in dirs for s in n])
    return ferrers_multibody(
        MultiBodyDescription(
            omega=sp.Matrix(omega),
            bodies={name: sp.Matrix(w) for name, w in bodies},
            kinetic_energy=kinetic_energy,
            constraints=list(constraints),
            kinematics={name: (sp.Matrix(X), sp.Matrix(Xd)) for name, X, Xd in kinematics},
            phase_space=unit,
            time=T_SYMBOL,
            quasi_velocities=list(quasi),
        )
    )


def support_derivation(desc: MechanicalDescription) -> SupportDerivation:
    """Reduce the Ferrers equations of a body on balls (multipliers eliminated).

    Parameters
    ----------
    desc : MechanicalDescription
        A support (:func:`support_description`) with its effects applied; the balls'
        directions are symbolic unit vectors.

    Returns
    -------
    SupportDerivation
    """
    balls = [w for w, _, _, _ in desc.bodies]
    dirs = [n for _, n, _, _ in desc.bodies]
    free = spins_are_free(desc)
    spins = tuple(sp.Symbol(f"nu{k + 1}", real=True) for k in range(len(balls)) if free[k])
    quasi = tuple(
        (nu, dot(balls[k], dirs[k]))
        for nu, k in zip(spins, [k for k in range(len(balls)) if free[k]], strict=True)
    )
    kinematics = tuple(
        (name, sp.ImmutableMatrix(X), sp.ImmutableMatrix(Xd))
        for name, (X, Xd) in desc.kinematics.items()
        if any(X == n for n in dirs)
    )
    reduction = _ferrers(
        sp.ImmutableMatrix(desc.omega),
        tuple((f"ball{k + 1}", sp.ImmutableMatrix(w)) for k, w in enumerate(balls)),
        desc.total_kinetic_energy(),
        tuple(desc.constraints),
        kinematics,
        tuple(sp.ImmutableMatrix(n) for n in dirs),
        quasi,
    )
    P0 = reduction.gyrostatic_momentum
    return SupportDerivation(
        reduction=reduction,
        omega=desc.omega,
        ball_velocities=balls,
        directions=dirs,
        spins=spins,
        I=sp.Matrix(desc.moments),
        lambdas=tuple(lam for _, _, lam, _ in desc.bodies),
        ratios=tuple(r for _, _, _, r in desc.bodies),
        K=None if P0.is_zero_matrix else P0,
        rubber=not any(free),
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
    chosen = parse_effects(effects, SUPPORTED_EFFECTS)
    desc = support_description(check_n_balls(n_balls), chosen)
    apply_effects(desc, chosen, SUPPORTED_EFFECTS)
    return support_derivation(desc)
