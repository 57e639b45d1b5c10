"""Shared fixtures: fresh mpmath precision for every test; the ``quick`` marker.

``pytest -m quick`` is the developers' quick loop (about a minute with a warm model cache):
the tests a module marks ``quick`` itself, and every test of :data:`QUICK_MODULES` that is
not marked ``slow`` or ``benchmark``. The default run (``pytest``) runs everything.
"""

from __future__ import annotations

import mpmath
import pytest

#: Test modules whose tests (except the ``slow`` ones) are all in the quick loop: unit tests
#: of one layer that need no compiler run, no subprocess and no long integration.
QUICK_MODULES = frozenset(
    {
        "test_constrained_ball",
        "test_coverage",
        "test_docs",
        "test_effects",
        "test_engine",
        "test_hamiltonisation",
        "test_identity",
        "test_integrate",
        "test_propagator",
        "test_model_cache",
        "test_rotation_number",
        "test_transformation",
    }
)


#: The modules of at least 20 s of test time, longest first, with their seconds: setup, call
#: and teardown summed from the ``--durations=0`` run of the whole suite of 2026-11-26
#: (``-n 2``, 2-core machine, load ~4, so about 1.5x a quiet machine's; 1312 s wall, 2546 s
#: of test time). test_described_systems.py took 486 s there; its Kane cross-checks have
#: moved since to the two test_described_kane_* modules, whose rows sum their tests' seconds
#: of that run. Under pytest-xdist (``--dist loadfile``
#: in pyproject: a module runs in one worker, so its module fixtures and in-process caches
#: are made once) they are handed out first, longest first, so that no long module starts
#: last and keeps one core busy alone at the end.
SLOW_MODULES_FIRST = (
    "tests/derive/test_convex_sphere_trace.py",  # 121 (CI 24: two support-surface first uses)
    "tests/derive/test_convex_moving.py",  # 250 beside another job; ~80 idle (FLINT builder)
    "tests/derive/test_sphere_trace.py",  # 75 (CI 24: it ran last)
    "tests/verify/test_claims.py",  # 241
    "tests/verify/test_sweep.py",  # 227
    "tests/verify/test_described_kane_supports.py",  # 211
    "tests/numerics/test_determinism.py",  # 151
    "tests/verify/test_described_kane_bodies.py",  # 145
    "tests/verify/test_described_kane_convex.py",  # 140 beside another job
    "tests/derive/test_codegen.py",  # 136
    "tests/verify/test_described_systems.py",  # 129
    "tests/numerics/test_first_use.py",  # 100
    "tests/arith/test_detmath.py",  # 92
    "tests/verify/scene/test_scene_examples.py",  # 91
    "tests/verify/test_hostile_cache.py",  # 81
    "tests/derive/test_m03.py",  # 69
    "tests/verify/test_report.py",  # 67
    "tests/verify/test_layers.py",  # 50
    "tests/verify/test_hostile_sweep.py",  # 46
    "tests/verify/test_hostile_cli.py",  # 45
    "tests/derive/test_builtin_descriptions.py",  # 40 beside another job
    "tests/numerics/test_taylor_mpfr.py",  # 37
    "tests/derive/test_description.py",  # 37
    "tests/verify/scene/test_scene_diagram.py",  # 37
    "tests/derive/test_bm20.py",  # 36
    "tests/verify/test_cache_faults.py",  # 32
    "tests/derive/test_rolling_system.py",  # 29
    "tests/derive/test_densities.py",  # 28
    "tests/verify/test_verify_pool.py",  # 27
    "tests/derive/test_support.py",  # 26
    "tests/verify/test_hostile_scenes.py",  # 25
    "tests/numerics/ball/test_bifurcation.py",  # 24
    "tests/verify/scene/test_periodic_output.py",  # 23
    "tests/numerics/test_input_precision.py",  # 23
)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark the tests of :data:`QUICK_MODULES` ``quick`` (not the slow ones); in an xdist
    worker, put the modules of :data:`SLOW_MODULES_FIRST` first (every worker sorts alike)."""
    if hasattr(config, "workerinput"):
        rank = {name: i for i, name in enumerate(SLOW_MODULES_FIRST)}
        root = config.rootpath

        def module_rank(item: pytest.Item) -> int:
            try:
                name = item.path.relative_to(root).as_posix()
            except ValueError:
                return len(rank)
            return rank.get(name, len(rank))

        items.sort(key=module_rank)  # stable: the collection order within a rank
    for item in items:
        if item.path.stem not in QUICK_MODULES:
            continue
        if item.get_closest_marker("slow") or item.get_closest_marker("benchmark"):
            continue
        item.add_marker(pytest.mark.quick)


@pytest.fixture(autouse=True)
def _reset_mpmath_precision():
    """Every test starts (and ends) at mpmath's default 53-bit precision."""
    mpmath.mp.prec = 53
    yield
    mpmath.mp.prec = 53


def pytest_terminal_summary(terminalreporter, exitstatus, config) -> None:
    """The hostile suites' tally (issue 25): cases per surface and each failure's count."""
    import sys

    hostile = sys.modules.get("hostile")
    if hostile is None or not hostile.TALLY:
        return
    terminalreporter.section("hostile cases (this process)")
    for surface, tally in sorted(hostile.TALLY.items()):
        failures = ", ".join(f"{tally[name]} {name}" for name in hostile.FAILURES)
        terminalreporter.write_line(f"{surface}: {tally['cases']} cases; {failures}")


@pytest.fixture
def chunk_steps(monkeypatch):
    """``chunk_steps(arithmetic, n)``: the compiled Taylor loop of that arithmetic runs in
    blocks of ``n`` steps under a wall-time limit (its row of ARITHMETICS, for this test)."""
    import dataclasses

    from chaplygin.numerics.precision import ARITHMETICS

    def set_steps(name: str, steps: int) -> None:
        monkeypatch.setitem(
            ARITHMETICS, name, dataclasses.replace(ARITHMETICS[name], chunk_steps=steps)
        )

    return set_steps
