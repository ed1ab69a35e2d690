import numpy as np
import pytest

import contactalpha as ca
from contactalpha.paper.fig9.compute import (
    deviation_table,
    fig9_statements,
    max_deviation,
    nonseparation_mask,
    post_vs_pre,
)

EPS = np.array([0.05, 0.3, 0.6, 0.95])


@pytest.fixture(scope="module")
def ds():
    return post_vs_pre(["hunt_crossley", "hu_guo", "exact"], [0.0, 0.227, 0.91], EPS)


def test_exact_model_delivers_what_it_is_asked_for(ds):
    post = ds.eps_post.sel(model="exact")
    np.testing.assert_allclose(post, np.broadcast_to(EPS, post.shape), atol=1e-6)


def test_post_restitution_is_the_engine_run_with_the_models_alpha(ds):
    a = ca.alpha(0.3, 0.227, model="hu_guo")
    assert float(ds.alpha.sel(model="hu_guo", xi=0.227, eps_pre=0.3)) == a
    assert float(ds.eps_post.sel(model="hu_guo", xi=0.227, eps_pre=0.3)) == ca.restitution(a, 0.227)


def test_hunt_crossley_over_restitutes_at_low_eps(ds):
    dev, where = max_deviation(ds)
    assert float(dev.sel(model="hunt_crossley", xi=0.0)) > 0.3
    assert float(where.sel(model="hunt_crossley", xi=0.0)) == 0.05
    assert "| Hunt–Crossley |" in deviation_table(ds)


def test_non_separating_ends_are_marked(ds):
    mask = nonseparation_mask(ds)
    state = ds.state.sel(model="exact", xi=0.91).values
    assert mask.sel(model="exact", xi=0.91).values.tolist() == [s != 1 for s in state]
    assert not mask.sel(xi=0.0).any()  # without a load every impact separates


def test_statements_carry_verdicts(ds):
    st = fig9_statements(ds, new="hu_guo", reference="exact")
    assert all(s["holds"] in ("holds", "partly", "does not hold") for s in st)
    fixed = [s for s in st if "fixed when" in s["claim"]][0]
    assert fixed["holds"] == "holds"
