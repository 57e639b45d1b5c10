"""Scenes: schema, loading, validation errors, initial states by integrals, ``chaplygin run``."""

from __future__ import annotations

import json
from pathlib import Path

import mpmath
import numpy as np
import pytest
from chaplygin.numerics.ball.initial_state import integral_residuals, state_from_integrals
from chaplygin.numerics.code import load_model_code
from chaplygin.verify.cli import main
from chaplygin.verify.scene import Scene, SceneError, scene_json_schema

ROOT = Path(__file__).resolve().parents[3]
SCENES = ROOT / "examples" / "scenes"
FIG6F = SCENES / "k01-fig6f.toml"

ISSUE_EXAMPLE = """title = "K01 Fig. 6(f): critical energy on M || gamma, the trace drifts away"
system = "chaplygin_ball"
effects = []                  # what the outputs need is added and reported

[parameters]
I = [1, 3, 5]
D = 1
b = 1                         # ball radius (the paper omits it: assumed)

[initial]                     # by state, or by the values of the integrals
C = 1                         # (M, gamma)
parallel = true               # M || gamma, i.e. n = C^2
h = "0.1803189"               # energy

[run]
t_end = 3000
precision = "double"
rtol = 1e-12

[outputs]
contact_trace = { plot = true }
drift = { plot = true }
"""


def test_issue_example_is_shipped_verbatim():
    assert FIG6F.read_text() == ISSUE_EXAMPLE


def test_shipped_json_schema_equals_the_export():
    shipped = json.loads((SCENES / "scene.schema.json").read_text())
    assert shipped == json.loads(json.dumps(scene_json_schema()))
    assert set(shipped["properties"]) >= {"system", "effects", "parameters", "initial", "run"}


def test_from_toml_and_from_dict_agree():
    import tomllib

    a = Scene.from_toml(FIG6F)
    b = Scene.from_dict(tomllib.loads(FIG6F.read_text()))
    assert a.model_dump() == b.model_dump()
    assert a.initial.parallel and a.initial.h == "0.1803189"
    assert a.run_options.t_end == 3000


def _write(tmp_path, text: str) -> Path:
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    "old, new, path, line, words",
    [
        ("h = ", "hh = ", "initial.hh", 13, ["did you mean 'h'"]),
        ('"chaplygin_ball"', '"chaplygin_bal"', "system", 2, ["did you mean 'chaplygin_ball'"]),
        ("t_end = 3000", "t_end = [1]", "run.t_end", 16, ["got list"]),
        ("contact_trace =", "contact_trac =", "outputs.contact_trac", 21, ["contact_trace"]),
        ("effects = []", 'effects = ["gyrostatt"]', "effects[0]", 3, ["did you mean 'gyrostat'"]),
        ("rtol = 1e-12", "rtl = 1e-12", "run.rtl", 18, ["did you mean 'rtol'"]),
        ("rtol = 1e-12", 'method = "taylorr"', "run.method", 18, ["did you mean 'taylor'"]),
    ],
)
def test_errors_name_file_path_line_and_choices(tmp_path, old, new, path, line, words):
    scene = _write(tmp_path, ISSUE_EXAMPLE.replace(old, new, 1))
    with pytest.raises(SceneError) as info:
        Scene.from_toml(scene).resolve()
    err = info.value
    assert err.path == path and err.line == line and err.file == str(scene)
    msg = str(err)
    assert msg.startswith(f"{scene}:{line}: {path}: ") and "\n" not in msg
    for w in words:
        assert w in msg


def test_toml_syntax_error_gives_the_line(tmp_path):
    scene = _write(tmp_path, ISSUE_EXAMPLE.replace("D = 1", "D = = 1"))
    with pytest.raises(SceneError) as info:
        Scene.from_toml(scene)
    assert info.value.line == 7


def test_unused_effect_parameter_is_refused(tmp_path):
    scene = _write(tmp_path, ISSUE_EXAMPLE.replace("D = 1\n", "D = 1\nK = [0.1, 0.1, 0.2]\n"))
    with pytest.raises(SceneError, match="belongs to effect gyrostat"):
        Scene.from_toml(scene).resolve()


def test_cli_error_is_one_line_exit_2_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "out"
    status = main(["run", str(FIG6F), "--out", str(out), "--set", "initial.h=0.6"])
    err = capsys.readouterr().err
    assert status == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "admissible h in [h3, h1] = [0.1, 0.5]" in err
    assert not out.exists()


# ------------------------------------------------------------------------- initial states
BALL = {"I1": 1, "I2": 3, "I3": 5, "D": 1}


@pytest.mark.parametrize("point", range(4))
def test_parallel_state_has_the_prescribed_integrals(point):
    code = load_model_code("chaplygin_ball")
    r = state_from_integrals(
        code, BALL, {"h": "0.1803189", "C": 1, "parallel": True, "point": point}, 30
    )
    y = r.values["M"] + r.values["gamma"]
    res = integral_residuals(code, y, [1, 3, 5, 1], r.prescribed, 30)
    assert set(res) == {"H", "(M,gamma)"}
    assert max(abs(v) for v in res.values()) < 1e-25
    # M = C gamma exactly, gamma a unit vector
    assert all(m == g for m, g in zip(r.values["M"], r.values["gamma"], strict=True))


def test_parallel_range_ends_are_the_rotations_about_the_axes():
    code = load_model_code("chaplygin_ball")
    for h in ("0.1", "0.5", str(mpmath.mpf(1) / 6)):
        state_from_integrals(code, BALL, {"h": h, "C": 1, "parallel": True}, 30)
    for h in ("0.0999", "0.5001"):
        with pytest.raises(Exception, match=r"\[0.1, 0.5\]"):
            state_from_integrals(code, BALL, {"h": h, "C": 1, "parallel": True}, 30)


@pytest.mark.parametrize("point", (0, 1, 3))
def test_state_on_h_C_n_level_set(point):
    code = load_model_code("chaplygin_ball")
    req = {"h": "0.3", "C": "0.5", "n": 2, "point": point}
    r = state_from_integrals(code, BALL, req, 30)
    y = r.values["M"] + r.values["gamma"]
    res = integral_residuals(code, y, [1, 3, 5, 1], r.prescribed, 30)
    assert set(res) == {"H", "(M,gamma)", "(M,M)"}
    assert max(abs(v) for v in res.values()) < 1e-25
    again = state_from_integrals(code, BALL, req, 30)
    assert again.values == r.values  # reproducible


def test_gyrostat_parallel_state_K01_fig7():
    code = load_model_code("chaplygin_ball", ["gyrostat"])
    p = {**BALL, "K1": "0.1", "K2": "0.1", "K3": "0.2"}
    r = state_from_integrals(code, p, {"h": "0.1366", "C": 1, "parallel": True}, 30)
    M, g = r.values["M"], r.values["gamma"]
    with mpmath.workdps(40):
        K = [mpmath.mpf("0.1"), mpmath.mpf("0.1"), mpmath.mpf("0.2")]
        # M + K = C gamma
        assert max(abs(m + k - gi) for m, k, gi in zip(M, K, g, strict=True)) < 1e-25
        pv = [1, 3, 5, 1, *K]
    res = integral_residuals(code, M + g, pv, r.prescribed, 30)
    assert max(abs(v) for v in res.values()) < 1e-20


def test_impossible_n_is_refused_with_range():
    code = load_model_code("chaplygin_ball")
    with pytest.raises(Exception, match="n >= C"):
        state_from_integrals(code, BALL, {"h": "0.3", "C": 2, "n": 1}, 30)
    with pytest.raises(Exception, match="energy ranges over"):
        state_from_integrals(code, BALL, {"h": 50, "C": 0, "n": 1}, 30)


# ------------------------------------------------------------------------------ running
def test_run_writes_outputs_and_json(tmp_path, capsys):
    out = tmp_path / "fig6f"
    status = main(
        ["run", str(FIG6F), "--out", str(out), "--set", "run.t_end=20", "--json", "--quiet"]
    )
    assert status == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["effects"] == ["contact_point"]
    assert set(summary["y"]) == set(summary["states"])
    assert all(isinstance(v, str) and float(v) == float(v) for v in summary["y"].values())
    names = {Path(p).name for p in summary["outputs"]}
    assert names == {
        "trajectory.nc",
        "contact_trace.png",
        "contact_trace.svg",
        "drift.png",
        "drift.svg",
        "summary.json",
    }
    for name in names:
        assert (out / name).stat().st_size > 0
    full = json.loads((out / "summary.json").read_text())
    assert full["scene"]["run"]["t_end"] == 20  # as given (with the override)
    assert full["resolved"]["residuals"]["H"] == pytest.approx(0, abs=1e-15)
    assert max(full["drift"].values()) < 1e-9
    from scipy.io import netcdf_file

    with netcdf_file(out / "trajectory.nc", mmap=False) as nc:
        assert nc.variables["x"].units == b"length"
        assert nc.variables["t"][-1] == pytest.approx(20)
        assert set(summary["states"]) <= set(nc.variables)
    import xarray as xr

    with xr.open_dataset(out / "trajectory.nc") as ds:  # the run, as summary.json has it
        assert ds.attrs["Conventions"].startswith("CF-1.")
        assert (ds.attrs["system"], ds.attrs["effects"]) == (full["system"], "contact_point")
        assert ds.attrs["model"] == full["model"] and ds.attrs["method"] == full["method"]
        assert ds.attrs["precision_kind"] == full["precision"]["kind"]
        assert ds.attrs["mpmath_version"] == full["versions"]["mpmath"]


def test_run_json_of_several_scenes_is_one_document(tmp_path, capsys):
    """``run A.toml B.toml --json`` prints one JSON document (issue 28, 2): a list of the
    scenes' objects in the order given, each the object one scene alone prints."""
    scenes = []
    for stem in ("first", "second"):
        scenes.append(tmp_path / f"{stem}.toml")
        scenes[-1].write_text(FIG6F.read_text())
    argv = ["--set", "run.t_end=1", "--json", "--quiet"]
    out = tmp_path / "out"
    assert main(["run", *map(str, scenes), "--out", str(out), *argv]) == 0
    both = json.loads(capsys.readouterr().out)
    assert isinstance(both, list) and len(both) == 2
    assert [Path(d["outputs"][0]).parent.name for d in both] == ["first", "second"]
    assert main(["run", str(scenes[0]), "--out", str(tmp_path / "one"), *argv]) == 0
    one = json.loads(capsys.readouterr().out)
    assert isinstance(one, dict) and one["y"] == both[0]["y"] and one.keys() == both[0].keys()


def test_run_refuses_a_foreign_non_empty_folder(tmp_path, capsys):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "keep.txt").write_text("x")
    assert main(["run", str(FIG6F), "--out", str(out), "--set", "run.t_end=1"]) == 2
    assert sorted(p.name for p in out.iterdir()) == ["keep.txt"]
    assert "that chaplygin run did not make" in capsys.readouterr().err


def test_explain_runs_nothing(tmp_path, capsys):
    out = tmp_path / "x"
    assert main(["run", str(FIG6F), "--out", str(out), "--explain"]) == 0
    text = capsys.readouterr().out
    assert "contact_point: needed by outputs.contact_trace" in text
    assert "operations" in text and "generated/chaplygin_ball__contact_point" in text
    assert not out.exists()


def test_scene_result_api():
    scene = Scene.from_toml(FIG6F, ["run.t_end=5", "run.points=51"])
    result = scene.run()
    assert result.success and len(result.t) == 51
    assert set(result.y) >= {"x", "y", "gamma1"}
    assert "SceneResult" in repr(result) and "<table>" in result._repr_html_()
    figs = result.figures()
    assert set(figs) == {"contact_trace", "drift"}
    from matplotlib.figure import Figure

    assert isinstance(result.body_trace_figure(), Figure)
    assert isinstance(result.series_figure(["omega1", "H"]), Figure)
    h = result.quantity("H")
    assert np.max(np.abs(h - float(mpmath.mpf("0.1803189")))) < 1e-12


NEAR = """title = "near"
system = "chaplygin_ball"
[parameters]
I = [1, 1.5, 3]
D = 1
[initial]
C = 1
n = 2
near = "p{axis}"
[run]
t_end = 20
rtol = 1e-12
atol = 1e-12
"""


@pytest.mark.parametrize("axis", (1, 2, 3))
def test_near_is_the_steady_rotation_of_branch_p_i(tmp_path, axis):
    from chaplygin.numerics.ball.bifurcation import sigma

    scene = Scene.from_toml(_write(tmp_path, NEAR.format(axis=axis)))
    res = scene.resolve()
    assert max(abs(v) for v in res.residuals.values()) < 1e-14
    result = scene.run()
    H = result.quantity("H")
    # its energy is the branch p_i of the diagram at n = 2 (numerics.ball.bifurcation, K01 (3.3))
    assert H[0] == pytest.approx(float(sigma(axis - 1, 2.0, 1.0, (1, 1.5, 3), 1.0)) / 2, rel=1e-12)
    # a steady rotation: omega stays along e_i (stable p1, p3; p2 too over this short time)
    w = np.array([result.quantity(f"omega{i}") for i in (1, 2, 3)])
    others = np.delete(w, axis - 1, axis=0)
    assert np.max(np.abs(others)) < 1e-6 * np.max(np.abs(w[axis - 1]))


def test_offset_pushes_off_and_separatrix_needs_the_middle_axis(tmp_path):
    near = Scene.from_toml(_write(tmp_path, NEAR.format(axis=2)), ["initial.offset=1e-6"])
    assert abs(near.resolve().residuals["(M,M)"]) > 1e-13  # pushed off: n moved
    text = NEAR.format(axis=2).replace('near = "p2"', "separatrix = 2").replace("n = 2\n", "")
    res = Scene.from_toml(_write(tmp_path, text)).resolve()
    assert res.prescribed["H"] == pytest.approx(1 / 3)  # h2 = C^2/(2 I2)
    assert max(abs(v) for v in res.residuals.values()) < 1e-15
    with pytest.raises(SceneError, match="middle axis, here 2"):
        Scene.from_toml(
            _write(tmp_path, text.replace("separatrix = 2", "separatrix = 3"))
        ).resolve()
    with pytest.raises(SceneError, match="admissible n >= 1"):
        Scene.from_toml(_write(tmp_path, NEAR.format(axis=2)), ["initial.n=0.5"]).resolve()


def test_andoyer_deprit_state_and_range(tmp_path):
    text = (SCENES / "bm20-fig5.toml").read_text()
    res = Scene.from_toml(_write(tmp_path, text)).resolve()
    y = res.state_by_name()
    M = np.array([float(y[f"M{i}"]) for i in (1, 2, 3)])
    g = np.array([float(y[f"gamma{i}"]) for i in (1, 2, 3)])
    assert np.linalg.norm(M) == pytest.approx(3, rel=1e-15)  # |M| = G
    assert abs(M @ g) < 1e-15 and np.linalg.norm(g) == pytest.approx(1, rel=1e-15)
    assert M[2] == pytest.approx(1.5, rel=1e-15)  # M3 = G z
    with pytest.raises(SceneError, match=r"\|z\| <= 1"):
        Scene.from_toml(_write(tmp_path, text), ["initial.z=1.5"]).resolve()


@pytest.mark.parametrize("precision", ["double", 30])
def test_scene_and_api_complete_the_frame_by_one_rule(precision):
    """On M || gamma (M = 1.5 gamma, a generic gamma, given by state) a scene and
    ``chaplygin.integrate`` start from the same bits: both complete alpha, beta by the one rule
    of ``numerics/frame.py`` (BKM12-7 is undefined there), and the scene says so. Before
    issue 23 the scene chose a frame and the API refused."""
    from chaplygin.numerics import integrate

    with mpmath.workdps(45):
        g = [mpmath.mpf("0.2"), mpmath.mpf("-0.3"), mpmath.sqrt(mpmath.mpf("0.87"))]
        gamma = [mpmath.nstr(c, 40) for c in g]
        M = [mpmath.nstr(mpmath.mpf("1.5") * c, 40) for c in g]
    params = {"I": [1, 2, 3], "D": 1, "b": 1}
    scene = Scene.from_dict({
        "system": "chaplygin_ball", "effects": ["contact_point"], "parameters": params,
        "initial": {"M": M, "gamma": gamma}, "run": {"t_end": 1, "precision": precision},
    })  # fmt: skip
    res = scene.resolve()
    assert "M || gamma: alpha = the body axis least aligned with gamma" in res.how
    r = integrate("chaplygin_ball", {"M": M, "gamma": gamma}, 1e-3, params,
                  effects="contact_point", precision=precision)
    assert list(r.y[:, 0]) == list(res.y0)  # the same numbers (mpf: exact comparison)
    off = scene.with_initial(M=["0.3", "0.45", "1.3990"])  # off the line: BKM12-7, no note
    assert "M || gamma" not in off.resolve().how


def test_effect_combination_not_in_generated_is_derived_and_says_so(tmp_path, capsys):
    """The path that derives, emits and compiles a variant on first use (no longer untested)."""
    from chaplygin.numerics.code import generated_manifest

    assert "chaplygin_ball__variable_gyrostat" not in generated_manifest()
    scene = _write(
        tmp_path,
        """title = "k(t) alone"
system = "chaplygin_ball"
effects = ["variable_gyrostat"]
[parameters]
I = [4, 3, 2]
D = 1
K = [1, -1, 2]
Omega = 0.5
[initial]
M = [0.1, 0.2, 0.3]
gamma = [0, 0, 1]
[run]
t_end = 5
rtol = 1e-12
atol = 1e-12
""",
    )
    out = tmp_path / "o"
    assert main(["run", str(scene), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    # first use in this process: derived (or loaded from the first-use cache) and said so
    assert "note: chaplygin_ball__variable_gyrostat is not in generated/: " in err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["code_origin"] in ("derived on first use", "cache of first-use code")
    assert summary["code_note"] in err
    assert summary["resolved"]["effects"] == {"variable_gyrostat": "named in the scene"}
    assert max(summary["drift"].values()) < 1e-9  # its integrals (M,M), (M,gamma) hold


def test_write_dataset_round_trip_and_refuses_inconsistent_dimensions(tmp_path):
    from chaplygin.verify.outputs.trajectory import write_dataset
    from scipy.io import netcdf_file

    z = np.linspace(-1, 1, 7) / 3
    n = np.arange(7, dtype=np.int64)
    path = tmp_path / "poincare.nc"
    write_dataset(
        path,
        {
            "z": (("point",), z, {"long_name": "M3/G", "units": "1"}),
            "iteration": (("point",), n, {"long_name": "map iteration", "units": "1"}),
            "grid": (("point", "k"), np.outer(z, [1.0, 2.0]), {"units": "1"}),
        },
        {"title": "t"},
    )
    with netcdf_file(path, mmap=False) as nc:
        assert nc.title == b"t"
        assert np.array_equal(nc.variables["z"][:], z)
        assert np.array_equal(nc.variables["iteration"][:], n)
        assert nc.variables["grid"].shape == (7, 2)
        assert nc.variables["z"].units == b"1"
    with pytest.raises(ValueError, match="lengths"):
        write_dataset(tmp_path / "bad.nc", {"a": (("p",), z, {}), "b": (("p",), z[:3], {})})
    with pytest.raises(ValueError, match="dimensions"):
        write_dataset(tmp_path / "bad.nc", {"a": (("p", "q"), z, {})})


@pytest.mark.parametrize(
    "precision,named",
    [
        ("double", "chaplygin_ball__contact_point_taylor.c (compiled Taylor integrator, double; "
                   "the coefficients written out for the run's orders, pairs of nodes in vectors"),
        ("quad", "chaplygin_ball__contact_point_taylor.c (compiled Taylor integrator, __float128"),
        ("25", "chaplygin_ball__contact_point_taylor.c (compiled Taylor integrator, double-double"),
        ("40", "chaplygin_ball__contact_point_taylor.c (compiled Taylor integrator, quad-double"),
        ("100", "chaplygin_ball__contact_point_taylor_mpfr.c (compiled Taylor integrator, MPFR"),
    ],
)
def test_explain_names_the_taylor_code_that_runs(precision, named):
    scene = Scene.from_toml(FIG6F, [f"run.precision={precision}", "run.method=taylor"])
    text = scene.explain()
    assert named in text, text


# ------------------------------------------------------------- titles after --set (issue 22)
def test_title_placeholders_show_the_values_that_run():
    scene = Scene.from_toml(SCENES / "k01-fig7a.toml", ["initial.h=0.1"])
    assert scene.title == "K01 Fig. 7(a): gyrostat, M + K || gamma, h = 0.1"
    assert "0.1366" not in scene.title
    scene = Scene.from_toml(SCENES / "k01-fig3b.toml", ["parameters.I=[1, 2, 3]"])
    assert "(I = (1, 2, 3), C = 1)" in scene.title and "h = 0.6" in scene.title
    # the raw title stays in the summary's copy of the scene
    assert scene._given["title"].endswith("(I = {parameters.I}, C = {initial.C})")


def test_a_title_without_the_placeholder_says_what_set_changed(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(ISSUE_EXAMPLE)
    plain = Scene.from_toml(path)
    assert plain.title == "K01 Fig. 6(f): critical energy on M || gamma, the trace drifts away"
    changed = Scene.from_toml(path, ["initial.h=0.1", "run.t_end=100"])
    assert changed.title.startswith(plain.title)
    assert "--set initial.h = 0.1, run.t_end = 100" in changed.title
    assert "the scene file's" in changed.title
    # --set title=... replaces the title: nothing to mark
    assert Scene.from_toml(path, ["title=mine h = {initial.h}"]).title == "mine h = 0.1803189"


def test_title_braces_and_unknown_placeholders(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(ISSUE_EXAMPLE.replace('the trace drifts away"', '{{set}} at {run.t_end}"'))
    assert Scene.from_toml(path).title.endswith("{set} at 3000")
    path.write_text(ISSUE_EXAMPLE.replace('the trace drifts away"', 'h = {initial.hh}"'))
    with pytest.raises(SceneError, match=r"\{initial.hh\} in the title names no key") as err:
        Scene.from_toml(path)
    assert err.value.line == 1


def test_plots_carry_the_shown_title(tmp_path, capsys):
    out = tmp_path / "o"
    argv = ["run", str(SCENES / "k01-fig6a.toml"), "--out", str(out), "--quiet"]
    argv += ["--set", "run.t_end=2", "--set", "initial.h=0.45"]
    assert main(argv) == 0, capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert (
        summary["title"] == "K01 Fig. 6(a): M || gamma, h = 0.45 (I = (1, 3, 5), C = 1) [run "
        "with --set run.t_end = 2; the title's own values are the scene file's]"
    )
    svg = (out / "contact_trace.svg").read_text()
    assert "h = 0.45" in svg and "0.4993" not in svg


# ------------------------------------------------------------------- contact-trace aspect
def test_contact_trace_aspect_auto_shows_the_oscillation():
    from chaplygin.derive.errors import UserInputError
    from chaplygin.verify.outputs.trajectory_figures import contact_trace_figure

    x = np.linspace(0, 100, 500)
    y = 0.3 * np.sin(x)
    equal = contact_trace_figure(x, y, "t").axes[0]
    auto = contact_trace_figure(x, y, "t", "auto").axes[0]
    assert equal.get_aspect() == 1.0 and auto.get_aspect() == "auto"
    # the oscillation spans the auto axes, and the axes say the scales differ
    lo, hi = auto.get_ylim()
    assert hi - lo < 1.0 and "different scales" in auto.get_xlabel()
    with pytest.raises(UserInputError):
        contact_trace_figure(x, y, "t", "square")
    with pytest.raises(SceneError, match="aspect"):
        Scene.from_toml(SCENES / "k01-fig3a.toml", ['outputs.contact_trace={aspect="square"}'])
    for c in "abcd":
        assert Scene.from_toml(SCENES / f"k01-fig3{c}.toml").outputs.contact_trace.aspect == "auto"


# --------------------------------------------------------- integrals with a given gamma
def test_integrals_with_a_given_gamma_resolve_at_that_gamma():
    g = [0.3, -0.5, 0.81]
    data = {
        "system": "chaplygin_ball",
        "effects": ["gyrostat"],
        "parameters": {"I": [1, 3, 5], "D": 1, "K": [0.1, 0.1, 0.2]},
        "initial": {"C": 1, "n": 2.3, "h": "0.41", "gamma": g},
        "run": {"t_end": 1},
    }
    resolved = Scene.from_dict(data).resolve()
    y = np.array([float(v) for v in resolved.y0])
    assert np.allclose(y[3:6], np.array(g) / np.linalg.norm(g), rtol=0, atol=1e-15)
    assert max(abs(float(v)) for v in resolved.residuals.values()) < 1e-14


def test_fig7f_scene_starts_at_the_elliptic_rotations_gamma():
    from chaplygin.verify.claims.k01_trace import fig7f_rotation

    scene = Scene.from_toml(SCENES / "k01-fig7f.toml")
    given = np.array([float(v) for v in scene.initial.gamma])
    rotation = fig7f_rotation()
    assert np.allclose(given, rotation["state"][3:], rtol=0, atol=1e-15)
    assert rotation["floquet"].stable
    assert float(scene.initial.n) < rotation["n"] < float(scene.initial.n) + 0.01


def test_bifurcation_k01_2_is_titled_fig_2a():
    from chaplygin.verify.plots import FIGURES

    assert FIGURES["k01-2"][2] == "K01 Fig. 2(a)"
    assert not any("2b" in title for _, _, title in FIGURES.values())
