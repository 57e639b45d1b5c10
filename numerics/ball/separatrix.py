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

from ...derive.errors import UserInputError
from ..arguments import check_choice, check_count, check_inertia_vector, check_real

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
