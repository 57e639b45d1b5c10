"""What the subcommands of ``chaplygin`` share: exit statuses and the parsing of their flags."""

from __future__ import annotations

import argparse
from collections.abc import Sequence

from chaplygin.derive.errors import UserInputError

__all__ = ["EXIT_OK", "EXIT_FAILED", "EXIT_USAGE", "key_values", "positive_float"]

#: Exit statuses: success, a check or run that failed, a user error (one line on stderr).
EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2


def key_values(items: Sequence[str] | None, flag: str) -> dict[str, str]:
    """Parse repeated ``NAME=VALUE[,VALUE...]`` flags into ``{NAME: "VALUE[,VALUE...]"}``.

    Parameters
    ----------
    items : sequence of str or None
        The values given to ``flag`` (``action="append"``), or None when it was not given.
    flag : str
        The flag's name, for the error messages (``"--param"``).

    Returns
    -------
    dict of str to str
        Names to their (stripped, unparsed) values.

    Raises
    ------
    UserInputError
        An item without ``=``, a name or a value, or a name given twice.
    """
    out: dict[str, str] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name or not value.strip():
            raise UserInputError(f"{flag} expects NAME=VALUE[,VALUE...], got {item!r}")
        if name in out:
            raise UserInputError(f"{flag} {name} given twice")
        out[name] = value.strip()
    return out


def positive_float(text: str) -> float:
    """argparse ``type=``: a positive finite number.

    Parameters
    ----------
    text : str
        The flag's value.

    Returns
    -------
    float

    Raises
    ------
    argparse.ArgumentTypeError
        Not a number, or not positive and finite.
    """
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (value > 0 and value != float("inf")):
        raise argparse.ArgumentTypeError(f"{text!r} must be a positive finite number")
    return value
