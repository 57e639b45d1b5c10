"""The compiled MPFR loop at any number of digits: a whole integration in C
(:func:`_mpfr_run`), or one step at a time for event location in Python
(:class:`_MpfrStepper`)."""

from __future__ import annotations

import time

import mpmath
import numpy as np

from ..precision import ARITHMETICS
from .control import jorba_zou_order
from .library import CompiledTaylorMPFR, _mpfr_ffi
from .reals import _mpfr_text, _mpfr_token, _rows_lists, _times_working
from .solution import _MESSAGES, TaylorSolution

__all__ = ["MPFR_TAPER"]

#: Whether the MPFR loop computes the high-order coefficients at lower precision (see
#: ``coefficient_prec`` in ``derive/templates/taylor_mpfr.c``); never with a fixed step.
MPFR_TAPER = True


class _MpfrStepper:
    """One adaptive step at a time of the compiled MPFR integrator (for event location in
    Python), the same steps as :func:`_mpfr_run` and ``_Stepper._py_step``; its work space is
    allocated once, at ``bits`` (the working precision)."""

    def __init__(self, mlib: CompiledTaylorMPFR, p, rtol, atol, order, step, bits: int):
        ffi = _mpfr_ffi
        self.mlib = mlib
        self.width = mlib.width(bits)
        self.ctrl = ffi.new("double[2]", [float(rtol), float(atol)])
        self.p_text = _mpfr_text(p)
        self.fixed_h = _mpfr_text([step]) if step else b""
        self.order = order or 0
        handle = mlib.lib.chaplygin_taylor_mpfr_stepper_new(
            bits, self.ctrl, self.order, MPFR_TAPER and not step
        )
        if handle == ffi.NULL:
            raise ValueError("the MPFR Taylor stepper has no memory or an order out of range")
        self.handle = ffi.gc(handle, mlib.lib.chaplygin_taylor_mpfr_stepper_free)
        n = mlib.n_state
        most = self.order or jorba_zou_order(min(rtol, atol), max_order=mlib.max_order)
        self.ty = ffi.new("char[]", (n + 1) * self.width)
        self.coeffs = ffi.new("char[]", n * (most + 1) * self.width)
        self.h = ffi.new("char[]", self.width)
        self.ord = ffi.new("int *")
        self.backend = "c-mpfr"

    def step(self, t, y, t_end):
        """Advance one step: ``(t_new, y_new, coefficients, h, order, status)`` as
        ``_Stepper.step`` (``h = 0`` and status -3 when the step size underflows)."""
        lib, n, width = self.mlib, self.mlib.n_state, self.width
        status = lib.lib.chaplygin_taylor_mpfr_step(
            self.handle,
            _mpfr_text([t, *y]),
            self.p_text,
            self.ctrl,
            self.fixed_h,
            self.order,
            _mpfr_text([t_end]),
            self.ty,
            self.coeffs,
            self.h,
            self.ord,
            width,
        )
        if status == -5:
            raise ValueError("the MPFR Taylor stepper could not read a number")
        p = self.ord[0]
        if status == -3:
            return t, y, list, mpmath.mpf(0), p, -3
        vals = lib._slots(self.ty, n + 1, width)
        (h,) = lib._slots(self.h, 1, width)
        coeffs = self.coeffs

        def coefficients():  # read before the next step overwrites the buffer
            return _rows_lists(lib._slots(coeffs, n * (p + 1), width), n, p + 1)

        return vals[0], vals[1:], coefficients, h, p, status


def _mpfr_run(mlib, y0, t_span, p, rtol, atol, t_eval, order, step, max_steps, max_wall_s,
              bits):
    """The compiled MPFR loop at ``bits`` (the working precision, whose context the caller
    is in); numbers cross as exact text, a run cut into chunks (wall-time limit) resumes from
    the exact state."""
    ffi, n, prec = _mpfr_ffi, mlib.n_state, bits
    width = mlib.width(prec)
    m = len(t_eval)
    y_eval = ffi.new("char[]", max(m, 1) * n * width)
    y_end, t_reached = ffi.new("char[]", n * width), ffi.new("char[]", width)
    t_text, y_text = _mpfr_text(t_span), _mpfr_text(y0)
    p_text = _mpfr_text(p)
    ctrl = ffi.new("double[2]", [float(rtol), float(atol)])
    fixed_h = _mpfr_text([step]) if step else b""
    stats = ffi.new("long[4]")
    tokens = [_mpfr_token(v) for v in t_eval]
    chunk = max_steps if max_wall_s is None else ARITHMETICS["mpfr"].chunk_steps
    deadline = None if max_wall_s is None else time.perf_counter() + max_wall_s
    steps, pmax, pmin, done = 0, 0, 10**9, 0
    while True:
        left = max_steps - steps
        status = mlib.lib.chaplygin_taylor_mpfr_run(
            prec,
            t_text,
            y_text,
            p_text,
            ctrl,
            fixed_h,
            order or 0,
            MPFR_TAPER and not step,
            m - done,
            " ".join(tokens[done:]).encode("ascii"),
            y_eval + done * n * width,
            width,
            y_end,
            t_reached,
            min(chunk, left),
            stats,
        )
        if status in (-4, -5, -7):
            raise ValueError(f"the MPFR Taylor integrator failed (status {status})")
        steps += int(stats[0])
        if stats[0]:
            pmax, pmin = max(pmax, int(stats[1])), min(pmin, int(stats[2]))
        done += int(stats[3])
        if status != -2 or steps >= max_steps:
            break
        if deadline is not None and time.perf_counter() > deadline:
            status = -6
            break
        # resume exactly where the call stopped: its time and state, as MPFR holds them
        t_text = ffi.string(t_reached) + b" " + _mpfr_text(t_span[1:])
        y_text = b" ".join(ffi.string(y_end + i * width) for i in range(n))
    flat = mlib._slots(y_eval, done * n, width)
    y_out = np.array(_rows_lists(flat, done, n), dtype=object).reshape(done, n).T.copy()
    return TaylorSolution(
        t=_times_working(t_eval[:done]),
        y=y_out,
        status=int(status),
        message=_MESSAGES.get(int(status), "failed"),
        nsteps=steps,
        order_min=pmin if steps else 0,
        order_max=pmax,
        backend="c-mpfr",
    )
