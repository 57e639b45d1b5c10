"""Shared fixtures: fresh mpmath precision for every test, the reference problem."""

from __future__ import annotations

import mpmath
import pytest


@pytest.fixture(autouse=True)
def _reset_mpmath_precision():
    """Every test starts (and ends) at mpmath's default 53-bit precision."""
    mpmath.mp.prec = 53
    yield
    mpmath.mp.prec = 53
