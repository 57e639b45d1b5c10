"""Reference data shared by the tests (one place), with its source.

The reference problem is the one of the foundation issue and of the benchmark
(BKM12 §1.1 equations): I = (1, 2, 3), D = 1, gamma0 = (0.2, 0.3, sqrt(0.87)),
M0 = (0.7, -0.4, 0.5).
"""

from __future__ import annotations

import functools

import numpy as np

REFERENCE_PARAMS = {"I": (1, 2, 3), "D": 1}
REFERENCE_Y0 = {"M": (0.7, -0.4, 0.5), "gamma": ("0.2", "0.3", "sqrt(0.87)")}
EPS = np.finfo(float).eps


def random_unit(rng: np.random.Generator, n: int | None = None) -> np.ndarray:
    """Uniform random unit vector(s), shape (3,) or (3, n)."""
    v = rng.normal(size=(3,) if n is None else (3, n))
    return v / np.linalg.norm(v, axis=0)


def random_frame(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A random right-handed orthonormal frame (alpha, beta, gamma = alpha x beta)."""
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    if np.linalg.det(q) < 0:
        q[:, 0] *= -1
    alpha, beta = q[:, 0], q[:, 1]
    return alpha, beta, np.cross(alpha, beta)


def random_state(code, rng: np.random.Generator) -> np.ndarray:
    """A random point of the phase space of a model variant (by its state groups)."""
    groups = code.state_groups
    values: dict[str, np.ndarray] = {"M": rng.normal(size=3)}
    if "alpha" in groups:
        values["alpha"], values["beta"], values["gamma"] = random_frame(rng)
        values["x"], values["y"] = rng.normal(size=1), rng.normal(size=1)
    else:
        values["gamma"] = random_unit(rng)
    return np.concatenate([np.atleast_1d(values[name]) for name in groups])


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
