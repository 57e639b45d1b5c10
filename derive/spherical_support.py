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
* where the constraints leave a ball's spin ``nu_k = (omega_k, n_k)`` free (without
  ``rubber_balls``), the spin is an extra quasi-velocity of the reduction.

:func:`derive_support` reduces the Ferrers equations of ``N`` balls with symbolic unit
directions (:mod:`.support_derivation`: the multi-body reduction, multipliers eliminated
by projection). Two reduction stages of the shared finishing step
(:func:`~.description.form_model`) make models of it: :class:`NBallReduction`
(:func:`n_ball_model`), optionally for concrete space-fixed directions written in a
body-fixed view of the space axes (a frame ``alpha, beta, gamma``), and
:class:`ClosedSupportReduction`, the registered closed model.

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
:func:`~.support_parameters.support_parameters` computes ``D_iso, D_al, D_be`` and the
eigenframe from physical ball data.

References
----------
BKM12-27..38, BKM12-Rem2, BKM12-39..42, BKM12-2.2, BKM12-2.3 (FORMULAS.md §1.6, §1.7).
"""

from __future__ import annotations

import functools
import random
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import sympy as sp

from .algebra import ConstraintIdeal
from .body_on_sphere import _adjugate_and_det
from .description import MechanicalDescription, Reduced, apply_effects, form_model
from .effects import parse_effects
from .engine import ReducedEquations, StructuredInverse
from .errors import DerivationError, UserInputError
from .geometry import FRAME, UNIT_VECTOR, PoissonGroup
from .model import Model, ModelDetails, ParameterSpec
from .model_store import kept_model
from .rigid_body import moment_reparametrisation
from .support_derivation import (
    SUPPORTED_EFFECTS,
    T_SYMBOL,
    SupportDerivation,
    add_balls,
    ball_weight,
    check_n_balls,
    derive_support,
    support_body,
    support_derivation,
    support_description,
)
from .support_parameters import SupportParameters, support_parameters, unit_exact
from .vectors import cross, dot, vector

__all__ = [
    "NAME",
    "DESCRIPTION",
    "SUPPORTED_EFFECTS",
    "GENERATED_VARIANTS",
    "PARAMETER_ORDER",
    "BUILDER",
    "SupportDerivation",
    "NBallDetails",
    "ClosedSupportDetails",
    "NBallReduction",
    "ClosedSupportReduction",
    "support_description",
    "n_ball_description",
    "closed_support_description",
    "SupportParameters",
    "derive_support",
    "n_ball_model",
    "on_space_frame",
    "support_parameters",
    "build_spherical_support",
]

NAME = "spherical_support"
DESCRIPTION = (
    "rigid body in a spherical support of N balls (Fedorov's problem), closed system in the "
    "eigenframe of the support tensor (BKM12 §2.1-2.3)"
)
#: Effect combinations whose code is committed in generated/ (``rubber_balls`` gives the same
#: closed equations as the plain support: only the meaning of the D parameters changes).
GENERATED_VARIANTS: tuple[tuple[str, ...], ...] = ((), ("gyrostat",))
#: Order of the parameter groups of the closed model (and the generated code).
PARAMETER_ORDER = ("I", "D_iso", "D_al", "D_be", "K")
#: ... and of the N-ball models.
N_BALL_PARAMETER_ORDER = ("I", "lambda", "r", "K")
#: The eigenframe of the support tensor: the closed model's space-fixed vectors.
FRAME_NAMES = ("alpha", "beta", "gamma")


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


# ============================================================== N balls
def _random_unit_vectors(n: int, seed: int) -> list[sp.Matrix]:
    rng = random.Random(seed)
    group = PoissonGroup(UNIT_VECTOR, ("n",))
    return [sp.Matrix(group.sample_rational(rng)["n"]) for _ in range(n)]


@dataclass(frozen=True)
class NBallReduction:
    """The multi-body reduction of a support, as it stands (the N-ball models).

    Parameters
    ----------
    space_directions : tuple of sympy.Matrix or None
        None: the symbolic body-frame directions are the state (groups ``n1 .. nN``).
        Else the exact space components of the directions: the state carries the body
        components of the space axes (the frame ``alpha, beta, gamma``) and
        ``n_k = c_k1 alpha + c_k2 beta + c_k3 gamma``.
    momentum : str
        The state group of the reduced momentum (its rate is derived).
    conserved : bool
        With ``space_directions``: ship the closed model's integrals where they hold for
        ``N`` balls (BKM12-35..37, Rem2, 2.3: ``H = (M, omega)/2``, ``(M + K, e)`` for each
        space axis ``e``, ``(M + K, M + K)``, the frame's relations) and the density
        ``det(II)^-1/2`` (BKM12-38 in any space frame), the momentum rate written ``(M +
        K) x omega`` once its derived form is reduced to it modulo the frame's relations;
        the state ``M`` is then ``II omega``, without ``K``, as in the closed model (a
        :class:`~.rolling_system.RollingSystem` on balls), and the entries of ``II`` are
        expanded: polynomials of the frame with rational coefficients (the radicals of
        normalised directions cancel in ``n_k n_k^T``).
    """

    space_directions: tuple[sp.Matrix, ...] | None = None
    momentum: str = "M"
    conserved: bool = False

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """The momentum rate, ``omega = II^-1 M`` by cofactors, on the directions.

        Parameters
        ----------
        desc : MechanicalDescription
            A support (:func:`n_ball_description`) with its effects applied.

        Returns
        -------
        Reduced
            No integral, no density; ``details`` an :class:`NBallDetails`.
        """
        desc.refuse(
            "spherical support", ("potential", "phase_space", "momentum_in_state", "positions")
        )
        der = support_derivation(desc)
        red = der.reduction
        omega, n_balls = der.omega, len(der.directions)
        M = desc.state_group(self.momentum)
        if self.space_directions is None:
            names: tuple[str, ...] = tuple(f"n{k + 1}" for k in range(n_balls))
            geometry = tuple(PoissonGroup(UNIT_VECTOR, (name,)) for name in names)
            body_dirs = list(der.directions)
            subs: dict = {}
            space = None
        else:
            names = FRAME_NAMES
            geometry = (PoissonGroup(FRAME, names),)
            frame = [desc.state_group(name) for name in names]
            space = list(self.space_directions)
            body_dirs = [sum((c[i] * frame[i] for i in range(3)), sp.zeros(3, 1)) for c in space]
            subs = {
                s: e
                for n, b in zip(der.directions, body_dirs, strict=True)
                for s, e in zip(n, b, strict=True)
            }
        II = red.inertia_operator.xreplace(subs)
        if self.conserved and space is not None:  # rational entries: the directions' radicals
            II = II.applyfunc(sp.expand)  # cancel in n_k n_k^T (sum_k w_k c_k c_k^T is rational)
        adj, det = _adjugate_and_det(II)  # unexpanded: omega is only evaluated, never simplified
        detII = sp.Symbol("det_II", real=True)
        # M = II omega + K as derived; a description's M = II omega (the closed model's)
        K = sp.zeros(3, 1) if self.conserved else red.gyrostatic_momentum
        omega_val = adj * (M - K) / detII
        vectors = {name: desc.state_group(name) for name in names}
        tensor = sum(
            (der.weight(k) * body_dirs[k] * body_dirs[k].T for k in range(n_balls)),
            sp.zeros(3, 3),
        )
        constraints = [c for g in geometry for c in g.constraints(vectors)]
        conserved: dict = {
            "rates": {self.momentum: list(red.momentum_rate.xreplace(subs))},
            "integrals": (),
            "density": None,
        }
        if self.conserved and space is not None:
            conserved = _n_ball_integrals(
                der, subs, II, M, [vectors[n] for n in names], constraints
            )
            conserved["rates"] = {self.momentum: conserved["rates"]}
            conserved["density"] = det ** sp.Rational(-1, 2)
        return Reduced(
            aux=[(detII, det)] + [(omega[i], omega_val[i]) for i in range(3)],
            constraints=constraints,
            geometry=geometry,
            omega=omega,
            **conserved,
            details=NBallDetails(
                derivation=der,
                directions=body_dirs,
                space_directions=space,
                on_directions=subs,
                support_tensor=tensor,
                n_balls=n_balls,
            ),
        )


def _n_ball_integrals(
    der: SupportDerivation,
    subs: dict,
    II: sp.Matrix,
    M: sp.Matrix,
    frame: list[sp.Matrix],
    constraints: list,
) -> dict:
    """The momentum rate ``(M + K) x omega``, checked against the derived one modulo the
    frame's relations, the closed model's integrals and ``M = II omega`` (N balls in a
    space frame; ``II`` the inertia operator on the frame)."""
    red, omega = der.reduction, der.omega
    P0 = red.gyrostatic_momentum.xreplace(subs)
    derived = red.momentum_rate.xreplace(subs)
    frame_ideal = ConstraintIdeal(constraints, [s for v in frame for s in v])
    remainder = derived - cross(II * omega + P0, omega)
    if any(frame_ideal.reduce(sp.expand(e)) != 0 for e in remainder):  # pragma: no cover
        raise DerivationError("the momentum rate of the balls is not (M + K) x omega")
    name = "M" if der.K is None else "M+K"
    return {
        "rates": list(cross(M + P0, omega)),
        "integrals": _closed_integrals(M, P0, omega, tuple(frame), name),
        "momentum_of_omega": II * omega,
        "inertia_operator": II,
    }


def n_ball_description(
    n_balls: int,
    effects: frozenset[str] = frozenset(),
    space_directions: Sequence[Sequence[sp.Expr]] | int | None = None,
) -> MechanicalDescription:
    """The body on ``n_balls`` balls with the state of an N-ball model (no effect applied).

    Parameters
    ----------
    n_balls : int
    effects : frozenset of str
        Recorded in the description; not applied here.
    space_directions : sequence of 3-vectors, or int, optional
        See :func:`n_ball_model`.

    Returns
    -------
    MechanicalDescription
        :func:`~.support_derivation.support_description` with the state ``M`` and the
        directions (or the frame) and the stage :class:`NBallReduction`.

    Raises
    ------
    UserInputError
        A direction that is not three real numbers or is zero, or as many directions as
        balls not given.
    """
    desc = support_description(n_balls, effects, system="spherical_support_n_balls")
    desc.parameter_order = N_BALL_PARAMETER_ORDER
    desc.references.update(equations="BKM12-31", momentum="BKM12-2.1M")
    desc.add_state("M", tuple(vector("M", real=True)), None)
    if space_directions is None:
        for k, (_, n, _, _) in enumerate(desc.bodies):
            desc.add_state(f"n{k + 1}", tuple(n), list(cross(n, desc.omega)))
        desc.reduction = NBallReduction()
        return desc
    if isinstance(space_directions, int):
        space = _random_unit_vectors(n_balls, space_directions)
    else:
        space = [unit_exact(d, k) for k, d in enumerate(space_directions)]
    if len(space) != n_balls:
        raise UserInputError(f"{n_balls} balls need {n_balls} directions, got {len(space)}")
    return on_space_frame(desc, space)


def on_space_frame(
    desc: MechanicalDescription, space: Sequence[sp.Matrix], conserved: bool = False
) -> MechanicalDescription:
    """Put a support on the body components ``alpha, beta, gamma`` of the space axes.

    Parameters
    ----------
    desc : MechanicalDescription
        A support (its balls in ``desc.bodies``) with the state ``M``.
    space : sequence of sympy.Matrix
        The exact space components of the balls' unit directions.
    conserved : bool
        See :class:`NBallReduction`.

    Returns
    -------
    MechanicalDescription
        ``desc``, with the frame and the stage :class:`NBallReduction`.
    """
    for name in FRAME_NAMES:
        desc.add_poisson_vector(name)
    desc.reduction = NBallReduction(space_directions=tuple(space), conserved=conserved)
    return desc


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

    Raises
    ------
    UserInputError
        ``N < 1``, an unknown effect, bad directions.
    """
    chosen = parse_effects(effects, SUPPORTED_EFFECTS)
    desc = n_ball_description(check_n_balls(n_balls), chosen, space_directions)
    apply_effects(desc, chosen, SUPPORTED_EFFECTS)
    # the directions were read and checked above: a seed, None, or exact vectors
    directions = (
        repr(space_directions)
        if space_directions is None or isinstance(space_directions, int)
        else sp.srepr(tuple(tuple(sp.sympify(c) for c in v) for v in space_directions))
    )
    return kept_model("n-ball", f"{n_balls} {sorted(chosen)} {directions}",
                      lambda: form_model(desc))  # fmt: skip


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


def _virtual_balls(
    weights: tuple[sp.Symbol, sp.Symbol, sp.Symbol], spin_free: bool
) -> tuple[list[sp.Expr], sp.Expr]:
    """Moments and radius ratio of balls along ``alpha, beta, gamma`` that realise
    ``D_iso, D_al, D_be``."""
    D_iso, D_al, D_be = weights
    lam = sp.symbols("_la _lb _lg")
    r = sp.S.One if spin_free else sp.Rational(1, 2)  # any r != 1 works for rubber balls
    w = [ball_weight(x, r, spin_free) for x in lam]
    iso = sum(x / r**2 for x in lam)
    (sol,) = sp.linsolve([iso - w[2] - D_iso, w[0] - w[2] - D_al, w[1] - w[2] - D_be], lam)
    return list(sol), r


@dataclass(frozen=True)
class ClosedSupportReduction:
    """The support of three virtual balls along the eigenframe: the closed model.

    The multi-body reduction of three balls with symbolic directions, put on the
    eigenframe with the moments that realise ``D_iso, D_al, D_be`` (their spins, constant,
    set to zero), and inverted by the rank-2 structured inverse ``U = [alpha beta]``.

    Parameters
    ----------
    weights : (sympy.Symbol, sympy.Symbol, sympy.Symbol)
        ``D_iso, D_al, D_be``.
    momentum : str
        The state group of the momentum (its rate is derived).
    gyrostatic : str
        Name of the gyrostatic momentum in the integrals' names (``(M+K,gamma)``).
    """

    weights: tuple[sp.Symbol, sp.Symbol, sp.Symbol]
    momentum: str = "M"
    gyrostatic: str = "K"

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """Derive the closed model's equations, ``omega``, integrals and density.

        Parameters
        ----------
        desc : MechanicalDescription
            :func:`closed_support_description` with its effects applied.

        Returns
        -------
        Reduced

        Raises
        ------
        DerivationError
            When the inertia operator has no rank-2 structure or the momentum rate is not
            ``(M + K) x omega`` (neither happens for a support).
        """
        desc.refuse(
            "spherical support", ("potential", "phase_space", "momentum_in_state", "positions")
        )
        der = support_derivation(desc)
        M = desc.state_group(self.momentum)
        alpha, beta, gamma = frame = tuple(desc.state_group(name) for name in FRAME_NAMES)
        lam, r = _virtual_balls(self.weights, not der.rubber)
        subs = {
            s: e
            for n, b in zip(der.directions, frame, strict=True)
            for s, e in zip(n, b, strict=True)
        }
        subs.update(dict(zip(der.lambdas, lam, strict=True)))
        subs.update({ri: r for ri in der.ratios})
        subs.update({nu: 0 for nu in der.spins})  # the virtual balls' spins (constant) are zero
        geometry = (PoissonGroup(FRAME, FRAME_NAMES),)
        constraints = geometry[0].constraints(dict(zip(FRAME_NAMES, frame, strict=True)))
        proxy, rate, II = _on_the_frame(der, subs, frame)
        structured = proxy.structured_inverse(
            ConstraintIdeal(
                [dot(alpha, alpha) - 1, dot(beta, beta) - 1, dot(alpha, beta)], [*alpha, *beta]
            )
        )
        if structured is None or structured.U.shape[1] != 2:  # pragma: no cover
            raise DerivationError(
                "no rank-2 structure J + U C U^T of the support's inertia operator"
            )
        _, remainder = proxy.euler_poincare_form(M)
        frame_ideal = ConstraintIdeal(constraints, [s for v in frame for s in v])
        if any(frame_ideal.reduce(sp.expand(e)) != 0 for e in remainder):  # pragma: no cover
            raise DerivationError("the momentum rate is not (M + K) x omega")
        P0, omega = proxy.gyrostatic_momentum, der.omega
        aux, det_X = _omega_of_momentum(structured, M, omega)
        gyro = der.K is not None
        return Reduced(
            rates={self.momentum: list(cross(M + P0, omega))},
            aux=aux,
            integrals=_closed_integrals(
                M, P0, omega, frame, f"{self.momentum}+{self.gyrostatic}" if gyro else self.momentum
            ),
            density=det_X ** sp.Rational(-1, 2),
            constraints=constraints,
            geometry=geometry,
            omega=omega,
            momentum_of_omega=II * omega,
            inertia_operator=II,
            structured_inverse=structured,
            euler_poincare_remainder=remainder,
            reparametrisation=moment_reparametrisation(structured.J, desc.moments),
            details=ClosedSupportDetails(
                derivation=der,
                gyrostatic_momentum=P0,
                virtual_support=subs,
                momentum_rate_of_omega=rate,
                derived_energy=proxy.energy,
            ),
        )


def _on_the_frame(
    der: SupportDerivation, subs: dict, frame: tuple[sp.Matrix, ...]
) -> tuple[ReducedEquations, sp.Matrix, sp.Matrix]:
    """The virtual balls' reduction on the frame, as the engine's record (the rank-2
    structure ``J - D_al alpha⊗alpha - D_be beta⊗beta``, ``gamma⊗gamma`` eliminated), the
    momentum rate and the inertia operator as derived."""
    alpha, beta, gamma = frame
    red, omega = der.reduction, der.omega
    gamma_ab = dict(zip(gamma, cross(alpha, beta), strict=True))
    II = red.inertia_operator.xreplace(subs).applyfunc(sp.expand)
    P0 = red.gyrostatic_momentum.xreplace(subs)
    rate = red.momentum_rate.xreplace(subs).applyfunc(sp.expand)
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
        energy=sp.expand(red.energy.xreplace(subs)),
        omega=omega,
        kinematics=kin,
        time=T_SYMBOL,
    )
    return proxy, rate, II


def _omega_of_momentum(
    structured: StructuredInverse, M: sp.Matrix, omega: sp.Matrix
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], sp.Expr]:
    """``omega = A (M + U Z)`` with the 2x2 ``X`` inverted by cofactors (BKM12-34)."""
    A, U = structured.A, structured.U
    X = structured.X()
    Z = sp.Matrix(sp.symbols("Z_al Z_be", real=True))
    Y = U.T * A * M
    det_X = X[0, 0] * X[1, 1] - X[0, 1] * X[1, 0]
    Z_val = sp.Matrix([X[1, 1] * Y[0] - X[0, 1] * Y[1], X[0, 0] * Y[1] - X[1, 0] * Y[0]]) / det_X
    omega_val = A * (M + U * Z)
    aux = [(Z[i], Z_val[i]) for i in range(2)] + [(omega[i], omega_val[i]) for i in range(3)]
    return aux, det_X


def _closed_integrals(
    M: sp.Matrix, P0: sp.Matrix, omega: sp.Matrix, frame: tuple[sp.Matrix, ...], P_name: str
) -> list[tuple[str, sp.Expr]]:
    """The closed model's integrals (BKM12-35..37, Rem2)."""
    alpha, beta, gamma = frame
    P = M + P0
    return [
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


def closed_support_description(effects: frozenset[str] = frozenset()) -> MechanicalDescription:
    """The closed support: the body on three virtual balls along ``alpha, beta, gamma``.

    State ``M, alpha, beta, gamma``; parameters ``I, D_iso, D_al, D_be``; the stage
    :class:`ClosedSupportReduction`; no effect applied yet.

    Parameters
    ----------
    effects : frozenset of str
        Recorded in the description; not applied here.

    Returns
    -------
    MechanicalDescription
    """
    desc = support_body(NAME, effects)
    add_balls(desc, 3)
    D_iso, D_al, D_be = sp.symbols("D_iso D_al D_be", real=True)
    for symbol, text in (
        (
            D_iso,
            "isotropic part of the support, J = I + D_iso Id: sum_k lambda_k/r_k^2 - D_ga0 (>= 0)",
        ),
        (D_al, "D_al0 - D_ga0 (eigenvalues of the support tensor along alpha and gamma; non-zero)"),
        (D_be, "D_be0 - D_ga0 (eigenvalues of the support tensor along beta and gamma; non-zero)"),
    ):
        desc.add_parameter(ParameterSpec(symbol.name, (symbol,), "real", text))
    desc.add_state("M", tuple(vector("M", real=True)), None)
    for name in FRAME_NAMES:
        desc.add_poisson_vector(name)
    desc.reduction = ClosedSupportReduction(weights=(D_iso, D_al, D_be))
    desc.parameter_order = PARAMETER_ORDER
    desc.sampler = _physical_support_sampler(D_iso, D_al, D_be)
    desc.references.update(
        {
            "equations": "BKM12-32",
            "momentum": "BKM12-33",
            "omega": "BKM12-34",
            "integrals": "BKM12-35,36,37,Rem2",
            "density": "BKM12-38",
            "rubber_balls": "BKM12-2.2",
        }
    )
    return desc


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
    chosen = parse_effects(effects, SUPPORTED_EFFECTS)
    desc = closed_support_description(chosen)
    apply_effects(desc, chosen, SUPPORTED_EFFECTS)
    return form_model(desc)


BUILDER = build_spherical_support
