"""One Taylor step at a time and the loop that drives it in Python.

The number namespaces of the generated Python recurrences (:func:`python_lib`), the stepper
(:class:`_Stepper`: a step of the compiled double/quad library, or of the Python
recurrences in floats, MPFR or mpmath numbers), the step polynomials and event location on
them, and the loop (:func:`_py_run`) used for events and for the Python backends.
"""

from __future__ import annotations

import math
import time
import types
from collections.abc import Sequence
from typing import Any

import gmpy2
import mpmath
import numpy as np

from ...arith import detmath
from ..precision import Precision
from .control import PY_MAX_ORDER, jorba_zou_order
from .library import CompiledTaylor, _ffi
from .reals import _to_mpf
from .solution import _MESSAGES, TaylorSolution

__all__ = ["python_lib"]

# --------------------------------------------------------------------------- Python libs


def python_lib(kind: str) -> types.SimpleNamespace:
    """Number namespace for the generated Python recurrences.

    ``"float"`` (math), ``"mpmath"`` (the ``mpmath.mp`` context) or ``"gmpy2"`` (MPFR at
    the precision of the active gmpy2 context).

    Parameters
    ----------
    kind : {"float", "mpmath", "gmpy2"}
        The number library.

    Returns
    -------
    types.SimpleNamespace
        ``mpf`` (the number constructor), ``sqrt``, ``exp``, ``sin``, ``cos``, ``log``;
        gmpy2 also ``fsum`` (correctly rounded sums of the recurrences).

    Raises
    ------
    ValueError
        An unknown ``kind``.
    """
    if kind == "float":
        return types.SimpleNamespace(
            mpf=float, sqrt=math.sqrt, exp=detmath.exp, sin=detmath.sin, cos=detmath.cos,
            log=detmath.log,
        )
    if kind == "mpmath":
        return types.SimpleNamespace(
            mpf=mpmath.mpf,
            sqrt=mpmath.sqrt,
            exp=mpmath.exp,
            sin=mpmath.sin,
            cos=mpmath.cos,
            log=mpmath.log,
        )
    if kind == "gmpy2":
        return types.SimpleNamespace(
            mpf=gmpy2.mpfr,
            sqrt=gmpy2.sqrt,
            exp=gmpy2.exp,
            sin=gmpy2.sin,
            cos=gmpy2.cos,
            log=gmpy2.log,
            fsum=_mpfr_sum,
        )
    raise ValueError(f"unknown number library {kind!r}")


def _mpfr_sum(values) -> gmpy2.mpfr:
    """Correctly rounded sum (``mpfr_sum``) of the values: one call instead of one Python
    addition per term, and no rounding of the partial sums."""
    return gmpy2.fsum(list(values))


def _from_mpf(x, lib_kind: str):
    if lib_kind == "float":
        return float(x)
    if lib_kind == "mpmath":
        return +mpmath.mpf(x)
    x = mpmath.mpf(x)
    sign, man, exp, _ = x._mpf_
    if man == 0:
        return gmpy2.mpfr(0)
    v = gmpy2.mul_2exp(gmpy2.mpfr(gmpy2.mpz(man)), int(exp))
    return -v if sign else v


def _loop_vector(precision: Precision, values: Sequence) -> Any:
    """A state as the Python loop's vector: a float64 array in double, a list of ``mpf``."""
    if precision.is_double:
        return np.asarray(values, dtype=float)
    return [mpmath.mpf(v) for v in values]


def _loop_linspace(precision: Precision, a: Any, b: Any, n: int) -> Sequence:
    """``n`` equispaced output times from ``a`` to ``b`` in the precision's numbers."""
    if precision.is_double:
        return np.linspace(float(a), float(b), n)
    return mpmath.linspace(mpmath.mpf(a), mpmath.mpf(b), n)


class _Stepper:
    """One adaptive step in the chosen number system; ``step`` returns the polynomial."""

    def __init__(self, code, numbers, p, rtol, atol, order, step, lib: CompiledTaylor | None):
        self.clib = lib
        self.rtol, self.atol = rtol, atol
        self.order, self.fixed_h = order, step
        if lib is not None:
            self.P = lib.pack(p)
            self.ctrl = lib.pack([rtol, atol, step or 0])
            self.coeffs = lib.empty(lib.n_state * (lib.max_order + 1))
            self.h = lib.empty(1)
            self.ty = lib.empty(lib.n_state + 1)
            self.ord = _ffi.new("int *")
            self.backend = f"c-{lib.kind}"
        else:
            self.lib_kind = numbers  # "float", "gmpy2" or "mpmath" (python_lib)
            self.lib = python_lib(self.lib_kind)
            self.fn = code.taylor.taylor_coefficients
            self.p = [_from_mpf(v, self.lib_kind) for v in p]
            self.backend = f"python-{self.lib_kind}"

    # values used by Python-side event code: floats (double) or mpf
    def step(self, t, y, t_end):
        """Advance one step: ``(t_new, y_new, coefficients, h, order, status)``;
        ``coefficients()`` gives the step's Taylor coefficients (the state at ``t + s`` by
        :func:`_eval_poly`), to be called before the next step."""
        if self.clib is not None:
            return self._c_step(t, y, t_end)
        return self._py_step(t, y, t_end)

    def _c_step(self, t, y, t_end):
        lib = self.clib
        n = lib.n_state
        ty = lib.pack([t, *y])
        tend = lib.pack([t_end])
        ptr = CompiledTaylor._ptr
        status = lib.lib.chaplygin_taylor_step(
            ptr(ty),
            ptr(self.P),
            ptr(self.ctrl),
            self.order or 0,
            ptr(tend),
            ptr(self.coeffs),
            ptr(self.h),
            self.ord,
        )
        p = self.ord[0]
        S = p + 1
        coeffs = self.coeffs

        def coefficients():  # read before the next step overwrites the buffer
            return lib.real.rows(lib.unpack(coeffs, n * S), n, S)

        (h,) = lib.unpack(self.h, 1)
        vals = lib.unpack(ty, n + 1)
        return vals[0], vals[1:], coefficients, h, p, status

    def _py_step(self, t, y, t_end):
        L, kind = self.lib, self.lib_kind
        tt = _from_mpf(t, kind)
        yy = [_from_mpf(v, kind) for v in y]
        xn = max(abs(v) for v in yy)
        absolute = self.rtol * float(xn) <= self.atol
        scale = L.mpf(1) if absolute else xn
        eps = self.atol if absolute else self.rtol
        # Python recurrences have no order limit: the Jorba-Zou order for any digits (the
        # C cap of 80 would leave a truncation error e^(-2 p) ~ 1e-70 at 100 digits)
        p = self.order or jorba_zou_order(eps, max_order=PY_MAX_ORDER)
        C = self.fn(tt, yy, self.p, p, L)
        remaining = _from_mpf(t_end, kind) - tt
        if self.fixed_h:
            h = _from_mpf(self.fixed_h, kind)
        else:
            rho = math.inf
            for k in (p - 1, p):
                nk = max(abs(c[k]) for c in C)
                if nk > 0:
                    rho = min(rho, detmath.exp(float(L.log(scale) - L.log(nk)) / k))
            # e^-2 is eps^(1/(p-1)) at the Jorba-Zou order; a lower (fixed or capped) order
            # needs the smaller eps^(1/(p-1)) to keep the truncation error below eps
            factor = min(-2.0, detmath.log(eps) / (p - 1)) - 0.7 / (p - 1)
            h = abs(remaining) if math.isinf(rho) else L.mpf(rho * detmath.exp(factor))
        if h >= abs(remaining):
            h, t_new = remaining, _from_mpf(t_end, kind)
        else:
            h = h if remaining > 0 else -h
            t_new = tt + h
        y_new = [_horner(c, h) for c in C]
        status = 0 if all(math.isfinite(float(v)) for v in y_new) else -1
        if kind == "float":
            C = np.array(C)
            return t_new, np.array(y_new), lambda: C, h, p, status
        return (
            _to_mpf(t_new),
            [_to_mpf(v) for v in y_new],
            lambda: [[_to_mpf(v) for v in c] for c in C],  # only for dense output, events
            _to_mpf(h),
            p,
            status,
        )


def _horner(c: Sequence, s):
    v = c[-1]
    for a in reversed(c[:-1]):
        v = v * s + a
    return v


def _eval_poly(C, s):
    """State at offset ``s`` from the Taylor coefficients of a step."""
    if isinstance(C, np.ndarray):
        v = C[:, -1].copy()
        for k in range(C.shape[1] - 2, -1, -1):
            v = v * s + C[:, k]
        return v
    return [_horner(c, s) for c in C]


def _locate(g, t, C, h, g0, g1, eps):
    """Root of ``g(t + s, poly(s))`` in ``s`` between 0 (value g0) and h (value g1).

    Illinois (modified regula falsi) with bisection safeguard, to a bracket of relative width
    ``eps`` (the working precision).
    """
    a, b, fa, fb = 0 * h, h, g0, g1
    side = 0
    tol = eps * max(abs(t), abs(t + h), 1) * 4
    for _ in range(400):
        if abs(b - a) <= tol:
            break
        s = b - fb * (b - a) / (fb - fa) if fb != fa else (a + b) / 2
        if not (min(a, b) < s < max(a, b)):
            s = (a + b) / 2
        fs = g(t + s, _eval_poly(C, s))
        if fs == 0:
            return s
        if (fs > 0) == (fb > 0):
            b, fb = s, fs
            if side == -1:
                fa /= 2
            side = -1
        else:
            a, fa = s, fs
            if side == 1:
                fb /= 2
            side = 1
        if abs(b - a) <= tol:
            break
    return a if abs(fa) < abs(fb) else b


def _py_run(stepper, y0, t_span, t_eval, events, max_steps, precision, max_wall_s=None):
    t, t1 = precision.number(t_span[0]), precision.number(t_span[1])
    y = _loop_vector(precision, y0)
    eps = precision.unit_roundoff()
    direction = 1 if t1 > t else -1
    ts, ys = [], []
    j = 0
    while j < len(t_eval) and direction * (t_eval[j] - t) <= 0:
        ts.append(t_eval[j])
        ys.append(list(y))
        j += 1
    g_prev = [g(t, y) for g in events]
    t_events: list[list] = [[] for _ in events]
    y_events: list[list] = [[] for _ in events]
    nsteps, omin, omax, status = 0, 10**9, 0, 0
    deadline = None if max_wall_s is None else time.perf_counter() + max_wall_s
    stop, y_stop = False, None
    while direction * (t1 - t) > 0 and not stop:
        if nsteps >= max_steps:
            status = -2
            break
        if deadline is not None and time.perf_counter() > deadline:
            status = -6
            break
        t_new, y_new, coefficients, h, p, status = stepper.step(t, y, t1)
        C = None  # the step's polynomial, converted when an event or output needs it
        nsteps += 1
        omin, omax = min(omin, p), max(omax, p)
        if h == 0:
            status = -3
            break
        t_stop = t_new
        for i, g in enumerate(events):
            g_new = g(t_new, y_new)
            g0 = g_prev[i]
            crossing = (g0 < 0 < g_new) or (g0 > 0 > g_new) or (g_new == 0 and g0 != 0)
            want = getattr(g, "direction", 0)
            if crossing and (want == 0 or (want > 0) == (g_new > g0)):
                C = coefficients() if C is None else C
                s = _locate(g, t, C, h, g0, g_new, eps)
                te = t + s
                ye = _eval_poly(C, s)
                t_events[i].append(te)
                y_events[i].append(list(ye))
                if getattr(g, "terminal", False) and (not stop or direction * (te - t_stop) < 0):
                    stop, t_stop, y_stop = True, te, list(ye)
            g_prev[i] = g_new
        while j < len(t_eval) and direction * (t_eval[j] - t_stop) <= 0:
            C = coefficients() if C is None else C
            ts.append(t_eval[j])
            ys.append(list(_eval_poly(C, t_eval[j] - t)))
            j += 1
        if stop:
            ts.append(t_stop)
            ys.append(y_stop)
        t, y = t_new, y_new
        if status:
            break
    n = len(y0)
    dtype = precision.dtype
    ty = np.array([precision.number(v) for v in ts], dtype=dtype)
    yy = np.array(ys, dtype=dtype).T if ys else np.empty((n, 0), dtype=dtype)
    te = [np.array(v, dtype=dtype) for v in t_events]
    ye = [np.array(v, dtype=dtype).reshape(-1, n) for v in y_events]
    msg = _MESSAGES.get(status, "failed")
    if stop:
        msg = "a terminal event occurred"
    return TaylorSolution(
        t=ty,
        y=yy,
        status=status,
        message=msg,
        nsteps=nsteps,
        order_min=omin if nsteps else 0,
        order_max=omax,
        backend=stepper.backend,
        t_events=te,
        y_events=ye,
    )
