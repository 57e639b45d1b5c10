"""The layers of the package: arith < derive < generated < numerics < verify.

Imports are read from the source with :mod:`ast` (function-level imports included, since
they are cycles all the same once both functions run): no module imports a higher layer and
no set of modules imports itself round a cycle. Plotting selects no matplotlib backend.
"""

from __future__ import annotations

import ast
import importlib.util
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

#: Layers from the lowest up; a module may import its own layer and the ones below.
LAYERS = ("arith", "derive", "generated", "numerics", "verify")


def _package_dir(layer: str) -> Path:
    spec = importlib.util.find_spec(f"chaplygin.{layer}")
    return Path(next(iter(spec.submodule_search_locations)))


def _modules() -> dict[str, tuple[Path, bool]]:
    """``chaplygin.<layer>.<...>`` -> (file, is a package ``__init__``)."""
    out = {}
    for layer in LAYERS:
        root = _package_dir(layer)
        for path in sorted(root.rglob("*.py")):
            parts = [layer, *path.relative_to(root).with_suffix("").parts]
            is_package = parts[-1] == "__init__"
            if is_package:
                parts = parts[:-1]
            out["chaplygin." + ".".join(parts)] = (path, is_package)
    return out


MODULES = _modules()


def _owner(name: str) -> str | None:
    """The module of ``MODULES`` that ``name`` (a module or a name in one) belongs to."""
    while name and name not in MODULES:
        name = name.rpartition(".")[0]
    return name or None


def _constant_prefix(arg: ast.expr, module: str, package: str) -> str | None:
    """The known start of an ``import_module`` argument (``f"{__package__}.{name}"``)."""
    if isinstance(arg, ast.Constant):
        return arg.value
    if not isinstance(arg, ast.JoinedStr):
        return None
    known = {"__name__": module, "__package__": package}
    prefix = ""
    for part in arg.values:
        if isinstance(part, ast.Constant):
            prefix += part.value
        elif isinstance(part.value, ast.Name) and part.value.id in known:
            prefix += known[part.value.id]
        else:
            break
    return prefix.rstrip(".") or None


def imports_of(module: str) -> set[str]:
    """Modules of the package that ``module`` imports anywhere in its source."""
    path, is_package = MODULES[module]
    package = module if is_package else module.rpartition(".")[0]
    found = set()
    tree = ast.parse(path.read_text(), str(path))
    # imports under "if TYPE_CHECKING:" are for annotations only: never run, no cycle
    typing_only = {
        id(inner)
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and ast.unparse(node.test).endswith("TYPE_CHECKING")
        for stmt in node.body
        for inner in ast.walk(stmt)
    }
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            for a in node.names:  # "from . import x" imports the submodule x when there is one
                sub = f"{target}.{a.name}"
                found.add(sub if sub in MODULES else target)
        elif (
            isinstance(node, ast.Call)
            and getattr(node.func, "attr", getattr(node.func, "id", None)) == "import_module"
            and node.args
        ):
            name = _constant_prefix(node.args[0], module, package)
            # a computed name: its known prefix tells the layer, not the module; within the
            # module's own layer it says nothing about cycles, so it is left out
            if name is not None and name.split(".")[:2] != module.split(".")[:2]:
                found.add(name)
    return {owner for name in found if (owner := _owner(name)) and owner != module}


GRAPH = {module: imports_of(module) for module in MODULES}


def _layer(module: str) -> int:
    return LAYERS.index(module.split(".")[1])


def test_the_graph_is_read():
    # a control: the parser sees relative, absolute and function-level imports
    assert "chaplygin.derive.errors" in GRAPH["chaplygin.numerics.separatrix"]
    assert "chaplygin.verify.delta_cmd" in GRAPH["chaplygin.verify.cli"]
    assert "chaplygin.numerics.integrate" in GRAPH["chaplygin.verify.plots"]  # inside a function
    assert "chaplygin.generated" in GRAPH["chaplygin.numerics.code"]  # import_module(f"...")
    assert len(MODULES) > 40


def test_no_lower_layer_imports_a_higher_one():
    bad = sorted(
        f"{m} imports {d}" for m, deps in GRAPH.items() for d in deps if _layer(d) > _layer(m)
    )
    assert bad == []


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's components of more than one module (the import cycles)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return cycles


def test_cycle_finder_finds_a_cycle():
    assert strongly_connected({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [
        ["a", "b", "c"]
    ]


def test_no_import_cycles():
    assert strongly_connected(GRAPH) == []


def _calls_matplotlib_use_or_pyplot(tree: ast.AST) -> list[str]:
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            names = [a.name for a in node.names]
            module = getattr(node, "module", None) or ""
            if "matplotlib.pyplot" in names or module == "matplotlib.pyplot" or (
                module == "matplotlib" and "pyplot" in names
            ):
                found.append(f"line {node.lineno}: imports pyplot")
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            if node.func.attr == "use" and getattr(node.func.value, "id", "") == "matplotlib":
                found.append(f"line {node.lineno}: matplotlib.use")
    return found


def test_no_module_selects_a_backend():
    bad = {
        m: hits
        for m, (path, _) in MODULES.items()
        if (hits := _calls_matplotlib_use_or_pyplot(ast.parse(path.read_text())))
    }
    assert bad == {}
    # a control: the check recognises both forms
    control = ast.parse("import matplotlib.pyplot\nmatplotlib.use('Agg')")
    assert len(_calls_matplotlib_use_or_pyplot(control)) == 2


@pytest.mark.slow
def test_plotting_leaves_the_backend_alone():
    """Importing :mod:`chaplygin.verify.plots` and making and saving a figure neither selects
    a matplotlib backend nor imports pyplot (a notebook keeps its inline figures)."""
    script = textwrap.dedent(
        """
        import io, sys
        import matplotlib
        before = dict.__getitem__(matplotlib.rcParams, "backend")
        import chaplygin.verify.plots as plots
        after_import = dict.__getitem__(matplotlib.rcParams, "backend")
        rows = [
            {"problem": "p", "method": "taylor", "rhs": "C", "precision": "double",
             "median_s": t, "error": e}
            for t, e in ((1e-3, 1e-8), (2e-3, 1e-12))
        ]
        fig = plots.work_precision_figure({"rows": rows, "quick": True})
        buffer = io.BytesIO()
        fig.savefig(buffer, format="png")
        after_figure = dict.__getitem__(matplotlib.rcParams, "backend")
        print(repr(before), repr(after_import), repr(after_figure),
              "matplotlib.pyplot" in sys.modules, buffer.getvalue()[:4] == b"\\x89PNG", sep="|")
        """
    )
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    proc = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, check=True
    )
    before, after_import, after_figure, pyplot, png = proc.stdout.strip().split("|")
    assert before == after_import == after_figure
    assert pyplot == "False" and png == "True"
