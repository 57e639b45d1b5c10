"""The contact point's trace on ``M || gamma`` (K01 §3.3) and ``M + K || gamma`` (K01 §4),
period by period.

On these invariant sets ``gamma(t)`` alone is periodic in the body (an Euler top, K01-2.34; a
Zhukovsky–Volterra gyrostat, K01-4.4) with a period ``T``. After one period the body state is
back and the space-fixed horizontal frame, seen from the body, has turned about the
vertical, so the trace over the next period is the trace over the first one turned by an
angle ``psi`` and moved to its end:

    z(t + T) = z(T) + exp(i psi) (z(t) - z(0)),      z = x + i y.

Hence (K01-Fig6f) the points ``z(k T)`` lie on the circle through ``z(0)`` about
``c = z(0) + d/(1 - exp(i psi))``, ``d = z(T) - z(0)``, of radius
``R = |d|/(2 |sin(psi/2)|)``; the whole trace lies in the annulus ``inner <= |z - c| <=
outer`` (the *envelope* circles of K01 §3.3: ``min`` and ``max`` of ``|z(t) - c|`` over a
period) and is bounded unless ``psi = 0 mod 2 pi`` (a *critical energy*: then it drifts by
``d`` per period). ``psi`` is ``-Phi`` of :func:`chaplygin.numerics.ball.frame_turn.frame_turn`.

The *turning* ``Theta`` of the trace -- the total angle by which its tangent
``x' + i y'`` turns over one period -- is a continuous lift of ``psi`` (``Theta = psi mod 2
pi``): the velocity ``b omega x gamma`` vanishes only where ``omega || gamma``, at the
equilibria of the reduced flow, so ``Theta`` is continuous along every family of periodic
orbits. The critical energies of a family are therefore the energies where
``Theta/(2 pi)`` passes an integer, and they can be counted without locating each one. Near
a saddle of the reduced flow (the middle axis of K01 §3.3) the orbit lingers while the
ball spins about the vertical at ``sigma = (omega, gamma)``, and ``Theta`` grows like
``k (sigma/lam) ln(1/|h - h_s|)`` (``k`` passages per period, ``lam`` the saddle's rate):
the critical energies accumulate at every saddle energy. ``Theta/(4 pi)`` is the number of
full turns of the tangent per passage, the *wreaths* of K01's spirals (two passages per
period on ``M || gamma``).

Near the middle axis the passage of the ball is the linearised separatrix motion, so the
trace is ``s + P exp((lam + i kap) t) + Q exp((-lam + i kap) t)`` (K01-3.5, 3.6) about the
*spiral centre* ``s``; three samples ``tau`` apart give ``s`` exactly for that form
(:func:`spiral_centres`).

The integrations are the generated Taylor integrator's dense solution (the ``taylor``
integrator with ``dense_output``, :func:`dense_solution`; the return of ``gamma`` is located on its
step polynomials, as :func:`~chaplygin.numerics.ball.frame_turn.frame_turn` does), one period per
energy; angles, moduli and complex products are the project's own
(:mod:`chaplygin.arith.detmath`, :mod:`chaplygin.arith.detcomplex`) and dot products and
norms are summed in a fixed order (:mod:`chaplygin.arith.detlinalg`), so every number here
has the same bits on every machine.

References
----------
K01-2.34, K01-3.3q, K01-3.5, K01-3.6, K01-3.7, K01-Fig6f, K01-4.3, K01-4.4 (FORMULAS.md).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ...arith import detcomplex, detlinalg
from ...derive.errors import ComputationError, UserInputError
from ..arguments import check_inertia_vector, check_real, check_vector
from ..code import ModelCode, load_model_code
from ..integrators import INTEGRATORS, Problem
from ..precision import Precision
from ..taylor import TaylorDense

__all__ = [
    "dense_solution",
    "TracePeriod",
    "trace_period",
    "spiral_centres",
    "segment_state",
    "segment_energy",
]

SYSTEM = "chaplygin_ball"
#: Longest time searched for the return of gamma.
MAX_PERIOD = 1e5
#: Largest turn of the tangent between two samples before the sampling is refined.
MAX_SAMPLE_TURN = 0.25
#: Arc-length step of :func:`gradient_line` (classical Runge-Kutta, halved at the end).
LINE_STEP = 1e-2
#: Norm of the tangential gradient below which :func:`gradient_line` has reached an extremum.
LINE_FLAT = 1e-7


@dataclass
class TracePeriod:
    """One period of ``gamma`` on ``M (+ K) || gamma`` and the geometry of the trace.

    Attributes
    ----------
    h : float
        Energy of the orbit.
    period : float
        ``T``, the first return of ``gamma`` to its start.
    turn : float
        ``psi`` in ``(-pi, pi]``: each period's trace is the previous one turned by ``psi``.
    turning : float
        ``Theta``: the total turning of the trace's tangent over one period (a continuous
        lift of ``psi``).
    displacement : complex
        ``d = z(T) - z(0)``.
    centre : complex
        ``c = z(0) + d/(1 - exp(i psi))`` (infinite where ``psi = 0``).
    radius : float
        ``|z(0) - c| = |d|/(2 |sin(psi/2)|)``: the circle of the points ``z(k T)``.
    inner, outer : float
        The envelope radii: least and largest ``|z(t) - c|`` over a period.
    speed : float
        ``|d|/T``: how fast the trace moves along its circle.
    closure : float
        ``|(M, gamma)(T) - (M, gamma)(0)|``: how well the body state returns.
    t, z : ndarray
        Samples of one period (times and ``x + i y``).
    y0 : ndarray
        The start (state of ``chaplygin_ball__contact_point[__gyrostat]``).
    sol : TaylorDense
        The dense solution from ``t = 0`` to at least ``T``: ``sol(t)`` is the state at
        ``t`` (a number: shape (14,); a sequence: shape (14, m)).
    """

    h: float
    period: float
    turn: float
    turning: float
    displacement: complex
    centre: complex
    radius: float
    inner: float
    outer: float
    speed: float
    closure: float
    t: np.ndarray = field(repr=False)
    z: np.ndarray = field(repr=False)
    y0: np.ndarray = field(repr=False)
    sol: TaylorDense | None = field(repr=False, default=None)


def _code(gyrostat: bool) -> ModelCode:
    effects = ("contact_point", "gyrostat") if gyrostat else ("contact_point",)
    return load_model_code(SYSTEM, effects)


def _check_body(I, D, K, C) -> tuple[tuple[float, ...], float, tuple[float, ...], float]:
    I, D = check_inertia_vector(I, D, double=True)
    K = (0.0, 0.0, 0.0) if K is None else tuple(check_vector(K, "K", double=True))
    C = check_real(C, "C", nonzero=True, double=True)
    return tuple(float(v) for v in I), float(D), tuple(float(v) for v in K), float(C)


def _params(I, D, K, b=1.0) -> np.ndarray:
    gyro = any(k != 0 for k in K)
    return np.array([*I, D, b, *K] if gyro else [*I, D, b], float)


def segment_state(
    I: Sequence[float],
    D: float,
    gamma: Sequence[float],
    C: float = 1.0,
    K: Sequence[float] | None = None,
) -> np.ndarray:
    """The state on ``M + K = C gamma`` at ``gamma`` (``K = 0``: ``M = C gamma``), trace at 0.

    ``alpha`` is the unit vector of the body axis least aligned with ``gamma``, projected
    on the horizontal plane; ``beta = gamma x alpha``; ``x = y = 0``.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    gamma : sequence of 3 floats
        Unit vertical in the body (normalised here).
    C : float
        ``(M + K, gamma)``.
    K : sequence of 3 floats, optional
        Gyrostatic momentum (None or zero: the plain ball).

    Returns
    -------
    ndarray, shape (14,)
        ``M, gamma, alpha, beta, x, y``.
    """
    I, D, K, C = _check_body(I, D, K, C)
    g = _unit_vector(gamma, "gamma")
    e = np.zeros(3)
    e[int(np.argmin(np.abs(g)))] = 1.0
    a = e - g * detlinalg.dot(e, g)
    a = a / detlinalg.norm(a)
    beta = np.cross(g, a)
    return np.concatenate([C * g - np.asarray(K), g, a, beta, [0.0, 0.0]])


def _unit_vector(v, name: str) -> np.ndarray:
    """``v`` (three finite numbers, not all zero) normalised; errors name ``name``."""
    g = np.asarray([float(x) for x in check_vector(v, name, double=True)], float)
    norm = detlinalg.norm(g)
    if not norm > 0:
        raise UserInputError(f"{name} = {v!r} must be a nonzero vector (a direction)")
    return g / norm


def segment_energy(
    I: Sequence[float],
    D: float,
    gamma: np.ndarray,
    C: float = 1.0,
    K: Sequence[float] | None = None,
) -> np.ndarray:
    """Energy ``h`` on ``M + K = C gamma`` at unit vectors ``gamma`` (generated integrals).

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    gamma : ndarray, shape (3,) or (3, N)
        Unit vectors (real or complex: complex steps give derivatives).
    C : float
    K : sequence of 3 floats, optional

    Returns
    -------
    ndarray
        ``h``, shaped like ``gamma[0]``.
    """
    return _segment_energy(*_check_body(I, D, K, C), gamma)


def _segment_energy(I, D, K, C, gamma) -> np.ndarray:
    """:func:`segment_energy` with checked arguments (``I, D, K, C`` as floats)."""
    gyro = any(k != 0 for k in K)
    code = load_model_code(SYSTEM, ("gyrostat",) if gyro else ())
    g = np.asarray(gamma)
    M = C * g - np.asarray(K).reshape((3,) + (1,) * (g.ndim - 1))
    p = [*I, D, *K] if gyro else [*I, D]
    return code.numpy.integrals(0.0, np.concatenate([M, g]), p)[0]


def dense_solution(
    code: ModelCode, y0: np.ndarray, span: tuple[float, float], p: np.ndarray, rtol: float
) -> TaylorDense:
    """The double-precision Taylor solution over ``span`` with every step's polynomial (the
    ``taylor`` integrator with dense output, ``atol = rtol``).

    Parameters
    ----------
    code : ModelCode
    y0 : ndarray, shape (n_state,)
    span : (t0, t1)
    p : ndarray, shape (n_param,)
    rtol : float

    Returns
    -------
    TaylorDense
    """
    problem = Problem(code, y0, span, p, Precision("double"), rtol, rtol, dense_output=True)
    return INTEGRATORS["taylor"]().solve(problem).dense


def _period_solution(code: ModelCode, p: np.ndarray, y0: np.ndarray, rtol: float):
    """Integrate from ``y0`` until ``gamma`` first returns to ``gamma(0)``; the period.

    The return is the first upward crossing of the plane through ``gamma(0)`` normal to
    ``gamma'(0)`` within 1e-3 of ``gamma(0)``, located on the dense Taylor solution; the
    integration goes on in pieces of growing length until it is found.
    """
    f0 = code.numpy.rhs(0.0, y0, p)
    g0, u = y0[3:6], f0[3:6]
    speed = detlinalg.norm(u)
    if speed == 0:
        raise UserInputError("the start is an equilibrium of gamma (a steady rotation): no period")
    u = u / speed

    def plane(t, y):
        return detlinalg.dot(y[3:6] - g0, u)

    length = 50.0
    sol = dense_solution(code, y0, (0.0, length), p, rtol)
    while True:
        if sol.status:
            raise ComputationError(f"the integration stopped at t = {sol.t[-1]:g}: {sol.message}")
        times, states = sol.crossings(plane, direction=1)
        for t, y in zip(times, states, strict=True):
            if t > 1e-9 and detlinalg.norm(y[3:6] - g0) < 1e-3:
                return float(t), sol
        end = float(sol.t[-1])
        if end > MAX_PERIOD:
            raise ComputationError(f"gamma does not return within t = {MAX_PERIOD:g}")
        length *= 2
        sol.extend(end + length)


def _velocity(code, p, y) -> complex | np.ndarray:
    """``x' + i y'`` at the state(s) ``y``."""
    f = code.numpy.rhs(0.0, y, p)
    return detcomplex.make(f[12], f[13])


def _turn_between(v0: complex, v1: complex) -> float:
    """The angle from ``v0`` to ``v1`` in ``[-pi, pi]`` (the argument of ``v1 conj(v0)``)."""
    return detcomplex.phase(detcomplex.mul(v1, v0.conjugate()))


def trace_period(
    I: Sequence[float],
    D: float,
    h: float | None = None,
    C: float = 1.0,
    K: Sequence[float] | None = None,
    gamma0: Sequence[float] | None = None,
    rtol: float = 1e-12,
) -> TracePeriod:
    """One period of the trace on ``M || gamma`` (``K = 0``) or ``M + K || gamma``.

    Parameters
    ----------
    I : sequence of 3 floats
    D : float
    h : float, optional
        The energy (the plain ball without ``gamma0``: the start of
        :func:`~chaplygin.numerics.ball.frame_turn.near_separatrix_state`, ``gamma`` in the plane
        of the extreme axes).
    C : float
        ``(M + K, gamma)``.
    K : sequence of 3 floats, optional
        Gyrostatic momentum (needs ``gamma0``).
    gamma0 : sequence of 3 floats, optional
        The start on the segment (:func:`segment_state`); its energy is the orbit's.
    rtol : float
        Tolerance of the Taylor integration (relative and absolute).

    Returns
    -------
    TracePeriod

    Raises
    ------
    UserInputError
        Bad parameters, neither ``h`` (ball) nor ``gamma0`` given, or a start that is an
        equilibrium.
    ComputationError
        No return of ``gamma`` within ``t = 1e5``.

    References
    ----------
    K01-2.34, K01-Fig6f, K01-4.3 (FORMULAS.md).
    """
    I, D, K, C = _check_body(I, D, K, C)
    check_real(rtol, "rtol", positive=True, double=True)
    gyro = any(k != 0 for k in K)
    if gamma0 is None:
        if gyro or h is None:
            raise UserInputError("give gamma0 (the start on M + K = C gamma), or h for the ball")
        from .frame_turn import near_separatrix_state

        y0 = near_separatrix_state(I, D, float(check_real(h, "h", positive=True, double=True)), C)
    else:
        y0 = segment_state(I, D, _unit_vector(gamma0, "gamma0"), C, K)
    return _trace_period(I, D, K, C, tuple(y0), float(rtol))


@lru_cache(maxsize=512)
def _trace_period(I, D, K, C, y0, rtol) -> TracePeriod:
    gyro = any(k != 0 for k in K)
    code = _code(gyro)
    p = _params(I, D, K)
    y0 = np.asarray(y0, float)
    h = float(_segment_energy(I, D, K, C, y0[3:6]))
    T, sol = _period_solution(code, p, y0, rtol)
    yT = sol(T)
    count = max(4001, int(40 * T))
    while True:
        t = np.linspace(0.0, T, count)
        Y = sol(t)
        theta = np.unwrap(detcomplex.phase(_velocity(code, p, Y)))
        if np.max(np.abs(np.diff(theta))) <= MAX_SAMPLE_TURN or count > 2_000_000:
            break
        count *= 2
    turning = float(theta[-1] - theta[0])
    turn = _turn_between(_velocity(code, p, y0), _velocity(code, p, yT))
    z = detcomplex.make(Y[12], Y[13])
    d = complex(z[-1] - z[0])
    denominator = 1 - detcomplex.cis(turn)
    if denominator == 0:
        centre = complex(math.inf, math.inf)
        inner = outer = radius = math.inf
    else:
        centre = complex(z[0]) + detcomplex.div(d, denominator)
        radius = detcomplex.absolute(complex(z[0]) - centre)
        r = detcomplex.absolute(z - centre)
        inner = _extreme(sol, t, r, centre, +1)
        outer = _extreme(sol, t, r, centre, -1)
    return TracePeriod(
        h=h,
        period=T,
        turn=turn,
        turning=turning,
        displacement=d,
        centre=centre,
        radius=radius,
        inner=inner,
        outer=outer,
        speed=detcomplex.absolute(d) / T,
        closure=detlinalg.norm(yT[:6] - y0[:6]),
        t=t,
        z=z,
        y0=y0,
        sol=sol,
    )


def _extreme(sol, t, r, centre, sign) -> float:
    """Least (``sign = 1``) or largest (-1) ``|z(t) - c|``, refined about the best sample."""
    k = int(np.argmin(sign * r))
    lo, hi = t[max(k - 1, 0)], t[min(k + 1, len(t) - 1)]

    def f(s):
        y = sol(s)
        return sign * detcomplex.absolute(detcomplex.make(y[12], y[13]) - centre)

    res = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    return float(sign * min(res.fun, sign * r[k]))


def spiral_centres(
    I: Sequence[float], D: float, h: float, C: float = 1.0, rtol: float = 1e-12
) -> dict[str, object]:
    """The spiral centres of the trace near the middle axis (the ball, ``h`` near ``h2``).

    The passages are the maxima of ``|gamma_2|`` over one period (``gamma`` closest to
    ``+-e2``, two per period); at each, with the separatrix's ``lam`` and ``kap``
    (:func:`~chaplygin.numerics.ball.separatrix.separatrix_quantities`) and ``tau = 1/lam``,
    ``s = (z_+ - (r1 + r2) z_0 + r1 r2 z_-)/((1 - r1)(1 - r2))``, ``r1 = exp((lam + i kap)
    tau)``, ``r2 = exp((-lam + i kap) tau)``, from the trace at ``t* - tau, t*, t* + tau``:
    exact for the linearised passage ``s + P exp((lam + i kap) t) + Q exp((-lam + i kap) t)``
    (K01-3.5), with an error that vanishes as ``h -> h2``.

    Parameters
    ----------
    I : sequence of 3 floats
        ``I1 < I2 < I3`` (or ``I1 > I2 > I3``).
    D, h, C : float
    rtol : float

    Returns
    -------
    dict
        ``centres`` (complex, one per passage), ``times``, ``chord`` (``|s_1 - s_0|``),
        ``half_turn`` (the turn of the trace between the passages, ``(-pi, pi]``),
        ``radius`` (``|s_0 - c|``: the circle on which the centres move, ``c`` of
        :class:`TracePeriod`) and the period's :class:`TracePeriod` as ``period``.

    References
    ----------
    K01-3.3q, K01-3.5, K01-3.6, K01-3.7 (FORMULAS.md).
    """
    from .separatrix import check_inertia, separatrix_quantities

    check_inertia(I, D)
    tp = trace_period(I, D, h, C, rtol=rtol)
    Q = separatrix_quantities(I, D, C)
    lam, kap = float(Q["lam"]), float(Q["kap"])
    code = _code(False)
    p = _params(*_check_body(I, D, None, C)[:3])
    sol = tp.sol
    g2 = np.abs(sol(tp.t)[4])
    times = []
    for k in range(len(tp.t)):
        a, b = g2[k - 1] if k else g2[-2], g2[k + 1] if k + 1 < len(g2) else g2[1]
        if g2[k] > a and g2[k] >= b:
            lo, hi = tp.t[max(k - 1, 0)], tp.t[min(k + 1, len(tp.t) - 1)]
            rate = lambda s: code.numpy.rhs(s, sol(s), p)[4]  # noqa: E731
            if rate(lo) * rate(hi) < 0:
                times.append(float(brentq(rate, lo, hi, xtol=1e-13)))
            else:
                times.append(float(tp.t[k]))
    if len(times) < 2:
        raise ComputationError(f"found {len(times)} passage(s) near the middle axis, not 2")
    tau = 1.0 / lam
    r1 = detcomplex.exp(complex(lam * tau, kap * tau))
    r2 = detcomplex.exp(complex(-lam * tau, kap * tau))
    mul = detcomplex.mul
    den = mul(1 - r1, 1 - r2)
    centres = []
    for ts in times[:2]:
        zm, z0, zp = (_z_periodic(tp, s) for s in (ts - tau, ts, ts + tau))
        centres.append(detcomplex.div(zp - mul(r1 + r2, z0) + mul(mul(r1, r2), zm), den))
    v0 = _velocity(code, p, sol(times[0]))
    v1 = _velocity(code, p, sol(times[1]))
    return {
        "centres": centres,
        "times": times[:2],
        "chord": detcomplex.absolute(centres[1] - centres[0]),
        "half_turn": _turn_between(v0, v1),
        "radius": detcomplex.absolute(centres[0] - tp.centre),
        "period": tp,
    }


def _z_periodic(tp: TracePeriod, s: float) -> complex:
    """``z(s)`` for any real ``s``, from one period and the rule ``z(t + T) = z(T) +
    exp(i psi) (z(t) - z(0))``."""
    k, rest = divmod(s, tp.period)
    y = tp.sol(rest)
    w = detcomplex.make(y[12], y[13])
    z0, d = complex(tp.z[0]), tp.displacement
    rot = detcomplex.cis(tp.turn * k)
    if tp.turn == 0:
        base = complex(k * d.real, k * d.imag)
    else:
        base = detcomplex.div(detcomplex.mul(d, 1 - rot), 1 - detcomplex.cis(tp.turn))
    return z0 + base + detcomplex.mul(rot, w - z0)


