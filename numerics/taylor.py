"""Taylor integrator generated from the model: double and quad in C, any digits in Python.

The recurrences come from :mod:`chaplygin.derive.emit.taylor` (``generated/*_taylor.py`` and
``*_taylor.c``). Order and step follow Jorba and Zou (2005): with ``eps = atol`` when
``rtol |y|_inf <= atol`` (absolute control, scale 1) and ``eps = rtol`` otherwise (relative
control, scale ``|y|_inf``), the order is ``p = ceil(-ln(eps)/2 + 1)`` and the step
``h = rho e^-2 e^(-0.7/(p-1))``, ``rho = min((scale/|y_[p-1]|)^(1/(p-1)),
(scale/|y_[p]|)^(1/p))`` (the last two coefficients' norms; ``e^(-0.7/(p-1))`` is the
safety factor). Every step keeps its Taylor polynomial, so the solution is known at any
time inside it (dense output) and sign changes of user functions ``g(t, y)`` are located by
root finding on that polynomial to the working precision (event location, for Poincaré
maps).

Backends
--------
* ``double`` -- the C integrator in IEEE double; the whole loop (coefficients, step choice,
  polynomial evaluation, output at the requested times) runs in C, one call per
  integration (one call per step when events are requested);
* ``quad`` -- the same C code in ``__float128`` (libquadmath), values crossing the
  interface as exact binary128 bytes, converted to and from ``mpmath.mpf``;
* digits up to 31 (at most 106 bits) -- the same C code in double-double
  (``-DCHAPLYGIN_TAYLOR_DD``: two doubles, 106 bits, error-free transformations), and up to
  60 digits (203 bits) in quad-double (``-DCHAPLYGIN_TAYLOR_QD``, four doubles); the
  working numbers are split exactly into their limbs and the results rounded once back to
  the working precision;
* more digits -- C on MPFR (``generated/*_taylor_mpfr.c``, linked to gmpy2's own MPFR;
  backend ``c-mpfr``) at the precision's bits, numbers crossing as exact
  base-16 text; its order and step are those of the Python stepper to the bit (one call
  per step when events are asked for); ``lib="gmpy2"`` and a missing compiler or MPFR: the
  Python recurrences with ``gmpy2`` (MPFR) numbers (``mpmath`` numbers when
  ``lib="mpmath"``).

Without a C compiler double and quad fall back to the Python recurrences (floats, or MPFR at
113 bits) with a :class:`~chaplygin.numerics.compiled.CompilerUnavailableWarning`.

Which arithmetic a precision runs in, and everything else that depends on it, is read from
its :class:`~chaplygin.numerics.precision.Precision` (``precision.arithmetic``: one row of
:data:`~chaplygin.numerics.precision.ARITHMETICS`); :func:`taylor_solve` is given it and
enters its context itself. The integrations of the project reach this engine through the
``taylor`` integrator (:mod:`chaplygin.numerics.integrators`).
"""

from __future__ import annotations

import functools
import math
import os
import platform
import threading
import time
import types
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import cffi
import gmpy2
import mpmath
import numpy as np

from ..arith import detmath
from ..derive.emit.c_sources import taylor_source
from ..derive.emit.taylor_unroll import unrolled_source
from ..derive.errors import UserInputError
from .compiled import CompilerError, CompilerUnavailableWarning, compile_c
from .precision import ARITHMETICS, DD_BITS, QD_BITS, Precision

if TYPE_CHECKING:
    from .code import ModelCode

__all__ = [
    "TaylorSolution",
    "TaylorDense",
    "taylor_dense",
    "CompiledTaylor",
    "load_taylor_library",
    "run_orders",
    "CompiledTaylorMPFR",
    "load_taylor_mpfr_library",
    "mpfr_build_flags",
    "taylor_solve",
    "jorba_zou_order",
    "encode_binary128",
    "decode_binary128",
    "encode_multi_double",
    "decode_multi_double",
    "DD_BITS",
    "QD_BITS",
    "python_lib",
    "RealType",
    "REAL_TYPES",
]

_CDEF = """
const char *chaplygin_taylor_model_hash(void);
void chaplygin_taylor_sizes(int *OUT);
void chaplygin_taylor_coefficients(int order, const void *T0, const void *Y, const void *P,
                                   void *OUT);
int chaplygin_taylor_step(void *TY, const void *P, const void *CTRL, int fixed_order,
                          const void *T_END, void *COEFFS, void *H, int *ORDER);
int chaplygin_taylor_run(const void *T01, const void *Y0, const void *P, const void *CTRL,
                         int fixed_order, long n_eval, const void *T_EVAL, void *Y_EVAL,
                         void *Y_END, void *T_REACHED, long max_steps, long *STATS,
                         void *Y_LO);
"""
_ffi = cffi.FFI()
_ffi.cdef(_CDEF)

#: Largest order the Python recurrences use by default (the C library has its own cap).
PY_MAX_ORDER = 400

#: Default largest number of steps of one integration.
MAX_STEPS = 10_000_000


@functools.lru_cache(maxsize=256)
def jorba_zou_order(eps: float, max_order: int = 80) -> int:
    """Order ``ceil(-ln(eps)/2 + 1)`` of Jorba and Zou (2005), between 2 and ``max_order``.

    Parameters
    ----------
    eps : float
        Tolerance of the step (``atol`` or ``rtol``, see the module docstring), ``> 0``.
    max_order : int
        Largest order returned.

    Returns
    -------
    int
        The order ``p``.
    """
    return int(min(max(math.ceil(-0.5 * detmath.log(eps) + 1.0), 2), max_order))


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


# --------------------------------------------------------------------------- C library


class CompiledTaylor:
    """The compiled C Taylor integrator of one model, in ``double`` or ``quad``.

    Parameters
    ----------
    library : path-like
    kind : {"double", "quad", "dd", "qd"}
    expected_hash : str, optional
    """

    def __init__(self, library: os.PathLike | str, kind: str, expected_hash: str | None = None):
        self.lib = _ffi.dlopen(os.fspath(library))
        self.kind = kind
        self.real = REAL_TYPES[kind]
        self.model_hash = _ffi.string(self.lib.chaplygin_taylor_model_hash()).decode()
        if expected_hash is not None and self.model_hash != expected_hash:
            raise ValueError(
                f"Taylor library {library} has hash {self.model_hash}, expected {expected_hash}"
            )
        sizes = _ffi.new("int[5]")
        self.lib.chaplygin_taylor_sizes(sizes)
        self.n_state, self.n_param, self.n_nodes, self.max_order, self.real_size = list(sizes)
        if self.real_size != self.real.size:
            raise ValueError(f"{library} holds {self.real_size}-byte reals, not {kind}")

    # conversion between Python values and REAL buffers
    def pack(self, values: Sequence[Any]) -> np.ndarray:
        """Buffer of ``values`` as the library's reals.

        Parameters
        ----------
        values : sequence of numbers
            Floats (double) or anything ``mpmath.mpf`` accepts (quad).

        Returns
        -------
        numpy.ndarray
            float64 array (double) or ``uint8`` binary128 bytes (quad).
        """
        return self.real.pack(values)

    def unpack(self, buf: np.ndarray, count: int | None = None) -> np.ndarray | list[mpmath.mpf]:
        """The first ``count`` reals of ``buf`` (all by default).

        Parameters
        ----------
        buf : numpy.ndarray
            A buffer of the library's reals (:meth:`pack`, :meth:`empty`).
        count : int, optional
            Number of values (default all).

        Returns
        -------
        numpy.ndarray or list of mpmath.mpf
            float64 array (double, a view of ``buf``) or list of mpf (quad).
        """
        return self.real.unpack(buf, count)

    def empty(self, count: int) -> np.ndarray:
        """A zeroed buffer of ``count`` reals.

        Parameters
        ----------
        count : int
            Number of reals.

        Returns
        -------
        numpy.ndarray
            ``count`` float64 zeros (double) or ``16 * count`` zero bytes (quad).
        """
        return self.real.empty(count)

    @staticmethod
    def _ptr(a: np.ndarray):
        return _ffi.from_buffer("char[]", a, require_writable=False)

    def coefficients(
        self,
        order: int,
        t0: float | mpmath.mpf,
        y: Sequence[float | mpmath.mpf],
        p: Sequence[float | mpmath.mpf],
    ) -> np.ndarray | list[list[mpmath.mpf]]:
        """Normalised Taylor coefficients, ``n_state x (order + 1)`` (ndarray or mpf lists).

        Parameters
        ----------
        order : int
            Highest order, ``1 <= order <= max_order``.
        t0 : number
            Expansion time.
        y : sequence of numbers, length n_state
            State at ``t0``.
        p : sequence of numbers, length n_param
            Parameters.

        Returns
        -------
        numpy.ndarray, shape (n_state, order + 1), or list of n_state lists of mpmath.mpf
            Row ``i``, column ``k``: ``y_i^(k)(t0)/k!`` (double: float64 array; quad: lists).

        Raises
        ------
        ValueError
            If ``order`` is out of range.
        """
        if not 1 <= order <= self.max_order:
            raise ValueError(f"order must be in 1..{self.max_order}")
        out = self.empty(self.n_state * (order + 1))
        ptr = self._ptr
        self.lib.chaplygin_taylor_coefficients(
            order, ptr(self.pack([t0])), ptr(self.pack(y)), ptr(self.pack(p)), ptr(out)
        )
        return self.real.rows(self.unpack(out), self.n_state, order + 1)


_LIBS: dict[tuple[str, str, tuple[int, ...]], CompiledTaylor | None] = {}

#: Extra flags for the written-out code: scheduling before register allocation, aware of
#: register pressure (gcc; measured 3-8 % faster steps on the bench's reference problem).
#: They change the instruction order only, not the arithmetic (no -ffast-math).
UNROLLED_CFLAGS = ("-fschedule-insns", "-fsched-pressure")


def run_orders(rtol: float, atol: float, order: int | None = None) -> tuple[int, ...]:
    """The orders the C step control can choose for these tolerances (or the fixed order).

    Parameters
    ----------
    rtol, atol : float
        Tolerances (relative control uses the order of ``rtol``, absolute that of ``atol``).
    order : int, optional
        A fixed order.

    Returns
    -------
    tuple of int
        One or two orders (:func:`jorba_zou_order`, capped at the C limit 80).
    """
    if order:
        return (int(order),)
    return tuple(sorted({jorba_zou_order(float(rtol)), jorba_zou_order(float(atol))}))


def load_taylor_library(
    code: ModelCode, kind: str, orders: Sequence[int] = ()
) -> CompiledTaylor | None:
    """Compile (cached by source hash) and load the C Taylor integrator of ``code``.

    ``kind="quad"`` compiles with ``-DCHAPLYGIN_TAYLOR_QUAD``, ``kind="dd"`` (double-double,
    for up to :data:`DD_BITS` bits of the digits precisions) with ``-DCHAPLYGIN_TAYLOR_DD``
    (both link ``-lquadmath``), ``kind="qd"`` (quad-double, up to :data:`QD_BITS` bits) with
    ``-DCHAPLYGIN_TAYLOR_QD``.
    Returns None, after a :class:`CompilerUnavailableWarning`, without a usable compiler.

    Parameters
    ----------
    code : ModelCode
        The model (its ``taylor_c_source`` and ``hash``).
    kind : {"double", "quad", "dd", "qd"}
        The arithmetic (a key of :data:`REAL_TYPES`).
    orders : sequence of int, optional
        Orders whose coefficients are written out
        (:mod:`chaplygin.derive.emit.taylor_unroll`, from the model's printed Taylor program;
        double only, the same bits as the loop, faster): one more library per set of orders,
        compiled once and cached like the others, with pairs of nodes in GNU C vectors; a
        compiler that refuses the vectors gets the written-out scalar code, one that refuses
        that (or a model without a printed program) the library of the loop.

    Returns
    -------
    CompiledTaylor or None
        The loaded library, the same object for every call with the same model and kind;
        None (also cached) when compiling or loading failed.

    Raises
    ------
    KeyError
        An unknown ``kind``.
    """
    unroll = tuple(sorted({int(p) for p in orders})) if ARITHMETICS[kind].unrolled else ()
    key = (code.hash, kind, unroll)
    if key in _LIBS:
        return _LIBS[key]
    real = REAL_TYPES[kind]
    source, ldlibs = taylor_source(code.taylor_c_source, kind), real.ldlibs
    if unroll:
        # written out with the pairs in GNU C vectors, else written out without them, else
        # (a compiler that refuses both, a model without its printed Taylor program) the
        # loop: the same bits every way
        for vectors in (True, False):
            if code.taylor_program is None:
                break
            written_out = unrolled_source(source, code.taylor_program, unroll, vectors=vectors)
            if written_out is None:
                break
            try:
                path = _compile_quietly(written_out, ldlibs, (*real.cflags, *UNROLLED_CFLAGS))
                lib = CompiledTaylor(path, kind, expected_hash=code.hash)
            except (CompilerError, OSError):
                continue
            _LIBS[key] = lib
            return lib
        lib = load_taylor_library(code, kind)
        _LIBS[key] = lib
        return lib
    try:
        if real.cflags:
            path = _compile_quietly(source, ldlibs, real.cflags)
        else:
            path = compile_c(source, ldlibs=ldlibs)
        lib = CompiledTaylor(path, kind, expected_hash=code.hash)
    except (CompilerError, OSError) as exc:
        warnings.warn(
            f"compiled {kind} Taylor integrator unavailable, using the (much slower) Python "
            f"recurrences instead: {exc}",
            CompilerUnavailableWarning,
            stacklevel=2,
        )
        lib = None
    _LIBS[key] = lib
    return lib


def _compile_quietly(source: str, ldlibs, cflags) -> str:
    """Compile with ``cflags``, or without them for a compiler that refuses them."""
    try:
        return compile_c(source, ldlibs=ldlibs, cflags=cflags)
    except CompilerError:
        return compile_c(source, ldlibs=ldlibs)


# --------------------------------------------------------------------------- C, MPFR

_MPFR_CDEF = """
const char *chaplygin_taylor_model_hash(void);
const char *chaplygin_taylor_mpfr_version(void);
void chaplygin_taylor_sizes(int *OUT);
int chaplygin_taylor_mpfr_coefficients(long prec, int order, const char *T0, const char *Y,
                                       const char *P, char *OUT, int width);
int chaplygin_taylor_mpfr_run(long prec, const char *T01, const char *Y0, const char *P,
                              const double *CTRL, const char *FIXED_H, int fixed_order,
                              int taper, long n_eval, const char *T_EVAL, char *Y_EVAL, int width,
                              char *Y_END, char *T_REACHED, long max_steps, long *STATS);
void *chaplygin_taylor_mpfr_stepper_new(long prec, const double *CTRL, int fixed_order,
                                        int taper);
void chaplygin_taylor_mpfr_stepper_free(void *ST);
int chaplygin_taylor_mpfr_step(void *ST, const char *TY, const char *P, const double *CTRL,
                               const char *FIXED_H, int fixed_order, const char *T_END,
                               char *TY_OUT, char *COEFFS, char *H, int *ORDER, int width);
"""
_mpfr_ffi = cffi.FFI()
_mpfr_ffi.cdef(_MPFR_CDEF)


#: Whether the MPFR loop computes the high-order coefficients at lower precision (see
#: ``coefficient_prec`` in ``derive/templates/taylor_mpfr.c``); never with a fixed step.
MPFR_TAPER = True


def mpfr_build_flags() -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Compiler flags and libraries of the MPFR Taylor integrator: gmpy2's own MPFR.

    The gmpy2 wheel ships ``mpfr.h`` and ``gmp.h`` in its package folder and the shared
    libraries in ``gmpy2.libs``: the source is compiled against those headers and linked to
    those files by path with an rpath, so the library runs with the very MPFR that gmpy2 has
    loaded (no system package, no network). Without them (a gmpy2 built against a system
    MPFR) the system's ``-lmpfr -lgmp`` are tried; :class:`CompiledTaylorMPFR` checks that
    the versions agree.

    Returns
    -------
    (tuple of str, tuple of str)
        Extra compiler flags (``-O2``, ``-I<gmpy2 folder>``) and libraries to link.
    """
    folder = os.path.dirname(os.path.abspath(gmpy2.__file__))
    libs = os.path.join(os.path.dirname(folder), "gmpy2.libs")
    headers = all(os.path.isfile(os.path.join(folder, h)) for h in ("mpfr.h", "gmp.h"))
    found = {}
    if os.path.isdir(libs):
        for name in sorted(os.listdir(libs)):
            for stem in ("libmpfr", "libgmp"):
                if name.startswith(stem + "-") and ".so" in name:
                    found.setdefault(stem, os.path.join(libs, name))
    if headers and len(found) == 2:
        return (
            ("-O2", f"-I{folder}"),
            (found["libmpfr"], found["libgmp"], f"-Wl,-rpath,{libs}"),
        )
    return (("-O2", *((f"-I{folder}",) if headers else ())), ("-lmpfr", "-lgmp"))


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


class CompiledTaylorMPFR:
    """The compiled MPFR Taylor integrator of one model (precision chosen per call).

    Parameters
    ----------
    library : path-like
    expected_hash : str, optional

    Raises
    ------
    ValueError
        The library is of another model, or runs with another MPFR version than gmpy2's.
    """

    kind = "mpfr"

    def __init__(self, library: os.PathLike | str, expected_hash: str | None = None):
        self.lib = _mpfr_ffi.dlopen(os.fspath(library))
        self.model_hash = _mpfr_ffi.string(self.lib.chaplygin_taylor_model_hash()).decode()
        if expected_hash is not None and self.model_hash != expected_hash:
            raise ValueError(
                f"Taylor library {library} has hash {self.model_hash}, expected {expected_hash}"
            )
        self.mpfr_version = _mpfr_ffi.string(self.lib.chaplygin_taylor_mpfr_version()).decode()
        wanted = gmpy2.mpfr_version().split()[-1]
        if self.mpfr_version != wanted:
            raise ValueError(
                f"{library} runs with MPFR {self.mpfr_version}, gmpy2 with MPFR {wanted}"
            )
        sizes = _mpfr_ffi.new("int[5]")
        self.lib.chaplygin_taylor_sizes(sizes)
        self.n_state, self.n_param, self.n_nodes, self.max_order, _ = list(sizes)

    @staticmethod
    def width(prec: int) -> int:
        """Characters of one output slot at ``prec`` bits (exact ``%Ra`` text and NUL).

        Parameters
        ----------
        prec : int
            Working precision in bits.

        Returns
        -------
        int
        """
        return prec // 4 + 48

    def _slots(self, buf, count: int, width: int) -> list[mpmath.mpf]:
        raw = _mpfr_ffi.buffer(buf)
        return [
            _parse_mpfr(raw[i * width : (i + 1) * width].split(b"\0", 1)[0]) for i in range(count)
        ]

    def coefficients(
        self,
        order: int,
        t0: Any,
        y: Sequence[Any],
        p: Sequence[Any],
    ) -> list[list[mpmath.mpf]]:
        """Normalised Taylor coefficients at the working precision of ``mpmath.mp``.

        Parameters
        ----------
        order : int
            Highest order, ``1 <= order <= max_order``.
        t0 : number
            Expansion time.
        y : sequence of numbers, length n_state
            State at ``t0``.
        p : sequence of numbers, length n_param
            Parameters.

        Returns
        -------
        list of n_state lists of mpmath.mpf
            Row ``i``, column ``k``: ``y_i^(k)(t0)/k!``.

        Raises
        ------
        ValueError
            If ``order`` is out of range.
        """
        if not 1 <= order <= self.max_order:
            raise ValueError(f"order must be in 1..{self.max_order}")
        prec = mpmath.mp.prec
        width = self.width(prec)
        count = self.n_state * (order + 1)
        out = _mpfr_ffi.new("char[]", count * width)
        status = self.lib.chaplygin_taylor_mpfr_coefficients(
            prec, order, _mpfr_text([t0]), _mpfr_text(y), _mpfr_text(p), out, width
        )
        if status:
            raise ValueError(f"the MPFR Taylor coefficients failed (status {status})")
        return _rows_lists(self._slots(out, count, width), self.n_state, order + 1)


def load_taylor_mpfr_library(code: ModelCode) -> CompiledTaylorMPFR | None:
    """Compile (cached by source hash) and load the MPFR Taylor integrator of ``code``.

    Returns None, after a :class:`CompilerUnavailableWarning`, without a usable compiler,
    without MPFR's headers and library, or when the library's MPFR is not gmpy2's.

    Parameters
    ----------
    code : ModelCode
        The model (its ``taylor_mpfr_source`` and ``hash``).

    Returns
    -------
    CompiledTaylorMPFR or None
        The loaded library, the same object for every call with the same model; None (also
        cached) when compiling or loading failed.
    """
    key = (code.hash, "mpfr")
    if key in _LIBS:
        return _LIBS[key]  # type: ignore[return-value]
    lib: CompiledTaylorMPFR | None
    try:
        if code.taylor_mpfr_source is None:
            raise OSError(f"{code.name} has no MPFR Taylor source")
        cflags, ldlibs = mpfr_build_flags()
        path = compile_c(code.taylor_mpfr_source, ldlibs=ldlibs, cflags=cflags)
        lib = CompiledTaylorMPFR(path, expected_hash=code.hash)
    except (CompilerError, OSError, ValueError) as exc:
        warnings.warn(
            f"compiled MPFR Taylor integrator unavailable, using the (much slower) Python "
            f"recurrences instead: {exc}",
            CompilerUnavailableWarning,
            stacklevel=2,
        )
        lib = None
    _LIBS[key] = lib  # type: ignore[assignment]
    return lib


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


def _to_mpf(x) -> mpmath.mpf:
    if isinstance(x, mpmath.mpf):
        return x
    if isinstance(x, float):
        return mpmath.mpf(x)
    m, e = x.as_mantissa_exp()
    return mpmath.ldexp(mpmath.mpf(int(m)), int(e))


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


# --------------------------------------------------------------------------- solution


@dataclass
class TaylorSolution:
    """Raw outcome of :func:`taylor_solve` (``integrate`` wraps it in an IntegrationResult).

    ``y`` is ``(n_state, len(t))``: float64 in double, ``mpmath.mpf`` objects otherwise;
    ``t_events[i]``, ``y_events[i]``: times and states where event ``i`` fired.
    """

    t: np.ndarray
    y: np.ndarray
    status: int
    message: str
    nsteps: int
    order_min: int
    order_max: int
    backend: str
    t_events: list = field(default_factory=list)
    y_events: list = field(default_factory=list)


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


def taylor_solve(
    code: ModelCode,
    y0: Sequence[float | mpmath.mpf],
    t_span: tuple[float | mpmath.mpf, float | mpmath.mpf],
    p: Sequence[float | mpmath.mpf],
    *,
    precision: Precision | str | int = "double",
    rtol: float,
    atol: float,
    t_eval: Sequence[float | mpmath.mpf] | None = None,
    events: Sequence[Callable] | Callable | None = None,
    order: int | None = None,
    step: float | None = None,
    max_steps: int = MAX_STEPS,
    lib: str | None = None,
    max_wall_s: float | None = None,
) -> TaylorSolution:
    """Integrate with the Taylor method; see the module docstring.

    Parameters
    ----------
    code : ModelCode
        The model (:func:`chaplygin.numerics.code.load_model_code`).
    y0, p : sequence
        State and parameters (floats in double, ``mpmath.mpf`` otherwise).
    t_span : (t0, t1)
        Start and end times; ``t1 < t0`` integrates backward.
    precision : Precision, "double", "quad" or int
        The working precision (a number: of digits); the run enters its context
        (:meth:`~chaplygin.numerics.precision.Precision.context`) itself.
    rtol, atol : float
        Local tolerances of the Jorba-Zou control.
    t_eval : sequence, optional
        Output times inside the span (default 11 equispaced points).
    events : callable or sequence of callables, optional
        ``g(t, y)``; a sign change inside a step is an event, located on the step's Taylor
        polynomial to the working precision. ``g.terminal = True`` stops the integration at
        the first event; ``g.direction`` (> 0 rising, < 0 falling, 0 both) as in scipy.
    order, step : optional
        Fixed order and/or fixed step (for convergence studies); default adaptive.
    lib : {"c", "gmpy2", "mpmath", "float"}, optional
        Force a backend (default: the compiled integrator in the precision's arithmetic:
        double, quad, double-double up to :data:`DD_BITS` bits, quad-double up to
        :data:`QD_BITS`, MPFR beyond).
    max_wall_s : float, optional
        Wall-time limit (status -6 past it), checked between steps of the Python loop and
        between calls of ``precision.arithmetic.chunk_steps`` steps of the compiled loop
        (which resume exactly: the results do not depend on the limit).

    max_steps : int
        Largest number of steps (status -2 beyond it).

    Returns
    -------
    TaylorSolution
        States at ``t_eval``, status (0: reached ``t1``) and message, step count, the orders
        used, the backend and the events.

    Raises
    ------
    ValueError
        A fixed order outside 2..80, ``t_eval`` not sorted in the direction of
        integration, or ``lib="float"`` outside double precision.
    UserInputError
        An unknown precision.
    """
    precision = Precision(precision)
    with precision.context():
        return _solve(
            code, y0, t_span, p, precision, rtol, atol, t_eval, events, order, step,
            max_steps, lib, max_wall_s,
        )  # fmt: skip


def _solve(code, y0, t_span, p, precision, rtol, atol, t_eval, events, order, step, max_steps,
           lib, max_wall_s) -> TaylorSolution:
    """:func:`taylor_solve` inside the precision's context: the backend from its arithmetic."""
    if order is not None and not 2 <= order <= 80:
        raise ValueError("order must be in 2..80")
    t0, t1 = t_span
    direction = 1 if t1 > t0 else -1
    t_eval = list(_loop_linspace(precision, t0, t1, 11) if t_eval is None else t_eval)
    if any(direction * (t_eval[i + 1] - t_eval[i]) < 0 for i in range(len(t_eval) - 1)):
        raise ValueError("t_eval must be sorted in the direction of integration")
    if events is not None and callable(events):
        events = [events]
    events = list(events or [])
    arithmetic = precision.arithmetic
    clib = None
    if lib in (None, "c") and arithmetic.name != "mpfr":
        # the compiled integrator in the precision's arithmetic: double, __float128, or
        # fixed-size multi-double where it carries the working precision
        clib = load_taylor_library(code, arithmetic.name, run_orders(rtol, atol, order))
    elif lib in (None, "c"):
        # MPFR in C beyond (one call per step when events are asked for)
        mlib = load_taylor_mpfr_library(code)
        if mlib is not None and not events:
            return _mpfr_run(mlib, y0, (t0, t1), p, rtol, atol, t_eval, order, step, max_steps,
                             max_wall_s, precision.bits)  # fmt: skip
        if mlib is not None:  # events located in Python on the compiled steps
            stepper = _MpfrStepper(mlib, p, rtol, atol, order, step, precision.bits)
            return _py_run(
                stepper, y0, (t0, t1), t_eval, events, max_steps, precision, max_wall_s
            )
    numbers = "mpmath" if lib == "mpmath" else arithmetic.python_numbers
    if clib is None and lib == "float" and numbers != "float":
        raise ValueError("lib='float' works in double precision only")
    if clib is not None and not events:
        return _c_run(clib, y0, (t0, t1), p, rtol, atol, t_eval, order, step, max_steps, max_wall_s)
    if clib is None and numbers == "gmpy2":
        # gmpy2/MPFR at the working precision (113 bits for the quad fallback). The stepper
        # converts the parameters when it is made: it must be made inside the context, or
        # MPFR rounds them to the default 53 bits.
        with gmpy2.context(gmpy2.get_context(), precision=precision.bits):
            stepper = _Stepper(code, numbers, p, rtol, atol, order, step, clib)
            return _py_run(stepper, y0, (t0, t1), t_eval, events, max_steps, precision, max_wall_s)
    stepper = _Stepper(code, numbers, p, rtol, atol, order, step, clib)
    return _py_run(stepper, y0, (t0, t1), t_eval, events, max_steps, precision, max_wall_s)


_MESSAGES = {
    0: "reached t_end",
    -1: "the solution became NaN or infinite; check the parameters and state",
    -2: "too many steps (max_steps); shorten the span or loosen the tolerance",
    -3: "the step size underflowed: the solution is singular near this time",
    -4: "out of memory in the C integrator",
    -6: "the wall-time limit (max_wall_s) was reached: raise it (None: no limit) or shorten "
    "the span",
}


#: Output buffers of at most this many points are kept by a compiled run between calls.
_KEPT_OUTPUTS_MAX = 4096


class CompiledTaylorRun:
    """The compiled loop of one problem (library, parameters, tolerances, order, step and
    limits) with its arguments converted to C pointers once: :meth:`run` packs a start, runs
    the loop, in blocks of ``ARITHMETICS[kind].chunk_steps`` when a wall-time limit is set
    (each block resumes from the exact time, state and compensation the previous one
    reached, so the steps and results are those of one uninterrupted call), and returns the
    solution.
    ``integrate`` makes one per call (:func:`_c_run`); a
    :class:`~chaplygin.numerics.propagator.Propagator` keeps one."""

    def __init__(self, clib, p, rtol, atol, order, step, max_steps, max_wall_s=None):
        ptr = CompiledTaylor._ptr
        n = clib.n_state
        self.clib, self.n, self.max_steps, self.max_wall_s = clib, n, max_steps, max_wall_s
        self.order = order
        self.chunk = max_steps if max_wall_s is None else ARITHMETICS[clib.kind].chunk_steps
        self.size = clib.real.size  # bytes per real: pointers below are char pointers
        # parameters and step control in the library's format
        self.P, self.ctrl = clib.pack(p), clib.pack([rtol, atol, step or 0])
        self.t01, self.y, self.y_end, self.t_reached = (
            clib.empty(2), clib.empty(n), clib.empty(n), clib.empty(1)
        )
        # the compensation of the state (double and quad: the rounding error the loop
        # carries), zero at the start, handed from one block of steps to the next in place
        self.y_lo = clib.empty(n)
        self.stats = np.zeros(4, dtype=np.int64)
        self.args = [ptr(self.t01), ptr(self.y), ptr(self.P), ptr(self.ctrl), order or 0, 0,
                     None, None, ptr(self.y_end), ptr(self.t_reached), 0,
                     _ffi.cast("long *", self.stats.ctypes.data), ptr(self.y_lo)]
        self._outputs: dict[int, tuple] = {}  # number of outputs -> buffers and pointers

    def _output_buffers(self, m: int) -> tuple:
        bufs = self._outputs.get(m)
        if bufs is None:
            t_buf, y_buf = self.clib.empty(max(m, 1)), self.clib.empty(max(m, 1) * self.n)
            bufs = (t_buf, y_buf, CompiledTaylor._ptr(t_buf), CompiledTaylor._ptr(y_buf))
            # kept for the next call when small (a kept run must not hold a long output)
            if len(self._outputs) < 8 and m <= _KEPT_OUTPUTS_MAX:
                self._outputs[m] = bufs
        return bufs

    def run(
        self, y0: Sequence[Any], t_span: Sequence[Any], t_eval: Sequence[Any]
    ) -> TaylorSolution:
        """Integrate from ``y0`` over ``t_span`` with output at ``t_eval``.

        Parameters
        ----------
        y0 : sequence of numbers
            The initial state (working numbers of the library's kind).
        t_span : (t0, t1)
            The span (``t1 < t0``: backward).
        t_eval : sequence of numbers
            Output times, sorted in the direction of integration, inside the span.

        Returns
        -------
        TaylorSolution
            Outputs reached, status and message, steps and orders, backend ``c-<kind>``.
        """
        clib, n, m, size = self.clib, self.n, len(t_eval), self.size
        t_buf, y_buf, t_ptr, y_ptr = self._output_buffers(m)
        # float64 buffers take the numbers as they are (numpy converts); others are packed
        pack = _same if clib.kind == "double" else clib.pack
        if m:
            t_buf[:] = pack(t_eval)  # m reals: the buffer of m outputs
        self.t01[:] = pack(t_span)
        self.y[:] = pack(y0)
        self.y_lo[:] = 0
        args, stats = self.args, self.stats
        deadline = None if self.max_wall_s is None else time.perf_counter() + self.max_wall_s
        steps, pmax, pmin, done = 0, 0, 10**9, 0
        while True:
            args[5] = m - done
            args[6] = t_ptr + size * done if done < m else t_ptr
            args[7] = y_ptr + size * done * n if done < m else y_ptr
            args[10] = min(self.chunk, self.max_steps - steps)
            status = clib.lib.chaplygin_taylor_run(*args)
            steps += int(stats[0])
            if stats[0]:
                pmax, pmin = max(pmax, int(stats[1])), min(pmin, int(stats[2]))
            done += int(stats[3])
            if status != -2 or steps >= self.max_steps:
                break
            if deadline is not None and time.perf_counter() > deadline:
                status = -6
                break
            # resume exactly where the call stopped: its time, state and compensation, as
            # they are in C (y_lo is updated in place)
            self.t01[: len(self.t_reached)] = self.t_reached
            self.y[:] = self.y_end
        real = clib.real
        if clib.kind == "double":  # the float64 buffer as it is: one copy, transposed
            y_out = y_buf[: done * n].reshape(done, n).T.copy()
        else:
            rows = real.rows(real.unpack(y_buf, done * n), done, n)
            y_out = np.array(rows, dtype=real.dtype).reshape(done, n).T.copy()
        return TaylorSolution(
            t=real.times(t_eval[:done]),
            y=y_out,
            status=int(status),
            message=_MESSAGES.get(int(status), "failed"),
            nsteps=steps,
            order_min=pmin if steps else 0,
            order_max=pmax,
            backend=f"c-{clib.kind}",
        )


def _same(values):
    return values


#: The compiled runs of recent problems, per thread (a run's buffers are its own while it
#: runs): ``integrate`` called again with the same model, parameters and control reuses the
#: pointers and buffers instead of converting them again (the outputs are copied out).
_RUNS = threading.local()
_RUNS_MAX = 16


def _c_run(clib, y0, t_span, p, rtol, atol, t_eval, order, step, max_steps, max_wall_s=None):
    try:
        key = (clib, tuple(p), rtol, atol, order, step, max_steps, max_wall_s,
               ARITHMETICS[clib.kind].chunk_steps)
        hash(key)
    except TypeError:  # pragma: no cover - working numbers are hashable
        key = None
    runs = getattr(_RUNS, "runs", None)
    if runs is None:
        runs = _RUNS.runs = {}
    run = runs.get(key) if key is not None else None
    if run is None:
        run = CompiledTaylorRun(clib, p, rtol, atol, order, step, max_steps, max_wall_s)
        if key is not None:
            if len(runs) >= _RUNS_MAX:
                del runs[next(iter(runs))]
            runs[key] = run
    return run.run(y0, t_span, t_eval)


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


# --------------------------------------------------------------------------- dense solution


def _compensated_eval(C: np.ndarray, s: Any, y_lo: Any) -> tuple[np.ndarray, np.ndarray]:
    """State at offset ``s`` from the coefficients ``C`` (``(..., n, p + 1)``) of a step and
    the compensation ``y_lo`` carried into it, with the new compensation: the operations of
    the C loop's ``taylor_eval_compensated`` (``derive/templates/taylor.c``) on float64,
    bit for bit (each numpy operation is one IEEE operation, never fused, and the C is
    built with ``-ffp-contract=off``)."""
    p = C.shape[-1] - 1
    v = C[..., p]
    for k in range(p - 1, 0, -1):
        v = v * s + C[..., k]
    d = v * s + y_lo
    c0 = C[..., 0]
    y = c0 + d
    bb = y - c0  # TwoSum: c0 + d = y + error exactly
    return y, (c0 - (y - bb)) + (d - bb)


def _horner_rows(C: np.ndarray, s: Any) -> np.ndarray:
    """State at offset ``s`` from the coefficients ``C`` (``(..., n, p + 1)``): Horner, the
    operations of :func:`_eval_poly` (the Python loop, uncompensated)."""
    p = C.shape[-1] - 1
    v = C[..., p]
    for k in range(p - 1, -1, -1):
        v = v * s + C[..., k]
    return v


#: Times evaluated together by :meth:`TaylorDense.__call__` (bounds the gathered
#: coefficients' memory; the values do not depend on it).
DENSE_CHUNK = 8192


class TaylorDense:
    """The double-precision Taylor solution as a function of time (dense output).

    Made by :func:`taylor_dense`. Every step keeps its Taylor polynomial, so the state is
    known at any time of the span: ``sol(t)`` evaluates the polynomial of the step that holds
    ``t`` by Horner's rule, the operations of the integrator's own output, so that the values
    are those :func:`taylor_solve` gives at the same output times, bit for bit (the compiled
    loop carries the rounding error of the state from step to step, ``y_lo``, and so does
    this solution; the Python recurrences carry none, and neither does it then). Steps and
    polynomials are IEEE operations in a fixed order (the C library, or Python floats): the
    same bits on every machine.

    Attributes
    ----------
    t : ndarray, shape (nsteps + 1,)
        Step times: ``t[0] = t0``, ``t[-1]`` the time reached.
    orders : ndarray of int, shape (nsteps,)
        Order of each step.
    coefficients : list of ndarray
        Step ``j``: shape ``(n_state, orders[j] + 1)``, the normalised Taylor coefficients at
        ``t[j]``: ``y(t[j] + s) = sum_k c[:, k] s^k + y_lo[j]``.
    y_lo : ndarray, shape (nsteps, n_state)
        The compensation carried into each step (zeros without the compiled loop).
    y_end : ndarray, shape (n_state,)
        The state at ``t[-1]``.
    status : int
        0 (the end was reached), -1 (the state became NaN or infinite), -2 (more than
        ``max_steps`` steps), -3 (step size underflow).
    message, backend : str
    compensated : bool
        Whether ``y_lo`` is carried (the compiled loop's update).
    """

    def __init__(self, stepper: _Stepper, t0: float, y0: np.ndarray, max_steps: int):
        self._stepper = stepper
        self.backend = stepper.backend
        self.compensated = stepper.clib is not None
        self.max_steps = max_steps
        self.n = len(y0)
        self._y0 = np.array(y0, dtype=float)
        self._t: list[float] = [float(t0)]
        self._orders: list[int] = []
        self._coeffs: list[np.ndarray] = []
        self._ylo: list[np.ndarray] = []
        self._y = self._y0.copy()
        self._y_lo = np.zeros(self.n)
        self.direction = 0
        self.status = 0
        self.message = _MESSAGES[0]
        self._groups_cache: tuple | None = None

    # ------------------------------------------------------------------ the steps
    def extend(self, t1: float) -> TaylorDense:
        """Integrate on from the time reached to ``t1`` (in the direction of the span),
        exactly as one integration would go on from there (state and compensation).

        Parameters
        ----------
        t1 : float
            The new end.

        Returns
        -------
        TaylorDense
            ``self``; ``status`` says whether ``t1`` was reached.

        Raises
        ------
        UserInputError
            ``t1`` not a finite number, or not beyond the time reached in the direction
            of integration.
        """
        from .arguments import check_real

        check_real(t1, "t1", double=True)
        t1 = float(t1)
        t = self._t[-1]
        direction = 1 if t1 > t else -1
        if t1 == t or (self.direction and direction != self.direction):
            raise UserInputError(
                f"the solution goes on from t = {t!r} "
                + ("forward" if self.direction >= 0 else "backward")
                + f": t1 = {t1!r} is not beyond it"
            )
        self.direction = direction
        if self.status:
            return self
        self._groups_cache = None
        stepper, y, y_lo = self._stepper, self._y, self._y_lo
        status = 0
        while direction * (t1 - t) > 0:
            if len(self._orders) >= self.max_steps:
                status = -2
                break
            t_new, y_next, coefficients, h, p, step_status = stepper.step(t, y, t1)
            h, t_new = float(h), float(t_new)
            if h == 0 or t + h == t:
                status = -3
                break
            C = np.array(coefficients(), dtype=float)
            if self.compensated:
                y_new, y_lo_new = _compensated_eval(C, h, y_lo)
            else:
                y_new, y_lo_new = np.array(y_next, dtype=float), y_lo
            self._coeffs.append(C)
            self._orders.append(int(p))
            self._ylo.append(y_lo)
            self._t.append(t_new)
            t, y, y_lo = t_new, y_new, y_lo_new
            if step_status or not np.all(np.isfinite(y)):
                status = -1
                break
        self._y, self._y_lo = y, y_lo
        self.status = status
        self.message = _MESSAGES.get(status, "failed")
        return self

    @property
    def t(self) -> np.ndarray:
        return np.array(self._t)

    @property
    def orders(self) -> np.ndarray:
        return np.array(self._orders, dtype=int)

    @property
    def coefficients(self) -> list[np.ndarray]:
        return list(self._coeffs)

    @property
    def y_lo(self) -> np.ndarray:
        return np.array(self._ylo).reshape(len(self._ylo), self.n)

    @property
    def y_end(self) -> np.ndarray:
        return self._y.copy()

    @property
    def nsteps(self) -> int:
        return len(self._orders)

    @property
    def order_min(self) -> int:
        return min(self._orders, default=0)

    @property
    def order_max(self) -> int:
        return max(self._orders, default=0)

    # ------------------------------------------------------------------ evaluation
    def _start_value(self) -> np.ndarray:
        # the C loop's output at t0 is y + y_lo (y_lo = 0 there); the Python loop's is y
        return self._y0 + 0.0 if self.compensated else self._y0.copy()

    def _at_step(self, j: int, s: float) -> np.ndarray:
        """State at ``t[j] + s`` on step ``j``'s polynomial."""
        C = self._coeffs[j]
        if self.compensated:
            return _compensated_eval(C, s, self._ylo[j])[0]
        return _horner_rows(C, s)

    def _groups(self) -> tuple[np.ndarray, dict[int, tuple[np.ndarray, np.ndarray]]]:
        """Each step's place in the stack of the steps of its order, and the stacks."""
        if self._groups_cache is None:
            orders = np.array(self._orders, dtype=int)
            place = np.zeros(len(orders), dtype=int)
            stacks = {}
            for p in np.unique(orders):
                steps = np.flatnonzero(orders == p)
                place[steps] = np.arange(len(steps))
                stacks[int(p)] = (
                    np.stack([self._coeffs[j] for j in steps]),
                    np.stack([self._ylo[j] for j in steps]),
                )
            self._groups_cache = (place, stacks)
        return self._groups_cache

    def _check_times(self, t: Any) -> tuple[np.ndarray, bool]:
        try:
            times = np.asarray(t)
        except (TypeError, ValueError):
            times = np.asarray(None)
        if times.dtype.kind not in "iuf":
            raise UserInputError(f"times must be real numbers, got {t!r}")
        times = times.astype(float)
        if times.ndim > 1:
            raise UserInputError(f"times must be a number or a 1-D sequence, got shape "
                                 f"{times.shape}")  # fmt: skip
        lo, hi = min(self._t[0], self._t[-1]), max(self._t[0], self._t[-1])
        inside = (times >= lo) & (times <= hi)
        if not np.all(inside):
            bad = float(np.atleast_1d(times)[~np.atleast_1d(inside)][0])
            raise UserInputError(
                f"t = {bad!r} is outside the span [{lo!r}, {hi!r}] of the solution"
            )
        return np.atleast_1d(times), times.ndim == 0

    def __call__(self, t: Any) -> np.ndarray:
        """The state at ``t`` (a number or a 1-D sequence of times in the span).

        A time ``t[j] < t <= t[j + 1]`` (forward) is evaluated on step ``j`` at offset
        ``t - t[j]``, as the integrator's output at that time.

        Parameters
        ----------
        t : float or array_like, shape (m,)

        Returns
        -------
        ndarray
            Shape ``(n_state,)`` for a number, ``(n_state, m)`` for a sequence (as
            scipy's ``OdeSolution``).

        Raises
        ------
        UserInputError
            Times that are not numbers, not finite or outside the span.
        """
        times, scalar = self._check_times(t)
        out = np.empty((self.n, times.size))
        steps = np.array(self._t)
        key = self.direction * steps  # increasing
        index = np.searchsorted(key[1:], self.direction * times, side="left")
        index = np.minimum(index, max(self.nsteps - 1, 0))
        start = times == steps[0]
        if self.nsteps:
            place, stacks = self._groups()
            orders = np.array(self._orders, dtype=int)[index]
            for a in range(0, times.size, DENSE_CHUNK):
                chunk = slice(a, a + DENSE_CHUNK)
                for p, (stack, lo_stack) in stacks.items():
                    sel = np.flatnonzero((orders[chunk] == p) & ~start[chunk]) + a
                    if sel.size == 0:
                        continue
                    rows = place[index[sel]]
                    C = stack[rows]
                    s = (times[sel] - steps[index[sel]])[:, None]
                    if self.compensated:
                        values = _compensated_eval(C, s, lo_stack[rows])[0]
                    else:
                        values = _horner_rows(C, s)
                    out[:, sel] = values.T
        out[:, start] = self._start_value()[:, None]
        return out[:, 0] if scalar else out

    def crossings(
        self, g: Callable[[float, np.ndarray], float], direction: int = 0, samples: int = 4
    ) -> tuple[np.ndarray, np.ndarray]:
        """Where ``g(t, y)`` changes sign along the solution (event location).

        ``g`` is sampled at ``samples`` equal parts of every step; each sign change between
        two samples is located on that step's polynomial by Brent's method
        (:func:`scipy.optimize.brentq`, scalar code: the same bits everywhere) to a few
        units in the last place of ``t``. A change at a sample counts once, where ``g``
        reaches 0 from a nonzero value.

        Parameters
        ----------
        g : callable
            ``g(t, y) -> float``.
        direction : {0, 1, -1}
            Every crossing, only those where ``g`` increases (1), or decreases (-1), along
            the direction of integration.
        samples : int
            Samples per step (>= 1): sign changes between them are found.

        Returns
        -------
        t : ndarray, shape (m,)
            The crossing times in the order of integration.
        y : ndarray, shape (m, n_state)
            The states there.

        Raises
        ------
        UserInputError
            A bad ``direction`` or ``samples``.
        """
        from scipy.optimize import brentq

        if direction not in (-1, 0, 1) or isinstance(direction, bool):
            raise UserInputError(f"direction must be 1, -1 or 0, got {direction!r}")
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
            raise UserInputError(f"samples must be a positive integer, got {samples!r}")
        steps = self._t
        eps = 2.0**-52
        found_t: list[float] = []
        found_y: list[np.ndarray] = []
        g_prev = float(g(steps[0], self._start_value()))
        for j in range(self.nsteps):
            a, b = steps[j], steps[j + 1]
            h = b - a
            t_prev = a
            for k in range(1, samples + 1):
                tk = b if k == samples else a + h * k / samples
                gk = float(g(tk, self._at_step(j, tk - a)))
                crossing = (g_prev < 0 < gk) or (g_prev > 0 > gk) or (gk == 0 and g_prev != 0)
                if crossing and (direction == 0 or (direction > 0) == (gk > g_prev)):
                    if gk == 0:
                        root = tk
                    else:
                        lo, hi = min(t_prev, tk), max(t_prev, tk)
                        root = float(brentq(
                            lambda x, j=j, a=a: float(g(x, self._at_step(j, x - a))),
                            lo, hi, rtol=4 * eps, maxiter=200,
                            xtol=4 * eps * max(abs(lo), abs(hi), np.finfo(float).tiny),
                        ))  # fmt: skip
                    found_t.append(root)
                    found_y.append(self._at_step(j, root - a))
                g_prev, t_prev = gk, tk
        y = np.array(found_y).reshape(len(found_y), self.n)
        return np.array(found_t, dtype=float), y


def taylor_dense(
    code: ModelCode,
    y0: Sequence[float],
    t_span: tuple[float, float],
    p: Sequence[float],
    *,
    rtol: float,
    atol: float,
    max_steps: int = MAX_STEPS,
    lib: str | None = None,
) -> TaylorDense:
    """Integrate in double precision with the Taylor method and keep every step's polynomial.

    The steps are those of :func:`taylor_solve` (the compiled C loop's order, step and
    compensated state update; the Python recurrences on floats without a compiler or with
    ``lib="float"``), so :meth:`TaylorDense.__call__` at any time gives what
    ``taylor_solve(..., t_eval=...)`` gives there, bit for bit, and the same bits on every
    machine.

    Parameters
    ----------
    code : ModelCode
        The model (:func:`chaplygin.numerics.code.load_model_code`).
    y0 : sequence of float
        Initial state (``n_state`` finite numbers).
    t_span : (t0, t1)
        Start and end; ``t1 < t0`` integrates backward.
    p : sequence of float
        Parameters in the model's order.
    rtol, atol : float
        Local tolerances of the Jorba-Zou control (at least the unit roundoff ``2^-52``).
    max_steps : int
        Largest number of steps (status -2 beyond it).
    lib : {None, "c", "float"}
        The compiled double library (default, with the Python recurrences as fallback
        when there is no compiler) or the Python recurrences on floats.

    Returns
    -------
    TaylorDense
        Its ``status`` is 0 when ``t1`` was reached.

    Raises
    ------
    UserInputError
        States, parameters, span or tolerances that are not finite numbers of the right
        count, an empty span, tolerances below the unit roundoff, a bad ``max_steps`` or
        ``lib``.

    Examples
    --------
    >>> from chaplygin.numerics.code import load_model_code
    >>> code = load_model_code("chaplygin_ball")
    >>> sol = taylor_dense(code, [0.7, -0.4, 0.5, 0.6, 0.0, 0.8], (0.0, 2.0),
    ...                    [1.0, 2.0, 3.0, 1.0], rtol=1e-12, atol=1e-12)
    >>> sol.status, sol(1.0).shape, sol([0.5, 1.5]).shape
    (0, (6,), (6, 2))
    """
    from .arguments import check_real, check_vector

    n, m = len(code.state), len(code.params)
    y = [float(v) for v in _checked_values(check_vector, y0, "y0", n)]
    params = [float(v) for v in _checked_values(check_vector, p, "p", m)]
    t0, t1 = (float(v) for v in _checked_values(check_vector, t_span, "t_span", 2))
    if t0 == t1:
        raise UserInputError("t_span must be non-empty (t1 != t0)")
    tolerances = []
    for value, name in ((rtol, "rtol"), (atol, "atol")):
        check_real(value, name, positive=True, double=True)
        if float(value) < 2.0**-52:
            raise UserInputError(
                f"{name} = {float(value)!r} is below the unit roundoff of double precision "
                "(2^-52): use precision='quad' or digits with chaplygin.numerics.integrate"
            )
        tolerances.append(float(value))
    rtol, atol = tolerances
    if isinstance(max_steps, bool) or not isinstance(max_steps, int) or max_steps < 1:
        raise UserInputError(f"max_steps must be a positive integer, got {max_steps!r}")
    if lib not in (None, "c", "float"):
        raise UserInputError(f"lib must be None, 'c' or 'float', got {lib!r}")
    clib = load_taylor_library(code, "double", run_orders(rtol, atol)) if lib != "float" else None
    stepper = _Stepper(code, "float", params, rtol, atol, None, None, clib)
    return TaylorDense(stepper, t0, np.array(y), max_steps).extend(t1)


def _checked_values(check_vector: Callable, values: Any, name: str, count: int) -> list:
    """``values`` as given (floats kept exactly), after ``check_vector``'s checks."""
    check_vector(values, name, count, double=True)
    return list(values)
