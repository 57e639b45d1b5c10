"""Symbolic layer: mechanical descriptions -> derived models -> emitted code.

Imports nothing from the other layers of chaplygin.
"""

from __future__ import annotations

from .declaration import Constraint, Declaration
from .description import MechanicalDescription, Reduced, Reduction, apply_effects, form_model
from .effects import EFFECTS, Effect, parse_effects
from .engine import ReducedEquations, RigidBodyDescription, lagrange_dalembert
from .errors import ChaplyginError, DerivationError, UserInputError
from .model import Model, ModelDetails, ParameterSpec, Reparametrisation
from .phase_space import sample_point
from .rigid_body import RigidBodyReduction
from .systems import SYSTEMS, build_model, builtin_variants, variant_name

__version__ = "0.1.0"

__all__ = [
    "EFFECTS",
    "Effect",
    "parse_effects",
    "MechanicalDescription",
    "Declaration",
    "Constraint",
    "Reduced",
    "Reduction",
    "RigidBodyReduction",
    "apply_effects",
    "form_model",
    "RigidBodyDescription",
    "ReducedEquations",
    "lagrange_dalembert",
    "ChaplyginError",
    "DerivationError",
    "UserInputError",
    "Model",
    "ParameterSpec",
    "ModelDetails",
    "Reparametrisation",
    "sample_point",
    "SYSTEMS",
    "build_model",
    "builtin_variants",
    "variant_name",
    "__version__",
]
