"""The law registry: one list of values with their capabilities, and clear errors."""

import numpy as np
import pytest

from contactalpha.engine.exact import restitution_exact
from contactalpha.laws import LAWS, ContactLaw, get_law


def test_every_law_is_a_registered_value_with_its_capabilities():
    names = [law.name for law in LAWS]
    assert len(set(names)) == len(names) and names[0] == "hunt_crossley"  # the default law first
    for law in LAWS:
        assert isinstance(law, ContactLaw)
        assert get_law(law.name) is law
        assert law.exponent in (1.0, 1.5)
        assert set(law.restitutions) == {"energetic", "kinematic"}
        assert law.load_domain == (0.0, 0.99)
        # The scaled force is the law's: f(x_eq(A), 0) = A at a load.
        A = 0.37
        assert law.force(float(law.equilibrium(A)), 0.0, 0.5, A, law.impedance) == pytest.approx(A, rel=1e-14)
        # A piecewise-linear law has a closed form, and the closed form is its exact inverse.
        closed = law.fast is not None and law.fast.exact_inverse is not None
        assert law.piecewise_linear == closed


def test_unknown_law_and_bad_parameters_name_the_valid_choices():
    with pytest.raises(
        ValueError, match=r"unknown contact law 'bullet'; valid: hunt_crossley, hunt_crossley_linear"
    ):
        get_law("bullet")
    with pytest.raises(ValueError, match=r"impedance = 1.0 is outside the valid range \[0.0, 1.0\)"):
        get_law("mujoco_soft", impedance=1.0)
    with pytest.raises(ValueError, match="has no impedance; laws with one: mujoco_soft"):
        get_law("kelvin_voigt", impedance=0.5)
    law = get_law("kelvin_voigt")
    with pytest.raises(ValueError, match=r"zeta = -0.1 is outside the valid range"):
        law.impact(-0.1, 0.0)
    with pytest.raises(ValueError, match=r"xi = 1.0 is outside the valid range \[0.0, 1.0\)"):
        law.impact(0.1, 1.0)
    with pytest.raises(ValueError, match=r"e_N = 0.0 is outside the valid range \(0.0, 1.0\]"):
        law.damping_for(0.0, 0.1, restitution="kinematic")
    with pytest.raises(ValueError, match="restitution = 'newton' is not one of 'energetic', 'kinematic'"):
        law.damping_for(0.5, 0.1, restitution="newton")


@pytest.mark.parametrize("law", LAWS, ids=lambda law: law.name)
def test_load_factor_and_scaled_load_are_inverse(law):
    xi = np.array([0.0, 1e-6, 0.2325, 0.5, 0.99])
    A = law.scaled_load(xi)
    assert np.all(np.diff(A) > 0)
    np.testing.assert_allclose(law.load_factor(A), xi, rtol=1e-13, atol=1e-16)


def test_load_factor_generalises_the_papers_influence_factor():
    from contactalpha.engine.scaling import scaled_load

    xi = np.linspace(0.0, 0.99, 12)
    np.testing.assert_allclose(get_law("hertz_tsuji").scaled_load(xi), scaled_load(xi), rtol=1e-14)
    # n = 1: A = xi (1 - xi)^(-1/2) / 2 (docs/laws.md).
    np.testing.assert_allclose(
        get_law("kelvin_voigt").scaled_load(xi), 0.5 * xi / np.sqrt(1 - xi), rtol=1e-14
    )


def test_spring_dashpot_with_floor_matches_schwager_poeschel():
    """Schwager & Poeschel 2007: zeta = 0.3 delivers e_N = 0.451 with the floor, not the textbook 0.372."""
    law = get_law("kelvin_voigt")
    A = np.array([0.0, 0.1])
    r = law.impact(0.3, law.load_factor(A))
    np.testing.assert_allclose(r.e_n, [0.451, 0.348], atol=5e-4)
    # Their closed form at zero load: e = exp(-zeta (pi - phi) / w), phi the angle where the force is 0.
    z = np.array([0.05, 0.3, 0.6, 0.9])
    w = np.sqrt(1 - z**2)
    phase = np.arctan2(2 * z * w, 1 - 2 * z**2)  # the angle at which x + 2 zeta x' = 0
    closed = np.exp(-z / w * (np.pi - phase))
    np.testing.assert_allclose(law.impact(z, 0.0).e_n, closed, rtol=0, atol=1e-11)


def test_hunt_crossley_n1_reproduces_the_exact_unloaded_relation():
    alpha = np.geomspace(1e-3, 300.0, 25)
    r = get_law("hunt_crossley_linear").impact(alpha, 0.0)
    np.testing.assert_allclose(r.eps, restitution_exact(alpha), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(r.e_n, r.eps)


def test_hunt_crossley_law_is_the_engine_unchanged():
    from contactalpha.engine.driver import impact
    from contactalpha.engine.solver import solve_alpha

    law = get_law("hunt_crossley")
    r = law.impact([0.3, 2.0], [0.1, 0.5])
    ref = impact(np.array([0.3, 2.0]), np.array([0.1, 0.5]))
    np.testing.assert_array_equal(r.eps, ref.eps)
    np.testing.assert_array_equal(r.e_n, ref.e_n)
    s = law.damping_for(0.5, 0.2325)
    assert s.damping == solve_alpha(0.5, 0.2325).alpha


def test_length_scale_and_load_are_the_laws_scaling():
    """delta_s is the undamped unloaded maximum compression: v / omega for n = 1, Eq. 8's delta* for 3/2."""
    from contactalpha.engine.scaling import influence_factor, length_scale

    m, k, v, a = 0.5, 1.4e8, 0.5, 129.81
    tsuji = get_law("hertz_tsuji")
    assert tsuji.length_scale(m, k, v) == pytest.approx(float(length_scale(m, k, v)), rel=1e-15)
    assert tsuji.load_factor(tsuji.load(m, k, v, a)) == pytest.approx(influence_factor(m, k, v, a), rel=1e-13)
    linear = get_law("kelvin_voigt")
    assert linear.length_scale(2.0, 800.0, 0.5) == pytest.approx(0.5 / 20.0, rel=1e-15)
    assert linear.load(2.0, 800.0, 0.5, 9.81) == pytest.approx(9.81 / (20.0 * 0.5), rel=1e-15)


def test_tsuji_at_zero_load_is_the_spring_dashpot_with_zeta_beta_over_sqrt5():
    """With tau = int x^{1/4} dt and y = x^{5/4}, Tsuji's unloaded motion is y'' + gamma y' + (25/16) y = 0.

    So zeta = 2 gamma / 5 = beta / sqrt(5), the floor maps to the floor, and y' = (5/4) x': the same
    e_N as the spring-dashpot (docs/laws.md, "Zero-load anchors").  Independent of the approach speed.
    """
    zeta = np.array([0.05, 0.3, 0.9, 1.0, 3.0])
    tsuji = get_law("hertz_tsuji").impact(np.sqrt(5.0) * zeta, 0.0)
    spring = get_law("kelvin_voigt").fast_restitution(zeta, 0.0, "kinematic")
    np.testing.assert_allclose(tsuji.e_n, spring, rtol=0, atol=2e-11)
    np.testing.assert_array_equal(tsuji.eps, tsuji.e_n)


@pytest.mark.parametrize("speed", [0.01, 1.0, 30.0])
def test_tsuji_restitution_does_not_depend_on_the_approach_speed_at_zero_load(speed):
    """The physical Tsuji law, integrated by SciPy in SI units, restitutes as the scaled law at any speed."""
    from scipy.integrate import solve_ivp

    m, k, beta = 0.2, 3.0e6, 0.8
    eta = beta * np.sqrt(m * k)

    def rhs(_t, y):
        d = max(y[0], 0.0)
        return [y[1], -max(0.0, k * d**1.5 + eta * d**0.25 * y[1]) / m]

    def leaves(_t, y):
        return y[0]

    leaves.terminal, leaves.direction = True, -1.0
    t_scale = (1.25 * m * speed**2 / k) ** 0.4 / speed
    sol = solve_ivp(
        rhs,
        (0.0, 50 * t_scale),
        [0.0, speed],
        method="DOP853",
        rtol=1e-12,
        atol=1e-12 * speed * t_scale,
        events=leaves,
        max_step=0.01 * t_scale,
    )
    e_n = -sol.y_events[0][0][1] / speed
    assert e_n == pytest.approx(get_law("hertz_tsuji").impact(beta, 0.0).e_n, abs=1e-8)
