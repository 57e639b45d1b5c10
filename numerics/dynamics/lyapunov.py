"""Lyapunov spectra by Benettin's method (QR re-orthonormalisation of tangent vectors).

Two spectra (``spectrum=``):

* ``"level_set"`` -- the tangent vectors are kept in the tangent space of the level set of the
  model's first integrals (projected onto the orthogonal complement of the integrals' gradients
  before every QR), so there are ``n - r`` exponents (``r`` the rank of the gradients): three for
  BM20's ball at fixed ``G = |M|``, ``(M, gamma) = 0`` and ``|gamma| = 1``.
* ``"full"`` -- all ``n`` exponents; ``r`` of them vanish because the integrals are conserved,
  which is reported as a check (:attr:`LyapunovSpectrum.forced_zeros`).

Units: exponents are given **per unit time** and, for a time-periodic model (a parameter
``Omega``, forcing period ``2 pi/Omega``), **per map iteration** (per forcing period), which is
how BM20 quotes them. Error bars are standard errors: from batch means over windows of each
run, and from the spread over several initial states; the larger is reported. The average
divergence carries its own standard error, computed the same way.

The symbolic tie: the sum of the full spectrum equals the time average of ``div f = tr J``
(Liouville's formula ``d/dt log det Phi = tr J``); the exponents come from the QR route, the
average divergence from a quadrature of ``tr J`` integrated with the orbit, so both are reported
with their difference. Where the model ships a proved invariant density ``rho`` (its
``REFERENCES`` name one, e.g. BKM12-4 for the ball), ``div f = -d/dt log rho`` along orbits, so
the average divergence is also ``-(log rho(end) - log rho(start))/T``, a third route, which
tends to zero for bounded ``rho``.

References
----------
G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, Meccanica 15 (1980) 9-30.
BM20 (FORMULAS.md: BM20-Lyap).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...arith import detlinalg, detmath
from ...derive.errors import UserInputError
from ..code import ModelCode
from ..integrators import VariationalFlow
from ..integrators.dop853_c import VARIATIONAL_STATUS
from .variational import (
    VariationalSystem,
    renormalised_after_transient,
    variational_batch_available,
)

__all__ = [
    "SPECTRA",
    "LyapunovSpectrum",
    "forcing_period",
    "lyapunov_spectrum",
    "states_on_level_set",
]

#: The spectra :func:`lyapunov_spectrum` computes.
SPECTRA = ("level_set", "full")

#: Running estimates kept per initial state for the convergence plot.
CONVERGENCE_POINTS = 200

UNITS_PER_TIME = "per unit time"
UNITS_PER_ITERATION = "per map iteration (per forcing period 2 pi/Omega)"


@dataclass
class LyapunovSpectrum:
    """A Lyapunov spectrum with its error bars and checks.

    Attributes
    ----------
    spectrum : str
        ``"level_set"`` or ``"full"``.
    exponents : ndarray, shape (k,)
        Exponents per unit time, largest first (mean over the initial states).
    errors : ndarray, shape (k,)
        Their error bars per unit time (one standard error: the larger of
        `window_errors` and `state_errors`).
    window_errors, state_errors : ndarray, shape (k,)
        Standard error from batch means over windows (combined over the states), and from the
        spread over the initial states (NaN with one state).
    per_state : ndarray, shape (n_states, k)
        Each initial state's exponents per unit time.
    interval : float
        Renormalisation interval (time between QRs).
    period : float or None
        Forcing period ``2 pi/Omega`` of a time-periodic model, else None.
    intervals, transient : int
        Intervals averaged, and intervals discarded before them, per state.
    windows : int
        Windows of the batch means.
    sum_of_exponents : float
        Sum of `exponents` (per unit time).
    mean_divergence : float
        Time average of ``div f`` along the orbits (quadrature of ``tr J``), per unit time.
    divergence_error : float
        Its standard error per unit time: the larger of batch means over the windows (combined
        over the states) and the spread over the initial states (as for `errors`).
    density_rate : float or None
        ``-(log rho(end) - log rho(start))/T`` averaged over the states, per unit time, where
        the model ships an invariant density, else None.
    forced_zeros : ndarray or None
        For the full spectrum, the ``r`` exponents closest to zero (per unit time), which the
        ``r`` independent integrals force to vanish; None for the level set.
    integral_rank : int
        ``r``, the rank of the integrals' gradients at the first initial state.
    convergence_iterations : ndarray, shape (m,)
        Interval counts at which the running estimates were taken.
    convergence : ndarray, shape (n_states, m, k)
        Running estimates per unit time (for the convergence plot).
    initial_states : ndarray, shape (n_states, n)
        The initial states used.
    work : dict
        ``steps``, ``rejected``, ``evaluations`` summed over the runs.
    wall_time : float
        Seconds.
    rtol, atol : float
        The integrator's tolerances.
    """

    spectrum: str
    exponents: NDArray
    errors: NDArray
    window_errors: NDArray
    state_errors: NDArray
    per_state: NDArray
    interval: float
    period: float | None
    intervals: int
    transient: int
    windows: int
    sum_of_exponents: float
    mean_divergence: float
    divergence_error: float
    density_rate: float | None
    forced_zeros: NDArray | None
    integral_rank: int
    convergence_iterations: NDArray
    convergence: NDArray
    initial_states: NDArray
    work: dict[str, int] = field(default_factory=dict)
    wall_time: float = 0.0
    rtol: float = 0.0
    atol: float = 0.0

    @property
    def divergence_difference(self) -> float:
        """``sum_of_exponents - mean_divergence`` (per unit time).

        Returns
        -------
        float
        """
        return self.sum_of_exponents - self.mean_divergence

    def per_iteration(self, values: ArrayLike) -> NDArray:
        """Values per unit time converted to per map iteration (times the forcing period).

        Parameters
        ----------
        values : array_like
            Rates per unit time.

        Returns
        -------
        ndarray
            Rates per forcing period ``2 pi/Omega``.

        Raises
        ------
        UserInputError
            The model is not time-periodic (no map iteration).
        """
        if self.period is None:
            raise UserInputError("an autonomous model has no map iteration: use per unit time")
        return np.asarray(values, dtype=float) * self.period

    def summary(self) -> dict[str, Any]:
        """JSON-able numbers with their units spelled out.

        Returns
        -------
        dict
            ``per_unit_time`` (and ``per_iteration`` for a time-periodic model) with
            ``exponents``, ``errors``, ``sum``, ``mean_divergence`` (and its error),
            ``difference``; the run's settings and work counters.
        """

        def block(scale: float, units: str) -> dict[str, Any]:
            out: dict[str, Any] = {
                "units": units,
                "exponents": [float(v) * scale for v in self.exponents],
                "errors": [float(v) * scale for v in self.errors],
                "window_errors": [float(v) * scale for v in self.window_errors],
                "state_errors": [
                    None if math.isnan(v) else float(v) * scale for v in self.state_errors
                ],
                "sum_of_exponents": self.sum_of_exponents * scale,
                "mean_divergence": self.mean_divergence * scale,
                "mean_divergence_error": self.divergence_error * scale,
                "difference": self.divergence_difference * scale,
            }
            if self.density_rate is not None:
                out["minus_mean_dlog_density_dt"] = self.density_rate * scale
            if self.forced_zeros is not None:
                out["forced_zeros"] = [float(v) * scale for v in self.forced_zeros]
            return out

        out: dict[str, Any] = {
            "spectrum": self.spectrum,
            "per_unit_time": block(1.0, UNITS_PER_TIME),
        }
        if self.period is not None:
            out["per_iteration"] = block(self.period, UNITS_PER_ITERATION)
            out["period"] = self.period
        out.update(
            interval=self.interval,
            intervals=self.intervals,
            transient=self.transient,
            windows=self.windows,
            initial_states=int(self.per_state.shape[0]),
            integral_rank=self.integral_rank,
            rtol=self.rtol,
            atol=self.atol,
            work=dict(self.work),
            wall_time_s=round(self.wall_time, 3),
        )
        return out


def forcing_period(code: ModelCode, params: ArrayLike) -> float | None:
    """``2 pi/Omega`` for a model with a forcing frequency ``Omega``, else None.

    Parameters
    ----------
    code : ModelCode
    params : array_like, shape (n_param,)
        Parameter values in ``code.params`` order.

    Returns
    -------
    float or None

    Raises
    ------
    UserInputError
        ``Omega`` is not positive.
    """
    if code.forcing is None:
        return None
    omega = float(np.asarray(params, dtype=float)[code.params.index(code.forcing)])
    if not omega > 0:
        raise UserInputError(f"Omega must be > 0 for a forcing period, got {omega}")
    return 2 * math.pi / omega


def states_on_level_set(
    system: VariationalSystem,
    y0: ArrayLike,
    count: int,
    *,
    spread: float = 1e-2,
    t: float = 0.0,
    seed: int = 20200,
) -> NDArray:
    """``y0`` and ``count - 1`` states near it on the same level set of the integrals.

    Each is ``y0`` moved by ``spread |y0|`` along a random direction of the level set's tangent
    space, then pulled back onto the level set by Gauss-Newton steps on the integrals.

    Parameters
    ----------
    system : VariationalSystem
    y0 : array_like, shape (n,)
    count : int
        Number of states (the first is ``y0``).
    spread : float
        Relative size of the displacement.
    t : float
        Time (for time-dependent integrals).
    seed : int
        Seed of the random directions (reproducible).

    Returns
    -------
    ndarray, shape (count, n)

    Raises
    ------
    UserInputError
        ``count < 1`` or ``spread`` not finite and positive.
    """
    if count < 1:
        raise UserInputError("at least one initial state is needed")
    if not (math.isfinite(spread) and spread > 0):
        raise UserInputError(f"spread must be finite and > 0, got {spread}")
    y0 = np.asarray(y0, dtype=float)
    code, p = system.code, system.params
    target = np.asarray(code.numpy.integrals(t, y0, p), dtype=float)
    rng = np.random.default_rng(seed)
    states = [y0.copy()]
    scale = spread * max(detlinalg.norm(y0), 1.0)
    for _ in range(count - 1):
        _, tangent = system.level_set_basis(t, y0)
        direction = detlinalg.matmul(tangent, detlinalg.unit_vectors(rng, 1, tangent.shape[1])[0])
        y = y0 + scale * direction
        for _ in range(20):  # Gauss-Newton onto F(y) = F(y0)
            r = np.asarray(code.numpy.integrals(t, y, p), dtype=float) - target
            if np.all(np.abs(r) <= 4 * np.finfo(float).eps * np.maximum(1, np.abs(target))):
                break
            G = system.integral_gradients(t, y)
            y = y - detlinalg.lstsq(G, r)
        states.append(y)
    return np.array(states)


def _uniform_matrix(rng: np.random.Generator, rows: int, cols: int) -> NDArray:
    """Entries uniform in [-1, 1): the generator's integers scaled exactly (a normal deviate's
    tail uses libm's log, whose bits depend on the processor)."""
    return 2.0 * rng.random((rows, cols)) - 1.0


def _log_density(code: ModelCode, t: float, y: NDArray, p: NDArray) -> float:
    return detmath.log(float(np.asarray(code.numpy.density(t, y, p), dtype=float).ravel()[0]))


def _has_density(code: ModelCode) -> bool:
    return "density" in dict(getattr(code.numpy, "REFERENCES", ()))


def lyapunov_spectrum(
    code: ModelCode,
    params: ArrayLike,
    y0: ArrayLike,
    *,
    spectrum: Literal["level_set", "full"] = "level_set",
    intervals: int = 10_000,
    transient: int = 500,
    interval: float | None = None,
    t0: float = 0.0,
    states: int = 1,
    spread: float = 1e-2,
    windows: int = 10,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    seed: int = 20200,
    system: VariationalSystem | None = None,
    count: int | None = None,
    subspace: ArrayLike | None = None,
) -> LyapunovSpectrum:
    """Lyapunov exponents of the orbit of ``y0`` (and of ``states - 1`` neighbours).

    Parameters
    ----------
    code : ModelCode
        The model's generated code.
    params : array_like, shape (n_param,)
        Parameter values in ``code.params`` order (double precision).
    y0 : array_like, shape (n,)
        Initial state.
    spectrum : {"level_set", "full"}
        Tangent vectors in the tangent space of the integrals' level set, or all ``n``.
    intervals : int
        Renormalisation intervals averaged per state (map iterations when `interval` is the
        forcing period).
    transient : int
        Intervals discarded first (the tangent vectors align, the orbit reaches the attractor).
    interval : float, optional
        Time between QRs; default the forcing period ``2 pi/Omega`` (required for autonomous
        models).
    t0 : float
        Start time.
    states : int
        Number of initial states (``y0`` and neighbours on its level set, see
        :func:`states_on_level_set`) for the spread error bar.
    spread : float
        Relative distance of the neighbours.
    windows : int
        Windows of the batch means (at least 2).
    rtol, atol : float
        Integrator tolerances.
    seed : int
        Seed of the neighbours and of the initial tangent vectors.
    system : VariationalSystem, optional
        A prepared system (its tolerances are used instead of `rtol`, `atol`).
    count : int, optional
        Only the ``count`` largest exponents (fewer tangent vectors: cheaper; the largest
        alone needs one).
    subspace : array_like, shape (n, m), optional
        Columns spanning a subspace of the level set's tangent space that the variational
        flow keeps invariant: the tangent vectors start in it (instead of in the whole
        tangent space) and are projected onto the level set as usual (``states=1``). Where the
        level set is singular, e.g. from rest (``M = 0``, the critical level of ``(M, M)``:
        ``delta M = 0``, ``delta gamma`` normal to ``gamma``; the projection removes the
        radial drift of ``delta gamma``, which would otherwise grow with exponent 0 and hide
        the contraction on the sphere).

    Returns
    -------
    LyapunovSpectrum

    Raises
    ------
    UserInputError
        Bad settings (unknown spectrum, counts, no interval for an autonomous model).
    ComputationError
        An integration failed.
    """
    start = time.perf_counter()
    intervals, transient, states, windows = _check_counts(
        spectrum, intervals, transient, states, windows
    )
    vs = system if system is not None else VariationalSystem(code, params, rtol=rtol, atol=atol)
    p = vs.params
    period = forcing_period(code, p)
    tau = _renormalisation_interval(code, interval, period)
    y_first = vs._state(y0)
    normal, tangent = vs.level_set_basis(t0, y_first)
    rank = normal.shape[1]
    if subspace is not None:
        tangent = detlinalg.qr(np.asarray(subspace, dtype=np.float64))[0]
        if tangent.shape[0] != vs.n or spectrum != "level_set" or states != 1:
            raise UserInputError(
                f"subspace must have {vs.n} rows, with spectrum='level_set' and states=1"
            )
    starts = states_on_level_set(vs, y_first, states, spread=spread, t=t0, seed=seed)
    rng = np.random.default_rng(seed + 1)
    k = _vector_count(code, tangent.shape[1] if spectrum == "level_set" else vs.n, count)
    checkpoints = np.unique(np.geomspace(1, intervals, CONVERGENCE_POINTS).astype(int))
    runs = _StateRuns(states, k, checkpoints.size)
    with_density = _has_density(code)
    vectors = []
    for y in starts:
        tangent_s = vs.level_set_basis(t0, y)[1] if subspace is None else tangent
        basis = tangent_s if spectrum == "level_set" else np.eye(vs.n)
        vectors.append(
            detlinalg.matmul(basis, detlinalg.qr(_uniform_matrix(rng, basis.shape[1], k))[0])
        )
    settings = (t0, tau, transient, intervals, windows, checkpoints, spectrum == "level_set",
                with_density)  # fmt: skip
    if states > 1 and vs.compiled and variational_batch_available(code):
        runs.run_many(vs, starts, vectors, *settings)  # in vector lanes, the same bits
    else:
        for s, (y, V) in enumerate(zip(starts, vectors, strict=True)):
            runs.run(s, vs, y, V, *settings)
    return runs.spectrum(
        spectrum=spectrum, tau=tau, period=period, intervals=intervals, transient=transient,
        windows=windows, rank=rank, with_density=with_density, checkpoints=checkpoints,
        starts=starts, wall_time=time.perf_counter() - start, vs=vs,
    )  # fmt: skip


def _check_counts(
    spectrum: str, intervals: int, transient: int, states: int, windows: int
) -> tuple[int, int, int, int]:
    """The counts of :func:`lyapunov_spectrum` as integers, or :class:`UserInputError`."""
    if spectrum not in SPECTRA:
        raise UserInputError(f"unknown spectrum {spectrum!r}: choose one of {', '.join(SPECTRA)}")
    intervals, transient = int(intervals), int(transient)
    states, windows = int(states), int(windows)
    if windows < 2:
        raise UserInputError("at least 2 windows are needed for the batch-means error")
    if intervals < windows:
        raise UserInputError(f"intervals ({intervals}) must be at least windows ({windows})")
    if transient < 0:
        raise UserInputError("transient must be >= 0")
    return intervals, transient, states, windows


def _renormalisation_interval(code: ModelCode, interval: Any, period: float | None) -> float:
    """The time between QRs: ``interval``, by default the forcing period."""
    if interval is None:
        if period is None:
            raise UserInputError(
                f"{code.name} is autonomous: give the renormalisation interval (a time)"
            )
        interval = period
    tau = float(interval)
    if not (math.isfinite(tau) and tau > 0):
        raise UserInputError(f"the renormalisation interval must be > 0, got {interval}")
    return tau


def _vector_count(code: ModelCode, available: int, count: int | None) -> int:
    """How many tangent vectors: all ``available`` or the ``count`` largest."""
    if available == 0:
        raise UserInputError(f"the level set of {code.name}'s integrals is a point: no exponents")
    if count is not None:
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise UserInputError(f"count must be a positive integer, got {count!r}")
        return min(available, count)
    return available


class _StateRuns:
    """The per-state sums of :func:`lyapunov_spectrum` and their statistics."""

    def __init__(self, states: int, k: int, points: int) -> None:
        self.states = states
        self.per_state = np.zeros((states, k))
        self.window_se = np.zeros((states, k))
        self.divergence = np.zeros(states)
        self.divergence_se = np.zeros(states)
        self.density_rate = np.zeros(states)
        self.running = np.zeros((states, points, k))
        self.work = {"steps": 0, "rejected": 0, "evaluations": 0}

    def run(self, s, vs, y, V, t0, tau, transient, intervals, windows, checkpoints, project,
            with_density) -> None:  # fmt: skip
        """Renormalised runs from state number ``s``: the transient, then the measured ones."""
        t = t0
        if transient:
            _, _, y, V, w = vs.renormalised(y, V, t, tau, transient, project=project)
            t = t0 + transient * tau
            for key in self.work:
                self.work[key] += w[key]
        y_start, t_start = y, t
        logs, divs, y, V, w = vs.renormalised(y, V, t, tau, intervals, project=project)
        for key in self.work:
            self.work[key] += w[key]
        density = (vs.code, vs.params, t_start, y_start, y) if with_density else None
        self.record(s, logs, divs, tau, windows, checkpoints, density)

    def run_many(self, vs, starts, vectors, t0, tau, transient, intervals, windows, checkpoints,
                 project, with_density) -> None:  # fmt: skip
        """:meth:`run` for every state at once (one C call for the transient, one for the
        measured intervals, the states in vector lanes): the same numbers, bit for bit."""
        count, k = len(starts), vectors[0].shape[1]
        flow = VariationalFlow(vs.code, k)
        Z = np.array([flow.pack(y, V) for y, V in zip(starts, vectors, strict=True)])
        runs = renormalised_after_transient(
            vs.code, np.tile(vs.params, (count, 1)), Z, np.full(count, float(t0)),
            np.full(count, float(tau)), transient, intervals, tangents=k, project=project,
            rtol=vs.rtol, atol=vs.atol, max_steps=vs.max_steps,
        )  # fmt: skip
        failed = np.flatnonzero(runs.status)
        if failed.size:  # the one-point loop's error, at the start of the call that failed
            j = failed[0]
            status = int(runs.status[j])
            t = t0 if runs.failed_in_transient[j] else float(runs.t_start[j])
            vs._raise(VARIATIONAL_STATUS.get(status, f"status {status}"), t)
        for key, total in zip(("steps", "rejected", "evaluations"), runs.work.sum(axis=0),
                              strict=True):  # fmt: skip
            self.work[key] += int(total)
        sol, n = runs.measured, vs.n
        for s in range(count):
            t_start, y_start = float(runs.t_start[s]), runs.start[s, :n]
            density = (vs.code, vs.params, t_start, y_start, sol.y[s, :n]) if with_density else None
            self.record(s, sol.info["logs"][s], sol.info["divergence"][s], tau, windows,
                        checkpoints, density)  # fmt: skip

    def record(self, s, logs, divs, tau, windows, checkpoints, density) -> None:  # fmt: skip
        """The statistics of state number ``s`` from its measured intervals' ``logs`` (intervals,
        k) and divergence integrals ``divs``; ``density`` is ``(code, params, t_start, y_start,
        y_end)`` for the density route of the divergence, or None."""
        intervals, k = logs.shape
        self.per_state[s] = logs.mean(axis=0) / tau
        usable = (intervals // windows) * windows
        batches = logs[intervals - usable :].reshape(windows, -1, k).mean(axis=1) / tau
        self.window_se[s] = batches.std(axis=0, ddof=1) / math.sqrt(windows)
        self.divergence[s] = divs.mean() / tau
        div_batches = divs[intervals - usable :].reshape(windows, -1).mean(axis=1) / tau
        self.divergence_se[s] = div_batches.std(ddof=1) / math.sqrt(windows)
        self.running[s] = np.cumsum(logs, axis=0)[checkpoints - 1] / (checkpoints[:, None] * tau)
        if density is not None:
            code, p, t_start, y_start, y = density
            t_end = t_start + intervals * tau
            self.density_rate[s] = -(
                _log_density(code, t_end, y, p) - _log_density(code, t_start, y_start, p)
            ) / (intervals * tau)

    def spectrum(self, *, spectrum, tau, period, intervals, transient, windows, rank,
                 with_density, checkpoints, starts, wall_time, vs) -> LyapunovSpectrum:  # fmt: skip
        """The exponents, their error bars and the record of the run."""
        states, per_state = self.states, self.per_state
        k = per_state.shape[1]
        exponents = per_state.mean(axis=0)
        window_errors = np.sqrt((self.window_se**2).sum(axis=0)) / states
        state_errors = (
            per_state.std(axis=0, ddof=1) / math.sqrt(states) if states > 1 else np.full(k, np.nan)
        )
        errors = np.fmax(window_errors, state_errors)
        divergence = self.divergence
        divergence_error = math.sqrt(float((self.divergence_se**2).sum())) / states
        if states > 1:
            divergence_error = max(
                divergence_error, float(divergence.std(ddof=1)) / math.sqrt(states)
            )
        forced = None
        if spectrum == "full" and rank and k == vs.n:
            forced = np.sort(exponents[np.argsort(np.abs(exponents))[:rank]])[::-1]
        return LyapunovSpectrum(
            spectrum=spectrum,
            exponents=exponents,
            errors=errors,
            window_errors=window_errors,
            state_errors=state_errors,
            per_state=per_state,
            interval=tau,
            period=period,
            intervals=intervals,
            transient=transient,
            windows=windows,
            sum_of_exponents=float(exponents.sum()),
            mean_divergence=float(divergence.mean()),
            divergence_error=divergence_error,
            density_rate=float(self.density_rate.mean()) if with_density else None,
            forced_zeros=forced,
            integral_rank=rank,
            convergence_iterations=checkpoints,
            convergence=self.running,
            initial_states=starts,
            work=self.work,
            wall_time=wall_time,
            rtol=vs.rtol,
            atol=vs.atol,
        )
