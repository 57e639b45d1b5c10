"""Constants of the project's own transcendental kernels (``templates/detmath.h``), from mpmath.

Every number in the constants block of ``detmath.h`` -- splits of ln 2 and pi/2, the bits of 2/pi,
the tables of 2^(j/128), log(1/r), sin/cos(i/128) and atan(i/64), the polynomial coefficients --
is computed here with mpmath at 1600 bits and rounded to double precision (round to nearest) or to
the fixed grid its algorithm needs.  The script also checks the design conditions the kernels rely
on (exact products, Fast2Sum preconditions, the range of every reduced argument) and prints the
truncation error of every polynomial, so a change that breaks one fails here.

The header's constants block is printed from these numbers by
:mod:`chaplygin.derive.emit.detmath_header` at development time (the test
``tests/arith/test_detmath.py`` re-runs it and checks the header)::

    python -m chaplygin.derive.emit.detmath_header            # print the constants block
    python -m chaplygin.derive.emit.detmath_header --write    # write it into detmath.h

The polynomials are truncated Taylor series with exactly rounded coefficients: on the small
intervals used their truncation error is bounded by the first omitted term (alternating series)
or by the Lagrange remainder, so the design bounds quoted in ``detmath.h`` follow from this file
without any fitting.  Only the starting guess of cbrt (refined by Halley and Newton steps) is an
interpolating polynomial (at Chebyshev nodes).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import mpmath
from mpmath import mpf

__all__ = ["constants", "header_path"]

_PREC = 1600  # bits: 2/pi is needed to about 1280 bits

#: Table sizes and grids (the C code and the numpy port use the same numbers).
EXP_N = 128  # exp: 2^(j/128), j = 0..127
LOG_JMIN, LOG_JMAX = -75, 106  # log: m = 1 + j/256 with m in [sqrt(2)/2, sqrt(2))
LOG_R_BITS = 10  # log: r_j is a multiple of 2^-10 (at most 11 significant bits)
LN2_HI_BITS = 42  # ln2_hi and the log table's hi parts are multiples of 2^-42
TRIG_IMIN, TRIG_IMAX = 16, 101  # sin/cos: a_i = i/128 for |r| in [1/8, pi/4 + eps]
ATAN_N = 64  # atan: c_i = i/64, i = 0..64
TWO_OVER_PI_WORDS = 20  # 64 zero bits, then 1216 bits of 2/pi


def header_path() -> Path:
    """Path of the header whose constants block is computed here.

    Returns
    -------
    pathlib.Path
        ``templates/detmath.h`` next to this module.
    """
    return Path(__file__).resolve().parent / "templates" / "detmath.h"


# --------------------------------------------------------------------------- rounding helpers


def _rn(x: mpf) -> float:
    """Round to the nearest double (ties to even); the constants are all normal numbers."""
    with mpmath.workprec(53):
        y = +x  # rounds to 53 bits, nearest-even
    f = float(y)
    assert mpf(f) == y, "constant outside the normal double range"
    return f


def _grid(x: mpf, lsb_exp: int) -> float:
    """Round to the nearest multiple of 2^lsb_exp (must fit in a double exactly)."""
    n = mpmath.nint(x * mpf(2) ** (-lsb_exp))
    f = float(mpmath.ldexp(n, lsb_exp))
    assert mpf(f) == mpmath.ldexp(n, lsb_exp)
    return f


def _split(x: mpf) -> tuple[float, float]:
    """Double-double (hi, lo): hi = RN(x), lo = RN(x - hi)."""
    hi = _rn(x)
    return hi, _rn(x - mpf(hi))


def _sig_bits(f: float) -> int:
    """Number of significant bits of a (normal) double (0 for zero)."""
    if f == 0.0:
        return 0
    m, _ = mpmath.frexp(mpf(abs(f)))
    n = int(m * 2**53)
    while n % 2 == 0:
        n //= 2
    return n.bit_length()


def _taylor_coeffs(kind: str, count: int) -> list[float]:
    """Exactly rounded Taylor coefficients."""
    out = []
    for k in range(count):
        if kind == "exp":  # 1/n!, n = 2, 3, ...
            c = mpf(1) / mpmath.factorial(k + 2)
        elif kind == "log1p":  # log1p(u) = u + u^2 * sum_k (-1)^(k+1) u^k / (k+2)
            c = mpf((-1) ** (k + 1)) / (k + 2)
        elif kind == "sin":  # (-1)^(k+1) / (2k+3)!
            c = mpf((-1) ** (k + 1)) / mpmath.factorial(2 * k + 3)
        elif kind == "cos":  # (-1)^(k+1) / (2k+2)!
            c = mpf((-1) ** (k + 1)) / mpmath.factorial(2 * k + 2)
        elif kind == "sinh":  # 1 / (2k+3)!
            c = mpf(1) / mpmath.factorial(2 * k + 3)
        elif kind == "atan":  # (-1)^(k+1) / (2k+3)
            c = mpf((-1) ** (k + 1)) / (2 * k + 3)
        else:  # pragma: no cover - programming error
            raise ValueError(kind)
        out.append(_rn(c))
    return out


# --------------------------------------------------------------------------- the constants
#
# One function per group of the header's constants block, in header order; each appends its
# constants (and the design numbers it checks) to a _Block. They run inside constants(), at
# the working precision _PREC.


class _Block:
    """The constants in header order, ``(name, C type, value or list)``, and the comment lines
    with the design numbers."""

    def __init__(self) -> None:
        self.items: list[tuple[str, str, object]] = []
        self.notes: list[str] = []

    def scalar(self, name: str, value: float) -> None:
        self.items.append((name, "double", value))

    def table(self, name: str, values: Sequence[float]) -> None:
        self.items.append((name, "double[]", list(values)))


def _pi_splits(out: _Block) -> None:
    """ln 2 and pi splits, and the Cody-Waite constants of pi/2."""
    pi = mpmath.pi
    ln2 = mpmath.log(2)
    ln2_hi = _grid(ln2, -LN2_HI_BITS)
    ln2_lo = _rn(ln2 - mpf(ln2_hi))
    assert _sig_bits(ln2_hi) <= 42  # e * ln2_hi exact for |e| < 2^11
    out.scalar("LN2_HI", ln2_hi)
    out.scalar("LN2_LO", ln2_lo)
    pio2_hi, pio2_lo = _split(pi / 2)
    out.scalar("PIO2_HI", pio2_hi)
    out.scalar("PIO2_LO", pio2_lo)
    pi_hi, pi_lo = _split(pi)
    out.scalar("PI_HI", pi_hi)
    out.scalar("PI_LO", pi_lo)
    out.scalar("PI3O4", _rn(3 * pi / 4))
    out.scalar("PI_O4", _rn(pi / 4))
    out.scalar("INV_PIO2", _rn(2 / pi))
    # Cody-Waite: pi/2 = P1 + P2 + P3 + P4, P1..P3 with at most 33 significant bits so that
    # n * Pk is exact for n < 2^20.
    p1 = _grid(pi / 2, -32)
    p2 = _grid(pi / 2 - mpf(p1), -65)
    p3 = _grid(pi / 2 - mpf(p1) - mpf(p2), -98)
    p4 = _rn(pi / 2 - mpf(p1) - mpf(p2) - mpf(p3))
    for p in (p1, p2, p3):
        assert _sig_bits(p) <= 33
    cw_err = abs(pi / 2 - mpf(p1) - mpf(p2) - mpf(p3) - mpf(p4))
    out.notes.append(f"Cody-Waite |pi/2 - (P1+P2+P3+P4)| = 2^{float(mpmath.log(cw_err, 2)):.1f}")
    out.scalar("CW_P1", p1)
    out.scalar("CW_P2", p2)
    out.scalar("CW_P3", p3)
    out.scalar("CW_P4", p4)


def _exp_tables(out: _Block) -> None:
    """exp: x = k ln2/128 + r, |r| <= ln2/256 (+ rounding of k)."""
    ln2 = mpmath.log(2)
    out.scalar("EXP_INV_LN2_N", _rn(EXP_N / ln2))
    c1 = _grid(ln2 / EXP_N, -42)
    assert _sig_bits(c1) <= 35  # k * C1 exact for |k| < 2^18 (|x| < 1419)
    c2 = _rn(ln2 / EXP_N - mpf(c1))
    out.scalar("EXP_LN2_N_HI", c1)
    out.scalar("EXP_LN2_N_LO", c2)
    r_max = ln2 / (2 * EXP_N) * (1 + mpf(2) ** -40) + mpf(2) ** -40
    ncoef = 5  # r^2/2! .. r^6/6!
    exp_trunc = r_max ** (ncoef + 2) / mpmath.factorial(ncoef + 2) * mpmath.exp(r_max)
    out.notes.append(
        f"exp: |r| <= {float(r_max):.6g}; Taylor degree {ncoef + 1}, "
        f"relative truncation < 2^{float(mpmath.log(exp_trunc, 2)):.1f}"
    )
    out.table("EXP_POLY", _taylor_coeffs("exp", ncoef))
    t_hi, t_lo = [], []
    for j in range(EXP_N):
        h, lo = _split(mpf(2) ** (mpf(j) / EXP_N))
        t_hi.append(h)
        t_lo.append(lo)
    out.table("EXP_T_HI", t_hi)
    out.table("EXP_T_LO", t_lo)


#: log1p(u) = u + u^2 (c0 + c1 u + ... + c5 u^5): terms to u^7 (log, and log2/log10 divided by
#: ln b).
_N_LOG = 6


def _log_tables(out: _Block) -> tuple[list[float], list[mpf]]:
    """log: x = 2^e m, m in [sqrt(2)/2, sqrt(2)), j = round(256 (m - 1)), u = m r_j - 1 exact
    as u_hi + u_lo, log x = e ln2 + log(1/r_j) + log1p(u).

    Returns the table of r_j and the bound of |u| per row, which log2 and log10 share.
    """
    r_tab, l_hi, l_lo, u_maxes = [], [], [], []
    u_max = mpf(0)
    sqrt2_t = _rn(mpmath.sqrt(2))
    lo_m = mpf(sqrt2_t) / 2
    hi_m = mpf(sqrt2_t)
    for j in range(LOG_JMIN, LOG_JMAX + 1):
        c = 1 + mpf(j) / 256
        r = mpmath.nint(mpf(2) ** LOG_R_BITS / c) / mpf(2) ** LOG_R_BITS
        if j == 0:
            assert r == 1
        rf = float(r)
        assert _sig_bits(rf) <= 11
        lh = _grid(-mpmath.log(r), -LN2_HI_BITS)
        ll = _rn(-mpmath.log(r) - mpf(lh))
        r_tab.append(rf)
        l_hi.append(lh)
        l_lo.append(ll)
        # interval of m mapped to j (rounding ties either way), clipped to [sqrt2/2, sqrt2]
        a = max(c - mpf(1) / 512, lo_m)
        b = min(c + mpf(1) / 512, hi_m)
        umax_j = max(abs(a * r - 1), abs(b * r - 1))
        u_max = max(u_max, umax_j)
        u_maxes.append(umax_j)
        if j != 0:
            # Fast2Sum(H, u) with H = log(1/r_j) (e = 0): |H| >= |u| on the interval
            assert abs(mpf(lh)) >= umax_j, j
    assert u_max < mpf(2) ** -8
    out.notes.append(f"log: |u| <= 2^{float(mpmath.log(u_max, 2)):.3f}")
    out.scalar("LOG_SQRT2", sqrt2_t)
    out.table("LOG_R", r_tab)
    out.table("LOG_L_HI", l_hi)
    out.table("LOG_L_LO", l_lo)
    log_trunc = u_max ** (_N_LOG + 1) / (_N_LOG + 2) / (1 - u_max)
    out.notes.append(
        f"log: Taylor to u^{_N_LOG + 1}, truncation < 2^{float(mpmath.log(log_trunc, 2)):.1f} |u|"
    )
    out.table("LOG_POLY", _taylor_coeffs("log1p", _N_LOG))
    n_logdd = 6  # double-double log: u^3 (1/3 - u/4 + ... ) to u^8
    logdd_coef = [_rn(mpf((-1) ** k) / (k + 3)) for k in range(n_logdd)]
    logdd_trunc = u_max ** (n_logdd + 2) / (n_logdd + 3) / (1 - u_max)
    out.notes.append(
        f"log (double-double, for pow): Taylor to u^{n_logdd + 2}, "
        f"truncation < 2^{float(mpmath.log(logdd_trunc, 2)):.1f} |u|"
    )
    out.table("LOGDD_POLY", logdd_coef)
    return r_tab, u_maxes


def _log_base_tables(out: _Block, r_tab: list[float], u_maxes: list[mpf]) -> None:
    """log2, log10: log_b x = e log_b(2) + log_b(1/r_j) + log1p(u) / ln b, the reduction of
    :func:`_log_tables`."""
    ln2 = mpmath.log(2)
    for base, name, lsb in ((2, "LOG2", -42), (10, "LOG10", -43)):
        ln_b = mpmath.log(base)
        k_hi, k_lo = _split(1 / ln_b)
        out.scalar(f"{name}_K_HI", k_hi)  # 1 / ln b
        out.scalar(f"{name}_K_LO", k_lo)
        e_hi = _grid(ln2 / ln_b, lsb)  # log_b 2 (exactly 1 for base 2)
        assert _sig_bits(e_hi) <= 42  # e * e_hi exact
        out.scalar(f"{name}_E_HI", e_hi)
        out.scalar(f"{name}_E_LO", _rn(ln2 / ln_b - mpf(e_hi)))
        lb_hi, lb_lo = [], []
        for r, umax_j in zip(r_tab, u_maxes, strict=True):
            value = -mpmath.log(mpf(r)) / ln_b
            lb_hi.append(_grid(value, lsb))
            lb_lo.append(_rn(value - mpf(lb_hi[-1])))
            # Fast2Sum(H, u/ln b) when e = 0: |H| >= |u| / ln b (with room for rounding)
            assert lb_hi[-1] == 0 or abs(mpf(lb_hi[-1])) >= umax_j / ln_b * (1 + mpf(2) ** -40)
        out.table(f"{name}_L_HI", lb_hi)
        out.table(f"{name}_L_LO", lb_lo)
        poly = [_rn(mpf((-1) ** (k + 1)) / (k + 2) / ln_b) for k in range(_N_LOG)]
        out.table(f"{name}_POLY", poly)


def _trig_tables(out: _Block) -> None:
    """sin/cos: |r| < 1/8 polynomial, else a = i/128 + d, |d| <= 1/256."""
    small = mpf(1) / 8
    n_sin = 5  # r^3 .. r^11
    sin_trunc = small ** (2 * n_sin + 2) / mpmath.factorial(2 * n_sin + 3)
    n_cos = 5  # r^2 .. r^10
    cos_trunc = small ** (2 * n_cos + 2) / mpmath.factorial(2 * n_cos + 2)
    out.notes.append(
        f"sin |r| < 1/8: Taylor to r^{2 * n_sin + 1}, truncation < "
        f"2^{float(mpmath.log(sin_trunc, 2)):.1f} |r|; cos: to r^{2 * n_cos}, truncation < "
        f"2^{float(mpmath.log(cos_trunc, 2)):.1f}"
    )
    out.table("SIN_POLY", _taylor_coeffs("sin", n_sin))
    out.table("COS_POLY", _taylor_coeffs("cos", n_cos))
    d_max = mpf(1) / 256 + mpf(2) ** -50
    sd_trunc = d_max**7 / mpmath.factorial(7)
    cd_trunc = d_max**8 / mpmath.factorial(8)
    out.notes.append(
        f"sin/cos table path: |d| <= 1/256, sin d to d^5 (truncation < "
        f"2^{float(mpmath.log(sd_trunc, 2)):.1f}), cos d to d^6 (truncation < "
        f"2^{float(mpmath.log(cd_trunc, 2)):.1f})"
    )
    out.table("SIND_POLY", _taylor_coeffs("sin", 2))
    out.table("COSD_POLY", _taylor_coeffs("cos", 3))
    # round(128 |r|) <= TRIG_IMAX
    assert (TRIG_IMAX + mpf(1) / 2) / 128 > mpmath.pi / 4 + mpf(2) ** -30
    s_hi, s_lo, c_hi, c_lo = [], [], [], []
    for i in range(TRIG_IMIN, TRIG_IMAX + 1):
        a = mpf(i) / 128
        h, lo = _split(mpmath.sin(a))
        s_hi.append(h)
        s_lo.append(lo)
        h, lo = _split(mpmath.cos(a))
        c_hi.append(h)
        c_lo.append(lo)
    out.table("TRIG_S_HI", s_hi)
    out.table("TRIG_S_LO", s_lo)
    out.table("TRIG_C_HI", c_hi)
    out.table("TRIG_C_LO", c_lo)


def _atan_tables(out: _Block) -> None:
    """atan: atan(u/v) = atan(c) + atan(t), c = i/64, |t| <= 1/128."""
    t_max = mpf(1) / 128 * (1 + mpf(2) ** -40)
    n_atan = 4  # t^3 .. t^9
    atan_trunc = t_max ** (2 * n_atan + 2) / (2 * n_atan + 3)
    out.notes.append(
        f"atan: |t| <= 1/128, Taylor to t^{2 * n_atan + 1}, truncation < "
        f"2^{float(mpmath.log(atan_trunc, 2)):.1f} |t|"
    )
    out.table("ATAN_POLY", _taylor_coeffs("atan", n_atan))
    a_hi, a_lo = [], []
    for i in range(ATAN_N + 1):
        h, lo = _split(mpmath.atan(mpf(i) / ATAN_N))
        a_hi.append(h)
        a_lo.append(lo)
    out.table("ATAN_HI", a_hi)
    out.table("ATAN_LO", a_lo)


def _sinh_poly(out: _Block) -> None:
    """sinh: |x| < 1/4 polynomial."""
    n_sinh = 6  # x^3 .. x^13
    q = mpf(1) / 4
    sinh_trunc = q ** (2 * n_sinh + 2) / mpmath.factorial(2 * n_sinh + 3) * mpmath.cosh(q)
    out.notes.append(
        f"sinh |x| < 1/4: Taylor to x^{2 * n_sinh + 1}, truncation < "
        f"2^{float(mpmath.log(sinh_trunc, 2)):.1f} |x|"
    )
    out.table("SINH_POLY", _taylor_coeffs("sinh", n_sinh))


def _cbrt_tables(out: _Block) -> None:
    """cbrt: starting guess p(m) ~ cbrt(m) on [1, 2] (degree 5, interpolating at the six
    Chebyshev nodes), cbrt(2^j) j = 0,1,2."""
    nodes = [mpf(3) / 2 + mpmath.cos((2 * k + 1) * mpmath.pi / 12) / 2 for k in range(6)]
    vandermonde = mpmath.matrix([[x ** (5 - d) for d in range(6)] for x in nodes])
    poly = mpmath.lu_solve(vandermonde, mpmath.matrix([mpmath.cbrt(x) for x in nodes]))
    cb = [_rn(poly[d]) for d in range(6)]  # highest degree first
    worst = max(
        abs(mpmath.polyval([mpf(c) for c in cb], x) / mpmath.cbrt(x) - 1)
        for x in mpmath.linspace(1, 2, 2001)
    )
    assert worst < mpf(2) ** -18
    out.notes.append(f"cbrt: starting guess relative error < 2^{float(mpmath.log(worst, 2)):.1f}")
    out.table("CBRT_POLY", cb)
    out.table("CBRT_2J", [_rn(mpmath.cbrt(mpf(2) ** j)) for j in range(3)])


def _two_over_pi_bits(out: _Block) -> None:
    """2/pi for Payne-Hanek: word 0 is zero, words 1.. hold the bits after the point."""
    bits = 64 * (TWO_OVER_PI_WORDS - 1)
    big = int(mpmath.floor(2 / mpmath.pi * mpf(2) ** bits))
    words = [0] + [(big >> (64 * (TWO_OVER_PI_WORDS - 2 - k))) & (2**64 - 1)
                   for k in range(TWO_OVER_PI_WORDS - 1)]
    out.items.append(("TWO_OVER_PI_BITS", "uint64_t[]", words))


def _constants() -> tuple[list[tuple[str, str, object]], list[str]]:
    """(name, C type, value or list) in header order, and comment lines (design numbers)."""
    out = _Block()
    _pi_splits(out)
    _exp_tables(out)
    r_tab, u_maxes = _log_tables(out)
    _log_base_tables(out, r_tab, u_maxes)
    _trig_tables(out)
    _atan_tables(out)
    _sinh_poly(out)
    _cbrt_tables(out)
    _two_over_pi_bits(out)
    return out.items, out.notes


def constants() -> tuple[list[tuple[str, str, object]], list[str]]:
    """Every constant of the kernels, and the design notes, at the working precision needed.

    Returns
    -------
    (list of (str, str, object), list of str)
        ``(name, C type, value)`` per constant (``"double"``, ``"double[]"`` or
        ``"uint64_t[]"``) and the notes (reduced-argument ranges, truncation errors) that
        the header quotes.
    """
    with mpmath.workprec(_PREC):
        return _constants()
