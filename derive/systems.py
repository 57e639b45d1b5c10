"""Registry of the built-in systems and of the model variants shipped in ``generated/``.

Each system lives in its own module of ``chaplygin.derive`` (listed in
:data:`SYSTEM_MODULES`) and declares ``NAME``, ``DESCRIPTION``, ``BUILDER`` (effects ->
Model), ``SUPPORTED_EFFECTS`` and ``GENERATED_VARIANTS`` (the effect combinations whose
code is committed in ``generated/``); optionally ``SIGNATURE`` (effects -> state groups
and parameters, from the mechanical description alone, without deriving).
"""

from __future__ import annotations

import hashlib
import importlib
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

from .effects import parse_effects
from .errors import UserInputError
from .model import Model
from .model_store import (  # noqa: F401 - (the cache's names, as they were here)
    MODEL_CACHE_VERSION,
    _derivation_digest,
    _load_cached,
    _store,
    described_model,
    load_or_derive,
    model_cache_dir,
)
from .rolling_system import RollingSystem

__all__ = [
    "System",
    "SYSTEMS",
    "SYSTEM_MODULES",
    "build_model",
    "store_derived",
    "builtin_variants",
    "variant_name",
    "variant_signature",
    "VariantSignature",
    "register_system",
    "model_cache_dir",
    "variant_cache_key",
    "variant_cache_file",
    "described_model",
]

#: Modules of chaplygin.derive that define a system (see the module docstring).
SYSTEM_MODULES = ("chaplygin_ball", "ball_on_surface", "spherical_support")


@dataclass(frozen=True)
class System:
    """A system family: its builder, the effects it supports, the variants it ships."""

    name: str
    builder: Callable[..., Model]
    effects: tuple[str, ...]
    variants: tuple[tuple[str, ...], ...]
    description: str
    signature: Callable[[frozenset[str]], tuple] | None = None
    fingerprint: str = ""
    conditions: tuple[tuple[object, str], ...] = ()


@dataclass(frozen=True)
class VariantSignature:
    """The state and parameter names of a variant, known before it is derived.

    Same attributes as the generated code's ``ModelCode`` that input checks read, so
    that bad input (a missing parameter ...) is refused before a derivation starts.

    Attributes
    ----------
    name : str
    state_groups : dict of str to tuple of str
    parameter_groups : dict of str to (tuple of str, str, str)
        ``name -> (symbols, domain, description)``.
    geometry : tuple of (str, tuple of str)
        The Poisson groups, ``(kind, names)``.
    completion : tuple of ((str, ...), str)
        How omitted state groups are completed.
    system : str
        The system the variant belongs to.
    """

    name: str
    state_groups: dict[str, tuple[str, ...]]
    parameter_groups: dict[str, tuple[tuple[str, ...], str, str]]
    geometry: tuple[tuple[str, tuple[str, ...]], ...] = ()
    completion: tuple[tuple[tuple[str, ...], str], ...] = ()
    system: str = ""

    @property
    def state(self) -> tuple[str, ...]:
        """State names in order."""
        return tuple(s for group in self.state_groups.values() for s in group)

    @property
    def params(self) -> tuple[str, ...]:
        """Parameter names in order."""
        return tuple(s for symbols, _, _ in self.parameter_groups.values() for s in symbols)


def _load_systems() -> dict[str, System]:
    out = {}
    for module_name in SYSTEM_MODULES:
        mod = importlib.import_module(f"{__package__}.{module_name}")
        out[mod.NAME] = System(
            mod.NAME,
            mod.BUILDER,
            tuple(mod.SUPPORTED_EFFECTS),
            tuple(tuple(sorted(v)) for v in mod.GENERATED_VARIANTS),
            mod.DESCRIPTION,
            getattr(mod, "SIGNATURE", None),
        )
    return out


SYSTEMS: dict[str, System] = _load_systems()

_CACHE: dict[tuple[str, frozenset[str]], Model] = {}
#: The cache file of each model in :data:`_CACHE` (by ``id``), for :func:`store_derived`.
_CACHE_FILES: dict[int, Path] = {}


def get_system(name: str) -> System:
    """The built-in system called ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`SYSTEMS` (``"chaplygin_ball"``, ...).

    Returns
    -------
    System
        Its registry entry (builder, supported effects, generated variants ...).

    Raises
    ------
    UserInputError
        For an unknown name (the message lists the valid ones).
    """
    try:
        return SYSTEMS[name]
    except (KeyError, TypeError):  # TypeError: an unhashable name (a list, a dict)
        raise UserInputError(
            f"unknown system {name!r}; valid systems: {', '.join(sorted(SYSTEMS))}"
        ) from None


def variant_name(system: str, effects: Iterable[str]) -> str:
    """``system__effect1__effect2`` with the effects sorted.

    Parameters
    ----------
    system : str
        System name.
    effects : iterable of str
        Effect names (any order); none gives the bare system name.

    Returns
    -------
    str
        The variant name, the key of the variant's files in ``generated/``.
    """
    return "__".join([system, *sorted(effects)])


def variant_cache_key(system: str, effects: Iterable[str]) -> str:
    """Key of a variant's derived files in the on-disk caches (models, first-use code).

    It changes with any edit of this package's sources and with the versions of Python,
    sympy and mpmath, so a cache entry never outlives what it was derived with.

    Parameters
    ----------
    system : str
    effects : iterable of str

    Returns
    -------
    str
        32 hexadecimal digits.
    """
    described = SYSTEMS[system].fingerprint if system in SYSTEMS else ""
    key = hashlib.sha256(
        f"{_derivation_digest()} {variant_name(system, effects)} {described}".encode()
    )
    return key.hexdigest()[:32]


def variant_cache_file(
    folder: str, system: str, effects: frozenset[str], suffix: str
) -> Path | None:
    """A variant's file in one of the on-disk caches of derived things.

    Parameters
    ----------
    folder : str
        The cache's folder under the cache root (``models``, ``emitted``, ``rendered``).
    system : str
    effects : frozenset of str
        Validated effect names.
    suffix : str
        The file's suffix (``.pickle``).

    Returns
    -------
    pathlib.Path or None
        ``<cache root>/<folder>/<variant>-<key><suffix>`` (the key:
        :func:`variant_cache_key`); None when ``CHAPLYGIN_MODEL_CACHE=0``.
    """
    models = model_cache_dir()
    if models is None:
        return None
    name = variant_name(system, effects)
    return models.parent / folder / f"{name}-{variant_cache_key(system, effects)}{suffix}"


def _cache_file(system: str, effects: frozenset[str]) -> Path | None:
    return variant_cache_file("models", system, effects, ".pickle")


def build_model(
    system: str, effects: Iterable[str] | str | None = (), disk_cache: bool = True
) -> Model:
    """Build (and memoise) the model of a system with the given effects.

    Derived models are memoised in the process and, unless ``disk_cache`` is False or
    ``CHAPLYGIN_MODEL_CACHE=0``, on disk (:func:`model_cache_dir`), keyed by the sources
    of this package and the versions of Python, sympy and mpmath, so that a later
    process does not derive them again.

    Parameters
    ----------
    system : str
        A key of :data:`SYSTEMS`.
    effects : iterable of str or comma-separated str, optional
    disk_cache : bool
        Read and write the on-disk cache.

    Returns
    -------
    Model

    Raises
    ------
    UserInputError
        Unknown system or effect (the message lists the valid names), effects that
        exclude each other, an effect without one it requires: all before anything is
        derived.
    """
    sysdef = get_system(system)
    chosen = parse_effects(effects, sysdef.effects)
    key = (system, chosen)
    if key not in _CACHE:
        path = _cache_file(system, chosen) if disk_cache else None
        model = load_or_derive(path, lambda: sysdef.builder(chosen))
        _CACHE[key] = model
        if path is not None:
            _CACHE_FILES[id(model)] = path
    return _CACHE[key]


def store_derived(model: Model) -> bool:
    """Write a model of :func:`build_model` to its disk cache again, with what has been
    derived from it since it was built or loaded (its Jacobian, ...: the cached properties
    travel with the pickle), so that the next process loads them instead of deriving them.

    Parameters
    ----------
    model : Model
        A model :func:`build_model` returned in this process.

    Returns
    -------
    bool
        Whether it was written (False: not from :func:`build_model`, no disk cache, or the
        cache refused the write).
    """
    path = _CACHE_FILES.get(id(model))
    if path is None or not any(m is model for m in _CACHE.values()):
        return False
    return _store(path, model)


def variant_signature(
    system: str, effects: Iterable[str] | str | None = ()
) -> VariantSignature | None:
    """State and parameter names of a variant without deriving it (milliseconds).

    Parameters
    ----------
    system : str
    effects : iterable of str or comma-separated str, optional

    Returns
    -------
    VariantSignature or None
        None when the system has no ``SIGNATURE`` (its model must be built).

    Raises
    ------
    UserInputError
        Unknown system or effect, conflicting effects, a missing required effect.
    """
    sysdef = get_system(system)
    chosen = parse_effects(effects, sysdef.effects)
    if sysdef.signature is None:
        return None
    state_groups, parameters, geometry, completion = sysdef.signature(chosen)
    return VariantSignature(
        variant_name(system, chosen),
        {name: tuple(s.name for s in group) for name, group in state_groups},
        {p.name: (tuple(s.name for s in p.symbols), p.domain, p.description) for p in parameters},
        tuple(geometry),
        tuple(completion),
        system,
    )


def register_system(description: RollingSystem) -> System:
    """Make a described system usable by name everywhere a built-in is.

    After registration :func:`build_model` derives (and caches, keyed also by the
    description's fingerprint) its model, and the numerical layer emits and compiles its
    code on first use. Registering the same description again is a no-op.

    Parameters
    ----------
    description : RollingSystem

    Returns
    -------
    System
        The registry entry (no effects, no shipped variants).

    Raises
    ------
    UserInputError
        When the name is a built-in system's, or another description holds it.
    """
    if not isinstance(description, RollingSystem):
        raise UserInputError(f"expected a RollingSystem, got {type(description).__name__}")
    name = description.name
    old = SYSTEMS.get(name)
    if old is not None:
        if old.fingerprint == description.fingerprint():
            return old
        what = "a built-in system" if not old.fingerprint else "another described system"
        raise UserInputError(f"system name {name!r} is taken by {what}; choose another name")
    entry = System(
        name,
        lambda effects, _d=description: _d.derive(effects),  # (build_model caches it)
        description.effects_taken,
        (),
        description.description or f"described rolling system {name}",
        lambda effects, _d=description: _d.mechanical_description(effects).input_signature(),
        description.fingerprint(),
        description.parameter_conditions,
    )
    SYSTEMS[name] = entry
    return entry


def builtin_variants() -> list[tuple[str, frozenset[str]]]:
    """Every (system, effects) combination whose code is committed in ``generated/``.

    Returns
    -------
    list of (str, frozenset of str)
        ``(system name, effects)`` pairs, in the order of :data:`SYSTEMS` and of each
        system's ``GENERATED_VARIANTS``.
    """
    return [(s.name, frozenset(v)) for s in SYSTEMS.values() for v in s.variants]
