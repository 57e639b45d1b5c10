"""The validated integrator: every enclosure contains a reference computed by an independent
route (closed forms: a linear system's exponential, the pendulum's Jacobi elliptic solution;
mpmath's own Taylor ODE solver on the generated mpmath right-hand side), and is narrow enough
for that containment to mean something (a reference moved by a few widths falls outside)."""

from __future__ import annotations

from types import SimpleNamespace

import mpmath
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import load_model_code
from chaplygin.numerics.validated import EnclosureError, enclose_flow, to_ball, working_precision
from chaplygin.numerics.validated.jets import ARB_LIB
from flint import arb

DPS = 40
#: Double precision's unit roundoff: every enclosure here must be narrower than that.
EPS = 2.0**-52


def _ref(value: mpmath.mpf) -> arb:
    """The reference as a ball at 256 bits (its decimal rounding at DPS digits enclosed)."""
    with working_precision(256):
        return arb(mpmath.nstr(value, DPS)) + arb(0, 10.0 ** (3 - DPS) * (1 + abs(float(value))))


def _contains(ball: arb, value: mpmath.mpf) -> bool:
    return ball.contains(_ref(value))


def _outside_when_moved(ball: arb, value: mpmath.mpf) -> bool:
    """The reference moved by three of the enclosure's widths is outside it (the enclosure is
    tighter than what the test could tell from a wrong answer)."""
    moved = value + 3 * mpmath.mpf(float(ball.rad()) * 2 + 1e-300)
    return not _contains(ball, moved)


# ------------------------------------------------------------------ hand-written models
A_LINEAR = [["-0.3", "1.7", "0.2"], ["-1.1", "-0.4", "0.9"], ["0.5", "-0.7", "-0.2"]]


def _linear_taylor(t0, y, p, order, lib):  # noqa: ANN001, ANN202 - the generated signature
    """x' = A x: c_(k+1) = A c_k / (k+1) (A's entries are the parameters)."""
    n = len(y)
    c = [[lib.mpf(0)] * (order + 1) for _ in range(n)]
    for i in range(n):
        c[i][0] = y[i]
    for k in range(order):
        for i in range(n):
            c[i][k + 1] = sum(p[3 * i + j] * c[j][k] for j in range(n)) / (k + 1)
    return c


def _pendulum_taylor(t0, y, p, order, lib):  # noqa: ANN001, ANN202
    """theta' = v, v' = -sin(theta), with the sin/cos recurrences written out here."""
    th, v = [lib.mpf(0)] * (order + 1), [lib.mpf(0)] * (order + 1)
    s, c = [lib.mpf(0)] * (order + 1), [lib.mpf(0)] * (order + 1)
    th[0], v[0] = y
    s[0], c[0] = lib.sin(th[0]), lib.cos(th[0])
    for k in range(order):
        if k:
            s[k] = sum(j * th[j] * c[k - j] for j in range(1, k + 1)) / k
            c[k] = -sum(j * th[j] * s[k - j] for j in range(1, k + 1)) / k
        th[k + 1] = v[k] / (k + 1)
        v[k + 1] = -s[k] / (k + 1)
    return [th, v]


def _code(name: str, state: tuple, params: tuple, fn) -> SimpleNamespace:  # noqa: ANN001
    return SimpleNamespace(
        name=name, state=state, params=params, taylor=SimpleNamespace(taylor_coefficients=fn)
    )


LINEAR = _code("linear", ("x", "y", "z"), tuple(f"a{i}" for i in range(9)), _linear_taylor)
PENDULUM = _code("pendulum", ("theta", "v"), (), _pendulum_taylor)


def test_linear_system_flow_and_derivative_contain_the_matrix_exponential() -> None:
    params = [a for row in A_LINEAR for a in row]
    x0 = ["0.7", "-0.3", "1.3"]
    t1 = "2.9"
    e = enclose_flow(LINEAR, params, x0, 0, t1, jacobian=True)
    with mpmath.workdps(DPS):
        E = mpmath.expm(
            mpmath.matrix([[mpmath.mpf(a) for a in r] for r in A_LINEAR]) * mpmath.mpf(t1)
        )
        x = E * mpmath.matrix([mpmath.mpf(v) for v in x0])
        for i in range(3):
            assert _contains(e.state[i], x[i])
            assert _outside_when_moved(e.state[i], x[i])
            for j in range(3):
                assert _contains(e.jacobian[i][j], E[i, j])
    assert e.max_width < EPS  # tighter than the rounding of one double result


def test_pendulum_contains_the_jacobi_elliptic_solution() -> None:
    theta0, t1 = "2.1", "7.3"  # a large swing, past one half-period
    e = enclose_flow(PENDULUM, [], [theta0, "0"], 0, t1, jacobian=True)
    with mpmath.workdps(DPS):

        def theta(t, th0):  # noqa: ANN001, ANN202
            k = mpmath.sin(th0 / 2)
            K = mpmath.ellipk(k * k)
            return 2 * mpmath.asin(k * mpmath.ellipfun("sn", K - t, m=k * k))

        th0, t = mpmath.mpf(theta0), mpmath.mpf(t1)
        ref = theta(t, th0)
        v_ref = mpmath.diff(lambda s: theta(s, th0), t)
        d_ref = mpmath.diff(lambda a: theta(t, a), th0)
        assert _contains(e.state[0], ref)
        assert _outside_when_moved(e.state[0], ref)
        assert e.state[1].overlaps(_ref(v_ref) + arb(0, 1e-25))
        assert e.jacobian[0][0].overlaps(_ref(d_ref) + arb(0, 1e-25))
    assert e.max_width < EPS


@pytest.mark.parametrize(
    ("system", "effects", "params", "state", "t1"),
    [
        (
            "chaplygin_ball",
            "",
            ["1.1", "1.7", "2.3", "0.9"],
            ["0.3", "-0.2", "0.5", "0.6", "0", "0.8"],
            "4.7",
        ),
        (
            "chaplygin_ball",
            "variable_gyrostat,variable_inertia",
            ["4", "3", "2", "4.385", "0.3", "2", "-6", "-3", "-9", "1.06675"],
            ["0.7", "-1.9", "2.1", "0.48", "0.6", "0.64"],
            "3.1",
        ),
    ],
)
def test_generated_models_contain_mpmaths_own_taylor_solution(
    system: str, effects: str, params: list, state: list, t1: str
) -> None:
    code = load_model_code(system, effects)
    e = enclose_flow(code, params, state, 0, t1)
    with mpmath.workdps(DPS):
        p = [mpmath.mpf(v) for v in params]
        f = mpmath.odefun(lambda t, y: code.mpmath.rhs(t, y, p), 0, [mpmath.mpf(v) for v in state])
        ref = f(mpmath.mpf(t1))
        for ball, value in zip(e.state, ref, strict=True):
            assert _contains(ball, value)
            assert _outside_when_moved(ball, value)
    assert e.max_width < EPS


def test_derivative_of_a_box_contains_central_differences() -> None:
    """The C^1 enclosure over a box of half-width 1e-9 contains the derivative at its centre
    by central differences of mpmath's solution (step 1e-12 at 40 digits: error ~1e-24)."""
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    params = ["4", "3", "2", "4.385", "0", "2", "-6", "-3", "-9", "1.0669"]
    state = ["0.7", "-1.9", "2.1", "0.48", "0.6", "0.64"]
    box = [to_ball(v) + arb(0, 1e-9) for v in state]
    e = enclose_flow(code, params, box, 0, "1.3", jacobian=True)
    with mpmath.workdps(DPS):
        p = [mpmath.mpf(v) for v in params]
        h = mpmath.mpf("1e-12")

        def run(y0):  # noqa: ANN001, ANN202
            f = mpmath.odefun(lambda t, y: code.mpmath.rhs(t, y, p), 0, y0)
            return f(mpmath.mpf("1.3"))

        for j in (0, 4):
            up = [mpmath.mpf(v) + (h if i == j else 0) for i, v in enumerate(state)]
            dn = [mpmath.mpf(v) - (h if i == j else 0) for i, v in enumerate(state)]
            a, b = run(up), run(dn)
            for i in range(6):
                d = (a[i] - b[i]) / (2 * h)
                assert e.jacobian[i][j].overlaps(_ref(d) + arb(0, 1e-20))


def test_a_parameter_ball_is_carried_to_the_result() -> None:
    """Omega as the interval [1.0669, 1.0670]: the enclosure contains the flows of both ends."""
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    body = ["4", "3", "2", "4.385", "0", "2", "-6", "-3", "-9"]
    state = ["0.7", "-1.9", "2.1", "0.48", "0.6", "0.64"]
    wide = enclose_flow(code, [*body, ("1.0669", "1.0670")], state, 0, "1.1")
    for omega in ("1.0669", "1.0670"):
        thin = enclose_flow(code, [*body, omega], state, 0, "1.1")
        assert all(w.contains(s) for w, s in zip(wide.state, thin.state, strict=True))
    assert wide.max_width > 1e3 * thin.max_width


def test_bad_input_is_refused_and_blow_up_is_reported() -> None:
    code = load_model_code("chaplygin_ball")
    good = ["0.3", "-0.2", "0.5", "0.6", "0", "0.8"]
    with pytest.raises(UserInputError):
        enclose_flow(code, ["1.1", "1.7", "2.3"], good, 0, 1)
    with pytest.raises(UserInputError):
        enclose_flow(code, ["1.1", "1.7", "2.3", "0.9"], good, 1, 1)
    with pytest.raises(UserInputError):
        enclose_flow(code, ["1.1", "1.7", "2.3", "nan"], good, 0, 1)
    with pytest.raises(UserInputError):
        enclose_flow(code, ["1.1", "1.7", "2.3", "0.9"], good, 0, 1, order=1)
    # x' = x^2 from x(0) = 1 blows up at t = 1: no enclosure reaches t = 1.5
    blow = _code(
        "blow-up",
        ("x",),
        (),
        lambda t0, y, p, order, lib: [_square_series(y[0], order, lib)],
    )
    with pytest.raises(EnclosureError):
        enclose_flow(blow, [], ["1"], 0, "1.5", max_steps=400)


def _square_series(x0, order, lib):  # noqa: ANN001, ANN202
    """Taylor coefficients of x' = x^2: c_(k+1) = sum_j c_j c_(k-j) / (k+1)."""
    c = [lib.mpf(0)] * (order + 1)
    c[0] = x0
    for k in range(order):
        c[k + 1] = sum(c[j] * c[k - j] for j in range(k + 1)) / (k + 1)
    return c


def test_arb_lib_runs_the_generated_recurrences_like_mpmath() -> None:
    """The Arb namespace gives the generated recurrences the values mpmath gives them."""
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    params = ["4", "3", "2", "4.385", "0.3", "2", "-6", "-3", "-9", "1.06675"]
    state = ["0.7", "-1.9", "2.1", "0.48", "0.6", "0.64"]
    ball = code.taylor.taylor_coefficients(
        to_ball("0.37"), [to_ball(v) for v in state], [to_ball(v) for v in params], 12, ARB_LIB
    )
    with mpmath.workdps(DPS):
        ref = code.taylor.taylor_coefficients(
            mpmath.mpf("0.37"),
            [mpmath.mpf(v) for v in state],
            [mpmath.mpf(v) for v in params],
            12,
            mpmath,
        )
        for row_b, row_r in zip(ball, ref, strict=True):
            for b, r in zip(row_b, row_r, strict=True):
                assert _contains(b, r)


def test_an_enclosure_that_grows_past_its_limit_says_where() -> None:
    """BM20 at Omega = 1.07 (Fig. 7C, chaotic) from a box of half-width 1e-12: the width grows
    with the flow; past the limit the integrator stops with where it grew, and a run that stops
    before the limit returns the widths and times of every step."""
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    params = ["4", "3", "2", "4.385", "0", "2", "-6", "-3", "-9", "1.07"]
    box = [to_ball(v) + arb(0, 1e-12) for v in ["0.7", "-1.9", "2.1", "0.48", "0.6", "0.64"]]
    e = enclose_flow(code, params, box, 0, "2", order=20, tol=1e-16)
    assert len(e.widths) == len(e.times) == e.steps
    assert e.times == sorted(e.times) and e.times[-1] == pytest.approx(2)
    limit = 2 * e.widths[-1]
    with pytest.raises(EnclosureError, match=r"grew past .* at t = .*step"):
        enclose_flow(code, params, box, 0, "40", order=20, tol=1e-16, max_width=limit)
