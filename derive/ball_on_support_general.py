"""A ball of any mass distribution rolling on a fixed support surface ``F(p) = 0``.

:mod:`.ball_on_support` derives a *homogeneous* ball there: its fixed-frame angular
momentum ``I omega`` does not depend on the attitude, so the state is ``omega`` and the
contact point ``p`` alone. A ball of radius ``b`` with any central inertia tensor ``I``
(body axes, products of inertia allowed), its centre of mass at ``a`` from the
geometric centre (body axes) and a constant rotor ``K`` (body axes) needs the attitude:
the state is ``omega`` and ``p`` in the fixed frame and the body axes' fixed-frame
components ``e1, e2, e3`` (the columns of the rotation ``Q`` from body to fixed axes,
``e_i' = omega x e_i``; a right-handed orthonormal frame, the phase-space constraints
``e3 = e1 x e2``, ``|e1| = |e2| = 1``, ``(e1, e2) = 0``; components ``e1_1, e1_2,
e1_3`` ...).

Derivation (Lagrange–d'Alembert with multipliers in the fixed frame, as
:func:`~.ball_on_surface.derive_fixed_frame` does for the homogeneous ball):

* in the fixed frame ``I_f = Q I Q^T``, ``a_f = Q a``, ``K_f = Q K``; the unit normal
  ``n`` from the contact to the geometric centre (``n = s nu(p)``, ``nu = grad F/|grad
  F|``, ``s = 1`` outside, ``-1`` inside) and ``rho = b n + a_f`` from the contact point
  to the centre of mass;
* quasi-velocities ``q = (omega, v)``, ``v`` the centre of mass's velocity; the
  Newton–Euler equations ``d/dt (I_f omega + K_f) = I_f omega' + omega x (I_f omega +
  K_f)`` (``Q' = [omega] Q``) and ``m v' = F = (0, 0, -m g)``, with the reactions
  ``Phi^T lambda`` of the no-slip constraint ``Phi q = v - omega x rho = 0`` (the body's
  material point at ``p`` is at rest);
* the admissible velocities ``v = omega x rho``: the columns of ``G = d(omega, v)/d omega``
  annihilate ``Phi^T`` identically, and ``G^T`` times the equations (``v' = omega' x rho +
  omega x rho'``, ``rho' = b n' + omega x a_f``) is free of the multipliers: ``P omega' =
  h`` with ``P = I_f + m (|rho|^2 Id - rho rho^T)`` (the inertia about the contact point;
  found as the Jacobian, checked symmetric), solved by its adjugate over its determinant;
* the contact point: the geometric centre ``p + b n(p)`` moves at ``b omega x n``, so
  ``(Id + s b dnu/dp) p' = b omega x n`` and ``n' = s (dnu/dp) p'`` (the support's
  curvature; the same as :mod:`.ball_on_support`).

The energy ``m (v, v)/2 + (omega, I_f omega)/2 + m g (p + b n + a_f)_3`` is an integral
(``(omega, P omega' - h) = 0`` and the reaction does no work), and so is the support's
level ``F(p)`` (``(nu, p') = 0``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

from .ball_on_support import support_normal
from .body_on_sphere import _adjugate_and_det
from .description import MechanicalDescription, Reduced, form_model
from .errors import DerivationError
from .geometry import FRAME, PoissonGroup
from .model import Model, ModelDetails, ParameterSpec
from .vectors import cross, dot, vector

__all__ = [
    "AXES",
    "AUX_NAMES",
    "FIXED_FRAME_REFUSED",
    "GeneralBallDerivation",
    "GeneralBallEquations",
    "GeneralBallReduction",
    "add_axes",
    "derive_general_ball",
    "project_newton_euler",
    "general_ball_description",
    "general_ball_model",
]

#: The state groups of the body axes' fixed-frame components (the columns of ``Q``).
AXES = ("e1", "e2", "e3")
#: The names of the auxiliary symbols (a parameter must not take them).
AUX_NAMES = frozenset(
    {f"{n}{i}" for n in ("nu", "pdot", "af", "Kf", "Kdf", "hc", "tau", "w", "zr")
     for i in (1, 2, 3)}  # fmt: skip
    | {"mu"}
    | {f"{n}{i}{j}" for n in ("Dnu", "If", "Idf", "Pc") for i in (1, 2, 3) for j in (1, 2, 3)}
)


#: What a fixed-frame support reduction does not take from a description (it derives
#: everything from its own data).
FIXED_FRAME_REFUSED = (
    ("inertia", "kinetic_energy", "potential", "constraints", "kinematics")
    + ("momentum_in_state", "bodies", "positions")
)


def _axis(name: str) -> sp.Matrix:
    """The components ``name_1, name_2, name_3`` of a body axis (``e1_1`` ...)."""
    return sp.Matrix(sp.symbols(f"{name}_1:4", real=True))


def _symmetric(name: str) -> sp.Matrix:
    """A symmetric 3 x 3 matrix of symbols ``name11, name12, ...`` (``name21`` is ``name12``)."""
    return sp.Matrix(
        3, 3, lambda i, j: sp.Symbol(f"{name}{min(i, j) + 1}{max(i, j) + 1}", real=True)
    )


@dataclass
class GeneralBallDerivation:
    """The fixed-frame Lagrange–d'Alembert equations with abstract frame quantities.

    Everything is written in ``omega``, the abstract unit normal ``n`` (contact to centre)
    and its rate ``ndot``, and the abstract fixed-frame ``I_f`` (symmetric), ``a_f``,
    ``K_f`` (symbols ``If11 ...``, ``af1 ...``, ``Kf1 ...``).

    Attributes
    ----------
    omega, v, omega_dot, v_dot, n, ndot, inertia, offset, rotor : sympy.Matrix
    inertia_rate, rotor_rate : sympy.Matrix
        The abstract ``Q I'(t) Q^T`` (symmetric, ``Idf11 ...``) and ``Q K'(t)`` (``Kdf1
        ...``): zero for a constant inertia and rotor.
    rho : sympy.Matrix
        ``b n + a_f``, from the contact point to the centre of mass.
    constraints : list of sympy.Expr
        ``v - omega x rho`` (three rows).
    with_multipliers : sympy.Matrix, shape (6, 1)
    multipliers : tuple of sympy.Symbol
    admissible : sympy.Matrix, shape (6, 3)
        ``G``.
    projected : sympy.Matrix, shape (3, 1)
        ``G^T`` times the equations on the admissible velocities (no multiplier).
    contact_inertia : sympy.Matrix
        ``P = d projected/d omega'`` (symmetric).
    forcing : sympy.Matrix
        ``h = -projected`` at ``omega' = 0``: ``P omega' = h``.
    kinetic_energy : sympy.Expr
        On the admissible velocities.
    height : sympy.Expr
        Of the centre of mass above the contact point (``rho_3``).
    """

    omega: sp.Matrix
    v: sp.Matrix
    omega_dot: sp.Matrix
    v_dot: sp.Matrix
    n: sp.Matrix
    ndot: sp.Matrix
    inertia: sp.Matrix
    offset: sp.Matrix
    rotor: sp.Matrix
    inertia_rate: sp.Matrix
    rotor_rate: sp.Matrix
    rho: sp.Matrix
    constraints: list[sp.Expr]
    with_multipliers: sp.Matrix
    multipliers: tuple[sp.Symbol, ...]
    admissible: sp.Matrix
    projected: sp.Matrix
    contact_inertia: sp.Matrix
    forcing: sp.Matrix
    kinetic_energy: sp.Expr
    height: sp.Expr


def derive_general_ball(
    m: sp.Expr, b: sp.Expr, g: sp.Expr, omega: sp.Matrix, n: sp.Matrix, ndot: sp.Matrix
) -> GeneralBallDerivation:
    """Derive ``P omega' = h`` of a rolling ball of any mass distribution (fixed frame).

    Parameters
    ----------
    m, b, g : sympy.Expr
        Mass, radius and the field's strength along ``-e3`` (0: none).
    omega, n, ndot : sympy.Matrix
        The angular velocity, the abstract unit normal from the contact to the centre and
        its rate.

    Returns
    -------
    GeneralBallDerivation

    Raises
    ------
    DerivationError
        When a step that must hold identically does not (``G^T Phi^T != 0``, a
        multiplier survives the projection, ``P`` is not symmetric).
    """
    af = vector("af", real=True)
    rho = b * n + af
    core = project_newton_euler(m, g, omega, rho, b * ndot + cross(omega, af))  # a_f turns
    return GeneralBallDerivation(n=n, ndot=ndot, offset=af, **core)


def project_newton_euler(
    m: sp.Expr, g: sp.Expr, omega: sp.Matrix, rho: sp.Matrix, rho_rate: sp.Matrix
) -> dict[str, Any]:
    """The fixed-frame Newton–Euler equations of a rolling body projected on its
    admissible velocities ``v = omega x rho``: ``P omega' = h`` free of the reactions.

    Parameters
    ----------
    m, g : sympy.Expr
        Mass and the field's strength along ``-e3`` (0: none).
    omega : sympy.Matrix
        The angular velocity (fixed frame).
    rho, rho_rate : sympy.Matrix
        From the contact point to the centre of mass, and its rate along the motion.

    Returns
    -------
    dict
        The fields of :class:`GeneralBallDerivation` but ``n``, ``ndot``, ``offset``
        (``inertia``, ``rotor`` and their rates the abstract ``If``, ``Kf``, ``Idf``,
        ``Kdf``).

    Raises
    ------
    DerivationError
        When a step that must hold identically does not (``G^T Phi^T != 0``, a
        multiplier survives the projection, ``P`` is not symmetric).
    """
    v, omega_dot, v_dot = (vector(x, real=True) for x in ("v", "omega_dot", "v_dot"))
    If, Kf = _symmetric("If"), vector("Kf", real=True)
    Idf, Kdf = _symmetric("Idf"), vector("Kdf", real=True)  # Q I'(t) Q^T, Q K'(t)
    q = sp.Matrix.vstack(omega, v)
    constraints = list(v - cross(omega, rho))
    Phi = sp.Matrix(constraints).jacobian(q)
    if (Phi * q - sp.Matrix(constraints)).applyfunc(sp.expand) != sp.zeros(3, 1):
        raise DerivationError("the no-slip constraint is not linear and homogeneous")
    lam = sp.Matrix(sp.symbols("lambda1:4", real=True))
    # Newton–Euler in the fixed frame: d/dt (I_f omega + K_f), I_f' = [omega] I_f - I_f
    # [omega] + Q I'(t) Q^T, K_f' = omega x K_f + Q K'(t); the weight at the centre of
    # mass; the reactions.
    rotation = If * omega_dot + cross(omega, If * omega + Kf) + Idf * omega + Kdf
    translation = m * v_dot - sp.Matrix([0, 0, -m * g])
    with_multipliers = sp.Matrix.vstack(rotation, translation) - Phi.T * lam
    v_of_omega = cross(omega, rho)
    G = sp.Matrix.vstack(sp.eye(3), v_of_omega.jacobian(omega))
    if (G.T * Phi.T).applyfunc(sp.expand) != sp.zeros(3, 3):
        raise DerivationError("G^T Phi^T != 0: the projection would not remove the reactions")
    on_admissible = {
        **dict(zip(v, v_of_omega, strict=True)),
        **dict(zip(v_dot, cross(omega_dot, rho) + cross(omega, rho_rate), strict=True)),
    }
    projected = (G.T * with_multipliers.xreplace(on_admissible)).applyfunc(sp.expand)
    if projected.free_symbols & set(lam):
        raise DerivationError("a multiplier survived the projection")
    P = projected.jacobian(omega_dot).applyfunc(sp.expand)
    if (P - P.T).applyfunc(sp.expand) != sp.zeros(3, 3):
        raise DerivationError("the projected inertia operator is not symmetric")
    forcing = -projected.xreplace(dict.fromkeys(omega_dot, 0)).applyfunc(sp.expand)
    kinetic = m * dot(v_of_omega, v_of_omega) / 2 + dot(omega, If * omega) / 2
    return dict(
        omega=omega, v=v, omega_dot=omega_dot, v_dot=v_dot, inertia=If, rotor=Kf,
        inertia_rate=Idf, rotor_rate=Kdf, rho=rho, constraints=constraints,
        with_multipliers=with_multipliers, multipliers=tuple(lam), admissible=G,
        projected=projected, contact_inertia=P, forcing=forcing,
        kinetic_energy=sp.expand(kinetic), height=rho[2],
    )  # fmt: skip


@dataclass
class GeneralBallEquations(ModelDetails):
    """The derivation on a concrete support (the ``details`` of the model).

    Attributes
    ----------
    support : sympy.Expr
        ``F(p)``.
    normal : sympy.Matrix
        ``nu(p) = grad F/|grad F|``.
    side : int
        ``s``: 1 outside, -1 inside.
    rotation : sympy.Matrix
        ``Q``, the body axes' state symbols as columns.
    p_rate, omega_rate : sympy.Matrix
        In the state and the auxiliary symbols.
    energy : sympy.Expr
    derivation : GeneralBallDerivation or dict
        The ball's; a convex body's (:mod:`.body_on_support`) the record of
        :func:`project_newton_euler`.
    """

    support: sp.Expr
    normal: sp.Matrix
    side: int
    rotation: sp.Matrix
    p_rate: sp.Matrix
    omega_rate: sp.Matrix
    energy: sp.Expr
    derivation: GeneralBallDerivation | dict


@dataclass(frozen=True)
class GeneralBallReduction:
    """A ball of any mass distribution on the fixed support ``F(p) = 0``.

    Parameters
    ----------
    support : sympy.Expr
        ``F`` in the contact point's state symbols.
    mass, radius : sympy.Expr
        ``m`` and ``b``.
    inertia : sympy.Matrix
        Central inertia tensor in body axes (symmetric; it may change with the time ``t``:
        masses moving in the body in symmetric pairs, ``d/dt (I_f omega)`` gains ``Q I'
        Q^T omega``).
    centre : sympy.Matrix
        ``a``: the centre of mass from the geometric centre, body axes.
    rotor : sympy.Matrix
        ``K``: a gyrostatic momentum, body axes (constant, or prescribed in ``t``: ``Q K'``).
    side : int
        1: outside the support (on the side of ``grad F``); -1: inside.
    gravity : sympy.Expr
        ``g`` of a field along ``-e3`` (0: none).
    potential : sympy.Expr
        ``V(p, e1, e2, e3)`` (0: none): its generalised force on the admissible velocities
        ``tau = -d(dV/dt)/d omega = -(dp'/d omega)^T dV/dp - sum_i e_i x dV/de_i`` joins
        ``h``, and ``V`` the energy.
    rubber : bool
        Rubber rolling: no spin about the normal, ``(omega, n) = 0`` (an invariant relation,
        written ``(omega, grad F) = 0``); its reaction torque ``mu n`` joins ``P omega' = h
        + mu n``, ``mu`` from ``d/dt (omega, n) = 0``: ``omega' = w + mu z``, ``w = P^-1 h``,
        ``z = P^-1 n``, ``mu = -((omega, n') + (w, n))/(z, n)``.
    """

    support: sp.Expr
    mass: sp.Expr
    radius: sp.Expr
    inertia: sp.Matrix
    centre: sp.Matrix
    rotor: sp.Matrix
    side: int = 1
    gravity: sp.Expr = sp.S.Zero
    potential: sp.Expr = sp.S.Zero
    rubber: bool = False

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """``omega'`` and ``p'`` (the axes' rates are declared), the energy (when nothing
        depends on the time) and ``F``.

        Parameters
        ----------
        desc : MechanicalDescription
            With the state groups ``omega``, ``p`` and :data:`AXES`.

        Returns
        -------
        Reduced
            The frame geometry of :data:`AXES`; ``details`` a :class:`GeneralBallEquations`.

        Raises
        ------
        DerivationError
            For declared data this derivation does not take, or from
            :func:`derive_general_ball`.
        """
        desc.refuse("general support-surface", FIXED_FRAME_REFUSED)
        omega, p = desc.state_group("omega"), desc.state_group("p")
        Q = sp.Matrix.hstack(*(desc.state_group(e) for e in AXES))
        m, b, s = self.mass, self.radius, self.side
        n_abs, ndot_abs = vector("n", real=True), vector("ndot", real=True)
        der = derive_general_ball(m, b, self.gravity, omega, n_abs, ndot_abs)
        geometry = support_normal(self.support, p, s, b)
        nu, nu_of_p, J, pdot = geometry.nu, geometry.normal, geometry.curvature, geometry.pdot
        p_rate = (geometry.adjugate * (b * cross(omega, s * nu)) / geometry.determinant).applyfunc(
            sp.expand
        )
        to_support = {
            **dict(zip(n_abs, s * nu, strict=True)),
            **dict(zip(ndot_abs, s * J * pdot, strict=True)),
        }
        If = Q * self.inertia * Q.T
        frame = _frame_aux(der, Q * self.centre, Q * self.rotor, If)
        t = desc.time
        rates = _time_rates(der, Q * self.inertia.diff(t) * Q.T, Q * self.rotor.diff(t))
        to_support.update(rates[1])
        Pc, hc = _symmetric("Pc"), vector("hc", real=True)
        contact_aux = [
            (Pc[i, j], der.contact_inertia[i, j].xreplace(to_support))
            for i in range(3)
            for j in range(i, 3)
        ]
        tau, force = _potential_force(self.potential, omega, p, Q, p_rate)
        contact_aux += force
        contact_aux += [(hc[i], der.forcing[i].xreplace(to_support) + tau[i]) for i in range(3)]
        adjP, detP = _adjugate_and_det(Pc)
        omega_rate = adjP * hc / detP
        if self.rubber:  # the reaction mu n of (omega, n) = 0
            omega_rate, no_spin = _no_spin(omega_rate, adjP * (s * nu) / detP, omega, s * nu,
                                           s * J * pdot)  # fmt: skip
            contact_aux += no_spin
        potential = m * self.gravity * (p[2] + der.height.xreplace(to_support)) + self.potential
        energy = der.kinetic_energy.xreplace(to_support) + potential
        aux = (
            geometry.aux(p, p_rate)
            + frame
            + rates[0]
            + tuple(contact_aux)
        )
        details = GeneralBallEquations(
            support=self.support, normal=nu_of_p, side=s, rotation=Q, p_rate=p_rate,
            omega_rate=omega_rate, energy=energy, derivation=der,
        )  # fmt: skip
        frame_group = PoissonGroup(FRAME, AXES)
        timed = any(sp.sympify(e).has(t) for _, e in aux)  # work done: no energy integral
        return Reduced(
            rates={"omega": list(omega_rate), "p": list(pdot)},
            aux=aux,
            integrals=([] if timed else [("H", energy)]) + [("F", geometry.level)],
            density=None,
            constraints=frame_group.constraints({e: desc.state_group(e) for e in AXES}),
            geometry=(frame_group,),
            relation_unknowns=tuple(omega) if self.rubber else (),
            omega=omega,
            details=details,
        )


def _time_rates(
    der: GeneralBallDerivation, inertia_rate: sp.Matrix, rotor_rate: sp.Matrix
) -> tuple[tuple[tuple[sp.Symbol, sp.Expr], ...], dict]:
    """The auxiliaries ``Q I' Q^T`` (upper triangle) and ``Q K'`` where they are not zero,
    and the substitution of the zero ones."""
    pairs = [*zip(der.rotor_rate, rotor_rate, strict=True)]
    pairs += [
        (der.inertia_rate[i, j], inertia_rate[i, j]) for i in range(3) for j in range(i, 3)
    ]
    pairs = [(x, sp.expand(e)) for x, e in pairs]
    zero = {x: sp.S.Zero for x, e in pairs if e == 0}  # (Idf21 is Idf12)
    return tuple((x, e) for x, e in pairs if e != 0), zero


def _no_spin(
    free: sp.Matrix, z: sp.Matrix, omega: sp.Matrix, n: sp.Matrix, ndot: sp.Matrix
) -> tuple[sp.Matrix, list[tuple[sp.Symbol, sp.Expr]]]:
    """``omega' = w + mu z`` with ``w`` the rate without the no-spin reaction, ``z = P^-1
    n`` and ``mu = -((omega, n') + (w, n))/(z, n)``: the auxiliaries ``w``, ``z``, ``mu``."""
    w, zs, mu = vector("w", real=True), vector("zr", real=True), sp.Symbol("mu", real=True)
    aux = [*zip(w, free, strict=True), *zip(zs, z, strict=True)]
    aux.append((mu, -(dot(omega, ndot) + dot(w, n)) / dot(zs, n)))
    return w + mu * zs, aux


def _potential_force(
    V: sp.Expr, omega: sp.Matrix, p: sp.Matrix, Q: sp.Matrix, p_rate: sp.Matrix
) -> tuple[sp.Matrix, list[tuple[sp.Symbol, sp.Expr]]]:
    """``tau = -(dp'/d omega)^T dV/dp - sum_i e_i x dV/de_i`` (the auxiliaries ``tau1..3``
    and the symbols, or zeros without a potential)."""
    if sp.sympify(V).is_zero:
        return sp.zeros(3, 1), []
    grad_p = sp.Matrix([sp.diff(V, c) for c in p])
    force = -p_rate.jacobian(omega).T * grad_p
    for i in range(3):
        e = Q[:, i]
        force -= cross(e, sp.Matrix([sp.diff(V, c) for c in e]))
    tau = vector("tau", real=True)
    return tau, [(tau[i], sp.expand(force[i])) for i in range(3)]


def _frame_aux(
    der: GeneralBallDerivation, offset: sp.Matrix, rotor: sp.Matrix, inertia: sp.Matrix
) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
    """``a_f``, ``K_f`` and ``I_f`` (upper triangle) in the axes' state symbols."""
    pairs = [*zip(der.offset, offset, strict=True), *zip(der.rotor, rotor, strict=True)]
    pairs += [(der.inertia[i, j], inertia[i, j]) for i in range(3) for j in range(i, 3)]
    return tuple((x, sp.expand(e)) for x, e in pairs)


def general_ball_description(
    support: sp.Expr,
    mass: sp.Expr,
    radius: sp.Expr,
    inertia: sp.Matrix,
    centre: sp.Matrix,
    rotor: sp.Matrix,
    *,
    side: int = 1,
    gravity: sp.Expr = sp.S.Zero,
    potential: sp.Expr = sp.S.Zero,
    rubber: bool = False,
    parameters: tuple[ParameterSpec, ...] = (),
    system: str = "ball_on_support",
) -> MechanicalDescription:
    """The description: state ``omega``, ``p``, the body axes ``e1, e2, e3`` (fixed frame).

    Parameters
    ----------
    support : sympy.Expr
        ``F`` in the contact point's symbols ``p1, p2, p3``.
    mass, radius : sympy.Expr
    inertia : sympy.Matrix
        Central inertia tensor, body axes.
    centre, rotor : sympy.Matrix
        ``a`` and ``K``, body axes.
    side : int
        1 outside, -1 inside.
    gravity : sympy.Expr
    potential : sympy.Expr
        ``V`` of the contact point ``p`` and the axes ``e1_1 .. e3_3`` (see
        :class:`GeneralBallReduction`).
    rubber : bool
        Rubber rolling (see :class:`GeneralBallReduction`).
    parameters : tuple of ParameterSpec
        Declared in this order.
    system : str

    Returns
    -------
    MechanicalDescription
    """
    omega = vector("omega", real=True)
    desc = MechanicalDescription(
        system=system,
        effects=frozenset(),
        time=sp.Symbol("t", real=True),
        omega=omega,
        reduction=GeneralBallReduction(
            support, mass, radius, inertia, centre, rotor, side=side, gravity=gravity,
            potential=sp.sympify(potential), rubber=rubber,
        ),  # fmt: skip
        parameter_order=tuple(spec.name for spec in parameters),
    )
    desc.add_state("omega", tuple(omega), None)
    p = vector("p", real=True)
    desc.add_state("p", tuple(p), None)
    if rubber:  # no spin about the normal: (omega, grad F) = 0, kept by the flow
        grad = sp.Matrix([sp.diff(support, c) for c in p])
        desc.add_invariant_relation("(omega,grad F)", sp.expand(dot(omega, grad)))
    add_axes(desc, parameters)
    return desc


def add_axes(desc: MechanicalDescription, parameters: tuple[ParameterSpec, ...]) -> None:
    """Add the body axes ``e1, e2, e3`` (fixed frame, ``e' = omega x e``) to the state of a
    fixed-frame description, then declare its parameters.

    Parameters
    ----------
    desc : MechanicalDescription
        With its angular velocity ``omega``.
    parameters : tuple of ParameterSpec
    """
    for name in AXES:  # body-fixed: e' = omega x e
        e = _axis(name)
        desc.add_state(name, tuple(e), list(cross(desc.omega, e)))
    for spec in parameters:
        desc.add_parameter(spec)


def general_ball_model(*args: Any, **kwargs: Any) -> Model:
    """Derive the model of :func:`general_ball_description` (the same arguments).

    Parameters
    ----------
    *args, **kwargs
        As :func:`general_ball_description`.

    Returns
    -------
    Model
        State ``omega, p, e1, e2, e3``; integrals ``H`` (when nothing depends on the time)
        and ``F``; the frame's constraints.
    """
    return form_model(general_ball_description(*args, **kwargs))
