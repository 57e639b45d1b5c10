"""chaplygin: derive, verify and integrate nonholonomic rolling systems.

``import chaplygin`` gives the public surface in one import. This folder is the package root
``chaplygin`` itself (pyproject maps it: the fixed top-level layout has no folder of its own
for the root); the layers stay where they are: ``chaplygin.derive`` (sympy models),
``chaplygin.generated`` (emitted code), ``chaplygin.numerics`` (integration) and
``chaplygin.verify`` (claims, verdicts, commands). Names are resolved on first use, so the
import itself is cheap (sympy, scipy and matplotlib load when a function needs them).

Examples
--------
>>> import chaplygin
>>> model = chaplygin.build_model("chaplygin_ball", effects=["gyrostat"])    # doctest: +SKIP
>>> chaplygin.check("BKM12-4")                                               # doctest: +SKIP
BKM12-4: proved (Groebner normal form ...)
>>> r = chaplygin.integrate("chaplygin_ball", {"M": (0.7, -0.4, 0.5),
...     "gamma": (0.2, 0.3, "sqrt(0.87)")}, 10, {"I": (1, 2, 3), "D": 1})   # doctest: +SKIP
>>> chaplygin.delta((1, 3, 5), 1, 1, digits=30).closed                       # doctest: +SKIP
"""

from __future__ import annotations

import importlib
from importlib.metadata import PackageNotFoundError, version
from typing import Any

try:
    __version__ = version("chaplygin")
except PackageNotFoundError:  # pragma: no cover - running from an uninstalled tree
    __version__ = "0+unknown"

#: public name -> "module:attribute" (modules relative to the package root)
_PUBLIC: dict[str, str] = {
    # models and effects (derive)
    "build_model": "derive.systems:build_model",
    "RollingSystem": "derive.rolling_system:RollingSystem",
    "register_system": "derive.systems:register_system",
    "builtin_description": "derive.builtin_descriptions:builtin_description",
    "BuiltinDescription": "derive.builtin_descriptions:BuiltinDescription",
    "Model": "derive.model:Model",
    "EFFECTS": "derive.effects:EFFECTS",
    "UserInputError": "derive.errors:UserInputError",
    "ChaplyginError": "derive.errors:ChaplyginError",
    "ComputationError": "derive.errors:ComputationError",
    "CacheError": "derive.errors:CacheError",
    # numerics
    "integrate": "numerics.integrate:integrate",
    "integrate_many": "numerics.ensemble:integrate_many",
    "EnsembleResult": "numerics.ensemble:EnsembleResult",
    "Propagator": "numerics.propagator:Propagator",
    "EnsemblePropagator": "numerics.ensemble_propagator:EnsemblePropagator",
    "IntegrationResult": "numerics.integrate:IntegrationResult",
    "METHODS": "numerics.integrate:METHODS",
    "Precision": "numerics.precision:Precision",
    "load_model_code": "numerics.code:load_model_code",
    "delta": "numerics.ball.separatrix:delta_three_ways",
    "torus_quadratures": "numerics.ball.quadratures:torus_quadratures",
    "flow_with_jacobian": "numerics.dynamics.variational:flow_with_jacobian",
    "flow_jacobians": "numerics.dynamics.variational:flow_jacobians",
    "attractor_regimes": "numerics.ball.regimes:attractor_regimes",
    "lyapunov_spectrum": "numerics.dynamics.lyapunov:lyapunov_spectrum",
    "lyapunov_spectra": "numerics.dynamics.lyapunov_batch:lyapunov_spectra",
    # proofs by computation (Arb ball arithmetic)
    "enclose_flow": "numerics.validated.lohner:enclose_flow",
    "FlowEnclosure": "numerics.validated.lohner:FlowEnclosure",
    "EnclosureError": "numerics.validated.lohner:EnclosureError",
    "enclose_crossing": "numerics.validated.sections:enclose_crossing",
    "prove_bm20_periodic_orbit": "numerics.ball.bm20_enclosure:prove_bm20_periodic_orbit",
    "prove_critical_energy": "numerics.ball.frame_turn_enclosure:prove_critical_energy",
    "enclose_frame_turn": "numerics.ball.frame_turn_enclosure:enclose_frame_turn",
    "prove_steady_rotation_stability": (
        "numerics.ball.steady_enclosure:prove_steady_rotation_stability"
    ),
    "enclose_delta": "numerics.ball.separatrix_enclosure:enclose_delta",
    # claims and verdicts (verify)
    "claims": "verify.claims:select_claims",
    "check": "verify.check:check",
    "Claim": "verify.claims:Claim",
    "Verdict": "verify.verdict:Verdict",
    # discovery (derive searches, verify proves)
    "discover": "verify.discover:discover",
    "find_polynomial_integrals": "derive.discovery:find_polynomial_integrals",
    "find_invariant_densities": "derive.densities:find_invariant_densities",
    "find_invariant_relations": "derive.invariants:find_invariant_relations",
    "find_symmetries": "derive.symmetries:find_symmetries",
    # figures (matplotlib Figure objects)
    "delta_figure": "verify.plots:delta_of_mu_figure",
    "separatrix_figures": "verify.plots:separatrix_figures",
    "bifurcation_figure": "verify.plots:bifurcation_figure",
    "work_precision_figure": "verify.plots:work_precision_figure",
    # scenes (one experiment per TOML file)
    "Scene": "verify.scene:Scene",
}

__all__ = ["__version__", *_PUBLIC]


def __getattr__(name: str) -> Any:
    """Resolve a public name on first use (PEP 562) and cache it in the module."""
    target = _PUBLIC.get(name)
    if target is None:
        raise AttributeError(f"module 'chaplygin' has no attribute {name!r}")
    module, attribute = target.split(":")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), attribute)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_PUBLIC))
