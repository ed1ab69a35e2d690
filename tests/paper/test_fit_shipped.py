"""The shipped refit constants (model shen_refit) against a fresh refit (paper/fit/shipped.py).

A run never rewrites the shipped file (issue 15, item 6), so the test suite is what notices
when the shipped constants are no longer the refit of the surface the code computes: a fresh
refit on the default grid must land within SHIPPED_TOL_SE standard errors of them.
"""

import copy

import numpy as np
import pytest
import yaml

from contactalpha.models import shen
from contactalpha.models.shen import load_refit
from contactalpha.paper.fit import compute as fit
from contactalpha.paper.fit import report as fit_report
from contactalpha.paper.fit.shipped import SHIPPED_TOL_SE, agreement_markdown, shipped_agreement
from contactalpha.paper.surface.compute import compute_surface, grid_from_config
from contactalpha.provenance import PACKAGE_DIR

CONFIG = yaml.safe_load((PACKAGE_DIR.parents[1] / "config.yaml").read_text())


def _report(values, se=1.0, surface=None):
    """A minimal refit report: the shipped file's reading, grid and fit settings."""
    shipped = load_refit()
    zero = values.pop("zero_load_exp")
    return {
        "surface": surface or dict(shipped["surface"]),
        "settings": dict(shipped["fit"]),
        "reading": {"used": shipped["reading"]},
        "eq40": {"constants": {k: {"refit": v, "se": se} for k, v in values.items()}},
        "zero_load": {"constants": {"zero_load_exp": {"refit": zero, "se": se}}},
    }


def _shipped_values():
    shipped = load_refit()
    keys = shen.reading_constants(shipped["reading"])
    return {**{k: shipped["constants"][k] for k in keys}, "zero_load_exp": shipped["zero_load_exp"]}


def test_identical_constants_are_reported_as_the_same_bits():
    result = shipped_agreement(_report(_shipped_values()), load_refit())
    assert result["identical"] and result["max_in_se"] == 0.0 and not result["stale"]
    assert "bit for bit" in agreement_markdown(result)


@pytest.mark.parametrize(("shift_se", "stale"), [(0.5 * SHIPPED_TOL_SE, False), (2 * SHIPPED_TOL_SE, True)])
def test_a_constant_moved_by_a_fraction_of_its_standard_error(shift_se, stale):
    values = _shipped_values()
    values["a"] += shift_se * 0.07  # SE 0.07
    result = shipped_agreement(_report(values, se=0.07), load_refit())
    assert result["stale"] is stale
    assert result["max_in_se"] == pytest.approx(shift_se, rel=1e-6)
    assert ("snakemake -c2 ship" in agreement_markdown(result)) is stale


def test_a_constant_without_standard_error_must_be_identical():
    values = _shipped_values()
    values["beta"] *= 1 + 1e-15
    result = shipped_agreement(_report(values, se=None), load_refit())
    assert result["stale"] and result["max_in_se"] == np.inf


def test_a_refit_of_another_grid_is_not_compared():
    surface = {**load_refit()["surface"], "n_xi": 4}
    values = _shipped_values()
    values["a"] += 100.0
    result = shipped_agreement(_report(values, surface=surface), load_refit())
    assert not result["comparable"] and not result["stale"]
    assert "n_xi: 4 here, 124 shipped" in agreement_markdown(result)


def test_bad_tolerance_names_value_and_range():
    with pytest.raises(ValueError, match=r"tol_se = 0 is outside the valid range \(0, inf\)"):
        shipped_agreement(_report(_shipped_values()), load_refit(), tol_se=0)


@pytest.fixture(scope="module")
def fresh_report():
    """The fits behind the shipped file, redone on the default surface as the workflow does them.

    Only the two fits whose constants are shipped (Eq. 40 by continuation, the zero-load
    exponent), not the whole ``refit_report`` (its per-section fits take four times longer).
    """
    section = CONFIG["surface"]
    eps, xi = grid_from_config(section)
    ds = compute_surface(eps, xi, **section["solver"])
    weights, loss = CONFIG["fit"]["weights"], CONFIG["fit"]["loss"]
    eq40 = fit.fit_eq40_surface(ds, shen.BEST_READING, weights=weights, loss=loss)
    loaded, unloaded, _ = fit.surface_points(ds, weights=weights)
    zero = fit.fit_zero_load(np.unique(np.concatenate([unloaded.eps, loaded.eps])))
    fit.require_converged(eq40, zero)
    entry = {k: {"refit": v, "se": se} for (k, v), se in zip(eq40.values().items(), eq40.se, strict=True)}
    return {
        "surface": fit_report.surface_info(ds),
        "settings": {"weights": weights, "loss": loss},
        "reading": {"used": shen.BEST_READING},
        "eq40": {"constants": entry},
        "zero_load": {"constants": {"zero_load_exp": {"refit": zero.x[0], "se": zero.se[0]}}},
    }


def test_a_fresh_refit_of_the_default_surface_is_the_shipped_one_within_its_tolerance(fresh_report):
    result = shipped_agreement(copy.deepcopy(fresh_report), load_refit())
    print("\n" + agreement_markdown(result))
    assert result["comparable"], result["differences"]
    assert not result["stale"], agreement_markdown(result)
    # Every constant has a standard error on the default grid, and agrees to far better than it.
    assert all(np.isfinite(r["se"]) and r["se"] > 0 for r in result["rows"])
    assert result["max_in_se"] <= SHIPPED_TOL_SE
