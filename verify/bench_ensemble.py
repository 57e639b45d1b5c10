"""Many orbits at once: seconds per orbit of ``integrate_many`` against one ``integrate`` call
per orbit and, when installed, heyoka's ensemble (``ensemble_propagate_until``, threads) and
batch mode (``taylor_adaptive_batch``, SIMD lanes), on the study's problems, side by side in
one run (issue 26)."""

from __future__ import annotations

import os
import statistics
import time
from typing import Any

import mpmath
import numpy as np

from ..derive.errors import UserInputError
from ..numerics.ensemble import integrate_many
from ..numerics.ensemble_propagator import EnsemblePropagator
from ..numerics.integrate import integrate
from .bench_peers import heyoka_system
from .bench_problems import PROBLEMS, state_strings
from .bench_timing import peers_available

__all__ = ["ensemble_throughput"]

#: The study's Taylor tolerances of the ensemble rows (issue 26's tol 1e-9 and 1e-12).
ENSEMBLE_TOLERANCES = (1e-9, 1e-12)


def _orbits(name: str, count: int) -> list[list[float]]:
    """``count`` starts: the problem's state with ``M`` scaled by ``1 + j 1e-3`` (the same
    level of ``(M, gamma)``'s direction; every start generic, none the same)."""
    y = [float(mpmath.mpf(v)) for v in state_strings(PROBLEMS[name], 17)]
    return [[v * (1 + 1e-3 * j) for v in y[:3]] + y[3:] for j in range(count)]


def _heyoka_rows(name: str, starts: list[list[float]], T: float, tol: float,
                 repeats: int) -> dict[str, float]:  # fmt: skip
    """heyoka's seconds per orbit: the ensemble (threads) and the batch mode (4 lanes)."""
    import heyoka as hy

    sys_ = heyoka_system(hy, PROBLEMS[name])
    ta = hy.taylor_adaptive(sys_, np.array(starts[0]), tol=tol)
    N = len(starts)

    def gen(ta_copy, j):
        ta_copy.time = 0.0
        ta_copy.state[:] = starts[j]
        return ta_copy

    ens, bat = [], []
    width = 4
    tb = hy.taylor_adaptive_batch(sys_, np.array(starts[:width]).T.copy(), tol=tol)
    for _ in range(repeats):
        start = time.perf_counter()
        hy.ensemble_propagate_until(ta, T, N, gen)
        ens.append((time.perf_counter() - start) / N)
        start = time.perf_counter()
        for k in range(0, N, width):
            tb.set_time(0.0)
            block = np.array([starts[(k + i) % N] for i in range(width)]).T
            tb.state[:] = block
            tb.propagate_until(T)
        bat.append((time.perf_counter() - start) / N)
    return {"heyoka_ensemble": statistics.median(ens), "heyoka_batch4": statistics.median(bat)}


def ensemble_throughput(orbits: tuple[int, ...] = (64, 1024), repeats: int = 3,
                        quick: bool = False, peers: bool = True) -> dict[str, Any]:  # fmt: skip
    """Seconds per orbit of the reference problem and the separatrix run in double (Taylor,
    tol 1e-9 and 1e-12), for each number of orbits: ``ours_one`` (one ``integrate`` call per
    orbit, timed on at most :data:`ONE_AT_A_TIME` of them: its cost per orbit does not depend
    on their number), ``ours_many``, ``ours_many_1`` and ``ours_many_<cpus>``
    (``integrate_many``, the orbits in vector lanes, with the default threads -- as many as
    the work needs -- on 1 thread and on the usable CPUs; the whole call) and
    ``ours_many_1_c`` (the compiled integration alone, the orbits' ``wall_s``),
    ``ours_prop`` (an :class:`~chaplygin.numerics.ensemble_propagator.EnsemblePropagator`
    made once, each call ``reset()`` and ``propagate_until(T)``: heyoka's batch row sets its
    time and states and propagates), heyoka's ensemble and batch mode when installed;
    medians of ``repeats``; the ratios of ``ours_many`` (what a call gives by default) and of
    ``ours_prop`` to heyoka's.

    Parameters
    ----------
    orbits : tuple of int
        Orbits per call (perturbed copies of the problem's start), one row each.
    repeats : int
    quick : bool
        Short spans (T = 20 and 5).
    peers : bool
        Include heyoka when it is installed.

    Returns
    -------
    dict
        ``"<problem> tol=<tol> T=<T> N=<orbits>"`` -> ``{"<row>_s": seconds per orbit, ...,
        ratios}``, and the load average before and after.

    Raises
    ------
    UserInputError
        No orbits, a count below 1 or ``repeats < 1``.
    """
    if not orbits or min(orbits) < 1 or repeats < 1:
        raise UserInputError("ensemble_throughput needs orbits >= 1 and repeats >= 1")
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1
    have_heyoka = peers and peers_available()["heyoka"]
    out: dict[str, Any] = {"orbits": list(orbits), "threads": cpus,
                           "load_before": os.getloadavg()[0]}  # fmt: skip
    for name in ("reference", "separatrix"):
        problem = PROBLEMS[name]
        T = (20.0 if name == "reference" else 5.0) if quick else problem.t_double
        for tol in ENSEMBLE_TOLERANCES:
            for count in orbits:
                row = _ours_rows(name, T, tol, count, repeats, cpus)
                if have_heyoka:
                    row.update({f"{k}_s": v for k, v in _heyoka_rows(
                        name, _orbits(name, count), T, tol, repeats).items()})  # fmt: skip
                    best = row["ours_many_s"]
                    row["ratio_many_to_heyoka_ensemble"] = best / row["heyoka_ensemble_s"]
                    row["ratio_many_to_heyoka_batch4"] = best / row["heyoka_batch4_s"]
                    row["ratio_prop_to_heyoka_batch4"] = (
                        row["ours_prop_s"] / row["heyoka_batch4_s"])
                out[f"{name} tol={tol:g} T={T:g} N={count}"] = row
    out["load_after"] = os.getloadavg()[0]
    return out


#: At most this many orbits are integrated one ``integrate`` call each in a row of
#: :func:`ensemble_throughput`.
ONE_AT_A_TIME = 64


def _ours_rows(name: str, T: float, tol: float, count: int, repeats: int,
               cpus: int) -> dict[str, Any]:  # fmt: skip
    """Our rows of one problem, tolerance and number of orbits (medians, seconds per orbit)."""
    starts = _orbits(name, count)
    p = PROBLEMS[name].params
    kw = {"rtol": tol, "atol": tol, "t_eval": [0.0, T]}
    integrate("chaplygin_ball", starts[0], T, p, **kw)  # compiled first
    runs: dict[str, list[float]] = {}
    few = starts[:ONE_AT_A_TIME]
    for _ in range(repeats):
        start = time.perf_counter()
        for y in few:
            integrate("chaplygin_ball", y, T, p, **kw)
        runs.setdefault("ours_one_s", []).append((time.perf_counter() - start) / len(few))
        for threads in [None, *sorted({1, cpus})]:
            # each row timed warm: the single calls above evict the lanes' code and data
            integrate_many("chaplygin_ball", starts, T, p, threads=threads, **kw)
            r = integrate_many("chaplygin_ball", starts, T, p, threads=threads, **kw)
            label = "ours_many_s" if threads is None else f"ours_many_{threads}_s"
            runs.setdefault(label, []).append(r.wall_s / count)
            if threads == 1:  # the compiled integration alone (one thread: its wall time)
                runs.setdefault("ours_many_1_c_s", []).append(
                    float(r.orbit_wall_s.sum()) / count)
    # prepared once (heyoka's taylor_adaptive_batch): each call goes back to the starts
    prop = EnsemblePropagator("chaplygin_ball", starts, p, rtol=tol, atol=tol)
    prop.propagate_until(T)  # warm
    for _ in range(repeats):
        start = time.perf_counter()
        prop.reset()
        prop.propagate_until(T)
        runs.setdefault("ours_prop_s", []).append((time.perf_counter() - start) / count)
    row: dict[str, Any] = {k: statistics.median(v) for k, v in runs.items()}
    row["steps_per_orbit"] = float(np.median(r.nsteps))
    row["failed"] = int((r.status != 0).sum())
    return row
