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

References
----------
K01-3.3seg, K01-3.4 (separatrix point); issue 5 §4 (targets).
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import math
import os
import statistics
import tempfile
import time
import timeit
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import mpmath
import numpy as np

from ..derive.errors import ComputationError, UserInputError
from ..numerics.code import load_model_code
from ..numerics.inputs import Precision
from ..numerics.integrate import integrate
from ..numerics.separatrix import separatrix_state as exact_separatrix_state

__all__ = [
    "BenchProblem",
    "BenchRow",
    "PROBLEMS",
    "separatrix_state",
    "reference_solution",
    "run_study",
    "rhs_call_times",
    "compile_times",
    "map_throughput",
    "peers_available",
    "render_markdown",
    "speed_targets",
    "target_ratios",
]

#: Part of the reference-cache key: bump when the inputs' meaning changes (2: decimal literals
#: are read with all their digits).
_CACHE_VERSION = 2


@dataclass(frozen=True)
class BenchProblem:
    """One initial-value problem of the study."""

    name: str
    params: dict
    y0: dict
    t_double: float
    t_digits: float
    description: str

    def key(self) -> str:
        """Cache key of the problem's reference solutions.

        Returns
        -------
        str
            The first 16 hex digits of the sha256 of the cache version, name, parameters
            and initial state (not of the spans: those are part of the file name).
        """
        data = [_CACHE_VERSION, self.name, self.params, self.y0]
        return hashlib.sha256(json.dumps(data, sort_keys=True, default=str).encode()).hexdigest()[
            :16
        ]


def separatrix_state(
    I: Sequence[float | str] = (1, 2, 3),
    D: float | str = 1,
    C: float | str = 1,
    dps: int = 250,
) -> dict[str, tuple[str, ...]]:
    """``M`` and ``gamma`` at the separatrix point ``t = 0`` of K01-3.4 (C > 0 form).

    ``gamma = (-s32, 0, -s21)``, ``M = C gamma``, computed by
    :func:`chaplygin.numerics.separatrix.separatrix_state` at ``dps + 10`` digits; values as
    decimal strings of ``dps`` digits (the inputs are parsed at the working precision of
    each run).

    Parameters
    ----------
    I : sequence of 3 numbers
        Moments of inertia, ``I1 < I2 < I3``.
    D, C : number
        ``D = m b^2`` and ``C = (M, gamma)``.
    dps : int
        Digits of the strings.

    Returns
    -------
    dict of str to tuple of str
        ``{"M": (3 str), "gamma": (3 str)}``.

    Raises
    ------
    UserInputError
        Unless ``I1 < I2 < I3``.

    References
    ----------
    K01-3.4 (corrected for C > 0), K01-3.3seg.
    """
    with mpmath.workdps(dps + 10):
        I1, I2, I3 = (mpmath.mpf(str(v)) for v in I)
        if not I1 < I2 < I3:
            raise UserInputError("the separatrix point needs I1 < I2 < I3")
        y = exact_separatrix_state((I1, I2, I3), mpmath.mpf(str(D)), mpmath.mpf(str(C)))
        return {
            "M": tuple(mpmath.nstr(v, dps, strip_zeros=False) for v in y[:3]),
            "gamma": tuple(mpmath.nstr(v, dps, strip_zeros=False) for v in y[3:6]),
        }


PROBLEMS: dict[str, BenchProblem] = {
    "reference": BenchProblem(
        "reference",
        {"I": (1, 2, 3), "D": 1},
        {"M": ("0.7", "-0.4", "0.5"), "gamma": ("0.2", "0.3", "sqrt(0.87)")},
        1000.0,
        50.0,
        "I=(1,2,3), D=1, gamma0=(0.2,0.3,sqrt(0.87)), M0=(0.7,-0.4,0.5)",
    ),
    "separatrix": BenchProblem(
        "separatrix",
        {"I": (1, 2, 3), "D": 1},
        separatrix_state(),
        50.0,
        50.0,
        "I=(1,2,3), D=1, M = gamma on the separatrix h = h2 (K01-3.4, C=1)",
    ),
}


@dataclass
class BenchRow:
    """One measured (or unavailable) configuration.

    ``median_s`` is the integration alone (``IntegrationResult.wall_s``); for our rows
    ``call_s`` is the median of the whole public call ``integrate(...)`` and ``setup_s``,
    ``evidence_s`` its parts before and after the integration (reading the inputs, loading
    the compiled code; drift evidence and result), all medians of the same runs. For the
    Taylor rows ``propagate_s`` is the median of ``Propagator.propagate_until(T)`` (inputs
    checked and the integrator loaded once, as heyoka's ``taylor_adaptive``; the same steps
    and bits as the ``integrate`` call, drift evidence included).
    """

    problem: str
    method: str
    rhs: str
    precision: str
    rtol: float | None
    T: float
    error: float | None
    drift: dict = field(default_factory=dict)
    median_s: float | None = None
    runs: int = 0
    steps: int | None = None
    nfev: int | None = None
    note: str = ""
    call_s: float | None = None
    setup_s: float | None = None
    evidence_s: float | None = None
    propagate_s: float | None = None

    def to_json(self) -> dict[str, object]:
        """The row as a JSON-ready dict.

        Returns
        -------
        dict of str to object
            ``dataclasses.asdict`` of the row: one entry per field.
        """
        return asdict(self)


# --------------------------------------------------------------------------- reference


def _reference_file(out: Path, problem: BenchProblem, T: float, digits: int) -> Path:
    return out / f"reference_{problem.name}_{problem.key()}_T{T:g}_{digits}d.json"


def reference_solution(
    problem: BenchProblem, T: float, digits: int, out: Path | None
) -> list[mpmath.mpf]:
    """State at ``T`` with at least ``digits`` digits (Taylor; cached in ``out``).

    ``digits <= 34`` uses quad (C ``__float128``, 34 digits), else MPFR at ``digits``;
    the tolerance is the smallest the precision delivers.

    Parameters
    ----------
    problem : BenchProblem
        The initial-value problem (Chaplygin ball).
    T : float
        End time.
    digits : int
        Digits the reference must have at least.
    out : pathlib.Path or None
        Folder of the cached references (read when the file exists, written after a
        computation); None computes without caching.

    Returns
    -------
    list of mpmath.mpf
        The state at ``T`` in model order (six components).

    Raises
    ------
    RuntimeError
        When the Taylor integration fails.
    """
    path = None if out is None else _reference_file(out, problem, T, digits)
    if path is not None and path.exists():
        data = json.loads(path.read_text())
        with mpmath.workdps(data["digits"] + 5):
            return [mpmath.mpf(v) for v in data["y"]]
    prec: str | int = "quad" if digits <= Precision.QUAD_DIGITS else digits
    P = Precision(prec)
    r = integrate(
        "chaplygin_ball",
        problem.y0,
        T,
        problem.params,
        method="taylor",
        precision=prec,
        rtol=P.min_rtol,
        atol=P.min_rtol,
        t_eval=[0, T],
    )
    if not r.success:  # pragma: no cover - the reference problems integrate
        raise RuntimeError(f"reference integration failed: {r.message}")
    ys = list(r.y[:, -1])
    if path is not None:
        got = P.QUAD_DIGITS if P.is_quad else P.digits
        with mpmath.workdps(got + 5):
            text = [mpmath.nstr(v, got + 3, strip_zeros=False) for v in ys]
        path.write_text(
            json.dumps(
                {"problem": problem.name, "T": T, "digits": got, "precision": repr(P),
                 "y": text, "wall_s": r.wall_s},
                indent=1,
            )
        )
    return ys


def _error(y_final, ref, digits: int) -> float:
    with mpmath.workdps(digits + 10):
        return float(max(abs(mpmath.mpf(v) - r) for v, r in zip(y_final, ref, strict=True)))


# --------------------------------------------------------------------------- measuring


#: Runs shorter than this in all are repeated until their total reaches it (at most
#: :data:`SHORT_RUNS_MAX` runs): a median of 5 calls of 10 us is mostly the machine's noise.
#: Applied alike to our rows and the peers'.
SHORT_RUN_BUDGET_S = 0.05
SHORT_RUNS_MAX = 500


def _runs(first_s: float, repeats: int) -> int:
    """How many runs to time when one takes ``first_s`` (at least ``repeats``; exactly one
    when one is asked for)."""
    if first_s <= 0 or repeats <= 1:  # one run asked for (--quick, --repeats 1): one run
        return repeats
    return max(repeats, min(SHORT_RUNS_MAX, int(SHORT_RUN_BUDGET_S / first_s)))


def _timed_runs(fn: Callable[[], object], repeats: int) -> tuple[list[float], object]:
    """The wall times of ``fn()`` (its set-up outside: ``fn`` times itself and returns
    ``(seconds, value)``), as many runs as :func:`_runs` says; and the last value."""
    wall, last = fn()
    times = [wall]
    for _ in range(_runs(wall, repeats) - 1):
        wall, last = fn()
        times.append(wall)
    return times, last


def _median_run(fn: Callable[[], tuple[float, object]], repeats: int):
    times, last = _timed_runs(fn, repeats)
    return statistics.median(times), last, len(times)


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
    med, r, runs = _median_run(once, repeats)
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
    error = _error(list(r.y[:, -1]), ref, ref_digits) if r.success and r.y.shape[1] else math.inf
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

    times, r = _timed_runs(once, repeats)
    if [str(v) for v in r.y[:, -1]] != [str(v) for v in integrated.y[:, -1]]:
        raise ComputationError("Propagator and integrate() disagree on the bench problem")
    return statistics.median(times)


def peers_available() -> dict[str, bool]:
    """Whether the optional peers (``pip install chaplygin[peers]``) are importable.

    Returns
    -------
    dict of str to bool
        ``{"heyoka": ..., "jitcode": ...}``.
    """
    return {name: importlib.util.find_spec(name) is not None for name in ("heyoka", "jitcode")}


def _state_strings(problem: BenchProblem, digits: int) -> list[str]:
    """The problem's initial state (model order), as decimal strings of ``digits`` digits."""
    from ..numerics.inputs import pack_state

    code = load_model_code("chaplygin_ball")
    with mpmath.workdps(digits + 10):
        y = pack_state(code, problem.y0, Precision(digits + 10))
        return [mpmath.nstr(v, digits + 5, strip_zeros=False) for v in y]


def _heyoka_system(hy, problem: BenchProblem, number=float, digits: int = 17):
    """The Chaplygin ball (BKM12 §1.1) in heyoka's expression system.

    ``M' = M x omega``, ``gamma' = gamma x omega``, ``omega = A M + k A gamma``,
    ``A = (I + D)^-1``, ``k = D (gamma, A M) / (1 - D (gamma, A gamma))`` -- written out by
    hand (heyoka cannot take our generated code); ``1/(I_i + D)`` enters as a constant of
    the working type (``number`` of a ``digits``-digit string: heyoka would fold a division
    by a constant into a double reciprocal). Checked by the final error against our
    reference in every heyoka row.
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


def _heyoka_rows(problem, quick, repeats, reference, compile_s, say) -> list[BenchRow]:
    """heyoka in double (two tolerances and its default), real128 and 30/50/100 digits."""
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
        sys_ = _heyoka_system(hy, problem, conv, own)
        y0 = [conv(v) for v in _state_strings(problem, own + 5)]
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

        times, outcome = _timed_runs(once, repeats)
        with mpmath.workdps(2 * own + 10):  # parse heyoka's decimal output at full precision
            state = [mpmath.mpf(str(v)) if not is_double else float(v) for v in ta.state]
            error = _error(state, ref, 2 * own)
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


def _jitcode_rows(problem, quick, repeats, reference, compile_s, say) -> list[BenchRow]:
    """jitcode (C code from symengine, scipy's Fortran dop853) in double, two tolerances.

    The same hand-written system as :func:`_heyoka_system`, with exact rational constants.
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
    y0 = [float(v) for v in _state_strings(problem, 20)]
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

        times, state = _timed_runs(once, repeats)
        F0 = code.numpy.integrals(0.0, np.array(y0), p)
        F1 = code.numpy.integrals(T, np.asarray(state, dtype=float), p)
        drift = {
            n: float(abs(b - a) / abs(a)) if abs(a) > 1e-8 else float(abs(b - a))
            for n, a, b in zip(code.integral_names, F0, F1, strict=True)
        }
        rows.append(BenchRow(
            problem.name, "jitcode", "C (dop853)", "double", tol, T,
            _error([float(v) for v in state], ref, 32), drift, statistics.median(times),
            len(times), note="; ".join(x for x in (
                "drift at the end point only", f"quick: T={T:g}, 1 run" if quick else "") if x),
        ))
    return rows


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
        compile/JIT times), ``"map_throughput"`` (:func:`map_throughput`), ``"quick"`` and
        ``"repeats"``.
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
            rows += _heyoka_rows(problem, quick, repeats, reference, peer_compile, say)
        else:
            rows.append(BenchRow(pname, "heyoka", "-", "-", None, problem.t_double, None,
                                 note="not installed (pip install chaplygin[peers])"))
        if peers["jitcode"]:
            rows += _jitcode_rows(problem, quick, repeats, reference, peer_compile, say)
        else:
            rows.append(BenchRow(pname, "jitcode", "-", "-", None, problem.t_double, None,
                                 note="not installed (pip install chaplygin[peers])"))
    return {
        "rows": [r.to_json() for r in rows],
        "rhs_call_s": rhs_call_times(2000 if quick else 20000),
        "compile_s": {**compile_times(), **peer_compile},
        "map_throughput": map_throughput(100 if quick else 700, repeats),
        "quick": quick,
        "repeats": repeats,
    }


def _integrate_methods():
    from ..numerics.integrate import METHODS

    return METHODS


# --------------------------------------------------------------------------- output


def _fmt(x, spec=".2e") -> str:
    if x is None:
        return "-"
    if isinstance(x, float) and not math.isfinite(x):
        return "inf" if x > 0 else "nan"
    return format(x, spec)


def render_markdown(study: dict) -> str:
    """The study as Markdown: one table per problem, rhs-call and compile times, ratios.

    Parameters
    ----------
    study : dict
        The output of :func:`run_study` (or the JSON it was saved as).

    Returns
    -------
    str
        The Markdown document, ending with a newline.
    """
    rows = study["rows"]
    lines = ["# Work-precision study (chaplygin bench)", ""]
    if study.get("quick"):
        lines += ["**Quick run** (`--quick`): shortened spans and one run per row; see notes.", ""]
    for pname in dict.fromkeys(r["problem"] for r in rows):
        prob = PROBLEMS[pname]
        lines += [f"## {pname}: {prob.description}", ""]
        names = sorted({k for r in rows if r["problem"] == pname for k in r["drift"]})
        head = ["method", "rhs", "precision", "rtol", "T", "final error", *(
            f"drift {n}" for n in names), "median s", "runs", "steps", "rhs calls",
            "integrate() s (set-up + steps + evidence, ms)", "x heyoka",
            "propagate_until() s", "x heyoka", "note"]
        lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for r in rows:
            if r["problem"] != pname:
                continue
            cells = [r["method"], r["rhs"], r["precision"], _fmt(r["rtol"], ".0e"),
                     _fmt(r["T"], "g"), _fmt(r["error"]),
                     *(_fmt(r["drift"].get(n)) for n in names),
                     _fmt(r["median_s"], ".4g"), str(r["runs"]), _fmt(r["steps"], "d"),
                     _fmt(r.get("nfev"), "d"), _call_parts(r), _heyoka_ratio(r, rows),
                     _fmt(r.get("propagate_s"), ".4g"),
                     _heyoka_ratio(r, rows, "propagate_s"), r["note"]]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    lines += ["## Right-hand side called from Python (seconds per evaluation)", ""]
    lines += [f"- {k}: {v * 1e9:.0f} ns" for k, v in study["rhs_call_s"].items()]
    lines += ["", "## Compile time (separate from the integration times above)", ""]
    lines += [
        f"- {k}: {v:.2f} s" if isinstance(v, float) else f"- {k}: {v}"
        for k, v in study["compile_s"].items()
    ]
    if study.get("map_throughput"):
        lines += ["", "## BM20's stroboscopic map (us per forcing period per point)", ""]
        lines += [f"- {k}: {v:.4g}" if isinstance(v, float) else f"- {k}: {v}"
                  for k, v in study["map_throughput"].items()]  # fmt: skip
    lines += ["", "## Against heyoka at equal or better final error (issue 15, this run)", ""]
    lines += [f"- {t}" for t in speed_targets(study)] or ["- heyoka not installed"]
    lines += ["", "## Targets of issue 5 (ratios from this run)", ""]
    lines += [f"- {t}" for t in target_ratios(study)]
    return "\n".join(lines) + "\n"


def _call_parts(row: dict) -> str:
    """``call (setup + steps + evidence)`` of one of our rows, or ``-``."""
    if row.get("call_s") is None:
        return "-"
    ms = [1e3 * row[k] for k in ("setup_s", "median_s", "evidence_s")]
    return f"{row['call_s']:.4g} ({ms[0]:.2f} + {ms[1]:.2f} + {ms[2]:.2f})"


def _heyoka_peer(row: dict, rows: list[dict]) -> dict | None:
    """heyoka's row for one of ours: same problem, precision and span; in double the same
    tolerance, in the wider precisions heyoka's default (its epsilon)."""
    if row["method"] == "heyoka":
        return None
    label = {"quad": "quad (real128)"}.get(row["precision"], row["precision"])
    peers = [r for r in rows if r["method"] == "heyoka" and r["problem"] == row["problem"]
             and r["precision"] == label and r["T"] == row["T"] and r["median_s"]]
    same_tol = [r for r in peers if r["rtol"] == row["rtol"]]
    return (same_tol or ([] if row["precision"] == "double" else peers) or [None])[0]


def _heyoka_ratio(row: dict, rows: list[dict], key: str = "call_s") -> str:
    """Our ``integrate(...)`` call (``key="call_s"``) or ``Propagator.propagate_until``
    (``"propagate_s"``) over heyoka's ``propagate_until``, or ``-``."""
    peer = _heyoka_peer(row, rows)
    if row.get(key) is None or peer is None:
        return "-"
    return f"{row[key] / peer['median_s']:.2f}"


#: "Equal or better final error" (issue 15): at most this factor above heyoka's error (the
#: same method at the same tolerance gives errors that differ in their third digit).
EQUAL_ERROR_FACTOR = 1.25


def speed_targets(study: dict) -> list[str]:
    """Issue 15's comparison with heyoka, one sentence per problem and precision.

    For each heyoka row (double at its two tolerances, real128, 30, 50 and 100 digits) the
    fastest of our Taylor rows in the same precision and span whose final error is at most
    :data:`EQUAL_ERROR_FACTOR` times heyoka's: the whole ``integrate(...)`` call and
    ``Propagator.propagate_until`` (both with the drift evidence) over heyoka's
    ``propagate_until``; target <= 1.0.

    Parameters
    ----------
    study : dict
        The output of :func:`run_study` (or its JSON).

    Returns
    -------
    list of str
        One sentence per heyoka row (none when heyoka is not installed).
    """
    rows = study["rows"]
    out = []
    for peer in rows:
        if peer["method"] != "heyoka" or not peer.get("median_s") or peer["error"] is None:
            continue
        if peer["precision"] == "double" and peer["rtol"] not in (1e-9, 1e-12):
            continue
        precision = {"quad (real128)": "quad"}.get(peer["precision"], peer["precision"])
        ours = [r for r in rows if r["method"] == "taylor" and r["problem"] == peer["problem"]
                and r["precision"] == precision and r["T"] == peer["T"]
                and r.get("call_s") and r["error"] is not None
                and r["error"] <= EQUAL_ERROR_FACTOR * peer["error"]]
        what = f"{peer['problem']}, {peer['precision']}" + (
            f" tol {peer['rtol']:.0e}" if precision == "double" else "") + f", T={peer['T']:g}"
        if not ours:
            near = [r for r in rows if r["method"] == "taylor" and r["problem"] == peer["problem"]
                    and r["precision"] == precision and r["T"] == peer["T"]
                    and r.get("call_s") and r["error"] is not None]
            closest = min(near, key=lambda r: r["error"]) if near else None
            out.append(
                f"{what}: no Taylor row of ours reached heyoka's error {peer['error']:.1e}"
                + (f" (closest: {closest['error']:.1e} at rtol {closest['rtol']:.0e}, "
                   f"{closest['error'] / peer['error']:.1f}x heyoka's error, in "
                   f"{closest['call_s'] / peer['median_s']:.2f}x its time)" if closest else "")
                + " (target missed)"
            )
            continue
        best = min(ours, key=lambda r: r["call_s"])
        ratio = best["call_s"] / peer["median_s"]
        prop = best.get("propagate_s")
        pratio = prop / peer["median_s"] if prop else None
        verdict = "met" if ratio <= 1.0 else (
            "met by Propagator only" if pratio is not None and pratio <= 1.0 else "missed")
        out.append(
            f"{what}: integrate() {best['call_s'] * 1e3:.3g} ms (set-up {best['setup_s'] * 1e3:.2f}"
            f" + steps {best['median_s'] * 1e3:.3g} + evidence {best['evidence_s'] * 1e3:.2f}"
            f" ms, rtol {best['rtol']:.0e}, error {best['error']:.1e})"
            + (f", Propagator {prop * 1e3:.3g} ms" if prop else "")
            + f"; heyoka {peer['median_s'] * 1e3:.3g} ms (error {peer['error']:.1e}); ratio "
            f"{ratio:.2f}" + (f" / {pratio:.2f}" if pratio is not None else "")
            + f" (target <= 1.0: {verdict})"
        )
    return out


def _best(rows, **want):
    out = [r for r in rows if all(r.get(k) == v for k, v in want.items())
           and r["median_s"] is not None and r["error"] is not None]
    return out


def target_ratios(study: dict) -> list[str]:
    """The four targets of issue 5 §4, as measured in this run (plain sentences).

    Against heyoka measured in the same run when it is installed, else against the times
    quoted in the issue (measured on other machines; marked as such).

    Parameters
    ----------
    study : dict
        The output of :func:`run_study`; only its ``reference`` rows and ``rhs_call_s``
        are used.

    Returns
    -------
    list of str
        One sentence per target that the rows allow to assess (double and quad Taylor
        against heyoka, 50 digits against ``mpmath.odefun``, the C right-hand-side call).
    """
    rows = [r for r in study["rows"] if r["problem"] == "reference"]
    msgs = []

    def fastest(method, precision, max_error=None):
        cands = [r for r in _best(rows, method=method, precision=precision)
                 if max_error is None or r["error"] <= max_error]
        return min(cands, key=lambda r: r["median_s"]) if cands else None

    def versus(ours, peer, quoted, what):
        if peer is not None:
            return (f"{ours['median_s'] / peer['median_s']:.1f}x heyoka {what} measured in this "
                    f"run ({peer['median_s'] * 1e3:.2f} ms, error {peer['error']:.1e})")
        return (f"{ours['median_s'] / quoted:.1f}x heyoka {what} quoted in the issue "
                f"({quoted * 1e3:.0f} ms, other machine; heyoka not installed here)")

    r = fastest("taylor", "double", 1e-10)
    if r:
        msgs.append(
            f"double, error <= 1e-10 at T={r['T']:g}: Taylor {r['median_s'] * 1e3:.2f} ms "
            f"(error {r['error']:.1e}, rtol {r['rtol']:.0e}); "
            + versus(r, fastest("heyoka", "double", 1e-10), 1.0e-3, "double") + " (target <= 2x)"
        )
    else:
        msgs.append("double: no Taylor row reached error <= 1e-10 (or Taylor unavailable)")
    q = fastest("taylor", "quad", 1e-32)
    if q:
        digits = -math.log10(max(q["error"], 1e-300))
        msgs.append(
            f"quad, T={q['T']:g}: Taylor {q['median_s'] * 1e3:.1f} ms, error {q['error']:.1e} "
            f"({digits:.1f} digits); "
            + versus(q, fastest("heyoka", "quad (real128)"), 62e-3, "real128") + " (target <= 2x)"
        )
    t50 = fastest("taylor", "50 digits")
    o50 = fastest("odefun", "50 digits")
    if t50 and o50 and t50["T"] == o50["T"]:
        ratio = o50["median_s"] / t50["median_s"]
        h50 = fastest("heyoka", "50 digits")
        extra = ""
        if h50:
            extra = (f"; heyoka 50 digits {h50['median_s']:.3f} s "
                     f"(ours takes {t50['median_s'] / h50['median_s']:.2f}x its time)")
        msgs.append(
            f"50 digits, T={t50['T']:g}: Taylor {t50['median_s']:.3f} s vs mpmath.odefun "
            f"{o50['median_s']:.3f} s: {ratio:.1f}x faster (target >= 10x){extra}"
        )
    rc = study["rhs_call_s"]
    single = [k for k in rc if k.startswith("C, CompiledModel.rhs with out")]
    if single:
        fresh = [k for k in rc if k.startswith("C, CompiledModel.rhs, new output")]
        value = rc[single[0]]
        msgs.append(
            f"rhs call of the compiled C code from Python: {value * 1e9:.0f} ns per call"
            f" ({single[0].split('(')[-1].rstrip(')')}; "
            + (f"{rc[fresh[0]] * 1e9:.0f} ns with a new output array; " if fresh else "")
            + f"cffi alone {rc.get('C via cffi only (per call)', float('nan')) * 1e9:.0f} ns"
            f", batched {rc['C rhs_many, 1000 states (per state)'] * 1e9:.0f} ns per state)"
            f" (target < 300 ns: {'met' if value < 300e-9 else 'missed'})"
        )
    return msgs


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
    (:class:`~chaplygin.numerics.batch_map.BatchStroboscopicMap`, 1, 4 and 16 points per call;
    DOP853 rows ``ours_batch<n>``, Taylor rows ``ours_taylor_batch<n>``)
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
    from ..numerics.batch_map import BatchStroboscopicMap, batch_map_available
    from ..numerics.map_coordinates import state_from_reduced

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
