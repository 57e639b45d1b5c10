"""Nanoseconds per call of detmath.h's functions against glibc's libm, on the same arguments.

Each function is a C loop over 10^4 arguments, compiled by ``compile_c`` with the project's flags
(``-O2 -ffp-contract=off``); the detmath loop and the glibc loop alternate, 200 times each, and
the fastest run of each counts (the machines are shared: the minimum is what the code costs,
the rest is other processes). Throughput of independent calls, as in a vectorised right-hand
side; random arguments, so branches are as unpredictable as they get.

Run: ``python examples/bench/detmath_speed.py [REPEATS]``.
"""

from __future__ import annotations

import sys
import time

import cffi
import numpy as np
from chaplygin.arith import detmath
from chaplygin.numerics.ccompile import compile_c

N = 10_000
UNARY = ("exp", "log", "log2", "log10", "sin", "cos", "atan", "asin", "acos", "cbrt", "sinh",
         "cosh")  # fmt: skip
BINARY = ("pow", "atan2", "hypot")


def cases(rng: np.random.Generator) -> dict[str, tuple[str, tuple[np.ndarray, ...]]]:
    """Label -> (function, arguments)."""
    return {
        "exp": ("exp", (rng.uniform(-700, 700, N),)),
        "exp |x| < 1": ("exp", (rng.uniform(-1, 1, N),)),
        "log": ("log", (np.exp2(rng.uniform(-1000, 1000, N)),)),
        "log x near 1": ("log", (rng.uniform(0.9, 1.1, N),)),
        "log2": ("log2", (np.exp2(rng.uniform(-1000, 1000, N)),)),
        "log10": ("log10", (np.exp2(rng.uniform(-1000, 1000, N)),)),
        "pow": ("pow", (rng.uniform(0, 10, N), rng.uniform(-20, 20, N))),
        "sin |x| < 10": ("sin", (rng.uniform(-10, 10, N),)),
        "sin |x| < 1e6": ("sin", (rng.uniform(-1e6, 1e6, N),)),
        "sin x ~ 1e100": ("sin", (rng.uniform(1e100, 2e100, N),)),
        "cos |x| < 10": ("cos", (rng.uniform(-10, 10, N),)),
        "atan": ("atan", (rng.uniform(-10, 10, N),)),
        "atan2": ("atan2", (rng.uniform(-5, 5, N), rng.uniform(-5, 5, N))),
        "asin": ("asin", (rng.uniform(-1, 1, N),)),
        "acos": ("acos", (rng.uniform(-1, 1, N),)),
        "cbrt": ("cbrt", (rng.uniform(-100, 100, N),)),
        "hypot": ("hypot", (rng.uniform(-5, 5, N), rng.uniform(-5, 5, N))),
        "sinh": ("sinh", (rng.uniform(-20, 20, N),)),
        "cosh": ("cosh", (rng.uniform(-20, 20, N),)),
    }


def library() -> tuple[cffi.FFI, object]:
    """The loops ``c_<name>`` (detmath) and ``g_<name>`` (libm), compiled and loaded."""
    ffi = cffi.FFI()
    declarations, source = [], [detmath.header_text()]
    for name in UNARY + BINARY:
        args = "const double *x, double *o, long n" if name in UNARY else (
            "const double *x, const double *y, double *o, long n")  # fmt: skip
        call = "(x[i])" if name in UNARY else "(x[i], y[i])"
        for prefix, function in (("c", f"chaplygin_{name}"), ("g", name)):
            declarations.append(f"void {prefix}_{name}({args});")
            loop = f"for (long i = 0; i < n; i++) o[i] = {function}{call};"
            source.append(f"void {prefix}_{name}({args}) {{ {loop} }}")
    ffi.cdef("\n".join(declarations))
    return ffi, ffi.dlopen(str(compile_c("\n".join(source) + "\n")))


def main() -> None:
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    ffi, lib = library()
    out = np.empty(N)
    print(f"{'case':16s} {'detmath':>9s} {'glibc':>9s}  ratio   (ns per call, best of {repeats})")
    for label, (name, args) in cases(np.random.default_rng(2024)).items():
        pointers = [ffi.cast("double *", a.ctypes.data) for a in args]
        target = ffi.cast("double *", out.ctypes.data)
        best = {"c": np.inf, "g": np.inf}
        for _ in range(repeats):
            for prefix in best:
                fn = getattr(lib, f"{prefix}_{name}")
                t0 = time.perf_counter()
                fn(*pointers, target, N)
                best[prefix] = min(best[prefix], time.perf_counter() - t0)
        c, g = best["c"] / N * 1e9, best["g"] / N * 1e9
        print(f"{label:16s} {c:9.1f} {g:9.1f}  {c / g:5.2f}")


if __name__ == "__main__":
    main()
