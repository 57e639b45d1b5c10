"""The ``[sweep]`` table of a scene: a grid over parameters and initial values, and the numbers
each point is reduced to (:mod:`chaplygin.verify.sweep` runs it; ``chaplygin sweep``).

Example
-------
.. code-block:: toml

    [sweep]
    grid = "product"                 # or "list" (the axes' i-th values form the i-th point)
    chunk = 8                        # points per task (and per Zarr chunk)
    reduce = ["period", "drift"]

    [sweep.axes]
    "parameters.D" = { start = 4.3, stop = 4.45, num = 16 }
    "parameters.Omega" = [1.0, 1.07, "1.1"]

    [sweep.period]
    transient = 500
    recorded = 200
    max_period = 14
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    StrictFloat,
    StrictInt,
    StrictStr,
    field_validator,
    model_validator,
)

__all__ = [
    "Sweep",
    "SweepRange",
    "PeriodOptions",
    "RegimeOptions",
    "DeltaOptions",
    "RefineOptions",
    "AXIS_ROOTS",
]

#: The tables a sweep axis may vary (``parameters.D``, ``initial.h``, ``run.t_end``).
AXIS_ROOTS = ("parameters", "initial", "run")


def _check_number(value: object) -> object:
    from ..numerics.inputs import parse_number

    parse_number(value, 30)  # refuses malformed, hostile or non-finite text
    return value


_Number = Annotated[
    StrictInt | StrictFloat | StrictStr,
    AfterValidator(_check_number),
    Field(description='a number, or text such as "sqrt(0.87)" or "1/3" (no eval)'),
]


class _Table(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class SweepRange(_Table):
    """Evenly spaced values ``start, ..., stop`` (both included), computed at 30 digits."""

    start: _Number
    stop: _Number
    num: Annotated[StrictInt, Field(ge=1, le=100_000)] = Field(description="number of values")


class PeriodOptions(_Table):
    """The stroboscopic map (one forcing period ``2 pi/Omega``) and its attractor's period."""

    forcing: StrictStr = Field("Omega", description="the parameter that is the forcing frequency")
    transient: Annotated[StrictInt, Field(ge=0, le=1_000_000)] = Field(
        500, description="map iterations discarded first"
    )
    recorded: Annotated[StrictInt, Field(ge=2, le=1_000_000)] = Field(
        200, description="map iterations classified after the transient"
    )
    max_period: Annotated[StrictInt, Field(ge=1, le=1000)] = Field(
        14, description="largest period looked for (longer orbits count as 0, not periodic)"
    )
    tol: Annotated[StrictFloat, Field(gt=0, lt=1)] = Field(
        1e-6,
        description="a recorded orbit has period p when every y[k+p] - y[k] is within tol "
        "(relative to the largest |y|)",
    )
    engine: Literal["auto", "batch", "taylor-batch", "scene"] = Field(
        "auto",
        description="batch: all points of a chunk in one compiled call (DOP853 in C, double, the "
        "scene's rtol/atol); taylor-batch: the same call with the model's Taylor integrator; "
        "scene: each point with the scene's method and precision; auto: batch (DOP853) for "
        "double precision when a C compiler is present",
    )


class LyapunovOptions(_Table):
    """The largest Lyapunov exponent on the integrals' level set (Benettin/QR, one QR per
    forcing period), with its error bar."""

    transient: Annotated[StrictInt, Field(ge=0, le=1_000_000)] = Field(
        200, description="forcing periods discarded first"
    )
    intervals: Annotated[StrictInt, Field(ge=10, le=10_000_000)] = Field(
        2000, description="forcing periods averaged"
    )


class RegimeOptions(_Table):
    """The regime of the stroboscopic map's attractor: the period, then the largest Lyapunov
    exponent (:func:`chaplygin.numerics.ball.regimes.attractor_regime`)."""

    transient: Annotated[StrictInt, Field(ge=0, le=10_000_000)] = Field(
        2000, description="map iterations discarded first (from the scene's start)"
    )
    carried_transient: Annotated[StrictInt, Field(ge=0, le=10_000_000)] | None = Field(
        None,
        description="map iterations discarded from a start carried from the previous point "
        "(default: transient)",
    )
    recorded: Annotated[StrictInt, Field(ge=3, le=1_000_000)] = Field(
        600, description="iterations searched for a period (more than max_period)"
    )
    max_period: Annotated[StrictInt, Field(ge=1, le=10_000)] = Field(
        64, description="largest period looked for"
    )
    tol: Annotated[StrictFloat, Field(gt=0, lt=1)] = Field(
        1e-4, description="closing tolerance in (M/|M|, gamma), max norm"
    )
    intervals: Annotated[StrictInt, Field(ge=10, le=10_000_000)] = Field(
        2000, description="map iterations of the largest Lyapunov exponent (no period found)"
    )
    lyapunov_transient: Annotated[StrictInt, Field(ge=0, le=1_000_000)] = Field(
        100, description="iterations that align the tangent vector first"
    )

    @model_validator(mode="after")
    def _enough(self) -> RegimeOptions:
        if self.recorded <= self.max_period:
            raise ValueError("regime.recorded must exceed regime.max_period")
        return self


class DeltaOptions(_Table):
    """Delta of K01 (displacement per tumble on the separatrix)."""

    digits: Annotated[StrictInt, Field(ge=5, le=60)] = Field(
        12, description="digits of the measured Delta (Taylor integration of the full equations)"
    )


class RefineOptions(_Table):
    """After the scan: the zeros of a number along the (single) axis, refined by Brent's method."""

    variable: StrictStr = Field(description="a scalar result, e.g. frame_turn_phi")
    digits: Annotated[StrictInt, Field(ge=2, le=14)] = Field(
        10, description="relative digits of each zero"
    )


class Sweep(_Table):
    """A grid of points, each the scene with some keys replaced, reduced to numbers."""

    grid: Literal["product", "list"] = Field(
        "product", description="product of the axes, or their values side by side"
    )
    axes: dict[StrictStr, list[_Number] | SweepRange] = Field(
        min_length=1,
        description='dotted key -> values: "parameters.D", "initial.h", "run.t_end"',
    )
    chunk: Annotated[StrictInt, Field(ge=1, le=100_000)] = Field(
        8, description="points per task and per Zarr chunk"
    )
    reduce: list[StrictStr] = Field(
        default_factory=lambda: ["final_state", "drift"],
        min_length=1,
        description="what each point is reduced to (chaplygin.verify.sweep.REDUCERS)",
    )
    period: PeriodOptions = PeriodOptions()
    delta: DeltaOptions = DeltaOptions()
    lyapunov: LyapunovOptions = LyapunovOptions()
    regime: RegimeOptions = RegimeOptions()
    refine: RefineOptions | None = None
    carry: Literal["none", "forward", "backward", "both"] = Field(
        "none",
        description="carry each point's final state to the next point along the last axis "
        "(one task per grid line): forward in the axis's order, backward, or both (a leading "
        "dimension 'carry'); reducers that carry (regime) start there, so one attractor is "
        "followed and coexisting ones show where the two directions differ",
    )

    @field_validator("axes")
    @classmethod
    def _axis_keys(cls, value: dict) -> dict:
        import re

        for key, values in value.items():
            parts = key.split(".")
            if (
                len(parts) != 2
                or parts[0] not in AXIS_ROOTS
                or not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", parts[1])
            ):
                raise ValueError(
                    f"axis {key!r}: a key path TABLE.NAME with TABLE one of "
                    f"{', '.join(AXIS_ROOTS)} (e.g. parameters.D, initial.h)"
                )
            if isinstance(values, list) and not values:
                raise ValueError(f"axis {key!r} has no values")
        names = [k.split(".")[1] for k in value]
        if len(set(names)) != len(names):
            raise ValueError("two axes have the same name (the last part of the key path)")
        return value

    @field_validator("reduce")
    @classmethod
    def _unique(cls, value: list[str]) -> list[str]:
        if len(set(value)) != len(value):
            raise ValueError("a reducer is named twice")
        return value

    @model_validator(mode="after")
    def _grid_shape(self) -> Sweep:
        if self.grid == "list":
            sizes = {len(v) if isinstance(v, list) else v.num for v in self.axes.values()}
            if len(sizes) != 1:
                raise ValueError('grid = "list" needs axes of the same length')
        if self.refine is not None and len(self.axes) != 1:
            raise ValueError("refine needs a sweep over a single axis")
        if self.carry != "none":
            if self.grid != "product":
                raise ValueError('carry needs grid = "product" (it follows the grid lines)')
            last = list(self.axes.values())[-1]
            n = len(last) if isinstance(last, list) else last.num
            if self.chunk < n:
                raise ValueError(
                    f"carry needs one task per grid line: chunk >= {n} (the number of values "
                    "of the last axis)"
                )
        return self
