import numpy as np
import pytest

import contactalpha as ca
from contactalpha.baselines.fixedstep import STATUS, impact_rk4, rk4_impact_kernel

CASES = [  # (alpha, xi, end state): one per end state
    (0.5, 0.2, "separation"),
    (5.0, 0.2, "nonseparation"),
    (50.0, 0.2, "creep"),
    (500.0, 0.2, "no_restitution"),
    (10.0, 0.0, "separation"),
]


@pytest.mark.parametrize("alpha, xi, state", CASES)
def test_rk4_agrees_with_engine_in_every_end_state(alpha, xi, state):
    ours = ca.impact(alpha, xi)
    rk = impact_rk4(alpha, xi, h=1e-3)
    assert ours.state == state
    assert rk.status == "ok"
    assert rk.state == state
    assert rk.eps == pytest.approx(ours.eps, abs=1e-9)
    assert rk.x_max == pytest.approx(ours.x_max, rel=1e-8)


def test_rk4_converges_with_order_near_five_halves_from_the_hertz_singularity():
    # x^{3/2} is not smooth at x = 0 (start and separation): local error
    # h^{7/2} there caps RK4's global order at about 2.5 instead of 4.
    hs = np.array([0.04, 0.02, 0.01, 0.005, 0.0025])
    err = [abs(impact_rk4(10.0, 0.0, h=h).eps - ca.restitution_exact(10.0)) for h in hs]
    order = np.polyfit(np.log(hs), np.log(err), 1)[0]
    assert 2.2 < order < 2.9


def test_step_too_large_for_stiff_damping_is_a_missed_event():
    r = impact_rk4(500.0, 0.2, h=0.1)
    assert r.status == "missed event"
    assert r.state == "failed"
    assert np.isnan(r.eps)


def test_step_budget_is_reported_as_step_limit():
    r = impact_rk4(50.0, 0.2, h=1e-3, max_steps=100)
    assert r.status == "step limit exceeded"
    assert r.steps == 100
    assert np.isnan(r.eps)


def test_non_finite_state_is_reported_by_the_kernel():
    out = rk4_impact_kernel(np.nan, 0.1, 1e-3, 1000, 1e-9)
    assert STATUS[int(out[2])] == "non-finite state"
    assert np.isnan(out[0])


def test_creep_rest_tolerance_controls_the_stop():
    loose = impact_rk4(50.0, 0.2, h=1e-3, rest_tol=1e-4)
    tight = impact_rk4(50.0, 0.2, h=1e-3, rest_tol=1e-10)
    assert loose.state == tight.state == "creep"
    assert loose.steps < tight.steps


@pytest.mark.parametrize("kw, name", [({"h": 0.0}, "h"), ({"h": 2.0}, "h"), ({"rest_tol": -1.0}, "rest_tol")])
def test_bad_settings_raise_naming_the_value(kw, name):
    with pytest.raises(ValueError, match=name):
        impact_rk4(1.0, 0.2, **kw)


def test_baseline_writes_its_own_force_law_and_load():
    # A baseline that imported the engine's force law could not catch an error in it.
    import ast
    import inspect

    import contactalpha.baselines.fixedstep as fixedstep

    tree = ast.parse(inspect.getsource(fixedstep))
    imported = {
        (node.module, alias.name)
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom)
        for alias in node.names
    }
    engine = {name for module, name in imported if module and module.startswith("contactalpha.engine")}
    assert engine <= {"END_STATES", "ImpactResult"}, engine


@pytest.mark.parametrize("xi", [0.0, 1e-6, 0.2, 0.9])
def test_own_load_and_rest_position_agree_with_the_paper(xi):
    from contactalpha.baselines.fixedstep import acceleration, load_of_xi, rest_position

    A = load_of_xi(xi)
    # Eq. 10 scaled: xi = A x_m / (1/2 + A x_m) with x_m = (1 - xi)^(-2/5) the undamped maximum.
    x_m = (1.0 - xi) ** -0.4
    assert A * x_m / (0.5 + A * x_m) == pytest.approx(xi, rel=1e-14, abs=0)
    if xi > 0:
        assert acceleration(rest_position(A), 0.3, A, 0.0) == pytest.approx(0.0, abs=1e-14 * A)
    # Hertz constant 5/4 and damping: x'' at x = 1, v = -2, alpha = 0.5 is A - 1.25 (1 - 1).
    assert acceleration(1.0, -2.0, A, 0.5) == pytest.approx(A, abs=1e-15)
    assert acceleration(1.0, 0.0, A, 0.5) == pytest.approx(A - 1.25, abs=1e-15)
    assert acceleration(-1e-3, 5.0, A, 0.5) == A  # out of contact
