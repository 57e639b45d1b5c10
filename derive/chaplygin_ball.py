"""The Chaplygin ball: a dynamically asymmetric, balanced ball rolling without slipping.

Built by the Lagrange–d'Alembert engine from its mechanical description: kinetic energy
``T = (omega, I omega)/2 + m (v, v)/2`` (plus ``(K, omega)`` with a gyrostat), the no-slip
constraint ``v + omega x r = 0`` with ``r = -b gamma`` from the centre to the contact
point, and the Poisson equations of the space-fixed vectors. ``D = m b^2``.

Two effects make the parameters periodic in time (BM20, the ball with moving internal
masses and rotors): ``variable_inertia`` replaces ``I`` by
``I(t) = diag(I1 + (J_off + delta sin(Omega t))^2, I2, I3 + (J_off + delta sin(Omega t))^2)``
(BM20-3.4) and ``variable_gyrostat`` adds the term ``(k(t), omega)`` to ``T`` with
``k(t) = K sin(Omega t)`` (BM20-3.5). The engine differentiates the explicit time
dependence of ``T``; with ``variable_gyrostat`` the state is BM20's *total* momentum
``M = I(t) omega + D gamma x (omega x gamma) + k(t)``, whose equations keep the form
``M' = M x omega`` with ``omega = A(t) (M - k(t))`` (BM20-2.5) and whose integrals
``(M, M)``, ``(M, gamma)`` do not depend on time.

References
----------
BKM12-1..7, K01-2.1..2.6 (ball); K01-4.1, K01-4.2 (gyrostat); BM20-2.2..2.7, 3.4, 3.5
(variable inertia and gyrostatic momentum).
"""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

from .description import MechanicalDescription, apply_effects, form_model
from .effects import parse_effects
from .model import Model, ParameterSpec
from .rigid_body import RigidBodyReduction
from .vectors import cross, dot, vector

__all__ = [
    "build_chaplygin_ball",
    "ball_description",
    "ball_signature",
    "SUPPORTED_EFFECTS",
    "PARAMETER_ORDER",
    "NAME",
    "DESCRIPTION",
    "GENERATED_VARIANTS",
]

NAME = "chaplygin_ball"
DESCRIPTION = (
    "balanced dynamically asymmetric ball rolling without slipping on a plane (BKM12 §1.1, K01 §2)"
)
#: The effects it takes, in the order they are applied (derive/effects.py).
SUPPORTED_EFFECTS = (
    "gyrostat",
    "contact_point",
    "variable_inertia",
    "variable_gyrostat",
    "rubber",
    "straight_line",
)
#: Effect combinations whose code is committed in generated/.
GENERATED_VARIANTS = (
    (),
    ("gyrostat",),
    ("contact_point",),
    ("contact_point", "gyrostat"),
    ("variable_inertia",),
    ("variable_gyrostat", "variable_inertia"),
    ("contact_point", "variable_gyrostat", "variable_inertia"),  # BM20 Fig. 5 contact trace
    ("rubber",),  # BKM12 §3 (no slip, no twist)
    ("straight_line",),  # BKM12 (57), Veselovs' system
)
#: Laws of the time-dependent parameters: BM20's (3.4)-(3.5), or undefined functions of t
#: (``I1(t)`` ..., ``k1(t)`` ...) so that a check covers every law (private, for verify).
LAWS = ("bm20", "generic")


#: Order of the parameter groups in the model (and the generated code).
PARAMETER_ORDER = ("I", "D", "b", "J_off", "delta", "K", "Omega")


def ball_description(
    effects: frozenset[str] = frozenset(), laws: str = "bm20"
) -> MechanicalDescription:
    """The mechanical description of the plain ball (no effect applied yet).

    ``T = (omega, I omega)/2 + m (v, v)/2`` with ``m = D/b^2``, the no-slip constraint
    ``v + omega x r = 0`` with ``r = -b gamma`` (K01-2.5), the Poisson equation of
    ``gamma``; state ``M, gamma``; parameters ``I, D``; derived by the rigid-body stage
    (:class:`~.rigid_body.RigidBodyReduction`).

    Parameters
    ----------
    effects : frozenset of str
        Recorded in the description (the model's name); not applied here.
    laws : {"bm20", "generic"}

    Returns
    -------
    MechanicalDescription
    """
    t = sp.Symbol("t", real=True)
    Iv = vector("I", positive=True)
    D, b = sp.symbols("D b", positive=True)
    omega = vector("omega", real=True)
    v = vector("v", real=True)
    m = D / b**2  # D = m b^2
    desc = MechanicalDescription(
        system=NAME,
        effects=effects,
        time=t,
        omega=omega,
        reduction=RigidBodyReduction(momentum="M", gyrostatic="K"),
        parameter_order=PARAMETER_ORDER,
        v=v,
        laws=laws,
        inertia=sp.diag(*Iv),
        moments=tuple(Iv),
    )
    desc.add_kinetic_energy(m * dot(v, v) / 2)
    desc.contact_vector = -b * vector("gamma", real=True)  # centre -> contact point (K01-2.5)
    for c in v + cross(omega, desc.contact_vector):  # no slip
        desc.add_constraint(c)
    desc.add_state("M", tuple(vector("M", real=True)), None)
    desc.add_poisson_vector("gamma")
    desc.add_parameter(
        ParameterSpec("I", tuple(Iv), "positive", "central principal moments of inertia I1, I2, I3")
    )
    desc.add_parameter(
        ParameterSpec("D", (D,), "positive", "D = m b^2 (mass times squared radius)")
    )
    desc.references.update(
        momentum="BKM12-1",
        equations="BKM12-2",
        omega="BKM12-3",
        density="BKM12-4",
        integrals="BKM12-5",
        contact_point="BKM12-6",
    )
    return desc


def ball_signature(
    effects: frozenset[str],
) -> tuple[tuple[tuple[str, tuple[sp.Symbol, ...]], ...], tuple[ParameterSpec, ...]]:
    """State groups and parameters of a variant, from its description (nothing derived).

    Parameters
    ----------
    effects : frozenset of str
        Checked names.

    Returns
    -------
    state_groups : tuple of (str, tuple of sympy.Symbol)
    parameters : tuple of ParameterSpec
        In :data:`PARAMETER_ORDER`, as the derived model has them.
    geometry : tuple of (str, tuple of str)
    completion : tuple of ((str, ...), str)
    """
    desc = ball_description(effects)
    apply_effects(desc, effects, SUPPORTED_EFFECTS)
    return desc.input_signature()


def build_chaplygin_ball(effects: Iterable[str] | str | None = (), *, _laws: str = "bm20") -> Model:
    """Derive the Chaplygin ball model.

    Parameters
    ----------
    effects : iterable of str or str, optional
        Any of :data:`SUPPORTED_EFFECTS` (``"variable_gyrostat"`` not together with
        ``"gyrostat"``); each applies itself to :func:`ball_description`.
    _laws : {"bm20", "generic"}, optional
        Private (verification): ``"generic"`` makes ``I(t)`` and ``k(t)`` undefined
        functions of time instead of BM20's laws (3.4)-(3.5), so that an identity proved on
        that model holds for every law. Such a model is never emitted.

    Returns
    -------
    Model
        State ``M, gamma`` (+ ``alpha, beta`` with ``contact_point`` or
        ``straight_line``, + ``x, y`` with ``contact_point``), parameters ``I1, I2, I3, D``
        (+ ``b`` with ``contact_point``, ``K1, K2, K3`` with ``gyrostat`` or
        ``variable_gyrostat``, ``J_off, delta`` with ``variable_inertia``, ``Omega`` with
        either variable effect). With ``variable_gyrostat`` the state ``M`` is BM20's total
        momentum (it includes ``k(t)``).

    Raises
    ------
    UserInputError
        ``variable_gyrostat`` together with ``gyrostat`` (one gyrostatic momentum: give
        either a constant one or a periodic one), or an unknown effect; before anything
        is derived.

    Examples
    --------
    >>> model = build_chaplygin_ball()
    >>> model.state_names
    ('M1', 'M2', 'M3', 'gamma1', 'gamma2', 'gamma3')
    >>> model.param_names
    ('I1', 'I2', 'I3', 'D')
    """
    effects = parse_effects(effects, SUPPORTED_EFFECTS)
    if _laws not in LAWS:
        raise ValueError(f"unknown parameter laws {_laws!r}; valid: {', '.join(LAWS)}")
    desc = ball_description(effects, _laws)
    apply_effects(desc, effects, SUPPORTED_EFFECTS)
    return form_model(desc)


BUILDER = build_chaplygin_ball
SIGNATURE = ball_signature
