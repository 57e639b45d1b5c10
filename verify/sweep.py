"""Sweeps: a scene plus a grid (its ``[sweep]`` table, :mod:`chaplygin.verify.sweep_table`), each
point reduced to numbers, computed in chunks on Dask and stored chunk by chunk in Zarr.

* **Grid.** Each axis is a dotted key of the scene (``parameters.D``, ``initial.h``) and its
  values; ``grid = "product"`` takes every combination (C order, the last axis fastest),
  ``grid = "list"`` the i-th values of all axes as the i-th point. A point is the scene with
  those keys replaced (values reach the scene as the user wrote them, or as 30-digit text for a
  ``{start, stop, num}`` range), resolved and checked like any scene.
* **Reducers** (:data:`REDUCERS`): what a point is reduced to. Each declares its variables
  (names, extra dimensions, units) and computes them from a :class:`PointContext`. A reducer is
  added with :func:`register_reducer` (e.g. the largest Lyapunov exponent, once
  :mod:`chaplygin.numerics.lyapunov` exists).
* **Store** (:mod:`chaplygin.verify.sweep_store`). An xarray Dataset in Zarr: the grid as
  coordinates, one Zarr chunk per sweep chunk (``chunk`` points along the last axis),
  ``status`` per point (0 done, 1 input refused at that point, 2 computation failed),
  ``chunk_digest`` (the SHA-256 of each chunk's values) and ``computed`` (1 once the point's
  chunk is stored; written after the chunk's data and digest, so a chunk is either complete
  or computed again). The store is first built in a temporary folder and renamed into place.
  Its attributes hold the scene, the grid, the versions and the model hash, and a fingerprint
  of all of these: a store made by another scene, grid or code version is refused, never
  mixed. On every resume each chunk marked done is read and checked against its digest, and
  computed again when it does not match; missing or damaged arrays are made again.
* **Checked first** (:mod:`chaplygin.verify.sweep_checks`): the grid's memory, disk and
  least time against the machine, the worker count, the scheduler's address and handshake.
* **Resumable.** Tasks are chunks (Dask distributed: a LocalCluster, or ``--scheduler``); the
  client writes each finished chunk at once (Zarr writes each chunk file atomically). A sweep
  killed at any moment and started again skips the chunks marked ``computed`` whose values
  match their digest and computes the others; every point is computed by the same
  deterministic code, so the results are bit-identical to an uninterrupted run.
"""

from __future__ import annotations

import copy
import hashlib
import json
import math
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from itertools import product
from pathlib import Path
from typing import Any

import numpy as np

from ..arith import detmath
from ..derive.errors import ComputationError, UserInputError
from ..numerics.regimes import linear_growth_rate
from .sweep_checks import (
    CHUNK_OVERHEAD_BYTES,
    CONNECT_TIMEOUT_S,
    GridCost,
    check_grid_cost,
    check_workers,
    parse_scheduler_address,
    probe_scheduler,
    usable_cpus,
)
from .sweep_store import (
    STORE_FORMAT,
    _extra_shape,
    create_store,
    inspect_store,
    repair_store,
    write_chunk,
)

__all__ = [
    "REDUCERS",
    "Reducer",
    "Variable",
    "PointContext",
    "SweepPlan",
    "register_reducer",
    "plan_sweep",
    "compute_chunk",
    "chunk_payload",
    "linear_growth_rate",
    "evaluate_point",
    "run_sweep",
    "open_store",
    "require_dask",
    "period_of_orbit",
    "zeros_along_axis",
    "STORE_FORMAT",
]

#: The leading dimension of a sweep with ``carry = "both"``, and its labels (the order of the
#: last axis's values, and the reverse).
CARRY_KEY = "carry"
CARRY_DIRECTIONS = ("forward", "backward")

#: ``status`` values.
STATUS_DONE, STATUS_REFUSED, STATUS_FAILED = 0, 1, 2

#: Relative radius growth above which a contact trace counts as unbounded (second half of the
#: run against the first: a drift at constant speed gives 2, a bounded trace about 1).
UNBOUNDED_GROWTH = 1.5


def require_dask() -> None:
    """Check that the ``dask`` extra (dask.distributed, xarray, zarr) is installed.

    Raises
    ------
    UserInputError
        One line saying how to install it.
    """
    missing = []
    for name in ("distributed", "xarray", "zarr"):
        try:
            __import__(name)
        except ImportError:
            missing.append(name)
    if missing:
        raise UserInputError(
            f"chaplygin sweep needs {', '.join(missing)}: pip install 'chaplygin[dask]' "
            '(from a source tree: pip install -e ".[dask]")'
        )


# ------------------------------------------------------------------------------- reducers
@dataclass(frozen=True)
class Variable:
    """One stored result of a reducer.

    Attributes
    ----------
    dims : tuple of str
        Extra dimensions after the grid's (``("state",)``), empty for a number per point.
    dtype : str
        ``"float64"``, ``"int16"`` or ``"int8"``.
    attrs : dict
        ``long_name`` and ``units``.
    """

    dims: tuple[str, ...] = ()
    dtype: str = "float64"
    attrs: dict = field(default_factory=dict)

    @property
    def fill(self) -> float | int:
        """The value of a point not (yet) computed: NaN, or -1 for integers."""
        return math.nan if self.dtype.startswith("float") else -1


@dataclass
class PointContext:
    """What a reducer sees of one point.

    Attributes
    ----------
    scene : chaplygin.verify.scene.Scene
        The scene with the point's keys replaced.
    resolved : chaplygin.verify.scene.Resolved
    sweep : chaplygin.verify.sweep_table.Sweep
        The sweep table (reducer options).
    start : sequence or None
        With ``carry``: the state the previous point of the grid line ended on (the point's
        reducers start there instead of at the scene's state).
    end : sequence or None
        Set by a reducer that carries (:attr:`Reducer.carries`): the state to start the next
        point from.
    """

    scene: Any
    resolved: Any
    sweep: Any
    _trajectory: Any = None
    batched: dict[str, Any] = field(default_factory=dict)
    #: A start carried from the previous point of the grid line (``carry``), else None.
    start: Any = None
    #: The state a reducer ended on (on the attractor), carried to the next point.
    end: Any = None

    def trajectory(self) -> Any:
        """The scene's trajectory (integrated once, shared by the reducers).

        Returns
        -------
        chaplygin.numerics.integrate.IntegrationResult
        """
        if self._trajectory is None:
            from .scene import integrate_trajectory

            self._trajectory, _ = integrate_trajectory(self.scene, self.resolved, False)
        return self._trajectory

    def param(self, name: str) -> Any:
        """A parameter's value at the working precision.

        Parameters
        ----------
        name : str

        Returns
        -------
        number

        Raises
        ------
        UserInputError
            The model has no such parameter.
        """
        try:
            return self.resolved.params[name]
        except KeyError:
            raise UserInputError(
                f"the model {self.resolved.code.name} has no parameter {name!r}"
            ) from None


@dataclass(frozen=True)
class Reducer:
    """One way to reduce a point to numbers.

    Attributes
    ----------
    name : str
        Its name in ``reduce = [...]``.
    variables : callable
        ``variables(code, sweep) -> dict name -> Variable``.
    run : callable
        ``run(context) -> dict name -> value`` (arrays shaped by the variable's dims).
    coords : callable or None
        ``coords(code) -> dict dim -> list of labels`` for its extra dimensions.
    description : str
    batch : callable or None
        ``batch(contexts) -> list`` for all resolved points of a chunk at once: per point the
        values (as from ``run``), an exception (raised for that point alone) or None (that
        point goes through ``run``).
    carries : bool
        ``run`` starts at ``context.start`` when given and sets ``context.end``: usable with
        the sweep's ``carry``.
    """

    name: str
    variables: Callable[[Any, Any], dict[str, Variable]]
    run: Callable[[PointContext], dict[str, Any]]
    coords: Callable[[Any], dict[str, list]] | None = None
    description: str = ""
    batch: Callable[[list[PointContext]], list[Any]] | None = None
    carries: bool = False


#: Reducers by name (see :func:`register_reducer`).
REDUCERS: dict[str, Reducer] = {}


def register_reducer(reducer: Reducer) -> Reducer:
    """Make a reducer available to ``reduce = [...]``.

    Parameters
    ----------
    reducer : Reducer

    Returns
    -------
    Reducer
        The same object.
    """
    REDUCERS[reducer.name] = reducer
    return reducer


def _final_state(ctx: PointContext) -> dict:
    r = ctx.trajectory()
    if not r.success:
        raise ComputationError(r.message)
    return {"final_state": np.asarray([float(v) for v in r.y_final.values()])}


register_reducer(
    Reducer(
        "final_state",
        lambda code, sweep: {
            "final_state": Variable(("state",), attrs={"long_name": "state at t_end"})
        },
        _final_state,
        lambda code: {"state": list(code.state)},
        "the state at t_end (float64)",
    )
)


def _drift(ctx: PointContext) -> dict:
    r = ctx.trajectory()
    names = ctx.resolved.code.integral_names
    return {"drift": np.asarray([float(r.drift.get(n, math.nan)) for n in names])}


register_reducer(
    Reducer(
        "drift",
        lambda code, sweep: {
            "drift": Variable(
                ("integral",),
                attrs={"long_name": "largest relative change of the integral", "units": "1"},
            )
        },
        _drift,
        lambda code: {"integral": list(code.integral_names)},
        "each integral's largest relative change",
    )
)


def _trace(ctx: PointContext) -> dict:
    code = ctx.resolved.code
    if "x" not in code.state or "y" not in code.state:
        raise UserInputError("reduce = trace needs the contact_point effect (x, y)")
    r = ctx.trajectory()
    y = np.asarray(r.y, dtype=float)
    x_, y_ = y[code.state.index("x")], y[code.state.index("y")]
    radius = detmath.hypot(x_ - x_[0], y_ - y_[0])
    half = len(radius) // 2
    first, second = radius[: half + 1].max(), radius[half:].max()
    bounded = second <= UNBOUNDED_GROWTH * first
    return {"trace_radius": float(radius.max()), "trace_bounded": int(bounded)}


register_reducer(
    Reducer(
        "trace",
        lambda code, sweep: {
            "trace_radius": Variable(
                attrs={
                    "long_name": "largest distance of the contact point from its start",
                    "units": "b",
                }
            ),
            "trace_bounded": Variable(
                dtype="int8",
                attrs={
                    "long_name": "1 when the trace's radius over the second half of the run is "
                    f"at most {UNBOUNDED_GROWTH} times that over the first",
                    "units": "1",
                },
            ),
        },
        _trace,
        None,
        "the contact trace's radius, and whether it is bounded",
    )
)


def period_of_orbit(points: np.ndarray, max_period: int, tol: float) -> int:
    """The period of a recorded map orbit: the smallest ``p <= max_period`` with every
    ``|y[k+p] - y[k]| <= tol * max|y|``, or 0 (quasi-periodic, chaotic or a longer period).

    Parameters
    ----------
    points : array, shape (n, dim)
        Successive iterates (after the transient).
    max_period : int
    tol : float
        Relative tolerance.

    Returns
    -------
    int

    Raises
    ------
    UserInputError
        Fewer than ``max_period + 1`` points.
    """
    points = np.asarray(points, dtype=float)
    n = len(points)
    if n < max_period + 1:
        raise UserInputError(
            f"{n} recorded iterates cannot show a period up to {max_period} "
            "(record at least max_period + 1)"
        )
    scale = max(float(np.abs(points).max()), np.finfo(float).tiny)
    for p in range(1, max_period + 1):
        if float(np.abs(points[p:] - points[:-p]).max()) <= tol * scale:
            return p
    return 0


def _map_columns(code: Any) -> list[int]:
    """State components of the stroboscopic map: ``M`` and ``gamma`` (the reduced system; the
    frame ``alpha, beta`` and the contact point do not act back on it), else all but x, y."""
    groups = code.state_groups
    if "M" in groups and "gamma" in groups:
        names = [n for n in code.state if n[:-1] in ("M", "gamma")]
    else:
        names = [n for n in code.state if n not in ("x", "y")]
    return [code.state.index(n) for n in names]


def _period(ctx: PointContext) -> dict:
    import mpmath

    from ..numerics.inputs import Precision
    from ..numerics.integrate import integrate

    opts = ctx.sweep.period
    scene, res = ctx.scene, ctx.resolved
    omega = ctx.param(opts.forcing)
    prec = Precision(scene.run_options.precision)
    n = opts.transient + opts.recorded
    t0 = res.t_span[0]
    if prec.is_double:
        period = 2 * math.pi / float(omega)
        t_eval = [float(t0) + k * period for k in range(n + 1)]
    else:
        with mpmath.workprec(prec.prec):
            period = 2 * mpmath.pi / omega
            t_eval = [t0 + k * period for k in range(n + 1)]
    r = integrate(
        res.code,
        res.y0,
        (t_eval[0], t_eval[-1]),
        [res.params[k] for k in res.code.params],
        method=scene.run_options.method,
        precision=scene.run_options.precision,
        rtol=scene.run_options.rtol,
        atol=scene.run_options.atol,
        backend=scene.run_options.backend,
        t_eval=t_eval,
    )
    if not r.success:
        raise ComputationError(r.message)
    y = np.asarray(r.y, dtype=float)[_map_columns(res.code)].T[opts.transient + 1 :]
    return {"period": period_of_orbit(y, opts.max_period, opts.tol)}


#: Tolerances of the batch map when the scene gives none.
BATCH_DEFAULT_TOL = 1e-12


#: The batch map's integrator for each ``period.engine`` that uses it (``"auto"`` keeps DOP853,
#: whatever ``[run] method`` says; ``"taylor-batch"`` asks for the Taylor method).
BATCH_ENGINE_METHODS = {"auto": "dop853", "batch": "dop853", "taylor-batch": "taylor"}


def _batch_eligible(ctx: PointContext) -> bool:
    """Whether the ``period`` reducer takes this point through the compiled batch map
    (``period.engine`` "auto", "batch": DOP853; "taylor-batch": the Taylor method)."""
    from ..numerics.batch_map import batch_map_available
    from ..numerics.inputs import Precision

    opts, run = ctx.sweep.period, ctx.scene.run_options
    if opts.engine == "scene":
        return False
    usable = (
        Precision(run.precision).is_double
        and opts.forcing == "Omega"
        and batch_map_available(ctx.resolved.code, BATCH_ENGINE_METHODS[opts.engine])
    )
    if opts.engine != "auto" and not usable:
        raise UserInputError(
            f'period engine = "{opts.engine}" needs double precision, forcing = "Omega" and a '
            'C compiler; use engine = "scene"'
        )
    return usable


def _period_batch(contexts: list[PointContext]) -> list[Any]:
    """The ``period`` reducer for a chunk: the eligible points (double precision, a compiler)
    through :class:`~chaplygin.numerics.batch_map.BatchStroboscopicMap`, one call per model and
    tolerances; the others are left to :func:`_period`."""
    from ..numerics.batch_map import STATUS_MESSAGES, BatchStroboscopicMap

    out: list[Any] = [None] * len(contexts)
    groups: dict[tuple, list[int]] = {}
    for i, ctx in enumerate(contexts):
        try:
            if not _batch_eligible(ctx):
                continue
        except UserInputError as exc:
            out[i] = exc
            continue
        run = ctx.scene.run_options
        method = BATCH_ENGINE_METHODS[ctx.sweep.period.engine]
        key = (ctx.resolved.code.hash, run.rtol, run.atol, method)
        groups.setdefault(key, []).append(i)
    for indices in groups.values():
        first = contexts[indices[0]]
        code, run, opts = first.resolved.code, first.scene.run_options, first.sweep.period
        bm = BatchStroboscopicMap(
            code,
            rtol=run.rtol if run.rtol is not None else BATCH_DEFAULT_TOL,
            atol=run.atol if run.atol is not None else BATCH_DEFAULT_TOL,
            method=BATCH_ENGINE_METHODS[opts.engine],
        )
        res = [contexts[i].resolved for i in indices]
        try:
            r = bm.run(
                [[float(v) for v in x.y0] for x in res],
                [[float(x.params[k]) for k in code.params] for x in res],
                n=opts.recorded,
                transient=opts.transient + 1,
                t0=[float(x.t_span[0]) for x in res],
            )
        except UserInputError:  # e.g. one point's Omega <= 0: each point on its own then
            continue
        columns = _map_columns(code)
        for j, i in enumerate(indices):
            if r.status[j]:
                out[i] = ComputationError(STATUS_MESSAGES[int(r.status[j])])
            else:
                y = r.y[j][:, columns]
                out[i] = {"period": period_of_orbit(y, opts.max_period, opts.tol)}
    return out


register_reducer(
    Reducer(
        "period",
        lambda code, sweep: {
            "period": Variable(
                dtype="int16",
                attrs={
                    "long_name": "period of the stroboscopic map's attractor (forcing periods); "
                    f"0: none up to max_period = {sweep.period.max_period} (quasi-periodic or "
                    "chaotic)",
                    "units": "1",
                },
            )
        },
        _period,
        None,
        "the period of the stroboscopic map's orbit after a transient (0: none)",
        _period_batch,
    )
)


def _lyapunov_max(ctx: PointContext) -> dict:
    from ..numerics.lyapunov import lyapunov_spectrum

    opts, run, res = ctx.sweep.lyapunov, ctx.scene.run_options, ctx.resolved
    spec = lyapunov_spectrum(
        res.code,
        [float(res.params[k]) for k in res.code.params],
        [float(v) for v in res.y0],
        spectrum="level_set",
        intervals=opts.intervals,
        transient=opts.transient,
        t0=float(res.t_span[0]),
        rtol=run.rtol if run.rtol is not None else 1e-10,
        atol=run.atol if run.atol is not None else 1e-12,
    )
    lam, err = float(spec.exponents[0]), float(spec.errors[0])
    per_iteration, per_iteration_error = lam * spec.period, err * spec.period
    return {
        "lyapunov_max": lam,
        "lyapunov_max_error": err,
        "lyapunov_max_per_iteration": per_iteration,
        "lyapunov_max_per_iteration_error": per_iteration_error,
        "chaotic": int(
            per_iteration - 3 * per_iteration_error > linear_growth_rate(opts.intervals)
        ),
    }


def _lyapunov_variables(code: Any, sweep: Any) -> dict[str, Variable]:
    from ..numerics.lyapunov import UNITS_PER_ITERATION, UNITS_PER_TIME

    what = (
        "largest Lyapunov exponent on the integrals' level set (Benettin/QR, one QR per forcing "
        f"period, {sweep.lyapunov.intervals} periods after {sweep.lyapunov.transient})"
    )
    error = "its error bar (one standard error)"
    return {
        "lyapunov_max": Variable(attrs={"long_name": what, "units": UNITS_PER_TIME}),
        "lyapunov_max_error": Variable(attrs={"long_name": error, "units": UNITS_PER_TIME}),
        "lyapunov_max_per_iteration": Variable(
            attrs={"long_name": what, "units": UNITS_PER_ITERATION}
        ),
        "lyapunov_max_per_iteration_error": Variable(
            attrs={"long_name": error, "units": UNITS_PER_ITERATION}
        ),
        "chaotic": Variable(
            dtype="int8",
            attrs={
                "long_name": "1 when the largest exponent per iteration minus 3 error bars "
                "exceeds ln(N)/N (what linear growth over N iterations shows), else 0",
                "units": "1",
            },
        ),
    }


register_reducer(
    Reducer(
        "lyapunov_max",
        _lyapunov_variables,
        _lyapunov_max,
        None,
        "the largest Lyapunov exponent (per unit time and per forcing period) with its error "
        "bar: about 0 quasi-periodic or periodic, > 0 chaotic (time-periodic models, double)",
    )
)


def _regime(ctx: PointContext) -> dict:
    """Period, then the largest Lyapunov exponent: periodic, quasi-periodic or chaotic
    (:func:`chaplygin.numerics.regimes.attractor_regime`), from the scene's state or the one
    carried from the previous point."""
    from ..numerics.regimes import attractor_regime

    opts, run, res = ctx.sweep.regime, ctx.scene.run_options, ctx.resolved
    carried = ctx.start is not None
    y0 = ctx.start if carried else [float(v) for v in res.y0]
    transient = opts.transient
    if carried and opts.carried_transient is not None:
        transient = opts.carried_transient
    r = attractor_regime(
        res.code,
        [float(res.params[k]) for k in res.code.params],
        y0,
        transient=transient,
        recorded=opts.recorded,
        max_period=opts.max_period,
        tol=opts.tol,
        intervals=opts.intervals,
        lyapunov_transient=opts.lyapunov_transient,
        rtol=run.rtol if run.rtol is not None else 1e-10,
        atol=run.atol if run.atol is not None else 1e-12,
        t0=float(res.t_span[0]),
    )
    ctx.end = [float(v) for v in r.end]
    return {
        "regime": r.code,
        "period": r.period,
        "lyapunov_max_per_iteration": r.lyapunov,
        "lyapunov_max_per_iteration_error": r.lyapunov_error,
        "symmetric_copy": r.copy.code if r.copy is not None else -1,
        "copy_statistic": r.copy.statistic if r.copy is not None else math.nan,
        "carried": int(carried),
    }


def _regime_variables(code: Any, sweep: Any) -> dict[str, Variable]:
    from ..numerics.lyapunov import UNITS_PER_ITERATION
    from ..numerics.regimes import REGIMES
    from ..numerics.symmetry import COPY_RULE, symmetries_of

    o = sweep.regime
    names = ", ".join(f"{v} {k}" for k, v in REGIMES.items())
    symmetry = symmetries_of(code)
    copy_name = symmetry[0].name if symmetry else "none"
    return {
        "regime": Variable(
            dtype="int8",
            attrs={
                "long_name": f"regime of the map's attractor: {names} (periodic: closes within "
                f"{o.tol:g} with a period <= {o.max_period}; else the largest Lyapunov exponent "
                f"over {o.intervals} iterations: > ln(N)/N + 3 errors chaotic, < -(ln(N)/N + 3 "
                "errors) contracting (a periodic attractor not resolved), within ln(N)/N + 2 "
                "errors of 0 quasi-periodic, else undecided)",
                "units": "1",
            },
        ),
        "period": Variable(
            dtype="int16",
            attrs={
                "long_name": f"period (forcing periods; 0: none <= {o.max_period})",
                "units": "1",
            },
        ),
        "lyapunov_max_per_iteration": Variable(
            attrs={
                "long_name": "largest Lyapunov exponent on the level set (one tangent vector; "
                "NaN where the attractor is periodic: not measured)",
                "units": UNITS_PER_ITERATION,
            }
        ),
        "lyapunov_max_per_iteration_error": Variable(
            attrs={"long_name": "its error bar (one standard error)", "units": UNITS_PER_ITERATION}
        ),
        "symmetric_copy": Variable(
            dtype="int8",
            attrs={
                "long_name": f"copy reached under the symmetry {copy_name!r}: 0 canonical, 1 its "
                f"mirror, 2 self-symmetric, -1 undetermined or no symmetry ({COPY_RULE})",
                "units": "1",
            },
        ),
        "copy_statistic": Variable(
            attrs={
                "long_name": "mean of phi over the recorded points (the copy's sign)",
                "units": "1",
            }
        ),
        "carried": Variable(
            dtype="int8",
            attrs={
                "long_name": "1 when the start was carried from the previous grid point",
                "units": "1",
            },
        ),
    }


register_reducer(
    Reducer(
        "regime",
        _regime_variables,
        _regime,
        None,
        "periodic (with its period), quasi-periodic or chaotic by the period and then the largest "
        "Lyapunov exponent (per map iteration, with its error bar); the symmetric copy reached; "
        "usable with carry (starts carried along the grid lines)",
        carries=True,
    )
)


def _integrals(ctx: PointContext) -> dict:
    res = ctx.resolved
    p = np.asarray([float(res.params[k]) for k in res.code.params])
    y0 = np.asarray([float(v) for v in res.y0])
    values = res.code.numpy.integrals(float(res.t_span[0]), y0, p)
    return {"initial_integrals": np.asarray(values, dtype=float)}


register_reducer(
    Reducer(
        "integrals",
        lambda code, sweep: {
            "initial_integrals": Variable(
                ("integral",), attrs={"long_name": "the integrals at the initial state"}
            )
        },
        _integrals,
        lambda code: {"integral": list(code.integral_names)},
        "the integrals at the initial state (no integration: where a point exists is the "
        "region of motion; status 1 where the scene finds no state)",
    )
)


def _inertia(ctx: PointContext) -> tuple[list, Any, Any]:
    names = ("I1", "I2", "I3", "D", "b")
    if any(n not in ctx.resolved.params for n in names):
        raise UserInputError("this reducer needs the ball's I, D and b")
    p = ctx.resolved.params
    return [p["I1"], p["I2"], p["I3"]], p["D"], p["b"]


def _delta(ctx: PointContext) -> dict:
    import mpmath

    from ..numerics.separatrix import agreeing_digits, delta_closed_form, delta_ode, mu_of

    I, D, b = _inertia(ctx)
    digits = ctx.sweep.delta.digits
    with mpmath.workdps(digits + 10):
        I_m = [mpmath.mpf(v) for v in I]
        mu = mu_of(I_m, mpmath.mpf(D))
        closed = delta_closed_form(mu, mpmath.mpf(b), digits + 10)
    measured = delta_ode(I, D, b, digits)["delta"]
    return {
        "mu": float(mu),
        "delta_closed_form": float(closed),
        "delta_measured": float(measured),
        "delta_digits": float(agreeing_digits([measured], closed)),
    }


register_reducer(
    Reducer(
        "delta",
        lambda code, sweep: {
            "mu": Variable(attrs={"long_name": "mu = kap/lam (K01-3.7)", "units": "1"}),
            "delta_closed_form": Variable(
                attrs={"long_name": "Delta = pi b/ch(pi mu/2) (K01-3.7)", "units": "b"}
            ),
            "delta_measured": Variable(
                attrs={"long_name": "Delta from the full equations (Taylor)", "units": "b"}
            ),
            "delta_digits": Variable(
                attrs={"long_name": "digits on which measured and closed form agree", "units": "1"}
            ),
        },
        _delta,
        None,
        "Delta of K01 per tumble: closed form and measured (full equations)",
    )
)


def _frame_turn(ctx: PointContext) -> dict:
    from ..numerics.separatrix import frame_turn

    if "gyrostat" in ctx.resolved.effects:
        raise UserInputError(
            "reduce = frame_turn is the plain ball's on M || gamma; with the gyrostat the orbits "
            "of an energy are several: chaplygin.numerics.trace_geometry (trace_period along a "
            "gradient_line, examples/k01_turning.py) follows each family"
        )
    I, D, _ = _inertia(ctx)
    initial = ctx.scene.initial
    if initial.h is None:
        raise UserInputError("reduce = frame_turn needs initial.h (and parallel = true)")
    from ..numerics.inputs import parse_number

    h = float(parse_number(initial.h))
    C = float(parse_number(initial.C)) if initial.C is not None else 1.0
    rtol = ctx.scene.run_options.rtol or 1e-12
    T, phi = frame_turn([float(v) for v in I], float(D), h, C, rtol=float(rtol))
    return {"frame_turn_period": T, "frame_turn_phi": phi}


register_reducer(
    Reducer(
        "frame_turn",
        lambda code, sweep: {
            "frame_turn_period": Variable(
                attrs={"long_name": "period of gamma on M = C gamma (K01-2.34)", "units": "time"}
            ),
            "frame_turn_phi": Variable(
                attrs={
                    "long_name": "turn of the horizontal frame per period; the trace is "
                    "unbounded where it vanishes (K01-Fig6f)",
                    "units": "rad",
                }
            ),
        },
        _frame_turn,
        None,
        "period and frame turn on M || gamma (K01 Fig. 6f)",
    )
)


# ---------------------------------------------------------------------------------- the plan
@dataclass
class SweepPlan:
    """A sweep made concrete: axes, points, chunks, variables and fingerprint.

    Attributes
    ----------
    scene : Scene
        The scene as written (its ``sweep`` table included).
    base : dict
        The scene's data without ``sweep`` (each point replaces some keys of it).
    axes : list of (str, str, list)
        ``(key path, dimension name, values as given)``.
    coords : dict of str to numpy.ndarray
        Float64 coordinates of each axis.
    dims : tuple of str
    shape : tuple of int
    chunks : list of tuple of slice
        Region of each chunk in the grid.
    variables : dict of str to Variable
    extra_coords : dict of str to list
    code : ModelCode
        The model of the first point.
    fingerprint : dict of str to str
        Hashes of the scene, the grid and the code version.
    """

    scene: Any
    base: dict
    axes: list[tuple[str, str, list]]
    coords: dict[str, np.ndarray]
    dims: tuple[str, ...]
    shape: tuple[int, ...]
    chunks: list[tuple[slice, ...]]
    variables: dict[str, Variable]
    extra_coords: dict[str, list]
    code: Any
    fingerprint: dict[str, str]

    def points(self, region: tuple[slice, ...]) -> list[dict[str, Any]]:
        """The points of a chunk: key path -> value as given, in C order.

        Parameters
        ----------
        region : tuple of slice

        Returns
        -------
        list of dict
        """
        ranges = [range(s.start, s.stop) for s in region]
        out = []
        for index in product(*ranges):
            if len(self.dims) == 1 and self.dims[0] == "point":  # a list grid
                out.append({key: values[index[0]] for key, _, values in self.axes})
            else:
                out.append(
                    {key: values[i] for (key, _, values), i in zip(self.axes, index, strict=True)}
                )
        return out

    @property
    def total(self) -> str:
        """The fingerprint as one hex string."""
        return _sha(self.fingerprint)


def _sha(data: object) -> str:
    return hashlib.sha256(json.dumps(data, sort_keys=True, default=str).encode()).hexdigest()


def _axis_values(spec: Any, first_only: bool = False) -> list:
    import mpmath

    from ..numerics.inputs import parse_number

    if isinstance(spec, list):
        return list(spec[:1] if first_only else spec)

    def exact(value: object) -> Any:  # a TOML float as the decimal written
        return parse_number(repr(value) if isinstance(value, float) else value, 30)

    with mpmath.workdps(30):
        a, b = exact(spec.start), exact(spec.stop)
        if spec.num == 1 or first_only:
            return [mpmath.nstr(a, 30)]
        step = (b - a) / (spec.num - 1)
        return [mpmath.nstr(a + step * i, 30) for i in range(spec.num)]


def point_scene(base: Mapping, overrides: Mapping[str, Any], source: str | None = None) -> Any:
    """The scene of one point: ``base`` with dotted keys replaced.

    Parameters
    ----------
    base : mapping
        A scene's data (without ``sweep``).
    overrides : mapping of str to value
        ``"parameters.D" -> 4.39`` (values as a scene holds them).
    source : str, optional
        For messages.

    Returns
    -------
    Scene

    Raises
    ------
    SceneError
    """
    from .scene import Scene

    data = copy.deepcopy(dict(base))
    for key, value in overrides.items():
        root, name = key.split(".")
        data.setdefault(root, {})[name] = value
    return Scene.from_dict(data, source=source)


def plan_sweep(scene: Any, workers: int | None = None, store: Path | None = None) -> SweepPlan:
    """Resolve a scene's sweep: axes, chunks, variables, fingerprint; the first point is
    resolved to check the keys and load the model, and the grid's cost is checked
    (:func:`~chaplygin.verify.sweep_checks.check_grid_cost`) before its points are made.

    Parameters
    ----------
    scene : Scene
        With a ``[sweep]`` table.
    workers : int, optional
        Worker processes, for the time estimate (default: the usable CPUs).
    store : Path, optional
        Where the store goes, for the disk estimate.

    Returns
    -------
    SweepPlan

    Raises
    ------
    SceneError
        No ``[sweep]`` table, an unknown reducer, a key the scene refuses.
    UserInputError
        A grid beyond the machine (memory, disk, time), with the numbers.
    """
    from .scene import SceneError, did_you_mean, package_version

    sweep = scene.sweep
    if sweep is None:
        raise SceneError("the scene has no [sweep] table", scene.source, "sweep")
    for name in sweep.reduce:
        if name not in REDUCERS:
            raise SceneError(
                f"unknown reducer {name!r}; valid: {', '.join(REDUCERS)}"
                f"{did_you_mean(name, list(REDUCERS))}",
                scene.source,
                "sweep.reduce",
            )
    base = {k: v for k, v in scene.given.items() if k != "sweep"}
    carry_both = False
    if sweep.carry != "none":
        cannot = [n for n in sweep.reduce if not REDUCERS[n].carries]
        if cannot:
            able = ", ".join(n for n, r in REDUCERS.items() if r.carries)
            raise SceneError(
                f"carry follows an attractor along the grid lines: the reducers "
                f"{', '.join(cannot)} do not carry a state (use {able})",
                scene.source,
                "sweep.carry",
            )
        carry_both = sweep.carry == "both"  # a leading dimension: the two directions
    sizes = [len(v) if isinstance(v, list) else v.num for v in sweep.axes.values()]
    if carry_both:
        sizes.insert(0, len(CARRY_DIRECTIONS))
    if sweep.grid == "list":
        dims: tuple[str, ...] = ("point",)
        shape: tuple[int, ...] = (sizes[0],)
    else:
        dims = ((CARRY_KEY,) if carry_both else ()) + tuple(key.split(".")[1] for key in sweep.axes)
        shape = tuple(sizes)
    n_chunks = math.prod(shape[:-1]) * -(-shape[-1] // sweep.chunk)
    first = {key: _axis_values(v, first_only=True)[0] for key, v in sweep.axes.items()}
    try:
        first_scene = point_scene(base, first, scene.source)
        code = first_scene.resolve().code
    except SceneError as exc:
        # a point may lie where the scene finds no state (that point's status says so); the
        # scene as written must resolve then
        try:
            first_scene = point_scene(base, {}, scene.source)
            code = first_scene.resolve().code
        except SceneError:
            exc.args = (f"{exc.args[0]} (at the sweep's first point {first})",)
            raise exc from None
    per_point = math.inf  # the model is loaded: what resolving a point costs (least of 3)
    for _ in range(3):
        started = time.perf_counter()
        first_scene.resolve()
        per_point = min(per_point, time.perf_counter() - started)
    _check_axis_keys(scene, code)
    if "period" in sweep.reduce and sweep.period.forcing not in code.params:
        raise SceneError(
            f"reduce = period needs the forcing frequency {sweep.period.forcing!r}, a parameter "
            f"of {code.name} (params: {', '.join(code.params)}); set period.forcing",
            scene.source,
            "sweep.period.forcing",
        )
    if "regime" in sweep.reduce and "Omega" not in code.params:
        raise SceneError(
            f"reduce = regime needs a time-periodic model (the forcing frequency Omega); "
            f"{code.name} has {', '.join(code.params)}",
            scene.source,
            "sweep.reduce",
        )
    if "regime" in sweep.reduce and "Omega" not in code.params:
        raise SceneError(
            f"reduce = regime needs a time-periodic model (the forcing frequency Omega); "
            f"{code.name} has {', '.join(code.params)}",
            scene.source,
            "sweep.reduce",
        )
    variables: dict[str, Variable] = {}
    extra: dict[str, list] = {}
    for name in sweep.reduce:
        reducer = REDUCERS[name]
        variables.update(reducer.variables(code, sweep))
        if reducer.coords is not None:
            extra.update(reducer.coords(code))
    variables["status"] = Variable(
        dtype="int8",
        attrs={
            "long_name": "0 done, 1 input refused at this point, 2 computation failed",
            "units": "1",
        },
    )
    if sweep.refine is not None and (
        sweep.refine.variable not in variables or variables[sweep.refine.variable].dims
    ):
        raise SceneError(
            f"refine.variable {sweep.refine.variable!r} is not a number per point of this sweep; "
            f"valid: {', '.join(k for k, v in variables.items() if not v.dims)}",
            scene.source,
            "sweep.refine.variable",
        )
    points = math.prod(shape)
    per_point_bytes = 1 + sum(  # computed, and each variable with its extra dimensions
        np.dtype(var.dtype).itemsize * math.prod(len(extra[d]) for d in var.dims)
        for var in variables.values()
    )
    float_bytes = sum(
        8 * math.prod(len(extra[d]) for d in var.dims)
        for var in variables.values()
        if var.dtype.startswith("float")
    )
    n_workers = workers or usable_cpus()
    check_grid_cost(
        GridCost(
            points=points,
            chunks=n_chunks,
            memory=points * per_point_bytes + n_chunks * (CHUNK_OVERHEAD_BYTES + 32),
            disk=points * float_bytes,
            seconds=points * per_point / n_workers,
            workers=n_workers,
        ),
        store,
    )
    axes = [(key, key.split(".")[1], _axis_values(v)) for key, v in sweep.axes.items()]
    from ..numerics.inputs import parse_number

    coords = {name: np.asarray([float(parse_number(v)) for v in vals]) for _, name, vals in axes}
    if carry_both:
        axes.insert(0, (CARRY_KEY, CARRY_KEY, list(CARRY_DIRECTIONS)))
        coords[CARRY_KEY] = np.asarray(CARRY_DIRECTIONS)
    chunks = []
    outer = [range(n) for n in shape[:-1]]
    for index in product(*outer):
        for start in range(0, shape[-1], sweep.chunk):
            last = slice(start, min(start + sweep.chunk, shape[-1]))
            chunks.append(tuple(slice(i, i + 1) for i in index) + (last,))
    fingerprint = {
        "scene": _sha(base),
        "grid": _sha({"sweep": scene.given.get("sweep"), "axes": axes, "dims": dims}),
        "code": _sha(
            {"chaplygin": package_version(), "model_hash": code.hash, "format": STORE_FORMAT}
        ),
    }
    return SweepPlan(
        scene, base, axes, coords, dims, shape, chunks, variables, extra, code, fingerprint
    )


def _check_axis_keys(scene: Any, code: Any) -> None:
    """Refuse an axis that names no parameter, initial key or run setting of this model (it
    would make every point refused)."""
    from .scene import Initial, Run, SceneError, did_you_mean

    valid = {
        "parameters": list(code.parameter_groups) + list(code.params),
        "initial": list(Initial.model_fields) + list(code.state_groups),
        "run": [f.alias or n for n, f in Run.model_fields.items()],
    }
    for key in scene.sweep.axes:
        root, name = key.split(".")
        if name not in valid[root]:
            raise SceneError(
                f"axis {key!r}: {code.name} has no {root} key {name!r}; valid: "
                f"{', '.join(valid[root])}{did_you_mean(name, valid[root])}",
                scene.source,
                "sweep.axes",
            )


# ---------------------------------------------------------------------------- computation
def evaluate_point(
    base: Mapping, overrides: Mapping[str, Any], sweep: Any, source: str | None = None
) -> tuple[int, dict[str, Any]]:
    """Reduce one point.

    Parameters
    ----------
    base : mapping
        The scene's data without ``sweep``.
    overrides : mapping
        The point's keys.
    sweep : Sweep
    source : str, optional

    Returns
    -------
    (status, values) : (int, dict)
        ``STATUS_DONE`` with every variable, or ``STATUS_REFUSED`` / ``STATUS_FAILED`` with
        none (those points keep the fill values).
    """
    ctx = _point_context(base, overrides, sweep, source)
    return ctx if isinstance(ctx, tuple) else _reduce_point(ctx)


_FAILURES = (ComputationError, ArithmeticError, ValueError, RuntimeError)


def _point_context(
    base: Mapping, overrides: Mapping[str, Any], sweep: Any, source: str | None
) -> PointContext | tuple[int, dict]:
    """The point's resolved scene, or ``(status, {})`` when it cannot be resolved."""
    try:
        scene = point_scene(base, overrides, source)
        return PointContext(scene, scene.resolve(), sweep)
    except UserInputError:
        return STATUS_REFUSED, {}
    except _FAILURES:
        return STATUS_FAILED, {}


def _reduce_point(ctx: PointContext) -> tuple[int, dict[str, Any]]:
    """Run the sweep's reducers on one point (taking a chunk's batch results where present)."""
    try:
        values: dict[str, Any] = {}
        for name in ctx.sweep.reduce:
            done = ctx.batched.get(name)
            if isinstance(done, Exception):
                raise done
            values.update(done if done is not None else REDUCERS[name].run(ctx))
    except UserInputError:
        return STATUS_REFUSED, {}
    except _FAILURES:
        return STATUS_FAILED, {}
    return STATUS_DONE, values


def chunk_payload(plan: SweepPlan) -> dict[str, Any]:
    """What every task of a sweep receives besides its points (see :func:`compute_chunk`).

    Parameters
    ----------
    plan : SweepPlan

    Returns
    -------
    dict
        ``base``, ``sweep``, ``source``, ``variables``.
    """
    return {
        "base": plan.base,
        "sweep": plan.scene.sweep.model_dump(mode="json"),
        "source": plan.scene.source,
        "variables": {
            name: (_extra_shape(plan, var), var.dtype) for name, var in plan.variables.items()
        },
    }


def compute_chunk(payload: Mapping, points: Sequence[Mapping[str, Any]]) -> dict[str, np.ndarray]:
    """Reduce a chunk of points (a Dask task; runs on a worker).

    Parameters
    ----------
    payload : mapping
        ``base`` (scene data), ``sweep`` (the table as data), ``source``, ``variables``
        (name -> (extra shape, dtype)).
    points : sequence of mapping
        The points' keys.

    Returns
    -------
    dict of str to numpy.ndarray
        Each variable, shaped ``(len(points), *extra)``.
    """
    from .sweep_table import Sweep

    sweep = Sweep.model_validate(payload["sweep"])
    out = {
        name: np.full((len(points), *shape), -1 if dtype.startswith("int") else np.nan, dtype)
        for name, (shape, dtype) in payload["variables"].items()
    }
    if sweep.carry != "none":
        return _carried_chunk(payload, points, sweep, out)
    contexts = [
        _point_context(payload["base"], point, sweep, payload.get("source")) for point in points
    ]
    live = [c for c in contexts if isinstance(c, PointContext)]
    for name in sweep.reduce:
        batch = REDUCERS[name].batch
        if batch is not None and live:
            for ctx, result in zip(live, batch(live), strict=True):
                ctx.batched[name] = result
    for i, ctx in enumerate(contexts):
        status, values = ctx if isinstance(ctx, tuple) else _reduce_point(ctx)
        out["status"][i] = status
        for name, value in values.items():
            out[name][i] = value
    return out


def _carried_chunk(
    payload: Mapping, points: Sequence[Mapping[str, Any]], sweep: Any, out: dict[str, np.ndarray]
) -> dict[str, np.ndarray]:
    """One grid line with its starts carried: the points in the line's order (or reversed),
    each starting where the previous one ended (the first, and any after a point that failed
    or was refused, at the scene's state)."""
    direction = points[0].get(CARRY_KEY, sweep.carry) if points else sweep.carry
    order = range(len(points)) if direction == "forward" else range(len(points) - 1, -1, -1)
    carried = None
    for i in order:
        point = {k: v for k, v in points[i].items() if k != CARRY_KEY}
        ctx = _point_context(payload["base"], point, sweep, payload.get("source"))
        if isinstance(ctx, PointContext):
            ctx.start = carried
            status, values = _reduce_point(ctx)
            carried = ctx.end if status == STATUS_DONE else None
        else:
            (status, values), carried = ctx, None
        out["status"][i] = status
        for name, value in values.items():
            out[name][i] = value
    return out


# ---------------------------------------------------------------------------------- the store
def open_store(plan: SweepPlan, store: str | Path) -> Any:
    """Open the sweep's Zarr store, creating it (atomically) if absent, and repairing what
    :func:`~chaplygin.verify.sweep_store.inspect_store` found missing or damaged.

    Parameters
    ----------
    plan : SweepPlan
    store : str or Path

    Returns
    -------
    zarr.Group
        Opened for writing.

    Raises
    ------
    UserInputError
        ``store`` exists but is not a sweep store of ours, or was made by another scene, grid
        or code version (the message says which), or cannot be written.
    """
    check = inspect_store(plan, store)
    return repair_store(plan, check) if check.exists else create_store(plan, check)


# ------------------------------------------------------------------------------- the driver
def _client(
    scheduler: str | None, workers: int | None, connect_timeout: float = CONNECT_TIMEOUT_S
) -> tuple[Any, Any]:
    """A Dask client: of the scheduler at ``scheduler`` (checked by
    :func:`~chaplygin.verify.sweep_checks.probe_scheduler` first, then given
    ``connect_timeout`` to connect and ``connect_timeout`` more to show a worker), or of a
    LocalCluster of ``workers`` processes."""
    from distributed import Client, LocalCluster

    if scheduler:
        address = parse_scheduler_address(scheduler)
        probe_scheduler(address, connect_timeout)
        try:
            client = Client(address.url, timeout=f"{connect_timeout}s")
        except (OSError, TimeoutError, ValueError) as exc:
            reason = " ".join(str(exc).split())[:200]
            raise UserInputError(f"--scheduler {address.url}: cannot connect ({reason})") from None
        try:
            client.wait_for_workers(1, timeout=connect_timeout)
        except (OSError, TimeoutError) as exc:
            client.close()
            raise UserInputError(
                f"--scheduler {address.url}: the scheduler has no worker (none within "
                f"{connect_timeout:g} s); start some: dask worker {address.url}"
            ) from exc
        return client, None
    n = check_workers(workers) if workers is not None else usable_cpus()
    cluster = LocalCluster(
        n_workers=n,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=40,
    )
    return Client(cluster), cluster


def run_sweep(
    scene: Any,
    store: str | Path,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = False,
    client: Any = None,
    connect_timeout: float = CONNECT_TIMEOUT_S,
) -> dict:
    """Run (or continue) a scene's sweep into a Zarr store.

    Everything is checked before any work: the worker count, the scheduler's address, the
    grid's cost (:func:`~chaplygin.verify.sweep_checks.check_grid_cost`), the store (whose it
    is, and every chunk marked done against its digest:
    :func:`~chaplygin.verify.sweep_store.inspect_store`); the store is created or repaired
    only once a client is connected.

    Parameters
    ----------
    scene : Scene
        With a ``[sweep]`` table.
    store : str or Path
        The Zarr store (a folder); continued if it holds this sweep.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``); default a LocalCluster.
    workers : int, optional
        Worker processes of the LocalCluster (default: one per usable CPU; at most that).
    progress : bool
        Show a tqdm bar on stderr.
    client : distributed.Client, optional
        Use this client (tests); ``scheduler`` and ``workers`` are then ignored.
    connect_timeout : float
        Seconds to connect to ``scheduler``, to receive its handshake, and to see a worker.

    Returns
    -------
    dict
        ``chunks`` (total), ``computed`` (now), ``skipped`` (already stored, verified),
        ``repaired`` (chunks marked done that did not verify, computed again),
        ``recreated`` (arrays made again), ``points``, ``refused``, ``failed``, ``refined``
        (zeros, if asked).

    Raises
    ------
    SceneError
        The scene or its sweep is invalid.
    UserInputError
        The dask extra is missing, a bad worker count or scheduler address, a grid beyond
        the machine, or ``store`` belongs to another sweep or cannot be repaired.
    ComputationError
        A task failed on every worker it was tried on.
    """
    require_dask()
    if client is None and scheduler is not None:
        parse_scheduler_address(scheduler)  # a malformed address: before any work
    if client is None and scheduler is None and workers is not None:
        check_workers(workers)
    if not (isinstance(connect_timeout, int | float) and 0 < connect_timeout <= 3600):
        raise UserInputError(f"the connect timeout must be 0..3600 s, got {connect_timeout!r}")
    n_workers = workers or (usable_cpus() if scheduler is None else 1)
    plan = plan_sweep(scene, workers=n_workers, store=Path(store))
    check = inspect_store(plan, store)
    pending = [k for k in range(len(plan.chunks)) if k not in check.done]
    payload = chunk_payload(plan)
    own = client is None and bool(pending)
    cluster = None
    if own:
        client, cluster = _client(scheduler, workers, connect_timeout)
    try:
        group = repair_store(plan, check) if check.exists else create_store(plan, check)
        if pending:
            _compute(plan, group, payload, pending, client, progress, len(check.done))
    finally:
        if own:
            client.close()
            if cluster is not None:
                cluster.close()
    status = np.asarray(group["status"][...])
    summary = {
        "chunks": len(plan.chunks),
        "computed": len(pending),
        "skipped": len(check.done),
        "repaired": len(check.damaged),
        "recreated": sorted(check.recreate),
        "points": int(np.prod(plan.shape)),
        "refused": int((status == STATUS_REFUSED).sum()),
        "failed": int((status == STATUS_FAILED).sum()),
    }
    if scene.sweep.refine is not None:
        summary["refined"] = _refine(plan, group)
    return summary


def _compute(plan, group, payload, pending, client, progress, already) -> None:
    from distributed import as_completed
    from tqdm import tqdm

    from .scene import package_version

    payload_future = client.scatter(payload, broadcast=True)
    futures = {}
    for k in pending:
        region = plan.chunks[k]
        key = f"chaplygin-sweep-{plan.total[:12]}-{package_version()}-{k}"
        fut = client.submit(compute_chunk, payload_future, plan.points(region), key=key, retries=2)
        futures[fut] = k
    bar = tqdm(
        total=len(plan.chunks),
        initial=already,
        disable=not progress,
        unit="chunk",
        file=sys.stderr,
        desc="sweep",
    )
    try:
        for fut in as_completed(list(futures)):
            k = futures[fut]
            try:
                result = fut.result()
            except Exception as exc:
                raise ComputationError(f"chunk {k} failed: {type(exc).__name__}: {exc}") from None
            write_chunk(plan, group, k, result)
            bar.update(1)
            fut.release()
    finally:
        bar.close()


# ------------------------------------------------------------------------------ refinement
def zeros_along_axis(values: np.ndarray, coords: np.ndarray, wrap: float | None = None) -> list:
    """Brackets ``(a, b)`` of the axis where ``values`` changes sign through zero.

    Parameters
    ----------
    values, coords : 1-D arrays
    wrap : float, optional
        For an angle in ``(-wrap, wrap]``: a sign change by a jump larger than ``wrap`` is the
        angle wrapping round, not a zero.

    Returns
    -------
    list of (float, float)
    """
    out = []
    for i in range(len(values) - 1):
        a, b = values[i], values[i + 1]
        if not (np.isfinite(a) and np.isfinite(b)) or a * b > 0:
            continue
        if wrap is not None and abs(a - b) > wrap:
            continue
        out.append((float(coords[i]), float(coords[i + 1])))
    return out


def _refine(plan: SweepPlan, group: Any) -> list[str]:
    from scipy.optimize import brentq

    sweep = plan.scene.sweep
    opts = sweep.refine
    stored = group.attrs.get("refined")
    if stored is not None:
        return json.loads(stored)
    ((key, name, _),) = plan.axes
    values = np.asarray(group[opts.variable][...], dtype=float)
    units = plan.variables[opts.variable].attrs.get("units")
    brackets = zeros_along_axis(values, plan.coords[name], math.pi if units == "rad" else None)

    def f(x: float) -> float:
        status, out = evaluate_point(plan.base, {key: repr(x)}, sweep, plan.scene.source)
        if status != STATUS_DONE:
            raise ComputationError(f"refine: the point {key} = {x!r} could not be computed")
        return float(out[opts.variable])

    zeros = []
    for a, b in brackets:
        scale = max(abs(a), abs(b))
        root = brentq(f, a, b, xtol=scale * 10.0 ** (-opts.digits - 2), rtol=1e-15)
        zeros.append(f"{root:.{opts.digits + 2}g}")
    import zarr

    group.attrs["refined"] = json.dumps(zeros)
    zarr.consolidate_metadata(group.store)
    return zeros
