"""The peers' rows of the study: heyoka (double, and its own multiprecision) and jitcode on the
same problems, each from a hand-written system (the peers are optional:
``pip install chaplygin[peers]``)."""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable
from typing import Any

import mpmath
import numpy as np

from ..numerics.code import load_model_code
from .bench_problems import BenchProblem, BenchRow, final_error, state_strings
from .bench_timing import timed_runs

__all__ = ["heyoka_rows", "heyoka_system", "jitcode_rows"]


def heyoka_system(
    hy: Any, problem: BenchProblem, number: Callable[[str], Any] = float, digits: int = 17
) -> list[tuple[Any, Any]]:
    """The Chaplygin ball (BKM12 §1.1) in heyoka's expression system.

    ``M' = M x omega``, ``gamma' = gamma x omega``, ``omega = A M + k A gamma``,
    ``A = (I + D)^-1``, ``k = D (gamma, A M) / (1 - D (gamma, A gamma))`` -- written out by
    hand (heyoka cannot take our generated code); ``1/(I_i + D)`` enters as a constant of
    the working type (``number`` of a ``digits``-digit string: heyoka would fold a division
    by a constant into a double reciprocal). Checked by the final error against our
    reference in every heyoka row.

    Parameters
    ----------
    hy : module
        ``heyoka``.
    problem : BenchProblem
        With integer ``I`` and ``D``.
    number : callable
        The working type, from a decimal string (``float``, ``hy.real128``, ...).
    digits : int
        Digits of the constants.

    Returns
    -------
    list of (heyoka.expression, heyoka.expression)
        ``(variable, right-hand side)`` pairs.
    """
    I = [float(v) for v in problem.params["I"]]
    D = float(problem.params["D"])
    if not all(float(v).is_integer() for v in (*I, D)):
        raise ValueError("the heyoka adapter needs integer I, D (exact in every precision)")
    M = hy.make_vars("M1", "M2", "M3")
    g = hy.make_vars("g1", "g2", "g3")
    with mpmath.workdps(digits + 10):
        inv = [mpmath.nstr(1 / (mpmath.mpf(v) + mpmath.mpf(D)), digits + 5) for v in I]
    A = [hy.expression(number(v)) for v in inv]
    Dx = hy.expression(number(str(D)))
    AM = [M[i] * A[i] for i in range(3)]
    Ag = [g[i] * A[i] for i in range(3)]
    k = Dx * hy.sum([g[i] * AM[i] for i in range(3)]) / (
        hy.expression(number("1")) - Dx * hy.sum([g[i] * Ag[i] for i in range(3)])
    )
    w = [AM[i] + k * Ag[i] for i in range(3)]

    def cross(u, v):
        return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]

    return list(zip(M + g, cross(M, w) + cross(g, w), strict=True))


def heyoka_rows(
    problem: BenchProblem,
    quick: bool,
    repeats: int,
    reference: Callable[[float, int], list],
    compile_s: dict,
    say: Callable[[str], None],
) -> list[BenchRow]:
    """heyoka in double (two tolerances and its default), real128 and 30/50/100 digits.

    Parameters
    ----------
    problem : BenchProblem
    quick : bool
    repeats : int
    reference : callable
        ``reference(T, digits)``: the reference final state.
    compile_s : dict
        Filled with heyoka's compile times.
    say : callable
        Progress messages.

    Returns
    -------
    list of BenchRow
    """
    import heyoka as hy

    rows = []
    configs = [("double", 1e-9), ("double", 1e-12), ("double", None), ("real128", None)]
    configs += [(d, None) for d in (30, 50, 100)]
    for kind, tol in configs:
        is_double = kind == "double"
        T = problem.t_double if is_double else problem.t_digits
        note = ""
        if quick:
            T = 20.0 if is_double else (0.5 if kind == 100 else 2.0)
            note = f"quick: T={T:g}, 1 run"
        if is_double:
            own, conv = 16, float
            kw = {"tol": tol} if tol else {}
            label = "double"
        elif kind == "real128":
            own, conv, kw, label = 34, hy.real128, {"fp_type": hy.real128}, "quad (real128)"
        else:
            bits = int(math.ceil(kind * math.log2(10))) + 1
            own, label = kind, f"{kind} digits"

            def conv(x, bits=bits):
                return hy.real(x, bits)

            kw = {"fp_type": hy.real, "prec": bits}
        ref = reference(T, 2 * own)
        sys_ = heyoka_system(hy, problem, conv, own)
        y0 = [conv(v) for v in state_strings(problem, own + 5)]
        if is_double:
            y0 = [float(v) for v in y0]
        say(f"{problem.name}: heyoka {label} tol={tol} T={T:g}")
        start = time.perf_counter()
        ta = hy.taylor_adaptive(sys_, np.array(y0), **kw)
        compile_s[f"heyoka {label} (JIT, {problem.name})"] = time.perf_counter() - start
        t0, end = ta.time, conv(T) if not is_double else T

        def once(ta=ta, t0=t0, y0=y0, end=end):
            ta.time = t0
            ta.state[:] = y0
            start = time.perf_counter()
            outcome = ta.propagate_until(end)
            return time.perf_counter() - start, outcome

        times, outcome = timed_runs(once, repeats)
        with mpmath.workdps(2 * own + 10):  # parse heyoka's decimal output at full precision
            state = [mpmath.mpf(str(v)) if not is_double else float(v) for v in ta.state]
            error = final_error(state, ref, 2 * own)
            y0m = [mpmath.mpf(str(v)) for v in y0]
        code = load_model_code("chaplygin_ball")
        p = [mpmath.mpf(v) for v in (*problem.params["I"], problem.params["D"])]
        with mpmath.workdps(own + 5):
            F0 = code.mpmath.integrals(0, y0m, p)
            F1 = code.mpmath.integrals(T, state, p)
            drift = {
                n: float(abs(b - a) / abs(a)) if abs(a) > 10.0 ** (-own / 2) else float(abs(b - a))
                for n, a, b in zip(code.integral_names, F0, F1, strict=True)
            }
        ok = str(outcome[0]).endswith("time_limit")
        rows.append(BenchRow(
            problem.name, "heyoka", "LLVM JIT", label, tol if tol else ta.tol if is_double
            else float(ta.tol), T, error, drift, statistics.median(times), len(times),
            steps=None, nfev=None,
            note="; ".join(x for x in ("" if ok else f"outcome {outcome[0]}", note,
                                       "drift at the end point only") if x),
        ))
    return rows


def jitcode_rows(
    problem: BenchProblem,
    quick: bool,
    repeats: int,
    reference: Callable[[float, int], list],
    compile_s: dict,
    say: Callable[[str], None],
) -> list[BenchRow]:
    """jitcode (C code from symengine, scipy's Fortran dop853) in double, two tolerances.

    The same hand-written system as :func:`heyoka_system`, with exact rational constants.

    Parameters
    ----------
    problem, quick, repeats, reference, compile_s, say
        As for :func:`heyoka_rows`.

    Returns
    -------
    list of BenchRow
    """
    import symengine as se
    from jitcode import jitcode, y

    I = [se.Integer(int(v)) if float(v).is_integer() else se.sympify(str(v))
         for v in problem.params["I"]]
    D = (se.Integer(int(problem.params["D"])) if float(problem.params["D"]).is_integer()
         else se.sympify(str(problem.params["D"])))
    A = [1 / (v + D) for v in I]
    M, g = [y(i) for i in range(3)], [y(i) for i in range(3, 6)]
    AM = [A[i] * M[i] for i in range(3)]
    Ag = [A[i] * g[i] for i in range(3)]
    k = D * sum(g[i] * AM[i] for i in range(3)) / (1 - D * sum(g[i] * Ag[i] for i in range(3)))
    w = [AM[i] + k * Ag[i] for i in range(3)]

    def cross(u, v):
        return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]

    say(f"{problem.name}: jitcode compile")
    start = time.perf_counter()
    ode = jitcode(cross(M, w) + cross(g, w), verbose=False)
    ode.compile_C()
    compile_s[f"jitcode C (compile, {problem.name})"] = time.perf_counter() - start
    T = 20.0 if quick else problem.t_double
    ref = reference(T, 32)
    y0 = [float(v) for v in state_strings(problem, 20)]
    code = load_model_code("chaplygin_ball")
    p = np.array([float(v) for v in (*problem.params["I"], problem.params["D"])])
    rows = []
    for tol in ([1e-10] if quick else [1e-8, 1e-12]):
        say(f"{problem.name}: jitcode dop853 rtol={tol} T={T:g}")

        def once(ode=ode, tol=tol):
            ode.set_integrator("dop853", rtol=tol, atol=tol, nsteps=10**8)
            ode.set_initial_value(y0, 0.0)
            start = time.perf_counter()
            state = ode.integrate(T)
            return time.perf_counter() - start, state

        times, state = timed_runs(once, repeats)
        F0 = code.numpy.integrals(0.0, np.array(y0), p)
        F1 = code.numpy.integrals(T, np.asarray(state, dtype=float), p)
        drift = {
            n: float(abs(b - a) / abs(a)) if abs(a) > 1e-8 else float(abs(b - a))
            for n, a, b in zip(code.integral_names, F0, F1, strict=True)
        }
        rows.append(BenchRow(
            problem.name, "jitcode", "C (dop853)", "double", tol, T,
            final_error([float(v) for v in state], ref, 32), drift, statistics.median(times),
            len(times), note="; ".join(x for x in (
                "drift at the end point only", f"quick: T={T:g}, 1 run" if quick else "") if x),
        ))
    return rows
