"""Lagrange–d'Alembert (Ferrers) equations of a rigid body in body-frame quasi-velocities.

The body is described by its kinetic energy ``T(omega, v)`` in the body frame (``omega``
angular velocity, ``v`` velocity of the reference point, normally the centre of mass),
velocity constraints linear and homogeneous in ``(omega, v)`` whose coefficients depend on
vectors fixed in space (``gamma`` ...), and the kinematic equations of those vectors.

With constraint matrix ``Phi`` (``Phi (omega, v) = 0``) and multipliers ``lambda`` the
equations of motion in the body frame (Kirchhoff form) are::

    d/dt dT/domega = dT/domega x omega + dT/dv x v + N + Phi_omega^T lambda
    d/dt dT/dv     = dT/dv x omega              + F + Phi_v^T lambda

The engine solves the constraints for ``v = V omega``; the columns of
``G = d(omega, V omega)/d omega`` span the admissible velocities, so ``G^T Phi^T = 0``
and projecting on them eliminates the multipliers exactly. The projected momentum
``P = G^T dT/d(omega, v)`` is the momentum about the contact point of the rolling
papers; it splits into ``M = II omega`` (``II`` the constrained inertia operator) and a
velocity-independent part ``P0`` (the gyrostatic momentum), and::

    d/dt P = G^T f + (dG/dt)^T p,      M' = d/dt P - d/dt P0.

``omega`` as a function of ``M`` is found by a structured (Woodbury) inversion when
``II`` equals a constant matrix plus a low-rank term in the space-fixed vectors on the
phase space (``II = J - D gamma ⊗ gamma`` for the ball, giving ``omega = A (M + Z gamma)``
with ``A = J^-1``, BKM12-3), and by a generic solve otherwise.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp

from .algebra import ConstraintIdeal
from .errors import DerivationError
from .vectors import cross

__all__ = ["RigidBodyDescription", "ReducedEquations", "lagrange_dalembert", "StructuredInverse"]


@dataclass
class RigidBodyDescription:
    """Mechanical description of a constrained rigid body (input of the engine).

    Parameters
    ----------
    omega, v : sympy.Matrix, shape (3, 1)
        Quasi-velocity symbols: angular velocity and reference-point velocity, body frame.
    kinetic_energy : sympy.Expr
        ``T(omega, v)``, quadratic plus (optionally) linear in the velocities; the
        coefficients may depend on parameters, on the space-fixed vectors and on time.
    constraints : sequence of sympy.Expr
        Velocity constraints, linear and homogeneous in ``(omega, v)``.
    kinematics : mapping of str to (sympy.Matrix, sympy.Matrix)
        ``name -> (X, dX/dt)``: the space-fixed vectors the coefficients depend on and
        their kinematic equations (Poisson: ``X' = X x omega``).
    time : sympy.Symbol
    force, torque : sympy.Matrix, shape (3, 1), optional
        External force at the reference point and torque about it (body frame).
    """

    omega: sp.Matrix
    v: sp.Matrix
    kinetic_energy: sp.Expr
    constraints: Sequence[sp.Expr]
    kinematics: Mapping[str, tuple[sp.Matrix, sp.Matrix]]
    time: sp.Symbol
    force: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))
    torque: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))


@dataclass
class StructuredInverse:
    """``II = J + U C U^T`` on the phase space and the Woodbury form of ``II^-1``.

    ``omega = A (M + U Z)``, ``A = J^-1``, ``Z = X^-1 U^T A M``, ``X = -(C^-1 + U^T A U)``.
    For the Chaplygin ball ``J = I + D Id``, ``U = gamma``, ``C = -D``,
    ``X = D^-1 - (gamma, A gamma)``.
    """

    J: sp.Matrix
    U: sp.Matrix
    C: sp.Matrix

    @property
    def A(self) -> sp.Matrix:
        if self.J.is_diagonal():
            return sp.diag(*[1 / self.J[i, i] for i in range(self.J.shape[0])])
        return self.J.inv()

    def X(self) -> sp.Matrix:
        """The capacitance matrix ``X = -(C^-1 + U^T A U)`` of the Woodbury form.

        Returns
        -------
        sympy.Matrix, shape (k, k)
            ``k`` the number of columns of ``U``; for the ball ``D^-1 - (gamma, A gamma)``
            (BKM12-3).
        """
        return -(self.C.inv() + self.U.T * self.A * self.U)

    def apply_inverse(self, u: sp.Matrix) -> sp.Matrix:
        """``II^-1 u = A (u + U X^-1 U^T A u)`` on the phase space.

        Parameters
        ----------
        u : sympy.Matrix, shape (3, 1)
            The vector to multiply by ``II^-1`` (a momentum, say).

        Returns
        -------
        sympy.Matrix, shape (3, 1)
            ``II^-1 u`` by the Woodbury identity (for the ball ``omega = A (M + Z gamma)``
            when ``u = M``, BKM12-3).

        References
        ----------
        BKM12-3.
        """
        X = self.X()
        w = self.U.T * self.A * u
        z = X.LUsolve(w) if X.shape[0] > 1 else sp.Matrix([w[0] / X[0, 0]])
        return self.A * (u + self.U * z)


@dataclass
class ReducedEquations:
    """Output of :func:`lagrange_dalembert`.

    Attributes
    ----------
    with_multipliers : sympy.Matrix, shape (6, 1)
        Residuals of the unreduced equations in ``omega', v'`` and the multipliers.
    multipliers : tuple of sympy.Symbol
    velocity_map : dict
        ``v_i -> expression in omega`` solved from the constraints.
    admissible : sympy.Matrix, shape (6, 3)
        ``G``: the admissible quasi-velocities are ``G omega``.
    momentum : sympy.Matrix, shape (3, 1)
        ``P = G^T dT/d(omega, v)`` as a function of ``omega``.
    inertia_operator : sympy.Matrix, shape (3, 3)
        ``II = dP/domega`` (``M = II omega``).
    gyrostatic_momentum : sympy.Matrix, shape (3, 1)
        ``P0 = P - II omega`` (velocity independent).
    momentum_rate : sympy.Matrix, shape (3, 1)
        ``M'`` in terms of ``omega``, the space-fixed vectors and time.
    energy : sympy.Expr
        Generalised energy ``(q, dT/dq) - T`` on the admissible velocities (an integral
        only for homogeneous constraints and ``T`` free of time).
    velocity_shift : sympy.Matrix, shape (3, 1)
        ``v`` at ``omega = 0``: the affine part of the constraints (zero unless the
        support moves, e.g. a rotating plane: ``v + omega x r = Omega gamma x rho``).
    omega_shift : sympy.Matrix or None
        ``c`` of the constraints on omega alone, ``C omega + c = 0`` (zero but for a
        prescribed rate: no twist relative to a turntable, ``(omega, gamma) = Omega``).
    """

    with_multipliers: sp.Matrix
    multipliers: tuple[sp.Symbol, ...]
    velocity_map: dict[sp.Symbol, sp.Expr]
    admissible: sp.Matrix
    momentum: sp.Matrix
    inertia_operator: sp.Matrix
    gyrostatic_momentum: sp.Matrix
    momentum_rate: sp.Matrix
    energy: sp.Expr
    omega: sp.Matrix
    kinematics: Mapping[str, tuple[sp.Matrix, sp.Matrix]]
    omega_constraints: sp.Matrix | None = None
    omega_multipliers: tuple[sp.Symbol, ...] = ()
    time: sp.Symbol | None = None
    velocity_shift: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))
    omega_shift: sp.Matrix | None = None

    def multiplier_solution(
        self, rate: sp.Matrix, apply_inverse: Callable[[sp.Matrix], sp.Matrix]
    ) -> dict[sp.Symbol, sp.Expr]:
        """Multipliers of the constraints on omega alone, ``C omega + c = 0``.

        They follow from ``d/dt (C omega + c) = 0`` with ``omega' = II^-1 (M' - II'
        omega)``::

            mu = -(C II^-1 C^T)^-1 [C' omega + c' + C II^-1 (F - II' omega)],

        where ``M' = F + C^T mu`` (``c`` is zero but for a prescribed rate: no twist
        relative to a turntable).

        Parameters
        ----------
        rate : sympy.Matrix, shape (3, 1)
            ``F``: the momentum rate without the multiplier terms (any variables).
        apply_inverse : callable of sympy.Matrix to sympy.Matrix
            ``u -> II^-1 u`` for columns of shape (3, 1) (a structured inverse, say).

        Returns
        -------
        dict of sympy.Symbol to sympy.Expr
            ``mu_j -> expression``; empty when there are no constraints on omega alone.
        """
        C = self.omega_constraints
        if C is None:
            return {}
        t = self.time
        C_dot = C.applyfunc(lambda e: _time_derivative(e, self.kinematics, t))
        II_dot = self.inertia_operator.applyfunc(lambda e: _time_derivative(e, self.kinematics, t))
        rhs = C_dot * self.omega + C * apply_inverse(rate - II_dot * self.omega)
        if self.omega_shift is not None:
            rhs += self.omega_shift.applyfunc(lambda e: _time_derivative(e, self.kinematics, t))
        S = C * sp.Matrix.hstack(*[apply_inverse(C.row(j).T) for j in range(C.shape[0])])
        sol = -(S.LUsolve(rhs)) if S.shape[0] > 1 else sp.Matrix([-rhs[0] / S[0, 0]])
        return dict(zip(self.omega_multipliers, sol, strict=True))

    def euler_poincare_form(self, M: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
        """``M'`` written as ``(M + P0) x omega + R``; returns ``(rhs, R)``.

        ``R`` is what is left after the (expanded, exact) subtraction; it is zero for
        the Chaplygin ball with or without a gyrostat. ``M`` are the state symbols.

        Parameters
        ----------
        M : sympy.Matrix, shape (3, 1)
            The momentum state symbols.

        Returns
        -------
        rhs : sympy.Matrix, shape (3, 1)
            ``(M + P0) x omega + R`` (still in ``omega``, the space-fixed vectors and time).
        R : sympy.Matrix, shape (3, 1)
            The remainder ``M' - (II omega + P0) x omega``, expanded and factored termwise.
        """
        P_of_omega = self.inertia_operator * self.omega + self.gyrostatic_momentum
        remainder = (self.momentum_rate - cross(P_of_omega, self.omega)).applyfunc(
            lambda e: sp.factor_terms(sp.expand(e))
        )
        rhs = cross(M + self.gyrostatic_momentum, self.omega) + remainder
        return rhs, remainder

    def structured_inverse(
        self, ideal: ConstraintIdeal, max_rank: int = 3
    ) -> StructuredInverse | None:
        """Find ``II = J + U C U^T`` modulo the phase-space constraints.

        ``J`` is constant (free of the space-fixed vectors), ``U`` holds the space-fixed
        vectors that occur in ``II``; ``J`` and ``C`` are found by matching the
        coefficients of the normal forms. Returns None when no such split exists.

        Parameters
        ----------
        ideal : ConstraintIdeal
            The phase-space constraints (``(gamma, gamma) = 1`` ...) the match is taken
            modulo.
        max_rank : int, default 3
            Largest number of space-fixed vectors ``U`` may hold.

        Returns
        -------
        StructuredInverse or None
            ``J`` (3, 3), ``U`` (3, k), ``C`` (k, k); None when ``II`` depends on no
            space-fixed vector, on more than ``max_rank`` of them, when the linear match
            has no solution, when ``J`` still depends on a space-fixed vector, or when
            ``J`` or ``C`` is singular.
        """
        II = self.inertia_operator
        config = [X for X, _ in self.kinematics.values() if set(X) & II.free_symbols]
        if not config or len(config) > max_rank:
            return None
        k = len(config)
        U = sp.Matrix.hstack(*config)
        j = sp.symbols("_j0:9")
        c = sp.symbols(f"_c0:{k * k}")
        J = sp.Matrix(3, 3, lambda a, b: j[3 * min(a, b) + max(a, b)])
        C = sp.Matrix(k, k, lambda a, b: c[k * min(a, b) + max(a, b)])
        unknowns = sorted(set(J) | set(C), key=sp.default_sort_key)
        equations = []
        for a, b in itertools.product(range(3), repeat=2):
            if a <= b:
                equations += ideal.coefficient_equations(II[a, b] - J[a, b] - (U * C * U.T)[a, b])
        solutions = sp.linsolve(equations, unknowns)
        if not solutions:
            return None
        (sol,) = solutions
        values = dict(zip(unknowns, sol, strict=True))
        free = set().union(*(sp.sympify(v).free_symbols for v in sol)) & set(unknowns)
        values = {u: sp.sympify(v).subs({f: 0 for f in free}) for u, v in values.items()}
        J_val = J.subs(values).applyfunc(sp.factor)
        C_val = C.subs(values).applyfunc(sp.factor)
        if J_val.free_symbols & set().union(*(set(X) for X in config)):
            return None
        if C_val.det() == 0 or J_val.det() == 0:
            return None
        return StructuredInverse(J=J_val, U=U, C=C_val)


def _time_derivative(expr, kinematics, time):
    """Total time derivative of an expression in the space-fixed vectors and time."""
    out = sp.diff(expr, time)
    for X, Xdot in kinematics.values():
        for i in range(3):
            if X[i] in expr.free_symbols:
                out += sp.diff(expr, X[i]) * Xdot[i]
    return out


def lagrange_dalembert(desc: RigidBodyDescription) -> ReducedEquations:
    """Derive the reduced equations of a constrained rigid body.

    Parameters
    ----------
    desc : RigidBodyDescription

    Returns
    -------
    ReducedEquations

    Raises
    ------
    DerivationError
        When a constraint is not linear and homogeneous in the velocities, or when the
        constraints that involve ``v`` do not determine it. Constraints on ``omega`` alone
        (no twist, rolling along a line) keep their multipliers ``mu`` in
        ``momentum_rate`` (``+ C^T mu``); :meth:`ReducedEquations.multiplier_solution`
        eliminates them.
    """
    omega, v, t = desc.omega, desc.v, desc.time
    q = list(omega) + list(v)
    T = sp.sympify(desc.kinetic_energy)

    Phi = sp.Matrix([[sp.diff(c, qi) for qi in q] for c in desc.constraints])
    for row, c in enumerate(desc.constraints):
        shift = sp.expand(c - (Phi.row(row) * sp.Matrix(q))[0])
        # constraints may be affine (a moving support): the shift a function of time and
        # configuration (no twist relative to a turntable: (omega, gamma) = Omega(t))
        affine_ok = not (shift.free_symbols & set(q))
        if (shift != 0 and not affine_ok) or any(s in Phi.row(row).free_symbols for s in q):
            raise DerivationError(
                f"constraint {c} is not linear in (omega, v) (homogeneous for omega alone)"
            )

    # Equations with undetermined multipliers (kept for inspection and documentation).
    lam = sp.symbols(f"lambda1:{len(desc.constraints) + 1}")
    omega_dot = sp.Matrix(sp.symbols("omega_dot1:4"))
    v_dot = sp.Matrix(sp.symbols("v_dot1:4"))
    p = sp.Matrix([sp.diff(T, qi) for qi in q])
    p_omega, p_v = p[:3, :], p[3:, :]

    def d_dt(expr):
        out = _time_derivative(expr, desc.kinematics, t)
        for i in range(3):
            out += sp.diff(expr, omega[i]) * omega_dot[i] + sp.diff(expr, v[i]) * v_dot[i]
        return out

    f_omega = cross(p_omega, omega) + cross(p_v, v) + desc.torque
    f_v = cross(p_v, omega) + desc.force
    reaction = Phi.T * sp.Matrix(lam) if lam else sp.zeros(6, 1)
    with_multipliers = p.applyfunc(d_dt) - sp.Matrix.vstack(f_omega, f_v) - reaction

    # Constraints on omega alone (no twist, rolling along a line) keep their multipliers;
    # the others are solved for the reference-point velocity.
    omega_rows = [c for c in desc.constraints if not (set(v) & sp.sympify(c).free_symbols)]
    v_rows = [c for c in desc.constraints if set(v) & sp.sympify(c).free_symbols]
    sol = sp.solve(v_rows, list(v), dict=True)
    if len(sol) != 1 or set(sol[0]) != set(v):
        raise DerivationError(
            "the constraints do not determine the reference-point velocity v uniquely"
        )
    vmap = {vi: sp.expand(sol[0][vi]) for vi in v}
    residual = [sp.expand(c.subs(vmap)) for c in v_rows]
    if any(r != 0 for r in residual):
        raise DerivationError(
            "after solving for v, constraints involving v remain on omega: write them as "
            "constraints on omega alone"
        )
    C = sp.Matrix([[sp.diff(c, w) for w in omega] for c in omega_rows]) if omega_rows else None
    omega_shift = None if C is None else (sp.Matrix(omega_rows) - C * omega).applyfunc(sp.expand)
    mu = sp.symbols(f"mu1:{len(omega_rows) + 1}", real=True) if omega_rows else ()
    v_of_omega = v.subs(vmap)
    shift = v_of_omega.xreplace(dict.fromkeys(omega, 0)).applyfunc(sp.expand)
    # virtual velocities: the homogeneous part (the support's motion is prescribed)
    G = sp.Matrix.vstack(sp.eye(3), v_of_omega.jacobian(omega))
    if any(s in G.free_symbols for s in omega):
        raise DerivationError("the admissible velocities are not linear in omega")

    on = lambda e: sp.expand(e.subs(vmap))  # noqa: E731  (restrict to admissible velocities)
    p_adm = p.applyfunc(on)
    f_adm = sp.Matrix.vstack(f_omega, f_v).applyfunc(on)
    P = (G.T * p_adm).applyfunc(sp.expand)
    II = P.jacobian(omega).applyfunc(sp.expand)
    P0 = (P - II * omega).applyfunc(sp.expand)
    if P0.free_symbols & set(omega):
        raise DerivationError("the projected momentum is not affine in omega")
    G_dot = G.applyfunc(lambda e: _time_derivative(e, desc.kinematics, t))
    P_rate = (G.T * f_adm + G_dot.T * p_adm).applyfunc(sp.expand)
    P0_rate = P0.applyfunc(lambda e: _time_derivative(e, desc.kinematics, t))
    M_rate = (P_rate - P0_rate).applyfunc(sp.expand)
    if C is not None:
        # G^T Phi^T lambda leaves exactly the reaction of the constraints on omega alone
        M_rate = M_rate + C.T * sp.Matrix(mu)
    # Generalised (Jacobi) energy sum q dT/dq - T = T2 - T0: a gyrostatic term linear in
    # the velocities does no work and drops out.
    energy = sp.expand((sp.Matrix(q).T * p)[0] - T).subs(vmap)
    energy = sp.expand(energy)

    return ReducedEquations(
        with_multipliers=with_multipliers,
        multipliers=tuple(lam),
        velocity_map=vmap,
        admissible=G,
        momentum=P,
        inertia_operator=II,
        gyrostatic_momentum=P0,
        momentum_rate=M_rate,
        energy=energy,
        omega=omega,
        kinematics=desc.kinematics,
        omega_constraints=C,
        omega_multipliers=tuple(mu),
        time=t,
        velocity_shift=shift,
        omega_shift=omega_shift,
    )
