import numpy as np
import pytest

import contactalpha as ca


def test_paper_example_reaches_xi_0_985():
    # m_e = 5 kg, k = 5.4e9 N/m^1.5, v0 = 1 m/s, a = 23 000 m/s^2 (Sect. 4.1)
    assert ca.influence_factor(5.0, 5.4e9, 1.0, 23000.0) == pytest.approx(0.985, abs=5e-4)


@pytest.mark.parametrize("F, xi", [(0.1, 0.021), (60.0, 0.233), (495.0, 0.799)])
def test_bouncing_ball_influence_factors(F, xi):
    a = 9.81 + F / 0.5
    assert ca.influence_factor(0.5, 1.4e8, 0.5, a) == pytest.approx(xi, abs=1e-3)


def test_load_for_inverts_influence_factor():
    xi = np.array([0.0, 1e-6, 0.2, 0.9, 0.999])
    a = ca.load_for(xi, 2.0, 1e9, 0.7)
    np.testing.assert_allclose(ca.influence_factor(2.0, 1e9, 0.7, a), xi, atol=1e-13)


def test_scaled_load_matches_eq_10_and_11():
    xi = np.array([0.1, 0.5, 0.95])
    A = ca.scaled_load(xi)
    xm = (1 - xi) ** -0.4  # undamped maximum compression, Eq. 11 scaled
    np.testing.assert_allclose(A * xm / (0.5 + A * xm), xi, rtol=1e-14)  # Eq. 10
    np.testing.assert_allclose(0.5 * (xm**2.5 - 1), A * xm, rtol=1e-14)  # Eq. 8


def test_time_scale_is_length_over_speed():
    assert ca.time_scale(1.0, 1e8, 2.0) == pytest.approx(ca.length_scale(1.0, 1e8, 2.0) / 2.0)
