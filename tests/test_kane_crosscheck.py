"""Cross-check of our Chaplygin-ball model against an independent ``KanesMethod`` model.

The Kane model (:mod:`chaplygin.verify.kane`) is built from the physical description only
(3-2-1 Euler angles, contact coordinates, body angular velocity and centre velocity as speeds,
no-slip as nonholonomic velocity constraints, gravity included). Both sides give the body-frame
angular acceleration at the same state ``(M, gamma)``; they must agree to the tolerance of the
issue: 1e-12 relative, in double precision.

The two variants with one more constraint on the angular velocity are checked the same way:
the rubber ball (``["rubber"]``, no twist ``(omega, gamma) = 0``) and Veselovs' ball rolling
along a straight line (``["straight_line"]``, ``(omega, alpha) = 0``). The Kane side imposes
``omega . N.z = 0`` resp. ``omega . N.x = 0`` as a velocity constraint (a dependent speed), and
the states are admissible: ``omega`` is drawn on the constraint plane first, ``M = II omega``;
for the straight line ``alpha, beta`` are the body-frame components of ``N.x, N.y`` in the
Kane configuration (:func:`space_axes_in_body`). Same tolerance, 1e-12 relative: both sides are
a few dozen well-conditioned floating-point operations away from the exact value, and the
observed discrepancy is a few 1e-14.

The gyrostat (``["gyrostat"]``, K01 §4) is checked against a Kane model with a second rigid
body, a rotor spinning at a constant rate inside the ball; our model's ``K`` is the rotor's
axial momentum ``Ia s e``. BM20's time-varying inertia (``["variable_inertia"]``, (3.4)) is
checked against a Kane model in which two point masses slide along the body axis 2 at the
prescribed positions. Same tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from chaplygin.derive import build_model
from chaplygin.verify.kane import (
    EXTRA_CONSTRAINTS,
    GAMMA1_LIMIT,
    Rotor,
    euler_angles_for_gamma,
    kane_angular_acceleration,
    kane_contact_momentum,
    kane_energy_and_rate,
    kane_moving_masses_angular_acceleration,
    model_angular_acceleration,
    omega_from_momentum,
    space_axes_in_body,
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


# --------------------------------------------------------------------------------------------
# One more constraint on the angular velocity: the rubber ball and Veselovs' straight line
# --------------------------------------------------------------------------------------------

#: Kane-side constraint name -> the model effect, and the row of ``space_axes_in_body``
#: (alpha = N.x, beta = N.y, gamma = N.z) along which omega must vanish.
CONSTRAINED = {"rubber": ("rubber", 2), "straight_line": ("straight_line", 0)}
OMEGA_SEED = 20240608


@dataclass(frozen=True)
class ConstrainedSample:
    """An admissible state of a constrained variant (built on a :class:`Sample`)."""

    base: Sample
    constraint: str
    omega: np.ndarray
    M: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray

    @property
    def gamma(self) -> np.ndarray:
        return self.base.gamma

    def kane(self) -> np.ndarray:
        s = self.base
        return kane_angular_acceleration(
            s.I, s.D, s.b, self.M, s.gamma, yaw=s.yaw, constraint=self.constraint
        )

    def ours(self, model) -> np.ndarray:
        groups = {"alpha": self.alpha, "beta": self.beta}
        return model_angular_acceleration(model, self.base.params(), self.M, self.gamma, groups)


def _constrained_samples(constraint: str) -> list[ConstrainedSample]:
    """Admissible states: omega on the constraint plane first, then ``M = II omega``."""
    rng = np.random.default_rng([OMEGA_SEED, EXTRA_CONSTRAINTS.index(constraint)])
    out = []
    for s in SAMPLES:
        alpha, beta, gamma = space_axes_in_body(s.gamma, s.yaw)
        normal = (alpha, beta, gamma)[CONSTRAINED[constraint][1]]
        omega = rng.normal(size=3)
        omega -= (omega @ normal) * normal
        omega *= rng.uniform(0.5, 2.0) / np.linalg.norm(omega)  # |omega| away from 0
        II = np.diag(s.I) + s.D * (np.eye(3) - np.outer(s.gamma, s.gamma))
        out.append(ConstrainedSample(s, constraint, omega, II @ omega, alpha, beta))
    return out


CONSTRAINED_SAMPLES = {c: _constrained_samples(c) for c in EXTRA_CONSTRAINTS}
CONSTRAINED_CASES = [
    pytest.param(c, i, id=f"{c}-state{i}") for c in EXTRA_CONSTRAINTS for i in range(N_STATES)
]


@pytest.fixture(scope="module")
def constrained_models():
    return {c: build_model("chaplygin_ball", [CONSTRAINED[c][0]]) for c in EXTRA_CONSTRAINTS}


def test_constrained_samples_are_admissible_frames() -> None:
    """The sampled alpha, beta, gamma form a right-handed orthonormal frame (gamma = alpha x
    beta) with the drawn vertical, and omega satisfies the constraint."""
    for c in EXTRA_CONSTRAINTS:
        for cs in CONSTRAINED_SAMPLES[c]:
            frame = np.array([cs.alpha, cs.beta, cs.gamma])
            assert np.allclose(frame @ frame.T, np.eye(3), rtol=0, atol=1e-14)
            assert np.linalg.norm(np.cross(cs.alpha, cs.beta) - cs.gamma) <= 1e-14
            normal = frame[CONSTRAINED[c][1]]
            assert abs(cs.omega @ normal) <= 1e-14 * np.linalg.norm(cs.omega)
            assert np.linalg.norm(cs.omega) > 0.1


@pytest.mark.parametrize(("constraint", "i"), CONSTRAINED_CASES)
def test_constrained_angular_acceleration_matches_kane(
    constrained_models, constraint: str, i: int
) -> None:
    cs = CONSTRAINED_SAMPLES[constraint][i]
    kane = cs.kane()
    ours = cs.ours(constrained_models[constraint])
    assert kane.shape == ours.shape == (3,)
    assert np.linalg.norm(kane) > 0
    assert np.linalg.norm(ours - kane) <= RTOL * np.linalg.norm(kane)


@pytest.mark.parametrize("constraint", EXTRA_CONSTRAINTS)
def test_negative_control_plain_ball_disagrees_with_constrained_kane(
    model, constraint: str
) -> None:
    """The plain ball (no extra constraint) at the same admissible states must fail the
    comparison with the constrained Kane result, and by far: the reaction of the extra
    constraint changes omega_dot at every state."""
    worst = min(
        _relative_difference(
            cs.kane(), model_angular_acceleration(model, cs.base.params(), cs.M, cs.gamma)
        )
        for cs in CONSTRAINED_SAMPLES[constraint]
    )
    assert worst > 1e6 * RTOL


def test_negative_control_constrained_models_are_not_interchangeable(constrained_models) -> None:
    """The rubber model at straight-line states (and vice versa) disagrees with Kane."""
    for c, other in [("rubber", "straight_line"), ("straight_line", "rubber")]:
        worst = min(
            _relative_difference(cs.kane(), cs.ours(constrained_models[other]))
            for cs in CONSTRAINED_SAMPLES[c]
        )
        assert worst > 1e6 * RTOL


@pytest.mark.parametrize("constraint", EXTRA_CONSTRAINTS)
def test_constrained_kane_side_keeps_constraint_and_energy(constraint: str) -> None:
    """Self-checks of the constrained Kane model: (omega, n)' = (omega_dot, n) = 0 for the
    space-fixed n (its body components obey n' = n x omega), and the constraint's reaction
    does no work, dT/dt = 0."""
    for cs in CONSTRAINED_SAMPLES[constraint][:8]:
        s = cs.base
        normal = np.array([cs.alpha, cs.beta, cs.gamma])[CONSTRAINED[constraint][1]]
        w_dot = cs.kane()
        assert abs(w_dot @ normal) <= RTOL * np.linalg.norm(w_dot)
        T, rate = kane_energy_and_rate(
            s.I, s.D, s.b, cs.M, s.gamma, yaw=s.yaw, constraint=constraint
        )
        assert T > 0
        assert abs(rate) <= RTOL * T * np.linalg.norm(cs.omega)


def test_constrained_kane_rejects_inadmissible_states() -> None:
    s = SAMPLES[0]
    with pytest.raises(ValueError, match="violates the 'rubber' constraint"):
        kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, yaw=s.yaw, constraint="rubber")
    with pytest.raises(ValueError, match="unknown constraint"):
        kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, constraint="no_spin")


def test_straight_line_depends_on_heading_rubber_does_not() -> None:
    """Turning the heading turns the line in the body frame (another alpha): the straight-line
    dynamics change; the rubber ball's do not (no horizontal direction is distinguished)."""
    s = SAMPLES[1]
    rubber = CONSTRAINED_SAMPLES["rubber"][1]
    ref = rubber.kane()
    turned = kane_angular_acceleration(
        s.I, s.D, s.b, rubber.M, s.gamma, yaw=s.yaw + 1.0, constraint="rubber"
    )
    assert np.linalg.norm(turned - ref) <= RTOL * np.linalg.norm(ref)
    # A spin about the vertical, omega = gamma, is admissible for every heading of the line.
    g = s.gamma
    M = (np.diag(s.I) + s.D * (np.eye(3) - np.outer(g, g))) @ g
    results = [
        kane_angular_acceleration(s.I, s.D, s.b, M, g, yaw=yaw, constraint="straight_line")
        for yaw in (s.yaw, s.yaw + 1.0)
    ]
    assert _relative_difference(*results) > 1e6 * RTOL


def test_model_angular_acceleration_needs_every_state_group(constrained_models) -> None:
    cs = CONSTRAINED_SAMPLES["straight_line"][0]
    with pytest.raises(KeyError, match="alpha"):
        model_angular_acceleration(
            constrained_models["straight_line"], cs.base.params(), cs.M, cs.gamma
        )


# ------------------------------------------------------------------ gyrostat (K01 §4)
N_ROTOR_STATES = 6


def _rotor_samples() -> list[tuple[Sample, Rotor]]:
    rng = np.random.default_rng(SEED + 4)
    out = []
    for s in SAMPLES[:N_ROTOR_STATES]:
        # a small rotor, so that the ball's own tensor diag(I) - rotor stays positive
        axial, transverse = (float(x) for x in rng.uniform(0.05, 0.2, 2))
        rotor = Rotor(tuple(rng.normal(size=3)), axial, transverse, float(rng.uniform(-8, 8)))
        out.append((s, rotor))
    return out


ROTOR_SAMPLES = _rotor_samples()


def _gyrostat_params(s: Sample, K: np.ndarray) -> dict[str, float]:
    return {**s.params(), "K1": K[0], "K2": K[1], "K3": K[2]}


@pytest.mark.parametrize(
    ("s", "rotor"), ROTOR_SAMPLES, ids=[f"state{i}" for i in range(N_ROTOR_STATES)]
)
def test_gyrostat_angular_acceleration_matches_kane_with_a_spinning_rotor(s, rotor):
    """K01-4.1: the ball with a rotor turning at a constant rate (a second rigid body of the
    Kane model) is our gyrostat model with K = Ia s e; same tolerance as the plain ball."""
    model = build_model("chaplygin_ball", ["gyrostat"])
    kane = kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, yaw=s.yaw, rotor=rotor)
    ours = model_angular_acceleration(model, _gyrostat_params(s, rotor.momentum()), s.M, s.gamma)
    assert _relative_difference(kane, ours) < RTOL


def test_negative_control_reversed_gyrostatic_momentum_disagrees_with_kane():
    model = build_model("chaplygin_ball", ["gyrostat"])
    for s, rotor in ROTOR_SAMPLES:
        kane = kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, yaw=s.yaw, rotor=rotor)
        wrong = model_angular_acceleration(
            model, _gyrostat_params(s, -rotor.momentum()), s.M, s.gamma
        )
        assert _relative_difference(kane, wrong) > 1e3 * RTOL


def test_a_rotor_needs_an_axis_and_positive_moments():
    s = SAMPLES[0]
    for bad in (Rotor((0, 0, 0), 0.1, 0.1, 1.0), Rotor((1, 0, 0), -0.1, 0.1, 1.0)):
        with pytest.raises(ValueError):
            kane_angular_acceleration(s.I, s.D, s.b, s.M, s.gamma, rotor=bad)


# ------------------------------------------- time-varying inertia (BM20 (3.4), moving masses)
def _moving_mass_samples(n: int = 6):
    rng = np.random.default_rng(SEED + 5)
    out = []
    while len(out) < n:
        I = rng.uniform(0.5, 3.0, 3)
        b = float(rng.uniform(0.5, 1.5))
        D = b**2 * float(rng.uniform(1.5, 4.0))  # the two masses weigh 1 together
        law = (float(rng.uniform(-1, 1)), float(rng.uniform(0.2, 2)), float(rng.uniform(0.3, 2)))
        M = rng.normal(size=3)
        gamma = rng.normal(size=3)
        gamma /= np.linalg.norm(gamma)
        if abs(gamma[0]) <= GAMMA1_MAX:
            out.append((I, D, b, law, M, gamma, float(rng.uniform(-5, 5))))
    return out


MOVING = _moving_mass_samples()


def _bm20_params(I, D, law) -> dict[str, float]:
    return {
        "I1": I[0],
        "I2": I[1],
        "I3": I[2],
        "D": D,
        "J_off": law[0],
        "delta": law[1],
        "Omega": law[2],
    }


@pytest.mark.parametrize("sample", MOVING, ids=[f"state{i}" for i in range(len(MOVING))])
def test_variable_inertia_matches_kane_with_two_moving_masses(sample):
    """BM20 (2.5) with I(t) of (3.4), derived by our engine, against a Kane model in which
    two point masses slide along the body axis 2 at the prescribed positions
    +-(J_off + delta sin(Omega t)): same tolerance as the plain ball."""
    I, D, b, law, M, gamma, t = sample
    model = build_model("chaplygin_ball", ["variable_inertia"])
    kane = kane_moving_masses_angular_acceleration(I, D, b, law, M, gamma, t)
    ours = model_angular_acceleration(model, _bm20_params(I, D, law), M, gamma, t=t)
    assert _relative_difference(kane, ours) < RTOL


def test_negative_control_frozen_inertia_disagrees_with_the_moving_masses():
    """The plain ball with the inertia frozen at I(t) misses the I'(t) omega term."""
    plain = build_model("chaplygin_ball")
    for I, D, b, law, M, gamma, t in MOVING:
        offset = law[0] + law[1] * np.sin(law[2] * t)
        frozen = {"I1": I[0] + offset**2, "I2": I[1], "I3": I[2] + offset**2, "D": D}
        kane = kane_moving_masses_angular_acceleration(I, D, b, law, M, gamma, t)
        wrong = model_angular_acceleration(plain, frozen, M, gamma)
        assert _relative_difference(kane, wrong) > 1e3 * RTOL
