"""Numbers behind the bifurcation diagrams: the derived curves evaluated, the stability of
each family (Floquet multipliers) and seeded samples of integrated states on the levels.

The curves are the derived ones (:mod:`chaplygin.derive.bifurcation`, proved in
``verify/claims/bifurcation.py``); the stability comes from :mod:`.stability` at a sample
point of each family; random seeded initial states are integrated for a short time and
their integral values mark the region of motion (BKM12-Fig2region). Drawing them is
:mod:`chaplygin.verify.plots`'s part.

References
----------
K01-Fig1, K01-Fig2, K01-Fig3, BKM12-24, BKM12-Fig3, BKM12-2.7c, BKM12-1.5stab8.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache, lru_cache

import numpy as np
import sympy as sp

from ...arith import detlinalg, detmath
from ...derive.bifurcation import bifurcation_curve
from ...derive.emit import emit_function
from ...derive.systems import build_model
from ..code import load_model_code
from ..integrate import integrate
from .stability import (
    euler_floquet,
    floquet,
    steady_rotation_floquet,
    support_steady_state,
)

__all__ = [
    "CriticalTrace",
    "critical_trace",
    "LevelSetComponents",
    "level_set_components",
    "sigma",
    "family_stability",
    "euler_stability",
    "support_stability",
    "ball_energy",
    "sample_levels",
    "support_sample",
]


@cache
def _sigma_functions():
    """Derived ``E = Sigma_i(C, M_gamma)`` of the ball as numpy functions of (C, M_gamma, I1, I2,
    I3, D) (:func:`~chaplygin.derive.emit.emit_function`)."""
    model = build_model("chaplygin_ball", ())
    C, Mg = sp.Symbol("C", real=True), sp.Symbol("M_gamma", real=True)
    args = [C, Mg, *model.params]
    return [
        emit_function(args, bifurcation_curve(model, i), name=f"sigma{i + 1}") for i in range(3)
    ]


def sigma(
    i: int, C: float | np.ndarray, Mg: float | np.ndarray, I: Sequence[float], D: float
) -> float | np.ndarray:
    """Energy ``E = 2h`` on the derived curve ``Sigma_i`` (BKM12-Sigma_i, K01-3.2c).

    Parameters
    ----------
    i : int
        The family, 0, 1 or 2 (steady rotations about ``e_1``, ``e_2``, ``e_3``).
    C, Mg : float or numpy.ndarray
        ``(M, M)`` and ``(M, gamma)`` (arrays broadcast).
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.

    Returns
    -------
    float or numpy.ndarray
        ``E`` on the curve, shaped like the broadcast of ``C`` and ``Mg``.

    References
    ----------
    BKM12-Sigma_i, K01-3.2c (FORMULAS.md).
    """
    return _sigma_functions()[i](C, Mg, *I, D)


def family_stability(
    I: Sequence[float], D: float, C: float = 1.0, Mg: float = 0.0
) -> list[tuple[bool, float]]:
    """Stability of the steady rotations about ``e_1``, ``e_2``, ``e_3`` of the ball.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    C, Mg : float
        ``(M, M)`` and ``(M, gamma)`` of the sample point of each family.

    Returns
    -------
    list of (bool, float)
        ``(stable, max |multiplier|)`` per axis.
    """
    return [(r.stable, r.max_abs) for r in steady_rotation_floquet(tuple(I), D, C, Mg)]


def euler_stability(I: Sequence[float], D: float, Ep: float) -> tuple[bool, float]:
    """Stability of the orbit ``M = sqrt(C) gamma`` at ``E' = E D/C`` (``Sigma_4``).

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    Ep : float
        ``E' = E D/C``.

    Returns
    -------
    (bool, float)
        ``(stable, max |multiplier|)``.
    """
    r = euler_floquet(tuple(I), D, Ep)
    return r.stable, r.max_abs


@lru_cache(maxsize=16)
def support_stability(params: tuple[float, ...]) -> list[tuple[bool, float]]:
    """Stability of the spherical support's steady rotations, in a generic frame.

    Parameters
    ----------
    params : tuple of 6 floats
        ``(I1, I2, I3, D_iso, D_al, D_be)``.

    Returns
    -------
    list of (bool, float)
        ``(stable, max |multiplier|)`` per axis.
    """
    c, s = detmath.cos(0.7), detmath.sin(0.7)
    R1 = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    R2 = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    frame = detlinalg.matmul(R1, R2)
    out = []
    for i in range(3):
        y0, T = support_steady_state(params, i, 1.0, frame)
        r = floquet(None, None, y0, T, system="spherical_support", params=params)
        out.append((r.stable, r.max_abs))
    return out


def _random_unit(rng, n):
    return detlinalg.unit_vectors(rng, n, 3)


@cache
def _ball_code():
    return load_model_code("chaplygin_ball")


def ball_energy(y: np.ndarray, I: Sequence[float], D: float) -> float:
    """``E = (M, omega) = 2 h`` of a ball state ``(M, gamma)`` (generated integrals).

    Parameters
    ----------
    y : numpy.ndarray, shape (6,)
        ``M, gamma``.
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.

    Returns
    -------
    float
        ``E``, twice the energy integral ``H`` of the generated code.
    """
    return 2 * float(_ball_code().numpy.integrals(0.0, y, [*I, D])[0])


def sample_levels(
    I: Sequence[float],
    D: float,
    n: int,
    seed: int,
    C_range: tuple[float, float] = (0.05, 1.0),
    Mg: float | None = None,
    g: float | None = None,
    t_end: float = 2.0,
) -> tuple[np.ndarray, float, np.ndarray]:
    """Random seeded ball states, integrated to ``t_end``: their ``(C, M_gamma, E)``.

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    n : int
        Number of states.
    seed : int
        Seed of :func:`numpy.random.default_rng`.
    C_range : (float, float)
        ``C = (M, M)`` is drawn uniformly in this range.
    Mg : float, optional
        Fixes ``(M, gamma)``.
    g : float, optional
        Fixes ``M_gamma/sqrt(C)`` (normalised diagram); without ``Mg`` or ``g`` it is random.
    t_end : float
        Integration time (DOP853, ``rtol = 1e-10``).

    Returns
    -------
    values : numpy.ndarray, shape (n, 3)
        ``(C, M_gamma, E)`` at ``t_end``.
    drift : float
        Largest relative drift of the integrals.
    states : numpy.ndarray, shape (n, 6)
        The final states.
    """
    rng = np.random.default_rng(seed)
    gam = _random_unit(rng, n)
    out, drift, states = [], 0.0, []
    for k in range(n):
        C = rng.uniform(*C_range)
        perp = detlinalg.unit_vectors(rng, 1, 3)[0]
        perp -= detlinalg.dot(perp, gam[k]) * gam[k]
        perp /= detlinalg.norm(perp)
        if Mg is not None:
            mg = Mg
        elif g is not None:
            mg = g * np.sqrt(C)
        else:
            mg = rng.uniform(-1, 1) * np.sqrt(C)
        M = mg * gam[k] + np.sqrt(max(C - mg**2, 0.0)) * perp
        r = integrate(
            "chaplygin_ball",
            {"M": tuple(M), "gamma": tuple(gam[k])},
            t_end,
            {"I": tuple(I), "D": D},
            rtol=1e-10,
            atol=1e-12,
        )
        y = r.y[:, -1]
        Mv, gv = y[:3], y[3:]
        out.append((detlinalg.dot(Mv, Mv), detlinalg.dot(Mv, gv), ball_energy(y, I, D)))
        states.append(y)
        drift = max(drift, max(r.drift.values()))
    return np.array(out), drift, np.array(states)


def support_sample(
    params: Sequence[float], n: int, seed: int, t_end: float = 1.0
) -> tuple[np.ndarray, float]:
    """Random support states integrated to ``t_end``: ``(g_al, g_be, position)``.

    ``position`` is ``(E' - min_i E'_i)/(max_i E'_i - min_i E'_i)`` with ``E'_i`` the
    surfaces of BKM12-2.7c at the state's ``g``: in ``[0, 1]`` inside the region of motion.

    Parameters
    ----------
    params : sequence of 6 floats
        ``(I1, I2, I3, D_iso, D_al, D_be)``.
    n : int
        Number of states.
    seed : int
        Seed of :func:`numpy.random.default_rng`.
    t_end : float
        Integration time.

    Returns
    -------
    values : numpy.ndarray, shape (n, 3)
        ``(g_al, g_be, position)``.
    drift : float
        Largest relative drift of the integrals.

    References
    ----------
    BKM12-2.7c (FORMULAS.md).
    """
    rng = np.random.default_rng(seed)
    code = load_model_code("spherical_support")
    I, D_iso, D_al, D_be = params[:3], params[3], params[4], params[5]
    J = np.asarray(I, float) + D_iso
    out, drift = [], 0.0
    for _ in range(n):
        q = detlinalg.unit_vectors(rng, 1, 4)[0]
        w, x, y, z = q
        R = np.array(
            [
                [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
            ]
        )
        M = 2.0 * rng.random(3) - 1.0
        y0 = {"M": tuple(M), "alpha": tuple(R[0]), "beta": tuple(R[1]), "gamma": tuple(R[2])}
        p = {"I": tuple(I), "D_iso": D_iso, "D_al": D_al, "D_be": D_be}
        r = integrate("spherical_support", y0, t_end, p, rtol=1e-10, atol=1e-12)
        yv = r.y[:, -1]
        Mv, al, be, ga = yv[:3], yv[3:6], yv[6:9], yv[9:12]
        C = detlinalg.dot(Mv, Mv)
        gx = np.array([detlinalg.dot(Mv, v) for v in (al, be, ga)]) / np.sqrt(C)
        E = 2 * float(code.numpy.integrals(0.0, yv, [*I, D_iso, D_al, D_be])[0])
        surf = [
            gx[0] ** 2 / (J[i] - D_al) + gx[1] ** 2 / (J[i] - D_be) + gx[2] ** 2 / J[i]
            for i in range(3)
        ]
        lo, hi = min(surf), max(surf)
        out.append((gx[0], gx[1], (E / C - lo) / (hi - lo)))
        drift = max(drift, max(r.drift.values()))
    return np.array(out), drift


# ---------------------------------------------------------------- the bifurcation complex
@dataclass
class LevelSetComponents:
    """The connected components of a common level set of the ball's integrals.

    Attributes
    ----------
    count : int
        Number of components.
    sizes : list of int
        Sample points per component, largest first.
    mean_M : ndarray, shape (count, 3)
        Mean of ``M/sqrt(C)`` over each component (same order): a component that shrinks onto
        a steady rotation ``M = +-sqrt(C) e_i`` has its mean along ``+-e_i``.
    separation : float
        Least distance between points of different components (inf for one component), in
        ``(M/sqrt(C), gamma)``.
    radius : float
        Points closer than this are joined.
    points : int
        Sample points on the level set.
    """

    count: int
    sizes: list
    mean_M: np.ndarray
    separation: float
    radius: float
    points: int


def _fibonacci_sphere(n: int) -> np.ndarray:
    k = np.arange(n) + 0.5
    z = 1 - 2 * k / n
    r = np.sqrt(1 - z * z)
    phi = np.pi * (1 + 5**0.5) * k
    return np.stack([r * detmath.cos(phi), r * detmath.sin(phi), z], axis=1)


@dataclass(frozen=True)
class _EnergyGrid:
    """``2 H = (M, omega)`` sampled on the circles of ``M`` over a Fibonacci grid of
    ``gamma`` (:func:`level_set_components`), the same for every level ``E``."""

    G: np.ndarray
    a: np.ndarray
    b: np.ndarray
    t: np.ndarray
    Mg: float
    s: float
    energy: np.ndarray

    def momentum(self, rows: np.ndarray, angles: np.ndarray) -> np.ndarray:
        G, a, b = self.G, self.a, self.b
        return self.Mg * G[rows] + self.s * (
            detmath.cos(angles)[..., None] * a[rows] + detmath.sin(angles)[..., None] * b[rows]
        )


@lru_cache(maxsize=2)
def _energy_grid(p: tuple, C: float, Mg: float, n_gamma: int, n_theta: int) -> _EnergyGrid:
    """The energy on the sampling grid of the level sets at ``(C, M_gamma)`` (kept for the
    next levels ``E`` of the same point: the claims ask for three; read-only arrays)."""
    G = _fibonacci_sphere(n_gamma)
    e = np.eye(3)[np.argmin(np.abs(G), axis=1)]
    a = np.cross(G, e)
    a /= np.sqrt(a[:, 0] * a[:, 0] + a[:, 1] * a[:, 1] + a[:, 2] * a[:, 2])[:, None]
    b = np.cross(G, a)
    t = np.linspace(0, 2 * np.pi, n_theta, endpoint=False)
    grid = _EnergyGrid(G, a, b, t, Mg, float(np.sqrt(C - Mg * Mg)), np.empty(0))
    M = grid.momentum(np.arange(len(G))[:, None], t[None, :])
    Y = np.concatenate([M, np.broadcast_to(G[:, None, :], M.shape)], axis=2).reshape(-1, 6).T
    energy = 2 * np.asarray(_ball_code().numpy.integrals(0.0, Y, list(p)))[0].reshape(M.shape[:2])
    for x in (G, a, b, t, energy):
        x.flags.writeable = False
    return dataclasses.replace(grid, energy=energy)


def level_set_components(
    I: Sequence[float],
    D: float,
    E: float,
    C: float = 1.0,
    Mg: float = 0.0,
    n_gamma: int = 6000,
    n_theta: int = 360,
    radius: float = 0.3,
) -> LevelSetComponents:
    """Connected components of ``{(gamma, gamma) = 1, (M, gamma) = M_gamma, (M, M) = C,
    (M, omega) = E}`` (a union of Liouville tori, or a critical level): the leaves of the
    bifurcation complex over the point ``(C, M_gamma, E)`` of the diagram.

    The level set is sampled: ``gamma`` on a Fibonacci grid of the sphere; for each,
    ``M = M_gamma gamma + sqrt(C - M_gamma^2)(cos t a + sin t b)`` (``a, b`` normal to
    ``gamma``), and the energy on that circle (the generated integral) crosses ``E`` where a
    grid in ``t`` changes sign (linear interpolation). Points closer than ``radius`` in
    ``(M/sqrt(C), gamma)`` are joined; the components of that graph are counted (SciPy's
    ``connected_components``). The result is trustworthy when ``separation`` is well above
    ``radius`` and ``radius`` well above the sampling's spacing (about ``4/sqrt(n_gamma)``).

    Parameters
    ----------
    I : sequence of 3 floats
        Moments of inertia.
    D : float
        ``D = m b^2``.
    E : float
        ``2 H = (M, omega)``.
    C, Mg : float
        ``(M, M)`` and ``(M, gamma)``, ``Mg**2 < C``.
    n_gamma, n_theta : int
        Grid sizes on the sphere and on each circle.
    radius : float
        Joining distance.

    Returns
    -------
    LevelSetComponents

    Raises
    ------
    UserInputError
        Bad inertia, ``C <= 0`` or ``Mg**2 >= C``, or an empty level set.

    References
    ----------
    BKM12 §1.5, Figs. 2(b), 3(b) (BKM12-Fig2b, BKM12-Fig3b).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    from ...derive.errors import UserInputError
    from ..arguments import check_inertia_vector

    I, D = check_inertia_vector(I, D, double=True)
    if not (C > 0 and Mg * Mg < C):
        raise UserInputError(f"need C > 0 and M_gamma^2 < C, got C={C}, M_gamma={Mg}")
    grid = _energy_grid(tuple(float(v) for v in (*I, D)), float(C), float(Mg), int(n_gamma),
                        int(n_theta))  # fmt: skip
    G, t, momentum = grid.G, grid.t, grid.momentum
    f = grid.energy - E
    f_next = np.roll(f, -1, axis=1)
    i, j = np.nonzero(np.sign(f) != np.sign(f_next))
    if not len(i):
        raise UserInputError(f"the level E = {E} is empty at C = {C}, M_gamma = {Mg}")
    angle = t[j] + f[i, j] / (f[i, j] - f_next[i, j]) * (2 * np.pi / len(t))
    X = np.hstack([momentum(i, angle) / np.sqrt(C), G[i]])
    tree = cKDTree(X)
    pairs = tree.query_pairs(radius, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(X), len(X)))
    count, label = connected_components(graph, directed=False)
    sizes = np.bincount(label)
    order = np.argsort(sizes, kind="stable")[::-1]
    separation = np.inf
    for k in order[1:]:
        others = label != k
        d = cKDTree(X[others]).query(X[label == k])[0]
        separation = min(separation, float(d.min()))
    return LevelSetComponents(
        count=int(count),
        sizes=[int(sizes[k]) for k in order],
        mean_M=np.array([X[label == k, :3].mean(axis=0) for k in order]),
        separation=separation,
        radius=float(radius),
        points=len(X),
    )


# ------------------------------------------------------------ traces of critical solutions
@dataclass
class CriticalTrace:
    """The contact point's trace on the plane along a critical solution.

    Attributes
    ----------
    t : ndarray, shape (n,)
    x, y : ndarray, shape (n,)
        The trace (radius ``b``).
    speed : float
        Mean speed ``|trace(t_end) - trace(0)|/t_end``.
    deviation : float
        Largest distance of the trace from the straight line through its ends.
    omega0 : ndarray, shape (3,)
        ``omega`` at ``t = 0`` (body frame).
    gamma0 : ndarray, shape (3,)
    drift : float
        Largest relative drift of the integrals.
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    speed: float
    deviation: float
    omega0: np.ndarray
    gamma0: np.ndarray
    drift: float


def critical_trace(
    y0: Sequence[float],
    I: Sequence[float],
    D: float,
    b: float,
    t_end: float,
    rtol: float = 1e-12,
    points: int = 2001,
) -> CriticalTrace:
    """Integrate the ball with the contact point from ``y0 = (M, gamma)`` and measure its trace:
    its mean speed and its largest distance from the straight line through its ends.

    Parameters
    ----------
    y0 : sequence of 6 floats
        ``M, gamma`` (a critical solution: :func:`~chaplygin.numerics.ball.stability.critical_state`
        or :func:`~chaplygin.numerics.ball.stability.euler_state`).
    I : sequence of 3 floats
    D, b : float
        ``D = m b^2`` and the radius ``b``.
    t_end : float
    rtol : float
        DOP853 tolerance (``atol = rtol/100``).
    points : int
        Output points.

    Returns
    -------
    CriticalTrace

    References
    ----------
    BKM12-25, BKM12-crit (FORMULAS.md): uniform rolling along a straight line.
    """
    y0 = np.asarray(y0, dtype=float)
    t_eval = np.linspace(0.0, float(t_end), int(points))
    start = {"M": tuple(y0[:3]), "gamma": tuple(y0[3:])}
    g = y0[3:] / detlinalg.norm(y0[3:])
    if detlinalg.norm(np.cross(y0[:3], g)) <= 1e-12 * max(detlinalg.norm(y0[:3]), 1.0):
        # M || gamma (Sigma_4, Sigma_5): BKM12-7's frame is undefined; the body axis least
        # aligned with gamma, projected, as the scenes do
        e = np.eye(3)[int(np.argmin(np.abs(g)))]
        alpha = e - detlinalg.dot(e, g) * g
        alpha /= detlinalg.norm(alpha)
        start.update(alpha=tuple(alpha), beta=tuple(np.cross(g, alpha)))
    r = integrate(
        "chaplygin_ball",
        start,
        float(t_end),
        {"I": tuple(I), "D": D, "b": b},
        effects=("contact_point",),
        rtol=rtol,
        atol=rtol / 100,
        t_eval=t_eval,
    )
    x, y = r.y[r.state_names.index("x")], r.y[r.state_names.index("y")]
    chord = np.array([x[-1] - x[0], y[-1] - y[0]])
    length = detlinalg.norm(chord)
    normal = np.array([-chord[1], chord[0]]) / max(length, np.finfo(float).tiny)
    deviation = float(np.max(np.abs((x - x[0]) * normal[0] + (y - y[0]) * normal[1])))
    code = _ball_code()
    aux = np.asarray(code.numpy.aux(0.0, y0, [*I, D]), dtype=float)
    omega0 = np.array([aux[code.aux_names.index(f"omega{i}")] for i in (1, 2, 3)])
    return CriticalTrace(
        t=np.asarray(r.t, dtype=float), x=np.asarray(x, float), y=np.asarray(y, float),
        speed=length / float(t_end), deviation=deviation, omega0=omega0, gamma0=y0[3:].copy(),
        drift=float(max(r.drift.values())),
    )  # fmt: skip
