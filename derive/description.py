"""A mechanical description that effects add to, and the one step that makes a Model of it.

The shape is sympy's ``physics.mechanics.System``: a system module writes its base
description (kinetic energy, constraints, kinematics, states, parameters, the *reduction
stage* that derives its equations) with ``add_*``; each chosen effect declares what it adds
(a :class:`~.declaration.Declaration`: states, parameters, integrals, constraints and the
invariant relations they are, kinetic and potential terms, Poisson vectors) and the
description merges it (:meth:`MechanicalDescription.add`). :func:`form_model` — the one
finishing step of every system — runs the declared stage and makes the
:class:`~.model.Model` of what it derived and of what the description declares; no step
reads an effect's name.

A stage is an object with ``reduce(desc) -> Reduced``: the rolling rigid body of the
Chaplygin ball (:class:`~.rigid_body.RigidBodyReduction`, Lagrange–d'Alembert in the body
frame), the body in a spherical support (:mod:`.spherical_support`: the multi-body
Ferrers reduction, closed in the eigenframe of the support tensor or on given contact
directions), the ball whose centre rolls on a surface (:mod:`.ball_on_surface`, written in
the fixed frame) and the body on a sphere (:mod:`.body_on_sphere`). A stage refuses the
data it cannot take (:meth:`MechanicalDescription.refuse`) instead of dropping it.

References
----------
BKM12-1..7, K01-2.1..2.6, K01-4.1, K01-4.2, BM20-2.2..2.7 (the rolling ball and its
effects); see :mod:`.chaplygin_ball`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

import sympy as sp

from .declaration import Constraint, Declaration, StateGroup
from .effects import EFFECTS
from .errors import DerivationError
from .geometry import FRAME, UNIT_VECTOR, PoissonGroup
from .model import (
    Model,
    ModelDetails,
    ParameterSpec,
    PhaseSpaceSampler,
    Reparametrisation,
)
from .vectors import cross, vector

if TYPE_CHECKING:  # pragma: no cover
    from .engine import StructuredInverse

__all__ = [
    "MechanicalDescription",
    "StateGroup",
    "Constraint",
    "Declaration",
    "Reduced",
    "Reduction",
    "apply_effects",
    "form_model",
]


@dataclass(frozen=True)
class Reduced:
    """What a reduction stage derives from a description (consumed by :func:`form_model`).

    Attributes
    ----------
    rates : mapping of str to sequence of sympy.Expr
        The rates of the state groups the description leaves to the stage.
    aux : sequence of (sympy.Symbol, sympy.Expr)
        Auxiliary definitions, in order (``Model.aux``).
    integrals : sequence of (str, sympy.Expr)
        The integrals the stage finds, shipped before those the description declares.
    density : sympy.Expr or None
        The density of the invariant measure the stage derives (None: none known).
    constraints : sequence of sympy.Expr
        Phase-space polynomials of the stage's geometry (before the declared ones).
    geometry : tuple of PoissonGroup
    velocity_map : mapping of sympy.Symbol to sympy.Expr
        The reference-point velocity on the admissible velocities (``v -> ...``); the
        declared rates written in ``v`` are put on them.
    relation_unknowns : tuple of sympy.Symbol
        ``Model.relation_unknowns``.
    omega, momentum_of_omega, inertia_operator, structured_inverse,
    euler_poincare_remainder, reparametrisation, details :
        The :class:`~.model.Model` fields of the same names.
    """

    rates: Mapping[str, Sequence[sp.Expr]]
    aux: Sequence[tuple[sp.Symbol, sp.Expr]]
    integrals: Sequence[tuple[str, sp.Expr]]
    density: sp.Expr | None
    constraints: Sequence[sp.Expr] = ()
    geometry: tuple[PoissonGroup, ...] = ()
    velocity_map: Mapping[sp.Symbol, sp.Expr] = field(default_factory=dict)
    relation_unknowns: tuple[sp.Symbol, ...] = ()
    omega: sp.Matrix | None = None
    momentum_of_omega: sp.Matrix | None = None
    inertia_operator: sp.Matrix | None = None
    structured_inverse: StructuredInverse | None = None
    euler_poincare_remainder: sp.Matrix | None = None
    reparametrisation: Reparametrisation | None = None
    details: ModelDetails | None = None


class Reduction(Protocol):
    """A reduction stage: the way a system's equations are derived from its description."""

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """Derive the equations of ``desc``.

        Parameters
        ----------
        desc : MechanicalDescription
            A base description with its effects applied (not modified).

        Returns
        -------
        Reduced
        """
        ...  # pragma: no cover


@dataclass
class MechanicalDescription:
    """What a system and its effects say about a mechanical system, as data.

    Attributes
    ----------
    system : str
    effects : frozenset of str
    time : sympy.Symbol
    omega : sympy.Matrix, shape (3, 1)
        Angular-velocity symbols (body frame for a rigid body, fixed frame for the ball on
        a surface).
    reduction : Reduction or None
        The stage :func:`form_model` derives the equations with (set by the system).
    parameter_order : tuple of str
        Order of the parameter groups in the model (every declared group must be named).
    v : sympy.Matrix or None, shape (3, 1)
        Velocity symbols of the reference point (the centre).
    laws : {"bm20", "generic"}
        Laws of time-dependent parameters, read by the effects that make them (see
        :mod:`.chaplygin_ball`).
    inertia : sympy.Matrix or None, shape (3, 3)
        Central inertia tensor of the body in body axes (``T`` has
        ``(omega, inertia omega)/2``).
    moments : tuple of sympy.Symbol
        The parameters the principal moments are written in (``I1, I2, I3``): exact
        checks change them to ``A_i = 1/J_ii`` (``Model.reparametrisation``); empty when
        the moments are functions of time.
    kinetic_energy : sympy.Expr
        The other terms of ``T`` (translation, gyrostatic terms ...).
    potential : sympy.Expr
        Potential energy of the external forces (in the state symbols).
    constraints : list of sympy.Expr
        Velocity constraints, linear and homogeneous in the velocities.
    reacting : list of str
        For each constraint on omega alone ``(omega, X) = 0``, the space-fixed vector
        ``X`` its reaction torque lies along (it kills the momentum integrals along it).
    invariant_relations : dict of str to sympy.Expr
        Relations the flow keeps (zero on the phase space): the constraints on omega
        alone, ``(omega,X)``.
    kinematics : dict of str to (sympy.Matrix, sympy.Matrix)
        Space-fixed vectors and their Poisson equations.
    positions : dict of str to (sympy.Matrix, sympy.Matrix)
        Configuration vectors that are not unit vectors (the contact point's position
        from a rotating plane's axis), body axes, and their rates: the coefficients may
        depend on them; they are state, not geometry.
    states : list of StateGroup
    parameters : dict of str to ParameterSpec
    integrals : dict of str to sympy.Expr
        First integrals the system or an effect states; shipped after those the stage
        finds.
    phase_space : list of sympy.Expr
        Polynomials vanishing on the phase space beyond those of the Poisson vectors (the
        surface the centre lies on).
    momentum_in_state : sympy.Matrix, shape (3, 1)
        Velocity-independent momentum the momentum state includes (BM20's total momentum
        includes ``k(t)``, BM20-2.2); zero when the state is ``II omega``.
    contact_vector : sympy.Matrix or None
        From the centre to the contact point.
    centre_offset : sympy.Matrix or None, shape (3, 1)
        From the reference point of ``v`` (the centre of mass) to the centre of the
        body's spherical surface, when they differ (None: the same point).
    bodies : list of (sympy.Matrix, sympy.Matrix, sympy.Symbol, sympy.Symbol)
        Further bodies (the support's balls): angular velocity, contact direction, moment
        of inertia, radius ratio.
    references : dict of str to str
    effect_references : dict of str to dict of str to str
        References the system gives for an effect (they update the effect's own).
    completion : dict of (str, ...) to str
        How omitted state groups are completed (``Model.completion``).
    sampler : callable or None
        ``Model.sampler``: exact points of a phase space not made of Poisson vectors.
    trace_velocity : sympy.Matrix or None, shape (3, 1)
        The velocity in space (body axes) the contact point's trace moves with, where it
        is not that of the body's spherical centre (a convex body: the plane's velocity
        under the contact plus the contact point's rate on the body); read by the
        ``contact_point`` effect.
    trace_parameters : tuple of ParameterSpec
        Parameters only the trace uses (a constant velocity of a moving plane: it carries
        the trace but not the body).
    trace_on_normal : sympy.Expr or None
        On a fixed sphere: the contact point is this times the normal ``gamma`` from the
        sphere's centre (``R`` outside, ``-R`` inside); the ``contact_point`` effect then
        adds the fixed frame ``alpha, beta, zeta`` instead of a trace in a plane.
    """

    system: str
    effects: frozenset[str]
    time: sp.Symbol
    omega: sp.Matrix
    reduction: Reduction | None = None
    parameter_order: tuple[str, ...] = ()
    v: sp.Matrix | None = None
    laws: str = "bm20"
    inertia: sp.Matrix | None = None
    moments: tuple[sp.Symbol, ...] = ()
    kinetic_energy: sp.Expr = sp.S.Zero
    potential: sp.Expr = sp.S.Zero
    constraints: list[sp.Expr] = field(default_factory=list)
    reacting: list[str] = field(default_factory=list)
    invariant_relations: dict[str, sp.Expr] = field(default_factory=dict)
    kinematics: dict[str, tuple[sp.Matrix, sp.Matrix]] = field(default_factory=dict)
    positions: dict[str, tuple[sp.Matrix, sp.Matrix]] = field(default_factory=dict)
    states: list[StateGroup] = field(default_factory=list)
    parameters: dict[str, ParameterSpec] = field(default_factory=dict)
    integrals: dict[str, sp.Expr] = field(default_factory=dict)
    phase_space: list[sp.Expr] = field(default_factory=list)
    momentum_in_state: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))
    contact_vector: sp.Matrix | None = None
    centre_offset: sp.Matrix | None = None
    bodies: list[tuple[sp.Matrix, sp.Matrix, sp.Symbol, sp.Symbol]] = field(default_factory=list)
    references: dict[str, str] = field(default_factory=dict)
    effect_references: dict[str, dict[str, str]] = field(default_factory=dict)
    completion: dict[tuple[str, ...], str] = field(default_factory=dict)
    sampler: PhaseSpaceSampler | None = None
    trace_velocity: sp.Matrix | None = None
    trace_parameters: tuple[ParameterSpec, ...] = ()
    trace_on_normal: sp.Expr | None = None

    # ------------------------------------------------------------------ add_*
    def add(self, declaration: Declaration) -> None:
        """Merge what an effect declares (:class:`~.declaration.Declaration`).

        Parameter groups it redeclares are dropped first; then its parameters, its
        kinetic and potential terms, its Poisson vectors (those not there yet), its
        constraints (with the invariant relations of those on omega alone), its states,
        integrals, phase-space constraints, inertia and moments, the momentum the state
        includes and its completion rules are added, each by the ``add_*`` method of
        the same name.

        Parameters
        ----------
        declaration : Declaration

        Raises
        ------
        DerivationError
            For a state group or an invariant relation added twice, or a parameter group
            declared again differently without being redeclared.
        """
        d = declaration
        for name in d.redeclared_parameters:
            self.remove_parameter(name)
        for spec in d.parameters:
            self.add_parameter(spec)
        self.add_kinetic_energy(d.kinetic_energy)
        self.add_potential(d.potential)
        for name in d.poisson_vectors:
            if name not in self.kinematics:
                self.add_poisson_vector(name)
        for constraint in d.constraints:
            self.add_constraint(constraint.expr, constraint.reacts_along)
        for group in d.states:
            self.add_state(group.name, group.symbols, group.rate)
        for name, expr in d.integrals:
            self.add_integral(name, expr)
        for expr in d.phase_space:
            self.add_phase_space_constraint(expr)
        if d.inertia is not None:
            self.inertia = d.inertia
        if d.moments is not None:
            self.moments = tuple(d.moments)
        if d.momentum_in_state is not None:
            self.add_momentum_in_state(d.momentum_in_state)
        for groups, rule in d.completion:
            self.add_completion(groups, rule)

    def add_kinetic_energy(self, term: sp.Expr) -> None:
        """Add a term to ``T``.

        Parameters
        ----------
        term : sympy.Expr
        """
        self.kinetic_energy += term

    def add_potential(self, term: sp.Expr) -> None:
        """Add a term to the potential energy of the external forces.

        Parameters
        ----------
        term : sympy.Expr
        """
        self.potential += term

    def add_constraint(self, expr: sp.Expr, reacts_along: str | None = None) -> None:
        """Add a velocity constraint.

        Parameters
        ----------
        expr : sympy.Expr
            Linear and homogeneous in the velocities.
        reacts_along : str, optional
            For a constraint on omega alone ``(omega, X) = 0``: the name of ``X``. The
            flow keeps such a constraint (its multiplier is eliminated from
            ``d/dt (omega, X) = 0``): it is declared the invariant relation ``(omega,X)``.
        """
        self.constraints.append(expr)
        if reacts_along is not None:
            self.reacting.append(reacts_along)
            self.add_invariant_relation(f"(omega,{reacts_along})", expr)

    def add_invariant_relation(self, name: str, expr: sp.Expr) -> None:
        """Declare a relation the flow keeps, zero on the phase space.

        Parameters
        ----------
        name : str
        expr : sympy.Expr
            Linear in the momentum state (the verifier solves it when it samples).
        """
        if name in self.invariant_relations:
            raise DerivationError(f"invariant relation {name!r} declared twice")
        self.invariant_relations[name] = expr

    def add_kinematics(self, name: str, symbols: sp.Matrix, rate: sp.Matrix) -> None:
        """Add a space-fixed vector and its kinematic equation.

        Parameters
        ----------
        name : str
        symbols, rate : sympy.Matrix, shape (3, 1)
        """
        self.kinematics[name] = (symbols, rate)

    def add_position(self, name: str, symbols: sp.Matrix, rate: sp.Matrix) -> None:
        """Add a configuration vector (not a unit vector) as state, with its rate.

        Parameters
        ----------
        name : str
        symbols, rate : sympy.Matrix, shape (3, 1)
            The rate in ``omega``, the state and the parameters (not ``v``).
        """
        self.positions[name] = (symbols, rate)
        self.add_state(name, tuple(symbols), list(rate))

    def add_poisson_vector(self, name: str, rate_factor: sp.Expr = sp.S.One) -> None:
        """Add the unit vector ``name`` (``X' = s X x omega``) as kinematics and state.

        Parameters
        ----------
        name : str
        rate_factor : sympy.Expr, default 1
            ``s``: 1 for a vector fixed in space (Poisson's equation); the normal of a
            fixed sphere the body rolls on turns at ``s = R/(R +- b)`` of that rate.
        """
        X = vector(name, real=True)
        rate = cross(X, self.omega) * rate_factor
        self.add_kinematics(name, X, rate)
        self.add_state(name, tuple(X), list(rate))

    def add_frame(self) -> None:
        """Add the space-fixed horizontal axes ``alpha, beta`` (once)."""
        for name in ("alpha", "beta"):
            if name not in self.kinematics:
                self.add_poisson_vector(name)

    def add_state(
        self, name: str, symbols: Sequence[sp.Symbol], rate: Sequence[sp.Expr] | None
    ) -> None:
        """Add a state group.

        Parameters
        ----------
        name : str
        symbols : sequence of sympy.Symbol
        rate : sequence of sympy.Expr or None
            Its time derivative (it may use the reference-point velocity ``v``), or None
            when the reduction stage derives it (the momentum ``M``).
        """
        if any(group.name == name for group in self.states):
            raise DerivationError(f"state group {name!r} added twice")
        self.states.append(StateGroup(name, tuple(symbols), None if rate is None else tuple(rate)))

    def add_parameter(self, spec: ParameterSpec, replace: bool = False) -> None:
        """Declare a parameter group.

        Parameters
        ----------
        spec : ParameterSpec
        replace : bool
            Replace a group of the same name (a new description of the same symbols);
            otherwise a second, identical declaration is a no-op and a different one an
            error.
        """
        old = self.parameters.get(spec.name)
        if old is not None and old != spec and not replace:
            raise DerivationError(f"parameter group {spec.name!r} declared twice, differently")
        self.parameters[spec.name] = spec

    def remove_parameter(self, name: str) -> None:
        """Remove a parameter group (its symbols became functions of time ...).

        Parameters
        ----------
        name : str
        """
        self.parameters.pop(name, None)

    def add_integral(self, name: str, expr: sp.Expr) -> None:
        """Add a first integral, or a term to one of that name already stated.

        Parameters
        ----------
        name : str
        expr : sympy.Expr
        """
        self.integrals[name] = self.integrals.get(name, sp.S.Zero) + expr

    def add_phase_space_constraint(self, expr: sp.Expr) -> None:
        """Add a polynomial that vanishes on the phase space (a surface the state lies on).

        Parameters
        ----------
        expr : sympy.Expr
            A polynomial in the state and the parameters.
        """
        self.phase_space.append(expr)

    def add_momentum_in_state(self, momentum: sp.Matrix) -> None:
        """Make the momentum state include a velocity-independent momentum.

        With ``k(t)`` in the state (BM20's total momentum, BM20-2.2) the state's rate keeps
        the form ``M' = M x omega`` without a ``k'(t)`` term.

        Parameters
        ----------
        momentum : sympy.Matrix, shape (3, 1)
        """
        self.momentum_in_state = self.momentum_in_state + momentum

    def add_completion(self, groups: tuple[str, ...], rule: str) -> None:
        """Declare how the state groups ``groups`` are completed when a user omits them.

        Parameters
        ----------
        groups : tuple of str
            State groups completed together (``("alpha", "beta")``).
        rule : str
            One of :data:`~chaplygin.derive.model.COMPLETION_RULES`.
        """
        self.completion[tuple(groups)] = rule

    # ------------------------------------------------------------------ queries
    def state_group(self, name: str) -> sp.Matrix:
        """The symbols of state group ``name`` as a column matrix.

        Parameters
        ----------
        name : str

        Returns
        -------
        sympy.Matrix
        """
        for group in self.states:
            if group.name == name:
                return sp.Matrix(group.symbols)
        raise KeyError(name)

    @property
    def vectors(self) -> dict[str, sp.Matrix]:
        """The space-fixed vectors by name."""
        return {name: X for name, (X, _) in self.kinematics.items()}

    def total_kinetic_energy(self) -> sp.Expr:
        """``T = (omega, inertia omega)/2`` plus the added terms.

        Returns
        -------
        sympy.Expr
            The kinetic energy in ``omega`` (and whatever the added terms use: ``v``,
            the space-fixed vectors, parameters, time).
        """
        if self.inertia is None:
            return self.kinetic_energy
        rotation = (self.omega.T * self.inertia * self.omega)[0] / 2
        return rotation + self.kinetic_energy

    def geometry(self) -> tuple[PoissonGroup, ...]:
        """A frame when ``alpha, beta`` and the vertical are there, else unit vectors.

        Returns
        -------
        tuple of PoissonGroup
            One ``FRAME`` group ``(alpha, beta, gamma)`` (``(alpha, beta, zeta)`` on a
            fixed sphere, where ``gamma`` is the turning normal: then also its
            ``UNIT_VECTOR`` group), or one ``UNIT_VECTOR`` group per space-fixed vector, in
            the order of ``kinematics``.
        """
        states = {g.name for g in self.states}  # (a convex body's vertical: a state)
        third = "zeta" if "zeta" in self.kinematics or "zeta" in states else "gamma"
        frame = ("alpha", "beta", third)
        if not set(frame) <= set(self.kinematics) | ({"zeta"} & states):
            return tuple(PoissonGroup(UNIT_VECTOR, (name,)) for name in self.kinematics)
        rest = [name for name in self.kinematics if name not in frame]
        return (PoissonGroup(FRAME, frame), *(PoissonGroup(UNIT_VECTOR, (n,)) for n in rest))

    def ordered_parameters(self) -> tuple[ParameterSpec, ...]:
        """The declared parameter groups in :attr:`parameter_order`.

        Returns
        -------
        tuple of ParameterSpec

        Raises
        ------
        DerivationError
            For a declared group that :attr:`parameter_order` does not name.
        """
        unknown = [n for n in self.parameters if n not in self.parameter_order]
        if unknown:
            raise DerivationError(
                f"parameter groups {unknown} are not in the system's PARAMETER_ORDER: add them"
            )
        return tuple(self.parameters[n] for n in self.parameter_order if n in self.parameters)

    def signature(
        self,
    ) -> tuple[tuple[tuple[str, tuple[sp.Symbol, ...]], ...], tuple[ParameterSpec, ...]]:
        """State groups and parameters as the model will have them (nothing derived).

        Returns
        -------
        state_groups : tuple of (str, tuple of sympy.Symbol)
        parameters : tuple of ParameterSpec
        """
        groups = tuple((group.name, group.symbols) for group in self.states)
        return groups, self.ordered_parameters()

    def input_signature(self) -> tuple:
        """What an input check needs before anything is derived.

        Returns
        -------
        state_groups : tuple of (str, tuple of sympy.Symbol)
        parameters : tuple of ParameterSpec
        geometry : tuple of (str, tuple of str)
            The Poisson groups as ``(kind, names)`` (``Model.geometry``'s form in code).
        completion : tuple of ((str, ...), str)
        """
        groups, parameters = self.signature()
        geometry = tuple((g.kind, tuple(g.names)) for g in self.geometry())
        return groups, parameters, geometry, tuple(self.completion.items())

    def refuse(self, stage: str, names: Iterable[str]) -> None:
        """Refuse declared data a reduction stage does not take (rather than drop it).

        Parameters
        ----------
        stage : str
            The stage, for the message.
        names : iterable of str
            Attributes the stage does not read; each must be empty, zero or None.

        Raises
        ------
        DerivationError
            Naming the attributes that are set.
        """
        given = [name for name in names if _is_set(getattr(self, name))]
        if given:
            raise DerivationError(
                f"{self.system}: the {stage} derivation does not take {', '.join(given)}"
            )


def _is_set(value: object) -> bool:
    if value is None:
        return False
    if isinstance(value, sp.MatrixBase):
        return not value.is_zero_matrix
    if isinstance(value, sp.Basic):
        return value != 0
    return bool(value)


def apply_effects(
    desc: MechanicalDescription, effects: Iterable[str], order: Sequence[str]
) -> None:
    """Apply the chosen effects to ``desc`` in the system's order.

    Each effect's declaration is merged (:meth:`~.effects.Effect.apply`), with the
    references it cites and those the system gives for it
    (:attr:`MechanicalDescription.effect_references`).

    Parameters
    ----------
    desc : MechanicalDescription
    effects : iterable of str
        Names already checked by :func:`~.effects.parse_effects`.
    order : sequence of str
        The system's supported effects, in the order they are applied.
    """
    chosen = set(effects)
    for name in order:
        if name in chosen:
            EFFECTS[name].apply(desc)


def _rates(desc: MechanicalDescription, reduced: Reduced) -> list[sp.Expr]:
    """The right-hand side in state order: declared rates (on the admissible velocities
    when they use ``v``) and the stage's."""
    velocities = set(reduced.velocity_map)
    rhs: list[sp.Expr] = []
    for group in desc.states:
        if group.rate is None:
            if group.name not in reduced.rates:
                raise DerivationError(
                    f"{desc.system}: no rate for the state group {group.name!r} (declare it "
                    "or use a reduction stage that derives it)"
                )
            rhs += list(reduced.rates[group.name])
            continue
        for e in group.rate:
            if velocities & sp.sympify(e).free_symbols:
                e = sp.expand(sp.sympify(e).xreplace(reduced.velocity_map))
            rhs.append(e)
    return rhs


def form_model(desc: MechanicalDescription) -> Model:
    """Derive the Model of a mechanical description: the finishing step of every system.

    Runs the description's reduction stage, then makes the Model of the declared state
    groups (their declared or derived rates), the parameters in the system's order, the
    integrals the stage finds followed by the declared ones, the declared invariant
    relations and phase-space constraints, completion rules, sampler and references.

    Parameters
    ----------
    desc : MechanicalDescription
        A base description with its effects applied.

    Returns
    -------
    Model

    Raises
    ------
    DerivationError
        Without a reduction stage, from the stage, for a parameter group not in
        ``parameter_order``, for a state group without a rate, or from the Model's own
        validation.
    """
    if desc.reduction is None:
        raise DerivationError(f"{desc.system}: the description names no reduction stage")
    reduced = desc.reduction.reduce(desc)
    rhs = _rates(desc, reduced)
    integrals = (*reduced.integrals, *desc.integrals.items())
    references = dict(desc.references)
    if reduced.density is None:  # no reference for what the model does not have
        references.pop("density", None)
    if not integrals:
        references.pop("integrals", None)
    return Model(
        system=desc.system,
        effects=desc.effects,
        time=desc.time,
        state_groups=tuple((group.name, group.symbols) for group in desc.states),
        parameters=desc.ordered_parameters(),
        aux=tuple(reduced.aux),
        rhs=tuple(rhs),
        constraints=(*reduced.constraints, *desc.phase_space),
        geometry=reduced.geometry,
        integrals=integrals,
        density=reduced.density,
        omega=reduced.omega,
        momentum_of_omega=reduced.momentum_of_omega,
        inertia_operator=reduced.inertia_operator,
        structured_inverse=reduced.structured_inverse,
        euler_poincare_remainder=reduced.euler_poincare_remainder,
        invariant_relations=tuple(sorted(desc.invariant_relations.items())),
        relation_unknowns=reduced.relation_unknowns,
        completion=tuple(desc.completion.items()),
        reparametrisation=reduced.reparametrisation,
        sampler=desc.sampler,
        details=reduced.details,
        references=references,
    )
