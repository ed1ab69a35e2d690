"""The two DEM laws' zero-load anchors and their inverse in SI units, against independent integrations.

Tsuji's law without its floor is, at zero load, the textbook damped oscillator in ``y = x^{5/4}``;
Hertz with sqrt(delta) damping restitutes as ``1 - e = C1 kappa - C2 kappa^2 + ...`` (Schwager &
Poeschel 1998, Ramirez et al. 1999) with ``kappa = eta v^{1/5} / (k^{3/5} m^{2/5})``.  The physical
scenes are integrated by SciPy in SI units: nothing of the package's scaling is used there.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import gamma
from scipy_reference import reference_impact

from contactalpha.laws import get_law

UNFLOORED, VISCOELASTIC = "hertz_tsuji_unfloored", "hertz_viscoelastic"
SQRT_DELTA = (VISCOELASTIC, "hertz_viscoelastic_unfloored")
# Ramirez, Poeschel, Brilliantov & Schwager, PRE 60, 4465 (1999): the first two coefficients.
C1_PUBLISHED, C2_PUBLISHED = 1.15344, 0.79826


def drop_si(law_name, mass, stiffness, eta, speed, accel):
    """e_N of one drop in SI units by SciPy: m d'' = m a - F(d, d') while d > 0, from d = 0, d' = speed."""
    root = 0.5 if law_name in SQRT_DELTA else 0.25  # the damping's power of the compression
    floored = not law_name.endswith("_unfloored")

    def rhs(_t, y):
        d = max(y[0], 0.0)
        f = stiffness * d**1.5 + eta * d**root * y[1]
        return [y[1], accel - (max(0.0, f) if floored else f) / mass]

    def leaves(_t, y):
        return y[0]

    leaves.terminal, leaves.direction = True, -1.0
    t_scale = (1.25 * mass * speed**2 / stiffness) ** 0.4 / speed
    sol = solve_ivp(
        rhs,
        (0.0, 200 * t_scale),
        [0.0, speed],
        method="DOP853",
        rtol=1e-13,
        atol=1e-14 * speed * t_scale,
        events=leaves,
        max_step=0.01 * t_scale,
    )
    assert sol.t_events[0].size, "no separation"
    return -sol.y_events[0][0][1] / speed


def test_unfloored_tsuji_at_zero_load_is_the_textbook_oscillator():
    # y = x^{5/4}, tau = int x^{1/4} dt: y'' + gamma y' + (25/16) y = 0 without a floor, zeta = beta/sqrt(5).
    law = get_law(UNFLOORED)
    zeta = np.array([0.01, 0.1, 0.3, 0.6, 0.9, 0.97])
    r = law.impact(np.sqrt(5.0) * zeta, 0.0)
    textbook = np.exp(-np.pi * zeta / np.sqrt(1.0 - zeta**2))
    np.testing.assert_allclose(r.e_n, textbook, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(r.eps, r.e_n)
    assert set(r.state) == {"separation"}
    # Overdamped (zeta >= 1): never back to delta = 0, the limit of a creep into it.
    over = law.impact(np.sqrt(5.0) * np.array([1.0, 2.0]), 0.0)
    assert list(over.state) == ["creep", "creep"] and np.all(over.e_n == 0.0) and np.all(over.eps == 0.0)
    # LAMMPS's coeff_restitution: beta = -sqrt(5) ln e / sqrt(pi^2 + ln^2 e) is its exact inverse there.
    e = np.array([0.05, 0.3, 0.5, 0.9])
    lammps = -np.sqrt(5.0) * np.log(e) / np.sqrt(np.pi**2 + np.log(e) ** 2)
    sol = law.damping_for(e, 0.0, "kinematic")
    np.testing.assert_allclose(sol.damping, lammps, rtol=1e-9)


@pytest.mark.parametrize("speed", [0.01, 1.0, 30.0])
def test_unfloored_tsuji_at_zero_load_does_not_depend_on_the_speed(speed):
    m, k, beta = 0.2, 3.0e6, 1.3
    got = drop_si(UNFLOORED, m, k, beta * math.sqrt(m * k), speed, 0.0)
    assert got == pytest.approx(get_law(UNFLOORED).impact(beta, 0.0).e_n, abs=1e-9)


def test_the_floor_changes_tsuji_only_where_the_force_pulls():
    # The unfloored law restitutes less: its pull takes energy the floor's flight keeps.
    beta = np.array([0.2, 1.0, 2.0])
    floored, unfloored = get_law("hertz_tsuji").impact(beta, 0.0), get_law(UNFLOORED).impact(beta, 0.0)
    assert np.all(unfloored.e_n < floored.e_n)


@pytest.mark.parametrize("name", SQRT_DELTA)
def test_sqrt_delta_law_at_small_damping_is_the_published_expansion(name):
    c1 = math.sqrt(math.pi) * gamma(0.6) / (2**0.2 * 5**0.4 * gamma(2.1))  # Schwager & Poeschel 1998
    assert c1 == pytest.approx(C1_PUBLISHED, abs=1e-5)  # published truncated: 1.1534489
    kappa = np.array([1e-5, 1e-4, 3e-4])
    r = get_law(name).impact(kappa, 0.0)
    # 1 - e = C1 kappa - C2 kappa^2 + O(kappa^{5/2}), with or without the floor (it enters at kappa^{5/2}).
    np.testing.assert_allclose((1.0 - r.e_n) / kappa, c1 - C2_PUBLISHED * kappa, rtol=0, atol=2e-6)


@pytest.mark.parametrize("name", SQRT_DELTA)
@pytest.mark.parametrize("speed", [0.01, 1.0, 30.0])
def test_sqrt_delta_law_depends_on_the_speed_as_v_to_the_one_fifth(name, speed):
    # One physical eta at three speeds: kappa = eta v^{1/5} / (k^{3/5} m^{2/5}) carries the whole dependence.
    law = get_law(name)
    m, k, eta = 0.2, 3.0e6, 40.0
    kappa = law.damping_from_physical(eta, m, k, speed)
    assert kappa == pytest.approx(eta * speed**0.2 / (k**0.6 * m**0.4), rel=1e-14)
    got = drop_si(name, m, k, eta, speed, 0.0)
    assert got == pytest.approx(law.impact(kappa, 0.0).e_n, abs=1e-9)


def _scenes(n, seed):
    """Random SI scenes, half of them without a load; the other half's load gives 0 < xi <= 0.9."""
    rng = np.random.default_rng(seed)
    law = get_law(VISCOELASTIC)
    m = 10.0 ** rng.uniform(-4.0, 1.0, n)
    k = 10.0 ** rng.uniform(5.0, 10.0, n)
    v = 10.0 ** rng.uniform(-2.0, 1.0, n)
    xi = np.where(np.arange(n) % 2 == 0, 0.0, 0.9 * rng.random(n) ** 2)
    accel = law.scaled_load(xi) * v**2 / law.length_scale(m, k, v)
    target = rng.uniform(0.05, 0.99, n)
    return m, k, v, accel, target


def _check_inverse(n, seed):
    law = get_law(VISCOELASTIC)
    for i, (m, k, v, a, e) in enumerate(zip(*_scenes(n, seed), strict=True)):
        xi = law.scene_load_factor(m, k, v, a)
        sol = law.damping_for(e, xi, "kinematic")
        eta = law.physical_damping(sol.damping, m, k, v)
        assert drop_si(VISCOELASTIC, m, k, eta, v, a) == pytest.approx(e, abs=1e-8), (i, m, k, v, a, e)
        # Stronge's eps: the scaled reference (tests/laws/scipy_reference.py) at the eps inverse.
        p = law.damping_for(e, xi, "energetic").damping
        eps = reference_impact(VISCOELASTIC, p, law.scaled_load(xi))[0]
        assert eps == pytest.approx(e, abs=1e-8), (i, m, k, v, a, e)


def test_sqrt_delta_inverse_delivers_its_target_in_si_units():
    _check_inverse(4, 45)


@pytest.mark.integration
def test_sqrt_delta_inverse_delivers_its_target_at_150_scenes():
    _check_inverse(150, 2045)


def test_lammps_drops_under_gravity_are_the_two_tsuji_laws():
    """LAMMPS 2025.7.22, fix wall/gran granular hertz/material 1e7 0.5 0.3, damping coeff_restitution 0.5.

    A 5 mm sphere (rho = 2500) on the wall (E* = E / (2 (1 - nu^2)), LAMMPS's mix with itself):
    measured e_N without and with limit_damping, to its 3 printed digits, and an independent SciPy
    integration of the unfloored law at 0.02 m/s (0.280666).
    """
    radius, nu = 2.5e-3, 0.3
    mass = 2500.0 * 4.0 / 3.0 * math.pi * radius**3
    stiffness = 4.0 / 3.0 * 1e7 / (2.0 * (1.0 - nu**2)) * math.sqrt(radius)
    beta = -math.sqrt(5.0) * math.log(0.5) / math.sqrt(math.pi**2 + math.log(0.5) ** 2)
    speeds = [1.0, 0.2, 0.05, 0.02]
    measured = {UNFLOORED: [0.499, 0.490, 0.443, 0.281], "hertz_tsuji": [0.549, 0.540, 0.492, 0.328]}
    for name, want in measured.items():
        law = get_law(name)
        xi = [law.scene_load_factor(mass, stiffness, v, 9.81) for v in speeds]
        np.testing.assert_allclose(law.impact(beta, xi).e_n, want, rtol=0, atol=6e-4)
    law = get_law(UNFLOORED)
    assert float(law.impact(beta, law.scene_load_factor(mass, stiffness, 0.02, 9.81)).e_n) == pytest.approx(
        0.280666, abs=1e-6
    )


def test_unfloored_tsuji_table_at_zero_load_is_lammps_coeff_restitution():
    e = np.exp(np.linspace(np.log(0.01), np.log(0.999), 60))
    lammps = -np.sqrt(5.0) * np.log(e) / np.sqrt(np.pi**2 + np.log(e) ** 2)
    for restitution in ("energetic", "kinematic"):
        beta = get_law(UNFLOORED).fast_damping(e, 0.0, restitution)
        np.testing.assert_allclose(beta, lammps, rtol=3e-6)  # 1.6e-6 at e = 0.999, where e hardly moves
        zeta = beta / np.sqrt(5.0)
        np.testing.assert_allclose(np.exp(-np.pi * zeta / np.sqrt(1.0 - zeta**2)), e, rtol=0, atol=1e-7)


def test_a_table_on_another_target_coordinate_is_refused(tmp_path):
    from dataclasses import replace

    from contactalpha.laws.table import load_law_tables, save_law_tables

    law = get_law(VISCOELASTIC)
    assert law.fast.root_near_one and not get_law("hertz_tsuji").fast.root_near_one
    arrays, meta = load_law_tables(law.fast.path)
    path = save_law_tables(arrays, dict(meta, root_near_one=False), tmp_path / "table.npz")
    with pytest.raises(ValueError, match="has root_near_one = False, expected True"):
        replace(law, fast=replace(law.fast, file=str(path))).fast_damping(0.5, 0.2)
