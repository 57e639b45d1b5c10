"""Random physical states of the Kane cross-check (the claims KANE-* and
``tests/verify/test_kane_crosscheck.py``): the plain ball, its constrained variants, the gyrostat
and the moving masses, each with the Kane side's and the model's angular accelerations
(:mod:`chaplygin.verify.kane`)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy as sp

from ..arith import detlinalg
from .kane import EXTRA_CONSTRAINTS, Rotor, kane_angular_acceleration, space_axes_in_body
from .kane_moving_masses import kane_moving_masses_angular_acceleration

if TYPE_CHECKING:  # pragma: no cover
    from ..derive.model import Model

__all__ = [
    "SEED",
    "N_STATES",
    "GAMMA1_MAX",
    "OMEGA_SEED",
    "CONSTRAINT_AXIS",
    "KaneSample",
    "ConstrainedSample",
    "MovingMassSample",
    "random_samples",
    "constrained_samples",
    "rotor_samples",
    "gyrostat_params",
    "moving_mass_samples",
    "relative_difference",
    "model_angular_acceleration",
]


#: Seed and number of the random physical states of the cross-check.
SEED = 20240607
N_STATES = 24
#: Samples keep |gamma1| below this, away from the 3-2-1 Euler singularity gamma1 = +-1.
GAMMA1_MAX = 0.9
#: Seed of the admissible angular velocities of the constrained variants.
OMEGA_SEED = 20240608
#: Row of :func:`space_axes_in_body` (alpha = N.x, beta = N.y, gamma = N.z) along which
#: omega vanishes, per extra constraint.
CONSTRAINT_AXIS = {"rubber": 2, "straight_line": 0}


@dataclass(frozen=True)
class KaneSample:
    """One random physical state and parameter set of the plain ball.

    Attributes
    ----------
    I : numpy.ndarray
        Principal moments, shape (3,).
    D, b : float
        ``m b^2`` and the radius.
    M, gamma : numpy.ndarray
        Momentum about the contact point and unit vertical (body frame), shape (3,).
    yaw : float
        Heading of the Kane configuration.
    """

    I: np.ndarray  # noqa: E741  (the papers' name)
    D: float
    b: float
    M: np.ndarray
    gamma: np.ndarray
    yaw: float

    def params(self, D_factor: float = 1.0) -> dict[str, float]:
        """Our model's parameters (optionally with a deliberately scaled ``D``).

        Parameters
        ----------
        D_factor : float, optional
            Factor on ``D`` (a negative control uses ``1.1``).

        Returns
        -------
        dict of str to float
            ``I1, I2, I3, D``.
        """
        return {"I1": self.I[0], "I2": self.I[1], "I3": self.I[2], "D": self.D * D_factor}

    def kane(self, **kwargs: Any) -> np.ndarray:
        """:func:`kane_angular_acceleration` at this state (keyword arguments passed on).

        Parameters
        ----------
        **kwargs
            Keyword arguments of :func:`kane_angular_acceleration` other than ``yaw``
            (``g``, ``constraint``, ``rotor``).

        Returns
        -------
        numpy.ndarray
            ``omega_dot`` in the body frame, shape (3,).
        """
        return kane_angular_acceleration(
            self.I, self.D, self.b, self.M, self.gamma, yaw=self.yaw, **kwargs
        )


def random_samples(n: int = N_STATES, seed: int = SEED) -> list[KaneSample]:
    """Random states: ``I`` in [0.5, 3], ``D`` in [0.3, 2], ``b`` in [0.5, 2], normal ``M``,
    uniform unit ``gamma`` with ``|gamma1| <= GAMMA1_MAX``, uniform heading.

    Parameters
    ----------
    n : int
    seed : int

    Returns
    -------
    list of KaneSample
    """
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        I = rng.uniform(0.5, 3.0, 3)  # noqa: E741
        D = float(rng.uniform(0.3, 2.0))
        b = float(rng.uniform(0.5, 2.0))
        M = rng.normal(size=3)
        while True:
            gamma = rng.normal(size=3)
            gamma /= detlinalg.norm(gamma)
            if abs(gamma[0]) <= GAMMA1_MAX:
                break
        yaw = float(rng.uniform(-np.pi, np.pi))
        out.append(KaneSample(I, D, b, M, gamma, yaw))
    return out


@dataclass(frozen=True)
class ConstrainedSample:
    """An admissible state of a constrained variant (built on a :class:`KaneSample`).

    Attributes
    ----------
    base : KaneSample
        Parameters, ``gamma`` and heading.
    constraint : str
        One of :data:`EXTRA_CONSTRAINTS`.
    omega, M : numpy.ndarray
        Angular velocity on the constraint plane and ``M = II omega``, shape (3,).
    alpha, beta : numpy.ndarray
        Body-frame components of ``N.x``, ``N.y``, shape (3,).
    """

    base: KaneSample
    constraint: str
    omega: np.ndarray
    M: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray

    @property
    def gamma(self) -> np.ndarray:
        return self.base.gamma

    def kane(self) -> np.ndarray:
        """The constrained Kane model's ``omega_dot`` at this state, shape (3,).

        Returns
        -------
        numpy.ndarray
            :func:`kane_angular_acceleration` with ``constraint=self.constraint``,
            body frame, shape (3,).
        """
        s = self.base
        return kane_angular_acceleration(
            s.I, s.D, s.b, self.M, s.gamma, yaw=s.yaw, constraint=self.constraint
        )

    def ours(self, model: Model) -> np.ndarray:
        """``omega_dot`` of ``model`` at this state (with ``alpha, beta`` if it has them).

        Parameters
        ----------
        model : chaplygin.derive.Model
            The constrained variant (``chaplygin_ball`` with ``rubber`` or
            ``straight_line``).

        Returns
        -------
        numpy.ndarray
            :func:`model_angular_acceleration` at this state, body frame, shape (3,).
        """
        groups = {"alpha": self.alpha, "beta": self.beta}
        return model_angular_acceleration(model, self.base.params(), self.M, self.gamma, groups)


def constrained_samples(
    constraint: str, samples: Sequence[KaneSample] | None = None
) -> list[ConstrainedSample]:
    """Admissible states: ``omega`` on the constraint plane first, then ``M = II omega``.

    Parameters
    ----------
    constraint : {"rubber", "straight_line"}
    samples : sequence of KaneSample, optional
        Default: :func:`random_samples`.

    Returns
    -------
    list of ConstrainedSample
        ``|omega|`` in [0.5, 2].
    """
    rng = np.random.default_rng([OMEGA_SEED, EXTRA_CONSTRAINTS.index(constraint)])
    out = []
    for s in random_samples() if samples is None else samples:
        alpha, beta, gamma = space_axes_in_body(s.gamma, s.yaw)
        normal = (alpha, beta, gamma)[CONSTRAINT_AXIS[constraint]]
        omega = rng.normal(size=3)
        omega -= detlinalg.dot(omega, normal) * normal
        omega *= rng.uniform(0.5, 2.0) / detlinalg.norm(omega)  # |omega| away from 0
        g = np.asarray(s.gamma, dtype=float)
        II = np.diag(s.I) + s.D * (np.eye(3) - g[:, None] * g[None, :])
        momentum = detlinalg.matmul(II, omega)
        out.append(ConstrainedSample(s, constraint, omega, momentum, alpha, beta))
    return out


def rotor_samples(
    samples: Sequence[KaneSample] | None = None, n: int = 6, seed: int = SEED + 4
) -> list[tuple[KaneSample, Rotor]]:
    """The first ``n`` states with a small random rotor each (the ball's own tensor
    ``diag(I) -`` rotor stays positive).

    Parameters
    ----------
    samples : sequence of KaneSample, optional
        Default: :func:`random_samples`.
    n, seed : int

    Returns
    -------
    list of (KaneSample, Rotor)
    """
    rng = np.random.default_rng(seed)
    out = []
    for s in (random_samples() if samples is None else samples)[:n]:
        axial, transverse = (float(x) for x in rng.uniform(0.05, 0.2, 2))
        rotor = Rotor(tuple(rng.normal(size=3)), axial, transverse, float(rng.uniform(-8, 8)))
        out.append((s, rotor))
    return out


def gyrostat_params(s: KaneSample, K: Sequence[float]) -> dict[str, float]:
    """The gyrostat model's parameters: ``s.params()`` and ``K1, K2, K3``.

    Parameters
    ----------
    s : KaneSample
        The state whose ``I1, I2, I3, D`` are used.
    K : sequence of 3 floats
        Gyrostatic momentum (body frame), e.g. :meth:`Rotor.momentum`.

    Returns
    -------
    dict of str to float
        ``I1, I2, I3, D, K1, K2, K3``.
    """
    return {**s.params(), "K1": K[0], "K2": K[1], "K3": K[2]}


@dataclass(frozen=True)
class MovingMassSample:
    """A state of the ball with BM20's two moving masses (see
    :func:`kane_moving_masses_angular_acceleration` for the fields)."""

    I: np.ndarray  # noqa: E741  (the papers' name)
    D: float
    b: float
    law: tuple[float, float, float]
    M: np.ndarray
    gamma: np.ndarray
    t: float

    def params(self) -> dict[str, float]:
        """The ``variable_inertia`` model's parameters.

        Returns
        -------
        dict of str to float
            ``I1, I2, I3, D, J_off, delta, Omega`` (BM20-3.4).
        """
        J_off, delta, Omega = self.law
        I1, I2, I3 = self.I
        return {
            "I1": I1,
            "I2": I2,
            "I3": I3,
            "D": self.D,
            "J_off": J_off,
            "delta": delta,
            "Omega": Omega,
        }

    def frozen_params(self) -> dict[str, float]:
        """The plain ball's parameters with the inertia frozen at ``I(t)``.

        Returns
        -------
        dict of str to float
            ``I1 + o^2, I2, I3 + o^2, D`` with ``o = J_off + delta sin(Omega t)``
            (BM20-3.4).
        """
        offset = self.law[0] + self.law[1] * np.sin(self.law[2] * self.t)
        I1, I2, I3 = self.I
        return {"I1": I1 + offset**2, "I2": I2, "I3": I3 + offset**2, "D": self.D}

    def kane(self) -> np.ndarray:
        """The Kane model's ``omega_dot``, shape (3,).

        Returns
        -------
        numpy.ndarray
            :func:`kane_moving_masses_angular_acceleration` at this state, body frame,
            shape (3,).
        """
        return kane_moving_masses_angular_acceleration(
            self.I, self.D, self.b, self.law, self.M, self.gamma, self.t
        )


def moving_mass_samples(n: int = 6, seed: int = SEED + 5) -> list[MovingMassSample]:
    """Random states of the ball with moving masses (``D = b^2 x [1.5, 4]``, the masses
    weigh 1 together; ``|gamma1| <= GAMMA1_MAX``).

    Parameters
    ----------
    n, seed : int

    Returns
    -------
    list of MovingMassSample
    """
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        I = rng.uniform(0.5, 3.0, 3)  # noqa: E741
        b = float(rng.uniform(0.5, 1.5))
        D = b**2 * float(rng.uniform(1.5, 4.0))
        law = (float(rng.uniform(-1, 1)), float(rng.uniform(0.2, 2)), float(rng.uniform(0.3, 2)))
        M = rng.normal(size=3)
        gamma = rng.normal(size=3)
        gamma /= detlinalg.norm(gamma)
        if abs(gamma[0]) <= GAMMA1_MAX:
            out.append(MovingMassSample(I, D, b, law, M, gamma, float(rng.uniform(-5, 5))))
    return out


def relative_difference(reference: np.ndarray, other: np.ndarray) -> float:
    """``|other - reference| / |reference|`` (Euclidean norms).

    Parameters
    ----------
    reference : numpy.ndarray
        The value compared against (nonzero).
    other : numpy.ndarray
        The value compared, same shape.

    Returns
    -------
    float
        The relative difference.
    """
    return float(detlinalg.norm(other - reference) / detlinalg.norm(reference))


# ------------------------------------------------------------------ the model's side
@lru_cache(maxsize=8)
def _model_omega_dot(model: Any) -> tuple[Callable[..., Any], tuple[str, ...]]:
    """Lambdified ``omega_dot(state, params)`` of a model and its parameter names.

    ``state`` is the model's whole state vector (``M, gamma`` and e.g. ``alpha, beta``).
    """
    state = list(model.state)
    omega = model.expand_aux(model.omega)
    rhs = model.rhs_expanded
    allowed = set(state) | set(model.params) | {model.time}
    free = omega.free_symbols | rhs.free_symbols
    if not free <= allowed:
        raise ValueError(f"omega or the state's rate depend on more than state: {free - allowed}")
    jac = omega.jacobian(state)
    explicit = omega.diff(model.time)  # a time-dependent inertia (BM20)
    f = sp.lambdify(
        (state, list(model.params), model.time), [jac, rhs, explicit], modules="numpy", cse=True
    )
    return f, tuple(model.param_names)


def model_angular_acceleration(
    model: Model,
    params: Mapping[str, float],
    M: Sequence[float],
    gamma: Sequence[float],
    groups: Mapping[str, Sequence[float]] | None = None,
    t: float = 0.0,
) -> np.ndarray:
    """Body-frame angular acceleration from our model: ``(d omega / d state) . state'``
    (plus ``d omega / dt`` for a model with explicit time).

    Parameters
    ----------
    model : chaplygin.derive.Model
        A ``chaplygin_ball`` model (any variant whose ``omega`` and state rates depend on the
        state and the parameters only, e.g. plain, ``rubber``, ``straight_line``).
    params : mapping of str to float
        Parameter values by name (``I1, I2, I3, D`` ...).
    M : sequence of 3 floats
        Angular momentum about the contact point, body frame.
    gamma : sequence of 3 floats
        Unit upward vertical, body frame.
    groups : mapping of str to sequence of float, optional
        Values of the model's other state groups by name (``straight_line``: ``alpha``,
        ``beta``).
    t : float, optional
        Time, for a model whose parameters depend on it (``variable_inertia``).

    Returns
    -------
    numpy.ndarray
        ``omega_dot``, shape (3,).

    Raises
    ------
    KeyError
        A parameter or a state group of the model without a value.
    """
    f, names = _model_omega_dot(model)
    missing = [n for n in names if n not in params]
    if missing:
        raise KeyError(f"missing parameter values: {missing}")
    values: dict[str, Sequence[float]] = {**(groups or {}), "M": M, "gamma": gamma}
    absent = [name for name, _ in model.state_groups if name not in values]
    if absent:
        raise KeyError(f"missing values of the state groups: {absent}")
    state: list[float] = []
    for name, symbols in model.state_groups:
        group = [float(v) for v in values[name]]
        if len(group) != len(symbols):
            raise ValueError(f"state group {name!r} needs {len(symbols)} values, got {len(group)}")
        state += group
    jac, rhs, explicit = f(state, [float(params[n]) for n in names], float(t))
    jac, rhs = np.asarray(jac, dtype=float), np.asarray(rhs, dtype=float)
    return detlinalg.matmul(jac, rhs).ravel() + np.asarray(explicit, dtype=float).ravel()
