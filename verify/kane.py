"""Independent cross-check of the Chaplygin ball through ``sympy.physics.mechanics.KanesMethod``.

The same physical system as :func:`chaplygin.derive.build_model` ``("chaplygin_ball")`` is set
up again from scratch with Kane's method, sharing no code and no formula with our
Lagrange–d'Alembert engine:

* **Frames and coordinates.** ``N`` is the inertial frame, ``N.z`` pointing up, the plane
  ``z = 0``. The body frame ``B`` (principal axes) is oriented by body-fixed 3-2-1 Euler angles
  ``q1`` (yaw about ``N.z``), ``q2`` (pitch about the new ``y``), ``q3`` (roll about the new
  ``x``). The centre ``O`` (= centre of mass) sits at ``x N.x + y N.y + b N.z``. Generalised
  coordinates ``(q1, q2, q3, x, y)``.
* **Speeds.** ``u1, u2, u3`` are the body-frame components of the angular velocity of ``B`` in
  ``N`` (independent speeds); ``u4, u5`` the horizontal components of the velocity of ``O``
  (dependent speeds).
* **Constraints.** Rolling without slipping: the material point of the ball at the contact
  point ``P = O - b N.z`` has zero velocity; its two horizontal components are passed to
  ``KanesMethod`` as ``velocity_constraints`` with ``u_dependent=[u4, u5]`` (the vertical
  component vanishes identically because ``O`` moves horizontally).
* **Loads.** Gravity ``-m g N.z`` at ``O`` *is* included. Its generalised active forces vanish
  identically (the partial velocities of ``O`` are horizontal), so it does not change the
  dynamics of the balanced ball, as expected; the contact force is non-working and never
  appears in Kane's equations.

Kane's equations (3 dynamical equations + 2 differentiated constraints) are formed
symbolically once, lambdified, and solved numerically (a 5 x 5 linear solve) for
``(u1', u2', u3', u4', u5')``. Since ``u1..u3`` are body-frame components, ``(u1', u2', u3')`` is
the body-frame angular acceleration ``omega_dot`` that
:func:`chaplygin.verify.kane_samples.model_angular_acceleration`
computes from our model as ``(d omega / d(M, gamma)) . (M', gamma')``.

The state ``(M, gamma)`` of our model is mapped to the Kane state by choosing Euler angles with
body-frame upward vertical ``gamma`` (``q2 = -asin(gamma1)``, ``q3 = atan2(gamma2, gamma3)``,
any yaw ``q1``) and ``omega = (I + D (Id - gamma gamma^T))^-1 M``; the latter formula is checked
against sympy's own angular momentum about the contact point by :func:`kane_contact_momentum`.

**One extra constraint on the angular velocity** (``constraint=`` of
:func:`kane_angular_acceleration` and :func:`kane_energy_and_rate`, named after the model
effects):

* ``"rubber"`` -- no twist: the component of the angular velocity along the vertical ``N.z``
  vanishes (the rubber ball of ``build_model("chaplygin_ball", ["rubber"])``);
* ``"straight_line"`` -- the component along the space-fixed horizontal axis ``N.x`` vanishes
  (Veselovs' system ``build_model("chaplygin_ball", ["straight_line"])``, whose state vector
  ``alpha`` is then the body-frame components of ``N.x``, ``beta`` those of ``N.y``; see
  :func:`space_axes_in_body`).

For these the independent speeds are chosen adapted to the constraint: ``u1, u2, u3`` are the
*space-frame* components of the angular velocity (``omega = u1 N.x + u2 N.y + u3 N.z``), so the
extra constraint is simply ``u3 = 0`` (resp. ``u1 = 0``), passed to ``KanesMethod`` as a third
velocity constraint with that speed dependent (together with ``u4, u5``); its coefficient is 1
at every configuration, so no conditioning is lost (making a *body* component dependent would
divide by ``gamma3`` or ``alpha3``). With these speeds the no-slip constraints do not even depend
on the configuration. Kane's equations (2 dynamical + 3 differentiated constraints) give the
space-frame ``u'``; the angular acceleration vector is the same seen from ``N`` and from ``B``
(``omega x omega = 0``), so its body-frame components are ``C (u1', u2', u3')`` with ``C`` the
direction cosines ``B_i . N_j`` of the Euler angles. The reaction torque of the extra constraint
never appears (it has no partial angular velocity along the independent speeds).

**A gyrostat** (``rotor=`` of :func:`kane_angular_acceleration`, K01 §4): a second rigid body,
an axisymmetric rotor about a body-fixed axis ``e`` through the centre, turning relative to
the ball at a constant rate ``s`` (``R.set_ang_vel(B, s e)``; the motor torque is internal and
has the same partial angular velocities on both bodies). The ball's own tensor is
``diag(I1, I2, I3)`` minus the rotor's, so the composite body has the model's principal
moments and our gyrostat model applies with ``K = Ia s e`` (:meth:`Rotor.momentum`).

**Time-varying inertia** (BM20 (3.4),
:func:`chaplygin.verify.kane_moving_masses.kane_moving_masses_angular_acceleration`): two
point masses of 1/2 slide along the body axis 2 at the prescribed positions
``+-(J_off + delta sin(Omega t))``; they add ``(J_off + delta sin(Omega t))^2`` to the
moments about the axes 1 and 3 and keep the centre of mass at the centre.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy as sp
from sympy.physics import mechanics as me

from ..arith import detlinalg
from .kane_euler import euler_rates

if TYPE_CHECKING:  # pragma: no cover
    pass

__all__ = [
    "Rotor",
    "ADMISSIBLE_RTOL",
    "EXTRA_CONSTRAINTS",
    "GAMMA1_LIMIT",
    "kane_angular_acceleration",
    "kane_contact_momentum",
    "kane_energy_and_rate",
    "euler_angles_for_gamma",
    "omega_from_momentum",
    "space_axes_in_body",
]

#: Largest ``|gamma1|`` accepted: the 3-2-1 Euler angles are singular at ``gamma1 = +-1``.
GAMMA1_LIMIT = 0.99

#: Extra constraints on the angular velocity the Kane side can impose (model effect names):
#: ``"rubber"`` (``omega . N.z = 0``, no twist), ``"straight_line"`` (``omega . N.x = 0``).
EXTRA_CONSTRAINTS = ("rubber", "straight_line")

#: A state is admissible for an extra constraint when the constrained component of
#: ``omega = II^-1 M`` is at most this fraction of ``|omega|`` (rounding of the caller's
#: ``M = II omega`` and of the solve only; the Kane side then sets it to exactly zero).
ADMISSIBLE_RTOL = 1e-10


@dataclass(frozen=True)
class Rotor:
    """An axisymmetric rotor inside the ball, turning at a constant rate relative to it.

    Parameters
    ----------
    axis : sequence of 3 floats
        Body-frame direction of the rotor axis (normalised here).
    axial, transverse : float
        Moments of inertia of the rotor about its axis and about a transverse axis through
        the ball's centre (positive).
    spin : float
        Rate of the rotor relative to the ball.
    """

    axis: tuple[float, float, float]
    axial: float
    transverse: float
    spin: float

    def unit_axis(self) -> np.ndarray:
        """The rotor axis normalised to length 1.

        Returns
        -------
        numpy.ndarray
            Body-frame unit vector ``e``, shape (3,).

        Raises
        ------
        ValueError
            For a zero (or non-finite) axis or a non-positive moment of inertia.
        """
        a = np.asarray(self.axis, dtype=float)
        n = float(detlinalg.norm(a))
        if not n > 0 or self.axial <= 0 or self.transverse <= 0:
            raise ValueError("a rotor needs a non-zero axis and positive moments of inertia")
        return a / n

    def momentum(self) -> np.ndarray:
        """Gyrostatic momentum ``K = Ia s e`` (body frame), the model's parameter ``K``.

        Returns
        -------
        numpy.ndarray
            ``axial * spin * unit_axis()``, shape (3,).

        Raises
        ------
        ValueError
            As :meth:`unit_axis`.

        References
        ----------
        K01-4.1 (the constant gyrostatic momentum ``K``).
        """
        return self.axial * self.spin * self.unit_axis()


@dataclass(frozen=True)
class _KaneSystem:
    """Lambdified pieces of the Kane model; every function takes ``(q, u, p)``.

    ``q = (q1, q2, q3, x, y)``, ``u = (u1, ..., u5)``, ``p = (I1, I2, I3, m, b, g)``.
    """

    mass_matrix: Callable[..., Any]
    forcing: Callable[..., Any]
    gamma: Callable[..., Any]
    dependent_speeds: Callable[..., Any]
    contact_momentum: Callable[..., Any]
    energy: Callable[..., Any]
    energy_gradient: Callable[..., Any]
    qdot: Callable[..., Any]
    speed_order: tuple[str, ...]


@lru_cache(maxsize=2)
def _kane_system(rotor: bool = False) -> _KaneSystem:
    """Form Kane's equations of the rolling ball once (symbolic), and lambdify them.

    With ``rotor``, the ball carries an axisymmetric rotor about a body-fixed unit axis
    ``e`` through the centre, spinning at the constant rate ``s`` relative to the ball
    (axial and transverse moments ``Ia``, ``It``): a gyrostat. The ball's own tensor is
    ``diag(I1, I2, I3)`` minus the rotor's, so that the composite body has the principal
    moments ``I1, I2, I3`` of the model; ``p`` gets ``(e1, e2, e3, Ia, It, s)``.
    """
    q1, q2, q3, x, y = me.dynamicsymbols("q1 q2 q3 x y")
    u1, u2, u3, u4, u5 = me.dynamicsymbols("u1 u2 u3 u4 u5")
    I1, I2, I3, m, b, g = sp.symbols("I1 I2 I3 m b g", positive=True)
    e1, e2, e3, Ia, It, spin = sp.symbols("e1 e2 e3 Ia It s", real=True)
    t = me.dynamicsymbols._t
    q = [q1, q2, q3, x, y]
    u = [u1, u2, u3, u4, u5]
    p = [I1, I2, I3, m, b, g] + ([e1, e2, e3, Ia, It, spin] if rotor else [])

    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, (q1, q2, q3), "zyx")
    # The kinematic equations already solved for the Euler-angle rates (only 1/cos(q2), the
    # true 3-2-1 singularity). Letting KanesMethod LU-solve the implicit form leaves spurious
    # denominators sin(q3), cos(q3) in the unsimplified rates, which lose digits to
    # cancellation near gamma2 = 0 or gamma3 = 0 (seen: 1.5e-11 relative error at
    # gamma3 = 3e-4, against 1e-14 with the solved form).
    rates = [s.diff(t) for s in (q1, q2, q3)]
    rate_sol = euler_rates("body")
    kd = [r - rate_sol[r] for r in rates]
    kd += [x.diff(t) - u4, y.diff(t) - u5]
    B.set_ang_vel(N, u1 * B.x + u2 * B.y + u3 * B.z)

    origin = me.Point("origin")
    origin.set_vel(N, 0)
    O = origin.locatenew("O", x * N.x + y * N.y + b * N.z)
    O.set_vel(N, u4 * N.x + u5 * N.y)
    P = O.locatenew("P", -b * N.z)  # material point of the ball at the contact
    P.v2pt_theory(O, N, B)
    v_contact = P.vel(N)
    velocity_constraints = [v_contact.dot(N.x), v_contact.dot(N.y)]
    if sp.simplify(v_contact.dot(N.z)) != 0:  # pragma: no cover - geometric guard
        raise AssertionError("vertical velocity of the contact point does not vanish")

    inertia = me.inertia(B, I1, I2, I3)
    bodies = []
    if rotor:
        # The rotor's frame R turns about e relative to B; its central dyadic is the same
        # in R and in B (axisymmetric about e), so it is written in B's basis.
        e = e1 * B.x + e2 * B.y + e3 * B.z
        R = me.ReferenceFrame("R")
        R.set_ang_vel(B, spin * e)
        rotor_inertia = Ia * (e | e) + It * (me.inertia(B, 1, 1, 1) - (e | e))
        inertia = inertia - rotor_inertia
        bodies.append(me.RigidBody("rotor", O, R, 0, (rotor_inertia, O)))
    ball = me.RigidBody("ball", O, B, m, (inertia, O))
    bodies.insert(0, ball)
    loads = [(O, -m * g * N.z)]

    kane = me.KanesMethod(
        N,
        q_ind=q,
        u_ind=[u1, u2, u3],
        u_dependent=[u4, u5],
        kd_eqs=kd,
        velocity_constraints=velocity_constraints,
    )
    kane.kanes_equations(bodies, loads)
    mass_matrix = kane.mass_matrix
    forcing = kane.forcing
    speed_order = tuple(str(s.func) for s in kane.u)

    # Dependent speeds from the (linear) no-slip constraints.
    A_dep, b_dep = sp.linear_eq_to_matrix(velocity_constraints, [u4, u5])
    u_dep = A_dep.LUsolve(b_dep)
    dep = {u4: u_dep[0], u5: u_dep[1]}

    # Body-frame upward vertical and angular momentum about the contact point.
    gamma = sp.Matrix([N.z.dot(B.x), N.z.dot(B.y), N.z.dot(B.z)])
    H = sum((body.angular_momentum(P, N) for body in bodies), me.Vector(0))
    H_body = sp.Matrix([H.dot(B.x), H.dot(B.y), H.dot(B.z)]).xreplace(dep)

    # Kinetic energy (gravity does no work) and its gradient, to check energy conservation.
    T = sum(body.kinetic_energy(N) for body in bodies)
    qdot = sp.Matrix([rate_sol[r] for r in rates] + [u4, u5])  # kd solved
    T_grad = sp.Matrix([T]).jacobian(q + u)

    def lam(expr: Any) -> Callable[..., Any]:
        return sp.lambdify((q, u, p), expr, modules="numpy", cse=True)

    return _KaneSystem(
        mass_matrix=lam(mass_matrix),
        forcing=lam(forcing),
        gamma=lam(gamma),
        dependent_speeds=lam(u_dep),
        contact_momentum=lam(H_body),
        energy=lam(T),
        energy_gradient=lam(T_grad),
        qdot=lam(qdot),
        speed_order=speed_order,
    )


@dataclass(frozen=True)
class _KaneConstrainedSystem:
    """Lambdified pieces of the Kane model with one extra constraint on the angular velocity.

    Every function takes ``(q, u, p)`` as :class:`_KaneSystem`, but ``u1, u2, u3`` are the
    space-frame components of the angular velocity. ``speed_order`` is the order of
    ``KanesMethod.u`` (independent speeds first), the columns of ``mass_matrix``.
    """

    mass_matrix: Callable[..., Any]
    forcing: Callable[..., Any]
    body_from_space: Callable[..., Any]
    dependent_speeds: Callable[..., Any]
    energy: Callable[..., Any]
    energy_gradient: Callable[..., Any]
    qdot: Callable[..., Any]
    speed_order: tuple[str, ...]
    dependent: tuple[int, ...]  # indices (0-based) of the dependent speeds in u1..u5
    axis: int  # index of the space axis (N.x, N.y, N.z) along which omega vanishes


def _euler_frames() -> tuple[me.ReferenceFrame, me.ReferenceFrame, list[Any]]:
    """Inertial frame ``N`` and body frame ``B`` oriented by 3-2-1 Euler angles ``q1..q3``."""
    q123 = list(me.dynamicsymbols("q1 q2 q3"))
    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, tuple(q123), "zyx")
    return N, B, q123


@lru_cache(maxsize=1)
def _space_axes_function() -> Callable[..., Any]:
    """Lambdified body-frame components of ``N.x, N.y, N.z`` (rows) from ``(q1, q2, q3)``."""
    N, B, q123 = _euler_frames()
    rows = sp.Matrix([[n.dot(bv) for bv in (B.x, B.y, B.z)] for n in (N.x, N.y, N.z)])
    return sp.lambdify([q123], rows, modules="numpy", cse=True)


@lru_cache(maxsize=len(EXTRA_CONSTRAINTS))
def _kane_constrained_system(constraint: str) -> _KaneConstrainedSystem:
    """Form Kane's equations of the rolling ball with one extra constraint on omega."""
    if constraint not in EXTRA_CONSTRAINTS:
        raise ValueError(
            f"unknown constraint {constraint!r}; valid: {', '.join(EXTRA_CONSTRAINTS)}"
        )
    N, B, (q1, q2, q3) = _euler_frames()
    x, y = me.dynamicsymbols("x y")
    u1, u2, u3, u4, u5 = me.dynamicsymbols("u1 u2 u3 u4 u5")
    I1, I2, I3, m, b, g = sp.symbols("I1 I2 I3 m b g", positive=True)
    t = me.dynamicsymbols._t
    q = [q1, q2, q3, x, y]
    u = [u1, u2, u3, u4, u5]
    p = [I1, I2, I3, m, b, g]

    # Kinematics: u1..u3 = space-frame components of the angular velocity, the Euler-angle
    # rates solved in the form whose only denominator is cos(q2), the 3-2-1 singularity.
    rates = [s.diff(t) for s in (q1, q2, q3)]
    rate_sol = euler_rates("space")
    rate_values = [rate_sol[r] for r in rates]
    kd = [r - v for r, v in zip(rates, rate_values, strict=True)]
    kd += [x.diff(t) - u4, y.diff(t) - u5]
    B.set_ang_vel(N, u1 * N.x + u2 * N.y + u3 * N.z)

    origin = me.Point("origin")
    origin.set_vel(N, 0)
    O = origin.locatenew("O", x * N.x + y * N.y + b * N.z)
    O.set_vel(N, u4 * N.x + u5 * N.y)
    P = O.locatenew("P", -b * N.z)  # material point of the ball at the contact
    P.v2pt_theory(O, N, B)
    v_contact = P.vel(N)
    if sp.simplify(v_contact.dot(N.z)) != 0:  # pragma: no cover - geometric guard
        raise AssertionError("vertical velocity of the contact point does not vanish")
    # The extra constraint: no twist (no spin about the vertical) or rolling along the line
    # N.x (no rotation about the space-fixed horizontal axis N.x).
    axis_vector, axis = (N.z, 2) if constraint == "rubber" else (N.x, 0)
    omega = B.ang_vel_in(N)
    velocity_constraints = [v_contact.dot(N.x), v_contact.dot(N.y), omega.dot(axis_vector)]
    dependent = (axis, 3, 4)
    u_dep = [u[i] for i in dependent]
    u_ind = [s for s in u[:3] if s not in u_dep]

    inertia = me.inertia(B, I1, I2, I3)
    ball = me.RigidBody("ball", O, B, m, (inertia, O))
    loads = [(O, -m * g * N.z)]

    kane = me.KanesMethod(
        N,
        q_ind=q,
        u_ind=u_ind,
        u_dependent=u_dep,
        kd_eqs=kd,
        velocity_constraints=velocity_constraints,
    )
    kane.kanes_equations([ball], loads)

    # Dependent speeds from the (linear) velocity constraints.
    Cmat, rhs = sp.linear_eq_to_matrix(velocity_constraints, u_dep)
    dep_values = Cmat.LUsolve(rhs).applyfunc(sp.simplify)

    body_from_space = sp.Matrix([[bv.dot(n) for n in (N.x, N.y, N.z)] for bv in (B.x, B.y, B.z)])
    T = ball.kinetic_energy(N)
    qdot = sp.Matrix([*rate_values, u4, u5])
    T_grad = sp.Matrix([T]).jacobian(q + u)

    def lam(expr: Any) -> Callable[..., Any]:
        return sp.lambdify((q, u, p), expr, modules="numpy", cse=True)

    return _KaneConstrainedSystem(
        mass_matrix=lam(kane.mass_matrix),
        forcing=lam(kane.forcing),
        body_from_space=lam(body_from_space),
        dependent_speeds=lam(dep_values),
        energy=lam(T),
        energy_gradient=lam(T_grad),
        qdot=lam(qdot),
        speed_order=tuple(str(s.func) for s in kane.u),
        dependent=dependent,
        axis=axis,
    )


def space_axes_in_body(gamma: Sequence[float], yaw: float = 0.0) -> np.ndarray:
    """Body-frame components of the space axes ``N.x, N.y, N.z`` of the Kane configuration.

    The configuration is the one every Kane function uses for ``(gamma, yaw)``: the Euler
    angles of :func:`euler_angles_for_gamma`. For the ``straight_line`` model the rows are its
    state vectors ``alpha`` (the line ``N.x``), ``beta`` (``N.y``) and ``gamma`` (``N.z``).

    Parameters
    ----------
    gamma : sequence of 3 floats
        Unit upward vertical in the body frame; ``|gamma1| <= GAMMA1_LIMIT``.
    yaw : float, optional
        Heading angle (about the vertical).

    Returns
    -------
    numpy.ndarray
        Shape (3, 3); rows ``alpha, beta, gamma``, a right-handed orthonormal frame.

    Examples
    --------
    >>> import numpy as np
    >>> bool(np.allclose(space_axes_in_body([0.0, 0.0, 1.0]), np.eye(3)))
    True
    """
    q = euler_angles_for_gamma(gamma, yaw)
    axes = np.asarray(_space_axes_function()(q), dtype=float)
    if detlinalg.norm(axes[2] - np.asarray(gamma, dtype=float)) > 1e-12:  # pragma: no cover
        raise AssertionError(f"Euler angles give gamma={axes[2]}, wanted {gamma}")
    return axes


def euler_angles_for_gamma(gamma: Sequence[float], yaw: float = 0.0) -> np.ndarray:
    """Body-fixed 3-2-1 Euler angles whose body-frame upward vertical is ``gamma``.

    Parameters
    ----------
    gamma : sequence of 3 floats
        Unit upward vertical in the body frame.
    yaw : float, optional
        First angle (about the vertical); free, it does not change the dynamics.

    Returns
    -------
    numpy.ndarray
        ``(yaw, pitch, roll)`` with ``pitch = -asin(gamma1)``, ``roll = atan2(gamma2, gamma3)``.

    Raises
    ------
    ValueError
        If ``gamma`` is not a unit vector or lies within the 3-2-1 singularity margin
        (``|gamma1| > GAMMA1_LIMIT``).
    """
    g = np.asarray(gamma, dtype=float)
    if g.shape != (3,):
        raise ValueError(f"gamma must have shape (3,), got {g.shape}")
    if abs(float(detlinalg.norm(g)) - 1.0) > 1e-10:
        raise ValueError("gamma must be a unit vector")
    if abs(g[0]) > GAMMA1_LIMIT:
        raise ValueError(f"|gamma1| = {abs(g[0])} is too close to the 3-2-1 Euler singularity")
    return np.array([yaw, -math.asin(g[0]), math.atan2(g[1], g[2])])


def omega_from_momentum(
    I: Sequence[float], D: float, M: Sequence[float], gamma: Sequence[float]
) -> np.ndarray:
    """Body angular velocity from the momentum about the contact point.

    Solves ``M = (I + D (Id - gamma gamma^T)) omega`` (``I = diag(I1, I2, I3)``).

    Parameters
    ----------
    I : sequence of 3 floats
        Central principal moments of inertia.
    D : float
        ``m b^2``.
    M : sequence of 3 floats
        Angular momentum about the contact point, body frame.
    gamma : sequence of 3 floats
        Unit upward vertical, body frame.

    Returns
    -------
    numpy.ndarray
        ``omega``, shape (3,).
    """
    g = np.asarray(gamma, dtype=float)
    J = np.diag(np.asarray(I, dtype=float)) + D * (np.eye(3) - g[:, None] * g[None, :])
    return detlinalg.solve(J, np.asarray(M, dtype=float))


def _kane_point(
    I: Sequence[float],
    D: float,
    b: float,
    omega: Sequence[float],
    gamma: Sequence[float],
    yaw: float,
    g: float,
    rotor: Rotor | None = None,
) -> tuple[_KaneSystem, np.ndarray, np.ndarray, np.ndarray]:
    """Kane system and numeric ``(q, u, p)`` at the state ``(omega, gamma)``."""
    sys_ = _kane_system(rotor is not None)
    if len(I) != 3:
        raise ValueError("I must have 3 components")
    if b <= 0 or D <= 0:
        raise ValueError("D and b must be positive")
    q = np.concatenate([euler_angles_for_gamma(gamma, yaw), [0.0, 0.0]])
    extra = [] if rotor is None else [*rotor.unit_axis(), rotor.axial, rotor.transverse, rotor.spin]
    p = np.array([*map(float, I), D / b**2, b, g, *extra])
    gamma_kane = np.asarray(sys_.gamma(q, np.zeros(5), p), dtype=float).ravel()
    if detlinalg.norm(gamma_kane - np.asarray(gamma, dtype=float)) > 1e-12:  # pragma: no cover
        raise AssertionError(f"Euler angles give gamma={gamma_kane}, wanted {gamma}")
    u = np.concatenate([np.asarray(omega, dtype=float), [0.0, 0.0]])
    u[3:] = np.asarray(sys_.dependent_speeds(q, u, p), dtype=float).ravel()
    return sys_, q, u, p


def _kane_constrained_point(
    I: Sequence[float],
    D: float,
    b: float,
    M: Sequence[float],
    gamma: Sequence[float],
    yaw: float,
    g: float,
    constraint: str,
) -> tuple[_KaneConstrainedSystem, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Constrained Kane system, numeric ``(q, u, p)`` and body-from-space matrix at ``(M, gamma)``.

    Raises ``ValueError`` if ``omega = II^-1 M`` violates the extra constraint.
    """
    sys_ = _kane_constrained_system(constraint)
    if len(I) != 3:
        raise ValueError("I must have 3 components")
    if b <= 0 or D <= 0:
        raise ValueError("D and b must be positive")
    q = np.concatenate([euler_angles_for_gamma(gamma, yaw), [0.0, 0.0]])
    p = np.array([*map(float, I), D / b**2, b, g])
    omega = omega_from_momentum(I, D, M, gamma)
    C = np.asarray(sys_.body_from_space(q, np.zeros(5), p), dtype=float)
    omega_space = detlinalg.matmul(C.T, omega)
    if abs(omega_space[sys_.axis]) > ADMISSIBLE_RTOL * detlinalg.norm(omega):
        raise ValueError(
            f"state violates the {constraint!r} constraint: omega . N_{'xyz'[sys_.axis]} = "
            f"{omega_space[sys_.axis]:.3e} (|omega| = {detlinalg.norm(omega):.3e})"
        )
    u = np.concatenate([omega_space, [0.0, 0.0]])
    u[list(sys_.dependent)] = np.asarray(sys_.dependent_speeds(q, u, p), dtype=float).ravel()
    return sys_, q, u, p, C


def _kane_constrained_rates(
    sys_: _KaneConstrainedSystem, q: np.ndarray, u: np.ndarray, p: np.ndarray
) -> np.ndarray:
    """``(u1', ..., u5')`` in the natural order from Kane's equations."""
    A = np.asarray(sys_.mass_matrix(q, u, p), dtype=float)
    f = np.asarray(sys_.forcing(q, u, p), dtype=float).ravel()
    solved = detlinalg.solve(A, f)
    udot = np.empty(5)
    for name, value in zip(sys_.speed_order, solved, strict=True):
        udot[int(name[1:]) - 1] = value
    return udot


def kane_angular_acceleration(
    I: Sequence[float],
    D: float,
    b: float,
    M: Sequence[float],
    gamma: Sequence[float],
    *,
    yaw: float = 0.0,
    g: float = 9.81,
    constraint: str | None = None,
    rotor: Rotor | None = None,
) -> np.ndarray:
    """Body-frame angular acceleration of the rolling ball from ``KanesMethod``.

    Parameters
    ----------
    I : sequence of 3 floats
        Central principal moments of inertia ``I1, I2, I3``.
    D : float
        ``m b^2``; the mass is ``m = D / b**2``.
    b : float
        Ball radius.
    M : sequence of 3 floats
        Angular momentum about the contact point, body frame.
    gamma : sequence of 3 floats
        Unit upward vertical, body frame; ``|gamma1| <= GAMMA1_LIMIT``.
    yaw : float, optional
        Heading angle of the Kane configuration (does not affect the result).
    g : float, optional
        Gravitational acceleration (does not affect the result of a balanced ball).
    constraint : {None, "rubber", "straight_line"}, optional
        One extra constraint on the angular velocity (see :data:`EXTRA_CONSTRAINTS`): no twist
        ``omega . N.z = 0`` or rolling along the line ``N.x``, ``omega . N.x = 0``. The
        heading ``yaw`` then matters for ``"straight_line"`` (it fixes ``alpha``, see
        :func:`space_axes_in_body`).
    rotor : Rotor, optional
        A rotor spinning at a constant rate inside the ball (a gyrostat, K01 §4): a second
        rigid body of the Kane model. The composite body has the principal moments ``I``;
        our model's gyrostatic momentum is :meth:`Rotor.momentum`. Not combined with
        ``constraint``.

    Returns
    -------
    numpy.ndarray
        ``omega_dot`` in the body frame, shape (3,).

    Raises
    ------
    ValueError
        Bad parameters, a singular ``gamma``, an unknown ``constraint``, or a state whose
        ``omega = II^-1 M`` violates the constraint (relative tolerance
        :data:`ADMISSIBLE_RTOL`).

    Examples
    --------
    >>> w_dot = kane_angular_acceleration([1, 2, 3], 1.0, 1.0, [0.1, 0.2, 0.3], [0, 0, 1])
    >>> w_dot.shape
    (3,)
    """
    if constraint is not None:
        if rotor is not None:
            raise ValueError("a rotor and an extra constraint are not combined here")
        sys_c, q, u, p, C = _kane_constrained_point(I, D, b, M, gamma, yaw, g, constraint)
        return detlinalg.matmul(C, _kane_constrained_rates(sys_c, q, u, p)[:3])
    omega = omega_from_momentum(I, D, M, gamma)
    sys_, q, u, p = _kane_point(I, D, b, omega, gamma, yaw, g, rotor)
    A = np.asarray(sys_.mass_matrix(q, u, p), dtype=float)
    f = np.asarray(sys_.forcing(q, u, p), dtype=float).ravel()
    udot = detlinalg.solve(A, f)
    return udot[:3].copy()


def kane_contact_momentum(
    I: Sequence[float],
    D: float,
    b: float,
    omega: Sequence[float],
    gamma: Sequence[float],
    *,
    yaw: float = 0.0,
) -> np.ndarray:
    """Angular momentum about the contact point from ``RigidBody.angular_momentum``.

    Parameters
    ----------
    I, D, b : as in :func:`kane_angular_acceleration`
    omega : sequence of 3 floats
        Body-frame angular velocity.
    gamma : sequence of 3 floats
        Unit upward vertical, body frame.
    yaw : float, optional
        Heading angle of the configuration.

    Returns
    -------
    numpy.ndarray
        ``M`` in the body frame, shape (3,), with the no-slip centre velocity.
    """
    sys_, q, u, p = _kane_point(I, D, b, omega, gamma, yaw, 0.0)
    return np.asarray(sys_.contact_momentum(q, u, p), dtype=float).ravel()


def kane_energy_and_rate(
    I: Sequence[float],
    D: float,
    b: float,
    M: Sequence[float],
    gamma: Sequence[float],
    *,
    yaw: float = 0.0,
    constraint: str | None = None,
) -> tuple[float, float]:
    """Kinetic energy and its time derivative along the Kane solution.

    ``dT/dt = (dT/dq) . q' + (dT/du) . u'`` with ``q'`` from the kinematic differential
    equations and ``u'`` from Kane's equations; it must vanish (rolling, gravity and the
    reaction of an extra constraint on omega do no work).

    Parameters
    ----------
    I, D, b, M, gamma, yaw, constraint : as in :func:`kane_angular_acceleration`

    Returns
    -------
    tuple of float
        ``(T, dT/dt)``.
    """
    if constraint is not None:
        sys_c, q, u, p, _ = _kane_constrained_point(I, D, b, M, gamma, yaw, 9.81, constraint)
        udot = _kane_constrained_rates(sys_c, q, u, p)
        qdot = np.asarray(sys_c.qdot(q, u, p), dtype=float).ravel()
        grad = np.asarray(sys_c.energy_gradient(q, u, p), dtype=float).ravel()
        T = float(sys_c.energy(q, u, p))
        return T, detlinalg.dot(grad[:5], qdot) + detlinalg.dot(grad[5:], udot)
    omega = omega_from_momentum(I, D, M, gamma)
    sys_, q, u, p = _kane_point(I, D, b, omega, gamma, yaw, 9.81)
    A = np.asarray(sys_.mass_matrix(q, u, p), dtype=float)
    f = np.asarray(sys_.forcing(q, u, p), dtype=float).ravel()
    udot = detlinalg.solve(A, f)
    qdot = np.asarray(sys_.qdot(q, u, p), dtype=float).ravel()
    grad = np.asarray(sys_.energy_gradient(q, u, p), dtype=float).ravel()
    T = float(sys_.energy(q, u, p))
    return T, detlinalg.dot(grad[:5], qdot) + detlinalg.dot(grad[5:], udot)
