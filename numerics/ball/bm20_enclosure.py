"""Proofs by computation for BM20's stroboscopic map: a periodic orbit enclosed, proved to
exist and to be unique in a box (Krawczyk), and proved attracting or not (Schur-Cohn on the
enclosed multipliers).

The map is the one of :mod:`~chaplygin.numerics.ball.bm20_map`: the state ``(M, gamma)`` of
the point ``x = (z, l, g)`` on the level ``|M| = G``, ``(M, gamma) = 0``, ``|gamma| = 1``
(BM20 (3.7)) carried by the flow over ``k`` forcing periods ``2 pi/Omega`` and read back in
Andoyer-Deprit variables. Here every step is in Arb ball arithmetic: the chart and its
derivative by jets, the flow and its derivative by the validated integrator
(:func:`~chaplygin.numerics.validated.enclose_flow`), the read-back by jets. The zero
searched is that of ``F(x) = (z' - z, l' - l, g' - g)`` with the angle differences taken as
``atan2`` of the rotated image (no branch cut near a fixed point). A zero of ``F`` is a
periodic point of the map on the level set because the flow keeps ``|M|``, ``(M, gamma)`` and
``|gamma|`` (BM20-2.5int, proved symbolically by ``chaplygin verify``): the image has the
same ``G`` and ``(M, gamma)`` as the start, so equal ``(z, l, g)`` means the same state.

References
----------
BM20-3.7, BM20-2.5int, BM20-map (FORMULAS.md); Krawczyk (1969); Lohner (1987).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

from flint import arb, arb_mat, ctx

from ...arith import detlinalg
from ...derive.errors import ComputationError
from ..code import load_model_code
from ..validated.jets import (
    JET_LIB,
    jet_atan2,
    jet_gradient,
    jet_value,
    jets_from_matrix,
    seed_jets,
)
from ..validated.krawczyk import krawczyk_test, schur_cohn
from ..validated.lohner import enclose_flow, to_ball, working_precision
from .bm20_map import BM20_EFFECTS

__all__ = [
    "MapOrbitProof",
    "prove_bm20_periodic_orbit",
    "bm20_orbit_guess",
    "bm20_chart",
    "BM20_FIG5_BODY",
]

#: BM20 Fig. 5-7's body as decimal strings, in the model's parameter order
#: (I1, I2, I3, D, J_off, delta, K1, K2, K3, Omega); Omega is set per call.
BM20_FIG5_BODY = ("4", "3", "2", "4.385", "0", "2", "-6", "-3", "-9")


@dataclass
class MapOrbitProof:
    """What :func:`prove_bm20_periodic_orbit` proved, with its evidence.

    Attributes
    ----------
    exists : {"unique zero", "no zero", "undecided"}
        The Krawczyk test's outcome on ``box``: ``"unique zero"`` proves exactly one periodic
        point of the k-fold map in the box.
    attracting : {"inside", "not inside", "undecided"}
        The Schur-Cohn test on the enclosed derivative of the k-fold map over the box:
        ``"inside"`` proves every multiplier of the orbit strictly inside the unit circle,
        ``"not inside"`` proves one on or outside it.
    centre : list of arb
        The Newton point ``(z, l, g)``.
    box : list of arb
        The box ``X`` tested.
    krawczyk_image : list of arb
        The Krawczyk box ``K`` (``K ⊆ int X`` proves existence and uniqueness).
    margin : float
        The smallest relative gap between ``K`` and ``X``'s boundary.
    multipliers : list of complex
        The eigenvalues of the derivative's midpoint (for the report; the proof is the
        Schur-Cohn test).
    derivative : list of list of arb
        The enclosure of the k-fold map's derivative over the box.
    residual : float
        ``max |F(centre)|`` (upper bound).
    steps, seconds : int, float
        Integration steps of the box run; wall time of the whole proof.
    widths : list of float
        The box run's widest state enclosure after each step.
    cycle_box, cycle_image : list of arb
        ``X`` and ``K`` for all ``3k`` unknowns (the orbit's ``k`` points).
    """

    exists: str
    attracting: str
    centre: list
    box: list
    krawczyk_image: list
    margin: float
    multipliers: list
    derivative: list
    residual: float
    steps: int
    seconds: float
    widths: list = field(default_factory=list)
    cycle_box: list = field(default_factory=list)
    cycle_image: list = field(default_factory=list)


def bm20_chart(x: Sequence, G: arb) -> list:
    """BM20 (3.7): ``(M, gamma)`` of ``(z, l, g)`` on balls or jets (the derivative of the
    chart comes with jets).

    Parameters
    ----------
    x : sequence of 3 arb or ArbJet
        ``(z, l, g)``.
    G : arb
        ``|M|``.

    Returns
    -------
    list of 6 arb or ArbJet
        ``M1, M2, M3, gamma1, gamma2, gamma3``.
    """
    z, l_, g = x
    s = JET_LIB.sqrt(1 - z * z)
    sl, cl, sg, cg = JET_LIB.sin(l_), JET_LIB.cos(l_), JET_LIB.sin(g), JET_LIB.cos(g)
    M = [G * s * sl, G * s * cl, G * z]
    gamma = [z * cg * sl + sg * cl, z * cg * cl - sg * sl, -s * cg]
    return M + gamma


def _read_back(y: Sequence, x: Sequence) -> list:
    """``F = (z' - z, l' - l, g' - g)`` of the image ``y = (M', gamma')`` of ``x``."""
    M1, M2, M3, g1, g2, g3 = y
    z, l_, g = x
    rho = JET_LIB.sqrt(M1 * M1 + M2 * M2)
    G = JET_LIB.sqrt(rho * rho + M3 * M3)
    z1, s1 = M3 / G, rho / G
    sl1, cl1 = M1 / rho, M2 / rho
    sin_g = g1 * cl1 - g2 * sl1
    cos_g = z1 * (g1 * sl1 + g2 * cl1) - s1 * g3
    sl, cl, sg, cg = JET_LIB.sin(l_), JET_LIB.cos(l_), JET_LIB.sin(g), JET_LIB.cos(g)
    dl = jet_atan2(M1 * cl - M2 * sl, M2 * cl + M1 * sl)
    dg = jet_atan2(sin_g * cg - cos_g * sg, cos_g * cg + sin_g * sg)
    return [z1 - z, dl, dg]


def _chart_set(x: Sequence, G: arb) -> tuple[list, list, list, arb_mat]:
    """The chart's image of the box ``x`` in Lohner's form ``c + B r``: ``c`` the image of the
    midpoint plus ``E = (Dchart(X) - A)(X - mid)`` (mean value theorem), ``B = [A | K]`` with
    ``A`` the midpoint of the chart's derivative over the box and ``K`` an orthonormal
    complement, ``r = (x - mid, 0)``; and the derivative over the box."""
    mid = [v.mid() for v in x]
    jets = bm20_chart(seed_jets(list(x)), G)
    D = arb_mat([jet_gradient(v, 3) for v in jets])
    A = [[float(D[i, j].mid()) for j in range(3)] for i in range(6)]
    E = [sum((D[i, j] - A[i][j]) * (x[j] - mid[j]) for j in range(3)) for i in range(6)]
    c = bm20_chart(mid, G)
    _, K = detlinalg.orthonormal_split([[A[i][j] for i in range(6)] for j in range(3)])
    basis = [[*A[i], *(float(v) for v in K[i])] for i in range(6)]
    coefficients = [x[j] - mid[j] for j in range(3)] + [arb(0)] * 3
    return [c[i] + E[i] for i in range(6)], basis, coefficients, D


def _period_map(code, params, x, x_next, G, t1, jacobian, order, tol, dtol=None):  # noqa: ANN001, ANN202
    """``F = P(x) - x_next`` over the balls ``x`` (angles as rotated differences) and, with
    ``jacobian``, its derivative with respect to ``x`` over them (that with respect to
    ``x_next`` is ``-Id`` exactly). The box's image under the chart starts the flow as a thin
    set in Lohner's form (not as the 6-D box around it)."""
    if jacobian:
        y_start, basis, coefficients, Dchart = _chart_set(x, G)
    else:
        y_start, basis, coefficients = bm20_chart(list(x), G), None, None
    # at the caller's working precision (prove_bm20_periodic_orbit's ``prec``); a parameter
    # interval (Omega over a range) is carried in the Lohner set, not in the coefficients
    # (wider than the working precision's rounding of a typed decimal, as lohner's end times)
    wide = 2.0 ** (20 - ctx.prec)
    carry = [i for i, q in enumerate(params) if float(q.rad()) > wide * float(abs(q).upper())]
    e = enclose_flow(
        code,
        params,
        y_start,
        0,
        t1,
        jacobian=jacobian,
        order=order,
        tol=tol,
        derivative_tol=dtol,
        prec=ctx.prec,
        carry=carry,
        basis=basis,
        coefficients=coefficients,
    )
    if jacobian:
        y = jets_from_matrix(e.state, arb_mat(e.jacobian) * Dchart)
    else:
        y = e.state
    F = _read_back(y, x_next)
    DF = arb_mat([jet_gradient(f, 3) for f in F]) if jacobian else None
    return [jet_value(f) for f in F], DF, e


def _shooting_points(code, params, x0, G, tau, period, order, tol):  # noqa: ANN001, ANN202
    """Parallel shooting centres ``x_0 .. x_(k-1)`` (``x_0`` the guess, ``x_(i+1)`` the
    midpoint of the enclosed image of ``x_i``) and the enclosed residuals
    ``P(x_i) - x_(i+1)`` (cyclic: the last closes on ``x_0``, angles reduced mod 2 pi)."""
    origin = [arb(0)] * 3
    xs, residuals = [[to_ball(v).mid() for v in x0]], []
    for i in range(period):
        # against x_next = 0 the read-back is the image itself: (z', l', g')
        image, _, _ = _period_map(code, params, xs[i], origin, G, tau, False, order, tol)
        if i < period - 1:
            xs.append([v.mid() for v in image])
        target = xs[(i + 1) % period]
        diff = [image[j] - target[j] for j in range(3)]
        for j in (1, 2):  # the angle's representative nearest 0
            turns = round(float(diff[j].mid()) / (2 * 3.141592653589793))
            diff[j] = diff[j] - 2 * arb.pi() * turns
        residuals.append(diff)
    return xs, residuals


def _cyclic_jacobian(blocks: list) -> arb_mat:
    """The derivative of ``(P(x_i) - x_(i+1))_i`` in all the ``x_i``: block ``(i, i)`` the map's
    derivative over ``X_i``, block ``(i, i+1 mod k)`` ``-Id``."""
    k = len(blocks)
    n = 3 * k
    rows = [[0] * n for _ in range(n)]
    for i, A in enumerate(blocks):
        nxt = (i + 1) % k
        for a in range(3):
            for b in range(3):
                rows[3 * i + a][3 * i + b] = A[a, b]
            rows[3 * i + a][3 * nxt + a] = rows[3 * i + a][3 * nxt + a] - 1
    return arb_mat(rows)


class _BoxRuns:
    """The period maps' derivatives over boxes around the shooting points (C^1 runs)."""

    def __init__(self, code, params, G, tau, xs, order, tol, dtol) -> None:  # noqa: ANN001
        self.args = (code, params, G, tau, xs, order, tol, dtol)
        self.steps, self.widths, self.blocks_done = 0, [], []

    def blocks(self, boxes: list) -> list:
        code, params, G, tau, xs, order, tol, dtol = self.args
        k = len(xs)
        self.blocks_done = []
        for i in range(k):
            box = boxes[3 * i : 3 * i + 3]
            _F, DF, e = _period_map(code, params, box, xs[(i + 1) % k], G, tau, True, order,
                                    tol, dtol)  # fmt: skip
            self.blocks_done.append(DF)
            self.steps += e.steps
            self.widths += e.widths
        return self.blocks_done


def _product(blocks: list) -> arb_mat:
    DP = blocks[0]
    for A in blocks[1:]:
        DP = A * DP
    return DP


def _multipliers_test(blocks: list) -> str:
    return schur_cohn(_product(blocks))[0]


def prove_bm20_periodic_orbit(
    omega: str | tuple[str, str],
    guess: Sequence[float],
    period: int = 7,
    *,
    multipliers: bool = True,
    body: Sequence[str] = BM20_FIG5_BODY,
    G: str = "3",
    radius: float = 1e-13,
    order: int = 28,
    prec: int = 128,
    tol: float = 1e-20,
    box_order: int = 20,
    box_tol: float = 1e-16,
) -> MapOrbitProof:
    """Prove a periodic orbit of BM20's stroboscopic map and decide whether it attracts.

    Parallel shooting: the unknowns are the orbit's ``k`` points ``x_i``, the equations
    ``P(x_i) - x_(i+1 mod k) = 0`` with ``P`` the map over one forcing period (each enclosed
    with its derivative over a box ``X_i = x_i +- radius`` by the validated integrator); the
    Krawczyk test on the ``3k``-dimensional system proves one and only one solution in the
    product of the boxes, i.e. one periodic orbit through them. The multipliers are the
    eigenvalues of ``DP(x_(k-1)) ... DP(x_0)``, enclosed by the product of the boxes'
    derivatives and decided by the Schur-Cohn test.

    Parameters
    ----------
    omega : str or (str, str)
        The forcing frequency as typed (a decimal string is enclosed, not rounded to double),
        or an interval ``(lo, hi)``: then the Krawczyk test proves, for every ``Omega`` in
        it, one and only one cycle through the boxes (the interval is carried through the
        flow as a constant state; the forcing period ``2 pi/Omega`` is an end-time interval).
    guess : sequence of 3 numbers or decimal strings
        A point ``(z, l, g)`` near the orbit, closer than ``radius`` over the conditioning of
        the shooting system (e.g. refined to 30 digits by
        :func:`~chaplygin.numerics.dynamics.periodic_orbits.refine_periodic_orbit` on
        ``bm20_map_with_jacobian(..., digits=30)``); the proof does not depend on how it was
        found.
    period : int, optional
        The number of forcing periods ``k`` (7 for BM20 Fig. 7A).
    body : sequence of str, optional
        ``I1, I2, I3, D, J_off, delta, K1, K2, K3`` (default: BM20 Fig. 5-7).
    G : str, optional
        ``|M|`` on the level set.
    radius : float, optional
        Half-width of the boxes ``X_i`` around the shooting points.
    order, prec, tol : optional
        The validated integrator's Taylor order, Arb precision (bits) and step control
        (the remainder per step) of the runs from the points.
    multipliers : bool, optional
        Decide the multipliers (False: existence only; ``attracting`` is ``"undecided"``).
    box_order, box_tol : optional
        Taylor order and step control of the runs over the boxes (whose width dominates
        there); the derivative's remainder per step there is bounded by ``radius/10``
        (``derivative_tol`` of :func:`~chaplygin.numerics.validated.lohner.enclose_flow`).
        When the multipliers are undecided on the boxes, the runs are repeated over
        the Krawczyk boxes ``K`` (which contain the cycle too, and are much smaller).

    Returns
    -------
    MapOrbitProof

    Examples
    --------
    >>> x = ["-0.913250392820383617", "1.822981612162557638", "1.495152429516041719"]
    >>> r = prove_bm20_periodic_orbit("1.06675", x)  # doctest: +SKIP
    >>> r.exists, r.attracting  # doctest: +SKIP
    ('unique zero', 'inside')
    """
    started = time.perf_counter()
    code = load_model_code("chaplygin_ball", BM20_EFFECTS)
    with working_precision(prec):
        params = [to_ball(p) for p in (*body, omega)]
        Gb = to_ball(G)
        tau = 2 * arb.pi() / params[-1]
        xs, residuals = _shooting_points(code, params, guess, Gb, tau, period, order, tol)
        centre = [v for x in xs for v in x]
        big_box = [v + arb(0, radius) for v in centre]
        F = [v for r in residuals for v in r]
        # the derivative's remainder per step: a tenth of the box's radius (the derivative's
        # own variation over the box, about |D^2 P| radius, dominates its width there)
        run = _BoxRuns(code, params, Gb, tau, xs, box_order, box_tol, max(box_tol, radius / 10))
        test = krawczyk_test(centre, big_box, F, _cyclic_jacobian(run.blocks(big_box)))
        attracting = _multipliers_test(run.blocks_done) if multipliers else "undecided"
        if multipliers and test.verdict == "unique zero" and attracting == "undecided":
            # the cycle is in K too: the derivatives over K's (much smaller) boxes
            attracting = _multipliers_test(run.blocks(test.image))
        DP = _product(run.blocks_done)
        mid = [[float(DP[i, j].mid()) for j in range(3)] for i in range(3)]
    multipliers = [complex(m) for m in detlinalg.eigvals(mid)]
    return MapOrbitProof(
        exists=test.verdict,
        attracting=attracting,
        centre=xs[0],
        box=big_box[:3],
        krawczyk_image=test.image[:3],
        margin=test.margin,
        multipliers=multipliers,
        derivative=[[DP[i, j] for j in range(3)] for i in range(3)],
        residual=max(float(abs(f).upper()) for f in F),
        steps=run.steps,
        seconds=time.perf_counter() - started,
        widths=run.widths,
        cycle_box=big_box,
        cycle_image=test.image,
    )


def bm20_orbit_guess(omega: str, period: int = 7, *, digits: int = 30) -> list[str]:
    """A starting point for :func:`prove_bm20_periodic_orbit`, by the floating-point route:
    the attractor of BM20 Fig. 5's start (``z = 0.5, l = 1, g = 1``, ``G = 3``) at
    ``Omega = 1.06675`` (Fig. 7A), its period-``period`` orbit refined in double, continued in
    ``Omega`` to ``omega`` and refined there by Newton at ``digits`` digits.

    Parameters
    ----------
    omega : str
        The target frequency (decimal string).
    period : int, optional
    digits : int, optional

    Returns
    -------
    list of str
        ``(z, l, g)`` to ``digits`` digits.

    Raises
    ------
    ComputationError
        The attractor at 1.06675 is not of the period asked for, or Newton did not converge.
    """
    import mpmath
    import numpy as np

    from ..dynamics.continuation import continue_periodic_orbit
    from ..dynamics.periodic_orbits import detect_period, refine_periodic_orbit
    from ..dynamics.reversibility import stroboscopic_samples
    from .bm20_map import bm20_map_with_jacobian, bm20_point, bm20_state

    body = [float(v) for v in BM20_FIG5_BODY] + [1.06675]
    code = load_model_code("chaplygin_ball", BM20_EFFECTS)
    start = bm20_state(np.array([0.5, 1.0, 1.0]), 3.0)
    states = stroboscopic_samples(code, body, start, 700, transient=12000, rtol=1e-10)
    points = np.array([bm20_point(y) for y in states])
    if detect_period(points, 64, 1e-4, angles=(1, 2), window=600) != period:
        raise ComputationError(f"the attractor at Omega = 1.06675 is not of period {period}")
    smap = bm20_map_with_jacobian(body, 3.0, rtol=1e-12)
    x = refine_periodic_orbit(smap, points[-1], period, 1.06675).points[0]
    if float(omega) != 1.06675:
        r = continue_periodic_orbit(
            smap, x, period, 1.06675, float(omega), step=5e-4, max_points=300
        )
        x = r.branches[0].points[-1]
    with mpmath.workdps(digits):
        fine = bm20_map_with_jacobian([*BM20_FIG5_BODY, omega], 3, digits=digits, rtol=1e-12)
        orbit = refine_periodic_orbit(fine, mpmath.matrix(list(x)), period, mpmath.mpf(omega))
        if not orbit.converged:
            raise ComputationError(f"Newton at {digits} digits: {orbit.message}")
        return [mpmath.nstr(v, digits) for v in orbit.points[0]]
