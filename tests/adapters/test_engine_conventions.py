"""Conversions of alpha into OpenSim's and Exudyn's parameters: pure formulas, no engine needed."""

import numpy as np
import pytest

from contactalpha.adapters.engine_conventions import (
    exudyn_alpha,
    exudyn_restitution_input,
    opensim_alpha,
    opensim_dissipation,
    opensim_hertz_stiffness,
    opensim_stiffness,
)

ALPHAS = np.concatenate([[0.0], np.geomspace(1e-4, 1e4, 200), [8.0 / 3.0]])


def test_exudyn_model2_input_inverts_its_mapping_over_every_alpha():
    e = exudyn_restitution_input(ALPHAS, 2)
    assert np.all((e > 0) & (e <= 1))
    np.testing.assert_allclose(exudyn_alpha(e, 2), ALPHAS, rtol=1e-12, atol=1e-15)


def test_exudyn_model2_branches_meet_at_one_third_and_fall_monotonically():
    third = 1.0 / 3.0
    assert exudyn_alpha(third, 2) == pytest.approx(8.0 / 3.0, rel=1e-14)
    assert exudyn_alpha(third * (1 + 1e-12), 2) == pytest.approx(8.0 / 3.0, rel=1e-10)
    e = np.linspace(1e-3, 1.0, 2001)
    assert np.all(np.diff(exudyn_alpha(e, 2)) < 0)
    assert exudyn_alpha(1.0, 2) == 0.0


def test_exudyn_model1_is_hunt_crossley_and_stops_at_three_halves():
    assert exudyn_alpha(0.5, 1) == pytest.approx(0.75)
    assert exudyn_restitution_input(0.75, 1) == pytest.approx(0.5)
    with pytest.raises(ValueError, match=r"alpha = 1\.5 is outside the valid range \[0\.0, 1\.5\)"):
        exudyn_restitution_input(1.5, 1)


@pytest.mark.parametrize("bad", [{"impact_model": 0}, {"impact_model": 3}])
def test_exudyn_unknown_impact_model_is_named(bad):
    with pytest.raises(ValueError, match="impact_model"):
        exudyn_alpha(0.5, **bad)


def test_exudyn_restitution_out_of_range_is_named():
    with pytest.raises(ValueError, match=r"restitution = 0\.0"):
        exudyn_alpha(0.0)


def test_opensim_stiffness_gives_back_the_hertz_stiffness_through_simbodys_combination():
    k, r = 1.4e8, 0.08
    e = opensim_stiffness(k, r)
    assert e == pytest.approx(3 * k / np.sqrt(2 * r), rel=1e-15)
    assert opensim_hertz_stiffness(e, e, r) == pytest.approx(k, rel=1e-14)


def test_opensim_combination_limits():
    # A rigid partner leaves the soft geometry's modulus; two spheres combine their radii.
    e, r = 2.0e9, 0.05
    assert opensim_hertz_stiffness(e, 1e30, r) == pytest.approx(4 / 3 * np.sqrt(r) * e, rel=1e-12)
    two = opensim_hertz_stiffness(e, e, r, r)
    assert two == pytest.approx(4 / 3 * np.sqrt(r / 2) * e / 2**1.5, rel=1e-14)


def test_opensim_dissipation_round_trip_and_units():
    c = opensim_dissipation(1.5, 0.5)
    assert c == pytest.approx(2.0, rel=1e-15)  # 2 alpha / (3 v), s/m
    assert opensim_alpha(c, 0.5) == pytest.approx(1.5, rel=1e-15)
    # The same c gives a smaller alpha to a slower impact: it must be reset per impact.
    assert opensim_alpha(c, 0.25) == pytest.approx(0.75)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: opensim_stiffness(-1.0, 0.08), r"stiffness = -1\.0"),
        (lambda: opensim_stiffness(1e8, 0.0), r"radius = 0\.0"),
        (lambda: opensim_dissipation(-0.1, 0.5), r"alpha = -0\.1"),
        (lambda: opensim_dissipation(0.5, np.nan), r"approach_speed = nan"),
        (lambda: opensim_hertz_stiffness(1e9, 1e9, 0.08, -2.0), r"radius_2 = -2\.0"),
    ],
)
def test_bad_inputs_name_the_value(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_scalar_fast_paths_are_the_array_paths_bit_for_bit():
    # alpha on both impactModel-2 branches (8/3 is the switch) and at 0.
    alphas = np.array([0.0, 1e-9, 0.3721473105581984, 1.0, 8.0 / 3.0, 2.7, 50.0, 1e6])
    speeds = np.array([1e-3, 0.5, 3.7])
    for a in alphas:
        assert exudyn_restitution_input(float(a)) == exudyn_restitution_input(np.array([a]))[0]
        for v in speeds:
            assert (
                opensim_dissipation(float(a), float(v))
                == opensim_dissipation(np.array([a]), np.array([v]))[0]
            )
    with pytest.raises(ValueError, match="alpha"):
        exudyn_restitution_input(-1.0)
    with pytest.raises(ValueError, match="approach_speed"):
        opensim_dissipation(0.3, 0.0)
