"""Speed of detmath.h against glibc's libm (pytest-benchmark; skipped in the default test run).

Run: ``pytest -n 0 tests/benchmarks/test_bench_detmath.py --benchmark-enable --benchmark-only
--benchmark-group-by=group``.  Each benchmark is one C loop over 10^4 arguments (compiled by
``compile_c`` with the project's flags), so the time per call is the median divided by 10^4;
the two implementations of a function share a group and run on the same arguments.  The
machines are shared and noisy: compare the two rows of a group, not runs.
"""

from __future__ import annotations

import cffi
import numpy as np
import pytest
from chaplygin.arith import detmath
from chaplygin.numerics.ccompile import compile_c

pytestmark = pytest.mark.benchmark

N = 10_000
UNARY = ("exp", "log", "log2", "log10", "sin", "cos", "atan", "asin", "acos", "cbrt", "sinh",
         "cosh")  # fmt: skip
BINARY = ("pow", "atan2", "hypot")

_rng = np.random.default_rng(2024)
ARGUMENTS = {
    "exp": (_rng.uniform(-700, 700, N),),
    "exp, |x| < 1": (_rng.uniform(-1, 1, N),),
    "log": (np.exp2(_rng.uniform(-1000, 1000, N)),),
    "log, x near 1": (_rng.uniform(0.9, 1.1, N),),
    "log2": (np.exp2(_rng.uniform(-1000, 1000, N)),),
    "log10": (np.exp2(_rng.uniform(-1000, 1000, N)),),
    "sin": (_rng.uniform(-10, 10, N),),
    "sin, |x| < 1e6": (_rng.uniform(-1e6, 1e6, N),),
    "sin, x ~ 1e100": (_rng.uniform(1e100, 2e100, N),),
    "cos": (_rng.uniform(-10, 10, N),),
    "atan": (_rng.uniform(-10, 10, N),),
    "asin": (_rng.uniform(-1, 1, N),),
    "acos": (_rng.uniform(-1, 1, N),),
    "cbrt": (_rng.uniform(-100, 100, N),),
    "sinh": (_rng.uniform(-20, 20, N),),
    "cosh": (_rng.uniform(-20, 20, N),),
    "pow": (_rng.uniform(0, 10, N), _rng.uniform(-20, 20, N)),
    "atan2": (_rng.uniform(-5, 5, N), _rng.uniform(-5, 5, N)),
    "hypot": (_rng.uniform(-5, 5, N), _rng.uniform(-5, 5, N)),
}

_FFI = cffi.FFI()
_SIGNATURES = []
_SOURCE = [detmath.header_text()]
for _name in UNARY + BINARY:
    _args = "const double *x, double *o, long n" if _name in UNARY else (
        "const double *x, const double *y, double *o, long n")  # fmt: skip
    _call = "(x[i])" if _name in UNARY else "(x[i], y[i])"
    for _prefix, _function in (("c", f"chaplygin_{_name}"), ("g", _name)):
        _SIGNATURES.append(f"void {_prefix}_{_name}({_args});")
        _loop = f"for (long i = 0; i < n; i++) o[i] = {_function}{_call};"
        _SOURCE.append(f"void {_prefix}_{_name}({_args}) {{ {_loop} }}")
_FFI.cdef("\n".join(_SIGNATURES))


@pytest.fixture(scope="module")
def library():
    return _FFI.dlopen(str(compile_c("\n".join(_SOURCE) + "\n")))


@pytest.mark.parametrize("implementation", ["chaplygin", "glibc"])
@pytest.mark.parametrize("case", list(ARGUMENTS))
def test_per_call(benchmark, library, case, implementation):
    name = case.split(",")[0]
    args = tuple(np.ascontiguousarray(a) for a in ARGUMENTS[case])
    out = np.empty(N)
    pointers = [_FFI.cast("double *", a.ctypes.data) for a in args]
    prefix, other = ("c_", "g_") if implementation == "chaplygin" else ("g_", "c_")
    benchmark.group = f"{case} ({N} calls)"
    benchmark(getattr(library, prefix + name), *pointers, _FFI.cast("double *", out.ctypes.data),
              N)  # fmt: skip
    check = np.empty(N)
    getattr(library, other + name)(*pointers, _FFI.cast("double *", check.ctypes.data), N)
    # both faithful (glibc's documented bounds are a few ulps for some functions): a few ulps
    assert np.allclose(out, check, rtol=1e-15, atol=0, equal_nan=True)
