"""The validated integrator on a system a user describes (not one of the papers'): Routh's
sphere (a ball with its centre of mass off the centre on the axis of symmetry, under gravity),
from its description to an enclosure that contains mpmath.odefun's flow of the same
description's mpmath code at 30 digits, and that keeps Jellett's integral (typed from the
mechanics, not from the model) at its initial value."""

from __future__ import annotations

import mpmath
from chaplygin.derive.rolling_system import RollingSystem
from chaplygin.derive.systems import register_system
from chaplygin.numerics import load_model_code
from chaplygin.numerics.validated import enclose_flow, to_ball, working_precision

VALUES = {"m": "1.3", "b": "0.9", "A": "0.41", "C": "0.57", "a": "0.23", "g": "9.81"}
START = ["0.7", "-0.3", "1.1", "0.36", "0.48", "0.8"]  # |gamma| = 1 exactly


def test_a_described_system_is_enclosed_around_an_independent_reference() -> None:
    system = RollingSystem(
        "routh_enclosed", inertia=("A", "A", "C"), centre_of_mass=(0, 0, "a"), gravity="g"
    )
    register_system(system)
    code = load_model_code("routh_enclosed")
    params = [VALUES[k] for k in code.params]
    with working_precision(128):
        e = enclose_flow(code, params, START, 0, "0.6", tol=1e-24)
    with mpmath.workdps(30):
        p = [mpmath.mpf(v) for v in params]
        flow = mpmath.odefun(lambda t, y: code.mpmath.rhs(t, y, p), 0,
                             [mpmath.mpf(v) for v in START])  # fmt: skip
        reference = flow(mpmath.mpf("0.6"))
    with working_precision(128):
        refs = [to_ball(mpmath.nstr(v, 30)) for v in reference]
        assert all(b.contains(r) for b, r in zip(e.state, refs, strict=True))
        assert e.max_width < 1e-20
        # moved by three widths the reference falls outside
        k = max(range(6), key=lambda i: float(e.state[i].rad()))
        assert not e.state[k].contains(refs[k] + 3 * e.state[k].rad())

        # Jellett's integral (M, r), r = a e3 + b gamma, at the start and over the enclosure
        def jellett(y: list) -> object:
            a, b = to_ball(VALUES["a"]), to_ball(VALUES["b"])
            return sum(y[i] * b * y[3 + i] for i in range(3)) + a * y[2]

        start = jellett([to_ball(v) for v in START])
        assert (jellett(e.state) - start).contains(0)
