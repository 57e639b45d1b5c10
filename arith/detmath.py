"""The project's own transcendental functions, bit for bit ``detmath.h``, for Python and numpy.

``arith/templates/detmath.h`` defines ``chaplygin_exp``, ``chaplygin_sin``, ... in C with IEEE-754
basic operations only (+ - * / sqrt, comparisons, exact scaling and bit manipulation), so that
every compiler and processor computes the same bits; this module performs *the same sequence of
operations* on Python floats (a scalar path) and on numpy float64 arrays (element-wise numpy
operations, which are correctly rounded per element and never fused), so the three agree bit for
bit (``tests/test_detmath.py`` checks it).  Unlike :mod:`math` and numpy's ufuncs -- glibc and
numpy choose FMA/AVX2/AVX-512 code paths by processor -- the result does not depend on the
machine.

The constants (tables, splits of ln 2 and pi/2, the bits of 2/pi, polynomial coefficients) are
read from the header's generated block, the single source both ports use.

Accuracy, by design and measured (``tests/test_detmath.py``, mpmath at 200 bits): every function
is faithful (error below 1 ulp, also for subnormal results) and almost always correctly rounded;
see the header's top comment for the numbers.

Each function accepts a Python float or int (returns a float) or anything :func:`numpy.asarray`
turns into float64 (returns an ndarray of the same shape; a 0-d input gives a numpy scalar).
Special values follow C99 Annex F; every NaN result is the positive quiet NaN
``0x7ff8000000000000`` (payloads of NaN inputs are not kept).

References
----------
T. J. Dekker, "A floating-point technique for extending the available precision", Numer. Math.
18 (1971) -- Fast2Sum and the exact product without FMA.
M. H. Payne and R. N. Hanek, "Radian reduction for trigonometric functions", SIGNUM Newsl. 18
(1983) -- reduction of huge arguments with the bits of 2/pi.
J.-M. Muller et al., *Handbook of Floating-Point Arithmetic*, 2nd ed., Birkhauser 2018.
"""

from __future__ import annotations

import math
import re
import struct
from importlib import resources
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "HEADER_NAME",
    "header_text",
    "exp",
    "log",
    "log2",
    "log10",
    "pow",
    "sin",
    "cos",
    "atan",
    "atan2",
    "asin",
    "acos",
    "cbrt",
    "hypot",
    "sinh",
    "cosh",
]

#: The C header, shipped as package data of ``chaplygin.arith`` (``templates/detmath.h``).
HEADER_NAME = "templates/detmath.h"

Float = NDArray[np.float64]


def header_text() -> str:
    """Text of ``detmath.h`` (to paste into, or ``#include`` from, generated C code).

    Returns
    -------
    str
        The header's source.
    """
    return resources.files("chaplygin.arith").joinpath(HEADER_NAME).read_text("utf-8")


def _read_constants(text: str) -> dict[str, Any]:
    """The generated constants of the header: floats, tuples of floats, tuples of ints."""
    start = text.index("BEGIN GENERATED CONSTANTS")
    end = text.index("END GENERATED CONSTANTS")
    pattern = re.compile(
        r"static const (double|uint64_t) chaplygin_dm_(\w+)(\[\d+\])? = (.*?);", re.S
    )
    out: dict[str, Any] = {}
    for ctype, name, dim, body in pattern.findall(text[start:end]):
        if ctype == "double":
            values = [float.fromhex(v) for v in body.strip("{} \n").replace("\n", " ").split(",")
                      if v.strip()]
        else:
            values = [int(v.strip()[len("UINT64_C("):-1], 16)
                      for v in body.strip("{} \n").replace("\n", " ").split(",") if v.strip()]
        out[name] = tuple(values) if dim else values[0]
    return out


_K = _read_constants(header_text())

# scalar constants
_LN2_HI: float = _K["LN2_HI"]
_LN2_LO: float = _K["LN2_LO"]
_PIO2_HI: float = _K["PIO2_HI"]
_PIO2_LO: float = _K["PIO2_LO"]
_PI_HI: float = _K["PI_HI"]
_PI_LO: float = _K["PI_LO"]
_PI3O4: float = _K["PI3O4"]
_PI_O4: float = _K["PI_O4"]
_INV_PIO2: float = _K["INV_PIO2"]
_CW_P1: float = _K["CW_P1"]
_CW_P2: float = _K["CW_P2"]
_CW_P3: float = _K["CW_P3"]
_CW_P4: float = _K["CW_P4"]
_EXP_INV_LN2_N: float = _K["EXP_INV_LN2_N"]
_EXP_LN2_N_HI: float = _K["EXP_LN2_N_HI"]
_EXP_LN2_N_LO: float = _K["EXP_LN2_N_LO"]
_LOG_SQRT2: float = _K["LOG_SQRT2"]
_EXP_POLY: tuple[float, ...] = _K["EXP_POLY"]
_LOG_POLY: tuple[float, ...] = _K["LOG_POLY"]
_LOGDD_POLY: tuple[float, ...] = _K["LOGDD_POLY"]
_SIN_POLY: tuple[float, ...] = _K["SIN_POLY"]
_COS_POLY: tuple[float, ...] = _K["COS_POLY"]
_SIND_POLY: tuple[float, ...] = _K["SIND_POLY"]
_COSD_POLY: tuple[float, ...] = _K["COSD_POLY"]
_ATAN_POLY: tuple[float, ...] = _K["ATAN_POLY"]
_SINH_POLY: tuple[float, ...] = _K["SINH_POLY"]
_CBRT_POLY: tuple[float, ...] = _K["CBRT_POLY"]
_TWO_OVER_PI_BITS: tuple[int, ...] = _K["TWO_OVER_PI_BITS"]
# tables (tuples for the scalar path, arrays for the numpy path)
_TABLE_NAMES = (
    "EXP_T_HI", "EXP_T_LO", "LOG_R", "LOG_L_HI", "LOG_L_LO", "TRIG_S_HI", "TRIG_S_LO",
    "TRIG_C_HI", "TRIG_C_LO", "ATAN_HI", "ATAN_LO", "LOG2_L_HI", "LOG2_L_LO", "LOG2_POLY",
    "LOG10_L_HI", "LOG10_L_LO", "LOG10_POLY", "CBRT_2J",
)  # fmt: skip
_T: dict[str, tuple[float, ...]] = {name: _K[name] for name in _TABLE_NAMES}
_A: dict[str, Float] = {name: np.array(_K[name], dtype=np.float64) for name in _TABLE_NAMES}
#: log2 and log10: (e_hi, e_lo, table hi, table lo, k_hi, k_lo, polynomial) by base name
_LOG_BASES = {
    name: (_K[f"{name}_E_HI"], _K[f"{name}_E_LO"], f"{name}_L_HI", f"{name}_L_LO",
           _K[f"{name}_K_HI"], _K[f"{name}_K_LO"], f"{name}_POLY")
    for name in ("LOG2", "LOG10")
}  # fmt: skip

_SHIFT = 6755399441055744.0  # 1.5 * 2^52; (z + SHIFT) - SHIFT rounds |z| < 2^51 to an integer
_M64 = (1 << 64) - 1
_NAN_BITS = 0x7FF8000000000000
_INF = math.inf
_SQRT2_HALF_BITS = struct.unpack("<Q", struct.pack("<d", 0.5 * _LOG_SQRT2))[0]

_pack_d = struct.Struct("<d").pack
_unpack_d = struct.Struct("<d").unpack
_pack_q = struct.Struct("<Q").pack
_unpack_q = struct.Struct("<Q").unpack
_NAN: float = _unpack_d(_pack_q(_NAN_BITS))[0]


# =========================================================================== shared arithmetic
#
# The floating-point kernels below are written once and run on Python floats (the scalar port)
# and on float64 arrays (the numpy port): + - * / are the same IEEE operations on both. What
# differs -- bit fields, table rows, integer parts, selections -- goes through an "ops" object,
# _S for Python floats and ints, _V for numpy arrays. Each kernel is the C function of the same
# name, operation for operation.


class _ScalarOps:
    """Bit fields, table rows and integer parts of Python floats (exact)."""

    @staticmethod
    def bits(x: float) -> int:
        return _unpack_q(_pack_d(x))[0]

    @staticmethod
    def double(u: int) -> float:
        return _unpack_d(_pack_q(u & _M64))[0]

    @staticmethod
    def pow2(k: int) -> float:
        return _ScalarOps.double((k + 1023) << 52)

    @staticmethod
    def index(x: float, lo: int, hi: int) -> int:  # x is integral
        return int(x)

    @staticmethod
    def take(table: str, i: int) -> float:
        return _T[table][i]

    @staticmethod
    def tofloat(k: int) -> float:
        return float(k)

    @staticmethod
    def select(c: bool, a: Any, b: Any) -> Any:
        return a if c else b

    sqrt = staticmethod(math.sqrt)


class _ArrayOps:
    """The same on float64 arrays (lanes of a branch not taken may hold garbage: clipped)."""

    @staticmethod
    def bits(x: Any) -> NDArray[np.uint64]:
        return np.ascontiguousarray(x, dtype=np.float64).view(np.uint64)

    @staticmethod
    def double(u: Any) -> Float:
        return np.ascontiguousarray(u, dtype=np.uint64).view(np.float64)

    @staticmethod
    def pow2(k: Any) -> Float:
        return _ArrayOps.double((np.asarray(k) + 1023).astype(np.uint64) << _U52)

    @staticmethod
    def index(x: Any, lo: int, hi: int) -> NDArray[np.int64]:
        return np.clip(np.asarray(x).astype(np.int64), lo, hi)

    @staticmethod
    def take(table: str, i: Any) -> Float:
        return _A[table][i]

    @staticmethod
    def tofloat(k: Any) -> Float:
        return np.asarray(k).astype(np.float64)

    select = staticmethod(np.where)
    sqrt = staticmethod(np.sqrt)


_S = _ScalarOps
_V = _ArrayOps
_U52 = np.uint64(52)
_U63 = np.uint64(63)


def _fast_two_sum(a: Any, b: Any) -> tuple[Any, Any]:
    s = a + b
    return s, b - (s - a)


def _two_sum(a: Any, b: Any) -> tuple[Any, Any]:
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def _two_prod(a: Any, b: Any) -> tuple[Any, Any]:
    p = a * b
    ca = 134217729.0 * a
    ah = ca - (ca - a)
    al = a - ah
    cb = 134217729.0 * b
    bh = cb - (cb - b)
    bl = b - bh
    return p, (((ah * bh - p) + ah * bl) + al * bh) + al * bl


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


def _sinh_small(ax: Any) -> Any:
    c = _SINH_POLY
    z = ax * ax
    z2 = z * z
    P = ((c[0] + z * c[1]) + z2 * (c[2] + z * c[3])) + (z2 * z2) * (c[4] + z * c[5])
    return ax + (ax * z) * P


# =========================================================================== scalar port


def _scale(h: float, l: float, k: int) -> float:
    v = h + l
    if k > 1000:
        return (v * _S.pow2(k - 100)) * 2.0**100
    if k >= -1021:
        return v * _S.pow2(k)
    G = _S.pow2(-1022 - k)
    if v >= G:
        return (v * _S.pow2(k + 200)) * 2.0**-200
    d = (h + G) - G
    f = (h - d) + l
    S = 1.5 * G
    g = (f + S) - S
    return ((d + g) * _S.pow2(k + 200)) * 2.0**-200


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


def _vscale(h: Float, l: Float, k: NDArray[np.int64]) -> Float:
    v = h + l
    out = v * _V.pow2(np.clip(k, -1021, 1000))
    big = np.nonzero(k > 1000)[0]
    if big.size:
        out[big] = (v[big] * _V.pow2(k[big] - 100)) * 2.0**100
    tiny = np.nonzero(k < -1021)[0]
    if tiny.size:
        kt, vt, ht, lt = k[tiny], v[tiny], h[tiny], l[tiny]
        G = _V.pow2(-1022 - kt)
        normal = (vt * _V.pow2(kt + 200)) * 2.0**-200
        d = (ht + G) - G
        f = (ht - d) + lt
        S = 1.5 * G
        g = (f + S) - S
        sub = ((d + g) * _V.pow2(kt + 200)) * 2.0**-200
        out[tiny] = np.where(vt >= G, normal, sub)
    return out


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


# =========================================================================== public functions


#: Elements per numpy pass: the temporaries of a kernel stay in the cache (3-5x faster than one
#: pass over 10^6 elements); element-wise, so the bits do not depend on it.
_CHUNK = 16384


def _is_scalar(x: Any) -> bool:
    return isinstance(x, float | int) and not isinstance(x, bool | np.ndarray)


def _apply(vector: Any, *arrays: Any) -> Any:
    """``vector`` on broadcast float64 copies of ``arrays``, chunk by chunk, in the input shape."""
    flat = [np.ascontiguousarray(a).reshape(-1)
            for a in np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in arrays))]
    shape = np.broadcast_shapes(*(np.shape(a) for a in arrays))
    out = np.empty(flat[0].size)
    with np.errstate(all="ignore"):
        for start in range(0, out.size, _CHUNK):
            out[start : start + _CHUNK] = vector(*(f[start : start + _CHUNK] for f in flat))
    out = out.reshape(shape)
    return out[()] if out.ndim == 0 else out


def _unary(scalar: Any, vector: Any, x: Any) -> Any:
    return scalar(float(x)) if _is_scalar(x) else _apply(vector, x)


def _binary(scalar: Any, vector: Any, a: Any, b: Any) -> Any:
    if _is_scalar(a) and _is_scalar(b):
        return scalar(float(a), float(b))
    return _apply(vector, a, b)


def exp(x: float | ArrayLike) -> Any:
    """Exponential e^x, the bits of ``chaplygin_exp``.

    Parameters
    ----------
    x : float or array_like
        Argument(s).

    Returns
    -------
    float or numpy.ndarray
        e^x rounded faithfully (almost always correctly); +inf above 709.78, subnormal results
        rounded once, +0 below -745.14.
    """
    return _unary(_exp_s, _vexp, x)


def log(x: float | ArrayLike) -> Any:
    """Natural logarithm, the bits of ``chaplygin_log``.

    Parameters
    ----------
    x : float or array_like
        Argument(s); log(+-0) = -inf, log(x < 0) = NaN, log(+inf) = +inf.

    Returns
    -------
    float or numpy.ndarray
        log x.
    """
    return _unary(_log_s, _vlog, x)


def log2(x: float | ArrayLike) -> Any:
    """Base-2 logarithm, the bits of ``chaplygin_log2`` (exact at powers of two).

    Parameters
    ----------
    x : float or array_like
        Argument(s); special values as :func:`log`.

    Returns
    -------
    float or numpy.ndarray
        log2 x.
    """
    return _unary(lambda v: _log_base_s(v, "LOG2"), lambda v: _vlog_base(v, "LOG2"), x)


def log10(x: float | ArrayLike) -> Any:
    """Base-10 logarithm, the bits of ``chaplygin_log10``.

    Parameters
    ----------
    x : float or array_like
        Argument(s); special values as :func:`log`.

    Returns
    -------
    float or numpy.ndarray
        log10 x.
    """
    return _unary(lambda v: _log_base_s(v, "LOG10"), lambda v: _vlog_base(v, "LOG10"), x)


def pow(x: float | ArrayLike, y: float | ArrayLike) -> Any:
    """Power x^y, the bits of ``chaplygin_pow`` (special cases of C99 Annex F).

    Parameters
    ----------
    x, y : float or array_like
        Base and exponent (broadcast together).

    Returns
    -------
    float or numpy.ndarray
        x^y: e^(y log|x|) with log|x| as a double-double; negative x only for integer y
        (NaN otherwise).
    """
    return _binary(_pow_s, _vpow, x, y)


def sin(x: float | ArrayLike) -> Any:
    """Sine, the bits of ``chaplygin_sin``, right for every finite argument.

    Parameters
    ----------
    x : float or array_like
        Argument(s) in radians; +-inf and NaN give NaN.

    Returns
    -------
    float or numpy.ndarray
        sin x (Cody-Waite reduction below 2^20, Payne-Hanek above).
    """
    return _unary(_sin_s, lambda v: _vsincos(v, 0), x)


def cos(x: float | ArrayLike) -> Any:
    """Cosine, the bits of ``chaplygin_cos``, right for every finite argument.

    Parameters
    ----------
    x : float or array_like
        Argument(s) in radians; +-inf and NaN give NaN.

    Returns
    -------
    float or numpy.ndarray
        cos x.
    """
    return _unary(_cos_s, lambda v: _vsincos(v, 1), x)


def atan(x: float | ArrayLike) -> Any:
    """Arc tangent, the bits of ``chaplygin_atan``.

    Parameters
    ----------
    x : float or array_like
        Argument(s).

    Returns
    -------
    float or numpy.ndarray
        atan x in [-pi/2, pi/2].
    """
    return _unary(_atan_s, _vatan, x)


def atan2(y: float | ArrayLike, x: float | ArrayLike) -> Any:
    """Arc tangent of y/x in the right quadrant, the bits of ``chaplygin_atan2``.

    Parameters
    ----------
    y, x : float or array_like
        Coordinates (broadcast together); signed zeros and infinities as C99 Annex F.

    Returns
    -------
    float or numpy.ndarray
        The angle in [-pi, pi].
    """
    return _binary(_atan2_s, _vatan2, y, x)


def asin(x: float | ArrayLike) -> Any:
    """Arc sine, the bits of ``chaplygin_asin``.

    Parameters
    ----------
    x : float or array_like
        Argument(s) in [-1, 1] (NaN outside).

    Returns
    -------
    float or numpy.ndarray
        asin x in [-pi/2, pi/2].
    """
    return _unary(_asin_s, _vasin, x)


def acos(x: float | ArrayLike) -> Any:
    """Arc cosine, the bits of ``chaplygin_acos``.

    Parameters
    ----------
    x : float or array_like
        Argument(s) in [-1, 1] (NaN outside).

    Returns
    -------
    float or numpy.ndarray
        acos x in [0, pi].
    """
    return _unary(_acos_s, _vacos, x)


def cbrt(x: float | ArrayLike) -> Any:
    """Real cube root, the bits of ``chaplygin_cbrt`` (exact for exact cubes).

    Parameters
    ----------
    x : float or array_like
        Argument(s), any sign.

    Returns
    -------
    float or numpy.ndarray
        The real cube root.
    """
    return _unary(_cbrt_s, _vcbrt, x)


def hypot(x: float | ArrayLike, y: float | ArrayLike) -> Any:
    """sqrt(x^2 + y^2) without undue overflow or underflow, the bits of ``chaplygin_hypot``.

    Parameters
    ----------
    x, y : float or array_like
        Legs (broadcast together); an infinite leg gives +inf even with a NaN.

    Returns
    -------
    float or numpy.ndarray
        The hypotenuse.
    """
    return _binary(_hypot_s, _vhypot, x, y)


def sinh(x: float | ArrayLike) -> Any:
    """Hyperbolic sine, the bits of ``chaplygin_sinh``.

    Parameters
    ----------
    x : float or array_like
        Argument(s).

    Returns
    -------
    float or numpy.ndarray
        sinh x (+-inf beyond +-710.48).
    """
    return _unary(_sinh_s, _vsinh, x)


def cosh(x: float | ArrayLike) -> Any:
    """Hyperbolic cosine, the bits of ``chaplygin_cosh``.

    Parameters
    ----------
    x : float or array_like
        Argument(s).

    Returns
    -------
    float or numpy.ndarray
        cosh x (+inf beyond 710.48).
    """
    return _unary(_cosh_s, _vcosh, x)
