"""Ferrers equations of several rigid bodies in mutual rolling contact (body-frame form).

A *reference* body (angular velocity ``omega``, body frame) and ``N`` dynamically
symmetric bodies (balls: kinetic energy ``lambda_k (omega_k, omega_k)/2``, invariant
under rotations) whose angular velocities ``omega_k`` are written in the reference
body's frame. All centres are fixed in space. Velocity constraints are linear and
homogeneous in ``q = (omega, omega_1, ..., omega_N)``, ``Phi(X) q = 0``, with
coefficients that depend on space-fixed vectors ``X`` (``X' = X x omega``).

Every angular momentum ``p_j = dT/dq_j`` is a space-fixed vector up to the reaction
torques; seen from the frame that rotates with ``omega`` the Ferrers equations are::

    d/dt p_j = p_j x omega + (Phi_j^T Lambda)_j,     j = 0 .. N,

(BKM12-29 and, with extra multipliers, BKM12-40). The admissible velocities are
``q = G(X) s``: the constraints are solved for the balls' angular velocities in terms
of ``omega`` and of the *extra quasi-velocities* the caller declares (the balls' spins
``nu_k = (omega_k, n_k)`` about the contact normals when the constraints leave them
free). ``Phi G = 0`` on the phase space, so projecting on the columns of ``G``
eliminates every multiplier::

    d/dt (G^T p) = G^T (p x omega) + (dG/dt)^T p.

The rows of ``P = G^T p`` that belong to ``omega`` are the momentum of the reduced
system, those that belong to an extra quasi-velocity its conjugate momentum.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp

from .algebra import ConstraintIdeal
from .errors import DerivationError
from .vectors import cross

__all__ = ["MultiBodyDescription", "MultiBodyReduction", "ferrers_multibody"]


@dataclass
class MultiBodyDescription:
    """Mechanical description of a reference body and balls rolling on it.

    Parameters
    ----------
    omega : sympy.Matrix, shape (3, 1)
        Angular velocity of the reference body (its own frame).
    bodies : mapping of str to sympy.Matrix
        Angular velocities of the other bodies, components in the reference frame. Their
        kinetic energy must be rotation invariant (``lambda (w, w)/2``).
    kinetic_energy : sympy.Expr
        ``T(omega, omega_k)``: quadratic (plus linear terms in ``omega``, a gyrostat) with
        coefficients free of the space-fixed vectors.
    constraints : sequence of sympy.Expr
        Linear homogeneous in all angular velocities.
    kinematics : mapping of str to (sympy.Matrix, sympy.Matrix)
        ``name -> (X, X')`` of the space-fixed vectors the constraints depend on.
    phase_space : ConstraintIdeal
        Polynomial relations of those vectors (unit length ...).
    time : sympy.Symbol
    quasi_velocities : sequence of (sympy.Symbol, sympy.Expr), optional
        Extra independent quasi-velocities ``s_i = expression`` (linear in the
        velocities), for the directions the constraints leave free.
    """

    omega: sp.Matrix
    bodies: Mapping[str, sp.Matrix]
    kinetic_energy: sp.Expr
    constraints: Sequence[sp.Expr]
    kinematics: Mapping[str, tuple[sp.Matrix, sp.Matrix]]
    phase_space: ConstraintIdeal
    time: sp.Symbol
    quasi_velocities: Sequence[tuple[sp.Symbol, sp.Expr]] = field(default_factory=tuple)


@dataclass
class MultiBodyReduction:
    """Output of :func:`ferrers_multibody` (all entries reduced modulo the phase space).

    Attributes
    ----------
    velocity_map : dict
        ``omega_k component -> expression in omega and the extra quasi-velocities``.
    independent : tuple of sympy.Symbol
        ``s = (omega1, omega2, omega3, s_1, ...)``.
    admissible : sympy.Matrix
        ``G`` (``q = G s``), rows in the order of ``q``.
    constraint_matrix : sympy.Matrix
        ``Phi``.
    momentum : sympy.Matrix, shape (3, 1)
        ``P`` rows of ``omega``: the reduced momentum (``II omega + P0``).
    inertia_operator, gyrostatic_momentum : sympy.Matrix
        ``II = dP/domega`` and ``P0 = P - II omega``.
    momentum_rate : sympy.Matrix, shape (3, 1)
        ``P'`` (multipliers eliminated) in the velocities and the space-fixed vectors.
    quasi_momentum, quasi_momentum_rate : sympy.Matrix
        The rows of the extra quasi-velocities and their rates.
    energy : sympy.Expr
        ``(q, dT/dq) - T`` on the admissible velocities.
    """

    description: MultiBodyDescription
    velocity_map: dict[sp.Symbol, sp.Expr]
    independent: tuple[sp.Symbol, ...]
    admissible: sp.Matrix
    constraint_matrix: sp.Matrix
    momentum: sp.Matrix
    inertia_operator: sp.Matrix
    gyrostatic_momentum: sp.Matrix
    momentum_rate: sp.Matrix
    quasi_momentum: sp.Matrix
    quasi_momentum_rate: sp.Matrix
    energy: sp.Expr

    def reduce(self, expr: sp.Expr) -> sp.Expr:
        """Normal form of a polynomial (or constant-denominator fraction) on the phase space.

        Parameters
        ----------
        expr : sympy.Expr
            An expression in the space-fixed vectors (and anything else).

        Returns
        -------
        sympy.Expr
            Its normal form modulo the phase-space constraints among the generators that
            occur in it (expanded when none occur); equal to ``expr`` on the phase space.

        Raises
        ------
        DerivationError
            If ``expr`` is a fraction whose denominator does not reduce to a nonzero
            constant on the phase space.
        """
        return _reduce(expr, self.description.phase_space)

    def reaction(
        self,
        body: str,
        omega_rate: sp.Matrix,
        quasi_rates: Sequence[sp.Expr | float] | None = None,
    ) -> sp.Matrix:
        """Reaction torque on ``body`` along a motion with ``omega' = omega_rate``.

        ``(Phi^T Lambda)_body = d/dt p_body - p_body x omega`` on the admissible velocities,
        with ``q' = G s' + G' s`` (``s'`` = ``omega_rate`` and ``quasi_rates``, default 0).

        Parameters
        ----------
        body : str
            ``"omega"`` (the reference body) or a key of the description's bodies.
        omega_rate : sympy.Matrix, shape (3, 1)
            ``omega'`` along the motion.
        quasi_rates : sequence of sympy.Expr, optional
            Rates of the extra quasi-velocities (``len(independent) - 3`` of them); None
            means all zero.

        Returns
        -------
        sympy.Matrix, shape (3, 1)
            The reaction torque ``(Phi^T Lambda)_body``, each entry reduced on the phase
            space (:meth:`reduce`).

        Raises
        ------
        ValueError
            If ``body`` is neither ``"omega"`` nor a body of the description.

        References
        ----------
        BKM12-29, BKM12-40.
        """
        d = self.description
        q, vel = _velocities(d)
        extra = list(quasi_rates) if quasi_rates is not None else [0] * (len(self.independent) - 3)
        s_rate = sp.Matrix(list(omega_rate) + extra)
        s = sp.Matrix(self.independent)
        G = self.admissible
        G_dot = G.applyfunc(lambda e: _time_derivative(e, d.kinematics))
        q_rate = G * s_rate + G_dot * s
        on = {qi: e for qi, e in zip(q, G * s, strict=True)}
        p = sp.Matrix([sp.diff(d.kinetic_energy, qi) for qi in q])
        H = p.jacobian(q)  # constant coefficients (checked)
        p_rate = H * q_rate
        sl = slice(3 * vel.index(body), 3 * vel.index(body) + 3)
        out = p_rate[sl, :] - cross(p[sl, :].xreplace(on), d.omega)
        return out.applyfunc(self.reduce)


def _velocities(d: MultiBodyDescription) -> tuple[list[sp.Symbol], list[str]]:
    q = list(d.omega)
    names = ["omega"]
    for name, w in d.bodies.items():
        q += list(w)
        names.append(name)
    return q, names


def _time_derivative(expr, kinematics) -> sp.Expr:
    out = sp.S.Zero
    for X, Xdot in kinematics.values():
        for i in range(3):
            if X[i] in expr.free_symbols:
                out += sp.diff(expr, X[i]) * Xdot[i]
    return out


def _reduce(expr: sp.Expr, ideal: ConstraintIdeal) -> sp.Expr:
    """Normal form modulo the ideal of ``num/den`` when ``den`` reduces to a constant.

    Only the constraints among the generators that occur are used (a sub-ideal: the
    result is equal on the phase space, and each ball's terms reduce on their own).
    """
    expr = sp.sympify(expr)
    present = expr.free_symbols & set(ideal.gens)
    if not present:
        return sp.expand(expr)
    local = ideal.restricted_to(present)
    expanded = sp.expand(expr)
    if expanded.is_polynomial(*present):
        return local.reduce(expanded)
    num, den = sp.fraction(sp.together(expr))
    den_r = local.reduce(den)
    if den_r.free_symbols & set(ideal.gens) or den_r == 0:
        raise DerivationError(f"denominator {den} does not reduce to a constant on the phase space")
    return sp.expand(local.reduce(num) / den_r)


def ferrers_multibody(desc: MultiBodyDescription) -> MultiBodyReduction:
    """Reduce the Ferrers equations of a body with rolling balls (multipliers eliminated).

    Parameters
    ----------
    desc : MultiBodyDescription

    Returns
    -------
    MultiBodyReduction

    Raises
    ------
    DerivationError
        A constraint that is not linear and homogeneous; a ball whose kinetic energy is
        not rotation invariant; constraints that do not determine the balls' angular
        velocities from ``omega`` and the extra quasi-velocities; ``Phi G != 0``.
    """
    q, names = _velocities(desc)
    T = sp.expand(desc.kinetic_energy)
    config = set().union(*(set(X) for X, _ in desc.kinematics.values()))
    if T.free_symbols & config:
        raise DerivationError("the kinetic energy must not depend on the space-fixed vectors")
    # --- the Ferrers form needs rotation-invariant balls ------------------------------
    H = sp.hessian(T, q)
    for b, name in enumerate(names[1:], start=1):
        blk = H[3 * b : 3 * b + 3, :]
        own = blk[:, 3 * b : 3 * b + 3]
        other = blk.copy()
        other[:, 3 * b : 3 * b + 3] = sp.zeros(3, 3)
        if other != sp.zeros(3, len(q)) or own != own[0, 0] * sp.eye(3):
            raise DerivationError(
                f"body {name!r}: its kinetic energy must be lambda (w, w)/2 (a dynamically "
                "symmetric ball, no coupling to the other bodies)"
            )
        lin = [sp.diff(T, s).subs({x: 0 for x in q}) for s in desc.bodies[name]]
        if any(e != 0 for e in lin):
            raise DerivationError(f"body {name!r}: no linear terms in its angular velocity")
    Phi = sp.Matrix([[sp.diff(c, qi) for qi in q] for c in desc.constraints])
    for row, c in enumerate(desc.constraints):
        if sp.expand(c - (Phi.row(row) * sp.Matrix(q))[0]) != 0 or Phi.row(row).free_symbols & set(
            q
        ):
            raise DerivationError(f"constraint {c} is not linear and homogeneous in the velocities")

    # --- admissible velocities: solve ball by ball -------------------------------------
    extra = [s for s, _ in desc.quasi_velocities]
    equations = list(desc.constraints) + [e - s for s, e in desc.quasi_velocities]
    vmap: dict[sp.Symbol, sp.Expr] = {}
    for name in names[1:]:
        unknowns = list(desc.bodies[name])
        rows = [e for e in equations if set(unknowns) & sp.sympify(e).free_symbols]
        if any(set(e.free_symbols) & (set(q[3:]) - set(unknowns)) for e in rows):
            raise DerivationError(f"constraints couple body {name!r} to another ball")
        sol = sp.linsolve(rows, unknowns)
        if not sol or len(sol) != 1:
            raise DerivationError(f"no solution for the angular velocity of {name!r}")
        (values,) = sol
        if set().union(*(sp.sympify(v).free_symbols for v in values)) & set(unknowns):
            raise DerivationError(
                f"the constraints leave the angular velocity of {name!r} undetermined: declare "
                "the free directions as extra quasi-velocities"
            )
        for u, v in zip(unknowns, values, strict=True):
            vmap[u] = _reduce(v, desc.phase_space)
    s = list(desc.omega) + extra
    q_adm = sp.Matrix([vmap.get(qi, qi) for qi in q])
    G = q_adm.jacobian(s)
    if set().union(*(e.free_symbols for e in G)) & set(s):
        raise DerivationError("the admissible velocities are not linear in omega")
    residual = (Phi * G).applyfunc(lambda e: _reduce(e, desc.phase_space))
    if residual != sp.zeros(*residual.shape):
        raise DerivationError("the solved velocities violate the constraints (Phi G != 0)")

    # --- projection -----------------------------------------------------------------------
    on = dict(zip(q, q_adm, strict=True))
    p = sp.Matrix([sp.diff(T, qi) for qi in q])
    p_adm = p.xreplace(on)
    F = sp.Matrix.vstack(
        *[cross(p_adm[3 * b : 3 * b + 3, :], desc.omega) for b in range(len(names))]
    )
    G_dot = G.applyfunc(lambda e: _time_derivative(e, desc.kinematics))
    red = lambda e: _reduce(e, desc.phase_space)  # noqa: E731
    # body by body: each ball's terms involve only its own space-fixed vectors
    P = sp.zeros(len(s), 1)
    P_rate = sp.zeros(len(s), 1)
    for b in range(len(names)):
        rows = slice(3 * b, 3 * b + 3)
        Gb, Gb_dot, pb = G[rows, :], G_dot[rows, :], p_adm[rows, :]
        P += (Gb.T * pb).applyfunc(red)
        P_rate += (Gb.T * F[rows, :] + Gb_dot.T * pb).applyfunc(red)
    P = P.applyfunc(sp.expand)
    P_rate = P_rate.applyfunc(sp.expand)
    P_omega, P_extra = P[:3, :], P[3:, :]
    if P_omega.free_symbols & set(extra):
        raise DerivationError("the reduced momentum depends on the extra quasi-velocities")
    II = P_omega.jacobian(desc.omega).applyfunc(sp.expand)
    P0 = (P_omega - II * desc.omega).applyfunc(sp.expand)
    energy = red(sp.expand((sp.Matrix(q).T * p)[0] - T).xreplace(on))
    return MultiBodyReduction(
        description=desc,
        velocity_map=vmap,
        independent=tuple(s),
        admissible=G,
        constraint_matrix=Phi,
        momentum=P_omega,
        inertia_operator=II,
        gyrostatic_momentum=P0,
        momentum_rate=P_rate[:3, :],
        quasi_momentum=P_extra,
        quasi_momentum_rate=P_rate[3:, :],
        energy=energy,
    )
