"""cbrt and hypot of :mod:`.detmath`, bit for bit ``detmath.h``.

The real cube root (a polynomial guess, one Halley step, one Newton step with the exact
residual) and ``sqrt(x^2 + y^2)`` as a double-double after exact scaling. The kernels, then the
scalar port on Python floats and the numpy port on float64 arrays, each the C function of the
same name, operation for operation (see :mod:`.detmath_core`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .detmath_core import (
    _CBRT_POLY,
    _INF,
    _NAN,
    _S,
    _U52,
    _V,
    Float,
    _fast_two_sum,
    _scale,
    _two_prod,
    _vscale,
)


def _cbrt_core(m: Any, j: Any, o: Any) -> Any:
    """cbrt(m 2^j) for m in [1, 2), j in {0, 1, 2}: guess, Halley, Newton with exact residual."""
    c = _CBRT_POLY
    a = m * o.pow2(j)
    y = (((((c[0] * m + c[1]) * m + c[2]) * m + c[3]) * m + c[4]) * m + c[5]) * o.take(
        "CBRT_2J", j)
    y3 = (y * y) * y
    y = y * ((y3 + 2.0 * a) / (2.0 * y3 + a))
    p, pe = _two_prod(y, y)
    cc, ce = _two_prod(y, p)
    res = ((a - cc) - ce) - y * pe
    return y + res / (3.0 * p)


def _hypot_core(M: Any, m: Any, o: Any) -> tuple[Any, Any]:
    """sqrt(M^2 + m^2) as a double-double for M in [1, 2), m in [2^-60, M]."""
    a, ae = _two_prod(M, M)
    b, be = _two_prod(m, m)
    s, se = _fast_two_sum(a, b)
    t = se + (ae + be)
    wh, wl = _fast_two_sum(s, t)
    r = o.sqrt(wh)
    q, qe = _two_prod(r, r)
    corr = (((wh - q) - qe) + wl) / (r + r)
    return _fast_two_sum(r, corr)


# =========================================================================== scalar port


def _cbrt_s(x: float) -> float:
    ax = abs(x)
    if ax == 0.0 or ax == _INF:
        return x
    if ax != ax:
        return _NAN
    adj = 0
    if ax < 2.0**-1022:
        ax *= 2.0**54
        adj = -18
    ia = _S.bits(ax)
    e = (ia >> 52) - 1023
    m = _S.double((ia & 0x000FFFFFFFFFFFFF) | 0x3FF0000000000000)
    q = (e + 3075) // 3 - 1025
    r = _cbrt_core(m, e - 3 * q, _S) * _S.pow2(q + adj)
    return -r if x < 0.0 else r


def _hypot_s(x: float, y: float) -> float:
    ax = abs(x)
    ay = abs(y)
    if ax == _INF or ay == _INF:
        return _INF
    if ax != ax or ay != ay:
        return _NAN
    M = ax if ax > ay else ay
    m = ay if ax > ay else ax
    if m == 0.0:
        return M
    K = 0
    if M > 2.0**1000:
        M *= 2.0**-600
        m *= 2.0**-600
        K = 600
    elif M < 2.0**-1000:
        M *= 2.0**600
        m *= 2.0**600
        K = -600
    k = (_S.bits(M) >> 52) - 1023
    f = _S.pow2(-k)
    M *= f
    m *= f
    if m < 2.0**-60:
        return ax if ax > ay else ay
    hh, hl = _hypot_core(M, m, _S)
    return _scale(hh, hl, K + k)


# =========================================================================== numpy port
#
# A branch of the C code becomes a partition of the elements: each element follows exactly its
# own branch's operations (the others' lanes are computed on harmless stand-in values and
# discarded by np.where), hence np.errstate(all="ignore") around every public call.


def _vcbrt(x: Float) -> Float:
    ax0 = np.abs(x)
    regular = (ax0 > 0.0) & (ax0 < _INF)
    ax = np.where(regular, ax0, 1.0)
    sub = ax < 2.0**-1022
    ax = np.where(sub, ax * 2.0**54, ax)
    ia = _V.bits(ax)
    e = (ia >> _U52).astype(np.int64) - 1023
    m = _V.double((ia & np.uint64(0x000FFFFFFFFFFFFF)) | np.uint64(0x3FF0000000000000))
    q = (e + 3075) // 3 - 1025
    r = _cbrt_core(m, e - 3 * q, _V) * _V.pow2(q + np.where(sub, -18, 0))
    r = np.where(x < 0.0, -r, r)
    r = np.where(regular, r, x)
    return np.where(np.isnan(x), _NAN, r)


def _vhypot(x: Float, y: Float) -> Float:
    ax = np.abs(x)
    ay = np.abs(y)
    M0 = np.where(ax > ay, ax, ay)
    m0 = np.where(ax > ay, ay, ax)
    regular = (m0 > 0.0) & (M0 < _INF)
    M = np.where(regular, M0, 1.0)
    m = np.where(regular, m0, 1.0)
    big = M > 2.0**1000
    tiny = M < 2.0**-1000
    M = np.where(big, M * 2.0**-600, np.where(tiny, M * 2.0**600, M))
    m = np.where(big, m * 2.0**-600, np.where(tiny, m * 2.0**600, m))
    k = (_V.bits(M) >> _U52).astype(np.int64) - 1023
    f = _V.pow2(-k)
    M = M * f
    m = m * f
    hh, hl = _hypot_core(M, m, _V)
    res = _vscale(hh, hl, np.where(big, 600, np.where(tiny, -600, 0)) + k)
    res = np.where(m < 2.0**-60, M0, res)
    res = np.where(m0 == 0.0, M0, res)
    res = np.where(np.isnan(ax) | np.isnan(ay), _NAN, res)
    return np.where((ax == _INF) | (ay == _INF), _INF, res)
