"""What a described system costs: description -> equations -> discovery -> proofs -> code.

Issue 24's target: for a 6-D system with one symbolic parameter, description ->
equations -> discovery up to degree 2 (with the density search) -> proofs -> compiled code
in <= 60 s on 2 cores, cached like the built-ins (a second run <= 2 s). Measured on the
Chaplygin top of ``examples/systems/chaplygin_top.toml`` (moments 2/5, 1/2, 3/5, centre of
mass on the third axis at ``a``, gravity): each run is a fresh Python process (imports
included) with its own cache folder, first empty (cold), then as the first run left it
(warm).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile

__all__ = ["described_system_times", "SCRIPT"]

#: The process each run is (prints its stage times as JSON on the last line).
SCRIPT = r"""
import json, time
t0 = time.perf_counter()
import chaplygin
top = chaplygin.RollingSystem("bench_chaplygin_top", inertia=("0.4", "0.5", "0.6"), mass=1,
                              radius=1, centre_of_mass=(0, 0, "a"), gravity=1)
chaplygin.register_system(top)
chaplygin.build_model("bench_chaplygin_top")
t1 = time.perf_counter()
found = chaplygin.discover(top, degree=2, coefficient_degree=2, momentum="omega",
                           in_parameters=True, densities=True)
t2 = time.perf_counter()
state = {"M": (0.3, -0.2, 0.9), "gamma": (0.28, 0.3, "sqrt(1 - 0.28**2 - 0.3**2)")}
chaplygin.integrate("bench_chaplygin_top", state, 1, {"a": 0.2})
t3 = time.perf_counter()
print(json.dumps({"equations": t1 - t0, "discovery and proofs": t2 - t1,
                  "code, compilation and a first run": t3 - t2, "total": t3 - t0,
                  "integrals found": len(found.search.integrals),
                  "all proved": found.all_proved}))
"""


def described_system_times() -> dict[str, dict]:
    """Run :data:`SCRIPT` cold and warm; the seconds of each stage.

    Returns
    -------
    dict
        ``{"cold": {...}, "warm": {...}}``, each the stage times in seconds (the whole
        process, imports included, in ``total``), or ``{"error": message}``.
    """
    out: dict[str, dict] = {}
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "CHAPLYGIN_CACHE_DIR": cache}
        for run in ("cold", "warm"):
            done = subprocess.run(
                [sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env,
                timeout=1800,
            )  # fmt: skip
            if done.returncode != 0:
                out[run] = {"error": (done.stderr.strip().splitlines() or ["failed"])[-1][:200]}
                continue
            out[run] = json.loads(done.stdout.strip().splitlines()[-1])
    return out
