"""The shared parts of the project's elementary functions (:mod:`.detmath`): constants, bits, sums.

``arith/templates/detmath.h`` is the C side; its generated block holds every constant (tables,
splits of ln 2 and pi/2, the bits of 2/pi, polynomial coefficients), read here once -- the single
source both ports use. The kernels are written once and run on Python floats (the scalar port)
and on float64 arrays (the numpy port); what differs between the two -- bit fields, table rows,
integer parts, selections -- goes through an "ops" object, ``_S`` for Python floats and ints,
``_V`` for numpy arrays. Here also live the error-free transformations (Fast2Sum, 2Sum, Dekker's
product) and the final scaling by 2^k with one rounding of subnormal results, which every
family of functions uses.

The functions are split by family, each module the Python twin of its C functions, operation
for operation: :mod:`.detmath_explog` (exp, log, log2, log10, pow, sinh, cosh),
:mod:`.detmath_trig` (sin, cos), :mod:`.detmath_inverse_trig` (atan, atan2, asin, acos) and
:mod:`.detmath_roots` (cbrt, hypot). The names here are for those modules only; users import
:mod:`chaplygin.arith.detmath`.
"""

from __future__ import annotations

import math
import re
import struct
from importlib import resources
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["HEADER_NAME", "Float", "header_text"]

#: The C header, shipped as package data of ``chaplygin.arith`` (``templates/detmath.h``).
HEADER_NAME = "templates/detmath.h"

#: The float64 arrays of the numpy port.
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
# The floating-point kernels of the detmath_* modules are written once and run on Python floats
# (the scalar port) and on float64 arrays (the numpy port): + - * / are the same IEEE operations
# on both. What differs -- bit fields, table rows, integer parts, selections -- goes through an
# "ops" object, _S for Python floats and ints, _V for numpy arrays. Each kernel is the C function
# of the same name, operation for operation.


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


# =========================================================================== scaling by 2^k


def _scale(h: float, l: float, k: int) -> float:
    """(h + l) 2^k, a subnormal result rounded once (the scalar port)."""
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


def _vscale(h: Float, l: Float, k: NDArray[np.int64]) -> Float:
    """The same on float64 arrays."""
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
