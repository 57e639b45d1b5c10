"""A state of the ball on prescribed values of its first integrals (K01 §2-§4, BKM12 §1.1).

The papers give their trajectories by the values of the integrals, not by a state: the energy
``h``, the constant of areas ``C = (M, gamma)`` (K01's ``C``), ``n = (M, M)``, or the line
``M || gamma`` (``parallel``, i.e. ``n = C^2``). With the gyrostat (K01 §4) ``M`` is replaced by
``M + K`` in ``C`` and ``n``. :func:`state_from_integrals` turns such a request into a state
``(M, gamma)``, with a documented and reproducible choice where the level set is not a point,
and refuses an impossible request with the admissible range. (The other ways of choosing an
initial state, and the one entry that chooses between them, are in
:mod:`chaplygin.numerics.ball.initial_state`.)

Every energy is evaluated with the model's own generated integrals (``code.mpmath.integrals``)
at the working digits; nothing here restates the Hamiltonian.

Choice of the point (reproducible)
----------------------------------
* ``parallel`` without the gyrostat: ``M = C gamma``,
  ``s = (gamma, A gamma) = 2h/(C^2 + 2hD)``, and ``gamma`` lies in the plane of the axes of
  largest and smallest ``A_i`` (which every level set meets):
  ``gamma = (cos t) e_max + (sin t) e_min``, ``cos^2 t = (s - A_min)/(A_max - A_min)``.
  ``point = k`` (0..3) picks the signs ``(+,+), (+,-), (-,+), (-,-)`` of ``(cos t, sin t)``.
* otherwise ``gamma`` is given, or taken from a fixed grid of the sphere (a Fibonacci lattice of
  :data:`GRID` points in a fixed order); ``M + K = C gamma + u`` with ``u`` perpendicular to
  ``gamma`` and ``|u|^2 = n - C^2`` (a circle; a point when ``n = C^2``), and the energy on that
  circle is a trigonometric polynomial of degree 2 in the angle of ``u``, fitted exactly from 5
  samples; its roots are sorted by angle and polished to the working precision; ``point = k``
  picks the k-th root (over the grid points in order, the first ``gamma`` that has roots is used).
* ``parallel`` with the gyrostat: ``M = C gamma - K`` and the energy is a function on the sphere;
  the first pair of neighbouring grid points (in grid order) where it crosses ``h`` is bisected
  along their great-circle arc (``point = k``: the k-th such pair).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import mpmath
import numpy as np

from ...arith import detlinalg, detmath
from ...derive.errors import UserInputError
from ..code import ModelCode
from ..frame import horizontal_frame
from ..level_certificate import fibonacci_lattice

__all__ = [
    "ResolvedState",
    "state_from_integrals",
    "integral_name",
    "GRID",
    "INTEGRAL_KEYS",
]

#: Points of the Fibonacci lattice on the sphere that candidate ``gamma`` are taken from.
GRID = 400

#: Keys of a request by integrals.
INTEGRAL_KEYS = ("h", "C", "n", "parallel")


@dataclass
class ResolvedState:
    """A state resolved from integrals.

    Attributes
    ----------
    values : dict of str to list of mpmath.mpf
        State groups (``M``, ``gamma``) at the working digits.
    how : str
        How the point was chosen (for the summary).
    prescribed : dict of str to mpmath.mpf
        The integral values asked for, by the model's integral name.
    """

    values: dict[str, list]
    how: str
    prescribed: dict[str, object] = field(default_factory=dict)


def integral_name(code: ModelCode, key: str) -> str:
    """The model's name of the integral a request key stands for (``"C"`` -> ``"(M,gamma)"``,
    or ``"(M+K,gamma)"`` with the gyrostat).

    Parameters
    ----------
    code : ModelCode
    key : {"h", "C", "n"}

    Returns
    -------
    str

    Raises
    ------
    UserInputError
        The model has no such integral.
    """
    names = code.integral_names
    gyro = "(M+K,gamma)" in names
    wanted = {
        "h": "H",
        "C": "(M+K,gamma)" if gyro else "(M,gamma)",
        "n": "(M+K,M+K)" if gyro else "(M,M)",
    }[key]
    if wanted not in names:
        raise UserInputError(
            f"{code.name} has no first integral {wanted} (needed by initial.{key}); "
            f"its integrals: {', '.join(names)}"
        )
    return wanted


def _energy_fn(code: ModelCode, params: Sequence, dps: int):
    """``H(M, gamma)`` from the generated integrals (other state groups set to a frame)."""
    hi = code.integral_names.index("H")
    groups = code.state_groups

    def energy(M, gamma):
        values = {"M": M, "gamma": gamma}
        y = []
        for name, comps in groups.items():
            y.extend(values.get(name, [mpmath.mpf(0)] * len(comps)))
        order = [s for comps in groups.values() for s in comps]
        y = [y[order.index(s)] for s in code.state]
        return code.mpmath.integrals(mpmath.mpf(0), y, list(params))[hi]

    return energy


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b, strict=True))


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _unit(v):
    n = mpmath.sqrt(_dot(v, v))
    return [x / n for x in v]


def _trig_roots(f, level, k_max: int = 8) -> list:
    """Roots in [0, 2 pi) of ``f(phi) = level`` where ``f`` is a trig polynomial of degree 2."""
    N = 5
    samples = [f(2 * mpmath.pi * j / N) - level for j in range(N)]
    c = [
        sum(samples[j] * mpmath.expj(-2 * mpmath.pi * j * m / N) for j in range(N)) / N
        for m in range(-2, 3)
    ]  # f - level = sum_m c_m e^{i m phi}, m = -2..2
    coeffs = [complex(v) for v in reversed(c)]  # z^2 (f - level) as a polynomial in z
    scale = max(abs(v) for v in coeffs)
    if scale == 0:
        return []
    while coeffs and abs(coeffs[0]) <= 1e-14 * scale:
        coeffs = coeffs[1:]
    roots = np.roots(coeffs) if len(coeffs) > 1 else []
    out = []
    for z in roots:
        if abs(abs(z) - 1) > 1e-6:
            continue
        phi = mpmath.mpf(float(np.angle(z)) % (2 * np.pi))
        try:
            phi = mpmath.findroot(lambda x: f(x) - level, phi)
        except (ValueError, ZeroDivisionError):
            pass
        out.append(mpmath.mpf(phi) % (2 * mpmath.pi))
    out.sort()
    unique = []
    for phi in out:
        if not unique or abs(phi - unique[-1]) > mpmath.mpf(10) ** (-mpmath.mp.dps // 2):
            unique.append(phi)
    return unique


def _range_msg(lo, hi) -> str:
    return f"[{mpmath.nstr(mpmath.mpf(lo), 10)}, {mpmath.nstr(mpmath.mpf(hi), 10)}]"


def state_from_integrals(
    code: ModelCode,
    params: Mapping[str, Sequence],
    request: Mapping[str, object],
    dps: int,
) -> ResolvedState:
    """A state ``(M, gamma)`` on prescribed values of the integrals.

    Parameters
    ----------
    code : ModelCode
        The model (its generated integrals give the energy).
    params : mapping
        Parameter vector by symbol name (``I1, I2, I3, D, ...``), already numbers.
    request : mapping
        ``h``, ``C``, ``n``, ``parallel`` (bool), ``point`` (int, default 0) and optionally
        ``gamma`` (a unit vector: the level set is then searched at this ``gamma`` only).
    dps : int
        Working decimal digits of the resolution.

    Returns
    -------
    ResolvedState

    Raises
    ------
    UserInputError
        An under- or over-determined request, or values outside the admissible range (the
        message gives the range).
    """
    with mpmath.workdps(dps + 10):
        return _state_on_level(code, params, request)


def _state_on_level(code, params, request) -> ResolvedState:
    p = [mpmath.mpf(params[s]) for s in code.params]
    if "H" not in code.integral_names:
        raise UserInputError(
            f"{code.name} has no energy integral: give the initial state by its components"
        )
    energy = _energy_fn(code, p, mpmath.mp.dps)
    h = request.get("h")
    C = request.get("C")
    n = request.get("n")
    parallel = bool(request.get("parallel", False))
    point = int(request.get("point", 0))
    gamma = request.get("gamma")
    if h is None or C is None:
        raise UserInputError(
            "an initial state by integrals needs at least initial.h (energy) and initial.C "
            "((M, gamma)), and either initial.n ((M, M)) or parallel = true"
        )
    if parallel and n is not None:
        raise UserInputError("give initial.n or parallel = true, not both (parallel means n = C^2)")
    if not parallel and n is None:
        raise UserInputError(
            "initial.n ((M, M)) is missing; give it, or parallel = true for M || gamma (n = C^2)"
        )
    if point < 0:
        raise UserInputError(f"initial.point must be 0 or more, got {point}")
    h, C = mpmath.mpf(h), mpmath.mpf(C)
    K = [p[code.params.index(f"K{i}")] for i in (1, 2, 3)] if "K1" in code.params else None
    prescribed = {integral_name(code, "h"): h, integral_name(code, "C"): C}
    if parallel:
        n = C * C
    else:
        n = mpmath.mpf(n)
        prescribed[integral_name(code, "n")] = n
        if n < C * C:
            raise UserInputError(
                f"n = (M, M) = {mpmath.nstr(n, 10)} is below C^2 = {mpmath.nstr(C * C, 10)}; "
                f"admissible: n >= C^2 (|(M, gamma)| <= |M|)"
            )
    if gamma is not None:
        gamma = _unit([mpmath.mpf(v) for v in gamma])
    if parallel and K is None and gamma is None:
        return _parallel_ball(code, p, h, C, point, prescribed)
    Kv = K or [mpmath.mpf(0)] * 3
    r = mpmath.sqrt(n - C * C)

    def momentum(g, phi):
        e1, e2 = horizontal_frame(g)
        u = [r * (mpmath.cos(phi) * a + mpmath.sin(phi) * b) for a, b in zip(e1, e2, strict=True)]
        return [C * gi + ui - ki for gi, ui, ki in zip(g, u, Kv, strict=True)]

    candidates = [gamma] if gamma is not None else fibonacci_lattice(GRID)
    if r == 0:  # a point per gamma: M + K = C gamma; energy is a function on the sphere
        values = [energy(momentum(g, 0), g) - h for g in candidates]
        if gamma is not None:
            if abs(values[0]) > mpmath.mpf(10) ** (-mpmath.mp.dps // 2) * (1 + abs(h)):
                raise UserInputError(
                    "with parallel = true and a given gamma the energy is fixed: "
                    f"h = {mpmath.nstr(values[0] + h, 15)}, not {mpmath.nstr(h, 15)}"
                )
            return ResolvedState(
                {"M": momentum(gamma, 0), "gamma": gamma}, "M + K = C gamma", prescribed
            )
        crossings = _grid_crossings(candidates, values)
        if point >= len(crossings):
            lo, hi = min(values) + h, max(values) + h
            raise _no_point(h, lo, hi, point, len(crossings), "parallel")
        a, b = crossings[point]
        g = _bisect_arc(lambda g: energy(momentum(g, 0), g) - h, candidates[a], candidates[b])
        how = (
            f"M + K = C gamma; gamma on the arc between Fibonacci grid points {a} and {b} "
            f"(of {GRID}) where the energy crosses h (crossing {point})"
        )
        return ResolvedState({"M": momentum(g, 0), "gamma": g}, how, prescribed)
    # a double-precision pre-scan of every circle (16 angles): its range decides which
    # candidates can have roots (with a margin of 10 % of the circle's span), and the range
    # reported when none has
    ranges = _circle_ranges(code, p, C, r, Kv, candidates)
    lo, hi = float(ranges[:, 0].min()), float(ranges[:, 1].max())
    seen = 0
    for idx, g in enumerate(candidates):
        a, b = ranges[idx]
        if not a - 0.1 * (b - a) - 1e-12 <= float(h) <= b + 0.1 * (b - a) + 1e-12:
            continue
        f = lambda phi, g=g: energy(momentum(g, phi), g)  # noqa: E731
        roots = _trig_roots(f, h)
        if seen + len(roots) > point:
            phi = roots[point - seen]
            where = "the given gamma" if gamma is not None else f"Fibonacci grid point {idx}"
            how = (
                f"gamma = {where}; M + K = C gamma + u, u perpendicular to gamma, |u|^2 = n - C^2,"
                f" at angle {mpmath.nstr(phi, 12)} (root {point - seen} of "
                f"{len(roots)} sorted by angle)"
            )
            return ResolvedState({"M": momentum(g, phi), "gamma": g}, how, prescribed)
        seen += len(roots)
    raise _no_point(h, lo, hi, point, seen, "n")


def _circle_ranges(code: ModelCode, p, C, r, K, candidates) -> np.ndarray:
    """(min, max) of the energy over 16 angles of each candidate's circle, in double."""
    g = np.array([[float(c) for c in v] for v in candidates])  # (G, 3)
    k = np.argmin(np.abs(g) + np.arange(3) * 1e-15, axis=1)  # same rule as horizontal_frame
    e = np.eye(3)[k]
    e1 = e - np.sum(e * g, axis=1)[:, None] * g
    e1 /= np.sqrt(np.sum(e1 * e1, axis=1))[:, None]
    e2 = np.cross(g, e1)
    phi = 2 * np.pi * np.arange(16) / 16
    u = float(r) * (
        detmath.cos(phi)[None, :, None] * e1[:, None, :]
        + detmath.sin(phi)[None, :, None] * e2[:, None, :]
    )
    M = float(C) * g[:, None, :] + u - np.array([float(v) for v in K])[None, None, :]
    gam = np.broadcast_to(g[:, None, :], M.shape)
    values = {"M": M.reshape(-1, 3).T, "gamma": gam.reshape(-1, 3).T}
    n = M.shape[0] * M.shape[1]
    rows = {}
    for name, comps in code.state_groups.items():
        block = values.get(name, np.zeros((len(comps), n)))
        rows.update(zip(comps, block, strict=True))
    y = np.array([rows[s] for s in code.state])
    H = np.asarray(
        code.numpy.integrals(np.zeros(n), y, np.array([float(v) for v in p]))[
            code.integral_names.index("H")
        ],
        float,
    ).reshape(M.shape[0], M.shape[1])
    return np.stack([H.min(axis=1), H.max(axis=1)], axis=1)


def _no_point(h, lo, hi, point, found, case) -> UserInputError:
    if found and point >= found:
        return UserInputError(
            f"initial.point = {point} but this level set has only {found} point(s) to choose "
            f"from; use 0..{found - 1}"
        )
    where = "on M || gamma" if case == "parallel" else "for these C and n"
    return UserInputError(
        f"no state has energy h = {mpmath.nstr(h, 10)} {where}: the energy ranges over about "
        f"{_range_msg(lo, hi)} (sampled)"
    )


def _grid_crossings(points, values) -> list[tuple[int, int]]:
    """Pairs (i, j), i < j, of nearest-neighbour grid points where ``values`` changes sign."""
    arr = np.array([[float(c) for c in g] for g in points])
    out = []
    for i in range(len(points)):
        d = detlinalg.matmul(arr, arr[i])
        near = np.argsort(-d)[1:7]
        for j in sorted(int(j) for j in near):
            if j > i and (values[i] > 0) != (values[j] > 0):
                out.append((i, j))
    return out


def _bisect_arc(f, a, b):
    def point(s):
        return _unit([(1 - s) * x + s * y for x, y in zip(a, b, strict=True)])

    s = mpmath.findroot(lambda s: f(point(s)), (mpmath.mpf(0), mpmath.mpf(1)), solver="anderson")
    return point(s)


def _parallel_ball(code, p, h, C, point, prescribed) -> ResolvedState:
    Ii = [p[code.params.index(f"I{i}")] for i in (1, 2, 3)]
    D = p[code.params.index("D")]
    A = [1 / (v + D) for v in Ii]
    h_at = [C * C * a / (2 * (1 - D * a)) for a in A]  # = C^2/(2 I_i): rotation about axis i
    lo, hi = min(h_at), max(h_at)
    if C == 0:
        raise UserInputError("parallel = true with C = 0 is the state of rest (M = 0): h = 0 only")
    slack = mpmath.mpf(10) ** (10 - mpmath.mp.dps) * hi  # rounding of the ends themselves
    if not lo - slack <= h <= hi + slack:
        raise UserInputError(
            f"no state on M || gamma has energy h = {mpmath.nstr(h, 10)} at C = "
            f"{mpmath.nstr(C, 10)}: admissible h in [h3, h1] = {_range_msg(lo, hi)} "
            f"(h_i = C^2/(2 I_i))"
        )
    if point > 3:
        raise UserInputError(f"initial.point on M || gamma is 0..3 (the sign choices), got {point}")
    s = 2 * h / (C * C + 2 * h * D)
    imax = max(range(3), key=lambda i: (A[i], -i))
    imin = min(range(3), key=lambda i: (A[i], i))
    if A[imax] == A[imin]:
        c2 = mpmath.mpf(1)
    else:
        c2 = (s - A[imin]) / (A[imax] - A[imin])
    c2 = min(max(c2, mpmath.mpf(0)), mpmath.mpf(1))
    c, sn = mpmath.sqrt(c2), mpmath.sqrt(1 - c2)
    c = -c if point in (2, 3) else c
    sn = -sn if point in (1, 3) else sn
    g = [mpmath.mpf(0)] * 3
    g[imax] += c
    g[imin] += sn
    how = (
        f"M = C gamma, gamma in the plane of body axes {imax + 1} (largest A_i) and {imin + 1} "
        f"(smallest A_i), (gamma, A gamma) = 2h/(C^2 + 2hD); signs of point {point}"
    )
    return ResolvedState({"M": [C * v for v in g], "gamma": g}, how, prescribed)
