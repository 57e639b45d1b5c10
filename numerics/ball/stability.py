"""Floquet multipliers of the ball's periodic solutions (BKM12 §1.5, K01 §3.2).

The monodromy matrix comes from the variational equations ``Phi' = J(y) Phi`` with the
generated Jacobian, integrated together with the state (6 + 36 equations, DOP853) over one
period. The integrals ``F`` of the model (energy, ``(M, M)``, ``(M, gamma)``,
``(gamma, gamma)``) give trivial multipliers: ``dF(y0) Phi = dF(y0)``, so ``Phi`` maps the
tangent space ``ker dF(y0)`` of the level set into itself and fixes the flow direction.
On a critical orbit ``dF`` has rank 3 (that is what *critical* means), ``ker dF`` is
3-dimensional, and the map induced on ``ker dF / span f(y0)`` is a 2x2 matrix whose
eigenvalues are the nontrivial multipliers: a pair ``mu, 1/mu`` (unstable) or
``exp(+-i theta)`` (stable).

The periodic solutions are the derived families of ``derive/bifurcation.py``: the steady
rotations about ``e_i`` on ``Sigma_i`` (BKM12-25, BKM12-crit) and the Euler-top orbits on
``M = M_gamma gamma`` (``Sigma_4``, ``Sigma_5``, BKM12-Sigma45), whose period is found
from the first return to the initial state.

References
----------
BKM12-1.5stab, BKM12-1.5stab8, K01-3.2stab, BKM12-Sigma45.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache, lru_cache

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike
from scipy.optimize import brentq

from ...arith import detlinalg
from ...derive.bifurcation import steady_parameters, steady_rotation
from ...derive.emit import emit_function
from ...derive.errors import ComputationError, UserInputError
from ...derive.systems import build_model
from ..arguments import check_choice, check_inertia_vector, check_real
from ..code import ModelCode, load_model_code
from ..dynamics.variational import VariationalSystem

__all__ = [
    "FloquetResult",
    "critical_state",
    "euler_state",
    "return_period",
    "monodromy",
    "floquet",
    "integral_gradients",
    "support_steady_state",
    "steady_rotation_floquet",
    "euler_floquet",
]

SYSTEM = "chaplygin_ball"


@dataclass
class FloquetResult:
    """Multipliers of one periodic solution, with the evidence.

    Attributes
    ----------
    period : float
    multipliers : ndarray, shape (6,)
        All eigenvalues of the monodromy matrix.
    nontrivial : ndarray, shape (2,)
        Eigenvalues of the map induced on ``ker dF / span f`` (see the module docstring).
    max_abs : float
        ``max |nontrivial|``.
    tolerance : float
        ``sqrt(rtol)``: a pair on the unit circle that is about to leave it (a double
        multiplier) moves by the square root of a perturbation of size ``rtol``.
    stable : bool
        ``|max_abs - 1| <= tolerance``.
    closure : float
        ``|y(T) - y(0)|``: how well the orbit closes.
    drift : float
        Largest change of an integral over the period.
    rank : int
        Numerical rank of ``dF(y0)`` (3 on a critical orbit).
    """

    period: float
    multipliers: np.ndarray
    nontrivial: np.ndarray
    max_abs: float
    tolerance: float
    stable: bool
    closure: float
    drift: float
    rank: int
    y0: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(6))


@cache
def _critical_functions(axis: int):
    """Lambdified derived expressions: (w, g) on a level, and the state at t = 0."""
    model = build_model(SYSTEM, ())
    C, Mg = sp.Symbol("C", real=True), sp.Symbol("M_gamma", real=True)
    params = list(model.params)
    sols = steady_parameters(model, axis)
    par = [emit_function([C, Mg, *params], [s["w"], s["g"]], name="steady_level") for s in sols]
    fam = steady_rotation(model, axis)
    gamma = model.vectors["gamma"]
    g = sp.Symbol("g", real=True)
    j = (axis + 1) % 3
    at = {gamma[axis]: g, gamma[j]: sp.sqrt(1 - g**2), gamma[(axis + 2) % 3]: 0}
    state = [fam.state[s].xreplace({model.time: 0}).xreplace(at) for s in model.state]
    y_of = emit_function([fam.w, g, *params], state, name="steady_state")
    return par, y_of


def _params(I, D) -> list[float]:
    """``I1, I2, I3, D`` as floats, each finite and positive (errors name the argument)."""
    I, D = check_inertia_vector(I, D, double=True)
    return [float(v) for v in (*I, D)]


def critical_state(
    I: Sequence[float], D: float, axis: int, C: float, Mg: float = 0.0, branch: int = 0
) -> tuple[np.ndarray, float]:
    """A steady rotation about ``e_axis`` on the level ``(C, M_gamma)`` (BKM12-crit).

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    axis : {0, 1, 2}
        The body axis of the rotation.
    C, Mg : float
        ``(M, M)`` and ``(M, gamma)``; ``Mg**2 < C``.
    branch : {0, 1}
        The two senses of rotation.

    Returns
    -------
    y0 : ndarray, shape (6,)
        ``M, gamma`` at ``t = 0``.
    period : float
        ``2 pi/|w|``.

    Raises
    ------
    UserInputError
        Not three positive finite moments and a positive ``D``, or not ``C > 0`` and
        ``Mg**2 < C``.

    References
    ----------
    BKM12-25, BKM12-crit (FORMULAS.md).
    """
    p = _params(I, D)
    check_choice(axis, (0, 1, 2), "axis")
    check_choice(branch, (0, 1), "branch")
    C, Mg = float(check_real(C, "C", double=True)), float(check_real(Mg, "Mg", double=True))
    if not (C > 0 and Mg * Mg < C):
        raise UserInputError(f"need C > 0 and M_gamma^2 < C, got C={C}, M_gamma={Mg}")
    par, y_of = _critical_functions(axis)
    w, g = (float(v) for v in par[branch](C, Mg, *p))
    y0 = np.array([float(v) for v in y_of(w, g, *p)])
    return y0, 2 * np.pi / abs(w)


def euler_state(I: Sequence[float], D: float, C: float, Ep: float, sign: int = 1) -> np.ndarray:
    """A state with ``M = M_gamma gamma`` (``Sigma_4`` for sign +1, ``Sigma_5`` for -1).

    ``C = M_gamma^2`` and ``E' = E D/C``: the orbit lies on ``(gamma, A gamma) =
    E/(C + E D)`` (BKM12-Sigma45, Fig3); gamma(0) is taken in the plane of the axes of
    largest and smallest ``A_i``, which every such curve crosses.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    C : float
        ``C = (M, M) = M_gamma^2``.
    Ep : float
        ``E' = E D/C``.
    sign : {1, -1}
        ``M = sign sqrt(C) gamma``: ``Sigma_4`` (+1) or ``Sigma_5`` (-1).

    Returns
    -------
    ndarray, shape (6,)
        ``M, gamma`` at ``t = 0``.

    Raises
    ------
    UserInputError
        Bad ``I`` or ``D``, or ``E'`` outside the range of ``Sigma_4/5`` (the message
        gives the range).

    References
    ----------
    BKM12-Sigma45 (FORMULAS.md).
    """
    p = _params(I, D)
    A = 1 / (np.asarray(p[:3]) + p[3])
    q = Ep / (1 + Ep) / p[3]  # (gamma, A gamma) = E/(C + E D) = E'/((1 + E') D)
    hi, lo = int(np.argmax(A)), int(np.argmin(A))
    if not (A[lo] < q < A[hi]):
        raise UserInputError(
            f"E' = {Ep} is outside the range of Sigma_4/5: "
            f"({A[lo] * p[3] / (1 - A[lo] * p[3])}, {A[hi] * p[3] / (1 - A[hi] * p[3])})"
        )
    c2 = (q - A[lo]) / (A[hi] - A[lo])
    gamma = np.zeros(3)
    gamma[hi], gamma[lo] = np.sqrt(c2), np.sqrt(1 - c2)
    m = sign * np.sqrt(C)
    return np.concatenate([m * gamma, gamma])


def integral_gradients(code: ModelCode, y: ArrayLike, p: ArrayLike) -> np.ndarray:
    """``dF(y)`` of every integral of the model, complex-step derivatives, shape (k, n).

    Parameters
    ----------
    code : ModelCode
        The model (its numpy ``integrals``, which must accept complex states).
    y : array_like, shape (n,)
        State.
    p : array_like
        Parameters of the generated code.

    Returns
    -------
    ndarray, shape (k, n)
        Row ``i``: the gradient of integral ``i`` (step ``1e-30``, exact to rounding).
    """
    n = len(y)
    h = 1e-30
    Y = np.asarray(y, dtype=complex)[:, None] + 1j * h * np.eye(n)
    return np.imag(code.numpy.integrals(0.0, Y, p)) / h


def return_period(
    I: Sequence[float], D: float, y0: np.ndarray, t_max: float, rtol: float = 1e-12
) -> float:
    """First return time of a periodic orbit to ``y0``.

    Zeros of ``(y(t) - y0, f(y0))`` from below, found on the dense output and refined
    with Brent's method; the one where ``|y(t) - y0|`` is smallest within the first
    crossings is the period: the first crossing within ``1e-6 max(1, |y0|)`` of ``y0``.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    y0 : ndarray, shape (6,)
        A state of the periodic orbit (``M, gamma``).
    t_max : float
        Longest time searched (4000 samples of the dense output).
    rtol : float
        Relative and absolute tolerance of the DOP853 integration.

    Returns
    -------
    float
        The period.

    Raises
    ------
    RuntimeError
        When the orbit does not come back within ``t_max``.
    UserInputError
        Bad ``I`` or ``D``.
    """
    p = _params(I, D)
    code = load_model_code(SYSTEM)
    y0 = np.asarray(y0, dtype=float)
    f0 = np.asarray(code.numpy.rhs(0.0, y0, p), dtype=float)
    flow = VariationalSystem(code, p, rtol=rtol, atol=rtol)
    no_tangent = np.zeros((len(y0), 1))  # the state alone drives the error control

    def advance(y: np.ndarray, t0: float, t1: float) -> np.ndarray:
        return flow.flow(y, t0, t1, V0=no_tangent).y

    ts = np.linspace(0, t_max, 4000)
    ys = [y0]
    for k in range(1, ts.size):
        ys.append(advance(ys[-1], float(ts[k - 1]), float(ts[k])))
    h = [detlinalg.dot(y - y0, f0) for y in ys]
    scale = max(1.0, detlinalg.norm(y0))
    best = None
    for k in range(1, len(ts) - 1):
        if h[k] < 0 <= h[k + 1]:
            yk, tk = ys[k], float(ts[k])
            t = brentq(
                lambda s, yk=yk, tk=tk: detlinalg.dot(advance(yk, tk, s) - y0, f0),
                tk, float(ts[k + 1]), xtol=1e-14,
            )  # fmt: skip
            dist = detlinalg.norm(advance(yk, tk, t) - y0)
            if dist < 1e-6 * scale:
                return float(t)
            if best is None or dist < best[1]:
                best = (t, dist)
    raise ComputationError(f"no return to the initial state within t = {t_max} (closest: {best})")


def monodromy(
    code: ModelCode, y0: np.ndarray, T: float, p: ArrayLike, rtol: float = 1e-12
) -> tuple[np.ndarray, np.ndarray]:
    """``Phi(T)`` of the variational equations, and ``y(T)`` (DOP853, atol = rtol).

    ``Phi' = J(y) Phi``, ``Phi(0) = Id``, integrated together with ``y' = f(y)``.

    Parameters
    ----------
    code : ModelCode
        The model (numpy ``rhs`` and ``jac``).
    y0 : ndarray, shape (n,)
        Initial state.
    T : float
        End time (the period).
    p : array_like
        Parameters of the generated code.
    rtol : float
        Relative and absolute tolerance.

    Returns
    -------
    Phi : ndarray, shape (n, n)
        The monodromy matrix.
    yT : ndarray, shape (n,)
        The state at ``T``.

    Raises
    ------
    RuntimeError
        If the integration fails.

    References
    ----------
    BKM12-1.5stab (FORMULAS.md).
    """
    res = VariationalSystem(code, p, rtol=rtol, atol=rtol).flow(y0, 0.0, float(T))
    return res.V, res.y


def floquet(
    I: Sequence[float],
    D: float,
    y0: ArrayLike,
    T: float,
    rtol: float = 1e-12,
    *,
    system: str = SYSTEM,
    params: Sequence[float] | None = None,
    effects: Sequence[str] = (),
) -> FloquetResult:
    """Floquet multipliers of the periodic solution through ``y0`` with period ``T``.

    ``system``, ``effects`` and ``params`` (the generated code's parameter vector) select
    another model (the spherical support, the ball with a gyrostat); ``I, D`` are then
    ignored.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    y0 : array_like, shape (n,)
        A state of the periodic solution.
    T : float
        Its period.
    rtol : float
        Tolerance of :func:`monodromy`; ``sqrt(rtol)`` is the stability tolerance.
    system : str
        Model name.
    params : sequence of floats, optional
        The generated code's parameter vector (replaces ``I, D``).
    effects : sequence of str
        Effects of the model (``("gyrostat",)``).

    Returns
    -------
    FloquetResult
        All and the nontrivial multipliers, stability, closure, drift of the integrals
        and the rank of ``dF(y0)``.

    Raises
    ------
    UserInputError
        Bad ``I`` or ``D`` (when ``params`` is None).

    References
    ----------
    BKM12-1.5stab, BKM12-1.5stab8.
    """
    p = _params(I, D) if params is None else [float(v) for v in params]
    code = load_model_code(system, tuple(effects))
    y0 = np.asarray(y0, dtype=float)
    Phi, yT = monodromy(code, y0, T, p, rtol)
    dF = integral_gradients(code, y0, p)
    normal, K = detlinalg.orthonormal_split(dF, rtol=1e-8)  # K: orthonormal basis of ker dF
    rank = normal.shape[1]
    f = np.asarray(code.numpy.rhs(0.0, y0, p), dtype=float)
    f = f / detlinalg.norm(f)
    # quotient by the flow direction: basis of ker dF orthogonal to f
    fk = detlinalg.matmul(K.T, f)
    _, B_k = detlinalg.orthonormal_split(fk[None, :])
    B = detlinalg.matmul(K, B_k)  # (n, n - rank - 1), orthonormal, orthogonal to f
    # induced map on ker dF / span f: project Phi B back onto B along f
    P = np.eye(len(y0)) - f[:, None] * f[None, :]
    Mq = detlinalg.matmul(B.T, detlinalg.matmul(P, detlinalg.matmul(Phi, B)))
    nontrivial = detlinalg.eigvals(Mq)
    F0 = code.numpy.integrals(0.0, y0, p)
    FT = code.numpy.integrals(0.0, yT, p)
    tol = float(np.sqrt(rtol))
    max_abs = float(np.max(np.abs(nontrivial)))
    return FloquetResult(
        period=float(T),
        multipliers=detlinalg.eigvals(Phi),
        nontrivial=nontrivial,
        max_abs=max_abs,
        tolerance=tol,
        stable=abs(max_abs - 1) <= tol,
        closure=detlinalg.norm(yT - y0),
        drift=float(np.max(np.abs(FT - F0))),
        rank=rank,
        y0=y0,
    )


def steady_rotation_floquet(
    I: tuple[float, float, float],
    D: float,
    C: float = 1.0,
    Mg: float = 0.0,
    rtol: float = 1e-12,
) -> tuple[FloquetResult, FloquetResult, FloquetResult]:
    """:func:`floquet` of the steady rotations about ``e_1, e_2, e_3`` on ``(C, M_gamma)``.

    Results are memoised (on ``tuple(I)`` and the other arguments).

    Parameters
    ----------
    I : tuple of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    C, Mg : float
        ``(M, M)`` and ``(M, gamma)``; ``Mg**2 < C``.
    rtol : float
        Tolerance of :func:`floquet`.

    Returns
    -------
    tuple of 3 FloquetResult
        The rotations about ``e_1``, ``e_2``, ``e_3`` (branch 0 of :func:`critical_state`).

    Raises
    ------
    UserInputError
        From :func:`critical_state`.

    References
    ----------
    BKM12-1.5stab, BKM12-1.5stab8, K01-3.2stab.
    """
    _params(I, D)
    for name, value in (("C", C), ("Mg", Mg)):
        check_real(value, name, double=True)
    check_real(rtol, "rtol", positive=True, double=True)
    return _steady_rotation_floquet(tuple(I), D, C, Mg, rtol)


@lru_cache(maxsize=256)
def _steady_rotation_floquet(I, D, C, Mg, rtol) -> tuple[FloquetResult, ...]:
    out = []
    for axis in range(3):
        y0, T = critical_state(I, D, axis, C, Mg)
        out.append(floquet(I, D, y0, T, rtol=rtol))
    return tuple(out)


def euler_floquet(I: Sequence[float], D: float, Ep: float, rtol: float = 1e-12) -> FloquetResult:
    """:func:`floquet` of the Euler-top orbit ``M = gamma`` at ``E' = Ep`` (``Sigma_4``, C = 1).

    Its period comes from :func:`return_period` within 40 periods of the fastest rotation.
    Results are memoised (on ``tuple(I)``).

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    Ep : float
        ``E' = E D/C`` (:func:`euler_state`).
    rtol : float
        Tolerance of the integrations.

    Returns
    -------
    FloquetResult
        Multipliers and evidence of the orbit through :func:`euler_state` ``(I, D, 1, Ep)``.

    Raises
    ------
    UserInputError
        Arguments of a wrong type or non-physical, or from :func:`euler_state`.
    RuntimeError
        From :func:`return_period`: no return found.

    References
    ----------
    BKM12-1.5stab8, BKM12-Sigma45.
    """
    _params(I, D)
    check_real(Ep, "Ep", double=True)
    check_real(rtol, "rtol", positive=True, double=True)
    return _euler_floquet(tuple(I), D, Ep, rtol)


@lru_cache(maxsize=256)
def _euler_floquet(I, D, Ep, rtol) -> FloquetResult:
    y0 = euler_state(I, D, 1.0, Ep)
    A = 1 / (np.asarray(I, float) + D)
    T = return_period(I, D, y0, t_max=40 * 2 * np.pi / A.min(), rtol=rtol)
    return floquet(I, D, y0, T, rtol=rtol)


@cache
def _support_functions(axis: int):
    model = build_model("spherical_support", ())
    fam = steady_rotation(model, axis)
    frame = [s for n in ("alpha", "beta", "gamma") for s in model.vectors[n]]
    state = [fam.state[s].xreplace({model.time: 0}) for s in model.state]
    return emit_function([fam.w, *frame, *model.params], state, name="support_state")


def support_steady_state(
    params: Sequence[float], axis: int, w: float, frame: ArrayLike
) -> tuple[np.ndarray, float]:
    """Steady rotation ``omega = w e_axis`` of the spherical support (BKM12-2.7b).

    Parameters
    ----------
    params : sequence of 6 floats
        ``I1, I2, I3, D_iso, D_al, D_be``.
    axis : {0, 1, 2}
        The body axis of the rotation.
    w : float
        Angular velocity (nonzero).
    frame : array_like, shape (3, 3)
        Rows ``alpha, beta, gamma`` at ``t = 0`` (orthonormal, right-handed).

    Returns
    -------
    y0 : ndarray, shape (12,)
        The state of ``spherical_support`` at ``t = 0``.
    period : float
        ``2 pi/|w|``.

    Raises
    ------
    UserInputError
        If ``frame`` is not three orthonormal rows.

    References
    ----------
    BKM12-2.7b (FORMULAS.md).
    """
    F = np.asarray(frame, dtype=float)
    if F.shape != (3, 3) or not np.allclose(detlinalg.matmul(F, F.T), np.eye(3), atol=1e-12):
        raise UserInputError("the frame must be three orthonormal rows alpha, beta, gamma")
    y = _support_functions(axis)(w, *F.ravel(), *[float(v) for v in params])
    return np.array([float(v) for v in y]), 2 * np.pi / abs(w)
