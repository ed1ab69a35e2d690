"""Our alpha inside Simbody, through OpenSim's HuntCrossleyForce: a few impacts in the engine.

Skipped with the reason when OpenSim is missing, except under CI=true (tests/conftest.py).
"""

from dataclasses import replace

import numpy as np
import pytest

from contactalpha import impact
from contactalpha.adapters.engine_conventions import opensim_dissipation, opensim_stiffness
from contactalpha.scene.ball import Scene, simulate
from contactalpha.studies.engines.compute import exact_alpha

# Heavy (workflow runs, compiles, real engines): run by `pytest -m integration` (.ci/run).
pytestmark = pytest.mark.integration

BALL = Scene()  # the paper's ball
M, R, K, V, G = BALL.mass, BALL.radius, BALL.stiffness, BALL.approach_speed, BALL.gravity
# Coarse but ample for the checks below: each impact takes ~0.1 s.
FAST = {"accuracy": 1e-8, "per_tstar": 100, "window": 12.0}


@pytest.fixture(scope="module")
def oh(opensim):
    from contactalpha.adapters import opensim_hc

    return opensim_hc


@pytest.mark.parametrize("force", [0.1, 495.0])
def test_static_penetration_confirms_the_stiffness_conversion(oh, force):
    delta = oh.static_penetration(M, R, K, G, force)
    assert delta == pytest.approx((M * (G + force / M) / K) ** (2 / 3), rel=1e-9)


def test_engine_reads_the_parameters_we_set(oh):
    drop = oh.build_drop(M, R, K, 0.37, G, 5.1)
    hc = drop.model.getForceSet().get("contact")
    hc = type(oh._opensim().HuntCrossleyForce()).safeDownCast(hc)
    assert hc.getStiffness() == pytest.approx(opensim_stiffness(K, R), rel=1e-15)
    assert hc.getDissipation() == pytest.approx(0.37, rel=1e-15)


def test_separating_impact_delivers_the_target_eps_and_the_package_e_n(oh):
    xi, alpha, _ = exact_alpha(BALL, 0.5, 60.0)
    res, samples = oh.drop_impact(M, R, K, V, opensim_dissipation(alpha, V), G, 60.0, **FAST)
    assert res.state == "separation"
    assert abs(res.eps - 0.5) <= 1e-6
    assert res.e_n == pytest.approx(-float(impact(alpha, xi).v_end), abs=1e-6)
    assert samples.seconds > 0


def test_impact_predicted_nonseparating_does_not_separate(oh):
    xi, alpha, _ = exact_alpha(BALL, 0.3, 60.0)
    assert impact(alpha, xi).state == "nonseparation"
    res, samples = oh.drop_impact(M, R, K, V, opensim_dissipation(alpha, V), G, 60.0, **FAST)
    assert res.state != "separation" and not samples.extra["separated_later"]
    assert samples.extra["min_delta_after_end"] > 0
    assert abs(res.eps - 0.3) <= 1e-6


def test_hunt_crossley_reading_misses_the_target_as_the_package_predicts(oh):
    xi, _, _ = exact_alpha(BALL, 0.5, 5.1)
    alpha_hc = 1.5 * (1 - 0.5)
    res, _ = oh.drop_impact(M, R, K, V, (1 - 0.5) / V, G, 5.1, **FAST)
    assert res.eps == pytest.approx(float(impact(alpha_hc, xi).eps), abs=1e-6)
    assert res.eps - 0.5 > 0.1


def test_case_a_matches_the_package_count_and_time_to_rest(oh):
    scene = replace(Scene(), eps=0.8, force=5.1, t_end=0.3)
    run = oh.bounce(scene, "exact", settle=20, **FAST)
    ours = simulate(scene, "exact", "A")
    assert run["count"] == ours.count == 11
    assert run["rebounds"] == ours.rebounds == 10
    assert run["rest_time"] == pytest.approx(ours.end_time, abs=1e-6)
    assert not run["left_ground_after_rest"]
    np.testing.assert_allclose(run["contacts"]["eps"], 0.8, atol=1e-5)
    np.testing.assert_allclose(run["contacts"]["v_in"], ours.collisions["v_in"], rtol=1e-5)


def test_case_a_with_the_first_dissipation_kept_does_not_come_to_rest(oh):
    scene = replace(Scene(), eps=0.8, force=5.1, t_end=0.3)
    run = oh.bounce(scene, "exact", per_impact=False, settle=20, **FAST)
    assert np.isnan(run["rest_time"]) and run["count"] > 11
    # alpha = (3/2) c v_in falls with the approach speed, so eps climbs above the target.
    assert np.all(np.diff(run["contacts"]["eps"]) > 0)
