"""Turning user values into state and parameter vectors, with clear errors.

Values are parsed without ``eval``: a number is a decimal literal or a small arithmetic
expression of literals with ``sqrt``, ``pi``, ``+ - * / **`` and parentheses, evaluated
with mpmath at the working precision (so ``sqrt(0.87)`` carries every digit asked for).
"""

from __future__ import annotations

import ast
import math
import numbers
import operator
import re
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction

import gmpy2
import mpmath
import numpy as np
from mpmath.libmp import dps_to_prec, from_rational, round_nearest

from ..derive.errors import UserInputError
from .code import ModelCode
from .frame import complete_frame, unit_vector
from .precision import Precision

__all__ = [
    "UNIT_TOLERANCE",
    "parse_number",
    "working_number",
    "pack_params",
    "pack_state",
    "complete_state",
    "CompletedState",
    "Precision",
]

#: How far a unit vector (gamma, alpha, beta) may be from unit length, relatively, before
#: it is rejected; within it the vector is renormalised exactly at the working precision.
UNIT_TOLERANCE = 1e-9

_BINOPS = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
_FUNCS = {
    "sqrt": mpmath.sqrt,
    "cbrt": mpmath.cbrt,
    "exp": mpmath.exp,
    "log": mpmath.log,
    "sin": mpmath.sin,
    "cos": mpmath.cos,
}
_CONSTS = {"pi": lambda: +mpmath.pi, "e": lambda: +mpmath.e}


Number = str | int | float | Fraction | Decimal | mpmath.mpf

#: A plain decimal literal: read directly at the working precision (correctly rounded).
_LITERAL = re.compile(r"[+-]?(?:\d[\d_]*\.?[\d_]*|\.\d[\d_]*)(?:[eE][+-]?\d+)?")


_MPFR = type(gmpy2.mpfr(0))


def _exact_mpf(value: object, prec: int) -> mpmath.mpf | None:
    """``value`` rounded once to ``prec`` bits, for the number types that carry an exact value.

    A Python or numpy float is the exact binary value it is; ``Fraction``, ``Decimal``,
    gmpy2 ``mpz``/``mpq``/``mpfr`` and ``mpf`` are rounded to nearest from their exact
    value. Returns None for anything else (text, unknown types).
    """
    if isinstance(value, bool):
        return None
    if isinstance(value, mpmath.mpf):
        with mpmath.workprec(prec):
            return +value
    if isinstance(value, Decimal):
        if not value.is_finite():
            return mpmath.mpf("nan")
        return _exact_mpf(Fraction(value), prec)
    if isinstance(value, float | np.floating):
        with mpmath.workprec(max(prec, 53)):
            x = mpmath.mpf(float(value))
        with mpmath.workprec(prec):
            return +x
    if isinstance(value, _MPFR):
        if not gmpy2.is_finite(value):
            return mpmath.mpf("nan")
        return _exact_mpf(Fraction(*value.as_integer_ratio()), prec)
    if isinstance(value, numbers.Rational):  # int, numpy ints, Fraction, mpz, mpq
        num, den = int(value.numerator), int(value.denominator)
        with mpmath.workprec(prec):  # mpf(raw) rounds to the context's precision
            return mpmath.mpf(from_rational(num, den, prec, round_nearest))
    return None


def parse_number(text: Number | object, dps: int = 30) -> mpmath.mpf:
    """Parse a user number safely (no ``eval``) at ``dps`` digits.

    Parameters
    ----------
    text : str, int, float, Fraction, Decimal, mpmath.mpf or gmpy2 number
        Text is a decimal literal or an expression of literals with ``sqrt``, ``cbrt``,
        ``exp``, ``log``, ``sin``, ``cos``, ``pi``, ``e``, ``+ - * / **`` and parentheses;
        every literal is read from its own text (``0.1`` is one tenth). Number types are
        taken at their exact value (a float is the binary value it is).
    dps : int
        Decimal digits of the result.

    Returns
    -------
    mpmath.mpf
        The value at ``dps`` digits.

    Raises
    ------
    UserInputError
        Malformed text, an unsupported type, NaN or infinity.
    """
    exact = _exact_mpf(text, dps_to_prec(dps))
    with mpmath.workdps(dps):
        if exact is not None:
            value = exact
        elif isinstance(text, str | bytes):
            src = text.decode() if isinstance(text, bytes) else text
            src = src.strip()
            if len(src) > MAX_TEXT:
                raise UserInputError(
                    f"a number of {len(src)} characters is too long (at most {MAX_TEXT})"
                )
            try:
                if _LITERAL.fullmatch(src):
                    value = _bounded(mpmath.mpf(src.replace("_", "")))
                else:
                    tree = ast.parse(src, mode="eval")
                    if _depth(tree) > MAX_DEPTH:
                        raise _Refused(f"the expression is nested deeper than {MAX_DEPTH}")
                    value = +_eval_node(tree.body, src)
            except _Refused as exc:
                raise UserInputError(f"cannot use {src[:60]!r} as a number: {exc}") from None
            except ZeroDivisionError:
                raise UserInputError(
                    f"cannot use {src[:60]!r} as a number: division by zero"
                ) from None
            except (
                SyntaxError,
                ValueError,
                TypeError,
                KeyError,
                RecursionError,
                MemoryError,
                OverflowError,
            ):
                raise UserInputError(
                    f"cannot read {src!r} as a number: use a decimal like 0.93 or an "
                    "expression of numbers with sqrt, pi, + - * / ** and parentheses"
                ) from None
        else:
            raise UserInputError(f"{text!r} is not a number (give a decimal string or a number)")
        if not isinstance(value, mpmath.mpf):
            raise UserInputError(f"value {text!r} is not a real number")
        if not mpmath.isfinite(value):
            raise UserInputError(
                f"value {text!r} is not finite (NaN or infinity); give a finite number"
            )
        return value


def working_number(value: Number | object, precision: Precision) -> float | mpmath.mpf:
    """A user number at the working precision, rounded once where that is possible.

    A decimal literal (``"1.2716"``), an ``int``, ``Fraction``, ``Decimal``, float, ``mpf``
    or gmpy2 number is rounded to nearest directly from its exact value; an expression
    (``"sqrt(0.87)"``) is evaluated with 10 guard digits and then rounded.

    Parameters
    ----------
    value : str or number
        The user's number or its text (as for :func:`parse_number`).
    precision : Precision
        The working precision.

    Returns
    -------
    float (double) or mpmath.mpf with ``precision.prec`` bits (quad, digits)
        The value rounded to the working precision.

    Raises
    ------
    UserInputError
        Malformed or non-finite input, or a value that overflows the working precision.
    """
    if precision.is_double and isinstance(value, float | int) and not isinstance(value, bool):
        # fast path, same result: a double is its own rounding; an int within 2^53 is exact
        if isinstance(value, float) and math.isfinite(value):
            return float(value)
        if isinstance(value, int) and abs(value) <= 2**53:
            return float(value)
    if precision.is_double and isinstance(value, mpmath.mpf):
        # fast path, same result: an mpf of at most 53 significant bits in the normal range
        # of doubles is a double exactly (float() of it rounds nothing)
        _, man, exp, bc = value._mpf_
        if value._mpf_ == (0, 0, 0, 0) or (man and bc <= 53 and -1021 <= exp + bc <= 1024):
            return float(value)
    bits = precision.prec
    exact = _exact_mpf(value, bits)
    if (
        exact is None
        and isinstance(value, str)
        and len(value.strip()) <= MAX_TEXT  # longer: parse_number refuses it
        and _LITERAL.fullmatch(value.strip())
    ):
        with mpmath.workprec(bits):
            exact = mpmath.mpf(value.strip().replace("_", ""))
    if exact is None:
        exact = parse_number(value, precision.parse_dps)
    if not mpmath.isfinite(exact):
        raise UserInputError(
            f"value {value!r} is not finite (NaN or infinity); give a finite number"
        )
    if precision.is_double:
        out = float(exact)
        if abs(out) == float("inf") or (out == 0 and exact != 0):
            what = "overflows" if out else "underflows to zero in"
            raise UserInputError(
                f'value {value!r} {what} double precision; use precision="quad" or digits, e.g. '
                "precision=30"
            )
        return out
    with mpmath.workprec(bits):
        return +exact


#: Bounds of the number parser, checked before anything is evaluated: the length of the
#: text, the nesting depth of the expression, and the size of every intermediate value
#: (``|log10 x| <= MAX_LOG10``: far beyond any physical input, small enough that no
#: operation can take long or use much memory).
MAX_TEXT, MAX_DEPTH, MAX_LOG10 = 1000, 50, 10_000


class _Refused(ValueError):
    """An expression the parser will not evaluate (the message says why)."""


def _depth(tree: ast.AST) -> int:
    """Nesting depth of an expression tree, without recursion."""
    deepest, stack = 0, [(tree, 1)]
    while stack:
        node, d = stack.pop()
        deepest = max(deepest, d)
        stack.extend((child, d + 1) for child in ast.iter_child_nodes(node))
    return deepest


def _log10_abs(x: mpmath.mpf) -> float:
    """``log10 |x|`` from the binary exponent (cheap at any size; 0 for x = 0)."""
    if x == 0:
        return 0.0
    man, exp = mpmath.frexp(x)
    return float(exp) * 0.30102999566398120 + float(mpmath.log10(abs(man)))


def _bounded(x) -> mpmath.mpf:
    if not isinstance(x, mpmath.mpf):
        raise _Refused("the value is not a real number")
    if mpmath.isfinite(x) and abs(_log10_abs(x)) > MAX_LOG10:
        raise _Refused(f"an intermediate value is beyond 1e±{MAX_LOG10}")
    return x


def _power(base: mpmath.mpf, exponent: mpmath.mpf) -> mpmath.mpf:
    # estimate the size of the result before computing it (9**9**9**9 must not start)
    if base != 0 and abs(exponent) * abs(_log10_abs(base)) > MAX_LOG10:
        raise _Refused(f"a power is beyond 1e±{MAX_LOG10}")
    if base < 0 and exponent != mpmath.floor(exponent):
        raise _Refused("a negative number to a fractional power is not real")
    return base**exponent


def _exp(x: mpmath.mpf) -> mpmath.mpf:
    if abs(x) > MAX_LOG10 * 2.302585092994046:
        raise _Refused(f"exp of {mpmath.nstr(x, 5)} is beyond 1e±{MAX_LOG10}")
    return mpmath.exp(x)


def _real_only(fn, what: str):
    def f(x):
        if x < 0:
            raise _Refused(f"{what} of a negative number is not real")
        if what == "log" and x == 0:
            raise _Refused("log of 0 is not finite")
        return fn(x)

    return f


def _trig(fn):
    def f(x):
        if abs(x) > 1e100:  # reducing a larger argument mod 2 pi costs time, not accuracy
            raise _Refused("the argument of sin/cos is beyond 1e100")
        return fn(x)

    return f


_FUNCS.update(
    sqrt=_real_only(mpmath.sqrt, "sqrt"),
    log=_real_only(mpmath.log, "log"),
    exp=_exp,
    cbrt=lambda x: mpmath.cbrt(x) if x >= 0 else -mpmath.cbrt(-x),  # the real root
    sin=_trig(mpmath.sin),
    cos=_trig(mpmath.cos),
)
_BINOPS[ast.Pow] = _power


def _eval_node(node: ast.AST, src: str = "") -> mpmath.mpf:
    return _bounded(_eval_unchecked(node, src))


def _eval_unchecked(node: ast.AST, src: str = "") -> mpmath.mpf:
    if (
        isinstance(node, ast.Constant)
        and isinstance(node.value, int | float)
        and not isinstance(node.value, bool)
    ):
        # re-read the literal's own text so that 0.1 means one tenth and a 40-digit literal
        # keeps its 40 digits at the working precision (the Python float has only 17)
        text = ast.get_source_segment(src, node) if src else None
        return mpmath.mpf(text.replace("_", "") if text else repr(node.value))
    if isinstance(node, ast.Name) and node.id.lower() in ("nan", "inf", "infinity"):
        return mpmath.mpf("nan") if node.id.lower() == "nan" else mpmath.mpf("inf")
    if isinstance(node, ast.Name) and node.id in _CONSTS:
        return _CONSTS[node.id]()
    if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
        return _BINOPS[type(node.op)](_eval_node(node.left, src), _eval_node(node.right, src))
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_eval_node(node.operand, src))
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Name)
        and node.func.id in _FUNCS
        and len(node.args) == 1
        and not node.keywords
    ):
        return _FUNCS[node.func.id](_eval_node(node.args[0], src))
    raise ValueError("unsupported syntax")


def _argument(mapping: str, key: str, count: int, placeholder: str) -> str:
    """How to give a value, in the API's words: ``params["I"]=(V1, V2, V3)``.

    The command line translates this form to its flags (``--param I=V1,V2,V3``).
    """
    if count == 1:
        return f'{mapping}["{key}"]={placeholder}'
    values = ", ".join(f"{placeholder}{i}" for i in range(1, count + 1))
    return f'{mapping}["{key}"]=({values})'


def _items(name: str, raw: object, expected: int) -> list:
    """The ``expected`` raw entries of a group given as text ``"a,b,c"``, a sequence or a number."""
    if isinstance(raw, str | bytes):
        items = (raw.decode() if isinstance(raw, bytes) else raw).split(",")
    elif isinstance(raw, Sequence) or hasattr(raw, "__len__"):
        items = list(raw)
    else:
        items = [raw]
    if len(items) != expected:
        raise UserInputError(
            f"{name} needs {expected} value{'s' if expected > 1 else ''}, got {len(items)}: "
            f"give {name}=" + ",".join(["..."] * expected)
        )
    return items


def _values(name: str, raw: object, expected: int, convert) -> list:
    """A group's values, each converted by ``convert`` (errors name the group)."""
    out = []
    for item in _items(name, raw, expected):
        try:
            out.append(convert(item))
        except UserInputError as exc:
            raise UserInputError(f"{name}: {exc}") from None
    return out


def _working_values(name: str, raw: object, expected: int, precision: Precision) -> list:
    """A group's values rounded once to the working precision."""
    return _values(name, raw, expected, lambda v: working_number(v, precision))


def pack_params(
    code: ModelCode, values: Mapping[str, object], precision: Precision
) -> list[float | mpmath.mpf]:
    """Parameter vector in the model's order, validated.

    Parameters
    ----------
    code : ModelCode
        The model (its parameter groups, their domains and order).
    values : mapping of group name to values
        ``{"I": (1, 2, 3), "D": 1}``; strings are parsed safely.
    precision : Precision
        The working precision.

    Returns
    -------
    list of float (double) or mpmath.mpf (digits)
        The parameters in ``code.params`` order, each rounded once.

    Raises
    ------
    UserInputError
        Unknown or missing group, wrong length, non-finite or out-of-domain value.
    """
    groups = code.parameter_groups
    unknown = sorted(set(values) - set(groups))
    if unknown:
        raise UserInputError(
            f"unknown parameter {unknown[0]!r} for {code.name}; valid parameters: "
            + ", ".join(f"{n} ({desc})" for n, (_, _, desc) in groups.items())
        )
    out: dict[str, object] = {}
    for name, (symbols, domain, desc) in groups.items():
        if name not in values:
            raise UserInputError(
                f"missing parameter {name} ({desc}) for {code.name}: give "
                + _argument("params", name, len(symbols), "VALUE")
            )
        # each value is rounded once to the working precision, and checked after rounding
        vals = _working_values(name, values[name], len(symbols), precision)
        if domain == "positive" and any(v <= 0 for v in vals):
            raise UserInputError(
                f"{name} must be positive ({desc}); got {','.join(mpmath.nstr(v, 8) for v in vals)}"
            )
        out.update(zip(symbols, vals, strict=True))
    _check_conditions(code, out)
    return [out[s] for s in code.params]


def _check_conditions(code: ModelCode, values: Mapping[str, object]) -> None:
    """A described system's conditions on its parameters' values (its registry entry's
    :attr:`~chaplygin.derive.rolling_system.RollingSystem.parameter_conditions`: each must
    be positive), decided in the values' own precision. Only a process that registered a
    description has one (``derive.systems`` is loaded then)."""
    systems = sys.modules.get("chaplygin.derive.systems")
    entry = systems.SYSTEMS.get(code.system) if systems is not None else None
    conditions = getattr(entry, "conditions", ())
    if conditions:
        import sympy as sp  # (loaded already: a description was registered)
    for expr, what in conditions:
        at = {x: sp.Float(values[x.name]) for x in expr.free_symbols}
        value = expr.xreplace(at)
        if not value > 0:
            names = sorted(x.name for x in at)
            shown = ", ".join(f"{n} = {mpmath.nstr(values[n], 8)}" for n in names)
            raise UserInputError(
                f"{what} ({expr}) must be positive; it is {mpmath.nstr(value, 8)} at {shown}"
            )


def round_to(values: Sequence[mpmath.mpf], precision: Precision) -> list[float | mpmath.mpf]:
    """Values (mpf at a guard precision) rounded once to the working precision.

    Parameters
    ----------
    values : sequence of mpmath.mpf
        Values at a guard precision.
    precision : Precision
        The working precision.

    Returns
    -------
    list of float (double) or mpmath.mpf with ``precision.prec`` bits
        The values rounded to nearest (:func:`working_number`).

    Raises
    ------
    UserInputError
        A value that is not finite or overflows the working precision.
    """
    return [working_number(v, precision) for v in values]


@dataclass(frozen=True)
class CompletedState:
    """A state vector and how the groups the user omitted were completed.

    Attributes
    ----------
    y : list of float or mpmath.mpf
        The state in the model's order at the working precision (what :func:`pack_state`
        returns).
    notes : tuple of str
        Where a completion rule took its documented fallback (the frame on ``M || gamma``,
        :data:`chaplygin.numerics.frame.PARALLEL_FRAME_NOTE`); empty otherwise.
    """

    y: list
    notes: tuple[str, ...] = ()


def pack_state(
    code: ModelCode, values: Mapping[str, object], precision: Precision
) -> list[float | mpmath.mpf]:
    """State vector in the model's order, validated and completed as the model declares.

    The vectors of the model's Poisson groups (``code.geometry``: ``gamma``, or the frame
    ``alpha, beta, gamma``) must be unit vectors (a frame orthonormal and right-handed)
    within :data:`UNIT_TOLERANCE`; they are renormalised at the working precision. A group
    the user omits is completed by the rule the model declares for it (``code.completion``:
    with the contact point, ``alpha, beta`` by :func:`chaplygin.numerics.frame.complete_frame`:
    BKM12-7, ``alpha = M x gamma/|M x gamma|``, and on ``M || gamma``, where that formula is
    undefined, the body axis least aligned with ``gamma``, projected; ``x, y`` start at 0); a
    group without a rule must be given (the spherical support's eigenframe, the ball on a
    surface's ``x``). The constraints that involve parameters (the ellipsoid) are checked by
    ``integrate``.

    Parameters
    ----------
    code : ModelCode
        The model (its state groups and state order).
    values : mapping of str to value
        Group name (``"M"``, ``"gamma"``, ``"alpha"``, ``"x"`` ...) -> its components: a
        sequence, comma-separated text ``"a,b,c"`` or, for a one-component group, a single
        value; each entry anything :func:`parse_number` reads.
    precision : Precision
        Working precision; the text is read at ``precision.parse_dps`` digits.

    Returns
    -------
    list of float (double) or mpmath.mpf with ``precision.prec`` bits
        The state in ``code.state`` order; groups kept as given are rounded once from their
        own text, normalised or completed ones from the guard-precision values.

    Raises
    ------
    UserInputError
        An unknown group, a wrong number of components, an unreadable number, a missing
        group the model has no completion rule for, a vector off its variety (not a unit
        vector, not an orthonormal right-handed frame), or only one of ``alpha`` and ``beta``.

    See Also
    --------
    complete_state : the same, with the notes of the completion.

    References
    ----------
    BKM12-7 (FORMULAS.md).
    """
    return complete_state(code, values, precision).y


def complete_state(
    code: ModelCode, values: Mapping[str, object], precision: Precision
) -> CompletedState:
    """:func:`pack_state`, and the notes of the completion rules' fallbacks.

    Parameters
    ----------
    code : ModelCode
    values : mapping of str to value
    precision : Precision

    Returns
    -------
    CompletedState

    Raises
    ------
    UserInputError
        As :func:`pack_state`.
    """
    groups = code.state_groups
    unknown = sorted(set(values) - set(groups))
    if unknown:
        raise UserInputError(
            f"unknown state variable {unknown[0]!r} for {code.name}; valid: {', '.join(groups)}"
        )
    dps = precision.parse_dps
    notes: list[str] = []
    # the vectors of the model's Poisson groups are read at a guard precision (they are
    # renormalised or complete a frame); every other group is rounded once to the working
    # precision from its own text, and the frame of BKM12-7 is built from those values
    vectors = {n for _, names in code.geometry for n in names}
    with mpmath.workdps(dps):
        got = {
            name: [
                mpmath.mpf(v)
                for v in (
                    _values(name, values[name], len(groups[name]), lambda v: parse_number(v, dps))
                    if name in vectors
                    else _working_values(name, values[name], len(groups[name]), precision)
                )
            ]
            for name in values
        }
        rules = {g: rule for names, rule in code.completion for g in names}
        # a fixed vector starting as the normal: the model's unit vector outside its frame
        normal = next((n[0] for kind, n in code.geometry if kind == "unit_vector"), None)
        for name, rule in rules.items():
            if name not in got and rule == "normal" and normal in got:
                got[name] = list(unit_vector(normal, got[normal], UNIT_TOLERANCE))
        for name, comps in groups.items():
            if name not in got and name not in rules:
                raise UserInputError(
                    f"missing initial value of {name}: give "
                    + _argument("y0", name, len(comps), "V")
                )
        for kind, names in code.geometry:
            if kind == "unit_vector":
                got[names[0]] = unit_vector(names[0], got[names[0]], UNIT_TOLERANCE)
            else:  # a frame alpha, beta, gamma: checked, or completed by its rule
                alpha, beta, gamma = names
                got[gamma] = unit_vector(gamma, got[gamma], UNIT_TOLERANCE)
                if (alpha in got) != (beta in got):
                    raise UserInputError(
                        f"give both {alpha} and {beta}, or neither (they are then computed)"
                    )
                if alpha in got or rules.get(alpha) == "frame_bkm12_7":
                    about = _frame_axis(groups, code.geometry, rules)
                    frame = complete_frame(
                        got.get(about), got[gamma], got.get(alpha), got.get(beta),
                        UNIT_TOLERANCE, names=(alpha, beta),
                    )  # fmt: skip
                    got[alpha], got[beta] = frame.alpha, frame.beta
                    if frame.note:
                        notes.append(frame.note)
        for name, rule in rules.items():
            if name not in got and rule == "zero":
                got[name] = [mpmath.mpf(0)] * len(groups[name])
        flat = {
            s: v for name, comps in groups.items() for s, v in zip(comps, got[name], strict=True)
        }
        state = [flat[s] for s in code.state]
    # one rounding to the working precision (exact for the groups already at it)
    return CompletedState(round_to(state, precision), tuple(notes))


def _frame_axis(
    groups: dict[str, tuple[str, ...]],
    geometry: Sequence[tuple[str, tuple[str, ...]]],
    rules: dict[str, str],
) -> str | None:
    """The state group a frame is completed about (BKM12-7's momentum): the model's first
    3-vector group that is neither in a Poisson group nor completed by a rule."""
    bound = {n for _, names in geometry for n in names} | set(rules)
    return next((g for g, comps in groups.items() if len(comps) == 3 and g not in bound), None)


