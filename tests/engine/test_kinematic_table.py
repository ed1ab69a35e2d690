"""The kinematic table, alpha(..., restitution=...), convert_restitution."""

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.baselines.reference import impact_scipy
from contactalpha.engine.table import EPS_MIN, XI_MAX
from contactalpha.engine.table_build import random_points


def test_kinematic_table_meets_1e_6_off_its_nodes():
    e_n, xi = random_points(300, seed=7)
    ref = ca.solve_alpha(e_n, xi, restitution="kinematic", guess="formula", tol=1e-13)
    assert np.all(ref.ok)
    got = ca.alpha(e_n, xi, restitution="kinematic")
    assert np.max(np.abs(got / ref.alpha - 1)) <= 1e-6


def test_kinematic_table_ends():
    assert ca.alpha(1.0, 0.4, restitution="kinematic") == 0.0
    xi = np.array([0.0, 0.3, 0.9])
    # Without a load e_N = eps, so both tables agree at xi = 0 only.
    k = ca.alpha(0.5, xi, restitution="kinematic")
    e = ca.alpha(0.5, xi)
    assert k[0] == pytest.approx(e[0], rel=1e-6)
    assert np.all(k[1:] < e[1:])  # e_N < eps under a load: less damping gives the same e_N
    # and each is the impact's own inverse: the alpha whose e_N (SciPy oracle's exit speed) is 0.5
    for a, x in zip(k[1:], xi[1:], strict=True):
        assert -impact_scipy(float(a), float(x), rtol=1e-12, atol=1e-14).v_end == pytest.approx(0.5, abs=1e-6)


def test_kinematic_lookup_refuses_what_it_does_not_cover():
    with pytest.raises(ValueError, match=r"e_N = 0.0 has no kinematic inverse"):
        ca.alpha(0.0, 0.3, restitution="kinematic")
    with pytest.raises(ValueError, match=r"e_N = 0.005 .*exact_solve"):
        ca.alpha(0.005, 0.3, restitution="kinematic")
    with pytest.raises(ValueError, match="defined for Stronge's energetic eps"):
        ca.alpha(0.5, 0.3, model="hunt_crossley", restitution="kinematic")
    assert ca.alpha(0.005, 0.3, model="exact_solve", restitution="kinematic") == pytest.approx(
        ca.solve_alpha(0.005, 0.3, restitution="kinematic").alpha, rel=1e-12
    )
    f = ca.jit_alpha_tabulated(restitution="kinematic")
    assert np.isnan(f(0.5, XI_MAX + 1e-3)) and np.isnan(f(EPS_MIN / 2, 0.3))
    assert f(0.5, 0.3) == ca.alpha(0.5, 0.3, restitution="kinematic")


@pytest.mark.parametrize("xi", [0.0, 0.2, 0.7])
def test_convert_restitution_round_trips_and_obeys_the_identity(xi):
    eps = np.array([0.3, 0.6, 0.95])
    e_n = ca.convert_restitution(eps, xi, to="kinematic")
    back = ca.convert_restitution(e_n[e_n > 0], xi, to="energetic")
    np.testing.assert_allclose(back, eps[e_n > 0], atol=1e-10)
    if xi == 0.0:
        np.testing.assert_allclose(e_n, eps, atol=1e-12)
    else:
        assert np.all(e_n < eps)


def test_convert_below_the_boundary_gives_zero_and_zero_has_no_inverse():
    assert ca.convert_restitution(0.2, 0.5, to="kinematic") == 0.0  # eps_b(0.5) ~ 0.67
    with pytest.raises(ValueError, match="no kinematic inverse"):
        ca.convert_restitution(0.0, 0.5, to="energetic")
    with pytest.raises(ValueError, match="to = 'newton'"):
        ca.convert_restitution(0.5, 0.5, to="newton")


def test_scalar_alpha_fast_path_equals_array_path():
    for kind in ("energetic", "kinematic"):
        for e, x in [(0.5, 0.3), (0.01, 0.0), (0.99, 0.99), (1.0, 0.5)]:
            assert (
                ca.alpha(e, x, restitution=kind)
                == ca.alpha(np.array([e]), np.array([x]), restitution=kind)[0]
            )
    with pytest.raises(ValueError, match="eps = 0.005 .*exact_solve"):
        ca.alpha(0.005, 0.3)
