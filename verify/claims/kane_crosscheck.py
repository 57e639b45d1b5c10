"""Claims that our derived models agree with an independent Kane's-method derivation.

:mod:`chaplygin.verify.kane` sets the rolling ball up again from the physical description
only, with ``sympy.physics.mechanics.KanesMethod`` (Euler angles, contact coordinates,
no-slip as velocity constraints, gravity included), sharing no code and no formula with our
Lagrange–d'Alembert engine. Each claim compares the body-frame angular acceleration
``omega_dot`` of a derived model with the Kane model's at random states
(:func:`~chaplygin.verify.kane_samples.random_samples`, seeded): the plain ball, the rubber ball
(no twist), Veselovs' ball along a straight line, the gyrostat (a second rigid body, a rotor
spinning at a constant rate) and BM20's time-varying inertia (two point masses sliding along
a body axis).

Both sides are evaluated in double precision: the lambdified expressions (a few hundred
operations each, with common subexpressions), a 5 x 5 linear solve on the Kane side, a
Jacobian times the state's rate on ours. Their rounding errors add up to at most some
hundred units of ``eps`` (the largest seen: about 340 eps); the bound :data:`BOUND` is
``2**12 eps``. Each claim has a negative control that the same comparison refutes (a wrong
``D``, a missing constraint, a reversed rotor, a frozen inertia).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from chaplygin.derive import build_model

from .base import Computed, ComputedClaim, register

# kane_samples (and with it sympy.physics.mechanics, ~0.4 s) is imported by the functions that
# compute: loading the registry imports this module, and most runs decide no Kane claim.

BALL = "chaplygin_ball"
EPS = float(np.finfo(float).eps)
#: Largest relative difference of the two angular accelerations: the rounding of two
#: double-precision evaluations of a few hundred operations each (see the module text).
BOUND = 2**12 * EPS
SOURCE = "independent derivation (sympy.physics.mechanics.KanesMethod, verify/kane.py)"


def _comparison(
    pairs: Callable[[], Sequence[tuple[np.ndarray, np.ndarray]]], what: str
) -> Callable[[], Computed]:
    """A computation comparing ``(kane, ours)`` pairs of ``omega_dot``: the error is the
    largest relative difference over the states, the bound :data:`BOUND`."""

    def run() -> Computed:
        from .. import kane_samples

        differences = [kane_samples.relative_difference(k, ours) for k, ours in pairs()]
        worst = int(np.argmax(differences))
        return Computed(
            error=differences[worst],
            bound=BOUND,
            what=f"an independent Kane's-method derivation (KanesMethod) against the derived "
            f"{what}: largest relative difference of omega_dot at {len(differences)} random "
            "states; bound 2^12 eps from the double-precision evaluation of both sides",
            values={"state": str(worst), "relative difference": f"{differences[worst]:.6g}"},
        )

    return run


def _ball(D_factor: float = 1.0) -> list[tuple[np.ndarray, np.ndarray]]:
    from .. import kane_samples

    model = build_model(BALL)
    return [
        (s.kane(), kane_samples.model_angular_acceleration(model, s.params(D_factor), s.M, s.gamma))
        for s in kane_samples.random_samples()
    ]


def _constrained(constraint: str, effects: tuple[str, ...]) -> Callable[[], list]:
    def pairs() -> list[tuple[np.ndarray, np.ndarray]]:
        from .. import kane_samples

        model = build_model(BALL, effects)
        return [(cs.kane(), cs.ours(model)) for cs in kane_samples.constrained_samples(constraint)]

    return pairs


def _gyrostat(sign: float) -> list[tuple[np.ndarray, np.ndarray]]:
    from .. import kane_samples

    model = build_model(BALL, ["gyrostat"])
    return [
        (
            s.kane(rotor=rotor),
            kane_samples.model_angular_acceleration(
                model, kane_samples.gyrostat_params(s, sign * rotor.momentum()), s.M, s.gamma
            ),
        )
        for s, rotor in kane_samples.rotor_samples()
    ]


def _moving_masses(frozen: bool) -> list[tuple[np.ndarray, np.ndarray]]:
    from .. import kane_samples

    model = build_model(BALL, [] if frozen else ["variable_inertia"])
    out = []
    for x in kane_samples.moving_mass_samples():
        if frozen:
            ours = kane_samples.model_angular_acceleration(model, x.frozen_params(), x.M, x.gamma)
        else:
            ours = kane_samples.model_angular_acceleration(model, x.params(), x.M, x.gamma, t=x.t)
        out.append((x.kane(), ours))
    return out


register(
    ComputedClaim(
        id="KANE-ball",
        source=SOURCE,
        kind="equation",
        statement="omega' of the derived Chaplygin ball equals omega' of a KanesMethod model "
        "(Euler angles, no-slip velocity constraints, gravity) at random states",
        system=BALL,
        compute=_comparison(_ball, "plain ball"),
    ),
    ComputedClaim(
        id="KANE-ball/control-D*1.1",
        source="negative control",
        kind="equation",
        statement="the same with the derived model evaluated at 1.1 D (false)",
        system=BALL,
        compute=_comparison(lambda: _ball(D_factor=1.1), "plain ball evaluated at 1.1 D"),
        expected="fails",
    ),
    ComputedClaim(
        id="KANE-rubber",
        source=SOURCE,
        kind="equation",
        statement="omega' of the derived rubber ball equals omega' of the KanesMethod model "
        "with the no-twist velocity constraint (omega, N.z) = 0 at random admissible states",
        system=BALL,
        effects=("rubber",),
        compute=_comparison(_constrained("rubber", ("rubber",)), "rubber ball"),
    ),
    ComputedClaim(
        id="KANE-rubber/control-plain-ball",
        source="negative control",
        kind="equation",
        statement="the plain ball's omega' equals the constrained (no-twist) Kane model's "
        "(false: the constraint's reaction changes omega')",
        system=BALL,
        compute=_comparison(_constrained("rubber", ()), "plain ball at rubber states"),
        expected="fails",
    ),
    ComputedClaim(
        id="KANE-straight_line",
        source=SOURCE,
        kind="equation",
        statement="omega' of the derived ball along a straight line equals omega' of the "
        "KanesMethod model with the velocity constraint (omega, N.x) = 0 at random admissible "
        "states (alpha, beta = N.x, N.y in the body frame)",
        system=BALL,
        effects=("straight_line",),
        compute=_comparison(
            _constrained("straight_line", ("straight_line",)), "ball along a straight line"
        ),
    ),
    ComputedClaim(
        id="KANE-straight_line/control-plain-ball",
        source="negative control",
        kind="equation",
        statement="the plain ball's omega' equals the Kane model's with (omega, N.x) = 0 (false)",
        system=BALL,
        compute=_comparison(
            _constrained("straight_line", ()), "plain ball at straight-line states"
        ),
        expected="fails",
    ),
    ComputedClaim(
        id="KANE-gyrostat",
        source=SOURCE,
        kind="equation",
        statement="omega' of the derived gyrostat (K01 §4) equals omega' of a KanesMethod "
        "model of the ball with a rotor spinning at a constant rate s, K = Ia s e",
        system=BALL,
        effects=("gyrostat",),
        compute=_comparison(lambda: _gyrostat(1.0), "gyrostat"),
    ),
    ComputedClaim(
        id="KANE-gyrostat/control-reversed-K",
        source="negative control",
        kind="equation",
        statement="the same with the gyrostatic momentum reversed, K = -Ia s e (false)",
        system=BALL,
        effects=("gyrostat",),
        compute=_comparison(lambda: _gyrostat(-1.0), "gyrostat with K reversed"),
        expected="fails",
    ),
    ComputedClaim(
        id="KANE-variable_inertia",
        source=SOURCE,
        kind="equation",
        statement="omega' of the derived ball with the inertia I(t) of BM20 (3.4) equals "
        "omega' of a KanesMethod model in which two point masses slide along the body axis 2 "
        "at +-(J_off + delta sin(Omega t))",
        system=BALL,
        effects=("variable_inertia",),
        compute=_comparison(
            lambda: _moving_masses(False), "ball with the variable inertia of BM20 (3.4)"
        ),
    ),
    ComputedClaim(
        id="KANE-variable_inertia/control-frozen-inertia",
        source="negative control",
        kind="equation",
        statement="the plain ball with the inertia frozen at I(t) has the moving masses' "
        "omega' (false: it misses the I'(t) omega term)",
        system=BALL,
        compute=_comparison(
            lambda: _moving_masses(True), "plain ball with the inertia frozen at I(t)"
        ),
        expected="fails",
    ),
)
