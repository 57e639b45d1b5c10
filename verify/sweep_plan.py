"""A sweep's plan: its axes, grid points, chunks, variables and fingerprint
(:func:`plan_sweep`), each point a scene with the axis keys replaced (:func:`point_scene`)."""

from __future__ import annotations

import copy
import hashlib
import json
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from itertools import product
from pathlib import Path
from typing import Any

import numpy as np

from .sweep_checks import (
    CHUNK_OVERHEAD_BYTES,
    GridCost,
    check_grid_cost,
    usable_cpus,
)
from .sweep_reducers import REDUCERS, Variable
from .sweep_store import (
    STORE_FORMAT,
)

__all__ = ["SweepPlan", "plan_sweep", "point_scene", "CARRY_KEY", "CARRY_DIRECTIONS"]

#: The leading dimension of a sweep with ``carry = "both"``, and its labels (the order of the
#: last axis's values, and the reverse).
CARRY_KEY = "carry"
CARRY_DIRECTIONS = ("forward", "backward")


# ---------------------------------------------------------------------------------- the plan
@dataclass
class SweepPlan:
    """A sweep made concrete: axes, points, chunks, variables and fingerprint.

    Attributes
    ----------
    scene : Scene
        The scene as written (its ``sweep`` table included).
    base : dict
        The scene's data without ``sweep`` (each point replaces some keys of it).
    axes : list of (str, str, list)
        ``(key path, dimension name, values as given)``.
    coords : dict of str to numpy.ndarray
        Float64 coordinates of each axis.
    dims : tuple of str
    shape : tuple of int
    chunks : list of tuple of slice
        Region of each chunk in the grid.
    variables : dict of str to Variable
    extra_coords : dict of str to list
    code : ModelCode
        The model of the first point.
    fingerprint : dict of str to str
        Hashes of the scene, the grid and the code version.
    """

    scene: Any
    base: dict
    axes: list[tuple[str, str, list]]
    coords: dict[str, np.ndarray]
    dims: tuple[str, ...]
    shape: tuple[int, ...]
    chunks: list[tuple[slice, ...]]
    variables: dict[str, Variable]
    extra_coords: dict[str, list]
    code: Any
    fingerprint: dict[str, str]

    def points(self, region: tuple[slice, ...]) -> list[dict[str, Any]]:
        """The points of a chunk: key path -> value as given, in C order.

        Parameters
        ----------
        region : tuple of slice

        Returns
        -------
        list of dict
        """
        ranges = [range(s.start, s.stop) for s in region]
        out = []
        for index in product(*ranges):
            if len(self.dims) == 1 and self.dims[0] == "point":  # a list grid
                out.append({key: values[index[0]] for key, _, values in self.axes})
            else:
                out.append(
                    {key: values[i] for (key, _, values), i in zip(self.axes, index, strict=True)}
                )
        return out

    @property
    def total(self) -> str:
        """The fingerprint as one hex string."""
        return _sha(self.fingerprint)


def _sha(data: object) -> str:
    return hashlib.sha256(json.dumps(data, sort_keys=True, default=str).encode()).hexdigest()


def _axis_values(spec: Any, first_only: bool = False) -> list:
    import mpmath

    from ..numerics.inputs import parse_number

    if isinstance(spec, list):
        return list(spec[:1] if first_only else spec)

    def exact(value: object) -> Any:  # a TOML float as the decimal written
        return parse_number(repr(value) if isinstance(value, float) else value, 30)

    with mpmath.workdps(30):
        a, b = exact(spec.start), exact(spec.stop)
        if spec.num == 1 or first_only:
            return [mpmath.nstr(a, 30)]
        step = (b - a) / (spec.num - 1)
        return [mpmath.nstr(a + step * i, 30) for i in range(spec.num)]


def point_scene(base: Mapping, overrides: Mapping[str, Any], source: str | None = None) -> Any:
    """The scene of one point: ``base`` with dotted keys replaced.

    Parameters
    ----------
    base : mapping
        A scene's data (without ``sweep``).
    overrides : mapping of str to value
        ``"parameters.D" -> 4.39`` (values as a scene holds them).
    source : str, optional
        For messages.

    Returns
    -------
    Scene

    Raises
    ------
    SceneError
    """
    from .scene import Scene

    data = copy.deepcopy(dict(base))
    for key, value in overrides.items():
        root, name = key.split(".")
        data.setdefault(root, {})[name] = value
    return Scene.from_dict(data, source=source)


def plan_sweep(scene: Any, workers: int | None = None, store: Path | None = None) -> SweepPlan:
    """Resolve a scene's sweep: axes, chunks, variables, fingerprint; the first point is
    resolved to check the keys and load the model, and the grid's cost is checked
    (:func:`~chaplygin.verify.sweep_checks.check_grid_cost`) before its points are made.

    Parameters
    ----------
    scene : Scene
        With a ``[sweep]`` table.
    workers : int, optional
        Worker processes, for the time estimate (default: the usable CPUs).
    store : Path, optional
        Where the store goes, for the disk estimate.

    Returns
    -------
    SweepPlan

    Raises
    ------
    SceneError
        No ``[sweep]`` table, an unknown reducer, a key the scene refuses.
    UserInputError
        A grid beyond the machine (memory, disk, time), with the numbers.
    """
    from .scene import SceneError, package_version

    sweep = scene.sweep
    if sweep is None:
        raise SceneError("the scene has no [sweep] table", scene.source, "sweep")
    carry_both = _check_reducers(scene, sweep)
    base = {k: v for k, v in scene.given.items() if k != "sweep"}
    dims, shape = _grid_shape(sweep, carry_both)
    first_scene, code = _first_point(scene, base, sweep)
    per_point = math.inf  # the model is loaded: what resolving a point costs (least of 3)
    for _ in range(3):
        started = time.perf_counter()
        first_scene.resolve()
        per_point = min(per_point, time.perf_counter() - started)
    _check_axis_keys(scene, code)
    _check_model(scene, sweep, code)
    variables, extra = _variables(scene, sweep, code)
    n_chunks = math.prod(shape[:-1]) * -(-shape[-1] // sweep.chunk)
    _check_cost(shape, n_chunks, variables, extra, per_point, workers, store)
    chunks = _chunks(shape, sweep.chunk)  # after the check: a grid beyond the machine is refused
    axes = [(key, key.split(".")[1], _axis_values(v)) for key, v in sweep.axes.items()]
    from ..numerics.inputs import parse_number

    coords = {name: np.asarray([float(parse_number(v)) for v in vals]) for _, name, vals in axes}
    if carry_both:
        axes.insert(0, (CARRY_KEY, CARRY_KEY, list(CARRY_DIRECTIONS)))
        coords[CARRY_KEY] = np.asarray(CARRY_DIRECTIONS)
    fingerprint = {
        "scene": _sha(base),
        "grid": _sha({"sweep": scene.given.get("sweep"), "axes": axes, "dims": dims}),
        "code": _sha(
            {"chaplygin": package_version(), "model_hash": code.hash, "format": STORE_FORMAT}
        ),
    }
    return SweepPlan(
        scene, base, axes, coords, dims, shape, chunks, variables, extra, code, fingerprint
    )


def _check_reducers(scene: Any, sweep: Any) -> bool:
    """Refuse an unknown reducer, or ``carry`` with a reducer that carries no state; whether
    the grid has the leading dimension of ``carry = "both"``."""
    from .scene import SceneError, did_you_mean

    for name in sweep.reduce:
        if name not in REDUCERS:
            raise SceneError(
                f"unknown reducer {name!r}; valid: {', '.join(REDUCERS)}"
                f"{did_you_mean(name, list(REDUCERS))}",
                scene.source,
                "sweep.reduce",
            )
    if sweep.carry == "none":
        return False
    cannot = [n for n in sweep.reduce if not REDUCERS[n].carries]
    if cannot:
        able = ", ".join(n for n, r in REDUCERS.items() if r.carries)
        raise SceneError(
            f"carry follows an attractor along the grid lines: the reducers "
            f"{', '.join(cannot)} do not carry a state (use {able})",
            scene.source,
            "sweep.carry",
        )
    return sweep.carry == "both"  # a leading dimension: the two directions


def _grid_shape(sweep: Any, carry_both: bool) -> tuple[tuple[str, ...], tuple[int, ...]]:
    """The grid's dimensions and shape."""
    sizes = [len(v) if isinstance(v, list) else v.num for v in sweep.axes.values()]
    if carry_both:
        sizes.insert(0, len(CARRY_DIRECTIONS))
    if sweep.grid == "list":
        return ("point",), (sizes[0],)
    dims = ((CARRY_KEY,) if carry_both else ()) + tuple(key.split(".")[1] for key in sweep.axes)
    return dims, tuple(sizes)


def _first_point(scene: Any, base: Mapping, sweep: Any) -> tuple[Any, Any]:
    """The scene of the grid's first point and its model code (resolved: the keys checked)."""
    from .scene import SceneError

    first = {key: _axis_values(v, first_only=True)[0] for key, v in sweep.axes.items()}
    try:
        first_scene = point_scene(base, first, scene.source)
        return first_scene, first_scene.resolve().code
    except SceneError as exc:
        # a point may lie where the scene finds no state (that point's status says so); the
        # scene as written must resolve then
        try:
            first_scene = point_scene(base, {}, scene.source)
            return first_scene, first_scene.resolve().code
        except SceneError:
            exc.args = (f"{exc.args[0]} (at the sweep's first point {first})",)
            raise exc from None


def _check_model(scene: Any, sweep: Any, code: Any) -> None:
    """Refuse reducers the model cannot serve (no forcing frequency)."""
    from .scene import SceneError

    if "period" in sweep.reduce and sweep.period.forcing not in code.params:
        raise SceneError(
            f"reduce = period needs the forcing frequency {sweep.period.forcing!r}, a parameter "
            f"of {code.name} (params: {', '.join(code.params)}); set period.forcing",
            scene.source,
            "sweep.period.forcing",
        )
    if "regime" in sweep.reduce and "Omega" not in code.params:
        raise SceneError(
            f"reduce = regime needs a time-periodic model (the forcing frequency Omega); "
            f"{code.name} has {', '.join(code.params)}",
            scene.source,
            "sweep.reduce",
        )


def _variables(scene: Any, sweep: Any, code: Any) -> tuple[dict[str, Variable], dict[str, list]]:
    """The stored variables (the reducers' and ``status``) and their extra coordinates."""
    from .scene import SceneError

    variables: dict[str, Variable] = {}
    extra: dict[str, list] = {}
    for name in sweep.reduce:
        reducer = REDUCERS[name]
        variables.update(reducer.variables(code, sweep))
        if reducer.coords is not None:
            extra.update(reducer.coords(code))
    variables["status"] = Variable(
        dtype="int8",
        attrs={
            "long_name": "0 done, 1 input refused at this point, 2 computation failed",
            "units": "1",
        },
    )
    if sweep.refine is not None and (
        sweep.refine.variable not in variables or variables[sweep.refine.variable].dims
    ):
        raise SceneError(
            f"refine.variable {sweep.refine.variable!r} is not a number per point of this sweep; "
            f"valid: {', '.join(k for k, v in variables.items() if not v.dims)}",
            scene.source,
            "sweep.refine.variable",
        )
    return variables, extra


def _chunks(shape: tuple[int, ...], chunk: int) -> list[tuple[slice, ...]]:
    """The grid's chunks: ``chunk`` points along the last axis, one index of the others."""
    chunks = []
    for index in product(*[range(n) for n in shape[:-1]]):
        for start in range(0, shape[-1], chunk):
            last = slice(start, min(start + chunk, shape[-1]))
            chunks.append(tuple(slice(i, i + 1) for i in index) + (last,))
    return chunks


def _check_cost(shape, n_chunks, variables, extra, per_point, workers, store) -> None:
    """The grid's memory, disk and least time against the machine
    (:func:`~chaplygin.verify.sweep_checks.check_grid_cost`)."""
    points = math.prod(shape)
    per_point_bytes = 1 + sum(  # computed, and each variable with its extra dimensions
        np.dtype(var.dtype).itemsize * math.prod(len(extra[d]) for d in var.dims)
        for var in variables.values()
    )
    float_bytes = sum(
        8 * math.prod(len(extra[d]) for d in var.dims)
        for var in variables.values()
        if var.dtype.startswith("float")
    )
    n_workers = workers or usable_cpus()
    check_grid_cost(
        GridCost(
            points=points,
            chunks=n_chunks,
            memory=points * per_point_bytes + n_chunks * (CHUNK_OVERHEAD_BYTES + 32),
            disk=points * float_bytes,
            seconds=points * per_point / n_workers,
            workers=n_workers,
        ),
        store,
    )


def _check_axis_keys(scene: Any, code: Any) -> None:
    """Refuse an axis that names no parameter, initial key or run setting of this model (it
    would make every point refused)."""
    from .scene import Initial, Run, SceneError, did_you_mean

    valid = {
        "parameters": list(code.parameter_groups) + list(code.params),
        "initial": list(Initial.model_fields) + list(code.state_groups),
        "run": [f.alias or n for n, f in Run.model_fields.items()],
    }
    for key in scene.sweep.axes:
        root, name = key.split(".")
        if name not in valid[root]:
            raise SceneError(
                f"axis {key!r}: {code.name} has no {root} key {name!r}; valid: "
                f"{', '.join(valid[root])}{did_you_mean(name, valid[root])}",
                scene.source,
                "sweep.axes",
            )


