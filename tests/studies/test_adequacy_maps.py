"""Adequacy maps on a tiny surface: the same verdicts as the advisor's rule, point by point."""

import numpy as np
import pytest
import xarray as xr

from contactalpha import models
from contactalpha.engine.codes import STATE_CODES
from contactalpha.engine.driver import impact
from contactalpha.engine.solver import solve_alpha
from contactalpha.studies.adequacy import maps

COSTS = {name: 1e-6 for name in models.MODELS} | {"exact_solve": 1e-4}


def _surface(eps, xi):
    e, x = np.meshgrid(eps, xi, indexing="ij")
    sol = solve_alpha(e, x)
    state = np.vectorize(STATE_CODES.get)(sol.state).astype(np.int8)
    variables = {"alpha": (("epsilon", "xi"), sol.alpha), "state": (("epsilon", "xi"), state)}
    return xr.Dataset(variables, coords={"epsilon": eps, "xi": xi})


@pytest.fixture(scope="module")
def adequacy():
    surface = _surface([0.2, 0.5, 0.8], [0.0, 0.001, 0.2, 0.4])
    return surface, maps.compute_maps(surface, (0.01, 0.05), COSTS)


def test_exact_alpha_is_adequate_everywhere(adequacy):
    _, ds = adequacy
    assert ds["adequate"].sel(model="exact_solve").all() and ds["adequate"].sel(model="exact").all()
    assert np.allclose(ds["area_share"].sel(model="exact_solve"), 1.0)


def test_delivered_eps_is_one_impact_with_the_models_alpha(adequacy):
    _, ds = adequacy
    a = float(ds["alpha"].sel(model="hunt_crossley", epsilon=0.5, xi=0.2))
    assert a == 0.75
    d = float(ds["delivered_eps"].sel(model="hunt_crossley", epsilon=0.5, xi=0.2))
    assert d == pytest.approx(float(impact(0.75, 0.2).eps), abs=1e-14)
    ok = bool(ds["adequate"].sel(tol=0.05, model="hunt_crossley", epsilon=0.5, xi=0.2))
    assert ok == (abs(d - 0.5) <= 0.05)


def test_ignoring_the_load_and_xi_ignore(adequacy):
    _, ds = adequacy
    # At xi = 0 the exact unloaded alpha is the exact alpha: always adequate.
    assert ds["ignore_adequate"].sel(xi=0.0).all()
    row = ds["ignore_adequate"].sel(tol=0.01).values
    expected = [ds.xi.values[np.argmin(r) - 1] if not r.all() else ds.xi.values[-1] for r in row.astype(bool)]
    assert np.array_equal(ds["xi_ignore"].sel(tol=0.01).values, expected)
    # A looser tolerance never shrinks xi_ignore.
    assert np.all(ds["xi_ignore"].sel(tol=0.05).values >= ds["xi_ignore"].sel(tol=0.01).values)


def test_cheapest_is_an_adequate_model(adequacy):
    _, ds = adequacy
    names = list(ds.model.values)
    for t in ds.tol.values:
        best = ds["cheapest"].sel(tol=t).values
        for idx in np.ndindex(best.shape):
            assert best[idx] >= 0  # the exact models are adequate everywhere
            assert ds["adequate"].sel(tol=t, model=names[best[idx]]).values[idx] == 1
            assert names[best[idx]] != "exact_solve"  # 100x the cost of the others


def test_xi_ignore_of_rows():
    xi = np.array([0.0, 0.1, 0.2])
    adequate = np.array([[1, 1, 1], [1, 0, 1], [0, 1, 1]], dtype=bool)
    got = maps.xi_ignore(xi, adequate)
    assert got[0] == 0.2 and got[1] == 0.0 and np.isnan(got[2])
