"""Claims about our own models: every integral and density a built-in model ships is proved.

Numerics reports the drift of these integrals; they must be true first-integrals.
IDs: ``MODEL:<variant>.integral(<name>)`` and ``MODEL:<variant>.density``.
"""

from __future__ import annotations

import sympy as sp
from chaplygin.derive import Model, builtin_variants, variant_name

from ..identity import lie_derivative, measure_residual
from . import Check, Claim, register


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


def _register_all() -> None:
    from chaplygin.derive import build_model

    for system, effects in builtin_variants():
        name = variant_name(system, effects)
        model = build_model(system, effects)
        for integral, _ in model.integrals:
            register(
                Claim(
                    f"MODEL:{name}.integral{integral}",
                    "chaplygin model",
                    "integral",
                    f"{integral} is a first integral of the derived model {name}",
                    system,
                    tuple(sorted(effects)),
                    _integral(integral),
                )
            )
        if model.density is not None:
            register(
                Claim(
                    f"MODEL:{name}.density",
                    "chaplygin model",
                    "measure",
                    f"the density the model ships is invariant for {name}",
                    system,
                    tuple(sorted(effects)),
                    _density,
                )
            )


_register_all()
