"""Shared printing of Python modules (numpy and mpmath differ in printer and containers)."""

from __future__ import annotations

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from ..model import Model
from .base import Emitter, ModelRoutines, Routine, header_lines

__all__ = ["PythonModuleEmitter"]


def _metadata(model: Model) -> list[str]:
    params = tuple(
        (spec.name, tuple(s.name for s in spec.symbols), spec.domain, spec.description)
        for spec in model.parameters
    )
    groups = tuple((name, tuple(s.name for s in g)) for name, g in model.state_groups)
    geometry = tuple((g.kind, g.names) for g in model.geometry)
    return [
        f"MODEL_NAME = {model.name!r}",
        f"MODEL_HASH = {model.hash!r}",
        f"SYSTEM = {model.system!r}",
        f"EFFECTS = {tuple(sorted(model.effects))!r}",
        f"STATE = {model.state_names!r}",
        f"STATE_GROUPS = {groups!r}",
        f"PARAMS = {model.param_names!r}",
        f"PARAMETERS = {params!r}",
        f"AUX = {tuple(s.name for s in model.aux_symbols)!r}",
        f"INTEGRALS = {tuple(n for n, _ in model.integrals)!r}",
        "RELATIONS = " + repr(tuple(n for n, _ in model.invariant_relations)),
        f"GEOMETRY = {geometry!r}",
        f"CONSTRAINTS = {tuple(f'{sp.sstr(c)} = 0' for c in model.constraints)!r}",
        f"COMPLETION = {model.completion!r}",
        f"REFERENCES = {tuple(sorted(model.references.items()))!r}",
    ]


class PythonModuleEmitter(Emitter):
    """Python module with model metadata and one function per routine."""

    printer_class: type = PythonCodePrinter
    module_import: str = ""
    suffix: str = ""

    def filename(self, model: Model) -> str:
        """Name of the emitted module.

        Parameters
        ----------
        model : Model
            The model printed.

        Returns
        -------
        str
            ``"<model name>_<suffix>.py"``.
        """
        return f"{model.name}_{self.suffix}.py"

    def _print(self, expr: sp.Expr) -> str:
        return self.printer_class({"fully_qualified_modules": True}).doprint(expr)

    def _unpack(self, model: Model) -> list[str]:
        lines = []
        if model.state:
            lines.append(f"    {', '.join(model.state_names)}, = y")
        if model.params:
            lines.append(f"    {', '.join(model.param_names)}, = p")
        return lines

    def _temporaries(self, routine: Routine) -> list[str]:
        return [f"    {s} = {self._print(e)}" for s, e in routine.temporaries]

    def _function(self, model: Model, routine: Routine, signature: str, doc: str) -> list[str]:
        lines = [f"def {routine.name}({signature}):", f'    """{doc}"""']
        lines += self._unpack(model)
        lines += self._temporaries(routine)
        lines += self._outputs(model, routine)
        return lines

    def _outputs(self, model: Model, routine: Routine) -> list[str]:
        raise NotImplementedError

    def _emit_files(self, model: Model, routines: ModelRoutines) -> list[tuple[str, str]]:
        lines = ['"""' + header_lines(model, self.language)[0]]
        lines += header_lines(model, self.language)[1:]
        lines += ['"""', "", "# ruff: noqa", self.module_import, ""]
        lines += _metadata(model)
        n, m = len(model.state), len(model.integrals)
        specs = [
            (routines.rhs, "t, y, p", f"Right-hand side dy/dt, shape ({n}, ...)."),
            (routines.jacobian, "t, y, p", f"Jacobian d(dy/dt)/dy, shape ({n}, {n}, ...)."),
            (routines.aux, "t, y, p", "Auxiliary quantities (AUX order: Z, omega ...)."),
            (
                routines.integrals,
                "t, y, p",
                f"First integrals (INTEGRALS order), shape ({m}, ...).",
            ),
            (routines.density, "t, y, p", "Invariant-measure density, shape (1, ...)."),
            (
                routines.constraints,
                "t, y, p",
                "Phase-space constraints (CONSTRAINTS order), then their scales.",
            ),
        ]
        for routine, signature, doc in specs:
            lines += ["", ""]
            lines += self._function(model, routine, signature, doc)
        return [(self.filename(model), "\n".join(lines) + "\n")]
