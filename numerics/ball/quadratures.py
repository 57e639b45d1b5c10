"""Action variables, frequencies and the rotation number at zero constant of areas.

Quadratures (K01-2.23, 2.26, 2.27 with the true turning points): on the torus of a state
with ``(M, gamma) = 0`` the sphero-conical coordinates oscillate between consecutive real
roots of ``R(q) = (2 lam1 + q lam2)(q - a1)(q - a2)(q - a3)(1 + D q)`` (K01-2.17,
``a_i = 1/I_i``, ``lam1 = h``, ``lam2 = 2 D h - n``, K01-2.18), found with
``mpmath.polyroots`` at the working precision. One of the two ranges ends at the extra
root ``q* = -2 lam1/lam2``, not at ``a2`` as K01 prints (FORMULAS.md K01-2.23).

With ``A_i = int dq/sqrt(R)`` and ``B_i = int q dq/sqrt(R)`` over the range of ``q_i``, the
Abel–Jacobi equations (K01-2.22) give the frequencies (oscillations per unit of the time
``tau`` of K01-2.7) ``nu1 = c0 B2/(2 (A2 B1 - A1 B2))``, ``nu2 = c0 B1/(2 (A2 B1 - A1 B2))``,
``c0 = 2/sqrt(prod(1 + D a_i))``, and the rotation number ``nu1/nu2 = B2/B1`` (K01-2.27,
corrected limits; independent of the time change). The substitution
``q = m + r sin(theta)`` removes the endpoint singularities, so Gauss–Legendre
quadrature converges exponentially.

:func:`measured_rotation_number` measures the same number from an integrated trajectory
(DOP853, double precision): the phase of each coordinate's oscillation in the plane
``(q_i - c_i, q_i')`` is unwrapped and its weighted Birkhoff average (smooth bump weight,
super-polynomial convergence on a non-resonant torus) gives the ratio.

References
----------
K01-2.17, K01-2.18, K01-2.22, K01-2.23, K01-2.26, K01-2.27
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import lru_cache

import mpmath
import numpy as np
import sympy as sp

from ...arith import detmath
from ...derive import hamiltonisation as hz
from ...derive.emit import emit_function
from ...derive.errors import ComputationError, UserInputError
from ..arguments import check_count, check_inertia_vector, check_real, check_vector
from ..code import load_model_code

__all__ = [
    "TorusQuadratures",
    "torus_quadratures",
    "rotation_number",
    "measured_rotation_number",
    "MeasuredRotation",
    "spheroconical_coordinates",
    "separation_roots",
    "separation_R",
]


#: Most output samples :func:`measured_rotation_number` takes (about 1 GB of states).
MAX_SAMPLES = 10**7


@lru_cache(maxsize=1)
def _R_coefficients():
    """Coefficients of R(q) (highest first) as an mpmath function of (lam1, lam2, a, D);
    see :func:`separation_R`."""
    q, l1, l2, D = sp.symbols("q lam1 lam2 D")
    a = sp.symbols("a1:4")
    poly = sp.Poly(sp.expand(hz.separation_polynomial(q, l1, l2, a, D)), q)
    return emit_function((l1, l2, *a, D), poly.all_coeffs(), "mpmath", name="R_coefficients")


@dataclass
class TorusQuadratures:
    """Quadratures of one torus at ``(M, gamma) = 0``.

    Attributes
    ----------
    h, n : mpf
        Energy ``(M, omega)/2`` and ``(M, M)``.
    lam1, lam2 : mpf
        Separation constants (K01-2.18).
    roots : list of mpf
        Real roots of R, ascending.
    ranges : ((lo1, hi1), (lo2, hi2))
        Oscillation ranges of ``q1`` and ``q2`` (consecutive roots of R).
    q0 : (mpf, mpf)
        Sphero-conical coordinates of the state.
    A, B : (mpf, mpf)
        ``int dq/sqrt(R)`` and ``int q dq/sqrt(R)`` over each range.
    actions : (mpf, mpf)
        ``oint p_i dq_i`` with the canonical momenta of K01-2.13.
    frequencies : (mpf, mpf)
        Oscillations of ``q1``, ``q2`` per unit of ``tau`` (K01-2.7).
    rotation_number : mpf
        ``nu1/nu2 = B2/B1``.
    digits : int
        Working precision.
    """

    h: object
    n: object
    lam1: object
    lam2: object
    roots: list
    ranges: tuple
    q0: tuple
    A: tuple
    B: tuple
    actions: tuple
    frequencies: tuple
    rotation_number: object
    digits: int
    details: dict = field(default_factory=dict)


def spheroconical_coordinates(
    gamma: Sequence[float | mpmath.mpf] | np.ndarray, a: Sequence[float | mpmath.mpf]
) -> tuple[mpmath.mpf | np.ndarray, mpmath.mpf | np.ndarray]:
    """``q1 > q2``: the roots of ``sum_i gamma_i^2 prod_{j!=i}(a_j - x) = 0`` (K01-2.11).

    On the sphere the polynomial is ``x^2 - s x + p``.

    Parameters
    ----------
    gamma : sequence of 3 numbers, or ndarray, shape (3,) or (3, N)
        The vertical (normalised here, need not be a unit vector); an array evaluates many
        states at once.
    a : sequence of 3 numbers
        ``a_i = 1/I_i``.

    Returns
    -------
    q1, q2 : mpmath.mpf or ndarray, shape (N,)
        ``q1 >= q2`` (a negative discriminant from rounding counts as zero).

    References
    ----------
    K01-2.11 (FORMULAS.md).

    Raises
    ------
    UserInputError
        ``a`` not three positive numbers; ``gamma`` not three finite numbers (or a (3, N)
        array of them) or zero.
    """
    check_vector(a, "a", positive=True)
    if isinstance(gamma, np.ndarray) and gamma.ndim == 2:
        if gamma.shape[0] != 3 or not np.all(np.isfinite(gamma)):
            raise UserInputError(f"gamma must be finite with shape (3, N), got {gamma.shape}")
        if np.any(np.sum(gamma * gamma, axis=0) == 0):
            raise UserInputError("gamma must not be zero (it is normalised here)")
    elif all(v == 0 for v in check_vector(gamma, "gamma")):
        raise UserInputError("gamma must not be zero (it is normalised here)")
    g2 = [g * g for g in gamma]
    norm = g2[0] + g2[1] + g2[2]
    s = (g2[0] * (a[1] + a[2]) + g2[1] * (a[0] + a[2]) + g2[2] * (a[0] + a[1])) / norm
    p = (g2[0] * a[1] * a[2] + g2[1] * a[0] * a[2] + g2[2] * a[0] * a[1]) / norm
    disc = s * s - 4 * p
    if isinstance(disc, np.ndarray):
        r = np.sqrt(np.maximum(disc, 0.0))
    else:
        r = mpmath.sqrt(disc) if disc > 0 else 0 * disc
    return (s + r) / 2, (s - r) / 2


def _check_separation_args(lam1, lam2, a, D) -> None:
    """Finite ``lam1``, ``lam2``, three positive ``a`` and a positive ``D``."""
    check_real(lam1, "lam1")
    check_real(lam2, "lam2")
    check_vector(a, "a", positive=True)
    check_real(D, "D", positive=True)


def separation_roots(
    lam1: float | mpmath.mpf,
    lam2: float | mpmath.mpf,
    a: Sequence[float | mpmath.mpf],
    D: float | mpmath.mpf,
) -> list[mpmath.mpf]:
    """Real roots of R (K01-2.17), ascending, by ``mpmath.polyroots`` at the working precision.

    Parameters
    ----------
    lam1, lam2 : number
        Separation constants ``lam1 = h``, ``lam2 = 2 D h - n`` (K01-2.18).
    a : sequence of 3 numbers
        ``a_i = 1/I_i``.
    D : number
        ``D = m b^2``.

    Returns
    -------
    list of mpmath.mpf
        The roots whose imaginary part is below ``10^(-dps/2) (1 + |r|)``, real parts,
        ascending.

    References
    ----------
    K01-2.17, K01-2.18 (FORMULAS.md).
    """
    _check_separation_args(lam1, lam2, a, D)
    coeffs = _R_coefficients()(lam1, lam2, *a, D)
    roots = mpmath.polyroots(coeffs, maxsteps=200, extraprec=2 * mpmath.mp.prec)
    tol = mpmath.mpf(10) ** (-mpmath.mp.dps // 2)
    return sorted(mpmath.re(r) for r in roots if abs(mpmath.im(r)) <= tol * (1 + abs(r)))


def _state(I, D, M, gamma, dps):
    check_inertia_vector(I, D)
    check_vector(M, "M")
    check_vector(gamma, "gamma")
    I = [mpmath.mpf(x) for x in I]
    D = mpmath.mpf(D)
    M = [mpmath.mpf(x) for x in M]
    gamma = [mpmath.mpf(x) for x in gamma]
    if not (I[0] < I[1] < I[2]):
        raise UserInputError("sphero-conical coordinates need I1 < I2 < I3 (K01-2.11)")
    ng = mpmath.sqrt(sum(g * g for g in gamma))
    if abs(ng - 1) > mpmath.mpf(10) ** (-8):
        raise UserInputError(f"gamma must be a unit vector, |gamma| = {mpmath.nstr(ng, 10)}")
    gamma = [g / ng for g in gamma]
    C = sum(m * g for m, g in zip(M, gamma, strict=True))
    scale = mpmath.sqrt(sum(m * m for m in M))
    if abs(C) > mpmath.mpf(10) ** (-8) * max(scale, 1):
        raise UserInputError(
            f"the quadratures need (M, gamma) = 0 (K01 §2.2), got {mpmath.nstr(C, 6)}"
        )
    M = [m - C * g for m, g in zip(M, gamma, strict=True)]
    return I, D, M, gamma


def separation_R(
    lam1: float | mpmath.mpf,
    lam2: float | mpmath.mpf,
    a: Sequence[float | mpmath.mpf],
    D: float | mpmath.mpf,
) -> Callable[[mpmath.mpf], mpmath.mpf]:
    """``R(q)`` of K01-2.17 (from ``derive/hamiltonisation.py``) as an mpmath function of q.

    Parameters
    ----------
    lam1, lam2 : number
        Separation constants (K01-2.18).
    a : sequence of 3 numbers
        ``a_i = 1/I_i``.
    D : number
        ``D = m b^2``.

    Returns
    -------
    callable
        ``q -> R(q)``, Horner's scheme on the coefficients computed once here.

    References
    ----------
    K01-2.17 (FORMULAS.md).
    """
    _check_separation_args(lam1, lam2, a, D)
    coeffs = _R_coefficients()(lam1, lam2, *a, D)
    return lambda q: mpmath.polyval(coeffs, q)


def torus_quadratures(
    I: Sequence[float | mpmath.mpf],
    D: float | mpmath.mpf,
    M: Sequence[float | mpmath.mpf],
    gamma: Sequence[float | mpmath.mpf],
    digits: int = 30,
) -> TorusQuadratures:
    """Quadratures of the torus through ``(M, gamma)`` with ``(M, gamma) = 0``.

    Parameters
    ----------
    I : three numbers, ``I1 < I2 < I3``
        Moments of inertia.
    D : number
        ``D = m b^2``.
    M, gamma : three numbers each; ``gamma`` a unit vector, ``(M, gamma) = 0``
        The state.
    digits : int
        Working precision (decimal digits, at least 15).

    Returns
    -------
    TorusQuadratures
        Integrals, roots, ranges, ``A``, ``B``, actions, frequencies and the rotation
        number (computed at ``digits + 10``).

    Raises
    ------
    UserInputError
        ``digits`` not an integer ``>= 15``, non-physical parameters, ``(M, gamma) != 0``,
        or a state on a critical torus
        (a range whose ends are not two simple roots of R).

    References
    ----------
    K01-2.17, K01-2.18, K01-2.22, K01-2.23, K01-2.26, K01-2.27
    """
    check_count(digits, "digits", 15, 10000)
    with mpmath.workdps(digits + 10):
        I, D, M, gamma = _state(I, D, M, gamma, digits)
        code = load_model_code("chaplygin_ball", ())
        vals = code.mpmath.integrals(mpmath.mpf(0), list(M) + list(gamma), list(I) + [D])
        h, n = vals[code.integral_names.index("H")], vals[code.integral_names.index("(M,M)")]
        lam1, lam2 = h, 2 * D * h - n  # K01-2.18
        a = [1 / x for x in I]
        q0 = spheroconical_coordinates(gamma, a)
        roots = separation_roots(lam1, lam2, a, D)
        coeffs = _R_coefficients()(lam1, lam2, *a, D)
        lead = coeffs[0]
        # q1 oscillates in [a2, a1], q2 in [a3, a2] (K01-2.11); inside each, between the
        # consecutive roots of R where R > 0 (p^2 >= 0; the extra root q* splits one of
        # them). Chosen by the sign of R, so a state with q_i on a root (gamma_2 = 0 ...)
        # is handled too.
        tol = mpmath.mpf(10) ** (-digits // 2)

        R_at = separation_R(lam1, lam2, a, D)

        ranges = []
        for lo_a, hi_a in ((a[1], a[0]), (a[2], a[1])):
            inside = [r for r in roots if lo_a - tol * (1 + abs(lo_a)) <= r]
            inside = [r for r in inside if r <= hi_a + tol * (1 + abs(hi_a))]
            good = [
                (lo, hi)
                for lo, hi in zip(inside[:-1], inside[1:], strict=True)
                if hi - lo > tol and R_at((lo + hi) / 2) > 0
            ]
            if len(good) != 1:
                raise UserInputError("critical torus: no single oscillation range of R")
            ranges.append(good[0])
        for lo, hi in ranges:
            if hi - lo <= mpmath.mpf(10) ** (-digits // 3) * (1 + abs(hi)):
                raise UserInputError("critical torus: a range of R has collapsed")

        def integral(k, rng, weight=None):
            lo, hi = rng
            m, r = (lo + hi) / 2, (hi - lo) / 2
            others = [x for x in roots if x not in (lo, hi)]
            # R = lead (q - lo)(q - hi) prod (q - other) = -lead r^2 cos^2 th prod(...)
            # on the range; dq/sqrt(R) = d th / sqrt(-lead prod (q - other)).

            def f(th):
                q = m + r * mpmath.sin(th)
                rest = -lead
                for x in others:
                    rest *= q - x
                w = q**k if weight is None else weight(q)
                return w / mpmath.sqrt(rest)

            return mpmath.quad(f, [-mpmath.pi / 2, 0, mpmath.pi / 2], method="gauss-legendre")

        A = tuple(integral(0, rng) for rng in ranges)
        B = tuple(integral(1, rng) for rng in ranges)
        K = (1 + D * a[0]) * (1 + D * a[1]) * (1 + D * a[2])
        c0 = 2 / mpmath.sqrt(K)
        den = 2 * (A[1] * B[0] - A[0] * B[1])
        nu = (c0 * B[1] / den, c0 * B[0] / den)
        # actions: oint p dq = 2 int sqrt(K)/2 |2 lam1 + q lam2|/sqrt(R) dq
        actions = tuple(
            mpmath.sqrt(K) * integral(0, rng, weight=lambda q: abs(2 * lam1 + q * lam2))
            for rng in ranges
        )
        out = TorusQuadratures(
            h=+h,
            n=+n,
            lam1=+lam1,
            lam2=+lam2,
            roots=roots,
            ranges=tuple(ranges),
            q0=q0,
            A=A,
            B=B,
            actions=actions,
            frequencies=nu,
            rotation_number=B[1] / B[0],
            digits=digits,
            details={"q_star": -2 * lam1 / lam2, "a": a, "K": K, "c0": c0},
        )
    return out


def rotation_number(
    I: Sequence[float | mpmath.mpf],
    D: float | mpmath.mpf,
    M: Sequence[float | mpmath.mpf],
    gamma: Sequence[float | mpmath.mpf],
    digits: int = 30,
) -> mpmath.mpf:
    """Rotation number ``nu1/nu2`` (oscillations of ``q1`` per oscillation of ``q2``).

    Parameters
    ----------
    I, D, M, gamma, digits
        As for :func:`torus_quadratures`.

    Returns
    -------
    mpmath.mpf
        ``B2/B1`` of :func:`torus_quadratures`.

    Raises
    ------
    UserInputError
        As :func:`torus_quadratures`.

    References
    ----------
    K01-2.27 (with the true turning points, FORMULAS.md)

    Examples
    --------
    >>> import mpmath
    >>> g = (mpmath.mpf("0.6"), mpmath.mpf("0.0"), mpmath.mpf("0.8"))
    >>> nu = rotation_number((1, 1.5, 3), 1, (0.8, 0.5, -0.6), g, digits=20)
    >>> 0 < nu < 2
    True
    """
    return torus_quadratures(I, D, M, gamma, digits).rotation_number


@dataclass
class MeasuredRotation:
    """Rotation number measured from an integrated trajectory.

    Attributes
    ----------
    value : float
        Weighted Birkhoff average of the phase increments of q1 over those of q2.
    counted : float
        Oscillation counts (phase / 2 pi) of q1 over q2 without weights (cruder).
    oscillations : (float, float)
        Number of oscillations of q1 and q2 in the time span.
    frequencies_t : (float, float)
        Oscillations of q1, q2 per unit of the time t (weighted Birkhoff averages).
    mean_rho : float
        Weighted Birkhoff average of K01's ``rho`` along the trajectory: ``tau/t`` in the
        long run (K01-2.7), so ``frequencies_t / mean_rho`` are the frequencies in tau.
    q_ranges : ((float, float), (float, float))
        Smallest and largest sampled ``q1`` and ``q2``: the observed oscillation ranges.
    q_sampling : (float, float)
        ``max |q''| dt^2 / 8`` (from second differences): how far the sample nearest to a
        turning point can miss it.
    drift : dict
        Drift of the first integrals of the integration.
    t_end : float
    samples : int
    """

    value: float
    counted: float
    oscillations: tuple
    frequencies_t: tuple
    mean_rho: float
    drift: dict
    t_end: float
    samples: int
    q_ranges: tuple = ()
    q_sampling: tuple = ()


def _bump(s):
    out = np.zeros_like(s)
    inside = (s > 0) & (s < 1)
    x = s[inside]
    out[inside] = detmath.exp(-1.0 / (x * (1.0 - x)))
    return out


def measured_rotation_number(
    I: Sequence[float],
    D: float,
    M: Sequence[float],
    gamma: Sequence[float],
    t_end: float,
    samples_per_unit: float = 40.0,
    rtol: float = 1e-12,
) -> MeasuredRotation:
    """Measure ``nu1/nu2`` from a trajectory integrated in double precision (DOP853).

    The phase of ``q_i`` is the angle of ``(q_i - c_i, s_i q_i')`` (``c_i`` the middle of
    the observed range, ``s_i`` a scale), unwrapped; the ratio of the weighted Birkhoff
    sums ``sum w_k (theta_i(t_{k+1}) - theta_i(t_k))`` with the bump weight
    ``w = exp(-1/(s (1 - s)))``, ``s = t/t_end``, converges faster than any power of the
    number of oscillations on a non-resonant torus (Das, Sander, Yorke et al.).

    Parameters
    ----------
    I, D, M, gamma : sequence of 3 floats, float, sequence of 3 floats each
        Parameters and a state with ``(M, gamma) = 0``.
    t_end : float
        Length of the trajectory (time t).
    samples_per_unit : float
        Output samples per unit of time (must resolve every oscillation).
    rtol : float
        Relative tolerance of DOP853 (``atol = rtol``).

    Returns
    -------
    MeasuredRotation
        The weighted and the counted ratio, oscillation counts, frequencies in ``t``, the
        mean of ``rho`` and the sampling evidence.

    Raises
    ------
    RuntimeError
        If the integration fails.

    References
    ----------
    K01-2.7, K01-2.11, K01-2.27 (FORMULAS.md).
    """
    from ..integrate import integrate

    check_inertia_vector(I, D, double=True)
    check_vector(M, "M", double=True)
    check_vector(gamma, "gamma", double=True)
    check_real(t_end, "t_end", positive=True, double=True)
    check_real(samples_per_unit, "samples_per_unit", positive=True, double=True)
    check_real(rtol, "rtol", positive=True, double=True)
    if t_end * samples_per_unit > MAX_SAMPLES:
        raise UserInputError(
            f"t_end * samples_per_unit = {t_end * samples_per_unit:g} samples is more than "
            f"{MAX_SAMPLES}; shorten t_end or lower samples_per_unit"
        )
    n = int(t_end * samples_per_unit) + 1
    t_eval = np.linspace(0.0, t_end, n)
    res = integrate(
        "chaplygin_ball",
        {"M": tuple(M), "gamma": tuple(gamma)},
        (0.0, t_end),
        {"I": tuple(I), "D": D},
        rtol=rtol,
        atol=rtol,
        t_eval=t_eval,
    )
    if not res.success:
        raise ComputationError(res.message)
    y = np.asarray(res.y, dtype=float)
    Mv, g = y[:3], y[3:6]
    Iv = np.asarray(I, dtype=float)
    A = 1.0 / (Iv + D)
    Z = np.sum(A[:, None] * Mv * g, axis=0) / (1.0 / D - np.sum(A[:, None] * g * g, axis=0))
    w = A[:, None] * (Mv + Z * g)  # BKM12-3
    gd = np.cross(g.T, w.T).T  # gamma' = gamma x omega
    a = 1.0 / Iv
    q1, q2 = spheroconical_coordinates(g, a)
    thetas = []
    q_ranges = tuple((float(q.min()), float(q.max())) for q in (q1, q2))
    q_sampling = tuple(float(np.max(np.abs(np.diff(q, 2)))) / 8 for q in (q1, q2))
    for q in (q1, q2):
        # dq/dt from P(q, gamma) = sum gamma_i^2 prod_{j!=i}(a_j - q) = 0
        dP_dq = np.zeros_like(q)
        dP_dt = np.zeros_like(q)
        for i in range(3):
            j, k = [m for m in range(3) if m != i]
            dP_dq += g[i] ** 2 * (-(a[k] - q) - (a[j] - q))
            dP_dt += 2 * g[i] * gd[i] * (a[j] - q) * (a[k] - q)
        qd = -dP_dt / dP_dq
        c = (q.max() + q.min()) / 2
        s = (q.max() - q.min()) / 2 / max(np.abs(qd).max(), 1e-300)
        th = np.unwrap(detmath.atan2(s * qd, q - c))
        thetas.append(th)
    wts = _bump(t_eval / t_end)[:-1]
    inc = [np.diff(th) for th in thetas]
    value = float(np.sum(wts * inc[0]) / np.sum(wts * inc[1]))
    osc = tuple(float(abs(th[-1] - th[0]) / (2 * np.pi)) for th in thetas)
    dt = t_eval[1] - t_eval[0]
    freq_t = tuple(float(abs(np.sum(wts * d)) / (2 * np.pi * dt * np.sum(wts))) for d in inc)
    rho = 1.0 / np.sqrt(1.0 - D * np.sum(A[:, None] * g * g, axis=0))  # K01-2.2
    mean_rho = float(np.sum(wts * rho[:-1]) / np.sum(wts))
    return MeasuredRotation(
        value=abs(value),
        counted=osc[0] / osc[1],
        oscillations=osc,
        frequencies_t=freq_t,
        mean_rho=mean_rho,
        drift=res.drift,
        t_end=t_end,
        samples=n,
        q_ranges=q_ranges,
        q_sampling=q_sampling,
    )
