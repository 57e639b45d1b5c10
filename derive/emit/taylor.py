"""Taylor-coefficient backend: automatic-differentiation recurrences from the model graph.

The model's auxiliary definitions and right-hand side (in that order) are reduced by common
subexpression elimination and decomposed into a *Taylor program*: a list of nodes, each an
elementary operation on earlier nodes (``+ - * /``, squares, integer and rational powers,
``sqrt``, ``exp``, ``sin``/``cos`` pairs) or a constant (an expression in the parameters
only). The normalised Taylor coefficients ``x_[k] = x^(k)(t0) / k!`` of every node follow
from the coefficients of its arguments by the classical recurrences (Moore 1966; Jorba and
Zou 2005, *Exp. Math.* 14, 99), e.g. for ``c = a b`` ``c_k = sum_j a_j b_(k-j)``, for
``c = a^r`` ``c_k = 1/(k a_0) sum_(j<k) (r (k-j) - j) a_(k-j) c_j``; the state's next
coefficient is ``y_[k+1] = f_[k] / (k+1)``. The time ``t`` is the node with coefficients
``(t0, 1, 0, ...)``, so explicitly time-dependent models (``sin(Omega t)`` of BM20) need
nothing special.

The emitters print the same program:

* :class:`TaylorPythonEmitter` (language ``taylor_py``, here): a Python module whose
  ``taylor_coefficients(t0, y, p, order, lib)`` works with any number type supporting
  ``+ - * /`` and a namespace ``lib`` of ``mpf, sqrt, exp, sin, cos`` -- ``mpmath`` at any
  precision, or ``gmpy2`` (MPFR, much faster per operation) for the same recurrences;
* :class:`~chaplygin.derive.emit.taylor_c.TaylorCEmitter` (language ``taylor_c``): one C99
  source generic in the type ``REAL`` (double, binary128, double-double, quad-double), and
  :class:`~chaplygin.derive.emit.taylor_c.TaylorProgramEmitter` the program as data for the
  coefficients written out for fixed orders (:mod:`~chaplygin.derive.emit.taylor_unroll`);
* :class:`~chaplygin.derive.emit.taylor_mpfr.TaylorMpfrEmitter` (language ``taylor_mpfr``):
  C on MPFR numbers.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from ..model import Model
from .base import Emitter, ModelRoutines, _temporaries, header_lines, register

__all__ = [
    "TaylorNode",
    "TaylorProgram",
    "build_taylor_program",
    "TaylorPythonEmitter",
    "OPS",
]

#: Operations of a Taylor program (see :class:`TaylorNode`).
OPS = (
    "var",  # state component (args: ()), value = index in the state
    "time",  # the independent variable
    "const",  # expression in the parameters (expr)
    "add",
    "sub",
    "neg",
    "addc",  # a + c, c a constant node
    "mulc",  # a * c
    "mul",
    "sq",
    "div",
    "cdiv",  # c / b
    "sqrt",
    "pow",  # a^r, r = expr (sympy Rational)
    "exp",
    "sin",  # args (a, partner cos node)
    "cos",  # args (a, partner sin node)
)


@dataclass(frozen=True)
class TaylorNode:
    """One node: ``op`` applied to earlier nodes ``args`` (``expr``: constant or exponent)."""

    op: str
    args: tuple[int, ...] = ()
    expr: sp.Expr | None = None
    index: int = -1


@dataclass
class TaylorProgram:
    """Nodes in evaluation order; ``outputs[i]`` is the node of ``d y_i / dt``.

    The first ``n_state`` nodes are the state components, node ``n_state`` is the time.
    """

    model_name: str
    state: tuple[sp.Symbol, ...]
    params: tuple[sp.Symbol, ...]
    nodes: list[TaylorNode] = field(default_factory=list)
    outputs: tuple[int, ...] = ()

    @property
    def n_state(self) -> int:
        return len(self.state)

    def count(self, op: str) -> int:
        """Number of nodes with operation ``op``.

        Parameters
        ----------
        op : str
            One of :data:`OPS` (``"mul"``, ``"sin"`` ...).

        Returns
        -------
        int
            How many nodes of the program apply ``op``.
        """
        return sum(1 for n in self.nodes if n.op == op)


class _Builder:
    def __init__(self, model: Model):
        self.model = model
        self.params = set(model.params)
        self.prog = TaylorProgram(model.name, model.state, model.params)
        self.memo: dict[sp.Expr, int] = {}
        self.bound: dict[sp.Symbol, int] = {}
        self.pending: dict[sp.Symbol, sp.Expr] = {}
        self.const_values: dict[sp.Symbol, sp.Expr] = {}
        for i, s in enumerate(model.state):
            self.bound[s] = self._add(TaylorNode("var", index=i))
        self.bound[model.time] = self._add(TaylorNode("time"))

    def _add(self, node: TaylorNode) -> int:
        self.prog.nodes.append(node)
        return len(self.prog.nodes) - 1

    def _node(self, op: str, args: tuple[int, ...], expr: sp.Expr | None = None) -> int:
        key = (op, args, expr)
        if key in self.memo:
            return self.memo[key]
        idx = self._add(TaylorNode(op, args, expr))
        self.memo[key] = idx
        return idx

    # ------------------------------------------------------------------ constants
    def _const_expr(self, expr: sp.Expr) -> sp.Expr | None:
        """``expr`` in parameters only if it is constant in time and state, else None."""
        expr = sp.sympify(expr)
        subs = {}
        for s in expr.free_symbols:
            if s in self.params:
                continue
            if s in self.const_values:
                subs[s] = self.const_values[s]
                continue
            if s in self.pending and s not in self.bound:
                value = self._const_expr(self.pending[s])
                if value is not None:
                    self.const_values[s] = value
                    subs[s] = value
                    continue
            return None
        return expr.xreplace(subs) if subs else expr

    def const(self, value: sp.Expr) -> int:
        return self._node("const", (), sp.sympify(value))

    # ------------------------------------------------------------------ series
    def symbol(self, s: sp.Symbol) -> int:
        if s in self.bound:
            return self.bound[s]
        if s in self.pending:
            idx = self.build(self.pending[s])
            self.bound[s] = idx
            return idx
        raise ValueError(f"symbol {s} of {self.model.name} has no definition")

    def build(self, expr: sp.Expr) -> int:
        expr = sp.sympify(expr)
        value = self._const_expr(expr)
        if value is not None:
            return self.const(value)
        if expr.is_Symbol:
            return self.symbol(expr)
        if expr.is_Add:
            return self._add_expr(expr)
        if expr.is_Mul:
            return self._mul_expr(expr)
        if expr.is_Pow:
            return self._pow(self.build(expr.base), expr.exp)
        if isinstance(expr, sp.exp):
            return self._node("exp", (self.build(expr.args[0]),))
        if isinstance(expr, (sp.sin, sp.cos)):
            a = self.build(expr.args[0])
            key = ("sin", (a,), None)
            if key not in self.memo:
                s = len(self.prog.nodes)
                self._add(TaylorNode("sin", (a, s + 1)))
                self._add(TaylorNode("cos", (a, s)))
                self.memo[key] = s
                self.memo[("cos", (a,), None)] = s + 1
            return self.memo[(("sin" if isinstance(expr, sp.sin) else "cos"), (a,), None)]
        raise NotImplementedError(
            f"no Taylor recurrence for {type(expr).__name__} in {self.model.name}: {expr}"
        )

    def _add_expr(self, expr: sp.Expr) -> int:
        const_terms, plus, minus = [], [], []
        for term in expr.args:
            if self._const_expr(term) is not None:
                const_terms.append(self._const_expr(term))
                continue
            coeff, rest = term.as_coeff_Mul()
            if coeff.is_negative:
                minus.append(self.build(-term))
            else:
                plus.append(self.build(term))
        if plus:
            acc = plus[0]
            for b in plus[1:]:
                acc = self._node("add", (acc, b))
            for b in minus:
                acc = self._node("sub", (acc, b))
        else:
            acc = self._node("neg", (minus[0],))
            for b in minus[1:]:
                acc = self._node("sub", (acc, b))
        if const_terms:
            acc = self._node("addc", (acc, self.const(sp.Add(*const_terms))))
        return acc

    def _mul_expr(self, expr: sp.Expr) -> int:
        const_factors, num, den = [], [], []
        for factor in expr.args:
            value = self._const_expr(factor)
            if value is not None:
                const_factors.append(value)
            elif factor.is_Pow and factor.exp.is_Integer and factor.exp < 0:
                den.append(self._pow(self.build(factor.base), -factor.exp))
            else:
                num.append(self.build(factor))
        c = sp.Mul(*const_factors)
        acc = None
        for b in num:
            acc = b if acc is None else self._node("mul", (acc, b))
        d = None
        for b in den:
            d = b if d is None else self._node("mul", (d, b))
        if d is not None:
            if acc is None:
                return self._node("cdiv", (self.const(c), d))
            acc = self._node("div", (acc, d))
        if c != 1:
            acc = self._node("mulc", (acc, self.const(c)))
        return acc

    def _pow(self, a: int, e: sp.Expr) -> int:
        e = sp.sympify(e)
        if not e.is_Rational:
            raise NotImplementedError(f"power with non-rational exponent {e}")
        if e == 1:
            return a
        if e.is_Integer and e > 0:
            n = int(e)
            if n == 2:
                return self._node("sq", (a,))
            half = self._pow(a, n // 2)
            sq = self._node("sq", (half,))
            return sq if n % 2 == 0 else self._node("mul", (sq, a))
        if e.is_Integer:
            return self._node("cdiv", (self.const(1), self._pow(a, -e)))
        if e == sp.Rational(1, 2):
            return self._node("sqrt", (a,))
        return self._node("pow", (a,), e)


def build_taylor_program(model: Model) -> TaylorProgram:
    """Decompose the model's aux definitions and right-hand side into a Taylor program.

    The aux expressions and the rhs are reduced together by ``sympy.cse`` (canonical order,
    deterministic); symbols (aux, temporaries) are bound lazily, so only what the rhs needs
    becomes a node.

    Parameters
    ----------
    model : Model
        The model: its auxiliary definitions and right-hand side are decomposed.

    Returns
    -------
    TaylorProgram
        The nodes in evaluation order (state components, time, then operations and
        constants); ``outputs[i]`` is the node of ``d y_i / dt``.
    """
    exprs = [e for _, e in model.aux] + list(model.rhs)
    taken = {s.name for e in exprs for s in sp.sympify(e).free_symbols}
    taken |= {s.name for s, _ in model.aux}
    temps, reduced = sp.cse(exprs, symbols=_temporaries(taken), order="canonical")
    b = _Builder(model)
    for s, e in temps:
        b.pending[s] = e
    for (s, _), e in zip(model.aux, reduced[: len(model.aux)], strict=True):
        b.pending[s] = e
    b.prog.outputs = tuple(b.build(e) for e in reduced[len(model.aux) :])
    return b.prog


# ---------------------------------------------------------------------------- Python


class _GenericPrinter(PythonCodePrinter):
    """Constants for any number type: rationals through ``_mpf``, functions from ``lib``."""

    def __init__(self, names: dict[sp.Symbol, str]):
        super().__init__({"fully_qualified_modules": False})
        self._names = names

    def _print_Symbol(self, expr):
        return self._names.get(expr, expr.name)

    def _print_Rational(self, expr):
        return f"(_mpf({expr.p})/{expr.q})"

    def _print_Half(self, expr):
        return "(_mpf(1)/2)"

    def _print_Integer(self, expr):
        return f"_mpf({expr.p})"

    def _print_Float(self, expr):  # pragma: no cover - models are exact
        return f"_mpf({str(expr)!r})"

    def _print_Pow(self, expr, rational=False):
        base, e = expr.as_base_exp()
        b = self.parenthesize(base, 100)
        if e == sp.Rational(1, 2):
            return f"_sqrt({self._print(base)})"
        if e.is_Integer:
            return f"{b}**{int(e)}"
        return f"{b}**{self.parenthesize(e, 100)}"

    def _print_Function(self, expr):
        name = type(expr).__name__
        if name in ("sin", "cos", "exp"):
            return f"_{name}({self._print(expr.args[0])})"
        raise NotImplementedError(name)

    _print_sin = _print_cos = _print_exp = _print_Function

    def _print_Pi(self, expr):
        return "_pi"


def _python_lines(prog: TaylorProgram, printer: _GenericPrinter) -> tuple[list, list, list]:
    """(constants and k = 0, per-order body) lines of ``taylor_coefficients``."""
    init, zero, body = [], [], []
    a = [f"a{i}" for i in range(len(prog.nodes))]
    for i, node in enumerate(prog.nodes):
        op, args = node.op, node.args
        x = a[i]
        init.append(f"    {x} = [_zero] * S")
        ar = [a[j] for j in args]
        if op == "var":
            zero.append(f"    {x}[0] = y[{node.index}]")
        elif op == "time":
            zero.append(f"    {x}[0] = t0")
            zero.append(f"    if S > 1: {x}[1] = _mpf(1)")
        elif op == "const":
            zero.append(f"    {x}[0] = {printer.doprint(node.expr)}")
        elif op in ("add", "sub"):
            sign = "+" if op == "add" else "-"
            zero.append(f"    {x}[0] = {ar[0]}[0] {sign} {ar[1]}[0]")
            body.append(f"        {x}[k] = {ar[0]}[k] {sign} {ar[1]}[k]")
        elif op == "neg":
            zero.append(f"    {x}[0] = -{ar[0]}[0]")
            body.append(f"        {x}[k] = -{ar[0]}[k]")
        elif op == "addc":
            zero.append(f"    {x}[0] = {ar[0]}[0] + {ar[1]}[0]")
            body.append(f"        {x}[k] = {ar[0]}[k]")
        elif op == "mulc":
            zero.append(f"    {x}[0] = {ar[0]}[0] * {ar[1]}[0]")
            body.append(f"        {x}[k] = {ar[0]}[k] * {ar[1]}[0]")
        elif op in ("mul", "sq"):
            b = ar[1] if op == "mul" else ar[0]
            zero.append(f"    {x}[0] = {ar[0]}[0] * {b}[0]")
            body.append(
                f"        {x}[k] = (_conv({ar[0]}, {b}, 0, k, k) if _conv "
                f"else _sum(_map(_mul, {ar[0]}[:k1], {b}[k::-1])))"
            )
        elif op == "div":
            zero.append(f"    {x}[0] = {ar[0]}[0] / {ar[1]}[0]")
            body.append(
                f"        {x}[k] = ({ar[0]}[k] - (_conv({ar[1]}, {x}, 1, k, k) if _conv "
                f"else _sum(_map(_mul, {ar[1]}[1:k1], {x}[k - 1::-1])))) / {ar[1]}[0]"
            )
        elif op == "cdiv":
            zero.append(f"    {x}[0] = {ar[0]}[0] / {ar[1]}[0]")
            body.append(
                f"        {x}[k] = -(_conv({ar[1]}, {x}, 1, k, k) if _conv "
                f"else _sum(_map(_mul, {ar[1]}[1:k1], {x}[k - 1::-1]))) / {ar[1]}[0]"
            )
        elif op == "sqrt":
            zero.append(f"    {x}[0] = _sqrt({ar[0]}[0])")
            body.append(
                f"        {x}[k] = ({ar[0]}[k] - (_conv({x}, {x}, 1, k - 1, k) if _conv "
                f"else _sum(_map(_mul, {x}[1:k], {x}[k - 1:0:-1])))) / (2 * {x}[0])"
            )
        elif op == "pow":
            r = sp.Rational(node.expr)
            p, q = int(r.p), int(r.q)
            zero.append(f"    {x}[0] = {ar[0]}[0] ** ({printer.doprint(r)})")
            body.append(
                f"        {x}[k] = _sum([({p} * (k - j) - {q} * j) * {ar[0]}[k - j] * {x}[j] "
                f"for j in range(k)]) / ({q} * k * {ar[0]}[0])"
            )
        elif op == "exp":
            zero.append(f"    {x}[0] = _exp({ar[0]}[0])")
            body.append(
                f"        {x}[k] = (_wconv({ar[0]}, {x}, 1, k, k) if _conv "
                f"else _sum([j * {ar[0]}[j] * {x}[k - j] for j in range(1, k1)])) / k"
            )
        elif op in ("sin", "cos"):
            partner = ar[1]
            fn = "_sin" if op == "sin" else "_cos"
            zero.append(f"    {x}[0] = {fn}({ar[0]}[0])")
            sign = "" if op == "sin" else "-"
            body.append(
                f"        {x}[k] = {sign}(_wconv({ar[0]}, {partner}, 1, k, k) if _conv "
                f"else _sum([j * {ar[0]}[j] * {partner}[k - j] for j in range(1, k1)])) / k"
            )
        else:  # pragma: no cover
            raise ValueError(op)
    return init, zero, body


@register
class TaylorPythonEmitter(Emitter):
    """Python recurrences for any arbitrary-precision number type (mpmath, gmpy2)."""

    language = "taylor_py"
    ending = "_taylor.py"

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        prog = build_taylor_program(model)
        names = {s: f"p_{s.name}" for s in model.params}
        printer = _GenericPrinter(names)
        init, zero, body = _python_lines(prog, printer)
        n = prog.n_state
        lines = ['"""' + header_lines(model, "taylor, python")[0]]
        lines += header_lines(model, "taylor, python")[1:]
        lines += [
            "",
            "Taylor coefficients by automatic differentiation (chaplygin.derive.emit.taylor).",
            '"""',
            "",
            "# ruff: noqa",
            "from operator import mul as _mul",
            "",
            f"MODEL_NAME = {model.name!r}",
            f"MODEL_HASH = {model.hash!r}",
            f"N_STATE = {n}",
            f"N_NODES = {len(prog.nodes)}",
            f"OPS = {tuple(sorted((op, prog.count(op)) for op in OPS if prog.count(op)))!r}",
            "",
            "",
            "def taylor_coefficients(t0, y, p, order, lib):",
            '    """Normalised Taylor coefficients ``y_i^(k)(t0) / k!``, ``k = 0..order``.',
            "",
            "    ``lib`` provides ``mpf, sqrt, exp, sin, cos`` (``mpmath`` or a gmpy2 namespace)",
            "    and optionally ``fsum`` (sums of products; default the built-in ``sum``)",
            "    and ``conv``/``wconv`` (both or neither: ``conv(a, b, lo, hi, k)`` is",
            "    ``sum(a[j] * b[k - j] for j in lo..hi)``, ``wconv`` the same with weights ``j``);",
            "    the working precision is the caller's. Returns ``n_state`` lists of",
            "    ``order + 1`` numbers.",
            '    """',
            "    _mpf, _sqrt, _exp, _sin, _cos = lib.mpf, lib.sqrt, lib.exp, lib.sin, lib.cos",
            "    _sum, _map = getattr(lib, 'fsum', sum), map",
            "    _conv, _wconv = getattr(lib, 'conv', None), getattr(lib, 'wconv', None)",
            "    _zero = _mpf(0)",
            "    S = order + 1",
        ]
        if model.params:
            lines.append(f"    {', '.join(names[s] for s in model.params)}, = p")
        lines += init
        lines += zero
        outs = [f"a{j}" for j in prog.outputs]
        lines.append("    for k in range(order):")
        lines.append("        k1 = k + 1")
        lines.append("        if k:")
        lines += ["    " + ln for ln in body] or ["            pass"]
        for i, o in enumerate(outs):
            lines.append(f"        a{i}[k1] = {o}[k] / k1")
        lines.append(f"    return [{', '.join(f'a{i}' for i in range(n))}]")
        return [(self.filename(model), "\n".join(lines) + "\n")]
