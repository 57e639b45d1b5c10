"""The compiled Arb kernel of the Taylor recurrences (numerics.validated.arb_kernel).

References by independent routes: the Taylor coefficients of a small model that uses every
operation of a Taylor program, and their derivatives with respect to the state, by sympy
(repeated Lie derivatives of the right-hand side, differentiated symbolically, evaluated at
60 digits); the kernel's balls, computed at 128 bits at a point, must contain them, and a
reference moved by a few radii must fall outside. For a paper's model (BM20's body, with a
time-dependent forcing), the kernel's balls over a box meet the Python recurrences' on
python-flint jets (another implementation of the recurrences) at every order and gradient
entry, and are at most 1/64 wider (the quality of the enclosure, not its correctness).
"""

from __future__ import annotations

import math
import types

import pytest
import sympy as sp
from chaplygin.derive.emit import TaylorProgramEmitter, TaylorPythonEmitter
from chaplygin.derive.emit.functions import module_from_source
from chaplygin.derive.emit.taylor import OPS
from chaplygin.derive.emit.taylor_arb import taylor_arb_source
from chaplygin.derive.emit.taylor_c import PrintedProgram
from chaplygin.derive.model import Model, ParameterSpec
from chaplygin.numerics.ccompile import find_compiler
from chaplygin.numerics.validated import arb_kernel as kernel_module
from chaplygin.numerics.validated.arb_kernel import (
    ArbTaylorKernel,
    KernelUnavailableWarning,
    arb_kernel,
    flint_library,
)
from chaplygin.numerics.validated.jets import (
    ARB_LIB,
    JET_LIB,
    ArbJet,
    jet_gradient,
    jet_value,
    seed_jets,
)
from flint import arb, ctx

PREC = 128


def _compiler() -> bool:
    try:
        find_compiler()
    except Exception:  # noqa: BLE001 - any failure means no compiler here
        return False
    return True


pytestmark = pytest.mark.skipif(
    not _compiler() or flint_library() is None,
    reason="needs a C compiler and python-flint's FLINT library",
)


def _every_op_model() -> Model:
    """x' = sqrt(1 + x^2) y - a z, y' = -x z - exp(-x) - sin(z)/(2 + cos(z)) - b,
    z' = (1 + y^2)^(-3/2) + b/(a + x) + sqrt(a) t: every operation of a Taylor program."""
    x, y, z, t = sp.symbols("x y z t", real=True)
    a, b = sp.symbols("a b", positive=True)
    return Model(
        system="every_op",
        effects=frozenset(),
        time=t,
        state_groups=(("x", (x,)), ("y", (y,)), ("z", (z,))),
        parameters=(
            ParameterSpec("a", (a,), "positive", "a"),
            ParameterSpec("b", (b,), "positive", "b"),
        ),
        aux=(),
        rhs=(
            sp.sqrt(1 + x**2) * y - a * z,
            -x * z - sp.exp(-x) - sp.sin(z) / (2 + sp.cos(z)) - b,
            (1 + y**2) ** sp.Rational(-3, 2) + b / (a + x) + sp.sqrt(a) * t,
        ),
        constraints=(),
        geometry=(),
        integrals=(),
        density=sp.S.One,
    )


def _code(model: Model) -> types.SimpleNamespace:
    ((_, program),) = TaylorProgramEmitter().emit(model)
    ((_, python),) = TaylorPythonEmitter().emit(model)
    return types.SimpleNamespace(
        name=model.name,
        hash=model.hash,
        taylor_program=program,
        taylor=module_from_source(f"{model.name}_taylor_test", python),
    )


def _lie_coefficients(model: Model, order: int) -> list[list[sp.Expr]]:
    """c_k = L^(k-1) f / k! (k = 1..order) per state component, L g = g_t + grad(g) f."""
    state, f, t = list(model.state), list(model.rhs), model.time
    out, current = [], list(f)
    for k in range(1, order + 1):
        out.append([c / math.factorial(k) for c in current])
        current = [
            sp.diff(g, t) + sum(sp.diff(g, s) * fs for s, fs in zip(state, f, strict=True))
            for g in current
        ]
    return out


def test_the_small_model_uses_every_operation() -> None:
    program = PrintedProgram.from_json(_code(_every_op_model()).taylor_program)
    assert {node.op for node in program.nodes} == set(OPS)


def test_coefficients_and_gradients_contain_the_symbolic_ones() -> None:
    model = _every_op_model()
    code = _code(model)
    kernel = arb_kernel(code)
    assert isinstance(kernel, ArbTaylorKernel)
    point = {"x": "0.37", "y": "-0.61", "z": "0.83", "t": "0.29", "a": "1.3", "b": "0.47"}
    order = 4
    lie = _lie_coefficients(model, order)
    subs = {s: sp.Rational(point[s.name]) for s in (*model.state, model.time, *model.params)}
    old = ctx.prec
    try:
        ctx.prec = PREC
        y = [arb(point[s.name]) for s in model.state]
        p = [arb(point[s.name]) for s in model.params]
        t0 = arb(point["t"])
        # point inputs (decimal balls of radius ~2^-128): the balls are narrow
        values = kernel(t0, y, p, order, ARB_LIB)
        jets = kernel(t0, seed_jets(y), p, order, JET_LIB)
        # the same coefficients with their gradients written into matrices
        series, grads = kernel.gradient_series(t0, y, p, order)
        checked = 0
        for k in range(1, order + 1):
            for i, s in enumerate(model.state):
                exact = lie[k - 1][i]
                want = [exact, *(sp.diff(exact, v) for v in model.state)]
                got = [values[i][k], jet_value(jets[i][k]), *jet_gradient(jets[i][k], 3),
                       series[i][k], *(grads[i][k, c] for c in range(3))]  # fmt: skip
                refs = [want[0], want[0], *want[1:], *want]
                for ball, ref in zip(got, refs, strict=True):
                    r = arb(sp.N(ref.subs(subs), 60).__str__())
                    assert ball.overlaps(r), (k, s, ball, r)
                    # a few radii away the reference is outside (the balls are narrow)
                    shift = 4 * (ball.rad() + r.rad()) + arb(2) ** (-PREC)
                    assert not ball.overlaps(r + shift)
                    assert float(ball.rad()) <= 2.0 ** (-PREC + 24) * max(1.0, abs(float(r)))
                    checked += 1
        assert checked == order * 3 * 9
    finally:
        ctx.prec = old


def test_bm20_model_over_a_box_meets_the_python_jets() -> None:
    from chaplygin.numerics import load_model_code
    from chaplygin.numerics.ball.bm20_enclosure import BM20_EFFECTS

    code = load_model_code("chaplygin_ball", BM20_EFFECTS)
    kernel = arb_kernel(code)
    assert isinstance(kernel, ArbTaylorKernel)
    python = code.taylor.taylor_coefficients
    old = ctx.prec
    try:
        ctx.prec = PREC
        p = [arb(v) for v in ("1.1", "1.7", "2.3", "0.9", "0.31", "0.27", "0.13", "-0.21",
                              "0.17", "1.0669")]  # fmt: skip
        box = [arb(v) + arb(0, "1e-9") for v in ("0.3", "-0.2", "0.5", "0.6", "0.1", "0.79")]
        t0 = arb("0.37") + arb(0, "1e-6")
        order = 24
        for lib, y in ((ARB_LIB, box), (JET_LIB, seed_jets(box))):
            ours, theirs = kernel(t0, y, p, order, lib), python(t0, y, p, order, lib)
            for i in range(6):
                for k in range(order + 1):
                    a, b = ours[i][k], theirs[i][k]
                    pairs = [(jet_value(a), jet_value(b))]
                    if lib is JET_LIB:
                        assert type(a) is ArbJet
                        pairs += list(zip(jet_gradient(a, 6), jet_gradient(b, 6), strict=True))
                    for u, v in pairs:
                        assert u.overlaps(v)
                        # the same recurrences evaluated in another order (one dot against
                        # matrix products, u/w against u (1/w)): the widths are those of the
                        # box carried through them, within 1/64 (measured: 0.7 % at most)
                        assert float(u.rad()) <= float(v.rad()) * (1 + 1 / 64) + 2.0 ** (
                            -PREC + 8
                        ) * max(1.0, float(abs(v).upper()))
    finally:
        ctx.prec = old


def test_what_the_kernel_does_not_take_goes_to_the_python_recurrences(monkeypatch) -> None:
    code = _code(_every_op_model())
    kernel = arb_kernel(code)
    calls = []

    def fallback(*args):
        calls.append(args)
        return code.taylor.taylor_coefficients(*args)

    monkeypatch.setattr(kernel, "fallback", fallback)  # the kernel is cached per model
    y = seed_jets([arb("0.37"), arb("-0.61"), arb("0.83")])
    p = [ArbJet(arb("1.3"), y[0].g), arb("0.47")]  # a parameter with a gradient (carried)
    kernel(arb("0.29"), y, p, 3, JET_LIB)
    assert len(calls) == 1
    kernel(arb("0.29"), y, [arb("1.3"), arb("0.47")], 3, JET_LIB)
    assert len(calls) == 1


def test_a_missing_library_or_another_model_is_refused(monkeypatch) -> None:
    model = _every_op_model()
    code = _code(model)
    kernel = arb_kernel(code)
    with pytest.raises(ValueError, match="expected"):
        ArbTaylorKernel(kernel.library, kernel.fallback, "0" * 64)
    # no FLINT library: no kernel, a warning, and the integrator's Python route
    other = types.SimpleNamespace(**{**vars(code), "hash": "not-built-" + model.hash})
    monkeypatch.setattr(kernel_module, "flint_library", lambda: None)
    with pytest.warns(KernelUnavailableWarning, match="FLINT library"):
        assert arb_kernel(other) is None


def test_a_constant_outside_the_macros_is_refused_not_run() -> None:
    program = _code(_every_op_model()).taylor_program
    assert "R_SQRT(p_a)" in program
    for bad in ("R_SQRT(p_a); system(1)", "__import__(p_a)", "R_ADD(p_a)", "p_c"):
        with pytest.raises(ValueError):
            taylor_arb_source(program.replace("R_SQRT(p_a)", bad))


def test_a_program_whose_c_would_reach_outside_its_arrays_is_refused() -> None:
    import json

    program = _code(_every_op_model()).taylor_program
    taylor_arb_source(program)  # the program itself is printed
    data = json.loads(program)
    mul = next(i for i, node in enumerate(data["nodes"]) if node["op"] == "mul")
    changes = {
        "a later operand": lambda d: d["nodes"][mul].update(args=[mul + 1, 0]),
        "an operand past the end": lambda d: d["nodes"][mul].update(args=[0, 10**6]),
        "a negative operand": lambda d: d["nodes"][mul].update(args=[-1, 0]),
        "an operand missing": lambda d: d["nodes"][mul].update(args=[0]),
        "an output past the end": lambda d: d.update(outputs=[0, 1, 10**6]),
        "a hash with a quote": lambda d: d.update(model_hash='0" ; int x = 1; "'),
    }
    for change in changes.values():
        bad = json.loads(program)
        change(bad)
        with pytest.raises(ValueError):
            taylor_arb_source(json.dumps(bad))
    # a comment's end in the header stays inside the comment
    about = json.loads(program)
    about["about"] = ["*/ int planted(void) { return 1; } /*"]
    text = taylor_arb_source(json.dumps(about))
    assert "*/ int planted" not in text and "* / int planted" in text


def test_without_the_matrix_route_the_jets_give_the_same_enclosure(monkeypatch) -> None:
    """The gradients written into matrices and the jets' gradients are the same balls: a
    C^1 enclosure is the same, ball for ball, when the kernel cannot write into matrices
    (another FLINT layout: ``_matrix_addresses`` reads no ``rows x cols`` struct)."""
    from chaplygin.numerics import load_model_code
    from chaplygin.numerics.validated import arb_kernel as ak
    from chaplygin.numerics.validated import enclose_flow

    code = load_model_code("chaplygin_ball")
    kernel = arb_kernel(code)
    assert isinstance(kernel, ArbTaylorKernel) and kernel._matrices
    body, start = ["1.1", "1.7", "2.3", "0.9"], ["0.3", "-0.2", "0.5", "0.6", "0", "0.8"]

    def run():
        e = enclose_flow(code, body, start, 0, "2.7", jacobian=True, order=16, tol=1e-18)
        return [*e.state, *(x for row in e.jacobian for x in row)]

    direct = run()
    assert ak._matrix_addresses(ak.arb_mat(2, 3), 3, 2) is None  # not read as 3 x 2
    monkeypatch.setattr(kernel, "_matrices", False)
    assert kernel.gradient_series(ak.arb(0), [ak.arb(0)] * 6, [ak.arb(1)] * 4, 3) is None
    jets = run()
    assert all(a.mid() == b.mid() and a.rad() == b.rad() for a, b in zip(direct, jets,
                                                                        strict=True))
