"""The reduction stage of a rolling rigid body in body-frame quasi-velocities.

:class:`RigidBodyReduction` is the stage of the Chaplygin ball (:mod:`.chaplygin_ball`)
and of any rigid body whose description gives ``T(omega, v)``, velocity constraints and
Poisson vectors: the Lagrange–d'Alembert engine (:func:`~.engine.lagrange_dalembert`)
derives the momentum and its rate, the momentum is inverted by the structured (Woodbury)
inverse on the phase space, the multipliers of constraints on omega alone are
eliminated, and the integrals are collected — all from the description's data:

* the energy is an integral when ``T`` and the constraints do not depend on time
  explicitly (time-dependent parameters do work when they change, BM20-2.6);
* the momentum fixed in space ``P = M + (what the state leaves out of the gyrostatic
  momentum)`` gives ``(P, P)`` and ``(P, X)``, except along the reactions of the
  constraints on omega alone;
* the density ``det(X)^-1/2`` of the Woodbury form (times ``det(C II^-1 C^T)^1/2`` with
  one constraint on omega alone) is shipped when it does not depend on time explicitly.

References
----------
BKM12-1..7, K01-2.1..2.6, K01-4.1, K01-4.2, BM20-2.2..2.7.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import sympy as sp

from .algebra import ConstraintIdeal, seeded_factor
from .description import MechanicalDescription, Reduced
from .engine import (
    ReducedEquations,
    RigidBodyDescription,
    StructuredInverse,
    _time_derivative,
    lagrange_dalembert,
)
from .errors import DerivationError
from .geometry import FRAME
from .model import ModelDetails, Reparametrisation
from .vectors import cross, dot

__all__ = ["RigidBodyReduction", "RigidBodyDetails", "moment_reparametrisation"]


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
        The momentum the state includes, ``k(t)`` (zero without ``variable_gyrostat``).
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


def moment_reparametrisation(
    J: sp.Matrix, moments: tuple[sp.Symbol, ...]
) -> Reparametrisation | None:
    """``A_i = 1/J_ii`` and the principal moments solved for in the ``A_i``.

    Used by exact identity checks: ``A_i`` (the paper's ``A = (I + D Id)^-1``) keep the
    numerators small. With BM20's ``I(t)`` the ``A_i`` depend on time through
    ``sin(Omega t)``: the verifier evaluates the forward map once it has drawn that point
    of the circle.

    Parameters
    ----------
    J : sympy.Matrix, shape (3, 3)
        The constant part of a structured inverse (``J = I + D Id`` for the ball).
    moments : tuple of sympy.Symbol
        The principal-moment parameters ``I1, I2, I3``; empty when the moments are
        functions of time (a substitution would lose their derivatives).

    Returns
    -------
    Reparametrisation or None
        None without moments.
    """
    if not moments:
        return None
    A_syms = sp.symbols("A1:4", positive=True)
    return Reparametrisation(
        forward={A_syms[i]: 1 / J[i, i] for i in range(3)},
        inverse={moments[i]: sp.solve(J[i, i] * A_syms[i] - 1, moments[i])[0] for i in range(3)},
    )


def _reaction_free_integrals(
    desc: MechanicalDescription, P: sp.Matrix, P_name: str, frame: bool
) -> list[tuple[str, sp.Expr]]:
    """``(P, P)`` and ``(P, X)``: the momentum is fixed in space (``P' = P x omega``);
    a reaction torque along ``X`` leaves only the projections on the other axes."""
    vectors = desc.vectors
    reacting = set(desc.reacting)
    # (P, X) needs X fixed in space too: not the normal of a sphere the body rolls on
    turning = {n for n in vectors if n not in _space_fixed(desc)}
    out: list[tuple[str, sp.Expr]] = []
    if not reacting:
        out.append((f"({P_name},{P_name})", sp.expand(dot(P, P))))
    elif not frame:  # (P - (P, X) X)^2; with a frame it is a sum of the ones below
        name = "".join(f"-({P_name},{x})^2" for x in sorted(reacting))
        value = dot(P, P) - sum((dot(P, vectors[x]) ** 2 for x in sorted(reacting)), sp.S.Zero)
        out.append((f"({P_name},{P_name}){name}", sp.expand(value)))
    frame_names = ("gamma", "alpha", "beta") if frame and "zeta" not in vectors else ()
    for name in frame_names or tuple(vectors):
        if name not in reacting and name not in turning:
            out.append((f"({P_name},{name})", sp.expand(dot(P, vectors[name]))))
    return out


def _space_fixed(desc: MechanicalDescription) -> set[str]:
    """The vectors whose rate is Poisson's ``X' = X x omega`` (fixed in space)."""
    return {
        name
        for name, (X, rate) in desc.kinematics.items()
        if (sp.Matrix(rate) - cross(X, desc.omega)).applyfunc(sp.expand).is_zero_matrix
    }


def _density_applies(desc: MechanicalDescription, red: ReducedEquations, density) -> bool:
    """Whether ``det(X)^-1/2`` solves Liouville's equation here: it is derived for a fixed
    support (no affine constraint), Poisson's equations of every vector (on a sphere the
    normal turns at another rate) and an autonomous structure (an explicit time dependence,
    I(t) of BM20-3.4, leaves its time derivative over); chaplygin.discover searches
    otherwise."""
    if density is None or not red.velocity_shift.is_zero_matrix:
        return False
    if red.omega_shift is not None and not red.omega_shift.is_zero_matrix:
        return False
    return not (set(desc.kinematics) - _space_fixed(desc)) and not density.has(desc.time)


def _geometric_integrals(
    desc: MechanicalDescription, frame: bool
) -> tuple[list[tuple[str, sp.Expr]], list[tuple[str, sp.Expr]]]:
    """The frame's relations, and ``(X, X)`` of every unit vector (shipped after the
    relations)."""
    vectors = desc.vectors
    before: list[tuple[str, sp.Expr]] = []
    if frame:  # alpha, beta and the third: gamma, or on a fixed sphere the vertical zeta
        third = next(g.names[2] for g in desc.geometry() if g.kind == FRAME)
        alpha, beta, normal = (vectors[n] for n in ("alpha", "beta", third))
        before = [
            ("(alpha,alpha)", dot(alpha, alpha)),
            ("(beta,beta)", dot(beta, beta)),
            ("(alpha,beta)", dot(alpha, beta)),
            (f"({third},alpha)", dot(normal, alpha)),
            (f"({third},beta)", dot(normal, beta)),
        ]
    units = [n for group in desc.geometry() if group.kind != FRAME for n in group.names]
    return before, [(f"({n},{n})", dot(vectors[n], vectors[n])) for n in units or ["gamma"]]


@dataclass(frozen=True)
class RigidBodyReduction:
    """Lagrange–d'Alembert in body-frame quasi-velocities; the momentum state inverted.

    Parameters
    ----------
    momentum : str
        The state group of the momentum about the contact point (its rate is derived).
    gyrostatic : str
        Name of the gyrostatic momentum in the integrals' names (``(M+K,gamma)``) when
        the state leaves it out.
    """

    momentum: str = "M"
    gyrostatic: str = "K"

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """Derive the equations, ``omega`` of the momentum, the integrals and the density.

        Parameters
        ----------
        desc : MechanicalDescription
            A rigid body (``inertia``, ``v``, constraints, Poisson vectors ``gamma`` ...)
            with the state group :attr:`momentum` (rate None).

        Returns
        -------
        Reduced

        Raises
        ------
        DerivationError
            From the engine; for a potential or further bodies (not derived here); when
            the inertia operator has no structured inverse on the phase space.
        """
        desc.refuse("rigid-body (body frame)", ("bodies", "phase_space"))
        t, omega = desc.time, desc.omega
        kinematics = {**desc.kinematics, **desc.positions}
        potential = sp.sympify(desc.potential)
        red = lagrange_dalembert(
            RigidBodyDescription(
                omega=omega,
                v=desc.v,
                kinetic_energy=desc.total_kinetic_energy(),
                constraints=list(desc.constraints),
                kinematics=kinematics,
                time=t,
                torque=potential_torque(potential, desc),
            )
        )
        geometry = desc.geometry()
        frame = geometry[0].kind == FRAME
        vectors = desc.vectors
        constraints = [c for g in geometry for c in g.constraints(vectors)]
        gens = [s for g in geometry for n in g.names for s in vectors[n]]
        ideal = ConstraintIdeal(constraints, gens)
        structured = red.structured_inverse(ideal)

        M = desc.state_group(self.momentum)
        Q = desc.momentum_in_state  # the state is II omega + Q
        Q_rate = Q.applyfunc(lambda e: _time_derivative(e, kinematics, t))
        P0 = red.gyrostatic_momentum
        outside = (P0 - Q).applyfunc(sp.expand)  # the fixed momentum is P = M + outside
        # M' = d/dt (G^T dT/dq) - P0' + Q', written as (M + outside) x omega + remainder
        P_of_omega = red.inertia_operator * omega + P0
        remainder = (red.momentum_rate + Q_rate - cross(P_of_omega, omega)).applyfunc(
            lambda e: sp.factor_terms(sp.expand(e))
        )
        rhs_M = cross(M + outside, omega) + remainder

        if structured is not None:
            aux, X = _omega_of_momentum(structured, M - Q, omega)
            density = X.det() ** sp.Rational(-1, 2)
            apply_inverse = structured.apply_inverse
        else:  # a body whose inertia operator is not J + U C U^T (a displaced centre of mass)
            aux, apply_inverse = _omega_by_adjugate(red.inertia_operator, M - Q, omega)
            density = None  # not derived here: chaplygin.discover searches for one
        if red.omega_multipliers:
            mu_aux, mu_density = _eliminate_multipliers(
                red, rhs_M - Q_rate, apply_inverse, None if structured is None else X
            )
            aux += mu_aux
            density = None if structured is None else mu_density
        density = density if _density_applies(desc, red, density) else None

        P_name = self.momentum if outside.is_zero_matrix else f"{self.momentum}+{self.gyrostatic}"
        integrals: list[tuple[str, sp.Expr]] = []
        scleronomic = not any(
            sp.sympify(e).has(t) for e in (desc.total_kinetic_energy(), *desc.constraints)
        )
        # a moving support (affine constraints) does work too
        scleronomic = scleronomic and red.velocity_shift.is_zero_matrix
        twist = red.omega_shift
        scleronomic = scleronomic and (twist is None or twist.is_zero_matrix)
        if scleronomic:  # the parameters do work when they change: no energy (BM20-2.6)
            integrals.append(("H", sp.expand(red.energy + potential)))
        # P' = P x omega (+ reactions along the reacting vectors) makes (P, P) and (P, X)
        # integrals; a torque of the potential or of a displaced centre of mass breaks it
        # (with a prescribed K(t) the fixed momentum's rate is M' + K')
        outside_rate = outside.applyfunc(lambda e: _time_derivative(e, kinematics, t))
        unreacted = (remainder + outside_rate).xreplace({mu: 0 for mu in red.omega_multipliers})
        if all(ideal.is_zero(e) for e in unreacted):
            integrals += _reaction_free_integrals(desc, M + outside, P_name, frame)
        frame_relations, unit = _geometric_integrals(desc, frame)
        integrals += frame_relations
        integrals += sorted(desc.invariant_relations.items())  # zero on the phase space
        integrals += unit
        return Reduced(
            rates={self.momentum: list(rhs_M)},
            aux=aux,
            integrals=integrals,
            density=density,
            constraints=constraints,
            geometry=geometry,
            velocity_map=red.velocity_map,
            # the relations are linear in the momentum (no twist) or in a position (rho
            # horizontal on a rotating plane): both are projected onto them when sampled
            relation_unknowns=tuple(M) + tuple(s for X, _ in desc.positions.values() for s in X),
            omega=omega,
            momentum_of_omega=red.inertia_operator * omega + Q,
            inertia_operator=red.inertia_operator,
            structured_inverse=structured,
            euler_poincare_remainder=remainder,
            reparametrisation=(
                None if structured is None else moment_reparametrisation(structured.J, desc.moments)
            ),
            details=RigidBodyDetails(
                reduced_equations=red,
                inertia=desc.inertia,
                gyrostatic_momentum_of_time=Q,
                gyrostatic_momentum=P0,
                centre_velocity=sp.Matrix(desc.v).subs(red.velocity_map),
                contact_vector=desc.contact_vector,
                laws=desc.laws,
            ),
        )


def _omega_of_momentum(
    structured: StructuredInverse, M_kinetic: sp.Matrix, omega: sp.Matrix
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], sp.Matrix]:
    """``omega = A (M_kinetic + U Z)``, ``Z = X^-1 U^T A M_kinetic``: the auxiliary
    definitions ``Z``, ``omega`` and the capacitance matrix ``X``."""
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
    omega_val = A * (M_kinetic + U * Z)
    aux = [(Z[i], Zval[i]) for i in range(k)] + [(omega[i], omega_val[i]) for i in range(3)]
    return aux, X


def potential_torque(potential: sp.Expr, desc: MechanicalDescription) -> sp.Matrix:
    """The torque of a potential of the configuration's unit vectors: ``sum_X s_X X x dV/dX``.

    A vector fixed in space turns as ``X' = X x omega`` (``s_X = 1``), the normal of a
    fixed sphere the body rolls on as ``X' = s X x omega`` (``s = R/(R +- b)``). Along
    every admissible virtual displacement ``delta X = s_X X x delta theta``, so ``delta V
    = (delta theta, sum_X s_X dV/dX x X)`` and the torque doing the work ``-delta V`` is
    ``sum_X s_X X x dV/dX`` (the heavy top's ``m g gamma x r_c`` for ``V = m g (r_c,
    gamma)``). Only its projection on the admissible velocities enters the equations
    (Lagrange–d'Alembert), so a potential of the sphere's normal — a function of where
    the body is — needs no force beside it.

    Parameters
    ----------
    potential : sympy.Expr
        In the unit vectors of the kinematics and the parameters.
    desc : MechanicalDescription

    Returns
    -------
    sympy.Matrix, shape (3, 1)

    Raises
    ------
    DerivationError
        When the potential depends on the velocities, the momentum, another state or time,
        or on a vector whose rate is not a multiple of Poisson's.
    """
    torque = sp.zeros(3, 1)
    if potential == 0:
        return torque
    vectors = desc.vectors
    allowed = set().union(*(set(X) for X in vectors.values()))
    others = {s for group in desc.states for s in group.symbols} - allowed
    moving = set(desc.omega) | set(desc.v if desc.v is not None else ()) | {desc.time}
    if potential.free_symbols & (others | moving):
        raise DerivationError(
            f"{desc.system}: the potential must depend on the orientation (the space-fixed "
            f"vectors {', '.join(vectors)}) and the parameters only"
        )
    for name, (X, rate) in desc.kinematics.items():
        grad = sp.Matrix([sp.diff(potential, x) for x in X])
        if grad.is_zero_matrix:
            continue
        torque += _poisson_factor(name, X, sp.Matrix(rate), desc) * cross(X, grad)
    return torque.applyfunc(sp.expand)


def _poisson_factor(name: str, X: sp.Matrix, rate: sp.Matrix, desc: MechanicalDescription):
    """``s`` with ``X' = s X x omega`` (constant in the state), or a DerivationError."""
    poisson = cross(X, desc.omega)
    s = sp.cancel(sp.expand(rate[0]) / sp.expand(poisson[0]))
    state = {x for group in desc.states for x in group.symbols} | set(desc.omega)
    rest = (rate - s * poisson).applyfunc(lambda e: sp.cancel(sp.together(e)))
    if s.free_symbols & state or not rest.is_zero_matrix:
        raise DerivationError(
            f"{desc.system}: the potential depends on {name}, whose rate is not a multiple "
            "of Poisson's (its torque is not derived)"
        )
    return s


def _omega_by_adjugate(
    II: sp.Matrix, M_kinetic: sp.Matrix, omega: sp.Matrix
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], object]:
    """``omega = adj(II) M / det(II)``: ``det(II)`` and the entries of the adjugate are
    auxiliary definitions (``Delta``, ``Adj11`` ...: functions of the configuration
    alone, so that the emitted code and its Taylor decomposition stay small); and
    ``u -> II^-1 u`` for the multipliers."""
    delta = sp.Symbol("Delta", real=True)
    det = seeded_factor(II.det())  # Wang's random points: the same path in every process
    adjugate = II.adjugate().applyfunc(sp.expand)
    symmetric = (adjugate - adjugate.T).is_zero_matrix
    names = {}
    aux = [(delta, det)]
    for i in range(3):
        for j in range(3):
            if symmetric and j < i:
                names[i, j] = names[j, i]
                continue
            if adjugate[i, j] == 0:
                names[i, j] = sp.S.Zero
                continue
            symbol = sp.Symbol(f"Adj{i + 1}{j + 1}", real=True)
            names[i, j] = symbol
            aux.append((symbol, adjugate[i, j]))
    adj = sp.Matrix(3, 3, lambda i, j: names[i, j])
    omega_val = (adj * M_kinetic).applyfunc(lambda e: sp.expand(e) / delta)
    aux += [(omega[i], omega_val[i]) for i in range(3)]

    def apply_inverse(u: sp.Matrix) -> sp.Matrix:
        return (adj * u).applyfunc(lambda e: sp.expand(e) / delta)

    return aux, apply_inverse


def _eliminate_multipliers(
    red: ReducedEquations, rate: sp.Matrix, apply_inverse, X: sp.Matrix | None
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], sp.Expr | None]:
    """Multipliers of the constraints on omega alone, and the density on their zero level.

    They are eliminated from ``d/dt (C omega) = 0``: the flow keeps ``C omega`` constant
    everywhere, and the model's phase space is its zero level (an invariant relation).
    ``rate`` is the rate of ``II omega`` with the reactions.
    """
    reaction = red.omega_constraints.T * sp.Matrix(red.omega_multipliers)
    mu_values = red.multiplier_solution(rate - reaction, apply_inverse)
    mu_aux = [(mu, mu_values[mu]) for mu in red.omega_multipliers]
    # On the zero level of C omega the ball's density times det(C II^-1 C^T)^(1/2)
    # satisfies Liouville's equation (no twist: rho ~ (gamma, A gamma)^(1/2) /
    # (D^-1 - (gamma, A gamma)); proved by the claims MODEL:...density), so
    # rho dM dgamma / d(C omega) is invariant. With two such constraints (no twist and
    # the line) it is (D^-1 - (gamma, A gamma))^-1, the density chaplygin discover finds,
    # times the square root of a first integral (claims BKM12-3rub57.*).
    C = red.omega_constraints
    if X is None:
        return mu_aux, None
    if C.shape[0] == 1:
        S = (C * apply_inverse(C.T))[0, 0]
    else:  # Leibniz's sum: Matrix.det simplifies its products (minutes for two rows)
        gram = C * sp.Matrix.hstack(*(apply_inverse(C[i, :].T) for i in range(C.shape[0])))
        S = sp.Add(
            *(
                (-1) ** sum(a > b for a, b in itertools.combinations(p, 2))
                * sp.Mul(*(gram[i, j] for i, j in enumerate(p)))
                for p in itertools.permutations(range(gram.shape[0]))
            )
        )
    return mu_aux, sp.sqrt(sp.together(S)) * X.det() ** sp.Rational(-1, 2)
