"""The ``periodic_orbits`` scene output on BM20 Fig. 7A (Omega = 1.06675, d = 4.385).

The multipliers from the variational equations (the map's Jacobian) are checked against an
independent route: central differences of ``P^7`` itself (no variational equations), whose
error is ``~ accuracy / h + h^2 |D^3 P^7|``. The Neimark–Sacker point found by the
continuation is checked by refining the orbit on both sides of it (the pair's modulus below
and above 1).

No test here rests on where a chaotic orbit goes. From Fig. 5's start (z, l, g) = (0.5, 1, 1)
the map at Omega = 1.06675 reaches the period-7 cycle (or its gamma -> -gamma mirror, g + pi)
only after a chaotic transient whose length is decided by the last bits: 825 to 8112 periods
on 48 starts perturbed by 1e-12 (relative), one of which had not closed within 1e-4 after 8000
(the compiled batch map, DOP853 at rtol 1e-12). The cycle's tests therefore start at
``NEAR_CYCLE``, 3e-3 from a point of the cycle, in its basin: the orbit converges without chaos
(its distance to the cycle after 2000 periods agreed to 2 digits on every perturbed start).
After ``CYCLE_TRANSIENT`` = 3000 periods the 7-cycle closes within 0.004 of ``detect_tol``
(period 14: 0.005) while every period that is not a multiple of 7 stays 2.3e4 times
``detect_tol`` open: a margin over 200 both ways. At Omega = 1.07 (the strange attractor) no
period <= 16 closes within 1.6e4 times ``detect_tol`` after 3000 periods on 12 perturbed
starts (the scene's Taylor map at rtol 1e-10).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from chaplygin.numerics.ball.bm20_map import bm20_map_with_jacobian
from chaplygin.numerics.dynamics.periodic_orbits import refine_periodic_orbit
from chaplygin.verify.cli import main

BM20 = """title = "BM20 Fig. 7A period"
system = "chaplygin_ball"
effects = ["variable_inertia", "variable_gyrostat"]
[parameters]
I = [4, 3, 2]
D = 4.385
J_off = 0
delta = 2
K = [-6, -3, -9]
Omega = {omega}
[initial]
G = 3
{start}
[run]
t_end = 1
[outputs.periodic_orbits]
transient = {transient}
max_period = 16
rtol = 1e-10
"""

CONTINUATION = """[outputs.periodic_orbits.continuation]
parameter = "Omega"
range = [1.06675, 1.0671]
step = 2e-4
follow_doublings = 0
"""

PARAMS = [4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.06675]
#: Fig. 5's start (BM20 (3.7)) and a start 3e-3 from a point of the period-7 cycle of Fig. 7A
#: (the cycle found from Fig. 5's start, rounded to two decimals), in the cycle's basin.
FIG5_START = "z = 0.5\nl = 1\ng = 1"
NEAR_CYCLE = (-0.44, 1.46, -1.01)
NEAR_CYCLE_START = "z = {}\nl = {}\ng = {}".format(*NEAR_CYCLE)
CYCLE_TRANSIENT = 3000


def _run(tmp_path, text, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    status = main(["run", str(scene), "--out", str(tmp_path / "out"), "--json", "--quiet"])
    captured = capsys.readouterr()
    return status, captured


def test_model_without_forcing_is_refused(tmp_path, capsys):
    text = """title = "x"
system = "chaplygin_ball"
[parameters]
I = [1, 2, 3]
D = 1
[initial]
M = [0.1, 0.2, 0.3]
gamma = [0, 0, 1]
[run]
t_end = 1
[outputs.periodic_orbits]
"""
    status, captured = _run(tmp_path, text, capsys)
    assert status == 2
    assert "time-periodic" in captured.err and captured.err.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_unknown_key_is_refused(tmp_path, capsys):
    text = BM20.format(omega=1.06675, transient=10, start=FIG5_START) + "max_periods = 3\n"
    status, captured = _run(tmp_path, text, capsys)
    assert status == 2 and "max_periods" in captured.err


def test_a_map_continued_in_another_parameter_is_refused(tmp_path, capsys):
    """The stroboscopic map is continued in Omega, D, delta or J_off only (a section's flow
    route takes any parameter of the model): one line, exit 2, nothing written."""
    text = BM20.format(omega=1.06675, transient=10, start=FIG5_START) + (
        '[outputs.periodic_orbits.continuation]\nparameter = "I1"\nrange = [3.9, 4.1]\n'
        "step = 0.01\n"
    )
    status, captured = _run(tmp_path, text, capsys)
    assert status == 2 and captured.err.count("\n") == 1
    assert "continuation.parameter" in captured.err and "'I1'" in captured.err
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_period_seven_and_its_multipliers(tmp_path, capsys):
    text = BM20.format(omega=1.06675, transient=CYCLE_TRANSIENT, start=NEAR_CYCLE_START)
    status, captured = _run(tmp_path, text, capsys)
    assert status == 0, captured.err
    out = json.loads(captured.out)["analyses"]["periodic_orbits"]
    assert out["period"] == 7 and out["converged"] and out["stable"]
    assert out["residual"] <= out["tolerance"]
    mult = np.array([complex(m) for m in out["multipliers"]])
    # independent route: central differences of P^7 (the map only, no Jacobian)
    smap = bm20_map_with_jacobian(PARAMS, 3.0, rtol=1e-10)
    x0 = np.array([float(v) for v in out["orbit (z, l, g)"][0]])
    h = 1e-4

    def p7(x):
        for _ in range(7):
            x = smap.f(x, 1.06675)
        return x

    def fd_moduli(step):
        cols = [
            smap.difference(p7(x0 + step * e), p7(x0 - step * e)) / (2 * step) for e in np.eye(3)
        ]
        return np.sort(np.abs(np.linalg.eigvals(np.array(cols).T)))

    fd, fd2 = fd_moduli(h), fd_moduli(2 * h)
    # error of the differences: the map's accuracy over h, plus the truncation O(h^2),
    # estimated from the step 2h (Richardson: |fd(2h) - fd(h)| = 3 c h^2)
    bound = 10 * 7 * smap.accuracy / h + np.max(np.abs(fd2 - fd))
    assert np.max(np.abs(fd - np.sort(np.abs(mult)))) <= bound
    assert (tmp_path / "out" / "periodic_orbits.nc").stat().st_size > 0


@pytest.mark.slow
def test_chaotic_attractor_has_no_short_period(tmp_path, capsys):
    # control: at Omega = 1.07 (Fig. 5, the strange attractor) no period <= 16 closes
    text = BM20.format(omega=1.07, transient=3000, start=FIG5_START)
    status, captured = _run(tmp_path, text, capsys)
    assert status == 0, captured.err
    out = json.loads(captured.out)["analyses"]["periodic_orbits"]
    assert out["period"] is None and "no period" in out["message"]


@pytest.mark.slow
def test_neimark_sacker_of_the_period_seven_orbit(tmp_path, capsys):
    text = BM20.format(omega=1.06675, transient=CYCLE_TRANSIENT, start=NEAR_CYCLE_START)
    text += CONTINUATION
    status, captured = _run(tmp_path, text, capsys)
    assert status == 0, captured.err
    cont = json.loads(captured.out)["analyses"]["periodic_orbits"]["continuation"]
    (ns,) = cont["events"]
    assert ns["kind"] == "neimark-sacker" and ns["period"] == 7
    omega_ns = float(ns["parameter"])
    # the pair's modulus crosses 1 there: refine on both sides (shift by 100x the Newton
    # tolerance's effect on the parameter, far above the located uncertainty)
    smap = bm20_map_with_jacobian(PARAMS, 3.0, rtol=1e-10)
    orbit_text = json.loads(captured.out)["analyses"]["periodic_orbits"]["orbit (z, l, g)"]
    start = np.array([float(v) for v in orbit_text[0]])
    moduli = []
    for om in (omega_ns - 2e-5, omega_ns + 2e-5):
        orbit = refine_periodic_orbit(smap, start, 7, om)
        assert orbit.converged
        moduli.append(max(abs(m) for m in orbit.multipliers if abs(m.imag) > 0))
    assert moduli[0] < 1 < moduli[1]


@pytest.mark.slow
def test_period_seven_cycle_refined_at_30_digits():
    """Newton at 30 digits (the map at 30 digits, the Jacobian in double) closes the period-7
    cycle of Fig. 7A to the working precision; the double orbit agrees to its own accuracy,
    and P^7 of the refined point computed independently at 40 digits returns to it."""
    import mpmath
    from chaplygin.numerics.ball.bm20_map import bm20_map_with_jacobian, bm20_point, bm20_state
    from chaplygin.numerics.ball.map_coordinates import reduced_point, state_from_reduced
    from chaplygin.numerics.code import load_model_code
    from chaplygin.numerics.dynamics.poincare import StroboscopicMap

    exact = ["4", "3", "2", "4.385", "0", "2", "-6", "-3", "-9", "1.06675"]
    double = bm20_map_with_jacobian([float(v) for v in exact], 3.0, rtol=1e-11)
    x = bm20_point(bm20_state(list(NEAR_CYCLE), 3.0))
    for _ in range(CYCLE_TRANSIENT):
        x = double.f(x, 1.06675)
    coarse = refine_periodic_orbit(double, x, 7, 1.06675)
    assert coarse.converged
    fine_map = bm20_map_with_jacobian(exact, 3.0, rtol=1e-11, digits=30)
    # the parameter as text: rounded once to 30 digits by the map (an mpf made here would be
    # rounded to the context's 53 bits first)
    fine = refine_periodic_orbit(fine_map, mpmath.matrix(list(coarse.points[0])), 7, "1.06675")
    assert fine.converged and fine.residual <= 1e-24
    start = list(fine.points[0])  # mpf at 30 digits (no re-rounding to the context)
    assert max(abs(float(a) - b) for a, b in zip(start, coarse.points[0], strict=True)) < 1e-8
    # an independent run at 40 digits (other precision, other tolerance) closes the cycle
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    with mpmath.workdps(40):
        strobe = StroboscopicMap(code, exact, precision=40, rtol=1e-38, atol=1e-38)
        y = state_from_reduced(start, 3, [0] * 6, code.state)
        y7 = strobe.orbit(y, 1, transient=7).y[0]
        back = reduced_point(list(y7), code.state)[1]
        gap = max(abs(mpmath.mpf(a) - b) for a, b in zip(back, start, strict=True))
    assert gap < 1e-24


@pytest.mark.slow
def test_mirror_starts_print_the_same_canonical_cycle(tmp_path, capsys):
    """From a start in the 7-cycle's basin and its exact mirror image (gamma -> -gamma) the
    refined 7-cycles are mirror copies (BM20-3.1); both runs print the same canonical orbit,
    starting at the same point, and name the copy each reached (opposite). (Not from Fig. 5's
    start: when its chaotic transient is captured by the cycle depends on the last bits.)"""
    from chaplygin.numerics.ball.bm20_map import bm20_state

    y0 = bm20_state(list(NEAR_CYCLE), 3.0)
    outs = []
    for sign in (1, -1):
        text = BM20.format(omega=1.06675, transient=CYCLE_TRANSIENT, start=NEAR_CYCLE_START)
        text = text.replace(
            "G = 3\n" + NEAR_CYCLE_START,
            f"M = {[repr(float(v)) for v in y0[:3]]}\n"
            f"gamma = {[repr(float(sign * v)) for v in y0[3:]]}",
        )
        (tmp_path / str(sign)).mkdir()
        status, captured = _run(tmp_path / str(sign), text, capsys)
        assert status == 0, captured.err
        outs.append(json.loads(captured.out)["analyses"]["periodic_orbits"])
    assert [o["period"] for o in outs] == [7, 7]
    assert {o["copy_reached"] for o in outs} == {"canonical", "mirror"}
    assert {o["symmetric_copy"] for o in outs} == {"none", "gamma -> -gamma"}
    a, b = (np.array([[float(v) for v in x] for x in o["orbit (z, l, g)"]]) for o in outs)
    d = a - b
    d[:, 1:] = (d[:, 1:] + np.pi) % (2 * np.pi) - np.pi
    assert np.max(np.abs(d)) <= 1e-8
