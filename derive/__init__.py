"""Symbolic layer: mechanical descriptions -> derived models -> emitted code.

Imports nothing from the other layers of chaplygin. The names below are resolved on first
use (as the package root does), so ``import chaplygin.derive.errors`` -- the exceptions every
layer raises, and the command line catches -- loads no sympy; ``from chaplygin.derive import
build_model`` loads what it needs.
"""

from __future__ import annotations

import importlib
from typing import Any

from .errors import ChaplyginError, DerivationError, UserInputError

__version__ = "0.1.0"

#: public name -> the module of this package that defines it
_PUBLIC: dict[str, str] = {
    "EFFECTS": "effects",
    "Effect": "effects",
    "parse_effects": "effects",
    "MechanicalDescription": "description",
    "Declaration": "declaration",
    "Constraint": "declaration",
    "Reduced": "description",
    "Reduction": "description",
    "RigidBodyReduction": "rigid_body",
    "apply_effects": "description",
    "form_model": "description",
    "RigidBodyDescription": "engine",
    "ReducedEquations": "engine",
    "lagrange_dalembert": "engine",
    "Model": "model",
    "ParameterSpec": "model",
    "ModelDetails": "model",
    "Reparametrisation": "model",
    "sample_point": "phase_space",
    "SYSTEMS": "systems",
    "build_model": "systems",
    "builtin_variants": "systems",
    "variant_name": "systems",
}

__all__ = [
    *_PUBLIC,
    "ChaplyginError",
    "DerivationError",
    "UserInputError",
    "__version__",
]


def __getattr__(name: str) -> Any:
    """Resolve a public name on first use (PEP 562) and cache it in the package."""
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC))
