"""One precision, one row: what a working precision is and how its numbers are computed.

A :class:`Precision` is the value every integration is given explicitly (``"double"``,
``"quad"`` or a number of decimal digits). Everything that depends on it is read from it:
its name, bits and digits, its unit roundoff and tolerance floor, the number type of its
values, how a value is printed, the mpmath context its numbers are computed in
(:meth:`Precision.context`: entered by whoever computes, never set by assigning
``mpmath.mp.prec``), and its :class:`Arithmetic` -- the one vocabulary of how the compiled
and Python Taylor code carries the numbers (``double``, ``quad``, ``dd``, ``qd``, ``mpfr``).

:data:`ARITHMETICS` is the one table of the arithmetics (heyoka's ``fp_type``); a
precision's row is :attr:`Precision.arithmetic`.
"""

from __future__ import annotations

import math
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from typing import Any

import mpmath
from mpmath.libmp import dps_to_prec

from ..derive.errors import UserInputError

__all__ = ["Arithmetic", "ARITHMETICS", "DD_BITS", "QD_BITS", "Precision"]

#: Significand bits of double-double (two doubles, 53 + 53): the digits precisions up to
#: these bits (31 digits) run in the compiled double-double integrator.
DD_BITS = 106
#: Bits of quad-double that the digits precisions may use (60 digits: 203 of the 212 bits
#: of four doubles; the "sloppy" quad-double sums keep about 209).
QD_BITS = 203


@dataclass(frozen=True)
class Arithmetic:
    """How the numbers of one precision are carried: one row of :data:`ARITHMETICS`.

    Attributes
    ----------
    name : str
        ``double``, ``quad`` (IEEE binary128, ``__float128``), ``dd`` (double-double),
        ``qd`` (quad-double) or ``mpfr``: the kind of the compiled Taylor library
        (``backend="c-<name>"``) and of its C real type.
    description : str
        For messages and ``--explain``.
    most_bits : int or None
        Largest working precision (bits) it carries; None: any (MPFR).
    python_numbers : str
        Number library of the Python recurrences in this arithmetic (``backend="numpy"`` or
        no compiler): ``float`` or ``gmpy2`` (MPFR at the working bits).
    chunk_steps : int
        Steps per call of the compiled loop when a wall-time limit is set (checked between
        calls; a run resumes exactly, so the results do not depend on it).
    unrolled : bool
        Whether the compiled Taylor coefficients are written out for the orders a run uses
        (double: the loop's overhead is most of a step; the wider types spend their time in
        arithmetic).
    """

    name: str
    description: str
    most_bits: int | None
    python_numbers: str
    chunk_steps: int
    unrolled: bool = False


#: The arithmetics, narrowest first (the digits precisions take the first that holds their
#: bits).
ARITHMETICS: dict[str, Arithmetic] = {
    "double": Arithmetic("double", "IEEE double", 53, "float", 65536, unrolled=True),
    "quad": Arithmetic("quad", "__float128", 113, "gmpy2", 256),
    "dd": Arithmetic("dd", "double-double", DD_BITS, "gmpy2", 1024),
    "qd": Arithmetic("qd", "quad-double", QD_BITS, "gmpy2", 128),
    "mpfr": Arithmetic("mpfr", "MPFR", None, "gmpy2", 4),
}

#: The arithmetics a digits precision may run in, narrowest first.
_DIGITS_ARITHMETICS = ("dd", "qd", "mpfr")

_SQRT_EPS_DOUBLE = math.sqrt(2.0**-52)


class Precision:
    """Working precision: ``"double"``, ``"quad"`` (IEEE binary128) or decimal digits.

    Parameters
    ----------
    value : str, int or Precision
        ``"double"``, ``"quad"`` or a number of digits (16..10000).

    Raises
    ------
    UserInputError
        Anything else.
    """

    #: Decimal digits carried by IEEE binary128 (113-bit significand).
    QUAD_DIGITS = 34

    def __init__(self, value: str | int | Precision):
        self.is_quad = False
        if isinstance(value, Precision):
            self.digits, self.is_quad = value.digits, value.is_quad
        elif isinstance(value, str) and value.strip().lower() == "double":
            self.digits = None
        elif isinstance(value, str) and value.strip().lower() == "quad":
            self.digits, self.is_quad = self.QUAD_DIGITS, True
        else:
            try:
                if isinstance(value, float) and not value.is_integer():
                    raise ValueError  # 20.7 digits is not a number of digits
                digits = int(value)
            except (TypeError, ValueError, OverflowError):
                raise UserInputError(
                    f"precision {value!r} is neither 'double', 'quad' nor a number of digits; "
                    'use precision="double", precision="quad" or a number of digits, '
                    "e.g. precision=30"
                ) from None
            if not 16 <= digits <= 10000:
                raise UserInputError(
                    f"precision of {digits} digits is out of range; use 16..10000 digits "
                    "(or 'double')"
                )
            self.digits = digits

    @classmethod
    def working(cls, digits: int) -> Precision:
        """A digits precision for internal work, without the users' range (16..10000).

        The separatrix flow runs at the digits asked for plus guard digits, which may be
        fewer than 16 (``chaplygin.delta(..., digits=3)``).

        Parameters
        ----------
        digits : int
            At least 1.

        Returns
        -------
        Precision

        Raises
        ------
        UserInputError
            Fewer than 1 digit.
        """
        digits = int(digits)
        if digits < 1:
            raise UserInputError(f"a precision needs at least 1 digit, got {digits}")
        prec = cls.__new__(cls)
        prec.digits, prec.is_quad = digits, False
        return prec

    # ---------------------------------------------------------------- identity
    @property
    def kind(self) -> str:
        """``"double"``, ``"quad"`` or ``"digits"``."""
        return "double" if self.is_double else ("quad" if self.is_quad else "digits")

    @property
    def name(self) -> str:
        """``double``, ``quad`` or ``<n> digits`` (as results and messages print it)."""
        return repr(self)

    def __repr__(self) -> str:
        if self.is_quad:
            return "quad"
        return "double" if self.digits is None else f"{self.digits} digits"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Precision):
            return NotImplemented
        return (self.digits, self.is_quad) == (other.digits, other.is_quad)

    def __hash__(self) -> int:
        return hash((self.digits, self.is_quad))

    @property
    def is_double(self) -> bool:
        return self.digits is None

    @property
    def decimal_digits(self) -> int:
        """Decimal digits the working numbers carry: 15 (double: what ``mpmath.mp.dps`` is
        at 53 bits), 34 (binary128) or the digits asked for."""
        return 15 if self.is_double else self.digits

    def to_json(self) -> dict[str, object]:
        """The precision as a structured JSON value (never prose such as ``"30 digits"``).

        Returns
        -------
        dict
            ``{"kind": "double" | "quad" | "digits", "digits": int, "bits": int}``: the
            kind, the decimal digits the numbers carry (:attr:`decimal_digits`) and the
            significand bits (:attr:`prec`).

        Examples
        --------
        >>> Precision(30).to_json()
        {'kind': 'digits', 'digits': 30, 'bits': 103}
        >>> Precision("double").to_json()
        {'kind': 'double', 'digits': 15, 'bits': 53}
        """
        return {"kind": self.kind, "digits": self.decimal_digits, "bits": self.prec}

    # ---------------------------------------------------------------- bits
    @property
    def prec(self) -> int:
        """Binary precision in bits: 53 (double), 113 (binary128) or mpmath's bits for
        the number of digits (what ``mpmath.workdps(digits)`` uses)."""
        if self.is_double:
            return 53
        if self.is_quad:
            return 113
        return dps_to_prec(self.digits)

    @property
    def bits(self) -> int:
        """:attr:`prec`: significand bits of the working numbers."""
        return self.prec

    @property
    def parse_dps(self) -> int:
        """Digits user input is read at before it is rounded to the working precision."""
        return 30 if self.digits is None else self.digits + 10

    @property
    def arithmetic(self) -> Arithmetic:
        """The row of :data:`ARITHMETICS` that carries this precision's numbers in the
        compiled Taylor code (digits: the narrowest that holds :attr:`bits`)."""
        if self.is_double:
            return ARITHMETICS["double"]
        if self.is_quad:
            return ARITHMETICS["quad"]
        bits = self.bits
        for name in _DIGITS_ARITHMETICS:
            most = ARITHMETICS[name].most_bits
            if most is None or bits <= most:
                return ARITHMETICS[name]
        raise AssertionError("unreachable: mpfr carries any precision")  # pragma: no cover

    # ---------------------------------------------------------------- tolerances
    @property
    def epsilon(self) -> float:
        """Unit roundoff as the tolerances state it: 2^-52 (double), 2^-112 (binary128) or
        10^-digits."""
        if self.is_double:
            return 2.0**-52
        if self.is_quad:
            return 2.0**-112
        return 10.0 ** (-self.digits)

    @property
    def min_rtol(self) -> float:
        """Smallest relative tolerance worth asking for in general: 100 eps in double
        (what the scipy methods deliver), 10 eps otherwise (the Taylor method, whose
        control works to the unit roundoff, accepts down to 1 eps)."""
        return (100.0 if self.is_double else 10.0) * self.epsilon

    @property
    def default_tolerances(self) -> tuple[float, float]:
        """``(rtol, atol)`` when none are given: (1e-10, 1e-12) in double, :attr:`min_rtol`
        otherwise."""
        if self.is_double:
            return 1e-10, 1e-12
        return self.min_rtol, self.min_rtol

    @property
    def default_method(self) -> str:
        """The method used when none is given: the generated Taylor integrator in every
        precision (its bits do not depend on the machine; scipy's methods sum their stages
        with BLAS, whose kernels differ by processor)."""
        return "taylor"

    @property
    def zero(self) -> float:
        """An integral whose initial value is below this has no meaningful relative change:
        the square root of the working precision."""
        if self.is_double:
            return _SQRT_EPS_DOUBLE
        return 10.0 ** (-self.digits / 2)

    def unit_roundoff(self) -> float | mpmath.mpf:
        """``2^(1 - bits)``: what the Taylor loop locates events to.

        Returns
        -------
        float or mpmath.mpf
            A float in double and quad, an ``mpf`` for the digits precisions (whose roundoff
            may be below the range of a float).
        """
        if self.is_double:
            return 2.0**-52
        if self.is_quad:
            return 2.0**-112
        return mpmath.ldexp(mpmath.mpf(1), 1 - self.bits)

    # ---------------------------------------------------------------- numbers
    @property
    def number_type(self) -> type:
        """``float`` in double, ``mpmath.mpf`` otherwise."""
        return float if self.is_double else mpmath.mpf

    @property
    def dtype(self) -> type:
        """numpy dtype of arrays of working numbers (``float`` or ``object``)."""
        return float if self.is_double else object

    def number(self, value: Any) -> Any:
        """``value`` as a working number (``float``, or ``mpf`` in the current context).

        Parameters
        ----------
        value : number

        Returns
        -------
        float or mpmath.mpf
        """
        return float(value) if self.is_double else mpmath.mpf(value)

    def context(self) -> AbstractContextManager:
        """The mpmath context the precision's numbers are computed in, entered by whoever
        computes (``with p.context():``).

        Returns
        -------
        context manager
            Nothing in double, ``mpmath.workdps(digits)`` otherwise (quad: 34 digits, 116
            bits, in which every binary128 value is exact).
        """
        if self.is_double:
            return nullcontext()
        return mpmath.workdps(self.digits)

    def format(self, value: Any) -> str:
        """``value`` as decimal text: the shortest repr of a double, ``digits`` significant
        digits otherwise.

        Parameters
        ----------
        value : number

        Returns
        -------
        str
        """
        if self.is_double:
            return repr(float(value))
        return mpmath.nstr(value, self.digits, strip_zeros=False)
