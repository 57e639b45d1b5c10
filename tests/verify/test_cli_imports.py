"""``chaplygin --help``, ``--version`` and ``chaplygin <command> --help`` load no heavy module.

Answering them is building the parser: every command module is imported for its arguments,
and the work (sympy, numpy, scipy, matplotlib, Dask, xarray, zarr, the numerics) is imported
only when a command runs. Issue 26 asks for ``--help`` in at most 0.5 s; that time depends on
the machine, the modules loaded do not, so this is what is tested (the time is measured in
the benchmarks, never here): each invocation runs in a fresh interpreter, which then lists
``sys.modules``.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from chaplygin.verify import cli, integrate_cmd

#: What the probe runs: ``main(argv)``, then the names of the loaded modules as JSON.
_PROBE = """
import json, sys
{preload}
from chaplygin.verify.cli import main
code = main({argv!r})
print(json.dumps({{"code": code, "modules": sorted(sys.modules)}}), file=sys.stderr)
"""

#: Named in issue 26 (and what loading them costs): none may be loaded by ``--help``.
HEAVY = ("numpy", "scipy", "sympy", "mpmath", "matplotlib", "dask", "distributed", "xarray",
         "zarr", "pandas")

#: Of the package, ``--help`` may load the commands (chaplygin.verify) and the exceptions they
#: raise (chaplygin.derive.errors, with its lazily resolving package): nothing of the
#: symbolic layer's work, the generated code or the numerics.
ALLOWED_OF_THE_PACKAGE = ("chaplygin", "chaplygin.verify", "chaplygin.derive",
                          "chaplygin.derive.errors")


def _commands() -> list[str]:
    sub = next(a for a in cli.build_parser()._actions if a.dest == "command")
    return list(sub.choices)


def _loaded(argv: list[str], preload: str = "") -> tuple[int, set[str]]:
    """Exit status of ``chaplygin argv`` and the modules it loaded beyond a bare interpreter."""
    def run(code: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              timeout=120)

    bare = run("import json, sys; print(json.dumps(sorted(sys.modules)), file=sys.stderr)")
    done = run(_PROBE.format(preload=preload, argv=argv))
    assert done.stdout.strip(), "no help text printed"
    report = json.loads(done.stderr.strip().splitlines()[-1])
    return report["code"], set(report["modules"]) - set(json.loads(bare.stderr))


def _too_heavy(modules: set[str]) -> list[str]:
    """The modules of ``modules`` that answering ``--help`` must not load: any outside the
    standard library and chaplygin, and of chaplygin any but :data:`ALLOWED_OF_THE_PACKAGE`
    and the command modules."""
    out = []
    for name in modules:
        top = name.partition(".")[0]
        if top == "chaplygin":
            if name not in ALLOWED_OF_THE_PACKAGE and not name.startswith("chaplygin.verify."):
                out.append(name)
        elif top in HEAVY or top not in sys.stdlib_module_names:
            out.append(name)
    return sorted(out)


def test_every_command_is_probed():
    assert {"verify", "run", "integrate", "sweep", "discover"} <= set(_commands())


@pytest.mark.parametrize(
    "argv",
    [["--help"], ["--version"], *([c, "--help"] for c in _commands())],
    ids=lambda argv: " ".join(argv),
)
def test_help_and_version_load_no_heavy_module(argv):
    code, modules = _loaded(argv)
    assert code == 0
    found = _too_heavy(modules)
    packages = sorted({".".join(n.split(".")[: 2 if n.startswith("chaplygin.") else 1])
                       for n in found})
    assert found == [], f"chaplygin {' '.join(argv)} loads {', '.join(packages)}"
    assert "chaplygin.verify.cli" in modules  # (a control: the probe saw the command line)


def test_the_probe_sees_a_heavy_import():
    # the same probe and the same rule, with the module integrate runs on loaded first: the
    # numerics and numpy are reported (the rule is not blind to them)
    code, modules = _loaded(["integrate", "--help"], preload="import chaplygin.numerics")
    assert code == 0
    found = _too_heavy(modules)
    assert "numpy" in found and "chaplygin.numerics" in found and "sympy" in found


def test_the_default_step_budget_is_the_numerics_one():
    # written out in the command so that its parser loads no numerics
    from chaplygin.numerics.step_budget import DEFAULT_MAX_STEPS

    assert integrate_cmd.DEFAULT_MAX_STEPS == DEFAULT_MAX_STEPS
