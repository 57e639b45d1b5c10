"""The Taylor program in C on MPFR numbers, at a precision chosen per run.

:class:`TaylorMpfrEmitter` (language ``taylor_mpfr``) prints the program of
:func:`~chaplygin.derive.emit.taylor.build_taylor_program` as in-place MPFR calls into the
template ``templates/taylor_mpfr.c`` (the precisions past quad-double).
"""

from __future__ import annotations

from importlib import resources

import sympy as sp

from ..model import Model
from .base import Emitter, ModelRoutines, header_lines, register
from .taylor import TaylorProgram, build_taylor_program

__all__ = ["TaylorMpfrEmitter", "TAYLOR_MPFR_TEMPLATE", "TAYLOR_MPFR_MAX_ORDER"]

TAYLOR_MPFR_TEMPLATE = "taylor_mpfr.c"
#: Largest order of the MPFR C code (the Python recurrences' default cap, PY_MAX_ORDER of
#: numerics/taylor/): the Jorba-Zou order of 10^-170 (about 197); the workspace is
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
    ending = "_taylor_mpfr.c"

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
