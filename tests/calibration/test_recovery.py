"""Recovery (issue 28, done-when): 95 % intervals cover the truth in >= 90 of 100 noisy replicates.

The full study (three scenes x 100 replicates, minutes) is an integration test; the default run
keeps a small version of it (one scene, 4 replicates) that still fails when the intervals or the
fit are wrong.  benchmarks/study_calibrate_recovery.py prints the same numbers.
"""

import pytest

from contactalpha.calibration.recovery import SCENES, selection_study, study


def test_small_recovery_study():
    r = study(SCENES[0], replicates=4, seed=101)
    for k in ("eps", "stiffness"):
        assert r[k]["covered"] >= 3
        assert r[k]["bias_over_width"] < 0.5


@pytest.mark.integration
@pytest.mark.parametrize("index", range(len(SCENES)))
def test_recovery_coverage_and_bias(index):
    r = study(SCENES[index], replicates=100, seed=index)
    for k in ("eps", "stiffness"):
        assert r[k]["covered"] >= 90, (k, r[k])
        assert r[k]["bias_over_width"] < 0.1, (k, r[k])


@pytest.mark.integration
@pytest.mark.parametrize("index", range(len(SCENES)))
def test_selection_picks_the_law_that_made_the_data(index):
    s = selection_study(SCENES[index], replicates=50, seed=100 + index)
    assert s["right"]["hc_eps"] >= 48, s
    assert s["right"]["constant_e"] >= 48, s
