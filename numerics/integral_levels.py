"""An initial state on prescribed values of any first integrals: the free components solved for.

A request gives a state (its groups, e.g. ``M`` and ``gamma``), names the components that
are free (``free = ["M"]`` or ``["M1", "M3"]``) and prescribes as many integral values
(``integrals = {"H": 1.1, "ROUTH-jellett": 0.4}``). An integral is one the model ships (its
generated ``integrals``: ``H``, ``(M,gamma)`` ...) or an expression of the state, the angular
velocity ``omega1..3`` (the model's auxiliary quantities) and the parameters, read without
``eval`` (:func:`chaplygin.derive.expression_text.parse_expression`): a described system's
``[[claims]]`` of kind ``integral``, found by ``chaplygin discover`` or typed from the
literature. Nothing here is specific to one system.

The point chosen (reproducible): Newton's method on ``F(x) = values``, ``x`` the free
components, from their given values, with the Jacobian by central differences and a step
halved until ``|F - values|`` decreases, at ``parse_dps + 10`` digits (mpmath: the same bits
on every machine); the root it reaches is the state's. Where no step decreases the residual,
or the Jacobian is singular, no state near the given one has those values: the error gives the
least residual reached (a real state may not exist at all: an energy below the potential of
the configuration, a value beyond an integral's range on the given configuration).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import mpmath

from ..derive.errors import UserInputError
from .code import ModelCode
from .inputs import complete_state
from .precision import Precision

__all__ = ["LevelRequest", "IntegralLevelError", "level_values", "state_on_levels"]

#: Newton iterations at most.
MAX_ITERATIONS = 60


class IntegralLevelError(UserInputError):
    """A request :func:`state_on_levels` cannot meet; ``key`` names the request key at fault
    (``"integrals"``, ``"free"`` or a state group)."""

    def __init__(self, message: str, key: str):
        super().__init__(message)
        self.key = key


@dataclass(frozen=True)
class LevelRequest:
    """What :func:`state_on_levels` solves.

    Attributes
    ----------
    given : mapping of str to sequence
        State groups as given (the free components' values are Newton's start).
    free : sequence of str
        Free components (names like ``M1``) or whole groups (``M``).
    targets : mapping of str to value
        Integral name -> value (numbers or text the number parser reads).
    expressions : mapping of str to str
        Integrals the model does not ship: name -> expression text.
    point : int or None
        None: the root Newton reaches from the given values; ``k``: the k-th point of the
        level set's documented enumeration (:mod:`chaplygin.numerics.level_points`).
    """

    given: Mapping[str, Sequence]
    free: Sequence[str]
    targets: Mapping[str, object]
    expressions: Mapping[str, str]
    point: int | None = None


def _free_components(code: ModelCode, given: Mapping, free: Sequence[str]) -> list:
    """``[(group, index, name)]`` of the free components, in the request's order."""
    groups = code.state_groups
    out = []
    for item in free:
        if item in groups:
            out += [(item, i, n) for i, n in enumerate(groups[item])]
            continue
        owner = next((g for g, names in groups.items() if item in names), None)
        if owner is None:
            valid = [*groups, *(n for names in groups.values() for n in names)]
            raise IntegralLevelError(
                f"free: {code.name} has no state component {item!r}; valid: {', '.join(valid)}",
                "free",
            )
        out.append((owner, groups[owner].index(item), item))
    names = [n for _, _, n in out]
    if len(set(names)) != len(names):
        raise IntegralLevelError("free names a component twice", "free")
    for group, _, name in out:
        if group not in given:
            raise IntegralLevelError(
                f"free component {name} needs a start: give {group} (its values start the solve)",
                group,
            )
    return out


def _evaluators(code: ModelCode, request: LevelRequest) -> dict[str, Callable]:
    """Integral name -> ``f(y, p)`` at the current mpmath precision."""
    import sympy as sp

    from ..derive.expression_text import parse_expression

    shipped = list(code.integral_names)
    names = [*code.state, *code.aux_names, *code.params]
    symbols = {n: sp.Symbol(n, real=True) for n in names}
    out: dict[str, Callable] = {}
    last: dict = {}
    for name in request.targets:
        if name in shipped:
            k = shipped.index(name)
            out[name] = lambda y, p, k=k: code.mpmath.integrals(mpmath.mpf(0), y, p)[k]
        elif name in request.expressions:
            expr = parse_expression(
                request.expressions[name], symbols, f"integral {name}"
            )  # the file's claim: state, omega, parameters only
            used = sorted(expr.free_symbols, key=lambda s: s.name)
            out[name] = _expression_evaluator(code, expr, used, last)
        else:
            valid = [*shipped, *request.expressions]
            raise IntegralLevelError(
                f"{code.name} has no integral {name!r}; valid: {', '.join(valid)} (the model's "
                "and the file's [[claims]] of kind integral)",
                "integrals",
            )
    return out


def _expression_evaluator(code: ModelCode, expr, used, last: dict) -> Callable:
    """``f(y, p)`` of a sympy expression over state, auxiliary and parameter names (values
    substituted exactly as binary numbers; no code is generated from the text); ``last``
    holds the auxiliary quantities of the last state (shared by a request's expressions)."""
    import sympy as sp

    state, aux, params = list(code.state), list(code.aux_names), list(code.params)

    def value(y, p):
        aux_values = ()
        if any(s.name in aux for s in used):
            key = (tuple(y), tuple(p), mpmath.mp.prec)
            if key not in last:
                last.clear()
                last[key] = code.mpmath.aux(mpmath.mpf(0), y, p)
            aux_values = last[key]
        table = {}
        for s in used:
            if s.name in state:
                v = y[state.index(s.name)]
            elif s.name in aux:
                v = aux_values[aux.index(s.name)]
            else:
                v = p[params.index(s.name)]
            table[s] = mpmath.mpf(v)
        dps = mpmath.mp.dps
        try:
            with mpmath.workdps(dps + 5):
                out = _tree_value(expr, table)
            if isinstance(out, mpmath.mpf):
                return +out
        except (_NotInTree, ZeroDivisionError, ValueError):
            pass  # sympy's evalf decides, as it always did
        floats = {s: sp.Float(v, dps + 5) for s, v in table.items()}
        return mpmath.mpf(str(expr.xreplace(floats).evalf(dps + 5)))

    return value


class _NotInTree(Exception):
    """A node :func:`_tree_value` does not evaluate (sympy's evalf does it instead)."""


def _tree_value(node, table: dict):
    """A sympy expression's value in mpmath at the current precision, by walking its tree
    (numbers, symbols from ``table``, sums, products, powers, the functions of
    :data:`chaplygin.derive.expression_text.FUNCTIONS`, ``pi`` and ``E``): no code is made
    from the text; a node it does not know raises :class:`_NotInTree`."""
    import sympy as sp

    from ..derive.expression_text import FUNCTIONS

    if node.is_Symbol:
        return table[node]
    if node.is_Rational:
        return mpmath.mpf(int(node.p)) / int(node.q)
    if node.is_Float:
        return mpmath.mpf(node._mpf_)
    if node is sp.pi or node is sp.E:
        return +mpmath.pi if node is sp.pi else +mpmath.e
    args = [_tree_value(a, table) for a in node.args]
    if node.is_Add:
        return mpmath.fsum(args)
    if node.is_Mul:
        return mpmath.fprod(args)
    if node.is_Pow:
        exponent = node.args[1]
        if exponent.is_Integer:
            return args[0] ** int(exponent)
        return args[0] ** args[1]
    for name, func in FUNCTIONS.items():
        if node.func is func and len(args) == 1:
            return getattr(mpmath, name)(args[0])
    raise _NotInTree(type(node).__name__)


def level_values(
    code: ModelCode,
    y: Sequence,
    params: Sequence,
    names: Sequence[str],
    expressions: Mapping[str, str],
    dps: int,
) -> dict[str, mpmath.mpf]:
    """The integrals ``names`` at the state ``y`` (shipped ones or expressions), at ``dps``.

    Parameters
    ----------
    code : ModelCode
    y, params : sequence
        State and parameter vectors.
    names : sequence of str
    expressions : mapping of str to str
        Expression texts of the integrals the model does not ship.
    dps : int

    Returns
    -------
    dict of str to mpmath.mpf
    """
    request = LevelRequest({}, (), dict.fromkeys(names, 0), expressions)
    with mpmath.workdps(dps):
        f = _evaluators(code, request)
        yy, pp = [mpmath.mpf(v) for v in y], [mpmath.mpf(v) for v in params]
        return {n: f[n](yy, pp) for n in names}


def state_on_levels(
    code: ModelCode, params: Mapping[str, object], request: LevelRequest, precision: Precision
) -> tuple[dict, dict, str]:
    """The given state with its free components moved onto the prescribed integral values.

    Parameters
    ----------
    code : ModelCode
    params : mapping of str to number
        Parameter values by symbol at the working precision.
    request : LevelRequest
    precision : Precision
        The working precision (the solve runs at ``precision.parse_dps + 10`` digits).

    Returns
    -------
    (dict, dict, str)
        The state groups (text at the solve's digits), the prescribed values by name (as
        given), and how the point was chosen.

    Raises
    ------
    IntegralLevelError
        Unknown names, a count of free components other than the integrals', a start
        missing, or no state reached with those values; ``point`` set (that is
        :func:`chaplygin.numerics.level_points.point_on_levels`).
    """
    from .inputs import parse_number
    from .level_certificate import certificate_refusal

    if request.point is not None:
        raise IntegralLevelError(
            "point = k is chosen by chaplygin.numerics.level_points.point_on_levels", "point"
        )
    with mpmath.workdps(precision.parse_dps + 10):
        _evaluators(code, request)  # unknown names first
    free = _free_components(code, request.given, request.free)
    if len(free) != len(request.targets) or not free:
        raise IntegralLevelError(
            f"{len(request.targets)} integral value(s) need as many free components, "
            f"{len(free)} given (free = [...] names components or groups)",
            "free",
        )
    dps = precision.parse_dps + 10
    solve_precision = Precision(dps)
    with mpmath.workdps(dps):
        evaluate = _evaluators(code, request)
        names = list(request.targets)
        target = mpmath.matrix([parse_number(request.targets[n], dps) for n in names])
        p = [mpmath.mpf(params[k]) for k in code.params]
        base = {k: [parse_number(v, dps) for v in vals] for k, vals in request.given.items()}

        def groups_at(x):
            trial = {k: list(v) for k, v in base.items()}
            for (group, i, _), value in zip(free, x, strict=True):
                trial[group][i] = value
            return {k: [mpmath.nstr(v, dps) for v in vals] for k, vals in trial.items()}

        def residual(x):
            try:
                y = [mpmath.mpf(v) for v in complete_state(code, groups_at(x), solve_precision).y]
            except UserInputError as exc:
                raise IntegralLevelError(str(exc), "integrals") from None
            return mpmath.matrix([evaluate[n](y, p) for n in names]) - target

        x0 = mpmath.matrix([base[g][i] for g, i, _ in free])
        try:
            x = _newton(residual, x0, names, [n for _, _, n in free], target, dps)
        except IntegralLevelError as exc:
            proof = certificate_refusal(lambda x: residual(x) + target, x0, names, target)
            raise (IntegralLevelError(proof, "integrals") if proof else exc) from None
        values = groups_at(x)
    how = (
        f"{', '.join(n for _, _, n in free)} solved for the integral values "
        f"{', '.join(names)} (Newton from the given values)"
    )
    return values, dict(request.targets), how


def _newton(residual, x0, names, free_names, target, dps, iterations=MAX_ITERATIONS, halvings=30):
    """Damped Newton with a central-difference Jacobian (a step halved at most ``halvings``
    times until the residual falls); refuses with the least residual."""
    x, r = x0, residual(x0)
    scale = 1 + mpmath.norm(target, mpmath.inf)
    tol = mpmath.mpf(10) ** (-(dps - 8)) * scale
    h = mpmath.mpf(10) ** (-(dps // 2))
    for _ in range(iterations):
        size = mpmath.norm(r, mpmath.inf)
        if size <= tol:
            return x
        J = mpmath.matrix(len(r), len(x))
        for j in range(len(x)):
            step = h * (1 + abs(x[j]))
            e = mpmath.matrix(len(x), 1)
            e[j] = step
            column = (residual(x + e) - residual(x - e)) / (2 * step)
            for i in range(len(r)):
                J[i, j] = column[i]
        try:
            dx = mpmath.lu_solve(J, -r)
        except (ZeroDivisionError, TypeError):
            break  # a singular Jacobian: no Newton step (mpmath's LU leaves the pivot of a
            # zero column None: a TypeError)
        t = mpmath.mpf(1)
        while t > mpmath.mpf(2) ** -halvings:
            trial = x + t * dx
            r_trial = residual(trial)
            if mpmath.norm(r_trial, mpmath.inf) < size:
                x, r = trial, r_trial
                break
            t /= 2
        else:
            break
    raise IntegralLevelError(
        f"no state near the given one has {', '.join(names)} = "
        f"{', '.join(mpmath.nstr(v, 10) for v in target)} with {', '.join(free_names)} free: "
        f"Newton from the given values stops at a residual of "
        f"{mpmath.nstr(mpmath.norm(r, mpmath.inf), 3)} (such a state may not exist: give "
        "other values, or other free components or start values)",
        "integrals",
    )
