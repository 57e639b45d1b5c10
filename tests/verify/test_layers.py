"""The layers of the package: arith < derive < generated < numerics < verify.

Imports are read from the source with :mod:`ast` (function-level imports included, since
they are cycles all the same once both functions run, and modules loaded by name through
``importlib``): no module imports a higher layer and no set of modules imports itself round a
cycle. Scene outputs import only the scene's public interface for outputs. Plotting selects no
matplotlib backend.
"""

from __future__ import annotations

import ast
import functools
import importlib.util
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

#: Layers from the lowest up; a module may import its own layer and the ones below.
LAYERS = ("arith", "derive", "generated", "numerics", "verify")

#: Calls that load a module by name.
_IMPORT_CALLS = ("import_module", "__import__")


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


def _owner(name: str, modules: dict = MODULES) -> str | None:
    """The module of ``modules`` that ``name`` (a module or a name in one) belongs to."""
    while name and name not in modules:
        name = name.rpartition(".")[0]
    return name or None


#: The name Python gives a module at run time, where it differs from its place in the tree:
#: pyproject maps the package root ``chaplygin`` to ``verify/api``.
RUNTIME_NAMES = {"chaplygin.verify.api": "chaplygin"}


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


def _from_target(node: ast.ImportFrom, package: str) -> str:
    """The module a ``from ... import`` names (relative ones resolved in ``package``)."""
    if node.level:
        parts = package.split(".")
        base = parts[: len(parts) - node.level + 1]
        return ".".join(base + ([node.module] if node.module else []))
    return node.module or ""


class _Strings:
    """The values a string expression of a module can take, read from its source: constants,
    ``__name__``/``__package__``, f-strings and ``+`` of those, and names bound by a ``for``
    (or a comprehension) over a module-level literal (a tuple, list or set of strings, or a
    dict: its keys, ``.keys()``, ``.values()``, ``.items()``). None when it cannot tell."""

    def __init__(self, tree: ast.AST, module: str, package: str):
        self.known = {"__name__": module, "__package__": package}
        self.literals: dict[str, object] = {}
        for node in getattr(tree, "body", []):
            target = value = None
            if isinstance(node, ast.Assign) and len(node.targets) == 1:
                target, value = node.targets[0], node.value
            elif isinstance(node, ast.AnnAssign) and node.value is not None:
                target, value = node.target, node.value
            if isinstance(target, ast.Name):
                try:
                    self.literals[target.id] = ast.literal_eval(value)
                except (ValueError, TypeError, SyntaxError, RecursionError):
                    pass
        self.tree = tree
        self.loops = self._loops(tree)

    @staticmethod
    def _loops(scope: ast.AST) -> dict[str, list[tuple[ast.expr, int | None]]]:
        """Names bound by ``for`` loops and comprehensions in ``scope``: their iterables."""
        loops: dict[str, list[tuple[ast.expr, int | None]]] = {}
        for node in ast.walk(scope):
            if isinstance(node, ast.For | ast.comprehension):
                if isinstance(node.target, ast.Name):
                    loops.setdefault(node.target.id, []).append((node.iter, None))
                elif isinstance(node.target, ast.Tuple):
                    for i, elt in enumerate(node.target.elts):
                        if isinstance(elt, ast.Name):
                            loops.setdefault(elt.id, []).append((node.iter, i))
        return loops

    def within(self, function: ast.AST | None) -> _Strings:
        """The same reading with loop variables looked up in ``function`` first."""
        if function is None:
            return self
        inner = object.__new__(_Strings)
        inner.known, inner.literals, inner.tree = self.known, self.literals, self.tree
        local = self._loops(function)
        inner.loops = {**self.loops, **local}
        return inner

    def _items(self, node: ast.expr, position: int | None) -> set[str] | None:
        """The strings a loop over ``node`` binds (``position``: of a tuple target)."""
        method = None
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr in ("keys", "values", "items")
            and not node.args
        ):
            method, node = node.func.attr, node.func.value
        if isinstance(node, ast.Name) and node.id in self.literals:
            value = self.literals[node.id]
        else:
            try:
                value = ast.literal_eval(node)
            except (ValueError, TypeError, SyntaxError, RecursionError):
                return None
        if isinstance(value, dict):
            items = {"values": value.values(), "items": value.items()}.get(method, value.keys())
        elif isinstance(value, tuple | list | set | frozenset) and method is None:
            items = value
        else:
            return None
        out = set()
        for item in items:
            if position is not None:
                if not isinstance(item, tuple) or len(item) <= position:
                    return None
                item = item[position]
            if not isinstance(item, str):
                return None
            out.add(item)
        return out

    def values(self, node: ast.expr) -> set[str] | None:
        if isinstance(node, ast.Constant):
            return {node.value} if isinstance(node.value, str) else None
        if isinstance(node, ast.Name):
            if node.id in self.known:
                return {self.known[node.id]}
            if isinstance(self.literals.get(node.id), str):
                return {self.literals[node.id]}
            bindings = self.loops.get(node.id)
            if not bindings:
                return None
            out: set[str] = set()
            for iterable, position in bindings:
                found = self._items(iterable, position)
                if found is None:
                    return None
                out |= found
            return out
        parts: list[ast.expr]
        if isinstance(node, ast.JoinedStr):
            parts = [p.value if isinstance(p, ast.FormattedValue) else p for p in node.values]
        elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
            parts = [node.left, node.right]
        else:
            return None
        out = {""}
        for part in parts:
            found = self.values(part)
            if found is None:
                return None
            out = {a + b for a in out for b in found}
        return out


def dynamic_imports(
    source: str, module: str, package: str, modules: dict = MODULES
) -> tuple[set[str], list[str]]:
    """Modules of ``modules`` that ``source`` loads by name (``importlib.import_module``,
    ``__import__``), and the calls whose name it cannot tell (line numbers).

    A name read from the source (:class:`_Strings`) gives those modules; a name that is only
    partly known (``f"{__name__}.{name}"`` with ``name`` from ``pkgutil``) counts as loading
    every module under its known prefix, which is what it may do.
    """
    if not any(call in source for call in _IMPORT_CALLS):
        return set(), []  # no such call in the text: none in the tree either
    tree = ast.parse(source)
    strings = _Strings(tree, RUNTIME_NAMES.get(module, module), package)
    parents = {id(child): node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
    found: set[str] = set()
    unknown = []
    for node in ast.walk(tree):
        if not (
            isinstance(node, ast.Call)
            and getattr(node.func, "attr", getattr(node.func, "id", None)) in _IMPORT_CALLS
            and node.args
        ):
            continue
        function = node
        while id(function) in parents and not isinstance(
            function, ast.FunctionDef | ast.AsyncFunctionDef
        ):
            function = parents[id(function)]
        scope = function if isinstance(function, ast.FunctionDef | ast.AsyncFunctionDef) else None
        names = strings.within(scope).values(node.args[0])
        if names is None:
            prefix = _constant_prefix(node.args[0], RUNTIME_NAMES.get(module, module), package)
            if prefix is None:
                unknown.append(f"line {node.lineno}")
                continue
            names = {m for m in modules if m == prefix or m.startswith(prefix + ".")}
            if prefix == "chaplygin":
                names = set(modules)
        found |= {owner for name in names if (owner := _owner(name, modules))}
    return found - {module}, unknown


def imports_of(module: str, modules: dict = MODULES, dynamic: bool = True) -> set[str]:
    """Modules of ``modules`` that ``module`` imports anywhere in its source: ``import`` and
    ``from`` statements (function-level ones included) and, with ``dynamic``, the modules it
    loads by name (:func:`dynamic_imports`)."""
    path, is_package = modules[module]
    package = module if is_package else module.rpartition(".")[0]
    found = set()
    source = path.read_text()
    tree = ast.parse(source, str(path))
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
            target = _from_target(node, package)
            for a in node.names:  # "from . import x" imports the submodule x when there is one
                sub = f"{target}.{a.name}"
                found.add(sub if sub in modules else target)
    out = {owner for name in found if (owner := _owner(name, modules)) and owner != module}
    if dynamic:
        out |= dynamic_imports(source, module, package, modules)[0]
    return out


@functools.cache
def import_graph() -> dict[str, set[str]]:
    """Every module of the package -> the modules it imports (:func:`imports_of`). Read on
    first use, not at import: reading all sources takes seconds, which collecting the tests
    (and ``pytest -m quick``, which runs none of these) would otherwise pay in every process."""
    return {module: imports_of(module) for module in MODULES}


def _layer(module: str) -> int:
    return LAYERS.index(module.split(".")[1])


def test_the_graph_is_read():
    # a control: the parser sees relative, absolute and function-level imports
    graph = import_graph()
    assert "chaplygin.derive.errors" in graph["chaplygin.numerics.ball.separatrix"]
    assert "chaplygin.verify.delta_cmd" in graph["chaplygin.verify.cli"]
    assert "chaplygin.numerics.integrate" in graph["chaplygin.verify.plots"]  # inside a function
    assert "chaplygin.generated" in graph["chaplygin.numerics.code"]  # import_module(f"...")
    # names loaded through importlib: from a dict's values, a tuple, a pkgutil prefix
    assert "chaplygin.verify.outputs.poincare" in graph["chaplygin.verify.scene.registry"]
    assert "chaplygin.derive.chaplygin_ball" in graph["chaplygin.derive.systems"]
    assert "chaplygin.verify.claims.ball" in graph["chaplygin.verify.claims"]
    assert len(MODULES) > 40


def test_every_import_by_name_is_read():
    """Every ``import_module``/``__import__`` of the package names modules the reader can
    tell (or a prefix it counts whole): none is left out of the graph."""
    unknown = {}
    for m, (path, is_package) in MODULES.items():
        package = m if is_package else m.rpartition(".")[0]
        if missing := dynamic_imports(path.read_text(), m, package)[1]:
            unknown[m] = missing
    assert unknown == {}


def test_no_lower_layer_imports_a_higher_one():
    graph = import_graph()
    bad = sorted(
        f"{m} imports {d}" for m, deps in graph.items() for d in deps if _layer(d) > _layer(m)
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
    assert strongly_connected(import_graph()) == []


# ------------------------------------------------------------------------ scene outputs

#: The scene package, and the one module of it that outputs may import.
SCENE = "chaplygin.verify.scene"
SCENE_INTERFACE = "chaplygin.verify.scene.outputs"


def _public_names(module: str, modules: dict = MODULES) -> set[str]:
    """The ``__all__`` of ``module``, read from its source."""
    tree = ast.parse(modules[module][0].read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets
        ):
            return set(ast.literal_eval(node.value))
    return set()


def scene_imports(module: str, modules: dict = MODULES, scene: str = SCENE) -> list[tuple]:
    """``(line, module imported, name or None)`` for every import of ``module`` that reaches the
    scene package (annotation-only ones included)."""
    path, is_package = modules[module]
    package = module if is_package else module.rpartition(".")[0]
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name, None) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            target = _from_target(node, package)
            for a in node.names:
                sub = f"{target}.{a.name}"
                out.append((node.lineno, sub, None) if sub in modules else (
                    node.lineno, target, a.name))
    return [i for i in out if i[1] == scene or i[1].startswith(scene + ".")]


def interface_violations(
    module: str, modules: dict = MODULES, scene: str = SCENE, interface: str = SCENE_INTERFACE
) -> list[str]:
    """Imports of ``module`` that reach the scene package other than public names of its
    interface for outputs."""
    public = _public_names(interface, modules) if interface in modules else set()
    return [
        f"line {line}: {target}" + (f".{name}" if name else "")
        for line, target, name in scene_imports(module, modules, scene)
        if target != interface or name is None or name not in public
    ]


def output_modules() -> list[str]:
    """The scene's output modules: ``verify/outputs/`` and every analysis the registry names."""
    from chaplygin.verify.scene.registry import ANALYSIS_MODULES

    named = set(ANALYSIS_MODULES.values())
    assert named <= set(MODULES)  # the registry names modules that exist
    return sorted(named | {m for m in MODULES if m.startswith("chaplygin.verify.outputs.")})


def test_outputs_import_only_the_scene_interface():
    """Output modules import of the scene package only the public names of
    ``chaplygin.verify.scene.outputs`` (which reaches no output: no cycle)."""
    outputs = output_modules()
    assert {"chaplygin.verify.outputs.poincare", "chaplygin.verify.outputs.lyapunov"} <= set(
        outputs
    )
    bad = {m: hits for m in outputs if (hits := interface_violations(m))}
    assert bad == {}
    # a control on the real code: the analyses do use the interface
    assert scene_imports("chaplygin.verify.outputs.poincare")


def test_no_module_imports_a_private_name_of_the_scene():
    """Outside the scene package no module imports a ``_name`` of it."""
    bad = {
        m: hits
        for m in MODULES
        if not (m == SCENE or m.startswith(SCENE + "."))
        and (hits := [i for i in scene_imports(m) if i[2] and i[2].startswith("_")])
    }
    assert bad == {}


#: The shape of the scene before issue 23: the scene imports the analyses' registry, which
#: loads the analyses by name, and an analysis imports the scene's private helpers.
OLD_SCENE_LOOP = {
    "scene": "from .analyses import requested\n"
    "class SceneError(ValueError):\n    pass\n"
    "def _dotted(loc):\n    return '.'.join(loc)\n",
    "analyses": "import importlib\n"
    'ANALYSIS_MODULES = ("poincare_output", "lyapunov_output")\n'
    "def analyses():\n"
    "    for name in ANALYSIS_MODULES:\n"
    '        importlib.import_module(f"{__package__}.{name}")\n'
    "def requested(outputs):\n    return analyses()\n",
    "poincare_output": "from .scene import SceneError, _dotted\n",
    "lyapunov_output": "from .scene import SceneError\n",
}


def test_the_checks_catch_the_old_scene_loop(tmp_path):
    """A negative control: on a copy of the old shape the cycle through ``importlib`` is
    found (and only through it: without the imports by name there is none), and the
    analyses' imports of the scene are refused."""
    root = tmp_path / "verify"
    root.mkdir()
    (root / "__init__.py").write_text("")
    fake = {"chaplygin.verify": (root / "__init__.py", True)}
    for name, source in OLD_SCENE_LOOP.items():
        (root / f"{name}.py").write_text(source)
        fake[f"chaplygin.verify.{name}"] = (root / f"{name}.py", False)
    graph = {m: imports_of(m, fake) for m in fake}
    loop = ["chaplygin.verify.analyses", "chaplygin.verify.lyapunov_output",
            "chaplygin.verify.poincare_output", "chaplygin.verify.scene"]
    assert strongly_connected(graph) == [loop]
    static = {m: imports_of(m, fake, dynamic=False) for m in fake}
    assert strongly_connected(static) == []
    scene = "chaplygin.verify.scene"
    interface = "chaplygin.verify.scene_outputs"  # absent here: nothing of the scene is public
    assert interface_violations("chaplygin.verify.poincare_output", fake, scene, interface) == [
        "line 1: chaplygin.verify.scene.SceneError", "line 1: chaplygin.verify.scene._dotted"
    ]
    assert [i for i in scene_imports("chaplygin.verify.poincare_output", fake, scene)
            if i[2].startswith("_")] == [(1, scene, "_dotted")]


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


# ------------------------------------------------------------------------ the one door

#: What only ``numerics/integrators/`` may reach: module -> names (scipy's and mpmath's ODE
#: solvers, and the entry points of the generated Taylor engine).
SOLVERS: dict[str, frozenset[str]] = {
    "scipy.integrate": frozenset(
        {"solve_ivp", "RK23", "RK45", "DOP853", "LSODA", "Radau", "BDF", "odeint", "ode",
         "OdeSolver"}
    ),
    "mpmath": frozenset({"odefun"}),
    "mpmath.mp": frozenset({"odefun"}),
    "mpmath.fp": frozenset({"odefun"}),
    "mpmath.calculus.odes": frozenset({"odefun", "ode_taylor"}),
    "chaplygin.numerics.taylor": frozenset(
        {"taylor_solve", "taylor_dense", "CompiledTaylorRun", "load_taylor_library",
         "load_taylor_mpfr_library"}
    ),
    # the same entry points in the engine's modules that define them
    "chaplygin.numerics.taylor.solve": frozenset({"taylor_solve"}),
    "chaplygin.numerics.taylor.dense": frozenset({"taylor_dense"}),
    "chaplygin.numerics.taylor.c_run": frozenset({"CompiledTaylorRun"}),
    "chaplygin.numerics.taylor.library": frozenset(
        {"load_taylor_library", "load_taylor_mpfr_library"}
    ),
}
#: Modules of solvers: loading one by name (``importlib``) outside the door is refused too.
SOLVER_MODULES = ("scipy.integrate", "mpmath.calculus.odes")


def _import_call_target(node: ast.AST) -> str | None:
    """The module named by ``importlib.import_module("...")`` or ``__import__("...")``."""
    if not (isinstance(node, ast.Call) and node.args):
        return None
    name = getattr(node.func, "attr", getattr(node.func, "id", None))
    arg = node.args[0]
    if name in _IMPORT_CALLS and isinstance(arg, ast.Constant) and isinstance(arg.value, str):
        return arg.value
    return None


def _aliases(tree: ast.AST, package: str) -> dict[str, str]:
    """Names bound to modules or module attributes anywhere in the source (function bodies
    included; no scoping: a conservative reading)."""
    bound: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                top = a.name.split(".")[0]
                bound[a.asname or top] = a.name if a.asname else top
        elif isinstance(node, ast.ImportFrom):
            base = _from_target(node, package)
            for a in node.names:
                bound[a.asname or a.name] = f"{base}.{a.name}"
        elif isinstance(node, ast.Assign) and (target := _import_call_target(node.value)):
            for t in node.targets:
                if isinstance(t, ast.Name):
                    bound[t.id] = target
    return bound


def _dotted(node: ast.AST, bound: dict[str, str]) -> str | None:
    """``a.b.c`` of an attribute chain, its root resolved through the aliases (or an
    ``import_module`` call)."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if isinstance(node, ast.Name):
        root = bound.get(node.id, node.id)
    else:
        root = _import_call_target(node)
        if root is None:
            return None
    return ".".join([root, *reversed(parts)])


def _is_solver(dotted: str) -> bool:
    module, _, name = dotted.rpartition(".")
    return name in SOLVERS.get(module, ())


def solver_uses(source: str, package: str) -> list[str]:
    """Where ``source`` (a module of ``package``) reaches a solver: ``from`` imports of one
    (or ``*`` from a solver module), attribute access through a module alias or an
    ``import_module`` call, ``getattr`` by name, and loading a solver module by name."""
    tree = ast.parse(source)
    bound = _aliases(tree, package)
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = _from_target(node, package)
            for a in node.names:
                if _is_solver(f"{base}.{a.name}") or (a.name == "*" and base in SOLVERS):
                    found.append(f"line {node.lineno}: from {base} import {a.name}")
        elif isinstance(node, ast.Attribute):
            dotted = _dotted(node, bound)
            if dotted and _is_solver(dotted):
                found.append(f"line {node.lineno}: {dotted}")
        elif isinstance(node, ast.Call):
            target = _import_call_target(node)
            if target and target.startswith(SOLVER_MODULES):
                found.append(f"line {node.lineno}: loads {target} by name")
            if (
                getattr(node.func, "id", None) == "getattr"
                and len(node.args) >= 2
                and isinstance(node.args[1], ast.Constant)
                and (dotted := _dotted(node.args[0], bound))
                and _is_solver(f"{dotted}.{node.args[1].value}")
            ):
                found.append(f"line {node.lineno}: getattr({dotted}, {node.args[1].value!r})")
    return found


def _module_solver_uses(module: str) -> list[str]:
    path, is_package = MODULES[module]
    package = module if is_package else module.rpartition(".")[0]
    return solver_uses(path.read_text(), package)


def test_only_the_integrators_reach_a_solver():
    """Every integration goes through an Integrator: no module outside
    ``numerics/integrators/`` imports or reaches scipy's or mpmath's ODE solvers or the
    Taylor engine's entry points, at module level, inside a function or through
    ``importlib`` (the engine's own modules, ``numerics/taylor/``, hand them to each other)."""
    door, engine = "chaplygin.numerics.integrators", "chaplygin.numerics.taylor"
    bad = {
        m: hits
        for m in MODULES
        if not any(m == d or m.startswith(d + ".") for d in (door, engine))
        and (hits := _module_solver_uses(m))
    }
    assert bad == {}
    # a control on the real code: the door's own modules do reach them
    assert _module_solver_uses("chaplygin.numerics.integrators.scipy_methods")
    assert _module_solver_uses("chaplygin.numerics.integrators.odefun")
    assert _module_solver_uses("chaplygin.numerics.integrators.taylor_method")


def test_the_solver_check_sees_every_way_in():
    """A negative control: each way of reaching a solver is found once, and neighbours that
    are not solvers (a quadrature of scipy.integrate, mpmath.quad) are not."""
    forms = [
        "from scipy.integrate import solve_ivp",
        "def f():\n    from scipy.integrate import RK45 as R",
        "import scipy.integrate as si\nsi.DOP853",
        "from scipy import integrate\nintegrate.LSODA",
        "import scipy.integrate\nscipy.integrate.Radau",
        "import importlib\nimportlib.import_module('mpmath').odefun",
        "import importlib\nm = importlib.import_module('mpmath')\nm.odefun",
        "import mpmath\nmpmath.odefun",
        "from mpmath import mp\nmp.odefun",
        "import mpmath\ngetattr(mpmath, 'odefun')",
        "from mpmath import *",
        "import importlib\nimportlib.import_module('scipy.integrate')",
        "__import__('mpmath.calculus.odes')",
        "from .taylor import taylor_solve",
        "def g():\n    from ..numerics import taylor\n    taylor.taylor_dense",
        "from .taylor.solve import taylor_solve",
        "from .taylor import library\nlibrary.load_taylor_library",
    ]
    for form in forms:
        assert len(solver_uses(form, "chaplygin.numerics")) == 1, form
    quiet = "from scipy.integrate import cumulative_simpson\nimport mpmath\nmpmath.quad\n"
    assert solver_uses(quiet + "from .taylor import TaylorDense", "chaplygin.numerics") == []


# ------------------------------------------------------------------------ the precision row

_PRECISION_ATTRIBUTES = ("prec", "dps")
_CONTEXT_MANAGERS = ("workprec", "workdps", "extraprec", "extradps")


def _is_mpmath_context(node: ast.AST, bound: dict[str, str]) -> bool:
    dotted = _dotted(node, bound)
    return dotted in ("mpmath", "mpmath.mp", "mpmath.fp", "mpmath.iv")


def _inside_local_context(node: ast.AST, parents: dict[int, ast.AST]) -> bool:
    """Whether ``node`` is in the body of a ``with`` over mpmath's local precision."""
    while id(node) in parents:
        node = parents[id(node)]
        if isinstance(node, ast.With | ast.AsyncWith):
            for item in node.items:
                call = item.context_expr
                name = getattr(getattr(call, "func", None), "attr", None) or getattr(
                    getattr(call, "func", None), "id", None
                )
                if name in _CONTEXT_MANAGERS:
                    return True
    return False


def precision_assignments(source: str, package: str) -> list[str]:
    """Assignments of mpmath's working precision (``mp.prec``, ``mp.dps``: plain, augmented,
    annotated, in tuples, by ``setattr``) outside a ``with mpmath.workprec/workdps/
    extraprec/extradps(...)`` block: precision passed through the ambient context."""
    tree = ast.parse(source)
    bound = _aliases(tree, package)
    parents = {id(child): node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
    found = []
    for node in ast.walk(tree):
        targets: list[ast.AST] = []
        if isinstance(node, ast.Assign):
            targets = list(node.targets)
        elif isinstance(node, ast.AugAssign | ast.AnnAssign):
            targets = [node.target]
        elif (
            isinstance(node, ast.Call)
            and getattr(node.func, "id", None) == "setattr"
            and len(node.args) == 3
            and isinstance(node.args[1], ast.Constant)
            and node.args[1].value in _PRECISION_ATTRIBUTES
            and _is_mpmath_context(node.args[0], bound)
            and not _inside_local_context(node, parents)
        ):
            found.append(f"line {node.lineno}: setattr(..., {node.args[1].value!r})")
        expanded = []
        for target in targets:
            expanded += target.elts if isinstance(target, ast.Tuple | ast.List) else [target]
        for target in expanded:
            if (
                isinstance(target, ast.Attribute)
                and target.attr in _PRECISION_ATTRIBUTES
                and _is_mpmath_context(target.value, bound)
                and not _inside_local_context(node, parents)
            ):
                found.append(f"line {node.lineno}: {ast.unparse(target)} assigned")
    return found


def test_no_module_passes_precision_through_mpmath_mp():
    """A precision is passed explicitly (a Precision, entered with its context): no module
    sets ``mpmath.mp.prec``/``dps`` outside a ``workprec``/``workdps`` block."""
    bad = {}
    for m, (path, is_package) in MODULES.items():
        package = m if is_package else m.rpartition(".")[0]
        if hits := precision_assignments(path.read_text(), package):
            bad[m] = hits
    assert bad == {}


def test_the_precision_check_sees_every_assignment():
    """A negative control: each way of setting the ambient precision is found; the same
    assignment inside a workdps block, and other objects' ``prec``, are not."""
    forms = [
        "import mpmath\nmpmath.mp.prec = 100",
        "from mpmath import mp\nmp.dps = 30",
        "import mpmath as m\ndef f():\n    m.mp.prec += 5",
        "import mpmath\nmpmath.mp.dps: int = 40",
        "import mpmath\nsetattr(mpmath.mp, 'dps', 40)",
        "from mpmath import mp\nmp.prec, x = 80, 1",
        "import mpmath\nwith open('f'):\n    mpmath.mp.prec = 70",
    ]
    for form in forms:
        assert len(precision_assignments(form, "chaplygin.numerics")) == 1, form
    quiet = (
        "import mpmath\nfrom mpmath import mp\n"
        "with mpmath.workdps(30):\n    mpmath.mp.dps = 40\n"
        "with mp.workprec(90), open('f'):\n    mp.prec += 3\n"
        "self.prec = 5\nctx.dps = 3\n"
    )
    assert precision_assignments(quiet, "chaplygin.numerics") == []


# ------------------------------------------------------------------------ C in one layer

#: The only package that writes C (templates, printers, the sources numerics compiles).
C_WRITERS = "chaplygin.derive.emit"

#: What C text looks like in a string (a literal, a regular expression's pattern or its
#: replacement): a preprocessor line, a function body opening, a declaration of a C number
#: type, the Taylor template's macros and recurrences. cffi's declarations (strings given to
#: ``cdef``, or named ``*CDEF``) are the loader's and are not C that is compiled.
_C_TEXT = re.compile(
    r"^\s*#\s*(?:include|define|undef|ifn?def|if|elif|else|endif|pragma)\b"
    r"|\)\s*\{\s*$"
    r"|\bconst\s+(?:double|float|int|long|REAL|vreal|bm_vec)\b"
    r"|\b(?:static|void|double|REAL|vreal|bm_vec)\s+\**\w+\s*(?:\[[^\]]*\])?\s*="
    r"|\b(?:R_[A-Z]+|tc_[a-z]+|chaplygin_(?:sin|cos|exp|log|pow))\s*\(",
    re.MULTILINE,
)

#: What edits text: methods of str and of compiled regular expressions, and the re functions.
_TEXT_EDITS = frozenset(
    {"replace", "join", "format", "find", "rfind", "index", "rindex", "split", "rsplit",
     "splitlines", "partition", "rpartition", "strip", "lstrip", "rstrip", "removeprefix",
     "removesuffix", "sub", "subn", "findall", "finditer", "search", "match", "fullmatch",
     "translate", "expandtabs"}
)  # fmt: skip


def _plain(text: str) -> str:
    """A regular expression's text as the C it matches, roughly (``\\b``, ``\\s`` ... a
    space, other escapes their character)."""
    return re.sub(r"\\[bBsSdDwW]", " ", text).replace("\\", "")


def _is_c_source_value(node: ast.AST) -> bool:
    """A name or attribute that holds C source by the project's naming: a name ending in
    ``source`` (``source``, ``c_source``, ``FASTCALL_SOURCE``), an attribute ending in
    ``_source`` (``code.c_source``, ``code.taylor_c_source``; not a scene's ``source``, its
    file)."""
    if isinstance(node, ast.Name):
        return node.id.lower().endswith("source")
    return isinstance(node, ast.Attribute) and node.attr.lower().endswith("_source")


def c_text_uses(source: str) -> list[str]:
    """Where a module's source writes or edits C: C in a string that is not a docstring or
    a cffi declaration, and C source put together or taken apart (``+``, ``%``, an f-string,
    a str or re method) -- anything beyond passing it on.

    Parameters
    ----------
    source : str
        A module's Python text.

    Returns
    -------
    list of str
        ``"line N: ..."`` per finding.
    """
    tree = ast.parse(source)
    skip: set[int] = set()
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) \
                and isinstance(body[0].value, ast.Constant):
            skip.add(id(body[0].value))  # a docstring
        if isinstance(node, ast.Assign) and any(
            "CDEF" in getattr(t, "id", "").upper() for t in node.targets
        ):
            skip.update(id(n) for n in ast.walk(node.value))
        if isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "cdef":
            skip.update(id(n) for a in node.args for n in ast.walk(a))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) \
                and id(node) not in skip and _C_TEXT.search(_plain(node.value)):
            found.append(f"line {node.lineno}: C text {node.value[:40]!r}")
        operands: list[ast.AST] = []
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add | ast.Mod):
            operands = [node.left, node.right]
        elif isinstance(node, ast.JoinedStr):
            operands = [v.value for v in node.values if isinstance(v, ast.FormattedValue)]
        elif isinstance(node, ast.Subscript):
            operands = [node.value]
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", "") in _TEXT_EDITS:
            operands = [node.func.value, *node.args]
            operands += [e for a in node.args if isinstance(a, ast.Tuple | ast.List)
                         for e in a.elts]
        if any(_is_c_source_value(o) for o in operands):
            found.append(f"line {node.lineno}: C source edited: {ast.unparse(node)[:60]}")
    return found


def test_only_the_emitters_write_c():
    """Every C source is written in ``derive/emit`` (issue 23, deliverable 3): no other module
    holds C text (a template, a pattern or a replacement of a regular expression over C) or
    puts C source together or takes it apart; numerics compiles and loads what the emitters
    return."""
    bad = {
        m: hits
        for m, (path, _) in MODULES.items()
        if not m.startswith(C_WRITERS) and (hits := c_text_uses(path.read_text()))
    }
    assert bad == {}


def test_the_c_check_sees_every_way_of_writing_c():
    """A negative control, from the code before the emitters took it over: each way of
    writing C outside the emitters is found; passing a source on, cffi declarations and
    docstrings that show C are not."""
    forms = [
        'QUAD = "#define CHAPLYGIN_TAYLOR_QUAD 1\\n"',  # a define prepended to a source
        'SHIM = r"""\nstatic void many(int m)\n{\n    f(m);\n}\n"""',  # a C function
        "def f(code, t):\n    return compile_c(code.c_source + '\\n' + t.read_text())",
        "def f(source):\n    return source.replace(MARKER, inserted, 1)",
        "def f(body):\n    return re.sub(r'\\bconst double\\b', 'const bm_vec', body)",
        "_MUL = re.compile(r'tc_mul\\(a(\\d+), a(\\d+), k\\)')",
        "def f(c_source):\n    return c_source[c_source.index('{'):]",
        "def f(code):\n    return '\\n'.join((code.c_source, 'x'))",
        "def f(code):\n    return f'{code.taylor_c_source}'",
        "def f(source):\n    return PATTERN.sub(lambda m: header, source)",
    ]
    for form in forms:
        assert c_text_uses(form), form
    quiet = (
        '"""Compiles ``#include "detmath.h"`` sources: ``const double x = 1;``."""\n'
        '_CDEF = """\nvoid chaplygin_rhs(double T, const double *Y, double *OUT);\n"""\n'
        'ffi.cdef("int f(const double *x);")\n'
        "def f(code):\n    return compile_c(taylor_source(code.taylor_c_source, 'quad'))\n"
        "def g(code):\n    return len(code.c_source), hashlib.sha256(code.c_source.encode())\n"
    )
    assert c_text_uses(quiet) == []


# ---------------------------------------------------------------- rooms inside numerics
#: The engine (integration, code loading, precision, inputs) and the generic dynamics: no
#: module here names a state variable of a particular system, and none imports the ball's
#: studies (``numerics/ball/``), which sit above them.
ENGINE_PREFIXES = ("chaplygin.numerics.dynamics", "chaplygin.numerics.taylor")
BALL_ROOM = "chaplygin.numerics.ball"

#: ``x`` and ``y`` are also the generic names of the state in ``y' = f(t, y)`` and of the
#: compiled routines' arguments (the surface's ``x`` and the contact point's ``y`` are
#: state groups too): they are left out of the names searched for.
GENERIC_NAMES = {"x", "y"}


def engine_modules(modules: dict = MODULES) -> list[str]:
    """The engine's and the generic dynamics' modules."""
    return sorted(
        m
        for m in modules
        if m.startswith("chaplygin.numerics")
        and not m.startswith(BALL_ROOM)
        and (m.count(".") == 2 or m.startswith(("chaplygin.numerics.integrators",
                                                 *ENGINE_PREFIXES)))
    )  # fmt: skip


def state_variable_names() -> set[str]:
    """Every state variable and state group of the built-in models (from ``generated/``)."""
    import importlib

    names: set[str] = set()
    for path in _package_dir("generated").glob("*_numpy.py"):
        gen = importlib.import_module(f"chaplygin.generated.{path.stem}")
        names |= set(gen.STATE) | {group for group, _ in gen.STATE_GROUPS}
    return names - GENERIC_NAMES


def state_names_in(source: str, names: set[str]) -> list[str]:
    """String constants of ``source`` (docstrings left out) that are one of ``names``, or
    that index such a name by a number (``f"M{i}"``)."""
    tree = ast.parse(source)
    docstrings = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            if id(node) not in docstrings and node.value in names:
                found.append(f"line {node.lineno}: {node.value!r}")
        elif isinstance(node, ast.JoinedStr) and len(node.values) == 2:
            head, tail = node.values
            if isinstance(head, ast.Constant) and isinstance(tail, ast.FormattedValue) \
                    and f"{head.value}1" in names:
                found.append(f"line {node.lineno}: {ast.unparse(node)}")
    return found


def test_the_engine_names_no_state_variable():
    """Issue 23, deliverable 5: the engine and the generic dynamics read a model's state,
    groups and geometry from the model; only the systems' own rooms name ``M``, ``gamma`` ..."""
    names = state_variable_names()
    assert {"M", "M1", "gamma3", "alpha", "omega2", "x_1"} <= names
    bad = {
        m: hits
        for m in engine_modules()
        if (hits := state_names_in(MODULES[m][0].read_text(), names))
    }
    assert bad == {}
    assert "chaplygin.numerics.integrate" in engine_modules()
    assert "chaplygin.numerics.dynamics.poincare" in engine_modules()
    assert "chaplygin.numerics.taylor.dense" in engine_modules()
    assert "chaplygin.numerics.ball.separatrix" not in engine_modules()


def test_the_state_name_check_sees_the_old_engine():
    """A negative control, from the engine before the rooms: each way it named the ball's
    state is found; docstrings and the generic ``y`` are not."""
    names = state_variable_names()
    forms = [
        'BM20_STATE = ("M1", "M2", "M3", "gamma1", "gamma2", "gamma3")',
        "def f(code):\n    return [code.state.index(f'M{i}') for i in (1, 2, 3)]",
        "def f(got):\n    return got.get('M')",
        "def f(aux, code):\n    return [aux[code.aux_names.index(f'omega{i}')] for i in (1, 2)]",
    ]
    for form in forms:
        assert state_names_in(form, names), form
    quiet = '"""Starts at ``{"M": (1, 2, 3)}``."""\ndef f(y):\n    return y["y"]\n'
    assert state_names_in(quiet, names) == []


def test_the_engine_does_not_import_the_ball_room():
    bad = sorted(
        f"{m} imports {d}"
        for m in engine_modules()
        for d in import_graph()[m]
        if d.startswith(BALL_ROOM)
    )
    assert bad == []
