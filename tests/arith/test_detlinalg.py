"""The project's fixed-order linear algebra (numerics/detlinalg.py) against exact references.

References are computed in exact rational arithmetic (fractions) or in mpmath at 200 bits, an
independent route; tolerances are stated in units of the double epsilon times the size of the
problem (the textbook backward-error bounds of each algorithm).
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from fractions import Fraction

import mpmath
import numpy as np
import pytest
from chaplygin.arith import detlinalg as dl

pytestmark = pytest.mark.quick

EPS = np.finfo(float).eps
#: OpenBLAS kernels every x86-64 processor with AVX2 runs (SkylakeX needs AVX-512)
OPENBLAS_CORES = ("Prescott", "Nehalem", "Sandybridge", "Haswell")


def _random(shape, seed):
    rng = np.random.default_rng(seed)
    return 2.0 * rng.random(shape) - 1.0 + 0.1 * np.sqrt(2.0)  # generic, non-dyadic


def _exact_matmul(A, B):
    A = [[Fraction(float(v)) for v in row] for row in np.atleast_2d(A)]
    B = [[Fraction(float(v)) for v in row] for row in np.atleast_2d(B)]
    return [[sum(A[i][k] * B[k][j] for k in range(len(B))) for j in range(len(B[0]))]
            for i in range(len(A))]  # fmt: skip


@pytest.mark.parametrize("shape", [(3, 3, 3), (6, 6, 4), (5, 1, 7), (1, 9, 1)])
def test_matmul_within_the_summation_bound_of_the_exact_product(shape):
    m, k, n = shape
    A, B = _random((m, k), 1), _random((k, n), 2)
    C = dl.matmul(A, B)
    exact = _exact_matmul(A, B)
    absAB = np.abs(A) @ np.abs(B)  # only a scale for the bound
    for i in range(m):
        for j in range(n):
            assert abs(Fraction(float(C[i, j])) - exact[i][j]) <= k * EPS * absAB[i, j]


def test_matmul_shapes_follow_numpy():
    A, B, v = _random((4, 3), 3), _random((3, 5), 4), _random(3, 5)
    assert dl.matmul(A, B).shape == (4, 5)
    assert dl.matmul(A, v).shape == (4,)
    assert dl.matmul(v, B).shape == (5,)
    assert dl.matmul(v, v).shape == ()
    with pytest.raises(dl.LinAlgError):
        dl.matmul(A, A)


def test_dot_is_the_left_to_right_sum_of_rounded_products():
    x, y = _random(7, 6), _random(7, 7)
    s = 0.0
    for a, b in zip(x.tolist(), y.tolist(), strict=True):
        s += a * b
    assert dl.dot(x, y) == s


def test_norm_scales_and_matches_exact_value():
    x = _random(9, 8) * 1e200  # x.x overflows without the scaling
    exact = math.sqrt(sum(Fraction(float(v / 1e200)) ** 2 for v in x)) * 1e200
    assert abs(dl.norm(x) - exact) <= 10 * EPS * exact
    assert dl.norm(np.zeros(3)) == 0.0


@pytest.mark.parametrize("shape", [(6, 6), (6, 3), (12, 5)])
def test_qr_is_orthonormal_triangular_and_reproduces_a(shape):
    A = _random(shape, 9)
    Q, R = dl.qr(A)
    m, k = shape
    assert Q.shape == (m, k) and R.shape == (k, k)
    assert np.all(np.diag(R) >= 0) and np.all(np.tril(R, -1) == 0)
    np.testing.assert_allclose(dl.matmul(Q.T, Q), np.eye(k), rtol=0, atol=4 * m * EPS)
    scale = dl.norm(A)
    np.testing.assert_allclose(dl.matmul(Q, R), A, rtol=0, atol=4 * m * k * EPS * scale)


def test_qr_agrees_with_lapack_up_to_its_rounding():
    """LAPACK's Householder QR is another implementation of the same factorisation."""
    A = _random((6, 4), 10)
    Q, R = dl.qr(A)
    Qn, Rn = np.linalg.qr(A)
    signs = np.sign(np.diag(Rn))
    np.testing.assert_allclose(R, Rn * signs[:, None], rtol=0, atol=100 * EPS)
    np.testing.assert_allclose(Q, Qn * signs[None, :], rtol=0, atol=100 * EPS)


def test_orthonormal_split_finds_the_rank_and_complementary_spaces():
    g = _random((2, 6), 11)
    G = np.vstack([g, 0.3 * g[0] - 1.7 * g[1]])  # rank 2
    span, comp = dl.orthonormal_split(G)
    assert span.shape == (6, 2) and comp.shape == (6, 4)
    Q = np.hstack([span, comp])
    np.testing.assert_allclose(dl.matmul(Q.T, Q), np.eye(6), rtol=0, atol=50 * EPS)
    # every row of G lies in the span: its component in the complement vanishes
    np.testing.assert_allclose(dl.matmul(G, comp), 0, rtol=0, atol=50 * EPS)
    # negative control: a full-rank set leaves a smaller complement
    span3, comp3 = dl.orthonormal_split(_random((3, 6), 12))
    assert span3.shape == (6, 3) and comp3.shape == (6, 3)
    assert dl.orthonormal_split(np.zeros((0, 4)))[1].shape == (4, 4)


def _mp(A):
    return mpmath.matrix([[mpmath.mpf(float(v)) for v in row] for row in np.atleast_2d(A)])


def test_solve_matches_high_precision_solution():
    A, b = _random((6, 6), 13), _random(6, 14)
    x = dl.solve(A, b)
    with mpmath.workprec(200):
        ref = mpmath.lu_solve(_mp(A), mpmath.matrix([mpmath.mpf(float(v)) for v in b]))
        cond = mpmath.mnorm(_mp(A), 1) * mpmath.mnorm(mpmath.inverse(_mp(A)), 1)
        for i in range(6):
            assert abs(x[i] - ref[i]) <= 36 * EPS * float(cond) * float(mpmath.mnorm(ref, 1))
    with pytest.raises(dl.LinAlgError):
        dl.solve(np.array([[1.0, 2.0], [2.0, 4.0]]), [1.0, 1.0])


def test_lstsq_over_and_underdetermined():
    A, b = _random((8, 3), 15), _random(8, 16)
    x = dl.lstsq(A, b)
    with mpmath.workprec(200):  # normal equations in high precision: an independent route
        M = _mp(A)
        ref = mpmath.lu_solve(M.T * M, M.T * mpmath.matrix([mpmath.mpf(float(v)) for v in b]))
    np.testing.assert_allclose(x, [float(v) for v in ref], rtol=0, atol=1e4 * EPS)
    # minimum norm: the solution lies in the row space and solves the system
    A2, b2 = _random((2, 5), 17), _random(2, 18)
    x2 = dl.lstsq(A2, b2)
    np.testing.assert_allclose(dl.matmul(A2, x2), b2, rtol=0, atol=100 * EPS)
    _, comp = dl.orthonormal_split(A2)
    np.testing.assert_allclose(dl.matmul(comp.T, x2), 0, rtol=0, atol=100 * EPS)


def test_null_vector_spans_the_kernel():
    A = _random((5, 6), 19)
    v = dl.null_vector(A)
    assert abs(dl.norm(v) - 1) <= 10 * EPS
    np.testing.assert_allclose(dl.matmul(A, v), 0, rtol=0, atol=100 * EPS)


def test_eigenvalues_match_high_precision_and_pair_exactly():
    A = _random((6, 6), 20)
    w = dl.eigvals(A)
    with mpmath.workprec(300):
        ref = mpmath.eig(_mp(A), left=False, right=False)
    for r in ref:
        assert min(abs(w - complex(r))) <= 1e3 * EPS * dl.norm(A)
    for z in w:  # conjugate pairs are exact conjugates; real ones have imaginary part 0
        assert z.imag == 0 or np.conj(z) in w
    vals, vecs = dl.eig(A)
    for i in range(6):
        resid = A @ vecs[:, i] - vals[i] * vecs[:, i]
        assert np.max(np.abs(resid)) <= 1e3 * EPS * dl.norm(A)


def test_gauss_legendre_integrates_its_degree_exactly():
    for n in (1, 3, 7, 12):
        x, w = dl.gauss_legendre(n)
        for d in range(2 * n):
            exact = 0.0 if d % 2 else 2.0 / (d + 1)
            assert abs(float(np.sum(w * x**d)) - exact) <= 20 * n * EPS
        # negative control: degree 2n is not integrated exactly
        assert abs(float(np.sum(w * x ** (2 * n))) - 2.0 / (2 * n + 1)) > 1e3 * EPS


def test_unit_vectors_are_unit_and_unbiased():
    rng = np.random.default_rng(21)
    V = dl.unit_vectors(rng, 4000, 3)
    np.testing.assert_allclose(np.sqrt(np.sum(V * V, axis=1)), 1, rtol=0, atol=4 * EPS)
    # the mean of N uniform unit vectors has per-component sd 1/sqrt(3N): 5 sd (p < 1e-6)
    assert np.all(np.abs(V.mean(axis=0)) < 5 / math.sqrt(3 * 4000))


@pytest.mark.slow
def test_results_do_not_depend_on_the_blas_kernel():
    """The same bits with OpenBLAS forced to another processor's kernels (numpy's own @ and
    linalg do change: that is the negative control)."""
    script = (
        "import numpy as np, hashlib\n"
        "from chaplygin.arith import detlinalg as dl\n"
        "rng = np.random.default_rng(5); A = 2*rng.random((9, 9)) - 1.1\n"
        "out = [dl.matmul(A, A), dl.qr(A)[0], dl.solve(A, A[0]), dl.orthonormal_split(A[:3])[1]]\n"
        "ref = [A @ A @ A @ A, np.linalg.qr(A)[0], np.linalg.solve(A, A[0])]\n"
        "h = lambda xs: hashlib.sha256(b''.join(np.ascontiguousarray(x).tobytes() for x in xs))"
        ".hexdigest()\n"
        "print(h(out), h(ref))\n"
    )
    seen = {}
    for core in OPENBLAS_CORES:
        env = {**os.environ, "OPENBLAS_CORETYPE": core}
        out = subprocess.run(
            [sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True
        ).stdout.split()
        seen[core] = out
    assert len({v[0] for v in seen.values()}) == 1, seen
    assert len({v[1] for v in seen.values()}) > 1, "negative control: numpy's BLAS kept its bits"


def test_one_by_one_and_two_by_two_eigenproblems():
    assert dl.eigvals([[-0.35320768999999835]]).tolist() == [-0.35320768999999835 + 0j]
    w, v = dl.eig([[2.5]])
    assert w.tolist() == [2.5 + 0j] and v.tolist() == [[1 + 0j]]
    # a rotation by 0.7 scaled by 1.3: a conjugate pair 1.3 e^(+-0.7i)
    c, s = 1.3 * math.cos(0.7), 1.3 * math.sin(0.7)
    w = dl.eigvals([[c, -s], [s, c]])
    assert w[0] == np.conj(w[1]) and abs(abs(w[0]) - 1.3) <= 4 * EPS


def _in_order(values: np.ndarray) -> float:
    """Left to right from 0.0 (not ``sum``, which compensates since Python 3.12)."""
    s = 0.0
    for v in values.tolist():
        s += v
    return s


def _numpy_qr_full(A: np.ndarray, pivot: bool) -> tuple:
    """The same Householder QR on numpy arrays, column by column (the reference for the
    list-based one: the same IEEE operations in the same order must give the same bits)."""
    m, n = A.shape
    R, QT, perm = A.copy(), np.eye(m), np.arange(n)
    for j in range(min(m, n)):
        if pivot:
            norms = [_in_order(R[j:, c] * R[j:, c]) for c in range(j, n)]
            best = j + int(np.argmax(norms))
            R[:, [j, best]], perm[[j, best]] = R[:, [best, j]], perm[[best, j]]
        x = R[j:, j].copy()
        big = float(np.max(np.abs(x)))
        sigma = big if big == 0 or not np.isfinite(big) else big * math.sqrt(
            _in_order((x / big) * (x / big)))  # fmt: skip
        if sigma == 0:
            continue
        alpha = -sigma if x[0] >= 0 else sigma
        v = x.copy()
        v[0] = x[0] - alpha
        vv = _in_order(v * v)
        if vv == 0:
            continue
        beta = 2.0 / vv
        for M in (R, QT):
            w = v[0] * M[j]
            for i in range(1, m - j):
                w = w + v[i] * M[j + i]
            M[j:] = M[j:] - v[:, None] * (w * beta)[None, :]
        R[j, j], R[j + 1 :, j] = alpha, 0.0
    return QT.T, R, perm


@pytest.mark.parametrize("pivot", [False, True])
def test_the_list_based_qr_gives_the_bits_of_the_same_operations_on_arrays(pivot):
    rng = np.random.default_rng(29)
    for trial in range(300):
        m, n = int(rng.integers(1, 8)), int(rng.integers(1, 8))
        A = rng.normal(size=(m, n)) * 10.0 ** float(rng.integers(-6, 6))
        if trial % 5 == 0:
            A[:, int(rng.integers(0, n))] = 0.0  # a zero column: no reflector there
        got = dl._qr_full(A, pivot)
        want = _numpy_qr_full(A, pivot)
        for a, b in zip(got, want, strict=True):
            assert a.shape == b.shape and np.array_equal(a, b), (trial, m, n)
            if a.dtype == np.float64:
                assert np.array_equal(a.view(np.int64), b.view(np.int64))
