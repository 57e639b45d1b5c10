"""A mechanical description that effects add to, and the one step that makes a Model of it.

The shape is sympy's ``physics.mechanics.System``: a system module writes its base
description (kinetic energy, constraints, kinematics, states, parameters), each chosen
effect adds to it with ``add_*`` (:meth:`~.effects.Effect.apply`), and :func:`form_model`
derives the equations (:func:`~.engine.lagrange_dalembert`), inverts the momentum,
eliminates the multipliers of constraints on omega alone, collects the integrals and
makes the :class:`~.model.Model`, which validates itself.

References
----------
BKM12-1..7, K01-2.1..2.6, K01-4.1, K01-4.2, BM20-2.2..2.7 (the rolling ball and its
effects); see :mod:`.chaplygin_ball`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import sympy as sp

from .algebra import ConstraintIdeal
from .effects import EFFECTS
from .engine import ReducedEquations, RigidBodyDescription, _time_derivative, lagrange_dalembert
from .errors import DerivationError
from .geometry import FRAME, UNIT_VECTOR, PoissonGroup
from .model import Model, ModelDetails, ParameterSpec, Reparametrisation
from .vectors import cross, dot, vector

__all__ = ["MechanicalDescription", "RigidBodyDetails", "apply_effects", "form_model"]

#: A state group's rate: expressions, or a function of the reduced equations.
Rate = Sequence[sp.Expr] | Callable[[ReducedEquations], Sequence[sp.Expr]]


@dataclass
class MechanicalDescription:
    """What a system and its effects say about a constrained rigid body.

    Attributes
    ----------
    system : str
    effects : frozenset of str
    time : sympy.Symbol
    omega : sympy.Matrix, shape (3, 1)
        Angular-velocity symbols (body frame).
    v : sympy.Matrix or None, shape (3, 1)
        Velocity symbols of the reference point (the centre).
    laws : {"bm20", "generic"}
        Laws of time-dependent parameters (see :mod:`.chaplygin_ball`).
    inertia : list of sympy.Expr
        Principal moments of the body (``T`` has ``(omega, diag(inertia) omega)/2``).
    kinetic_energy : sympy.Expr
        The other terms of ``T`` (translation, gyrostatic terms ...).
    constraints : list of sympy.Expr
        Velocity constraints, linear and homogeneous in the velocities.
    reacting : list of str
        For each constraint on omega alone, the space-fixed vector its reaction torque
        lies along (it kills the momentum integrals along that vector).
    kinematics : dict of str to (sympy.Matrix, sympy.Matrix)
        Space-fixed vectors and their Poisson equations.
    states : list of (str, tuple of sympy.Symbol, rate)
        State groups in order; the rate of ``M`` is derived by :func:`form_model`.
    parameters : dict of str to ParameterSpec
    references : dict of str to str
    conservative : bool
        False when the parameters depend on time (no energy integral).
    has_density : bool
        False when no invariant density is known.
    total_momentum : bool
        The state ``M`` includes the time-dependent gyrostatic momentum (BM20-2.2).
    gyrostatic_momentum_of_time : sympy.Matrix, shape (3, 1)
    contact_vector : sympy.Matrix or None
        From the centre to the contact point.
    potential : sympy.Expr
        Potential energy of external forces on the centre (in the state symbols).
    integrals : dict of str to sympy.Expr
        First integrals the system or an effect states; :func:`form_model` ships them
        after those it finds itself.
    bodies : list of (sympy.Matrix, sympy.Matrix)
        Further bodies (the support's balls): angular velocity and contact direction.
    free_spins : bool
        The bodies' spins about their contact directions are free quasi-velocities.
    completion : dict of (str, ...) to str
        How omitted state groups are completed (``Model.completion``).
    """

    system: str
    effects: frozenset[str]
    time: sp.Symbol
    omega: sp.Matrix
    v: sp.Matrix | None = None
    laws: str = "bm20"
    inertia: list[sp.Expr] = field(default_factory=list)
    kinetic_energy: sp.Expr = sp.S.Zero
    constraints: list[sp.Expr] = field(default_factory=list)
    reacting: list[str] = field(default_factory=list)
    kinematics: dict[str, tuple[sp.Matrix, sp.Matrix]] = field(default_factory=dict)
    states: list[tuple[str, tuple[sp.Symbol, ...], Rate | None]] = field(default_factory=list)
    parameters: dict[str, ParameterSpec] = field(default_factory=dict)
    references: dict[str, str] = field(default_factory=dict)
    conservative: bool = True
    has_density: bool = True
    total_momentum: bool = False
    gyrostatic_momentum_of_time: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))
    contact_vector: sp.Matrix | None = None
    potential: sp.Expr = sp.S.Zero
    integrals: dict[str, sp.Expr] = field(default_factory=dict)
    bodies: list[tuple[sp.Matrix, sp.Matrix]] = field(default_factory=list)
    free_spins: bool = True
    completion: dict[tuple[str, ...], str] = field(default_factory=dict)

    # ------------------------------------------------------------------ add_*
    def add_kinetic_energy(self, term: sp.Expr) -> None:
        """Add a term to ``T``.

        Parameters
        ----------
        term : sympy.Expr
        """
        self.kinetic_energy += term

    def add_constraint(self, expr: sp.Expr, reacts_along: str | None = None) -> None:
        """Add a velocity constraint.

        Parameters
        ----------
        expr : sympy.Expr
            Linear and homogeneous in the velocities.
        reacts_along : str, optional
            For a constraint on omega alone ``(omega, X) = 0``: the name of ``X``.
        """
        self.constraints.append(expr)
        if reacts_along is not None:
            self.reacting.append(reacts_along)

    def add_kinematics(self, name: str, symbols: sp.Matrix, rate: sp.Matrix) -> None:
        """Add a space-fixed vector and its kinematic equation.

        Parameters
        ----------
        name : str
        symbols, rate : sympy.Matrix, shape (3, 1)
        """
        self.kinematics[name] = (symbols, rate)

    def add_poisson_vector(self, name: str) -> None:
        """Add the space-fixed vector ``name`` (``X' = X x omega``) as kinematics and state.

        Parameters
        ----------
        name : str
        """
        X = vector(name, real=True)
        rate = cross(X, self.omega)
        self.add_kinematics(name, X, rate)
        self.add_state(name, tuple(X), list(rate))

    def add_frame(self) -> None:
        """Add the space-fixed horizontal axes ``alpha, beta`` (once)."""
        for name in ("alpha", "beta"):
            if name not in self.kinematics:
                self.add_poisson_vector(name)

    def add_state(self, name: str, symbols: tuple[sp.Symbol, ...], rate: Rate | None) -> None:
        """Add a state group.

        Parameters
        ----------
        name : str
        symbols : tuple of sympy.Symbol
        rate : sequence of sympy.Expr, callable or None
            Its time derivative, or a function of the reduced equations that gives it;
            None when the step that makes the Model derives it (the momentum ``M`` in
            :func:`form_model`).
        """
        if any(n == name for n, _, _ in self.states):
            raise DerivationError(f"state group {name!r} added twice")
        self.states.append((name, tuple(symbols), rate))

    def add_potential(self, term: sp.Expr) -> None:
        """Add a term to the potential energy of the external forces.

        Parameters
        ----------
        term : sympy.Expr
        """
        self.potential += term

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

    def add_integral(self, name: str, expr: sp.Expr) -> None:
        """Add a first integral, or a term to one of that name already stated.

        Parameters
        ----------
        name : str
        expr : sympy.Expr
        """
        self.integrals[name] = self.integrals.get(name, sp.S.Zero) + expr

    def state_group(self, name: str) -> sp.Matrix:
        """The symbols of state group ``name`` as a column matrix.

        Parameters
        ----------
        name : str

        Returns
        -------
        sympy.Matrix
        """
        for group, symbols, _ in self.states:
            if group == name:
                return sp.Matrix(symbols)
        raise KeyError(name)

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

    # ------------------------------------------------------------------ queries
    @property
    def vectors(self) -> dict[str, sp.Matrix]:
        """The space-fixed vectors by name."""
        return {name: X for name, (X, _) in self.kinematics.items()}

    def total_kinetic_energy(self) -> sp.Expr:
        """``T = (omega, diag(inertia) omega)/2`` plus the added terms.

        Returns
        -------
        sympy.Expr
            The kinetic energy in ``omega`` (and whatever the added terms use: ``v``,
            the space-fixed vectors, parameters, time).
        """
        rotation = (self.omega.T * sp.diag(*self.inertia) * self.omega)[0] / 2
        return rotation + self.kinetic_energy

    def geometry(self) -> tuple[PoissonGroup, ...]:
        """A frame when ``alpha, beta, gamma`` are all there, else unit vectors.

        Returns
        -------
        tuple of PoissonGroup
            One ``FRAME`` group ``(alpha, beta, gamma)``, or one ``UNIT_VECTOR`` group per
            space-fixed vector, in the order of ``kinematics``.
        """
        if {"alpha", "beta", "gamma"} <= set(self.kinematics):
            return (PoissonGroup(FRAME, ("alpha", "beta", "gamma")),)
        return tuple(PoissonGroup(UNIT_VECTOR, (name,)) for name in self.kinematics)

    def centre_velocity(self, red: ReducedEquations) -> sp.Matrix:
        """The reference-point velocity on the admissible velocities.

        Parameters
        ----------
        red : ReducedEquations
            The engine's output; its ``velocity_map`` expresses ``v`` in ``omega``.

        Returns
        -------
        sympy.Matrix, shape (3, 1)
            ``v`` with the velocity map substituted (body frame).
        """
        return sp.Matrix(self.v).subs(red.velocity_map)


def apply_effects(
    desc: MechanicalDescription, effects: Iterable[str], order: Sequence[str]
) -> None:
    """Apply the chosen effects to ``desc`` in the system's order.

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


@dataclass(frozen=True)
class RigidBodyDetails(ModelDetails):
    """Derived objects of a rolling rigid body (``Model.details`` of the ball).

    Attributes
    ----------
    reduced_equations : ReducedEquations
        The engine's output (momentum, admissible velocities ...).
    inertia : sympy.Matrix, shape (3, 3)
        ``diag(I)``, or ``I(t)`` with ``variable_inertia``.
    gyrostatic_momentum_of_time : sympy.Matrix, shape (3, 1)
        ``k(t)`` (zero without ``variable_gyrostat``).
    gyrostatic_momentum : sympy.Matrix, shape (3, 1)
        ``P0``, the velocity-independent part of the momentum.
    centre_velocity : sympy.Matrix, shape (3, 1)
        The centre's velocity in ``omega`` (body frame).
    contact_vector : sympy.Matrix or None
        From the centre to the contact point.
    laws : str
        Laws of the time-dependent parameters.
    """

    reduced_equations: ReducedEquations
    inertia: sp.Matrix
    gyrostatic_momentum_of_time: sp.Matrix
    gyrostatic_momentum: sp.Matrix
    centre_velocity: sp.Matrix
    contact_vector: sp.Matrix | None
    laws: str


def _reaction_free_integrals(
    desc: MechanicalDescription, P: sp.Matrix, P_name: str, frame: bool
) -> list[tuple[str, sp.Expr]]:
    """``(P, P)`` and ``(P, X)``: the momentum is fixed in space (``P' = P x omega``);
    a reaction torque along ``X`` leaves only the projections on the other axes."""
    vectors = desc.vectors
    reacting = set(desc.reacting)
    out: list[tuple[str, sp.Expr]] = []
    if not reacting:
        out.append((f"({P_name},{P_name})", sp.expand(dot(P, P))))
    elif not frame:  # (P - (P, X) X)^2; with a frame it is a sum of the ones below
        name = "".join(f"-({P_name},{x})^2" for x in sorted(reacting))
        value = dot(P, P) - sum((dot(P, vectors[x]) ** 2 for x in sorted(reacting)), sp.S.Zero)
        out.append((f"({P_name},{P_name}){name}", sp.expand(value)))
    for name in ("gamma", "alpha", "beta") if frame else tuple(vectors):
        if name not in reacting:
            out.append((f"({P_name},{name})", sp.expand(dot(P, vectors[name]))))
    return out


def form_model(desc: MechanicalDescription, parameter_order: Sequence[str]) -> Model:
    """Derive the Model of a rolling rigid body from its description.

    Parameters
    ----------
    desc : MechanicalDescription
        A base description with its effects applied; state ``M`` (rate None) first.
    parameter_order : sequence of str
        Order of the parameter groups in the model (every declared group must be named).

    Returns
    -------
    Model

    Raises
    ------
    DerivationError
        From the engine, for a parameter group not in ``parameter_order``, or from the
        Model's own validation.
    """
    t, omega = desc.time, desc.omega
    M = vector("M", real=True)
    kinematics = desc.kinematics
    red = lagrange_dalembert(
        RigidBodyDescription(
            omega=omega,
            v=desc.v,
            kinetic_energy=desc.total_kinetic_energy(),
            constraints=list(desc.constraints),
            kinematics=kinematics,
            time=t,
        )
    )

    # --- phase space ----------------------------------------------------------------
    geometry = desc.geometry()
    frame = geometry[0].kind == FRAME
    vectors = desc.vectors
    constraints = [c for g in geometry for c in g.constraints(vectors)]
    gens = [s for g in geometry for n in g.names for s in vectors[n]]
    ideal = ConstraintIdeal(constraints, gens)

    # --- omega from the momentum (structured inverse on the phase space) -----------
    if desc.total_momentum:
        # State: the total momentum P = II omega + k(t) (BM20-2.2). Its rate is the
        # engine's d/dt (G^T dT/dq) = M' + P0', written as P x omega + remainder.
        P0 = red.gyrostatic_momentum
        rate = red.momentum_rate + P0.applyfunc(lambda e: _time_derivative(e, kinematics, t))
        P_of_omega = red.inertia_operator * omega + P0
        remainder = (rate - cross(P_of_omega, omega)).applyfunc(
            lambda e: sp.factor_terms(sp.expand(e))
        )
        rhs_M = cross(M, omega) + remainder
        M_kinetic = M - P0  # = II omega
    else:
        rhs_M, remainder = red.euler_poincare_form(M)
        M_kinetic = M
    structured = red.structured_inverse(ideal)
    if structured is None:  # pragma: no cover - the rolling bodies here have the structure
        raise DerivationError("the inertia operator has no structured (Woodbury) inverse")
    aux: list[tuple[sp.Symbol, sp.Expr]] = []
    A, U = structured.A, structured.U
    X = structured.X()
    k = U.shape[1]
    Z = (
        sp.Matrix(sp.symbols(f"Z1:{k + 1}", real=True))
        if k > 1
        else sp.Matrix([sp.Symbol("Z", real=True)])
    )
    Zval = (
        X.LUsolve(U.T * A * M_kinetic) if k > 1 else sp.Matrix([(U.T * A * M_kinetic)[0] / X[0, 0]])
    )
    aux += [(Z[i], Zval[i]) for i in range(k)]
    omega_val = A * (M_kinetic + U * Z)
    density = X.det() ** sp.Rational(-1, 2)
    # Invertible change of parameters used by exact identity checks: A_i = 1/J_ii
    # (the paper's A = (I + D Id)^-1) keeps numerators small. With BM20's I(t) the
    # A_i depend on time through sin(Omega t): the verifier evaluates the forward map
    # once it has drawn that point of the circle. Undefined functions I_i(t) (generic
    # laws: no parameter I) are left alone: a substitution would lose their derivatives.
    reparametrisation = None
    if "I" in desc.parameters:
        Iv = desc.parameters["I"].symbols
        A_syms = sp.symbols("A1:4", positive=True)
        reparametrisation = Reparametrisation(
            forward={A_syms[i]: 1 / structured.J[i, i] for i in range(3)},
            inverse={
                Iv[i]: sp.solve(structured.J[i, i] * A_syms[i] - 1, Iv[i])[0] for i in range(3)
            },
        )
    mu_aux: list[tuple[sp.Symbol, sp.Expr]] = []
    if red.omega_multipliers:
        # Multipliers of the constraints on omega alone (no twist, the straight line),
        # eliminated from d/dt (C omega) = 0: the flow keeps C omega constant everywhere,
        # and the model's phase space is its zero level (an invariant relation).
        reaction = red.omega_constraints.T * sp.Matrix(red.omega_multipliers)
        rate = rhs_M - reaction  # the momentum rate without the reaction
        if desc.total_momentum:  # the state includes k(t): II omega = M - P0
            rate -= red.gyrostatic_momentum.applyfunc(lambda e: _time_derivative(e, kinematics, t))
        mu_values = red.multiplier_solution(rate, structured.apply_inverse)
        mu_aux = [(mu, mu_values[mu]) for mu in red.omega_multipliers]
        # The reduced flow keeps C omega constant everywhere. On its zero level the
        # ball's density times det(C II^-1 C^T)^(1/2) satisfies Liouville's equation
        # (no twist: rho ~ (gamma, A gamma)^(1/2) / (D^-1 - (gamma, A gamma)); proved by
        # the claims MODEL:...density), so rho dM dgamma / d(C omega) is invariant.
        # With two such constraints (no twist and the line) the proof does not finish in
        # reasonable time, so no density is shipped for that combination.
        C = red.omega_constraints
        density = None
        if C.shape[0] == 1:
            S = (C * structured.apply_inverse(C.T))[0, 0]
            density = sp.sqrt(sp.together(S)) * X.det() ** sp.Rational(-1, 2)
    if not desc.has_density:
        density = None
    aux += [(omega[i], omega_val[i]) for i in range(3)]
    aux += mu_aux

    # --- state and right-hand side ----------------------------------------------------
    state_groups = []
    rhs: list[sp.Expr] = []
    for name, symbols, state_rate in desc.states:
        state_groups.append((name, symbols))
        if state_rate is None:
            rhs += list(rhs_M)
        elif callable(state_rate):
            rhs += list(state_rate(red))
        else:
            rhs += list(state_rate)

    # --- parameters, in the system's order -------------------------------------------
    unknown = [n for n in desc.parameters if n not in parameter_order]
    if unknown:
        raise DerivationError(
            f"parameter groups {unknown} are not in the system's PARAMETER_ORDER: add them"
        )
    specs = tuple(desc.parameters[n] for n in parameter_order if n in desc.parameters)

    # --- invariants shipped with the model -------------------------------------------
    # momentum fixed in space: P' = P x omega (with the total momentum it is the state)
    P0 = red.gyrostatic_momentum
    P = M if desc.total_momentum else M + P0
    P_name = "M" if desc.total_momentum or P0.is_zero_matrix else "M+K"
    integrals: list[tuple[str, sp.Expr]] = []
    if desc.conservative:
        # the parameters do work when they change: no energy integral (BM20-2.6)
        integrals.append(("H", red.energy))
    integrals += _reaction_free_integrals(desc, P, P_name, frame)
    if frame:
        alpha, beta, gamma = (vectors[n] for n in ("alpha", "beta", "gamma"))
        integrals += [
            ("(alpha,alpha)", dot(alpha, alpha)),
            ("(beta,beta)", dot(beta, beta)),
            ("(alpha,beta)", dot(alpha, beta)),
            ("(gamma,alpha)", dot(gamma, alpha)),
            ("(gamma,beta)", dot(gamma, beta)),
        ]
    # the constraints on omega alone: invariant relations, zero on the phase space
    relations = tuple(
        (f"(omega,{name})", dot(omega, vectors[name])) for name in sorted(set(desc.reacting))
    )
    integrals += relations
    integrals.append(("(gamma,gamma)", dot(vectors["gamma"], vectors["gamma"])))
    integrals += list(desc.integrals.items())  # stated by the system or an effect

    references = dict(desc.references)
    if density is None:
        references.pop("density", None)
    return Model(
        system=desc.system,
        effects=desc.effects,
        time=t,
        state_groups=tuple(state_groups),
        parameters=specs,
        aux=tuple(aux),
        rhs=tuple(rhs),
        constraints=tuple(constraints),
        geometry=geometry,
        integrals=tuple(integrals),
        density=density,
        omega=omega,
        # the state M as a function of omega (it includes k(t) with the total momentum)
        momentum_of_omega=red.inertia_operator * omega
        + (P0 if desc.total_momentum else sp.zeros(3, 1)),
        inertia_operator=red.inertia_operator,
        structured_inverse=structured,
        euler_poincare_remainder=remainder,
        # constraints on omega alone, kept by the flow (zero on the phase space); the
        # verifier samples them by solving for the momentum, which they are linear in
        invariant_relations=relations,
        relation_unknowns=tuple(M),
        completion=tuple(desc.completion.items()),
        reparametrisation=reparametrisation,
        details=RigidBodyDetails(
            reduced_equations=red,
            inertia=sp.diag(*desc.inertia),
            gyrostatic_momentum_of_time=desc.gyrostatic_momentum_of_time,
            gyrostatic_momentum=P0,
            centre_velocity=desc.centre_velocity(red),
            contact_vector=desc.contact_vector,
            laws=desc.laws,
        ),
        references=references,
    )
