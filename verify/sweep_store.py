"""The Zarr store of a sweep: made atomically, each chunk stored with its SHA-256, and on
every resume verified before anything in it is trusted.

* **Created** in a folder ``.<store>.partial-XXXX`` beside it (holding :data:`PARTIAL_MARKER`
  with our process id), renamed into place when complete. A partial folder is removed later
  only when it holds our marker and the process that made it is gone: a folder of the user's
  with a similar name is never touched.
* **Written** chunk by chunk: the data, then the chunk's digest (``chunk_digest``: SHA-256 of
  every variable's values in the chunk), then ``computed`` (the chunk is done).
* **Verified** on resume (:func:`inspect_store`, read only): the store must carry our
  fingerprint (a store of another sweep, or one whose attributes are unreadable, is refused
  with the reason and left as it is); every array the sweep needs must be present with its
  shape, type and chunks (a missing or damaged one is recreated); every chunk marked done
  must be readable and its values must hash to its stored digest (a deleted chunk file reads
  as the fill value, a garbled one fails to decode: either way the chunk is computed again).
  So nothing marked done holds a NaN the computation did not produce.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import socket
import stat
import tempfile
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..derive.errors import UserInputError
from .output_folder import current_umask, probe_folder, resolve_path

__all__ = [
    "STORE_FORMAT",
    "DIGEST",
    "PARTIAL_MARKER",
    "StoreCheck",
    "chunk_digest",
    "inspect_store",
    "create_store",
    "repair_store",
    "write_chunk",
]

#: Version of the store layout (part of the fingerprint). 2: ``chunk_digest``.
STORE_FORMAT = 2

#: The variable holding each chunk's SHA-256 (dimensions ``chunk``, ``digest_byte``).
DIGEST = "chunk_digest"

#: The file that marks a ``.<store>.partial-*`` folder as one we made (pid and host).
PARTIAL_MARKER = ".chaplygin-partial.json"


# ------------------------------------------------------------------------------- the layout
def _attrs(plan: Any) -> dict:
    from .scene import software_versions

    return {
        "title": plan.scene.title,
        "source": plan.scene.source or "",
        "scene": json.dumps(plan.scene.given, sort_keys=True, default=str),
        "axes": json.dumps([[k, n, [str(v) for v in vals]] for k, n, vals in plan.axes]),
        "model": plan.code.name,
        "model_hash": plan.code.hash,
        "versions": json.dumps(software_versions()),
        "fingerprint": json.dumps(plan.fingerprint, sort_keys=True),
        "store_format": STORE_FORMAT,
    }


def extra_shape(plan: Any, var: Any) -> tuple[int, ...]:
    """The lengths of a variable's extra dimensions (beyond the grid's).

    Parameters
    ----------
    plan : SweepPlan
    var : Variable

    Returns
    -------
    tuple of int
    """
    return tuple(len(plan.extra_coords[d]) for d in var.dims)


def _zarr_chunks(plan: Any, var_dims: tuple[str, ...]) -> tuple[int, ...]:
    chunk = plan.scene.sweep.chunk
    grid = (1,) * (len(plan.shape) - 1) + (min(chunk, plan.shape[-1]),)
    return grid + tuple(len(plan.extra_coords[d]) for d in var_dims)


def _expected(plan: Any) -> dict[str, tuple[tuple[str, ...], tuple[int, ...], tuple[int, ...]]]:
    """Every array the store needs: name -> (dimensions, shape, zarr chunks); None chunks
    for the coordinates (one chunk each)."""
    out: dict[str, Any] = {}
    for name, var in plan.variables.items():
        out[name] = (plan.dims + var.dims, plan.shape + extra_shape(plan, var),
                     _zarr_chunks(plan, var.dims))  # fmt: skip
    out["computed"] = (plan.dims, plan.shape, _zarr_chunks(plan, ()))
    out[DIGEST] = (("chunk", "digest_byte"), (len(plan.chunks), 32), (1, 32))
    for _, name, values in plan.axes:
        dim = "point" if plan.dims == ("point",) else name
        out[name] = ((dim,), (len(values),), None)
    for dim, labels in plan.extra_coords.items():
        out[dim] = ((dim,), (len(labels),), None)
    return out


def _template(plan: Any, names: list[str] | None = None) -> Any:
    """The store's Dataset (fill values), or only the variables ``names`` among its data
    (every coordinate is always there)."""
    import xarray as xr

    data_vars = {}
    for name, var in plan.variables.items():
        if names is None or name in names:
            shape = plan.shape + extra_shape(plan, var)
            data_vars[name] = (plan.dims + var.dims, np.full(shape, var.fill, var.dtype), var.attrs)
    if names is None or "computed" in names:
        data_vars["computed"] = (
            plan.dims,
            np.zeros(plan.shape, "uint8"),
            {"long_name": "1 once the point's chunk is stored", "units": "1"},
        )
    if names is None or DIGEST in names:
        data_vars[DIGEST] = (
            ("chunk", "digest_byte"),
            np.zeros((len(plan.chunks), 32), "uint8"),
            {"long_name": "SHA-256 of the chunk's stored values (checked on every resume)"},
        )
    coords: dict[str, Any] = {}
    for key, name, _ in plan.axes:
        dim = "point" if plan.dims == ("point",) else name
        coords[name] = (dim, plan.coords[name], {"key": key})
    for dim, labels in plan.extra_coords.items():
        coords[dim] = (dim, np.asarray(labels, dtype=str))
    return xr.Dataset(data_vars, coords=coords, attrs=_attrs(plan))


def _encoding(plan: Any, names: list[str]) -> dict:
    out = {}
    for name in names:
        if name in plan.variables:
            out[name] = {"chunks": _zarr_chunks(plan, plan.variables[name].dims)}
        elif name == "computed":
            out[name] = {"chunks": _zarr_chunks(plan, ())}
        elif name == DIGEST:
            out[name] = {"chunks": (1, 32)}
    return out


def chunk_digest(plan: Any, values: Mapping[str, np.ndarray]) -> bytes:
    """SHA-256 of a chunk's values: every variable in name order, its name, shape and
    little-endian bytes.

    Parameters
    ----------
    plan : SweepPlan
    values : mapping of str to ndarray
        Each variable of ``plan.variables`` over the chunk's region (shaped as stored).

    Returns
    -------
    bytes
        32 bytes.
    """
    h = hashlib.sha256()
    for name in sorted(plan.variables):
        _update(h, name, values[name], plan.variables[name].dtype)
    return h.digest()


def _update(h: Any, name: str, value: np.ndarray, dtype: str) -> None:
    a = np.ascontiguousarray(np.asarray(value, dtype=np.dtype(dtype).newbyteorder("<")))
    h.update(f"{name}\0{a.shape}\0".encode())
    h.update(a.tobytes())


# ------------------------------------------------------------------------------ the checks
@dataclass
class StoreCheck:
    """What :func:`inspect_store` found (nothing changed yet).

    Attributes
    ----------
    path : pathlib.Path
        The store, resolved.
    exists : bool
        False: the store is to be created (absent, or an empty folder).
    done : set of int
        Chunks marked done whose values match their digest.
    damaged : dict of int to str
        Chunks marked done that did not verify, with the reason.
    recreate : list of str
        Arrays missing or damaged (made again, all their chunks computed again).
    """

    path: Path
    exists: bool
    done: set[int] = field(default_factory=set)
    damaged: dict[int, str] = field(default_factory=dict)
    recreate: list[str] = field(default_factory=list)


def _refuse(given: str, reason: str) -> UserInputError:
    return UserInputError(f"--out {given}: {reason}")


def _open_group(path: Path, mode: str = "r+") -> Any:
    import zarr

    # never the consolidated metadata: it may list arrays that are gone
    return zarr.open_group(str(path), mode=mode, zarr_format=2, use_consolidated=False)


def inspect_store(plan: Any, store: str | os.PathLike[str]) -> StoreCheck:
    """Check a store before any work, changing nothing: whose it is, what it lacks, which
    chunks marked done still hold what was computed.

    Parameters
    ----------
    plan : SweepPlan
    store : path-like

    Returns
    -------
    StoreCheck

    Raises
    ------
    UserInputError
        Not a folder; a folder that is not a sweep store of ours (or whose attributes cannot
        be read: it cannot be told whose it is); a store of another scene, grid or code
        version; a place where nothing can be written.
    """
    given = os.fspath(store)
    if not given.strip():
        raise UserInputError("--out needs a store name (a folder), got an empty one")
    path = resolve_path(given, "--out")
    if path == Path.cwd().resolve() or path in Path.cwd().resolve().parents:
        raise _refuse(given, "the store cannot be the current folder or one of its parents")
    if path.exists() and not path.is_dir():
        raise _refuse(given, "it exists and is not a folder (a Zarr store is a folder)")
    if not path.exists() or not any(path.iterdir()):
        folder = path if path.exists() else path.parent
        while not folder.exists():
            folder = folder.parent
        if not folder.is_dir():
            raise _refuse(given, f"{str(folder)!r} is not a folder")
        problem = probe_folder(folder)
        if problem:
            raise _refuse(given, f"nothing can be created in {str(folder)!r} ({problem})")
        return StoreCheck(path, exists=False)
    try:
        group = _open_group(path, "r")
        stored = json.loads(group.attrs["fingerprint"])
        if not isinstance(stored, dict):
            raise TypeError
    except Exception:  # noqa: BLE001 - whatever fails here, it cannot be told whose it is
        raise _refuse(
            given,
            "exists and is not a chaplygin sweep store, or its attributes are damaged beyond "
            "repair (the fingerprint cannot be read, so it cannot be told whose it is): "
            "nothing in it is touched; choose another path",
        ) from None
    differs = [k for k in ("scene", "grid", "code") if stored.get(k) != plan.fingerprint[k]]
    if differs:
        what = {
            "scene": "a different scene",
            "grid": "a different grid",
            "code": "a different code version (chaplygin, model or store format)",
        }
        raise _refuse(
            given,
            f"holds a sweep made by {' and '.join(what[k] for k in differs)}; it is not "
            "mixed with this one: choose another --out, or delete it to start again",
        )
    problem = probe_folder(path)
    if problem:
        raise _refuse(given, f"the store cannot be written ({problem})")
    return _verify(plan, group, StoreCheck(path, exists=True))


def _array(group: Any, name: str, dims, shape, chunks) -> Any | None:
    """The array ``name`` if it is as the sweep made it, else None."""
    try:
        arr = group[name]
        ok = (
            tuple(arr.shape) == tuple(shape)
            and (chunks is None or tuple(arr.chunks) == tuple(chunks))
            and list(arr.attrs.get("_ARRAY_DIMENSIONS", [])) == list(dims)
        )
    except Exception:  # noqa: BLE001 - missing (KeyError) or unreadable metadata
        return None
    return arr if ok else None


def _read(arr: Any, regions: list[tuple[slice, ...]]) -> tuple[np.ndarray | None, set[int]]:
    """The whole array, or (when some chunk cannot be decoded) the readable regions: the
    array with the failing regions left unread, and their indices."""
    try:
        return np.asarray(arr[...]), set()
    except Exception:  # noqa: BLE001 - a garbled chunk: find which
        pass
    out = np.zeros(arr.shape, arr.dtype)
    bad = set()
    for k, region in enumerate(regions):
        try:
            out[region] = arr[region]
        except Exception:  # noqa: BLE001
            bad.add(k)
    return out, bad


def _verify(plan: Any, group: Any, check: StoreCheck) -> StoreCheck:
    expected = _expected(plan)
    arrays = {name: _array(group, name, *spec) for name, spec in expected.items()}
    check.recreate = [name for name, arr in arrays.items() if arr is None]
    # coordinates hold what the plan says (they are ours: a changed one is made again)
    for _, name, _ in plan.axes:
        if arrays[name] is not None:
            values, bad = _read(arrays[name], [(slice(None),)])
            if bad or not np.array_equal(values, plan.coords[name]):
                check.recreate.append(name)
    for dim, labels in plan.extra_coords.items():
        if arrays[dim] is not None:
            values, bad = _read(arrays[dim], [(slice(None),)])
            if bad or [str(v) for v in values] != [str(v) for v in labels]:
                check.recreate.append(dim)
    data = [*plan.variables, "computed", DIGEST]
    if any(name in check.recreate for name in data):
        return check  # every chunk is computed again into the arrays made anew
    n = len(plan.chunks)
    computed, bad = _read(arrays["computed"], plan.chunks)
    marked = [k for k in range(n) if k not in bad and computed[plan.chunks[k]].all()]
    if not marked:
        return check
    digests, bad_rows = _read(arrays[DIGEST], [(slice(k, k + 1),) for k in range(n)])
    hashers = {k: hashlib.sha256() for k in marked}
    unreadable: dict[int, str] = {}
    for name in sorted(plan.variables):
        values, bad = _read(arrays[name], plan.chunks)
        for k in marked:
            if k in bad:
                unreadable.setdefault(k, f"a chunk of {name} cannot be read")
            else:
                _update(hashers[k], name, values[plan.chunks[k]], plan.variables[name].dtype)
        del values
    for k in marked:
        if k in unreadable:
            check.damaged[k] = unreadable[k]
        elif k in bad_rows or hashers[k].digest() != bytes(digests[k]):
            check.damaged[k] = "its values do not match their digest"
        else:
            check.done.add(k)
    return check


# ------------------------------------------------------------------------------ the changes
def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, ValueError):
        return True
    return True


def _remove_stale_partials(path: Path) -> None:
    """Remove ``.<store>.partial-*`` folders that we made and whose process is gone."""
    host = socket.gethostname()
    for stale in path.parent.glob(f".{path.name}.partial-*"):
        marker = stale / PARTIAL_MARKER
        try:
            st = os.lstat(marker)
            if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid():
                continue
            info = json.loads(marker.read_text(encoding="utf-8"))
            pid = int(info["pid"])
            if info.get("host") != host or _alive(pid):
                continue
        except (OSError, ValueError, KeyError, TypeError):
            continue  # not ours (or not readable): left alone
        shutil.rmtree(stale, ignore_errors=True)


def create_store(plan: Any, check: StoreCheck) -> Any:
    """Create the store where :func:`inspect_store` found none (atomically).

    Parameters
    ----------
    plan : SweepPlan
    check : StoreCheck
        ``check.exists`` is False.

    Returns
    -------
    zarr.Group
    """
    import zarr

    path = check.path
    path.parent.mkdir(parents=True, exist_ok=True)
    _remove_stale_partials(path)
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.partial-", dir=path.parent))
    try:
        (tmp / PARTIAL_MARKER).write_text(
            json.dumps({"pid": os.getpid(), "host": socket.gethostname()}), encoding="utf-8"
        )
        ds = _template(plan)
        names = [*plan.variables, "computed", DIGEST]
        with warnings.catch_warnings():  # zarr notes our marker as a stray object
            warnings.filterwarnings("ignore", message=f".*{re.escape(PARTIAL_MARKER)}")
            ds.to_zarr(
                tmp, mode="a", encoding=_encoding(plan, names), consolidated=False, zarr_format=2
            )
        (tmp / PARTIAL_MARKER).unlink()
        zarr.consolidate_metadata(str(tmp), zarr_format=2)
        os.chmod(tmp, 0o777 & ~current_umask())
        os.replace(tmp, path)  # onto an empty folder too
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)  # ours: made above
        raise
    return _open_group(path)


def repair_store(plan: Any, check: StoreCheck) -> Any:
    """Make again the arrays :func:`inspect_store` found missing or damaged, and the
    consolidated metadata.

    Parameters
    ----------
    plan : SweepPlan
    check : StoreCheck
        ``check.exists`` is True.

    Returns
    -------
    zarr.Group
    """
    # A file of the user's inside the store is left where it is and unlisted; zarr's note
    # that it is not part of the hierarchy (when the arrays are listed) is not for the user.
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Object at .* is not recognized as a component")
        return _repair(plan, check)


def _repair(plan: Any, check: StoreCheck) -> Any:
    import zarr

    path = check.path
    if check.recreate:
        for name in check.recreate:
            target = path / name
            # an array folder of our store (the names are the plan's: no separator)
            if "/" not in name and name not in (".", "..") and target.parent == path:
                if target.is_dir() and not target.is_symlink():
                    shutil.rmtree(target)
                elif os.path.lexists(target):
                    target.unlink()
        ds = _template(plan, check.recreate)
        ds.attrs = dict(_open_group(path, "r").attrs)  # as they are (xarray puts them anew)
        ds.to_zarr(
            path,
            mode="a",
            encoding=_encoding(plan, check.recreate),
            consolidated=False,
            zarr_format=2,
        )
    # the consolidated metadata (what xr.open_zarr reads first) made anew: it may be stale,
    # damaged or gone
    zarr.consolidate_metadata(str(path), zarr_format=2)
    return _open_group(path)


def write_chunk(plan: Any, group: Any, k: int, result: Mapping) -> None:
    """Store chunk ``k``: its values, then its digest, then ``computed`` (the chunk is done).

    Parameters
    ----------
    plan : SweepPlan
    group : zarr.Group
    k : int
    result : mapping
        Each variable, shaped ``(points, *extra)`` (:func:`~chaplygin.verify.sweep.
        compute_chunk`).
    """
    region = plan.chunks[k]
    sizes = tuple(s.stop - s.start for s in region)
    values = {}
    for name, var in plan.variables.items():
        value = np.asarray(result[name], dtype=var.dtype)
        values[name] = value.reshape(sizes + value.shape[1:])
        group[name][region] = values[name]
    group[DIGEST][k : k + 1] = np.frombuffer(chunk_digest(plan, values), "uint8")[None, :]
    group["computed"][region] = np.ones(sizes, "uint8")  # last: the chunk is complete

