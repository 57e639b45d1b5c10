"""emit_function: run-time functions printed like the generated models, across backends.

The model's own right-hand side printed by :func:`emit_function` must give what the
generated module gives (same printer, same CSE); numpy, mpmath and sympy's exact
evaluation must agree on random states to the precision of each (STYLE.md item 11).
"""

from __future__ import annotations

import linecache
import random

import mpmath
import numpy as np
import pytest
import sympy as sp
from chaplygin.derive.emit import emit_function, function_source
from chaplygin.derive.emit.base import GENERATOR_VERSION
from chaplygin.derive.systems import build_model
from chaplygin.numerics.code import load_model_code

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def ball():
    return build_model("chaplygin_ball", ())


def _random_point(model, seed: int) -> list[sp.Rational]:
    """Exact random state and positive parameters (rationals: sympy evaluates exactly)."""
    rng = random.Random(seed)
    state = [sp.Rational(rng.randint(-900, 900), 1000) for _ in model.state]
    params = [sp.Rational(rng.randint(200, 3000), 1000) for _ in model.params]
    return state + params


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_model_rhs_printed_at_run_time_matches_the_generated_module(ball, seed):
    """Same printer and CSE as generated/: bit-identical in numpy, digit-identical in mpmath."""
    args = [*ball.state, *ball.params]
    code = load_model_code("chaplygin_ball")
    point = _random_point(ball, seed)
    n = len(ball.state)
    f_np = emit_function(args, list(ball.rhs_expanded), "numpy", name="rhs")
    x = [float(v) for v in point]
    got = np.array(f_np(*x), dtype=float)
    want = code.numpy.rhs(0.0, np.array(x[:n]), np.array(x[n:]))
    assert np.array_equal(got, want)
    f_mp = emit_function(args, list(ball.rhs_expanded), "mpmath", name="rhs")
    with mpmath.workdps(30):
        y = [mpmath.mpf(v.p) / v.q for v in point]
        assert f_mp(*y) == code.mpmath.rhs(0, y[:n], y[n:])


@pytest.mark.parametrize("seed", [4, 5])
def test_numpy_mpmath_and_sympy_agree_on_derived_expressions(ball, seed):
    """Integrals of the model: exact sympy values against mpmath (30 digits) and numpy."""
    args = [*ball.state, *ball.params]
    exprs = [ball.expand_aux(e) for _, e in ball.integrals]
    point = _random_point(ball, seed)
    exact = [e.xreplace(dict(zip(args, point, strict=True))) for e in exprs]
    with mpmath.workdps(30):
        got_mp = emit_function(args, exprs, "mpmath")(*[mpmath.mpf(v.p) / v.q for v in point])
        for g, e in zip(got_mp, exact, strict=True):
            assert abs(g - mpmath.mpf(sp.N(e, 40))) <= mpmath.mpf(10) ** -27 * max(1, abs(g))
    got_np = emit_function(args, exprs, "numpy")(*[float(v) for v in point])
    for g, e in zip(got_np, exact, strict=True):
        assert abs(g - float(e)) <= 100 * EPS * max(1.0, abs(float(e)))


def test_awkward_arguments_are_renamed_without_changing_the_expression():
    """A function value, a Python keyword, a module name and a temporary's name as
    arguments; a single expression returns one value."""
    t = sp.Symbol("t")
    f = sp.Function("f")(t)
    lam, module, x0 = sp.Symbol("lambda", positive=True), sp.Symbol("numpy"), sp.Symbol("x0")
    expr = sp.sqrt(lam**2) * f + module * (x0 + f) ** 2 + (x0 + f) ** 3 / 7
    args = [f, lam, module, x0]
    values = [sp.Rational(3, 10), sp.Rational(17, 10), sp.Rational(-2, 5), sp.Rational(1, 9)]
    exact = expr.xreplace(dict(zip(args, values, strict=True)))
    for language, convert, tol in (("numpy", float, 10 * EPS), ("mpmath", mpmath.mpf, 1e-25)):
        with mpmath.workdps(30):
            got = emit_function(args, expr, language)(*[convert(v.p) / v.q for v in values])
            assert abs(got - convert(sp.N(exact, 40))) <= tol


def test_source_is_stamped_cached_and_in_tracebacks():
    x, y = sp.symbols("x y")
    text = function_source([x, y], [x / y, x * y], "mpmath", name="ratio")
    assert f"chaplygin code generator {GENERATOR_VERSION} (mpmath function)" in text
    assert f"sympy {sp.__version__}" in text and "expressions hash: " in text
    assert "DO NOT EDIT" in text and "def ratio(x, y):" in text
    assert "mpmath.mpf" not in function_source([x], [x / 3], "numpy")
    assert "mpmath.mpf(1)/mpmath.mpf(3)" in function_source([x], [x / 3], "mpmath")
    f = emit_function([x, y], [x / y, x * y], "numpy", name="ratio")
    assert emit_function([x, y], [x / y, x * y], "numpy", name="ratio") is f
    source = "".join(linecache.getlines(f.__code__.co_filename))
    assert "def ratio(x, y):" in source and "expressions hash" in source


def test_bad_requests_are_refused():
    x, y = sp.symbols("x y")
    with pytest.raises(ValueError, match="not arguments"):
        function_source([x], [x + y])
    with pytest.raises(ValueError, match="repeated"):
        function_source([x, x], [x])
    with pytest.raises(ValueError, match="numpy or mpmath"):
        emit_function([x], [x], "c")
