"""The dynamical regime of a stroboscopic map's attractor: periodic (with its period),
quasi-periodic or chaotic, told apart by the period and then the largest Lyapunov exponent.

From a start the map ``P: y(t0) -> y(t0 + 2 pi/Omega)`` is iterated ``transient`` times;
the next ``recorded`` iterates are searched for the smallest period ``p <= max_period`` that
closes within ``tol`` (max norm in ``(M/|M|, gamma)``, so ``tol`` is relative). Without a
period, the largest Lyapunov exponent on the integrals' level set (Benettin, one tangent
vector, :func:`~chaplygin.numerics.dynamics.lyapunov.lyapunov_spectrum` with ``count=1``) is
measured over ``intervals`` further iterations (from rest, ``M = 0``, on the sphere of
``gamma`` alone), per map iteration, with its standard error
``s`` (batch means over 10 windows). With ``N = intervals`` and ``r = ln(N)/N`` (what a
tangent vector growing linearly, as on a torus or a periodic orbit, shows after ``N``
iterations):

* ``lambda - 3 s > r``: **chaotic**;
* ``lambda + 3 s < -r``: **contracting**: a periodic attractor that was not resolved (a period
  above ``max_period``, or an approach slower than the transient);
* ``|lambda| <= r + 2 s``: **quasi-periodic** (``lambda`` is zero within two errors);
* otherwise (``|lambda|`` between ``r + 2 s`` and ``r + 3 s``): **undecided** (an intermittent,
  sticky orbit, whose exponent over ``N`` iterations has a large error; BM20 Fig. 6's window
  has such points with ``lambda = 0.08-0.10 +- 0.03``).
  (:func:`classify_exponent`.)

An orbit spiralling onto a ``q``-cycle whose multipliers turn by about ``2 pi k/p`` per cycle
closes at period ``p`` (a multiple of ``q``) within ``tol`` before it settles (BM20 Fig. 2A
from rest: period 3 after 3000 iterations, period 1, the true fixed point, after 10000; Fig. 6
at Omega = 1.0668, d = 4.384: 28 for the 7-cycle): the period found is reduced to the divisor
whose closure still shrinks over the recorded iterates (:func:`settled_period`). The transient
must still be long against the slowest contraction.

The attractor's symmetric copy is named (:mod:`chaplygin.numerics.ball.symmetry`) from the
recorded points. The state after the last iteration is returned, so that a chart can carry
it to the next parameter value (:func:`chaplygin.verify.sweep`'s ``carry``), following one
attractor along a grid line and so revealing coexisting attractors.

References
----------
G. Benettin et al., Meccanica 15 (1980); BM20 §3.2, Fig. 6 (chart of dynamical regimes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...arith import detlinalg, detmath
from ...derive.errors import ComputationError, UserInputError
from ..arguments import check_rows
from ..code import ModelCode
from .symmetry import CopyName, map_points_scaled, name_copy, symmetries_of

__all__ = [
    "REGIMES",
    "AttractorRegime",
    "attractor_regime",
    "attractor_regimes",
    "classify_exponent",
    "closing_period",
    "settled_period",
    "linear_growth_rate",
    "map_points_scaled",
]

#: Regime names and their codes in stores (0: not classified).
REGIMES = {"periodic": 1, "quasi-periodic": 2, "chaotic": 3, "contracting": 4, "undecided": 5}

#: Standard errors a decision for chaos (or contraction) needs, and within which the exponent
#: counts as zero.
SIGMAS, ZERO_SIGMAS = 3.0, 2.0


def linear_growth_rate(iterations: int) -> float:
    """The exponent per iteration that a tangent vector growing linearly (``|v_N| = N |v_0|``,
    as on an invariant torus or a periodic orbit) shows after ``N`` iterations: ``ln(N)/N``.

    Parameters
    ----------
    iterations : int

    Returns
    -------
    float
        Per map iteration.
    """
    return detmath.log(float(iterations)) / iterations


@dataclass
class AttractorRegime:
    """The regime of the attractor reached from one start.

    Attributes
    ----------
    regime : str
        A key of :data:`REGIMES`.
    period : int
        The period (0 when none up to ``max_period`` closes).
    lyapunov, lyapunov_error : float
        Largest exponent and its standard error, per map iteration (NaN for a periodic
        attractor: not measured).
    threshold : float
        ``ln(N)/N`` of the decision.
    copy : CopyName or None
        The symmetric copy reached (None when the model has no such symmetry).
    points : ndarray, shape (recorded, n)
        The recorded iterates (states).
    end : ndarray, shape (n,)
        The state after the last iteration (on the attractor).
    work : dict
        ``map_periods`` and ``lyapunov_periods`` integrated.
    """

    regime: str
    period: int
    lyapunov: float
    lyapunov_error: float
    threshold: float
    copy: CopyName | None
    points: NDArray
    end: NDArray
    work: dict = field(default_factory=dict)

    @property
    def code(self) -> int:
        """The regime's code in :data:`REGIMES`.

        Returns
        -------
        int
        """
        return REGIMES[self.regime]


def classify_exponent(lam: float, err: float, intervals: int) -> str:
    """The regime of an attractor without a period from its largest Lyapunov exponent.

    Parameters
    ----------
    lam, err : float
        The exponent per map iteration and its standard error.
    intervals : int
        ``N``, the iterations it was measured over (``r = ln(N)/N``).

    Returns
    -------
    str
        ``"chaotic"`` (``lam - 3 err > r``), ``"contracting"`` (``lam + 3 err < -r``),
        ``"quasi-periodic"`` (``|lam| <= r + 2 err``), else ``"undecided"``.
    """
    r = linear_growth_rate(intervals)
    if lam - SIGMAS * err > r:
        return "chaotic"
    if lam + SIGMAS * err < -r:
        return "contracting"
    if abs(lam) <= r + ZERO_SIGMAS * err:
        return "quasi-periodic"
    return "undecided"


def _newton_period(
    code: ModelCode,
    params: list,
    points: NDArray,
    scaled: NDArray,
    period: int,
    tol: float,
    rtol: float,
) -> int:
    """For BM20's model on ``|M| = G > 0``: the smallest divisor ``q < period`` with a stable
    ``q``-cycle within ``sqrt(tol)`` of the orbit, refined by Newton on ``P^q``
    (:func:`~chaplygin.numerics.dynamics.periodic_orbits.refine_periodic_orbit` with the variational
    Jacobian); tried where the orbit's ``q``-closure is below ``sqrt(tol)`` (a slow spiral onto
    the ``q``-cycle closes at ``period`` first: BM20 Fig. 6 near the Neimark-Sacker point,
    multipliers 0.9987 per 7 iterations, closes at 28). Else ``period``."""
    from ..dynamics.periodic_orbits import refine_periodic_orbit
    from .bm20_map import BM20_EFFECTS, BM20_STATE, bm20_map_with_jacobian, bm20_point

    if tuple(code.state) != BM20_STATE or set(code.effects) != set(BM20_EFFECTS.split(",")):
        return period
    G = detlinalg.norm(points[-1][:3])
    if G == 0:
        return period
    last = scaled[len(scaled) - period - 1 :]
    smap = None
    for q in range(1, period):
        if period % q or float(np.max(np.abs(last[q:] - last[:-q]))) > math.sqrt(tol):
            continue
        smap = smap or bm20_map_with_jacobian(params, G, rtol=rtol)
        x = bm20_point(points[-1])
        try:
            orbit = refine_periodic_orbit(smap, x, q, params[code.params.index("Omega")])
        except (ComputationError, UserInputError):
            continue
        near = min(float(np.max(np.abs(smap.difference(np.asarray(c, float), x))))
                   for c in orbit.points)  # fmt: skip
        if orbit.converged and orbit.stable and near <= math.sqrt(tol):
            return q
    return period


def settled_period(x: ArrayLike, period: int, windows: int = 4) -> int:
    """The period of the attractor a recorded orbit that closes at ``period`` approaches: the
    smallest divisor ``q < period`` whose closure ``max |x[k + q] - x[k]|``, measured over
    ``period`` points at ``windows`` evenly spaced places of the record, decreases from each
    place to the next and by at least 10 % in all (the orbit spirals onto a ``q``-cycle whose
    multipliers turn by about ``2 pi j q/period`` per cycle, and closed at ``period`` before
    it settled: BM20 Fig. 6 at Omega = 1.0668, d = 4.384 closes at 28 within 1e-4 while it
    converges to the 7-cycle, multipliers 0.955 e^(+-1.58 i), and at Omega = 1.0672 with
    0.995 e^(+-1.64 i)); else ``period`` (a settled cycle's closures at its divisors stay as
    they are).

    Parameters
    ----------
    x : array_like, shape (n, dim)
        The recorded map points (``n >= (windows + 1) period``).
    period : int
        The closing period found (0: none).
    windows : int
        Places where the closures are compared.

    Returns
    -------
    int
    """
    x = np.asarray(x, dtype=float)
    if period < 2 or len(x) < (windows + 1) * period:
        return period
    starts = np.linspace(0, len(x) - 2 * period, windows).astype(int)
    for q in range(1, period):
        if period % q:
            continue
        closures = [float(np.max(np.abs(x[a + q : a + q + period] - x[a : a + period])))
                    for a in starts]  # fmt: skip
        shrinking = all(b < a for a, b in zip(closures, closures[1:], strict=False))
        if shrinking and closures[-1] <= 0.9 * closures[0]:
            return q
    return period


def closing_period(x: ArrayLike, max_period: int, tol: float) -> int:
    """The smallest ``p <= max_period`` with every ``|x[k + p] - x[k]| <= tol`` (max norm), or 0.

    Parameters
    ----------
    x : array_like, shape (n, dim)
        Consecutive map points (``n > max_period``).
    max_period : int
    tol : float

    Returns
    -------
    int
    """
    x = np.asarray(x, dtype=float)
    for p in range(1, min(max_period, len(x) - 1) + 1):
        if float(np.max(np.abs(x[p:] - x[:-p]))) <= tol:
            return p
    return 0


def _from_rest_subspace(y: NDArray, state: tuple[str, ...]) -> NDArray | None:
    """From rest (``M = 0`` exactly, kept by ``M' = M x omega``) the map acts on the sphere of
    ``gamma``: tangent vectors ``delta M = 0``, ``delta gamma`` normal to ``gamma`` (the
    variational flow keeps them there). The level set's tangent space would add the
    directions of ``delta M``, which only rotate (exponent 0) and would hide a contraction.
    None when ``M != 0``."""
    m = [state.index(f"M{i}") for i in (1, 2, 3)]
    g = [state.index(f"gamma{i}") for i in (1, 2, 3)]
    if np.any(y[m] != 0):
        return None
    # two unit vectors normal to gamma (Householder QR: the same bits on every processor)
    normal_plane = detlinalg.orthonormal_split(y[g][None, :])[1]
    basis = np.zeros((len(state), 2))
    basis[g, :] = normal_plane
    return basis


def attractor_regime(
    code: ModelCode,
    params: ArrayLike,
    y0: ArrayLike,
    *,
    transient: int = 2000,
    recorded: int = 600,
    max_period: int = 64,
    tol: float = 1e-4,
    intervals: int = 2000,
    lyapunov_transient: int = 100,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    t0: float = 0.0,
) -> AttractorRegime:
    """Classify the attractor of the stroboscopic map reached from ``y0``.

    Parameters
    ----------
    code : ModelCode
        A time-periodic model (parameter ``Omega``) with state ``M``, ``gamma``.
    params : array_like
        Parameters in ``code.params`` order (double).
    y0 : array_like, shape (n,)
        Start.
    transient : int
        Map iterations discarded first.
    recorded : int
        Iterations searched for a period (``> max_period``).
    max_period : int
        Largest period looked for.
    tol : float
        Closing tolerance in ``(M/|M|, gamma)`` (max norm).
    intervals : int
        Map iterations of the Lyapunov exponent (at least 10).
    lyapunov_transient : int
        Iterations that align the tangent vector first.
    rtol, atol : float
        Tolerances of the integrations (DOP853 in C: the batch map and the variational
        equations).
    t0 : float
        Phase of the section.

    Returns
    -------
    AttractorRegime

    Raises
    ------
    UserInputError
        Bad counts or tolerances; a model without ``Omega`` or without ``M``, ``gamma``.
    ComputationError
        An integration failed.
    """
    (r,) = attractor_regimes(
        code, [params], [y0], transient=transient, recorded=recorded, max_period=max_period,
        tol=tol, intervals=intervals, lyapunov_transient=lyapunov_transient, rtol=rtol,
        atol=atol, t0=t0,
    )  # fmt: skip
    if isinstance(r, ComputationError):
        raise r
    return r


def attractor_regimes(
    code: ModelCode,
    params: ArrayLike,
    y0: ArrayLike,
    *,
    transient: int = 2000,
    recorded: int = 600,
    max_period: int = 64,
    tol: float = 1e-4,
    intervals: int = 2000,
    lyapunov_transient: int = 100,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    t0: ArrayLike = 0.0,
) -> list[AttractorRegime | ComputationError]:
    """:func:`attractor_regime` of ``N`` starts at once: the map of every start in one call of
    the batch map (vector lanes), then the largest exponents of the starts without a period in
    one call of :func:`~chaplygin.numerics.dynamics.lyapunov_batch.lyapunov_spectra` (vector
    lanes). Each start's result is :func:`attractor_regime`'s for it, bit for bit (the lanes
    give every point the bits of a run on its own), whatever ``N`` and the other starts.

    Parameters
    ----------
    code : ModelCode
    params : array_like, shape (N, n_param)
        Parameters of every start, in ``code.params`` order (double).
    y0 : array_like, shape (N, n)
        Starts.
    transient, recorded, max_period, tol, intervals, lyapunov_transient, rtol, atol
        As :func:`attractor_regime`, the same for every start.
    t0 : float or array_like, shape (N,)
        Phases of the section.

    Returns
    -------
    list of AttractorRegime or ComputationError
        Per start its regime, or the error of the integration that failed for it (the other
        starts are unaffected).

    Raises
    ------
    UserInputError
        Bad counts, tolerances or shapes; a model without ``Omega`` or without ``M``, ``gamma``.
    """
    from ..dynamics.batch_map import STATUS_MESSAGES, BatchStroboscopicMap

    _check_settings(code, transient, recorded, max_period, tol, intervals, lyapunov_transient)
    Y = check_rows(y0, "y0", len(code.state))
    P = check_rows(params, "params", len(code.params), len(Y))
    try:
        T0 = np.broadcast_to(np.asarray(t0, dtype=float), (len(Y),))
    except (TypeError, ValueError, OverflowError):
        raise UserInputError(f"t0 must be a number or {len(Y)} numbers") from None
    if not np.isfinite(T0).all():
        raise UserInputError("t0 must be finite")
    bm = BatchStroboscopicMap(code, rtol=rtol, atol=atol)
    r = bm.run(Y, P, n=recorded + 1, transient=transient, t0=T0)
    state, out = tuple(code.state), []
    periods: list[int] = []
    for j in range(len(Y)):
        if r.status[j]:
            out.append(ComputationError(f"the map failed: {STATUS_MESSAGES[int(r.status[j])]}"))
            periods.append(-1)
            continue
        points = np.asarray(r.y[j], dtype=float)[:-1]
        scaled = map_points_scaled(points, state)
        period = settled_period(scaled, closing_period(scaled, max_period, float(tol)))
        if period > 1:
            period = _newton_period(code, list(P[j]), points, scaled, period, float(tol), rtol)
        periods.append(period)
        out.append(None)
    lyap = _exponents(
        code, P, np.asarray(r.y, dtype=float)[:, -1], T0, periods, transient + recorded,
        intervals, lyapunov_transient, rtol, atol,
    )  # fmt: skip
    for j, period in enumerate(periods):
        if period < 0:
            continue
        y = np.asarray(r.y[j], dtype=float)
        out[j] = _regime_of(code, list(P[j]), y[:-1], y[-1], period, lyap.get(j), tol, intervals)
        if isinstance(out[j], AttractorRegime):
            out[j].work["map_periods"] = transient + recorded
            if period == 0:
                out[j].work["lyapunov_periods"] = intervals + lyapunov_transient
    return out


def _check_settings(
    code: ModelCode, transient: int, recorded: int, max_period: int, tol: float,
    intervals: int, lyapunov_transient: int,
) -> None:  # fmt: skip
    for name, value, least in (
        ("transient", transient, 0),
        ("recorded", recorded, 2),
        ("max_period", max_period, 1),
        ("intervals", intervals, 10),
        ("lyapunov_transient", lyapunov_transient, 0),
    ):
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            raise UserInputError(f"{name} must be an integer >= {least}, got {value!r}")
    if recorded <= max_period:
        raise UserInputError(f"recorded ({recorded}) must exceed max_period ({max_period})")
    if not 0 < float(tol) < 1:
        raise UserInputError(f"tol must be in (0, 1), got {tol}")
    if not {"M1", "gamma1"} <= set(code.state):
        raise UserInputError(f"{code.name} has no M and gamma: no map regime")
    if "Omega" not in code.params:
        raise UserInputError(f"{code.name} has no Omega: no stroboscopic map")


def _exponents(
    code: ModelCode, P: NDArray, ends: NDArray, T0: NDArray, periods: list[int], maps: int,
    intervals: int, lyapunov_transient: int, rtol: float, atol: float,
) -> dict[int, tuple[float, float] | ComputationError]:  # fmt: skip
    """The largest exponent per iteration and its error of the starts without a period
    (``periods[j] == 0``), from their end states: in vector lanes, except from rest (on the
    sphere of ``gamma`` alone: one at a time in its subspace)."""
    from ..dynamics.lyapunov import lyapunov_spectrum
    from ..dynamics.lyapunov_batch import lyapunov_spectra

    state, found = tuple(code.state), {}
    omega = code.params.index("Omega")
    t_end = {j: float(T0[j]) + maps * (2 * math.pi / P[j][omega]) for j in range(len(P))}
    lanes = [j for j, q in enumerate(periods) if q == 0]
    for j in [j for j in lanes if _from_rest_subspace(ends[j], state) is not None]:
        lanes.remove(j)
        try:
            spec = lyapunov_spectrum(
                code, list(P[j]), ends[j], intervals=intervals, transient=lyapunov_transient,
                t0=t_end[j], rtol=rtol, atol=atol, count=1,
                subspace=_from_rest_subspace(ends[j], state),
            )  # fmt: skip
        except ComputationError as exc:
            found[j] = exc
            continue
        found[j] = (spec.per_iteration(spec.exponents)[0], spec.per_iteration(spec.errors)[0])
    if lanes:
        batch = lyapunov_spectra(
            code, P[lanes], ends[lanes], intervals=intervals, transient=lyapunov_transient,
            t0=[t_end[j] for j in lanes], rtol=rtol, atol=atol, count=1,
        )  # fmt: skip
        for k, j in enumerate(lanes):
            spec = batch.spectra[k]
            found[j] = (
                ComputationError(batch.messages[k])
                if spec is None
                else (spec.per_iteration(spec.exponents)[0], spec.per_iteration(spec.errors)[0])
            )
    return found


def _regime_of(
    code: ModelCode, p: list, points: NDArray, end: NDArray, period: int, lyap: Any,
    tol: float, intervals: int,
) -> AttractorRegime | ComputationError:  # fmt: skip
    """The regime from the period and (without one) the exponent; the copy named."""
    if isinstance(lyap, ComputationError):
        return lyap
    state = tuple(code.state)
    lam = err = math.nan
    if period:
        regime = "periodic"
    else:
        lam, err = float(lyap[0]), float(lyap[1])
        regime = classify_exponent(lam, err, intervals)
    copy = None
    if symmetries_of(code):
        if period:  # tol is relative to |M| in M: in state units at most tol max(1, |M|)
            m = [state.index(f"M{i}") for i in (1, 2, 3)]
            scale = max(1.0, max(detlinalg.norm(q) for q in points[:, m]))
            copy = name_copy(points[-period:], state, periodic=True, tol=float(tol) * scale)
        else:
            copy = name_copy(points, state)
    return AttractorRegime(
        regime=regime, period=period, lyapunov=lam, lyapunov_error=err,
        threshold=linear_growth_rate(intervals), copy=copy, points=points, end=end, work={},
    )  # fmt: skip
