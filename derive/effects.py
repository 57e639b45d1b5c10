"""Effects: structural options that decide which terms, states and parameters exist.

An effect that is off contributes nothing to a model. Each system lists the effects it
supports; numeric parameter values are never part of an effect.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from .errors import UserInputError

__all__ = ["Effect", "EFFECTS", "parse_effects"]


@dataclass(frozen=True)
class Effect:
    """A named structural option.

    Parameters
    ----------
    name : str
    description : str
    adds : str
        What it adds to a model (for help texts and the README).
    """

    name: str
    description: str
    adds: str


EFFECTS: dict[str, Effect] = {
    e.name: e
    for e in (
        Effect(
            "gyrostat",
            "a rotor spinning at a constant relative rate: constant gyrostatic momentum K "
            "(K01 §4, BKM12 §2.3)",
            "parameters K1, K2, K3; the term (K, omega) in T",
        ),
        Effect(
            "variable_inertia",
            "periodically varying inertia I(t) = diag(I1 + (J_off + delta sin(Omega t))^2, I2, "
            "I3 + (J_off + delta sin(Omega t))^2) (BM20 (3.4): two masses moving along Cx2)",
            "parameters J_off, delta, Omega; I becomes the constant part",
        ),
        Effect(
            "variable_gyrostat",
            "periodically varying gyrostatic momentum k(t) = K sin(Omega t) (BM20 (3.5)); "
            "the state M is then BM20's total momentum I omega + D gamma x (omega x gamma) + k",
            "parameters K1, K2, K3, Omega; excludes the constant gyrostat",
        ),
        Effect(
            "contact_point",
            "track the space-fixed horizontal frame alpha, beta and the contact point x, y "
            "(BKM12-6, K01-2.4..2.6)",
            "states alpha, beta, x, y; parameter b (ball radius)",
        ),
        Effect(
            "rubber",
            "no twist at the contact: the extra constraint (omega, gamma) = 0 (rubber ball, "
            "BKM12 §3); its multiplier is eliminated by the engine",
            "no new states or parameters; (M, M) is no longer an integral",
        ),
        Effect(
            "straight_line",
            "the ball rolls along a straight line of the plane: the extra constraint "
            "(omega, alpha) = 0 (Veselovs' system, BKM12 §3, (57)-(58))",
            "states alpha, beta (the space-fixed horizontal frame)",
        ),
        Effect(
            "potential",
            "a quadratic potential U = k/2 (c1 x1^2 + c2 x2^2 + c3 x3^2) acting on the centre "
            "(M03 (1.6))",
            "parameters k, c1, c2, c3",
        ),
        Effect(
            "rubber_balls",
            "the supporting balls roll without slipping and without twisting (BKM12 §2.2): "
            "the support tensor becomes sum_k lambda_k (1/r_k^2 - 1) n_k ⊗ n_k",
            "no new states; the support parameters keep their meaning (modified D tensor)",
        ),
    )
}


def parse_effects(effects: str | Iterable[str] | None, supported: Iterable[str]) -> frozenset[str]:
    """Validate a set of effect names against what a system supports.

    Parameters
    ----------
    effects : str or iterable of str or None
        Comma-separated string or names; None or "" means no effects.
    supported : iterable of str

    Returns
    -------
    frozenset of str

    Raises
    ------
    UserInputError
        For an unknown or unsupported effect; the message lists the valid names.
    """
    if effects is None:
        return frozenset()
    if isinstance(effects, str):
        names = [e.strip() for e in effects.split(",") if e.strip()]
    else:
        names = [str(e).strip() for e in effects]
    supported = sorted(supported)
    bad = [n for n in names if n not in supported]
    if bad:
        raise UserInputError(
            f"unknown effect {bad[0]!r}; this system supports: {', '.join(supported) or 'none'}"
        )
    return frozenset(names)
