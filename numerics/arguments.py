"""Checks of the API's arguments: a number, a vector, an inertia, a choice or a count, each
refused with a :class:`~chaplygin.derive.errors.UserInputError` that names the argument.

The values are read by :func:`~chaplygin.numerics.inputs.parse_number` (no ``eval``).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping, Sequence
from typing import Any

import mpmath

from ..derive.errors import UserInputError
from .inputs import parse_number

__all__ = [
    "check_choice",
    "check_count",
    "check_inertia_vector",
    "check_real",
    "check_rows",
    "check_vector",
]


def check_real(
    value: object,
    name: str,
    *,
    positive: bool = False,
    nonzero: bool = False,
    double: bool = False,
) -> mpmath.mpf:
    """``value`` as a finite real number, or :class:`UserInputError` naming ``name``.

    Parameters
    ----------
    value : number or str
        Anything :func:`parse_number` reads (a number type or a decimal string).
    name : str
        The argument's name, used in the message.
    positive, nonzero : bool
        Also require ``value > 0`` (``value != 0``).
    double : bool
        The caller computes in double precision: the value must be a number (not text)
        that stays finite (and, if asked, positive or nonzero) when rounded to a float.

    Returns
    -------
    mpmath.mpf
        The value at 30 digits (for checks; callers keep using their own value).

    Raises
    ------
    UserInputError
        Not a real number, not finite, or not of the sign asked for.
    """
    if isinstance(value, bool) or value is None or double and isinstance(value, str | bytes):
        raise UserInputError(f"{name} = {value!r} is not a number")
    try:
        x = parse_number(value)
    except UserInputError as exc:
        raise UserInputError(f"{name}: {exc}") from None
    if double:
        if not math.isfinite(float(x)):
            raise UserInputError(f"{name} = {mpmath.nstr(x, 8)} overflows double precision")
        if (positive or nonzero) and x != 0 and float(x) == 0:
            raise UserInputError(
                f"{name} = {mpmath.nstr(x, 8)} underflows to 0 in double precision"
            )
    if positive and not x > 0:
        raise UserInputError(f"{name} = {mpmath.nstr(x, 8)} must be positive")
    if nonzero and x == 0:
        raise UserInputError(f"{name} must not be zero")
    return x


def check_vector(
    value: object, name: str, length: int = 3, *, positive: bool = False, double: bool = False
) -> list[mpmath.mpf]:
    """``value`` as ``length`` finite real numbers (a sequence or a 1-D array).

    Parameters
    ----------
    value : sequence of numbers
    name : str
        The argument's name, used in the message (entries are named ``name[i]``).
    length : int
        The number of entries required.
    positive, double : bool
        As for :func:`check_real`, for every entry.

    Returns
    -------
    list of mpmath.mpf

    Raises
    ------
    UserInputError
        Not a sequence of ``length`` finite numbers (of the sign asked for).
    """
    if isinstance(value, str | bytes | Mapping) or value is None:
        raise UserInputError(f"{name} must be a sequence of {length} numbers, got {value!r}")
    try:
        items = list(value)
    except TypeError:
        raise UserInputError(
            f"{name} must be a sequence of {length} numbers, got {type(value).__name__}"
        ) from None
    if len(items) != length:
        count = {2: "two", 3: "three", 4: "four"}.get(length, str(length))
        raise UserInputError(f"{name} needs {count} numbers, got {len(items)}")
    return [
        check_real(v, f"{name}[{i}]", positive=positive, double=double) for i, v in enumerate(items)
    ]


def check_inertia_vector(
    I: object, D: object, name: str = "I", *, double: bool = False
) -> tuple[list, mpmath.mpf]:
    """Three finite positive moments of inertia ``I`` and a finite positive ``D = m b^2``.

    Parameters
    ----------
    I : sequence of 3 numbers
    D : number
    name : str
        The name of the inertia argument in messages.
    double : bool
        The caller computes in double precision (see :func:`check_real`).

    Returns
    -------
    (list of mpmath.mpf, mpmath.mpf)

    Raises
    ------
    UserInputError
        A wrong type or shape, a non-finite value, a moment or ``D`` not positive.
    """
    return (
        check_vector(I, name, 3, positive=True, double=double),
        check_real(D, "D", positive=True, double=double),
    )


def check_choice(value: object, choices: Sequence, name: str) -> None:
    """Raise :class:`UserInputError` unless ``value`` is one of ``choices``.

    Parameters
    ----------
    value : object
    choices : sequence
        The allowed values (compared with ``==``; ``bool`` is never taken for an int).
    name : str
        The argument's name, used in the message.

    Raises
    ------
    UserInputError
        ``value`` is not one of ``choices``.
    """
    try:
        ok = (
            not isinstance(value, bool)
            and any(
                type(value) is type(c) or isinstance(c, int) and isinstance(value, numbers.Integral)
                for c in choices
            )
            and value in choices
        )
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise UserInputError(
            f"{name} = {value!r} is not one of {', '.join(repr(c) for c in choices)}"
        )


def check_count(value: object, name: str, low: int, high: int) -> int:
    """An integer ``low <= value <= high`` (digits, samples, nodes), or :class:`UserInputError`.

    Parameters
    ----------
    value : int
    name : str
        The argument's name, used in the message.
    low, high : int
        The accepted range.

    Returns
    -------
    int

    Raises
    ------
    UserInputError
        Not an integer or out of range.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise UserInputError(f"{name} = {value!r} must be an integer in {low}..{high}")
    if not low <= int(value) <= high:
        raise UserInputError(f"{name} = {value} is out of range; use {low}..{high}")
    return int(value)


def check_rows(value: object, name: str, width: int, count: int | None = None) -> Any:
    """``value`` as a C-contiguous float64 array of shape ``(N, width)`` with finite entries
    (double precision: the batched routines run in double).

    Parameters
    ----------
    value : array_like
    name : str
        The argument's name, used in the message.
    width : int
        The number of columns required.
    count : int, optional
        The number of rows required (``N``); any ``N >= 1`` when None.

    Returns
    -------
    numpy.ndarray

    Raises
    ------
    UserInputError
        Not numbers, another shape, no rows, or an entry that is not finite.
    """
    import numpy as np

    if isinstance(value, str | bytes | Mapping) or value is None:
        raise UserInputError(f"{name} must be an array of shape (N, {width}), got {value!r}")
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise UserInputError(f"{name} must be an array of numbers of shape (N, {width})") from None
    if a.ndim != 2 or a.shape[1] != width or len(a) == 0:
        raise UserInputError(f"{name} must be an array of shape (N, {width}), got {a.shape}")
    if count is not None and len(a) != count:
        raise UserInputError(f"{name} must have {count} rows (one per point), got {len(a)}")
    if not np.isfinite(a).all():
        raise UserInputError(f"{name} must be finite")
    return np.ascontiguousarray(a)
