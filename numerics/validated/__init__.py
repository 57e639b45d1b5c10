"""Validated numerics: enclosures of the flow and of its derivative in Arb ball arithmetic
(python-flint), on the same generated Taylor recurrences as the floating-point integrators."""

from .constraints import unit_norm
from .lohner import EnclosureError, FlowEnclosure, enclose_flow, to_ball, working_precision

__all__ = [
    "EnclosureError",
    "FlowEnclosure",
    "enclose_flow",
    "to_ball",
    "unit_norm",
    "working_precision",
]
