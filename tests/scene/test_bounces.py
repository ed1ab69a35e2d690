"""Rest prediction without time stepping, against the time-domain ball simulation."""

import numpy as np
import pytest

from contactalpha.scene.ball import Scene, simulate
from contactalpha.scene.bounces import predict_bounces
from contactalpha.scene.threshold import critical_speed
from contactalpha.studies.adequacy.rest_check import check_rest_prediction, random_scenes


def _agree(result):
    assert np.all(result["simulated_end"] == "rests")
    assert np.array_equal(result["contacts_predicted"], result["contacts_simulated"])
    assert np.array_equal(result["bounces_predicted"], result["bounces_simulated"])
    assert np.max(result["rest_rel_diff"]) <= 1e-6


def test_ten_random_scenes_agree_with_the_simulation():
    result = check_rest_prediction(random_scenes(10, seed=1))
    assert result["contacts_predicted"].max() > 5  # some scenes really bounce
    _agree(result)


@pytest.mark.slow
def test_two_hundred_random_scenes_agree_with_the_simulation():
    _agree(check_rest_prediction(random_scenes(200, seed=0)))


def test_case_a_count_without_simulation():
    scene = Scene(eps=0.8, force=5.1)
    pred = predict_bounces(scene, "shen_published")
    # The paper: "10 collisions occur in case A" -- 10 rebounds, then an 11th contact that stays.
    assert (pred.bounces, pred.contacts) == (10, 11)
    run = simulate(scene, "shen_published", "A")
    assert (run.rebounds, run.count) == (pred.bounces, pred.contacts)
    assert pred.time_to_rest == pytest.approx(run.end_time, rel=1e-9)


def test_exact_model_stops_at_the_first_approach_below_the_critical_speed():
    scene = Scene(eps=0.6, force=40.0, approach_speed=1.0)
    pred = predict_bounces(scene, "exact_solve")
    v_crit = critical_speed(scene.eps, scene.mass, scene.stiffness, scene.accel)
    assert np.all(pred.approach_speeds[:-1] > v_crit) and pred.approach_speeds[-1] < v_crit
    assert pred.states[-1] != "separation" and set(pred.states[:-1]) == {"separation"}
    # Flights are parabolas: each lasts 2 u / a, and speeds fall monotonically.
    assert np.allclose(pred.flight_durations, 2 * pred.rebound_speeds[:-1] / scene.accel, rtol=0, atol=0)
    assert np.all(np.diff(pred.approach_speeds) < 0)
    total = pred.contact_durations.sum() + pred.flight_durations.sum()
    assert pred.time_to_rest == pytest.approx(total, rel=1e-14)
