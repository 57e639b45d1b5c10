"""Reference data shared by the tests (one place), with its source.

The reference problem is the one of the foundation issue and of the benchmark
(BKM12 §1.1 equations): I = (1, 2, 3), D = 1, gamma0 = (0.2, 0.3, sqrt(0.87)),
M0 = (0.7, -0.4, 0.5).
"""

from __future__ import annotations

import functools

import numpy as np
from chaplygin.derive import phase_space

REFERENCE_PARAMS = {"I": (1, 2, 3), "D": 1}
REFERENCE_Y0 = {"M": (0.7, -0.4, 0.5), "gamma": ("0.2", "0.3", "sqrt(0.87)")}
EPS = np.finfo(float).eps


def random_state(code, rng: np.random.Generator) -> np.ndarray:
    """A random point of the phase space of a model variant (by its state groups):
    derive's floating-point sampler (:func:`chaplygin.derive.phase_space.random_state`)."""
    return phase_space.random_state(code.state_groups, rng)


def random_params(code, rng: np.random.Generator) -> np.ndarray:
    """Random physical parameters: positive ones in [0.3, 3], real ones in [-1, 1]."""
    out = []
    for _, (symbols, domain, _) in code.parameter_groups.items():
        low, high = (0.3, 3.0) if domain == "positive" else (-1.0, 1.0)
        out += list(rng.uniform(low, high, size=len(symbols)))
    return np.array(out)


def assert_close_rel(actual, desired, rtol: float, what: str = "") -> None:
    """``|actual - desired| <= rtol * max(|desired|)`` elementwise over the array."""
    actual, desired = np.asarray(actual, dtype=float), np.asarray(desired, dtype=float)
    scale = np.max(np.abs(desired))
    err = np.max(np.abs(actual - desired))
    assert err <= rtol * scale, f"{what}: max error {err:.3e} > {rtol:.1e} x {scale:.3e}"


@functools.cache
def verdict(claim_id: str, method: str = "auto"):
    """The verdict of a registered claim, decided once per test session (several test
    modules look at the same claims; the sampler is seeded, so a verdict is the same
    whenever it is decided)."""
    from chaplygin.verify.claims import REGISTRY, select_claims
    from chaplygin.verify.verdict import check_claim

    select_claims()
    return check_claim(REGISTRY[claim_id], method=method)
