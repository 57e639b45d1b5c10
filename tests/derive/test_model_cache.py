"""Derived models are cached on disk: a cached model is the derivation, byte for byte."""

from __future__ import annotations

import pickle
from pathlib import Path

import pytest
from chaplygin.derive import model_store, systems
from chaplygin.verify.claims import REGISTRY, select_claims
from chaplygin.verify.verdict import check_claim


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("CHAPLYGIN_MODEL_CACHE", raising=False)
    monkeypatch.setattr(systems, "_CACHE", {})
    monkeypatch.setattr(model_store, "_DESCRIBED", {})
    return tmp_path / "models"


def test_a_cached_model_is_the_derivation(fresh_cache):
    derived = systems.build_model("chaplygin_ball", ["gyrostat"])
    (stored,) = fresh_cache.glob("chaplygin_ball__gyrostat-*.pickle")
    systems._CACHE.clear()
    loaded = systems.build_model("chaplygin_ball", ["gyrostat"])
    assert loaded is not derived
    assert loaded.canonical_text() == derived.canonical_text()
    assert loaded.reparametrisation == derived.reparametrisation
    assert type(loaded.details) is type(derived.details)
    assert stored.stat().st_size > 0
    # the verifier reaches the same verdicts with the cached model
    select_claims()
    for claim_id in ("K01-4.2.n", "K01-4.2m", "K01-4.4/control-muK"):
        assert check_claim(REGISTRY[claim_id]).ok


def test_a_described_systems_model_is_cached_by_its_fingerprint(fresh_cache):
    """``RollingSystem.model()``: derived once, stored signed, loaded by the next process as
    the derivation; another number or another effect is another entry; an effect the
    description does not take raises and stores nothing."""
    from chaplygin.derive.errors import UserInputError
    from chaplygin.derive.rolling_system import RollingSystem

    fields = dict(inertia=[["3/7", "1/17", 0], ["1/17", "5/9", 0], [0, 0, "8/11"]],
                  mass="13/10", radius="7/10", centre_of_mass=("1/9", 0, "-2/13"),
                  gravity="49/5")  # fmt: skip
    body = RollingSystem("offset_heavy_ball", **fields)
    derived = body.model()
    assert body.model() is derived  # memoised in the process
    (stored,) = fresh_cache.glob("described-*.pickle")
    model_store._DESCRIBED.clear()
    loaded = body.model()
    assert loaded is not derived and loaded.canonical_text() == derived.canonical_text()
    assert body.derive().canonical_text() == loaded.canonical_text()
    other = RollingSystem("offset_heavy_ball", **{**fields, "gravity": "49/6"}).model()
    assert other.canonical_text() != loaded.canonical_text()
    body.model(["contact_point"])
    assert len(list(fresh_cache.glob("described-*.pickle"))) == 3 and stored.exists()
    with pytest.raises(UserInputError):
        body.model(["no_such_effect"])
    assert len(list(fresh_cache.glob("described-*.pickle"))) == 3



def test_the_n_ball_models_are_kept_on_disk_as_derived(fresh_cache, monkeypatch):
    """The multi-body derivation of a body on N balls (4 s each, nine of them in every run
    of the verifier) is kept in the model cache: the next process loads the derivation (the
    same canonical text and support tensor, no derivation run: counted), another seed or
    number of balls or effect is another file, and bad directions raise and store nothing."""
    from chaplygin.derive import spherical_support
    from chaplygin.derive.errors import UserInputError

    formed = []
    real = spherical_support.form_model
    monkeypatch.setattr(spherical_support, "form_model", lambda d: formed.append(1) or real(d))
    derived = spherical_support.n_ball_model(2, (), space_directions=2102)
    (stored,) = fresh_cache.glob("n-ball-*.pickle")
    loaded = spherical_support.n_ball_model(2, (), space_directions=2102)
    assert len(formed) == 1 and loaded is not derived
    assert loaded.canonical_text() == derived.canonical_text()
    assert loaded.details.support_tensor == derived.details.support_tensor
    spherical_support.n_ball_model(2, (), space_directions=2103)
    spherical_support.n_ball_model(1, (), space_directions=2102)
    assert len(formed) == 3 and len(list(fresh_cache.glob("n-ball-*.pickle"))) == 3
    with pytest.raises(UserInputError):
        spherical_support.n_ball_model(2, (), space_directions=[(1, 0, 0)])
    assert len(list(fresh_cache.glob("n-ball-*.pickle"))) == 3 and stored.exists()

#: One change of each field that changes the derived model (the base: a heavy offset ball
#: with a rotor on a plane, rolling).
_CHANGES = {
    "name": "other_name", "mass": "11/10", "radius": "3/5", "centre_of_mass": (0, "1/7", 0),
    "gravity": "49/6", "gyrostat": (0, 0, "1/4"), "potential": "gamma3**2/7",
    "contact": "rubber", "support": "sphere", "positive": ("k",),
    "inertia": [["3/7", 0, 0], [0, "5/9", 0], [0, 0, "8/11"]],
}  # fmt: skip


def test_every_field_that_changes_the_model_changes_the_fingerprint():
    """The fingerprint keys the caches and tells registrations apart: a change of any field
    the derivation reads gives another one (gravity was once left out, and a description
    with another gravity loaded the cached model of the first); the same numbers written
    otherwise give the same one."""
    from chaplygin.derive.rolling_system import RollingSystem

    base = dict(inertia=[["3/7", "1/17", 0], ["1/17", "5/9", 0], [0, 0, "8/11"]],
                mass="13/10", radius="7/10", centre_of_mass=("1/9", 0, "-2/13"),
                gravity="49/5", gyrostat=(0, 0, "k"))  # fmt: skip
    first = RollingSystem("heavy", **base).fingerprint()
    same = {**base, "mass": "1.3", "gravity": "9.8"}
    assert RollingSystem("heavy", **same).fingerprint() == first
    for field, value in _CHANGES.items():
        changed = {**base, field: value}
        if field == "support":
            changed["support_radius"] = 5
        name = changed.pop("name", "heavy")
        assert RollingSystem(name, **changed).fingerprint() != first, field


#: Descriptions of the other supports and bodies, and a change of each field they use
#: (the fields ``_CHANGES`` changes on the heavy ball are not repeated).
_OTHER_BODIES = [
    (dict(inertia=(1, 2, 3), radius="7/10", support="sphere", support_radius=5),
     {"support_radius": "11/2", "side": "inside"}),
    (dict(inertia=(1, 2, 3), radius="7/10", support="rotating_plane", rotation_rate="5/3"),
     {"rotation_rate": "5/3*cos(t)"}),
    (dict(inertia=(1, 2, 3), radius="7/10", support="moving_plane", plane_velocity=("V1", "V2")),
     {"plane_velocity": ("V1", "2*V2")}),
    (dict(inertia=("A", "A", "C"), surface="x1**2 + x2**2 + x3**2 - b**2", support="surface",
          support_surface="p1**2 + p2**2 + p3**2 - 9"),
     {"support_surface": "p1**2 + p2**2/4 + p3**2 - 9",
      "surface": "x1**2 + x2**2/2 + x3**2 - b**2"}),
    (dict(inertia=("A", "A", "A"), mass="m", radius="R", gravity="g", support="surface",
          centre_surface="x1**2 + x2**2 + x3**2 - (R + S)**2"),
     {"centre_surface": "x1**2 + x2**2 + x3**2/2 - (R + S)**2"}),
    (dict(inertia=("I1", "I2", "I3"), support="balls",
          balls=[{"moment": "3/7", "ratio": "5/11", "direction": (2, 3, 6)},
                 {"moment": "4/13", "ratio": "2/3", "direction": (3, -6, 2)}]),
     {"balls": [{"moment": "3/7", "ratio": "5/11", "direction": (2, 3, 6)},
                {"moment": "4/13", "ratio": "3/5", "direction": (3, -6, 2)}]}),
]  # fmt: skip


def test_every_field_of_every_support_reaches_the_fingerprint():
    """Every field of a description but its prose changes the fingerprint on a support that
    uses it, so a field added to RollingSystem fails here until the fingerprint reads it
    (or it is added to the prose). The description's prose alone leaves it unchanged."""
    import dataclasses

    from chaplygin.derive.rolling_system import RollingSystem

    covered = set(_CHANGES)
    for base, changes in _OTHER_BODIES:
        first = RollingSystem("other", **base).fingerprint()
        for field, value in changes.items():
            assert RollingSystem("other", **{**base, field: value}).fingerprint() != first, field
            covered.add(field)
        prose = RollingSystem("other", description="a note", **base).fingerprint()
        assert prose == first
    prose_only = {"description", "_parsed"}  # the note, and the parsed cache
    assert covered | prose_only == {f.name for f in dataclasses.fields(RollingSystem)}


def test_a_described_system_with_another_gravity_is_not_served_the_cached_model(fresh_cache):
    """Two processes register the same name with other gravities: the second builds its
    own model, not the first's from the disk cache."""
    from chaplygin.derive.rolling_system import RollingSystem

    fields = dict(inertia=[[1, 0, 0], [0, 2, 0], [0, 0, 3]], centre_of_mass=(0, 0, "1/5"))
    for g in ("49/5", "49/6"):
        description = RollingSystem("moonball", gravity=g, **fields)
        systems.register_system(description)
        try:
            built = systems.build_model("moonball")
        finally:
            systems.SYSTEMS.pop("moonball")  # (the next process)
            systems._CACHE.clear()
        assert built.canonical_text() == description.derive().canonical_text(), g


def test_samplers_survive_the_cache(fresh_cache):
    """Models whose phase space has its own exact sampler (picklable partials)."""
    systems.build_model("ball_on_surface")
    systems._CACHE.clear()
    model = systems.build_model("ball_on_surface")
    import random

    point: dict = {}
    model.sampler(random.Random(1), point)
    b = [point[s] for s in model.param_group("b")]
    x = [point[s] for s in model.group("x")] if "x" in model.vectors else None
    assert all(v > 0 for v in b)
    if x is not None:
        assert sum(xi**2 / bi for xi, bi in zip(x, b, strict=True)) == 1


def test_a_damaged_cache_file_is_derived_again(fresh_cache):
    systems.build_model("chaplygin_ball")
    (stored,) = fresh_cache.glob("chaplygin_ball-*.pickle")
    stored.write_bytes(b"not a pickle")
    systems._CACHE.clear()
    model = systems.build_model("chaplygin_ball")
    assert model.name == "chaplygin_ball"
    assert isinstance(systems._load_cached(stored), type(model))  # rewritten, signed


def test_an_edit_of_the_derivation_changes_the_key(fresh_cache, monkeypatch):
    before = systems._cache_file("chaplygin_ball", frozenset())
    monkeypatch.setattr(systems, "_derivation_digest", lambda: "edited sources")
    assert systems._cache_file("chaplygin_ball", frozenset()) != before


def test_the_cache_can_be_switched_off(fresh_cache, monkeypatch):
    monkeypatch.setenv("CHAPLYGIN_MODEL_CACHE", "0")
    systems.build_model("chaplygin_ball")
    assert not fresh_cache.exists()


# ------------------------------------------------------------------ what is loaded (issue 11)
class _Payload:
    """Unpickling this runs code: it must never happen for a file we did not write."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (open, (str(self.marker), "w"))  # creates the marker file when unpickled


def test_a_planted_pickle_is_never_unpickled(fresh_cache, tmp_path):

    path = systems._cache_file("chaplygin_ball", frozenset())
    path.parent.mkdir(parents=True, exist_ok=True)
    marker = tmp_path / "ran"
    path.write_bytes(pickle.dumps(_Payload(marker)))  # a foreign file, no signature
    model = systems.build_model("chaplygin_ball")
    assert not marker.exists()  # never unpickled
    assert model.name == "chaplygin_ball" and systems._load_cached(path) is not None
    # the same payload behind a forged header and a wrong tag: refused as well
    path.write_bytes(b"chaplygin-model-1\n" + b"0" * 64 + b"\n" + pickle.dumps(_Payload(marker)))
    assert systems._load_cached(path) is None and not marker.exists()


def test_a_models_folder_others_can_write_is_refused(fresh_cache):
    from chaplygin.derive.errors import CacheError

    path = systems._cache_file("chaplygin_ball", frozenset())
    path.parent.mkdir(parents=True, exist_ok=True)
    systems._store(path, systems.build_model("chaplygin_ball", disk_cache=False))
    path.parent.chmod(0o777)
    with pytest.raises(CacheError, match="can be written by other users"):
        systems._load_cached(path)


def test_xdg_cache_home_is_honoured(tmp_path, monkeypatch):
    monkeypatch.delenv("CHAPLYGIN_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert systems.model_cache_dir() == tmp_path / "xdg" / "chaplygin" / "models"


def test_the_cache_root_is_the_platforms_user_cache_folder(tmp_path, monkeypatch):
    """The root comes from platformdirs (issue 28, 8), so it is the platform's own folder:
    here platformdirs answering as on macOS (``~/Library/Caches/chaplygin``, not
    ``~/.cache``); ``CHAPLYGIN_CACHE_DIR`` and an explicit folder still come first."""
    import platformdirs
    import platformdirs.macos
    from chaplygin.derive.cachefiles import cache_root

    def as_on_macos(appname=None, appauthor=None, *args, **kwargs):
        return platformdirs.macos.MacOS(appname, appauthor, *args, **kwargs).user_cache_dir

    monkeypatch.delenv("CHAPLYGIN_CACHE_DIR", raising=False)
    monkeypatch.setattr(platformdirs, "user_cache_dir", as_on_macos)
    assert cache_root() == Path.home() / "Library" / "Caches" / "chaplygin"
    assert systems.model_cache_dir() == cache_root() / "models"
    monkeypatch.setenv("CHAPLYGIN_CACHE_DIR", str(tmp_path / "mine"))
    assert cache_root() == tmp_path / "mine"
    assert cache_root(tmp_path / "arg") == tmp_path / "arg"


def test_what_is_derived_later_is_stored_for_the_next_process(fresh_cache):
    """store_derived: the Jacobian derived after the model was cached goes into the cache
    file, and the next load has it without deriving it, equal to a fresh derivation; a model
    that build_model did not return is not written."""
    model = systems.build_model("chaplygin_ball", ["gyrostat"])
    assert "jacobian_expanded" not in vars(model)
    J = model.jacobian_expanded
    assert systems.store_derived(model)
    systems._CACHE.clear()
    loaded = systems.build_model("chaplygin_ball", ["gyrostat"])
    assert loaded is not model and "jacobian_expanded" in vars(loaded)
    assert loaded.jacobian_expanded == J
    # the control: a model not from build_model is refused; the cache keeps the loaded one
    assert not systems.store_derived(pickle.loads(pickle.dumps(loaded)))
    systems._CACHE.clear()
    again = systems.build_model("chaplygin_ball", ["gyrostat"])
    fresh = systems.get_system("chaplygin_ball").builder(frozenset({"gyrostat"}))
    assert again.jacobian_expanded == fresh.jacobian_expanded
