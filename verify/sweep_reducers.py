"""What a point of a sweep is reduced to: :class:`Reducer` and :data:`REDUCERS` (final state,
drift, contact trace, period, largest Lyapunov exponent, regime, integrals, Δ, frame turn), each
declaring its variables and computing them from a :class:`PointContext`; the period reducer's
batched lanes."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..arith import detmath
from ..derive.errors import ComputationError, UserInputError
from .sweep_reducer_types import REDUCERS, PointContext, Reducer, Variable, register_reducer

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


# the map-dynamics reducers (lyapunov_max, regime) live in their own module; imported
# here so that the registry keeps its order
from . import sweep_reducers_maps  # noqa: E402, F401, I001


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


