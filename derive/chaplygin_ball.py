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

from .algebra import ConstraintIdeal
from .effects import parse_effects
from .engine import RigidBodyDescription, lagrange_dalembert
from .errors import UserInputError
from .geometry import FRAME, UNIT_VECTOR, PoissonGroup
from .model import Model, ParameterSpec
from .vectors import cross, dot, vector

__all__ = ["build_chaplygin_ball", "SUPPORTED_EFFECTS", "NAME", "DESCRIPTION", "GENERATED_VARIANTS"]

NAME = "chaplygin_ball"
DESCRIPTION = (
    "balanced dynamically asymmetric ball rolling without slipping on a plane (BKM12 §1.1, K01 §2)"
)
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


def _time_derivative(expr: sp.Expr, kinematics, t: sp.Symbol) -> sp.Expr:
    """Total time derivative of an expression in time and the space-fixed vectors."""
    out = sp.diff(expr, t)
    for X, Xdot in kinematics.values():
        for i in range(3):
            if X[i] in expr.free_symbols:
                out += sp.diff(expr, X[i]) * Xdot[i]
    return out


def build_chaplygin_ball(effects: Iterable[str] | str | None = (), *, _laws: str = "bm20") -> Model:
    """Derive the Chaplygin ball model.

    Parameters
    ----------
    effects : iterable of str or str, optional
        Any of ``"gyrostat"``, ``"contact_point"``, ``"variable_inertia"`` and
        ``"variable_gyrostat"`` (not together with ``"gyrostat"``).
    _laws : {"bm20", "generic"}, optional
        Private (verification): ``"generic"`` makes ``I(t)`` and ``k(t)`` undefined
        functions of time instead of BM20's laws (3.4)-(3.5), so that an identity proved on
        that model holds for every law. Such a model is never emitted.

    Returns
    -------
    Model
        State ``M, gamma`` (+ ``alpha, beta, x, y`` with ``contact_point``), parameters
        ``I1, I2, I3, D`` (+ ``b`` with ``contact_point``, ``K1, K2, K3`` with ``gyrostat``
        or ``variable_gyrostat``, ``J_off, delta`` with ``variable_inertia``, ``Omega`` with
        either variable effect). With ``variable_gyrostat`` the state ``M`` is BM20's total
        momentum (it includes ``k(t)``).

    Raises
    ------
    UserInputError
        ``variable_gyrostat`` together with ``gyrostat`` (one gyrostatic momentum: give
        either a constant one or a periodic one), or an unknown effect.

    Examples
    --------
    >>> model = build_chaplygin_ball()
    >>> model.state_names
    ('M1', 'M2', 'M3', 'gamma1', 'gamma2', 'gamma3')
    >>> model.param_names
    ('I1', 'I2', 'I3', 'D')
    """
    effects = parse_effects(effects, SUPPORTED_EFFECTS)
    gyro = "gyrostat" in effects
    contact = "contact_point" in effects
    var_inertia = "variable_inertia" in effects
    var_gyro = "variable_gyrostat" in effects
    rubber = "rubber" in effects
    line = "straight_line" in effects
    if gyro and var_gyro:
        raise UserInputError(
            "effects 'gyrostat' (constant gyrostatic momentum K) and 'variable_gyrostat' "
            "(k(t) = K sin(Omega t), BM20-3.5) exclude each other: choose one of them"
        )
    if _laws not in LAWS:
        raise ValueError(f"unknown parameter laws {_laws!r}; valid: {', '.join(LAWS)}")
    generic = _laws == "generic"

    t = sp.Symbol("t", real=True)
    Iv = vector("I", positive=True)
    D, b = sp.symbols("D b", positive=True)
    K = vector("K", real=True)
    omega = vector("omega", real=True)
    v = vector("v", real=True)
    M = vector("M", real=True)
    gamma = vector("gamma", real=True)
    alpha = vector("alpha", real=True)
    beta = vector("beta", real=True)
    m = D / b**2  # D = m b^2
    J_off, delta = sp.symbols("J_off delta", real=True)
    Omega = sp.Symbol("Omega", positive=True)

    # --- time-dependent parameters (BM20-3.4, BM20-3.5) ----------------------------
    inertia: list[sp.Expr] = list(Iv)
    if var_inertia and generic:
        inertia = [sp.Function(f"I{i}", positive=True)(t) for i in (1, 2, 3)]
    elif var_inertia:  # a pair of masses moving along C x2 (BM20-3.4)
        offset = (J_off + delta * sp.sin(Omega * t)) ** 2
        inertia = [Iv[0] + offset, Iv[1], Iv[2] + offset]
    k_of_t = sp.zeros(3, 1)
    if var_gyro and generic:
        k_of_t = sp.Matrix([sp.Function(f"k{i}", real=True)(t) for i in (1, 2, 3)])
    elif var_gyro:  # rotors (BM20-3.5)
        k_of_t = K * sp.sin(Omega * t)

    # --- mechanical description --------------------------------------------------
    T = (omega.T * sp.diag(*inertia) * omega)[0] / 2 + m * dot(v, v) / 2
    if gyro:
        T += dot(K, omega)
    if var_gyro:
        T += dot(k_of_t, omega)
    r = -b * gamma  # centre -> contact point (K01-2.5)
    kinematics = {"gamma": (gamma, cross(gamma, omega))}
    frame = contact or line
    if frame:
        kinematics["alpha"] = (alpha, cross(alpha, omega))
        kinematics["beta"] = (beta, cross(beta, omega))
    # no slip; no twist (rubber, BKM12 §3); rolling along the space-fixed line alpha
    # (Veselovs' constraint (omega, alpha) = 0, BKM12-57)
    extra_constraints = [dot(omega, gamma)] * rubber + [dot(omega, alpha)] * line
    desc = RigidBodyDescription(
        omega=omega,
        v=v,
        kinetic_energy=T,
        constraints=list(v + cross(omega, r)) + extra_constraints,
        kinematics=kinematics,
        time=t,
    )
    red = lagrange_dalembert(desc)

    # --- phase space ----------------------------------------------------------------
    geometry = (
        (PoissonGroup(FRAME, ("alpha", "beta", "gamma")),)
        if frame
        else (PoissonGroup(UNIT_VECTOR, ("gamma",)),)
    )
    vectors = {"gamma": gamma, "alpha": alpha, "beta": beta}
    constraints = [c for g in geometry for c in g.constraints(vectors)]
    gens = [s for g in geometry for n in g.names for s in vectors[n]]
    ideal = ConstraintIdeal(constraints, gens)

    # --- omega from the momentum (structured inverse on the phase space) -----------
    if var_gyro:
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
    aux: list[tuple[sp.Symbol, sp.Expr]] = []
    mu_aux: list[tuple[sp.Symbol, sp.Expr]] = []
    if structured is not None:
        A, U = structured.A, structured.U
        X = structured.X()
        k = U.shape[1]
        Z = (
            sp.Matrix(sp.symbols(f"Z1:{k + 1}", real=True))
            if k > 1
            else sp.Matrix([sp.Symbol("Z", real=True)])
        )
        Zval = (
            X.LUsolve(U.T * A * M_kinetic)
            if k > 1
            else sp.Matrix([(U.T * A * M_kinetic)[0] / X[0, 0]])
        )
        aux += [(Z[i], Zval[i]) for i in range(k)]
        omega_val = A * (M_kinetic + U * Z)
        density = X.det() ** sp.Rational(-1, 2)
        # Invertible change of parameters used by exact identity checks: A_i = 1/J_ii
        # (the paper's A = (I + D Id)^-1) keeps numerators small. With BM20's I(t) the
        # A_i depend on time through sin(Omega t): the verifier evaluates the forward map
        # once it has drawn that point of the circle. Undefined functions I_i(t) (generic
        # laws) are left alone: a substitution would lose their derivatives.
        A_syms = sp.symbols("A1:4", positive=True)
        reparametrisation = (
            None
            if generic and var_inertia
            else {
                "forward": {A_syms[i]: 1 / structured.J[i, i] for i in range(3)},
                "inverse": {
                    Iv[i]: sp.solve(structured.J[i, i] * A_syms[i] - 1, Iv[i])[0] for i in range(3)
                },
            }
        )
    else:  # pragma: no cover - the ball always has the structure
        omega_val = red.inertia_operator.LUsolve(M_kinetic)
        density = red.inertia_operator.det() ** sp.Rational(-1, 2)
        reparametrisation = None
    if red.omega_multipliers:
        # Multipliers of the constraints on omega alone (no twist, the straight line),
        # eliminated from d/dt (C omega) = 0: the flow keeps C omega constant everywhere,
        # and the model's phase space is its zero level (an invariant relation).
        reaction = red.omega_constraints.T * sp.Matrix(red.omega_multipliers)
        rate = rhs_M - reaction  # the momentum rate without the reaction
        if var_gyro:  # the state includes k(t): II omega = M - P0
            rate -= red.gyrostatic_momentum.applyfunc(lambda e: _time_derivative(e, kinematics, t))
        if structured is None:  # pragma: no cover - the ball always has the structure
            raise AssertionError("the multiplier elimination needs the structured inverse")
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
    if var_inertia:
        # X = D^-1 - (gamma, A(t) gamma) depends on time: det(X)^-1/2 is not invariant
        # (its explicit time derivative is left over), and no density is known.
        density = None
    aux += [(omega[i], omega_val[i]) for i in range(3)]
    aux += mu_aux

    # --- state and right-hand side ----------------------------------------------------
    state_groups: list[tuple[str, tuple[sp.Symbol, ...]]] = [
        ("M", tuple(M)),
        ("gamma", tuple(gamma)),
    ]
    rhs: list[sp.Expr] = list(rhs_M) + list(kinematics["gamma"][1])
    centre_velocity = sp.Matrix(v).subs(red.velocity_map)
    if frame:
        state_groups += [("alpha", tuple(alpha)), ("beta", tuple(beta))]
        rhs += list(kinematics["alpha"][1]) + list(kinematics["beta"][1])
    if contact:
        x, y = sp.symbols("x y", real=True)
        state_groups += [("x", (x,)), ("y", (y,))]
        # The contact point lies under the centre: its horizontal coordinates move with
        # the centre velocity projected on the space-fixed axes (BKM12-6).
        rhs += [sp.expand(dot(centre_velocity, alpha)), sp.expand(dot(centre_velocity, beta))]

    # --- parameters: exactly the symbols the equations use ---------------------------
    specs = []
    if not var_inertia:
        specs.append(
            ParameterSpec(
                "I", tuple(Iv), "positive", "central principal moments of inertia I1, I2, I3"
            )
        )
    elif not generic:
        specs.append(
            ParameterSpec(
                "I",
                tuple(Iv),
                "positive",
                "constant parts I1, I2, I3 of the principal moments of inertia "
                "I(t) = diag(I1 + (J_off + delta sin(Omega t))^2, I2, I3 + (...)^2)",
            )
        )
    specs.append(ParameterSpec("D", (D,), "positive", "D = m b^2 (mass times squared radius)"))
    if contact:
        specs.append(ParameterSpec("b", (b,), "positive", "ball radius"))
    if var_inertia and not generic:
        specs.append(
            ParameterSpec(
                "J_off", (J_off,), "real", "offset J of the moving mass pair in I(t) (BM20-3.4)"
            )
        )
        specs.append(
            ParameterSpec(
                "delta", (delta,), "real", "amplitude of the mass pair's motion (BM20-3.4)"
            )
        )
    if gyro:
        specs.append(
            ParameterSpec("K", tuple(K), "real", "constant gyrostatic momentum K1, K2, K3")
        )
    if var_gyro and not generic:
        specs.append(
            ParameterSpec(
                "K",
                tuple(K),
                "real",
                "amplitude K of the gyrostatic momentum k(t) = K sin(Omega t) (BM20-3.5)",
            )
        )
    if (var_inertia or var_gyro) and not generic:
        specs.append(
            ParameterSpec(
                "Omega",
                (Omega,),
                "positive",
                "angular frequency of the periodic parameters (BM20-3.4, 3.5)",
            )
        )

    # --- invariants shipped with the model -------------------------------------------
    # momentum fixed in space: P' = P x omega (with variable_gyrostat it is the state)
    P = M if var_gyro else M + red.gyrostatic_momentum
    P_name = "M+K" if gyro else "M"
    integrals: list[tuple[str, sp.Expr]] = []
    if not (var_inertia or var_gyro):
        # the parameters do work when they change: no energy integral (BM20-2.6)
        integrals.append(("H", red.energy))
    # The reaction torque of a constraint on omega alone lies along its space-fixed
    # vector (gamma: no twist; alpha: the straight line); the projections of P on the
    # other space-fixed axes stay constant, and so does (P, P) without such a reaction.
    reacting = ({"gamma"} if rubber else set()) | ({"alpha"} if line else set())
    if not reacting:
        integrals.append((f"({P_name},{P_name})", sp.expand(dot(P, P))))
    elif rubber and not frame:  # (P - (P, gamma) gamma)^2
        integrals.append(
            (f"({P_name},{P_name})-({P_name},gamma)^2", sp.expand(dot(P, P) - dot(P, gamma) ** 2))
        )
    for name in ("gamma", "alpha", "beta") if frame else ("gamma",):
        if name not in reacting:
            integrals.append((f"({P_name},{name})", sp.expand(dot(P, vectors[name]))))
    if frame:
        integrals += [
            ("(alpha,alpha)", dot(alpha, alpha)),
            ("(beta,beta)", dot(beta, beta)),
            ("(alpha,beta)", dot(alpha, beta)),
            ("(gamma,alpha)", dot(gamma, alpha)),
            ("(gamma,beta)", dot(gamma, beta)),
        ]
    # the constraints on omega alone: invariant relations, zero on the phase space
    relations = [(f"(omega,{name})", dot(omega, vectors[name])) for name in sorted(reacting)]
    integrals += relations
    integrals.append(("(gamma,gamma)", dot(gamma, gamma)))

    model = Model(
        system="chaplygin_ball",
        effects=effects,
        time=t,
        state_groups=tuple(state_groups),
        parameters=tuple(specs),
        aux=tuple(aux),
        rhs=tuple(rhs),
        constraints=tuple(constraints),
        geometry=geometry,
        integrals=tuple(integrals),
        density=density,
        definitions={
            "omega": omega,
            # the state M as a function of omega (it includes k(t) with variable_gyrostat)
            "momentum_of_omega": red.inertia_operator * omega
            + (red.gyrostatic_momentum if var_gyro else sp.zeros(3, 1)),
            "inertia_operator": red.inertia_operator,
            "inertia": sp.diag(*inertia),
            "gyrostatic_momentum_of_time": k_of_t,
            "laws": _laws,
            "gyrostatic_momentum": red.gyrostatic_momentum,
            "centre_velocity": centre_velocity,
            "contact_vector": r,
            "euler_poincare_remainder": remainder,
            "structured_inverse": structured,
            "reduced_equations": red,
            "mass": m,
            "reparametrisation": reparametrisation,
            # constraints on omega alone, kept by the flow (zero on the phase space); the
            # verifier samples them by solving for the momentum, which they are linear in
            "invariant_relations": tuple(relations),
            # what the verifier solves relations (and level sets of a claim) for
            "relation_unknowns": tuple(M),
        },
        references={
            "momentum": "BKM12-1",
            "equations": (
                "BM20-2.5" if var_inertia or var_gyro else "K01-4.1" if gyro else "BKM12-2"
            ),
            "omega": "BM20-2.5" if var_inertia or var_gyro else "BKM12-3",
            **({} if density is None else {"density": "BKM12-4"}),
            "integrals": (
                "BM20-2.5int" if var_inertia or var_gyro else "K01-4.2" if gyro else "BKM12-5"
            ),
            "contact_point": "BKM12-6",
            **({"straight_line": "BKM12-57"} if line else {}),
            **({"rubber": "BKM12 §3 (rubber ball)"} if rubber else {}),
        },
    )
    declared = set(model.params) | set(model.state) | set(model.aux_symbols) | {t}
    used = set().union(*(sp.sympify(e).free_symbols for e in (*model.rhs, *(e for _, e in aux))))
    if not used <= declared:  # pragma: no cover - guards the builder itself
        raise AssertionError(f"undeclared symbols in the model: {used - declared}")
    unused = set(model.params) - set().union(*(e.free_symbols for e in model.rhs_expanded))
    if unused:  # pragma: no cover
        raise AssertionError(f"parameters that no equation uses: {unused}")
    return model


BUILDER = build_chaplygin_ball
