"""sin and cos of :mod:`.detmath`, bit for bit ``detmath.h``, right for every finite argument.

Reduction modulo pi/2 by Cody-Waite below 2^20 and by Payne-Hanek (the bits of 2/pi, exact
integer products) above; the reduced argument, a double-double in [-pi/4, pi/4], goes to a
polynomial below 1/8 and to a table of sin/cos(i/128) above. The kernels, then the scalar port
on Python floats and the numpy port on float64 arrays, each the C function of the same name,
operation for operation (see :mod:`.detmath_core`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .detmath_core import (
    _COS_POLY,
    _COSD_POLY,
    _CW_P1,
    _CW_P2,
    _CW_P3,
    _CW_P4,
    _INF,
    _INV_PIO2,
    _M64,
    _NAN,
    _PI_O4,
    _PIO2_HI,
    _PIO2_LO,
    _S,
    _SHIFT,
    _SIN_POLY,
    _SIND_POLY,
    _T,
    _TWO_OVER_PI_BITS,
    _U52,
    _V,
    Float,
    _fast_two_sum,
    _two_prod,
    _two_sum,
)


def _sin_small(rh: Any, rl: Any) -> Any:
    c = _SIN_POLY
    z = rh * rh
    z2 = z * z
    P = (c[0] + z * c[1]) + z2 * ((c[2] + z * c[3]) + z2 * c[4])
    return rh + (rl + ((rh * z) * P - (0.5 * z) * rl))


def _cos_small(rh: Any, rl: Any) -> Any:
    c = _COS_POLY
    z = rh * rh
    z2 = z * z
    hz = 0.5 * z
    w = 1.0 - hz
    err = (1.0 - w) - hz
    Q = (c[1] + z * c[2]) + z2 * (c[3] + z * c[4])
    return w + (err + (z2 * Q - rh * rl))


def _trig_split(rh: Any, rl: Any, o: Any) -> tuple[Any, ...]:
    """The table path of the kernels: sign, xl, dh, sin d - d, cos d - 1, table row."""
    sg = o.select(rh < 0.0, -1.0, 1.0)
    xh = sg * rh
    idd = (xh * 128.0 + _SHIFT) - _SHIFT
    xl = sg * rl
    i = o.index(idd, 16, len(_T["TRIG_S_HI"]) + 15) - 16
    dh = xh - idd * 2.0**-7
    dz = dh * dh
    sd = (dh * dz) * (_SIND_POLY[0] + dz * _SIND_POLY[1])
    cd = dz * (_COSD_POLY[0] + dz * (_COSD_POLY[1] + dz * _COSD_POLY[2]))
    return sg, xl, dh, sd, cd, i


def _sin_table(rh: Any, rl: Any, o: Any) -> Any:
    sg, xl, dh, sd, cd, i = _trig_split(rh, rl, o)
    S, Sl = o.take("TRIG_S_HI", i), o.take("TRIG_S_LO", i)
    C, Cl = o.take("TRIG_C_HI", i), o.take("TRIG_C_LO", i)
    s, e = _fast_two_sum(S, C * dh)
    tail = Sl + (C * xl + Cl * dh) + (S * cd + C * sd)
    return sg * (s + (e + tail))


def _cos_table(rh: Any, rl: Any, o: Any) -> Any:
    _, xl, dh, sd, cd, i = _trig_split(rh, rl, o)
    S, Sl = o.take("TRIG_S_HI", i), o.take("TRIG_S_LO", i)
    C, Cl = o.take("TRIG_C_HI", i), o.take("TRIG_C_LO", i)
    s, e = _fast_two_sum(C, -(S * dh))
    tail = Cl - (S * xl + Sl * dh) + (C * cd - S * sd)
    return s + (e + tail)


# =========================================================================== scalar port


def _clz64(x: int) -> int:
    n = 0
    for width in (32, 16, 8, 4, 2, 1):
        if x < (1 << (64 - width)):
            n += width
            x = (x << width) & _M64
    return n


def _shl2(x: int, y: int, s: int) -> int:
    return x if s == 0 else ((x << s) & _M64) | (y >> (64 - s))


def _rem_pio2(ax: float) -> tuple[int, float, float]:
    if ax < 2.0**20:
        nd = (ax * _INV_PIO2 + _SHIFT) - _SHIFT
        t1 = ax - nd * _CW_P1
        t2, e2 = _two_sum(t1, -(nd * _CW_P2))
        t3, e3 = _two_sum(t2, -(nd * _CW_P3))
        lo = (e2 + e3) - nd * _CW_P4
        rh, rl = _fast_two_sum(t3, lo)
        return int(nd) & 3, rh, rl
    T = _TWO_OVER_PI_BITS
    ix = _S.bits(ax)
    ex = (ix >> 52) - 1023
    M = (ix & 0x000FFFFFFFFFFFFF) | 0x0010000000000000
    t0 = ex + 10
    q, s = t0 >> 6, t0 & 63
    w0 = _shl2(T[q], T[q + 1], s)
    w1 = _shl2(T[q + 1], T[q + 2], s)
    w2 = _shl2(T[q + 2], T[q + 3], s)
    # M (w0 2^128 + w1 2^64 + w2) mod 2^192, exactly (the C code's 64x64 -> 128 products)
    P = (M * ((w0 << 128) | (w1 << 64) | w2)) & ((1 << 192) - 1)
    r0, r1, r2 = P >> 128, (P >> 64) & _M64, P & _M64
    n = r0 >> 62
    r0 &= 0x3FFFFFFFFFFFFFFF
    neg = False
    if r0 >> 61:
        n += 1
        neg = True
        r2 = (~r2 + 1) & _M64
        c2 = 1 if r2 == 0 else 0
        r1 = (~r1 + c2) & _M64
        c1 = c2 & (1 if r1 == 0 else 0)
        r0 = (~r0 + c1) & 0x3FFFFFFFFFFFFFFF
    sh = 0
    if r0 == 0:
        r0, r1, r2, sh = r1, r2, 0, 64
    z = _clz64(r0)
    a = _shl2(r0, r1, z)
    b = _shl2(r1, r2, z)
    fh = float(a >> 11) * _S.pow2(-51 - z - sh)
    fl = float(((a & 0x7FF) << 42) | (b >> 22)) * _S.pow2(-104 - z - sh)
    ph, pe = _two_prod(fh, _PIO2_HI)
    lo = pe + (fh * _PIO2_LO + fl * _PIO2_HI)
    h, l = _fast_two_sum(ph, lo)
    return n & 3, (-h if neg else h), (-l if neg else l)


def _sincos(ax: float, odd: int) -> float:
    if ax <= _PI_O4:
        n, rh, rl = 0, ax, 0.0
    else:
        n, rh, rl = _rem_pio2(ax)
    n += odd
    if n & 1:
        v = _cos_small(rh, rl) if abs(rh) < 0.125 else _cos_table(rh, rl, _S)
    else:
        v = _sin_small(rh, rl) if abs(rh) < 0.125 else _sin_table(rh, rl, _S)
    return -v if n & 2 else v


def _sin_s(x: float) -> float:
    ax = abs(x)
    if ax < 2.0**-27:
        return x
    if not ax < _INF:
        return _NAN
    v = _sincos(ax, 0)
    return -v if x < 0.0 else v


def _cos_s(x: float) -> float:
    ax = abs(x)
    if ax < 2.0**-27:
        return 1.0
    if not ax < _INF:
        return _NAN
    return _sincos(ax, 1)


# =========================================================================== numpy port
#
# A branch of the C code becomes a partition of the elements: each element follows exactly its
# own branch's operations (the others' lanes are computed on harmless stand-in values and
# discarded by np.where), hence np.errstate(all="ignore") around every public call.


def _vclz64(x: NDArray[np.uint64]) -> NDArray[np.int64]:
    n = np.zeros(x.shape, dtype=np.int64)
    for width in (32, 16, 8, 4, 2, 1):
        below = x < np.uint64(1 << (64 - width))
        n += np.where(below, width, 0)
        x = np.where(below, x << np.uint64(width), x)
    return n


def _vshl2(x: NDArray[np.uint64], y: NDArray[np.uint64], s: NDArray[np.int64]) -> Any:
    shifted = (x << s.astype(np.uint64)) | (y >> ((64 - s) % 64).astype(np.uint64))
    return np.where(s == 0, x, shifted)


_M32 = np.uint64(0xFFFFFFFF)
_U32 = np.uint64(32)
_TWO_OVER_PI_ARRAY = np.array(_TWO_OVER_PI_BITS, dtype=np.uint64)


def _vmul64(a: NDArray[np.uint64], b: NDArray[np.uint64]) -> tuple[Any, Any]:
    """(hi, lo) of the 128-bit product, from 32-bit halves (the C code's portable path)."""
    a0, a1, b0, b1 = a & _M32, a >> _U32, b & _M32, b >> _U32
    p00, p01, p10, p11 = a0 * b0, a0 * b1, a1 * b0, a1 * b1
    mid = (p00 >> _U32) + (p01 & _M32) + (p10 & _M32)
    hi = p11 + (p01 >> _U32) + (p10 >> _U32) + (mid >> _U32)
    return hi, (mid << _U32) | (p00 & _M32)


def _vpayne_hanek(ax: Float) -> tuple[NDArray[np.int64], Float, Float]:
    T = _TWO_OVER_PI_ARRAY
    ix = _V.bits(ax)
    ex = (ix >> _U52).astype(np.int64) - 1023
    M = (ix & np.uint64(0x000FFFFFFFFFFFFF)) | np.uint64(0x0010000000000000)
    t0 = ex + 10
    q, s = t0 >> 6, t0 & 63
    w0 = _vshl2(T[q], T[q + 1], s)
    w1 = _vshl2(T[q + 1], T[q + 2], s)
    w2 = _vshl2(T[q + 2], T[q + 3], s)
    hi2, lo2 = _vmul64(M, w2)
    hi1, lo1 = _vmul64(M, w1)
    r2 = lo2
    r1 = lo1 + hi2
    r0 = M * w0 + hi1 + (r1 < hi2).astype(np.uint64)
    n = (r0 >> np.uint64(62)).astype(np.int64)
    r0 = r0 & np.uint64(0x3FFFFFFFFFFFFFFF)
    neg = (r0 >> np.uint64(61)) != 0
    n = n + neg
    nr2 = ~r2 + np.uint64(1)
    c2 = (nr2 == 0).astype(np.uint64)
    nr1 = ~r1 + c2
    c1 = c2 & (nr1 == 0).astype(np.uint64)
    nr0 = (~r0 + c1) & np.uint64(0x3FFFFFFFFFFFFFFF)
    r0, r1, r2 = np.where(neg, nr0, r0), np.where(neg, nr1, r1), np.where(neg, nr2, r2)
    empty = r0 == 0
    sh = np.where(empty, 64, 0)
    r0, r1, r2 = (np.where(empty, r1, r0), np.where(empty, r2, r1),
                  np.where(empty, np.uint64(0), r2))  # fmt: skip
    z = _vclz64(np.where(r0 == 0, np.uint64(1), r0))
    a = _vshl2(r0, r1, z)
    b = _vshl2(r1, r2, z)
    fh = (a >> np.uint64(11)).astype(np.float64) * _V.pow2(-51 - z - sh)
    low = ((a & np.uint64(0x7FF)) << np.uint64(42)) | (b >> np.uint64(22))
    fl = low.astype(np.float64) * _V.pow2(-104 - z - sh)
    ph, pe = _two_prod(fh, _PIO2_HI)
    lo = pe + (fh * _PIO2_LO + fl * _PIO2_HI)
    h, l = _fast_two_sum(ph, lo)
    return n & 3, np.where(neg, -h, h), np.where(neg, -l, l)


def _vrem_pio2(ax: Float) -> tuple[NDArray[np.int64], Float, Float]:
    """n mod 4 and the reduced argument of finite ax > pi/4."""
    n = np.zeros(ax.shape, dtype=np.int64)
    rh = np.empty_like(ax)
    rl = np.empty_like(ax)
    cw = np.nonzero(ax < 2.0**20)[0]
    if cw.size:
        a = ax[cw]
        nd = (a * _INV_PIO2 + _SHIFT) - _SHIFT
        t1 = a - nd * _CW_P1
        t2, e2 = _two_sum(t1, -(nd * _CW_P2))
        t3, e3 = _two_sum(t2, -(nd * _CW_P3))
        lo = (e2 + e3) - nd * _CW_P4
        rh[cw], rl[cw] = _fast_two_sum(t3, lo)
        n[cw] = nd.astype(np.int64) & 3
    ph = np.nonzero(~(ax < 2.0**20))[0]
    if ph.size:
        n[ph], rh[ph], rl[ph] = _vpayne_hanek(ax[ph])
    return n, rh, rl


def _vsincos(x: Float, odd: int) -> Float:
    ax = np.abs(x)
    a = np.where((ax >= 2.0**-27) & (ax < _INF), ax, 1.0)
    n = np.zeros(a.shape, dtype=np.int64)
    rh = a.copy()
    rl = np.zeros_like(a)
    far = np.nonzero(a > _PI_O4)[0]
    if far.size:
        n[far], rh[far], rl[far] = _vrem_pio2(a[far])
    n = n + odd
    small = np.abs(rh) < 0.125
    cos_v = np.where(small, _cos_small(rh, rl), _cos_table(rh, rl, _V))
    sin_v = np.where(small, _sin_small(rh, rl), _sin_table(rh, rl, _V))
    v = np.where(n & 1, cos_v, sin_v)
    v = np.where(n & 2, -v, v)
    if odd == 0:
        v = np.where(ax < 2.0**-27, x, np.where(x < 0.0, -v, v))
    else:
        v = np.where(ax < 2.0**-27, 1.0, v)
    return np.where(ax < _INF, v, _NAN)
