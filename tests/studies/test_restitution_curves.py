"""The e_N-versus-eps data: values against the SciPy oracle and the figure's content."""

import json
import re

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.baselines.reference import impact_scipy
from contactalpha.engine.boundary import separation_boundary
from contactalpha.studies.restitution.curves import restitution_curves
from contactalpha.studies.restitution.figures import restitution_figure


@pytest.fixture(scope="module")
def curves():
    return restitution_curves(xi=(0.0, 0.3, 0.8), n_eps=20)


def test_unloaded_e_n_is_eps_and_the_load_makes_it_smaller(curves):
    eps = curves["eps"].values
    np.testing.assert_allclose(curves["e_n"].sel(xi=0.0).values, eps, atol=1e-10)
    for xi in (0.3, 0.8):
        e_n = curves["e_n"].sel(xi=xi).values
        assert np.all(e_n[:-1] < eps[:-1])
        assert e_n[-1] == pytest.approx(1.0, abs=1e-10)  # alpha = 0: no loss (integration rtol 1e-12)
        assert np.all(np.diff(e_n[e_n > 0]) > 0)


def test_zero_below_the_boundary_positive_above(curves):
    eps = curves["eps"].values
    for xi in (0.3, 0.8):
        eps_b = float(separation_boundary(xi)[1])
        assert float(curves["eps_boundary"].sel(xi=xi)) == eps_b
        e_n = curves["e_n"].sel(xi=xi).values
        assert np.all(e_n[eps < eps_b] == 0.0)
        assert np.all(e_n[eps > eps_b] > 0.0)
    assert float(curves["eps_boundary"].sel(xi=0.0)) == 0.0
    assert float(separation_boundary(0.8)[1]) > 0.5  # the heavy load leaves points on the zero branch


@pytest.mark.parametrize("xi, k", [(0.3, 9), (0.3, 15), (0.8, 17)])
def test_separating_points_match_the_scipy_oracle(curves, xi, k):
    # The oracle at the solver's alpha restitutes the grid's eps and exits at e_N times the approach speed.
    eps = float(curves["eps"][k])
    e_n = float(curves["e_n"].sel(xi=xi)[k])
    assert e_n > 0
    ref = impact_scipy(float(ca.solve_alpha(eps, xi).alpha), xi)
    assert ref.state == "separation"
    assert ref.eps == pytest.approx(eps, abs=1e-9)
    assert -ref.v_end == pytest.approx(e_n, abs=1e-9)


def test_curves_record_their_settings_and_refuse_a_bad_grid(curves):
    # The settings that made the curves (defaults included), the grid they describe, the version.
    assert json.loads(curves.attrs["config"]) == {"xi": [0.0, 0.3, 0.8], "n_eps": 20, "tol": 1e-12}
    np.testing.assert_array_equal(curves["eps"].values, np.linspace(0.05, 1.0, 20))
    assert curves.attrs["contactalpha_version"] == ca.__version__
    assert re.fullmatch(r"\S+Z restitution_curves \(contactalpha .+\)", curves.attrs["history"])
    assert 0 < curves.attrs["compute_time_s"] < 600
    with pytest.raises(ValueError, match="n_eps = 1 "):
        restitution_curves(n_eps=1)


def test_figure_draws_one_curve_per_load_through_its_boundary(curves):
    fig = restitution_figure(curves)
    ax = fig.axes[0]
    lines = [ln for ln in ax.get_lines() if ln.get_label().startswith("ξ")]
    assert [ln.get_label() for ln in lines] == ["ξ = 0", "ξ = 0.3", "ξ = 0.8"]
    x, y = lines[2].get_data()
    eps_b = float(curves["eps_boundary"].sel(xi=0.8))
    assert eps_b in x and y[list(x).index(eps_b)] == 0.0
    np.testing.assert_array_equal(
        y[x > eps_b], curves["e_n"].sel(xi=0.8).values[curves["eps"].values > eps_b]
    )


def test_figure_legend_explains_the_dotted_boundary_lines(curves):
    fig = restitution_figure(curves)
    ax = fig.axes[0]
    dotted = [ln for ln in ax.get_lines() if ln.get_linestyle() == ":"]
    boundaries = [b for b in curves["eps_boundary"].values if b > 0]
    assert sorted(ln.get_xdata()[0] for ln in dotted) == sorted(boundaries)
    entries = dict(
        zip([t.get_text() for t in ax.get_legend().get_texts()], ax.get_legend().get_lines(), strict=True)
    )
    (label,) = [t for t in entries if t.startswith("separation boundary")]
    assert entries[label].get_linestyle() == ":" and "e_N = 0" in label
