"""``chaplygin integrate --points N --out FILE``: a trajectory without a scene."""

from __future__ import annotations

import numpy as np
import pytest
from chaplygin.verify.cli import main
from scipy.io import netcdf_file

ARGS = [
    "integrate",
    "chaplygin_ball",
    "--param",
    "I=1,2,3",
    "--param",
    "D=1",
    "--y0",
    "M=0.7,-0.4,0.5",
    "--y0",
    "gamma=0.2,0.3,sqrt(0.87)",
    "--t-end",
    "10",
    "--rtol",
    "1e-12",
    "--atol",
    "1e-12",
]


def test_csv_and_netcdf_agree_and_keep_the_integrals(tmp_path):
    csv, nc = tmp_path / "t.csv", tmp_path / "t.nc"
    assert main([*ARGS, "--points", "21", "--out", str(csv)]) == 0
    assert main([*ARGS, "--points", "21", "--out", str(nc)]) == 0
    header = csv.read_text().splitlines()[0]
    assert header.startswith("# t [time],M1 [mass*length^2/time]")
    data = np.loadtxt(csv, delimiter=",")
    assert data.shape == (21, 7) and np.allclose(data[:, 0], np.linspace(0, 10, 21))
    with netcdf_file(nc, mmap=False) as f:
        assert f.variables["gamma3"].units == b"1"
        cols = [np.asarray(f.variables[n][:]) for n in ("t", "M1", "M2", "M3")]
    assert np.array_equal(np.column_stack(cols), data[:, :4])
    M = data[:, 1:4]
    assert np.ptp(np.sum(M * M, axis=1)) < 1e-10  # (M, M) is an integral


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--points", "1"], "--points needs at least 2"),
        (["--out", "x.txt"], "--out must end in .nc"),
        (["--out", "/nonexistent-folder/x.nc"], "does not exist"),
        (["--t-eval", "1"], "--points needs at least 2"),  # the old spellings: the same checks
        (["--output", "x.txt"], "--out must end in .nc"),
    ],
)
def test_bad_output_flags_exit_2(extra, words, capsys):
    assert main([*ARGS, *extra]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1


def test_the_old_spellings_write_the_same_file(tmp_path):
    """``--t-eval N --output FILE`` (before the one vocabulary, issue 28) still work: the
    same trajectory as ``--points N --out FILE``."""
    new, old = tmp_path / "new.csv", tmp_path / "old.csv"
    assert main([*ARGS, "--points", "5", "--out", str(new)]) == 0
    assert main([*ARGS, "--t-eval", "5", "--output", str(old)]) == 0
    assert new.read_text() == old.read_text() and len(new.read_text().splitlines()) == 6


def test_the_netcdf_file_describes_its_run(tmp_path):
    """``trajectory.nc`` (issue 28, 7): written by xarray, CF-1.x conventions, units and long
    names on the variables, and the run in the global attributes: parameters, method,
    tolerances, precision and package versions (compared with what was asked and with the
    versions installed)."""
    import chaplygin
    import scipy
    import xarray as xr

    nc = tmp_path / "t.nc"
    assert main([*ARGS, "--points", "5", "--precision", "20", "--out", str(nc)]) == 0
    with xr.open_dataset(nc) as ds:
        a = ds.attrs
        assert a["Conventions"].startswith("CF-1.") and a["history"]
        assert (a["system"], a["model"], a["effects"]) == ("chaplygin_ball",) * 2 + ("",)
        assert [a[f"parameter_{k}"] for k in ("I1", "I2", "I3", "D")] == [1.0, 2.0, 3.0, 1.0]
        assert a["parameters"].startswith("I1=1.0, I2=2.0, I3=3.0, D=1.0")
        assert (a["method"], a["rtol"], a["atol"]) == ("taylor", 1e-12, 1e-12)
        assert (a["precision_kind"], a["precision_digits"]) == ("digits", 20)
        assert a["chaplygin_version"] == chaplygin.__version__
        assert a["scipy_version"] == scipy.__version__ and a["numpy_version"] == np.__version__
        assert ds["t"].attrs == {"long_name": "time", "units": "time", "axis": "T"}
        assert ds["M1"].attrs["units"] == "mass*length^2/time"
        assert ds["gamma2"].attrs["long_name"] == "state gamma2 (group gamma)"
        assert np.allclose(ds["t"].values, np.linspace(0, 10, 5))
