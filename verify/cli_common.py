"""What the subcommands of ``chaplygin`` share: exit statuses, the parsing of their flags,
the checks of output paths (made before any work) and JSON that is always valid."""

from __future__ import annotations

import argparse
import json
import math
import os
import tempfile
import unicodedata
from collections.abc import Callable, Sequence
from pathlib import Path

from chaplygin.derive.errors import UserInputError

__all__ = [
    "EXIT_OK",
    "EXIT_FAILED",
    "EXIT_USAGE",
    "EXIT_INTERNAL",
    "key_values",
    "positive_float",
    "check_output_file",
    "check_output_dir",
    "json_text",
    "printable",
    "add_quiet",
    "add_precision_digits",
    "precision_digits",
]

#: Exit statuses: success, a check or run that failed, a user error (one line on stderr),
#: an internal error (a bug: one line saying where to report it; the traceback with --debug).
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 3


def _writable_folder(folder: Path, refuse: Callable[[str], UserInputError]) -> None:
    """Refuse a folder that is missing or where no file can be created (tried, not guessed:
    permissions, read-only file systems and /proc all answer; the probe leaves nothing)."""
    if not folder.exists():
        raise refuse(f"the parent folder {str(folder)!r} does not exist")
    if not folder.is_dir():
        raise refuse(f"{str(folder)!r} is not a folder")
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=".chaplygin-probe-"):
            pass
    except OSError as exc:
        raise refuse(f"no file can be created in {str(folder)!r} ({exc.strerror})") from None


def check_output_file(
    path: str, flag: str, suffixes: Sequence[str] = (), what: str = "the file"
) -> Path:
    """Check, before any work, that a file can be written at ``path``.

    Parameters
    ----------
    path : str
        The flag's value.
    flag : str
        The flag's name, for the error messages (``"--out"``).
    suffixes : sequence of str, optional
        Accepted suffixes (``(".png",)``, compared without case); the name must end with one
        of them, so that nothing appends a suffix silently. Empty: any name.
    what : str, optional
        What is written, for the error messages (``"the report"``).

    Returns
    -------
    pathlib.Path
        The path, as given.

    Raises
    ------
    UserInputError
        An empty path, a folder (or a path ending in a separator), a missing or read-only
        parent folder, an existing file that is not writable, or a wrong suffix.
    """
    if not path or not path.strip():
        raise UserInputError(f"{flag} needs a file name, got an empty one")

    def refuse(reason: str) -> UserInputError:
        return UserInputError(f"{flag}: cannot write {what} to {path!r}: {reason}")

    target = Path(path)
    if target.is_dir() or path.endswith(("/", os.sep)):
        raise refuse("it is a folder; give a file name")
    if suffixes and target.suffix.lower() not in {s.lower() for s in suffixes}:
        raise UserInputError(f"{flag} must name a {' or '.join(suffixes)} file, got {path!r}")
    _writable_folder(target.parent, refuse)
    if target.exists() and not (target.is_file() and os.access(target, os.W_OK)):
        raise refuse("it exists and cannot be overwritten")
    return target


def check_output_dir(path: str, flag: str, what: str = "files") -> Path:
    """Check, before any work, that files can be written into the folder ``path``.

    The folder may not exist yet; then its parent must (only one level is created).

    Parameters
    ----------
    path : str
        The flag's value.
    flag : str
        The flag's name, for the error messages (``"--out"``).
    what : str, optional
        What is written, for the error messages (``"the figures"``).

    Returns
    -------
    pathlib.Path
        The path, as given.

    Raises
    ------
    UserInputError
        An empty path, an existing file, a read-only folder, or a missing parent folder.
    """
    if not path or not path.strip():
        raise UserInputError(f"{flag} needs a folder name, got an empty one")

    def refuse(reason: str) -> UserInputError:
        return UserInputError(f"{flag}: cannot write {what} into {path!r}: {reason}")

    target = Path(path)
    if target.exists():
        if not target.is_dir():
            raise refuse("it exists and is not a folder; give a folder")
        _writable_folder(target, refuse)
    else:
        _writable_folder(target.parent, refuse)
    return target


#: Unicode categories never sent to a terminal as they are: controls (escape sequences, bell,
#: carriage return), format characters (bidirectional overrides) and line/paragraph separators.
_UNPRINTABLE = frozenset({"Cc", "Cf", "Zl", "Zp"})


def printable(text: str, keep: str = "\n") -> str:
    r"""``text`` safe for a terminal: every control or format character shown as an escape.

    Text from user files (a scene's title, a file name) may hold escape sequences that
    recolour, retitle or clear the terminal, or bidirectional overrides that reorder what is
    shown; they are printed as ``\x1b``, ``\u202e`` (as Python's ``repr`` writes them).

    Parameters
    ----------
    text : str
    keep : str
        Characters left as they are (default: the newline of multi-line output).

    Returns
    -------
    str

    Examples
    --------
    >>> print(printable("title \x1b[2J"))
    title \x1b[2J
    """
    out = []
    for ch in text:
        if ch in keep or unicodedata.category(ch) not in _UNPRINTABLE:
            out.append(ch)
        elif ord(ch) < 0x100:
            out.append(f"\\x{ord(ch):02x}")
        else:
            out.append(f"\\u{ord(ch):04x}" if ord(ch) < 0x10000 else f"\\U{ord(ch):08x}")
    return "".join(out)


def _finite_or_none(value: object) -> object:
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite_or_none(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite_or_none(v) for v in value]
    return value


def json_text(value: object, indent: int | None = 2, sort_keys: bool = False) -> str:
    """``value`` as strict JSON: NaN and infinities become ``null`` (never a bare ``NaN``).

    Parameters
    ----------
    value : object
        Dicts, lists, tuples, strings, numbers, booleans and None.
    indent : int, optional
        As for :func:`json.dumps`.
    sort_keys : bool
        As for :func:`json.dumps`.

    Returns
    -------
    str
    """
    return json.dumps(_finite_or_none(value), indent=indent, allow_nan=False, sort_keys=sort_keys)


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


def add_quiet(parser: argparse.ArgumentParser, what: str = "no progress, no report line") -> None:
    """``--quiet``: the one spelling of "print no progress" on every command that prints any.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    what : str
        What it leaves out, for the help.
    """
    parser.add_argument("--quiet", action="store_true", help=what)


def add_precision_digits(parser: argparse.ArgumentParser, default: int) -> None:
    """``--precision`` as ``integrate`` takes it (``double``, ``quad`` or a number of digits)
    for a command that works at a number of decimal digits, with ``--digits N`` kept as a
    hidden alias.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    default : int
        Digits when neither is given.
    """
    parser.add_argument(
        "--precision",
        default=None,
        metavar="PRECISION",
        help=f"'double', 'quad' (binary128) or a number of digits (default {default} digits)",
    )
    parser.add_argument("--digits", type=int, default=None, help=argparse.SUPPRESS)
    parser.set_defaults(default_digits=default)


def _digits_of(text: str) -> int:
    """The decimal digits of a ``--precision`` value: ``double`` and ``quad`` are the digits
    their significands carry (:attr:`~chaplygin.numerics.precision.Precision.decimal_digits`),
    a whole number is itself."""
    from chaplygin.numerics.precision import Precision

    if text.strip().lower() in ("double", "quad"):
        return Precision(text).decimal_digits
    try:
        return int(text)
    except ValueError:
        raise UserInputError(
            f"--precision {text!r} is neither 'double', 'quad' nor a number of digits"
        ) from None


def precision_digits(args: argparse.Namespace) -> int:
    """The digits of ``--precision`` (or its old spelling ``--digits``).

    Parameters
    ----------
    args : argparse.Namespace

    Returns
    -------
    int

    Raises
    ------
    UserInputError
        A value that is not a precision, or both spellings given with different values.
    """
    given = None if args.precision is None else _digits_of(args.precision)
    if given is not None and args.digits is not None and given != args.digits:
        raise UserInputError("give --precision once (--digits is its old name)")
    for value in (given, args.digits):
        if value is not None:
            return value
    return args.default_digits
