"""Cost per forcing period per point of BM20's stroboscopic map (issue 14 §4), side by side
with heyoka (one point at a time, and its batch mode with 4 points), in one run.

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
    start = time.perf_counter()
    r = integrate(res.code, res.y0, (0, periods * T), p, method="taylor", rtol=1e-12,
                  atol=1e-12, t_eval=t_eval)
    wall = time.perf_counter() - start
    return wall / periods, np.asarray(r.y, dtype=float).T


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
    start = time.perf_counter()
    out = ta.propagate_grid(grid)
    one = (time.perf_counter() - start) / periods
    traj = np.asarray(out[5])
    batch = 4
    tb = hy.taylor_adaptive_batch(
        sys_, np.repeat(np.asarray(y0)[:, None], batch, 1),
        pars=np.repeat(np.asarray(pvals)[:, None], batch, 1), tol=1e-12,
    )
    start = time.perf_counter()
    tb.propagate_grid(np.repeat(grid[:, None], batch, 1))
    per_point = (time.perf_counter() - start) / periods / batch
    return {"heyoka_one_us": one * 1e6, "heyoka_batch4_us": per_point * 1e6, "traj": traj}


def main() -> None:
    periods = int(sys.argv[1]) if len(sys.argv) > 1 else 700
    res = Scene.from_toml(SCENE).resolve()
    cost, traj = ours(res, periods)
    row = {"periods": periods, "ours_taylor_c_us": cost * 1e6, "load": os.getloadavg()[0]}
    try:
        peer = heyoka_rows(res, periods)
    except ImportError:
        peer = None
    if peer is not None:
        row["heyoka_one_us"] = peer["heyoka_one_us"]
        row["heyoka_batch4_us"] = peer["heyoka_batch4_us"]
        row["max_diff_first_10_periods"] = float(np.abs(peer["traj"][:11] - traj[:11]).max())
    print(json.dumps(row, indent=1))


if __name__ == "__main__":
    main()
