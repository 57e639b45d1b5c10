"""Reading a scene file: the bytes with limits (a regular file of at most
:data:`MAX_SCENE_BYTES`), TOML nested at most :data:`MAX_SCENE_DEPTH` deep, ``--set`` overrides,
and the title's ``{dotted.key}`` placeholders. Every problem is one :class:`SceneError`.
"""

from __future__ import annotations

import json
import re
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path

from ...derive.errors import UserInputError
from .errors import SceneError, key_name_on, line_of

__all__ = [
    "MAX_SCENE_BYTES",
    "MAX_SCENE_DEPTH",
    "read_scene_file",
    "parse_toml",
    "check_depth",
    "text_of",
    "apply_overrides",
    "render_title",
    "stale_overrides",
    "mask_overridden",
]


#: Largest scene file read (a scene is a few kilobytes; a sweep's long list of values fits).
MAX_SCENE_BYTES = 1 << 20

#: Deepest nesting of tables and lists in a scene (the schema's deepest is 5:
#: ``sweep.axes."parameters.D".start``, or a list in a table of a table).
MAX_SCENE_DEPTH = 16


def read_scene_file(path: str | Path) -> bytes:
    """The bytes of a scene file, read with limits: a regular file (a FIFO, a device such as
    ``/dev/zero`` or a folder is refused without being opened for reading, so nothing
    blocks) of at most :data:`MAX_SCENE_BYTES`.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    bytes

    Raises
    ------
    SceneError
        Missing, unreadable, not a regular file, or too large.
    """
    import os
    import stat

    name = str(path)
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode):
            kind = "a folder" if stat.S_ISDIR(st.st_mode) else "not a regular file"
            raise SceneError(f"cannot read the scene: it is {kind} (a scene is a TOML file)", name)
        # O_NONBLOCK: a FIFO put there since the check cannot block the open
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
        with os.fdopen(fd, "rb") as fh:
            st = os.fstat(fh.fileno())
            if not stat.S_ISREG(st.st_mode):
                raise SceneError("cannot read the scene: it is not a regular file", name)
            raw = fh.read(MAX_SCENE_BYTES + 1)
    except SceneError:
        raise
    except (OSError, ValueError) as exc:
        reason = getattr(exc, "strerror", None) or exc
        raise SceneError(f"cannot read the scene: {reason}", name) from None
    if len(raw) > MAX_SCENE_BYTES:
        raise SceneError(
            f"the scene file is larger than {MAX_SCENE_BYTES // 1024} KiB (a scene is a few "
            "kilobytes; give long ranges of a sweep as {start, stop, num})",
            name,
        )
    return raw


def parse_toml(text: str, source: str | None, what: str = "TOML syntax") -> dict:
    """``tomllib.loads`` with its failures as one-line :class:`SceneError` (deep nesting
    included: the parser recurses).

    Parameters
    ----------
    text : str
    source : str or None
        File name for the messages.
    what : str
        What the text is, for the messages.

    Returns
    -------
    dict

    Raises
    ------
    SceneError
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = re.search(r"line (\d+)", str(exc))
        raise SceneError(
            f"{what}: {exc}", source, line=int(line.group(1)) if line else None
        ) from None
    except (RecursionError, MemoryError):
        raise SceneError(
            f"{what}: nested deeper than {MAX_SCENE_DEPTH} tables or lists", source
        ) from None
    check_depth(data, source)
    return data


def check_depth(data: object, source: str | None) -> None:
    """Refuse data nested deeper than :data:`MAX_SCENE_DEPTH` (walked without recursion).

    Parameters
    ----------
    data : object
    source : str or None
        File name for the messages.

    Raises
    ------
    SceneError
    """
    stack = [(data, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_SCENE_DEPTH:
            raise SceneError(f"nested deeper than {MAX_SCENE_DEPTH} tables or lists", source)
        if isinstance(node, Mapping):
            stack.extend((v, depth + 1) for v in node.values())
        elif isinstance(node, list | tuple):
            stack.extend((v, depth + 1) for v in node)


#: ``{initial.h}`` in a title: the value of that key (``{{`` and ``}}`` are literal braces).
_PLACEHOLDER = re.compile(r"\{\{|\}\}|\{([A-Za-z0-9_\-]+(?:\.[A-Za-z0-9_\-]+)*)\}")


def _title_value(value: object) -> str:
    """A scene value as a title shows it: text as written, lists as ``(a, b, c)``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list | tuple):
        return "(" + ", ".join(_title_value(v) for v in value) + ")"
    return str(value)


def _placeholders(title: str) -> list[str]:
    return [m.group(1) for m in _PLACEHOLDER.finditer(title) if m.group(1)]


def render_title(title: str, given: Mapping) -> str:
    """The title with each ``{dotted.key}`` replaced by that key's value in the scene.

    A title written with placeholders (``"K01 Fig. 7(a): h = {initial.h}"``) shows the values
    that run, also after ``--set``; ``{{`` and ``}}`` are literal braces.

    Parameters
    ----------
    title : str
    given : mapping
        The scene as given (``--set`` applied).

    Returns
    -------
    str

    Raises
    ------
    UserInputError
        A placeholder that names no key of the scene.
    """

    def value(match: re.Match) -> str:
        if match.group(0) in ("{{", "}}"):
            return match.group(0)[0]
        node: object = given
        for part in match.group(1).split("."):
            if not isinstance(node, Mapping) or part not in node:
                raise UserInputError(
                    f"{{{match.group(1)}}} in the title names no key of the scene "
                    "(write a dotted key such as {initial.h}, or {{ }} for braces)"
                )
            node = node[part]
        return _title_value(node)

    return _PLACEHOLDER.sub(value, title)


def stale_overrides(title: object, overrides: Sequence[str], given: Mapping) -> str:
    """``--set`` items (as run) whose keys the title does not show by a placeholder.

    Parameters
    ----------
    title : object
        The title as written.
    overrides : sequence of str
    given : mapping
        The scene as given (``--set`` applied).

    Returns
    -------
    str
        ``"key = value, ..."``, empty when the title shows every key set.
    """
    shown = _placeholders(title) if isinstance(title, str) else []
    out = []
    for item in overrides:
        key = item.partition("=")[0].strip()
        if key == "title" or any(
            key == k or key.startswith(k + ".") or k.startswith(key + ".") for k in shown
        ):
            continue
        node: object = given
        for part in key.split("."):
            node = node.get(part) if isinstance(node, Mapping) else None
        out.append(f"{key} = {_title_value(node)}")
    return ", ".join(out)


def mask_overridden(text: str, overrides: Sequence[str]) -> str:
    """``text`` with the lines of keys given by ``--set`` blanked, so that no message points at
    a line whose value was replaced.

    Parameters
    ----------
    text : str
    overrides : sequence of str

    Returns
    -------
    str
    """
    lines = text.splitlines()
    for item in overrides:
        key = item.partition("=")[0].strip()
        line = line_of("\n".join(lines), key.split("."))
        if line is not None and key_name_on(lines[line - 1] or "") == key.split(".")[-1]:
            lines[line - 1] = ""
    return "\n".join(lines)


def apply_overrides(data: Mapping, overrides: Sequence[str], source: str | None = None) -> dict:
    """``KEY=VALUE`` overrides (``run.t_end=100``) applied to a parsed scene.

    Parameters
    ----------
    data : mapping
        The parsed TOML.
    overrides : sequence of str
        Dotted key, ``=``, a TOML value (``100``, ``[1, 3, 5]``, ``"sqrt(2)"``, ``true``); a
        value that is not TOML is taken as text.
    source : str, optional
        File name for the messages.

    Returns
    -------
    dict
        A new mapping (``data`` is not changed).

    Raises
    ------
    SceneError
        A malformed item, or a key path through something that is not a table.
    """
    out = json.loads(json.dumps(data, default=str)) if overrides else dict(data)
    for item in overrides:
        key, sep, value = item.partition("=")
        key = key.strip()
        parts = key.split(".")
        if not sep or not key or not all(re.fullmatch(r"[A-Za-z0-9_\-]+", p) for p in parts):
            raise SceneError(f"--set expects KEY=VALUE with a dotted KEY, got {item!r}", source)
        try:
            parsed = tomllib.loads(f"v = {value.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            parsed = value.strip()
        except (RecursionError, MemoryError):
            raise SceneError(
                f"--set {key}: nested deeper than {MAX_SCENE_DEPTH} tables or lists", source
            ) from None
        check_depth(parsed, source)
        node = out
        for i, part in enumerate(parts[:-1]):
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                raise SceneError(
                    f"--set {key}: {'.'.join(parts[: i + 1])} is not a table", source, key
                )
        node[parts[-1]] = parsed
    return out


def text_of(source: str | None) -> str | None:
    """The text of a scene file, or None when there is none or it cannot be read.

    Parameters
    ----------
    source : str or None

    Returns
    -------
    str or None
    """
    if not source:
        return None
    try:
        return read_scene_file(source).decode("utf-8")
    except (SceneError, UnicodeDecodeError):
        return None
