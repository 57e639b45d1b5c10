"""atan, atan2, asin and acos of :mod:`.detmath`, bit for bit ``detmath.h``.

One kernel, ``atan(u/v)`` of double-double ``u, v`` by a table of atan(i/64) and a polynomial
in the remainder; ``asin`` and ``acos`` call it with ``sqrt(1 - x^2)`` as a double-double. The
kernels, then the scalar port on Python floats and the numpy port on float64 arrays, each the
C function of the same name, operation for operation (see :mod:`.detmath_core`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .detmath_core import (
    _ATAN_POLY,
    _INF,
    _M64,
    _NAN,
    _PI3O4,
    _PI_HI,
    _PI_LO,
    _PI_O4,
    _PIO2_HI,
    _PIO2_LO,
    _S,
    _SHIFT,
    _U52,
    _U63,
    _V,
    Float,
    _fast_two_sum,
    _two_prod,
    _two_sum,
)


def _atan_kernel(uh: Any, ul: Any, vh: Any, vl: Any, o: Any) -> tuple[Any, Any]:
    c = _ATAN_POLY
    q = uh / vh
    idd = (q * 64.0 + _SHIFT) - _SHIFT
    i = o.index(idd, 0, 64)
    ci = idd * 2.0**-6
    vhh = o.double(o.bits(vh) & (~0x3F & _M64))
    vhl = vh - vhh
    uhh = o.double(o.bits(uh) & (~0x3F & _M64))
    uhl = uh - uhh
    n1 = uh - ci * vhh
    N1, ne = _two_sum(n1, -(ci * vhl))
    Nl = ne + (ul - ci * vl)
    D1, de = _fast_two_sum(vh, ci * uhh)
    Dl = de + (ci * uhl + (vl + ci * ul))
    inv = 1.0 / D1
    th = N1 * inv
    p, pe = _two_prod(th, D1)
    tl = (((N1 - p) - pe) + (Nl - th * Dl)) * inv
    z = th * th
    P = (c[0] + z * c[1]) + (z * z) * (c[2] + z * c[3])
    tail = tl + (th * z) * P
    h, e = _fast_two_sum(o.take("ATAN_HI", i), th)
    return h, e + (o.take("ATAN_LO", i) + tail)


def _angle(bh: Any, bl: Any, sign: Any, h: Any, l: Any) -> Any:
    s, e = _fast_two_sum(bh, sign * h)
    return s + (e + (bl + sign * l))


def _sqrt1mx2(ax: Any, o: Any) -> tuple[Any, Any]:
    d, de = _fast_two_sum(1.0, -ax)
    a, ae = _fast_two_sum(1.0, ax)
    wh, pe = _two_prod(d, a)
    wl = pe + (d * ae + de * a)
    s = o.sqrt(wh)
    q, qe = _two_prod(s, s)
    return s, (((wh - q) - qe) + wl) / (s + s)


# =========================================================================== scalar port


def _atan_s(x: float) -> float:
    ax = abs(x)
    if ax < 2.0**-27:
        return x
    if not ax <= 2.0**60:
        if ax != ax:
            return _NAN
        return -_PIO2_HI if x < 0.0 else _PIO2_HI
    if ax <= 1.0:
        h, l = _atan_kernel(ax, 0.0, 1.0, 0.0, _S)
        res = h + l
    else:
        h, l = _atan_kernel(1.0, 0.0, ax, 0.0, _S)
        s, e = _fast_two_sum(_PIO2_HI, -h)
        res = s + (e + (_PIO2_LO - l))
    return -res if x < 0.0 else res


def _atan2_s(y: float, x: float) -> float:
    ax = abs(x)
    ay = abs(y)
    xneg = (_S.bits(x) >> 63) == 1
    if x != x or y != y:
        return _NAN
    if ay == 0.0:
        res = _PI_HI if xneg else 0.0
    elif ax == 0.0:
        res = _PIO2_HI
    elif ax == _INF:
        if ay == _INF:
            res = _PI3O4 if xneg else _PI_O4
        else:
            res = _PI_HI if xneg else 0.0
    elif ay == _INF:
        res = _PIO2_HI
    else:
        swap = ay > ax
        u, v = (ax, ay) if swap else (ay, ax)
        su, sv = u, v
        if sv > 2.0**1000:
            su *= 2.0**-600
            sv *= 2.0**-600
        elif sv < 2.0**-1000:
            su *= 2.0**600
            sv *= 2.0**600
        f = _S.pow2(1023 - (_S.bits(sv) >> 52))
        su *= f
        sv *= f
        if su < 2.0**-62:
            h, l = u / v, 0.0
        else:
            h, l = _atan_kernel(su, 0.0, sv, 0.0, _S)
        if swap:
            bh, bl, sign = _PIO2_HI, _PIO2_LO, (1.0 if xneg else -1.0)
        elif xneg:
            bh, bl, sign = _PI_HI, _PI_LO, -1.0
        else:
            bh, bl, sign = 0.0, 0.0, 1.0
        res = _angle(bh, bl, sign, h, l)
    return -res if (_S.bits(y) >> 63) == 1 else res


def _asin_s(x: float) -> float:
    ax = abs(x)
    if not ax <= 1.0:
        return _NAN
    if ax < 2.0**-27:
        return x
    if ax == 1.0:
        res = _PIO2_HI
    else:
        sh, sl = _sqrt1mx2(ax, _S)
        if ax <= sh:
            h, l = _atan_kernel(ax, 0.0, sh, sl, _S)
            res = _angle(0.0, 0.0, 1.0, h, l)
        else:
            h, l = _atan_kernel(sh, sl, ax, 0.0, _S)
            res = _angle(_PIO2_HI, _PIO2_LO, -1.0, h, l)
    return -res if x < 0.0 else res


def _acos_s(x: float) -> float:
    ax = abs(x)
    xneg = x < 0.0
    if not ax <= 1.0:
        return _NAN
    if ax < 2.0**-60:
        return _PIO2_HI
    if ax == 1.0:
        return _PI_HI if xneg else 0.0
    sh, sl = _sqrt1mx2(ax, _S)
    first = sh <= ax
    if first:
        h, l = _atan_kernel(sh, sl, ax, 0.0, _S)
        bh, bl = (_PI_HI, _PI_LO) if xneg else (0.0, 0.0)
    else:
        h, l = _atan_kernel(ax, 0.0, sh, sl, _S)
        bh, bl = _PIO2_HI, _PIO2_LO
    return _angle(bh, bl, -1.0 if first == xneg else 1.0, h, l)


# =========================================================================== numpy port
#
# A branch of the C code becomes a partition of the elements: each element follows exactly its
# own branch's operations (the others' lanes are computed on harmless stand-in values and
# discarded by np.where), hence np.errstate(all="ignore") around every public call.


def _vatan(x: Float) -> Float:
    ax = np.abs(x)
    a = np.where((ax >= 2.0**-27) & (ax <= 2.0**60), ax, 0.5)
    inside = a <= 1.0
    h1, l1 = _atan_kernel(np.where(inside, a, 0.5), 0.0, 1.0, 0.0, _V)
    h2, l2 = _atan_kernel(1.0, 0.0, np.where(inside, 2.0, a), 0.0, _V)
    s, e = _fast_two_sum(_PIO2_HI, -h2)
    res = np.where(inside, h1 + l1, s + (e + (_PIO2_LO - l2)))
    res = np.where(ax > 2.0**60, _PIO2_HI, res)
    res = np.where(x < 0.0, -res, res)
    res = np.where(ax < 2.0**-27, x, res)
    return np.where(np.isnan(x), _NAN, res)


def _vatan2(y: Float, x: Float) -> Float:
    ax = np.abs(x)
    ay = np.abs(y)
    xneg = (_V.bits(x) >> _U63) == 1
    regular = (ax > 0.0) & (ay > 0.0) & (ax < _INF) & (ay < _INF)
    ax_r = np.where(regular, ax, 1.0)
    ay_r = np.where(regular, ay, 1.0)
    swap = ay_r > ax_r
    u = np.where(swap, ax_r, ay_r)
    v = np.where(swap, ay_r, ax_r)
    big = v > 2.0**1000
    tiny = v < 2.0**-1000
    su = np.where(big, u * 2.0**-600, np.where(tiny, u * 2.0**600, u))
    sv = np.where(big, v * 2.0**-600, np.where(tiny, v * 2.0**600, v))
    f = _V.pow2(1023 - (_V.bits(sv) >> _U52).astype(np.int64))
    su = su * f
    sv = sv * f
    ratio_tiny = su < 2.0**-62
    kh, kl = _atan_kernel(np.where(ratio_tiny, 0.5, su), 0.0, np.where(ratio_tiny, 1.0, sv),
                          0.0, _V)  # fmt: skip
    h = np.where(ratio_tiny, u / v, kh)
    l = np.where(ratio_tiny, 0.0, kl)
    bh = np.where(swap, _PIO2_HI, np.where(xneg, _PI_HI, 0.0))
    bl = np.where(swap, _PIO2_LO, np.where(xneg, _PI_LO, 0.0))
    sign = np.where(swap, np.where(xneg, 1.0, -1.0), np.where(xneg, -1.0, 1.0))
    res = np.where(regular, _angle(bh, bl, sign, h, l), 0.0)
    # special cases, the C code's order reversed
    res = np.where((ax < _INF) & (ay == _INF), _PIO2_HI, res)
    x_inf = np.where(ay == _INF, np.where(xneg, _PI3O4, _PI_O4), np.where(xneg, _PI_HI, 0.0))
    res = np.where((ax == _INF) & (ay > 0.0), x_inf, res)
    res = np.where((ax == 0.0) & (ay > 0.0), _PIO2_HI, res)
    res = np.where(ay == 0.0, np.where(xneg, _PI_HI, 0.0), res)
    res = np.where((_V.bits(y) >> _U63) == 1, -res, res)
    return np.where(np.isnan(x) | np.isnan(y), _NAN, res)


def _vasin(x: Float) -> Float:
    ax = np.abs(x)
    a = np.where((ax >= 2.0**-27) & (ax < 1.0), ax, 0.5)
    sh, sl = _sqrt1mx2(a, _V)
    first = a <= sh
    h, l = _atan_kernel(np.where(first, a, sh), np.where(first, 0.0, sl),
                        np.where(first, sh, a), np.where(first, sl, 0.0), _V)  # fmt: skip
    res = _angle(np.where(first, 0.0, _PIO2_HI), np.where(first, 0.0, _PIO2_LO),
                 np.where(first, 1.0, -1.0), h, l)  # fmt: skip
    res = np.where(ax == 1.0, _PIO2_HI, res)
    res = np.where(x < 0.0, -res, res)
    res = np.where(ax < 2.0**-27, x, res)
    return np.where(ax <= 1.0, res, _NAN)


def _vacos(x: Float) -> Float:
    ax = np.abs(x)
    xneg = x < 0.0
    a = np.where((ax >= 2.0**-60) & (ax < 1.0), ax, 0.5)
    sh, sl = _sqrt1mx2(a, _V)
    first = sh <= a
    h, l = _atan_kernel(np.where(first, sh, a), np.where(first, sl, 0.0),
                        np.where(first, a, sh), np.where(first, 0.0, sl), _V)  # fmt: skip
    bh = np.where(first, np.where(xneg, _PI_HI, 0.0), _PIO2_HI)
    bl = np.where(first, np.where(xneg, _PI_LO, 0.0), _PIO2_LO)
    res = _angle(bh, bl, np.where(first == xneg, -1.0, 1.0), h, l)
    res = np.where(ax == 1.0, np.where(xneg, _PI_HI, 0.0), res)
    res = np.where(ax < 2.0**-60, _PIO2_HI, res)
    return np.where(ax <= 1.0, res, _NAN)
