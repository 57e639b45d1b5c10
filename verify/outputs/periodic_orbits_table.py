"""The scene table ``[outputs.periodic_orbits]`` (its own module: the scene's schema imports it
without importing the analysis, :mod:`chaplygin.verify.outputs.periodic_orbits`)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, StrictBool, StrictFloat, StrictInt, StrictStr

__all__ = ["ContinuationSpec", "PeriodicOrbitsOutput"]

Positive = Annotated[StrictFloat | StrictInt, Field(gt=0)]


class _Table(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class ContinuationSpec(_Table):
    """Continuation of the periodic orbit found, in one parameter of the model."""

    parameter: Annotated[StrictStr, Field(min_length=1, max_length=100)] = Field(
        "Omega",
        description="the parameter varied (the scene's value is the start): Omega, D, delta or "
        "J_off for the stroboscopic map; any parameter of the model with a section",
    )
    range: Annotated[list[StrictFloat | StrictInt], Field(min_length=2, max_length=2)] = Field(
        description="[a, b]: the branch is followed from the scene's value to a and to b"
    )
    step: Positive = Field(
        description="initial arclength step (in (x, parameter)); with a section, the step in "
        "the parameter"
    )
    max_points: Annotated[StrictInt, Field(ge=2, le=5000)] = Field(
        200, description="points per branch at most"
    )
    follow_doublings: Annotated[StrictInt, Field(ge=0, le=12)] = Field(
        3, description="period doublings at which to switch to the doubled branch"
    )


class PeriodicOrbitsOutput(_Table):
    """Periodic orbit of the stroboscopic map (a time-periodic model) or of the return map to
    a surface (an autonomous model, ``section``): period search, Newton, multipliers."""

    section: Annotated[StrictStr, Field(max_length=2000)] | None = Field(
        None,
        description="an autonomous model: the surface S(state) = 0 whose crossings are "
        "iterated (an expression of the state and omega, as for outputs.poincare); the orbit "
        "is then refined on the flow, phi_T(y) = y",
    )
    direction: Literal[-1, 0, 1] = Field(
        1, description="crossings where S increases (1), decreases (-1) or both (0)"
    )

    transient: Annotated[StrictInt, Field(ge=0, le=10_000_000)] = Field(
        5000, description="map iterations discarded before the period search"
    )
    max_period: Annotated[StrictInt, Field(ge=1, le=4096)] = Field(
        64, description="largest period tried"
    )
    detect_tol: Annotated[StrictFloat, Field(gt=0, lt=1)] = Field(
        1e-4,
        description="closing tolerance of a candidate period (the candidate is then refined "
        "by Newton to the integration's accuracy)",
    )
    rtol: Annotated[StrictFloat, Field(gt=0, lt=1e-4)] = Field(
        1e-11, description="integration tolerance of the map and its Jacobian"
    )
    continuation: ContinuationSpec | None = Field(
        None, description="continue the orbit in a parameter, locating its bifurcations"
    )
    plot: StrictBool = Field(True, description="write the multipliers' picture")
