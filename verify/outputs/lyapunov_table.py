"""The scene table ``[outputs.lyapunov]`` (its own module: the scene's schema imports it without
importing the analysis, :mod:`chaplygin.verify.outputs.lyapunov`)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, StrictBool, StrictFloat, StrictInt

__all__ = ["LyapunovOutput"]


class LyapunovOutput(BaseModel):
    """Lyapunov spectra by Benettin's QR method (variational equations in C)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    iterations: Annotated[StrictInt, Field(ge=10, le=10_000_000)] = Field(
        10_000,
        description="renormalisation intervals averaged per initial state (map iterations when "
        "the interval is the forcing period)",
    )
    transient: Annotated[StrictInt, Field(ge=0, le=10_000_000)] = Field(
        500, description="intervals discarded before averaging"
    )
    interval: Annotated[StrictFloat | StrictInt, Field(gt=0)] | None = Field(
        None,
        description="time between re-orthonormalisations (default: the forcing period "
        "2 pi/Omega; required for autonomous models)",
    )
    spectrum: Literal["level_set", "full", "both"] = Field(
        "level_set",
        description="tangent vectors on the level set of the integrals, all of them, or both",
    )
    states: Annotated[StrictInt, Field(ge=1, le=20)] = Field(
        3, description="initial states (the scene's and neighbours on its level set)"
    )
    spread: Annotated[StrictFloat, Field(gt=0, le=0.5)] = Field(
        0.01, description="relative distance of the neighbouring initial states"
    )
    windows: Annotated[StrictInt, Field(ge=2, le=1000)] = Field(
        10, description="windows of the batch-means error bar"
    )
    plot: StrictBool = Field(True, description="write the convergence plot (PNG and SVG)")
