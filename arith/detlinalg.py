"""Small dense linear algebra with an operation order the project fixes: the same bits everywhere.

``numpy.linalg``, ``@`` and ``np.dot`` on float64 call BLAS/LAPACK, whose kernels (chosen by
processor: ``OPENBLAS_CORETYPE``, MKL's code paths, Accelerate) sum in other orders and fuse
other multiply-adds, so a Jacobian, a QR of tangent vectors or a Newton step computed from a
trajectory takes other bits on another machine -- and a chaotic orbit amplifies them (issue 22).
The functions here use only numpy's element-wise operations (each an IEEE-754 operation,
correctly rounded, never fused) and Python loops over the summation index in a stated order, so
their results depend on nothing but the inputs. They are meant for the small matrices of this
project (a few to a few dozen rows): tangent spaces, state-transition matrices, Newton systems.

* sums are taken left to right over the summation index (``dot``, ``matmul``);
* :func:`qr` is Householder's, columns in order, ``R`` with a non-negative diagonal;
* :func:`orthonormal_split` is Householder QR with column pivoting (rank-revealing), used for the
  normal and tangent spaces of a level set;
* :func:`solve` is Gaussian elimination with partial pivoting (the first largest pivot);
* :func:`lstsq` solves full-rank least-squares problems through :func:`qr` (minimum norm when
  underdetermined);
* :func:`eigvals` and :func:`eig` run mpmath's QR algorithm at 106 bits on the exact double
  entries and round the results (mpmath's arithmetic is integer arithmetic: deterministic), so
  they are also more accurate than LAPACK's, at a few milliseconds per small matrix.

Errors are numpy's :class:`numpy.linalg.LinAlgError`, as from ``numpy.linalg``.
"""

from __future__ import annotations

import functools
import math

import mpmath
import numpy as np
from numpy.linalg import LinAlgError
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "LinAlgError",
    "dot",
    "eig",
    "eigvals",
    "gauss_legendre",
    "lstsq",
    "matmul",
    "norm",
    "null_vector",
    "orthonormal_split",
    "qr",
    "solve",
    "unit_vectors",
]

#: Bits of mpmath's working precision in :func:`eigvals` and :func:`eig`.
EIG_BITS = 106


def _matrix(a: ArrayLike, name: str = "a") -> NDArray[np.float64]:
    arr = np.array(a, dtype=np.float64)
    if arr.ndim != 2:
        raise LinAlgError(f"{name} must be a 2-D array, got shape {arr.shape}")
    return arr


def dot(x: ArrayLike, y: ArrayLike) -> float:
    """``sum_i x_i y_i``, the products rounded, then summed left to right.

    Parameters
    ----------
    x, y : array_like, shape (n,)

    Returns
    -------
    float
    """
    xs = np.asarray(x, dtype=np.float64).ravel()
    ys = np.asarray(y, dtype=np.float64).ravel()
    if xs.shape != ys.shape:
        raise LinAlgError(f"dot of shapes {xs.shape} and {ys.shape}")
    s = 0.0
    for p in (xs * ys).tolist():
        s += p
    return s


def norm(x: ArrayLike) -> float:
    """Euclidean norm ``sqrt(dot(x, x))`` (scaled by the largest magnitude, so no overflow).

    Parameters
    ----------
    x : array_like
        Any shape (flattened: the Frobenius norm of a matrix).

    Returns
    -------
    float
    """
    xs = np.asarray(x, dtype=np.float64).ravel()
    if xs.size == 0:
        return 0.0
    big = float(np.max(np.abs(xs)))
    if big == 0.0 or not math.isfinite(big):
        return big if not math.isnan(big) else math.nan
    scaled = xs / big
    return big * math.sqrt(dot(scaled, scaled))


def matmul(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """``a @ b`` summed over the inner index from first to last.

    Parameters
    ----------
    a : array_like, shape (m, k) or (k,)
    b : array_like, shape (k, n) or (k,)

    Returns
    -------
    ndarray
        Shape ``(m, n)``, ``(m,)``, ``(n,)`` or a 0-d array, as ``numpy.matmul``.
    """
    A = np.asarray(a, dtype=np.float64)
    B = np.asarray(b, dtype=np.float64)
    if A.ndim == 1 and B.ndim == 1:
        return np.asarray(dot(A, B))
    A2 = A[None, :] if A.ndim == 1 else A
    B2 = B[:, None] if B.ndim == 1 else B
    if A2.ndim != 2 or B2.ndim != 2 or A2.shape[1] != B2.shape[0]:
        raise LinAlgError(f"matmul of shapes {A.shape} and {B.shape}")
    k = A2.shape[1]
    if k == 0:
        out = np.zeros((A2.shape[0], B2.shape[1]))
    else:
        out = A2[:, 0:1] * B2[0:1, :]
        for j in range(1, k):
            out = out + A2[:, j : j + 1] * B2[j : j + 1, :]
    if A.ndim == 1:
        out = out[0]
    if B.ndim == 1:
        out = out[..., 0]
    return np.ascontiguousarray(out)


def _householder(x: list[float]) -> tuple[list[float], float, float]:
    """Reflector ``H = I - beta v v^T`` with ``H x = alpha e_1``, ``alpha = -sign(x_0) |x|``
    (``|x|`` as :func:`norm` computes it)."""
    v = list(x)
    big = 0.0
    for a in x:  # the largest magnitude, NaN if one is (as numpy's max)
        a = abs(a)
        if a != a:
            big = math.nan
            break
        big = a if a > big else big
    if big == 0.0 or not math.isfinite(big):
        sigma = big
    else:
        s = 0.0
        for a in x:
            a = a / big
            s += a * a
        sigma = big * math.sqrt(s)
    if sigma == 0.0:
        return v, 0.0, 0.0
    alpha = -sigma if x[0] >= 0 else sigma
    v[0] = x[0] - alpha
    vv = 0.0
    for a in v:
        vv += a * a
    beta = 0.0 if vv == 0.0 else 2.0 / vv
    return v, beta, alpha


def _reflect_rows(v: list[float], beta: float, M: list[list[float]], first: int) -> None:
    """``M[first:] <- (I - beta v v^T) M[first:]`` in place: ``w = beta v^T M`` summed over the
    rows in order, then each row less ``v_i w``."""
    if beta == 0.0:
        return
    rows = M[first:]  # (the lengths agree by construction: zip's check left out, hot loop)
    w = [v[0] * x for x in rows[0]]
    for vi, row in zip(v[1:], rows[1:], strict=False):
        w = [a + vi * x for a, x in zip(w, row, strict=False)]
    w = [a * beta for a in w]
    for vi, row in zip(v, rows, strict=False):
        row[:] = [x - vi * a for x, a in zip(row, w, strict=False)]


def _qr_full(
    A: NDArray[np.float64], pivot: bool
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """Householder QR ``A[:, perm] = Q R`` with the full orthogonal ``Q`` (m x m).

    On Python floats, row by row: each number is what the same operations on numpy arrays
    give (every product rounded, sums in order, no fused multiply-add; IEEE arithmetic
    either way), for the small matrices it serves without numpy's per-call cost."""
    m, n = A.shape
    R = A.tolist()
    QT = [[1.0 if i == j else 0.0 for j in range(m)] for i in range(m)]
    perm = list(range(n))
    for j in range(min(m, n)):
        if pivot:
            norms = []
            for c in range(j, n):
                s = 0.0
                for i in range(j, m):
                    s += R[i][c] * R[i][c]
                norms.append(s)
            best = j + int(np.argmax(norms))
            if best != j:
                for row in R:
                    row[j], row[best] = row[best], row[j]
                perm[j], perm[best] = perm[best], perm[j]
        v, beta, alpha = _householder([R[i][j] for i in range(j, m)])
        if beta == 0.0:
            continue
        _reflect_rows(v, beta, R, j)
        R[j][j] = alpha
        for i in range(j + 1, m):
            R[i][j] = 0.0
        _reflect_rows(v, beta, QT, j)  # Q <- Q H_j: the rows of Q^T
    Q = np.array(QT, dtype=np.float64).reshape(m, m).T.copy()
    return Q, np.array(R, dtype=np.float64).reshape(m, n), np.array(perm, dtype=np.intp)


def qr(a: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Thin QR factorisation ``a = Q R`` (Householder), ``R``'s diagonal non-negative.

    Parameters
    ----------
    a : array_like, shape (m, k), ``k <= m``

    Returns
    -------
    Q : ndarray, shape (m, k)
        Orthonormal columns.
    R : ndarray, shape (k, k)
        Upper triangular with ``R[j, j] >= 0``.

    Raises
    ------
    numpy.linalg.LinAlgError
        Not a 2-D array, or more columns than rows.
    """
    A = _matrix(a)
    m, k = A.shape
    if k > m:
        raise LinAlgError(f"qr needs at least as many rows as columns, got shape {A.shape}")
    Q, R, _ = _qr_full(A, pivot=False)
    Q, R = Q[:, :k].copy(), R[:k, :].copy()
    signs = np.where(np.diag(R) < 0, -1.0, 1.0)
    return Q * signs[None, :], R * signs[:, None]


def orthonormal_split(
    g: ArrayLike, rtol: float = 1e-8
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Orthonormal bases of the span of the rows of ``g`` and of its orthogonal complement.

    Householder QR with column pivoting of ``g^T``; the rank is the number of diagonal entries
    of ``R`` above ``rtol`` times the largest.

    Parameters
    ----------
    g : array_like, shape (r, n)
        Rows spanning a subspace of R^n (e.g. gradients of first integrals).
    rtol : float
        Relative rank threshold.

    Returns
    -------
    span : ndarray, shape (n, rank)
    complement : ndarray, shape (n, n - rank)
    """
    G = _matrix(g, "g")
    r, n = G.shape
    if r == 0:
        return np.zeros((n, 0)), np.eye(n)
    Q, R, _ = _qr_full(G.T.copy(), pivot=True)
    diag = np.abs(np.diag(R))
    top = float(diag[0]) if diag.size else 0.0
    rank = int(np.sum(diag > rtol * max(top, np.finfo(float).tiny)))
    return Q[:, :rank].copy(), Q[:, rank:].copy()


def null_vector(a: ArrayLike) -> NDArray[np.float64]:
    """A unit vector spanning the kernel of a full-rank ``m x (m + 1)`` matrix.

    Parameters
    ----------
    a : array_like, shape (m, m + 1)

    Returns
    -------
    ndarray, shape (m + 1,)
        The last column of the full ``Q`` of ``a^T = Q R`` (sign as it comes; callers orient).
    """
    A = _matrix(a)
    m, n = A.shape
    if n != m + 1:
        raise LinAlgError(f"null_vector needs an m x (m + 1) matrix, got shape {A.shape}")
    Q, _, _ = _qr_full(A.T.copy(), pivot=False)
    return Q[:, -1].copy()


def solve(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Solve ``a x = b`` by Gaussian elimination with partial pivoting.

    Parameters
    ----------
    a : array_like, shape (n, n)
    b : array_like, shape (n,) or (n, k)

    Returns
    -------
    ndarray
        Shape of ``b``.

    Raises
    ------
    numpy.linalg.LinAlgError
        ``a`` is not square or is singular (a zero pivot) or not finite.
    """
    A = _matrix(a)
    n = A.shape[0]
    if A.shape != (n, n):
        raise LinAlgError(f"solve needs a square matrix, got shape {A.shape}")
    B = np.array(b, dtype=np.float64)
    vector = B.ndim == 1
    B = B.reshape(n, -1) if B.size or n else B.reshape(0, 0)
    if B.shape[0] != n:
        raise LinAlgError(f"right-hand side of shape {np.shape(b)} for a {n} x {n} matrix")
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B))):
        raise LinAlgError("solve: non-finite entries")
    for j in range(n):
        p = j + int(np.argmax(np.abs(A[j:, j])))
        if A[p, j] == 0.0:
            raise LinAlgError("Singular matrix")
        if p != j:
            A[[j, p]] = A[[p, j]]
            B[[j, p]] = B[[p, j]]
        factors = A[j + 1 :, j] / A[j, j]
        A[j + 1 :, j:] = A[j + 1 :, j:] - factors[:, None] * A[j : j + 1, j:]
        B[j + 1 :] = B[j + 1 :] - factors[:, None] * B[j : j + 1]
    X = np.zeros_like(B)
    for j in range(n - 1, -1, -1):
        s = B[j].copy()
        for c in range(j + 1, n):
            s = s - A[j, c] * X[c]
        X[j] = s / A[j, j]
    return X[:, 0].copy() if vector else X


def _solve_upper(R: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    k = R.shape[0]
    x = np.zeros((k,) + b.shape[1:])
    for j in range(k - 1, -1, -1):
        if R[j, j] == 0.0:
            raise LinAlgError("rank-deficient least-squares problem")
        s = b[j].copy()
        for c in range(j + 1, k):
            s = s - R[j, c] * x[c]
        x[j] = s / R[j, j]
    return x


def _solve_lower_transposed(R: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Solve ``R^T y = b`` (R upper triangular), forward substitution."""
    k = R.shape[0]
    y = np.zeros((k,) + b.shape[1:])
    for j in range(k):
        if R[j, j] == 0.0:
            raise LinAlgError("rank-deficient least-squares problem")
        s = b[j].copy()
        for c in range(j):
            s = s - R[c, j] * y[c]
        y[j] = s / R[j, j]
    return y


def lstsq(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Least-squares solution of ``a x = b`` for a full-rank ``a`` (minimum norm if m < n).

    Parameters
    ----------
    a : array_like, shape (m, n)
    b : array_like, shape (m,) or (m, k)

    Returns
    -------
    ndarray, shape (n,) or (n, k)

    Raises
    ------
    numpy.linalg.LinAlgError
        ``a`` is rank-deficient (a zero diagonal entry of R).
    """
    A = _matrix(a)
    m, n = A.shape
    B = np.array(b, dtype=np.float64)
    if B.shape[0] != m:
        raise LinAlgError(f"right-hand side of shape {B.shape} for a {m} x {n} matrix")
    if m >= n:
        Q, R = qr(A)
        return _solve_upper(R, matmul(Q.T, B))
    Q, R = qr(A.T)  # A = R^T Q^T, x = Q y with R^T y = b
    return matmul(Q, _solve_lower_transposed(R, B))


def _eig_mp(A: NDArray[np.float64], vectors: bool):  # noqa: ANN202 - mpmath objects
    if A.shape[0] != A.shape[1]:
        raise LinAlgError(f"eigenvalues need a square matrix, got shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise LinAlgError("eigenvalues: non-finite entries")
    with mpmath.workprec(EIG_BITS):
        M = mpmath.matrix([[mpmath.mpf(float(v)) for v in row] for row in A])
        if A.shape[0] == 1:  # mpmath.eig's 1 x 1 answer has another shape
            return [M[0, 0]], mpmath.matrix([[1]])
        if vectors:
            return mpmath.eig(M, left=False, right=True)
        return mpmath.eig(M, left=False, right=False), None


def _round_eigenvalues(values, scale: float) -> NDArray[np.complex128]:  # noqa: ANN001
    """Round mpmath eigenvalues to complex128; imaginary parts below ``2^-90 scale`` are 0 and
    the members of a conjugate pair made exact conjugates."""
    tiny = math.ldexp(max(scale, np.finfo(float).tiny), -90)
    out = []
    for v in values:
        c = mpmath.mpc(v)
        re, im = float(c.real), float(c.imag)
        out.append(complex(re, 0.0 if abs(im) <= tiny else im))
    arr = np.array(out, dtype=np.complex128)
    free = [j for j in range(arr.size) if arr[j].imag < 0]
    for i in range(arr.size):  # each z with im > 0 takes the nearest unpaired im < 0 as z*
        if arr[i].imag > 0 and free:
            j = min(free, key=lambda c: (abs(arr[c] - np.conj(arr[i])), c))
            free.remove(j)
            arr[j] = np.conj(arr[i])
    return arr


def eigvals(a: ArrayLike) -> NDArray[np.complex128]:
    """Eigenvalues of a small square matrix (mpmath at :data:`EIG_BITS` bits, rounded).

    Parameters
    ----------
    a : array_like, shape (n, n)

    Returns
    -------
    ndarray of complex, shape (n,)
        In mpmath's order; real ones have imaginary part exactly 0, conjugate pairs are exact
        conjugates.
    """
    A = _matrix(a)
    E, _ = _eig_mp(A, vectors=False)
    return _round_eigenvalues(E, norm(A))


def eig(a: ArrayLike) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Eigenvalues and right eigenvectors (columns, unit 2-norm) of a small square matrix.

    Parameters
    ----------
    a : array_like, shape (n, n)

    Returns
    -------
    w : ndarray of complex, shape (n,)
    v : ndarray of complex, shape (n, n)
        ``v[:, i]`` belongs to ``w[i]``.
    """
    A = _matrix(a)
    E, ER = _eig_mp(A, vectors=True)
    w = _round_eigenvalues(E, norm(A))
    n = A.shape[0]
    with mpmath.workprec(EIG_BITS):
        V = np.zeros((n, n), dtype=np.complex128)
        for i in range(n):
            col = [mpmath.mpc(ER[r, i]) for r in range(n)]
            size = mpmath.sqrt(mpmath.fsum(abs(c) ** 2 for c in col))
            V[:, i] = [complex(c / size) if size else 0j for c in col]
    return w, V


def unit_vectors(rng: np.random.Generator, count: int, dim: int) -> NDArray[np.float64]:
    """``count`` random unit vectors of R^dim, uniform on the sphere, without libm.

    Points uniform in the cube ``[-1, 1)^dim`` (the generator's integers scaled exactly) are
    kept when inside the unit ball (and not too near its centre) and scaled to length 1 --
    rejection sampling, so the directions are uniform; numpy's normal deviates are not used
    because their tails call libm's ``log``, whose bits depend on the processor.

    Parameters
    ----------
    rng : numpy.random.Generator
    count, dim : int

    Returns
    -------
    ndarray, shape (count, dim)
    """
    out = np.zeros((count, dim))
    filled = 0
    while filled < count:
        batch = 2.0 * rng.random((max(2 * (count - filled), 8), dim)) - 1.0
        for row in batch:
            r = norm(row)
            if 1e-3 < r <= 1.0:
                out[filled] = row / r
                filled += 1
                if filled == count:
                    break
    return out


@functools.lru_cache(maxsize=64)
def _gauss_legendre(n: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
    with mpmath.workprec(EIG_BITS):
        nodes, weights = [], []
        for i in range(1, n + 1):  # Newton on P_n from the classical guess
            x = mpmath.cos(mpmath.pi * (i - mpmath.mpf(0.25)) / (n + mpmath.mpf(0.5)))
            for _ in range(100):
                p0, p1 = mpmath.mpf(1), x
                for k in range(2, n + 1):
                    p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
                dp = n * (x * p1 - p0) / (x * x - 1) if n > 1 else mpmath.mpf(1)
                dx = p1 / dp
                x -= dx
                if abs(dx) < mpmath.ldexp(1, -EIG_BITS + 4):
                    break
            p0, p1 = mpmath.mpf(1), x
            for k in range(2, n + 1):
                p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
            dp = n * (x * p1 - p0) / (x * x - 1) if n > 1 else mpmath.mpf(1)
            nodes.append(float(x))
            weights.append(float(2 / ((1 - x * x) * dp * dp)))
    order = sorted(range(n), key=lambda j: nodes[j])
    return tuple(nodes[j] for j in order), tuple(weights[j] for j in order)


def gauss_legendre(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss-Legendre nodes and weights on [-1, 1], computed at 106 bits and rounded.

    ``numpy.polynomial.legendre.leggauss`` takes them from a LAPACK eigenvalue problem
    (bits by processor); these are Newton's iteration on ``P_n`` in mpmath.

    Parameters
    ----------
    n : int
        Number of nodes (>= 1).

    Returns
    -------
    nodes, weights : ndarray, shape (n,)
        Nodes increasing.
    """
    if n < 1:
        raise LinAlgError(f"gauss_legendre needs n >= 1, got {n}")
    x, w = _gauss_legendre(int(n))
    return np.array(x), np.array(w)
