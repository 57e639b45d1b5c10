"""A rigid body rolling without slipping on a fixed sphere (M03 §2), body frame.

Not a built-in system (no generated code): the models here serve the claims of M03 §2.

Description: a body of mass ``m`` and central inertia ``I`` (scalar ``mu Id`` or a
diagonal tensor) with a convex surface ``f(r) = 0`` in body coordinates, ``r`` the vector
from the centre of mass ``G`` to the contact point ``Q``, ``n = -grad f/|grad f|``; it rolls
on a fixed sphere of radius ``R0``, ``k = +-1/R0`` (the sign from the configuration:
``Q = c - (1/k) n`` with ``c`` the sphere's centre, in body axes).

Derivation:

* contact kinematics — the contact point written twice, ``Q = G + r`` and
  ``Q = c - n/k``; differentiated in space (body-frame rates ``X' + omega x X``) with the
  no-slip condition ``v_G + omega x r = 0``, solved for ``n'``: ``k r' + n' = n x omega``;
  with ``n' = (dn/dr) r'`` (chain rule) this is ``(k Id + dn/dr) r' = n x omega``;
* dynamics — the body-frame Lagrange–d'Alembert engine (:mod:`.engine`) with
  ``T = (omega, I omega)/2 + m (v, v)/2``, the no-slip constraint ``v + omega x r = 0`` and
  ``r`` as the configuration the coefficients depend on, with an abstract rate ``r'``:
  the projected momentum ``M = I_Q omega``, ``I_Q = I + m r^2 Id - m r ⊗ r`` and its rate;
  then ``omega' = I_Q^-1 (M' - I_Q' omega)``.

:class:`BodyOnSphereReduction` is that derivation as the reduction stage of the shared
finishing step (:func:`~.description.form_model`); :func:`body_on_sphere_model` writes the
description (state ``omega, r``, the inertia tensor, parameters, phase-space constraint).

References
----------
M03-2.1 .. M03-2.5 (FORMULAS.md §4.2).
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass

import sympy as sp

from .algebra import seeded_factor
from .description import MechanicalDescription, Reduced, form_model
from .engine import (
    ReducedEquations,
    RigidBodyDescription,
    _time_derivative,
    lagrange_dalembert,
)
from .errors import DerivationError
from .geometry import FRAME
from .model import Model, ModelDetails, ParameterSpec
from .vectors import cross, dot, vector

__all__ = [
    "BodyOnSphere",
    "BodyOnSphereReduction",
    "PlaneMotion",
    "contact_normal_rate",
    "derive_body_on_sphere",
    "body_on_sphere_model",
    "outer_normal",
    "turning_frame_energy",
]


def contact_normal_rate(
    k: sp.Expr, r: sp.Matrix, r_rate: sp.Matrix, n: sp.Matrix, omega: sp.Matrix
) -> sp.Matrix:
    """``n'`` from the two expressions of the contact point and the no-slip condition.

    Parameters
    ----------
    k : sympy.Expr
        Signed curvature of the fixed sphere (``Q = c - n/k``).
    r, r_rate, n, omega : sympy.Matrix
        Body-frame vectors (``r_rate``, ``n`` may be abstract symbols).

    Returns
    -------
    sympy.Matrix
        ``n' = n x omega - k r'``.
    """
    v_G = vector("vG", real=True)
    n_rate = vector("nrate", real=True)
    # space rates in body axes: d/dt (G + r) and d/dt (c - n/k), c fixed
    lhs = v_G + r_rate + cross(omega, r)
    rhs = -(n_rate + cross(omega, n)) / k
    no_slip = {v_G[i]: (-cross(omega, r))[i] for i in range(3)}
    sol = sp.solve(list((lhs - rhs).xreplace(no_slip)), list(n_rate), dict=True)
    (s,) = sol
    return sp.Matrix([sp.expand(s[c]) for c in n_rate])


def _adjugate_and_det(A: sp.Matrix) -> tuple[sp.Matrix, sp.Expr]:
    """Adjugate and determinant of a 3x3 matrix by cofactors, without simplification."""

    def cofactor(i: int, j: int) -> sp.Expr:
        (a, b), (c, d) = ([A[p, q] for q in range(3) if q != j] for p in range(3) if p != i)
        return (-1) ** (i + j) * (a * d - b * c)

    cof = sp.Matrix(3, 3, cofactor)
    det = sum((A[0, j] * cof[0, j] for j in range(3)), sp.S.Zero)
    return cof.T, det


@dataclass(frozen=True)
class PlaneMotion:
    """How the plane under a convex body moves, and whether the body may twist on it.

    Parameters
    ----------
    rotation_rate : sympy.Expr
        ``Omega``, a constant or a function of ``t``: the plane turns about the fixed
        vertical axis through the point the carried position ``rho`` is measured from.
    velocity : sympy.Matrix or None, shape (2, 1)
        ``(V1, V2)`` along the fixed horizontal axes ``alpha, beta`` (Poisson vectors).
    no_twist : bool
        Rubber rolling: ``(omega, n) = Omega``.
    along_line : bool
        Rolling along the line ``alpha`` of the plane: ``(omega, alpha) = 0`` (BKM12-57's
        constraint; the axes ``alpha, beta`` join the configuration: fixed in space, or on a
        rotating plane carried by it, ``X' = X x omega + Omega n x X``).
    """

    rotation_rate: sp.Expr = sp.S.Zero
    velocity: sp.Matrix | None = None
    no_twist: bool = False
    along_line: bool = False

    @property
    def moves(self) -> bool:
        """Whether the plane turns or moves (then the energy is not an integral)."""
        return self.rotation_rate != 0 or (
            self.velocity is not None and not self.velocity.is_zero_matrix
        )

    def velocity_at_contact(self, n: sp.Matrix) -> sp.Matrix:
        """The plane's velocity under the contact point (body axes): ``Omega n x rho + V1
        alpha + V2 beta`` (the carried ``rho`` and fixed axes ``alpha, beta``).

        Parameters
        ----------
        n : sympy.Matrix, shape (3, 1)
            The upward normal at the contact, body axes.

        Returns
        -------
        sympy.Matrix, shape (3, 1)
        """
        carried = self.rotation_rate * cross(n, vector("rho", real=True))
        if self.velocity is not None:
            for name, V in zip(("alpha", "beta"), self.velocity, strict=True):
                carried += V * vector(name, real=True)
        return carried

    def kinematics(
        self, n: sp.Matrix, omega: sp.Matrix, r: sp.Matrix, r_dot: sp.Matrix
    ) -> tuple[dict[str, tuple[sp.Matrix, sp.Matrix]], sp.Matrix]:
        """The configuration vectors with their body-frame rates, and the plane's velocity
        at the contact.

        On a rotating plane the contact point's position from the axis ``rho`` joins:
        the contact point moves in space at ``v + r' + omega x r`` = ``Omega n x rho + r'``
        (no slip), so ``rho' = Omega n x rho + r' + rho x omega``; on a moving plane the
        fixed axes ``alpha, beta`` (``X' = X x omega``); along a line its axes ``alpha,
        beta`` (on a rotating plane carried: ``X' = X x omega + Omega n x X``).

        Parameters
        ----------
        n, omega, r, r_dot : sympy.Matrix
            The upward normal ``n(r)``, the angular velocity, the contact point from the
            centre of mass and its (abstract) rate, body axes.

        Returns
        -------
        kinematics : dict of str to (sympy.Matrix, sympy.Matrix)
        carried : sympy.Matrix, shape (3, 1)
            ``Omega n x rho + V1 alpha + V2 beta``.
        """
        kinematics = {"r": (r, r_dot)}
        carried = sp.zeros(3, 1)
        if self.rotation_rate != 0:
            rho = vector("rho", real=True)
            carried += self.rotation_rate * cross(n, rho)
            kinematics["rho"] = (rho, carried + r_dot + cross(rho, omega))
        moving = self.velocity is not None and not self.velocity.is_zero_matrix
        if moving or self.along_line:  # the fixed axes (X' = X x omega), or the line's
            velocity = self.velocity if moving else sp.zeros(2, 1)
            for name, V in zip(("alpha", "beta"), velocity, strict=True):
                X = vector(name, real=True)  # a turntable's line turns at Omega n x X too
                kinematics[name] = (X, cross(X, omega) + self.rotation_rate * cross(n, X))
                carried += V * X
        return kinematics, carried

    def jacobi_integral(
        self,
        eq: BodyOnSphere,
        inertia: sp.Matrix,
        m: sp.Expr,
        gravity: sp.Expr,
        gyrostat: sp.Matrix | None,
    ) -> sp.Expr | None:
        """The energy in the frame turning with the plane, ``E - Omega (n, L_O)`` (``E`` with
        the potential ``V(n)``), for a constant ``Omega`` (``L_O`` the angular momentum
        about the axis: ``I omega + K + m (rho - r) x v``); None on a moving plane, for
        ``Omega(t)`` and along a line (it holds on ``(omega, alpha) = 0``, but the line's
        reaction does work off that level of the state ``omega``).

        Parameters
        ----------
        eq : BodyOnSphere
        inertia : sympy.Matrix
            The central inertia tensor (constant).
        m, gravity : sympy.Expr
        gyrostat : sympy.Matrix or None

        Returns
        -------
        sympy.Expr or None
        """
        Omega, t = self.rotation_rate, sp.Symbol("t", real=True)
        if Omega == 0 or Omega.has(t) or (self.velocity is not None and any(self.velocity)):
            return None
        if self.along_line:  # J holds on (omega, alpha) = 0 only: not a relation of this state
            return None
        K = sp.zeros(3, 1) if gyrostat is None else gyrostat
        # the potential of the orientation to the vertical: the turning keeps it
        V = eq.potential - m * gravity * dot(eq.r, eq.normal)
        return turning_frame_energy(inertia, m, K, eq.omega, eq.r, eq.normal, Omega, V)


def turning_frame_energy(
    inertia: sp.Matrix, m: sp.Expr, gyrostat: sp.Matrix, omega: sp.Matrix, r: sp.Matrix,
    n: sp.Matrix, Omega: sp.Expr, potential: sp.Expr,
) -> sp.Expr:  # fmt: skip
    """A body's energy in the frame of a plane turning at the constant rate ``Omega``,
    ``J = E - Omega (n, I omega + K + m (rho - r) x v)`` with ``v = r x omega + Omega n x
    rho`` the centre of mass's velocity (no slip) and ``rho`` the carried contact position:
    the no-slip constraint is homogeneous in the turning frame's velocities.

    Parameters
    ----------
    inertia, m, gyrostat : sympy.Matrix, sympy.Expr, sympy.Matrix
        The constant central inertia tensor, the mass and ``K``.
    omega, r, n : sympy.Matrix
        The angular velocity, the contact point from the centre of mass and the upward
        normal, body axes.
    Omega, potential : sympy.Expr
        The rate and the potential energy (gravity's and the given one).

    Returns
    -------
    sympy.Expr
    """
    rho = vector("rho", real=True)
    v = cross(r, omega) + Omega * cross(n, rho)
    energy = (omega.T * inertia * omega)[0] / 2 + m * dot(v, v) / 2 + potential
    return energy - Omega * dot(n, inertia * omega + gyrostat + m * cross(rho - r, v))


@dataclass
class BodyOnSphere:
    """Derived equations of a body rolling on a sphere (in ``omega, r`` and ``r'``).

    Attributes
    ----------
    reduced : ReducedEquations
        The engine's output (``r'`` abstract: the symbols :attr:`r_rate_symbols`).
    inertia_operator : sympy.Matrix
        ``I_Q`` (``M = I_Q omega``).
    omega_rate : sympy.Matrix
        ``omega'`` in ``omega, r`` and the abstract ``r'``.
    normal, normal_jacobian : sympy.Matrix
        ``n(r) = -grad f/|grad f|`` and ``dn/dr``.
    r_rate : sympy.Matrix
        ``r' = (k Id + dn/dr)^-1 (n x omega)`` in the state.
    energy : sympy.Expr
        ``T + V`` on the admissible velocities (an integral on a fixed support with ``T``
        free of time).
    multipliers : tuple of (sympy.Symbol, sympy.Expr)
        The reaction ``mu`` of no twist (rubber) in the state and ``r'``; empty otherwise.
    plane : PlaneMotion
        The plane's motion the equations were derived for.
    kinematics : dict
        The engine's configuration vectors and their rates (``r``, ``rho``, ``alpha``,
        ``beta``).
    potential : sympy.Expr
        The given potential of the orientation ``V(n)`` in the state (part of ``energy``).
    """

    omega: sp.Matrix
    r: sp.Matrix
    r_rate_symbols: sp.Matrix
    reduced: ReducedEquations
    inertia_operator: sp.Matrix
    omega_rate: sp.Matrix
    normal: sp.Matrix
    normal_jacobian: sp.Matrix
    r_rate: sp.Matrix
    energy: sp.Expr
    multipliers: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()
    plane: PlaneMotion | None = None
    kinematics: dict | None = None
    potential: sp.Expr = sp.S.Zero


def derive_body_on_sphere(
    surface: sp.Expr,
    inertia: sp.Matrix,
    m: sp.Expr,
    k: sp.Expr,
    omega: sp.Matrix,
    r: sp.Matrix,
    gyrostat: sp.Matrix | None = None,
    gravity: sp.Expr = sp.S.Zero,
    plane: PlaneMotion | None = None,
    potential: tuple[sp.Expr, sp.Matrix] | None = None,
    vertical: sp.Matrix | None = None,
) -> BodyOnSphere:
    """Derive the equations of a body with surface ``f(r) = 0`` rolling on a sphere.

    With ``k = 0`` the support is a fixed plane: ``n`` is fixed in space (``n' = n x
    omega``) and the contact point stays on the surface (``(n, r') = 0``), so ``(dn/dr +
    n n^T) r' = n x omega``; a field ``g`` along ``-n`` (gravity) acts at the centre of
    mass, ``V = -m g (r, n)`` (the height of the centre of mass above the plane). On a
    sphere (``k != 0``) the field is along ``-zeta``, the given ``vertical`` (fixed in
    space: ``zeta' = zeta x omega``), and the centre of mass is at ``-n/k - r`` from the
    sphere's centre: ``V = -m g (r + n/k, zeta)``.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(r)`` (polynomial, or an undefined Function of ``r``).
    inertia : sympy.Matrix
        Central inertia tensor (body frame).
    m, k : sympy.Expr
        Mass and signed curvature ``+-1/R0`` of the fixed sphere.
    omega, r : sympy.Matrix
        State symbols.
    gyrostat : sympy.Matrix, optional
        A gyrostatic momentum ``K``: ``T`` gains ``(K, omega)``; constant or a function
        of the time ``t`` (rotors whose motors set it).
    gravity : sympy.Expr, optional
        ``g`` of a field along the downward vertical (``-n`` on a plane, ``-zeta`` on a
        sphere).
    plane : PlaneMotion, optional
        How the plane moves (``k = 0`` only): the no-slip constraint becomes affine, the
        body's contact point moving with the plane's point under it, and a rubber body
        does not twist relative to it. ``inertia`` may depend on ``t`` (``I(t)``). On a
        sphere a fixed one only (``no_twist``: a rubber body, ``(omega, n) = 0``).
    potential : (sympy.Expr, sympy.Matrix), optional
        A potential of the orientation ``V(gamma)`` and its vector ``gamma`` (the support's
        normal ``n`` in body axes; on a sphere also of the ``vertical``'s symbols): the
        torque doing the work ``-dV`` along the admissible motions (on a plane ``n x
        dV/dn``; on a sphere ``n x dV/dn + k L^T dV/dn + zeta x dV/dzeta`` with ``r' = L
        omega``: the normal turns at ``n x omega - k r'``), ``V`` in the energy.
    vertical : sympy.Matrix, optional
        The upward vertical ``zeta`` in body axes, a state (on a sphere, for a field).

    Returns
    -------
    BodyOnSphere
        The derived kinematics, momentum balance and energy.

    Raises
    ------
    ValueError
        For a moving support on a sphere (``k != 0``), a field on a sphere without the
        vertical, or a vertical on a plane.
    """
    t, v, r_dot = sp.Symbol("t", real=True), vector("v", real=True), vector("rdot", real=True)
    T = (omega.T * inertia * omega)[0] / 2 + m * dot(v, v) / 2
    if gyrostat is not None:
        T += dot(gyrostat, omega)
    n = outer_normal(surface, r)
    _check_support(k, gravity, plane, vertical)
    plane = plane or PlaneMotion()
    nu = vector("nu", real=True)
    kinematics, constraints = _engine_kinematics(plane, k, nu, omega, v, r, r_dot, vertical)
    to_n = dict(zip(nu, n, strict=True))
    Dn = n.jacobian(r)
    r_rate = _contact_rate(k, n, Dn, omega, r, r_dot)
    L = sp.zeros(3, 3) if potential is None or k == 0 else r_rate.jacobian(omega)  # r' = L omega
    V, torque, lag = _orientation_load(potential, nu, vertical, k * L)
    up = n if k == 0 else vertical if vertical is not None else sp.zeros(3, 1)
    desc = RigidBodyDescription(omega=omega, v=v, kinetic_energy=T, constraints=constraints,
                                kinematics=kinematics, time=t, force=-m * gravity * up,
                                torque=torque)  # fmt: skip
    red = lagrange_dalembert(desc)
    red.momentum = red.momentum.xreplace(to_n)
    red.momentum_rate = red.momentum_rate.xreplace(lag).xreplace(to_n)
    red.gyrostatic_momentum = red.gyrostatic_momentum.xreplace(to_n)
    II = red.inertia_operator
    II_rate = II.applyfunc(lambda e: _time_derivative(e, kinematics, t))  # r' and I'(t)
    adj, det = _adjugate_and_det(II)
    det = seeded_factor(det)
    omega_rate = adj * (red.momentum_rate - II_rate * omega) / det
    multipliers: tuple[tuple[sp.Symbol, sp.Expr], ...] = ()
    if red.omega_multipliers:  # eliminated from d/dt ((omega, n) - Omega) = 0
        free = red.momentum_rate.xreplace(dict.fromkeys(red.omega_multipliers, 0))
        solved = red.multiplier_solution(free, lambda u: adj * u / det)
        multipliers = tuple((mu, e.xreplace(to_n)) for mu, e in solved.items())
    kinematics.pop("nu", None)
    kinematics = {name: (X, rate.xreplace(to_n)) for name, (X, rate) in kinematics.items()}
    # minus the height of the centre of mass above the plane, or above the sphere's centre
    depth = dot(r, n) if k == 0 else dot(r + n / k, up)
    return BodyOnSphere(
        omega=omega,
        r=r,
        r_rate_symbols=r_dot,
        reduced=red,
        inertia_operator=II,
        omega_rate=omega_rate,
        normal=n,
        normal_jacobian=Dn,
        r_rate=r_rate,
        energy=red.energy - m * gravity * depth + V.xreplace(to_n),
        multipliers=multipliers,
        plane=plane,
        kinematics=kinematics,
        potential=V.xreplace(to_n),
    )


def outer_normal(surface: sp.Expr, r: sp.Matrix) -> sp.Matrix:
    """The unit normal ``-grad f/|grad f|`` of a body's surface at ``r`` (out of the body
    into the support: ``f < 0`` inside), its radicand in one canonical form.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(r)``.
    r : sympy.Matrix, shape (3, 1)

    Returns
    -------
    sympy.Matrix, shape (3, 1)
    """
    grad = sp.Matrix([sp.diff(surface, s) for s in r])
    q = sp.sqrt(sp.factor_terms(sp.expand(dot(grad, grad))))
    return (-grad / q).applyfunc(sp.factor_terms)


def _engine_kinematics(
    plane: PlaneMotion, k: sp.Expr, nu: sp.Matrix, omega: sp.Matrix, v: sp.Matrix,
    r: sp.Matrix, r_dot: sp.Matrix, vertical: sp.Matrix | None,
) -> tuple[dict[str, tuple[sp.Matrix, sp.Matrix]], list[sp.Expr]]:  # fmt: skip
    """The engine's configuration vectors with their rates, and the constraints: no slip
    (the plane's velocity at the contact), no twist for a rubber body. The normal is handed
    to the engine as the vector ``nu`` (on a plane fixed in space, ``nu' = nu x omega``, on
    a sphere ``nu' = nu x omega - k r'``: ``(dn/dr) r'`` either way), put back as ``n(r)``
    after: no square roots in its solve; the vertical is fixed in space."""
    kinematics, carried = plane.kinematics(nu, omega, r, r_dot)
    constraints = list(v + cross(omega, r) - carried)
    if plane.no_twist:  # (omega, n) = Omega: no twist relative to the plane
        constraints.append(dot(omega, nu) - plane.rotation_rate)
    if plane.along_line:  # no spin about the fixed line alpha
        constraints.append(dot(omega, kinematics["alpha"][0]))
    if set(kinematics) != {"r"} or plane.no_twist:
        rate = cross(nu, omega) if k == 0 else contact_normal_rate(k, r, r_dot, nu, omega)
        kinematics["nu"] = (nu, rate)
    if vertical is not None:
        kinematics["zeta"] = (vertical, cross(vertical, omega))
    return kinematics, constraints


def _check_support(k: sp.Expr, gravity: sp.Expr, plane: PlaneMotion | None,
                   vertical: sp.Matrix | None) -> None:  # fmt: skip
    """Refuse (ValueError) a moving sphere, a field on a sphere without the vertical and
    a vertical on a plane (where it is the normal)."""
    if k == 0:
        if vertical is not None:
            raise ValueError("on a plane (k = 0) the vertical is the normal: no vertical")
        return
    moving = plane is not None and (
        plane.rotation_rate != 0 or (plane.velocity is not None and any(plane.velocity))
    )
    if moving:
        raise ValueError("a moving support: on a plane (k = 0) only")
    if gravity != 0 and vertical is None:
        raise ValueError("a field on a sphere (k != 0) needs the vertical")


def _orientation_load(
    potential: tuple[sp.Expr, sp.Matrix] | None, nu: sp.Matrix, vertical: sp.Matrix | None,
    lag: sp.Matrix,
) -> tuple[sp.Expr, sp.Matrix, dict[sp.Symbol, sp.Expr]]:  # fmt: skip
    """``V(nu, zeta)`` and its torque for a potential of the orientation given in its
    vector (``nu`` the normal, ``zeta`` the vertical); zero for none.

    Along the admissible motions ``dV/dt = (dV/dnu, nu') + (dV/dzeta, zeta x omega)`` with
    ``nu' = nu x omega - k r'`` (:func:`contact_normal_rate`; ``k = 0`` on a plane) and
    ``r' = L omega`` (``lag`` is ``k L``): the torque ``-d(dV/dt)/d omega`` is ``nu x
    dV/dnu + zeta x dV/dzeta + k L^T dV/dnu`` (on a sphere of radius ``b`` written as a
    surface, ``s nu x dV/dnu`` with the spherical body's ``s``). The last term stands in
    the torque as the placeholder ``w`` (the engine expands the torque; ``L`` has the
    contact's determinant in its denominator): the returned mapping puts it back.
    """
    if potential is None:
        return sp.S.Zero, sp.zeros(3, 1), {}
    V = potential[0].xreplace(dict(zip(potential[1], nu, strict=True)))
    dV = sp.Matrix([sp.diff(V, x) for x in nu])
    torque = cross(nu, dV)
    if vertical is not None:
        torque += cross(vertical, sp.Matrix([sp.diff(V, x) for x in vertical]))
    if lag.is_zero_matrix or dV.is_zero_matrix:
        return V, torque, {}
    w = vector("w", real=True)
    return V, torque + w, dict(zip(w, lag.T * dV, strict=True))


def _contact_rate(k: sp.Expr, n: sp.Matrix, Dn: sp.Matrix, omega: sp.Matrix, r: sp.Matrix,
                  r_dot: sp.Matrix) -> sp.Matrix:  # fmt: skip
    """``r'`` in the state: on a plane ``n' = n x omega`` with ``r'`` tangent to the surface,
    on a sphere ``(k Id + dn/dr) r' = n x omega`` (contact_normal_rate, ``n' = (dn/dr) r'``;
    solved with an abstract normal, then ``n(r)``: the solve would rewrite ``|grad f|`` as
    the square root of a multiple of its radicand, a second radicand for the verifier)."""
    if k == 0:
        equations = Dn * r_dot - cross(n, omega) + n * dot(n, r_dot)
    else:
        nu = vector("nu", real=True)
        rate = contact_normal_rate(k, r, r_dot, nu, omega)
        equations = Dn * r_dot - rate.xreplace(dict(zip(nu, n, strict=True)))
    system = equations.jacobian(r_dot)
    source = -equations.xreplace(dict.fromkeys(r_dot, 0))
    adj, det = _adjugate_and_det(system)
    return adj * source / det


@dataclass(frozen=True)
class BodyOnSphereDetails(ModelDetails):
    """Derived objects of :func:`body_on_sphere_model` (``Model.details``).

    Attributes
    ----------
    equations : BodyOnSphere
        The derivation.
    surface : sympy.Expr
        ``f(r)`` of the body's surface.
    inertia : sympy.Matrix, shape (3, 3)
        Central inertia tensor of the body.
    """

    equations: BodyOnSphere
    surface: sp.Expr
    inertia: sp.Matrix


@dataclass(frozen=True)
class BodyOnSphereReduction:
    """A body with surface ``f(r) = 0`` rolling on a fixed sphere, in the body frame.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(r)`` in the position's state symbols.
    mass, curvature : sympy.Symbol
        ``m`` and the signed curvature ``k = +-1/R0`` (``0``: a fixed plane).
    angular_velocity, position : str
        The state groups ``omega`` and ``r`` (their rates are derived).
    gyrostat : sympy.Matrix, optional
        A gyrostatic momentum, constant or of the time ``t``.
    gravity : sympy.Expr
        ``g`` of a field along ``-n`` on a plane, ``-zeta`` on a sphere.
    plane : PlaneMotion, optional
        A moving plane (``curvature`` 0): the state groups ``rho`` (rotating) or
        ``alpha, beta`` (moving) are derived too; on a sphere a fixed one (rubber).
    potential : (sympy.Expr, sympy.Matrix), optional
        A potential of the orientation ``V(gamma)`` and its ``gamma`` (on a sphere also
        of ``zeta``).
    vertical : bool
        On a sphere: the state group ``zeta``, the upward vertical in body axes (its rate
        ``zeta x omega`` is derived), which a field or the potential needs.
    """

    surface: sp.Expr
    mass: sp.Symbol
    curvature: sp.Expr
    angular_velocity: str = "omega"
    position: str = "r"
    gyrostat: sp.Matrix | None = None
    gravity: sp.Expr = sp.S.Zero
    plane: PlaneMotion | None = None
    potential: tuple[sp.Expr, sp.Matrix] | None = None
    vertical: bool = False

    def reduce(self, desc: MechanicalDescription) -> Reduced:
        """``omega'`` and ``r'`` (an auxiliary ``rdot``), the carried groups' rates and
        the integrals; no density.

        The energy ``H`` is shipped on a fixed support with ``T`` free of time; on a
        plane turning at a constant rate the energy in its frame ``J``
        (:meth:`PlaneMotion.jacobi_integral`; rolling, not rubber); a rubber body's
        ``(omega,gamma)`` (``(omega, n) - Omega``, zero on the phase space); on a moving
        plane the frame's products with itself and with ``n``; the vertical's ``(zeta,
        zeta)``; then the description's invariant relations.

        Parameters
        ----------
        desc : MechanicalDescription
            With the body's ``inertia`` and the state groups :attr:`angular_velocity`,
            :attr:`position` (and ``rho`` or ``alpha, beta`` on a moving plane, ``zeta``
            with :attr:`vertical`).

        Returns
        -------
        Reduced
            ``details`` a :class:`BodyOnSphereDetails`.

        Raises
        ------
        DerivationError
            For declared data this derivation does not take (further kinetic-energy
            terms, a potential, velocity constraints, vectors that are not fixed in space,
            further bodies).
        """
        desc.refuse(
            "body-on-sphere",
            ("kinetic_energy", "potential", "constraints", "momentum_in_state")
            + ("bodies", "positions"),
        )
        for name, (X, rate) in desc.kinematics.items():  # only vectors fixed in space
            if not (rate - cross(X, desc.omega)).applyfunc(sp.expand).is_zero_matrix:
                raise DerivationError(
                    f"{desc.system}: body-on-sphere takes vectors fixed in space only, not "
                    f"{name!r} turning at {list(rate)}"
                )
        omega = desc.state_group(self.angular_velocity)
        r = desc.state_group(self.position)
        eq = derive_body_on_sphere(
            self.surface, desc.inertia, self.mass, self.curvature, omega, r,
            gyrostat=self.gyrostat, gravity=self.gravity, plane=self.plane,
            potential=self.potential,
            vertical=desc.state_group("zeta") if self.vertical else None,
        )  # fmt: skip
        rdot = eq.r_rate_symbols
        rates = {self.angular_velocity: list(eq.omega_rate), self.position: list(rdot)}
        carried = {n: X for n, X in eq.kinematics.items() if n != "r"}
        rates.update({n: list(eq.kinematics[n][1]) for n in carried})
        return Reduced(
            rates=rates,
            aux=tuple(zip(rdot, eq.r_rate, strict=True)) + eq.multipliers,
            integrals=self._integrals(desc, eq) + sorted(desc.invariant_relations.items()),
            density=None,
            omega=omega,
            relation_unknowns=tuple(s for X, _ in carried.values() for s in X),
            # on a sphere with the trace: the fixed frame alpha, beta, zeta (completed, sampled)
            geometry=tuple(g for g in desc.geometry() if g.kind == FRAME),
            details=BodyOnSphereDetails(equations=eq, surface=self.surface, inertia=desc.inertia),
        )

    def _integrals(self, desc: MechanicalDescription, eq: BodyOnSphere) -> list:
        plane = eq.plane or PlaneMotion()
        t = desc.time
        timed = desc.inertia.has(t) or (self.gyrostat is not None and self.gyrostat.has(t))
        moves = plane.moves
        integrals = []
        if not timed and not moves:
            integrals.append(("H", eq.energy))
        J = plane.jacobi_integral(eq, desc.inertia, self.mass, self.gravity, self.gyrostat)
        # (a rubber body's J holds on (omega, n) = Omega only, which is not a relation
        # of the state here: not shipped)
        if J is not None and not timed and not plane.no_twist:
            integrals.append(("J", sp.expand(J)))
        if plane.no_twist:
            integrals.append(("(omega,gamma)", dot(eq.omega, eq.normal) - plane.rotation_rate))
        frame = {n: X for n, (X, _) in (*desc.kinematics.items(), *eq.kinematics.items())}
        if plane.along_line:  # the constraint, kept by the flow (zero on the phase space)
            integrals.append(("(omega,alpha)", dot(eq.omega, frame["alpha"])))
        if "alpha" in frame:  # with the plane's normal, or on a sphere the vertical zeta
            a, b = frame["alpha"], frame["beta"]
            integrals += [("(alpha,alpha)", dot(a, a)), ("(alpha,beta)", dot(a, b))]
            integrals += [("(beta,beta)", dot(b, b))]
            if self.curvature == 0:
                integrals += [("(alpha,gamma)", dot(a, eq.normal))]
                integrals += [("(beta,gamma)", dot(b, eq.normal))]
            else:
                integrals += [("(zeta,alpha)", dot(frame["zeta"], a))]
                integrals += [("(zeta,beta)", dot(frame["zeta"], b))]
        if "zeta" in frame:
            zeta = frame["zeta"]
            integrals.append(("(zeta,zeta)", dot(zeta, zeta)))
        traced = {g.name: g.symbols for g in desc.states if g.name in ("x", "y")}
        if traced and "rho" in eq.kinematics:  # the trace is the carried rho's projection
            rho = eq.kinematics["rho"][0]
            for u, X in (("x", "alpha"), ("y", "beta")):
                integrals.append((f"{u}-(rho,{X})", traced[u][0] - dot(rho, frame[X])))
        return integrals


def body_on_sphere_model(
    surface: sp.Expr,
    inertia: sp.Matrix,
    parameters: tuple[ParameterSpec, ...],
    effects: tuple[str, ...] = (),
    constraints: tuple[sp.Expr, ...] = (),
    sampler: Callable[[random.Random, dict[sp.Symbol, sp.Rational]], None] | None = None,
) -> Model:
    """Model with state ``omega, r`` (``r'`` an auxiliary ``rdot``); density left to claims.

    Parameters
    ----------
    surface : sympy.Expr
        ``f(r)`` in the symbols ``r1, r2, r3``.
    inertia : sympy.Matrix, shape (3, 3)
        Central inertia tensor ``I``.
    parameters : tuple of ParameterSpec
        The parameters the surface and inertia use (``m``, ``k`` come first).
    effects : tuple of str
        Labels of the variant (for its name).
    constraints : tuple of sympy.Expr
        Polynomials vanishing on the phase space (the body surface ``f = 0``).
    sampler : callable, optional
        Exact rational sampler of the surface (``Model.sampler``).

    Returns
    -------
    Model
        System ``"body_on_sphere"``: state ``omega1..3, r1..3``, energy ``H`` as the only
        integral, no density; ``details`` carry the :class:`BodyOnSphere` equations,
        the surface and the inertia.

    References
    ----------
    M03-2.1, M03-2.2, M03-2.3
    """
    omega, r = vector("omega", real=True), vector("r", real=True)
    m, k = sp.Symbol("m", positive=True), sp.Symbol("k", real=True)
    desc = MechanicalDescription(
        system="body_on_sphere",
        effects=frozenset(effects),
        time=sp.Symbol("t", real=True),
        omega=omega,
        reduction=BodyOnSphereReduction(surface, m, k),
        parameter_order=("m", "k", *(spec.name for spec in parameters)),
        inertia=inertia,
    )
    desc.add_state("omega", tuple(omega), None)
    desc.add_state("r", tuple(r), None)
    desc.add_parameter(ParameterSpec("m", (m,), "positive", "mass of the body"))
    desc.add_parameter(
        ParameterSpec("k", (k,), "real", "signed curvature +-1/R0 of the fixed sphere")
    )
    for spec in parameters:
        desc.add_parameter(spec)
    for c in constraints:
        desc.add_phase_space_constraint(c)
    desc.sampler = sampler
    return form_model(desc)
