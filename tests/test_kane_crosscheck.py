"""Cross-check of our Chaplygin-ball model against an independent ``KanesMethod`` model.

The Kane model (:mod:`chaplygin.verify.kane`) is built from the physical description only
(3-2-1 Euler angles, contact coordinates, body angular velocity and centre velocity as speeds,
no-slip as nonholonomic velocity constraints, gravity included). Both sides give the body-frame
angular acceleration at the same state ``(M, gamma)``; they must agree to the tolerance of the
issue: 1e-12 relative, in double precision.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from chaplygin.derive import build_model
from chaplygin.verify.kane import (
    GAMMA1_LIMIT,
    euler_angles_for_gamma,
    kane_angular_acceleration,
    kane_contact_momentum,
    kane_energy_and_rate,
    model_angular_acceleration,
    omega_from_momentum,
)

#: From the issue: the two angular accelerations agree to 1e-12 relative (double precision).
RTOL = 1e-12
N_STATES = 24
SEED = 20240607
#: Samples keep |gamma1| below this, away from the 3-2-1 Euler singularity gamma1 = +-1.
GAMMA1_MAX = 0.9


@dataclass(frozen=True)
class Sample:
    """One random physical state and parameter set."""

    I: np.ndarray
    D: float
    b: float
    M: np.ndarray
    gamma: np.ndarray
    yaw: float

    def params(self, D_factor: float = 1.0) -> dict[str, float]:
        """Our model's parameters (optionally with a deliberately scaled ``D``)."""
        return {"I1": self.I[0], "I2": self.I[1], "I3": self.I[2], "D": self.D * D_factor}


def _samples() -> list[Sample]:
    rng = np.random.default_rng(SEED)
    out = []
    for _ in range(N_STATES):
        I = rng.uniform(0.5, 3.0, 3)
        D = float(rng.uniform(0.3, 2.0))
        b = float(rng.uniform(0.5, 2.0))
        M = rng.normal(size=3)
        while True:
            gamma = rng.normal(size=3)
            gamma /= np.linalg.norm(gamma)
            if abs(gamma[0]) <= GAMMA1_MAX:
                break
        yaw = float(rng.uniform(-np.pi, np.pi))
        out.append(Sample(I, D, b, M, gamma, yaw))
    return out


SAMPLES = _samples()


@pytest.fixture(scope="module")
def model():
    return build_model("chaplygin_ball")


def _relative_difference(reference: np.ndarray, other: np.ndarray) -> float:
    return float(np.linalg.norm(other - reference) / np.linalg.norm(reference))


@pytest.mark.parametrize("s", SAMPLES, ids=[f"state{i}" for i in range(N_STATES)])
def test_angular_acceleration_matches_kane(model, s: Sample) -> None:
    kane = kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, yaw=s.yaw)
    ours = model_angular_acceleration(model, s.params(), s.M, s.gamma)
    assert kane.shape == ours.shape == (3,)
    assert np.linalg.norm(kane) > 0
    assert np.linalg.norm(ours - kane) <= RTOL * np.linalg.norm(kane)


def test_negative_control_wrong_D_disagrees(model) -> None:
    """A model evaluated with D*1.1 must fail the same comparison at every state."""
    for s in SAMPLES:
        kane = kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, yaw=s.yaw)
        wrong = model_angular_acceleration(model, s.params(D_factor=1.1), s.M, s.gamma)
        assert np.linalg.norm(wrong - kane) > RTOL * np.linalg.norm(kane)
    # And by far, not marginally: the smallest discrepancy is still many orders above RTOL.
    worst = min(
        _relative_difference(
            kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, yaw=s.yaw),
            model_angular_acceleration(model, s.params(D_factor=1.1), s.M, s.gamma),
        )
        for s in SAMPLES
    )
    assert worst > 1e6 * RTOL


@pytest.mark.parametrize("s", SAMPLES[:8], ids=[f"state{i}" for i in range(8)])
def test_kane_side_conserves_energy(s: Sample) -> None:
    """Self-check of the Kane model: rolling and gravity do no work, so dT/dt = 0."""
    T, rate = kane_energy_and_rate(s.I, s.D, s.b, s.M, s.gamma, yaw=s.yaw)
    omega = omega_from_momentum(s.I, s.D, s.M, s.gamma)
    assert T > 0
    assert abs(rate) <= RTOL * T * np.linalg.norm(omega)


@pytest.mark.parametrize("s", SAMPLES[:8], ids=[f"state{i}" for i in range(8)])
def test_state_map_is_consistent(s: Sample) -> None:
    """sympy's angular momentum about the contact point, at the omega the Kane side uses,
    is the given M: the closed-form omega(M, gamma) of the Kane side is right."""
    omega = omega_from_momentum(s.I, s.D, s.M, s.gamma)
    M = kane_contact_momentum(s.I, s.D, s.b, omega, s.gamma, yaw=s.yaw)
    assert np.linalg.norm(M - s.M) <= RTOL * np.linalg.norm(s.M)


def test_yaw_gravity_and_radius_do_not_change_the_kane_result() -> None:
    """The heading, g and (at fixed D = m b^2) the radius drop out of the dynamics."""
    s = SAMPLES[0]
    ref = kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, yaw=0.0, g=9.81)
    for yaw, g, b in [(1.3, 9.81, s.b), (-2.0, 0.0, s.b), (0.4, 25.0, 2.0 * s.b)]:
        other = kane_angular_acceleration(s.I, s.D, b, s.M, s.gamma, yaw=yaw, g=g)
        assert np.linalg.norm(other - ref) <= RTOL * np.linalg.norm(ref)


def test_euler_angles_reject_singular_and_non_unit_gamma() -> None:
    near_pole = np.array([GAMMA1_LIMIT + 1e-3, 0.0, 0.0])
    near_pole[2] = np.sqrt(1.0 - near_pole[0] ** 2)
    with pytest.raises(ValueError, match="singularity"):
        euler_angles_for_gamma(near_pole)
    with pytest.raises(ValueError, match="unit"):
        euler_angles_for_gamma([0.0, 0.0, 2.0])
