"""Compiled Taylor coefficients on Arb balls and jets: the validated integrator's kernel.

The validated integrator (:mod:`~chaplygin.numerics.validated.lohner`) spends nearly all its
time in the model's Taylor recurrences on :class:`~chaplygin.numerics.validated.jets.ArbJet`
numbers, one python-flint call (about a microsecond) per operation. :func:`arb_kernel`
compiles the same recurrences as C on Arb balls (:mod:`chaplygin.derive.emit.taylor_arb`),
linked to the FLINT library python-flint itself loads, and returns a drop-in for the
generated module's ``taylor_coefficients(t0, y, p, order, lib)`` for ``lib`` one of
:data:`~chaplygin.numerics.validated.jets.ARB_LIB` and
:data:`~chaplygin.numerics.validated.jets.JET_LIB`.

Both routes compute enclosures of the same coefficients by the same recurrences; their balls
are not bit for bit the same (a convolution is one ``arb_dot`` here, three matrix products
there) but each contains the exact values, and each is the same on every machine for a given
FLINT version.

The balls cross as pointers into python-flint's objects. The kernel is used only when every
check passes, and the Python recurrences are used otherwise (and for parameters that carry
a gradient):

* a C compiler and python-flint's own FLINT library (the wheel's ``python_flint.libs``, or the
  library the process has mapped) are found;
* the library reports the FLINT version python-flint reports, of major version 3 (whose ball
  layout, 48 bytes, the C source declares);
* a probe reads a ball python-flint computed and writes one python-flint reads back, both
  equal to the kernel's own computation.

:meth:`ArbTaylorKernel.gradient_series` gives the validated integrator the coefficients'
gradients as one matrix per state component (written by the kernel into python-flint's
``arb_mat``, the balls the jets would carry, without a jet per coefficient) when a second
probe finds FLINT 3's matrix layout (entries, rows, columns, stride) and a ball written
through it where it was meant to go; otherwise the integrator runs the jets.
"""

from __future__ import annotations

import glob
import os
import threading
import warnings
from itertools import repeat
from typing import Any

import cffi
import flint
import numpy as np
from flint import arb, arb_mat, ctx

from ...derive.emit.taylor_arb import taylor_arb_source
from ..ccompile import CompilerError, compile_c
from .jets import ARB_LIB, JET_LIB, ArbJet

__all__ = ["ArbTaylorKernel", "arb_kernel", "flint_library", "KernelUnavailableWarning"]

#: Bytes of an Arb ball (FLINT 3's arb_struct), as the C source declares it.
BALL_BYTES = 48

_CDEF = """
const char *chaplygin_taylor_model_hash(void);
const char *chaplygin_arb_flint_version(void);
int chaplygin_arb_ball_size(void);
void chaplygin_taylor_sizes(int *OUT);
int chaplygin_arb_probe(void *X, void *Y, long prec);
int chaplygin_taylor_arb(long prec, int order, int m, void **T0, void **Y, void **YG,
                         void **P, void **OUT, void **OUTG);
"""
_ffi = cffi.FFI()
_ffi.cdef(_CDEF)

#: Where python-flint keeps a ball in its ``arb`` object: the last field.
_OFFSET = arb.__basicsize__ - BALL_BYTES
#: Where python-flint keeps FLINT 3's ``arb_mat_struct`` (entries, rows, columns, stride) in
#: its ``arb_mat`` object: the last fields.
_MAT_OFFSET = arb_mat.__basicsize__ - 32

_KERNELS: dict[str, ArbTaylorKernel | None] = {}
_LOCK = threading.Lock()


class KernelUnavailableWarning(UserWarning):
    """The compiled Arb kernel could not be built or failed its checks; the validated
    integrator uses the (slower) Python recurrences."""


def flint_library() -> str | None:
    """The FLINT shared library python-flint runs with, or None.

    The file the process has mapped (Linux ``/proc/self/maps``), else the one python-flint's
    wheel ships (``python_flint.libs`` on Linux, ``flint/.dylibs`` on macOS).

    Returns
    -------
    str or None
        The library's path.
    """
    maps = "/proc/self/maps"
    if os.path.isfile(maps):
        try:
            with open(maps, encoding="utf-8", errors="replace") as fh:
                for line in fh:
                    path = line.split(None, 5)[-1].strip()
                    if os.path.basename(path).startswith("libflint") and os.path.isfile(path):
                        return path
        except OSError:
            pass
    package = os.path.dirname(os.path.abspath(flint.__file__))
    for pattern in (
        os.path.join(os.path.dirname(package), "python_flint.libs", "libflint*.so*"),
        os.path.join(package, ".dylibs", "libflint*.dylib"),
    ):
        found = sorted(glob.glob(pattern))
        if found:
            return found[0]
    return None


def _addresses(balls: list) -> Any:
    """A C array of pointers to the balls inside python-flint objects (kept alive by the
    caller while the array is used)."""
    addr = np.fromiter(map(id, balls), dtype=np.uint64, count=len(balls)) + np.uint64(_OFFSET)
    return addr, _ffi.cast("void **", _ffi.from_buffer(addr))


def _matrix_addresses(M: arb_mat, rows: int, cols: int) -> np.ndarray | None:
    """The addresses of the balls of a matrix python-flint made, row by row, from FLINT 3's
    ``arb_mat_struct`` (entries, r, c, stride); None when the struct does not read as a
    ``rows x cols`` matrix with contiguous rows (another layout: nothing is written)."""
    fields = _ffi.cast("int64_t *", id(M) + _MAT_OFFSET)
    entries, r, c, stride = fields[0], fields[1], fields[2], fields[3]
    if entries == 0 or r != rows or c != cols or stride != cols:
        return None
    index = np.arange(rows * cols, dtype=np.uint64) * np.uint64(BALL_BYTES)
    return index + np.uint64(entries)


def _fresh(count: int) -> list:
    """``count`` new zero balls (python-flint objects nobody else holds)."""
    return list(map(arb.__new__, repeat(arb, count)))


class ArbTaylorKernel:
    """The compiled Taylor coefficients of one model on Arb balls and jets.

    Call it as the generated module's ``taylor_coefficients(t0, y, p, order, lib)``.

    Parameters
    ----------
    library : path-like
        The compiled kernel.
    fallback : callable
        The Python recurrences, for what the kernel does not take (parameters with a
        gradient, another ``lib``).
    expected_hash : str
        The model's hash.

    Raises
    ------
    ValueError
        The library is of another model or of another FLINT, or fails the probe.
    """

    def __init__(self, library: os.PathLike | str, fallback: Any, expected_hash: str):
        self.library = os.fspath(library)
        self.lib = _ffi.dlopen(self.library)
        self.fallback = fallback
        got = _ffi.string(self.lib.chaplygin_taylor_model_hash()).decode()
        if got != expected_hash:
            raise ValueError(f"{library} is of model {got}, expected {expected_hash}")
        version = _ffi.string(self.lib.chaplygin_arb_flint_version()).decode()
        if version != flint.__FLINT_VERSION__ or not version.startswith("3."):
            raise ValueError(
                f"{library} runs with FLINT {version}, python-flint with "
                f"{flint.__FLINT_VERSION__} (the kernel is written for FLINT 3)"
            )
        if self.lib.chaplygin_arb_ball_size() != BALL_BYTES or _OFFSET < 16:
            raise ValueError("python-flint's balls are not laid out as the kernel expects")
        sizes = _ffi.new("int[4]")
        self.lib.chaplygin_taylor_sizes(sizes)
        self.n_state, self.n_param, _, self.max_seeds = list(sizes)
        self._probe()
        #: the identity seeds of :meth:`gradient_series` (kept: their addresses are passed)
        self._seeds = [arb(int(i == c)) for i in range(self.n_state) for c in range(self.n_state)]
        self._matrices = self._probe_matrices()

    def _probe(self) -> None:
        old = ctx.prec
        try:
            ctx.prec = 128
            x, y = arb(1) / 3, _fresh(1)[0]
            keep_x, px = _addresses([x])
            keep_y, py = _addresses([y])
            same = self.lib.chaplygin_arb_probe(px[0], py[0], 128)
            z = arb(2) / 3
            ok = same == 1 and y.mid() == z.mid() and y.rad() == z.rad()
        finally:
            ctx.prec = old
        del keep_x, keep_y
        if not ok:
            raise ValueError("the probe of python-flint's balls failed")

    def _probe_matrices(self) -> bool:
        """Whether the kernel can write into python-flint's matrices: a ball written through
        the addresses of :func:`_matrix_addresses` is read back where it was meant to go."""
        old = ctx.prec
        try:
            ctx.prec = 128
            M = arb_mat(2, 3)
            where = _matrix_addresses(M, 2, 3)
            if where is None:
                return False
            x = arb(1) / 3
            keep_x, px = _addresses([x])
            keep_y = where[5:6]
            py = _ffi.cast("void **", _ffi.from_buffer(keep_y))
            same = self.lib.chaplygin_arb_probe(px[0], py[0], 128)
            z = arb(2) / 3
            entries = [M[i, j] for i in range(2) for j in range(3)]
            return (same == 1 and entries[5].mid() == z.mid() and entries[5].rad() == z.rad()
                    and all(e == 0 for e in entries[:5]))  # fmt: skip
        finally:
            ctx.prec = old

    def gradient_series(self, t0: Any, y: list, p: list, order: int) -> tuple | None:
        """The Taylor coefficients ``0..order`` of the state over the balls ``y`` and their
        derivatives with respect to the initial state, as matrices (what the jets seeded with
        the unit vectors give, without a jet per coefficient).

        Parameters
        ----------
        t0 : arb
        y : list of arb
            The state's balls.
        p : list of arb
        order : int

        Returns
        -------
        (list of list of arb, list of arb_mat) or None
            ``n_state`` lists of ``order + 1`` balls, and for each state component the
            ``(order + 1) x n_state`` matrix of the coefficients' gradients; None when the
            kernel does not take these inputs (the caller runs the jets).
        """
        n = self.n_state
        if (not self._matrices or len(y) != n or len(p) != self.n_param or n > self.max_seeds
                or any(type(q) is not arb for q in p) or any(type(v) is not arb for v in y)):
            return None  # fmt: skip
        S = order + 1
        grads = [arb_mat(S, n) for _ in range(n)]
        where = [_matrix_addresses(G, S, n) for G in grads]
        if any(w is None for w in where):
            return None
        outg = np.concatenate(where)
        t0 = t0 if type(t0) is arb else arb(t0)
        out = _fresh(n * S)
        arrays = [_addresses(b) for b in ([t0], y, self._seeds, p or [t0], out)]
        pointers = [a[1] for a in arrays]
        pointers.append(_ffi.cast("void **", _ffi.from_buffer(outg)))
        status = self.lib.chaplygin_taylor_arb(ctx.prec, order, n, *pointers)
        del arrays, pointers
        if status != 0:  # pragma: no cover - the checks above keep the kernel's limits
            return None
        return [out[i * S : (i + 1) * S] for i in range(n)], grads

    def __call__(self, t0: Any, y: list, p: list, order: int, lib: Any) -> list:
        """Normalised Taylor coefficients ``0..order`` of the state components.

        Parameters
        ----------
        t0 : arb
        y : list of arb or ArbJet
            The state (jets: all with gradients of one width).
        p : list of arb
        order : int
        lib : namespace
            :data:`ARB_LIB` or :data:`JET_LIB` (anything else goes to the fallback).

        Returns
        -------
        list of list
            ``n_state`` lists of ``order + 1`` balls (``ARB_LIB``) or jets (``JET_LIB``).
        """
        if (lib is not ARB_LIB and lib is not JET_LIB) or any(type(q) is not arb for q in p):
            return self.fallback(t0, y, p, order, lib)
        n = self.n_state
        jets = lib is JET_LIB and any(type(v) is ArbJet for v in y)
        m = 0
        if jets:
            m = max(v.g.ncols() for v in y if type(v) is ArbJet and v.g is not None)
        if len(y) != n or len(p) != self.n_param or m > self.max_seeds:
            return self.fallback(t0, y, p, order, lib)
        values = [v.v if type(v) is ArbJet else arb(v) for v in y]
        grads: list = []
        if m:
            for v in y:
                g = v.g if type(v) is ArbJet else None
                if g is None:
                    grads.extend(_fresh(m))
                elif g.ncols() != m:
                    return self.fallback(t0, y, p, order, lib)
                else:
                    grads.extend(g[0, c] for c in range(m))
        t0 = t0 if type(t0) is arb else arb(t0)
        S = order + 1
        out = _fresh(n * S)
        outg = _fresh(n * S * m) if m else []
        inputs = ([t0], values, grads or [t0], p or [t0], out, outg or [t0])
        arrays = [_addresses(b) for b in inputs]
        status = self.lib.chaplygin_taylor_arb(ctx.prec, order, m, *(a[1] for a in arrays))
        del arrays
        if status != 0:  # pragma: no cover - the checks above keep the kernel's limits
            return self.fallback(t0, y, p, order, lib)
        if not m:
            return [out[i * S : (i + 1) * S] for i in range(n)]
        rows = [outg[j * m : (j + 1) * m] for j in range(n * S)]
        result = [ArbJet(v, arb_mat([r])) for v, r in zip(out, rows, strict=True)]
        return [result[i * S : (i + 1) * S] for i in range(n)]


def arb_kernel(code: Any) -> ArbTaylorKernel | None:
    """The compiled Arb kernel of a model's Taylor recurrences, or None (then the Python
    recurrences ``code.taylor.taylor_coefficients`` are the route).

    Built once per model and process; its library is cached with the other compiled code.

    Parameters
    ----------
    code : ModelCode
        The model's generated code (its ``taylor_program`` and ``taylor`` module).

    Returns
    -------
    ArbTaylorKernel or None
        None for recurrences without a printed program (no warning), and without a C
        compiler, without python-flint's FLINT library, or when a check fails (a
        :class:`KernelUnavailableWarning` says why, once per model).
    """
    key, program = getattr(code, "hash", None), getattr(code, "taylor_program", None)
    if not key or not program:  # recurrences without a printed program: nothing to compile
        return None
    with _LOCK:
        if key in _KERNELS:
            return _KERNELS[key]
        kernel = None
        library = flint_library()
        try:
            if library is None:
                raise ValueError("python-flint's FLINT library was not found")
            source = taylor_arb_source(program)
            folder = os.path.dirname(library)
            path = compile_c(source, ldlibs=(library, f"-Wl,-rpath,{folder}"))
            kernel = ArbTaylorKernel(path, code.taylor.taylor_coefficients, code.hash)
        except (CompilerError, OSError, ValueError) as exc:
            warnings.warn(
                f"compiled Arb kernel of {code.name} unavailable, the validated integrator "
                f"uses the Python recurrences: {exc}",
                KernelUnavailableWarning,
                stacklevel=2,
            )
        _KERNELS[key] = kernel
        return kernel
