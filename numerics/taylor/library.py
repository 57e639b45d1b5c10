"""Compiling and loading the generated Taylor code: the C library in double, quad,
double-double and quad-double (:class:`CompiledTaylor`) and the MPFR library
(:class:`CompiledTaylorMPFR`), each compiled once per model and kept (:data:`_LIBS`)."""

from __future__ import annotations

import os
import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import cffi
import gmpy2
import mpmath
import numpy as np

from ...derive.emit.c_sources import taylor_source
from ...derive.emit.taylor_unroll import unrolled_source
from ..compiled import CompilerError, CompilerUnavailableWarning, compile_c
from ..precision import ARITHMETICS
from .reals import REAL_TYPES, _mpfr_text, _parse_mpfr, _rows_lists

if TYPE_CHECKING:
    from ..code import ModelCode

__all__ = [
    "CompiledTaylor",
    "CompiledTaylorMPFR",
    "load_taylor_library",
    "load_taylor_mpfr_library",
    "mpfr_build_flags",
    "UNROLLED_CFLAGS",
    "UNROLLED_CFLAGS_MAX_BYTES",
    "UNROLLED_MAX_BYTES",
    "unrolled_cflags",
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

#: Written-out sources longer than this (bytes) are compiled without :data:`UNROLLED_CFLAGS`:
#: the scheduler's cost grows faster than the source (one basic block per order). Measured
#: with gcc -O2 at order 20 (2 cores, 2026-11-27; without / with the flags): the ball 322 kB
#: 0.9 / 1.8 s, BM20's ball 479 kB 1.8 / 4.4 s, the spherical support 733 kB 3.6 / 10.2 s, the
#: described ball on a turntable 1.77 MB 16.7 / 105.8 s.
UNROLLED_CFLAGS_MAX_BYTES = 512_000

#: Written-out sources longer than this (bytes) are not compiled: the loop's library runs
#: instead (the same bits, a slower step). A large described model's program (a convex body
#: on a support surface: 916 nodes, 3.1 MB at order 13) took minutes of gcc -O2 (328 s
#: under load ~4, 2026-11-27) against 11 s for its loop; the built-ins write out at most
#: 1.1 MB at order 20 (1.6 MB at order 24) and keep their written-out steps.
UNROLLED_MAX_BYTES = 2_000_000


def unrolled_cflags(source: str) -> tuple[str, ...]:
    """The extra flags of a written-out source: :data:`UNROLLED_CFLAGS` up to
    :data:`UNROLLED_CFLAGS_MAX_BYTES`, none above (the same bits either way).

    Parameters
    ----------
    source : str

    Returns
    -------
    tuple of str
    """
    return UNROLLED_CFLAGS if len(source) <= UNROLLED_CFLAGS_MAX_BYTES else ()


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
        double only, the same bits as the loop, faster; not above :data:`UNROLLED_MAX_BYTES`
        of source): one more library per set of orders,
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
            if written_out is None or len(written_out) > UNROLLED_MAX_BYTES:
                break  # (too large: the loop, whose compilation takes seconds, not minutes)
            try:
                flags = (*real.cflags, *unrolled_cflags(written_out))
                path = _compile_quietly(written_out, ldlibs, flags)
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
