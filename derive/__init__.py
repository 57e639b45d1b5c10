"""Symbolic layer: mechanical descriptions -> derived models -> emitted code.

Imports nothing from the other layers of chaplygin.
"""

from __future__ import annotations

from .effects import EFFECTS, Effect, parse_effects
from .engine import ReducedEquations, RigidBodyDescription, lagrange_dalembert
from .errors import ChaplyginError, DerivationError, UserInputError
from .model import Model, ParameterSpec
from .systems import SYSTEMS, build_model, builtin_variants, variant_name

__version__ = "0.1.0"

__all__ = [
    "EFFECTS",
    "Effect",
    "parse_effects",
    "RigidBodyDescription",
    "ReducedEquations",
    "lagrange_dalembert",
    "ChaplyginError",
    "DerivationError",
    "UserInputError",
    "Model",
    "ParameterSpec",
    "SYSTEMS",
    "build_model",
    "builtin_variants",
    "variant_name",
    "__version__",
]
