"""Expressions of a model's state, read without ``eval``, and the numbers they compute in.

A :class:`StateExpression` (``"M3/sqrt(M1**2 + M2**2 + M3**2)"``, ``"atan2(gamma1, gamma2)"``)
is parsed with :mod:`ast` into a small tree of arithmetic, a few elementary functions and the
model's names, and evaluated on floats (the project's deterministic kernels) or on
``mpmath.mpf`` at the working precision, elementwise on arrays: the coordinates of a Poincaré
map and the surface of a section are such expressions. :func:`wrap_angle` maps angles to
``[-pi, pi)`` in either number type.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import mpmath
import numpy as np

from ...arith import detmath
from ...derive.errors import UserInputError
from ..inputs import MAX_DEPTH, MAX_TEXT, parse_number

__all__ = [
    "NumberOps",
    "StateExpression",
    "is_exact",
    "number_ops",
    "scalar_or_array",
    "wrap_angle",
]


class NumberOps:
    """Elementary functions for one number type (numpy or mpmath, elementwise).

    Parameters
    ----------
    exact : bool
        mpmath (object arrays of ``mpf``) rather than float64.
    """

    def __init__(self, exact: bool):
        if exact:
            self.sqrt = np.frompyfunc(mpmath.sqrt, 1, 1)
            self.sin = np.frompyfunc(mpmath.sin, 1, 1)
            self.cos = np.frompyfunc(mpmath.cos, 1, 1)
            self.atan2 = np.frompyfunc(mpmath.atan2, 2, 1)
            self.exp = np.frompyfunc(mpmath.exp, 1, 1)
            self.log = np.frompyfunc(mpmath.log, 1, 1)
            self.pi = +mpmath.pi
            self.zero = mpmath.mpf(0)
        else:
            # the project's kernels, not numpy's processor-dispatched ones: the same bits anywhere
            self.sqrt, self.sin, self.cos = np.sqrt, detmath.sin, detmath.cos
            self.atan2, self.exp, self.log = detmath.atan2, detmath.exp, detmath.log
            self.pi = math.pi
            self.zero = 0.0


def is_exact(*values: Any) -> bool:
    """Whether any value is an ``mpmath.mpf`` or an object array (of them).

    Parameters
    ----------
    *values : number or array

    Returns
    -------
    bool
    """
    for v in values:
        a = np.asarray(v)
        if a.dtype == object or isinstance(v, mpmath.mpf):
            return True
    return False


def scalar_or_array(value: Any) -> Any:
    """A 0-d array back to its scalar; arrays unchanged.

    Parameters
    ----------
    value : number or array

    Returns
    -------
    number or ndarray
    """
    a = np.asarray(value)
    return a.item() if a.ndim == 0 else a


def number_ops(*values: Any) -> NumberOps:
    """The elementary functions for the values' number type.

    Parameters
    ----------
    *values : number or array

    Returns
    -------
    NumberOps
    """
    return NumberOps(is_exact(*values))


def wrap_angle(angle: Any) -> Any:
    """An angle (or array of them) mapped to ``[-pi, pi)``.

    Parameters
    ----------
    angle : number or array
        Radians; float, ``mpmath.mpf`` or arrays of either.

    Returns
    -------
    number or ndarray
        The same type, in ``[-pi, pi)``.
    """
    ops = number_ops(angle)
    a = np.asarray(angle)
    two_pi = 2 * ops.pi
    if a.dtype == object:
        w = np.frompyfunc(lambda x: x - two_pi * mpmath.floor((x + ops.pi) / two_pi), 1, 1)(a)
    else:
        w = a - two_pi * np.floor((a + ops.pi) / two_pi)
        w = np.where(w >= ops.pi, w - two_pi, w)
    return scalar_or_array(w)


_BINARY: dict[type, Callable[[Any, Any], Any]] = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.Pow: lambda a, b: a**b,
}
_FUNCTIONS = {"sqrt": 1, "sin": 1, "cos": 1, "exp": 1, "log": 1, "atan2": 2, "abs": 1}
_CONSTANTS = ("pi",)


@dataclass(frozen=True)
class StateExpression:
    """An expression of the state and auxiliary quantities, parsed safely (no ``eval``).

    ``M3/sqrt(M1**2 + M2**2 + M3**2)``, ``atan2(gamma1, gamma2)``, ``omega1``: names are the
    model's state components and whatever else the caller allows (auxiliary quantities,
    integrals); ``+ - * / **``, numbers (read by the project's number parser), ``pi`` and the
    functions ``sqrt sin cos exp log abs atan2``. The text is parsed by :mod:`ast` and the tree
    checked node by node; evaluation walks the tree itself.

    Parameters
    ----------
    text : str
    names : sequence of str
        The names the expression may use.

    Raises
    ------
    UserInputError
        Malformed text, an unknown name (the message lists the valid ones) or function, or
        syntax other than the above.
    """

    text: str
    names: tuple[str, ...]

    def __post_init__(self) -> None:
        if not isinstance(self.text, str) or not self.text.strip():
            raise UserInputError("a map coordinate must be a non-empty expression of the state")
        if len(self.text) > MAX_TEXT:
            raise UserInputError(f"the expression {self.text[:40]!r}... is too long")
        try:
            tree = ast.parse(self.text.strip(), mode="eval")
        except SyntaxError:
            raise UserInputError(
                f"cannot read {self.text!r} as an expression of the state"
            ) from None
        depth, stack = 0, [(tree, 0)]
        while stack:
            node, d = stack.pop()
            depth = max(depth, d)
            stack.extend((child, d + 1) for child in ast.iter_child_nodes(node))
        if depth > MAX_DEPTH:
            raise UserInputError(f"the expression {self.text!r} is nested too deeply")
        self._check(tree.body)
        object.__setattr__(self, "_tree", tree.body)

    def _check(self, node: ast.AST) -> None:
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, int | float):
                raise UserInputError(f"{self.text!r}: only numbers may appear as constants")
            return
        if isinstance(node, ast.Name):
            if node.id not in self.names and node.id not in _CONSTANTS:
                import difflib

                near = difflib.get_close_matches(node.id, self.names, n=1)
                hint = f" (did you mean {near[0]!r}?)" if near else ""
                raise UserInputError(
                    f"{self.text!r}: unknown name {node.id!r}; valid: "
                    f"{', '.join(self.names)}, pi{hint}"
                )
            return
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            self._check(node.left)
            self._check(node.right)
            return
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.UAdd | ast.USub):
            self._check(node.operand)
            return
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in _FUNCTIONS
            and not node.keywords
            and len(node.args) == _FUNCTIONS[node.func.id]
        ):
            for a in node.args:
                self._check(a)
            return
        raise UserInputError(
            f"{self.text!r}: unsupported syntax (use names, numbers, pi, + - * / **, "
            f"{', '.join(_FUNCTIONS)})"
        )

    def evaluate(self, values: Mapping[str, Any]) -> Any:
        """The expression's value.

        Parameters
        ----------
        values : mapping of str to number or array
            A value (or array of values, all of one shape) for every name used.

        Returns
        -------
        number or ndarray
            In the values' number type (float64 or mpmath.mpf).
        """
        ops = number_ops(*values.values())
        dps = mpmath.mp.dps if ops.zero.__class__ is mpmath.mpf else 17
        return scalar_or_array(self._eval(self._tree, values, ops, dps))  # type: ignore[attr-defined]

    def _eval(self, node: ast.AST, values: Mapping[str, Any], ops: NumberOps, dps: int) -> Any:
        if isinstance(node, ast.Constant):
            text = ast.get_source_segment(self.text.strip(), node) or repr(node.value)
            v = parse_number(text, dps + 5)
            return v if isinstance(ops.zero, mpmath.mpf) else float(v)
        if isinstance(node, ast.Name):
            return ops.pi if node.id == "pi" else np.asarray(values[node.id])
        if isinstance(node, ast.BinOp):
            a = self._eval(node.left, values, ops, dps)
            b = self._eval(node.right, values, ops, dps)
            return _BINARY[type(node.op)](a, b)
        if isinstance(node, ast.UnaryOp):
            v = self._eval(node.operand, values, ops, dps)
            return -v if isinstance(node.op, ast.USub) else v
        assert isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
        args = [self._eval(a, values, ops, dps) for a in node.args]
        name = node.func.id
        if name == "abs":
            return abs(args[0])
        return getattr(ops, name)(*args)
