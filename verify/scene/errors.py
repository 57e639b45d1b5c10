"""Problems with a scene: :class:`SceneError`, key paths and the lines they are on.

Every problem with a scene is one :class:`SceneError` (a :class:`UserInputError`): its message
names the file, the dotted key path and, where it can be found, the line; unknown keys and names
list the valid choices with a "did you mean".
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any

from pydantic import BaseModel, ValidationError

from ...derive.errors import UserInputError, did_you_mean

__all__ = [
    "SceneError",
    "KeyProblem",
    "did_you_mean",
    "dotted",
    "key_name_on",
    "line_of",
    "validation_error",
]


class SceneError(UserInputError):
    """A scene that cannot be used: the message names the file, key path and line.

    Attributes
    ----------
    file : str or None
    path : str
        Dotted key path (``"initial.h"``), empty for the whole file.
    line : int or None
    """

    def __init__(
        self, message: str, file: str | None = None, path: str = "", line: int | None = None
    ):
        self.file, self.path, self.line = file, path, line
        where = file or "<scene>"
        if line is not None:
            where += f":{line}"
        if path:
            where += f": {path}"
        # one line, always (the CLI prints it on stderr)
        super().__init__(f"{where}: {' '.join(str(message).split())}")


class KeyProblem(ValueError):
    """Raised by a validator of the scene's models: ``message`` about the key at ``loc``."""

    def __init__(self, loc: tuple, message: str):
        super().__init__(message)
        self.loc, self.message = loc, message


def dotted(loc: Sequence) -> str:
    """A key path as written in messages: ``("outputs", "series", "quantities", 2)`` ->
    ``outputs.series.quantities[2]``.

    Parameters
    ----------
    loc : sequence of str or int

    Returns
    -------
    str
    """
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


_HEADER = re.compile(r"^\s*\[\s*([A-Za-z0-9_.\-\" ]+?)\s*\]\s*(#.*)?$")
_KEY = re.compile(r"^\s*([A-Za-z0-9_\-]+)\s*=")


def key_name_on(line: str) -> str | None:
    """The key a TOML line assigns (``h = 0.2`` -> ``"h"``), or None.

    Parameters
    ----------
    line : str

    Returns
    -------
    str or None
    """
    m = _KEY.match(line)
    return m.group(1) if m else None


def line_of(text: str | None, loc: Sequence) -> int | None:
    """Line (1-based) of the deepest key of ``loc`` found in ``text`` (None when not found).

    Parameters
    ----------
    text : str or None
        The scene's TOML text.
    loc : sequence of str or int
        A key path (indices are skipped).

    Returns
    -------
    int or None
    """
    if not text:
        return None
    keys = [str(k) for k in loc if not isinstance(k, int)]
    best = None
    for depth in range(len(keys), 0, -1):
        table, key = keys[: depth - 1], keys[depth - 1]
        current: list[str] = []
        for number, line in enumerate(text.splitlines(), 1):
            header = _HEADER.match(line)
            if header:
                current = [p.strip().strip('"') for p in header.group(1).split(".")]
                if current == keys[:depth]:
                    best = number
                    break
                continue
            m = _KEY.match(line)
            if m and m.group(1) == key and current == table:
                best = number
                break
            # inline tables: key = { ... inner = ... }
            if m and current == table[:-1] and table and m.group(1) == table[-1]:
                if re.search(rf"[{{,]\s*{re.escape(key)}\s*=", line):
                    best = number
                    break
        if best is not None:
            return best
    return None


def _fields_of(model: Any, loc: Sequence) -> list[str]:
    """Valid keys of the table at ``loc`` of ``model`` (for unknown-key messages)."""
    for part in loc:
        if isinstance(part, int) or model is None:
            return []
        info = next((f for n, f in model.model_fields.items() if (f.alias or n) == part), None)
        if info is None:
            return []
        ann = info.annotation
        model = next(
            (
                a
                for a in (ann, *getattr(ann, "__args__", ()))
                if isinstance(a, type) and issubclass(a, BaseModel)
            ),
            None,
        )
    if model is None:
        return []
    return [f.alias or n for n, f in model.model_fields.items()]


def _input_path(loc: Sequence, data: object) -> tuple:
    """The parts of a pydantic ``loc`` that are keys or indices of the input (pydantic also
    puts the names of union members and validators in it)."""
    out, node = [], data
    for part in loc:
        if isinstance(node, Mapping) and isinstance(part, str) and part in node:
            out.append(part)
            node = node[part]
        elif isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node):
            out.append(part)
            node = node[part]
    return tuple(out)


def validation_error(
    exc: ValidationError,
    model: type[BaseModel],
    source: str | None,
    text: str | None,
    data: object = None,
) -> SceneError:
    """The first problem pydantic found, as one :class:`SceneError` with key path and line.

    Parameters
    ----------
    exc : pydantic.ValidationError
    model : type
        The root model validated (its fields name the valid keys of each table).
    source : str or None
        File name.
    text : str or None
        The TOML text.
    data : object
        The data validated.

    Returns
    -------
    SceneError
    """
    err = exc.errors(include_url=False)[0]
    loc = _input_path(err["loc"], data)
    if err["type"] == "missing" and err["loc"]:
        loc = (*loc, err["loc"][-1])
    kind, msg = err["type"], err["msg"]
    ctx_error = (err.get("ctx") or {}).get("error")
    if isinstance(ctx_error, KeyProblem):
        loc, msg = ctx_error.loc, ctx_error.message
    elif isinstance(ctx_error, ValueError):
        msg = str(ctx_error)
    if kind == "extra_forbidden":
        valid = _fields_of(model, loc[:-1])
        msg = (
            f"unknown key {loc[-1]!r}; valid keys here: {', '.join(valid)}"
            f"{did_you_mean(loc[-1], valid)}"
        )
    elif kind == "missing":
        msg = "required key is missing"
    elif kind == "literal_error":
        expected = (err.get("ctx") or {}).get("expected", "")
        choices = re.findall(r"'([^']*)'", expected)
        msg = f"{err['input']!r} is not valid; valid: {', '.join(choices)}" + did_you_mean(
            err["input"], choices
        )
    elif kind.endswith("_type") or kind in ("model_type", "dict_type", "list_type"):
        msg = f"{msg}, got {type(err['input']).__name__} {_short(err['input'])}"
    path = dotted(loc)
    line = line_of(text, loc) if kind != "missing" else line_of(text, loc[:-1])
    return SceneError(msg, source, path, line)


def _short(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
