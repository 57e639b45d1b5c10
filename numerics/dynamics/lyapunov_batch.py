"""Lyapunov spectra of many points in one call: Benettin's loop in vector lanes.

:func:`lyapunov_spectra` computes for ``N`` points, each with its own initial state and
parameters, what :func:`~chaplygin.numerics.dynamics.lyapunov.lyapunov_spectrum` computes for
one (``states=1``): the same initial tangent vectors (from the same seed), the same DOP853
integration of the variational equations with the same QR after every interval, the same
statistics. Point ``j``'s spectrum is bit-identical to ``lyapunov_spectrum(code, params[j],
y0[j], ...)`` with the same settings. The integrations of all points run in one C call (the
``dop853`` integrator of :data:`~chaplygin.numerics.integrators.INTEGRATORS` on a
:class:`~chaplygin.numerics.integrators.VariationalBatch`, ``derive/templates/
variational_batch.c``): eight points at a time in the lanes of GCC vector types where the
compiler targets AVX-512, else four, where the model's right-hand side and Jacobian have a
vector form (``generated/<model>_lanes.c``), each lane with the IEEE operations of the
one-point integrator (the sine and cosine too: ``templates/batch_map.c`` writes detmath's on
vectors), so that the lanes change no bit.
Points are independent: one that fails gets its own status and message, the others are
unaffected. Double precision only.

Units as in :mod:`~chaplygin.numerics.dynamics.lyapunov`: exponents per unit time (and, for a
time-periodic model, per forcing period through :meth:`LyapunovSpectrum.per_iteration`).

Examples
--------
>>> from chaplygin.numerics.code import load_model_code
>>> code = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
>>> p = [4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.07]
>>> y = [1.5, 2.0, 1.0, 0.6, -0.8, 0.0]
>>> r = lyapunov_spectra(code, [p, p], [y, y], intervals=20, transient=0, count=1)
>>> r.status.tolist(), len(r.spectra)
([0, 0], 2)

References
----------
G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, Meccanica 15 (1980) 9-30.
BM20 (FORMULAS.md: BM20-Lyap).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...arith import detlinalg
from ...derive.errors import ComputationError, UserInputError
from ..code import ModelCode
from ..integrators import VariationalFlow
from ..integrators.dop853_c import VARIATIONAL_STATUS
from .lyapunov import (
    CONVERGENCE_POINTS,
    LyapunovSpectrum,
    _check_counts,
    _has_density,
    _renormalisation_interval,
    _StateRuns,
    _uniform_matrix,
    _vector_count,
    forcing_period,
    lyapunov_spectrum,
)
from .variational import (
    DEFAULT_MAX_STEPS,
    VariationalSystem,
    renormalised_after_transient,
    variational_batch_available,
)

__all__ = ["LyapunovBatch", "lyapunov_spectra"]


@dataclass
class LyapunovBatch:
    """The spectra of a batch of points.

    Attributes
    ----------
    spectra : list of LyapunovSpectrum or None
        Point ``j``'s spectrum (its ``wall_time`` its share of the call), None where it failed.
    status : ndarray of int, shape (N,)
        0 done, else a key of
        :data:`~chaplygin.numerics.integrators.dop853_c.VARIATIONAL_STATUS` (-1: failed
        without the compiled batch, see ``messages``).
    messages : list of str
        ``"done"`` or what went wrong, per point.
    lockstep : bool
        Whether the points ran in vector lanes (four or eight at a time).
    wall_time : float
        Seconds for the whole batch.
    """

    spectra: list[LyapunovSpectrum | None]
    status: NDArray[np.int32]
    messages: list[str]
    lockstep: bool
    wall_time: float

    @property
    def ok(self) -> NDArray[np.bool_]:
        """Which points have a spectrum.

        Returns
        -------
        ndarray of bool, shape (N,)
        """
        return self.status == 0

    def largest(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The largest exponent of every point and its error bar, per unit time (NaN where a
        point failed).

        Returns
        -------
        (ndarray, ndarray), shape (N,) each
        """
        lam = np.array([s.exponents[0] if s else np.nan for s in self.spectra])
        err = np.array([s.errors[0] if s else np.nan for s in self.spectra])
        return lam, err


def _rows(values: ArrayLike, width: int, what: str) -> NDArray[np.float64]:
    a = np.array(values, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != width or len(a) == 0:
        raise UserInputError(f"{what} must be an array of shape (N, {width}), got {a.shape}")
    return np.ascontiguousarray(a)


def lyapunov_spectra(
    code: ModelCode,
    params: ArrayLike,
    y0: ArrayLike,
    *,
    spectrum: Literal["level_set", "full"] = "level_set",
    intervals: int = 10_000,
    transient: int = 500,
    interval: float | None = None,
    t0: ArrayLike = 0.0,
    windows: int = 10,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    seed: int = 20200,
    count: int | None = None,
    lockstep: bool = True,
    max_steps: int = DEFAULT_MAX_STEPS,
) -> LyapunovBatch:
    """Lyapunov exponents of ``N`` orbits at once (one initial state each).

    Parameters
    ----------
    code : ModelCode
        The model's generated code.
    params : array_like, shape (N, n_param)
        Parameters of every point, in ``code.params`` order (double).
    y0 : array_like, shape (N, n)
        Initial states.
    spectrum, intervals, transient, interval, windows, rtol, atol, seed, count
        As :func:`~chaplygin.numerics.dynamics.lyapunov.lyapunov_spectrum` (``states=1``);
        every point takes the same number of tangent vectors.
    t0 : float or array_like, shape (N,)
        Start times.
    lockstep : bool, default True
        Four points at a time in vector lanes where available (the same bits); False: one
        after another in the same C call.
    max_steps : int
        Cap on the steps of one interval.

    Returns
    -------
    LyapunovBatch

    Raises
    ------
    UserInputError
        Bad shapes or settings, non-finite values, points whose level sets differ in
        dimension.
    """
    start = time.perf_counter()
    intervals, transient, _, windows = _check_counts(spectrum, intervals, transient, 1, windows)
    n = len(code.state)
    Y, P = _rows(y0, n, "y0"), _rows(params, len(code.params), "params")
    N = len(Y)
    if len(P) != N:
        raise UserInputError(f"y0 has {N} rows but params has {len(P)}")
    T0 = np.ascontiguousarray(np.broadcast_to(np.asarray(t0, dtype=np.float64), (N,)))
    if not variational_batch_available(code):  # no compiler: one by one (scipy's DOP853)
        return _one_by_one(code, P, Y, T0, start, spectrum=spectrum, intervals=intervals,
                           transient=transient, interval=interval, windows=windows, rtol=rtol,
                           atol=atol, seed=seed, count=count)  # fmt: skip
    systems = [VariationalSystem(code, p, rtol=rtol, atol=atol, max_steps=max_steps) for p in P]
    taus = np.array(
        [_renormalisation_interval(code, interval, forcing_period(code, vs.params))
         for vs in systems]
    )  # fmt: skip
    Z0, k, ranks = _initial_tangents(code, systems, Y, T0, spectrum, count, seed)
    settings = {"tangents": k, "project": spectrum == "level_set", "rtol": rtol, "atol": atol,
                "max_steps": max_steps, "lockstep": lockstep}  # fmt: skip
    runs_all = renormalised_after_transient(code, P, Z0, T0, taus, transient, intervals,
                                            **settings)  # fmt: skip
    Z, T_start, sol, status, work = (runs_all.start, runs_all.t_start, runs_all.measured,
                                     runs_all.status, runs_all.work)  # fmt: skip
    wall = time.perf_counter() - start
    checkpoints = np.unique(np.geomspace(1, intervals, CONVERGENCE_POINTS).astype(int))
    with_density = _has_density(code)
    spectra: list[LyapunovSpectrum | None] = []
    for j, vs in enumerate(systems):
        if status[j]:
            spectra.append(None)
            continue
        runs = _StateRuns(1, k, checkpoints.size)
        runs.work = dict(zip(("steps", "rejected", "evaluations"), map(int, work[j]), strict=True))
        density = (code, vs.params, T_start[j], Z[j, :n], sol.y[j, :n]) if with_density else None
        runs.record(0, sol.info["logs"][j], sol.info["divergence"][j], taus[j], windows,
                    checkpoints, density)  # fmt: skip
        spectra.append(runs.spectrum(
            spectrum=spectrum, tau=taus[j], period=forcing_period(code, vs.params),
            intervals=intervals, transient=transient, windows=windows, rank=ranks[j],
            with_density=with_density, checkpoints=checkpoints, starts=Y[j][None].copy(),
            wall_time=wall / N, vs=vs,
        ))  # fmt: skip
    messages = [VARIATIONAL_STATUS.get(int(s), f"status {s}") if s else "done" for s in status]
    return LyapunovBatch(spectra, status.astype(np.int32), messages,
                         bool(sol.info["lockstep"]), wall)  # fmt: skip


def _initial_tangents(code, systems, Y, T0, spectrum, count, seed):  # fmt: skip
    """The augmented states ``(y, V, 0)`` of every point with the tangent vectors that
    :func:`~chaplygin.numerics.dynamics.lyapunov.lyapunov_spectrum` starts from, their number
    and the rank of the integrals' gradients of every point."""
    rows, k_all, ranks = [], set(), []
    for vs, y, t in zip(systems, Y, T0, strict=True):
        y = vs._state(y)
        normal, tangent = vs.level_set_basis(float(t), y)
        ranks.append(normal.shape[1])
        basis = tangent if spectrum == "level_set" else np.eye(vs.n)
        k = _vector_count(code, basis.shape[1], count)
        k_all.add(k)
        rng = np.random.default_rng(seed + 1)
        V = detlinalg.matmul(basis, detlinalg.qr(_uniform_matrix(rng, basis.shape[1], k))[0])
        rows.append(VariationalFlow(code, k).pack(y, V))
    if len(k_all) != 1:
        raise UserInputError(
            "the points' level sets differ in dimension (a singular level among them): give "
            "count, or compute them with lyapunov_spectrum one by one"
        )
    return np.ascontiguousarray(np.array(rows)), k_all.pop(), ranks


def _one_by_one(code, P, Y, T0, start, **settings) -> LyapunovBatch:  # fmt: skip
    """Without the compiled batch: :func:`lyapunov_spectrum` per point."""
    spectra: list[LyapunovSpectrum | None] = []
    messages = []
    for p, y, t in zip(P, Y, T0, strict=True):
        try:
            spectra.append(lyapunov_spectrum(code, p, y, t0=float(t), **settings))
            messages.append("done")
        except ComputationError as exc:
            spectra.append(None)
            messages.append(str(exc))
    status = np.array([0 if s is not None else -1 for s in spectra], dtype=np.int32)
    return LyapunovBatch(spectra, status, messages, False, time.perf_counter() - start)
