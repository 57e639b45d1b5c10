"""A homogeneous (dynamically symmetric) ball rolling on a fixed surface (M03 §1).

Everything is written in the *fixed* frame: the centre ``x`` of a ball of mass ``m``,
radius ``R`` and scalar central inertia ``I = m_e R^2`` moves on a surface ``f(x) = 0``
(the surface the centre describes, parallel to the supporting one) with unit normal
``n = grad f/|grad f|``; the contact point is ``x - R n``.

Derivation (Lagrange–d'Alembert with multipliers, as :mod:`.engine` does in the body
frame):

* quasi-velocities ``q = (omega, v)``, ``v = x'``, all in the fixed frame;
  ``T = m (v, v)/2 + I (omega, omega)/2``. For scalar inertia the space-frame angular
  momentum ``I omega`` does not depend on the attitude, so the Newton–Euler equations in
  the fixed frame carry no gyroscopic terms: ``d/dt dT/dq = (N, F) + Phi^T lambda`` with the
  torque ``N = 0`` about the centre and the external force ``F = -grad U`` at the centre;
* constraints ``Phi q = 0``: no slip at the contact point, ``v + omega x (-R n) = 0``
  (reaction ``Lambda`` at the contact point: force ``Lambda``, torque ``-R n x Lambda``),
  and the tangency of the centre velocity to the surface, ``(n, v) = 0`` (normal
  reaction; redundant with the first three, its multiplier drops out as well);
* the constraints give ``v = R omega x n``; the columns of ``G = d(omega, v)/d omega``
  span the admissible velocities, ``G^T Phi^T = 0`` identically, and projecting the
  equations on them eliminates every multiplier exactly;
* the projected equations are linear in ``omega'`` with the operator
  ``a Id + c n ⊗ n`` (found by matching normal forms modulo ``(n, n) = 1``), inverted by
  Sherman–Morrison.

The derivation runs with an abstract unit normal ``nu`` and its rate ``nudot`` (symbols);
:func:`surface_equations` then substitutes ``n(x) = grad f/|grad f|`` and
``n' = (dn/dx) x'`` (chain rule) for any surface ``f`` and potential ``U`` — an undefined
sympy Function included (the claims about a generic surface use that). That is the
reduction stage :class:`FixedFrameReduction` of the shared finishing step
(:func:`~.description.form_model`): a description (:func:`fixed_frame_description`)
declares the state ``omega, x``, the parameters, the potential, the integrals, the
phase-space constraint and the sampler; the stage derives the rates, the energy and the
density ``|grad f|``.

For the generated code the surface is the triaxial ellipsoid ``(x, B^-1 x) = 1``,
``B = diag(b1, b2, b3)``; the effect ``potential`` adds the force of
``U = k (x, x)/2 + (1/2) sum_i c_i/x_i^2`` (M03-1.6).

References
----------
M03-1.1 .. M03-1.7 (FORMULAS.md §4.1).
"""

from __future__ import annotations

import functools
import random
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import sympy as sp

from .algebra import ConstraintIdeal, seeded_factor
from .description import MechanicalDescription, Reduced, apply_effects, form_model
from .effects import ellipsoid_potential, parse_effects
from .errors import DerivationError
from .model import Model, ModelDetails, ParameterSpec
from .vectors import cross, dot, vector

__all__ = [
    "NAME",
    "DESCRIPTION",
    "SUPPORTED_EFFECTS",
    "GENERATED_VARIANTS",
    "PARAMETER_ORDER",
    "BUILDER",
    "FixedFrameDerivation",
    "SurfaceEquations",
    "FixedFrameReduction",
    "derive_fixed_frame",
    "surface_equations",
    "fixed_frame_description",
    "generic_surface_model",
    "ellipsoid_potential",
    "ellipsoid_sampler",
    "build_ball_on_surface",
    "ellipsoid_description",
]

NAME = "ball_on_surface"
DESCRIPTION = (
    "homogeneous ball whose centre rolls on a surface f(x) = 0, fixed frame; "
    "triaxial ellipsoid (x, B^-1 x) = 1 for the code (M03 §1)"
)
SUPPORTED_EFFECTS = ("potential",)
#: Effect combinations whose code is committed in generated/.
GENERATED_VARIANTS = ((), ("potential",))
#: Order of the parameter groups in the model (and the generated code).
PARAMETER_ORDER = ("m", "m_e", "R", "b", "k", "c")


# --------------------------------------------------------------------- symbols
def _state_symbols() -> tuple[sp.Matrix, sp.Matrix]:
    """``omega1..3`` and the centre ``x_1..x_3``.

    The centre's components are named ``x_1`` ... rather than ``x1`` ...: the emitters
    name common subexpressions ``x0, x1, ...``, and a state called ``x1`` would be
    shadowed in the generated Python code.
    """
    omega = vector("omega", real=True)
    x = sp.Matrix(sp.symbols("x_1:4", real=True))
    return omega, x


def _mechanical_parameters() -> tuple[sp.Symbol, sp.Symbol, sp.Symbol]:
    m, m_e, R = sp.symbols("m m_e R", positive=True)
    return m, m_e, R


# ------------------------------------------------------------- the derivation
@dataclass
class FixedFrameDerivation:
    """Lagrange–d'Alembert equations of the ball, with an abstract unit normal.

    Attributes
    ----------
    omega, v : sympy.Matrix
        Quasi-velocities (fixed frame).
    nu, nudot : sympy.Matrix
        Abstract unit normal at the contact and its time derivative.
    force : sympy.Matrix
        External force at the centre (abstract symbols ``F1..F3``).
    kinetic_energy : sympy.Expr
    constraints : list of sympy.Expr
        ``v + omega x (-R nu)`` (three rows) and ``(nu, v)``.
    with_multipliers : sympy.Matrix, shape (6, 1)
        Residuals of the Newton–Euler equations with the reactions ``Phi^T lambda``, in
        ``omega_dot, v_dot`` and the multipliers.
    multipliers : tuple of sympy.Symbol
    velocity_map : dict
        ``v_i -> (R omega x nu)_i`` solved from the constraints.
    admissible : sympy.Matrix, shape (6, 3)
        ``G``.
    projected : sympy.Matrix, shape (3, 1)
        ``G^T (equations)`` on the admissible velocities: free of the multipliers.
    inertia : tuple of sympy.Expr
        ``(a, c)`` with ``d projected/d omega_dot = a Id + c nu ⊗ nu`` on ``|nu| = 1``.
    omega_rate : sympy.Matrix
        ``omega'`` in ``omega, nu, nudot, F``.
    energy : sympy.Expr
        Kinetic energy on the admissible velocities (without the potential).
    """

    omega: sp.Matrix
    v: sp.Matrix
    omega_dot: sp.Matrix
    v_dot: sp.Matrix
    nu: sp.Matrix
    nudot: sp.Matrix
    force: sp.Matrix
    kinetic_energy: sp.Expr
    constraints: list[sp.Expr]
    with_multipliers: sp.Matrix
    multipliers: tuple[sp.Symbol, ...]
    velocity_map: dict[sp.Symbol, sp.Expr]
    admissible: sp.Matrix
    projected: sp.Matrix
    inertia: tuple[sp.Expr, sp.Expr]
    omega_rate: sp.Matrix
    energy: sp.Expr


def derive_fixed_frame(
    m: sp.Expr, m_e: sp.Expr, R: sp.Expr, omega: sp.Matrix | None = None
) -> FixedFrameDerivation:
    """Derive ``omega'`` of a homogeneous ball rolling without slipping (fixed frame).

    Parameters
    ----------
    m, m_e, R : sympy.Expr
        Mass, effective mass (``I = m_e R^2``) and radius.
    omega : sympy.Matrix, optional
        Angular-velocity symbols (default ``omega1..3``).

    Returns
    -------
    FixedFrameDerivation

    Raises
    ------
    DerivationError
        When a step that must hold identically does not (the constraints do not fix
        ``v``, ``G^T Phi^T != 0``, a multiplier survives the projection, the projected
        operator is not ``a Id + c nu ⊗ nu``).
    """
    if omega is None:
        omega, _ = _state_symbols()
    v = vector("v", real=True)
    omega_dot = vector("omega_dot", real=True)
    v_dot = vector("v_dot", real=True)
    nu = vector("nu", real=True)
    nudot = vector("nudot", real=True)
    F = vector("F", real=True)
    q = sp.Matrix.vstack(omega, v)
    q_dot = sp.Matrix.vstack(omega_dot, v_dot)

    # --- mechanical description -----------------------------------------------------
    inertia = m_e * R**2
    T = m * dot(v, v) / 2 + inertia * dot(omega, omega) / 2
    r = -R * nu  # centre -> contact point
    constraints = [*(v + cross(omega, r)), dot(nu, v)]

    p = sp.Matrix([sp.diff(T, s) for s in q])
    hess = p.jacobian(q)
    if hess[:3, :3] != inertia * sp.eye(3) or hess[:3, 3:] != sp.zeros(3, 3):
        raise DerivationError("the fixed-frame form needs a scalar (homogeneous) inertia")
    Phi = sp.Matrix([[sp.diff(c, s) for s in q] for c in constraints])
    if any(sp.expand(c - (Phi.row(i) * q)[0]) != 0 for i, c in enumerate(constraints)):
        raise DerivationError("the constraints are not linear and homogeneous in (omega, v)")
    lam = sp.symbols(f"lambda1:{len(constraints) + 1}", real=True)
    # Newton–Euler in the fixed frame: the coefficients of T are constant, torque N = 0
    # about the centre, force F at the centre, reactions Phi^T lambda.
    generalised_force = sp.Matrix.vstack(sp.zeros(3, 1), F)
    with_multipliers = hess * q_dot - generalised_force - Phi.T * sp.Matrix(lam)

    # --- admissible velocities -----------------------------------------------------------
    sol = sp.solve(constraints[:3], list(v), dict=True)
    if len(sol) != 1 or set(sol[0]) != set(v):
        raise DerivationError("the no-slip constraint does not determine v")
    vmap = {s: sp.expand(sol[0][s]) for s in v}
    if any(sp.expand(c.xreplace(vmap)) != 0 for c in constraints):
        raise DerivationError("the constraints restrict omega: not a rolling ball")
    v_of_omega = v.xreplace(vmap)
    G = sp.Matrix.vstack(sp.eye(3), v_of_omega.jacobian(omega))
    if (G.T * Phi.T).applyfunc(sp.expand) != sp.zeros(3, len(constraints)):
        raise DerivationError("G^T Phi^T != 0: the projection would not remove the reactions")

    # --- projection ------------------------------------------------------------------------
    v_dot_of = v_of_omega.jacobian(omega) * omega_dot + v_of_omega.jacobian(nu) * nudot
    on_admissible = {**vmap, **dict(zip(v_dot, v_dot_of, strict=True))}
    projected = (G.T * with_multipliers.xreplace(on_admissible)).applyfunc(sp.expand)
    if projected.free_symbols & set(lam):
        raise DerivationError("a multiplier survived the projection")
    A = projected.jacobian(omega_dot)
    b0 = projected.xreplace(dict.fromkeys(omega_dot, 0)).applyfunc(sp.expand)
    a_, c_ = sp.symbols("_a _c")
    ideal = ConstraintIdeal([dot(nu, nu) - 1], list(nu))
    equations = []
    for i in range(3):
        for j in range(i, 3):
            target = a_ * sp.eye(3)[i, j] + c_ * nu[i] * nu[j]
            equations += ideal.coefficient_equations(A[i, j] - target)
    solutions = sp.linsolve(equations, [a_, c_])
    if not solutions:
        raise DerivationError("the projected inertia operator is not a Id + c nu ⊗ nu")
    ((a, c),) = solutions
    a, c = seeded_factor(a), seeded_factor(c)
    # Sherman–Morrison on |nu| = 1: (a Id + c nu ⊗ nu)^-1 = (Id - c/(a + c) nu ⊗ nu)/a.
    inverse = (sp.eye(3) - c / (a + c) * nu * nu.T) / a
    omega_rate = (-(inverse * b0)).applyfunc(lambda e: sp.factor_terms(sp.expand(e)))
    energy = sp.expand(T.xreplace(vmap))

    return FixedFrameDerivation(
        omega=omega,
        v=v,
        omega_dot=omega_dot,
        v_dot=v_dot,
        nu=nu,
        nudot=nudot,
        force=F,
        kinetic_energy=T,
        constraints=constraints,
        with_multipliers=with_multipliers,
        multipliers=tuple(lam),
        velocity_map=vmap,
        admissible=G,
        projected=projected,
        inertia=(a, c),
        omega_rate=omega_rate,
        energy=energy,
    )


# ------------------------------------------------------------------- a surface
@dataclass
class SurfaceEquations(ModelDetails):
    """The derivation on a concrete surface ``f(x) = 0`` with potential ``U(x)``.

    It is the ``details`` of a model of :class:`FixedFrameReduction`.

    Expressions are written in the state ``omega, x``, the parameters and the auxiliary
    symbols ``n1..n3`` (unit normal) and ``ndot1..ndot3`` (its rate) of :attr:`aux`.

    Attributes
    ----------
    surface, potential : sympy.Expr
    gradient : sympy.Matrix
        ``grad f``.
    grad_norm : sympy.Expr
        ``|grad f|``.
    normal : sympy.Matrix
        ``n(x) = grad f/|grad f|`` (in ``x``).
    normal_rate : sympy.Matrix
        ``n' = (dn/dx) x'`` in ``x`` and the auxiliary ``n``.
    force : sympy.Matrix
        ``F = -grad U``.
    x_rate, omega_rate : sympy.Matrix
    energy : sympy.Expr
        ``T`` on the admissible velocities plus ``U``.
    aux : tuple of (sympy.Symbol, sympy.Expr)
    derivation : FixedFrameDerivation
    """

    omega: sp.Matrix
    x: sp.Matrix
    surface: sp.Expr
    potential: sp.Expr
    gradient: sp.Matrix
    grad_norm: sp.Expr
    normal: sp.Matrix
    normal_symbols: sp.Matrix
    normal_rate: sp.Matrix
    normal_rate_symbols: sp.Matrix
    force: sp.Matrix
    x_rate: sp.Matrix
    omega_rate: sp.Matrix
    energy: sp.Expr
    aux: tuple[tuple[sp.Symbol, sp.Expr], ...]
    derivation: FixedFrameDerivation


def surface_equations(
    surface: sp.Expr,
    potential: sp.Expr,
    x: sp.Matrix,
    omega: sp.Matrix,
    m: sp.Expr,
    m_e: sp.Expr,
    R: sp.Expr,
) -> SurfaceEquations:
    """Put the fixed-frame derivation on the surface ``f(x) = 0`` with potential ``U``.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(x)``: a polynomial, or an undefined Function of ``x`` for a generic surface.
    potential : sympy.Expr
        ``U(x)`` (0 without external force); the force is ``F = -grad U``.
    x, omega : sympy.Matrix
        State symbols.
    m, m_e, R : sympy.Expr

    Returns
    -------
    SurfaceEquations
    """
    der = derive_fixed_frame(m, m_e, R, omega)
    grad = sp.Matrix([sp.diff(surface, s) for s in x])
    grad_norm = sp.sqrt(sp.factor_terms(sp.expand(dot(grad, grad))))
    normal = (grad / grad_norm).applyfunc(sp.factor_terms)
    n = sp.Matrix(sp.symbols("n1:4", real=True))
    ndot = sp.Matrix(sp.symbols("ndot1:4", real=True))
    force = -sp.Matrix([sp.diff(potential, s) for s in x])
    # x' = v on the admissible velocities, with the abstract normal replaced by n(x)
    x_rate = der.v.xreplace(der.velocity_map).xreplace(dict(zip(der.nu, n, strict=True)))
    normal_rate = normal.jacobian(x) * x_rate  # chain rule
    to_surface = {
        **dict(zip(der.nu, n, strict=True)),
        **dict(zip(der.nudot, ndot, strict=True)),
        **dict(zip(der.force, force, strict=True)),
    }
    omega_rate = der.omega_rate.xreplace(to_surface)
    energy = der.energy.xreplace(to_surface) + potential
    aux = tuple(zip(n, normal, strict=True)) + tuple(zip(ndot, normal_rate, strict=True))
    return SurfaceEquations(
        omega=omega,
        x=x,
        surface=surface,
        potential=potential,
        gradient=grad,
        grad_norm=grad_norm,
        normal=normal,
        normal_symbols=n,
        normal_rate=normal_rate,
        normal_rate_symbols=ndot,
        force=force,
        x_rate=x_rate,
        omega_rate=omega_rate,
        energy=energy,
        aux=aux,
        derivation=der,
    )


@dataclass(frozen=True)
class FixedFrameReduction:
    """The ball whose centre rolls on ``f(x) = 0``, written in the fixed frame.

    Parameters
    ----------
    surface : sympy.Expr
        ``f`` in the centre's state symbols (a polynomial, or an undefined Function).
    mass, effective_mass, radius : sympy.Symbol
        ``m``, ``m_e`` (``I = m_e R^2``) and ``R``.
    angular_velocity, centre : str
        The state groups ``omega`` and ``x`` (their rates are derived).
    """

    surface: sp.Expr
    mass: sp.Symbol
    effective_mass: sp.Symbol
    radius: sp.Symbol
    angular_velocity: str = "omega"
    centre: str = "x"

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """``omega'`` and ``x'`` on the surface, the energy ``H`` and the density ``|grad f|``.

        Parameters
        ----------
        desc : MechanicalDescription
            With the state groups :attr:`angular_velocity` and :attr:`centre` and the
            potential ``U`` of the force on the centre.

        Returns
        -------
        Reduced
            ``details`` the :class:`SurfaceEquations`.

        Raises
        ------
        DerivationError
            For declared data this derivation does not take (kinetic-energy terms,
            velocity constraints, Poisson vectors, further bodies), or from
            :func:`derive_fixed_frame`.
        """
        desc.refuse(
            "fixed-frame",
            ("inertia", "kinetic_energy", "constraints", "kinematics", "momentum_in_state")
            + ("bodies", "positions"),
        )
        omega = desc.state_group(self.angular_velocity)
        x = desc.state_group(self.centre)
        eq = surface_equations(
            self.surface,
            desc.potential,
            x,
            omega,
            self.mass,
            self.effective_mass,
            self.radius,
        )
        return Reduced(
            rates={self.angular_velocity: list(eq.omega_rate), self.centre: list(eq.x_rate)},
            aux=eq.aux,
            integrals=[("H", eq.energy)],
            density=eq.grad_norm,
            omega=omega,
            details=eq,
        )


def fixed_frame_description(
    surface: sp.Expr,
    effects: Iterable[str] = (),
    *,
    potential: sp.Expr = sp.S.Zero,
    parameter_order: tuple[str, ...] = ("m", "m_e", "R"),
    system: str = NAME,
) -> MechanicalDescription:
    """A homogeneous ball whose centre rolls on ``f(x) = 0``: state, mass, inertia, radius.

    Parameters
    ----------
    surface : sympy.Expr
        ``f`` in the centre symbols ``x_1, x_2, x_3`` (see :func:`_state_symbols`).
    effects : iterable of str
        Recorded in the description; not applied here.
    potential : sympy.Expr
        ``U`` in the same symbols.
    parameter_order : tuple of str
        The model's parameter groups in order (``m, m_e, R`` and those the caller adds).
    system : str

    Returns
    -------
    MechanicalDescription
        State ``omega, x``; parameters ``m, m_e, R``; the stage
        :class:`FixedFrameReduction`. The caller adds the surface's parameters, its
        integrals, phase-space constraint, sampler and references.
    """
    omega, x = _state_symbols()
    m, m_e, R = _mechanical_parameters()
    desc = MechanicalDescription(
        system=system,
        effects=frozenset(effects),
        time=sp.Symbol("t", real=True),
        omega=omega,
        reduction=FixedFrameReduction(surface, m, m_e, R),
        parameter_order=parameter_order,
    )
    desc.add_state("omega", tuple(omega), None)
    desc.add_state("x", tuple(x), None)
    desc.add_parameter(ParameterSpec("m", (m,), "positive", "mass of the ball"))
    desc.add_parameter(ParameterSpec("m_e", (m_e,), "positive", "effective mass: I = m_e R^2"))
    desc.add_parameter(ParameterSpec("R", (R,), "positive", "radius of the ball"))
    desc.add_potential(potential)
    return desc


def generic_surface_model(with_potential: bool = True) -> Model:
    """The ball on a generic surface: ``f`` and ``U`` undefined Functions of ``x``.

    Used by the claims about an arbitrary surface (M03-1.1 .. 1.4, 1Y): the verifier
    treats ``f``, ``U`` and their partial derivatives at a point as independent
    generators, so an identity proved for this model holds for every smooth ``f`` and
    ``U`` at every point where ``grad f != 0`` — on every level set of ``f``, not only on
    ``f = 0`` (the flow preserves each of them).

    Parameters
    ----------
    with_potential : bool
        ``F = -grad U`` with ``U`` generic, or ``F = 0``.

    Returns
    -------
    Model
    """
    _, x = _state_symbols()
    f = sp.Function("f")(*x)
    U = sp.Function("U")(*x) if with_potential else sp.S.Zero
    desc = fixed_frame_description(
        f, ("generic_surface", *(("potential",) if with_potential else ())), potential=U
    )
    desc.references.update({"equations": "M03-1.1", "energy": "M03-1.3", "density": "M03-1Y"})
    return form_model(desc)


# ------------------------------------------------------------ the ellipsoid
def _sample_ellipsoid(b: sp.Matrix, x: sp.Matrix, rng: random.Random, point: dict) -> None:
    def r() -> sp.Rational:
        return sp.Rational(rng.choice([-1, 1]) * rng.randint(1, 9), rng.randint(1, 9))

    s = [sp.Rational(rng.randint(1, 12), rng.randint(1, 6)) for _ in range(3)]
    p, q = r(), r()
    while p**2 + q**2 == 1:  # u3 = 0
        p, q = r(), r()
    d = 1 + p**2 + q**2
    u = [2 * p / d, 2 * q / d, (1 - p**2 - q**2) / d]
    for i in range(3):
        point[b[i]] = s[i] ** 2
        point[x[i]] = s[i] * u[i]


def ellipsoid_sampler(b: sp.Matrix, x: sp.Matrix) -> Callable[[random.Random, dict], None]:
    """Rational points of ``(x, B^-1 x) = 1``: ``b_i = s_i^2``, ``x_i = s_i u_i``, ``|u| = 1``.

    ``u`` comes from the inverse stereographic projection of a random rational point,
    ``s_i`` are random positive rationals, so the point is exact and the ellipsoid a
    physical one (positive ``b_i``). Points on the coordinate planes (where the
    potential of M03-1.6 is singular) are not drawn. The sampler is picklable (models
    are cached on disk).

    Parameters
    ----------
    b : sympy.Matrix, shape (3, 1)
        The semi-axis parameters ``b_1, b_2, b_3`` (squares of the semi-axes).
    x : sympy.Matrix, shape (3, 1)
        The centre's state symbols.

    Returns
    -------
    callable ``(rng, point) -> None``
        A :data:`~.model.PhaseSpaceSampler`: writes exact rational values of ``b`` and
        ``x`` into the dict ``point``, drawing from ``rng`` (a ``random.Random``).
    """
    return functools.partial(_sample_ellipsoid, b, x)


def ellipsoid_description(effects: frozenset[str] = frozenset()) -> MechanicalDescription:
    """The ball whose centre rolls on ``(x, B^-1 x) = 1``, no effect applied yet.

    State ``omega, x``; parameters ``m, m_e, R, b``; the integrals ``K`` (M03-1.5) and
    ``(x, B^-1 x)``; the ellipsoid as the phase-space constraint, with its exact sampler.

    Parameters
    ----------
    effects : frozenset of str
        Recorded in the description; not applied here.

    Returns
    -------
    MechanicalDescription
    """
    omega, x = _state_symbols()
    b = sp.Matrix(sp.symbols("b1:4", positive=True))
    B = sp.diag(*b)
    Binv = sp.diag(*[1 / bi for bi in b])
    quadric = dot(x, Binv * x)
    surface = quadric - 1
    desc = fixed_frame_description(surface, effects, parameter_order=PARAMETER_ORDER)
    desc.add_parameter(
        ParameterSpec(
            "b", tuple(b), "positive", "ellipsoid of the centre (x, B^-1 x) = 1, B = diag(b)"
        )
    )
    n = sp.Matrix(sp.symbols("n1:4", real=True))
    u = cross(n, omega)
    desc.add_integral("K", dot(u, Binv * u) / dot(n, B * n))  # M03-1.5
    desc.add_integral("(x,B^-1 x)", quadric)
    # The surface polynomial with its denominators cleared (same real variety for b > 0),
    # so that it lies in the polynomial ring of the verifier.
    desc.add_phase_space_constraint(sp.expand(b[0] * b[1] * b[2] * surface))
    desc.sampler = ellipsoid_sampler(b, x)
    desc.references.update(
        {
            "equations": "M03-1.1",
            "normal": "M03-1.2",
            "energy": "M03-1.3",
            "density": "M03-1Y",
            "integrals": "M03-1.5",
        }
    )
    return desc


def build_ball_on_surface(effects: Iterable[str] | str | None = ()) -> Model:
    """Derive the ball whose centre rolls on the ellipsoid ``(x, B^-1 x) = 1``.

    Parameters
    ----------
    effects : iterable of str or str, optional
        ``"potential"``: the external potential of M03-1.6.

    Returns
    -------
    Model
        State ``omega1..3, x_1..x_3``; parameters ``m, m_e, R, b1..b3`` (+ ``k, c1..c3``
        with ``potential``); integrals ``H``, the Joachimsthal-type ``K`` (M03-1.5, and
        its generalisation M03-1.7 with the potential) and ``(x,B^-1 x)``; density
        ``|grad f|``.

    Examples
    --------
    >>> model = build_ball_on_surface()
    >>> model.state_names
    ('omega1', 'omega2', 'omega3', 'x_1', 'x_2', 'x_3')
    >>> model.param_names
    ('m', 'm_e', 'R', 'b1', 'b2', 'b3')
    >>> [name for name, _ in model.integrals]
    ['H', 'K', '(x,B^-1 x)']
    """
    effects = parse_effects(effects, SUPPORTED_EFFECTS)
    desc = ellipsoid_description(effects)
    apply_effects(desc, effects, SUPPORTED_EFFECTS)
    return form_model(desc)


BUILDER = build_ball_on_surface
