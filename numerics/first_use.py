"""Code of an effect combination that is not in ``generated/``: derived, emitted and compiled on
first use, and cached on disk so that later processes only load it.

The emitted sources (numpy, mpmath, C, Taylor Python, Taylor C, Taylor C on MPFR, the Taylor
program, the right-hand side in vector lanes) of a variant are stored in
``<cache root>/emitted/<variant>-<key>.src`` (the root:
:func:`~chaplygin.derive.cachefiles.cache_root`; none with ``CHAPLYGIN_MODEL_CACHE=0``).
The key (:func:`chaplygin.derive.systems.variant_cache_key`)
changes with any edit of ``derive/`` and with the versions of Python, sympy and mpmath. The
Python sources are executed when loaded, so a file is used only when it carries the HMAC made
with the cache root's per-user secret (:mod:`chaplygin.derive.cachefiles`), and a folder other
users can write to is refused. The compiled C library is cached by
:mod:`chaplygin.numerics.ccompile` as for every model.
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

from ..derive.cachefiles import read_signed, write_signed
from ..derive.systems import variant_cache_file

__all__ = ["FirstUse", "emitted_sources", "emitted_cache_file", "SOURCE_KINDS"]

#: The emitted sources of a variant, in the order of ``generated/manifest.json``'s files.
SOURCE_KINDS = (
    "numpy", "mpmath", "c", "taylor_py", "taylor_c", "taylor_mpfr", "taylor_program", "c_lanes"
)

#: First line of a cache file: the format, then the HMAC of the JSON that follows.
_MAGIC = b"chaplygin-emitted-1\n"


@dataclass(frozen=True)
class FirstUse:
    """Where the code of a variant outside ``generated/`` came from.

    Attributes
    ----------
    sources : dict of str to str
        :data:`SOURCE_KINDS` -> source text (``""`` for a kind the variant has none of: the
        lanes of a right-hand side they cannot compute).
    derived : bool
        True when it was derived and emitted now, False when loaded from the cache.
    seconds : float
        Time to derive and emit it, or to load it.
    cache_file : pathlib.Path or None
        Where it is cached (None when the cache is off or not writable).
    """

    sources: dict[str, str]
    derived: bool
    seconds: float
    cache_file: Path | None


def emitted_cache_file(system: str, effects: frozenset[str]) -> Path | None:
    """The cache file of a variant's emitted sources (None with ``CHAPLYGIN_MODEL_CACHE=0``).

    Parameters
    ----------
    system : str
    effects : frozenset of str
        Validated effect names.

    Returns
    -------
    pathlib.Path or None
    """
    return variant_cache_file("emitted", system, effects, ".src")


def _load(path: Path | None) -> dict[str, str] | None:
    data = read_signed(path, _MAGIC)
    if data is None:
        return None  # not ours, or damaged: derive again and overwrite it
    try:
        sources = json.loads(data)
    except ValueError:
        return None
    if not isinstance(sources, dict) or set(sources) != set(SOURCE_KINDS):
        return None
    return sources


def _store(path: Path | None, sources: dict[str, str]) -> Path | None:
    """Write signed; None when the cache is off or cannot be written (it is an aid)."""
    return path if write_signed(path, _MAGIC, json.dumps(sources).encode()) else None


def emitted_sources(system: str, effects: frozenset[str]) -> FirstUse:
    """The emitted sources of a variant: from the cache, else derived, emitted and cached.

    Parameters
    ----------
    system : str
    effects : frozenset of str
        Validated effect names (:func:`chaplygin.derive.effects.parse_effects`).

    Returns
    -------
    FirstUse

    Raises
    ------
    CacheError
        The cache folder can be written by other users.
    """
    start = time.perf_counter()
    path = emitted_cache_file(system, effects)
    cached = _load(path)
    if cached is not None:
        return FirstUse(cached, False, time.perf_counter() - start, path)
    from ..derive.emit import (
        CEmitter,
        CLanesEmitter,
        ModelRoutines,
        MpmathEmitter,
        NumpyEmitter,
        TaylorCEmitter,
        TaylorMpfrEmitter,
        TaylorProgramEmitter,
        TaylorPythonEmitter,
    )
    from ..derive.systems import build_model

    model = build_model(system, effects)
    routines = ModelRoutines(model)
    emitters = (
        NumpyEmitter,
        MpmathEmitter,
        CEmitter,
        TaylorPythonEmitter,
        TaylorCEmitter,
        TaylorMpfrEmitter,
        TaylorProgramEmitter,
        CLanesEmitter,
    )
    sources = {}
    for kind, emitter in zip(SOURCE_KINDS, emitters, strict=True):
        files = emitter().emit(model, routines)  # one file, or none (no lanes)
        sources[kind] = files[0][1] if files else ""
    stored = _store(path, sources)
    return FirstUse(sources, True, time.perf_counter() - start, stored)
