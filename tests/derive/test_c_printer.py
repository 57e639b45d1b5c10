"""The C printer's powers (derive/emit/c_emitter.py ``ChaplyginCPrinter._print_Pow``): integer
powers as products, half-integer powers as products times one ``sqrt``, other powers through
``chaplygin_pow``. The text is what the generated C of every model is made of
(``chaplygin derive --check`` holds it for the built-ins, whose numbers the integration tests
check against independent references); here each form's text, and the printer's work on a
nested root."""

from __future__ import annotations

import pytest
import sympy as sp
from chaplygin.derive.emit.c_emitter import ChaplyginCPrinter

x, y = sp.symbols("x y")
PRINTER = ChaplyginCPrinter({x: "s_x", y: "p_y"})


@pytest.mark.parametrize(
    ("expr", "text"),
    [
        (sp.sqrt(x + y), "sqrt(s_x + p_y)"),
        ((x + y) ** sp.Rational(3, 2), "((s_x + p_y)*sqrt(s_x + p_y))"),
        ((x + y) ** sp.Rational(-5, 2), "(1.0/((s_x + p_y)*(s_x + p_y)*sqrt(s_x + p_y)))"),
        (1 / sp.sqrt(x), "(1.0/sqrt(s_x))"),
        (sp.sqrt(1 + sp.sqrt(x)), "sqrt(sqrt(s_x) + 1)"),
        (x**3, "(s_x*s_x*s_x)"),
        (x**-2, "(1.0/(s_x*s_x))"),
        (x ** sp.Rational(1, 3), "chaplygin_pow(s_x, 1.0/3.0)"),
    ],
)
def test_powers_print_as_products_roots_and_pow(expr, text):
    assert PRINTER.doprint(expr) == text


def test_a_nested_root_is_printed_once_per_level():
    """sqrt(1 + sqrt(1 + ... sqrt(x))) is printed with a constant number of printer calls per
    level: the base of a plain root is not printed a second time for a factor it does not
    have (that doubled the work with every level, 2^depth: minutes for a convex body's
    normal on first use). Counted in printer calls, not timed; the text is the chain."""
    calls = []

    class Counting(ChaplyginCPrinter):
        def _print(self, expr, **kw):
            calls.append(expr)
            return super()._print(expr, **kw)

    depth = 16
    expr = x
    for _ in range(depth):
        expr = sp.sqrt(1 + expr)
    text = Counting({x: "s_x"}).doprint(expr)
    assert text == "sqrt(" * depth + "s_x" + " + 1)" * depth
    assert len(calls) < 10 * depth  # printed twice per level: more than 2^16
