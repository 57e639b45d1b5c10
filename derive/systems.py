"""Registry of the built-in systems and of the model variants shipped in ``generated/``."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

from .chaplygin_ball import SUPPORTED_EFFECTS as BALL_EFFECTS
from .chaplygin_ball import build_chaplygin_ball
from .effects import parse_effects
from .errors import UserInputError
from .model import Model

__all__ = ["System", "SYSTEMS", "build_model", "builtin_variants", "variant_name"]


@dataclass(frozen=True)
class System:
    """A system family: its builder and the effects it supports."""

    name: str
    builder: Callable[..., Model]
    effects: tuple[str, ...]
    description: str


SYSTEMS: dict[str, System] = {
    s.name: s
    for s in (
        System(
            "chaplygin_ball",
            build_chaplygin_ball,
            BALL_EFFECTS,
            "balanced dynamically asymmetric ball rolling without slipping on a plane "
            "(BKM12 §1.1, K01 §2)",
        ),
    )
}

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
    out = []
    for sysdef in SYSTEMS.values():
        for r in range(len(sysdef.effects) + 1):
            for combo in _combinations(sorted(sysdef.effects), r):
                out.append((sysdef.name, frozenset(combo)))
    return out


def _combinations(items, r):
    from itertools import combinations

    return combinations(items, r)
