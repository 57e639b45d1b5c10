"""exp, log, log2, log10, pow, sinh and cosh of :mod:`.detmath`, bit for bit ``detmath.h``.

The kernels (``e^x`` by a table of 2^(j/128) and a polynomial; ``log`` by a table of 1/r and
log1p of the exactly reduced argument, also as a double-double for ``pow``; ``sinh`` of small
arguments by its series), then the scalar port on Python floats and the numpy port on float64
arrays, each the C function of the same name, operation for operation (see
:mod:`.detmath_core`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .detmath_core import (
    _A,
    _EXP_INV_LN2_N,
    _EXP_LN2_N_HI,
    _EXP_LN2_N_LO,
    _EXP_POLY,
    _INF,
    _LN2_HI,
    _LN2_LO,
    _LOG_BASES,
    _LOG_POLY,
    _LOGDD_POLY,
    _M64,
    _NAN,
    _S,
    _SHIFT,
    _SINH_POLY,
    _SQRT2_HALF_BITS,
    _T,
    _U52,
    _U63,
    _V,
    Float,
    _fast_two_sum,
    _scale,
    _two_prod,
    _vscale,
)


def _exp_kernel(xh: Any, xl: Any, o: Any) -> tuple[Any, Any, Any]:
    z = xh * _EXP_INV_LN2_N
    kd = (z + _SHIFT) - _SHIFT
    k = o.index(kd, -(2**40), 2**40)
    j = k & 127
    t = xh - kd * _EXP_LN2_N_HI
    r = t + (xl - kd * _EXP_LN2_N_LO)
    r2 = r * r
    c = _EXP_POLY
    q = (c[0] + r * c[1]) + r2 * ((c[2] + r * c[3]) + r2 * c[4])
    p = r + r2 * q
    th = o.take("EXP_T_HI", j)
    small = o.take("EXP_T_LO", j) + th * p
    h, l = _fast_two_sum(th, small)
    return h, l, (k - j) // 128


def _exp_pm(ax: Any, o: Any) -> tuple[Any, Any, Any, Any]:
    h, l, m = _exp_kernel(-ax, 0.0, o)
    f = o.pow2(m)
    ih, il = h * f, l * f
    h, l, m = _exp_kernel(ax, 0.0, o)
    f = o.pow2(m)
    return h * f, l * f, ih, il


def _log_poly(uh: Any, c: tuple[float, ...]) -> Any:
    u2 = uh * uh
    return ((c[0] + uh * c[1]) + u2 * (c[2] + uh * c[3])) + (u2 * u2) * (c[4] + uh * c[5])


def _log_core(idx: Any, e: Any, uh: Any, ul: Any, o: Any) -> Any:
    ed = o.tofloat(e)
    H = ed * _LN2_HI + o.take("LOG_L_HI", idx)
    lo = ed * _LN2_LO + o.take("LOG_L_LO", idx)
    s, es = _fast_two_sum(H, uh)
    return s + (es + (ul + (lo + (uh * uh) * _log_poly(uh, _LOG_POLY))))


def _log_base_core(idx: Any, e: Any, uh: Any, ul: Any, base: str, o: Any) -> Any:
    eh, el, lh, ll, kh, kl, poly = _LOG_BASES[base]
    ed = o.tofloat(e)
    H = ed * eh + o.take(lh, idx)
    lo = ed * el + o.take(ll, idx)
    p, pe = _two_prod(uh, kh)
    s, es = _fast_two_sum(H, p)
    q = _log_poly(uh, _T[poly])
    return s + (es + ((pe + (uh * kl + ul * kh)) + (lo + (uh * uh) * q)))


def _log_dd_core(idx: Any, e: Any, uh: Any, ul: Any, o: Any) -> tuple[Any, Any]:
    ed = o.tofloat(e)
    H = ed * _LN2_HI + o.take("LOG_L_HI", idx)
    lo = ed * _LN2_LO + o.take("LOG_L_LO", idx)
    s1, e1 = _fast_two_sum(H, uh)
    q, qe = _two_prod(uh, uh)
    s2, e2 = _fast_two_sum(s1, -0.5 * q)
    c = _LOGDD_POLY
    R = ((c[0] + uh * c[1]) + q * (c[2] + uh * c[3])) + (q * q) * (c[4] + uh * c[5])
    tail = ((e1 + e2) + (ul - 0.5 * qe)) + ((lo - uh * ul) + (uh * q) * R)
    return _fast_two_sum(s2, tail)


def _sinh_small(ax: Any) -> Any:
    c = _SINH_POLY
    z = ax * ax
    z2 = z * z
    P = ((c[0] + z * c[1]) + z2 * (c[2] + z * c[3])) + (z2 * z2) * (c[4] + z * c[5])
    return ax + (ax * z) * P


# =========================================================================== scalar port


def _exp_s(x: float) -> float:
    if not x <= 709.8:
        return _NAN if x != x else _INF
    if x < -746.0:
        return 0.0
    h, l, m = _exp_kernel(x, 0.0, _S)
    return _scale(h, l, m)


def _log_reduce(x: float) -> tuple[int, int, float, float]:
    ix = _S.bits(x)
    adj = 0
    if ix < 0x0010000000000000:
        ix = _S.bits(x * 2.0**54)
        adj = -54
    top = (ix + ((1024 << 52) - _SQRT2_HALF_BITS)) >> 52
    e = top - 1024 + adj
    mb = ix - (top << 52) + (1024 << 52)
    m = _S.double(mb)
    below = 1023 - (mb >> 52)
    sh = 44 + below
    idx = (((mb & 0x000FFFFFFFFFFFFF) + (1 << (sh - 1))) >> sh) - 128 * below + 75
    r = _T["LOG_R"][idx]
    mh = _S.double(mb & ~0x7FF)
    ml = m - mh
    t1 = mh * r - 1.0
    t2 = ml * r
    uh, ul = _fast_two_sum(t1, t2)
    return idx, e, uh, ul


def _log_special(x: float) -> float | None:
    ix = _S.bits(x)
    if 0 < ix < 0x7FF0000000000000:
        return None
    if x == 0.0:
        return -_INF
    if ix == 0x7FF0000000000000:
        return x
    return _NAN


def _log_s(x: float) -> float:
    special = _log_special(x)
    return _log_core(*_log_reduce(x), _S) if special is None else special


def _log_base_s(x: float, base: str) -> float:
    special = _log_special(x)
    return _log_base_core(*_log_reduce(x), base, _S) if special is None else special


def _integer_kind(y: float) -> int:
    ay = abs(y)
    if not ay < 2.0**53:
        return 2
    k = int(ay)
    if float(k) != ay:
        return 0
    return 1 if k & 1 else 2


def _pow_abs(ax: float, y: float) -> float:
    lh, ll = _log_dd_core(*_log_reduce(ax), _S)
    ph, pe = _two_prod(y, lh)
    pl = pe + y * ll
    if ph > 709.8:
        return _INF
    if ph < -746.0:
        return 0.0
    h, l, m = _exp_kernel(ph, pl, _S)
    return _scale(h, l, m)


def _pow_s(x: float, y: float) -> float:
    ax = abs(x)
    if 0.0 < x < _INF and abs(y) < 2.0**64:
        return _pow_abs(x, y)
    if y == 0.0 or x == 1.0:
        return 1.0
    if x != x or y != y:
        return _NAN
    kind = _integer_kind(y)
    negative = (_S.bits(x) >> 63) == 1 and kind == 1
    if x == 0.0:
        if y < 0.0:
            return -_INF if negative else _INF
        return -0.0 if negative else 0.0
    if abs(y) == _INF:
        if ax == 1.0:
            return 1.0
        return _INF if (ax < 1.0) == (y < 0.0) else 0.0
    if ax == _INF:
        if y < 0.0:
            return -0.0 if negative else 0.0
        return -_INF if negative else _INF
    if x < 0.0 and kind == 0:
        return _NAN
    if not abs(y) < 2.0**64:
        if ax == 1.0:
            return 1.0
        return _INF if (ax > 1.0) == (y > 0.0) else 0.0
    res = _pow_abs(ax, y)
    return -res if negative else res


def _sinh_s(x: float) -> float:
    ax = abs(x)
    if ax < 0.25:
        res = _sinh_small(ax)
    elif ax != ax:
        return _NAN
    elif ax > 22.0:
        if ax > 711.0:
            res = _INF
        else:
            h, l, m = _exp_kernel(ax, 0.0, _S)
            res = _scale(h, l, m - 1)
    else:
        eh, el, ih, il = _exp_pm(ax, _S)
        s, e = _fast_two_sum(eh, -ih)
        res = 0.5 * (s + (e + (el - il)))
    return -res if (_S.bits(x) >> 63) == 1 else res


def _cosh_s(x: float) -> float:
    ax = abs(x)
    if ax != ax:
        return _NAN
    if ax < 2.0**-27:
        return 1.0
    if ax > 22.0:
        if ax > 711.0:
            return _INF
        h, l, m = _exp_kernel(ax, 0.0, _S)
        return _scale(h, l, m - 1)
    eh, el, ih, il = _exp_pm(ax, _S)
    s, e = _fast_two_sum(eh, ih)
    return 0.5 * (s + (e + (el + il)))


# =========================================================================== numpy port
#
# A branch of the C code becomes a partition of the elements: each element follows exactly its
# own branch's operations (the others' lanes are computed on harmless stand-in values and
# discarded by np.where), hence np.errstate(all="ignore") around every public call.


def _vexp(x: Float) -> Float:
    ok = (x <= 709.8) & (x >= -746.0)
    h, l, m = _exp_kernel(np.where(ok, x, 0.0), 0.0, _V)
    out = _vscale(h, l, m)
    out = np.where(x < -746.0, 0.0, out)
    out = np.where(x > 709.8, _INF, out)
    return np.where(np.isnan(x), _NAN, out)


def _vlog_reduce(x: Float) -> tuple[NDArray[np.int64], NDArray[np.int64], Float, Float]:
    ix = _V.bits(x).copy()
    sub = ix < np.uint64(0x0010000000000000)
    ix[sub] = _V.bits(x[sub] * 2.0**54)
    adj = np.where(sub, -54, 0)
    top = (ix + np.uint64((1024 << 52) - _SQRT2_HALF_BITS)) >> _U52
    e = top.astype(np.int64) - 1024 + adj
    mb = ix - (top << _U52) + np.uint64(1024 << 52)
    m = _V.double(mb)
    below = (np.uint64(1023) - (mb >> _U52)).astype(np.int64)
    sh = (44 + below).astype(np.uint64)
    rounded = ((mb & np.uint64(0x000FFFFFFFFFFFFF)) + (np.uint64(1) << (sh - np.uint64(1)))) >> sh
    idx = rounded.astype(np.int64) - 128 * below + 75
    r = _A["LOG_R"][idx]
    mh = _V.double(mb & np.uint64(~0x7FF & _M64))
    ml = m - mh
    t1 = mh * r - 1.0
    t2 = ml * r
    uh, ul = _fast_two_sum(t1, t2)
    return idx, e, uh, ul


def _vlog_family(x: Float, core: Any) -> Float:
    """log, log2 or log10 (``core`` after the reduction) with the special values."""
    ok = (x > 0.0) & (x < _INF)
    special = np.where(x == 0.0, -_INF, np.where(x == _INF, _INF, _NAN))
    out = core(*_vlog_reduce(np.where(ok, x, 1.0)))
    return np.where(ok, out, special)


def _vlog(x: Float) -> Float:
    return _vlog_family(x, lambda *reduced: _log_core(*reduced, _V))


def _vlog_base(x: Float, base: str) -> Float:
    return _vlog_family(x, lambda *reduced: _log_base_core(*reduced, base, _V))


def _vpow(x: Float, y: Float) -> Float:
    ax = np.abs(x)
    ay = np.abs(y)
    # integer kind of y: 0 not an integer, 1 odd, 2 even (|y| >= 2^53 and infinities even)
    small = ay < 2.0**53
    ays = np.where(small, ay, 0.0)
    k = ays.astype(np.int64)
    kind = np.where(small, np.where(k.astype(np.float64) != ays, 0, np.where(k & 1, 1, 2)), 2)
    negative = ((_V.bits(x) >> _U63) == 1) & (kind == 1)
    xinf = ax == _INF
    yinf = ay == _INF
    # the general path on sanitised lanes
    general = ~((y == 0.0) | (x == 1.0) | np.isnan(x) | np.isnan(y) | (x == 0.0) | yinf | xinf
                | ((x < 0.0) & (kind == 0)) | ~(ay < 2.0**64))  # fmt: skip
    ys = np.where(general, y, 1.0)
    lh, ll = _log_dd_core(*_vlog_reduce(np.where(general, ax, 2.0)), _V)
    ph, pe = _two_prod(ys, lh)
    pl = pe + ys * ll
    mid = (ph <= 709.8) & (ph >= -746.0)
    h, l, m = _exp_kernel(np.where(mid, ph, 0.0), np.where(mid, pl, 0.0), _V)
    res = _vscale(h, l, m)
    res = np.where(ph > 709.8, _INF, np.where(ph < -746.0, 0.0, res))
    res = np.where(negative, -res, res)
    # the special cases, the C code's order reversed
    big_y = np.where(ax == 1.0, 1.0, np.where((ax > 1.0) == (y > 0.0), _INF, 0.0))
    res = np.where(~(ay < 2.0**64), big_y, res)
    res = np.where((x < 0.0) & (kind == 0), _NAN, res)
    x_inf = np.where(y < 0.0, np.where(negative, -0.0, 0.0), np.where(negative, -_INF, _INF))
    res = np.where(xinf, x_inf, res)
    y_inf = np.where(ax == 1.0, 1.0, np.where((ax < 1.0) == (y < 0.0), _INF, 0.0))
    res = np.where(yinf, y_inf, res)
    x_zero = np.where(y < 0.0, np.where(negative, -_INF, _INF), np.where(negative, -0.0, 0.0))
    res = np.where(x == 0.0, x_zero, res)
    res = np.where(np.isnan(x) | np.isnan(y), _NAN, res)
    return np.where((y == 0.0) | (x == 1.0), 1.0, res)


def _vexp_half(ax: Float) -> Float:
    """e^ax / 2 for 22 < ax (inf above 711)."""
    h, l, m = _exp_kernel(np.where(ax <= 711.0, ax, 0.0), 0.0, _V)
    return np.where(ax > 711.0, _INF, _vscale(h, l, m - 1))


def _vsinh(x: Float) -> Float:
    ax = np.abs(x)
    eh, el, ih, il = _exp_pm(np.where((ax >= 0.25) & (ax <= 22.0), ax, 1.0), _V)
    s, e = _fast_two_sum(eh, -ih)
    res_mid = 0.5 * (s + (e + (el - il)))
    large = ax > 22.0
    res_large = _vexp_half(np.where(large, ax, 23.0))
    res = np.where(ax < 0.25, _sinh_small(ax), np.where(large, res_large, res_mid))
    res = np.where((_V.bits(x) >> _U63) == 1, -res, res)
    return np.where(np.isnan(x), _NAN, res)


def _vcosh(x: Float) -> Float:
    ax = np.abs(x)
    eh, el, ih, il = _exp_pm(np.where((ax >= 2.0**-27) & (ax <= 22.0), ax, 1.0), _V)
    s, e = _fast_two_sum(eh, ih)
    res = 0.5 * (s + (e + (el + il)))
    large = ax > 22.0
    res = np.where(large, _vexp_half(np.where(large, ax, 23.0)), res)
    res = np.where(ax < 2.0**-27, 1.0, res)
    return np.where(np.isnan(x), _NAN, res)
