"""Run-time functions of sympy expressions, printed like the generated models.

:func:`emit_function` is the project's ``lambdify``: the expressions go through the same
common-subexpression elimination (:func:`~chaplygin.derive.emit.base._cse`) and the same
printer (:class:`~chaplygin.derive.emit.NumpyEmitter`,
:class:`~chaplygin.derive.emit.MpmathEmitter`) as the files in ``generated/``; the source is
stamped (generator, sympy and mpmath versions, a hash of the expressions), registered in
:mod:`linecache` (tracebacks show it) and compiled once per process.
"""

from __future__ import annotations

import hashlib
import keyword
import linecache
import types
from collections.abc import Callable, Sequence
from functools import lru_cache

import mpmath
import sympy as sp

from .base import GENERATOR_VERSION, _cse, get_emitter
from .python_common import PythonModuleEmitter

__all__ = ["function_source", "emit_function", "module_from_source"]


def module_from_source(name: str, source: str) -> types.ModuleType:
    """Execute our own emitted Python ``source`` as a module registered in :mod:`linecache`.

    Parameters
    ----------
    name : str
        Module name; the file name is ``<chaplygin-generated name>``.
    source : str
        Text produced by an emitter (never user text).

    Returns
    -------
    module
    """
    filename = f"<chaplygin-generated {name}>"
    linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
    module = types.ModuleType(name)
    module.__file__ = filename
    exec(compile(source, filename, "exec"), module.__dict__)  # our own emitted code
    return module


def _python_emitter(language: str) -> PythonModuleEmitter:
    emitter = get_emitter(language)
    if not isinstance(emitter, PythonModuleEmitter):
        raise ValueError(f"emit_function prints Python (numpy or mpmath), not {language!r}")
    return emitter


_RESERVED = frozenset({"numpy", "mpmath", "math"})


def _argument_names(args: tuple, emitter: PythonModuleEmitter) -> dict:
    """``argument -> symbol`` printed as a valid, distinct Python parameter name."""
    names = {a.name for a in args if isinstance(a, sp.Symbol)}
    out = {}
    for i, a in enumerate(args):
        if (
            isinstance(a, sp.Symbol)
            and a.name.isidentifier()
            and not keyword.iskeyword(a.name)
            and a.name not in _RESERVED
            and emitter._print(a) == a.name
        ):
            out[a] = a
            continue
        name = f"a{i}"
        while name in names:
            name = "_" + name
        names.add(name)
        assumptions = a.assumptions0 if isinstance(a, sp.Symbol) else {}
        out[a] = sp.Symbol(name, **assumptions)
    return out


def _normalise(args: Sequence, exprs) -> tuple[tuple, tuple, bool]:
    """Arguments as a tuple, expressions as a tuple of sympy objects, and whether a single
    expression (not a list) was given."""
    single = isinstance(exprs, sp.Basic) and not isinstance(exprs, sp.MatrixBase)
    items = (exprs,) if single else tuple(exprs)
    return tuple(sp.sympify(a) for a in args), tuple(sp.sympify(e) for e in items), single


def function_source(
    args: Sequence[sp.Basic],
    exprs: sp.Expr | Sequence[sp.Expr],
    language: str = "numpy",
    name: str = "f",
) -> str:
    """Python source of ``name(*args)`` returning the values of ``exprs``.

    Symbols keep their names, so an expression of a model's state and parameters prints
    exactly as in the model's generated module; an argument that is not a symbol
    (``f(t)``) or whose name cannot be a Python parameter becomes ``a<i>`` (a symbol with
    the same assumptions: no expression changes). Common subexpressions become ``x0, x1,
    ...`` and everything is printed by the emitter of ``language``.

    Parameters
    ----------
    args : sequence of sympy symbols or expressions (e.g. ``f(t)``)
    exprs : sympy expression or sequence of them
    language : {"numpy", "mpmath"}
    name : str
        Function name.

    Returns
    -------
    str
        A stamped module defining ``name``: a list of values, or one value when ``exprs`` is
        a single expression.
    """
    emitter = _python_emitter(language)
    args, items, single = _normalise(args, exprs)
    if len(set(args)) != len(args):
        raise ValueError(f"repeated arguments in {args}")
    renamed = _argument_names(args, emitter)
    missing = set().union(*(e.free_symbols for e in items)) - set(args)
    if missing - {s for a in args for s in a.free_symbols}:
        raise ValueError(
            f"the expressions use {sorted(map(str, missing))}, which are not arguments"
        )
    routine = _cse(name, [e.xreplace(renamed) for e in items], (len(items),))
    digest = hashlib.sha256(
        "\n".join([language, *map(sp.srepr, args), *map(sp.srepr, items)]).encode()
    ).hexdigest()
    outputs = [emitter._print(e) for e in routine.outputs]
    result = outputs[0] if single else "[" + ", ".join(outputs) + "]"
    signature = ", ".join(s.name for s in renamed.values())
    lines = [
        f'"""Generated by chaplygin code generator {GENERATOR_VERSION} ({language} function), '
        f"sympy {sp.__version__}, mpmath {mpmath.__version__}.",
        "DO NOT EDIT: emitted at run time by chaplygin.derive.emit.emit_function.",
        f"expressions hash: {digest}",
        f"arguments: {', '.join(map(str, args))}",
        '"""',
        "",
        emitter.module_import,
        "",
        "",
        f"def {name}({signature}):",
        *emitter._temporaries(routine),
        f"    return {result}",
    ]
    return "\n".join(lines) + "\n"


@lru_cache(maxsize=256)
def _compiled(args: tuple, items: tuple, single: bool, language: str, name: str) -> Callable:
    exprs = items[0] if single else items
    source = function_source(args, exprs, language, name)
    digest = source.split("expressions hash: ", 1)[1][:12]
    return getattr(module_from_source(f"{name}_{language}_{digest}", source), name)


def emit_function(
    args: Sequence[sp.Basic],
    exprs: sp.Expr | Sequence[sp.Expr],
    language: str = "numpy",
    name: str = "f",
) -> Callable:
    """A numpy or mpmath function of ``args`` computing ``exprs`` (``sympy.lambdify``'s role).

    Compiled from :func:`function_source` once per process (cached by the expressions).

    Parameters
    ----------
    args : sequence of sympy symbols or expressions
    exprs : sympy expression or sequence of them
    language : {"numpy", "mpmath"}
        ``numpy`` works on floats and arrays; ``mpmath`` at the caller's ``mpmath.mp``
        precision (rational constants are quotients of ``mpf``).
    name : str
        Function name (in tracebacks).

    Returns
    -------
    callable
        ``f(*values)``: a list (one value when ``exprs`` is a single expression).

    Examples
    --------
    >>> x, y = sp.symbols("x y")
    >>> emit_function([x, y], [x + y, x * y])(2.0, 3.0)
    [5.0, 6.0]
    """
    _python_emitter(language)
    return _compiled(*_normalise(args, exprs), language, name)
