"""Expressions a user types (a potential, an inertia entry), read without ``eval``.

A text is parsed by Python's :mod:`ast` (parsing runs no code) and only a small set of
nodes is turned into sympy: numbers, the names the caller allows, ``+ - * / **``,
unary signs, parentheses and calls of a few elementary functions. A decimal number is
read exactly as typed (``0.1`` is ``1/10``), so what a user types keeps its precision.
Anything else — attributes, subscripts, lambdas, comprehensions, unknown names — is
refused with a :class:`~.errors.UserInputError` naming what is allowed.
"""

from __future__ import annotations

import ast
from collections.abc import Mapping

import sympy as sp

from .errors import UserInputError

__all__ = ["FUNCTIONS", "parse_expression", "exact_number"]

#: Elementary functions a typed expression may call.
FUNCTIONS = {
    "sin": sp.sin,
    "cos": sp.cos,
    "tan": sp.tan,
    "exp": sp.exp,
    "log": sp.log,
    "sqrt": sp.sqrt,
    "sinh": sp.sinh,
    "cosh": sp.cosh,
    "tanh": sp.tanh,
    "atan": sp.atan,
}

#: Longest text accepted (a description, not a program).
MAX_LENGTH = 2000

#: Largest numeric exponent (``10**10**10`` would exhaust the machine).
MAX_EXPONENT = 64

_BINARY = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.Pow: lambda a, b: a**b,
}


def exact_number(value: object, what: str) -> sp.Expr:
    """A number as an exact sympy number: integers and decimals exactly as written.

    Parameters
    ----------
    value : int, float, str or sympy number
        A float is read through its shortest decimal form (``0.1`` -> ``1/10``).
    what : str
        What the number is, for the message.

    Returns
    -------
    sympy.Expr

    Raises
    ------
    UserInputError
        For booleans, non-finite floats and anything not a number.
    """
    if isinstance(value, bool):
        raise UserInputError(f"{what}: expected a number, got {value!r}")
    if isinstance(value, int):
        return sp.Integer(value)
    if isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise UserInputError(f"{what}: expected a finite number, got {value!r}")
        return sp.Rational(repr(value))
    if isinstance(value, sp.Basic) and value.is_number:
        return value
    raise UserInputError(f"{what}: expected a number, got {value!r}")


def parse_expression(
    text: object, names: Mapping[str, sp.Expr], what: str, free_names: bool = False
) -> sp.Expr:
    """Read a typed expression into sympy without evaluating any code.

    Parameters
    ----------
    text : str, number or sympy expression
        A number is returned exactly (:func:`exact_number`); a sympy expression is
        checked for its symbols.
    names : mapping of str to sympy.Expr
        The names the expression may use and what they stand for.
    what : str
        What the expression is, for the messages (``"potential"``).
    free_names : bool
        Let a name that is not in ``names`` (nor a function) become a new real symbol:
        a parameter of the description.

    Returns
    -------
    sympy.Expr

    Raises
    ------
    UserInputError
        For a syntax error, a construct other than arithmetic and the functions of
        :data:`FUNCTIONS`, an unknown name, a text longer than :data:`MAX_LENGTH`.
    """
    if isinstance(text, sp.Basic) and not text.is_number:
        if not isinstance(text, sp.Expr) or text.atoms(sp.Function) - text.atoms(
            *(f for f in FUNCTIONS.values() if isinstance(f, type))
        ):
            raise UserInputError(f"{what}: expected an expression of numbers and names")
        unknown = sorted(
            s.name for s in text.free_symbols if s.name not in names and not free_names
        )
        if unknown:
            raise UserInputError(f"{what}: unknown names {unknown}; allowed: {_allowed(names)}")
        # the caller's symbols (their assumptions) replace those of the same name
        return text.xreplace({s: names[s.name] for s in text.free_symbols if s.name in names})
    if not isinstance(text, str):
        return exact_number(text, what)
    if len(text) > MAX_LENGTH:
        raise UserInputError(f"{what}: an expression of {len(text)} characters is too long")
    source = text.strip()
    try:
        tree = ast.parse(source, mode="eval")
    except SyntaxError as err:
        raise UserInputError(f"{what}: cannot read {text!r} ({err.msg})") from None
    return _Reader(source, names, what, free_names).read(tree.body)


def _allowed(names: Mapping[str, sp.Expr]) -> str:
    return ", ".join([*sorted(names), *(f"{f}()" for f in FUNCTIONS)]) or "numbers only"


class _Reader:
    def __init__(
        self, source: str, names: Mapping[str, sp.Expr], what: str, free_names: bool
    ) -> None:
        self.source, self.names, self.what, self.free_names = source, names, what, free_names

    def refuse(self, part: str) -> UserInputError:
        return UserInputError(
            f"{self.what}: {part} is not allowed (arithmetic of numbers and "
            f"{_allowed(self.names)} only)"
        )

    def read(self, node: ast.AST) -> sp.Expr:
        if isinstance(node, ast.Constant):
            if isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
                typed = ast.get_source_segment(self.source, node)
                if isinstance(node.value, float) and typed is not None:
                    try:  # the digits as typed, not the nearest double
                        return sp.Rational(typed.replace("_", ""))
                    except (TypeError, ValueError):
                        pass
                return exact_number(node.value, self.what)
            raise self.refuse(f"the constant {node.value!r}")
        if isinstance(node, ast.Name):
            if node.id in self.names:
                return self.names[node.id]
            if self.free_names and node.id not in FUNCTIONS and node.id.isidentifier():
                return sp.Symbol(node.id, real=True)
            raise UserInputError(
                f"{self.what}: unknown name {node.id!r}; allowed: {_allowed(self.names)}"
            )
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            left, right = self.read(node.left), self.read(node.right)
            if isinstance(node.op, ast.Pow) and right.is_number and abs(right) > MAX_EXPONENT:
                raise self.refuse(f"the exponent {right} (at most {MAX_EXPONENT} in size)")
            return _BINARY[type(node.op)](left, right)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            value = self.read(node.operand)
            return -value if isinstance(node.op, ast.USub) else value
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in FUNCTIONS
            and len(node.args) == 1
            and not node.keywords
        ):
            return FUNCTIONS[node.func.id](self.read(node.args[0]))
        raise self.refuse(type(node).__name__)
