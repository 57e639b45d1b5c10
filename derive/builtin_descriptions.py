"""The built-in systems as :class:`~.rolling_system.RollingSystem` descriptions (issue 24).

:func:`builtin_description` gives, for a built-in system and a combination of its
effects, the public description of that variant and the identification of the two
models' names: the built-in ball's ``D`` is the description's ``m b^2``; with
``variable_gyrostat`` the built-in's state ``M`` is BM20's total momentum, which includes
the rotors' ``k(t) = K sin(Omega t)``, while the description's ``M`` does not.

The claims still run on the built-in modules (:data:`~.systems.SYSTEM_MODULES`, their
code in ``generated/``); that the description derives the same model after the
identification — the same vector field, integrals and density — is proved by
``tests/derive/test_builtin_descriptions.py``, exactly (sympy, not sampling).

The ball on a surface is named by the surface its *centre* moves on (``centre_surface``,
the ellipsoid ``(x, B^-1 x) = 1``), with ``I = m_e R^2`` and its ``potential`` of the centre
(M03-1.6): no identification is needed.

The body in a spherical support is a description on balls (``support="balls"``): three
balls along ``alpha, beta, gamma`` with moments ``lambda_k`` and ratios ``r_k``, whose
weights ``w_k`` (:func:`~.support_derivation.ball_weight`: ``lambda_k/r_k^2``, rubber
``lambda_k (1/r_k^2 - 1)``) give the closed model's ``D_al = w1 - w3``, ``D_be = w2 - w3``
and ``D_iso = sum_k lambda_k/r_k^2 - w3`` (BKM12-33, 2.2: ``w1 + w2`` for rolling balls,
``lambda1/r1^2 + lambda2/r2^2 + lambda3`` for rubber ones). The two models are equal on the
phase space (the closed one writes ``gamma⊗gamma`` as ``Id - alpha⊗alpha - beta⊗beta``), and
the closed model's density ``det(X)^-1/2`` is ``sqrt(det(J) D_al D_be)`` times the
description's ``det(II)^-1/2`` (:attr:`BuiltinDescription.density_factor`). What a
description cannot express is refused in one line (no built-in is, in this version).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from itertools import combinations
from typing import Any

import sympy as sp

from .effects import parse_effects
from .errors import UserInputError
from .expression_text import parse_expression
from .model import Model
from .rolling_system import RollingSystem
from .support_derivation import ball_weight
from .systems import get_system, variant_name

__all__ = ["BuiltinDescription", "builtin_description", "expressible_variants"]


@dataclass(frozen=True)
class BuiltinDescription:
    """A built-in variant written as a :class:`~.rolling_system.RollingSystem`.

    Attributes
    ----------
    system : str
        The built-in system (``"chaplygin_ball"``).
    effects : frozenset of str
        The built-in variant's effects.
    description : RollingSystem
        The description of the same mechanics.
    described_effects : tuple of str
        The effects the description's model is derived with (``contact_point`` ...).
    identification : dict of str to str
        Each built-in name that is not the description's by the same name, as an
        expression in the description's names (parameters, state, time ``t``):
        ``{"D": "m*b**2"}``; with ``variable_gyrostat`` also ``"M1": "M1 +
        K1*sin(Omega*t)"`` ... (a change of state).
    note : str
        One line on what the identification means.
    density_factor : str
        The built-in density over the description's, in the built-in's names (a density
        is defined up to a constant factor); empty: 1.
    """

    system: str
    effects: frozenset[str]
    description: RollingSystem
    described_effects: tuple[str, ...] = ()
    identification: dict[str, str] = field(default_factory=dict)
    note: str = ""
    density_factor: str = ""

    @property
    def variant(self) -> str:
        """The built-in variant's name (``chaplygin_ball__rubber``)."""
        return variant_name(self.system, self.effects)

    def model(self) -> Model:
        """Derive the description's model (not cached).

        Returns
        -------
        Model
            :meth:`RollingSystem.model` with :attr:`described_effects`.
        """
        return self.description.model(self.described_effects)

    def substitution(self, builtin: Model, described: Model) -> dict[sp.Symbol, sp.Expr]:
        """The identification as a substitution of the built-in model's symbols.

        Parameters
        ----------
        builtin : Model
            The built-in variant's model (:func:`~.systems.build_model`).
        described : Model
            The model of :meth:`model`.

        Returns
        -------
        dict of sympy.Symbol to sympy.Expr
            Every state and parameter symbol of ``builtin`` (and its time) to an
            expression in ``described``'s symbols: the identification's expression, or
            the described symbol of the same name.

        Raises
        ------
        UserInputError
            When a built-in name is neither identified nor a name of ``described``.
        """
        names: dict[str, sp.Expr] = {
            s.name: s for s in (*described.state, *described.params, described.time)
        }
        out: dict[sp.Symbol, sp.Expr] = {builtin.time: described.time}
        for s in (*builtin.state, *builtin.params):
            text = self.identification.get(s.name)
            if text is not None:
                out[s] = parse_expression(text, names, f"identification of {s.name}")
            elif s.name in names:
                out[s] = names[s.name]
            else:
                raise UserInputError(
                    f"{self.variant}: {s.name} is neither identified nor a name of the description"
                )
        return out

    def call(self) -> str:
        """The description as the ``RollingSystem(...)`` call that makes it.

        Returns
        -------
        str
            The call with the fields that differ from their defaults.
        """
        d = self.description
        fields = [repr(d.name)]
        defaults = RollingSystem.__dataclass_fields__
        keys = ("inertia", "mass", "radius", "gyrostat", "contact", "support", "centre_surface",
                "balls")  # fmt: skip
        for key in (*keys, "potential", "positive"):
            value = getattr(d, key)
            if value != defaults[key].default and value:
                fields.append(f"{key}={_plain(value)}")
        text = f"RollingSystem({', '.join(fields)})"
        if self.described_effects:
            text += f".model({list(self.described_effects)!r})"
        return text


def _plain(value: object) -> str:
    """A tuple of strings as Python writes it."""
    if isinstance(value, tuple):
        return "(" + ", ".join(repr(v) for v in value) + ")"
    return repr(value)


#: BM20-3.4: the moving pair of masses adds this to I1 and I3.
_PAIR = "(J_off + delta*sin(Omega*t))**2"

#: What each effect of the ball sets in its description, as data: fields of the
#: RollingSystem, names known positive, the description's effects, identifications, notes.
_BALL_EFFECTS: dict[str, dict[str, Any]] = {
    "gyrostat": {"fields": {"gyrostat": ("K1", "K2", "K3")}},
    "variable_gyrostat": {  # BM20-3.5; the built-in state is the total momentum
        "fields": {"gyrostat": tuple(f"K{i}*sin(Omega*t)" for i in (1, 2, 3))},
        "positive": ("Omega",),
        "identification": {f"M{i}": f"M{i} + K{i}*sin(Omega*t)" for i in (1, 2, 3)},
        "note": "the built-in state M is BM20's total momentum, the description's M plus "
        "the rotors' k(t) = K sin(Omega t)",
    },
    "variable_inertia": {  # BM20-3.4
        "fields": {"inertia": (f"I1 + {_PAIR}", "I2", f"I3 + {_PAIR}")},
        "positive": ("I1", "I3", "Omega"),
    },
    "contact_point": {"described_effects": ("contact_point",)},
}
#: The effects that choose the contact, and the contact (with the description's effects)
#: each combination of them is: a rubber body along a line takes the effect.
_CONTACT_EFFECTS = frozenset({"rubber", "straight_line"})
_CONTACTS: dict[frozenset[str], tuple[str, tuple[str, ...]]] = {
    frozenset(): ("rolling", ()),
    frozenset({"rubber"}): ("rubber", ()),
    frozenset({"straight_line"}): ("line", ()),
    frozenset({"rubber", "straight_line"}): ("rubber", ("straight_line",)),
}


def _ball(effects: frozenset[str]) -> BuiltinDescription:
    """The Chaplygin ball: a balanced sphere of mass ``m`` and radius ``b``, D = m b^2."""
    fields: dict[str, Any] = {"inertia": ("I1", "I2", "I3")}
    positive: set[str] = set()
    described: list[str] = []
    identification = {"D": "m*b**2"}
    notes = ["D = m b^2 (the ball's mass m, radius b)"]
    for name in sorted(effects - _CONTACT_EFFECTS):
        part = _BALL_EFFECTS[name]
        fields.update(part.get("fields", {}))
        positive.update(part.get("positive", ()))
        described += part.get("described_effects", ())
        identification.update(part.get("identification", {}))
        notes += [part["note"]] if "note" in part else []
    contact, along = _CONTACTS[effects & _CONTACT_EFFECTS]
    system = RollingSystem(
        "described_chaplygin_ball",
        contact=contact,
        positive=tuple(sorted(positive)),
        description="the Chaplygin ball as a described system",
        **fields,
    )
    return BuiltinDescription(
        "chaplygin_ball", effects, system, (*described, *along), identification, "; ".join(notes)
    )


#: M03-1.6's potential of the centre (the effect ``potential`` of the ball on a surface).
_CENTRE_POTENTIAL = "k*(x1**2 + x2**2 + x3**2)/2 + (c1/x1**2 + c2/x2**2 + c3/x3**2)/2"


#: What each effect of the ball on a surface sets in its description (fields).
_SURFACE_EFFECTS: dict[str, dict[str, Any]] = {"potential": {"potential": _CENTRE_POTENTIAL}}


def _ball_on_surface(effects: frozenset[str]) -> BuiltinDescription:
    """M03's homogeneous ball (``I = m_e R^2``) whose centre moves on ``(x, B^-1 x) = 1``."""
    fields: dict[str, Any] = {}
    for name in sorted(effects):
        fields.update(_SURFACE_EFFECTS[name])
    system = RollingSystem(
        "described_ball_on_surface",
        inertia=("m_e*R**2",) * 3,
        mass="m",
        radius="R",
        support="surface",
        centre_surface="x1**2/b1 + x2**2/b2 + x3**2/b3 - 1",
        positive=("m_e", "b1", "b2", "b3"),
        description="M03's ball on an ellipsoid as a described system",
        **fields,
    )
    note = "the same names; the description ships H and the level of the centre's surface"
    return BuiltinDescription("ball_on_surface", effects, system, (), {}, note)


#: What each effect of the support sets in its description (fields).
_SUPPORT_EFFECTS: dict[str, dict[str, Any]] = {
    "gyrostat": {"gyrostat": ("K1", "K2", "K3")},
    "rubber_balls": {"contact": "rubber"},  # BKM12-39
}
#: Whether a contact leaves the balls' spins free (:func:`~.support_derivation.ball_weight`).
_SPIN_FREE = {"rolling": True, "rubber": False}


def _spherical_support(effects: frozenset[str]) -> BuiltinDescription:
    """Fedorov's body on three balls along the eigenframe ``alpha, beta, gamma`` of the
    support tensor (BKM12-33): ``D_sup = w1 alpha⊗alpha + w2 beta⊗beta + w3 gamma⊗gamma``."""
    fields: dict[str, Any] = {"contact": "rolling"}
    for name in sorted(effects):
        fields.update(_SUPPORT_EFFECTS[name])
    axes = ((1, 0, 0), (0, 1, 0), (0, 0, 1))
    balls = tuple(
        {"moment": f"lambda{k + 1}", "ratio": f"r{k + 1}", "direction": axes[k]} for k in range(3)
    )
    system = RollingSystem(
        "described_spherical_support",
        inertia=("I1", "I2", "I3"),
        support="balls",
        balls=balls,
        description="Fedorov's body on three balls along the support's eigenframe",
        **fields,
    )
    lam, r = sp.symbols("lambda1:4", positive=True), sp.symbols("r1:4", positive=True)
    w = [ball_weight(lam[k], r[k], _SPIN_FREE[fields["contact"]]) for k in range(3)]
    iso = sum((lam[k] / r[k] ** 2 for k in range(3)), sp.S.Zero)
    identification = {"D_iso": iso - w[2], "D_al": w[0] - w[2], "D_be": w[1] - w[2]}
    note = "D_iso = sum_k lambda_k/r_k^2 - w3, D_al = w1 - w3, D_be = w2 - w3 (w_k the weights)"
    return BuiltinDescription(
        "spherical_support", effects, system, (),
        {name: sp.sstr(sp.expand(value)) for name, value in identification.items()}, note,
        density_factor="sqrt((I1 + D_iso)*(I2 + D_iso)*(I3 + D_iso)*D_al*D_be)",
    )  # fmt: skip


#: How each built-in system is written as a description, or what a description lacks.
_WRITERS: dict[str, Callable[[frozenset[str]], BuiltinDescription] | str] = {
    "chaplygin_ball": _ball,
    "ball_on_surface": _ball_on_surface,
    "spherical_support": _spherical_support,
}


def builtin_description(
    system: str, effects: Iterable[str] | str | None = ()
) -> BuiltinDescription:
    """A built-in variant as a :class:`~.rolling_system.RollingSystem`, with the
    identification of the two models.

    Parameters
    ----------
    system : str
        A built-in system (``"chaplygin_ball"``, ...).
    effects : iterable of str or comma-separated str, optional
        Effects of that system.

    Returns
    -------
    BuiltinDescription
        The description, the effects its model takes and the identification
        (``D = m b^2`` ...).

    Raises
    ------
    UserInputError
        An unknown system or effect, a combination the system refuses, a system that is
        not built in, or a variant no description expresses (the message says what is
        missing).

    Examples
    --------
    >>> b = builtin_description("chaplygin_ball", ["rubber"])
    >>> b.call()
    "RollingSystem('described_chaplygin_ball', inertia=('I1', 'I2', 'I3'), contact='rubber')"
    >>> b.identification
    {'D': 'm*b**2'}
    """
    sysdef = get_system(system)
    writer = _WRITERS.get(system)
    if writer is None:
        raise UserInputError(f"{system!r} is not a built-in system: it is described already")
    chosen = parse_effects(effects, sysdef.effects)
    if isinstance(writer, str):
        raise UserInputError(f"{variant_name(system, chosen)} is not expressible: {writer}")
    return writer(chosen)


def expressible_variants() -> list[tuple[str, frozenset[str]]]:
    """Every effect combination of the built-in systems that a description expresses.

    Returns
    -------
    list of (str, frozenset of str)
        ``(system, effects)``: each combination the system accepts (its effects'
        exclusions respected), of the systems :func:`builtin_description` writes.
    """
    out = []
    for system, writer in _WRITERS.items():
        if isinstance(writer, str):
            continue
        supported = get_system(system).effects
        for k in range(len(supported) + 1):
            for combination in combinations(supported, k):
                try:
                    out.append((system, parse_effects(combination, supported)))
                except UserInputError:  # effects that exclude each other
                    continue
    return out
