"""The Taylor coefficients written out for fixed orders (derive/emit/taylor_unroll.py).

The written-out code must give the same bits as the template's loop (it is a speed-up, never
a change of result): coefficients of every kind of recurrence (products, squares, quotients,
powers, sines and cosines) at several orders, and whole adaptive runs with dense output,
compared bit for bit against the loop's library; every generated variant's program is
written out; an operation the emitter does not know is refused, and a model without its
printed program runs the loop. The nodes computed two at a time in GNU C vectors (pairs)
give the loop's bits for every generated variant, and a change of association inside a
vector line is seen by the same comparison.
"""

from __future__ import annotations

import dataclasses
import random
import re

import cffi
import chaplygin.numerics.taylor.library as taylor_library
import numpy as np
import pytest
from chaplygin.derive.emit.taylor_c import PrintedProgram
from chaplygin.derive.emit.taylor_unroll import (
    MARKER,
    UNROLL_MAX_ORDER,
    VECTOR_PRELUDE,
    unrolled_source,
)
from chaplygin.derive.systems import builtin_variants
from chaplygin.numerics import load_model_code
from chaplygin.numerics.ccompile import compile_c
from chaplygin.numerics.inputs import Precision, pack_params, pack_state
from chaplygin.numerics.taylor import (
    CompiledTaylor,
    _c_run,
    load_taylor_library,
    run_orders,
    taylor_solve,
)
from reference import REFERENCE_PARAMS, REFERENCE_Y0

VARIANTS = [(s, tuple(sorted(e))) for s, e in builtin_variants()]
#: variants whose recurrences cover every form: products, squares and quotients (the ball),
#: powers (the ball on a surface), sines and cosines (the ball along a line), the rubber
#: ball's longer chains
COVERING = [
    ("chaplygin_ball", ()),
    ("chaplygin_ball", ("rubber",)),
    ("ball_on_surface", ()),
    ("chaplygin_ball", ("straight_line",)),
]


def _bits(values) -> np.ndarray:
    return np.asarray(values, dtype=np.float64).view(np.int64)


def _point(code, seed: int):
    """A generic non-dyadic point: state in (-0.9, 0.9), parameters in (1.1, 2.9)."""
    rng = random.Random(seed)
    y = [rng.uniform(-0.9, 0.9) / 3 * 7 / 3 for _ in code.state]
    p = [1.1 + 1.8 * rng.random() for _ in code.params]
    return y, p


@pytest.mark.parametrize("system,effects", VARIANTS)
def test_every_generated_variant_is_written_out(system, effects):
    code = load_model_code(system, effects)
    source, program = code.taylor_c_source, code.taylor_program
    assert MARKER in source
    out = unrolled_source(source, program, (2, 3, 12, UNROLL_MAX_ORDER, UNROLL_MAX_ORDER + 1))
    assert out is not None
    for p in (2, 3, 12, UNROLL_MAX_ORDER):
        assert f"static void taylor_coefficients_{p}(" in out
    assert f"taylor_coefficients_{UNROLL_MAX_ORDER + 1}(" not in out  # above the limit: loop
    # every recurrence of the loop body became single assignments: no loop call left in them
    body = out[out.index("static void taylor_coefficients_2(") : out.index(
        "static void taylor_coefficients_unrolled("
    )]
    assert "tc_" not in body
    # nodes paired in vectors (every variant has pairs), the scalar functions for other
    # compilers, the same text as without vectors
    assert VECTOR_PRELUDE in out and "const vreal v0_1 = " in body
    scalar = unrolled_source(source, program, (2, 3, 12, UNROLL_MAX_ORDER), vectors=False)
    assert scalar is not None
    assert "TAYLOR_VREAL 1" not in scalar and "const vreal v0_1" not in scalar
    for p in (2, 3, 12, UNROLL_MAX_ORDER):
        start = scalar.index(f"static void taylor_coefficients_{p}(")
        function = scalar[start : scalar.index("\n}\n", start) + 3]
        assert "#else\n" + function + "#endif\n" in out


def test_the_ball_pairs_its_convolutions():
    """The Chaplygin ball's cross products M x w and gamma x w pair up: of its 22 products,
    squares and quotients at least 18 run two at a time (the quotient and the third
    component's product and square stay alone)."""
    code = load_model_code("chaplygin_ball", ())
    out = unrolled_source(code.taylor_c_source, code.taylor_program, (12,))
    body = out[out.index("static void taylor_coefficients_12("):]
    body = body[: body.index("\n}\n")]
    pairs = re.findall(r"const vreal v(\d+)_5 = (.*);", body)
    convolutions = [e for _, e in pairs if e.count("R_MUL(") >= 3]
    assert len(convolutions) >= 9


def test_an_unknown_operation_is_refused_and_a_missing_program_runs_the_loop(monkeypatch):
    code = load_model_code("chaplygin_ball", ())
    source, program = code.taylor_c_source, PrintedProgram.from_json(code.taylor_program)
    assert unrolled_source(source, program, (12,)) is not None
    i = next(i for i, node in enumerate(program.nodes) if node.op == "mul")
    nodes = list(program.nodes)
    nodes[i] = dataclasses.replace(nodes[i], op="mystery")
    with pytest.raises(ValueError, match="mystery"):
        unrolled_source(source, dataclasses.replace(program, nodes=tuple(nodes)), (12,))
    with pytest.raises(ValueError, match="not a printed Taylor program"):
        unrolled_source(source, '{"nodes": []}', (12,))
    assert unrolled_source(source.replace(MARKER, ""), program, (12,)) is None
    assert unrolled_source(source, program, (1, UNROLL_MAX_ORDER + 1)) is None  # none in range
    # code without its printed program (a ModelCode made by hand) runs the loop's library,
    # with the loop's bits
    monkeypatch.setattr(taylor_library, "_LIBS", {})
    bare = dataclasses.replace(code, taylor_program=None)
    loop = load_taylor_library(bare, "double", (12,))
    assert loop is load_taylor_library(bare, "double")
    monkeypatch.setattr(taylor_library, "_LIBS", {})
    written = load_taylor_library(code, "double", (12,))
    assert written is not loop
    y, p = _point(code, 3)
    assert np.array_equal(_bits(loop.coefficients(12, 0.3, y, p)),
                          _bits(written.coefficients(12, 0.3, y, p)))


@pytest.mark.parametrize("system,effects", VARIANTS)
def test_coefficients_are_bit_identical_to_the_loop(system, effects):
    code = load_model_code(system, effects)
    orders = (2, 3, 4, 7, 12) if (system, effects) in COVERING else (3, 12)
    loop = load_taylor_library(code, "double")
    written = load_taylor_library(code, "double", orders)
    assert loop is not None and written is not None and written is not loop
    compared = 0
    for seed in range(3):
        y, p = _point(code, seed)
        for order in orders:
            a = loop.coefficients(order, 0.3, y, p)
            b = written.coefficients(order, 0.3, y, p)
            assert np.array_equal(_bits(a), _bits(b)), (system, effects, order, seed)
            compared += np.isfinite(np.asarray(a, dtype=float)).sum()
    assert compared > 0  # finite values were compared, not only NaNs


@pytest.mark.parametrize("kind", ["REAL", "vreal"])
def test_a_different_recurrence_order_would_be_seen(kind):
    """Negative control for the bit comparison: the same products summed with another
    association ((s + p) + q for s + (p + q), the two new terms) differ in the last bits
    somewhere, so equal bits above are not a tautology -- changed in the scalar lines, or
    only in the vector lines (the pairs)."""
    code = load_model_code("chaplygin_ball", ())
    source = unrolled_source(code.taylor_c_source, code.taylor_program, (12,))
    assert source is not None

    i = source.index("static void taylor_coefficients_12(")
    j = source.index("static void taylor_coefficients_unrolled(")
    op = r"(?:\(\(vreal\)\{[^}]*\}\)|[av]\d+_\d+)"
    part = re.sub(
        rf"^(    const {kind} \S+) = R_ADD\((.*), R_ADD\((R_MUL\({op}, {op}\)), "
        rf"(R_MUL\({op}, {op}\))\)\);$",
        r"\1 = R_ADD(R_ADD(\2, \3), \4);",
        source[i:j],
        flags=re.MULTILINE,
    )
    assert part != source[i:j]

    changed = CompiledTaylor(compile_c(source[:i] + part + source[j:]), "double")
    loop = load_taylor_library(code, "double")
    differs = 0
    for seed in range(5):
        y, p = _point(code, seed)
        a, b = loop.coefficients(12, 0.3, y, p), changed.coefficients(12, 0.3, y, p)
        differs += not np.array_equal(_bits(a), _bits(b))
        # ... while agreeing to rounding: the same numbers summed in another order
        np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-300)
    assert differs > 0


@pytest.mark.parametrize("rtol", [1e-9, 1e-12, 3e-15])
def test_adaptive_runs_are_bit_identical_to_the_loop(rtol):
    code = load_model_code("chaplygin_ball", ())

    prec = Precision("double")
    y0 = pack_state(code, REFERENCE_Y0, prec)
    p = pack_params(code, REFERENCE_PARAMS, prec)
    t_eval = list(np.linspace(0.0, 37.3, 29))
    orders = run_orders(rtol, rtol / 7)
    assert len(orders) == 2  # relative and absolute control at different orders
    loop = load_taylor_library(code, "double")
    runs = [
        _c_run(lib, y0, (0.0, 37.3), p, rtol, rtol / 7, t_eval, None, None, 10**6)
        for lib in (loop, load_taylor_library(code, "double", orders))
    ]
    assert runs[0].status == runs[1].status == 0
    assert runs[0].nsteps == runs[1].nsteps > 10
    assert np.array_equal(_bits(runs[0].y), _bits(runs[1].y))
    # and taylor_solve (what integrate runs) takes the written-out library
    sol = taylor_solve(code, y0, (0.0, 37.3), p, rtol=rtol, atol=rtol / 7, t_eval=t_eval)
    assert np.array_equal(_bits(sol.y), _bits(runs[0].y))


def test_run_orders():
    assert run_orders(1e-12, 1e-12) == (15,)
    assert run_orders(1e-9, 1e-12) == (12, 15)
    assert run_orders(1e-9, 1e-12, order=7) == (7,)


@pytest.mark.parametrize("kind", ["double", "quad"])
def test_runs_in_blocks_hand_over_the_compensation(kind, chunk_steps):
    """The compiled loop carries the rounding error of its state updates (Kahan); a run cut
    into blocks of 7 steps (as a wall-time limit cuts it) hands it from block to block and
    gives the bits of the uncut run; without the handover the bits would differ (the
    compensation is active: it changes the state in its last bits)."""

    code = load_model_code("chaplygin_ball", ())
    prec = Precision(kind)
    y0 = pack_state(code, REFERENCE_Y0, prec)
    p = pack_params(code, REFERENCE_PARAMS, prec)
    rtol = 1e-13 if kind == "double" else 1e-30
    lib = load_taylor_library(code, kind, run_orders(rtol, rtol) if kind == "double" else ())
    t_eval = [0, 3.1, 9.7, 23.3]
    whole = _c_run(lib, y0, (0, 23.3), p, rtol, rtol, t_eval, None, None, 10**6, None)
    chunk_steps(kind, 7)
    cut = _c_run(lib, y0, (0, 23.3), p, rtol, rtol, t_eval, None, None, 10**6, 3600.0)
    assert whole.nsteps == cut.nsteps > 14  # more than two blocks
    assert all(a == b for a, b in zip(whole.y.ravel(), cut.y.ravel(), strict=True))  # exact
    if kind == "double":
        return
    # the handover matters (shown in quad, where the compensation is far from the last bit of
    # the output): restarting each block with a zero compensation changes the bits
    real = lib.real
    ptr = lib._ptr
    n = lib.n_state

    ffi = cffi.FFI()
    t01, y = lib.pack([0, 23.3]), lib.pack(y0)
    P, ctrl = lib.pack(p), lib.pack([rtol, rtol, 0])
    y_end, t_reached, y_lo = lib.empty(n), lib.empty(1), lib.pack([0] * n)
    stats = np.zeros(4, dtype=np.int64)
    while True:
        status = lib.lib.chaplygin_taylor_run(
            ptr(t01), ptr(y), ptr(P), ptr(ctrl), 0, 0, ptr(lib.empty(1)), ptr(lib.empty(n)),
            ptr(y_end), ptr(t_reached), 7, ffi.cast("long *", stats.ctypes.data), ptr(y_lo))
        if status != -2:
            break
        width = real.size // np.dtype(t01.dtype).itemsize
        t01 = np.concatenate([t_reached, t01[width:]])
        y = y_end.copy()
        y_lo = lib.pack([0] * n)  # dropped
    dropped = real.unpack(y_end, n)
    assert any(a != b for a, b in zip(dropped, whole.y[:, -1], strict=True))


def test_the_state_update_runs_two_components_at_a_time():
    """With the written-out coefficients the compensated state update runs two components
    per vector (template ``TAYLOR_VREAL``): the runs above are bit-identical to the loop's
    through it, and it is the code that runs -- dropping its compensation (the TwoSum's low
    part) changes the bits of the same run."""
    code = load_model_code("chaplygin_ball", ())
    prec = Precision("double")
    y0 = pack_state(code, REFERENCE_Y0, prec)
    p = pack_params(code, REFERENCE_PARAMS, prec)
    source = unrolled_source(code.taylor_c_source, code.taylor_program, (12,))
    assert source is not None and "#define TAYLOR_VREAL 1" in source
    twosum = "const vreal lo = (a - (y - bb)) + (d - bb);"
    assert source.count(twosum) == 1
    changed = source.replace(twosum, "const vreal lo = {0.0, 0.0};")

    def run(text):
        lib = CompiledTaylor(compile_c(text), "double")
        return _c_run(lib, y0, (0.0, 37.3), p, 1e-9, 1e-9, [37.3], None, None, 10**6)

    same, dropped = run(source), run(changed)
    loop = _c_run(load_taylor_library(code, "double"), y0, (0.0, 37.3), p, 1e-9, 1e-9, [37.3],
                  None, None, 10**6)
    assert same.status == dropped.status == loop.status == 0
    assert np.array_equal(_bits(same.y), _bits(loop.y))
    assert not np.array_equal(_bits(dropped.y), _bits(loop.y))


def test_a_compiler_without_gnu_vectors_gets_the_scalar_code_then_the_loop(monkeypatch):
    """A compiler that refuses the vector code gets the written-out scalar code, one that
    refuses both the loop: never the (much slower) Python recurrences, always the bits."""
    code = load_model_code("chaplygin_ball", ())
    y, p = _point(code, 7)
    loop = load_taylor_library(code, "double")
    real_compile = taylor_library.compile_c
    compiled = []

    def refusing(marker):
        def compile_c(source, **kw):
            if marker in source:
                raise taylor_library.CompilerError("refused")
            compiled.append(source)
            return real_compile(source, **kw)
        return compile_c

    monkeypatch.setattr(taylor_library, "_LIBS", {})
    monkeypatch.setattr(taylor_library, "compile_c", refusing("#define TAYLOR_VREAL 1"))
    scalar = load_taylor_library(code, "double", (12,))
    assert scalar is not None and "taylor_coefficients_12(" in compiled[-1]
    assert np.array_equal(_bits(scalar.coefficients(12, 0.3, y, p)),
                          _bits(loop.coefficients(12, 0.3, y, p)))

    monkeypatch.setattr(taylor_library, "_LIBS", {})
    monkeypatch.setattr(taylor_library, "compile_c", refusing("taylor_coefficients_12("))
    fallback = load_taylor_library(code, "double", (12,))
    assert fallback is not None and "taylor_coefficients_12(" not in compiled[-1]
    assert np.array_equal(_bits(fallback.coefficients(12, 0.3, y, p)),
                          _bits(loop.coefficients(12, 0.3, y, p)))


def test_the_scheduling_flags_only_where_the_scheduler_is_quick():
    """-fschedule-insns -fsched-pressure for written-out sources up to the limit (the ball's,
    the bench's reference problem, keeps them), none above (a 1.8 MB source took 106 s with
    them and 17 s without); the bits are the loop's either way (the test above)."""
    from chaplygin.numerics.taylor.library import (
        UNROLLED_CFLAGS,
        UNROLLED_CFLAGS_MAX_BYTES,
        unrolled_cflags,
    )

    assert unrolled_cflags("x" * UNROLLED_CFLAGS_MAX_BYTES) == UNROLLED_CFLAGS
    assert unrolled_cflags("x" * (UNROLLED_CFLAGS_MAX_BYTES + 1)) == ()
    ball = load_model_code("chaplygin_ball")
    written = unrolled_source(ball.taylor_c_source, ball.taylor_program, (20,))
    assert unrolled_cflags(written) == UNROLLED_CFLAGS


def test_a_written_out_source_above_the_limit_runs_the_loop(monkeypatch):
    """Above UNROLLED_MAX_BYTES the written-out source is not compiled (a large described
    model's took minutes of gcc): the orders run the loop's library, with the loop's bits;
    at the limit it is written out."""
    code = load_model_code("chaplygin_ball", ())
    size = len(unrolled_source(taylor_library.taylor_source(code.taylor_c_source, "double"),
                               code.taylor_program, (12,)))  # fmt: skip
    loop = load_taylor_library(code, "double")
    monkeypatch.setattr(taylor_library, "_LIBS", {})
    monkeypatch.setattr(taylor_library, "UNROLLED_MAX_BYTES", size - 1)
    assert load_taylor_library(code, "double", (12,)) is load_taylor_library(code, "double")
    monkeypatch.setattr(taylor_library, "_LIBS", {})
    monkeypatch.setattr(taylor_library, "UNROLLED_MAX_BYTES", size)
    written = load_taylor_library(code, "double", (12,))
    assert written is not load_taylor_library(code, "double")
    y, p = _point(code, 5)
    assert np.array_equal(_bits(written.coefficients(12, 0.3, y, p)),
                          _bits(loop.coefficients(12, 0.3, y, p)))
