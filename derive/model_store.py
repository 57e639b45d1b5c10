"""The on-disk cache of derived models: where it is, the key of the derivation's sources and
versions, signed pickles that load as they were written, and the models of descriptions
(:meth:`~.rolling_system.RollingSystem.model`), memoised in the process and on disk.

:mod:`.systems` builds the registered systems' models on it; this module imports neither it
nor the descriptions (it is below both)."""

from __future__ import annotations

import hashlib
import io
import os
import pickle
import sys
from collections.abc import Callable, Iterable
from functools import cache
from pathlib import Path
from typing import Any

import mpmath
import sympy as sp

from .cachefiles import cache_root, read_signed, write_signed
from .effects import parse_effects
from .model import Model

__all__ = [
    "MODEL_CACHE_VERSION",
    "model_cache_dir",
    "described_model",
    "kept_model",
    "load_or_derive",
]

#: Bumped when the layout of the on-disk model cache changes.
MODEL_CACHE_VERSION = 1


def model_cache_dir() -> Path | None:
    """Folder of derived models on disk.

    Returns
    -------
    pathlib.Path or None
        ``<cache root>/models`` (the root:
        :func:`~chaplygin.derive.cachefiles.cache_root`); None when
        ``CHAPLYGIN_MODEL_CACHE=0``.
    """
    if os.environ.get("CHAPLYGIN_MODEL_CACHE", "1") == "0":
        return None
    return cache_root() / "models"


@cache
def _derivation_digest() -> str:
    """Hash of everything a derivation depends on: this package's sources and the
    versions of Python, sympy and mpmath. Any edit of ``derive/`` gives new keys."""
    h = hashlib.sha256(f"{MODEL_CACHE_VERSION} {sys.version} {sp.__version__}".encode())
    h.update(mpmath.__version__.encode())
    here = Path(__file__).resolve().parent
    for path in sorted(here.rglob("*.py")):
        h.update(str(path.relative_to(here)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


#: First line of a model file: the format, then the HMAC of the pickle that follows.
_MODEL_MAGIC = b"chaplygin-model-1\n"


def _load_cached(path: Path | None) -> Model | None:
    """The cached model at ``path``, or None (absent, damaged, or not written by us).

    The pickle is read only after its HMAC (made with the cache root's per-user secret when
    we wrote it) checks out: a file anyone else put there is never unpickled.
    """
    data = read_signed(path, _MODEL_MAGIC)
    if data is None:
        return None  # not ours (or damaged): derive again and overwrite it
    try:
        model = pickle.loads(data)  # signed by us: our own bytes
    except Exception:  # an older class layout: derive again
        return None
    return model if isinstance(model, Model) else None


def _unevaluated(cls: type, args: tuple) -> sp.Basic:
    """A sum, product or power from its arguments as they were (:class:`_ModelPickler`)."""
    return cls(*args, evaluate=False)


class _ModelPickler(pickle.Pickler):
    """Pickles sums, products and powers so that they load as they were: sympy's own
    pickles build them again with evaluation, which distributes a number over a sum (a
    ``Mul(1/n, Add(...))`` of ``factor`` comes back expanded), so a loaded model would not
    be the derivation and the code emitted from it would round otherwise."""

    def reducer_override(self, obj: object) -> object:
        if type(obj) in (sp.Add, sp.Mul, sp.Pow):
            return _unevaluated, (type(obj), obj.args)
        return NotImplemented


def _pickled(model: Model) -> bytes:
    out = io.BytesIO()
    _ModelPickler(out, protocol=pickle.HIGHEST_PROTOCOL).dump(model)
    return out.getvalue()


def _store(path: Path | None, model: Model) -> bool:
    """Write atomically (parallel processes may derive the same model at once), signed;
    whether it was written."""
    if path is None:
        return False
    try:
        data = _pickled(model)
    except (pickle.PicklingError, AttributeError, TypeError):
        return False  # an unpicklable definition: the cache is only an aid
    return bool(write_signed(path, _MODEL_MAGIC, data))


def kept_model(kind: str, key: str, derive: Callable[[], Model]) -> Model:
    """A derived model kept in the on-disk model cache: loaded when a model of ``kind`` with
    ``key`` was derived before by the same sources and versions, else ``derive()``'d and
    stored (signed, written atomically; the cache is only an aid: a model that does not
    pickle is returned all the same).

    Parameters
    ----------
    kind : str
        A name for the files (``<kind>-<digest>.pickle``).
    key : str
        Everything the derivation reads besides ``derive/``'s sources and the versions of
        Python, sympy and mpmath (which the file's digest includes).
    derive : callable
        Derives the model (what it raises is raised; nothing is stored then).

    Returns
    -------
    Model
    """
    path = None
    models = model_cache_dir()
    if models is not None:
        digest = hashlib.sha256(f"{_derivation_digest()} {kind} {key}".encode()).hexdigest()
        path = models / f"{kind}-{digest[:32]}.pickle"
    return load_or_derive(path, derive)


def load_or_derive(path: Path | None, derive: Callable[[], Model]) -> Model:
    """The model cached at ``path``, else ``derive()``'d and stored there.

    Parameters
    ----------
    path : pathlib.Path or None
        The cache file (None: no disk cache, derive).
    derive : callable
        Derives the model (what it raises is raised; nothing is stored then).

    Returns
    -------
    Model
    """
    model = _load_cached(path)
    if model is None:
        model = derive()
        _store(path, model)
    return model


#: Models of descriptions (:meth:`RollingSystem.model`) in this process, by the
#: description's fingerprint and the effects.
_DESCRIBED: dict[tuple[str, frozenset[str]], Model] = {}


def described_model(description: Any, effects: Iterable[str] | str | None = ()) -> Model:
    """The model of a description that need not be registered: memoised in the process and
    kept in the on-disk model cache like :func:`build_model`'s, keyed by the description's
    :meth:`~.rolling_system.RollingSystem.fingerprint`, the effects and the derivation's
    sources and versions (the digest :func:`~.systems.variant_cache_key` uses too).

    Parameters
    ----------
    description : RollingSystem
        (read through its ``fingerprint()``, ``effects_taken`` and ``derive(effects)``)
    effects : iterable of str or comma-separated str, optional

    Returns
    -------
    Model

    Raises
    ------
    UserInputError
        An effect the description does not take (before any work), or what
        :meth:`~.rolling_system.RollingSystem.derive` raises: nothing is cached then.
    """
    chosen = parse_effects(effects, description.effects_taken)  # (checked before any work)
    key = (description.fingerprint(), chosen)
    model = _DESCRIBED.get(key)
    if model is None:
        model = kept_model("described", f"{key[0]} {sorted(chosen)}",
                           lambda: description.derive(sorted(chosen)))  # fmt: skip
        _DESCRIBED[key] = model
    return model
