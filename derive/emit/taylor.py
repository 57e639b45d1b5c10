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

Two emitters print the same program:

* :class:`TaylorPythonEmitter` (language ``taylor_py``): a Python module whose
  ``taylor_coefficients(t0, y, p, order, lib)`` works with any number type supporting
  ``+ - * /`` and a namespace ``lib`` of ``mpf, sqrt, exp, sin, cos`` -- ``mpmath`` at any
  precision, or ``gmpy2`` (MPFR, much faster per operation) for the same recurrences;
* :class:`TaylorCEmitter` (language ``taylor_c``): one C99 source, generic in the type
  ``REAL``, from the template ``templates/taylor.c`` that also holds the step-size and order
  control, the dense output and the whole integration loop. Compiled as is it works in
  ``double``; with ``-DCHAPLYGIN_TAYLOR_QUAD`` (``numerics`` prepends the define) in IEEE
  binary128 ``__float128`` with libquadmath.

Why ``__float128`` and not double-double: binary128 has a 113-bit significand (34 decimal
digits, the ">= 32 digits" the issue asks for, with margin; double-double has 106 bits and a
less regular rounding), its arithmetic is correctly rounded (IEEE), so error bounds derived
from ``eps = 2^-112`` hold; it needs no hand-written transcendental functions (libquadmath
has ``sinq, cosq, expq, powq, sqrtq``), and the generated code stays identical for both
types (only ``REAL`` and the function names change). Its cost -- software arithmetic, about
10-30x slower than double -- is still far below multi-precision libraries at 34 digits.
GCC ships it on x86-64 and aarch64; without it numerics falls back to the Python recurrences.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from importlib import resources

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from ..model import Model
from .base import Emitter, ModelRoutines, _temporaries, header_lines, register
from .c_emitter import ChaplyginCPrinter

__all__ = [
    "TaylorNode",
    "TaylorProgram",
    "build_taylor_program",
    "TaylorPythonEmitter",
    "TaylorCEmitter",
    "TaylorMpfrEmitter",
    "TAYLOR_TEMPLATE",
    "TAYLOR_MPFR_TEMPLATE",
    "TAYLOR_MPFR_MAX_ORDER",
    "TAYLOR_MAX_ORDER",
]

TAYLOR_TEMPLATE = "taylor.c"
#: Largest order the C code supports (workspace size); enough for 1e-60 in one step.
TAYLOR_MAX_ORDER = 80

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
            body.append(f"        {x}[k] = _sum(_map(_mul, {ar[0]}[:k1], {b}[k::-1]))")
        elif op == "div":
            zero.append(f"    {x}[0] = {ar[0]}[0] / {ar[1]}[0]")
            body.append(
                f"        {x}[k] = ({ar[0]}[k] - _sum(_map(_mul, {ar[1]}[1:k1], "
                f"{x}[k - 1::-1]))) / {ar[1]}[0]"
            )
        elif op == "cdiv":
            zero.append(f"    {x}[0] = {ar[0]}[0] / {ar[1]}[0]")
            body.append(
                f"        {x}[k] = -_sum(_map(_mul, {ar[1]}[1:k1], {x}[k - 1::-1])) / {ar[1]}[0]"
            )
        elif op == "sqrt":
            zero.append(f"    {x}[0] = _sqrt({ar[0]}[0])")
            body.append(
                f"        {x}[k] = ({ar[0]}[k] - _sum(_map(_mul, {x}[1:k], {x}[k - 1:0:-1])))"
                f" / (2 * {x}[0])"
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
                f"        {x}[k] = _sum([j * {ar[0]}[j] * {x}[k - j] for j in range(1, k1)]) / k"
            )
        elif op in ("sin", "cos"):
            partner = ar[1]
            fn = "_sin" if op == "sin" else "_cos"
            zero.append(f"    {x}[0] = {fn}({ar[0]}[0])")
            sign = "" if op == "sin" else "-"
            body.append(
                f"        {x}[k] = {sign}_sum([j * {ar[0]}[j] * {partner}[k - j] "
                "for j in range(1, k1)]) / k"
            )
        else:  # pragma: no cover
            raise ValueError(op)
    return init, zero, body


@register
class TaylorPythonEmitter(Emitter):
    """Python recurrences for any arbitrary-precision number type (mpmath, gmpy2)."""

    language = "taylor_py"

    def filename(self, model: Model) -> str:
        """Name of the emitted module.

        Parameters
        ----------
        model : Model
            The model printed.

        Returns
        -------
        str
            ``"<model name>_taylor.py"``.
        """
        return f"{model.name}_taylor.py"

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
            "    and optionally ``fsum`` (sums of products; default the built-in ``sum``);",
            "    the working precision is the caller's. Returns ``n_state`` lists of",
            "    ``order + 1`` numbers.",
            '    """',
            "    _mpf, _sqrt, _exp, _sin, _cos = lib.mpf, lib.sqrt, lib.exp, lib.sin, lib.cos",
            "    _sum, _map = getattr(lib, 'fsum', sum), map",
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


# ---------------------------------------------------------------------------- C


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
            For another function, or an integer too large for a double.
        """
        return self._print(sp.sympify(expr))

    def _int(self, n: int) -> str:
        if abs(n) > 2**53:
            raise NotImplementedError(f"integer {n} is not exact in a double")
        return f"R_INT({n})"

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


def _c_lines(
    prog: TaylorProgram, printer: _TaylorCPrinter, macro_printer: _TaylorMacroPrinter
) -> tuple[list, list]:
    """(order 0, per-order body) lines of ``taylor_coefficients``; arithmetic on ``REAL``
    through the template's ``R_*`` macros, so one text serves every ``REAL`` type."""
    zero, body = [], []
    a = [f"a{i}" for i in range(len(prog.nodes))]
    for i, node in enumerate(prog.nodes):
        op, args = node.op, node.args
        x = a[i]
        ar = [a[j] for j in args]
        if op == "var":
            zero.append(f"    {x}[0] = Y[{node.index}];")
        elif op == "time":
            zero.append(f"    {x}[0] = T0; if (S > 1) {x}[1] = R_INT(1);")
        elif op == "const":
            # C operators where REAL has them (the double and binary128 text, unchanged);
            # R_* macros for the other types
            zero.append("#ifdef R_OPERATORS")
            zero.append(f"    {x}[0] = {printer.doprint(node.expr)};")
            zero.append("#else")
            zero.append(f"    {x}[0] = {macro_printer.doprint(node.expr)};")
            zero.append("#endif")
        elif op in ("add", "sub"):
            fn = "R_ADD" if op == "add" else "R_SUB"
            zero.append(f"    {x}[0] = {fn}({ar[0]}[0], {ar[1]}[0]);")
            body.append(f"        {x}[k] = {fn}({ar[0]}[k], {ar[1]}[k]);")
        elif op == "neg":
            zero.append(f"    {x}[0] = R_NEG({ar[0]}[0]);")
            body.append(f"        {x}[k] = R_NEG({ar[0]}[k]);")
        elif op == "addc":
            zero.append(f"    {x}[0] = R_ADD({ar[0]}[0], {ar[1]}[0]);")
            body.append(f"        {x}[k] = {ar[0]}[k];")
        elif op == "mulc":
            zero.append(f"    {x}[0] = R_MUL({ar[0]}[0], {ar[1]}[0]);")
            body.append(f"        {x}[k] = R_MUL({ar[0]}[k], {ar[1]}[0]);")
        elif op == "mul":
            zero.append(f"    {x}[0] = R_MUL({ar[0]}[0], {ar[1]}[0]);")
            body.append(f"        {x}[k] = tc_mul({ar[0]}, {ar[1]}, k);")
        elif op == "sq":
            zero.append(f"    {x}[0] = R_MUL({ar[0]}[0], {ar[0]}[0]);")
            body.append(f"        {x}[k] = tc_sq({ar[0]}, k);")
        elif op == "div":
            zero.append(f"    {x}[0] = R_DIV({ar[0]}[0], {ar[1]}[0]);")
            body.append(f"        {x}[k] = tc_div({ar[0]}[k], {ar[1]}, {x}, k);")
        elif op == "cdiv":
            zero.append(f"    {x}[0] = R_DIV({ar[0]}[0], {ar[1]}[0]);")
            body.append(f"        {x}[k] = tc_div(R_INT(0), {ar[1]}, {x}, k);")
        elif op == "sqrt":
            zero.append(f"    {x}[0] = R_SQRT({ar[0]}[0]);")
            body.append(f"        {x}[k] = tc_sqrt({ar[0]}, {x}, k);")
        elif op == "pow":
            r = sp.Rational(node.expr)
            zero.append(
                f"    {x}[0] = R_POW({ar[0]}[0], R_DIV(R_INT({int(r.p)}), R_INT({int(r.q)})));"
            )
            body.append(f"        {x}[k] = tc_pow({ar[0]}, {x}, {int(r.p)}, {int(r.q)}, k);")
        elif op == "exp":
            zero.append(f"    {x}[0] = R_EXP({ar[0]}[0]);")
            body.append(f"        {x}[k] = tc_exp({ar[0]}, {x}, k);")
        elif op in ("sin", "cos"):
            fn = "R_SIN" if op == "sin" else "R_COS"
            zero.append(f"    {x}[0] = {fn}({ar[0]}[0]);")
            call = f"tc_exp({ar[0]}, {ar[1]}, k)"
            body.append(f"        {x}[k] = {call if op == 'sin' else f'R_NEG({call})'};")
        else:  # pragma: no cover
            raise ValueError(op)
    return zero, body


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

    def filename(self, model: Model) -> str:
        """Name of the emitted C file.

        Parameters
        ----------
        model : Model
            The model printed.

        Returns
        -------
        str
            ``"<model name>_taylor.c"``.
        """
        return f"{model.name}_taylor.c"

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        prog = build_taylor_program(model)
        names = {s: f"p_{s.name}" for s in model.params}
        printer = _TaylorCPrinter(names)
        zero, body = _c_lines(prog, printer, _TaylorMacroPrinter(names))
        nodes = len(prog.nodes)
        decl = [f"    REAL *restrict a{i} = X + {i} * S;" for i in range(nodes)]
        params = [f"    const REAL p_{s.name} = P[{i}];" for i, s in enumerate(model.params)]
        params += [f"    (void)p_{s.name};" for s in model.params]
        out = [
            f"        a{i}[k + 1] = R_DIV(a{o}[k], R_INT(k + 1));"
            for i, o in enumerate(prog.outputs)
        ]
        fn = [
            "static void taylor_coefficients(int order, REAL T0, const REAL *restrict Y,",
            "                                const REAL *restrict P, REAL *restrict X)",
            "{",
            "    const int S = order + 1;",
            *params,
            *decl,
            # only the time and constant nodes have coefficients that no recurrence writes
            # (every other node's k = 0..order-1 and the state's 0..order are computed
            # before they are read): zero those rows, not the whole workspace
            *[
                f"    for (int k = 0; k < S; ++k) a{i}[k] = R_INT(0);"
                for i, node in enumerate(prog.nodes)
                if node.op in ("time", "const")
            ],
            *zero,
            "    for (int k = 0; k < order; ++k) {",
            "        if (k > 0) {",
            *["    " + ln for ln in body],
            "        }",
            *out,
            "    }",
            "}",
        ]
        text = read_taylor_template()
        for key, value in {
            "HEADER": "\n".join(header_lines(model, "taylor, C")),
            "N_STATE": str(prog.n_state),
            "N_PARAM": str(len(model.params)),
            "N_NODES": str(nodes),
            "MAX_ORDER": str(TAYLOR_MAX_ORDER),
            "MODEL_HASH": model.hash,
            "COEFFICIENTS": "\n".join(fn),
        }.items():
            text = text.replace("{{" + key + "}}", value)
        return [(self.filename(model), text)]


# ---------------------------------------------------------------------------- C, MPFR

TAYLOR_MPFR_TEMPLATE = "taylor_mpfr.c"
#: Largest order of the MPFR C code (the Python recurrences' default cap, PY_MAX_ORDER of
#: numerics/taylor.py): the Jorba-Zou order of 10^-170 (about 197); the workspace is
#: allocated per run at the order the run needs, so the cap costs nothing.
TAYLOR_MPFR_MAX_ORDER = 400


class _MpfrConstPrinter:
    """Constants (expressions in the parameters) as in-place MPFR calls.

    Each node ``expr`` is evaluated into its target with temporaries ``w->c[d]`` (``d`` the
    nesting depth), every operation rounded to nearest at the run's precision like the
    Python recurrences' ``gmpy2`` evaluation of the same expression.
    """

    _FUNCTIONS = {sp.sin: "mpfr_sin", sp.cos: "mpfr_cos", sp.exp: "mpfr_exp"}

    def __init__(self, names: dict[sp.Symbol, str]):
        self._names = names
        self.depth = 0

    def lines(self, expr: sp.Expr, target: str) -> list[str]:
        """C statements computing ``expr`` into ``target``.

        Parameters
        ----------
        expr : sympy.Expr
            A constant of the Taylor program (parameters, rationals, ``pi``, powers,
            ``sin``, ``cos``, ``exp``).
        target : str
            C expression of an ``mpfr_ptr`` (not used by ``expr``).

        Returns
        -------
        list of str
            The statements; :attr:`depth` grows to the temporaries they need.

        Raises
        ------
        NotImplementedError
            For another function.
        """
        out: list[str] = []
        self._emit(sp.sympify(expr), target, 0, out)
        return out

    def _tmp(self, d: int) -> str:
        self.depth = max(self.depth, d + 1)
        return f"w->c[{d}]"

    def _int(self, n: int, target: str, out: list[str]) -> None:
        if abs(n) < 2**31:
            out.append(f"mpfr_set_si({target}, {n}L, MPFR_RNDN);")
        else:
            out.append(f'mpfr_set_str({target}, "{n}", 10, MPFR_RNDN);')

    def _emit(self, e: sp.Expr, target: str, d: int, out: list[str]) -> None:
        rn = "MPFR_RNDN"
        if e.is_Symbol:
            out.append(f"mpfr_set({target}, {self._names[e]}, {rn});")
        elif e.is_Integer:
            self._int(int(e), target, out)
        elif e.is_Rational:
            self._int(int(e.p), target, out)
            if int(e.q) < 2**31:
                out.append(f"mpfr_div_ui({target}, {target}, {int(e.q)}UL, {rn});")
            else:
                t = self._tmp(d)
                self._int(int(e.q), t, out)
                out.append(f"mpfr_div({target}, {target}, {t}, {rn});")
        elif e is sp.pi:
            out.append(f"mpfr_const_pi({target}, {rn});")
        elif e.is_Add or e.is_Mul:
            fn = "mpfr_add" if e.is_Add else "mpfr_mul"
            args = list(e.args)
            self._emit(args[0], target, d, out)
            t = self._tmp(d)
            for arg in args[1:]:
                self._emit(arg, t, d + 1, out)
                out.append(f"{fn}({target}, {target}, {t}, {rn});")
        elif e.is_Pow:
            base, x = e.base, e.exp
            self._emit(base, target, d, out)
            if x == sp.Rational(1, 2):
                out.append(f"mpfr_sqrt({target}, {target}, {rn});")
            elif x == sp.Rational(-1, 2):
                out.append(f"mpfr_rec_sqrt({target}, {target}, {rn});")
            elif x.is_Integer and abs(int(x)) < 2**31:
                out.append(f"mpfr_pow_si({target}, {target}, {int(x)}L, {rn});")
            else:
                t = self._tmp(d)
                self._emit(x, t, d + 1, out)
                out.append(f"mpfr_pow({target}, {target}, {t}, {rn});")
        elif e.func in self._FUNCTIONS:
            self._emit(e.args[0], target, d, out)
            out.append(f"{self._FUNCTIONS[e.func]}({target}, {target}, {rn});")
        else:
            raise NotImplementedError(f"no MPFR form of {type(e).__name__}: {e}")


def _mpfr_lines(
    prog: TaylorProgram, printer: _MpfrConstPrinter
) -> tuple[list[str], list[str], int]:
    """(order 0, per-order body, rows) of the MPFR ``taylor_coefficients``; ``rows`` counts
    the nodes plus one extra series ``j a_j`` per ``exp`` node and ``sin``/``cos`` pair."""
    rn = "MPFR_RNDN"
    zero, body = [], []
    rows = len(prog.nodes)
    derivative_row: dict[int, int] = {}  # exp or sin node -> its row j a_j
    for i, node in enumerate(prog.nodes):
        op, ar = node.op, node.args
        x0, xk = f"A({i}, 0)", f"A({i}, k)"
        if op == "var":
            zero.append(f"mpfr_set({x0}, w->Y[{node.index}], {rn});")
        elif op == "time":
            zero.append(f"mpfr_set({x0}, w->T0, {rn});")
            zero.append(f"if (order >= 1) mpfr_set_ui(A({i}, 1), 1, {rn});")
        elif op == "const":
            zero.extend(printer.lines(node.expr, x0))
        elif op in ("add", "sub"):
            fn = f"mpfr_{op}"
            zero.append(f"{fn}({x0}, A({ar[0]}, 0), A({ar[1]}, 0), {rn});")
            body.append(f"{fn}({xk}, A({ar[0]}, k), A({ar[1]}, k), {rn});")
        elif op == "neg":
            zero.append(f"mpfr_neg({x0}, A({ar[0]}, 0), {rn});")
            body.append(f"mpfr_neg({xk}, A({ar[0]}, k), {rn});")
        elif op == "addc":
            zero.append(f"mpfr_add({x0}, A({ar[0]}, 0), A({ar[1]}, 0), {rn});")
            body.append(f"mpfr_set({xk}, A({ar[0]}, k), {rn});")
        elif op == "mulc":
            zero.append(f"mpfr_mul({x0}, A({ar[0]}, 0), A({ar[1]}, 0), {rn});")
            body.append(f"mpfr_mul({xk}, A({ar[0]}, k), A({ar[1]}, 0), {rn});")
        elif op == "mul":
            zero.append(f"mpfr_mul({x0}, A({ar[0]}, 0), A({ar[1]}, 0), {rn});")
            body.append(f"tc_dot(w, {xk}, FWD({ar[0]}, 0), REV({ar[1]}, k), k + 1);")
        elif op == "sq":
            a = ar[0]
            zero.append(f"mpfr_sqr({x0}, A({a}, 0), {rn});")
            # 2 sum_{j < (k+1)/2} a_j a_(k-j) (+ a_(k/2)^2 for even k)
            body.append(f"tc_dot(w, {xk}, FWD({a}, 0), REV({a}, k), (k + 1) / 2);")
            body.append(f"mpfr_mul_2ui({xk}, {xk}, 1, {rn});")
            body.append(
                f"if (k % 2 == 0) {{ mpfr_sqr(w->t, A({a}, k / 2), {rn}); "
                f"mpfr_add({xk}, {xk}, w->t, {rn}); }}"
            )
        elif op in ("div", "cdiv"):
            zero.append(f"mpfr_div({x0}, A({ar[0]}, 0), A({ar[1]}, 0), {rn});")
            body.append(f"tc_dot(w, w->s, FWD({ar[1]}, 1), REV({i}, k - 1), k);")
            if op == "div":
                body.append(f"mpfr_sub(w->s, A({ar[0]}, k), w->s, {rn});")
            else:
                body.append(f"mpfr_neg(w->s, w->s, {rn});")
            body.append(f"mpfr_div({xk}, w->s, A({ar[1]}, 0), {rn});")
        elif op == "sqrt":
            zero.append(f"mpfr_sqrt({x0}, A({ar[0]}, 0), {rn});")
            body.append(f"tc_dot(w, w->s, FWD({i}, 1), REV({i}, k - 1), k - 1);")
            body.append(f"mpfr_sub(w->s, A({ar[0]}, k), w->s, {rn});")
            body.append(f"mpfr_div({xk}, w->s, A({i}, 0), {rn});")
            body.append(f"mpfr_div_2ui({xk}, {xk}, 1, {rn});")
        elif op == "pow":
            r = sp.Rational(node.expr)
            p, q = int(r.p), int(r.q)
            zero.append(f"mpfr_set_si(w->e, {p}L, {rn}); mpfr_div_ui(w->e, w->e, {q}UL, {rn});")
            zero.append(f"mpfr_pow({x0}, A({ar[0]}, 0), w->e, {rn});")
            body.append(f"tc_pow(w, {ar[0]}, {i}, {p}L, {q}L, k);")
        elif op in ("exp", "sin", "cos"):
            fn = {"exp": "mpfr_exp", "sin": "mpfr_sin", "cos": "mpfr_cos"}[op]
            zero.append(f"{fn}({x0}, A({ar[0]}, 0), {rn});")
            # the sin node (first of its pair) writes the row j a_j, the cos node reads it
            owner = ar[1] if op == "cos" else i
            if owner not in derivative_row:
                derivative_row[owner] = rows
                rows += 1
            d = derivative_row[owner]
            if op != "cos":
                body.append(f"mpfr_mul_ui(A({d}, k), A({ar[0]}, k), (unsigned long)k, {rn});")
            partner = i if op == "exp" else ar[1]
            body.append(f"tc_dot(w, w->s, FWD({d}, 1), REV({partner}, k - 1), k);")
            if op == "cos":
                body.append(f"mpfr_neg(w->s, w->s, {rn});")
            body.append(f"mpfr_div_ui({xk}, w->s, (unsigned long)k, {rn});")
        else:  # pragma: no cover
            raise ValueError(op)
    return zero, body, rows


def read_taylor_mpfr_template() -> str:
    """Text of the C template of the MPFR Taylor integrator (package data).

    Returns
    -------
    str
        The contents of ``chaplygin/derive/templates/taylor_mpfr.c``.
    """
    return (
        resources.files("chaplygin.derive").joinpath("templates", TAYLOR_MPFR_TEMPLATE).read_text()
    )


@register
class TaylorMpfrEmitter(Emitter):
    """C99 Taylor integrator on MPFR numbers at a precision chosen per run."""

    language = "taylor_mpfr"

    def filename(self, model: Model) -> str:
        """Name of the emitted C file.

        Parameters
        ----------
        model : Model
            The model printed.

        Returns
        -------
        str
            ``"<model name>_taylor_mpfr.c"``.
        """
        return f"{model.name}_taylor_mpfr.c"

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        prog = build_taylor_program(model)
        names = {s: f"w->P[{i}]" for i, s in enumerate(model.params)}
        printer = _MpfrConstPrinter(names)
        zero, body, rows = _mpfr_lines(prog, printer)
        out = [
            f"        mpfr_div_ui(A({i}, k + 1), A({o}, k), (unsigned long)(k + 1), MPFR_RNDN);"
            for i, o in enumerate(prog.outputs)
        ]
        fn = [
            "/* coefficients 0..order of every node from w->T0, w->Y, w->P (order <= S - 1) */",
            "static void taylor_coefficients(int order, ws_t *w)",
            "{",
            *["    " + ln for ln in zero],
            "    for (int k = 0; k < order; ++k) {",
            "        if (k > 0) {",
            *["            " + ln for ln in body],
            "        }",
            *out,
            "    }",
            "}",
        ]
        text = read_taylor_mpfr_template()
        for key, value in {
            "HEADER": "\n".join(header_lines(model, "taylor, C, MPFR")),
            "N_STATE": str(prog.n_state),
            "N_PARAM": str(len(model.params)),
            "N_NODES": str(len(prog.nodes)),
            "N_ROWS": str(rows),
            "N_CONST_TMP": str(printer.depth),
            "MAX_ORDER": str(TAYLOR_MPFR_MAX_ORDER),
            "MODEL_HASH": model.hash,
            "COEFFICIENTS": "\n".join(fn),
        }.items():
            text = text.replace("{{" + key + "}}", value)
        return [(self.filename(model), text)]
