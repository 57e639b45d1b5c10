"""The stroboscopic map's throughput: BM20's map iterated by the batch lanes, against heyoka's
batch mode when it is installed; and the largest Lyapunov exponent per point, one point per call
and in the lanes of the variational batch."""

from __future__ import annotations

import math
import os
import time
from typing import Any

import numpy as np

from ..derive.errors import UserInputError
from ..numerics.ball.map_coordinates import state_from_reduced
from ..numerics.code import load_model_code
from ..numerics.integrate import integrate
from .bench_timing import peers_available

__all__ = [
    "MAP_BENCH_PARAMS",
    "MAP_BENCH_START",
    "lyapunov_throughput",
    "map_throughput",
    "regime_throughput",
    "jacobian_throughput",
]


# ------------------------------------------------------- the stroboscopic map's throughput
#: BM20 Fig. 5's system (the Fig. 6 chart's centre): (I1, I2, I3, D, J_off, delta, K1, K2, K3,
#: Omega) and the start G = 3, (z, l, g) = (0.5, 1, 1).
MAP_BENCH_PARAMS = (4.0, 3.0, 2.0, 4.385, 0.0, 2.0, -6.0, -3.0, -9.0, 1.07)
MAP_BENCH_START = ((0.5, 1.0, 1.0), 3.0)


def _heyoka_map_rows(code, p, y0, periods: int, rtol: float) -> dict[str, Any]:
    """heyoka on the same right-hand side (the model's sympy expressions), one point and a batch
    of 4; seconds per period per point, wall and CPU."""
    import heyoka as hy
    import sympy

    from ..derive.systems import build_model

    model = build_model("chaplygin_ball", code.effects)
    state = [s for _, group in model.state_groups for s in group]
    hvars = hy.make_vars(*[str(s) for s in state])
    subs = {s: v for s, v in zip(state, hvars, strict=True)}
    params = [s for spec in model.parameters for s in spec.symbols]
    subs.update({s: hy.par[i] for i, s in enumerate(params)})
    subs[model.time] = hy.time
    system = [
        (v, hy.from_sympy(sympy.sympify(e), subs))
        for v, e in zip(hvars, model.rhs_expanded, strict=True)
    ]
    pvals = [p[code.params.index(str(s))] for s in params]
    grid = np.arange(periods + 1) * (2 * math.pi / p[code.params.index("Omega")])
    ta = hy.taylor_adaptive(system, list(y0), pars=pvals, tol=rtol)
    wall, cpu = time.perf_counter(), time.process_time()
    out = ta.propagate_grid(grid)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    batch = 4
    tb = hy.taylor_adaptive_batch(
        system, np.repeat(np.asarray(y0)[:, None], batch, 1),
        pars=np.repeat(np.asarray(pvals)[:, None], batch, 1), tol=rtol,
    )  # fmt: skip
    bwall, bcpu = time.perf_counter(), time.process_time()
    tb.propagate_grid(np.repeat(grid[:, None], batch, 1))
    bwall, bcpu = time.perf_counter() - bwall, time.process_time() - bcpu
    return {
        "heyoka_one": (wall / periods, cpu / periods),
        "heyoka_batch4": (bwall / periods / batch, bcpu / periods / batch),
        "heyoka_steps_per_period": int(out[3]) / periods,
        "traj": np.asarray(out[5]),
    }


def map_throughput(
    periods: int = 700, repeats: int = 5, rtol: float = 1e-12, peers: bool = True
) -> dict[str, Any]:
    """Microseconds per forcing period per point of BM20's stroboscopic map (issue 14): our
    Taylor integrator (one point per call), our compiled batch map
    (:class:`~chaplygin.numerics.dynamics.batch_map.BatchStroboscopicMap`, 1, 4 and 16 points per
    call; DOP853 rows ``ours_batch<n>``, Taylor rows ``ours_taylor_batch<n>``)
    and heyoka (one point, batch of 4) when installed, in one run.

    Medians of ``repeats`` runs, interleaved so that the machine's load affects all alike; wall
    time and CPU time (``time.process_time``: less sensitive to other processes on a loaded
    machine). The map is sampled every period, as the sweep's ``period`` reducer does.

    Parameters
    ----------
    periods : int, default 700
        Forcing periods per run (the Fig. 6 chart: 500 transient + 200 recorded).
    repeats : int, default 5
    rtol : float, default 1e-12
        Tolerance of every integrator (atol the same).
    peers : bool, default True
        Include heyoka when it is installed.

    Returns
    -------
    dict
        ``<row>_us`` and ``<row>_cpu_us`` per row; the batch map's steps, rejected steps and
        right-hand-side evaluations per period, the Taylor batch's steps per period and its
        highest order, heyoka's steps per period; the largest
        difference of the first 10 periods from the Taylor run; the load average before and
        after; ratios to heyoka's batch mode.

    Raises
    ------
    UserInputError
        ``periods < 10`` or ``repeats < 1``.
    """
    from ..numerics.dynamics.batch_map import BatchStroboscopicMap, batch_map_available

    if periods < 10 or repeats < 1:
        raise UserInputError("map_throughput needs periods >= 10 and repeats >= 1")
    code = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
    p = list(MAP_BENCH_PARAMS)
    y0 = [float(v) for v in state_from_reduced(*MAP_BENCH_START, [0] * 6, code.state)]
    tau = 2 * math.pi / p[-1]
    t_eval = [k * tau for k in range(periods + 1)]
    have_heyoka = peers and peers_available()["heyoka"]
    have_batch = batch_map_available(code)
    have_taylor_batch = batch_map_available(code, "taylor")
    runs: dict[str, list[float]] = {}
    row: dict[str, Any] = {"periods": periods, "repeats": repeats, "rtol": rtol}
    row["load_before"] = os.getloadavg()[0]

    def record(name: str, wall: float, cpu: float, per: int = 1) -> None:
        runs.setdefault(f"{name}_us", []).append(wall / periods / per * 1e6)
        runs.setdefault(f"{name}_cpu_us", []).append(cpu / periods / per * 1e6)

    integrate(code, y0, (0, 2 * tau), p, method="taylor", rtol=rtol, atol=rtol)  # warm
    for _ in range(repeats):
        wall, cpu = time.perf_counter(), time.process_time()
        r = integrate(code, y0, (0, periods * tau), p, method="taylor", rtol=rtol, atol=rtol,
                      t_eval=t_eval)  # fmt: skip
        record("ours_taylor_c", time.perf_counter() - wall, time.process_time() - cpu)
        taylor = np.asarray(r.y, dtype=float).T
        if have_batch:
            bm = BatchStroboscopicMap(code, rtol=rtol, atol=rtol)
            for n in (1, 4, 16):
                cpu = time.process_time()
                b = bm.run(np.repeat([y0], n, 0), np.repeat([p], n, 0), n=periods + 1)
                record(f"ours_batch{n}", b.wall_s, time.process_time() - cpu, n)
        if have_taylor_batch:
            tbm = BatchStroboscopicMap(code, rtol=rtol, atol=rtol, method="taylor")
            for n in (1, 4, 16):
                cpu = time.process_time()
                tb = tbm.run(np.repeat([y0], n, 0), np.repeat([p], n, 0), n=periods + 1)
                record(f"ours_taylor_batch{n}", tb.wall_s, time.process_time() - cpu, n)
        if have_heyoka:
            peer = _heyoka_map_rows(code, p, y0, periods, rtol)
            for name in ("heyoka_one", "heyoka_batch4"):
                runs.setdefault(f"{name}_us", []).append(peer[name][0] * 1e6)
                runs.setdefault(f"{name}_cpu_us", []).append(peer[name][1] * 1e6)
    row.update({name: float(np.median(values)) for name, values in runs.items()})
    if have_batch:
        row["ours_batch_steps_per_period"] = float(b.steps[0]) / periods
        row["ours_batch_rejected_per_period"] = float(b.rejected[0]) / periods
        row["ours_batch_rhs_per_period"] = float(b.evaluations[0]) / periods
        row["ours_batch_vs_taylor_first_10_periods"] = float(
            np.abs(b.y[0][:11] - taylor[:11]).max()
        )
    if have_taylor_batch:
        row["ours_taylor_batch_steps_per_period"] = float(tb.steps[0]) / periods
        row["ours_taylor_batch_max_order"] = int(tb.orders[0, 1])
        row["ours_taylor_batch_vs_taylor_first_10_periods"] = float(
            np.abs(tb.y[0][:11] - taylor[:11]).max()
        )
    if have_heyoka:
        row["heyoka_steps_per_period"] = peer["heyoka_steps_per_period"]
        row["heyoka_vs_taylor_first_10_periods"] = float(
            np.abs(peer["traj"][:11] - taylor[:11]).max()
        )
        if have_batch:
            for n in (4, 16):
                row[f"ratio_batch{n}_to_heyoka_batch4_wall"] = (
                    row[f"ours_batch{n}_us"] / row["heyoka_batch4_us"]
                )
                row[f"ratio_batch{n}_to_heyoka_batch4_cpu"] = (
                    row[f"ours_batch{n}_cpu_us"] / row["heyoka_batch4_cpu_us"]
                )
    row["load_after"] = os.getloadavg()[0]
    return row


# ------------------------------------------------------- the Lyapunov exponent's throughput
def lyapunov_throughput(
    intervals: int = 2000, transient: int = 200, repeats: int = 3, points: int = 16
) -> dict[str, Any]:
    """Seconds per point of the largest Lyapunov exponent of BM20's map (issue 26; the sweep's
    ``lyapunov_max`` at its defaults: 2000 forcing periods after 200, one tangent vector,
    rtol 1e-10, atol 1e-12): one point per call
    (:func:`~chaplygin.numerics.dynamics.lyapunov.lyapunov_spectrum`, row ``ours_one``) and
    ``points`` points per call
    (:func:`~chaplygin.numerics.dynamics.lyapunov_batch.lyapunov_spectra`) in vector lanes
    (``ours_lanes``) and one after another (``ours_serial``), the same points throughout: the
    Fig. 6 chart's centre with ``d`` and ``Omega`` spread over the chart; the three-vector
    spectrum the reducer computed before (``ours_one_3_vectors``) for comparison. Medians of
    ``repeats`` interleaved runs, wall and CPU time.

    Parameters
    ----------
    intervals, transient : int
        Forcing periods measured and discarded.
    repeats : int
    points : int
        Points of the batched rows.

    Returns
    -------
    dict
        ``<row>_s`` and ``<row>_cpu_s`` per point; whether the lanes ran; the ratio of the
        lanes to one point per call; the 101 x 101 chart's CPU time at the lanes' rate
        (``chart_101x101_core_min``) and on 2 cores (``chart_101x101_2_cores_min``).

    Raises
    ------
    UserInputError
        ``intervals < 10``, ``repeats < 1`` or ``points < 1``.
    """
    from ..numerics.dynamics.lyapunov import lyapunov_spectrum
    from ..numerics.dynamics.lyapunov_batch import lyapunov_spectra

    if intervals < 10 or repeats < 1 or points < 1:
        raise UserInputError("lyapunov_throughput needs intervals >= 10, repeats, points >= 1")
    code, P, Y = _chart_points(points)
    settings = {"intervals": intervals, "transient": transient, "rtol": 1e-10, "atol": 1e-12}
    runs: dict[str, list[float]] = {}
    row: dict[str, Any] = {**settings, "repeats": repeats, "points": points}
    row["load_before"] = os.getloadavg()[0]

    def timed(name: str, per: int, call) -> Any:
        wall, cpu = time.perf_counter(), time.process_time()
        out = call()
        runs.setdefault(f"{name}_s", []).append((time.perf_counter() - wall) / per)
        runs.setdefault(f"{name}_cpu_s", []).append((time.process_time() - cpu) / per)
        return out

    serial = {**settings, "count": 1, "lockstep": False}
    lyapunov_spectra(code, P[:2], Y[:2], count=1, intervals=10, transient=0)  # compiled first
    for _ in range(repeats):
        for name, count in (("ours_one", 1), ("ours_one_3_vectors", None)):
            timed(name, points, lambda count=count: [
                lyapunov_spectrum(code, p, y, count=count, **settings)
                for p, y in zip(P, Y, strict=True)
            ])  # fmt: skip
        lanes = timed("ours_lanes", points,
                      lambda: lyapunov_spectra(code, P, Y, count=1, **settings))  # fmt: skip
        timed("ours_serial", points, lambda: lyapunov_spectra(code, P, Y, **serial))
    row.update({name: float(np.median(values)) for name, values in runs.items()})
    row["lanes_ran"] = bool(lanes.lockstep)
    row["failed_points"] = int((lanes.status != 0).sum())
    row["ratio_lanes_to_one"] = row["ours_lanes_s"] / row["ours_one_s"]
    row["ratio_lanes_to_one_3_vectors"] = row["ours_lanes_s"] / row["ours_one_3_vectors_s"]
    row["chart_101x101_core_min"] = row["ours_lanes_cpu_s"] * 101 * 101 / 60
    row["chart_101x101_2_cores_min"] = row["chart_101x101_core_min"] / 2
    row["load_after"] = os.getloadavg()[0]
    return row


def regime_throughput(repeats: int = 3, points: int = 16, quick: bool = False) -> dict[str, Any]:
    """Seconds per point of the ``regime`` reducer on BM20's map at its defaults (2000
    transient periods, 600 recorded, the largest exponent over 2000 more where no period
    closes; rtol 1e-10, atol 1e-12): one point per call
    (:func:`~chaplygin.numerics.ball.regimes.attractor_regime`, row ``ours_one``) and
    ``points`` points per call (:func:`~chaplygin.numerics.ball.regimes.attractor_regimes`,
    the map and the exponents in vector lanes, row ``ours_lanes``); the points of
    :func:`lyapunov_throughput` (``d`` and ``Omega`` spread over the Fig. 6 chart). Medians of
    ``repeats`` interleaved runs, wall and CPU time.

    Parameters
    ----------
    repeats : int
    points : int
    quick : bool
        200 transient, 100 recorded and 200 exponent periods instead of the defaults.

    Returns
    -------
    dict
        ``<row>_s`` and ``<row>_cpu_s`` per point, the ratio, how many points were periodic,
        and the 101 x 101 chart's time on 2 cores at the lanes' rate.

    Raises
    ------
    UserInputError
        ``repeats < 1`` or ``points < 1``.
    """
    from ..numerics.ball.regimes import attractor_regime, attractor_regimes

    if repeats < 1 or points < 1:
        raise UserInputError("regime_throughput needs repeats >= 1 and points >= 1")
    code, P, Y = _chart_points(points)
    settings: dict[str, Any] = {"transient": 2000, "recorded": 600, "intervals": 2000}
    if quick:
        settings = {"transient": 200, "recorded": 100, "intervals": 200, "max_period": 32}
    runs: dict[str, list[float]] = {}
    row: dict[str, Any] = {**settings, "repeats": repeats, "points": points}
    row["load_before"] = os.getloadavg()[0]
    attractor_regimes(code, P[:1], Y[:1], **{**settings, "intervals": 10})  # compiled first
    for _ in range(repeats):
        for name, call in (
            ("ours_one", lambda: [attractor_regime(code, p, y, **settings)
                                  for p, y in zip(P, Y, strict=True)]),  # fmt: skip
            ("ours_lanes", lambda: attractor_regimes(code, P, Y, **settings)),
        ):
            wall, cpu = time.perf_counter(), time.process_time()
            found = call()
            runs.setdefault(f"{name}_s", []).append((time.perf_counter() - wall) / points)
            runs.setdefault(f"{name}_cpu_s", []).append((time.process_time() - cpu) / points)
    row.update({name: float(np.median(values)) for name, values in runs.items()})
    row["periodic_points"] = sum(1 for r in found if getattr(r, "period", 0) > 0)
    row["ratio_lanes_to_one"] = row["ours_lanes_s"] / row["ours_one_s"]
    row["chart_101x101_2_cores_min"] = row["ours_lanes_cpu_s"] * 101 * 101 / 60 / 2
    row["load_after"] = os.getloadavg()[0]
    return row


def jacobian_throughput(repeats: int = 3, points: int = 64) -> dict[str, Any]:
    """Seconds per point of BM20's map Jacobian (the state and ``Phi`` over one forcing period,
    rtol 1e-10, atol 1e-12, the points of :func:`lyapunov_throughput`): one call per point
    (:func:`~chaplygin.numerics.dynamics.variational.flow_with_jacobian`, row ``ours_one``),
    ``points`` per call in vector lanes
    (:func:`~chaplygin.numerics.dynamics.variational.flow_jacobians`, ``ours_lanes``) and one
    after another in that call (``ours_serial``). Medians of ``repeats`` interleaved runs.

    Parameters
    ----------
    repeats, points : int

    Returns
    -------
    dict
        ``<row>_s`` per point and the ratio of the lanes to one call per point.

    Raises
    ------
    UserInputError
        ``repeats < 1`` or ``points < 1``.
    """
    from ..numerics.dynamics.variational import flow_jacobians, flow_with_jacobian

    if repeats < 1 or points < 1:
        raise UserInputError("jacobian_throughput needs repeats >= 1 and points >= 1")
    code, P, Y = _chart_points(points)
    tau = 2 * np.pi / P[:, 9]
    tol = {"rtol": 1e-10, "atol": 1e-12}
    flow_jacobians(code, P[:2], Y[:2], 0.0, tau[:2], **tol)  # compiled first
    runs: dict[str, list[float]] = {}
    calls = (
        ("ours_one", lambda: [flow_with_jacobian(code, P[j], Y[j], 0.0, tau[j], **tol)
                              for j in range(points)]),
        ("ours_lanes", lambda: flow_jacobians(code, P, Y, 0.0, tau, **tol)),
        ("ours_serial", lambda: flow_jacobians(code, P, Y, 0.0, tau, lockstep=False, **tol)),
    )  # fmt: skip
    for _ in range(repeats):
        for name, call in calls:
            wall = time.perf_counter()
            call()
            runs.setdefault(f"{name}_s", []).append((time.perf_counter() - wall) / points)
    row: dict[str, Any] = {"repeats": repeats, "points": points, **tol}
    row.update({name: float(np.median(values)) for name, values in runs.items()})
    row["ratio_lanes_to_one"] = row["ours_lanes_s"] / row["ours_one_s"]
    return row


#: The Taylor batch map's tolerances tried for :func:`taylor_map_equal_accuracy`, tightest first.
EQUAL_ACCURACY_RTOLS = (1e-12, 1e-11, 1e-10, 1e-9, 1e-8)


def taylor_map_equal_accuracy(periods: int = 200, repeats: int = 3, points: int = 16,
                              rtol: float = 1e-12) -> dict[str, Any]:  # fmt: skip
    """Microseconds per forcing period per point of BM20's map, the Taylor batch map in vector
    lanes against the DOP853 lanes at equal accuracy (issue 26): the DOP853 batch at ``rtol``,
    its error the largest over the first 10 periods against a Taylor run at rtol 1e-15; the
    Taylor batch at the loosest of :data:`EQUAL_ACCURACY_RTOLS` whose error is not larger.
    ``points`` copies of the bench's start per call; best of ``repeats`` calls.

    Parameters
    ----------
    periods, repeats, points : int
    rtol : float
        The DOP853's tolerance (atol the same).

    Returns
    -------
    dict
        ``dop853_us``, ``dop853_error``, ``taylor_rtol``, ``taylor_us``, ``taylor_error``,
        the Taylor time at every tolerance tried (``taylor_<rtol>_us``) and
        ``ratio_taylor_to_dop853``.

    Raises
    ------
    UserInputError
        ``periods < 10``, ``repeats < 1`` or ``points < 1``.
    """
    from ..numerics.dynamics.batch_map import BatchStroboscopicMap

    if periods < 10 or repeats < 1 or points < 1:
        raise UserInputError("taylor_map_equal_accuracy needs periods >= 10, repeats, points >= 1")
    code = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
    p = list(MAP_BENCH_PARAMS)
    y0 = [float(v) for v in state_from_reduced(*MAP_BENCH_START, [0] * 6, code.state)]
    tau = 2 * math.pi / p[-1]
    ref = integrate(code, y0, (0, 10 * tau), p, method="taylor", rtol=1e-15, atol=1e-15,
                    t_eval=[k * tau for k in range(11)])  # fmt: skip
    ref_y = np.asarray(ref.y, dtype=float).T

    def measure(tol: float, method: str) -> tuple[float, float]:
        bm = BatchStroboscopicMap(code, rtol=tol, atol=tol, method=method)
        walls, r = [], None
        for _ in range(repeats):
            r = bm.run(np.repeat([y0], points, 0), np.repeat([p], points, 0), n=periods + 1)
            walls.append(r.wall_s / periods / points * 1e6)
        return min(walls), float(np.abs(r.y[0][:11] - ref_y).max())

    row: dict[str, Any] = {"periods": periods, "points": points, "rtol": rtol}
    row["dop853_us"], row["dop853_error"] = measure(rtol, "dop853")
    for tol in EQUAL_ACCURACY_RTOLS:
        us, error = measure(tol, "taylor")
        row[f"taylor_{tol:g}_us"] = us
        if error <= row["dop853_error"]:
            row["taylor_rtol"], row["taylor_us"], row["taylor_error"] = tol, us, error
    if "taylor_us" in row:
        row["ratio_taylor_to_dop853"] = row["taylor_us"] / row["dop853_us"]
    return row


def _chart_points(points: int) -> tuple[Any, np.ndarray, np.ndarray]:
    """BM20's model and ``points`` points of the Fig. 6 chart (``d`` and ``Omega`` spread over
    it) from the map bench's start: the points of the Lyapunov, regime and Jacobian rows."""

    code = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
    y0 = [float(v) for v in state_from_reduced(*MAP_BENCH_START, [0] * 6, code.state)]
    P = np.tile(np.array(MAP_BENCH_PARAMS), (points, 1))
    P[:, 3] = np.linspace(4.37, 4.39, points)  # d over the Fig. 6 chart
    P[:, 9] = np.linspace(1.064, 1.08, points)[::-1]  # Omega
    return code, P, np.tile(np.array(y0), (points, 1))
