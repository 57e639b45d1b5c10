"""Hard cases of issue 5 §3: each test asserts stability (no NaN or overflow), a bounded drift
of every first integral and agreement between two precisions.

How the bounds are derived (used by every test below)
------------------------------------------------------
* **Drift.** A one-step method with a local error control keeps each step's local error
  below ``tol * scale`` (Taylor, Jorba-Zou: ``scale = max(1, |y|_inf)``; DOP853: ``rtol |y| +
  atol`` per component). A first integral ``F`` changes over one step by at most
  ``|grad F| * local error``; for the quadratic integrals of the ball ``|grad F| |y| / |F| <= 2``
  and for the energy it is at most 2 as well (``H`` is a quadratic form in ``M``), so after
  ``N`` steps the relative drift is at most ``2 N tol`` (worst case, errors all of one sign),
  plus rounding ``2 N eps``. We assert ``drift <= 4 (N + 10) max(tol, eps) * s`` where
  ``s = |y|_inf / |y_F|`` corrects for an integral that depends only on components much
  smaller than ``|y|_inf`` (the thin body, where ``M ~ 1e-6``).
* **Two precisions.** The double run's global error bounds the distance to the quad (or
  digits) run, whose own error is ~1e-30. On a regular (invariant-torus) motion the global
  error grows at most linearly: ``|e(T)| <= N tol (1 + T |dw/dF| |F|) <= 1e3 N tol`` for the
  spans used here (frequencies ``w`` of order 1, ``T <= 1e3``); where the motion may be chaotic
  (BM20 Fig. 5) an error made at time ``t`` is amplified by at most ``||Phi(T, t)||``, the
  state-transition matrix of the orbit itself, measured from the variational equations
  (:func:`chaplygin.numerics.dynamics.variational.flow_with_jacobian`) rather than assumed.

Each test states its own numbers in its docstring. Reference values cite FORMULAS.md IDs.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import integrate, load_model_code
from chaplygin.numerics.dynamics.variational import flow_with_jacobian
from chaplygin.verify.bench import separatrix_state
from chaplygin.verify.cli import main

EPS = 2.0**-52
QUAD_TOL = 1e-30
TOL = 1e-13  # double: a bit above Precision("double").min_rtol = 100 eps


def _finite(r) -> None:
    assert r.success, r.message
    vals = np.asarray([float(v) for v in np.ravel(r.y)])
    assert np.all(np.isfinite(vals)), "NaN or overflow in the solution"
    assert np.max(np.abs(vals)) < 1e6, "the solution blew up"
    assert all(math.isfinite(v) for v in r.drift.values())


def _drift_bound(r, tol: float, scale: float = 1.0) -> float:
    eps = EPS if r.precision == "double" else 2.0**-112
    return 4 * (r.nsteps + 10) * max(tol, eps) * scale


def _assert_drift(r, tol: float, scale: float = 1.0, only=None) -> None:
    bound = _drift_bound(r, tol, scale)
    for name, d in r.drift.items():
        if only is None or name in only:
            assert d <= bound, f"{name}: drift {d:.2e} > bound {bound:.2e} ({r.precision})"


def _max_diff(a, b) -> float:
    with mpmath.workdps(40):
        return float(max(abs(mpmath.mpf(x) - mpmath.mpf(y)) for x, y in zip(a, b, strict=True)))


def _near_separatrix_state(dh: str = "5e-9", dps: int = 40):
    """``M = gamma`` (C = 1), gamma moved off the separatrix point of K01-3.4 along e1 so
    that ``H - h2 = dh`` exactly to ``dps`` digits (``h2 = 1/4``, K01-3.3seg)."""
    code = load_model_code("chaplygin_ball")
    sep = separatrix_state(dps=dps + 5)
    with mpmath.workdps(dps + 10):
        g0 = [mpmath.mpf(v) for v in sep["gamma"]]
        p = [mpmath.mpf(v) for v in (1, 2, 3, 1)]
        iH = code.integral_names.index("H")

        def gamma(e):
            g = [g0[0] + e, g0[1], g0[2]]
            n = mpmath.sqrt(sum(x * x for x in g))
            return [x / n for x in g]

        def excess(e):
            g = gamma(e)
            return code.mpmath.integrals(0, g + g, p)[iH] - mpmath.mpf(1) / 4 - mpmath.mpf(dh)

        e = mpmath.findroot(excess, mpmath.mpf("-2e-8"))
        g = gamma(e)
        text = [mpmath.nstr(x, dps, strip_zeros=False) for x in g]
    return {"M": text, "gamma": text}


def _tumble(t, y):
    return y[4]  # gamma2 changes sign once per passage near the middle axis


# ----------------------------------------------------------------------- near the separatrix
@pytest.mark.slow
def test_near_separatrix_many_tumbles():
    """Energy 5e-9 above the middle-axis value h2 = C^2/(2 I2) on M || gamma (K01-3.3seg,
    K01-3.4; I = (1, 2, 3), D = 1, C = 1), T = 3000: 27 passages of gamma2 through 0.

    Bounds: drift as in the module docstring (about 1000 steps at tol 1e-13: 4e-10). The
    solution must stay on M || gamma (an invariant line: ``|M - gamma| <= drift bound``) and
    at ``|H - h2| <= 1e-8``. The passage period ``P(h) ~ k ln(1/(h - h2))`` is so sensitive to
    ``h`` (``dP/dh = k/(h - h2)``, ``k = P/ln(1/(h - h2))``) that the double/quad agreement of
    the n-th passage time is bounded by ``n dP/dh dh_err`` with ``dh_err`` the double run's
    energy error (drift plus 4 eps of the initial rounding), times 10.
    """
    y0 = _near_separatrix_state()
    P = {"I": (1, 2, 3), "D": 1}
    r = integrate("chaplygin_ball", y0, 3000, P, method="taylor", rtol=TOL, atol=TOL,
                  events=[_tumble], t_eval=np.linspace(0, 3000, 301))
    _finite(r)
    _assert_drift(r, TOL)
    H = load_model_code("chaplygin_ball").numpy.integrals(r.t, r.y, np.array([1.0, 2, 3, 1]))[0]
    assert np.all(np.abs(H - 0.25) <= 1e-8) and np.all(H > 0.25)
    assert np.max(np.abs(r.y[:3] - r.y[3:])) <= _drift_bound(r, TOL)
    times = np.asarray(r.t_events[0], dtype=float)
    assert len(times) >= 20, "expected many tumbles"
    periods = np.diff(times)
    period = float(np.median(periods))
    # periodic motion: every passage takes the same time (the energy is conserved)
    dP_dh = period / 5e-9 / math.log(1 / 5e-9)
    dh_err = 0.25 * (r.drift["H"] + 4 * EPS)
    assert np.max(np.abs(periods - period)) <= 10 * dP_dh * dh_err
    # two precisions: quad over two passages
    rq = integrate("chaplygin_ball", y0, 2.2 * period, P, method="taylor", precision="quad",
                   rtol=QUAD_TOL, atol=QUAD_TOL, events=[_tumble])
    _finite(rq)
    _assert_drift(rq, QUAD_TOL)
    tq = [float(v) for v in rq.t_events[0]]
    assert len(tq) == 2
    for n, (a, b) in enumerate(zip(times[:2], tq, strict=True), start=1):
        assert abs(a - b) <= 10 * n * dP_dh * dh_err, (n, a, b)


# ----------------------------------------------------------------------- M exactly || gamma
def _frame_for(gamma):
    with mpmath.workdps(45):
        g = [mpmath.mpf(v) if not isinstance(v, str) else mpmath.mpf(v) for v in gamma]
        a = [g[1], -g[0], mpmath.mpf(0)]
        n = mpmath.sqrt(a[0] ** 2 + a[1] ** 2)
        a = [x / n for x in a]
        b = [g[1] * a[2] - g[2] * a[1], g[2] * a[0] - g[0] * a[2], g[0] * a[1] - g[1] * a[0]]
        return [mpmath.nstr(x, 40) for x in a], [mpmath.nstr(x, 40) for x in b]


def _parallel_state():
    with mpmath.workdps(45):
        g = [mpmath.mpf("0.2"), mpmath.mpf("0.3"), mpmath.sqrt(mpmath.mpf("0.87"))]
        alpha, beta = _frame_for(g)
        return {
            "M": [mpmath.nstr(mpmath.mpf("1.5") * x, 40) for x in g],
            "gamma": [mpmath.nstr(x, 40) for x in g],
            "alpha": alpha,
            "beta": beta,
        }


@pytest.mark.slow
def test_m_exactly_parallel_to_gamma_with_contact_point():
    """M = 1.5 gamma exactly (the line of K01-3.3seg), contact point tracked, explicit frame.

    BKM12-7's frame ``alpha = M x gamma / |M x gamma|`` is singular here, so alpha, beta are
    given. T = 50, tol 1e-13 (double) and 1e-30 (quad): drift bound of the module docstring
    for all 11 integrals; M stays parallel to gamma (``|M - 1.5 gamma|`` within the drift
    bound); the contact point is finite and moves (K01-3.5: a rolling ball on M || gamma
    drifts); double and quad agree to ``1e3 N tol``.
    """
    y0 = _parallel_state()
    P = {"I": (1, 2, 3), "D": 1, "b": 1}
    kw = dict(effects="contact_point", method="taylor")
    r = integrate("chaplygin_ball", y0, 50, P, rtol=TOL, atol=TOL, **kw)
    rq = integrate("chaplygin_ball", y0, 50, P, precision="quad", rtol=QUAD_TOL, atol=QUAD_TOL,
                   **kw)
    for res, tol in ((r, TOL), (rq, QUAD_TOL)):
        _finite(res)
        _assert_drift(res, tol)
    y = r.y.astype(float)
    assert np.max(np.abs(y[:3] - 1.5 * y[3:6])) <= 1.5 * _drift_bound(r, TOL)
    assert np.hypot(y[12, -1], y[13, -1]) > 1e-3  # the contact point has moved
    assert _max_diff(r.y[:, -1], rq.y[:, -1]) <= 1e3 * r.nsteps * TOL


def test_m_parallel_to_gamma_without_frame_takes_the_one_frame_rule(capsys):
    """Without alpha, beta on M || gamma, where BKM12-7 is undefined, the API and the CLI
    complete the frame by the rule scenes use (``numerics/frame.py``): alpha is the body axis
    least aligned with gamma (here e1, |gamma1| = 0.2), projected on the plane perpendicular to
    gamma, beta = gamma x alpha; never NaN. Checked against that frame computed here at 45
    digits, to the rounding of the double state (4 eps). Only one of alpha and beta is still
    refused in one line (API and CLI, exit 2). Just off the line (|M x gamma| / |M| ~ 3e-5)
    BKM12-7 is well defined and used."""
    st = _parallel_state()
    P = {"I": (1, 2, 3), "D": 1, "b": 1}
    r = integrate("chaplygin_ball", {"M": st["M"], "gamma": st["gamma"]}, 1, P,
                  effects="contact_point")
    _finite(r)
    with mpmath.workdps(45):
        g = [mpmath.mpf(v) for v in st["gamma"]]
        e1 = [mpmath.mpf(1), mpmath.mpf(0), mpmath.mpf(0)]
        a = [e - g[0] * c for e, c in zip(e1, g, strict=True)]  # e1 - (e1, gamma) gamma
        n = mpmath.sqrt(sum(c * c for c in a))
        a = [c / n for c in a]
        b = [g[1] * a[2] - g[2] * a[1], g[2] * a[0] - g[0] * a[2], g[0] * a[1] - g[1] * a[0]]
    y0 = np.asarray(r.y[:, 0], float)
    assert np.max(np.abs(y0[6:9] - [float(c) for c in a])) <= 4 * EPS
    assert np.max(np.abs(y0[9:12] - [float(c) for c in b])) <= 4 * EPS
    with pytest.raises(UserInputError, match="alpha and beta"):
        integrate("chaplygin_ball", {"M": st["M"], "gamma": st["gamma"], "alpha": st["alpha"]},
                  1, P, effects="contact_point")
    argv = ["integrate", "chaplygin_ball", "--effects", "contact_point",
            "--param", "I=1,2,3", "--param", "D=1", "--param", "b=1",
            "--y0", "M=" + ",".join(st["M"]), "--y0", "gamma=" + ",".join(st["gamma"]),
            "--t-end", "1"]
    assert main(argv) == 0
    capsys.readouterr()
    assert main([*argv, "--y0", "alpha=" + ",".join(st["alpha"])]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "alpha and beta" in err and "Traceback" not in err
    # the explicit frame on the CLI works
    argv += ["--y0", "alpha=" + ",".join(st["alpha"]), "--y0", "beta=" + ",".join(st["beta"])]
    assert main(argv) == 0
    capsys.readouterr()
    off = {"M": ("0.3", "0.45", "1.3990"), "gamma": st["gamma"]}
    r = integrate("chaplygin_ball", off, 1, P, effects="contact_point")
    _finite(r)


# ----------------------------------------------------------------------- thin body
def test_thin_body():
    """I = (1, 2, 3) 1e-6, D = 1 (I_i / D <= 3e-6): the denominator ``D^-1 - (gamma, A gamma)``
    of omega is ~1e-6 (half of double's digits cancel in it). M = 1e-6 (0.7, -0.4, 0.5) keeps
    |omega| of order 1. T = 50.

    Bounds: the Taylor control works on ``|y|_inf ~ |gamma| = 1`` while the integrals in M
    live on the scale ``|M| ~ 1e-6``, so their drift bound carries ``s = 1/|M| = 1.1e6``;
    double vs quad agreement ``1e3 N tol`` (absolute, states of order 1 and 1e-6).
    """
    P = {"I": ("1e-6", "2e-6", "3e-6"), "D": 1}
    y0 = {"M": ("0.7e-6", "-0.4e-6", "0.5e-6"), "gamma": ("0.2", "0.3", "sqrt(0.87)")}
    r = integrate("chaplygin_ball", y0, 50, P, method="taylor", rtol=TOL, atol=TOL)
    rq = integrate("chaplygin_ball", y0, 50, P, method="taylor", precision="quad",
                   rtol=QUAD_TOL, atol=QUAD_TOL * 1e-6)
    s = 1 / math.sqrt(0.7**2 + 0.4**2 + 0.5**2) / 1e-6
    for res, tol in ((r, TOL), (rq, QUAD_TOL)):
        _finite(res)
        _assert_drift(res, tol, scale=s)
        _assert_drift(res, tol, only=("(gamma,gamma)",))
    assert _max_diff(r.y[:, -1], rq.y[:, -1]) <= 1e3 * (r.nsteps + 10) * TOL
    # the M part agrees relatively too (its own scale 1e-6)
    assert _max_diff(r.y[:3, -1], rq.y[:3, -1]) <= 1e3 * (r.nsteps + 10) * TOL * 1e-6 * s
    # DOP853 (C right-hand side) agrees with the quad Taylor solution as well
    rd = integrate("chaplygin_ball", y0, 50, P, method="DOP853", rtol=1e-12, atol=1e-18)
    _finite(rd)
    assert _max_diff(rd.y[:, -1], rq.y[:, -1]) <= 1e3 * (rd.nfev / 12 + 10) * 1e-12


# ----------------------------------------------------------------------- nearly symmetric
def test_nearly_symmetric_body():
    """I = (1, 1 + 1e-10, 3), D = 1 (|I1 - I2| = 1e-10; sphero-conical coordinates
    degenerate, the state variables M, gamma do not). T = 100, reference initial state.

    Bounds as in the module docstring; and the motion is within ``1e-10 T |dy/dI|`` of the
    exactly symmetric body's (continuity in I2: |dy/dI| <= 10 over this span), which rules
    out a silent switch to a different branch.
    """
    y0 = {"M": ("0.7", "-0.4", "0.5"), "gamma": ("0.2", "0.3", "sqrt(0.87)")}
    P = {"I": ("1", "1.0000000001", "3"), "D": 1}
    r = integrate("chaplygin_ball", y0, 100, P, method="taylor", rtol=TOL, atol=TOL)
    rq = integrate("chaplygin_ball", y0, 100, P, method="taylor", precision="quad",
                   rtol=QUAD_TOL, atol=QUAD_TOL)
    for res, tol in ((r, TOL), (rq, QUAD_TOL)):
        _finite(res)
        _assert_drift(res, tol)
    assert _max_diff(r.y[:, -1], rq.y[:, -1]) <= 1e3 * (r.nsteps + 10) * TOL
    rs = integrate("chaplygin_ball", y0, 100, {"I": (1, 1, 3), "D": 1}, method="taylor",
                   rtol=TOL, atol=TOL)
    _finite(rs)
    diff = np.max(np.abs(rs.y[:, -1] - r.y[:, -1]))
    assert diff <= 10 * 100 * 1e-10 + 1e3 * (r.nsteps + 10) * TOL


# ----------------------------------------------------------------------- long run
@pytest.mark.slow
def test_long_run_T_1e5(record_property, capsys):
    """Reference problem, T = 1e5: Taylor (double, tol 1e-13) and DOP853 (C right-hand side,
    rtol = atol = 1e-6, kept cheap) -- drift of every integral bounded and reported.

    Bounds: the module docstring's ``4 (N + 10) tol`` with N the steps (DOP853: nfev / 12).
    DOP853 against Taylor: after 1e5 time units DOP853's phase has drifted (its integrals
    drift by ~1e-3), so the states are not compared; its final integrals must agree with
    Taylor's (i.e. lie on the same invariant torus) to DOP853's drift bound. Two precisions:
    double and quad Taylor agree at T = 300 within ``1e3 N tol``.
    """
    y0 = {"M": ("0.7", "-0.4", "0.5"), "gamma": ("0.2", "0.3", "sqrt(0.87)")}
    P = {"I": (1, 2, 3), "D": 1}
    T = 1e5
    rt = integrate("chaplygin_ball", y0, T, P, method="taylor", rtol=TOL, atol=TOL,
                   t_eval=np.linspace(0, T, 101))
    rd = integrate("chaplygin_ball", y0, T, P, method="DOP853", rtol=1e-6, atol=1e-6,
                   backend="auto", t_eval=np.linspace(0, T, 101))
    _finite(rt)
    _finite(rd)
    _assert_drift(rt, TOL)
    rd.nsteps = rd.nfev // 12
    _assert_drift(rd, 1e-6)
    code = load_model_code("chaplygin_ball")
    p = np.array([1.0, 2, 3, 1])
    Ft = code.numpy.integrals(T, rt.y[:, -1], p)
    Fd = code.numpy.integrals(T, rd.y[:, -1], p)
    assert np.all(np.abs(Ft - Fd) <= _drift_bound(rd, 1e-6) * np.abs(Ft))
    report = {f"taylor drift {k}": v for k, v in rt.drift.items()}
    report.update({f"DOP853 drift {k}": v for k, v in rd.drift.items()})
    for k, v in report.items():
        record_property(k, v)
    with capsys.disabled():
        print("\nT = 1e5 drifts: " + ", ".join(f"{k} {v:.1e}" for k, v in report.items()))
    r1 = integrate("chaplygin_ball", y0, 300, P, method="taylor", rtol=TOL, atol=TOL)
    rq = integrate("chaplygin_ball", y0, 300, P, method="taylor", precision="quad",
                   rtol=QUAD_TOL, atol=QUAD_TOL)
    _finite(rq)
    _assert_drift(rq, QUAD_TOL)
    assert _max_diff(r1.y[:, -1], rq.y[:, -1]) <= 1e3 * (r1.nsteps + 10) * TOL


# ----------------------------------------------------------------------- BM20, delta = 2
def _bm20_fig5_state():
    """BM20 Fig. 5 start g(0) = 1, l(0) = 1, z(0) = 0.5, G = 3 in Andoyer-Deprit variables
    (BM20-3.7), to 40 digits."""
    with mpmath.workdps(45):
        G, l, z, g = (mpmath.mpf(3), mpmath.mpf(1), mpmath.mpf("0.5"), mpmath.mpf(1))
        s = mpmath.sqrt(1 - z * z)
        M = [G * s * mpmath.sin(l), G * s * mpmath.cos(l), G * z]
        gamma = [
            z * mpmath.cos(g) * mpmath.sin(l) + mpmath.sin(g) * mpmath.cos(l),
            z * mpmath.cos(g) * mpmath.cos(l) - mpmath.sin(g) * mpmath.sin(l),
            -s * mpmath.cos(g),
        ]
        return {"M": [mpmath.nstr(v, 40) for v in M], "gamma": [mpmath.nstr(v, 40) for v in gamma]}


def _amplification(y0, T: float) -> float:
    """``2 max_t ||Phi(T, t)||_2`` for BM20 Fig. 5's orbit from ``y0``, t on a one-period grid.

    ``Phi(T, t) = Phi(T, 0) Phi(t, 0)^-1``, each from the variational equations (rtol 1e-12).
    """
    code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
    assert code.params == ("I1", "I2", "I3", "D", "J_off", "delta", "K1", "K2", "K3", "Omega")
    p = [4, 3, 2, 4.385, 0, 2, -6, -3, -9, 1.07]
    y = [float(mpmath.mpf(v)) for v in y0["M"] + y0["gamma"]]
    period = 2 * math.pi / 1.07
    times = [*np.arange(0.0, T, period), T]
    phis, state, total = [], y, np.eye(6)
    for a, b in zip(times[:-1], times[1:], strict=True):
        state, phi = flow_with_jacobian(code, p, state, a, b, rtol=1e-12, atol=1e-14)
        total = phi @ total
        phis.append(total.copy())
    norms = [np.linalg.norm(total @ np.linalg.inv(ph), 2) for ph in [np.eye(6), *phis[:-1]]]
    return 2 * max(norms)


@pytest.mark.slow
def test_time_varying_inertia_order_violated():
    """BM20 Fig. 5: I = (4, 3, 2), d = 4.385, J_off = 0, delta = 2, Omega = 1.07,
    K = (-6, -3, -9) (BM20-3.4, 3.5); delta = 2 > 1 breaks I1(t) > I2 > I3(t) periodically
    (BM20-3.2rem). T = 100 (about 17 periods of the masses).

    Bounds: the integrals (M, M), (M, gamma), (gamma, gamma) (BM20-2.5int) by the module
    docstring (``(M, gamma) = 0`` initially: absolute drift); double vs quad within
    ``N tol |y|_inf A`` with ``A = max_t ||Phi(T, t)||_2`` over a grid of one point per period
    (twice, for the times between), measured on this orbit from the variational equations
    (it is about 5e5 here: finite-time growth far above the asymptotic exponent).
    (17 periods from Fig. 5's start are not shown to lie on the chaotic attractor: BM20's
    largest exponent, 0.041 per iteration = 0.007 per unit time (BM20-Lyap), would give only
    ``exp(0.7)`` over T = 100; the measured A is what bounds this run.)
    """
    P = {"I": (4, 3, 2), "D": "4.385", "J_off": 0, "delta": 2, "K": (-6, -3, -9),
         "Omega": "1.07"}
    eff = "variable_gyrostat,variable_inertia"
    T = 100.0
    t = np.linspace(0, T, 2001)
    sin2 = (0 + 2 * np.sin(1.07 * t)) ** 2
    I1, I2, I3 = 4 + sin2, 3 + 0 * t, 2 + sin2
    ordered = (I1 > I2) & (I2 > I3)
    assert ordered.any() and (~ordered).sum() > 100, "the order must be violated periodically"
    y0 = _bm20_fig5_state()
    r = integrate("chaplygin_ball", y0, T, P, effects=eff, method="taylor", rtol=TOL, atol=TOL)
    rq = integrate("chaplygin_ball", y0, T, P, effects=eff, method="taylor", precision="quad",
                   rtol=QUAD_TOL, atol=QUAD_TOL)
    for res, tol in ((r, TOL), (rq, QUAD_TOL)):
        _finite(res)
        _assert_drift(res, tol)
    assert "(M,gamma)" in rq.drift_absolute  # exactly 0 initially (BM20-3.7), kept to 1e-30
    # each step's local error (<= TOL max(1, |y|_inf), |y|_inf = G = 3) amplified by <= A
    bound = (r.nsteps + 10) * TOL * 3 * _amplification(y0, T)
    assert _max_diff(r.y[:, -1], rq.y[:, -1]) <= bound
    # the same run with DOP853 stays on the attractor's integrals too
    rd = integrate("chaplygin_ball", y0, T, P, effects=eff, method="DOP853", rtol=1e-10,
                   atol=1e-10)
    _finite(rd)
    rd.nsteps = rd.nfev // 12
    _assert_drift(rd, 1e-10)


# ----------------------------------------------------------------------- precision rule
@pytest.mark.parametrize(
    "precision, rtol, wanted",
    [
        ("double", 1e-17, 'precision="quad"'),
        ("double", 1e-20, 'precision="quad"'),
        ("quad", 1e-34, "precision=36"),
        (30, 1e-40, "precision=42"),
        (100, 1e-101, "precision=103"),
    ],
)
def test_accuracy_the_precision_cannot_deliver_is_refused(precision, rtol, wanted):
    """With the Taylor method an rtol below the unit roundoff (2^-52, 2^-112, 10^(1 - d)) is
    refused, naming a precision that delivers it (quad when 2^-112 = 1.9e-34 suffices, else
    d digits with 10^(2 - d) <= rtol); that precision then accepts the same request."""
    y0 = {"M": ("0.7", "-0.4", "0.5"), "gamma": ("0.2", "0.3", "sqrt(0.87)")}
    P = {"I": (1, 2, 3), "D": 1}
    with pytest.raises(UserInputError, match="cannot deliver|below what") as err:
        integrate("chaplygin_ball", y0, 0.01, P, method="taylor", precision=precision,
                  rtol=rtol, atol=rtol)
    msg = str(err.value)
    assert wanted in msg and "\n" not in msg
    better = wanted.split("=")[1].strip('"')
    r = integrate("chaplygin_ball", y0, 0.01, P, method="taylor",
                  precision=better if better == "quad" else int(better), rtol=rtol, atol=rtol)
    assert r.success


def test_accuracy_rule_on_the_command_line(capsys):
    """The CLI: exit 2, one line naming the precision that would deliver; nothing else."""
    argv = ["integrate", "chaplygin_ball", "--param", "I=1,2,3", "--param", "D=1",
            "--y0", "M=0.7,-0.4,0.5", "--y0", "gamma=0.2,0.3,sqrt(0.87)", "--t-end", "1",
            "--rtol", "1e-18", "--atol", "1e-18"]
    assert main(argv) == 2
    out = capsys.readouterr()
    lines = out.err.strip().splitlines()
    assert len(lines) == 1 and "--precision quad" in lines[0] and "double" in lines[0]
    assert out.out == ""
    assert main([*argv, "--precision", "quad", "--method", "taylor"]) == 0
