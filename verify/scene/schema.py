"""The scene file's format: pydantic models of a scene and its tables, and its JSON Schema.

A scene is declared by pydantic models (:class:`Scene` and its tables), which also export the
JSON Schema shipped as ``examples/scenes/scene.schema.json`` (:func:`scene_json_schema`).
Numbers may be written as text (``"sqrt(0.87)"``); they go through the project's safe number
parser (:func:`chaplygin.numerics.inputs.parse_number`), never ``eval``. Reading the file
(limits, ``--set``, title placeholders) is :mod:`chaplygin.verify.scene.reading`; turning a
scene into a model and a state is :mod:`chaplygin.verify.scene.resolution`.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Literal

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    ValidationError,
    field_validator,
    model_validator,
)

from ...derive.errors import UserInputError
from ...derive.systems import SYSTEMS
from ..outputs.lyapunov_table import LyapunovOutput
from ..outputs.periodic_orbits_table import PeriodicOrbitsOutput
from ..outputs.poincare_table import PoincareOutput
from ..sweep_table import Sweep
from .errors import KeyProblem, SceneError, did_you_mean, dotted, line_of, validation_error
from .reading import (
    apply_overrides,
    check_depth,
    mask_overridden,
    parse_toml,
    read_scene_file,
    render_title,
    stale_overrides,
    text_of,
)

if TYPE_CHECKING:
    from ...derive.rolling_system import RollingSystem
    from .resolution import Resolved
    from .result import SceneResult

__all__ = [
    "SystemTable",
    "FileClaim",
    "FileDiscovery",
    "Number",
    "PlotOutput",
    "TraceOutput",
    "SeriesOutput",
    "TrajectoryOutput",
    "Outputs",
    "Run",
    "Initial",
    "Scene",
    "scene_json_schema",
    "load_scene",
]


# ---------------------------------------------------------------------------- declared schema
def _check_number(value: object) -> object:
    from ...numerics.inputs import parse_number

    parse_number(value, 30)  # refuses malformed, hostile or non-finite text
    return value


#: A number: a TOML integer or float, or text the safe number parser reads (``"sqrt(0.87)"``).
Number = Annotated[
    StrictInt | StrictFloat | StrictStr,
    AfterValidator(_check_number),
    Field(description='a number, or text such as "sqrt(0.87)" or "1/3" (no eval)'),
]
Vector3 = Annotated[list[Number], Field(min_length=3, max_length=3)]


class _Table(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class PlotOutput(_Table):
    """A plot output (``contact_trace``, ``body_trace``, ``drift``, ``diagram``,
    ``separatrix_delta``)."""

    plot: StrictBool = Field(True, description="write the picture as PNG and SVG")


class TraceOutput(PlotOutput):
    """The contact-point trace in the plane (``contact_trace``)."""

    aspect: Literal["equal", "auto"] = Field(
        "equal",
        description="equal: x and y to one scale (true shapes); auto: each axis spans the "
        "picture (a small oscillation about a long drift shows; the axes say so)",
    )


class SeriesOutput(_Table):
    """Time series of chosen quantities (state components, omega1.., integrals, I1(t)..)."""

    quantities: list[StrictStr] = Field(min_length=1, description="names of the quantities")
    plot: StrictBool = True


class TrajectoryOutput(_Table):
    """The trajectory file (always written)."""

    format: Literal["netcdf", "csv", "both"] = Field(
        "netcdf", description="trajectory.nc (netCDF3, self-describing), trajectory.csv, or both"
    )


class Outputs(_Table):
    """What a run writes besides ``summary.json``."""

    trajectory: TrajectoryOutput = TrajectoryOutput()
    contact_trace: TraceOutput | None = Field(
        None,
        description="the contact point (x, y) in the plane, or its longitude and latitude on "
        "a fixed sphere (needs contact_point)",
    )
    body_trace: PlotOutput | None = Field(
        None, description="the contact point -b gamma on the ball's surface (needs contact_point)"
    )
    series: SeriesOutput | None = None
    drift: PlotOutput | None = Field(None, description="the integrals' relative change over time")
    diagram: PlotOutput | None = Field(
        None,
        description="the energy diagram with the scene's point: K01's (n, h) for the ball, "
        "(n, h) at C = (M + K, gamma) with the gyrostat, BKM12 Fig. 5 for the spherical support",
    )
    separatrix_delta: PlotOutput | None = Field(
        None,
        description="on the separatrix (M || gamma, h = h2): integrate backward too, mark the "
        "two asymptotic centres of the contact-point trace and Delta between them, and compare "
        "it with pi b/ch(pi mu/2) (K01-3.7) (needs contact_point)",
    )
    lyapunov: LyapunovOutput | None = Field(
        None, description="Lyapunov spectra with error bars (an analysis: no trajectory needed)"
    )
    poincare: PoincareOutput | None = Field(
        None, description="a Poincaré map: stroboscopic or a section by a surface"
    )
    periodic_orbits: PeriodicOrbitsOutput | None = Field(
        None,
        description="periodic orbit of the stroboscopic map: period, Newton, multipliers, "
        "continuation with its bifurcations",
    )


class Run(_Table):
    """How to integrate."""

    t_end: Number | None = Field(
        None, description="final time (required unless the outputs are analyses only)"
    )
    t_start: Number = 0
    precision: StrictStr | StrictInt = Field(
        "double", description="'double', 'quad' or a number of decimal digits"
    )
    method: StrictStr | None = Field(None, description="DOP853, RK45, LSODA, Radau, BDF, taylor")
    rtol: Annotated[StrictFloat | StrictInt, Field(gt=0, lt=1)] | None = None
    atol: Annotated[StrictFloat | StrictInt, Field(gt=0, lt=1)] | None = None
    points: Annotated[StrictInt, Field(ge=2, le=1_000_000)] | None = Field(
        None,
        description="number of output points, evenly spaced (default: 20 per unit of time, "
        "at least 2001 and at most 200001)",
    )
    backend: Literal["auto", "c", "numpy"] = "auto"
    max_steps: Annotated[StrictInt, Field(ge=1, le=10**12)] | None = Field(
        None,
        description="step budget (default 1e7): a span whose estimated steps exceed it is "
        "refused before any work, and the run stops there",
    )


TypedValue = StrictInt | StrictFloat | Annotated[StrictStr, Field(max_length=2000)]


class BallTable(_Table):
    """One ball of a spherical support (``[[system.balls]]``, ``support = "balls"``)."""

    moment: TypedValue = Field(description="the ball's moment of inertia lambda_k")
    ratio: TypedValue = Field(description="r_k = R_k/R0, the ball's radius over the shell's")
    direction: list[TypedValue] = Field(
        description="the space-fixed direction of its contact: three exact numbers (normalised)"
    )


class SystemTable(_Table):
    """A rolling system described in the scene (``[system]``): see
    :class:`chaplygin.derive.rolling_system.RollingSystem`. Texts are expressions read
    without ``eval``; names in them become parameters (give their values in
    ``[parameters]``)."""

    name: Annotated[StrictStr, Field(max_length=100)] = Field(
        description="the system's name (an identifier, not a built-in system's)"
    )
    inertia: list[TypedValue] | list[list[TypedValue]] = Field(
        description="inertia tensor about the centre of mass, body axes: 3 principal "
        "moments or a 3 x 3 symmetric positive-definite matrix"
    )
    mass: TypedValue = "m"
    radius: TypedValue = Field("b", description="radius of the body's spherical surface")
    centre_of_mass: list[TypedValue] = Field(
        [0, 0, 0], description="centre of mass from the sphere's centre, body axes"
    )
    gravity: TypedValue | None = Field(None, description="g of a constant field along -gamma")
    gyrostat: list[TypedValue] | None = Field(
        None, description="gyrostatic momentum: constants or expressions of the time t"
    )
    potential: Annotated[StrictStr, Field(max_length=2000)] | None = Field(
        None, description="potential of the orientation: an expression of gamma1..gamma3"
    )
    contact: Literal["rolling", "rubber", "line"] = "rolling"
    support: Literal["plane", "rotating_plane", "moving_plane", "sphere", "surface", "balls"] = (
        "plane"
    )
    support_radius: TypedValue | None = Field(
        None, description="radius R of the fixed sphere (support = 'sphere')"
    )
    side: Literal["outside", "inside"] = Field(
        "outside",
        description="the body rolls on the outside of the fixed sphere (support surface) or "
        "inside it",
    )
    rotation_rate: TypedValue | None = Field(
        None,
        description="Omega of a plane rotating about a vertical axis (rotating_plane): a "
        "constant or an expression of the time t",
    )
    plane_velocity: list[TypedValue] | None = Field(
        None,
        description="(V1, V2): the horizontal velocity of a moving plane along the fixed axes "
        "(moving_plane), constants or expressions of t",
    )
    support_surface: TypedValue | None = Field(
        None,
        description="F(p1, p2, p3) of a fixed support surface F = 0 in the fixed frame (p3 up; "
        "support = 'surface'): a ball, or a convex body (surface) rolling on it",
    )
    centre_surface: TypedValue | None = Field(
        None,
        description="F(x1, x2, x3): instead of support_surface, the surface a homogeneous "
        "ball's centre moves on (fixed frame, x3 up; support = 'surface'; potential of x)",
    )
    surface: TypedValue | None = Field(
        None,
        description="f(x1, x2, x3) of a convex body f = 0 instead of a sphere (body axes; on a "
        "plane — fixed, rotating or moving —, a fixed sphere or a support surface, rolling or "
        "rubber)",
    )
    balls: list[BallTable] | None = Field(
        None,
        description="the balls of a spherical support (support = 'balls'): the body, its centre "
        "of mass at the shell's centre, on balls that roll (contact 'rolling') or also do not "
        "twist ('rubber')",
    )
    positive: list[StrictStr] = Field(default_factory=list)
    description: Annotated[StrictStr, Field(max_length=500)] = ""

    def rolling_system(self) -> RollingSystem:
        """The :class:`~chaplygin.derive.rolling_system.RollingSystem` of this table.

        Returns
        -------
        RollingSystem

        Raises
        ------
        UserInputError
            A description the toolkit refuses (see the class).
        """
        from ...derive.rolling_system import RollingSystem

        return RollingSystem(**self.model_dump())


class FileDiscovery(BaseModel):
    """The ``[discover]`` table: a class searched when the file's claims are checked; each
    integral, density, invariant relation and symmetry found becomes a claim, and so does
    the dimension of each class searched ("no other in this class")."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    degree: int = Field(2, ge=1, le=6)
    coefficient_degree: int = Field(2, ge=0, le=6)
    momentum: StrictStr | None = None
    in_parameters: bool = False
    densities: bool = False
    relations: bool = False
    symmetries: bool = False
    linear_degree: int = Field(1, ge=0, le=4)
    cofactor_degree: int = Field(1, ge=0, le=4)


class FileClaim(BaseModel):
    """One ``[[claims]]`` entry of a description file."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    id: StrictStr = Field(max_length=100, pattern=r"^[A-Za-z0-9_.:/+-]+$")
    kind: StrictStr = Field(pattern="^(integral|measure)$")
    expression: StrictStr = Field(max_length=2000)
    statement: StrictStr = Field("", max_length=500)
    expected: StrictStr = Field("holds", pattern="^(holds|fails)$")


class Initial(BaseModel):
    """The initial state: by state groups (``M``, ``gamma``, ...) or by integrals.

    ``M`` (a direction) with ``h`` alone: ``M`` scaled to the energy ``h`` (any model whose
    energy is quadratic in ``M``: a described system too). Integrals (the ball): ``h`` energy,
    ``C = (M, gamma)`` (with the gyrostat ``(M + K, gamma)``),
    ``n = (M, M)`` or ``parallel = true`` (``M || gamma``); ``point`` picks a point of the level
    set (see :mod:`chaplygin.numerics.ball.initial_state`); a given ``gamma`` fixes it. Any
    model (a described one too): ``integrals = {NAME = value}`` with ``free = [...]``, the
    free components of the given state solved for those values
    (:mod:`chaplygin.numerics.integral_levels`); with ``point = k`` the k-th point of the level
    set's documented enumeration (:mod:`chaplygin.numerics.level_points`). Any other key must
    be a state group of the model (checked when the model is known).
    """

    model_config = ConfigDict(extra="allow", frozen=True)
    __pydantic_extra__: dict[str, Number | list[Number]] = Field(init=False)

    M: Vector3 | None = Field(None, description="momentum about the contact point (body frame)")
    gamma: Vector3 | None = Field(None, description="unit vertical (body frame)")
    alpha: Vector3 | None = None
    beta: Vector3 | None = None
    x: Number | Vector3 | None = Field(
        None, description="the trace's x (contact_point), or a ball on a surface's centre (3)"
    )
    y: Number | None = None
    h: Number | None = Field(None, description="energy")
    C: Number | None = Field(None, description="(M, gamma)")
    n: Number | None = Field(None, description="(M, M)")
    parallel: StrictBool = Field(False, description="M || gamma (n = C^2)")
    point: Annotated[StrictInt, Field(ge=0, le=10_000)] | None = Field(
        None,
        description="which point of the level set (reproducible order; default 0); with "
        "integrals: the k-th point of the enumerated level set (without it: Newton from the "
        "given values)",
    )
    G: Number | None = Field(None, description="Andoyer-Deprit G = |M| (BM20 (3.7))")
    z: Number | None = Field(None, description="Andoyer-Deprit z = M3/G, |z| <= 1")
    l: Number | None = Field(None, description="Andoyer-Deprit angle l (radians)")
    g: Number | None = Field(None, description="Andoyer-Deprit angle g (radians)")
    rest: StrictBool = Field(False, description="from rest: M = 0 (BM20 §3.1, k(0) = 0)")
    near: Literal["p1", "p2", "p3"] | None = Field(
        None, description="the steady rotation of branch p_i (K01 (3.2)) at C and n"
    )
    separatrix: Literal[1, 2, 3] | None = Field(
        None, description="M || gamma at h = C^2/(2 I_i), i the middle axis (K01 §3.3)"
    )
    offset: Number = Field(0, description="push off near/separatrix (relative)")
    integrals: dict[Annotated[StrictStr, Field(max_length=100)], Number] | None = Field(
        None,
        description="integral name -> value: the model's integrals (H, (M,gamma), ...) or the "
        "file's [[claims]] of kind integral by id; the components named by free are solved "
        "for (Newton from their given values; with point = k: the k-th point of the level set)",
    )
    free: list[Annotated[StrictStr, Field(max_length=100)]] | None = Field(
        None,
        description="state components (M1, gamma2, ...) or groups (M) solved for the "
        "integrals' values, as many as there are values (default: the first state group)",
    )


class Scene(BaseModel):
    """One experiment. Build it with :meth:`from_toml` or :meth:`from_dict`; run it with
    :meth:`run`."""

    model_config = ConfigDict(
        extra="forbid", frozen=True, json_schema_extra={"title": "chaplygin scene"}
    )

    title: StrictStr = Field(
        "",
        max_length=500,
        description="shown on the plots and in the summary (at most 500 characters); "
        "{initial.h} (any dotted key) shows that key's value as run, {{ }} are braces",
    )
    system: Literal[tuple(sorted(SYSTEMS))] | SystemTable = Field(  # type: ignore[valid-type]
        description="a built-in system's name, or a [system] table describing a rolling body"
    )
    effects: list[StrictStr] = Field(
        default_factory=list,
        description="effects the scene names; those its outputs need are added and reported",
    )
    parameters: dict[StrictStr, Number | list[Number]] = Field(default_factory=dict)
    initial: Initial
    run_options: Run = Field(alias="run", description="how to integrate")
    outputs: Outputs = Outputs()
    sweep: Sweep | None = Field(
        None, description="a grid of points for `chaplygin sweep` (ignored by `chaplygin run`)"
    )
    discover: FileDiscovery | None = Field(
        None, description="a class `chaplygin verify --system` searches (ignored by `run`)"
    )
    claims: list[FileClaim] = Field(
        default_factory=list,
        max_length=200,
        description="claims about a described system, checked by `chaplygin verify --system`",
    )

    @field_validator("effects")
    @classmethod
    def _unique(cls, value: list[str]) -> list[str]:
        if len(set(value)) != len(value):
            raise ValueError("an effect is named twice")
        return value

    @model_validator(mode="after")
    def _effects_of_system(self) -> Scene:
        if isinstance(self.system, SystemTable):
            # a described system: derived, emitted and compiled on first use under its name
            from ...derive.systems import register_system

            try:
                entry = register_system(self.system.rolling_system())
            except UserInputError as exc:
                raise KeyProblem(("system",), str(exc)) from None
            self._described = self.system
            object.__setattr__(self, "system", entry.name)  # the name from here on
        supported = SYSTEMS[self.system].effects
        for i, e in enumerate(self.effects):
            if e not in supported:
                raise KeyProblem(
                    ("effects", i),
                    f"unknown effect {e!r} for {self.system}; valid: "
                    f"{', '.join(supported) or 'none'}{did_you_mean(e, supported)}",
                )
        return self

    # private, set by the loaders
    _described: SystemTable | None = None  # the [system] table of a described system
    _source: str | None = None
    _given: dict = {}
    _text: str | None = None  # the file's text, lines of --set keys blanked

    # -------------------------------------------------------------------------- loading
    @classmethod
    def from_toml(cls, path: str | Path, overrides: Sequence[str] = ()) -> Scene:
        """Read and validate a scene file.

        Parameters
        ----------
        path : str or Path
        overrides : sequence of str
            ``KEY=VALUE`` items (``run.t_end=100``), values in TOML syntax (bare words are text).

        Returns
        -------
        Scene

        Raises
        ------
        SceneError
            Unreadable file, TOML syntax, or an invalid scene (file, key path, line).
        """
        path = Path(path)
        name = str(path)
        raw = read_scene_file(path)
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            raise SceneError("not UTF-8 text (a scene is a TOML file)", name) from None
        data = parse_toml(text, name)
        text = mask_overridden(text, overrides)
        scene = cls.from_dict(apply_overrides(data, overrides, name), source=name, text=text)
        stale = stale_overrides(data.get("title", ""), overrides, scene._given)
        if stale:
            # the title names the file's values and --set changed some it does not refer to
            # by a placeholder: it says so, with the values that ran
            scene = scene.model_copy(
                update={"title": f"{scene.title} [run with --set {stale}; the title's own "
                        "values are the scene file's]"}
            )  # fmt: skip
        scene._text = text
        return scene

    @classmethod
    def from_dict(cls, data: Mapping, source: str | None = None, text: str | None = None) -> Scene:
        """Validate a scene given as a mapping (the parsed TOML).

        Parameters
        ----------
        data : mapping
        source : str, optional
            File name for the messages.
        text : str, optional
            The TOML text (to find the line of a key).

        Returns
        -------
        Scene

        Raises
        ------
        SceneError
        """
        if not isinstance(data, Mapping):
            raise SceneError("a scene is a table of keys", source)
        check_depth(data, source)
        try:
            scene = cls.model_validate(dict(data))
        except ValidationError as exc:
            raise validation_error(exc, Scene, source, text, dict(data)) from None
        except KeyProblem as exc:
            raise SceneError(exc.message, source, dotted(exc.loc), line_of(text, exc.loc)) from None
        given = json.loads(json.dumps(dict(data), default=str))
        try:
            shown = render_title(scene.title, given)
        except UserInputError as exc:
            raise SceneError(str(exc), source, "title", line_of(text, ("title",))) from None
        if shown != scene.title:
            scene = scene.model_copy(update={"title": shown})
        scene._source = source
        scene._given = given
        return scene

    @property
    def source(self) -> str | None:
        """The file the scene came from."""
        return self._source

    @property
    def given(self) -> dict:
        """The scene as given (``--set`` applied), as JSON-able data (``summary.json``'s
        ``scene``)."""
        return self._given

    def key_error(self, message: str, *loc: str | int, line_at: tuple = ()) -> SceneError:
        """A :class:`SceneError` about the key at ``loc``, with the scene's file and the key's line.

        Parameters
        ----------
        message : str
        *loc : str or int
            The key path (``"outputs", "poincare", "starts", 0``).
        line_at : tuple, optional
            Another key path whose line the message shows (default ``loc``'s).

        Returns
        -------
        SceneError
        """
        text = self._text if self._text is not None else text_of(self._source)
        return SceneError(message, self._source, dotted(loc), line_of(text, line_at or loc))

    def with_initial(self, **changes: object) -> Scene:
        """The same scene (file, text, values given) with keys of ``[initial]`` changed.

        Parameters
        ----------
        **changes
            ``[initial]`` keys and their new values (``point=1``, ``h="0.2"``).

        Returns
        -------
        Scene
        """
        other = self.model_copy(update={"initial": self.initial.model_copy(update=changes)})
        other._text = self._text
        return other

    # ------------------------------------------------------------------------ resolution
    def resolve(self) -> Resolved:
        """The model, parameters and initial state the scene asks for, checked.

        Returns
        -------
        Resolved

        Raises
        ------
        SceneError
        """
        from .resolution import resolve_scene

        return resolve_scene(self)

    def explain(self) -> str:
        """What :meth:`run` would do, without running: effects and why, states, parameters,
        the operation count of the right-hand side and the code that will run.

        Returns
        -------
        str
        """
        from .explain import explain_text

        return explain_text(self, self.resolve())

    def run(self, progress: bool = False) -> SceneResult:
        """Integrate the scene.

        Parameters
        ----------
        progress : bool
            Show a tqdm progress bar on stderr for runs longer than about 2 s.

        Returns
        -------
        SceneResult
        """
        from .running import run_resolved

        return run_resolved(self, self.resolve(), progress)


def scene_json_schema() -> dict:
    """The JSON Schema of a scene file (shipped as ``examples/scenes/scene.schema.json``).

    Returns
    -------
    dict
    """
    schema = Scene.model_json_schema(by_alias=True)
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    return schema


def load_scene(path: str | Path, overrides: Sequence[str] = ()) -> Scene:
    """Same as :meth:`Scene.from_toml`.

    Parameters
    ----------
    path : str or Path
    overrides : sequence of str

    Returns
    -------
    Scene
    """
    return Scene.from_toml(path, overrides)
