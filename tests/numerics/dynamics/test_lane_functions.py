"""The vector lanes' sine and cosine (``templates/batch_map.c``: detmath's functions written on
GCC vectors, the DOP853 lanes' only vector libm calls) against the bits of ``chaplygin_sin``
and ``chaplygin_cos``, computed by an independent route: the Python port
``chaplygin.arith.detmath``, itself checked bit for bit against the C (tests/arith)."""

from __future__ import annotations

import numpy as np
import pytest
from chaplygin.arith import detmath
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.integrators.c_batch import batch_library, lockstep_available

PI_4 = np.pi / 4


def _arguments() -> np.ndarray:
    """Every branch of the scalar functions, both signs: the identity and polynomial kernels
    (|x| < 2^-27, < 0.125), the table kernels, each quadrant, next to multiples of pi/4 and
    to 0.125 (where the kernel changes), the Cody-Waite range's end 2^20 and beyond (Payne-
    Hanek: the lanes fall back to the scalar function), huge, infinite and NaN arguments."""
    rng = np.random.default_rng(26)
    tiny = np.ldexp(rng.uniform(0.5, 1.0, 64), rng.integers(-40, -26, 64))
    ranges = [rng.uniform(-a, a, 3000) for a in (0.2, 1.0, 7.0, 2e3, 1.1e6)]
    k = rng.integers(-4000, 4000, 3000)
    near = k * PI_4 + rng.integers(-300, 300, 3000) * np.spacing(np.abs(k * PI_4) + 1.0)
    edges = np.array([0.125, 2.0**20, PI_4, 2.0**-27, 1e300, 0.0, np.inf, np.nan])
    around = np.concatenate([np.nextafter(edges, np.inf), edges, np.nextafter(edges, -np.inf)])
    x = np.concatenate([tiny, *ranges, near, around])
    return np.concatenate([x, -x])


@pytest.fixture(scope="module")
def lanes():
    code = load_model_code("chaplygin_ball", ["variable_inertia", "variable_gyrostat"])
    lib = batch_library(code)
    if lib is None or not lockstep_available(code):
        pytest.skip("no C compiler with vector lanes")
    ffi = __import__("cffi").FFI()

    def run(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
        x = np.ascontiguousarray(x, dtype=np.float64)
        s, c = np.empty_like(x), np.empty_like(x)
        width = lib.chaplygin_lanes_sincos(
            x.size, ffi.from_buffer("double[]", x), ffi.from_buffer("double[]", s),
            ffi.from_buffer("double[]", c),
        )  # fmt: skip
        return s, c, width

    return run


def _same_bits(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return (a.view(np.int64) == b.view(np.int64)) | (np.isnan(a) & np.isnan(b))


def test_the_lanes_give_the_bits_of_the_scalar_sine_and_cosine(lanes):
    x = _arguments()
    s, c, width = lanes(x)
    assert width in (4, 8)
    assert _same_bits(s, detmath.sin(x)).all(), x[~_same_bits(s, detmath.sin(x))][:5]
    assert _same_bits(c, detmath.cos(x)).all(), x[~_same_bits(c, detmath.cos(x))][:5]


def test_the_same_comparison_refutes_a_last_bit_change(lanes):
    """Control: the scalar bits moved by one ulp (up, and down) are refuted everywhere by the
    comparison that accepts the lanes."""
    x = _arguments()
    x = x[np.isfinite(x)]
    s, c, _ = lanes(x)
    for reference, got in ((detmath.sin(x), s), (detmath.cos(x), c)):
        for direction in (np.inf, -np.inf):
            assert not _same_bits(got, np.nextafter(reference, direction)).any()
