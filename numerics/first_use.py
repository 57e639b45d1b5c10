"""Code of an effect combination that is not in ``generated/``: derived, emitted and compiled on
first use, and cached on disk so that later processes only load it.

The emitted sources (numpy, mpmath, C, Taylor Python, Taylor C, Taylor C on MPFR, the Taylor
program, the right-hand side in vector lanes; the C and the lanes only when first asked for,
:data:`LAZY_KINDS`) of a variant are stored in
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

__all__ = ["FirstUse", "emitted_sources", "emitted_cache_file", "SOURCE_KINDS", "LAZY_KINDS"]

#: The emitted sources of a variant, in the order of ``generated/manifest.json``'s files.
SOURCE_KINDS = (
    "numpy", "mpmath", "c", "taylor_py", "taylor_c", "taylor_mpfr", "taylor_program", "c_lanes"
)

#: The kinds emitted only when first asked for (a run on the numpy backend needs no C, one
#: that is not a batch of DOP853 orbits no vector lanes; every run reads its start with the
#: mpmath module): for a large body that is most of a third of the emission (a convex body
#: on a support surface: C 8.4 s, lanes 4.3 s of 28 s, and the C compiler's 7 s).
LAZY_KINDS = ("c", "c_lanes")

#: The kinds emitted on first use (the numpy module carries the model's metadata).
EAGER_KINDS = tuple(k for k in SOURCE_KINDS if k not in LAZY_KINDS)

#: First line of a cache file: the format, then the HMAC of the JSON that follows.
_MAGIC = b"chaplygin-emitted-1\n"


@dataclass(frozen=True)
class FirstUse:
    """Where the code of a variant outside ``generated/`` came from.

    Attributes
    ----------
    sources : dict of str to str
        Kind of :data:`SOURCE_KINDS` -> source text, for every kind emitted so far (at least
        the eager ones; ``""`` for a kind the variant has none of: the lanes of a right-hand
        side they cannot compute).
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
    if not isinstance(sources, dict) or not set(EAGER_KINDS) <= set(sources) <= set(
        SOURCE_KINDS
    ):
        return None
    if not all(isinstance(v, str) for v in sources.values()):
        return None
    return sources


def _store(path: Path | None, sources: dict[str, str]) -> Path | None:
    """Write signed; None when the cache is off or cannot be written (it is an aid)."""
    return path if write_signed(path, _MAGIC, json.dumps(sources).encode()) else None


def emitted_sources(
    system: str, effects: frozenset[str], kinds: tuple[str, ...] = EAGER_KINDS
) -> FirstUse:
    """The emitted sources of a variant: from the cache, else derived, emitted and cached.

    Only ``kinds`` are emitted when missing (the eager ones by default; the lazy ones,
    :data:`LAZY_KINDS`, when first asked for); the cache file keeps every kind emitted so
    far, and ``sources`` holds them all.

    Parameters
    ----------
    system : str
    effects : frozenset of str
        Validated effect names (:func:`chaplygin.derive.effects.parse_effects`).
    kinds : tuple of str, optional
        The kinds wanted (of :data:`SOURCE_KINDS`).

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
    if cached is not None and all(k in cached for k in kinds):
        return FirstUse(cached, False, time.perf_counter() - start, path)
    sources = dict(cached or {})
    wanted = [k for k in (*EAGER_KINDS, *kinds) if k not in sources]
    model, routines = _derived(system, effects)
    for kind in dict.fromkeys(wanted):
        files = _EMITTERS[kind]().emit(model, routines)  # one file, or none (no lanes)
        sources[kind] = files[0][1] if files else ""
    again = _load(path)  # another process may have added kinds meanwhile: keep them
    stored = _store(path, {**(again or {}), **sources})
    return FirstUse(sources, True, time.perf_counter() - start, stored)


class _Emitters(dict):
    """:data:`SOURCE_KINDS` -> emitter class, imported when first needed."""

    def __missing__(self, kind: str):  # noqa: ANN204
        from ..derive import emit

        self.update({
            "numpy": emit.NumpyEmitter, "mpmath": emit.MpmathEmitter, "c": emit.CEmitter,
            "taylor_py": emit.TaylorPythonEmitter, "taylor_c": emit.TaylorCEmitter,
            "taylor_mpfr": emit.TaylorMpfrEmitter, "taylor_program": emit.TaylorProgramEmitter,
            "c_lanes": emit.CLanesEmitter,
        })  # fmt: skip
        return self[kind]


_EMITTERS = _Emitters()

#: The derived models and their routines (the common subexpressions every emitter shares)
#: of the last variants emitted in this process: a kind emitted later reuses them.
_DERIVED: dict[tuple, tuple] = {}
_DERIVED_MAX = 4


def _derived(system: str, effects: frozenset[str]) -> tuple:
    from ..derive.emit import ModelRoutines
    from ..derive.systems import build_model, variant_cache_key

    key = (system, effects, variant_cache_key(system, effects))
    hit = _DERIVED.get(key)
    if hit is None:
        model = build_model(system, effects)
        hit = (model, ModelRoutines(model))
        if len(_DERIVED) >= _DERIVED_MAX:
            del _DERIVED[next(iter(_DERIVED))]
        _DERIVED[key] = hit
    return hit
