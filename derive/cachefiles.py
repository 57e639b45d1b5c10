"""Where the caches live, who may write there, and files only we can have written.

Both caches (derived models, compiled libraries) live under one root (:func:`cache_root`):
``$CHAPLYGIN_CACHE_DIR``, else the platform's user cache folder as platformdirs gives it
(``$XDG_CACHE_HOME/chaplygin`` or ``~/.cache/chaplygin`` on Linux, ``~/Library/Caches/chaplygin``
on macOS, ``%LOCALAPPDATA%\\chaplygin\\Cache`` on Windows).
What is loaded from there can run code in our process (a pickle, a shared library), so a
folder other users can write to is refused, and a model file is loaded only when it
carries an HMAC made with a per-user secret key that only we can read.
"""

from __future__ import annotations

import hashlib
import hmac
import os
import secrets
import stat
import tempfile
from pathlib import Path

import platformdirs

from .errors import CacheError

__all__ = [
    "cache_root",
    "check_private_dir",
    "make_private_dir",
    "sign",
    "verify_signature",
    "read_signed",
    "write_signed",
    "KEY_FILE",
]

#: The per-user secret of the cache root (mode 0600), made on first use.
KEY_FILE = "cache.key"


def cache_root(cache_dir: str | os.PathLike[str] | None = None) -> Path:
    """Root folder of the caches.

    Parameters
    ----------
    cache_dir : path-like, optional
        An explicit root (tests, the compile cache's argument).

    Returns
    -------
    pathlib.Path
        ``cache_dir``, else ``$CHAPLYGIN_CACHE_DIR``, else the platform's user cache folder
        of ``chaplygin`` (``platformdirs.user_cache_dir``: it honours ``$XDG_CACHE_HOME``);
        not created here.
    """
    if cache_dir is not None:
        root = Path(cache_dir)
    elif os.environ.get("CHAPLYGIN_CACHE_DIR"):
        root = Path(os.environ["CHAPLYGIN_CACHE_DIR"])
    else:
        root = Path(platformdirs.user_cache_dir("chaplygin", appauthor=False))
    return root.expanduser()


def check_private_dir(directory: str | os.PathLike[str]) -> None:
    """Refuse a cache folder others could write to.

    The folder must be owned by the current user and not writable by group or others; its
    parent may be shared only with the sticky bit (like ``/tmp``), where others cannot
    replace what is ours.

    Parameters
    ----------
    directory : path-like
        The folder (it may not exist yet: then only its parent is checked).

    Raises
    ------
    CacheError
        The folder or its parent can be written by other users.
    """
    if not hasattr(os, "getuid"):  # pragma: no cover - Windows
        return
    path = Path(directory)
    for folder, sticky_ok in ((path, False), (path.parent, True)):
        try:
            st = folder.stat()
        except FileNotFoundError:
            continue
        others_write = st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)
        shared = others_write and not (sticky_ok and st.st_mode & stat.S_ISVTX)
        if (st.st_uid != os.getuid() and not sticky_ok) or shared:
            raise CacheError(
                f"the cache folder {folder} can be written by other users (mode "
                f"{stat.filemode(st.st_mode)}, owner uid {st.st_uid}): what is loaded from it "
                "could be theirs; use a private folder (chmod go-w, or set "
                "CHAPLYGIN_CACHE_DIR to a folder of your own)"
            )


def make_private_dir(directory: str | os.PathLike[str]) -> Path:
    """Create ``directory`` and its missing parents readable and writable by us alone
    (mode 0700 whatever the umask: under umask 002 or 000 a folder made by ``mkdir`` would be
    group- or world-writable, and :func:`check_private_dir` would refuse it). Folders that
    exist are left as they are.

    Parameters
    ----------
    directory : path-like

    Returns
    -------
    pathlib.Path

    Raises
    ------
    OSError
        A folder cannot be created.
    """
    path = Path(directory)
    missing = []
    for folder in (path, *path.parents):
        if folder.exists():
            break
        missing.append(folder)
    for folder in reversed(missing):
        try:
            folder.mkdir(mode=0o700)
        except FileExistsError:  # made meanwhile (another process): not ours to change
            continue
        os.chmod(folder, 0o700)  # the umask may have taken bits from 0700 too
    return path


def _key(root: Path) -> bytes:
    """The secret of ``root`` (made on first use, readable by us alone)."""
    path = root / KEY_FILE
    try:
        key = path.read_bytes()
        if len(key) == 32 and path.stat().st_uid == getattr(os, "getuid", lambda: -1)():
            return key
    except OSError:
        pass
    make_private_dir(root)
    key = secrets.token_bytes(32)
    tmp = root / f".tmp-key-{secrets.token_hex(8)}"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "wb") as fh:
        fh.write(key)
    os.replace(tmp, path)
    return key


def sign(root: Path, data: bytes) -> str:
    """HMAC-SHA256 of ``data`` with the secret of ``root``.

    Parameters
    ----------
    root : pathlib.Path
        The cache root holding the secret.
    data : bytes

    Returns
    -------
    str
        The tag, 64 hex digits.
    """
    return hmac.new(_key(root), data, hashlib.sha256).hexdigest()


def verify_signature(root: Path, data: bytes, tag: str) -> bool:
    """True when ``tag`` is our HMAC of ``data`` (constant-time comparison).

    Parameters
    ----------
    root : pathlib.Path
    data : bytes
    tag : str

    Returns
    -------
    bool
    """
    return hmac.compare_digest(sign(root, data), tag)


def read_signed(path: Path | None, magic: bytes) -> bytes | None:
    """The data of a file :func:`write_signed` wrote, or None (absent, damaged, not ours).

    The file is ``magic``, the HMAC of the data (a line), then the data; nothing of it is
    returned unless the HMAC, made with the folder's per-user secret, checks out.

    Parameters
    ----------
    path : pathlib.Path or None
    magic : bytes
        The first line, ending in a newline (the format and its version).

    Returns
    -------
    bytes or None

    Raises
    ------
    CacheError
        The folder can be written by other users.
    """
    if path is None or not path.is_file():
        return None
    check_private_dir(path.parent)
    try:
        blob = path.read_bytes()
    except OSError:
        return None
    head, _, rest = blob.partition(b"\n")
    tag, _, data = rest.partition(b"\n")
    if head + b"\n" != magic or not verify_signature(
        path.parent, data, tag.decode("ascii", "replace")
    ):
        return None
    return data


def write_signed(path: Path | None, magic: bytes, data: bytes) -> bool:
    """Write ``data`` signed (see :func:`read_signed`), atomically: parallel processes may
    write the same file at once.

    Parameters
    ----------
    path : pathlib.Path or None
        None: nothing is written.
    magic : bytes
    data : bytes

    Returns
    -------
    bool
        False when the file could not be written (a read-only home: the caches are an aid).

    Raises
    ------
    CacheError
        The folder can be written by other users.
    """
    if path is None:
        return False
    tmp = None
    try:
        make_private_dir(path.parent)
        check_private_dir(path.parent)
        tag = sign(path.parent, data).encode("ascii")
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
        with os.fdopen(fd, "wb") as fh:
            fh.write(magic + tag + b"\n" + data)
        os.replace(tmp, path)
        return True
    except OSError:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass
        return False
