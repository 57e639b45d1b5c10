"""Effects: an effect that is off leaves no term, state or parameter in generated code."""

from __future__ import annotations

import re

import pytest
from chaplygin.derive import UserInputError, build_model
from chaplygin.derive.emit import CEmitter, NumpyEmitter
from chaplygin.numerics import load_model_code


def _source(effects):
    model = build_model("chaplygin_ball", effects)
    ((_, np_src),) = NumpyEmitter().emit(model)
    ((_, c_src),) = CEmitter().emit(model)
    return model, np_src, c_src


@pytest.mark.parametrize(
    ("effect", "names"),
    [("gyrostat", ["K1", "K2", "K3"]), ("contact_point", ["alpha1", "beta3", "x", "y", "b"])],
)
def test_effect_off_leaves_nothing_behind(effect, names):
    model_off, np_off, c_off = _source(())
    model_on, np_on, c_on = _source([effect])
    for name in names:
        word = re.compile(rf"\b{re.escape(name)}\b")
        assert name not in model_off.state_names + model_off.param_names
        assert name in model_on.state_names + model_on.param_names
        # the C code names states s_<name> and parameters p_<name>; its header lists them
        header_off = [ln for ln in c_off.splitlines() if ln.startswith(("state:", "parameters:"))]
        header_on = [ln for ln in c_on.splitlines() if ln.startswith(("state:", "parameters:"))]
        assert not re.search(rf"\b[sp]_{re.escape(name)}\b", c_off)
        assert not any(word.search(ln) for ln in header_off)
        assert any(word.search(ln) for ln in header_on)
        # the numpy functions unpack exactly the model's states and parameters
        unpack_off = [ln for ln in np_off.splitlines() if ln.endswith((" = y", " = p"))]
        unpack_on = [ln for ln in np_on.splitlines() if ln.endswith((" = y", " = p"))]
        assert not any(word.search(ln.rsplit("=", 1)[0]) for ln in unpack_off)
        assert any(word.search(ln.rsplit("=", 1)[0]) for ln in unpack_on)


def test_gyrostat_enters_the_equations():
    model = build_model("chaplygin_ball", ["gyrostat"])
    K = set(model.param_group("K"))
    assert any(K & e.free_symbols for e in model.rhs[:3])


def test_unknown_effect_lists_valid_ones():
    with pytest.raises(UserInputError, match="contact_point, gyrostat"):
        build_model("chaplygin_ball", ["magnetic"])
    with pytest.raises(UserInputError, match="valid systems"):
        load_model_code("rubber_ball")
