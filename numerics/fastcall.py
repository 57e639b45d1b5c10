"""A CPython trampoline for single calls of the compiled routines.

cffi's ABI mode spends about 1.5 µs per call turning numpy arrays into pointers; an
integrator that calls the right-hand side once per stage pays it every time. This module
compiles (once, into the C cache) a small extension module with one function::

    call(address, n_out, n_state, n_param, t, y, p, out) -> out, a new array or NotImplemented

that checks in C that ``y``, ``p`` (and ``out``, when given) are aligned, C-contiguous
float64 numpy arrays of the right length (``out`` also writeable), calls the routine at
``address`` (a ``void f(double, const double *, const double *, double *)``) and returns
``out`` or a fresh array. Anything else gives ``NotImplemented`` and the caller takes its
general (converting) path, so the trampoline never changes a result, only the cost.

Without the Python or numpy headers, or without a C compiler, :func:`load_fastcall`
returns None and the cffi path is used.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import sys
import sysconfig
from functools import cache
from types import ModuleType

import numpy as np

from ..derive.emit.c_sources import fastcall_source
from .ccompile import CompilationError, CompilerNotFoundError, compile_c

__all__ = ["load_fastcall"]


@cache
def load_fastcall() -> ModuleType | None:
    """The compiled trampoline module, or None when it cannot be built here.

    Built into the C cache on first use (the interpreter and numpy versions are part of the
    cache key); None without a compiler or without Python or numpy headers. Cached for the
    process.

    Returns
    -------
    types.ModuleType or None
        The extension module ``chaplygin_fastcall``.
    """
    include = sysconfig.get_paths().get("include")
    if not include:
        return None
    flags = ("-std=gnu11", f"-I{include}", f"-I{np.get_include()}")
    # the interpreter and numpy it is built for are part of the cache key
    source = fastcall_source(f"python {sys.version}; numpy {np.__version__}")
    try:
        path = compile_c(source, cflags=flags)
    except (CompilationError, CompilerNotFoundError, OSError):
        return None
    loader = importlib.machinery.ExtensionFileLoader("chaplygin_fastcall", str(path))
    spec = importlib.util.spec_from_file_location("chaplygin_fastcall", str(path), loader=loader)
    if spec is None:
        return None
    try:
        module = importlib.util.module_from_spec(spec)
        loader.exec_module(module)
    except ImportError:
        return None
    return module
