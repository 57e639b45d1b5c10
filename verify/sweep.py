"""Sweeps: a scene plus a grid (its ``[sweep]`` table, :mod:`chaplygin.verify.sweep_table`), each
point reduced to numbers, computed in chunks on Dask and stored chunk by chunk in Zarr.

* **Grid.** Each axis is a dotted key of the scene (``parameters.D``, ``initial.h``) and its
  values; ``grid = "product"`` takes every combination (C order, the last axis fastest),
  ``grid = "list"`` the i-th values of all axes as the i-th point. A point is the scene with
  those keys replaced (values reach the scene as the user wrote them, or as 30-digit text for a
  ``{start, stop, num}`` range), resolved and checked like any scene.
* **Reducers** (:data:`REDUCERS`): what a point is reduced to. Each declares its variables
  (names, extra dimensions, units) and computes them from a :class:`PointContext`. A reducer is
  added with :func:`register_reducer` (e.g. the largest Lyapunov exponent, once
  :mod:`chaplygin.numerics.dynamics.lyapunov` exists).
* **Store** (:mod:`chaplygin.verify.sweep_store`). An xarray Dataset in Zarr: the grid as
  coordinates, one Zarr chunk per sweep chunk (``chunk`` points along the last axis),
  ``status`` per point (0 done, 1 input refused at that point, 2 computation failed),
  ``chunk_digest`` (the SHA-256 of each chunk's values) and ``computed`` (1 once the point's
  chunk is stored; written after the chunk's data and digest, so a chunk is either complete
  or computed again). The store is first built in a temporary folder and renamed into place.
  Its attributes hold the scene, the grid, the versions and the model hash, and a fingerprint
  of all of these: a store made by another scene, grid or code version is refused, never
  mixed. On every resume each chunk marked done is read and checked against its digest, and
  computed again when it does not match; missing or damaged arrays are made again.
* **Checked first** (:mod:`chaplygin.verify.sweep_checks`): the grid's memory, disk and
  least time against the machine, the worker count, the scheduler's address and handshake.
* **Resumable.** Tasks are chunks (Dask distributed: a LocalCluster, or ``--scheduler``); the
  client writes each finished chunk at once (Zarr writes each chunk file atomically). A sweep
  killed at any moment and started again skips the chunks marked ``computed`` whose values
  match their digest and computes the others; every point is computed by the same
  deterministic code, so the results are bit-identical to an uninterrupted run.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..derive.errors import ComputationError, UserInputError
from ..numerics.ball.regimes import linear_growth_rate
from .sweep_checks import (
    CONNECT_TIMEOUT_S,
    check_workers,
    parse_scheduler_address,
    probe_scheduler,
    usable_cpus,
)
from .sweep_plan import CARRY_KEY, SweepPlan, plan_sweep, point_scene
from .sweep_reducers import (
    REDUCERS,
    PointContext,
    Reducer,
    Variable,
    period_of_orbit,
    register_reducer,
)
from .sweep_store import (
    STORE_FORMAT,
    create_store,
    extra_shape,
    inspect_store,
    repair_store,
    write_chunk,
)

__all__ = [
    "REDUCERS",
    "Reducer",
    "Variable",
    "PointContext",
    "SweepPlan",
    "register_reducer",
    "plan_sweep",
    "compute_chunk",
    "chunk_payload",
    "linear_growth_rate",
    "evaluate_point",
    "run_sweep",
    "open_store",
    "require_dask",
    "period_of_orbit",
    "zeros_along_axis",
    "STORE_FORMAT",
]

#: ``status`` values.
STATUS_DONE, STATUS_REFUSED, STATUS_FAILED = 0, 1, 2


def require_dask() -> None:
    """Check that the ``dask`` extra (dask.distributed, xarray, zarr) is installed.

    Raises
    ------
    UserInputError
        One line saying how to install it.
    """
    missing = []
    for name in ("distributed", "xarray", "zarr"):
        try:
            __import__(name)
        except ImportError:
            missing.append(name)
    if missing:
        raise UserInputError(
            f"chaplygin sweep needs {', '.join(missing)}: pip install 'chaplygin[dask]' "
            '(from a source tree: pip install -e ".[dask]")'
        )


# ---------------------------------------------------------------------------- computation
def evaluate_point(
    base: Mapping, overrides: Mapping[str, Any], sweep: Any, source: str | None = None
) -> tuple[int, dict[str, Any]]:
    """Reduce one point.

    Parameters
    ----------
    base : mapping
        The scene's data without ``sweep``.
    overrides : mapping
        The point's keys.
    sweep : Sweep
    source : str, optional

    Returns
    -------
    (status, values) : (int, dict)
        ``STATUS_DONE`` with every variable, or ``STATUS_REFUSED`` / ``STATUS_FAILED`` with
        none (those points keep the fill values).
    """
    ctx = _point_context(base, overrides, sweep, source)
    return ctx if isinstance(ctx, tuple) else _reduce_point(ctx)


_FAILURES = (ComputationError, ArithmeticError, ValueError, RuntimeError)


def _point_context(
    base: Mapping, overrides: Mapping[str, Any], sweep: Any, source: str | None
) -> PointContext | tuple[int, dict]:
    """The point's resolved scene, or ``(status, {})`` when it cannot be resolved."""
    try:
        scene = point_scene(base, overrides, source)
        return PointContext(scene, scene.resolve(), sweep)
    except UserInputError:
        return STATUS_REFUSED, {}
    except _FAILURES:
        return STATUS_FAILED, {}


def _reduce_point(ctx: PointContext) -> tuple[int, dict[str, Any]]:
    """Run the sweep's reducers on one point (taking a chunk's batch results where present)."""
    try:
        values: dict[str, Any] = {}
        for name in ctx.sweep.reduce:
            done = ctx.batched.get(name)
            if isinstance(done, Exception):
                raise done
            values.update(done if done is not None else REDUCERS[name].run(ctx))
    except UserInputError:
        return STATUS_REFUSED, {}
    except _FAILURES:
        return STATUS_FAILED, {}
    return STATUS_DONE, values


def chunk_payload(plan: SweepPlan) -> dict[str, Any]:
    """What every task of a sweep receives besides its points (see :func:`compute_chunk`).

    Parameters
    ----------
    plan : SweepPlan

    Returns
    -------
    dict
        ``base``, ``sweep``, ``source``, ``variables``.
    """
    return {
        "base": plan.base,
        "sweep": plan.scene.sweep.model_dump(mode="json"),
        "source": plan.scene.source,
        "variables": {
            name: (extra_shape(plan, var), var.dtype) for name, var in plan.variables.items()
        },
    }


def compute_chunk(payload: Mapping, points: Sequence[Mapping[str, Any]]) -> dict[str, np.ndarray]:
    """Reduce a chunk of points (a Dask task; runs on a worker).

    Parameters
    ----------
    payload : mapping
        ``base`` (scene data), ``sweep`` (the table as data), ``source``, ``variables``
        (name -> (extra shape, dtype)).
    points : sequence of mapping
        The points' keys.

    Returns
    -------
    dict of str to numpy.ndarray
        Each variable, shaped ``(len(points), *extra)``.
    """
    from .sweep_table import Sweep

    sweep = Sweep.model_validate(payload["sweep"])
    out = {
        name: np.full((len(points), *shape), -1 if dtype.startswith("int") else np.nan, dtype)
        for name, (shape, dtype) in payload["variables"].items()
    }
    if sweep.carry != "none":
        return _carried_chunk(payload, points, sweep, out)
    contexts = [
        _point_context(payload["base"], point, sweep, payload.get("source")) for point in points
    ]
    live = [c for c in contexts if isinstance(c, PointContext)]
    for name in sweep.reduce:
        batch = REDUCERS[name].batch
        if batch is not None and live:
            for ctx, result in zip(live, batch(live), strict=True):
                ctx.batched[name] = result
    for i, ctx in enumerate(contexts):
        status, values = ctx if isinstance(ctx, tuple) else _reduce_point(ctx)
        out["status"][i] = status
        for name, value in values.items():
            out[name][i] = value
    return out


def _carried_chunk(
    payload: Mapping, points: Sequence[Mapping[str, Any]], sweep: Any, out: dict[str, np.ndarray]
) -> dict[str, np.ndarray]:
    """One grid line with its starts carried: the points in the line's order (or reversed),
    each starting where the previous one ended (the first, and any after a point that failed
    or was refused, at the scene's state)."""
    direction = points[0].get(CARRY_KEY, sweep.carry) if points else sweep.carry
    order = range(len(points)) if direction == "forward" else range(len(points) - 1, -1, -1)
    carried = None
    for i in order:
        point = {k: v for k, v in points[i].items() if k != CARRY_KEY}
        ctx = _point_context(payload["base"], point, sweep, payload.get("source"))
        if isinstance(ctx, PointContext):
            ctx.start = carried
            status, values = _reduce_point(ctx)
            carried = ctx.end if status == STATUS_DONE else None
        else:
            (status, values), carried = ctx, None
        out["status"][i] = status
        for name, value in values.items():
            out[name][i] = value
    return out


# ---------------------------------------------------------------------------------- the store
def open_store(plan: SweepPlan, store: str | Path) -> Any:
    """Open the sweep's Zarr store, creating it (atomically) if absent, and repairing what
    :func:`~chaplygin.verify.sweep_store.inspect_store` found missing or damaged.

    Parameters
    ----------
    plan : SweepPlan
    store : str or Path

    Returns
    -------
    zarr.Group
        Opened for writing.

    Raises
    ------
    UserInputError
        ``store`` exists but is not a sweep store of ours, or was made by another scene, grid
        or code version (the message says which), or cannot be written.
    """
    check = inspect_store(plan, store)
    return repair_store(plan, check) if check.exists else create_store(plan, check)


# ------------------------------------------------------------------------------- the driver
def _client(
    scheduler: str | None, workers: int | None, connect_timeout: float = CONNECT_TIMEOUT_S
) -> tuple[Any, Any]:
    """A Dask client: of the scheduler at ``scheduler`` (checked by
    :func:`~chaplygin.verify.sweep_checks.probe_scheduler` first, then given
    ``connect_timeout`` to connect and ``connect_timeout`` more to show a worker), or of a
    LocalCluster of ``workers`` processes."""
    from distributed import Client, LocalCluster

    if scheduler:
        address = parse_scheduler_address(scheduler)
        probe_scheduler(address, connect_timeout)
        try:
            client = Client(address.url, timeout=f"{connect_timeout}s")
        except (OSError, TimeoutError, ValueError) as exc:
            reason = " ".join(str(exc).split())[:200]
            raise UserInputError(f"--scheduler {address.url}: cannot connect ({reason})") from None
        try:
            client.wait_for_workers(1, timeout=connect_timeout)
        except (OSError, TimeoutError) as exc:
            client.close()
            raise UserInputError(
                f"--scheduler {address.url}: the scheduler has no worker (none within "
                f"{connect_timeout:g} s); start some: dask worker {address.url}"
            ) from exc
        return client, None
    n = check_workers(workers) if workers is not None else usable_cpus()
    cluster = LocalCluster(
        n_workers=n,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=40,
    )
    return Client(cluster), cluster


def run_sweep(
    scene: Any,
    store: str | Path,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = False,
    client: Any = None,
    connect_timeout: float = CONNECT_TIMEOUT_S,
) -> dict:
    """Run (or continue) a scene's sweep into a Zarr store.

    Everything is checked before any work: the worker count, the scheduler's address, the
    grid's cost (:func:`~chaplygin.verify.sweep_checks.check_grid_cost`), the store (whose it
    is, and every chunk marked done against its digest:
    :func:`~chaplygin.verify.sweep_store.inspect_store`); the store is created or repaired
    only once a client is connected.

    Parameters
    ----------
    scene : Scene
        With a ``[sweep]`` table.
    store : str or Path
        The Zarr store (a folder); continued if it holds this sweep.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``); default a LocalCluster.
    workers : int, optional
        Worker processes of the LocalCluster (default: one per usable CPU; at most that).
    progress : bool
        Show a tqdm bar on stderr.
    client : distributed.Client, optional
        Use this client (tests); ``scheduler`` and ``workers`` are then ignored.
    connect_timeout : float
        Seconds to connect to ``scheduler``, to receive its handshake, and to see a worker.

    Returns
    -------
    dict
        ``chunks`` (total), ``computed`` (now), ``skipped`` (already stored, verified),
        ``repaired`` (chunks marked done that did not verify, computed again),
        ``recreated`` (arrays made again), ``points``, ``refused``, ``failed``, ``refined``
        (zeros, if asked).

    Raises
    ------
    SceneError
        The scene or its sweep is invalid.
    UserInputError
        The dask extra is missing, a bad worker count or scheduler address, a grid beyond
        the machine, or ``store`` belongs to another sweep or cannot be repaired.
    ComputationError
        A task failed on every worker it was tried on.
    """
    require_dask()
    if client is None and scheduler is not None:
        parse_scheduler_address(scheduler)  # a malformed address: before any work
    if client is None and scheduler is None and workers is not None:
        check_workers(workers)
    if not (isinstance(connect_timeout, int | float) and 0 < connect_timeout <= 3600):
        raise UserInputError(f"the connect timeout must be 0..3600 s, got {connect_timeout!r}")
    n_workers = workers or (usable_cpus() if scheduler is None else 1)
    plan = plan_sweep(scene, workers=n_workers, store=Path(store))
    check = inspect_store(plan, store)
    pending = [k for k in range(len(plan.chunks)) if k not in check.done]
    payload = chunk_payload(plan)
    own = client is None and bool(pending)
    cluster = None
    if own:
        client, cluster = _client(scheduler, workers, connect_timeout)
    try:
        group = repair_store(plan, check) if check.exists else create_store(plan, check)
        if pending:
            _compute(plan, group, payload, pending, client, progress, len(check.done))
    finally:
        if own:
            client.close()
            if cluster is not None:
                cluster.close()
    status = np.asarray(group["status"][...])
    summary = {
        "chunks": len(plan.chunks),
        "computed": len(pending),
        "skipped": len(check.done),
        "repaired": len(check.damaged),
        "recreated": sorted(check.recreate),
        "points": int(np.prod(plan.shape)),
        "refused": int((status == STATUS_REFUSED).sum()),
        "failed": int((status == STATUS_FAILED).sum()),
    }
    if scene.sweep.refine is not None:
        summary["refined"] = _refine(plan, group)
    return summary


def _compute(plan, group, payload, pending, client, progress, already) -> None:
    from distributed import as_completed
    from tqdm import tqdm

    from .scene import package_version

    payload_future = client.scatter(payload, broadcast=True)
    futures = {}
    for k in pending:
        region = plan.chunks[k]
        key = f"chaplygin-sweep-{plan.total[:12]}-{package_version()}-{k}"
        fut = client.submit(compute_chunk, payload_future, plan.points(region), key=key, retries=2)
        futures[fut] = k
    bar = tqdm(
        total=len(plan.chunks),
        initial=already,
        disable=not progress,
        unit="chunk",
        file=sys.stderr,
        desc="sweep",
    )
    try:
        for fut in as_completed(list(futures)):
            k = futures[fut]
            try:
                result = fut.result()
            except Exception as exc:
                raise ComputationError(f"chunk {k} failed: {type(exc).__name__}: {exc}") from None
            write_chunk(plan, group, k, result)
            bar.update(1)
            fut.release()
    finally:
        bar.close()


# ------------------------------------------------------------------------------ refinement
def zeros_along_axis(values: np.ndarray, coords: np.ndarray, wrap: float | None = None) -> list:
    """Brackets ``(a, b)`` of the axis where ``values`` changes sign through zero.

    Parameters
    ----------
    values, coords : 1-D arrays
    wrap : float, optional
        For an angle in ``(-wrap, wrap]``: a sign change by a jump larger than ``wrap`` is the
        angle wrapping round, not a zero.

    Returns
    -------
    list of (float, float)
    """
    out = []
    for i in range(len(values) - 1):
        a, b = values[i], values[i + 1]
        if not (np.isfinite(a) and np.isfinite(b)) or a * b > 0:
            continue
        if wrap is not None and abs(a - b) > wrap:
            continue
        out.append((float(coords[i]), float(coords[i + 1])))
    return out


def _refine(plan: SweepPlan, group: Any) -> list[str]:
    from scipy.optimize import brentq

    sweep = plan.scene.sweep
    opts = sweep.refine
    stored = group.attrs.get("refined")
    if stored is not None:
        return json.loads(stored)
    ((key, name, _),) = plan.axes
    values = np.asarray(group[opts.variable][...], dtype=float)
    units = plan.variables[opts.variable].attrs.get("units")
    brackets = zeros_along_axis(values, plan.coords[name], math.pi if units == "rad" else None)

    def f(x: float) -> float:
        status, out = evaluate_point(plan.base, {key: repr(x)}, sweep, plan.scene.source)
        if status != STATUS_DONE:
            raise ComputationError(f"refine: the point {key} = {x!r} could not be computed")
        return float(out[opts.variable])

    zeros = []
    for a, b in brackets:
        scale = max(abs(a), abs(b))
        root = brentq(f, a, b, xtol=scale * 10.0 ** (-opts.digits - 2), rtol=1e-15)
        zeros.append(f"{root:.{opts.digits + 2}g}")
    import zarr

    group.attrs["refined"] = json.dumps(zeros)
    zarr.consolidate_metadata(group.store)
    return zeros
