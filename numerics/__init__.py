"""Numerical layer: generated code loaded and integrated in double or arbitrary precision."""

from .code import ModelCode, load_model_code
from .integrate import METHODS, IntegrationResult, integrate

__all__ = ["ModelCode", "load_model_code", "integrate", "IntegrationResult", "METHODS"]
