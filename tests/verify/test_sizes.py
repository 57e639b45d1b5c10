"""Sizes (issue 23, deliverable 6): no function over 120 lines and no module over 800 lines in
the package, outside claim data (``verify/claims/``: the papers' statements, one module per paper)
and generated code (``generated/``, never edited by hand).

Measured with :mod:`ast` over every module of ``arith``, ``derive``, ``numerics`` and
``verify``: a module's lines are its lines of text, a function's run from its ``def`` to its last
line (a method or a nested function is a function of its own). There is no allow-list: the
offenders of issue 23 (``arith/detmath.py``, ``derive/hamiltonisation.py``,
``numerics/taylor.py``, ``numerics/separatrix.py`` ...) were split by role.
"""

from __future__ import annotations

import ast
import importlib.util
from pathlib import Path

#: The limits.
MAX_FUNCTION_LINES = 120
MAX_MODULE_LINES = 800

#: Layers measured (``generated`` is emitted code).
MEASURED = ("arith", "derive", "numerics", "verify")

#: Claim data: exempt.
EXEMPT = ("verify/claims/",)



def _root(layer: str) -> Path:
    spec = importlib.util.find_spec(f"chaplygin.{layer}")
    return Path(next(iter(spec.submodule_search_locations)))


def sizes_over(source: str, name: str) -> dict[str, int]:
    """``{name: lines}`` if the module is over :data:`MAX_MODULE_LINES`, and
    ``{name:function: lines}`` for each function over :data:`MAX_FUNCTION_LINES`.

    Parameters
    ----------
    source : str
        A module's text.
    name : str
        Its path, for the keys.

    Returns
    -------
    dict of str to int
    """
    out = {}
    lines = len(source.splitlines())
    if lines > MAX_MODULE_LINES:
        out[name] = lines
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            length = node.end_lineno - node.lineno + 1
            if length > MAX_FUNCTION_LINES:
                key = f"{name}:{node.name}"
                out[key] = max(out.get(key, 0), length)
    return out


def measured(exempt: tuple[str, ...] = EXEMPT) -> dict[str, int]:
    """Every offender of the package (claim data and generated code left out)."""
    out: dict[str, int] = {}
    for layer in MEASURED:
        root = _root(layer)
        for path in sorted(root.rglob("*.py")):
            name = f"{layer}/{path.relative_to(root).as_posix()}"
            if not name.startswith(exempt):
                out.update(sizes_over(path.read_text(), name))
    return out


def test_the_measure_sees_long_functions_and_modules():
    # a control: one line over each limit is found, the limit itself is not
    body = "\n".join(f"    x{i} = {i}" for i in range(MAX_FUNCTION_LINES - 1))
    long_function = f"def f():\n{body}\n"  # def line + 119 = 120 lines: at the limit
    assert sizes_over(long_function, "m.py") == {}
    assert sizes_over(long_function + "    return x0\n", "m.py") == {"m.py:f": 121}
    method = "class A:\n    def g(self):\n" + "\n".join(["        pass"] * 121) + "\n"
    assert sizes_over(method, "m.py") == {"m.py:g": 122}
    module = "\n".join(["x = 1"] * MAX_MODULE_LINES) + "\n"
    assert sizes_over(module, "m.py") == {}
    assert sizes_over(module + "y = 2\n", "m.py") == {"m.py": MAX_MODULE_LINES + 1}
    # and the package is read: the claim data, measured too, has modules over the limit
    assert "verify/claims/bm20.py" in measured(exempt=())


def test_no_long_function_or_module():
    assert measured() == {}, (
        f"over {MAX_FUNCTION_LINES} lines a function or {MAX_MODULE_LINES} a module"
    )
