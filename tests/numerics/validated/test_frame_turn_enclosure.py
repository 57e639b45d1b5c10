"""The frame turn of K01 Fig. 6(f) enclosed by the rigorous section map: the period and the
turn against mpmath.odefun on the generated mpmath equations (the crossing located by
mpmath.findroot), the derivative in the energy against central differences of that solver,
the interval Newton decision on stand-in enclosures, bad input refused."""

from __future__ import annotations

import mpmath
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import load_model_code
from chaplygin.numerics.ball import frame_turn_enclosure as fte
from chaplygin.numerics.validated import to_ball, working_precision
from flint import arb

#: A generic body; C = 4 makes the period short (the time scales like 1/C).
BODY, D, C, H = ("1.1", "1.7", "2.3"), "0.9", "4", "7.04"
PERIOD_GUESS = 6.1552  # the double-precision frame_turn's period, to 5 digits


def _reference(h: str) -> tuple[mpmath.mpf, mpmath.mpf]:
    """(period, Phi) by mpmath.odefun at 25 digits from the same closed-form start."""
    code = load_model_code("chaplygin_ball", ("contact_point",))
    with working_precision(200):
        y0 = fte._start([to_ball(v) for v in BODY], to_ball(D), to_ball(C), to_ball(h))
    with mpmath.workdps(25):
        y = [mpmath.mpf(v.mid().str(40, radius=False)) for v in y0]
        p = [mpmath.mpf(v) for v in (*BODY, D)] + [mpmath.mpf(1)]
        sol = mpmath.odefun(lambda t, z: code.mpmath.rhs(t, z, p), 0, y)
        T = mpmath.findroot(lambda s: sol(s)[4], mpmath.mpf(PERIOD_GUESS))
        a, a0, b0 = sol(T)[6:9], y[6:9], y[9:12]
        dot = mpmath.fdot
        return T, mpmath.atan2(dot(a, b0), dot(a, a0))


def test_period_turn_and_slope_contain_independent_references() -> None:
    e = fte.enclose_frame_turn(BODY, D, H, PERIOD_GUESS, C, derivative=True)
    T, phi = _reference(H)
    with mpmath.workdps(25):
        step = mpmath.mpf("1e-6")
        h = mpmath.mpf(H)
        plus = _reference(mpmath.nstr(h + step, 20))[1]
        minus = _reference(mpmath.nstr(h - step, 20))[1]
        central = (plus - minus) / (2 * step)
    with working_precision(128):
        ref_T, ref_phi = to_ball(mpmath.nstr(T, 22)), to_ball(mpmath.nstr(phi, 22))
        assert e.period.contains(ref_T) and e.turn.contains(ref_phi)
        width = 2 * e.turn.rad()
        assert float(width) < 1e-13
        assert not e.turn.contains(ref_phi + 3 * width)
        # the central difference's error: |Phi'''| step^2/6, |Phi'''| far below 1e3 here
        slope_ref = to_ball(mpmath.nstr(central, 20))
        assert abs(float((e.slope - slope_ref).mid())) < 1e3 * 1e-12 / 6 + float(e.slope.rad())


def _stand_in(zero: str, slope: arb, cosine: arb):  # noqa: ANN202
    def fake(I, D, h, period, C="1", *, derivative=False, **kw):  # noqa: ANN001, ANN202
        hb = to_ball(h)
        return fte.FrameTurnEnclosure(
            h=hb, period=arb(1), turn=slope * (hb - to_ball(zero)),
            slope=slope if derivative else None, seconds=0.0, cosine=cosine,
        )  # fmt: skip

    return fake


@pytest.mark.parametrize(
    ("zero", "slope", "cosine", "verdict"),
    [
        ("0.18031891515", "240", "1", "unique zero"),
        ("0.1803191", "240", "1", "no zero"),
        ("0.18031891515", "[240 +/- 300]", "1", "undecided"),
        ("0.18031891515", "[240 +/- 300]", "-0.99", "no zero"),
    ],
)
def test_interval_newton_decides_on_the_enclosures(
    monkeypatch: pytest.MonkeyPatch, zero: str, slope: str, cosine: str, verdict: str
) -> None:
    """Phi(h) = 240 (h - zero) as stand-in enclosures: a zero 5e-12 from the guess is proved
    unique inside a narrow image with a sign change at its ends; one 2e-7 away is outside
    N = guess +- 1e-7 (no zero in N); a slope enclosure containing 0 decides nothing, unless
    cos Phi < 0 over N (Phi near pi: no zero mod 2 pi)."""
    with working_precision(128):
        fake = _stand_in(zero, arb(slope), arb(cosine))
        monkeypatch.setattr(fte, "enclose_frame_turn", fake)
        r = fte.prove_critical_energy(BODY, D, "0.180318915145", 42.14, C)
        assert r.verdict == verdict
        if verdict == "unique zero":
            assert r.energy.contains(to_ball(zero)) and 2 * float(r.energy.rad()) <= 1e-12
            assert r.ends[0] < 0 < r.ends[1]


def test_the_slope_tolerance_reaches_only_the_enclosure_over_n(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """``slope_tol`` loosens the step control of ``Phi'`` over ``N`` only; the point
    enclosures (the centre, the image's ends) keep ``tol``."""
    calls = []
    with working_precision(128):
        fake = _stand_in("0.18031891515", arb(240), arb(1))

        def recording(*args, derivative=False, **kw):  # noqa: ANN001, ANN002, ANN202
            calls.append((derivative, kw.get("tol")))
            return fake(*args, derivative=derivative, **kw)

        monkeypatch.setattr(fte, "enclose_frame_turn", recording)
        r = fte.prove_critical_energy(
            BODY, D, "0.180318915145", 42.14, C, tol=1e-20, slope_tol=1e-12
        )
    assert r.verdict == "unique zero"
    assert calls == [(True, 1e-12), (False, 1e-20), (False, 1e-20), (False, 1e-20)]


def test_bad_input_is_refused() -> None:
    with pytest.raises(UserInputError, match="segment"):
        fte.enclose_frame_turn(BODY, D, "100", PERIOD_GUESS, C)  # above h1
    with pytest.raises(UserInputError, match="I1 < I2 < I3"):
        fte.enclose_frame_turn(("2.3", "1.7", "1.1"), D, H, PERIOD_GUESS, C)
