"""Generated code: numpy, C, mpmath and direct sympy evaluation agree; generated/ is in sync."""

from __future__ import annotations

import dataclasses
import random
import shutil
import subprocess
import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest
import sympy as sp
from chaplygin.derive import build_model, builtin_variants, variant_name
from chaplygin.derive.emit import NumpyEmitter
from chaplygin.derive.model import Model, ParameterSpec
from chaplygin.derive.writer import check_generated, write_generated
from chaplygin.numerics import load_model_code
from chaplygin.verify.derive_cmd import generated_dir
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import EPS, assert_close_rel, random_params, random_state

VARIANTS = [variant_name(s, e) for s, e in builtin_variants()]
N_STATES = 50
#: Tolerances of the foundation issue: 1e-13 relative in double (a few hundred flops of
#: rounding, each ~1.1e-16), 1e-45 at 50 digits (five digits to spare).
DOUBLE_RTOL = 1e-13
DIGITS = 50
DIGITS_RTOL = 1e-45


def _variant(name):
    system, *effects = name.split("__")
    return build_model(system, effects), load_model_code(system, effects)


def _states(model, code, n: int):
    """``n`` random phase-space points and parameter vectors (one per point).

    Ball variants use the moderate ranges of ``reference`` (vectorised call checked too);
    other systems draw exact points from the phase-space sampler of derive.
    """
    rng = np.random.default_rng(2012)
    if {"M", "gamma"} <= set(code.state_groups):
        P = random_params(code, rng)
        return [(random_state(code, rng), P) for _ in range(n)]
    import random

    from chaplygin.derive.phase_space import sample_point

    prng = random.Random(2012)
    out = []
    for _ in range(n):
        point = sample_point(model, prng, model.state)
        out.append(
            (
                np.array([float(point[s]) for s in model.state]),
                np.array([float(point[s]) for s in model.params]),
            )
        )
    return out


@pytest.mark.parametrize("name", VARIANTS)
def test_numpy_c_mpmath_and_sympy_agree_at_random_states(name):
    model, code = _variant(name)
    lib = code.compiled()
    assert lib is not None, "the CI machine has a C compiler"
    T = 0.7  # a time where sin(Omega t) != 0: time-dependent parameters contribute (BM20)
    states = _states(model, code, N_STATES)
    Y = np.stack([y for y, _ in states], axis=1)
    if all(np.array_equal(states[0][1], p) for _, p in states):
        vec = code.numpy.rhs(T, Y, states[0][1])  # vectorised over the 50 states
    else:
        vec = np.stack([code.numpy.rhs(T, y, p) for y, p in states], axis=1)
    symbols = [model.time, *model.state, *model.params]
    for j, (y, P) in enumerate(states):
        c = lib.rhs(T, y, P)
        with mpmath.workdps(DIGITS):
            mp_args = [mpmath.mpf(float(v)) for v in y]
            mp_par = [mpmath.mpf(float(v)) for v in P]
            mp = code.mpmath.rhs(mpmath.mpf(T), mp_args, mp_par)
        point = {
            s: sp.Float(float(v), DIGITS + 10) for s, v in zip(symbols, [T, *y, *P], strict=True)
        }
        exact = [sp.N(e.xreplace(point), DIGITS + 10) for e in model.rhs_expanded]
        scale = max(abs(float(e)) for e in exact)
        assert_close_rel(vec[:, j], [float(e) for e in exact], DOUBLE_RTOL, f"numpy {name}")
        assert_close_rel(c, [float(e) for e in exact], DOUBLE_RTOL, f"C {name}")
        with mpmath.workdps(DIGITS + 10):
            err = max(abs(m - mpmath.mpf(str(e))) for m, e in zip(mp, exact, strict=True))
        assert err <= DIGITS_RTOL * scale, f"mpmath {name}: {err}"


@pytest.mark.parametrize(
    "system, effects",
    [
        ("chaplygin_ball", ("contact_point", "variable_gyrostat", "variable_inertia")),
        ("spherical_support", ("gyrostat",)),
        ("ball_on_surface", ("potential",)),
    ],
)
def test_the_chain_rule_jacobian_is_the_expanded_right_hand_side_s(system, effects):
    """``Model.jacobian_expanded`` (chain rule through the auxiliaries) against the
    expanded right-hand side differentiated one variable at a time, every other symbol
    first fixed at a generic rational point (an independent route: small univariate
    expressions), at exact points; a time-dependent, a support and a surface model (the generated
    Jacobians of two more are checked against differences below)."""
    from chaplygin.derive import build_model

    model = build_model(system, effects)
    rng = random.Random(29)
    symbols = [*model.state, *model.params, model.time]
    point = {s: sp.Rational(rng.randint(5, 95), rng.choice((37, 41, 43))) for s in symbols}
    point[model.time] = sp.Float(point[model.time], 70)  # sin(t) evaluated once, not carried
    J = model.jacobian_expanded.xreplace(point)
    for j, y in enumerate(model.state):
        others = {s: v for s, v in point.items() if s != y}
        for i, f in enumerate(model.rhs_expanded):
            reference = sp.diff(f.xreplace(others), y).xreplace({y: point[y]})
            # exact numbers, with sin(t) and square roots where the model has them: the
            # difference at 60 digits is zero to the working precision
            difference = sp.N(J[i, j] - reference, 60)
            assert abs(difference) <= sp.Float(10) ** -50 * (1 + abs(sp.N(reference, 60))), (i, j)


@pytest.mark.parametrize("name", ["chaplygin_ball", "chaplygin_ball__contact_point__gyrostat"])
def test_jacobian_matches_high_precision_differences(name):
    model, code = _variant(name)
    rng = np.random.default_rng(7)
    for _ in range(5):
        y, p = random_state(code, rng), random_params(code, rng)
        jac = code.numpy.jac(0.0, y, p)
        with mpmath.workdps(60):
            h = mpmath.mpf(10) ** -25
            yp = [mpmath.mpf(float(v)) for v in y]
            pp = [mpmath.mpf(float(v)) for v in p]
            fd = np.empty_like(jac)
            for k in range(len(y)):
                up, dn = list(yp), list(yp)
                up[k] += h
                dn[k] -= h
                fu, fdn = code.mpmath.rhs(0, up, pp), code.mpmath.rhs(0, dn, pp)
                fd[:, k] = [float((a - b) / (2 * h)) for a, b in zip(fu, fdn, strict=True)]
        assert_close_rel(jac, fd, DOUBLE_RTOL * 10, f"jac {name}")


@settings(max_examples=60, deadline=None)
@given(
    m=st.lists(st.floats(-10, 10), min_size=3, max_size=3),
    g=st.lists(st.floats(-1, 1), min_size=3, max_size=3).filter(lambda v: np.linalg.norm(v) > 0.1),
    inertia=st.lists(st.floats(0.1, 10), min_size=3, max_size=3),
    d=st.floats(0.1, 10),
)
def test_casimirs_are_conserved_by_the_generated_rhs(m, g, inertia, d):
    code = load_model_code("chaplygin_ball")
    y = np.concatenate([m, np.asarray(g) / np.linalg.norm(g)])
    p = np.array([*inertia, d])
    f = code.numpy.rhs(0.0, y, p)
    omega = code.numpy.aux(0.0, y, p)[1:]  # AUX = (Z, omega1, omega2, omega3)
    M, gamma, dM, dgamma = y[:3], y[3:], f[:3], f[3:]
    # M' = M x omega: each component is a difference of products of size |M||omega|, so the
    # rounding of (M, M') is a few eps |M|^2 |omega| whatever omega is (even M || omega)
    scale = np.max(np.abs(omega))  # |omega| without underflow (omega ~ 1e-271 squares to 0)
    w = scale * np.linalg.norm(omega / scale) if scale > 0 else 0.0
    assert abs(M @ dM) <= 16 * EPS * (M @ M) * w + 1e-300  # (M, M)' = 0
    assert abs(gamma @ dgamma) <= 16 * EPS * w + 1e-300  # (gamma, gamma)' = 0


def _tiny_model() -> Model:
    q, v, k = sp.symbols("q v k", real=True)
    k = sp.Symbol("k", positive=True)
    return Model(
        system="oscillator",
        effects=frozenset(),
        time=sp.Symbol("t"),
        state_groups=(("q", (q,)), ("v", (v,))),
        parameters=(ParameterSpec("k", (k,), "positive", "stiffness"),),
        aux=(),
        rhs=(v, -k * q),
        constraints=(),
        geometry=(),
        integrals=(("E", (v**2 + k * q**2) / 2),),
        density=sp.S.One,
    )


def test_numpy_emitter_golden_output_on_a_tiny_model():
    ((name, text),) = NumpyEmitter().emit(_tiny_model())
    assert name == "oscillator_numpy.py"
    assert "DO NOT EDIT" in text and "model hash: " in text
    expected_rhs = '''def rhs(t, y, p):
    """Right-hand side dy/dt, shape (2, ...)."""
    q, v, = y
    k, = p
    out = numpy.zeros((2,) + numpy.shape(q), dtype=numpy.result_type(q, *p))
    out[0] = v
    out[1] = -k*q
    return out
'''
    assert expected_rhs in text
    namespace: dict = {}
    exec(compile(text, name, "exec"), namespace)
    assert namespace["integrals"](0, np.array([1.0, 2.0]), np.array([3.0]))[0] == 3.5


def test_check_detects_stale_missing_and_extra_files(tmp_path: Path, capsys):
    """The check finds every kind of drift; ``chaplygin derive [--check] [--out]`` says so
    (one test: the ~40 s render of generated/ is paid once per process)."""
    from chaplygin.verify.cli import main

    assert main(["derive", "--check"]) == 0
    out = tmp_path / "gen"
    assert main(["derive", "--check", "--out", str(out)]) == 1
    assert main(["derive", "--out", str(out)]) == 0
    assert main(["derive", "--check", "--out", str(out)]) == 0
    capsys.readouterr()
    work = tmp_path / "generated"
    shutil.copytree(generated_dir(), work, ignore=shutil.ignore_patterns("__pycache__"))
    assert check_generated(work) == []
    target = work / "chaplygin_ball.c"
    target.write_text(target.read_text().replace("OUT[0] =", "OUT[0] = 1.0 +", 1))
    (work / "chaplygin_ball_numpy.py").unlink()
    (work / "orphan.py").write_text("# not generated\n")
    problems = check_generated(work)
    assert "chaplygin_ball.c: out of date" in problems
    assert "chaplygin_ball_numpy.py: missing" in problems
    assert "orphan.py: not produced by any built-in model" in problems
    write_generated(work)
    # a file it did not write is reported, never deleted (issue 11: nothing lost)
    assert check_generated(work) == ["orphan.py: not produced by any built-in model"]
    assert (work / "orphan.py").read_text() == "# not generated\n"
    (work / "orphan.py").unlink()
    assert check_generated(work) == []


#: One variant of each stage and kind of right-hand side (the plain ball, the multipliers of
#: the rubber ball, explicit time, the frame and contact point, the fixed-frame surface with a
#: potential, the support with a gyrostat): every emitter path at 5 of the 13 variants' cost.
HASH_SEED_VARIANTS = (
    ("chaplygin_ball", ()),
    ("chaplygin_ball", ("rubber",)),
    ("chaplygin_ball", ("contact_point", "variable_gyrostat", "variable_inertia")),
    ("ball_on_surface", ("potential",)),
    ("spherical_support", ("gyrostat",)),
)


def test_emission_is_independent_of_the_hash_seed(tmp_path: Path):
    script = (
        "import hashlib\n"
        "from chaplygin.derive import build_model\n"
        "from chaplygin.derive.emit import EMITTERS, ModelRoutines, get_emitter\n"
        "h = hashlib.sha256()\n"
        f"for system, effects in {HASH_SEED_VARIANTS!r}:\n"
        "    model = build_model(system, effects)\n"
        "    routines = ModelRoutines(model)\n"
        "    for language in sorted(EMITTERS):\n"
        "        h.update(repr(get_emitter(language).emit(model, routines)).encode())\n"
        "print(h.hexdigest())\n"
    )
    # both processes at once (the machine has two cores)
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", script],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env={"PYTHONHASHSEED": seed, "PATH": "/usr/bin:/bin"},
        )
        for seed in ("1", "4242")
    ]
    outs = [p.communicate() for p in procs]
    assert all(p.returncode == 0 for p in procs), [err for _, err in outs]
    digests = {out for out, _ in outs}
    assert len(digests) == 1 and len(next(iter(digests)).strip()) == 64


def test_cse_temporaries_never_shadow_a_model_symbol():
    """A state named ``x1`` must not be overwritten by a temporary ``x1``."""
    from chaplygin.derive.emit.base import _cse

    x0, x1 = sp.symbols("x0 x1", real=True)
    routine = _cse("t", [(x1 + x0) ** 2 + sp.sin(x1 + x0)], (1,))
    names = {s.name for s, _ in routine.temporaries}
    assert names and not names & {"x0", "x1"}


def test_rendered_files_are_cached_signed_and_a_foreign_file_is_not_used(tmp_path, monkeypatch):
    """A second process gets generated/'s files from the signed cache, bit for bit; a file
    changed by someone else, or made for another model, is emitted again, never used."""
    from chaplygin.derive import writer

    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("CHAPLYGIN_MODEL_CACHE", raising=False)
    model = build_model("chaplygin_ball", ())
    languages = ("c", "numpy")
    monkeypatch.setattr(writer, "_EMITTED", {})
    emitted = writer._emitted_variant(model, languages)
    path = writer.rendered_cache_file("chaplygin_ball", frozenset())
    assert path.is_file() and {name for name, _ in emitted["numpy"]} == {"chaplygin_ball_numpy.py"}

    calls = []
    real_get_emitter = writer.get_emitter

    def counting(language):
        calls.append(language)
        return real_get_emitter(language)

    monkeypatch.setattr(writer, "get_emitter", counting)
    monkeypatch.setattr(writer, "_EMITTED", {})  # a new process
    assert writer._emitted_variant(model, languages) == emitted and calls == []

    blob = path.read_bytes()
    path.write_bytes(blob.replace(b"OUT[0] =", b"OUT[0] = 1.0 +", 1))  # not our bytes
    monkeypatch.setattr(writer, "_EMITTED", {})
    assert writer._emitted_variant(model, languages) == emitted and sorted(calls) == sorted(
        languages
    )
    assert path.read_bytes() == blob  # rewritten with what the emitters give

    other = dataclasses.replace(model, rhs=tuple(-e for e in model.rhs))  # another model hash
    assert other.hash != model.hash
    assert writer._load_rendered(path, other) == {}
    monkeypatch.setenv("CHAPLYGIN_MODEL_CACHE", "0")
    assert writer.rendered_cache_file("chaplygin_ball", frozenset()) is None
