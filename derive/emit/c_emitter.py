"""C emitter: C99 source from the template ``templates/model.c`` (compiled by numerics)."""

from __future__ import annotations

import itertools
from importlib import resources

import sympy as sp
from sympy.printing.c import C99CodePrinter

from ..model import Model
from .base import Emitter, ModelRoutines, Routine, header_lines, register

__all__ = ["CEmitter", "ChaplyginCPrinter", "C_TEMPLATE"]

_SMALL_POWER = 4

#: Name of the template shipped as package data of ``chaplygin.derive``.
C_TEMPLATE = "model.c"


#: sympy functions printed as the project's kernels (``arith/templates/detmath.h``, inlined in
#: every emitted source): libm picks FMA/AVX2 variants of these by processor.
DETMATH_FUNCTIONS = {
    name: f"chaplygin_{name}"
    for name in ("sin", "cos", "exp", "log", "atan", "atan2", "asin", "acos", "sinh", "cosh")
}


class ChaplyginCPrinter(C99CodePrinter):
    """C99 printer: small integer powers become products, half-integer powers ``sqrt``, the
    elementary functions the project's kernels; symbols are renamed."""

    def __init__(self, names: dict[sp.Symbol, str]):
        super().__init__({"user_functions": dict(DETMATH_FUNCTIONS)})
        self._names = names

    def _print_Symbol(self, expr):
        return self._names.get(expr, super()._print_Symbol(expr))

    def _print_Pow(self, expr):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 1 < abs(int(exp)) <= _SMALL_POWER:
            b = self.parenthesize(base, 100)
            product = "*".join([b] * abs(int(exp)))
            return f"({product})" if exp > 0 else f"(1.0/({product}))"
        if exp == -1:
            return f"(1.0/{self.parenthesize(base, 100)})"
        if exp.is_Rational and exp.q == 2 and abs(exp.p) <= 2 * _SMALL_POWER + 1:
            b = self.parenthesize(base, 100)
            root = f"sqrt({self._print(base)})"
            k = abs(int(exp.p)) // 2
            value = root if k == 0 else f"({'*'.join([b] * k)}*{root})"
            return value if exp > 0 else f"(1.0/{value})"
        if exp.is_Number and float(exp) == int(float(exp)) and 1 <= abs(int(float(exp))) <= 4:
            return self._print_Pow(sp.Pow(base, sp.Integer(int(float(exp))), evaluate=False))
        return f"chaplygin_pow({self._print(base)}, {self._print(exp)})"


def read_template() -> str:
    """Text of the C template shipped as package data.

    Returns
    -------
    str
        ``chaplygin/derive/templates/<C_TEMPLATE>``.
    """
    return resources.files("chaplygin.derive").joinpath("templates", C_TEMPLATE).read_text()


@register
class CEmitter(Emitter):
    """C99 source with one function per routine (``chaplygin_rhs``, ``chaplygin_jac`` ...)."""

    language = "c"

    def filename(self, model: Model) -> str:
        """Name of the emitted file.

        Parameters
        ----------
        model : Model
            The model printed.

        Returns
        -------
        str
            ``"<model name>.c"``.
        """
        return f"{model.name}.c"

    def _routine(self, model: Model, routine: Routine, printer: ChaplyginCPrinter) -> str:
        lines = [
            f"void chaplygin_{routine.name}(double T, const double *restrict Y, "
            "const double *restrict P, double *restrict OUT)",
            "{",
            "    (void)T; (void)Y; (void)P;",
        ]
        used = set().union(
            *(e.free_symbols for _, e in routine.temporaries),
            *(sp.sympify(e).free_symbols for e in routine.outputs),
        )
        state = [(i, s) for i, s in enumerate(model.state) if s in used]
        params = [(i, s) for i, s in enumerate(model.params) if s in used]
        lines += [f"    const double s_{s.name} = Y[{i}];" for i, s in state]
        lines += [f"    const double p_{s.name} = P[{i}];" for i, s in params]
        lines += [f"    const double {s} = {printer.doprint(e)};" for s, e in routine.temporaries]
        width = routine.shape[-1]
        for index, expr in zip(
            itertools.product(*map(range, routine.shape)), routine.outputs, strict=True
        ):
            flat = index[0] if len(index) == 1 else index[0] * width + index[1]
            lines.append(f"    OUT[{flat}] = {printer.doprint(expr)};")
        lines.append("}")
        return "\n".join(lines)

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        names = {s: f"s_{s.name}" for s in model.state}
        names.update({s: f"p_{s.name}" for s in model.params})
        names[model.time] = "T"
        printer = ChaplyginCPrinter(names)
        body = "\n\n".join(self._routine(model, r, printer) for r in routines.all())
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
