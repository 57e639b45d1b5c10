"""The frame turn on the separatrix and near it (K01 §3.3, Fig. 6): the contact point's trace
near the separatrix, the turn of the frame over a period as a function of the energy, the
critical energies where it changes sign, the spiral centres of the trace, and Delta read from
the traces (a fourth route to K01-3.4).

References
----------
K01-3.4, K01-Fig6 (FORMULAS.md).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...derive.errors import ComputationError, UserInputError
from ..arguments import check_inertia_vector, check_real
from .separatrix import check_inertia, separatrix_quantities

__all__ = [
    "critical_energy",
    "delta_from_traces",
    "frame_turn",
    "near_separatrix_state",
    "separatrix_trace",
    "spiral_centre",
]


def near_separatrix_state(I: Sequence[float], D: float, h: float, C: float = 1.0) -> np.ndarray:
    """A state on ``M = C gamma`` with energy ``h`` in ``[C^2/(2 I3), C^2/(2 I1)]``.

    ``gamma = (cos psi, 0, sin psi)`` with ``(gamma, A gamma) = 1/(D + C^2/(2h))``
    (K01-3.3seg), ``alpha = e2``, ``beta = gamma x alpha``; ``x = y = 0``.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D, h, C : float
        ``D = m b^2``, the energy and ``C = (M, gamma)``.

    Returns
    -------
    numpy.ndarray, shape (14,)
        State of ``chaplygin_ball__contact_point``: ``M, gamma, alpha, beta, x, y``.

    Raises
    ------
    UserInputError
        If ``h`` is not on the segment ``n = C^2`` (or ``I``, ``D``, ``C`` are refused).

    References
    ----------
    K01-3.3seg (FORMULAS.md).
    """
    import numpy as np

    _check_frame_args(I, D, h, C)
    J1, _, J3 = (float(v) + D for v in I)
    g = 1.0 / (D + C**2 / (2 * h))
    c2 = (g - 1 / J3) / (1 / J1 - 1 / J3)
    if not 0 <= c2 <= 1:
        raise UserInputError(f"h = {h} is not on the segment n = C^2")
    gamma = np.array([np.sqrt(c2), 0.0, np.sqrt(1 - c2)])
    alpha = np.array([0.0, 1.0, 0.0])
    beta = np.cross(gamma, alpha)
    return np.concatenate([C * gamma, gamma, alpha, beta, [0.0, 0.0]])


def _check_frame_args(I, D, h, C) -> None:
    """The checks of :func:`near_separatrix_state` and :func:`frame_turn` (double precision)."""
    check_inertia(I, D)
    check_inertia_vector(I, D, double=True)
    check_real(h, "h", positive=True, double=True)
    check_real(C, "C", nonzero=True, double=True)


def separatrix_trace(
    I: Sequence[float], D: float, b: float, C: float = 1.0, n: int = 2001
) -> tuple[np.ndarray, np.ndarray]:
    """``x(t), y(t)`` of the contact point on the separatrix (K01 Fig. 4).

    Cumulative integrals (Simpson) of K01-3.5 with ``nu = -b lam`` over ``lam t`` in
    ``[-25, 25]``.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia, ``I1 < I2 < I3``.
    D, b, C : float
        ``D = m b^2``, the radius and ``C = (M, gamma)``.
    n : int
        Number of points.

    Returns
    -------
    x, y : numpy.ndarray, shape (n,)
        The contact point at ``lam t = linspace(-25, 25, n)``, zero at ``lam t = -25``.

    References
    ----------
    K01-3.5, K01-Fig4 (FORMULAS.md).
    """
    import numpy as np
    from scipy.integrate import cumulative_simpson

    Q = separatrix_quantities(I, D, C)
    lam, kap = float(Q["lam"]), float(Q["kap"])
    s = np.linspace(-25, 25, n)  # s = lam t
    nu = -b * lam
    xr = nu * np.cos(kap / lam * s) / np.cosh(s) / lam
    yr = nu * np.sin(kap / lam * s) / np.cosh(s) / lam
    return cumulative_simpson(xr, x=s, initial=0), cumulative_simpson(yr, x=s, initial=0)


def frame_turn(
    I: Sequence[float], D: float, h: float, C: float = 1.0, rtol: float = 1e-12
) -> tuple[float, float]:
    """Period of ``gamma(t)`` on ``M = C gamma`` at energy ``h`` and the turn of the frame.

    After one period ``T`` of ``gamma`` (an Euler top, K01-2.34) the space-fixed horizontal
    frame seen from the body has turned by ``Phi`` about ``gamma(0)``; the contact-point
    trace is a chain of copies rotated by ``Phi`` and is unbounded exactly when
    ``Phi = 0 mod 2 pi`` (K01-Fig6f). Double precision (the generated Taylor integrator in C,
    the return located on its step polynomials), ``h`` in ``(h3, h1)``, ``h != h2``.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D, h, C : float
        ``D = m b^2``, the energy and ``C = (M, gamma)``.
    rtol : float
        Relative and absolute tolerance of the Taylor integration.

    Returns
    -------
    (T, Phi) : tuple of float
        ``Phi`` in ``(-pi, pi]``.

    Raises
    ------
    ValueError
        From :func:`near_separatrix_state`: ``h`` off the segment ``n = C^2``.
    RuntimeError
        If ``gamma`` does not return within ``t = 10^5``.

    References
    ----------
    K01-2.34, K01-Fig6f (FORMULAS.md).
    """
    from ...arith import detlinalg, detmath
    from ..code import load_model_code
    from ..dynamics.poincare import EventSection

    _check_frame_args(I, D, h, C)
    check_real(rtol, "rtol", positive=True, double=True)
    code = load_model_code("chaplygin_ball", ("contact_point",))
    p = [float(v) for v in I] + [float(D), 1.0]
    y0 = near_separatrix_state(I, D, h, C)
    # start off the plane gamma2 = 0 crossing: a full period returns to gamma2 = 0 going
    # the same way
    f0 = code.numpy.rhs(0.0, y0, p)
    direction = 1 if f0[4] > 0 else -1

    def gamma2(t, y):
        return y[4]

    # the first return with the same direction (crossings at t > 0), located on the Taylor
    # polynomial of the deterministic C integrator
    section = EventSection(code, p, gamma2, direction=direction, rtol=rtol, atol=rtol, chunk=50.0)
    orbit = section.crossings(list(y0), 2, t_max=1e5)
    later = [k for k in range(len(orbit.t)) if orbit.t[k] > 1e-9]
    if not later:
        raise ComputationError("no return of gamma found")
    T, yT = float(orbit.t[later[0]]), orbit.y[later[0]]
    a0, b0 = y0[6:9], y0[9:12]
    aT = yT[6:9]
    return T, detmath.atan2(detlinalg.dot(aT, b0), detlinalg.dot(aT, a0))


def critical_energy(
    I: Sequence[float], D: float, bracket: tuple[float, float], C: float = 1.0
) -> float:
    """The energy in ``bracket`` where :func:`frame_turn`'s ``Phi`` vanishes (Brent's method).

    Where the trace becomes unbounded (K01-Fig6f); accuracy limited by the double-precision
    integration (``rtol = 1e-12``): about 1e-9 in ``h``.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    bracket : (float, float)
        Energies ``h`` where ``Phi`` has opposite signs, inside ``(h3, h1)``.
    C : float
        ``C = (M, gamma)``.

    Returns
    -------
    float
        The critical energy.

    Raises
    ------
    ValueError
        If ``Phi`` has the same sign at both ends of ``bracket`` (from Brent's method).

    References
    ----------
    K01-Fig6f (FORMULAS.md).
    """
    from scipy.optimize import brentq

    check_inertia(I, D)
    check_real(C, "C", nonzero=True, double=True)
    if isinstance(bracket, str | bytes) or not hasattr(bracket, "__len__") or len(bracket) != 2:
        raise UserInputError(f"bracket = {bracket!r} must be two energies (low, high)")
    for i, h in enumerate(bracket):
        check_real(h, f"bracket[{i}]", positive=True, double=True)

    return float(brentq(lambda h: frame_turn(I, D, h, C)[1], *bracket, xtol=1e-12))


def spiral_centre(z: Sequence[complex] | np.ndarray, lag: int) -> tuple[complex, float, int]:
    """The point a contact-point trace spirals into, from the trace alone (K01 Fig. 4).

    Near its asymptotic centre ``z_oo`` the trace ``z = x + i y`` of a separatrix motion is a
    logarithmic spiral, ``z(t) - z_oo ~ A exp((-lam + i kap) t)`` (K01-3.6), so equally spaced
    samples form a complex geometric sequence and Aitken's extrapolation
    ``z_oo ~ z2 - (z2 - z1)^2/(z2 - 2 z1 + z0)`` removes that term exactly; what remains is
    ``O(exp(-3 lam t))``. Further along, the separatrix's instability (a deviation ``delta``
    grows like ``delta exp(lam t)``) spoils the trace, so the estimate taken is the one of the
    window where consecutive estimates agree best (the plateau between the two errors).

    Parameters
    ----------
    z : sequence of complex
        The trace ``x + i y`` at equally spaced times, in the direction of the limit
        (forward for ``t -> +oo``, backward for ``t -> -oo``); at least ``3 lag + 1`` points.
    lag : int
        Samples between the three points of one extrapolation (about ``1/(lam dt)``: well
        conditioned when the spiral contracts by a factor ``e`` between them).

    Returns
    -------
    centre : complex
        The extrapolated centre.
    spread : float
        ``|E_k+lag - E_k|`` at the chosen window: how far consecutive estimates differ there.
    index : int
        Index of the first sample of the chosen window.

    Raises
    ------
    UserInputError
        ``lag`` not a positive integer, or fewer than ``3 lag + 1`` samples.

    References
    ----------
    K01-3.6, K01-3.7, K01-Fig4 (FORMULAS.md).
    """
    z = np.asarray(z, dtype=complex)
    if isinstance(lag, bool) or not isinstance(lag, int | np.integer) or lag < 1:
        raise UserInputError(f"lag = {lag!r} must be a positive integer")
    if z.ndim != 1 or len(z) < 3 * lag + 1:
        raise UserInputError(
            f"the trace has {len(z)} points: the spiral's centre needs at least {3 * lag + 1}"
        )
    z0, z1, z2 = z[: -2 * lag], z[lag:-lag], z[2 * lag :]
    den = z2 - 2 * z1 + z0
    with np.errstate(divide="ignore", invalid="ignore"):
        estimate = np.where(den != 0, z2 - (z2 - z1) ** 2 / den, z2)
    change = np.abs(estimate[lag:] - estimate[:-lag])
    change[~np.isfinite(change)] = np.inf
    k = int(np.argmin(change))
    return complex(estimate[k]), float(change[k]), k


def delta_from_traces(
    z_forward: Sequence[complex] | np.ndarray,
    z_backward: Sequence[complex] | np.ndarray,
    lag: int,
) -> dict[str, object]:
    """Delta measured on a trace: the distance between its two asymptotic centres.

    Parameters
    ----------
    z_forward, z_backward : sequence of complex
        The trace ``x + i y`` from the same start forward and backward in time, equally
        spaced (see :func:`spiral_centre`).
    lag : int
        See :func:`spiral_centre`.

    Returns
    -------
    dict
        ``delta`` (``|z(+oo) - z(-oo)|``), ``centre_forward``, ``centre_backward`` (complex),
        ``spread`` (the larger of the two plateau spreads), ``index_forward``,
        ``index_backward``.

    Raises
    ------
    UserInputError
        From :func:`spiral_centre`.

    References
    ----------
    K01-3.7, K01-Fig4 (FORMULAS.md).
    """
    fwd, s_f, k_f = spiral_centre(z_forward, lag)
    bwd, s_b, k_b = spiral_centre(z_backward, lag)
    return {
        "delta": abs(fwd - bwd),
        "centre_forward": fwd,
        "centre_backward": bwd,
        "spread": max(s_f, s_b),
        "index_forward": k_f,
        "index_backward": k_b,
    }
