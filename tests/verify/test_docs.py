"""Docstring examples run (numpydoc ``Examples`` sections)."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = [
    "chaplygin.derive.chaplygin_ball",
    "chaplygin.derive.builtin_descriptions",
    "chaplygin.derive.emit.functions",
    "chaplygin.numerics.integrate",
    "chaplygin.numerics.ensemble",
    "chaplygin.numerics.ensemble_propagator",
    "chaplygin.numerics.ball.quadratures",
    "chaplygin.numerics.dynamics.lyapunov_batch",
    "chaplygin.numerics.validated.lohner",
    "chaplygin.numerics.validated.krawczyk",
    "chaplygin.numerics.validated.constraints",
    "chaplygin.numerics.ball.steady_enclosure",
    "chaplygin.numerics.ball.separatrix_enclosure",
    "chaplygin.numerics.taylor",
    "chaplygin.verify.cli_common",
    "chaplygin.verify.output_folder",
    "chaplygin.verify.vocabulary",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0
    assert result.failed == 0


# ------------------------------------------------------------------ numpydoc and type hints
LAYERS = ("derive", "numerics", "verify")


def _public_functions():
    """(file, line, qualified name, node) of every public function and method of the layers.

    Public: the name and the names of the enclosing classes do not start with ``_``;
    properties count as attributes (a docstring, no sections) and are skipped.
    """
    import ast
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    out = []

    def visit(nodes, path, prefix):
        for node in nodes:
            if isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
                visit(node.body, path, f"{prefix}{node.name}.")
            elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                decorators = {ast.unparse(d) for d in node.decorator_list}
                if node.name.startswith("_") or decorators & {"property", "cached_property"}:
                    continue
                if any(d.endswith(".setter") or d == "overload" for d in decorators):
                    continue
                out.append((path.relative_to(root), node.lineno, prefix + node.name, node))

    for layer in LAYERS:
        for path in sorted((root / layer).rglob("*.py")):
            visit(ast.parse(path.read_text(encoding="utf-8")).body, path, "")
    return out


def _missing(node) -> list[str]:
    import ast

    doc = ast.get_docstring(node) or ""
    args = [
        a
        for a in (*node.args.posonlyargs, *node.args.args, *node.args.kwonlyargs)
        if a.arg not in ("self", "cls")
    ]
    for extra in (node.args.vararg, node.args.kwarg):
        if extra is not None:
            args.append(extra)
    problems = []
    if not doc:
        problems.append("no docstring")
    if args and "Parameters\n" not in doc + "\n":
        problems.append("no Parameters section")
    returns_none = node.returns is not None and ast.unparse(node.returns) == "None"
    if not returns_none and not any(f"{s}\n" in doc + "\n" for s in ("Returns", "Yields")):
        problems.append("no Returns section")
    unhinted = [a.arg for a in args if a.annotation is None]
    if unhinted:
        problems.append(f"arguments without type hints: {', '.join(unhinted)}")
    if node.returns is None:
        problems.append("no return type hint")
    return problems


def test_every_public_function_has_numpydoc_sections_and_type_hints():
    """Issue 10, item 7: Parameters/Returns sections and full hints on every public function."""
    report = [
        f"{path}:{line} {name}: {'; '.join(problems)}"
        for path, line, name, node in _public_functions()
        if (problems := _missing(node))
    ]
    assert not report, f"{len(report)} public functions lack docs or hints:\n" + "\n".join(report)


def test_the_docs_check_finds_an_undocumented_function():
    """Control: the same check refuses a bare function."""
    import ast

    node = ast.parse("def f(x, y=1):\n    return x\n").body[0]
    assert _missing(node) == [
        "no docstring",
        "no Parameters section",
        "no Returns section",
        "arguments without type hints: x, y",
        "no return type hint",
    ]
