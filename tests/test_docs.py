"""Docstring examples run (numpydoc ``Examples`` sections)."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = [
    "chaplygin.derive.chaplygin_ball",
    "chaplygin.derive.emit.functions",
    "chaplygin.numerics.integrate",
    "chaplygin.numerics.quadratures",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0
    assert result.failed == 0
