"""The convolutions of :data:`JET_LIB` (matrix products over stacked coefficients) against
the jet arithmetic they replace (``sum`` of :class:`ArbJet` products), and the generated
recurrences run both ways."""

from __future__ import annotations

import random
from operator import mul
from types import SimpleNamespace

import pytest
from chaplygin.numerics.validated.jets import JET_LIB, ArbJet, seed_jets
from chaplygin.numerics.validated.lohner import working_precision
from flint import arb, arb_mat

N_SEEDS, LENGTH = 6, 13


def _ball(rng: random.Random) -> arb:
    """A generic ball: a non-dyadic rational midpoint, a small radius."""
    return arb(rng.randint(-(10**6), 10**6)) / 999983 + arb(0, 1e-20)


def _jets(rng: random.Random) -> list:
    return [
        ArbJet(_ball(rng), arb_mat([[_ball(rng) for _ in range(N_SEEDS)]])) for _ in range(LENGTH)
    ]


def _parts(x: object) -> list:
    if isinstance(x, ArbJet):
        return [x.v] + [x.g[0, c] for c in range(x.g.ncols())]
    return [x]


@pytest.mark.parametrize("weighted", [False, True], ids=["plain", "weighted"])
def test_convolution_is_the_sum_of_jet_products(weighted):
    """Every (lo, hi, k) the generated code uses, jets with jets, with constants and with
    themselves: the same balls as the jet sum (overlapping, radii within 1 %)."""
    rng = random.Random(20261127)
    with working_precision(128):
        a, b = _jets(rng), _jets(rng)
        c = [_ball(rng) for _ in range(LENGTH)]  # a constant's coefficients: no gradient
        cases = [
            (k, x, y, lo, hi)
            for k in range(1, LENGTH)
            for x, y in ((a, b), (a, c), (c, a), (a, a))
            for lo, hi in ((0, k), (1, k), (1, k - 1))
            if hi >= lo
        ]
        # in the recurrence's order (k rising), then shuffled: the rows kept between calls
        # must not carry entries of an earlier call into a later one
        for k, x, y, lo, hi in cases + rng.sample(cases, len(cases)):
            js = range(lo, hi + 1)
            if weighted:
                ref = sum([j * x[j] * y[k - j] for j in js])
                got = JET_LIB.wconv(x, y, lo, hi, k)
            else:
                ref = sum(map(mul, x[lo : hi + 1], [y[k - j] for j in js]))
                got = JET_LIB.conv(x, y, lo, hi, k)
            assert isinstance(got, ArbJet) == isinstance(ref, ArbJet)
            for r, g in zip(_parts(ref), _parts(got), strict=True):
                assert r.overlaps(g)
                assert float(g.rad()) <= 1.01 * float(r.rad()) + 1e-300
                assert float(g.rad()) < 1e-15


def test_wrong_pairing_is_caught():
    """The negative control of the test above: pairing a[j] with b[j] instead of b[k - j]
    is not the convolution (its value lies outside)."""
    rng = random.Random(7)
    with working_precision(128):
        a, b = _jets(rng), _jets(rng)
        got = JET_LIB.conv(a, b, 0, 5, 5)
        wrong = sum(map(mul, a[:6], b[:6]))
        assert not got.v.overlaps(wrong.v)


def test_generated_recurrences_agree_with_and_without_the_convolutions():
    """The ball's generated Taylor recurrences on jets: with ``conv`` (matrix products) and
    without (the jet sums), the same coefficients and gradients as balls."""
    from chaplygin.numerics.code import load_model_code

    taylor = load_model_code("chaplygin_ball", ("variable_gyrostat", "variable_inertia")).taylor

    rng = random.Random(11)
    plain = SimpleNamespace(**{k: v for k, v in vars(JET_LIB).items() if "conv" not in k})
    with working_precision(128):
        y = [_ball(rng) for _ in range(6)]
        p = [arb(v) / 7 for v in (7, 9, 13, 5, 1, 2, 3, 4, 6, 8)]
        t0 = arb(3) / 11
        fast = taylor.taylor_coefficients(t0, seed_jets(y), p, 12, JET_LIB)
        slow = taylor.taylor_coefficients(t0, seed_jets(y), p, 12, plain)
        for row_f, row_s in zip(fast, slow, strict=True):
            for f, s in zip(row_f, row_s, strict=True):
                for g, r in zip(_parts(f), _parts(s), strict=True):
                    assert g.overlaps(r)
                    assert float(g.rad()) <= 1.01 * float(r.rad()) + 1e-300
