"""Compile C source into a shared library, cached per user and keyed by what it depends on.

Stages callable alone: :func:`find_compiler`, :func:`compile_c` (returns the library's path);
loading the library is :mod:`.compiled`'s part (and :mod:`.fastcall`'s for its trampoline).

* **cached and idempotent** -- a library is stored under a key that hashes the source text, the
  compiler (path and ``--version`` output), the flags and the platform; an existing library is
  reused without running the compiler;
* **safe under concurrency** -- the compiler writes a temporary file in the cache directory which
  is then moved into place with :func:`os.replace`; no process-global state (working directory,
  environment, umask) is ever changed.

The flags are ``-O2 -shared -fPIC -std=c99 -ffp-contract=off`` and ``-lm``: no ``-ffast-math``
and no fused multiply-add contraction, so results are IEEE double precision and reproducible
(clang contracts ``a*b + c`` into an FMA by default, hence the explicit ``-ffp-contract=off``;
gcc does on aarch64). ``CHAPLYGIN_OPT_LEVEL`` (``0``..``3``, ``s``) replaces the
optimisation level, for the determinism test (the same bits at every level).

The cache lives in ``$CHAPLYGIN_CACHE_DIR`` if set, else the platform's user cache folder
(:func:`~chaplygin.derive.cachefiles.cache_root`); libraries go into its ``c/`` subfolder
(see :func:`c_cache_dir`).
"""

from __future__ import annotations

import hashlib
import json
import os
import platform
import shlex
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import time
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..derive.cachefiles import (
    cache_root,
    check_private_dir,
    make_private_dir,
    sign,
    verify_signature,
)
from ..derive.emit.c_sources import inline_project_headers
from ..derive.errors import CacheError, ChaplyginError

__all__ = [
    "CFLAGS",
    "LDLIBS",
    "STALE_SECONDS",
    "CacheError",
    "check_cache_dir",
    "CompilerError",
    "CompilerNotFoundError",
    "CompilationError",
    "c_cache_dir",
    "compile_c",
    "find_compiler",
    "LibraryRebuiltWarning",
    "optimisation_override",
]

#: Compiler flags (IEEE-exact: no ``-ffast-math``, no FMA contraction).
CFLAGS: tuple[str, ...] = ("-O2", "-shared", "-fPIC", "-std=c99", "-ffp-contract=off")
#: Libraries linked after the source file.
LDLIBS: tuple[str, ...] = ("-lm",)

#: Compilers tried, in order, when neither ``compiler=`` nor ``CC`` is given.
_DEFAULT_COMPILERS = ("cc", "gcc", "clang")
#: Bump to invalidate every cached library (changes the cache key).
_CACHE_FORMAT = "chaplygin-c-cache-1"
_COMPILE_TIMEOUT = 900.0
_VERSION_TIMEOUT = 60.0
_LIB_SUFFIX = ".dll" if sys.platform == "win32" else ".so"

# --------------------------------------------------------------------------- errors


class CompilerError(ChaplyginError, RuntimeError):
    """The C compiler is missing or could not build the library."""


class CompilerNotFoundError(CompilerError):
    """No C compiler could be found (``compiler=`` argument, ``CC``, ``cc``, ``gcc``)."""


class CompilationError(CompilerError):
    """The C compiler ran but failed (non-zero exit status or time-out)."""


class LibraryRebuiltWarning(UserWarning):
    """A cached library did not match its authenticated record (changed, replaced or planted
    since we built it): it was not loaded, and was built again."""


# --------------------------------------------------------------------------- compiling


def c_cache_dir(cache_dir: str | os.PathLike[str] | None = None) -> Path:
    """Directory holding the compiled libraries.

    Parameters
    ----------
    cache_dir : path-like, optional
        Root of the chaplygin cache.  Default: ``$CHAPLYGIN_CACHE_DIR`` if set and non-empty,
        else the platform's user cache folder (:func:`~chaplygin.derive.cachefiles.cache_root`).

    Returns
    -------
    pathlib.Path
        ``<root>/c`` (not created here).
    """
    return cache_root(cache_dir) / "c"


def find_compiler(compiler: str | None = None) -> list[str]:
    """Command line that invokes the C compiler.

    Parameters
    ----------
    compiler : str, optional
        Compiler command (may contain arguments, e.g. ``"ccache gcc"``).  When given, it is
        the only candidate; otherwise the ``CC`` environment variable is, when set and
        non-empty; otherwise ``cc``, ``gcc`` and ``clang`` are searched on ``PATH``.

    Returns
    -------
    list of str
        The command split into words, its program resolved to an absolute path.

    Raises
    ------
    CompilerNotFoundError
        If the chosen candidate (or, without a choice, every default) is not found.
    """
    if compiler is None:
        compiler = os.environ.get("CC") or None
        origin = "the CC environment variable"
    else:
        origin = "the compiler argument"
    if compiler is not None:
        words = shlex.split(compiler)
        found = shutil.which(words[0]) if words else None
        if found is None:
            raise CompilerNotFoundError(
                f"C compiler {compiler!r} (from {origin}) not found; install it or point CC "
                "to an installed C compiler"
            )
        return [found, *words[1:]]
    for name in _DEFAULT_COMPILERS:
        found = shutil.which(name)
        if found is not None:
            return [found]
    raise CompilerNotFoundError(
        f"no C compiler found on PATH (tried {', '.join(_DEFAULT_COMPILERS)}); install one "
        "(e.g. gcc) or set the CC environment variable"
    )


_identity_cache: dict[tuple[Any, ...], str] = {}


def _compiler_identity(argv: Sequence[str]) -> str:
    """Path, file stamp and ``--version`` output of the compiler (memoised per process)."""
    try:
        st = os.stat(argv[0])
    except OSError as exc:
        raise CompilerNotFoundError(f"C compiler {argv[0]!r} not usable: {exc}") from exc
    memo_key = (tuple(argv), st.st_mtime_ns, st.st_size, st.st_ino)
    identity = _identity_cache.get(memo_key)
    if identity is None:
        try:
            proc = subprocess.run(
                [*argv, "--version"],
                capture_output=True,
                text=True,
                errors="replace",
                stdin=subprocess.DEVNULL,
                timeout=_VERSION_TIMEOUT,
                check=False,
            )
        except (OSError, subprocess.SubprocessError) as exc:
            raise CompilerNotFoundError(
                f"C compiler {shlex.join(argv)!r} cannot be run: {exc}"
            ) from exc
        identity = "\n".join([shlex.join(argv), proc.stdout.strip(), proc.stderr.strip()])
        _identity_cache[memo_key] = identity
    return identity


def _platform_tag() -> str:
    return f"{sysconfig.get_platform()}|{platform.machine()}|{sys.platform}"


def _cache_key(source: str, identity: str, flags: Sequence[str]) -> str:
    h = hashlib.sha256()
    for part in (_CACHE_FORMAT, source, identity, shlex.join(flags), _platform_tag()):
        h.update(part.encode("utf-8", "surrogatepass"))
        h.update(b"\0")
    return h.hexdigest()


def _unlink_quietly(path: str | os.PathLike[str]) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass


#: A build's temporaries older than this are left over from a killed build: removed.
STALE_SECONDS = 3600.0


def check_cache_dir(directory: str | os.PathLike[str]) -> None:
    """Refuse a cache folder (or a parent up to the cache root) others could write to.

    A library in the cache is loaded with ``dlopen``: whoever can write there can run code
    in our process. The folder must be owned by the current user and not writable by group
    or others (a parent may be shared only if it has the sticky bit, like ``/tmp``).

    Parameters
    ----------
    directory : path-like
        The folder holding the compiled libraries (it may not exist yet).

    Raises
    ------
    CacheError
        The folder or its cache root is writable by others or owned by another user.
    """
    check_private_dir(directory)


def _digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _record_path(library: Path) -> Path:
    return library.with_name(library.name + ".record")


#: What the MAC of a library's record covers (with its name, size and SHA-256).
_RECORD_DOMAIN = b"chaplygin compiled library 1\0"


def _mac_message(library: Path, size: int, digest: str) -> bytes:
    return _RECORD_DOMAIN + f"{library.name}\0{size}\0{digest}".encode()


def _write_record(library: Path) -> None:
    """Record size, SHA-256 and a keyed MAC of a library just built (written atomically).

    The MAC is an HMAC-SHA256 with the cache folder's per-user secret
    (:func:`chaplygin.derive.cachefiles.sign`, as the model pickles are signed): a record
    made by anyone without that secret does not verify.
    """
    size, digest = library.stat().st_size, _digest(library)
    mac = sign(library.parent, _mac_message(library, size, digest))
    record = json.dumps({"size": size, "sha256": digest, "mac": mac})
    fd, tmp = tempfile.mkstemp(prefix=".tmp-record-", dir=library.parent)
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        fh.write(record)
    os.replace(tmp, _record_path(library))


def _record_matches(library: Path) -> bool | None:
    """Whether the library is exactly what our build wrote: its size and SHA-256 as recorded,
    and the record's MAC made with our secret. None for no record, or a record of an older
    version (no MAC) that matches the file: not loaded either, but built again without a
    warning."""
    try:
        text = _record_path(library).read_text(encoding="utf-8")
    except FileNotFoundError:
        return None  # unrecorded (a build killed before its record): built again quietly
    except (OSError, ValueError):  # unreadable, not UTF-8
        return False
    try:
        record = json.loads(text)
        if not isinstance(record, dict):
            return False
        size, digest = library.stat().st_size, _digest(library)
        if record.get("size") != size or record.get("sha256") != digest:
            return False
        mac = record.get("mac")
        if mac is None:
            return None
        return isinstance(mac, str) and verify_signature(
            library.parent, _mac_message(library, size, digest), mac
        )
    except (OSError, ValueError):
        return False


def _remove_stale_temporaries(directory: Path) -> None:
    """Remove our ``.tmp-*`` files that a killed build left behind (older than an hour)."""
    now = time.time()
    for path in directory.glob(".tmp-*"):
        try:
            st = path.stat()
            if now - st.st_mtime > STALE_SECONDS and st.st_uid == os.getuid():
                path.unlink()
        except OSError:
            continue


#: Optimisation levels ``CHAPLYGIN_OPT_LEVEL`` may select.
OPT_LEVELS = ("0", "1", "2", "3", "s")


def optimisation_override() -> tuple[str, ...]:
    """``("-O<level>",)`` from ``CHAPLYGIN_OPT_LEVEL`` (one of :data:`OPT_LEVELS`), else ``()``.

    The level is applied after every other flag (and is part of the cache key). The results
    do not depend on it -- the generated code is IEEE-exact at every level (no FMA
    contraction, the project's own elementary functions) -- which the determinism test
    checks; the variable exists so that it can.

    Returns
    -------
    tuple of str

    Raises
    ------
    CompilerError
        The variable holds anything else.
    """
    level = os.environ.get("CHAPLYGIN_OPT_LEVEL", "").strip()
    if not level:
        return ()
    if level not in OPT_LEVELS:
        raise CompilerError(
            f"CHAPLYGIN_OPT_LEVEL={level!r} is not an optimisation level: use one of "
            f"{', '.join(OPT_LEVELS)}"
        )
    return (f"-O{level}",)


def compile_c(
    source: str,
    *,
    cache_dir: str | os.PathLike[str] | None = None,
    compiler: str | None = None,
    force: bool = False,
    ldlibs: Sequence[str] = (),
    cflags: Sequence[str] = (),
) -> Path:
    """Compile C source to a shared library, or reuse the cached one.

    Parameters
    ----------
    source : str
        Complete C99 translation unit.
    cache_dir : path-like, optional
        Root of the cache (see :func:`c_cache_dir`); the library goes into ``<root>/c``.
    compiler : str, optional
        Compiler command; see :func:`find_compiler` (default: ``CC``, else ``cc``/``gcc``).
    force : bool, default False
        Recompile even when the library is cached (replacing it atomically).
    ldlibs : sequence of str, optional
        Extra libraries linked after :data:`LDLIBS` (``("-lquadmath",)``); part of the key.
    cflags : sequence of str, optional
        Extra compiler flags after :data:`CFLAGS` (include folders ``-I...``); part of the key.

    Returns
    -------
    pathlib.Path
        The shared library ``<root>/c/<sha256>.so``; the key hashes the source, the compiler
        identity, :data:`CFLAGS` + :data:`LDLIBS` and the platform.  The source is kept next
        to it as ``<sha256>.c`` for inspection.

    Raises
    ------
    CompilerNotFoundError
        If no compiler can be found or run.
    CompilationError
        If the compiler fails; the message holds its command line and diagnostics.
    OSError
        If the cache directory cannot be created or written.

    Notes
    -----
    The compiler writes to a temporary file in the cache directory that is then moved into
    place with :func:`os.replace`: concurrent builds of the same source (threads or processes)
    are safe and the final library is never seen half-written.
    """
    argv = find_compiler(compiler)
    source = inline_project_headers(source)
    cflags = (*cflags, *optimisation_override())
    flags = (*CFLAGS, *cflags, *LDLIBS, *ldlibs)
    key = _cache_key(source, _compiler_identity(argv), flags)
    directory = c_cache_dir(cache_dir)
    target = directory / f"{key}{_LIB_SUFFIX}"
    if not force and target.is_file():
        check_cache_dir(directory)
        matches = _record_matches(target)
        if matches:
            return target
        # damaged, replaced, planted or unrecorded: never load it, build it again
        if matches is False:
            warnings.warn(
                f"the cached library {target} does not match its record (changed, replaced "
                "or planted since it was built): not loaded; building it again",
                LibraryRebuiltWarning,
                stacklevel=2,
            )

    try:
        make_private_dir(directory)
    except OSError as exc:
        raise CacheError(
            f"cannot create the cache folder {directory}: {exc.strerror or exc}; set "
            "CHAPLYGIN_CACHE_DIR to a writable folder"
        ) from None
    check_cache_dir(directory)
    if not os.access(directory, os.W_OK | os.X_OK):
        raise CacheError(
            f"the cache folder {directory} is read-only: compiled code cannot be stored; set "
            "CHAPLYGIN_CACHE_DIR to a writable folder"
        )
    _remove_stale_temporaries(directory)
    prefix = f".tmp-{key[:16]}-"
    fd, tmp_c = tempfile.mkstemp(prefix=prefix, suffix=".c", dir=directory)
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        fh.write(source)
    fd, tmp_lib = tempfile.mkstemp(prefix=prefix, suffix=_LIB_SUFFIX, dir=directory)
    os.close(fd)
    command = [*argv, *CFLAGS, *cflags, "-o", tmp_lib, tmp_c, *LDLIBS, *ldlibs]
    try:
        try:
            proc = subprocess.run(
                command,
                capture_output=True,
                text=True,
                errors="replace",
                stdin=subprocess.DEVNULL,
                timeout=_COMPILE_TIMEOUT,
                check=False,
            )
        except FileNotFoundError as exc:
            raise CompilerNotFoundError(f"C compiler {argv[0]!r} not found: {exc}") from exc
        except (OSError, subprocess.SubprocessError) as exc:
            raise CompilationError(f"running {shlex.join(command)} failed: {exc}") from exc
        if proc.returncode != 0 or os.path.getsize(tmp_lib) == 0:
            diagnostics = (proc.stderr or proc.stdout).strip()
            if len(diagnostics) > 4000:
                diagnostics = diagnostics[:4000] + "\n[...]"
            raise CompilationError(
                f"{shlex.join(command)} exited with status {proc.returncode}:\n{diagnostics}"
            )
        os.chmod(tmp_lib, 0o700)  # the linker's mode follows the umask (0777 under umask 0)
        os.replace(tmp_c, directory / f"{key}.c")
        os.replace(tmp_lib, target)
        _write_record(target)
    finally:
        _unlink_quietly(tmp_c)
        _unlink_quietly(tmp_lib)
    return target
