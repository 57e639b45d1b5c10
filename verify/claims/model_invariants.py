"""Claims about our own models: every integral and density a built-in model ships is proved.

Numerics reports the drift of these integrals; they must be true first-integrals.
IDs: ``MODEL:<variant>.integral(<name>)`` and ``MODEL:<variant>.density``.
"""

from __future__ import annotations

from collections.abc import Iterator

import sympy as sp
from chaplygin.derive import Model, builtin_variants, variant_name

from ..identity import lie_derivative, measure_residual
from .base import Check, Claim, register


def _integral(name: str):
    def build(model: Model) -> Check:
        full = Check([lie_derivative(model.integral(name), model)])
        mu = [s for s in model.aux_symbols if s.name.startswith("mu")]
        if not mu:
            return full
        # The reaction of a constraint on omega alone does no work and has no moment
        # about the free axes: most integrals are conserved whatever the multipliers
        # are, which is far cheaper to prove (the multipliers' expressions are large).
        keep = lie_derivative(model.integral(name), model, keep=mu)
        parts = [keep.xreplace({m: 0 for m in mu})] + [sp.diff(keep, m) for m in mu]
        return Check(parts, free=mu, fallback=full, note="for every value of the multipliers")

    return build


def _density(model: Model) -> Check:
    return Check([measure_residual(model.density, model)])


def _model_claims() -> Iterator[Claim]:
    """One claim per integral and density of every built-in variant (derives the models:
    the registry loads this module only when a ``MODEL:`` claim may be asked for)."""
    from chaplygin.derive import build_model

    for system, effects in builtin_variants():
        name = variant_name(system, effects)
        model = build_model(system, effects)
        for integral, _ in model.integrals:
            yield Claim(
                id=f"MODEL:{name}.integral{integral}",
                source="chaplygin model",
                kind="integral",
                statement=f"{integral} is a first integral of the derived model {name}",
                system=system,
                effects=tuple(sorted(effects)),
                build=_integral(integral),
            )
        if model.density is not None:
            yield Claim(
                id=f"MODEL:{name}.density",
                source="chaplygin model",
                kind="measure",
                statement=f"the density the model ships is invariant for {name}",
                system=system,
                effects=tuple(sorted(effects)),
                build=_density,
            )


register(*_model_claims())
