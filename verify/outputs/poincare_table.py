"""The ``[outputs.poincare]`` table of scenes (its own module: the scene's schema imports it for
:class:`~chaplygin.verify.scene.schema.Outputs` without importing the analysis,
:mod:`chaplygin.verify.outputs.poincare`)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
)

__all__ = ["PoincareOutput"]


def _number(value: object) -> object:
    from ...numerics.inputs import parse_number

    parse_number(value, 30)  # refuses malformed, hostile or non-finite text
    return value


# the scene's schema imports this table, so the table imports nothing of the scene: these
# mirror schema.Number (without its description, which the JSON Schema would show) and its
# table base.
Number = Annotated[StrictInt | StrictFloat | StrictStr, AfterValidator(_number)]


class _Table(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


Coordinates = (
    Literal["andoyer", "cylindrical"]
    | Annotated[list[StrictStr], Field(min_length=1, max_length=3)]
)


class PoincareOutput(_Table):
    """A Poincaré map of the scene's model (``[outputs.poincare]``)."""

    section: StrictStr = Field(
        "stroboscopic",
        description="'stroboscopic' (t = t_start mod 2 pi/Omega, time-periodic models) or an "
        "expression S of the state: the map records where S crosses 0",
    )
    direction: Literal[-1, 0, 1] = Field(
        1, description="crossings of the surface where S increases (1), decreases (-1), both (0)"
    )
    iterations: Annotated[StrictInt, Field(ge=1, le=1_000_000)] = Field(
        1000, description="map points kept per orbit"
    )
    transient: Annotated[StrictInt, Field(ge=0, le=10_000_000)] = Field(
        0, description="iterations (crossings) discarded first"
    )
    coordinates: Coordinates = Field(
        "andoyer",
        description="'andoyer' (z, l, g of BM20 (3.7); needs (M, gamma) = 0), 'cylindrical' "
        "(z, l of gamma, BM20 §3.1) or a list of 1-3 expressions of the state",
    )
    projections: list[Annotated[list[StrictStr], Field(min_length=2, max_length=2)]] | None = Field(
        None,
        description="pairs of coordinate names to plot (default: the first two; for "
        "andoyer (l, z) and (l, g))",
    )
    starts: list[list[Number]] = Field(
        default_factory=list,
        description="more starting points in the map coordinates (andoyer: [z, l, g] at the "
        "initial G; cylindrical: [z, l] from rest, M = 0)",
    )
    level_points: Annotated[StrictInt, Field(ge=0, le=200)] = Field(
        0,
        description="more starts on the initial level set: initial.point = 1..level_points "
        "(for an initial state given by integrals)",
    )
    vary: dict[StrictStr, list[Number]] = Field(
        default_factory=dict,
        description="more starts: the initial state with one key replaced by each value "
        "(e.g. vary = { n = [3.5, 4, 5] } on an energy level)",
    )
    mark_rotations: StrictBool = Field(
        False,
        description="mark where the steady rotations p1, p2, p3 of K01 (3.2) at the scene's C "
        "and h cross the section (chaplygin_ball, initial state by h and C)",
    )
    copies: Literal["reached", "canonical"] = Field(
        "reached",
        description="stroboscopic maps of the ball: store and draw each orbit as reached, or as "
        "the canonical copy under the symmetry gamma -> -gamma (chaplygin.numerics.ball.symmetry); "
        "the summary names the copy reached either way",
    )
    plot: StrictBool = Field(True, description="write the 2-D projections as PNG and SVG")
    plot3d: StrictBool = Field(
        False, description="also the 3-D map of the first three coordinates (BM20 Fig. 5 style)"
    )
