"""Compile emitted C model code on demand, cache the shared library, load it with cffi.

The C sources written by :class:`chaplygin.derive.emit.CEmitter` (``generated/*.c``) define,
for one model, ``chaplygin_model_hash``, ``chaplygin_sizes`` and the routines
``chaplygin_rhs``, ``chaplygin_jac``, ``chaplygin_aux``, ``chaplygin_integrals`` and
``chaplygin_density``, each ``void f(double T, const double *Y, const double *P, double *OUT)``.
This module turns such a source into a :class:`CompiledModel` with numpy-friendly methods;
the compiler and its cache are :mod:`.ccompile`'s (its names are re-exported here), the
CPython trampoline for single calls is :mod:`.fastcall`'s.

Design rules:

* **lazy** -- nothing is compiled at import; :func:`load_c_model` compiles on first use;
* **cached and idempotent** -- a library is stored under a key that hashes the source text, the
  compiler (path and ``--version`` output), the flags and the platform; an existing library is
  reused without running the compiler;
* **safe under concurrency** -- the compiler writes a temporary file in the cache directory which
  is then moved into place with :func:`os.replace`, so several processes building the same model
  at once all end up loading a complete library; no process-global state (working directory,
  environment, umask) is ever changed;
* **optional** -- without a working C compiler :func:`load_c_model` warns with
  :class:`CompilerUnavailableWarning` and returns ``None``; callers then use the numpy module.

The flags are ``-O2 -shared -fPIC -std=c99 -ffp-contract=off`` and ``-lm``: no ``-ffast-math``
and no fused multiply-add contraction, so results are IEEE double precision and reproducible
(clang contracts ``a*b + c`` into an FMA by default, hence the explicit ``-ffp-contract=off``).

The cache lives in ``$CHAPLYGIN_CACHE_DIR`` if set, else the platform's user cache folder
(:func:`~chaplygin.derive.cachefiles.cache_root`); libraries go into its ``c/`` subfolder
(see :func:`c_cache_dir`).

Examples
--------
>>> from pathlib import Path
>>> from chaplygin.numerics.compiled import load_c_model
>>> source = Path("generated/chaplygin_ball.c").read_text()  # doctest: +SKIP
>>> model = load_c_model(source)  # doctest: +SKIP
>>> model.rhs(0.0, y, p)  # doctest: +SKIP
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import Any

import cffi
import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..derive.emit.c_sources import model_library_source
from ..derive.errors import ChaplyginError
from .ccompile import (
    CFLAGS,
    LDLIBS,
    CacheError,
    CompilationError,
    CompilerError,
    CompilerNotFoundError,
    c_cache_dir,
    compile_c,
    find_compiler,
)
from .fastcall import load_fastcall

__all__ = [
    "CFLAGS",
    "LDLIBS",
    "CompilerError",
    "CompilerNotFoundError",
    "CompilationError",
    "CompilerUnavailableWarning",
    "ModelHashMismatchError",
    "CompiledModel",
    "c_cache_dir",
    "compile_c",
    "find_compiler",
    "load_c_model",
]

_F64 = np.dtype(np.float64)

_CDEF = """
const char *chaplygin_model_hash(void);
void chaplygin_sizes(int *OUT);
void chaplygin_rhs(double T, const double *Y, const double *P, double *OUT);
void chaplygin_jac(double T, const double *Y, const double *P, double *OUT);
void chaplygin_aux(double T, const double *Y, const double *P, double *OUT);
void chaplygin_integrals(double T, const double *Y, const double *P, double *OUT);
void chaplygin_density(double T, const double *Y, const double *P, double *OUT);
void chaplygin_many_rhs(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0, ptrdiff_t YS1,
                        const double *P, double *OUT, ptrdiff_t OS0, ptrdiff_t OS1);
void chaplygin_many_jac(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0, ptrdiff_t YS1,
                        const double *P, double *OUT, ptrdiff_t OS0, ptrdiff_t OS1);
void chaplygin_many_aux(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0, ptrdiff_t YS1,
                        const double *P, double *OUT, ptrdiff_t OS0, ptrdiff_t OS1);
void chaplygin_many_integrals(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0,
                              ptrdiff_t YS1, const double *P, double *OUT, ptrdiff_t OS0,
                              ptrdiff_t OS1);
void chaplygin_many_density(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0,
                            ptrdiff_t YS1, const double *P, double *OUT, ptrdiff_t OS0,
                            ptrdiff_t OS1);
void chaplygin_many_params_rhs(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0,
        ptrdiff_t YS1, const double *P, ptrdiff_t PS0, ptrdiff_t PS1, double *OUT,
        ptrdiff_t OS0, ptrdiff_t OS1);
void chaplygin_many_params_jac(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0,
        ptrdiff_t YS1, const double *P, ptrdiff_t PS0, ptrdiff_t PS1, double *OUT,
        ptrdiff_t OS0, ptrdiff_t OS1);
void chaplygin_many_params_aux(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0,
        ptrdiff_t YS1, const double *P, ptrdiff_t PS0, ptrdiff_t PS1, double *OUT,
        ptrdiff_t OS0, ptrdiff_t OS1);
void chaplygin_many_params_integrals(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0,
        ptrdiff_t YS1, const double *P, ptrdiff_t PS0, ptrdiff_t PS1, double *OUT,
        ptrdiff_t OS0, ptrdiff_t OS1);
void chaplygin_many_params_density(double T, ptrdiff_t N, const double *Y, ptrdiff_t YS0,
        ptrdiff_t YS1, const double *P, ptrdiff_t PS0, ptrdiff_t PS1, double *OUT,
        ptrdiff_t OS0, ptrdiff_t OS1);
"""

_ffi = cffi.FFI()
_ffi.cdef(_CDEF)
_from_buffer = _ffi.from_buffer
_DOUBLES = _ffi.typeof("double[]")  # pre-parsed: from_buffer is faster without the string

# --------------------------------------------------------------------------- errors


class ModelHashMismatchError(ChaplyginError, ValueError):
    """The compiled library reports a model hash other than the expected one."""


class CompilerUnavailableWarning(UserWarning):
    """No usable C compiler: the (slower) numpy implementation is used instead."""


# --------------------------------------------------------------------------- loading


def _as_input(a: Any, shape: tuple[int, ...], name: str) -> NDArray[np.float64]:
    """``a`` as a C-contiguous float64 array of the given shape (no copy when it is one)."""
    if type(a) is not np.ndarray or a.dtype is not _F64 or not a.flags.c_contiguous:
        a = np.ascontiguousarray(a, dtype=np.float64)
    if a.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {a.shape}")
    return a


def _out_buffer(out: Any, shape: tuple[int, ...]) -> Any:
    """cffi ``double[]`` view of a caller-provided output array (validated, never copied)."""
    if type(out) is np.ndarray and out.dtype is _F64 and out.shape == shape:
        try:
            return _from_buffer(_DOUBLES, out, True)
        except (ValueError, BufferError, TypeError):
            pass
    return _from_buffer(_DOUBLES, _as_output(out, shape), True)


def _as_output(out: Any, shape: tuple[int, ...]) -> NDArray[np.float64]:
    if not isinstance(out, np.ndarray) or out.dtype != _F64 or out.shape != shape:
        raise ValueError(
            f"out must be a float64 array of shape {shape}, got "
            f"{getattr(out, 'dtype', type(out).__name__)} {getattr(out, 'shape', '')}"
        )
    if not (out.flags.c_contiguous and out.flags.writeable):
        raise ValueError("out must be C-contiguous and writeable")
    return out


class CompiledModel:
    """One model's compiled routines, loaded with cffi (ABI mode).

    Parameters
    ----------
    library : path-like
        Shared library built from an emitted C source (see :func:`compile_c`).
    expected_hash : str, optional
        Model hash the library must report (``chaplygin_model_hash()``).

    Attributes
    ----------
    path : pathlib.Path
        The loaded library.
    model_hash : str
        Hash reported by the library.
    n_state, n_param, n_aux, n_integrals : int
        Sizes reported by ``chaplygin_sizes``.

    Raises
    ------
    ModelHashMismatchError
        If `expected_hash` is given and differs from the library's hash.
    OSError
        If the library cannot be loaded.

    Notes
    -----
    All routines take ``(t, y, p)`` like the numpy modules: ``y`` is the state (``n_state``
    doubles), ``p`` the parameters (``n_param`` doubles).  float64 C-contiguous arrays are
    used as they are, anything else is converted.  Without ``out`` a fresh array is returned,
    so results stay valid across calls (scipy keeps references to them); pass ``out`` to
    avoid the allocation.  The parameter array of the previous call is remembered, so passing
    the same array object again (as ``scipy.integrate.solve_ivp(model.rhs, ..., args=(p,))``
    does) skips its conversion; the values are read at each call, so in-place changes to it
    are seen.  Methods are thread-safe (no shared scratch buffers); cffi releases the GIL
    during the C call.
    """

    def __init__(self, library: str | os.PathLike[str], expected_hash: str | None = None) -> None:
        self.path = Path(library)
        lib = _ffi.dlopen(os.fspath(self.path))
        try:
            model_hash_fn = lib.chaplygin_model_hash
            sizes_fn = lib.chaplygin_sizes
            routines = {
                name: getattr(lib, f"chaplygin_{name}")
                for name in ("rhs", "jac", "aux", "integrals", "density")
            }
        except AttributeError as exc:
            raise ValueError(f"{self.path} is not a chaplygin model library: {exc}") from exc
        self._lib = lib  # keeps the library loaded while the function pointers are used
        self.model_hash: str = _ffi.string(model_hash_fn()).decode("ascii")
        if expected_hash is not None and self.model_hash != expected_hash:
            raise ModelHashMismatchError(
                f"compiled model {self.path} has hash {self.model_hash}, expected "
                f"{expected_hash}: the C source is out of date with the model; regenerate it "
                "with `chaplygin derive`"
            )
        sizes = _ffi.new("int[4]")
        sizes_fn(sizes)
        self.n_state, self.n_param, self.n_aux, self.n_integrals = (int(s) for s in sizes)
        n = self.n_state
        self._y_shape = (n,)
        self._p_shape = (self.n_param,)
        self._rhs = routines["rhs"]
        self._jac = routines["jac"]
        self._aux = routines["aux"]
        self._integrals = routines["integrals"]
        self._density = routines["density"]
        self._out_shapes: dict[str, tuple[int, ...]] = {
            "rhs": (n,),
            "jac": (n, n),
            "aux": (self.n_aux,),
            "integrals": (self.n_integrals,),
            "density": (1,),
        }
        self._many: dict[str, Any] = {}
        for name in self._out_shapes:
            for kind in ("many", "many_params"):
                try:
                    self._many[kind, name] = getattr(lib, f"chaplygin_{kind}_{name}")
                except AttributeError:  # library built without (this version of) the shim
                    pass
        self._p_last: tuple[Any, Any] = (None, None)
        # the CPython trampoline for single calls (None: the cffi path below)
        fast = load_fastcall()
        self._fast = None if fast is None else fast.call
        self._address = {name: int(_ffi.cast("uintptr_t", fn)) for name, fn in routines.items()}

    def __repr__(self) -> str:
        return (
            f"<CompiledModel {self.model_hash[:12]} n_state={self.n_state} "
            f"n_param={self.n_param} from {self.path}>"
        )

    # -- helpers ---------------------------------------------------------------------

    def _p_buffer(self, p: Any) -> Any:
        last = self._p_last
        if p is last[0]:
            return last[1]
        if type(p) is np.ndarray and p.dtype is _F64 and p.shape == self._p_shape:
            try:
                buf = _from_buffer(_DOUBLES, p)
            except (ValueError, BufferError):  # not contiguous: converted below
                pass
            else:
                self._p_last = (p, buf)
                return buf
        return _from_buffer(_DOUBLES, _as_input(p, self._p_shape, "p"))

    def _y_buffer(self, y: Any) -> Any:
        if type(y) is np.ndarray and y.dtype is _F64 and y.shape == self._y_shape:
            try:
                return _from_buffer(_DOUBLES, y)
            except (ValueError, BufferError):  # not contiguous
                pass
        return _from_buffer(_DOUBLES, _as_input(y, self._y_shape, "y"))

    def _call(self, fn: Any, name: str, t: float, y: Any, p: Any, out: Any) -> NDArray:
        shape = self._out_shapes[name]
        if self._fast is not None and len(shape) == 1:
            r = self._fast(self._address[name], shape[0], self.n_state, self.n_param, t, y, p, out)
            if r is not NotImplemented:
                return r
        if out is None:
            out = np.empty(shape)
            obuf = _from_buffer(_DOUBLES, out)
        else:
            obuf = _out_buffer(out, shape)
        fn(t, self._y_buffer(y), self._p_buffer(p), obuf)
        return out

    # -- single state ----------------------------------------------------------------

    def rhs(self, t: float, y: ArrayLike, p: ArrayLike, out: NDArray | None = None) -> NDArray:
        """Right-hand side dy/dt.

        Parameters
        ----------
        t : float
            Time.
        y : array_like, shape (n_state,)
            State.
        p : array_like, shape (n_param,)
            Parameters.
        out : ndarray, shape (n_state,), optional
            float64 C-contiguous array receiving the result.

        Returns
        -------
        ndarray, shape (n_state,)
            `out` if given, else a new array.
        """
        # Fast path inlined (this is the routine an integrator calls most).
        fast = self._fast
        if fast is not None:
            n = self.n_state
            r = fast(self._address["rhs"], n, n, self.n_param, t, y, p, out)
            if r is not NotImplemented:
                return r
        if out is None:
            out = np.empty(self._y_shape)
            obuf = _from_buffer(_DOUBLES, out)
        else:
            obuf = _out_buffer(out, self._y_shape)
        if type(y) is np.ndarray and y.dtype is _F64 and y.shape == self._y_shape:
            try:
                ybuf = _from_buffer(_DOUBLES, y)
            except (ValueError, BufferError):  # not contiguous
                ybuf = self._y_buffer(y)
        else:
            ybuf = self._y_buffer(y)
        last = self._p_last
        self._rhs(t, ybuf, last[1] if p is last[0] else self._p_buffer(p), obuf)
        return out

    def jac(self, t: float, y: ArrayLike, p: ArrayLike, out: NDArray | None = None) -> NDArray:
        """Jacobian d(dy/dt)/dy.

        Parameters
        ----------
        t, y, p, out
            As for :meth:`rhs`; `out` has shape (n_state, n_state).

        Returns
        -------
        ndarray, shape (n_state, n_state)
            ``J[i, j] = d rhs_i / d y_j``.
        """
        return self._call(self._jac, "jac", t, y, p, out)

    def aux(self, t: float, y: ArrayLike, p: ArrayLike, out: NDArray | None = None) -> NDArray:
        """Auxiliary quantities (order of the numpy module's ``AUX``).

        Parameters
        ----------
        t, y, p, out
            As for :meth:`rhs`; `out` has shape (n_aux,).

        Returns
        -------
        ndarray, shape (n_aux,)
            The auxiliary quantities at ``(t, y)``.
        """
        return self._call(self._aux, "aux", t, y, p, out)

    def integrals(
        self, t: float, y: ArrayLike, p: ArrayLike, out: NDArray | None = None
    ) -> NDArray:
        """First integrals (order of the numpy module's ``INTEGRALS``).

        Parameters
        ----------
        t, y, p, out
            As for :meth:`rhs`; `out` has shape (n_integrals,).

        Returns
        -------
        ndarray, shape (n_integrals,)
            The first integrals at ``(t, y)``.
        """
        return self._call(self._integrals, "integrals", t, y, p, out)

    def density(self, t: float, y: ArrayLike, p: ArrayLike, out: NDArray | None = None) -> NDArray:
        """Invariant-measure density.

        Parameters
        ----------
        t, y, p, out
            As for :meth:`rhs`; `out` has shape (1,).

        Returns
        -------
        ndarray, shape (1,)
            Same shape as the numpy module's ``density``.
        """
        return self._call(self._density, "density", t, y, p, out)

    # -- many states -----------------------------------------------------------------

    def _call_many(self, name: str, t: float, Y: ArrayLike, p: ArrayLike, out: Any) -> NDArray:
        Y = np.asarray(Y, dtype=np.float64)
        if Y.ndim != 2 or Y.shape[0] != self.n_state:
            raise ValueError(f"Y must have shape ({self.n_state}, N), got {Y.shape}")
        if not Y.flags.aligned or any(s % Y.itemsize for s in Y.strides):
            Y = np.array(Y, order="C")  # a fresh copy is aligned
        N = Y.shape[1]
        shape = (*self._out_shapes[name], N)
        out = np.empty(shape) if out is None else _as_output(out, shape)
        if N == 0:
            return out
        per_state = np.ndim(p) == 2
        fn = self._many.get(("many_params" if per_state else "many", name))
        if per_state:
            p = np.asarray(p, dtype=np.float64)
            if p.shape != (self.n_param, N):
                raise ValueError(f"p must have shape ({self.n_param},) or ({self.n_param}, {N})")
        if fn is None:  # no batch shim in this library: loop over columns
            single = getattr(self, name)
            for j in range(N):
                out[..., j] = single(t, Y[:, j], p[:, j] if per_state else p)
            return out
        m = out.size // N
        ys0, ys1 = (s // Y.itemsize for s in Y.strides)
        Yp = _ffi.cast("double *", Y.ctypes.data)
        obuf = _from_buffer(_DOUBLES, out)
        if per_state:
            if not p.flags.aligned or any(s % p.itemsize for s in p.strides):
                p = np.array(p, order="C")
            ps0, ps1 = (s // p.itemsize for s in p.strides)
            pp = _ffi.cast("double *", p.ctypes.data)
            fn(t, N, Yp, ys0, ys1, pp, ps0, ps1, obuf, N if m > 0 else 0, 1)
        else:
            fn(t, N, Yp, ys0, ys1, self._p_buffer(p), obuf, N if m > 0 else 0, 1)
        return out

    def rhs_many(self, t: float, Y: ArrayLike, p: ArrayLike, out: NDArray | None = None) -> NDArray:
        """Right-hand side at many states (columns of `Y`), evaluated in one C call.

        Parameters
        ----------
        t : float
            Time (shared by all states).
        Y : array_like, shape (n_state, N)
            States as columns, like the numpy modules' vectorised input; any strides.
        p : array_like, shape (n_param,) or (n_param, N)
            Parameters: one set for all states, or one per state (columns; any strides).
            Each state's values are the single-state routine's, bit for bit.
        out : ndarray, shape (n_state, N), optional
            float64 C-contiguous array receiving the result.

        Returns
        -------
        ndarray, shape (n_state, N)
            Same layout as the numpy module's ``rhs(t, Y, p)``.
        """
        return self._call_many("rhs", t, Y, p, out)

    def jac_many(self, t: float, Y: ArrayLike, p: ArrayLike, out: NDArray | None = None) -> NDArray:
        """Jacobians at many states, evaluated in one C call.

        Parameters
        ----------
        t, Y, p
            Time, states as columns (shape ``(n_state, N)``) and parameters, as in
            :meth:`rhs_many`.
        out : ndarray, shape (n_state, n_state, N), optional
            float64 C-contiguous array receiving the result.

        Returns
        -------
        ndarray, shape (n_state, n_state, N)
            ``out[i, k, j]`` is ``d rhs_i/d y_k`` at ``Y[:, j]``.
        """
        return self._call_many("jac", t, Y, p, out)

    def aux_many(self, t: float, Y: ArrayLike, p: ArrayLike, out: NDArray | None = None) -> NDArray:
        """Auxiliary quantities at many states, evaluated in one C call.

        Parameters
        ----------
        t, Y, p
            Time, states as columns (shape ``(n_state, N)``) and parameters, as in
            :meth:`rhs_many`.
        out : ndarray, shape (n_aux, N), optional
            float64 C-contiguous array receiving the result.

        Returns
        -------
        ndarray, shape (n_aux, N)
            Rows in the order of the numpy module's ``AUX`` names.
        """
        return self._call_many("aux", t, Y, p, out)

    def integrals_many(
        self, t: float, Y: ArrayLike, p: ArrayLike, out: NDArray | None = None
    ) -> NDArray:
        """First integrals at many states, evaluated in one C call.

        Parameters
        ----------
        t, Y, p
            Time, states as columns (shape ``(n_state, N)``) and parameters, as in
            :meth:`rhs_many`.
        out : ndarray, shape (n_integrals, N), optional
            float64 C-contiguous array receiving the result.

        Returns
        -------
        ndarray, shape (n_integrals, N)
            Rows in the order of the numpy module's ``INTEGRALS``.
        """
        return self._call_many("integrals", t, Y, p, out)

    def density_many(
        self, t: float, Y: ArrayLike, p: ArrayLike, out: NDArray | None = None
    ) -> NDArray:
        """Density at many states, evaluated in one C call.

        Parameters
        ----------
        t, Y, p
            Time, states as columns (shape ``(n_state, N)``) and parameters, as in
            :meth:`rhs_many`.
        out : ndarray, shape (1, N), optional
            float64 C-contiguous array receiving the result.

        Returns
        -------
        ndarray, shape (1, N)
            The invariant-measure density at each state.
        """
        return self._call_many("density", t, Y, p, out)


def load_c_model(
    source: str,
    expected_hash: str | None = None,
    *,
    cache_dir: str | os.PathLike[str] | None = None,
    compiler: str | None = None,
) -> CompiledModel | None:
    """Compile (cached) and load an emitted C model source.

    Parameters
    ----------
    source : str
        C source emitted by :class:`chaplygin.derive.emit.CEmitter`.  The batch versions of
        its routines (``chaplygin_many_*``, used by :meth:`CompiledModel.rhs_many` and
        friends: :func:`chaplygin.derive.emit.c_sources.model_library_source`) are added
        before compiling.
    expected_hash : str, optional
        Model hash the library must report.
    cache_dir : path-like, optional
        Root of the cache; see :func:`c_cache_dir`.
    compiler : str, optional
        Compiler command; see :func:`find_compiler`.

    Returns
    -------
    CompiledModel or None
        None, after a :class:`CompilerUnavailableWarning`, if no C compiler is available, the
        compilation fails or the cache directory is not writable.

    Raises
    ------
    ModelHashMismatchError
        If `expected_hash` differs from the compiled model's hash.
    """
    full_source = model_library_source(source)
    try:
        path = compile_c(full_source, cache_dir=cache_dir, compiler=compiler)
        try:
            return CompiledModel(path, expected_hash)
        except OSError:
            # unloadable cache entry (e.g. damaged on disk): rebuild it once
            path = compile_c(full_source, cache_dir=cache_dir, compiler=compiler, force=True)
            return CompiledModel(path, expected_hash)
    except CacheError:
        raise
    except (CompilerError, OSError) as exc:
        warnings.warn(
            f"compiled C model unavailable, using the (slower) numpy implementation instead: "
            f"{exc}\nTo enable compiled models install a C compiler (e.g. `apt install gcc`, "
            "`xcode-select --install`) or set the CC environment variable to one; the cache "
            "directory can be moved with CHAPLYGIN_CACHE_DIR.",
            CompilerUnavailableWarning,
            stacklevel=2,
        )
        return None
