"""The sweep reducers of a stroboscopic map's dynamics: ``lyapunov_max`` (the largest
Lyapunov exponent with its error bar) and ``regime`` (periodic, quasi-periodic or chaotic),
each with its batch over a chunk's points in vector lanes (bit-identical to the point-by-point
reducer). Registered in :data:`~chaplygin.verify.sweep_reducers.REDUCERS`, which imports this
module between its period and integrals reducers (the registry's order)."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from ..derive.errors import ComputationError, UserInputError
from ..numerics.ball.regimes import linear_growth_rate
from .sweep_reducer_types import PointContext, Reducer, Variable, register_reducer

__all__: list[str] = []


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

    def key(ctx: PointContext) -> tuple | None:  # an autonomous model: _lyapunov_max says why
        code = ctx.resolved.code
        return None if code.forcing is None else _lyapunov_tolerances(ctx.scene.run_options)

    for (rtol, atol), indices, code, (P, Y, T0) in _chunk_groups(contexts, key):
        opts = contexts[indices[0]].sweep.lyapunov
        try:
            r = lyapunov_spectra(
                code, P, Y,
                intervals=opts.intervals,
                transient=opts.transient,
                t0=T0,
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

    opts, res = ctx.sweep.regime, ctx.resolved
    rtol, atol = _regime_tolerances(ctx.scene.run_options)
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
        rtol=rtol,
        atol=atol,
        t0=float(res.t_span[0]),
    )
    ctx.end = [float(v) for v in r.end]
    return _regime_values(r, carried)


def _regime_values(r: Any, carried: bool) -> dict:
    """The ``regime`` reducer's variables from an :class:`AttractorRegime`."""
    return {
        "regime": r.code,
        "period": r.period,
        "lyapunov_max_per_iteration": r.lyapunov,
        "lyapunov_max_per_iteration_error": r.lyapunov_error,
        "symmetric_copy": r.copy.code if r.copy is not None else -1,
        "copy_statistic": r.copy.statistic if r.copy is not None else math.nan,
        "carried": int(carried),
    }


def _regime_batch(contexts: list[PointContext]) -> list[Any]:
    """The ``regime`` reducer for a chunk whose starts are not carried: the points of one
    model and tolerances in one call of
    :func:`~chaplygin.numerics.ball.regimes.attractor_regimes` (the map and the exponents in
    vector lanes; each point's numbers bit-identical to :func:`_regime`'s)."""
    from ..numerics.ball.regimes import attractor_regimes

    out: list[Any] = [None] * len(contexts)

    def key(ctx: PointContext) -> tuple | None:  # carried starts run one after another
        if ctx.start is not None or ctx.resolved.code.forcing is None:
            return None
        return _regime_tolerances(ctx.scene.run_options)

    for (rtol, atol), indices, code, (P, Y, T0) in _chunk_groups(contexts, key):
        opts = contexts[indices[0]].sweep.regime
        try:
            found = attractor_regimes(
                code, P, Y, transient=opts.transient, recorded=opts.recorded,
                max_period=opts.max_period, tol=opts.tol, intervals=opts.intervals,
                lyapunov_transient=opts.lyapunov_transient, rtol=rtol, atol=atol, t0=T0,
            )  # fmt: skip
        except UserInputError:  # e.g. one point's settings: each point on its own then
            continue
        for j, i in enumerate(indices):
            r = found[j]
            if not isinstance(r, Exception):
                contexts[i].end = [float(v) for v in r.end]
                r = _regime_values(r, False)
            out[i] = r
    return out


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
        _regime_batch,
        carries=True,
    )
)


def _regime_tolerances(run: Any) -> tuple[float, float]:
    """The ``regime`` reducer's integration tolerances: the scene's, else 1e-10 and 1e-12."""
    return (run.rtol if run.rtol is not None else 1e-10,
            run.atol if run.atol is not None else 1e-12)  # fmt: skip


def _chunk_groups(contexts: list[PointContext], key: Any) -> Iterator[tuple]:
    """A chunk's points that a batch can take, grouped by model and ``key(ctx)`` (None: the
    point goes through the point-by-point reducer): per group the key, the points' indices,
    the model's code and their parameter rows, initial states and start times (double)."""
    groups: dict[tuple, list[int]] = {}
    for i, ctx in enumerate(contexts):
        k = key(ctx)
        if k is not None:
            groups.setdefault((ctx.resolved.code.hash, k), []).append(i)
    for (_, k), indices in groups.items():
        res = [contexts[i].resolved for i in indices]
        code = res[0].code
        rows = (
            [[float(x.params[n]) for n in code.params] for x in res],
            [[float(v) for v in x.y0] for x in res],
            [float(x.t_span[0]) for x in res],
        )
        yield k, indices, code, rows
