"""Emitters: printers that turn a Model into source files (numpy, mpmath, C), and every C source
the project compiles.

Each emitter returns ``[(filename, text)]`` and writes nothing; :mod:`.writer` puts the
files in ``generated/`` and checks that they are up to date. :func:`emit_function` prints
run-time functions of other expressions the same way (the project's ``lambdify``). This is
the only place that writes C (``tests/verify/test_layers.py``): the printers work on sympy
expressions and on the Taylor program's expression trees, and :mod:`.c_sources` puts the
emitted files and the templates (``derive/templates``) together into the translation units
numerics compiles; :mod:`.taylor_unroll` writes the Taylor coefficients out for the orders a
run needs, at run time, from the printed program (no sympy).
"""

from __future__ import annotations

from .base import EMITTERS, Emitter, ModelRoutines, get_emitter, header_lines
from .c_emitter import CEmitter, CLanesEmitter
from .functions import emit_function, function_source, module_from_source
from .mpmath_emitter import MpmathEmitter
from .numpy_emitter import NumpyEmitter
from .taylor import TaylorPythonEmitter, build_taylor_program
from .taylor_c import PrintedProgram, TaylorCEmitter, TaylorProgramEmitter
from .taylor_mpfr import TaylorMpfrEmitter

__all__ = [
    "EMITTERS",
    "Emitter",
    "ModelRoutines",
    "NumpyEmitter",
    "MpmathEmitter",
    "CEmitter",
    "CLanesEmitter",
    "TaylorCEmitter",
    "TaylorMpfrEmitter",
    "TaylorPythonEmitter",
    "TaylorProgramEmitter",
    "PrintedProgram",
    "build_taylor_program",
    "emit_function",
    "function_source",
    "module_from_source",
    "get_emitter",
    "header_lines",
]
