"""The minimum versions pyproject.toml declares are versions that work (issue 28, 3).

Measured on 2026-11-26 in a scratch venv holding the declared minimum of one package and
pip's choice for everything else (numpy 2.4.6, numcodecs 0.16.6, dask and distributed
2024.1.0), running tests/verify/test_sweep.py, test_hostile_sweep.py and test_sweep_batch.py:

* xarray 2024.1.0 with zarr 2.17.0: zarr does not import (numcodecs has no ``cbuffer_sizes``);
  the sweep store needs zarr 3's ``open_group(zarr_format=2, use_consolidated=...)``.
* zarr 3.0.8 (the oldest zarr 3 on the index) to 3.1.3 depend on ``crc32c``, for which
  numcodecs >= 0.16.4 prints a DeprecationWarning on stderr at import: ``chaplygin sweep``'s
  one-line errors get two more lines (2 tests fail). zarr 3.1.4 depends on google-crc32c.
* xarray 2024.10.0, 2024.11.0 and 2025.1.0 fail to write the store with zarr 3
  (``chunks=None``, ``exists_ok``); 2025.1.1 passes all 41 tests with zarr 3.1.4.
"""

from __future__ import annotations

import re
import tomllib
from importlib.metadata import version
from pathlib import Path

import pytest

pytestmark = pytest.mark.quick

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"

#: The oldest versions that passed the sweep tests (see the module's docstring).
MEASURED = {"xarray": (2025, 1, 1), "zarr": (3, 1, 4)}


def _numbers(text: str) -> tuple[int, ...]:
    return tuple(int(part) for part in re.findall(r"\d+", text))


def _declared_minimums() -> dict[str, tuple[int, ...]]:
    project = tomllib.loads(PYPROJECT.read_text())["project"]
    groups = [project["dependencies"], *project["optional-dependencies"].values()]
    found = {}
    for requirement in (r for group in groups for r in group):
        match = re.fullmatch(r"([A-Za-z0-9_.-]+)(\[[^\]]*\])?>=([\d.]+)", requirement)
        if match:
            found[match.group(1).lower()] = _numbers(match.group(3))
    return found


def test_declared_minimums_are_the_measured_working_ones():
    declared = _declared_minimums()
    for name, oldest in MEASURED.items():
        assert declared[name] >= oldest, (name, declared[name])


def test_the_installed_versions_satisfy_the_declarations():
    """A control on the reading: the versions this suite runs with meet what is declared."""
    declared = _declared_minimums()
    assert set(MEASURED) <= set(declared)
    for name in MEASURED:
        assert _numbers(version(name))[:3] >= declared[name], name
