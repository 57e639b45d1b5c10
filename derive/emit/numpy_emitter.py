"""numpy emitter: vectorised over states (``y`` of shape ``(n,)`` or ``(n, N)``)."""

from __future__ import annotations

import itertools

from sympy.printing.numpy import NumPyPrinter

from ..model import Model
from .base import Routine, register
from .python_common import PythonModuleEmitter

__all__ = ["NumpyEmitter"]


@register
class NumpyEmitter(PythonModuleEmitter):
    """Print routines as numpy functions returning arrays of shape ``routine.shape + batch``."""

    language = "numpy"
    suffix = "numpy"
    printer_class = NumPyPrinter
    module_import = "import numpy"

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
