"""mpmath emitter: arbitrary precision, set by the caller's ``mpmath.mp`` context."""

from __future__ import annotations

from sympy.printing.pycode import MpmathPrinter

from ..model import Model
from .base import Routine, register
from .python_common import PythonModuleEmitter

__all__ = ["MpmathEmitter"]


@register
class MpmathEmitter(PythonModuleEmitter):
    """Print routines as functions of mpf values returning (nested) lists of mpf.

    Rational constants are printed as quotients of ``mpf`` so that they carry the
    working precision; nothing is rounded to double.
    """

    language = "mpmath"
    suffix = "mpmath"
    printer_class = MpmathPrinter
    module_import = "import mpmath"

    def _outputs(self, model: Model, routine: Routine) -> list[str]:
        items = [self._print(e) if e != 0 else "mpmath.mpf(0)" for e in routine.outputs]
        if len(routine.shape) == 1:
            if not items:  # no phase-space constraint (no unit vector in the state)
                return ["    return []"]
            body = ",\n        ".join(items)
            return [f"    return [\n        {body},\n    ]"]
        n = routine.shape[1]
        rows = ["[" + ", ".join(items[i * n : (i + 1) * n]) + "]" for i in range(routine.shape[0])]
        body = ",\n        ".join(rows)
        return [f"    return [\n        {body},\n    ]"]
