"""What a point of a sweep is reduced to: :class:`Reducer` and :data:`REDUCERS` (final state,
drift, contact trace, period, largest Lyapunov exponent, regime, integrals, Δ, frame turn), each
declaring its variables and computing them from a :class:`PointContext`; the period reducer's
batched lanes."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..arith import detmath
from ..derive.errors import ComputationError, UserInputError
from ..numerics.ball.regimes import linear_growth_rate

__all__ = [
    "REDUCERS",
    "Reducer",
    "Variable",
    "PointContext",
    "register_reducer",
    "period_of_orbit",
    "UNBOUNDED_GROWTH",
    "BATCH_DEFAULT_TOL",
    "BATCH_ENGINE_METHODS",
]

#: Relative radius growth above which a contact trace counts as unbounded (second half of the
#: run against the first: a drift at constant speed gives 2, a bounded trace about 1).
UNBOUNDED_GROWTH = 1.5



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
    from ..numerics.dynamics.batch_map import batch_map_available
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
    through :class:`~chaplygin.numerics.dynamics.batch_map.BatchStroboscopicMap`, one call per
    model and tolerances; the others are left to :func:`_period`."""
    from ..numerics.dynamics.batch_map import STATUS_MESSAGES, BatchStroboscopicMap

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
    from ..numerics.dynamics.lyapunov import lyapunov_spectrum

    opts, run, res = ctx.sweep.lyapunov, ctx.scene.run_options, ctx.resolved
    spec = lyapunov_spectrum(
        res.code,
        [float(res.params[k]) for k in res.code.params],
        [float(v) for v in res.y0],
        spectrum="level_set",
        intervals=opts.intervals,
        transient=opts.transient,
        t0=float(res.t_span[0]),
        rtol=_lyapunov_tolerances(run)[0],
        atol=_lyapunov_tolerances(run)[1],
        count=1,
    )
    return _lyapunov_values(spec, opts.intervals)


def _lyapunov_tolerances(run: Any) -> tuple[float, float]:
    return (
        run.rtol if run.rtol is not None else 1e-10,
        run.atol if run.atol is not None else 1e-12,
    )


def _lyapunov_values(spec: Any, intervals: int) -> dict:
    """The reducer's values from the spectrum (one exponent) of a point."""
    lam, err = float(spec.exponents[0]), float(spec.errors[0])
    per_iteration, per_iteration_error = lam * spec.period, err * spec.period
    return {
        "lyapunov_max": lam,
        "lyapunov_max_error": err,
        "lyapunov_max_per_iteration": per_iteration,
        "lyapunov_max_per_iteration_error": per_iteration_error,
        "chaotic": int(per_iteration - 3 * per_iteration_error > linear_growth_rate(intervals)),
    }


def _lyapunov_max_batch(contexts: list[PointContext]) -> list[Any]:
    """The ``lyapunov_max`` reducer for a chunk: the points of one model and tolerances in one
    call of :func:`~chaplygin.numerics.dynamics.lyapunov_batch.lyapunov_spectra` (vector lanes;
    each point's numbers bit-identical to :func:`_lyapunov_max`'s)."""
    from ..numerics.dynamics.lyapunov_batch import lyapunov_spectra

    out: list[Any] = [None] * len(contexts)
    groups: dict[tuple, list[int]] = {}
    for i, ctx in enumerate(contexts):
        code = ctx.resolved.code
        if code.forcing is None:
            continue  # an autonomous model: _lyapunov_max says what is missing
        key = (code.hash, *_lyapunov_tolerances(ctx.scene.run_options))
        groups.setdefault(key, []).append(i)
    for (_, rtol, atol), indices in groups.items():
        first = contexts[indices[0]]
        code, opts = first.resolved.code, first.sweep.lyapunov
        res = [contexts[i].resolved for i in indices]
        try:
            r = lyapunov_spectra(
                code,
                [[float(x.params[k]) for k in code.params] for x in res],
                [[float(v) for v in x.y0] for x in res],
                intervals=opts.intervals,
                transient=opts.transient,
                t0=[float(x.t_span[0]) for x in res],
                rtol=rtol,
                atol=atol,
                count=1,
            )
        except UserInputError:  # e.g. one point's settings: each point on its own then
            continue
        for j, i in enumerate(indices):
            spec = r.spectra[j]
            out[i] = ComputationError(r.messages[j]) if spec is None else _lyapunov_values(
                spec, opts.intervals
            )
    return out


def _lyapunov_variables(code: Any, sweep: Any) -> dict[str, Variable]:
    from ..numerics.dynamics.lyapunov import UNITS_PER_ITERATION, UNITS_PER_TIME

    what = (
        "largest Lyapunov exponent on the integrals' level set (Benettin/QR with one tangent "
        f"vector, one QR per forcing period, {sweep.lyapunov.intervals} periods after "
        f"{sweep.lyapunov.transient})"
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
        _lyapunov_max_batch,
    )
)


def _regime(ctx: PointContext) -> dict:
    """Period, then the largest Lyapunov exponent: periodic, quasi-periodic or chaotic
    (:func:`chaplygin.numerics.ball.regimes.attractor_regime`), from the scene's state or the one
    carried from the previous point."""
    from ..numerics.ball.regimes import attractor_regime

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
    from ..numerics.ball.regimes import REGIMES
    from ..numerics.ball.symmetry import COPY_RULE, symmetries_of
    from ..numerics.dynamics.lyapunov import UNITS_PER_ITERATION

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

    from ..numerics.ball.separatrix import agreeing_digits, delta_closed_form, delta_ode, mu_of

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
    from ..numerics.ball.frame_turn import frame_turn

    if "gyrostat" in ctx.resolved.effects:
        raise UserInputError(
            "reduce = frame_turn is the plain ball's on M || gamma; with the gyrostat the orbits "
            "of an energy are several: chaplygin.numerics.ball.trace_geometry (trace_period "
            "along a gradient_line, examples/k01_turning.py) follows each family"
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


