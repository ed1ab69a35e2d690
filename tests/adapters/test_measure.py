"""Restitution measured from sampled states: checked on the package's own trajectories."""

import numpy as np
import pytest

from contactalpha import impact, influence_factor, length_scale, solve_alpha, time_scale, trajectory
from contactalpha.adapters.measure import hermite, measure_impact

M, K, V, G = 0.5, 1.4e8, 0.5, 9.81


def _physical_samples(eps, force, step=0.02):
    """The package's trajectory of the exact-alpha impact, in SI units, every ``step`` t*."""
    a = G + force / M
    xi = influence_factor(M, K, V, a)
    alpha = float(solve_alpha(eps, xi).alpha)
    path, res = trajectory(alpha, xi, max_step=step)
    ds, ts = float(length_scale(M, K, V)), float(time_scale(M, K, V))
    t, d, dd = path[:, 0] * ts, path[:, 1] * ds, path[:, 2] * V
    if res.state == "separation":  # the package stops at the event; an engine runs on into the flight
        tau = np.linspace(0.0, 2e-4, 5)[1:]
        t, d, dd = (
            np.r_[t, t[-1] + tau],
            np.r_[d, dd[-1] * tau + 0.5 * a * tau**2],
            np.r_[dd, dd[-1] + a * tau],
        )
    return t, d, dd, a, res, alpha, xi


def test_hermite_reproduces_a_cubic_exactly():
    def cubic(t):
        return 1.0 - 2.0 * t + 0.5 * t**2 + 0.3 * t**3

    def slope(t):
        return -2.0 + t + 0.9 * t**2

    pos, vel = hermite(0.2, 1.7, cubic(0.2), cubic(1.7), slope(0.2), slope(1.7))
    s = np.linspace(0, 1, 7)
    np.testing.assert_allclose(pos(s), cubic(0.2 + 1.5 * s), rtol=1e-14)
    np.testing.assert_allclose(vel(s), slope(0.2 + 1.5 * s), rtol=1e-13)


def test_separating_impact_matches_the_energy_identity_of_the_package():
    t, d, dd, a, res, alpha, xi = _physical_samples(0.5, 60.0)
    m = measure_impact(t, d, dd, a, V)
    assert m.state == "separation" and res.state == "separation"
    assert m.eps == pytest.approx(0.5, abs=1e-8)
    assert m.e_n == pytest.approx(-float(res.v_end), abs=1e-8)
    assert m.e_n == pytest.approx(0.287, abs=1e-3)  # the check on this ball at F = 60 N
    assert m.delta_max == pytest.approx(float(res.x_max) * float(length_scale(M, K, V)), rel=1e-9)


def test_nonseparating_impact_is_cut_where_the_speed_returns_to_zero():
    t, d, dd, a, res, *_ = _physical_samples(0.3, 60.0)
    m = measure_impact(t, d, dd, a, V)
    assert res.state == "nonseparation" and m.state == "nonseparation"
    assert m.e_n == 0.0 and m.v_end == 0.0
    assert m.eps == pytest.approx(0.3, abs=1e-7)
    assert m.delta_end == pytest.approx(float(res.x_end) * float(length_scale(M, K, V)), rel=1e-7)


def test_touchdown_is_located_when_the_samples_start_in_flight():
    t, d, dd, a, *_ = _physical_samples(0.7, 5.1)
    # Prepend an exact flight parabola that reaches the ground at t = 0 with speed V.
    tau = np.linspace(-2e-3, 0.0, 9)[:-1]
    flight_d, flight_v = V * tau + 0.5 * a * tau**2, V + a * tau
    m = measure_impact(np.r_[tau, t], np.r_[flight_d, d], np.r_[flight_v, dd], a)
    assert m.t_touch == pytest.approx(0.0, abs=1e-12)
    assert m.approach_speed == pytest.approx(V, rel=1e-10)
    assert m.eps == pytest.approx(0.7, abs=1e-8)


def test_samples_without_a_maximum_fail_with_nan():
    t = np.linspace(0, 1e-4, 20)
    m = measure_impact(t, V * t, np.full_like(t, V), 20.0, V)
    assert m.state == "failed" and np.isnan(m.eps)


def test_samples_that_end_before_the_contact_does_report_creep_at_the_last_sample():
    t, d, dd, a, *_ = _physical_samples(0.5, 5.1)
    half = np.argmax(d) + 5
    m = measure_impact(t[:half], d[:half], dd[:half], a, V)
    assert m.state == "creep" and m.t_end == t[half - 1]


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="accel = -1.0"):
        measure_impact([0, 1], [0, 1], [1, 1], -1.0)
    with pytest.raises(ValueError, match="one length"):
        measure_impact([0, 1, 2], [0, 1], [1, 1], 1.0)


def test_package_eps_of_the_exact_alpha_is_the_target():
    # Guards the premise of the tests above: solve_alpha hits its target on this ball.
    xi = influence_factor(M, K, V, G + 60.0 / M)
    assert float(impact(solve_alpha(0.5, xi).alpha, xi).eps) == pytest.approx(0.5, abs=1e-10)
