"""Registry of the built-in systems and of the model variants shipped in ``generated/``.

Each system lives in its own module of ``chaplygin.derive`` (listed in
:data:`SYSTEM_MODULES`) and declares ``NAME``, ``DESCRIPTION``, ``BUILDER`` (effects ->
Model), ``SUPPORTED_EFFECTS`` and ``GENERATED_VARIANTS`` (the effect combinations whose
code is committed in ``generated/``).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from .effects import parse_effects
from .errors import UserInputError
from .model import Model

__all__ = ["System", "SYSTEMS", "SYSTEM_MODULES", "build_model", "builtin_variants", "variant_name"]

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
        )
    return out


SYSTEMS: dict[str, System] = _load_systems()

_CACHE: dict[tuple[str, frozenset[str]], Model] = {}


def get_system(name: str) -> System:
    try:
        return SYSTEMS[name]
    except KeyError:
        raise UserInputError(
            f"unknown system {name!r}; valid systems: {', '.join(sorted(SYSTEMS))}"
        ) from None


def variant_name(system: str, effects: Iterable[str]) -> str:
    """``system__effect1__effect2`` with the effects sorted."""
    return "__".join([system, *sorted(effects)])


def build_model(system: str, effects: Iterable[str] | str | None = ()) -> Model:
    """Build (and memoise) the model of a system with the given effects.

    Parameters
    ----------
    system : str
        A key of :data:`SYSTEMS`.
    effects : iterable of str or comma-separated str, optional

    Returns
    -------
    Model

    Raises
    ------
    UserInputError
        Unknown system or effect (the message lists the valid names).
    """
    sysdef = get_system(system)
    chosen = parse_effects(effects, sysdef.effects)
    key = (system, chosen)
    if key not in _CACHE:
        _CACHE[key] = sysdef.builder(chosen)
    return _CACHE[key]


def builtin_variants() -> list[tuple[str, frozenset[str]]]:
    """Every (system, effects) combination whose code is committed in ``generated/``."""
    return [(s.name, frozenset(v)) for s in SYSTEMS.values() for v in s.variants]
