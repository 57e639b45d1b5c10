"""The constants block of the project's elementary functions in C (``arith/templates/detmath.h``).

The numbers come from :mod:`chaplygin.arith.detmath_tables` (mpmath at 1600 bits, the design
conditions checked there); this module prints them as C -- exact hexadecimal literals -- and
writes the block between its two marker lines. Run at development time (the test
``tests/arith/test_detmath.py`` checks the header)::

    python -m chaplygin.derive.emit.detmath_header            # print the constants block
    python -m chaplygin.derive.emit.detmath_header --write    # write it into detmath.h
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from ...arith.detmath_tables import constants, header_path

__all__ = ["BEGIN_MARK", "END_MARK", "constants_block", "write_header"]

BEGIN_MARK = "/* ---- BEGIN GENERATED CONSTANTS (chaplygin.derive.emit.detmath_header) ---- */"
END_MARK = "/* ---- END GENERATED CONSTANTS ---- */"


def _format_double(value: float) -> str:
    return float(value).hex()


def constants_block() -> str:
    """The constants block of ``detmath.h`` (between and including the two marker lines).

    Returns
    -------
    str
        C99 source text: ``static const`` scalars and tables with exact hexadecimal literals,
        preceded by comment lines with the design numbers (reduced-argument ranges and
        polynomial truncation errors).
    """
    items, notes = constants()
    lines = [BEGIN_MARK]
    lines.append("/* Do not edit: regenerate with")
    lines.append(" * `python -m chaplygin.derive.emit.detmath_header --write`.")
    for note in notes:
        lines.append(f" * {note}")
    lines.append(" */")
    for name, ctype, value in items:
        cname = f"chaplygin_dm_{name}"
        if ctype == "double":
            lines.append(f"static const double {cname} = {_format_double(value)};")
        elif ctype == "double[]":
            vals = [_format_double(v) for v in value]
            lines.append(f"static const double {cname}[{len(vals)}] = {{")
            for k in range(0, len(vals), 3):
                lines.append("    " + ", ".join(vals[k : k + 3]) + ",")
            lines.append("};")
        else:  # uint64_t[]
            vals = [f"UINT64_C(0x{v:016x})" for v in value]
            lines.append(f"static const uint64_t {cname}[{len(vals)}] = {{")
            for k in range(0, len(vals), 2):
                lines.append("    " + ", ".join(vals[k : k + 2]) + ",")
            lines.append("};")
    lines.append(END_MARK)
    return "\n".join(lines) + "\n"


def write_header(path: Path | None = None) -> bool:
    """Replace the constants block of ``detmath.h`` with :func:`constants_block`.

    Parameters
    ----------
    path : pathlib.Path, optional
        The header (default :func:`chaplygin.arith.detmath_tables.header_path`).

    Returns
    -------
    bool
        True when the file changed.
    """
    path = header_path() if path is None else path
    text = path.read_text(encoding="utf-8")
    start = text.index(BEGIN_MARK)
    end = text.index(END_MARK) + len(END_MARK) + 1
    new = text[:start] + constants_block() + text[end:]
    if new != text:
        path.write_text(new, encoding="utf-8")
        return True
    return False


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: print the block, or ``--write`` it into the header.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status, 0.
    """
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="write the block into detmath.h")
    args = parser.parse_args(argv)
    if args.write:
        changed = write_header()
        print(f"{header_path()}: {'updated' if changed else 'unchanged'}")
    else:
        sys.stdout.write(constants_block())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
