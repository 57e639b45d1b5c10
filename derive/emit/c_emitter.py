"""C emitter: C99 source from the template ``templates/model.c`` (compiled by numerics)."""

from __future__ import annotations

import itertools
from importlib import resources

import sympy as sp
from sympy.printing.c import C99CodePrinter

from ..model import Model
from .base import Emitter, ModelRoutines, Routine, header_lines, register

__all__ = [
    "CEmitter",
    "CLanesEmitter",
    "ChaplyginCPrinter",
    "C_TEMPLATE",
    "LANES_TEMPLATE",
    "LANEWISE_FUNCTIONS",
    "lanes_obstacle",
    "power_form",
]

_SMALL_POWER = 4

#: Name of the template shipped as package data of ``chaplygin.derive``.
C_TEMPLATE = "model.c"
#: The template of the right-hand side in vector lanes (:class:`CLanesEmitter`).
LANES_TEMPLATE = "lanes.c"


#: sympy functions printed as the project's kernels (``arith/templates/detmath.h``, inlined in
#: every emitted source): libm picks FMA/AVX2 variants of these by processor.
DETMATH_FUNCTIONS = {
    name: f"chaplygin_{name}"
    for name in ("sin", "cos", "exp", "log", "atan", "atan2", "asin", "acos", "sinh", "cosh")
}


def power_form(exp: sp.Expr) -> str:
    """How the C printers write a power ``x**exp``.

    Parameters
    ----------
    exp : sympy.Expr
        The exponent.

    Returns
    -------
    str
        ``"product"`` (``x*x*x``, or its reciprocal), ``"reciprocal"`` (``1.0/x``),
        ``"sqrt"`` (a half-integer: products and one ``sqrt``), ``"integer"`` (a float that
        is a small integer: as that integer) or ``"pow"`` (``chaplygin_pow``).
    """
    if exp.is_Integer and 1 < abs(int(exp)) <= _SMALL_POWER:
        return "product"
    if exp == -1:
        return "reciprocal"
    if exp.is_Rational and exp.q == 2 and abs(exp.p) <= 2 * _SMALL_POWER + 1:
        return "sqrt"
    if exp.is_Number and float(exp) == int(float(exp)) and 1 <= abs(int(float(exp))) <= 4:
        return "integer"
    return "pow"


class ChaplyginCPrinter(C99CodePrinter):
    """C99 printer: small integer powers become products, half-integer powers ``sqrt``, the
    elementary functions the project's kernels; symbols are renamed.

    Parameters
    ----------
    names : dict of sympy.Symbol to str
        C names of the symbols.
    functions : dict of str to str, optional
        C names of the sympy functions (default :data:`DETMATH_FUNCTIONS`).
    sqrt : str, default "sqrt"
        C name of the square root.
    """

    def __init__(self, names: dict[sp.Symbol, str], functions: dict[str, str] | None = None,
                 sqrt: str = "sqrt"):
        super().__init__({"user_functions": dict(DETMATH_FUNCTIONS if functions is None
                                                 else functions)})
        self._names = names
        self._sqrt = sqrt

    def _print_Symbol(self, expr):
        return self._names.get(expr, super()._print_Symbol(expr))

    def _print_Pow(self, expr):
        base, exp = expr.as_base_exp()
        form = power_form(exp)
        if form == "product":
            b = self.parenthesize(base, 100)
            product = "*".join([b] * abs(int(exp)))
            return f"({product})" if exp > 0 else f"(1.0/({product}))"
        if form == "reciprocal":
            return f"(1.0/{self.parenthesize(base, 100)})"
        if form == "sqrt":
            root = f"{self._sqrt}({self._print(base)})"
            k = abs(int(exp.p)) // 2
            # the base printed once more only when a power of it multiplies the root (a
            # nested root would otherwise be printed twice per level: 2^depth)
            value = root if k == 0 else f"({'*'.join([self.parenthesize(base, 100)] * k)}*{root})"
            return value if exp > 0 else f"(1.0/{value})"
        if form == "integer":
            return self._print_Pow(sp.Pow(base, sp.Integer(int(float(exp))), evaluate=False))
        return f"chaplygin_pow({self._print(base)}, {self._print(exp)})"


def read_template(name: str = C_TEMPLATE) -> str:
    """Text of a C template shipped as package data.

    Parameters
    ----------
    name : str, default :data:`C_TEMPLATE`

    Returns
    -------
    str
        ``chaplygin/derive/templates/<name>``.
    """
    return resources.files("chaplygin.derive").joinpath("templates", name).read_text()


def c_names(model: Model) -> dict[sp.Symbol, str]:
    """The C names of a model's symbols: ``s_<name>`` (state), ``p_<name>``, ``T``.

    Parameters
    ----------
    model : Model

    Returns
    -------
    dict of sympy.Symbol to str
    """
    names = {s: f"s_{s.name}" for s in model.state}
    names.update({s: f"p_{s.name}" for s in model.params})
    names[model.time] = "T"
    return names


def routine_function(model: Model, routine: Routine, printer: ChaplyginCPrinter,
                     signature: str, scalar: str) -> str:
    """One routine as a C function: the used state and parameters unpacked into locals, the
    temporaries, the outputs ``OUT[i]``.

    Parameters
    ----------
    model : Model
    routine : Routine
    printer : ChaplyginCPrinter
    signature : str
        The function's declarator (``void chaplygin_rhs(double T, ...)``).
    scalar : str
        The C type of the locals (``double``, a vector type).

    Returns
    -------
    str
        The function, ending with its closing brace (no newline).
    """
    lines = [signature, "{", "    (void)T; (void)Y; (void)P;"]
    used = set().union(
        *(e.free_symbols for _, e in routine.temporaries),
        *(sp.sympify(e).free_symbols for e in routine.outputs),
    )
    state = [(i, s) for i, s in enumerate(model.state) if s in used]
    params = [(i, s) for i, s in enumerate(model.params) if s in used]
    lines += [f"    const {scalar} s_{s.name} = Y[{i}];" for i, s in state]
    lines += [f"    const {scalar} p_{s.name} = P[{i}];" for i, s in params]
    lines += [f"    const {scalar} {s} = {printer.doprint(e)};" for s, e in routine.temporaries]
    width = routine.shape[-1]
    for index, expr in zip(
        itertools.product(*map(range, routine.shape)), routine.outputs, strict=True
    ):
        flat = index[0] if len(index) == 1 else index[0] * width + index[1]
        lines.append(f"    OUT[{flat}] = {printer.doprint(expr)};")
    lines.append("}")
    return "\n".join(lines)


@register
class CEmitter(Emitter):
    """C99 source with one function per routine (``chaplygin_rhs``, ``chaplygin_jac`` ...)."""

    language = "c"
    ending = ".c"

    def _routine(self, model: Model, routine: Routine, printer: ChaplyginCPrinter) -> str:
        signature = (
            f"void chaplygin_{routine.name}(double T, const double *restrict Y, "
            "const double *restrict P, double *restrict OUT)"
        )
        return routine_function(model, routine, printer, signature, "double")

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        printer = ChaplyginCPrinter(c_names(model))
        body = "\n\n".join(
            self._routine(model, r, printer) for r in (*routines.all(), routines.rhs_jacobian)
        )
        text = read_template()
        for key, value in {
            "HEADER": "\n".join(header_lines(model, self.language)),
            "N_STATE": str(len(model.state)),
            "N_PARAM": str(len(model.params)),
            "N_AUX": str(len(model.aux)),
            "N_INTEGRALS": str(len(model.integrals)),
            "MODEL_HASH": model.hash,
            "ROUTINES": body,
        }.items():
            text = text.replace("{{" + key + "}}", value)
        return [(self.filename(model), text)]


#: The sympy functions the vector lanes apply lane by lane, with their C names
#: (``BM_LANEWISE`` of ``templates/batch_map.c``: the project's kernels and the exact fabs).
LANEWISE_FUNCTIONS = {
    "sin": "bm_v_chaplygin_sin",
    "cos": "bm_v_chaplygin_cos",
    "exp": "bm_v_chaplygin_exp",
    "log": "bm_v_chaplygin_log",
    "Abs": "bm_v_fabs",
}


def lanes_obstacle(routine: Routine) -> str | None:
    """What keeps a routine out of the vector lanes, or None.

    The lanes compute sums, products, quotients, the powers the printer writes as products
    and square roots, and :data:`LANEWISE_FUNCTIONS`, on numbers and symbols: every lane
    the IEEE operations of the scalar code.

    Parameters
    ----------
    routine : Routine

    Returns
    -------
    str or None
        The first expression of another kind (``chaplygin_pow``, ``atan2``, ``Piecewise`` ...).
    """
    exprs = [e for _, e in routine.temporaries] + [sp.sympify(e) for e in routine.outputs]
    for expr in exprs:
        for node in sp.preorder_traversal(expr):
            if node.is_Symbol or node.is_Number or node.is_NumberSymbol or node.is_Add \
                    or node.is_Mul:
                continue
            if node.is_Pow:
                if power_form(node.as_base_exp()[1]) == "pow":
                    return f"chaplygin_pow ({node})"
                continue
            if type(node).__name__ not in LANEWISE_FUNCTIONS:
                return type(node).__name__
    return None


@register
class CLanesEmitter(Emitter):
    """The right-hand side, and the right-hand side with the Jacobian, in the vector lanes of
    the DOP853 batches (``bm_rhs_vec``, ``bm_rhs_jac_vec``).

    The emitted ``chaplygin_rhs`` (and ``chaplygin_rhs_jac``) with every double a ``bm_vec``
    (a GNU C vector of doubles, ``templates/batch_map.c``) and the functions applied lane by
    lane: every lane computes the IEEE operations of the scalar code. No file for a model whose
    right-hand side has another operation (:func:`lanes_obstacle`): its batch advances one
    point at a time; no ``bm_rhs_jac_vec`` when only the Jacobian has one (the variational
    batch then advances one point at a time).
    """

    language = "c_lanes"
    ending = "_lanes.c"

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        if lanes_obstacle(routines.rhs) is not None:
            return []
        printer = ChaplyginCPrinter(c_names(model), LANEWISE_FUNCTIONS, sqrt="bm_v_sqrt")
        arguments = "(bm_vec T, const bm_vec *restrict Y, const bm_vec *restrict P, " \
            "bm_vec *restrict OUT)"  # fmt: skip
        lanes = {"bm_rhs_vec": routines.rhs}
        if lanes_obstacle(routines.rhs_jacobian) is None:
            lanes["bm_rhs_jac_vec"] = routines.rhs_jacobian
        functions = [
            routine_function(model, routine, printer, f"static void {name}{arguments}", "bm_vec")
            for name, routine in lanes.items()
        ]
        text = read_template(LANES_TEMPLATE)
        for key, value in {
            "HEADER": "\n".join(header_lines(model, "c, vector lanes")),
            "FUNCTION": "\n\n".join(functions),
        }.items():
            text = text.replace("{{" + key + "}}", value)
        return [(self.filename(model), text)]
