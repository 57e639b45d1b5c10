"""Trajectory files: netCDF3 (self-describing: names, units, long names) or CSV with a header.

netCDF3 is written with :mod:`scipy.io` (no new dependency); xarray opens it in one line
(``xr.open_dataset("trajectory.nc")``) and so does scipy (``netcdf_file(path, mmap=False)``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

__all__ = ["UNITS", "trajectory_columns", "write_trajectory"]

#: Units of the state groups and auxiliary quantities (the scene's own units: ``I, D`` in
#: mass*length^2, ``b`` in length, ``t`` in time).
UNITS = {
    "t": "time",
    "M": "mass*length^2/time",
    "gamma": "1",
    "alpha": "1",
    "beta": "1",
    "x": "length",
    "y": "length",
    "omega": "1/time",
}


def trajectory_columns(
    t: np.ndarray, y: np.ndarray, state_names: Sequence[str], groups: Mapping[str, Sequence[str]]
) -> list[tuple[str, np.ndarray, str, str]]:
    """``(name, values, unit, long_name)`` for ``t`` and every state component.

    Parameters
    ----------
    t : ndarray, shape (n,)
    y : ndarray, shape (n_state, n)
    state_names : sequence of str
    groups : mapping
        State group -> its components (``ModelCode.state_groups``).

    Returns
    -------
    list of tuple
    """
    group_of = {c: g for g, comps in groups.items() for c in comps}
    cols = [("t", np.asarray(t, dtype=float), UNITS["t"], "time")]
    arr = np.asarray(y, dtype=float)
    for name, values in zip(state_names, arr, strict=True):
        group = group_of.get(name, name)
        unit = UNITS.get(group, "see the model")
        cols.append((name, values, unit, f"state {name} (group {group})"))
    return cols


def write_trajectory(
    path: str | Path,
    columns: Sequence[tuple[str, np.ndarray, str, str]],
    attributes: Mapping[str, str] | None = None,
) -> None:
    """Write columns to ``path``: netCDF3 for ``.nc``, CSV (``# name [unit]`` header) otherwise.

    Parameters
    ----------
    path : str or Path
    columns : sequence of (name, values, unit, long_name)
    attributes : mapping of str to str, optional
        Global attributes of the netCDF file (title, model, model_hash).
    """
    path = Path(path)
    if path.suffix == ".nc":
        from scipy.io import netcdf_file

        with netcdf_file(path, "w", version=2) as nc:
            for key, value in (attributes or {}).items():
                # netCDF3 text attributes are bytes: UTF-8 keeps a title such as "café —"
                setattr(nc, key, value.encode() if isinstance(value, str) else value)
            nc.createDimension("t", len(columns[0][1]))
            for name, values, unit, long in columns:
                var = nc.createVariable(name, "d", ("t",))
                var[:] = values
                var.units = unit.encode()
                var.long_name = long.encode()
        return
    header = ",".join(f"{n} [{u}]" for n, _, u, _ in columns)
    data = np.column_stack([c[1] for c in columns])
    np.savetxt(path, data, delimiter=",", header=header, comments="# ", fmt="%.17g")


def write_dataset(
    path: str | Path,
    variables: Mapping[str, tuple[tuple[str, ...], np.ndarray, Mapping[str, str]]],
    attributes: Mapping[str, str] | None = None,
) -> None:
    """Write named arrays with their dimensions to a netCDF3 file (an analysis's ``<key>.nc``).

    Parameters
    ----------
    path : str or Path
    variables : mapping of str to (dimensions, values, attributes)
        Each variable's dimension names (one per axis of ``values``) and attributes
        (``long_name``, ``units``); a dimension shared by several variables must have one length.
    attributes : mapping of str to str, optional
        Global attributes.

    Raises
    ------
    ValueError
        A dimension has two lengths, or a variable's dimensions do not match its shape.
    """
    from scipy.io import netcdf_file

    sizes: dict[str, int] = {}
    for name, (dims, values, _) in variables.items():
        shape = np.shape(values)
        if len(dims) != len(shape):
            raise ValueError(f"{name}: dimensions {dims} for an array of shape {shape}")
        for d, n in zip(dims, shape, strict=True):
            if sizes.setdefault(d, n) != n:
                raise ValueError(f"dimension {d} has lengths {sizes[d]} and {n}")
    with netcdf_file(Path(path), "w", version=2) as nc:
        for key, value in (attributes or {}).items():
            # netCDF3 text attributes are bytes: UTF-8 keeps a title such as "Poincaré"
            setattr(nc, key, value.encode() if isinstance(value, str) else value)
        for d, n in sizes.items():
            nc.createDimension(d, n)
        for name, (dims, values, attrs) in variables.items():
            arr = np.asarray(values)
            kind = "i" if np.issubdtype(arr.dtype, np.integer) else "d"
            var = nc.createVariable(name, kind, dims)
            var[...] = arr.astype("i4" if kind == "i" else "f8")
            for k, v in attrs.items():
                setattr(var, k, v.encode() if isinstance(v, str) else v)
