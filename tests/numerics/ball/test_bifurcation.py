"""Bifurcation analysis: curves and solutions (claims), Floquet stability, region of motion,
the figures of ``chaplygin bifurcation`` and its refusal of bad input.

References: BKM12-24, 25, Sigma_i, crit, Sigma45, Fig3, 1.5stab, 1.5stab8, Fig2region,
2.7a-c; K01-3.1, 3.2, 3.2c.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from chaplygin.derive import build_model
from chaplygin.derive.bifurcation import (
    steady_axes,
    steady_rotation_residual,
)
from chaplygin.numerics import integrate, load_model_code
from chaplygin.numerics.ball import bifurcation as nb
from chaplygin.numerics.ball.stability import (
    critical_state,
    euler_floquet,
    steady_rotation_floquet,
    support_steady_state,
)
from chaplygin.verify.claims import REGISTRY
from chaplygin.verify.claims import bifurcation as _bifurcation_claims  # registers them
from chaplygin.verify.cli import main
from chaplygin.verify.plots import FIGURES
from chaplygin.verify.verdict import check_claim

I_REF, D_REF = (1.0, 1.5, 3.0), 1.0  # BKM12-1.5stab, K01-Fig1
RTOL = 1e-12
assert _bifurcation_claims.BALL == "chaplygin_ball"

# literal readings FORMULAS.md marks FAILED, beside their corrections
PAIRS = [
    ("BKM12-25/literal", "BKM12-25"),
    ("K01-3.2/literal", "K01-3.2"),
    ("BKM12-2.7a-sol/literal", "BKM12-2.7a-sol"),
]
IDS = [
    "BKM12-1.5R", "BKM12-24", "BKM12-25", "BKM12-Sigma_i", "BKM12-crit", "BKM12-Sigma45",
    "BKM12-Fig3", "BKM12-1.5a", "BKM12-26", "K01-3.1", "K01-3.2a", "K01-3.2b", "K01-3.2c",
    "K01-3.2", "K01-3.3", "K01-3.2y", "BKM12-2.7a", "BKM12-2.7a-sol", "BKM12-2.7b.e1",
    "BKM12-2.7b.e2", "BKM12-2.7b.e3", "BKM12-2.7c",
]  # fmt: skip


def test_registry_has_the_bifurcation_claims_literals_and_controls():
    assert set(IDS) <= set(REGISTRY)
    for literal, corrected in PAIRS:
        assert REGISTRY[literal].expected == "fails"
        assert REGISTRY[corrected].expected == "holds"
    controls = {"BKM12-Sigma_i/control-coefficient", "BKM12-26/control-factor2"}
    assert all(REGISTRY[c].expected == "fails" for c in controls)


@pytest.mark.parametrize("literal,corrected", PAIRS)
def test_literal_reading_refuted_and_correction_proved(literal, corrected):
    # (every registered claim is decided in test_claims; here the pairs side by side)
    bad, good = check_claim(REGISTRY[literal]), check_claim(REGISTRY[corrected])
    assert bad.verdict == "refuted" and bad.witness
    assert good.verdict == "proved"


def test_middle_curve_control_is_refuted_with_a_witness():
    v = check_claim(REGISTRY["BKM12-Sigma_i/control-coefficient"])
    assert v.verdict == "refuted" and float(sp.sympify(v.residual)) != 0


def test_steady_rotations_are_rotations_about_principal_axes():
    model = build_model("chaplygin_ball", ())
    w = sp.Matrix(model.omega)
    I = sp.diag(*model.param_group("I"))
    # derived residual is omega x (I omega): no dependence on gamma left
    assert sp.simplify(steady_rotation_residual(model) - w.cross(I * w)) == sp.zeros(3, 1)
    assert steady_axes(model) == [sp.eye(3)[:, i] for i in range(3)]


@pytest.mark.parametrize("axis", [0, 1, 2])
@pytest.mark.parametrize("Mg", [0.0, 0.5])
def test_derived_curve_matches_integrated_steady_rotation(axis, Mg):
    """Independent numeric check: the state built from the family stays a rotation about e_i
    and its energy is the derived Sigma_i (BKM12-24 at Mg = 0, Sigma_i otherwise)."""
    y0, T = critical_state(I_REF, D_REF, axis, 1.0, Mg)
    r = integrate(
        "chaplygin_ball",
        {"M": tuple(y0[:3]), "gamma": tuple(y0[3:])},
        T,
        {"I": I_REF, "D": D_REF},
        rtol=RTOL,
        atol=RTOL,
        t_eval=np.linspace(0, T, 50),
    )
    code = load_model_code("chaplygin_ball")
    p = [*I_REF, D_REF]
    aux = np.asarray(code.numpy.aux(0.0, r.y, p))
    omega = aux[-3:]
    others = [j for j in range(3) if j != axis]
    # omega stays on the axis and constant; the orbit closes after one period
    assert np.max(np.abs(omega[others])) < 1e-9
    assert np.ptp(omega[axis]) < 1e-9
    assert np.linalg.norm(r.y[:, -1] - y0) < 1e-9
    E = 2 * code.numpy.integrals(0.0, y0, p)[0]
    assert abs(E - nb.sigma(axis, 1.0, Mg, I_REF, D_REF)) < 1e-13


# --------------------------------------------------------------------- stability
def _finite_difference_monodromy(y0, T, digits=34, h="1e-12"):
    """Phi(T) by central differences of the Taylor flow at ``digits`` digits: a route
    independent of the variational equations (no Jacobian, another integrator)."""
    import mpmath

    cols = []
    with mpmath.workdps(digits):
        hm = mpmath.mpf(h)
        for j in range(6):
            ends = []
            for s in (1, -1):
                y = [mpmath.mpf(v) for v in y0]
                y[j] += s * hm
                r = integrate(
                    "chaplygin_ball", {"M": tuple(y[:3]), "gamma": tuple(y[3:])},
                    mpmath.mpf(T), {"I": I_REF, "D": D_REF}, precision=digits,
                    rtol=mpmath.mpf(10) ** (4 - digits),
                )  # fmt: skip
                ends.append([mpmath.mpf(v) for v in r.y_final.values()])
            cols.append([(a - b) / (2 * hm) for a, b in zip(*ends, strict=True)])
    return np.array([[float(c[i]) for c in cols] for i in range(6)])


@pytest.mark.parametrize("Mg", [0.0, 0.5])  # BKM12-1.5stab, BKM12-1.5stab8
def test_floquet_multipliers_agree_with_an_independent_route(Mg):
    """BKM12 prints the rule, not numbers: the multipliers of the variational route (DOP853,
    rtol 1e-12) are checked against the eigenvalues of the monodromy by central differences
    of the 34-digit Taylor flow (measured difference about 1e-12 relative, the variational
    route's error; asserted below 1e4 rtol relative: rtol amplified by the orbit's growth,
    at most max|mu| ~ 10, with a margin)."""
    A = 1 / (np.asarray(I_REF) + D_REF)
    middle = int(np.argsort(A)[1])
    for axis, r in enumerate(steady_rotation_floquet(I_REF, D_REF, 1.0, Mg, RTOL)):
        assert r.rank == 3  # a critical orbit
        assert r.closure < 1e-9 and r.drift < 1e-10
        # the pair is mu, 1/mu or on the unit circle
        assert abs(np.prod(r.nontrivial) - 1) < 1e-8
        assert r.stable == (axis != middle)
        if axis == middle:  # the hyperbolic pair: the largest eigenvalue of Phi is mu
            y0, T = critical_state(I_REF, D_REF, axis, 1.0, Mg)
            fd = float(np.max(np.abs(np.linalg.eigvals(_finite_difference_monodromy(y0, T)))))
            assert r.max_abs > 2
            assert abs(fd - r.max_abs) <= 1e4 * RTOL * r.max_abs, (fd, r.max_abs)


def test_floquet_rule_extreme_stable_middle_unstable_random_inertia():
    """The papers' rule for random seeded inertia: the axis of the middle A_i is unstable."""
    rng = np.random.default_rng(7)
    for _ in range(2):
        I = tuple(rng.uniform(0.5, 4.0, 3))
        D = float(rng.uniform(0.2, 2.0))
        A = 1 / (np.asarray(I) + D)
        middle = int(np.argsort(A)[1])
        for axis, r in enumerate(steady_rotation_floquet(I, D, 1.0, 0.3, RTOL)):
            assert r.stable == (axis != middle), (I, D, axis, r.max_abs)
            if axis == middle:
                assert r.max_abs > 1 + 1e3 * r.tolerance


@pytest.mark.parametrize("Ep", [0.5, 0.9])  # the two arcs of Sigma_4 (split at E' = 2/3)
def test_sigma4_orbits_are_stable(Ep):
    """BKM12-1.5stab8: on Sigma_4 (both arcs) all |multipliers| = 1."""
    r = euler_floquet(I_REF, D_REF, Ep, RTOL)
    assert r.rank == 3 and r.stable and r.closure < 1e-9


def test_support_steady_rotations_follow_the_same_rule():
    params = (1.0, 1.5, 3.0, 0.5, 0.3, -0.2)
    stab = nb.support_stability(params)
    assert [s for s, _ in stab] == [True, False, True]
    y0, T = support_steady_state(params, 0, 1.0, np.eye(3))
    assert y0.shape == (12,) and T > 0


# --------------------------------------------------------------- region of motion
def test_region_of_motion_between_the_extreme_curves():
    """BKM12-Fig2region and K01-3.2a: integrated states lie between the extreme curves."""
    vals, drift, _ = nb.sample_levels(I_REF, D_REF, 25, seed=3, Mg=0.0)
    A = 1 / (np.asarray(I_REF) + D_REF)
    tol = 10 * max(drift, 1e-12)
    C, E = vals[:, 0], vals[:, 2]
    assert np.all(E >= A.min() * C * (1 - tol)) and np.all(E <= A.max() * C * (1 + tol))
    # general M_gamma: between Sigma_min and Sigma_max, and n >= C^2
    vals, drift, _ = nb.sample_levels(I_REF, D_REF, 25, seed=4)
    C, Mg, E = vals.T
    lo = np.minimum.reduce([nb.sigma(i, C, Mg, I_REF, D_REF) for i in range(3)])
    hi = np.maximum.reduce([nb.sigma(i, C, Mg, I_REF, D_REF) for i in range(3)])
    tol = 10 * max(drift, 1e-12)
    assert np.all(E >= lo * (1 - tol)) and np.all(E <= hi * (1 + tol))
    assert np.all(C >= Mg**2)


def test_support_region_of_motion_between_extreme_surfaces():
    pos, drift = nb.support_sample((1.0, 1.5, 3.0, 0.5, 0.3, -0.2), 15, seed=5)
    tol = 10 * max(drift, 1e-12)
    assert np.all(pos[:, 2] >= -tol) and np.all(pos[:, 2] <= 1 + tol)


# -------------------------------------------------------------------- figures, CLI
@pytest.fixture(scope="module")
def figures(tmp_path_factory):
    out = tmp_path_factory.mktemp("figures")
    written = {}
    for fig in FIGURES:
        system = FIGURES[fig][0]
        path = out / f"{fig}.png"
        status = main(
            ["bifurcation", system, "--figure", fig, "--out", str(path), "--samples", "6"]
        )
        written[fig] = (status, path)
    return written


@pytest.mark.slow
@pytest.mark.parametrize("fig", list(FIGURES))
def test_figures_are_written(figures, fig):
    status, path = figures[fig]
    assert status == 0
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000


@pytest.mark.parametrize(
    "argv,needle",
    [
        (["chaplygin_ball", "--figure", "k01-9"], "unknown figure"),
        (["chaplygin_ball", "--param", "I=__import__('os')"], "--param I"),
        (["chaplygin_ball", "--param", "I=1,-2,3", "--figure", "bkm12-2"], "positive"),
        (["chaplygin_ball", "--param", "D=0", "--figure", "bkm12-2"], "D must be positive"),
        (["chaplygin_ball", "--param", "D=nan", "--figure", "bkm12-2"], "finite"),
        (["chaplygin_ball", "--figure", "bkm12-5"], "not chaplygin_ball"),
        (["rubber_duck"], "no bifurcation diagram"),
        (["chaplygin_ball", "--param", "K=1", "--figure", "bkm12-2"], "not used"),
    ],
)
def test_bad_input_one_line_exit_2(tmp_path, capsys, argv, needle):
    out = tmp_path / "f.png"
    status = main(["bifurcation", *argv, "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2
    assert needle in err and err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()


def test_out_must_be_png(tmp_path, capsys):
    status = main(["bifurcation", "chaplygin_ball", "--out", str(tmp_path / "f.txt")])
    assert status == 2 and ".png" in capsys.readouterr().err


@pytest.mark.parametrize("I", [I_REF, (3.0, 1.5, 1.0), (1.5, 1.0, 3.0)])
def test_bkm12_figures_number_the_sigmas_as_the_paper(I):
    """BKM12 Figs. 2 and 3 assume A1 < A2 < A3 (b_i = D A_i): the curve labelled Sigma_k is
    E = A_(k) C with A_(k) the k-th smallest A_i, and in Fig. 3 E'(g = 0) = b_(k), whatever
    the order of the body's moments (at I_REF, A is decreasing: Sigma_1 is body axis e3)."""
    from chaplygin.verify.plots import bifurcation_figure

    A = np.sort(1 / (np.asarray(I) + D_REF))
    fig2, _ = bifurcation_figure("bkm12-2", {"I": I}, samples=1)
    fig3, _ = bifurcation_figure("bkm12-3", {"I": I}, samples=1)
    for k in range(3):
        (line,) = [x for x in fig2.axes[0].lines if x.get_label().startswith(f"Sigma_{k + 1}:")]
        C, E = line.get_data()
        assert abs(E[-1] / C[-1] - A[k]) <= 1e-14
        (line,) = [x for x in fig3.axes[0].lines if x.get_label().startswith(f"Sigma_{k + 1}:")]
        g, Ep = line.get_data()
        assert abs(Ep[np.argmin(np.abs(g))] - D_REF * A[k]) <= 1e-14


def test_bifurcation_complex_figure_draws_four_leaves_glued_at_sigma2():
    """BKM12 Fig. 2(b) as computed: over each chamber two leaves, at means of M of opposite
    sign along the stable family's axis, approaching +-1 at the stable rotations; Sigma_2's
    level is one component (BKM12-Fig2b)."""
    from chaplygin.verify.plots import bifurcation_complex_figure

    fig = bifurcation_complex_figure(gs=(0.0,), levels=2)
    ax = fig.axes[0]
    leaves = [ln for ln in ax.lines if ln.get_marker() == "o" and ln.get_linestyle() == "-"]
    assert len(leaves) == 4
    ends = sorted(float(ln.get_ydata()[0 if ln.get_xdata()[0] < 0.4 else -1]) for ln in leaves)
    assert ends[0] < -0.9 and ends[1] < -0.9 and ends[2] > 0.9 and ends[3] > 0.9
    assert any("Sigma_2: 1 component" in (ln.get_label() or "") for ln in ax.lines)


def test_the_levels_of_one_point_share_one_energy_grid(monkeypatch):
    """BKM12 Fig. 2(b)'s three levels at (C, M_gamma) = (1, 0): the energy is sampled once for
    all three (the claims ask for three levels per point), and each level's components are
    those of a fresh grid, number for number; another M_gamma samples anew."""
    from chaplygin.numerics.ball import bifurcation as bif

    I, D = (1.0, 1.5, 3.0), 1.0
    levels = (0.325, 0.4, 0.45)
    grid = {"n_gamma": 2500, "n_theta": 180}  # spacing about 0.08, well below the radius 0.3
    bif._energy_grid.cache_clear()
    fresh = []
    for E in levels:
        fresh.append(bif.level_set_components(I, D, E, 1.0, 0.0, **grid))
        bif._energy_grid.cache_clear()
    calls = []
    integrals = bif._ball_code().numpy.integrals
    monkeypatch.setattr(bif._ball_code().numpy, "integrals",
                        lambda *a: calls.append(1) or integrals(*a))  # fmt: skip
    kept = [bif.level_set_components(I, D, E, 1.0, 0.0, **grid) for E in levels]
    assert len(calls) == 1
    assert [r.count for r in kept] == [2, 1, 2]  # BKM12-Fig2b
    for a, b in zip(fresh, kept, strict=True):
        assert (a.count, a.sizes, a.separation, a.points) == (b.count, b.sizes, b.separation,
                                                              b.points)  # fmt: skip
        assert np.array_equal(a.mean_M, b.mean_M)
    bif.level_set_components(I, D, 0.45, 1.0, 0.2, **grid)
    assert len(calls) == 2
    assert not bif._energy_grid(tuple((*I, D)), 1.0, 0.0, 2500, 180).energy.flags.writeable
