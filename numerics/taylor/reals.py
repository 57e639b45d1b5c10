"""How numbers cross the interface of the compiled Taylor libraries.

Exact binary128 bytes (quad), multi-double limbs (double-double, quad-double), the C real
types of the compiled integrator by arithmetic (:data:`REAL_TYPES`), and the exact base-16
text of the MPFR library.
"""

from __future__ import annotations

import math
import platform
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import mpmath
import numpy as np

__all__ = [
    "RealType",
    "REAL_TYPES",
    "encode_binary128",
    "decode_binary128",
    "encode_multi_double",
    "decode_multi_double",
]

# --------------------------------------------------------------------------- binary128

_MASK112 = (1 << 112) - 1


def encode_binary128(values: Sequence[Any]) -> np.ndarray:
    """IEEE binary128 bytes (little-endian) of ``values``, rounded to nearest (113 bits).

    Returns a ``uint8`` array of ``16 * len(values)`` bytes.

    Parameters
    ----------
    values : sequence of numbers
        Anything ``mpmath.mpf`` accepts (``mpmath.mpf`` values are rounded as they are).

    Returns
    -------
    numpy.ndarray of uint8, shape (16 * len(values),)
        The values one after the other, 16 bytes each.

    Raises
    ------
    ValueError
        For a value that is not finite or is outside the normal binary128 range
        (subnormals included).
    """
    out = bytearray()
    with mpmath.workprec(113):
        for v in values:
            x = mpmath.mpf(v) if not isinstance(v, mpmath.mpf) else +v
            if not mpmath.isfinite(x):
                raise ValueError(f"cannot encode {x} as binary128")
            sign = 1 if x < 0 else 0
            if x == 0:
                bits = sign << 127
            else:
                man, exp = mpmath.frexp(abs(x))  # abs(x) = man 2^exp, 0.5 <= man < 1
                m = int(mpmath.ldexp(man, 113))  # exact: x has at most 113 bits
                e = int(exp) - 1  # x = m 2^(e - 112), m in [2^112, 2^113)
                biased = e + 16383
                if biased <= 0 or biased >= 0x7FFF:
                    raise ValueError(f"{x} is outside the binary128 normal range")
                bits = (sign << 127) | (biased << 112) | (m & _MASK112)
            out += bits.to_bytes(16, "little")
    return np.frombuffer(bytes(out), dtype=np.uint8).copy()


def decode_binary128(buf: np.ndarray | bytes, count: int | None = None) -> list[mpmath.mpf]:
    """``mpmath.mpf`` values (exact at >= 113 bits) of little-endian binary128 bytes.

    Parameters
    ----------
    buf : numpy.ndarray of uint8 or bytes
        The bytes, 16 per value.
    count : int, optional
        Number of values to read (default all of ``buf``).

    Returns
    -------
    list of mpmath.mpf
        The values at ``max(mp.prec, 113)`` bits; infinities and NaN as ``mpmath.inf``,
        ``mpmath.ninf``, ``mpmath.nan``.
    """
    raw = bytes(buf)
    count = len(raw) // 16 if count is None else count
    out = []
    for i in range(count):
        bits = int.from_bytes(raw[16 * i : 16 * i + 16], "little")
        sign = bits >> 127
        biased = (bits >> 112) & 0x7FFF
        m = bits & _MASK112
        if biased == 0x7FFF:
            out.append(mpmath.nan if m else (mpmath.ninf if sign else mpmath.inf))
            continue
        if biased == 0:
            e = 1 - 16383 - 112
        else:
            m |= 1 << 112
            e = biased - 16383 - 112
        with mpmath.workprec(max(mpmath.mp.prec, 113)):
            v = mpmath.ldexp(mpmath.mpf(-m if sign else m), e)
        out.append(v)
    return out


# --------------------------------------------------------------------------- C reals


def _pack_double(values: Sequence[Any]) -> np.ndarray:
    return np.ascontiguousarray(np.asarray([float(v) for v in values], dtype=float))


def _unpack_double(buf: np.ndarray, count: int | None = None) -> np.ndarray:
    return buf if count is None else buf[:count]


def _rows_array(flat: np.ndarray, n: int, width: int) -> np.ndarray:
    return np.asarray(flat[: n * width]).reshape(n, width).copy()


def _rows_lists(flat: list, n: int, width: int) -> list[list]:
    return [flat[i * width : (i + 1) * width] for i in range(n)]


def _times_113(values: Sequence) -> np.ndarray:
    with mpmath.workprec(113):
        return np.array([+mpmath.mpf(v) for v in values], dtype=object)


@dataclass(frozen=True)
class RealType:
    """The C ``REAL`` of one Taylor library and how values cross the interface.

    Attributes
    ----------
    size : int
        Bytes per value.
    ldlibs : tuple of str
    pack : callable
        Values -> buffer.
    unpack : callable
        ``(buffer, count=None)`` -> float64 array (double) or list of mpf (quad).
    empty : callable
        ``count`` -> zeroed buffer.
    rows : callable
        ``(flat, n, width)`` -> ``n`` rows of ``width`` values.
    times : callable
        Times as the output array (float64, or mpf at 113 bits).
    dtype : type
        dtype of the output arrays.
    cflags : tuple of str
        Extra compiler flags tried first (without them when the compiler refuses them).
    """

    size: int
    ldlibs: tuple[str, ...]
    pack: Callable[[Sequence[Any]], np.ndarray]
    unpack: Callable[..., Any]
    empty: Callable[[int], np.ndarray]
    rows: Callable[[Any, int, int], Any]
    times: Callable[[Sequence], np.ndarray]
    dtype: type
    cflags: tuple[str, ...] = ()


#: The C integrator's real types, by arithmetic (keys of
#: :data:`~chaplygin.numerics.precision.ARITHMETICS`; ``dd`` and ``qd`` are added below).
REAL_TYPES: dict[str, RealType] = {
    "double": RealType(
        size=8,
        ldlibs=(),
        pack=_pack_double,
        unpack=_unpack_double,
        empty=np.zeros,
        rows=_rows_array,
        times=lambda values: np.asarray(values, dtype=float),
        dtype=float,
    ),
    "quad": RealType(
        size=16,
        ldlibs=("-lquadmath",),
        pack=encode_binary128,
        unpack=decode_binary128,
        empty=lambda count: np.zeros(16 * count, np.uint8),
        rows=_rows_lists,
        times=_times_113,
        dtype=object,
    ),
}


def encode_multi_double(values: Sequence[Any], limbs: int = 2) -> np.ndarray:
    """Multi-double limbs of ``values``, exactly: ``x_0 + ... + x_(limbs-1) == value``.

    Each limb is the remainder so far rounded to the nearest double, so the limbs are
    normalised (each at most half an ulp of the one before) and exact for a value of at most
    ``53 * limbs`` significant bits (double-double: 106, quad-double: 212).

    Parameters
    ----------
    values : sequence of numbers
        ``mpmath.mpf``, ``gmpy2.mpfr``, ``int`` or ``float`` values (working numbers).
    limbs : int, default 2
        Doubles per value (2: double-double, 4: quad-double).

    Returns
    -------
    numpy.ndarray of float64, shape (limbs * len(values),)
        The limbs of every value, one value after the other.

    Raises
    ------
    ValueError
        For a value that is not finite, overflows a double, or is not exactly a sum of
        ``limbs`` doubles (too many bits, or below the normal range).
    """
    out = np.empty(limbs * len(values))
    for i, v in enumerate(values):
        x = _to_mpf(v) if not isinstance(v, int | float) else mpmath.mpf(v)
        if not mpmath.isfinite(x):
            raise ValueError(f"cannot encode {x} as {limbs} doubles")
        with mpmath.workprec(max(mpmath.mp.prec, 4 * 53 * limbs)):
            rest = +x
            for j in range(limbs):
                with mpmath.workprec(53):
                    limb = float(+rest)  # round to nearest (mpmath's default rounding)
                if not math.isfinite(limb) or (limb != 0 and abs(limb) < 2.0**-1021):
                    raise ValueError(f"{x} is outside the range of {limbs} doubles")
                out[limbs * i + j] = limb
                rest = rest - limb  # exact at this precision
            if rest != 0:
                raise ValueError(f"{x} is not exactly a sum of {limbs} doubles")
    return out


def decode_multi_double(
    buf: np.ndarray, count: int | None = None, limbs: int = 2
) -> list[mpmath.mpf]:
    """``mpmath.mpf`` values of multi-double limbs: their sum rounded once to ``mp.prec``.

    Parameters
    ----------
    buf : numpy.ndarray of float64
        Limbs, ``limbs`` per value, one value after the other.
    count : int, optional
        Number of values (default ``len(buf) // limbs``).
    limbs : int, default 2
        Doubles per value.

    Returns
    -------
    list of mpmath.mpf
        The values at the working precision of ``mpmath.mp`` (infinities and NaN as
        mpmath's).
    """
    parts = np.asarray(buf, dtype=float)
    count = len(parts) // limbs if count is None else count
    out = []
    for i in range(count):
        group = [float(v) for v in parts[limbs * i : limbs * (i + 1)]]
        if not all(math.isfinite(v) for v in group):
            out.append(mpmath.mpf(math.fsum(group)))
            continue
        exact = mpmath.mpf(0)
        with mpmath.workprec(max(mpmath.mp.prec, 53) + 2200):  # every double is exact
            for v in group:
                exact += v
        out.append(+exact)
    return out


def _times_working(values: Sequence) -> np.ndarray:
    return np.array([mpmath.mpf(v) for v in values], dtype=object)


def _multi_double(limbs: int, ldlibs: tuple[str, ...]) -> RealType:
    return RealType(
        size=8 * limbs,
        ldlibs=ldlibs,
        pack=lambda values: encode_multi_double(values, limbs),
        unpack=lambda buf, count=None: decode_multi_double(buf, count, limbs),
        empty=lambda count: np.zeros(limbs * count),
        rows=_rows_lists,
        times=_times_working,
        dtype=object,
        # inlining of the limb arithmetic, and the hardware FMA for the exact products
        # (the same bits as Dekker's splitting: both are error-free)
        cflags=("-O3", *_fma_flags()),
    )


def _fma_flags() -> tuple[str, ...]:
    """``-mfma`` when this x86-64 CPU has the fused multiply-add (Linux ``/proc/cpuinfo``),
    else nothing (aarch64 has it without a flag). The flags are part of the compile-cache
    key, so a library built with ``-mfma`` is never loaded by a process on a CPU without it."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return ()
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as fh:
            for line in fh:
                if line.startswith("flags"):
                    return ("-mfma",) if " fma " in f" {line.split(':', 1)[-1].strip()} " else ()
    except OSError:
        pass
    return ()


#: The multi-double real types of the digits precisions: double-double
#: (``-DCHAPLYGIN_TAYLOR_DD``, transcendental functions through libquadmath) up to
#: :data:`DD_BITS` bits, quad-double (``-DCHAPLYGIN_TAYLOR_QD``) up to :data:`QD_BITS`
#: (``ARITHMETICS[...].most_bits``).
REAL_TYPES["dd"] = _multi_double(2, ("-lquadmath",))
REAL_TYPES["qd"] = _multi_double(4, ())


# --------------------------------------------------------------------------- MPFR text


def _mpfr_token(value: Any) -> str:
    """Exact base-16 text of a number for ``mpfr_strtofr``: hexadecimal integer significand,
    ``p``, decimal binary exponent."""
    if isinstance(value, int):
        value = mpmath.mpf(value) if abs(value) < 2**53 else _exact_int(value)
    x = _to_mpf(value)
    if not mpmath.isfinite(x):
        return "nan" if mpmath.isnan(x) else ("-inf" if x < 0 else "inf")
    sign, man, exp, _ = x._mpf_
    if not man:
        return "0"
    return f"{'-' if sign else ''}{int(man):x}p{int(exp)}"


def _exact_int(value: int) -> mpmath.mpf:
    with mpmath.workprec(max(value.bit_length(), 53)):
        return mpmath.mpf(value)


def _mpfr_text(values: Sequence[Any]) -> bytes:
    return " ".join(_mpfr_token(v) for v in values).encode("ascii")


def _parse_mpfr(text: bytes) -> mpmath.mpf:
    """The number of one ``%Ra`` slot (``-0x1.8p+1``, ``inf``, ``nan``), rounded once to the
    working precision of ``mpmath.mp`` (exact when it is the run's precision)."""
    s = text.decode("ascii").strip()
    negative = s.startswith("-")
    s = s.lstrip("+-")
    if s.startswith("inf"):
        return mpmath.ninf if negative else mpmath.inf
    if not s.startswith("0x"):
        return mpmath.nan
    significand, exponent = s[2:].split("p")
    whole, _, fraction = significand.partition(".")
    man = int(whole + fraction, 16)
    return mpmath.mpf((-man if negative else man, int(exponent) - 4 * len(fraction)))


# --------------------------------------------------------------------------- working numbers


def _to_mpf(x) -> mpmath.mpf:
    if isinstance(x, mpmath.mpf):
        return x
    if isinstance(x, float):
        return mpmath.mpf(x)
    m, e = x.as_mantissa_exp()
    return mpmath.ldexp(mpmath.mpf(int(m)), int(e))
