"""The Krawczyk and Schur-Cohn tests: decided against independent facts (closed-form zeros,
eigenvalues by mpmath at 50 digits), each with its negative control."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from chaplygin.numerics.validated.krawczyk import krawczyk_test, schur_cohn
from chaplygin.numerics.validated.lohner import working_precision
from flint import arb, arb_mat
from hypothesis import given, settings
from hypothesis import strategies as st


def _newton_system(c: arb, box: list) -> tuple[list, arb_mat]:
    """F(x, y) = (x^2 + y^2 - c, x - y): zeros (+-sqrt(c/2), +-sqrt(c/2))."""
    x, y = box
    return [x * x + y * y - c, x - y], arb_mat([[2 * x, 2 * y], [1, -1]])


def test_krawczyk_proves_the_zero_and_refutes_a_box_without_one() -> None:
    with working_precision(128):
        c = arb("2.3")
        root = float((c / 2).sqrt().mid())
        centre = [arb(root + 1e-9), arb(root - 2e-9)]
        box = [v + arb(0, 1e-6) for v in centre]
        F, _ = _newton_system(c, centre)
        _, DF = _newton_system(c, box)
        r = krawczyk_test(centre, box, F, DF)
        assert r.verdict == "unique zero"
        exact = (c / 2).sqrt()
        assert all(k.contains(exact) for k in r.image)
        # control: the same machinery on a box 1e-3 away from the zero finds none there
        far = [arb(root + 1e-3), arb(root + 1e-3)]
        fbox = [v + arb(0, 1e-6) for v in far]
        F, _ = _newton_system(c, far)
        _, DF = _newton_system(c, fbox)
        assert krawczyk_test(far, fbox, F, DF).verdict == "no zero"


def _moduli(a: np.ndarray) -> list[float]:
    with mpmath.workdps(50):
        return [
            float(abs(v)) for v in mpmath.eig(mpmath.matrix(a.tolist()), left=False, right=False)
        ]


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(2, 5),
    scale=st.floats(0.3, 1.6),
)
def test_schur_cohn_agrees_with_the_eigenvalues(seed: int, n: int, scale: float) -> None:
    a = np.random.default_rng(seed).normal(size=(n, n)) * scale / np.sqrt(n)
    moduli = _moduli(a)
    verdict, _ = schur_cohn(arb_mat(a.tolist()))
    if verdict == "inside":
        assert max(moduli) < 1
    elif verdict == "not inside":
        assert max(moduli) >= 1
    else:  # undecided only where an eigenvalue is within rounding of the circle
        assert min(abs(m - 1) for m in moduli) < 1e-10
    # a thin point matrix is decided unless an eigenvalue sits on the circle
    if min(abs(m - 1) for m in moduli) > 1e-6:
        assert verdict != "undecided"


@pytest.mark.parametrize("radius", [0.0, 1e-3])
def test_schur_cohn_on_a_rotation_near_the_circle(radius: float) -> None:
    """A rotation scaled by 0.999 (inside) and 1.001 (outside); with a 1e-3 ball on every entry
    the question is open for both (the box holds matrices of either kind)."""
    out = []
    for r in ("0.999", "1.001"):
        with working_precision(128):
            c, s = arb("0.6") * arb(r), arb("0.8") * arb(r)
            m = arb_mat([[c, -s], [s, c]]) + arb_mat([[arb(0, radius)] * 2] * 2)
            out.append(schur_cohn(m)[0])
    assert out == (["inside", "not inside"] if radius == 0 else ["undecided", "undecided"])


def test_a_singular_derivative_leaves_the_question_open() -> None:
    """F(x, y) = (x^2, y) at the double zero x = 0: the midpoint derivative is singular."""
    box = [arb(0, 1e-3), arb(0, 1e-3)]
    r = krawczyk_test([arb(0), arb(0)], box, [arb(0), arb(0)], arb_mat([[2 * box[0], 0], [0, 1]]))
    assert r.verdict == "undecided"
