"""What the Kane cross-checks of described bodies share (:mod:`.kane_rolling`,
:mod:`.kane_implicit`, :mod:`.kane_support_implicit`, :mod:`.kane_body_support`): the working
digits and the comparison's points, its result, the described body as sympy rigid bodies,
where the body is put for a given normal, and Kane's equations with placeholders for the
constraint solver (:func:`form_with_placeholders`, :func:`solve_speeds`)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mpmath
import sympy as sp
import sympy.physics.mechanics as me

from ..derive.expression_dag import dag_xreplace

__all__ = [
    "DIGITS",
    "body_coordinates",
    "RATIONAL_UNIT_VECTORS",
    "SPHERE_POSITION",
    "T0",
    "KaneComparison",
    "frame_of",
    "model_rates",
    "placement",
    "PlaceholderKane",
    "form_with_placeholders",
    "potential_loads",
    "rigid_bodies",
    "solve_speeds",
    "support_line",
    "support_loads",
]

#: Working digits of the comparison.
DIGITS = 40
#: Where the body's centre sits on a fixed sphere at the comparison points (the angles
#: ``x, y`` of ``O``): away from the pole, so that the vertical is not the normal.
SPHERE_POSITION = ("1.1", "0.7")
#: Exact unit vectors (Pythagorean quadruples) away from the Euler angles' singularity.
RATIONAL_UNIT_VECTORS = (
    (sp.Rational(2, 7), sp.Rational(3, 7), sp.Rational(6, 7)),
    (sp.Rational(-1, 9), sp.Rational(4, 9), sp.Rational(8, 9)),
    (sp.Rational(6, 11), sp.Rational(-2, 11), sp.Rational(9, 11)),
    (sp.Rational(-2, 3), sp.Rational(1, 3), sp.Rational(-2, 3)),
)


@dataclass(frozen=True)
class KaneComparison:
    """The model against Kane's method at exact points.

    Attributes
    ----------
    points : int
    max_acceleration_error : float
        Largest ``|omega'_model - omega'_Kane| / (1 + |omega'|)``.
    max_momentum_error : float
        Largest ``|M + K - H_P| / (1 + |M + K|)``, ``H_P`` sympy's angular momentum
        about the contact point (body and rotor), ``K`` the gyrostatic momentum the
        state leaves out.
    max_normal_rate_error : float
        Largest ``|gamma'_model - gamma'_Kane| / (1 + |gamma'|)`` (the support's normal
        in body axes: Poisson's equation on a plane, a slower or faster turn on a
        sphere).
    tolerance : float
        ``10**-(DIGITS - 10)``.
    """

    points: int
    max_acceleration_error: float
    max_momentum_error: float
    max_normal_rate_error: float
    tolerance: float

    @property
    def agrees(self) -> bool:
        """Every error within the tolerance."""
        worst = max(self.max_acceleration_error, self.max_momentum_error)
        return max(worst, self.max_normal_rate_error) <= self.tolerance


#: The time of the comparison when the support moves by a prescribed law.
T0 = sp.Rational(7, 10)

#: The contact point's position from the axis before its vertical part is removed.
_RHO_SEED = (sp.Rational(5, 7), sp.Rational(-3, 11), sp.Rational(2, 13))

def frame_of(n: mpmath.matrix) -> mpmath.matrix:
    """A right-handed orthonormal frame (columns) whose third column is the unit ``n``.

    Parameters
    ----------
    n : mpmath.matrix
        A unit 3-vector.

    Returns
    -------
    mpmath.matrix
        3 x 3, orthogonal, determinant 1.
    """
    helper = mpmath.matrix([1, 0, 0]) if abs(n[0]) < mpmath.mpf("0.9") else mpmath.matrix([0, 1, 0])
    u = helper - (helper.T * n)[0] * n
    u = u / mpmath.norm(u)
    w = mpmath.matrix(
        [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
    )
    return mpmath.matrix([[u[i], w[i], n[i]] for i in range(3)])


def rigid_bodies(
    p: Mapping, sub: Mapping, frames: tuple[me.ReferenceFrame, me.ReferenceFrame],
    G: me.Point, t: sp.Symbol,
) -> list:  # fmt: skip
    """The described body at its centre of mass ``G`` (frame ``B``, mass, the given tensor,
    a prescribed ``I(t)`` a function of Kane's time ``t``) and its gyrostat as real rotors:
    one along each body axis ``K`` has a component on, a symmetric rotor turning about
    ``e_i`` relative to ``B`` at ``K_i(t)/Ia`` (prescribed by its motor); the body's own
    tensor is the given one minus the rotors'.

    Parameters
    ----------
    p : mapping
        The description's parsed fields (``RollingSystem._parsed``).
    sub : mapping
        The parameters' values.
    frames : (ReferenceFrame, ReferenceFrame)
        ``N`` and the body frame ``B``.
    G : sympy.physics.mechanics.Point
        The centre of mass (its velocity set).
    t : sympy.Symbol
        Kane's time.

    Returns
    -------
    list of sympy.physics.mechanics.RigidBody
        The body first, then the rotors.
    """
    _, B = frames
    now = {sp.Symbol("t", real=True): t, **sub}
    inertia = p["inertia"].xreplace(now)
    axes = (B.x, B.y, B.z)
    dyadic = sum(
        (inertia[i, j] * (e_i | e_j) for i, e_i in enumerate(axes) for j, e_j in enumerate(axes)),
        me.Dyadic(0),
    )
    bodies = []
    K = p["rotor_momentum"].xreplace(now)
    Ia, It = sp.Integer(1), sp.Rational(1, 2)
    for i, e in enumerate(axes):
        if K[i] == 0:
            continue
        R = me.ReferenceFrame(f"R{i + 1}")
        R.set_ang_vel(B, K[i] / Ia * e)
        rotor = Ia * (e | e) + It * (me.inertia(B, 1, 1, 1) - (e | e))
        dyadic = dyadic - rotor
        bodies.append(me.RigidBody(f"rotor{i + 1}", G, R, 0, (rotor, G)))
    bodies.insert(0, me.RigidBody("body", G, B, p["mass"].xreplace(sub), (dyadic, G)))
    return bodies


def body_coordinates(extra: str) -> tuple:
    """Kane's coordinates of a body: its body-fixed 3-2-1 Euler angles ``q1, q2, q3`` and
    the coordinates named in ``extra``; speeds ``u1, u2, u3`` the space components of the
    angular velocity and one more per extra coordinate, its rate.

    Parameters
    ----------
    extra : str
        The further coordinates' names, space-separated (``"p1 p2 p3"``).

    Returns
    -------
    tuple
        ``(q, u, N, B, euler, kd, rates)``: the coordinates and speeds (lists of dynamic
        symbols), the fixed frame and the body's, the angles' rates in the speeds
        (:func:`~.kane_euler.euler_rates`), the kinematic equations and the extra
        coordinates' rates by their derivative.
    """
    from .kane_euler import euler_rates

    t = me.dynamicsymbols._t
    q = list(me.dynamicsymbols("q1 q2 q3 " + extra))
    u = list(me.dynamicsymbols(f"u1:{len(q) + 1}"))
    N, B = me.ReferenceFrame("N"), me.ReferenceFrame("B")
    B.orient_body_fixed(N, tuple(q[:3]), "zyx")
    B.set_ang_vel(N, u[0] * N.x + u[1] * N.y + u[2] * N.z)
    euler = euler_rates()
    kd = [s.diff(t) - euler[s.diff(t)] for s in q[:3]]
    kd += [q[i].diff(t) - u[i] for i in range(3, len(q))]
    return q, u, N, B, euler, kd, {q[i].diff(t): u[i] for i in range(3, len(q))}


@dataclass(frozen=True)
class PlaceholderKane:
    """Kane's equations formed with placeholders ``X`` for ``B_dep^-1 B_ind`` (the
    constraint solver's answer), lambdified at mpmath as functions of ``(q, u, t)``, ``u``
    in KanesMethod's order (independent first).

    Attributes
    ----------
    method : sympy.physics.mechanics.KanesMethod
        The equations formed (``kanes_equations`` called).
    order : list of str
        The speeds' names, independent first.
    n_dependent : int
        How many speeds are dependent (the placeholders' rows).
    constraints : (callable, callable)
        ``A``, ``b`` of the velocity constraints ``A u = b`` (the coordinates' rates mapped).
    mass, forcing : callable
        The mass matrix and forcing, taking ``q, u, t`` and the placeholders (row by row).
    args : tuple
        ``(q, u, t)``: the coordinates, the speeds in order, Kane's time.
    """

    method: me.KanesMethod
    order: list[str]
    n_dependent: int
    constraints: tuple[Callable, Callable]
    mass: Callable
    forcing: Callable
    args: tuple

    def lambdify(self, expr: Any, *extra: Any) -> Callable:
        """``expr`` as an mpmath function of ``(q, u, t)`` and ``extra`` (with ``cse``).

        Parameters
        ----------
        expr : sympy expression or matrix
        *extra : sequence
            Further arguments after ``(q, u, t)``.

        Returns
        -------
        callable
        """
        return _mpmath_function(self.args, expr, extra)


def _mpmath_function(args: tuple, expr: Any, extra: Sequence = ()) -> Callable:
    """``expr`` lambdified at mpmath (with ``cse``) over ``args`` and then ``extra``."""
    return sp.lambdify((*args, *extra), expr, modules="mpmath", cse=True)


def support_line(
    N: me.ReferenceFrame, Omega: sp.Expr, carried: bool = True
) -> tuple[me.Vector, Callable[[Any], Any]]:
    """The line a body rolls along (``contact="line"``) and what completes Kane's
    expressions once formed: ``N.x`` on a fixed or shaken plane; on a turntable (``Omega``
    not zero) the line it carries, along ``N.x + tan(theta) N.y`` with the angle ``theta(t)``
    a function of time — sympy differentiates the constraint with it —, then ``theta' =
    Omega`` and ``theta = 0`` put in: the line is ``N.x`` at the compared instant, turning
    at ``Omega N.y`` (the vector and its rate are the unit direction's there; scaled so,
    ``u1``'s coefficient in the constraint is 1, as on a fixed plane, and sympy's solve of
    the constraints pivots on it). ``carried=False`` holds it fixed in space: a control.

    Parameters
    ----------
    N : sympy.physics.mechanics.ReferenceFrame
        The fixed frame (``N.z`` up).
    Omega : sympy.Expr
        The turntable's rate (of Kane's time), or 0.
    carried : bool
        Whether the turntable carries the line.

    Returns
    -------
    direction : sympy.physics.mechanics.Vector
    settle : callable
        Puts ``theta'`` and ``theta`` in a sympy expression or matrix.
    """
    if Omega == 0 or not carried:
        return N.x, lambda e: e
    t = me.dynamicsymbols._t
    theta = me.dynamicsymbols("theta_line")
    rate = {theta.diff(t): Omega}
    return N.x + sp.tan(theta) * N.y, (
        lambda e: sp.sympify(e).xreplace(rate).xreplace({theta: 0})
    )


def form_with_placeholders(
    N: me.ReferenceFrame, q: list, speeds: tuple[list, list], kd: list, constraints: list,
    bodies: list, loads: list, settle: Callable[[Any], Any] = lambda e: e,
) -> PlaceholderKane:  # fmt: skip
    """Kane's equations with the constraint solver handed placeholders ``X`` (``X_i_j``,
    dependent by independent) for ``B_dep^-1 B_ind`` (filled numerically by
    :func:`solve_speeds`), and their mpmath functions.

    Parameters
    ----------
    N : sympy.physics.mechanics.ReferenceFrame
        The fixed frame.
    q : list
        The coordinates (all independent).
    speeds : (list, list)
        The independent and the dependent speeds.
    kd : list
        The kinematic differential equations.
    constraints : list
        The velocity constraints (their coordinates' rates are mapped to the speeds).
    bodies, loads : list
        For ``kanes_equations``.
    settle : callable, optional
        Applied to the formed matrices (:func:`support_line`'s: a turntable's line).

    Returns
    -------
    PlaceholderKane
    """
    independent, dependent = speeds
    X = sp.Matrix(len(dependent), len(independent), lambda i, j: sp.Symbol(f"X{i}_{j}"))
    kane = me.KanesMethod(
        N, q_ind=q, u_ind=independent, u_dependent=dependent, kd_eqs=kd,
        velocity_constraints=constraints, constraint_solver=lambda A, b: X,
    )  # fmt: skip
    kane.kanes_equations(bodies, loads)
    q, u, kdmap = list(kane.q), list(kane.u), kane.kindiffdict()
    A, b = sp.linear_eq_to_matrix([sp.sympify(c).xreplace(kdmap) for c in constraints], u)
    args = (q, u, me.dynamicsymbols._t)
    flat = list(X)
    return PlaceholderKane(
        kane, [str(s.func) for s in u], X.rows,
        (_mpmath_function(args, settle(A)), _mpmath_function(args, settle(b))),
        _mpmath_function(args, settle(kane.mass_matrix), (flat,)),
        _mpmath_function(args, settle(kane.forcing), (flat,)), args,
    )  # fmt: skip


def solve_speeds(kane: PlaceholderKane, q: list, known: Mapping[str, Any], time: Any) -> tuple:
    """The dependent speeds from the velocity constraints and every speed's rate, at the
    coordinates ``q``, for a set-up whose ``constraint_solver`` got placeholders ``X =
    B_dep^-1 B_ind`` (filled here, row by row as KanesMethod's matrix is read).

    Parameters
    ----------
    kane : PlaceholderKane
        Formed by :func:`form_with_placeholders`.
    q : list of mpmath.mpf
    known : mapping of str to number
        The independent speeds by name (others are ignored).
    time : mpmath.mpf

    Returns
    -------
    (dict, dict, list)
        The speeds and their rates by name, and ``u`` in order.
    """
    n_ind = len(kane.order) - kane.n_dependent
    u = [mpmath.mpf(known[name]) if k < n_ind else mpmath.mpf(0)
         for k, name in enumerate(kane.order)]  # fmt: skip
    A = mpmath.matrix(kane.constraints[0](q, u, time))
    b = mpmath.matrix(kane.constraints[1](q, u, time))
    A_ind = mpmath.matrix([[A[i, j] for j in range(n_ind)] for i in range(A.rows)])
    A_dep = mpmath.matrix([[A[i, j] for j in range(n_ind, A.cols)] for i in range(A.rows)])
    u[n_ind:] = list(mpmath.lu_solve(A_dep, b - A_ind * mpmath.matrix(u[:n_ind])))
    X = [mpmath.lu_solve(A_dep, A_ind.column(j)) for j in range(n_ind)]
    flat = [X[j][i] for i in range(A.rows) for j in range(n_ind)]
    udot = mpmath.lu_solve(
        mpmath.matrix(kane.mass(q, u, time, flat)), mpmath.matrix(kane.forcing(q, u, time, flat))
    )
    speed = dict(zip(kane.order, u, strict=True))
    return speed, dict(zip(kane.order, udot, strict=True)), u


def support_loads(parsed: Mapping, sub: Mapping, frames: tuple, G: me.Point, angles: tuple,
                  place: tuple) -> tuple[list, list]:  # fmt: skip
    """The bodies and loads of a body on a support surface in Kane's set-up: the body and
    its rotors at ``G`` (:func:`rigid_bodies`: ``I(t)``, ``K(t)``), gravity ``-m g N.z`` at
    ``G``, and a potential ``V(p, e1, e2, e3)`` (``e_i_j``: body axis ``i`` on ``N``'s axis
    ``j``, from the attitude) as the loads of :func:`potential_loads` on the Euler angles and
    on the contact point.

    Parameters
    ----------
    parsed, sub : mapping
        The description's parsed fields and the parameters' values.
    frames : (ReferenceFrame, ReferenceFrame)
        ``N`` and ``B``.
    G : sympy.physics.mechanics.Point
        The centre of mass, its velocity set.
    angles, place : (sequence, sequence)
        The Euler angles and their rates, the contact point's coordinates and rates.

    Returns
    -------
    (list, list)
        The bodies and the loads.
    """
    N, B = frames
    t = me.dynamicsymbols._t
    bodies = rigid_bodies(parsed, sub, (N, B), G, t)
    loads = [(G, -bodies[0].mass * parsed["field"].xreplace(sub) * N.z)]
    at = dict(zip(sp.symbols("p1:4", real=True), place[0], strict=True))
    for i, axis in enumerate((B.x, B.y, B.z), 1):
        at.update((sp.Symbol(f"e{i}_{j}", real=True), axis.dot(n))
                  for j, n in enumerate((N.x, N.y, N.z), 1))  # fmt: skip
    V = parsed["potential"].xreplace({sp.Symbol("t", real=True): t, **sub}).xreplace(at)
    groups = [("angles", *angles), ("place", *place)]
    return bodies, loads + potential_loads(V, N, groups)


def potential_loads(V: sp.Expr, N: me.ReferenceFrame, groups: Sequence[tuple]) -> list:
    """A potential ``V`` of the coordinates as loads: for each group ``(name, coordinates,
    rates)`` a massless point moving at ``sum_j rate_j N_j`` with the force ``-sum_j
    dV/dq_j N_j`` (its generalised active force is ``-sum_j dV/dq_j dq_j'/du_r``: the
    potential's, whatever the kinematic equations are).

    Parameters
    ----------
    V : sympy.Expr
        The potential as a function of the coordinates (dynamic symbols).
    N : sympy.physics.mechanics.ReferenceFrame
        The fixed frame.
    groups : sequence of (str, sequence, sequence)
        At most three coordinates per group, with their rates in the speeds.

    Returns
    -------
    list of (Point, Vector)
    """
    if V == 0:
        return []
    axes, loads = (N.x, N.y, N.z), []
    for name, coords, rates in groups:
        point = me.Point(name)
        point.set_vel(N, sum((w * e for w, e in zip(rates, axes, strict=False)), me.Vector(0)))
        pairs = zip(coords, axes, strict=False)
        loads.append((point, sum((-sp.diff(V, c) * e for c, e in pairs), me.Vector(0))))
    return loads


def placement(gamma: Sequence[object], sphere: bool, inside: bool) -> list:
    """Euler angles and position ``x, y`` putting the support's normal into the body at
    body components ``gamma``: on a plane ``N.z`` is the normal; on a sphere the body's
    place sits at the generic angles :data:`SPHERE_POSITION` (the vertical is not the
    normal there) and the body is turned so that ``e_r`` (outside; ``-e_r`` inside) has
    components ``gamma``.

    Parameters
    ----------
    gamma : sequence of 3 numbers
        A unit vector (body components).
    sphere, inside : bool
        On a fixed sphere; inside it.

    Returns
    -------
    list of mpmath.mpf
        ``q1, q2, q3, x, y`` at :data:`DIGITS` digits (``x = y = 0`` on a plane).
    """
    with mpmath.workdps(DIGITS):
        g = mpmath.matrix([_mpf(x) for x in gamma])
        if inside:  # inside a sphere the normal into the body is -e_r
            g = -g
        if not sphere:
            q2 = -mpmath.asin(g[0])
            q3 = mpmath.atan2(g[1], g[2])
            return [mpmath.mpf("0.3"), q2, q3, mpmath.mpf(0), mpmath.mpf(0)]
        x, y = (mpmath.mpf(c) for c in SPHERE_POSITION)
        e_r = mpmath.matrix(
            [mpmath.cos(x), mpmath.sin(x) * mpmath.cos(y), mpmath.sin(x) * mpmath.sin(y)]
        )
        # body axes in N (columns of C^T): any orthonormal right-handed frame with
        # C e_r = g; built from g's frame and e_r's frame
        Fb, Fs = frame_of(g), frame_of(e_r)
        M = Fs * Fb.T  # N <- B: takes g (body) to e_r (space)
        q2 = -mpmath.asin(M[2, 0])
        q3 = mpmath.atan2(M[2, 1], M[2, 2])
        q1 = mpmath.atan2(M[1, 0], M[0, 0])
        return [q1, q2, q3, x, y]


def _mpf(v: object) -> mpmath.mpf:
    """A number at :data:`DIGITS` (sympy's functions of exact arguments evaluated)."""
    if isinstance(v, mpmath.mpf):
        return v
    return mpmath.mpf(sp.Float(sp.N(v, DIGITS + 5), DIGITS))


def _relative(a: Sequence[object], b: Sequence[object]) -> float:
    with mpmath.workdps(DIGITS):
        x = [_mpf(v) for v in a]
        y = [_mpf(v) for v in b]
        diff = mpmath.sqrt(sum((p - q) ** 2 for p, q in zip(x, y, strict=True)))
        scale = 1 + mpmath.sqrt(sum(p**2 for p in x))
        return float(diff / scale)


def model_rates(model: Any, values: dict) -> list:
    """A model's rates at ``values`` (exact or ``DIGITS``-digit numbers): its auxiliary
    definitions evaluated in order, five digits beyond the comparison's (the expanded
    right-hand side repeats them: minutes at these digits).

    Parameters
    ----------
    model : chaplygin.derive.model.Model
    values : dict of sympy.Symbol to number
        The state, parameters and time; the auxiliaries' values are added to it.

    Returns
    -------
    list of sympy.Float
        ``model.rhs`` at ``values``, in state order.
    """
    memo: dict = {}  # each distinct subexpression evaluated once, at twice the digits
    with mpmath.workdps(2 * (DIGITS + 5)):
        for symbol, expr in model.aux:
            memo[symbol] = _numeric(expr, values, memo)
            values[symbol] = sp.Float(memo[symbol], DIGITS + 5)
        return [sp.Float(_numeric(e, values, memo), DIGITS + 5) for e in model.rhs]


_MPMATH_FUNCTIONS = {sp.sin: mpmath.sin, sp.cos: mpmath.cos, sp.tan: mpmath.tan,
                     sp.exp: mpmath.exp, sp.log: mpmath.log}  # fmt: skip


def _numeric(expr: sp.Expr, values: dict, memo: dict) -> mpmath.mpf:
    """``expr`` at ``values`` in mpmath at the working precision, each distinct
    subexpression once (sympy's ``N`` walks a tree: the auxiliaries' shared parts again and
    again); an expression with another kind of node is left to ``sympy.N``."""
    try:
        return _walk(expr, values, memo)
    except _NotNumeric:
        return mpmath.mpf(sp.N(dag_xreplace(expr, values), mpmath.mp.dps)._mpf_)


class _NotNumeric(Exception):
    """A node :func:`_walk` does not evaluate (then ``sympy.N`` does)."""


def _walk(e: sp.Basic, values: dict, memo: dict) -> mpmath.mpf:
    hit = memo.get(e)
    if hit is not None:
        return hit
    if e in values:  # a number, or a constant expression (an exact algebraic point)
        v = values[e]
        out = _walk(v, {}, memo) if isinstance(v, sp.Basic) else mpmath.mpf(v)
    elif isinstance(e, sp.Rational):
        out = mpmath.mpf(e.p) / e.q
    elif isinstance(e, sp.Float) or e in (sp.pi, sp.E):
        out = mpmath.mpf(e.evalf(mpmath.mp.dps)._mpf_)
    elif isinstance(e, sp.Add):
        out = mpmath.fsum(_walk(a, values, memo) for a in e.args)
    elif isinstance(e, sp.Mul):
        out = mpmath.fprod(_walk(a, values, memo) for a in e.args)
    elif isinstance(e, sp.Pow) and isinstance(e.exp, sp.Rational):
        base = _walk(e.base, values, memo)
        if e.exp.q == 1:
            out = base ** int(e.exp.p)
        elif base > 0:
            out = mpmath.power(base, mpmath.mpf(e.exp.p) / e.exp.q)
        else:
            raise _NotNumeric(e)
    elif type(e) in _MPMATH_FUNCTIONS:
        out = _MPMATH_FUNCTIONS[type(e)](_walk(e.args[0], values, memo))
    else:
        raise _NotNumeric(e)
    memo[e] = out
    return out
