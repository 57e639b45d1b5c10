"""A body in a spherical support of balls as a :class:`~.rolling_system.RollingSystem`.

``RollingSystem(..., support="balls", balls=[{"moment": ..., "ratio": ..., "direction":
...}, ...])`` is Fedorov's body in a spherical support (BKM12 §2.1-2.3): the body (the
given ``inertia``, a constant ``gyrostat``) is enclosed in a spherical shell centred at its
centre of mass; each ball (moment of inertia ``lambda_k``, radius ratio ``r_k = R_k/R0``)
has a fixed centre and touches the shell at the space-fixed unit direction ``n_k`` (three
exact numbers, normalised). The balls roll on the shell without slipping (``contact =
"rolling"``, BKM12-27) or also without twisting (``"rubber"``, BKM12-39: the effect
``rubber_balls`` of the built-in support).

The model is the N-ball reduction of :mod:`.spherical_support` (the multi-body Ferrers
equations reduced by projection, :class:`~.spherical_support.NBallReduction`) on the
user's data: state ``M = II omega`` (without ``K``) and the body components ``alpha, beta,
gamma`` of the space axes; it ships the closed model's integrals, which hold for any ``N``
(``H = (M, omega)/2``, ``(M + K, alpha)`` ..., ``(M + K, M + K)``, the frame's relations)
and the density ``det(II)^-1/2``. The entries of ``II`` are polynomials of the frame with
rational coefficients (the radicals of normalised directions cancel). In any placement of
the balls (a support tensor ``sum_k lambda_k/r_k^2 n_k n_k^T`` diagonal in the space axes
or not) ``chaplygin verify --system`` proves ``H`` and the density in seconds, in the
coordinates ``(omega, alpha, beta, gamma)`` (:mod:`chaplygin.verify.omega_coordinates`:
one denominator ``det II``); expanded in ``M`` (powers of ``det II``) they took minutes.

The centre of mass is the shell's centre and does not move: the body's ``mass`` and
``radius`` (the shell's ``R0``) do not enter (the ratios carry the radii); they are read
and checked as for any body but are not parameters. Refused in one line, on construction:
a centre of mass off the centre, gravity, a potential, rolling along a line, a
time-dependent inertia or gyrostat, the fields of other supports, balls on another
support, no balls, a ball that is not ``{moment, ratio, direction}``, a direction that is
not three numbers or is zero, a moment or ratio that is not positive.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import sympy as sp

from .description import MechanicalDescription, apply_effects
from .errors import UserInputError
from .expression_text import parse_expression
from .rolling_surfaces import _declare_parameters
from .spherical_support import on_space_frame
from .support_derivation import SUPPORTED_EFFECTS, add_balls, support_body
from .support_parameters import unit_exact
from .vectors import dot, vector

if TYPE_CHECKING:
    from .rolling_system import RollingSystem

__all__ = ["BALL_KEYS", "ball_values", "read_balls", "balls_description"]

#: The entries of a ball, each required.
BALL_KEYS = ("moment", "ratio", "direction")
#: The built-in support's effects a contact is (no twist: BKM12-39).
_CONTACT_EFFECTS = {"rolling": (), "rubber": ("rubber_balls",)}


def _ball_tables(s: RollingSystem) -> list[Mapping[str, Any]]:
    """The balls as given, each checked to be a table of :data:`BALL_KEYS`."""
    if s.balls is None:
        return []
    if isinstance(s.balls, (str, bytes, Mapping)) or not isinstance(s.balls, Sequence):
        raise UserInputError(f"balls: expected a list of balls, got {s.balls!r}")
    for k, ball in enumerate(s.balls, start=1):
        if not isinstance(ball, Mapping) or set(ball) != set(BALL_KEYS):
            raise UserInputError(
                f"ball {k}: expected a table with the keys {', '.join(BALL_KEYS)}, got {ball!r}"
            )
    return list(s.balls)


def ball_values(s: RollingSystem) -> list[Any]:
    """The balls' moments and ratios as typed (their names become parameters).

    Parameters
    ----------
    s : RollingSystem

    Returns
    -------
    list
        ``lambda_1, r_1, lambda_2, r_2, ...`` (empty without balls).

    Raises
    ------
    UserInputError
        ``balls`` not a list of tables ``{moment, ratio, direction}``.
    """
    return [ball[key] for ball in _ball_tables(s) for key in ("moment", "ratio")]


def read_balls(
    s: RollingSystem, read: Callable[[Any, str], sp.Expr], parsed: dict
) -> tuple[tuple[sp.Expr, sp.Expr, sp.Matrix], ...] | None:
    """The balls read exactly, and what a support of balls refuses.

    Parameters
    ----------
    s : RollingSystem
    read : callable
        Reads a typed value with the description's parameters (``read(value, what)``).
    parsed : dict
        The body as read: ``centre``, ``field``, ``potential``, ``inertia``,
        ``rotor_momentum``.

    Returns
    -------
    tuple of (sympy.Expr, sympy.Expr, sympy.Matrix) or None
        ``(lambda_k, r_k, n_k)`` for each ball (``n_k`` the exact unit direction); None on
        another support.

    Raises
    ------
    UserInputError
        See the module docstring.
    """
    tables = _ball_tables(s)
    if s.support != "balls":
        if s.balls is not None:
            raise UserInputError(f"balls are given but the support is a {s.support}")
        return None
    if not tables:
        raise UserInputError(
            "support 'balls' needs balls: a list of {moment, ratio, direction}, one a ball"
        )
    t = sp.Symbol("t", real=True)
    refused = {
        "a centre of mass off the shell's centre": not parsed["centre"].is_zero_matrix,
        "gravity": s.gravity is not None,
        "a potential": s.potential is not None,
        "rolling along a line (contact 'line')": s.contact == "line",
        "a time-dependent inertia": parsed["inertia"].has(t),
        "a prescribed rotor K(t)": parsed["rotor_momentum"].has(t),
    }
    for what, present in refused.items():
        if present:
            raise UserInputError(
                f"support 'balls' (a body in a spherical support) does not take {what}"
            )
    return tuple(_read_ball(k, ball, read) for k, ball in enumerate(tables))


def _read_ball(
    k: int, ball: Mapping[str, Any], read: Callable[[Any, str], sp.Expr]
) -> tuple[sp.Expr, sp.Expr, sp.Matrix]:
    """``(lambda_k, r_k, n_k)`` of ball ``k`` (from 0): positive moment and ratio, an exact
    unit direction."""
    values = []
    for key in ("moment", "ratio"):
        value = read(ball[key], f"ball {k + 1} {key}")
        if value.is_positive is False or value.is_zero:
            raise UserInputError(f"ball {k + 1}: the {key} must be positive, got {value}")
        values.append(value)
    d = ball["direction"]
    if isinstance(d, (str, bytes, Mapping)) or not isinstance(d, (Sequence, sp.MatrixBase)):
        raise UserInputError(f"ball {k + 1}: the direction must be three numbers, got {d!r}")
    what = f"ball {k + 1} direction"
    entries = [parse_expression(c, {"pi": sp.pi}, what) for c in d]
    return values[0], values[1], unit_exact(entries, k)


def balls_description(s: RollingSystem, moments: tuple[sp.Symbol, ...]) -> MechanicalDescription:
    """The body on the described balls, with the N-ball model's state and stage.

    ``T = (omega, I omega)/2 + (K, omega) + sum_k lambda_k (omega_k, omega_k)/2``, no slip
    at each ball (BKM12-27; rubber: also no twist, BKM12-39).

    Parameters
    ----------
    s : RollingSystem
        With ``support="balls"``.
    moments : tuple of sympy.Symbol
        The symbols the principal moments are (none unless three distinct symbols).

    Returns
    -------
    MechanicalDescription
        State ``M`` and the frame ``alpha, beta, gamma``; the stage
        :class:`~.spherical_support.NBallReduction` shipping the integrals and the density.
    """
    p = s._parsed
    balls = p["balls"]
    desc = support_body(s.name, frozenset(), inertia=p["inertia"], moments=moments)
    add_balls(desc, len(balls), [b[0] for b in balls], [b[1] for b in balls])
    desc.add_kinetic_energy(dot(p["rotor_momentum"], desc.omega))
    apply_effects(desc, _CONTACT_EFFECTS[s.contact], SUPPORTED_EFFECTS)
    desc.add_state("M", tuple(vector("M", real=True)), None)
    desc.parameter_order = tuple(x.name for x in p["parameters"])
    _declare_parameters(desc, p)
    desc.references.update(
        equations="BKM12-31", momentum="BKM12-2.1M", integrals="BKM12-35,36,37,Rem2",
        density="BKM12-38",
    )  # fmt: skip
    return on_space_frame(desc, [b[2] for b in balls], conserved=True)
