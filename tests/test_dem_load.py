"""Does the load matter: the zero-load damping run at the scene's load, against a SciPy integration."""

import math

import pytest
from scipy.integrate import solve_ivp

from contactalpha.dem.load import load_effect

# The bead: d = 5 mm, E = 1e7 Pa, nu = 0.3, rho = 2500, on a wall of its material.
R = 2.5e-3
MASS = 4.0 / 3.0 * math.pi * R**3 * 2500.0
K = 4.0 / 3.0 * (1e7 / (2.0 * (1.0 - 0.09))) * math.sqrt(R)


def _unfloored_tsuji_e_n(beta, v, accel):
    """e_N of ``m x'' = m a - K x^{3/2} - beta sqrt(m K) x^{1/4} x'`` while x > 0 (SciPy)."""

    def rhs(t, y):
        x, u = max(y[0], 0.0), y[1]
        return [u, accel - (K * x**1.5 + beta * math.sqrt(MASS * K) * x**0.25 * u) / MASS]

    def leave(t, y):
        return y[0] if t > 0 else 1.0

    leave.terminal, leave.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1.0), [1e-300, v], events=leave, rtol=1e-11, atol=1e-18, max_step=1e-5)
    return abs(sol.y_events[0][0][1]) / v


def test_the_load_matters_for_a_slow_soft_bead():
    got = load_effect("hertz_tsuji_unfloored", 0.5, "kinematic", MASS, K, 0.02, 9.81)
    assert got.matters and got.change < -0.2
    assert got.delivered_ignoring == pytest.approx(
        _unfloored_tsuji_e_n(got.damping_ignoring, 0.02, 9.81), abs=1e-6
    )
    assert "matters" in got.line()


def test_the_load_may_be_ignored_for_a_fast_glass_bead():
    # glass, d = 2 mm, E = 63 GPa, nu = 0.23, at 1 m/s under gravity (the user)
    r, e_mod, nu = 1e-3, 6.3e10, 0.23
    m = 4.0 / 3.0 * math.pi * r**3 * 2500.0
    k = 4.0 / 3.0 * e_mod / (2.0 * (1.0 - nu * nu)) * math.sqrt(r)
    got = load_effect("hertz_tsuji", 0.9, "kinematic", m, k, 1.0, 9.81)
    assert not got.matters and abs(got.change) < 1e-4
    assert "may be ignored" in got.line()


def test_params_prints_the_loads_effect(capsys):
    from contactalpha.cli import main

    args = ["params", "--law", "hertz_tsuji", "--e-n", "0.5", "--mass", repr(MASS), "--stiffness", repr(K)]
    assert main([*args, "--speed", "0.02", "--accel", "9.81"]) == 0
    line = capsys.readouterr().out.splitlines()[-1]
    want = load_effect("hertz_tsuji", 0.5, "kinematic", MASS, K, 0.02, 9.81)
    assert line.startswith("load            matters") and f"{want.delivered_ignoring:.6g}" in line
