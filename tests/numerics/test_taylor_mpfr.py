"""The compiled MPFR Taylor integrator (issue 15): digits past quad-double (> 60) in C.

``generated/<model>_taylor_mpfr.c`` runs the recurrences of the same Taylor program as the
other builds with in-place MPFR calls at the run's precision, linked to gmpy2's own MPFR;
numbers cross the interface as exact base-16 text. References are independent routes: the
Python recurrences with gmpy2 at 30 more digits (coefficients and solutions), and
``mpmath.odefun`` for a solution. Tolerances: every MPFR operation (and the correctly rounded
``mpfr_dot``) is rounded once to ``2^-prec``; the coefficient bound allows ``2^10 2^-prec``
relative to the largest coefficient of the same order (as the multi-double tests), the
solution bound ``10 * rtol`` per step summed over the steps.
"""

from __future__ import annotations

import gmpy2
import mpmath
import numpy as np
import pytest
from chaplygin.numerics import integrate, load_model_code
from chaplygin.numerics.code import generated_manifest
from chaplygin.numerics.compiled import CompilerUnavailableWarning
from chaplygin.numerics.inputs import Precision, pack_state
from chaplygin.numerics.taylor import (
    CompiledTaylorMPFR,
    _mpfr_text,
    _parse_mpfr,
    load_taylor_mpfr_library,
    taylor_solve,
)
from test_taylor_multi_double import _coefficient_error  # the same comparison as there

# non-dyadic decimals (more digits than a double or quad-double holds)
STATE = {
    "M": (
        "0.71234567890123456789012345678901234567890123456789012345678901234567891",
        "-0.4098765432109876543210987654321",
        "0.5",
    ),
    "gamma": ("0.2", "0.3", "sqrt(0.87)"),
}
PARAMS = {"I": ("1.2716", "2.9031", "4.4187"), "D": "0.6513"}


def test_text_interface_is_exact():
    """A working number goes in as base-16 text and comes back from MPFR's %Ra bit for bit,
    at 200 digits, its last bit included."""
    code = load_model_code("chaplygin_ball")
    lib = load_taylor_mpfr_library(code)
    assert lib is not None
    with mpmath.workdps(200):
        x = -mpmath.mpf(10) / 7
        y = x + mpmath.ldexp(1, mpmath.mag(x) - mpmath.mp.prec)  # the next number down
        assert x != y
        assert _mpfr_text([x, 0, 3]) == f"-{int(x._mpf_[1]):x}p{x._mpf_[2]} 0 3p0".encode()
        # order 1 coefficients: row 0 starts with y_0 itself, read back from C
        for v in (x, y):
            rows = lib.coefficients(1, 0, [v, *([mpmath.mpf(1) / 3] * 5)], [2, 3, 5, 1])
            assert rows[0][0] == v
        assert _parse_mpfr(b"-0x1.8p+1") == -3 and _parse_mpfr(b"0x0p+0") == 0
        assert _parse_mpfr(b"inf") == mpmath.inf and mpmath.isnan(_parse_mpfr(b"nan"))


def test_more_than_60_digits_run_in_mpfr():
    """61 digits and more run in C MPFR, 60 in quad-double; backend 'numpy' forces the
    Python recurrences."""
    assert Precision(61).arithmetic.name == "mpfr"
    ran = [
        integrate("chaplygin_ball", STATE, 0.5, PARAMS, precision=d).backend for d in (60, 61, 100)
    ]
    assert ran == ["c-qd", "c-mpfr", "c-mpfr"]
    forced = integrate("chaplygin_ball", STATE, 0.5, PARAMS, precision=80, backend="numpy")
    assert forced.backend == "python-gmpy2"


def _generic_inputs(code, digits):
    with mpmath.workdps(digits):
        n, m = len(code.state), len(code.params)
        y = [mpmath.mpf(3 + i) / (11 + 2 * i) * (-1) ** i for i in range(n)]
        p = [mpmath.mpf(13 + 3 * i) / (7 + i) for i in range(m)]
        t0 = mpmath.mpf(3) / 10
    return t0, y, p


# chaplygin_ball: products and a quotient; the potential surface: a rational power; variable
# inertia: sin and cos
@pytest.mark.parametrize("digits", [80, 120, 200])
@pytest.mark.parametrize(
    "system,effects",
    [
        ("chaplygin_ball", ()),
        ("ball_on_surface", ("potential",)),
        ("chaplygin_ball", ("variable_inertia",)),
    ],
)
def test_coefficients_match_mpfr_recurrences(system, effects, digits):
    """Order-40 coefficients at generic non-dyadic data against the Python recurrences in
    MPFR at 30 more digits; a parameter rounded to double is refuted by the same check."""
    code = load_model_code(system, effects)
    lib = load_taylor_mpfr_library(code)
    assert lib is not None
    t0, y, p = _generic_inputs(code, digits)
    bound = 2**10 * 2.0 ** -Precision(digits).prec
    err = _coefficient_error(code, lib, t0, y, p, 40, digits)
    assert err < bound, err

    class Rounded:
        """The library with its first parameter rounded to double on the way in."""

        def coefficients(self, order, t0, y, p):
            return lib.coefficients(order, t0, y, [mpmath.mpf(float(p[0])), *p[1:]])

    assert _coefficient_error(code, Rounded(), t0, y, p, 40, digits) > bound * 1e6


def test_every_generated_variant_compiles_loads_and_agrees():
    """Each variant of generated/ has its MPFR source; it compiles, loads (model hash and
    MPFR version checked) and its order-12 coefficients at 70 digits agree with the Python
    recurrences."""
    manifest = generated_manifest()
    assert all("taylor_mpfr" in entry["files"] for entry in manifest.values())
    for entry in manifest.values():
        code = load_model_code(entry["system"], entry["effects"])
        lib = load_taylor_mpfr_library(code)
        assert lib is not None, code.name
        assert lib.model_hash == entry["hash"]
        assert lib.mpfr_version == gmpy2.mpfr_version().split()[-1]
        t0, y, p = _generic_inputs(code, 70)
        err = _coefficient_error(code, lib, t0, y, p, 12, 70)
        assert err < 2**10 * 2.0 ** -Precision(70).prec, (code.name, err)


def test_another_mpfr_version_is_refused(monkeypatch):
    """A library whose MPFR is not gmpy2's is not loaded."""
    from chaplygin.numerics.ccompile import compile_c
    from chaplygin.numerics.taylor import library as taylor_library

    code = load_model_code("chaplygin_ball")
    cflags, ldlibs = taylor_library.mpfr_build_flags()
    so = compile_c(code.taylor_mpfr_source, ldlibs=ldlibs, cflags=cflags)
    assert CompiledTaylorMPFR(so, expected_hash=code.hash).mpfr_version  # gmpy2's: loads
    monkeypatch.setattr(gmpy2, "mpfr_version", lambda: "MPFR 0.0.1")
    with pytest.raises(ValueError, match="MPFR 0.0.1"):
        CompiledTaylorMPFR(so, expected_hash=code.hash)
    monkeypatch.setattr(taylor_library, "_LIBS", {})
    with pytest.warns(CompilerUnavailableWarning, match="MPFR 0.0.1"):
        assert load_taylor_mpfr_library(code) is None


@pytest.mark.parametrize("digits", [70, 100])
def test_solution_agrees_with_mpfr_at_more_digits(digits):
    """To T = 1.25 with non-dyadic inputs: the compiled MPFR run and the Python recurrences
    at the same digits take the same steps (the step control is the same to the bit) and
    both lie within the tolerance bound of the Python recurrences at 30 more digits."""
    T = "1.25"
    kw = {"t_eval": [0, "0.3", "0.9", T]}
    r = integrate("chaplygin_ball", STATE, (0, T), PARAMS, precision=digits, **kw)
    g = integrate("chaplygin_ball", STATE, (0, T), PARAMS, precision=digits, backend="numpy", **kw)
    ref = integrate(
        "chaplygin_ball", STATE, (0, T), PARAMS, precision=digits + 30, backend="numpy", **kw
    )
    assert r.backend == "c-mpfr" and g.backend == "python-gmpy2"
    assert (r.nsteps, r.info["order_min"], r.info["order_max"]) == (
        g.nsteps,
        g.info["order_min"],
        g.info["order_max"],
    )
    rtol = r.info["rtol"]
    with mpmath.workdps(digits + 30):
        scale = max(1, max(abs(v) for v in ref.y.ravel()))
        bound = 10 * rtol * r.nsteps * scale
        for res in (r, g):
            assert res.y.shape == ref.y.shape == (6, 4)  # dense output at every t_eval
            err = max(abs(a - b) for a, b in zip(res.y.ravel(), ref.y.ravel(), strict=True))
            assert err < bound, (res.backend, err, bound)
        # the same steps: C and Python differ only by the rounding of their sums
        same = max(abs(a - b) for a, b in zip(r.y.ravel(), g.y.ravel(), strict=True))
        assert same < 2**10 * r.nsteps * 2.0 ** -Precision(digits).prec * scale, same
    assert max(r.drift.values()) < 10 * rtol * r.nsteps


def test_mpfr_run_agrees_with_odefun():
    """The compiled MPFR run at 70 digits against mpmath.odefun (mpmath's own Taylor method)
    at 70 digits: 1e-64 apart (odefun's own tolerance is about 1e-68)."""
    kw = {"t_eval": [0, "0.75"]}
    r = integrate("chaplygin_ball", STATE, (0, "0.75"), PARAMS, precision=70, **kw)
    odefun = integrate(
        "chaplygin_ball", STATE, (0, "0.75"), PARAMS, precision=70, method="odefun", **kw
    )
    assert r.backend == "c-mpfr"
    with mpmath.workdps(70):
        pairs = zip(odefun.y[:, -1], r.y[:, -1], strict=True)
        assert max(abs(a - b) for a, b in pairs) < 1e-64


def test_inputs_reach_the_compiled_code_to_the_last_digit():
    """The output at t0 comes back from the C run: it equals the working state."""
    r = integrate("chaplygin_ball", STATE, (0, 1.25), PARAMS, precision=72, t_eval=[0, "1.25"])
    assert r.backend == "c-mpfr"
    with mpmath.workdps(72):
        y0 = pack_state(load_model_code("chaplygin_ball"), STATE, Precision(72))
        assert list(r.y[:, 0]) == list(y0)
        assert r.t[-1] == mpmath.mpf("1.25")


def _run(code, digits, **kw):
    with mpmath.workdps(digits):
        y0 = pack_state(code, STATE, Precision(digits))
        p = [mpmath.mpf(v) for v in ("1.2716", "2.9031", "4.4187", "0.6513")]
        t_eval = [mpmath.mpf(v) / 4 for v in range(0, 13, 3)]
        return taylor_solve(
            code,
            y0,
            (mpmath.mpf(0), mpmath.mpf(3)),
            p,
            precision=digits,
            rtol=10.0**-digits,
            atol=10.0**-digits,
            t_eval=t_eval,
            **kw,
        )


def test_runs_are_bit_stable_and_resume_exactly_in_blocks(chunk_steps):
    """Two runs give the same bits; with a wall-time limit the loop runs in blocks of 2
    steps, each resuming from the exact time and state the last reached: the same steps,
    orders and bits."""

    code = load_model_code("chaplygin_ball")
    first, second = _run(code, 90), _run(code, 90)
    assert first.backend == "c-mpfr" and first.status == 0 and first.nsteps > 2 * 2
    assert np.array_equal(first.y, second.y) and list(first.t) == list(second.t)
    chunk_steps("mpfr", 2)
    blocks = _run(code, 90, max_wall_s=1e6)
    assert (blocks.nsteps, blocks.order_min, blocks.order_max, blocks.status) == (
        first.nsteps,
        first.order_min,
        first.order_max,
        0,
    )
    assert np.array_equal(blocks.y, first.y) and len(blocks.t) == 5


def test_without_a_compiler_digits_fall_back_to_python_mpfr(tmp_path, monkeypatch):
    """The MPFR library cannot be built: 80 digits run the Python recurrences after a
    CompilerUnavailableWarning, with the result of the Python path asked for directly."""
    from chaplygin.numerics.ccompile import CompilationError
    from chaplygin.numerics.taylor import library as taylor_library

    expected = integrate("chaplygin_ball", STATE, 0.5, PARAMS, precision=80, backend="numpy")

    def broken(*args, **kwargs):
        raise CompilationError("no MPFR headers here")

    monkeypatch.setattr(taylor_library, "_LIBS", {})
    monkeypatch.setattr(taylor_library, "compile_c", broken)
    with pytest.warns(CompilerUnavailableWarning, match="MPFR Taylor integrator unavailable"):
        r = integrate("chaplygin_ball", STATE, 0.5, PARAMS, precision=80)
    assert r.backend == "python-gmpy2" and r.success
    assert list(r.y[:, -1]) == list(expected.y[:, -1])


@pytest.mark.parametrize("spread", [10, 60, 300])
def test_coefficients_of_far_apart_magnitudes(spread):
    """State components 10^(+-spread) apart (the terms of one convolution span up to
    2 spread decades: products below the fixed-point window of the sums, products at its
    top): against the Python recurrences in MPFR at 30 more digits, relative to the largest
    state coefficient of the same order."""
    code = load_model_code("chaplygin_ball")
    lib = load_taylor_mpfr_library(code)
    digits, order = 90, 24
    t0, y, p = _generic_inputs(code, digits)
    with mpmath.workdps(digits):
        y = [v * mpmath.mpf(10) ** (spread * (-1) ** i) for i, v in enumerate(y)]
    err = _coefficient_error(code, lib, t0, y, p, order, digits)
    assert err < 2**10 * 2.0 ** -Precision(digits).prec, err


def test_fixed_order_and_step_match_the_python_stepper():
    """A fixed order (30) and step (0.1; every coefficient at full precision): the compiled
    MPFR loop and the Python recurrences take the same 30 steps (to T = 3) and agree to the
    rounding of their sums."""
    code = load_model_code("chaplygin_ball")
    kw = {"order": 30, "step": mpmath.mpf(1) / 10}
    with mpmath.workdps(75):
        r = _run(code, 75, **kw)
    assert r.backend == "c-mpfr" and r.nsteps == 30 and r.order_max == r.order_min == 30
    with mpmath.workdps(75):
        g = _run(code, 75, lib="gmpy2", **kw)
    assert g.backend == "python-gmpy2" and g.nsteps == r.nsteps
    with mpmath.workdps(75):
        scale = max(1, max(abs(v) for v in g.y.ravel()))
        same = max(abs(a - b) for a, b in zip(r.y.ravel(), g.y.ravel(), strict=True))
        assert same < 2**10 * r.nsteps * 2.0 ** -Precision(75).prec * scale, same


def _gamma3(t, y):
    return y[5]


def test_events_on_the_compiled_mpfr_steps():
    """Zero crossings of gamma3 at 70 digits, located in Python on the compiled steps (one
    call per step): the same steps and crossings as the Python recurrences, the crossing
    times equal to the rounding of the sums, gamma3 zero there to the tolerance."""
    from reference import REFERENCE_PARAMS, REFERENCE_Y0

    kw = {"events": [_gamma3], "precision": 70, "t_eval": [0, 12]}
    r = integrate("chaplygin_ball", REFERENCE_Y0, 12, REFERENCE_PARAMS, **kw)
    g = integrate("chaplygin_ball", REFERENCE_Y0, 12, REFERENCE_PARAMS, backend="numpy", **kw)
    assert r.backend == "c-mpfr" and g.backend == "python-gmpy2"
    assert r.nsteps == g.nsteps
    te, tg = r.t_events[0], g.t_events[0]
    assert len(te) == len(tg) >= 2
    rtol = r.info["rtol"]
    eps = 2.0 ** -Precision(70).prec
    with mpmath.workdps(70):
        for a, b in zip(te, tg, strict=True):
            assert abs(a - b) < 2**10 * r.nsteps * eps * max(1, abs(b)), (a, b)
        for ye in r.y_events[0]:
            assert abs(ye[5]) < 10 * rtol
        final = max(abs(a - b) for a, b in zip(r.y[:, -1], g.y[:, -1], strict=True))
        assert final < 2**10 * r.nsteps * eps, final


def test_backward_run_matches_the_python_stepper():
    """From t = 0 back to t = -1.25 at 66 digits: the same steps as the Python recurrences,
    agreement to the rounding of the sums, outputs at the requested (decreasing) times."""
    kw = {"precision": 66, "t_eval": [0, "-0.5", "-1.25"]}
    r = integrate("chaplygin_ball", STATE, (0, "-1.25"), PARAMS, **kw)
    g = integrate("chaplygin_ball", STATE, (0, "-1.25"), PARAMS, backend="numpy", **kw)
    assert r.backend == "c-mpfr" and r.success and r.nsteps == g.nsteps
    assert r.y.shape == g.y.shape == (6, 3)
    with mpmath.workdps(66):
        assert list(r.t) == [0, mpmath.mpf("-0.5"), mpmath.mpf("-1.25")]
        same = max(abs(a - b) for a, b in zip(r.y.ravel(), g.y.ravel(), strict=True))
        assert same < 2**10 * r.nsteps * 2.0 ** -Precision(66).prec, same
