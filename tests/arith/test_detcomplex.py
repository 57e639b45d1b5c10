"""Complex arithmetic in a fixed operation order (arith/detcomplex.py) against mpmath.

References are mpmath at 200 bits on the exact double inputs, an independent route; bounds
are the textbook ones in units of the double epsilon (a product's component, Smith's
quotient, faithful elementary functions). numpy's own complex multiply and modulus pick
their loops by processor: the negative control shows them taking other bits without the
AVX2/FMA loops while these functions do not.
"""

from __future__ import annotations

import os
import subprocess
import sys

import mpmath
import numpy as np
import pytest
from chaplygin.arith import detcomplex as dc

pytestmark = pytest.mark.quick

EPS = np.finfo(float).eps


def _complex(count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    scale = np.exp2(rng.integers(-20, 20, count))  # exact powers of two: wide magnitudes
    return (rng.normal(size=count) + 1j * rng.normal(size=count)) * scale


def _mp(z) -> mpmath.mpc:
    return mpmath.mpc(float(z.real), float(z.imag))


def test_products_and_quotients_are_accurate():
    a, b = _complex(300, 1), _complex(300, 2)
    prod, quot = dc.mul(a, b), dc.div(a, b)
    with mpmath.workprec(200):
        for x, y, p, q in zip(a, b, prod, quot, strict=True):
            exact = _mp(x) * _mp(y)
            # each component: two rounded products and a rounded sum
            bound = 2 * EPS * abs(x) * abs(y)
            assert abs(p.real - exact.real) <= bound and abs(p.imag - exact.imag) <= bound
            exact = _mp(x) / _mp(y)
            assert abs(_mp(q) - exact) <= 4 * EPS * abs(exact)


def test_modulus_argument_and_exponentials_are_faithful():
    z = _complex(300, 3)
    x = 40 * np.random.default_rng(4).random(300) - 20
    mod, arg, cis, exp = dc.absolute(z), dc.phase(z), dc.cis(x), dc.exp(z / np.abs(z) * 3)
    with mpmath.workprec(200):
        for w, m, a in zip(z, mod, arg, strict=True):
            assert abs(m - abs(_mp(w))) <= EPS * m
            assert abs(a - mpmath.arg(_mp(w))) <= EPS * abs(a)
        for t, c in zip(x, cis, strict=True):
            exact = mpmath.expjpi(mpmath.mpf(float(t)) / mpmath.pi)
            assert abs(_mp(c) - exact) <= EPS
        for w, e in zip(z / np.abs(z) * 3, exp, strict=True):
            exact = mpmath.exp(_mp(w))
            assert abs(_mp(e) - exact) <= 3 * EPS * abs(exact)


def test_numbers_and_arrays_take_the_same_bits():
    a, b = _complex(50, 5), _complex(50, 6)
    for f in (dc.mul, dc.div):
        one = np.array([f(complex(x), complex(y)) for x, y in zip(a, b, strict=True)])
        assert np.array_equal(one, f(a, b))
        assert isinstance(f(complex(a[0]), 2.0), complex)
    for f in (dc.absolute, dc.phase):
        one = np.array([f(complex(x)) for x in a])
        assert np.array_equal(one, f(a)) and isinstance(f(complex(a[0])), float)
    assert np.array_equal(np.array([dc.exp(complex(x)) for x in a / 1e6]), dc.exp(a / 1e6))
    assert np.array_equal(np.array([dc.cis(float(x)) for x in a.real]), dc.cis(a.real))


def test_special_values():
    assert dc.make(np.inf, -np.inf) == complex(np.inf, -np.inf)
    z = dc.make([1.0, np.inf], [np.nan, 0.0])
    assert np.isnan(z[0].imag) and z[1].real == np.inf
    assert dc.mul(3 + 4j, 1j) == -4 + 3j  # exact: products of small integers
    assert dc.div(-4 + 3j, 1j) == 3 + 4j
    assert dc.absolute(3 + 4j) == 5.0 and dc.phase(-1.0) == np.pi
    q = dc.div(1 + 1j, 0j)  # no exception: IEEE NaN, as an array division gives
    assert np.isnan(q.real) and np.isnan(q.imag)


def test_results_do_not_depend_on_numpys_simd_loops():
    """The same bits with numpy's AVX2/FMA loops switched off; numpy's own complex multiply
    and modulus change there (the negative control, where the processor has those loops)."""
    script = (
        "import hashlib, numpy as np\n"
        "try:\n"
        "    from numpy._core._multiarray_umath import __cpu_features__ as f\n"
        "except ImportError:  # numpy 1\n"
        "    from numpy.core._multiarray_umath import __cpu_features__ as f\n"
        "from chaplygin.arith import detcomplex as dc\n"
        "rng = np.random.default_rng(8)\n"
        "a = rng.normal(size=999) + 1j * rng.normal(size=999)\n"
        "b = rng.normal(size=999) + 1j * rng.normal(size=999)\n"
        "h = lambda xs: hashlib.sha256(b''.join(np.ascontiguousarray(x).tobytes() for x in xs))"
        ".hexdigest()\n"
        "print(h([dc.mul(a, b), dc.div(a, b), dc.absolute(a), dc.phase(a), dc.exp(a)]), "
        "h([a * b, np.abs(a)]), int(f['AVX2'] and f['FMA3']))\n"
    )
    seen = {}
    for name, extra in (("default", {}), ("baseline", {"NPY_DISABLE_CPU_FEATURES": "X86_V3"})):
        env = {k: v for k, v in os.environ.items() if not k.startswith("NPY_")} | extra
        seen[name] = subprocess.run(
            [sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True
        ).stdout.split()
    assert seen["default"][0] == seen["baseline"][0], seen
    if seen["default"][2] == "1":  # the default run used the AVX2/FMA loops
        assert seen["default"][1] != seen["baseline"][1], "numpy kept its bits (control)"
