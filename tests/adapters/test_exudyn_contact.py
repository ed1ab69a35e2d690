"""Our alpha inside Exudyn's ObjectContactSphereSphere: a few impacts in the engine.

Skipped with the reason when Exudyn is missing, except under CI=true (tests/conftest.py).
"""

import pytest

from contactalpha import impact
from contactalpha.adapters.engine_conventions import exudyn_alpha, exudyn_restitution_input
from contactalpha.scene.ball import Scene
from contactalpha.studies.engines.compute import exact_alpha

# Heavy (workflow runs, compiles, real engines): run by `pytest -m integration` (.ci/run).
pytestmark = pytest.mark.integration

BALL = Scene()  # the paper's ball
M, R, K, V, G = BALL.mass, BALL.radius, BALL.stiffness, BALL.approach_speed, BALL.gravity
FAST = {"tolerance": 1e-9, "steps_per_tstar": 200, "window": 12.0}


@pytest.fixture(scope="module")
def ex(exudyn):
    from contactalpha.adapters import exudyn_contact

    return exudyn_contact


@pytest.mark.parametrize("force", [0.1, 495.0])
def test_static_penetration_confirms_the_stiffness(ex, force):
    delta = ex.static_penetration(M, R, K, G, force)
    assert delta == pytest.approx((M * (G + force / M) / K) ** (2 / 3), rel=1e-9)


@pytest.mark.parametrize("solver", ["dopri5", "generalized_alpha"])
def test_separating_impact_delivers_the_target_eps(ex, solver):
    xi, alpha, _ = exact_alpha(BALL, 0.5, 60.0)
    res, samples = ex.drop_impact(M, R, K, V, exudyn_restitution_input(alpha), G, 60.0, solver=solver, **FAST)
    assert res.state == "separation"
    assert abs(res.eps - 0.5) <= 1e-5
    assert res.e_n == pytest.approx(-float(impact(alpha, xi).v_end), abs=1e-5)


def test_connector_records_the_impact_speed_itself_a_hair_above_the_true_one(ex):
    xi, alpha, _ = exact_alpha(
        BALL, 0.5, 0.1
    )  # a long flight after the impact: no second touchdown in the window
    _, samples = ex.drop_impact(M, R, K, V, exudyn_restitution_input(alpha), G, 0.1, **FAST)
    recorded = samples.extra["last_recorded_impact_speed"]
    assert V < recorded < V * (1 + 1e-5)


def test_impact_predicted_nonseparating_does_not_separate(ex):
    xi, alpha, _ = exact_alpha(BALL, 0.5, 495.0)
    assert impact(alpha, xi).state == "nonseparation"
    res, samples = ex.drop_impact(M, R, K, V, exudyn_restitution_input(alpha), G, 495.0, **FAST)
    assert res.state != "separation" and not samples.extra["separated_later"]
    assert abs(res.eps - 0.5) <= 1e-4


@pytest.mark.parametrize("model", [1, 2])
def test_builtin_restitution_delivers_what_the_package_predicts_for_its_alpha(ex, model):
    xi, _, _ = exact_alpha(BALL, 0.3, 0.1)
    res, _ = ex.drop_impact(M, R, K, V, 0.3, G, 0.1, impact_model=model, **FAST)
    assert res.eps == pytest.approx(float(impact(exudyn_alpha(0.3, model), xi).eps), abs=1e-5)
    assert abs(res.eps - 0.3) > (0.2 if model == 1 else 0.005)


def test_unknown_solver_is_named(ex):
    with pytest.raises(ValueError, match="solver = 'rk4'"):
        ex.drop_impact(M, R, K, V, 0.5, G, 0.1, solver="rk4")


@pytest.mark.parametrize("solver", ["dopri5", "generalized_alpha"])
def test_a_stiff_steel_contact_runs_at_the_default_settings(ex, solver):
    """Issue 29, also: k = 2e10 N/m^1.5 stopped with SolverError (Exudyn's absolute 1e-8 s step floor)."""
    steel = Scene(stiffness=2e10)
    xi, alpha, _ = exact_alpha(steel, 0.5, 5.1)
    res, _ = ex.drop_impact(
        steel.mass, steel.radius, steel.stiffness, steel.approach_speed, exudyn_restitution_input(alpha),
        steel.gravity, 5.1, solver=solver,
    )  # fmt: skip
    assert res.state == "separation"
    assert abs(res.eps - 0.5) <= 1e-5
    assert res.e_n == pytest.approx(-float(impact(alpha, xi).v_end), abs=1e-5)
