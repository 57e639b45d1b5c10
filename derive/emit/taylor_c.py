"""The Taylor program in C: the loop over the orders, and the program as data.

:class:`TaylorCEmitter` (language ``taylor_c``) prints one C99 source, generic in the type
``REAL``, from the template ``templates/taylor.c`` that also holds the step-size and order
control, the dense output and the whole integration loop: the normalised Taylor coefficients
are computed in a loop over the order ``k`` whose convolutions are the template's ``tc_*``
loops over ``j``. Compiled as is it works in ``double``; with ``CHAPLYGIN_TAYLOR_QUAD``
defined (:func:`~chaplygin.derive.emit.c_sources.taylor_source` prepends the define) in IEEE
binary128 ``__float128`` with libquadmath, with ``CHAPLYGIN_TAYLOR_DD``/``_QD`` in
double-double and quad-double.

Why ``__float128`` and not double-double for quad: binary128 has a 113-bit significand (34
decimal digits, with margin), its arithmetic is correctly rounded (IEEE), so error bounds
derived from ``eps = 2^-112`` hold; it needs no hand-written transcendental functions
(libquadmath has ``sinq, cosq, expq, powq, sqrtq``), and the generated code stays identical
for both types (only ``REAL`` and the function names change). Its cost -- software
arithmetic, about 10-30x slower than double -- is still far below multi-precision libraries
at 34 digits.

Both the loop and the code written out for fixed orders
(:mod:`~chaplygin.derive.emit.taylor_unroll`, chosen at run time when the orders are known)
are printed from one :class:`PrintedProgram`: the program's nodes with their constants
already printed in C, so that no sympy is needed at run time. :class:`TaylorProgramEmitter`
(language ``taylor_program``) writes it to ``generated/<model>_taylor_program.json``.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources

import sympy as sp

from ..model import Model
from .base import Emitter, ModelRoutines, header_lines, register
from .c_emitter import ChaplyginCPrinter
from .taylor import TaylorProgram, build_taylor_program

__all__ = [
    "PrintedNode",
    "PrintedProgram",
    "printed_program",
    "order_loop",
    "reciprocal_lines",
    "prologue_lines",
    "order_zero",
    "TaylorCEmitter",
    "TaylorProgramEmitter",
    "TAYLOR_TEMPLATE",
    "TAYLOR_MAX_ORDER",
]

TAYLOR_TEMPLATE = "taylor.c"
#: Largest order the C code supports (workspace size); enough for 1e-60 in one step.
TAYLOR_MAX_ORDER = 80


class _TaylorCPrinter(ChaplyginCPrinter):
    """Constants in ``REAL``: literals as exact integer quotients, functions via ``R_*``."""

    def _print_Integer(self, expr):
        return f"((REAL){int(expr)})"

    def _print_Rational(self, expr):
        return f"((REAL){int(expr.p)}/(REAL){int(expr.q)})"

    def _print_Half(self, expr):
        return "((REAL)1/(REAL)2)"

    def _print_Pow(self, expr):
        base, e = expr.as_base_exp()
        if e == sp.Rational(1, 2):
            return f"R_SQRT({self._print(base)})"
        if e.is_Integer and abs(int(e)) <= 4:
            b = self.parenthesize(base, 100)
            product = "*".join([b] * abs(int(e)))
            return f"({product})" if e > 0 else f"(((REAL)1)/({product}))"
        return f"R_POW({self._print(base)}, {self._print(e)})"

    def _print_Function(self, expr):
        name = type(expr).__name__
        if name in ("sin", "cos", "exp"):
            return f"R_{name.upper()}({self._print(expr.args[0])})"
        raise NotImplementedError(name)

    _print_sin = _print_cos = _print_exp = _print_Function

    def _print_Pi(self, expr):
        return "R_PI"


class _TaylorMacroPrinter:
    """Constants (expressions in the parameters) with the template's ``R_*`` macros only,
    for a ``REAL`` without C operators (double-double). Integers up to 2^53 are exact
    (``R_INT`` goes through a double)."""

    _FUNCTIONS = {sp.sin: "R_SIN", sp.cos: "R_COS", sp.exp: "R_EXP"}

    def __init__(self, names: dict[sp.Symbol, str]):
        self._names = names

    def doprint(self, expr: sp.Expr) -> str:
        """C expression of ``expr`` built from ``R_*`` macros.

        Parameters
        ----------
        expr : sympy.Expr
            A constant of the Taylor program (parameters, rationals, ``pi``, ``sqrt``,
            ``sin``, ``cos``, ``exp``, powers).

        Returns
        -------
        str
            The C expression.

        Raises
        ------
        NotImplementedError
            For another function.
        """
        return self._print(sp.sympify(expr))

    def _int(self, n: int) -> str:
        """An integer: exact in a double up to ``2**53``; beyond, in digits of ``2**48``
        (``hi 2**48 + lo``: exact scalings, the sum rounded once per digit at the working
        precision, exact in double-double and quad up to their mantissas)."""
        if abs(n) <= 2**53:
            return f"R_INT({n})"
        sign, m = (-1 if n < 0 else 1), abs(n)
        hi, lo = divmod(m, 2**48)
        out = f"R_ADD(R_MUL({self._int(hi)}, R_INT({2**48})), R_INT({lo}))"
        return f"R_NEG({out})" if sign < 0 else out

    def _print(self, e: sp.Expr) -> str:
        if e.is_Symbol:
            return self._names.get(e, e.name)
        if e.is_Integer:
            return self._int(int(e))
        if e.is_Rational:
            return f"R_DIV({self._int(int(e.p))}, {self._int(int(e.q))})"
        if e is sp.pi:
            return "R_PI"
        if e.is_Add:
            terms = list(e.as_ordered_terms())
            out = self._print(terms[0])
            for term in terms[1:]:
                if term.could_extract_minus_sign():
                    out = f"R_SUB({out}, {self._print(-term)})"
                else:
                    out = f"R_ADD({out}, {self._print(term)})"
            return out
        if e.is_Mul:
            if e.could_extract_minus_sign():
                return f"R_NEG({self._print(-e)})"
            num, den = [], []
            for factor in e.as_ordered_factors():
                if factor.is_Pow and factor.exp.is_Rational and factor.exp < 0:
                    den.append(factor.base ** (-factor.exp))
                elif factor.is_Rational and factor.q != 1:
                    num.append(sp.Integer(factor.p))
                    den.append(sp.Integer(factor.q))
                else:
                    num.append(factor)
            out = self._product(num) if num else "R_INT(1)"
            return f"R_DIV({out}, {self._product(den)})" if den else out
        if e.is_Pow:
            base, x = e.base, e.exp
            if x.is_Integer and x < 0:
                return f"R_DIV(R_INT(1), {self._print(base ** (-x))})"
            if x.is_Integer:
                return self._product([base] * int(x))
            if x == sp.Rational(1, 2):
                return f"R_SQRT({self._print(base)})"
            return f"R_POW({self._print(base)}, {self._print(x)})"
        if e.func in self._FUNCTIONS:
            return f"{self._FUNCTIONS[e.func]}({self._print(e.args[0])})"
        raise NotImplementedError(f"no R_* form of {type(e).__name__}: {e}")

    def _product(self, factors: list) -> str:
        out = self._print(factors[0])
        for f in factors[1:]:
            out = f"R_MUL({out}, {self._print(f)})"
        return out


@dataclass(frozen=True)
class PrintedNode:
    """One node of a :class:`PrintedProgram`.

    Attributes
    ----------
    op : str
        The operation (:data:`chaplygin.derive.emit.taylor.OPS`).
    args : tuple of int
        The operand nodes (``sin``/``cos``: the argument and the partner node).
    index : int
        ``var``: the state component; else -1.
    power : (int, int) or None
        ``pow``: numerator and denominator of the exponent.
    c, c_macros : str or None
        ``const``: the value in C with the operators of ``REAL`` (double, binary128) and with
        the template's ``R_*`` macros only (multi-double types).
    """

    op: str
    args: tuple[int, ...] = ()
    index: int = -1
    power: tuple[int, int] | None = None
    c: str | None = None
    c_macros: str | None = None


@dataclass(frozen=True)
class PrintedProgram:
    """A Taylor program with its constants printed in C: what the C emitters read.

    Attributes
    ----------
    model_name, model_hash : str
    params : tuple of str
        The parameters' names (C locals ``p_<name>``).
    nodes : tuple of PrintedNode
        In evaluation order: the state components, the time, then operations and constants.
    outputs : tuple of int
        ``outputs[i]`` is the node of ``d y_i / dt``.
    """

    model_name: str
    model_hash: str
    params: tuple[str, ...]
    nodes: tuple[PrintedNode, ...]
    outputs: tuple[int, ...]

    def to_json(self, about: list[str]) -> str:
        """The program as JSON text, one node per line.

        Parameters
        ----------
        about : list of str
            Header lines (generator, model, "DO NOT EDIT").

        Returns
        -------
        str
        """
        nodes = []
        for node in self.nodes:
            entry: dict = {"op": node.op}
            if node.args:
                entry["args"] = list(node.args)
            if node.index >= 0:
                entry["index"] = node.index
            if node.power is not None:
                entry["power"] = list(node.power)
            if node.c is not None:
                entry["c"], entry["c_macros"] = node.c, node.c_macros
            nodes.append(json.dumps(entry))
        head = {
            "about": about,
            "model": self.model_name,
            "model_hash": self.model_hash,
            "params": list(self.params),
            "outputs": list(self.outputs),
        }
        fields = [f"  {json.dumps(k)}: {json.dumps(v)}" for k, v in head.items()]
        fields.append('  "nodes": [\n' + ",\n".join(f"    {n}" for n in nodes) + "\n  ]")
        return "{\n" + ",\n".join(fields) + "\n}\n"

    @classmethod
    def from_json(cls, text: str) -> PrintedProgram:
        """The program of :meth:`to_json`'s text.

        Parameters
        ----------
        text : str

        Returns
        -------
        PrintedProgram

        Raises
        ------
        ValueError
            Not a program's JSON.
        """
        try:
            data = json.loads(text)
            nodes = tuple(
                PrintedNode(
                    op=n["op"],
                    args=tuple(int(a) for a in n.get("args", ())),
                    index=int(n.get("index", -1)),
                    power=tuple(int(v) for v in n["power"]) if "power" in n else None,
                    c=n.get("c"),
                    c_macros=n.get("c_macros"),
                )
                for n in data["nodes"]
            )
            return cls(
                model_name=data["model"],
                model_hash=data["model_hash"],
                params=tuple(data["params"]),
                nodes=nodes,
                outputs=tuple(int(o) for o in data["outputs"]),
            )
        except (KeyError, TypeError, ValueError) as exc:
            raise ValueError(f"not a printed Taylor program: {exc}") from None

    @property
    def n_state(self) -> int:
        return len(self.outputs)


def printed_program(model: Model, program: TaylorProgram | None = None) -> PrintedProgram:
    """The Taylor program of ``model`` with its constants printed in C.

    Parameters
    ----------
    model : Model
    program : TaylorProgram, optional
        ``build_taylor_program(model)`` when already built.

    Returns
    -------
    PrintedProgram
    """
    prog = program or build_taylor_program(model)
    names = {s: f"p_{s.name}" for s in model.params}
    printer, macros = _TaylorCPrinter(names), _TaylorMacroPrinter(names)
    nodes = []
    for node in prog.nodes:
        if node.op == "const":
            c, c_macros = printer.doprint(node.expr), macros.doprint(node.expr)
            nodes.append(PrintedNode("const", c=c, c_macros=c_macros))
        elif node.op == "pow":
            r = sp.Rational(node.expr)
            nodes.append(PrintedNode("pow", node.args, power=(int(r.p), int(r.q))))
        else:
            nodes.append(PrintedNode(node.op, node.args, index=node.index))
    return PrintedProgram(
        model.name, model.hash, tuple(s.name for s in model.params), tuple(nodes), prog.outputs
    )


#: order 0 of an operation node: (C macro, operand count)
_ORDER_ZERO = {
    "add": "R_ADD", "sub": "R_SUB", "addc": "R_ADD", "mulc": "R_MUL", "mul": "R_MUL",
    "div": "R_DIV", "cdiv": "R_DIV", "neg": "R_NEG", "sqrt": "R_SQRT", "exp": "R_EXP",
    "sin": "R_SIN", "cos": "R_COS",
}  # fmt: skip


def order_zero(node: PrintedNode, a: Callable[[int], str]) -> str:
    """The order-0 value of an operation node in C, its operands named by ``a``.

    Parameters
    ----------
    node : PrintedNode
        Not ``var``, ``time`` or ``const``.
    a : callable
        Node index -> the C name of its order-0 coefficient (``a3[0]``, ``a3_0``).

    Returns
    -------
    str
    """
    args = node.args
    if node.op == "sq":
        return f"R_MUL({a(args[0])}, {a(args[0])})"
    if node.op == "pow":
        p, q = node.power
        return f"R_POW({a(args[0])}, R_DIV(R_INT({p}), R_INT({q})))"
    if node.op in ("neg", "sqrt", "exp", "sin", "cos"):
        return f"{_ORDER_ZERO[node.op]}({a(args[0])})"
    return f"{_ORDER_ZERO[node.op]}({a(args[0])}, {a(args[1])})"


def reciprocal_lines(printed: PrintedProgram, a: Callable[[int], str],
                     real: str = "REAL") -> list[str]:
    """``a<x>r_0 = 1 / b_0`` for every division node ``x = a / b``: its recurrences multiply
    by the reciprocal of the divisor's order 0, worked out once per step.

    Parameters
    ----------
    printed : PrintedProgram
    a : callable
        Node index -> the C name of its order-0 coefficient.
    real : str
        The C type of the locals.

    Returns
    -------
    list of str
    """
    return [
        f"    const {real} a{i}r_0 = R_DIV(R_INT(1), {a(node.args[1])});"
        for i, node in enumerate(printed.nodes)
        if node.op in ("div", "cdiv")
    ]


def prologue_lines(printed: PrintedProgram) -> list[str]:
    """The first lines of a ``taylor_coefficients`` function: the row length, the parameters
    and the rows of the workspace ``X``.

    Parameters
    ----------
    printed : PrintedProgram

    Returns
    -------
    list of str
    """
    lines = ["    const int S = order + 1;"]
    lines += [f"    const REAL p_{name} = P[{i}];" for i, name in enumerate(printed.params)]
    lines += [f"    (void)p_{name};" for name in printed.params]
    lines += [f"    REAL *restrict a{i} = X + {i} * S;" for i in range(len(printed.nodes))]
    return lines


#: order k >= 1 of an operation node in the loop (the template's tc_* recurrences)
_LOOP_BODY: dict[str, Callable[[int, tuple[int, ...], PrintedNode], str]] = {
    "add": lambda x, a, n: f"R_ADD(a{a[0]}[k], a{a[1]}[k])",
    "sub": lambda x, a, n: f"R_SUB(a{a[0]}[k], a{a[1]}[k])",
    "neg": lambda x, a, n: f"R_NEG(a{a[0]}[k])",
    "addc": lambda x, a, n: f"a{a[0]}[k]",
    "mulc": lambda x, a, n: f"R_MUL(a{a[0]}[k], a{a[1]}[0])",
    "mul": lambda x, a, n: f"tc_mul(a{a[0]}, a{a[1]}, k)",
    "sq": lambda x, a, n: f"tc_sq(a{a[0]}, k)",
    "div": lambda x, a, n: f"tc_div(a{a[0]}[k], a{a[1]}, a{x}, a{x}r_0, k)",
    "cdiv": lambda x, a, n: f"tc_div(R_INT(0), a{a[1]}, a{x}, a{x}r_0, k)",
    "sqrt": lambda x, a, n: f"tc_sqrt(a{a[0]}, a{x}, k)",
    "pow": lambda x, a, n: f"tc_pow(a{a[0]}, a{x}, {n.power[0]}, {n.power[1]}, k)",
    "exp": lambda x, a, n: f"tc_exp(a{a[0]}, a{x}, k)",
    "sin": lambda x, a, n: f"tc_exp(a{a[0]}, a{a[1]}, k)",
    "cos": lambda x, a, n: f"R_NEG(tc_exp(a{a[0]}, a{a[1]}, k))",
}


def _loop_lines(printed: PrintedProgram) -> tuple[list[str], list[str]]:
    """(order 0, per-order body) lines of ``taylor_coefficients``; arithmetic on ``REAL``
    through the template's ``R_*`` macros, so one text serves every ``REAL`` type."""
    zero, body = [], []
    for i, node in enumerate(printed.nodes):
        if node.op == "var":
            zero.append(f"    a{i}[0] = Y[{node.index}];")
        elif node.op == "time":
            zero.append(f"    a{i}[0] = T0; if (S > 1) a{i}[1] = R_INT(1);")
        elif node.op == "const":
            # C operators where REAL has them (the double and binary128 text, unchanged);
            # R_* macros for the other types
            zero += ["#ifdef R_OPERATORS", f"    a{i}[0] = {node.c};", "#else",
                     f"    a{i}[0] = {node.c_macros};", "#endif"]  # fmt: skip
        elif node.op in _LOOP_BODY:
            zero.append(f"    a{i}[0] = {order_zero(node, lambda j: f'a{j}[0]')};")
            body.append(f"        a{i}[k] = {_LOOP_BODY[node.op](i, node.args, node)};")
        else:  # pragma: no cover
            raise ValueError(node.op)
    return zero, body


def loop_function(printed: PrintedProgram) -> str:
    """``taylor_coefficients``: every node's coefficients in a loop over the orders.

    Parameters
    ----------
    printed : PrintedProgram

    Returns
    -------
    str
        The C function (the template's ``{{COEFFICIENTS}}``).
    """
    zero, body = _loop_lines(printed)
    out = [
        f"        a{i}[k + 1] = R_DIV_INT(a{o}[k], k + 1);"
        for i, o in enumerate(printed.outputs)
    ]
    fn = [
        "static void taylor_coefficients(int order, REAL T0, const REAL *restrict Y,",
        "                                const REAL *restrict P, REAL *restrict X)",
        "{",
        *prologue_lines(printed),
        # only the time and constant nodes have coefficients that no recurrence writes
        # (every other node's k = 0..order-1 and the state's 0..order are computed
        # before they are read): zero those rows, not the whole workspace
        *[
            f"    for (int k = 0; k < S; ++k) a{i}[k] = R_INT(0);"
            for i, node in enumerate(printed.nodes)
            if node.op in ("time", "const")
        ],
        *zero,
        *reciprocal_lines(printed, lambda j: f"a{j}[0]"),
        *order_loop(["    " + ln for ln in body], out),
        "}",
    ]
    return "\n".join(fn)


def order_loop(body: list[str], out: list[str]) -> list[str]:
    """The loop over the orders: ``body`` (the nodes' order ``k``, from 1) then ``out`` (the
    state's order ``k + 1``), for ``k`` below ``order``.

    Parameters
    ----------
    body, out : list of str
        C lines, indented for their place in the loop.

    Returns
    -------
    list of str
    """
    return ["    for (int k = 0; k < order; ++k) {", "        if (k > 0) {", *body, "        }",
            *out, "    }"]  # fmt: skip


def read_taylor_template() -> str:
    """Text of the C template of the Taylor integrator (package data).

    Returns
    -------
    str
        The contents of ``chaplygin/derive/templates/taylor.c`` (:data:`TAYLOR_TEMPLATE`).
    """
    return resources.files("chaplygin.derive").joinpath("templates", TAYLOR_TEMPLATE).read_text()


@register
class TaylorCEmitter(Emitter):
    """C99 Taylor integrator (``double``, or ``__float128`` with ``CHAPLYGIN_TAYLOR_QUAD``)."""

    language = "taylor_c"
    ending = "_taylor.c"

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        printed = printed_program(model)
        text = read_taylor_template()
        for key, value in {
            "HEADER": "\n".join(header_lines(model, "taylor, C")),
            "N_STATE": str(printed.n_state),
            "N_PARAM": str(len(model.params)),
            "N_NODES": str(len(printed.nodes)),
            "MAX_ORDER": str(TAYLOR_MAX_ORDER),
            "MODEL_HASH": model.hash,
            "COEFFICIENTS": loop_function(printed),
        }.items():
            text = text.replace("{{" + key + "}}", value)
        return [(self.filename(model), text)]


@register
class TaylorProgramEmitter(Emitter):
    """The Taylor program as data (JSON): what the coefficients written out for fixed orders
    are printed from at run time (:mod:`~chaplygin.derive.emit.taylor_unroll`)."""

    language = "taylor_program"
    ending = "_taylor_program.json"

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        about = header_lines(model, "taylor program, JSON")
        return [(self.filename(model), printed_program(model).to_json(about))]
