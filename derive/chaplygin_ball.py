"""The Chaplygin ball: a dynamically asymmetric, balanced ball rolling without slipping.

Built by the Lagrange–d'Alembert engine from its mechanical description: kinetic energy
``T = (omega, I omega)/2 + m (v, v)/2`` (plus ``(K, omega)`` with a gyrostat), the no-slip
constraint ``v + omega x r = 0`` with ``r = -b gamma`` from the centre to the contact
point, and the Poisson equations of the space-fixed vectors. ``D = m b^2``.

References
----------
BKM12-1..7, K01-2.1..2.6 (ball); K01-4.1, K01-4.2 (gyrostat).
"""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

from .algebra import ConstraintIdeal
from .effects import parse_effects
from .engine import RigidBodyDescription, lagrange_dalembert
from .geometry import FRAME, UNIT_VECTOR, PoissonGroup
from .model import Model, ParameterSpec
from .vectors import cross, dot, vector

__all__ = ["build_chaplygin_ball", "SUPPORTED_EFFECTS", "NAME", "DESCRIPTION", "GENERATED_VARIANTS"]

NAME = "chaplygin_ball"
DESCRIPTION = (
    "balanced dynamically asymmetric ball rolling without slipping on a plane (BKM12 §1.1, K01 §2)"
)
SUPPORTED_EFFECTS = ("gyrostat", "contact_point")
#: Effect combinations whose code is committed in generated/.
GENERATED_VARIANTS = (
    (),
    ("gyrostat",),
    ("contact_point",),
    ("contact_point", "gyrostat"),
)


def build_chaplygin_ball(effects: Iterable[str] | str | None = ()) -> Model:
    """Derive the Chaplygin ball model.

    Parameters
    ----------
    effects : iterable of str or str, optional
        Any of ``"gyrostat"`` and ``"contact_point"``.

    Returns
    -------
    Model
        State ``M, gamma`` (+ ``alpha, beta, x, y`` with ``contact_point``), parameters
        ``I1, I2, I3, D`` (+ ``b`` with ``contact_point``, ``K1, K2, K3`` with ``gyrostat``).

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

    # --- mechanical description --------------------------------------------------
    T = (omega.T * sp.diag(*Iv) * omega)[0] / 2 + m * dot(v, v) / 2
    if gyro:
        T += dot(K, omega)
    r = -b * gamma  # centre -> contact point (K01-2.5)
    kinematics = {"gamma": (gamma, cross(gamma, omega))}
    if contact:
        kinematics["alpha"] = (alpha, cross(alpha, omega))
        kinematics["beta"] = (beta, cross(beta, omega))
    desc = RigidBodyDescription(
        omega=omega,
        v=v,
        kinetic_energy=T,
        constraints=list(v + cross(omega, r)),
        kinematics=kinematics,
        time=t,
    )
    red = lagrange_dalembert(desc)

    # --- phase space ----------------------------------------------------------------
    geometry = (
        (PoissonGroup(FRAME, ("alpha", "beta", "gamma")),)
        if contact
        else (PoissonGroup(UNIT_VECTOR, ("gamma",)),)
    )
    vectors = {"gamma": gamma, "alpha": alpha, "beta": beta}
    constraints = [c for g in geometry for c in g.constraints(vectors)]
    gens = [s for g in geometry for n in g.names for s in vectors[n]]
    ideal = ConstraintIdeal(constraints, gens)

    # --- omega from the momentum (structured inverse on the phase space) -----------
    rhs_M, remainder = red.euler_poincare_form(M)
    structured = red.structured_inverse(ideal)
    aux: list[tuple[sp.Symbol, sp.Expr]] = []
    if structured is not None:
        A, U = structured.A, structured.U
        X = structured.X()
        k = U.shape[1]
        Z = (
            sp.Matrix(sp.symbols(f"Z1:{k + 1}", real=True))
            if k > 1
            else sp.Matrix([sp.Symbol("Z", real=True)])
        )
        Zval = X.LUsolve(U.T * A * M) if k > 1 else sp.Matrix([(U.T * A * M)[0] / X[0, 0]])
        aux += [(Z[i], Zval[i]) for i in range(k)]
        omega_val = A * (M + U * Z)
        density = X.det() ** sp.Rational(-1, 2)
        # Invertible change of parameters used by exact identity checks: A_i = 1/J_ii
        # (the paper's A = (I + D Id)^-1) keeps numerators small.
        A_syms = sp.symbols("A1:4", positive=True)
        reparametrisation = {
            "forward": {A_syms[i]: 1 / structured.J[i, i] for i in range(3)},
            "inverse": {
                Iv[i]: sp.solve(structured.J[i, i] * A_syms[i] - 1, Iv[i])[0] for i in range(3)
            },
        }
    else:  # pragma: no cover - the ball always has the structure
        omega_val = red.inertia_operator.LUsolve(M)
        density = red.inertia_operator.det() ** sp.Rational(-1, 2)
        reparametrisation = None
    aux += [(omega[i], omega_val[i]) for i in range(3)]

    # --- state and right-hand side ----------------------------------------------------
    state_groups: list[tuple[str, tuple[sp.Symbol, ...]]] = [
        ("M", tuple(M)),
        ("gamma", tuple(gamma)),
    ]
    rhs: list[sp.Expr] = list(rhs_M) + list(kinematics["gamma"][1])
    centre_velocity = sp.Matrix(v).subs(red.velocity_map)
    if contact:
        x, y = sp.symbols("x y", real=True)
        state_groups += [("alpha", tuple(alpha)), ("beta", tuple(beta)), ("x", (x,)), ("y", (y,))]
        rhs += list(kinematics["alpha"][1]) + list(kinematics["beta"][1])
        # The contact point lies under the centre: its horizontal coordinates move with
        # the centre velocity projected on the space-fixed axes (BKM12-6).
        rhs += [sp.expand(dot(centre_velocity, alpha)), sp.expand(dot(centre_velocity, beta))]

    # --- parameters: exactly the symbols the equations use ---------------------------
    specs = [
        ParameterSpec(
            "I", tuple(Iv), "positive", "central principal moments of inertia I1, I2, I3"
        ),
        ParameterSpec("D", (D,), "positive", "D = m b^2 (mass times squared radius)"),
    ]
    if contact:
        specs.append(ParameterSpec("b", (b,), "positive", "ball radius"))
    if gyro:
        specs.append(
            ParameterSpec("K", tuple(K), "real", "constant gyrostatic momentum K1, K2, K3")
        )

    # --- invariants shipped with the model -------------------------------------------
    P = M + red.gyrostatic_momentum  # momentum fixed in space: P' = P x omega
    P_name = "M+K" if gyro else "M"
    integrals: list[tuple[str, sp.Expr]] = [
        ("H", red.energy),
        (f"({P_name},{P_name})", sp.expand(dot(P, P))),
        (f"({P_name},gamma)", sp.expand(dot(P, gamma))),
    ]
    if contact:
        integrals += [
            (f"({P_name},alpha)", sp.expand(dot(P, alpha))),
            (f"({P_name},beta)", sp.expand(dot(P, beta))),
        ]
    if contact:
        integrals += [
            ("(alpha,alpha)", dot(alpha, alpha)),
            ("(beta,beta)", dot(beta, beta)),
            ("(alpha,beta)", dot(alpha, beta)),
            ("(gamma,alpha)", dot(gamma, alpha)),
            ("(gamma,beta)", dot(gamma, beta)),
        ]
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
            "momentum_of_omega": red.inertia_operator * omega,
            "inertia_operator": red.inertia_operator,
            "gyrostatic_momentum": red.gyrostatic_momentum,
            "centre_velocity": centre_velocity,
            "contact_vector": r,
            "euler_poincare_remainder": remainder,
            "structured_inverse": structured,
            "reduced_equations": red,
            "mass": m,
            "reparametrisation": reparametrisation,
        },
        references={
            "momentum": "BKM12-1",
            "equations": "K01-4.1" if gyro else "BKM12-2",
            "omega": "BKM12-3",
            "density": "BKM12-4",
            "integrals": "K01-4.2" if gyro else "BKM12-5",
            "contact_point": "BKM12-6",
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
