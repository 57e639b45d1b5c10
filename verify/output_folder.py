"""Output folders of ``chaplygin run``: we write only into folders that are ours, and replace
only files we wrote.

A folder is ours when it holds :data:`MARKER`, a JSON file we wrote that lists the files we
wrote there with their SHA-256 digests. Anything else in it (the user's notes, a copy of the
scene) is never touched. Before any work, :meth:`OutputFolder.check`:

* resolves the path (``results/..``, ``x/../..`` and symbolic links name the folder they lead
  to, and that folder is what is checked);
* accepts a folder that does not exist yet (its nearest existing parent must be a folder
  where files can be created), an empty folder, or a folder of ours in which every file we
  listed is still what we wrote (a regular file with the digest we recorded);
* refuses, in one line, anything else: a non-empty folder without our marker, a file of
  ours the user changed or replaced (by a symbolic link, say), a folder where nothing can be
  created (read-only, not a folder).

:meth:`OutputFolder.write` then writes the new files into a temporary folder beside them,
records them as pending in the marker, moves each into place with :func:`os.replace` (atomic
per file), removes the files of our previous run that this run did not write (only those
still as we wrote them), and records the new list. A run that fails before the moves leaves
the previous results as they were; a crash during the moves leaves files the next run still
recognises as ours (the marker lists both digests).

Names derived from user input (scene file stems) go through :func:`safe_name`.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path

from ..derive.errors import UserInputError

__all__ = [
    "MARKER",
    "OutputFolder",
    "safe_name",
    "current_umask",
    "resolve_path",
    "probe_folder",
]

#: The file that makes a folder ours: the files we wrote there, with their digests.
MARKER = ".chaplygin-run.json"

#: What :data:`MARKER` says it is (a marker of another kind is not ours).
_KIND = "chaplygin run output"
_FORMAT = 1

#: Longest name :func:`safe_name` returns (file systems allow 255 bytes).
_NAME_MAX = 100


def safe_name(text: str, fallback: str = "scene") -> str:
    """A file name made from user text: ASCII letters, digits, ``. _ + -``; no leading dot.

    Every other character becomes ``_``; leading dots are dropped (``..`` and ``...`` name no
    folder of their own and ``.x`` would be hidden); at most 100 characters.

    Parameters
    ----------
    text : str
        A scene file's stem, say.
    fallback : str
        The name when nothing is left.

    Returns
    -------
    str
        Never empty, never ``.`` or ``..``, never containing a path separator.

    Examples
    --------
    >>> safe_name("..")
    'scene'
    >>> safe_name("k01 fig6f/../x")
    'k01_fig6f_.._x'
    """
    name = re.sub(r"[^A-Za-z0-9._+-]", "_", text).lstrip(".")[:_NAME_MAX]
    return name or fallback


def resolve_path(given: str, flag: str) -> Path:
    """The absolute path ``given`` leads to (symbolic links followed, ``..`` after them).

    Parameters
    ----------
    given : str
    flag : str
        For the messages.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    UserInputError
        A name longer than the file system allows, a loop of symbolic links, or a broken
        symbolic link on the way (following it would create folders where it points).
    """
    path = Path(given).expanduser()
    if any(len(os.fsencode(part)) > 255 for part in path.parts) or len(os.fsencode(given)) > 4000:
        raise UserInputError(
            f"{flag} {given[:60]!r}...: longer than a path may be (255 bytes a name, 4000 in all)"
        )
    partial = Path(path.anchor) if path.is_absolute() else Path()
    for part in path.parts[1:] if path.is_absolute() else path.parts:
        partial = partial / part
        if os.path.islink(partial) and not partial.exists():
            raise UserInputError(
                f"{flag} {given!r}: {str(partial)!r} is a broken symbolic link (to "
                f"{os.readlink(partial)!r}); give the folder it should lead to"
            )
    try:
        return path.resolve(strict=False)
    except (OSError, RuntimeError) as exc:  # a loop of symbolic links
        raise UserInputError(f"{flag} {given!r}: cannot resolve the path ({exc})") from None


def _digest(path: Path) -> str | None:
    """SHA-256 of a regular file (not followed through a symbolic link), or None."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | os.O_NONBLOCK)
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        h = hashlib.sha256()
        with os.fdopen(fd, "rb", closefd=False) as fh:
            for block in iter(lambda: fh.read(1 << 20), b""):
                h.update(block)
        return h.hexdigest()
    finally:
        os.close(fd)


def probe_folder(folder: Path) -> str | None:
    """Why no file can be created in ``folder`` (tried, not guessed: permissions, read-only
    file systems and /proc all answer; the probe leaves nothing), or None.

    Parameters
    ----------
    folder : Path

    Returns
    -------
    str or None
    """
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=".chaplygin-probe-"):
            pass
    except OSError as exc:
        return exc.strerror or str(exc)
    return None


class OutputFolder:
    """A folder ``chaplygin run`` may write into (see the module's notes).

    Build it with :meth:`check` (before any work); write with :meth:`write`.

    Attributes
    ----------
    given : str
        The path as the user gave it (for messages).
    target : pathlib.Path
        The folder it resolves to (absolute; symbolic links followed).
    """

    def __init__(self, given: str, target: Path, flag: str):
        self.given, self.target, self.flag = given, target, flag

    # ------------------------------------------------------------------------------ checks
    @classmethod
    def check(cls, path: str | os.PathLike[str], flag: str = "--out") -> OutputFolder:
        """Check, before any work, that a run may write into ``path``.

        Parameters
        ----------
        path : str or path-like
        flag : str
            The flag's name, for the messages.

        Returns
        -------
        OutputFolder

        Raises
        ------
        UserInputError
            The path is empty, is not a folder, cannot be written, or is a non-empty folder
            that is not ours, or holds a file of ours that was changed since.
        """
        given = os.fspath(path)
        if not given.strip():
            raise UserInputError(f"{flag} needs a folder name, got an empty one")
        if "\0" in given:
            raise UserInputError(f"{flag} {given!r}: a path cannot hold a NUL character")
        target = resolve_path(given, flag)
        folder = cls(given, target, flag)
        folder._check_target()
        return folder

    def _refuse(self, reason: str) -> UserInputError:
        where = repr(self.given)
        if self.target != Path(self.given).expanduser().absolute():
            where += f" (that is {str(self.target)!r})"
        return UserInputError(f"{self.flag} {where}: {reason}")

    def _check_target(self) -> None:
        target = self.target
        if target.exists():
            if not target.is_dir():
                raise self._refuse("it exists and is not a folder; give a folder")
            problem = probe_folder(target)
            if problem:
                raise self._refuse(f"no file can be created there ({problem})")
            self.previous()  # refuses a folder that is not ours
            return
        ancestor = target.parent
        while not ancestor.exists():
            ancestor = ancestor.parent
        if not ancestor.is_dir():
            raise self._refuse(f"{str(ancestor)!r} is not a folder")
        problem = probe_folder(ancestor)
        if problem:
            raise self._refuse(f"no folder can be created in {str(ancestor)!r} ({problem})")

    def previous(self) -> dict[str, set[str]]:
        """The files of ours in the folder, each with the digests it may have (recorded and
        pending); empty for a folder that does not exist or is empty.

        Returns
        -------
        dict of str to set of str

        Raises
        ------
        UserInputError
            A non-empty folder without our marker, a damaged marker, or a file of ours that is
            no longer what we wrote.
        """
        target = self.target
        try:
            names = [n for n in os.listdir(target) if not n.startswith(".chaplygin-new-")]
        except FileNotFoundError:
            return {}
        except OSError as exc:
            raise self._refuse(f"cannot list the folder ({exc.strerror or exc})") from None
        if not names:
            return {}
        if MARKER not in names:
            shown = ", ".join(sorted(names)[:3]) + (", ..." if len(names) > 3 else "")
            raise self._refuse(
                f"a non-empty folder that chaplygin run did not make (no {MARKER}; it holds "
                f"{shown}): nothing in it is touched; choose an empty or new folder"
            )
        ours = self._read_marker()
        for name, digests in ours.items():
            path = target / name
            if not os.path.lexists(path):
                continue  # removed by the user: nothing to replace
            if _digest(path) not in digests:
                raise self._refuse(
                    f"{name} was changed or replaced since chaplygin wrote it: it is left "
                    "alone; move it away (or choose another folder) to run again"
                )
        return ours

    def _read_marker(self) -> dict[str, set[str]]:
        path = self.target / MARKER
        try:
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | os.O_NONBLOCK)
            with os.fdopen(fd, "rb") as fh:
                st = os.fstat(fh.fileno())
                ok = stat.S_ISREG(st.st_mode) and st.st_uid == getattr(os, "getuid", lambda: 0)()
                data = json.loads(fh.read(1 << 20).decode("utf-8")) if ok else None
        except (OSError, ValueError):
            data = None
        files = data.get("files") if isinstance(data, dict) else None
        pending = data.get("pending", {}) if isinstance(data, dict) else None
        if (
            not isinstance(data, dict)
            or data.get("kind") != _KIND
            or not isinstance(files, dict)
            or not isinstance(pending, dict)
            or not all(
                isinstance(k, str) and isinstance(v, str) and _plain(k)
                for k, v in (*files.items(), *pending.items())
            )
        ):
            raise self._refuse(
                f"{MARKER} is not one chaplygin run wrote (damaged or foreign): nothing in the "
                "folder is touched; choose another folder"
            )
        ours: dict[str, set[str]] = {}
        for table in (files, pending):
            for name, digest in table.items():
                ours.setdefault(name, set()).add(digest)
        return ours

    # ------------------------------------------------------------------------------ writing
    def write(self, produce: Callable[[Path], list[str]]) -> list[str]:
        """Write a run's files: ``produce(folder)`` writes them into an empty temporary folder
        and returns their names; they are then moved into place (see the module's notes).

        Parameters
        ----------
        produce : callable
            ``produce(folder) -> names`` (plain file names, no folders).

        Returns
        -------
        list of str
            The names written, as ``produce`` returned them.

        Raises
        ------
        UserInputError
            The folder changed since :meth:`check` so that it is no longer ours.
        OSError
            Writing failed (the previous results are then as they were).
        """
        target = self.target
        if not target.exists():
            return self._write_new(produce)
        previous = self.previous()
        tmp = Path(tempfile.mkdtemp(prefix=".chaplygin-new-", dir=target))
        try:
            written = self._produce(produce, tmp)
            new = {name: _digest(tmp / name) or "" for name in written}
            self._write_marker(target, {k: sorted(v)[0] for k, v in previous.items()}, new)
            for name in written:
                os.replace(tmp / name, target / name)
            for name, digests in previous.items():
                path = target / name
                if name not in new and _digest(path) in digests:
                    with contextlib.suppress(FileNotFoundError):
                        path.unlink()
            self._write_marker(target, new, {})
        finally:
            shutil.rmtree(tmp, ignore_errors=True)  # ours: made above
        return written

    def _write_new(self, produce: Callable[[Path], list[str]]) -> list[str]:
        target = self.target
        ancestor = target.parent
        while not ancestor.exists():
            ancestor = ancestor.parent
        tmp = Path(tempfile.mkdtemp(prefix=".chaplygin-new-", dir=ancestor))
        made: list[Path] = []
        try:
            written = self._produce(produce, tmp)
            self._write_marker(tmp, {name: _digest(tmp / name) or "" for name in written}, {})
            for parent in reversed(target.parents):
                if not parent.exists():
                    parent.mkdir()
                    made.append(parent)
            os.chmod(tmp, 0o777 & ~current_umask())  # mkdtemp: 0700; as mkdir would make it
            try:
                os.rename(tmp, target)
            except OSError as exc:
                if exc.errno in (errno.ENOTEMPTY, errno.EEXIST):  # made meanwhile: not ours
                    raise self._refuse("the folder was made by someone else meanwhile") from None
                raise
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)  # ours: made above
            for parent in reversed(made):  # the empty folders we made, innermost first
                with contextlib.suppress(OSError):
                    parent.rmdir()
            raise
        return written

    @staticmethod
    def _produce(produce: Callable[[Path], list[str]], tmp: Path) -> list[str]:
        written = list(produce(tmp))
        for name in written:
            if not _plain(name) or name == MARKER or not (tmp / name).is_file():
                raise RuntimeError(f"a run wrote {name!r}: not a plain file name")  # a bug
        return written

    @staticmethod
    def _write_marker(folder: Path, files: dict[str, str], pending: dict[str, str]) -> None:
        text = json.dumps(
            {"kind": _KIND, "format": _FORMAT, "files": files, "pending": pending},
            indent=1,
            sort_keys=True,
        )
        fd, tmp = tempfile.mkstemp(prefix=".chaplygin-new-", dir=folder)
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                fh.write(text + "\n")
            os.chmod(tmp, 0o666 & ~current_umask())
            os.replace(tmp, folder / MARKER)
        except BaseException:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)
            raise


def _plain(name: str) -> bool:
    """A name of a file directly in the folder (no separator, not ``.``/``..``)."""
    return bool(name) and name not in (".", "..") and "/" not in name and os.sep not in name


def current_umask() -> int:
    """The process's umask, read without changing it (from /proc; 022 where there is none).

    Returns
    -------
    int
    """
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    return 0o022
