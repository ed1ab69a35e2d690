"""critical_speed never returns a silent NaN, for any law (issue 34, R3)."""

import warnings

import numpy as np
import pytest

from contactalpha.laws import LAWS, get_law
from contactalpha.scene.threshold import CRITICAL_EPS_MIN, critical_speed, critical_speed_status

G = 9.81


def test_a_linear_hunt_crossley_boundary_is_found_below_a_failing_upper_bracket():
    law = get_law("hunt_crossley_linear")
    m, k = 0.5, 1e5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        v = critical_speed(0.5, m, k, G, law=law)
    A_b = law.load(m, k, v, G)
    assert 0.1 < A_b < 1.0
    for factor, separates in ((1.001, True), (0.999, False)):
        sol = law.damping_for(0.5, law.load_factor(law.load(m, k, factor * v, G)))
        assert sol.ok and (str(sol.state) == "separation") == separates


@pytest.mark.parametrize("law", [law.name for law in LAWS])
def test_every_law_refuses_a_restitution_below_the_searched_range(law):
    with pytest.raises(ValueError, match=f"eps = 1e-06 is outside the valid range \\[{CRITICAL_EPS_MIN}"):
        critical_speed(1e-6, 0.5, 1e5, G, law=law)


def test_a_failed_search_warns_with_its_status():
    with pytest.warns(RuntimeWarning, match="eps = 0.8 .*step limit exceeded"):
        v = critical_speed(0.8, 0.5, 1.4e8, G, max_steps=1)
    assert np.isnan(v)
    assert critical_speed_status(0.8, 0.5, 1.4e8, G, max_steps=1)[1].startswith("step limit exceeded")


def test_another_law_takes_the_integrator_settings_too():
    with pytest.raises(ValueError, match="rtol = -1.0"):
        critical_speed(0.5, 1.0, 1e4, G, law="kelvin_voigt", rtol=-1.0)
    with pytest.warns(RuntimeWarning, match="boundary search failed at eps = 0.5"):
        assert np.isnan(critical_speed(0.5, 1.0, 1e4, G, law="hertz_tsuji", max_steps=1))
