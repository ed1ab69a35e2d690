"""The closed form of issue 13: exact at xi = 0, asymptotes, monotone in eps, delivered restitution."""

from pathlib import Path

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.engine.codes import END_STATES
from contactalpha.engine.exact import alpha_exact
from contactalpha.engine.scaling import scaled_load
from contactalpha.engine.unloaded import alpha_unloaded_scalar
from contactalpha.models import closed_form as cf
from contactalpha.paper.closedform import compute as cc

EPS = np.linspace(0.01, 0.99, 99)


def test_exact_on_the_unloaded_column():
    eps = np.r_[np.geomspace(1e-4, 0.01, 20), EPS]
    a = cf.alpha_closed_form(eps, 0.0)
    np.testing.assert_allclose(a, alpha_exact(eps), rtol=2e-15, atol=0)
    # towards eps = 1 the Newton solver loses digits (eps^n - 1); the explicit root keeps them
    # (tests/engine/test_unloaded.py checks it against a 50-digit root there)
    near_one = 1 - np.geomspace(1e-2, 1e-8, 20)
    expected = [alpha_unloaded_scalar(e) for e in near_one]
    np.testing.assert_array_equal(cf.alpha_closed_form(near_one, 0.0), expected)
    np.testing.assert_allclose(expected, alpha_exact(near_one), rtol=1e-9, atol=0)


def test_asymptotes():
    # alpha ~ 1/eps as eps -> 0 at xi = 0
    for e in (1e-3, 1e-4):
        assert abs(cf.alpha_closed_form(e, 0.0) * e - 1) < 2e-3
    # alpha -> 0 as eps -> 1, at every load
    for x in (0.0, 1e-4, 0.1, 0.5, 0.9, 0.99):
        assert cf.alpha_closed_form(1.0, x) == 0.0
        near = cf.alpha_closed_form(1 - np.array([1e-3, 1e-5, 1e-7]), x)
        assert np.all(np.diff(near) < 0) and near[-1] < 1e-5


@pytest.mark.parametrize("xi", [1e-5, 1e-4, 1e-3, 0.01, 0.05, 0.2, 0.5, 0.8, 0.99])
def test_monotone_in_eps_where_the_exact_surface_is(xi):
    eps = np.linspace(0.01, 0.99, 981)
    exact_dec = np.diff(ca.alpha(eps, xi, model="exact")) < 0
    model_dec = np.diff(cf.alpha_closed_form(eps, xi)) < 0
    assert np.all(model_dec[exact_dec])


def test_smooth_and_finite_on_the_domain():
    E, X = np.meshgrid(np.linspace(0.001, 1.0, 300), np.r_[0.0, np.geomspace(1e-12, 0.999, 300)])
    a = cf.alpha_closed_form(E, X)
    assert np.all(np.isfinite(a)) and np.all(a >= 0)


def test_the_separation_coordinate_follows_the_exact_boundary():
    """The bump's ln A_b, with the boundary's own eps -> 0 constant, is within 0.033 of
    scene.threshold's fit (good to 4.5e-4) and exact as eps -> 1; the bump vanishes far from it."""
    from contactalpha.scene.threshold import BOUNDARY_FIT, boundary_load_fit

    eps = np.linspace(0.01, 0.99, 99)
    approx = np.array([cf.log_separation_load(e, np.log(e), BOUNDARY_FIT[-1]) for e in eps])
    assert np.max(np.abs(approx - np.log(boundary_load_fit(eps)))) < 0.033
    near_one = 1 - np.geomspace(1e-3, 1e-6, 4)
    exact_limit = np.log(2 ** (-0.6) / 2 * (1 - near_one) ** (-0.6))
    np.testing.assert_allclose(
        [cf.log_separation_load(e, np.log(e), -0.9) for e in near_one], exact_limit, atol=2e-3
    )
    c = cf.shipped_vector()
    for e, x in ((0.5, 1e-9), (1 - 1e-9, 0.5), (1e-6, 0.5)):
        assert abs(cf.log_branches(e, x, c)[3]) < 1e-3


@pytest.mark.parametrize("xi", [1e-3, 0.05, 0.3, 0.7, 0.99])
def test_the_creep_coordinate_is_the_exact_creep_boundary(xi):
    """alpha_crit = exp(LOG_CRITICAL) x_eq^(-5/4): an impact creeps just above it and not just below;
    the creep bump vanishes far from it (eps -> 1, xi -> 0)."""
    x_eq = (0.8 * scaled_load(xi)) ** (2.0 / 3.0)
    alpha_crit = np.exp(cf.LOG_CRITICAL) * x_eq**-1.25
    states = ca.impact(alpha_crit * np.array([1 + 1e-6, 1 - 1e-6]), xi).state
    assert states[0] == "creep" and states[1] != "creep"
    c = cf.shipped_vector()
    crit_r0 = c[cf.CONSTANT_NAMES.index("crit_r0")]
    assert cf.log_branches(0.3, xi, c)[4] == pytest.approx(np.log(alpha_crit) + crit_r0, abs=1e-12)
    for e, x in ((1 - 1e-9, xi), (0.5, 1e-12)):
        log_s, log_c, k, sep, crit = cf.log_branches(e, x, c)
        log_b = max(log_s, log_c) + np.log1p(np.exp(-k * abs(log_s - log_c))) / k + sep
        assert abs(np.log(cf.alpha_closed_form(e, x)) - log_b) < 1e-3


def test_the_exact_onset_approaches_its_heavy_load_limit_like_one_over_a_x_eq():
    """Why alpha_c carries exp(on_g g), g = A x_eq / (1/2 + A x_eq): the exact onset of "no
    restitution" (eps -> 0) tends to c x_eq^(-5/4) with a correction ~ 1/(A x_eq), the impact's
    kinetic energy 1/2 against the load's work to x_eq (measured: ln(alpha x_eq^(5/4)) =
    1.0735 + 0.254 / (A x_eq) from xi = 0.99 to 0.999 and 0.2554 from 0.999 to 0.9999)."""
    xi = np.array([0.99, 0.999, 0.9999])
    a = scaled_load(xi)
    x_eq = (0.8 * a) ** (2.0 / 3.0)
    y = np.log([ca.alpha(1e-4, x, model="exact_solve") for x in xi]) + 1.25 * np.log(x_eq)
    slopes = np.diff(y) / np.diff(1.0 / (a * x_eq))
    assert abs(slopes[1] / slopes[0] - 1) < 0.02 and 0.2 < slopes[1] < 0.3
    # the term leaves the onset's light-load limit 2 x_eq^(-5/2) exact (g -> 0 as xi -> 0) and
    # tends to on_g at heavy load
    c = cf.shipped_vector()
    on_g = cf.CONSTANT_NAMES.index("on_g")
    off = c.copy()
    off[on_g] = 0.0
    for x, g in ((1e-10, 0.0), (1e-4, 0.0), (0.9999, 1.0)):
        shift = cf.log_branches(0.3, x, c)[1] - cf.log_branches(0.3, x, off)[1]
        assert abs(shift - c[on_g] * g) < 1e-3 * abs(c[on_g])


def test_jitted_scalar_and_registry_agree_and_refuse_bad_input():
    f = cf.jit_alpha_closed_form()
    e, x = 0.3, 0.2
    assert f(e, x) == cf.alpha_closed_form(e, x) == ca.alpha(e, x, model="closed_form")
    assert np.isnan(f(0.0, 0.2)) and np.isnan(f(0.5, 1.0)) and np.isnan(f(np.nan, 0.1))
    with pytest.raises(ValueError, match="xi"):
        ca.alpha(0.5, 1.2, model="closed_form")
    with pytest.raises(ValueError, match="missing"):
        cf.alpha_closed_form(0.5, 0.2, {"s_xi": 1.0})


def test_held_out_points_deliver_their_restitution():
    """Random points off the fit grid (exact alpha from the table): measured level, with margin.

    Measured: max 0.0046, RMS 0.00095, 398 of 400 end states the same.  On the full surface grid
    the shipped constants deliver max 0.0075, RMS 0.00090 (0.0008981), same end state 99.7 %
    (issue 13's targets 0.01 / 1e-3 / 99 % all met; see results/closedform/comparison.json).
    """
    rng = np.random.default_rng(13)
    eps = rng.uniform(0.01, 0.99, 400)
    xi = np.r_[10 ** rng.uniform(-5, -2, 100), rng.uniform(0.0, 0.99, 300)]
    exact = ca.alpha(eps, xi, model="exact")
    delivered = ca.impact(cf.alpha_closed_form(eps, xi), xi)
    err = delivered.eps - eps
    assert np.all(delivered.ok)
    assert np.max(np.abs(err)) <= 0.0050
    assert np.sqrt(np.mean(err**2)) <= 0.0010
    states = ca.impact(exact, xi).state
    assert np.mean(states == delivered.state) >= 0.99


def test_shipped_file_records_its_scores():
    d = cf.load_constants()
    assert d["format_version"] == cf.FORMAT_VERSION and set(d["constants"]) == set(cf.CONSTANT_NAMES)
    assert set(d["standard_errors"]) == set(cf.CONSTANT_NAMES)
    assert len(cf.CONSTANT_NAMES) <= 25
    for part in ("fitted", "held_out"):
        scores = d["delivered"][part]
        # measured (format 8): fitted 0.0075 / 0.000898 / 99.7 %, held out 0.0073 / 0.000898 / 99.6 %
        assert scores["n_failed"] == 0 and scores["eps_abs_max"] <= 0.0080
        assert scores["eps_abs_rms"] <= 0.00092 and scores["state_agreement"] >= 0.995


def _table_targets(seed, n):
    """Fit targets (``paper.closedform.compute.surface_targets`` layout) at random points, alpha
    from the shipped exact table (1e-8): ~1/5 on the small-xi ridge, the rest uniform."""
    rng = np.random.default_rng(seed)
    eps = rng.uniform(0.01, 0.99, n)
    xi = np.r_[10 ** rng.uniform(-5, -2, n // 5), rng.uniform(0.0, 0.99, n - n // 5)]
    alpha = ca.alpha(eps, xi, model="exact")
    r = ca.impact(alpha, xi)
    code = {name: c for c, name in END_STATES.items()}
    state = np.array([code[s] for s in np.atleast_1d(r.state)])
    slope = np.asarray(r.deps_dalpha) * alpha
    held = np.zeros(n, bool)
    return {"eps": eps, "xi": xi, "alpha": alpha, "state": state, "slope": slope, "holdout": held}


# A fresh refit may beat the shipped constants off its points by this much RMS in delivered eps
# (measured 0.0012 shipped vs 0.0013 refit; shipping on_b 1 % off gives 0.0030 vs 0.0013,
# s_log_eps 20 % off 0.0054, q_0 10 % off 0.0186, k_0 10 % off 0.0064).
REFIT_RMS_MARGIN = 5e-4


def test_refit_on_the_coarse_test_surface_agrees_with_the_shipped_constants(coarse_surface):
    """CI: the shipped constants are what this code's fit gives.

    The coarse test surface (workflow/test-config.yaml, solved afresh) is delivered within the
    issue's max target with every end state; a refit from the shipped constants on it plus 400
    random points (12 grid points cannot pin 25 constants) is no better than the shipped
    constants, by ``REFIT_RMS_MARGIN``, on 400 other random points held out of the fit.
    """
    coarse = cc.surface_targets(coarse_surface)
    coarse["holdout"][:] = False
    shipped = cf.load_constants()["constants"]
    on_grid = cc.judge(cf.alpha_closed_form(coarse["eps"], coarse["xi"], shipped), coarse)
    assert on_grid["eps_abs_max"] <= cc.TARGETS["eps_abs_max"] and on_grid["state_agreement"] == 1.0

    extra = _table_targets(1, 400)
    fit_set = {k: np.r_[coarse[k], extra[k]] for k in coarse}
    fit = cc.fit_closed_form(fit_set, shipped, max_nfev=40)
    held = _table_targets(2, 400)
    scores = [
        cc.judge(cf.alpha_closed_form(held["eps"], held["xi"], c), held)
        for c in (shipped, fit.extra["constants"])
    ]
    assert scores[0]["eps_abs_rms"] <= scores[1]["eps_abs_rms"] + REFIT_RMS_MARGIN
    assert scores[0]["state_agreement"] >= scores[1]["state_agreement"] - 0.01


@pytest.fixture(scope="module")
def coarse_surface():
    """The alpha surface on workflow/test-config.yaml's grid, solved by the package."""
    import xarray as xr
    import yaml

    from contactalpha.paper.surface.compute import grid_from_config

    root = Path(__file__).resolve().parents[2]
    cfg = yaml.safe_load((root / "workflow" / "test-config.yaml").read_text(encoding="utf-8"))
    eps, xi = grid_from_config(cfg["surface"])
    E, X = np.meshgrid(eps, xi, indexing="ij")
    sol = ca.solve_alpha(E, X)
    code = {name: c for c, name in END_STATES.items()}
    dims = ("epsilon", "xi")
    return xr.Dataset(
        {
            "alpha": (dims, np.asarray(sol.alpha, dtype=float)),
            "state": (dims, np.vectorize(code.get)(sol.state).astype(np.int8)),
            "status": (dims, np.where(np.asarray(sol.status) == "ok", 0, 1).astype(np.int8)),
        },
        coords={"epsilon": eps, "xi": xi},
    )


def test_a_fit_with_some_constants_free_keeps_the_others(coarse_surface):
    t = cc.surface_targets(coarse_surface)
    t["holdout"][:] = False
    shipped = cf.load_constants()["constants"]
    fit = cc.fit_closed_form(t, shipped, free=("s_xi", "on_eps"), max_nfev=20)
    assert fit.names == ["s_xi", "on_eps"]
    moved = {n for n, v in fit.extra["constants"].items() if v != shipped[n]}
    assert moved <= {"s_xi", "on_eps"} and moved
    with pytest.raises(ValueError, match="free"):
        cc.fit_closed_form(t, shipped, free=("s_xi", "nope"))


def test_the_polish_jacobian_is_the_engines_slope_times_the_forms_derivative():
    """The polish's Jacobian (no extra impacts) matches central differences of true delivered eps."""
    t = _table_targets(3, 80)
    c = cf.shipped_vector()
    names = ("s_xi", "on_b", "q_0", "k_0", "sep_a", "sep_r0", "crit_a", "crit_r0")
    cols = [cf.CONSTANT_NAMES.index(n) for n in names]
    r, J = cc.delivered_residuals_and_jacobian(t, c, cols)
    np.testing.assert_array_equal(r, cc.delivered_residuals(t, c))
    assert J.shape == (80, len(cols)) and np.all(np.any(J != 0, axis=0))
    for j, i in enumerate(cols):
        h = 1e-5 * max(1.0, abs(c[i]))
        up, down = c.copy(), c.copy()
        up[i] += h
        down[i] -= h
        fd = (cc.delivered_residuals(t, up) - cc.delivered_residuals(t, down)) / (2 * h)
        np.testing.assert_allclose(J[:, j], fd, rtol=1e-3, atol=1e-6 * np.max(np.abs(fd)))


def test_the_polish_lowers_the_true_delivered_error_from_the_linearised_fit(coarse_surface):
    # Perturbed constants: the linearised fit (2 evaluations) leaves room that the polish on true
    # delivered eps, sharing one impact pass between residuals and Jacobian, must take.
    t = cc.surface_targets(coarse_surface)
    t["holdout"][:] = False
    start = {**cf.load_constants()["constants"]}
    start["s_xi"] += 0.3
    free = ("s_xi", "on_eps", "k_0")
    lin = cc.fit_closed_form(t, start, free=free, max_nfev=2)
    pol = cc.fit_closed_form(t, start, free=free, max_nfev=2, polish_steps=20)
    cost = {
        name: 0.5 * float(np.sum(cc.delivered_residuals(t, cf.constants_vector(f.extra["constants"])) ** 2))
        for name, f in (("lin", lin), ("pol", pol))
    }
    assert pol.extra["stage"] == "delivered eps (polished)"
    assert cost["pol"] < cost["lin"]
    assert pol.cost == pytest.approx(cost["pol"], rel=1e-12)


# Issue 29, planted bug: S_LOG_EXP -0.6 -> -0.606 moved alpha by up to 0.36 % with every held-out
# score under its limit, and +1 % in a_x_eq's 1.25 was caught by a 0.00509 vs 0.005 margin only.
# The closed form's formula, pinned: its values with these constants (the shipped ones when pinned),
# at points on every branch (xi = 0, the ridge, the loaded plateau, xi -> 1).
PIN_CONSTANTS = (
    -0.6732706303500418,
    1.029122829210627,
    0.15458597522160714,
    0.309509854366603,
    1.9151119271344694,
    2.444292510429238,
    -0.18081402395118504,
    -0.3233543974356905,
    -0.4211457804071342,
    -0.15909433138149448,
    1.4293526379239525,
    0.2453596386263412,
    0.017263577196553706,
    0.77341276877947,
    0.24641525277320064,
    -0.8253774974315442,
    1.645153685915205,
    -1.988574922275223,
    0.350790563517143,
    0.11594542851386942,
    1.6542125160607741,
    -0.521865926273882,
    0.16583049061492058,
    0.3698001289144811,
    -0.173511500668641,
)
PIN_EPS = [0.01, 0.05, 0.2, 0.5, 0.8, 0.97]
PIN_XI = [0.0, 0.0001, 0.01, 0.2, 0.6, 0.95]
PIN_ALPHA = (
    (100.0, 99.60936429709287, 8229.959547843693, 109.18516238827839, 10.445193652639679, 1.5384075423560182),
    (
        19.999999681532362,
        19.983359850577553,
        86.19465082900098,
        95.17349222106903,
        10.21275904610354,
        1.5128105936043827,
    ),
    (
        4.919166715790785,
        4.917423136173107,
        5.002847584789633,
        18.416133026836107,
        7.534547109978545,
        1.2682110469689243,
    ),
    (
        1.432750533271375,
        1.4324581397288274,
        1.4422529861369748,
        1.5367207837801389,
        1.710317109437661,
        0.5223015040575947,
    ),
    (
        0.3731462033650536,
        0.3731018193981229,
        0.3736889410603828,
        0.362256007339619,
        0.32062842491922094,
        0.1314901981652063,
    ),
    (
        0.046387449100585496,
        0.04638464822397389,
        0.04635632732637578,
        0.044777723245530046,
        0.03706317181101216,
        0.01583096813118735,
    ),
)


def test_the_closed_form_formula_is_pinned_at_fixed_points():
    e, x = np.meshgrid(PIN_EPS, PIN_XI, indexing="ij")
    got = cf.alpha_closed_form(e, x, np.array(PIN_CONSTANTS))
    np.testing.assert_allclose(got, np.array(PIN_ALPHA), rtol=1e-13, atol=0)
    # The jitted scalar form is the same formula.
    scalar = cf.jit_alpha_closed_form(dict(zip(cf.CONSTANT_NAMES, PIN_CONSTANTS, strict=True)))
    assert scalar(0.2, 0.2) == pytest.approx(PIN_ALPHA[2][3], rel=1e-13)
