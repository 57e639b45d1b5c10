"""A proof that integral values are never taken together, and the lattices of the spheres.

:func:`quadratic_certificate` looks for multipliers ``lambda`` for which ``sum lambda_i (F_i -
v_i)``, over conditions ``F_i(x) = v_i`` that are quadratics in the unknowns ``x``, is a
positive-definite quadratic with a positive least value: then the ``F_i - v_i`` never vanish
together (a degree-2 Positivstellensatz certificate, no sum of squares needed). The quadratics
are fitted exactly from values (:func:`quadratic_fit`, checked at one more point to half the
working digits): the proof is about those quadratics. Not finding a certificate proves nothing.
Used by :mod:`chaplygin.numerics.integral_levels` and :mod:`chaplygin.numerics.level_points`,
with the lattices of the unit spheres they start from (:func:`fibonacci_lattice`,
:func:`unit_sphere_lattice`).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence

import mpmath

from ..derive.errors import UserInputError

__all__ = [
    "fibonacci_lattice",
    "unit_sphere_lattice",
    "quadratic_fit",
    "least_of_quadratic",
    "quadratic_certificate",
    "certificate_refusal",
]

#: Angles of the circle of multipliers searched (two conditions).
CERTIFICATE_CIRCLE = 192
#: Fibonacci points of the sphere of multipliers searched (three conditions).
CERTIFICATE_SPHERE = 384


def fibonacci_lattice(n: int) -> list[list]:
    """The Fibonacci lattice of the unit sphere of ``R^3``, in its fixed order.

    Parameters
    ----------
    n : int
        Number of points.

    Returns
    -------
    list of [mpmath.mpf, mpmath.mpf, mpmath.mpf]
        Point ``i`` at height ``z = 1 - (2 i + 1)/n`` and longitude ``2 pi i / golden``, at the
        current mpmath precision.
    """
    golden = (1 + mpmath.sqrt(5)) / 2
    out = []
    for i in range(n):
        z = 1 - (2 * mpmath.mpf(i) + 1) / n
        r = mpmath.sqrt(1 - z * z)
        phi = 2 * mpmath.pi * i / golden
        out.append([r * mpmath.cos(phi), r * mpmath.sin(phi), z])
    return out


def unit_sphere_lattice(m: int, circle: int, sphere: int, reach: int) -> list[list]:
    """A fixed lattice of the unit sphere of ``R^m``.

    Parameters
    ----------
    m : int
        Dimension.
    circle : int
        Equal angles for ``m = 2``.
    sphere : int
        Fibonacci points for ``m = 3``.
    reach : int
        For ``m >= 4``: the normalised points of ``{-reach..reach}^m`` without 0.

    Returns
    -------
    list of list of mpmath.mpf
        ``[-1], [1]`` for ``m = 1``; otherwise as above, in a fixed order.
    """
    if m == 1:
        return [[mpmath.mpf(-1)], [mpmath.mpf(1)]]
    if m == 2:
        angles = [2 * mpmath.pi * j / circle for j in range(circle)]
        return [[mpmath.cos(t), mpmath.sin(t)] for t in angles]
    if m == 3:
        return fibonacci_lattice(sphere)
    out = []
    for signs in itertools.product(range(-reach, reach + 1), repeat=m):
        if any(signs):
            norm = mpmath.sqrt(sum(s * s for s in signs))
            out.append([s / norm for s in signs])
    return out


def quadratic_fit(f: Callable, x0: mpmath.matrix) -> list:
    """``(c, g, Q)`` per entry of ``f`` with ``f_k(x0 + d) = c + g.d + d.Q.d/2``, fitted exactly
    from the values at ``x0``, ``x0 +- e_i``, ``x0 + e_i + e_j`` and checked at ``x0 + 2 e`` (to
    half the working digits); None for an entry that is not such a quadratic.

    Parameters
    ----------
    f : callable
        ``f(x)``: an mpmath column of numbers at an mpmath column ``x``.
    x0 : mpmath.matrix
        The centre of the fit.

    Returns
    -------
    list of (mpmath.mpf, mpmath.matrix, mpmath.matrix) or None
    """
    n = len(x0)
    unit = [mpmath.matrix([1 if i == j else 0 for i in range(n)]) for j in range(n)]
    c = f(x0)
    up = [f(x0 + e) for e in unit]
    down = [f(x0 - e) for e in unit]
    pairs = {(i, j): f(x0 + unit[i] + unit[j]) for i in range(n) for j in range(i)}
    ones = mpmath.matrix([2] * n)
    far = f(x0 + ones)
    fits = []
    for k in range(len(c)):
        grad = mpmath.matrix([(u[k] - d[k]) / 2 for u, d in zip(up, down, strict=True)])
        Q = mpmath.matrix(n, n)
        for i in range(n):
            Q[i, i] = up[i][k] + down[i][k] - 2 * c[k]
            for j in range(i):
                Q[i, j] = Q[j, i] = pairs[i, j][k] - up[i][k] - up[j][k] + c[k]
        predicted = c[k] + (grad.T * ones)[0] + (ones.T * Q * ones)[0] / 2
        scale = 1 + abs(c[k]) + mpmath.norm(grad, 1) + mpmath.mnorm(Q, 1)
        exact = abs(far[k] - predicted) <= mpmath.mpf(10) ** (-mpmath.mp.dps // 2) * scale
        fits.append((c[k], grad, Q) if exact else None)
    return fits


def least_of_quadratic(c: mpmath.mpf, g: mpmath.matrix, Q: mpmath.matrix) -> tuple | None:
    """The least value of ``c + g.d + d.Q.d/2`` and where, when ``Q`` is positive definite.

    Parameters
    ----------
    c : mpmath.mpf
    g : mpmath.matrix
        Gradient (a column).
    Q : mpmath.matrix
        Hessian (symmetric).

    Returns
    -------
    (mpmath.mpf, mpmath.matrix) or None
        The least value and the offset ``d`` of its point; None when the Cholesky
        factorisation of ``Q`` fails at the working digits (not positive definite).
    """
    try:
        mpmath.cholesky(Q)
    except ValueError:
        return None
    d = -mpmath.lu_solve(Q, g)
    return c + (g.T * d)[0] / 2, d


def quadratic_certificate(c: Sequence, g: Sequence, Q: Sequence, values: Sequence) -> tuple | None:
    """Multipliers proving that ``F_i(x) = values_i`` has no real solution, or None.

    ``F_i(x0 + d) = c_i + g_i.d + d.Q_i.d/2`` (as :func:`quadratic_fit` gives them). A
    certificate is ``lambda`` with ``Q_lambda = sum lambda_i Q_i`` positive definite and the
    least value of ``sum lambda_i (F_i - values_i)`` positive (then that sum is positive
    everywhere, so the ``F_i - values_i`` never vanish together). Candidates: each sign of each
    ``e_i``, then the maximiser over ``|lambda| = 1`` of the smaller of the least value and the
    least eigenvalue of ``Q_lambda``, by Nelder-Mead (scipy, in double) from the best point of
    the lattice of that sphere; only the check decides, at the working digits (Cholesky, and
    the least value above ``10^-(digits/2)`` of the scale).

    Parameters
    ----------
    c, g, Q : sequence
        Per condition: constant, gradient (column) and Hessian at the fit's centre.
    values : sequence
        The prescribed values.

    Returns
    -------
    (list of mpmath.mpf, mpmath.mpf) or None
        ``lambda`` and the least value of the combination.
    """
    k = len(c)

    def least(lam):
        cc = sum((li * (ci - vi) for li, ci, vi in zip(lam, c, values, strict=True)), 0)
        gg = sum((li * gi for li, gi in zip(lam, g, strict=True)), mpmath.zeros(len(g[0]), 1))
        QQ = sum((li * Qi for li, Qi in zip(lam, Q, strict=True)), mpmath.zeros(len(g[0])))
        found = least_of_quadratic(cc, gg, QQ)
        return None if found is None else found[0]

    scale = 1 + max(abs(v) for v in [*c, *values])
    margin = mpmath.mpf(10) ** (-mpmath.mp.dps // 2) * scale

    def check(lam):
        lam = [mpmath.mpf(v) for v in lam]
        value = least(lam)
        return (lam, value) if value is not None and value > margin else None

    for i in range(k):
        for sign in (1, -1):
            found = check([sign * int(j == i) for j in range(k)])
            if found:
                return found
    if k < 2:
        return None
    lattice = unit_sphere_lattice(k, CERTIFICATE_CIRCLE, CERTIFICATE_SPHERE, 2)

    def objective(lam):
        """``-min(least value, least eigenvalue of Q_lambda)`` at ``lambda/|lambda|``: the
        maximiser is a certificate far from both edges (robust to rounding ``lambda``)."""
        norm = mpmath.sqrt(sum(mpmath.mpf(v) ** 2 for v in lam))
        if norm == 0:
            return mpmath.mpf(1)
        with mpmath.workdps(20):
            unit = [mpmath.mpf(v) / norm for v in lam]
            QQ = sum((li * Qi for li, Qi in zip(unit, Q, strict=True)), mpmath.zeros(len(g[0])))
            lowest = min(mpmath.eigsy(QQ, eigvals_only=True))
            value = least(unit) if lowest > 0 else None
        return -lowest if value is None else -min(value, lowest)

    best = min(lattice, key=lambda u: (objective(u), [float(v) for v in u]))
    from scipy.optimize import minimize

    refined = minimize(
        lambda v: float(objective(list(v))), [float(v) for v in best], method="Nelder-Mead"
    ).x
    norm = sum(float(v) ** 2 for v in refined) ** 0.5
    return check([float(v) / norm for v in refined]) or check(best)


def certificate_refusal(
    conditions: Callable, x0: mpmath.matrix, names: Sequence[str], target: mpmath.matrix
) -> str | None:
    """The refusal, with its proof, of values the conditions that are quadratics in the free
    scalars never take together (:func:`quadratic_certificate`); None without a verdict.

    Parameters
    ----------
    conditions : callable
        ``x -> (F_i(x))`` (an mpmath column), the integrals at the free components ``x``.
    x0 : mpmath.matrix
        The centre of the fits.
    names : sequence of str
        The integrals' names, in the column's order.
    target : mpmath.matrix
        The prescribed values.

    Returns
    -------
    str or None
        The message (one line), or None when no certificate is found.
    """
    try:
        every = quadratic_fit(conditions, x0)
    except UserInputError:
        return None  # a fit point off the state's domain
    used = [i for i, fit in enumerate(every) if fit is not None]
    fits = [every[i] for i in used]
    if not fits:
        return None
    found = quadratic_certificate(
        [f[0] for f in fits], [f[1] for f in fits], [f[2] for f in fits], [target[i] for i in used]
    )
    if found is None:
        return None
    lam, least = found
    nonzero = [i for i, v in zip(used, lam, strict=True) if v != 0]
    if len(nonzero) == 1 and names[nonzero[0]] == "H" and lam[used.index(nonzero[0])] > 0:
        k = nonzero[0]
        return (
            f"no real state with the other components as given has H = "
            f"{mpmath.nstr(target[k], 10)}: the energy is a positive-definite quadratic in the "
            f"free components, least {mpmath.nstr(least + target[k], 10)}"
        )
    terms = ", ".join(
        f"{mpmath.nstr(v, 6)} ({names[i]} - {mpmath.nstr(target[i], 10)})"
        for i, v in zip(used, lam, strict=True)
        if v != 0
    )
    return (
        f"no real state with the other components as given has "
        f"{', '.join(names)} = {', '.join(mpmath.nstr(v, 10) for v in target)}: the sum of "
        f"{terms} is a positive-definite quadratic in the free components with least value "
        f"{mpmath.nstr(least, 6)} > 0, so the values are never taken together"
    )
