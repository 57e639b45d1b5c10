"""Scenes: one TOML file names one experiment (system, effects, parameters, initial state, run,
outputs); :meth:`Scene.run` simulates only what it calls for.

A scene is declared by pydantic models (:class:`Scene` and its tables), which also export the
JSON Schema shipped as ``examples/scenes/scene.schema.json`` (:func:`scene_json_schema`). Every
problem with a scene is one :class:`SceneError` (a :class:`UserInputError`): its message names
the file, the key path and, where it can be found, the line; unknown keys and names list the valid
choices with a "did you mean". Numbers may be written as text (``"sqrt(0.87)"``); they go through
the project's safe number parser (:func:`chaplygin.numerics.inputs.parse_number`), never ``eval``.

The model is built from the scene's effects plus those its outputs need
(:data:`OUTPUT_EFFECTS`), and nothing else: a parameter of an effect that is not on is refused.

Examples
--------
>>> scene = Scene.from_toml("examples/scenes/k01-fig6f.toml")      # doctest: +SKIP
>>> result = scene.run()                                          # doctest: +SKIP
>>> result.contact_trace_figure().savefig("trace.png")            # doctest: +SKIP
"""

from __future__ import annotations

import difflib
import html
import json
import math
import platform
import re
import sys
import time
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import numpy as np
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

from ..arith import detmath
from ..derive.errors import UserInputError
from ..derive.systems import SYSTEMS
from .analyses import AnalysisResult, requested
from .lyapunov_table import LyapunovOutput
from .periodic_output import PeriodicOrbitsOutput
from .poincare_table import PoincareOutput
from .sweep_table import Sweep

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "Scene",
    "SceneError",
    "SceneResult",
    "Resolved",
    "OUTPUT_EFFECTS",
    "scene_json_schema",
    "apply_overrides",
    "render_title",
    "load_scene",
    "explain_text",
    "run_resolved",
    "quantity_names",
    "prepare_output",
    "write_atomically",
    "read_scene_file",
    "MAX_SCENE_BYTES",
    "MAX_SCENE_DEPTH",
]

#: Effects an output needs: output key -> effects.
OUTPUT_EFFECTS: dict[str, tuple[str, ...]] = {
    "contact_trace": ("contact_point",),
    "body_trace": ("contact_point",),
    "separatrix_delta": ("contact_point",),
}

#: Andoyer-Deprit variables of BM20 (3.7), in their order.
ANDOYER = ("G", "z", "l", "g")


class SceneError(UserInputError):
    """A scene that cannot be used: the message names the file, key path and line.

    Attributes
    ----------
    file : str or None
    path : str
        Dotted key path (``"initial.h"``), empty for the whole file.
    line : int or None
    """

    def __init__(
        self, message: str, file: str | None = None, path: str = "", line: int | None = None
    ):
        self.file, self.path, self.line = file, path, line
        where = file or "<scene>"
        if line is not None:
            where += f":{line}"
        if path:
            where += f": {path}"
        # one line, always (the CLI prints it on stderr)
        super().__init__(f"{where}: {' '.join(str(message).split())}")


# ---------------------------------------------------------------------------- declared schema
def _check_number(value: object) -> object:
    from ..numerics.inputs import parse_number

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
        None, description="the contact point (x, y) in the plane (needs contact_point)"
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


class Initial(BaseModel):
    """The initial state: by state groups (``M``, ``gamma``, ...) or by integrals.

    Integrals (the ball): ``h`` energy, ``C = (M, gamma)`` (with the gyrostat ``(M + K, gamma)``),
    ``n = (M, M)`` or ``parallel = true`` (``M || gamma``); ``point`` picks a point of the level
    set (see :mod:`chaplygin.numerics.initial_state`); a given ``gamma`` fixes it. Any other key
    must be a state group of the model (checked when the model is known).
    """

    model_config = ConfigDict(extra="allow", frozen=True)
    __pydantic_extra__: dict[str, Number | list[Number]] = Field(init=False)

    M: Vector3 | None = Field(None, description="momentum about the contact point (body frame)")
    gamma: Vector3 | None = Field(None, description="unit vertical (body frame)")
    alpha: Vector3 | None = None
    beta: Vector3 | None = None
    x: Number | None = None
    y: Number | None = None
    h: Number | None = Field(None, description="energy")
    C: Number | None = Field(None, description="(M, gamma)")
    n: Number | None = Field(None, description="(M, M)")
    parallel: StrictBool = Field(False, description="M || gamma (n = C^2)")
    point: Annotated[StrictInt, Field(ge=0, le=10_000)] = Field(
        0, description="which point of the level set (reproducible order)"
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
    system: Literal[tuple(sorted(SYSTEMS))]  # type: ignore[valid-type]
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

    @field_validator("effects")
    @classmethod
    def _unique(cls, value: list[str]) -> list[str]:
        if len(set(value)) != len(value):
            raise ValueError("an effect is named twice")
        return value

    @model_validator(mode="after")
    def _effects_of_system(self) -> Scene:
        supported = SYSTEMS[self.system].effects
        for i, e in enumerate(self.effects):
            if e not in supported:
                raise _KeyProblem(
                    ("effects", i),
                    f"unknown effect {e!r} for {self.system}; valid: "
                    f"{', '.join(supported) or 'none'}{_did_you_mean(e, supported)}",
                )
        return self

    # private, set by the loaders
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
        data = _parse_toml(text, name)
        text = _mask_overridden(text, overrides)
        scene = cls.from_dict(apply_overrides(data, overrides, name), source=name, text=text)
        stale = _stale_overrides(data.get("title", ""), overrides, scene._given)
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
        _check_depth(data, source)
        try:
            scene = cls.model_validate(dict(data))
        except ValidationError as exc:
            raise _scene_error(exc, source, text, dict(data)) from None
        except _KeyProblem as exc:
            raise SceneError(
                exc.message, source, _dotted(exc.loc), _line_of(text, exc.loc)
            ) from None
        given = json.loads(json.dumps(dict(data), default=str))
        try:
            shown = render_title(scene.title, given)
        except UserInputError as exc:
            raise SceneError(str(exc), source, "title", _line_of(text, ("title",))) from None
        if shown != scene.title:
            scene = scene.model_copy(update={"title": shown})
        scene._source = source
        scene._given = given
        return scene

    @property
    def source(self) -> str | None:
        """The file the scene came from."""
        return self._source

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
        return _resolve(self)

    def explain(self) -> str:
        """What :meth:`run` would do, without running: effects and why, states, parameters,
        the operation count of the right-hand side and the code that will run.

        Returns
        -------
        str
        """
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
        return run_resolved(self, self.resolve(), progress)


#: Largest scene file read (a scene is a few kilobytes; a sweep's long list of values fits).
MAX_SCENE_BYTES = 1 << 20

#: Deepest nesting of tables and lists in a scene (the schema's deepest is 5:
#: ``sweep.axes."parameters.D".start``, or a list in a table of a table).
MAX_SCENE_DEPTH = 16


def read_scene_file(path: str | Path) -> bytes:
    """The bytes of a scene file, read with limits: a regular file (a FIFO, a device such as
    ``/dev/zero`` or a folder is refused without being opened for reading, so nothing
    blocks) of at most :data:`MAX_SCENE_BYTES`.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    bytes

    Raises
    ------
    SceneError
        Missing, unreadable, not a regular file, or too large.
    """
    import os
    import stat

    name = str(path)
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode):
            kind = "a folder" if stat.S_ISDIR(st.st_mode) else "not a regular file"
            raise SceneError(f"cannot read the scene: it is {kind} (a scene is a TOML file)", name)
        # O_NONBLOCK: a FIFO put there since the check cannot block the open
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
        with os.fdopen(fd, "rb") as fh:
            st = os.fstat(fh.fileno())
            if not stat.S_ISREG(st.st_mode):
                raise SceneError("cannot read the scene: it is not a regular file", name)
            raw = fh.read(MAX_SCENE_BYTES + 1)
    except SceneError:
        raise
    except (OSError, ValueError) as exc:
        reason = getattr(exc, "strerror", None) or exc
        raise SceneError(f"cannot read the scene: {reason}", name) from None
    if len(raw) > MAX_SCENE_BYTES:
        raise SceneError(
            f"the scene file is larger than {MAX_SCENE_BYTES // 1024} KiB (a scene is a few "
            "kilobytes; give long ranges of a sweep as {start, stop, num})",
            name,
        )
    return raw


def _parse_toml(text: str, source: str | None, what: str = "TOML syntax") -> dict:
    """``tomllib.loads`` with its failures as one-line :class:`SceneError` (deep nesting
    included: the parser recurses)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        line = re.search(r"line (\d+)", str(exc))
        raise SceneError(
            f"{what}: {exc}", source, line=int(line.group(1)) if line else None
        ) from None
    except (RecursionError, MemoryError):
        raise SceneError(
            f"{what}: nested deeper than {MAX_SCENE_DEPTH} tables or lists", source
        ) from None
    _check_depth(data, source)
    return data


def _check_depth(data: object, source: str | None) -> None:
    """Refuse data nested deeper than :data:`MAX_SCENE_DEPTH` (walked without recursion)."""
    stack = [(data, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_SCENE_DEPTH:
            raise SceneError(f"nested deeper than {MAX_SCENE_DEPTH} tables or lists", source)
        if isinstance(node, Mapping):
            stack.extend((v, depth + 1) for v in node.values())
        elif isinstance(node, list | tuple):
            stack.extend((v, depth + 1) for v in node)


class _KeyProblem(ValueError):
    def __init__(self, loc: tuple, message: str):
        super().__init__(message)
        self.loc, self.message = loc, message


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


# ------------------------------------------------------------------------------ error messages
def _did_you_mean(word: object, choices: Sequence[str]) -> str:
    close = difflib.get_close_matches(str(word), list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _dotted(loc: Sequence) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


_HEADER = re.compile(r"^\s*\[\s*([A-Za-z0-9_.\-\" ]+?)\s*\]\s*(#.*)?$")
_KEY = re.compile(r"^\s*([A-Za-z0-9_\-]+)\s*=")


def _line_of(text: str | None, loc: Sequence) -> int | None:
    """Line (1-based) of the deepest key of ``loc`` found in ``text`` (None when not found)."""
    if not text:
        return None
    keys = [str(k) for k in loc if not isinstance(k, int)]
    best = None
    for depth in range(len(keys), 0, -1):
        table, key = keys[: depth - 1], keys[depth - 1]
        current: list[str] = []
        for number, line in enumerate(text.splitlines(), 1):
            header = _HEADER.match(line)
            if header:
                current = [p.strip().strip('"') for p in header.group(1).split(".")]
                if current == keys[:depth]:
                    best = number
                    break
                continue
            m = _KEY.match(line)
            if m and m.group(1) == key and current == table:
                best = number
                break
            # inline tables: key = { ... inner = ... }
            if m and current == table[:-1] and table and m.group(1) == table[-1]:
                if re.search(rf"[{{,]\s*{re.escape(key)}\s*=", line):
                    best = number
                    break
        if best is not None:
            return best
    return None


def _fields_of(loc: Sequence) -> list[str]:
    """Valid keys of the table at ``loc`` (for unknown-key messages)."""
    model: Any = Scene
    for part in loc:
        if isinstance(part, int) or model is None:
            return []
        info = next((f for n, f in model.model_fields.items() if (f.alias or n) == part), None)
        if info is None:
            return []
        ann = info.annotation
        model = next(
            (
                a
                for a in (ann, *getattr(ann, "__args__", ()))
                if isinstance(a, type) and issubclass(a, BaseModel)
            ),
            None,
        )
    if model is None:
        return []
    return [f.alias or n for n, f in model.model_fields.items()]


def _input_path(loc: Sequence, data: object) -> tuple:
    """The parts of a pydantic ``loc`` that are keys or indices of the input (pydantic also
    puts the names of union members and validators in it)."""
    out, node = [], data
    for part in loc:
        if isinstance(node, Mapping) and isinstance(part, str) and part in node:
            out.append(part)
            node = node[part]
        elif isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node):
            out.append(part)
            node = node[part]
    return tuple(out)


def _scene_error(
    exc: ValidationError, source: str | None, text: str | None, data: object = None
) -> SceneError:
    err = exc.errors(include_url=False)[0]
    loc = _input_path(err["loc"], data)
    if err["type"] == "missing" and err["loc"]:
        loc = (*loc, err["loc"][-1])
    kind, msg = err["type"], err["msg"]
    ctx_error = (err.get("ctx") or {}).get("error")
    if isinstance(ctx_error, _KeyProblem):
        loc, msg = ctx_error.loc, ctx_error.message
    elif isinstance(ctx_error, ValueError):
        msg = str(ctx_error)
    if kind == "extra_forbidden":
        valid = _fields_of(loc[:-1])
        msg = (
            f"unknown key {loc[-1]!r}; valid keys here: {', '.join(valid)}"
            f"{_did_you_mean(loc[-1], valid)}"
        )
    elif kind == "missing":
        msg = "required key is missing"
    elif kind == "literal_error":
        expected = (err.get("ctx") or {}).get("expected", "")
        choices = re.findall(r"'([^']*)'", expected)
        msg = f"{err['input']!r} is not valid; valid: {', '.join(choices)}" + _did_you_mean(
            err["input"], choices
        )
    elif kind.endswith("_type") or kind in ("model_type", "dict_type", "list_type"):
        msg = f"{msg}, got {type(err['input']).__name__} {_short(err['input'])}"
    path = _dotted(loc)
    line = _line_of(text, loc) if kind != "missing" else _line_of(text, loc[:-1])
    return SceneError(msg, source, path, line)


def _short(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


#: ``{initial.h}`` in a title: the value of that key (``{{`` and ``}}`` are literal braces).
_PLACEHOLDER = re.compile(r"\{\{|\}\}|\{([A-Za-z0-9_\-]+(?:\.[A-Za-z0-9_\-]+)*)\}")


def _title_value(value: object) -> str:
    """A scene value as a title shows it: text as written, lists as ``(a, b, c)``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list | tuple):
        return "(" + ", ".join(_title_value(v) for v in value) + ")"
    return str(value)


def _placeholders(title: str) -> list[str]:
    return [m.group(1) for m in _PLACEHOLDER.finditer(title) if m.group(1)]


def render_title(title: str, given: Mapping) -> str:
    """The title with each ``{dotted.key}`` replaced by that key's value in the scene.

    A title written with placeholders (``"K01 Fig. 7(a): h = {initial.h}"``) shows the values
    that run, also after ``--set``; ``{{`` and ``}}`` are literal braces.

    Parameters
    ----------
    title : str
    given : mapping
        The scene as given (``--set`` applied).

    Returns
    -------
    str

    Raises
    ------
    UserInputError
        A placeholder that names no key of the scene.
    """

    def value(match: re.Match) -> str:
        if match.group(0) in ("{{", "}}"):
            return match.group(0)[0]
        node: object = given
        for part in match.group(1).split("."):
            if not isinstance(node, Mapping) or part not in node:
                raise UserInputError(
                    f"{{{match.group(1)}}} in the title names no key of the scene "
                    "(write a dotted key such as {initial.h}, or {{ }} for braces)"
                )
            node = node[part]
        return _title_value(node)

    return _PLACEHOLDER.sub(value, title)


def _stale_overrides(title: object, overrides: Sequence[str], given: Mapping) -> str:
    """``--set`` items (as run) whose keys the title does not show by a placeholder."""
    shown = _placeholders(title) if isinstance(title, str) else []
    out = []
    for item in overrides:
        key = item.partition("=")[0].strip()
        if key == "title" or any(
            key == k or key.startswith(k + ".") or k.startswith(key + ".") for k in shown
        ):
            continue
        node: object = given
        for part in key.split("."):
            node = node.get(part) if isinstance(node, Mapping) else None
        out.append(f"{key} = {_title_value(node)}")
    return ", ".join(out)


def _mask_overridden(text: str, overrides: Sequence[str]) -> str:
    """``text`` with the lines of keys given by ``--set`` blanked, so that no message points at
    a line whose value was replaced."""
    lines = text.splitlines()
    for item in overrides:
        key = item.partition("=")[0].strip()
        line = _line_of("\n".join(lines), key.split("."))
        if line is not None and _KEY.match(lines[line - 1] or "") is not None:
            if _KEY.match(lines[line - 1]).group(1) == key.split(".")[-1]:
                lines[line - 1] = ""
    return "\n".join(lines)


def apply_overrides(data: Mapping, overrides: Sequence[str], source: str | None = None) -> dict:
    """``KEY=VALUE`` overrides (``run.t_end=100``) applied to a parsed scene.

    Parameters
    ----------
    data : mapping
        The parsed TOML.
    overrides : sequence of str
        Dotted key, ``=``, a TOML value (``100``, ``[1, 3, 5]``, ``"sqrt(2)"``, ``true``); a
        value that is not TOML is taken as text.
    source : str, optional
        File name for the messages.

    Returns
    -------
    dict
        A new mapping (``data`` is not changed).

    Raises
    ------
    SceneError
        A malformed item, or a key path through something that is not a table.
    """
    out = json.loads(json.dumps(data, default=str)) if overrides else dict(data)
    for item in overrides:
        key, sep, value = item.partition("=")
        key = key.strip()
        parts = key.split(".")
        if not sep or not key or not all(re.fullmatch(r"[A-Za-z0-9_\-]+", p) for p in parts):
            raise SceneError(f"--set expects KEY=VALUE with a dotted KEY, got {item!r}", source)
        try:
            parsed = tomllib.loads(f"v = {value.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            parsed = value.strip()
        except (RecursionError, MemoryError):
            raise SceneError(
                f"--set {key}: nested deeper than {MAX_SCENE_DEPTH} tables or lists", source
            ) from None
        _check_depth(parsed, source)
        node = out
        for i, part in enumerate(parts[:-1]):
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                raise SceneError(
                    f"--set {key}: {'.'.join(parts[: i + 1])} is not a table", source, key
                )
        node[parts[-1]] = parsed
    return out


# ---------------------------------------------------------------------------------- resolution
@dataclass
class Resolved:
    """A scene made concrete: model code, effects with reasons, vectors at working precision.

    Attributes
    ----------
    code : ModelCode
    effects : dict of str to str
        Effect -> why it is on.
    params : dict of str to number
        Parameter symbol -> value at the working precision.
    y0 : list
        Initial state vector (model order) at the working precision.
    prescribed : dict of str to number
        Integral values asked for (by integrals only).
    residuals : dict of str to float
        ``F(y0) - prescribed`` with the model's generated integrals.
    how : str
        How the initial point was chosen.
    load_s : float
        Time to load (or derive and emit) the model code.
    t_span : (t0, t1)
        At the working precision.
    digits : int or None
        Working decimal digits (None in double precision).
    """

    code: Any
    effects: dict[str, str]
    params: dict[str, Any]
    y0: list
    prescribed: dict[str, Any] = field(default_factory=dict)
    residuals: dict[str, float] = field(default_factory=dict)
    how: str = "given by state"
    load_s: float = 0.0
    t_span: tuple = (0.0, 1.0)
    digits: int | None = None

    def state_by_name(self) -> dict[str, str]:
        """Initial state by component name, as decimal strings (every working digit).

        Returns
        -------
        dict of str to str
        """
        return {n: _decimal(v, self.digits) for n, v in zip(self.code.state, self.y0, strict=True)}


def _decimal(value: object, digits: int | None = None) -> str:
    """A number as decimal text: floats by their shortest repr, mpf with ``digits`` digits."""
    import mpmath

    if isinstance(value, float | np.floating):
        return repr(float(value))
    if isinstance(value, mpmath.mpf):
        return mpmath.nstr(value, digits or 17, strip_zeros=False)
    return str(value)


def _resolve(scene: Scene) -> Resolved:
    import warnings

    import mpmath

    from ..numerics.code import load_model_code
    from ..numerics.initial_state import (
        INTEGRAL_KEYS,
        horizontal_frame,
        integral_residuals,
        state_from_integrals,
    )
    from ..numerics.inputs import Precision, pack_params, pack_state

    src = scene.source
    text = scene._text if scene._text is not None else _text_of(src)
    reasons = {e: "named in the scene" for e in scene.effects}
    for key, needs in OUTPUT_EFFECTS.items():
        if getattr(scene.outputs, key) is not None:
            for e in needs:
                reasons.setdefault(e, f"needed by outputs.{key}")
    for key, (analysis, _) in requested(scene.outputs).items():
        for e in analysis.effects:
            reasons.setdefault(e, f"needed by outputs.{key}")
    supported = SYSTEMS[scene.system].effects
    for e in reasons:
        if e not in supported:
            raise SceneError(f"{scene.system} does not support {e}, which outputs need", src)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            code = load_model_code(scene.system, sorted(reasons))
        except UserInputError as exc:
            raise SceneError(str(exc), src, "effects", _line_of(text, ("effects",))) from None
    load_s = time.perf_counter() - start
    try:
        prec = Precision(scene.run_options.precision)
    except UserInputError as exc:
        raise SceneError(
            str(exc), src, "run.precision", _line_of(text, ("run", "precision"))
        ) from None
    t_span = _time_span(scene, prec, text)
    method = scene.run_options.method
    if method is not None:
        from ..numerics.integrate import METHODS

        if method not in METHODS:
            loc = ("run", "method")
            raise SceneError(
                f"unknown method {method!r}; valid: {', '.join(METHODS)}"
                f"{_did_you_mean(method, list(METHODS))}",
                src,
                _dotted(loc),
                _line_of(text, loc),
            )
    # parameters: exactly the model's groups
    groups = code.parameter_groups
    for name in scene.parameters:
        if name not in groups:
            owner = _owner_effect(scene.system, name)
            hint = (
                f"; it belongs to effect {owner}, which is not on (add it to effects)"
                if owner
                else f"; valid: {', '.join(groups)}{_did_you_mean(name, list(groups))}"
            )
            raise SceneError(
                f"{code.name} has no parameter {name!r}{hint}",
                src,
                f"parameters.{name}",
                _line_of(text, ("parameters", name)),
            )
    missing = [g for g in groups if g not in scene.parameters]
    if missing:
        desc = groups[missing[0]][2]
        raise SceneError(
            f"parameter {missing[0]!r} is missing ({desc})",
            src,
            f"parameters.{missing[0]}",
            _line_of(text, ("parameters",)),
        )
    try:
        p = pack_params(code, dict(scene.parameters), prec)
    except UserInputError as exc:
        raise SceneError(str(exc), src, "parameters", _line_of(text, ("parameters",))) from None
    params = dict(zip(code.params, p, strict=True))
    # initial state
    given = {
        k: v
        for k, v in {**dict(scene.initial), **(scene.initial.model_extra or {})}.items()
        if v is not None
        and k not in ("parallel", "point", "rest", "near", "separatrix", "offset", *ANDOYER)
    }
    if scene.initial.parallel:
        given["parallel"] = True
    andoyer = {
        k: getattr(scene.initial, k) for k in ANDOYER if getattr(scene.initial, k) is not None
    }
    if scene.initial.rest:
        andoyer.setdefault("G", 0)
        if "M" in given or (andoyer.get("G") not in (0, "0")):
            raise SceneError("rest = true means M = 0: give no M and no G", src, "initial.rest",
                             _line_of(text, ("initial", "rest")))  # fmt: skip
        if "gamma" in given:
            given["M"] = [0, 0, 0]
    by_integrals = {k: given.pop(k) for k in INTEGRAL_KEYS if k in given}
    state_groups = code.state_groups
    for k in given:
        if k not in state_groups:
            valid = [*state_groups, *INTEGRAL_KEYS, "point"]
            raise SceneError(
                f"{code.name} has no state {k!r}; valid: {', '.join(valid)}"
                f"{_did_you_mean(k, valid)}",
                src,
                f"initial.{k}",
                _line_of(text, ("initial", k)),
            )
    _check_outputs(scene, code, text)
    prescribed, how = {}, "given by state"
    dps = prec.parse_dps
    special = _near_or_separatrix(scene, code, params, given, by_integrals, dps, text)
    if special is not None:
        given.update(special[0])
        by_integrals.update(special[1])
        prescribed, how = special[2], special[3]
    if andoyer and not (scene.initial.rest and set(andoyer) == {"G"} and "gamma" in given):
        missing = [k for k in ANDOYER if k not in andoyer]
        clash = [k for k in ("M", "gamma") if k in given] + list(by_integrals)
        if missing or clash:
            loc = ("initial", missing[0] if missing else clash[0])
            what = (
                f"initial.{missing[0]} is missing (Andoyer-Deprit needs G, z, l, g)"
                if missing
                else f"give the Andoyer-Deprit variables or {clash[0]}, not both"
            )
            raise SceneError(what, src, _dotted(loc), _line_of(text, loc))
        from ..numerics.initial_state import state_from_andoyer

        with mpmath.workdps(dps + 10):
            try:
                values = state_from_andoyer(*(_num(andoyer[k], dps) for k in ANDOYER))
            except UserInputError as exc:
                loc = ("initial", "z" if "z =" in str(exc) else "G")
                raise SceneError(str(exc), src, _dotted(loc), _line_of(text, loc)) from None
            given.update({k: [mpmath.nstr(c, dps + 5) for c in v] for k, v in values.items()})
        how = "Andoyer-Deprit variables G, z, l, g (BM20 (3.7))"
    elif scene.initial.rest:
        if "gamma" not in given:
            loc = ("initial", "rest")
            raise SceneError(
                "rest = true needs gamma (or the Andoyer-Deprit z, l, g)",
                src,
                _dotted(loc),
                _line_of(text, loc),
            )
        how = "from rest (M = 0)"
    if by_integrals and not prescribed:
        if "M" in given:
            raise SceneError(
                "give M or the integrals (h, C, n, parallel), not both", src, "initial.M",
                _line_of(text, ("initial", "M")),
            )  # fmt: skip
        request = {**by_integrals, "point": scene.initial.point}
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
            resolved = state_from_integrals(
                code, {k: mpmath.mpf(v) for k, v in params.items()}, num, dps
            )
        except UserInputError as exc:
            key = "h" if "energy" in str(exc) else "initial"
            loc = ("initial", key) if key in by_integrals else ("initial",)
            raise SceneError(str(exc), src, _dotted(loc), _line_of(text, loc)) from None
        prescribed, how = resolved.prescribed, resolved.how
        given.update({k: [mpmath.nstr(c, dps + 5) for c in v] for k, v in resolved.values.items()})
    if "alpha" in state_groups and "alpha" not in given and "M" in given and "gamma" in given:
        with mpmath.workdps(dps):
            M = [_num(v, dps) for v in given["M"]]
            g = [_num(v, dps) for v in given["gamma"]]
            gn = mpmath.sqrt(sum(c * c for c in g))
            g = [c / gn for c in g]
            cross = [
                M[1] * g[2] - M[2] * g[1],
                M[2] * g[0] - M[0] * g[2],
                M[0] * g[1] - M[1] * g[0],
            ]
            if mpmath.sqrt(sum(c * c for c in cross)) <= 1e-6 * max(
                mpmath.sqrt(sum(c * c for c in M)), 1
            ):
                alpha, beta = horizontal_frame(g)
                given["alpha"] = [mpmath.nstr(c, dps + 5) for c in alpha]
                given["beta"] = [mpmath.nstr(c, dps + 5) for c in beta]
                how += (
                    "; M || gamma: alpha = the body axis least aligned with gamma, projected "
                    "(BKM12-7 is undefined there)"
                )
    try:
        y0 = pack_state(code, given, prec)
    except UserInputError as exc:
        raise SceneError(str(exc), src, "initial", _line_of(text, ("initial",))) from None
    if needs_trajectory(scene):
        _check_step_budget(scene, code, t_span, y0, p, prec, text)
    residuals = {}
    if prescribed:
        residuals = integral_residuals(code, y0, p, prescribed, max(prec.digits or 17, 17))
    if scene.outputs.separatrix_delta is not None:
        from .scene_delta import separatrix_delta_problem

        problem = separatrix_delta_problem(scene.system, code, params, y0)
        if problem:
            loc = ("outputs", "separatrix_delta")
            raise SceneError(problem, src, _dotted(loc), _line_of(text, loc))
    return Resolved(
        code, reasons, params, y0, prescribed, residuals, how, load_s, t_span, prec.digits
    )


def _near_or_separatrix(scene, code, params, given, by_integrals, dps, text):
    """``near = "p_i"`` or ``separatrix = i``: ``(state groups, integral request, prescribed,
    how)`` or None."""
    import mpmath

    from ..numerics.initial_state import state_near_rotation

    ini, src = scene.initial, scene.source
    if ini.near is None and ini.separatrix is None:
        if ini.offset not in (0, "0"):
            loc = ("initial", "offset")
            raise SceneError(
                "offset needs near or separatrix", src, _dotted(loc), _line_of(text, loc)
            )
        return None
    key = "near" if ini.near is not None else "separatrix"
    loc = ("initial", key)
    where = (src, _dotted(loc), _line_of(text, loc))
    clash = [k for k in ("M", "gamma") if k in given] + [
        k for k in by_integrals if k not in (("C", "n") if key == "near" else ("C",))
    ]
    if ini.near is not None and ini.separatrix is not None:
        clash.append("separatrix")
    if clash or ini.parallel:
        raise SceneError(f"{key} fixes the state: give no {(clash or ['parallel'])[0]}", *where)
    if "K1" in code.params or "I1" not in code.params or "D" not in code.params:
        raise SceneError(f"{key} is defined for chaplygin_ball without gyrostat", *where)
    need = ("C", "n") if key == "near" else ("C",)
    missing = [k for k in need if k not in by_integrals]
    if missing:
        raise SceneError(f"{key} needs initial.{missing[0]}", *where)
    with mpmath.workdps(dps + 10):
        C = _num(by_integrals["C"], dps)
        offset = _num(ini.offset, dps)
        p = {k: mpmath.mpf(v) for k, v in params.items()}
        if key == "near":
            try:
                r = state_near_rotation(
                    code, p, int(ini.near[1]), C, _num(by_integrals["n"], dps), offset
                )
            except UserInputError as exc:
                raise SceneError(str(exc), *where) from None
            values = {k: [mpmath.nstr(c, dps + 5) for c in v] for k, v in r.values.items()}
            by_integrals.clear()
            return values, {}, r.prescribed, r.how
        I = sorted((p[f"I{i}"], i) for i in (1, 2, 3))
        if ini.separatrix != I[1][1]:
            raise SceneError(
                f"the separatrix on M || gamma belongs to the middle axis, here {I[1][1]} "
                f"(I = {', '.join(mpmath.nstr(v, 8) for v, _ in sorted(I, key=lambda t: t[1]))})",
                *where,
            )
        h = C * C / (2 * p[f"I{ini.separatrix}"]) * (1 + offset)
        request = {"C": by_integrals["C"], "h": mpmath.nstr(h, dps + 5), "parallel": True}
        by_integrals.clear()
        by_integrals.update(request)
        return {}, {}, {}, ""


def _time_span(scene: Scene, prec: Any, text: str | None) -> tuple:
    from ..numerics.inputs import working_number

    src = scene.source
    out = []
    if scene.run_options.t_end is None:
        if needs_trajectory(scene):
            loc = ("run", "t_end")
            raise SceneError(
                "run.t_end is required: this scene integrates a trajectory", src, _dotted(loc),
                _line_of(text, ("run",)),
            )  # fmt: skip
        start = working_number(scene.run_options.t_start, prec)
        return (start, start + 1)  # analyses only: they choose their own spans
    for key in ("t_start", "t_end"):
        loc = ("run", key)
        try:
            out.append(working_number(getattr(scene.run_options, key), prec))
        except UserInputError as exc:
            raise SceneError(str(exc), src, _dotted(loc), _line_of(text, loc)) from None
    if not out[1] > out[0]:
        loc = ("run", "t_end")
        raise SceneError(
            f"run.t_end must be after run.t_start ({_decimal(out[0])})",
            src,
            _dotted(loc),
            _line_of(text, loc),
        )
    return tuple(out)


def _check_step_budget(scene: Scene, code: Any, t_span, y0, p, prec: Any, text) -> None:
    """Refuse, before any work, a span whose estimated steps exceed ``run.max_steps`` (as
    ``chaplygin integrate`` does: :mod:`chaplygin.numerics.step_budget`)."""
    from ..numerics.step_budget import DEFAULT_MAX_STEPS, estimated_steps, motion_rate

    run = scene.run_options
    budget = run.max_steps or DEFAULT_MAX_STEPS
    span = abs(float(t_span[1] - t_span[0]))
    rate = motion_rate(code, float(t_span[0]), y0, p) if math.isfinite(span) else 1.0
    steps = estimated_steps(span * rate, run.method, run.rtol, prec.is_double)
    if steps > budget:
        loc = ("run", "t_end")
        at = "" if rate == 1 else f" at a rate |f(y0)|/|y0| of {rate:.2g}"
        raise SceneError(
            f"a span of {span:.3g}{at} needs about {steps:.2g} steps, beyond the budget of "
            f"{budget:.3g}; shorten the span or raise run.max_steps (default "
            f"{DEFAULT_MAX_STEPS:.0e})",
            scene.source,
            _dotted(loc),
            _line_of(text, loc),
        )


def quantity_names(code: Any) -> list[str]:
    """Names a series may show: state components, auxiliary quantities, integrals, ``I_i(t)``.

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    list of str
    """
    extra = ["I1(t)", "I2(t)", "I3(t)"] if "I1" in code.params else []
    return [*code.state, *code.aux_names, *code.integral_names, *extra]


def _check_outputs(scene: Scene, code: Any, text: str | None) -> None:
    src = scene.source
    series = scene.outputs.series
    if series is not None:
        valid = quantity_names(code)
        for i, q in enumerate(series.quantities):
            if q not in valid:
                loc = ("outputs", "series", "quantities", i)
                raise SceneError(
                    f"unknown quantity {q!r} for {code.name}; valid: {', '.join(valid)}"
                    f"{_did_you_mean(q, valid)}",
                    src,
                    _dotted(loc),
                    _line_of(text, loc),
                )
    if scene.outputs.diagram is not None:
        from .scene_diagram import diagram_problem

        problem = diagram_problem(scene.system, code.effects, code.name)
        if problem:
            loc = ("outputs", "diagram")
            raise SceneError(problem, src, _dotted(loc), _line_of(text, loc))
    for analysis, spec in requested(scene.outputs).values():
        if analysis.check is not None:
            analysis.check(scene, code, spec)


def _num(value: object, dps: int):
    from ..numerics.inputs import parse_number

    return parse_number(value, dps + 10)


def _text_of(source: str | None) -> str | None:
    if not source:
        return None
    try:
        return read_scene_file(source).decode("utf-8")
    except (SceneError, UnicodeDecodeError):
        return None


def _owner_effect(system: str, parameter: str) -> str | None:
    """The effects of the smallest variant in ``generated/`` that has ``parameter`` (for
    messages; nothing is derived)."""
    from ..numerics.code import generated_manifest, load_model_code

    if parameter in load_model_code(system, ()).parameter_groups:
        return None
    variants = sorted(
        (tuple(sorted(entry.get("effects") or [])) for entry in generated_manifest().values()
         if entry.get("system") == system),
        key=lambda v: (len(v), v),
    )  # fmt: skip
    for effects in variants:
        if effects and parameter in load_model_code(system, effects).parameter_groups:
            return " + ".join(effects)
    return None


# ------------------------------------------------------------------------------------ explain
def rhs_operation_count(code: Any) -> int:
    """Arithmetic operations (binary, unary, calls) in the generated numpy right-hand side.

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    int
    """
    import ast
    import inspect

    tree = ast.parse(inspect.getsource(code.numpy.rhs))
    count = 0
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp | ast.UnaryOp):
            count += 1
        elif isinstance(node, ast.Call) and not (
            isinstance(node.func, ast.Attribute)
            and node.func.attr in ("zeros", "shape", "result_type")
        ):
            count += 1
    return count


def _largest_variant(system: str) -> Any:
    from ..numerics.code import load_model_code

    variants = SYSTEMS[system].variants
    biggest = max(variants, key=lambda v: (len(v), v))
    return load_model_code(system, biggest)


def explain_text(scene: Scene, res: Resolved) -> str:
    """What a run of ``scene`` (resolved as ``res``) would do, as text (``--explain``).

    Parameters
    ----------
    scene : Scene
    res : Resolved

    Returns
    -------
    str
    """
    from ..numerics.code import generated_manifest
    from .cli_common import printable

    code = res.code
    title = printable(scene.title or scene.source or "(untitled)", keep="")
    lines = [f"scene: {title}", f"model: {code.name}"]
    lines.append("effects:")
    if not res.effects:
        lines.append("  none (the bare system)")
    for e, why in res.effects.items():
        lines.append(f"  {e}: {why}")
    lines.append(f"states ({len(code.state)}): {', '.join(code.state)}")
    lines.append(
        "parameters: "
        + ", ".join(f"{k} = {_decimal(v, res.digits)}" for k, v in res.params.items())
    )
    lines.append(f"initial state ({res.how}):")
    lines.extend(f"  {k} = {v}" for k, v in res.state_by_name().items())
    for name, r in res.residuals.items():
        lines.append(f"  residual of {name}: {r:.3e}")
    big = _largest_variant(scene.system)
    ops, ops_big = rhs_operation_count(code), rhs_operation_count(big)
    lines.append(
        f"right-hand side: {ops} operations ({len(code.state)} states) against {ops_big} "
        f"({len(big.state)} states) for {big.name}, the largest effect combination in generated/"
    )
    manifest = generated_manifest()
    method = scene.run_options.method or "taylor"
    if code.name in manifest:
        files = manifest[code.name]["files"]
        if method == "taylor":
            which = _taylor_files(files, scene.run_options.precision)
        else:
            which = f"{files['c']} (compiled on first use, cached) or {files['numpy']}"
        code_line = f"code: generated/{which}"
    else:
        code_line = f"code: {code.note}"
    if needs_trajectory(scene):
        lines.append(f"{code_line}; trajectory method {method}")
    else:
        lines.append(code_line)
        lines.append("trajectory: none (the outputs are analyses; add [outputs.trajectory])")
    for key, (analysis, _) in requested(scene.outputs).items():
        lines.append(f"analysis {key}: {analysis.description}")
    return "\n".join(lines)


def _taylor_files(files: Mapping[str, str], precision) -> str:
    """Which generated Taylor source runs at ``precision`` (what --explain names)."""
    from ..numerics.inputs import Precision

    prec = Precision(precision)
    fallback = f"; generated/{files['taylor_py']} without a compiler)"
    if prec.is_double:
        what = ("double; the coefficients written out for the run's orders, pairs of nodes "
                "in vectors of two doubles")
    elif prec.is_quad:
        what = "__float128"
    else:
        arithmetic = prec.arithmetic
        if arithmetic.name == "mpfr" and "taylor_mpfr" in files:
            return f"{files['taylor_mpfr']} (compiled Taylor integrator, MPFR" + fallback
        what = arithmetic.description if arithmetic.name != "mpfr" else "MPFR in Python"
    return f"{files['taylor_c']} (compiled Taylor integrator, {what}" + fallback


# ---------------------------------------------------------------------------------------- run
def _progress_event(t0: float, t1: float, enabled: bool):
    """An event function that never fires and moves a tqdm bar (shown after 2 s)."""
    if not enabled:
        return None, None
    from tqdm import tqdm

    total = abs(float(t1) - float(t0))
    bar = tqdm(
        total=total,
        delay=2.0,
        file=sys.stderr,
        leave=False,
        mininterval=0.5,
        bar_format="{l_bar}{bar}| t = {n:.6g} of {total:.6g} [{elapsed}<{remaining}]",
    )
    state = {"last": float(t0)}

    def event(t, y):
        now = float(t)
        step = abs(now - state["last"])
        if step > 0:
            bar.update(min(step, total - bar.n))
            state["last"] = now
        return 1.0

    return event, bar


def run_resolved(scene: Scene, res: Resolved, progress: bool) -> SceneResult:
    """Integrate a resolved scene.

    Parameters
    ----------
    scene : Scene
    res : Resolved
        What :meth:`Scene.resolve` returned.
    progress : bool
        Show a tqdm bar on stderr (after 2 s).

    Returns
    -------
    SceneResult

    Raises
    ------
    SceneError
        The integrator refused the run settings.
    """
    started = time.perf_counter()
    result = backward = None
    if needs_trajectory(scene):
        result, backward = _integrate_trajectory(scene, res, progress)
    done = {}
    for key, (analysis, spec) in requested(scene.outputs).items():
        done[key] = analysis.run(scene, res, spec, progress)
    wall = time.perf_counter() - started
    return SceneResult(scene, res, result, wall, done, backward)


#: Outputs drawn from the scene's trajectory.
TRAJECTORY_OUTPUTS = (
    "contact_trace",
    "body_trace",
    "series",
    "drift",
    "diagram",
    "separatrix_delta",
)


def needs_trajectory(scene: Scene) -> bool:
    """Whether a run integrates the scene's trajectory: a trajectory output is asked for, or
    ``[outputs.trajectory]`` is given, or the scene asks for no analysis.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    bool
    """
    outputs = scene.outputs
    if "trajectory" in outputs.model_fields_set or not requested(outputs):
        return True
    return any(getattr(outputs, key) is not None for key in TRAJECTORY_OUTPUTS)


def _integrate_trajectory(scene: Scene, res: Resolved, progress: bool) -> tuple[Any, Any]:
    import mpmath

    from ..numerics.inputs import Precision
    from ..numerics.integrate import integrate
    from ..numerics.step_budget import DEFAULT_MAX_STEPS

    prec = Precision(scene.run_options.precision)
    t0, t1 = res.t_span
    n = scene.run_options.points or int(min(max(20 * float(t1 - t0) + 1, 2001), 200_001))
    if prec.is_double:
        t_eval = list(np.linspace(t0, t1, n))
    else:
        with mpmath.workprec(prec.prec):
            t_eval = [t0 + (t1 - t0) * mpmath.mpf(i) / (n - 1) for i in range(n)]
    method = scene.run_options.method
    event, bar = _progress_event(t0, t1, progress and method != "odefun")

    def run_over(t_end, times, events=None):
        return integrate(
            res.code,
            res.y0,
            (t0, t_end),
            [res.params[k] for k in res.code.params],
            method=method,
            precision=scene.run_options.precision,
            rtol=scene.run_options.rtol,
            atol=scene.run_options.atol,
            backend=scene.run_options.backend,
            t_eval=times,
            events=events,
            max_steps=scene.run_options.max_steps or DEFAULT_MAX_STEPS,  # the budget checked
        )

    try:
        result = run_over(t1, t_eval, [event] if event else None)
    except UserInputError as exc:
        raise SceneError(str(exc), scene.source, "run") from None
    finally:
        if bar is not None:
            bar.close()
    backward = None
    if scene.outputs.separatrix_delta is not None and result.success:
        # the same run mirrored about t_start: the trace's other asymptotic centre
        t_back = [2 * t0 - t for t in t_eval]
        backward = run_over(t_back[-1], t_back)
    return result, backward


@dataclass
class SceneResult:
    """What :meth:`Scene.run` returns: the arrays, the drift, figures and the summary.

    Attributes
    ----------
    scene : Scene
    resolved : Resolved
    integration : IntegrationResult or None
        The scene's trajectory; None when its outputs are analyses only
        (:func:`needs_trajectory`).
    wall_s : float
        Wall time of the whole run (set-up included).
    analyses : dict of str to AnalysisResult
        The analyses' results by output key (:mod:`chaplygin.verify.analyses`).
    backward : IntegrationResult or None
        With ``outputs.separatrix_delta``: the run from ``t_start`` back to
        ``2 t_start - t_end``.
    """

    scene: Scene
    resolved: Resolved
    integration: Any
    wall_s: float
    analyses: dict[str, AnalysisResult] = field(default_factory=dict)

    def _trajectory(self) -> Any:
        if self.integration is None:
            raise SceneError(
                "this run integrated no trajectory (its outputs are analyses only); "
                "add [outputs.trajectory] to the scene to get one",
                self.scene.source,
                "outputs",
            )
        return self.integration

    backward: Any = None
    _delta_report: dict | None = field(default=None, repr=False)

    # ------------------------------------------------------------------- arrays
    @property
    def t(self) -> np.ndarray:
        """Output times (float64)."""
        return np.asarray(self._trajectory().t, dtype=float)

    @property
    def y(self) -> dict[str, np.ndarray]:
        """State components by name (float64 arrays)."""
        arr = np.asarray(self._trajectory().y, dtype=float)
        return dict(zip(self.integration.state_names, arr, strict=True))

    @property
    def drift(self) -> dict[str, float]:
        """Largest relative change of every integral (absolute where its start is ~0)."""
        return dict(self._trajectory().drift)

    @property
    def success(self) -> bool:
        """True when the trajectory reached ``t_end`` (True without a trajectory)."""
        return self.integration is None or self.integration.success

    def _p(self) -> np.ndarray:
        return np.asarray([float(v) for v in self.resolved.params.values()])

    def quantity(self, name: str) -> np.ndarray:
        """A state component, auxiliary quantity (``omega1``), integral or ``I1(t)``..``I3(t)``.

        Parameters
        ----------
        name : str

        Returns
        -------
        ndarray

        Raises
        ------
        SceneError
            An unknown name (the message lists the valid ones).
        """
        code = self.resolved.code
        y = np.asarray(self._trajectory().y, dtype=float)
        if name in code.state:
            return y[code.state.index(name)]
        if name in code.aux_names:
            return np.asarray(code.numpy.aux(self.t, y, self._p()))[code.aux_names.index(name)]
        if name in code.integral_names:
            values = code.numpy.integrals(self.t, y, self._p())
            return np.asarray(values)[code.integral_names.index(name)] * np.ones_like(self.t)
        m = re.fullmatch(r"I([123])\(t\)", name)
        if m and "I1" in code.params:
            p = self.resolved.params
            base = float(p[f"I{m.group(1)}"])
            if m.group(1) == "2" or "J_off" not in p:
                return base * np.ones_like(self.t)
            off = float(p["J_off"]) + float(p["delta"]) * detmath.sin(
                float(p["Omega"]) * np.asarray(self.t, dtype=float)
            )
            return base + off**2
        valid = self.quantity_names()
        raise SceneError(
            f"unknown quantity {name!r}; valid: {', '.join(valid)}{_did_you_mean(name, valid)}",
            self.scene.source,
            "outputs.series.quantities",
        )

    def quantity_names(self) -> list[str]:
        """Every name :meth:`quantity` accepts.

        Returns
        -------
        list of str
        """
        return quantity_names(self.resolved.code)

    def integral_change(self) -> dict[str, np.ndarray]:
        """``|F(t) - F(0)|``, relative to ``|F(0)|`` where that is not ~0, per integral.

        Returns
        -------
        dict of str to ndarray
        """
        code = self.resolved.code
        values = np.asarray(
            code.numpy.integrals(self.t, np.asarray(self.integration.y, float), self._p()), float
        )
        values = values * np.ones((len(values), len(self.t)))
        out = {}
        for i, name in enumerate(code.integral_names):
            ref = abs(values[i, 0])
            change = np.abs(values[i] - values[i, 0])
            out[name] = change / ref if name not in self.integration.drift_absolute else change
        return out

    # ------------------------------------------------------------------ figures
    def contact_trace_figure(self) -> Figure:
        """The contact point in the plane (``x, y``).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from .plots import contact_trace_figure

        y = self.y
        spec = self.scene.outputs.contact_trace
        aspect = spec.aspect if spec is not None else "equal"
        return contact_trace_figure(y["x"], y["y"], self._title(), aspect)

    def body_trace_figure(self) -> Figure:
        """The contact point ``-b gamma`` on the ball's surface, in the body frame.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from .plots import body_trace_figure

        y = self.y
        gamma = np.array([y["gamma1"], y["gamma2"], y["gamma3"]])
        return body_trace_figure(gamma, float(self.resolved.params["b"]), self._title())

    def series_figure(self, quantities: Sequence[str] | None = None) -> Figure:
        """Time series of ``quantities`` (default: those of ``outputs.series``).

        Parameters
        ----------
        quantities : sequence of str, optional

        Returns
        -------
        matplotlib.figure.Figure
        """
        from .plots import series_figure

        if quantities is None:
            series = self.scene.outputs.series
            quantities = series.quantities if series else ["H"]
        return series_figure(self.t, {q: self.quantity(q) for q in quantities}, self._title())

    def drift_figure(self) -> Figure:
        """Change of every integral over time (log scale).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from .plots import drift_figure

        return drift_figure(self.t, self.integral_change(), self._title())

    def diagram_figure(self) -> Figure:
        """The energy diagram (n, h) at this ``C`` with the scene's point.

        K01's diagram for the ball (``C = (M, gamma)``, ``n = (M, M)``); with the gyrostat the
        diagram at ``C = (M + K, gamma)``, ``n = (M + K, M + K)``
        (:func:`chaplygin.verify.scene_diagram.gyrostat_diagram_figure`); BKM12 Fig. 5's for
        the spherical support (:func:`chaplygin.verify.scene_diagram.support_diagram_figure`).

        Returns
        -------
        matplotlib.figure.Figure

        Raises
        ------
        SceneError
            A model without a diagram (the message lists those that have one).
        """
        from .plots import scene_diagram_figure
        from .scene_diagram import (
            diagram_kind,
            diagram_problem,
            gyrostat_diagram_figure,
            support_diagram_figure,
        )

        code = self.resolved.code
        kind = diagram_kind(self.scene.system, code.effects)
        if kind is None:
            raise SceneError(
                diagram_problem(self.scene.system, code.effects, code.name),
                self.scene.source,
                "outputs.diagram",
            )
        names = code.integral_names
        F0 = np.asarray(
            code.numpy.integrals(
                self.t[:1], np.asarray(self.integration.y, float)[:, :1], self._p()
            ),
            float,
        )[:, 0]
        p = self.resolved.params
        I = [float(p[f"I{i}"]) for i in (1, 2, 3)]
        h = F0[names.index("H")]
        if kind == "gyrostat":
            C, n = F0[names.index("(M+K,gamma)")], F0[names.index("(M+K,M+K)")]
            K = [float(p[f"K{i}"]) for i in (1, 2, 3)]
            return gyrostat_diagram_figure(I, float(p["D"]), K, C, n, h, self._title())
        if kind == "support":
            C = F0[names.index("(M,M)")]
            g = [F0[names.index(f"(M,{v})")] / np.sqrt(C) for v in ("alpha", "beta", "gamma")]
            params = [float(v) for v in p.values()]
            return support_diagram_figure(params, g, 2 * h / C, self._title())
        C, n = F0[names.index("(M,gamma)")], F0[names.index("(M,M)")]
        return scene_diagram_figure(I, float(p["D"]), C, n, h, self._title())

    def separatrix_delta(self) -> dict:
        """Delta measured between the trace's two asymptotic centres, against K01-3.7.

        See :func:`chaplygin.verify.scene_delta.separatrix_delta_report` (computed once).

        Returns
        -------
        dict

        Raises
        ------
        SceneError
            The scene did not ask for ``separatrix_delta`` or its run failed.
        """
        if self.backward is None:
            raise SceneError(
                "Delta needs outputs.separatrix_delta and a run that reached its end",
                self.scene.source,
                "outputs.separatrix_delta",
            )
        if self._delta_report is None:
            from ..numerics.inputs import Precision
            from .scene_delta import separatrix_delta_report

            rtol = self.scene.run_options.rtol
            if rtol is None:
                prec = Precision(self.scene.run_options.precision)
                rtol = prec.default_tolerances[0]
            self._delta_report = separatrix_delta_report(self, float(rtol))
        return self._delta_report

    def separatrix_delta_figure(self) -> Figure:
        """Both halves of the separatrix trace with their centres and Delta marked.

        Returns
        -------
        matplotlib.figure.Figure

        Raises
        ------
        SceneError
            As :meth:`separatrix_delta`.
        """
        from .scene_delta import separatrix_delta_figure

        return separatrix_delta_figure(self, self.separatrix_delta(), self._title())

    def figures(self) -> dict:
        """The figures the scene asks for (``outputs.* .plot = true``).

        Returns
        -------
        dict of str to matplotlib.figure.Figure
        """
        makers = {
            "contact_trace": self.contact_trace_figure,
            "body_trace": self.body_trace_figure,
            "series": self.series_figure,
            "drift": self.drift_figure,
            "diagram": self.diagram_figure,
            "separatrix_delta": self.separatrix_delta_figure,
        }
        out = {}
        for key, make in makers.items():
            spec = getattr(self.scene.outputs, key)
            if key == "separatrix_delta" and self.backward is None:
                continue  # the forward run failed: there is no Delta to draw
            if spec is not None and spec.plot:
                out[key] = make()
        for key, done in self.analyses.items():
            if getattr(getattr(self.scene.outputs, key), "plot", True):
                for name, make in done.figures.items():
                    out[name] = make()
        return out

    def _title(self) -> str:
        from .plots import literal_text

        return literal_text(self.scene.title or self.resolved.code.name)

    # ------------------------------------------------------------------ summary and files
    def summary(self, outputs: Sequence[str] = ()) -> dict:
        """Everything that identifies and qualifies the run (``summary.json``).

        Parameters
        ----------
        outputs : sequence of str
            Files written (relative names).

        Returns
        -------
        dict
        """

        r, res = self.integration, self.resolved
        digits = res.digits
        summary = {
            "title": self.scene.title,
            "source": self.scene.source,
            "scene": self.scene._given,
            "resolved": {
                "system": self.scene.system,
                "model": res.code.name,
                "effects": res.effects,
                "parameters": {k: _decimal(v, digits) for k, v in res.params.items()},
                "initial": res.state_by_name(),
                "initial_how": res.how,
                "prescribed": {k: _decimal(v, digits) for k, v in res.prescribed.items()},
                "residuals": res.residuals,
            },
            "system": self.scene.system,
            "effects": sorted(res.effects),
            "states": list(res.code.state),
            "model_hash": res.code.hash,
            "code_origin": res.code.origin,
            "code_load_s": res.load_s,
            **({"code_note": res.code.note} if res.code.note else {}),
            "precision": str(self.scene.run_options.precision),
            "rtol": self.scene.run_options.rtol,
            "atol": self.scene.run_options.atol,
            "wall_s": self.wall_s,
            "versions": _software_versions(),
            **(
                {"separatrix_delta": self.separatrix_delta()}
                if self.scene.outputs.separatrix_delta is not None and self.backward is not None
                else {}
            ),
        }
        if r is not None:
            summary.update(
                {
                    "y": {k: _decimal(v, digits) for k, v in r.y_final.items()},
                    "t_end": _decimal(r.t[-1], digits),
                    "drift": {k: (v if math.isfinite(v) else None) for k, v in r.drift.items()},
                    "drift_absolute": list(r.drift_absolute),
                    "status": r.status,
                    "message": r.message,
                    "method": r.method,
                    "backend": r.backend,
                    "precision": r.precision,
                    "steps": r.nsteps,
                    "nfev": r.nfev,
                    "integration_wall_s": r.wall_s,
                    "setup_s": r.setup_s,
                }
            )
        if self.analyses:
            summary["analyses"] = {key: done.summary for key, done in self.analyses.items()}
        summary["outputs"] = list(outputs)
        return summary

    def write(self, folder: str | Path) -> list[str]:
        """Write the outputs into an existing empty ``folder``.

        Parameters
        ----------
        folder : str or Path

        Returns
        -------
        list of str
            The files written (names relative to ``folder``), ``summary.json`` last.
        """
        from .trajectory import write_dataset

        folder = Path(folder)
        written = []
        fmt = self.scene.outputs.trajectory.format if self.integration is not None else None
        if fmt in ("netcdf", "both"):
            self._write_netcdf(folder / "trajectory.nc")
            written.append("trajectory.nc")
        if fmt in ("csv", "both"):
            self._write_csv(folder / "trajectory.csv")
            written.append("trajectory.csv")
        for key, done in self.analyses.items():
            if done.arrays:
                attrs = {"title": self.scene.title or "", "model": self.resolved.code.name}
                write_dataset(folder / f"{key}.nc", done.arrays, attrs)
                written.append(f"{key}.nc")
        for key, fig in self.figures().items():
            for ext in ("png", "svg"):
                fig.savefig(folder / f"{key}.{ext}", dpi=120)
                written.append(f"{key}.{ext}")
        written.append("summary.json")
        (folder / "summary.json").write_text(
            json.dumps(self.summary(written), indent=2, allow_nan=False, default=str) + "\n"
        )
        return written

    def _columns(self) -> list[tuple[str, np.ndarray, str, str]]:
        from .trajectory import trajectory_columns

        code = self.resolved.code
        return trajectory_columns(self.t, self.integration.y, code.state, code.state_groups)

    def _write_netcdf(self, path: Path) -> None:
        from .trajectory import write_trajectory

        code = self.resolved.code
        attrs = {"title": self.scene.title or "", "model": code.name, "model_hash": code.hash}
        write_trajectory(path, self._columns(), attrs)

    def _write_csv(self, path: Path) -> None:
        from .trajectory import write_trajectory

        write_trajectory(path, self._columns())

    # ------------------------------------------------------------------ display
    def __repr__(self) -> str:
        if self.integration is None:
            return (
                f"<SceneResult {self.resolved.code.name}: analyses "
                f"{', '.join(self.analyses)}, {self.wall_s:.3g} s>"
            )
        worst = max(self.drift.values(), default=0.0)
        return (
            f"<SceneResult {self.resolved.code.name}: t = {self.t[-1]:g}, "
            f"{len(self.t)} points, {self.integration.nsteps} steps, max drift {worst:.2e}, "
            f"status {self.integration.status}>"
        )

    def _repr_html_(self) -> str:
        if self.integration is None:
            return f"<pre>{html.escape(repr(self))}</pre>"
        rows = "".join(
            f"<tr><td>{html.escape(k)}</td><td>{v:.3e}</td></tr>" for k, v in self.drift.items()
        )
        return (
            f"<b>{html.escape(self.scene.title or self.resolved.code.name)}</b><br>"
            f"model {html.escape(self.resolved.code.name)}, t = {self.t[-1]:g}, "
            f"{self.integration.nsteps} steps, status {self.integration.status}"
            f"<table><tr><th>integral</th><th>drift</th></tr>{rows}</table>"
        )


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("chaplygin")
    except PackageNotFoundError:  # pragma: no cover
        return "unknown"


def _software_versions() -> dict[str, str]:
    """The versions a result depends on: chaplygin, Python, numpy, scipy, sympy, mpmath."""
    import mpmath
    import scipy
    import sympy

    return {
        "chaplygin": _version(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "sympy": sympy.__version__,
        "mpmath": mpmath.__version__,
    }


# ------------------------------------------------------------------------- output folder
def prepare_output(out: str | Path) -> Any:
    """Check, before any work, that a run may write into ``out``: a new folder, an empty one,
    or a folder of a previous run (its marker lists the files we wrote, each unchanged).

    See :mod:`chaplygin.verify.output_folder`.

    Parameters
    ----------
    out : str or Path

    Returns
    -------
    chaplygin.verify.output_folder.OutputFolder

    Raises
    ------
    UserInputError
        Anything else (a non-empty folder that is not ours, a changed file of ours, a folder
        where nothing can be created); nothing is touched.
    """
    from .output_folder import OutputFolder

    return out if isinstance(out, OutputFolder) else OutputFolder.check(out)


def write_atomically(result: SceneResult, out: Any) -> list[str]:
    """Write the outputs beside the folder's files and move them into place at the end,
    replacing only the files of our previous run (see :func:`prepare_output`).

    Parameters
    ----------
    result : SceneResult
    out : str, Path or OutputFolder
        Checked by :func:`prepare_output` (again, if a path).

    Returns
    -------
    list of str
        Files written (relative to ``out``).
    """
    return prepare_output(out).write(result.write)
