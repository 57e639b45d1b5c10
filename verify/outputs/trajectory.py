"""Trajectory files: netCDF3 (self-describing, CF-1.10 style) or CSV with a header.

The netCDF file is written by xarray (its scipy engine, netCDF3 64-bit offset): a variable per
column with its ``long_name`` and, where known, ``units``; global attributes after the CF
conventions (``Conventions``, ``title``, ``source``, ``history``) and the run itself
(:func:`run_attributes`: system, effects, model and its hash, the parameters, method, backend,
tolerances, precision and package versions). xarray opens it in one line
(``xr.open_dataset("trajectory.nc")``) and so does scipy (``netcdf_file(path, mmap=False)``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["UNITS", "trajectory_columns", "write_trajectory", "run_attributes"]

#: The CF conventions the netCDF files follow.
CONVENTIONS = "CF-1.10"

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
) -> list[tuple[str, np.ndarray, str | None, str]]:
    """``(name, values, unit, long_name)`` for ``t`` and every state component (``unit``
    None where the model does not say).

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
        unit = UNITS.get(group)
        cols.append((name, values, unit, f"state {name} (group {group})"))
    return cols


def run_attributes(
    result: Any,
    code: Any,
    precision: Any,
    versions: Mapping[str, str],
    title: str = "",
    system: str | None = None,
    effects: Sequence[str] = (),
) -> dict[str, object]:
    """The global attributes of a run's trajectory file.

    Parameters
    ----------
    result : IntegrationResult
        The run (its model, parameters, method, backend, tolerances).
    code : ModelCode
        Its model (name and hash).
    precision : Precision
        The working precision.
    versions : mapping of str to str
        Package -> version (``software_versions()``).
    title : str, optional
    system : str, optional
        The system as named (default: the model's name up to its effects).
    effects : sequence of str, optional

    Returns
    -------
    dict
        Text and numbers only (netCDF attributes); each parameter twice: ``parameter_<name>``
        as a double and, in ``parameters``, as text with every digit of the run.
    """
    params = dict(result.params)
    attrs: dict[str, object] = {
        "Conventions": CONVENTIONS,
        "title": title or f"trajectory of {code.name}",
        "source": f"chaplygin {versions.get('chaplygin', '?')}, method {result.method} "
        f"({result.backend}), {precision!r}",
        "history": "written by chaplygin (chaplygin run or chaplygin integrate --out)",
        "system": system or code.name.split("__")[0],
        "effects": ",".join(sorted(effects)),
        "model": code.name,
        "model_hash": code.hash,
        "parameters": ", ".join(f"{k}={v}" for k, v in params.items()),
        **{f"parameter_{k}": float(v) for k, v in params.items()},
        "method": result.method,
        "backend": result.backend,
        "precision_kind": precision.kind,
        "precision_digits": int(precision.decimal_digits),
        "precision_bits": int(precision.prec),
        **{f"{k}_version": str(v) for k, v in versions.items()},
    }
    for name in ("rtol", "atol"):
        value = getattr(result, name, None)
        if value is not None and math.isfinite(float(value)):
            attrs[name] = float(value)
    return attrs


def write_trajectory(
    path: str | Path,
    columns: Sequence[tuple[str, np.ndarray, str | None, str]],
    attributes: Mapping[str, object] | None = None,
) -> None:
    """Write columns to ``path``: netCDF3 for ``.nc``, CSV (``# name [unit]`` header) otherwise.

    Parameters
    ----------
    path : str or Path
    columns : sequence of (name, values, unit, long_name)
        The first is the time, the dimension of the others; ``unit`` None: not known.
    attributes : mapping of str to str or number, optional
        Global attributes of the netCDF file (:func:`run_attributes`); ``Conventions`` is
        added.
    """
    path = Path(path)
    if path.suffix == ".nc":
        import xarray as xr

        (tname, tvalues, tunit, tlong), *states = columns
        time_attrs = {"long_name": tlong, "axis": "T", **({"units": tunit} if tunit else {})}
        data = {
            name: ((tname,), np.asarray(values, dtype=np.float64),
                   {"long_name": long, **({"units": unit} if unit else {})})
            for name, values, unit, long in states
        }  # fmt: skip
        ds = xr.Dataset(
            data,
            coords={tname: ((tname,), np.asarray(tvalues, dtype=np.float64), time_attrs)},
            attrs={"Conventions": CONVENTIONS, **(attributes or {})},
        )
        # no _FillValue: every value is written (non-finite ones as they are)
        encoding = {name: {"_FillValue": None} for name in ds.variables}
        ds.to_netcdf(path, engine="scipy", format="NETCDF3_64BIT", encoding=encoding)
        return
    header = ",".join(f"{n} [{u or '?'}]" for n, _, u, _ in columns)
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
