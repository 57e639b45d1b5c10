"""The displacement Delta of the contact point along the separatrix, three ways (K01 §3.3).

On ``M = C gamma`` at ``h = h2 = C^2/(2 I2)`` the ball tumbles once along a separatrix and
its contact point moves by ``Delta`` (K01 (3.4)-(3.7); derived in
:mod:`chaplygin.derive.separatrix`). With ``mu = xi = kap/lam = 1/(J2 sqrt(a21 a32))``:

(a) :func:`delta_ode`: the full equations of ``chaplygin_ball__contact_point`` (explicit
    ``alpha, beta`` states: the frame of BKM12-7 is singular at ``M || gamma``) integrated
    at high precision from the exact separatrix point at ``t = 0`` forward to ``lam t = L``
    and backward to ``-L``; the tails ``|t| > L/lam`` are summed from the asymptotic series
    of ``x' = nu cos(kap t)/ch(lam t)`` (``1/ch = 2 sum (-1)^n exp(-(2n+1) lam t)``) with
    the bound of the first omitted term;
(b) :func:`delta_quadrature`: ``|nu| int cos(kap t)/ch(lam t) dt = b int cos(mu s)/ch(s) ds``
    by Gauss-Legendre between the zeros of ``cos(mu s)`` plus the tail series (or
    ``mpmath.quadosc``, a cross-check);
(c) :func:`delta_closed_form`: ``pi b/ch(pi mu/2)``, derived by residues.

``Delta`` here is the length of the displacement, ``|x(+oo) - x(-oo)|``; with the frame of
the corrected K01-3.4 the contact point moves along ``-alpha`` (``nu = -b lam``).

References
----------
K01-3.4, K01-3.5, K01-3.6, K01-3.7, K01-Fig4 (FORMULAS.md).
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import mpmath
import numpy as np

from ...derive.errors import ComputationError, UserInputError
from ..inputs import check_choice, check_count, check_inertia_vector, check_real

#: Digits the separatrix functions accept (``digits``, ``dps``).
MAX_DIGITS = 10000

__all__ = [
    "mu_of",
    "separatrix_quantities",
    "separatrix_state",
    "delta_closed_form",
    "delta_quadrature",
    "delta_ode",
    "tail_integral",
    "DeltaResult",
    "delta_three_ways",
    "agreeing_digits",
    "check_inertia",
    "flow",
    "ENGINES",
    "near_separatrix_state",
    "separatrix_trace",
    "frame_turn",
    "critical_energy",
    "spiral_centre",
    "delta_from_traces",
]


def check_inertia(I: Sequence[float | mpmath.mpf], D: float | mpmath.mpf) -> None:
    """Raise :class:`UserInputError` unless ``I1 < I2 < I3`` or ``I1 > I2 > I3``, all > 0.

    The separatrix of K01 §3.3 belongs to the middle axis ``I2``.

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia ``I1, I2, I3``.
    D : number
        ``D = m b^2``.

    Raises
    ------
    UserInputError
        If ``I`` does not hold three values, a value is not finite and positive, or ``I2``
        is not strictly between ``I1`` and ``I3``.

    References
    ----------
    K01-3.4 (FORMULAS.md).
    """
    I, D = check_inertia_vector(I, D)
    if not (I[0] < I[1] < I[2] or I[0] > I[1] > I[2]):
        raise UserInputError(
            "I2 must be the middle moment, strictly between I1 and I3 "
            f"(got I = {', '.join(mpmath.nstr(v, 8) for v in I)}): the separatrix of "
            "K01 §3.3 needs three different moments"
        )


def mu_of(I: Sequence[float | mpmath.mpf], D: float | mpmath.mpf) -> mpmath.mpf:
    """``mu = xi = kap/lam = 1/(J2 sqrt(a21 a32))``, ``J_i = I_i + D`` (K01-3.7).

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia ``I1, I2, I3`` (``I2`` the middle one).
    D : number
        ``D = m b^2``.

    Returns
    -------
    mpmath.mpf
        ``mu`` at the current mpmath precision.

    Raises
    ------
    UserInputError
        ``I``, ``D`` refused by :func:`check_inertia` (``I2`` must be the middle moment).

    References
    ----------
    K01-3.7 (FORMULAS.md).
    """
    check_inertia(I, D)
    J1, J2, J3 = (mpmath.mpf(v) + D for v in I)
    return 1 / (J2 * mpmath.sqrt((1 / J1 - 1 / J2) * (1 / J2 - 1 / J3)))


def separatrix_quantities(
    I: Sequence[float | mpmath.mpf], D: float | mpmath.mpf, C: float | mpmath.mpf = 1
) -> dict[str, mpmath.mpf]:
    """``lam, kap, s32, s21, l`` for ``I1 < I2 < I3`` (mpmath at the current precision).

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia ``I1 < I2 < I3``.
    D : number
        ``D = m b^2``.
    C : number
        ``C = (M, gamma)`` on the segment ``M = C gamma``.

    Returns
    -------
    dict of str to mpmath.mpf
        ``lam = |C| J2/I2 sqrt(a21 a32)`` (the rate of ``ch(lam t)``), ``kap = C/I2``,
        ``s32 = sqrt(a32/(a21 + a32))``, ``s21 = sqrt(a21/(a21 + a32))`` and
        ``l = C J2/I2``, with ``a21 = 1/J1 - 1/J2``, ``a32 = 1/J2 - 1/J3``.

    References
    ----------
    K01-3.4, K01-3.6 (FORMULAS.md).
    """
    I1, I2, I3 = (mpmath.mpf(v) for v in I)
    D, C = mpmath.mpf(D), mpmath.mpf(C)
    J1, J2, J3 = I1 + D, I2 + D, I3 + D
    d21, d32 = 1 / J1 - 1 / J2, 1 / J2 - 1 / J3
    lam = abs(C) * J2 / I2 * mpmath.sqrt(d21 * d32)
    return {
        "lam": lam,
        "kap": C / I2,
        "s32": mpmath.sqrt(d32 / (d21 + d32)),
        "s21": mpmath.sqrt(d21 / (d21 + d32)),
        "l": C * J2 / I2,
    }


def separatrix_state(
    I: Sequence[float | mpmath.mpf], D: float | mpmath.mpf, C: float | mpmath.mpf = 1
) -> list[mpmath.mpf]:
    """The corrected K01-3.4 solution at ``t = 0`` (``th = 0``, ``sech = 1``, ``c = 1``).

    State order of ``chaplygin_ball__contact_point``: ``M, gamma, alpha, beta, x, y``.

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia ``I1 < I2 < I3``.
    D : number
        ``D = m b^2``.
    C : number
        ``C = (M, gamma)``; ``M = C gamma``.

    Returns
    -------
    list of mpmath.mpf, length 14
        ``M = C gamma``, ``gamma = (-s32, 0, -s21)``, ``alpha = e2``,
        ``beta = (s21, 0, -s32)``, ``x = y = 0``.

    References
    ----------
    K01-3.4 (FORMULAS.md; the corrected form for ``C > 0``).
    """
    check_inertia(I, D)
    check_real(C, "C", nonzero=True)
    Q = separatrix_quantities(I, D, C)
    s32, s21 = Q["s32"], Q["s21"]
    gamma = [-s32, mpmath.mpf(0), -s21]
    alpha = [mpmath.mpf(0), mpmath.mpf(1), mpmath.mpf(0)]
    beta = [s21, mpmath.mpf(0), -s32]
    C = mpmath.mpf(C)
    return [C * g for g in gamma] + gamma + alpha + beta + [mpmath.mpf(0), mpmath.mpf(0)]


def delta_closed_form(
    mu: float | mpmath.mpf, b: float | mpmath.mpf = 1, dps: int = 30
) -> mpmath.mpf:
    """(c) ``Delta = pi b / ch(pi mu/2)`` (K01-3.7, derived by residues).

    Parameters
    ----------
    mu : number
        ``mu = kap/lam`` (:func:`mu_of`).
    b : number
        Radius of the ball.
    dps : int
        Decimal digits of the evaluation.

    Returns
    -------
    mpmath.mpf
        ``Delta``, rounded to ``dps`` digits.

    References
    ----------
    K01-3.7 (FORMULAS.md).
    """
    _check_delta_args(mu, b, dps, "dps")
    with mpmath.workdps(dps):
        return +(mpmath.pi * b / mpmath.cosh(mpmath.pi * mpmath.mpf(mu) / 2))


def tail_integral(
    mu: float | mpmath.mpf, L: float | mpmath.mpf, terms: int
) -> tuple[mpmath.mpf, mpmath.mpf]:
    """``int_L^oo cos(mu s)/ch(s) ds`` from ``1/ch s = 2 sum (-1)^n exp(-(2n+1) s)``.

    Returns ``(value, bound)``: the bound of the omitted terms is
    ``2 exp(-(2N+1) L)/((2N+1)(1 - exp(-2L)))``.

    Parameters
    ----------
    mu : number
        Frequency ``mu = kap/lam`` of the integrand.
    L : number
        Lower limit (``L > 0``).
    terms : int
        Number ``N`` of terms of the series summed.

    Returns
    -------
    value, bound : mpmath.mpf
        The sum of the first ``N`` terms and the bound of the omitted ones (current
        mpmath precision).

    References
    ----------
    K01-3.7 (FORMULAS.md).
    """
    mu, L = mpmath.mpf(mu), mpmath.mpf(L)
    total = mpmath.mpf(0)
    c, s = mpmath.cos(mu * L), mpmath.sin(mu * L)
    for n in range(terms):
        a = 2 * n + 1
        total += 2 * (-1) ** n * mpmath.exp(-a * L) * (a * c - mu * s) / (a**2 + mu**2)
    a = 2 * terms + 1
    bound = 2 * mpmath.exp(-a * L) / (a * (1 - mpmath.exp(-2 * L)))
    return total, bound


def _zero_points(mu, L) -> list:
    """``0``, the zeros ``(k + 1/2) pi/mu`` of ``cos(mu s)`` below ``L``, and ``L``.

    Pieces longer than 2 are split (the scale of ``1/ch``).
    """
    z = [mpmath.mpf(0)]
    k = 0
    while True:
        s = (k + mpmath.mpf(1) / 2) * mpmath.pi / mu
        if s >= L:
            break
        while s - z[-1] > 2:
            z.append(z[-1] + 2)
        z.append(s)
        k += 1
    while L - z[-1] > 2:
        z.append(z[-1] + 2)
    z.append(mpmath.mpf(L))
    return z


def delta_quadrature(
    mu: float | mpmath.mpf, b: float | mpmath.mpf = 1, dps: int = 30, method: str = "zeros"
) -> mpmath.mpf:
    """(b) ``b int_{-oo}^{oo} cos(mu s)/ch(s) ds`` (K01 (3.7) with ``s = lam t``).

    Parameters
    ----------
    mu : number
        ``mu = kap/lam`` (:func:`mu_of`).
    b : number
        Radius of the ball.
    dps : int
        Digits wanted; the quadrature runs at ``dps + 10``.
    method : {"zeros", "quadosc"}
        ``zeros``: Gauss-Legendre between consecutive zeros of ``cos(mu s)`` (the
        classical method for oscillatory integrands; the exponential decay makes a
        series acceleration unnecessary) up to ``L = (dps + 12) ln 10/3``, plus the tail
        series (:func:`tail_integral`, three terms, bound ``< 10^-(dps+10)``).
        ``quadosc``: ``mpmath.quadosc`` (slower, a cross-check).

    Returns
    -------
    mpmath.mpf
        ``Delta`` (at ``dps + 10`` digits).

    Raises
    ------
    ValueError
        An unknown ``method``.

    References
    ----------
    K01-3.7 (FORMULAS.md).
    """
    _check_delta_args(mu, b, dps, "dps", mu_positive=True)
    check_choice(method, ("zeros", "quadosc"), "method")
    with mpmath.workdps(dps + 10):
        mu = mpmath.mpf(mu)

        def f(s):
            return mpmath.cos(mu * s) / mpmath.cosh(s)

        if method == "quadosc":
            half = mpmath.quadosc(f, [0, mpmath.inf], omega=mu)
        elif method == "zeros":
            L = (dps + 12) * mpmath.log(10) / 3
            half = mpmath.quad(f, _zero_points(mu, L), method="gauss-legendre")
            tail, _ = tail_integral(mu, L, 3)
            half += tail
        return +(2 * b * half)


def _check_delta_args(mu, b, digits, digits_name: str, mu_positive: bool = False) -> None:
    """A finite ``mu`` (``> 0`` if asked), the radius ``b > 0`` (Delta is a length) and a
    count of digits."""
    check_real(mu, "mu", positive=mu_positive)
    check_real(b, "b", positive=True)
    check_count(digits, digits_name, 1, MAX_DIGITS)


#: Integrators of the full equations for :func:`flow`; ``jet`` (the tape integrator of
#: ``numerics/jet.py``, now removed) is kept as an alias of ``taylor``.
ENGINES = ("taylor", "odefun")
_ENGINE_ALIASES = {"jet": "taylor"}


def flow(
    y0: Sequence[float | mpmath.mpf],
    params: Sequence[float | mpmath.mpf],
    t_end: float | mpmath.mpf,
    digits: int,
    engine: str = "taylor",
) -> tuple[list[mpmath.mpf], int]:
    """Integrate the full ``chaplygin_ball__contact_point`` equations from ``y0`` at t = 0.

    One integration through the integrators' door at ``digits``: ``taylor`` (the generated
    Taylor integrator: compiled double-double or quad-double up to 60 digits, MPFR beyond;
    local tolerance ``10^-digits``; ``jet`` is an alias) or ``odefun`` (``mpmath.odefun``, a
    cross-check; a backward span is the forward span of the reversed flow).

    Parameters
    ----------
    y0, params : sequence of numbers
        State in the model's order and ``I1, I2, I3, D, b``.
    t_end : number
        Negative for a backward integration.
    digits : int
        Working precision (decimal digits).
    engine : {"taylor", "odefun", "jet"}
        The integrator (``jet`` is an alias of ``taylor``).

    Returns
    -------
    (list of mpmath.mpf, int)
        The state at ``t_end`` and the number of steps (``odefun``: right-hand side calls).

    Raises
    ------
    ValueError
        An unknown engine, or a failed integration.
    """
    from ..code import load_model_code
    from ..integrators import INTEGRATORS, Problem
    from ..precision import Precision

    engine = _ENGINE_ALIASES.get(engine, engine)
    if engine not in ENGINES:
        raise ValueError(
            f"unknown engine {engine!r}: {' or '.join(ENGINES)} (jet is an alias of taylor)"
        )
    code = load_model_code("chaplygin_ball", ("contact_point",))
    precision = Precision.working(digits)
    with precision.context():
        eps = 10.0**-digits  # the Taylor method's local tolerance (odefun works to the full
        # precision); odefun runs a backward span on the reversed flow
        t1 = mpmath.mpf(t_end)
        problem = Problem(
            code, [mpmath.mpf(v) for v in y0], (mpmath.mpf(0), t1),
            [mpmath.mpf(v) for v in params], precision, eps, eps, t_eval=[t1],
        )  # fmt: skip
    sol = INTEGRATORS[engine]().solve(problem)
    if sol.status != 0:
        raise ValueError(f"the separatrix flow failed: {sol.message}")
    return list(sol.y[:, -1]), sol.nsteps if engine == "taylor" else sol.nfev


def delta_ode(
    I: Sequence[float | mpmath.mpf],
    D: float | mpmath.mpf,
    b: float | mpmath.mpf,
    digits: int,
    C: float | mpmath.mpf = 1,
    L: float | None = None,
    engine: str = "taylor",
) -> dict[str, object]:
    """(a) Delta from the full equations, forward and backward from the separatrix point.

    Parameters
    ----------
    I, D, b : numbers
        Inertia (``I2`` the middle moment), ``D = m b^2``, radius.
    digits : int
        Digits wanted; the working precision adds ``L/ln 10`` (a perturbation off the
        stable manifold grows like ``exp(lam t)``) and 8 guard digits.
    C : number
        ``(M, gamma)`` (the time scale; Delta does not depend on it).
    L : number, optional
        ``lam t`` at the ends (default ``max(8, (digits + 5) ln 10/7)``): the tail series
        then needs 3 terms.
    engine : {"taylor", "odefun", "jet"}
        Integrator of :func:`flow` (``jet`` is an alias of ``taylor``).

    Returns
    -------
    dict
        ``delta`` (``|x(oo) - x(-oo)|``), ``signed`` (``x(oo) - x(-oo)``), ``y_shift``,
        ``tail``, ``tail_bound``, ``steps``, ``work_digits``, ``L``, ``seconds``.

    Raises
    ------
    ValueError
        From :func:`flow`: an unknown engine or a failed integration.

    References
    ----------
    K01-3.4, K01-3.5, K01-3.6, K01-3.7 (FORMULAS.md).
    """
    start = time.perf_counter()
    I = list(I)
    if I[0] > I[2]:  # the same body with axes 1 and 3 renamed (mu is symmetric)
        I = I[::-1]
    if L is None:
        L = max(8.0, (digits + 5) * math.log(10) / 7)
    work = digits + int(math.ceil(L / math.log(10))) + 8
    terms = int(math.ceil((digits + 8) * math.log(10) / (2 * L) + 0.5))
    with mpmath.workdps(work):
        Q = separatrix_quantities(I, D, C)
        lam, kap = Q["lam"], Q["kap"]
        y0 = separatrix_state(I, D, C)
        params = [mpmath.mpf(v) for v in I] + [mpmath.mpf(D), mpmath.mpf(b)]
        T = mpmath.mpf(L) / lam
        fwd, n1 = flow(y0, params, T, work, engine)
        bwd, n2 = flow(y0, params, -T, work, engine)
        mu = kap / lam
        tail, bound = tail_integral(mu, L, terms)
        nu = -mpmath.mpf(b) * lam
        # x(oo) - x(T) = x(-T) - x(-oo) = (nu/lam) int_L^oo cos(mu s)/ch(s) ds
        tail_x = nu / lam * tail
        signed = fwd[12] - bwd[12] + 2 * tail_x
        return {
            "delta": abs(signed),
            "signed": signed,
            "y_shift": fwd[13] - bwd[13],
            "tail": 2 * tail_x,
            "tail_bound": 2 * abs(nu / lam) * bound,
            "steps": n1 + n2,
            "work_digits": work,
            "L": L,
            "seconds": time.perf_counter() - start,
        }


def agreeing_digits(values: Sequence[float | mpmath.mpf], reference: float | mpmath.mpf) -> float:
    """``-log10(max |v/reference - 1|)`` (capped at the working precision).

    Parameters
    ----------
    values : sequence of numbers
        Values compared with ``reference`` (at least one).
    reference : number
        The reference value (nonzero).

    Returns
    -------
    float
        Number of agreeing decimal digits of the worst value; ``mpmath.mp.dps`` when
        all values equal ``reference``.
    """
    worst = max(abs(mpmath.mpf(v) / reference - 1) for v in values)
    if worst == 0:
        return float(mpmath.mp.dps)
    return float(-mpmath.log10(worst))


@dataclass
class DeltaResult:
    """The three values of Delta and their agreement.

    Attributes
    ----------
    mu : mpmath.mpf
    ode, quadrature, closed : mpmath.mpf
    digits_agree : float
        ``-log10`` of the largest relative difference of the three.
    seconds : dict of str to float
    ode_info : dict
    """

    mu: object
    ode: object
    quadrature: object
    closed: object
    digits: int
    digits_agree: float
    seconds: dict = field(default_factory=dict)
    ode_info: dict = field(default_factory=dict)


def delta_three_ways(
    I: Sequence[float | mpmath.mpf],
    D: float | mpmath.mpf,
    b: float | mpmath.mpf,
    digits: int,
    C: float | mpmath.mpf = 1,
    engine: str = "taylor",
    methods: Sequence[str] = ("ode", "quadrature", "closed"),
) -> DeltaResult:
    """Delta by the full equations, the quadrature (3.7) and the closed form, at ``digits``.

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia (``I2`` the middle one).
    D, b : number
        ``D = m b^2`` and the radius.
    digits : int
        Digits wanted (the closed form is evaluated at ``digits + 10``).
    C : number
        ``C = (M, gamma)`` (the time scale of :func:`delta_ode`).
    engine : {"taylor", "odefun", "jet"}
        Integrator of :func:`delta_ode`.
    methods : sequence of str
        Which of ``"ode"`` and ``"quadrature"`` to run; the closed form always runs.

    Returns
    -------
    DeltaResult
        The values (``None`` for a method not run), their agreement with the closed
        form (``digits`` when no other method ran), the times and :func:`delta_ode`'s
        details.

    Raises
    ------
    UserInputError
        ``I``, ``D`` refused by :func:`check_inertia`, ``b <= 0`` (a radius), ``C = 0``,
        ``digits`` not a count, an unknown ``engine`` or method.

    References
    ----------
    K01-3.7 (FORMULAS.md).
    """
    check_inertia(I, D)
    check_real(b, "b", positive=True)
    check_real(C, "C", nonzero=True)
    check_count(digits, "digits", 1, MAX_DIGITS)
    check_choice(engine, (*ENGINES, *_ENGINE_ALIASES), "engine")
    if (
        isinstance(methods, str | bytes)
        or not isinstance(methods, Iterable)
        or not all(isinstance(m, str) and m in ("ode", "quadrature", "closed") for m in methods)
    ):
        raise UserInputError(
            f"methods = {methods!r}: give a sequence of 'ode', 'quadrature', 'closed'"
        )
    seconds: dict = {}
    with mpmath.workdps(digits + 10):
        mu = mu_of(I, D)
        t = time.perf_counter()
        closed = delta_closed_form(mu, b, digits + 10)
        seconds["closed"] = time.perf_counter() - t
        quad = ode = None
        info: dict = {}
        if "quadrature" in methods:
            t = time.perf_counter()
            quad = delta_quadrature(mu, b, digits + 5)
            seconds["quadrature"] = time.perf_counter() - t
        if "ode" in methods:
            t = time.perf_counter()
            info = delta_ode(I, D, b, digits, C=C, engine=engine)
            ode = info["delta"]
            seconds["ode"] = time.perf_counter() - t
        others = [v for v in (ode, quad) if v is not None]
        agree = agreeing_digits(others, closed) if others else float(digits)
        return DeltaResult(mu, ode, quad, closed, digits, agree, seconds, info)


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
    section = EventSection(
        code, p, gamma2, direction=direction, rtol=rtol, atol=rtol, chunk=50.0
    )
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
