"""The DEM codes' names: each conversion against the code's own formula written out, or a SciPy drop."""

import math

import pytest
from scipy.integrate import solve_ivp

from contactalpha.dem import names


def test_liggghts_beta_is_negative_and_converts():
    e = 0.5
    beta_l = math.log(e) / math.sqrt(math.log(e) ** 2 + math.pi**2)  # createBetaEff
    assert float(names.liggghts_beta(e)) == pytest.approx(beta_l, rel=1e-15) and beta_l < 0
    # gamma_n = -2 sqrt(5/6) beta_L sqrt(S_n m), S_n = 2 Y* sqrt(R delta), kn = 4/3 Y* sqrt(R delta)
    y, r, m, delta = 5e6, 2e-3, 1e-4, 1e-6
    gamma_n = -2.0 * math.sqrt(5.0 / 6.0) * beta_l * math.sqrt(2.0 * y * math.sqrt(r * delta) * m)
    k = 4.0 / 3.0 * y * math.sqrt(r)
    beta = float(names.beta_from_liggghts(beta_l))
    assert beta * math.sqrt(m * k) * delta**0.25 == pytest.approx(gamma_n, rel=1e-13)
    assert float(names.liggghts_restitution(beta)) == pytest.approx(e, rel=1e-13)
    assert float(names.beta_from_restitution(e)) == pytest.approx(beta, rel=1e-14)


def test_reduced_mass():
    assert names.reduced_mass(2.0, 3.0) == pytest.approx(1.2, rel=1e-15)
    assert names.reduced_mass(2.0) == 2.0
    assert names.yade_reduced_mass(2.0) == 1.0  # a massless wall takes the sphere's mass
    with pytest.raises(ValueError, match="m2"):
        names.reduced_mass(1.0, -1.0)


def _linear_drop(m, k, c):
    """(e_N, contact time) of ``m x'' = -k x - c x'`` from x = 0, x' = 1 to x = 0 (no floor), SciPy."""

    def leave(t, y):
        return y[0] if t > 0 else 1.0

    leave.terminal, leave.direction = True, -1
    span = (0.0, 100.0 * math.sqrt(m / k))

    def rhs(t, y):
        return [y[1], -(k * y[0] + c * y[1]) / m]

    sol = solve_ivp(rhs, span, [0.0, 1.0], events=leave, rtol=1e-12, atol=1e-14)
    return -sol.y_events[0][0][1], sol.t_events[0][0]


def test_yade_en_tc_is_its_oscillator():
    en, tc, mass_r = 0.6, 1e-3, 2e-3
    k, c = names.yade_stiffness_damping(en, tc, mass_r)
    e, t = _linear_drop(mass_r, k, c)  # the unfloored oscillator of massR: en and tc exactly
    assert e == pytest.approx(en, rel=1e-8) and t == pytest.approx(tc, rel=1e-8)
    assert names.yade_material(k, c, mass_r) == pytest.approx((en, tc), rel=1e-12)
    # A sphere of mass m on a massless wall: massR = m/2, so zeta is classic/sqrt(2).
    z = names.zeta_of_yade(en, tc, names.yade_reduced_mass(4e-3), 4e-3)
    assert z == pytest.approx(float(names.classic_zeta(en)) / math.sqrt(2.0), rel=1e-14)
    with pytest.raises(ValueError, match="critical"):
        names.yade_material(1.0, 10.0, 1.0)


def test_mfix_damping_delivers_its_restitution_without_floor():
    kn, en, m = 1e3, 0.7, 1e-3
    etan = names.mfix_damping(kn, en, m)
    assert _linear_drop(m, kn, etan)[0] == pytest.approx(en, rel=1e-8)
    assert names.mfix_restitution(etan / (2.0 * math.sqrt(kn * m))) == pytest.approx(en, rel=1e-13)
