"""Chaplygin's transformation applied to integrated trajectories (BKM12 §1.3-1.4, K01 §2.3).

A trajectory of the ball ``(A, D)`` with ``(M, gamma) != 0`` is mapped point by point with
constant coefficients (computed from the integrals of its initial state):
``M~ = m1 M + m2 gamma``, ``gamma~ = c1 M + c2 gamma``. In the original time ``t`` the images
obey ``M~' = mu^-1 M~ x omega~`` (BKM12-19, ``mu = m1 + c1 Z~``), so they are a trajectory
of the ball ``(A, D~)`` in the new time ``s`` with ``ds/dt = 1/mu``. :func:`transformation_test`
integrates the original ball, maps it, computes ``s(t)`` by Gauss–Legendre quadrature of
``1/mu`` over the output, integrates the transformed ball independently from the mapped
initial state (where ``(M~, gamma~) = 0``) and reports the largest difference.

The coefficients are the derived expressions of :mod:`chaplygin.derive.transformation`
turned into numpy functions.

References
----------
BKM12-19, BKM12-22, BKM12-23, K01-2.29 ... K01-2.33.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp

from ...arith import detlinalg
from ...derive.emit import emit_function
from ...derive.errors import UserInputError
from ...derive.phase_space import random_orthonormal
from ...derive.transformation import chaplygin_map, kilin_map, proposition2
from ..arguments import check_choice, check_count, check_inertia_vector, check_real, check_vector
from ..integrate import integrate

#: Most Gauss-Legendre panels :func:`transformation_test` lays on ``[0, t_end]``.
MAX_PANELS = 10**6

__all__ = [
    "MapCoefficients",
    "chaplygin_coefficients",
    "kilin_coefficients",
    "map_state",
    "mu_of_mapped",
    "TransformationReport",
    "transformation_test",
    "support_coefficients",
    "random_support_state",
]


@dataclass(frozen=True)
class MapCoefficients:
    """``M~ = m1 M + m2 gamma``, ``gamma~ = c1 M + c2 gamma`` and the new ``D~``, ``E~``."""

    m1: float
    m2: float
    c1: float
    c2: float
    Dt: float
    Et: float
    f: float
    form: str

    @property
    def matrix(self) -> np.ndarray:
        return np.array([[self.m1, self.m2], [self.c1, self.c2]])


@lru_cache(maxsize=1)
def _chaplygin_funcs():
    cm = chaplygin_map()
    s = cm.symbols
    args = [s["E"], s["D"], s["C"], s["Mg"]]
    f_fun = emit_function(args, cm.roots[0], name="chaplygin_f")
    rest = emit_function(
        args + [s["f"]],
        [cm.m1, cm.m2, cm.c1, cm.c2, cm.Dt_inv, cm.Et],
        name="chaplygin_coefficients",
    )
    return f_fun, rest


@lru_cache(maxsize=1)
def _kilin_funcs():
    km = kilin_map()
    s = km.symbols
    args = [s["n"], s["C"], s["h"], s["D"], s["f"]]
    inv = km.inverse
    outputs = [inv[0, 0], inv[0, 1], inv[1, 0], inv[1, 1], km.Dt, km.h1]
    return emit_function(args, outputs, name="kilin_coefficients")


def chaplygin_coefficients(E: float, D: float, C: float, Mg: float) -> MapCoefficients:
    """BKM12-22/23: ``(M~, M~) = C``, ``(gamma~, gamma~) = 1``, ``(M~, gamma~) = 0``.

    Parameters
    ----------
    E : float
        ``2H = (M, omega)``.
    D, C, Mg : float
        ``D``, ``(M, M)``, ``(M, gamma)`` (``Mg != 0``; at ``Mg = 0`` the map is the identity).

    Returns
    -------
    MapCoefficients
        ``m1, m2, c1, c2``, the new ``D~`` and ``E~``, the root ``f`` used, ``form =
        "chaplygin"``.

    Raises
    ------
    UserInputError
        Unless ``E > 0``, ``D > 0`` and ``C > 0``.

    References
    ----------
    BKM12-22, BKM12-23, BKM12-1.4a.
    """
    if not (E > 0 and D > 0 and C > 0):
        raise UserInputError("Chaplygin's coefficients need E > 0, D > 0, (M, M) > 0")
    f_fun, rest = _chaplygin_funcs()
    f = float(f_fun(E, D, C, Mg))
    m1, m2, c1, c2, Dt_inv, Et = (float(x) for x in rest(E, D, C, Mg, f))
    return MapCoefficients(m1, m2, c1, c2, 1.0 / Dt_inv, Et, f, "chaplygin")


def kilin_coefficients(E: float, D: float, C: float, Mg: float) -> MapCoefficients:
    """K01-2.29 ... 2.33 (Kilin's normalisation ``(M~, M~) = n1``), inverted.

    Parameters
    ----------
    E : float
        ``2H = (M, omega)``.
    D, C, Mg : float
        ``D``, ``(M, M)``, ``(M, gamma)``.

    Returns
    -------
    MapCoefficients
        The inverse of Kilin's matrix as ``m1, m2, c1, c2``, ``D~``, ``E~ = 2 h1``, the
        root ``f`` of Chaplygin's map, ``form = "kilin"``.

    Raises
    ------
    UserInputError
        Unless ``E > 0``, ``D > 0`` and ``C > Mg**2``.

    References
    ----------
    K01-2.29, K01-2.32, K01-2.33.
    """
    if not (E > 0 and D > 0 and C > Mg**2):
        raise UserInputError("Kilin's coefficients need E > 0, D > 0, (M, M) > (M, gamma)^2")
    f_fun, _ = _chaplygin_funcs()
    f = float(f_fun(E, D, C, Mg))
    a, b, c, d, Dt, h1 = (float(x) for x in _kilin_funcs()(C, Mg, E / 2, D, f))
    return MapCoefficients(a, b, c, d, Dt, 2 * h1, f, "kilin")


def map_state(y: np.ndarray, k: MapCoefficients) -> np.ndarray:
    """Map states ``(M, gamma)`` (shape ``(6, ...)``) to ``(M~, gamma~)``.

    Parameters
    ----------
    y : ndarray, shape (6, ...)
        States ``M, gamma`` (more rows are ignored).
    k : MapCoefficients
        The map.

    Returns
    -------
    ndarray, shape (6, ...)
        ``M~ = m1 M + m2 gamma``, ``gamma~ = c1 M + c2 gamma``.

    References
    ----------
    BKM12-22, K01-2.29 (FORMULAS.md).
    """
    M, g = y[:3], y[3:6]
    return np.concatenate([k.m1 * M + k.m2 * g, k.c1 * M + k.c2 * g])


def mu_of_mapped(yt: np.ndarray, A: np.ndarray, k: MapCoefficients) -> np.ndarray:
    """``mu = m1 + c1 Z~`` (BKM12-18, corrected) at mapped states (shape ``(6, N)``).

    Parameters
    ----------
    yt : ndarray, shape (6, N)
        Mapped states ``M~, gamma~`` (:func:`map_state`).
    A : array_like, shape (3,)
        ``A_i = 1/(I_i + D)`` (unchanged by the map).
    k : MapCoefficients
        The map (``m1``, ``c1`` and ``D~``).

    Returns
    -------
    ndarray, shape (N,)
        ``mu`` at each state, ``ds/dt = 1/mu``.

    References
    ----------
    BKM12-18, BKM12-19 (FORMULAS.md).
    """
    Mt, gt = yt[:3], yt[3:6]
    A = np.asarray(A, dtype=float).reshape(3, 1)
    Zt = np.sum(A * Mt * gt, axis=0) / (1.0 / k.Dt - np.sum(A * gt * gt, axis=0))
    return k.m1 + k.c1 * Zt


@dataclass
class TransformationReport:
    """Outcome of :func:`transformation_test`.

    Attributes
    ----------
    coefficients : MapCoefficients
    params_new : dict
        ``I~ = I + D - D~`` (``J = I + D Id`` kept), ``D~``.
    t, s : ndarray
        Original times of the comparison points and the new times ``s(t)``.
    max_error : float
        ``max |y~_mapped(t) - y~_integrated(s(t))|`` over the comparison points.
    tolerance : float
        Derived from ``rtol`` and the time span (see :func:`transformation_test`).
    initial_products : dict
        ``(M~, gamma~)``, ``(gamma~, gamma~) - 1`` and ``(M~, M~)`` of the mapped initial state.
    drift : dict
        Drift of the integrals of both integrations.
    """

    coefficients: MapCoefficients
    params_new: dict
    t: np.ndarray
    s: np.ndarray
    max_error: float
    tolerance: float
    initial_products: dict
    drift: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return self.max_error <= self.tolerance


def transformation_test(
    I: tuple[float, float, float],  # the papers' name
    D: float,
    M0: tuple[float, float, float],
    gamma0: tuple[float, float, float],
    t_end: float = 10.0,
    *,
    form: str = "chaplygin",
    rtol: float = 1e-13,
    panel: float = 0.25,
    nodes: int = 12,
) -> TransformationReport:
    """Map an integrated trajectory and compare it with the transformed ball's own trajectory.

    Parameters
    ----------
    I, D : tuple of 3 floats, float
        Inertia and ``D = m b^2`` of the original ball.
    M0, gamma0 : tuple of 3 floats each
        Initial state (``|gamma0| = 1``, ``(M0, gamma0) != 0``).
    t_end : float
        Time span of the original trajectory.
    form : {"chaplygin", "kilin"}
        BKM12-22/23 normalisation or K01-2.29 ... 2.33.
    rtol : float
        Relative tolerance of both DOP853 integrations (``atol = rtol``, the state is O(1)).
    panel, nodes : float, int
        Gauss–Legendre panels for ``s(t) = int_0^t dt'/mu``: the quadrature error,
        ``~ (panel/2)^(2 nodes)`` times derivatives of ``1/mu``, is far below ``rtol``.

    Returns
    -------
    TransformationReport
        ``tolerance = 10 * rtol * (1 + s_end) * max(1, |y~|_max) * (1 + L)`` with
        ``L = max |mu|/min |mu|``: each integration's global error grows at most
        linearly over the span for this integrable (quasi-periodic) flow, and the
        time change maps errors in ``t`` to errors in ``s`` by the factor ``1/mu``.

    Raises
    ------
    UserInputError
        Non-physical inputs, ``(M, gamma) = 0``, or a transformed ball whose inertia
        ``I + D - D~`` is not positive.

    References
    ----------
    BKM12-19, BKM12-22, BKM12-23, K01-2.29 ... K01-2.33.
    """
    _check_arguments(I, D, M0, gamma0, t_end, form, rtol, panel, nodes)
    I = np.asarray(I, dtype=float)
    M0 = np.asarray(M0, dtype=float)
    gamma0 = np.asarray(gamma0, dtype=float)
    A, coeffs, I_new = _transformed_ball(I, D, M0, gamma0, form)
    # Gauss-Legendre nodes on panels of [0, t_end]
    n_pan = max(1, int(np.ceil(t_end / panel)))
    edges = np.linspace(0.0, t_end, n_pan + 1)
    x, w = detlinalg.gauss_legendre(nodes)
    h = np.diff(edges)
    t_nodes = (edges[:-1, None] + (x[None, :] + 1) * h[:, None] / 2).ravel()
    t_all = np.concatenate([edges, t_nodes])
    order = np.argsort(t_all)
    t_sorted = t_all[order]
    y0 = np.concatenate([M0, gamma0])
    params = {"I": tuple(I), "D": D}
    r1 = integrate(
        "chaplygin_ball", y0, (0.0, t_end), params, rtol=rtol, atol=rtol, t_eval=t_sorted
    )
    if not r1.success:
        raise RuntimeError(f"integration of the original ball failed: {r1.message}")
    y_all = np.empty_like(r1.y)
    y_all[:, order] = r1.y
    y_edges, y_nodes = y_all[:, : n_pan + 1], y_all[:, n_pan + 1 :]
    yt_nodes = map_state(y_nodes, coeffs)
    inv_mu = 1.0 / mu_of_mapped(yt_nodes, A, coeffs)
    panel_int = (inv_mu.reshape(n_pan, nodes) * w[None, :]).sum(axis=1) * h / 2
    s_edges = np.concatenate([[0.0], np.cumsum(panel_int)])
    yt_edges = map_state(y_edges, coeffs)
    if np.any(np.diff(s_edges) <= 0):  # pragma: no cover - mu keeps its sign on a trajectory
        raise RuntimeError("the new time is not monotonic (mu changes sign)")
    params_new = {"I": tuple(I_new), "D": coeffs.Dt}
    r2 = integrate(
        "chaplygin_ball",
        yt_edges[:, 0],
        (0.0, s_edges[-1]),
        params_new,
        rtol=rtol,
        atol=rtol,
        t_eval=s_edges,
    )
    if not r2.success:
        raise RuntimeError(f"integration of the transformed ball failed: {r2.message}")
    err = float(np.max(np.abs(r2.y - yt_edges)))
    mu_all = 1.0 / inv_mu
    L = float(np.max(np.abs(mu_all)) / np.min(np.abs(mu_all)))
    scale = max(1.0, float(np.max(np.abs(yt_edges))), float(np.max(np.abs(y_edges))))
    tol = 10 * rtol * (1 + s_edges[-1]) * scale * (1 + L)
    products = _transformed_products(yt_edges[:3, 0], yt_edges[3:, 0], A, coeffs)
    drift = {f"original {k}": v for k, v in r1.drift.items()}
    drift.update({f"transformed {k}": v for k, v in r2.drift.items()})
    return TransformationReport(coeffs, params_new, edges, s_edges, err, tol, products, drift)


# ------------------------------------------------------------------ spherical support
def support_coefficients(
    E: float, C: float, M_al: float, M_be: float, D_al: float, D_be: float
) -> dict[str, np.ndarray]:
    """BKM12 Proposition 2: rows of ``Q_E`` from the roots of the cubic (55).

    Parameters
    ----------
    E : float
        Twice the energy.
    C : float
        ``(M, M)``.
    M_al, M_be : float
        ``(M, alpha)`` and ``(M, beta)``.
    D_al, D_be : float
        The support's ``D`` along ``alpha`` and ``beta``.

    Returns
    -------
    dict of str to ndarray
        ``roots`` (ascending, shape (3,)), ``Q`` (shape (3, 3): rows for the roots, first
        entry 1), ``Gamma`` (3, 3), ``g`` (3, 3) and ``cubic`` (the cubic's coefficients,
        highest degree first, shape (4,)).

    References
    ----------
    BKM12-50 ... BKM12-55.
    """
    p = proposition2()
    s = p.symbols
    vals = {
        s["E"]: E,
        s["C"]: C,
        s["M_al"]: M_al,
        s["M_be"]: M_be,
        s["D_al"]: D_al,
        s["D_be"]: D_be,
    }
    coeffs = [
        float(sp.Poly(p.cubic, s["lam"]).coeff_monomial(s["lam"] ** k).xreplace(vals))
        for k in (3, 2, 1, 0)
    ]
    roots = np.sort(np.roots(coeffs).real)
    Gamma = np.array([[C, M_al, M_be], [M_al, 1, 0], [M_be, 0, 1]], dtype=float)
    g = np.diag([E, 1 / D_al, 1 / D_be])
    Q = np.array([[1.0, M_al * D_al / (lam - D_al), M_be * D_be / (lam - D_be)] for lam in roots])
    return {"roots": roots, "Q": Q, "Gamma": Gamma, "g": g, "cubic": np.array(coeffs)}


def random_support_state(rng: np.random.Generator) -> tuple[float, ...]:
    """``(E, C, M_al, M_be, D_al, D_be)`` of a random support state.

    A random orthonormal pair alpha, beta, a normal random M, E in [0.2, 3], D_al, D_be in
    [0.2, 2] (the arguments of :func:`support_coefficients`).

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of the random numbers.

    Returns
    -------
    tuple of 6 floats
        ``E, C = (M, M), (M, alpha), (M, beta), D_al, D_be``.
    """
    Qr = random_orthonormal(rng)
    alpha, beta = Qr[:, 0], Qr[:, 1]
    M = 2.0 * rng.random(3) - 1.0
    E = rng.uniform(0.2, 3.0)
    Da, Db = rng.uniform(0.2, 2.0, 2)
    C, Ma, Mb = (detlinalg.dot(M, v) for v in (M, alpha, beta))
    return float(E), C, Ma, Mb, float(Da), float(Db)


def _check_arguments(I, D, M0, gamma0, t_end, form, rtol, panel, nodes) -> None:
    """Refuse what :func:`transformation_test` cannot use (:class:`UserInputError`)."""
    check_inertia_vector(I, D, double=True)
    check_vector(M0, "M0", double=True)
    check_vector(gamma0, "gamma0", double=True)
    check_choice(form, ("chaplygin", "kilin"), "form")
    for name, value in (("t_end", t_end), ("rtol", rtol), ("panel", panel)):
        check_real(value, name, positive=True, double=True)
    check_count(nodes, "nodes", 1, 100)
    if t_end / panel > MAX_PANELS:
        raise UserInputError(
            f"t_end/panel = {t_end / panel:g} panels is more than {MAX_PANELS}; "
            "shorten t_end or widen panel"
        )


def _transformed_ball(I, D, M0, gamma0, form) -> tuple[np.ndarray, Any, np.ndarray]:
    """``A = (I + D)^-1``, the transformation's coefficients for the state's integrals and
    the transformed ball's inertia ``I + D - D~`` (refused unless physical)."""
    if abs(detlinalg.dot(gamma0, gamma0) - 1) > 1e-12:
        raise UserInputError("gamma0 must be a unit vector")
    Mg = detlinalg.dot(M0, gamma0)
    if abs(Mg) < 1e-8:
        raise UserInputError("(M, gamma) = 0 already: nothing to transform")
    A = 1.0 / (I + D)
    X = 1.0 / D - detlinalg.dot(gamma0, A * gamma0)
    Y = detlinalg.dot(A * M0, gamma0)
    omega0 = A * (M0 + (Y / X) * gamma0)
    E = detlinalg.dot(M0, omega0)
    C = detlinalg.dot(M0, M0)
    coeffs = (chaplygin_coefficients if form == "chaplygin" else kilin_coefficients)(E, D, C, Mg)
    I_new = I + D - coeffs.Dt
    if np.any(I_new <= 0) or coeffs.Dt <= 0:
        raise UserInputError(
            f"the transformed ball is not physical (I~ = {I_new.tolist()}, D~ = {coeffs.Dt})"
        )
    return A, coeffs, I_new


def _transformed_products(Mt0, gt0, A, coeffs) -> dict[str, float]:
    """The transformed start's products ``(M~, gamma~)``, ``|gamma~|^2 - 1``, ``|M~|^2`` and
    its energy with the transformed ``D~``."""
    return {
        "(M~,gamma~)": detlinalg.dot(Mt0, gt0),
        "(gamma~,gamma~)-1": detlinalg.dot(gt0, gt0) - 1,
        "(M~,M~)": detlinalg.dot(Mt0, Mt0),
        "E~": detlinalg.dot(
            Mt0,
            A
            * (
                Mt0
                + detlinalg.dot(A * Mt0, gt0) / (1 / coeffs.Dt - detlinalg.dot(gt0, A * gt0)) * gt0
            ),
        ),
    }
