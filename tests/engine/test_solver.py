import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import contactalpha as ca
from contactalpha.engine.solver import solve_table

EPS = np.round(np.arange(1, 100) * 0.01, 2)


def test_exact_relation_round_trips_to_machine_precision():
    eps = np.concatenate([[1e-6], EPS, [0.999999]])
    np.testing.assert_allclose(ca.restitution_exact(ca.alpha_exact(eps)), eps, rtol=0, atol=5e-16)


def test_exact_relation_asymptotes():
    # alpha -> 1/eps for small eps, and 3(1 - eps)/2 near eps = 1 (Hunt-Crossley)
    assert ca.alpha_exact(1e-4) == pytest.approx(1e4, rel=1e-12)
    assert ca.alpha_exact(1 - 1e-6) == pytest.approx(1.5e-6, rel=1e-5)


def test_zero_load_column_integrated_matches_exact_relation(paper_eps):
    s = ca.solve_alpha(paper_eps, 0.0, exact_at_zero=False)
    assert np.all(s.ok)
    assert s.alpha[0] == pytest.approx(100.0, rel=1e-3)  # eps = 0.01
    np.testing.assert_allclose(s.alpha, ca.alpha_exact(paper_eps), rtol=1e-9)


def test_zero_load_uses_the_exact_relation_without_integrating():
    s = ca.solve_alpha(0.3, 0.0)
    assert s.impacts == 0 and s.alpha == ca.alpha_exact(0.3)


# The paper's domain, with the stiff ridge near eps -> 0, xi -> 0+ resolved.
RIDGE_XI = np.concatenate([[1e-5, 1e-4, 1e-3, 3e-3, 0.005], np.linspace(0.01, 0.99, 9)])
RIDGE_EPS = np.array([0.01, 0.02, 0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99])


def test_round_trip_hits_target_to_1e_10_over_domain_and_ridge():
    E, X = np.meshgrid(RIDGE_EPS, RIDGE_XI, indexing="ij")
    s = ca.solve_alpha(E, X)
    assert np.all(s.ok), E[~s.ok]
    back = ca.restitution(s.alpha, X)
    assert np.max(abs(back - E)) < 1e-10
    # the ridge: alpha climbs by orders of magnitude over a thin layer of xi
    assert s.alpha[0, 0] < 110 and s.alpha[0, 5] > 1000


@given(eps=st.floats(0.01, 0.99), xi=st.floats(1e-6, 0.99))
def test_solver_hits_its_target_anywhere(eps, xi):
    s = ca.solve_alpha(eps, xi)
    assert s.ok
    assert abs(s.eps_reached - eps) <= 1e-12
    assert abs(ca.restitution(s.alpha, xi) - eps) <= 1e-12


def test_alpha_grows_as_eps_falls():
    s = ca.solve_alpha(EPS[::7], 0.3)
    assert np.all(np.diff(s.alpha) < 0)


def test_onset_alpha_for_zero_restitution():
    s = ca.solve_alpha(0.0, 0.2)
    assert s.ok and s.state == "no_restitution"
    just_below = ca.impact(s.alpha * (1 - 1e-9), 0.2)
    assert just_below.state != "no_restitution"
    assert just_below.eps < 1e-3
    assert ca.impact(s.alpha * (1 + 1e-9), 0.2).state == "no_restitution"


def test_split_grid_is_bit_identical():
    E, X = np.meshgrid(EPS[::11], np.linspace(0, 0.98, 8), indexing="ij")
    whole, _ = solve_table(E, X)
    parts = [solve_table(E[:, j], X[:, j])[0] for j in range(X.shape[1])]
    pieced = np.stack([p for p in parts], axis=1).reshape(-1, whole.shape[1])
    reordered = whole.reshape(E.shape + (-1,)).reshape(-1, whole.shape[1])
    assert np.array_equal(np.nan_to_num(pieced), np.nan_to_num(reordered))
    single = solve_table(E[3, 5], X[3, 5])[0]
    assert np.array_equal(np.nan_to_num(single[0]), np.nan_to_num(whole.reshape(E.shape + (-1,))[3, 5]))


def test_unreachable_target_is_an_error():
    with pytest.raises(ValueError, match="eps = 0.0 at xi = 0.0 cannot be reached"):
        ca.solve_alpha(0.0, 0.0)


@pytest.mark.parametrize(
    "eps, xi, match",
    [
        (1.5, 0.2, r"eps = 1.5 .*\[0.0, 1.0\]"),
        (-0.1, 0.2, "eps = -0.1"),
        (np.nan, 0.2, "eps = nan"),
        (0.5, 1.0, r"xi = 1.0 .*\[0.0, 1.0\)"),
        (0.5, np.inf, "xi = inf"),
    ],
)
def test_bad_targets_are_rejected(eps, xi, match):
    with pytest.raises(ValueError, match=match):
        ca.solve_alpha(eps, xi)


def test_failure_is_reported_in_status_not_as_a_number():
    s = ca.solve_alpha(0.3, 0.5, max_steps=10)
    assert not s.ok and s.status == "step limit exceeded"
    assert np.isnan(s.alpha)


def test_full_restitution_needs_no_damping():
    s = ca.solve_alpha(1.0, 0.4)
    assert s.alpha == 0.0 and s.state == "separation"
