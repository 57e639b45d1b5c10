"""The Kane side of BM20's time-varying inertia (BM20 (3.4)): two point masses of 1/2 sliding
along the body axis 2 at ``+-(J_off + delta sin(Omega t))``, set up with
``sympy.physics.mechanics.KanesMethod`` like the rest of :mod:`chaplygin.verify.kane`."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp
from sympy.physics import mechanics as me

from ..arith import detlinalg
from .kane import euler_angles_for_gamma, omega_from_momentum
from .kane_euler import euler_rates

__all__ = ["kane_moving_masses_angular_acceleration"]


@lru_cache(maxsize=1)
def _kane_moving_masses_system() -> tuple[Callable[..., Any], Callable[..., Any], Callable]:
    """Kane's equations of the ball carrying two point masses that move along ``B.y``.

    BM20 (3.4) as a mechanism: masses ``1/2`` at ``+-x(t) B.y``, ``x = J_off + delta
    sin(Omega t)``, add ``2 (1/2) x^2 = x^2`` to the moments about ``B.x`` and ``B.z`` and keep
    the centre of mass at the centre. Their positions are prescribed functions of time (the
    drive force along ``B.y`` is internal and has no partial velocity along the speeds).
    Returns lambdified ``mass_matrix, forcing`` and the dependent speeds, each of
    ``(q, u, p, t)`` with ``p = (I1, I2, I3, m_ball, b, J_off, delta, Omega)``.
    """
    q1, q2, q3, x, y = me.dynamicsymbols("q1 q2 q3 x y")
    u1, u2, u3, u4, u5 = me.dynamicsymbols("u1 u2 u3 u4 u5")
    I1, I2, I3, m, b = sp.symbols("I1 I2 I3 m b", positive=True)
    J_off, delta, Omega = sp.symbols("J_off delta Omega", real=True)
    t = me.dynamicsymbols._t
    q = [q1, q2, q3, x, y]
    u = [u1, u2, u3, u4, u5]
    p = [I1, I2, I3, m, b, J_off, delta, Omega]

    N = me.ReferenceFrame("N")
    B = me.ReferenceFrame("B")
    B.orient_body_fixed(N, (q1, q2, q3), "zyx")
    rates = [s_.diff(t) for s_ in (q1, q2, q3)]
    sol = euler_rates("body")
    kd = [r - sol[r] for r in rates]
    kd += [x.diff(t) - u4, y.diff(t) - u5]
    B.set_ang_vel(N, u1 * B.x + u2 * B.y + u3 * B.z)

    origin = me.Point("origin")
    origin.set_vel(N, 0)
    O = origin.locatenew("O", x * N.x + y * N.y + b * N.z)
    O.set_vel(N, u4 * N.x + u5 * N.y)
    P = O.locatenew("P", -b * N.z)
    P.v2pt_theory(O, N, B)
    velocity_constraints = [P.vel(N).dot(N.x), P.vel(N).dot(N.y)]

    bodies: list[Any] = [me.RigidBody("ball", O, B, m, (me.inertia(B, I1, I2, I3), O))]
    offset = J_off + delta * sp.sin(Omega * t)
    for sign, name in ((1, "p_plus"), (-1, "p_minus")):
        point = O.locatenew(name, sign * offset * B.y)
        # velocity = centre + omega x r + the prescribed sliding along B.y
        point.set_vel(
            N, O.vel(N) + B.ang_vel_in(N).cross(point.pos_from(O)) + sign * offset.diff(t) * B.y
        )
        bodies.append(me.Particle(name, point, sp.Rational(1, 2)))

    kane = me.KanesMethod(
        N,
        q_ind=q,
        u_ind=[u1, u2, u3],
        u_dependent=[u4, u5],
        kd_eqs=kd,
        velocity_constraints=velocity_constraints,
    )
    kane.kanes_equations(bodies, [])
    A_dep, b_dep = sp.linear_eq_to_matrix(velocity_constraints, [u4, u5])
    u_dep = A_dep.LUsolve(b_dep)

    def lam(expr: Any) -> Callable[..., Any]:
        return sp.lambdify((q, u, p, t), expr, modules="numpy", cse=True)

    return lam(kane.mass_matrix), lam(kane.forcing), lam(u_dep)


def kane_moving_masses_angular_acceleration(
    I: Sequence[float],
    D: float,
    b: float,
    law: tuple[float, float, float],
    M: Sequence[float],
    gamma: Sequence[float],
    t: float,
) -> np.ndarray:
    """Body-frame angular acceleration of the ball with BM20's moving masses (``KanesMethod``).

    Parameters
    ----------
    I : sequence of 3 floats
        The ball's own central moments (BM20 (3.4)'s ``I1, I2, I3``).
    D : float
        ``m b^2`` with ``m`` the total mass (ball + masses, the masses weigh 1 together), so
        ``D > b^2``.
    b : float
        Radius.
    law : (J_off, delta, Omega)
        Positions ``+-(J_off + delta sin(Omega t))`` of the masses along the body axis 2.
    M : sequence of 3 floats
        ``I(t) omega + D gamma x (omega x gamma)`` (body frame), BM20 (2.2) with ``k = 0``.
    gamma : sequence of 3 floats
        Unit upward vertical, body frame; ``|gamma1| <= GAMMA1_LIMIT``.
    t : float
        Time.

    Returns
    -------
    numpy.ndarray
        ``omega_dot``, shape (3,).
    """
    J_off, delta, Omega = (float(v) for v in law)
    mass = D / b**2 - 1.0
    if not mass > 0:
        raise ValueError("D must exceed b^2: the two masses weigh 1 together")
    offset = J_off + delta * math.sin(Omega * t)
    inertia_t = [I[0] + offset**2, I[1], I[2] + offset**2]
    omega = omega_from_momentum(inertia_t, D, M, gamma)
    mass_matrix, forcing, dependent = _kane_moving_masses_system()
    q = np.concatenate([euler_angles_for_gamma(gamma, 0.0), [0.0, 0.0]])
    p = np.array([*map(float, I), mass, b, J_off, delta, Omega])
    u = np.concatenate([omega, [0.0, 0.0]])
    u[3:] = np.asarray(dependent(q, u, p, t), dtype=float).ravel()
    A = np.asarray(mass_matrix(q, u, p, t), dtype=float)
    f = np.asarray(forcing(q, u, p, t), dtype=float).ravel()
    return detlinalg.solve(A, f)[:3].copy()
