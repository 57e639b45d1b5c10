"""Initial states: the one function that turns a request into a state, for the API and scenes.

A request (a scene's ``[initial]`` table, or the same keys as a mapping) gives the state of a
model in one of these ways, each a documented and reproducible choice:

* by state groups (``M``, ``gamma``, ``alpha``, ``x``, ...), completed as the model declares
  (:func:`chaplygin.numerics.inputs.pack_state`; the frame ``alpha, beta`` by the one rule of
  :mod:`chaplygin.numerics.frame`: BKM12-7, and on ``M || gamma`` the body axis least aligned
  with ``gamma``, projected);
* by the values of the ball's first integrals: ``h``, ``C``, and ``n`` or ``parallel``,
  ``point`` choosing the point of the level set (:mod:`chaplygin.numerics.ball.level_set`);
* by ``M`` as a direction, the configuration (``gamma`` ...) and the energy ``h`` alone: ``M``
  scaled so that ``H = h`` (any model whose energy is quadratic in ``M`` plus a function of
  the configuration: the ball, the gyrostat, a described body under gravity);
* by the values of any model's integrals (``integrals`` with ``free``): the free components
  solved by Newton from their given values (:mod:`chaplygin.numerics.integral_levels`), or with
  ``point = k`` the k-th point of the level set's enumeration
  (:mod:`chaplygin.numerics.level_points`);
* by BM20's Andoyer-Deprit variables ``G, z, l, g`` (BM20 (3.7)), or ``rest = true`` (``M = 0``);
* near a named solution of the plain ball: ``near = "p_i"`` (the steady rotation about axis
  ``i``, K01 (3.2)) or ``separatrix = i`` (``M || gamma`` at ``h = C^2/(2 I_i)``, the middle axis),
  pushed off by ``offset``.

:func:`initial_state` chooses between them and returns the state at the working precision with
how it was chosen, the integral values prescribed and their residuals. A request it cannot use
raises :class:`InitialStateError`, whose ``key`` names the request key at fault (a scene shows
it as ``initial.<key>`` with its line).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import mpmath

from ...derive.errors import UserInputError, did_you_mean
from ..code import ModelCode
from ..frame import horizontal_frame
from .level_set import GRID, INTEGRAL_KEYS, ResolvedState, integral_name, state_from_integrals

__all__ = [
    "ANDOYER",
    "REQUEST_KEYS",
    "InitialState",
    "InitialStateError",
    "check_initial_request",
    "initial_state",
    "ResolvedState",
    "state_from_integrals",
    "state_from_andoyer",
    "state_near_rotation",
    "horizontal_frame",
    "integral_residuals",
    "GRID",
    "INTEGRAL_KEYS",
]


def integral_residuals(
    code: ModelCode, y: Sequence, params: Sequence, prescribed: Mapping[str, object], dps: int
) -> dict[str, float]:
    """``F(y0) - prescribed`` for every prescribed integral, with the generated integrals.

    Parameters
    ----------
    code : ModelCode
    y : sequence
        The state vector as it will be integrated.
    params : sequence
        The parameter vector as it will be integrated.
    prescribed : mapping
        Integral name -> value asked for.
    dps : int
        Digits of the evaluation.

    Returns
    -------
    dict of str to float
    """
    with mpmath.workdps(dps):
        values = code.mpmath.integrals(
            mpmath.mpf(0), [mpmath.mpf(v) for v in y], [mpmath.mpf(v) for v in params]
        )
        return {
            name: float(values[code.integral_names.index(name)] - mpmath.mpf(want))
            for name, want in prescribed.items()
        }


def state_from_andoyer(
    G: mpmath.mpf, z: mpmath.mpf, l: mpmath.mpf, g: mpmath.mpf
) -> dict[str, list]:
    """``M, gamma`` from BM20's Andoyer-Deprit variables (BM20 (3.7), ``(M, gamma) = 0``).

    ``M = (G sqrt(1-z^2) sin l, G sqrt(1-z^2) cos l, G z)``,
    ``gamma = (z cos g sin l + sin g cos l, z cos g cos l - sin g sin l, -sqrt(1-z^2) cos g)``.

    Parameters
    ----------
    G, z, l, g : mpmath.mpf
        ``G = |M| >= 0``, ``|z| <= 1``; angles in radians. Evaluated at the current mpmath
        precision.

    Returns
    -------
    dict of str to list of mpmath.mpf
        ``{"M": [...], "gamma": [...]}``.

    Raises
    ------
    UserInputError
        ``|z| > 1`` or ``G < 0`` (the message gives the admissible range).
    """
    if not -1 <= z <= 1:
        raise UserInputError(
            f"Andoyer-Deprit z = {mpmath.nstr(z, 10)} is outside its range: |z| <= 1 (z = M3/G)"
        )
    if G < 0:
        raise UserInputError(f"Andoyer-Deprit G = |M| must be 0 or more, got {mpmath.nstr(G, 10)}")
    from .map_coordinates import from_andoyer_deprit

    M, gamma = from_andoyer_deprit(*(mpmath.mpf(v) for v in (G, z, l, g)))
    return {"M": M, "gamma": gamma}


def state_near_rotation(
    code: ModelCode,
    params: Mapping,
    axis: int,
    C: mpmath.mpf,
    n: mpmath.mpf,
    offset: mpmath.mpf | int = 0,
) -> ResolvedState:
    """The steady rotation about body axis ``axis`` (K01 (3.2): branch ``p_axis`` of the diagram)
    at ``C = (M, gamma)`` and ``n = (M, M)``, optionally pushed off it by ``offset``.

    On the rotation ``omega = w e_i`` and ``gamma = g_i e_i + sqrt(1 - g_i^2) e_j`` (``j`` the next
    axis), ``M = I omega + D gamma x (omega x gamma) = J_i w e_i - D g_i w gamma``, so
    ``C = I_i w g_i`` and ``n = J_i^2 w^2 - (2 J_i D - D^2) C^2/I_i^2``. ``offset`` adds
    ``offset |M|`` to the component of ``M`` along the third axis ``k`` (a documented push off
    the periodic solution; the residuals then show how far the integrals moved).

    Parameters
    ----------
    code : ModelCode
    params : mapping
        Parameter values by symbol (``I1, I2, I3, D``).
    axis : int
        1, 2 or 3.
    C, n : mpmath.mpf
    offset : mpmath.mpf

    Returns
    -------
    ResolvedState

    Raises
    ------
    UserInputError
        No such rotation at these ``C, n`` (the message gives the admissible ``n``).
    """
    I = [mpmath.mpf(params[f"I{i}"]) for i in (1, 2, 3)]
    D = mpmath.mpf(params["D"])
    i = axis - 1
    Ji = I[i] + D
    w2 = (n + (2 * Ji * D - D * D) * C * C / I[i] ** 2) / Ji**2
    n_min = (Ji**2 - (2 * Ji * D - D * D)) * C * C / I[i] ** 2  # where |g_i| = 1
    if w2 <= 0 or (C != 0 and abs(C / (I[i] * mpmath.sqrt(w2))) > 1):
        raise UserInputError(
            f"no rotation about axis {axis} has C = {mpmath.nstr(C, 10)} and n = "
            f"{mpmath.nstr(n, 10)}: admissible n >= {mpmath.nstr(n_min, 10)}"
        )
    w = mpmath.sqrt(w2)
    gi = C / (I[i] * w)
    j, k = (i + 1) % 3, (i + 2) % 3
    gamma = [mpmath.mpf(0)] * 3
    gamma[i], gamma[j] = gi, mpmath.sqrt(1 - gi * gi)
    M = [-D * gi * w * g for g in gamma]
    M[i] += Ji * w
    size = mpmath.sqrt(sum(m * m for m in M))
    M[k] += offset * size
    how = (
        f"steady rotation about body axis {axis} (K01 (3.2), branch p{axis}): omega = "
        f"{mpmath.nstr(w, 12)} e{axis}, gamma{axis} = {mpmath.nstr(gi, 12)}"
        + (f"; M{k + 1} pushed by offset |M| = {mpmath.nstr(offset * size, 6)}" if offset else "")
    )
    prescribed = {integral_name(code, "C"): C, integral_name(code, "n"): n}
    return ResolvedState({"M": M, "gamma": gamma}, how, prescribed)


# ------------------------------------------------------------------------ the one entry
#: BM20's Andoyer-Deprit variables (3.7), in their order.
ANDOYER = ("G", "z", "l", "g")

#: Keys of a request that are not state groups (a state group of the model is a key too).
REQUEST_KEYS = (
    *INTEGRAL_KEYS,
    "point",
    *ANDOYER,
    "rest",
    "near",
    "separatrix",
    "offset",
    "integrals",
    "free",
)

#: Keys that choose how (not what): left out of the state groups and integrals given.
_CHOICE_KEYS = (
    "parallel",
    "point",
    "rest",
    "near",
    "separatrix",
    "offset",
    "integrals",
    "free",
    *ANDOYER,
)


class InitialStateError(UserInputError):
    """A request :func:`initial_state` cannot use.

    Attributes
    ----------
    key : str or None
        The request key the message is about (``"h"``, ``"near"``, a state group), or None for
        the request as a whole.
    """

    def __init__(self, message: str, key: str | None = None):
        super().__init__(message)
        self.key = key


@dataclass
class InitialState:
    """An initial state chosen from a request.

    Attributes
    ----------
    y0 : list of float or mpmath.mpf
        The state in the model's order at the working precision.
    how : str
        How it was chosen (``"given by state"``, the level-set point, the rotation, ...).
    prescribed : dict of str to mpmath.mpf
        The integral values asked for, by the model's integral name (empty when none).
    residuals : dict of str to float
        ``F(y0) - prescribed`` for each, with the model's generated integrals.
    """

    y0: list
    how: str = "given by state"
    prescribed: dict = field(default_factory=dict)
    residuals: dict = field(default_factory=dict)


@dataclass
class _Request:
    """A request split by role: state groups, integrals, Andoyer-Deprit variables, choices."""

    given: dict
    by_integrals: dict
    andoyer: dict
    choices: dict


def _split(code: ModelCode, request: Mapping[str, object]) -> _Request:
    """The request by role, with ``rest`` applied; the structural refusals of
    :func:`check_initial_request`."""
    items = {k: v for k, v in request.items() if v is not None}
    choices = {
        "parallel": bool(items.get("parallel", False)),
        "point": items.get("point"),
        "rest": bool(items.get("rest", False)),
        "near": items.get("near"),
        "separatrix": items.get("separatrix"),
        "offset": items.get("offset", 0),
        "integrals": dict(items.get("integrals") or {}),
        "free": list(items.get("free") or []),
    }
    given = {k: v for k, v in items.items() if k not in _CHOICE_KEYS}
    if choices["parallel"]:
        given["parallel"] = True
    andoyer = {k: items[k] for k in ANDOYER if k in items}
    if choices["free"] and not choices["integrals"]:
        raise InitialStateError("free needs integrals = { NAME = value, ... }", "free")
    if choices["rest"]:
        andoyer.setdefault("G", 0)
        if "M" in given or (andoyer.get("G") not in (0, "0")):
            raise InitialStateError("rest = true means M = 0: give no M and no G", "rest")
        if "gamma" in given:
            given["M"] = [0, 0, 0]
    by_integrals = {k: given.pop(k) for k in INTEGRAL_KEYS if k in given}
    state_groups = code.state_groups
    for k in given:
        if k not in state_groups:
            valid = [*state_groups, *INTEGRAL_KEYS, "point"]
            raise InitialStateError(
                f"{code.name} has no state {k!r}; valid: {', '.join(valid)}"
                f"{did_you_mean(k, valid)}",
                k,
            )
    return _Request(given, by_integrals, andoyer, choices)


def check_initial_request(code: ModelCode, request: Mapping[str, object]) -> None:
    """Refuse a request whose keys cannot work for ``code`` (an unknown state group, ``rest``
    with ``M`` or ``G``) before anything is computed; :func:`initial_state` checks the rest.

    Parameters
    ----------
    code : ModelCode
    request : mapping of str to value
        As for :func:`initial_state`.

    Raises
    ------
    InitialStateError
    """
    _split(code, request)


def initial_state(
    code: ModelCode,
    params: Mapping[str, object],
    request: Mapping[str, object],
    precision: Any,
    expressions: Mapping[str, str] | None = None,
) -> InitialState:
    """The initial state a request asks for, at the working precision (see the module).

    Parameters
    ----------
    code : ModelCode
        The model.
    params : mapping of str to number
        Parameter values by symbol (``I1, I2, I3, D, ...``) at the working precision.
    request : mapping of str to value
        State groups of the model (``M``, ``gamma``, ...) and the keys of :data:`REQUEST_KEYS`:
        ``h``, ``C``, ``n``, ``parallel`` (bool), ``point`` (int; with ``integrals``: the
        k-th point of :mod:`chaplygin.numerics.level_points`), ``G, z, l, g``, ``rest``
        (bool), ``near`` (``"p1"``..``"p3"``), ``separatrix`` (1..3), ``offset``,
        ``integrals`` (name -> value) with ``free`` (components or groups solved for:
        :mod:`chaplygin.numerics.integral_levels`). Values are numbers or text
        :func:`~chaplygin.numerics.inputs.parse_number` reads; None means absent.
    precision : Precision
        The working precision (the request is read at ``precision.parse_dps`` digits).
    expressions : mapping of str to str, optional
        Integrals ``integrals`` may name beside the model's: name -> expression of the state,
        ``omega1..3`` and the parameters (a described system's ``[[claims]]``).

    Returns
    -------
    InitialState

    Raises
    ------
    InitialStateError
        A request that cannot be used; ``key`` names the key at fault.
    UserInputError
        A number the parser refuses where no key is at fault.

    References
    ----------
    K01 (3.2), K01 §3.3, BM20 (3.7), BKM12-7 (FORMULAS.md).
    """
    from ..inputs import complete_state

    req = _split(code, request)
    given, by_integrals, andoyer, choices = req.given, req.by_integrals, req.andoyer, req.choices
    prescribed: dict = {}
    how = "given by state"
    dps = precision.parse_dps
    special = _near_or_separatrix(code, params, req, dps)
    if special is not None:
        given.update(special[0])
        prescribed, how = special[1], special[2]
    if andoyer and not (choices["rest"] and set(andoyer) == {"G"} and "gamma" in given):
        values = _from_andoyer(andoyer, given, by_integrals, dps)
        given.update(values)
        how = "Andoyer-Deprit variables G, z, l, g (BM20 (3.7))"
    elif choices["rest"]:
        if "gamma" not in given:
            raise InitialStateError(
                "rest = true needs gamma (or the Andoyer-Deprit z, l, g)", "rest"
            )
        how = "from rest (M = 0)"
    if choices["integrals"]:
        return _on_levels(code, params, req, precision, dict(expressions or {}))
    if set(by_integrals) == {"h"} and "M" in given and not prescribed:
        given["M"], prescribed, how = _scaled_to_energy(
            code, params, given, by_integrals["h"], precision
        )
    elif by_integrals and not prescribed:
        resolved = _from_integrals(
            code, params, by_integrals, given, choices["point"] or 0, dps
        )
        prescribed, how = resolved.prescribed, resolved.how
        given.update({k: [mpmath.nstr(c, dps + 5) for c in v] for k, v in resolved.values.items()})
    try:
        state = complete_state(code, given, precision)
    except UserInputError as exc:
        raise InitialStateError(str(exc)) from None
    for note in state.notes:
        how += f"; {note}"
    residuals = {}
    if prescribed:
        p = [params[k] for k in code.params]
        residuals = integral_residuals(
            code, state.y, p, prescribed, max(precision.digits or 17, 17)
        )
    return InitialState(state.y, how, prescribed, residuals)


def _on_levels(code, params, req: _Request, precision, expressions) -> InitialState:
    """``integrals`` with ``free``: :func:`chaplygin.numerics.integral_levels.state_on_levels`
    (the other ways of giving integrals, Andoyer-Deprit and the named solutions excluded)."""
    from ..inputs import complete_state
    from ..integral_levels import LevelRequest, level_values, state_on_levels
    from ..level_points import point_on_levels

    choices = req.choices
    clash = [*req.by_integrals, *req.andoyer] + [
        k for k in ("rest", "near", "separatrix") if choices[k]
    ]
    if clash:
        raise InitialStateError(f"give integrals = {{...}} or {clash[0]}, not both", clash[0])
    free = choices["free"] or list(code.state_groups)[:1]
    point = choices["point"]
    request = LevelRequest(
        req.given, free, choices["integrals"], expressions, None if point is None else int(point)
    )
    try:
        solve = state_on_levels if point is None else point_on_levels
        values, prescribed, how = solve(code, params, request, precision)
        state = complete_state(code, {**req.given, **values}, precision)
        p = [params[k] for k in code.params]
        dps = max(precision.digits or 17, 17)
        reached = level_values(code, state.y, p, list(prescribed), expressions, dps)
    except UserInputError as exc:
        raise InitialStateError(str(exc), getattr(exc, "key", "integrals")) from None
    with mpmath.workdps(dps):
        residuals = {n: float(reached[n] - _num(prescribed[n], dps)) for n in prescribed}
    for note in state.notes:
        how += f"; {note}"
    return InitialState(state.y, how, prescribed, residuals)


def _scaled_to_energy(code, params, given, h, precision) -> tuple[list, dict, str]:
    """``M`` (a direction) scaled by ``s > 0`` so that the energy ``H`` is ``h``.

    For any model whose energy is ``T(M) + V(configuration)`` with ``T`` quadratic in the
    momentum (the ball, the gyrostat, a described body with a potential): ``H(s M) = V +
    s^2 T``, so ``s = sqrt((h - V) / T)``. The form is checked at ``s = 0, 1, 2`` (and
    refused otherwise) before it is used.
    """
    from ..inputs import complete_state

    dps = precision.parse_dps
    if "H" not in code.integral_names:
        raise InitialStateError(f"{code.name} ships no energy H to scale M to", "h")
    p = [params[k] for k in code.params]
    with mpmath.workdps(dps + 10):
        direction = [_num(v, dps) for v in given["M"]]
        target = _num(h, dps)

        def energy(scale):
            trial = {**given, "M": [mpmath.nstr(scale * c, dps + 10) for c in direction]}
            try:
                y = complete_state(code, trial, precision).y
            except UserInputError as exc:
                raise InitialStateError(str(exc)) from None
            values = code.mpmath.integrals(
                mpmath.mpf(0), [mpmath.mpf(v) for v in y], [mpmath.mpf(v) for v in p]
            )
            return values[code.integral_names.index("H")]

        V, H1, H2 = energy(0), energy(1), energy(2)
        T = H1 - V
        tol = mpmath.mpf(10) ** (-(dps // 2)) * (1 + abs(H1) + abs(V))
        if abs((H2 - V) - 4 * T) > tol:
            raise InitialStateError(
                f"the energy of {code.name} is not quadratic in M plus a function of the "
                "configuration: give M and gamma, or the integrals, not M and h",
                "h",
            )
        if T <= 0 or target < V:
            raise InitialStateError(
                f"no multiple of the given M reaches the energy h = {mpmath.nstr(target, 8)} "
                f"(the configuration's potential alone is {mpmath.nstr(V, 8)})",
                "h",
            )
        scale = mpmath.sqrt((target - V) / T)
        scaled = [mpmath.nstr(scale * c, dps + 5) for c in direction]
    how = "M given as a direction, scaled to the energy h (H = V + s^2 T)"
    return scaled, {"H": h}, how


def _num(value: object, dps: int):
    from ..inputs import parse_number

    return parse_number(value, dps + 10)


def _from_andoyer(andoyer: dict, given: dict, by_integrals: dict, dps: int) -> dict:
    """``M, gamma`` (text at ``dps + 5`` digits) from ``G, z, l, g``."""
    missing = [k for k in ANDOYER if k not in andoyer]
    clash = [k for k in ("M", "gamma") if k in given] + list(by_integrals)
    if missing:
        raise InitialStateError(
            f"initial.{missing[0]} is missing (Andoyer-Deprit needs G, z, l, g)", missing[0]
        )
    if clash:
        raise InitialStateError(
            f"give the Andoyer-Deprit variables or {clash[0]}, not both", clash[0]
        )
    with mpmath.workdps(dps + 10):
        try:
            values = state_from_andoyer(*(_num(andoyer[k], dps) for k in ANDOYER))
        except UserInputError as exc:
            raise InitialStateError(str(exc), "z" if "z =" in str(exc) else "G") from None
        return {k: [mpmath.nstr(c, dps + 5) for c in v] for k, v in values.items()}


def _from_integrals(code, params, by_integrals, given, point, dps) -> ResolvedState:
    """:func:`state_from_integrals` on the request's integrals (and ``gamma``, if given)."""
    if "M" in given:
        raise InitialStateError("give M or the integrals (h, C, n, parallel), not both", "M")
    request = {**by_integrals, "point": point}
    if "gamma" in given:
        request["gamma"] = given["gamma"]
    try:
        num = {
            k: (v if isinstance(v, bool) else _num(v, dps))
            for k, v in request.items()
            if k != "gamma"
        }
        if "gamma" in request:
            num["gamma"] = [_num(v, dps) for v in request["gamma"]]
        return state_from_integrals(code, {k: mpmath.mpf(v) for k, v in params.items()}, num, dps)
    except UserInputError as exc:
        key = "h" if "energy" in str(exc) else None
        raise InitialStateError(str(exc), key if key in by_integrals else None) from None


def _near_or_separatrix(code, params, req: _Request, dps: int):
    """``near = "p_i"`` or ``separatrix = i``: ``(state groups, prescribed, how)`` or None (the
    separatrix becomes a request by integrals: ``h`` and ``parallel``)."""
    choices, given, by_integrals = req.choices, req.given, req.by_integrals
    near, separatrix, offset = choices["near"], choices["separatrix"], choices["offset"]
    if near is None and separatrix is None:
        if offset not in (0, "0"):
            raise InitialStateError("offset needs near or separatrix", "offset")
        return None
    key = "near" if near is not None else "separatrix"
    clash = [k for k in ("M", "gamma") if k in given] + [
        k for k in by_integrals if k not in (("C", "n") if key == "near" else ("C",))
    ]
    if near is not None and separatrix is not None:
        clash.append("separatrix")
    if clash or choices["parallel"]:
        raise InitialStateError(f"{key} fixes the state: give no {(clash or ['parallel'])[0]}", key)
    if "K1" in code.params or "I1" not in code.params or "D" not in code.params:
        raise InitialStateError(f"{key} is defined for chaplygin_ball without gyrostat", key)
    need = ("C", "n") if key == "near" else ("C",)
    missing = [k for k in need if k not in by_integrals]
    if missing:
        raise InitialStateError(f"{key} needs initial.{missing[0]}", key)
    with mpmath.workdps(dps + 10):
        C = _num(by_integrals["C"], dps)
        push = _num(offset, dps)
        p = {k: mpmath.mpf(v) for k, v in params.items()}
        if key == "near":
            try:
                n = _num(by_integrals["n"], dps)
                r = state_near_rotation(code, p, int(near[1]), C, n, push)
            except UserInputError as exc:
                raise InitialStateError(str(exc), key) from None
            values = {k: [mpmath.nstr(c, dps + 5) for c in v] for k, v in r.values.items()}
            by_integrals.clear()
            return values, r.prescribed, r.how
        I = sorted((p[f"I{i}"], i) for i in (1, 2, 3))
        if separatrix != I[1][1]:
            raise InitialStateError(
                f"the separatrix on M || gamma belongs to the middle axis, here {I[1][1]} "
                f"(I = {', '.join(mpmath.nstr(v, 8) for v, _ in sorted(I, key=lambda t: t[1]))})",
                key,
            )
        h = C * C / (2 * p[f"I{separatrix}"]) * (1 + push)
        request = {"C": by_integrals["C"], "h": mpmath.nstr(h, dps + 5), "parallel": True}
        by_integrals.clear()
        by_integrals.update(request)
        return None
