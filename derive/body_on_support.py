"""A convex body ``f(x) = 0`` rolling on a fixed convex support surface ``F(p) = 0``.

The general ball on a support (:mod:`.ball_on_support_general`) with its spherical
surface replaced by any convex one. The state is the angular velocity ``omega`` and the
contact point ``p`` (fixed frame), the contact point ``r`` on the body (body axes, from
the centre of mass) and the body axes' fixed-frame components ``e1, e2, e3`` (the columns
of ``Q``, ``e_i' = omega x e_i``).

Derivation:

* the contact point seen from the centre of mass, fixed frame: ``rho = -Q r`` points from
  the contact to the centre of mass; no slip (the body's material point at the contact is
  at rest) makes the centre of mass's velocity ``v = omega x rho``; the fixed-frame
  Newton–Euler equations projected on these admissible velocities are the general ball's
  (:func:`~.ball_on_support_general.project_newton_euler`: ``P omega' = h``, ``P = I_f +
  m (|rho|^2 Id - rho rho^T)``) with the rate ``rho' = omega x rho - Q r'``;
* the contact point: ``p = X + Q r`` (``X`` the centre of mass) moves at ``p' = X' + omega
  x Q r + Q r' = Q r'`` (no slip): the contact slides over both surfaces at one velocity,
  ``r' = Q^T p'`` and ``rho' = omega x rho - p'``;
* the normals: ``nu = grad F/|grad F|`` (the support's, ``F < 0`` inside it), ``nu_b =
  grad f/|grad f|`` (the body's outward normal, body axes, ``f < 0`` inside the body);
  the body touches the support from outside, ``Q nu_b(r) = -nu(p)``, or from inside a
  concave support, ``Q nu_b(r) = nu(p)``: ``Q nu_b = -s nu`` with ``s = 1`` outside, ``-1``
  inside (``n = s nu`` points from the contact into the body, as the ball's). Its rate
  along the motion, ``omega x Q nu_b + Q (dnu_b/dr) Q^T p' = -s (dnu/dp) p'``, gives
  ``(C + s dnu/dp) p' = s omega x nu`` with ``C = Q (dnu_b/dr) Q^T``, whose normal
  component is ``0 = 0``; with ``p'`` tangent to the support, ``(nu, p') = 0``, the
  system solved is ``((Id - nu nu^T) C + s dnu/dp + nu nu^T) p' = s omega x nu``
  (adjugate over determinant). A sphere of radius ``b`` (``C = (Id - nu nu^T)/b``) gives
  the ball's ``(Id + s b dnu/dp) p' = b omega x n``.

The energy ``m (v, v)/2 + (omega, I_f omega)/2 + m g (p + rho)_3`` is an integral at every
point with ``Q`` a rotation (the reaction does no work; ``(p + rho)' = v``), the support's
level ``F(p)`` too (``(nu, p') = 0`` by construction), and on the normals' alignment
(which the flow keeps) so is the body's level ``f(r)``. Gravity along ``-e3``, a rotor
``K`` (constant or ``K(t)``), an inertia ``I(t)``, a potential ``V(p, e1, e2, e3)`` and rubber
rolling (``(omega, nu) = 0``) enter as in the general ball (its ``Q I' Q^T omega + Q K'``, the
torque ``-d(dV/dt)/d omega`` and the reaction ``mu nu``); with ``I(t)`` or ``K(t)`` there is
no energy integral.

:func:`aligned_sampler` draws exact points of the phase space (the normals aligned) when
the body or the support is a quadric: the verifier's sampling needs them.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass
from types import SimpleNamespace

import sympy as sp

from .ball_on_support import support_normal
from .ball_on_support_general import (
    AXES,
    FIXED_FRAME_REFUSED,
    GeneralBallEquations,
    _axis,
    _no_spin,
    _potential_force,
    _symmetric,
    _time_rates,
    add_axes,
    project_newton_euler,
)
from .body_on_sphere import _adjugate_and_det, outer_normal
from .description import MechanicalDescription, Reduced
from .geometry import FRAME, PoissonGroup
from .model import ParameterSpec
from .vectors import cross, vector

__all__ = [
    "BODY_AUX_NAMES",
    "BodyOnSupportEquations",
    "BodyOnSupportReduction",
    "aligned_sampler",
    "body_on_support_description",
]

#: The auxiliary symbols this derivation adds to the general ball's (a parameter must not
#: take them): the body's ``|grad f|``, normal and its Jacobian, that in the fixed frame, the
#: contact's system and ``rho``.
BODY_AUX_NAMES = frozenset(
    {f"{n}{i}{j}" for n in ("Dnb", "Cf", "Ac") for i in (1, 2, 3) for j in (1, 2, 3)}
    | {f"{n}{i}" for n in ("rg", "nb") for i in (1, 2, 3)}
    | {"gl"}
)


@dataclass
class BodyOnSupportEquations(GeneralBallEquations):
    """The derivation on a concrete support and body (the ``details`` of the model): the
    general ball's record (``derivation`` the dict of
    :func:`~.ball_on_support_general.project_newton_euler`) and the body's surface.

    Attributes
    ----------
    surface : sympy.Expr
        ``f(r)``.
    body_normal : sympy.Matrix
        ``nu_b(r) = grad f/|grad f|`` (body axes).
    """

    surface: sp.Expr
    body_normal: sp.Matrix


@dataclass(frozen=True)
class BodyOnSupportReduction:
    """A convex body ``f(r) = 0`` on the fixed support ``F(p) = 0``, fixed frame.

    Parameters
    ----------
    support : sympy.Expr
        ``F`` in the contact point's state symbols ``p1 .. p3``.
    surface : sympy.Expr
        ``f`` in the body's contact point ``r1 .. r3`` (body axes, from the centre of
        mass; ``f < 0`` inside the body).
    mass : sympy.Expr
    inertia : sympy.Matrix
        Central inertia tensor in body axes (constant, symmetric).
    rotor : sympy.Matrix
        A constant gyrostatic momentum ``K``, body axes.
    side : int
        1: outside the support (on the side of ``grad F``); -1: inside.
    gravity : sympy.Expr
        ``g`` of a field along ``-e3`` (0: none).
    potential : sympy.Expr
        ``V(p, e1, e2, e3)`` (the general ball's: its torque ``-d(dV/dt)/d omega``).
    rubber : bool
        No spin about the support's normal, ``(omega, nu) = 0`` (the reaction ``mu nu``).

    The inertia and the rotor may be functions of the time ``t`` (``Q I' Q^T omega`` and
    ``Q K'`` join the momentum's rate; no energy integral then).
    """

    support: sp.Expr
    surface: sp.Expr
    mass: sp.Expr
    inertia: sp.Matrix
    rotor: sp.Matrix
    side: int = 1
    gravity: sp.Expr = sp.S.Zero
    potential: sp.Expr = sp.S.Zero
    rubber: bool = False

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """``omega'``, ``p'`` and ``r'`` (the axes' rates are declared), the energy and the
        two levels.

        Parameters
        ----------
        desc : MechanicalDescription
            With the state groups ``omega``, ``p``, ``r`` and :data:`AXES`.

        Returns
        -------
        Reduced
            The frame geometry of :data:`AXES`; ``details`` a :class:`BodyOnSupportEquations`.

        Raises
        ------
        DerivationError
            For declared data this derivation does not take, or from
            :func:`~.ball_on_support_general.project_newton_euler`.
        """
        desc.refuse("body-on-support", FIXED_FRAME_REFUSED)
        omega, p, r = (desc.state_group(x) for x in ("omega", "p", "r"))
        Q = sp.Matrix.hstack(*(desc.state_group(e) for e in AXES))
        m, s = self.mass, self.side
        geometry = support_normal(self.support, p, s, sp.S.Zero)  # (its adjugate unused)
        nu, J, pdot = geometry.nu, geometry.curvature, geometry.pdot
        body_normal = -outer_normal(self.surface, r)  # grad f/|grad f|
        # d(grad f/|grad f|)/dr = (Id - nu_b nu_b^T) (Hessian of f)/|grad f|, in the
        # auxiliaries |grad f| (gl) and nu_b (nb): compact, no expanded square roots
        length, nb = sp.Symbol("gl", real=True), vector("nb", real=True)
        grad_f = sp.Matrix([sp.diff(self.surface, x) for x in r])
        body_aux = [(length, sp.sqrt(sp.factor_terms(sp.expand(grad_f.dot(grad_f)))))]
        body_aux += [*zip(nb, grad_f / length, strict=True)]
        hessian = sp.hessian(self.surface, list(r))
        Dnb = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Dnb{i + 1}{j + 1}", real=True))
        C = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Cf{i + 1}{j + 1}", real=True))
        A = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"Ac{i + 1}{j + 1}", real=True))
        tangent = sp.eye(3) - nu * nu.T
        system = tangent * C + s * J + nu * nu.T
        adjA, detA = _adjugate_and_det(A)
        p_rate = adjA * (s * cross(omega, nu)) / detA
        rho = vector("rg", real=True)  # -Q r: from the contact to the centre of mass
        core = project_newton_euler(m, self.gravity, omega, rho, cross(omega, rho) - pdot)
        If, Kf = core["inertia"], core["rotor"]
        t = desc.time
        rated = SimpleNamespace(inertia_rate=core["inertia_rate"], rotor_rate=core["rotor_rate"])
        timed, zero_rates = _time_rates(
            rated, Q * self.inertia.diff(t) * Q.T, Q * self.rotor.diff(t)
        )
        Pc, hc = _symmetric("Pc"), vector("hc", real=True)
        body_aux += _entries(Dnb, (sp.eye(3) - nb * nb.T) * hessian / length)
        aux = [*body_aux, *_entries(C, Q * Dnb * Q.T)]
        aux += [*zip(nu, geometry.normal, strict=True)]
        aux += [*_entries(J, geometry.normal.jacobian(p)), *_entries(A, system)]
        aux += [*zip(pdot, p_rate, strict=True), *zip(rho, -Q * r, strict=True)]
        aux += [*zip(Kf, Q * self.rotor, strict=True)]
        aux += [(If[i, j], (Q * self.inertia * Q.T)[i, j]) for i in range(3) for j in range(i, 3)]
        P = core["contact_inertia"].xreplace(zero_rates)
        aux += [*timed, *((Pc[i, j], P[i, j]) for i in range(3) for j in range(i, 3))]
        tau, force = _potential_force(self.potential, omega, p, Q, p_rate)
        aux += [*force, *zip(hc, core["forcing"].xreplace(zero_rates) + tau, strict=True)]
        adjP, detP = _adjugate_and_det(Pc)
        omega_rate = adjP * hc / detP
        if self.rubber:  # the reaction mu nu of (omega, nu) = 0 (nu' = J p')
            omega_rate, no_spin = _no_spin(omega_rate, adjP * (s * nu) / detP, omega, s * nu,
                                           s * J * pdot)  # fmt: skip
            aux += no_spin
        potential = m * self.gravity * (p[2] + rho[2]) + self.potential
        energy = core["kinetic_energy"] + potential
        level = sp.expand(self.surface - self.surface.xreplace(dict.fromkeys(r, 0)))
        frame_group = PoissonGroup(FRAME, AXES)
        details = BodyOnSupportEquations(
            support=self.support, surface=self.surface, normal=geometry.normal,
            body_normal=body_normal, side=s, rotation=Q, p_rate=p_rate,
            omega_rate=omega_rate, energy=energy, derivation=core,
        )  # fmt: skip
        return Reduced(
            rates={"omega": list(omega_rate), "p": list(pdot), "r": list(Q.T * pdot)},
            aux=tuple((x, sp.expand(e)) for x, e in aux),
            integrals=([] if timed else [("H", energy)]) + [("F", geometry.level), ("f", level)],
            density=None,
            constraints=frame_group.constraints({e: desc.state_group(e) for e in AXES}),
            geometry=(frame_group,),
            relation_unknowns=tuple(omega) if self.rubber else (),
            omega=omega,
            details=details,
        )


def _entries(symbols: sp.Matrix, values: sp.Matrix) -> list[tuple[sp.Symbol, sp.Expr]]:
    """The pairs ``(symbol, value)`` of two 3 x 3 matrices, row by row."""
    return [(symbols[i, j], values[i, j]) for i in range(3) for j in range(3)]


def aligned_sampler(
    support: sp.Expr, surface: sp.Expr, side: int
) -> Callable[[random.Random, dict], None] | None:
    """Exact points with the normals aligned, ``grad f(r) = -s c Q^T grad F(p)``, ``c > 0``:
    when the body is a quadric, ``r`` solves that linear system for a random ``p`` and
    frame; when the support is, ``p`` does for a random ``r``. Each surface through the
    point is a level set of ``f`` or ``F`` (the flow keeps every level).

    Parameters
    ----------
    support, surface : sympy.Expr
        ``F(p)`` and ``f(r)`` in the state symbols.
    side : int
        1 outside, -1 inside.

    Returns
    -------
    callable or None
        ``sampler(rng, point)`` writing ``p``, ``r`` and the axes into ``point`` (the
        parameters' values are there already); None when neither is a quadric.
    """
    p, r = vector("p", real=True), vector("r", real=True)
    quadric = {
        "r": sp.Poly(surface, *r).total_degree() == 2,
        "p": sp.Poly(support, *p).total_degree() == 2,
    }
    if not any(quadric.values()):
        return None
    frame = PoissonGroup(FRAME, AXES)

    def sample(rng: random.Random, point: dict) -> None:
        F, f = support.xreplace(point), surface.xreplace(point)
        axes = frame.sample_rational(rng)
        for name in AXES:
            point.update(zip(_axis(name), axes[name], strict=True))
        Q = sp.Matrix([axes[name] for name in AXES]).T
        draw = lambda: sp.Matrix([sp.Rational(rng.randint(-9, 9), rng.randint(1, 9))  # noqa: E731
                                  for _ in range(3)])  # fmt: skip
        scale = sp.Rational(rng.randint(1, 9), rng.randint(1, 9))
        if quadric["r"]:  # grad f(r) = H r + g0 = c d, d the body's outward normal
            at = draw()
            d = -side * Q.T * _gradient(F, p).xreplace(dict(zip(p, at, strict=True)))
            point.update(zip(p, at, strict=True))
            point.update(zip(r, _linear_point(f, r, scale * d), strict=True))
        else:  # grad F(p) = -s c Q grad f(r)
            at = draw()
            u = Q * _gradient(f, r).xreplace(dict(zip(r, at, strict=True)))
            point.update(zip(r, at, strict=True))
            point.update(zip(p, _linear_point(F, p, -side * scale * u), strict=True))

    return sample


def _gradient(q: sp.Expr, x: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([sp.diff(q, c) for c in x])


def _linear_point(q: sp.Expr, x: sp.Matrix, gradient: sp.Matrix) -> sp.Matrix:
    """The point where the quadric ``q``'s gradient is ``gradient``."""
    grad = _gradient(q, x)
    return grad.jacobian(x).LUsolve(gradient - grad.xreplace(dict.fromkeys(x, 0)))


def body_on_support_description(
    support: sp.Expr,
    surface: sp.Expr,
    mass: sp.Expr,
    inertia: sp.Matrix,
    rotor: sp.Matrix,
    *,
    side: int = 1,
    gravity: sp.Expr = sp.S.Zero,
    potential: sp.Expr = sp.S.Zero,
    rubber: bool = False,
    parameters: tuple[ParameterSpec, ...] = (),
    system: str = "body_on_support",
) -> MechanicalDescription:
    """The description: state ``omega``, ``p`` (fixed frame), ``r`` (body axes) and the
    body axes ``e1, e2, e3`` (fixed frame).

    Parameters
    ----------
    support : sympy.Expr
        ``F`` in the contact point's symbols ``p1, p2, p3``.
    surface : sympy.Expr
        ``f`` in the body's contact point ``r1, r2, r3`` from the centre of mass.
    mass : sympy.Expr
    inertia : sympy.Matrix
        Central inertia tensor, body axes.
    rotor : sympy.Matrix
        ``K``, body axes (constant or of ``t``; the inertia too).
    side : int
        1 outside, -1 inside.
    gravity : sympy.Expr
    potential : sympy.Expr
        ``V(p, e1, e2, e3)``.
    rubber : bool
        No spin about the support's normal (the invariant relation ``(omega, grad F)``).
    parameters : tuple of ParameterSpec
        Declared in this order.
    system : str

    Returns
    -------
    MechanicalDescription
        With :func:`aligned_sampler`'s sampler.
    """
    omega = vector("omega", real=True)
    desc = MechanicalDescription(
        system=system,
        effects=frozenset(),
        time=sp.Symbol("t", real=True),
        omega=omega,
        reduction=BodyOnSupportReduction(
            support, surface, mass, inertia, rotor, side=side, gravity=gravity,
            potential=sp.sympify(potential), rubber=rubber,
        ),  # fmt: skip
        parameter_order=tuple(spec.name for spec in parameters),
    )
    for name in ("omega", "p", "r"):
        desc.add_state(name, tuple(vector(name, real=True)), None)
    if rubber:  # no spin about the normal: (omega, grad F) = 0, kept by the flow
        grad = _gradient(support, vector("p", real=True))
        desc.add_invariant_relation("(omega,grad F)", sp.expand(grad.dot(omega)))
    add_axes(desc, parameters)
    desc.sampler = aligned_sampler(support, surface, side)
    return desc

