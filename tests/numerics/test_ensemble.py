"""Many orbits in one call (numerics/ensemble.py): every orbit is integrate()'s result for it,
bit for bit, whatever the number of threads (the Taylor orbits in vector lanes); states,
parameter sets or both per orbit; quad orbits keep their precision; a failing orbit fails
alone; bad input names the orbit and runs nothing."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from chaplygin.derive.errors import UserInputError
from chaplygin.numerics import ensemble
from chaplygin.numerics.ensemble import integrate_many
from chaplygin.numerics.integrate import integrate

PARAMS = {"I": ("1.13", "2.07", "3.31"), "D": "0.93"}


def _states(count: int, seed: int = 3) -> list[dict]:
    """Generic (non-dyadic) states on |gamma| = 1."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        g = rng.normal(size=3)
        g /= np.linalg.norm(g)
        out.append({"M": tuple(rng.uniform(-0.9, 0.9, 3)), "gamma": tuple(g)})
    return out


def _same(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and bool(np.all(a == b))


@pytest.mark.parametrize("threads", [1, 2])
def test_every_orbit_is_integrates_result_bit_for_bit(threads):
    """Five states, one parameter set, the Taylor method in double: each orbit's outputs,
    drift and steps equal integrate()'s for that state alone, with 1 and 2 threads."""
    states = _states(5)
    r = integrate_many("chaplygin_ball", states, 7.3, PARAMS, rtol=1e-12, atol=1e-12,
                       threads=threads)  # fmt: skip
    assert r.threads == threads and len(r) == 5 and r.success.all()
    for j, s in enumerate(states):
        one = integrate("chaplygin_ball", s, 7.3, PARAMS, rtol=1e-12, atol=1e-12)
        assert _same(r.y[j], one.y) and _same(r.t, one.t)
        assert r.drift["H"][j] == one.drift["H"] and r.nsteps[j] == one.nsteps
        assert r.results[j].drift == one.drift
    assert r.drift["H"].max() < 1e4 * 1e-12  # the evidence is there (and small)
    assert len({float(v) for v in r.y[:, 0, -1]}) == 5  # five different orbits


def test_one_state_many_parameter_sets_and_a_failing_orbit():
    """One state, four bodies (per-orbit parameter sets): every orbit is integrate()'s result
    for its body. Then a step limit that the three slow bodies stay within and the fast one
    (inertia a twentieth: it turns twenty times faster and needs more steps) exceeds: that
    orbit fails alone, with its status and message, and the others do not change a bit."""
    state = _states(1, seed=8)[0]
    sets = [{"I": ("1.13", "2.07", "3.31"), "D": d} for d in ("0.93", "1.7", "0.41")]
    sets.append({"I": ("0.0565", "0.1035", "0.1655"), "D": "0.0465"})
    r = integrate_many("chaplygin_ball", state, 3.1, sets, rtol=1e-11, atol=1e-11)
    assert r.success.all()
    for j, p in enumerate(sets):
        one = integrate("chaplygin_ball", state, 3.1, p, rtol=1e-11, atol=1e-11)
        assert _same(r.y[j], one.y)
    assert not _same(r.y[0], r.y[1])
    slow = int(max(r.nsteps[:3]))
    assert r.nsteps[3] > slow
    limited = integrate_many("chaplygin_ball", state, 3.1, sets, rtol=1e-11, atol=1e-11,
                             max_steps=slow)  # fmt: skip
    assert limited.status.tolist()[:3] == [0, 0, 0] and limited.status[3] != 0
    assert "max_steps" in limited.messages[3]
    assert np.isnan(limited.y[3][:, -1]).all()
    for j in range(3):
        assert _same(limited.y[j], r.y[j])


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_the_taylor_orbits_run_in_vector_lanes_bit_for_bit(threads, monkeypatch):
    """Eleven orbits (not a multiple of the four lanes), each with its own state and body,
    in the lanes driver (whose blocks follow the threads): every orbit's result is
    integrate()'s -- outputs, status, steps, orders in the message, drift (the ensemble's
    arrays, computed for all orbits with their own parameters at once, too)."""
    used = []
    lanes = ensemble.run_lanes
    monkeypatch.setattr(ensemble, "run_lanes", lambda *a: used.append(a[2]) or lanes(*a))
    states = _states(11, seed=11)
    rng = np.random.default_rng(4)
    sets = [{"I": tuple(rng.uniform(1.0, 3.0, 3)), "D": rng.uniform(0.5, 1.5)} for _ in states]
    r = integrate_many("chaplygin_ball", states, 4.2, sets, rtol=1e-12, atol=1e-12,
                       threads=threads)  # fmt: skip
    assert used == [threads] and r.success.all()
    for j, s in enumerate(states):
        one = integrate("chaplygin_ball", s, 4.2, sets[j], rtol=1e-12, atol=1e-12)
        got = r.results[j]
        assert _same(got.y, one.y) and _same(got.t, one.t) and got.status == one.status
        assert got.message == one.message and got.nsteps == one.nsteps
        assert got.drift == one.drift and got.backend == one.backend
        assert {n: r.drift[n][j] for n in r.drift} == one.drift and r.status[j] == one.status
    assert len({float(v) for v in r.y[:, 0, -1]}) == 11


def test_quad_orbits_keep_their_precision():
    """precision = "quad": the orbits run one after another (threads ignored) and each is
    integrate()'s quad result; the outputs are mpf at 34 digits, not doubles."""
    states = _states(2, seed=5)
    r = integrate_many("chaplygin_ball", states, 1.7, PARAMS, precision="quad", threads=2)
    assert r.threads == 1 and r.y.dtype == object
    one = integrate("chaplygin_ball", states[1], 1.7, PARAMS, precision="quad")
    assert all(a == b for a, b in zip(r.y[1].ravel(), one.y.ravel(), strict=True))
    assert isinstance(r.y[1, 0, -1], mpmath.mpf)


def test_scipy_orbits_share_eleven_output_times():
    """A method whose own output is every step gets the 11 times of the Taylor method, so
    that the orbits share them; the last is the end of the span exactly."""
    r = integrate_many("chaplygin_ball", _states(3), (0.25, 2.5), PARAMS, method="DOP853")
    assert r.success.all() and len(r.t) == 11 and r.t[0] == 0.25 and r.t[-1] == 2.5
    assert r.y.shape == (3, 6, 11)


def test_bad_input_names_the_orbit_and_runs_nothing(monkeypatch):
    """A bad state among good ones: UserInputError naming its index, raised before any orbit
    is integrated; mismatched rows and a bad thread count are refused too."""
    ran = []
    monkeypatch.setattr(ensemble, "_collect", lambda *a, **k: ran.append(1))
    states = _states(3)
    states[2] = {"M": (0.1, 0.2, 0.3), "gamma": (0.0, 0.0, 2.0)}  # |gamma| != 1
    with pytest.raises(UserInputError, match="orbit 2"):
        integrate_many("chaplygin_ball", states, 1.0, PARAMS)
    with pytest.raises(UserInputError, match="rows"):
        integrate_many("chaplygin_ball", _states(3), 1.0, [PARAMS, PARAMS])
    with pytest.raises(UserInputError, match="threads"):
        integrate_many("chaplygin_ball", _states(2), 1.0, PARAMS, threads=0)
    with pytest.raises(UserInputError):
        integrate_many("chaplygin_ball", [], 1.0, PARAMS)
    assert not ran


def test_states_as_arrays_are_read_at_once_and_give_integrate_s_results(monkeypatch):
    """Eight states as a float array and eight parameter rows (numbers): the starts are read
    at once (the per-orbit route runs for none of them: counted), and every orbit is
    integrate()'s result for its row, bit for bit. A row off |gamma| = 1 by 0.3 of the
    tolerance is renormalised as integrate renormalises it (the same bits); a row off by 1e-3
    goes to integrate's own route and is refused with its index, as integrate refuses it."""
    import importlib

    from chaplygin.numerics.inputs import UNIT_TOLERANCE

    integrate_module = importlib.import_module("chaplygin.numerics.integrate")

    rng = np.random.default_rng(11)
    G = rng.normal(size=(8, 3))
    G /= np.linalg.norm(G, axis=1)[:, None]
    Y = np.hstack([rng.uniform(-0.9, 0.9, (8, 3)), G])
    P = np.column_stack([rng.uniform(1.0, 1.2, 8), rng.uniform(2.0, 2.2, 8),
                         rng.uniform(3.1, 3.4, 8), rng.uniform(0.8, 1.1, 8)])  # fmt: skip
    calls = []
    real = integrate_module.prepare_problem
    monkeypatch.setattr(ensemble, "prepare_problem",
                        lambda *a, **k: calls.append(1) or real(*a, **k))  # fmt: skip
    r = integrate_many("chaplygin_ball", Y, 4.1, P, rtol=1e-12, atol=1e-12)
    assert len(calls) == 1  # the first orbit only
    assert r.success.all()
    for j in range(8):
        one = integrate("chaplygin_ball", Y[j], 4.1, P[j], rtol=1e-12, atol=1e-12)
        assert _same(r.y[j], one.y) and r.results[j].drift == one.drift
        assert r.nsteps[j] == one.nsteps
    Y[5, 3:] *= 1 + 0.3 * UNIT_TOLERANCE  # off |gamma| = 1 within the tolerance: renormalised
    calls.clear()
    r = integrate_many("chaplygin_ball", Y, 4.1, P, rtol=1e-12, atol=1e-12)
    assert len(calls) == 1 and r.success.all()
    one = integrate("chaplygin_ball", Y[5], 4.1, P[5], rtol=1e-12, atol=1e-12)
    assert _same(r.y[5], one.y)
    Y[6, 3:] *= 1 + 1e-3
    with pytest.raises(UserInputError, match="orbit 6"):
        integrate_many("chaplygin_ball", Y, 4.1, P, rtol=1e-12, atol=1e-12)
    with pytest.raises(UserInputError):
        integrate("chaplygin_ball", Y[6], 4.1, P[6], rtol=1e-12, atol=1e-12)


def test_unit_vectors_renormalised_at_once_have_integrate_s_bits():
    """unit_rows against pack_state (x/|x| at 30 digits, rounded once) on 3000 generic
    vectors, a third of them off unit length within the tolerance: every row it accepts has
    pack_state's bits, and it accepts them all (no ties in generic data); a row beyond the
    tolerance is not accepted. The control: plain double x/|x| differs from pack_state on
    some of the same rows (the comparison sees the last bit)."""
    from chaplygin.numerics.code import load_model_code
    from chaplygin.numerics.ensemble_inputs import unit_rows
    from chaplygin.numerics.inputs import pack_state
    from chaplygin.numerics.precision import Precision

    code, prec = load_model_code("chaplygin_ball"), Precision("double")
    rng = np.random.default_rng(2026)
    G = rng.normal(size=(3000, 3))
    G /= np.linalg.norm(G, axis=1)[:, None]
    G[::3] *= 1 + rng.uniform(-5e-10, 5e-10, (1000, 1))
    G[7] *= 1 + 1e-6
    G[11] = (-(3**-0.5), 0.0, -((2 / 3) ** 0.5))  # a component exactly 0 (the separatrix start)
    out, ok = unit_rows(G)
    assert not ok[7] and ok.sum() == len(G) - 1
    plain = G / np.linalg.norm(G, axis=1)[:, None]
    differs = 0
    for j in [11, *np.flatnonzero(ok)[::3]]:
        ref = pack_state(code, {"M": (0.1, 0.2, 0.3), "gamma": tuple(G[j])}, prec)[3:]
        assert list(out[j]) == list(ref), j
        differs += list(plain[j]) != list(ref)
    assert differs > 10


def test_the_bench_section_reports_every_row():
    """chaplygin bench's ensemble section (no timing asserted): every row for both problems
    and tolerances, positive, no orbit failed."""
    from chaplygin.verify.bench_ensemble import ensemble_throughput

    out = ensemble_throughput(orbits=(3, 5), repeats=1, quick=True, peers=False)
    rows = [v for v in out.values() if isinstance(v, dict)]
    assert len(rows) == 8 and sum(key.endswith(" N=5") for key in out) == 4
    for row in rows:
        assert row["failed"] == 0 and row["steps_per_orbit"] > 0
        assert row["ours_one_s"] > 0 and row["ours_many_1_s"] > 0 and row["ours_many_s"] > 0
    with pytest.raises(UserInputError):
        ensemble_throughput(orbits=(0,))


def test_the_evidence_of_all_orbits_at_once_is_each_orbit_s(monkeypatch):
    """Fourteen states (numbers, one body) in the lanes with a step limit that the faster
    orbits exceed: the ensemble's status and drift arrays, computed for all orbits at once,
    are each orbit's integrate() result's, bit for bit -- orbits that reached the end and
    orbits stopped after fewer outputs -- and no orbit's result was made to compute them
    (counted: the results are made when asked for). With 20 output times (beyond the compiled
    point-by-point evidence) every orbit's evidence is its own result's, and still integrate()'s."""
    made = []
    real = ensemble.lanes_result
    monkeypatch.setattr(ensemble, "lanes_result", lambda *a: made.append(a[3]) or real(*a))
    rng = np.random.default_rng(29)
    G = rng.normal(size=(14, 3))
    G /= np.linalg.norm(G, axis=1)[:, None]
    scale = np.geomspace(0.3, 6.0, 14)[:, None]
    Y = np.hstack([rng.uniform(-0.9, 0.9, (14, 3)) * scale, G]).tolist()
    kw = {"rtol": 1e-11, "atol": 1e-11, "max_steps": 9}
    for t_eval in (None, list(np.linspace(0.0, 4.3, 20))):
        made.clear()
        r = integrate_many("chaplygin_ball", Y, 4.3, PARAMS, t_eval=t_eval, **kw)
        if t_eval is None:
            assert made == []  # the arrays came first, no result was needed
        assert 0 < int(r.success.sum()) < 14  # some orbits stopped at the step limit
        for j in range(14):
            one = integrate("chaplygin_ball", Y[j], 4.3, PARAMS, t_eval=t_eval, **kw)
            assert r.status[j] == one.status and r.nsteps[j] == one.nsteps
            assert {n: r.drift[n][j] for n in r.drift} == one.drift
            assert r.results[j].drift == one.drift and r.results[j].message == one.message


@pytest.mark.parametrize(("every_output", "energy_at_zero"),
                         [(False, True), (True, True), (True, False)])  # fmt: skip
def test_evidence_at_once_keeps_what_the_point_by_point_loop_keeps(every_output,
                                                                  energy_at_zero):  # fmt: skip
    """ensemble_evidence on made-up outputs -- NaN and infinity at the first or a later
    output, an orbit with one output, outputs after an orbit's last that are garbage, an
    integral starting at zero (absolute drift) -- against base._drift and the finiteness
    check, orbit by orbit (the route integrate() takes for a run on the C backend).
    ``every_output``: every orbit reached every output (the route without masks);
    ``energy_at_zero`` False: no integral starts at zero (that route's plain quotient)."""
    from chaplygin.numerics.code import load_model_code
    from chaplygin.numerics.ensemble_evidence import ensemble_evidence
    from chaplygin.numerics.integrators.base import _all_finite, _drift
    from chaplygin.numerics.precision import Precision

    code, prec = load_model_code("chaplygin_ball"), Precision("double")
    compiled = code.compiled()
    p = np.array([1.13, 2.07, 3.31, 0.93])
    rng = np.random.default_rng(5)
    N, m = 9, 6
    y = rng.normal(size=(N, 6, m))
    y[:, :3, :] *= 1 + 1e-9 * rng.normal(size=(N, 3, m))
    y[1, 2, 3] = np.nan
    y[2, 0, 0] = np.inf
    y[3, 1, 4] = -np.inf
    if energy_at_zero:
        y[4, :3, :] = 0.0  # M = 0: the energy starts at zero (absolute drift)
        y[4, 0, 2] = 1e-9
    done = np.full(N, m) if every_output else np.array([6, 6, 6, 6, 6, 1, 3, 4, 6])
    y[6, 0, 3:] = np.nan  # after orbit 6's last output: not its evidence
    status = np.array([0, 0, 0, 0, 0, 0, -2, -3, 0])
    P = np.tile(p, (N, 1))
    P[8] = [1.41, 2.23, 3.17, 1.09]  # an orbit with its own body
    got_status, got = ensemble_evidence(code, compiled, np.linspace(0, 1, m), y, done, status,
                                        P, prec.zero, lambda j: None)  # fmt: skip
    t = np.linspace(0, 1, m)
    for j in range(N):
        drift, _ = _drift(code, t[: done[j]], y[j, :, : done[j]], P[j], prec, compiled)
        want = status[j] if _all_finite(y[j, :, : done[j]]) else -1
        if want == 0 and not all(np.isfinite(list(drift.values()))):
            want = -5
        assert got_status[j] == want, j
        for name, v in drift.items():
            assert got[name][j] == v or (np.isnan(got[name][j]) and np.isnan(v)), (j, name)
    assert got_status.tolist()[:4] == [0, -1, -1, -1]
    assert got_status[6] == (-1 if every_output else -2)
    assert every_output == bool(np.isnan(got["H"][6]))  # its garbage counts when it is output
    assert np.isnan(got["H"][1]) and got["H"][4] > 0


def test_the_kept_threads_of_the_lanes_serve_a_forked_child():
    """The lanes' blocks run on threads kept between calls; a child forked after a call
    (whose copy of the pool has no threads) gets a pool of its own and finishes its
    ensemble with the parent's bits (a hang here would be the inherited pool)."""
    import multiprocessing
    import os

    if len(os.sched_getaffinity(0)) < 2:  # one block only: the kept pool is not used
        pytest.skip("needs 2 usable CPUs (two blocks of lanes)")
    states = _states(40, seed=21)
    kw = {"rtol": 1e-11, "atol": 1e-11, "threads": 2}
    parent = integrate_many("chaplygin_ball", states, 2.9, PARAMS, **kw)
    ctx = multiprocessing.get_context("fork")
    with ctx.Pool(1) as pool:
        child = pool.apply_async(_ensemble_outputs, (states, kw)).get(timeout=120)
    assert np.array_equal(child, parent.y) and parent.threads == 2


def _ensemble_outputs(states, kw):
    return integrate_many("chaplygin_ball", states, 2.9, PARAMS, **kw).y


def test_an_ensemble_from_the_lanes_pickles_with_its_results():
    """An EnsembleResult whose results are made when asked for (the lanes) goes through
    pickle (a Dask task returns it so) with every orbit's result, equal to the original's."""
    import pickle

    r = integrate_many("chaplygin_ball", _states(6, seed=5), 1.7, PARAMS, rtol=1e-11,
                       atol=1e-11)  # fmt: skip
    back = pickle.loads(pickle.dumps(r))
    assert isinstance(back.results, list) and len(back.results) == 6
    for j in range(6):
        assert _same(back.results[j].y, r.results[j].y)
        assert back.results[j].drift == {n: r.drift[n][j] for n in r.drift}
    assert _same(back.y, r.y) and back.status.tolist() == r.status.tolist()


def test_the_same_ensemble_again_reads_its_starts_once_and_gives_the_same_bits(monkeypatch):
    """integrate_many called again with the same inputs (as typed) does not read its starts
    again (counted); its arrays are the first call's bit for bit and its own; changed starts
    are read anew; a refused orbit is refused every time."""
    monkeypatch.setattr(ensemble, "_READ", {})
    calls = []
    real = ensemble.read_starts
    monkeypatch.setattr(ensemble, "read_starts",
                        lambda *a, **k: calls.append(1) or real(*a, **k))  # fmt: skip
    rng = np.random.default_rng(23)
    G = rng.normal(size=(6, 3))
    G /= np.linalg.norm(G, axis=1)[:, None]
    Y = np.hstack([rng.uniform(-0.9, 0.9, (6, 3)), G])
    kw = {"rtol": 1e-11, "atol": 1e-11, "t_eval": [0.0, 1.7, 3.3]}
    a = integrate_many("chaplygin_ball", Y, 3.3, PARAMS, **kw)
    b = integrate_many("chaplygin_ball", Y, 3.3, PARAMS, **kw)
    assert len(calls) == 1 and a.success.all() and b.success.all()
    assert _same(a.y, b.y) and a.y is not b.y and _same(a.status, b.status)
    for name in a.drift:
        assert _same(a.drift[name], b.drift[name])
    for j in range(6):
        one = integrate("chaplygin_ball", Y[j], 3.3, PARAMS, **kw)
        assert _same(b.y[j], one.y) and b.results[j].drift == one.drift
    Y[2, 0] += 0.01  # another start: read anew
    c = integrate_many("chaplygin_ball", Y, 3.3, PARAMS, **kw)
    assert len(calls) == 2 and not _same(c.y[2], a.y[2]) and _same(c.y[3], a.y[3])
    Y[4, 3:] *= 1 + 1e-3  # off |gamma| = 1: refused, each time
    for _ in range(2):
        with pytest.raises(UserInputError, match="orbit 4"):
            integrate_many("chaplygin_ball", Y, 3.3, PARAMS, **kw)


def test_the_threads_follow_the_estimated_work():
    """spread_threads: one thread below twice SPREAD_MIN_S of estimated work (or where the
    estimate is not a number), then one per SPREAD_MIN_S, at most ``workers`` and ``left``."""
    from chaplygin.numerics.ensemble_lanes import SPREAD_MIN_S, spread_threads

    per = SPREAD_MIN_S / 7.3  # seconds per orbit: 7.3 orbits make one thread's least work
    assert spread_threads(per, 14, 4) == 1  # 1.92 of the least work
    assert spread_threads(per, 15, 4) == 2  # 2.05
    assert spread_threads(per, 22, 4) == 3  # 3.01
    assert spread_threads(per, 10_000, 4) == 4 and spread_threads(per, 10_000, 1) == 1
    assert spread_threads(1.0, 3, 8) == 3  # no more threads than orbits
    assert spread_threads(float("nan"), 100, 4) == 1 and spread_threads(0.0, 100, 4) == 1


@pytest.mark.parametrize("least_work", [0.0, float("inf")])
def test_the_default_threads_are_chosen_from_the_work_and_keep_the_bits(least_work,
                                                                          monkeypatch):  # fmt: skip
    """threads left to the default: the first group of lanes is timed alone, then the other
    orbits run on this thread (least work per thread infinite) or on every usable CPU (none),
    and every orbit's numbers are those of threads=1 (one block, no timing)."""
    import os

    from chaplygin.numerics import ensemble_lanes

    usable = len(os.sched_getaffinity(0))
    if least_work == 0.0 and usable < 2:
        pytest.skip("needs 2 usable CPUs (more than one thread to spread over)")
    states = _states(23, seed=17)
    kw = {"rtol": 1e-11, "atol": 1e-11}
    one = integrate_many("chaplygin_ball", states, 2.3, PARAMS, threads=1, **kw)
    monkeypatch.setattr(ensemble_lanes, "SPREAD_MIN_S", least_work)
    r = integrate_many("chaplygin_ball", states, 2.3, PARAMS, **kw)
    # the first group is four lanes (AVX2) or eight (AVX-512): 19 or 15 orbits left
    assert r.threads in ({1} if least_work else {min(usable, 19), min(usable, 15)})
    assert _same(r.y, one.y) and _same(r.status, one.status) and _same(r.nsteps, one.nsteps)
    assert all(_same(r.drift[k], one.drift[k]) for k in one.drift)
    assert r.orbit_wall_s.shape == (23,) and (r.orbit_wall_s > 0).all()
