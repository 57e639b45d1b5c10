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
the body-frame angular acceleration ``omega_dot`` that :func:`model_angular_acceleration`
computes from our model as ``(d omega / d(M, gamma)) . (M', gamma')``.

The state ``(M, gamma)`` of our model is mapped to the Kane state by choosing Euler angles with
body-frame upward vertical ``gamma`` (``q2 = -asin(gamma1)``, ``q3 = atan2(gamma2, gamma3)``,
any yaw ``q1``) and ``omega = (I + D (Id - gamma gamma^T))^-1 M``; the latter formula is checked
against sympy's own angular momentum about the contact point by :func:`kane_contact_momentum`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
from sympy.physics import mechanics as me

__all__ = [
    "GAMMA1_LIMIT",
    "kane_angular_acceleration",
    "kane_contact_momentum",
    "kane_energy_and_rate",
    "model_angular_acceleration",
    "euler_angles_for_gamma",
    "omega_from_momentum",
]

#: Largest ``|gamma1|`` accepted: the 3-2-1 Euler angles are singular at ``gamma1 = +-1``.
GAMMA1_LIMIT = 0.99


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


@lru_cache(maxsize=1)
def _kane_system() -> _KaneSystem:
    """Form Kane's equations of the rolling ball once (symbolic), and lambdify them."""
    q1, q2, q3, x, y = me.dynamicsymbols("q1 q2 q3 x y")
    u1, u2, u3, u4, u5 = me.dynamicsymbols("u1 u2 u3 u4 u5")
    I1, I2, I3, m, b, g = sp.symbols("I1 I2 I3 m b g", positive=True)
    t = me.dynamicsymbols._t
    q = [q1, q2, q3, x, y]
    u = [u1, u2, u3, u4, u5]
    p = [I1, I2, I3, m, b, g]

    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, (q1, q2, q3), "zyx")
    omega_q = B.ang_vel_in(N)  # in terms of the Euler-angle rates
    kd_implicit = [omega_q.dot(B.x) - u1, omega_q.dot(B.y) - u2, omega_q.dot(B.z) - u3]
    # Pass the kinematic equations already solved for the Euler-angle rates (simplified: only
    # 1/cos(q2), the true 3-2-1 singularity). Letting KanesMethod LU-solve the implicit form
    # leaves spurious denominators sin(q3), cos(q3) in the unsimplified rates, which lose digits
    # to cancellation near gamma2 = 0 or gamma3 = 0 (seen: 1.5e-11 relative error at
    # gamma3 = 3e-4, against 1e-14 with the solved form).
    rates = [s.diff(t) for s in (q1, q2, q3)]
    rate_sol = sp.solve(kd_implicit, rates, dict=True)[0]
    kd = [r - sp.trigsimp(sp.simplify(rate_sol[r])) for r in rates]
    if any(
        sp.simplify(e.xreplace({r: r - k for r, k in zip(rates, kd, strict=True)})) != 0
        for e in kd_implicit
    ):  # pragma: no cover - guards the solved kinematics
        raise AssertionError("solved Euler kinematics do not satisfy omega = u")
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
    ball = me.RigidBody("ball", O, B, m, (inertia, O))
    loads = [(O, -m * g * N.z)]

    kane = me.KanesMethod(
        N,
        q_ind=q,
        u_ind=[u1, u2, u3],
        u_dependent=[u4, u5],
        kd_eqs=kd,
        velocity_constraints=velocity_constraints,
    )
    kane.kanes_equations([ball], loads)
    mass_matrix = kane.mass_matrix
    forcing = kane.forcing
    speed_order = tuple(str(s.func) for s in kane.u)

    # Dependent speeds from the (linear) no-slip constraints.
    dep = sp.solve(velocity_constraints, [u4, u5], dict=True)[0]
    u_dep = sp.Matrix([dep[u4], dep[u5]])

    # Body-frame upward vertical and angular momentum about the contact point.
    gamma = sp.Matrix([N.z.dot(B.x), N.z.dot(B.y), N.z.dot(B.z)])
    H = ball.angular_momentum(P, N)
    H_body = sp.Matrix([H.dot(B.x), H.dot(B.y), H.dot(B.z)]).xreplace(dep)

    # Kinetic energy (gravity does no work) and its gradient, to check energy conservation.
    T = ball.kinetic_energy(N)
    qdot_sol = sp.solve(kd, [s.diff(t) for s in q], dict=True)[0]
    qdot = sp.Matrix([qdot_sol[s.diff(t)] for s in q])
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
    if abs(float(np.linalg.norm(g)) - 1.0) > 1e-10:
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
    J = np.diag(np.asarray(I, dtype=float)) + D * (np.eye(3) - np.outer(g, g))
    return np.linalg.solve(J, np.asarray(M, dtype=float))


def _kane_point(
    I: Sequence[float],
    D: float,
    b: float,
    omega: Sequence[float],
    gamma: Sequence[float],
    yaw: float,
    g: float,
) -> tuple[_KaneSystem, np.ndarray, np.ndarray, np.ndarray]:
    """Kane system and numeric ``(q, u, p)`` at the state ``(omega, gamma)``."""
    sys_ = _kane_system()
    if len(I) != 3:
        raise ValueError("I must have 3 components")
    if b <= 0 or D <= 0:
        raise ValueError("D and b must be positive")
    q = np.concatenate([euler_angles_for_gamma(gamma, yaw), [0.0, 0.0]])
    p = np.array([*map(float, I), D / b**2, b, g])
    gamma_kane = np.asarray(sys_.gamma(q, np.zeros(5), p), dtype=float).ravel()
    if np.linalg.norm(gamma_kane - np.asarray(gamma, dtype=float)) > 1e-12:  # pragma: no cover
        raise AssertionError(f"Euler angles give gamma={gamma_kane}, wanted {gamma}")
    u = np.concatenate([np.asarray(omega, dtype=float), [0.0, 0.0]])
    u[3:] = np.asarray(sys_.dependent_speeds(q, u, p), dtype=float).ravel()
    return sys_, q, u, p


def kane_angular_acceleration(
    I: Sequence[float],
    D: float,
    b: float,
    M: Sequence[float],
    gamma: Sequence[float],
    *,
    yaw: float = 0.0,
    g: float = 9.81,
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

    Returns
    -------
    numpy.ndarray
        ``omega_dot`` in the body frame, shape (3,).

    Examples
    --------
    >>> w_dot = kane_angular_acceleration([1, 2, 3], 1.0, 1.0, [0.1, 0.2, 0.3], [0, 0, 1])
    >>> w_dot.shape
    (3,)
    """
    omega = omega_from_momentum(I, D, M, gamma)
    sys_, q, u, p = _kane_point(I, D, b, omega, gamma, yaw, g)
    A = np.asarray(sys_.mass_matrix(q, u, p), dtype=float)
    f = np.asarray(sys_.forcing(q, u, p), dtype=float).ravel()
    udot = np.linalg.solve(A, f)
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
) -> tuple[float, float]:
    """Kinetic energy and its time derivative along the Kane solution.

    ``dT/dt = (dT/dq) . q' + (dT/du) . u'`` with ``q'`` from the kinematic differential
    equations and ``u'`` from Kane's equations; it must vanish (rolling and gravity do no work).

    Parameters
    ----------
    I, D, b, M, gamma, yaw : as in :func:`kane_angular_acceleration`

    Returns
    -------
    tuple of float
        ``(T, dT/dt)``.
    """
    omega = omega_from_momentum(I, D, M, gamma)
    sys_, q, u, p = _kane_point(I, D, b, omega, gamma, yaw, 9.81)
    A = np.asarray(sys_.mass_matrix(q, u, p), dtype=float)
    f = np.asarray(sys_.forcing(q, u, p), dtype=float).ravel()
    udot = np.linalg.solve(A, f)
    qdot = np.asarray(sys_.qdot(q, u, p), dtype=float).ravel()
    grad = np.asarray(sys_.energy_gradient(q, u, p), dtype=float).ravel()
    T = float(sys_.energy(q, u, p))
    return T, float(grad[:5] @ qdot + grad[5:] @ udot)


@lru_cache(maxsize=8)
def _model_omega_dot(model: Any) -> tuple[Callable[..., Any], tuple[str, ...]]:
    """Lambdified ``omega_dot(M, gamma, params)`` of a model and its parameter names."""
    M = list(model.group("M"))
    gamma = list(model.group("gamma"))
    state = M + gamma
    omega = model.expand_aux(model.definitions["omega"])
    rows = [model.state.index(s) for s in state]
    rhs = sp.Matrix([model.rhs_expanded[i] for i in rows])
    allowed = set(state) | set(model.params)
    free = omega.free_symbols | rhs.free_symbols
    if not free <= allowed:
        raise ValueError(f"omega or (M', gamma') depend on more than M, gamma: {free - allowed}")
    jac = omega.jacobian(state)
    f = sp.lambdify((state, list(model.params)), [jac, rhs], modules="numpy", cse=True)
    return f, tuple(model.param_names)


def model_angular_acceleration(
    model: Any, params: dict[str, float], M: Sequence[float], gamma: Sequence[float]
) -> np.ndarray:
    """Body-frame angular acceleration from our model: ``(d omega / d state) . rhs``.

    Parameters
    ----------
    model : chaplygin.derive.Model
        A ``chaplygin_ball`` model (any variant whose ``omega`` and ``(M', gamma')`` depend on
        ``M``, ``gamma`` and the parameters only).
    params : dict of str to float
        Parameter values by name (``I1, I2, I3, D`` ...).
    M : sequence of 3 floats
        Angular momentum about the contact point, body frame.
    gamma : sequence of 3 floats
        Unit upward vertical, body frame.

    Returns
    -------
    numpy.ndarray
        ``omega_dot``, shape (3,).
    """
    f, names = _model_omega_dot(model)
    missing = [n for n in names if n not in params]
    if missing:
        raise KeyError(f"missing parameter values: {missing}")
    state = [*map(float, M), *map(float, gamma)]
    jac, rhs = f(state, [float(params[n]) for n in names])
    return (np.asarray(jac, dtype=float) @ np.asarray(rhs, dtype=float)).ravel()
