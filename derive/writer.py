"""Write the built-in models' code to ``generated/`` and check that it is up to date."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

from .cachefiles import read_signed, write_signed
from .emit import EMITTERS, ModelRoutines, get_emitter
from .emit.base import GENERATOR_VERSION
from .errors import UserInputError
from .systems import build_model, builtin_variants, variant_cache_file

__all__ = [
    "render_generated",
    "write_generated",
    "check_generated",
    "is_ours",
    "refuse_foreign",
    "MANIFEST",
]

MANIFEST = "manifest.json"

_INIT = '''"""Code emitted by ``chaplygin derive`` for the built-in models. DO NOT EDIT.

Per model variant (``<system>[__<effect>...]``) the files of every emitter of
``chaplygin.derive.emit``: numpy, mpmath and C modules, the Taylor recurrences in Python, C and
C on MPFR, the Taylor program as data and the right-hand side in vector lanes;
``manifest.json`` maps each variant to its model hash and files. ``chaplygin derive
--check`` fails when any file here differs from a fresh emission.
"""
'''


#: Emitted files per (model hash, generator version, language): emission is a pure function
#: of the model, and a process that renders twice (``derive --check`` then ``derive``, the
#: tests) pays for it once.
_EMITTED: dict[tuple[str, str, str], tuple[tuple[str, str], ...]] = {}

#: First line of a rendered-variant file: the format, then the HMAC of the JSON that follows.
_RENDERED_MAGIC = b"chaplygin-rendered-1\n"


class _LazyRoutines:
    """The model's routines, built on first use (not at all when every emission is memoised)."""

    def __init__(self, model):
        self.model = model
        self.value = None

    def get(self):
        if self.value is None:
            self.value = ModelRoutines(self.model)
        return self.value


def rendered_cache_file(system: str, effects: frozenset[str]) -> Path | None:
    """The cache file of a built-in variant's emitted files: ``<cache root>/rendered/`` under
    the model cache's key (:func:`~chaplygin.derive.systems.variant_cache_file`: a new key with
    any edit of ``derive/``, the emitters included), so that a later process (``derive
    --check`` after the tests, CI) does not emit the same text again.

    Parameters
    ----------
    system : str
    effects : frozenset of str
        Validated effect names.

    Returns
    -------
    pathlib.Path or None
        None when the caches are off (``CHAPLYGIN_MODEL_CACHE=0``).
    """
    return variant_cache_file("rendered", system, effects, ".json")


def _load_rendered(path: Path | None, model) -> dict[str, list[list[str]]]:
    """Emitted files per language from ``path``, or {} (absent, damaged, not ours, or another
    model or generator): read only when its HMAC (the cache root's per-user secret) checks out."""
    data = read_signed(path, _RENDERED_MAGIC)
    if data is None:
        return {}
    try:
        entry = json.loads(data)
    except ValueError:
        return {}
    if (
        not isinstance(entry, dict)
        or entry.get("model_hash") != model.hash
        or entry.get("generator") != GENERATOR_VERSION
        or not isinstance(entry.get("files"), dict)
    ):
        return {}
    return {
        language: files
        for language, files in entry["files"].items()
        if isinstance(files, list)
        and all(
            isinstance(f, list) and len(f) == 2 and all(isinstance(x, str) for x in f)
            for f in files
        )
    }


def _emitted(model, language: str, routines: _LazyRoutines) -> tuple[tuple[str, str], ...]:
    key = (model.hash, GENERATOR_VERSION, language)
    if key not in _EMITTED:
        _EMITTED[key] = tuple(get_emitter(language).emit(model, routines.get()))
    return _EMITTED[key]


def _emitted_variant(model, languages: tuple[str, ...]) -> dict[str, tuple[tuple[str, str], ...]]:
    """The files of every language for one variant: memoised in the process, else from the
    signed on-disk cache, else emitted (and then cached on disk)."""
    missing = [lang for lang in languages if (model.hash, GENERATOR_VERSION, lang) not in _EMITTED]
    if missing:
        path = rendered_cache_file(model.system, model.effects)
        cached = _load_rendered(path, model)
        for language in missing:
            if language in cached:
                files = tuple((name, text) for name, text in cached[language])
                _EMITTED[(model.hash, GENERATOR_VERSION, language)] = files
        if any(language not in cached for language in missing):
            routines = _LazyRoutines(model)
            every = {language: _emitted(model, language, routines) for language in languages}
            for language, files in cached.items():
                every.setdefault(language, tuple(map(tuple, files)))
            entry = {
                "model_hash": model.hash,
                "generator": GENERATOR_VERSION,
                "files": {language: [list(f) for f in files] for language, files in every.items()},
            }
            write_signed(path, _RENDERED_MAGIC, json.dumps(entry, sort_keys=True).encode())
    return {language: _EMITTED[(model.hash, GENERATOR_VERSION, language)] for language in languages}


def render_generated(languages: tuple[str, ...] | None = None) -> dict[str, str]:
    """Every file of ``generated/`` as ``{filename: text}`` (nothing is written).

    Parameters
    ----------
    languages : tuple of str, optional
        Emitters to run (default: all registered).

    Returns
    -------
    dict of str to str
        File name (relative to ``generated/``) to text: the package ``__init__.py``,
        each emitter's files for every built-in variant, and ``manifest.json``.
    """
    languages = languages or tuple(sorted(EMITTERS))
    files: dict[str, str] = {"__init__.py": _INIT}
    manifest: dict[str, dict] = {}
    for system, effects in builtin_variants():
        model = build_model(system, effects)
        emitted = _emitted_variant(model, languages)
        entry = {
            "system": system,
            "effects": sorted(effects),
            "hash": model.hash,
            "generator": GENERATOR_VERSION,
            "files": {},
        }
        for language in languages:
            for filename, text in emitted[language]:
                files[filename] = text
                entry["files"][language] = filename
        manifest[model.name] = entry
    files[MANIFEST] = json.dumps(manifest, indent=2, sort_keys=True) + "\n"
    return files


def _atomic_write(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _is_generated(path: Path) -> bool:
    return path.is_file() and path.suffix in {".py", ".c", ".json"}


#: Every file this writer emits says so in its first lines (the manifest is recognised by
#: its shape): only such files are ever overwritten or removed.
_STAMP = "DO NOT EDIT"


def is_ours(path: Path) -> bool:
    """True when ``path`` is a file ``chaplygin derive`` wrote (its stamp or the manifest).

    Parameters
    ----------
    path : pathlib.Path

    Returns
    -------
    bool
    """
    if not path.is_file():
        return False
    try:
        with open(path, encoding="utf-8") as fh:
            head = fh.read(4096)
    except (OSError, UnicodeDecodeError):
        return False
    if path.name == MANIFEST:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return False
        return isinstance(data, dict) and all(
            isinstance(v, dict) and {"system", "hash", "files"} <= set(v) for v in data.values()
        )
    first = "\n".join(head.splitlines()[:5])
    return _STAMP in first and "chaplygin derive" in first


def refuse_foreign(directory: Path, names: set[str] | None = None) -> None:
    """Refuse to write into a folder holding files the project did not write.

    Parameters
    ----------
    directory : pathlib.Path
        The output folder (it may not exist: then nothing is refused).
    names : set of str, optional
        The files about to be written; without it only the folder itself is checked.

    Raises
    ------
    UserInputError
        The folder is not a folder, is not empty and holds no manifest of ours, or holds a
        file of the same name as one to be written that is not ours.
    """
    if not directory.exists():
        return
    if not directory.is_dir():
        raise UserInputError(f"output folder {directory}: not a folder")
    present = [p for p in directory.iterdir() if not p.name.startswith(".")]
    if present and not is_ours(directory / MANIFEST):
        raise UserInputError(
            f"output folder {directory}: the folder is not empty and was not written by chaplygin "
            f"derive ({len(present)} entries, no {MANIFEST} of ours); give an empty or new folder"
        )
    for p in present:
        if names is not None and p.name in names and not is_ours(p):
            raise UserInputError(
                f"output folder {directory}: {p.name} is not a file chaplygin derive wrote; "
                "it would be overwritten: move it away or give another folder"
            )


def write_generated(directory: Path) -> list[str]:
    """(Re)write ``directory``; returns the names of files that changed or were removed.

    Files are written atomically and only when their text differs. Only files this writer
    made (stamped, see :func:`is_ours`) are overwritten or removed; a folder with anything
    else in it is refused before any work is done.

    Parameters
    ----------
    directory : pathlib.Path
        The ``generated/`` directory (created if missing).

    Returns
    -------
    list of str
        Names of the files written or removed, sorted within each group.

    Raises
    ------
    UserInputError
        See :func:`refuse_foreign`.
    """
    refuse_foreign(directory)
    files = render_generated()
    refuse_foreign(directory, set(files))  # (the folder may have changed meanwhile)
    directory.mkdir(parents=True, exist_ok=True)
    changed = []
    for name, text in sorted(files.items()):
        path = directory / name
        if not path.exists() or path.read_text() != text:
            _atomic_write(path, text)
            changed.append(name)
    for path in sorted(directory.iterdir()):
        if _is_generated(path) and path.name not in files and is_ours(path):
            path.unlink()
            changed.append(path.name)
    return changed


def check_generated(directory: Path) -> list[str]:
    """Names of files in ``directory`` that are stale, missing or extra (empty: in sync).

    Parameters
    ----------
    directory : pathlib.Path
        The ``generated/`` directory (may be missing).

    Returns
    -------
    list of str
        One ``"<name>: <problem>"`` line per file that is missing, out of date or
        not produced by any built-in model; empty when ``directory`` is in sync.
    """
    files = render_generated()
    problems = []
    for name, text in sorted(files.items()):
        path = directory / name
        if not path.exists():
            problems.append(f"{name}: missing")
        elif path.read_text() != text:
            problems.append(f"{name}: out of date")
    for path in sorted(directory.iterdir()) if directory.exists() else []:
        if _is_generated(path) and path.name not in files:
            problems.append(f"{path.name}: not produced by any built-in model")
    return problems
