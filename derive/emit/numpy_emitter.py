"""numpy emitter: vectorised over states (``y`` of shape ``(n,)`` or ``(n, N)``)."""

from __future__ import annotations

import itertools

import sympy as sp
from sympy.printing.numpy import NumPyPrinter

from ..model import Model
from .base import Routine, register
from .python_common import PythonModuleEmitter

__all__ = ["DeterministicNumPyPrinter", "NumpyEmitter"]

#: sympy functions printed as the project's kernels (``chaplygin.arith.detmath``): numpy's
#: float64 ``sin``, ``exp``, ``log`` ... pick SIMD code by processor (other bits elsewhere).
DETMATH_FUNCTIONS = {
    "sin": "sin", "cos": "cos", "exp": "exp", "log": "log", "atan": "atan", "atan2": "atan2",
    "asin": "asin", "acos": "acos", "sinh": "sinh", "cosh": "cosh",
}  # fmt: skip

#: Largest integer power printed as a product (larger ones through ``detmath.pow``).
SMALL_POWER = 4


class DeterministicNumPyPrinter(NumPyPrinter):
    """numpy printer whose transcendental functions and powers are the project's kernels.

    Element-wise ``+ - * /`` and ``numpy.sqrt`` are IEEE operations (correctly rounded, the
    same bits everywhere); ``sin``, ``exp``, ``log``, ... and non-trivial powers go through
    ``detmath`` (imported by the emitted module), small integer powers become products and
    half-integer powers ``sqrt``.
    """

    _kf = {**NumPyPrinter._kf, **{k: f"detmath.{v}" for k, v in DETMATH_FUNCTIONS.items()}}

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        b = self.parenthesize(base, 100)
        if exp.is_Integer and 1 <= abs(int(exp)) <= SMALL_POWER:
            product = "*".join([b] * abs(int(exp)))
            return f"({product})" if exp > 0 else f"(1.0/({product}))"
        if exp.is_Rational and exp.q == 2 and abs(exp.p) <= 2 * SMALL_POWER + 1:
            root = f"numpy.sqrt({self._print(base)})"
            k = abs(int(exp.p)) // 2
            value = root if k == 0 else f"({'*'.join([b] * k)}*{root})"
            return value if exp > 0 else f"(1.0/{value})"
        if exp.is_Number and float(exp) == int(float(exp)) and 1 <= abs(int(float(exp))) <= 4:
            return self._print_Pow(sp.Pow(base, sp.Integer(int(float(exp))), evaluate=False))
        return f"detmath.pow({self._print(base)}, {self._print(exp)})"


@register
class NumpyEmitter(PythonModuleEmitter):
    """Print routines as numpy functions returning arrays of shape ``routine.shape + batch``."""

    language = "numpy"
    suffix = "numpy"
    printer_class = DeterministicNumPyPrinter
    module_import = "import numpy\n\nfrom chaplygin.arith import detmath"

    def _outputs(self, model: Model, routine: Routine) -> list[str]:
        first = model.state_names[0]
        lines = [
            f"    out = numpy.zeros({routine.shape!r} + numpy.shape({first}), "
            f"dtype=numpy.result_type({first}, *p))"
        ]
        for index, expr in zip(
            itertools.product(*map(range, routine.shape)), routine.outputs, strict=True
        ):
            if expr != 0:
                lines.append(f"    out[{', '.join(map(str, index))}] = {self._print(expr)}")
        lines.append("    return out")
        return lines
