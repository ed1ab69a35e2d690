import re

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


def test_length_and_time_scales_are_those_of_the_undamped_hertz_impact():
    # An undamped, unloaded Hertz impact in SI units (SciPy), m d'' = -k d^(3/2): it reaches
    # delta_star, and lasts 2 sqrt(pi) Gamma(7/5) / Gamma(9/10) = 2.9433 t_star.
    from scipy.integrate import solve_ivp
    from scipy.special import gamma

    m, k, v0 = 2.0, 1e9, 0.7

    def touch(t, y):
        return y[0]

    def turn(t, y):
        return y[1]

    touch.terminal, touch.direction = True, -1
    run = solve_ivp(
        lambda t, y: [y[1], -k / m * max(y[0], 0.0) ** 1.5], (0.0, 1.0), [0.0, v0],
        method="DOP853", rtol=1e-13, atol=1e-20, events=[touch, turn], first_step=1e-9,
    )  # fmt: skip
    assert run.y_events[1][0][0] == pytest.approx(ca.length_scale(m, k, v0), rel=1e-9)
    duration = 2 * np.sqrt(np.pi) * gamma(1.4) / gamma(0.9)
    assert run.t_events[0][0] == pytest.approx(duration * ca.time_scale(m, k, v0), rel=1e-9)
    assert ca.impact(0.0, 0.0).t_end == pytest.approx(duration, rel=1e-10)


@pytest.mark.parametrize("a, v0", [(1e30, 1.0), (1e250, 1.0), (9.81, 1e-30), (9.81, 1e-200), (1e300, 1e200)])
def test_a_load_whose_xi_rounds_to_one_is_an_error_naming_the_users_arguments(a, v0):
    # Before: 1.0 (outside [0, 1)), NaN with a RuntimeWarning, or an error naming the internal A.
    expected = re.escape(f"accel = {a!r} m/s^2 at approach_speed = {v0!r} m/s") + ".* xi rounds to 1.0"
    with pytest.raises(ValueError, match=expected):
        ca.influence_factor(5.0, 5.4e9, v0, a)


def test_influence_factor_is_stable_at_extreme_speeds_and_loads():
    # xi = 2A (1 + O(A)) for a small load; A = a delta_star / v0^2 formed in logs where the product
    # under- or overflows (v0^2 = inf at v0 = 1e200; delta_star = 0 at v0 = 1e-200).
    for m_e, k, v0, a in [(5.0, 5.4e9, 1e200, 9.81), (5.0, 5.4e9, 1.0, 1e-300), (1e-200, 1e100, 1.0, 1.0)]:
        log_A = np.log(a) + 0.4 * np.log(1.25 * m_e / k) - 1.2 * np.log(v0)
        assert ca.influence_factor(m_e, k, v0, a) == pytest.approx(2.0 * np.exp(log_A), rel=1e-12)
    # Close to 1, 1 - xi = x_m^(-5/2) with x_m^(3/2) ~ 2A: still below 1, and right.
    xi = ca.influence_factor(5.0, 5.4e9, 1.0, 1e12)
    assert 1.0 - 1e-14 < xi < 1.0
    assert ca.load_for(xi, 5.0, 5.4e9, 1.0) == pytest.approx(1e12, rel=0.05)
    with np.errstate(all="raise"):  # no overflow or invalid operation anywhere
        assert ca.influence_factor(5.0, 5.4e9, 1e-150, 1e-280) < 1.0


def test_scalar_length_scale_is_the_array_one_bit_for_bit():
    rng = np.random.default_rng(3)
    for m, k, v in zip(
        10 ** rng.uniform(-3, 3, 200),
        10 ** rng.uniform(3, 12, 200),
        10 ** rng.uniform(-3, 2, 200),
        strict=True,
    ):
        got = ca.length_scale(float(m), float(k), float(v))
        assert type(got) is float
        assert got == ca.length_scale(np.array([m]), np.array([k]), np.array([v]))[0]
    with pytest.raises(ValueError, match="stiffness = 0.0"):
        ca.length_scale(1.0, 0.0, 1.0)


def test_early_stopping_xi_kernel_is_the_fixed_step_iteration_bit_for_bit():
    # The scalar kernel stops at a fixed point of the Newton step; the fixed-count iteration
    # (the array path's and the C export's) must give the same bits, including at the extremes.
    from contactalpha.engine import scaling

    rng = np.random.default_rng(11)
    loads = np.concatenate([10 ** rng.uniform(-15, 30, 3000), [0.0, 1e-300, 5e-324, 1e30, 0.5, 1.0]])
    for A in loads:
        assert scaling.xi_of_load_kernel(float(A)) == scaling._xi_of_load(float(A))


@pytest.mark.parametrize("v0", [1e300, 1e-300, 1e170, 1e-170])
def test_scales_at_extreme_valid_speeds_are_their_logarithms_values(v0, recwarn):
    """Issue 29, N7: length_scale, time_scale and load_for gave 0.0, inf or NaN with only a warning."""
    m, k = 0.5, 1.4e8
    log_d = 0.4 * (np.log(1.25) + np.log(m) - np.log(k)) + 0.8 * np.log(v0)
    assert ca.length_scale(m, k, v0) == pytest.approx(np.exp(log_d), rel=1e-12)
    assert ca.time_scale(m, k, v0) == pytest.approx(np.exp(log_d - np.log(v0)), rel=1e-12)
    arr = ca.length_scale(np.array([m, m]), k, np.array([v0, 1.0]))
    assert arr[0] == ca.length_scale(m, k, v0)
    assert len(recwarn) == 0


@pytest.mark.parametrize("v0", [1e170, 1e-170])
def test_load_for_at_extreme_speeds_inverts_influence_factor(v0, recwarn):
    m, k = 0.5, 1.4e8
    log_a = np.log(ca.scaled_load(0.2)) + 2 * np.log(v0) - np.log(ca.length_scale(m, k, v0))
    a = ca.load_for(0.2, m, k, v0)
    assert a == pytest.approx(np.exp(log_a), rel=1e-12)
    assert ca.influence_factor(m, k, v0, a) == pytest.approx(0.2, rel=1e-9)
    assert len(recwarn) == 0


def test_contact_parameters_at_a_huge_speed_reports_a_finite_length_scale():
    cp = ca.contact_parameters(0.5, 0.5, 1.4e8, 1e300, accel=9.81)
    log_d = 0.4 * (np.log(1.25) + np.log(0.5) - np.log(1.4e8)) + 0.8 * np.log(1e300)
    assert cp.delta_star == pytest.approx(np.exp(log_d), rel=1e-12)


@pytest.mark.parametrize(
    "call",
    [
        lambda: ca.length_scale(1e300, 1e-300, 1e300),
        lambda: ca.time_scale(1e-300, 1e300, 1e-300),
        lambda: ca.load_for(0.2, 0.5, 1.4e8, 1e300),
    ],
)
def test_a_scale_beyond_the_doubles_is_an_error_naming_the_inputs(call):
    with pytest.raises(ValueError, match="beyond the range of double precision"):
        call()


def _xi_by_brentq(m, k, v, a):
    """Eq. 10 independently: x_m of (x^{5/2} - 1)/2 = A x by Brent's method, A from SI by hand."""
    from scipy.optimize import brentq

    A = a * (5 * m * v * v / (4 * k)) ** 0.4 / (v * v)
    x_m = brentq(
        lambda x: 0.5 * (x**2.5 - 1.0) - A * x,
        1.0,
        (1.0 + 2.0 * A) ** (2.0 / 3.0) + 1.0,
        xtol=1e-15,
        rtol=1e-15,
    )
    return A * x_m / (0.5 + A * x_m)


@pytest.mark.parametrize(
    "m, k, v, a", [(0.5, 1.4e8, 0.5, 19.61), (5.0, 5.4e9, 0.01, 9.81), (1e-3, 1e5, 3.0, 1e3)]
)
def test_the_scalar_fast_path_answers_and_equals_an_independent_xi(m, k, v, a):
    """Issue 29, planted bug: a wrong exponent in the fast path was hidden by its guard (the array path
    answered instead); the fast path must answer plain floats itself, and with the right number."""
    from contactalpha.engine.scaling import _influence_factor_plain

    fast = _influence_factor_plain(m, k, v, a)
    assert fast is not None
    assert fast == pytest.approx(_xi_by_brentq(m, k, v, a), rel=1e-12)
    assert ca.influence_factor(m, k, v, a) == fast
