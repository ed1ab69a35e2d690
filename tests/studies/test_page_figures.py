"""The engine pages' figures: the right runs, variables and loads of the round-trip datasets."""

import numpy as np
import xarray as xr

from contactalpha.studies.engines.page_figures import page_figure, page_series


def _roundtrip():
    runs = ["opensim_exact", "opensim_hunt_crossley"]
    eps, forces = [0.3, 0.5], [0.1, 5.1, 60.0, 495.0]
    measured = np.arange(16.0).reshape(2, 2, 4)
    return xr.Dataset(
        {
            "eps_measured": (("run", "epsilon", "force"), measured),
            "xi": (("epsilon", "force"), np.tile([0.02, 0.04, 0.23, 0.8], (2, 1))),
        },
        coords={"run": runs, "epsilon": eps, "force": forces},
        attrs={"engine": "opensim"},
    )


def _stepping():
    shape = (3, 3)
    return xr.Dataset(
        {
            "e_n_refined": (("target", "load"), np.full(shape, 0.5)),
            "e_n_usual": (("target", "load"), np.arange(9.0).reshape(shape)),
            "xi": (("target", "load"), np.full(shape, 0.1)),
        },
        coords={"target": [0.2, 0.5, 0.8], "load": [0.05, 0.3, 0.6]},
        attrs={"engine": "drake"},
    )


def test_roundtrip_series_take_ours_and_the_usual_run_at_the_two_forces():
    series = page_series(_roundtrip())
    assert [(s.usual, s.load.split(" (")[0]) for s in series] == [
        (False, "F = 0.1 N"), (True, "F = 0.1 N"), (False, "F = 60 N"), (True, "F = 60 N"),
    ]  # fmt: skip
    np.testing.assert_array_equal(series[1].delivered, [8.0, 12.0])  # hunt_crossley, force 0.1
    np.testing.assert_array_equal(series[2].delivered, [2.0, 6.0])  # exact, force 60
    np.testing.assert_array_equal(series[0].target, [0.3, 0.5])


def test_stepping_series_take_the_refined_and_usual_e_n_at_the_outer_loads():
    series = page_series(_stepping())
    assert [s.load.split(" (")[0] for s in series] == ["A = 0.05"] * 2 + ["A = 0.6"] * 2
    np.testing.assert_array_equal(series[3].delivered, [2.0, 5.0, 8.0])  # usual at A = 0.6
    assert "d = 1/(e v)" in series[1].label


def test_a_skipped_engine_draws_an_empty_figure_that_says_so():
    ds = xr.Dataset(attrs={"engine": "drake", "skipped": "pydrake not installed"})
    assert page_series(ds) == []
    fig = page_figure(ds)
    assert "pydrake not installed" in fig.axes[0].get_title()
