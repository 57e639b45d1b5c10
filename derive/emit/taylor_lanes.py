"""The Taylor coefficients of several orbits at once, in the lanes of a GNU C vector.

:func:`written_out_lanes` prints ``taylor_coefficients_lanes``: the loop over the orders of
:func:`~chaplygin.derive.emit.taylor_c.loop_function` with every coefficient a ``tl_vec`` of
``TL_W`` doubles, one orbit per lane (``derive/templates/taylor_lanes.c`` defines the type,
the recurrences ``tl_mul`` .. ``tl_exp`` and the driver that calls it). Each lane computes
the IEEE operations of the double loop in the same order: the arithmetic is the C operators
on the vector (lane-wise, no contraction under ``-ffp-contract=off``), the constants and the
transcendental functions at order 0 are the double code's text evaluated lane by lane
(``R_SQRT``, ``R_EXP``, ``chaplygin_pow`` ... of the double build, in the same translation
unit). So lane ``l``'s coefficients are, bit for bit, those the double loop computes for its
orbit, whatever the other lanes hold; and the coefficient of order ``k`` does not depend on
the order the loop runs to (a recurrence reads lower orders only), so lanes that want
different orders share the highest and each reads its own.

For the orders of a run the coefficients are also written out (``taylor_coefficients_lanes_<p>``,
chosen by ``TL_COEFFICIENTS``): the expression trees of
:mod:`~chaplygin.derive.emit.taylor_unroll` (the loop's operations in the loop's order, the
same bits) printed with every coefficient a ``const`` vector; the time's and the constants'
literal higher orders stay doubles, which GNU C applies to every lane (``tl_splat`` where a
whole coefficient is one). BM20's forced ball at rtol 1e-12: 28 -> 23 us per point and period
against the loop in lanes.

Printed at run time from the model's printed program (``<model>_taylor_program.json``),
like :mod:`~chaplygin.derive.emit.taylor_unroll`.
"""

from __future__ import annotations

from collections.abc import Iterable

from .taylor_c import PrintedNode, PrintedProgram, order_loop, order_zero, reciprocal_lines
from .taylor_unroll import UNROLL_MAX_ORDER, _div_int, _Printed, _Unrolled

__all__ = ["written_out_lanes"]

#: order k >= 1 of an operation node in the lanes (the template's tl_* recurrences)
_BODY = {
    "add": lambda x, a, n: f"a{a[0]}[k] + a{a[1]}[k]",
    "sub": lambda x, a, n: f"a{a[0]}[k] - a{a[1]}[k]",
    "neg": lambda x, a, n: f"-(a{a[0]}[k])",
    "addc": lambda x, a, n: f"a{a[0]}[k]",
    "mulc": lambda x, a, n: f"a{a[0]}[k] * a{a[1]}[0]",
    "mul": lambda x, a, n: f"tl_mul(a{a[0]}, a{a[1]}, k)",
    "sq": lambda x, a, n: f"tl_sq(a{a[0]}, k)",
    "div": lambda x, a, n: f"tl_div(a{a[0]}[k], a{a[1]}, a{x}, a{x}r_0, k)",
    "cdiv": lambda x, a, n: f"tl_div(tl_zero(), a{a[1]}, a{x}, a{x}r_0, k)",
    "sqrt": lambda x, a, n: f"tl_sqrt(a{a[0]}, a{x}, k)",
    "pow": lambda x, a, n: f"tl_pow(a{a[0]}, a{x}, {n.power[0]}, {n.power[1]}, k)",
    "exp": lambda x, a, n: f"tl_exp(a{a[0]}, a{x}, k)",
    "sin": lambda x, a, n: f"tl_exp(a{a[0]}, a{a[1]}, k)",
    "cos": lambda x, a, n: f"-(tl_exp(a{a[0]}, a{a[1]}, k))",
}

#: operations whose order 0 is a function call: evaluated lane by lane
_LANEWISE = frozenset({"sqrt", "exp", "sin", "cos", "pow"})


def _order_zero(i: int, node: PrintedNode) -> list[str]:
    """Order 0 of operation node ``i``: vector operators, or lane by lane for a function."""
    if node.op in _LANEWISE:
        value = order_zero(node, lambda j: f"a{j}[0][l]")
        return [f"    for (int l = 0; l < TL_W; ++l) a{i}[0][l] = {value};"]
    return [f"    a{i}[0] = {order_zero(node, lambda j: f'a{j}[0]')};"]


def _order_zero_lines(printed: PrintedProgram) -> tuple[list[str], list[str]]:
    """The lines up to order 0 (rows of ``X``, the time's and constants' rows zeroed, the
    constants lane by lane) and the loop's order-``k`` line of every operation node."""
    params = printed.params
    lines = ["    const int S = order + 1;"]
    lines += [f"    tl_vec *restrict a{i} = X + {i} * S;" for i in range(len(printed.nodes))]
    consts = [(i, n) for i, n in enumerate(printed.nodes) if n.op == "const"]
    for i, node in enumerate(printed.nodes):
        if node.op in ("time", "const"):
            lines.append(f"    for (int k = 0; k < S; ++k) a{i}[k] = tl_zero();")
    if consts:  # the double code's constants, lane by lane
        lines.append("    for (int l = 0; l < TL_W; ++l) {")
        lines += [f"        const REAL p_{name} = P[{j}][l];" for j, name in enumerate(params)]
        lines += [f"        (void)p_{name};" for name in params]
        lines += [f"        a{i}[0][l] = {node.c};" for i, node in consts]
        lines.append("    }")
    body = []
    for i, node in enumerate(printed.nodes):
        if node.op == "var":
            lines.append(f"    a{i}[0] = Y[{node.index}];")
        elif node.op == "time":
            lines.append(f"    a{i}[0] = T0; if (S > 1) a{i}[1] = tl_zero() + 1.0;")
        elif node.op in _BODY:
            lines += _order_zero(i, node)
            body.append(f"            a{i}[k] = {_BODY[node.op](i, node.args, node)};")
        elif node.op != "const":
            raise ValueError(f"no lanes form of the operation {node.op!r}")
    return lines, body


_SIGNATURE = "(tl_vec T0, const tl_vec *restrict Y, const tl_vec *restrict P, tl_vec *restrict X)"


def _lanes_function(printed: PrintedProgram) -> str:
    """``taylor_coefficients_lanes(order, T0, Y, P, X)``: every node's coefficients up to
    ``order`` for ``TL_W`` orbits in the loop over the orders, ``X[node * (order + 1) + k]``
    the vector of their lanes."""
    lines, body = _order_zero_lines(printed)
    out = [
        f"        a{i}[k + 1] = a{o}[k] * (1.0 / (double)(k + 1));"
        for i, o in enumerate(printed.outputs)
    ]
    return "\n".join([
        "static void taylor_coefficients_lanes(int order, " + _SIGNATURE[1:],
        "{",
        *lines,
        *reciprocal_lines(printed, lambda j: f"a{j}[0]", "tl_vec"),
        *order_loop(body, out),
        "}",
        "",
    ])


def _value(tree: tuple) -> str:
    """A written-out coefficient as a vector: a tree without coefficients (the time's and the
    constants' literal orders only) is a double, copied into every lane."""
    printed = _Printed(tree)
    text = printed.text(twice="tl_twice")
    return text if printed.leaves else f"tl_splat({text})"


def _written_out_function(printed: PrintedProgram, u: _Unrolled, p: int) -> str:
    """``taylor_coefficients_lanes_<p>``: order 0 as the loop computes it, then every
    coefficient of orders 1 .. p a ``const`` vector, the trees of
    :mod:`~chaplygin.derive.emit.taylor_unroll` (the loop's operations in its order: the
    same bits); the state's rows stored in ``X``."""
    zero, _ = _order_zero_lines(printed)
    nodes = range(len(printed.nodes))
    lines = [f"    const int order = {p};", *zero]
    lines += [f"    const tl_vec a{i}_0 = a{i}[0];" for i in nodes]
    lines += [f"    (void)a{i}_0;" for i in nodes]
    lines += reciprocal_lines(printed, lambda j: f"a{j}_0", "tl_vec")
    assigned = [n for n, node in u.nodes.items() if node.op not in ("var", "time", "const")]
    for k in range(p):
        if k > 0:
            lines += [f"    const tl_vec a{x}_{k} = {_value(u.expression(x, k))};"
                      for x in assigned]  # fmt: skip
        lines += [f"    const tl_vec a{i}_{k + 1} = "
                  f"{_value(_div_int(u.ref(str(o), k), k + 1))};"
                  for i, o in enumerate(printed.outputs)]  # fmt: skip
    lines += [f"    a{i}[{k}] = a{i}_{k};" for i in range(printed.n_state) for k in range(1, p + 1)]
    return "\n".join([f"static void taylor_coefficients_lanes_{p}" + _SIGNATURE, "{", *lines,
                      "}", ""])  # fmt: skip


def written_out_lanes(printed: PrintedProgram, orders: Iterable[int]) -> str:
    """``taylor_coefficients_lanes`` (the loop over the orders), the coefficients of the lanes
    written out for each of ``orders`` (between 2 and
    :data:`~chaplygin.derive.emit.taylor_unroll.UNROLL_MAX_ORDER`; others run the loop) and
    ``TL_COEFFICIENTS``, which picks one by the order.

    Parameters
    ----------
    printed : PrintedProgram
        The model's Taylor program, constants printed in C.
    orders : iterable of int
        The orders of a run (:func:`chaplygin.numerics.taylor.run_orders`).

    Returns
    -------
    str

    Raises
    ------
    ValueError
        An operation with no written-out recurrence.
    """
    wanted = sorted({int(p) for p in orders if 2 <= int(p) <= UNROLL_MAX_ORDER})
    u = _Unrolled(printed)
    parts = [_lanes_function(printed)]
    parts += [_written_out_function(printed, u, p) for p in wanted]
    cases = [f"    case {p}: taylor_coefficients_lanes_{p}(T0, Y, P, X); return;" for p in wanted]
    parts.append("\n".join([
        "static void tl_coefficients(int order, " + _SIGNATURE[1:], "{", "    switch (order) {",
        *cases, "    default: taylor_coefficients_lanes(order, T0, Y, P, X);", "    }", "}",
        "#define TL_COEFFICIENTS tl_coefficients", "",
    ]))  # fmt: skip
    return "\n".join(parts)
