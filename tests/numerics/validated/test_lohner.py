"""The validated integrator: every enclosure contains a reference computed by an independent
route (closed forms: a linear system's exponential, the pendulum's Jacobi elliptic solution;
mpmath's own Taylor ODE solver on the generated mpmath right-hand side), and is narrow enough
for that containment to mean something (a reference moved by a few widths falls outside)."""

from __future__ import annotations

import math
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


def _linear_reference(x0: list[str], t: str) -> tuple:
    """``expm(A t)`` and ``expm(A t) x0`` by mpmath at DPS digits."""
    E = mpmath.expm(mpmath.matrix([[mpmath.mpf(a) for a in r] for r in A_LINEAR]) * mpmath.mpf(t))
    return E, E * mpmath.matrix([mpmath.mpf(v) for v in x0])


def test_backward_flow_and_derivative_contain_the_matrix_exponential() -> None:
    params = [a for row in A_LINEAR for a in row]
    x0 = ["0.7", "-0.3", "1.3"]
    e = enclose_flow(LINEAR, params, x0, "0.4", "-2.5", jacobian=True)
    assert e.times[-1] < e.times[0] < 0.4  # negative steps
    with mpmath.workdps(DPS):
        E, x = _linear_reference(x0, "-2.9")
        for i in range(3):
            assert _contains(e.state[i], x[i])
            assert _outside_when_moved(e.state[i], x[i])
            for j in range(3):
                assert _contains(e.jacobian[i][j], E[i, j])
    assert e.max_width < EPS
    # an end-time interval before t0: the flow at every time in it
    wide = enclose_flow(LINEAR, params, x0, 0, ("-1.3", "-1.2"))
    with mpmath.workdps(DPS):
        for t in ("-1.3", "-1.25", "-1.2"):
            _, x = _linear_reference(x0, t)
            assert all(_contains(wide.state[i], x[i]) for i in range(3))


def test_forward_then_backward_returns_to_the_start() -> None:
    # x' = x^2, x(0) = 1: x(t) = 1/(1 - t), so x(-1) = 1/2 (a nonlinear closed form)
    square = _code(
        "square", ("x",), (), lambda t0, y, p, order, lib: [_square_series(y[0], order, lib)]
    )
    back = enclose_flow(square, [], ["1"], 0, -1)
    assert back.state[0].contains(arb(1) / 2)
    assert not back.state[0].contains(arb(1) / 2 + 3 * back.max_width)
    # the pendulum forward to t = 4.125, then back from that ball: the (exact) start is inside
    start = [2.125, 0.0]
    fwd = enclose_flow(PENDULUM, [], start, 0, 4.125)
    bwd = enclose_flow(PENDULUM, [], fwd.state, 4.125, 0)
    assert bwd.contains(start)
    assert bwd.max_width < 1e-18  # the round trip adds a few widths of the forward run
    assert not bwd.state[0].contains(arb(2.125) + 3 * bwd.max_width)


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
    by central differences of mpmath's solution (step 1e-12 at 40 digits: error ~1e-24);
    so does the run whose derivative remainder per step is bounded by 1e-11 (a hundredth of
    the box's radius) instead of the state's 1e-20: it takes fewer steps, its derivative
    is wider by less than a tenth (the box's own spread dominates it), and its state by
    less than 1 %. A bound that is not a positive number is refused."""
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    params = ["4", "3", "2", "4.385", "0", "2", "-6", "-3", "-9", "1.0669"]
    state = ["0.7", "-1.9", "2.1", "0.48", "0.6", "0.64"]
    box = [to_ball(v) + arb(0, 1e-9) for v in state]
    e = enclose_flow(code, params, box, 0, "1.3", jacobian=True)
    loose = enclose_flow(code, params, box, 0, "1.3", jacobian=True, derivative_tol=1e-11)
    assert loose.steps < e.steps
    width = lambda m: max(2 * float(x.rad()) for row in m for x in row)  # noqa: E731
    # the box's own spread dominates the derivative's width (6e-6 here): the longer steps
    # add a few per cent to it (3 % here), the remainders at most steps x 1e-11 x |D|
    assert width(e.jacobian) < width(loose.jacobian) < 1.1 * width(e.jacobian)
    assert all(a.overlaps(b) for a, b in zip(e.state, loose.state, strict=True))
    assert loose.max_width < 1.01 * e.max_width  # the box's image: 0.3 % wider here
    for bad in (0, -1e-9, float("nan"), float("inf"), "1e-9", True):
        with pytest.raises(UserInputError, match="derivative_tol"):
            enclose_flow(code, params, state, 0, "0.1", jacobian=True, derivative_tol=bad)
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
                assert loose.jacobian[i][j].overlaps(_ref(d) + arb(0, 1e-20))


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


def _growth_code() -> SimpleNamespace:
    """x' = p x: Taylor coefficients c_(k+1) = p c_k/(k+1)."""

    def coefficients(t0, y, p, order, lib):  # noqa: ANN001, ANN202
        c = [y[0]]
        for k in range(order):
            c.append(p[0] * c[k] / (k + 1))
        return [c]

    return _code("growth", ("x",), ("p",), coefficients)


def _rotation_code() -> SimpleNamespace:
    """x' = p y, y' = -p x: c_(k+1) = (p cy_k, -p cx_k)/(k+1)."""

    def coefficients(t0, y, p, order, lib):  # noqa: ANN001, ANN202
        cx, cy = [y[0]], [y[1]]
        for k in range(order):
            cx.append(p[0] * cy[k] / (k + 1))
            cy.append(-p[0] * cx[k] / (k + 1))
        return [cx, cy]

    return _code("rotation", ("x", "y"), ("p",), coefficients)


def test_a_parameter_interval_carried_as_a_state_does_not_wrap() -> None:
    """A rotation at a rate p in [p0 - d, p0 + d] for t = 23: the exact set is an arc of
    x-width about 2 d |dx/dp|. Carried as a state the enclosure contains the flows of both
    ends and is within 1% of that width (plus the step remainders); with p in the
    coefficients the wrapping of the rotating box makes it wider (1.4 times here)."""
    code = _rotation_code()
    with working_precision(128):
        p_ball = to_ball(("0.729999999", "0.730000001"))
        carried = enclose_flow(
            code, [p_ball], ["1.37", "-0.41"], 0, "23", jacobian=True, carry=[0], tol=1e-30
        )
        plain = enclose_flow(code, [p_ball], ["1.37", "-0.41"], 0, "23", tol=1e-30)
    with mpmath.workdps(40):
        p0, d, x0, y0, t = (mpmath.mpf(v) for v in ("0.73", "1e-9", "1.37", "-0.41", "23"))

        def x_at(p: mpmath.mpf) -> mpmath.mpf:
            return x0 * mpmath.cos(p * t) + y0 * mpmath.sin(p * t)

        ends = [x_at(p0 - d), x_at(p0 + d)]
        slope = mpmath.diff(x_at, p0)  # dx/dp
    x = carried.state[0]
    with working_precision(128):
        assert all(x.contains(to_ball(mpmath.nstr(e, 35))) for e in ends)
        dp = carried.parameter_jacobian[0][0]
        assert dp.contains(to_ball(mpmath.nstr(slope, 30)))
    arc = float(2 * d * abs(slope))
    assert 2 * float(x.rad()) < 1.01 * arc
    assert float(plain.state[0].rad()) > 1.2 * float(x.rad())  # wrapping, carrying avoids
    assert float(dp.rad()) < 1e-6 * abs(float(slope))
    with pytest.raises(UserInputError, match="carry"):
        enclose_flow(code, [p_ball], ["1.37", "-0.41"], 0, "4.1", carry=[1])


def test_growth_past_the_limit_is_reported_with_where_it_grew() -> None:
    """x' = 3 x from a ball of radius 1e-30: its width 2e-30 exp(3 t) passes 1e-20 at
    t = ln(5e9)/3 = 7.44; the error carries the widths and the times."""
    code = _growth_code()
    with working_precision(128):
        start = to_ball("1") + arb(0, 1e-30)
        with pytest.raises(EnclosureError, match="grew past") as info:
            enclose_flow(code, ["3"], [start], 0, 20, max_width=1e-20, tol=1e-36)
    exc = info.value
    crossing = math.log(5e9) / 3
    assert exc.widths[-1] > 1e-20 >= exc.widths[-2]
    assert exc.times[-2] <= crossing * (1 + 1e-6) and exc.times[-1] >= crossing * (1 - 1e-6)


def test_an_invariant_relation_tightens_the_box_and_keeps_the_flow() -> None:
    """|gamma| = 1 (BKM12-5.F0) as a tightening: from a box of radius 1e-6 around a state
    with |gamma| = 1 exactly, the enclosure at t = 3 still contains mpmath.odefun's flow
    of the centre (30 digits) and is narrower in gamma3 than without the relation; a box
    with no point on the sphere is refused."""
    from chaplygin.derive.errors import ComputationError
    from chaplygin.numerics.validated.constraints import unit_norm

    code = load_model_code("chaplygin_ball")
    body, centre = ["1.1", "1.7", "2.3", "0.9"], ["0.3", "-0.2", "0.5", "0.6", "0", "0.8"]
    with working_precision(128):
        box = [to_ball(v) + (arb(0, 1e-6) if i >= 3 else 0) for i, v in enumerate(centre)]
        tight = enclose_flow(code, body, box, 0, 3, invariants=[unit_norm((3, 4, 5))])
        loose = enclose_flow(code, body, box, 0, 3)
    with mpmath.workdps(30):
        p = [mpmath.mpf(v) for v in body]
        flow = mpmath.odefun(lambda t, y: code.mpmath.rhs(t, y, p), 0,
                             [mpmath.mpf(v) for v in centre])  # fmt: skip
        ref = flow(3)
    with working_precision(128):
        pairs = zip(tight.state, ref, strict=True)
        assert all(b.contains(to_ball(mpmath.nstr(r, 30))) for b, r in pairs)
    assert float(tight.state[5].rad()) < 0.995 * float(loose.state[5].rad())  # 1.2% here
    pairs = zip(tight.state, loose.state, strict=True)
    assert all(float(a.rad()) <= float(b.rad()) for a, b in pairs)
    with pytest.raises(ComputationError, match="no point"):
        unit_norm((0, 1, 2))([arb("0.1", 1e-3)] * 3)
    with pytest.raises(UserInputError, match="indices"):
        unit_norm((1, 1))


def test_an_initial_set_in_lohner_form_contains_the_flow_of_its_points() -> None:
    """A thin segment {c + B (r, 0)} tilted by 0.7 rad, under the rotation at rate 0.73 for
    t = 23: the exact images of its ends and of its centre (cos/sin at 40 digits) lie in the
    enclosure, which is thinner than that of the box around the segment; a singular basis
    is refused."""
    code = _rotation_code()
    a, half = mpmath.mpf("0.7"), mpmath.mpf("1e-6")
    basis = [
        [float(mpmath.cos(a)), -float(mpmath.sin(a))],
        [float(mpmath.sin(a)), float(mpmath.cos(a))],
    ]
    with working_precision(128):
        r = [arb(0, float(half)), arb(0)]
        thin = enclose_flow(code, ["0.73"], ["1.37", "-0.41"], 0, "23", basis=basis,
                            coefficients=r, tol=1e-30)  # fmt: skip
        hull = [
            to_ball(v) + arb(0, float(half) * abs(basis[i][0]))
            for i, v in enumerate(("1.37", "-0.41"))
        ]
        box = enclose_flow(code, ["0.73"], hull, 0, "23", tol=1e-30)
    with mpmath.workdps(40):
        w = mpmath.mpf("0.73") * 23
        starts = [
            (mpmath.mpf("1.37") + s * basis[0][0], mpmath.mpf("-0.41") + s * basis[1][0])
            for s in (-half, 0, half)
        ]
        images = [
            (x * mpmath.cos(w) + y * mpmath.sin(w), -x * mpmath.sin(w) + y * mpmath.cos(w))
            for x, y in starts
        ]
    with working_precision(128):
        for image in images:
            assert all(
                b.contains(to_ball(mpmath.nstr(v, 35)))
                for b, v in zip(thin.state, image, strict=True)
            )
    # the segment's image is thinner than the image of the box around it (0.66 times here)
    widths = [sum(float(b.rad()) for b in e.state) for e in (thin, box)]
    assert widths[0] < 0.75 * widths[1]
    with pytest.raises(UserInputError, match="invertible"):
        enclose_flow(code, ["0.73"], ["1", "0"], 0, 1, basis=[[1, 2], [2, 4]], coefficients=[0, 0])


def _euler_top_code() -> SimpleNamespace:
    """The free rigid body: I1 w1' = (I2 - I3) w2 w3 and cyclically (Taylor recurrences of
    the quadratic right-hand side)."""

    def coefficients(t0, y, p, order, lib):  # noqa: ANN001, ANN202
        I1, I2, I3 = p
        a = ((I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3)
        c = [[y[0]], [y[1]], [y[2]]]
        for k in range(order):
            for i in range(3):
                u, v = c[(i + 1) % 3], c[(i + 2) % 3]
                c[i].append(a[i] * sum(u[j] * v[k - j] for j in range(k + 1)) / (k + 1))
        return c

    return _code("euler top", ("w1", "w2", "w3"), ("I1", "I2", "I3"), coefficients)


def test_the_free_rigid_body_is_enclosed_around_its_jacobi_elliptic_solution() -> None:
    """From w = (w10, 0, w30) the free rigid body (I1 < I2 < I3) turns as w1 = w10 cn(l t),
    w2 = B sn(l t), w3 = w30 dn(l t) with l^2 = -a1 a2 w30^2, B = a2 w10 w30/l and
    k^2 = -a2 a3 w10^2/l^2 (a_i the Euler coefficients): the enclosure at t = 3.7 contains
    it (mpmath's Jacobi functions at 40 digits), moved by three widths it does not."""
    code = _euler_top_code()
    body, start = ["1.1", "1.7", "2.3"], ["0.6", "0", "1.3"]
    with working_precision(128):
        e = enclose_flow(code, body, start, 0, "3.7", tol=1e-30)
    with mpmath.workdps(40):
        I1, I2, I3 = (mpmath.mpf(v) for v in body)
        w10, w30, t = mpmath.mpf("0.6"), mpmath.mpf("1.3"), mpmath.mpf("3.7")
        a1, a2, a3 = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3
        lam = mpmath.sqrt(-a1 * a2) * w30
        B, m = a2 * w10 * w30 / lam, -a2 * a3 * w10**2 / lam**2
        u = lam * t
        exact = [w10 * mpmath.ellipfun("cn", u, m=m), B * mpmath.ellipfun("sn", u, m=m),
                 w30 * mpmath.ellipfun("dn", u, m=m)]  # fmt: skip
    with working_precision(128):
        refs = [to_ball(mpmath.nstr(v, 38)) for v in exact]
        assert all(b.contains(r) for b, r in zip(e.state, refs, strict=True))
        assert e.max_width < 1e-25
        for b, r in zip(e.state, refs, strict=True):
            assert not b.contains(r + 3 * 2 * b.rad())


@pytest.mark.parametrize("jacobian", [False, True])
def test_the_next_step_follows_the_last_remainder_and_is_seldom_cut(jacobian, monkeypatch):
    """The step after an accepted one grows by what its remainder allows (``w^(-1/(p+1))``
    with a safety factor), so that trial steps cut by the remainder control are rare: at most
    one in ten steps tried again (before, a growth of 1.1 whatever the remainder: about half
    the steps were tried twice, the control below)."""
    from chaplygin.numerics.validated import lohner

    code = load_model_code("chaplygin_ball")
    body, start = ["1.1", "1.7", "2.3", "0.9"], ["0.3", "-0.2", "0.5", "0.6", "0", "0.8"]
    tried = []
    step = lohner._step
    monkeypatch.setattr(lohner, "_step", lambda *a, **k: tried.append(1) or step(*a, **k))
    e = enclose_flow(code, body, start, 0, 13, jacobian=jacobian, order=20, tol=1e-18)
    assert len(tried) <= 1.1 * e.steps + 1
    tried.clear()
    monkeypatch.setattr(lohner, "_growth", lambda w, order: lohner.STEP_GROWTH)  # the control
    e = enclose_flow(code, body, start, 0, 13, jacobian=jacobian, order=20, tol=1e-18)
    assert len(tried) > 1.1 * e.steps + 1
