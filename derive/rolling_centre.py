"""A described homogeneous ball named by the surface its *centre* moves on (M03 §1).

``RollingSystem(support="surface", centre_surface="F(x1, x2, x3)")``: the support is the
surface parallel to ``F = 0`` at the ball's radius (outside), given through the surface of
the centre ``x`` (fixed frame, ``x3`` up), as M03 writes the ball on an ellipsoid; the
potential may be any expression of the centre ``x1, x2, x3`` (a force on the centre, M03-1.6's
kind) and gravity acts along ``-x3``. The stage is
:class:`~.ball_on_surface.FixedFrameReduction` (state ``omega`` in the fixed frame and the
centre ``x``), the built-in ball on a surface's own; the description is its public door, and
the built-in ``ball_on_surface`` is one (:mod:`.builtin_descriptions`). A body other than a
homogeneous ball is refused in one line: with a scalar inertia the fixed-frame angular
momentum does not depend on the attitude, which this stage needs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import sympy as sp

from .ball_on_surface import FixedFrameReduction
from .description import MechanicalDescription
from .errors import UserInputError
from .rolling_surfaces import CENTRE, _declare_parameters, _homogeneous, read_fixed_surface
from .vectors import vector

if TYPE_CHECKING:
    from .rolling_system import RollingSystem

__all__: list[str] = []

def _read_centre_surface(s: RollingSystem, scope: dict, parsed: dict) -> sp.Expr | None:
    """``F(x)`` of the centre's surface; what it refuses (anything but a homogeneous ball
    rolling without slipping, the support surface given too)."""
    if s.centre_surface is None:
        return None
    if s.support != "surface":
        raise UserInputError(f"centre_surface is given but the support is a {s.support}")
    if s.support_surface is not None:
        raise UserInputError("give support_surface (the contact's) or centre_surface, not both")
    plain = (
        _homogeneous(parsed)
        and not parsed["inertia"].has(sp.Symbol("t", real=True))
        and s.surface is None
        and s.contact == "rolling"
    )
    if not plain:
        raise UserInputError(
            "with centre_surface this version derives a homogeneous ball (equal moments, centre "
            "of mass at its centre, no rotor) rolling without slipping"
        )
    return read_fixed_surface(s.centre_surface, scope, CENTRE, "centre_surface")


def _centre_surface_description(s: RollingSystem) -> MechanicalDescription:
    """The ball whose centre moves on ``F(x) = 0``: state ``omega`` and ``x`` (fixed frame),
    ``I = m_e b^2``, the potential of the centre plus ``m g x3``; the level of ``F`` an
    integral (the equations hold on each level)."""
    p = s._parsed
    omega = vector("omega", real=True)
    x = sp.Matrix(list(CENTRE.values()))
    m, b, F = p["mass"], p["radius"], p["centre_surface"]
    desc = MechanicalDescription(
        system=s.name,
        effects=frozenset(),
        time=sp.Symbol("t", real=True),
        omega=omega,
        reduction=FixedFrameReduction(F, m, p["inertia"][0, 0] / b**2, b),
        parameter_order=tuple(x.name for x in p["parameters"]),
    )
    desc.add_state("omega", tuple(omega), None)
    desc.add_state("x", tuple(x), None)
    desc.add_potential(p["potential"] + m * p["field"] * x[2])
    level = F - F.xreplace(dict.fromkeys(x, 0))
    desc.add_integral("F", sp.expand(level))  # up to a constant
    _declare_parameters(desc, p)
    return desc
