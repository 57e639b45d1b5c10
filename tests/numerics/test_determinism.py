"""The same bits on every machine: a chaotic scene under other BLAS kernels, other numpy and
glibc code paths, two compilers and two optimisation levels (issue 22).

BM20 Fig. 5 (Omega = 1.07, d = 4.385: the strange attractor) is run in fresh processes: a few
hundred periods of the stroboscopic map (the Taylor integrator in C) and the Lyapunov spectrum
in both forms (the variational DOP853 in C, QR in C, the level-set bases and start vectors in
Python), then the vector lanes (map Jacobians of six points, their attractors' regimes: the batch
map and the Lyapunov loop in lanes) and ``integrate_many`` (the starts read together, the Taylor
integrator in its lanes). Every array and number of those results (wall times
aside) is hashed; the hashes must be equal under

* ``OPENBLAS_CORETYPE`` = Prescott, Nehalem, Sandybridge, Haswell (numpy's BLAS kernels: they
  give other bits for ``@``, ``qr``, ``solve`` -- shown in tests/arith/test_detlinalg.py);
* numpy's SIMD dispatch switched off (``NPY_DISABLE_CPU_FEATURES``) and glibc's AVX2/FMA
  variants of libm switched off (``GLIBC_TUNABLES``);
* gcc and clang, each at ``-O0`` and ``-O2`` (``CC``, ``CHAPLYGIN_OPT_LEVEL``).

The control: the same run from an initial state moved by one unit in the last place of one
coordinate gives another hash -- the hash sees every last bit, and the orbit is chaotic.

A second, smaller test runs K01's trace geometry (two claims' computations: dense Taylor
solutions, event location, complex arithmetic, the gyrostat's segment) under two BLAS kernels
and without numpy's SIMD dispatch, and demands equal bits too.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "examples" / "scenes"

#: The run in a fresh process: prints one JSON line {"hash": ..., "sizes": ...}.
PROBE = r"""
import hashlib, json, math, sys
import numpy as np
from chaplygin.verify.scene import Scene

nudge = float(sys.argv[1])
h = hashlib.sha256()
sizes = {}

def feed(name, value):
    if isinstance(value, dict):
        for k in sorted(value):
            if "wall" in k or k.endswith("_s") or k == "seconds":
                continue
            feed(f"{name}.{k}", value[k])
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            feed(f"{name}[{i}]", v)
    elif isinstance(value, np.ndarray) and value.dtype.kind in "fciub":
        arr = np.ascontiguousarray(value)
        sizes[name] = int(arr.size)
        h.update(name.encode() + arr.tobytes())
    elif isinstance(value, (float, int, str, bool)) or value is None:
        h.update(f"{name}={value!r};".encode())

overrides_map = ["outputs.poincare.transient=0", "outputs.poincare.iterations=300",
                 "outputs.poincare.plot3d=false"]
overrides_lyap = ["outputs.lyapunov.iterations=250", "outputs.lyapunov.transient=50",
                  "outputs.lyapunov.states=2", "outputs.lyapunov.windows=5",
                  "outputs.lyapunov.plot=false"]
if nudge:
    overrides_map.append(f"initial.z={math.nextafter(0.5, 1.0)!r}")
    overrides_lyap.append(f"initial.z={math.nextafter(0.5, 1.0)!r}")
for path, overrides in (("bm20-fig5-map.toml", overrides_map),
                        ("bm20-fig5-lyapunov.toml", overrides_lyap)):
    result = Scene.from_toml(sys.argv[2] + "/" + path, overrides).run()
    for key, done in sorted(result.analyses.items()):
        feed(f"{path}.{key}.summary", done.summary)
        for name, (_dims, values, _attrs) in sorted(done.arrays.items()):
            feed(f"{path}.{key}.{name}", np.asarray(values))
# the vector lanes: map Jacobians (variational lanes) and regimes (batch map and Lyapunov lanes)
from chaplygin.numerics.ball.regimes import attractor_regimes
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.dynamics.variational import flow_jacobians

code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
P = np.array([[4, 3, 2, 4.385, 0, 2, -6, -3, -9, w] for w in np.linspace(1.064, 1.08, 6)])
Y = np.array([[1.3, -2.1, 0.7, 0.36, 0.48, 0.8]] * 6) * np.linspace(0.9, 1.1, 6)[:, None]
Y[:, 3:] /= np.linalg.norm(Y[:, 3:], axis=1)[:, None]
if nudge:
    Y[0, 0] = math.nextafter(Y[0, 0], 2.0)
jac = flow_jacobians(code, P, Y, 0.0, 2 * math.pi / P[:, -1])
feed("flow_jacobians", {"y": jac.y, "jacobians": jac.jacobians, "status": jac.status})
for j, r in enumerate(attractor_regimes(code, P, Y, transient=60, recorded=40, max_period=8,
                                        intervals=40, lyapunov_transient=5)):
    feed(f"regime[{j}]", {"regime": r.regime, "period": r.period, "lyapunov": r.lyapunov,
                          "error": r.lyapunov_error, "points": r.points})
# many orbits at once: the starts read together, the Taylor integrator in its lanes
from chaplygin.numerics.ensemble import integrate_many

ball = np.hstack([Y[:, :3] * 0.3, Y[:, 3:]])
many = integrate_many("chaplygin_ball", ball, 9.7, {"I": (1.13, 2.07, 3.31), "D": 0.93},
                      rtol=1e-11, atol=1e-11)
feed("integrate_many", {"y": many.y, "drift": many.drift, "nsteps": many.nsteps})
print(json.dumps({"hash": h.hexdigest(), "sizes": sizes}))
"""


#: numpy's SIMD dispatch and glibc's AVX2/FMA variants of libm switched off.
WITHOUT_SIMD = {
    "NPY_DISABLE_CPU_FEATURES": "X86_V3 X86_V4 AVX512_ICL AVX512_SPR",
    "GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA",
}


def _compiler(name: str) -> str:
    path = shutil.which(name)
    if path is None:
        if os.environ.get("CI"):
            pytest.fail(f"{name} is needed for the determinism test (CI installs it)")
        pytest.skip(f"{name} is not installed")
    return path


#: K01's trace geometry in a fresh process (the claims K01-Fig6f.circle and K01-4.3bounded:
#: dense Taylor solutions, crossings, Brent, complex arithmetic, the gyrostat's segment, its
#: gradient lines): every number of their computation hashed, bit for bit; prints one JSON
#: line {"hash": ..., "count": ...}. The argument "1" moves the printed energy of Fig. 6(f)
#: by one unit in the last place (the control).
TRACE_PROBE = r"""
import hashlib, json, math, sys
import numpy as np
from chaplygin.verify.claims import REGISTRY
from chaplygin.verify.claims import k01_trace as k

if sys.argv[1] == "1":
    k.H_FIG6F = math.nextafter(k.H_FIG6F, 1.0)
h = hashlib.sha256()
count = 0

def feed(value):
    global count
    arr = np.ascontiguousarray(np.asarray(value))
    assert arr.dtype.kind in "fcib", arr.dtype
    count += arr.size
    h.update(arr.dtype.str.encode() + arr.tobytes())

fig = k._fig6f_run()
tp = fig["tp"]
for name in ("period", "turn", "turning", "displacement", "centre", "radius", "inner", "outer",
             "speed", "closure", "t", "z"):
    feed(getattr(tp, name))
feed(tp.sol.t)
for c in tp.sol.coefficients:
    feed(c)
for name in ("z", "circle", "line"):
    feed(fig[name])
seg = k._segment_turning()
for e in seg["equilibria"]:
    feed(e["gamma"])
    feed([e["h"], e["spin"], e["rate"] or 0.0, e["residual"]])
for side in seg["sides"]:
    feed(side["turns"])
feed(sorted(seg["fig7"].items()))
for claim in ("K01-Fig6f.circle", "K01-4.3bounded"):
    r = REGISTRY[claim].compute()
    feed([r.error, r.bound])
print(json.dumps({"hash": h.hexdigest(), "count": count}))
"""


#: The validated integrator on the compiled Arb kernel (issue 26): BM20's model from a start of
#: decimal balls for a while, with the flow's derivative (Lohner's QR in detlinalg, the
#: recurrences in the kernel built by the configuration's compiler): every ball's midpoint and
#: radius hashed exactly.
#: The argument "1" moves one start coordinate by 10^-30 (the control).
ENCLOSURE_PROBE = r"""
import hashlib, json, sys
from chaplygin.numerics.code import load_model_code
from chaplygin.numerics.validated import enclose_flow
from chaplygin.numerics.validated.arb_kernel import arb_kernel

code = load_model_code("chaplygin_ball", "variable_gyrostat,variable_inertia")
assert arb_kernel(code) is not None, "no compiled kernel"
params = ["4", "3", "2", "4.385", "0", "2", "-6", "-3", "-9", "1.06675"]
start = ["1.3", "-2.1", "0.7", "0.36", "0.48", "0.8"]
if sys.argv[1] == "1":
    start[0] = "1.300000000000000000000000000001"
e = enclose_flow(code, params, start, 0, "0.37", jacobian=True, order=24, tol=1e-20)
h = hashlib.sha256()
count = 0
for ball in [*e.state, *(x for row in e.jacobian for x in row)]:
    h.update(repr((ball.mid().man_exp(), ball.rad().man_exp())).encode())
    count += 1
print(json.dumps({"hash": h.hexdigest(), "count": count, "steps": e.steps}))
"""


def _run(env_extra: dict[str, str], cache: Path, nudge: bool = False, probe: str = PROBE) -> dict:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OPENBLAS", "NPY_", "GLIBC"))}
    env.update(CHAPLYGIN_CACHE_DIR=str(cache), **env_extra)
    proc = subprocess.run(
        [sys.executable, "-c", probe, "1" if nudge else "0", str(SCENES)],
        env=env, capture_output=True, text=True, timeout=1500,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def cache(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("chaplygin-cache")


def test_chaotic_scene_has_the_same_bits_on_every_code_path(cache):
    gcc, clang = _compiler("gcc"), _compiler("clang")
    configurations = {
        "gcc -O2": {"CC": gcc},
        "OpenBLAS Prescott": {"CC": gcc, "OPENBLAS_CORETYPE": "Prescott"},
        "OpenBLAS Nehalem": {"CC": gcc, "OPENBLAS_CORETYPE": "Nehalem"},
        "OpenBLAS Sandybridge": {"CC": gcc, "OPENBLAS_CORETYPE": "Sandybridge"},
        "OpenBLAS Haswell": {"CC": gcc, "OPENBLAS_CORETYPE": "Haswell"},
        "numpy without SIMD dispatch, glibc without AVX2/FMA": {"CC": gcc, **WITHOUT_SIMD},
        "gcc -O0": {"CC": gcc, "CHAPLYGIN_OPT_LEVEL": "0"},
        "clang -O2": {"CC": clang},
        "clang -O0": {"CC": clang, "CHAPLYGIN_OPT_LEVEL": "0"},
    }
    seen = {name: _run(env, cache) for name, env in configurations.items()}
    reference = seen["gcc -O2"]
    assert reference["sizes"], "nothing was hashed"
    assert sum(reference["sizes"].values()) > 300  # the map points and the spectra
    differing = {name: r["hash"] for name, r in seen.items() if r["hash"] != reference["hash"]}
    assert not differing, f"other bits than gcc -O2 ({reference['hash']}): {differing}"
    # control: one ulp in one coordinate of the start changes the hash
    assert _run(configurations["gcc -O2"], cache, nudge=True)["hash"] != reference["hash"]


def test_k01_trace_geometry_has_the_same_bits_on_every_code_path(cache):
    """K01's trace claims (integrable motions; dense Taylor solutions, no BLAS, the
    project's own angles and complex products) under other BLAS kernels and without numpy's
    SIMD loops and glibc's AVX2/FMA paths (numpy's complex multiply and modulus take other
    bits there); the control moves one input by one ulp."""
    gcc = _compiler("gcc")
    configurations = {
        "OpenBLAS Prescott": {"CC": gcc, "OPENBLAS_CORETYPE": "Prescott"},
        "OpenBLAS Haswell": {"CC": gcc, "OPENBLAS_CORETYPE": "Haswell"},
        "numpy without SIMD dispatch, glibc without AVX2/FMA": {"CC": gcc, **WITHOUT_SIMD},
    }
    seen = {name: _run(env, cache, probe=TRACE_PROBE) for name, env in configurations.items()}
    reference = seen["OpenBLAS Prescott"]
    assert reference["count"] > 10_000  # the samples of a period, the circle, the polynomials
    differing = {name: r["hash"] for name, r in seen.items() if r["hash"] != reference["hash"]}
    assert not differing, f"other bits than under Prescott ({reference['hash']}): {differing}"
    nudged = _run(configurations["OpenBLAS Prescott"], cache, nudge=True, probe=TRACE_PROBE)
    assert nudged["hash"] != reference["hash"]


def test_enclosures_on_the_arb_kernel_have_the_same_bits_on_every_code_path(cache):
    """The compiled Arb kernel of the validated integrator built by gcc and clang at -O0 and
    -O2, and Lohner's step under two BLAS kernels: the same balls to the last bit; the
    control moves one start coordinate by 10^-30."""
    gcc, clang = _compiler("gcc"), _compiler("clang")
    configurations = {
        "gcc -O2": {"CC": gcc},
        "gcc -O0": {"CC": gcc, "CHAPLYGIN_OPT_LEVEL": "0"},
        "clang -O2": {"CC": clang},
        "clang -O0": {"CC": clang, "CHAPLYGIN_OPT_LEVEL": "0"},
        "OpenBLAS Prescott": {"CC": gcc, "OPENBLAS_CORETYPE": "Prescott"},
        "OpenBLAS Haswell": {"CC": gcc, "OPENBLAS_CORETYPE": "Haswell"},
    }
    seen = {n: _run(env, cache, probe=ENCLOSURE_PROBE) for n, env in configurations.items()}
    reference = seen["gcc -O2"]
    assert reference["count"] == 6 + 36 and reference["steps"] > 1
    differing = {name: r["hash"] for name, r in seen.items() if r["hash"] != reference["hash"]}
    assert not differing, f"other bits than gcc -O2 ({reference['hash']}): {differing}"
    nudged = _run(configurations["gcc -O2"], cache, nudge=True, probe=ENCLOSURE_PROBE)
    assert nudged["hash"] != reference["hash"]
