"""Cost per forcing period per point of BM20's stroboscopic map (issue 14 §4), side by side
with heyoka (one point at a time, and its batch mode with 4 points), in one run: our Taylor
integrator (one point per call) and our compiled batch map (DOP853 in C, N points per call,
:class:`chaplygin.numerics.batch_map.BatchStroboscopicMap`). Each timing is the median of
``REPEATS`` runs, interleaved so that the machine's load affects all alike; wall time and
CPU time (``time.process_time``, less sensitive to other processes on a loaded machine) are
both reported.

BM20 Fig. 5's system: I = diag(4, 3, 2), K = (-6, -3, -9), d = 4.385, J = 0, delta = 2,
Omega = 1.07, G = 3 (z = 0.5, l = g = 1); double precision, rtol = 1e-12; the map is sampled at
every period (as the sweep's ``period`` reducer does). heyoka gets the same right-hand side
(the model's sympy expressions through ``heyoka.from_sympy``); the first periods of both are
compared (the attractor is chaotic: they part later, at the rate of the largest exponent).

Run: ``python examples/bench/sweep_map_throughput.py [PERIODS]`` (heyoka optional: ``pip
install heyoka``; never needed by the tests).
"""

from __future__ import annotations

import json
import math
import os
import sys
import time

import numpy as np
from chaplygin.verify.scene import Scene

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "sweeps", "bm20-fig6-chart.toml")


def ours(res, periods: int) -> tuple[float, np.ndarray]:
    """Our Taylor integrator (generated C, double), one point, sampled every period."""
    from chaplygin.numerics.integrate import integrate

    omega = float(res.params["Omega"])
    T = 2 * math.pi / omega
    p = [res.params[k] for k in res.code.params]
    t_eval = [k * T for k in range(periods + 1)]
    integrate(res.code, res.y0, (0, 2 * T), p, method="taylor", rtol=1e-12, atol=1e-12,
              t_eval=[0, T, 2 * T])  # warm: compile and load once
    start, cpu = time.perf_counter(), time.process_time()
    r = integrate(res.code, res.y0, (0, periods * T), p, method="taylor", rtol=1e-12,
                  atol=1e-12, t_eval=t_eval)
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    return wall / periods, cpu / periods, np.asarray(r.y, dtype=float).T


def ours_batch(res, periods: int, batch: int) -> dict:
    """Our batch map: ``batch`` copies of the point in one call; per period per point."""
    from chaplygin.numerics.batch_map import BatchStroboscopicMap

    p = [float(res.params[k]) for k in res.code.params]
    y0 = [float(v) for v in res.y0]
    bm = BatchStroboscopicMap(res.code, rtol=1e-12, atol=1e-12)
    bm.run([y0], [p], n=2)  # warm: compile and load once
    cpu = time.process_time()
    r = bm.run(np.repeat([y0], batch, 0), np.repeat([p], batch, 0), n=periods + 1)
    cpu = time.process_time() - cpu
    return {
        "us": r.wall_s / periods / batch * 1e6,
        "cpu_us": cpu / periods / batch * 1e6,
        "steps_per_period": float(r.steps[0]) / periods,
        "rejected_per_period": float(r.rejected[0]) / periods,
        "rhs_per_period": float(r.evaluations[0]) / periods,
        "traj": r.y[0],
    }


def heyoka_rows(res, periods: int) -> dict:
    """heyoka 1 point and batch of 4 (the same point four times), per period per point."""
    import heyoka as hy
    import sympy
    from chaplygin.derive.systems import build_model

    model = build_model("chaplygin_ball", res.code.effects)
    state = [s for _, group in model.state_groups for s in group]
    hvars = hy.make_vars(*[str(s) for s in state])
    subs = {s: v for s, v in zip(state, hvars, strict=True)}
    params = [s for spec in model.parameters for s in spec.symbols]
    subs.update({s: hy.par[i] for i, s in enumerate(params)})
    subs[model.time] = hy.time
    rhs = [sympy.sympify(e) for e in model.rhs_expanded]
    sys_ = [(v, hy.from_sympy(e, subs)) for v, e in zip(hvars, rhs, strict=True)]
    pvals = [float(res.params[str(s)]) for s in params]
    y0 = [float(v) for v in res.y0]
    T = 2 * math.pi / float(res.params["Omega"])
    grid = np.array([k * T for k in range(periods + 1)])
    ta = hy.taylor_adaptive(sys_, y0, pars=pvals, tol=1e-12)
    start, cpu = time.perf_counter(), time.process_time()
    out = ta.propagate_grid(grid)
    one = (time.perf_counter() - start) / periods
    one_cpu = (time.process_time() - cpu) / periods
    steps = int(out[3]) / periods
    traj = np.asarray(out[5])
    batch = 4
    tb = hy.taylor_adaptive_batch(
        sys_, np.repeat(np.asarray(y0)[:, None], batch, 1),
        pars=np.repeat(np.asarray(pvals)[:, None], batch, 1), tol=1e-12,
    )
    start, cpu = time.perf_counter(), time.process_time()
    tb.propagate_grid(np.repeat(grid[:, None], batch, 1))
    per_point = (time.perf_counter() - start) / periods / batch
    per_point_cpu = (time.process_time() - cpu) / periods / batch
    return {
        "heyoka_one_us": one * 1e6,
        "heyoka_batch4_us": per_point * 1e6,
        "heyoka_one_cpu_us": one_cpu * 1e6,
        "heyoka_batch4_cpu_us": per_point_cpu * 1e6,
        "heyoka_steps_per_period": steps,
        "traj": traj,
    }


REPEATS = 5


def main() -> None:
    periods = int(sys.argv[1]) if len(sys.argv) > 1 else 700
    res = Scene.from_toml(SCENE).resolve()
    runs: dict[str, list[float]] = {}
    row: dict = {"periods": periods, "load_before": os.getloadavg()[0]}
    try:
        import heyoka  # noqa: F401

        have_heyoka = True
    except ImportError:
        have_heyoka = False
    for _ in range(REPEATS):
        cost, cost_cpu, traj = ours(res, periods)
        runs.setdefault("ours_taylor_c_us", []).append(cost * 1e6)
        runs.setdefault("ours_taylor_c_cpu_us", []).append(cost_cpu * 1e6)
        for batch in (1, 4, 16):
            b = ours_batch(res, periods, batch)
            runs.setdefault(f"ours_batch{batch}_us", []).append(b["us"])
            runs.setdefault(f"ours_batch{batch}_cpu_us", []).append(b["cpu_us"])
        if have_heyoka:
            peer = heyoka_rows(res, periods)
            runs.setdefault("heyoka_one_us", []).append(peer["heyoka_one_us"])
            runs.setdefault("heyoka_batch4_us", []).append(peer["heyoka_batch4_us"])
            runs.setdefault("heyoka_one_cpu_us", []).append(peer["heyoka_one_cpu_us"])
            runs.setdefault("heyoka_batch4_cpu_us", []).append(peer["heyoka_batch4_cpu_us"])
    for name, values in runs.items():
        row[name] = float(np.median(values))
    for key in ("steps_per_period", "rejected_per_period", "rhs_per_period"):
        row[f"ours_batch_{key}"] = b[key]
    row["ours_batch_vs_taylor_first_10_periods"] = float(np.abs(b["traj"][:11] - traj[:11]).max())
    if have_heyoka:
        row["heyoka_steps_per_period"] = peer["heyoka_steps_per_period"]
        row["heyoka_vs_taylor_first_10_periods"] = float(
            np.abs(peer["traj"][:11] - traj[:11]).max()
        )
        row["ratio_batch16_to_heyoka_batch4"] = row["ours_batch16_us"] / row["heyoka_batch4_us"]
        row["ratio_batch4_to_heyoka_batch4"] = row["ours_batch4_us"] / row["heyoka_batch4_us"]
        row["cpu_ratio_batch16_to_heyoka_batch4"] = (
            row["ours_batch16_cpu_us"] / row["heyoka_batch4_cpu_us"]
        )
    row["load_after"] = os.getloadavg()[0]
    print(json.dumps(row, indent=1))


if __name__ == "__main__":
    main()
