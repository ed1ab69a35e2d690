"""Adequacy study reports: the "small xi" verdicts, tables, thresholds and figures carry the maps' numbers."""

import numpy as np
import pytest
import xarray as xr

import contactalpha as ca
from contactalpha import models
from contactalpha.paper.statements import FAILS, HOLDS, NOT_CHECKED, PARTLY
from contactalpha.scene.threshold import critical_speed
from contactalpha.studies.adequacy import figures, maps, report

COSTS = {name: 1e-6 for name in models.MODELS} | {"exact_solve": 1e-4}


def _ignore_maps(xi, rows, tols=(0.01,)):
    """A maps dataset with only what the claim needs: ignore_adequate rows (same at every tol)."""
    ok = np.array(rows, dtype=np.int8)
    ignore = np.broadcast_to(ok, (len(tols), *ok.shape))
    eps = np.linspace(0.2, 0.8, ok.shape[0])
    return xr.Dataset(
        {
            "ignore_adequate": (("tol", "epsilon", "xi"), ignore),
            "xi_ignore": (("tol", "epsilon"), np.array([maps.xi_ignore(xi, ok.astype(bool))] * len(tols))),
        },
        coords={"tol": list(tols), "epsilon": eps, "xi": xi},
    )


def test_small_claim_verdicts_follow_xi_ignore():
    xi = np.array([0.0, 0.05, 0.09, 0.2, 0.6])
    # row 0: adequate below 0.1 and in the moderate level too; row 1: fails at 0.09; row 2: fails at 0.2.
    ds = _ignore_maps(xi, [[1, 1, 1, 1, 0], [1, 1, 0, 0, 0], [1, 1, 1, 0, 0]])
    small, beyond = report.small_claim_statements(ds)
    assert small.verdict == PARTLY and "holds at 2 of 3 ε" in small.evidence
    assert "ξ_ignore is as small as 0.05" in small.evidence
    assert beyond.verdict == PARTLY and "at 2 of 3 ε" in beyond.evidence
    all_good = report.small_claim_statements(_ignore_maps(xi, [[1, 1, 1, 1, 1]] * 2))
    assert [s.verdict for s in all_good] == [HOLDS, FAILS]
    none_small = report.small_claim_statements(_ignore_maps(xi, [[1, 0, 0, 0, 0]] * 2))
    assert none_small[0].verdict == FAILS


def test_claims_without_grid_columns_are_not_checked():
    xi = np.array([0.0, 0.6])  # no moderate column
    _, beyond = report.small_claim_statements(_ignore_maps(xi, [[1, 0]]))
    assert beyond.verdict == NOT_CHECKED


@pytest.fixture(scope="module")
def tiny_maps():
    from contactalpha.engine.codes import STATE_CODES
    from contactalpha.engine.solver import solve_alpha

    eps, xi = np.array([0.2, 0.5, 0.8]), np.array([0.0, 0.001, 0.2, 0.4])
    e, x = np.meshgrid(eps, xi, indexing="ij")
    sol = solve_alpha(e, x)
    state = np.vectorize(STATE_CODES.get)(sol.state).astype(np.int8)
    surface = xr.Dataset(
        {"alpha": (("epsilon", "xi"), sol.alpha), "state": (("epsilon", "xi"), state)},
        coords={"epsilon": eps, "xi": xi},
    )
    return surface, maps.compute_maps(surface, (0.01, 0.05), COSTS)


def test_one_parallel_pass_equals_the_per_model_impacts(tiny_maps):
    surface, ds = tiny_maps
    x = np.broadcast_to(surface["xi"].values, surface["alpha"].shape)
    for name in ("hunt_crossley", "shen_published", "exact"):
        eps, state = maps.delivered(maps.model_alpha(name, surface), x)
        np.testing.assert_array_equal(ds["delivered_eps"].sel(model=name).values, eps)
        np.testing.assert_array_equal(ds["state"].sel(model=name).values, state)
    # "ignore the load" is exact_unloaded's alpha: the shared impacts give the same numbers.
    np.testing.assert_array_equal(ds["ignore_alpha"].values, ds["alpha"].sel(model="exact_unloaded").values)
    np.testing.assert_array_equal(
        ds["ignore_delivered_eps"].values, ds["delivered_eps"].sel(model="exact_unloaded").values
    )


def test_subgrid_keeps_every_small_xi_column():
    eps = np.round(np.arange(1, 10) / 10, 2)
    xi = np.array([0.0, 1e-4, 1e-3, 1e-2, 0.1, 0.2, 0.3, 0.4, 0.5])
    surface = xr.Dataset({"alpha": (("epsilon", "xi"), np.zeros((9, 9)))}, coords={"epsilon": eps, "xi": xi})
    sub = maps.subgrid(surface, 2, 2, 0.01)
    np.testing.assert_array_equal(sub["epsilon"].values, eps[::2])
    np.testing.assert_array_equal(sub["xi"].values, [0.0, 1e-4, 1e-3, 1e-2, 0.1, 0.3, 0.5])
    assert maps.subgrid(surface, 1, 1).sizes == surface.sizes
    with pytest.raises(ValueError, match="eps_stride = 0"):
        maps.subgrid(surface, 0, 1)
    with pytest.raises(ValueError, match="xi_stride = 1.5"):
        maps.subgrid(surface, 1, 1.5)


def test_tables_print_the_maps_numbers(tiny_maps):
    _, ds = tiny_maps
    table = report.xi_ignore_table(ds, [0.5, 0.79])
    for t in ds["tol"].values:
        for e in (0.5, 0.8):
            value = float(ds["xi_ignore"].sel(tol=t, epsilon=e))
            assert f"{value:.3g}" in table.splitlines()[2 + (e == 0.8)]
    shares = report.share_table(ds)
    row = next(line for line in shares.splitlines() if line.startswith("| `hu_guo`"))
    assert row.split("|")[2].strip() == f"{float(ds['area_share'].sel(tol=0.01, model='hu_guo')):.1%}"
    for t, s in report.cheapest_shares(ds).items():
        assert sum(s.values()) == pytest.approx(1.0) and "none" not in s  # exact models always adequate
        best = ds["cheapest"].sel(tol=t).values
        for i, name in enumerate(ds.model.values):
            assert s.get(name, 0.0) == pytest.approx(np.mean(best == i))


def test_the_report_has_no_hertz_formula_of_its_own():
    """One ``hertz_stiffness`` (scene.hertz): the report's scenes go through it."""
    assert not hasattr(report, "hertz_stiffness") or report.hertz_stiffness is ca.hertz_stiffness


def test_scene_thresholds_are_the_critical_speed():
    scene = {"name": "s", "eps": 0.6, "mass": 0.2, "radius": 0.01, "modulus": 1e8, "accel": 9.81}
    scene["source"] = "x"
    (row,) = report.scene_thresholds([scene])
    k = 4.0 / 3.0 * 1e8 * 0.1
    assert row.stiffness == pytest.approx(k, rel=1e-15)
    assert row.v_crit == pytest.approx(critical_speed(0.6, 0.2, k, 9.81), rel=1e-12)
    assert row.v_crit_fit == pytest.approx(row.v_crit, rel=1e-3)
    assert row.status == "ok"
    text = report.thresholds_markdown([row])
    assert f"{row.v_crit:.4g}" in text and f"{2.0 / row.v_crit:.3g}" in text
    with pytest.raises(ValueError, match="eps"):
        report.scene_thresholds([scene | {"eps": 1.2}])


def test_figures_draw_the_maps(tiny_maps):
    _, ds = tiny_maps
    fig = figures.adequacy_figure(ds, 0.05)
    for ax, name in zip(fig.axes, ds["model"].values, strict=False):
        drawn = np.asarray(ax.collections[0].get_array()).reshape(ds.sizes["epsilon"], ds.sizes["xi"])
        np.testing.assert_array_equal(drawn, ds["adequate"].sel(tol=0.05, model=name).values)
    fig = figures.cheapest_figure(ds)
    drawn = np.asarray(fig.axes[1].collections[0].get_array()).reshape(ds.sizes["epsilon"], ds.sizes["xi"])
    np.testing.assert_array_equal(drawn, ds["cheapest"].sel(tol=0.05))
    # The xi axis is in xi values: cells meet halfway between grid values of xi, ticks name their
    # own position, and the dotted line sits at xi = 0.1.
    ax = fig.axes[1]
    xi = ds["xi"].values
    edges = ax.collections[0].get_coordinates()[0, :, 0]
    np.testing.assert_allclose(edges[1:-1], 0.5 * (xi[1:] + xi[:-1]), rtol=1e-12)
    assert np.all((edges[:-1] < xi) & (xi < edges[1:]))
    assert [float(t.get_text()) for t in ax.get_xticklabels()] == list(ax.get_xticks())
    assert [ln.get_xdata()[0] for ln in ax.get_lines() if ln.get_linestyle() == ":"] == [0.1]
    assert "column" not in ax.get_xlabel()
    xi = np.array([0.0, 1e-5, 1e-3, 0.1, 0.5, 0.99])
    np.testing.assert_allclose(figures._xi_inverse(figures._xi_forward(xi)), xi, rtol=1e-9, atol=1e-15)
    assert np.all(np.diff(figures._xi_forward(xi)) > 0)
    fig = figures.xi_ignore_figure(ds)
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_ydata(), ds["xi_ignore"].sel(tol=0.01).values)
