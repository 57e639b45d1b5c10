"""Work-precision study: what each digit of accuracy costs in time (issue 5 §4).

Two problems (the Chaplygin ball, BKM12 §1.1 equations):

* ``reference`` -- ``I = (1, 2, 3)``, ``D = 1``, ``gamma0 = (0.2, 0.3, sqrt(0.87))``,
  ``M0 = (0.7, -0.4, 0.5)``; ``T = 1000`` in double, ``T = 50`` at 30 digits and above;
* ``separatrix`` -- the same body, ``M = C gamma`` with ``C = 1`` at the exact separatrix
  point of K01-3.4 (corrected ``C > 0`` form, FORMULAS.md): ``gamma(0) = (-s32, 0, -s21)``,
  ``s_ij = sqrt(a_ij/a31)``, ``a_ij = 1/J_i - 1/J_j``, ``J_i = I_i + D``; the energy is
  ``h2 = C^2/(2 I2)`` (K01-3.3seg) and the solution creeps towards the unstable rotation
  about the middle axis, so errors grow like ``exp(lam t)`` (``lam`` of K01-3.4);
  ``T = 50`` (``lam T = 8.8``).

Every row is one (method, precision, tolerance): the final error is the max-norm distance
of the state at ``T`` from a reference computed at (at least) twice the digits of the
row's precision with the Taylor method (cached in the output folder), the drift of every
first integral comes from :func:`~chaplygin.numerics.integrate.integrate`, and the time is
the median wall time of ``repeats`` runs (integration only; compilation timed separately);
our rows also give the median of the whole public call ``integrate(...)`` split into set-up,
steps and evidence, and its ratio to heyoka's ``propagate_until`` when heyoka ran.

The tables and the speed targets of a study are in :mod:`chaplygin.verify.bench_report`, the
stroboscopic map's throughput in :mod:`chaplygin.verify.bench_map`.

References
----------
K01-3.3seg, K01-3.4 (separatrix point); issue 5 §4 (targets).
"""

from __future__ import annotations

import math
import statistics
import tempfile
import time
import timeit
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from ..derive.errors import ComputationError
from ..numerics.code import load_model_code
from ..numerics.inputs import Precision
from ..numerics.integrate import integrate
from .bench_described import described_system_times
from .bench_enclosure import enclosure_cost
from .bench_ensemble import ensemble_throughput
from .bench_map import (
    jacobian_throughput,
    lyapunov_throughput,
    map_throughput,
    regime_throughput,
    taylor_map_equal_accuracy,
)
from .bench_peers import heyoka_rows, jitcode_rows
from .bench_problems import (
    PROBLEMS,
    BenchProblem,
    BenchRow,
    final_error,
    reference_solution,
    separatrix_state,
)
from .bench_timing import median_run, peers_available, timed_runs
from .bench_verify import verify_time

__all__ = [
    "BenchProblem",
    "BenchRow",
    "PROBLEMS",
    "separatrix_state",
    "reference_solution",
    "run_study",
    "rhs_call_times",
    "compile_times",
    "peers_available",
]


def _measure_integrate(
    problem, method, precision, rtol, T, backend, repeats, ref, ref_digits
) -> BenchRow:
    prec = Precision(precision)
    label_rhs = {"c": "C", "numpy": "numpy"}.get(backend, backend)
    if method == "taylor":
        label_rhs = "C" if prec.is_double or prec.is_quad else "MPFR (gmpy2)"
    if method == "odefun":
        label_rhs = "mpmath"

    def once():
        start = time.perf_counter()
        r = integrate(
            "chaplygin_ball",
            problem.y0,
            T,
            problem.params,
            method=method,
            precision=precision,
            rtol=rtol,
            atol=rtol,
            backend=backend,
            t_eval=[0, T],
        )
        call = time.perf_counter() - start
        parts.append((call, r.setup_s, call - r.setup_s - r.wall_s))
        return r.wall_s, r

    parts: list[tuple[float, float, float]] = []
    med, r, runs = median_run(once, repeats)
    propagate_s = None
    if method == "taylor" and r.success:
        propagate_s = _measure_propagator(problem, precision, rtol, T, backend, repeats, r)
    if method == "taylor":
        label_rhs = {
            "c-dd": "C double-double",
            "c-qd": "C quad-double",
            "c-mpfr": "C MPFR",
            "python-gmpy2": "MPFR (gmpy2)",
        }.get(r.backend, label_rhs)
    call_s, setup_s, evidence_s = (statistics.median(v) for v in zip(*parts, strict=True))
    reached = r.success and r.y.shape[1]
    error = final_error(list(r.y[:, -1]), ref, ref_digits) if reached else math.inf
    return BenchRow(
        problem=problem.name,
        method=method,
        rhs=label_rhs,
        precision=repr(prec),
        rtol=None if method == "odefun" else rtol,
        T=T,
        error=error,
        drift={k: float(v) for k, v in r.drift.items()},
        median_s=med,
        runs=runs,
        steps=r.nsteps if method == "taylor" else None,
        nfev=r.nfev if method != "taylor" else None,
        note="" if r.success else f"failed: {r.message}",
        call_s=call_s,
        setup_s=setup_s,
        evidence_s=evidence_s,
        propagate_s=propagate_s,
    )


def _measure_propagator(problem, precision, rtol, T, backend, repeats, integrated) -> float:
    """Median time of ``Propagator.propagate_until(T)`` from the problem's start, prepared
    once and sent back to the start by ``reset()`` before each run (not timed; heyoka's rows
    set ``ta.time`` and ``ta.state`` the same way); checked to give the ``integrate`` call's
    end state bit for bit."""
    from ..numerics.propagator import Propagator

    prop = Propagator("chaplygin_ball", problem.y0, problem.params, precision=precision,
                      rtol=rtol, atol=rtol, backend=backend)

    def once():
        prop.reset()
        start = time.perf_counter()
        result = prop.propagate_until(T)
        return time.perf_counter() - start, result

    times, r = timed_runs(once, repeats)
    if [str(v) for v in r.y[:, -1]] != [str(v) for v in integrated.y[:, -1]]:
        raise ComputationError("Propagator and integrate() disagree on the bench problem")
    return statistics.median(times)


def rhs_call_times(number: int = 20000) -> dict[str, float]:
    """Seconds per right-hand-side evaluation of the reference problem, called from Python.

    ``C, CompiledModel.rhs``: the single call users and scipy make, with and without a
    preallocated ``out`` (through the CPython trampoline of
    :mod:`chaplygin.numerics.fastcall` when it could be built); ``C via cffi only``: the same
    with the trampoline switched off;
    ``C (rhs_many, per state)``: one batched C call on 1000 states, divided by 1000;
    ``numpy (per call)``: the generated numpy ``rhs``. Best of 5 repeats of ``number``.

    Parameters
    ----------
    number : int, default 20000
        Calls per repeat for the C timings (the numpy timing uses 2000).

    Returns
    -------
    dict of str to float
        Seconds per evaluation by label; only the numpy entry when the C code could not
        be compiled.
    """
    code = load_model_code("chaplygin_ball")
    lib = code.compiled()
    y = np.array([0.7, -0.4, 0.5, 0.2, 0.3, math.sqrt(0.87)])
    p = np.array([1.0, 2.0, 3.0, 1.0])
    out: dict[str, float] = {}
    np_rhs = code.numpy.rhs
    out["numpy (per call)"] = min(timeit.repeat(lambda: np_rhs(0.0, y, p), number=2000,
                                                repeat=5)) / 2000
    if lib is None:
        return out
    buf = np.empty(6)
    rhs = lib.rhs
    env = {"rhs": rhs, "y": y, "p": p, "buf": buf}  # timed as statements: no lambda frame
    via = "CPython trampoline" if lib._fast is not None else "cffi (no trampoline here)"
    out[f"C, CompiledModel.rhs with out ({via})"] = min(
        timeit.repeat("rhs(0.0, y, p, buf)", globals=env, number=number, repeat=5)
    ) / number
    out[f"C, CompiledModel.rhs, new output array ({via})"] = min(
        timeit.repeat("rhs(0.0, y, p)", globals=env, number=number, repeat=5)
    ) / number
    saved, lib._fast = lib._fast, None  # the cffi path alone, for comparison
    try:
        out["C via cffi only (per call)"] = min(
            timeit.repeat("rhs(0.0, y, p, buf)", globals=env, number=number, repeat=5)
        ) / number
    finally:
        lib._fast = saved
    raw, ybuf, pbuf, obuf = lib._rhs, lib._y_buffer(y), lib._p_buffer(p), lib._y_buffer(buf)
    out["C via cffi, raw call on pre-built buffers (floor of ABI mode)"] = min(
        timeit.repeat(lambda: raw(0.0, ybuf, pbuf, obuf), number=number, repeat=5)
    ) / number
    Y = np.repeat(y[:, None], 1000, axis=1)
    many = lib.rhs_many
    out["C rhs_many, 1000 states (per state)"] = (
        min(timeit.repeat(lambda: many(0.0, Y, p), number=200, repeat=5)) / 200 / 1000
    )
    return out


def compile_times() -> dict[str, float]:
    """Seconds to compile (from scratch, in a temporary cache) the model's C code.

    Returns
    -------
    dict of str to float
        Seconds by job (the right-hand side, and the Taylor code in double and quad when
        there is one); a job that fails has ``nan`` and an entry ``"<job> (error)"``
        holding the first 80 characters of the error message (a str).
    """
    from ..derive.emit.c_sources import taylor_source
    from ..numerics.ccompile import compile_c

    code = load_model_code("chaplygin_ball")
    out: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        jobs = [("C right-hand side (rhs, jac, integrals)", code.c_source, ())]
        if code.taylor_c_source:
            jobs += [
                ("Taylor double", code.taylor_c_source, ()),
                ("Taylor quad", taylor_source(code.taylor_c_source, "quad"), ("-lquadmath",)),
            ]
        for name, src, ldlibs in jobs:
            start = time.perf_counter()
            try:
                compile_c(src, cache_dir=tmp, force=True, ldlibs=ldlibs)
            except Exception as exc:  # reported in the table, not fatal
                out[name] = float("nan")
                out[name + " (error)"] = str(exc)[:80]  # type: ignore[assignment]
                continue
            out[name] = time.perf_counter() - start
    return out


# --------------------------------------------------------------------------- the study


def _configs(quick: bool):
    """(method, backend, precision, rtols, slow) per family."""
    ladders = {  # full study: two tolerances per scipy method (slow ones kept affordable)
        "RK45": [1e-7, 1e-10],
        "DOP853": [1e-8, 1e-12],
        "LSODA": [1e-8, 1e-11],
        "Radau": [1e-6, 1e-9],
    }
    return [
        *(
            (m, b, "double", ladders[m] if not quick else [1e-10],
             b == "numpy" or m in ("RK45", "Radau"))
            for m in ladders
            for b in ("numpy", "c")
        ),
        ("taylor", "c", "double", [1e-9, 1e-12, 2.3e-14] if not quick else [1e-12], False),
        ("taylor", "c", "quad", [1e-20, 2e-33, 2e-34] if not quick else [2e-33], False),
        # two tolerances per digits precision: 100 eps, and eps (heyoka's default tol is its
        # eps, the comparison is at equal or better final error)
        ("taylor", "auto", 30, [1e-28, 1e-30] if not quick else [1e-30], False),
        ("taylor", "auto", 50, [1e-48, 1e-50] if not quick else [1e-50], False),
        ("taylor", "auto", 100, [1e-98, 1e-100] if not quick else [1e-100], True),
        ("odefun", "auto", 30, [None], True),
        ("odefun", "auto", 50, [None], True),
    ]


def run_study(
    out: Path,
    *,
    quick: bool = False,
    repeats: int | None = None,
    problems: Sequence[str] = ("reference", "separatrix"),
    progress: Callable[[str], None] | None = None,
) -> dict:
    """Run the work-precision study; return ``{"rows", "rhs_call_s", "compile_s", ...}``.

    ``quick``: one run per row, one tolerance per method, ``T`` shortened (double: 20,
    digits: 2; slow families -- numpy right-hand sides, RK45, Radau, 100 digits, odefun --
    double: 5, digits: 0.5); every shortened row says so in ``note``.

    Parameters
    ----------
    out : pathlib.Path
        Folder for the cached reference solutions (created).
    quick : bool, default False
        Shortened study (see above).
    repeats : int, optional
        Runs per row; default 1 when ``quick``, else 5.
    problems : sequence of str, default ("reference", "separatrix")
        Keys of :data:`PROBLEMS`.
    progress : callable of str, optional
        Called with a line of text before each measurement.

    Returns
    -------
    dict
        ``"rows"`` (list of :meth:`BenchRow.to_json` dicts, the peers' rows included,
        or a row saying they are not installed), ``"rhs_call_s"``
        (:func:`rhs_call_times`), ``"compile_s"`` (:func:`compile_times` and the peers'
        compile/JIT times), ``"map_throughput"`` (:func:`map_throughput`),
        ``"taylor_map_equal_accuracy"``
        (:func:`~chaplygin.verify.bench_map.taylor_map_equal_accuracy`),
        ``"lyapunov_throughput"`` (:func:`~chaplygin.verify.bench_map.lyapunov_throughput`),
        ``"regime_throughput"`` (:func:`~chaplygin.verify.bench_map.regime_throughput`),
        ``"jacobian_throughput"`` (:func:`~chaplygin.verify.bench_map.jacobian_throughput`),
        ``"ensemble_throughput"``
        (:func:`~chaplygin.verify.bench_ensemble.ensemble_throughput`), ``"verify_time"``
        (:func:`~chaplygin.verify.bench_verify.verify_time`: every claim; quick: K01-2.2's),
        ``"enclosure_cost"`` (:func:`~chaplygin.verify.bench_enclosure.enclosure_cost`),
        ``"quick"`` and ``"repeats"``.
    """
    out.mkdir(parents=True, exist_ok=True)
    repeats = (1 if quick else 5) if repeats is None else repeats
    say = progress or (lambda s: None)
    rows: list[BenchRow] = []
    peer_compile: dict[str, float] = {}
    have_taylor = "taylor" in _integrate_methods()
    for pname in problems:
        problem = PROBLEMS[pname]
        refs: dict = {}
        for method, backend, precision, rtols, slow in _configs(quick):
            prec = Precision(precision)
            T = problem.t_double if prec.is_double else problem.t_digits
            note = ""
            if quick:
                T = (5.0 if slow else 20.0) if prec.is_double else (0.5 if slow else 2.0)
                full = problem.t_double if prec.is_double else problem.t_digits
                note = f"quick: T={T:g} (full: {full:g}), 1 run"
            if method == "taylor" and not have_taylor:
                rows.append(BenchRow(pname, "taylor", "-", repr(prec), None, T, None,
                                     note="unavailable (no taylor method)"))
                continue
            own = 16 if prec.is_double else (Precision.QUAD_DIGITS if prec.is_quad else prec.digits)
            ref_digits = 2 * own
            if (T, ref_digits) not in refs:
                say(f"reference {pname} T={T:g} at {ref_digits} digits")
                refs[(T, ref_digits)] = reference_solution(problem, T, ref_digits, out)
            ref = refs[(T, ref_digits)]
            for rtol in rtols:
                say(f"{pname}: {method} {backend} {prec!r} rtol={rtol} T={T:g}")
                row = _measure_integrate(
                    problem, method, precision, rtol if rtol else prec.min_rtol, T, backend,
                    repeats, ref, ref_digits,
                )
                row.note = "; ".join(x for x in (row.note, note) if x)
                rows.append(row)
        peers = peers_available()

        def reference(T, digits, problem=problem, refs=refs):
            if (T, digits) not in refs:
                say(f"reference {problem.name} T={T:g} at {digits} digits")
                refs[(T, digits)] = reference_solution(problem, T, digits, out)
            return refs[(T, digits)]

        if peers["heyoka"]:
            rows += heyoka_rows(problem, quick, repeats, reference, peer_compile, say)
        else:
            rows.append(BenchRow(pname, "heyoka", "-", "-", None, problem.t_double, None,
                                 note="not installed (pip install chaplygin[peers])"))
        if peers["jitcode"]:
            rows += jitcode_rows(problem, quick, repeats, reference, peer_compile, say)
        else:
            rows.append(BenchRow(pname, "jitcode", "-", "-", None, problem.t_double, None,
                                 note="not installed (pip install chaplygin[peers])"))
    return {
        "rows": [r.to_json() for r in rows],
        "rhs_call_s": rhs_call_times(2000 if quick else 20000),
        "compile_s": {**compile_times(), **peer_compile},
        "map_throughput": map_throughput(100 if quick else 700, repeats),
        "taylor_map_equal_accuracy": taylor_map_equal_accuracy(
            *((20, 1, 4) if quick else (200, repeats))
        ),
        "lyapunov_throughput": (
            lyapunov_throughput(200, 20, 1, 4) if quick else lyapunov_throughput(repeats=repeats)
        ),
        "regime_throughput": regime_throughput(1, 4, True) if quick else regime_throughput(repeats),
        "jacobian_throughput": jacobian_throughput(1, 8) if quick else jacobian_throughput(repeats),
        "ensemble_throughput": ensemble_throughput((8,) if quick else (64, 1024), repeats, quick),
        "verify_time": verify_time("K01-2.2*") if quick else verify_time(),
        "enclosure_cost": enclosure_cost(1, proof=False) if quick else enclosure_cost(repeats),
        "described_system_s": {} if quick else described_system_times(),
        "quick": quick,
        "repeats": repeats,
    }


def _integrate_methods():
    from ..numerics.integrate import METHODS

    return METHODS
