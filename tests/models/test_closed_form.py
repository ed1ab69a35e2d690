"""The closed form of issue 13: exact at xi = 0, asymptotes, monotone in eps, delivered restitution."""

from pathlib import Path

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.engine.exact import alpha_exact
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

    On the full surface grid the shipped constants deliver max 0.020, RMS 0.0042 (issue 13's
    targets 0.01 and 1e-3 are not met; see results/closedform/comparison.md).
    """
    rng = np.random.default_rng(13)
    eps = rng.uniform(0.01, 0.99, 400)
    xi = np.r_[10 ** rng.uniform(-5, -2, 100), rng.uniform(0.0, 0.99, 300)]
    exact = ca.alpha(eps, xi, model="exact")
    delivered = ca.impact(cf.alpha_closed_form(eps, xi), xi)
    err = delivered.eps - eps
    assert np.all(delivered.ok)
    assert np.max(np.abs(err)) <= 0.025
    assert np.sqrt(np.mean(err**2)) <= 0.006
    states = ca.impact(exact, xi).state
    assert np.mean(states == delivered.state) >= 0.97


def test_shipped_file_records_its_scores():
    d = cf.load_constants()
    assert d["format_version"] == cf.FORMAT_VERSION and set(d["constants"]) == set(cf.CONSTANT_NAMES)
    assert len(cf.CONSTANT_NAMES) <= 25
    held = d["delivered"]["held_out"]
    assert held["eps_abs_max"] <= 0.025 and held["eps_abs_rms"] <= 0.006


def test_refit_on_the_coarse_test_surface_agrees_with_the_shipped_constants(coarse_surface):
    """CI: a refit from the shipped constants on workflow/test-config.yaml's grid is no worse,
    and the shipped constants deliver the coarse surface's restitution within the shipped level."""
    t = cc.surface_targets(coarse_surface)
    t["holdout"][:] = False
    shipped = cf.load_constants()["constants"]
    fit = cc.fit_closed_form(t, shipped, max_nfev=50)
    before = cc.judge(cf.alpha_closed_form(t["eps"], t["xi"], shipped), t)
    after = cc.judge(cf.alpha_closed_form(t["eps"], t["xi"], fit.values()), t)
    assert before["eps_abs_max"] <= 0.025 and before["state_agreement"] >= 0.9
    assert after["eps_abs_rms"] <= before["eps_abs_rms"] + 1e-4


@pytest.fixture(scope="module")
def coarse_surface():
    """The alpha surface on workflow/test-config.yaml's grid, solved by the package."""
    import xarray as xr
    import yaml

    from contactalpha.engine.codes import END_STATES
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
