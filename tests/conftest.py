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


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark the tests of :data:`QUICK_MODULES` ``quick`` (not the slow ones)."""
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
